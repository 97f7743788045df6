"""trajectory.csv and summary.json: columns, values, byte-for-byte determinism."""

from __future__ import annotations

import csv
import hashlib
import io
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from conftest import SCENES

from armanim import __version__
from armanim.arm.kinematics import forward
from armanim.output.csvfile import read_trajectory_csv, trajectory_csv_text
from armanim.runs.options import RunOptions
from armanim.runs.pipeline import run_scene

REQUIRED_HEAD = ["frame", "time_s", "goal"]
REQUIRED_TAIL = ["x", "y", "z", "goal_distance", "clearance", "reached"]


def required_columns(n: int) -> list[str]:
    return [*REQUIRED_HEAD, *(f"phi{i}_deg" for i in range(1, n + 1)), *REQUIRED_TAIL]


@pytest.fixture(scope="module")
def notes_run(tmp_path_factory):
    return run_scene(SCENES / "notes-arm.yaml", tmp_path_factory.mktemp("notes"), RunOptions(video=False))


def test_run_writes_only_csv_and_summary_without_video(notes_run):
    assert notes_run.folder.name == "notes-arm"
    names = {p.name for p in notes_run.folder.iterdir()}
    assert {"summary.json", "trajectory.csv"} <= names
    assert not names & {"animation.mp4", "animation.gif", "plot.png", "poster.png"}
    assert not [n for n in names if n.endswith(".tmp")]


def test_trajectory_csv_columns_and_values(notes_run):
    path = notes_run.files["trajectory"]
    rows = list(csv.reader(io.StringIO(path.read_text(encoding="utf-8"))))
    n = notes_run.problem.arm.n
    assert rows[0][: len(required_columns(n))] == required_columns(n)
    traj = notes_run.solution.trajectory
    assert len(rows) - 1 == traj.frames
    table = read_trajectory_csv(path)
    np.testing.assert_array_equal(table.column("frame"), np.arange(traj.frames))
    np.testing.assert_allclose(table.column("time_s"), np.arange(traj.frames) / notes_run.problem.fps, rtol=0, atol=0)
    np.testing.assert_array_equal(table.column("goal"), traj.goal)
    # angles in degrees, written exactly (repr round trip)
    np.testing.assert_array_equal(np.radians(table.angles_deg), np.radians(np.degrees(traj.phi)))
    np.testing.assert_allclose(np.radians(table.angles_deg), traj.phi, atol=1e-12)
    tip = np.stack([table.column(c) for c in "xyz"], axis=1)
    np.testing.assert_allclose(tip, forward(notes_run.problem.arm, np.radians(table.angles_deg)).tip, atol=1e-9)
    np.testing.assert_allclose(table.column("clearance"), traj.clearance)
    assert np.all(table.column("clearance") > 0)
    reached = table.column("reached")
    assert set(np.unique(reached)) <= {0.0, 1.0}
    assert np.all(table.column("goal_distance")[reached == 1] < notes_run.problem.solver.tolerance)


def test_clearance_column_is_empty_without_obstacles(tmp_path):
    result = run_scene(SCENES / "singular-start.yaml", tmp_path, RunOptions(video=False))
    rows = list(csv.DictReader(io.StringIO(result.files["trajectory"].read_text())))
    assert rows and all(r["clearance"] == "" for r in rows)


def test_summary_json(notes_run):
    summary = json.loads(notes_run.files["summary"].read_text(encoding="utf-8"))
    assert summary == json.loads(json.dumps(notes_run.summary))
    assert summary["armanim_version"] == __version__
    scene_file = SCENES / "notes-arm.yaml"
    assert summary["scene"]["sha256"] == hashlib.sha256(scene_file.read_bytes()).hexdigest()
    assert summary["scene"]["name"] == "notes-arm"
    assert summary["method"] == "pinv"
    sol = notes_run.solution
    totals = summary["totals"]
    assert totals["goals"] == len(sol.goals) == 4
    assert totals["reached"] + totals["missed"] == totals["goals"]
    assert totals["frames"] == sol.trajectory.frames
    assert len(summary["goals"]) == 4
    for entry, report in zip(summary["goals"], sol.goals):
        for key in ("reached", "reason", "frames", "final_distance", "iterations"):
            assert key in entry
        assert entry["reached"] is report.reached
        assert entry["frames"] == report.frames
        assert entry["final_distance"] == pytest.approx(report.final_distance)
        assert entry["iterations"] == report.iterations
    assert summary["max_joint_step_deg"] <= np.degrees(notes_run.problem.solver.max_joint_step) + 1e-9
    assert summary["min_clearance"] > 0
    text = notes_run.files["summary"].read_text()
    assert str(notes_run.folder) not in text  # no absolute paths: reproducible


def test_summary_of_a_missed_goal_has_its_reason(tmp_path):
    result = run_scene(SCENES / "out-of-reach.yaml", tmp_path, RunOptions(video=False))
    goals = json.loads(result.files["summary"].read_text())["goals"]
    assert goals[0]["reached"] is False and goals[0]["reason"] == "out_of_reach"
    assert goals[1]["reached"] is True and goals[1]["reason"] is None


def test_csv_text_has_no_negative_zero(notes_run):
    assert ",-0.0," not in trajectory_csv_text(notes_run.solution.trajectory)


@pytest.mark.parametrize("scene", ["notes-arm.yaml", "out-of-reach.yaml"])
def test_two_runs_are_byte_identical(tmp_path, scene):
    a = run_scene(SCENES / scene, tmp_path / "a", RunOptions(video=False))
    b = run_scene(SCENES / scene, tmp_path / "b", RunOptions(video=False))
    for kind in ("trajectory", "summary"):
        assert a.files[kind].read_bytes() == b.files[kind].read_bytes(), kind


def test_a_run_shows_its_plans_and_writes_what_a_quiet_run_writes(tmp_path):
    """The bars' "plan" stage: a planned run reports its search; its files are a quiet run's."""
    seen = []
    told = run_scene(
        SCENES / "planning-wall.yaml",
        tmp_path / "told",
        RunOptions(video=False),
        progress=lambda *call: seen.append(call),
    )
    quiet = run_scene(SCENES / "planning-wall.yaml", tmp_path / "quiet", RunOptions(video=False))
    assert {stage for stage, *_ in seen} == {"solve", "plan"}
    assert any(stage == "plan" and done == most for stage, done, most in seen)
    for kind in ("trajectory", "summary"):
        assert told.files[kind].read_bytes() == quiet.files[kind].read_bytes(), kind


def armanim_command() -> list[str]:
    exe = Path(sys.executable).parent / "armanim"
    return [str(exe)] if exe.exists() else [sys.executable, "-m", "armanim"]


def test_two_processes_are_byte_identical(tmp_path):
    scene = SCENES / "singular-start.yaml"
    outs = []
    for name in ("p1", "p2"):
        out = tmp_path / name
        env = dict(os.environ, PYTHONHASHSEED=name[-1])
        proc = subprocess.run(
            [*armanim_command(), "run", str(scene), "--no-video", "--quiet", "--out", str(out)],
            capture_output=True,
            text=True,
            cwd=tmp_path,
            env=env,
            timeout=120,
        )
        assert proc.returncode == 0, proc.stderr
        outs.append(out / "singular-start")
    for name in ("trajectory.csv", "summary.json"):
        assert (outs[0] / name).read_bytes() == (outs[1] / name).read_bytes(), name


def test_invalid_scene_writes_nothing(tmp_path):
    from armanim.errors import SceneError

    bad = tmp_path / "bad.yaml"
    bad.write_text("version: 1\narm:\n  links: [1, -1]\ngoals:\n  - [0, 0, 1]\n")
    with pytest.raises(SceneError):
        run_scene(bad, tmp_path / "out", RunOptions(video=False))
    assert not (tmp_path / "out").exists()
