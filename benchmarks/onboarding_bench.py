"""Issue 52's onboarding benchmark, the capsules: vendor URDFs with mesh collisions, as their makers
ship them, fitted by ``collision: auto``, against independent measures of their meshes.

For each robot every link's capsules are fitted as a run fits them (:func:`armanim.scene.meshcapsules.mesh_capsules`:
its ``<collision>`` meshes, else its visual meshes; no cache, so the time is the fit's). The oracle
reads the same mesh files with trimesh (not armanim's reader), places them by the URDF's ``scale`` and
``<origin>``, and measures

- the share of vertices inside a capsule (distance to the nearest capsule's segment minus its radius
  at most 1e-6 m; target 100 %), by a plain point-to-segment distance;
- each link's capsule volume against its mesh's convex hull (trimesh); the robot's total against the
  sum of its links' hulls (target <= 1.6x, no link over 2.5x).

The bundled robots are measured on the meshes they ship (``visual.npz``), fitted as
``tools/fit_bundled.py`` fits them for ``collision: fitted``.

The vendor URDFs come from the example-robot-data wheel (PyPI, BSD-3-Clause), unpacked, not installed::

    pip download --no-deps example-robot-data==6.0.0 -d /tmp/erd && unzip -q /tmp/erd/*.whl -d /tmp/erd/wheel
    python benchmarks/onboarding_bench.py --erd /tmp/erd/wheel/cmeel.prefix/share/example-robot-data

and VAMP's mesh URDFs (``--vamp``: KavrakiLab/vamp's ``resources/`` folder, the Panda and UR5 that
MotionBenchMaker's problems are posed for).

``--against OTHER_FITTING.py`` times another fit (main's, say) against this one robot by robot in one
process; ``--set NAME=VALUE`` runs with one of the fit's constants changed (a variant measured).
"""

from __future__ import annotations

import argparse
import sys
import time
from importlib import resources
from pathlib import Path

import numpy as np
import trimesh

from armanim.arm.fitting import fit_capsules
from armanim.scene.meshcapsules import geometry_specs, mesh_capsules
from armanim.scene.urdf import read_urdf
from armanim.scene.visuals import bundled_link_meshes, mesh_path

VENDOR = {
    "UR10": "robots/ur_description/urdf/ur10_robot.urdf",
    "xArm7": "robots/xarm_description/urdf/xarm7.urdf",
    "Z1": "robots/z1_description/urdf/z1.urdf",
    "SO-101": "robots/so_arm_description/urdf/so101.urdf",
    "Panda (franka_description)": "robots/panda_description/urdf/panda.urdf",
}
VAMP = {
    "VAMP panda.urdf": "panda/panda.urdf",
    "VAMP ur5.urdf": "ur5/ur5.urdf",
}
"""VAMP's mesh URDFs (KavrakiLab/vamp's ``resources/``, Apache-2.0), the ones MotionBenchMaker's problems use."""
TOLERANCE = 1e-6


def segment_distance(points: np.ndarray, a, b) -> np.ndarray:
    """Each point's distance to the segment a-b (the textbook clamp)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    ab = b - a
    den = float(ab @ ab)
    t = np.zeros(len(points)) if den == 0 else np.clip((points - a) @ ab / den, 0.0, 1.0)
    return np.linalg.norm(points - (a + t[:, None] * ab), axis=1)


def oracle_points(urdf: Path, link: str, tag: str, dirs: list[Path]) -> np.ndarray:
    """The link's mesh vertices read by trimesh, scaled and placed by the URDF."""
    robot = read_urdf(urdf)
    out = []
    for spec in geometry_specs(robot, tag).get(link, []):
        if spec.kind != "mesh":
            continue
        mesh = trimesh.load(str(mesh_path(spec.filename, urdf.parent, dirs)), force="mesh")
        v = np.asarray(mesh.vertices) * np.asarray(spec.scale)
        out.append(v @ spec.origin[:3, :3].T + spec.origin[:3, 3])
    return np.concatenate(out) if out else np.zeros((0, 3))


def measure(points: np.ndarray, capsules) -> tuple[int, int, float, float]:
    """(vertices held, vertices, capsule volume, hull volume) of one link."""
    gap = np.min([segment_distance(points, c.start, c.end) - c.radius for c in capsules], axis=0)
    hull = trimesh.convex.convex_hull(points).volume if len(points) >= 4 else 0.0
    return int(np.sum(gap <= TOLERANCE)), len(points), sum(c.volume for c in capsules), float(hull)


def report(name: str, rows: list[tuple[str, int, tuple[int, int, float, float]]], seconds: float) -> dict:
    held = sum(r[2][0] for r in rows)
    total = sum(r[2][1] for r in rows)
    caps, hulls = sum(r[2][2] for r in rows), sum(r[2][3] for r in rows)
    worst = max(rows, key=lambda r: r[2][2] / max(r[2][3], 1e-12))
    ratio = caps / hulls
    print(
        f"| {name} | {len(rows)} | {sum(r[1] for r in rows)} | {held}/{total} ({100 * held / total:.2f} %) | "
        f"{ratio:.2f}x | {worst[2][2] / max(worst[2][3], 1e-12):.2f}x ({worst[0]}) | {seconds:.1f} s |"
    )
    return {"ratio": ratio, "held": held == total}


def vendor(root: Path, name: str, relative: str) -> dict:
    """Fit and measure the URDF ``root / relative`` (its ``package://`` names found under root's
    parent and the URDF's own parents)."""
    urdf = root / relative
    robot = read_urdf(urdf)
    dirs = [root.parent, *urdf.parents]
    started = time.process_time()
    fits = mesh_capsules(robot, tuple(robot.links), urdf.parent, dirs, cache=None)
    seconds = time.process_time() - started
    by_link: dict[str, list] = {}
    for link, capsule in fits.capsules:
        by_link.setdefault(link, []).append(capsule)
    rows = []
    for link, capsules in by_link.items():
        tag = "visual" if link in fits.from_visuals else "collision"
        rows.append((link, len(capsules), measure(oracle_points(urdf, link, tag, dirs), capsules)))
    for link, count, (held, total, caps, hull) in rows:
        print(
            f"    {link}: {count} capsule(s), {held}/{total} vertices, {caps / max(hull, 1e-12):.2f}x its hull",
            file=sys.stderr,
        )
    return report(name, rows, seconds)


def bundled(name: str) -> dict:
    folder = Path(str(resources.files("armanim.arm").joinpath("robots", name)))
    rows, started = [], time.process_time()
    for mesh in bundled_link_meshes(folder):
        capsules = fit_capsules(mesh.vertices, mesh.faces)
        rows.append((mesh.link, len(capsules), measure(mesh.vertices, capsules)))
    return report(f"bundled {name} (visual.npz)", rows, time.process_time() - started)


def vendor_urdfs(erd: Path | None, vamp: Path | None) -> list[tuple[Path, str, str]]:
    """(root, name, relative path) of each vendor URDF asked for."""
    out = []
    for root, urdfs in ((erd, VENDOR), (vamp, VAMP)):
        if root is not None:
            out += [(root, name, relative) for name, relative in urdfs.items()]
    return out


def against(urdfs: list[tuple[Path, str, str]], other: Path) -> None:
    """Another ``fitting.py`` (e.g. main's: ``git show main:src/armanim/arm/fitting.py > /tmp/f.py``)
    against this one, in one process robot by robot: the load is the same for both."""
    import importlib.util

    from armanim.arm import fitting
    from armanim.scene import meshcapsules

    spec = importlib.util.spec_from_file_location("fitting_other", other)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules["fitting_other"] = module  # dataclasses look their module up
    spec.loader.exec_module(module)
    print(f"| robot | fit CPU, {other.name} | fit CPU, this tree | ratio | capsule volume, this tree / {other.name} |")
    print("|---|---|---|---|---|")
    for root, name, relative in urdfs:
        urdf = root / relative
        robot = read_urdf(urdf)
        dirs = [root.parent, *urdf.parents]
        measured = []
        for fit in (module.fit_capsules, fitting.fit_capsules):
            meshcapsules.fit_capsules = fit  # type: ignore[attr-defined]
            started = time.process_time()
            fits = mesh_capsules(robot, tuple(robot.links), urdf.parent, dirs, cache=None)
            measured.append((time.process_time() - started, sum(c.volume for _, c in fits.capsules)))
        meshcapsules.fit_capsules = fitting.fit_capsules  # type: ignore[attr-defined]
        (t0, v0), (t1, v1) = measured
        print(f"| {name} | {t0:.1f} s | {t1:.1f} s | {t0 / t1:.1f}x | {v1 / v0:.4f} |", flush=True)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--erd", type=Path, help="example-robot-data's share folder (holds robots/)")
    parser.add_argument("--vamp", type=Path, help="VAMP's resources folder (holds panda/panda.urdf and ur5/ur5.urdf)")
    parser.add_argument(
        "--against", type=Path, help="another fitting.py to time and weigh this one against (needs --erd or --vamp)"
    )
    parser.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help="set one of armanim.arm.fitting's constants for this run (e.g. DIAGONALS=True, COARSE_AXES=3)",
    )
    args = parser.parse_args(argv)
    from armanim.arm import fitting

    for setting in args.set:
        name, _, value = setting.partition("=")
        setattr(
            fitting, name, type(getattr(fitting, name))(value == "True" if value in ("True", "False") else float(value))
        )
    if args.against is not None:
        against(vendor_urdfs(args.erd, args.vamp), args.against)
        return 0
    print("| robot | links fitted | capsules | vertices held (1e-6 m) | capsules / hulls | worst link | fit time |")
    print("|---|---|---|---|---|---|---|")
    results = {}
    for root, name, relative in vendor_urdfs(args.erd, args.vamp):
        results[name] = vendor(root, name, relative)
    for name in ("panda", "ur5", "iiwa"):
        results[name] = bundled(name)
    met = all(r["held"] and r["ratio"] <= 1.6 for r in results.values())
    print(f"targets (100 % held, <= 1.6x the hulls): {'met' if met else 'not met on every robot'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
