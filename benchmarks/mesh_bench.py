"""Issue 38's benchmark: video frames of the bundled robot scenes drawn with the robots' meshes
against the same frames drawn as capsules, in one process, interleaved.

For each scene: solve once at 10 fps, then draw every frame with ``render.robot: mesh`` and with
``capsules`` (the picture before meshes), alternating, best of ``--rounds`` CPU times each. Prints
the milliseconds a frame and the frame-rate ratio (target: meshes at >= 0.8x the capsules' frame
rate at 1280 x 720), and notes-arm (an arm of links: no meshes) drawn twice, whose ratio must stay 1.

Run: ``python benchmarks/mesh_bench.py [--size 1280x720] [--rounds 3]``.
"""

from __future__ import annotations

import argparse
import time
from dataclasses import replace
from pathlib import Path

from armanim.arm.kinematics import forward
from armanim.render.settings import RenderOverrides
from armanim.render.video.segment import frame_drawer
from armanim.runs.options import RunOptions, output_choice
from armanim.runs.pipeline import solve_scene, with_meshes
from armanim.scene import load_scene

ROOT = Path(__file__).resolve().parent.parent
SCENES = (
    "panda-place",
    "panda-clutter",
    "panda-shelf",
    "ur5-table",
    "ur5-pen",
    "ur5-around",
    "iiwa-redundancy",
    "notes-arm",
)


def frame_seconds(run, settings) -> float:
    """CPU seconds to draw every frame of ``run`` once."""
    draw = frame_drawer(run, settings)
    poses = [forward(run.problem.arm, phi) for phi in run.trajectory.phi]
    draw(0, poses[0])  # the first frame compiles and caches
    start = time.process_time()
    for f, pose in enumerate(poses):
        draw(f, pose)
    return time.process_time() - start


def measure(name: str, size: tuple[int, int], rounds: int) -> tuple[float, float, int]:
    """(ms a frame with meshes, ms a frame as capsules, triangles drawn) for one scene."""
    scene = load_scene(ROOT / "scenes" / f"{name}.yaml")
    settings = output_choice(scene, RunOptions(render=RenderOverrides(size=size)))[1].render
    run = solve_scene(scene, 10.0)
    meshed, _ = with_meshes(run, scene, settings)
    capsules = replace(settings, robot="capsules")
    best = {"mesh": float("inf"), "capsules": float("inf")}
    for _ in range(rounds):
        best["mesh"] = min(best["mesh"], frame_seconds(meshed, settings))
        best["capsules"] = min(best["capsules"], frame_seconds(run, capsules))
    frames = run.trajectory.frames
    triangles = meshed.meshes.triangles if meshed.meshes is not None else 0
    return 1000 * best["mesh"] / frames, 1000 * best["capsules"] / frames, triangles


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--size", default="1280x720")
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args()
    size = tuple(int(v) for v in args.size.split("x"))
    print(f"{'scene':<16} {'triangles':>9} {'mesh ms':>8} {'capsule ms':>10} {'fps ratio':>9}")
    for name in SCENES:
        mesh, caps, triangles = measure(name, size, args.rounds)
        print(f"{name:<16} {triangles:>9,} {mesh:>8.2f} {caps:>10.2f} {caps / mesh:>9.2f}")


if __name__ == "__main__":
    main()
