"""URDF arms in a scene: the bundled robots, and a scene's ``arm.urdf`` or ``arm.robot`` resolved.

:func:`resolve_robot` runs while the scene is validated: it reads the URDF, picks the path
from ``base_link`` to ``tip_link`` and the collision capsules (in URDF units: metres and
radians). The scene's own angles (``base_rpy``, ``tool.rpy``, ``home``, ``limits``) become
radians in :mod:`armanim.scene.convert`, as every other angle does.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cache
from importlib import resources
from pathlib import Path

import numpy as np
import yaml

from armanim.arm.chain import ChainJoint
from armanim.scene.armmodel import ArmModel, CapsuleModel
from armanim.scene.fields import ROBOTS
from armanim.scene.meshcapsules import MeshCapsules, collision_yaml, mesh_capsules
from armanim.scene.models import SceneModel
from armanim.scene.srdf import resolve_self_collision
from armanim.scene.urdf import (
    ON_PATH,
    SLIDING,
    Hanging,
    Joint,
    Robot,
    chain_joints,
    hanging_links,
    joint_speeds,
    read_urdf,
)
from armanim.scene.visuals import default_package_dirs

RATE_UNITS = {
    "max_joint_speed": ("rad/s", "deg/s"),
    "max_joint_acceleration": ("rad/s^2", "deg/s^2"),
    "max_joint_jerk": ("rad/s^3", "deg/s^3"),
}
"""The rates a robot.yaml may publish (its ``rates``), each in one of these units."""


@dataclass(frozen=True)
class PublishedRate:
    """A joint rate a robot's maker publishes, as published (one value per joint, in ``unit``)."""

    values: tuple[float, ...]
    unit: str
    source: str


@dataclass(frozen=True)
class BundledRobot:
    """A bundled robot's description: where its URDF is and the defaults it brings.

    ``rates`` holds the maker's published joint limits, (scene field name, rate) pairs
    (``max_joint_speed``, ``max_joint_acceleration``, ``max_joint_jerk``), where published.
    """

    name: str
    title: str
    urdf: Path
    base_link: str
    tip_link: str
    home: tuple[float, ...]  # degrees
    collision: object  # "auto" or a list of {link, from, to, radius}
    width: float
    source: str
    rates: tuple[tuple[str, PublishedRate], ...] = ()

    def rate(self, name: str) -> PublishedRate | None:
        """The published rate of scene field ``name`` (e.g. ``max_joint_acceleration``), or None."""
        return dict(self.rates).get(name)


def _published_rates(info: dict) -> tuple[tuple[str, PublishedRate], ...]:
    """robot.yaml's ``rates`` (package data, checked by the tests) as (field name, rate) pairs."""
    out = {}
    for name, rate in (info.get("rates") or {}).items():
        if name not in RATE_UNITS or rate["unit"] not in RATE_UNITS[name]:
            raise ValueError(f"robot.yaml: rates.{name} in {rate.get('unit')!r}: not a rate armanim reads")
        out[name] = PublishedRate(
            tuple(float(v) for v in rate["values"]), rate["unit"], " ".join(rate["source"].split())
        )
    return tuple(out.items())


@cache
def bundled_robot(name: str) -> BundledRobot:
    """The bundled robot ``name`` (one of :data:`ROBOTS`); KeyError if there is none."""
    if name not in ROBOTS:
        raise KeyError(name)
    folder = resources.files("armanim.arm").joinpath("robots", name)
    info = yaml.safe_load(folder.joinpath("robot.yaml").read_text(encoding="utf-8"))  # package data, not user input
    return BundledRobot(
        name=name,
        title=info["title"],
        urdf=Path(str(folder.joinpath(info["urdf"]))),
        base_link=info["base_link"],
        tip_link=info["tip_link"],
        home=tuple(info["home"]),
        collision=info["collision"],
        width=float(info["width"]),
        source=info["source"],
        rates=_published_rates(info),
    )


@cache
def published_joint_names(name: str) -> tuple[str, ...]:
    """The joints a bundled robot's published rates are listed for: its own chain's, from its
    ``base_link`` to its ``tip_link`` (a scene may choose others; rates go by joint name)."""
    robot = bundled_robot(name)
    urdf = read_urdf(robot.urdf, f"robot {name}'s URDF")
    return tuple(j.name for j in urdf.path(robot.base_link, robot.tip_link) if j.kind in ON_PATH)


SELF_COLLISION_FILE = "self-collision.yaml"
"""A bundled robot's allowed-collision matrix (package data, written by tools/self_collision_matrix.py)."""


@dataclass(frozen=True)
class BundledMatrix:
    """A bundled robot's committed allowed-collision matrix: the link pairs never checked and why.

    ``clearance`` (metres) is how near counted as touching when it was computed: it serves every
    scene whose ``solver.self_clearance`` is at most that (a pair never that near is never nearer)."""

    clearance: float
    samples: int
    seed: int
    allowed: tuple[tuple[str, str, str], ...]


@cache
def bundled_matrix(name: str) -> BundledMatrix | None:
    """The committed matrix of bundled robot ``name``, or None if it ships none."""
    file = resources.files("armanim.arm").joinpath("robots", name, SELF_COLLISION_FILE)
    if not file.is_file():
        return None
    info = yaml.safe_load(file.read_text(encoding="utf-8"))  # package data, not user input
    return BundledMatrix(
        float(info["clearance"]),
        int(info["samples"]),
        int(info["seed"]),
        tuple((str(a), str(b), str(reason)) for a, b, reason in info["allowed"]),
    )


FITTED_FILE = "fitted-capsules.yaml"
"""A bundled robot's capsules fitted to its own meshes (package data, written by tools/fit_bundled.py)."""
CAPSULES_FILE = "capsules.yaml"
"""A run folder's capsules (``arm.collision``'s list format), beside its copy of the URDF."""
MAX_CAPSULES_BYTES = 1024 * 1024


def bundled_fitted(name: str) -> list[dict]:
    """A bundled robot's fitted capsules, as ``arm.collision`` lists them."""
    file = resources.files("armanim.arm").joinpath("robots", name, FITTED_FILE)
    return list(yaml.safe_load(file.read_text(encoding="utf-8"))["collision"])  # package data, not user input


def run_capsules(path: Path) -> list:
    """The capsules of a run folder's ``capsules.yaml``, checked as ``arm.collision`` is.

    Raises
    ------
    SceneError
        The file is not such a list (exit 2).
    """
    from pydantic import TypeAdapter, ValidationError

    from armanim.errors import Diagnostic, SceneError
    from armanim.output.files import read_bounded

    try:
        data = yaml.safe_load(read_bounded(path, MAX_CAPSULES_BYTES, "a run's capsules.yaml"))
        return TypeAdapter(list[CapsuleModel]).validate_python(data["collision"])
    except (yaml.YAMLError, ValidationError, KeyError, TypeError) as exc:
        raise SceneError(
            str(path), [Diagnostic("", f"is not a list of collision capsules ({str(exc).splitlines()[0]})")]
        ) from None


def capsules_text(robot: UrdfArm) -> str:
    """A run's ``capsules.yaml``: the URDF arm's capsules as the scene's ``arm.collision`` list,
    with a header saying where they came from."""
    header = [
        "The arm's collision capsules in this run (armanim), each in its URDF link's frame, in metres.",
        "Copy the list under the scene's arm section (arm.collision) to keep or edit them.",
    ]
    if robot.fitted_links:
        header.append(f"Fitted to their meshes: {', '.join(robot.fitted_links)} (each capsule holds every vertex).")
    if robot.from_visuals:
        header.append(f"(from their visual meshes, having no <collision>: {', '.join(robot.from_visuals)})")
    if robot.fallback_links:
        header.append(
            f"Not listed: the joint-to-joint capsules of {', '.join(robot.fallback_links)} (radius arm.width / 2)."
        )
    return collision_yaml([(c.link, c.start, c.end, c.radius) for c in robot.capsules], "\n".join(header))


def fitted_collision_text(urdf: str | Path, package_dirs: list[Path] | None = None) -> str:
    """``armanim robots --fit``: every link's capsules of a URDF as ``collision: auto`` makes them
    (its primitives, and capsules fitted to its meshes), as the scene's ``arm.collision`` list.

    Parameters
    ----------
    urdf : str or Path
    package_dirs : list of Path, optional
        Where ``package://`` meshes are found; default the URDF's folder and its parents.

    Raises
    ------
    SceneError
        The URDF, or a collision mesh, cannot be used (exit 2).
    """
    path = Path(urdf)
    robot = read_urdf(path)
    fits = mesh_capsules(robot, tuple(robot.links), path.parent, package_dirs or default_package_dirs(path.parent))
    fitted: dict[str, list] = {}
    for link, capsule in fits.capsules:
        fitted.setdefault(link, []).append((link, capsule.start, capsule.end, capsule.radius))
    rows = [
        row
        for link in robot.links
        for row in (
            [(c.link, c.start, c.end, c.radius) for c in primitive_capsules(link, robot)] + fitted.get(link, [])
        )
    ]
    header = [
        f"Collision capsules of {path.name} (armanim robots --fit), each in its URDF link's frame, in metres:",
        "paste under the scene's arm section (arm.collision), after removing the links outside the arm's body.",
    ]
    if fits.capsules:
        header.append(
            f"Fitted to meshes: {', '.join(dict.fromkeys(link for link, _ in fits.capsules))} (each capsule holds every vertex)."
        )
    if fits.from_visuals:
        header.append(f"(from their visual meshes, having no <collision>: {', '.join(fits.from_visuals)})")
    header += [f"Not fitted: {problem}" for problem in fits.unread]
    return collision_yaml(rows, "\n".join(header))


@dataclass(frozen=True)
class CapsuleSpec:
    """A capsule in its link's frame (metres)."""

    link: str
    start: np.ndarray
    end: np.ndarray
    radius: float


@dataclass(frozen=True)
class UrdfArm:
    """A scene's URDF arm, resolved: the path of joints and the capsules, in URDF units.

    Attributes
    ----------
    file : str
        The URDF as messages name it.
    joints : tuple of ChainJoint
        From base_link to tip_link.
    joint_names : tuple of str
        The moving joints, in order (``phi1`` is the first).
    limits : tuple of (lower, upper) radians or None
        Per moving joint, from the URDF (None: continuous); metres for a prismatic joint.
    velocities : tuple of float or None
        Per moving joint, the URDF's ``<limit velocity>`` in rad/s, m/s for a prismatic joint (None: not given).
    path_links : tuple of str
        The child link of each joint of ``joints``.
    capsules : tuple of CapsuleSpec
    fallback_links : tuple of str
        Moving links without a usable collision primitive: they get a joint-to-joint capsule of radius width / 2.
    bundled : BundledRobot or None
    source : bytes or None
        The bytes of the user's URDF file that were read and solved with (None for a bundled
        robot): what a run folder keeps as its copy, never a second read of a file that may
        have changed since.
    """

    file: str
    joints: tuple[ChainJoint, ...]
    joint_names: tuple[str, ...]
    limits: tuple[tuple[float, float] | None, ...]
    path_links: tuple[str, ...]
    capsules: tuple[CapsuleSpec, ...]
    fallback_links: tuple[str, ...]
    bundled: BundledRobot | None
    source: bytes | None = None
    velocities: tuple[float | None, ...] = ()
    prismatic: tuple[bool, ...] = ()
    """Per moving joint: whether it slides (metres) instead of turning (radians)."""
    links: tuple[str, ...] = ()
    """Every link of the URDF (names an SRDF or ``self_collision`` lists may use)."""
    base_link: str = ""
    tip_link: str = ""
    robot: Robot | None = field(default=None, repr=False, compare=False)
    """The parsed URDF (its links' visuals are drawn from it: :mod:`armanim.scene.visuals`)."""
    folder: Path | None = None
    """The folder of the URDF file read (mesh files are relative to it); None for a bundled robot."""
    hanging: tuple[Hanging, ...] = ()
    """The links below ``base_link`` off the path (a gripper's fingers, a camera): each hangs from
    the base link or a link of the path, with its collision geometry."""
    held: tuple[Joint, ...] = ()
    """The joints among those that are not fixed, in the file's order: each held at a value
    (``arm.joint_values``, its default, or its ``<mimic>``)."""
    fitted_links: tuple[str, ...] = ()
    """The links whose capsules were fitted to their meshes (``collision: auto`` of your own URDF)."""
    from_visuals: tuple[str, ...] = ()
    """Those of them without ``<collision>``, fitted to their visual meshes."""
    unread_meshes: tuple[str, ...] = ()
    """Why visual meshes a fit would have used could not be read."""


class ArmFieldError(ValueError):
    """A problem of a field inside the scene's ``arm`` section that only the URDF tells: ``loc``
    is the field's path below ``arm`` (e.g. ``("joint_values", "panda_finger_joint1")``)."""

    def __init__(self, loc: tuple, message: str) -> None:
        super().__init__(message)
        self.loc = loc


def default_held_value(joint: Joint) -> float:
    """A held joint's value when the scene gives none (URDF units: radians or metres): 0 if its
    limits allow it, else its lower limit.

    >>> from armanim.scene.urdf import parse_urdf
    >>> robot = parse_urdf(b'<robot name="r"><link name="a"/><link name="b"/><joint name="j" type="prismatic">'
    ...     b'<parent link="a"/><child link="b"/><limit lower="0.01" upper="0.04"/></joint></robot>', "r.urdf")
    >>> default_held_value(robot.joints["j"])
    0.01
    """
    if joint.limits is None or joint.limits[0] <= 0.0 <= joint.limits[1]:
        return 0.0
    return float(joint.limits[0])


def _check_mimics(robot: Robot, held: tuple[Joint, ...]) -> None:
    """Each held mimic joint follows a held joint that is no mimic itself (its value is then known);
    a SceneError at its line otherwise (a mimic of the chain's joints would move with the arm)."""
    free = {j.name for j in held if j.follows is None}
    for joint in held:
        if joint.follows is not None and joint.follows[0] not in free:
            raise robot.error(
                f"joint {joint.name!r} mimics {joint.follows[0]!r}, which is not a joint held off the arm's chain "
                "(armanim holds a mimic joint off the chain at its <mimic> of such a joint; choose another "
                "base_link or tip_link)",
                joint.line,
            )


def _check_joint_values(values: dict, robot: Robot, path_joints: list[Joint], held: tuple[Joint, ...]) -> None:
    """``arm.joint_values`` names held joints (not the chain's, not fixed, not a mimic) with values
    inside their limits (degrees, or metres for a prismatic joint); an :class:`ArmFieldError` at the
    joint's entry otherwise."""
    chain = {j.name for j in path_joints if j.kind in ON_PATH}
    mine = {j.name: j for j in held}
    for name, value in values.items():
        loc = ("joint_values", name)
        if name in chain:
            raise ArmFieldError(
                loc,
                f"{name!r} is a joint of the arm's chain (its angle is arm.home's: "
                "joint_values holds the joints off the chain, such as a gripper's)",
            )
        joint = robot.joints.get(name)
        if joint is None:
            close = [n for n in mine if name.lower() in n.lower() or n.lower() in name.lower()][:1]
            hint = f"did you mean {close[0]!r}? " if close else ""
            raise ArmFieldError(
                loc,
                f"{name!r} is not a joint of {robot.file} ({hint}the joints held off "
                f"the chain: {', '.join(mine) or 'none'})",
            )
        if joint.follows is not None:
            raise ArmFieldError(
                loc,
                f"joint {name!r} mimics {joint.follows[0]!r} (it follows that joint's "
                f"value by its <mimic>, line {joint.line}: set {joint.follows[0]!r} instead)",
            )
        if name not in mine:
            why = "is fixed" if joint.kind == "fixed" else "is not below base_link"
            raise ArmFieldError(
                loc,
                f"joint {name!r} {why} (expected one of the joints held off the chain: {', '.join(mine) or 'none'})",
            )
        if joint.limits is not None:
            lower, upper = joint.limits
            unit = " m"
            if joint.kind != "prismatic":
                lower, upper, unit = float(np.degrees(lower)), float(np.degrees(upper)), " degrees"
            if not lower <= value <= upper:
                raise ArmFieldError(
                    loc,
                    f"{value:g} is outside the limits of joint {name!r}, "
                    f"[{lower:g}, {upper:g}]{unit} (line {joint.limit_line} of {robot.file})",
                )


def read_scene_files(
    scene: SceneModel,
    scene_dir: str | Path = ".",
    urdf_file: str | Path | None = None,
    srdf_file: str | Path | None = None,
) -> SceneModel:
    """The validated ``scene`` with its arm's files read (:func:`read_arm_files`)."""
    return scene.model_copy(update={"arm": read_arm_files(scene.arm, scene_dir, urdf_file, srdf_file)})


def read_arm_files(
    arm: ArmModel, scene_dir: str | Path = ".", urdf_file: str | Path | None = None, srdf_file: str | Path | None = None
) -> ArmModel:
    """A validated ``arm`` section with what its files say: the URDF arm (:func:`resolve_robot`)
    and the SRDF's pairs (:func:`armanim.scene.srdf.resolve_self_collision`).

    ``scene_dir`` is the folder ``arm.urdf`` and ``self_collision.srdf`` are relative to;
    ``urdf_file`` and ``srdf_file`` are read in their place (a run folder's copies).

    Raises
    ------
    ValueError
        A problem of the scene's arm section (a link that is not the URDF's): reported at ``arm``.
    SceneError
        A problem of the URDF or SRDF file, ``FILE:LINE: message`` (exit 2).
    """
    robot = resolve_robot(arm, scene_dir, urdf_file)
    if isinstance(arm.self_collision, str):
        return arm.with_files(robot, None)
    links = robot.links if robot is not None else tuple(f"link{k + 1}" for k in range(len(arm.links or ())))
    return arm.with_files(robot, resolve_self_collision(arm.self_collision, links, scene_dir, srdf_file))


def resolve_robot(arm: ArmModel, scene_dir: str | Path = ".", urdf_file: str | Path | None = None) -> UrdfArm | None:
    """The URDF arm of a validated ``arm`` section, or None for an arm of links.

    ``arm.urdf`` is relative to ``scene_dir``; ``urdf_file`` is read in its place (a run
    folder's copy). Problems of the scene raise ValueError (reported at ``arm``); problems of
    the URDF file raise its SceneError (``FILE:LINE: message``).
    """
    if not arm.is_urdf:
        return None
    bundled = bundled_robot(arm.robot) if arm.robot is not None else None
    if bundled is not None:
        path, shown = bundled.urdf, f"robot {bundled.name}'s URDF"
    else:
        assert arm.urdf is not None, "a URDF arm that is not bundled names its file (ArmModel)"
        path = Path(urdf_file) if urdf_file else Path(scene_dir or ".") / arm.urdf
        shown = str(path)
    robot = read_urdf(path, shown, field="urdf" if bundled is None else None)
    base = _link(robot, arm.base_link or (bundled.base_link if bundled else robot.root), "base_link")
    tip = _link(robot, arm.tip_link or (bundled.tip_link if bundled else _only_leaf(robot)), "tip_link")
    joints = chain_joints(robot, base, tip)
    path_joints = robot.path(base, tip)
    moving = [j for j in path_joints if j.kind in ON_PATH]
    links = tuple(j.child for j in path_joints)
    hanging = tuple(hanging_links(robot, base, links))
    held = tuple({j.name: j for h in hanging for j in h.joints if j.kind != "fixed"}.values())
    _check_mimics(robot, held)
    _check_joint_values(arm.joint_values or {}, robot, path_joints, held)
    body = (base, *links, *(h.link for h in hanging))
    collision = arm.collision if arm.collision is not None else (bundled.collision if bundled else "auto")
    fits = MeshCapsules()
    if collision == "fitted":
        if bundled is None:
            raise ValueError(
                "collision: fitted is a bundled robot's set of capsules fitted to its meshes (robot: panda, "
                "ur5, iiwa); for your own URDF, collision: auto fits capsules to its meshes"
            )
        collision = bundled_fitted(bundled.name)
    kept = Path(urdf_file).parent / CAPSULES_FILE if urdf_file and bundled is None else None
    if collision == "auto" and kept is not None and kept.is_file():
        collision = run_capsules(kept)  # a run folder's copy: the capsules it was solved with (its meshes stay behind)
    if collision == "auto":
        if bundled is None:
            dirs = (
                [Path(scene_dir or ".") / d for d in arm.package_dirs]
                if arm.package_dirs
                else default_package_dirs(path.parent)
            )
            fits = mesh_capsules(robot, body, path.parent, dirs)
        fitted: dict[str, list[CapsuleSpec]] = {}
        for link, capsule in fits.capsules:
            fitted.setdefault(link, []).append(CapsuleSpec(link, capsule.start, capsule.end, capsule.radius))
        capsules = tuple(c for link in body for c in (*primitive_capsules(link, robot), *fitted.get(link, ())))
    else:
        capsules = tuple(_listed_capsules(collision, body))
    return UrdfArm(
        file=shown,
        joints=tuple(joints),
        joint_names=tuple(j.name for j in moving),
        limits=tuple(j.limits for j in moving),
        prismatic=tuple(j.kind == SLIDING for j in moving),
        path_links=links,
        capsules=capsules,
        fallback_links=_uncovered(joints, links, capsules),
        bundled=bundled,
        source=None if bundled is not None else robot.raw,
        velocities=joint_speeds(robot, moving),
        links=tuple(robot.links),
        base_link=base,
        tip_link=tip,
        robot=robot,
        folder=None if bundled is not None else path.parent,
        hanging=hanging,
        held=held,
        fitted_links=tuple(dict.fromkeys(link for link, _ in fits.capsules)),
        from_visuals=fits.from_visuals,
        unread_meshes=fits.unread,
    )


def _link(robot: Robot, name: str, field: str) -> str:
    if name not in robot.links:
        close = [n for n in robot.links if name.lower() in n.lower()][:3]
        hint = f"did you mean {close[0]!r}? " if close else ""
        raise ValueError(
            f"{field} {name!r} is not a link of {robot.file} ({hint}it has {len(robot.links)} links: "
            f"{', '.join(list(robot.links)[:12])}{', ...' if len(robot.links) > 12 else ''})"
        )
    return name


def _only_leaf(robot: Robot) -> str:
    leaves = robot.leaves
    if len(leaves) != 1:
        raise ValueError(
            f"tip_link is not given and {robot.file} has {len(leaves)} leaf links "
            f"({', '.join(leaves[:12])}): set arm.tip_link to the link the arm ends at"
        )
    return leaves[0]


def primitive_capsules(link: str, robot: Robot) -> list[CapsuleSpec]:
    """The capsules of a link's ``<collision>`` primitives, in its frame: a cylinder becomes
    the capsule around its axis, a sphere a zero-length capsule, a box the capsule along its
    longest side that holds it; meshes give none. Capsules inside another are dropped."""
    out = []
    for prim in robot.links[link]:
        if prim.kind == "mesh":
            continue
        local = _primitive_segment(prim.kind, prim.size)
        ends = prim.origin[:3, :3] @ np.array(local[:2]).T + prim.origin[:3, 3:4]
        out.append(CapsuleSpec(link, ends[:, 0], ends[:, 1], local[2]))
    return [
        c
        for i, c in enumerate(out)
        if not any(j != i and _inside(c, o) and (not _inside(o, c) or j < i) for j, o in enumerate(out))
    ]


def _primitive_segment(kind: str, size) -> tuple[np.ndarray, np.ndarray, float]:
    if kind == "cylinder":
        radius, length = size
        return np.array([0, 0, -length / 2]), np.array([0, 0, length / 2]), float(radius)
    if kind == "sphere":
        return np.zeros(3), np.zeros(3), float(size[0])
    half = np.asarray(size, dtype=float) / 2  # box
    axis = int(np.argmax(half))
    rest = np.delete(half, axis)
    tip = np.zeros(3)
    tip[axis] = half[axis]
    return -tip, tip, float(np.hypot(*rest))


def _inside(inner: CapsuleSpec, outer: CapsuleSpec) -> bool:
    """Whether capsule ``inner`` lies within ``outer`` (both ends' balls do: the distance to a segment is convex)."""
    ab = outer.end - outer.start
    length2 = float(ab @ ab)
    for p in (inner.start, inner.end):
        t = 0.0 if length2 == 0 else min(1.0, max(0.0, float((p - outer.start) @ ab) / length2))
        if np.linalg.norm(p - (outer.start + t * ab)) + inner.radius > outer.radius + 1e-12:
            return False
    return True


def _listed_capsules(collision, links: tuple[str, ...]):
    for i, capsule in enumerate(collision):
        link = capsule.link if hasattr(capsule, "link") else capsule["link"]
        if link not in links:
            raise ValueError(
                f"collision[{i}].link {link!r} is not a link of the arm (base_link, the links to tip_link "
                f"and those hanging from them; expected one of: {', '.join(links)})"
            )
        get = (
            (lambda k, c=capsule: getattr(c, "from_" if k == "from" else k))
            if hasattr(capsule, "link")
            else capsule.__getitem__
        )
        yield CapsuleSpec(
            link, np.asarray(get("from"), dtype=float), np.asarray(get("to"), dtype=float), float(get("radius"))
        )


def _uncovered(joints: list[ChainJoint], links: tuple[str, ...], capsules) -> tuple[str, ...]:
    """The moving joints' links (each named by the first link a joint moves) none of whose
    carried links has a capsule."""
    covered = {c.link for c in capsules}
    out: list[str] = []
    group: list[str] = []
    moving = False
    for joint, link in zip(joints, links):
        if joint.axis is not None:
            if moving and not covered.intersection(group):
                out.append(group[0])
            group, moving = [], True
        group.append(link)
    if moving and not covered.intersection(group):
        out.append(group[0])
    return tuple(out)
