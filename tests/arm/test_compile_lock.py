"""Processes that share numba's cache compile each kernel once (:func:`armanim.arm.kernel.held_alone`):
the second waits for the first's machine code instead of compiling it again, the lock goes with
its holder however the holder ends, and a thread of the holder's process is never made to wait."""

from __future__ import annotations

import fcntl
import os
import signal
import subprocess
import sys
import textwrap
import threading
from pathlib import Path

import pytest

from armanim.arm import kernel


def _locked_elsewhere(path: Path) -> bool:
    """Whether some open file description other than a new one holds ``path``'s flock."""
    fd = os.open(path, os.O_RDWR | os.O_CREAT)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        return True
    finally:
        os.close(fd)
    return False


def _wait_for(path: Path, process: subprocess.Popen[str]) -> None:
    """Block until ``path`` exists (a subprocess's signal), failing if ``process`` ends first."""
    while not path.exists():
        if process.poll() is not None:
            pytest.fail(f"the subprocess ended first: {process.communicate()}")
        threading.Event().wait(0.01)


# A subprocess that compiles world/compiled.kind_count for a None argument (a fresh cache: the
# test's NUMBA_CACHE_DIR), optionally first taking the kernel's lock itself, and prints how many
# times it compiled the kernel (numba's cache misses) and how many times it loaded it (hits).
_COMPILE = textwrap.dedent(
    """
    import sys, time
    from pathlib import Path
    from numba import types
    from armanim.arm import kernel
    from armanim.world.compiled import kind_count
    role, folder = sys.argv[1], Path(sys.argv[2])
    def wait(name):  # never for ever: a test stopped midway left a holder waiting for hours
        given_up = time.monotonic() + 600
        while not (folder / name).exists():
            if time.monotonic() > given_up:
                sys.exit(f"gave up waiting for {name}")
            time.sleep(0.01)
    if role == "holder":  # holds the None signature's lock until the other is done
        with kernel.held_alone(kernel.compile_lock_path(kind_count, (types.none,))):
            (folder / "held").touch()
            wait("other-done")
        sys.exit(0)
    if role == "other":  # another signature: compiles beside the holder, not after it
        wait("held")
        kind_count.compile((types.float64[:, ::1],))
        (folder / "other-done").touch()
    elif role == "first":
        with kernel.held_alone(kernel.compile_lock_path(kind_count, (types.none,))):
            (folder / "held").touch()
            wait("second-ready")
            kind_count.compile((types.none,))  # nested: this process holds the lock already
    else:
        wait("held")
        (folder / "second-ready").touch()
        kind_count.compile((types.none,))
    stats = kind_count.stats
    print(sum(stats.cache_misses.values()), sum(stats.cache_hits.values()))
    """
)


def _compiler(role: str, folder: Path, cache: Path) -> subprocess.Popen[str]:
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache))
    return subprocess.Popen(
        [sys.executable, "-c", _COMPILE, role, str(folder)],
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )


def _misses_and_hits(process: subprocess.Popen[str]) -> list[str]:
    """What a :func:`_compiler` printed once it ended well: its compiles and its loads of the kernel."""
    out, err = process.communicate(timeout=300)
    assert process.returncode == 0, err
    return out.split()


def test_a_second_process_loads_the_first_ones_compile_instead_of_compiling_again(tmp_path):
    # The second asks for the kernel while the first holds its lock and has not compiled it yet:
    # without the lock it would find no cache and compile too (1 miss).
    cache = tmp_path / "cache"
    first = _compiler("first", tmp_path, cache)
    _wait_for(tmp_path / "held", first)
    second = _compiler("second", tmp_path, cache)
    assert _misses_and_hits(first) == ["1", "0"]  # the first compiled it
    assert _misses_and_hits(second) == ["0", "1"]  # the second loaded the first one's machine code


def test_another_signature_of_the_same_kernel_compiles_beside_a_held_one(tmp_path):
    # were the lock the kernel's, not its signature's, the other would wait for the holder, which
    # waits for it: the timeout would end the test
    cache = tmp_path / "cache"
    holder = _compiler("holder", tmp_path, cache)
    _wait_for(tmp_path / "held", holder)
    other = _compiler("other", tmp_path, cache)
    assert _misses_and_hits(other) == ["1", "0"]
    assert _misses_and_hits(holder) == []  # it compiled nothing, and ended


def test_the_lock_goes_with_a_holder_killed_outright(tmp_path):
    lock = tmp_path / "k.lock"
    holder = subprocess.Popen(
        [
            sys.executable,
            "-c",
            "import sys, time; from armanim.arm import kernel\n"
            "with kernel.held_alone(sys.argv[1]):\n    open(sys.argv[1] + '.held', 'w').close(); time.sleep(600)",
            str(lock),
        ],
    )
    try:
        _wait_for(Path(str(lock) + ".held"), holder)
        assert _locked_elsewhere(lock)
    finally:
        holder.send_signal(signal.SIGKILL)
        holder.wait()
    with kernel.held_alone(str(lock), wait_s=600):  # would wait 600 s were the lock still held
        assert _locked_elsewhere(lock)
    assert not _locked_elsewhere(lock)


def test_a_compile_that_fails_releases_the_lock(tmp_path):
    lock = tmp_path / "k.lock"
    with pytest.raises(ZeroDivisionError):
        with kernel.held_alone(str(lock)):
            assert _locked_elsewhere(lock)
            1 / 0  # noqa: B018
    assert not _locked_elsewhere(lock)


def test_another_thread_of_the_holders_process_goes_on_without_the_lock(tmp_path):
    # numba's own lock orders the threads of one process; waiting here as well could deadlock a
    # thread that holds numba's lock and compiles a kernel nested in this one.
    lock = str(tmp_path / "k.lock")
    entered = threading.Event()

    def other() -> None:
        with kernel.held_alone(lock, wait_s=600):
            entered.set()

    with kernel.held_alone(lock):
        thread = threading.Thread(target=other)
        thread.start()
        assert entered.wait(timeout=300)
        thread.join()
        assert _locked_elsewhere(Path(lock))  # still this thread's


def test_a_lock_that_cannot_be_made_compiles_as_before(tmp_path):
    with kernel.held_alone(str(tmp_path / "no-such-folder" / "k.lock")):
        pass


def test_a_link_at_the_lock_is_not_followed(tmp_path):
    (tmp_path / "k.lock").symlink_to(tmp_path / "elsewhere")
    with kernel.held_alone(str(tmp_path / "k.lock")):
        pass
    assert not (tmp_path / "elsewhere").exists()


def test_every_cached_kernel_compiles_under_the_lock():
    from armanim.world import compiled

    assert type(compiled.kind_count) is kernel._CompilesOnce
    assert kernel.compile_lock_path(compiled.kind_count, ()).endswith(".lock")


def _held_by_another_process(lock: Path) -> subprocess.Popen[str]:
    """A process holding ``lock`` (flock) until it is killed."""
    holder = subprocess.Popen(
        [
            sys.executable,
            "-c",
            "import fcntl, os, sys, time\nfd = os.open(sys.argv[1], os.O_RDWR | os.O_CREAT)\n"
            "fcntl.flock(fd, fcntl.LOCK_EX)\nopen(sys.argv[1] + '.held', 'w').close()\ntime.sleep(900)",
            str(lock),
        ],
        text=True,
    )
    _wait_for(Path(str(lock) + ".held"), holder)
    return holder


_LOAD = textwrap.dedent(
    """
    from numba import types
    from armanim.arm import kernel
    from armanim.world.compiled import kind_count
    waits = []
    getattr(kernel, "WAIT_LISTENERS", []).append(lambda path, seconds: waits.append(path))
    kind_count.compile((types.none,))
    stats = kind_count.stats
    print(sum(stats.cache_misses.values()), sum(stats.cache_hits.values()), len(waits))
    """
)


def test_a_kernel_already_in_the_cache_loads_without_waiting_on_its_lock(tmp_path):
    # campaign 17: a process holding every compile lock (a warm stopped with Ctrl-Z) kept a run on a
    # warmed cache waiting 600 s for each kernel it only had to load
    from numba import types

    from armanim.world.compiled import kind_count

    cache = tmp_path / "cache"
    first = _compiler("first", tmp_path, cache)
    (tmp_path / "second-ready").touch()  # the first compiles at once: no second process here
    assert _misses_and_hits(first) == ["1", "0"]
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache))
    lock_path = subprocess.run(
        [
            sys.executable,
            "-c",
            "from numba import types\nfrom armanim.arm import kernel\nfrom armanim.world.compiled import kind_count\n"
            "print(kernel.compile_lock_path(kind_count, (types.none,)))",
        ],
        env=env,
        capture_output=True,
        text=True,
        check=True,
    ).stdout.strip()
    assert kind_count is not None and types.none is not None
    holder = _held_by_another_process(Path(lock_path))
    try:
        loader = subprocess.run(
            [sys.executable, "-c", _LOAD], env=env, capture_output=True, text=True, timeout=300, check=True
        )
    finally:
        holder.kill()
        holder.wait()
    assert loader.stdout.split() == ["0", "1", "0"]  # loaded, compiled nothing, never waited


def test_waits_on_locks_held_elsewhere_are_told_and_share_one_budget(tmp_path, monkeypatch):
    # campaign 17: on a cold cache, a holder of every lock made each kernel wait its own 600 s
    told: list[str] = []
    monkeypatch.setattr(kernel, "_WAIT_LEFT", [1.5])
    monkeypatch.setattr(kernel, "WAIT_LISTENERS", [lambda path, seconds: told.append(path)])
    locks = [tmp_path / "a.lock", tmp_path / "b.lock"]
    holders = [_held_by_another_process(lock) for lock in locks]
    try:
        with kernel.held_alone(str(locks[0]), wait_s=600):  # waits out what is left of the budget
            pass
        with kernel.held_alone(str(locks[1]), wait_s=600):  # the budget spent: no wait at all
            pass
        assert told == [str(locks[0])]
        assert kernel._WAIT_LEFT == [0.0]
        assert all(_locked_elsewhere(lock) for lock in locks)  # the holders' still: it went on without
    finally:
        for holder in holders:
            holder.kill()
            holder.wait()


def test_a_process_compiling_without_holding_locks_waits_for_others_and_makes_none_wait(tmp_path, monkeypatch):
    """A first run's second process (armanim.runs.beside) waits for the run's compiles but never makes
    the run wait on its own (nor say that it waits)."""
    monkeypatch.setattr(kernel, "_HOLDS_LOCKS", [True])
    kernel.compile_without_holding_locks()
    lock = str(tmp_path / "k.lock")
    other = os.open(lock, os.O_RDWR | os.O_CREAT)
    fcntl.flock(other, fcntl.LOCK_EX)  # another process's compile under way
    entered = threading.Event()

    def compile_beside() -> None:
        with kernel.held_alone(lock):
            entered.set()
            mine = os.open(lock, os.O_RDWR)  # the run, meanwhile, takes the lock at once
            try:
                fcntl.flock(mine, fcntl.LOCK_EX | fcntl.LOCK_NB)
            finally:
                os.close(mine)

    worker = threading.Thread(target=compile_beside)
    worker.start()
    assert not entered.wait(0.3)  # it waits for the other's compile
    os.close(other)
    worker.join(timeout=60)
    assert entered.is_set() and not worker.is_alive()
