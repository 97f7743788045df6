"""Input files read with bounds: regular files only, never more than a limit of bytes.

The size a file reports is not trusted (``/dev/zero`` reports 0 and never ends), and
opening a FIFO must not wait for a writer: a file is opened without blocking, checked
to be a regular file, and then read up to a limit.
"""

from __future__ import annotations

import fcntl
import hashlib
import os
import stat
from pathlib import Path
from typing import BinaryIO

from armanim.errors import Diagnostic, SceneError, message_lines

_KINDS = (
    (stat.S_ISDIR, "a folder"),
    (stat.S_ISCHR, "a character device"),
    (stat.S_ISBLK, "a block device"),
    (stat.S_ISFIFO, "a FIFO (named pipe)"),
    (stat.S_ISSOCK, "a socket"),
)


def special_kind(mode: int) -> str | None:
    """What a file of this ``st_mode`` is, if it is not a regular file (``"a folder"``, ...).

    >>> special_kind(stat.S_IFIFO), special_kind(stat.S_IFREG)
    ('a FIFO (named pipe)', None)
    """
    for is_kind, kind in _KINDS:
        if is_kind(mode):
            return kind
    return None


def resolved(path: str | Path) -> Path:
    """``path`` absolute, its symbolic links followed as far as they go: :meth:`Path.resolve`
    without its RuntimeError (Python 3.11) on a link that loops, which is left as it is, to be
    refused where it is used (campaign 18: ``export --out`` a link to itself, and ``view --out``,
    ended in that traceback).

    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     os.symlink("loop", Path(d) / "loop")
    ...     resolved(Path(d) / "loop") == Path(os.path.realpath(d)) / "loop"
    True
    """
    return Path(os.path.realpath(path))


def is_regular_file(path: str | Path) -> bool:
    """Whether ``path`` is a regular file (or a link to one), for a name from a user's file: any
    name that cannot be looked up (too long, a NUL in it, a loop of links) is none, where
    :meth:`pathlib.Path.is_file` raises (campaign 10: a URDF mesh name of 5,000 characters ended
    ``robots --fit``, ``fk --png`` and ``run`` with ``File name too long``, exit 3).

    >>> is_regular_file("x" * 5000), is_regular_file("a\\0b"), is_regular_file(__file__)
    (False, False, True)
    """
    try:
        return stat.S_ISREG(os.stat(path).st_mode)
    except (OSError, ValueError):
        return False


def write_protected(path: str | Path) -> bool:
    """Whether the file or folder at ``path`` is write-protected: no write bit left for anyone (a
    user's ``chmod a-w``, which root's writes would pass), or this process may not write it (a folder:
    nor enter it). armanim replaces neither such a file nor a folder holding one; a path that cannot be
    looked up is not protected (it is absent, or another check names it).

    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     before = write_protected(folder)
    ...     os.chmod(folder, 0o555)
    ...     after = write_protected(folder)
    ...     os.chmod(folder, 0o755)
    >>> before, after
    (False, True)
    """
    try:
        mode = os.stat(path).st_mode
    except (OSError, ValueError):
        return False
    needed = os.W_OK | os.X_OK if stat.S_ISDIR(mode) else os.W_OK
    return not mode & 0o222 or not os.access(path, needed)


def protection_kind(path: str | Path) -> str:
    """How the write-protected file or folder at ``path`` (:func:`write_protected`) is protected:
    ``"read-only"`` (no write bit for its owner), ``"immutable or append-only"`` (its modes allow
    writing, root is refused all the same: ``chattr +i`` or ``+a``; campaign 19's message advised
    ``chmod u+w``, which does not lift it), ``"on a read-only file system"`` (a read-only mount:
    root meets it too; said before the modes, which no chmod there can change), or ``"another
    user's"`` (its modes allow its owner, not us).

    >>> import tempfile
    >>> with tempfile.NamedTemporaryFile() as f:
    ...     os.chmod(f.name, 0o444)
    ...     protection_kind(f.name)
    'read-only'
    """
    try:
        mode = os.stat(path).st_mode
        read_only_mount = bool(os.statvfs(path).f_flag & os.ST_RDONLY)
    except (OSError, ValueError):
        return "read-only"
    if read_only_mount:
        return "on a read-only file system"
    if not mode & 0o200:
        return "read-only"
    return "immutable or append-only" if os.geteuid() == 0 else "another user's"


def unprotecting(kind: str, path: str | Path, *, recursive: bool = False) -> str:
    """What lifts a write protection of ``kind`` (:func:`protection_kind`) from ``path``, as advice.

    >>> unprotecting("read-only", "g/a.csv"), unprotecting("immutable or append-only", "o/run", recursive=True)
    ('make it writable (chmod u+w g/a.csv)', 'lift it (chattr -R -i -a o/run)')
    """
    flag = "-R " if recursive else ""
    if kind == "read-only":
        return f"make it writable (chmod {flag}u+w {path})"
    if kind == "immutable or append-only":
        return f"lift it (chattr {flag}-i -a {path})"
    if kind == "on a read-only file system":
        return "choose a folder on a writable disk, or mount this one read-write"
    return "ask its owner to make it writable"


def _error(path: Path, message: str) -> SceneError:
    return SceneError(str(path), [Diagnostic("", message)])


def open_regular(path: str | Path, what: str) -> BinaryIO:
    """Open a regular file for reading in binary mode, never blocking on a FIFO.

    Parameters
    ----------
    path : str or Path
    what : str
        What the file should be, for messages (e.g. ``"a scene .yaml file"``).

    Raises
    ------
    SceneError
        Missing, unreadable, or not a regular file (exit 2).
    """
    path = Path(path)
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | os.O_CLOEXEC)
    except FileNotFoundError:
        raise _error(path, f"no such file (expected {what})") from None
    except PermissionError:
        raise _error(path, "cannot be read: permission denied") from None
    except OSError as exc:
        raise _error(path, f"cannot be read: {exc.strerror or exc}") from None
    kind = special_kind(os.fstat(fd).st_mode)
    if kind is not None:
        os.close(fd)
        raise _error(path, f"is {kind}, not a regular file (expected {what})")
    fcntl.fcntl(fd, fcntl.F_SETFL, fcntl.fcntl(fd, fcntl.F_GETFL) & ~os.O_NONBLOCK)
    return os.fdopen(fd, "rb")


def stream_sha256(handle: BinaryIO) -> str:
    """The sha256 (hex) of what is left to read of ``handle``, read a megabyte at a time (a file of
    any size in bounded memory).

    >>> import io
    >>> stream_sha256(io.BytesIO(b"abc"))[:16]
    'ba7816bf8f01cfea'
    """
    digest = hashlib.sha256()
    while block := handle.read(1 << 20):
        digest.update(block)
    return digest.hexdigest()


def read_bounded(path: str | Path, limit: int, what: str) -> bytes:
    """The bytes of a regular file of at most ``limit`` bytes (never reads more than that plus one).

    Raises
    ------
    SceneError
        As :func:`open_regular`, or the file is larger than ``limit`` (exit 2).
    """
    with open_regular(path, what) as handle:
        size = os.fstat(handle.fileno()).st_size
        if size > limit:
            raise _error(Path(path), f"is {size:,} bytes ({what} may be at most {limit:,} bytes)")
        try:
            data = handle.read(limit + 1)
        except OSError as exc:
            raise _error(Path(path), f"cannot be read: {exc.strerror or exc}") from None
    if len(data) > limit:
        raise _error(Path(path), f"is more than {limit:,} bytes ({what} may be at most {limit:,} bytes)")
    return data


def read_named_file(field: str, path: str | Path, limit: int, what: str) -> bytes:
    """:func:`read_bounded` of a file a scene's ``field`` names: a file that cannot be read (missing,
    a folder, a FIFO, too large) is the scene's problem, reported at that field and its line.

    Raises
    ------
    ValueError
        ``FIELD: FILE: what is wrong``, for the scene's loader to place at the field's line.
    """
    try:
        return read_bounded(path, limit, what)
    except SceneError as exc:
        raise ValueError(f"{field}: {message_lines(exc.report())}") from None
