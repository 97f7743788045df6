"""The compiled motion kernels in lockstep with the numpy line (:mod:`lockstep`): for each piece,
one test body run by both lines against the numpy oracle.

- the inverses: the pseudo-inverse against numpy's SVD (its cut-off :data:`PINV_RTOL`), the damped
  inverse against the normal equations of J^T J + lambda^2 I;
- the proposal: the frame's (:func:`armanim.motion.kernels.frame.frame_step`) against
  :func:`armanim.motion.solvers.proposed_step`, at random poses of general arms among spheres and
  the robots with their own pairs, goals with and without an orientation;
- the filter's QP: its KKT conditions (DAQP, the numpy filter's solver, meets them to its
  tolerance; the compiled exact QP to rounding), the two answers against each other;
- the check: the arm's own pairs' gaps, closest points and normals against
  :func:`armanim.world.selfdistances.self_gaps`;
- the attempt's step: from each iterate of an attempt (:func:`armanim.motion.ik._attempt`), the next
  is the numpy step's (:func:`armanim.motion.ik._steps`) to 1e-9 times the tip's conditioning,
  or, where a pair's row is active in the filter's QP, that QP's exact answer;
- the frame: at the states of real runs (general arms among spheres, boxes, capsules, cylinders
  and a floor; the robots among spheres with their own pairs; goals with an orientation), the
  same proposal, step, new pose, clearances and gaps as the numpy frame, to 1e-12 times the
  tasks' conditioning (:func:`lockstep.conditioning`).

Every case a random search has found is pinned as an ``@example`` of its body (b3efd72, eee6f58).
Under the ``ci`` profile (tests/conftest.py) the draws are the same on every run of a commit.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, note, settings
from hypothesis import strategies as st
from lockstep import LINES, agree, assert_agree, conditioning, numpy_only, tip_condition
from strategies import cluttered_problems, poses, problems, robot_problems, shaped_problems

from armanim.arm.kernel import _forward_one
from armanim.arm.kinematics import forward, tool_rotation
from armanim.arm.linalg import PINV_RTOL, pseudo_inverse
from armanim.arm.rotations import rotation_exp
from armanim.motion import ik
from armanim.motion.filter.barrier import (
    Constraints,
    clearly_allowed,
    closest_safe_step,
    filter_constraints,
    filtered_step,
    joint_bounds,
    safe_step,
)
from armanim.motion.framestep import method_step
from armanim.motion.kernels import attempt, check, linalg, qp
from armanim.motion.kernels.frame import frame_step
from armanim.motion.kernels.plan import compiled_plan
from armanim.motion.orientation import Orientation
from armanim.motion.problem import Goal, Limits, Problem, step_caps
from armanim.motion.solution import Trajectory
from armanim.motion.solvers import proposed_step, solver_method
from armanim.motion.solvers.common import ArmState, arm_state
from armanim.motion.solvers.linear import damped_inverse
from armanim.motion.trajectory import solve_trajectory
from armanim.scene import default_solver_settings, scene_model, scene_to_problem
from armanim.world.obstacles import Obstacles
from armanim.world.selfdistances import self_gaps

SETTINGS = dict(deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
lines = pytest.mark.parametrize("line", LINES)


# ----------------------------------------------------------------------------- the problems


def robot(name: str, method: str, self_collision: str = "auto") -> Problem:
    return scene_to_problem(
        scene_model(
            {
                "version": 1,
                "arm": {"robot": name, "self_collision": self_collision},
                "goals": [[0.4, 0.0, 0.4]],
                "solver": {"method": method, "tolerance": 0.001, "orientation_tolerance": 1},
            }
        )
    )


def notes_arm(method: str) -> Problem:
    """The course notes' arm (z, y, y, y; links 2, 5, 5, 5) with limits on its last three joints."""
    from armanim.arm.kinematics import Arm

    lower = np.radians([-np.inf, -100.0, -150.0, -150.0])
    return Problem(
        arm=Arm.from_names([2.0, 5.0, 5.0, 5.0], base=(5.0, 5.0, 0.0)),
        half_width=0.3,
        home=np.zeros(4),
        limits=Limits(lower=lower, upper=-lower, margin=float(np.radians(15.0))),
        obstacles=Obstacles.none(),
        goals=(Goal(np.zeros(3), hold=0.0),),
        solver=default_solver_settings(method=method, tolerance=1e-3),
        fps=30.0,
    )


ARMS = {
    "panda": lambda m: robot("panda", m, "off"),
    "panda-self": lambda m: robot("panda", m),
    "ur5": lambda m: robot("ur5", m),
    "iiwa": lambda m: robot("iiwa", m),
    "notes": notes_arm,
}
SLIDING = {
    "ur5-rail": lambda m: robot("ur5_rail", m),  # a UR5 on a 2.5 m rail: its first joint prismatic, in metres
}
_PROBLEMS: dict[tuple[str, str], Problem] = {}


def problem_of(name: str, method: str) -> Problem:
    """The named arm's problem (:data:`ARMS`, :data:`SLIDING`), made once per session."""
    if (name, method) not in _PROBLEMS:
        _PROBLEMS[name, method] = {**ARMS, **SLIDING}[name](method)
    return _PROBLEMS[name, method]


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


def linear(problem: Problem, method: str) -> Problem:
    """The problem with a compiled method and the analytic Jacobian."""
    return replace(problem, solver=replace(problem.solver, method=method, jacobian="analytic"))


def with_orientations(problem: Problem, seed: int, kind: str) -> Problem:
    """The problem with each goal given an orientation: a random rotation (``kind`` "rotation")
    or tool axis ("axis"), which the arm may or may not be able to hold there."""
    rng = np.random.default_rng(seed)
    goals = []
    for goal in problem.goals:
        if kind == "rotation":
            orientation = Orientation(rotation=rotation_exp(rng.normal(0.0, 1.5, 3)))
        elif kind == "axis":
            orientation = Orientation(axis=rng.normal(0.0, 1.0, 3))
        else:
            orientation = None
        goals.append(replace(goal, orientation=orientation))
    return replace(problem, goals=tuple(goals))


LINEAR = st.sampled_from(["pinv", "dls"])
ORIENTED = st.sampled_from(["none", "rotation", "axis"])


# ----------------------------------------------------------------------------- the inverses


matrices = st.tuples(st.integers(1, 7), st.integers(1, 7), st.integers(0, 2**31), st.integers(0, 3)).map(
    lambda a: _matrix(*a)
)


def _matrix(m: int, n: int, seed: int, drop: int) -> np.ndarray:
    """An m x n matrix, its rank cut by ``drop`` (a rank-deficient Jacobian, as at a singular pose)."""
    rng = np.random.default_rng(seed)
    mat = rng.normal(size=(m, n))
    if drop:
        u, d, vt = np.linalg.svd(mat, full_matrices=False)
        d[len(d) - min(drop, len(d) - 1) :] = 0.0
        mat = (u * d) @ vt
    return mat


def inverse_of(line: str, mat: np.ndarray, damping: float | None) -> np.ndarray:
    """The pseudo-inverse (``damping`` None) or the damped inverse of ``mat`` by ``line``."""
    if line == "numpy":
        return pseudo_inverse(mat) if damping is None else damped_inverse(mat, damping)
    m, n = mat.shape
    out = np.empty((n, m))
    if damping is None:
        linalg.pseudo_inverse(mat, out)
    else:
        assert linalg.damped(mat, damping, out)
    return out


@lines
@settings(max_examples=150, **SETTINGS)
@given(mat=matrices, damping=st.one_of(st.none(), st.floats(1e-3, 1.0)))
def test_the_inverses(line, mat, damping):
    if damping is None:  # numpy's own SVD and cut-off (largest singular value times the relative tolerance)
        want = np.linalg.pinv(mat, rcond=PINV_RTOL)
        d = np.linalg.svd(mat, compute_uv=False)
        kept = d[d > PINV_RTOL * d[0]] if d[0] > 0 else d[:1]
        kappa = float(d[0] / kept[-1]) if d[0] > 0 else 1.0
    else:  # (J^T J + lambda^2 I)^-1 J^T, the same matrix from the other side
        gram = mat.T @ mat + damping**2 * np.eye(mat.shape[1])
        want = np.linalg.solve(gram, mat.T)
        kappa = float(np.linalg.cond(gram))
    assert_agree(inverse_of(line, mat, damping), want, 1e-13 * max(kappa, 1e3), "inverse")


# ----------------------------------------------------------------------------- the proposal


def frame_of(line: str, problem: Problem, state: ArmState, goal: Goal, proposal: np.ndarray):
    """(the filter's answer or None, the proposal or None) of one frame by ``line``: the compiled
    frame (:func:`frame_step`), or the numpy frame through the frame loop's own dispatch
    (:func:`method_step` with the compiled frames off; its proposal is the oracle's, ``proposal``)."""
    method = problem.solver.method
    if line == "compiled":
        return frame_step(problem, method, state, goal.position, goal.orientation)
    moved, _, _ = method_step(numpy_only(problem), solver_method(method), state, goal.position, goal.orientation)
    return moved, proposal


@lines
@settings(max_examples=30, **SETTINGS)
@given(
    problem=st.one_of(
        problems(methods=("pinv", "dls")),
        cluttered_problems(max_goals=1),
        robot_problems(robots=("panda", "ur5", "iiwa")),
    ),
    method=LINEAR,
    oriented=ORIENTED,
    seed=st.integers(0, 2**32 - 1),
    data=st.data(),
)
def test_the_proposal(line, problem, method, oriented, seed, data):
    assert_the_proposal(line, problem, method, oriented, seed, data)


@lines
@settings(max_examples=20, **SETTINGS)
@given(
    problem=st.one_of(
        problems(methods=("pinv", "dls"), slides=True),
        cluttered_problems(max_goals=1, slides=True),
        robot_problems(robots=("ur5_rail",)),
    ),
    method=LINEAR,
    oriented=ORIENTED,
    seed=st.integers(0, 2**32 - 1),
    data=st.data(),
)
def test_the_proposal_with_prismatic_joints(line, problem, method, oriented, seed, data):
    # chains that mix revolute and prismatic joints, and the UR5 on its rail: each slide's columns (w_j, no turn)
    assert_the_proposal(line, problem, method, oriented, seed, data)


def assert_the_proposal(line: str, problem: Problem, method: str, oriented: str, seed: int, data) -> None:
    """At the home pose and at a random one: the proposal before the filter, every push and task in it."""
    problem = with_orientations(linear(problem, method), seed, oriented)
    goal = problem.goals[0]
    for phi in (problem.home, np.clip(data.draw(poses(problem.arm.n)), problem.limits.lower, problem.limits.upper)):
        state = arm_state(problem, phi)
        want = proposed_step(numpy_only(problem), solver_method(method), state, goal.position, goal.orientation).dphi
        if line == "numpy":  # the numpy proposal made again: the same bits (no state kept between calls)
            dphi = proposed_step(
                numpy_only(problem), solver_method(method), state, goal.position, goal.orientation
            ).dphi
            assert np.array_equal(dphi, want, equal_nan=True)
        else:
            _, dphi = frame_of(line, problem, state, goal, want)
        if dphi is None:  # an inverse failed in the compiled line: the numpy line proposes
            assert line == "compiled"
            continue
        assert_agree(dphi, want, 1e-12 * conditioning(problem, state, goal.orientation), "proposal")


# ----------------------------------------------------------------------------- the filter's QP

QP_KKT = 1e-12
"""Of the filter's QP (radians): each constraint met to this, and the active ones' multipliers'
stationarity to ``QP_KKT`` times the step's scale."""

DAQP_KKT = 1e-6
"""DAQP's answer meets the KKT conditions to its own tolerances (some 1e-7)."""


def assert_solves_the_qp(x: np.ndarray, nominal: np.ndarray, cons: Constraints, tol: float = QP_KKT) -> None:
    """x minimises |x - nominal|^2 subject to ``cons`` (rows x >= lower, lo <= x <= hi): every
    constraint met to ``tol`` (primal feasibility), and x - nominal = A_act^T lambda for some
    lambda >= 0 on the constraints x meets with equality (stationarity, dual feasibility; the
    others' multipliers are 0: complementary slackness). The multipliers are found by
    non-negative least squares: where the active rows are dependent (a robot's twin capsules
    give equal rows, eee6f58) many lambda solve the equation, and the least-norm one may have a
    negative entry where a non-negative one exists."""
    from scipy.optimize import nnls

    n = len(x)
    a = np.concatenate([cons.rows, np.eye(n), -np.eye(n)])
    b = np.concatenate([cons.lower, cons.lo, -cons.hi])
    slack = a @ x - b
    assert slack.min() >= -tol, f"a constraint broken by {-slack.min():.3g}"
    active = slack <= max(1e-9, 10 * tol)  # met with equality, to the reading of x
    scale = max(1.0, float(np.abs(nominal).max()))
    if not active.any():  # the nominal itself
        assert np.abs(x - nominal).max() <= tol * scale
        return
    lam, _ = nnls(a[active].T, x - nominal)  # dual feasibility: lambda >= 0 by construction
    assert np.abs(a[active].T @ lam - (x - nominal)).max() <= 1e3 * tol * scale  # stationarity


def qp_answer(line: str, nominal: np.ndarray, cons: Constraints) -> np.ndarray | None:
    """The filter's QP by ``line``: DAQP's answer (:func:`closest_safe_step`) or the compiled exact
    one (from the clip, the bounds it breaks active); None where no step meets the constraints."""
    if line == "numpy":
        return closest_safe_step(nominal, cons)
    n = len(nominal)
    cmat = np.concatenate([np.eye(n), -np.eye(n), cons.rows])
    cb = np.concatenate([cons.lo, -cons.hi, cons.lower])
    x = np.empty(n)
    solved = qp.closest_step(nominal, cmat, cb, len(cb), x, 2 * n)
    assert solved >= 0
    cold = np.empty(n)  # from the nominal, every constraint added in turn: the same answer (the QP's only one)
    assert qp.closest_step(nominal, cmat, cb, len(cb), cold) == solved
    if solved:
        assert_agree(cold, x, 1e-12, "cold start")
    return x if solved else None


@lines
@settings(max_examples=150, **SETTINGS)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 7), k=st.integers(1, 6))
def test_the_filters_qp(line, seed, n, k):
    # random filter QPs (rows and bounds as the filter's: 0 feasible)
    rng = np.random.default_rng(seed)
    rows = rng.normal(size=(k, n))
    cons = Constraints(rows, -rng.uniform(0, 0.3, k), -rng.uniform(0, 0.5, n), rng.uniform(0, 0.5, n))
    nominal = rng.normal(size=n)
    x = qp_answer(line, nominal, cons)
    assert x is not None  # 0 meets every constraint
    assert_solves_the_qp(x, nominal, cons, DAQP_KKT if line == "numpy" else QP_KKT)
    assert_agree(x, closest_safe_step(nominal, cons), 1e-5, "against DAQP")


@lines
def test_a_qp_no_step_meets(line):
    # x_0 >= 1 and x_0 <= 0.5
    cons = Constraints(np.array([[1.0, 0.0]]), np.array([1.0]), np.full(2, -1.0), np.array([0.5, 1.0]))
    assert qp_answer(line, np.zeros(2), cons) is None


# ----------------------------------------------------------------------------- the check: the arm's own pairs


def pair_gaps_of(
    line: str, problem: Problem, phi: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, float]:
    """(gaps, t, s, normals, least) of the enabled pairs at ``phi`` by ``line``."""
    if line == "numpy":
        g = self_gaps(forward(problem.arm, phi), problem.capsules, problem.self_pairs)
        return g.d, g.t, g.s, g.normal, float(g.least)
    k = problem.kernel
    n, count = problem.arm.n, len(k.first)
    points, frames, axes, tool = np.empty((n + 1, 3)), np.empty((n, 3, 3)), np.empty((n, 3)), np.empty((3, 3))
    _forward_one(k.rows, k.root, phi, points, frames, axes, tool)
    ends, gaps, near = np.empty((2, len(k.caps), 3)), np.empty(count), np.empty((count, 5))
    least = check.pair_gaps(points, frames, k.caps, k.link, k.first, k.second, ends, gaps, near)
    return gaps, near[:, 0], near[:, 1], near[:, 2:], least


@lines
@pytest.mark.parametrize("name", ["panda-self", "ur5", "iiwa", "ur5-rail"])
@settings(max_examples=10, **SETTINGS)
@given(seed=st.integers(0, 2**32 - 1))
def test_the_pairs_gaps(line, name, seed):
    # the attempt measures its spheres' pairs (a capsule of no length) in closed form, the shared
    # segment-segment function by its box form: the same gaps, closest points and normals to rounding
    problem = problem_of(name, "pinv")
    first, second = problem.self_pairs.first, problem.self_pairs.second
    lengths = np.linalg.norm(problem.capsules.end - problem.capsules.start, axis=1)
    rng = np.random.default_rng(seed)
    for phi in rng.uniform(
        np.maximum(problem.limits.lower, -np.pi), np.minimum(problem.limits.upper, np.pi), (20, problem.arm.n)
    ):
        gaps, t, s, normal, least = pair_gaps_of(line, problem, phi)
        expected = self_gaps(forward(problem.arm, phi), problem.capsules, problem.self_pairs)
        assert_agree(gaps, expected.d, 1e-12, "gaps")
        assert least == gaps.min()
        apart = expected.d > 1e-6
        assert_agree(normal[apart], expected.normal[apart], 1e-9, "normals")
        spheres = apart & (
            (lengths[first] == 0) | (lengths[second] == 0)
        )  # the pairs measured in closed form (the others'
        # closest points may be a tie, parallel links, that the capsule ends' rounding decides either way)
        along_first, along_second = spheres & (lengths[first] > 0), spheres & (lengths[second] > 0)
        assert_agree(t[along_first], expected.t[along_first], 1e-9, "t")
        assert_agree(s[along_second], expected.s[along_second], 1e-9, "s")


# ----------------------------------------------------------------------------- the attempt's step

ITERATE_TOL = 1e-9
"""Radians, times the conditioning of the tip's task along the way (1 to 10 on the robots; the
notes' arm turning its tool as close as it can, a task second in priority, passes poses near its
straight singular one)."""


def attempt_of(
    line: str, problem: Problem, goal: np.ndarray, start: np.ndarray, budget: int, orientation: Orientation | None
):
    """An attempt of ``budget`` steps from ``start`` by ``line`` (:func:`armanim.motion.ik._attempt`;
    the numpy line with the compiled attempt off)."""
    solving = ik.solving_problem(problem if line == "compiled" else numpy_only(problem))
    chosen = solver_method(problem.solver.method)
    assert (compiled_plan(solving, chosen, None, "attempt") is not None) == (
        line == "compiled"
    )  # no obstacles, the analytic Jacobian
    return ik._attempt(solving, chosen, goal, start, budget, orientation)


def assert_the_attempt_takes_the_numpy_steps(
    line: str, problem: Problem, goal: np.ndarray, start: np.ndarray, orientation: Orientation | None
) -> None:
    """From each iterate of an attempt of up to 6 steps, the next is the numpy step from there."""
    before = start
    for budget in range(1, 7):
        got = attempt_of(line, problem, goal, start, budget, orientation)
        if assert_the_numpy_step(line, problem, goal, orientation, before, budget - 1, got):
            break  # the attempt ended before its budget: so did the line's, at the same step
        before = got.phi


def assert_the_numpy_step(line: str, problem: Problem, goal, orientation, before: np.ndarray, steps: int, got) -> bool:
    """The attempt ``got`` (of ``steps + 1`` steps) took, from its iterate ``before`` (of ``steps``
    steps), the numpy step from there (the oracle's proposal through its filter): to
    :data:`ITERATE_TOL` where no pair's row is active in the filter's QP, else, for the compiled
    line, the exact answer of that QP (the oracle's rows and bounds at ``before``: KKT
    conditions), unless the compiled loop hands that step back (the QP's active rows dependent to
    rounding: 4283247, then it is the numpy step). Returns whether the attempt ended there."""
    oracle = ik.solving_problem(numpy_only(problem))
    chosen = solver_method(problem.solver.method)
    state = arm_state(oracle, before)
    one, _, _, stopped, _ = ik._steps(oracle, chosen, goal, state, 1, orientation)
    assert (got.steps - steps, got.numerical) == (one.steps, one.numerical)
    tol = ITERATE_TOL * max(tip_condition(problem, before), tip_condition(problem, one.phi))
    qp = pair_qp(oracle, chosen, goal, orientation, state) if line == "compiled" else None
    if qp is None or hands_back(problem, goal, orientation, before):  # no pair's row acts, or the numpy step takes it
        assert_agree(got.phi, one.phi, tol, "iterate")
        assert_agree(got.tip, one.tip, tol * problem.arm.reach, "tip")
        assert_agree(got.errors[2], one.errors[2], tol * problem.arm.reach, "progress")
    else:
        nominal, cons, daqp = qp
        taken, taken_numpy = wrapped(oracle, got.phi - before), wrapped(oracle, one.phi - before)
        halvings = 0 if not np.any(taken_numpy) else round(np.log2(np.linalg.norm(daqp) / np.linalg.norm(taken_numpy)))
        # the step is read back from two iterates (rounding eps |phi|), then doubled back over the halvings
        readback = 2.0**halvings * 4 * np.finfo(float).eps * max(1.0, float(np.abs(before).max()))
        assert_solves_the_qp(taken * 2.0**halvings, nominal, cons, QP_KKT + readback)
        assert_agree(taken, taken_numpy, 1e-4, "against DAQP")  # DAQP's answer, to its tolerance
    return stopped


def hands_back(problem: Problem, goal, orientation, before: np.ndarray) -> bool:
    """Whether the compiled loop hands the step from ``before`` back to the numpy path (its QP's
    active rows dependent to rounding, a gap at its floor: the module's hand-back), so that the
    attempt takes the numpy step there, to rounding."""
    solving = ik.solving_problem(problem)
    plan = compiled_plan(
        solving, solver_method(problem.solver.method), orientation, "attempt"
    )  # as the attempt runs it
    assert plan is not None
    ran = attempt.run_attempt(solving, plan.step, plan.stacked, goal, before, 1, orientation)
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
    nominal = dphi * min(1.0, float(np.min(step_caps(oracle) / np.maximum(np.abs(dphi), 1e-300))))  # safe_step's
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


@lines
@settings(max_examples=40, **SETTINGS)
@given(
    name=st.sampled_from(sorted(ARMS)),
    method=LINEAR,
    seed=st.integers(0, 2**31),
    kind=st.sampled_from(["pose", "axis", "position"]),
    from_home=st.booleans(),
)
# The cases the search found in CI (eee6f58: the UR5's twin capsules give 7 active rows of rank 3,
# whose least-norm multipliers had a negative entry); both fail with that commit's parent's test.
# Its Panda seed 1124805897 and 4283247's Panda seed 448: their method, kind and start were not
# recorded; pinned here are the combinations whose steps meet the pair QP (1124805897, from a random
# start) or are handed back to the numpy path (448, a tool-axis goal from a random start), as those
# commits describe. 448 with a position goal from a random start: see the test below.
@example(name="ur5", method="pinv", seed=249955419, kind="position", from_home=False)
@example(name="ur5", method="dls", seed=249955419, kind="position", from_home=False)
@example(name="panda-self", method="pinv", seed=1124805897, kind="position", from_home=False)
@example(name="panda-self", method="dls", seed=1124805897, kind="position", from_home=False)
@example(name="panda-self", method="pinv", seed=448, kind="axis", from_home=False)
@example(name="panda-self", method="dls", seed=448, kind="axis", from_home=False)
def test_the_attempts_steps_on_the_robots(line, name, method, seed, kind, from_home):
    problem = problem_of(name, method)
    goal, orientation, _ = target_of(problem, seed, kind)
    assert_the_attempt_takes_the_numpy_steps(line, problem, goal, start_of(problem, seed, from_home), orientation)


@pytest.mark.xfail(
    strict=True,
    reason="known: the compiled attempt's step where the pair QP acts is 0.9x the numpy "
    "path's (Panda seed 448, a position goal from a random start; found 2026-12-06, left to the motion work)",
)
@pytest.mark.parametrize("method", ["pinv", "dls"])
def test_panda_seed_448_position_step_is_the_numpy_step(method):
    """The Panda seed 448 of 4283247 with a position goal from its random start: the compiled step
    differs from the numpy one by 10 % (6 of 7 joints past DAQP's 1e-4). Strict: it reports when
    fixed, and then belongs among the @example cases above."""
    problem = problem_of("panda-self", method)
    goal, orientation, _ = target_of(problem, 448, "position")
    assert_the_attempt_takes_the_numpy_steps("compiled", problem, goal, start_of(problem, 448, False), orientation)


@lines
@settings(max_examples=20, **SETTINGS)
@given(
    method=LINEAR,
    seed=st.integers(0, 2**31),
    kind=st.sampled_from(["pose", "axis", "position"]),
    from_home=st.booleans(),
)
def test_the_attempts_steps_on_the_rail(line, method, seed, kind, from_home):
    # the UR5 on its rail (a prismatic first joint, metres, capped by max_slide_step), with its own pairs
    problem = problem_of("ur5-rail", method)
    goal, orientation, _ = target_of(problem, seed, kind)
    assert_the_attempt_takes_the_numpy_steps(line, problem, goal, start_of(problem, seed, from_home), orientation)


@lines
@settings(max_examples=60, **SETTINGS)
@given(
    problem=problems(methods=["pinv", "dls"], max_links=7),
    data=st.data(),
    kind=st.sampled_from(["pose", "axis", "position"]),
)
def test_the_attempts_steps_on_any_arm(line, problem, data, kind):
    assert_the_attempts_steps_on(line, problem, data, kind)


@lines
@settings(max_examples=40, **SETTINGS)
@given(
    problem=problems(methods=["pinv", "dls"], max_links=7, slides=True),
    data=st.data(),
    kind=st.sampled_from(["pose", "axis", "position"]),
)
def test_the_attempts_steps_with_prismatic_joints(line, problem, data, kind):
    # chains that mix revolute and prismatic joints: the compiled attempt runs them (each slide capped in metres)
    assert_the_attempts_steps_on(line, problem, data, kind)


def assert_the_attempts_steps_on(line: str, problem: Problem, data, kind: str) -> None:
    """General arms, limits and settings (obstacles left out: those attempts are the numpy steps'); an arm that
    cannot hold the goal's orientation stays with the numpy steps, which amplify rounding there."""
    problem = replace(problem, obstacles=Obstacles.none(), solver=replace(problem.solver, jacobian="analytic"))
    pose = forward(problem.arm, data.draw(poses(problem.arm.n)))
    rot = tool_rotation(problem.arm, pose)
    orientation = {"pose": Orientation(rotation=rot), "axis": Orientation(axis=rot[:, 2]), "position": None}[kind]
    assert_the_attempt_takes_the_numpy_steps(line, problem, pose.tip, problem.home, orientation)


# ----------------------------------------------------------------------------- the frame

FRAME_TOL = 1e-12
"""Radians (and scene units for clearances and gaps), relative to the size of what is compared
(at least 1) and, for what follows from a proposal, to the conditioning of the tasks it inverts
(:func:`lockstep.conditioning`): an inverse computed two ways agrees to about eps times it, and a
task second in priority inverts the first's rounding again."""


_RUNS: dict[str, Trajectory] = {}


def run_of(problem: Problem) -> Trajectory:
    """The compiled run of ``problem``: real states (the numpy run's to rounding), made once a
    process for both lines (a named scene's two parametrized lines, a drawn problem's shrinking)."""
    with np.printoptions(precision=17, threshold=10**9):
        key = repr(problem)  # every number to its last bit
    if key not in _RUNS:
        if len(_RUNS) > 64:
            _RUNS.clear()
        _RUNS[key] = solve_trajectory(problem).trajectory
    return _RUNS[key]


def assert_frames_lockstep(line: str, problem: Problem, stride: int = 3, most: int | None = None) -> tuple[int, int]:
    """Every ``stride``-th state of the run of ``problem`` (at most ``most`` of them, spread over
    the run): the line's frame against the numpy one. Returns how many frames were compared and
    how many the line took whole."""
    oracle = numpy_only(problem)
    traj = run_of(problem)
    method = problem.solver.method
    chosen = solver_method(method)
    compared = taken = 0
    picked = range(0, traj.frames, stride)
    if most is not None and len(picked) > most:
        picked = range(0, traj.frames, -(-traj.frames // most))
    for i in picked:
        goal = problem.goals[int(traj.goal[i])]
        state = arm_state(problem, traj.phi[i])
        proposal = proposed_step(oracle, chosen, state, goal.position, goal.orientation).dphi
        expected = safe_step(oracle, state, proposal)
        moved, dphi = frame_of(line, problem, state, goal, proposal)
        compared += 1
        if dphi is None:  # an inverse failed: the numpy frame was taken
            assert moved is None
            continue
        tol = FRAME_TOL * conditioning(problem, state, goal.orientation)
        assert_agree(dphi, proposal, tol, ("proposal", i))
        if moved is None:  # the numpy filter takes the proposal
            continue
        taken += 1
        assert_the_same_filtered_step(oracle, state, moved, expected, dphi, proposal, tol, i)
    return compared, taken


def assert_frames_lockstep_on_both_lines(problem: Problem, stride: int, most: int) -> None:
    """:func:`assert_frames_lockstep` of each line at the same run's states: a drawn problem is
    solved once for the two. (Lines parametrized apart never shared a run: Hypothesis gives each
    parametrized test its own draws, the ``ci`` profile's too, so each line solved its own problems.)"""
    for line in LINES:
        note(f"line: {line}")
        assert_frames_lockstep(line, problem, stride=stride, most=most)


def assert_the_same_filtered_step(
    oracle: Problem, state: ArmState, moved, expected, dphi, proposal, tol: float, i: int
) -> None:
    length = float(np.linalg.norm(proposal))
    slack = FRAME_TOL + (expected.scale * tol * max(1.0, length) / length if length > 0 else 0.0)
    if abs(moved.scale - expected.scale) > slack:
        # The proposals agree to rounding, but a joint's rounding-level component decided the scale
        # (a joint on its kept bound: a halving's edge, or its room over a component of 1e-13, 27e8a7b):
        # the filters must then take the same proposal alike.
        expected = safe_step(oracle, state, dphi)
    assert abs(moved.scale - expected.scale) <= slack, (i, moved.scale, expected.scale)
    assert moved.blocked_by == expected.blocked_by, i
    assert_agree(moved.phi, expected.phi, tol, ("phi", i))
    if expected.state is state:  # no halving kept the guarantees: the arm stays
        assert moved.state is state
        return
    assert_agree(moved.state.pose.points, expected.state.pose.points, tol, ("points", i))
    assert_agree(moved.state.pose.axes, expected.state.pose.axes, tol, ("axes", i))
    if expected.state.clearance is not None:
        for got, want in zip(
            (moved.state.clearance.d, moved.state.clearance.t, moved.state.clearance.normal),
            (expected.state.clearance.d, expected.state.clearance.t, expected.state.clearance.normal),
        ):
            assert_agree(got, want, tol, ("clearances", i))
    else:
        assert moved.state.clearance is None
    if expected.state.self_gaps is not None:
        got, want = moved.state.self_gaps, expected.state.self_gaps
        for a, b in ((got.d, want.d), (got.normal, want.normal), (got.least, want.least)):
            assert_agree(a, b, tol, ("gaps", i))
        assert_the_same_closest_points(oracle, expected.state.pose, got, want, tol, i)
    else:
        assert moved.state.self_gaps is None


def assert_the_same_closest_points(problem: Problem, pose, got, want, tol: float, i: int) -> None:
    """The pairs' closest points (t along the first capsule, s along the second) are the oracle's,
    but for two parallel capsules (the UR5 on its rail at home: its upper arm and wrist, 4e-17 off
    parallel): a whole segment of point pairs is closest there, and which the rounding of the ends
    picks is either line's; then the line's points must be as near each other as the oracle's."""
    from armanim.arm.capsules import capsule_ends

    a, b = capsule_ends(problem.capsules, pose)
    first, second = problem.self_pairs.first, problem.self_pairs.second
    u, v = b[first] - a[first], b[second] - a[second]
    size = np.linalg.norm(u, axis=1) * np.linalg.norm(v, axis=1)
    tie = (size > 0) & (np.linalg.norm(np.cross(u, v), axis=1) <= 1e-9 * size)
    assert_agree(got.t[~tie], want.t[~tie], tol, ("gaps' t", i))
    assert_agree(got.s[~tie], want.s[~tie], tol, ("gaps' s", i))

    def apart(t: np.ndarray, s: np.ndarray) -> np.ndarray:
        return np.linalg.norm(a[first] + t[:, None] * u - (a[second] + s[:, None] * v), axis=1)

    assert_agree(apart(got.t, got.s)[tie], apart(want.t, want.s)[tie], tol, ("tied closest points", i))


FAMILIES = {
    # general arms and cluttered scenes among spheres
    "spheres": st.one_of(problems(methods=("pinv", "dls")), cluttered_problems(max_goals=2)),
    # the bundled robots among spheres, with their own pairs
    "robots": robot_problems(robots=("panda", "ur5", "iiwa")),
    # chains that mix revolute and prismatic joints among spheres; the UR5 on its rail
    "sliding": st.one_of(problems(methods=("pinv", "dls"), slides=True), cluttered_problems(max_goals=2, slides=True)),
    "rail": robot_problems(robots=("ur5_rail",)),
}
SHAPES = {
    # spheres, boxes, capsules and a floor; and cylinders (a run among them plans more: fewer of them)
    "shapes": shaped_problems(max_goals=2, max_frames=30),
    "cylinders": shaped_problems(max_goals=2, max_frames=30, cylinders=True),
}


@pytest.mark.parametrize("family", sorted(FAMILIES))
@settings(max_examples=15, **SETTINGS)
@given(data=st.data(), method=LINEAR, oriented=ORIENTED, seed=st.integers(0, 2**32 - 1))
def test_the_frames(family, data, method, oriented, seed):
    problem = with_orientations(linear(data.draw(FAMILIES[family], label="problem"), method), seed, oriented)
    assert_frames_lockstep_on_both_lines(problem, stride=3, most=24)


@pytest.mark.parametrize("family", sorted(SHAPES))
@settings(max_examples=8, **SETTINGS)
@given(data=st.data(), method=LINEAR, oriented=ORIENTED, seed=st.integers(0, 2**32 - 1))
def test_the_frames_among_shapes(family, data, method, oriented, seed):
    # the planner off: its searches among the shapes were most of this test's time, and a planned
    # route's frames are not the method's (the frames pressed against the shapes are still here)
    problem = with_orientations(linear(data.draw(SHAPES[family], label="problem"), method), seed, oriented)
    problem = replace(problem, solver=replace(problem.solver, planner="off"))
    assert_frames_lockstep_on_both_lines(problem, stride=4, most=16)


def robot_scene(method: str, obstacles: list[dict], goals: list[list[float]], **solver) -> Problem:
    return scene_to_problem(
        scene_model(
            {
                "version": 1,
                "arm": {"robot": "panda"},
                "obstacles": obstacles,
                "goals": goals,
                "solver": {
                    "method": method,
                    "planner": "off",
                    "tolerance": 0.005,
                    "clearance": 0.02,
                    "max_step": 0.02,
                    **solver,
                },
            }
        )
    )


SCENES = {
    "cylinders": lambda m: robot_scene(
        m,
        [
            {"cylinder": {"center": [0.45, 0.1, 0.4], "length": 0.2, "radius": 0.04}, "influence": 0.1},
            {
                "cylinder": {"center": [0.2, -0.35, 0.5], "length": 0.3, "radius": 0.03, "rpy": [90, 0, 0]},
                "influence": 0.1,
            },
        ],
        [[0.5, 0.2, 0.3], [0.3, -0.45, 0.4], [-0.2, 0.4, 0.6]],
    ),
    "spheres": lambda m: robot_scene(
        m,
        [
            {"center": [0.45, 0.1, 0.45], "radius": 0.05, "influence": 0.1},
            {"center": [0.2, -0.35, 0.5], "radius": 0.06, "influence": 0.1},
        ],
        [[0.5, 0.2, 0.3], [0.3, -0.45, 0.4], [-0.2, 0.4, 0.6]],
    ),
    # the Panda's base (carrier -1: its capsules in the world, Jacobian columns all zero) in play: a sphere within
    # the base's influence (no push, no row: the base never moves) and a goal behind the base (pairs of the base and
    # the hand in the filter's rows)
    "beside the base": lambda m: robot_scene(
        m, [{"center": [0.0, -0.25, 0.05], "radius": 0.05, "influence": 0.2}], [[-0.12, 0.1, 0.12]], self_clearance=0.01
    ),
    # the bundled rail scene: the UR5 slides along a long table between goals its arm alone cannot span
    "rail": lambda m: rail_scene(m),
}


def rail_scene(method: str) -> Problem:
    from pathlib import Path

    from armanim.scene import load_scene

    scene = load_scene(Path(__file__).resolve().parents[3] / "scenes" / "ur5-rail.yaml")
    problem = scene_to_problem(scene.model)
    return replace(problem, solver=replace(problem.solver, method=method))


@lines
@pytest.mark.parametrize("scene", sorted(SCENES))
@pytest.mark.parametrize("method", ["pinv", "dls"])
def test_the_frames_of_robot_runs(line, scene, method):
    compared, taken = assert_frames_lockstep(line, SCENES[scene](method), stride=1)
    assert taken >= 10  # the line's frames are taken here, not a path never taken


def test_the_tolerance_sees_a_difference():
    # the harness's one tolerance is relative to the oracle's size (at least 1) and tells non-finite entries apart
    want = np.array([1.0, -2.0, np.inf])
    assert agree(want + 1e-13, want, 1e-12) and not agree(want + 1e-11, want, 1e-12)
    assert not agree(np.array([np.nan, -2.0, np.inf]), want, 1.0) and not agree(want[:2], want, 1.0)
