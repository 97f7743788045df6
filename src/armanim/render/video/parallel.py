"""Render a video in worker processes: contiguous segments, each drawn and encoded by its
own worker, joined without re-encoding.

Where workers are forked (Linux), the parent draws the scene's static part once (imports,
framing, background, meshes: :func:`~armanim.render.video.segment.frame_drawer`) and every
worker inherits it, instead of each building its own. While the workers draw, the parent does
the caller's other work (the plot, the poster, the viewer page), so no core waits on another.

Workers start with SIGINT and SIGTERM blocked, ignore Ctrl-C (the parent decides),
stop quietly on the parent's ``terminate()`` and when the parent dies, so no worker or
ffmpeg outlives armanim. Progress and failures come back on a queue.
"""

from __future__ import annotations

import contextlib
import multiprocessing
import os
import queue as queue_module
import shutil
import tempfile
import traceback
from collections.abc import Callable
from pathlib import Path

import numpy as np

from armanim.errors import OutputError, RenderError
from armanim.output.solved import SolvedRun
from armanim.procs.workers import init_worker, resource_tracker_started, signals_blocked
from armanim.render.settings import RenderSettings
from armanim.render.video.segment import draw_segment, frame_drawer

PROGRESS_EVERY = 8  # a worker reports its progress every this many frames


def segment_bounds(frames: int, jobs: int) -> list[tuple[int, int]]:
    """Contiguous, nearly equal ``(start, stop)`` ranges covering ``range(frames)``.

    >>> segment_bounds(10, 3)
    [(0, 3), (3, 6), (6, 10)]
    """
    edges = np.linspace(0, frames, jobs + 1).astype(int)
    return [(int(a), int(b)) for a, b in zip(edges[:-1], edges[1:]) if b > a]


def _segment_worker(args: tuple, messages, parent: int) -> None:
    """Body of a worker process: draw and encode one segment, report through ``messages``.

    A worker ignores Ctrl-C (the terminal sends it to the whole process group; the
    parent decides) and turns SIGTERM, sent by the parent's ``terminate()``, into a
    quiet exit that kills its ffmpeg (:func:`armanim.procs.workers.init_worker`).
    Signals are blocked by the parent while it starts workers, so none arrives before
    these handlers are in place. A worker whose parent ends (even by ``kill -9``) stops
    the same way, so no worker or ffmpeg outlives armanim or holds its folder lock.
    """
    run, settings, path, start, stop, index, frame = args
    init_worker(parent)

    def report(done: int) -> None:
        if done % PROGRESS_EVERY == 0 or done == stop - start:
            messages.put(("progress", index, done))

    try:
        draw_segment(run, settings, path, start=start, stop=stop, progress=report, frame=frame)
        messages.put(("done", index, None))
    except BaseException as err:  # noqa: BLE001  (reported to the parent, which raises)
        if isinstance(err, (RenderError, OutputError)):
            detail = str(err)
        elif isinstance(err, OSError):
            detail = f"cannot write {path.name}: {err.strerror or err}"
        else:
            detail = traceback.format_exc(limit=6)
        messages.put(("error", index, detail))


def render_parallel(
    run: SolvedRun,
    settings: RenderSettings,
    tmp: Path,
    jobs: int,
    progress: Callable[[int], None] | None,
    meanwhile: Callable[[], None] | None = None,
) -> None:
    """Render the video ``tmp`` of ``run`` in ``jobs`` worker processes, one contiguous segment
    each, and join the segments (see :func:`armanim.render.video.movie.render_video`).

    ``meanwhile`` is called in this process once the workers have started (its progress
    reports wait until it returns); an exception from it stops the workers and is raised.
    """
    from armanim.procs.deferred import interrupts_deferred
    from armanim.render.video.encode import concat_segments

    ctx = multiprocessing.get_context()
    frame = inherited_drawer(run, settings) if ctx.get_start_method() == "fork" else None
    workdir = Path(tempfile.mkdtemp(prefix=f".{tmp.name}.", dir=tmp.parent))
    segments = segment_bounds(run.trajectory.frames, jobs)
    paths = [workdir / f"segment{i:03d}.mp4" for i in range(len(segments))]
    messages = ctx.Queue()
    workers = [
        ctx.Process(
            target=_segment_worker,
            args=((run, settings, p, a, b, i, frame), messages, os.getpid()),
            daemon=True,
        )
        for i, ((a, b), p) in enumerate(zip(segments, paths))
    ]
    started = []
    try:
        with signals_blocked():
            resource_tracker_started(ctx)  # a forkserver or spawn context (Python 3.14's default) starts one
            for w in workers:
                w.start()
                started.append(w)
        if meanwhile is not None:
            meanwhile()
        _collect(workers, messages, progress)
        concat_segments(paths, tmp, settings.format)
    finally:
        with interrupts_deferred():  # a second Ctrl-C must not leave workers or files behind
            _stop_workers(started)
            messages.close()
            shutil.rmtree(workdir, ignore_errors=True)


def inherited_drawer(run: SolvedRun, settings: RenderSettings):
    """The run's frame drawer, built here for forked workers to inherit, and warmed by drawing
    the first frame once (the compiled rasteriser is loaded before the fork, not in each worker)."""
    from armanim.arm.kinematics import Pose, forward

    frame = frame_drawer(run, settings)
    pose = forward(run.problem.arm, run.trajectory.phi[:1])
    frame(0, Pose(pose.points[0], pose.frames[0]))
    return frame


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
