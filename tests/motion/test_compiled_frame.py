"""The compiled frame (:mod:`armanim.motion.solvers.compiled_frame`) against the numpy frame it
compiles (:func:`armanim.motion.solvers.proposed_step` through the filter
:func:`armanim.motion.solvers.barrier.safe_step`, the oracle, ``tunables.ik.compiled_frames``
off): at the states of real runs (general arms among spheres, boxes, capsules and a floor, the
bundled robots among spheres with their own pairs; goals with and without an orientation), the
same proposal and the same step, the same new pose, clearances and gaps, to 1e-12 times the tip
task's conditioning; whole runs keep every invariant and end as the numpy runs."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from invariants import assert_trajectory_invariants
from strategies import cluttered_problems, problems, robot_problems, shaped_problems

from armanim.arm.kinematics import tip_jacobian
from armanim.arm.linalg import PINV_RTOL, pseudo_inverse
from armanim.arm.rotations import rotation_exp
from armanim.motion.cost import self_influence
from armanim.motion.orientation import Orientation, orientation_task
from armanim.motion.problem import Problem
from armanim.motion.solvers import proposed_step, solver_method
from armanim.motion.solvers.barrier import safe_step
from armanim.motion.solvers.common import ArmState, arm_state, jacobian_of_capsule_point, self_pair_jacobians
from armanim.motion.solvers.compiled_frame import frame_step
from armanim.motion.trajectory import solve_trajectory
from armanim.scene import scene_model, scene_to_problem

TOL = 1e-12
"""Radians (and scene units for clearances and gaps), relative to the size of what is compared
(at least 1) and, for what follows from a proposal, to the conditioning of the tasks it inverts
(:func:`conditioning`): an inverse computed two ways (LAPACK's SVD, the compiled one) agrees to
about eps times it, and a task second in priority inverts the first's rounding again."""

LINEAR = st.sampled_from(["pinv", "dls"])


def numpy_frames(problem: Problem) -> Problem:
    return replace(problem, tunables=replace(problem.tunables, ik=replace(problem.tunables.ik, compiled_frames=False)))


def linear(problem: Problem, method: str) -> Problem:
    """The problem with a compiled method and the analytic Jacobian, goals without an orientation."""
    return replace(problem, solver=replace(problem.solver, method=method, jacobian="analytic"))


def close(a: np.ndarray, b: np.ndarray, tol: float = TOL) -> bool:
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    if not np.array_equal(np.isfinite(a), np.isfinite(b)):
        return False
    both = np.isfinite(a)
    scale = max(1.0, float(np.abs(np.where(both, b, 0.0)).max(initial=0.0)))
    with np.errstate(invalid="ignore"):  # inf - inf where neither is finite: not compared
        return bool(np.all(np.abs(np.where(both, a - b, 0.0)) <= tol * scale))


def condition(matrix: np.ndarray, scale: float = 0.0) -> float:
    """Largest singular value over the least one the pseudo-inverse keeps (1 at least); with
    ``scale``, the size its entries' rounding is relative to, at least ``scale`` over that least
    value: a matrix made from a larger one (the rotation task in the tip task's null space, whose
    projector rounds at the rotation task's size) can keep a singular value far below that
    rounding's scale, and its inverse carries the rounding up by their ratio."""
    d = np.linalg.svd(matrix, compute_uv=False)
    kept = d[d > PINV_RTOL * d[0]] if len(d) and d[0] > 0 else d[:0]
    return max(1.0, float(kept[0] / kept[-1]), float(scale / kept[-1])) if len(kept) else 1.0


def damped_condition(matrix: np.ndarray, damping: float) -> float:
    """Condition number of M M^T + lambda^2 I, what the damped inverse solves with (m x m)."""
    d = np.linalg.svd(matrix, compute_uv=False)
    eig = np.zeros(matrix.shape[0])
    eig[:len(d)] = d * d
    return float((eig.max() + damping**2) / (eig.min() + damping**2))


def conditioning(problem: Problem, state: ArmState, orientation: Orientation | None) -> float:
    """Of the tasks a step inverts, in turn: the tip's Jacobian; for a goal with an orientation,
    the rotation task in the tip task's null space (w B J_w (I - J^+ J)), which acts on the first's
    rounding; the Jacobians of the points the obstacles and the arm's own pairs push, projected
    through both. Each stage's condition number (for ``dls`` also its damped Gram matrix's; for
    the rotation task, relative to its size before the projection: :func:`condition`), their
    product: what rounding in one stage may be multiplied by in the next."""
    dls = problem.solver.method == "dls"

    def stage(tasks: list[np.ndarray], scale: float = 0.0) -> float:
        kappa = max((condition(task, scale) for task in tasks), default=1.0)
        if dls:
            kappa = max([kappa] + [damped_condition(task, problem.solver.damping) for task in tasks])
        return kappa

    jac = tip_jacobian(problem.arm, state.pose)
    kappa = stage([jac])
    if orientation is not None:
        _, jac_w = orientation_task(orientation, problem.arm, state.pose)
        jac_r = problem.solver.orientation_weight * jac_w
        kappa *= stage([jac_r @ (np.eye(problem.arm.n) - pseudo_inverse(jac) @ jac)], float(np.linalg.norm(jac_r, 2)))
    pushed = []
    cl = state.clearance
    if cl is not None:  # the links pushed off obstacles: each point's Jacobian is inverted
        parts, columns = np.nonzero((cl.d[:-1] > 0) & (cl.d[:-1] < problem.obstacles.influence))
        pushed.extend(jacobian_of_capsule_point(problem, state.phi, state.pose, parts, cl.t[parts, columns]))
    gaps = state.self_gaps
    if gaps is not None:  # the pairs pushed apart: each J_A - J_B is inverted
        which = np.nonzero((gaps.d > 0) & (gaps.d < self_influence(problem)))[0]
        pushed.extend(self_pair_jacobians(problem, state.phi, state.pose, gaps, which))
    return kappa * stage(pushed)


def frames_agree(problem: Problem, stride: int = 3) -> tuple[int, int]:
    """Every ``stride``-th state of the numpy run of ``problem``: the compiled frame against the
    numpy one. Returns how many frames were compared and how many the compiled one took whole."""
    oracle = numpy_frames(problem)
    solution = solve_trajectory(oracle)
    traj = solution.trajectory
    method = problem.solver.method
    compared = taken = 0
    for i in range(0, traj.frames, stride):
        goal = problem.goals[int(traj.goal[i])]
        state = arm_state(problem, traj.phi[i])
        moved, dphi = frame_step(problem, method, state, goal.position, goal.orientation)
        proposal = proposed_step(oracle, solver_method(method), state, goal.position, goal.orientation).dphi
        expected = safe_step(oracle, state, proposal)
        compared += 1
        if dphi is None:  # an inverse failed: the numpy frame was taken
            assert moved is None
            continue
        tol = TOL * conditioning(problem, state, goal.orientation)
        assert close(dphi, proposal, tol), (i, dphi, proposal)
        if moved is None:  # the numpy filter takes the proposal
            continue
        taken += 1
        length = float(np.linalg.norm(proposal))
        slack = TOL + (expected.scale * tol * max(1.0, length) / length if length > 0 else 0.0)
        if abs(moved.scale - expected.scale) > slack:
            # The proposals agree to rounding (above), but a joint's rounding-level component decided
            # the scale (a joint on its kept bound: a halving's edge, or its room over a component of
            # 1e-13): the filters must then take the same proposal alike.
            expected = safe_step(oracle, state, dphi)
            assert abs(moved.scale - expected.scale) <= slack, (i, moved.scale, expected.scale)
        assert moved.blocked_by == expected.blocked_by, i
        assert close(moved.phi, expected.phi, tol), (i, moved.phi, expected.phi)
        assert abs(moved.scale - expected.scale) <= slack, (i, moved.scale, expected.scale)
        if expected.state is state:  # no halving kept the guarantees: the arm stays
            assert moved.state is state
            continue
        assert close(moved.state.pose.points, expected.state.pose.points, tol)
        assert close(moved.state.pose.axes, expected.state.pose.axes, tol)
        if expected.state.clearance is not None:
            for got, want in zip((moved.state.clearance.d, moved.state.clearance.t, moved.state.clearance.normal),
                                 (expected.state.clearance.d, expected.state.clearance.t, expected.state.clearance.normal)):
                assert close(got, want, tol), i
        else:
            assert moved.state.clearance is None
        if expected.state.self_gaps is not None:
            got, want = moved.state.self_gaps, expected.state.self_gaps
            assert close(got.d, want.d, tol) and close(got.normal, want.normal, tol) and close(got.least, want.least, tol), i
            assert close(got.t, want.t, tol) and close(got.s, want.s, tol), i
        else:
            assert moved.state.self_gaps is None
    return compared, taken


SETTINGS = dict(deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])


@settings(max_examples=25, **SETTINGS)
@given(st.one_of(problems(methods=("pinv", "dls")), cluttered_problems(max_goals=2)), LINEAR)
def test_general_arms_among_spheres_take_the_numpy_frames(problem, method):
    frames_agree(linear(problem, method))


def with_orientations(problem: Problem, seed: int, kind: str) -> Problem:
    """The problem with each goal given an orientation: a random rotation (``kind`` "rotation")
    or tool axis ("axis"), which the arm may or may not be able to hold there."""
    rng = np.random.default_rng(seed)
    goals = []
    for goal in problem.goals:
        if kind == "rotation":
            orientation = Orientation(rotation=rotation_exp(rng.normal(0.0, 1.5, 3)))
        else:
            orientation = Orientation(axis=rng.normal(0.0, 1.0, 3))
        goals.append(replace(goal, orientation=orientation))
    return replace(problem, goals=tuple(goals))


@settings(max_examples=25, **SETTINGS)
@given(st.one_of(problems(methods=("pinv", "dls")), robot_problems(robots=("panda", "ur5", "iiwa"))), LINEAR,
       st.integers(0, 2**32 - 1), st.sampled_from(["rotation", "axis"]))
def test_goals_with_an_orientation_take_the_numpy_frames(problem, method, seed, kind):
    frames_agree(with_orientations(linear(problem, method), seed, kind))


@settings(max_examples=20, **SETTINGS)
@given(robot_problems(robots=("panda", "ur5", "iiwa")), LINEAR)
def test_robots_among_spheres_with_their_own_pairs_take_the_numpy_frames(problem, method):
    frames_agree(linear(problem, method))


@settings(max_examples=8, **SETTINGS)
@given(shaped_problems(max_goals=2, max_frames=30), LINEAR)
def test_other_shapes_and_a_floor_take_the_numpy_frames(problem, method):
    frames_agree(linear(problem, method), stride=4)


@settings(max_examples=8, **SETTINGS)
@given(shaped_problems(max_goals=2, max_frames=30, cylinders=True), LINEAR)
def test_cylinders_take_the_numpy_frames(problem, method):
    frames_agree(linear(problem, method), stride=4)


@pytest.mark.parametrize("method", ["pinv", "dls"])
def test_a_robot_run_among_cylinders_is_the_numpy_run(method):
    problem = scene_to_problem(scene_model({
        "version": 1, "arm": {"robot": "panda"},
        "obstacles": [{"cylinder": {"center": [0.45, 0.1, 0.4], "length": 0.2, "radius": 0.04}, "influence": 0.1},
                      {"cylinder": {"center": [0.2, -0.35, 0.5], "length": 0.3, "radius": 0.03, "rpy": [90, 0, 0]}, "influence": 0.1}],
        "goals": [[0.5, 0.2, 0.3], [0.3, -0.45, 0.4], [-0.2, 0.4, 0.6]],
        "solver": {"method": method, "planner": "off", "tolerance": 0.005, "clearance": 0.02, "max_step": 0.02}}))
    compared, taken = frames_agree(problem, stride=1)
    assert taken >= 10  # the compiled frames are taken here, not a path never taken
    fast, slow = solve_trajectory(problem), solve_trajectory(numpy_frames(problem))
    assert fast.trajectory.frames == slow.trajectory.frames
    assert [g.reason for g in fast.goals] == [g.reason for g in slow.goals]
    assert np.abs(fast.trajectory.phi - slow.trajectory.phi).max() < 1e-9
    assert_trajectory_invariants(problem, fast)


@pytest.mark.parametrize("method", ["pinv", "dls"])
def test_a_robot_run_among_spheres_is_the_numpy_run(method):
    problem = scene_to_problem(scene_model({
        "version": 1, "arm": {"robot": "panda"},
        "obstacles": [{"center": [0.45, 0.1, 0.45], "radius": 0.05, "influence": 0.1},
                      {"center": [0.2, -0.35, 0.5], "radius": 0.06, "influence": 0.1}],
        "goals": [[0.5, 0.2, 0.3], [0.3, -0.45, 0.4], [-0.2, 0.4, 0.6]],
        "solver": {"method": method, "planner": "off", "tolerance": 0.005, "clearance": 0.02, "max_step": 0.02}}))
    compared, taken = frames_agree(problem, stride=1)
    assert taken >= 10  # the compiled frames are taken here, not a path never taken
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

    problem = scene_to_problem(scene_model({
        "version": 1, "arm": {"robot": "panda"},
        "obstacles": [{"center": [0.0, -0.25, 0.05], "radius": 0.05, "influence": 0.2}],
        "goals": [[-0.12, 0.1, 0.12]],
        "solver": {"method": method, "planner": "off", "tolerance": 0.005, "clearance": 0.02, "max_step": 0.02,
                   "self_clearance": 0.01}}))
    compared, taken = frames_agree(problem, stride=1)
    assert taken >= 10
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
