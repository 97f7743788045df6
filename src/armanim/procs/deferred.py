"""Ctrl-C, SIGTERM and SIGHUP held back while a clean-up or a swap runs, then delivered."""

from __future__ import annotations

import contextlib
import signal
import threading
from collections.abc import Iterator

from armanim.procs.interrupted import INTERRUPT_SIGNALS, left_ignored


@contextlib.contextmanager
def interrupts_deferred() -> Iterator[None]:
    """Hold Ctrl-C, SIGTERM and SIGHUP back while a clean-up or a swap runs, then deliver them.

    A second Ctrl-C during the clean-up of the first must not leave a temporary file or
    half a swap behind. Only the main thread can set signal handlers; elsewhere (or if a
    handler was not set from Python) this does nothing.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    received: list[int] = []
    signum: int  # SIGINT, SIGTERM and SIGHUP, then the numbers received
    old = {}
    try:
        for signum in INTERRUPT_SIGNALS:
            handler = signal.getsignal(signum)
            if handler is None or left_ignored(signum):
                continue
            old[signum] = handler
            signal.signal(signum, lambda n, frame: received.append(n))
    except (ValueError, OSError):  # pragma: no cover  (not the main interpreter)
        pass
    try:
        yield
    finally:
        for signum, handler in old.items():
            signal.signal(signum, handler)
        for signum in dict.fromkeys(received):
            signal.raise_signal(signum)  # the usual handler runs now: KeyboardInterrupt, ...
