"""The distance of a carried solid itself (not its cover) to the box it is set down on.

A carried object is kept clear of the world by its cover (:func:`~armanim.world.carried.cover_capsules`),
which lies a little beyond the solid. Set down on a board, the cover lies inside the board by that
margin while the solid touches it: only the solid's own distance tells a box put down on the
board (0) from one pushed into it (negative). :func:`solid_box_distance` is that distance for a
box and a sphere (exact, apart or overlapping), a capsule (exact apart; overlapping, of the right
sign) and a cylinder (the distance of the box round it: a lower bound, exact for a cylinder
standing on one of its flat faces on a level board).

Two boxes: they overlap exactly when no separating axis of the fifteen (each box's three face
normals and the nine cross products of their edges) separates them (the separating-axis
theorem), and then their signed distance is minus the least overlap along those axes (the
penetration depth: the normals of the faces of their Minkowski difference are among them);
apart, their closest points lie on an edge of one of them (two faces' closest points can slide
to an edge of either), so the distance is the least of every edge of each to the other solid
(:func:`~armanim.world.closest.segment_box`). Pure core: numpy only, scene units.
"""

from __future__ import annotations

import itertools
from typing import cast

import numpy as np

from armanim.world.carried import Body
from armanim.world.closest import segment_box
from armanim.world.obstacles import BOX, CYLINDER, ROD, SPHERE

PARALLEL = 1e-12
"""A cross product of two edges shorter than this (the edges parallel) is no separating axis of
its own: the face normals stand for it."""


def box_of(body: Body) -> Body:
    """The box that is ``body`` (a box) or holds it tightly (a cylinder: the box of half edges
    (r, r, h) in its frame).

    >>> box_of(Body(CYLINDER, np.eye(3), np.zeros(3), np.array([0, 0, 0.3]), 0.1)).half.tolist()
    [0.1, 0.1, 0.3]
    """
    if body.kind == BOX:
        return body
    if body.kind == CYLINDER:
        return Body(BOX, body.rotation, body.center, np.array([body.radius, body.radius, body.half[2]]))
    raise ValueError("only a box or a cylinder has a box of its own")


def solid_box_distance(body: Body, box: Body) -> float:
    """Signed distance (scene units; negative: minus the depth they overlap) of the solid ``body``
    to the box ``box``.

    A sphere or a capsule: its centre or axis segment's signed distance to the box less its
    radius (exact apart; overlapping, a sphere's is minus its depth, a capsule's minus its axis'
    deepest point's depth plus its radius: negative exactly when it overlaps). A box: :func:`box_box_distance` (exact). A cylinder: that of the box round it
    (:func:`box_of`; at most the cylinder's own distance, equal to it where the box's closest
    face is the cylinder's flat face).

    >>> board = Body(BOX, np.eye(3), np.zeros(3), np.array([0.2, 0.2, 0.01]))
    >>> cube = Body(BOX, np.eye(3), np.array([0.0, 0, 0.03]), np.full(3, 0.02))
    >>> round(solid_box_distance(cube, board), 12) + 0.0
    0.0
    """
    if box.kind != BOX:
        raise ValueError("the support must be a box")
    if body.kind == SPHERE:
        return float(segment_box(body.center, body.center, box.center, box.half, box.rotation)[1]) - body.radius
    if body.kind == ROD:
        along = body.rotation[:, 0] * body.half[0]
        return (
            float(segment_box(body.center - along, body.center + along, box.center, box.half, box.rotation)[1])
            - body.radius
        )
    return box_box_distance(box_of(body), box)


def box_box_distance(a: Body, b: Body) -> float:
    """Signed distance of two boxes (scene units): apart, the least distance between them; touching,
    0; overlapping, minus the least distance one must move to leave the other (the penetration
    depth), as coal's ``distance`` reports it.

    >>> a = Body(BOX, np.eye(3), np.zeros(3), np.ones(3))
    >>> round(box_box_distance(a, Body(BOX, np.eye(3), np.array([3.0, 3, 0]), np.ones(3))), 12)
    1.414213562373
    >>> round(box_box_distance(a, Body(BOX, np.eye(3), np.array([1.5, 0, 0]), np.ones(3))), 12)
    -0.5
    """
    overlap = axis_overlaps(a, b)
    if overlap.min() < 0.0:
        return min(_edges_to(a, b), _edges_to(b, a))
    return -float(overlap.min())


def axis_overlaps(a: Body, b: Body) -> np.ndarray:
    """(k,) how far the two boxes' shadows on each separating axis overlap (negative: apart along
    it): the three face normals of each and the cross products of their edges that are not
    parallel (:data:`PARALLEL`)."""
    axes = [a.rotation[:, i] for i in range(3)] + [b.rotation[:, i] for i in range(3)]
    for i, j in itertools.product(range(3), range(3)):
        cross = np.cross(a.rotation[:, i], b.rotation[:, j])
        size = float(np.linalg.norm(cross))
        if size > PARALLEL:
            axes.append(cross / size)
    axis = np.array(axes)
    reach_a = np.abs(axis @ a.rotation) @ a.half
    reach_b = np.abs(axis @ b.rotation) @ b.half
    return cast(np.ndarray, reach_a + reach_b - np.abs(axis @ (b.center - a.center)))


def box_edges(box: Body) -> tuple[np.ndarray, np.ndarray]:
    """The box's twelve edges in the world: their starts and ends, (12, 3) each."""
    starts, ends = [], []
    for axis in range(3):
        others = [i for i in range(3) if i != axis]
        for su, sv in itertools.product((-1.0, 1.0), repeat=2):
            local = np.zeros(3)
            local[others[0]], local[others[1]] = su * box.half[others[0]], sv * box.half[others[1]]
            a, b = local.copy(), local.copy()
            a[axis], b[axis] = -box.half[axis], box.half[axis]
            starts.append(a)
            ends.append(b)
    return np.array(starts) @ box.rotation.T + box.center, np.array(ends) @ box.rotation.T + box.center


def _edges_to(a: Body, b: Body) -> float:
    """The least distance of the edges of box ``a`` to the solid box ``b``."""
    starts, ends = box_edges(a)
    return float(np.min(segment_box(starts, ends, b.center, b.half, b.rotation)[1]))
