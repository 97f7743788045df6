"""A MoveIt user's saved scene and request become an armanim run in two commands: MotionBenchMaker's
problems (vendored in tests/data/mbm, with VAMP's robots in tests/data/vamp) imported by the installed
`armanim import moveit` and run by `armanim run`; the joint goal reached exactly, every frame clear of
the objects and the enabled pairs by the numpy clearances, and the fingers (links off the chain) in the
collision model."""

from __future__ import annotations

import csv
import json
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest
from conftest import ROOT
from runfolders import armanim_exe

from armanim.motion.filter.clearance import split_clearances
from armanim.scene import load_scene, scene_to_problem

MBM = ROOT / "tests" / "data" / "mbm"
VAMP = ROOT / "tests" / "data" / "vamp"


def _armanim(*args, cwd: Path) -> subprocess.CompletedProcess:
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src"))
    return subprocess.run(
        [armanim_exe(), *map(str, args)], cwd=cwd, env=env, capture_output=True, text=True, timeout=600
    )


@pytest.mark.parametrize(("problem", "robot"), [("bookshelf_small_panda", "panda"), ("box_ur5", "ur5")])
def test_a_motionbenchmaker_problem_in_two_commands(tmp_path, problem, robot):
    imported = _armanim(
        "import",
        "moveit",
        MBM / f"{problem}-scene0001.yaml",
        "--request",
        MBM / f"{problem}-request0001.yaml",
        "--urdf",
        VAMP / f"{robot}_spherized.urdf",
        "--srdf",
        VAMP / f"{robot}.srdf",
        "--out",
        "scene.yaml",
        cwd=tmp_path,
    )
    assert imported.returncode == 0, imported.stderr
    run = _armanim("run", "scene.yaml", "--no-video", "--quiet", "--out", "out", cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    folder = tmp_path / "out" / "scene"
    summary = json.loads((folder / "summary.json").read_text())
    assert summary["goals"][0]["reached"] and summary["goals"][0]["planned"]
    scene = load_scene(tmp_path / "scene.yaml").model
    problem_ = scene_to_problem(scene)
    rows = list(csv.DictReader((folder / "trajectory.csv").open()))
    n = problem_.arm.n
    phi = np.radians([[float(r[f"phi{j}_deg"]) for j in range(1, n + 1)] for r in rows])
    np.testing.assert_allclose(phi[-1], problem_.goals[0].joints, atol=1e-12)
    clear, own = split_clearances(problem_, phi)
    assert clear.min() >= problem_.solver.clearance - 1e-12
    assert (
        own.min() - (problem_.solver.clearance - problem_.self_pairs.clearance) >= problem_.self_pairs.clearance - 1e-12
    )
    if robot == "panda":  # the fingers hang off the chain (panda_link0 .. panda_link8) and are in the model
        assert {"panda_leftfinger", "panda_rightfinger", "panda_hand", "panda_link0"} <= set(problem_.capsules.names)
