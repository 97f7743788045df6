"""Whether Ctrl-C or SIGTERM came while the current command ran.

The signal handler (:mod:`armanim.cli.interrupts`) raises KeyboardInterrupt and notes the
signal here. A KeyboardInterrupt raised inside a Python callback of a compiled library can
come out as an error of the library's own: matplotlib's pybind11 layer clears it while it
converts a transform and raises ``ValueError("Invalid affine transformation matrix")``
instead. So an error raised after a signal came is the signal's: the command ends as
interrupted (exit 130), never with a traceback, and a batch never reports it as one failed
scene and goes on with the rest.

>>> forget_signal(); signal_came()
False
>>> note_signal(); signal_came()
True
>>> forget_signal()
"""

from __future__ import annotations

import signal

INTERRUPT_SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)
"""The signals that interrupt a command: Ctrl-C, SIGTERM (``kill``) and SIGHUP (the terminal or the
ssh session closes; campaign 13: it killed armanim outright, exit -1, its staging folder left).
SIGHUP is armanim's only where it was not ignored when armanim started: under ``nohup`` the run
goes on (:func:`left_ignored`)."""

_came = [False]


def note_signal() -> None:
    """Called by the signal handler: a Ctrl-C or SIGTERM came."""
    _came[0] = True


def forget_signal() -> None:
    """Called as a command starts."""
    _came[0] = False


def left_ignored(signum: int) -> bool:
    """Whether ``signum`` is SIGHUP ignored now, as ``nohup`` leaves it: armanim then leaves it
    ignored, so the run goes on when the terminal closes. (Ctrl-C and SIGTERM are armanim's always.)

    >>> left_ignored(signal.SIGTERM)
    False
    """
    return signum == signal.SIGHUP and signal.getsignal(signum) == signal.SIG_IGN


def signal_came() -> bool:
    """Whether an interrupting signal (:data:`INTERRUPT_SIGNALS`) came since the command started."""
    return _came[0]
