"""The ``armanim`` command: the console script and ``python -m armanim``.

Its first act, before any other import, makes Ctrl-C and SIGTERM quiet. Until a command
starts nothing has been written, so a signal then ends the process at once with the
contract's line and exit 130 (importing typer, rich and numpy takes most of a second; an
interrupt inside an import would otherwise print a traceback, and SIGTERM would kill
with -15). :mod:`armanim.cli.interrupts` takes over while a command runs.
"""

import errno
import os
import signal
import sys


def _quit_before_the_command(signum, frame):
    os.write(
        2, b"armanim: interrupted; nothing half-written was left behind\n"
    )  # errors.INTERRUPTED (not imported yet)
    os._exit(130)


def _print_version() -> int:
    """``armanim --version``: the line :func:`armanim.cli.app._version` prints, and the exit code. A
    closed reader (``armanim --version | head -0``) or no stdout at all is not an error, as
    :class:`armanim.cli.app.QuietWhenClosed` says; a device that refuses the line (``/dev/full``) is
    exit 3 with the reason, as for every command's output (campaign 17: exit 0, nothing written)."""
    from armanim import __version__

    try:
        os.write(1, f"armanim {__version__}\n".encode())
    except (BrokenPipeError, OSError) as exc:
        if isinstance(exc, BrokenPipeError) or exc.errno == errno.EBADF:
            return 0
        os.write(2, f"armanim: output: {exc.strerror or exc}\n".encode())
        return 3  # errors.EXIT_OUTPUT_FAILED (not imported yet)
    return 0


def _compiled_always() -> None:
    """Drop ``NUMBA_DISABLE_JIT`` when it is on, with a note: numba would run armanim's kernels as
    plain Python, and they are written for numba's numpy error model, where x / 0 is inf or NaN and
    plain Python raises (campaign 15: validate and run of a plain scene ended in a ZeroDivisionError
    traceback). Done before numba is imported, which reads it once; worker processes inherit the
    environment without it."""
    try:
        on = int(os.environ.get("NUMBA_DISABLE_JIT", "")) != 0  # as numba reads it (not an integer: off)
    except ValueError:
        on = False
    if on:
        del os.environ["NUMBA_DISABLE_JIT"]
        os.write(2, b"armanim: NUMBA_DISABLE_JIT ignored: armanim's numerical code runs compiled only\n")


def main() -> None:
    """Entry point of the ``armanim`` console script."""
    signal.signal(signal.SIGINT, _quit_before_the_command)
    signal.signal(signal.SIGTERM, _quit_before_the_command)
    if signal.getsignal(signal.SIGHUP) != signal.SIG_IGN:  # the terminal closing (left ignored under nohup)
        signal.signal(signal.SIGHUP, _quit_before_the_command)
    if sys.argv[1:] == ["--version"]:  # the app's own --version line, without importing typer and rich (0.1 s)
        code = _print_version()
        if code:
            sys.exit(code)
        return
    import warnings

    # numpy's floating-point RuntimeWarnings are not the user's business: a value they would
    # warn about is checked where it matters (and the processes this one starts do the same)
    os.environ.setdefault("PYTHONWARNINGS", "ignore::RuntimeWarning")
    _compiled_always()
    warnings.filterwarnings("ignore", category=RuntimeWarning)
    from armanim.cli import main as run_command

    run_command()


if __name__ == "__main__":
    main()
