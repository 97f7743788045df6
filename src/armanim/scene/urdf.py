"""Read a URDF robot description: its joints, links and collision primitives, with lines.

Untrusted input is parsed with expat under guards (the job ``defusedxml`` does): no DTD
and so no entity expansion, at most :data:`MAX_URDF_BYTES`, :data:`MAX_DEPTH` levels of
nesting and :data:`MAX_ELEMENTS` elements (10,000 joints and their children). Meshes are
never read. Every problem is a :class:`SceneError` of ``FILE:LINE: message`` (exit 2).

The arm is the path from ``base_link`` to ``tip_link``, found by walking from the tip up
through each link's one parent joint (unique in a tree). Revolute and continuous joints
on it move, fixed ones fold into the next origin; any other type on it is an error. Links
off it below ``base_link`` (a gripper's fingers, a camera) hang from it at their joints' held
values (:func:`hanging_links`).
"""

from __future__ import annotations

import functools
import math
import re
import xml.parsers.expat
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from armanim.arm.chain import ChainJoint, transform
from armanim.errors import Diagnostic, SceneError, shown
from armanim.output.files import read_bounded, read_named_file
from armanim.scene.fields import LIMITS

MAX_URDF_BYTES = 4 * 1024 * 1024
"""A URDF without meshes is 10-100 KB; 4 MB leaves room for long comments."""
MAX_DEPTH = 32
MAX_ELEMENTS = 200_000
MAX_JOINTS = LIMITS["links"]  # moving joints on the arm's path: as many as an arm of links may have
MOVING = ("revolute", "continuous")
SLIDING = "prismatic"
ON_PATH = (*MOVING, SLIDING)
"""The joints an arm's path moves: they turn (radians) or slide (metres)."""
UNSUPPORTED = ("planar", "floating")
NUMBER = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")
"""A URDF number as XML Schema's double writes it: no ``_`` (Python's ``float`` reads
``-1_0`` as -10), no hex, no ``inf`` or ``nan``."""


@dataclass
class Element:
    """One XML element: tag, attributes, 1-based line, children."""

    tag: str
    attrib: dict
    line: int
    children: list = field(default_factory=list)

    def find(self, tag: str) -> Element | None:
        return next((c for c in self.children if c.tag == tag), None)

    def findall(self, tag: str) -> list[Element]:
        return [c for c in self.children if c.tag == tag]


@dataclass(frozen=True)
class Primitive:
    """A ``<collision>`` shape in its link's frame: ``kind`` cylinder, sphere, box or mesh."""

    kind: str
    origin: np.ndarray  # (4, 4)
    size: tuple[float, ...]  # cylinder (radius, length); sphere (radius,); box (x, y, z); mesh ()
    line: int


@dataclass(frozen=True)
class Joint:
    """A URDF joint as written (radians, metres)."""

    name: str
    kind: str
    parent: str
    child: str
    origin: np.ndarray
    axis: np.ndarray
    limits: tuple[float, float] | None
    mimic: bool
    line: int
    velocity: float | None = (
        None  # <limit velocity>, rad/s, as written (checked > 0 on the arm's path: :func:`joint_speeds`)
    )
    limit_line: int | None = None
    follows: tuple[str, float, float] | None = None
    """A mimic joint's ``<mimic joint multiplier offset>``: value = multiplier x the other's + offset."""


@dataclass(frozen=True)
class Robot:
    """A parsed URDF: links (with their collision primitives) and joints, by name, and the
    bytes it was parsed from."""

    file: str
    name: str
    links: dict[str, list[Primitive]]
    link_lines: dict[str, int]
    joints: dict[str, Joint]
    raw: bytes = b""

    @property
    def parent_joint(self) -> dict[str, Joint]:
        """Child link -> the joint above it."""
        return {j.child: j for j in self.joints.values()}

    @property
    def root(self) -> str:
        """The one link that is no joint's child."""
        children = {j.child for j in self.joints.values()}
        return next(name for name in self.links if name not in children)

    @property
    def leaves(self) -> list[str]:
        """Links that are no joint's parent, in file order."""
        parents = {j.parent for j in self.joints.values()}
        return [name for name in self.links if name not in parents]

    def path(self, base: str, tip: str) -> list[Joint]:
        """The joints from ``base`` down to ``tip``, in order (walking up from the tip)."""
        up = self.parent_joint
        joints, link = [], tip
        while link != base:
            joint = up.get(link)
            if joint is None:
                raise self.error(
                    f"no path from base_link {base!r} down to tip_link {tip!r} "
                    f"({tip!r} is not below {base!r}: choose links on one branch)",
                    self.link_lines[tip],
                )
            joints.append(joint)
            link = joint.parent
        return joints[::-1]

    def error(self, message: str, line: int | None = None) -> SceneError:
        return SceneError(self.file, [Diagnostic("", message, line)])


def read_urdf(path: Path, shown: str | None = None, field: str | None = None) -> Robot:
    """Read and check a URDF file (``shown`` names it in messages; default: the path). Named by a
    scene's ``field``, a file that cannot be read is reported at that field (a ValueError, as an
    SRDF's: campaign 11, a scene's ``arm.urdf`` of a folder, a FIFO or a missing file said only
    ``sub: is a folder ...``, without the scene's line); its contents' problems are the URDF's own
    ``FILE:LINE``."""
    what = "a URDF robot description"
    raw = (
        read_bounded(path, MAX_URDF_BYTES, what)
        if field is None
        else read_named_file(field, path, MAX_URDF_BYTES, what)
    )
    return _parsed(raw, shown or str(path))


@functools.lru_cache(maxsize=8)
def _parsed(raw: bytes, file: str) -> Robot:
    """:func:`parse_urdf`, kept for the last few files read: a batch of scenes on one robot reads
    its URDF for each scene (the bytes may change between them) but parses the same bytes once."""
    return parse_urdf(raw, file)


def parse_urdf(raw: bytes, file: str) -> Robot:
    """Parse URDF bytes (``file`` names them in messages).

    >>> robot = parse_urdf(b'<robot name="r"><link name="a"/><link name="b"/>'
    ...     b'<joint name="j" type="continuous"><parent link="a"/><child link="b"/></joint></robot>', "r.urdf")
    >>> robot.root, robot.leaves, robot.joints["j"].axis.tolist()
    ('a', ['b'], [1.0, 0.0, 0.0])
    """
    root = _parse_xml(raw, file)
    if root.tag != "robot":
        raise SceneError(
            file, [Diagnostic("", f"the top element is <{root.tag}> (expected <robot>: a URDF file)", root.line)]
        )
    links: dict[str, list[Primitive]] = {}
    lines: dict[str, int] = {}
    for el in root.findall("link"):
        name = _name(el, file, "link")
        if name in links:
            raise SceneError(
                file, [Diagnostic("", f"link {name!r} is defined twice (first on line {lines[name]})", el.line)]
            )
        links[name], lines[name] = [_primitive(c, file) for c in el.findall("collision")], el.line
    joints: dict[str, Joint] = {}
    for el in root.findall("joint"):
        joint = _joint(el, file, links)
        if joint.name in joints:
            raise SceneError(
                file,
                [
                    Diagnostic(
                        "", f"joint {joint.name!r} is defined twice (first on line {joints[joint.name].line})", el.line
                    )
                ],
            )
        joints[joint.name] = joint
    if not links:
        raise SceneError(file, [Diagnostic("", "has no <link> (expected a robot's links and joints)", root.line)])
    robot = Robot(file, root.attrib.get("name", ""), links, lines, joints, raw)
    _check_tree(robot)
    return robot


def _parse_xml(raw: bytes, file: str) -> Element:
    """A tree of :class:`Element` from bytes, refusing DTDs, deep nesting and floods of elements."""
    parser = xml.parsers.expat.ParserCreate()
    stack: list[Element] = []
    top: list[Element] = []
    count = [0]

    def refuse(message: str) -> None:
        raise SceneError(file, [Diagnostic("", message, parser.CurrentLineNumber)])

    def start(tag, attrib):
        count[0] += 1
        if count[0] > MAX_ELEMENTS:
            refuse(f"has more than {MAX_ELEMENTS:,} elements (expected a robot description of at most 10,000 joints)")
        if len(stack) >= MAX_DEPTH:
            refuse(
                f"nests elements more than {MAX_DEPTH} deep (expected a URDF: robot, link, collision, geometry, ...)"
            )
        el = Element(tag, dict(attrib), parser.CurrentLineNumber)
        (stack[-1].children if stack else top).append(el)
        stack.append(el)

    def doctype(*_):
        refuse(
            "declares a DTD (<!DOCTYPE>), which URDF does not use and armanim does not read "
            "(entity expansion is refused: remove the declaration)"
        )

    parser.StartElementHandler = start
    parser.EndElementHandler = lambda tag: stack.pop()
    parser.StartDoctypeDeclHandler = doctype
    parser.EntityDeclHandler = doctype
    try:
        parser.Parse(raw, True)
    except xml.parsers.expat.ExpatError as exc:
        message = xml.parsers.expat.ErrorString(exc.code)
        raise SceneError(
            file, [Diagnostic("", f"is not well-formed XML: {message} (column {exc.offset + 1})", exc.lineno)]
        ) from None
    if not top:
        raise SceneError(file, [Diagnostic("", "has no elements (expected a <robot>)", 1)])
    return top[0]


def _name(el: Element, file: str, what: str) -> str:
    name = el.attrib.get("name")
    if not name:
        raise SceneError(
            file, [Diagnostic("", f"a <{what}> has no name attribute (every {what} needs a unique name)", el.line)]
        )
    return name


def _numbers(el: Element | None, key: str, count: int, default, file: str, what: str) -> tuple[float, ...]:
    """``count`` finite numbers from attribute ``key`` of ``el`` (``default`` when absent)."""
    if el is None or key not in el.attrib:
        return tuple(default)
    text = el.attrib[key]
    words = text.split()
    values = tuple(float(v) for v in words) if all(NUMBER.fullmatch(v) for v in words) else ()
    if len(values) != count or not all(math.isfinite(v) for v in values):
        raise SceneError(
            file,
            [
                Diagnostic(
                    "", f"{what}: {key}={shown(text)} (expected {count} finite numbers separated by spaces)", el.line
                )
            ],
        )
    big = LIMITS["magnitude"]
    if any(abs(v) > big for v in values):
        raise SceneError(
            file,
            [
                Diagnostic(
                    "",
                    f"{what}: {key}={shown(text)} has a number above {big:g} in size "
                    "(expected at most that, as in a scene: choose a smaller unit)",
                    el.line,
                )
            ],
        )
    return values


def _origin(el: Element, file: str, what: str) -> np.ndarray:
    origin = el.find("origin")
    xyz = _numbers(origin, "xyz", 3, (0.0, 0.0, 0.0), file, f"{what} <origin>")
    rpy = _numbers(origin, "rpy", 3, (0.0, 0.0, 0.0), file, f"{what} <origin>")
    return transform(xyz, rpy)


def _primitive(el: Element, file: str) -> Primitive:
    origin = _origin(el, file, "<collision>")
    geometry = el.find("geometry")
    shape = geometry.children[0] if geometry is not None and geometry.children else None
    if shape is None:
        return Primitive("mesh", origin, (), el.line)  # nothing usable: treated like a mesh
    sizes = {
        "cylinder": lambda: (
            *_numbers(shape, "radius", 1, (), file, "<cylinder>"),
            *_numbers(shape, "length", 1, (), file, "<cylinder>"),
        ),
        "sphere": lambda: _numbers(shape, "radius", 1, (), file, "<sphere>"),
        "box": lambda: _numbers(shape, "size", 3, (), file, "<box>"),
    }
    if shape.tag not in sizes:
        return Primitive("mesh", origin, (), shape.line)
    for attr in {"cylinder": ("radius", "length"), "sphere": ("radius",), "box": ("size",)}[shape.tag]:
        if attr not in shape.attrib:
            raise SceneError(file, [Diagnostic("", f"<{shape.tag}> has no {attr} attribute", shape.line)])
    size = sizes[shape.tag]()
    if any(v < 0 for v in size):
        raise SceneError(
            file, [Diagnostic("", f"<{shape.tag}> has a negative size {size} (expected sizes >= 0)", shape.line)]
        )
    return Primitive(shape.tag, origin, size, shape.line)


def _joint(el: Element, file: str, links: dict) -> Joint:
    name = _name(el, file, "joint")
    what = f"joint {name!r}"
    kind = el.attrib.get("type", "")
    ends = {}
    for end in ("parent", "child"):
        sub = el.find(end)
        link = sub.attrib.get("link") if sub is not None else None
        if not link:
            raise SceneError(file, [Diagnostic("", f"{what} has no <{end} link=...>", el.line)])
        if link not in links:
            assert sub is not None  # it named the link
            raise SceneError(
                file,
                [Diagnostic("", f"{what}: {end} link {link!r} is not defined (no <link name={link!r}>)", sub.line)],
            )
        ends[end] = link
    given = el.find("axis")
    axis = np.array(_numbers(given, "xyz", 3, (1.0, 0.0, 0.0), file, f"{what} <axis>"))
    if kind in ON_PATH and not np.abs(axis).max() > 0:  # the default is (1, 0, 0): an axis of zeros was given
        raise SceneError(
            file,
            [
                Diagnostic(
                    "",
                    f'{what} has the axis 0 0 0 (expected a direction, e.g. xyz="0 0 1")',
                    given.line if given is not None else el.line,
                )
            ],
        )
    limit = el.find("limit")
    limits = None
    if kind == "prismatic" and limit is not None:  # URDF's defaults: lower = upper = 0
        lower, upper = (_numbers(limit, k, 1, (0.0,), file, f"{what} <limit>")[0] for k in ("lower", "upper"))
        if not lower <= upper:
            raise SceneError(
                file, [Diagnostic("", f"{what}: <limit> lower {lower:g} is above upper {upper:g}", limit.line)]
            )
        limits = (lower, upper)
    if kind == "revolute":
        if limit is None or "lower" not in limit.attrib or "upper" not in limit.attrib:
            raise SceneError(
                file,
                [
                    Diagnostic(
                        "",
                        f"{what} is revolute but has no <limit lower=... upper=...> "
                        "(give its limits in radians, or make it continuous)",
                        el.line,
                    )
                ],
            )
        lower, upper = (_numbers(limit, k, 1, (), file, f"{what} <limit>")[0] for k in ("lower", "upper"))
        if not lower < upper:
            raise SceneError(
                file, [Diagnostic("", f"{what}: <limit> lower {lower:g} is not below upper {upper:g}", limit.line)]
            )
        limits = (lower, upper)
    velocity = None
    if kind in ON_PATH and limit is not None and "velocity" in limit.attrib:
        velocity = _numbers(limit, "velocity", 1, (), file, f"{what} <limit>")[0]
    return Joint(
        name,
        kind,
        ends["parent"],
        ends["child"],
        _origin(el, file, what),
        axis,
        limits,
        el.find("mimic") is not None,
        el.line,
        velocity,
        limit.line if limit is not None else None,
        _mimic(el.find("mimic"), file, what),
    )


def _mimic(el: Element | None, file: str, what: str) -> tuple[str, float, float] | None:
    """``<mimic joint= multiplier= offset=>`` as (joint, multiplier, offset), URDF's defaults 1 and 0."""
    if el is None:
        return None
    other = el.attrib.get("joint")
    if not other:
        raise SceneError(
            file, [Diagnostic("", f"{what}: <mimic> has no joint attribute (the joint it follows)", el.line)]
        )
    multiplier = _numbers(el, "multiplier", 1, (1.0,), file, f"{what} <mimic>")[0]
    offset = _numbers(el, "offset", 1, (0.0,), file, f"{what} <mimic>")[0]
    return other, multiplier, offset


def _check_tree(robot: Robot) -> None:
    """One parent per link, no cycle, one root."""
    file = robot.file
    parent: dict[str, Joint] = {}
    for joint in robot.joints.values():
        if joint.child in parent:
            first = parent[joint.child]
            raise SceneError(
                file,
                [
                    Diagnostic(
                        "",
                        f"link {joint.child!r} is the child of joints {first.name!r} (line {first.line}) "
                        f"and {joint.name!r} (a URDF is a tree: each link has one parent joint)",
                        joint.line,
                    )
                ],
            )
        parent[joint.child] = joint
    rooted: set[str] = set()  # links known to lead up to a root: each link is walked once
    for joint in robot.joints.values():
        seen, link = set(), joint.child
        while link in parent and link not in rooted:
            if link in seen:
                raise SceneError(
                    file,
                    [
                        Diagnostic(
                            "",
                            f"joints form a cycle through link {link!r} "
                            "(a URDF is a tree: follow the parent links to find it)",
                            parent[link].line,
                        )
                    ],
                )
            seen.add(link)
            link = parent[link].parent
        rooted |= seen
    roots = [name for name in robot.links if name not in parent]
    if len(roots) != 1:
        names = ", ".join(repr(r) for r in roots[:5])
        raise SceneError(
            file,
            [
                Diagnostic(
                    "",
                    f"has {len(roots)} root links ({names}; expected one link that no joint has as child)",
                    robot.link_lines[roots[1]] if len(roots) > 1 else None,
                )
            ],
        )


def chain_joints(robot: Robot, base: str, tip: str) -> list[ChainJoint]:
    """The joints from ``base`` to ``tip`` as the chain takes them; an unsupported joint on
    the path is an error naming it and its line."""
    out = []
    for joint in robot.path(base, tip):
        if joint.kind in UNSUPPORTED or joint.kind not in (*ON_PATH, "fixed"):
            kind = joint.kind or "(none)"
            raise robot.error(
                f"joint {joint.name!r} between {base!r} and {tip!r} is of type {kind!r} "
                "(armanim moves revolute, continuous and prismatic joints and folds fixed ones; "
                "choose another base_link or tip_link)",
                joint.line,
            )
        if joint.mimic and joint.kind in ON_PATH:
            raise robot.error(
                f"joint {joint.name!r} between {base!r} and {tip!r} mimics another joint "
                "(a mimic joint on the arm's path is not supported: choose another tip_link)",
                joint.line,
            )
        if joint.kind == SLIDING and (joint.limits is None or not joint.limits[0] < joint.limits[1]):
            raise robot.error(
                f"joint {joint.name!r} between {base!r} and {tip!r} is prismatic without room to slide "
                "(expected <limit lower=... upper=...> in metres, lower below upper)",
                joint.limit_line or joint.line,
            )
        out.append(
            ChainJoint(joint.name, joint.origin, joint.axis if joint.kind in ON_PATH else None, joint.kind == SLIDING)
        )
    moving = sum(j.axis is not None for j in out)
    if moving > MAX_JOINTS:
        raise robot.error(
            f"{moving:,} moving joints between {base!r} and {tip!r} (expected at most {MAX_JOINTS}, "
            "as for an arm of links)",
            robot.link_lines[tip],
        )
    if not moving:
        raise robot.error(
            f"no revolute, continuous or prismatic joint between {base!r} and {tip!r} (nothing would move)",
            robot.link_lines[tip],
        )
    return out


def joint_speeds(robot: Robot, joints: list[Joint]) -> tuple[float | None, ...]:
    """Each joint's ``<limit velocity>`` (rad/s, m/s for a prismatic joint), None where the URDF gives none (``effort`` is
    not read). Only the arm's own joints are checked, so a gripper's ``velocity="0"`` elsewhere
    in the file does no harm.

    Raises
    ------
    SceneError
        A velocity of the arm is 0 or negative, with its line (exit 2).

    >>> robot = parse_urdf(b'<robot name="r"><link name="a"/><link name="b"/><joint name="j" type="continuous">'
    ...     b'<parent link="a"/><child link="b"/><limit effort="1" velocity="2.5"/></joint></robot>', "r.urdf")
    >>> joint_speeds(robot, [robot.joints["j"]])
    (2.5,)
    """
    for joint in joints:
        if joint.velocity is not None and not joint.velocity > 0:
            raise robot.error(
                f"joint {joint.name!r}: <limit> velocity {joint.velocity:g} is not a speed (expected rad/s > 0, "
                "or leave velocity out for armanim's default max_joint_speed)",
                joint.limit_line,
            )
    return tuple(j.velocity for j in joints)


@dataclass(frozen=True)
class Hanging:
    """A link below ``base_link`` off the arm's path: it hangs from ``anchor``, the nearest link
    above it that is ``base_link`` or on the path, through ``joints`` (from the anchor down)."""

    link: str
    anchor: str
    joints: tuple[Joint, ...]


def hanging_links(robot: Robot, base: str, path_links: tuple[str, ...]) -> list[Hanging]:
    """Every link below ``base`` that is neither it nor on the path (``path_links``: the
    children of the path's joints), in the file's order of links: a gripper's hand and fingers
    below the tip, a camera on a flange, a part fixed to the base.

    >>> robot = parse_urdf(b'<robot name="r"><link name="a"/><link name="b"/><link name="f"/>'
    ...     b'<joint name="j" type="continuous"><parent link="a"/><child link="b"/></joint>'
    ...     b'<joint name="g" type="prismatic"><parent link="b"/><child link="f"/><limit lower="0" upper="0.1"/></joint></robot>', "r.urdf")
    >>> [(h.link, h.anchor, [j.name for j in h.joints]) for h in hanging_links(robot, "a", ("b",))]
    [('f', 'b', ['g'])]
    """
    up = robot.parent_joint
    arm = {base, *path_links}
    out = []
    for link in robot.links:
        if link in arm:
            continue
        joints, at = [], link
        while at not in arm and at in up:
            joints.append(up[at])
            at = up[at].parent
        if at in arm:
            out.append(Hanging(link, at, tuple(joints[::-1])))
    return out
