"""Imported first by the batch pool's forkserver (``executors._PRELOAD``): it blocks SIGINT and
SIGTERM there, so that every worker the forkserver forks starts with them blocked until
:func:`armanim.procs.workers.init_worker` has put its handlers in place.

The forkserver inherits the mask of the thread that starts it, but CPython's resource
tracker, started just before it, unblocks both signals in that thread (see
:func:`armanim.procs.workers.resource_tracker_started`, which now keeps them blocked); this
block is the second line of defence: without either, a worker runs its first milliseconds
with Python's default handlers: a Ctrl-C to the group then raised
KeyboardInterrupt in it (a traceback on the terminal), and the parent's SIGTERM killed it
outright, once between the two halves of Python's temporary-folder probe (the signal sweep's
"litter: $TMPDIR/9kcrha9s" at a batch's "workers" moment). The forkserver itself needs
neither signal: it ignores Ctrl-C and ends when its parent does. It sets its own handlers
after the preload, and a signal that came meanwhile stays pending until then (SIGINT is
dropped when it is ignored).

Imported anywhere else (the doctest collection imports every module), it does nothing.
"""

from __future__ import annotations

import multiprocessing.forkserver
import signal
import sys
from types import FrameType

from armanim.procs.workers import WORKER_SIGNALS


def _importing_forkserver() -> bool:
    """Whether this import runs inside ``multiprocessing.forkserver.main`` (its preload)."""
    frame: FrameType | None = sys._getframe(1)
    while frame is not None:
        if frame.f_code is multiprocessing.forkserver.main.__code__:
            return True
        frame = frame.f_back
    return False


if _importing_forkserver():
    signal.pthread_sigmask(signal.SIG_BLOCK, WORKER_SIGNALS)
