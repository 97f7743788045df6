"""Path goals in the pictures: ink where the tool has been along the path (pen down only), the path
ahead faintly, in video frames, the poster and the viewer's data (issue 39, item 5).

Frames are checked by their pixels at the path's projected points (the canvas's own camera),
against the same frame drawn without any path progress: what differs there is the ink.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from armanim.arm.kinematics import Arm, Pose, forward
from armanim.motion.problem import Goal, Problem
from armanim.motion.solution import GoalReport, Solution, Trajectory
from armanim.motion.toolpath import Piece, ToolPath
from armanim.output.solved import SolvedRun
from armanim.render.overlay.paths import SampledPath, path_progress
from armanim.render.paint.style import INK_COLOR
from armanim.scene import default_render_settings, default_solver_settings, unlimited_limits
from armanim.world.obstacles import Obstacles

SIZE = (640, 360)  # the ink 1.4 px wide
FRAMES = 20
A, B, C, D = (np.array(p, dtype=float) for p in ([14, -4, 3], [14, 12, 3], [14, 12, 11], [14, -4, 11]))
PATH = ToolPath((Piece.line(A, B), Piece.line(B, C, ink=False), Piece.line(C, D)))  # 16 down, 8 up, 16 down
INK_RGB = np.array(INK_COLOR) * 255


def path_problem(path: ToolPath = PATH) -> Problem:
    """The course notes' arm, a point goal, then a path goal starting at the path's start."""
    arm = Arm.from_names([2, 5, 5, 5], base=(5, 5, 0))
    goals = (Goal(np.array([6.0, 15, 9]), hold=0.0), Goal(path.start, hold=0.0, path=path, speed=1.0))
    return Problem(
        arm, 0.3, np.zeros(4), unlimited_limits(4), Obstacles.none(), goals, default_solver_settings(), fps=30.0
    )


def path_trajectory(problem: Problem, path_s: np.ndarray | None) -> Trajectory:
    """The arm turning a little (away from the path) over FRAMES frames: goal 0 for 5 frames,
    then goal 1, following its path (mode "path") from frame 8 on with ``path_s``."""
    phi = np.linspace(0.0, 1.0, FRAMES)[:, None] * np.radians([-60.0, 10.0, 10.0, 10.0])
    tip = forward(problem.arm, phi).tip
    goal = (np.arange(FRAMES) >= 5).astype(int)
    mode = np.where(np.arange(FRAMES) >= 8, "path", "ik")
    return Trajectory(
        phi=phi,
        tip=tip,
        goal=goal,
        distance=np.ones(FRAMES),
        clearance=np.full(FRAMES, np.inf),
        reached=np.zeros(FRAMES, dtype=bool),
        iterations=np.zeros(FRAMES, dtype=int),
        step_scale=np.zeros(FRAMES),
        fps=30.0,
        mode=mode,
        path_s=path_s,
    )


def linear_path_s(last: float) -> np.ndarray:
    """NaN off the path's frames, then 0 at frame 8 growing linearly to ``last`` at the last frame."""
    s = np.full(FRAMES, np.nan)
    s[8:] = np.linspace(0.0, last, FRAMES - 8)
    return s


def solved(problem: Problem, trajectory: Trajectory, meshes=None) -> SolvedRun:
    reports = (
        GoalReport(0, problem.goals[0].position, True, None, 5, 0, 4, 0.0, 5),
        GoalReport(1, problem.goals[1].position, True, None, 15, 5, FRAMES - 1, 0.0, 15),
    )
    return SolvedRun("paths", problem, Solution(trajectory, reports), meshes=meshes)


def settings():
    return default_render_settings(size=SIZE)


def frame_pixels(run: SolvedRun, f: int) -> tuple[np.ndarray, object]:
    """Frame ``f`` of ``run``'s video as (H, W, 3) ints, and its canvas's camera."""
    from armanim.render.pictures.canvas import SceneCanvas
    from armanim.render.video.segment import frame_drawer

    pose = forward(run.problem.arm, run.trajectory.phi[f : f + 1])
    image = frame_drawer(run, settings())(f, Pose(pose.points[0], pose.frames[0]))[..., :3].astype(int).copy()
    extent = forward(run.problem.arm, run.trajectory.phi).points  # as the video frames it: the same camera
    return image, SceneCanvas(run.problem, settings(), title="view", meshes=run.meshes, extent=extent).view


def inked(image: np.ndarray, reference: np.ndarray, view, points: np.ndarray) -> np.ndarray:
    """(k,) bool: within a pixel of each world point, some pixel of ``image`` is ink (within 60 of
    its colour) and at least 40 nearer to it than the same pixel of ``reference``."""
    h = image.shape[0]
    out = []
    for x, y, _ in view.project(points):
        r, c = int(round(h - y)), int(round(x))
        now = np.linalg.norm(image[r - 1 : r + 2, c - 1 : c + 2] - INK_RGB, axis=-1)
        before = np.linalg.norm(reference[r - 1 : r + 2, c - 1 : c + 2] - INK_RGB, axis=-1)
        out.append(bool(np.any((now < 60) & (before > now + 40))))
    return np.array(out)


def along(a: np.ndarray, b: np.ndarray, lo: float, hi: float, k: int = 9) -> np.ndarray:
    """(k, 3) points from ``lo`` to ``hi`` of the way from a to b."""
    return a + np.linspace(lo, hi, k)[:, None] * (b - a)


# ---- the pure parts ---------------------------------------------------------------------


def test_progress_is_the_farthest_path_s_of_the_goal_s_frames_so_far():
    rng = np.random.default_rng(3)
    goal = np.sort(rng.integers(0, 4, 60))
    path_s = np.where(rng.random(60) < 0.7, rng.random(60) * 5, np.nan)
    done = path_progress(goal, path_s, 4)
    for f in range(60):  # the oracle: a plain loop over the frames so far
        for g in range(4):
            seen = [path_s[k] for k in range(f + 1) if goal[k] == g and np.isfinite(path_s[k])]
            assert done[f, g] == (max(seen) if seen else 0.0)
    assert np.all(np.diff(done, axis=0) >= 0)  # ink never shrinks
    assert not path_progress(goal, None, 4).any()


def test_between_is_the_pen_down_path_between_two_arc_lengths():
    arc = Piece.arc(np.zeros(3), np.array([1.0, 0, 0]), np.pi, np.array([0, 0, 1.0]))
    path = ToolPath(
        (arc, Piece.line(arc.end, arc.end + [0, -1, 0], ink=False), Piece.line(arc.end + [0, -1, 0], [1.0, -1, 0]))
    )
    sampled = SampledPath.of(0, path, 0.01)
    for lo, hi in ((0.0, 1.0), (0.5, 4.0), (2.0, 6.0), (3.5, 4.5), (0.0, np.inf)):
        poly = sampled.between(lo, hi)
        rows = poly[np.isfinite(poly[:, 0])]
        s, d = path.nearest(rows)
        assert d.max() < 1e-3  # on the path (arc chords within 0.01^2/8)
        assert np.all(path.inked(s) | np.isclose(s, path.corners[1]) | np.isclose(s, path.corners[2]))  # pen down
        assert s.min() == pytest.approx(max(lo, 0.0) if lo < np.pi or lo > np.pi + 1 else np.pi + 1, abs=1e-6)
        want_hi = min(hi, path.length)
        if not (np.pi < want_hi < np.pi + 1):
            assert s.max() == pytest.approx(want_hi, abs=1e-6)
        breaks = np.isnan(poly[:, 0]).sum()
        assert breaks == (1 if lo < np.pi and hi > np.pi + 1 else 0)  # one gap: the pen-up piece


def pen_down_between(sampled: SampledPath, lo: float, hi: float) -> np.ndarray:
    """The oracle of :meth:`SampledPath.between`: its rows built from the samples at every call (each
    run's start, each kept segment's end, a NaN row between runs), as before the whole path's rows were
    kept."""
    s, d = sampled.s, sampled.points.shape[1]
    kept = np.flatnonzero(sampled.ink & (s[:-1] < hi) & (s[1:] > lo))
    if hi <= lo or not len(kept):
        return np.zeros((0, d))
    rows: list[np.ndarray] = []
    for n, k in enumerate(kept):
        if n == 0 or kept[n - 1] != k - 1:
            if rows:
                rows.append(np.full((1, d), np.nan))
            rows.append(sampled.at(np.maximum(s[k : k + 1], lo)))
        rows.append(sampled.at(np.minimum(s[k + 1 : k + 2], hi)))
    return np.concatenate(rows)


def test_between_keeps_the_rows_of_the_oracle_to_the_bit():
    from armanim.scene.convert import tool_path
    from armanim.scene.models import PathModel

    text = {"string": "armanim", "origin": [0.55, 0.23, 0.36], "height": 0.08, "right": [0, -1, 0], "up": [0, 0, 1]}
    path = tool_path(PathModel(text=text))
    sampled = SampledPath.of(0, path, 0.002)
    assert (~sampled.ink).any() and len(sampled.s) > 100  # pen-up travel between strokes, arcs split
    rng = np.random.default_rng(7)
    s = sampled.s
    ends = np.concatenate([s, s[::7] + 1e-12, rng.random(300) * s[-1] * 1.1, [-1.0, 0.0, np.inf, np.nan]])
    for lo in [0.0, -1.0, *rng.choice(ends, 60)]:
        for hi in [np.inf, *rng.choice(ends, 25)]:
            want = pen_down_between(sampled, lo, hi)
            got = sampled.between(lo, hi)
            assert got.shape == want.shape and np.array_equal(got, want, equal_nan=True), (lo, hi)


# ---- video frames -------------------------------------------------------------------------


def test_ink_only_where_the_tool_has_been_and_never_on_pen_up_travel():
    problem = path_problem()
    halfway = solved(problem, path_trajectory(problem, linear_path_s(8.0)))  # half the first piece
    bare = solved(problem, path_trajectory(problem, None))
    image, view = frame_pixels(halfway, FRAMES - 1)
    reference, _ = frame_pixels(bare, FRAMES - 1)  # (the path's start is under the goal's marker and number)
    assert inked(image, reference, view, along(A, B, 0.3, 0.45)).all()
    assert not inked(image, reference, view, along(A, B, 0.6, 0.95)).any()  # not reached: faint at most
    assert not inked(image, reference, view, along(C, D, 0.05, 0.95)).any()
    early, _ = frame_pixels(halfway, 16)  # path_s 5.8 at frame 16: a third of the first piece
    assert inked(early, reference, view, along(A, B, 0.3, 0.34, 3)).all()
    assert not inked(early, reference, view, along(A, B, 0.45, 0.6)).any()

    whole = solved(problem, path_trajectory(problem, linear_path_s(PATH.length)))
    image, _ = frame_pixels(whole, FRAMES - 1)
    assert inked(image, reference, view, along(A, B, 0.3, 0.95)).all()
    assert inked(image, reference, view, along(C, D, 0.05, 0.95)).all()
    assert not inked(image, reference, view, along(B, C, 0.2, 0.8)).any()  # the pen was up


def test_the_path_ahead_is_faint_and_only_while_its_goal_is_the_frame_s():
    problem = path_problem()
    run = solved(problem, path_trajectory(problem, linear_path_s(5.0)))
    bare = solved(
        dataclasses.replace(problem, goals=(problem.goals[0], dataclasses.replace(problem.goals[1], path=None))),
        path_trajectory(problem, None),
    )
    image, view = frame_pixels(run, FRAMES - 1)
    reference, _ = frame_pixels(bare, FRAMES - 1)
    h = image.shape[0]
    ahead = along(C, D, 0.1, 0.9, 41)
    xy = view.project(ahead)
    changed = [
        np.abs(
            image[int(round(h - y)) - 1 : int(round(h - y)) + 2, int(round(x)) - 1 : int(round(x)) + 2]
            - reference[int(round(h - y)) - 1 : int(round(h - y)) + 2, int(round(x)) - 1 : int(round(x)) + 2]
        ).max()
        for x, y, _ in xy
    ]
    assert np.mean(np.array(changed) > 20) > 0.4  # dashed: drawn along much of it ...
    assert not inked(image, reference, view, ahead).any()  # ... and never as dark as ink
    before, _ = frame_pixels(run, 2)  # goal 0's frame: no path ahead yet, and no ink
    reference_before, _ = frame_pixels(bare, 2)
    assert np.array_equal(before[40:-40], reference_before[40:-40])  # (the legend differs)


def test_ink_is_drawn_on_furniture_not_hidden_by_it():
    from types import SimpleNamespace

    from armanim.arm.visuals import placed_meshes
    from armanim.scene.looks import furniture_meshes

    # the board behind the path (the camera is on the +x side), its face 0.05 from it
    board = SimpleNamespace(
        box=SimpleNamespace(center=[13.45, 4.0, 7.0], size=[1.0, 20.0, 12.0], rpy=[0, 0, 0]), color=(0.96, 0.96, 0.94)
    )
    meshes = placed_meshes(furniture_meshes([board]), [-1], [np.eye(4)])
    problem = path_problem()
    run = solved(problem, path_trajectory(problem, linear_path_s(PATH.length)), meshes)
    bare = solved(problem, path_trajectory(problem, None), meshes)
    image, view = frame_pixels(run, FRAMES - 1)
    reference, _ = frame_pixels(bare, FRAMES - 1)
    x, y, _ = view.project(0.5 * (B + C))
    assert reference[int(round(image.shape[0] - y)), int(round(x))].sum() < 3 * 230  # the (shaded) board is drawn there
    assert inked(image, reference, view, along(A, B, 0.3, 0.95)).all()
    assert not inked(image, reference, view, along(B, C, 0.2, 0.8)).any()


# ---- the poster -----------------------------------------------------------------------------


def poster_pixels(run: SolvedRun, tmp_path, name: str) -> np.ndarray:
    from PIL import Image

    from armanim.render.pictures.poster import render_poster
    from armanim.render.settings import OutputOptions

    render_poster(run, OutputOptions(settings()), tmp_path / name)
    return np.asarray(Image.open(tmp_path / name).convert("RGB")).astype(int)


def test_the_poster_has_the_run_s_whole_ink_and_nothing_faint(tmp_path):
    problem = path_problem()
    blocked = solved(problem, path_trajectory(problem, linear_path_s(30.0)))  # stopped 6 into the last piece
    bare = solved(problem, path_trajectory(problem, None))
    image, reference = poster_pixels(blocked, tmp_path, "ink.png"), poster_pixels(bare, tmp_path, "bare.png")
    _, view = frame_pixels(blocked, 0)
    assert inked(image, reference, view, along(A, B, 0.3, 0.95)).all()
    assert inked(image, reference, view, along(C, D, 0.05, 0.35)).all()
    h = image.shape[0]
    for x, y, _ in view.project(np.vstack([along(C, D, 0.5, 0.95), along(B, C, 0.2, 0.8)])):  # not done, pen up
        r, c = int(round(h - y)), int(round(x))
        assert np.array_equal(image[r - 1 : r + 2, c - 1 : c + 2], reference[r - 1 : r + 2, c - 1 : c + 2])


# ---- the viewer's data ------------------------------------------------------------------------


def test_the_viewer_data_has_the_paths_and_the_path_s_of_every_frame():
    from armanim.render.viewer.data import viewer_data

    arc = Piece.arc(np.array([14.0, 3, 7]), np.array([14.0, 3, 10]), np.pi, np.array([1.0, 0, 0]))
    path = ToolPath((*PATH.pieces, Piece.line(D, arc.start, ink=False), arc))
    problem = path_problem(path)
    path_s = linear_path_s(path.length)
    data = viewer_data(
        problem,
        path_trajectory(problem, path_s),
        solved(problem, path_trajectory(problem, None)).reports,
        settings(),
        title="paths",
    )
    entry = data["paths"]
    (g,) = entry["goals"]
    assert g["goal"] == 1
    s, points = np.array(g["s"]), np.array(g["points"]).reshape(-1, 3)
    assert len(s) == len(points) == len(g["ink"]) + 1
    step = 10.0 ** -data["decimals"]
    assert np.isin(np.round(path.corners, data["decimals"]), s).all()  # every corner is a sample
    assert np.abs(points - path.points(s)).max() <= step  # the samples are on the path (rounded)
    size = float(np.max(np.subtract(data["view"]["box"][1], data["view"]["box"][0])))
    assert path.distance(0.5 * (points[1:] + points[:-1])).max() <= size / 4000 + step  # arcs as close chords
    assert g["ink"] == [int(b) for b in path.inked(0.5 * (s[1:] + s[:-1]))]
    assert 0 in g["ink"] and 1 in g["ink"]
    assert np.allclose(np.abs(g["normal"]), [1, 0, 0])  # the path's plane: x = 14
    assert len(entry["path_s"]) == FRAMES
    assert entry["path_s"][:8] == [None] * 8
    assert entry["path_s"][8:] == pytest.approx(path_s[8:], abs=step)
    assert entry["width"] > 0 and entry["ink"].startswith("#")


def test_a_run_without_path_goals_has_no_path_data():
    from armanim.render.viewer.data import viewer_data

    problem = dataclasses.replace(path_problem(), goals=(path_problem().goals[0],))
    trajectory = dataclasses.replace(path_trajectory(problem, None), goal=np.zeros(FRAMES, dtype=int))
    assert "paths" not in viewer_data(problem, trajectory, (), settings(), title="plain")


def test_the_arm_in_front_of_the_ink_covers_it():
    problem = path_problem()
    _, view = frame_pixels(solved(problem, path_trajectory(problem, None)), 0)
    toward = np.linalg.solve(view.linear, [0.0, 0.0, 1.0])  # world direction of growing nearness
    across = np.linalg.solve(view.linear, [1.0, 0.0, 0.0])
    toward, across = toward / np.linalg.norm(toward), across / np.linalg.norm(across)
    behind = (
        np.array([5.0, 5, 9.5]) - 3 * toward
    )  # behind the arm's column (all its angles 0: straight up), between joints
    line = ToolPath((Piece.line(behind - 5 * across, behind + 5 * across),))
    problem = path_problem(line)
    still = np.zeros((FRAMES, 4))

    def run(path_s):
        t = path_trajectory(problem, path_s)
        return solved(problem, dataclasses.replace(t, phi=still, tip=forward(problem.arm, still).tip))

    image, view = frame_pixels(run(linear_path_s(line.length)), FRAMES - 1)
    reference, _ = frame_pixels(
        run(None), 2
    )  # the arm still, goal 0's: neither ink nor the path ahead (drawn over all)
    a, b = line.start, line.end
    assert inked(image, reference, view, np.vstack([along(a, b, 0.75, 0.95, 4)])).all()
    assert not inked(
        image, reference, view, along(behind, behind + 0.1 * across, 0, 1, 3)
    ).any()  # the column is in front
