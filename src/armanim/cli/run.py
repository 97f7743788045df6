"""``armanim run`` and ``armanim render``: animate scenes, and redraw a finished run."""

from __future__ import annotations

import contextlib
import functools
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from armanim.cli.app import app, err, handle_errors, message_lines, print_notes, say, tell_first_compile
from armanim.cli.interrupts import ignore_until_exit
from armanim.cli.options import (
    JobsOpt,
    QualityOpt,
    QuietOpt,
    SchedulerOpt,
    render_overrides,
    usable_cores,
    usable_jobs,
)
from armanim.cli.reports import (
    batch_exit_code,
    print_batch_problems,
    print_batch_table,
    print_goal_table,
    print_missed_goals,
)
from armanim.errors import EXIT_CHECK_FAILED, InterruptedAfterCommit

if TYPE_CHECKING:
    from armanim.runs.options import RunOptions


@app.command()
@handle_errors
def run(
    scenes: Annotated[list[Path], typer.Argument(help="Scene files to run.", show_default=False)],
    out_root: Annotated[Path, typer.Option("--out", help="Outputs go to OUT/<scene name>/.")] = Path("outputs"),
    no_video: Annotated[
        bool,
        typer.Option("--no-video", help="Write trajectory.csv and summary.json only (and viewer.html with --viewer)."),
    ] = False,
    viewer: Annotated[
        bool | None,
        typer.Option(
            "--viewer/--no-viewer",
            help="Write viewer.html, the interactive 3-D page (default: when the video is written).",
            show_default=False,
        ),
    ] = None,
    quiet: QuietOpt = False,
    jobs: Annotated[
        int | None,
        typer.Option(
            "--jobs",
            "-j",
            help="Worker processes (default: all cores): scenes in parallel for a batch, video segments for one scene.",
        ),
    ] = None,
    scheduler: SchedulerOpt = None,
    size: Annotated[str | None, typer.Option("--size", help="Override render.size, e.g. 640x360.")] = None,
    fps: Annotated[float | None, typer.Option("--fps", help="Override render.fps.")] = None,
    fmt: Annotated[str | None, typer.Option("--format", help="Override render.format: mp4 or gif.")] = None,
    quality: QualityOpt = None,
    strict: Annotated[bool, typer.Option("--strict", help="Exit 1 if any goal is missed.")] = False,
) -> None:
    """Animate scenes: solve every goal and write OUT/<name>/ with the outputs.

    The outputs: trajectory.csv, summary.json, the video, plot.png, poster.png and viewer.html (open it in a browser; see docs/viewer.md). Several scenes run in parallel and also write OUT/index.csv; a bad scene is reported and the others finish (exit 2 if any scene was invalid, 3 if any failed while writing).

    Examples:

    [bold]armanim run scenes/notes-arm.yaml[/bold]

    [bold]armanim run scenes/*.yaml --jobs 2 --no-video[/bold]
    """
    from armanim.output.rundir import refuse_in_run_folder

    refuse_in_run_folder(out_root, "--out", itself=True)  # a run folder inside another would stop that one's next run
    from armanim.runs.options import RunOptions

    options = RunOptions(
        video=not no_video,
        viewer=viewer,
        jobs=usable_jobs(jobs),
        render=render_overrides(size, fps, fmt, quality=quality),
    )
    if not quiet:
        tell_first_compile("run")
    if len(scenes) == 1 and not scheduler:
        run_one(scenes[0], out_root, options, quiet=quiet, strict=strict)
        return
    from armanim.cli.progress import bars
    from armanim.runs.batch import run_batch

    if not quiet:
        say(f"batch: {len(dict.fromkeys(scenes))} scenes", err)
    with bars(quiet) as shown:
        entries = run_batch(scenes, out_root, options, scheduler=scheduler, progress=functools.partial(shown, "scenes"))
    ignore_until_exit()  # every scene and index.csv are in place: the batch has its outcome
    if not quiet:
        print_batch_table(entries, out_root / "index.csv")
    print_batch_problems(entries)
    raise typer.Exit(batch_exit_code(entries, strict))


def run_one(path: Path, out_root: Path, options: RunOptions, *, quiet: bool, strict: bool) -> None:
    """One scene in this process, its video rendered by ``options.jobs`` workers (at a first run, a
    second process compiles meanwhile what the run calls after its solve: :mod:`armanim.runs.beside`)."""
    from armanim.cli.progress import bars
    from armanim.runs.beside import compiling_beside
    from armanim.runs.pipeline import run_scene

    with (
        committed_is_done(),
        compiling_beside(path, options.video, options.jobs or usable_cores()),
        bars(quiet) as shown,
    ):
        result = run_scene(path, out_root, options, progress=shown)
    ignore_until_exit()  # the outputs are in place: the run has succeeded, whatever comes now
    print_notes(result.scene)  # warnings (the picture or the collision model is not what was asked): also with --quiet
    for note in result.notes:
        say(message_lines("note: " + note), err)
    if not quiet:
        print_goal_table(result)
    if strict and result.solution.reached < len(result.solution.goals):
        print_missed_goals(result, path)
        raise typer.Exit(EXIT_CHECK_FAILED)


@contextlib.contextmanager
def committed_is_done():
    """A command whose one output folder was swapped in as Ctrl-C or SIGTERM came has succeeded: exit 0, saying so.

    Never "interrupted" about outputs that are in place.
    """
    try:
        yield
    except InterruptedAfterCommit as done:
        ignore_until_exit()
        say(f"armanim: the outputs were written to {done.folder} just as the interrupt came", err)
        raise typer.Exit(0) from None


@app.command()
@handle_errors
def render(
    folder: Annotated[
        Path, typer.Argument(help="An output folder of armanim run, e.g. outputs/notes-arm.", show_default=False)
    ],
    size: Annotated[str | None, typer.Option("--size", help="Frame size WIDTHxHEIGHT, e.g. 640x360.")] = None,
    fps: Annotated[float | None, typer.Option("--fps", help="Frames per second.")] = None,
    fmt: Annotated[str | None, typer.Option("--format", help="mp4 or gif.")] = None,
    elevation: Annotated[float | None, typer.Option("--elevation", help="Camera elevation, degrees.")] = None,
    azimuth: Annotated[float | None, typer.Option("--azimuth", help="Camera azimuth, degrees.")] = None,
    jobs: JobsOpt = None,
    quiet: Annotated[bool, typer.Option("--quiet", "-q", help="No progress bar.")] = False,
    quality: QualityOpt = None,
    out_dir: Annotated[
        Path | None,
        typer.Option(
            "--out", help="Write the video, plot.png and poster.png to this folder instead of replacing the run's."
        ),
    ] = None,
) -> None:
    """Re-render a finished run from its trajectory.csv, without solving (other size, view, fps or format).

    Example: [bold]armanim render outputs/notes-arm --size 640x360 --format gif[/bold]
    """
    from armanim.cli.progress import bars
    from armanim.runs.pipeline import rerender_run

    overrides = render_overrides(size, fps, fmt, elevation, azimuth, quality)
    jobs = usable_jobs(jobs)
    notes: list[str] = []
    with committed_is_done(), bars(quiet) as shown:
        files = rerender_run(
            folder, out=out_dir, jobs=jobs, render_overrides=overrides, progress=shown, notes=notes.append
        )
    ignore_until_exit()
    for note in notes:  # a picture that is not what the run drew (its meshes not found): also with --quiet
        say(message_lines("note: " + note), err)
    if not quiet:
        say("wrote " + ", ".join(str(p) for p in files.values()))
