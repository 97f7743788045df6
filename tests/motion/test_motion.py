"""Motion that does not freeze: the safety filter, stall detection and the planner.

The scenes are the failures reported against the first frame loop: an arm resting on
a sphere's safety shell with the goal on the far side, a goal on the axis of the
straight arm (no Jacobian column points along it), a goal behind a sphere, a wall
of spheres that only a planned path gets around.
"""

from __future__ import annotations

import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from conftest import DOCS, ROOT
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from invariants import assert_trajectory_invariants, small_planning_budget
from strategies import cluttered_problems

from armanim.arm.kinematics import Arm, forward
from armanim.motion.filter.barrier import point_travel_bound, safe_step, takes_unchanged
from armanim.motion.filter.clearance import (
    kept_clearance,
    limit_buffer,
    planning_floor,
    pose_clearance,
    pose_is_free,
    settle_clearance,
    within_limits,
)
from armanim.motion.planning import plan_motion
from armanim.motion.planning.follow import path_frames
from armanim.motion.planning.path import (
    motion_is_free,
    motion_samples,
    plan_iterations,
)
from armanim.motion.planning.poses import goal_poses
from armanim.motion.problem import Goal, Limits, Problem
from armanim.motion.solvers import METHODS, arm_state, step_function
from armanim.motion.stalls import stall_frames
from armanim.motion.trajectory import _next_on_path, _Visit, solve_trajectory
from armanim.motion.tunables import DEFAULTS
from armanim.scene import default_solver_settings, unlimited_limits
from armanim.world.distances import min_link_clearance
from armanim.world.obstacles import Obstacles

NOTES_ARM = Arm.from_names([2, 5, 5, 5])  # base at the origin: straight up, the tip at (0, 0, 17)
CONTACT = [((3.0, 0.0, 10.0), 2.7)]  # the straight arm's capsules exactly solver.clearance (0.05) from it
WALL = [((4, 0, 12), 1.5), ((4, 0, 8.5), 1.5), ((4, 0, 15.5), 1.5), ((4, 3, 12), 1.5), ((4, -3, 12), 1.5)]


def notes_problem(obstacles=(), goals=((7.0, 0.0, 9.0),), method="pinv", planner="auto", limits=None, home=None):
    """The notes' arm at the origin with spheres (centre, radius) and goals."""
    centers = np.array([c for c, _ in obstacles], dtype=float).reshape(-1, 3)
    radii = np.array([r for _, r in obstacles], dtype=float)
    return Problem(
        arm=NOTES_ARM,
        half_width=0.25,
        home=np.zeros(4) if home is None else np.radians(home),
        limits=limits or unlimited_limits(4),
        obstacles=Obstacles(centers, radii, radii.copy()) if obstacles else Obstacles.none(),
        goals=tuple(Goal(np.array(g, dtype=float), hold=0.0) for g in goals),
        solver=default_solver_settings(method=method, max_step=0.5, planner=planner),
        fps=30.0,
    )


@pytest.mark.parametrize("method", sorted(METHODS))
def test_arm_resting_on_a_sphere_reaches_the_goal_on_its_far_side(method):
    problem = notes_problem(CONTACT, method=method)
    assert float(
        min_link_clearance(forward(problem.arm, problem.home), problem.obstacles, problem.capsules)
    ) == pytest.approx(0.05)
    solution = solve_trajectory(problem)
    assert solution.goals[0].reached, solution.goals[0]
    assert_trajectory_invariants(problem, solution)


@pytest.mark.parametrize("method", sorted(METHODS))
def test_goals_on_the_straight_arms_own_axis_are_reached(method):
    problem = notes_problem(goals=((0.0, 0.0, 16.5), (0.0, 0.0, 3.0)), method=method)
    solution = solve_trajectory(problem)
    assert [g.reached for g in solution.goals] == [True, True], solution.goals
    first = solution.goals[0]
    assert first.planned and first.frames < 60  # stalled for half a second, then planned
    assert_trajectory_invariants(problem, solution)


@pytest.mark.parametrize("method", sorted(METHODS))
def test_goal_directly_behind_a_sphere_is_reached(method):
    problem = notes_problem([((0.0, 6.0, 11.5), 2.0)], goals=((0.0, 10.0, 8.0),), method=method)
    solution = solve_trajectory(problem)
    assert solution.goals[0].reached
    assert "plan" in set(solution.trajectory.mode)
    assert_trajectory_invariants(problem, solution)


def test_wall_of_spheres_is_passed_by_rrt_connect():
    problem = notes_problem(WALL, goals=((8.0, 0.0, 10.0),))
    solution = solve_trajectory(problem)
    goal = solution.goals[0]
    assert goal.reached and goal.planning.path == "rrt_connect"
    assert goal.planning.frames == np.count_nonzero(solution.trajectory.mode == "plan")
    assert_trajectory_invariants(problem, solution)


@pytest.mark.parametrize("method", sorted(METHODS))
def test_planner_off_misses_a_stalled_goal_within_seconds(method):
    problem = notes_problem(WALL, goals=((8.0, 0.0, 10.0),), method=method, planner="off")
    solution = solve_trajectory(problem)
    goal = solution.goals[0]
    assert not goal.reached and goal.reason in {"blocked_by_obstacle", "stalled"}
    assert goal.frames <= 2 * problem.fps and not goal.planned  # half a second after progress stops
    assert set(solution.trajectory.mode) == {"ik"}


def test_limits_alone_do_not_stop_pinv():
    # the notes' limits and goals 20 degrees inside them: the filter slides along the limits
    lim = Limits(np.radians([-180.0, -100, -150, -150]), np.radians([180.0, 100, 150, 150]), np.radians(10.0))
    poses = np.radians([[30, 80, 130, -20], [-60, -80, 40, 130], [120, 60, -130, 0], [0, -80, -130, 120]])
    goals = tuple(map(tuple, forward(NOTES_ARM, poses).tip))
    problem = notes_problem(goals=goals, limits=lim, planner="off")
    solution = solve_trajectory(problem)
    assert all(g.reached for g in solution.goals), [(g.reason, g.final_distance) for g in solution.goals]
    assert_trajectory_invariants(problem, solution)


def test_goal_only_reachable_outside_the_limits_is_reported_as_no_free_pose():
    # (0, 10, 8) needs the base turned by 90 degrees; its limits allow 10
    lim = Limits(np.radians([-10.0, -100, -150, -150]), np.radians([10.0, 100, 150, 150]), np.radians(10.0))
    solution = solve_trajectory(notes_problem(goals=((0.0, 10.0, 8.0),), limits=lim))
    goal = solution.goals[0]
    assert goal.reason == "no_free_pose" and goal.planned and goal.planning.poses == 0


def test_out_of_reach_goal_is_not_planned():
    solution = solve_trajectory(notes_problem(goals=((30.0, 0.0, 5.0),)))
    assert solution.goals[0].reason == "out_of_reach" and not solution.goals[0].planned


@pytest.mark.parametrize("method", sorted(METHODS))
def test_planner_off_without_active_constraint_takes_the_methods_own_step(method):
    problem = notes_problem(goals=((6.0, 2.0, 9.0),), method=method, planner="off", home=[10, 30, 40, 20])
    problem = replace(problem, solver=replace(problem.solver, max_joint_step=np.pi))
    state = arm_state(problem, problem.home)
    proposal = step_function(method)(problem, state, problem.goals[0].position)
    solution = solve_trajectory(problem)
    if METHODS[method].compiled_inverse is None:
        np.testing.assert_array_equal(solution.trajectory.phi[1], problem.home + proposal.dphi)
    else:  # pinv and dls frames run compiled (motion/kernels/frame.py): the same step to rounding
        np.testing.assert_allclose(solution.trajectory.phi[1], problem.home + proposal.dphi, rtol=0, atol=1e-12)


def test_filter_slides_along_a_sphere_instead_of_stopping():
    problem = notes_problem(CONTACT)
    state = arm_state(problem, problem.home)
    into = safe_step(problem, state, np.array([0.0, 0.3, 0.0, 0.0]))  # tilts the whole arm into the sphere
    assert into.blocked_by == "obstacle" and into.phi[1] < 0.1
    assert into.phi[2] < 0  # the elbow bends the arm away instead: it moves, not freezes
    sideways = safe_step(problem, state, np.array([0.2, 0.3, 0.0, 0.0]))  # ... with a turn about the base
    assert sideways.blocked_by == "obstacle" and sideways.phi[0] > 0.1  # the free direction is kept
    for moved in (into, sideways):
        assert moved.state.min_clearance >= problem.solver.clearance


def test_filter_stops_at_the_limit_buffer_and_keeps_the_other_joints():
    lim = Limits(np.array([-np.inf, -0.2, -np.inf, -np.inf]), np.array([np.inf, 0.2, np.inf, np.inf]), 0.2)
    problem = notes_problem(limits=lim)
    state = arm_state(problem, np.array([0.0, 0.199, 0.0, 0.0]))
    moved = safe_step(problem, state, np.array([0.0, 0.1, 0.1, 0.0]))
    assert moved.blocked_by == "limit"
    assert moved.phi[1] <= 0.199 and moved.phi[2] == pytest.approx(0.1)
    state = arm_state(problem, np.array([0.0, 0.1, 0.0, 0.0]))
    for _ in range(30):
        state = safe_step(problem, state, np.array([0.0, 0.1, 0.0, 0.0])).state
    assert 0.2 - limit_buffer(problem) - 1e-9 <= state.phi[1] < 0.2  # approaches the buffer, never the limit


def test_plan_frames_are_free_and_within_the_joint_step():
    problem = notes_problem(WALL, goals=((8.0, 0.0, 10.0),))
    plan = plan_motion(problem, problem.home, problem.goals[0].position)
    assert plan.reason is None and plan.source == "rrt_connect"
    frames = np.vstack([problem.home, plan.frames])
    assert np.abs(np.diff(frames, axis=0)).max() <= problem.solver.max_joint_step + 1e-12
    assert (
        np.linalg.norm(forward(problem.arm, plan.frames[-1]).tip - problem.goals[0].position) < problem.solver.tolerance
    )
    assert pose_is_free(problem, plan.frames[-1:]).all()


def test_a_plan_tells_its_search_as_it_goes_and_plans_the_same():
    """The iterations a plan's path search has used, for the plan bar: rising, at most the budget,
    ending full; and being told changes nothing of the plan."""
    problem = notes_problem(WALL, goals=((8.0, 0.0, 10.0),))
    told = []
    plan = plan_motion(
        problem, problem.home, problem.goals[0].position, searched=lambda done, most: told.append((done, most))
    )
    np.testing.assert_array_equal(plan.frames, plan_motion(problem, problem.home, problem.goals[0].position).frames)
    assert plan.source == "rrt_connect" and len(told) >= 2
    done = [d for d, most in told]
    assert {most for _, most in told} == {plan_iterations()}
    settled = (
        DEFAULTS.planner.settle_searches * DEFAULTS.planner.ompl_iterations
    )  # the planning floor's searches count from there
    assert done == sorted(done) and done[0] in (0, settled) and done[-1] == plan_iterations()


def test_a_goal_without_a_path_tells_the_whole_search_budget():
    """An arm held nearly rigid by its limits turns about its base only, and spheres at 90 degrees
    either side of it close both ways round: the free pose behind it has no path, and every search runs."""
    bent = np.radians([0.0, 60.0, 30.0, 0.0])
    lim = Limits(np.r_[-np.inf, bent[1:] - np.radians(2)], np.r_[np.inf, bent[1:] + np.radians(2)], np.radians(0.5))
    tip = forward(NOTES_ARM, bent).tip
    radius = np.hypot(*tip[:2])
    sides = [((0.0, side * radius, tip[2]), 2.5) for side in (1, -1)]
    problem = notes_problem(sides, goals=((-tip[0], tip[1], tip[2]),), limits=lim, home=np.degrees(bent))
    told = []
    small = small_planning_budget(problem)
    plan = plan_motion(small, small.home, small.goals[0].position, searched=lambda done, most: told.append(done))
    most = plan_iterations(small.tunables.planner)
    assert plan.reason == "no_path", plan.reason
    assert (
        told[-1] == most and max(told[:-1]) >= most - small.tunables.planner.ompl_iterations
    )  # the last search ran to its end before the plan ended


def test_the_docs_give_the_planning_budget_the_code_has():
    scene_format, python_api = (
        " ".join((DOCS / page).read_text(encoding="utf-8").split()) for page in ("scene-format.md", "python-api.md")
    )
    planner = DEFAULTS.planner
    assert (
        planner.settle_searches == 1
        and f"one search of {planner.ompl_iterations:,} iterations with room to settle" in scene_format
    )
    assert (
        planner.ompl_searches == 2
        and f"two searches of {planner.ompl_iterations:,} iterations at the planning floor" in scene_format
    )
    assert f"whole budget, {plan_iterations():,} iterations" in scene_format
    assert f"of at most {plan_iterations():,}" in python_api


def test_a_straight_plan_tells_nothing():
    problem = notes_problem(goals=((6.0, 2.0, 9.0),))
    told = []
    plan = plan_motion(problem, problem.home, problem.goals[0].position, searched=lambda *a: told.append(a))
    assert plan.source == "straight" and told == []


def test_path_frames_start_and_stop_slowly():
    frames = path_frames(np.array([[0.0, 0.0], [1.0, 0.5], [2.0, 0.5]]), 0.1)
    speed = np.abs(np.diff(frames, axis=0)).max(axis=1)
    assert speed.max() <= 0.1 + 1e-12
    assert speed[0] < 0.2 * speed.max() and speed[-1] < 0.2 * speed.max()
    np.testing.assert_allclose(frames[-1], [2.0, 0.5])


@given(cluttered_problems())
@settings(max_examples=12)
def test_cluttered_scene_trajectory_invariants(problem):
    assert_trajectory_invariants(problem, solve_trajectory(small_planning_budget(problem)))


def test_planning_run_is_byte_identical_in_two_processes_and_after_other_plans(tmp_path):
    # the second process plans another scene first: OMPL's process-wide random numbers
    # must not leak from one plan into the next
    program = (
        "import sys, numpy as np\n"
        "sys.path[:0] = [sys.argv[1], sys.argv[1] + '/motion']\n"
        "from test_motion import WALL, CONTACT, notes_problem\n"
        "from armanim.output.csvfile import trajectory_csv_text\n"
        "from armanim.motion.trajectory import solve_trajectory\n"
        "if sys.argv[2] == 'warm':\n"
        "    solve_trajectory(notes_problem(CONTACT, method='dls'))\n"
        "print(trajectory_csv_text(solve_trajectory(notes_problem(WALL, goals=((8.0, 0.0, 10.0),))).trajectory), end='')\n"
    )
    tests = str(ROOT / "tests")
    runs = [
        subprocess.run([sys.executable, "-c", program, tests, how], capture_output=True, text=True, check=True)
        for how in ("cold", "warm")
    ]
    assert ",plan" in runs[0].stdout
    assert runs[0].stdout == runs[1].stdout
    assert not any("leaked" in run.stderr for run in runs)  # OMPL's objects are freed before exit


def test_a_step_whose_linear_algebra_fails_is_reported_as_numerical(monkeypatch):
    from armanim.motion.solvers import METHODS

    def failing_step(problem, state, goal):
        raise np.linalg.LinAlgError("SVD did not converge")

    monkeypatch.setitem(
        METHODS, "pinv", replace(METHODS["pinv"], step_function=failing_step, compiled_inverse=None)
    )  # its own step only
    problem = notes_problem(goals=((6.0, 2.0, 9.0),))
    solution = solve_trajectory(problem)
    goal = solution.goals[0]
    assert not goal.reached and goal.reason == "numerical" and not goal.planned
    assert np.all(solution.trajectory.phi == problem.home)  # the arm held its last safe pose


def test_goal_reports_survive_summary_json_both_ways():
    import json

    from armanim.output.summary import goal_report_dict, goal_report_from_dict

    solution = solve_trajectory(notes_problem(WALL, goals=((8.0, 0.0, 10.0), (30.0, 0.0, 5.0))))
    for report in solution.goals:  # one planned and reached, one missed out of reach
        back = goal_report_from_dict(json.loads(json.dumps(goal_report_dict(report))))
        assert back.planning == report.planning and back.reason == report.reason
        np.testing.assert_array_equal(back.position, report.position)
        assert (back.reached, back.frames, back.final_distance) == (
            report.reached,
            report.frames,
            report.final_distance,
        )


# ---------------------------------------------------------------- one margin for planner, follower and filter (issue 18)


@given(cluttered_problems(max_goals=1), st.data())
@settings(
    max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much]
)  # as the suite's profile
def test_a_certified_motion_keeps_the_floor_everywhere_and_a_refused_one_breaks_it(problem, data):
    # the oracle: clearance sampled so densely that no arm point moves more than 1e-3 clearances
    n = problem.arm.n
    a = np.array(data.draw(st.lists(st.floats(-3, 3), min_size=n, max_size=n)))
    b = a + np.array(data.draw(st.lists(st.floats(-1.5, 1.5), min_size=n, max_size=n)))
    floor = kept_clearance(problem)
    free, _ = motion_is_free(problem, a, b, floor)
    spacing = max(1e-3 * problem.solver.clearance, point_travel_bound(problem, b - a) / 20000)  # the whole motion
    dense = motion_samples(problem, a, b, spacing)
    lowest = float(pose_clearance(problem, dense).min()) if len(problem.obstacles) else np.inf
    inside = bool(within_limits(problem, np.stack([a, b])).all())
    if free:
        assert lowest >= floor - DEFAULTS.planner.certify_to * problem.solver.clearance / 2 - 1e-9
    elif inside:  # refused only where some pose really comes closer than the floor (to the oracle's spacing)
        assert lowest < floor + spacing / 2 + 1e-9


def test_goal_poses_keep_what_the_filter_keeps_and_the_roomy_come_first():
    problem = notes_problem(WALL, goals=((8.0, 0.0, 12.0),))
    found = goal_poses(problem, problem.home, problem.goals[0].position)
    clear = pose_clearance(problem, found.poses)
    assert len(found.poses) > 1 and clear.min() >= planning_floor(problem, problem.home) - 1e-12
    roomy = clear >= settle_clearance(problem)
    assert roomy.any() and not np.any(np.diff(roomy.astype(int)) > 0)  # never a roomy pose after a tight one


def test_the_planned_path_never_runs_ahead_of_an_arm_the_filter_holds_back():
    problem = notes_problem()
    step = problem.solver.max_joint_step
    visit = _Visit(0, problem.goals[0], [1.0], [None], [1.0], path=[np.full(4, k * step) for k in range(1, 6)])
    state = arm_state(problem, np.zeros(4))
    assert np.allclose(_next_on_path(problem, state, visit), step) and len(visit.path) == 4  # on schedule
    held = arm_state(problem, np.full(4, 0.2 * step))  # the filter let the arm move a fifth of the way
    target = _next_on_path(problem, held, visit)
    assert np.allclose(target, 2 * step) and len(visit.path) == 4  # kept: wait, do not run ahead
    for _ in range(stall_frames(problem)):
        _next_on_path(problem, held, visit)
    assert visit.path == []  # held back for a stall window: the path is dropped, the method takes over


def test_a_frame_that_ends_its_path_takes_the_planned_step():
    # the frame that reaches a path's last pose ends the path; it must still take the
    # planned step (it read the method's proposal, which no planned frame has, and crashed)
    from armanim.motion.solution import PlanningReport
    from armanim.motion.solvers import solver_method
    from armanim.motion.trajectory import _one_frame, _Recorder

    problem = notes_problem(method="gradient")
    state = arm_state(problem, np.zeros(4))
    visit = _Visit(0, problem.goals[0], [1.0], [None], [1.0], path=[np.zeros(4)], planning=PlanningReport())
    moved = _one_frame(problem, solver_method("gradient"), _Recorder(), state, visit)
    assert visit.path == [] and visit.frames == 1 and visit.planning.frames == 1
    np.testing.assert_array_equal(moved.phi, state.phi)  # at the last pose: the planned step is 0


def test_a_goal_pinned_at_the_margin_is_reached_with_one_plan():
    # before: the filter bent a path planned right down to its own margin, the arm stopped
    # 4.6 from the goal at 1.1 clearances, and three plans from the same pocket failed alike
    from armanim import load_scene, scene_to_problem

    problem = scene_to_problem(load_scene(Path(__file__).parents[1] / "data" / "planner-pocket.yaml").model)
    solution = solve_trajectory(problem)
    goal = solution.goals[0]
    assert goal.reached and goal.planning.plans == 1, goal
    assert_trajectory_invariants(problem, solution)


def test_paced_path_frames_lie_on_the_path_and_the_filter_takes_each_one_unchanged():
    problem = notes_problem(WALL, goals=((8.0, 0.0, 12.0),))
    plan = plan_motion(problem, problem.home, problem.goals[0].position)
    assert plan.frames is not None
    poses = np.concatenate([problem.home[None], plan.frames])
    taken = [takes_unchanged(problem, arm_state(problem, a), b - a) for a, b in zip(poses[:-1], poses[1:])]
    assert all(taken)  # so the arm follows the plan exactly, frame by frame
    solution = solve_trajectory(problem)  # the run plans from where its method stalled
    following = solution.trajectory.mode == "plan"
    assert following.sum() >= 10 and solution.goals[0].planning.plans == 1
    np.testing.assert_allclose(solution.trajectory.step_scale[following], 1.0)  # every planned step taken whole
