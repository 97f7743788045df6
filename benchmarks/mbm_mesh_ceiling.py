"""Issue 52's MotionBenchMaker ceiling: how many of the 700 Panda problems are valid under VAMP's
``panda.urdf`` collision *meshes* themselves (pinocchio's collision model, coal's distances), as
``armanim validate`` checks capsules: at home and at the joint goal, every link at least 0.5 mm
(the importer's clearance) from every obstacle, every pair the SRDF leaves enabled 0.5 mm apart,
the fingers held at 0 as the import holds them. Any capsules that hold the meshes can only refuse
more; ``mbm_starts_bench.py --urdf`` counts what the fitted capsules admit.

Run: ``python benchmarks/mbm_mesh_ceiling.py /work/shared/data/mbm --vamp /work/vamp/resources``
(a minute or two on one core). ``--names`` prints the nearest distance of the meshes for each
problem named (``cage_panda/scene0018.yaml``...): how far the real links are where capsules refuse.
"""

from __future__ import annotations

import argparse
import math
import re
import sys
import tarfile
import tempfile
from pathlib import Path

import coal
import numpy as np
import pinocchio as pin

from armanim.scene.moveitscene import RobotSource, moveit_scene

CLEARANCE = 0.0005


def obstacle(item: dict) -> tuple[str, object, object]:
    """(name, coal shape, placement) of one scene obstacle (rpy in degrees, as the scene writes it)."""
    kind = next(k for k in item if k != "name")
    p = item[kind]
    shapes = {"box": lambda: coal.Box(*p["size"]), "cylinder": lambda: coal.Cylinder(p["radius"], p["length"])}
    shape = shapes.get(kind, lambda: coal.Sphere(p["radius"]))()
    rotation = pin.rpy.rpyToMatrix(*np.radians(p.get("rpy", [0.0, 0.0, 0.0])))
    return item.get("name", kind), shape, coal.Transform3s(rotation, np.asarray(p["center"], float))


class Meshes:
    """VAMP's Panda as pinocchio reads it, with its collision meshes and its SRDF's disabled pairs."""

    def __init__(self, urdf: Path, srdf: Path) -> None:
        self.model, self.geometry = pin.buildModelsFromUrdf(
            str(urdf), package_dirs=[str(urdf.parent)], geometry_types=pin.GeometryType.COLLISION
        )
        self.data, self.placed = self.model.createData(), pin.GeometryData(self.geometry)
        text = srdf.read_text(encoding="utf-8")
        self.disabled = {frozenset(p) for p in re.findall(r'link1="([^"]+)" link2="([^"]+)"', text)}

    def gaps(self, degrees: list[float], obstacles: list) -> dict[tuple[str, str], float]:
        """Each link's nearest distance to each obstacle, and each enabled pair's (metres)."""
        q = pin.neutral(self.model)
        for k, value in enumerate(degrees):
            q[self.model.joints[self.model.getJointId(f"panda_joint{k + 1}")].idx_q] = math.radians(value)
        pin.forwardKinematics(self.model, self.data, q)
        pin.updateGeometryPlacements(self.model, self.data, self.geometry, self.placed)
        links: dict[str, list] = {}
        for k, item in enumerate(self.geometry.geometryObjects):
            placement = self.placed.oMg[k]
            links.setdefault(self.model.frames[item.parentFrame].name, []).append(
                (item.geometry, coal.Transform3s(placement.rotation, placement.translation))
            )
        out = {}
        for link, parts in links.items():
            for name, shape, where in obstacles:
                out[(link, name)] = min(distance(part, (shape, where)) for part in parts)
        names = list(links)
        for i, a in enumerate(names):
            for b in names[i + 1 :]:
                if frozenset((a, b)) not in self.disabled:
                    out[(a, b)] = min(distance(x, y) for x in links[a] for y in links[b])
        return out


def distance(a: tuple, b: tuple) -> float:
    return float(coal.distance(a[0], a[1], b[0], b[1], coal.DistanceRequest(), coal.DistanceResult()))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder", type=Path, help="the folder of panda/problems.tar.bz2")
    parser.add_argument("--vamp", type=Path, required=True, help="VAMP's resources folder (panda/panda.urdf, .srdf)")
    parser.add_argument("--names", nargs="*", default=[], help="problems whose nearest gaps to print")
    args = parser.parse_args(argv)
    urdf, srdf = args.vamp / "panda" / "panda.urdf", args.vamp / "panda" / "panda.srdf"
    meshes, source = Meshes(urdf, srdf), RobotSource(urdf=urdf, srdf=srdf)
    valid, total = 0, 0
    with tempfile.TemporaryDirectory() as tmp, tarfile.open(args.folder / "panda" / "problems.tar.bz2") as archive:
        archive.extractall(tmp, filter="data")
        for scene in sorted(Path(tmp).glob("problems/*/scene*.yaml")):
            name = f"{scene.parent.name}/{scene.name}"
            request = scene.with_name(scene.name.replace("scene", "request"))
            data = moveit_scene(scene, request, source, Path(tmp) / "out.yaml").data
            obstacles = [obstacle(o) for o in data["obstacles"]]
            poses = {"home": data["arm"]["home"], "goal": data["goals"][0]["joints"]}
            gaps = {pose: meshes.gaps(q, obstacles) for pose, q in poses.items()}
            total += 1
            valid += all(g >= CLEARANCE for pose in gaps.values() for g in pose.values())
            if name in args.names:
                for pose, values in gaps.items():
                    (a, b), g = min(values.items(), key=lambda kv: kv[1])
                    print(f"{name} {pose}: nearest {a} - {b} {1000 * g:.2f} mm")
    print(f"valid under the meshes themselves: {valid}/{total}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
