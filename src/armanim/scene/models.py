"""pydantic v2 models of the scene file (contract version 1), degrees as written.

Every field of ``scene-format.md`` with its default; unknown keys are errors
(``extra="forbid"``) and models are frozen. Checks that involve several fields
(lengths that must agree, the home pose clear of obstacles, ...) are in
:mod:`armanim.scene.checks`, so that every problem is reported at once. The ``arm`` section's
models are in :mod:`armanim.scene.armmodel`.
"""

from __future__ import annotations

import math
from typing import Annotated, Literal

from pydantic import (
    ConfigDict,
    Field,
    WithJsonSchema,
    field_validator,
    model_validator,
)

from armanim.names import JacobianMode, MethodName, PlannerMode, RobotLook, VideoFormat
from armanim.scene.armmodel import ArmModel
from armanim.scene.fields import (
    LIMITS,
    MIN_DEGREES,
    MIN_FPS,
    MIN_JOINT_STEP,
    NAME_MAX,
    NAME_PATTERN,
    Angle,
    Finite,
    NonNegative,
    Positive,
    Side,
    Strict,
    Vector3,
    name_problem,
)

SCENE_VERSION = 1


class BoxModel(Strict):
    """A solid box: its centre, full edge lengths and orientation."""

    center: Vector3
    size: Annotated[list[Positive], Field(min_length=3, max_length=3)] = Field(
        description="Full edge lengths along the box's own x, y, z axes (each > 0)."
    )
    rpy: Annotated[list[Angle], Field(min_length=3, max_length=3)] = Field(
        default=[0.0, 0.0, 0.0],
        description="Roll, pitch, yaw of the box in the world, degrees (URDF: R = Rz(yaw) Ry(pitch) Rx(roll)).",
    )


class RodModel(Strict):
    """A solid capsule (a post, a bar): every point within ``radius`` of the segment ``from``-``to``."""

    from_: Vector3 = Field(alias="from", description="One end of the capsule's axis.")
    to: Vector3 = Field(description="The other end (the same point: a sphere).")
    radius: Positive = Field(description="Radius of the solid capsule (> 0).")


class CylinderModel(Strict):
    """A solid cylinder (a can, a post, a pipe): its axis is its own z, as in MoveIt and URDF."""

    center: Vector3 = Field(description="The middle of the cylinder's axis.")
    length: Positive = Field(description="Full height along the cylinder's own z axis (> 0).")
    radius: Positive = Field(description="Radius of the solid cylinder (> 0).")
    rpy: Annotated[list[Angle], Field(min_length=3, max_length=3)] = Field(
        default=[0.0, 0.0, 0.0],
        description="Roll, pitch, yaw of the cylinder in the world, degrees (URDF: R = Rz(yaw) Ry(pitch) Rx(roll)); 0: the axis along world z.",
    )


SHAPE_FORMS = ("center", "box", "capsule", "cylinder")
"""The keys that say an obstacle's shape: a sphere (``center`` and ``radius``), ``box``, ``capsule`` or ``cylinder``."""

OBSTACLE_NAME_PATTERN = r"^[^\x00-\x1f\x7f]+$"
"""An obstacle's ``name``: any text without control characters (MoveIt's object ids, for one)."""


class ObstacleModel(Strict):
    """One obstacle: a sphere ``{center, radius}`` (the default form), ``{box: ...}``, ``{capsule: ...}`` or ``{cylinder: ...}``."""

    model_config = ConfigDict(
        extra="forbid",
        frozen=True,
        strict=True,
        json_schema_extra={
            "oneOf": [
                {"required": ["center", "radius"]},
                {"required": ["box"]},
                {"required": ["capsule"]},
                {"required": ["cylinder"]},
            ]
        },
    )

    center: Vector3 | None = Field(default=None, description="A sphere's centre.")
    radius: NonNegative | None = Field(default=None, description="Radius of the solid sphere no arm part may enter.")
    box: BoxModel | None = Field(default=None, description="A solid box instead of a sphere.")
    capsule: RodModel | None = Field(default=None, description="A solid capsule instead of a sphere.")
    cylinder: CylinderModel | None = Field(default=None, description="A solid cylinder instead of a sphere.")
    name: Annotated[str, Field(min_length=1, max_length=NAME_MAX, pattern=OBSTACLE_NAME_PATTERN)] | None = Field(
        default=None,
        description="A name for messages and pictures (unique within the scene); default none: obstacles[k].",
    )
    influence: Positive | None = Field(
        default=None,
        description="R: how far beyond the surface the avoidance field reaches; default the sphere's or capsule's radius, half a box's "
        "shortest edge, a cylinder's radius or half its length, whichever is less.",
    )

    @model_validator(mode="after")
    def _one_shape(self):
        given = [key for key in SHAPE_FORMS if getattr(self, key) is not None]
        if len(given) != 1:
            what = "none" if not given else " and ".join(given)
            raise ValueError(
                f"an obstacle is one shape (got {what}): expected {{center, radius}} (a sphere), {{box: {{center, size, rpy}}}}, "
                "{capsule: {from, to, radius}} or {cylinder: {center, length, radius, rpy}}"
            )
        if self.center is not None and self.radius is None:
            raise ValueError("a sphere needs a radius (expected {center: [x, y, z], radius: r})")
        if self.radius is not None and self.center is None:
            raise ValueError(
                "radius belongs to a sphere, which needs a center (a box, capsule or cylinder gives its own inside box:, "
                "capsule: or cylinder:)"
            )
        return self

    @property
    def kind(self) -> str:
        """``"sphere"``, ``"box"``, ``"capsule"`` or ``"cylinder"``."""
        if self.cylinder is not None:
            return "cylinder"
        return "box" if self.box is not None else "capsule" if self.capsule is not None else "sphere"

    @property
    def resolved_influence(self) -> float:
        """``influence``, or its default: the sphere's or capsule's radius, half the box's shortest
        edge, the cylinder's radius or half its length (the lesser)."""
        if self.influence is not None:
            return float(self.influence)
        if self.box is not None:
            return min(self.box.size) / 2.0
        if self.cylinder is not None:
            return min(float(self.cylinder.radius), self.cylinder.length / 2.0)
        if self.capsule is not None:
            return float(self.capsule.radius)
        assert self.radius is not None, "a sphere has its radius (ObstacleModel)"
        return float(self.radius)


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
        default=None,
        description="[roll, pitch, yaw] in degrees: R = Rz(yaw) Ry(pitch) Rx(roll), as URDF's <origin rpy>.",
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


UNIT_TOLERANCE = 1e-6
"""How far a text's ``right`` and ``up`` may be from unit length, and their dot product from 0."""


def _length(vector) -> float:
    """Euclidean length of a short list of finite floats (no overflow or underflow)."""
    return math.hypot(*vector)


def _difference(a, b) -> list[float]:
    return [x - y for x, y in zip(a, b)]


def _cross(a, b) -> list[float]:
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def _shown_vector(vector) -> str:
    return "[" + ", ".join(f"{v:g}" for v in vector) + "]"


def _unit(vector: list[float]) -> list[float]:
    """``vector``, if it has unit length within :data:`UNIT_TOLERANCE`."""
    length = _length(vector)
    if abs(length - 1.0) > UNIT_TOLERANCE:
        raise ValueError(
            f"{_shown_vector(vector)} has length {length:.6g} (expected a unit vector, within {UNIT_TOLERANCE:g}: "
            f"right and up are the board's unit directions, square to each other, e.g. right: [0, -1, 0], up: [0, 0, 1])"
        )
    return vector


class ArcModel(Strict):
    """A circular arc: from ``start`` about ``center`` through ``angle`` degrees about ``normal``."""

    center: Vector3 = Field(description="The circle's centre.")
    start: Vector3 = Field(
        description="Where the arc starts (its distance from center, square to normal, is the radius)."
    )
    angle: Angle = Field(
        description="Degrees swept, nonzero, within [-360, 360]: positive turns counterclockwise about normal "
        "(the right-hand rule), negative clockwise."
    )
    normal: Vector3 = Field(description="The axis the arc turns about, square to its plane (any length > 0).")

    @field_validator("start")
    @classmethod
    def _off_center(cls, value, info):
        center = info.data.get("center")
        if center is not None and _length(_difference(value, center)) < LIMITS["smallest"]:
            raise ValueError(
                f"{_shown_vector(value)} is the center: the arc has radius 0 (expected a start at the arc's radius from center)"
            )
        return value

    @field_validator("angle")
    @classmethod
    def _turns(cls, value):
        if abs(value) < MIN_DEGREES:
            raise ValueError(
                f"{value:g} sweeps no arc (expected a nonzero angle in degrees, at most 360 in size; "
                "negative turns clockwise about normal)"
            )
        return value

    @field_validator("normal")
    @classmethod
    def _off_axis(cls, value, info):
        _nonzero(value, "normal")
        center, start = info.data.get("center"), info.data.get("start")
        if center is None or start is None:
            return value
        offset = _difference(start, center)
        scale = max(abs(v) for v in value)
        unit = [v / scale for v in value]
        unit = [v / _length(unit) for v in unit]
        radius = _length(_cross(unit, offset))  # the offset's part square to the normal
        if radius < LIMITS["smallest"] or radius < 1e-9 * _length(offset):
            raise ValueError(
                f"{_shown_vector(value)} is parallel to start - center = {_shown_vector(offset)}: the start lies on the arc's "
                "axis, radius 0 (expected a normal square to the arc's plane, e.g. [0, 0, 1] for an arc in a horizontal plane)"
            )
        return value


class TextModel(Strict):
    """Text written on a board with the bundled single-stroke font (docs/scene-format.md, Path goals)."""

    string: str = Field(
        json_schema_extra={"minLength": 1, "maxLength": LIMITS["text_characters"]},
        description="The text to write: printable ASCII (letters, digits, punctuation, spaces).",
    )
    origin: Vector3 = Field(description="The left end of the baseline, on the board.")
    height: Positive = Field(description="Height of a capital letter, scene units.")
    right: Vector3 = Field(description="Unit direction the text runs along, on the board.")
    up: Vector3 = Field(
        description="Unit direction of the letters' up, on the board, square to right. "
        "The board's front, where the text reads and the pen lifts to, is right x up."
    )
    lift: Positive | None = Field(
        default=None,
        description="How far the pen lifts off the board between strokes, scene units; default 0.3 x height.",
    )

    @field_validator("string")
    @classmethod
    def _writable(cls, value):
        from armanim.scene.text import missing_characters

        if not value.strip():
            raise ValueError(
                "is empty (expected the text to write, e.g. string: armanim)"
                if not value
                else "holds only spaces (expected some text to write)"
            )
        if len(value) > LIMITS["text_characters"]:
            raise ValueError(f"has {len(value):,} characters (expected at most {LIMITS['text_characters']:,})")
        missing = missing_characters(value)
        if missing:
            names = ", ".join(repr(c) for c in missing[:8]) + (
                f" and {len(missing) - 8} more" if len(missing) > 8 else ""
            )
            raise ValueError(
                f"has characters the font lacks: {names} (expected printable ASCII: letters, digits, "
                "punctuation and spaces, one line)"
            )
        return value

    @field_validator("right")
    @classmethod
    def _right_unit(cls, value):
        return _unit(value)

    @field_validator("up")
    @classmethod
    def _up_square(cls, value, info):
        _unit(value)
        right = info.data.get("right")
        if right is not None:
            dot = sum(a * b for a, b in zip(right, value))
            if abs(dot) > UNIT_TOLERANCE:
                raise ValueError(
                    f"{_shown_vector(value)} is not square to right {_shown_vector(right)} (their dot product is {dot:.6g}; "
                    f"expected unit vectors square to each other, within {UNIT_TOLERANCE:g}, e.g. right: [0, -1, 0], up: [0, 0, 1])"
                )
        return value

    @property
    def resolved_lift(self) -> float:
        """``lift``, or its default: 0.3 x ``height``."""
        return float(self.lift) if self.lift is not None else LIFT_PER_HEIGHT * self.height


LIFT_PER_HEIGHT = 0.3
"""A text's default ``lift`` as a fraction of its ``height``."""

PATH_FORMS = ("line", "arc", "polyline", "text")
"""The keys that say a path's form."""


class PathModel(Strict):
    """A path goal's path, exactly one form: ``line``, ``arc``, ``polyline`` or ``text``."""

    model_config = ConfigDict(
        extra="forbid",
        frozen=True,
        strict=True,
        json_schema_extra={"oneOf": [{"required": [form]} for form in PATH_FORMS]},
    )

    line: Annotated[list[Vector3], Field(min_length=2, max_length=2)] | None = Field(
        default=None, description="[p0, p1]: a straight line from p0 to p1."
    )
    arc: ArcModel | None = Field(default=None, description="A circular arc: {center, start, angle (degrees), normal}.")
    polyline: Annotated[list[Vector3], Field(min_length=2, max_length=LIMITS["path_points"])] | None = Field(
        default=None,
        description="[[x, y, z], ...]: straight lines through the points in turn (at least 2 points, not all the same).",
    )
    text: TextModel | None = Field(default=None, description="Written text: {string, origin, height, right, up, lift}.")

    @field_validator("line")
    @classmethod
    def _line_has_length(cls, value):
        if value is not None and _length(_difference(value[1], value[0])) < LIMITS["smallest"]:
            raise ValueError(
                f"starts and ends at {_shown_vector(value[0])}: the line has length 0 (expected two different points)"
            )
        return value

    @field_validator("polyline")
    @classmethod
    def _polyline_has_length(cls, value):
        if value is not None and all(_length(_difference(p, value[0])) < LIMITS["smallest"] for p in value):
            raise ValueError(
                f"has all its points at {_shown_vector(value[0])}: the polyline has length 0 "
                "(expected at least two different points; repeated points are dropped)"
            )
        return value

    @model_validator(mode="after")
    def _one_form(self):
        given = [form for form in PATH_FORMS if getattr(self, form) is not None]
        if len(given) != 1:
            what = "none" if not given else " and ".join(given)
            raise ValueError(
                f"a path is one form (got {what}): expected {{line: [p0, p1]}}, {{arc: {{center, start, angle, normal}}}}, "
                "{polyline: [[x, y, z], ...]} or {text: {string, origin, height, right, up}}"
            )
        return self

    @property
    def form(self) -> str:
        """``"line"``, ``"arc"``, ``"polyline"`` or ``"text"``."""
        return next(form for form in PATH_FORMS if getattr(self, form) is not None)


GOAL_FORMS = ("position", "path", "joints")
"""The keys that say what a goal is: a point, a path, or a pose of the joints."""


class ApproachModel(Strict):
    """A grasp's or release's approach: the tool comes in along a straight line over its last
    ``distance`` (the path machinery: a path goal whose line ends at the goal)."""

    distance: Positive = Field(description="Length of the straight line in, scene units (> 0).")
    axis: Literal["tool"] | Vector3 = Field(
        default="tool",
        description="The direction the tool moves along it: tool (the tool's z axis at the goal, which needs orientation or "
        "tool_axis) or a world direction [x, y, z]; default tool.",
    )
    speed: Positive | None = Field(
        default=None, description="The tool's speed along it, scene units per second; default distance per second."
    )

    @field_validator("axis")
    @classmethod
    def _axis_not_zero(cls, value):
        return _nonzero(value, "axis") if not isinstance(value, str) else value


class RetreatModel(ApproachModel):
    """A goal's retreat: once it is reached (a grasp taken, a release put down), the tool leaves
    along a straight line of ``distance`` (the path machinery: a path goal of its own after it)."""

    axis: Literal["tool"] | Vector3 = Field(
        default="tool",
        description="The direction the tool moves along it: tool (back along the tool's z axis at the goal, the way an approach "
        "along tool came in; needs orientation or tool_axis) or a world direction [x, y, z]; default tool.",
    )


class GoalModel(Strict):
    """One goal: a point (``position``; a bare ``[x, y, z]`` list is read as ``{position: [x, y, z]}``),
    a path (``path`` and ``speed``: the arm goes to the path's start as to a point, then the tool follows it),
    or a pose of the joints (``joints``: degrees, or metres for a prismatic joint, one per moving joint, like ``arm.home``)."""

    model_config = ConfigDict(
        extra="forbid",
        frozen=True,
        strict=True,
        json_schema_extra={
            "oneOf": [{"required": ["position"]}, {"required": ["path", "speed"]}, {"required": ["joints"]}]
        },
    )

    position: Vector3 | None = Field(default=None, description="A point goal's position.")
    joints: Annotated[list[Angle], Field(min_length=1)] | None = Field(
        default=None,
        description="A joint goal: the arm's pose, one value per moving joint in order (degrees, as arm.home, each within "
        "[-360, 360]), reached when every joint is within solver.joint_tolerance of it.",
    )
    path: PathModel | None = Field(
        default=None,
        description="A path goal's path for the tool to follow: line, arc, polyline or text (docs/scene-format.md, Path goals).",
    )
    speed: Positive | None = Field(
        default=None,
        validate_default=True,
        description="A path goal's tool speed along its path, scene units per second (> 0).",
    )
    hold: Annotated[float, Field(ge=0, le=3600, allow_inf_nan=False)] = Field(
        default=0.0, description="Seconds to stay after reaching it (a path goal: after the path's end)."
    )
    orientation: OrientationModel | None = Field(
        default=None,
        description="The tool frame's orientation at the goal (6-D goal; a path goal holds it along the path); default none (position only).",
    )
    tool_axis: Vector3 | None = Field(
        default=None,
        description="World direction of the tool's z axis at the goal (a path goal holds it along the path), roll free (5-D goal); default none.",
    )
    blend: NonNegative | None = Field(
        default=None,
        description="Pass within this of the goal without stopping (scene units; degrees in every joint for a joint goal; "
        "0: exactly through it); default solver.blend. The last goal, a goal with hold and a missed goal end at rest.",
    )
    grasp: Annotated[str, Field(min_length=1, max_length=NAME_MAX, pattern=OBSTACLE_NAME_PATTERN)] | None = Field(
        default=None,
        description="The name of an obstacle the tool takes once this goal is reached: from then on it moves with the tool, part of "
        "the arm, until a goal with release: true (docs/scene-format.md, Pick and place); default none.",
    )
    release: bool = Field(
        default=False,
        description="Put down what the tool holds once this goal is reached: it stays where it is, an obstacle again.",
    )
    approach: ApproachModel | None = Field(
        default=None,
        description="Come in along a straight line over the last distance, {distance: 0.1, axis: tool}, as pick pipelines do "
        "(a point or pose goal; docs/scene-format.md, Pick and place).",
    )
    retreat: RetreatModel | None = Field(
        default=None,
        description="Leave along a straight line once the goal is reached, {distance: 0.1, axis: tool} (back along the tool), as "
        "pick pipelines do: solved as a path goal of its own right after this one (a point or pose goal; "
        "docs/scene-format.md, Pick and place).",
    )
    touch_links: Annotated[list[Annotated[str, Field(min_length=1)]], Field(max_length=LIMITS["links"])] | None = Field(
        default=None,
        description="With grasp: the links allowed to touch the object while it is carried; default every link the last joint carries "
        "(the hand and the fingers).",
    )

    @field_validator("speed")
    @classmethod
    def _speed_of_a_path(cls, value, info):
        if value is None and info.data.get("path") is not None:
            raise ValueError(
                "is required on a path goal (the tool's speed along the path, scene units per second, e.g. speed: 0.05)"
            )
        if value is not None and info.data.get("joints") is not None:
            raise ValueError(
                "belongs to a path goal (a joint goal's motion is timed by the arm's joint speeds: leave speed out)"
            )
        if value is not None and info.data.get("position") is not None:
            raise ValueError(
                "belongs to a path goal (a point goal's motion is timed by the arm's joint speeds: "
                "leave speed out, or give path instead of position)"
            )
        return value

    @field_validator("tool_axis")
    @classmethod
    def _axis_not_zero(cls, value):
        return _nonzero(value, "tool_axis") if value is not None else value

    @field_validator("blend")
    @classmethod
    def _blend_of_a_point(cls, value, info):
        if value is not None and info.data.get("path") is not None:
            raise ValueError(
                "belongs to a point, pose or joint goal (a path goal starts and ends at rest: leave blend out)"
            )
        if value is not None and info.data.get("joints") is not None and value > 180:
            raise ValueError(
                f"is {value:g} degrees on a joint goal (expected at most 180: the most any joint may pass from it)"
            )
        return value

    @model_validator(mode="after")
    def _one_orientation(self):
        if self.joints is not None and (self.orientation is not None or self.tool_axis is not None):
            raise ValueError(
                "sets joints with an orientation (a joint goal fixes the whole pose, the tool's orientation "
                "with it: leave orientation and tool_axis out, or give position instead of joints)"
            )
        if self.orientation is not None and self.tool_axis is not None:
            raise ValueError(
                "sets both orientation and tool_axis (expected at most one: tool_axis leaves the roll free, orientation fixes it)"
            )
        return self

    @model_validator(mode="before")
    @classmethod
    def _from_list(cls, value):
        if isinstance(value, list):
            return {"position": value}
        if isinstance(value, dict):
            given = [key for key in GOAL_FORMS if value.get(key) is not None]
            if len(given) >= 2:
                raise ValueError(
                    f"sets both {' and '.join(given)} (expected one: position for a point goal, path with speed "
                    "for a path goal, whose arm goes to the path's start first, or joints for a pose of the joints)"
                )
            if not given:
                raise ValueError(
                    "has neither position, path nor joints (expected position: [x, y, z] for a point goal, "
                    "path: {...} with speed for a path goal, or joints: [...] for a pose of the joints, degrees)"
                )
        return value

    @property
    def is_path(self) -> bool:
        """Whether this is a path goal."""
        return self.path is not None

    @property
    def is_joint(self) -> bool:
        """Whether this is a joint goal."""
        return self.joints is not None

    @classmethod
    def __get_pydantic_json_schema__(cls, core_schema, handler):
        # editors must accept the short form too
        as_object = handler(core_schema)
        as_list = {
            "type": "array",
            "items": {"type": "number"},
            "minItems": 3,
            "maxItems": 3,
            "description": "[x, y, z]",
        }
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
        default=10.0,
        description="No joint turns by more than this many degrees in one solver step (a solved frame of render.fps); arm.max_joint_speed is the speed.",
    )
    max_slide_step: Annotated[float, Field(ge=1e-6, le=10, allow_inf_nan=False)] = Field(
        default=0.05,
        description="No prismatic joint slides by more than this many metres in one solver step (max_joint_step's counterpart).",
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
    joint_tolerance: Annotated[float, Field(ge=MIN_DEGREES, le=180, allow_inf_nan=False)] = Field(
        default=0.01,
        description="Degrees (a prismatic joint: this many radians, as metres): a joint goal is reached when every joint is within this of it. "
        "The planned path ends on the goal itself, so this only absorbs rounding; MoveIt's default is 1e-4 rad (0.0057 deg).",
    )
    orientation_tolerance: Annotated[float, Field(ge=MIN_DEGREES, le=180, allow_inf_nan=False)] = Field(
        default=1.0,
        description="Degrees: a goal with an orientation is reached when the tool is within this angle of it (and within tolerance).",
    )
    path_tolerance: Positive | None = Field(
        default=None,
        description="The most a path goal's tool may stray from its path, at every frame and between frames, scene units; default tolerance.",
    )
    blend: NonNegative | None = Field(
        default=None,
        description="Every point, pose and joint goal's blend where it sets none: pass within this of it without stopping "
        "(scene units; degrees for a joint goal; 0: exactly through it); default none (every goal at rest).",
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


class FurnitureModel(Strict):
    """A box drawn in the pictures and never checked: a table, a shelf's back, a whiteboard."""

    box: BoxModel
    color: Annotated[
        list[Annotated[float, Field(ge=0, le=1, allow_inf_nan=False)]], Field(min_length=3, max_length=3)
    ] = Field(default=[0.80, 0.75, 0.66], description="RGB, 0 to 1; default a light wood.")


class RenderModel(Strict):
    """The ``render`` section."""

    fps: Annotated[float, Field(ge=MIN_FPS, le=240, allow_inf_nan=False)] = 30.0
    size: Annotated[list[Side], Field(min_length=2, max_length=2)] = Field(
        default=[1280, 720], description="Pixels, width x height."
    )
    view: ViewModel = ViewModel()
    bounds: (
        Literal["auto"]
        | Annotated[list[Annotated[list[Finite], Field(min_length=2, max_length=2)]], Field(min_length=3, max_length=3)]
    ) = Field(default="auto", description="auto, or [[xmin, xmax], [ymin, ymax], [zmin, zmax]].")
    trail: bool = True
    format: VideoFormat = "mp4"
    furniture: Annotated[list[FurnitureModel], Field(max_length=LIMITS["obstacles"])] = Field(
        default_factory=list,
        description="Boxes drawn but never checked (no clearance, no cost): furniture the tool may touch, e.g. a whiteboard.",
    )
    robot: RobotLook = Field(
        default="mesh",
        description="A robot with visual meshes drawn as it looks (mesh), as the capsules every clearance is measured on "
        "(capsules), or both (the capsules translucent over it). An arm of links is always its capsules.",
    )


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
        default=None,
        description="Height of a floor plane z = floor that every link keeps solver.clearance above (the base excepted); default none.",
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
