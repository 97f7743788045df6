"""The exception tree of armanim and the exit codes of the contract.

Exceptions are for bad input and failures while producing outputs; a goal that is
not reached is a result, never an exception.
"""

from __future__ import annotations

from dataclasses import dataclass

EXIT_OK = 0
EXIT_CHECK_FAILED = 1
EXIT_BAD_INPUT = 2
EXIT_OUTPUT_FAILED = 3
EXIT_INTERRUPTED = 130

INTERRUPTED = "armanim: interrupted; nothing half-written was left behind"
"""The one line on stderr of an interrupted command (exit 130)."""


SHOWN_CHARACTERS = 80
"""Longest piece of a user's text (a name, a flag value) quoted in a message."""


def shown(text: str, limit: int = SHOWN_CHARACTERS) -> str:
    """``text`` quoted for a message: control and format characters escaped (a newline or a
    right-to-left override from a file cannot forge or reorder output lines), cut after
    ``limit`` characters with the length said.

    >>> print(shown("j1\\nok evil.yaml\\u202e"), shown("x" * 100, 4))
    'j1\\nok evil.yaml\\u202e' 'xxxx...' (100 characters)
    """
    if len(text) <= limit:
        return repr(text)
    return repr(text[:limit])[:-1] + f"...' ({len(text):,} characters)"


def shown_path(text: str, limit: int = SHOWN_CHARACTERS) -> str:
    """A file name quoted for a message as :func:`shown` does, but a long one cut in its middle:
    its start and its end kept (the file's own name is the end, the part a user looks for).

    >>> print(shown_path("/tmp/" + "d" * 100 + "/broken.stl", 30))
    '/tmp/dd...dddddddddddd/broken.stl' (116 characters)
    """
    if len(text) <= limit:
        return repr(text)
    head = max(limit // 4, 1)
    return (
        repr(text[:head])[:-1] + "..." + repr(text[len(text) - (limit - head) :])[1:] + f" ({len(text):,} characters)"
    )


MESSAGE_LINE = 600
"""Longest line of a message armanim prints: a longer one is cut (its length said)."""


def printable(text: str) -> str:
    """``text`` with every character that is not printable (newline, tab, C1 controls, format
    characters such as the right-to-left override) written as its escape, unquoted.

    >>> printable("ok a.yaml"), printable("j1\\nok\\u202e")
    ('ok a.yaml', 'j1\\\\nok\\\\u202e')
    """
    if text.isprintable():
        return text
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in text)


def message_lines(text: str, limit: int = MESSAGE_LINE) -> str:
    """A message as printed: each line :func:`printable`, one longer than ``limit`` characters cut
    in its middle, so that its end, where a message says what went wrong and what to do, is kept
    (campaign 16: a path past PATH_MAX left nothing but the path).

    >>> len(message_lines("x" * 5000)) < 700, message_lines("a" * 5000 + ": the disk is full", 40)
    (True, 'aaaaaaaaaaaaaaaaaaaa ... (4,978 characters cut) ... aa: the disk is full')
    """
    lines = []
    for line in text.split("\n"):
        line = printable(line)
        if len(line) > limit:
            head = limit // 2
            cut = f" ... ({len(line) - limit:,} characters cut) ... "
            line = line[:head] + cut + line[len(line) - (limit - head) :]
        lines.append(line)
    return "\n".join(lines)


def shown_list(names, limit: int = 8) -> str:
    """Names for a message, each :func:`shown`, the first ``limit`` and a count of the rest.

    >>> shown_list([f"c{i}" for i in range(12000)], 3)
    "'c0', 'c1', 'c2' and 11,997 more"
    """
    names = list(names)
    head = ", ".join(shown(n) for n in names[:limit])
    return head if len(names) <= limit else f"{head} and {len(names) - limit:,} more"


class ArmanimError(Exception):
    """Base of every error armanim reports to a user (never shown as a traceback)."""

    exit_code = EXIT_BAD_INPUT

    def report(self) -> str:
        """The message as printed on stderr."""
        return str(self)


@dataclass(frozen=True)
class Diagnostic:
    """One thing wrong with an input: where it is and what was expected.

    Parameters
    ----------
    path : str
        Field path such as ``arm.limits[2]``; empty for the whole file.
    message : str
        What is wrong, with what was expected, e.g. ``must be > 0 (got -2)``.
    line : int or None
        1-based line in the file, where known.
    """

    path: str
    message: str
    line: int | None = None

    def format(self, file: str) -> str:
        """``FILE:LINE: field.path: message`` (parts that are unknown are left out)."""
        where = f"{file}:{self.line}" if self.line is not None else file
        return f"{where}: {self.path}: {self.message}" if self.path else f"{where}: {self.message}"


class SceneError(ArmanimError):
    """A scene (or another input file) that cannot be used; lists every problem found."""

    def __init__(self, file: str, problems: list[Diagnostic], also: tuple | list = ()):
        self.file = file
        self.problems = list(problems)
        self.also = tuple(also)  # the problems of files the scene names (its URDF, its SRDF), found in the same pass
        super().__init__(self.report())

    def report(self) -> str:
        return "\n".join([p.format(self.file) for p in self.problems] + [other.report() for other in self.also])

    def __reduce__(self):
        # pickled to and from worker processes: rebuilt from its parts, not from its message
        return (type(self), (self.file, self.problems, self.also))


class UsageError(ArmanimError):
    """A bad flag or a flag combination that does not fit (exit 2)."""


class OutputError(ArmanimError):
    """Outputs could not be written: folder not writable, disk full (exit 3)."""

    exit_code = EXIT_OUTPUT_FAILED


class RenderError(OutputError):
    """Drawing or encoding failed, e.g. ffmpeg exited with an error (exit 3)."""


class InterruptedAfterCommit(KeyboardInterrupt):
    """Ctrl-C or SIGTERM that came while a folder was being swapped in, after the swap.

    It is a KeyboardInterrupt (a caller asked to stop, and stops), but the new outputs at
    ``folder`` are complete and in place: a command whose last output this was has succeeded.
    """

    def __init__(self, folder):
        super().__init__(str(folder))
        self.folder = folder
