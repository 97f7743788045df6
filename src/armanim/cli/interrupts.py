"""How the armanim process answers Ctrl-C, SIGTERM and SIGHUP while a command runs, and after.

SIGHUP (the terminal or the ssh session closes) is an interruption as the other two are
(:data:`armanim.procs.interrupted.INTERRUPT_SIGNALS`), unless armanim was started with it ignored
(``nohup``): then it stays ignored and the command goes on.

Three phases, so that an interrupted command always ends with exit 130 and one line, and a
finished one with its own exit code, never a traceback or death by a signal (-2, -15):

1. before the command (imports, parsing the flags): :mod:`armanim.__main__` ends the process
   at once with exit 130; nothing has been written yet;
2. while the command runs (:func:`command_signals`): both signals raise KeyboardInterrupt, so
   every clean-up runs (staging folders, temporary files, workers, ffmpeg), then exit 130.
   The first signal makes later ones ignored: a second Ctrl-C cannot cut a clean-up short.
   Python swallows an exception raised where nothing can catch it (a ``__del__``, a weakref
   callback run by the garbage collector) and prints "Exception ignored"; a KeyboardInterrupt
   swallowed so is raised again, silently, at the next Python call or return
   (:func:`_redeliver_swallowed`), so the command never goes on with the first signal spent
   and half-updated state behind it (matplotlib's transform tree, say). A library may also
   turn the KeyboardInterrupt into an error of its own (:mod:`armanim.procs.interrupted`):
   any error after a signal ends the command as interrupted;
3. once the command has decided its exit code (or its last output is in place): both
   signals are ignored until the process ends, so interpreter shutdown is never interrupted;
   a signal that came before that, with the first, is ignored too, without CPython's
   "Signal N ignored due to race condition" traceback (:func:`_a_signal_already_ignored`).

In a test's CliRunner (not the armanim process) only phase 2 applies, and the previous
handlers come back afterwards.
"""

from __future__ import annotations

import contextlib
import functools
import signal
import sys
import threading
from collections.abc import Iterator

from armanim.procs.interrupted import INTERRUPT_SIGNALS, forget_signal, left_ignored, note_signal

SIGNALS = INTERRUPT_SIGNALS
_process = [False]  # set by main(): this is the armanim process, its signals are ours to the end


def own_the_process() -> None:
    """Called by the console script: phase 3 (ignore until exit) applies."""
    _process[0] = True


def _interrupt(signum, frame):
    note_signal()
    if _process[0]:
        ignore_until_exit()
    raise KeyboardInterrupt


def _redeliver_swallowed(unraisable, *, previous) -> None:
    """``sys.unraisablehook`` while a command runs: a KeyboardInterrupt that Python could not
    raise (it came in a ``__del__`` or a weakref callback) is raised again, silently, in the
    main thread's next Python call or return after this hook; a signal already ignored is
    dropped (:func:`_a_signal_already_ignored`); anything else goes to ``previous``."""
    if isinstance(unraisable.exc_value, KeyboardInterrupt) and threading.current_thread() is threading.main_thread():
        sys.setprofile(_raise_the_swallowed_interrupt)
    elif not _a_signal_already_ignored(unraisable):
        previous(unraisable)


def _a_signal_already_ignored(unraisable) -> bool:
    """Whether ``unraisable`` is CPython's note of a signal that came before Python ran the first
    one's handler, which then made it ignored (phase 3): ``OSError: Signal 15 ignored due to race
    condition``, written with a traceback (campaign 18: Ctrl-C, then SIGTERM 1 ms later, during a
    run's video). That signal is ignored, as phase 3 promises: nothing to say."""
    error = unraisable.exc_value
    return isinstance(error, OSError) and str(error).endswith("ignored due to race condition")


def _quiet_about_ignored_signals(unraisable, *, previous) -> None:
    """``sys.unraisablehook`` in phase 3: a signal already ignored is dropped, anything else goes to ``previous``."""
    if not _a_signal_already_ignored(unraisable):
        previous(unraisable)


def _raise_the_swallowed_interrupt(frame, event, arg) -> None:
    """A profile function that raises KeyboardInterrupt at its first event outside the hook (an
    exception raised in the hook would be swallowed again), then removes itself."""
    if frame.f_code is _redeliver_swallowed.__code__:
        return
    sys.setprofile(None)
    raise KeyboardInterrupt


def ignore_until_exit() -> None:
    """Phase 3: SIGINT, SIGTERM and SIGHUP are ignored from now on, and the exit code is the command's
    own (in the armanim process only)."""
    if _process[0] and threading.current_thread() is threading.main_thread():
        hook = sys.unraisablehook  # first: setting a handler runs the signals that came meanwhile
        if getattr(hook, "func", None) not in (_quiet_about_ignored_signals, _redeliver_swallowed):
            sys.unraisablehook = functools.partial(_quiet_about_ignored_signals, previous=hook)
        for signum in SIGNALS:
            signal.signal(signum, signal.SIG_IGN)
        _forget_pythons_unhandled_interrupt()


def _forget_pythons_unhandled_interrupt() -> None:
    """CPython notes a KeyboardInterrupt that leaves code it runs from text (``exec`` or
    ``eval`` of a string: dataclasses, namedtuple and pydantic make their methods so, as a
    command imports them) in a process-wide flag that catching it does not clear; at exit,
    ``python -m armanim`` then killed itself with SIGINT (-2) whatever exit code the command
    had chosen. Each run of text starts by clearing that flag: this one runs nothing else."""
    exec("pass")  # a constant: nothing from outside is run


@contextlib.contextmanager
def command_signals() -> Iterator[None]:
    """Phase 2 for the duration, then phase 3 (or, outside the armanim process, the previous handlers)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    forget_signal()
    previous = {signum: signal.signal(signum, _interrupt) for signum in SIGNALS if not left_ignored(signum)}
    previous_hook = sys.unraisablehook
    sys.unraisablehook = functools.partial(_redeliver_swallowed, previous=previous_hook)
    try:
        yield
    finally:
        forget_signal()  # the command has answered it; an API call made later is not interrupted
        sys.unraisablehook = previous_hook
        if sys.getprofile() is _raise_the_swallowed_interrupt:
            sys.setprofile(None)
        if _process[0]:
            ignore_until_exit()
        else:
            for signum, handler in previous.items():
                signal.signal(signum, handler)
