"""The compiled pose-solve attempt (:mod:`armanim.motion.solvers.compiled`) against the numpy
steps it compiles (:func:`armanim.motion.solvers.linear.linear_step` through the filter
:func:`armanim.motion.solvers.barrier.safe_step`, the oracle): the same iterates to 1e-9 over
an attempt's first steps on the Panda (with and without its self-collision), UR5, iiwa and the
notes' arm, for 6-D, tool-axis and position goals; whole solves that meet the tolerances by
the numpy chain's FK, inside the limits and with the arm's own pairs apart; its small linear
algebra against numpy's and LAPACK's."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from strategies import poses, problems

from armanim.arm.kinematics import forward, tip_jacobian, tool_rotation
from armanim.arm.linalg import PINV_RTOL, pseudo_inverse
from armanim.motion import ik
from armanim.motion.orientation import Orientation, orientation_angle
from armanim.motion.problem import Goal, Limits, Problem
from armanim.motion.solvers import compiled, solver_method
from armanim.motion.solvers.barrier import within_limits
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
def test_the_compiled_attempt_takes_the_numpy_steps(name, method, seed, kind, from_home):
    problem = ik.solving_problem(problem_of(name, method))
    oracle = ik.solving_problem(numpy_only(problem_of(name, method)))
    goal, orientation, _ = target_of(problem, seed, kind)
    start = start_of(problem, seed, from_home)
    chosen = solver_method(method)
    assert ik.runs_compiled(problem, chosen) and not ik.runs_compiled(oracle, chosen)
    kappa = tip_condition(problem, start)
    for budget in range(1, 7):
        got = ik._attempt(problem, chosen, goal, start, budget, orientation)
        expected = ik._attempt(oracle, chosen, goal, start, budget, orientation)
        assert (got.steps, got.numerical) == (expected.steps, expected.numerical)
        tol = ITERATE_TOL * kappa  # rounding grows with the conditioning of the steps so far
        np.testing.assert_allclose(got.phi, expected.phi, atol=tol, rtol=0)
        np.testing.assert_allclose(got.tip, expected.tip, atol=tol * problem.arm.reach, rtol=0)
        np.testing.assert_allclose(got.errors[2], expected.errors[2], atol=tol * problem.arm.reach, rtol=0)
        if expected.steps < budget:  # the attempt ended before its budget: so did the compiled one, at the same step
            break
        kappa = max(kappa, tip_condition(problem, expected.phi))


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
    for budget in (1, 3, 6):
        got = ik._attempt(solving, chosen, pose.tip, problem.home, budget, orientation)
        expected = ik._attempt(oracle, chosen, pose.tip, problem.home, budget, orientation)
        assert (got.steps, got.numerical) == (expected.steps, expected.numerical)
        np.testing.assert_allclose(got.phi, expected.phi, atol=ITERATE_TOL * tip_condition(problem, expected.phi), rtol=0)


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


def test_the_compiled_attempt_hands_a_near_pair_back():
    # from the Panda's home, link3 and link5 are 2.8 cm apart: the filter's row of that pair acts on
    # the first large step, so the compiled loop hands the attempt back there
    problem = ik.solving_problem(robot("panda", "pinv"))
    goal, orientation, _ = target_of(problem, 0, "pose")
    ran = compiled.run_attempt(problem, compiled.PINV, True, goal, problem.home, 25, orientation)
    assert ran.handed_back and ran.steps == 0
    off = ik.solving_problem(robot("panda", "pinv", "off"))
    assert not compiled.run_attempt(off, compiled.PINV, True, goal, off.home, 25, orientation).handed_back


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
