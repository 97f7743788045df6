"""Time has one owner: the scene's seconds. The motion is solved at the scene's own
``render.fps`` and shown at any other rate (``--fps``, ``--quality``) as the same motion."""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from invariants import assert_trajectory_invariants, assert_within_rates, small_planning_budget
from strategies import cluttered_problems, robot_problems

from armanim.arm.geometry import wrap_angle
from armanim.arm.kinematics import Arm, forward
from armanim.motion.filter.clearance import pose_clearance
from armanim.motion.problem import Goal, Problem
from armanim.motion.solution import GoalReport, Solution, Trajectory
from armanim.motion.timing.retime import at_fps, retime
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
        assert np.all(table.column("reached")[last - 2 * fps : last + 1] == 1)
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

ROOT = Path(__file__).resolve().parents[2]


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


@settings(
    max_examples=10, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much]
)  # as the suite's profile
@given(problem=cluttered_problems(max_goals=2), fps=st.sampled_from([7.0, 15.0, 24.0, 60.0, 90.0]))
def test_every_retimed_frame_keeps_the_guarantees_at_that_rate(problem, fps):
    solved = solve_trajectory(small_planning_budget(problem))
    timed = retime(problem, solved, fps)
    shown = at_fps(problem, fps)
    # clearance, limits, holds, reports, and each joint's speed and acceleration within its limits
    assert_trajectory_invariants(shown, timed)
    assert [g.reached for g in timed.goals] == [g.reached for g in solved.goals]
    assert [g.reason for g in timed.goals] == [g.reason for g in solved.goals]
    assert timed.trajectory.iterations.sum() == solved.trajectory.iterations.sum()
    for g, report in zip(timed.goals, solved.goals):  # every goal ends on its last solved pose, at rest
        if g.frames:
            last, solved_last = (r.first_frame + r.frames - 1 + (r.index == 0) for r in (g, report))
            gap = wrap_angle(timed.trajectory.phi[last] - solved.trajectory.phi[solved_last])
            np.testing.assert_allclose(gap, 0, atol=1e-9)
            assert np.all(timed.trajectory.velocity[last] == 0)
            assert g.timing.peak_speed_ratio <= 1 + 1e-9 and g.timing.peak_acceleration_ratio <= 1 + 1e-9
            assert g.timing.duration == pytest.approx(g.frames / fps)


@settings(max_examples=6, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(problem=robot_problems(), fps=st.sampled_from([15.0, 30.0, 60.0]))
def test_a_robots_frames_keep_its_own_speed_and_acceleration_limits(problem, fps):
    solved = solve_trajectory(small_planning_budget(problem))
    timed = retime(problem, solved, fps)
    assert_trajectory_invariants(at_fps(problem, fps), timed)  # within problem.rates: the URDF's and Franka's / UR's
    assert all(g.timing.peak_speed_ratio <= 1 + 1e-9 for g in timed.goals)


@settings(max_examples=6, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(problem=robot_problems(), fps=st.sampled_from([15.0, 30.0, 60.0]), jerk=st.floats(50.0, 5000.0))
def test_with_a_jerk_limit_a_robots_frames_keep_it_too(problem, fps, jerk):
    problem = replace(problem, rates=replace(problem.rates, jerk=np.full(problem.arm.n, jerk)))
    solved = solve_trajectory(small_planning_budget(problem))
    assert_trajectory_invariants(at_fps(problem, fps), retime(problem, solved, fps))  # goals meet without a jerk too


def test_the_clock_is_the_same_at_every_fps():
    problem = scene_to_problem(load_scene(ROOT / "scenes" / "notes-arm.yaml").model)
    solved = solve_trajectory(problem)
    durations = {fps: [g.timing.duration for g in retime(problem, solved, fps).goals] for fps in (15.0, 30.0, 60.0)}
    for fps in (15.0, 60.0):  # whole frames: each goal rounds up by less than one frame
        np.testing.assert_allclose(durations[fps], durations[30.0], atol=1 / 15)


def _one_step(
    start_deg: float, end_deg: float, sphere: np.ndarray, radius: float, fps: float
) -> tuple[Problem, Solution]:
    """A one-link arm (unlimited) solved in a single frame from ``start_deg`` to ``end_deg``, past a sphere."""
    arm = Arm.from_names([2.0], axes=["z"], direction="x")
    phi = np.radians([[start_deg], [end_deg]])
    pose = forward(arm, phi)
    goal = Goal(pose.tip[-1], 0.0)
    problem = Problem(
        arm=arm,
        half_width=0.05,
        home=phi[0],
        limits=unlimited_limits(1),
        obstacles=Obstacles(sphere[None], np.array([radius]), np.array([radius])),
        goals=(goal,),
        solver=default_solver_settings(max_joint_step=np.radians(180.0)),
        fps=fps,
    )
    trajectory = Trajectory(
        phi=phi,
        tip=pose.tip,
        goal=np.zeros(2, dtype=int),
        distance=np.array([1.0, 0.0]),
        clearance=pose_clearance(problem, phi),
        reached=np.array([False, True]),
        iterations=np.array([0, 1]),
        step_scale=np.array([0.0, 1.0]),
        fps=fps,
    )
    report = GoalReport(
        index=0,
        position=goal.position,
        reached=True,
        reason=None,
        frames=1,
        first_frame=0,
        last_frame=1,
        final_distance=0.0,
        iterations=1,
        newton_iterations=0,
        planning=None,
    )
    return problem, Solution(trajectory, (report,))


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(
    start=st.floats(-180.0, 180.0),
    turn=st.floats(30.0, 170.0),
    sign=st.sampled_from([-1.0, 1.0]),
    at=st.floats(0.2, 0.8),
    reach=st.floats(0.6, 1.9),
    radius=st.floats(0.05, 0.4),
    fps=st.sampled_from([30.0, 90.0]),
)
def test_a_step_whose_chord_cuts_an_obstacle_never_jumps(start, turn, sign, at, reach, radius, fps):
    # issue 50 item 12: a frame on a chord under the floor showed the solved pose (157 degrees in
    # one frame); now the step goes another certified way, every frame within the rates, clear
    end = start + sign * turn
    middle = np.radians(start + at * (end - start))
    problem, solved = _one_step(start, end, reach * np.array([np.cos(middle), np.sin(middle), 0.0]), radius, fps)
    assume(solved.trajectory.clearance.min() > 1.5 * problem.solver.clearance)  # both solved poses clear
    timed = retime(problem, solved, fps).trajectory
    assert_within_rates(at_fps(problem, fps), timed)  # finite differences, and the CSV's velocity agrees
    assert timed.clearance.min() >= problem.solver.clearance
    np.testing.assert_allclose(timed.phi[-1], solved.trajectory.phi[-1])


def test_an_in_between_pose_that_would_cut_an_obstacle_is_moved_back():
    # one link sweeping +-60 degrees past a sphere in a single solved frame: the joint-space
    # chord passes through the sphere at 0 degrees, both solved poses are clear of it
    arm = Arm.from_names([2.0], axes=["z"], direction="x")
    problem = Problem(
        arm=arm,
        half_width=0.05,
        home=np.radians([-60.0]),
        limits=unlimited_limits(1),
        obstacles=Obstacles(np.array([[1.5, 0.0, 0.0]]), np.array([0.3]), np.array([0.3])),
        goals=(Goal(np.array([1.0, 1.732, 0.0]), 0.0),),
        solver=default_solver_settings(max_joint_step=np.radians(120.0)),
        fps=10.0,
    )
    phi = np.radians([[-60.0], [60.0]])
    pose = forward(arm, phi)
    distance = np.linalg.norm(pose.tip - problem.goals[0].position, axis=1)
    trajectory = Trajectory(
        phi=phi,
        tip=pose.tip,
        goal=np.zeros(2, dtype=int),
        distance=distance,
        clearance=pose_clearance(problem, phi),
        reached=distance < 0.01,
        iterations=np.array([0, 1]),
        step_scale=np.array([0.0, 1.0]),
        fps=10.0,
    )
    assert trajectory.clearance.min() > problem.solver.clearance
    report = GoalReport(
        index=0,
        position=problem.goals[0].position,
        reached=True,
        reason=None,
        frames=1,
        first_frame=0,
        last_frame=1,
        final_distance=float(distance[-1]),
        iterations=1,
        newton_iterations=0,
        planning=None,
    )
    solved = Solution(trajectory, (report,))
    straight = np.radians(np.linspace(-60.0, 60.0, 11))
    assert pose_clearance(problem, straight[:, None]).min() < 0  # plain interpolation would cut the sphere
    timed = retime(problem, solved, 100.0)
    assert timed.trajectory.clearance.min() >= problem.solver.clearance  # safe in-between poses only
    np.testing.assert_array_equal(timed.trajectory.phi[-1], phi[-1])  # the solved pose itself ends the motion
    # ... and no frame jumps to get there (issue 50 item 12: the chord's frames once showed the
    # solved pose, 120 degrees in one frame): every frame within the rates, by finite differences,
    # the clock's velocity agreeing with them, and the way round is the long one (through 180 degrees)
    assert_within_rates(at_fps(problem, 100.0), timed.trajectory)
    assert np.abs(timed.trajectory.phi[:, 0]).max() > np.radians(170.0)


def test_a_chord_that_passes_an_obstacle_between_two_frames_goes_round_it():
    # two limited links sweep -60 -> 60 degrees straight past a sphere at their tips' radius in one
    # solved step: at 30 fps every frame keeps the floor, but the arm passes through the sphere
    # between two of them. The chord is certified by halving (motion_is_free), it is not, and the
    # planner's way round it (the elbow folded) is taken instead.
    from armanim.motion.problem import Limits
    from armanim.world.distances import min_link_clearance

    arm = Arm.from_names([1.0, 1.0], axes=["z", "z"], direction="x")
    phi = np.radians([[-60.0, 0.0], [60.0, 0.0]])
    pose = forward(arm, phi)
    goal = Goal(pose.tip[-1], 0.0)
    problem = Problem(
        arm=arm,
        half_width=0.05,
        home=phi[0],
        limits=Limits(np.radians([-90.0, -150.0]), np.radians([90.0, 150.0]), 0.1),
        obstacles=Obstacles(np.array([[1.8, 0.0, 0.0]]), np.array([0.15]), np.array([0.15])),
        goals=(goal,),
        solver=default_solver_settings(max_joint_step=np.radians(180.0)),
        fps=30.0,
    )
    trajectory = Trajectory(
        phi=phi,
        tip=pose.tip,
        goal=np.zeros(2, dtype=int),
        distance=np.array([1.0, 0.0]),
        clearance=pose_clearance(problem, phi),
        reached=np.array([False, True]),
        iterations=np.array([0, 1]),
        step_scale=np.array([0.0, 1.0]),
        fps=30.0,
    )
    report = GoalReport(
        index=0,
        position=goal.position,
        reached=True,
        reason=None,
        frames=1,
        first_frame=0,
        last_frame=1,
        final_distance=0.0,
        iterations=1,
        newton_iterations=0,
        planning=None,
    )
    timed = retime(problem, Solution(trajectory, (report,)), 30.0).trajectory
    assert_within_rates(at_fps(problem, 30.0), timed)
    np.testing.assert_array_equal(timed.phi[-1], phi[-1])
    # between every two frames too, each joint halfway and in 64ths: never through the sphere
    fine = (
        timed.phi[:-1, None, :] + np.linspace(0.0, 1.0, 65)[None, :, None] * np.diff(timed.phi, axis=0)[:, None, :]
    ).reshape(-1, 2)
    assert min_link_clearance(forward(arm, fine), problem.obstacles, problem.capsules).min() > 0.0
