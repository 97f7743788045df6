"""Atomic writes: a temporary file beside the target, then ``os.replace``.

Nothing a user made is ever half-written: a reader sees the old file or the new one.
Only a regular file (or nothing) is ever replaced: a write to a symbolic link goes to
the file it points to, and a folder, device, FIFO or socket at the target is an error.
"""

from __future__ import annotations

import contextlib
import errno
import os
import secrets
import tempfile
from collections.abc import Iterable, Iterator
from pathlib import Path

from armanim.errors import OutputError
from armanim.output.files import special_kind
from armanim.procs.deferred import interrupts_deferred


def current_umask() -> int:
    """The process's umask (read without changing it for long)."""
    mask = os.umask(0)
    os.umask(mask)
    return mask


OUT_ADVICE = "choose another folder with --out"
"""How an output error ends where the output is the command's ``--out`` (:func:`advised` names another flag)."""


def output_error(path: Path, exc: OSError) -> OutputError:
    """A clear OutputError for an OSError met while writing ``path``."""
    if exc.errno == errno.ENOSPC:
        return OutputError(f"{path}: the disk is full (free some space and run again)")
    if exc.errno in (errno.EEXIST, errno.ENOTDIR):
        return OutputError(f"{path}: a file stands where a folder is needed ({OUT_ADVICE})")
    if exc.errno == errno.EROFS:  # campaign 17: it said "permission denied", which chmod cannot mend
        return OutputError(f"{path}: cannot write here: the file system is read-only ({OUT_ADVICE})")
    if exc.errno in (errno.EACCES, errno.EPERM):
        return OutputError(f"{path}: cannot write here: permission denied ({OUT_ADVICE})")
    return OutputError(f"{path}: cannot write: {exc.strerror or exc}")


def advised(exc: OutputError, advice: str) -> OutputError:
    """``exc`` advising ``advice`` where it advises another ``--out``: for a command whose output
    another flag names (campaign 16: ``check --update`` and ``fk --png`` into a read-only folder
    said to choose another folder with --out, a flag neither has).

    >>> str(advised(OutputError(f"g/a.csv: cannot write here: permission denied ({OUT_ADVICE})"), "choose another folder with --golden"))
    'g/a.csv: cannot write here: permission denied (choose another folder with --golden)'
    """
    return type(exc)(str(exc).replace(OUT_ADVICE, advice))


def write_target(path: Path) -> Path:
    """The file a write to ``path`` replaces: ``path``, or the file a link there points to.

    Raises
    ------
    OutputError
        Something other than a regular file stands there (exit 3); it is left as it was.
    """
    path = Path(path)
    target = Path(os.path.realpath(path)) if path.is_symlink() else path
    try:
        mode = os.stat(target).st_mode
    except FileNotFoundError:
        return target
    except OSError as exc:
        raise output_error(path, exc) from None
    kind = special_kind(mode)
    if kind is not None:
        raise OutputError(
            f"{path}: is {kind}, not a regular file; armanim writes only regular files (choose another path)"
        )
    return target


def _fresh_temporary(path: Path, suffix: str = "") -> Path:
    """A new, empty temporary file in ``path``'s folder (the folder is made if needed)."""
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp_name = tempfile.mkstemp(prefix=f".{path.name}.", suffix=suffix + ".tmp", dir=path.parent)
        os.fchmod(fd, 0o666 & ~current_umask())  # mkstemp makes 0600; outputs get the usual mode
        os.close(fd)
    except OSError as exc:
        raise output_error(path, exc) from None
    return Path(tmp_name)


def _write_synced(path: Path, data: bytes | Iterable[bytes]) -> None:
    """Write ``data`` (bytes, or its pieces one after the other) to ``path``, flushed to disk."""
    with open(path, "wb") as handle:
        for piece in (data,) if isinstance(data, bytes) else data:
            handle.write(piece)
        handle.flush()
        os.fsync(handle.fileno())


@contextlib.contextmanager
def temporary_beside(path: Path, suffix: str = "") -> Iterator[Path]:
    """Yield a fresh temporary path in ``path``'s folder; on success rename it onto ``path``.

    On any exception the temporary file is removed and ``path`` is left untouched. A link
    at ``path`` is written through (its target is replaced); see :func:`write_target`.
    """
    path = write_target(path)
    tmp = _fresh_temporary(path, suffix)
    try:
        yield tmp
        os.replace(tmp, path)
    except OSError as exc:
        with interrupts_deferred():
            tmp.unlink(missing_ok=True)
        raise output_error(path, exc) from None
    except BaseException:
        with interrupts_deferred():
            tmp.unlink(missing_ok=True)
        raise


def write_all_or_none(files: dict[Path, bytes]) -> None:
    """Write several files so that a reader finds all of them new or all of them as they were.

    Every file is first written in full to a temporary file beside it; then, with Ctrl-C
    held back, the old ones are kept aside (hard links) and the new ones renamed into place
    one after the other. If any step fails (a full disk, a denied rename), the files
    already replaced get their old contents back (or are removed if they were new).

    Raises
    ------
    OutputError
        A file could not be written (exit 3); every target is as it was.
    """
    targets = {write_target(path): data for path, data in files.items()}
    staged: dict[Path, Path] = {}
    kept: dict[Path, Path] = {}
    try:
        for target, data in targets.items():
            staged[target] = _fresh_temporary(target)
            try:
                _write_synced(staged[target], data)
            except OSError as exc:
                raise output_error(target, exc) from None
        with interrupts_deferred():
            _replace_all(staged, kept)
    finally:
        with interrupts_deferred():
            for leftover in [*staged.values(), *kept.values()]:
                leftover.unlink(missing_ok=True)


def _replace_all(staged: dict[Path, Path], kept: dict[Path, Path]) -> None:
    """Rename each staged file onto its target, the old ones kept aside first (hard links,
    recorded in ``kept``); on a failure, put back what was already replaced."""
    done: list[Path] = []
    current: Path | None = None
    try:
        for current in staged:
            if current.exists():
                kept[current] = current.with_name(f".{current.name}.{os.getpid()}.{secrets.token_hex(4)}.old.tmp")
                os.link(current, kept[current])
        for current, tmp in staged.items():
            os.replace(tmp, current)
            done.append(current)
    except OSError as exc:
        for replaced in reversed(done):
            with contextlib.suppress(OSError):
                if replaced in kept:
                    os.replace(kept.pop(replaced), replaced)
                else:
                    replaced.unlink()
        assert current is not None  # os.link or os.replace failed on a target
        raise output_error(current, exc) from None


def write_bytes_atomic(path: Path, data: bytes) -> None:
    """Write bytes to ``path`` atomically (flushed to disk before the rename)."""
    with temporary_beside(path) as tmp:
        _write_synced(tmp, data)


def write_chunks_atomic(path: Path, chunks: Iterable[bytes]) -> None:
    """Write ``chunks`` one after the other to ``path`` atomically, never holding them all: a
    long file (trajectory.csv) is made a chunk at a time in its temporary file, which is
    renamed onto ``path`` when complete (on an error or Ctrl-C it is removed, ``path`` as it was)."""
    with temporary_beside(path) as tmp:
        _write_synced(tmp, chunks)


def text_bytes(text: str) -> bytes:
    """``text`` as UTF-8, a file name's bytes that are not UTF-8 (Python's surrogate escapes, as in
    ``os.fsdecode``) written back as they were: campaign 17's batch into an outputs folder named in
    latin-1 under LANG=C ended in a UnicodeEncodeError writing index.csv, which names the folder.

    >>> text_bytes("o/" + os.fsdecode(b"\\xe9t\\xe9"))
    b'o/\\xe9t\\xe9'
    """
    return text.encode("utf-8", "surrogateescape")


def write_text_atomic(path: Path, text: str) -> None:
    """Write UTF-8 text to ``path`` atomically (no newline translation; :func:`text_bytes`)."""
    write_bytes_atomic(path, text_bytes(text))
