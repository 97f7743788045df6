"""Time has one owner: the scene's seconds. The motion is solved at the scene's own
``render.fps`` and shown at any other rate (``--fps``, ``--quality``) as the same motion."""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from invariants import assert_trajectory_invariants, small_planning_budget
from strategies import cluttered_problems

from armanim.arm.geometry import wrap_angle
from armanim.arm.kinematics import Arm, forward
from armanim.motion.problem import Goal, Problem
from armanim.motion.resample import at_fps, resample, sample_times
from armanim.motion.solution import GoalReport, Solution, Trajectory
from armanim.motion.solvers.barrier import pose_clearance
from armanim.motion.trajectory import solve_trajectory
from armanim.output.csvfile import read_trajectory_csv
from armanim.runs.reload import load_run
from armanim.scene import default_solver_settings, load_scene, scene_to_problem, unlimited_limits
from armanim.world.obstacles import Obstacles

SCENE = """\
version: 1
name: held
arm: {links: [2, 5, 5, 5]}
goals:
  - {position: [6, 0, 10], hold: 2}
  - [0, 6, 10]
render: {fps: 10, size: [64, 48]}
"""


def _held_frames(summary: dict, goal: int) -> int:
    g = summary["goals"][goal]  # its frames: (frame 0, for goal 0), the motion, then the hold
    return g["last_frame"] - g["first_frame"] + 1 - g["frames"] - (goal == 0)


def test_run_fps_override_holds_for_the_scenes_seconds(cli, tmp_path):
    scene = tmp_path / "held.yaml"
    scene.write_text(SCENE, encoding="utf-8")
    for fps in (10, 40):
        result = cli("run", scene, "--out", tmp_path / f"at{fps}", "--no-video", "--quiet", "--fps", fps)
        assert result.exit_code == 0, result.output
        table = read_trajectory_csv(tmp_path / f"at{fps}" / "held" / "trajectory.csv")
        np.testing.assert_allclose(table.column("time_s"), np.arange(len(table.data)) / fps)
        summary = json.loads((tmp_path / f"at{fps}" / "held" / "summary.json").read_text())
        assert _held_frames(summary, 0) == 2 * fps  # two seconds, whatever the fps
        last = summary["goals"][0]["last_frame"]
        assert np.all(table.column("reached")[last - 2 * fps: last + 1] == 1)
        assert summary["fps"] == fps and summary["totals"]["duration_s"] == len(table.data) / fps


def test_a_finished_run_keeps_its_own_clock(cli, tmp_path):
    # solved at --fps 40 on a 10 fps scene: reading it back must not retime it at 10 fps
    scene = tmp_path / "held.yaml"
    scene.write_text(SCENE, encoding="utf-8")
    assert cli("run", scene, "--out", tmp_path, "--no-video", "--quiet", "--fps", "40").exit_code == 0
    run = load_run(tmp_path / "held")
    table = read_trajectory_csv(tmp_path / "held" / "trajectory.csv")
    assert run.solution.trajectory.fps == 40
    np.testing.assert_array_equal(run.solution.trajectory.time, table.column("time_s"))


# ---------------------------------------------------------------- one motion at any fps (issue 18)

ROOT = Path(__file__).resolve().parent.parent


def _goal_seconds(summary: dict) -> list[float]:
    return [g["frames"] / summary["fps"] for g in summary["goals"]]


@pytest.mark.parametrize("name", ["notes-arm", "breen-gradient"])
def test_a_scene_moves_the_same_in_seconds_at_15_30_and_60_fps(cli, tmp_path, name):
    # before: the same solver frames at every fps, so 60 fps showed the arm twice as fast as 30
    summaries = {}
    for fps in (15, 30, 60):
        out = tmp_path / f"at{fps}"
        result = cli("run", ROOT / "scenes" / f"{name}.yaml", "--out", out, "--no-video", "--quiet", "--fps", fps)
        assert result.exit_code == 0, result.output
        summaries[fps] = json.loads((out / name / "summary.json").read_text())
        table = read_trajectory_csv(out / name / "trajectory.csv")
        assert len(table.data) == summaries[fps]["totals"]["frames"]
    base = _goal_seconds(summaries[30])
    for fps in (15, 60):
        for k, (seconds, expected) in enumerate(zip(_goal_seconds(summaries[fps]), base)):
            assert abs(seconds - expected) <= max(0.05 * expected, 2 / fps), (name, fps, k, seconds, expected)
        assert [g["reached"] for g in summaries[fps]["goals"]] == [g["reached"] for g in summaries[30]["goals"]]
        duration = summaries[fps]["totals"]["duration_s"]
        assert abs(duration - summaries[30]["totals"]["duration_s"]) <= 0.05 * duration


@given(steps=st.integers(1, 5000), rates=st.sampled_from([(30.0, 24.0), (30.0, 7.0), (24.0, 30.0), (25.0, 60.0), (30.0, 90.0), (60.0, 15.0)]))
def test_the_samples_that_fall_on_solved_frames_are_those_frames_exactly(steps, rates):
    """The last sample is the last solved frame, bit for bit (at 108.99999999999999 a frame's
    iterations were dropped: hypothesis found 1937 of 1952 at 24 fps), and so is every sample
    that lands on a whole solved frame."""
    times = sample_times(steps, *rates)
    assert times[-1] == steps
    count = len(times)
    on_frames = [k for k in range(1, count + 1) if k * steps % count == 0]
    assert all(times[k - 1] == k * steps // count for k in on_frames)
    assert np.all(np.diff(times) > 0) and np.diff(times, prepend=0).max() <= steps / count + 1e-12


@settings(max_examples=10, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])  # as the suite's profile
@given(problem=cluttered_problems(max_goals=2), fps=st.sampled_from([7.0, 15.0, 24.0, 60.0, 90.0]))
def test_every_resampled_frame_keeps_the_guarantees_at_that_rate(problem, fps):
    with small_planning_budget():
        solved = solve_trajectory(problem)
    resampled = resample(problem, solved, fps)
    shown = at_fps(problem, fps)
    # clearance, limits, holds, reports; the joint step at most the larger of one frame at this rate
    # and one solved step (the fallback's bound) ...
    loose = max(shown.solver.max_joint_step, problem.solver.max_joint_step)
    assert_trajectory_invariants(replace(shown, solver=replace(shown.solver, max_joint_step=loose)), resampled)
    # ... and within the speed at this rate, but where a frame shows a solved pose instead of an
    # in-between one whose chord would cut a surface (docs/scene-format.md, "Frames and goals")
    phi = resampled.trajectory.phi
    fast = np.nonzero(np.abs(wrap_angle(np.diff(phi, axis=0))).max(axis=1, initial=0) > shown.solver.max_joint_step + 1e-9)[0]
    solved_poses = {tuple(row) for row in solved.trajectory.phi}
    assert all(tuple(phi[k]) in solved_poses or tuple(phi[k + 1]) in solved_poses for k in fast)
    assert [g.reached for g in resampled.goals] == [g.reached for g in solved.goals]
    assert [g.reason for g in resampled.goals] == [g.reason for g in solved.goals]
    assert resampled.trajectory.iterations.sum() == solved.trajectory.iterations.sum()
    for g_new, g_old in zip(resampled.goals, solved.goals):  # the same seconds of motion, to a frame
        assert abs(g_new.frames / fps - g_old.frames / problem.fps) <= 1 / fps + 1e-9


def test_at_the_scenes_own_fps_nothing_is_resampled():
    problem = scene_to_problem(load_scene(ROOT / "scenes" / "notes-arm.yaml").model)
    solved = solve_trajectory(problem)
    assert resample(problem, solved, problem.fps) is solved and at_fps(problem, problem.fps) is problem


def test_an_in_between_pose_that_would_cut_an_obstacle_is_moved_back():
    # one link sweeping +-60 degrees past a sphere in a single solved frame: the joint-space
    # chord passes through the sphere at 0 degrees, both solved poses are clear of it
    arm = Arm.from_names([2.0], axes=["z"], direction="x")
    problem = Problem(arm=arm, half_width=0.05, home=np.radians([-60.0]), limits=unlimited_limits(1),
                      obstacles=Obstacles(np.array([[1.5, 0.0, 0.0]]), np.array([0.3]), np.array([0.3])),
                      goals=(Goal(np.array([1.0, 1.732, 0.0]), 0.0),), solver=default_solver_settings(
                          max_joint_step=np.radians(120.0)), fps=10.0)
    phi = np.radians([[-60.0], [60.0]])
    pose = forward(arm, phi)
    distance = np.linalg.norm(pose.tip - problem.goals[0].position, axis=1)
    trajectory = Trajectory(phi=phi, tip=pose.tip, goal=np.zeros(2, dtype=int), distance=distance,
                            clearance=pose_clearance(problem, phi), reached=distance < 0.01,
                            iterations=np.array([0, 1]), step_scale=np.array([0.0, 1.0]), fps=10.0)
    assert trajectory.clearance.min() > problem.solver.clearance
    report = GoalReport(index=0, position=problem.goals[0].position, reached=True, reason=None, frames=1,
                        first_frame=0, last_frame=1, final_distance=float(distance[-1]), iterations=1,
                        newton_iterations=0, planning=None)
    solved = Solution(trajectory, (report,))
    straight = np.radians(np.linspace(-60.0, 60.0, 11))
    assert pose_clearance(problem, straight[:, None]).min() < 0  # plain interpolation would cut the sphere
    resampled = resample(problem, solved, 100.0)
    shown = at_fps(problem, 100.0)
    solved_step = replace(shown, solver=replace(shown.solver, max_joint_step=problem.solver.max_joint_step))
    assert_trajectory_invariants(solved_step, resampled)  # the joint-speed bound is then the solved step's
    assert resampled.trajectory.clearance.min() >= problem.solver.clearance
    shown = np.round(np.degrees(resampled.trajectory.phi[:, 0]), 9)
    assert {-48.0, 48.0} <= set(shown) and not set(shown) & {-12.0, 0.0, 12.0}  # safe in-between poses only
    np.testing.assert_array_equal(resampled.trajectory.phi[-1], phi[-1])  # the solved pose itself ends the motion
