"""Exact distances from the arm's parts to the obstacles' surfaces.

The parts are the link capsules (radius ``width / 2``) and the tip as a point. For each
part and obstacle: the clearance (negative inside), where on the link the closest point
lies, and the unit normal that the safety filter's constraints and the cost's gradient
need. One pose or a batch of poses. Pure core: numpy only, no I/O.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from armanim.arm.geometry import closest_on_segment
from armanim.arm.kinematics import Pose
from armanim.world.obstacles import Obstacles


@dataclass(frozen=True)
class Clearances:
    """Clearance of every arm part to every obstacle, for one pose or a batch.

    Parts are the n link capsules (indices 0..n-1) and the tip as a point (index n).

    Attributes
    ----------
    d : (..., n+1, m) array
        Clearance to each obstacle's surface (negative inside).
    t : (..., n+1, m) array
        Fraction along the part's link of its point closest to the obstacle.
    normal : (..., n+1, m, 3) array
        Unit vector from the obstacle's centre to that closest point.
    """

    d: np.ndarray
    t: np.ndarray
    normal: np.ndarray

    @property
    def links(self) -> np.ndarray:
        """(..., n, m): clearances of the link capsules only."""
        return self.d[..., :-1, :]


def clearances(pose: Pose, obstacles: Obstacles, half_width: float) -> Clearances:
    """Clearances of the link capsules and of the tip to every obstacle.

    Parameters
    ----------
    pose : Pose
        One pose or a batch (points of shape (..., n+1, 3)).
    obstacles : Obstacles
    half_width : float
        Capsule radius of the links.
    """
    pts = pose.points
    ends = np.concatenate([pts[..., 1:, :], pts[..., -1:, :]], axis=-2)  # the tip: a zero-length segment
    ab = (ends - pts)[..., None, :]  # (..., n+1, 1, 3)
    t = closest_on_segment(pts[..., :, None, :], ends[..., :, None, :], obstacles.centers)  # (..., n+1, m)
    t[..., -1, :] = 1.0  # the tip sits at the end of the last link
    offset = pts[..., :, None, :] + t[..., None] * ab - obstacles.centers
    dist = np.sqrt((offset * offset).sum(axis=-1))
    radius = np.full((pts.shape[-2], 1), half_width)
    radius[-1] = 0.0  # the tip is a point
    d = dist - obstacles.radii - radius
    normal = offset / np.where(dist > 0, dist, 1.0)[..., None]
    return Clearances(d=d, t=t, normal=normal)


def min_link_clearance(pose: Pose, obstacles: Obstacles, half_width: float) -> np.ndarray:
    """Smallest clearance of any link capsule to any obstacle, shape (...); +inf if none."""
    if len(obstacles) == 0:
        return np.full(pose.points.shape[:-2], np.inf)
    return clearances(pose, obstacles, half_width).links.min(axis=(-1, -2))
