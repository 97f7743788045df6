"""MoveIt's files read: a planning scene (YAML or ``.scene`` text), a motion plan request, SRDF groups.

What :mod:`armanim.scene.moveitscene` turns into an armanim scene. Every shape is returned in
the planning frame (the URDF's root link), every problem as ``FILE:LINE: field: message``
(:class:`armanim.errors.SceneError`, exit 2). The YAML goes through the scene's own reader
(:func:`armanim.scene.yamlread.read_yaml`: lines, bounded size, no tags executed).

The messages read, with the fields used:

- ``moveit_msgs/PlanningScene``: ``world.collision_objects`` (``id``, ``header.frame_id``,
  ``pose``, ``primitives`` with ``type`` and ``dimensions``, ``primitive_poses``; meshes, planes and
  cones are refused), ``robot_state.joint_state`` (``name``, ``position``), ``fixed_frame_transforms``.
- the ``.scene`` text RViz's Motion Planning panel exports (MoveIt's ``saveGeometryToStream``): a
  name line, then per object ``* id``, its pose (the newer format), the shape count, each shape
  (``box x y z``, ``sphere r``, ``cylinder r l``) with its pose and colour, its subframes (newer
  format), and a closing ``.``.
- ``moveit_msgs/MotionPlanRequest``: ``start_state.joint_state``, ``group_name``, the first of
  ``goal_constraints``: ``joint_constraints`` (``joint_name``, ``position``) or a
  ``position_constraints`` (``link_name``, ``target_point_offset``, ``constraint_region``'s first
  primitive pose) with an optional ``orientation_constraints`` (``orientation``).

Poses are ROS's: a position and an x-y-z-w quaternion (a list, or a mapping of x, y, z, w),
normalised as MoveIt does; a pose missing its orientation is the identity.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import cast

import numpy as np

from armanim.arm.rotations import quaternion_rotation, rotation_quaternion
from armanim.errors import Diagnostic, SceneError, shown
from armanim.output.files import read_bounded
from armanim.scene.fieldpaths import YamlDocument, join_path
from armanim.scene.loader import decode_scene
from armanim.scene.urdf import _parse_xml
from armanim.scene.yamlread import MAX_FILE_BYTES, read_yaml

PRIMITIVE_TYPES = {1: "box", 2: "sphere", 3: "cylinder", 4: "cone", 5: "prism"}
"""shape_msgs/SolidPrimitive's type constants (PRISM since ROS 2 Humble); MBM writes the names instead."""
DIMENSIONS = {"box": ("x", "y", "z"), "sphere": ("radius",), "cylinder": ("height", "radius")}
"""The ``dimensions`` of each primitive armanim takes, in SolidPrimitive's order (BOX_X=0, BOX_Y=1,
BOX_Z=2; SPHERE_RADIUS=0; CYLINDER_HEIGHT=0, CYLINDER_RADIUS=1)."""
TEXT_DIMENSIONS = {"box": ("x", "y", "z"), "sphere": ("radius",), "cylinder": ("radius", "length")}
"""The numbers after each shape word of a ``.scene`` file (geometric_shapes' ``saveAsText``: radius first)."""
UNSUPPORTED_HINT = "armanim's obstacles are boxes, spheres and cylinders: replace it with those, or remove it"
PLANNING_FRAMES = ("", "world", "/world")
"""Frame ids that name the planning frame itself (with the URDF's root link and any fixed frame at identity)."""


@dataclass(frozen=True)
class Solid:
    """One primitive of a collision object, in the planning frame.

    Attributes
    ----------
    kind : str
        ``box``, ``sphere`` or ``cylinder`` (axis: the local z).
    size : tuple of float
        box (x, y, z) full edges; sphere (radius,); cylinder (length, radius). Metres.
    pose : ndarray, shape (4, 4)
        The primitive's frame in the planning frame: the object's pose times the primitive's.
    name : str
        The object's id, suffixed ``-2``, ``-3``... for its second, third... primitive.
    line : int or None
    """

    kind: str
    size: tuple[float, ...]
    pose: np.ndarray
    name: str
    line: int | None


@dataclass(frozen=True)
class JointValue:
    """One joint's position from a joint state or a joint constraint (radians or metres, as in ROS)."""

    name: str
    value: float
    line: int | None
    path: str = ""  # its field, e.g. ``start_state.joint_state.name[2]``


@dataclass(frozen=True)
class PlanningWorld:
    """A planning scene's shapes and robot state.

    ``state`` maps each joint name of ``robot_state.joint_state`` to its value (empty for a ``.scene``
    file, which has no robot state).
    """

    file: str
    solids: tuple[Solid, ...]
    state: dict[str, JointValue] = field(default_factory=dict)
    notes: tuple[Diagnostic, ...] = ()


@dataclass(frozen=True)
class PoseTarget:
    """A pose goal: where the point ``offset`` (in ``link``'s frame) must be, and how ``link`` is turned.

    ``quaternion_wxyz`` is None for a position-only goal.
    """

    link: str
    position: np.ndarray
    quaternion_wxyz: np.ndarray | None
    offset: np.ndarray
    line: int | None


@dataclass(frozen=True)
class MotionRequest:
    """A motion plan request: the start state, the planning group, and one goal (joints or a pose)."""

    file: str
    start: dict[str, JointValue]
    group: str | None
    joint_goal: tuple[JointValue, ...] | None
    pose_goal: PoseTarget | None
    goal_line: int | None
    notes: tuple[Diagnostic, ...] = ()
    group_line: int | None = None


@dataclass(frozen=True)
class PlanningGroup:
    """An SRDF ``<group>``: its ``<chain>`` ends, or its ``<joint>`` and ``<link>`` names, in file order."""

    name: str
    chain: tuple[str, str] | None
    joints: tuple[str, ...]
    links: tuple[str, ...]
    line: int


class Frames:
    """The frames a ``header.frame_id`` may name, each with its pose in the planning frame.

    ``fixed`` maps a frame id to its (4, 4) transform: the URDF's links rigidly attached to the root,
    the planning scene's ``fixed_frame_transforms``. ``""`` and ``world`` are the planning frame.

    >>> Frames({"base": np.eye(4)}).pose("world", "x.yaml", "header.frame_id", 3).tolist()[0]
    [1.0, 0.0, 0.0, 0.0]
    """

    def __init__(self, fixed: dict[str, np.ndarray]):
        self.fixed = dict(fixed)

    def with_fixed(self, more: dict[str, np.ndarray]) -> Frames:
        """These frames and ``more`` (a planning scene's fixed frames)."""
        return Frames({**more, **self.fixed})

    def pose(self, frame: str, file: str, path: str, line: int | None) -> np.ndarray:
        """The transform of ``frame`` in the planning frame; SceneError if it is not a fixed frame."""
        if frame in PLANNING_FRAMES:
            return np.eye(4)
        key = frame[1:] if frame.startswith("/") else frame
        if key in self.fixed:
            return self.fixed[key]
        known = ", ".join(sorted(self.fixed)[:8]) or "none"
        raise SceneError(
            file,
            [
                Diagnostic(
                    path,
                    f"frame {shown(frame)} is not the planning frame or a frame fixed to it "
                    f"(expected '' or world, the robot's root link, or a link or fixed frame "
                    f"that never moves: {known})",
                    line,
                )
            ],
        )


def rigid_pose(position, quaternion_xyzw) -> np.ndarray:
    """The (4, 4) transform of a ROS pose: a position and an x-y-z-w quaternion (normalised).

    >>> rigid_pose([1, 2, 3], [0, 0, 1, 0])[:3].round(12).tolist()
    [[-1.0, 0.0, 0.0, 1.0], [0.0, -1.0, 0.0, 2.0], [0.0, 0.0, 1.0, 3.0]]
    """
    x, y, z, w = (float(v) for v in quaternion_xyzw)
    pose = np.eye(4)
    pose[:3, :3] = quaternion_rotation([w, x, y, z])
    pose[:3, 3] = [float(v) for v in position]
    return pose


class YamlReader:
    """Typed access to a YAML document with field paths and lines: every wrong value a SceneError."""

    def __init__(self, doc: YamlDocument, file: str):
        self.doc, self.file = doc, file

    def line(self, path: str) -> int | None:
        return self.doc.line_of(path)

    def error(self, path: str, message: str) -> SceneError:
        return SceneError(self.file, [Diagnostic(path, message, self.line(path))])

    def mapping(self, value, path: str) -> dict:
        """A mapping (``None``: empty)."""
        if value is None:
            return {}
        if not isinstance(value, dict):
            raise self.error(path, f"must be a mapping of keys (got {_kind(value)})")
        return value

    def sequence(self, value, path: str) -> list:
        """A list (``None``: empty)."""
        if value is None:
            return []
        if not isinstance(value, list):
            raise self.error(path, f"must be a list (got {_kind(value)})")
        return value

    def number(self, value, path: str) -> float:
        """A finite number."""
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise self.error(path, f"must be a finite number (got {_kind(value)})")
        return float(value)

    def text(self, value, path: str, default: str = "") -> str:
        """A string (``None``: ``default``); a number is read as its text, as ROS's YAML does for ids."""
        if value is None:
            return default
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            return str(value)
        if not isinstance(value, str):
            raise self.error(path, f"must be a string (got {_kind(value)})")
        return value

    def vector(self, value, path: str, keys: str) -> list[float]:
        """A list of ``len(keys)`` numbers, or a mapping of ``keys`` (ROS's message form; a missing key is 0)."""
        if isinstance(value, list):
            if len(value) != len(keys):
                raise self.error(path, f"has {len(value)} items (expected {len(keys)}: [{', '.join(keys)}])")
            return [self.number(v, join_path(path, k)) for k, v in enumerate(value)]
        if isinstance(value, dict):
            extra = [k for k in value if k not in keys]
            if extra:
                raise self.error(
                    join_path(path, extra[0]), f"unknown key {shown(str(extra[0]))} (expected {', '.join(keys)})"
                )
            return [self.number(value.get(k, 0), join_path(path, k)) for k in keys]
        raise self.error(
            path, f"must be a list [{', '.join(keys)}] or a mapping of {', '.join(keys)} (got {_kind(value)})"
        )

    def pose(self, value, path: str) -> np.ndarray:
        """A geometry_msgs/Pose as a (4, 4) transform (``None`` or missing parts: the identity's)."""
        value = self.mapping(value, path)
        position = self.vector(value.get("position", [0, 0, 0]), join_path(path, "position"), "xyz")
        where = join_path(path, "orientation")
        quaternion = (
            self.vector(value["orientation"], where, "xyzw")
            if value.get("orientation") is not None
            else [0.0, 0.0, 0.0, 1.0]
        )
        return rigid_pose(position, self.unit_quaternion(quaternion, where))

    def unit_quaternion(self, q: list[float], path: str) -> list[float]:
        """``q`` (x, y, z, w) if it has a length to normalise; the zero quaternion is refused."""
        if not math.hypot(*q) > 1e-9:
            raise self.error(
                path, "is the zero quaternion (expected x, y, z, w of a rotation, e.g. [0, 0, 0, 1] for none)"
            )
        return q


def _kind(value) -> str:
    if value is None:
        return "null"
    if isinstance(value, bool):
        return str(value).lower()
    if isinstance(value, (list, dict)):
        return f"a {type(value).__name__}"
    return shown(value) if isinstance(value, str) else repr(value)


def read_yaml_file(path: str | Path, what: str) -> YamlReader:
    """A MoveIt YAML file read with lines (bounded as a scene file is)."""
    path = Path(path)
    raw = read_bounded(path, MAX_FILE_BYTES, what)
    doc = read_yaml(decode_scene(raw, str(path)), str(path))
    if doc.problems:
        raise SceneError(str(path), list(doc.problems))
    if not isinstance(doc.data, dict):
        raise SceneError(
            str(path), [Diagnostic("", f"the top level is {_kind(doc.data)} (expected a mapping: {what})", 1)]
        )
    return YamlReader(doc, str(path))


# ---------------------------------------------------------------- planning scene, YAML


PLANNING_SCENE_FIELDS = (
    *("name", "robot_state", "robot_model_name", "fixed_frame_transforms", "allowed_collision_matrix"),
    *("link_padding", "link_scale", "object_colors", "world", "is_diff", "collision_objects", "octomap"),
)
"""The fields of ``moveit_msgs/PlanningScene`` (and of a ``PlanningSceneWorld``, read the same way)."""
REQUEST_FIELDS = (
    *("workspace_parameters", "start_state", "goal_constraints", "path_constraints", "trajectory_constraints"),
    *("reference_trajectories", "pipeline_id", "planner_id", "group_name", "num_planning_attempts"),
    *("allowed_planning_time", "max_velocity_scaling_factor", "max_acceleration_scaling_factor"),
    *("cartesian_speed_end_effector_link", "max_cartesian_speed", "cartesian_speed_limited_link"),
)
"""The fields of ``moveit_msgs/MotionPlanRequest`` (ROS 1 and 2)."""


def _of_its_kind(reader: YamlReader, data: dict, fields: tuple[str, ...], what: str, every: bool) -> None:
    """A SceneError at the first top-level key that is not one of ``fields``: at any such key
    (``every``), else only when no key is one (a message of another ROS version may add fields).

    Campaign 11: a motion plan request or an armanim scene given as the planning scene was read as
    an empty world, exit 0 (the keys it did not know were ignored).
    """
    foreign = [key for key in data if key not in fields]
    if not foreign or (not every and len(foreign) < len(data)):
        return
    looks = next(
        (
            hint
            for known, hint in (
                (REQUEST_FIELDS, "it looks like a motion plan request: give it with --request"),
                (PLANNING_SCENE_FIELDS, "it looks like a planning scene: give it as SCENE"),
                (("version", "arm", "goals"), "it looks like an armanim scene, which needs no import"),
            )
            if known is not fields and set(map(str, foreign)) & set(known)
        ),
        "",
    )
    raise reader.error(
        join_path("", str(foreign[0])),
        f"is not a field of {what} (expected one of: {', '.join(fields)})" + (f"; {looks}" if looks else ""),
    )


def read_planning_scene(path: str | Path, frames: Frames) -> PlanningWorld:
    """A planning scene file: MoveIt's ``.scene`` text if its name ends in ``.scene``, else a
    ``moveit_msgs/PlanningScene`` in YAML (or a ``PlanningSceneWorld``: ``collision_objects`` at the top).

    Raises
    ------
    SceneError
        A malformed file, a mesh, plane, cone or prism, an object in a frame that moves, an
        attached object (``FILE:LINE: field: message``).
    """
    if Path(path).suffix == ".scene":
        return read_scene_text(path, frames)
    reader = read_yaml_file(path, "a MoveIt planning scene (moveit_msgs/PlanningScene as YAML)")
    data = cast(dict, reader.doc.data)  # read_yaml_file checked it is a mapping
    _of_its_kind(reader, data, PLANNING_SCENE_FIELDS, "a MoveIt planning scene", every=True)
    frames = frames.with_fixed(_fixed_frames(reader, data.get("fixed_frame_transforms")))
    top = "world" if "world" in data or "collision_objects" not in data else ""  # a PlanningSceneWorld has no world:
    world = reader.mapping(data.get("world"), "world") if top else data
    objects_path = join_path(top, "collision_objects")
    solids: list[Solid] = []
    seen: dict[str, int | None] = {}
    for k, item in enumerate(reader.sequence(world.get("collision_objects"), objects_path)):
        obj_path = join_path(objects_path, k)
        obj = reader.mapping(item, obj_path)
        name = reader.text(obj.get("id"), join_path(obj_path, "id"))
        if name and name in seen:
            raise reader.error(
                join_path(obj_path, "id"),
                f"id {shown(name)} is used again (first on line {seen[name]}; "
                "MoveIt would replace that object: keep one)",
            )
        seen[name] = reader.line(join_path(obj_path, "id"))
        solids += collision_object_solids(reader, obj, obj_path, name or f"object{k + 1}", frames)
    octomap_path = join_path(top, "octomap")
    octomap = reader.mapping(
        reader.mapping(world.get("octomap"), octomap_path).get("octomap"), join_path(octomap_path, "octomap")
    )
    if octomap.get("data"):
        raise reader.error(
            octomap_path, "an octomap is not read (expected collision objects: boxes, spheres, cylinders)"
        )
    state = reader.mapping(data.get("robot_state"), "robot_state")
    _no_attached_objects(reader, state, "robot_state")
    _base_not_moved(reader, state, "robot_state")
    return PlanningWorld(
        reader.file, tuple(solids), joint_state(reader, state.get("joint_state"), "robot_state.joint_state")
    )


def _fixed_frames(reader: YamlReader, transforms, path: str = "fixed_frame_transforms") -> dict[str, np.ndarray]:
    """The planning scene's fixed frames (geometry_msgs/TransformStamped, in the planning frame)."""
    out = {}
    for k, item in enumerate(reader.sequence(transforms, path)):
        where = join_path(path, k)
        item = reader.mapping(item, where)
        name = reader.text(item.get("child_frame_id"), join_path(where, "child_frame_id"))
        parent = reader.text(reader.mapping(item.get("header"), join_path(where, "header")).get("frame_id"), where)
        if parent not in PLANNING_FRAMES:
            continue  # a chain of fixed frames: not followed (none of MoveIt's exports writes one)
        t = reader.mapping(item.get("transform"), join_path(where, "transform"))
        translation = reader.vector(t.get("translation", [0, 0, 0]), join_path(where, "transform.translation"), "xyz")
        rotation = reader.vector(t.get("rotation", [0, 0, 0, 1]), join_path(where, "transform.rotation"), "xyzw")
        if name:
            out[name.lstrip("/")] = rigid_pose(
                translation, reader.unit_quaternion(rotation, join_path(where, "transform.rotation"))
            )
    return out


def collision_object_solids(reader: YamlReader, obj: dict, path: str, name: str, frames: Frames) -> list[Solid]:
    """The primitives of one moveit_msgs/CollisionObject in the planning frame: its header's frame,
    then its ``pose``, then each primitive's pose."""
    operation = obj.get("operation", 0)
    if operation not in (0, "add", "ADD", "b'\\x00'", None):  # ros2 topic echo writes a byte so
        raise reader.error(
            join_path(path, "operation"),
            f"operation {_kind(operation)} is not read (expected ADD, 0: "
            "the importer reads a whole scene, not changes to one)",
        )
    for key, what in (("meshes", "a mesh"), ("planes", "a plane")):
        if reader.sequence(obj.get(key), join_path(path, key)):
            raise reader.error(join_path(path, key), f"object {shown(name)} has {what} ({UNSUPPORTED_HINT})")
    header = reader.mapping(obj.get("header"), join_path(path, "header"))
    frame_path = join_path(path, "header.frame_id")
    base = frames.pose(
        reader.text(header.get("frame_id"), frame_path), reader.file, frame_path, reader.line(frame_path)
    )
    base = base @ reader.pose(obj.get("pose"), join_path(path, "pose"))
    primitives = reader.sequence(obj.get("primitives"), join_path(path, "primitives"))
    poses = reader.sequence(obj.get("primitive_poses"), join_path(path, "primitive_poses"))
    if len(poses) != len(primitives):
        raise reader.error(
            join_path(path, "primitive_poses"),
            f"object {shown(name)} has {len(primitives)} primitives and "
            f"{len(poses)} primitive_poses (expected one pose per primitive)",
        )
    solids = []
    for k, (primitive, pose) in enumerate(zip(primitives, poses)):
        where = join_path(path, f"primitives[{k}]")
        kind, size = _primitive(reader, primitive, where, name)
        solids.append(
            Solid(
                kind,
                size,
                base @ reader.pose(pose, join_path(path, f"primitive_poses[{k}]")),
                name if k == 0 else f"{name}-{k + 1}",
                reader.line(where),
            )
        )
    return solids


def _primitive(reader: YamlReader, value, path: str, name: str) -> tuple[str, tuple[float, ...]]:
    """(kind, sizes) of a shape_msgs/SolidPrimitive: its type as the constant or its name."""
    value = reader.mapping(value, path)
    raw = value.get("type")
    kind = (
        PRIMITIVE_TYPES.get(raw)
        if isinstance(raw, int) and not isinstance(raw, bool)
        else raw.lower()
        if isinstance(raw, str)
        else None
    )
    type_path = join_path(path, "type")
    if kind not in ("box", "sphere", "cylinder", "cone", "prism"):
        raise reader.error(
            type_path, f"type {_kind(raw)} is not a SolidPrimitive type (expected box (1), sphere (2), cylinder (3))"
        )
    if kind not in DIMENSIONS:
        raise reader.error(type_path, f"object {shown(name)} has a {kind} ({UNSUPPORTED_HINT})")
    names = DIMENSIONS[kind]
    dims_path = join_path(path, "dimensions")
    dims = reader.sequence(value.get("dimensions"), dims_path)
    if len(dims) != len(names):
        raise reader.error(
            dims_path, f"a {kind} has {len(dims)} dimensions (expected {len(names)}: [{', '.join(names)}])"
        )
    size = tuple(reader.number(v, join_path(dims_path, k)) for k, v in enumerate(dims))
    _positive_sizes(reader.error, dims_path, kind, names, size)
    return kind, size


def _positive_sizes(error, path: str, kind: str, names, size) -> None:
    for label, v in zip(names, size):
        if not v > 0:
            raise error(path, f"a {kind}'s {label} is {v:g} (expected a size > 0, metres)")


def _no_attached_objects(reader: YamlReader, state: dict, path: str) -> None:
    where = join_path(path, "attached_collision_objects")
    if reader.sequence(state.get("attached_collision_objects"), where):
        raise reader.error(
            where, "an object attached to the robot is not read (expected it in world.collision_objects, or left out)"
        )


def _base_not_moved(reader: YamlReader, state: dict, path: str) -> None:
    """A multi-DOF joint (MoveIt's virtual joint) must leave the robot's root at the planning frame."""
    where = join_path(path, "multi_dof_joint_state")
    multi = reader.mapping(state.get("multi_dof_joint_state"), where)
    for k, item in enumerate(reader.sequence(multi.get("transforms"), join_path(where, "transforms"))):
        at = join_path(where, f"transforms[{k}]")
        item = reader.mapping(item, at)
        t = reader.vector(item.get("translation", [0, 0, 0]), join_path(at, "translation"), "xyz")
        q = reader.unit_quaternion(
            reader.vector(item.get("rotation", [0, 0, 0, 1]), join_path(at, "rotation"), "xyzw"), at
        )
        if not np.allclose(rigid_pose(t, q), np.eye(4), atol=1e-12):
            raise reader.error(
                at,
                "moves the robot's root away from the planning frame (expected the identity: "
                "armanim's arm stands at the planning frame; move the objects instead)",
            )


def joint_state(reader: YamlReader, value, path: str) -> dict[str, JointValue]:
    """A sensor_msgs/JointState's positions by name (``None``: none)."""
    value = reader.mapping(value, path)
    names = reader.sequence(value.get("name"), join_path(path, "name"))
    positions = reader.sequence(value.get("position"), join_path(path, "position"))
    if len(names) != len(positions):
        raise reader.error(
            join_path(path, "position"),
            f"has {len(positions)} positions for {len(names)} names (expected one position per name)",
        )
    out: dict[str, JointValue] = {}
    for k, (name, position) in enumerate(zip(names, positions)):
        at = join_path(path, f"name[{k}]")
        name = reader.text(name, at)
        if name in out:
            raise reader.error(at, f"joint {shown(name)} is named twice (first on line {out[name].line}; keep one)")
        out[name] = JointValue(name, reader.number(position, join_path(path, f"position[{k}]")), reader.line(at), at)
    return out


# ---------------------------------------------------------------- planning scene, .scene text


@dataclass
class _Tokens:
    """The words of a ``.scene`` file with their lines, read one after another."""

    file: str
    words: list[tuple[str, int]]
    at: int = 0

    def error(self, message: str, line: int | None = None) -> SceneError:
        if line is None:
            line = self.words[min(self.at, len(self.words) - 1)][1] if self.words else 1
        return SceneError(self.file, [Diagnostic("", message, line)])

    def word(self, what: str) -> tuple[str, int]:
        if self.at >= len(self.words):
            raise self.error(
                f"the file ends where {what} was expected (a .scene file ends with a line '.')",
                self.words[-1][1] if self.words else 1,
            )
        self.at += 1
        return self.words[self.at - 1]

    def number(self, what: str) -> float:
        word, line = self.word(what)
        try:
            value = float(word)
        except ValueError:
            raise self.error(f"{shown(word)} is not a number (expected {what})", line) from None
        if not math.isfinite(value):
            raise self.error(f"{shown(word)} is not finite (expected {what})", line)
        return value

    def count(self, what: str) -> int:
        word, line = self.word(what)
        if not word.isdigit():
            raise self.error(f"{shown(word)} is not a count (expected {what}: a whole number >= 0)", line)
        return int(word)

    def pose(self, what: str) -> np.ndarray:
        position = [self.number(f"{what}: x y z") for _ in range(3)]
        line = self.words[self.at - 1][1]
        quaternion = [self.number(f"{what}: a quaternion x y z w") for _ in range(4)]
        if not math.hypot(*quaternion) > 1e-9:
            raise self.error(f"{what} has the zero quaternion (expected x y z w of a rotation)", line)
        return rigid_pose(position, quaternion)


def read_scene_text(path: str | Path, frames: Frames | None = None) -> PlanningWorld:
    """A ``.scene`` file as RViz's Motion Planning panel exports it, in either of MoveIt's formats
    (the newer one gives each object a pose line and a subframe count: a line with spaces after
    the first ``*`` line). Shape poses are relative to their object's pose, which is in the
    planning frame.

    >>> import tempfile, os
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = os.path.join(d, "s.scene")
    ...     _ = open(p, "w").write("shelf\\n* pole\\n1\\ncylinder\\n0.05 1\\n0 0 0.5\\n0 0 0 1\\n0 0 0 0\\n.\\n")
    ...     w = read_scene_text(p)
    >>> [(s.kind, s.size, float(s.pose[2, 3])) for s in w.solids]
    [('cylinder', (1.0, 0.05), 0.5)]
    """
    path = Path(path)
    text = decode_scene(read_bounded(path, MAX_FILE_BYTES, "a MoveIt .scene file"), str(path))
    lines = text.splitlines()
    if not lines:
        raise SceneError(
            str(path), [Diagnostic("", "the file is empty (expected a MoveIt .scene: a name line, objects, '.')", 1)]
        )
    objects_at = next((k for k, line in enumerate(lines) if line.strip().startswith("*")), None)
    newer = objects_at is not None and objects_at + 1 < len(lines) and " " in lines[objects_at + 1].strip()
    tokens, solids = _Tokens(str(path), []), []
    k = 1
    while k < len(lines):
        stripped = lines[k].strip()
        if stripped.startswith("*"):  # the id is the rest of the line, spaces and all
            tokens.words.append(("*", k + 1))
            tokens.words.append((stripped[1:].strip(), k + 1))
        else:
            tokens.words += [(w, k + 1) for w in stripped.split()]
        k += 1
    names: dict[str, int] = {}
    while True:
        marker, line = tokens.word("'*' (an object) or '.' (the end)")
        if marker == ".":
            break
        if marker != "*":
            raise tokens.error(
                f"{shown(marker)} is not a marker (expected '* NAME' to start an object, or '.' to end the scene)", line
            )
        name, line = tokens.word("the object's name")
        if name in names:
            raise tokens.error(f"object {shown(name)} is defined again (first on line {names[name]}; keep one)", line)
        names[name] = line
        solids += _text_object(tokens, name, line, newer)
    extra = tokens.words[tokens.at :]
    if extra:
        raise tokens.error(
            f"{shown(extra[0][0])} after the '.' that ends the scene (expected nothing more)", extra[0][1]
        )
    return PlanningWorld(str(path), tuple(solids))


def _line_error(tokens: _Tokens, line: int, _path: str, message: str) -> SceneError:
    return tokens.error(message, line)


def _text_object(tokens: _Tokens, name: str, line: int, newer: bool) -> list[Solid]:
    """One object of a ``.scene`` file: its pose (newer format), shapes, subframes (newer format)."""
    object_pose = tokens.pose(f"object {shown(name)}'s pose") if newer else np.eye(4)
    solids = []
    for k in range(tokens.count(f"object {shown(name)}'s number of shapes")):
        word, at = tokens.word("a shape: box, sphere or cylinder")
        if word not in TEXT_DIMENSIONS:
            known = word in ("cone", "plane", "mesh", "octree")
            raise tokens.error(
                f"object {shown(name)} has a {word} ({UNSUPPORTED_HINT})"
                if known
                else f"{shown(word)} is not a shape (expected box, sphere or cylinder)",
                at,
            )
        labels = TEXT_DIMENSIONS[word]
        numbers = tuple(tokens.number(f"the {word}'s {label}") for label in labels)
        _positive_sizes(functools.partial(_line_error, tokens, at), "", word, labels, numbers)
        size = (numbers[1], numbers[0]) if word == "cylinder" else numbers  # (length, radius), as from YAML
        pose = tokens.pose(f"the {word}'s pose")
        for _ in range(4):
            tokens.number("the shape's colour r g b a")
        solids.append(Solid(word, size, object_pose @ pose, name if k == 0 else f"{name}-{k + 1}", at))
    if newer:
        for _ in range(tokens.count(f"object {shown(name)}'s number of subframes")):
            tokens.word("a subframe's name")
            tokens.pose("the subframe's pose")
    return solids


# ---------------------------------------------------------------- motion plan request


def read_motion_request(path: str | Path, frames: Frames) -> MotionRequest:
    """A ``moveit_msgs/MotionPlanRequest`` in YAML: its start state, group and first goal.

    Raises
    ------
    SceneError
        A malformed file, a goal with neither joint nor position constraints, or with both.
    """
    reader = read_yaml_file(path, "a MoveIt motion plan request (moveit_msgs/MotionPlanRequest as YAML)")
    data = cast(dict, reader.doc.data)  # read_yaml_file checked it is a mapping
    _of_its_kind(reader, data, REQUEST_FIELDS, "a MoveIt motion plan request", every=False)
    start_value = reader.mapping(data.get("start_state"), "start_state")
    _no_attached_objects(reader, start_value, "start_state")
    _base_not_moved(reader, start_value, "start_state")
    start = joint_state(reader, start_value.get("joint_state"), "start_state.joint_state")
    group = reader.text(data.get("group_name"), "group_name") or None
    goals = reader.sequence(data.get("goal_constraints"), "goal_constraints")
    notes = []
    group_line = reader.line("group_name") if group is not None else None
    if not goals:
        return MotionRequest(reader.file, start, group, None, None, None, group_line=group_line)
    if len(goals) > 1:
        notes.append(
            Diagnostic(
                "goal_constraints",
                f"has {len(goals)} goals, which MoveIt reads as alternatives: the first is imported",
                reader.line("goal_constraints[1]"),
            )
        )
    path0 = "goal_constraints[0]"
    goal = reader.mapping(goals[0], path0)
    joints = reader.sequence(goal.get("joint_constraints"), join_path(path0, "joint_constraints"))
    positions = reader.sequence(goal.get("position_constraints"), join_path(path0, "position_constraints"))
    if joints and positions:
        raise reader.error(
            path0, "has joint_constraints and position_constraints (expected one kind: a joint goal or a pose goal)"
        )
    if joints:
        return MotionRequest(
            reader.file,
            start,
            group,
            _joint_goal(reader, joints, join_path(path0, "joint_constraints")),
            None,
            reader.line(path0),
            tuple(notes),
            group_line,
        )
    if positions:
        return MotionRequest(
            reader.file,
            start,
            group,
            None,
            _pose_goal(reader, goal, path0, frames),
            reader.line(path0),
            tuple(notes),
            group_line,
        )
    raise reader.error(
        path0,
        "has no joint_constraints and no position_constraints (expected a joint goal, or a position "
        "constraint on a link with an optional orientation constraint)",
    )


def _joint_goal(reader: YamlReader, items: list, path: str) -> tuple[JointValue, ...]:
    out: dict[str, JointValue] = {}
    for k, item in enumerate(items):
        at = join_path(path, k)
        item = reader.mapping(item, at)
        name = reader.text(item.get("joint_name"), join_path(at, "joint_name"))
        if not name:
            raise reader.error(at, "has no joint_name (expected joint_name and position)")
        if name in out:
            raise reader.error(
                at, f"joint {shown(name)} is constrained twice (first on line {out[name].line}; keep one)"
            )
        if "position" not in item:
            raise reader.error(
                at, f"joint {shown(name)} has no position (expected radians, or metres for a prismatic joint)"
            )
        out[name] = JointValue(name, reader.number(item["position"], join_path(at, "position")), reader.line(at), at)
    return tuple(out.values())


def _pose_goal(reader: YamlReader, goal: dict, path: str, frames: Frames) -> PoseTarget:
    """The pose goal of one position constraint (the centre of its region's first primitive) and at
    most one orientation constraint on the same link."""
    positions = reader.sequence(goal.get("position_constraints"), join_path(path, "position_constraints"))
    orientations = reader.sequence(goal.get("orientation_constraints"), join_path(path, "orientation_constraints"))
    if len(positions) > 1 or len(orientations) > 1:
        which = "position_constraints" if len(positions) > 1 else "orientation_constraints"
        raise reader.error(
            join_path(path, f"{which}[1]"),
            f"has more than one of {which} (expected one, on the link whose pose is the goal)",
        )
    at = join_path(path, "position_constraints[0]")
    constraint = reader.mapping(positions[0], at)
    link = reader.text(constraint.get("link_name"), join_path(at, "link_name"))
    if not link:
        raise reader.error(at, "has no link_name (expected the link whose point must reach the region)")
    frame = _frame(reader, constraint, at, frames)
    offset = np.array(
        reader.vector(constraint.get("target_point_offset", [0, 0, 0]), join_path(at, "target_point_offset"), "xyz")
    )
    region = reader.mapping(constraint.get("constraint_region"), join_path(at, "constraint_region"))
    poses = reader.sequence(region.get("primitive_poses"), join_path(at, "constraint_region.primitive_poses"))
    if not poses:
        raise reader.error(
            join_path(at, "constraint_region"),
            "has no primitive_poses (expected the region's centre as its first "
            "primitive pose: where the link's point must be)",
        )
    centre = frame @ reader.pose(poses[0], join_path(at, "constraint_region.primitive_poses[0]"))
    quaternion = None
    if orientations:
        o_at = join_path(path, "orientation_constraints[0]")
        o = reader.mapping(orientations[0], o_at)
        o_link = reader.text(o.get("link_name"), join_path(o_at, "link_name")) or link
        if o_link != link:
            raise reader.error(
                join_path(o_at, "link_name"),
                f"constrains link {shown(o_link)}, the position constraint "
                f"{shown(link)} (expected one link whose pose is the goal)",
            )
        o_frame = _frame(reader, o, o_at, frames)
        where = join_path(o_at, "orientation")
        x, y, z, w = reader.unit_quaternion(reader.vector(o.get("orientation", [0, 0, 0, 1]), where, "xyzw"), where)
        quaternion = quaternion_product(rotation_quaternion(o_frame[:3, :3]), np.array([w, x, y, z]))
        norm = float(np.linalg.norm(quaternion))
        quaternion = quaternion / norm if abs(norm - 1.0) > 1e-12 else quaternion  # a unit one is kept as written
    return PoseTarget(link, centre[:3, 3].copy(), quaternion, offset, reader.line(join_path(at, "link_name")))


def quaternion_product(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The Hamilton product a b of quaternions (w, x, y, z): the rotation b, then a.

    >>> quaternion_product(np.array([1.0, 0, 0, 0]), np.array([0.5, 0.5, 0.5, 0.5])).tolist()
    [0.5, 0.5, 0.5, 0.5]
    """
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return np.array(
        [
            w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
            w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
            w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
            w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2,
        ]
    )


def _frame(reader: YamlReader, constraint: dict, path: str, frames: Frames) -> np.ndarray:
    header = reader.mapping(constraint.get("header"), join_path(path, "header"))
    where = join_path(path, "header.frame_id")
    return frames.pose(reader.text(header.get("frame_id"), where), reader.file, where, reader.line(where))


# ---------------------------------------------------------------- SRDF groups


def srdf_groups(raw: bytes, file: str) -> dict[str, PlanningGroup]:
    """The SRDF's ``<group>`` elements by name, each with its chain, joints and links.

    >>> srdf_groups(b'<robot name="r"><group name="arm"><chain base_link="a" tip_link="c"/></group></robot>', "r.srdf")["arm"].chain
    ('a', 'c')
    """
    root = _parse_xml(raw, file)
    if root.tag != "robot":
        raise SceneError(
            file, [Diagnostic("", f"the top element is <{root.tag}> (expected <robot>: an SRDF file)", root.line)]
        )
    groups = {}
    for el in root.findall("group"):
        name = el.attrib.get("name", "")
        chains = el.findall("chain")
        chain = None
        if chains:
            base, tip = chains[0].attrib.get("base_link"), chains[0].attrib.get("tip_link")
            if base is None or tip is None:
                raise SceneError(
                    file, [Diagnostic("", "a <chain> needs base_link and tip_link attributes", chains[0].line)]
                )
            chain = base, tip
        groups[name] = PlanningGroup(
            name,
            chain,
            tuple(j.attrib.get("name", "") for j in el.findall("joint")),
            tuple(k.attrib.get("name", "") for k in el.findall("link")),
            el.line,
        )
    return groups
