"""End to end through the installed ``armanim`` console script."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from conftest import SCENES

from armanim.arm.kinematics import Arm, forward


def armanim_exe() -> str:
    exe = Path(sys.executable).parent / "armanim"
    found = str(exe) if exe.exists() else shutil.which("armanim")
    if found is None:
        pytest.fail("the armanim console script is not installed")
    return found


def test_installed_fk_json(tmp_path):
    proc = subprocess.run(
        [armanim_exe(), "fk", "--angles", "0,30,45,10", "--json"],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        timeout=60,
    )
    assert proc.returncode == 0, proc.stderr
    data = json.loads(proc.stdout)
    assert set(data) == {"angles_deg", "joints", "tip", "tip_quaternion_wxyz", "tip_rpy_deg"}
    pose = forward(Arm.from_names([1.0] * 4), np.radians([0, 30, 45, 10]))
    np.testing.assert_allclose(data["tip"], pose.tip, atol=1e-12)
    assert len(data["joints"]) == 5


def test_installed_run_out_of_reach(tmp_path):
    scene = SCENES / "out-of-reach.yaml"
    proc = subprocess.run(
        [armanim_exe(), "run", str(scene), "--no-video", "--quiet", "--out", str(tmp_path)],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        timeout=120,
    )
    assert proc.returncode == 0, proc.stderr
    assert "Traceback" not in proc.stderr
    folder = tmp_path / "out-of-reach"
    summary = json.loads((folder / "summary.json").read_text())
    assert [g["reached"] for g in summary["goals"]] == [False, True]
    assert summary["goals"][0]["reason"] == "out_of_reach"
    assert (folder / "trajectory.csv").read_text().startswith("frame,time_s,goal,phi1_deg")


def test_installed_bad_scene_exits_2_without_traceback(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text("version: 1\narm:\n  links: [1, 1]\n  limits: [[10, 5], null]\ngoals:\n  - [0, 0, 1]\n")
    proc = subprocess.run(
        [armanim_exe(), "validate", str(bad)], capture_output=True, text=True, cwd=tmp_path, timeout=60
    )
    assert proc.returncode == 2
    assert f"{bad}:4: arm.limits[0]: min must be below max" in proc.stderr
    assert "Traceback" not in proc.stderr
