"""The fixed world box of a video (computed once, so the camera never moves) and the world
extent of the boxes, capsules and cylinders in it."""

from __future__ import annotations

import numpy as np

from armanim.motion.problem import Problem
from armanim.render.settings import RenderSettings
from armanim.world.obstacles import Boxes

MARGIN = 0.05  # fraction of the largest extent added on every side


def auto_bounds(problem: Problem, points: np.ndarray | None = None, margin: float = MARGIN) -> np.ndarray:
    """One box around the arm, every obstacle and every goal.

    With ``points`` (every joint position the video will show, e.g. all frames of a
    trajectory) the box fits what the arm actually does, so the arm fills the frame;
    without them it is the cube base +- reach, which holds any pose. Either way it is
    computed once, so the camera never moves. No side is shorter than a fifth of the
    longest, so a planar arm still gets a readable box.

    Parameters
    ----------
    problem : Problem
    points : (..., 3) array, optional
        Joint positions to fit (the links' half width is added).
    margin : float
        Fraction of the largest side added on each side.

    Returns
    -------
    (3, 2) array
        ``[[xmin, xmax], [ymin, ymax], [zmin, zmax]]`` in scene units.

    Examples
    --------
    >>> from armanim.scene import SceneModel, scene_to_problem
    >>> arm = {"links": [2, 5, 5, 5], "base": [5, 5, 0], "width": 0.6}
    >>> p = scene_to_problem(SceneModel.model_validate({"version": 1, "arm": arm, "goals": [[14, 5, 6]]}))
    >>> auto_bounds(p, margin=0.0)
    array([[-12.3,  22.3],
           [-12.3,  22.3],
           [-17.3,  17.3]])
    >>> auto_bounds(p, points=np.array([[5.0, 5, 0], [5, 5, 17]]), margin=0.0)
    array([[ 4.7 , 14.  ],
           [ 3.24,  6.76],
           [-0.3 , 17.3 ]])
    """
    arm = problem.arm
    if points is None:
        extent = arm.reach + problem.half_width
        lo, hi = [arm.base - extent], [arm.base + extent]
    else:
        pts = np.asarray(points, dtype=float).reshape(-1, 3)
        lo, hi = [pts.min(axis=0) - problem.half_width], [pts.max(axis=0) + problem.half_width]
    obstacles = problem.obstacles
    if len(obstacles.radii):
        lo.append((obstacles.centers - obstacles.radii[:, None]).min(axis=0))
        hi.append((obstacles.centers + obstacles.radii[:, None]).max(axis=0))
    if len(obstacles.boxes) + len(obstacles.rods) + len(obstacles.cylinders):
        points, radii = shape_extent(obstacles.boxes, obstacles.rods, obstacles.cylinders)
        lo.append((points - radii[:, None]).min(axis=0))
        hi.append((points + radii[:, None]).max(axis=0))
    goals = np.vstack([goal_points(problem), path_points(problem)])
    if len(goals):
        lo.append(goals.min(axis=0))
        hi.append(goals.max(axis=0))
    low, high = np.min(lo, axis=0), np.max(hi, axis=0)
    shortest = 0.2 * float(np.max(high - low))
    grow = np.maximum(shortest - (high - low), 0.0) / 2.0
    low, high = low - grow, high + grow
    pad = margin * float(np.max(high - low))
    return np.stack([low - pad, high + pad], axis=1)


def goal_points(problem: Problem) -> np.ndarray:
    """(N, 3) positions of the problem's goals, world units ((0, 3) without goals)."""
    return np.array([g.position for g in problem.goals], dtype=float).reshape(-1, 3)


PATH_EXTENT_SAMPLES = 64  # points of a path goal's path that the pictures frame (every corner among them)


def path_points(problem: Problem) -> np.ndarray:
    """(P, 3) points along every path goal's path (its corners, its arcs every 1/64 of the
    path's length): what a picture must frame of them ((0, 3) without path goals)."""
    paths = [g.path for g in problem.goals if g.path is not None]
    points = [p.points(p.samples(p.length / PATH_EXTENT_SAMPLES)) for p in paths if p.length > 0]
    return np.vstack(points) if points else np.zeros((0, 3))


def resolve_bounds(problem: Problem, settings: RenderSettings, points: np.ndarray | None = None) -> np.ndarray:
    """The settings' bounds if given, else :func:`auto_bounds` (fitted to ``points``); shape (3, 2)."""
    if settings.bounds is not None:
        return np.asarray(settings.bounds, dtype=float).reshape(3, 2)
    return auto_bounds(problem, points)


def box_corners(center: np.ndarray, half: np.ndarray, rotation: np.ndarray) -> np.ndarray:
    """(8, 3) world corners of one box (corner order of :data:`armanim.render.solids.shapes.BOX_FACES`, :meth:`Boxes.corners`)."""
    return Boxes(np.asarray(center)[None], np.asarray(half)[None], np.asarray(rotation)[None]).corners()[0]


def shape_extent(boxes, rods, cylinders=None) -> tuple[np.ndarray, np.ndarray]:
    """World points (P, 3) and radii (P,) that hold every box (its corners), capsule (its ends)
    and cylinder (its caps' centres, with its radius)."""
    corners = [box_corners(c, h, r) for c, h, r in zip(boxes.centers, boxes.half, boxes.rotations)]
    caps = list(cylinders.ends()) if cylinders is not None and len(cylinders) else []
    points = np.vstack(corners + [rods.start, rods.end] + caps).reshape(-1, 3)
    radii = np.concatenate(
        [np.zeros(8 * len(boxes)), rods.radius, rods.radius] + ([cylinders.radius] * 2 if caps else [])
    )
    return points, radii
