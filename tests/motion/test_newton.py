"""The n-link assignment's objective: published f, g, H, finite differences, GDLS + NM."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from strategies import arm_and_pose

from armanim.arm.kinematics import Arm, forward
from armanim.motion.solvers.newton import newton_direction, newton_solve, objective, objective_derivatives

W_TAR, W_REG = 1e3, 1.0


def planar(n: int) -> Arm:
    return Arm.from_names([1.0] * n, axes=["z"] * n, direction="x")


PUBLISHED = {
    1: dict(goal=(0.0, 1.0), f=1000.0, g=[-1000.0], H=[[1.0]]),
    2: dict(goal=(1.0, 1.0), f=1000.0, g=[-2000.0, -1000.0], H=[[2001.0, 1000.0], [1000.0, 1.0]]),
    4: dict(
        goal=(3.0, 1.0),
        f=1000.0,
        g=[-4000.0, -3000.0, -2000.0, -1000.0],
        H=[[12001, 9000, 6000, 3000], [9000, 6001, 4000, 2000], [6000, 4000, 2001, 1000], [3000, 2000, 1000, 1]],
    ),
}


@pytest.mark.parametrize("n", [1, 2, 4])
def test_objective_derivatives_equal_the_assignment_published_values(n):
    ref = PUBLISHED[n]
    arm = planar(n)
    target = np.array([*ref["goal"], 0.0])
    f, g, H = objective_derivatives(arm, np.zeros(n), target, np.zeros(n), W_TAR, W_REG)
    assert f == pytest.approx(ref["f"], abs=1e-9)
    np.testing.assert_allclose(g, ref["g"], atol=1e-9)
    np.testing.assert_allclose(H, np.array(ref["H"], dtype=float), atol=1e-9)
    assert objective(arm, np.zeros(n), target, np.zeros(n), W_TAR, W_REG) == pytest.approx(f, abs=1e-9)


@given(arm_and_pose(), st.data())
def test_newton_gradient_and_hessian_match_central_differences(ap, data):
    arm, phi = ap
    n = arm.n
    target = forward(arm, phi).tip + np.array(data.draw(st.tuples(*(st.floats(-2, 2) for _ in range(3)))))
    rest = phi + np.array(data.draw(st.lists(st.floats(-0.5, 0.5), min_size=n, max_size=n)))
    w_tar = data.draw(st.sampled_from([1.0, 10.0, 1e3]))
    w_reg = data.draw(st.sampled_from([0.0, 1.0, 5.0]))
    f, g, H = objective_derivatives(arm, phi, target, rest, w_tar, w_reg)
    h = 1e-6
    g_fd = np.array(
        [
            (
                objective(arm, phi + h * e, target, rest, w_tar, w_reg)
                - objective(arm, phi - h * e, target, rest, w_tar, w_reg)
            )
            / (2 * h)
            for e in np.eye(n)
        ]
    )
    scale = max(1.0, float(np.abs(g).max()))
    np.testing.assert_allclose(g, g_fd, atol=1e-6 * scale)
    h = 1e-5
    H_fd = np.stack(
        [
            (
                objective_derivatives(arm, phi + h * e, target, rest, w_tar, w_reg)[1]
                - objective_derivatives(arm, phi - h * e, target, rest, w_tar, w_reg)[1]
            )
            / (2 * h)
            for e in np.eye(n)
        ],
        axis=1,
    )
    scale = max(1.0, float(np.abs(H).max()))
    np.testing.assert_allclose(H, H_fd, atol=1e-6 * scale)
    np.testing.assert_allclose(H, H.T, atol=1e-9 * scale)


def test_one_link_gdls_approaches_pi_over_two():
    """The assignment: from theta = 0 towards goal (0, 1) the answer is close to pi/2."""
    arm = planar(1)
    result = newton_solve(arm, np.zeros(1), np.array([0.0, 1.0, 0.0]), np.zeros(1), W_TAR, W_REG)
    assert result.phi[0] == pytest.approx(np.pi / 2, abs=0.01)
    assert result.phi[0] != np.pi / 2  # regularised: close to, not exactly
    assert result.f < 1000.0
    assert result.gd_iterations >= 1


@pytest.mark.parametrize("n, goal", [(2, (1.0, 1.0)), (4, (3.0, 1.0)), (4, (-2.0, 2.5))])
def test_newton_solve_reaches_the_assignment_goals(n, goal):
    arm = planar(n)
    target = np.array([*goal, 0.0])
    result = newton_solve(arm, np.zeros(n), target, np.zeros(n), W_TAR, W_REG)
    # w_reg pulls toward the rest pose, so "reached" means within the assignment's visual tolerance
    assert np.linalg.norm(forward(arm, result.phi).tip - target) < 1e-2
    assert result.f == pytest.approx(objective(arm, result.phi, target, np.zeros(n), W_TAR, W_REG))
    assert result.f < objective(arm, np.zeros(n), target, np.zeros(n), W_TAR, W_REG)


def test_newton_is_kept_only_when_it_lowers_f():
    arm = planar(4)
    target = np.array([3.0, 1.0, 0.0])
    full = newton_solve(arm, np.zeros(4), target, np.zeros(4), W_TAR, W_REG)
    from armanim.motion.solvers.newton import NewtonOptions

    gd_only = newton_solve(arm, np.zeros(4), target, np.zeros(4), W_TAR, W_REG, NewtonOptions(nm_iterations=0))
    assert full.f <= gd_only.f
    if full.newton_kept:
        assert full.f < gd_only.f
    else:
        np.testing.assert_allclose(full.phi, gd_only.phi)


def test_newton_direction_is_descent_even_for_indefinite_hessian():
    H = np.array([[1.0, 0.0], [0.0, -2.0]])
    g = np.array([1.0, 1.0])
    d = newton_direction(H, g)
    assert d is not None and g @ d < 0
    np.testing.assert_allclose(newton_direction(np.diag([2.0, 4.0]), g), [-0.5, -0.25])
