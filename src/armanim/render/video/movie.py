"""A trajectory to a video: one video frame per trajectory row, at the run's fps.

With several jobs the frames are split into contiguous segments; each worker process
draws and encodes its own segment (:mod:`armanim.render.video.segment`), and the segments are
joined without re-encoding (:mod:`armanim.render.video.parallel`).
The result goes to a temporary file beside the target and is moved in place only when
complete: a failure or an interrupt leaves no partial video.
"""

from __future__ import annotations

import contextlib
import os
import re
import shutil
from collections.abc import Callable
from pathlib import Path

from armanim.errors import RenderError
from armanim.output.solved import SolvedRun
from armanim.procs.workers import alive
from armanim.render.settings import OutputOptions
from armanim.render.video.parallel import render_parallel
from armanim.render.video.segment import draw_segment

MIN_FRAMES_PER_JOB = 24  # fewer frames than this per worker are not worth a process


def render_video(
    run: SolvedRun,
    options: OutputOptions,
    path,
    *,
    progress: Callable[[int], None] | None = None,
    meanwhile: Callable[[], None] | None = None,
) -> None:
    """Render a run to an MP4 or a GIF, one video frame per trajectory row.

    Parameters
    ----------
    run : SolvedRun
        The arm, obstacles and goals that are drawn, the frames (F rows; ``run.fps`` is the
        exact frame rate of the video), the goals' reports (for the markers and the caption);
        its name is shown top left on every frame.
    options : OutputOptions
        ``render``: ``size`` (pixels; an MP4 of odd
        width or height is padded by one pixel, as yuv420p needs even sides),
        view, bounds, trail, ``format`` ("mp4": libx264 yuv420p; "gif"). ``jobs``: worker
        processes, each drawing and encoding a contiguous segment, joined without
        re-encoding; default ``os.cpu_count()``, limited so every worker gets at least
        ``MIN_FRAMES_PER_JOB`` frames. GIFs are always one job.
    path : str or Path
        The video file. Written to a temporary file beside it, then moved in place.
    progress : callable, optional
        Called with the number of frames done so far.
    meanwhile : callable, optional
        Other work of this process (another picture), done while worker processes draw the
        video; with one job, after the video. An exception from it ends the render as a
        failure of the video does.

    Raises
    ------
    RenderError
        ffmpeg failed (its last lines are in the message) or a worker died. No
        partial file is left at ``path``.
    """
    from armanim.output.atomic import write_target

    path = write_target(Path(path))
    settings = options.render
    frames = run.trajectory.frames
    if frames == 0:
        raise RenderError(f"cannot write {path.name}: the trajectory has no frames")
    jobs = effective_jobs(options.jobs, frames, settings.format)
    remove_dead_leftovers(path)
    # not output/atomic.py's temporary file: ffmpeg writes this one by name, and the PID in
    # the name lets remove_dead_leftovers tell a killed render's file from a running one's
    tmp = path.with_name(f".{path.name}.{os.getpid()}.part")
    other = _Other(meanwhile) if meanwhile is not None else None
    try:
        if jobs == 1:
            draw_segment(run, settings, tmp, start=0, stop=frames, progress=progress)
            if other is not None:
                other()
        else:
            render_parallel(run, settings, tmp, jobs, progress, other)
        os.replace(tmp, path)
    except _OtherFailed as failed:  # the other picture's own error, not the video's
        raise failed.error from None
    except RenderError as exc:  # name the video the user asked for, not its temporary file
        raise RenderError(str(exc).replace(tmp.name, path.name)) from None
    except OSError as exc:  # the folder, the log file or the segment folder could not be written
        from armanim.output.atomic import output_error

        raise output_error(path, exc) from None
    finally:
        tmp.unlink(missing_ok=True)


class _OtherFailed(Exception):
    """An Exception of the work done meanwhile, carried past the video's own error handling."""

    def __init__(self, error: Exception):
        super().__init__(str(error))
        self.error = error


class _Other:
    """``meanwhile`` with its exceptions wrapped in :class:`_OtherFailed`."""

    def __init__(self, work: Callable[[], None]):
        self.work = work

    def __call__(self) -> None:
        try:
            self.work()
        except Exception as err:  # noqa: BLE001  (re-raised as itself by render_video)
            raise _OtherFailed(err) from err


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
