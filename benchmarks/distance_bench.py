"""Distances to boxes and capsules (issue 22): armanim's closed form (compiled with numba) against coal.

    python benchmarks/distance_bench.py            # best of 5
    python benchmarks/distance_bench.py --quick    # best of 2

What a run needs is measured both ways on the same arm and shapes: the notes' arm (4 links,
radius 0.25) plus its tip, among 3 boxes and 2 capsule obstacles (25 part-shape pairs):

- **one pose** (what every frame's safety filter computes): armanim's ``clearances`` with its
  closest points and normals, against one ``coal.distance`` per pair (with the coal objects
  built once, only each link's transform per pose, as a run would have to);
- **a batch of 1000 poses** (what the planner checks): armanim's ``clearances`` (every pair
  exactly) and ``min_link_clearance`` (exact only where a bound leaves doubt), against coal
  pair by pair.

Before timing, the two are checked to agree to 1e-9 on every clear pair. Prints microseconds
and the ratio coal / armanim (above 1: armanim is faster). Nothing asserts on times.
The closed form is compiled (and cached) before the first timing.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from armanim.arm.capsules import capsule_ends, joint_capsules
from armanim.arm.chain import rpy_rotation
from armanim.arm.kinematics import Arm, forward
from armanim.world.distances import clearances, min_link_clearance
from armanim.world.obstacles import BOX, ROD, Boxes, Obstacles, Rods


def scene():
    """The notes' arm, its capsules and five shapes around it."""
    arm = Arm.from_names([2, 5, 5, 5], base=(5, 5, 0))
    boxes = Boxes(
        np.array([[12.0, 5, 3], [8.0, 12, 9], [2.0, 0, 12]]),
        np.array([[1.0, 3, 0.5], [2.0, 0.3, 2], [1.0, 1, 1]]),
        np.stack([rpy_rotation(r) for r in ([0, 0, 0.3], [0.2, 0.1, 1.0], [0.5, 0.5, 0.5])]),
    )
    rods = Rods(np.array([[0.0, 8, 0], [10.0, 0, 12]]), np.array([[0.0, 8, 10], [14.0, 3, 12]]), np.array([0.5, 0.3]))
    kinds = np.array([BOX, BOX, BOX, ROD, ROD])
    return (
        arm,
        joint_capsules(arm, 0.25),
        Obstacles(np.zeros((0, 3)), np.zeros(0), np.ones(5), boxes, rods, None, kinds),
    )


def coal_objects(obstacles):
    """coal's boxes and capsules with their placements."""
    import coal
    from oracles.geometry import coal_capsule

    boxes, rods = obstacles.boxes, obstacles.rods
    shapes = [
        (coal.Box(*(2 * h)), coal.Transform3s(r, c)) for c, h, r in zip(boxes.centers, boxes.half, boxes.rotations)
    ]
    return shapes + [coal_capsule(a, b, float(r)) for a, b, r in zip(rods.start, rods.end, rods.radius)]


def coal_clearances(shapes, a, b, radius):
    """(k, s) clearances of segments a-b (k, 3) of radii (k,) to every shape, one coal call per pair."""
    import coal
    from oracles.geometry import coal_capsule

    request = coal.DistanceRequest()
    request.gjk_tolerance = 1e-13
    out = np.empty((len(a), len(shapes)))
    for i, (p, q) in enumerate(zip(a, b)):
        part = (
            coal_capsule(p, q, float(radius[i]))
            if np.linalg.norm(q - p) > 0
            else (coal.Sphere(float(radius[i])), coal.Transform3s(np.eye(3), p))
        )
        for j, (shape, placement) in enumerate(shapes):
            result = coal.DistanceResult()
            out[i, j] = coal.distance(shape, placement, part[0], part[1], request, result)
            result.normal  # what the filter needs  # noqa: B018
    return out


def parts(capsules, pose):
    """Segment ends (..., c+1, 3) and radii (c+1,) of the capsules and the tip."""
    a, b = capsule_ends(capsules, pose)
    tip = pose.points[..., -1:, :]
    return np.concatenate([a, tip], axis=-2), np.concatenate([b, tip], axis=-2), np.append(capsules.radius, 0.0)


def best_of(repeats: int, run) -> float:
    """Least wall time of ``run()`` over ``repeats`` calls, seconds."""
    best = np.inf
    for _ in range(repeats):
        start = time.perf_counter()
        run()
        best = min(best, time.perf_counter() - start)
    return best


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args(argv)
    repeats = 2 if args.quick else 5
    arm, capsules, obstacles = scene()
    shapes = coal_objects(obstacles)
    rng = np.random.default_rng(22)
    phi = rng.uniform(-np.pi, np.pi, (1000, arm.n))
    pose = forward(arm, phi)
    a, b, radius = parts(capsules, pose)
    ours = clearances(pose, obstacles, capsules).d
    theirs = np.array([coal_clearances(shapes, a[k], b[k], radius) for k in range(50)])
    clear = (ours[:50] > 1e-6) & (theirs > 1e-6)
    print(
        f"agreement on {clear.sum()} clear pairs: max |armanim - coal| = {np.abs(ours[:50] - theirs)[clear].max():.2e}"
    )

    singles = [forward(arm, q) for q in phi[:100]]
    ours_one = best_of(repeats, lambda: [clearances(p, obstacles, capsules) for p in singles]) / 100
    coal_one = best_of(repeats, lambda: [coal_clearances(shapes, *parts(capsules, p)) for p in singles]) / 100
    ours_all = best_of(repeats, lambda: clearances(forward(arm, phi), obstacles, capsules)) / 1000
    ours_min = best_of(repeats, lambda: min_link_clearance(forward(arm, phi), obstacles, capsules)) / 1000
    coal_all = (
        best_of(
            max(1, repeats // 2),
            lambda: [coal_clearances(shapes, *parts(capsules, forward(arm, q))) for q in phi[:200]],
        )
        / 200
    )
    pairs = len(radius) * len(shapes)
    print(f"{pairs} part-shape pairs per pose; microseconds per pose (per pair):")
    print(
        f"  one pose   armanim clearances {1e6 * ours_one:8.1f} ({1e6 * ours_one / pairs:.2f})   coal {1e6 * coal_one:8.1f} "
        f"({1e6 * coal_one / pairs:.2f})   coal/armanim {coal_one / ours_one:.2f}"
    )
    print(
        f"  1000 poses armanim clearances {1e6 * ours_all:8.1f} ({1e6 * ours_all / pairs:.2f})   coal {1e6 * coal_all:8.1f} "
        f"({1e6 * coal_all / pairs:.2f})   coal/armanim {coal_all / ours_all:.2f}"
    )
    print(f"  1000 poses armanim min_link_clearance {1e6 * ours_min:8.1f}   coal/armanim {coal_all / ours_min:.2f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
