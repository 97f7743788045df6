"""The fixed world box of a video: computed once, so the camera never moves."""

from __future__ import annotations

import numpy as np

from armanim.problem import Problem, RenderSettings

MARGIN = 0.05  # fraction of the largest extent added on every side


def auto_bounds(problem: Problem, margin: float = MARGIN) -> np.ndarray:
    """Everything the arm can reach, every obstacle and every goal, in one box.

    The reachable set is taken as the cube base +- reach (sum of the link lengths)
    grown by the link half width, so no pose of any trajectory leaves the box.

    Parameters
    ----------
    problem : Problem
    margin : float
        Fraction of the largest side added on each side.

    Returns
    -------
    (3, 2) array
        ``[[xmin, xmax], [ymin, ymax], [zmin, zmax]]`` in scene units.

    Examples
    --------
    >>> from armanim.kinematics import Arm
    >>> from armanim.problem import Goal, Limits, Obstacles, Problem, SolverSettings
    >>> arm = Arm.from_names([2, 5, 5, 5], base=(5, 5, 0))
    >>> p = Problem(arm, 0.3, np.zeros(4), Limits.unlimited(4), Obstacles.none(),
    ...             (Goal(np.array([14.0, 5, 6])),), SolverSettings())
    >>> auto_bounds(p, margin=0.0)
    array([[-12.3,  22.3],
           [-12.3,  22.3],
           [-17.3,  17.3]])
    """
    arm = problem.arm
    reach = arm.reach + problem.half_width
    lo = [arm.base - reach]
    hi = [arm.base + reach]
    obstacles = problem.obstacles
    if len(obstacles):
        lo.append((obstacles.centers - obstacles.radii[:, None]).min(axis=0))
        hi.append((obstacles.centers + obstacles.radii[:, None]).max(axis=0))
    goals = np.array([g.position for g in problem.goals], dtype=float).reshape(-1, 3)
    if len(goals):
        lo.append(goals.min(axis=0))
        hi.append(goals.max(axis=0))
    low = np.min(lo, axis=0)
    high = np.max(hi, axis=0)
    pad = margin * float(np.max(high - low))
    return np.stack([low - pad, high + pad], axis=1)


def resolve_bounds(problem: Problem, settings: RenderSettings) -> np.ndarray:
    """The settings' bounds if given, else :func:`auto_bounds`; shape (3, 2)."""
    if settings.bounds is not None:
        return np.asarray(settings.bounds, dtype=float).reshape(3, 2)
    return auto_bounds(problem)
