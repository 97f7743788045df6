"""Ctrl-C where Python hides it (issue 19): swallowed in a weakref callback, raised in code run
from text, turned into an error by matplotlib: the command still ends with 130 at once.

Each test is named in docs/reliability.md, which it keeps true.
"""

from __future__ import annotations

import pytest

from armanim.errors import INTERRUPTED

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


_TWO_SIGNALS_AT_ONCE = """
import os, signal, sys
from armanim.cli.interrupts import command_signals, own_the_process
own_the_process()
try:
    with command_signals():
        both = {signal.SIGINT, signal.SIGTERM}
        signal.pthread_sigmask(signal.SIG_BLOCK, both)  # both come before Python runs either handler
        os.kill(os.getpid(), signal.SIGTERM)
        os.kill(os.getpid(), signal.SIGINT)
        signal.pthread_sigmask(signal.SIG_UNBLOCK, both)
        for _ in range(1000):
            pass
except KeyboardInterrupt:
    for _ in range(1000):  # Python looks at the second signal's flag again here
        pass
    print("interrupted")
    sys.exit(130)
print("finished")
"""


def test_a_second_signal_that_comes_with_the_first_is_ignored_silently(tmp_path):
    """Campaign 18: Ctrl-C, then SIGTERM 1 ms later, during a run's video: both came before Python ran
    a handler; the first made the signals ignored (phase 3), and CPython, finding the second's
    handler now SIG_IGN, printed ``Traceback ... OSError: Signal 15 ignored due to race condition``
    before the interrupted line. The second signal is ignored, as promised, without a word."""
    import subprocess
    import sys

    script = tmp_path / "two_signals.py"
    script.write_text(_TWO_SIGNALS_AT_ONCE)
    done = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=60)
    assert (done.returncode, done.stdout.strip(), done.stderr) == (130, "interrupted", "")


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
    done = subprocess.run(
        [sys.executable, "-m", "ctrl_c_in_text"], cwd=tmp_path, capture_output=True, text=True, timeout=60
    )
    assert (done.returncode, done.stderr.strip()) == (130, INTERRUPTED)


class _TransformThatMeetsACtrlC:
    """A matplotlib transform's matrix, asked for while a Ctrl-C comes."""

    def __array__(self, dtype=None, copy=None):
        import signal

        import numpy as np

        signal.raise_signal(signal.SIGINT)
        return np.eye(3)


def test_a_ctrl_c_that_matplotlib_turns_into_an_error_still_ends_with_130(capsys, ctrl_c_raises):
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


_SIGNAL_AT_EXIT = """
import atexit, os, signal, sys, time

def late_signal():  # a SIGTERM as the process ends: CPython then puts SIG_DFL back for a Python handler
    os.kill(os.getpid(), signal.SIGTERM)
    time.sleep(0.2)

atexit.register(late_signal)
sys.argv = ["armanim", "fk", "no-such-argument.yaml", "--angles", "0,0"]
from armanim.__main__ import main
main()
"""


def test_a_signal_as_a_usage_error_ends_keeps_its_exit_code():
    """Campaign 5: ``armanim fk s.yaml ...`` (a usage error) killed by SIGTERM 1.3 s in died by the
    signal (-15, 143 in a shell) after printing the usage error: the error path ran no command,
    so nothing made the signals ignored before Python restored their default handlers at shutdown.
    Every way out of the command line now ignores them, so the exit code stays the command's own."""
    import subprocess
    import sys

    done = subprocess.run([sys.executable, "-c", _SIGNAL_AT_EXIT], capture_output=True, text=True, timeout=60)
    assert done.returncode == 2 and "Usage" in done.stderr, (done.returncode, done.stderr)
    assert "interrupted" not in done.stderr and "Exception ignored" not in done.stderr
