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

import numpy as np

from armanim.arm.capsules import Capsules, capsule_ends
from armanim.arm.geometry import closest_on_segment
from armanim.arm.kinematics import Pose
from armanim.world.closest import segment_box, segment_segment
from armanim.world.obstacles import BOX, FLOOR, ROD, SPHERE, Boxes, Obstacles, Rods


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
        return self.d.shape[-2] - 1


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
    radius = np.append(capsules.radius, 0.0)  # the tip is a point
    if obstacles.spheres_only:
        return sphere_clearances(pts, ends, radius, obstacles)
    shape = pts.shape[:-1] + (len(obstacles),)
    d, t, normal = np.empty(shape), np.empty(shape), np.empty(shape + (3,))
    kinds = (
        (SPHERE, lambda: astuple(sphere_clearances(pts, ends, radius, obstacles))),
        (BOX, lambda: box_clearances(pts, ends, radius, obstacles.boxes)),
        (ROD, lambda: rod_clearances(pts, ends, radius, obstacles.rods)),
        (FLOOR, lambda: floor_clearances(pts, ends, radius, obstacles.floor, standing(capsules))),
    )
    for kind, compute in kinds:
        columns = obstacles.columns(kind)
        if len(columns):
            d[..., columns], t[..., columns], normal[..., columns, :] = compute()
    return Clearances(d=d, t=t, normal=normal)


def astuple(cl: Clearances) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(d, t, normal) of clearances."""
    return cl.d, cl.t, cl.normal


def sphere_clearances(pts: np.ndarray, ends: np.ndarray, radius: np.ndarray, obstacles: Obstacles) -> Clearances:
    """Clearances of the parts (segments pts-ends, (..., p, 3), of radius (p,), the last the tip)
    to the spheres, (..., p, s)."""
    ab = (ends - pts)[..., None, :]  # (..., c+1, 1, 3)
    t = closest_on_segment(pts[..., :, None, :], ends[..., :, None, :], obstacles.centers)  # (..., c+1, m)
    t[..., -1, :] = 1.0  # the tip sits at the end of its zero-length segment
    offset = pts[..., :, None, :] + t[..., None] * ab - obstacles.centers
    dist = np.sqrt((offset * offset).sum(axis=-1))
    d = dist - obstacles.radii - radius[:, None]
    normal = offset / np.where(dist > 0, dist, 1.0)[..., None]
    return Clearances(d=d, t=t, normal=normal)


def box_clearances(pts: np.ndarray, ends: np.ndarray, radius: np.ndarray, boxes: Boxes):
    """(d, t, normal) of the parts to the boxes, (..., p, k): the least signed distance of
    each part's segment to each box less the part's radius (:func:`~armanim.world.closest.segment_box`)."""
    t, dist, normal = segment_box(pts[..., :, None, :], ends[..., :, None, :], boxes.centers, boxes.half, boxes.rotations)
    t[..., -1, :] = 1.0
    return dist - radius[:, None], t, normal


def rod_clearances(pts: np.ndarray, ends: np.ndarray, radius: np.ndarray, rods: Rods):
    """(d, t, normal) of the parts to the capsule obstacles, (..., p, k): the distance between
    the two segments less both radii, the normal from the obstacle's axis to the part's."""
    t, _, offset = segment_segment(pts[..., :, None, :], ends[..., :, None, :], rods.start, rods.end)
    t[..., -1, :] = 1.0
    dist = np.sqrt((offset * offset).sum(axis=-1))
    normal = offset / np.where(dist > 0, dist, 1.0)[..., None]
    return dist - rods.radius - radius[:, None], t, normal


def floor_clearances(pts: np.ndarray, ends: np.ndarray, radius: np.ndarray, floor: float, exempt: np.ndarray):
    """(d, t, normal) of the parts to the plane z = ``floor``, (..., p, 1): the lower end's
    height above it less the radius; +inf for the ``exempt`` parts ((p,) bool)."""
    lower_end = ends[..., 2] <= pts[..., 2]  # a level part: its far end, the one its joint moves most
    height = np.minimum(pts[..., 2], ends[..., 2]) - floor - radius
    d = np.where(exempt, np.inf, height)[..., None]
    t = np.where(lower_end, 1.0, 0.0)
    t[..., -1] = 1.0
    normal = np.zeros(d.shape + (3,))
    normal[..., 2] = 1.0
    return d, t[..., None], normal


def standing(capsules: Capsules) -> np.ndarray:
    """(c+1,) bool: the parts the floor leaves out, the capsules the first joint carries
    (they stand on the base); the tip never."""
    return np.append(capsules.link == 0, False)


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
    if len(obstacles.boxes):
        boxes = obstacles.boxes
        d[:, obstacles.columns(BOX)] = segment_box(points[:, None], points[:, None], boxes.centers, boxes.half, boxes.rotations)[1]
    if len(obstacles.rods):
        rods = obstacles.rods
        offset = segment_segment(points[:, None], points[:, None], rods.start, rods.end)[2]
        d[:, obstacles.columns(ROD)] = np.sqrt((offset * offset).sum(axis=-1)) - rods.radius
    if obstacles.floor is not None:
        d[:, obstacles.columns(FLOOR)] = points[:, 2:] - obstacles.floor
    return d


def min_link_clearance(pose: Pose, obstacles: Obstacles, capsules: Capsules) -> np.ndarray:
    """Smallest clearance of any capsule to any obstacle, shape (...); +inf if none."""
    if len(obstacles) == 0:
        return np.full(pose.points.shape[:-2], np.inf)
    return clearances(pose, obstacles, capsules).links.min(axis=(-1, -2))
