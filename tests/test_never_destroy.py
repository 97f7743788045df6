"""Issue 12: armanim never destroys what it did not make, and hostile inputs, special
files and signals end with a message and the contract's exit code.

Each test is named in docs/reliability.md, which it keeps true.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import psutil
import pytest
from conftest import SCENES

from armanim.output.rundir import MARKER

NOTES = SCENES / "notes-arm.yaml"
SMALL = "version: 1\narm:\n  links: [1, 1, 1, 1]\ngoals:\n  - [1, 1, 2]\n"
CSV_HEADER = "frame,time_s,goal,phi1_deg,phi2_deg,x,y,z,goal_distance,clearance,reached,step_scale,iterations"


def armanim(*args, timeout: float = 120, **kwargs) -> subprocess.CompletedProcess:
    """Run ``python -m armanim ARGS`` as a real process."""
    return subprocess.run([sys.executable, "-m", "armanim", *map(str, args)], capture_output=True, text=True,
                          timeout=timeout, **kwargs)


def no_traceback(result) -> str:
    """stderr, after checking it is a message and not a traceback."""
    text = result.stderr if hasattr(result, "stderr") else result.output
    assert "Traceback" not in text and "Error:" not in text.split(":", 1)[0], text
    return text


def user_files(root: Path) -> dict[str, bytes]:
    return {str(p.relative_to(root)): p.read_bytes() for p in sorted(root.rglob("*")) if p.is_file()}


# ------------------------------------------------------------------ 1. names


@pytest.mark.parametrize("stem", ["..", ".", ".notes-arm.old-1", ".notes-arm.abcdefgh.partial", "a" * 101, "bell\x07"])
def test_unsafe_file_stems_are_rejected_with_the_name_field(cli, tmp_path, stem):
    out = tmp_path / "out"
    (out / "mine").mkdir(parents=True)
    (out / "mine" / "thesis.txt").write_text("x")
    scene = tmp_path / f"{stem}.yaml"
    scene.write_text(SMALL)
    before = user_files(tmp_path)
    result = cli("run", scene, "--out", out, "--no-video", "--quiet")
    assert result.exit_code == 2, result.output
    assert ":1: name: not set, so the file name gives the name" in result.stderr
    assert user_files(tmp_path) == before


@pytest.mark.parametrize("name", ["..", ".hidden", "a/b", "x" * 101])
def test_unsafe_name_fields_are_rejected(cli, tmp_path, name):
    scene = tmp_path / "scene.yaml"
    scene.write_text(SMALL + f"name: {json.dumps(name)}\n")
    result = cli("validate", scene)
    assert result.exit_code == 2 and ":6: name:" in result.stderr, result.output


def test_dot_dot_yaml_with_out_dot_is_exit_2(tmp_path):
    (tmp_path / "..yaml").write_text(SMALL)
    (tmp_path / "keep.txt").write_text("x")
    result = armanim("run", "..yaml", "--out", ".", "--no-video", "-q", cwd=tmp_path)
    assert result.returncode == 2 and "name:" in no_traceback(result)
    assert (tmp_path / "keep.txt").read_text() == "x"


# ------------------------------------------------------------------ 2. folders armanim did not make


def test_a_user_folder_at_the_run_folder_is_never_replaced(cli, tmp_path):
    (tmp_path / "src").mkdir()
    (tmp_path / "src" / "main.py").write_text("print('mine')\n")
    scene = tmp_path / "scene.yaml"
    scene.write_text(SMALL + "name: src\n")
    result = cli("run", scene, "--out", tmp_path, "--no-video", "--quiet")
    assert result.exit_code == 3, result.output
    assert "not made by armanim" in result.stderr and "main.py" in result.stderr and "--out" in result.stderr
    assert (tmp_path / "src" / "main.py").read_text() == "print('mine')\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == [".src.lock", "scene.yaml", "src"]


def test_a_user_file_added_to_a_run_folder_stops_the_next_run(cli, tmp_path):
    scene = tmp_path / "notes.yaml"
    scene.write_text(SMALL)
    assert cli("run", scene, "--out", tmp_path / "out", "--no-video", "-q").exit_code == 0
    folder = tmp_path / "out" / "notes"
    assert json.loads((folder / MARKER).read_text())["files"] == ["scene.yaml", "summary.json", "trajectory.csv"]
    (folder / "thesis.txt").write_text("mine")
    result = cli("run", scene, "--out", tmp_path / "out", "--no-video", "-q")
    assert result.exit_code == 3 and "thesis.txt" in result.stderr, result.output
    assert (folder / "thesis.txt").read_text() == "mine"
    (folder / "thesis.txt").unlink()
    assert cli("run", scene, "--out", tmp_path / "out", "--no-video", "-q").exit_code == 0


def test_an_empty_folder_is_taken_and_a_link_is_refused(cli, tmp_path):
    scene = tmp_path / "notes.yaml"
    scene.write_text(SMALL)
    (tmp_path / "out" / "notes").mkdir(parents=True)
    assert cli("run", scene, "--out", tmp_path / "out", "--no-video", "-q").exit_code == 0
    (tmp_path / "elsewhere").mkdir()
    (tmp_path / "out2").mkdir()
    (tmp_path / "out2" / "notes").symlink_to(tmp_path / "elsewhere")
    result = cli("run", scene, "--out", tmp_path / "out2", "--no-video", "-q")
    assert result.exit_code == 3 and "is a link" in result.stderr
    assert (tmp_path / "out2" / "notes").is_symlink()


# ------------------------------------------------------------------ 3. special files and links


def test_a_write_through_a_link_replaces_its_target(cli, tmp_path):
    (tmp_path / "real.json").write_text("old")
    (tmp_path / "link.json").symlink_to("real.json")
    assert cli("schema", "--out", tmp_path / "link.json").exit_code == 0
    assert (tmp_path / "link.json").is_symlink()
    assert json.loads((tmp_path / "real.json").read_text())["title"] == "armanim scene"


@pytest.mark.parametrize("kind", ["fifo", "device", "folder"])
def test_special_files_at_a_target_are_an_error(cli, tmp_path, kind):
    target = tmp_path / "target"
    if kind == "fifo":
        os.mkfifo(target)
    elif kind == "folder":
        target.mkdir()
    else:
        target = Path("/dev/null")
    before = os.stat(target)
    for args in (("schema", "--out", target), ("fk", "--angles", "0,0,0,0", "--png", target)):
        result = cli(*args)
        assert result.exit_code == 3, result.output
        assert "not a regular file" in result.stderr
    after = os.stat(target)
    assert (before.st_ino, before.st_mode) == (after.st_ino, after.st_mode)
