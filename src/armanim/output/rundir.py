"""A run's output folder, replaced whole or not at all.

A run writes into a hidden temporary folder beside ``ROOT/<name>`` and swaps it in
only when every file is complete, so a failed or interrupted run leaves the previous
outputs untouched. A lock file beside the folder keeps two runs of the same scene
from interleaving: the second waits for the first. The swap and the clean-up hold
Ctrl-C back until they are done, and a run killed outright (``kill -9``, a power
cut) is tidied up by the next run of the same folder: its staging folder is
removed, and an old folder it had moved aside is put back.
"""

from __future__ import annotations

import contextlib
import errno
import fcntl
import os
import re
import shutil
import tempfile
from pathlib import Path
from typing import Iterator

from armanim.output.atomic import current_umask, interrupts_deferred, output_error


@contextlib.contextmanager
def folder_lock(folder: Path) -> Iterator[None]:
    """Hold an exclusive lock on ``folder`` (a hidden ``.<name>.lock`` file beside it)."""
    try:
        folder.parent.mkdir(parents=True, exist_ok=True)
        handle = open(folder.parent / f".{folder.name}.lock", "a")
    except OSError as exc:
        raise output_error(folder, exc) from None
    try:
        fcntl.flock(handle, fcntl.LOCK_EX)
        yield
    finally:
        fcntl.flock(handle, fcntl.LOCK_UN)
        handle.close()


def _not_a_file(final: Path) -> None:
    """An OutputError if a file (not a folder) stands where the output folder goes."""
    if final.exists() and not final.is_dir():
        raise output_error(final, OSError(errno.ENOTDIR, "Not a directory", str(final)))


def swap_in(staged: Path, final: Path) -> None:
    """Put ``staged`` in place of ``final`` (which may not exist), removing the old one.

    A file standing at ``final`` is an error, never moved aside: only a folder is replaced.
    """
    _not_a_file(final)
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


def recover(final: Path) -> None:
    """Tidy up after a run of ``final`` that was killed outright; call with the lock held.

    An old folder moved aside by an unfinished swap is put back if ``final`` is missing;
    every other leftover is removed.
    """
    final = Path(final)
    for path in leftovers(final):
        if path.name.endswith(".partial") or final.exists():
            shutil.rmtree(path, ignore_errors=True)
        else:
            with contextlib.suppress(OSError):
                os.rename(path, final)


@contextlib.contextmanager
def staged_folder(final: Path) -> Iterator[Path]:
    """Yield an empty temporary folder; on success it replaces ``final`` whole.

    On any exception, including KeyboardInterrupt, the temporary folder is removed
    and ``final`` is left as it was.
    """
    final = Path(final)
    with folder_lock(final):
        recover(final)
        _not_a_file(final)  # fail before the work, not after it
        try:
            staged = Path(tempfile.mkdtemp(prefix=f".{final.name}.", suffix=".partial", dir=final.parent))
            staged.chmod(0o777 & ~current_umask())
        except OSError as exc:
            raise output_error(final, exc) from None
        try:
            yield staged
            with interrupts_deferred():
                swap_in(staged, final)
        finally:
            with interrupts_deferred():
                shutil.rmtree(staged, ignore_errors=True)
