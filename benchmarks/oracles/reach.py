"""The reach oracle: a goal is feasible when a multi-start bounded least-squares search
(scipy's ``least_squares``, the joint limits as bounds, deterministic starts) finds a pose
whose tip is within tolerance/2 of it, inside the limits and clear of every obstacle.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from oracles.geometry import Geometry, capsule_clearances, has_obstacles, joint_points
from oracles.robots import RobotGeometry, min_clearance, tip_of

ORACLE_STARTS = 48


ORACLE_LIMIT_MARGIN = 1e-4  # radians: "strictly inside the limits"


ORACLE_PENALTY_TARGET = 0.02  # the search aims for clearance + this


@dataclass(frozen=True)
class Verdict:
    """The oracle's label of one goal: ``feasible`` with a witness pose, else why not."""

    feasible: bool
    why: str  # "feasible", "out_of_reach" or "no_free_pose"
    pose: np.ndarray | None = None


def search_bounds(geo: Geometry) -> tuple[np.ndarray, np.ndarray]:
    """Bounds of the IK search: the limits pulled in by ORACLE_LIMIT_MARGIN (free joints unbounded)."""
    return geo.lower + ORACLE_LIMIT_MARGIN, geo.upper - ORACLE_LIMIT_MARGIN


def start_poses(geo: Geometry, rng: np.random.Generator, count: int) -> np.ndarray:
    """Deterministic starts of the search: home, the zero pose, then uniform draws inside the limits."""
    lo, hi = search_bounds(geo)
    box_lo, box_hi = np.maximum(lo, -np.pi), np.minimum(hi, np.pi)
    draws = rng.uniform(box_lo, box_hi, (max(count - 2, 0), len(geo.lower)))
    starts = np.vstack([geo.home, np.zeros(len(geo.lower)), draws])[:count]
    return np.clip(starts, box_lo + 1e-7, box_hi - 1e-7)


ORACLE_ORIENTATION_WEIGHT = 0.3  # metres per radian in the oracle's residual (the poses family)


ORIENTATION_TOLERANCE = np.radians(1.0)  # armanim's default solver.orientation_tolerance


def oracle_residual(
    geo: Geometry, goal: np.ndarray, phi: np.ndarray, orientation: np.ndarray | None = None
) -> np.ndarray:
    """Tip error (3), the weighted rotation error (3, pinocchio's log3 of R_goal R^T, only with an
    ``orientation``) and one hinge term per link-sphere pair, max(0, clearance + target - d)."""
    if isinstance(geo, RobotGeometry):
        tip, a, b = geo.placements(phi)
        tip_error = tip - goal
        if orientation is not None:
            tip_error = np.concatenate([tip_error, ORACLE_ORIENTATION_WEIGHT * geo.rotation_error(phi, orientation)])
        gaps = geo.capsule_gaps(a, b) if has_obstacles(geo) else None
    else:
        points = joint_points(geo, phi)
        tip_error = points[-1] - goal
        gaps = capsule_clearances(geo, points) if has_obstacles(geo) else None
    if gaps is None:
        return tip_error
    shortfall = np.maximum(0.0, geo.clearance + ORACLE_PENALTY_TARGET - gaps)
    return np.concatenate([tip_error, shortfall.ravel()])


def is_witness(geo: Geometry, goal: np.ndarray, phi: np.ndarray, orientation: np.ndarray | None = None) -> bool:
    """True when ``phi`` proves the goal feasible: inside the limits, tip within tolerance/2, clear
    (and, with an ``orientation``, the tool within half the orientation tolerance of it)."""
    inside = np.all(phi > geo.lower) and np.all(phi < geo.upper)
    close = np.linalg.norm(tip_of(geo, phi) - goal) < geo.tolerance / 2
    if orientation is not None:
        close = close and np.linalg.norm(geo.rotation_error(phi, orientation)) < ORIENTATION_TOLERANCE / 2
    return bool(inside and close and min_clearance(geo, phi) >= geo.clearance)


def label_goal(
    geo: Geometry,
    goal: np.ndarray,
    rng: np.random.Generator,
    starts: int = ORACLE_STARTS,
    orientation: np.ndarray | None = None,
) -> Verdict:
    """Label one goal feasible or not by a multi-start bounded least-squares search.

    Parameters
    ----------
    geo : Geometry
    goal : (3,) array
    rng : numpy Generator
        Source of the deterministic starts.
    starts : int
        Most starts tried; the search stops at the first witness.

    Returns
    -------
    Verdict
    """
    if (
        not isinstance(geo, RobotGeometry) and np.linalg.norm(goal - geo.base) > geo.reach
    ):  # a robot's reach is sampled: no shortcut
        return Verdict(False, "out_of_reach")
    lo, hi = search_bounds(geo)
    for start in start_poses(geo, rng, starts):
        fit = least_squares(
            lambda p: oracle_residual(geo, goal, p, orientation),
            start,
            bounds=(lo, hi),
            xtol=1e-12,
            ftol=1e-12,
            gtol=1e-12,
        )
        if is_witness(geo, goal, fit.x, orientation):
            return Verdict(True, "feasible", fit.x)
    return Verdict(False, "no_free_pose")
