"""Closest points between a segment and a solid, in closed form (numpy, batched).

A link capsule is a segment with a radius; its clearance to a solid is the least signed
distance of its segment's points to the solid, less the radius. :func:`segment_box` returns,
for segments a-b, the fraction t along the segment of that least point and the box's signed
distance there (negative inside), with the unit normal (the signed distance's gradient
there, pointing out of the box). A box may be flat or a segment (edges of length 0): a
capsule obstacle is its axis, a box with one edge, grown by its radius. Everything
broadcasts over leading dimensions. Pure core: numpy only.

Exact: the least distance of a segment to a box is a convex problem in one variable whose
pieces are quadratics (outside) or linear (inside); the minimiser is found on its piece in
closed form (measured against coal's GJK and against sampling in the tests).
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


def excess_beyond(p: np.ndarray, low: np.ndarray, half: np.ndarray) -> np.ndarray:
    """How far points ``p`` (box frame) lie beyond the box [low, half] along each axis: p less
    its nearest point of the box, 0 inside; its length is the distance. Elementwise: points
    (..., 3) with bounds (3,), or coordinates first, (3, ...) with bounds that broadcast.

    >>> excess_beyond(np.array([2.0, 0.5, -3.0]), -np.ones(3), np.ones(3)).tolist()
    [1.0, 0.0, -2.0]
    """
    return p - np.minimum(np.maximum(p, low), half)


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
    gap = excess_beyond(p, -half, half)
    outside = np.sqrt(dot(gap, gap))
    if (outside > 0).all():  # every point outside (what a frame mostly has): no face to choose
        return gap / outside[..., None]
    q = np.abs(p) - half
    axis = np.argmax(q, axis=-1)
    face = np.where(np.arange(3) == axis[..., None], np.where(p >= 0, 1.0, -1.0), 0.0)
    return np.where((outside > 0)[..., None], gap / np.where(outside > 0, outside, 1.0)[..., None], face)


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

    Outside the box, the squared distance g(t) of a + t (b - a) is convex, and its derivative
    is piecewise linear and nondecreasing, with knots where the segment crosses the box's
    six slab planes. The least point is where that derivative changes sign: between the
    first knot where it is positive and the knot before, on one piece, where a closed form
    gives it. Of tied points (a link along a face) it is the one nearest b, the far end,
    which a joint moves most. A segment that reaches within :data:`TOUCHING` of the box
    is searched again among the candidates of its depth inside (:func:`_inside_candidates`).
    A box may have edges of length 0: with half edges (L/2, 0, 0) it is a segment, and
    the distance is between two segments (a capsule obstacle's axis).

    Parameters
    ----------
    a, b : (..., 3) arrays
        The segment's ends, world.
    center, half : (..., 3) arrays
        The box's centre (world) and half edges (>= 0).
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
    x0 = np.matmul((a - center)[..., None, :], rotation)[..., 0, :]  # box frame: (R^T v) as a row is v R
    u = np.matmul((b - a)[..., None, :], rotation)[..., 0, :]
    single = x0.ndim == 1 and u.ndim == 1 and np.ndim(half) == 1  # one segment: computed as a batch of one, so that its results are arrays
    if single:
        x0, u = x0[None], u[None]
    half = np.asarray(half, dtype=float)
    half = half.reshape((1,) * (x0.ndim - half.ndim) + half.shape)
    # copied coordinates first: some 50 operations follow, and on a transposed view each would
    # step through memory three values at a time
    x0, u = np.ascontiguousarray(coordinates_first(x0)), np.ascontiguousarray(coordinates_first(u))
    t, dist, local = _least_in_box_frame(x0, u, coordinates_first(half))
    normal = np.matmul(rotation, coordinates_last(local)[..., None])[..., 0]
    return (t[0], dist[0], normal[0]) if single else (t, dist, normal)


def coordinates_first(v: np.ndarray) -> np.ndarray:
    """The view (3, ...) of points ``v`` (..., 3).

    >>> coordinates_first(np.zeros((4, 5, 3))).shape
    (3, 4, 5)
    """
    return v.transpose((v.ndim - 1,) + tuple(range(v.ndim - 1)))


def coordinates_last(v: np.ndarray) -> np.ndarray:
    """The view (..., 3) of points ``v`` (3, ...): :func:`coordinates_first` undone."""
    return v.transpose(tuple(range(1, v.ndim)) + (0,))


def _least_in_box_frame(x0: np.ndarray, u: np.ndarray, half: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`segment_box` in the box frame, coordinates first: x0 + t u against [-half, half],
    (3, ...) each (``half`` broadcast); (t (...), distance (...), the unit normal in the box
    frame (3, ...)).

    With the coordinates first, every operation runs along all of the pairs at once (a batch's
    cost is in its size, not in loops over three coordinates)."""
    low = -half
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):  # u_i = 0: no crossing (its knots go to an end)
        t = _least_outside(x0, u, low, half)
    xt = t * u
    xt += x0
    gap = excess_beyond(xt, low, half)
    squares = gap * gap
    dist = np.sqrt(squares[0] + squares[1] + squares[2])
    touching = dist <= TOUCHING
    if not touching.any():
        gap /= dist
        return t, dist, gap
    half = np.broadcast_to(half, x0.shape)  # the segment reaches the box: find its deepest point
    x0_in, u_in, half_in = x0[:, touching].T, u[:, touching].T, half[:, touching].T
    ends = np.broadcast_to(_FAR_END_FIRST, x0_in.shape[:-1] + (2,))
    t_in = np.concatenate([_inside_candidates(x0_in, u_in, half_in), ends, t[touching][..., None]], axis=-1)
    sdf_in = box_signed_distance(x0_in[..., None, :] + t_in[..., None] * u_in[..., None, :], half_in[..., None, :])
    dist[touching], t[touching] = least(sdf_in, t_in)
    return t, dist, coordinates_first(box_normal(coordinates_last(x0 + t * u), coordinates_last(half)))


TOUCHING = 1e-9
"""Scene units: a segment whose least outside distance to a box is this or less may enter it
(rounding puts a point on the surface a little either side), so its depth is searched for."""

_FAR_END_FIRST = np.array([1.0, 0.0])
"""The segment's ends as candidates inside, the far end first (of ties, the one a joint moves most)."""


def _least_outside(x0: np.ndarray, u: np.ndarray, low: np.ndarray, half: np.ndarray) -> np.ndarray:
    """(...) the largest t in [0, 1] that minimises the squared distance of x0 + t u (box
    frame, coordinates first: (3, ...)) to the box [low, half]: where its derivative,
    sum_i u_i e_i(t) with e the excess beyond the box, stops being <= 0 (0 inside the box)."""
    knots = np.empty((8,) + x0.shape[1:])  # the six slab crossings, clipped to [0, 1], and the ends
    inverse = 1.0 / u
    np.multiply(half - x0, inverse, out=knots[0:3])
    np.multiply(low - x0, inverse, out=knots[3:6])
    crossings = knots[:6]
    np.fmin(np.fmax(crossings, 0.0, out=crossings), 1.0, out=crossings)  # fmax: a NaN (0/0) goes to 0
    knots[6] = _FAR_END_FIRST[0]
    knots[7] = _FAR_END_FIRST[1]
    x = knots[:, None] * u  # (8, 3, ...): each knot's point
    x += x0
    excess = excess_beyond(x, low, half)
    excess *= u
    slope = excess[:, 0] + excess[:, 1]
    slope += excess[:, 2]
    right = np.where(slope > 0.0, knots, 2.0).min(axis=0)  # the first knot where g rises (2: none)
    left = np.where(knots < right, knots, 0.0).max(axis=0)  # the knot before it
    right = np.minimum(right, 1.0)
    mid = (0.5 * (left + right)) * u  # on (left, right) the same coordinates are beyond the box
    mid += x0
    near = np.minimum(np.maximum(mid, low), half)
    moving = np.where(mid != near, u, 0.0)
    offset = moving * (x0 - near)
    rate = moving * u
    root = -(offset[0] + offset[1] + offset[2]) / (rate[0] + rate[1] + rate[2])  # where that piece's derivative is 0
    return np.fmax(np.fmin(root, right), left)  # fmin: a flat piece (0/0) takes its right end
