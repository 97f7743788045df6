"""pydantic v2 models of the scene file (contract version 1), degrees as written.

Every field of ``scene-format.md`` with its default; unknown keys are errors
(``extra="forbid"``) and models are frozen. Checks that involve several fields
(lengths that must agree, the home pose clear of obstacles, ...) are in
:mod:`armanim.scene.checks`, so that every problem is reported at once.
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import (
    ConfigDict,
    Field,
    PrivateAttr,
    WithJsonSchema,
    field_validator,
    model_validator,
)

from armanim.names import JacobianMode, MethodName, PlannerMode, VideoFormat
from armanim.scene.fields import (
    LIMITS,
    MIN_DEGREES,
    MIN_FPS,
    MIN_JOINT_STEP,
    NAME_MAX,
    NAME_PATTERN,
    ROBOTS,
    Angle,
    Angles3,
    AxisName,
    Finite,
    LinkPair,
    NonNegative,
    Positive,
    Side,
    Strict,
    UrdfName,
    Vector3,
    joint_rate,
    name_problem,
)

SCENE_VERSION = 1


class CapsuleModel(Strict):
    """One collision capsule, in its URDF link's frame (metres)."""

    link: Annotated[str, Field(min_length=1, max_length=200)] = Field(description="The URDF link that carries it.")
    from_: Vector3 = Field(alias="from", description="One end of the capsule's segment, in the link's frame.")
    to: Vector3 = Field(description="The other end, in the link's frame (the same point: a sphere).")
    radius: NonNegative = Field(description="Every point within this distance of the segment is the arm's.")


class ToolModel(Strict):
    """The tool frame: the tip, placed in the tip link's frame."""

    xyz: Vector3 = Field(default=[0.0, 0.0, 0.0], description="The tip's position in the tip link's frame (metres).")
    rpy: Angles3 = Field(default=[0.0, 0.0, 0.0], description="The tool frame's roll, pitch, yaw in the tip link's frame, degrees.")



class SelfCollisionModel(Strict):
    """``arm.self_collision`` as a mapping: MoveIt's rules (``auto: true``) or an SRDF, with the
    user's own ``allow`` and ``check`` pairs of links on top."""

    auto: bool | None = Field(default=None, description="true: the allowed-collision matrix by MoveIt's rules (adjacent, default, never).")
    srdf: Annotated[str, Field(min_length=1, max_length=4096)] | None = Field(
        default=None, description="An SRDF file, relative to the scene file: its <disable_collisions link1= link2=/> pairs are allowed."
    )
    allow: Annotated[list[LinkPair], Field(max_length=10_000)] = Field(default=[], description="Link pairs never checked.")
    check: Annotated[list[LinkPair], Field(max_length=10_000)] = Field(default=[], description="Link pairs checked whatever the rules say.")

    @model_validator(mode="after")
    def _one_source(self):
        if (self.auto is True) == (self.srdf is not None):
            raise ValueError("gives " + ("both auto: true and srdf" if self.srdf is not None else "neither auto: true nor srdf")
                             + " (expected one: auto: true for MoveIt's rules, or srdf: FILE)")
        return self


class ArmModel(Strict):
    """The ``arm`` section: straight links (``links``), or a robot from a URDF (``urdf`` or ``robot``)."""

    base: Vector3 | None = Field(
        default=None, description="World position of joint 1 (links) or of base_link (URDF); default the origin."
    )
    links: Annotated[list[Positive], Field(min_length=1, max_length=LIMITS["links"])] | None = Field(
        default=None, description="Link lengths; link i runs from joint i to joint i+1, the last ends at the tip."
    )
    axes: list[AxisName] | None = Field(
        default=None, description="Each joint's rotation axis in its own frame; default z, then y (links only)."
    )
    direction: AxisName | None = Field(default=None, description="Local axis along which every link extends; default z (links only).")
    urdf: Annotated[str, Field(min_length=1, max_length=4096)] | None = Field(
        default=None, description="A URDF file, relative to the scene file: the arm is its chain from base_link to tip_link."
    )
    robot: Annotated[str, Field(min_length=1, max_length=100)] | None = Field(
        default=None, description="A bundled robot (armanim robots lists them): panda, ur5, iiwa."
    )
    base_link: UrdfName | None = Field(default=None, description="The URDF link the arm starts at; default the root (or the robot's).")
    tip_link: UrdfName | None = Field(default=None, description="The URDF link the arm ends at; default the only leaf (or the robot's).")
    base_rpy: Angles3 | None = Field(default=None, description="Roll, pitch, yaw of base_link in the world, degrees; default 0.")
    tool: ToolModel | None = Field(default=None, description="The tip in tip_link's frame; default its origin.")
    collision: Literal["auto"] | Annotated[list[CapsuleModel], Field(max_length=1000)] | None = Field(
        default=None, description="auto (the URDF's primitives, or the robot's capsules), or a list of capsules."
    )
    home: list[Angle] | None = Field(default=None, description="Starting joint angles, degrees; default all 0 (or the robot's).")
    limits: list[Annotated[list[Angle], Field(min_length=2, max_length=2)] | None] | None = Field(
        default=None, description="Per joint [min, max] in degrees, or null for an unlimited joint; default the URDF's."
    )
    limit_margin: Annotated[float, Field(ge=MIN_DEGREES, le=180, allow_inf_nan=False)] = Field(
        default=10.0, description="delta of the limit barrier, degrees."
    )
    width: Positive | None = Field(
        default=None,
        description="Drawn thickness of the links, collision radius width/2 of joint-to-joint capsules; default 0.5 (links) or 0.1 (URDF, metres).",
    )
    max_joint_speed: joint_rate("max_joint_speed") | None = Field(
        default=None,
        description="deg/s, one number or one per joint: the clock keeps every joint's speed within it; default the robot's "
                    "(robot.yaml, else the URDF's <limit velocity>, else 180), or solver.max_joint_step x render.fps (links).",
    )
    max_joint_acceleration: joint_rate("max_joint_acceleration") | None = Field(
        default=None,
        description="deg/s^2, one number or one per joint; default the robot's published one (robot.yaml), else 4 x max_joint_speed per second.",
    )
    max_joint_jerk: joint_rate("max_joint_jerk", robot=True) | None = Field(
        default=None,
        description="deg/s^3, one number or one per joint, or robot (the bundled robot's published one): the clock is also "
                    "jerk-bounded; default none (speed and acceleration only).",
    )
    self_collision: Annotated[
        Literal["auto", "off"],
        WithJsonSchema({"anyOf": [{"enum": ["auto", "off"]}, {"type": "boolean"}]}),  # YAML 1.1: a bare off is false
    ] | SelfCollisionModel = Field(
        default="auto",
        description="auto: every pair of the arm's own links keeps solver.self_clearance except those MoveIt's rules allow; "
        "off: none is checked; or {auto: true, allow: [[a, b]], check: [[a, b]]}, or {srdf: FILE}.",
    )

    _robot: object = PrivateAttr(default=None)  # the URDF arm read after validation (armanim.scene.robots.UrdfArm)
    _srdf: object = PrivateAttr(default=None)  # the SRDF's allowed pairs, read after validation (armanim.scene.srdf.Srdf)

    @field_validator("self_collision", mode="before")
    @classmethod
    def _self_collision_from_yaml_bool(cls, value):
        # YAML 1.1 reads a bare off as false: take what the user wrote
        return {False: "off", True: "auto"}.get(value, value) if isinstance(value, bool) else value

    @model_validator(mode="after")
    def _one_kind(self):
        """Exactly one of links, urdf, robot; the fields of the other kind left out; a robot that is bundled."""
        given = [name for name in ("links", "urdf", "robot") if getattr(self, name) is not None]
        if len(given) != 1:
            raise ValueError(f"gives {' and '.join(given) if given else 'none of links, urdf, robot'} "
                             "(expected exactly one: links for an arm of straight links, urdf for a URDF file, robot for a bundled robot)")
        wrong = ("base_link", "tip_link", "base_rpy", "tool", "collision") if given[0] == "links" else ("axes", "direction")
        for name in wrong:
            if getattr(self, name) is not None:
                kind = "an arm of links" if given[0] == "links" else "a URDF arm"
                raise ValueError(f"{name} does not apply to {kind} (remove it)")
        if self.robot is not None and self.robot not in ROBOTS:
            raise ValueError(f"robot {self.robot!r} is not bundled (expected one of: {', '.join(ROBOTS)}; "
                             "or give your own file with arm.urdf)")
        return self

    def with_files(self, robot, srdf) -> ArmModel:
        """This arm with what its files say: ``robot``, the URDF arm (``armanim.scene.robots.UrdfArm``,
        None for links), and ``srdf``, the SRDF's pairs (``armanim.scene.srdf.Srdf``, or None).
        :func:`armanim.scene.robots.read_arm_files` reads them, after validation."""
        arm = self.model_copy()
        arm._robot, arm._srdf = robot, srdf
        return arm

    @property
    def urdf_arm(self):
        """The URDF arm (``armanim.scene.robots.UrdfArm``) its file gave; None for an arm of links.

        Raises
        ------
        RuntimeError
            The arm is a URDF's and its file was not read: validate a scene with
            :func:`armanim.scene.load_scene` or :func:`armanim.scene.scene_model`, which read it.
        """
        if self._robot is None and self.is_urdf:
            raise RuntimeError("this URDF arm's file was not read: validate the scene with armanim.scene.load_scene, "
                               "scene_from_bytes or scene_model (SceneModel.model_validate reads no file)")
        return self._robot

    @property
    def is_urdf(self) -> bool:
        """Whether the arm comes from a URDF (``urdf`` or ``robot``)."""
        return self.urdf is not None or self.robot is not None

    @property
    def urdf_source(self) -> bytes | None:
        """The bytes of the user's URDF this arm was read from (None for links or a bundled robot)."""
        return self._robot.source if self._robot is not None else None

    @property
    def srdf_pairs(self) -> tuple[tuple[str, str, str], ...]:
        """(link1, link2, reason) of the SRDF ``self_collision`` read (() without one)."""
        if self._srdf is None and not isinstance(self.self_collision, str) and self.self_collision.srdf is not None:
            raise RuntimeError("this arm's SRDF was not read: validate the scene with armanim.scene.load_scene, "
                               "scene_from_bytes or scene_model (SceneModel.model_validate reads no file)")
        return self._srdf.pairs if self._srdf is not None else ()

    @property
    def srdf_source(self) -> bytes | None:
        """The bytes of the SRDF ``self_collision`` read (None without one)."""
        return self._srdf.source if self._srdf is not None else None

    @property
    def joint_count(self) -> int:
        """Number of joints."""
        return len(self.urdf_arm.joint_names) if self.is_urdf else len(self.links or ())

    @property
    def resolved_width(self) -> float:
        """``width``, or its default: 0.5 for links, 0.1 (metres) for a URDF arm."""
        if self.width is not None:
            return float(self.width)
        return URDF_WIDTH if self.is_urdf else LINKS_WIDTH


LINKS_WIDTH = 0.5
URDF_WIDTH = 0.1
"""Default ``arm.width`` of a link arm (scene units) and of a URDF arm (metres)."""

URDF_SPEED = 180.0
"""deg/s: ``arm.max_joint_speed`` of a URDF joint whose ``<limit>`` gives no velocity (and whose
robot publishes none): half a turn a second, a typical cobot's joint speed (a UR5's 180, a
Panda's 125 to 150)."""

RATE_FIELDS = ("max_joint_speed", "max_joint_acceleration", "max_joint_jerk")
"""The arm's joint rate fields (deg/s, deg/s^2, deg/s^3), in this order."""


class BoxModel(Strict):
    """A solid box: its centre, full edge lengths and orientation."""

    center: Vector3
    size: Annotated[list[Positive], Field(min_length=3, max_length=3)] = Field(
        description="Full edge lengths along the box's own x, y, z axes (each > 0)."
    )
    rpy: Annotated[list[Angle], Field(min_length=3, max_length=3)] = Field(
        default=[0.0, 0.0, 0.0], description="Roll, pitch, yaw of the box in the world, degrees (URDF: R = Rz(yaw) Ry(pitch) Rx(roll))."
    )


class RodModel(Strict):
    """A solid capsule (a post, a bar): every point within ``radius`` of the segment ``from``-``to``."""

    from_: Vector3 = Field(alias="from", description="One end of the capsule's axis.")
    to: Vector3 = Field(description="The other end (the same point: a sphere).")
    radius: Positive = Field(description="Radius of the solid capsule (> 0).")


SHAPE_FORMS = ("center", "box", "capsule")
"""The keys that say an obstacle's shape: a sphere (``center`` and ``radius``), ``box`` or ``capsule``."""


class ObstacleModel(Strict):
    """One obstacle: a sphere ``{center, radius}`` (the default form), ``{box: ...}`` or ``{capsule: ...}``."""

    model_config = ConfigDict(
        extra="forbid",
        frozen=True,
        strict=True,
        json_schema_extra={"oneOf": [{"required": ["center", "radius"]}, {"required": ["box"]}, {"required": ["capsule"]}]},
    )

    center: Vector3 | None = Field(default=None, description="A sphere's centre.")
    radius: NonNegative | None = Field(default=None, description="Radius of the solid sphere no arm part may enter.")
    box: BoxModel | None = Field(default=None, description="A solid box instead of a sphere.")
    capsule: RodModel | None = Field(default=None, description="A solid capsule instead of a sphere.")
    influence: Positive | None = Field(
        default=None,
        description="R: how far beyond the surface the avoidance field reaches; default the sphere's or capsule's radius, half a box's shortest edge.",
    )

    @model_validator(mode="after")
    def _one_shape(self):
        given = [key for key in SHAPE_FORMS if getattr(self, key) is not None]
        if len(given) != 1:
            what = "none" if not given else " and ".join(given)
            raise ValueError(
                f"an obstacle is one shape (got {what}): expected {{center, radius}} (a sphere), {{box: {{center, size, rpy}}}} "
                "or {capsule: {from, to, radius}}"
            )
        if self.center is not None and self.radius is None:
            raise ValueError("a sphere needs a radius (expected {center: [x, y, z], radius: r})")
        if self.radius is not None and self.center is None:
            raise ValueError("radius belongs to a sphere, which needs a center (a box or capsule gives its own inside box: or capsule:)")
        return self

    @property
    def kind(self) -> str:
        """``"sphere"``, ``"box"`` or ``"capsule"``."""
        return "box" if self.box is not None else "capsule" if self.capsule is not None else "sphere"

    @property
    def resolved_influence(self) -> float:
        """``influence``, or its default: the sphere's or capsule's radius, half the box's shortest edge."""
        if self.influence is not None:
            return float(self.influence)
        if self.box is not None:
            return min(self.box.size) / 2.0
        return float(self.capsule.radius if self.capsule is not None else self.radius)


QUATERNION_BAND = (0.99, 1.01)
"""|q| a goal's ``quaternion_wxyz`` may have: normalised inside the band, an error outside it."""


def _nonzero(vector: list[float], what: str) -> list[float]:
    if not any(v != 0 for v in vector):
        raise ValueError(f"{what} is the zero vector (expected a direction: any length > 0)")
    return vector


class OrientationModel(Strict):
    """A goal's tool orientation, exactly one form (degrees): ``rpy`` (URDF's fixed-axis
    roll-pitch-yaw, R = Rz(yaw) Ry(pitch) Rx(roll)), ``quaternion_wxyz``, or ``axis`` and ``angle``."""

    rpy: Annotated[list[Angle], Field(min_length=3, max_length=3)] | None = Field(
        default=None, description="[roll, pitch, yaw] in degrees: R = Rz(yaw) Ry(pitch) Rx(roll), as URDF's <origin rpy>."
    )
    quaternion_wxyz: Annotated[list[Finite], Field(min_length=4, max_length=4)] | None = Field(
        default=None, description="[w, x, y, z], scalar first; |q| within [0.99, 1.01] (normalised)."
    )
    axis: Vector3 | None = Field(default=None, description="Rotation axis (any length > 0), with angle.")
    angle: Angle | None = Field(default=None, description="Degrees about axis, within [-360, 360].")

    @model_validator(mode="after")
    def _one_form(self):
        forms = [name for name in ("rpy", "quaternion_wxyz", "axis") if getattr(self, name) is not None]
        if len(forms) != 1:
            raise ValueError(
                f"sets {' and '.join(forms) if forms else 'no form'} (expected exactly one of rpy, quaternion_wxyz, or axis with angle)"
            )
        if (self.axis is None) != (self.angle is None):
            raise ValueError("axis and angle go together (expected both, e.g. {axis: [0, 0, 1], angle: 30})")
        if self.axis is not None:
            _nonzero(self.axis, "axis")
        if self.quaternion_wxyz is not None:
            norm = sum(v * v for v in self.quaternion_wxyz) ** 0.5
            lo, hi = QUATERNION_BAND
            if not lo <= norm <= hi:
                raise ValueError(
                    f"quaternion_wxyz has length {norm:.6g} (expected a unit quaternion: length within [{lo:g}, {hi:g}], [w, x, y, z])"
                )
        return self


class GoalModel(Strict):
    """One goal; a bare ``[x, y, z]`` list is read as ``{position: [x, y, z]}``."""

    position: Vector3
    hold: Annotated[float, Field(ge=0, le=3600, allow_inf_nan=False)] = Field(
        default=0.0, description="Seconds to stay after reaching it."
    )
    orientation: OrientationModel | None = Field(
        default=None, description="The tool frame's orientation at the goal (6-D goal); default none (position only)."
    )
    tool_axis: Vector3 | None = Field(
        default=None, description="World direction of the tool's z axis at the goal, roll free (5-D goal); default none."
    )

    @field_validator("tool_axis")
    @classmethod
    def _axis_not_zero(cls, value):
        return _nonzero(value, "tool_axis") if value is not None else value

    @model_validator(mode="after")
    def _one_orientation(self):
        if self.orientation is not None and self.tool_axis is not None:
            raise ValueError("sets both orientation and tool_axis (expected at most one: tool_axis leaves the roll free, orientation fixes it)")
        return self

    @model_validator(mode="before")
    @classmethod
    def _from_list(cls, value):
        return {"position": value} if isinstance(value, list) else value

    @classmethod
    def __get_pydantic_json_schema__(cls, core_schema, handler):
        # editors must accept the short form too
        as_object = handler(core_schema)
        as_list = {"type": "array", "items": {"type": "number"}, "minItems": 3, "maxItems": 3, "description": "[x, y, z]"}
        return {"anyOf": [as_list, as_object]}


class WeightsModel(Strict):
    """Weights of the cost's terms (newton also takes target and regularizer)."""

    goal: NonNegative = 1.0
    obstacles: NonNegative = 1.0
    limits: NonNegative = 1.0
    target: Positive = 1e3
    regularizer: NonNegative = 1.0


class SolverModel(Strict):
    """The ``solver`` section."""

    method: MethodName = "pinv"
    step: Annotated[float, Field(gt=0, le=1, allow_inf_nan=False)] = Field(
        default=0.1, description="beta: the frame's task-space step is beta * (g - e)."
    )
    max_step: Positive | None = Field(default=None, description="Cap on the tip's travel per frame; default none.")
    tolerance: Positive = Field(default=0.01, description="A goal is reached when |e - g| < tolerance.")
    max_frames_per_goal: Annotated[int, Field(ge=1, le=LIMITS["max_frames_per_goal"])] = 600
    jacobian: JacobianMode = "analytic"
    damping: Positive = Field(default=0.05, description="lambda, for dls only.")
    max_joint_step: Annotated[float, Field(ge=MIN_JOINT_STEP, le=180, allow_inf_nan=False)] = Field(
        default=10.0, description="No joint turns by more than this many degrees in one solver step (a solved frame of render.fps); arm.max_joint_speed is the speed."
    )
    clearance: Positive | None = Field(
        default=None,
        description="d_safe: the distance every arm part keeps from every obstacle surface, scene units; default arm.width / 10.",
    )
    self_clearance: Positive | None = Field(
        default=None,
        description="The distance every enabled pair of the arm's own parts keeps apart, scene units; default clearance / 2.",
    )
    planner: Annotated[
        PlannerMode,
        WithJsonSchema({"anyOf": [{"enum": ["auto", "off"]}, {"type": "boolean"}]}),  # YAML 1.1: a bare off is false
    ] = Field(
        default="auto",
        description="auto: escape stalls by planning a joint-space path; off (or false): the pure local method (for teaching).",
    )
    orientation_weight: Positive | None = Field(
        default=None,
        description="Length per radian: how much a radian of tool rotation weighs against a unit of distance; default the arm's reach / 4.",
    )
    orientation_tolerance: Annotated[float, Field(ge=MIN_DEGREES, le=180, allow_inf_nan=False)] = Field(
        default=1.0, description="Degrees: a goal with an orientation is reached when the tool is within this angle of it (and within tolerance)."
    )
    weights: WeightsModel = WeightsModel()

    @field_validator("planner", mode="before")
    @classmethod
    def _planner_from_yaml_bool(cls, value):
        # YAML 1.1 reads a bare off as false (and on as true): take what the user wrote
        return {False: "off", True: "auto"}.get(value, value) if isinstance(value, bool) else value


class ViewModel(Strict):
    """Camera angles, degrees."""

    elevation: Annotated[float, Field(ge=-90, le=90, allow_inf_nan=False)] = 25.0
    azimuth: Annotated[float, Field(ge=-360, le=360, allow_inf_nan=False)] = -60.0




class RenderModel(Strict):
    """The ``render`` section."""

    fps: Annotated[float, Field(ge=MIN_FPS, le=240, allow_inf_nan=False)] = 30.0
    size: Annotated[list[Side], Field(min_length=2, max_length=2)] = Field(
        default=[1280, 720], description="Pixels, width x height."
    )
    view: ViewModel = ViewModel()
    bounds: Literal["auto"] | Annotated[list[Annotated[list[Finite], Field(min_length=2, max_length=2)]], Field(min_length=3, max_length=3)] = Field(
        default="auto", description="auto, or [[xmin, xmax], [ymin, ymax], [zmin, zmax]]."
    )
    trail: bool = True
    format: VideoFormat = "mp4"


class SceneModel(Strict):
    """A whole scene file (contract version 1)."""

    model_config = ConfigDict(
        extra="forbid",
        frozen=True,
        strict=True,
        title="armanim scene",
        json_schema_extra={"$schema": "https://json-schema.org/draft/2020-12/schema"},
    )

    version: Literal[1] = Field(description="Scene format version; this armanim reads version 1.")
    name: Annotated[str, Field(min_length=1, max_length=NAME_MAX, pattern=NAME_PATTERN)] | None = Field(
        default=None, description="Name of the run and its output folder; default: the file's stem."
    )
    arm: ArmModel
    obstacles: Annotated[list[ObstacleModel], Field(max_length=LIMITS["obstacles"])] = []
    floor: Finite | None = Field(
        default=None, description="Height of a floor plane z = floor that every link keeps solver.clearance above (the base excepted); default none."
    )
    goals: Annotated[list[GoalModel], Field(min_length=1, max_length=LIMITS["goals"])]
    solver: SolverModel = SolverModel()
    render: RenderModel = RenderModel()

    @field_validator("name")
    @classmethod
    def _not_a_table_name(cls, value):
        problem = name_problem(value) if value is not None else None
        if problem is not None:
            raise ValueError(problem)
        return value
