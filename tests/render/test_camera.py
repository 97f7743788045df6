"""The camera renderer: projection, depth order, layout, planar arms, hidden goals, GIF size, render --out."""

from __future__ import annotations

import dataclasses
import json
from itertools import combinations
from pathlib import Path

import imageio_ffmpeg
import numpy as np
import pytest
import yaml

from armanim.arm.kinematics import Arm, forward
from armanim.motion.problem import Goal, Problem
from armanim.render.camera.projection import camera_rotation, fit_view, planar_normal, view_angles
from armanim.scene import default_render_settings, default_solver_settings, unlimited_limits
from armanim.world.obstacles import Obstacles

ROOT = Path(__file__).resolve().parents[2]
SCENES = sorted((ROOT / "scenes").glob("*.yaml"))
SIZES = [(640, 360), (1280, 720), (1920, 1080)]


def problem_with(arm: Arm, centers, radii, goals, half_width=0.3) -> Problem:
    obs = Obstacles(np.array(centers, float).reshape(-1, 3), np.array(radii, float), np.zeros(len(radii)))
    return Problem(
        arm,
        half_width,
        np.zeros(arm.n),
        unlimited_limits(arm.n),
        obs,
        tuple(Goal(np.array(g, float), hold=0.0) for g in goals),
        default_solver_settings(),
        fps=30.0,
    )


# ----- projection -------------------------------------------------------------------------


def test_rotation_matches_hand_computed_axes_at_elevation_30_azimuth_45():
    s, c = np.sqrt(0.5), np.sqrt(0.75)
    rot = camera_rotation(30.0, 45.0)
    np.testing.assert_allclose(rot[0], [-s, s, 0.0], atol=1e-12)  # screen right
    np.testing.assert_allclose(rot[1], [-0.5 * s, -0.5 * s, c], atol=1e-12)  # screen up
    np.testing.assert_allclose(rot[2], [c * s, c * s, 0.5], atol=1e-12)  # toward the viewer
    np.testing.assert_allclose(np.linalg.det(rot), 1.0)


def test_top_view_puts_x_right_and_y_up_and_fits_the_points():
    rot = camera_rotation(90.0, -90.0)
    points = np.array([[0.0, 0, 0], [4, 2, 0]])
    view = fit_view(rot, points, np.zeros(2), (10, 20, 110, 220), (120, 240))
    # 4 x 2 units into a 100 x 200 box: 25 px per unit (width-limited), centred vertically
    np.testing.assert_allclose(view.project(points)[:, :2], [[10, 95], [110, 145]], atol=1e-9)
    np.testing.assert_allclose(view.pixels_per_unit, [25, 25])


def test_depth_grows_toward_the_viewer():
    view = fit_view(camera_rotation(0.0, 0.0), np.eye(3), np.zeros(3), (0, 0, 10, 10), (10, 10))
    near, far = view.project(np.array([[1.0, 0, 0], [-1.0, 0, 0]]))[:, 2]
    assert near > far  # looking from +x: x = 1 is nearer


# ----- planar arms --------------------------------------------------------------------------


def test_planar_detection():
    np.testing.assert_allclose(planar_normal(Arm.from_names([1, 1, 1], axes=["z"] * 3, direction="x")), [0, 0, 1])
    np.testing.assert_allclose(np.abs(planar_normal(Arm.from_names([1, 1], axes=["y", "y"], direction="z"))), [0, 1, 0])
    assert planar_normal(Arm.from_names([2, 5, 5, 5])) is None  # base yaw + elbows
    assert planar_normal(Arm.from_names([1, 1], axes=["z", "z"], direction="z")) is None  # links along the axis


def test_a_planar_arm_is_seen_face_on_unless_the_scene_sets_a_view():
    arm = Arm.from_names([1, 1], axes=["y", "y"], direction="z")
    elevation, azimuth = view_angles(arm, None, None)
    toward = camera_rotation(elevation, azimuth)[2]
    assert abs(abs(toward @ [0, 1, 0]) - 1) < 1e-9  # looking along the joint axes
    assert view_angles(arm, 25.0, -60.0) == (25.0, -60.0)


def test_the_planar_scene_file_without_a_view_gets_none():
    from armanim.scene import load_scene, render_settings

    text = (ROOT / "scenes" / "planar-nlink.yaml").read_text()
    settings = render_settings(load_scene(ROOT / "scenes" / "planar-nlink.yaml").model)
    assert ("view:" in text) == (settings.elevation is not None)


# ----- depth order and hidden goals ---------------------------------------------------------


def _frame(problem, phi, size=(320, 240)):
    from armanim.render.pictures.canvas import FrameState, SceneCanvas

    pose = forward(problem.arm, phi)
    scene = SceneCanvas(
        problem, default_render_settings(size=size, elevation=0.0, azimuth=0.0), title="t", extent=pose.points
    )
    state = FrameState(pose, 0, np.zeros(len(problem.goals), dtype=int), "")
    return scene, scene.draw(state).copy(), pose


@pytest.mark.parametrize("sphere_x, arm_wins", [(-3.0, True), (3.0, False)])
def test_a_link_in_front_of_a_sphere_is_drawn_after_it(sphere_x, arm_wins):
    from armanim.render.paint.style import ARM_COLOR

    # Seen from +x: the arm stands along z at x = 0; the sphere behind it (x = -3) or in front (x = 3).
    arm = Arm.from_names([4.0], axes=["y"], direction="z")
    problem = problem_with(arm, [[sphere_x, 0, 2]], [1.0], [[0, 0, 5.0]], half_width=0.3)
    scene, rgba, pose = _frame(problem, np.zeros(1))
    x, y, _ = scene.view.project(np.array([0.0, 0, 2]))
    pixel = rgba[int(scene.height - y), int(x), :3].astype(float)
    arm_rgb = np.asarray(ARM_COLOR)
    looks_like_arm = pixel @ arm_rgb / (np.linalg.norm(pixel) * np.linalg.norm(arm_rgb)) > 0.97
    assert looks_like_arm == arm_wins, pixel


def test_a_goal_behind_a_sphere_is_drawn_through_it():
    arm = Arm.from_names([4.0], axes=["y"], direction="z")
    problem = problem_with(arm, [[0, 3, 2]], [1.5], [[-3.0, 3, 2]])
    scene, with_goal, _ = _frame(problem, np.zeros(1))
    assert scene.goals.hidden.tolist() == [True]
    scene.goals.stamps.update({(0, code): None for code in range(4)})
    state_pose = forward(problem.arm, np.zeros(1))
    from armanim.render.pictures.canvas import FrameState

    without = scene.draw(FrameState(state_pose, 0, np.zeros(1, dtype=int), "")).copy()
    x, y = scene.goals.xy[0]
    rows = slice(int(scene.height - y) - 12, int(scene.height - y) + 12)
    cols = slice(int(x) - 12, int(x) + 12)
    assert np.abs(with_goal[rows, cols].astype(int) - without[rows, cols].astype(int)).max() > 40


# ----- layout: nothing overlaps --------------------------------------------------------------


def _overlaps(boxes: dict) -> list:
    return [
        (a, b)
        for (a, p), (b, q) in combinations(boxes.items(), 2)
        if p[0] < q[2] and q[0] < p[2] and p[1] < q[3] and q[1] < p[3]
    ]


@pytest.mark.parametrize("size", SIZES, ids=lambda s: f"{s[0]}x{s[1]}")
@pytest.mark.parametrize("scene_path", SCENES, ids=lambda p: p.stem)
def test_no_text_boxes_intersect_and_all_are_in_the_frame(scene_path, size):
    from conftest import solved_scene

    from armanim.render.pictures.canvas import SceneCanvas
    from armanim.scene import load_scene, render_settings

    loaded = load_scene(scene_path)
    problem, solution = solved_scene(scene_path)  # once for the three sizes
    traj = solution.trajectory
    settings = dataclasses.replace(render_settings(loaded.model), size=size)
    canvas = SceneCanvas(
        problem, settings, title=loaded.name, tips=traj.tip, extent=forward(problem.arm, traj.phi).points
    )
    boxes = canvas.text_boxes
    assert {"title", "caption", "legend 0"} <= set(boxes)
    named = [int(n) for k in boxes if k.startswith("goal ") for n in k.removeprefix("goal ").split(", ")]
    assert sorted(named) == list(range(len(problem.goals)))  # every goal named once (goals at one place: one label)
    assert not _overlaps(boxes), _overlaps(boxes)
    for name, (x0, y0, x1, y1) in boxes.items():
        assert 0 <= x0 and 0 <= y0 and x1 <= size[0] and y1 <= size[1], (name, (x0, y0, x1, y1))


# ----- files ---------------------------------------------------------------------------------


@pytest.mark.slow
def test_an_11_second_640x360_gif_stays_well_under_3_mb(tmp_path):
    from armanim.render.settings import RenderOverrides
    from armanim.runs.options import RunOptions
    from armanim.runs.pipeline import run_scene

    scene = yaml.safe_load((ROOT / "scenes" / "notes-arm.yaml").read_text())
    scene["arm"].update(max_joint_speed=60, max_joint_acceleration=120)  # slower than its defaults: some 12 s
    (tmp_path / "notes-arm.yaml").write_text(yaml.safe_dump(scene))
    result = run_scene(
        tmp_path / "notes-arm.yaml",
        tmp_path / "out",
        RunOptions(jobs=1, render=RenderOverrides(size=(640, 360), format="gif")),
    )
    gif = result.files["video"]
    frames = result.solution.trajectory.frames
    assert frames / 30.0 > 10.5  # the run is about 11 s long
    assert gif.stat().st_size < 1.5e6


@pytest.mark.slow
def test_render_out_keeps_the_run_video_byte_identical_and_writes_full_metadata(tmp_path):
    from typer.testing import CliRunner

    from armanim.cli import app

    runner = CliRunner()
    result = runner.invoke(
        app,
        [
            "run",
            str(ROOT / "scenes" / "planar-nlink.yaml"),
            "--out",
            str(tmp_path),
            "--size",
            "96x54",
            "--jobs",
            "1",
            "-q",
        ],
    )
    assert result.exit_code == 0, result.output
    run = tmp_path / "planar-nlink"
    before = {p.name: p.read_bytes() for p in run.iterdir()}
    other = tmp_path / "other"
    result = runner.invoke(
        app, ["render", str(run), "--out", str(other), "--size", "80x60", "--fps", "12", "--jobs", "1", "-q"]
    )
    assert result.exit_code == 0, result.output
    assert {p.name: p.read_bytes() for p in run.iterdir()} == before
    assert {p.name for p in other.iterdir()} == {
        "animation.mp4",
        "plot.png",
        "poster.png",
        ".armanim-run.json",
    }  # marked
    rows = len((run / "trajectory.csv").read_text().splitlines()) - 1
    reader = imageio_ffmpeg.read_frames(str(other / "animation.mp4"))
    meta = next(reader)
    reader.close()
    assert tuple(meta["size"]) == (80, 60)
    assert meta["fps"] == pytest.approx(12)
    from armanim.runs.resample import resampled_frames  # the run's seconds kept at 12 fps (issue 36)

    run_fps = json.loads((run / "summary.json").read_text())["fps"]
    assert imageio_ffmpeg.count_frames_and_secs(str(other / "animation.mp4"))[0] == resampled_frames(rows, run_fps, 12)


def test_quality_presets_set_size_and_fps_and_explicit_flags_win():
    from armanim.cli.options import render_overrides

    assert render_overrides(None, None, None, quality="high").given() == {"size": (1920, 1080), "fps": 60.0}
    assert render_overrides("640x360", None, None, quality="low").given() == {"size": (640, 360), "fps": 15.0}


def test_an_unknown_quality_is_a_usage_error():
    from armanim.cli.options import render_overrides
    from armanim.errors import UsageError

    with pytest.raises(UsageError, match="--quality"):
        render_overrides(None, None, None, quality="ultra")


def test_plot_labels_each_limit_with_its_joints_and_numbers_goals_from_0():
    from armanim.motion.trajectory import solve_trajectory
    from armanim.render.pictures.plot import plot_figure
    from armanim.scene import load_scene, scene_to_problem

    problem = scene_to_problem(load_scene(ROOT / "scenes" / "notes-arm.yaml").model)
    solution = solve_trajectory(problem)
    canvas = plot_figure(problem, solution.trajectory, solution.goals, title="t")
    texts = {t.get_text().strip() for ax in canvas.figure.axes for t in ax.texts}
    assert {"phi2 max 100", "phi2 min -100", "phi3, phi4 max 150", "goal 0"} <= texts
    assert not any("phi1" in t for t in texts)  # the unlimited base joint has no limit lines


# ----- captions ------------------------------------------------------------------------------


def _traj(phi, reached, mode=None):
    import types

    frames = len(phi)
    t = types.SimpleNamespace(
        phi=np.array(phi, float)[:, None],
        reached=np.array(reached),
        fps=2.0,
        frames=frames,
        goal=np.zeros(frames, int),
        distance=np.ones(frames),
    )
    if mode is not None:
        t.mode = np.array(mode)
    return t


def test_captions_say_moving_holding_stalled_planning_and_missed():
    import types

    from armanim.render.overlay.caption import frame_activity

    reached = types.SimpleNamespace(reached=True, first_frame=0, last_frame=5, reason=None)
    traj = _traj([0, 0.1, 0.2, 0.2, 0.2, 0.2], [False, False, True, True, True, True])
    assert frame_activity(traj, [reached]).tolist() == ["moving", "moving", "reached", "holding", "holding", "holding"]
    missed = types.SimpleNamespace(reached=False, first_frame=0, last_frame=5, reason="blocked_by_obstacle")
    traj = _traj([0, 0.1, 0.1, 0.1, 0.1, 0.1], [False] * 6, mode=["ik", "plan", "ik", "ik", "ik", "ik"])
    assert frame_activity(traj, [missed]).tolist() == [
        "moving",
        "planning",
        "stalled",
        "stalled",
        "missed: blocked by obstacle",
        "missed: blocked by obstacle",
    ]


def test_a_trajectory_without_mode_is_all_ik():
    from armanim.render.overlay.caption import frame_modes

    assert frame_modes(_traj([0, 1], [False, False])).tolist() == ["ik", "ik"]


@pytest.mark.parametrize("reached, shown", [((True, True), {"reached"}), ((True, False), {"reached", "missed"})])
def test_legend_lists_only_the_goal_outcomes_of_the_run(reached, shown):
    from types import SimpleNamespace

    from armanim.render.overlay.caption import goal_outcomes
    from armanim.render.pictures.canvas import SceneCanvas

    arm = Arm.from_names([2, 5, 5, 5])
    problem = Problem(
        arm=arm,
        half_width=0.25,
        home=np.zeros(4),
        limits=unlimited_limits(4),
        obstacles=Obstacles.none(),
        goals=(Goal(np.array([6.0, 0, 9]), hold=0.0), Goal(np.array([0.0, 6, 9]), hold=0.0)),
        solver=default_solver_settings(),
        fps=30.0,
    )
    reports = [SimpleNamespace(reached=r) for r in reached]
    scene = SceneCanvas(
        problem, default_render_settings(size=(640, 360)), title="t", picture="poster", outcomes=goal_outcomes(reports)
    )
    labels = [text.get_text() for text in scene.fig.legends[0].get_texts()]  # the legend as drawn
    assert {"reached", "missed"} & set(labels) == shown
    assert "obstacle" not in labels  # no obstacles in this scene


def test_the_longest_caption_fits_the_frame_at_960x540():
    # issue 50: a goal with an orientation at 960 x 540 cut the caption's last word to "reac"
    from armanim.render.pictures.canvas import FrameState, SceneCanvas

    arm = Arm.from_names([1.0, 1.0], axes=["z", "z"], direction="x")
    problem = Problem(
        arm=arm,
        half_width=0.05,
        home=np.zeros(2),
        limits=unlimited_limits(2),
        obstacles=Obstacles(np.zeros((0, 3)), np.zeros(0), np.zeros(0)),
        goals=(Goal(np.array([1.0, 1.0, 0.0]), 0.0),),
        solver=default_solver_settings(),
        fps=30.0,
    )
    caption = "t =  38.50 s   goal 1 (of 0-1)   distance    0.003   angle    0.0 deg   speed   0% (phi1)   following"
    pose = forward(arm, np.zeros(2))
    scene = SceneCanvas(problem, default_render_settings(size=(960, 540)), title="t", caption_template=caption)
    image = scene.draw(FrameState(pose, 0, np.zeros(1, dtype=int), caption)).copy()
    x, y = scene.layout.caption_xy
    band = image[int(y) : int(y) + 3 * scene.glyphs.height, :, :3].astype(float).sum(axis=-1)
    ink = np.nonzero((band < 200).any(axis=0))[0]  # dark text pixels (the box's edge is light)
    assert len(ink) and ink.max() < 960 - 8  # the whole caption inside the frame, its box's padding too
    assert len(caption) * scene.glyphs.advance <= 960 - 2 * x
