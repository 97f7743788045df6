"""Worker processes that never outlive the armanim process that started them.

A worker killed with its parent (``kill -9``, a power cut of the terminal) would go on
drawing, encoding and holding the run folder's lock until its work is done. Each worker
watches the armanim process (a pidfd where Linux has one, else polling) and, when it
ends, sends itself SIGTERM: the worker's usual quiet exit, which kills its own ffmpeg and
removes its temporary files. Workers ignore Ctrl-C: the terminal sends it to the whole
process group, and the parent decides (it stops them with SIGTERM).

It sits in ``render/``, the lowest room that starts worker processes (the frame
renderers); ``runs/`` starts its batch workers with it too.
"""

from __future__ import annotations

import os
import select
import signal
import threading
import time

POLL_SECONDS = 0.5  # where there is no pidfd


class Stopped(SystemExit):
    """Raised in a worker by SIGTERM: unwinds quietly, running every ``finally`` (no traceback)."""


def _stop(signum, frame):
    signal.signal(signal.SIGTERM, signal.SIG_IGN)  # a second SIGTERM (the pool's own) must not cut the clean-up short
    raise Stopped(128 + signum)


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
    """Set up a worker process: Ctrl-C ignored, SIGTERM a quiet exit, and gone with ``parent``."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, _stop)
    die_with(parent)
