"""Issue 52: which of the fit's candidate capsule sets a link's MotionBenchMaker count depends on.

For each link named, every candidate set the fit chooses among (:func:`armanim.arm.fitting.candidate_fits`:
one capsule and the best cuts into 2 and 3, each finished as the kept one is) is put in place of the
link's fitted capsules, every other link keeping its own, and the 700 Panda problems are checked as
``mbm_starts_bench.py --urdf`` checks them (``armanim validate``'s checks, the importer's 0.5 mm). Beside
each count, measures of the set against the link's convex hull: its volume, its volume outside the hull
(the fit's own grid, as the fit weighs it), its farthest stand-out (the capsules' surface points, not
inside another capsule of the set, their largest distance above the hull's face planes) and its mean
stand-out against a plane (the support functions' difference, capsules less hull, averaged over 512
directions: how much sooner a wall from a random direction meets the capsules than the mesh).
``--pick LINK=K`` (repeatable) checks one combination of candidates and prints its count.

Run: ``python benchmarks/mbm_fit_candidates.py /work/shared/data/mbm --urdf /work/vamp/resources/panda/panda.urdf
--srdf /work/vamp/resources/panda/panda.srdf --links panda_link5 panda_link7 panda_hand`` (each candidate is a
full check of the 700 problems: some 35 s of CPU on a quiet machine).
"""

from __future__ import annotations

import argparse
import sys
import tarfile
import tempfile
import time
from pathlib import Path

import numpy as np
from mbm_starts_bench import check

from armanim.arm import fitting
from armanim.arm.fitting import FittedCapsule, candidate_fits, fit_capsules
from armanim.scene.meshcapsules import link_meshes
from armanim.scene.moveitscene import RobotSource, moveit_scene
from armanim.scene.urdf import read_urdf

DIRECTIONS = 512


def scenes(folder: Path, urdf: Path, srdf: Path | None, limit: int | None) -> list[dict]:
    """The Panda problems imported for ``urdf`` (the scene data, its files named absolutely)."""
    robot, out = RobotSource(urdf=urdf, srdf=srdf), []
    with tempfile.TemporaryDirectory() as tmp, tarfile.open(folder / "panda" / "problems.tar.bz2") as archive:
        archive.extractall(tmp, filter="data")
        for scene in sorted(Path(tmp).glob("problems/*/scene*.yaml"))[:limit]:
            request = scene.with_name(scene.name.replace("scene", "request"))
            data = moveit_scene(scene, request, robot, Path(tmp) / "out.yaml").data
            data["arm"]["urdf"] = str(urdf.resolve())
            if srdf is not None:
                data["arm"]["self_collision"]["srdf"] = str(srdf.resolve())
            out.append(data)
    return out


def admitted(problems: list[dict], capsules: list[tuple[str, FittedCapsule]]) -> int:
    """How many problems nothing is wrong with under ``capsules`` (link, capsule) as ``arm.collision``
    (``mbm_starts_bench.check``, the list in place of a mode's name)."""
    written = [
        {"link": link, "from": c.start.tolist(), "to": c.end.tolist(), "radius": c.radius} for link, c in capsules
    ]
    return sum(check(data, written)[1] for data in problems)  # type: ignore[arg-type]


def fibonacci_directions(n: int) -> np.ndarray:
    """(n, 3) unit vectors spread evenly over the sphere."""
    k = np.arange(n) + 0.5
    polar, turn = np.arccos(1.0 - 2.0 * k / n), np.pi * (1.0 + 5.0**0.5) * k
    return np.stack([np.cos(turn) * np.sin(polar), np.sin(turn) * np.sin(polar), np.cos(polar)], axis=1)


def surface_points(capsule: FittedCapsule, around: int = 24) -> np.ndarray:
    """Points on a capsule's surface: rings a quarter radius apart along its segment, seven rings on each cap."""
    a, b, r = capsule.start, capsule.end, capsule.radius
    length = float(np.linalg.norm(b - a))
    d = (b - a) / length if length > 0 else np.array([0.0, 0.0, 1.0])
    u, v = fitting._perpendiculars(d)
    turn = np.linspace(0.0, 2.0 * np.pi, around, endpoint=False)
    ring = np.cos(turn)[:, None] * u + np.sin(turn)[:, None] * v
    rows = [a + s * (b - a) + r * ring for s in np.linspace(0.0, 1.0, int(np.ceil(length / (0.25 * r + 1e-12))) + 1)]
    for end, sign in ((a, -1.0), (b, 1.0)):
        rows += [end + r * (np.cos(p) * ring + sign * np.sin(p) * d) for p in np.linspace(0.0, np.pi / 2.0, 8)[1:]]
    return np.concatenate(rows)


def weighed(points: np.ndarray, capsules: list[FittedCapsule]) -> dict[str, float]:
    """The set's measures against the convex hull of ``points`` (volumes as multiples of the hull's, stand-outs in mm)."""
    from scipy.spatial import ConvexHull

    hull = ConvexHull(points)
    planes = hull.equations
    farthest = 0.0
    for i, capsule in enumerate(capsules):
        surface = surface_points(capsule)
        for j, other in enumerate(capsules):
            if j != i:
                surface = surface[
                    fitting.segment_distances(surface, other.start, other.end) > other.radius * (1 - 1e-9)
                ]
        if len(surface):
            farthest = max(farthest, float((surface @ planes[:, :3].T + planes[:, 3]).max()))
    n = fibonacci_directions(DIRECTIONS)
    reach = np.max([np.maximum(n @ c.start, n @ c.end) + c.radius for c in capsules], axis=0)
    outside = fitting._Outside(points if len(points) <= fitting.SEARCH_POINTS else fitting._search_points(points))
    fits = [(c.volume, c.start, c.end, c.radius) for c in capsules]
    return {
        "volume": sum(c.volume for c in capsules) / hull.volume,
        "outside": outside.volume(fits) / hull.volume,
        "farthest": 1000.0 * farthest,
        "plane": 1000.0 * float(np.mean(reach - (points @ n.T).max(axis=0))),
    }


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder", type=Path, help="the folder of panda/problems.tar.bz2")
    parser.add_argument("--urdf", type=Path, required=True, help="VAMP's mesh panda.urdf")
    parser.add_argument("--srdf", type=Path, default=None, help="its SRDF")
    parser.add_argument("--links", nargs="*", default=["panda_link5", "panda_link7", "panda_hand"])
    parser.add_argument("--pick", action="append", default=[], metavar="LINK=K", help="check this combination only")
    parser.add_argument("--limit", type=int, default=None)
    args = parser.parse_args(argv)
    robot = read_urdf(args.urdf)
    meshes = {
        link: (v, f)
        for link, v, f, _ in link_meshes(robot, tuple(robot.links), args.urdf.parent, [*args.urdf.parents], [])
    }
    started = time.process_time()
    fitted = {link: fit_capsules(v, f) for link, (v, f) in meshes.items()}
    print(f"fitted {len(fitted)} links in {time.process_time() - started:.1f} s of CPU", flush=True)
    problems = scenes(args.folder, args.urdf, args.srdf, args.limit)
    total = len(problems)
    picks = {link: int(k) for link, _, k in (p.partition("=") for p in args.pick)}
    if picks:
        chosen = dict(fitted)
        for link, k in picks.items():
            chosen[link] = candidate_fits(*meshes[link])[0][k]
        count = admitted(problems, [(link, c) for link, caps in chosen.items() for c in caps])
        print(f"{', '.join(f'{link} candidate {k}' for link, k in picks.items())}: {count}/{total} problems admitted")
        return 0
    print(
        f"all links as fitted: {admitted(problems, [(link, c) for link, caps in fitted.items() for c in caps])}/{total}"
    )
    print(
        "| link | candidate | capsules | kept | volume / hull | outside / hull | farthest stand-out | mean stand-out to a plane | problems admitted |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    for link in args.links:
        sets, kept = candidate_fits(*meshes[link])
        same = [(c.start.tolist(), c.end.tolist(), c.radius) for c in sets[kept]]
        assert same == [(c.start.tolist(), c.end.tolist(), c.radius) for c in fitted[link]], "the kept set is the fit"
        points = np.unique(meshes[link][0], axis=0)
        others = [(name, c) for name, caps in fitted.items() if name != link for c in caps]
        for k, capsules in enumerate(sets):
            w = weighed(points, capsules)
            count = admitted(problems, others + [(link, c) for c in capsules])
            print(
                f"| {link} | {k} | {len(capsules)} | {'yes' if k == kept else ''} | {w['volume']:.3f} | {w['outside']:.3f} | "
                f"{w['farthest']:.1f} mm | {w['plane']:.2f} mm | {count}/{total} |",
                flush=True,
            )
    return 0


if __name__ == "__main__":
    sys.exit(main())
