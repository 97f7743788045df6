"""A trajectory to a video: one video frame per trajectory row, at the settings' fps.

With several jobs the frames are split into contiguous segments; each worker process
draws and encodes its own segment, and the segments are joined without re-encoding.
The result goes to a temporary file beside the target and is moved in place only when
complete: a failure or an interrupt leaves no partial video.
"""

from __future__ import annotations

import contextlib
import multiprocessing
import os
import queue as queue_module
import re
import shutil
import signal
import tempfile
import traceback
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np

from armanim.errors import OutputError, RenderError
from armanim.problem import Problem, RenderSettings
from armanim.trajectory import GoalReport, Trajectory
from armanim.workers import Stopped, alive, die_with

CHUNK = 256  # poses sent through forward kinematics at once (memory stays flat)
MIN_FRAMES_PER_JOB = 24  # fewer frames than this per worker are not worth a process
PROGRESS_EVERY = 8  # a worker reports its progress every this many frames
PALETTE_FRAMES = 12  # frames a GIF's palette is made from


def draw_segment(
    problem: Problem,
    trajectory: Trajectory,
    reports: Sequence[GoalReport],
    settings: RenderSettings,
    path: Path,
    *,
    title: str,
    start: int,
    stop: int,
    progress: Callable[[int], None] | None = None,
) -> None:
    """Draw frames ``start`` to ``stop - 1`` and encode them into ``path``.

    ``progress`` is called with the number of frames of this segment done so far.
    """
    from armanim.kinematics import Pose, forward
    from armanim.render.caption import frame_activity, frame_caption, goal_outcomes, goal_status
    from armanim.render.draw import FrameState, SceneCanvas
    from armanim.render.encode import FrameWriter, gif_palette

    extent = forward(problem.arm, trajectory.phi).points  # the whole run's, so every segment frames alike
    goals = len(problem.goals)
    activity = frame_activity(trajectory, reports)
    captions = [frame_caption(trajectory, f, goals, activity[f]) for f in range(trajectory.frames)]
    scene = SceneCanvas(problem, settings, title=title, tips=trajectory.tip, extent=extent,
                        caption_template=max(captions, key=len), outcomes=goal_outcomes(reports))

    def frame(f: int, pose: Pose) -> np.ndarray:
        state = FrameState(pose=pose, trail_end=f + 1, goal_status=goal_status(trajectory, reports, f, goals),
                           caption=captions[f])
        return scene.draw(state)

    with contextlib.ExitStack() as stack:
        palette = None
        if settings.format == "gif":  # one palette for the whole GIF, from frames spread over it
            palette = stack.enter_context(gif_palette(path, settings.size, (
                frame(f, forward(problem.arm, trajectory.phi[f])) for f in palette_frames(start, stop))))
        writer = stack.enter_context(FrameWriter(path, settings.size, settings.fps, settings.format, palette=palette))
        for first in range(start, stop, CHUNK):
            last = min(first + CHUNK, stop)
            poses = forward(problem.arm, trajectory.phi[first:last])
            for f in range(first, last):
                writer.write(frame(f, Pose(poses.points[f - first], poses.frames[f - first])))
                if progress is not None:
                    progress(f + 1 - start)


def palette_frames(start: int, stop: int, count: int = PALETTE_FRAMES) -> list[int]:
    """Frames, spread evenly over ``[start, stop)``, from which a GIF's palette is made.

    >>> palette_frames(0, 100, 5)
    [0, 24, 49, 74, 99]
    """
    return sorted({int(f) for f in np.linspace(start, stop - 1, min(count, stop - start))})


def render_video(
    problem: Problem,
    trajectory: Trajectory,
    reports: Sequence[GoalReport],
    settings: RenderSettings,
    path,
    *,
    title: str,
    jobs: int | None = None,
    progress: Callable[[int], None] | None = None,
) -> None:
    """Render a trajectory to an MP4 or a GIF, one video frame per trajectory row.

    Parameters
    ----------
    problem : Problem
        The arm, obstacles and goals that are drawn.
    trajectory : Trajectory
        Frames to draw (F rows).
    reports : sequence of GoalReport
        Reached / missed per goal, for the goal markers and the caption.
    settings : RenderSettings
        ``fps`` (exact frame rate of the video), ``size`` (pixels; an MP4 of odd
        width or height is padded by one pixel, as yuv420p needs even sides),
        view, bounds, trail, ``format`` ("mp4": libx264 yuv420p; "gif").
    path : str or Path
        The video file. Written to a temporary file beside it, then moved in place.
    title : str
        Shown top left on every frame.
    jobs : int, optional
        Worker processes, each drawing and encoding a contiguous segment, joined
        without re-encoding. Default ``os.cpu_count()``; limited so every worker
        gets at least ``MIN_FRAMES_PER_JOB`` frames. GIFs are always one job.
    progress : callable, optional
        Called with the number of frames done so far.

    Raises
    ------
    RenderError
        ffmpeg failed (its last lines are in the message) or a worker died. No
        partial file is left at ``path``.
    """
    from armanim.output.atomic import write_target

    path = write_target(Path(path))
    frames = trajectory.frames
    if frames == 0:
        raise RenderError(f"cannot write {path.name}: the trajectory has no frames")
    jobs = effective_jobs(jobs, frames, settings.format)
    remove_dead_leftovers(path)
    # not output/atomic.py's temporary file: ffmpeg writes this one by name, and the PID in
    # the name lets remove_dead_leftovers tell a killed render's file from a running one's
    tmp = path.with_name(f".{path.name}.{os.getpid()}.part")
    try:
        if jobs == 1:
            draw_segment(problem, trajectory, reports, settings, tmp, title=title, start=0, stop=frames,
                         progress=progress)
        else:
            _render_parallel(problem, trajectory, reports, settings, tmp, title, jobs, progress)
        os.replace(tmp, path)
    except RenderError as exc:  # name the video the user asked for, not its temporary file
        raise RenderError(str(exc).replace(tmp.name, path.name)) from None
    except OSError as exc:  # the folder, the log file or the segment folder could not be written
        from armanim.output.atomic import output_error

        raise output_error(path, exc) from None
    finally:
        tmp.unlink(missing_ok=True)


def remove_dead_leftovers(path: Path) -> None:
    """Remove the temporary video, segment folders and GIF palettes beside ``path`` of
    renders whose process is gone (killed outright); those of live processes are left alone."""
    name = re.escape(path.name)
    pattern = re.compile(rf"\.{name}\.([0-9]+)\.part|\.\.{name}\.([0-9]+)\.part\.[a-z0-9_]{{8}}(?:\.palette\.png)?")
    try:
        entries = list(path.parent.iterdir())
    except OSError:
        return
    for entry in entries:
        match = pattern.fullmatch(entry.name)
        if match is None or alive(int(match.group(1) or match.group(2))):
            continue
        if entry.is_dir() and not entry.is_symlink():
            shutil.rmtree(entry, ignore_errors=True)
        else:
            with contextlib.suppress(OSError):
                entry.unlink()


def effective_jobs(jobs: int | None, frames: int, fmt: str) -> int:
    """How many workers to use.

    >>> effective_jobs(8, 60, "mp4"), effective_jobs(2, 600, "gif"), effective_jobs(2, 600, "mp4")
    (2, 1, 2)
    """
    if fmt != "mp4":
        return 1
    wanted = jobs if jobs is not None else (os.cpu_count() or 1)
    return max(1, min(int(wanted), frames // MIN_FRAMES_PER_JOB))


def segment_bounds(frames: int, jobs: int) -> list[tuple[int, int]]:
    """Contiguous, nearly equal ``(start, stop)`` ranges covering ``range(frames)``.

    >>> segment_bounds(10, 3)
    [(0, 3), (3, 6), (6, 10)]
    """
    edges = np.linspace(0, frames, jobs + 1).astype(int)
    return [(int(a), int(b)) for a, b in zip(edges[:-1], edges[1:]) if b > a]


_WORKER_SIGNALS = (signal.SIGINT, signal.SIGTERM)


def _segment_worker(args: tuple, messages, parent: int) -> None:
    """Body of a worker process: draw and encode one segment, report through ``messages``.

    A worker ignores Ctrl-C (the terminal sends it to the whole process group; the
    parent decides) and turns SIGTERM, sent by the parent's ``terminate()``, into a
    quiet exit that still runs every ``finally``: its ffmpeg is killed, no traceback.
    Signals are blocked by the parent while it starts workers, so none arrives before
    these handlers are in place. A worker whose parent ends (even by ``kill -9``) stops
    the same way, so no worker or ffmpeg outlives armanim or holds its folder lock.
    """
    index = args[-1]
    problem, trajectory, reports, settings, path, title, start, stop, _ = args

    def stop_worker(signum, frame):
        signal.signal(signal.SIGTERM, signal.SIG_IGN)  # once: a second SIGTERM must not cut the clean-up short
        messages.cancel_join_thread()  # the parent no longer reads: never block on exit
        raise Stopped(128 + signum)

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, stop_worker)
    signal.pthread_sigmask(signal.SIG_UNBLOCK, _WORKER_SIGNALS)
    die_with(parent)

    def report(done: int) -> None:
        if done % PROGRESS_EVERY == 0 or done == stop - start:
            messages.put(("progress", index, done))

    try:
        draw_segment(problem, trajectory, reports, settings, path, title=title, start=start, stop=stop,
                     progress=report)
        messages.put(("done", index, None))
    except Stopped:
        raise
    except BaseException as err:  # noqa: BLE001  (reported to the parent, which raises)
        if isinstance(err, (RenderError, OutputError)):
            detail = str(err)
        elif isinstance(err, OSError):
            detail = f"cannot write {path.name}: {err.strerror or err}"
        else:
            detail = traceback.format_exc(limit=6)
        messages.put(("error", index, detail))


@contextlib.contextmanager
def _signals_blocked():
    """Block SIGINT and SIGTERM in this thread for the duration (processes forked meanwhile
    start with them blocked); signals that arrive are delivered when it ends."""
    old = signal.pthread_sigmask(signal.SIG_BLOCK, _WORKER_SIGNALS)
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)


def _render_parallel(problem, trajectory, reports, settings, tmp: Path, title, jobs, progress) -> None:
    from armanim.output.atomic import interrupts_deferred
    from armanim.render.encode import concat_segments

    ctx = multiprocessing.get_context()
    workdir = Path(tempfile.mkdtemp(prefix=f".{tmp.name}.", dir=tmp.parent))
    segments = segment_bounds(trajectory.frames, jobs)
    paths = [workdir / f"segment{i:03d}.mp4" for i in range(len(segments))]
    messages = ctx.Queue()
    workers = [
        ctx.Process(
            target=_segment_worker,
            args=((problem, trajectory, reports, settings, p, title, a, b, i), messages, os.getpid()),
            daemon=True,
        )
        for i, ((a, b), p) in enumerate(zip(segments, paths))
    ]
    started = []
    try:
        with _signals_blocked():
            for w in workers:
                w.start()
                started.append(w)
        _collect(workers, messages, progress)
        concat_segments(paths, tmp, settings.format)
    finally:
        with interrupts_deferred():  # a second Ctrl-C must not leave workers or files behind
            _stop_workers(started)
            messages.close()
            shutil.rmtree(workdir, ignore_errors=True)


def _stop_workers(workers, grace: float = 10.0) -> None:
    """Terminate the workers still running (each kills its ffmpeg) and wait for all of them."""
    for w in workers:
        if w.is_alive():
            w.terminate()
    for w in workers:
        w.join(timeout=grace)
        if w.is_alive():  # pragma: no cover  (stuck: no second chance)
            w.kill()
            w.join()


def _collect(workers, messages, progress) -> None:
    """Wait for every worker, relaying progress; raise RenderError on the first failure."""
    done_frames = [0] * len(workers)
    finished: set[int] = set()
    silent_exits: dict[int, int] = {}
    while len(finished) < len(workers):
        try:
            kind, index, value = messages.get(timeout=0.5)
        except queue_module.Empty:
            for i, w in enumerate(workers):
                if i in finished or w.is_alive():
                    continue
                if w.exitcode != 0:
                    raise RenderError(f"render worker {i} stopped unexpectedly (exit code {w.exitcode})") from None
                silent_exits[i] = silent_exits.get(i, 0) + 1
                if silent_exits[i] > 2:  # ended without a word after its messages were drained
                    raise RenderError(f"render worker {i} ended without finishing its segment") from None
            continue
        if kind == "progress":
            done_frames[index] = value
            if progress is not None:
                progress(sum(done_frames))
        elif kind == "done":
            finished.add(index)
        else:
            raise RenderError(f"render worker {index} failed:\n{value}")
    for w in workers:
        with contextlib.suppress(Exception):
            w.join(timeout=30)
