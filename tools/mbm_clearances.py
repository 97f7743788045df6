"""How near MotionBenchMaker's starts and goals come to the objects and to the robot itself, and what
fraction of them each clearance admits: the measurement behind the clearance ``armanim import moveit``
writes (docs/moveit-import.md).

Every problem of the archives is imported (:func:`armanim.scene.moveitscene.moveit_scene`), and at its
start and its goal every collision sphere of VAMP's spherized robot (the whole tree: the fingers and the
gripper too, as MoveIt checks them) is measured against every box, sphere and cylinder, exactly and in
closed form, and against the spheres of every pair of links the SRDF leaves enabled. A pair whose
spheres overlap in every state measured is counted as MoveIt's setup assistant would allow it
(``Always``). Independent of armanim's solver: numpy, the URDF reader and the importer only.

Usage (a maintainer's measurement, some minutes)::

    python tools/mbm_clearances.py ../shared/data/mbm            # the folder of panda/ and ur5/
"""

from __future__ import annotations

import argparse
import itertools
import sys
import tarfile
import tempfile
from pathlib import Path

import numpy as np

from armanim.scene.moveitscene import RobotSource, link_pose, moveit_scene
from armanim.scene.srdf import parse_srdf
from armanim.scene.urdf import read_urdf

CLEARANCES = (0.0, 0.0002, 0.0005, 0.001, 0.002, 0.005)
"""The clearances (metres) whose admitted fractions are printed."""


def _local(centres: np.ndarray, shape: dict) -> np.ndarray:
    """Sphere centres (N, 3) in a box's or cylinder's own frame (URDF rpy, degrees)."""
    from armanim.arm.rotations import rpy_rotation

    return (centres - np.array(shape["center"])) @ rpy_rotation(np.radians(shape["rpy"]))


def box_gaps(centres: np.ndarray, radii: np.ndarray, box: dict) -> np.ndarray:
    """Signed distances from spheres to a box (negative: overlap; a centre inside: minus its depth)."""
    q = np.abs(_local(centres, box)) - np.array(box["size"]) / 2
    outside = np.linalg.norm(np.maximum(q, 0.0), axis=1)
    return np.where(outside > 0, outside, q.max(axis=1)) - radii


def cylinder_gaps(centres: np.ndarray, radii: np.ndarray, cylinder: dict) -> np.ndarray:
    """Signed distances from spheres to a solid cylinder (axis: its local z)."""
    local = _local(centres, cylinder)
    radial = np.hypot(local[:, 0], local[:, 1]) - cylinder["radius"]
    axial = np.abs(local[:, 2]) - cylinder["length"] / 2
    outside = np.hypot(np.maximum(radial, 0.0), np.maximum(axial, 0.0))
    return np.where(outside > 0, outside, np.maximum(radial, axial)) - radii


def obstacle_gaps(centres: np.ndarray, radii: np.ndarray, obstacle: dict) -> np.ndarray:
    if "box" in obstacle:
        return box_gaps(centres, radii, obstacle["box"])
    if "cylinder" in obstacle:
        return cylinder_gaps(centres, radii, obstacle["cylinder"])
    return np.linalg.norm(centres - np.array(obstacle["center"]), axis=1) - radii - obstacle["radius"]


def robot_spheres(robot, values: dict[str, float]) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Every link's collision spheres at joint ``values``: (centres (N, 3) in the world, radii (N,))."""
    out = {}
    for link, primitives in robot.links.items():
        spheres = [p for p in primitives if p.kind == "sphere"]
        if spheres:
            pose = link_pose(robot, link, values)
            out[link] = (np.array([(pose @ p.origin)[:3, 3] for p in spheres]), np.array([p.size[0] for p in spheres]))
    return out


def state_gaps(spheres, obstacles, pairs) -> tuple[float, dict]:
    """(least gap to an object, each enabled pair's least gap) of one state."""
    centres = np.concatenate([c for c, _ in spheres.values()])
    radii = np.concatenate([r for _, r in spheres.values()])
    world = min((float(obstacle_gaps(centres, radii, o).min()) for o in obstacles), default=np.inf)
    per_pair = {}
    for a, b in pairs:
        (ca, ra), (cb, rb) = spheres[a], spheres[b]
        gaps = np.linalg.norm(ca[:, None] - cb[None], axis=2) - ra[:, None] - rb[None]
        per_pair[(a, b)] = float(gaps.min())
    return world, per_pair


def measure(folder: Path, robot_name: str) -> None:
    urdf, srdf = folder / robot_name / f"{robot_name}_spherized.urdf", folder / robot_name / f"{robot_name}.srdf"
    robot = read_urdf(urdf)
    allowed = {frozenset(p[:2]) for p in parse_srdf(srdf.read_bytes(), str(srdf), tuple(robot.links))}
    with_spheres = [link for link, prims in robot.links.items() if any(p.kind == "sphere" for p in prims)]
    pairs = [(a, b) for a, b in itertools.combinations(with_spheres, 2) if frozenset((a, b)) not in allowed]
    states = []  # (family, world gap, pair gaps)
    with tempfile.TemporaryDirectory() as tmp, tarfile.open(folder / robot_name / "problems.tar.bz2") as archive:
        archive.extractall(tmp, filter="data")
        for scene in sorted(Path(tmp).glob("problems/*/scene*.yaml")):
            request = scene.with_name(scene.name.replace("scene", "request"))
            data = moveit_scene(scene, request, RobotSource(urdf=urdf, srdf=srdf), Path(tmp) / "out.yaml").data
            chain = data["arm"]["home"]
            names = [j.name for j in robot.path(data["arm"]["base_link"], data["arm"]["tip_link"]) if j.kind != "fixed"]
            for degrees in (chain, data["goals"][0]["joints"]):
                values = dict(zip(names, np.radians(degrees)))
                world, per_pair = state_gaps(robot_spheres(robot, values), data["obstacles"], pairs)
                states.append((scene.parent.name, world, per_pair))
    always = {pair for pair in pairs if all(s[2][pair] < 0 for s in states)}
    print(
        f"{robot_name}: {len(states)} states (starts and goals), {len(pairs)} enabled pairs; overlapping in every state "
        f"(allowed as MoveIt's Always): {sorted(always) or 'none'}"
    )
    worlds = np.array([s[1] for s in states])
    selfs = np.array([min((g for p, g in s[2].items() if p not in always), default=np.inf) for s in states])
    nearest = min((p for p in pairs if p not in always), key=lambda p: min(s[2][p] for s in states))
    print(
        f"  least gap to an object {worlds.min() * 1e3:.2f} mm; least self gap {selfs.min() * 1e3:.2f} mm ({nearest[0]}/{nearest[1]})"
    )
    positive = worlds[worlds > 0]
    print(
        f"  least positive gap to an object {positive.min() * 1e3:.3f} mm; states touching or inside an object: {np.sum(worlds <= 0)}"
    )
    for c in CLEARANCES:
        admitted = (worlds >= c) & (selfs >= c)
        problems = admitted.reshape(-1, 2).all(axis=1)  # a start and its goal, in turn
        print(
            f"  clearance = self_clearance = {c * 1e3:.1f} mm: {admitted.sum()}/{admitted.size} states "
            f"({np.sum(worlds >= c)} clear of the objects, {np.sum(selfs >= c)} of itself), "
            f"{problems.sum()}/{problems.size} problems with start and goal admitted"
        )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "folder", type=Path, help="The folder of panda/ and ur5/ (problems.tar.bz2, spherized URDF, SRDF)."
    )
    parser.add_argument("--robots", default="panda,ur5")
    args = parser.parse_args(argv)
    for name in args.robots.split(","):
        measure(args.folder, name)
    return 0


if __name__ == "__main__":
    sys.exit(main())
