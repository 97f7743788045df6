"""Rendering speed and memory: armanim's renderer against a naive FuncAnimation.

Run: ``python benchmarks/render_bench.py`` (about two minutes on two cores).

1. Speed at 1280x720 on the same solved trajectory (the course notes' arm,
   3 obstacles, 4 goals):
   - baseline: ``matplotlib.animation.FuncAnimation(...).save(...)`` on a pyplot-free
     Figure that clears and redraws everything every frame (first ``--baseline-frames``),
   - ``render_video`` with jobs=1 and jobs=2 (every frame).
   Frames per second and the ratios to the baseline are printed (target: >= 5x with 2 jobs).
2. Peak memory (max RSS of a fresh process) rendering 3000 vs 300 frames
   (target ratio <= 1.2: memory stays flat with the video's length).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from armanim.kinematics import Arm, forward
from armanim.problem import Goal, Limits, Obstacles, Problem, RenderSettings, SolverSettings
from armanim.trajectory import solve_trajectory


def bench_problem() -> Problem:
    """The course notes' arm with 3 obstacles and 4 goals."""
    arm = Arm.from_names([2, 5, 5, 5], base=(5, 5, 0))
    limits = Limits(
        np.array([-np.inf, *np.radians([-100, -150, -150])]),
        np.array([np.inf, *np.radians([100, 150, 150])]),
        np.radians(15),
    )
    obstacles = Obstacles(
        np.array([[12.0, 9, 8], [4, 13, 10], [10, 0, 12]]), np.array([2.0, 1.5, 1.8]), np.array([2.0, 1.5, 1.5])
    )
    goals = (
        Goal(np.array([14.0, 5, 6])),
        Goal(np.array([6.0, 15, 9]), hold_frames=15),
        Goal(np.array([8.0, -2, 4])),
        Goal(np.array([2.0, 8, 14])),
    )
    return Problem(arm, 0.3, np.zeros(4), limits, obstacles, goals, SolverSettings(max_step=0.5), fps=30.0)


def lengthen(trajectory, frames: int):
    """The trajectory repeated (cyclically) to exactly ``frames`` rows."""
    idx = np.arange(frames) % trajectory.frames
    fields = {f.name: getattr(trajectory, f.name) for f in dataclasses.fields(trajectory)}
    return dataclasses.replace(
        trajectory, **{k: v[idx] for k, v in fields.items() if isinstance(v, np.ndarray)}
    )


def baseline(problem: Problem, trajectory, path: Path, frames: int, size=(1280, 720)) -> float:
    """Naive FuncAnimation: clear the axes and redraw everything every frame. Returns seconds."""
    import imageio_ffmpeg
    import matplotlib
    from matplotlib.animation import FFMpegWriter, FuncAnimation
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    matplotlib.rcParams["animation.ffmpeg_path"] = imageio_ffmpeg.get_ffmpeg_exe()
    dpi = 100
    fig = Figure(figsize=(size[0] / dpi, size[1] / dpi), dpi=dpi)
    FigureCanvasAgg(fig)
    ax = fig.add_subplot(projection="3d")
    points = forward(problem.arm, trajectory.phi).points
    goals = np.array([g.position for g in problem.goals])
    u, v = np.mgrid[0 : 2 * np.pi : 24j, 0 : np.pi : 12j]
    sphere = np.stack([np.cos(u) * np.sin(v), np.sin(u) * np.sin(v), np.cos(v)])

    def update(f):
        ax.cla()
        ax.set_xlim(-13, 23)
        ax.set_ylim(-13, 23)
        ax.set_zlim(-13, 23)
        for c, r in zip(problem.obstacles.centers, problem.obstacles.radii):
            ax.plot_surface(*(c[:, None, None] + r * sphere), color="tab:red", shade=True)
        p = points[f]
        ax.plot(p[:, 0], p[:, 1], p[:, 2], "-o", color="tab:blue", linewidth=5)
        ax.plot(*trajectory.tip[: f + 1].T, color="orange")
        ax.scatter(*goals.T, color="green")
        ax.set_title(f"t = {f / trajectory.fps:.2f} s  goal {trajectory.goal[f] + 1}  d = {trajectory.distance[f]:.3f}")
        return []

    anim = FuncAnimation(fig, update, frames=frames, blit=False)
    start = time.perf_counter()
    anim.save(str(path), writer=FFMpegWriter(fps=trajectory.fps, codec="libx264"), dpi=dpi)
    return time.perf_counter() - start


def timed_render(problem, trajectory, reports, path: Path, jobs: int, size=(1280, 720)) -> float:
    from armanim.render.video import render_video

    start = time.perf_counter()
    render_video(problem, trajectory, reports, RenderSettings(size=size), path, title="benchmark", jobs=jobs)
    return time.perf_counter() - start


def memory_child(frames: int, size: tuple[int, int], jobs: int, out: str) -> None:
    """In a fresh process: render ``frames`` frames, print peak RSS (self and children), KiB."""
    problem = bench_problem()
    solution = solve_trajectory(problem)
    trajectory = lengthen(solution.trajectory, frames)
    timed_render(problem, trajectory, solution.goals, Path(out), jobs, size)
    own = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    children = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    print(json.dumps({"self_kib": own, "children_kib": children}))


def peak_memory(frames: int, size, jobs: int, workdir: Path) -> dict:
    cmd = [sys.executable, __file__, "--memory-child", str(frames), "--size", f"{size[0]}x{size[1]}",
           "--jobs", str(jobs), "--out", str(workdir / f"mem{frames}.mp4")]
    result = subprocess.run(cmd, capture_output=True, text=True, check=True)
    return json.loads(result.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--baseline-frames", type=int, default=120)
    parser.add_argument("--memory-size", default="640x360", help="frame size of the memory runs")
    parser.add_argument("--memory-child", type=int, help=argparse.SUPPRESS)
    parser.add_argument("--size", default="1280x720", help=argparse.SUPPRESS)
    parser.add_argument("--jobs", type=int, default=1, help=argparse.SUPPRESS)
    parser.add_argument("--out", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.memory_child:
        memory_child(args.memory_child, tuple(int(v) for v in args.size.split("x")), args.jobs, args.out)
        return

    problem = bench_problem()
    solution = solve_trajectory(problem)
    trajectory, reports = solution.trajectory, solution.goals
    frames = trajectory.frames
    print(f"trajectory: {frames} frames, {solution.reached}/{len(reports)} goals reached; size 1280x720")
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        nb = min(args.baseline_frames, frames)
        t_base = baseline(problem, trajectory, work / "baseline.mp4", nb)
        fps_base = nb / t_base
        print(f"baseline FuncAnimation.save   {nb:5d} frames  {t_base:7.2f} s  {fps_base:7.1f} frames/s   1.00x")
        for jobs in (1, 2):
            t = timed_render(problem, trajectory, reports, work / f"jobs{jobs}.mp4", jobs)
            fps = frames / t
            print(f"render_video jobs={jobs}           {frames:5d} frames  {t:7.2f} s  {fps:7.1f} frames/s"
                  f"  {fps / fps_base:5.2f}x")
        size = tuple(int(v) for v in args.memory_size.split("x"))
        small = peak_memory(300, size, 1, work)
        large = peak_memory(3000, size, 1, work)
        print(f"peak RSS at {size[0]}x{size[1]}, jobs=1: 300 frames {small['self_kib'] / 1024:.1f} MiB,"
              f" 3000 frames {large['self_kib'] / 1024:.1f} MiB, ratio {large['self_kib'] / small['self_kib']:.3f}"
              f"  (ffmpeg: {small['children_kib'] / 1024:.1f} -> {large['children_kib'] / 1024:.1f} MiB)")


if __name__ == "__main__":
    main()
