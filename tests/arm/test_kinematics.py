"""Forward kinematics and Jacobians against explicit oracles: the course notes'
matrices (Eqs. 2-7), the n-link assignment's published values, finite differences."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from strategies import arm_and_pose, arms, poses

from armanim.arm.geometry import closest_on_segment, wrap_angle
from armanim.arm.kinematics import (
    Arm,
    forward,
    joint_rotations,
    link_point,
    numeric_jacobian,
    point_hessian,
    point_jacobian,
    tip_jacobian,
)
from armanim.arm.linalg import PINV_RTOL, pseudo_inverse

NOTES_LINKS = (2.0, 5.0, 5.0, 5.0)
NOTES_BASE = (5.0, 5.0, 0.0)


# ------------------------------------------------------------ the notes' matrices


def rz(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])


def ry(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, 0, s], [0, 1.0, 0], [-s, 0, c]])


def homogeneous(rot, trans):
    t = np.eye(4)
    t[:3, :3] = rot
    t[:3, 3] = trans
    return t


def notes_joint_points(phi, links=NOTES_LINKS, base=NOTES_BASE):
    """p_1..p_5 from the chain T01 T12 T23 T34 T45 of Eqs. 2-7, built by hand."""
    l1, l2, l3, l4 = links
    tz = lambda length: np.array([0.0, 0.0, length])  # noqa: E731 (the notes' t_z(l), one line per factor)
    chain = [
        homogeneous(rz(phi[0]), np.asarray(base, dtype=float)),  # Eq. 2 (p1 = base)
        homogeneous(ry(phi[1]), tz(l1)),  # Eq. 3
        homogeneous(ry(phi[2]), tz(l2)),  # Eq. 4
        homogeneous(ry(phi[3]), tz(l3)),  # Eq. 5
        homogeneous(np.eye(3), tz(l4)),  # Eq. 6
    ]
    world = np.eye(4)
    points = []
    for t in chain:  # Eq. 7: T0i = T0,i-1 Ti-1,i
        world = world @ t
        points.append(world[:3, 3].copy())
    return np.array(points)


NOTES_POSES_DEG = [
    (0, 0, 0, 0),
    (0, 30, 45, 10),
    (90, -45, 60, -30),
    (-135, 100, -150, 150),
    (37, 12, -88, 123),
    (180, 90, 90, 90),
]


@pytest.mark.parametrize("deg", NOTES_POSES_DEG)
def test_fk_matches_course_notes_matrices(deg):
    arm = Arm.from_names(NOTES_LINKS, base=NOTES_BASE)
    phi = np.radians(deg)
    pose = forward(arm, phi)
    np.testing.assert_allclose(pose.points, notes_joint_points(phi), atol=1e-12)
    np.testing.assert_allclose(pose.tip, notes_joint_points(phi)[-1], atol=1e-12)


@given(st.lists(st.floats(-np.pi, np.pi), min_size=4, max_size=4))
def test_fk_matches_course_notes_matrices_random(phi):
    arm = Arm.from_names(NOTES_LINKS, base=NOTES_BASE)
    np.testing.assert_allclose(forward(arm, np.array(phi)).points, notes_joint_points(phi), atol=1e-12)


def test_fk_frames_are_the_notes_rotations():
    arm = Arm.from_names(NOTES_LINKS, base=NOTES_BASE)
    phi = np.radians([20.0, -35.0, 50.0, 75.0])
    frames = forward(arm, phi).frames
    expected = rz(phi[0])
    np.testing.assert_allclose(frames[0], expected, atol=1e-12)
    for i in range(1, 4):
        expected = expected @ ry(phi[i])
        np.testing.assert_allclose(frames[i], expected, atol=1e-12)


@given(arms())
def test_home_tip_is_base_plus_sum_of_links_for_default_axes(arm_any):
    arm = Arm.from_names(arm_any.links, base=arm_any.base)  # default axes z, y, ..., direction z
    pose = forward(arm, np.zeros(arm.n))
    np.testing.assert_allclose(pose.tip, arm.base + np.array([0.0, 0.0, arm.links.sum()]), atol=1e-12)
    np.testing.assert_allclose(pose.points[0], arm.base)
    np.testing.assert_allclose(np.diff(pose.points[:, 2]), arm.links, atol=1e-12)


def test_home_tip_of_the_notes_arm():
    arm = Arm.from_names(NOTES_LINKS, base=NOTES_BASE)
    np.testing.assert_allclose(forward(arm, np.zeros(4)).tip, [5.0, 5.0, 17.0])


# ------------------------------------------------------------ the n-link assignment


def planar(n: int) -> Arm:
    return Arm.from_names([1.0] * n, axes=["z"] * n, direction="x")


def assignment_tip(theta):
    """p = T0 R0(theta0) T1 R1(theta1) ... r in 2-D homogeneous coordinates, r = [1 0 1]."""
    world = np.eye(3)
    for i, th in enumerate(theta):
        t = np.eye(3)
        if i > 0:
            t[0, 2] = 1.0  # T_i: the previous link's length along x
        c, s = np.cos(th), np.sin(th)
        world = world @ t @ np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])
    return (world @ np.array([1.0, 0.0, 1.0]))[:2]


@pytest.mark.parametrize("n, expected", [(1, (1.0, 0.0)), (2, (2.0, 0.0)), (4, (4.0, 0.0))])
def test_planar_tip_equals_published_p(n, expected):
    tip = forward(planar(n), np.zeros(n)).tip
    np.testing.assert_allclose(tip, [*expected, 0.0], atol=1e-12)


@given(st.integers(1, 6).flatmap(lambda n: poses(n)))
def test_planar_fk_equals_assignment_chain(theta):
    n = len(theta)
    tip = forward(planar(n), theta).tip
    np.testing.assert_allclose(tip[:2], assignment_tip(theta), atol=1e-12)
    assert tip[2] == 0.0


# published P' and P'' (P'' as 2n x n: block row i, column j holds p''_ij)
PUBLISHED = {
    1: dict(P1=[[0.0], [1.0]], P2=[[-1.0], [0.0]]),
    2: dict(P1=[[0, 0], [2, 1]], P2=[[-2, -1], [0, 0], [-1, -1], [0, 0]]),
    4: dict(
        P1=[[0, 0, 0, 0], [4, 3, 2, 1]],
        P2=[
            [-4, -3, -2, -1],
            [0, 0, 0, 0],
            [-3, -3, -2, -1],
            [0, 0, 0, 0],
            [-2, -2, -2, -1],
            [0, 0, 0, 0],
            [-1, -1, -1, -1],
            [0, 0, 0, 0],
        ],
    ),
}


@pytest.mark.parametrize("n", [1, 2, 4])
def test_point_jacobian_of_tip_equals_published_P_prime(n):
    arm = planar(n)
    pose = forward(arm, np.zeros(n))
    jac = point_jacobian(arm, pose, n - 1, pose.tip)
    np.testing.assert_allclose(jac[:2], PUBLISHED[n]["P1"], atol=1e-9)
    np.testing.assert_allclose(jac[2], 0.0, atol=1e-12)
    np.testing.assert_allclose(tip_jacobian(arm, pose), jac, atol=0)


@pytest.mark.parametrize("n", [1, 2, 4])
def test_point_hessian_of_tip_equals_published_P_double_prime(n):
    arm = planar(n)
    pose = forward(arm, np.zeros(n))
    hess = point_hessian(arm, pose, n - 1, pose.tip)  # (3, n, n)
    published = np.array(PUBLISHED[n]["P2"], dtype=float).reshape(n, 2, n)  # [i, xy, j]
    np.testing.assert_allclose(hess[:2].transpose(1, 0, 2), published, atol=1e-9)
    np.testing.assert_allclose(hess[2], 0.0, atol=1e-12)


# ------------------------------------------------------------ batching


@given(arms(), st.integers(1, 7), st.randoms(use_true_random=False))
def test_batched_fk_equals_one_by_one(arm, frames, rnd):
    phi = np.array([[rnd.uniform(-np.pi, np.pi) for _ in range(arm.n)] for _ in range(frames)])
    batch = forward(arm, phi)
    assert batch.points.shape == (frames, arm.n + 1, 3)
    assert batch.frames.shape == (frames, arm.n, 3, 3)
    for k in range(frames):
        one = forward(arm, phi[k])
        np.testing.assert_allclose(batch.points[k], one.points, atol=1e-12)
        np.testing.assert_allclose(batch.frames[k], one.frames, atol=1e-12)
    jac = point_jacobian(arm, batch, arm.n - 1, link_point(batch, arm.n - 1, 0.5))
    for k in range(frames):
        one = forward(arm, phi[k])
        np.testing.assert_allclose(
            jac[k], point_jacobian(arm, one, arm.n - 1, link_point(one, arm.n - 1, 0.5)), atol=1e-12
        )


def test_fk_accepts_2d_batch_shape():
    arm = Arm.from_names(NOTES_LINKS, base=NOTES_BASE)
    phi = np.zeros((2, 3, 4))
    assert forward(arm, phi).points.shape == (2, 3, 5, 3)


@given(arm_and_pose())
def test_frames_are_rotations_and_links_keep_their_length(ap):
    arm, phi = ap
    pose = forward(arm, phi)
    eye = np.broadcast_to(np.eye(3), pose.frames.shape)
    np.testing.assert_allclose(pose.frames @ np.swapaxes(pose.frames, -1, -2), eye, atol=1e-12)
    np.testing.assert_allclose(np.linalg.det(pose.frames), 1.0, atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(np.diff(pose.points, axis=0), axis=1), arm.links, atol=1e-12)


# ------------------------------------------------------------ derivatives


def central_jacobian(fun, phi, h=1e-6):
    cols = []
    for i in range(len(phi)):
        e = np.zeros(len(phi))
        e[i] = h
        cols.append((fun(phi + e) - fun(phi - e)) / (2 * h))
    return np.stack(cols, axis=-1)


@given(arm_and_pose(), st.data())
def test_point_jacobian_of_any_point_matches_central_differences(ap, data):
    arm, phi = ap
    link = data.draw(st.integers(0, arm.n - 1))
    t = data.draw(st.floats(0.0, 1.0))
    pose = forward(arm, phi)
    analytic = point_jacobian(arm, pose, link, link_point(pose, link, t))
    numeric = central_jacobian(lambda p: link_point(forward(arm, p), link, t), phi)
    np.testing.assert_allclose(analytic, numeric, atol=1e-7 * max(1.0, arm.reach))
    np.testing.assert_array_equal(analytic[:, link + 1 :], 0.0)


@given(arm_and_pose(), st.data())
def test_point_hessian_matches_central_differences_of_the_jacobian(ap, data):
    arm, phi = ap
    link = data.draw(st.integers(0, arm.n - 1))
    t = data.draw(st.floats(0.0, 1.0))
    pose = forward(arm, phi)
    hess = point_hessian(arm, pose, link, link_point(pose, link, t))
    numeric = central_jacobian(lambda p: _link_point_jacobian(arm, forward(arm, p), link, t), phi, h=1e-5)
    np.testing.assert_allclose(hess, numeric, atol=1e-6 * max(1.0, arm.reach))
    np.testing.assert_allclose(hess, np.swapaxes(hess, 1, 2), atol=1e-12)


@given(arm_and_pose())
def test_numeric_jacobian_eq15_is_close_to_analytic(ap):
    arm, phi = ap
    numeric = numeric_jacobian(lambda p: forward(arm, p).tip, phi)
    analytic = tip_jacobian(arm, forward(arm, phi))
    assert numeric.shape == (3, arm.n)
    # forward differences: error O(h * |second derivative|) <= h * reach
    np.testing.assert_allclose(numeric, analytic, atol=1e-5 * max(1.0, arm.reach))


def test_numeric_jacobian_is_a_forward_difference():
    fun = lambda p: np.stack([p[..., 0] ** 2, p[..., 0] * p[..., 1]], -1)  # noqa: E731
    h = 1e-3
    jac = numeric_jacobian(fun, np.array([3.0, 2.0]), h=h)
    np.testing.assert_allclose(jac, [[6.0 + h, 0.0], [2.0, 3.0]], atol=1e-9)


@given(arm_and_pose())
def test_pseudo_inverse_is_moore_penrose(ap):
    arm, phi = ap
    jac = tip_jacobian(arm, forward(arm, phi))
    pinv = pseudo_inverse(jac)
    # singular values below PINV_RTOL of the largest are dropped on purpose: J - J J+ J is
    # exactly that dropped part, so its entries stay below PINV_RTOL times the largest one
    largest = np.linalg.svd(jac, compute_uv=False)[0]
    np.testing.assert_allclose(jac @ pinv @ jac, jac, atol=PINV_RTOL * largest + 1e-8 * max(1.0, arm.reach) ** 2)
    np.testing.assert_allclose(pinv @ jac @ pinv, pinv, atol=1e-6 * max(1.0, np.abs(pinv).max()) ** 2)


# ------------------------------------------------------------ geometry helpers


@pytest.mark.parametrize("axis, fn", [("z", rz), ("y", ry)])
@pytest.mark.parametrize("angle", [-2.5, -0.3, 0.0, 1.0, np.pi])
def test_rotation_about_coordinate_axes_matches_notes(axis, fn, angle):
    arm = Arm.from_names([1.0], axes=[axis])
    np.testing.assert_allclose(joint_rotations(arm, np.array([angle]))[0], fn(angle), atol=1e-15)


@given(st.floats(-100, 100))
def test_wrap_angle_range_and_equivalence(a):
    w = float(wrap_angle(np.array(a)))
    assert -np.pi < w <= np.pi
    assert np.isclose(np.cos(w), np.cos(a), atol=1e-9) and np.isclose(np.sin(w), np.sin(a), atol=1e-9)


def test_segment_distance_and_closest_point():
    a, b = np.zeros(3), np.array([2.0, 0, 0])
    assert float(closest_on_segment(a, b, np.array([-1.0, 1, 0]))) == 0.0
    assert float(closest_on_segment(a, b, np.array([5.0, 1, 0]))) == 1.0
    assert float(closest_on_segment(a, a, np.array([3.0, 4, 0]))) == 0.0  # a point: any t, 0 by convention


def _link_point_jacobian(arm, pose, link, t):
    return point_jacobian(arm, pose, link, link_point(pose, link, t))
