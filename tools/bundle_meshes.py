"""Maintainer script: the bundled robots' visual meshes, simplified, as package data.

Reads each bundled robot's URDF ``<visual>`` elements with armanim's own reader
(:mod:`armanim.scene.visuals`), finds the meshes in the makers' published folders, simplifies
each robot to ``--triangles`` (quadric decimation, fast-simplification), and writes
``src/armanim/arm/robots/NAME/visual.npz``: per link, its vertices (float32, metres, the
link's frame), triangles (uint16) and colours (uint8 RGB). Run time reads that file with numpy
alone. Users and CI never run this.

The sources, each with its licence beside the URDF already bundled from it (LICENSE):

- Panda and UR5: Gepetto/example-robot-data 39aa94379908fa743da90b21dc9e1fb8308f746b,
  ``robots/panda_description/meshes/visual/*.dae`` and ``robots/ur_description/meshes/ur5/visual/*.dae``
  (BSD-3-Clause; the Panda's meshes Apache-2.0 from frankaemika/franka_ros).
- iiwa: bulletphysics/bullet3 6c888f4abd7b46f572587360cc214985f02e5c6b, ``data/kuka_iiwa/meshes/*.obj``
  (the BSD-style licence of Robert Krug and Todor Stoyanov).

- UR5 on a rail (``ur5_rail``): the UR5's ``visual.npz`` and the rail's and carriage's boxes of
  its own URDF (no mesh of its own: ``--rail`` writes it alone, from the committed UR5 file).

Usage::

    python tools/bundle_meshes.py --erd PATH/TO/example-robot-data --bullet PATH/TO/bullet3/data [--triangles 12000]
    python tools/bundle_meshes.py --rail

where ``--erd`` holds ``robots/...`` and ``--bullet`` holds ``kuka_iiwa/...``.
"""

from __future__ import annotations

import argparse
import io
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "src"))

from armanim.scene.visuals import link_meshes, simplified, visual_specs  # noqa: E402

ROBOTS = ROOT / "src" / "armanim" / "arm" / "robots"


def bundle(name: str, package_dirs: list[Path], urdf_dir: Path, triangles: int) -> bytes:
    """One robot's ``visual.npz`` bytes and a line saying what it holds."""
    urdf = ROBOTS / name / f"{name}.urdf"
    warnings: list[str] = []
    meshes = link_meshes(visual_specs(urdf.read_bytes(), str(urdf)), urdf_dir, package_dirs, warnings.append, None)
    if warnings:
        raise SystemExit(f"{name}: " + "; ".join(warnings))
    before = sum(m.triangles for m in meshes)
    meshes = [simplified(m, max(12, round(m.triangles * triangles / before))) for m in meshes]
    arrays = {}
    for m in meshes:
        arrays[f"{m.link}/vertices"] = m.vertices.astype(np.float32)
        arrays[f"{m.link}/faces"] = m.faces.astype(np.uint16)
        arrays[f"{m.link}/colors"] = np.round(m.colors * 255).astype(np.uint8)
    out = io.BytesIO()
    np.savez_compressed(out, **arrays)
    after = sum(m.triangles for m in meshes)
    print(f"{name}: {len(meshes)} links, {before:,} -> {after:,} triangles, {len(out.getvalue()) / 1024:.0f} KB")
    return out.getvalue()


def bundle_rail() -> bytes:
    """``ur5_rail``'s ``visual.npz`` bytes: the UR5's committed meshes, then its URDF's boxes (rail, carriage)."""
    urdf = ROBOTS / "ur5_rail" / "ur5_rail.urdf"
    boxes = [spec for spec in visual_specs(urdf.read_bytes(), str(urdf)) if spec.kind == "box"]
    warnings: list[str] = []
    meshes = link_meshes(boxes, urdf.parent, [], warnings.append, None)
    if warnings:
        raise SystemExit("ur5_rail: " + "; ".join(warnings))
    with np.load(ROBOTS / "ur5" / "visual.npz") as ur5:
        arrays = {}
        for m in meshes:
            arrays[f"{m.link}/vertices"] = m.vertices.astype(np.float32)
            arrays[f"{m.link}/faces"] = m.faces.astype(np.uint16)
            arrays[f"{m.link}/colors"] = np.round(m.colors * 255).astype(np.uint8)
        arrays.update({key: ur5[key] for key in ur5.files})
    out = io.BytesIO()
    np.savez_compressed(out, **arrays)
    print(f"ur5_rail: the UR5's meshes and {len(meshes)} boxes, {len(out.getvalue()) / 1024:.0f} KB")
    return out.getvalue()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--rail", action="store_true", help="write ur5_rail's file alone, from the committed UR5 file")
    parser.add_argument("--erd", type=Path, help="a checkout of Gepetto/example-robot-data")
    parser.add_argument("--bullet", type=Path, help="bullet3's data folder (holds kuka_iiwa/)")
    parser.add_argument("--triangles", type=int, default=12_000, help="triangles per robot after simplifying")
    args = parser.parse_args()
    if args.rail or args.erd is None or args.bullet is None:
        if not args.rail:
            parser.error("--erd and --bullet are needed (or --rail)")
        (ROBOTS / "ur5_rail" / "visual.npz").write_bytes(bundle_rail())
        return
    packages = [args.erd.parent] if args.erd.name == "example-robot-data" else [args.erd.parent, args.erd]
    sources = {"panda": (packages, args.erd), "ur5": (packages, args.erd), "iiwa": ([], args.bullet / "kuka_iiwa")}
    for name, (dirs, urdf_dir) in sources.items():
        (ROBOTS / name / "visual.npz").write_bytes(bundle(name, dirs, urdf_dir, args.triangles))
    (ROBOTS / "ur5_rail" / "visual.npz").write_bytes(bundle_rail())


if __name__ == "__main__":
    main()
