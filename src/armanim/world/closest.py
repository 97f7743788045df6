"""Closest points between segments and solids, exact (batched).

A link capsule is a segment with a radius; its clearance to a solid is the least signed
distance of its segment's points to the solid, less the radius. :func:`segment_box` returns,
for segments a-b, the fraction t along the segment of that least point and the box's signed
distance there (negative inside), with the unit normal (the signed distance's gradient
there, pointing out of the box). A box may be flat or a segment (edges of length 0): a
capsule obstacle is its axis, a box with one edge, grown by its radius. A solid cylinder is
measured apart (:func:`segment_cylinder_grid`). Pure core.

Exact: the least distance of a segment to a box is a convex problem in one variable whose
pieces are quadratics (outside) or linear (inside); the minimiser is found on its piece in
closed form (measured against coal's GJK and against sampling in the tests). The closed form
is compiled (:mod:`armanim.world.compiled`, imported on the first box); the functions here
lay out the pairs.
"""

from __future__ import annotations

from typing import cast

import numpy as np
from numpy.typing import ArrayLike


def excess_beyond(p: np.ndarray, low: np.ndarray, half: np.ndarray) -> np.ndarray:
    """How far points ``p`` (box frame) lie beyond the box [low, half] along each axis: p less
    its nearest point of the box, 0 inside; its length is the distance. Elementwise: points
    (..., 3) with bounds (3,), or coordinates first, (3, ...) with bounds that broadcast.

    >>> excess_beyond(np.array([2.0, 0.5, -3.0]), -np.ones(3), np.ones(3)).tolist()
    [1.0, 0.0, -2.0]
    """
    return cast(np.ndarray, p - np.minimum(np.maximum(p, low), half))


def segment_box(
    a: np.ndarray, b: np.ndarray, center: np.ndarray, half: np.ndarray, rotation: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Least signed distance of segment a-b to a box: (t, distance, normal), shapes (...), (...), (..., 3).

    Outside the box, the squared distance g(t) of a + t (b - a) is convex, and its derivative
    is piecewise linear and nondecreasing, with knots where the segment crosses the box's
    six slab planes. The least point is where that derivative changes sign: between the
    first knot where it is positive and the knot before, on one piece, where a closed form
    gives it. Of tied points (a link along a face) it is the one nearest b, the far end,
    which a joint moves most. A segment that reaches within
    :data:`~armanim.world.compiled.TOUCHING` of the box is searched again for its deepest
    point (its depth is concave and piecewise linear: the greatest value lies where two
    face functions cross or at an end). A box may have edges of length 0: with half edges
    (L/2, 0, 0) it is a segment, and the distance is between two segments (a capsule
    obstacle's axis). Everything broadcasts over leading dimensions.

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
    a, b, center, half = (np.asarray(v, dtype=float) for v in (a, b, center, half))
    rotation = np.asarray(rotation, dtype=float)
    shape = np.broadcast_shapes(a.shape[:-1], b.shape[:-1], center.shape[:-1], half.shape[:-1], rotation.shape[:-2])
    a, b, center, half = (np.broadcast_to(v, shape + (3,)).reshape(-1, 3) for v in (a, b, center, half))
    rotation = np.broadcast_to(rotation, shape + (3, 3)).reshape(-1, 3, 3)
    every = np.arange(len(a))
    t, dist, normal = segment_box_pairs(a, b, center, half, rotation, every, every)
    return t.reshape(shape)[()], dist.reshape(shape)[()], normal.reshape(shape + (3,))


def segment_box_grid(
    a: np.ndarray, b: np.ndarray, center: np.ndarray, half: np.ndarray, rotation: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`segment_box` of every segment a-b ((..., p, 3) each) against every box
    (center and half (k, 3), rotation (k, 3, 3)): t and distance (..., p, k), normal (..., p, k, 3).

    >>> t, d, n = segment_box_grid(np.zeros((2, 3)), np.ones((2, 3)), np.full((1, 3), 3.0), np.ones((1, 3)), np.eye(3)[None])
    >>> d.shape, round(float(d[0, 0]) ** 2, 12)
    ((2, 1), 3.0)
    """
    from armanim.world import compiled

    segments = a.shape[:-1]
    a, b = _rows(a), _rows(b)
    k = len(center)
    t, dist, normal = np.empty((len(a), k)), np.empty((len(a), k)), np.empty((len(a), k, 3))
    compiled.segment_box_grid(a, b, _rows(center), _rows(half), _rows(rotation, 2), t, dist, normal)
    return t.reshape(segments + (k,)), dist.reshape(segments + (k,)), normal.reshape(segments + (k, 3))


def segment_box_pairs(
    a: np.ndarray,
    b: np.ndarray,
    center: np.ndarray,
    half: np.ndarray,
    rotation: np.ndarray,
    segment: ArrayLike,
    box: ArrayLike,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`segment_box` of the pairs (``segment[p]``, ``box[p]``) of the segments a-b
    ((M, 3) each) and the boxes ((K, 3), (K, 3), (K, 3, 3)): t and distance (P,), normal
    (P, 3); each pair's numbers are those :func:`segment_box_grid` gives it, bit for bit."""
    from armanim.world import compiled

    segment, box = np.asarray(segment, dtype=np.intp), np.asarray(box, dtype=np.intp)
    n = len(segment)
    t, dist, normal = np.empty(n), np.empty(n), np.empty((n, 3))
    compiled.segment_box_pairs(
        _rows(a), _rows(b), _rows(center), _rows(half), _rows(rotation, 2), segment, box, t, dist, normal
    )
    return t, dist, normal


def segment_cylinder_grid(
    a: np.ndarray, b: np.ndarray, center: np.ndarray, rotation: np.ndarray, half_length: np.ndarray, radius: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Least signed distance of every segment a-b ((..., p, 3) each) to every solid cylinder
    (center (k, 3), rotation (k, 3, 3) with the axis its third column, half_length and radius
    (k,)): t and distance (..., p, k), normal (..., p, k, 3), compiled
    (:func:`armanim.world.compiled.segment_cylinder_grid`; its numpy reference:
    :func:`armanim.world.distances.segment_cylinder`).

    >>> t, d, n = segment_cylinder_grid(np.array([[3.0, 0, 0]]), np.array([[3.0, 0, 1]]), np.zeros((1, 3)), np.eye(3)[None],
    ...                                 np.ones(1), np.ones(1))
    >>> float(t[0, 0]), float(d[0, 0]), n[0, 0].tolist()
    (1.0, 2.0, [1.0, 0.0, 0.0])
    """
    from armanim.world import compiled

    segments = a.shape[:-1]
    a, b = _rows(a), _rows(b)
    k = len(center)
    t, dist, normal = np.empty((len(a), k)), np.empty((len(a), k)), np.empty((len(a), k, 3))
    compiled.segment_cylinder_grid(
        a,
        b,
        _rows(center),
        _rows(rotation, 2),
        np.ascontiguousarray(half_length, dtype=float),
        np.ascontiguousarray(radius, dtype=float),
        t,
        dist,
        normal,
    )
    return t.reshape(segments + (k,)), dist.reshape(segments + (k,)), normal.reshape(segments + (k, 3))


def segment_cylinder_pairs(
    a: np.ndarray,
    b: np.ndarray,
    center: np.ndarray,
    rotation: np.ndarray,
    half_length: np.ndarray,
    radius: np.ndarray,
    segment: ArrayLike,
    cylinder: ArrayLike,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`segment_cylinder_grid` of the pairs (``segment[p]``, ``cylinder[p]``) of the segments
    a-b ((M, 3) each) and the cylinders: t and distance (P,), normal (P, 3), bit for bit the grid's."""
    from armanim.world import compiled

    segment, cylinder = np.asarray(segment, dtype=np.intp), np.asarray(cylinder, dtype=np.intp)
    n = len(segment)
    t, dist, normal = np.empty(n), np.empty(n), np.empty((n, 3))
    compiled.segment_cylinder_pairs(
        _rows(a),
        _rows(b),
        _rows(center),
        _rows(rotation, 2),
        np.ascontiguousarray(half_length, dtype=float),
        np.ascontiguousarray(radius, dtype=float),
        segment,
        cylinder,
        t,
        dist,
        normal,
    )
    return t, dist, normal


def _rows(v: np.ndarray, ndim: int = 1) -> np.ndarray:
    """``v`` as C-contiguous float rows of its last ``ndim`` axes: (N, 3) or (N, 3, 3)."""
    v = np.asarray(v, dtype=float)
    return np.ascontiguousarray(v.reshape((-1,) + v.shape[v.ndim - ndim :]))
