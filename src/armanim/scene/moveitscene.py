"""A MoveIt planning scene and motion plan request become an armanim scene file.

:func:`moveit_scene` returns the scene (a mapping and its YAML text) and notes; :func:`import_moveit`
also writes it, atomically, replacing only a file this importer wrote. The files are read by
:mod:`armanim.scene.moveit`; the robot is a URDF (with an optional SRDF) or a bundled robot.

What becomes what (docs/moveit-import.md):

- the chain: ``--tip-link``, else the SRDF's planning group (the request's ``group_name``, else its
  first group with a chain or joints), else the request's joints (or its pose goal's link). The
  arm starts at the URDF's root when no joint moves between the root and the group's base link;
- the start state (the scene's ``robot_state``, the request's ``start_state`` over it): the chain's
  joints become ``arm.home`` (degrees, or metres for a prismatic joint), the robot's other moving joints ``arm.joint_values``
  (degrees, or metres for a prismatic joint); fixed and mimic joints are noted and left out;
- joint constraints become ``- {joints: [...]}`` (degrees or metres, in the chain's order); a position and
  orientation constraint becomes ``- {position: ..., orientation: {quaternion_wxyz: ...}}`` with the
  constraint's ``target_point_offset`` as ``arm.tool.xyz``;
- boxes, spheres and cylinders become obstacles named after their object's ``id``;
- ``solver.clearance`` and ``solver.self_clearance`` are :data:`CLEARANCE` and :data:`SELF_CLEARANCE`.
"""

from __future__ import annotations

import functools
import hashlib
import json
import math
import os
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from armanim.arm.rotations import axis_angle_rotation, rpy_rotation
from armanim.errors import Diagnostic, OutputError, SceneError, UsageError, shown, shown_list
from armanim.output.files import read_bounded, resolved
from armanim.scene.moveit import (
    Frames,
    JointValue,
    MotionRequest,
    PlanningWorld,
    PoseTarget,
    Solid,
    read_motion_request,
    read_planning_scene,
    srdf_groups,
)
from armanim.scene.urdf import MAX_URDF_BYTES, MOVING, Robot, _parse_xml, chain_joints, read_urdf

CLEARANCE = 0.0005
"""``solver.clearance`` an imported scene gets, metres. MotionBenchMaker's starts and goals come within
1.1 mm of an object (Panda) and 2.1 mm (UR5): 0.5 mm keeps every part of the arm off the objects and
admits nearly all of them (docs/moveit-import.md has the measurement). MoveIt itself checks contact (0)."""
SELF_CLEARANCE = 0.0005
"""``solver.self_clearance`` an imported scene gets, metres (``panda_link5``/``panda_link7`` come within
10.8 mm in MotionBenchMaker's problems; 0.5 mm is a gap, not MoveIt's contact, and admits them)."""
MARKER = "# armanim import moveit:"
"""How an imported scene's first line begins; it ends with the sha256 of the lines below it. The importer
replaces only such a file, unchanged since (:func:`unedited_import`)."""
PLAIN_KEY = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
PLAIN_TEXT = re.compile(r"[A-Za-z_.][A-Za-z0-9_./-]*")
"""Names and paths written without quotes (when YAML reads them back as the same string)."""
TINY = 1e-12
"""Coordinates and angles this small are written 0 (the rounding of a rotation's conversions)."""


@dataclass(frozen=True)
class RobotSource:
    """The robot an import uses: a bundled ``robot``, or a ``urdf`` file with an optional ``srdf``;
    ``tip_link`` chooses the chain's end."""

    robot: str | None = None
    urdf: Path | None = None
    srdf: Path | None = None
    tip_link: str | None = None


@dataclass(frozen=True)
class ImportedScene:
    """An imported scene: its mapping, its YAML text, and notes (``FILE:LINE: message``) on what was
    left out or changed."""

    data: dict
    text: str
    notes: tuple[str, ...]


@dataclass(frozen=True)
class _Robot:
    """The robot's files as read: the URDF, the SRDF's bytes, a bundled robot's own chain ends."""

    urdf: Robot
    srdf: bytes | None
    base_link: str | None
    tip_link: str | None
    home: dict[str, float] | None = None  # a bundled robot's own home, degrees, by joint name


@dataclass(frozen=True)
class _Arm:
    """The robot and the chain an import chose."""

    robot: Robot
    base_link: str
    tip_link: str
    chain: tuple[str, ...]  # the moving joints from base_link to tip_link


# ---------------------------------------------------------------- the robot and its chain


def _read_robot(source: RobotSource) -> _Robot:
    """The files of ``source``."""
    if (source.robot is None) == (source.urdf is None):
        raise UsageError("give the robot with exactly one of --robot NAME (a bundled robot) or --urdf FILE")
    if source.robot is not None:
        from armanim.scene.robots import ROBOTS, bundled_robot

        if source.robot not in ROBOTS:
            raise UsageError(
                f"--robot {shown(source.robot)} is not bundled (expected one of: {', '.join(ROBOTS)}; "
                "or give your own file with --urdf)"
            )
        if source.srdf is not None:
            raise UsageError("--srdf goes with --urdf (a bundled robot brings its own allowed-collision matrix)")
        bundled = bundled_robot(source.robot)
        urdf = read_urdf(bundled.urdf, f"robot {bundled.name}'s URDF")
        chain = [j.name for j in urdf.path(bundled.base_link, bundled.tip_link) if j.kind in MOVING]
        return _Robot(urdf, None, bundled.base_link, bundled.tip_link, dict(zip(chain, bundled.home)))
    srdf = read_bounded(source.srdf, MAX_URDF_BYTES, "an SRDF file") if source.srdf is not None else None
    assert source.urdf is not None, "a robot that is not bundled comes from --urdf (RobotSource)"
    return _Robot(read_urdf(source.urdf), srdf, None, None)


def _depth(robot: Robot, link: str) -> int:
    """How many joints lie between the root and ``link``."""
    up, depth = robot.parent_joint, 0
    while link in up:
        link, depth = up[link].parent, depth + 1
    return depth


def _deepest_child(robot: Robot, joints: list[str]) -> str:
    """The child link of the joint among ``joints`` that lies deepest below the root."""
    return max((robot.joints[j].child for j in joints), key=lambda link: _depth(robot, link))


def _group_tip(robot: Robot, srdf: bytes, srdf_file: str, request: MotionRequest | None) -> tuple[str | None, str]:
    """(base_link or None, tip_link) of the SRDF's planning group: the request's ``group_name``, else the
    SRDF's first group with a chain or joints."""
    groups = srdf_groups(srdf, srdf_file)
    name = request.group if request is not None else None
    if request is not None and name is not None and name not in groups:
        raise SceneError(
            request.file,
            [
                Diagnostic(
                    "group_name",
                    f"group {shown(name)} is not a group of {srdf_file} "
                    f"(expected one of: {shown_list(groups) or 'none'}; or give --tip-link)",
                    request.group_line,
                )
            ],
        )
    if name is None:
        name = next((g.name for g in groups.values() if g.chain or g.joints), None)
        if name is None:
            raise SceneError(
                srdf_file,
                [
                    Diagnostic(
                        "",
                        "has no <group> with a <chain> or <joint> (expected the planning group; or give --tip-link)",
                        1,
                    )
                ],
            )
    group = groups[name]
    for link in (*(group.chain or ()), *group.links):
        if link not in robot.links:
            raise SceneError(
                srdf_file,
                [
                    Diagnostic(
                        "",
                        f"group {shown(name)} names link {shown(link)}, not a link of "
                        f"{robot.file} (expected one of: {shown_list(robot.links)})",
                        group.line,
                    )
                ],
            )
    if group.chain:
        return group.chain
    for joint in group.joints:
        if joint not in robot.joints:
            raise SceneError(
                srdf_file,
                [
                    Diagnostic(
                        "",
                        f"group {shown(name)} names joint {shown(joint)}, not a joint of "
                        f"{robot.file} (expected one of: {shown_list(robot.joints)})",
                        group.line,
                    )
                ],
            )
    moving = [j for j in group.joints if robot.joints[j].kind in MOVING]
    if moving:
        return None, _deepest_child(robot, moving)
    if group.links:
        return None, max(group.links, key=lambda link: _depth(robot, link))
    raise SceneError(
        srdf_file,
        [
            Diagnostic(
                "",
                f"group {shown(name)} has no moving joint (expected the arm's planning group; or give --tip-link)",
                group.line,
            )
        ],
    )


def _request_tip(robot: Robot, request: MotionRequest | None) -> str:
    """The tip the request implies: its pose goal's link, or the deepest of its joint goal's joints."""
    if request is not None and request.pose_goal is not None:
        return request.pose_goal.link
    if request is not None and request.joint_goal:
        for value in request.joint_goal:
            _known_joint(robot, value, request.file)
        return _deepest_child(robot, [v.name for v in request.joint_goal])
    if len(robot.leaves) == 1:
        return robot.leaves[0]
    raise UsageError(
        f"{robot.file} has {len(robot.leaves)} leaf links ({shown_list(robot.leaves)}): say where the arm ends "
        "with --tip-link LINK, or give --srdf with its planning group"
    )


def _choose_arm(source: RobotSource, files: _Robot, request: MotionRequest | None) -> _Arm:
    """The chain: ``--tip-link``, the bundled robot's, the SRDF group's, or the request's; a pose goal's
    link as its tip when the same joints move it."""
    robot, base, tip = files.urdf, files.base_link, files.tip_link
    if source.tip_link is not None:
        tip = source.tip_link
    elif files.srdf is not None:
        base, tip = _group_tip(robot, files.srdf, str(source.srdf), request)
    elif tip is None:
        tip = _request_tip(robot, request)
    pose = request.pose_goal if request is not None else None
    if request is not None and pose is not None:
        _known_link(robot, pose, request.file)
    for label, link in (("tip_link", tip), ("base_link", base)):
        if link is not None and link not in robot.links:
            raise UsageError(
                f"{label} {shown(link)} is not a link of {robot.file} (expected one of: {shown_list(robot.links)})"
            )
    if request is not None and pose is not None:
        tip = _pose_link(robot, base or robot.root, tip, pose, request.file)
    base = files.base_link if files.base_link is not None else _arm_base(robot, base)  # a bundled robot's own base
    assert tip is not None  # --tip-link, the bundled robot's, the group's or the request's
    joints = chain_joints(robot, base, tip)
    return _Arm(robot, base, tip, tuple(j.name for j in joints if j.axis is not None))


def _arm_base(robot: Robot, base: str | None) -> str:
    """The URDF's root, unless a joint moves between it and the group's ``base``: then ``base``."""
    if base is None or not any(j.kind != "fixed" for j in robot.path(robot.root, base)):
        return robot.root
    return base


def _known_link(robot: Robot, goal: PoseTarget, file: str) -> None:
    if goal.link not in robot.links:
        raise SceneError(
            file,
            [
                Diagnostic(
                    "goal_constraints[0].position_constraints[0].link_name",
                    f"link {shown(goal.link)} is not a link of {robot.file} "
                    f"(expected one of: {shown_list(robot.links)})",
                    goal.line,
                )
            ],
        )


def _pose_link(robot: Robot, base: str, tip: str, goal: PoseTarget, file: str) -> str:
    """The tip for a pose goal on ``goal.link``: that link, if the same joints move it as move ``tip``."""
    moving = [j.name for j in robot.path(base, tip) if j.kind != "fixed"]
    try:
        carried = [j.name for j in robot.path(base, goal.link) if j.kind != "fixed"]
    except SceneError:
        carried = None
    if carried != moving:
        raise SceneError(
            file,
            [
                Diagnostic(
                    "goal_constraints[0].position_constraints[0].link_name",
                    f"link {shown(goal.link)} is not moved by the chain's joints ({shown_list(moving)}) "
                    f"alone (expected a link fixed to {shown(tip)}, or --tip-link {goal.link})",
                    goal.line,
                )
            ],
        )
    return goal.link


# ---------------------------------------------------------------- frames, limits


def _joint_motion(joint, value: float) -> np.ndarray:
    """The (4, 4) motion of a joint at ``value`` (radians or metres) after its origin."""
    motion = np.eye(4)
    if joint.kind == "fixed":
        return motion
    axis = joint.axis / np.linalg.norm(joint.axis)
    if joint.kind in MOVING:
        motion[:3, :3] = axis_angle_rotation(axis, value)
    elif joint.kind == "prismatic":
        motion[:3, 3] = axis * value
    return motion


def link_pose(robot: Robot, link: str, values: dict[str, float]) -> np.ndarray:
    """The (4, 4) pose of ``link`` in the root's frame, each joint at ``values`` (0 where not given).

    >>> from armanim.scene.urdf import parse_urdf
    >>> r = parse_urdf(b'<robot name="r"><link name="a"/><link name="b"/><joint name="j" type="prismatic">'
    ...     b'<parent link="a"/><child link="b"/><axis xyz="0 0 1"/><origin xyz="1 0 0"/></joint></robot>', "r.urdf")
    >>> link_pose(r, "b", {"j": 0.5})[:3, 3].tolist()
    [1.0, 0.0, 0.5]
    """
    pose = np.eye(4)
    for joint in robot.path(robot.root, link):
        pose = pose @ joint.origin @ _joint_motion(joint, values.get(joint.name, 0.0))
    return pose


def fixed_frames(robot: Robot) -> Frames:
    """The frames a MoveIt file may use: the root and every link no joint moves relative to it."""
    frames = {}
    for link in robot.links:
        path = robot.path(robot.root, link)
        if all(j.kind == "fixed" for j in path):
            frames[link] = link_pose(robot, link, {})
    return Frames(frames)


def joint_limits(robot: Robot) -> dict[str, tuple[float, float]]:
    """``<limit lower upper>`` of every revolute and prismatic joint (the URDF reader keeps only the
    revolute ones)."""
    out = {name: j.limits for name, j in robot.joints.items() if j.limits is not None}
    if not any(j.kind == "prismatic" for j in robot.joints.values()):
        return out  # the URDF is not parsed again
    for el in _parse_xml(robot.raw, robot.file).findall("joint"):
        limit = el.find("limit")
        if el.attrib.get("type") == "prismatic" and limit is not None:
            try:
                out[el.attrib.get("name", "")] = (
                    float(limit.attrib.get("lower", 0)),
                    float(limit.attrib.get("upper", 0)),
                )
            except ValueError:
                continue  # armanim never moves it: its default value is then 0
    return out


# ---------------------------------------------------------------- joints


def _known_joint(robot: Robot, value: JointValue, file: str):
    joint = robot.joints.get(value.name)
    if joint is None:
        raise SceneError(
            file,
            [
                Diagnostic(
                    value.path,
                    f"joint {shown(value.name)} is not a joint of {robot.file} "
                    f"(expected one of: {shown_list(robot.joints)})",
                    value.line,
                )
            ],
        )
    return joint


def _within(value: JointValue, limits: tuple[float, float] | None, file: str) -> None:
    if limits is not None and not limits[0] <= value.value <= limits[1]:
        raise SceneError(
            file,
            [
                Diagnostic(
                    value.path,
                    f"joint {shown(value.name)} at {value.value!r} is outside its limits "
                    f"[{limits[0]!r}, {limits[1]!r}] (MoveIt's bounds are inclusive: "
                    "expected a value within them)",
                    value.line,
                )
            ],
        )


def _start_values(world: PlanningWorld, request: MotionRequest | None) -> dict[str, tuple[str, JointValue]]:
    """The start state by joint name, with its file: the scene's ``robot_state``, the request's over it."""
    values = {name: (world.file, v) for name, v in world.state.items()}
    if request is not None:
        values.update({name: (request.file, v) for name, v in request.start.items()})
    return values


def _arm_state(
    arm: _Arm, start: dict[str, tuple[str, JointValue]], limits, own_home: dict[str, float] | None = None
) -> tuple[list[float], dict, list[str]]:
    """(home in degrees, joint_values, notes) of the start state; a chain joint it leaves out takes the
    bundled robot's own home (``own_home``), else MoveIt's default value."""
    robot, notes, others = arm.robot, [], {}
    for name, (file, value) in start.items():
        joint = _known_joint(robot, value, file)
        if name in arm.chain:
            _within(value, limits.get(name), file)
        elif joint.kind == "fixed":
            notes.append(
                f"note: {file}:{value.line}: joint {shown(name)} is fixed in {robot.file}: its value {value.value!r} is not used"
            )
        elif joint.mimic:
            notes.append(
                f"note: {file}:{value.line}: joint {shown(name)} mimics another joint: its value is not written"
            )
        elif joint.kind in ("floating", "planar"):
            raise SceneError(
                file,
                [
                    Diagnostic(
                        value.path,
                        f"joint {shown(name)} is {joint.kind}: a joint_state cannot "
                        "set it (expected a revolute, continuous or prismatic joint)",
                        value.line,
                    )
                ],
            )
        else:
            others[name] = _off_chain_value(joint, value, limits.get(name), file, notes)
    home, missing = [], []
    for name in arm.chain:
        if name in start:
            home.append(scene_value(robot.joints[name], start[name][1].value, notes))
            continue
        missing.append(name)
        if own_home and name in own_home:
            home.append(float(own_home[name]))
        else:
            lo, hi = limits.get(name, (-math.inf, math.inf))
            home.append(scene_value(robot.joints[name], 0.0 if lo <= 0.0 <= hi else (lo + hi) / 2, notes))
    if missing:
        slides = any(robot.joints[n].kind == "prismatic" for n in missing)  # then each value its unit
        given = [
            f"{home[arm.chain.index(n)]:g}"
            + ((" m" if robot.joints[n].kind == "prismatic" else " degrees") if slides else "")
            for n in missing
        ]
        whose = (
            "the robot's own home" if own_home and all(n in own_home for n in missing) else "MoveIt's default values"
        )
        notes.append(
            f"note: no start value for {shown_list(missing)}: {', '.join(given)}{'' if slides else ' degrees'} ({whose})"
        )
    return home, others, notes


def scene_value(joint, value: float, notes: list[str]) -> float:
    """A joint's ROS value (radians, or metres for a prismatic joint) as a scene writes it: degrees
    (:func:`joint_degrees`), metres as they are.

    >>> from types import SimpleNamespace
    >>> scene_value(SimpleNamespace(name="rail", kind="prismatic"), 0.25, []), scene_value(SimpleNamespace(name="j", kind="revolute"), 0.0, [])
    (0.25, 0.0)
    """
    return float(value) if joint.kind == "prismatic" else joint_degrees(joint, value, notes)


def joint_degrees(joint, radians: float, notes: list[str]) -> float:
    """A revolute or continuous joint's value in degrees; a continuous joint's beyond one turn either
    way (a scene's angles are within [-360, 360]) taken within [-180, 180], as MoveIt normalises it,
    with a note.

    >>> from types import SimpleNamespace
    >>> notes = []
    >>> joint_degrees(SimpleNamespace(name="j", kind="continuous"), 7 * math.pi / 2, notes), len(notes)
    (-90.0, 1)
    """
    degrees = math.degrees(radians)
    if joint.kind == "continuous" and abs(degrees) > 360:
        turned = math.remainder(degrees, 360.0)
        notes.append(
            f"note: continuous joint {shown(joint.name)} at {radians!r} rad is {turned:g} degrees within one turn "
            "(a scene's angles are within [-360, 360])"
        )
        return turned
    return degrees


def _off_chain_value(joint, value: JointValue, limits, file: str, notes: list[str]) -> float:
    """A joint off the chain as ``arm.joint_values`` writes it (degrees, or metres for prismatic),
    moved within its limits (a note says so) as MoveIt's start-state fix does."""
    v = value.value
    if limits is not None and not limits[0] <= v <= limits[1]:
        clamped = min(max(v, limits[0]), limits[1])
        notes.append(
            f"note: {file}:{value.line}: joint {shown(joint.name)} at {v!r} is outside its limits "
            f"[{limits[0]!r}, {limits[1]!r}]: {clamped!r} is written"
        )
        v = clamped
    return scene_value(joint, v, notes)


def _joint_goal(arm: _Arm, request: MotionRequest, limits, notes: list[str]) -> list[float]:
    """The joint goal in degrees (metres for a prismatic joint), in the chain's order."""
    path = "goal_constraints[0].joint_constraints"
    given = {}
    for value in request.joint_goal or ():
        _known_joint(arm.robot, value, request.file)
        if value.name not in arm.chain:
            raise SceneError(
                request.file,
                [
                    Diagnostic(
                        value.path,
                        f"joint {shown(value.name)} is not one of the chain's joints from "
                        f"{arm.base_link} to {arm.tip_link} ({shown_list(arm.chain)}; "
                        "expected those, or another --tip-link)",
                        value.line,
                    )
                ],
            )
        _within(value, limits.get(value.name), request.file)
        given[value.name] = value.value
    missing = [name for name in arm.chain if name not in given]
    if missing:
        raise SceneError(
            request.file,
            [
                Diagnostic(
                    path,
                    f"sets no position for {shown_list(missing)} (expected one joint "
                    f"constraint per joint of the chain: {shown_list(arm.chain)})",
                    request.goal_line,
                )
            ],
        )
    return [scene_value(arm.robot.joints[name], given[name], notes) for name in arm.chain]


# ---------------------------------------------------------------- the scene


def _clean(values) -> list[float]:
    """Floats with rounding noise (below :data:`TINY`) written as 0."""
    return [0.0 if abs(float(v)) < TINY else float(v) for v in values]


def rpy_of(rotation: np.ndarray) -> np.ndarray:
    """URDF's roll, pitch, yaw (radians) of a rotation, well conditioned at every pitch: pitch and yaw
    from the first column, then roll from what is left (``rpy_rotation([0, pitch, yaw]).T @ rotation``,
    an x rotation), so R = Rz(yaw) Ry(pitch) Rx(roll) holds to rounding even next to pitch = +-90 degrees.

    >>> from armanim.arm.rotations import rpy_rotation
    >>> r = rpy_rotation([0.3, np.pi / 2 - 1e-9, -0.2])
    >>> bool(np.abs(rpy_rotation(rpy_of(r)) - r).max() < 1e-15)
    True
    """
    pitch = math.atan2(-rotation[2, 0], math.hypot(rotation[0, 0], rotation[1, 0]))
    yaw = math.atan2(rotation[1, 0], rotation[0, 0]) if math.hypot(rotation[0, 0], rotation[1, 0]) > 0 else 0.0
    rest = rpy_rotation([0.0, pitch, yaw]).T @ rotation
    return np.array([math.atan2(rest[2, 1], rest[2, 2]), pitch, yaw])


def _rpy_degrees(pose: np.ndarray) -> list[float]:
    return _clean(np.degrees(rpy_of(pose[:3, :3])))


def obstacle(solid: Solid) -> dict:
    """An armanim obstacle of a MoveIt primitive (``rpy`` in degrees, URDF's R = Rz Ry Rx).

    >>> obstacle(Solid("cylinder", (0.14, 0.03), np.eye(4), "can", 1))
    {'cylinder': {'center': [0.0, 0.0, 0.0], 'length': 0.14, 'radius': 0.03, 'rpy': [0.0, 0.0, 0.0]}, 'name': 'can'}
    """
    center = _clean(solid.pose[:3, 3])
    if solid.kind == "sphere":
        return {"center": center, "radius": solid.size[0], "name": solid.name}
    if solid.kind == "box":
        return {
            "box": {"center": center, "size": list(solid.size), "rpy": _rpy_degrees(solid.pose)},
            "name": solid.name,
        }
    length, radius = solid.size
    return {
        "cylinder": {"center": center, "length": length, "radius": radius, "rpy": _rpy_degrees(solid.pose)},
        "name": solid.name,
    }


NAME_MAX = 100
"""The longest obstacle ``name`` a scene takes."""


def obstacle_names(solids) -> list[str]:
    """One name per primitive, unique within the scene, at most :data:`NAME_MAX` characters, control
    characters written ``_``: the object's id (``-2``, ``-3``... for its further primitives), suffixed
    ``-N`` again where that would repeat another's.

    >>> obstacle_names([Solid("sphere", (1.0,), np.eye(4), n, 1) for n in ("a", "a-2", "a-2", "b\\nc")])
    ['a', 'a-2', 'a-2-2', 'b_c']
    """
    taken: set[str] = set()
    names = []
    for solid in solids:
        base = "".join(c if c.isprintable() else "_" for c in solid.name) or "object"
        name, k = base[:NAME_MAX], 1
        while name in taken:
            k += 1
            name = base[: NAME_MAX - len(f"-{k}")] + f"-{k}"
        taken.add(name)
        names.append(name)
    return names


def _relative(path: Path, folder: Path) -> str:
    """``path`` relative to ``folder`` (forward slashes), as a scene's file fields are."""
    return Path(os.path.relpath(resolved(path), resolved(folder))).as_posix()  # a folder that loops: no RuntimeError


def _arm_section(
    arm: _Arm, source: RobotSource, defaults: _Robot, out_dir: Path, placement: np.ndarray, home, others, tool_xyz
) -> dict:
    """The ``arm`` section; ``placement`` is base_link's pose in the planning frame (written as
    ``base`` and ``base_rpy`` unless it is the identity); a bundled robot's own chain ends (``defaults``)
    are left out."""
    section: dict
    if source.robot is not None:
        section = {"robot": source.robot}
    else:
        assert source.urdf is not None, "a bundled robot or --urdf (RobotSource)"
        section = {"urdf": _relative(source.urdf, out_dir)}
    if source.robot is None or arm.base_link != defaults.base_link:
        section["base_link"] = arm.base_link
    if source.robot is None or arm.tip_link != defaults.tip_link:
        section["tip_link"] = arm.tip_link
    if not np.allclose(placement, np.eye(4), rtol=0, atol=TINY):
        section["base"] = _clean(placement[:3, 3])
        section["base_rpy"] = _rpy_degrees(placement)
    if tool_xyz is not None and any(abs(v) > 0 for v in tool_xyz):
        section["tool"] = {"xyz": _clean(tool_xyz)}
    if source.srdf is not None:
        section["self_collision"] = {"srdf": _relative(source.srdf, out_dir)}
    section["home"] = home
    if others:
        section["joint_values"] = others
    return section


def moveit_scene(scene: str | Path, request: str | Path | None, source: RobotSource, out: str | Path) -> ImportedScene:
    """The armanim scene of a MoveIt planning scene and motion plan request, to be written at ``out``
    (its folder is what ``arm.urdf`` and ``self_collision.srdf`` are relative to).

    Raises
    ------
    SceneError
        A file is malformed or names what the robot does not have (``FILE:LINE: message``, exit 2).
    UsageError
        The flags do not fit (exit 2).
    """
    files = _read_robot(source)
    frames = fixed_frames(files.urdf)
    world = read_planning_scene(scene, frames)
    motion = read_motion_request(request, frames) if request is not None else None
    arm = _choose_arm(source, files, motion)
    limits = joint_limits(arm.robot)
    start = _start_values(world, motion)
    home, others, notes = _arm_state(arm, start, limits, files.home)
    goal, tool = _goal(arm, motion, home, limits, notes)
    out = Path(out)
    placement = link_pose(arm.robot, arm.base_link, {name: v.value for name, (_, v) in start.items()})
    data = {
        "version": 1,
        **({"name": name} if (name := run_name(out)) is not None else {}),
        "arm": _arm_section(arm, source, files, out.parent, placement, home, others, tool),
        "obstacles": [{**obstacle(s), "name": name} for s, name in zip(world.solids, obstacle_names(world.solids))],
        "goals": [goal],
        "solver": {"clearance": CLEARANCE, "self_clearance": SELF_CLEARANCE},
    }
    notes = ["note: " + n.format(f.file) for f, n in _file_notes(world, motion)] + notes
    sources = [Path(scene).name] + ([Path(request).name] if request is not None else [])
    return ImportedScene(data, scene_text(data, sources), tuple(notes))


def run_name(out: Path) -> str | None:
    """The ``name:`` an imported scene needs: None when the output file's stem is a valid run name (the
    scene takes it), else the stem with every other character ``-``.

    >>> run_name(Path("shelf.yaml")), run_name(Path("my shelf (2).yaml")), run_name(Path("-.yaml"))
    (None, 'my-shelf--2-', 'moveit-scene')
    """
    from armanim.scene.models import name_problem

    if name_problem(out.stem) is None:
        return None
    name = re.sub(r"[^A-Za-z0-9._-]", "-", out.stem).lstrip("._-")[:NAME_MAX]
    return name if name and name_problem(name) is None else "moveit-scene"


def _file_notes(world: PlanningWorld, motion: MotionRequest | None):
    return [(world, n) for n in world.notes] + ([(motion, n) for n in motion.notes] if motion is not None else [])


def _goal(
    arm: _Arm, motion: MotionRequest | None, home: list[float], limits, notes: list[str]
) -> tuple[dict, list | None]:
    """(the goal, the tool's xyz or None)."""
    if motion is None or (motion.joint_goal is None and motion.pose_goal is None):
        notes.append("note: no goal in the request: the goal is the start pose (edit goals: to give one)")
        return {"joints": list(home)}, None
    if motion.joint_goal is not None:
        return {"joints": _joint_goal(arm, motion, limits, notes)}, None
    pose = motion.pose_goal
    assert pose is not None  # not a joint goal, and a goal
    goal: dict = {"position": _clean(pose.position)}
    if pose.quaternion_wxyz is not None:
        goal["orientation"] = {"quaternion_wxyz": _clean(pose.quaternion_wxyz)}
    return goal, list(pose.offset)


# ---------------------------------------------------------------- the text


def yaml_number(value: float) -> str:
    """A float as YAML reads it back exactly (a dot in every float, as YAML 1.1 wants).

    >>> yaml_number(1e-05), yaml_number(-0.0), yaml_number(0.04), yaml_number(3)
    ('1.0e-05', '0.0', '0.04', '3.0')
    """
    value = float(value)
    if value == 0:
        return "0.0"
    text = repr(value)
    mantissa, _, exponent = text.partition("e")
    if exponent and "." not in mantissa:
        text = f"{mantissa}.0e{exponent}"
    return text


def flow(value) -> str:
    """A value in YAML's flow style: names quoted as JSON strings (which YAML reads as they are).

    >>> flow({"box": {"center": [1, 0, 0.5]}, "name": "a b"})
    '{box: {center: [1.0, 0.0, 0.5]}, name: "a b"}'
    """
    if isinstance(value, dict):
        return "{" + ", ".join(f"{_key(k)}: {flow(v)}" for k, v in value.items()) + "}"
    if isinstance(value, list):
        return "[" + ", ".join(flow(v) for v in value) + "]"
    if isinstance(value, str):
        return value if _plain(value) else json.dumps(value)
    if isinstance(value, bool):
        return str(value).lower()
    return yaml_number(value)


@functools.lru_cache(maxsize=4096)
def _plain(text: str) -> bool:
    """Whether YAML reads ``text`` written bare as this very string (a name or a relative path), as
    PyYAML's and the scene's resolvers both take it: a string, not a number, boolean or null.

    >>> _plain("panda_link0"), _plain("../robot.urdf"), _plain("on"), _plain("1e3"), _plain("a b")
    (True, True, False, False, False)
    """
    import yaml

    from armanim.scene.yamlscalars import SceneLoader

    if not PLAIN_TEXT.fullmatch(text):
        return False
    return all(
        loader("").resolve(yaml.ScalarNode, text, (True, False)) == "tag:yaml.org,2002:str"
        for loader in (yaml.SafeLoader, SceneLoader)
    )


def _key(key: str) -> str:
    return key if PLAIN_KEY.fullmatch(key) and _plain(key) else json.dumps(key)


def scene_text(data: dict, sources: list[str]) -> str:
    """The scene file's text: the importer's first line (with the sha256 of the rest: :func:`unedited_import`),
    then one line per field, obstacle and goal."""
    lines = [
        "# (from a MoveIt planning scene and motion plan request: armanim import moveit replaces this file "
        "only while it is as written)",
        "version: 1",
    ]
    for key, value in data.items():
        if key == "version":
            continue
        if isinstance(value, dict):
            lines.append(f"{key}:")
            lines += [f"  {_key(k)}: {flow(v)}" for k, v in value.items()]
        elif isinstance(value, list):
            lines.append(f"{key}:" + ("" if value else " []"))
            lines += [f"  - {flow(v)}" for v in value]
        else:
            lines.append(f"{key}: {flow(value)}")
    body = "\n".join(lines) + "\n"
    head = f"{MARKER} written from {' and '.join(json.dumps(s) for s in sources)}; sha256 {_digest(body)}"
    return head + "\n" + body  # json.dumps escapes every control and non-ASCII character: one line


def _digest(body: str) -> str:
    return hashlib.sha256(body.encode("utf-8")).hexdigest()


def unedited_import(raw: bytes) -> bool:
    """Whether ``raw`` is a scene this importer wrote, unchanged since: its first line is the importer's
    and ends with the sha256 of the lines below it.

    >>> text = scene_text({"version": 1, "goals": [[0.5, 0, 0.5]]}, ["s.yaml"])
    >>> unedited_import(text.encode()), unedited_import(text.replace("0.5", "0.6").encode())
    (True, False)
    """
    head, newline, body = raw.partition(b"\n")
    if not newline or not head.startswith(MARKER.encode()):
        return False
    return head.rsplit(b" ", 1)[-1] == hashlib.sha256(body).hexdigest().encode()


# ---------------------------------------------------------------- writing


MAX_REPLACED_BYTES = 4 * 1024 * 1024
"""A file larger than this at ``--out`` is not read to see whether the importer wrote it (it did not)."""


def replace_problem(target: Path) -> str | None:
    """Why the import must not be written at ``target``, or None (nothing there, or a scene it wrote,
    unchanged since)."""
    if os.path.islink(target) and not target.exists():
        return "is a link to nothing, which armanim did not make"
    if not target.exists():
        return None
    if target.is_dir():
        return "is a folder (expected a file name, e.g. scene.yaml)"
    if not target.is_file():
        return "is not a regular file, so armanim does not write there"
    try:
        with open(target, "rb") as handle:
            raw = handle.read(MAX_REPLACED_BYTES + 1)
    except OSError as exc:
        return f"cannot be read ({exc.strerror or exc}), so it is not replaced"
    if not raw.startswith(MARKER.encode()):
        return "is a file armanim import did not write (its first line is not the importer's), so it is not replaced"
    if not unedited_import(raw):
        return "was written by armanim import but changed since, so it is not replaced"
    return None


def import_moveit(scene: str | Path, request: str | Path | None, source: RobotSource, out: str | Path) -> ImportedScene:
    """Read a MoveIt planning scene and request, and write the armanim scene at ``out`` atomically.

    Raises
    ------
    SceneError, UsageError
        As :func:`moveit_scene`.
    OutputError
        ``out`` is a file the importer did not write, or one edited since, or could not be written
        (exit 3, as ``export`` and a run folder refuse what armanim did not make).
    """
    from armanim.output.atomic import write_text_atomic

    out = Path(out)
    problem = replace_problem(out)
    if problem is not None:
        raise OutputError(f"--out {out}: {problem} (move it away, or choose another file with --out)")
    imported = moveit_scene(scene, request, source, out)
    write_text_atomic(out, imported.text)
    return imported
