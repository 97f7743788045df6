"""The robots' oracle (issue 20): a bundled URDF arm's tool point and link frames from
pinocchio, armanim's capsule data placed by those frames, the smallest clearance of either kind
of geometry, and coal's distances between the enabled self-collision pairs (issue 35).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from armanim.arm.kinematics import forward
from armanim.scene import scene_model
from armanim.scene.robots import bundled_robot
from oracles.geometry import (
    NO_SOLIDS,
    Geometry,
    Solids,
    capsule_clearances,
    coal_capsule,
    has_obstacles,
    joint_points,
    solid_gaps,
)


def min_clearance(geo: Geometry, phi: np.ndarray) -> np.ndarray:
    """Smallest capsule clearance of one pose or a batch, shape (...); +inf without spheres."""
    if isinstance(geo, RobotGeometry):
        phi = np.asarray(phi, dtype=float)
        return geo.clearances(phi).min(axis=(-1, -2)) if has_obstacles(geo) else np.full(phi.shape[:-1], np.inf)
    points = joint_points(geo, phi)
    if not has_obstacles(geo):
        return np.full(points.shape[:-2], np.inf)
    return capsule_clearances(geo, points).min(axis=(-1, -2))


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


def robot_geometry(
    robot: str,
    centers: np.ndarray,
    radii: np.ndarray,
    tolerance: float = ROBOT_SOLVER["tolerance"],
    clearance: float = ROBOT_SOLVER["clearance"],
) -> RobotGeometry:
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
        robot=robot,
        model=model,
        tip_frame=tip_frame,
        cap_frames=tuple(model.getFrameId(c.link) for c in keep),
        cap_a=np.array([c.start for c in keep], dtype=float),
        cap_b=np.array([c.end for c in keep], dtype=float),
        cap_r=np.array([c.radius for c in keep], dtype=float),
        lower=lower,
        upper=upper,
        cap_first=np.array([model.frames[model.getFrameId(c.link)].parentJoint == 1 for c in keep]),
        centers=np.asarray(centers, dtype=float).reshape(-1, 3),
        radii=np.asarray(radii, dtype=float),
        home=home,
        base=np.zeros(3),
        reach=1.1 * far,
        tolerance=tolerance,
        clearance=clearance,
    )


_ROBOT_MODELS: dict = {}


def robot_model(robot: str):
    """pinocchio's model of a bundled robot's URDF, and the robot's capsule data as armanim reads it."""
    if robot not in _ROBOT_MODELS:
        import pinocchio as pin

        full = pin.buildModelFromUrdf(str(bundled_robot(robot).urdf))
        scene = scene_model({"version": 1, "name": "probe", "arm": {"robot": robot}, "goals": [[0.3, 0.0, 0.4]]})
        robot_arm = scene.arm.urdf_arm  # the chain's joint names and the capsule data, as the scene reads them
        off_chain = [
            j for j in range(1, full.njoints) if full.names[j] not in robot_arm.joint_names
        ]  # e.g. Panda's fingers
        model = pin.buildReducedModel(full, off_chain, pin.neutral(full)) if off_chain else full
        assert list(model.names)[1:] == list(robot_arm.joint_names), (
            f"{robot}: pinocchio's joints differ from the chain's"
        )
        assert model.nq == model.nv, f"{robot}: a joint with nq != nv (continuous) is not handled here"
        assert not robot_arm.fallback_links, f"{robot}: fallback capsules are not modelled by the oracle"
        _ROBOT_MODELS[robot] = (model, robot_arm.capsules)
    return _ROBOT_MODELS[robot]


_BASE_GEOMETRY: dict = {}


def base_geometry(robot: str) -> RobotGeometry:
    """The robot's geometry without spheres (cached: its reach takes 400 poses to find)."""
    if robot not in _BASE_GEOMETRY:
        _BASE_GEOMETRY[robot] = robot_geometry(robot, np.zeros((0, 3)), np.zeros(0))
    return _BASE_GEOMETRY[robot]


def tip_of(geo, phi: np.ndarray) -> np.ndarray:
    """The tip of one pose or a batch, for either kind of geometry."""
    return geo.tip(phi) if isinstance(geo, RobotGeometry) else joint_points(geo, phi)[..., -1, :]


def coal_pair_gaps(problem, phi: np.ndarray, which: np.ndarray | None = None) -> np.ndarray:
    """(F,) the least gap of any enabled pair (or of the enabled pairs ``which`` indexes) at each
    pose, by coal (capsules placed by the arm's forward kinematics; coal measures the distance)."""
    import coal

    from armanim.arm.capsules import capsule_ends

    pairs, caps = problem.self_pairs, problem.capsules
    first, second = np.asarray(pairs.first), np.asarray(pairs.second)
    if which is not None:
        first, second = first[which], second[which]
    a, b = capsule_ends(caps, forward(problem.arm, np.atleast_2d(phi)))
    out = np.full(len(a), np.inf)
    request = coal.DistanceRequest()
    used = sorted(set(first.tolist()) | set(second.tolist()))
    for f in range(len(a)):
        shapes = {k: coal_capsule(a[f, k], b[f, k], float(caps.radius[k])) for k in used}
        for i, j in zip(first, second):
            result = coal.DistanceResult()
            out[f] = min(out[f], coal.distance(*shapes[i], *shapes[j], request, result))
    return out
