"""The four methods: each reaches its bundled scene's goals; the shared barrier; ik."""

from __future__ import annotations

from dataclasses import replace
from typing import get_args

import numpy as np
import pytest
from conftest import SCENES, solved_scene

from armanim.arm.kinematics import Arm, forward
from armanim.arm.linalg import PINV_RTOL, pseudo_inverse, singular_factors
from armanim.motion.filter.barrier import safe_step
from armanim.motion.ik import solve_pose
from armanim.motion.problem import Goal, Limits, Problem
from armanim.motion.solvers import METHODS, arm_state, step_function
from armanim.motion.solvers.linear import damped_inverse
from armanim.motion.trajectory import solve_trajectory
from armanim.names import MethodName
from armanim.scene import default_solver_settings, load_scene, scene_to_problem, unlimited_limits
from armanim.world.obstacles import Obstacles

METHOD_SCENES = {
    "pinv": "notes-arm.yaml",
    "dls": "singular-start.yaml",
    "newton": "planar-nlink.yaml",
    "gradient": "breen-gradient.yaml",
}


def test_registry_has_the_four_methods():
    assert set(METHODS) == {"pinv", "dls", "newton", "gradient"}
    assert tuple(METHODS) == get_args(MethodName)  # the registry and the scene's words agree
    for name in METHODS:
        assert step_function(name) is METHODS[name].step_function
    with pytest.raises(ValueError, match="unknown solver method"):
        step_function("simplex")


@pytest.mark.parametrize("method, scene", sorted(METHOD_SCENES.items()))
def test_each_method_reaches_every_goal_of_its_bundled_scene(method, scene):
    problem, solution = solved_scene(SCENES / scene)
    assert problem.solver.method == method
    for report in solution.goals:
        assert report.reached, (report.index, report.reason, report.final_distance)
        assert report.reason is None
        assert report.final_distance < problem.solver.tolerance
    assert solution.reached == len(problem.goals)


def test_out_of_reach_goal_is_missed_and_the_next_is_reached():
    problem, solution = solved_scene(SCENES / "out-of-reach.yaml")
    first, second = solution.goals
    assert not first.reached and first.reason == "out_of_reach"
    # the arm stretches toward it until it stalls, then the goal ends (not at the frame cap)
    assert first.frames < problem.solver.max_frames_per_goal
    assert second.reached and second.reason is None
    # the arm stretches toward the unreachable goal: links 2-4 (15 long) point from the
    # shoulder (top of the vertical first link) at the goal, so the distance ends near
    # |g - shoulder| - 15, the least any pose can reach
    shoulder = problem.arm.base + np.array([0.0, 0.0, problem.arm.links[0]])
    best = np.linalg.norm(first.position - shoulder) - problem.arm.links[1:].sum()
    assert best - 1e-9 <= first.final_distance <= best + 0.25


def _numeric_vs_analytic(problem):
    analytic = solve_trajectory(problem)
    numeric = solve_trajectory(replace(problem, solver=replace(problem.solver, jacobian="numeric")))
    assert [g.reached for g in numeric.goals] == [g.reached for g in analytic.goals]
    a, b = analytic.trajectory, numeric.trajectory
    assert abs(a.frames - b.frames) <= 3
    f = min(a.frames, b.frames)
    np.testing.assert_allclose(b.tip[:f], a.tip[:f], atol=0.05)
    np.testing.assert_allclose(b.phi[:f], a.phi[:f], atol=np.radians(1.0))


def test_numeric_jacobian_gives_nearly_the_same_pinv_trajectory():
    """notes-arm.yaml from a bent (non-singular) home pose."""
    problem, _ = solved_scene(SCENES / "notes-arm.yaml")
    _numeric_vs_analytic(replace(problem, home=np.radians([0.0, 20.0, 30.0, 30.0])))


def test_numeric_jacobian_pinv_trajectory_on_the_bundled_scene():
    problem, _ = solved_scene(SCENES / "notes-arm.yaml")
    _numeric_vs_analytic(problem)


def test_numeric_gradient_gives_nearly_the_same_gradient_trajectory():
    problem = scene_to_problem(load_scene(SCENES / "breen-gradient.yaml").model)
    problem = replace(problem, goals=problem.goals[:1])
    analytic = solve_trajectory(problem)
    numeric = solve_trajectory(replace(problem, solver=replace(problem.solver, jacobian="numeric")))
    assert numeric.goals[0].reached == analytic.goals[0].reached
    f = min(analytic.trajectory.frames, numeric.trajectory.frames)
    np.testing.assert_allclose(numeric.trajectory.tip[:f], analytic.trajectory.tip[:f], atol=0.05)


@pytest.mark.parametrize("method", sorted(METHODS))
def test_every_method_reaches_a_goal_on_a_clear_arm(method):
    arm = Arm.from_names([2, 5, 5, 5], base=(5, 5, 0))
    goal = forward(arm, np.radians([40.0, 30.0, 50.0, 20.0])).tip
    problem = Problem(
        arm=arm,
        half_width=0.25,
        home=np.radians([0.0, 10.0, 10.0, 10.0]),
        limits=unlimited_limits(4),
        obstacles=Obstacles.none(),
        goals=(Goal(goal, hold=0.0),),
        solver=default_solver_settings(method=method, beta=0.2 if method != "gradient" else 0.5, max_step=0.5),
        fps=30.0,
    )
    solution = solve_trajectory(problem)
    assert solution.goals[0].reached, solution.goals[0]


# ------------------------------------------------------------ the shared barrier


def one_link_problem(**kw):
    defaults = dict(
        arm=Arm.from_names([2.0], axes=["z"], direction="x"),
        half_width=0.25,
        home=np.zeros(1),
        limits=unlimited_limits(1),
        obstacles=Obstacles.none(),
        goals=(Goal(np.array([0.0, 2.0, 0.0]), hold=0.0),),
        solver=default_solver_settings(max_joint_step=np.radians(180.0)),
        fps=30.0,
    )
    defaults.update(kw)
    return Problem(**defaults)


def test_safe_step_caps_the_joint_step():
    problem = one_link_problem(solver=default_solver_settings(max_joint_step=np.radians(10.0)))
    moved = safe_step(problem, arm_state(problem, np.zeros(1)), np.array([1.0]))
    assert moved.phi[0] == pytest.approx(np.radians(10.0))
    assert moved.blocked_by is None


def test_safe_step_stops_before_a_limit():
    lim = Limits(np.array([-0.5]), np.array([0.5]), margin=0.1)
    problem = one_link_problem(limits=lim)
    moved = safe_step(problem, arm_state(problem, np.zeros(1)), np.array([2.0]))
    assert moved.blocked_by == "limit"
    assert -0.5 < moved.phi[0] < 0.5
    assert 0 < moved.scale < 1


def test_safe_step_stops_before_an_obstacle():
    # an obstacle on the circle of the link's tip at 90 degrees
    obstacles = Obstacles(np.array([[0.0, 2.0, 0.0]]), np.array([0.5]), np.array([0.5]))
    problem = one_link_problem(obstacles=obstacles)
    moved = safe_step(problem, arm_state(problem, np.zeros(1)), np.array([np.pi / 2]))
    assert moved.blocked_by == "obstacle"
    from armanim.world.distances import min_link_clearance

    assert (
        float(min_link_clearance(forward(problem.arm, moved.phi), obstacles, problem.capsules))
        >= problem.solver.clearance
    )
    assert 0 < moved.phi[0] < np.pi / 2


def test_safe_step_holds_still_on_nan():
    problem = one_link_problem()
    moved = safe_step(problem, arm_state(problem, np.array([0.3])), np.array([np.nan]))
    assert moved.blocked_by == "nan" and moved.scale == 0.0
    np.testing.assert_array_equal(moved.phi, [0.3])


def test_safe_step_wraps_unlimited_joints():
    problem = one_link_problem()
    moved = safe_step(problem, arm_state(problem, np.array([3.0])), np.array([0.5]))
    assert -np.pi < moved.phi[0] <= np.pi
    assert moved.phi[0] == pytest.approx(3.5 - 2 * np.pi)


def test_damped_inverse_formula():
    jac = np.array([[1.0, 2.0, 0.0], [0.0, 1.0, 3.0], [0.0, 0.0, 0.0]])  # rank 2: singular J J^T
    lam = 0.3
    expected = jac.T @ np.linalg.inv(jac @ jac.T + lam**2 * np.eye(3))
    np.testing.assert_allclose(damped_inverse(jac, lam), expected, atol=1e-12)


def test_a_stack_of_jacobians_is_inverted_each_bit_for_bit_as_alone():
    # the link pushes are inverted in one call: the trajectories (and goldens) must not move
    rng = np.random.default_rng(4)
    for _ in range(300):
        n, k = rng.integers(1, 8), rng.integers(1, 6)
        stack = rng.normal(size=(k, 3, n))
        stack[: k // 2, :, -1] = 0.0  # some of them singular
        for invert in (pseudo_inverse, lambda j: damped_inverse(j, 0.2)):
            together = invert(stack)
            assert together.shape == (k, n, 3)
            for one, jac in zip(together, stack):
                assert np.array_equal(one, invert(jac))
    assert pseudo_inverse(np.zeros((0, 3, 4))).shape == (0, 4, 3)


def test_the_pseudo_inverse_is_eq20_of_gesdds_factors_bit_for_bit():
    # scipy.linalg.svd with gesdd is the design card's solver; singular_factors calls scipy's gesdd
    # wrapper directly (and numba's np.linalg.svd, in the compiled frames, the same LAPACK through
    # scipy.linalg.cython_lapack): the factors, and so J+ = V D+ U^T and every trajectory, are the
    # same bits. numpy.linalg.svd calls gesdd of numpy's own LAPACK build, the same bits only where
    # both wheels bundle the same OpenBLAS (not numpy 2.5.5 beside scipy 1.18.1, Python 3.13): it is
    # held to 1e-12 here, as an independent oracle, and never used by armanim's solve.
    from scipy.linalg import svd as scipy_svd

    rng = np.random.default_rng(37)
    for _ in range(500):
        shape = (*rng.integers(1, 4, size=rng.integers(0, 2)), 3, int(rng.integers(1, 8)))
        jac = rng.normal(size=shape)
        jac[..., -1] *= rng.random() < 0.3  # some of them singular
        u, d, vt = scipy_svd(jac, full_matrices=False, lapack_driver="gesdd")
        keep = (d > PINV_RTOL * d[..., :1]) & (d[..., :1] > 0)
        inverse = np.where(keep, 1.0 / np.where(keep, d, 1.0), 0.0)
        expected = np.matmul(np.swapaxes(vt, -1, -2) * inverse[..., None, :], np.swapaxes(u, -1, -2))
        assert all(np.array_equal(a, b) for a, b in zip(singular_factors(jac), (u, d, vt)))
        assert np.array_equal(pseudo_inverse(jac), expected)
        assert np.allclose(np.linalg.svd(jac, compute_uv=False), d, rtol=0, atol=1e-12)
        if not (d[..., 1:] < 1e-9).any():  # a rank-deficient J has no unique pseudo-inverse to compare
            assert np.allclose(np.linalg.pinv(jac, rcond=PINV_RTOL), expected, rtol=0, atol=1e-9)


def test_a_pseudo_inverse_of_a_nan_is_a_linear_algebra_error():
    with pytest.raises(np.linalg.LinAlgError):
        pseudo_inverse(np.array([[np.nan, 1.0], [0.0, 1.0]]))


# ------------------------------------------------------------ ik (one pose to convergence)


def planar_ik_problem(method: str, tol: float = 1e-3) -> Problem:
    """A planar arm of four unit links with the goal (3, 1, 0)."""
    return Problem(
        arm=Arm.from_names([1.0] * 4, axes=["z"] * 4, direction="x"),
        half_width=0.1,
        home=np.zeros(4),
        limits=unlimited_limits(4),
        obstacles=Obstacles.none(),
        goals=(Goal(np.array([3.0, 1.0, 0.0]), hold=0.0),),
        solver=default_solver_settings(method=method, tolerance=tol, beta=0.3 if method != "gradient" else 0.5),
        fps=30.0,
    )


def numpy_steps_only(problem: Problem) -> Problem:
    """``problem`` solved with the numpy steps everywhere (``tunables.ik.compiled`` off)."""
    return replace(problem, tunables=replace(problem.tunables, ik=replace(problem.tunables.ik, compiled=False)))


@pytest.mark.parametrize("method", sorted(METHODS))
def test_ik_round_trip_fk_of_ik_is_the_goal(method):
    tol = 1e-3
    problem = planar_ik_problem(method, tol)
    arm, goal = problem.arm, problem.goals[0].position
    result = solve_pose(problem, goal, np.radians([10.0, 10.0, 10.0, 10.0]), max_iterations=3000)
    assert result.converged and result.status == "converged", result
    np.testing.assert_allclose(forward(arm, result.phi).tip, result.tip, atol=1e-12)
    assert np.linalg.norm(result.tip - goal) < tol
    assert result.distance == pytest.approx(np.linalg.norm(result.tip - goal))
    if method == "newton":
        assert result.iterations >= 1 and result.newton_iterations >= 1  # GDLS, then Newton finishes


def test_ik_reports_a_linear_algebra_failure_as_numerical(monkeypatch):
    import armanim.motion.solvers.linear

    def fails(jac):
        raise np.linalg.LinAlgError("SVD did not converge")

    monkeypatch.setattr(armanim.motion.solvers.linear, "pseudo_inverse", fails)
    problem = numpy_steps_only(
        planar_ik_problem("pinv")
    )  # the compiled attempt has its own inverse (test_compiled_attempt.py)
    start = np.radians([10.0, 10.0, 10.0, 10.0])
    result = solve_pose(problem, problem.goals[0].position, start, max_iterations=100)
    assert result.status == "numerical" and not result.converged
    assert np.all(np.isfinite(result.phi)) and result.restarts == 4  # every start was tried
    assert result.distance == pytest.approx(
        np.linalg.norm(forward(problem.arm, result.phi).tip - problem.goals[0].position)
    )


@pytest.mark.parametrize("compiled", [True, False])
def test_ik_restarts_from_the_planner_seed_poses(monkeypatch, compiled):
    # one set of starts for every solve from a pose: the pose, its mirrored elbow, then the
    # planner's seeded random poses (the compiled attempts' starts, or the numpy steps' poses)
    import armanim.motion.kernels.attempt
    import armanim.motion.solvers.linear
    from armanim.motion.planning.poses import seed_poses

    seen = []
    jacobian_of_tip = armanim.motion.solvers.linear.jacobian_of_tip
    run_attempt = armanim.motion.kernels.attempt.run_attempt

    def recording(problem, phi, pose):
        seen.append(np.array(phi))
        return jacobian_of_tip(problem, phi, pose)

    def starting(problem, step, stacked, goal, start, *rest):
        seen.append(np.array(start))
        return run_attempt(problem, step, stacked, goal, start, *rest)

    monkeypatch.setattr(armanim.motion.solvers.linear, "jacobian_of_tip", recording)
    monkeypatch.setattr(armanim.motion.ik, "_RUN_ATTEMPT", [starting])
    problem = planar_ik_problem("pinv") if compiled else numpy_steps_only(planar_ik_problem("pinv"))
    start = np.radians([10.0, 20.0, 30.0, 40.0])
    result = solve_pose(problem, np.array([10.0, 0.0, 0.0]), start, max_iterations=1000)  # out of reach
    assert result.restarts == 4 and not result.converged
    for pose in seed_poses(problem, start, 1 + 4, seed=0):
        assert any(np.array_equal(pose, phi) for phi in seen), np.degrees(pose)


@pytest.mark.parametrize("scene", ["breen-gradient", "ur5-table"])
def test_gradient_hands_on_the_state_of_its_whole_step_and_the_filter_reuses_it(scene):
    # the filter's exact check of phi + dphi takes the gradient's own state of that pose; it
    # must be bit for bit the one it would compute, and the filtered step the same without it
    problem = scene_to_problem(load_scene(SCENES / f"{scene}.yaml").model)
    state = arm_state(problem, problem.home)
    for _ in range(25):
        proposal = step_function("gradient")(problem, state, problem.goals[0].position)
        if proposal.ahead is not None:
            again = arm_state(problem, state.phi + proposal.dphi)
            assert proposal.ahead.phi.tobytes() == again.phi.tobytes()
            for field in ("d", "t", "normal"):
                np.testing.assert_array_equal(getattr(proposal.ahead.clearance, field), getattr(again.clearance, field))
        reused, computed = (
            safe_step(problem, state, proposal.dphi, proposal.ahead),
            safe_step(problem, state, proposal.dphi),
        )
        assert reused.phi.tobytes() == computed.phi.tobytes() and (reused.scale, reused.blocked_by) == (
            computed.scale,
            computed.blocked_by,
        )
        state = computed.state
