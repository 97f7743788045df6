"""The invariants every trajectory keeps, checked from scratch (used by several test modules)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from armanim.arm.geometry import wrap_angle
from armanim.arm.kinematics import forward
from armanim.motion.filter.clearance import limit_buffer
from armanim.motion.paths.following import most_path_frames
from armanim.motion.problem import Problem
from armanim.motion.solution import MISS_REASONS, Solution, max_joint_step
from armanim.motion.trajectory import frame_budget, hold_frames
from armanim.world.distances import clearances
from armanim.world.selfdistances import self_gaps

TINY = 1e-9


def small_planning_budget(problem: Problem, share: int = 30, seed_share: int = 4) -> Problem:
    """``problem`` with the planner's RRT budget divided by ``share``, and its goal poses' random
    starts by ``seed_share`` (``problem.tunables``).

    A random goal with no path spends the whole budget (3 x 15,000 RRT iterations, up to a
    minute) before it is reported, and planning (the goal poses from 128 starts, then RRT)
    took most of a random scene's solve; a thirtieth of the one and a quarter of the other
    test the same invariants, and benchmarks/motion_bench.py measures what the whole budget finds.
    """
    t = problem.tunables
    return replace(
        problem,
        tunables=replace(
            t,
            planner=replace(t.planner, ompl_iterations=t.planner.ompl_iterations // share),
            poses=replace(t.poses, seeds=t.poses.seeds // seed_share),
        ),
    )


RATE_TOLERANCE = 1e-9
"""Relative: the frames' finite-difference speeds and accelerations may exceed the limits by
rounding only."""


def assert_within_rates(problem: Problem, traj) -> None:
    """Every frame of a timed trajectory within each joint's speed, acceleration (and jerk, where
    the problem bounds it) limits (differences over 1/fps, unlimited joints wrap-aware), the
    clock's velocities finite and 0 where the arm rests."""
    steps = wrap_angle(np.diff(traj.phi, axis=0))
    speed = np.abs(steps) * traj.fps
    assert np.all(speed <= problem.rates.speed * (1 + RATE_TOLERANCE)), float((speed / problem.rates.speed).max())
    accel = np.abs(np.diff(steps, axis=0)) * traj.fps**2
    assert np.all(accel <= problem.rates.acceleration * (1 + RATE_TOLERANCE)), float(
        (accel / problem.rates.acceleration).max()
    )
    if problem.rates.jerk is not None:
        jerk = np.abs(np.diff(steps, 2, axis=0)) * traj.fps**3
        assert np.all(jerk <= problem.rates.jerk * (1 + RATE_TOLERANCE)), float((jerk / problem.rates.jerk).max())
    assert np.all(np.isfinite(traj.velocity)) and np.all(np.abs(traj.velocity) <= problem.rates.speed * (1 + 1e-6)), (
        float((np.abs(traj.velocity) / problem.rates.speed).max())
    )
    rest = np.concatenate([[True], np.all(steps == 0, axis=1)]) & np.concatenate([np.all(steps == 0, axis=1), [True]])
    assert np.all(traj.velocity[rest] == 0)
    # the clock's velocity (trajectory.csv's dphi columns) agrees with the positions: a frame's
    # difference over 1/fps is the velocity somewhere in the frame before, within a/fps of its end's
    gap = np.abs(traj.velocity[1:] - steps * traj.fps)
    assert np.all(gap <= problem.rates.acceleration / traj.fps * (1 + RATE_TOLERANCE) + 1e-9), float(
        (gap / (problem.rates.acceleration / traj.fps)).max()
    )


def assert_passed_within_radius(problem: Problem, traj, k: int, report) -> None:
    """Via goal ``k``'s last frame (its pass) is within its blend radius (at least twice the
    tolerance), measured again by forward kinematics, and the arm does not rest there."""
    rows = np.nonzero(traj.goal == k)[0]
    goal = problem.goals[k]
    if goal.joints is not None:
        near = np.abs(wrap_angle(traj.phi[rows] - goal.joints)).max(axis=1)
        floor = problem.solver.joint_tolerance
    else:
        near = np.linalg.norm(forward(problem.arm, traj.phi[rows]).tip - goal.position, axis=1)
        floor = problem.solver.tolerance
    assert near[-1] == pytest.approx(report.blend.pass_distance, abs=1e-9)
    assert near[-1] <= max(goal.blend, 2 * floor) * (1 + 1e-9), (k, near[-1], goal.blend)
    last = rows[-1]
    assert (
        last + 1 < len(traj.phi)
        and np.any(traj.phi[last + 1] != traj.phi[last])
        and np.any(traj.phi[last] != traj.phi[last - 1])
    )


def _assert_clear(problem: Problem, traj, pose, mine: np.ndarray, first: int) -> None:
    """The obstacle and self-pair invariants of the frames ``mine`` (F,) of ``traj`` in ``problem``'s
    world (the first of them, frame ``first``, stands for home: from nearer than the clearance, no nearer)."""
    from armanim.arm.kinematics import Pose

    here = Pose(pose.points[mine], pose.frames[mine])
    if len(problem.obstacles):
        cl = clearances(here, problem.obstacles, problem.capsules)
        assert np.all(cl.links > 0), float(cl.links.min())
        # the tip too, but for a joint goal's frames: its tool point is no part of the arm (a grasp's lies in the object)
        toward_point = np.array([g.joints is None for g in problem.goals])[traj.goal[mine]]
        assert np.all(cl.d[toward_point] > 0), float(cl.d[toward_point].min()) if toward_point.any() else None
        np.testing.assert_allclose(traj.clearance[mine], cl.links.min(axis=(-1, -2)), atol=1e-12)
        # every link keeps solver.clearance (or, from a home closer than that, gets no closer)
        floor = min(problem.solver.clearance, traj.clearance[first])
        assert traj.clearance[mine].min() >= floor - TINY, (traj.clearance[mine].min(), floor)
    else:
        assert np.all(np.isinf(traj.clearance[mine]))
    # every enabled pair of the arm's own capsules keeps self_clearance (or, from a home nearer than
    # that, gets no nearer), recomputed; the trajectory's self columns say the least gap and its pair
    pairs = problem.self_pairs
    if len(pairs):
        gaps = self_gaps(here, problem.capsules, pairs).d
        least = gaps.min(axis=1)
        assert least.min() >= min(pairs.clearance, least[0]) - TINY, (
            least.min(),
            pairs.labels[int(gaps.min(axis=0).argmin())],
        )
        np.testing.assert_allclose(traj.self_clearance[mine], least, atol=1e-12)
        assert all(label in pairs.labels for label in traj.self_pair[mine])


def assert_trajectory_invariants(problem: Problem, solution: Solution) -> None:
    traj = solution.trajectory
    F, n = traj.phi.shape
    assert n == problem.arm.n and F >= 1
    timed = traj.velocity is not None  # on the clock: its limits, not the solver's step, bound the motion
    assert timed or F <= frame_budget(problem)
    for name in ("phi", "tip", "distance"):
        assert np.all(np.isfinite(getattr(traj, name))), name
    # frame 0 is home; frames are numbered 0..F-1 and timed by fps
    np.testing.assert_array_equal(traj.phi[0], problem.home)
    np.testing.assert_allclose(traj.time, np.arange(F) / problem.fps)
    # the tip is FK of the angles
    pose = forward(problem.arm, traj.phi)
    np.testing.assert_allclose(traj.tip, pose.tip, atol=1e-9, rtol=0)
    # distance to the frame's goal
    goals = np.array([g.position for g in problem.goals])
    expected = np.linalg.norm(traj.tip - goals[traj.goal], axis=1)
    paths = any(g.path is not None for g in problem.goals)
    assert (traj.path_s is not None) == paths and (traj.path_error is not None) == paths
    if paths:  # along a path: the tool's distance from it, measured again; within the path tolerance
        along = ~np.isnan(traj.path_s)
        np.testing.assert_array_equal(along, ~np.isnan(traj.path_error))
        assert np.all(along[traj.mode == "path"])  # and the hold at a path's end
        for k in np.unique(traj.goal[along]):
            mine = along & (traj.goal == k)
            path = problem.goals[k].path
            np.testing.assert_allclose(
                path.points(traj.path_s[mine]), traj.tip[mine], atol=traj.path_error[mine].max() + 1e-9
            )
            assert np.all(path.distance(traj.tip[mine]) <= traj.path_error[mine] + 1e-12)
        assert np.all(traj.path_error[along] <= problem.solver.path_tolerance), float(np.nanmax(traj.path_error))
        for k in (
            np.unique(traj.goal[traj.mode == "path"]) if traj.velocity is not None else ()
        ):  # on the clock: never faster than its speed
            f = np.nonzero((traj.mode == "path") & (traj.goal == k))[0]
            tool_speed = np.linalg.norm(traj.tip[f] - traj.tip[f - 1], axis=1) * traj.fps
            assert tool_speed.max() <= problem.goals[k].speed * (1 + 1e-9), float(
                tool_speed.max() / problem.goals[k].speed
            )
        expected = np.where(along, traj.path_error, expected)
    np.testing.assert_allclose(traj.distance, expected, atol=1e-9)
    # goal index never goes back
    assert np.all(np.diff(traj.goal) >= 0) and traj.goal[0] == 0
    # every link capsule (and the tip) stays clear of every obstacle, and every enabled pair of the
    # arm's own capsules keeps self_clearance, recomputed: in each goal's world for a run that carries
    # objects (a carried object's cover is then among the capsules, a resting one among the base's)
    if solution.carry is None:
        _assert_clear(problem, traj, pose, np.ones(F, dtype=bool), 0)
        if not len(problem.self_pairs):
            assert traj.self_clearance is None and traj.self_pair is None
    else:
        from armanim.motion.carry import frame_worlds

        for world, mine in frame_worlds(problem, solution.carry, traj.goal, traj.fps):  # the fingers where they are
            if mine.any():
                _assert_clear(world, traj, pose, mine, int(np.argmax(mine)))
    # limited joints within their limits, the ends included (a home or a joint goal may rest on one)
    lim = problem.limits
    limited = lim.limited
    assert np.all(traj.phi[:, limited] >= lim.lower[limited]), (traj.phi[:, limited] - lim.lower[limited]).min()
    assert np.all(traj.phi[:, limited] <= lim.upper[limited])
    # ... and the method's frames keep the filter's buffer from them (or get no closer than home
    # was); a joint goal's planned path keeps the limits themselves
    joint_goals = np.array([g.joints is not None for g in problem.goals])
    stepped = ~joint_goals[traj.goal]
    gaps = np.minimum(traj.phi - lim.lower, lim.upper - traj.phi)[:, limited]
    first = gaps[0] if stepped[0] or not joint_goals.any() else np.minimum(gaps[0], gaps.min(axis=0))
    assert np.all(gaps[stepped] >= np.minimum(limit_buffer(problem), first) - TINY)
    # modes: the method's steps, or a planned path when the planner is on (a joint goal's always)
    planned = problem.solver.planner == "auto" or joint_goals.any()
    assert set(traj.mode) <= ({"ik", "plan"} if planned else {"ik"}) | ({"path"} if paths else set())
    # unlimited joints wrapped (frame 0 may be any home)
    assert np.all(np.abs(traj.phi[1:, ~limited]) <= np.pi + TINY)
    if timed:
        assert_within_rates(problem, traj)
    # no joint turns more than max_joint_step in one solved frame (wrap-aware)
    elif F > 1:
        steps = np.abs(wrap_angle(np.diff(traj.phi, axis=0)))
        assert steps.max() <= problem.solver.max_joint_step + TINY
        assert max_joint_step(traj.phi) == pytest.approx(steps.max())
    # reached rows are within tolerance (and the orientation tolerance, where the goal has one), and only those
    # (a joint goal's rows: where every joint is within joint_tolerance of it)
    turned = (
        True if traj.orientation_error is None else ~(traj.orientation_error >= problem.solver.orientation_tolerance)
    )
    expected = (traj.distance < problem.solver.tolerance) & turned
    for k, g in enumerate(problem.goals):
        if g.joints is not None:
            mine = traj.goal == k
            expected = np.where(
                mine, np.all(np.abs(traj.phi - g.joints) <= problem.solver.joint_tolerance, axis=1), expected
            )
    np.testing.assert_array_equal(traj.reached, expected)
    # per-goal reports
    assert len(solution.goals) == len(problem.goals)
    for k, report in enumerate(solution.goals):
        assert report.index == k
        passed = report.blend is not None and report.blend.blended
        if passed:  # a via goal: reached as solved, and passed (not stopped at) within its radius, by FK of its frames
            assert report.reached and report.reason is None and report.blend.reason is None
            assert_passed_within_radius(problem, traj, k, report)
        elif report.reached:
            assert report.reason is None
            assert report.final_distance < problem.solver.tolerance
            assert (
                report.final_orientation_error is None
                or report.final_orientation_error < problem.solver.orientation_tolerance
            )
        else:
            assert report.reason in MISS_REASONS, report.reason
            # a miss ends early (stalled, planned in vain) or at the frame cap, and says which
            at_cap = report.frames == problem.solver.max_frames_per_goal
            assert timed or at_cap or report.reason != "too_slow"
            angle = report.final_orientation_error
            assert (
                report.final_distance >= problem.solver.tolerance
                or report.reason == "path_blocked"
                or (angle is not None and angle >= problem.solver.orientation_tolerance)
            )
        goal = problem.goals[k]
        assert (report.path is None) == (goal.path is None)
        if report.path is not None:  # the whole path exactly when reached; a stop point and cause when blocked
            assert (report.path.fraction == 1.0) == report.reached or report.reason != "path_blocked"
            assert (
                (report.reason == "path_blocked")
                == (report.path.cause is not None)
                == (report.path.stop_point is not None)
            )
            assert 0.0 <= report.path.fraction <= 1.0
        cap = problem.solver.max_frames_per_goal + most_path_frames(problem, goal)
        assert 0 <= report.frames and (timed or report.frames <= cap)
        if report.first_frame >= 0:
            rows = np.nonzero(traj.goal == k)[0]
            assert report.last_frame == rows[-1]
            assert report.final_distance == pytest.approx(traj.distance[report.last_frame])
        if report.reached:
            # holds: the goal's last frames repeat the reached pose
            hold = hold_frames(problem, problem.goals[k])
            if hold:
                last = report.last_frame
                assert np.all(traj.phi[last - hold + 1 : last + 1] == traj.phi[last])
                assert np.all(traj.reached[last - hold + 1 : last + 1])
    assert solution.reached == sum(g.reached for g in solution.goals)
