"""Renderer and encoder: videos checked by metadata, frames by projected pixels (no goldens)."""

from __future__ import annotations

import dataclasses
import subprocess
import sys

import imageio_ffmpeg
import numpy as np
import pytest

from armanim.arm.kinematics import Arm, forward
from armanim.errors import RenderError
from armanim.motion.problem import Goal, Problem
from armanim.motion.solution import GoalReport, Solution, Trajectory
from armanim.output.solved import SolvedRun
from armanim.render.settings import OutputOptions
from armanim.scene import default_render_settings, default_solver_settings, unlimited_limits
from armanim.world.obstacles import Obstacles

FRAMES = 12
SIZE = (160, 120)


def make_problem(half_width: float = 0.3, obstacles: bool = True) -> Problem:
    """The course notes' arm with two goals and (optionally) one obstacle."""
    arm = Arm.from_names([2, 5, 5, 5], base=(5, 5, 0))
    obs = Obstacles(np.array([[12.0, 9, 8]]), np.array([2.0]), np.array([2.0])) if obstacles else Obstacles.none()
    goals = (Goal(np.array([14.0, 5, 6]), hold=0.0), Goal(np.array([6.0, 15, 9]), hold=0.0))
    return Problem(arm, half_width, np.zeros(4), unlimited_limits(4), obs, goals, default_solver_settings(), fps=30.0)


def make_trajectory(problem: Problem, frames: int = FRAMES, fps: float = 30.0) -> Trajectory:
    """A synthetic trajectory: joint angles moving linearly, goal 0 then goal 1."""
    phi = np.linspace(0.0, 1.0, frames)[:, None] * np.radians([40.0, 30.0, 50.0, 20.0])
    tip = forward(problem.arm, phi).tip
    goal = (np.arange(frames) >= frames // 2).astype(int)
    targets = np.array([g.position for g in problem.goals])[goal]
    distance = np.linalg.norm(tip - targets, axis=1)
    return Trajectory(
        phi=phi,
        tip=tip,
        goal=goal,
        distance=distance,
        clearance=np.full(frames, np.inf),
        reached=np.zeros(frames, dtype=bool),
        iterations=np.zeros(frames, dtype=int),
        step_scale=np.zeros(frames),
        fps=fps,
    )


def make_reports(frames: int = FRAMES) -> tuple[GoalReport, ...]:
    half = frames // 2
    return (
        GoalReport(0, np.array([14.0, 5, 6]), True, None, half, 0, half - 1, 0.0, half),
        GoalReport(1, np.array([6.0, 15, 9]), False, "stalled", frames - half, half, frames - 1, 3.0, 6),
    )


def solved(problem: Problem, traj: Trajectory, reports, title: str = "t", fps: float | None = None) -> SolvedRun:
    """The run a writer takes, named ``title``, its frames at ``fps`` (default: the trajectory's)."""
    traj = traj if fps is None else dataclasses.replace(traj, fps=float(fps))
    return SolvedRun(title, problem, Solution(traj, tuple(reports)))


def options(jobs: int | None = None, **settings) -> OutputOptions:
    """The default render settings with ``settings`` changed, drawn by ``jobs`` workers."""
    return OutputOptions(default_render_settings(**settings), jobs=jobs)


def video_meta(path) -> dict:
    reader = imageio_ffmpeg.read_frames(str(path))
    meta = next(reader)
    reader.close()
    return meta


@pytest.fixture
def scene():
    problem = make_problem()
    return problem, make_trajectory(problem), make_reports()


def test_mp4_has_one_frame_per_row_at_the_settings_fps_and_size(scene, tmp_path):
    from armanim.render.video.movie import render_video

    problem, traj, reports = scene
    out = tmp_path / "animation.mp4"
    seen = []
    render_video(solved(problem, traj, reports, fps=30), options(size=SIZE, jobs=1), out, progress=seen.append)
    frames, secs = imageio_ffmpeg.count_frames_and_secs(str(out))
    meta = video_meta(out)
    assert frames == FRAMES
    assert meta["fps"] == pytest.approx(30.0)
    assert tuple(meta["size"]) == SIZE
    assert meta["codec"].startswith("h264") and meta["pix_fmt"].startswith("yuv420p")
    assert seen[-1] == FRAMES
    assert [p.name for p in tmp_path.iterdir()] == ["animation.mp4"]  # no temporary files left


def test_two_jobs_give_the_same_video_as_one(scene, tmp_path, monkeypatch):
    from armanim.render.video import movie as video

    monkeypatch.setattr(video, "MIN_FRAMES_PER_JOB", 4)
    problem, traj, reports = scene
    out = tmp_path / "animation.mp4"
    seen = []
    video.render_video(solved(problem, traj, reports, fps=24), options(size=SIZE, jobs=2), out, progress=seen.append)
    frames, _ = imageio_ffmpeg.count_frames_and_secs(str(out))
    meta = video_meta(out)
    assert frames == FRAMES
    assert meta["fps"] == pytest.approx(24.0)
    assert tuple(meta["size"]) == SIZE
    assert max(seen) == FRAMES
    assert [p.name for p in tmp_path.iterdir()] == ["animation.mp4"]


def test_odd_sizes_are_padded_to_even_for_mp4(scene, tmp_path):
    from armanim.render.video.movie import render_video

    problem, traj, reports = scene
    out = tmp_path / "odd.mp4"
    render_video(solved(problem, traj, reports), options(size=(161, 121), jobs=1), out)
    assert tuple(video_meta(out)["size"]) == (162, 122)
    assert imageio_ffmpeg.count_frames_and_secs(str(out))[0] == FRAMES


@pytest.mark.parametrize("size", [(16, 16), (48, 27), (200, 16), (16, 200)])
def test_the_smallest_frames_are_drawn(scene, tmp_path, size):
    """Campaign 9: ``run --size 16x16`` (the least size the scene takes) ended in matplotlib's
    RuntimeError "FT_Set_Char_Size ... invalid ppem value": the frame's dpi made the caption's glyphs
    less than half a pixel. Every size from 16 a side is drawn, its text at least :data:`LEAST_DPI`."""
    from armanim.render.paint.scenery import LEAST_DPI, frame_layout
    from armanim.render.video.movie import render_video

    problem, traj, reports = scene
    out = tmp_path / "small.mp4"
    render_video(solved(problem, traj, reports), options(size=size, jobs=1), out)
    assert imageio_ffmpeg.count_frames_and_secs(str(out))[0] == FRAMES
    layout = frame_layout(*size)
    assert layout.dpi == LEAST_DPI and layout.scene[1] < layout.scene[3] <= layout.caption_xy[1] < size[1]


def test_gif_frames_have_the_settings_duration(scene, tmp_path):
    from PIL import Image

    from armanim.render.video.movie import render_video

    problem, traj, reports = scene
    out = tmp_path / "animation.gif"
    render_video(solved(problem, traj, reports, fps=20), options(size=(161, 121), format="gif"), out)
    with Image.open(out) as im:
        assert im.size == (161, 121)
        durations = []
        for i in range(im.n_frames):
            im.seek(i)
            durations.append(im.info["duration"])
    assert len(durations) == FRAMES
    assert all(d == 50 for d in durations)  # 1/20 s, exactly representable in GIF's 1/100 s


def test_gif_total_duration_at_30_fps(scene, tmp_path):
    from PIL import Image

    from armanim.render.video.movie import render_video

    problem, traj, reports = scene
    out = tmp_path / "animation.gif"
    render_video(solved(problem, traj, reports, fps=30), options(size=SIZE, format="gif"), out)
    with Image.open(out) as im:
        durations = []
        for i in range(im.n_frames):
            im.seek(i)
            durations.append(im.info["duration"])
    assert set(durations) <= {30, 40}  # 1/30 s rounded to GIF's 1/100 s, without drift
    assert sum(durations) == pytest.approx(1000 * FRAMES / 30, abs=10)


def test_ffmpeg_failure_raises_render_error_and_leaves_no_file(scene, tmp_path, monkeypatch):
    from armanim.render.video import encode
    from armanim.render.video.movie import render_video

    monkeypatch.setattr(encode, "MP4_CODEC", "no_such_codec")
    problem, traj, reports = scene
    out = tmp_path / "animation.mp4"
    with pytest.raises(RenderError) as info:
        render_video(solved(problem, traj, reports), options(size=SIZE, jobs=1), out)
    assert "no_such_codec" in str(info.value)  # ffmpeg's own words are quoted
    assert list(tmp_path.iterdir()) == []


def test_a_failing_join_raises_render_error(tmp_path):
    from armanim.render.video.encode import concat_segments

    with pytest.raises(RenderError):
        concat_segments([tmp_path / "missing.mp4"], tmp_path / "out.mp4", "mp4")


def test_the_tip_is_drawn_in_the_arm_colour():
    from armanim.render.overlay.caption import PENDING
    from armanim.render.paint.style import ARM_COLOR
    from armanim.render.pictures.canvas import FrameState, SceneCanvas

    problem = make_problem(half_width=1.0, obstacles=False)
    phi = np.radians([20.0, 10.0, 20.0, 10.0])
    pose = forward(problem.arm, phi)
    scene = SceneCanvas(problem, default_render_settings(size=(320, 240)), title="tip")
    state = FrameState(pose, 0, np.full(len(problem.goals), PENDING), "")
    rgba = scene.draw(state).copy()
    px, py, _ = scene.view.project(pose.tip)
    pixel = rgba[int(rgba.shape[0] - py), int(px), :3].astype(float)
    arm = np.asarray(ARM_COLOR)
    cosine = pixel @ arm / (np.linalg.norm(pixel) * np.linalg.norm(arm))
    assert cosine > 0.98, pixel  # a shade of the arm colour ...
    assert pixel.max() < 235  # ... and not the white background


def test_render_pose_png_has_the_settings_size(tmp_path):
    from PIL import Image

    from armanim.render.pictures.pose import render_pose_png

    out = tmp_path / "pose.png"
    render_pose_png(
        make_problem(), np.radians([10, 20, 30, 40]), default_render_settings(size=(201, 149)), out, title="fk"
    )
    with Image.open(out) as im:
        assert im.size == (201, 149)


def test_plot_run_writes_a_png(scene, tmp_path):
    from PIL import Image

    from armanim.render.pictures.plot import PLOT_SIZE, plot_run

    problem, traj, reports = scene
    out = tmp_path / "plot.png"
    plot_run(solved(problem, traj, reports, "run"), options(), out)
    with Image.open(out) as im:
        assert im.size == PLOT_SIZE


def test_auto_bounds_hold_every_reachable_point_obstacle_and_goal():
    from armanim.render.camera.bounds import auto_bounds

    problem = make_problem()
    box = auto_bounds(problem)
    rng = np.random.default_rng(0)
    points = forward(problem.arm, rng.uniform(-np.pi, np.pi, (500, 4))).points.reshape(-1, 3)
    assert np.all(points >= box[:, 0]) and np.all(points <= box[:, 1])
    obs = problem.obstacles
    assert np.all(obs.centers - obs.radii[:, None] >= box[:, 0])
    assert np.all(obs.centers + obs.radii[:, None] <= box[:, 1])


def test_importing_render_does_not_load_matplotlib():
    code = "import sys, armanim.render; assert 'matplotlib' not in sys.modules"
    subprocess.run([sys.executable, "-c", code], check=True)


@pytest.mark.slow
def test_a_solved_run_renders_at_full_size(tmp_path):
    from armanim.motion.trajectory import solve_trajectory
    from armanim.render.video.movie import render_video

    problem = make_problem()
    solution = solve_trajectory(problem)
    out = tmp_path / "animation.mp4"
    render_video(SolvedRun("solved", problem, solution), options(size=(640, 360), jobs=2), out)
    assert imageio_ffmpeg.count_frames_and_secs(str(out))[0] == solution.trajectory.frames
    assert tuple(video_meta(out)["size"]) == (640, 360)


def test_a_path_goal_s_frames_say_following_not_reached():
    # issue 50: the caption said "reached" the whole time the pen wrote (the CSV's reached is 1 on
    # path frames: the tool within tolerance of the path)
    import types

    from armanim.render.overlay.caption import frame_activity

    phi = np.array([[0.0], [0.1], [0.2], [0.3], [0.3], [0.3]])
    t = types.SimpleNamespace(
        phi=phi,
        reached=np.array([False, True, True, True, True, True]),
        frames=6,
        fps=30.0,
        mode=np.array(["ik", "ik", "path", "path", "path", "ik"]),
    )
    report = types.SimpleNamespace(reached=True, first_frame=0, last_frame=5)
    assert frame_activity(t, [report]).tolist() == ["moving", "reached", "following", "following", "holding", "holding"]
