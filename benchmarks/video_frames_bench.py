"""Where a video frame's CPU goes: each drawing step of a solved run's frames, per frame.

Run: ``python benchmarks/video_frames_bench.py RUN [RUN ...]`` (run folders of ``armanim run``,
e.g. ``armanim run scenes/ur5-pen.yaml --no-video --out /tmp/runs``); ``--frames N --start F`` the
frames drawn (default 400 from 0); ``--against SRC`` another armanim source folder (its src/)
measured the same way, alternated with this one ``--rounds`` times. Each round is a fresh
process: the run's scene is drawn once (not timed), then its frames one after the other, as a
video's worker draws them, each with its yuv420p planes (what a worker sends to ffmpeg; the
encoding itself is not here). The steps are the canvas's and the rasteriser's functions, each
wrapped in a timer of process CPU (a step's time holds the steps it calls), so a machine shared
with other work stretches them less than the wall clock; compare trees only within one run.
"""

from __future__ import annotations

import argparse
import functools
import importlib
import os
import subprocess
import sys
import time
from collections import Counter, defaultdict

STEPS = (
    ("armanim.render.pictures.canvas", "SceneCanvas.draw"),
    ("armanim.render.pictures.canvas", "SceneCanvas._draw_shadow"),
    ("armanim.render.pictures.canvas", "SceneCanvas._draw_solids"),
    ("armanim.render.pictures.canvas", "SceneCanvas._draw_tool_triad"),
    ("armanim.render.pictures.canvas", "SceneCanvas._flush"),
    ("armanim.render.solids.robot", "RobotMeshes.parts"),
    ("armanim.render.solids.robot", "RasterQueue.flush"),
    ("armanim.render.solids.rasterloops", "fill_samples"),
    ("armanim.render.solids.rasterloops", "blend_samples"),
    ("armanim.render.solids.order", "paint_order"),
    ("armanim.render.solids.obstacle_order", "ObstacleOrder.paint_order"),
    ("armanim.render.overlay.markers", "GoalMarkers.draw"),
    ("armanim.render.overlay.glyphs", "GlyphAtlas.stamp"),
    ("armanim.render.video.planes", "yuv420"),
    ("matplotlib.collections", "Collection.draw"),
    ("matplotlib.lines", "Line2D.draw"),
)


def timed_steps() -> tuple[dict, Counter]:
    """Wrap every step of :data:`STEPS` (and rebind the names the canvas imported) in a CPU timer."""
    spent: dict[str, float] = defaultdict(float)
    calls: Counter = Counter()
    for module_name, qualified in STEPS:
        module = importlib.import_module(module_name)
        owner, name = (
            (getattr(module, qualified.split(".")[0]), qualified.split(".")[1])
            if "." in qualified
            else (module, qualified)
        )
        function = getattr(owner, name)

        def timed(*args, _f=function, _q=qualified, **kwargs):
            start = time.process_time()
            try:
                return _f(*args, **kwargs)
            finally:
                spent[_q] += time.process_time() - start
                calls[_q] += 1

        setattr(owner, name, functools.wraps(function)(timed))
    canvas = importlib.import_module("armanim.render.pictures.canvas")
    canvas.paint_order = importlib.import_module("armanim.render.solids.order").paint_order
    return spent, calls


def one_round(run: str, frames: int, start: int) -> None:
    """Draw ``frames`` frames of ``run`` from ``start`` in this process and print each step's CPU a frame."""
    import numpy as np

    spent, calls = timed_steps()
    from armanim.render.video.planes import yuv420
    from armanim.render.video.segment import chunked_poses, frame_drawer
    from armanim.runs.options import RunOptions
    from armanim.runs.pipeline import redrawn
    from armanim.runs.reload import load_run

    solved, options = redrawn(load_run(run), RunOptions())
    frame = frame_drawer(solved, options.render)
    trajectory = solved.trajectory
    poses = list(chunked_poses(solved.problem.arm, trajectory.phi, start, min(trajectory.frames, start + frames)))
    frame(*poses[0])  # (the compiled code loaded, the glyphs drawn: not timed)
    spent.clear(), calls.clear()
    width, height = options.render.size
    planes = np.empty(width * height * 3 // 2, dtype=np.uint8)
    begin = time.process_time()
    for f, pose in poses:
        yuv420(frame(f, pose), planes)
    total = (time.process_time() - begin) / len(poses)
    print(f"  {len(poses)} frames: {total * 1e3:.2f} ms of CPU a frame (drawing and yuv planes)")
    for step, seconds in sorted(spent.items(), key=lambda kv: -kv[1]):
        print(f"    {step:30s} {seconds / len(poses) * 1e3:6.2f} ms  ({calls[step] / len(poses):.1f} calls)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("runs", nargs="+")
    parser.add_argument("--frames", type=int, default=400)
    parser.add_argument("--start", type=int, default=0)
    parser.add_argument("--against", help="another armanim source folder (its src/), alternated with this one")
    parser.add_argument("--rounds", type=int, default=1)
    parser.add_argument("--one", action="store_true", help=argparse.SUPPRESS)  # a round, in a fresh process
    args = parser.parse_args()
    if args.one:
        one_round(args.runs[0], args.frames, args.start)
        return
    print(f"load average before: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    trees = ({"against": args.against} if args.against else {}) | {"this": None}
    for run in args.runs:
        for k in range(args.rounds):
            for name, src in trees.items():
                print(f"{run}, {name}, round {k + 1}:", flush=True)
                env = dict(os.environ, PYTHONPATH=src) if src else None
                command = [
                    sys.executable,
                    __file__,
                    run,
                    "--one",
                    "--frames",
                    str(args.frames),
                    "--start",
                    str(args.start),
                ]
                subprocess.run(command, check=True, env=env)
    print(f"load average after: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")


if __name__ == "__main__":
    main()
