"""Instructions per frame, shapes against their spheres-only twin: issue 22's frame-cost ratio
measured so that a busy machine cannot move it.

    python benchmarks/frame_instructions.py --family robot-shapes --scenes 4 --methods dls,gradient

Each scene of ``motion_bench.py``'s shape families is solved (planner off) with its boxes,
capsules and floor, and as its spheres-only twin (``Draft.spheres_twin``: each shape replaced by
the largest sphere inside it, the floor dropped), each in a fresh Python under valgrind's
callgrind, which counts the instructions executed: the same count on every run, whatever else
the machine does. A run that loads the same scenes without solving them is the baseline
(interpreter start, imports, URDF and scene loading) taken off each. CPU time per frame
(``motion_bench.py --timing-rounds``) is what the target names; on a busy machine the same
solve's CPU-time ratio moves by 10-20 % from one run to the next, and this count shows a
change's effect where that time cannot. It is not the target's measure: the shapes' many small
numpy calls spend more time per instruction than the spheres' few, so the count's ratio runs
some 5-6 % under the timed one (benchmarks/README.md). Needs ``valgrind`` on PATH; about a
minute per scene and method.
"""

from __future__ import annotations

import argparse
import os
import pickle
import re
import subprocess
import sys
import tempfile
from pathlib import Path

from generators.families import SHAPE_FAMILIES, make_scene, scene_name

SOLVE = """
import pickle, sys
from armanim.motion.trajectory import solve_trajectory
from armanim.scene import scene_to_problem
from armanim.scene import scene_model
scenes = [scene_to_problem(scene_model(d)) for d in pickle.load(open(sys.argv[1], "rb"))]
if sys.argv[2] == "solve":
    print("FRAMES", sum(solve_trajectory(problem).trajectory.frames for problem in scenes))
"""


def counted(scenes: list, folder: Path, solve: bool = True) -> tuple[int, int]:
    """(instructions, frames) of solving the scene mappings ``scenes`` in a fresh Python under
    callgrind (``solve`` False: of only loading them)."""
    data = folder / "scenes.pkl"
    data.write_bytes(pickle.dumps(scenes))
    env = dict(
        os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1", PYTHONHASHSEED="0"
    )  # idle BLAS threads spin: counts would vary
    out = subprocess.run(
        [
            "valgrind",
            "--tool=callgrind",
            "--callgrind-out-file=/dev/null",
            sys.executable,
            "-c",
            SOLVE,
            str(data),
            "solve" if solve else "load",
        ],
        capture_output=True,
        text=True,
        env=env,
        check=True,
    )
    instructions = int(re.search(r"Collected : (\d+)", out.stderr).group(1))
    frames = re.search(r"FRAMES (\d+)", out.stdout)
    return instructions, int(frames.group(1)) if frames else 0


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--family", choices=sorted(SHAPE_FAMILIES), default="robot-shapes")
    parser.add_argument("--scenes", type=int, default=4, help="scenes 0..N-1 of the family (default 4)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--methods", default="dls,gradient", help="comma-separated methods (default dls,gradient)")
    args = parser.parse_args(argv)
    drafts = [make_scene(args.seed, k, args.family) for k in range(args.scenes)]
    print(
        f"| method | shapes: M instructions/frame | spheres twin | ratio |   ({args.family}, seed {args.seed}, {args.scenes} scenes, planner off)"
    )
    print("|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for method in [m for m in args.methods.split(",") if m]:
            per_frame = []
            for twin in (False, True):
                scenes = [
                    (d.spheres_twin() if twin else d).as_scene_dict(
                        scene_name(args.seed, k, method, "off"), method, "off"
                    )
                    for k, d in enumerate(drafts)
                ]
                instructions, frames = counted(scenes, Path(tmp))
                per_frame.append((instructions - counted(scenes, Path(tmp), solve=False)[0]) / max(frames, 1) / 1e6)
            print(
                f"| {method} | {per_frame[0]:.3f} | {per_frame[1]:.3f} | {per_frame[0] / per_frame[1]:.2f}x |",
                flush=True,
            )
    return 0


if __name__ == "__main__":
    sys.exit(main())
