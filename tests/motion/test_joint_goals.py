"""Joint goals (``goals: - joints: [...]``): the arm plans its way to a pose of its joints and
ends on it, every frame keeping the invariants, also from a start resting on a joint limit;
bad joint goals are refused at their line."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from invariants import assert_trajectory_invariants, small_planning_budget
from runfolders import assert_reruns_byte_identical
from strategies import joint_goal_problems

from armanim.arm.kinematics import forward
from armanim.motion.timing.retime import retime
from armanim.motion.trajectory import solve_trajectory
from armanim.scene import scene_model
from armanim.scene.convert import scene_to_problem
from armanim.scene.loader import load_scene

PANDA_HOME = [0, -45, 0, -135, 0, 90, 45]
PANDA_JOINT2_LOWER = math.degrees(-1.7628)  # the Panda URDF's panda_joint2 lower limit (rad), in degrees


def solved(scene: dict, timed: bool = True):
    """(problem, solution) of a scene dict, put on the clock at its own fps when ``timed``."""
    problem = scene_to_problem(scene_model(scene))
    solution = solve_trajectory(problem)
    return problem, retime(problem, solution, problem.fps) if timed else solution


def last_frames(solution) -> list[np.ndarray]:
    """Each goal's last frame (radians)."""
    traj = solution.trajectory
    return [traj.phi[np.nonzero(traj.goal == g.index)[0][-1]] for g in solution.goals]


def test_notes_arm_ends_on_each_joint_goal_exactly():
    scene = {
        "version": 1,
        "arm": {"links": [2, 5, 5, 5], "base": [5, 5, 0], "limits": [[-170, 170]] * 4},
        "obstacles": [{"center": [12, 2, 8], "radius": 1.5}],
        "goals": [{"joints": [30, 40, 20, -10]}, {"joints": [-60, 10, 80, 30], "hold": 0.5}, {"joints": [0, 0, 0, 0]}],
    }
    problem, solution = solved(scene)
    assert all(g.reached for g in solution.goals)
    for goal, phi in zip(problem.goals, last_frames(solution)):
        np.testing.assert_allclose(phi, goal.joints, atol=1e-12)
        # the report's position is the goal's tool point, by forward kinematics
        np.testing.assert_allclose(goal.position, forward(problem.arm, goal.joints).tip, atol=1e-12)
    assert_trajectory_invariants(problem, solution)
    # reached only where the joints are there (not where the tool point passes by)
    traj = solution.trajectory
    for k, goal in enumerate(problem.goals):
        mine = traj.goal == k
        there = np.abs(traj.phi[mine] - goal.joints).max(axis=1) <= problem.solver.joint_tolerance
        np.testing.assert_array_equal(traj.reached[mine], there)


def test_panda_goes_round_a_board_to_joint_goals():
    """The straight joint path from one side to the other sweeps the arm through a board: the
    planner goes round it; every frame keeps clearance and the self pairs, within the rates."""
    scene = {
        "version": 1,
        "arm": {"robot": "panda"},
        "floor": 0.0,
        "obstacles": [{"box": {"center": [0.55, 0.0, 0.45], "size": [0.2, 0.05, 0.9]}}],
        "goals": [{"joints": [60, 20, 0, -100, 0, 120, 45]}, {"joints": [-60, 20, 0, -100, 0, 120, 45]}],
        "solver": {"clearance": 0.01},
    }
    problem, solution = solved(scene)
    assert all(g.reached for g in solution.goals), [g.reason for g in solution.goals]
    assert solution.goals[1].planning.path == "rrt_connect"
    for goal, phi in zip(problem.goals, last_frames(solution)):
        np.testing.assert_allclose(phi, goal.joints, atol=1e-12)
    assert_trajectory_invariants(problem, solution)


def test_a_start_on_a_joint_limit_is_taken_and_left():
    """MoveIt's bounds are closed: MotionBenchMaker's table_under_pick starts rest on joint 2's limit."""
    home = [0, PANDA_JOINT2_LOWER, 0, -135, 0, 90, 45]
    scene = {"version": 1, "arm": {"robot": "panda", "home": home}, "goals": [{"joints": PANDA_HOME}, [0.4, 0.1, 0.5]]}
    problem, solution = solved(scene)
    assert problem.home[1] == problem.limits.lower[1]
    assert all(g.reached for g in solution.goals), [g.reason for g in solution.goals]
    assert_trajectory_invariants(problem, solution)
    # and a joint goal on the limit is reached on it
    scene = {"version": 1, "arm": {"robot": "panda"}, "goals": [{"joints": home}]}
    problem, solution = solved(scene)
    assert solution.goals[0].reached
    assert last_frames(solution)[0][1] == problem.limits.lower[1]
    assert_trajectory_invariants(problem, solution)


def test_a_pose_goal_from_a_start_on_a_limit():
    """The filter moves a joint resting on its limit no further out, the barrier is silent there."""
    home = [0, PANDA_JOINT2_LOWER, 0, -135, 0, 90, 45]
    problem, solution = solved({"version": 1, "arm": {"robot": "panda", "home": home}, "goals": [[0.4, 0.1, 0.5]]})
    assert solution.goals[0].reached
    assert_trajectory_invariants(problem, solution)


@pytest.mark.parametrize(
    ("goal", "field", "words"),
    [
        ({"joints": [0, -45, 0]}, "goals[0].joints", "has 3 values, the arm has 7 moving joints"),
        ({"joints": [0, -120, 0, -135, 0, 90, 45]}, "goals[0].joints[1]", "outside joint 2's limits"),
        ({"joints": PANDA_HOME, "tool_axis": [0, 0, 1]}, "goals[0]", "sets joints with an orientation"),
        ({"joints": PANDA_HOME, "position": [0.4, 0, 0.4]}, "goals[0]", "sets both position and joints"),
        ({"joints": PANDA_HOME, "speed": 0.1}, "goals[0].speed", "belongs to a path goal"),
        ({"joints": [0, -45, 0, -135, 0, 90, float("nan")]}, "goals[0].joints[6]", "finite"),
    ],
)
def test_bad_joint_goals_are_refused_at_their_line(tmp_path, cli, goal, field, words):
    import yaml

    path = tmp_path / "bad.yaml"
    path.write_text(yaml.safe_dump({"version": 1, "arm": {"robot": "panda"}, "goals": [goal]}, sort_keys=False))
    result = cli("validate", path)
    assert result.exit_code == 2, result.output
    assert f"{field}" in result.output and words in result.output, result.output
    assert f"{path.name}:" in result.output


def test_a_joint_goal_in_collision_is_refused(tmp_path, cli):
    path = tmp_path / "inside.yaml"
    path.write_text(
        "version: 1\narm: {robot: panda}\nobstacles:\n  - {center: [0.3, 0.0, 0.49], radius: 0.05}\n"
        "goals:\n  - [0.5, 0.3, 0.5]\n  - {joints: [0, -45, 0, -135, 0, 90, 45]}\n"
    )
    result = cli("validate", path)
    assert result.exit_code == 2, result.output
    assert "goals[1]" in result.output and "of the joint goal's pose is inside obstacles[0]" in result.output, (
        result.output
    )


def test_a_home_beyond_a_limit_is_still_refused(tmp_path, cli):
    path = tmp_path / "beyond.yaml"
    path.write_text(
        f"version: 1\narm: {{robot: panda, home: [0, {PANDA_JOINT2_LOWER - 0.01!r}, 0, -135, 0, 90, 45]}}\n"
        "goals:\n  - {joints: [0, -45, 0, -135, 0, 90, 45]}\n"
    )
    result = cli("validate", path)
    assert result.exit_code == 2 and "the ends included" in result.output, result.output


def test_joint_goal_runs_are_byte_identical(tmp_path, cli):
    scene = tmp_path / "twice.yaml"
    scene.write_text(
        "version: 1\nname: twice\narm: {robot: panda}\nfloor: 0.0\nobstacles:\n"
        "  - {box: {center: [0.55, 0.0, 0.45], size: [0.2, 0.05, 0.9]}}\n"
        "goals:\n  - {joints: [60, 20, 0, -100, 0, 120, 45]}\n  - {joints: [-60, 20, 0, -100, 0, 120, 45]}\n"
        "solver: {clearance: 0.01}\n"
    )
    assert_reruns_byte_identical(cli, scene, "twice")


def test_the_documented_joint_goal_form_loads(tmp_path):
    """The loader takes the joint goal form as docs/scene-format.md writes it."""
    path = tmp_path / "form.yaml"
    path.write_text("version: 1\narm: {robot: ur5}\ngoals:\n  - joints: [0, -90, 90, -90, -90, 0]\n    hold: 0.2\n")
    assert load_scene(path).model.goals[0].joints == [0, -90, 90, -90, -90, 0]


def test_summary_path_length_is_the_joint_path_of_the_csv(tmp_path, cli):
    import csv
    import json

    scene = tmp_path / "length.yaml"
    scene.write_text(
        "version: 1\nname: length\narm: {robot: ur5}\n"
        "goals:\n  - {joints: [30, -60, 60, -90, -90, 0], hold: 0.3}\n  - [0.4, 0.2, 0.3]\n"
    )
    assert cli("run", scene, "--out", tmp_path / "out", "--no-video", "--quiet").exit_code == 0
    run = tmp_path / "out" / "length"
    rows = list(csv.DictReader((run / "trajectory.csv").open()))
    phi = np.radians([[float(r[f"phi{j}_deg"]) for j in range(1, 7)] for r in rows])
    goal = np.array([int(r["goal"]) for r in rows])
    summary = json.loads((run / "summary.json").read_text())
    for k, g in enumerate(summary["goals"]):
        mine = np.nonzero(goal == k)[0]
        expected = sum(np.linalg.norm(phi[i] - phi[i - 1]) for i in mine if i > 0)
        assert g["path_length_rad"] == pytest.approx(expected, rel=1e-6, abs=1e-9)
    assert summary["goals"][0]["path_length_rad"] > 1.0


def test_timed_frames_are_reached_only_on_the_goal():
    """On the clock too (retime), a joint goal's frames are reached where the joints are there,
    even where its tool point passes within solver.tolerance of the goal's on the way."""
    scene = {
        "version": 1,
        "arm": {"links": [1, 1], "axes": ["z", "z"], "direction": "x", "limits": [[-170, 170]] * 2},
        "goals": [{"joints": [90, -90]}, {"joints": [0, 90]}],
    }
    problem, solution = solved(scene)
    traj = solution.trajectory
    # the two poses put the tool on the same point: [1, 1] and ... (90, -90) -> (1, 1); (0, 90) -> (1, 1)
    np.testing.assert_allclose(problem.goals[0].position, problem.goals[1].position, atol=1e-12)
    second = traj.goal == 1
    there = np.abs(traj.phi[second] - problem.goals[1].joints).max(axis=1) <= problem.solver.joint_tolerance
    np.testing.assert_array_equal(traj.reached[second], there)
    assert not there[0] and there[-1]


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(joint_goal_problems())
def test_random_joint_goals_keep_every_invariant(problem):
    """Random arms among every shape: each joint goal reached exactly or missed with a planner's
    reason, and every invariant of the timed trajectory (clearance, the limits' ends, the rates)."""
    problem = small_planning_budget(problem)
    solution = retime(problem, solve_trajectory(problem), problem.fps)
    assert_trajectory_invariants(problem, solution)
    traj = solution.trajectory
    for report in solution.goals:
        left = traj.phi[np.nonzero(traj.goal <= report.index)[0][-1]]  # where the arm was when it left the goal
        if report.reached:
            np.testing.assert_allclose(left, problem.goals[report.index].joints, atol=1e-12)
        else:
            assert report.reason in {"no_path", "too_slow"}


def test_an_unlimited_joint_goal_is_taken_the_wrapped_way():
    """A continuous joint's 270 degrees is its -90: the frames stay in (-180, 180] and end there."""
    scene = {"version": 1, "arm": {"links": [2, 2], "limits": [None, [-120, 120]]}, "goals": [{"joints": [270, 30]}]}
    problem, solution = solved(scene)
    assert solution.goals[0].reached
    np.testing.assert_allclose(np.degrees(last_frames(solution)[0]), [-90.0, 30.0], atol=1e-9)
    assert_trajectory_invariants(problem, solution)
