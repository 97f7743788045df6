"""Closest points between a segment and a solid, in closed form (numpy, batched).

A link capsule is a segment with a radius; its clearance to a solid is the least signed
distance of its segment's points to the solid, less the radius. Each function here
returns, for segments a-b, the fraction t along the segment of that least point and the
solid's signed distance there (negative inside), with the unit normal (the signed
distance's gradient there, pointing out of the solid). Everything broadcasts over leading
dimensions. Pure core: numpy only.

Exact: the least distance of a segment to a box or to a segment is a convex problem in
one or two variables whose pieces are quadratics; each function evaluates every piece's
minimiser in closed form and keeps the least (measured against coal's GJK in the tests).
"""

from __future__ import annotations

from itertools import combinations

import numpy as np


def dot(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Dot product over the last axis, (...)."""
    return (u * v).sum(axis=-1)


def safe_ratio(num: np.ndarray, den: np.ndarray) -> np.ndarray:
    """num / den, 0 where den is 0."""
    nonzero = den != 0.0
    with np.errstate(over="ignore"):  # a huge ratio (a segment almost parallel to a plane) is clipped by the callers
        return np.where(nonzero, num / np.where(nonzero, den, 1.0), 0.0)


def segment_segment(a: np.ndarray, b: np.ndarray, c: np.ndarray, e: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Closest points of segments a-b and c-e: (s, t, offset), with s along a-b, t along c-e
    and offset = (a + s (b - a)) - (c + t (e - c)), shapes (...), (...), (..., 3).

    Ericson's closed form (Real-Time Collision Detection, 5.1.9): the squared distance is a
    convex quadratic on the unit square; s from the lines' closest points clamped, t the
    nearest to that point clamped, then s again for a clamped t. A zero-length a-b (the tip)
    and parallel segments take s = 0 first; a zero-length c-e (a capsule that is a sphere) the
    point of a-b nearest to it.

    >>> s, t, off = segment_segment(np.zeros(3), np.array([2.0, 0, 0]), np.array([1.0, -1, 1]), np.array([1.0, 1, 1]))
    >>> float(s), float(t), off.tolist()
    (0.5, 0.5, [0.0, 0.0, -1.0])
    """
    d1, d2, r = b - a, e - c, a - c
    aa, ee, bb, cc, ff = dot(d1, d1), dot(d2, d2), dot(d1, d2), dot(d1, r), dot(d2, r)
    denom = aa * ee - bb * bb
    s = np.clip(safe_ratio(bb * ff - cc * ee, np.where(denom > 1e-12 * aa * ee, denom, 0.0)), 0.0, 1.0)
    nearest_to_c = np.clip(safe_ratio(-cc, aa), 0.0, 1.0)  # the point of a-b nearest to c
    s = np.where(ee > 0.0, s, nearest_to_c)  # c-e a point: the nearest point of a-b to it
    t = safe_ratio(bb * s + ff, ee)
    below, above = t < 0.0, t > 1.0
    s = np.where(below, nearest_to_c, np.where(above, np.clip(safe_ratio(bb - cc, aa), 0.0, 1.0), s))
    t = np.clip(t, 0.0, 1.0)
    offset = r + s[..., None] * d1 - t[..., None] * d2
    return s, t, offset


def least(values: np.ndarray, *others: np.ndarray) -> tuple[np.ndarray, ...]:
    """The least of ``values`` (..., K) along its last axis, and the entries of ``others``
    (..., K) or (..., K, 3) at the same place (the first of ties)."""
    best = np.argmin(values, axis=-1)
    flat = best.reshape(-1) + values.shape[-1] * np.arange(best.size)
    picked = [values.reshape(-1)[flat].reshape(best.shape)]
    for other in others:
        tail = other.shape[values.ndim:]
        picked.append(other.reshape((-1,) + tail)[flat].reshape(best.shape + tail))
    return tuple(picked)


def box_signed_distance(p: np.ndarray, half: np.ndarray) -> np.ndarray:
    """Signed distance of points ``p`` (box frame, (..., 3)) to the box of half edges ``half``, (...).

    >>> box_signed_distance(np.array([[2.0, 0, 0], [0.5, 0, 0]]), np.ones(3)).tolist()
    [1.0, -0.5]
    """
    q = np.abs(p) - half
    beyond = np.maximum(q, 0.0)
    return np.sqrt(dot(beyond, beyond)) + np.minimum(q.max(axis=-1), 0.0)


def box_normal(p: np.ndarray, half: np.ndarray) -> np.ndarray:
    """Unit outward normal of the box's signed distance at ``p`` (box frame), (..., 3): from
    the nearest surface point outside, the deepest face's normal inside (ties: the first axis)."""
    gap = p - np.clip(p, -half, half)
    outside = np.sqrt(dot(gap, gap))
    if (outside > 0).all():  # every point outside (what a frame mostly has): no face to choose
        return gap / outside[..., None]
    q = np.abs(p) - half
    axis = np.argmax(q, axis=-1)
    face = np.where(np.arange(3) == axis[..., None], np.where(p >= 0, 1.0, -1.0), 0.0)
    return np.where((outside > 0)[..., None], gap / np.where(outside > 0, outside, 1.0)[..., None], face)


_FAR_END_FIRST = np.array([1.0, 0.0])
"""The segment's ends as candidates, the far end first: of tied points (a link along a face) the one a joint moves most."""


def _outside_candidates(x0: np.ndarray, u: np.ndarray, half: np.ndarray) -> np.ndarray:
    """(..., 9) fractions along x0 + t u that contain the least distance to the box when the
    segment stays outside it: its ends and the least point of each piece between the
    crossings of the box's slab planes (where the squared distance is one quadratic)."""
    low = -half
    crossings = safe_ratio(np.concatenate([half - x0, low - x0], axis=-1), np.concatenate([u, u], axis=-1))
    ends = np.empty(x0.shape[:-1] + (2,))
    ends[...] = _FAR_END_FIRST
    knots = np.sort(np.concatenate([np.clip(crossings, 0.0, 1.0), ends], axis=-1), axis=-1)  # (..., 8)
    lo, hi = knots[..., :-1], knots[..., 1:]
    mid = 0.5 * (lo + hi)
    x = x0[..., None, :] + mid[..., None] * u[..., None, :]  # (..., 7, 3)
    side = np.where(x > half[..., None, :], 1.0, np.where(x < low[..., None, :], -1.0, 0.0))
    out = side != 0.0
    uu = u[..., None, :]
    curvature = np.where(out, uu * uu, 0.0).sum(axis=-1)
    slope = np.where(out, uu * (x0[..., None, :] - side * half[..., None, :]), 0.0).sum(axis=-1)
    best = np.clip(safe_ratio(-slope, curvature), lo, hi)
    return np.concatenate([ends, np.where(curvature > 0, best, lo)], axis=-1)


_PAIRS = np.array(list(combinations(range(6), 2)))
"""The 15 pairs of the box's six face functions h_i -+ x_i (i = 0, 1, 2 with +, then with -)."""


def _inside_candidates(x0: np.ndarray, u: np.ndarray, half: np.ndarray) -> np.ndarray:
    """(..., 15) fractions where two of the depth functions h_i - sigma x_i(t) cross: the
    depth inside the box (their least) is concave and piecewise linear, so its greatest value
    along the segment lies at one of them or at an end."""
    sigma = np.array([1.0, 1.0, 1.0, -1.0, -1.0, -1.0])
    level = np.concatenate([half, half], axis=-1) - sigma * np.concatenate([x0, x0], axis=-1)  # (..., 6)
    rate = -sigma * np.concatenate([u, u], axis=-1)
    i, j = _PAIRS[:, 0], _PAIRS[:, 1]
    return np.clip(safe_ratio(level[..., j] - level[..., i], rate[..., i] - rate[..., j]), 0.0, 1.0)


def segment_box(
    a: np.ndarray, b: np.ndarray, center: np.ndarray, half: np.ndarray, rotation: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Least signed distance of segment a-b to a box: (t, distance, normal), shapes (...), (...), (..., 3).

    Parameters
    ----------
    a, b : (..., 3) arrays
        The segment's ends, world.
    center, half : (..., 3) arrays
        The box's centre (world) and half edges.
    rotation : (..., 3, 3) array
        World-from-box rotation.

    Returns
    -------
    t : fraction along a-b of the least point; distance : its signed distance to the box
    (negative inside: minus its depth); normal : the world unit normal there.

    >>> t, d, n = segment_box(np.array([3.0, 0, 0]), np.array([0.0, 0, 3]), np.zeros(3), np.ones(3), np.eye(3))
    >>> float(t), round(float(d) ** 2, 12), np.round(n ** 2, 12).tolist()
    (0.5, 0.5, [0.5, 0.0, 0.5])
    """
    to_box = np.swapaxes(rotation, -1, -2)
    x0 = np.einsum("...ab,...b->...a", to_box, a - center)
    u = np.einsum("...ab,...b->...a", to_box, b - a)
    half = np.asarray(half)
    if x0.shape != u.shape or half.shape != x0.shape[x0.ndim - half.ndim:]:  # else half alone broadcasts, where it is used
        x0, u, half = np.broadcast_arrays(x0, u, half)
    t = _outside_candidates(x0, u, half)
    sdf = box_signed_distance(x0[..., None, :] + t[..., None] * u[..., None, :], half[..., None, :])
    d_best, t_best = least(sdf, t)
    touching = d_best <= 0.0
    if touching.any():  # the segment enters the box: find its deepest point
        x0_in, u_in, half_in = x0[touching], u[touching], np.broadcast_to(half, x0.shape)[touching]
        t_in = np.concatenate([_inside_candidates(x0_in, u_in, half_in), t[touching]], axis=-1)
        sdf_in = box_signed_distance(x0_in[..., None, :] + t_in[..., None] * u_in[..., None, :], half_in[..., None, :])
        d_best[touching], t_best[touching] = least(sdf_in, t_in)
    local = box_normal(x0 + t_best[..., None] * u, half)
    return t_best, d_best, np.einsum("...ab,...b->...a", rotation, local)
