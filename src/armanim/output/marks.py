"""Marks of the single files armanim writes at a name it does not own (a table at a fixed name,
``schema --out``, ``fk --png``, ``export --out``): ``.NAME.armanim.json`` beside the file records
its size and sha256, so a file there is replaced only while it is still, byte for byte, what
armanim wrote. A file of yours, one you edited since, or one whose mark is missing is never
replaced (exit 3); nor is anything at the mark's own name that is not a mark armanim wrote.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
from collections.abc import Callable, Iterator
from pathlib import Path

from armanim.errors import OutputError, SceneError
from armanim.output.atomic import text_bytes, write_chunks_atomic, write_target
from armanim.output.files import open_regular, protection_kind, stream_sha256, unprotecting, write_protected
from armanim.output.jsontext import parse_json
from armanim.output.rundir import folder_locked

MAX_MARK_BYTES = 1_000
"""A mark is one short JSON line; anything longer at a mark's name is not armanim's."""


def file_mark(path: Path) -> Path:
    """The mark beside ``path``: ``.NAME.armanim.json``.

    >>> file_mark(Path("out/index.csv")).as_posix()
    'out/.index.csv.armanim.json'
    """
    return Path(path).with_name(f".{Path(path).name}.armanim.json")


def mark_line(path: Path, data: bytes, kind: str) -> str:
    """The mark of ``data`` written at ``path``: one JSON line (generator, file, bytes, sha256, and
    ``kind``, what armanim wrote there: :data:`KINDS`).

    >>> mark_line(Path("a.png"), b"x", "fk --png")[:54]
    '{"generator": "armanim", "file": "a.png", "bytes": 1, '
    """
    return (
        json.dumps(
            {
                "generator": "armanim",
                "file": Path(path).name,
                "bytes": len(data),
                "sha256": hashlib.sha256(data).hexdigest(),
                "kind": kind,
            }
        )
        + "\n"
    )


KINDS = ("index.csv", "sweep table", "schema", "fk --png", "export")
"""What a marked file is. A file is replaced only by a file of its own kind (campaign 9: `export
--out OUT/index.csv` replaced a batch's table with a trajectory, and the next batch stopped): a
mark without a kind (armanim before 2026-12-07) is taken as any kind."""


@contextlib.contextmanager
def marks_locked(folder: Path) -> Iterator[None]:
    """Hold an exclusive lock on ``folder`` itself (no lock file left there) while a marked file in
    it and its mark are checked and written, so that two commands writing one marked file at once
    (two batches into one OUT: their ``index.csv``) take turns: neither reads the other's file
    before its mark is written (campaign 18: the second batch ended "index.csv: has changed since
    armanim wrote it", exit 3, though nobody had touched it), and the pair left is one command's.
    A folder that cannot be opened or locked (:func:`~armanim.output.rundir.folder_locked`) is not
    locked: the write that follows says what is wrong."""
    try:
        fd = os.open(folder, os.O_RDONLY | os.O_DIRECTORY | os.O_CLOEXEC)
    except OSError:
        yield
        return
    with folder_locked(fd):
        yield


def write_marked(path: Path, data: bytes | str, kind: str, recheck: Callable[[], object] | None = None) -> None:
    """Write ``data`` at ``path`` (atomically; through a link there, to the file it names) and
    then its mark (:func:`file_mark`), a signal held back between the two (a file without its
    matching mark would be refused next time). Check first with :func:`check_marked_replaceable`;
    ``recheck`` (that check again, raising to refuse) runs just before the writes, under
    :func:`marks_locked` (no other armanim writes the pair meanwhile)."""
    from armanim.procs.deferred import interrupts_deferred

    raw = text_bytes(data) if isinstance(data, str) else data
    target = write_target(path)  # a link is written through: the mark goes beside the file it names
    with marks_locked(target.parent):
        if recheck is not None:
            recheck()
        refuse_write_protected(path)
        with interrupts_deferred():
            write_chunks_atomic(target, [raw])
            write_chunks_atomic(file_mark(target), [mark_line(target, raw, kind).encode()])


def refuse_write_protected(path: Path, option: str = "") -> None:
    """An OutputError (exit 3) if the file ``path`` names (through a link) is write-protected
    (:func:`~armanim.output.files.write_protected`: no write bit left for anyone, which root's writes
    would pass, or not writable by this process). Campaign 19: ``export --out x.json``, ``schema
    --out`` and ``fk --png`` replaced their own earlier file the user had made read-only (``chmod
    444``) as root, exit 0, the new file 0644: the rule run folders and golden files follow
    (campaign 16) now holds for marked files too."""
    target = Path(os.path.realpath(path)) if os.path.islink(path) else Path(path)
    if os.path.isfile(target) and write_protected(target):
        said = f"{path}: {option + ': ' if option else ''}"
        kind = protection_kind(target)
        raise OutputError(
            f"{said}is write-protected ({kind}), so it is not replaced: {unprotecting(kind, target)}, "
            "or choose another path"
        )


def read_mark(mark: Path) -> dict | None:
    """The fields of the mark at ``mark`` (``generator``, ``file``, ``bytes``, ``sha256``), or None
    when what is there is no mark of armanim's: a link, FIFO, device or folder, more than
    :data:`MAX_MARK_BYTES`, not JSON (however deeply nested), or other fields."""
    try:
        if os.path.islink(mark):
            return None
        with open_regular(mark, "an armanim file's mark") as handle:
            recorded = parse_json(handle.read(MAX_MARK_BYTES + 1))
    except (OSError, ValueError, SceneError):
        return None
    if (
        not isinstance(recorded, dict)
        or recorded.get("generator") != "armanim"
        or not isinstance(recorded.get("file"), str)
        or not isinstance(recorded.get("bytes"), int)
        or not isinstance(recorded.get("sha256"), str)
        or recorded.get("kind", KINDS[0]) not in KINDS
    ):
        return None
    return recorded


def foreign_mark(path: Path) -> str | None:
    """Why armanim must not write ``path``'s mark, or None: nothing is at the mark's name, or a
    mark of armanim's is (anything else there, a link included, is someone's and is kept).

    >>> foreign_mark(Path("/nonexistent/a.json")) is None
    True
    """
    mark = file_mark(path)
    if os.path.lexists(mark) and read_mark(mark) is None:
        return f"{mark.name} beside it is not a mark armanim wrote, so armanim does not write there"
    return None


def marked_kind(path: Path) -> str | None:
    """The kind (:data:`KINDS`) its mark gives the file at ``path``, None when it has none (a mark of
    an armanim before kinds were recorded) or there is no mark of armanim's."""
    recorded = read_mark(file_mark(path))
    return None if recorded is None else recorded.get("kind")


def as_marked(path: Path, kind: str) -> bool:
    """Whether the regular file ``path`` is, byte for byte, what its mark records, and of ``kind``
    (:data:`KINDS`; a mark without a kind is of any)."""
    recorded = read_mark(file_mark(path))
    if recorded is None or recorded["file"] != Path(path).name or recorded.get("kind", kind) != kind:
        return False
    try:
        with open_regular(path, "a file armanim wrote") as handle:
            if os.fstat(handle.fileno()).st_size != recorded["bytes"]:
                return False
            return stream_sha256(handle) == recorded["sha256"]
    except (OSError, SceneError):
        return False


def other_kind(path: Path, kind: str) -> str | None:
    """Why a file of ``kind`` must not replace ``path``, when ``path`` is a file armanim marked as of
    another kind (a batch's index.csv, a sweep's table, an export, ...), else None."""
    recorded = marked_kind(path)
    if recorded is None or recorded == kind:
        return None
    return f"is a file armanim wrote as its {recorded}, not as its {kind}, so it is not replaced"


def check_marked_replaceable(path: Path, option: str, kind: str) -> None:
    """An OutputError (exit 3) unless a write to ``path`` (named by ``option``) replaces nothing
    but a file armanim wrote there and nobody changed since: nothing there, or a file that is what
    its mark records. A link is judged by the file it names.

    Raises
    ------
    OutputError
        A file of someone else's, one changed since, or one with no mark (left as it was); a
        folder, device or FIFO there; something not armanim's at the mark's name.
    """
    target = write_target(path)  # a folder, device or FIFO there: exit 3
    foreign = foreign_mark(target)
    if foreign is not None:
        raise OutputError(f"{path}: {option}: {foreign} (move it away, or choose another path)")
    if not os.path.lexists(target):
        return
    other = other_kind(target, kind)
    if other is not None:
        raise OutputError(f"{path}: {option}: {other} (move it away, or choose another path)")
    if not as_marked(target, kind):
        raise OutputError(
            f"{path}: {option}: a file is there that armanim did not write, or that has changed since "
            f"(it is not what {file_mark(target).name} beside it records, or that mark is missing), "
            "so it is not replaced (move it away, or choose another path)"
        )
    refuse_write_protected(path, option)  # armanim's own file, made read-only since
