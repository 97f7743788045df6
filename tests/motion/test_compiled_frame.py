"""The compiled frame (:mod:`armanim.motion.kernels.frame`) in whole runs: runs among cylinders,
spheres and beside the Panda's base end as the numpy runs (``tunables.ik.compiled_frames`` off, the
oracle), and compiled runs keep every invariant. Frame by frame, the compiled frame is held to the
numpy frame by the lockstep harness (tests/motion/kernels/test_lockstep.py)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from invariants import assert_trajectory_invariants
from strategies import robot_problems
from test_lockstep import LINEAR, SCENES, linear

from armanim.motion.problem import Problem
from armanim.motion.trajectory import solve_trajectory

SETTINGS = dict(deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])


def numpy_frames(problem: Problem) -> Problem:
    return replace(problem, tunables=replace(problem.tunables, ik=replace(problem.tunables.ik, compiled_frames=False)))


@pytest.mark.parametrize("method", ["pinv", "dls"])
def test_a_robot_run_among_cylinders_is_the_numpy_run(method):
    problem = SCENES["cylinders"](method)
    fast, slow = solve_trajectory(problem), solve_trajectory(numpy_frames(problem))
    assert fast.trajectory.frames == slow.trajectory.frames
    assert [g.reason for g in fast.goals] == [g.reason for g in slow.goals]
    assert np.abs(fast.trajectory.phi - slow.trajectory.phi).max() < 1e-9
    assert_trajectory_invariants(problem, fast)


@pytest.mark.parametrize("method", ["pinv", "dls"])
def test_a_robot_run_among_spheres_is_the_numpy_run(method):
    problem = SCENES["spheres"](method)
    fast, slow = solve_trajectory(problem), solve_trajectory(numpy_frames(problem))
    assert fast.trajectory.frames == slow.trajectory.frames
    assert [g.reached for g in fast.goals] == [g.reached for g in slow.goals]
    assert [g.reason for g in fast.goals] == [g.reason for g in slow.goals]
    assert np.abs(fast.trajectory.phi - slow.trajectory.phi).max() < 1e-9
    assert_trajectory_invariants(problem, fast)


@pytest.mark.parametrize("method", ["pinv", "dls"])
def test_a_run_beside_the_base_is_the_numpy_run(method):
    """The Panda's base (carrier -1: its capsules in the world, Jacobian columns all zero) in play in
    both frames: a sphere within the base's influence (no push, no row: the base never moves) and a
    goal behind the base (pairs of the base and the hand in the filter's rows)."""
    from armanim.arm.capsules import BASE
    from armanim.arm.kinematics import forward
    from armanim.world.selfdistances import self_gaps

    problem = SCENES["beside the base"](method)
    fast, slow = solve_trajectory(problem), solve_trajectory(numpy_frames(problem))
    assert fast.trajectory.frames == slow.trajectory.frames
    assert np.abs(fast.trajectory.phi - slow.trajectory.phi).max() < 1e-9
    caps, pairs = problem.capsules, problem.self_pairs
    base = caps.link[pairs.first] == BASE
    gaps = self_gaps(forward(problem.arm, fast.trajectory.phi), caps, pairs).d[:, base]
    assert gaps.min() < 0.02  # the base's pairs came within the filter's reach (self_clearance 0.01)
    assert_trajectory_invariants(problem, fast)


@settings(max_examples=15, **SETTINGS)
@given(robot_problems(robots=("panda", "ur5", "iiwa")), LINEAR)
def test_compiled_runs_keep_every_invariant(problem, method):
    problem = linear(problem, method)
    assert_trajectory_invariants(problem, solve_trajectory(problem))
