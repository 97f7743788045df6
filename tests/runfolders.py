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
    return {
        str(p.relative_to(folder)): hashlib.sha256(p.read_bytes()).hexdigest()
        for p in sorted(folder.rglob("*"))
        if p.is_file()
    }


def leftovers(root: Path) -> list[str]:
    """Temporary files or folders anywhere below ``root`` (the lock file is meant to stay)."""
    return [str(p) for p in root.rglob("*") if any(mark in p.name for mark in LEFTOVER_MARKS)]


def one_line_error(result) -> str:
    text = result.stderr.strip()
    assert "Traceback" not in result.output
    assert text and len(text.splitlines()) == 1, text
    return text


SMALL = "version: 1\narm:\n  links: [1, 1, 1, 1]\ngoals:\n  - [1, 1, 2]\n"
"""A four-link scene that solves in a blink."""


def small_scene(folder: Path, name: str) -> Path:
    """:data:`SMALL` named ``name`` in ``folder``, drawn tiny (10 fps, 64 x 48)."""
    path = folder / f"{name}.yaml"
    path.write_text(SMALL + f"name: {name}\nrender: {{fps: 10, size: [64, 48]}}\n")
    return path


def assert_reruns_byte_identical(cli, scene: Path, name: str) -> list[Path]:
    """``scene`` run twice through ``cli`` (no video, each into its own folder beside it): the two
    runs' trajectory.csv and summary.json are the same bytes (``name``: the scene's name). Returns
    the two run folders."""
    outs = []
    for k in range(2):
        result = cli("run", scene, "--out", scene.parent / f"out{k}", "--no-video", "--quiet")
        assert result.exit_code == 0, result.output
        outs.append(scene.parent / f"out{k}" / name)
    for file in ("trajectory.csv", "summary.json"):
        assert (outs[0] / file).read_bytes() == (outs[1] / file).read_bytes(), file
    return outs
