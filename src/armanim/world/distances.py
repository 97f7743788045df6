"""Exact distances from the arm's parts to the obstacles' surfaces.

The parts are the arm's collision capsules (:mod:`armanim.arm.capsules`; today's arms: one
per link of radius ``width / 2``) and the tip as a point. For each part and obstacle
(sphere, box, capsule, or the floor): the clearance, the least signed distance of the
part's segment to the solid less the part's radius (negative inside), where on the
segment that least point lies, and the unit normal there (the gradient of the solid's
signed distance, out of the solid) that the safety filter's constraints and the cost's
gradient need; closed forms in :mod:`armanim.world.closest`. One pose or a
batch of poses. Pure core: numpy only, no I/O.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import cast

import numpy as np

from armanim.arm.capsules import Capsules, capsule_ends
from armanim.arm.geometry import closest_on_segment
from armanim.arm.kinematics import Pose
from armanim.world.closest import excess_beyond, segment_box_grid, segment_box_pairs
from armanim.world.obstacles import FLOOR, SPHERE, Obstacles


@dataclass(frozen=True)
class Clearances:
    """Clearance of every arm part to every obstacle, for one pose or a batch.

    Parts are the c capsules (indices 0..c-1) and the tip as a point (index c).

    Attributes
    ----------
    d : (..., c+1, m) array
        Clearance to each obstacle's surface (negative inside).
    t : (..., c+1, m) array
        Fraction along the part's segment of its point closest to the obstacle.
    normal : (..., c+1, m, 3) array
        Unit vector out of the obstacle at that closest point (for a sphere: from its centre).
    """

    d: np.ndarray
    t: np.ndarray
    normal: np.ndarray

    @property
    def links(self) -> np.ndarray:
        """(..., c, m): clearances of the capsules only (the arm's solid parts)."""
        return self.d[..., :-1, :]

    @property
    def tip(self) -> int:
        """Index of the tip among the parts (after the capsules)."""
        return cast(int, self.d.shape[-2] - 1)


def clearances(pose: Pose, obstacles: Obstacles, capsules: Capsules) -> Clearances:
    """Clearances of the capsules and of the tip to every obstacle (and the floor).

    Parameters
    ----------
    pose : Pose
        One pose or a batch (points of shape (..., n+1, 3)).
    obstacles : Obstacles
    capsules : Capsules
        The arm's collision capsules.

    Returns
    -------
    Clearances
        One column per obstacle in the order of ``obstacles.kinds``. The floor's column is
        +inf for the capsules the first joint carries (they stand on the base).
    """
    a, b = capsule_ends(capsules, pose)
    tip = pose.points[..., -1:, :]
    pts = np.concatenate([a, tip], axis=-2)
    ends = np.concatenate([b, tip], axis=-2)  # the tip: a zero-length segment
    radius = capsules.part_radius  # the tip is a point: 0
    if obstacles.spheres_only:
        return sphere_clearances(pts, ends, radius, obstacles)
    kinds = []  # (d, t, normal) of the spheres, the solids, the floor: the columns in that order
    if len(obstacles.radii):
        kinds.append(astuple(sphere_clearances(pts, ends, radius, obstacles)))
    if len(obstacles.solid_radius):
        kinds.append(solid_clearances(pts, ends, radius, obstacles))
    if obstacles.floor is not None:
        kinds.append(floor_clearances(pts, ends, radius, obstacles.floor, capsules.on_base))
    d, t, normal = kinds[0] if len(kinds) == 1 else (np.concatenate(c, axis=axis) for c, axis in zip(zip(*kinds), (-1, -1, -2)))
    order = obstacles.scene_order
    if order is not None:
        d, t, normal = d[..., order], t[..., order], normal[..., order, :]
    return Clearances(d=d, t=t, normal=normal)


def astuple(cl: Clearances) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(d, t, normal) of clearances."""
    return cl.d, cl.t, cl.normal


def sphere_clearances(pts: np.ndarray, ends: np.ndarray, radius: np.ndarray, obstacles: Obstacles, tip: bool = True) -> Clearances:
    """Clearances of the parts (segments pts-ends, (..., p, 3), of radius (p,), the last the tip
    unless ``tip`` is False) to the spheres, (..., p, s)."""
    ab = (ends - pts)[..., None, :]  # (..., c+1, 1, 3)
    t = closest_on_segment(pts[..., :, None, :], ends[..., :, None, :], obstacles.centers)  # (..., c+1, m)
    if tip:
        t[..., -1, :] = 1.0  # the tip sits at the end of its zero-length segment
    dist, normal = length_and_direction(pts[..., :, None, :] + t[..., None] * ab - obstacles.centers)
    return Clearances(d=dist - obstacles.radii - radius[:, None], t=t, normal=normal)


def length_and_direction(offset: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """|offset| (...) and the unit vector offset / |offset| (..., 3), 0 where the offset is 0:
    the distance between two closest points and the normal from the solid's to the part's."""
    dist = np.sqrt((offset * offset).sum(axis=-1))
    return dist, offset / np.where(dist > 0, dist, 1.0)[..., None]


def solid_clearances(pts: np.ndarray, ends: np.ndarray, radius: np.ndarray, obstacles: Obstacles) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(d, t, normal) of the parts to the solids (the boxes and capsule obstacles, in the scene's order), (..., p, k):
    the least signed distance of each part's segment to each solid's box (a capsule's: its
    axis, :meth:`~armanim.world.obstacles.Rods.axes`) less both radii
    (:func:`~armanim.world.closest.segment_box`), the normal out of the solid."""
    solids = obstacles.solids
    t, dist, normal = segment_box_grid(pts, ends, solids.centers, solids.half, solids.rotations)
    t[..., -1, :] = 1.0
    return dist - obstacles.solid_radius - radius[:, None], t, normal


def solid_pairs(pts: np.ndarray, ends: np.ndarray, radius: np.ndarray, obstacles: Obstacles,
                where: tuple[np.ndarray, ...]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(d, t, normal) of the part-solid pairs at the indices ``where`` of (..., p, k) only, each (K,)
    or (K, 3): the same numbers as :func:`solid_clearances` at those places (bit for bit)."""
    *pose, part, solid = where
    segment = np.ravel_multi_index(tuple(pose) + (part,), pts.shape[:-1])
    solids = obstacles.solids
    t, dist, normal = segment_box_pairs(pts.reshape(-1, 3), ends.reshape(-1, 3), solids.centers, solids.half, solids.rotations, segment, solid)
    return dist - obstacles.solid_radius[solid] - radius[part], t, normal


def floor_clearances(pts: np.ndarray, ends: np.ndarray, radius: np.ndarray, floor: float, exempt: np.ndarray,
                     tip: bool = True) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(d, t, normal) of the parts to the plane z = ``floor``, (..., p, 1): the lower end's
    height above it less the radius; +inf for the ``exempt`` parts ((p,) bool); the last part
    is the tip unless ``tip`` is False."""
    lower_end = ends[..., 2] <= pts[..., 2]  # a level part: its far end, the one its joint moves most
    height = np.minimum(pts[..., 2], ends[..., 2]) - floor - radius
    d = np.where(exempt, np.inf, height)[..., None]
    t = np.where(lower_end, 1.0, 0.0)
    if tip:
        t[..., -1] = 1.0
    normal = np.zeros(d.shape + (3,))
    normal[..., 2] = 1.0
    return d, t[..., None], normal


def point_clearances(points: np.ndarray, obstacles: Obstacles) -> np.ndarray:
    """(k, m) signed distance of each of the (k, 3) points to every obstacle's surface (the
    floor: the height above it), negative inside: how far a goal lies from each solid.

    >>> obs = Obstacles(np.zeros((1, 3)), np.ones(1), np.ones(2), floor=-2.0)
    >>> point_clearances(np.array([[3.0, 0, 0]]), obs).tolist()
    [[2.0, 2.0]]
    """
    points = np.asarray(points, dtype=float).reshape(-1, 3)
    d = np.empty((len(points), len(obstacles)))
    spheres = obstacles.columns(SPHERE)
    if len(spheres):
        d[:, spheres] = np.linalg.norm(points[:, None, :] - obstacles.centers, axis=-1) - obstacles.radii
    if len(obstacles.solid_radius):
        solids = obstacles.solids
        dist = segment_box_grid(points, points, solids.centers, solids.half, solids.rotations)[1]
        d[:, obstacles.solid_columns] = dist - obstacles.solid_radius
    if obstacles.floor is not None:
        d[:, obstacles.columns(FLOOR)] = points[:, 2:] - obstacles.floor
    return d


def min_link_clearance(pose: Pose, obstacles: Obstacles, capsules: Capsules) -> np.ndarray:
    """Smallest clearance of any capsule to any obstacle, shape (...); +inf if none.

    The same number as the least of :func:`clearances`' links, found with less work among
    boxes and capsules (the planner asks it of thousands of poses): each box's and capsule
    obstacle's exact clearance is computed only where a cheap lower bound
    (:func:`solid_bounds`) is below a pose's best upper bound (the same function's, or an
    exact sphere's or the floor's clearance).
    """
    if len(obstacles) == 0:
        return np.full(pose.points.shape[:-2], np.inf)
    if obstacles.spheres_only:
        return cast(np.ndarray, clearances(pose, obstacles, capsules).links.min(axis=(-1, -2)))
    a, b = capsule_ends(capsules, pose)
    radius = capsules.radius
    best = np.full(a.shape[:-2], np.inf)
    if len(obstacles.radii):
        best = np.minimum(best, sphere_clearances(a, b, radius, obstacles, tip=False).d.min(axis=(-1, -2)))
    if obstacles.floor is not None:
        height = floor_clearances(a, b, radius, obstacles.floor, capsules.on_base[:-1], tip=False)[0]
        best = np.minimum(best, height.min(axis=(-1, -2)))
    if len(obstacles.solid_radius):
        low, high = solid_bounds(a, b, radius, obstacles)
        best = np.minimum(best, high.min(axis=(-1, -2)))
        doubt = low <= best[..., None, None]
        if np.any(doubt):
            where = np.nonzero(doubt)
            found = np.full(doubt.shape, np.inf)
            found[where] = solid_pairs(a, b, radius, obstacles, where)[0]
            best = np.minimum(best, found.min(axis=(-1, -2)))
    return best


def solid_bounds(a: np.ndarray, b: np.ndarray, radius: np.ndarray, obstacles: Obstacles) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper bounds (..., c, k) of the capsules' clearances to the solids: in each
    solid's box frame, the gap between the box and the segment's bounding box (the segment lies
    inside that; when they overlap, minus the box's inradius, the deepest a point can be
    inside), and the distance of the segment's ends and middle to the box; both less the radii.

    The ends go into every box frame by one matrix product (:attr:`Obstacles.solid_axes`),
    rotated before the centre is taken off: bounds, so rounding at 1e-15 of the coordinates
    does not matter (the callers allow 1e-9). Laid out solid, coordinate, then the segments
    (k, 3, M), each operation runs along all of a batch's segments."""
    solids = obstacles.solids
    k = len(solids.half)
    x0 = (obstacles.solid_axes @ a.reshape(-1, 3).T).reshape(k, 3, -1) - obstacles.solid_origins
    x1 = (obstacles.solid_axes @ b.reshape(-1, 3).T).reshape(k, 3, -1) - obstacles.solid_origins
    half = obstacles.solid_half
    gap = np.maximum(np.maximum(np.minimum(x0, x1) - half, -half - np.maximum(x0, x1)), 0.0)
    apart = _length(gap)
    grown = obstacles.solid_radius[:, None] + np.broadcast_to(radius, a.shape[:-1]).reshape(1, -1)
    low = np.where(apart > 0, apart, -solids.half.min(axis=-1)[:, None]) - grown  # overlapping: as deep as the box allows
    high = np.minimum(np.minimum(_outside(x0, half), _outside(x1, half)), _outside(0.5 * (x0 + x1), half)) - grown
    return tuple(np.moveaxis(v.reshape((k,) + a.shape[:-1]), 0, -1) for v in (low, high))


def _length(v: np.ndarray) -> np.ndarray:
    """Length (k, M) of vectors laid out (k, 3, M)."""
    squares = v * v
    return cast(np.ndarray, np.sqrt(squares[:, 0] + squares[:, 1] + squares[:, 2]))


def _outside(p: np.ndarray, half: np.ndarray) -> np.ndarray:
    """Distance (k, M) of points ``p`` (each solid's frame, (k, 3, M)) to the box (0 inside)."""
    return _length(excess_beyond(p, -half, half))
