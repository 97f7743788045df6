"""How the armanim process answers Ctrl-C and SIGTERM while a command runs, and after.

Three phases, so that an interrupted command always ends with exit 130 and one line, and a
finished one with its own exit code, never a traceback or death by a signal (-2, -15):

1. before the command (imports, parsing the flags): :mod:`armanim.__main__` ends the process
   at once with exit 130; nothing has been written yet;
2. while the command runs (:func:`command_signals`): both signals raise KeyboardInterrupt, so
   every clean-up runs (staging folders, temporary files, workers, ffmpeg), then exit 130.
   The first signal makes later ones ignored: a second Ctrl-C cannot cut a clean-up short;
3. once the command has decided its exit code (or its last output is in place): both
   signals are ignored until the process ends, so interpreter shutdown is never interrupted.

In a test's CliRunner (not the armanim process) only phase 2 applies, and the previous
handlers come back afterwards.
"""

from __future__ import annotations

import contextlib
import signal
import threading
from collections.abc import Iterator

SIGNALS = (signal.SIGINT, signal.SIGTERM)
_process = [False]  # set by main(): this is the armanim process, its signals are ours to the end


def own_the_process() -> None:
    """Called by the console script: phase 3 (ignore until exit) applies."""
    _process[0] = True


def _interrupt(signum, frame):
    if _process[0]:
        ignore_until_exit()
    raise KeyboardInterrupt


def ignore_until_exit() -> None:
    """Phase 3: SIGINT and SIGTERM are ignored from now on (in the armanim process only)."""
    if _process[0] and threading.current_thread() is threading.main_thread():
        for signum in SIGNALS:
            signal.signal(signum, signal.SIG_IGN)


@contextlib.contextmanager
def command_signals() -> Iterator[None]:
    """Phase 2 for the duration, then phase 3 (or, outside the armanim process, the previous handlers)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = {signum: signal.signal(signum, _interrupt) for signum in SIGNALS}
    try:
        yield
    finally:
        if _process[0]:
            ignore_until_exit()
        else:
            for signum, handler in previous.items():
                signal.signal(signum, handler)
