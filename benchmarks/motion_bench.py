"""Motion benchmark for armanim (issue 11, item 6): does the arm reach every goal it can?

    python benchmarks/motion_bench.py                     # 40 scenes, every method, planner auto and off
    python benchmarks/motion_bench.py --quick             # 8 scenes, for development
    python benchmarks/motion_bench.py --scenes 100 --seed 3 --jobs 2
    python benchmarks/motion_bench.py --methods pinv,dls --planner off
    python benchmarks/motion_bench.py --list-misses       # one line per feasible goal that was missed
    python benchmarks/motion_bench.py --dump-scene 7 /tmp/scenes   # scene 7 as YAML, for `armanim run`
    python benchmarks/motion_bench.py --family hard --scenes 24 --planner auto   # the hard family
    python benchmarks/motion_bench.py --family robots --scenes 12 --planner auto   # Panda, UR5, iiwa (issue 20)
    python benchmarks/motion_bench.py --family poses --scenes 12 --planner auto    # their goals with orientations (issue 21)
    python benchmarks/motion_bench.py --family self --scenes 12                    # goals across the body (issue 35)

Scenes. A seeded generator (numpy ``Generator`` from ``--seed`` and the scene's index, so
scene K is the same whatever ``--scenes`` is) draws random cluttered scenes: arms of 3-7
links (the course notes' arm: axes z, y, y, ..., links along z; planar or planar-ish arms:
axes z, links along x; arms with mixed axes), random link lengths and width, limits on
about half the joints (home strictly inside them), 2-8 spheres (some across the straight
line between consecutive goals, some next to the arm, some anywhere), and 3-6 goals that
are the tips of random poses inside the limits and clear of the spheres, plus now and then
a goal out of reach. Every scene is validated by armanim itself (``SceneModel`` and
``scene_problems``); a scene that fails is redrawn. Each scene is solved with every
method, with ``solver.planner`` ``auto`` and ``off`` when armanim has that field.

Oracle. Each goal is labelled feasible or not WITHOUT armanim's solvers: a forward
kinematics written here (the contract's chain, checked against
``armanim.arm.kinematics.forward`` at start), then a multi-start search
(``scipy.optimize.least_squares`` with the joint limits as bounds, deterministic starts)
for a pose whose tip is within tolerance/2 of the goal, with every joint inside its
limits and every link capsule (radius width/2) at least ``clearance`` from every sphere's
surface (``clearance`` = the scene's ``solver.clearance`` when armanim has that field,
else 0.05). The oracle says nothing about whether a path to that pose exists: a planar
arm can have goal poses that are clear but cut off from it by a sphere in its plane.

Robot family (``--family robots``, issue 20). One bundled robot per scene, chosen by the
scene's rng: Franka Panda, UR5 or KUKA LBR iiwa (``arm: {robot: ...}``, metres), at its
home pose, among 3-10 spheres (radius 0.03-0.1 m, influence 0.1 m), with 3-5 goals that are
the tool points of random poses inside the URDF limits (10 degrees in, within +-180, tool
0.1 m above the base) and ``solver`` tolerance 0.005, clearance 0.02, max_step 0.02 as the
bundled robot scenes. Its oracle's kinematics is pinocchio's (``pin.buildModelFromUrdf`` of
the bundled URDF, reduced to the chain's joints; ``forwardKinematics`` and
``updateFramePlacements`` give the tool point and every link frame), and its clearances are
armanim's capsule *data* (link, two points in the link frame, radius) placed by pinocchio's
frames; a start-up self-test checks both against armanim's FK and clearances (1e-9) on random
poses. The same multi-start bounded least-squares search as above labels every goal, with
pinocchio's tool point and these clearances in its residual (no reach shortcut: a robot's
reach here is only sampled). Every drawn goal is the tool point of a clear pose, so all are
feasible by construction, the search is checked against the generator's poses ("generator
poses the oracle failed to match") and "reached infeasible" has nothing to count. Like the
other families' oracle, it says nothing about whether a path exists, nor about
self-collision or a floor (armanim checks neither).

Self-collision family (``--family self``, issue 35). Panda, UR5, iiwa and a 6-joint URDF chain of
this file's own (cylinders whose axes alternate z, y: it folds onto itself), one per scene in turn,
no obstacles, the bundled robot scenes' solver settings (self_clearance = clearance / 2 = 0.01 m),
``self_collision: auto``. Three goals per scene: tool points of random poses inside the limits
(10 degrees in) whose straight line from the previous tool point (home's first) passes within
0.15 m of the base's vertical axis, through the body, each pose free (every enabled pair at least
self_clearance + 0.2 x clearance apart, by coal; the tool 0.1 m above the base): feasible by
construction (no path claimed). Every method runs with ``self_collision`` auto and off (planner
auto); coal measures every frame's enabled pairs (capsules placed by armanim's forward kinematics,
which tests/test_urdf.py checks against pinocchio). Reported per robot and method: goals reached,
frames with an enabled pair under self_clearance, invariants broken (NaN, a limit, max_joint_step,
a pair under self_clearance), CPU ms per frame of each and their ratio.

Report. Per method and planner setting: feasible goals reached, goals reached that the
oracle called infeasible (an oracle bug if not 0), the share of frames within 1e-3 of an
obstacle surface, time per frame and per planned goal, and broken invariants (NaN, a
limited joint on or past its limit, clearance below the setting, a joint turning more
than ``max_joint_step`` in one frame). The exit code is 1 when an invariant is broken,
else 0. Nothing here asserts on times. See benchmarks/README.md.
"""

from __future__ import annotations

import argparse
import multiprocessing
import sys
import time
from collections import Counter, defaultdict
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np
import yaml
from pydantic import ValidationError
from scipy.optimize import least_squares

from armanim.arm.capsules import joint_capsules
from armanim.arm.kinematics import Arm, forward, tool_rotation
from armanim.motion.trajectory import solve_trajectory
from armanim.scene import scene_model
from armanim.scene.checks import scene_problems
from armanim.scene.convert import scene_to_problem
from armanim.scene.models import SceneModel, SolverModel
from armanim.scene.robots import bundled_robot
from armanim.world.distances import clearances, min_link_clearance
from armanim.world.obstacles import Obstacles
from armanim.world.selfdistances import self_gaps

METHODS = ("pinv", "dls", "newton", "gradient")
DEFAULT_CLEARANCE = 0.05  # the oracle's clearance when armanim has no solver.clearance
NEAR_SURFACE = 1e-3  # a frame "touches" when its smallest clearance is below this
AT_LIMIT = 1e-3  # radians: a frame "rests on a limit" when a joint is this close to it
ROUNDING = 1e-9  # slack of the invariants
GEN_CLEARANCE = 0.3  # the generator keeps home and goal poses this far from every sphere
GEN_LIMIT_MARGIN = np.radians(20.0)  # ... and home and goal poses this far inside their limits
HARD_CLEARANCE = 0.12  # the hard family keeps home and goal poses only this far from every sphere
ORACLE_STARTS = 48
ORACLE_LIMIT_MARGIN = 1e-4  # radians: "strictly inside the limits"
ORACLE_PENALTY_TARGET = 0.02  # the search aims for clearance + this
AXES = np.eye(3)
AXIS_INDEX = {"x": 0, "y": 1, "z": 2}

# ---------------------------------------------------------------------------------------
# The oracle's own geometry
# ---------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Solids:
    """Boxes, capsule obstacles and a floor as the oracle knows them (issue 22): their
    distances to the arm's capsules are coal's (the FCL successor, GJK), not armanim's
    closed forms; the floor's is the capsule's lower end's height (the capsules the first
    joint carries are left out, as the contract says).

    Attributes
    ----------
    boxes : tuple of (center (3,), half (3,), rotation (3, 3))
    rods : tuple of (a (3,), b (3,), radius)
    floor : float or None
    """

    boxes: tuple = ()
    rods: tuple = ()
    floor: float | None = None

    def __len__(self) -> int:
        return len(self.boxes) + len(self.rods) + int(self.floor is not None)

    def coal_shapes(self) -> list:
        """(coal geometry, coal transform) of every box and capsule (built once per call site)."""
        import coal

        shapes = [(coal.Box(*(2 * np.asarray(h))), coal.Transform3s(np.asarray(r), np.asarray(c))) for c, h, r in self.boxes]
        shapes += [coal_capsule(np.asarray(a), np.asarray(b), float(r)) for a, b, r in self.rods]
        return shapes


def coal_capsule(a: np.ndarray, b: np.ndarray, radius: float):
    """coal's capsule (its axis along its local z, centred) around the segment a-b."""
    import coal

    axis = b - a
    length = float(np.linalg.norm(axis))
    z = axis / length if length > 0 else np.array([0.0, 0.0, 1.0])
    x = np.cross(z, [1.0, 0, 0] if abs(z[0]) < 0.9 else [0, 1.0, 0])
    x /= np.linalg.norm(x)
    return coal.Capsule(radius, length), coal.Transform3s(np.stack([x, np.cross(z, x), z], axis=1), (a + b) / 2)


def solid_gaps(solids: Solids, a: np.ndarray, b: np.ndarray, radius: np.ndarray, first: np.ndarray) -> np.ndarray:
    """Clearances (..., k, s) of capsules with ends a, b (..., k, 3) and radii (k,) to the boxes,
    the capsule obstacles (coal, one call per pair) and the floor; ``first`` (k,) marks the
    capsules the floor leaves out (+inf)."""
    import coal

    batch = a.shape[:-1]
    flat_a, flat_b = a.reshape(-1, 3), b.reshape(-1, 3)
    k = len(radius)
    shapes = solids.coal_shapes()
    out = np.empty((len(flat_a), len(solids)))
    request = coal.DistanceRequest()
    request.gjk_tolerance = 1e-13
    for row, (p, q) in enumerate(zip(flat_a, flat_b)):
        r = float(radius[row % k])
        capsule, tf = coal_capsule(p, q, r) if np.linalg.norm(q - p) > 0 else (coal.Sphere(r), coal.Transform3s(np.eye(3), p))
        for col, (shape, placement) in enumerate(shapes):
            out[row, col] = coal.distance(shape, placement, capsule, tf, request, coal.DistanceResult())
        if solids.floor is not None:
            out[row, -1] = np.inf if first[row % k] else min(p[2], q[2]) - solids.floor - r
    return out.reshape(batch + (len(solids),))


NO_SOLIDS = Solids()


@dataclass(frozen=True)
class Geometry:
    """What the oracle knows of a scene, radians and scene units.

    Attributes
    ----------
    base : (3,) array
    links : (n,) array
    axes : tuple of str
        Joint axis names (x, y, z), each in its joint's own frame.
    direction : (3,) array
        Unit vector along which every link extends, in its joint's frame.
    half_width : float
    lower, upper : (n,) arrays
        Limits in radians, -inf / +inf for a free joint.
    centers : (m, 3) array
    radii : (m,) array
    home : (n,) array
    tolerance, clearance : float
    """

    base: np.ndarray
    links: np.ndarray
    axes: tuple
    direction: np.ndarray
    half_width: float
    lower: np.ndarray
    upper: np.ndarray
    centers: np.ndarray
    radii: np.ndarray
    home: np.ndarray
    tolerance: float = 0.01
    clearance: float = DEFAULT_CLEARANCE
    solids: Solids = NO_SOLIDS

    @property
    def reach(self) -> float:
        """Sum of the link lengths."""
        return float(self.links.sum())


def axis_rotation(axis: str, angle: np.ndarray) -> np.ndarray:
    """Rot(axis, angle) for a named coordinate axis, shape angle.shape + (3, 3)."""
    c, s = np.cos(angle), np.sin(angle)
    o, z = np.ones_like(c), np.zeros_like(c)
    rows = {
        "x": [[o, z, z], [z, c, -s], [z, s, c]],
        "y": [[c, z, s], [z, o, z], [-s, z, c]],
        "z": [[c, -s, z], [s, c, z], [z, z, o]],
    }[axis]
    return np.moveaxis(np.array(rows), (0, 1), (-2, -1))


def joint_points(geo: Geometry, phi: np.ndarray) -> np.ndarray:
    """The contract's chain, written independently of armanim: p_1 .. p_{n+1}, shape (..., n+1, 3).

    R_i = R_{i-1} Rot(axis_i, phi_i) with R_0 = I; p_1 = base; p_{i+1} = p_i + R_i (l_i d).
    """
    phi = np.asarray(phi, dtype=float)
    batch = phi.shape[:-1]
    rot = np.broadcast_to(np.eye(3), batch + (3, 3))
    points = [np.broadcast_to(geo.base, batch + (3,))]
    for i, axis in enumerate(geo.axes):
        rot = rot @ axis_rotation(axis, phi[..., i])
        points.append(points[-1] + rot @ (geo.links[i] * geo.direction))
    return np.stack(points, axis=-2)


def capsule_clearances(geo: Geometry, points: np.ndarray) -> np.ndarray:
    """Clearance of every link capsule to every sphere's surface, then to every solid (boxes,
    capsules, the floor), shape (..., n, m + s); negative inside."""
    a = points[..., :-1, None, :]
    ab = points[..., 1:, None, :] - a
    t = np.clip(((geo.centers - a) * ab).sum(-1) / np.maximum((ab * ab).sum(-1), 1e-300), 0.0, 1.0)
    gap = a + t[..., None] * ab - geo.centers
    spheres = np.sqrt((gap * gap).sum(-1)) - geo.radii - geo.half_width
    if not len(geo.solids):
        return spheres
    n = len(geo.links)
    first = np.arange(n) == 0
    solids = solid_gaps(geo.solids, points[..., :-1, :], points[..., 1:, :], np.full(n, geo.half_width), first)
    return np.concatenate([spheres, solids], axis=-1)


def has_obstacles(geo) -> bool:
    """Whether the oracle has anything to keep the arm from: spheres or solids."""
    return bool(len(geo.radii) or len(geo.solids))


def min_clearance(geo: Geometry, phi: np.ndarray) -> np.ndarray:
    """Smallest capsule clearance of one pose or a batch, shape (...); +inf without spheres."""
    if isinstance(geo, RobotGeometry):
        phi = np.asarray(phi, dtype=float)
        return geo.clearances(phi).min(axis=(-1, -2)) if has_obstacles(geo) else np.full(phi.shape[:-1], np.inf)
    points = joint_points(geo, phi)
    if not has_obstacles(geo):
        return np.full(points.shape[:-2], np.inf)
    return capsule_clearances(geo, points).min(axis=(-1, -2))


def self_test_geometry(rng: np.random.Generator, poses: int = 200) -> None:
    """Assert that the oracle's geometry is armanim's: joint points and capsule clearances agree to 1e-9.

    Raises
    ------
    AssertionError
        When the two forward kinematics or clearances differ on any random arm and pose.
    """
    for trial in range(12):
        n = int(rng.integers(1, 8))
        axes = tuple(rng.choice(["x", "y", "z"], size=n))
        direction = str(rng.choice(["x", "y", "z"]))
        geo = Geometry(
            base=rng.uniform(-5, 5, 3), links=rng.uniform(0.5, 5, n), axes=axes, direction=AXES[AXIS_INDEX[direction]],
            half_width=float(rng.uniform(0.1, 0.4)), lower=np.full(n, -np.inf), upper=np.full(n, np.inf),
            centers=rng.uniform(-8, 8, (3, 3)), radii=rng.uniform(0.2, 2, 3), home=np.zeros(n),
        )
        arm = Arm.from_names(list(geo.links), base=tuple(geo.base), axes=list(axes), direction=direction)
        phi = rng.uniform(-np.pi, np.pi, (poses, n))
        ours = joint_points(geo, phi)
        theirs = forward(arm, phi).points
        assert np.max(np.abs(ours - theirs)) < 1e-9, f"oracle FK differs from armanim's (trial {trial})"
        single = forward(arm, phi[0]).points
        assert np.max(np.abs(ours[0] - single)) < 1e-9, "oracle FK differs from armanim's single-pose FK"
        obstacles = Obstacles(centers=geo.centers, radii=geo.radii, influence=geo.radii)
        armanim_cl = min_link_clearance(forward(arm, phi), obstacles, joint_capsules(arm, geo.half_width))
        assert np.max(np.abs(min_clearance(geo, phi) - armanim_cl)) < 1e-9, "oracle clearance differs from armanim's"


# ---------------------------------------------------------------------------------------
# The oracle
# ---------------------------------------------------------------------------------------


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


def oracle_residual(geo: Geometry, goal: np.ndarray, phi: np.ndarray, orientation: np.ndarray | None = None) -> np.ndarray:
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


def label_goal(geo: Geometry, goal: np.ndarray, rng: np.random.Generator, starts: int = ORACLE_STARTS,
               orientation: np.ndarray | None = None) -> Verdict:
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
    if not isinstance(geo, RobotGeometry) and np.linalg.norm(goal - geo.base) > geo.reach:  # a robot's reach is sampled: no shortcut
        return Verdict(False, "out_of_reach")
    lo, hi = search_bounds(geo)
    for start in start_poses(geo, rng, starts):
        fit = least_squares(lambda p: oracle_residual(geo, goal, p, orientation), start, bounds=(lo, hi), xtol=1e-12, ftol=1e-12, gtol=1e-12)
        if is_witness(geo, goal, fit.x, orientation):
            return Verdict(True, "feasible", fit.x)
    return Verdict(False, "no_free_pose")


# ---------------------------------------------------------------------------------------
# The robot family (issue 20): bundled URDF arms, the oracle's kinematics from pinocchio
# ---------------------------------------------------------------------------------------

ROBOT_NAMES = ("panda", "ur5", "iiwa")
ROBOT_SOLVER = {"tolerance": 0.005, "clearance": 0.02, "max_step": 0.02}  # as the bundled robot scenes, metres
ROBOT_GEN_CLEARANCE = 0.05  # the robot family keeps home and goal poses this far from every sphere (metres)
ROBOT_BASE_KEEP_OUT = 0.2  # ... and every sphere centre this far from the base (capsules of the base are not checked)


@dataclass(frozen=True)
class RobotGeometry:
    """What the oracle knows of a robot scene: pinocchio's model of the bundled URDF and
    armanim's capsule data (link name, two points in that link's frame, radius), metres and radians.

    The capsules are data read from the robot's files; every transform that places them is
    pinocchio's (``forwardKinematics`` + ``updateFramePlacements``), not armanim's chain.
    Capsules on links that no moving joint carries (the robot's base) are left out, as
    armanim leaves them out.
    """

    robot: str
    model: object  # pin.Model
    tip_frame: int
    cap_frames: tuple  # frame id per capsule
    cap_a: np.ndarray  # (k, 3) in the link frame
    cap_b: np.ndarray  # (k, 3)
    cap_r: np.ndarray  # (k,)
    lower: np.ndarray
    upper: np.ndarray
    centers: np.ndarray
    radii: np.ndarray
    home: np.ndarray
    base: np.ndarray
    reach: float
    tolerance: float = ROBOT_SOLVER["tolerance"]
    clearance: float = ROBOT_SOLVER["clearance"]
    cap_first: np.ndarray | None = None  # (k,) the capsules the first joint carries (the floor leaves them out)
    solids: Solids = NO_SOLIDS

    def placements(self, phi: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Tip (..., 3) and capsule ends (..., k, 3) twice, by pinocchio's forward kinematics."""
        import pinocchio as pin

        phi = np.asarray(phi, dtype=float)
        flat = phi.reshape(-1, phi.shape[-1])
        data = self.model.createData()
        tips = np.empty((len(flat), 3))
        a = np.empty((len(flat), len(self.cap_r), 3))
        b = np.empty_like(a)
        for i, q in enumerate(flat):
            pin.forwardKinematics(self.model, data, q)
            pin.updateFramePlacements(self.model, data)
            tips[i] = data.oMf[self.tip_frame].translation
            for k, frame in enumerate(self.cap_frames):
                placement = data.oMf[frame]
                a[i, k] = placement.rotation @ self.cap_a[k] + placement.translation
                b[i, k] = placement.rotation @ self.cap_b[k] + placement.translation
        batch = phi.shape[:-1]
        return tips.reshape(batch + (3,)), a.reshape(batch + a.shape[1:]), b.reshape(batch + b.shape[1:])

    def tip(self, phi: np.ndarray) -> np.ndarray:
        """The tool point (the tip link's origin), shape (..., 3)."""
        return self.placements(phi)[0]

    def rotation(self, phi: np.ndarray) -> np.ndarray:
        """The tool frame's world rotation (3, 3) of one pose, by pinocchio."""
        import pinocchio as pin

        data = self.model.createData()
        pin.framesForwardKinematics(self.model, data, np.asarray(phi, dtype=float))
        return np.array(data.oMf[self.tip_frame].rotation)

    def rotation_error(self, phi: np.ndarray, orientation: np.ndarray) -> np.ndarray:
        """pinocchio's log3 of R_goal R^T (3,): the rotation vector still to turn, radians."""
        import pinocchio as pin

        return np.array(pin.log3(orientation @ self.rotation(phi).T))

    def clearances(self, phi: np.ndarray) -> np.ndarray:
        """Clearance of every capsule to every sphere's surface, shape (..., k, m); negative inside."""
        _, a, b = self.placements(phi)
        return self.capsule_gaps(a, b)

    def capsule_gaps(self, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        """Clearances (..., k, m + s) of the capsules with ends ``a``, ``b`` (..., k, 3) to every sphere, then every solid."""
        ends = a, b
        a, ab = a[..., None, :], (b - a)[..., None, :]
        t = np.clip(((self.centers - a) * ab).sum(-1) / np.maximum((ab * ab).sum(-1), 1e-300), 0.0, 1.0)
        gap = a + t[..., None] * ab - self.centers
        spheres = np.sqrt((gap * gap).sum(-1)) - self.radii - self.cap_r[:, None]
        if not len(self.solids):
            return spheres
        return np.concatenate([spheres, solid_gaps(self.solids, *ends, self.cap_r, self.cap_first)], axis=-1)


def robot_geometry(robot: str, centers: np.ndarray, radii: np.ndarray, tolerance: float = ROBOT_SOLVER["tolerance"],
                   clearance: float = ROBOT_SOLVER["clearance"]) -> RobotGeometry:
    """The oracle's geometry of bundled robot ``robot`` among the given spheres."""
    import pinocchio as pin

    model, capsules = robot_model(robot)
    keep = [c for c in capsules if model.frames[model.getFrameId(c.link)].parentJoint != 0]
    lower, upper = np.array(model.lowerPositionLimit), np.array(model.upperPositionLimit)
    bundled = bundled_robot(robot)
    home = np.radians(np.array(bundled.home, dtype=float))
    # reach: the farthest the tool point gets from the base over a fixed sample of poses, plus 10 %
    sample = np.random.default_rng(0).uniform(np.maximum(lower, -np.pi), np.minimum(upper, np.pi), (400, model.nq))
    data = model.createData()
    tip_frame = model.getFrameId(bundled.tip_link)
    far = 0.0
    for q in sample:
        pin.framesForwardKinematics(model, data, q)
        far = max(far, float(np.linalg.norm(data.oMf[tip_frame].translation)))
    return RobotGeometry(
        robot=robot, model=model, tip_frame=tip_frame, cap_frames=tuple(model.getFrameId(c.link) for c in keep),
        cap_a=np.array([c.start for c in keep], dtype=float), cap_b=np.array([c.end for c in keep], dtype=float),
        cap_r=np.array([c.radius for c in keep], dtype=float), lower=lower, upper=upper,
        cap_first=np.array([model.frames[model.getFrameId(c.link)].parentJoint == 1 for c in keep]),
        centers=np.asarray(centers, dtype=float).reshape(-1, 3), radii=np.asarray(radii, dtype=float),
        home=home, base=np.zeros(3), reach=1.1 * far, tolerance=tolerance, clearance=clearance,
    )


_ROBOT_MODELS: dict = {}


def robot_model(robot: str):
    """pinocchio's model of a bundled robot's URDF, and the robot's capsule data as armanim reads it."""
    if robot not in _ROBOT_MODELS:
        import pinocchio as pin

        full = pin.buildModelFromUrdf(str(bundled_robot(robot).urdf))
        scene = scene_model({"version": 1, "name": "probe", "arm": {"robot": robot}, "goals": [[0.3, 0.0, 0.4]]})
        robot_arm = scene.arm.urdf_arm  # the chain's joint names and the capsule data, as the scene reads them
        off_chain = [j for j in range(1, full.njoints) if full.names[j] not in robot_arm.joint_names]  # e.g. Panda's fingers
        model = pin.buildReducedModel(full, off_chain, pin.neutral(full)) if off_chain else full
        assert list(model.names)[1:] == list(robot_arm.joint_names), f"{robot}: pinocchio's joints differ from the chain's"
        assert model.nq == model.nv, f"{robot}: a joint with nq != nv (continuous) is not handled here"
        assert not robot_arm.fallback_links, f"{robot}: fallback capsules are not modelled by the oracle"
        _ROBOT_MODELS[robot] = (model, robot_arm.capsules)
    return _ROBOT_MODELS[robot]


# ---------------------------------------------------------------------------------------
# The scene generator
# ---------------------------------------------------------------------------------------


@dataclass
class Draft:
    """A scene being drawn, radians inside; ``as_scene_dict`` writes it in scene-file form."""

    kind: str
    base: np.ndarray
    links: np.ndarray
    axes: list
    direction: str
    width: float
    home: np.ndarray  # radians, rounded to 1e-3 degree
    limits: list  # per joint None or (lo, hi) in whole degrees
    spheres: list = field(default_factory=list)  # (center (3,), radius)
    goals: list = field(default_factory=list)  # (3,) arrays
    witnesses: list = field(default_factory=list)  # the generator's pose per goal (None: out of reach)
    orientations: list = field(default_factory=list)  # the tool's rotation (3, 3) per goal (the poses family), else empty
    robot: str | None = None  # a bundled robot (the robot family): base, links, axes, direction, limits unused
    boxes: list = field(default_factory=list)  # (center (3,), size (3,) full edges, rpy (3,) degrees)
    rods: list = field(default_factory=list)  # (from (3,), to (3,), radius)
    floor: float | None = None
    influence: float | None = None  # of the boxes and capsules (None: the scene's default)

    def solids(self) -> Solids:
        """The oracle's view of the boxes, capsules and floor."""
        from armanim.arm.chain import rpy_rotation  # a rotation is data here: the contract's formula of rpy

        boxes = tuple((np.asarray(c, float), np.asarray(sz, float) / 2, rpy_rotation(np.radians(r))) for c, sz, r in self.boxes)
        return Solids(boxes, tuple((np.asarray(a, float), np.asarray(b, float), float(r)) for a, b, r in self.rods), self.floor)

    def geometry(self, clearance: float = DEFAULT_CLEARANCE, tolerance: float = 0.01) -> Geometry:
        """The oracle's view of this draft."""
        if self.robot is not None:
            centers = np.array([c for c, _ in self.spheres]).reshape(-1, 3)
            return replace(base_geometry(self.robot), centers=centers, radii=np.array([r for _, r in self.spheres]),
                           tolerance=tolerance, clearance=clearance, solids=self.solids())
        lower = np.array([np.radians(p[0]) if p else -np.inf for p in self.limits])
        upper = np.array([np.radians(p[1]) if p else np.inf for p in self.limits])
        return Geometry(
            base=self.base, links=self.links, axes=tuple(self.axes), direction=AXES[AXIS_INDEX[self.direction]],
            half_width=self.width / 2, lower=lower, upper=upper,
            centers=np.array([c for c, _ in self.spheres]).reshape(-1, 3), radii=np.array([r for _, r in self.spheres]),
            home=self.home, tolerance=tolerance, clearance=clearance, solids=self.solids(),
        )

    def shape_entries(self) -> list:
        """The boxes and capsules as scene-file obstacles."""
        extra = {} if self.influence is None else {"influence": self.influence}
        boxes = [{"box": {"center": floats(c), "size": floats(sz), "rpy": floats(r, 3)}, **extra} for c, sz, r in self.boxes]
        rods = [{"capsule": {"from": floats(a), "to": floats(b), "radius": float(r)}, **extra} for a, b, r in self.rods]
        return boxes + rods

    def with_floor(self, scene: dict) -> dict:
        """``scene`` with the draft's shapes appended to its obstacles and its floor."""
        scene["obstacles"] = scene["obstacles"] + self.shape_entries()
        if self.floor is not None:
            scene["floor"] = float(self.floor)
        return scene

    def spheres_twin(self) -> Draft:
        """The same scene with every box and capsule replaced by the largest sphere inside it (at
        its centre): a scene of spheres only, for timing frames against the shapes' cost."""
        inner = [(np.asarray(c, float), round(float(min(sz)) / 2, 4)) for c, sz, _ in self.boxes]
        inner += [((np.asarray(a, float) + np.asarray(b, float)) / 2, float(r)) for a, b, r in self.rods]
        return replace(self, spheres=list(self.spheres) + inner, boxes=[], rods=[], floor=None)

    def as_scene_dict(self, name: str, method: str = "pinv", planner: str | None = None) -> dict:
        """The draft as a scene file's mapping (degrees), ready for ``scene_model``."""
        solver = {"method": method}
        if planner is not None:
            solver["planner"] = planner
        if self.robot is not None:
            return self.with_floor({
                "version": 1, "name": name, "arm": {"robot": self.robot},
                "obstacles": [{"center": floats(c), "radius": float(r), "influence": 0.1} for c, r in self.spheres],
                "goals": [goal_entry(g, self.orientations[k] if self.orientations else None) for k, g in enumerate(self.goals)],
                "solver": {**solver, **ROBOT_SOLVER}, "render": {"fps": 30},
            })
        return self.with_floor({
            "version": 1,
            "name": name,
            "arm": {
                "base": floats(self.base),
                "links": floats(self.links),
                "axes": list(self.axes),
                "direction": self.direction,
                "home": floats(np.degrees(self.home), 3),
                "limits": [None if p is None else [float(p[0]), float(p[1])] for p in self.limits],
                "width": float(self.width),
            },
            "obstacles": [{"center": floats(c), "radius": float(r)} for c, r in self.spheres],
            "goals": [floats(g) for g in self.goals],
            "solver": solver,
            "render": {"fps": 30},
        })


def goal_entry(position: np.ndarray, rotation: np.ndarray | None):
    """A goal of the scene file: the point, or the point and the tool's orientation as a quaternion
    (pinocchio's, written w first, 9 decimals)."""
    if rotation is None:
        return floats(position)
    import pinocchio as pin

    q = pin.Quaternion(np.asarray(rotation, dtype=float)).coeffs()  # x, y, z, w
    return {"position": floats(position), "orientation": {"quaternion_wxyz": floats([q[3], q[0], q[1], q[2]], 9)}}


def floats(values, decimals: int = 4) -> list:
    """Plain Python floats rounded for a readable scene file."""
    return [round(float(v), decimals) for v in np.asarray(values).ravel()]


def draw_arm(rng: np.random.Generator) -> Draft:
    """An arm of 3-7 links: the course notes' kind, a planar(-ish) one or one with mixed axes; home and limits."""
    n = int(rng.integers(3, 8))
    kind = str(rng.choice(["notes", "planar", "mixed"], p=[0.4, 0.3, 0.3]))
    if kind == "notes":
        axes, direction = ["z"] + ["y"] * (n - 1), "z"
        links = np.concatenate([[rng.uniform(1, 3)], rng.uniform(2, 6, n - 1)])
    elif kind == "planar":
        axes, direction = ["z"] * n, "x"
        if rng.random() < 0.4:  # planar-ish: one joint lifts the arm out of its plane
            axes[int(rng.integers(1, n))] = "y"
        links = rng.uniform(1.5, 5, n)
    else:
        direction = str(rng.choice(["x", "y", "z"]))
        choices = [a for a in "xyz" if a != direction]
        axes = ["z" if direction != "z" else "x"] + [str(rng.choice(choices)) for _ in range(n - 1)]
        links = rng.uniform(1, 5, n)
    home = np.zeros(n) if rng.random() < 0.5 else np.radians(np.round(rng.uniform(-60, 60, n), 3))
    limits = [draw_limit(rng, np.degrees(h)) if rng.random() < 0.5 else None for h in home]
    return Draft(kind=kind, base=np.round(rng.uniform(-5, 5, 3), 4), links=np.round(links, 4), axes=axes,
                 direction=direction, width=round(float(rng.uniform(0.3, 0.6)), 3), home=home, limits=limits)


def draw_limit(rng: np.random.Generator, home_deg: float) -> tuple[float, float]:
    """Whole-degree limits with home at least 25 degrees inside each, within [-175, 175]."""
    lo = float(np.floor(rng.uniform(max(-175.0, home_deg - 150), home_deg - 25)))
    hi = float(np.ceil(rng.uniform(home_deg + 25, min(175.0, home_deg + 150))))
    return lo, hi


def random_pose(rng: np.random.Generator, draft: Draft) -> np.ndarray:
    """A pose inside the limits, GEN_LIMIT_MARGIN away from them (free joints anywhere)."""
    geo = draft.geometry()
    lo = np.where(np.isfinite(geo.lower), geo.lower + GEN_LIMIT_MARGIN, -np.pi)
    hi = np.where(np.isfinite(geo.upper), geo.upper - GEN_LIMIT_MARGIN, np.pi)
    return rng.uniform(lo, hi)


def poses_clear(draft: Draft, poses: list, margin: float) -> bool:
    """True when every pose's capsules are at least ``margin`` from every sphere of the draft."""
    if not (draft.spheres or draft.boxes or draft.rods or draft.floor is not None) or not poses:
        return True
    return bool(np.all(min_clearance(draft.geometry(), np.array(poses)) >= margin))


def draw_goal_poses(rng: np.random.Generator, draft: Draft) -> list:
    """3-6 poses inside the limits whose tips will be the goals."""
    return [random_pose(rng, draft) for _ in range(int(rng.integers(3, 7)))]


def sphere_across(rng: np.random.Generator, a: np.ndarray, b: np.ndarray, size: float):
    """A sphere on the straight segment a-b, a little off its middle."""
    length = np.linalg.norm(b - a)
    radius = float(np.clip(rng.uniform(0.15, 0.35) * length, 0.3, size))
    offset = rng.normal(size=3) * 0.2 * radius
    return a + rng.uniform(0.35, 0.65) * (b - a) + offset, radius


def sphere_near_arm(rng: np.random.Generator, draft: Draft, pose: np.ndarray, size: float):
    """A sphere just beside a random point of the arm in ``pose``."""
    points = joint_points(draft.geometry(), pose)
    link = int(rng.integers(0, len(draft.links)))
    on_arm = points[link] + rng.uniform(0, 1) * (points[link + 1] - points[link])
    radius = float(rng.uniform(0.3, 1.0) * size)
    direction = rng.normal(size=3)
    direction /= np.linalg.norm(direction)
    gap = draft.width / 2 + GEN_CLEARANCE + rng.uniform(0.05, 0.8)
    return on_arm + (radius + gap) * direction, radius


def sphere_anywhere(rng: np.random.Generator, draft: Draft, size: float):
    """A sphere anywhere within the arm's reach."""
    direction = rng.normal(size=3)
    direction /= np.linalg.norm(direction)
    center = draft.base + direction * rng.uniform(0.3, 1.0) * draft.links.sum()
    return center, float(rng.uniform(0.3, 1.0) * size)


def place_spheres(rng: np.random.Generator, draft: Draft, goal_poses: list) -> None:
    """Add 2-8 spheres: across the paths between consecutive tips, beside the arm, anywhere.

    A sphere is kept only when home and every goal pose stay GEN_CLEARANCE clear of it.
    """
    geo = draft.geometry()
    tips = [joint_points(geo, p)[-1] for p in [draft.home] + goal_poses]
    size = float(np.mean(draft.links))
    wanted = int(rng.integers(2, 9))
    across = min(int(rng.integers(1, 5)), len(tips) - 1, wanted)
    near = min(int(rng.integers(0, 3)), wanted - across)
    kinds = ["across"] * across + ["near"] * near + ["anywhere"] * (wanted - across - near)
    segments = rng.permutation(len(tips) - 1)
    for i, kind in enumerate(kinds):
        for _ in range(30):
            if kind == "across":
                k = int(segments[i % len(segments)])
                candidate = sphere_across(rng, tips[k], tips[k + 1], size)
            elif kind == "near":
                pose = [draft.home] + goal_poses
                candidate = sphere_near_arm(rng, draft, pose[int(rng.integers(0, len(pose)))], size)
            else:
                candidate = sphere_anywhere(rng, draft, size)
            center = np.round(candidate[0], 4)
            trial = Draft(**{**draft.__dict__, "spheres": [(center, round(candidate[1], 4))]})
            if poses_clear(trial, [draft.home] + goal_poses, GEN_CLEARANCE):
                draft.spheres.append((center, round(candidate[1], 4)))
                break


def out_of_reach_goal(rng: np.random.Generator, draft: Draft) -> np.ndarray:
    """A point 1.1-1.5 times the arm's length from its base, outside every sphere."""
    while True:
        direction = rng.normal(size=3)
        direction /= np.linalg.norm(direction)
        goal = np.round(draft.base + direction * rng.uniform(1.1, 1.5) * draft.links.sum(), 4)
        if all(np.linalg.norm(goal - c) > r + 1.0 for c, r in draft.spheres):
            return goal


def draw_scene(rng: np.random.Generator) -> Draft:
    """One candidate scene (not yet validated by armanim)."""
    draft = draw_arm(rng)
    goal_poses = draw_goal_poses(rng, draft)
    place_spheres(rng, draft, goal_poses)
    geo = draft.geometry()
    draft.goals = [np.round(joint_points(geo, p)[-1], 4) for p in goal_poses]
    draft.witnesses = list(goal_poses)
    if rng.random() < 0.2:
        at = int(rng.integers(0, len(draft.goals) + 1))
        draft.goals.insert(at, out_of_reach_goal(rng, draft))
        draft.witnesses.insert(at, None)
    return draft


def draw_tight_arm(rng: np.random.Generator) -> Draft:
    """The hard family's arm: 7 links with mixed axes, a planar arm of 3-7, or the notes' kind;
    every joint limited, 70-160 degrees of range with home at least 25 inside."""
    draft = draw_arm(rng)
    kind = str(rng.choice(["mixed", "planar", "notes"], p=[0.4, 0.35, 0.25]))
    while draft.kind != kind or (kind == "mixed" and len(draft.links) != 7) or (kind == "planar" and "y" in draft.axes):
        draft = draw_arm(rng)
    home = np.degrees(draft.home)
    draft.limits = [(float(np.floor(h - rng.uniform(25, 80))), float(np.ceil(h + rng.uniform(25, 80)))) for h in home]
    draft.limits = [(max(lo, -175.0), min(hi, 175.0)) for lo, hi in draft.limits]
    return draft


def sphere_pair_across(rng: np.random.Generator, draft: Draft, a: np.ndarray, b: np.ndarray, size: float) -> list:
    """Two spheres either side of the segment a-b, leaving a passage 2.5-5 arm widths wide."""
    middle = a + rng.uniform(0.35, 0.65) * (b - a)
    along = (b - a) / max(np.linalg.norm(b - a), 1e-9)
    side = np.cross(along, rng.normal(size=3))
    side /= max(np.linalg.norm(side), 1e-9)
    radius = float(rng.uniform(0.4, 1.0) * size)
    half_gap = rng.uniform(1.25, 2.5) * draft.width
    return [(middle + s * (half_gap + radius) * side, radius) for s in (-1.0, 1.0)]


def sphere_near_goal(rng: np.random.Generator, draft: Draft, pose: np.ndarray, size: float):
    """A sphere beside the arm in a goal pose, only a few clearances away from it."""
    center, radius = sphere_near_arm(rng, draft, pose, size)
    points = joint_points(draft.geometry(), pose)
    pull = GEN_CLEARANCE + rng.uniform(0.05, 0.6)  # sphere_near_arm leaves this much more than needed
    direction = center - points[-1]
    return center - pull * direction / max(np.linalg.norm(direction), 1e-9), radius


def place_clutter(rng: np.random.Generator, draft: Draft, goal_poses: list) -> None:
    """6-12 spheres: passages across the paths, spheres close to goal poses, the rest anywhere.

    A sphere is kept only when home and every goal pose stay HARD_CLEARANCE clear of it."""
    geo = draft.geometry()
    tips = [joint_points(geo, p)[-1] for p in [draft.home] + goal_poses]
    size = float(np.mean(draft.links)) * 0.6
    poses = [draft.home] + goal_poses
    for _ in range(int(rng.integers(6, 13))):
        for _ in range(30):
            kind = rng.choice(["passage", "near_goal", "across", "anywhere"], p=[0.3, 0.3, 0.2, 0.2])
            k = int(rng.integers(0, len(tips) - 1))
            if kind == "passage":
                candidates = sphere_pair_across(rng, draft, tips[k], tips[k + 1], size)
            elif kind == "near_goal":
                candidates = [sphere_near_goal(rng, draft, goal_poses[int(rng.integers(0, len(goal_poses)))], size)]
            elif kind == "across":
                candidates = [sphere_across(rng, tips[k], tips[k + 1], size)]
            else:
                candidates = [sphere_anywhere(rng, draft, size)]
            rounded = [(np.round(c, 4), round(float(r), 4)) for c, r in candidates]
            trial = Draft(**{**draft.__dict__, "spheres": rounded})
            if poses_clear(trial, poses, HARD_CLEARANCE):
                draft.spheres.extend(rounded)
                break


def draw_hard_scene(rng: np.random.Generator) -> Draft:
    """One candidate scene of the hard family: tight limits, 8-12 goals (some at the edge of
    reach, some close to a sphere), dense clutter and narrow passages."""
    draft = draw_tight_arm(rng)
    goal_poses = [random_pose(rng, draft) for _ in range(int(rng.integers(8, 13)))]
    for k in range(len(goal_poses)):
        if rng.random() < 0.25:  # at the edge of reach: nearly straight (limits permitting)
            geo = draft.geometry()
            straight = np.clip(goal_poses[k] * 0.15, geo.lower + GEN_LIMIT_MARGIN, geo.upper - GEN_LIMIT_MARGIN)
            goal_poses[k] = np.where(np.isfinite(geo.lower), straight, goal_poses[k])
    place_clutter(rng, draft, goal_poses)
    draft.goals = [np.round(joint_points(draft.geometry(), p)[-1], 4) for p in goal_poses]
    draft.witnesses = list(goal_poses)
    return draft


_BASE_GEOMETRY: dict = {}


def base_geometry(robot: str) -> RobotGeometry:
    """The robot's geometry without spheres (cached: its reach takes 400 poses to find)."""
    if robot not in _BASE_GEOMETRY:
        _BASE_GEOMETRY[robot] = robot_geometry(robot, np.zeros((0, 3)), np.zeros(0))
    return _BASE_GEOMETRY[robot]


def tip_of(geo, phi: np.ndarray) -> np.ndarray:
    """The tip of one pose or a batch, for either kind of geometry."""
    return geo.tip(phi) if isinstance(geo, RobotGeometry) else joint_points(geo, phi)[..., -1, :]


def self_test_robots(rng: np.random.Generator, poses: int = 40) -> None:
    """Assert that pinocchio's tool point and the oracle's capsule clearances equal armanim's (1e-9) on
    every bundled robot: a check of the two sides, not a source of the oracle's numbers."""
    for robot in ROBOT_NAMES:
        geo = base_geometry(robot)
        centers, radii = rng.uniform(-0.6, 0.6, (4, 3)), rng.uniform(0.03, 0.1, 4)
        geo = replace(geo, centers=centers, radii=radii)
        model = scene_model({"version": 1, "name": "probe", "arm": {"robot": robot}, "goals": [[0.3, 0.0, 0.4]]})
        problem = scene_to_problem(model)
        phi = rng.uniform(np.maximum(geo.lower, -np.pi), np.minimum(geo.upper, np.pi), (poses, len(geo.lower)))
        pose = forward(problem.arm, phi)
        assert np.max(np.abs(geo.tip(phi) - pose.tip)) < 1e-9, f"{robot}: pinocchio's tool point differs from armanim's"
        rotations = tool_rotation(problem.arm, pose)
        assert max(np.abs(geo.rotation(q) - r).max() for q, r in zip(phi[:8], rotations)) < 1e-9, f"{robot}: pinocchio's tool frame differs from armanim's"
        obstacles = Obstacles(centers=centers, radii=radii, influence=radii)
        theirs = min_link_clearance(pose, obstacles, problem.capsules)
        assert np.max(np.abs(min_clearance(geo, phi) - theirs)) < 1e-9, f"{robot}: the oracle's capsule clearance differs from armanim's"


def self_test_solids(rng: np.random.Generator, poses: int = 60) -> None:
    """Assert that the oracle's clearances (coal) to boxes, capsules and a floor equal armanim's closed
    forms to 1e-9 on random arms and poses where every part is clear (inside, the two measure
    penetration differently), robots included."""
    from armanim.arm.chain import rpy_rotation
    from armanim.world.obstacles import BOX, FLOOR, ROD, Boxes, Rods

    for trial in range(6):
        n = int(rng.integers(2, 7))
        arm = Arm.from_names(list(rng.uniform(1, 4, n)), base=tuple(rng.uniform(-2, 2, 3)), axes=list(rng.choice(["x", "y", "z"], n)))
        boxes = [(rng.uniform(-8, 8, 3), rng.uniform(0.5, 3, 3), rng.uniform(-180, 180, 3)) for _ in range(2)]
        rods = [(a, a + rng.normal(size=3) * 2, float(rng.uniform(0.2, 1))) for a in rng.uniform(-8, 8, (2, 3))]
        floor = float(arm.base[2] - 1.0)
        draft = Draft(kind="test", base=arm.base, links=arm.links, axes=[], direction="z", width=0.4, home=np.zeros(n), limits=[],
                      boxes=boxes, rods=rods, floor=floor)
        solids = draft.solids()
        obstacles = Obstacles(np.zeros((0, 3)), np.zeros(0), np.ones(5),
                              Boxes(np.array([c for c, _, _ in boxes]), np.array([sz for _, sz, _ in boxes]) / 2,
                                    np.array([rpy_rotation(np.radians(r)) for _, _, r in boxes])),
                              Rods(np.array([a for a, _, _ in rods]), np.array([b for _, b, _ in rods]), np.array([r for _, _, r in rods])),
                              floor, np.array([BOX, BOX, ROD, ROD, FLOOR]))
        phi = rng.uniform(-np.pi, np.pi, (poses, n))
        pose = forward(arm, phi)
        ours = clearances(pose, obstacles, joint_capsules(arm, 0.2)).links
        theirs = solid_gaps(solids, pose.points[:, :-1], pose.points[:, 1:], np.full(n, 0.2), np.arange(n) == 0)
        clear = np.all(ours > 1e-6, axis=(-1, -2)) & np.all(theirs > 1e-6, axis=(-1, -2))
        assert clear.sum() >= 5, "too few clear poses to compare"
        both_inf = np.isinf(ours) & np.isinf(theirs)  # the floor's column of the first link: left out by both
        with np.errstate(invalid="ignore"):  # inf - inf where both are infinite, replaced by 0
            diff = np.abs(np.where(both_inf, 0.0, ours - theirs))
        assert np.max(diff[clear]) < 1e-9, f"trial {trial}: the oracle's solid clearances differ from armanim's by {np.max(diff[clear]):.3g}"


def robot_pose(rng: np.random.Generator, geo: RobotGeometry) -> np.ndarray:
    """A pose inside the limits, 10 degrees away from them, within +-180 degrees, tool point 0.1 m above the base."""
    lo = np.maximum(geo.lower + np.radians(10.0), -np.pi)
    hi = np.minimum(geo.upper - np.radians(10.0), np.pi)
    while True:
        pose = rng.uniform(lo, hi)
        if geo.tip(pose)[2] > 0.1:
            return pose


def draw_robot_scene(rng: np.random.Generator) -> Draft:
    """One candidate scene of the robot family: a bundled robot (Panda, UR5 or iiwa) at its home
    pose, 3-5 goals that are the tool points of random poses inside the limits, 3-10 spheres
    (across the tool's straight paths between goals, beside the arm in a goal pose, anywhere
    within reach), each kept only when home and every goal pose stay ROBOT_GEN_CLEARANCE clear."""
    robot = ROBOT_NAMES[int(rng.integers(0, len(ROBOT_NAMES)))]
    geo = base_geometry(robot)
    goal_poses = [robot_pose(rng, geo) for _ in range(int(rng.integers(3, 6)))]
    poses = np.array([geo.home] + goal_poses)
    tips, ends_a, ends_b = geo.placements(poses)
    draft = Draft(kind=robot, base=np.zeros(3), links=np.array([geo.reach]), axes=[], direction="z", width=0.1,
                  home=geo.home, limits=[], robot=robot)
    for _ in range(int(rng.integers(3, 11))):
        for _ in range(30):
            kind = rng.choice(["across", "near", "anywhere"], p=[0.4, 0.3, 0.3])
            radius = float(rng.uniform(0.03, 0.1))
            if kind == "across":
                k = int(rng.integers(0, len(tips) - 1))
                center = tips[k] + rng.uniform(0.35, 0.65) * (tips[k + 1] - tips[k]) + rng.normal(size=3) * 0.3 * radius
            elif kind == "near":
                k, c = int(rng.integers(1, len(poses))), int(rng.integers(0, len(geo.cap_r)))
                on_arm = ends_a[k, c] + rng.uniform(0, 1) * (ends_b[k, c] - ends_a[k, c])
                direction = rng.normal(size=3)
                gap = geo.cap_r[c] + ROBOT_GEN_CLEARANCE + rng.uniform(0.01, 0.1)
                center = on_arm + (radius + gap) * direction / np.linalg.norm(direction)
            else:
                direction = rng.normal(size=3)
                center = direction / np.linalg.norm(direction) * rng.uniform(0.3, 1.0) * geo.reach / 1.1
            center, radius = np.round(center, 4), round(radius, 4)
            if np.linalg.norm(center) < ROBOT_BASE_KEEP_OUT + radius:
                continue
            trial = replace(geo, centers=center[None], radii=np.array([radius]))
            if np.all(min_clearance(trial, poses) >= ROBOT_GEN_CLEARANCE):
                draft.spheres.append((center, radius))
                break
    draft.goals = [np.round(t, 4) for t in tips[1:]]
    draft.witnesses = list(goal_poses)
    return draft


# ---------------------------------------------------------------------------------------
# The shapes families (issue 22): tables, shelves, walls with a gap, posts, and a floor
# ---------------------------------------------------------------------------------------


def along_rpy(along: np.ndarray, roll: float) -> list:
    """rpy (degrees) of a box whose own x axis points along ``along`` (R = Rz(yaw) Ry(pitch) Rx(roll))."""
    along = along / max(np.linalg.norm(along), 1e-12)
    return [roll, float(np.degrees(-np.arcsin(np.clip(along[2], -1, 1)))), float(np.degrees(np.arctan2(along[1], along[0])))]


def shape_table(rng, tip, scale: dict) -> dict:
    """A table under a goal tip: its top ``scale['gap']`` and a little more below the tip."""
    thick = rng.uniform(*scale["thick"])
    gap = scale["gap"] + rng.uniform(0.1, 1.0) * scale["slack"]
    center = tip - [0.0, 0.0, gap + thick / 2]
    size = [rng.uniform(*scale["top"]), rng.uniform(*scale["top"]), thick]
    return {"boxes": [(center, size, [0.0, 0.0, rng.uniform(-45, 45)])]}


def shape_shelf(rng, tip, scale: dict) -> dict:
    """Two boards above and below a goal tip (a shelf's compartment around it)."""
    thick = rng.uniform(*scale["board"])
    half_gap = scale["gap"] + rng.uniform(0.2, 1.0) * scale["slack"]
    size = [rng.uniform(*scale["top"]), rng.uniform(*scale["top"]), thick]
    yaw = rng.uniform(-45, 45)
    return {"boxes": [(tip + [0.0, 0.0, s * (half_gap + thick / 2)], size, [0.0, 0.0, yaw]) for s in (-1.0, 1.0)]}


def shape_wall(rng, a, b, scale: dict) -> dict:
    """A wall across the path a-b with a gap in it: two slabs either side of the path."""
    from armanim.arm.chain import rpy_rotation

    rpy = along_rpy(b - a, rng.uniform(-90, 90))
    side = rpy_rotation(np.radians(rpy))[:, 1]
    middle = a + rng.uniform(0.35, 0.65) * (b - a)
    size = [rng.uniform(*scale["board"]), rng.uniform(*scale["wall"]), rng.uniform(*scale["wall"])]
    half_gap = rng.uniform(*scale["passage"])
    return {"boxes": [(middle + s * (half_gap + size[1] / 2) * side, size, rpy) for s in (-1.0, 1.0)]}


def shape_post(rng, a, b, scale: dict) -> dict:
    """A vertical capsule across the path a-b."""
    center = a + rng.uniform(0.35, 0.65) * (b - a) + rng.normal(size=3) * scale["jitter"]
    half = rng.uniform(*scale["post_half"]) * np.array([0.0, 0.0, 1.0])
    return {"rods": [(center - half, center + half, rng.uniform(*scale["post_r"]))]}


def rounded_shapes(shapes: dict) -> dict:
    """The shapes with their numbers rounded as a scene file writes them."""
    return {"boxes": [(np.round(c, 4), [round(float(v), 4) for v in sz], [round(float(v), 3) for v in r]) for c, sz, r in shapes.get("boxes", [])],
            "rods": [(np.round(a, 4), np.round(b, 4), round(float(r), 4)) for a, b, r in shapes.get("rods", [])]}


def place_shapes(rng, draft: Draft, poses: list, tips: list, scale: dict, keep: float, count: int) -> None:
    """Add ``count`` shapes (tables, shelves, walls with a gap, posts), each kept only when
    every pose stays ``keep`` clear of it (and of the base: ``scale['base']``)."""
    for _ in range(count):
        for _ in range(30):
            kind = rng.choice(["table", "shelf", "wall", "post"])
            k = int(rng.integers(1, len(tips)))
            shapes = rounded_shapes(shape_table(rng, tips[k], scale) if kind == "table" else
                                    shape_shelf(rng, tips[k], scale) if kind == "shelf" else
                                    shape_wall(rng, tips[k - 1], tips[k], scale) if kind == "wall" else
                                    shape_post(rng, tips[k - 1], tips[k], scale))
            trial = replace(draft, spheres=[], boxes=shapes["boxes"], rods=shapes["rods"], floor=None)
            if poses_clear(trial, poses, keep) and base_clear(trial, scale["base"]):
                draft.boxes.extend(shapes["boxes"])
                draft.rods.extend(shapes["rods"])
                break


def base_clear(draft: Draft, room: float) -> bool:
    """Whether no shape comes within ``room`` of the segment from the base 0.3 m (or a link length) down."""
    base = draft.base if draft.robot is None else np.zeros(3)
    solids = replace(draft.solids(), floor=None)
    if not len(solids):
        return True
    drop = np.array([0.0, 0.0, 0.3 if draft.robot else float(draft.links[0])])
    return bool(np.all(solid_gaps(solids, (base - drop)[None], base[None], np.array([room]), np.zeros(1, bool)) > 0))


LINK_SCALE = {"thick": (0.1, 0.3), "board": (0.1, 0.2), "top": (1.0, 3.0), "wall": (1.0, 3.0), "passage": (0.8, 1.5),
              "post_half": (1.0, 3.0), "post_r": (0.15, 0.4), "jitter": 0.2, "base": 0.5}
ROBOT_SCALE = {"thick": (0.03, 0.06), "board": (0.02, 0.03), "top": (0.3, 0.6), "wall": (0.2, 0.5), "passage": (0.12, 0.25),
               "post_half": (0.15, 0.3), "post_r": (0.02, 0.04), "jitter": 0.02, "base": 0.12}


def poses_above(rng, draft: Draft, draw_pose, count: int, keep: float) -> list:
    """``count`` poses (from ``draw_pose()``) that keep ``keep`` from the draft's floor (60 tries each)."""
    poses = []
    for _ in range(count):
        for _ in range(60):
            pose = draw_pose()
            if poses_clear(draft, [pose], keep):
                poses.append(pose)
                break
    return poses


def draw_shapes_scene(rng: np.random.Generator) -> Draft:
    """One candidate scene of the shapes family (issue 22): an arm of the standard family (the notes'
    kind, planar, mixed; 3-7 links), a floor under its base in 60 % of the scenes, 3-6 goal poses
    above it, then 2-5 tables, shelves, walls with a gap and posts across and around the goals."""
    draft = draw_arm(rng)
    size = float(np.mean(draft.links))
    if rng.random() < 0.6:
        draft.floor = round(float(draft.base[2] - rng.uniform(0.0, 0.5) * size), 4)
        if not poses_clear(draft, [draft.home], GEN_CLEARANCE):
            draft.floor = None
    goal_poses = poses_above(rng, draft, lambda: random_pose(rng, draft), int(rng.integers(3, 7)), GEN_CLEARANCE)
    tips = [joint_points(draft.geometry(), p)[-1] for p in [draft.home] + goal_poses]
    scale = {k: tuple(v * size for v in val) if isinstance(val, tuple) else val * size for k, val in LINK_SCALE.items()}
    scale.update(gap=draft.width / 2 + GEN_CLEARANCE, slack=0.3 * size, passage=(1.25 * draft.width, 2.5 * draft.width))
    place_shapes(rng, draft, [draft.home] + goal_poses, tips, scale, GEN_CLEARANCE, int(rng.integers(2, 6)))
    draft.influence = round(0.3 * size, 4)
    draft.goals = [np.round(t, 4) for t in tips[1:]]
    draft.witnesses = list(goal_poses)
    return draft


def draw_robot_shapes_scene(rng: np.random.Generator) -> Draft:
    """One candidate scene of the robot-shapes family (issue 22): a bundled Panda, UR5 or iiwa
    standing on the floor (z = 0), 3-5 goals (tool points of poses above the floor), 2-4 tables,
    shelves, walls with a gap and posts across and around them (metres)."""
    robot = ROBOT_NAMES[int(rng.integers(0, len(ROBOT_NAMES)))]
    geo = base_geometry(robot)
    draft = Draft(kind=robot, base=np.zeros(3), links=np.array([geo.reach]), axes=[], direction="z", width=0.1,
                  home=geo.home, limits=[], robot=robot, floor=0.0, influence=0.05)
    goal_poses = poses_above(rng, draft, lambda: robot_pose(rng, geo), int(rng.integers(3, 6)), ROBOT_GEN_CLEARANCE)
    tips = list(geo.placements(np.array([geo.home] + goal_poses))[0])
    tip_room = 0.07 + ROBOT_GEN_CLEARANCE  # the largest tool capsule radius of the bundled robots, and the margin
    scale = dict(ROBOT_SCALE, gap=tip_room, slack=0.05)
    place_shapes(rng, draft, [geo.home] + goal_poses, tips, scale, ROBOT_GEN_CLEARANCE, int(rng.integers(2, 5)))
    draft.goals = [np.round(t, 4) for t in tips[1:]]
    draft.witnesses = list(goal_poses)
    return draft


def draw_pose_scene(rng: np.random.Generator) -> Draft:
    """One candidate scene of the poses family (issue 21): the robot family's scene, each goal with
    the tool's orientation of its generator pose as well (a 6-D goal)."""
    draft = draw_robot_scene(rng)
    geo = base_geometry(draft.robot)
    draft.orientations = [geo.rotation(pose) for pose in draft.witnesses]
    draft.kind = f"{draft.robot}-pose"
    return draft


FAMILIES = {"standard": draw_scene, "hard": draw_hard_scene, "robots": draw_robot_scene, "poses": draw_pose_scene,
            "shapes": draw_shapes_scene, "robot-shapes": draw_robot_shapes_scene}
SHAPE_FAMILIES = ("shapes", "robot-shapes")
FAMILY_STREAMS = {"hard": 2, "robots": 3, "shapes": 4, "robot-shapes": 5, "poses": 4}
"""The random stream of each family's scenes, fixed so that published figures stay reproducible
(poses and shapes share a number; their generators differ, so their scenes do too)."""
"""Scene generators by ``--family``: the original distribution, the hard one of issue 18
(7-link mixed-axis and planar arms, tight limits everywhere, narrow passages, dense clutter,
goals near spheres and at the edge of reach, 8-12 goals) and the robots of issue 20
(a bundled Panda, UR5 or iiwa among 3-10 spheres, 3-5 goals)."""


def armanim_rejects(scene: dict) -> list:
    """armanim's own objections to a scene mapping: pydantic errors or cross-field problems (empty: valid)."""
    try:
        model = scene_model(scene)
    except ValidationError as exc:
        return [str(exc)]
    return scene_problems(model)


def make_scene(seed: int, index: int, family: str = "standard") -> Draft:
    """Scene ``index`` of the benchmark for ``seed``: drawn until armanim accepts it.

    Parameters
    ----------
    seed : int
        The benchmark's ``--seed``.
    index : int
        0-based scene index; the scene depends only on (seed, index, family).
    family : str
        A key of :data:`FAMILIES`.

    Returns
    -------
    Draft
    """
    rng = np.random.default_rng([seed, index] if family == "standard" else [seed, index, FAMILY_STREAMS[family]])
    while True:
        draft = FAMILIES[family](rng)
        enough = (len(draft.boxes) + len(draft.rods) >= 2 and len(draft.goals) >= 2) if family in SHAPE_FAMILIES else \
            len(draft.spheres) >= (3 if family in ("robots", "poses") else 2)
        if enough and not armanim_rejects(draft.as_scene_dict(scene_name(seed, index))):
            return draft


def scene_name(seed: int, index: int, method: str | None = None, planner: str | None = None) -> str:
    """The scene's ``name`` (and output folder of ``armanim run``)."""
    return "-".join(str(p) for p in (f"bench-s{seed}-k{index}", method, planner) if p is not None)


# ---------------------------------------------------------------------------------------
# Running armanim
# ---------------------------------------------------------------------------------------


def planner_field_exists() -> bool:
    """Whether this armanim has ``solver.planner``."""
    return "planner" in SolverModel.model_fields


def clearance_of(model: SceneModel) -> float | None:
    """The scene's resolved ``solver.clearance`` (scene units), or None when armanim has no such field."""
    if "clearance" not in SolverModel.model_fields:
        return None
    resolved = getattr(scene_to_problem(model).solver, "clearance", None)
    value = resolved if resolved is not None else model.solver.clearance
    return float(value) if value is not None else None


def timed_solve(problem):
    """Solve and time it: (solution, total seconds, per-goal end times in seconds from the start,
    CPU seconds of this process: less hit than the wall clock by other work on the machine)."""
    marks = []
    cpu = time.process_time()
    start = time.perf_counter()

    def progress(done, _bound):
        marks.append((done, time.perf_counter() - start))

    try:
        solution = solve_trajectory(problem, progress=progress)
    except TypeError:  # a solve_trajectory without progress
        solution = solve_trajectory(problem)
    return solution, time.perf_counter() - start, marks, time.process_time() - cpu


def goal_wall_times(reports, marks, total: float) -> list[float]:
    """Wall time of each goal from the progress marks (nan when there are none)."""
    if not marks:
        return [float("nan")] * len(reports)
    counts = np.array([m[0] for m in marks])
    times = np.array([m[1] for m in marks])
    ends, previous = [], 0.0
    for report in reports:
        last = report.last_frame + 1 if report.last_frame >= 0 else None
        if last is not None:
            upto = np.nonzero(counts <= last)[0]
            previous = float(times[upto[-1]]) if len(upto) else previous
        ends.append(previous)
    return list(np.diff([0.0] + ends))


def invariant_breaks(problem, trajectory, clearance: float | None, geo: Geometry) -> list[str]:
    """Every invariant a trajectory breaks, as short messages (empty: all hold).

    NaN anywhere; a limited joint on or past its limit; the smallest capsule clearance
    (armanim's own and the oracle's recomputation) below the setting (or <= 0 without
    one); a joint turning more than ``max_joint_step`` in a frame (wrap-aware).
    """
    breaks = []
    phi = trajectory.phi
    if not (np.all(np.isfinite(phi)) and np.all(np.isfinite(trajectory.tip)) and not np.any(np.isnan(trajectory.clearance))):
        return ["NaN or infinity in phi, tip or clearance"]
    lim = problem.limits
    outside = (phi <= lim.lower) | (phi >= lim.upper)
    if np.any(outside):
        frame, joint = np.argwhere(outside)[0]
        breaks.append(f"joint {joint + 1} at {np.degrees(phi[frame, joint]):.6g} deg on frame {frame} is not strictly inside its limits")
    floor = clearance - ROUNDING if clearance is not None else 0.0
    for source, values in (("armanim", trajectory.clearance), ("oracle", min_clearance(geo, phi))):
        bad = values < floor if clearance is not None else values <= floor
        if np.any(bad):
            frame = int(np.argmax(bad))
            wanted = f">= {clearance:.3g} (solver.clearance)" if clearance is not None else "> 0"
            breaks.append(f"clearance {values[frame]:.3g} ({source}) on frame {frame}, expected {wanted}")
    if len(phi) > 1:
        turn = np.abs(np.mod(np.diff(phi, axis=0) + np.pi, 2 * np.pi) - np.pi)
        if turn.max() > problem.solver.max_joint_step + ROUNDING:
            frame = int(np.argmax(turn.max(axis=1))) + 1
            breaks.append(f"a joint turned {np.degrees(turn.max()):.12g} deg on frame {frame} (max_joint_step "
                          f"{np.degrees(problem.solver.max_joint_step):.12g}, excess {turn.max() - problem.solver.max_joint_step:.3g} rad)")
    return breaks


@dataclass
class Run:
    """One scene solved with one method and planner setting."""

    scene: int
    kind: str
    method: str
    planner: str
    reached: list  # per goal
    reasons: list  # per goal: None or the miss reason
    planned: list  # per goal: True / False, or None when GoalReport has no ``planned``
    easy: list  # per goal: for a feasible miss, whether a straight joint-space line to an oracle pose is clear
    goal_seconds: list
    frames: int
    near_surface: int
    at_limit: int
    seconds: float
    breaks: list
    cpu_seconds: float = 0.0


def straight_line_clear(geo: Geometry, start: np.ndarray, end: np.ndarray) -> bool:
    """True when the straight joint-space segment start-end stays inside the limits and never enters a sphere.

    Sampled so that no arm point moves more than 0.02 (or the clearance, if smaller) between
    samples, at most 20000 samples. The start is the arm's own pose, which may touch a surface,
    so the test is clearance > 0, not >= the clearance setting.
    """
    travel = geo.reach * np.abs(end - start).sum()  # bounds how far any arm point moves along the segment
    samples = int(min(max(np.ceil(travel / min(geo.clearance, 0.02)), 2), 20000))
    path = start + np.linspace(0.0, 1.0, samples)[:, None] * (end - start)
    inside = np.all((path > geo.lower) & (path < geo.upper))
    return bool(inside and np.all(min_clearance(geo, path) > 0))


def easy_misses(geo: Geometry, verdicts: list, reports, phi: np.ndarray) -> list:
    """Per goal: for a feasible goal missed, whether the straight joint-space line from the arm's
    last pose on that goal to the oracle's pose is clear (an easy miss); None otherwise."""
    easy, pose = [], phi[0]
    for verdict, report in zip(verdicts, reports):
        pose = phi[report.last_frame] if report.last_frame >= 0 else pose
        easy.append(straight_line_clear(geo, pose, verdict.pose) if verdict.feasible and not report.reached else None)
    return easy


def solve_one(draft: Draft, seed: int, index: int, method: str, planner: str, geo: Geometry, verdicts: list) -> Run:
    """Solve a scene with one method and planner setting, and check its trajectory."""
    field_planner = planner if planner_field_exists() else None
    model = scene_model(draft.as_scene_dict(scene_name(seed, index, method, field_planner), method, field_planner))
    problem = scene_to_problem(model)
    try:
        solution, seconds, marks, cpu_seconds = timed_solve(problem)
    except Exception as exc:  # noqa: BLE001 - a crash is a broken invariant reported with its scene, not the end of the run
        return crashed_run(draft, index, method, planner, exc)
    traj = solution.trajectory
    lim = problem.limits
    gaps = np.minimum(traj.phi - lim.lower, lim.upper - traj.phi)
    return Run(
        scene=index, kind=draft.kind, method=method, planner=planner,
        reached=[bool(g.reached) for g in solution.goals],
        reasons=[g.reason for g in solution.goals],
        planned=[getattr(g, "planned", None) for g in solution.goals],
        easy=easy_misses(geo, verdicts, solution.goals, traj.phi),
        goal_seconds=goal_wall_times(solution.goals, marks, seconds),
        frames=int(traj.frames),
        near_surface=int(np.sum(traj.clearance < NEAR_SURFACE)),
        at_limit=int(np.sum(np.any(gaps < AT_LIMIT, axis=1))),
        seconds=seconds,
        breaks=invariant_breaks(problem, traj, clearance_of(model), geo),
        cpu_seconds=cpu_seconds,
    )


def crashed_run(draft: Draft, index: int, method: str, planner: str, exc: Exception) -> Run:
    """The Run of a solve that raised: every goal missed with reason ``crash``, one broken invariant."""
    goals = len(draft.goals)
    return Run(
        scene=index, kind=draft.kind, method=method, planner=planner, reached=[False] * goals,
        reasons=["crash"] * goals, planned=[None] * goals, easy=[None] * goals, goal_seconds=[float("nan")] * goals,
        frames=0, near_surface=0, at_limit=0, seconds=0.0, breaks=[f"solve_trajectory raised {type(exc).__name__}: {exc}"],
    )


@dataclass
class SceneResult:
    """Everything measured on one scene: the oracle's labels and one Run per method and planner."""

    index: int
    kind: str
    verdicts: list
    witness_missed: int  # goals whose generator pose is a witness but the oracle found none
    oracle_seconds: float
    runs: list
    twin_runs: list = field(default_factory=list)  # (method, frames, seconds, CPU seconds) of the spheres-only twin (shape families)
    shape_times: list = field(default_factory=list)  # (method, frames, seconds, CPU seconds) of the shapes, timed beside the twin
    distance_seconds: tuple = ()  # (shapes single, twin single, shapes batched, twin batched) seconds per pose


def oracle_geometry(draft: Draft, seed: int, index: int) -> Geometry:
    """The oracle's geometry of a scene, with armanim's tolerance and clearance setting."""
    model = scene_model(draft.as_scene_dict(scene_name(seed, index)))
    clearance = clearance_of(model)
    return draft.geometry(DEFAULT_CLEARANCE if clearance is None else clearance, model.solver.tolerance)


def label_scene(draft: Draft, geo: Geometry, seed: int, index: int) -> tuple[list, int]:
    """The oracle's verdict on every goal, and how many generator witnesses it failed to match."""
    verdicts, missed = [], 0
    for k, goal in enumerate(draft.goals):
        witness = draft.witnesses[k]
        orientation = draft.orientations[k] if draft.orientations else None
        verdict = label_goal(geo, goal, np.random.default_rng([seed, index, k, 7]), orientation=orientation)
        if not verdict.feasible and witness is not None and is_witness(geo, goal, witness, orientation):
            missed += 1
        verdicts.append(verdict)
    return verdicts, missed


def bench_scene(task: tuple) -> SceneResult:
    """Worker: generate scene ``index``, label its goals, solve it with every method and planner setting."""
    seed, index, methods, planners, family, rounds = task
    draft = make_scene(seed, index, family)
    geo = oracle_geometry(draft, seed, index)
    start = time.perf_counter()
    verdicts, missed = label_scene(draft, geo, seed, index)
    oracle_seconds = time.perf_counter() - start
    runs = [solve_one(draft, seed, index, m, p, geo, verdicts) for m in methods for p in planners]
    timings = [paired_timing(draft, seed, index, run, rounds) for run in runs if run.planner == planners[0]] if family in SHAPE_FAMILIES else []
    distances = distance_timing(draft, seed, index) if family in SHAPE_FAMILIES else ()
    return SceneResult(index, draft.kind, verdicts, missed, oracle_seconds, runs,
                       twin_runs=[t for _, t in timings], shape_times=[s for s, _ in timings], distance_seconds=distances)


def distance_timing(draft: Draft, seed: int, index: int, poses: int = 200, batch: int = 2000) -> tuple:
    """Seconds per pose of armanim's clearances (forward kinematics included) with the scene's shapes
    and with its spheres-only twin: every clearance of one pose at a time (what each frame's filter
    computes) and the smallest of ``batch`` poses at once (``min_link_clearance``: what the planner
    checks), the best of three rounds each."""
    problems = [scene_to_problem(scene_model(d.as_scene_dict(scene_name(seed, index)))) for d in (draft, draft.spheres_twin())]
    rng = np.random.default_rng([seed, index, 22])
    phi = rng.uniform(-np.pi, np.pi, (batch, problems[0].arm.n))
    out = []
    for single in (True, False):
        for problem in problems:
            best = np.inf
            for _ in range(3):
                start = time.perf_counter()
                if single:
                    for q in phi[:poses]:
                        clearances(forward(problem.arm, q), problem.obstacles, problem.capsules)
                else:
                    min_link_clearance(forward(problem.arm, phi), problem.obstacles, problem.capsules)
                best = min(best, (time.perf_counter() - start) / (poses if single else batch))
            out.append(best)
    return tuple(out)


def scene_problem(draft: Draft, seed: int, index: int, method: str, planner: str):
    """armanim's problem of a draft solved with one method and planner setting."""
    field_planner = planner if planner_field_exists() else None
    return scene_to_problem(scene_model(draft.as_scene_dict(scene_name(seed, index, method, field_planner), method, field_planner)))


def paired_timing(draft: Draft, seed: int, index: int, run: Run, rounds: int) -> tuple[tuple, tuple]:
    """(method, frames, seconds, CPU seconds) of the scene with its shapes and of its spheres-only
    twin (:meth:`Draft.spheres_twin`) solved alike, each the best of ``rounds`` solves taken in
    turn (shapes, twin, shapes, ...; the first shapes solve is ``run``'s own), so that both meet
    the same moments of a shared machine's load. A solve is deterministic: each round repeats it."""
    shaped = scene_problem(draft, seed, index, run.method, run.planner)
    twin = scene_problem(draft.spheres_twin(), seed, index, run.method, run.planner)
    best = {"shapes": [run.frames, run.seconds, run.cpu_seconds], "twin": [0, np.inf, np.inf]}
    for k in range(rounds):
        for name, problem in (("shapes", shaped), ("twin", twin)):
            if name == "shapes" and k == 0:
                continue  # timed already by solve_one
            solution, seconds, _, cpu_seconds = timed_solve(problem)
            kept = best[name]
            kept[0], kept[1], kept[2] = int(solution.trajectory.frames), min(kept[1], seconds), min(kept[2], cpu_seconds)
    return tuple([run.method] + best["shapes"]), tuple([run.method] + best["twin"])


def twin_rows(results: list, methods: list, planner: str) -> list[list[str]]:
    """Per method: ms per frame with the shapes, with their spheres-only twins, and the ratio; the
    same in CPU time (the wall clock's ratio moves with whatever else the machine runs)."""
    rows = []
    for method in methods:
        shapes = [t for r in results for t in r.shape_times if t[0] == method]
        twins = [t for r in results for t in r.twin_runs if t[0] == method]
        if not shapes or not twins:
            continue
        frames, twin_frames = max(sum(t[1] for t in shapes), 1), max(sum(t[1] for t in twins), 1)
        shaped = 1000.0 * sum(t[2] for t in shapes) / frames
        spheres = 1000.0 * sum(t[2] for t in twins) / twin_frames
        cpu_shaped = 1000.0 * sum(t[3] for t in shapes) / frames
        cpu_spheres = 1000.0 * sum(t[3] for t in twins) / twin_frames
        rows.append([method, f"{shaped:.2f}", f"{spheres:.2f}", f"{shaped / spheres:.2f}x",
                     f"{cpu_shaped:.2f}", f"{cpu_spheres:.2f}", f"{cpu_shaped / cpu_spheres:.2f}x"])
    return rows


# ---------------------------------------------------------------------------------------
# The report
# ---------------------------------------------------------------------------------------


def percent(part: float, whole: float) -> str:
    """``part/whole (x %)``, or ``-`` when whole is 0."""
    return f"{part}/{whole} ({100.0 * part / whole:.0f} %)" if whole else "-"


def summary_rows(results: list, methods: list, planners: list) -> list[list[str]]:
    """One table row per method and planner setting."""
    rows = []
    for method in methods:
        for planner in planners:
            runs = [(r, run) for r in results for run in r.runs if run.method == method and run.planner == planner]
            feasible = reached = bogus = frames = near = limit = broken = 0
            seconds = 0.0
            planned_times, any_planned_field = [], False
            for r, run in runs:
                for verdict, ok, was_planned, secs in zip(r.verdicts, run.reached, run.planned, run.goal_seconds):
                    feasible += verdict.feasible
                    reached += verdict.feasible and ok
                    bogus += (not verdict.feasible) and ok
                    any_planned_field |= was_planned is not None
                    if was_planned:
                        planned_times.append(secs)
                frames += run.frames
                near += run.near_surface
                limit += run.at_limit
                seconds += run.seconds
                broken += len(run.breaks)
            per_planned = f"{np.nanmean(planned_times):.2f} s ({len(planned_times)})" if planned_times else ("0 planned" if any_planned_field else "n/a")
            rows.append([
                method, planner, percent(reached, feasible), str(bogus),
                f"{100.0 * near / max(frames, 1):.1f} %", f"{100.0 * limit / max(frames, 1):.1f} %",
                f"{1000.0 * seconds / max(frames, 1):.2f}", per_planned, str(broken),
            ])
    return rows


HEADER = ["method", "planner", "feasible reached", "reached infeasible", "frames <1e-3 of surface",
          "frames on a limit", "ms/frame", "s/planned goal", "invariants broken"]


def print_table(header: list, rows: list) -> None:
    """A markdown table, columns padded."""
    widths = [max(len(str(x)) for x in col) for col in zip(header, *rows)]

    def line(cells):
        return "| " + " | ".join(str(c).ljust(w) for c, w in zip(cells, widths)) + " |"

    print(line(header))
    print("|" + "|".join("-" * (w + 2) for w in widths) + "|")
    for row in rows:
        print(line(row))


def miss_reasons(results: list) -> dict:
    """Counter of miss reasons on feasible goals, per (method, planner); key ``easy`` counts the
    misses with a clear straight joint-space line to an oracle pose."""
    counts = defaultdict(Counter)
    for r in results:
        for run in r.runs:
            for verdict, ok, reason, easy in zip(r.verdicts, run.reached, run.reasons, run.easy):
                if verdict.feasible and not ok:
                    counts[(run.method, run.planner)][reason] += 1
                    counts[(run.method, run.planner)]["(easy)"] += bool(easy)
    return counts


def kind_rows(results: list, planners: list) -> list[list[str]]:
    """Feasible goals reached per arm kind and planner setting, all methods together."""
    rows = []
    for kind in sorted({r.kind for r in results}):
        cells = [kind, str(sum(r.kind == kind for r in results))]
        for planner in planners:
            feasible = reached = 0
            for r in (r for r in results if r.kind == kind):
                for run in (run for run in r.runs if run.planner == planner):
                    feasible += sum(v.feasible for v in r.verdicts)
                    reached += sum(v.feasible and ok for v, ok in zip(r.verdicts, run.reached))
            cells.append(percent(reached, feasible))
        rows.append(cells)
    return rows


def print_report(results: list, methods: list, planners: list, list_misses: bool) -> int:
    """Print every table; return the number of broken invariants."""
    verdicts = [v for r in results for v in r.verdicts]
    why = Counter(v.why for v in verdicts)
    print(f"\n{len(results)} scenes, {len(verdicts)} goals: oracle says {why['feasible']} feasible, "
          f"{why['out_of_reach']} out of reach, {why['no_free_pose']} without a free pose inside the limits; "
          f"generator poses the oracle failed to match: {sum(r.witness_missed for r in results)}; "
          f"oracle time {sum(r.oracle_seconds for r in results):.1f} s")
    print(f"armanim: planner field {'present' if planner_field_exists() else 'absent (only the current behaviour, labelled off)'}, "
          f"clearance field {'present' if 'clearance' in SolverModel.model_fields else f'absent (oracle clearance {DEFAULT_CLEARANCE})'}\n")
    print_table(HEADER, summary_rows(results, methods, planners))
    print("\nMisses of feasible goals by reason (easy: the straight joint-space line from the arm's last pose to the oracle's pose is clear):")
    for (method, planner), counts in sorted(miss_reasons(results).items()):
        easy = counts.pop("(easy)")
        print(f"  {method:8s} {planner:4s} " + ", ".join(f"{reason} {n}" for reason, n in counts.most_common()) + f"; easy {easy}")
    if any(r.twin_runs for r in results):
        print(f"\nTime per frame against the same scenes with spheres only (each box and capsule replaced by the largest "
              f"sphere inside it, the floor dropped; planner {planners[0]}; each solve the best of its --timing-rounds, "
              f"taken in turn with its twin's):")
        print_table(["method", "ms/frame shapes", "ms/frame spheres twin", "ratio", "CPU ms/frame shapes", "CPU ms/frame twin", "CPU ratio"], twin_rows(results, methods, planners[0]))
        timed = np.array([r.distance_seconds for r in results if r.distance_seconds])
        if len(timed):
            single, batched = timed[:, 0].sum() / timed[:, 1].sum(), timed[:, 2].sum() / timed[:, 3].sum()
            print(f"armanim's clearances per pose (FK included), shapes / spheres twin: one pose at a time "
                  f"{1e6 * timed[:, 0].mean():.0f} / {1e6 * timed[:, 1].mean():.0f} us = {single:.2f}x; "
                  f"the smallest of 2000 at once {1e6 * timed[:, 2].mean():.1f} / {1e6 * timed[:, 3].mean():.1f} us = {batched:.2f}x")
    print("\nFeasible goals reached per arm kind (all methods):")
    print_table(["arm kind", "scenes"] + [f"planner {p}" for p in planners], kind_rows(results, planners))
    broken = 0
    for r in results:
        for run in r.runs:
            for message in run.breaks:
                broken += 1
                print(f"INVARIANT scene {r.index} {run.method} {run.planner}: {message}")
    flagged = [(r, run, k) for r in results for run in r.runs for k, (v, ok) in enumerate(zip(r.verdicts, run.reached)) if ok and not v.feasible]
    for r, run, k in flagged:
        print(f"ORACLE? scene {r.index} goal {k} reached by {run.method}/{run.planner} but labelled {r.verdicts[k].why}")
    if list_misses:
        print("\nFeasible goals missed (scene, goal, arm kind, method, planner, reason; easy: straight line clear):")
        for r in results:
            for run in r.runs:
                for k, (v, ok, reason, easy) in enumerate(zip(r.verdicts, run.reached, run.reasons, run.easy)):
                    if v.feasible and not ok:
                        print(f"  scene {r.index:3d} goal {k} {r.kind:7s} {run.method:8s} {run.planner:4s} {reason}{' (easy)' if easy else ''}")
    return broken


# ---------------------------------------------------------------------------------------
# Command line
# ---------------------------------------------------------------------------------------


def dump_scene(seed: int, index: int, folder: Path, methods: list, planners: list, family: str = "standard") -> None:
    """Write scene ``index`` as YAML, one file per method (and planner setting when armanim has it)."""
    folder.mkdir(parents=True, exist_ok=True)
    draft = make_scene(seed, index, family)
    geo = oracle_geometry(draft, seed, index)
    verdicts, _ = label_scene(draft, geo, seed, index)
    for method in methods:
        for planner in planners if planner_field_exists() else [None]:
            name = scene_name(seed, index, method, planner)
            text = f"# motion_bench.py --seed {seed}, scene {index} ({draft.kind} arm); oracle: " + ", ".join(
                f"goals[{k}] {v.why}" for k, v in enumerate(verdicts)) + "\n"
            text += yaml.safe_dump(draft.as_scene_dict(name, method, planner), sort_keys=False, default_flow_style=None)
            path = folder / f"{name}.yaml"
            path.write_text(text)
            print(f"wrote {path}   (armanim run {path})")


def parse_args(argv=None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--scenes", type=int, default=40, help="number of random scenes (default 40)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the scene generator (default 0)")
    parser.add_argument("--methods", default=",".join(METHODS), help="comma-separated methods (default all four)")
    parser.add_argument("--planner", default="auto,off", help="comma-separated planner settings (default auto,off)")
    parser.add_argument("--jobs", type=int, default=1, help="processes over scenes (default 1)")
    parser.add_argument("--family", choices=sorted([*FAMILIES, "self"]), default="standard",
                        help="scene distribution: standard, hard (issue 18: tight limits, passages, dense clutter, 8-12 goals), "
                             "robots (issue 20: bundled Panda, UR5, iiwa; pinocchio oracle, witness labels), "
                             "shapes or robot-shapes (issue 22: tables, shelves, walls with a gap, posts, a floor; coal oracle)")
    parser.add_argument("--timing-rounds", type=int, default=1, metavar="R",
                        help="shape families: time each solve and its spheres-only twin's R times in turn and keep the "
                             "best of each (default 1; 3 steadies the ratio on a shared machine)")
    parser.add_argument("--quick", action="store_true", help="8 scenes, for development")
    parser.add_argument("--list-misses", action="store_true", help="print every feasible goal that was missed")
    parser.add_argument("--dump-scene", nargs=2, metavar=("K", "DIR"), help="write scene K as YAML into DIR and exit")
    args = parser.parse_args(argv)
    args.methods = [m for m in args.methods.split(",") if m]
    unknown = set(args.methods) - set(METHODS)
    if unknown:
        parser.error(f"unknown method(s) {sorted(unknown)}; expected some of {', '.join(METHODS)}")
    args.planner = [p for p in args.planner.split(",") if p]
    if args.quick:
        args.scenes = 8
    return args


def effective_planners(requested: list) -> list:
    """The planner settings to run: as asked when armanim has ``solver.planner``, else just ``off``."""
    if planner_field_exists():
        return requested
    if requested != ["off"]:
        print("note: this armanim has no solver.planner; running the current behaviour, labelled 'off'", file=sys.stderr)
    return ["off"]


def main(argv=None) -> int:
    args = parse_args(argv)
    began = time.perf_counter()
    planners = effective_planners(args.planner)
    if args.dump_scene:
        dump_scene(args.seed, int(args.dump_scene[0]), Path(args.dump_scene[1]), args.methods, planners, args.family)
        return 0
    if args.family == "self":
        return self_family(args)
    self_test_geometry(np.random.default_rng(12345))
    print("self-test: the oracle's forward kinematics and clearances equal armanim's (1e-9)", file=sys.stderr)
    if args.family in SHAPE_FAMILIES:
        self_test_solids(np.random.default_rng(12345))
        print("self-test: the oracle's (coal's) clearances to boxes, capsules and the floor equal armanim's (1e-9)", file=sys.stderr)
    if args.family in ("robots", "poses", "robot-shapes"):
        self_test_robots(np.random.default_rng(12345))
        print("self-test: pinocchio's tool point and the oracle's robot capsule clearances equal armanim's (1e-9)", file=sys.stderr)
    tasks = [(args.seed, k, args.methods, planners, args.family, max(1, args.timing_rounds)) for k in range(args.scenes)]
    results = []
    if args.jobs > 1:
        with multiprocessing.get_context("forkserver").Pool(args.jobs) as pool:
            for result in pool.imap_unordered(bench_scene, tasks):
                results.append(result)
                report_progress(result, len(results), args.scenes, began)
    else:
        for task in tasks:
            results.append(bench_scene(task))
            report_progress(results[-1], len(results), args.scenes, began)
    results.sort(key=lambda r: r.index)
    print(f"motion_bench --family {args.family} --seed {args.seed} --scenes {args.scenes} --methods {','.join(args.methods)} --planner {','.join(planners)}")
    broken = print_report(results, args.methods, planners, args.list_misses)
    print(f"\nbenchmark took {time.perf_counter() - began:.1f} s ({args.jobs} job(s))")
    if broken:
        print(f"{broken} invariant(s) broken", file=sys.stderr)
    return 1 if broken else 0


# --- The self-collision family (issue 35) -----------------------------------------------------

SELF_ROBOTS = ("panda", "ur5", "iiwa", "chain")
"""Bundled robots, and a URDF chain of this file's own (:data:`CHAIN_URDF`): one per scene in turn."""
SELF_GOALS = 3
SELF_DRAWS = 4000  # random poses tried per scene for goals that cross the body
SELF_STREAM = 6
CHAIN_URDF = """<robot name="fold-chain">
  <link name="base"/>
{links}
{joints}
</robot>
"""


def chain_urdf_text(count: int = 6) -> str:
    """A 6-joint chain of 0.3 m cylinders (radius 0.04) whose axes alternate z, y: it folds onto itself."""
    links = "\n".join(f'  <link name="c{k}"><collision><origin xyz="0 0 0.15"/><geometry><cylinder radius="0.04" '
                      f'length="0.3"/></geometry></collision></link>' for k in range(count))
    joints = "\n".join(f'  <joint name="q{k}" type="revolute"><parent link="{"base" if k == 0 else f"c{k - 1}"}"/>'
                       f'<child link="c{k}"/><origin xyz="0 0 {0.05 if k == 0 else 0.3}"/>'
                       f'<axis xyz="{"0 0 1" if k % 2 == 0 else "0 1 0"}"/>'
                       f'<limit lower="-2.8" upper="2.8" effort="1" velocity="1"/></joint>' for k in range(count))
    return CHAIN_URDF.format(links=links, joints=joints)


def self_scene_problem(robot: str, folder: Path, goals: list, self_collision="auto"):
    """The problem of a self-collision scene: a bundled robot or the chain, no obstacles, the bundled
    robot scenes' solver settings (self_clearance: clearance / 2 = 0.01 m)."""
    arm = {"robot": robot} if robot != "chain" else {"urdf": str(folder / "chain.urdf"), "home": [0, 30, 60, 0, 30, 0]}
    scene = {"version": 1, "arm": {**arm, "self_collision": self_collision}, "goals": goals, "solver": dict(ROBOT_SOLVER)}
    return scene_to_problem(scene_model(scene, folder))


def coal_pair_gaps(problem, phi: np.ndarray) -> np.ndarray:
    """(F,) the least gap of any enabled pair at each pose, by coal (capsules placed by the arm's
    forward kinematics; coal measures the distance)."""
    import coal

    from armanim.arm.capsules import capsule_ends

    pairs, caps = problem.self_pairs, problem.capsules
    a, b = capsule_ends(caps, forward(problem.arm, np.atleast_2d(phi)))
    out = np.full(len(a), np.inf)
    request = coal.DistanceRequest()
    for f in range(len(a)):
        shapes = [coal_capsule(a[f, k], b[f, k], float(caps.radius[k])) for k in range(len(caps))]
        for i, j in zip(pairs.first, pairs.second):
            result = coal.DistanceResult()
            out[f] = min(out[f], coal.distance(*shapes[i], *shapes[j], request, result))
    return out


SELF_THROUGH = 0.15
"""Metres: a goal's straight line from the previous tool point (home's first) passes this near the base's
vertical axis, through the robot's body."""


def segment_axis_distance(a: np.ndarray, b: np.ndarray, base: np.ndarray) -> float:
    """Least horizontal distance of the segment a-b (above z = base + 0.05) to the vertical line through ``base``."""
    t = np.linspace(0.0, 1.0, 101)[:, None]
    points = a + t * (b - a)
    high = points[:, 2] > base[2] + 0.05
    if not high.any():
        return np.inf
    return float(np.linalg.norm(points[high, :2] - base[:2], axis=1).min())


def draw_self_goals(problem, rng: np.random.Generator) -> tuple[list, int]:
    """Goal poses whose tool point lies across the body from the previous one (home's first): the
    straight line between them passes within :data:`SELF_THROUGH` of the base's vertical axis,
    so the arm must swing round or fold past itself; each pose free (every enabled pair at least
    self_clearance + 0.2 x clearance apart by coal, the planner's room to settle; the tool 0.1 m
    above the base): feasible by construction. Returns (poses, draws tried)."""
    lim = problem.limits
    lo, hi = np.maximum(lim.lower, -np.pi) + np.radians(10), np.minimum(lim.upper, np.pi) - np.radians(10)
    keep = problem.self_pairs.clearance + 0.2 * problem.solver.clearance
    base = problem.arm.base
    found, tried = [], 0
    previous = forward(problem.arm, problem.home).tip
    while len(found) < SELF_GOALS and tried < SELF_DRAWS:
        tried += 1
        pose = lo + (hi - lo) * rng.random(problem.arm.n)
        tip = forward(problem.arm, pose).tip
        if tip[2] < base[2] + 0.1 or segment_axis_distance(previous, tip, base) > SELF_THROUGH:
            continue
        if self_gaps(forward(problem.arm, pose), problem.capsules, problem.self_pairs).least < keep:
            continue
        if coal_pair_gaps(problem, pose)[0] >= keep + 1e-6:
            found.append(pose)
            previous = tip
    return found, tried


def self_breaks(problem, trajectory, gaps: np.ndarray) -> list[str]:
    """The invariants a self-collision run breaks: NaN, a joint on or past its limit, a joint turning more
    than max_joint_step, an enabled pair under self_clearance (coal)."""
    phi = trajectory.phi
    if not np.all(np.isfinite(phi)):
        return ["NaN in phi"]
    breaks = []
    lim = problem.limits
    if np.any((phi <= lim.lower) | (phi >= lim.upper)):
        breaks.append("a joint on or past its limit")
    if len(phi) > 1 and np.abs(np.mod(np.diff(phi, axis=0) + np.pi, 2 * np.pi) - np.pi).max() > problem.solver.max_joint_step + ROUNDING:
        breaks.append("a joint turned more than max_joint_step")
    if gaps.min() < problem.self_pairs.clearance - ROUNDING:
        breaks.append(f"an enabled pair {gaps.min():.3g} apart (self_clearance {problem.self_pairs.clearance:g})")
    return breaks


def self_family(args) -> int:
    """``--family self``: per robot and method, goals reached (of the oracle-feasible ones), frames with
    an enabled pair under self_clearance and invariants broken, with self_collision auto and off, and
    the CPU time per frame of each."""
    import tempfile

    from armanim.world.selfdistances import SelfPairs

    rows: dict = defaultdict(lambda: Counter())
    broken = 0
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        (folder / "chain.urdf").write_text(chain_urdf_text())
        for k in range(args.scenes):
            robot = SELF_ROBOTS[k % len(SELF_ROBOTS)]
            rng = np.random.default_rng([args.seed, k, SELF_STREAM])
            base = self_scene_problem(robot, folder, [[0.4, 0.0, 0.4]])
            poses, tried = draw_self_goals(base, rng)
            if not poses:
                print(f"scene {k} ({robot}): no goal crossing the body in {tried} draws", file=sys.stderr)
                continue
            tips = forward(base.arm, np.array(poses)).tip
            problem = self_scene_problem(robot, folder, [[float(v) for v in t] for t in tips])
            for method in args.methods:
                on = replace(problem, solver=replace(problem.solver, method=method))
                for mode, prob in (("auto", on), ("off", replace(on, self_pairs=SelfPairs.none()))):
                    solution, _, _, cpu = timed_solve(prob)
                    gaps = coal_pair_gaps(problem, solution.trajectory.phi)
                    row = rows[(robot, method, mode)]
                    row["goals"] += len(poses)
                    row["reached"] += solution.reached
                    row["frames"] += solution.trajectory.frames
                    row["under"] += int((gaps < problem.self_pairs.clearance - ROUNDING).sum())
                    row["cpu_us"] += int(cpu * 1e6)
                    if mode == "auto":
                        found = self_breaks(problem, solution.trajectory, gaps)
                        row["breaks"] += len(found)
                        broken += len(found)
            print(f"[{k + 1}/{args.scenes}] scene {k} ({robot}, {len(poses)} goals crossing the body, {tried} draws)", file=sys.stderr, flush=True)
    print(f"motion_bench --family self --seed {args.seed} --scenes {args.scenes} --methods {','.join(args.methods)} --planner auto")
    header = ["robot", "method", "reached (auto)", "frames under (auto)", "broken", "ms/frame (auto)",
              "reached (off)", "frames under (off)", "ms/frame (off)", "time ratio"]
    table = []
    for robot in SELF_ROBOTS:
        for method in args.methods:
            a, o = rows.get((robot, method, "auto")), rows.get((robot, method, "off"))
            if not a:
                continue
            ms_a, ms_o = a["cpu_us"] / 1e3 / a["frames"], o["cpu_us"] / 1e3 / o["frames"]
            table.append([robot, method, f"{a['reached']}/{a['goals']}", f"{a['under']}/{a['frames']}", str(a["breaks"]),
                          f"{ms_a:.2f}", f"{o['reached']}/{o['goals']}", f"{o['under']}/{o['frames']}", f"{ms_o:.2f}", f"{ms_a / ms_o:.2f}"])
    print_table(header, table)
    print("\nframe cost of the enabled pairs on the bundled scenes (CPU ms per frame, best of 3; issue 35's bar: 1.5x)")
    print_table(["scene", "enabled pairs", "ms/frame (auto)", "ms/frame (off)", "ratio"], bundled_frame_costs())
    if broken:
        print(f"{broken} invariant(s) broken", file=sys.stderr)
    return 1 if broken else 0


BUNDLED_SCENES = ("panda-place", "panda-clutter", "panda-shelf", "ur5-table", "ur5-pen", "ur5-around", "iiwa-redundancy")


def bundled_frame_costs(rounds: int = 3) -> list[list[str]]:
    """CPU time per frame of each bundled robot scene with ``self_collision`` auto and off."""
    from armanim.scene.loader import load_scene
    from armanim.world.selfdistances import SelfPairs

    rows = []
    for name in BUNDLED_SCENES:
        problem = scene_to_problem(load_scene(Path(__file__).resolve().parent.parent / "scenes" / f"{name}.yaml").model)
        best = {}
        for mode, prob in (("auto", problem), ("off", replace(problem, self_pairs=SelfPairs.none()))) * rounds:
            solution, _, _, cpu = timed_solve(prob)
            best[mode] = min(best.get(mode, np.inf), cpu / solution.trajectory.frames)
        rows.append([name, str(len(set(problem.self_pairs.names))), f"{best['auto'] * 1e3:.2f}", f"{best['off'] * 1e3:.2f}",
                     f"{best['auto'] / best['off']:.2f}"])
    return rows


def report_progress(result: SceneResult, done: int, total: int, began: float) -> None:
    """One line on stderr per finished scene."""
    feasible = sum(v.feasible for v in result.verdicts)
    reached = " ".join(f"{run.method[:2]}/{run.planner}:{sum(v.feasible and ok for v, ok in zip(result.verdicts, run.reached))}"
                       for run in result.runs)
    print(f"[{done}/{total} {time.perf_counter() - began:6.1f}s] scene {result.index} ({result.kind}, "
          f"{len(result.verdicts)} goals, {feasible} feasible) {reached}", file=sys.stderr, flush=True)


if __name__ == "__main__":
    sys.exit(main())
