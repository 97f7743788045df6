"""The Typer application every command registers on, its consoles and its error handling.

Every ArmanimError becomes its message on stderr and the contract's exit code; rich
lives only in this package.
"""

from __future__ import annotations

import contextlib
import functools
import os
import sys
from typing import Annotated, Literal

import typer
from rich.console import Console

from armanim import __version__
from armanim.cli.interrupts import command_signals, ignore_until_exit
from armanim.errors import EXIT_INTERRUPTED, EXIT_OUTPUT_FAILED, INTERRUPTED, ArmanimError, message_lines
from armanim.procs.interrupted import signal_came

app = typer.Typer(
    name="armanim",
    help="Batch animator for articulated arms: inverse kinematics with cost minimisation, "
    "trajectories, videos.\n\nExample: [bold]armanim run scenes/notes-arm.yaml[/bold]",
    rich_markup_mode="rich",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_show_locals=False,
    context_settings={"help_option_names": ["-h", "--help"]},
)


def _forget_a_width_of_zero() -> None:
    """Drop ``COLUMNS`` when it says 0 (``0``, ``00``): rich and typer take it for a width of 0 and
    then print nothing at all, every error message and ``--help`` included, the exit code alone left
    (campaign 13). Without it they measure the terminal, 80 columns where there is none."""
    columns = os.environ.get("COLUMNS", "")
    if columns.isdigit() and int(columns) == 0:
        del os.environ["COLUMNS"]


NARROWEST_COLUMNS = 80
"""The narrowest armanim draws its help and tables: on a narrower terminal (``COLUMNS=20``) they are
drawn 80 wide and the terminal wraps their lines, every word and number kept. Drawn 20 wide, the
goal table showed only ellipses and the help only option names, the help text dropped, and at 80
``ik --help`` lost the last letters of its help's lines (campaign 17)."""


def _console_width() -> int | None:
    """The width to draw at: None (rich measures COLUMNS or the terminal each time) unless that is
    under :data:`NARROWEST_COLUMNS`."""
    return NARROWEST_COLUMNS if Console().width < NARROWEST_COLUMNS else None


_forget_a_width_of_zero()
out = Console(width=_console_width())
err = Console(stderr=True, width=_console_width())


def _plain_help() -> None:
    """Typer 0.29's help as click's was: a flag shows no ``<bool>`` type (it takes no value), and
    the usage line names an argument in capitals, ``FOLDER`` (``[FOLDER]`` when optional), not
    ``{folder}`` (issue 50's papercuts). Typer builds its parameters itself, so its two methods
    are replaced here, once, for every command."""
    from typer import core

    shown = core.TyperOption.display_type_rich

    def option_type(self, ctx):  # a flag takes no value: no type to show
        return None if self.is_flag and self.metavar is None else shown(self, ctx)

    def usage_name(self) -> str:
        name = self.metavar or (self.name or "").upper()
        name = name if self.required else f"[{name}]"
        return name + ("..." if self.nargs != 1 else "")

    patches = [
        (core.TyperOption, "display_type_rich", option_type),
        (core.TyperArgument, "_usage_display_name", usage_name),
    ]
    patches += [
        (kind, "format_help", _with_help_table(kind.format_help)) for kind in (core.TyperCommand, core.TyperGroup)
    ]
    for owner, name, method in patches:  # typer's help, patched once at import (a method replaced: setattr)
        setattr(owner, name, method)


def _with_help_table(format_help):
    """``format_help`` with typer's help tables made by :func:`_help_table` (rich is imported
    only when help is shown, so ``--version`` stays fast)."""

    def formatted(self, ctx, formatter):
        from typer import rich_utils

        if not getattr(rich_utils.Table, "keeps_names_whole", False):
            rich_utils.Table = _help_table()  # typer's option and command panels are its only tables
        rich_utils.MAX_WIDTH = max(rich_utils.MAX_WIDTH or Console().width, NARROWEST_COLUMNS)
        return format_help(self, ctx, formatter)

    return formatted


def _help_table():
    """A rich Table whose columns before the last (option names, short flags, types) are never
    narrower than their widest cell: at 80 columns typer's table cut ``--orientation-tolerance``
    to ``--orientation-tolera…`` (issue 50); the help text, the last column, wraps instead."""
    from rich.table import Table
    from rich.text import Text

    class HelpTable(Table):
        keeps_names_whole = True

        def add_row(self, *renderables, **options):
            super().add_row(*renderables, **options)
            for column, cell in list(zip(self.columns, renderables))[:-1]:
                if isinstance(cell, Text):
                    column.min_width = max(column.min_width or 0, cell.cell_len)

        def _calculate_column_widths(self, console, options):
            # rich measures the columns again after narrowing them, and a name column comes back
            # to its min_width: the table was then wider than the panel and the help text, wrapped
            # for the wider column, lost its last letters at the edge (campaign 17: `ik --help` at
            # 80 columns said "(default: fo" for "four"). The help column gives up the excess.
            widths = super()._calculate_column_widths(console, options)
            excess = sum(widths) + self._extra_width - options.max_width
            if excess > 0 and widths:
                widths[-1] = max(widths[-1] - excess, 1)
            return widths

    return HelpTable


_plain_help()


def dropped(fd: int) -> None:
    """Point file descriptor ``fd`` at /dev/null: what is still written to it is dropped."""
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, fd)
    os.close(devnull)


class QuietWhenClosed:
    """A text stream that a closed reader (``armanim validate s.yaml | head -0``) cannot break.

    The first BrokenPipeError points the stream's file descriptor at /dev/null: the rest of
    the output is dropped, and the command ends with its own exit code (a failed check
    stays exit 1, a pass exit 0), never click's exit 1 for a broken pipe.
    """

    def __init__(self, stream):
        self._stream = stream

    def write(self, text: str) -> int:
        try:
            return self._stream.write(text)
        except BrokenPipeError:
            self._drop_the_rest()
            return len(text)

    def flush(self) -> None:
        try:
            self._stream.flush()
        except BrokenPipeError:
            self._drop_the_rest()

    def _drop_the_rest(self) -> None:
        dropped(self._stream.fileno())

    def __getattr__(self, name):
        return getattr(self._stream, name)


def quiet_when_closed() -> None:
    """Wrap this process's stdout and stderr in :class:`QuietWhenClosed` (the armanim process only).
    A stream the process was started without (``armanim schema >&-``: Python's is None) writes to
    /dev/null, as a closed reader's does (campaign 17: ``schema`` ended in an AttributeError)."""
    for name in ("stdout", "stderr"):
        if getattr(sys, name) is None:
            setattr(sys, name, open(os.devnull, "w"))  # noqa: SIM115 (the process's own, for its life)
        stream = getattr(sys, name)
        if stream is not None and not isinstance(stream, QuietWhenClosed):
            with contextlib.suppress(OSError, ValueError, AttributeError):
                stream.fileno()  # a real file descriptor (not a test's capture)
                setattr(sys, name, QuietWhenClosed(stream))


def flushed_or_failed(failed: OSError | None = None) -> None:
    """Flush stdout at the end of the command; where that fails (a full device: ``armanim --help >
    /dev/full``), say so on stderr and end with exit 3, as a command's own output error does. Output
    written outside any command (``--help``, ``--version``, a usage error) reaches the device only
    here, or in Python's final flush: campaign 17 found a traceback there, and ``--version`` exit 0
    having written nothing. ``failed``: the error a write outside any command raised. The rest is
    dropped, so that Python's final flush has nothing to fail on."""
    try:
        if failed is not None:
            raise failed
        sys.stdout.flush()
    except OSError as exc:
        with contextlib.suppress(OSError, ValueError, AttributeError):
            dropped(sys.stdout.fileno())
        say(f"armanim: output: {exc.strerror or exc}", err)
        raise SystemExit(EXIT_OUTPUT_FAILED) from None


def say(text: str, console: Console = out) -> None:
    """Print a plain line (no rich markup or highlighting, never wrapped) to ``console``."""
    console.print(text, markup=False, highlight=False, soft_wrap=True)


def tell_first_compile(command: Literal["run", "ik"], problem: object = None) -> None:
    """At a terminal, say so before a solve whose kernels numba compiles first (:mod:`armanim.runs.warmth`;
    ``problem``: ik's, which says whether its compiled attempt runs)."""
    from armanim.runs.warmth import compiles_first, first_compile_notice, tell_lock_waits

    tell_lock_waits(lambda line: say(line, err))
    if not err.is_terminal:
        return

    if compiles_first(command, problem):
        say(first_compile_notice(), err)
        count_compiles(err)


def count_compiles(console: Console = err) -> object:
    """From now on in this process, a line on ``console`` as numba starts to compile each kernel
    called from Python (the kernels it calls are compiled inside it): its count, its name and the
    seconds of compiling so far, so that a first run shows its progress, not one still line.
    Returns the listener (``numba.core.event.unregister("numba:compile", it)`` stops it)."""
    import time

    from numba.core import event  # numba's event API (public since 0.53)

    class Counter(event.Listener):
        def __init__(self) -> None:
            self.depth = 0
            self.count = 0
            self.spent = 0.0
            self.started = 0.0

        def on_start(self, ev: event.Event) -> None:
            self.depth += 1
            if self.depth == 1:
                self.count += 1
                self.started = time.perf_counter()
                name = getattr(getattr(ev.data.get("dispatcher"), "py_func", None), "__qualname__", "a kernel")
                say(f"armanim: compiling {self.count}: {name} ({self.spent:.0f} s so far)", console)

        def on_end(self, ev: event.Event) -> None:
            self.depth -= 1
            if self.depth == 0:
                self.spent += time.perf_counter() - self.started

    counter = Counter()
    event.register("numba:compile", counter)
    return counter


def report(exc: ArmanimError) -> None:
    """An error's report on stderr, as the contract writes it (``FILE:LINE: field: message``)."""
    say(message_lines(exc.report()), err)


def handle_errors(command):
    """Turn ArmanimError into its message and exit code; Ctrl-C and SIGTERM into exit 130
    (see :mod:`armanim.cli.interrupts`)."""

    @functools.wraps(command)
    def wrapper(*args, **kwargs):
        with command_signals():
            return _reported(command, *args, **kwargs)

    return wrapper


def _reported(command, *args, **kwargs):
    """``command(...)``, its errors as their messages and exit codes; after a Ctrl-C or
    SIGTERM, any error is the signal's (:mod:`armanim.procs.interrupted`)."""
    try:
        return command(*args, **kwargs)
    except typer.Exit:  # the command's own exit code (a click Exit is a RuntimeError)
        raise
    except KeyboardInterrupt:
        _interrupted()
    except Exception as exc:
        if signal_came():
            _interrupted()
        if isinstance(exc, ArmanimError):
            report(exc)
            raise typer.Exit(exc.exit_code) from None
        if isinstance(exc, OSError):  # a safety net: writers raise OutputError, but the system may fail elsewhere
            say(f"armanim: {exc.filename or 'output'}: {exc.strerror or exc}", err)
            raise typer.Exit(EXIT_OUTPUT_FAILED) from None
        raise


def _interrupted() -> None:
    """End the command as interrupted: the contract's line and exit 130."""
    ignore_until_exit()
    say(INTERRUPTED, err)
    raise typer.Exit(EXIT_INTERRUPTED) from None


def _version(value: bool) -> None:
    if value:
        out.print(f"armanim {__version__}", highlight=False)
        raise typer.Exit()


@app.callback()
def _main(
    version: Annotated[
        bool, typer.Option("--version", callback=_version, is_eager=True, help="Show the version and exit.")
    ] = False,
) -> None:
    """Batch animator for articulated arms."""


def print_notes(scene) -> None:
    """A scene's notes (not errors) on stderr, as ``note: FILE:LINE: field: message``."""
    for note in scene.notes:
        say(message_lines("note: " + note.format(str(scene.path))), err)


def plural(count: int, word: str) -> str:
    """``1 obstacle``, ``3 obstacles``.

    >>> plural(1, "goal"), plural(0, "obstacle")
    ('1 goal', '0 obstacles')
    """
    return f"{count} {word}" + ("" if count == 1 else "s")


def fmt(value: float, scale: float = 1.0) -> str:
    """A number for a table: :func:`armanim.output.numbers.number` (six significant digits, 0 below
    1e-9 of ``scale``)."""
    from armanim.output.numbers import number

    return number(value, scale)
