"""A run's output folder, replaced whole or not at all.

A run writes into a hidden temporary folder beside ``ROOT/<name>`` and swaps it in
only when every file is complete, so a failed or interrupted run leaves the previous
outputs untouched. A lock file beside the folder keeps two runs of the same scene
from interleaving: the second waits for the first.
"""

from __future__ import annotations

import contextlib
import fcntl
import os
import shutil
import tempfile
from pathlib import Path
from typing import Iterator

from armanim.output.atomic import current_umask, output_error


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


def swap_in(staged: Path, final: Path) -> None:
    """Put ``staged`` in place of ``final`` (which may not exist), removing the old one."""
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


@contextlib.contextmanager
def staged_folder(final: Path) -> Iterator[Path]:
    """Yield an empty temporary folder; on success it replaces ``final`` whole.

    On any exception, including KeyboardInterrupt, the temporary folder is removed
    and ``final`` is left as it was.
    """
    final = Path(final)
    with folder_lock(final):
        try:
            staged = Path(tempfile.mkdtemp(prefix=f".{final.name}.", suffix=".partial", dir=final.parent))
            staged.chmod(0o777 & ~current_umask())
        except OSError as exc:
            raise output_error(final, exc) from None
        try:
            yield staged
            swap_in(staged, final)
        finally:
            shutil.rmtree(staged, ignore_errors=True)
