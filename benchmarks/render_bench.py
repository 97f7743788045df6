"""Rendering speed and memory: ``armanim run`` against a FuncAnimation baseline, as whole processes.

Run: ``python benchmarks/render_bench.py`` (a few minutes on two cores; ``--quick`` for a smoke run).

1. Speed at 1280x720 on a bundled scene (default ``scenes/notes-arm.yaml``), each
   measured as the whole command a user types, start-up and solve included:
   - baseline: a script that loads and solves the scene, then saves a
     ``matplotlib.animation.FuncAnimation`` over mplot3d axes whose artists are built
     once and updated in place every frame (``set_data_3d``, ``set_text``), with
     ``FFMpegWriter`` (libx264);
   - ``armanim run SCENE --jobs 2 --size 1280x720``.
   armanim runs once before and once after the baseline, so a change in the machine's
   load during the long baseline hits both alike; the ratio uses the mean of the two.
   Frames per second of each and the ratio are printed (target: >= 8x). With
   ``--baseline-frames N`` the baseline animates only its first N frames and its
   whole-run time is extrapolated as start-up + F x (time per animated frame).
   Beside it, the limits of armanim's two halves on one core: drawing only
   (``SceneCanvas.draw`` for every frame, nothing encoded) and encoding only (the
   same number of already drawn frames sent to the MP4 writer).
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

ROOT = Path(__file__).resolve().parent.parent
SIZE = (1280, 720)


def solved(scene: str):
    """(loaded scene, problem, solution) of a scene file, solved at its own fps."""
    from armanim.motion.trajectory import solve_trajectory
    from armanim.scene import load_scene, scene_to_problem

    loaded = load_scene(scene)
    problem = scene_to_problem(loaded.model)
    return loaded, problem, solve_trajectory(problem)


def baseline_child(scene: str, out: str, frames: int | None) -> None:
    """In a fresh process: solve, then FuncAnimation with in-place updates; print timings."""
    start = time.perf_counter()
    import imageio_ffmpeg
    import matplotlib
    from matplotlib.animation import FFMpegWriter, FuncAnimation
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    from armanim.arm.kinematics import forward

    _, problem, solution = solved(scene)
    traj = solution.trajectory
    matplotlib.rcParams["animation.ffmpeg_path"] = imageio_ffmpeg.get_ffmpeg_exe()
    dpi = 100
    fig = Figure(figsize=(SIZE[0] / dpi, SIZE[1] / dpi), dpi=dpi)
    FigureCanvasAgg(fig)
    ax = fig.add_subplot(projection="3d")
    points = forward(problem.arm, traj.phi).points
    lo, hi = points.reshape(-1, 3).min(axis=0) - 2, points.reshape(-1, 3).max(axis=0) + 2
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_zlim(lo[2], hi[2])
    u, v = np.mgrid[0 : 2 * np.pi : 24j, 0 : np.pi : 12j]
    sphere = np.stack([np.cos(u) * np.sin(v), np.sin(u) * np.sin(v), np.cos(v)])
    for c, r in zip(problem.obstacles.centers, problem.obstacles.radii):
        ax.plot_surface(*(c[:, None, None] + r * sphere), color="tab:red", shade=True)
    goals = np.array([g.position for g in problem.goals])
    ax.scatter(*goals.T, color="green")
    (arm,) = ax.plot([], [], [], "-o", color="tab:blue", linewidth=5)
    (trail,) = ax.plot([], [], [], color="orange")
    title = ax.set_title("")

    def update(f):
        p = points[f]
        arm.set_data_3d(p[:, 0], p[:, 1], p[:, 2])
        trail.set_data_3d(*traj.tip[: f + 1].T)
        title.set_text(f"t = {f / traj.fps:.2f} s  goal {traj.goal[f]}  d = {traj.distance[f]:.3f}")
        return arm, trail, title

    count = traj.frames if frames is None else min(frames, traj.frames)
    ready = time.perf_counter()
    anim = FuncAnimation(fig, update, frames=count, blit=False)
    anim.save(out, writer=FFMpegWriter(fps=traj.fps, codec="libx264"), dpi=dpi)
    done = time.perf_counter()
    print(json.dumps({"frames": traj.frames, "animated": count, "setup_s": ready - start, "loop_s": done - ready}))


def whole_process(cmd: list[str]) -> float:
    """Seconds of a fresh process, from start to exit."""
    start = time.perf_counter()
    subprocess.run(cmd, check=True, capture_output=True, text=True, cwd=ROOT)
    return time.perf_counter() - start


def baseline(scene: str, work: Path, frames: int | None) -> tuple[float, int]:
    """Whole-process seconds of the baseline (extrapolated to every frame if capped), frames."""
    cmd = [sys.executable, __file__, "--baseline-child", scene, "--out", str(work / "baseline.mp4")]
    if frames is not None:
        cmd += ["--baseline-frames", str(frames)]
    start = time.perf_counter()
    result = subprocess.run(cmd, check=True, capture_output=True, text=True, cwd=ROOT)
    total = time.perf_counter() - start
    data = json.loads(result.stdout.strip().splitlines()[-1])
    startup = total - data["loop_s"]
    return startup + data["loop_s"] * data["frames"] / data["animated"], data["frames"]


def drawing_only(scene: str) -> float:
    """Frames per second of SceneCanvas.draw alone, one core, every frame of the scene."""
    from armanim.arm.kinematics import Pose, forward
    from armanim.render.overlay.caption import frame_activity, frame_caption, goal_status
    from armanim.render.pictures.canvas import FrameState, SceneCanvas
    from armanim.scene import render_settings

    loaded, problem, solution = solved(scene)
    traj, reports = solution.trajectory, solution.goals
    settings = dataclasses.replace(render_settings(loaded.model), size=SIZE)
    start = time.perf_counter()
    poses = forward(problem.arm, traj.phi)
    canvas = SceneCanvas(problem, settings, title=loaded.name, tips=traj.tip, extent=poses.points)
    activity = frame_activity(traj, reports)
    goals = len(problem.goals)
    for f in range(traj.frames):
        state = FrameState(
            Pose(poses.points[f], poses.frames[f]),
            f + 1,
            goal_status(traj, reports, f, goals),
            frame_caption(traj, f, goals, activity[f]),
        )
        canvas.draw(state)
    return traj.frames / (time.perf_counter() - start)


def encoding_only(frames: int, work: Path) -> float:
    """Frames per second of the MP4 writer alone, one process, fed frames of a moving square."""
    from armanim.render.video.encode import FrameWriter

    canvas = np.full((SIZE[1], SIZE[0], 4), 255, dtype=np.uint8)
    start = time.perf_counter()
    with FrameWriter(work / "encode.mp4", SIZE, 30.0, "mp4") as writer:
        for f in range(frames):
            frame = canvas.copy()
            x = (7 * f) % (SIZE[0] - 80)
            frame[300:380, x : x + 80, :3] = (40, 100, 200)
            writer.write(frame)
    return frames / (time.perf_counter() - start)


def lengthen(trajectory, frames: int):
    """The trajectory repeated (cyclically) to exactly ``frames`` rows."""
    idx = np.arange(frames) % trajectory.frames
    fields = {f.name: getattr(trajectory, f.name) for f in dataclasses.fields(trajectory)}
    return dataclasses.replace(trajectory, **{k: v[idx] for k, v in fields.items() if isinstance(v, np.ndarray)})


def memory_child(scene: str, frames: int, out: str) -> None:
    """In a fresh process: render ``frames`` frames at 640x360, print peak RSS (self and children), KiB."""
    from armanim.motion.solution import Solution
    from armanim.output.solved import SolvedRun
    from armanim.render.settings import OutputOptions
    from armanim.render.video.movie import render_video
    from armanim.scene import render_settings

    loaded, problem, solution = solved(scene)
    settings = dataclasses.replace(render_settings(loaded.model), size=(640, 360))
    run = SolvedRun("benchmark", problem, Solution(lengthen(solution.trajectory, frames), solution.goals))
    render_video(run, OutputOptions(settings, jobs=1), Path(out))
    own = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    children = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    print(json.dumps({"self_kib": own, "children_kib": children}))


def peak_memory(scene: str, frames: int, work: Path) -> dict:
    cmd = [
        sys.executable,
        __file__,
        "--memory-child",
        str(frames),
        "--scene",
        scene,
        "--out",
        str(work / f"mem{frames}.mp4"),
    ]
    result = subprocess.run(cmd, capture_output=True, text=True, check=True, cwd=ROOT)
    return json.loads(result.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scene", default="scenes/notes-arm.yaml")
    parser.add_argument("--baseline-frames", type=int, default=None, help="animate only this many baseline frames")
    parser.add_argument("--quick", action="store_true", help="baseline capped at 60 frames, memory at 100 vs 1000")
    parser.add_argument("--baseline-child", help=argparse.SUPPRESS)
    parser.add_argument("--memory-child", type=int, help=argparse.SUPPRESS)
    parser.add_argument("--out", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.baseline_child:
        baseline_child(args.baseline_child, args.out, args.baseline_frames)
        return
    if args.memory_child:
        memory_child(args.scene, args.memory_child, args.out)
        return
    capped = 60 if args.quick and args.baseline_frames is None else args.baseline_frames
    small, large = (100, 1000) if args.quick else (300, 3000)
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        run = [
            sys.executable,
            "-m",
            "armanim",
            "run",
            args.scene,
            "--out",
            str(work / "runs"),
            "--jobs",
            "2",
            "--size",
            f"{SIZE[0]}x{SIZE[1]}",
            "--quiet",
        ]
        t_before = whole_process(run)
        t_base, frames = baseline(args.scene, work, capped)
        t_after = whole_process(run)
        note = f" (extrapolated from {capped} frames)" if capped else ""
        t_run = (t_before + t_after) / 2
        fps_base, fps_run = frames / t_base, frames / t_run
        print(f"{args.scene}: {frames} frames at {SIZE[0]}x{SIZE[1]}, whole processes")
        print(f"  baseline FuncAnimation, in-place   {t_base:7.2f} s  {fps_base:6.1f} frames/s   1.00x{note}")
        print(
            f"  armanim run --jobs 2               {t_run:7.2f} s  {fps_run:6.1f} frames/s  {fps_run / fps_base:5.2f}x"
            f"  (target >= 8x; runs before/after the baseline: {t_before:.2f} s, {t_after:.2f} s)"
        )
        draw = drawing_only(args.scene)
        enc = encoding_only(frames, work)
        print(
            f"  limits on one core: drawing only {draw:6.1f} frames/s ({draw / fps_base:5.2f}x),"
            f" encoding only {enc:6.1f} frames/s ({enc / fps_base:5.2f}x)"
        )
        a, b = peak_memory(args.scene, small, work), peak_memory(args.scene, large, work)
        print(
            f"peak RSS at 640x360, jobs=1: {small} frames {a['self_kib'] / 1024:.1f} MiB, {large} frames"
            f" {b['self_kib'] / 1024:.1f} MiB, ratio {b['self_kib'] / a['self_kib']:.3f}  (target <= 1.2;"
            f" ffmpeg: {a['children_kib'] / 1024:.1f} -> {b['children_kib'] / 1024:.1f} MiB)"
        )


if __name__ == "__main__":
    main()
