"""THE orientation part of the pose error, for every method: what a goal asks of the tool's rotation.

A goal with an orientation adds to the position error p_g - p the rotation error

- full orientation (6-D goal): r = log(R_g R^T), the rotation vector taking the tool frame R
  onto the goal's R_g, in the world;
- tool axis (5-D goal): r = the shortest rotation taking the tool's z axis onto the goal's
  axis (:func:`armanim.arm.rotations.alignment_vector`), perpendicular to the tool's z, so the
  roll about it stays free.

Its Jacobian is the geometric one: d r / d Phi ~ -J_w, J_w the angular Jacobian (the tool's
angular velocity per joint rate). The solvers use the rows of the task that the goal sets
(:func:`orientation_task`): all three for a full orientation, the two perpendicular to the
tool's z for a tool axis. For the cost methods the gradient of 1/2 |r|^2 is exactly -r^T J_w
(:func:`orientation_gradient`).

``solver.orientation_weight`` w (length per radian) turns radians into lengths: the solvers
work on [p_g - p ; w r] with [J_v ; w J_w]. Pure core: numpy only, radians only.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import cast

import numpy as np

from armanim.arm.geometry import unit_vector
from armanim.arm.kinematics import Arm, Pose, angular_jacobian, forward, tip_jacobian, tool_rotation
from armanim.arm.rotations import alignment_vector, perpendicular_basis, rotation_exp, rotation_log, rotation_quaternion


@dataclass(frozen=True)
class Orientation:
    """What a goal asks of the tool frame's rotation: exactly one of the two is set.

    Attributes
    ----------
    rotation : (3, 3) array or None
        R_g, the tool frame's world rotation at the goal (a 6-D goal).
    axis : (3,) array or None
        Unit world direction of the tool's z axis at the goal (a 5-D goal: the roll is free).
    """

    rotation: np.ndarray | None = None
    axis: np.ndarray | None = None

    def __post_init__(self) -> None:
        if (self.rotation is None) == (self.axis is None):
            raise ValueError("an orientation sets exactly one of rotation and axis")
        if self.axis is not None:
            object.__setattr__(self, "axis", unit_vector(self.axis))
        else:
            object.__setattr__(self, "rotation", np.asarray(self.rotation, dtype=float))

    @property
    def rows(self) -> int:
        """Rows it adds to the task: 3 for a rotation, 2 for a tool axis."""
        return 3 if self.rotation is not None else 2


def orientation_residual(orientation: Orientation, rot: np.ndarray) -> np.ndarray:
    """r (..., 3): the world rotation vector from the tool frames ``rot`` (..., 3, 3) to the goal's.

    >>> goal = Orientation(rotation=np.eye(3))
    >>> np.round(orientation_residual(goal, rotation_exp(np.array([0.0, 0, 0.5]))), 12).tolist()
    [0.0, 0.0, -0.5]
    >>> np.round(orientation_residual(Orientation(axis=np.array([1.0, 0, 0])), np.eye(3)), 6).tolist()
    [0.0, 1.570796, 0.0]
    """
    if orientation.rotation is not None:
        return rotation_log(orientation.rotation @ np.swapaxes(rot, -1, -2))
    assert orientation.axis is not None  # an orientation is a rotation or a tool axis
    return alignment_vector(rot[..., :, 2], orientation.axis)


def tool_residual(orientation: Orientation, arm: Arm, pose: Pose) -> np.ndarray:
    """:func:`orientation_residual` of the pose's tool frame, computed once per pose and
    orientation (kept in ``pose.memo``: a step's task and the progress measure of the same pose
    ask for it, the rotation log once)."""
    kept = pose.memo.get("tool_residual")
    if kept is not None and kept[0] is orientation:
        return cast(np.ndarray, kept[1])
    r = orientation_residual(orientation, tool_rotation(arm, pose))
    pose.memo["tool_residual"] = (orientation, r)
    return r


def orientation_angle(orientation: Orientation, rot: np.ndarray) -> np.ndarray:
    """|r| (...,): the angle (radians) still to turn, in [0, pi]."""
    return cast(np.ndarray, np.linalg.norm(orientation_residual(orientation, rot), axis=-1))


def orientation_rows(orientation: Orientation, rot: np.ndarray) -> np.ndarray:
    """(..., k, 3): the directions of the rotation the goal sets; identity (k = 3) for a full
    orientation, the two directions perpendicular to the tool's z (k = 2) for a tool axis."""
    if orientation.rotation is not None:
        return np.broadcast_to(np.eye(3), rot.shape[:-2] + (3, 3))
    return perpendicular_basis(rot[..., :, 2])


def orientation_task(orientation: Orientation, arm: Arm, pose: Pose) -> tuple[np.ndarray, np.ndarray]:
    """The orientation rows of the task: the error B r (..., k) and its Jacobian B J_w (..., k, n),
    unweighted (multiply both by ``solver.orientation_weight``)."""
    rot = tool_rotation(arm, pose)
    rows = orientation_rows(orientation, rot)
    residual = (
        tool_residual(orientation, arm, pose) if pose.points.ndim == 2 else orientation_residual(orientation, rot)
    )
    error = np.einsum("...kc,...c->...k", rows, residual)
    return error, rows @ angular_jacobian(arm, pose)


def orientation_gradient(orientation: Orientation, arm: Arm, pose: Pose) -> tuple[np.ndarray, np.ndarray]:
    """r (3,) and the exact gradient -r^T J_w (n,) of 1/2 |r|^2, for a single pose.

    Exact, not an approximation: r^T J_r^-1(r) = r^T for the right Jacobian J_r of SO(3), and
    for a tool axis the angle's derivative is -(r / |r|) . w_j.
    """
    r = orientation_residual(orientation, tool_rotation(arm, pose))
    return r, -(r @ angular_jacobian(arm, pose))


def partial_orientation(orientation: Orientation, rot: np.ndarray, step: np.ndarray) -> Orientation:
    """The orientation the tool frame ``rot`` (3, 3) reaches by turning by the rotation vector
    ``step`` (3,): a frame's target part of the way to the goal's (``newton``)."""
    turn = rotation_exp(step)
    if orientation.rotation is not None:
        return Orientation(rotation=turn @ rot)
    return Orientation(axis=turn @ rot[:, 2])


def pose_distance(
    distance: float | np.ndarray, angle: float | np.ndarray | None, tolerance: float, angle_tolerance: float
) -> float | np.ndarray:
    """One number for the progress toward a pose goal, in lengths: max(|p_g - p|, angle scaled so
    that ``angle_tolerance`` counts as ``tolerance``). Below ``tolerance`` exactly when both
    tolerances hold; ``angle`` None (a position-only goal): the distance itself.

    >>> float(pose_distance(0.005, np.radians(2.0), 0.01, np.radians(1.0)))
    0.02
    """
    if angle is None:
        return distance
    return np.maximum(distance, np.asarray(angle) * (tolerance / angle_tolerance))


GENERIC_POSES = 3
"""Seeded random poses :func:`holds_orientation` judges the arm's rank at (the largest rank wins)."""


def holds_orientation(arm: Arm, orientation: Orientation) -> bool:
    """Whether the arm, at a generic pose, moves its tip and the goal's rotation rows
    independently: the pose task [J_v ; B J_w] has full row rank 3 + k. False for a 4-joint arm
    with a 6-D goal or a planar arm with any orientation: then a position leaves no freedom to
    meet every orientation, and the orientation comes second.

    >>> notes = Arm.from_names([2, 5, 5, 5], base=(5, 5, 0))
    >>> holds_orientation(notes, Orientation(rotation=np.eye(3)))
    False
    """
    phi = np.random.default_rng(0).uniform(-np.pi, np.pi, size=(GENERIC_POSES, arm.n))
    pose = forward(arm, phi)
    rows = orientation_rows(orientation, tool_rotation(arm, pose))
    task = np.concatenate([tip_jacobian(arm, pose), rows @ angular_jacobian(arm, pose)], axis=-2)
    rank = max(int(np.linalg.matrix_rank(t, tol=1e-9 * max(np.abs(t).max(), 1.0))) for t in task)
    return rank == 3 + orientation.rows


def frame_orientations(
    arm: Arm, orientations: list[Orientation | None], phi: np.ndarray, goal: np.ndarray, pose: Pose | None = None
) -> tuple[np.ndarray | None, np.ndarray]:
    """Per frame of a trajectory: the tool's angle (radians) to its goal's orientation (F,), NaN
    where that goal has none (None when no goal has one), and the tool frame's quaternion (F, 4).

    Parameters
    ----------
    arm : Arm
    orientations : list of Orientation or None
        One per goal of the run.
    phi : (F, n) array
    goal : (F,) int array
        The goal of each frame.
    pose : Pose, optional
        ``forward(arm, phi)``, when the caller has it.
    """
    if pose is None:
        pose = forward(arm, np.asarray(phi, dtype=float).reshape(-1, arm.n))
    rot = tool_rotation(arm, pose)
    quaternions = rotation_quaternion(rot)
    if all(o is None for o in orientations):
        return None, quaternions
    angle = np.full(len(rot), np.nan)
    for k, orientation in enumerate(orientations):
        mine = goal == k
        if orientation is not None and mine.any():
            angle[mine] = orientation_angle(orientation, rot[mine])
    return angle, quaternions
