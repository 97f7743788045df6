"""Worker processes and signals (issue 19): a Ctrl-C while workers start is raised once they
have started, none is left running, a batch in one process stops at the error that follows a
signal, and batch workers start with Ctrl-C and SIGTERM blocked.

Each test is named in docs/reliability.md, which it keeps true.
"""

from __future__ import annotations

import contextlib
import threading
from pathlib import Path

import pytest


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
