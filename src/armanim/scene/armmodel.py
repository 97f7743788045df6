"""The ``arm`` section of a scene file (pydantic v2 models, degrees as written).

An arm of straight links, or a URDF's (``urdf`` or a bundled ``robot``), its collision
capsules, tool and self-collision rules. Validation reads no file: the URDF and SRDF are read
afterwards (:func:`armanim.scene.robots.read_arm_files`), which gives the arm what they say
(:meth:`ArmModel.with_files`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Annotated, Literal, TypeAlias

import numpy as np
from pydantic import Field, PrivateAttr, WithJsonSchema, field_validator, model_validator

from armanim.scene.fields import (
    LIMITS,
    MIN_DEGREES,
    ROBOTS,
    Angle,
    Angles3,
    AxisName,
    LinkPair,
    NonNegative,
    Positive,
    Strict,
    UrdfName,
    Vector3,
    joint_rate,
)

if TYPE_CHECKING:  # read after validation (armanim.scene.robots.read_arm_files), which imports this module
    from armanim.scene.robots import UrdfArm
    from armanim.scene.srdf import Srdf

    JointSpeed: TypeAlias = float | list[float]  # mypy's view of the constrained forms pydantic reads
    JointAcceleration: TypeAlias = float | list[float]
    JointJerk: TypeAlias = float | list[float] | Literal["robot"]
else:
    JointSpeed, JointAcceleration = joint_rate("max_joint_speed"), joint_rate("max_joint_acceleration")
    JointJerk = joint_rate("max_joint_jerk", robot=True)


class CapsuleModel(Strict):
    """One collision capsule, in its URDF link's frame (metres)."""

    link: Annotated[str, Field(min_length=1, max_length=200)] = Field(description="The URDF link that carries it.")
    from_: Vector3 = Field(alias="from", description="One end of the capsule's segment, in the link's frame.")
    to: Vector3 = Field(description="The other end, in the link's frame (the same point: a sphere).")
    radius: NonNegative = Field(description="Every point within this distance of the segment is the arm's.")


class ToolCapsuleModel(Strict):
    """The tool's collision capsule, in the tool frame (metres)."""

    from_: Vector3 = Field(alias="from", description="One end of the capsule's segment, in the tool frame.")
    to: Vector3 = Field(description="The other end, in the tool frame.")
    radius: NonNegative = Field(description="Every point within this distance of the segment is the tool's.")


class PenModel(Strict):
    """A pen drawn at the tool frame: its nib at the tip, its body back along the frame's -z."""

    length: Annotated[float, Field(gt=0, le=10, allow_inf_nan=False)] = Field(description="Nib to cap, metres.")
    radius: Annotated[float, Field(gt=0, le=1, allow_inf_nan=False)] = Field(default=0.008, description="Metres.")


class ToolModel(Strict):
    """The tool frame: the tip, placed in the tip link's frame; and what is drawn there."""

    xyz: Vector3 = Field(default=[0.0, 0.0, 0.0], description="The tip's position in the tip link's frame (metres).")
    rpy: Angles3 = Field(
        default=[0.0, 0.0, 0.0], description="The tool frame's roll, pitch, yaw in the tip link's frame, degrees."
    )
    pen: PenModel | None = Field(
        default=None, description="Draw a pen held at the tool frame (drawing only: it is not a capsule)."
    )
    mesh: Annotated[str, Field(min_length=1, max_length=4096)] | None = Field(
        default=None,
        description="A mesh file (STL, OBJ, COLLADA) drawn in the tool frame, relative to the scene file "
        "(drawing only).",
    )
    collision: ToolCapsuleModel | None = Field(
        default=None,
        description="A capsule in the tool frame checked like a link's (clearance, self-collision, the cost).",
    )
    gripper: Literal["panda"] | None = Field(
        default=None,
        description="A gripper drawn on the tip link's flange, fingers closed: panda (Franka's hand; drawing only).",
    )


class SelfCollisionModel(Strict):
    """``arm.self_collision`` as a mapping: MoveIt's rules (``auto: true``) or an SRDF, with the
    user's own ``allow`` and ``check`` pairs of links on top."""

    auto: bool | None = Field(
        default=None, description="true: the allowed-collision matrix by MoveIt's rules (adjacent, default, never)."
    )
    srdf: Annotated[str, Field(min_length=1, max_length=4096)] | None = Field(
        default=None,
        description="An SRDF file, relative to the scene file: its <disable_collisions link1= link2=/> pairs are allowed.",
    )
    allow: Annotated[list[LinkPair], Field(max_length=10_000)] = Field(
        default=[], description="Link pairs never checked."
    )
    check: Annotated[list[LinkPair], Field(max_length=10_000)] = Field(
        default=[], description="Link pairs checked whatever the rules say."
    )

    @model_validator(mode="after")
    def _one_source(self):
        if (self.auto is True) == (self.srdf is not None):
            raise ValueError(
                "gives "
                + ("both auto: true and srdf" if self.srdf is not None else "neither auto: true nor srdf")
                + " (expected one: auto: true for MoveIt's rules, or srdf: FILE)"
            )
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
    direction: AxisName | None = Field(
        default=None, description="Local axis along which every link extends; default z (links only)."
    )
    urdf: Annotated[str, Field(min_length=1, max_length=4096)] | None = Field(
        default=None,
        description="A URDF file, relative to the scene file: the arm is its chain from base_link to tip_link.",
    )
    package_dirs: Annotated[list[Annotated[str, Field(min_length=1, max_length=4096)]], Field(max_length=32)] | None = (
        Field(
            default=None,
            description="Folders where the URDF's package://NAME/... meshes are found (NAME/... under one of them, or ... "
            "in one named NAME), relative to the scene file; default: the URDF's folder and its parents. "
            "For drawing only.",
        )
    )
    robot: Annotated[str, Field(min_length=1, max_length=100)] | None = Field(
        default=None, description="A bundled robot (armanim robots lists them): panda, ur5, iiwa."
    )
    base_link: UrdfName | None = Field(
        default=None, description="The URDF link the arm starts at; default the root (or the robot's)."
    )
    tip_link: UrdfName | None = Field(
        default=None, description="The URDF link the arm ends at; default the only leaf (or the robot's)."
    )
    base_rpy: Angles3 | None = Field(
        default=None, description="Roll, pitch, yaw of base_link in the world, degrees; default 0."
    )
    tool: ToolModel | None = Field(default=None, description="The tip in tip_link's frame; default its origin.")
    collision: Literal["auto", "fitted"] | Annotated[list[CapsuleModel], Field(max_length=1000)] | None = Field(
        default=None,
        description="auto (the URDF's primitives and capsules fitted to its meshes, or a bundled robot's own "
        "capsules), fitted (a bundled robot's capsules fitted to its meshes), or a list of capsules.",
    )
    home: list[Angle] | None = Field(
        default=None, description="Starting joint angles, degrees; default all 0 (or the robot's)."
    )
    joint_values: (
        Annotated[dict[UrdfName, Annotated[float, Field(allow_inf_nan=False, ge=-1e9, le=1e9)]], Field(max_length=1000)]
        | None
    ) = Field(
        default=None,
        description="The joints off the arm's chain (a gripper's fingers) held at these values: joint name to degrees, "
        "or metres for a prismatic joint; default 0 if within the joint's limits, else its lower limit. "
        "Mimic joints follow their <mimic>.",
    )
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
    max_joint_speed: JointSpeed | None = Field(
        default=None,
        description="deg/s, one number or one per joint: the clock keeps every joint's speed within it; default the robot's "
        "(robot.yaml, else the URDF's <limit velocity>, else 180), or solver.max_joint_step x render.fps (links).",
    )
    max_joint_acceleration: JointAcceleration | None = Field(
        default=None,
        description="deg/s^2, one number or one per joint; default the robot's published one (robot.yaml), else 4 x max_joint_speed per second.",
    )
    max_joint_jerk: JointJerk | None = Field(
        default=None,
        description="deg/s^3, one number or one per joint, or robot (the bundled robot's published one): the clock is also "
        "jerk-bounded; default none (speed and acceleration only).",
    )
    self_collision: (
        Annotated[
            Literal["auto", "off"],
            WithJsonSchema(
                {"anyOf": [{"enum": ["auto", "off"]}, {"type": "boolean"}]}
            ),  # YAML 1.1: a bare off is false
        ]
        | SelfCollisionModel
    ) = Field(
        default="auto",
        description="auto: every pair of the arm's own links keeps solver.self_clearance except those MoveIt's rules allow; "
        "off: none is checked; or {auto: true, allow: [[a, b]], check: [[a, b]]}, or {srdf: FILE}.",
    )

    _robot: UrdfArm | None = PrivateAttr(default=None)  # the URDF arm read after validation
    _srdf: Srdf | None = PrivateAttr(default=None)  # the SRDF's allowed pairs, read after validation

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
            raise ValueError(
                f"gives {' and '.join(given) if given else 'none of links, urdf, robot'} "
                "(expected exactly one: links for an arm of straight links, urdf for a URDF file, robot for a bundled robot)"
            )
        wrong = (
            ("base_link", "tip_link", "base_rpy", "tool", "collision", "package_dirs", "joint_values")
            if given[0] == "links"
            else ("axes", "direction")
        )
        for name in wrong:
            if getattr(self, name) is not None:
                kind = "an arm of links" if given[0] == "links" else "a URDF arm"
                raise ValueError(f"{name} does not apply to {kind} (remove it)")
        if self.robot is not None and self.robot not in ROBOTS:
            raise ValueError(
                f"robot {self.robot!r} is not bundled (expected one of: {', '.join(ROBOTS)}; "
                "or give your own file with arm.urdf)"
            )
        return self

    def with_files(self, robot: UrdfArm | None, srdf: Srdf | None) -> ArmModel:
        """This arm with what its files say: ``robot``, the URDF arm (``armanim.scene.robots.UrdfArm``,
        None for links), and ``srdf``, the SRDF's pairs (``armanim.scene.srdf.Srdf``, or None).
        :func:`armanim.scene.robots.read_arm_files` reads them, after validation."""
        arm = self.model_copy()
        arm._robot, arm._srdf = robot, srdf
        return arm

    @property
    def urdf_arm(self) -> UrdfArm:
        """The URDF arm (``armanim.scene.robots.UrdfArm``) its file gave.

        Raises
        ------
        RuntimeError
            The arm is an arm of links (ask :attr:`is_urdf` first), or a URDF's whose file was not
            read: validate a scene with :func:`armanim.scene.load_scene` or
            :func:`armanim.scene.scene_model`, which read it.
        """
        if self._robot is None:
            if not self.is_urdf:
                raise RuntimeError("an arm of links has no URDF arm (ask is_urdf first)")
            raise RuntimeError(
                "this URDF arm's file was not read: validate the scene with armanim.scene.load_scene, "
                "scene_from_bytes or scene_model (SceneModel.model_validate reads no file)"
            )
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
            raise RuntimeError(
                "this arm's SRDF was not read: validate the scene with armanim.scene.load_scene, "
                "scene_from_bytes or scene_model (SceneModel.model_validate reads no file)"
            )
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
    def sliding(self) -> np.ndarray:
        """(n,) bool: which joints are prismatic (their values, limits and rates in metres, m/s, ...;
        a revolute joint's in degrees, deg/s, ...). All False for an arm of links."""
        if self.is_urdf and any(self.urdf_arm.prismatic):
            return np.array(self.urdf_arm.prismatic, dtype=bool)
        return np.zeros(self.joint_count, dtype=bool)

    @property
    def resolved_width(self) -> float:
        """``width``, or its default: 0.5 for links, 0.1 (metres) for a URDF arm."""
        if self.width is not None:
            return float(self.width)
        return URDF_WIDTH if self.is_urdf else LINKS_WIDTH


LINKS_WIDTH = 0.5
URDF_WIDTH = 0.1
"""Default ``arm.width`` of a link arm (scene units) and of a URDF arm (metres)."""
