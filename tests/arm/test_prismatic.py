"""Prismatic joints on the arm's chain (issue 52, item 3): the numpy forward kinematics and its
Jacobians (:mod:`armanim.arm.kinematics`) and the compiled ones (:mod:`armanim.arm.kernel`) on
random chains that mix revolute and prismatic joints, against pinocchio (a model built joint by
joint from the same constants: an independent chain) and finite differences."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from armanim.arm import kernel
from armanim.arm.kinematics import (
    Arm,
    angular_jacobian,
    forward,
    numeric_jacobian,
    point_hessian,
    point_jacobian,
    tip_jacobian,
    tool_rotation,
)
from armanim.arm.rotations import rotation_exp

TOL = 1e-12
vectors = st.lists(st.floats(-2.0, 2.0, allow_nan=False), min_size=3, max_size=3).map(np.array)


@st.composite
def mixed_arms(draw, max_links: int = 7) -> tuple[Arm, np.ndarray]:
    """Any chain of unit axes, offsets, turns and a base rotation, with at least one prismatic
    joint, and a pose of it (radians for a revolute joint, metres for a prismatic one)."""
    n = draw(st.integers(1, max_links))
    axes = [draw(vectors) for _ in range(n)]
    axes = [a / np.linalg.norm(a) if np.linalg.norm(a) > 1e-3 else np.array([0.0, 0, 1]) for a in axes]
    slides = draw(st.lists(st.booleans(), min_size=n, max_size=n))
    slides[draw(st.integers(0, n - 1))] = True
    arm = Arm(
        base=draw(vectors),
        axes=np.array(axes),
        offsets=np.array([draw(vectors) for _ in range(n)]),
        base_rotation=rotation_exp(draw(vectors)),
        turns=np.array([rotation_exp(draw(vectors)) for _ in range(n)]),
        prismatic=np.array(slides),
    )
    phi = np.array([draw(st.floats(-1.5, 1.5, allow_nan=False)) for _ in range(n)])
    return arm, phi


def pinocchio_model(pin, arm: Arm):
    """The arm as a pinocchio model: joint i placed by (T_{i-1}, o_{i-1}) in joint i-1's frame
    (the first by the base), a revolute or prismatic joint about its unaligned axis, and a tool
    frame by (T_{n-1}, o_{n-1}) in the last joint's."""
    model = pin.Model()
    parent = 0
    for i in range(arm.n):
        if i == 0:
            placement = pin.SE3(arm.base_rotation, arm.base)
        else:
            placement = pin.SE3(arm.turns[i - 1], arm.offsets[i - 1])
        joint = (pin.JointModelPrismaticUnaligned if arm.slides[i] else pin.JointModelRevoluteUnaligned)(arm.axes[i])
        parent = model.addJoint(parent, joint, placement, f"j{i}")
    tool = model.addFrame(pin.Frame("tool", parent, 0, pin.SE3(arm.turns[-1], arm.offsets[-1]), pin.FrameType.OP_FRAME))
    return model, tool


@settings(max_examples=60, deadline=None)
@given(mixed_arms())
def test_forward_kinematics_and_jacobians_equal_pinocchio(case):
    pin = pytest.importorskip("pinocchio")
    arm, phi = case
    model, tool = pinocchio_model(pin, arm)
    data = model.createData()
    pin.framesForwardKinematics(model, data, phi)
    pose = forward(arm, phi)
    for i in range(arm.n):  # each joint's frame: its (slid) origin and its rotation
        np.testing.assert_allclose(pose.points[i], data.oMi[i + 1].translation, atol=TOL, rtol=0)
        np.testing.assert_allclose(pose.frames[i], data.oMi[i + 1].rotation, atol=TOL, rtol=0)
    np.testing.assert_allclose(pose.tip, data.oMf[tool].translation, atol=TOL, rtol=0)
    np.testing.assert_allclose(tool_rotation(arm, pose), data.oMf[tool].rotation, atol=TOL, rtol=0)
    jac = np.asarray(pin.computeFrameJacobian(model, data, phi, tool, pin.LOCAL_WORLD_ALIGNED)).reshape(
        6, arm.n
    )  # (6,) for one joint
    np.testing.assert_allclose(tip_jacobian(arm, pose), jac[:3], atol=TOL, rtol=0)
    np.testing.assert_allclose(angular_jacobian(arm, pose), jac[3:], atol=TOL, rtol=0)
    compiled, compiled_tool = kernel.forward_with_tool(arm, phi)
    np.testing.assert_allclose(compiled.points, pose.points, atol=TOL, rtol=0)
    np.testing.assert_allclose(compiled_tool, data.oMf[tool].rotation, atol=TOL, rtol=0)
    np.testing.assert_allclose(kernel.geometric_jacobian(compiled, arm), jac, atol=TOL, rtol=0)


@settings(max_examples=60, deadline=None)
@given(mixed_arms(), st.floats(0.0, 1.0))
def test_jacobians_and_hessian_are_the_derivatives_of_forward_kinematics(case, t):
    arm, phi = case
    pose = forward(arm, phi)
    h = 1e-6
    for link in range(arm.n):  # a point a fraction t along each link, carried by its joint's frame
        local = t * arm.offsets[link]

        def carried(p, link=link, local=local):
            batch = forward(arm, p)
            return batch.points[..., link, :] + batch.frames[..., link, :, :] @ local

        point = carried(phi)
        expected = (numeric_jacobian(carried, phi, h) + numeric_jacobian(carried, phi, -h)) / 2  # central differences
        np.testing.assert_allclose(point_jacobian(arm, pose, link, point), expected, atol=1e-6, rtol=0)
        columns = point_jacobian(arm, pose, np.array([link]), point[None])[0]  # the many-points form
        np.testing.assert_allclose(columns, point_jacobian(arm, pose, link, point), atol=TOL, rtol=0)
        hess = point_hessian(arm, pose, link, point)
        for i in range(arm.n):  # d/dphi_i of the Jacobian, by central differences
            step = h * np.eye(arm.n)[i]
            plus = point_jacobian(arm, forward(arm, phi + step), link, carried(phi + step))
            minus = point_jacobian(arm, forward(arm, phi - step), link, carried(phi - step))
            np.testing.assert_allclose(hess[:, i, :], (plus - minus) / (2 * h), atol=1e-5, rtol=0)
    batch = forward(arm, np.stack([phi, -phi]))  # the batched chain is the single pose's
    np.testing.assert_allclose(batch.points[0], pose.points, atol=TOL, rtol=0)
    np.testing.assert_allclose(tip_jacobian(arm, batch)[1], tip_jacobian(arm, forward(arm, -phi)), atol=TOL, rtol=0)


def test_a_rail_carries_the_arm_along_its_axis():
    """One metre of rail along x, then a revolute joint about z with a 1 m link along x."""
    arm = Arm(
        base=np.zeros(3),
        axes=np.array([[1.0, 0, 0], [0, 0, 1.0]]),
        offsets=np.array([[0.0, 0, 0.5], [1.0, 0, 0]]),
        prismatic=np.array([True, False]),
    )
    pose = forward(arm, np.array([1.0, np.pi / 2]))
    np.testing.assert_allclose(pose.tip, [1.0, 1.0, 0.5], atol=TOL)
    np.testing.assert_allclose(tip_jacobian(arm, pose), [[1.0, -1.0], [0.0, 0.0], [0.0, 0.0]], atol=TOL)
    np.testing.assert_allclose(angular_jacobian(arm, pose), [[0.0, 0.0], [0.0, 0.0], [0.0, 1.0]], atol=TOL)
    assert Arm.from_names([1.0, 1.0]).prismatic is None
    assert (
        Arm(base=np.zeros(3), axes=np.eye(3)[:1], offsets=np.eye(3)[:1], prismatic=np.array([False])).prismatic is None
    )
