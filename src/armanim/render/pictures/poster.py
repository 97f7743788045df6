"""``poster.png``: one picture of a whole run, for slides.

The arm is drawn faintly at its pose on each goal (a strobe picture) and solidly at
its last pose, with the whole tip path and every goal in its final state, through the
same renderer as the video's frames.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from armanim.output.solved import SolvedRun
from armanim.render.settings import OutputOptions


def strobe_frames(reports: Sequence, frames: int) -> list[int]:
    """The frame on which the arm left each goal (its pose on that goal), without the last frame.

    >>> import types
    >>> r = [types.SimpleNamespace(last_frame=9), types.SimpleNamespace(last_frame=19)]
    >>> strobe_frames(r, 20)
    [9]
    """
    picks = sorted({int(r.last_frame) for r in reports if 0 <= r.last_frame < frames - 1})
    return picks


def poster_caption(reports: Sequence, frames: int, fps: float) -> str:
    """The poster's caption: goals reached and missed, and how long the run takes.

    >>> import types
    >>> poster_caption([types.SimpleNamespace(reached=True), types.SimpleNamespace(reached=False)], 60, 30.0)
    'goals 0-1: 1 reached, 1 missed   2.00 s, 60 frames'
    """
    reached = sum(bool(r.reached) for r in reports)
    goals = f"goals 0-{len(reports) - 1}: " if len(reports) > 1 else "goal 0: "
    return f"{goals}{reached} reached, {len(reports) - reached} missed   {frames / fps:.2f} s, {frames} frames"


def render_poster(run: SolvedRun, options: OutputOptions, path) -> None:
    """Draw the strobe picture of a run to a PNG of ``options.render.size`` pixels.

    Parameters
    ----------
    run : SolvedRun
        The run; its name is the title.
    options : OutputOptions
        ``render``: size, view, bounds and trail (``format`` is not used).
    path : str or Path
        Written atomically.
    """
    from armanim.arm.kinematics import Pose, forward
    from armanim.render.overlay.caption import MISSED, PENDING, REACHED, goal_outcomes
    from armanim.render.overlay.paths import path_progress
    from armanim.render.paint.pixels import write_png
    from armanim.render.pictures.canvas import FrameState, SceneCanvas, moving_objects, run_fingers
    from armanim.render.solids.arm import near_capsules

    problem, trajectory, reports, settings = run.problem, run.trajectory, run.reports, options.render
    poses = forward(problem.arm, trajectory.phi)
    last = trajectory.frames - 1
    caption = poster_caption(reports, trajectory.frames, trajectory.fps)
    near = near_capsules(problem, Pose(poses.points[last], poses.frames[last]))  # only the last pose is tinted
    still, carried = moving_objects(problem, run.solution)
    fingers = run_fingers(problem, run.solution)
    scene = SceneCanvas(
        still,
        settings,
        title=run.name,
        meshes=run.meshes,
        tips=trajectory.tip,
        extent=poses.points,
        caption_template=caption,
        picture="poster",
        outcomes=goal_outcomes(reports),
        near_self=near is not None and bool(near.any()),
    )
    status = np.full(len(problem.goals), PENDING)
    status[: len(reports)] = [REACHED if r.reached else MISSED for r in reports]
    ghosts = tuple(Pose(poses.points[f], poses.frames[f]) for f in strobe_frames(reports, trajectory.frames))
    done = path_progress(trajectory.goal, trajectory.path_s, len(problem.goals))[last] if scene.paths else None
    state = FrameState(
        Pose(poses.points[last], poses.frames[last]),
        trajectory.frames if settings.trail else 0,
        status,
        caption,
        ghosts=ghosts,
        path_done=done,  # all the run's ink, nothing ahead
        carried=None if carried is None else carried[last],
        fingers=fingers if fingers is None else float(fingers[last]),
    )
    write_png(scene.draw(state), path)
