"""The path benchmark's oracle (issue 39): how much of a path a robot can follow, found by a dense
continuous inverse kinematics along it from several starts and with several ways of using the
arm's spare joints, all of it pinocchio's (and coal's).

From each start (the robot's home and seeded random poses, each first solved onto the path's
start; up to ``starts`` that land on it inside the limits and clear of the spheres, of 5 x ``starts`` + 1 tried), the tool is stepped along the path 1 mm at a time; each point is solved by damped least
squares on pinocchio's 6 x n frame Jacobian (the position and the tool's z axis), warm-started
from the point before. A point counts as followed when the tool is within 0.2 mm of it and the
tool's z axis within 0.5 degree of the goal's, every joint inside its limits, every capsule of
the robot ``clearance`` from every sphere (pinocchio placing armanim's capsule data), and no joint
turned more than ``max_joint_step`` since the point before, and every enabled pair of the robot's
own capsules (placed by armanim's forward kinematics, equal to pinocchio's to 1e-14; measured by
coal) ``self_clearance`` apart.

Each start is followed in every way of :data:`DRIFTS`: the least-norm step alone (the solve's own
choice among the arm's poses at each point), then with a turn of at most :data:`DRIFT` radians per
point inside the null space of the path task (the tool's point and axis stay, to first order)
that widens the gaps nearest their floors: the spheres' and the own pairs' (and, in one of the
ways, the joints' limits), each within its :data:`INFLUENCE`. A redundant arm has a family of
poses at every point; the least-norm step follows one curve through it from each start, and a
path that only a drift through that family keeps clear (of a sphere, of its own links) is one the
least-norm step calls blocked. The drift's direction is a finite-difference gradient of the
gaps (numpy's closest points between segments, :func:`segment_gaps`); every point it reaches is
judged by the same tests as any other. The oracle's fraction is the farthest any start got in any
way: each is a continuous motion that keeps every test, so the fraction is a lower bound on the
best any follower can do, a tighter one than a single way gives. It shares nothing with
armanim's solver but the robot's files (and armanim's forward kinematics to place the capsules).
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
DRIFT = 0.01
"""Most radians any joint turns per point in a drift through the null space (10 radians a metre of path)."""
DRIFTS = ("none", "gaps and limits", "gaps")
"""The ways each start is followed: the least-norm step, then drifts that widen the nearest gaps
(the spheres', the own pairs' and the limits'; the spheres' and the own pairs' only)."""
INFLUENCE = {"sphere": 0.05, "self": 0.02, "limit": 0.2}
"""How near its floor a gap must be before a drift widens it (metres; radians for a limit)."""
COAL_WITHIN = 0.005
"""Metres: an own pair whose gap (numpy's closest points) is within this of its floor is measured by coal."""
FD_STEP = 1e-5
"""Radians of the finite differences of the drift's gradient."""


def _pose(geo: RobotGeometry, data, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """pinocchio's tool point (3,), tool z axis (3,) and world-aligned 6 x n Jacobian at ``q``."""
    import pinocchio as pin

    pin.computeJointJacobians(geo.model, data, q)
    pin.updateFramePlacements(geo.model, data)
    frame = data.oMf[geo.tip_frame]
    jacobian = pin.getFrameJacobian(geo.model, data, geo.tip_frame, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED)
    return np.array(frame.translation), np.array(frame.rotation[:, 2]), np.array(jacobian)


def _task_rows(jac: np.ndarray, z: np.ndarray) -> np.ndarray:
    """The 6 x n rows of the path task: the tool point's three, and the tool axis's turns square to it."""
    return np.concatenate([jac[:3], jac[3:] - np.outer(z, z) @ jac[3:]])


def solve_point(
    geo: RobotGeometry, data, q: np.ndarray, point: np.ndarray, axis: np.ndarray
) -> tuple[np.ndarray, bool]:
    """Damped least squares from ``q`` until the tool is at ``point`` with its z along ``axis``."""
    for _ in range(ITERATIONS):
        p, z, jac = _pose(geo, data, q)
        dp, turn = point - p, _cross(z, axis)  # turning by z x axis brings z toward axis
        angle = np.arctan2(np.linalg.norm(turn), z @ axis)
        if np.linalg.norm(dp) < POSITION_TOLERANCE and angle < AXIS_TOLERANCE:
            return q, True
        rotate = turn / max(np.linalg.norm(turn), 1e-12) * angle
        # the roll about the tool axis is free: only the two rows square to z are asked
        task = np.concatenate([dp, rotate - (rotate @ z) * z])
        rows = _task_rows(jac, z)
        step = rows.T @ np.linalg.solve(rows @ rows.T + DAMPING * np.eye(6), task)
        q = np.clip(q + step, geo.lower, geo.upper)
    p, z, _ = _pose(geo, data, q)
    return q, bool(
        np.linalg.norm(point - p) < POSITION_TOLERANCE
        and np.arctan2(np.linalg.norm(_cross(z, axis)), z @ axis) < AXIS_TOLERANCE
    )


def _cross(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """u x v of two 3-vectors (numpy's cross, without its overhead on one pair).

    >>> _cross(np.array([1.0, 0, 0]), np.array([0, 1.0, 0])).tolist()
    [0.0, 0.0, 1.0]
    """
    return np.array([u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]])


def segment_gaps(a1: np.ndarray, b1: np.ndarray, a2: np.ndarray, b2: np.ndarray) -> np.ndarray:
    """Distance (...) between the segments a1-b1 and a2-b2 (..., 3): their closest points
    (Ericson, Real-Time Collision Detection, 5.1.9), clamped to both segments.

    >>> z = np.zeros(3)
    >>> float(segment_gaps(z, np.array([1.0, 0, 0]), np.array([0.5, 1, -1]), np.array([0.5, 1, 1])))
    1.0
    >>> float(segment_gaps(z, z, np.array([2.0, 0, 0]), np.array([3.0, 0, 0])))
    2.0
    """
    d1, d2, r = b1 - a1, b2 - a2, a1 - a2
    a, e, f = (d1 * d1).sum(-1), (d2 * d2).sum(-1), (d2 * r).sum(-1)
    c, b = (d1 * r).sum(-1), (d1 * d2).sum(-1)
    tiny = 1e-18
    denom = a * e - b * b
    s = np.where(denom > tiny, np.clip((b * f - c * e) / np.maximum(denom, tiny), 0.0, 1.0), 0.0)
    s = np.where(a > tiny, s, 0.0)
    t = np.where(e > tiny, (b * s + f) / np.maximum(e, tiny), 0.0)
    # t outside [0, 1]: clamp it and find s again for that end of the second segment
    s = np.where(
        t < 0.0,
        np.clip(-c / np.maximum(a, tiny), 0.0, 1.0),
        np.where(t > 1.0, np.clip((b - c) / np.maximum(a, tiny), 0.0, 1.0), s),
    )
    s = np.where(
        e > tiny, s, np.clip(-c / np.maximum(a, tiny), 0.0, 1.0)
    )  # the second a point: its nearest on the first
    s = np.where(a > tiny, s, 0.0)
    t = np.clip(t, 0.0, 1.0)
    gap = a1 + s[..., None] * d1 - (a2 + t[..., None] * d2)
    return np.sqrt((gap * gap).sum(-1))


class _Gaps:
    """The gaps a path's poses keep to their floors, for one problem: the spheres' (capsule to
    surface), the own enabled pairs' (surface to surface) and the joints' limits, from capsules
    placed by armanim's forward kinematics (equal to pinocchio's to 1e-14) and numpy's closest points."""

    def __init__(self, geo: RobotGeometry, problem, floors: tuple) -> None:
        self.geo, self.problem, self.floors = geo, problem, floors
        pairs = problem.self_pairs if problem is not None and len(problem.self_pairs) else None
        self.first = np.asarray(pairs.first) if pairs is not None else np.zeros(0, int)
        self.second = np.asarray(pairs.second) if pairs is not None else np.zeros(0, int)

    def ends(self, qs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Capsule ends (k, c, 3) twice of poses (k, n)."""
        from armanim.arm.capsules import capsule_ends
        from armanim.arm.kinematics import forward

        return capsule_ends(self.problem.capsules, forward(self.problem.arm, qs))

    def own(self, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        """(k, P) surface gaps of the enabled pairs."""
        radius = np.asarray(self.problem.capsules.radius)
        i, j = self.first, self.second
        return segment_gaps(a[:, i], b[:, i], a[:, j], b[:, j]) - radius[i] - radius[j]

    def spheres(self, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        """(k, c * m) capsule-to-sphere-surface gaps."""
        geo = self.geo
        if not len(geo.radii):
            return np.zeros((len(a), 0))
        radius = np.asarray(self.problem.capsules.radius)
        centers = geo.centers[None, None]
        a, ab = a[:, :, None], (b - a)[:, :, None]
        t = np.clip(((centers - a) * ab).sum(-1) / np.maximum((ab * ab).sum(-1), 1e-300), 0.0, 1.0)
        gap = a + t[..., None] * ab - centers
        out = np.sqrt((gap * gap).sum(-1)) - geo.radii - radius[:, None]
        return out.reshape(len(out), -1)

    def cost(self, qs: np.ndarray, limits: bool) -> np.ndarray:
        """(k,) the drift's barrier: sum over every gap within its influence of its floor of (1 - gap / influence)^2."""
        a, b = self.ends(qs)
        parts = [(self.spheres(a, b) - self.floors[0]) / INFLUENCE["sphere"]]
        if len(self.first):
            parts.append((self.own(a, b) - self.floors[1]) / INFLUENCE["self"])
        if limits:
            parts.append(np.minimum(qs - self.geo.lower, self.geo.upper - qs) / INFLUENCE["limit"])
        margin = np.concatenate(parts, axis=1)
        return (np.maximum(1.0 - margin, 0.0) ** 2).sum(axis=1)

    def drift(self, q: np.ndarray, rows: np.ndarray, limits: bool) -> np.ndarray | None:
        """A turn (n,) of at most :data:`DRIFT` inside the null space of ``rows`` down the barrier's
        gradient (finite differences), or None when no gap is within its influence."""
        n = len(q)
        costs = self.cost(np.vstack([q, q + FD_STEP * np.eye(n)]), limits)  # one batch: as quick as one pose
        if costs[0] == 0.0:
            return None
        gradient = (costs[1:] - costs[0]) / FD_STEP
        null = np.eye(n) - np.linalg.pinv(rows) @ rows
        turn = -null @ gradient
        most = np.abs(turn).max()
        return None if most < 1e-12 else turn * (DRIFT / most)

    def own_clear(self, q: np.ndarray) -> bool:
        """Every enabled pair ``floors[1]`` apart: coal's distances of the pairs numpy's closest points
        put within :data:`COAL_WITHIN` of their floor (the others are clear by far more than the two differ)."""
        if not len(self.first):
            return True
        a, b = self.ends(q[None])
        near = np.nonzero(self.own(a, b)[0] < self.floors[1] + COAL_WITHIN)[0]
        return not len(near) or float(coal_pair_gaps(self.problem, q, near)[0]) >= self.floors[1]


def check_gaps(geo: RobotGeometry, problem, poses: int = 20, seed: int = 0) -> float:
    """The largest difference over ``poses`` seeded random poses between :class:`_Gaps`' numpy
    distances and the references: coal's for the own pairs, pinocchio-placed capsules' for the
    spheres (metres); the benchmark asserts it below 1e-9 before it trusts numpy's gaps."""
    gaps = _Gaps(geo, problem, (0.0, 0.0))
    rng = np.random.default_rng(seed)
    worst = 0.0
    for _ in range(poses):
        q = rng.uniform(np.maximum(geo.lower, -np.pi), np.minimum(geo.upper, np.pi))
        a, b = gaps.ends(q[None])
        if len(gaps.first):
            own, coal_gap = float(gaps.own(a, b).min()), float(coal_pair_gaps(problem, q)[0])
            if coal_gap > 0:  # coal's distance of overlapping shapes is not a signed depth
                worst = max(worst, abs(own - coal_gap))
        if len(geo.radii):
            worst = max(worst, float(np.abs(np.sort(gaps.spheres(a, b)[0]) - np.sort(geo.clearances(q).ravel())).max()))
    return worst


def followed_fraction(
    geo: RobotGeometry,
    points: np.ndarray,
    axis: np.ndarray,
    max_joint_step: float,
    clearance: float,
    starts: int = 24,
    seed: int = 0,
    problem=None,
    self_floor: float | None = None,
) -> float:
    """The farthest share (0..1) of the path through ``points`` (m, 3), spaced :data:`STEP` apart,
    that the oracle follows from any of its starts in any of its :data:`DRIFTS`; with ``problem``,
    its enabled pairs of the robot's own capsules also keep ``self_floor`` (default
    ``self_pairs.clearance``) apart (coal's distances)."""
    floors = (clearance, problem.self_pairs.clearance if self_floor is None and problem is not None else self_floor)
    gaps = _Gaps(geo, problem, floors) if problem is not None else None
    data = geo.model.createData()
    rng = np.random.default_rng(seed)
    seeds = [geo.home] + [
        rng.uniform(np.maximum(geo.lower, -np.pi), np.minimum(geo.upper, np.pi)) for _ in range(5 * starts)
    ]
    poses: list[np.ndarray] = []
    for q0 in seeds:
        q, ok = solve_point(geo, data, q0.copy(), points[0], axis)
        if ok and _allowed(geo, q, floors, gaps):
            poses.append(q)
            if len(poses) == starts:
                break
    last = len(points) - 1
    best, runs = 0, []
    for q in poses:
        run = _followed(geo, data, floors, gaps, points, axis, max_joint_step, [q], "none")
        runs.append(run)
        best = max(best, len(run) - 1)
        if best == last:
            return 1.0
    for drift in DRIFTS[1:] if gaps is not None else ():
        for run in runs:
            # the drift's follow is the least-norm one's up to the first point with a gap within its influence
            acts = np.nonzero(gaps.cost(np.array(run), limits=drift == "gaps and limits") > 0)[0]
            if not len(acts):
                continue
            drifted = _followed(geo, data, floors, gaps, points, axis, max_joint_step, run[: acts[0] + 1], drift)
            best = max(best, len(drifted) - 1)
            if best == last:
                return 1.0
    return best / last


def _followed(
    geo: RobotGeometry,
    data,
    floors: tuple,
    gaps: _Gaps | None,
    points: np.ndarray,
    axis: np.ndarray,
    max_joint_step: float,
    done: list[np.ndarray],
    drift: str,
) -> list[np.ndarray]:
    """The poses at ``points`` the oracle follows in the way ``drift`` on from ``done`` (the poses
    already followed, at ``points[:len(done)]``), those included."""
    done = list(done)
    q = done[-1]
    for i in range(len(done), len(points)):
        start = q
        if drift != "none" and gaps is not None:
            _, z, jac = _pose(geo, data, q)
            turn = gaps.drift(q, _task_rows(jac, z), limits=drift == "gaps and limits")
            if turn is not None:
                start = np.clip(q + turn, geo.lower, geo.upper)
        nxt, ok = solve_point(geo, data, start.copy(), points[i], axis)
        if not ok or np.abs(nxt - q).max() > max_joint_step or not _allowed(geo, nxt, floors, gaps):
            break
        q = nxt
        done.append(q)
    return done


def _allowed(geo: RobotGeometry, q: np.ndarray, floors: tuple, gaps: _Gaps | None = None) -> bool:
    """Inside the limits, every capsule ``floors[0]`` from every sphere, and (with ``gaps``) every
    enabled pair of the robot's own capsules ``floors[1]`` apart."""
    inside = bool(np.all(q >= geo.lower) and np.all(q <= geo.upper))
    if not inside or (len(geo.radii) and float(geo.clearances(q).min()) < floors[0]):
        return False
    return gaps is None or gaps.own_clear(q)
