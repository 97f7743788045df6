"""Helpers of the tests that look into run folders after faults and interruptions: the
installed command, a folder's hashes, leftover temporary files, a one-line error message.
"""

from __future__ import annotations

import hashlib
import shutil
import sys
from pathlib import Path

LEFTOVER_MARKS = (".partial", ".tmp", ".part", ".old-", ".concat")


def armanim_exe() -> str:
    exe = Path(sys.executable).parent / "armanim"
    return str(exe) if exe.exists() else shutil.which("armanim")


def snapshot(folder: Path) -> dict[str, str]:
    """sha256 of every file below ``folder``, by relative path."""
    return {str(p.relative_to(folder)): hashlib.sha256(p.read_bytes()).hexdigest() for p in sorted(folder.rglob("*")) if p.is_file()}


def leftovers(root: Path) -> list[str]:
    """Temporary files or folders anywhere below ``root`` (the lock file is meant to stay)."""
    return [str(p) for p in root.rglob("*") if any(mark in p.name for mark in LEFTOVER_MARKS)]


def one_line_error(result) -> str:
    text = result.stderr.strip()
    assert "Traceback" not in result.output
    assert text and len(text.splitlines()) == 1, text
    return text
