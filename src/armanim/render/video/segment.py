"""One contiguous run of a trajectory's frames, drawn and encoded into one file.

A video of one job is one segment; with several jobs each worker process draws its own
(:mod:`armanim.render.video.parallel`). Every segment frames the scene by the whole run, so
segments join without a jump.
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable, Iterator
from pathlib import Path

import numpy as np

from armanim.arm.kinematics import Arm, Pose, forward
from armanim.output.solved import SolvedRun
from armanim.render.overlay.caption import frame_activity, frame_caption, goal_outcomes, goal_status
from armanim.render.settings import RenderSettings

CHUNK = 256  # poses sent through forward kinematics at once (memory stays flat)
PALETTE_FRAMES = 12  # frames a GIF's palette is made from


def draw_segment(
    run: SolvedRun,
    settings: RenderSettings,
    path: Path,
    *,
    start: int,
    stop: int,
    progress: Callable[[int], None] | None = None,
    frame: Callable[[int, Pose], np.ndarray] | None = None,
) -> None:
    """Draw frames ``start`` to ``stop - 1`` of ``run`` and encode them into ``path``.

    ``progress`` is called with the number of frames of this segment done so far. ``frame``: the
    run's :func:`frame_drawer` for ``settings`` when one is built already (a worker forked from
    the process that built it); else it is built here.
    """
    from armanim.render.video.encode import FrameWriter, gif_palette

    problem, trajectory = run.problem, run.trajectory
    if frame is None:
        frame = frame_drawer(run, settings)
    with contextlib.ExitStack() as stack:
        palette = None
        if settings.format == "gif":  # one palette for the whole GIF, from frames spread over it
            palette = stack.enter_context(
                gif_palette(
                    path,
                    settings.size,
                    (frame(f, forward(problem.arm, trajectory.phi[f])) for f in palette_frames(start, stop)),
                )
            )
        writer = stack.enter_context(FrameWriter(path, settings.size, run.fps, settings.format, palette=palette))
        for f, pose in chunked_poses(problem.arm, trajectory.phi, start, stop):
            writer.write(frame(f, pose))
            if progress is not None:
                progress(f + 1 - start)


def frame_drawer(run: SolvedRun, settings: RenderSettings) -> Callable[[int, Pose], np.ndarray]:
    """The scene of a run drawn once (its name the title), as a function of (frame number,
    pose) -> RGBA frame.

    The frame returned is the canvas's live buffer: consume it before the next call.
    """
    from armanim.render.overlay.paths import path_progress
    from armanim.render.pictures.canvas import FrameState, SceneCanvas, moving_objects, near_in_frames, run_fingers

    problem, trajectory, reports = run.problem, run.trajectory, run.reports
    still, carried = moving_objects(problem, run.solution)
    fingers = run_fingers(problem, run.solution)
    extent = forward(problem.arm, trajectory.phi).points  # the whole run's, so every segment frames alike
    goals = len(problem.goals)
    activity = frame_activity(trajectory, reports)
    captions = [frame_caption(trajectory, f, goals, activity[f], problem.rates.speed) for f in range(trajectory.frames)]
    scene = SceneCanvas(
        still,
        settings,
        title=run.name,
        meshes=run.meshes,
        tips=trajectory.tip,
        extent=extent,
        caption_template=max(captions, key=len),
        outcomes=goal_outcomes(reports),
        near_self=near_in_frames(problem, trajectory.self_clearance),
    )
    done = path_progress(trajectory.goal, trajectory.path_s, goals) if scene.paths else None

    def frame(f: int, pose: Pose) -> np.ndarray:
        state = FrameState(
            pose=pose,
            trail_end=f + 1,
            goal_status=goal_status(trajectory, reports, f, goals),
            caption=captions[f],
            path_done=None if done is None else done[f],
            path_ahead=int(trajectory.goal[f]),
            carried=None if carried is None else carried[f],
            fingers=None if fingers is None else float(fingers[f]),
        )
        return scene.draw(state)

    return frame


def chunked_poses(arm: Arm, phi: np.ndarray, start: int, stop: int) -> Iterator[tuple[int, Pose]]:
    """Frames ``start`` .. ``stop - 1`` with their poses, ``CHUNK`` poses through forward kinematics at once."""
    for first in range(start, stop, CHUNK):
        last = min(first + CHUNK, stop)
        poses = forward(arm, phi[first:last])
        for f in range(first, last):
            yield f, Pose(poses.points[f - first], poses.frames[f - first])


def palette_frames(start: int, stop: int, count: int = PALETTE_FRAMES) -> list[int]:
    """Frames, spread evenly over ``[start, stop)``, from which a GIF's palette is made.

    >>> palette_frames(0, 100, 5)
    [0, 24, 49, 74, 99]
    """
    return sorted({int(f) for f in np.linspace(start, stop - 1, min(count, stop - start))})
