"""The path benchmark's seeded paths (issue 39): lines and arcs of 10-40 cm in front of a bundled
robot, the tool pointing down, among 0-4 spheres (some across the path, some not)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from armanim.motion.toolpath import Piece, ToolPath

REGION = {"panda": ((0.3, 0.6), (-0.3, 0.3), (0.15, 0.55)), "ur5": ((0.3, 0.6), (-0.35, 0.35), (0.15, 0.55))}
"""Where paths start, per robot (metres, x, y, z ranges)."""


@dataclass(frozen=True)
class DrawnPath:
    """One benchmark case: a robot, a path, the spheres around it."""

    robot: str
    kind: str
    path: ToolPath
    centers: np.ndarray
    radii: np.ndarray


def draw_path(rng: np.random.Generator, robot: str) -> DrawnPath:
    """A line or an arc (even odds) of 10-40 cm starting in the robot's :data:`REGION`, and 0-4
    spheres of radius 3-7 cm: each either across the path or beside it, never within 12 cm of the
    path's start nor 25 cm of the base."""
    low, high = np.array(REGION[robot]).T
    start = rng.uniform(low, high)
    length = rng.uniform(0.1, 0.4)
    if rng.random() < 0.5:
        direction = rng.normal(size=3)
        direction[2] *= 0.5
        end = start + length * direction / np.linalg.norm(direction)
        kind, path = "line", ToolPath.polyline(np.array([start, end]))
    else:
        radius = rng.uniform(0.06, 0.15)
        angle = min(length / radius, 2 * np.pi) * rng.choice([-1.0, 1.0])
        normal = rng.normal(size=3) * np.array([0.4, 0.4, 1.0])
        normal /= np.linalg.norm(normal)
        sideways = np.cross(normal, rng.normal(size=3))
        center = start - radius * sideways / np.linalg.norm(sideways)
        kind, path = "arc", ToolPath((Piece.arc(center, start, angle, normal),))
    centers, radii = [], []
    for _ in range(rng.integers(0, 5)):
        r = rng.uniform(0.03, 0.07)
        on = path.points(np.array([rng.uniform(0.3, 1.0) * path.length]))[0]
        c = on + rng.normal(size=3) * rng.choice([0.02, 0.15])
        if np.linalg.norm(c - path.start) > 0.12 + r and np.linalg.norm(c) > 0.25:
            centers.append(c)
            radii.append(r)
    return DrawnPath(robot, kind, path, np.array(centers).reshape(-1, 3), np.array(radii))
