"""THE rotation conversions of armanim: rpy, quaternions, axis-angle, the SO(3) exponential and log.

Every other module converts through these (the scene's goal orientations, the URDF's origins,
the CSV's tool quaternion, ``fk --json``, the pose error of the solvers). Conventions:

- rpy is URDF's fixed-axis roll-pitch-yaw: R = Rz(yaw) Ry(pitch) Rx(roll);
- quaternions are written (w, x, y, z), scalar first, and returned with w >= 0;
- a rotation vector v is the axis times the angle (radians), R = exp([v]x).

Functions accept a batch where their docstring says ``(..., 3, 3)``. Pure core: numpy only,
radians only, no I/O.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import cast

import numpy as np
from numpy.typing import ArrayLike

from armanim.arm.geometry import skew, unit_vector

SMALL_ANGLE = 1e-8
"""Below this angle (radians) exp and log use their Taylor series (no division by sin)."""


def rpy_rotation(rpy: Sequence[float] | np.ndarray) -> np.ndarray:
    """R = Rz(yaw) Ry(pitch) Rx(roll) of URDF's ``rpy`` (radians), shape (3, 3).

    >>> np.round(rpy_rotation([0, 0, np.pi / 2]) @ [1, 0, 0], 12) + 0.0
    array([0., 1., 0.])
    """
    roll, pitch, yaw = (float(v) for v in rpy)
    cr, sr, cp, sp, cy, sy = np.cos(roll), np.sin(roll), np.cos(pitch), np.sin(pitch), np.cos(yaw), np.sin(yaw)
    rz = np.array([[cy, -sy, 0.0], [sy, cy, 0.0], [0.0, 0.0, 1.0]])
    ry = np.array([[cp, 0.0, sp], [0.0, 1.0, 0.0], [-sp, 0.0, cp]])
    rx = np.array([[1.0, 0.0, 0.0], [0.0, cr, -sr], [0.0, sr, cr]])
    return cast(np.ndarray, rz @ ry @ rx)


def rotation_rpy(rot: np.ndarray) -> np.ndarray:
    """URDF's rpy (radians) of rotations (..., 3, 3), shape (..., 3): the inverse of :func:`rpy_rotation`.

    Pitch is in [-pi/2, pi/2]; at pitch = +-pi/2 (gimbal lock) roll is taken 0.

    >>> np.round(np.degrees(rotation_rpy(rpy_rotation(np.radians([10, -20, 30])))), 9).tolist()
    [10.0, -20.0, 30.0]
    """
    rot = np.asarray(rot, dtype=float)
    pitch = np.arcsin(np.clip(-rot[..., 2, 0], -1.0, 1.0))
    locked = np.abs(rot[..., 2, 0]) > 1.0 - 1e-12
    roll = np.where(locked, 0.0, np.arctan2(rot[..., 2, 1], rot[..., 2, 2]))
    yaw = np.where(locked, np.arctan2(-rot[..., 0, 1], rot[..., 1, 1]), np.arctan2(rot[..., 1, 0], rot[..., 0, 0]))
    return np.stack([roll, pitch, yaw], axis=-1)


def quaternion_rotation(q_wxyz: ArrayLike) -> np.ndarray:
    """The rotation (3, 3) of a quaternion (w, x, y, z), normalised first (any length > 0).

    >>> np.round(quaternion_rotation([0, 0, 0, 1]), 12) + 0.0
    array([[-1.,  0.,  0.],
           [ 0., -1.,  0.],
           [ 0.,  0.,  1.]])
    """
    w, x, y, z = unit_vector(q_wxyz)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def rotation_quaternion(rot: np.ndarray) -> np.ndarray:
    """Unit quaternions (w, x, y, z), w >= 0, of rotations (..., 3, 3), shape (..., 4).

    Shepperd's method: each batch entry is computed from the largest of w, x, y, z, so it
    never divides by a small number.

    >>> rotation_quaternion(np.diag([1.0, -1.0, -1.0])).round(12).tolist()
    [0.0, 1.0, 0.0, 0.0]
    """
    rot = np.asarray(rot, dtype=float)
    m = rot
    trace = m[..., 0, 0] + m[..., 1, 1] + m[..., 2, 2]
    candidates = np.stack([trace, m[..., 0, 0], m[..., 1, 1], m[..., 2, 2]], axis=-1)
    pick = np.argmax(candidates, axis=-1)
    q = np.empty(rot.shape[:-2] + (4,))
    # the four formulas, each exact where its component is the largest
    r = np.sqrt(np.maximum(1.0 + 2.0 * np.take_along_axis(candidates, pick[..., None], -1)[..., 0] - trace, 1e-300))
    s = 0.5 / r
    forms = [
        (
            0.5 * r,
            (m[..., 2, 1] - m[..., 1, 2]) * s,
            (m[..., 0, 2] - m[..., 2, 0]) * s,
            (m[..., 1, 0] - m[..., 0, 1]) * s,
        ),
        (
            (m[..., 2, 1] - m[..., 1, 2]) * s,
            0.5 * r,
            (m[..., 0, 1] + m[..., 1, 0]) * s,
            (m[..., 0, 2] + m[..., 2, 0]) * s,
        ),
        (
            (m[..., 0, 2] - m[..., 2, 0]) * s,
            (m[..., 0, 1] + m[..., 1, 0]) * s,
            0.5 * r,
            (m[..., 1, 2] + m[..., 2, 1]) * s,
        ),
        (
            (m[..., 1, 0] - m[..., 0, 1]) * s,
            (m[..., 0, 2] + m[..., 2, 0]) * s,
            (m[..., 1, 2] + m[..., 2, 1]) * s,
            0.5 * r,
        ),
    ]
    for k, form in enumerate(forms):
        chosen = pick == k
        for c in range(4):
            q[..., c] = np.where(chosen, form[c], q[..., c]) if k else form[c]
    q /= np.linalg.norm(q, axis=-1, keepdims=True)
    return np.where(q[..., :1] < 0, -q, q)


def rotation_exp(vector: np.ndarray) -> np.ndarray:
    """exp([v]x): the rotation (..., 3, 3) by |v| radians about v (Rodrigues' formula).

    >>> np.round(rotation_exp(np.array([0, 0, np.pi / 2])) @ [1, 0, 0], 12) + 0.0
    array([0., 1., 0.])
    """
    v = np.asarray(vector, dtype=float)
    angle = np.linalg.norm(v, axis=-1)[..., None, None]
    small = angle < SMALL_ANGLE
    safe = np.where(small, 1.0, angle)
    a = np.where(small, 1.0 - angle**2 / 6.0, np.sin(safe) / safe)
    b = np.where(small, 0.5 - angle**2 / 24.0, (1.0 - np.cos(safe)) / safe**2)
    k = skew_batch(v)
    return cast(np.ndarray, np.eye(3) + a * k + b * (k @ k))


def axis_angle_rotation(axis: ArrayLike, angle: float) -> np.ndarray:
    """The rotation (3, 3) by ``angle`` radians about ``axis`` (any length > 0).

    >>> np.round(axis_angle_rotation([0, 0, 2], np.pi) @ [1, 0, 0], 12) + 0.0
    array([-1.,  0.,  0.])
    """
    return rotation_exp(unit_vector(axis) * float(angle))


def rotation_log(rot: np.ndarray) -> np.ndarray:
    """The rotation vector (..., 3) of rotations (..., 3, 3): the axis times the angle in [0, pi].

    Accurate at every angle: near 0 by the series of the skew part, near pi from the
    diagonal of R + R^T (where the skew part vanishes), the sign taken from the skew part.

    >>> np.round(rotation_log(rotation_exp(np.array([0.3, -0.2, 0.1]))), 12).tolist()
    [0.3, -0.2, 0.1]
    """
    rot = np.asarray(rot, dtype=float)
    if rot.ndim == 2:
        return _log_one(rot)
    skew_part = 0.5 * np.stack(
        [rot[..., 2, 1] - rot[..., 1, 2], rot[..., 0, 2] - rot[..., 2, 0], rot[..., 1, 0] - rot[..., 0, 1]], axis=-1
    )  # sin(angle) * axis
    cos = np.clip(0.5 * (rot[..., 0, 0] + rot[..., 1, 1] + rot[..., 2, 2] - 1.0), -1.0, 1.0)
    sin = np.linalg.norm(skew_part, axis=-1)
    angle = np.arctan2(sin, cos)
    small = angle < 1e-4
    scale = np.where(small, 1.0 + angle**2 / 6.0, angle / np.where(sin > 0, sin, 1.0))
    near_pi = (cos < -0.9) & ~small
    if not np.any(near_pi):
        return cast(np.ndarray, scale[..., None] * skew_part)
    # axis from the symmetric part: (R + R^T)/2 = cos I + (1 - cos) a a^T
    sym = 0.5 * (rot + np.swapaxes(rot, -1, -2))
    outer = (sym - cos[..., None, None] * np.eye(3)) / np.where(near_pi, 1.0 - cos, 1.0)[..., None, None]
    column = np.argmax(np.diagonal(outer, axis1=-2, axis2=-1), axis=-1)
    axis = np.take_along_axis(outer, column[..., None, None], -1)[..., 0]
    length = np.linalg.norm(axis, axis=-1, keepdims=True)
    axis = axis / np.where(length > 0, length, 1.0)
    sign = np.where(np.sum(axis * skew_part, axis=-1) < 0, -1.0, 1.0)
    far = sign[..., None] * angle[..., None] * axis
    return cast(np.ndarray, np.where(near_pi[..., None], far, scale[..., None] * skew_part))


def _log_one(rot: np.ndarray) -> np.ndarray:
    """:func:`rotation_log` of one rotation, in scalar arithmetic (the solvers' hot path); the
    same formulas, batch code near pi."""
    sx, sy, sz = 0.5 * (rot[2, 1] - rot[1, 2]), 0.5 * (rot[0, 2] - rot[2, 0]), 0.5 * (rot[1, 0] - rot[0, 1])
    cos = min(1.0, max(-1.0, 0.5 * (rot[0, 0] + rot[1, 1] + rot[2, 2] - 1.0)))
    sin = math.sqrt(sx * sx + sy * sy + sz * sz)
    angle = math.atan2(sin, cos)
    if angle < 1e-4:
        scale = 1.0 + angle * angle / 6.0
    elif cos < -0.9:
        return cast(np.ndarray, rotation_log(rot[None])[0])
    else:
        scale = angle / sin
    return np.array([scale * sx, scale * sy, scale * sz])


def alignment_vector(current: np.ndarray, target: np.ndarray) -> np.ndarray:
    """The shortest rotation vector (..., 3) taking the unit vectors ``current`` onto ``target``.

    It is perpendicular to both, so it never turns about ``current`` (the roll stays free).
    For opposite vectors (angle pi) any perpendicular axis would do: the one nearest to
    current x e, e the coordinate axis least along ``current``.

    >>> np.round(alignment_vector(np.array([0.0, 0, 1]), np.array([1.0, 0, 0])), 12).tolist()
    [0.0, 1.570796326795, 0.0]
    """
    current = np.asarray(current, dtype=float)
    target = np.asarray(target, dtype=float)
    normal = np.cross(current, target)
    sin = np.linalg.norm(normal, axis=-1)
    cos = np.sum(current * target, axis=-1)
    angle = np.arctan2(sin, cos)
    least = np.eye(3)[np.argmin(np.abs(current), axis=-1)]
    fallback = np.cross(current, least)
    axis = np.where((sin < 1e-12)[..., None], fallback, normal)
    axis = axis / np.linalg.norm(axis, axis=-1, keepdims=True)
    rotation: np.ndarray = angle[..., None] * axis
    return rotation


def perpendicular_basis(axis: np.ndarray) -> np.ndarray:
    """Two unit rows (..., 2, 3) spanning the plane perpendicular to the unit vector ``axis``.

    >>> perpendicular_basis(np.array([0.0, 0, 1])) @ [0, 0, 1]
    array([0., 0.])
    """
    axis = np.asarray(axis, dtype=float)
    least = np.eye(3)[np.argmin(np.abs(axis), axis=-1)]
    first = np.cross(axis, least)
    first = first / np.linalg.norm(first, axis=-1, keepdims=True)
    second = np.cross(axis, first)
    return np.stack([first, second], axis=-2)


def skew_batch(v: np.ndarray) -> np.ndarray:
    """[v]x of vectors (..., 3), shape (..., 3, 3) (:func:`armanim.arm.geometry.skew` for one)."""
    v = np.asarray(v, dtype=float)
    if v.ndim == 1:
        return skew(v)
    zero = np.zeros(v.shape[:-1])
    x, y, z = v[..., 0], v[..., 1], v[..., 2]
    return np.stack([np.stack([zero, -z, y], -1), np.stack([z, zero, -x], -1), np.stack([-y, x, zero], -1)], -2)
