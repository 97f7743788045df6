"""Scene (validated, degrees) -> Problem (radians, numpy): the one place degrees become radians.

The scene model is also the one place defaults are written: the core's settings have
none, and code that wants the defaults without a scene file (tests, benchmarks, the
command line's arm flags) builds them here, through the model (:func:`default_solver_settings`,
:func:`default_render_settings`, :func:`armanim.scene.limits.unlimited_limits`).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import cast

import numpy as np

from armanim.arm.capsules import BASE, Capsules, frame_capsules, joint_capsules
from armanim.arm.chain import SerialChain, serial_chain, transform
from armanim.arm.geometry import unit_vector, wrap_angle
from armanim.arm.gripper import Gripper
from armanim.arm.kinematics import Arm, default_axes, forward, joints_in_si
from armanim.arm.rotations import axis_angle_rotation, quaternion_rotation, rpy_rotation
from armanim.arm.visuals import LinkPlaces
from armanim.motion.carry import finger_holds
from armanim.motion.orientation import Orientation
from armanim.motion.problem import (
    Goal,
    Limits,
    Problem,
    SolverSettings,
)
from armanim.motion.toolpath import Piece, ToolPath
from armanim.render.settings import RenderSettings
from armanim.scene.armmodel import LINKS_WIDTH, ArmModel
from armanim.scene.limits import joint_limits, rate_limits
from armanim.scene.models import (
    GoalModel,
    OrientationModel,
    PathModel,
    RenderModel,
    SceneModel,
    SolverModel,
)
from armanim.scene.robots import bundled_matrix, default_held_value
from armanim.scene.text import text_path
from armanim.world import selfcollision
from armanim.world.obstacles import BOX, CYLINDER, FLOOR, ROD, SPHERE, Boxes, Cylinders, Obstacles, Rods
from armanim.world.selfdistances import SelfPairs


def axis_names(scene: SceneModel) -> list[str]:
    """The scene's joint axes, or the contract's default (z, then y)."""
    return list(scene.arm.axes) if scene.arm.axes is not None else default_axes(len(scene.arm.links or ()))


def home_degrees(arm: ArmModel) -> list[float]:
    """``arm.home``, or the bundled robot's, or all zeros (degrees)."""
    if arm.home is not None:
        return list(arm.home)
    bundled = arm.urdf_arm.bundled if arm.is_urdf else None
    return list(bundled.home) if bundled is not None else [0.0] * arm.joint_count


def urdf_mount(arm: ArmModel) -> np.ndarray:
    """(4, 4) the URDF arm's base link in the world: ``base`` and ``base_rpy`` (degrees)."""
    zero = [0.0, 0.0, 0.0]
    return transform(arm.base or zero, np.radians(arm.base_rpy or zero))


def tool_frame(tool) -> np.ndarray:
    """(4, 4) the tool frame in the tip link's (``arm.tool``: ``xyz`` metres, ``rpy`` degrees; None:
    the tip link's own frame)."""
    return transform(tool.xyz, np.radians(tool.rpy)) if tool is not None else np.eye(4)


def urdf_chain(arm: ArmModel) -> SerialChain:
    """The URDF arm's chain, placed by ``base`` and ``base_rpy`` and ended by ``tool``."""
    mount = urdf_mount(arm)
    tool = tool_frame(arm.tool)
    chain = serial_chain(mount, list(arm.urdf_arm.joints), tool)
    if chain.arm.prismatic is None:
        return chain
    limits = joint_limits(arm)  # a prismatic joint's reach: its larger limit in size
    stroke = np.where(chain.arm.prismatic, np.maximum(np.abs(limits.lower), np.abs(limits.upper)), 0.0)
    return replace(chain, arm=replace(chain.arm, stroke=stroke))


def held_values(arm: ArmModel) -> dict[str, float]:
    """The value of every joint held off the URDF arm's chain (radians, or metres for a prismatic
    joint): ``arm.joint_values`` (degrees become radians here), else 0 if its limits allow it,
    else its lower limit; a mimic joint follows the joint it mimics (multiplier x value + offset)."""
    robot = arm.urdf_arm
    given = arm.joint_values or {}
    values = {}
    for joint in robot.held:
        if joint.follows is None:
            value = given.get(joint.name)
            values[joint.name] = (
                default_held_value(joint)
                if value is None
                else float(value)
                if joint.kind == "prismatic"
                else float(np.radians(value))
            )
    for joint in robot.held:
        if joint.follows is not None:
            other, multiplier, offset = joint.follows
            values[joint.name] = multiplier * values[other] + offset
    return values


def joint_motion(joint, value: float) -> np.ndarray:
    """(4, 4) a URDF joint's transform from its parent link to its child at ``value`` (radians, or
    metres for a prismatic joint; a fixed, floating or planar joint: its origin alone)."""
    motion = np.eye(4)
    if joint.kind == "prismatic":
        motion[:3, 3] = unit_vector(joint.axis) * value
    elif joint.kind in ("revolute", "continuous"):
        motion[:3, :3] = axis_angle_rotation(joint.axis, value)
    return cast(np.ndarray, joint.origin @ motion)


def link_places(arm: ArmModel, chain: SerialChain) -> LinkPlaces:
    """Where every link of the URDF arm's body sits: (carrier, (4, 4) its frame in the carrier's
    frame). The carrier is the moving joint whose frame carries it, or :data:`~armanim.arm.capsules.BASE`
    for the base link and what is fixed to it (their frames then in the world); links off the
    path hang from theirs at the held joint values (:func:`held_values`)."""
    robot = arm.urdf_arm
    places = {robot.base_link: (BASE, urdf_mount(arm))}
    places.update(
        {link: (carrier, place) for link, carrier, place in zip(robot.path_links, chain.carriers, chain.link_offsets)}
    )
    values = held_values(arm)
    for hanging in robot.hanging:
        carrier, place = places[hanging.anchor]
        for joint in hanging.joints:
            place = place @ joint_motion(joint, values.get(joint.name, 0.0))
        places[hanging.link] = (carrier, place)
    return places


def urdf_gripper(arm: ArmModel, chain: SerialChain, capsules: Capsules) -> Gripper | None:
    """The URDF arm's gripper (:class:`~armanim.arm.gripper.Gripper`): its one prismatic joint held
    off the chain that is no mimic, with limits and a velocity limit, and the prismatic joints that
    mimic it; each capsule's displacement per metre of it in its carrier's frame (``capsules``, as
    :func:`urdf_capsules` made them). None without exactly one such joint (the fingers then stay
    where ``arm.joint_values`` holds them)."""
    robot = arm.urdf_arm
    drivers = [j for j in robot.held if j.kind == "prismatic" and j.follows is None and j.limits is not None]
    if len(drivers) != 1 or not drivers[0].velocity:
        return None
    driver = drivers[0]
    values = held_values(arm)
    places = link_places(arm, chain)
    moves: dict[str, np.ndarray] = {}
    for hanging in robot.hanging:
        place, rate = places[hanging.anchor][1], np.zeros(3)
        for joint in hanging.joints:
            before = place @ joint.origin
            if joint.name == driver.name:
                rate = rate + before[:3, :3] @ unit_vector(joint.axis)
            elif joint.kind == "prismatic" and joint.follows is not None and joint.follows[0] == driver.name:
                rate = rate + before[:3, :3] @ unit_vector(joint.axis) * joint.follows[1]
            place = place @ joint_motion(joint, values.get(joint.name, 0.0))
        if np.any(rate):
            moves[hanging.link] = rate
    if not moves:
        return None
    rate = np.zeros((len(capsules.radius), 3))
    for i, spec in enumerate(robot.capsules):
        rate[i] = moves.get(spec.link, 0.0)
    span = 1.0 + sum(
        j.follows[1]
        for j in robot.held
        if j.kind == "prismatic" and j.follows is not None and j.follows[0] == driver.name
    )
    assert driver.limits is not None and driver.velocity is not None  # a driver has both (drivers above)
    lower, upper = driver.limits
    return Gripper(
        driver.name,
        float(lower),
        float(upper),
        float(driver.velocity),
        float(values[driver.name]),
        rate,
        float(span),
        tuple(moves),
        np.array(list(moves.values())).reshape(-1, 3),
    )


def urdf_capsules(arm: ArmModel, chain: SerialChain) -> Capsules:
    """The URDF arm's capsules moved into the frames of the joints that carry them (the base
    link's and what is fixed before the first moving joint: into the world, carrier
    :data:`~armanim.arm.capsules.BASE`; links off the path at their held joint values), a
    joint-to-joint capsule of radius width / 2 for each moving link without one, and the tool's
    capsule (``arm.tool.collision``), named after the link whose joint carries the tip."""
    robot = arm.urdf_arm
    places = link_places(arm, chain)
    links, starts, ends, radii, names = [], [], [], [], []
    for spec in robot.capsules:
        carrier, place = places[spec.link]
        links.append(carrier)
        starts.append(place[:3, :3] @ spec.start + place[:3, 3])
        ends.append(place[:3, :3] @ spec.end + place[:3, 3])
        radii.append(spec.radius)
        names.append(spec.link)
    for link in robot.fallback_links:
        carrier = chain.carriers[robot.path_links.index(link)]
        links.append(carrier)
        starts.append(np.zeros(3))
        ends.append(chain.arm.offsets[carrier])
        radii.append(arm.resolved_width / 2.0)
        names.append(link)
    if arm.tool is not None and arm.tool.collision is not None:  # checked as a part of the link that carries the tip
        tool, place = arm.tool.collision, chain.link_offsets[-1] @ tool_frame(arm.tool)
        links.append(chain.carriers[-1])
        starts.append(place[:3, :3] @ np.asarray(tool.from_) + place[:3, 3])
        ends.append(place[:3, :3] @ np.asarray(tool.to) + place[:3, 3])
        radii.append(float(tool.radius))
        names.append(robot.path_links[chain.carriers.index(chain.carriers[-1])])
    return frame_capsules(chain.arm, links, np.reshape(starts, (-1, 3)), np.reshape(ends, (-1, 3)), radii, tuple(names))


def scene_arm(arm: ArmModel, axes: list[str]) -> tuple[Arm, Capsules | None]:
    """The scene's arm and its capsules (None: today's joint-to-joint capsules)."""
    if not arm.is_urdf:
        assert arm.links is not None, "an arm of links has its links (ArmModel)"
        return Arm.from_names(
            arm.links, base=arm.base or (0.0, 0.0, 0.0), axes=axes, direction=arm.direction or "z"
        ), None
    chain = urdf_chain(arm)
    return chain.arm, urdf_capsules(arm, chain)


@dataclass(frozen=True)
class ConvertedScene:
    """A validated scene converted once (:func:`convert_scene`).

    Attributes
    ----------
    problem : Problem
        The solver's problem.
    places : dict or None
        Where each link of a URDF robot sits on ``problem.arm``'s joints
        (:data:`armanim.arm.visuals.LinkPlaces`, :func:`link_places`), made from the same chain
        as the problem's arm: the pictures place the robot's meshes by it. None for an arm of links.
    """

    problem: Problem
    places: LinkPlaces | None = None


def scene_obstacles(scene: SceneModel) -> Obstacles:
    """The scene's obstacles in the scene's order (box and cylinder angles become a rotation here), the floor last."""
    if not scene.obstacles and scene.floor is None:
        return Obstacles.none()
    spheres = [o for o in scene.obstacles if o.kind == "sphere"]
    boxes = [o.box for o in scene.obstacles if o.kind == "box" and o.box is not None]
    rods = [o.capsule for o in scene.obstacles if o.kind == "capsule" and o.capsule is not None]
    cylinders = [o.cylinder for o in scene.obstacles if o.kind == "cylinder" and o.cylinder is not None]
    kinds = [{"sphere": SPHERE, "box": BOX, "capsule": ROD, "cylinder": CYLINDER}[o.kind] for o in scene.obstacles]
    influence = [o.resolved_influence for o in scene.obstacles]
    if scene.floor is not None:
        kinds.append(FLOOR)
        influence.append(0.0)  # the floor has no field: the safety filter alone keeps it
    return Obstacles(
        centers=np.array([o.center for o in spheres], dtype=float).reshape(-1, 3),
        radii=np.array([o.radius for o in spheres], dtype=float),
        influence=np.array(influence, dtype=float),
        boxes=Boxes(
            centers=np.array([b.center for b in boxes], dtype=float).reshape(-1, 3),
            half=np.array([b.size for b in boxes], dtype=float).reshape(-1, 3) / 2.0,
            rotations=np.array([rpy_rotation(np.radians(b.rpy)) for b in boxes]).reshape(-1, 3, 3),
        ),
        rods=Rods(
            start=np.array([r.from_ for r in rods], dtype=float).reshape(-1, 3),
            end=np.array([r.to for r in rods], dtype=float).reshape(-1, 3),
            radius=np.array([r.radius for r in rods], dtype=float),
        ),
        floor=float(scene.floor) if scene.floor is not None else None,
        kinds=np.array(kinds, dtype=int),
        cylinders=Cylinders(
            centers=np.array([c.center for c in cylinders], dtype=float).reshape(-1, 3),
            rotations=np.array([rpy_rotation(np.radians(c.rpy)) for c in cylinders]).reshape(-1, 3, 3),
            half_length=np.array([c.length for c in cylinders], dtype=float) / 2.0,
            radius=np.array([c.radius for c in cylinders], dtype=float),
        ),
        names=tuple(o.name for o in scene.obstacles) if any(o.name is not None for o in scene.obstacles) else (),
    )


CLEARANCE_PER_WIDTH = 0.1
"""Default ``solver.clearance`` as a fraction of ``arm.width``: a tenth of the arm's thickness."""


def clearance(solver: SolverModel, width: float) -> float:
    """d_safe: the scene's ``solver.clearance``, or ``arm.width / 10``."""
    return float(solver.clearance) if solver.clearance is not None else CLEARANCE_PER_WIDTH * width


DEFAULT_REACH = 17.0
"""The reach :func:`default_solver_settings` resolves the orientation weight with: the course
notes' arm (links 2, 5, 5, 5)."""

ORIENTATION_WEIGHT_PER_REACH = 0.25
"""Default ``solver.orientation_weight`` as a fraction of the arm's reach (length per radian):
a radian of tool rotation weighs like a quarter of the arm's length, about how far a radian
of a wrist joint moves a point at the middle of the forearm. It scales with the arm, so the
notes' arm (reach 17) and a 1 m robot balance position and orientation alike."""


def orientation_weight(solver: SolverModel, reach: float) -> float:
    """w: the scene's ``solver.orientation_weight``, or the arm's reach / 4."""
    return (
        float(solver.orientation_weight)
        if solver.orientation_weight is not None
        else ORIENTATION_WEIGHT_PER_REACH * reach
    )


def solver_settings(s: SolverModel, width: float, reach: float = DEFAULT_REACH) -> SolverSettings:
    """The scene's ``solver`` section as the solvers' settings (radians; ``width`` and ``reach``
    are the arm's, for the default clearance and orientation weight). ``solver.step`` becomes ``beta``."""
    return SolverSettings(
        method=s.method,
        beta=s.step,
        max_step=s.max_step if s.max_step is not None else np.inf,
        tolerance=s.tolerance,
        max_frames_per_goal=s.max_frames_per_goal,
        jacobian=s.jacobian,
        damping=s.damping,
        max_joint_step=float(np.radians(s.max_joint_step)),
        max_slide_step=float(s.max_slide_step),
        clearance=clearance(s, width),
        planner=s.planner,
        w_goal=s.weights.goal,
        w_obstacles=s.weights.obstacles,
        w_limits=s.weights.limits,
        w_target=s.weights.target,
        w_regularizer=s.weights.regularizer,
        orientation_weight=orientation_weight(s, reach),
        orientation_tolerance=float(np.radians(s.orientation_tolerance)),
        joint_tolerance=float(np.radians(s.joint_tolerance)),
        path_tolerance=float(s.path_tolerance) if s.path_tolerance is not None else s.tolerance,
    )


SELF_CLEARANCE_PER_CLEARANCE = 0.5
"""Default ``solver.self_clearance`` as a fraction of ``solver.clearance``."""


def self_clearance(solver: SolverModel, d_safe: float) -> float:
    """The scene's ``solver.self_clearance``, or ``solver.clearance / 2``."""
    return float(solver.self_clearance) if solver.self_clearance is not None else SELF_CLEARANCE_PER_CLEARANCE * d_safe


def self_pairs(
    arm: ArmModel, chain: Arm, capsules: Capsules, limits: Limits, home: np.ndarray, clearance: float
) -> SelfPairs:
    """The enabled pairs of the arm's own capsules (:mod:`armanim.world.selfcollision`): ``off``,
    an SRDF's pairs allowed and, where it says nothing, MoveIt's ``Adjacent`` and ``Always`` rules
    (every other pair of links on different joints checked), or MoveIt's rules (a bundled robot's
    committed matrix when its capsules and limits are its own and the clearance is within the
    matrix's), then the scene's ``allow`` and ``check`` lists."""
    spec = arm.self_collision
    if spec == "off":
        return SelfPairs.none(clearance)
    allow = [] if isinstance(spec, str) else [(a, b) for a, b in spec.allow]
    check = [] if isinstance(spec, str) else [(a, b) for a, b in spec.check]
    if not isinstance(spec, str) and spec.srdf is not None:  # MoveIt's rules where the SRDF says nothing
        listed = {(a, b): reason for a, b, reason in arm.srdf_pairs}
        allowed = dict(
            _sampled_matrix(
                chain,
                capsules,
                limits.lower,
                limits.upper,
                (),
                clearance,
                (selfcollision.ADJACENT, selfcollision.ALWAYS),
                tuple(listed),
            )
        )
        allowed.update(listed)
        mode = "srdf"
    else:
        allowed = _automatic_matrix(arm, chain, capsules, limits, home, clearance)
        mode = "auto"
    allowed.update({pair: selfcollision.USER for pair in allow})
    return selfcollision.enabled_pairs(capsules, allowed, clearance, mode, check)


def _automatic_matrix(
    arm: ArmModel, chain: Arm, capsules: Capsules, limits: Limits, home: np.ndarray, clearance: float
) -> dict:
    """MoveIt's rules: the bundled robot's committed matrix when it applies, else sampled here."""
    bundled = arm.urdf_arm.bundled if arm.is_urdf else None
    if bundled is not None and arm.collision is None and arm.limits is None:
        matrix = bundled_matrix(bundled.name)
        if matrix is not None and clearance <= matrix.clearance:
            return {(a, b): reason for a, b, reason in matrix.allowed}
    defaults = [joints_in_si(np.array(bundled.home, dtype=float), chain.prismatic) if bundled is not None else home]
    if arm.is_urdf and bundled is None:  # a bundled robot's default is its home (its robot.yaml, as MoveIt's "ready")
        defaults.append(selfcollision.default_pose(limits.lower, limits.upper))
    return dict(
        _sampled_matrix(chain, capsules, limits.lower, limits.upper, tuple(d.tobytes() for d in defaults), clearance)
    )


_MATRICES: dict = {}


def _sampled_matrix(
    chain: Arm,
    capsules: Capsules,
    lower,
    upper,
    defaults: tuple[bytes, ...],
    clearance: float,
    rules: tuple[str, ...] = selfcollision.RULES,
    decided: tuple[tuple[str, str], ...] = (),
):
    """:func:`armanim.world.selfcollision.automatic_matrix`, kept per arm (a run converts its scene more than once)."""
    key = (
        chain.offsets.tobytes(),
        repr(chain.joint_names),
        capsules.link.tobytes(),
        capsules.start.tobytes(),
        capsules.end.tobytes(),
        capsules.radius.tobytes(),
        capsules.names,
        lower.tobytes(),
        upper.tobytes(),
        defaults,
        clearance,
        _axes_key(chain),
        rules,
        decided,
    )
    if key not in _MATRICES:
        poses = [np.frombuffer(d) for d in defaults]
        _MATRICES[key] = tuple(
            selfcollision.automatic_matrix(
                chain, capsules, lower, upper, poses, clearance, rules=rules, decided=decided
            ).items()
        )
    return _MATRICES[key]


def _axes_key(chain: Arm) -> bytes:
    """The parts of an arm's geometry beyond its offsets (axes, fixed rotations), as bytes."""
    return b"".join(np.asarray(v).tobytes() for v in vars(chain).values() if isinstance(v, np.ndarray))


def scene_to_problem(
    scene: SceneModel, fps: float | None = None, *, own_pairs: bool = True, retreats: bool = True
) -> Problem:
    """Convert a validated scene to the solver's problem (radians, numpy arrays): the problem of
    :func:`convert_scene`, whose parameters it takes.

    >>> scene_to_problem(SceneModel.model_validate({"version": 1, "arm": {"links": [1, 1]}, "goals": [[1, 1, 0]]})).arm.n
    2
    """
    return convert_scene(scene, fps, own_pairs=own_pairs, retreats=retreats).problem


def convert_scene(
    scene: SceneModel, fps: float | None = None, *, own_pairs: bool = True, retreats: bool = True
) -> ConvertedScene:
    """Convert a validated scene to the solver's problem (radians, numpy arrays), and a URDF
    robot's link places on its arm (for the pictures' meshes), from one chain.

    Parameters
    ----------
    scene : SceneModel
    fps : float, optional
        Frames per second of the frames the problem describes, when they are not the
        scene's own (a finished run shown at ``run --fps``). The motion is always solved at
        ``render.fps``, then put on the clock at the output rate (:func:`armanim.motion.timing.retime.retime`)
        or, for a finished run, resampled (:func:`armanim.runs.resample.resample_run`).
    own_pairs : bool
        Find the arm's own pairs to keep apart (``arm.self_collision``); False leaves them empty,
        for work that never asks (one pose's forward kinematics): an arm of links samples its
        matrix, some 0.4 s of compiled distances on a command that takes 0.3 s without.
    retreats : bool
        Each goal's ``retreat`` becomes a goal of its own after it, and a release's ``approach``
        starts with a goal of its own to the line's start (:func:`with_retreats`); False keeps one
        problem goal per scene goal (validation's messages name the scene's goals).

    Returns
    -------
    ConvertedScene
    """
    arm = scene.arm
    fps = scene.render.fps if fps is None else fps
    serial = (
        urdf_chain(arm) if arm.is_urdf else None
    )  # the one chain of a URDF arm: the problem's arm, its capsules, its links' places
    chain, capsules = (
        (serial.arm, urdf_capsules(arm, serial)) if serial is not None else scene_arm(arm, axis_names(scene))
    )
    solver = solver_settings(scene.solver, arm.resolved_width, chain.reach)
    home = joints_in_si(np.array(home_degrees(arm), dtype=float), chain.prismatic)
    limits = joint_limits(arm)
    every = capsules if capsules is not None else joint_capsules(chain, arm.resolved_width / 2.0)
    goals = tuple(
        handling(unlimited_joints_wrapped(scene_goal(g, chain, scene.solver.blend), limits), g, scene)
        for g in scene.goals
    )
    if retreats:
        goals = with_retreats(goals, scene.goals)
    gripper = None
    if (
        serial is not None and capsules is not None and any(g.grasp is not None for g in goals)
    ):  # the fingers move only in a run that grasps
        gripper = urdf_gripper(arm, serial, capsules)
    problem = Problem(
        arm=chain,
        half_width=arm.resolved_width / 2.0,
        home=home,
        limits=limits,
        obstacles=scene_obstacles(scene),
        goals=finger_holds(goals, gripper),
        solver=solver,
        fps=fps,
        capsules=cast(Capsules, capsules),  # None: the Problem's own default, today's joint-to-joint capsules
        rates=rate_limits(scene),
        self_pairs=(
            self_pairs(arm, chain, every, limits, home, self_clearance(scene.solver, solver.clearance))
            if own_pairs
            else SelfPairs.none(self_clearance(scene.solver, solver.clearance))
        ),
        gripper=gripper,
    )
    return ConvertedScene(problem, link_places(arm, serial) if serial is not None else None)


def orientation_rotation(o: OrientationModel) -> np.ndarray:
    """R_g (3, 3) of a goal's ``orientation`` (degrees become radians here).

    >>> np.round(orientation_rotation(OrientationModel(rpy=[0, 0, 90])) @ [1, 0, 0], 12) + 0.0
    array([0., 1., 0.])
    """
    if o.rpy is not None:
        return rpy_rotation(np.radians(o.rpy))
    if o.quaternion_wxyz is not None:
        return quaternion_rotation(o.quaternion_wxyz)
    assert o.axis is not None and o.angle is not None, "an orientation has one form (OrientationModel)"
    return axis_angle_rotation(o.axis, np.radians(o.angle))


def orientation_flag(form: str, values: list[float]) -> Orientation:
    """``ik --orientation FORM=VALUES`` (``rpy``, ``quat``, ``axis`` with the angle last, or
    ``tool_axis``; degrees) as an :class:`Orientation`, checked by the scene's own models and
    converted as a goal's ``orientation`` is.

    Raises
    ------
    pydantic.ValidationError
        The values are not an orientation (a zero axis, a quaternion far from unit length, ...).

    >>> orientation_flag("axis", [0, 0, 1, 90]).rotation.round(12).tolist()[0]
    [0.0, -1.0, 0.0]
    """
    if form == "tool_axis":
        GoalModel(position=[0.0, 0.0, 0.0], tool_axis=values)
        return Orientation(axis=np.array(values))
    fields = (
        {"rpy": values}
        if form == "rpy"
        else {"quaternion_wxyz": values}
        if form == "quat"
        else {"axis": values[:3], "angle": values[3]}
    )
    return Orientation(rotation=orientation_rotation(OrientationModel(**fields)))


def radians(degrees):
    """Angles in degrees (a number or an array), as a scene or ``fk``'s and ``ik``'s flags give
    them, in radians: the flags' angles take the scene's own conversion, here.

    >>> float(radians(180.0)), radians(np.array([90.0, -45.0])).tolist()
    (3.141592653589793, [1.5707963267948966, -0.7853981633974483])
    """
    return np.radians(degrees)


def scene_goal(goal: GoalModel, chain: Arm | None = None, blend: float | None = None) -> Goal:
    """A goal of the scene as the solver's: a point goal, a path goal whose position is its
    path's start (the arm goes there as to a point, then follows the path), or a joint goal
    (radians) whose position is its tool point on ``chain`` (which a joint goal needs). ``blend``:
    ``solver.blend``, the radius of a point or joint goal that sets none (a path goal never blends).

    >>> g = scene_goal(GoalModel(path={"line": [[0, 0, 0], [0.3, 0.4, 0]]}, speed=0.1))
    >>> g.position.tolist(), g.path.length, g.speed
    ([0.0, 0.0, 0.0], 0.5, 0.1)
    """
    radius = goal.blend if goal.blend is not None else blend
    if goal.joints is not None:
        assert chain is not None, "a joint goal's tool point needs the arm"
        joints = joints_in_si(np.array(goal.joints, dtype=float), chain.prismatic)
        return Goal(
            forward(chain, joints).tip.copy(),
            goal.hold,
            joints=joints,
            blend=None if radius is None else float(np.radians(min(radius, 180.0))),
        )
    if goal.path is None:
        return Goal(np.array(goal.position, dtype=float), goal.hold, goal_orientation(goal), blend=radius)
    path = tool_path(goal.path)
    assert goal.speed is not None, "a path goal's speed is required (GoalModel)"
    return Goal(path.start.copy(), goal.hold, goal_orientation(goal), path=path, speed=float(goal.speed))


def handling(goal: Goal, model: GoalModel, scene: SceneModel) -> Goal:
    """``goal`` with what it grasps (the named obstacle's clearance column: the scene's order) or
    releases (:mod:`armanim.motion.carry`); a goal that does neither, unchanged."""
    if model.grasp is not None or model.release:
        names = [o.name for o in scene.obstacles]
        column = names.index(model.grasp) if model.grasp is not None and model.grasp in names else None
        touch = tuple(model.touch_links) if model.touch_links is not None else None
        goal = replace(goal, grasp=column, release=model.release, touch_links=touch)
    if model.approach is None or goal.path is not None or goal.joints is not None:
        return goal
    direction = approach_direction(model)
    if direction is None:
        return goal  # validation reports it (an approach along the tool needs the tool's orientation)
    start = goal.position - model.approach.distance * direction
    speed = model.approach.speed if model.approach.speed is not None else model.approach.distance
    return replace(goal, position=start, path=ToolPath.polyline(np.array([start, goal.position])), speed=float(speed))


def with_retreats(goals: tuple[Goal, ...], models: list[GoalModel]) -> tuple[Goal, ...]:
    """``goals`` (one per scene goal ``models``) with, after each goal that gives a ``retreat``,
    its straight line out as a path goal of its own (:attr:`Goal.retreat`): from where the goal
    ends (its position, or its approach's end) ``distance`` along the retreat's direction
    (:func:`retreat_direction`), the goal's orientation held, at ``speed`` (default ``distance``
    per second); a retreat validation refuses (on a path or joint goal, along the tool without an
    orientation) adds nothing. Before each release whose ``approach`` is a line, a goal to the
    line's start, the release's orientation (:attr:`Goal.to_approach`): the object may touch what
    it is put on only along the line (:mod:`armanim.motion.carry`)."""
    out = []
    for goal, model in zip(goals, models):
        if goal.release and model.approach is not None and goal.path is not None and model.path is None:
            out.append(Goal(position=goal.path.start, hold=0.0, orientation=goal.orientation, to_approach=True))
        out.append(goal)
        if model.retreat is None or model.path is not None or goal.joints is not None:
            continue
        direction = retreat_direction(model)
        if direction is None:
            continue
        start = goal.path.end if goal.path is not None else goal.position
        speed = model.retreat.speed if model.retreat.speed is not None else model.retreat.distance
        end = start + model.retreat.distance * direction
        out.append(
            Goal(
                position=start,
                hold=0.0,
                orientation=goal.orientation,
                path=ToolPath.polyline(np.array([start, end])),
                speed=float(speed),
                retreat=True,
            )
        )
    return tuple(out)


def retreat_direction(model: GoalModel) -> np.ndarray | None:
    """The unit direction a goal's ``retreat`` moves the tool along (world): back along the tool's
    z at the goal, or the given vector; None for a retreat along the tool of a goal without orientation.

    >>> (retreat_direction(GoalModel(position=[0, 0, 0], orientation={"rpy": [180, 0, 0]}, retreat={"distance": 0.1})).round(12) + 0.0).tolist()
    [0.0, 0.0, 1.0]
    """
    assert model.retreat is not None
    axis = model.retreat.axis
    if not isinstance(axis, str):
        return unit_vector(np.array(axis, dtype=float))
    if model.orientation is not None:
        return -orientation_rotation(model.orientation)[:, 2]
    if model.tool_axis is not None:
        return -unit_vector(np.array(model.tool_axis, dtype=float))
    return None


def approach_direction(model: GoalModel) -> np.ndarray | None:
    """The unit direction a goal's ``approach`` moves the tool along (world): the tool's z at the
    goal, or the given vector; None for an approach along the tool of a goal without orientation.

    >>> approach_direction(GoalModel(position=[0, 0, 0], release=True, approach={"distance": 0.1, "axis": [0, 0, -2]})).tolist()
    [0.0, 0.0, -1.0]
    """
    assert model.approach is not None
    axis = model.approach.axis
    if not isinstance(axis, str):
        return unit_vector(np.array(axis, dtype=float))
    if model.orientation is not None:
        return orientation_rotation(model.orientation)[:, 2]
    if model.tool_axis is not None:
        return unit_vector(np.array(model.tool_axis, dtype=float))
    return None


def unlimited_joints_wrapped(goal: Goal, limits: Limits) -> Goal:
    """``goal`` with a joint goal's unlimited joints in (-pi, pi], as the frames keep them (a
    continuous joint at 270 degrees is the same pose as at -90).

    >>> from armanim.motion.problem import Limits
    >>> g = unlimited_joints_wrapped(Goal(np.zeros(3), 0.0, joints=np.radians([270.0, 270.0])), Limits(np.array([-5.0, -np.inf]), np.array([5.0, np.inf]), 0.1))
    >>> np.degrees(g.joints).round(9).tolist()
    [270.0, -90.0]
    """
    if goal.joints is None:
        return goal
    return replace(goal, joints=np.where(limits.limited, goal.joints, wrap_angle(goal.joints)))


def tool_path(path: PathModel) -> ToolPath:
    """A path goal's path as a :class:`ToolPath` (an arc's angle becomes radians here).

    >>> arc = tool_path(PathModel(arc={"center": [0, 0, 0], "start": [1, 0, 0], "angle": -90, "normal": [0, 0, 2]}))
    >>> np.round(arc.end, 12).tolist(), round(arc.length, 12)
    ([0.0, -1.0, 0.0], 1.570796326795)
    """
    if path.line is not None:
        return ToolPath.polyline(np.array(path.line, dtype=float))
    if path.polyline is not None:
        return ToolPath.polyline(np.array(path.polyline, dtype=float))
    if path.arc is not None:
        a = path.arc
        normal = np.array(a.normal, dtype=float)
        normal = normal / np.max(np.abs(normal))  # a tiny normal's square would underflow
        return ToolPath(
            (
                Piece.arc(
                    np.array(a.center, dtype=float), np.array(a.start, dtype=float), float(np.radians(a.angle)), normal
                ),
            )
        )
    t = path.text
    assert t is not None
    return text_path(
        t.string,
        np.array(t.origin, dtype=float),
        t.height,
        np.array(t.right, dtype=float),
        np.array(t.up, dtype=float),
        t.resolved_lift,
    )


def goal_orientation(goal: GoalModel) -> Orientation | None:
    """A goal's :class:`Orientation` (a rotation or a tool axis), or None for a position-only goal."""
    if goal.orientation is not None:
        return Orientation(rotation=orientation_rotation(goal.orientation))
    if goal.tool_axis is not None:
        return Orientation(axis=np.array(goal.tool_axis, dtype=float))
    return None


def render_settings(scene: SceneModel) -> RenderSettings:
    """The scene's render section as plain settings."""
    return render_section_settings(scene.render)


def render_section_settings(r: RenderModel) -> RenderSettings:
    """A ``render`` section as plain settings (camera angles None where the section leaves them out)."""
    return RenderSettings(
        size=(int(r.size[0]), int(r.size[1])),
        elevation=r.view.elevation if "elevation" in r.view.model_fields_set else None,
        azimuth=r.view.azimuth if "azimuth" in r.view.model_fields_set else None,
        bounds=None if r.bounds == "auto" else np.array(r.bounds, dtype=float),
        trail=r.trail,
        format=r.format,
        robot=r.robot,
    )


def default_solver_settings(**changes) -> SolverSettings:
    """The solver settings of a scene that leaves ``solver`` and ``arm.width`` out, with
    ``changes`` (the settings' own names and units: ``beta``, radians) applied.

    >>> settings = default_solver_settings(method="dls")
    >>> settings.method, settings.beta, settings.clearance
    ('dls', 0.1, 0.05)
    """
    return replace(solver_settings(SolverModel(), LINKS_WIDTH), **changes)


def default_render_settings(**changes) -> RenderSettings:
    """The render settings of a scene that leaves ``render`` out, with ``changes`` applied.

    >>> default_render_settings(size=(320, 240)).size
    (320, 240)
    """
    return replace(render_section_settings(RenderModel()), **changes)
