"""Issue 19: the holes the second attack campaign found (research/redteam-2026-12.md), each
held by a test that failed before its fix.

Each test is named in docs/reliability.md, which it keeps true. No test asserts how long
anything takes (benchmarks/reliability_bench.py measures that); waits are hang guards only.
"""

from __future__ import annotations

import ast
import contextlib
import errno
import re
import socket
import threading
import tracemalloc
from pathlib import Path

import pytest
from conftest import DOCS, SCENES, TESTS
from signals import Command, Sweep, snapshot

from armanim.errors import INTERRUPTED, UsageError
from armanim.output.rundir import MARKER

NOTES = SCENES / "notes-arm.yaml"
SMALL = "version: 1\narm:\n  links: [1, 1, 1, 1]\ngoals:\n  - [1, 1, 2]\n"


def _small(folder: Path, name: str) -> Path:
    path = folder / f"{name}.yaml"
    path.write_text(SMALL + f"name: {name}\nrender: {{fps: 10, size: [64, 48]}}\n")
    return path


# ------------------------------------------------------------------ 1. user files at armanim's fixed names


def test_a_user_index_csv_stops_a_batch_before_any_work(cli, tmp_path):
    a, b = _small(tmp_path, "a"), _small(tmp_path, "b")
    out = tmp_path / "proj"
    out.mkdir()
    (out / "index.csv").write_text("my precious index\n")
    result = cli("run", a, b, "--out", out, "--no-video", "-q", "--jobs", "1")
    assert result.exit_code == 3, result.output
    assert "index.csv: this file was not written by armanim" in result.stderr and "move it away" in result.stderr
    assert (out / "index.csv").read_text() == "my precious index\n"
    assert sorted(p.name for p in out.iterdir()) == ["index.csv"]  # refused before any scene ran
    (out / "index.csv").unlink()
    for _ in range(2):  # armanim's own index.csv is replaced
        assert cli("run", a, b, "--out", out, "--no-video", "-q", "--jobs", "1").exit_code == 0
    assert (out / "index.csv").read_text().startswith("name,status,")


@pytest.mark.parametrize("name", ["notes-arm-sweep.csv", "index.csv"])
def test_a_user_file_at_a_sweep_table_stops_the_sweep(cli, tmp_path, name):
    (tmp_path / name).write_text("mine\n")
    result = cli("sweep", NOTES, "--set", "solver.step=0.1,0.2", "--out", tmp_path, "-q", "--jobs", "1")
    assert result.exit_code == 3 and "was not written by armanim" in result.stderr, result.output
    assert sorted(p.name for p in tmp_path.iterdir()) == [name] and (tmp_path / name).read_text() == "mine\n"


@pytest.fixture()
def finished_run(cli, tmp_path) -> Path:
    assert cli("run", _small(tmp_path, "r"), "--out", tmp_path / "out", "--no-video", "-q").exit_code == 0
    return tmp_path / "out" / "r"


def test_render_out_writes_only_into_a_new_empty_or_armanim_folder(cli, tmp_path, finished_run):
    figures = tmp_path / "figures"
    figures.mkdir()
    (figures / "plot.png").write_text("my figure")
    result = cli("render", finished_run, "--out", figures, "-q", "--jobs", "1")
    assert result.exit_code == 3 and "not made by armanim" in result.stderr and "plot.png" in result.stderr
    assert sorted(p.name for p in figures.iterdir()) == ["plot.png"] and (figures / "plot.png").read_text() == "my figure"
    fresh = tmp_path / "fresh"
    for _ in range(2):  # a new folder, then the folder armanim marked: replaced
        assert cli("render", finished_run, "--out", fresh, "-q", "--jobs", "1").exit_code == 0
    assert sorted(p.name for p in fresh.iterdir()) == [MARKER, "animation.mp4", "plot.png", "poster.png"]


def test_render_out_inside_the_run_folder_is_refused(cli, finished_run):
    before = snapshot(finished_run)
    result = cli("render", finished_run, "--out", finished_run / "small", "-q", "--jobs", "1")
    assert result.exit_code == 2 and "is inside the run folder" in result.stderr, result.output
    assert snapshot(finished_run) == before


# ------------------------------------------------------------------ 2. the marker records what armanim wrote


def test_a_user_folder_at_a_listed_name_stops_the_next_run(cli, tmp_path, finished_run):
    (finished_run / "summary.json").unlink()
    (finished_run / "summary.json").mkdir()
    (finished_run / "summary.json" / "notes.txt").write_text("notes")
    result = cli("run", tmp_path / "r.yaml", "--out", tmp_path / "out", "--no-video", "-q")
    assert result.exit_code == 3, result.output
    assert "changed since armanim wrote them (summary.json" in result.stderr
    assert (finished_run / "summary.json" / "notes.txt").read_text() == "notes"


def test_a_listed_file_edited_since_stops_the_next_run(cli, tmp_path, finished_run):
    with (finished_run / "trajectory.csv").open("a") as handle:
        handle.write("# my note\n")
    before = snapshot(finished_run)
    result = cli("run", tmp_path / "r.yaml", "--out", tmp_path / "out", "--no-video", "-q")
    assert result.exit_code == 3 and "trajectory.csv" in result.stderr, result.output
    assert snapshot(finished_run) == before


@pytest.mark.parametrize("marker", ['{"made_by": "armanim", "files": null}', "not json"])
def test_an_unreadable_marker_is_named_as_such(cli, tmp_path, finished_run, marker):
    (finished_run / MARKER).write_text(marker)
    result = cli("run", tmp_path / "r.yaml", "--out", tmp_path / "out", "--no-video", "-q")
    assert result.exit_code == 3 and f"its {MARKER} cannot be read as armanim's marker" in result.stderr, result.output
    assert "no .armanim-run.json" not in result.stderr


# ------------------------------------------------------------------ 3, 9. golden pairs


def _pair(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir())}


@pytest.mark.parametrize("previous", [False, True])
def test_a_failure_on_the_second_golden_file_leaves_the_pair_as_it_was(cli, tmp_path, monkeypatch, previous):
    import os

    golden = tmp_path / "golden"
    golden.mkdir()
    scene = tmp_path / "g.yaml"
    scene.write_text(SMALL + "name: g\n")
    if previous:
        assert cli("check", scene, "--golden", golden, "--update", "-q").exit_code == 0
        scene.write_text(SMALL.replace("[1, 1, 2]", "[1, 1.5, 2]") + "name: g\n")
    before = _pair(golden)
    real_replace = os.replace

    def full_on_json(src, dst):
        if str(dst).endswith("g.json"):
            raise OSError(errno.ENOSPC, "No space left on device")
        real_replace(src, dst)

    monkeypatch.setattr("armanim.output.atomic.os.replace", full_on_json)
    result = cli("check", scene, "--golden", golden, "--update", "-q")
    assert result.exit_code == 3 and "g.json: the disk is full" in result.stderr, result.output
    assert _pair(golden) == before  # old/old (or nothing), never a new CSV beside an old JSON; no temporary file


def test_update_with_a_golden_csv_that_is_not_utf8_replaces_it(cli, tmp_path):
    (tmp_path / "notes-arm.csv").write_bytes(b"frame,\xff\xfe\n")
    result = cli("check", NOTES, "--golden", tmp_path, "--update")
    assert result.exit_code == 0 and "changed" in result.stdout, result.output
    assert (tmp_path / "notes-arm.csv").read_bytes().startswith(b"frame,time_s,")


def test_the_old_golden_csv_is_compared_without_reading_it_whole(tmp_path):
    from armanim.runs.golden import golden_status

    big = tmp_path / "big.csv"
    with big.open("wb") as handle:
        handle.truncate(2**31)  # 2 GiB, sparse
    tracemalloc.start()
    try:
        status = golden_status(big, b"frame,time_s\n0,0.0\n")
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert status == "changed" and peak < 2**20
    same = tmp_path / "same.csv"
    same.write_bytes(b"frame\n0\n")
    assert golden_status(same, b"frame\n0\n") == "unchanged" and golden_status(tmp_path / "none.csv", b"x") == "new"


# ------------------------------------------------------------------ 4. a scheduler that never answers


@pytest.fixture
def listening_port():
    """A port on 127.0.0.1 that accepts connections (the kernel's backlog) and never answers."""
    with socket.create_server(("127.0.0.1", 0)) as server:
        yield server.getsockname()[1]


@pytest.fixture
def closed_port():
    """A port on 127.0.0.1 that nothing listens on: bound and released."""
    with socket.create_server(("127.0.0.1", 0)) as server:
        port = server.getsockname()[1]
    return port


def test_a_scheduler_that_never_answers_is_given_up_after_the_deadline(listening_port):
    """The client is made on a thread that is given up: Client(timeout=...) does not bound the handshake."""
    from armanim.procs.executors import connect_client

    release = threading.Event()

    def silent_client(address, timeout):
        release.wait()  # accepts, never answers

    address = f"tcp://127.0.0.1:{listening_port}"
    try:
        with pytest.raises(UsageError, match=rf"the Dask scheduler at {address} did not answer within 0.2 s"):
            connect_client(silent_client, address, seconds=0.2)
    finally:
        release.set()


@pytest.mark.parametrize("error, words", [(ValueError("bad"), "is not a scheduler address"),
                                          (OSError("refused"), "cannot reach the Dask scheduler at")])
def test_a_scheduler_that_fails_is_exit_2_with_its_reason(error, words, listening_port):
    from armanim.procs.executors import connect_client

    def failing_client(address, timeout):
        raise error

    with pytest.raises(UsageError, match=words):
        connect_client(failing_client, f"tcp://127.0.0.1:{listening_port}", seconds=30)


@pytest.mark.parametrize("address, words", [("tcp://127.0.0.1:{closed}", r"connection refused: nothing listens on port {closed}"),
                                            ("127.0.0.1:{closed}", r"connection refused"),
                                            ("tcp://no-such-host.invalid:8786", r"no such host 'no-such-host.invalid'")])
def test_a_refused_scheduler_is_reported_at_once_not_after_the_timeout(address, words, closed_port):
    """Dask's client retries a refused port for its whole timeout and then calls it a timeout;
    armanim asks the port first, so the client is never made and the reason is the real one."""
    from armanim.procs.executors import connect_client

    def client_that_must_not_be_made(address, timeout):
        raise AssertionError("the client was made for a port that refuses")

    address = address.format(closed=closed_port)
    with pytest.raises(UsageError, match=rf"cannot reach the Dask scheduler at {re.escape(address)} \({words.format(closed=closed_port)}"):
        connect_client(client_that_must_not_be_made, address, seconds=30)


# ------------------------------------------------------------------ 5, 6. sweeps have a bound and say their size


def test_a_sweep_beyond_the_limit_is_exit_2_before_anything_is_built(cli, tmp_path):
    from armanim.runs.sweep import MAX_VARIANTS

    steps = ",".join(str(0.001 * (i + 1)) for i in range(50))
    tolerances = ",".join(str(0.0001 * (i + 1)) for i in range(MAX_VARIANTS // 50 + 1))
    result = cli("sweep", NOTES, "--set", f"solver.step={steps}", "--set", f"solver.tolerance={tolerances}", "--out", tmp_path)
    assert result.exit_code == 2, result.output
    assert f"--set: 1,050 variants (50 x 21 values; at most {MAX_VARIANTS:,} in one sweep" in result.stderr
    assert list(tmp_path.iterdir()) == []


def test_a_sweep_and_a_batch_say_their_size_first(cli, tmp_path):
    result = cli("sweep", _small(tmp_path, "s"), "--set", "solver.step=0.1,0.2,0.1", "--out", tmp_path / "o", "--jobs", "1")
    assert result.exit_code == 0, result.output
    assert result.stderr.splitlines()[0] == f"sweep of {tmp_path / 's.yaml'}: 2 variants (solver.step)"
    result = cli("run", _small(tmp_path, "a"), _small(tmp_path, "b"), "--out", tmp_path / "o", "--no-video", "--jobs", "1")
    assert result.exit_code == 0 and result.stderr.splitlines()[0] == "batch: 2 scenes", result.output


# ------------------------------------------------------------------ 10. a closed pipe


@pytest.mark.parametrize("args, code", [(["validate", NOTES], 0), (["check", NOTES, "--golden", TESTS / "golden"], 0),
                                        (["fk", "--angles", "0,0,0,0"], 0), (["check", "BROKEN", "--golden", "GOLDEN"], 1)])
def test_a_closed_pipe_keeps_the_command_s_own_exit_code(tmp_path, args, code):
    """``armanim validate s.yaml | head -0``: exit 0 (a failed check stays 1), never click's 1 for EPIPE, no message."""
    import subprocess
    import sys

    if "BROKEN" in args:  # a golden file that differs: the check fails whether or not anyone reads
        (tmp_path / "notes-arm.csv").write_text((TESTS / "golden" / "notes-arm.csv").read_text().replace(",0,", ",1,", 1))
        args = ["check", NOTES, "--golden", tmp_path]
    proc = subprocess.Popen([sys.executable, "-m", "armanim", *map(str, args)], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    proc.stdout.close()  # the reader is gone before armanim writes
    stderr = proc.stderr.read().decode()
    assert proc.wait(timeout=300) == code, stderr
    assert "Traceback" not in stderr and "Broken pipe" not in stderr


# ------------------------------------------------------------------ the wrong-but-harmless list


def test_render_refuses_a_scene_yaml_that_is_not_the_run_s(cli, finished_run):
    (finished_run / "scene.yaml").write_text(SMALL.replace("[1, 1, 2]", "[1, 2, 1]") + "name: r\n")
    result = cli("render", finished_run, "-q", "--jobs", "1")
    assert result.exit_code == 2 and "scene.yaml: is not the scene this run solved" in result.stderr, result.output


@pytest.mark.parametrize("column, value, message", [("goal", "1", "goal: 1 is not a goal of the scene (expected 0 to 0)"),
                                                    ("time_s", "-5", "time_s: -5 is negative")])
def test_render_refuses_a_goal_past_the_last_and_a_negative_time(cli, finished_run, column, value, message):
    lines = (finished_run / "trajectory.csv").read_text().splitlines()
    at = lines[0].split(",").index(column)
    row = lines[2].split(",")
    row[at] = value
    lines[2] = ",".join(row)
    (finished_run / "trajectory.csv").write_text("\n".join(lines) + "\n")
    result = cli("render", finished_run, "-q", "--jobs", "1")
    assert result.exit_code == 2 and f"trajectory.csv:3: {message}" in result.stderr, result.output


def test_a_scene_yaml_linked_to_a_device_is_named_as_one(cli, finished_run):
    (finished_run / "scene.yaml").unlink()
    (finished_run / "scene.yaml").symlink_to("/dev/zero")
    result = cli("render", finished_run, "-q")
    assert result.exit_code == 2 and "is a character device, not a regular file" in result.stderr, result.output


def test_a_huge_flag_value_is_cut_in_the_message(cli):
    result = cli("fk", "--angles", ",".join(["1"] * 60_000))
    assert result.exit_code == 2 and "(got 60,000:" in result.stderr and "(119,999 characters)" in result.stderr
    assert len(result.stderr) < 300, len(result.stderr)


def test_a_disk_full_message_names_the_run_folder_not_its_staging(cli, tmp_path, monkeypatch):
    import os

    real_fsync = os.fsync

    def full(fd):
        if ".partial/" in os.readlink(f"/proc/self/fd/{fd}"):  # OUT is full (not TMPDIR: that message names TMPDIR)
            raise OSError(errno.ENOSPC, "No space left on device")
        real_fsync(fd)

    monkeypatch.setattr("armanim.output.atomic.os.fsync", full)
    result = cli("run", _small(tmp_path, "a"), _small(tmp_path, "b"), "--out", tmp_path / "out", "--no-video", "-q", "--jobs", "1")
    assert result.exit_code == 3, result.output
    assert f"{tmp_path / 'out' / 'a'}/scene.yaml: the disk is full" in result.stderr and ".partial" not in result.stderr


def test_a_dangling_link_at_the_lock_is_refused_not_followed(cli, tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / ".a.lock").symlink_to(tmp_path / "elsewhere")
    result = cli("run", _small(tmp_path, "a"), "--out", out, "--no-video", "-q")
    assert result.exit_code == 3 and ".a.lock: is a link" in result.stderr, result.output
    assert not (tmp_path / "elsewhere").exists()


# ------------------------------------------------------------------ 7, 8. signals over each command's life

TINY = ("version: 1\nname: tiny\narm:\n  links: [1, 1]\ngoals:\n  - [1, 1, 0]\n  - {{position: [0, 1.5, 0.5], hold: 3}}\n"
        "solver: {{step: {step}}}\nrender: {{fps: 10, size: [96, 64]}}\n")  # about 70 frames: two render workers


def _scenes(folder: Path, count: int = 1) -> tuple[list[str], list[str]]:
    """``count`` new scenes and their previous versions (same names, another step: other bytes)."""
    folder.mkdir(parents=True, exist_ok=True)
    new, old = [], []
    for i in range(count):
        for step, paths in ((0.1, new), (0.3, old)):
            path = folder / f"{'new' if step == 0.1 else 'old'}{i}.yaml"
            path.write_text(TINY.format(step=step).replace("name: tiny", f"name: tiny{i}"))
            paths.append(str(path))
    return new, old


def _commands(folder: Path) -> dict:
    new, old = _scenes(folder / "scenes", 2)
    run_folder = ["out/tiny0"]
    batch = ["out/tiny0", "out/tiny1"]
    sweep = ["out/tiny0_step-0.1", "out/tiny0_step-0.2"]
    return {
        "run": Command("run", ["run", new[0], "--out", "{out}", "--jobs", "2"], run_folder,
                       [["run", old[0], "--out", "{out}", "--no-video"]]),  # the previous outputs need no video to differ
        "batch": Command("batch", ["run", *new, "--out", "{out}", "--jobs", "2"], [*batch, "out/index.csv"],
                         [["run", *old, "--out", "{out}", "--jobs", "2", "--no-video"]]),
        "sweep": Command("sweep", ["sweep", new[0], "--set", "solver.step=0.1,0.2", "--out", "{out}", "--jobs", "2"],
                         [*sweep, "out/new0-sweep.csv"],
                         [["sweep", old[0], "--set", "solver.step=0.1,0.2", "--set", "solver.max_step=0.4", "--out", "{out}", "--jobs", "2", "--no-video"]]),
        "check --update": Command("check", ["check", *new, "--golden", "{golden}", "--update"], ["golden/tiny0.*", "golden/tiny1.*"],
                                  [["check", *old, "--golden", "{golden}", "--update"]]),
        "render": Command("render", ["render", "{out}/tiny0", "--jobs", "2", "--size", "80x48"], run_folder,
                          [["run", new[0], "--out", "{out}", "--no-video"]]),
    }


MOMENTS = {  # a handful per command (each attempt is a real process); benchmarks/signal_campaign.py sweeps many more
    "run": [("start", 0.0, "SIGTERM"), ("ffmpeg", 0.2, "SIGINT"), ("poster", 0.0, "SIGINT"), ("poster", 0.05, "SIGTERM")],
    "batch": [("workers", 0.0, "SIGINT"), ("ffmpeg", 0.1, "SIGTERM")],
    "sweep": [("workers", 0.0, "SIGTERM")],
    "check --update": [("start", 0.5, "SIGINT")],
    "render": [("ffmpeg", 0.0, "SIGINT"), ("poster", 0.02, "SIGTERM")],
}


def _attempt_until_the_moment_comes(sweep: Sweep, moment: str, delay: float, signame: str, tries: int = 8):
    """An attempt whose moment came (or that went wrong); a busy machine can make a short
    moment (the poster: tens of milliseconds) pass between two polls, so such an attempt is
    made again (with both cores busy, 3 tries missed it in about one run of the sweep in four)."""
    for _ in range(tries):
        outcome = sweep.attempt(moment, delay, signame)
        if outcome.fired or outcome.problems():
            return outcome
    return outcome


@pytest.mark.slow
@pytest.mark.parametrize("name", MOMENTS)
def test_a_signal_at_any_moment_ends_with_0_or_130_and_old_or_new_outputs(tmp_path, name):
    """Ctrl-C (to the group) and SIGTERM (to armanim) over each command's life, at the commit too:
    exit 0 or 130, no traceback, each folder (golden pair) old or whole new, no litter, no process left."""
    sweep = Sweep(_commands(tmp_path)[name], tmp_path / "sweep")
    outcomes = [_attempt_until_the_moment_comes(sweep, *moment) for moment in MOMENTS[name]]
    wrong = {o.moment + " " + o.signame: o.problems() + [o.stderr[-2000:]] for o in outcomes if o.problems()}
    assert wrong == {}
    assert all(o.fired for o in outcomes), [o.moment for o in outcomes if not o.fired]  # each moment came: a real test
    for o in outcomes:
        interrupted = o.code == 130
        assert o.stderr.strip().splitlines()[-1:] == ([INTERRUPTED] if interrupted else o.stderr.strip().splitlines()[-1:])


_SWALLOWED_CTRL_C = """
import gc, signal, sys, weakref
from armanim.cli.interrupts import command_signals, own_the_process
if sys.argv[1] == "process":
    own_the_process()

class Node:  # matplotlib's transform tree: parents held by weak references with a callback
    pass

try:
    with command_signals():
        parent, reached = Node(), []
        def forget(ref):  # the Ctrl-C comes while the garbage collector runs this callback
            signal.raise_signal(signal.SIGINT)
            reached.append("the callback's end")
        ref = weakref.ref(parent, forget)
        del parent
        gc.collect()
        for _ in range(1000):
            reached.append("the command went on")
except KeyboardInterrupt:
    print(reached, "interrupted")
    sys.exit(130)
print(reached, "finished")
"""


@pytest.mark.parametrize("mode", ["process", "runner"])
def test_a_ctrl_c_swallowed_in_a_weakref_callback_still_interrupts_at_once(tmp_path, mode):
    """Python cannot raise in a weakref callback or ``__del__``: it prints "Exception ignored" and goes
    on, here with the first Ctrl-C spent. It left matplotlib's transform tree half-updated, and the
    render went on to fail with a traceback and exit 1 (CI, [render] at "ffmpeg", [run] at "poster").
    The interrupt must come back at once, silently, in the armanim process and in a test's runner."""
    import subprocess
    import sys

    script = tmp_path / "swallowed.py"
    script.write_text(_SWALLOWED_CTRL_C)
    done = subprocess.run([sys.executable, str(script), mode], capture_output=True, text=True, timeout=60)
    assert (done.returncode, done.stdout.strip(), done.stderr) == (130, "[] interrupted", "")


@pytest.fixture()
def ctrl_c_raises():
    """Ctrl-C raises KeyboardInterrupt here (a test runner's worker may have set another handler), and a
    second thread that does not block it is there: where the kernel delivers a process's signal while
    the main thread blocks it (as a progress bar's refresh thread is in a real batch)."""
    import signal

    old = signal.signal(signal.SIGINT, signal.default_int_handler)
    idle = threading.Event()
    threading.Thread(target=idle.wait, name="test-idle", daemon=True).start()
    yield
    idle.set()
    signal.signal(signal.SIGINT, old)


def test_a_ctrl_c_while_processes_start_is_raised_only_when_they_have_started(ctrl_c_raises):
    """Blocking the signal in the starting thread is not enough: another thread receives it, and Python
    runs the handler in the main thread at once, between a process's start and its caller's record of it."""
    import os
    import signal
    import time

    from armanim.procs.workers import signals_blocked

    reached = []
    with pytest.raises(KeyboardInterrupt):
        with signals_blocked():
            os.kill(os.getpid(), signal.SIGINT)
            time.sleep(0.3)  # time for the other thread to take it; Python would raise right after
            reached.append("the end of the block")
    assert reached == ["the end of the block"]


def test_a_ctrl_c_as_the_pool_starts_a_worker_leaves_no_worker_running(ctrl_c_raises, monkeypatch):
    """The batch's pool: a Ctrl-C just after the forkserver made a worker, before the pool listed it.
    The worker must be stopped with the rest (left running, it died with a traceback on the terminal
    once the batch had ended: the CI failure of [batch] at "workers")."""
    import multiprocessing.popen_forkserver
    import operator
    import os
    import signal
    import types

    import psutil

    from armanim.procs.executors import _LocalExecutor, _worker_context

    if _worker_context().get_start_method() != "forkserver":
        pytest.skip("the race is the forkserver's")
    launched = []
    launch = multiprocessing.popen_forkserver.Popen._launch

    def launch_then_ctrl_c(self, process_obj):
        launch(self, process_obj)
        launched.append(self.pid)
        if len(launched) == 1:
            os.kill(os.getpid(), signal.SIGINT)

    monkeypatch.setattr(multiprocessing.popen_forkserver.Popen, "_launch", launch_then_ctrl_c)
    tasks = [types.SimpleNamespace(name=n) for n in "ab"]
    try:
        with pytest.raises(KeyboardInterrupt):
            list(_LocalExecutor(2).map(operator.attrgetter("name"), tasks))
        running = [pid for pid in launched if psutil.pid_exists(pid) and psutil.Process(pid).status() != "zombie"]
        assert launched and running == []
    finally:
        for pid in launched:
            with contextlib.suppress(ProcessLookupError):
                os.kill(pid, signal.SIGKILL)


_CTRL_C_IN_TEXT = """
import typer
from armanim.cli.app import handle_errors
from armanim.cli.interrupts import own_the_process

app = typer.Typer()


@app.command()
@handle_errors
def make() -> None:
    exec("import signal; signal.raise_signal(signal.SIGINT)")  # as a dataclass makes its methods from text


own_the_process()
app()
"""


def test_a_ctrl_c_in_code_run_from_text_ends_with_130_not_by_the_signal(tmp_path):
    """CPython notes a KeyboardInterrupt that leaves exec'd text (dataclasses and pydantic make their
    methods so) in a flag that catching it does not clear, and ``python -m`` then killed itself with
    SIGINT at exit: the signal campaign's "render start+0.4 SIGINT: exit -2", after the right line."""
    import subprocess
    import sys

    (tmp_path / "ctrl_c_in_text.py").write_text(_CTRL_C_IN_TEXT)
    done = subprocess.run([sys.executable, "-m", "ctrl_c_in_text"], cwd=tmp_path, capture_output=True, text=True, timeout=60)
    assert (done.returncode, done.stderr.strip()) == (130, INTERRUPTED)


class _TransformThatMeetsACtrlC:
    """A matplotlib transform's matrix, asked for while a Ctrl-C comes."""

    def __array__(self, dtype=None, copy=None):
        import signal

        import numpy as np

        signal.raise_signal(signal.SIGINT)
        return np.eye(3)


def test_a_ctrl_c_that_matplotlib_turns_into_an_error_still_ends_with_130(capsys):
    """matplotlib's pybind11 layer clears a KeyboardInterrupt raised while it converts a transform and
    raises "Invalid affine transformation matrix" instead: CI's [render] at "ffmpeg" ended with that
    traceback and exit 1. After a signal, any error is the signal's."""
    import numpy as np
    import typer
    from matplotlib import _path

    from armanim.cli.app import handle_errors

    def drawing():
        _path.affine_transform(np.zeros((2, 2)), _TransformThatMeetsACtrlC())

    with pytest.raises(ValueError, match="Invalid affine transformation matrix"):
        drawing()  # the library's doing, outside a command (Python's own handler raised)
    with pytest.raises(typer.Exit) as exited:
        handle_errors(drawing)()
    assert exited.value.exit_code == 130 and capsys.readouterr().err.strip() == INTERRUPTED
    from armanim.procs.interrupted import signal_came

    assert not signal_came()  # answered: a batch run through the API later is not taken for interrupted


def test_a_batch_in_one_process_stops_at_an_error_that_follows_a_signal():
    """With --jobs 1 a scene's error is reported and the batch goes on; one that a Ctrl-C became
    (above) must stop the batch instead, or the user's Ctrl-C is lost (later ones are ignored)."""
    import types

    from armanim.procs.executors import _LocalExecutor
    from armanim.procs.interrupted import forget_signal, note_signal

    def work(task):
        if task.name == "b":
            note_signal()  # what the handler does as the Ctrl-C comes
        raise ValueError(task.name)

    tasks = [types.SimpleNamespace(name=n) for n in "abc"]
    forget_signal()  # as a command starts
    try:
        seen = []
        with pytest.raises(ValueError, match="b"):
            for task, _, exc in _LocalExecutor(1).map(work, tasks):
                seen.append((task.name, str(exc)))
        assert seen == [("a", "a")]  # an ordinary error is the scene's; the batch went on to b, not to c
    finally:
        forget_signal()


def _forkserver_masks(task) -> dict[str, int]:
    """In a batch worker: the signal masks of its parent, the pool's forkserver."""
    import os

    status = Path(f"/proc/{os.getppid()}/status").read_text().splitlines()
    return {line.split(":")[0]: int(line.split()[1], 16) for line in status if line.startswith(("SigBlk", "SigIgn"))}


def test_a_batch_worker_starts_with_ctrl_c_and_sigterm_blocked():
    """The forkserver is started by fork and exec, which resets the signal mask: its workers ran their
    first milliseconds with Python's default handlers, so a Ctrl-C raised a traceback there and the
    parent's SIGTERM killed one between the halves of Python's temporary-folder probe ("litter:
    $TMPDIR/dimjs171" at a batch's "workers" moment, under load). The forkserver blocks both (what
    it forks inherits that) and ignores Ctrl-C."""
    import signal
    import types

    from armanim.procs.executors import _LocalExecutor, _worker_context

    if _worker_context().get_start_method() != "forkserver" or not Path("/proc/self/status").exists():
        pytest.skip("the forkserver's, read from /proc")
    tasks = [types.SimpleNamespace(name=n) for n in "ab"]
    results = [(result, exc) for _, result, exc in _LocalExecutor(2).map(_forkserver_masks, tasks)]
    both = (1 << (signal.SIGINT - 1)) | (1 << (signal.SIGTERM - 1))
    for masks, exc in results:
        assert exc is None
        assert masks["SigBlk"] & both == both and masks["SigIgn"] & (1 << (signal.SIGINT - 1))


# ------------------------------------------------------------------ the page of promises


def named_tests(page: str) -> set[tuple[str, str]]:
    r"""(test file, test name) of every test docs/reliability.md names.

    A name is ``tests/FILE.py::test_x``; ``::test_x`` (in the file named last on the page);
    or a bare ``test_x`` (in the file named before it on its line, else ``tests/test_hardening.py``).

    >>> sorted(named_tests("| `test_a` | `tests/test_b.py::test_c`, `::test_d[x]` |\n| `test_e`, `::test_f` |"))
    [('test_b.py', 'test_c'), ('test_b.py', 'test_d'), ('test_b.py', 'test_f'), ('test_hardening.py', 'test_a'), ('test_hardening.py', 'test_e')]
    """
    found, last = set(), "test_hardening.py"
    for line in page.splitlines():
        on_line = "test_hardening.py"
        for ref in re.findall(r"`([^`]*test_\w+[^`]*)`", line):
            match = re.fullmatch(r"(tests/(test_\w+\.py))?(::)?(test_\w+)(?:\[.*\])?", ref.strip())
            if match is None:
                continue
            if match.group(2):
                last = on_line = match.group(2)
            found.add((match.group(2) or (last if match.group(3) else on_line), match.group(4)))
    return found


def test_every_test_the_reliability_page_names_exists():
    named = named_tests((DOCS / "reliability.md").read_text(encoding="utf-8"))
    defined = {(path.name, node.name) for path in TESTS.glob("test_*.py")
               for node in ast.parse(path.read_text()).body if isinstance(node, ast.FunctionDef)}
    assert len(named) > 50 and named <= defined, sorted(named - defined)


def test_the_reliability_page_names_every_test_of_this_file():
    named = {name for file, name in named_tests((DOCS / "reliability.md").read_text(encoding="utf-8"))
             if file == Path(__file__).name}
    here = {name for name in globals() if name.startswith("test_") and "reliability_page" not in name}
    assert here <= named, sorted(here - named)
