"""`armanim run` with video and `armanim render` re-rendering a finished run from its CSV."""

from __future__ import annotations

import json
import math
import shutil
from pathlib import Path

import imageio_ffmpeg
import pytest
from typer.testing import CliRunner

from armanim.cli import app

ROOT = Path(__file__).resolve().parents[2]
runner = CliRunner()


@pytest.fixture(scope="module")
def finished_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("runs")
    result = runner.invoke(
        app,
        ["run", str(ROOT / "scenes" / "planar-nlink.yaml"), "--out", str(out), "--size", "64x48", "--jobs", "1", "-q"],
    )
    assert result.exit_code == 0, result.output
    return out / "planar-nlink"


def _rows(folder: Path) -> int:
    return len((folder / "trajectory.csv").read_text().splitlines()) - 1


@pytest.mark.slow
def test_run_writes_video_plot_and_scene_copy(finished_run):
    names = {p.name for p in finished_run.iterdir()}
    assert names == {
        ".armanim-run.json",
        "scene.yaml",
        "self-collision.yaml",
        "trajectory.csv",
        "summary.json",
        "timing.json",
        "animation.mp4",
        "plot.png",
        "poster.png",
        "viewer.html",
    }
    frames, _ = imageio_ffmpeg.count_frames_and_secs(str(finished_run / "animation.mp4"))
    assert frames == _rows(finished_run)
    assert (finished_run / "scene.yaml").read_bytes() == (ROOT / "scenes" / "planar-nlink.yaml").read_bytes()


@pytest.mark.slow
def test_render_redraws_at_another_size_and_fps_without_solving(finished_run, tmp_path):
    folder = tmp_path / "copy"
    shutil.copytree(finished_run, folder)
    csv_before = (folder / "trajectory.csv").read_bytes()
    result = runner.invoke(app, ["render", str(folder), "--size", "80x60", "--fps", "12", "--jobs", "1", "-q"])
    assert result.exit_code == 0, result.output
    reader = imageio_ffmpeg.read_frames(str(folder / "animation.mp4"))
    meta = next(reader)
    reader.close()
    assert tuple(meta["size"]) == (80, 60)
    assert meta["fps"] == pytest.approx(12)
    frames, _ = imageio_ffmpeg.count_frames_and_secs(str(folder / "animation.mp4"))
    run_fps = json.loads((folder / "summary.json").read_text())["fps"]
    seconds = (
        _rows(folder) - 1
    ) / run_fps  # the run's own duration, kept at 12 fps (issue 36): frames at k / 12 and the end
    assert frames == math.floor(seconds * 12 + 1e-9) + 1 + (0 if abs(seconds * 12 - round(seconds * 12)) < 1e-9 else 1)
    assert (folder / "trajectory.csv").read_bytes() == csv_before  # nothing re-solved or rewritten


@pytest.mark.parametrize("make", ["missing", "empty"])
def test_render_of_a_folder_that_is_not_a_run_is_bad_input(tmp_path, make):
    folder = tmp_path / "not-a-run"
    if make == "empty":
        folder.mkdir()
    result = runner.invoke(app, ["render", str(folder)])
    assert result.exit_code == 2
    assert str(folder) in result.output
    assert "Traceback" not in result.output


def test_render_rejects_a_bad_view(tmp_path):
    result = runner.invoke(app, ["render", str(tmp_path), "--elevation", "120"])
    assert result.exit_code == 2
    assert "--elevation" in result.output


def test_auto_bounds_hold_every_frame_of_the_run_and_every_goal_and_obstacle():
    import numpy as np

    from armanim.arm.kinematics import forward
    from armanim.motion.trajectory import solve_trajectory
    from armanim.render.camera.bounds import auto_bounds
    from armanim.scene import load_scene, scene_to_problem

    problem = scene_to_problem(load_scene(ROOT / "scenes" / "notes-arm.yaml").model)
    points = forward(problem.arm, solve_trajectory(problem).trajectory.phi).points.reshape(-1, 3)
    box = auto_bounds(problem, points)
    lo, hi = box[:, 0], box[:, 1]
    obstacles = problem.obstacles
    assert np.all(points - problem.half_width >= lo) and np.all(points + problem.half_width <= hi)
    assert np.all(obstacles.centers - obstacles.radii[:, None] >= lo)
    assert np.all(obstacles.centers + obstacles.radii[:, None] <= hi)
    goals = np.array([g.position for g in problem.goals])
    assert np.all(goals >= lo) and np.all(goals <= hi)
    reach_box = auto_bounds(problem)  # without a run: base +- reach, which holds any pose
    assert np.all(reach_box[:, 0] <= lo) and np.all(reach_box[:, 1] >= hi)
