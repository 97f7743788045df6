"""A run's output folder, replaced whole or not at all.

A run writes into a hidden temporary folder beside ``ROOT/<name>`` and swaps it in
only when every file is complete, so a failed or interrupted run leaves the previous
outputs untouched. A lock file beside the folder keeps two runs of the same scene
from interleaving: the second waits for the first. The swap and the clean-up hold
Ctrl-C back until they are done, and a run killed outright (``kill -9``, a power
cut) is tidied up by the next run of the same folder: its staging folder is
removed, and an old folder it had moved aside is put back.

armanim replaces only what it made: every run folder holds a marker file
(:data:`MARKER`) listing the files armanim wrote into it, and an existing folder is
replaced only if it is empty or holds nothing but the marker and the files it lists.
Anything else at ``ROOT/<name>`` (a user's folder, a user's file added to a run, a
link, a file) is an error that names what is there, and it is left as it was.
"""

from __future__ import annotations

import contextlib
import errno
import fcntl
import os
import re
import shutil
import stat
import tempfile
from collections.abc import Iterator
from pathlib import Path

from armanim import __version__
from armanim.errors import InterruptedAfterCommit, OutputError, shown_path
from armanim.output.atomic import current_umask, output_error, write_text_atomic
from armanim.output.cachedir import CACHE_ENV, cache_inside
from armanim.output.files import protection_kind, special_kind, stream_sha256, unprotecting, write_protected
from armanim.output.jsontext import json_text, parse_json
from armanim.procs.deferred import interrupts_deferred

MARKER = ".armanim-run.json"
"""In every run folder: says armanim made it and lists the files it wrote there."""


@contextlib.contextmanager
def folder_lock(folder: Path) -> Iterator[None]:
    """Hold an exclusive lock on ``folder`` (a hidden ``.<name>.lock`` file beside it)."""
    lock = folder.parent / f".{folder.name}.lock"
    try:
        folder.parent.mkdir(parents=True, exist_ok=True)
        fd = _open_lock(lock)
    except OSError as exc:
        if exc.errno == errno.EACCES and os.path.lexists(lock):
            raise OutputError(
                f"{lock}: the lock of {folder} cannot be opened: permission denied (another user's, or made "
                f"unreadable; remove it if no armanim is writing {folder})"
            ) from None
        if exc.errno == errno.ELOOP:
            raise OutputError(
                f"{lock}: is a link, which armanim did not make and does not follow (remove it)"
            ) from None
        if exc.errno in (errno.ENXIO, errno.EISDIR):  # a FIFO with no reader; a folder
            raise _not_a_lock(lock, "a FIFO (named pipe)" if exc.errno == errno.ENXIO else "a folder") from None
        raise output_error(folder, exc) from None
    kind = special_kind(os.fstat(fd).st_mode)
    if kind is not None:  # a FIFO someone reads, a device
        os.close(fd)
        raise _not_a_lock(lock, kind)
    try:
        with _exclusively(fd):
            yield
    finally:
        os.close(fd)


def _open_lock(lock: Path) -> int:
    """The lock file ``lock`` opened (made if missing), for writing, or for reading where another
    user's lock may not be written (a shared folder: campaign 16's run stopped with "cannot write
    here" naming the run folder); ``flock`` locks either way."""
    # never through a link: a dangling one would make armanim create a file where it points;
    # never waiting: a FIFO there would block the open until a reader came (campaign 9)
    flags = os.O_NOFOLLOW | os.O_NONBLOCK | os.O_CLOEXEC
    try:
        return os.open(lock, os.O_WRONLY | os.O_CREAT | os.O_APPEND | flags, 0o666)
    except PermissionError:
        if not os.path.lexists(lock):
            raise
        return os.open(lock, os.O_RDONLY | flags)


def _not_a_lock(lock: Path, kind: str) -> OutputError:
    return OutputError(f"{lock}: is {kind}, which armanim did not make and does not use (remove it)")


@contextlib.contextmanager
def directory_lock(folder: Path) -> Iterator[None]:
    """Hold an exclusive lock on ``folder`` itself, made if missing (no lock file is left in it
    or beside it: for folders the user keeps, such as golden files under version control).

    A folder that cannot be flocked is used unlocked (:func:`folder_locked`; campaign 19: ``check
    --update`` on NFS ended ``armanim: output: Bad file descriptor``, exit 3, and no golden could
    ever be written)."""
    try:
        folder.mkdir(parents=True, exist_ok=True)
        fd = os.open(folder, os.O_RDONLY | os.O_DIRECTORY | os.O_CLOEXEC)
    except OSError as exc:
        raise output_error(folder, exc) from None
    with folder_locked(fd):
        yield


@contextlib.contextmanager
def folder_locked(fd: int) -> Iterator[None]:
    """Hold an exclusive ``flock`` on the open folder ``fd`` while the body runs, then close it
    (which releases the lock). A file system that cannot flock a folder leaves it unlocked: NFS
    emulates ``flock`` by a byte-range lock, which needs a file open for writing, and a folder opens
    only for reading (EBADF; also ENOLCK, EOPNOTSUPP)."""
    try:
        with contextlib.suppress(OSError):
            fcntl.flock(fd, fcntl.LOCK_EX)
        yield
    finally:
        os.close(fd)


@contextlib.contextmanager
def _exclusively(fd: int) -> Iterator[None]:
    """Hold an exclusive ``flock`` on the open file ``fd`` meanwhile (waiting for it first)."""
    fcntl.flock(fd, fcntl.LOCK_EX)
    try:
        yield
    finally:
        fcntl.flock(fd, fcntl.LOCK_UN)


RUN_FILE = "trajectory.csv"
"""What tells a run folder (which holds only what its marker lists) from a ``render --out`` folder (which keeps other files)."""


def run_folder_holding(target: Path, *, itself: bool = False) -> Path | None:
    """The run folder ``target`` would be written into, if any: a folder above it (or, with
    ``itself``, ``target`` itself) that holds armanim's marker and a run's ``trajectory.csv``, by
    the path as given and as resolved (a link into a run folder counts).

    A run folder holds only the files armanim lists in it: a file added there stops its next run.
    """
    given = Path(os.path.abspath(target))
    paths = [given]
    with contextlib.suppress(OSError, RuntimeError):
        paths.append(given.resolve())
    for path in paths:
        for folder in ([path] if itself else []) + list(path.parents):
            if (
                os.path.lexists(folder / MARKER)
                and os.path.lexists(folder / RUN_FILE)
                or STAGING.fullmatch(folder.name)
            ):
                return folder
    return None


STAGING = re.compile(r"\..+\.(?:[a-z0-9_]{8}\.partial|old-[0-9]+)")
"""The names of a run's staging and moved-aside folders (:func:`leftovers`), which the next run of
that folder removes: nothing armanim is asked to write may go into one.

>>> bool(STAGING.fullmatch(".rb.abcdefgh.partial")), bool(STAGING.fullmatch(".rb.old-123")), bool(STAGING.fullmatch("rb"))
(True, True, False)
"""


def refuse_in_run_folder(target: Path, flag: str, *, itself: bool = False) -> None:
    """Raise UsageError (exit 2) when ``target`` lies in a run folder (:func:`run_folder_holding`)."""
    from armanim.errors import UsageError

    folder = run_folder_holding(target, itself=itself)
    if folder is not None and STAGING.fullmatch(folder.name):
        raise UsageError(
            f"{flag} {target}: is inside {folder}, which is named as a run's staging or moved-aside folder: "
            "the next run of that folder removes it with all it holds (choose a path outside it)"
        )
    if folder is not None:
        where = (
            "is the run folder"
            if itself and Path(os.path.abspath(target)) in (folder, folder.resolve())
            else "is inside the run folder"
        )
        raise UsageError(
            f"{flag} {target}: {where} {folder}, which holds only the files armanim lists in it "
            "(what is written there would stop its next run: choose a path outside any run folder)"
        )


def file_stamp(path: Path, *, digest: bool = True) -> dict | None:
    """What the marker records of a file armanim wrote: its size, mtime (ns) and, with ``digest``,
    the sha256 of its bytes; None if ``path`` is not a regular file (a folder, a link, ...).

    Size and time alone miss an edit that keeps both: a value changed in place on a disk whose
    times count whole seconds (ext3, HFS+, FAT: 2 s) within the second the run wrote it, or any
    edit whose time was put back (``touch -r``, ``cp -p``, ``rsync -t``). Campaign 18: the next
    run replaced such an edited trajectory.csv, exit 0."""
    try:
        info = os.lstat(path)
    except OSError:
        return None
    if not stat.S_ISREG(info.st_mode):
        return None
    stamp: dict = {"bytes": info.st_size, "mtime_ns": info.st_mtime_ns}
    if digest:
        stamp["sha256"] = file_sha256(path)
    return stamp


def file_sha256(path: Path) -> str | None:
    """The sha256 of the regular file ``path``'s bytes (read a block at a time), or None when it
    cannot be read or is no longer a regular file (never opened through a link, never waited on)."""
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK | os.O_CLOEXEC)
    except OSError:
        return None
    with os.fdopen(fd, "rb") as handle:
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            return None
        try:
            return stream_sha256(handle)
        except OSError:
            return None


def marked_files(folder: Path) -> dict[str, dict | None] | None:
    """The files ``folder``'s marker lists, each with its recorded :func:`file_stamp` (None
    for a marker of an armanim before 0.1 that recorded names only), or None without a valid marker."""
    marker = Path(folder) / MARKER
    try:
        if not stat.S_ISREG(os.lstat(marker).st_mode) or os.lstat(marker).st_size > 100_000:
            return None
        data = parse_json(marker.read_text(encoding="utf-8"))
        files = data["files"]
        if data.get("made_by") != "armanim":
            return None
        if isinstance(files, list) and all(isinstance(f, str) for f in files):
            return dict.fromkeys(files)
        if isinstance(files, dict) and all(isinstance(s, dict) for s in files.values()):
            return files
        return None
    except (OSError, ValueError, KeyError, TypeError, AttributeError):
        return None


def write_marker(folder: Path) -> None:
    """Mark ``folder`` as armanim's: list every file in it with its size, mtime and sha256 (call when
    it is complete), so that only armanim's own, unchanged files count as armanim's."""
    files = {p.name: file_stamp(p) for p in sorted(Path(folder).iterdir()) if p.name not in (MARKER, STAGING_TAG)}
    data = {
        "made_by": "armanim",
        "armanim_version": __version__,
        "files": files,
        "note": "armanim replaces this folder whole on the next run of its scene; files not listed here, "
        "or changed since, stop it",
    }
    write_text_atomic(Path(folder) / MARKER, json_text(data, indent=2) + "\n")


def _changed(folder: Path, name: str, recorded: dict | None) -> bool:
    """Whether ``folder/name`` is no longer the regular file armanim wrote there: another size or
    time, or (when the marker records it: armanim since 2026-12-07) other bytes."""
    now = file_stamp(folder / name, digest=False)
    if now is None:
        return True
    if recorded is None:  # a marker of an armanim before 0.1: names only
        return False
    if (now["bytes"], now["mtime_ns"]) != (recorded.get("bytes"), recorded.get("mtime_ns")):
        return True
    return "sha256" in recorded and file_sha256(folder / name) != recorded["sha256"]


def _shown(names: list[str]) -> str:
    return ", ".join(names[:5]) + (", ..." if len(names) > 5 else "")


def replace_problem(final: Path) -> str | None:
    """Why ``final`` must not be replaced by a run, or None if it may (absent, empty, or armanim's)."""
    try:
        mode = os.lstat(final).st_mode
    except FileNotFoundError:
        return None
    except NotADirectoryError:  # a file above it (checked before anything is made: nothing there to name)
        return "a file stands where a folder is needed in its path"
    except OSError as exc:
        return f"cannot be inspected ({exc.strerror or exc})"
    if stat.S_ISLNK(mode):
        return "is a link, which armanim did not make and does not replace"
    if not stat.S_ISDIR(mode):
        return "a file stands where a folder is needed"
    if os.path.ismount(final):  # campaign 17: `render --out` a mounted disk ended "Device or resource busy"
        return "is a mount point, which armanim cannot swap a new folder in for (choose a folder inside it)"
    try:
        entries = sorted(p.name for p in final.iterdir())
    except OSError as exc:
        return f"cannot be listed ({exc.strerror or exc})"
    if not entries:
        return None
    listed = marked_files(final)
    if listed is None:
        if MARKER in entries:
            return f"its {MARKER} cannot be read as armanim's marker, so it is not replaced"
        return f"this folder was not made by armanim (no {MARKER} in it; it holds {_shown(entries)}), so it is not replaced"
    foreign = [name for name in entries if name != MARKER and name not in listed]
    if foreign:
        return f"holds files armanim did not write ({_shown(foreign)}), so it is not replaced"
    changed = [name for name in entries if name != MARKER and _changed(final, name, listed[name])]
    if changed:
        return f"holds files changed since armanim wrote them ({_shown(changed)}: edited, or now another file, a folder or a link), so it is not replaced"
    protected = _write_protected(final)
    if protected is not None:
        shown, kind = protected
        return f"is write-protected ({shown} is {kind}), so it is not replaced: {unprotecting(kind, final, recursive=True)}"
    return None


def _write_protected(folder: Path) -> tuple[str, str] | None:
    """The first folder or file in ``folder`` (itself included) that is write-protected
    (:func:`~armanim.output.files.write_protected`: a user's ``chmod a-w``, root or not), shown
    relative to it, and how it is protected (:func:`~armanim.output.files.protection_kind`), or None.

    A run folder is replaced by moving it aside and removing it: a write-protected one would be
    replaced anyway and, as a user who is not root, its moved-aside copy left behind for ever
    (campaign 16); as root, a ``chmod 555`` folder was replaced as if it were not protected."""
    for where, _, files in os.walk(folder):
        for path in (where, *(os.path.join(where, name) for name in sorted(files))):
            if write_protected(path):
                shown = "the folder" if path == str(folder) else shown_path(os.path.relpath(path, folder))
                return shown, protection_kind(path)
    return None


def check_replaceable(final: Path) -> None:
    """An OutputError (exit 3) if ``final`` is something armanim did not make.

    Raises
    ------
    OutputError
        Saying what is there and how to proceed; nothing is moved or deleted.
    """
    problem = replace_problem(Path(final))
    if problem is None:
        return
    cache = cache_inside(Path(final))
    if cache is not None:  # armanim's own cache, but a run folder holds only what its marker lists
        raise OutputError(
            f"{final}: {problem}: {cache} is armanim's capsule-fit cache ({CACHE_ENV}), which is set "
            f"inside the run folder, which a run replaces whole: set {CACHE_ENV} to a folder outside every run "
            "folder (and move the cache there, or remove it)"
        )
    raise OutputError(f"{final}: {problem} (move it away, or choose another folder with --out)")


def swap_in(staged: Path, final: Path) -> None:
    """Put ``staged`` in place of ``final`` (which may not exist), removing the old one.

    Only a folder armanim made (see :func:`check_replaceable`) is replaced.
    """
    check_replaceable(final)
    old = final.with_name(f".{final.name}.old-{os.getpid()}")
    try:
        if final.exists():
            os.rename(final, old)
        os.rename(staged, final)
    except OSError as exc:
        if old.exists() and not final.exists():
            os.rename(old, final)
        raise output_error(final, exc) from None
    shutil.rmtree(old, ignore_errors=True)


def leftovers(final: Path) -> list[Path]:
    """Staging folders and moved-aside old folders of ``final`` (hidden, beside it)."""
    parent = Path(final).parent
    if not parent.is_dir():
        return []
    # exactly the names staged_folder (mkdtemp: 8 random characters) and swap_in make, so
    # that another scene's folders (e.g. of a scene named "a.b" beside "a") never match
    pattern = re.compile(rf"\.{re.escape(Path(final).name)}\.(?:[a-z0-9_]{{8}}\.partial|old-[0-9]+)")
    return sorted(p for p in parent.iterdir() if pattern.fullmatch(p.name))


STAGING_TAG = ".armanim-staging"
"""The file a run's staging folder holds from the moment it is made until its marker is written,
so that the next run of the folder knows a killed run's staging folder as armanim's."""


def _made_by_armanim(leftover: Path) -> bool:
    """Whether a folder at a leftover's name (:func:`leftovers`) is armanim's to remove or put back:
    a staging folder that holds :data:`STAGING_TAG`, or a folder a run would replace (empty, or a
    run folder armanim marked and nobody changed since). A folder of the user's that only bears
    such a name (a copy kept as ``.NAME.old-1``) is not, nor is a link or a file."""
    try:
        if not stat.S_ISDIR(os.lstat(leftover).st_mode):
            return False
        if leftover.name.endswith(".partial") and stat.S_ISREG(os.lstat(leftover / STAGING_TAG).st_mode):
            return True
    except OSError:
        pass
    return replace_problem(leftover) is None


def recover(final: Path) -> None:
    """Tidy up after a run of ``final`` that was killed outright; call with the lock held.

    An old folder moved aside by an unfinished swap is put back if ``final`` is missing;
    every other leftover is removed. Only what armanim made (:func:`_made_by_armanim`) is
    touched: a folder of the user's at such a name is left as it is.
    """
    final = Path(final)
    for path in leftovers(final):
        if not _made_by_armanim(path):
            continue
        if path.name.endswith(".partial") or final.exists():
            shutil.rmtree(path, ignore_errors=True)
        else:
            with contextlib.suppress(OSError):
                os.rename(path, final)


def _link_or_copy(source: str, target: str) -> None:
    try:
        os.link(source, target)  # the staged copy shares the bytes; new files replace links, never edit them
    except OSError:
        shutil.copy2(source, target)


def _copy_run(final: Path, staged: Path) -> None:
    """Put the files of the run folder ``final`` into ``staged`` (hard links where possible)."""
    for entry in final.iterdir():
        if entry.name == MARKER:
            continue
        if entry.is_dir() and not entry.is_symlink():
            shutil.copytree(entry, staged / entry.name, copy_function=_link_or_copy)
        else:
            _link_or_copy(str(entry), str(staged / entry.name))


@contextlib.contextmanager
def staged_folder(final: Path, *, keep_files: bool = False) -> Iterator[Path]:
    """Yield a temporary folder; on success it replaces ``final`` whole.

    The folder is empty, or with ``keep_files`` holds the files of ``final`` (which must then
    be a run folder), so that a command that changes some of a run's files (``render``)
    stages and swaps like a run. On any exception, including KeyboardInterrupt, the
    temporary folder is removed and ``final`` is left as it was.

    Raises
    ------
    InterruptedAfterCommit
        Ctrl-C or SIGTERM came during the swap (it is held back until the swap is done):
        the new folder is in place.
    """
    final = Path(final)
    check_replaceable(final)  # refused before anything is made: no lock file beside a folder it refuses
    with folder_lock(final):
        recover(final)
        check_replaceable(final)  # again under the lock (fail before the work, not after it)
        try:
            staged = Path(tempfile.mkdtemp(prefix=f".{final.name}.", suffix=".partial", dir=final.parent))
            staged.chmod(0o777 & ~current_umask())
        except OSError as exc:
            raise output_error(final, exc) from None
        committed = False
        try:
            try:
                try:
                    (staged / STAGING_TAG).touch()  # (killed before it: an empty folder, armanim's too)
                    if keep_files and final.is_dir():
                        _copy_run(final, staged)
                except OSError as exc:
                    raise output_error(staged, exc) from None
                yield staged
                write_marker(staged)
                (staged / STAGING_TAG).unlink()  # after the marker: a killed run's folder is always known as armanim's
            except OutputError as exc:  # name the folder the user knows, not the hidden staging folder
                raise type(exc)(str(exc).replace(str(staged), str(final))) from None
            with interrupts_deferred():
                swap_in(staged, final)
                committed = True
        except KeyboardInterrupt:
            if committed:  # held back during the swap: the new folder is whole and in place
                raise InterruptedAfterCommit(final) from None
            raise
        finally:
            with interrupts_deferred():
                shutil.rmtree(staged, ignore_errors=True)
