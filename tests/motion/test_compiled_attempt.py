"""The compiled pose-solve attempt (:mod:`armanim.motion.solvers.compiled`) against the numpy
steps it compiles (:func:`armanim.motion.solvers.linear.linear_step` through the filter
:func:`armanim.motion.solvers.barrier.safe_step`, the oracle), step by step over an attempt's
first steps on the Panda (with and without its self-collision), UR5, iiwa and the notes' arm,
for 6-D, tool-axis and position goals: from each compiled iterate, the next equals the numpy
step's to 1e-9 where no row of the arm's own pairs is active in the filter's QP; where one is,
the compiled step solves that QP (the numpy filter's own rows and bounds at that pose) exactly,
by its KKT conditions checked directly (DAQP, the numpy filter's solver, meets them only to its
tolerance, some 1e-7: the two steps differ by up to 1e-5 rad there), unless the compiled loop
hands that step back (the QP's active rows dependent to rounding): then it is the numpy step.
Whole solves meet the tolerances by the numpy chain's FK, inside the limits and with the arm's
own pairs apart; its small linear algebra against numpy's and LAPACK's."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st
from strategies import poses, problems

from armanim.arm.kinematics import forward, tip_jacobian, tool_rotation
from armanim.arm.linalg import PINV_RTOL, pseudo_inverse
from armanim.motion import ik
from armanim.motion.orientation import Orientation, orientation_angle
from armanim.motion.problem import Goal, Limits, Problem
from armanim.motion.solvers import compiled, proposed_step, solver_method
from armanim.motion.solvers.barrier import (
    Constraints,
    clearly_allowed,
    closest_safe_step,
    filter_constraints,
    filtered_step,
    joint_bounds,
    within_limits,
)
from armanim.motion.solvers.common import arm_state
from armanim.motion.solvers.linear import damped_inverse
from armanim.scene import default_solver_settings, scene_model, scene_to_problem
from armanim.world.obstacles import Obstacles
from armanim.world.selfdistances import self_gaps

ITERATE_TOL = 1e-9
"""Radians, times the conditioning of the tip's task along the way (1 to 10 on the robots; the
notes' arm turning its tool as close as it can, a task second in priority, passes poses near its
straight singular one)."""


def robot(name: str, method: str, self_collision: str = "auto") -> Problem:
    return scene_to_problem(scene_model({
        "version": 1, "arm": {"robot": name, "self_collision": self_collision}, "goals": [[0.4, 0.0, 0.4]],
        "solver": {"method": method, "tolerance": 0.001, "orientation_tolerance": 1}}))


def notes_arm(method: str) -> Problem:
    """The course notes' arm (z, y, y, y; links 2, 5, 5, 5) with limits on its last three joints."""
    from armanim.arm.kinematics import Arm

    lower = np.radians([-np.inf, -100.0, -150.0, -150.0])
    return Problem(arm=Arm.from_names([2.0, 5.0, 5.0, 5.0], base=(5.0, 5.0, 0.0)), half_width=0.3, home=np.zeros(4),
                   limits=Limits(lower=lower, upper=-lower, margin=float(np.radians(15.0))), obstacles=Obstacles.none(),
                   goals=(Goal(np.zeros(3), hold=0.0),), solver=default_solver_settings(method=method, tolerance=1e-3), fps=30.0)


ARMS = {
    "panda": lambda m: robot("panda", m, "off"),
    "panda-self": lambda m: robot("panda", m),
    "ur5": lambda m: robot("ur5", m),
    "iiwa": lambda m: robot("iiwa", m),
    "notes": notes_arm,
}
_PROBLEMS: dict[tuple[str, str], Problem] = {}


def problem_of(name: str, method: str) -> Problem:
    if (name, method) not in _PROBLEMS:
        _PROBLEMS[name, method] = ARMS[name](method)
    return _PROBLEMS[name, method]


def numpy_only(problem: Problem) -> Problem:
    return replace(problem, tunables=replace(problem.tunables, ik=replace(problem.tunables.ik, compiled=False)))


def target_of(problem: Problem, seed: int, kind: str) -> tuple[np.ndarray, Orientation | None, np.ndarray]:
    """A reachable goal: the tip (and the tool's rotation or z axis) of a random pose inside the limits; and that pose."""
    rng = np.random.default_rng(seed)
    lo = np.maximum(problem.limits.lower, -np.pi) + 0.1
    hi = np.minimum(problem.limits.upper, np.pi) - 0.1
    phi = rng.uniform(lo, hi)
    pose = forward(problem.arm, phi)
    rot = tool_rotation(problem.arm, pose)
    orientation = {"pose": Orientation(rotation=rot), "axis": Orientation(axis=rot[:, 2]), "position": None}[kind]
    return pose.tip, orientation, phi


def start_of(problem: Problem, seed: int, from_home: bool) -> np.ndarray:
    if from_home:
        return problem.home
    rng = np.random.default_rng(seed + 1)
    lo = np.maximum(problem.limits.lower, -np.pi) + 0.05
    hi = np.minimum(problem.limits.upper, np.pi) - 0.05
    return rng.uniform(lo, hi)


@settings(max_examples=40, deadline=None)
@given(name=st.sampled_from(sorted(ARMS)), method=st.sampled_from(["pinv", "dls"]), seed=st.integers(0, 2**31),
       kind=st.sampled_from(["pose", "axis", "position"]), from_home=st.booleans())
# The cases the search found in CI (eee6f58: the UR5's twin capsules give 7 active rows of rank 3,
# whose least-norm multipliers had a negative entry); both fail with that commit's parent's test.
# Its Panda seed 1124805897 and 4283247's Panda seed 448: their method, kind and start were not
# recorded; pinned here are the combinations whose steps meet the pair QP (1124805897, from a random
# start) or are handed back to the numpy path (448, a tool-axis goal from a random start), as those
# commits describe. 448 with a position goal from a random start fails today: see
# test_panda_seed_448_position_step_is_the_numpy_step below.
@example(name="ur5", method="pinv", seed=249955419, kind="position", from_home=False)
@example(name="ur5", method="dls", seed=249955419, kind="position", from_home=False)
@example(name="panda-self", method="pinv", seed=1124805897, kind="position", from_home=False)
@example(name="panda-self", method="dls", seed=1124805897, kind="position", from_home=False)
@example(name="panda-self", method="pinv", seed=448, kind="axis", from_home=False)
@example(name="panda-self", method="dls", seed=448, kind="axis", from_home=False)
def test_the_compiled_attempt_takes_the_numpy_steps(name, method, seed, kind, from_home):
    problem = ik.solving_problem(problem_of(name, method))
    oracle = ik.solving_problem(numpy_only(problem_of(name, method)))
    goal, orientation, _ = target_of(problem, seed, kind)
    start = start_of(problem, seed, from_home)
    chosen = solver_method(method)
    assert ik.runs_compiled(problem, chosen) and not ik.runs_compiled(oracle, chosen)
    before = start
    for budget in range(1, 7):
        got = ik._attempt(problem, chosen, goal, start, budget, orientation)
        ended = assert_the_numpy_step(problem, oracle, chosen, goal, orientation, before, budget - 1, got)
        if ended:  # the attempt ended before its budget: so did the compiled one, at the same step
            break
        before = got.phi


@pytest.mark.xfail(strict=True, reason="known: the compiled attempt's step where the pair QP acts is 0.9x the numpy "
                   "path's (Panda seed 448, a position goal from a random start; found 2026-12-06, left to the motion work)")
@pytest.mark.parametrize("method", ["pinv", "dls"])
def test_panda_seed_448_position_step_is_the_numpy_step(method):
    """The Panda seed 448 of 4283247 with a position goal from its random start: the compiled step
    differs from the numpy one by 10 % (6 of 7 joints past DAQP's 1e-4). Strict: it reports when fixed,
    and then belongs among the @example cases above."""
    test_the_compiled_attempt_takes_the_numpy_steps.hypothesis.inner_test(
        name="panda-self", method=method, seed=448, kind="position", from_home=False)


QP_KKT = 1e-12
"""Of the filter's QP (radians): each constraint met to this, and the active ones' multipliers'
stationarity to ``QP_KKT`` times the step's scale."""


def assert_the_numpy_step(problem: Problem, oracle: Problem, chosen, goal, orientation, before: np.ndarray, steps: int, got) -> bool:
    """The compiled attempt ``got`` (of ``steps + 1`` steps) took, from its iterate ``before`` (of
    ``steps`` steps), the numpy step from there (the oracle's proposal through its filter): to
    :data:`ITERATE_TOL` where no pair's row is active in the filter's QP, else the exact answer of
    that QP (the oracle's rows and bounds at ``before``: KKT conditions, :func:`assert_solves_the_qp`).
    Returns whether the attempt ended there (both did)."""
    state = arm_state(oracle, before)
    one, _, _, stopped, _ = ik._steps(oracle, chosen, goal, state, 1, orientation)
    assert (got.steps - steps, got.numerical) == (one.steps, one.numerical)
    tol = ITERATE_TOL * max(tip_condition(problem, before), tip_condition(problem, one.phi))
    qp = pair_qp(oracle, chosen, goal, orientation, state)
    if qp is None or hands_back(problem, chosen, goal, orientation, before):  # no pair's row acts, or the numpy step takes it
        np.testing.assert_allclose(got.phi, one.phi, atol=tol, rtol=0)
        np.testing.assert_allclose(got.tip, one.tip, atol=tol * problem.arm.reach, rtol=0)
        np.testing.assert_allclose(got.errors[2], one.errors[2], atol=tol * problem.arm.reach, rtol=0)
    else:
        nominal, cons, daqp = qp
        taken, taken_numpy = wrapped(oracle, got.phi - before), wrapped(oracle, one.phi - before)
        halvings = 0 if not np.any(taken_numpy) else round(np.log2(np.linalg.norm(daqp) / np.linalg.norm(taken_numpy)))
        # the step is read back from two iterates (rounding eps |phi|), then doubled back over the halvings
        readback = 2.0**halvings * 4 * np.finfo(float).eps * max(1.0, float(np.abs(before).max()))
        assert_solves_the_qp(taken * 2.0**halvings, nominal, cons, QP_KKT + readback)
        np.testing.assert_allclose(taken, taken_numpy, atol=1e-4, rtol=0)  # DAQP's answer, to its tolerance
    return stopped


def hands_back(problem: Problem, chosen, goal, orientation, before: np.ndarray) -> bool:
    """Whether the compiled loop hands the step from ``before`` back to the numpy path (its QP's
    active rows dependent to rounding, a gap at its floor: the module's hand-back), so that the
    attempt takes the numpy step there, to rounding."""
    step, stacked = ik._compiled_plan(problem, chosen, orientation)  # as the attempt runs it
    ran = compiled.run_attempt(problem, step, stacked, goal, before, 1, orientation)
    return ran.handed_back and ran.steps == 0


def wrapped(problem: Problem, dphi: np.ndarray) -> np.ndarray:
    """A step between two iterates, its unlimited joints' part wrapped into (-pi, pi]."""
    return np.where(problem.limits.limited, dphi, (dphi + np.pi) % (2 * np.pi) - np.pi)


def pair_qp(oracle: Problem, chosen, goal, orientation, state) -> tuple[np.ndarray, Constraints, np.ndarray] | None:
    """Where the numpy filter solves a QP with a pair's row active at its answer: the nominal step,
    the constraints (relaxed where the numpy filter relaxes them) and DAQP's answer; else None."""
    dphi = proposed_step(oracle, chosen, state, goal, orientation).dphi
    biggest = float(np.abs(dphi).max(initial=0.0))
    if not 0.0 < biggest < np.inf:
        return None
    nominal = dphi * min(1.0, oracle.solver.max_joint_step / biggest)
    bounds = joint_bounds(oracle, state.phi)
    if clearly_allowed(oracle, state, nominal, bounds):
        return None
    cons = filter_constraints(oracle, state, nominal, bounds)
    if not len(cons.rows) or cons.violated_by(nominal) is None:
        return None
    if closest_safe_step(nominal, cons) is None:
        cons = Constraints(cons.rows, np.minimum(cons.lower, 0.0), cons.lo, cons.hi)
    answer = filtered_step(nominal, cons)
    if not np.any(cons.rows @ answer - cons.lower < 1e-6):
        return None  # DAQP's answer meets every pair's row with room: it is the box's clip, exactly
    return nominal, cons, answer


def assert_solves_the_qp(x: np.ndarray, nominal: np.ndarray, cons: Constraints, tol: float = QP_KKT) -> None:
    """x minimises |x - nominal|^2 subject to ``cons`` (rows x >= lower, lo <= x <= hi): every
    constraint met to ``tol`` (primal feasibility), and x - nominal = A_act^T lambda for some
    lambda >= 0 on the constraints x meets with equality (stationarity, dual feasibility; the
    others' multipliers are 0: complementary slackness). The multipliers are found by
    non-negative least squares: where the active rows are dependent (a robot's twin capsules
    give equal rows) many lambda solve the equation, and the least-norm one may have a
    negative entry where a non-negative one exists."""
    from scipy.optimize import nnls

    n = len(x)
    a = np.concatenate([cons.rows, np.eye(n), -np.eye(n)])
    b = np.concatenate([cons.lower, cons.lo, -cons.hi])
    slack = a @ x - b
    assert slack.min() >= -tol, f"a constraint broken by {-slack.min():.3g}"
    active = slack <= max(1e-9, 10 * tol)  # met with equality, to the reading of x
    lam, _ = nnls(a[active].T, x - nominal)  # dual feasibility: lambda >= 0 by construction
    scale = max(1.0, float(np.abs(nominal).max()))
    assert np.abs(a[active].T @ lam - (x - nominal)).max() <= 1e3 * tol * scale  # stationarity
    assert any(active[: len(cons.rows)])  # a pair's row is active: the case this check is for


def tip_condition(problem: Problem, phi: np.ndarray) -> float:
    """The condition number of the tip's Jacobian at ``phi`` (its singular values that the
    pseudo-inverse keeps), at least 1: how much a step's rounding may grow."""
    d = np.linalg.svd(tip_jacobian(problem.arm, forward(problem.arm, phi)), compute_uv=False)
    kept = d[d > PINV_RTOL * d[0]]
    return max(1.0, float(d[0] / kept[-1])) if d[0] > 0 else 1.0


@settings(max_examples=60, deadline=None)
@given(problem=problems(methods=["pinv", "dls"], max_links=7), data=st.data(), kind=st.sampled_from(["pose", "axis", "position"]))
def test_the_compiled_attempt_takes_the_numpy_steps_on_any_arm(problem, data, kind):
    # general arms, limits and settings (obstacles left out: those attempts are the numpy steps'); an arm that
    # cannot hold the goal's orientation stays with the numpy steps, which amplify rounding there
    problem = replace(problem, obstacles=Obstacles.none(), solver=replace(problem.solver, jacobian="analytic"))
    solving, oracle = ik.solving_problem(problem), ik.solving_problem(numpy_only(problem))
    pose = forward(problem.arm, data.draw(poses(problem.arm.n)))
    rot = tool_rotation(problem.arm, pose)
    orientation = {"pose": Orientation(rotation=rot), "axis": Orientation(axis=rot[:, 2]), "position": None}[kind]
    chosen = solver_method(problem.solver.method)
    before = problem.home
    for budget in range(1, 7):
        got = ik._attempt(solving, chosen, pose.tip, problem.home, budget, orientation)
        if assert_the_numpy_step(solving, oracle, chosen, pose.tip, orientation, before, budget - 1, got):
            break
        before = got.phi


@settings(max_examples=30, deadline=None)
@given(name=st.sampled_from(sorted(ARMS)), method=st.sampled_from(["pinv", "dls"]), seed=st.integers(0, 2**31),
       kind=st.sampled_from(["pose", "axis", "position"]))
def test_compiled_solves_meet_the_tolerances_by_the_numpy_chain(name, method, seed, kind):
    problem = problem_of(name, method)
    goal, orientation, _ = target_of(problem, seed, kind)
    solution = ik.solve_pose(problem, goal, problem.home, 2000, orientation=orientation)
    if not solution.converged:
        return  # a miss is allowed (the notes' arm cannot hold every orientation); what converges must be right
    pose = forward(problem.arm, solution.phi)  # the numpy chain, not the kernel
    assert np.linalg.norm(pose.tip - goal) < problem.solver.tolerance
    np.testing.assert_allclose(solution.tip, pose.tip, atol=1e-12 * problem.arm.reach, rtol=0)
    if orientation is not None:
        assert float(orientation_angle(orientation, tool_rotation(problem.arm, pose))) < problem.solver.orientation_tolerance
    assert within_limits(problem, solution.phi[None])[0]
    if len(problem.self_pairs):
        assert self_gaps(pose, problem.capsules, problem.self_pairs).least >= problem.self_pairs.clearance


@pytest.mark.parametrize("name", ["panda", "ur5", "iiwa", "notes"])
@pytest.mark.parametrize("method", ["pinv", "dls"])
def test_compiled_solves_end_as_the_numpy_solves(name, method):
    problem = problem_of(name, method)
    oracle = numpy_only(problem)
    same = 0
    for seed in range(8):
        goal, orientation, _ = target_of(problem, seed, "position" if name == "notes" else "pose")
        got = ik.solve_pose(problem, goal, problem.home, 2000, orientation=orientation)
        expected = ik.solve_pose(oracle, goal, problem.home, 2000, orientation=orientation)
        assert got.status == expected.status
        if (got.steps, got.restarts, got.found_by) == (expected.steps, expected.restarts, expected.found_by):
            np.testing.assert_allclose(got.phi, expected.phi, atol=1e-7, rtol=0)
            same += 1
    assert same >= 7  # rounding may tip a stall test late in a long solve, rarely


def test_a_singular_damped_inverse_is_numerical_in_both():
    # dls without damping at the straight planar arm: J J^T is singular, numpy's solve raises,
    # the compiled elimination meets a zero pivot; both report the attempt as numerical
    from armanim.arm.kinematics import Arm

    problem = Problem(arm=Arm.from_names([1.0] * 3, axes=["z"] * 3, direction="x"), half_width=0.1, home=np.zeros(3),
                      limits=Limits.unlimited(3, 0.1), obstacles=Obstacles.none(), goals=(Goal(np.array([1.0, 1.0, 0.0]), hold=0.0),),
                      solver=default_solver_settings(method="dls", tolerance=1e-3, damping=0.0), fps=30.0)
    for p in (problem, numpy_only(problem)):
        result = ik.solve_pose(p, np.array([1.0, 1.0, 0.0]), np.zeros(3), max_iterations=50)
        assert result.status == "numerical" and result.restarts == 4


def test_the_compiled_attempt_keeps_a_near_pair_inside_the_call():
    # from the Panda's home, link3 and link5 are 2.8 cm apart: the filter's row of that pair acts on
    # the first large step; the compiled loop solves that QP itself (it handed the attempt back before)
    problem = ik.solving_problem(robot("panda", "pinv"))
    goal, orientation, _ = target_of(problem, 0, "pose")
    state = arm_state(problem, problem.home)
    assert pair_qp(numpy_only(problem), solver_method("pinv"), goal, orientation, state) is not None
    ran = compiled.run_attempt(problem, compiled.PINV, True, goal, problem.home, 1, orientation)
    assert not ran.handed_back and ran.steps == 1


def test_the_exact_qp_meets_its_kkt_conditions_where_daqp_meets_its_tolerance():
    # random filter QPs (rows and bounds as the filter's: 0 feasible) and infeasible ones
    rng = np.random.default_rng(3)
    started = 0
    for _ in range(300):
        n, k = 7, int(rng.integers(1, 6))
        rows = rng.normal(size=(k, n))
        cons = Constraints(rows, -rng.uniform(0, 0.3, k), -rng.uniform(0, 0.5, n), rng.uniform(0, 0.5, n))
        nominal = rng.normal(size=n)
        cmat = np.concatenate([np.eye(n), -np.eye(n), rows])
        cb = np.concatenate([cons.lo, -cons.hi, cons.lower])
        x, warm = np.empty(n), np.empty(n)
        assert compiled._closest_step(nominal, cmat, cb, len(cb), x) == 1
        if np.any(rows @ x - cons.lower <= 1e-9):
            assert_solves_the_qp(x, nominal, cons)
        np.testing.assert_allclose(x, closest_safe_step(nominal, cons), atol=1e-5)
        # started from the clip, with the bounds it breaks active: the same answer
        assert compiled._closest_step(nominal, cmat, cb, len(cb), warm, 2 * n) == 1
        np.testing.assert_allclose(warm, x, atol=1e-12, rtol=0)
        started += bool(np.any(nominal < cons.lo) or np.any(nominal > cons.hi))
    assert started > 100
    # no x meets x_0 >= 1 and x_0 <= 0.5
    cmat = np.array([[1.0, 0.0], [-1.0, 0.0]])
    assert compiled._closest_step(np.zeros(2), cmat, np.array([1.0, -0.5]), 2, np.empty(2)) == 0


matrices = st.tuples(st.integers(1, 7), st.integers(1, 7), st.integers(0, 2**31), st.integers(0, 3)).map(
    lambda a: _matrix(*a))


def _matrix(m: int, n: int, seed: int, drop: int) -> np.ndarray:
    """An m x n matrix, its rank cut by ``drop`` (a rank-deficient Jacobian, as at a singular pose)."""
    rng = np.random.default_rng(seed)
    mat = rng.normal(size=(m, n))
    if drop:
        u, d, vt = np.linalg.svd(mat, full_matrices=False)
        d[len(d) - min(drop, len(d) - 1):] = 0.0
        mat = (u * d) @ vt
    return mat


@settings(max_examples=200, deadline=None)
@given(mat=matrices)
def test_the_compiled_pseudo_inverse_is_lapacks(mat):
    m, n = mat.shape
    out = np.empty((n, m))
    c = min(m, n)
    compiled._pinv(mat, out, np.eye(c))
    np.testing.assert_allclose(out, pseudo_inverse(mat), atol=1e-9 * max(1.0, np.abs(pseudo_inverse(mat)).max()), rtol=0)


@settings(max_examples=100, deadline=None)
@given(mat=matrices, damping=st.floats(1e-3, 1.0))
def test_the_compiled_damped_inverse_is_numpys(mat, damping):
    m, n = mat.shape
    out = np.empty((n, m))
    assert compiled._damped(mat, damping, out)
    np.testing.assert_allclose(out, damped_inverse(mat, damping), atol=1e-9, rtol=1e-9)


def test_a_numpy_step_hands_the_attempt_back_to_the_compiled_loop(monkeypatch):
    # the numpy path takes only the handed-back step: the compiled loop goes on from there
    problem = robot("panda", "pinv")
    calls = []
    run = compiled.run_attempt

    def spy(*args, **kwargs):
        calls.append(args[4])
        return run(*args, **kwargs)

    monkeypatch.setattr(compiled, "run_attempt", spy)
    goal, orientation, _ = target_of(problem, 0, "pose")
    ik.solve_pose(problem, goal, problem.home, 2000, orientation=orientation)
    assert len(calls) > 1 and np.array_equal(calls[0], problem.home)
    state = arm_state(problem, calls[1])
    assert np.all(np.isfinite(state.phi))


@pytest.mark.parametrize("name", ["panda-self", "ur5", "iiwa"])
def test_the_compiled_pairs_gaps_are_the_shared_closed_forms(name):
    # the attempt measures its spheres' pairs (a capsule of no length) in closed form, the shared
    # segment-segment function by its box form: the same gaps, closest points and normals to rounding
    from armanim.arm.kernel import _forward_one, packed_chain

    problem = problem_of(name, "pinv")
    caps, link, first, second, _, _ = compiled._pair_constants(problem)
    rows, root = packed_chain(problem.arm)
    n, count = problem.arm.n, len(first)
    lengths = np.linalg.norm(problem.capsules.end - problem.capsules.start, axis=1)
    rng = np.random.default_rng(11)
    for phi in rng.uniform(np.maximum(problem.limits.lower, -np.pi), np.minimum(problem.limits.upper, np.pi), (200, n)):
        points, frames, axes, tool = np.empty((n + 1, 3)), np.empty((n, 3, 3)), np.empty((n, 3)), np.empty((3, 3))
        _forward_one(rows, root, phi, points, frames, axes, tool)
        ends, gaps, near = np.empty((2, len(caps), 3)), np.empty(count), np.empty((count, 5))
        least = compiled._pair_gaps(points, frames, caps, link, first, second, ends, gaps, near)
        expected = self_gaps(forward(problem.arm, phi), problem.capsules, problem.self_pairs)
        np.testing.assert_allclose(gaps, expected.d, atol=1e-12, rtol=0)
        assert least == gaps.min()
        apart = expected.d > 1e-6
        np.testing.assert_allclose(near[apart, 2:], expected.normal[apart], atol=1e-9, rtol=0)
        spheres = apart & ((lengths[first] == 0) | (lengths[second] == 0))  # the pairs measured here (the others' closest
        # points may be a tie, parallel links, that the capsule ends' rounding decides either way)
        along_first, along_second = spheres & (lengths[first] > 0), spheres & (lengths[second] > 0)
        np.testing.assert_allclose(near[along_first, 0], expected.t[along_first], atol=1e-9, rtol=0)
        np.testing.assert_allclose(near[along_second, 1], expected.s[along_second], atol=1e-9, rtol=0)


def test_a_pose_solution_made_at_once_is_the_dataclasss():
    import dataclasses

    fields = dict(phi=np.zeros(2), tip=np.ones(3), distance=0.5, status="converged", steps=3, iterations=3, newton_iterations=0,
                  restarts=1, found_by="method", orientation_error=None)
    made, expected = ik._pose_solution(**fields), ik.PoseSolution(**fields)
    assert repr(made) == repr(expected) and made.converged and dataclasses.fields(made) == dataclasses.fields(expected)
    assert {f.name for f in dataclasses.fields(expected)} == set(fields)  # every field given
    with pytest.raises(dataclasses.FrozenInstanceError):
        made.steps = 4  # type: ignore[misc]
