"""The path benchmark's oracle (issue 39): how much of a path a robot can follow, found by a dense
continuous inverse kinematics along it from several starts, all of it pinocchio's.

From each start (the robot's home and seeded random poses, each first solved onto the path's
start; up to ``starts`` that land on it inside the limits and clear of the spheres, of 5 x ``starts`` + 1 tried), the tool is stepped along the path 1 mm at a time; each point is solved by damped least
squares on pinocchio's 6 x n frame Jacobian (the position and the tool's z axis), warm-started
from the point before. A point counts as followed when the tool is within 0.2 mm of it and the
tool's z axis within 0.5 degree of the goal's, every joint inside its limits, every capsule of
the robot ``clearance`` from every sphere (pinocchio placing armanim's capsule data), and no joint
turned more than ``max_joint_step`` since the point before, and every enabled pair of the robot's
own capsules (placed by armanim's forward kinematics, equal to pinocchio's to 1e-14; measured by
coal) ``self_clearance`` apart. The oracle's fraction is the farthest
any start got. It shares nothing with armanim's solver but the robot's files.
"""

from __future__ import annotations

import numpy as np

from oracles.robots import RobotGeometry, coal_pair_gaps

STEP = 0.001
"""Metres between the oracle's points along the path."""
POSITION_TOLERANCE = 2e-4
AXIS_TOLERANCE = np.radians(0.5)
ITERATIONS = 40
DAMPING = 1e-4


def _pose(geo: RobotGeometry, data, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """pinocchio's tool point (3,), tool z axis (3,) and world-aligned 6 x n Jacobian at ``q``."""
    import pinocchio as pin

    pin.computeJointJacobians(geo.model, data, q)
    pin.updateFramePlacements(geo.model, data)
    frame = data.oMf[geo.tip_frame]
    jacobian = pin.getFrameJacobian(geo.model, data, geo.tip_frame, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED)
    return np.array(frame.translation), np.array(frame.rotation[:, 2]), np.array(jacobian)


def solve_point(geo: RobotGeometry, data, q: np.ndarray, point: np.ndarray, axis: np.ndarray) -> tuple[np.ndarray, bool]:
    """Damped least squares from ``q`` until the tool is at ``point`` with its z along ``axis``."""
    for _ in range(ITERATIONS):
        p, z, jac = _pose(geo, data, q)
        dp, turn = point - p, np.cross(z, axis)  # turning by z x axis brings z toward axis
        angle = np.arctan2(np.linalg.norm(turn), z @ axis)
        if np.linalg.norm(dp) < POSITION_TOLERANCE and angle < AXIS_TOLERANCE:
            return q, True
        rotate = turn / max(np.linalg.norm(turn), 1e-12) * angle
        # the roll about the tool axis is free: only the two rows square to z are asked
        task = np.concatenate([dp, rotate - (rotate @ z) * z])
        rows = np.concatenate([jac[:3], jac[3:] - np.outer(z, z) @ jac[3:]])
        step = rows.T @ np.linalg.solve(rows @ rows.T + DAMPING * np.eye(6), task)
        q = np.clip(q + step, geo.lower, geo.upper)
    p, z, _ = _pose(geo, data, q)
    return q, bool(np.linalg.norm(point - p) < POSITION_TOLERANCE and np.arctan2(np.linalg.norm(np.cross(z, axis)), z @ axis) < AXIS_TOLERANCE)


def followed_fraction(geo: RobotGeometry, points: np.ndarray, axis: np.ndarray, max_joint_step: float,
                      clearance: float, starts: int = 12, seed: int = 0, problem=None, self_floor: float | None = None) -> float:
    """The farthest share (0..1) of the path through ``points`` (m, 3), spaced :data:`STEP` apart,
    that the oracle follows from any of its starts; with ``problem``, its enabled pairs of the
    robot's own capsules also keep ``self_floor`` (default ``self_pairs.clearance``) apart (coal's distances)."""
    floors = (clearance, problem.self_pairs.clearance if self_floor is None and problem is not None else self_floor)
    data = geo.model.createData()
    rng = np.random.default_rng(seed)
    seeds = [geo.home] + [rng.uniform(np.maximum(geo.lower, -np.pi), np.minimum(geo.upper, np.pi)) for _ in range(5 * starts)]
    best, tried = 0, 0
    for q0 in seeds:
        q, ok = solve_point(geo, data, q0.copy(), points[0], axis)
        if not ok or not _allowed(geo, q, floors, problem):
            continue
        tried += 1
        if tried > starts:
            break
        done = 0
        for i in range(1, len(points)):
            nxt, ok = solve_point(geo, data, q.copy(), points[i], axis)
            if not ok or np.abs(nxt - q).max() > max_joint_step or not _allowed(geo, nxt, floors, problem):
                break
            q, done = nxt, i
        best = max(best, done)
        if best == len(points) - 1:
            break
    return best / (len(points) - 1)


def _allowed(geo: RobotGeometry, q: np.ndarray, floors: tuple, problem=None) -> bool:
    """Inside the limits, every capsule ``floors[0]`` from every sphere, and (with ``problem``) every
    enabled pair of the robot's own capsules ``floors[1]`` apart."""
    inside = bool(np.all(q >= geo.lower) and np.all(q <= geo.upper))
    if not inside or (len(geo.radii) and float(geo.clearances(q).min()) < floors[0]):
        return False
    return problem is None or not len(problem.self_pairs) or float(coal_pair_gaps(problem, q)[0]) >= floors[1]
