"""Worker processes that never outlive the armanim process that started them, and stop
quietly: no traceback, no ffmpeg and no temporary folder left.

A worker killed with its parent (``kill -9``, a power cut of the terminal) would go on
drawing, encoding and holding the run folder's lock until its work is done. Each worker
watches the armanim process (a pidfd where Linux has one, else polling) and, when it
ends, sends itself SIGTERM. Workers ignore Ctrl-C and SIGHUP: the terminal sends them to the
whole process group, and the parent decides (it stops them with SIGTERM).

A SIGTERM in a worker does not raise in whatever frame happens to run (an initializer, a
weakref callback or the pool's own loop would print it, or swallow it and carry on):
the handler runs the worker's registered clean-ups (:func:`undone_on_stop`: kill its
ffmpeg, remove its temporary folder) and ends the process with ``os._exit``. Workers are
started with SIGINT, SIGTERM and SIGHUP blocked (:func:`signals_blocked`) and unblock them only
once these handlers are in place.

It sits in ``procs/``, the process room: ``render/`` starts a video's segment workers with it
and ``runs/`` its batch workers.
"""

from __future__ import annotations

import contextlib
import itertools
import os
import select
import signal
import tempfile
import threading
import time
from collections.abc import Callable, Iterator

from armanim.procs.deferred import interrupts_deferred
from armanim.procs.interrupted import INTERRUPT_SIGNALS

POLL_SECONDS = 0.5  # where there is no pidfd
WORKER_SIGNALS = INTERRUPT_SIGNALS
TEMP_PREFIX = "armanim-"
"""Temporary folders of armanim's workers are ``$TMPDIR/armanim-<PID>-*``, PID the armanim
process that started the worker, so that it removes what a stopped worker left."""

_UNDO: dict[int, Callable[[], None]] = {}
_KEYS = itertools.count()
_parent: list[int] = []  # in a worker: the armanim process that started it


def on_stop(undo: Callable[[], None]) -> int:
    """Run ``undo()`` if this worker is stopped (SIGTERM) before :func:`forget` of the key returned.

    Outside a worker it only records ``undo``. ``undo`` runs in a signal handler just
    before ``os._exit``: it must be quick and must not wait for a lock (killing a process
    and removing a folder are fine).
    """
    key = next(_KEYS)
    _UNDO[key] = undo
    return key


def forget(key: int) -> None:
    """The clean-up registered as ``key`` is no longer needed."""
    _UNDO.pop(key, None)


@contextlib.contextmanager
def undone_on_stop(undo: Callable[[], None]) -> Iterator[None]:
    """:func:`on_stop` for the duration of a block."""
    key = on_stop(undo)
    try:
        yield
    finally:
        forget(key)


def _stop(signum, frame):
    """SIGTERM in a worker: undo what it was doing, then end at once with 128 + signum."""
    signal.signal(signal.SIGTERM, signal.SIG_IGN)
    for undo in reversed(list(_UNDO.values())):
        with contextlib.suppress(Exception):
            undo()
    os._exit(128 + signum)


def alive(pid: int) -> bool:
    """Whether process ``pid`` exists (one that is not ours counts)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:
        return True
    return True


def _watch(pid: int, pidfd: int | None) -> None:
    if pidfd is not None:
        select.select([pidfd], [], [])  # readable once the process has ended
    else:
        while alive(pid):
            time.sleep(POLL_SECONDS)
    os.kill(os.getpid(), signal.SIGTERM)


def die_with(pid: int) -> None:
    """Send this process SIGTERM as soon as process ``pid`` ends (at once if it has already)."""
    try:
        pidfd = os.pidfd_open(pid) if hasattr(os, "pidfd_open") else None
    except ProcessLookupError:
        os.kill(os.getpid(), signal.SIGTERM)
        return
    except OSError:
        pidfd = None
    threading.Thread(target=_watch, args=(pid, pidfd), name="armanim-parent-watch", daemon=True).start()


def init_worker(parent: int) -> None:
    """Set up a worker process: Ctrl-C ignored, SIGTERM a quiet exit, and gone with ``parent``.

    The worker was started with both signals blocked (:func:`signals_blocked`); they are
    unblocked last, so one that came meanwhile finds these handlers (a pending SIGINT is
    dropped, a pending SIGTERM ends the worker quietly), and what must not be cut short by
    them (finding the temporary folder) is done before.
    """
    _parent[:] = [parent]
    _UNDO.clear()  # a forked worker must never run its parent's clean-ups
    # Python finds its temporary folder on first use by writing and removing a probe file there
    # (8 random characters); a SIGTERM's os._exit between the two would leave it behind, so
    # that happens now, while the signals are still blocked
    tempfile.gettempdir()
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGHUP, signal.SIG_IGN)  # the terminal closing, to the group: the parent decides too
    signal.signal(signal.SIGTERM, _stop)
    die_with(parent)
    signal.pthread_sigmask(signal.SIG_UNBLOCK, WORKER_SIGNALS)


@contextlib.contextmanager
def signals_blocked() -> Iterator[None]:
    """Hold SIGINT, SIGTERM and SIGHUP back while processes start, and deliver them when it ends.

    Two things are needed. The signals are blocked in this thread, so that processes
    started meanwhile (and a forkserver, and what it forks) start with them blocked. And
    their Python handlers are held back (:func:`armanim.procs.deferred.interrupts_deferred`):
    the kernel gives a process's signal to any thread that does not block it (a progress
    bar's), yet Python runs the handler in the main thread, which would raise
    KeyboardInterrupt between a process's start and its caller's record of it, leaving a
    worker nobody stops (it then dies unpickling what its ended parent unlinked, with a
    traceback on the terminal).
    """
    with interrupts_deferred():
        old = signal.pthread_sigmask(signal.SIG_BLOCK, WORKER_SIGNALS)
        try:
            yield
        finally:
            signal.pthread_sigmask(signal.SIG_SETMASK, old)  # then the held signals are delivered


def resource_tracker_started(context) -> None:
    """Start multiprocessing's resource tracker for ``context`` now, if its start method uses one,
    and leave this thread's signal mask as it was.

    CPython's ``resource_tracker.ensure_running`` (3.11 to 3.13) blocks SIGINT and SIGTERM around
    the tracker's start and then *unblocks* both, whatever the mask was before. A forkserver's
    start calls it first, so inside :func:`signals_blocked` the forkserver was then started with
    both signals unblocked: a Ctrl-C in its first ~50 ms (its interpreter importing
    ``multiprocessing.forkserver``, before its preload blocks them and before it ignores Ctrl-C)
    printed its KeyboardInterrupt traceback (campaign 10). Started here first, the tracker is
    running when the forkserver starts, and the forkserver inherits the blocked mask from its
    first instruction. No disposition is changed anywhere: nothing this starts ignores a signal.
    """
    if context.get_start_method() == "fork":
        return  # no tracker: the workers are plain forks of this thread, its mask included
    from multiprocessing import resource_tracker

    mask = signal.pthread_sigmask(signal.SIG_BLOCK, ())
    try:
        resource_tracker.ensure_running()
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, mask)


def temp_prefix() -> str:
    """The prefix of a worker's temporary folder: ``armanim-<PID of the armanim process>-``.

    >>> temp_prefix() == f"armanim-{os.getpid()}-"  # not in a worker: this process's
    True
    """
    return f"{TEMP_PREFIX}{(_parent or [os.getpid()])[0]}-"
