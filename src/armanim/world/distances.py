"""Exact distances from the arm's parts to the obstacles' surfaces.

The parts are the arm's collision capsules (:mod:`armanim.arm.capsules`; today's arms: one
per link of radius ``width / 2``) and the tip as a point. For each part and obstacle: the
clearance (negative inside), where on the capsule the closest point lies, and the unit
normal that the safety filter's constraints and the cost's gradient need. One pose or a
batch of poses. Pure core: numpy only, no I/O.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from armanim.arm.capsules import Capsules, capsule_ends
from armanim.arm.geometry import closest_on_segment
from armanim.arm.kinematics import Pose
from armanim.world.obstacles import Obstacles


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
        Unit vector from the obstacle's centre to that closest point.
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
    """Clearances of the capsules and of the tip to every obstacle.

    Parameters
    ----------
    pose : Pose
        One pose or a batch (points of shape (..., n+1, 3)).
    obstacles : Obstacles
    capsules : Capsules
        The arm's collision capsules.
    """
    a, b = capsule_ends(capsules, pose)
    tip = pose.points[..., -1:, :]
    pts = np.concatenate([a, tip], axis=-2)
    ends = np.concatenate([b, tip], axis=-2)  # the tip: a zero-length segment
    ab = (ends - pts)[..., None, :]  # (..., c+1, 1, 3)
    t = closest_on_segment(pts[..., :, None, :], ends[..., :, None, :], obstacles.centers)  # (..., c+1, m)
    t[..., -1, :] = 1.0  # the tip sits at the end of its zero-length segment
    offset = pts[..., :, None, :] + t[..., None] * ab - obstacles.centers
    dist = np.sqrt((offset * offset).sum(axis=-1))
    radius = np.append(capsules.radius, 0.0)[:, None]  # the tip is a point
    d = dist - obstacles.radii - radius
    normal = offset / np.where(dist > 0, dist, 1.0)[..., None]
    return Clearances(d=d, t=t, normal=normal)


def min_link_clearance(pose: Pose, obstacles: Obstacles, capsules: Capsules) -> np.ndarray:
    """Smallest clearance of any capsule to any obstacle, shape (...); +inf if none."""
    if len(obstacles) == 0:
        return np.full(pose.points.shape[:-2], np.inf)
    return clearances(pose, obstacles, capsules).links.min(axis=(-1, -2))
