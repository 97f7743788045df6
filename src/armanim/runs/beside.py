"""A first run's second core: another process compiles, during the solve, what the run calls after it.

At its first call after installing, numba compiles each of armanim's kernels in the process that
calls it, one after the other (:mod:`armanim.runs.warmth`). A run calls the solve's kernels first
(the frame loop: most of the compiling), then the clock's passes, the record's exact margins and,
for a video, the rasteriser. Those do not wait on the solve: :func:`compiling_beside` starts
``python -m armanim.runs.beside SCENE PID`` as the run starts, on the core the solve leaves idle, and it
calls them as the run will (:func:`compile_after_solve`: the same kernels, the same argument
types). numba's cache is shared: the run loads what the other process compiled. The other process
waits for the run's compiles (:func:`armanim.arm.kernel.held_alone`) but holds no lock itself
(:func:`armanim.arm.kernel.compile_without_holding_locks`), so the run never waits on it: a kernel
both reach at once is compiled by both. The outputs are the same bytes either way; the process
writes nothing but numba's cache, and it does not outlive the command.
"""

from __future__ import annotations

import contextlib
import os
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

STOP_WAIT_S = 5.0
"""Seconds the run gives the process to end after SIGTERM before it kills it."""


def compile_after_solve(scene_path: str | Path, video: bool) -> None:
    """Call, in this process, the kernels a run of the scene at ``scene_path`` calls after its solve,
    with the argument types the run passes: the exact margins of its world and self pairs (two of the
    arm's home poses), the clock's passes (a small move from home, at the scene's rate limits) and,
    with ``video``, the rasteriser's loops (:func:`armanim.runs.warm.draw_in_memory`)."""
    import numpy as np

    from armanim.motion.planning.check import frame_margins
    from armanim.motion.timing.goalmotion import goal_motion
    from armanim.scene import scene_to_problem
    from armanim.scene.loader import load_scene

    problem = scene_to_problem(load_scene(scene_path).model)
    home = np.asarray(problem.home, dtype=float)
    frame_margins(problem, np.stack([home, home]))
    rates = problem.rates
    goal_motion(
        np.stack([home, home + 0.1]),
        problem.limits.limited,
        rates.speed,
        rates.acceleration,
        problem.fps,
        jerk=rates.jerk,
    )
    if video:
        from armanim.runs.warm import draw_in_memory

        draw_in_memory()


def should_compile_beside(scene_path: Path, jobs: int) -> bool:
    """Whether a run of ``scene_path`` with ``jobs`` cores starts :func:`compiling_beside`'s process:
    a second core is allowed, the scene is a regular file (a pipe is read once, by the run), numba
    keeps its compiled code (else the run could not load the other's) and the solve's kernels are
    not compiled yet (:func:`armanim.runs.warmth.compiles_first`: a first run)."""
    if jobs < 2 or not scene_path.is_file():
        return False
    from armanim.runs.warmth import compiles_first, machine_code_kept

    return compiles_first("run") and machine_code_kept()


@contextlib.contextmanager
def compiling_beside(scene_path: Path, video: bool, jobs: int) -> Iterator[None]:
    """While the body runs (a run of the scene at ``scene_path``), a second process compiles what the run
    calls after its solve (:func:`compile_after_solve`), when :func:`should_compile_beside`; it is
    ended as the body ends (SIGTERM, then SIGKILL) if it has not finished."""
    if not should_compile_beside(scene_path, jobs):
        yield
        return
    from armanim.procs.workers import signals_blocked

    try:
        with signals_blocked():  # it starts with Ctrl-C and SIGTERM held, until its handlers are in place
            process = subprocess.Popen(
                beside_command(scene_path, video),
                stdin=subprocess.DEVNULL,
                stdout=subprocess.DEVNULL,
                stderr=subprocess.DEVNULL,
            )
    except OSError:  # no process to start (no Python to run, no memory): the run compiles everything itself
        yield
        return
    try:
        yield
    finally:
        ended(process)


def beside_command(scene_path: Path, video: bool) -> list[str]:
    """The command line of :func:`compiling_beside`'s process: this Python, :func:`main`, told this
    process's id (it ends with it)."""
    video_flag = ["--video"] if video else []
    return [sys.executable, "-m", "armanim.runs.beside", str(scene_path), str(os.getpid()), *video_flag]


def ended(process: subprocess.Popen) -> None:
    """``process`` ended: at once if it has (reaped), else after SIGTERM, else after SIGKILL."""
    if process.poll() is not None:
        return
    process.terminate()
    try:
        process.wait(STOP_WAIT_S)
    except subprocess.TimeoutExpired:
        process.kill()
        process.wait()


def main(argv: list[str]) -> int:
    """``python -m armanim.runs.beside SCENE PARENT [--video]``: :func:`compile_after_solve`, as a
    worker of process PARENT (:func:`armanim.procs.workers.init_worker`: it ignores Ctrl-C, for the
    run decides; ends at once on SIGTERM; and ends when PARENT does, however it ends). 0 when done, 1
    on any failure: it says nothing, for the run it helps reports its scene's problems."""
    from armanim.arm.kernel import compile_without_holding_locks
    from armanim.procs.workers import init_worker

    try:
        init_worker(int(argv[1]))
        compile_without_holding_locks()  # the run never waits on this process's compiles
        compile_after_solve(argv[0], "--video" in argv[2:])
    except Exception:  # noqa: BLE001 (the run compiles whatever was not)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
