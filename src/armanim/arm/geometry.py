"""Rotations and distances: the small geometric helpers of the pure core.

Radians everywhere; numpy only. No file, print or plotting in here.
"""

from __future__ import annotations

from typing import cast

import numpy as np
from numpy.typing import ArrayLike

AXIS_VECTORS = {
    "x": np.array([1.0, 0.0, 0.0]),
    "y": np.array([0.0, 1.0, 0.0]),
    "z": np.array([0.0, 0.0, 1.0]),
}


def axis_vector(name: str) -> np.ndarray:
    """Unit vector of a named axis (``"x"``, ``"y"`` or ``"z"``).

    >>> axis_vector("y")
    array([0., 1., 0.])
    """
    return AXIS_VECTORS[name].copy()


def unit_vector(v: ArrayLike) -> np.ndarray:
    """``v / |v|`` for any finite nonzero vector (...,  k), however small or large its components.

    Scaled by its largest component first, so that the length neither underflows (1e-320)
    nor overflows (1e308); a zero or non-finite vector is a ValueError, never NaN.

    >>> unit_vector([1e-320, 0, 0]).tolist(), unit_vector([1e308, 0, 1e308]).round(12).tolist()
    ([1.0, 0.0, 0.0], [0.707106781187, 0.0, 0.707106781187])
    """
    v = np.asarray(v, dtype=float)
    biggest = np.abs(v).max(axis=-1, keepdims=True) if v.size else np.zeros(v.shape[:-1] + (1,))
    if not (np.all(np.isfinite(v)) and np.all(biggest > 0)):
        raise ValueError("a direction must be finite and nonzero")
    scaled = v / biggest
    return cast(np.ndarray, scaled / np.sqrt(np.sum(scaled * scaled, axis=-1, keepdims=True)))


def skew(v: np.ndarray) -> np.ndarray:
    """Cross-product matrix ``[v]x`` with ``skew(v) @ u == cross(v, u)``."""
    x, y, z = v
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Cross product over the last axis, broadcasting: ``np.cross`` without its overhead.

    >>> cross(np.array([1.0, 0, 0]), np.array([0.0, 1, 0]))
    array([0., 0., 1.])
    """
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    out = np.empty(np.broadcast_shapes(a.shape, b.shape))
    out[..., 0] = a1 * b2 - a2 * b1
    out[..., 1] = a2 * b0 - a0 * b2
    out[..., 2] = a0 * b1 - a1 * b0
    return out


def wrap_angle(angle: np.ndarray) -> np.ndarray:
    """Wrap radians into (-pi, pi].

    >>> float(wrap_angle(np.array(3 * np.pi / 2)))
    -1.5707963267948966
    >>> float(wrap_angle(np.array(np.pi)))
    3.141592653589793
    """
    wrapped = np.mod(np.asarray(angle, dtype=float) + np.pi, 2 * np.pi) - np.pi
    return np.where(wrapped == -np.pi, np.pi, wrapped)


def closest_on_segment(a: np.ndarray, b: np.ndarray, point: np.ndarray) -> np.ndarray:
    """Fraction t in [0, 1] of the point of segment a-b closest to ``point``.

    Broadcasts over leading dimensions: ``a``, ``b`` of shape (..., 3) and ``point``
    of shape (..., 3) give t of shape (...).

    >>> float(closest_on_segment(np.zeros(3), np.array([2.0, 0, 0]), np.array([1.0, 5, 0])))
    0.5
    """
    ab = b - a
    denom = np.einsum("...i,...i->...", ab, ab)
    t = np.einsum("...i,...i->...", point - a, ab) / np.where(denom > 0.0, denom, 1.0)
    return np.clip(np.where(denom > 0.0, t, 0.0), 0.0, 1.0)
