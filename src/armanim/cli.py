"""The ``armanim`` command: thin Typer commands over the importable API.

Every ArmanimError becomes its message on stderr and the contract's exit code; rich
lives only here.
"""

from __future__ import annotations

import functools
import json
import sys
from dataclasses import replace
from pathlib import Path
from typing import Annotated

import numpy as np
import typer
from rich.console import Console
from rich.table import Table

from armanim import __version__
from armanim.errors import (
    EXIT_BAD_INPUT,
    EXIT_CHECK_FAILED,
    EXIT_INTERRUPTED,
    EXIT_OUTPUT_FAILED,
    ArmanimError,
    UsageError,
)

app = typer.Typer(
    name="armanim",
    help="Batch animator for articulated arms: inverse kinematics with cost minimisation, "
    "trajectories, videos.\n\nExample: [bold]armanim run scenes/notes-arm.yaml[/bold]",
    rich_markup_mode="rich",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_show_locals=False,
    context_settings={"help_option_names": ["-h", "--help"]},
)
out = Console()
err = Console(stderr=True)


def _report(exc: ArmanimError) -> None:
    err.print(exc.report(), markup=False, highlight=False, soft_wrap=True)


def handle_errors(command):
    """Turn ArmanimError into its message and exit code; Ctrl-C into exit 130."""

    @functools.wraps(command)
    def wrapper(*args, **kwargs):
        try:
            return command(*args, **kwargs)
        except ArmanimError as exc:
            _report(exc)
            raise typer.Exit(exc.exit_code) from None
        except KeyboardInterrupt:
            err.print("armanim: interrupted; nothing half-written was left behind", markup=False)
            raise typer.Exit(EXIT_INTERRUPTED) from None
        except OSError as exc:  # a safety net: writers raise OutputError, but the system may fail elsewhere
            err.print(f"armanim: {exc.filename or 'output'}: {exc.strerror or exc}", markup=False, highlight=False, soft_wrap=True)
            raise typer.Exit(EXIT_OUTPUT_FAILED) from None

    return wrapper


def _version(value: bool) -> None:
    if value:
        out.print(f"armanim {__version__}", highlight=False)
        raise typer.Exit()


@app.callback()
def _main(
    version: Annotated[
        bool, typer.Option("--version", callback=_version, is_eager=True, help="Show the version and exit.")
    ] = False,
) -> None:
    """Batch animator for articulated arms."""


# ---------------------------------------------------------------- parsing helpers


def parse_numbers(text: str, flag: str, count: int | None = None) -> np.ndarray:
    """``"0,30,45"`` -> array; a clear UsageError for anything else."""
    parts = [p.strip() for p in text.replace(" ", ",").split(",") if p.strip()]
    try:
        values = np.array([float(p) for p in parts])
    except ValueError:
        bad = next(p for p in parts if not _is_number(p))
        raise UsageError(f"{flag}: {bad!r} is not a number (expected comma-separated numbers, e.g. {flag} 0,30,45)") from None
    if not len(values) or not np.all(np.isfinite(values)):
        raise UsageError(f"{flag}: expected finite comma-separated numbers (got {text!r})")
    if count is not None and len(values) != count:
        raise UsageError(f"{flag}: expected {count} numbers (got {len(values)}: {text!r})")
    return values


def parse_lengths(text: str, flag: str, count: int | None = None) -> np.ndarray:
    """:func:`parse_numbers` for positions and lengths, held to the scene's size limit
    (beyond it, squares of distances overflow)."""
    from armanim.scene.models import LIMITS

    values = parse_numbers(text, flag, count)
    limit = LIMITS["magnitude"]
    if np.any(np.abs(values) > limit):
        big = values[np.argmax(np.abs(values))]
        raise UsageError(f"{flag}: {big:g} is too large (expected at most {limit:g} in size: choose a smaller unit)")
    return values


def _is_number(text: str) -> bool:
    try:
        float(text)
        return True
    except ValueError:
        return False


def arm_problem(scene: Path | None, links: str | None, base: str | None, axes: str | None, direction: str | None):
    """The Problem for ``fk``/``ik``: from ``--scene`` or from the arm flags (not both).

    Returns the problem and the loaded scene (None when the arm came from flags).
    """
    if scene is not None:
        flags = [f for f, v in (("--links", links), ("--base", base), ("--axes", axes), ("--direction", direction)) if v]
        if flags:
            raise UsageError(f"{', '.join(flags)} cannot be combined with --scene (the scene defines the arm)")
        from armanim.scene import load_scene, scene_to_problem

        loaded = load_scene(scene)
        return scene_to_problem(loaded.model), loaded
    from armanim.scene.models import LIMITS

    lengths = parse_lengths(links, "--links") if links else np.ones(4)
    if np.any(lengths <= 0):
        raise UsageError(f"--links: every length must be > 0 (got {links!r})")
    if len(lengths) > LIMITS["links"]:
        raise UsageError(f"--links: {len(lengths)} links (expected at most {LIMITS['links']})")
    n = len(lengths)
    names = [a.strip().lower() for a in axes.split(",")] if axes else None
    if names is not None and (len(names) != n or any(a not in ("x", "y", "z") for a in names)):
        raise UsageError(f"--axes: expected {n} of x, y, z separated by commas, one per link (got {axes!r})")
    dir_name = (direction or "z").lower()
    if dir_name not in ("x", "y", "z"):
        raise UsageError(f"--direction: expected x, y or z (got {direction!r})")
    arm = {"links": [float(v) for v in lengths], "direction": dir_name}
    if base:
        arm["base"] = [float(v) for v in parse_lengths(base, "--base", 3)]
    if names:
        arm["axes"] = names
    return flag_scene_problem(arm), None


def flag_scene_problem(arm: dict):
    """The problem of a scene made of the arm flags alone, through the scene model, so that
    every default (width, home, limits, solver) is the scene file's. Its goal is a placeholder."""
    from pydantic import ValidationError

    from armanim.scene import scene_to_problem
    from armanim.scene.models import SceneModel

    goal = [float(v) for v in np.asarray(arm.get("base", [0.0, 0.0, 0.0])) + 1.0]
    try:
        model = SceneModel.model_validate({"version": 1, "arm": arm, "goals": [goal]})
    except ValidationError as exc:
        first = exc.errors()[0]
        raise UsageError(f"--{first['loc'][1]}: {first['msg']}") from None
    return scene_to_problem(model)


SceneOpt = Annotated[Path | None, typer.Option("--scene", help="Take the arm (and its limits) from a scene file.")]
LinksOpt = Annotated[str | None, typer.Option("--links", help="Link lengths, e.g. 2,5,5,5 (default: four unit links).")]
BaseOpt = Annotated[str | None, typer.Option("--base", help="Base position x,y,z (default 0,0,0).")]
AxesOpt = Annotated[str | None, typer.Option("--axes", help="Joint axes, e.g. z,y,y,y (default: z, then y).")]
DirOpt = Annotated[str | None, typer.Option("--direction", help="Local axis the links extend along: x, y or z (default z).")]


def usable_jobs(jobs: int | None) -> int | None:
    """``--jobs``, at most the cores this process may use (more only add processes and
    memory); a note on stderr says so when it is lowered."""
    import os

    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
    if jobs is not None and jobs > cores:
        err.print(f"note: --jobs {jobs} is more than the {cores} cores here; using {cores}", markup=False, highlight=False, soft_wrap=True)
        return cores
    return jobs


def _fmt(v: float) -> str:
    return f"{v:.6g}"


# ---------------------------------------------------------------- fk


@app.command()
@handle_errors
def fk(
    angles: Annotated[str, typer.Option("--angles", help="Joint angles, comma-separated (degrees unless --radians). Negative first value: --angles=-30,10.")],
    scene: SceneOpt = None,
    links: LinksOpt = None,
    base: BaseOpt = None,
    axes: AxesOpt = None,
    direction: DirOpt = None,
    radians: Annotated[bool, typer.Option("--radians", help="Angles are in radians.")] = False,
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON: angles_deg, joints (base to tip), tip.")] = False,
    png: Annotated[Path | None, typer.Option("--png", help="Also draw the pose to this PNG file.")] = None,
) -> None:
    """Forward kinematics of one pose: joint positions and the tip.

    Example: [bold]armanim fk --angles 0,30,45,10 --links 2,5,5,5 --base 5,5,0[/bold]
    """
    from armanim.kinematics import forward

    problem, loaded = arm_problem(scene, links, base, axes, direction)
    values = parse_numbers(angles, "--angles", problem.arm.n)
    phi = values if radians else np.radians(values)
    pose = forward(problem.arm, phi)
    if as_json:
        angles_deg = np.degrees(values) if radians else values  # as typed, not round-tripped through radians
        data = {"angles_deg": angles_deg.tolist(), "joints": pose.points.tolist(), "tip": pose.tip.tolist()}
        print(json.dumps(data))
    else:
        table = Table(title="Forward kinematics", title_justify="left")
        for col in ("point", "angle (deg)", "x", "y", "z"):
            table.add_column(col, justify="right" if col != "point" else "left")
        for i, p in enumerate(pose.points):
            label = f"joint {i + 1}" if i < problem.arm.n else "tip"
            angle = _fmt(np.degrees(phi[i])) if i < problem.arm.n else ""
            table.add_row(label, angle, *(_fmt(v) for v in p))
        out.print(table)
    for note in limit_notes(problem, phi) if loaded else []:
        err.print(f"note: {note}", markup=False, highlight=False, soft_wrap=True)
    if png is not None:
        from armanim.problem import RenderSettings
        from armanim.render.draw import render_pose_png
        from armanim.scene import render_settings

        settings = render_settings(loaded.model) if loaded else RenderSettings()
        render_pose_png(problem, phi, settings, png, title="armanim fk")
        if not as_json:
            out.print(f"wrote {png}", highlight=False)


def limit_notes(problem, phi) -> list[str]:
    """One line per joint outside the scene's limits."""
    lim = problem.limits
    notes = []
    for i in np.nonzero(lim.limited & ((phi < lim.lower) | (phi > lim.upper)))[0]:
        notes.append(
            f"joint {i + 1} at {np.degrees(phi[i]):.6g} deg is outside its limits "
            f"[{np.degrees(lim.lower[i]):g}, {np.degrees(lim.upper[i]):g}]"
        )
    return notes


# ---------------------------------------------------------------- ik


@app.command()
@handle_errors
def ik(
    goal: Annotated[str, typer.Option("--goal", help="Goal position x,y,z. Negative first value: --goal=-3,1,0.")],
    scene: SceneOpt = None,
    links: LinksOpt = None,
    base: BaseOpt = None,
    axes: AxesOpt = None,
    direction: DirOpt = None,
    method: Annotated[str | None, typer.Option("--method", help="pinv, dls, newton or gradient (default: the scene's, else pinv).")] = None,
    start: Annotated[str | None, typer.Option("--from", help="Starting angles in degrees (default: the scene's home, else all 0).")] = None,
    tolerance: Annotated[float | None, typer.Option("--tolerance", help="Stop when |e - g| < tolerance (default: the scene's, else 0.001).")] = None,
    max_iterations: Annotated[int, typer.Option("--max-iterations", min=1, help="Give up after this many steps.")] = 2000,
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON.")] = False,
) -> None:
    """Solve one pose to convergence: angles, tip, error and iteration counts.

    Example: [bold]armanim ik --goal 3,1,0 --links 1,1,1,1 --axes z,z,z,z --direction x --method newton[/bold]
    """
    from armanim.ik import solve_pose
    from armanim.solvers import METHODS

    problem, loaded = arm_problem(scene, links, base, axes, direction)
    target = parse_lengths(goal, "--goal", 3)
    settings = problem.solver
    if method is not None:
        if method not in METHODS:
            raise UsageError(f"--method: {method!r} is not a method (expected one of {', '.join(METHODS)})")
        settings = replace(settings, method=method)
    if tolerance is not None:
        if not tolerance > 0:
            raise UsageError(f"--tolerance: must be > 0 (got {tolerance})")
        settings = replace(settings, tolerance=tolerance)
    elif not loaded:
        settings = replace(settings, tolerance=1e-3)
    problem = replace(problem, solver=settings)
    phi0 = np.radians(parse_numbers(start, "--from", problem.arm.n)) if start else problem.home
    result = solve_pose(problem, target, phi0, max_iterations)
    data = {
        "method": settings.method,
        "converged": result.converged,
        "angles_deg": np.degrees(result.phi).tolist(),
        "tip": result.tip.tolist(),
        "error": result.distance,
        "iterations": result.iterations,
    }
    reason = unreached_reason(problem, target, result.converged)
    if reason:
        data["reason"] = reason
    if settings.method == "newton":
        data["gd_iterations"] = data.pop("iterations")
        data["newton_iterations"] = result.newton_iterations
    if as_json:
        print(json.dumps(data))
        return
    status = "[green]converged[/green]" if result.converged else "[red]not converged[/red]"
    out.print(f"{settings.method}: {status}, error {result.distance:.3g} (tolerance {settings.tolerance:g})")
    if "reason" in data:
        out.print(f"why: {data['reason']}", highlight=False)
    out.print("angles (deg): " + ", ".join(_fmt(v) for v in data["angles_deg"]), highlight=False)
    out.print("tip: " + ", ".join(_fmt(v) for v in result.tip), highlight=False)
    if settings.method == "newton":
        out.print(f"iterations: gradient descent {result.iterations}, Newton {result.newton_iterations}", highlight=False)
    else:
        out.print(f"iterations: {result.iterations}", highlight=False)


# ---------------------------------------------------------------- validate, schema


@app.command()
@handle_errors
def validate(
    scenes: Annotated[list[Path], typer.Argument(help="Scene files to check.", show_default=False)],
) -> None:
    """Check scene files: [green]ok[/green] or every problem, as FILE:LINE: field: message.

    Example: [bold]armanim validate scenes/*.yaml[/bold]
    """
    from armanim.errors import SceneError
    from armanim.scene import load_scene

    failed = 0
    for path in scenes:
        try:
            scene = load_scene(path)
        except SceneError as exc:
            failed += 1
            _report(exc)
            continue
        m = scene.model
        counts = ", ".join(plural(k, word) for k, word in ((len(m.arm.links), "link"), (len(m.goals), "goal"), (len(m.obstacles), "obstacle")))
        out.print(f"ok {path} ({scene.name}: {counts}, method {m.solver.method})", highlight=False, soft_wrap=True)
        print_notes(scene)
    if failed:
        raise typer.Exit(EXIT_BAD_INPUT)


@app.command()
@handle_errors
def schema(
    output: Annotated[Path | None, typer.Option("--out", help="Write the schema to this file instead of stdout.")] = None,
) -> None:
    """Print the scene file's JSON Schema, for editors to complete and check scenes.

    Example: [bold]armanim schema --out scene.schema.json[/bold], then start a scene with [bold]# yaml-language-server: $schema=scene.schema.json[/bold]
    """
    from armanim.output.atomic import write_text_atomic
    from armanim.scene.models import SceneModel

    text = json.dumps(SceneModel.model_json_schema(), indent=2) + "\n"
    if output is None:
        sys.stdout.write(text)
    else:
        write_text_atomic(output, text)


# ---------------------------------------------------------------- run


def parse_size(text: str) -> list[int]:
    """``"640x360"`` -> [640, 360] (its range is the scene's ``render.size``, checked later)."""
    try:
        return [int(v) for v in text.lower().split("x", 1)]
    except ValueError:
        raise UsageError(f"--size: expected WIDTHxHEIGHT, e.g. 640x360 (got {text!r})") from None


_FLAGS = {("fps",): "--fps", ("size",): "--size", ("format",): "--format",
          ("view", "elevation"): "--elevation", ("view", "azimuth"): "--azimuth"}


QUALITY = {"low": ("854x480", 15.0), "medium": ("1280x720", 30.0), "high": ("1920x1080", 60.0),
           "4k": ("3840x2160", 60.0)}  # --quality: size and fps, as manim's presets
QualityOpt = Annotated[str | None, typer.Option(
    "--quality", help="low (854x480@15), medium (1280x720@30), high (1920x1080@60) or 4k (3840x2160@60): "
    "overrides the scene's render size and fps (--size and --fps override it in turn).")]


def render_overrides(
    size: str | None, fps: float | None, fmt: str | None, elevation: float | None = None, azimuth: float | None = None,
    quality: str | None = None,
) -> dict:
    """RenderSettings fields given on the command line, checked by the scene's own
    ``render`` model, so a flag accepts exactly what the scene file accepts.
    ``quality`` names a preset of :data:`QUALITY`; ``size`` and ``fps`` win over it."""
    if quality is not None:
        if quality.lower() not in QUALITY:
            raise UsageError(f"--quality: expected one of {', '.join(QUALITY)} (got {quality!r})")
        preset_size, preset_fps = QUALITY[quality.lower()]
        size, fps = size or preset_size, fps or preset_fps
    from pydantic import ValidationError

    from armanim.scene.loader import problem_message
    from armanim.scene.models import RenderModel

    given = {"fps": fps, "size": parse_size(size) if size else None, "format": fmt}
    view = {k: v for k, v in (("elevation", elevation), ("azimuth", azimuth)) if v is not None}
    data = {k: v for k, v in given.items() if v is not None} | ({"view": view} if view else {})
    try:
        model = RenderModel.model_validate(data)
    except ValidationError as exc:
        err = exc.errors()[0]
        loc = tuple(part for part in err["loc"] if isinstance(part, str))
        flag = _FLAGS.get(loc, f"--{loc[0]}")
        raise UsageError(f"{flag}: {problem_message(err, tuple(err['loc']))}") from None
    overrides = {k: getattr(model, k) for k in ("fps", "format") if k in data}
    if "size" in data:
        overrides["size"] = tuple(model.size)
    overrides.update({k: getattr(model.view, k) for k in view})
    return overrides


class _Bars:
    """A rich progress bar per stage, with frames per second and ETA."""

    def __init__(self, enabled: bool, console: Console | None = None):
        self.enabled = enabled
        self.console = console or err
        self.progress = None
        self.tasks: dict[str, int] = {}

    def __enter__(self):
        if self.enabled:
            from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeRemainingColumn

            self.progress = Progress(
                TextColumn("{task.description}"),
                BarColumn(),
                MofNCompleteColumn(),
                _RateColumn(),
                TimeRemainingColumn(),
                console=self.console,
                transient=True,
            )
            self.progress.__enter__()
        return self

    def __exit__(self, *exc):
        if self.progress is not None:
            self.progress.__exit__(*exc)

    def __call__(self, stage: str, done: int, total: int, running: tuple[str, ...] = ()) -> None:
        if self.progress is None:
            return
        if stage not in self.tasks:
            self.tasks[stage] = self.progress.add_task(f"{stage:>6}", total=total)
        label = f"{stage:>6} " + ", ".join(running) if running else f"{stage:>6}"
        self.progress.update(self.tasks[stage], completed=done, total=max(total, done), description=label)


def _RateColumn():
    """Items per second of a progress task ("--" until rich has measured a speed)."""
    from rich.progress import ProgressColumn
    from rich.text import Text

    class RateColumn(ProgressColumn):
        def render(self, task) -> Text:
            speed = task.finished_speed or task.speed
            return Text(f"{speed:7.1f}/s" if speed else "     --/s", style="progress.data.speed")

    return RateColumn()


SchedulerOpt = Annotated[
    str | None,
    typer.Option("--scheduler", envvar="ARMANIM_SCHEDULER", help="Run on Dask: tcp://HOST:8786, or 'local' for a LocalCluster (needs pip install -e '.\\[dask]').", show_envvar=True),
]


@app.command()
@handle_errors
def run(
    scenes: Annotated[list[Path], typer.Argument(help="Scene files to run.", show_default=False)],
    out_root: Annotated[Path, typer.Option("--out", help="Outputs go to OUT/<scene name>/.")] = Path("outputs"),
    no_video: Annotated[bool, typer.Option("--no-video", help="Write trajectory.csv and summary.json only.")] = False,
    quiet: Annotated[bool, typer.Option("--quiet", "-q", help="No progress bars and no tables.")] = False,
    jobs: Annotated[int | None, typer.Option("--jobs", "-j", min=1, help="Worker processes (default: all cores): scenes in parallel for a batch, video segments for one scene.")] = None,
    scheduler: SchedulerOpt = None,
    size: Annotated[str | None, typer.Option("--size", help="Override render.size, e.g. 640x360.")] = None,
    fps: Annotated[float | None, typer.Option("--fps", help="Override render.fps.")] = None,
    fmt: Annotated[str | None, typer.Option("--format", help="Override render.format: mp4 or gif.")] = None,
    quality: QualityOpt = None,
    strict: Annotated[bool, typer.Option("--strict", help="Exit 1 if any goal is missed.")] = False,
) -> None:
    """Animate scenes: solve every goal and write OUT/<name>/ with the outputs.

    The outputs: trajectory.csv, summary.json, the video, plot.png and poster.png. Several scenes run in parallel and also write OUT/index.csv; a bad scene is reported and the others finish (exit 2 if any scene was invalid, 3 if any failed while writing).

    Examples:

    [bold]armanim run scenes/notes-arm.yaml[/bold]

    [bold]armanim run scenes/*.yaml --jobs 2 --no-video[/bold]
    """
    overrides = render_overrides(size, fps, fmt, quality=quality)
    jobs = usable_jobs(jobs)
    if len(scenes) == 1 and not scheduler:
        from armanim.pipeline import run_scene

        with _Bars(enabled=not quiet and err.is_terminal) as bars:
            result = run_scene(scenes[0], out_root, video=not no_video, jobs=jobs, render_overrides=overrides, progress=bars)
        if not quiet:
            print_notes(result.scene)
            print_goal_table(result)
        if strict and result.solution.reached < len(result.solution.goals):
            for goal in result.solution.goals:
                if not goal.reached:
                    err.print(f"--strict: {scenes[0]}: goal {goal.index} missed ({goal.reason})", highlight=False, soft_wrap=True)
            raise typer.Exit(EXIT_CHECK_FAILED)
        return
    from armanim.batch import run_batch

    with _Bars(enabled=not quiet and err.is_terminal) as bars:
        entries = run_batch(
            scenes, out_root, jobs=jobs, scheduler=scheduler, video=not no_video, render_overrides=overrides,
            progress=functools.partial(bars, "scenes"),
        )
    if not quiet:
        print_batch_table(entries, out_root / "index.csv")
    print_batch_problems(entries)
    raise typer.Exit(batch_exit_code(entries, strict))


def batch_exit_code(entries, strict: bool) -> int:
    """3 if a scene failed while writing, 2 if one was invalid, 1 if --strict and a goal was missed, else 0."""
    statuses = {e.status for e in entries}
    if "failed" in statuses:
        return EXIT_OUTPUT_FAILED
    if "invalid" in statuses:
        return EXIT_BAD_INPUT
    if strict and any(e.missed for e in entries):
        return EXIT_CHECK_FAILED
    return 0


def print_batch_table(entries, index_path: Path) -> None:
    """One line per scene of a batch, then every problem in full."""
    table = Table(title=f"{len(entries)} scenes: {sum(e.status == 'ok' for e in entries)} ok", title_justify="left")
    for col in ("scene", "status", "reached", "missed", "frames", "min clear.", "folder"):
        table.add_column(col, justify="right" if col in ("reached", "missed", "frames", "min clear.") else "left", overflow="fold")
    for e in entries:
        style = {"ok": "green", "invalid": "red", "failed": "red"}[e.status]
        clearance = "" if e.min_clearance is None else f"{e.min_clearance:.3g}"
        table.add_row(e.name, f"[{style}]{e.status}[/{style}]", str(e.reached), str(e.missed), str(e.frames), clearance, e.folder)
    out.print(table)
    out.print(f"index: {index_path}", highlight=False)


def print_batch_problems(entries) -> None:
    """Every invalid or failed scene's report on stderr (also with --quiet: errors are not chatter)."""
    for e in entries:
        if e.message:
            err.print(e.message, markup=False, highlight=False, soft_wrap=True)


@app.command()
@handle_errors
def sweep(
    scene: Annotated[Path, typer.Argument(help="The scene to vary.", show_default=False)],
    settings: Annotated[list[str], typer.Option("--set", help="FIELD.PATH=V1,V2,... (repeatable); the product of all values is run.", show_default=False)],
    out_root: Annotated[Path, typer.Option("--out", help="Variants go to OUT/<variant name>/, the table to OUT/<scene>-sweep.csv.")] = Path("outputs"),
    video: Annotated[bool, typer.Option("--video/--no-video", help="Render each variant's video (off by default: sweeps compare numbers).")] = False,
    quiet: Annotated[bool, typer.Option("--quiet", "-q", help="No progress bar and no table.")] = False,
    jobs: Annotated[int | None, typer.Option("--jobs", "-j", min=1, help="Worker processes (default: all cores).")] = None,
    scheduler: SchedulerOpt = None,
) -> None:
    """Run a scene under every combination of settings and compare the results.

    Example: [bold]armanim sweep scenes/notes-arm.yaml --set solver.step=0.05,0.1,0.2 --set solver.method=pinv,dls[/bold]
    """
    from armanim.batch import index_csv_text, run_tasks
    from armanim.output.atomic import write_text_atomic
    from armanim.output.csvfile import table_csv_text
    from armanim.sweep import comparison_rows, parse_setting, variants

    jobs = usable_jobs(jobs)
    parsed = [parse_setting(text) for text in settings]
    items = variants(scene, parsed)
    tasks = [v.task for v in items if v.task is not None]
    with _Bars(enabled=not quiet and err.is_terminal) as bars:
        done = run_tasks(tasks, out_root, jobs=jobs, scheduler=scheduler, video=video, progress=functools.partial(bars, "variants"))
    by_name = {e.name: e for e in done}
    entries = [v.rejected if v.rejected is not None else by_name[v.name] for v in items]
    header, rows = comparison_rows(parsed, items, entries)
    table_path = out_root / f"{scene.stem}-sweep.csv"
    write_text_atomic(table_path, table_csv_text(header, rows))
    write_text_atomic(out_root / "index.csv", index_csv_text(entries))
    if not quiet:
        out.print(sweep_screen_table(f"sweep of {scene.name}: {len(items)} variants", header, rows, len(parsed)))
        out.print(f"table (every column, the variants' folder names): {table_path}", highlight=False)
    print_batch_problems(entries)
    raise typer.Exit(batch_exit_code(entries, strict=False))


SWEEP_SCREEN_COLUMNS = {"status": "status", "reached": "reached", "missed": "missed", "frames": "frames", "min_clearance": "min clear."}
"""Columns of the sweep CSV shown on screen, after the varied settings, with their short headers."""


def sweep_screen_table(title: str, header: list[str], rows: list, settings: int) -> Table:
    """The sweep's table for a terminal: the varied settings (named by their last part), then
    the outcome columns; cells fold instead of being cut. The CSV keeps every column.

    >>> sweep_screen_table("t", ["name", "solver.step", "status", "frames"], [["a", 0.1, "ok", 5]], 1).columns[0].header
    'step'
    """
    varied = header[1 : 1 + settings]
    short = [c.rsplit(".", 1)[-1] for c in varied]
    labels = [s if short.count(s) == 1 else c for s, c in zip(short, varied)]  # full path where two would look alike
    shown = [(header.index(c), label) for c, label in zip(varied, labels)]
    shown += [(header.index(c), label) for c, label in SWEEP_SCREEN_COLUMNS.items() if c in header]
    table = Table(title=title, title_justify="left")
    for _, label in shown:
        table.add_column(label, overflow="fold")
    for row in rows:
        table.add_row(*(str(row[i]) for i, _ in shown))
    return table


def print_goal_table(result) -> None:
    """The per-goal table printed at the end of a run."""
    from armanim.trajectory import MISS_REASONS

    sol = result.solution
    table = Table(title=f"{result.scene.name}: {sol.reached} of {len(sol.goals)} goals reached, {sol.trajectory.frames} frames", title_justify="left")
    for col in ("goal", "position", "result", "frames", "distance"):
        table.add_column(col, justify="right" if col in ("goal", "frames", "distance") else "left")
    for g in sol.goals:
        outcome = "[green]reached[/green]" if g.reached else f"[red]missed[/red]: {MISS_REASONS[g.reason]}"
        table.add_row(str(g.index), ", ".join(f"{v:g}" for v in g.position), outcome, str(g.frames), f"{g.final_distance:.3g}")
    out.print(table)
    out.print("outputs: " + ", ".join(str(p) for p in result.files.values()), highlight=False, soft_wrap=True)


@app.command()
@handle_errors
def render(
    folder: Annotated[Path, typer.Argument(help="An output folder of armanim run, e.g. outputs/notes-arm.", show_default=False)],
    size: Annotated[str | None, typer.Option("--size", help="Frame size WIDTHxHEIGHT, e.g. 640x360.")] = None,
    fps: Annotated[float | None, typer.Option("--fps", help="Frames per second.")] = None,
    fmt: Annotated[str | None, typer.Option("--format", help="mp4 or gif.")] = None,
    elevation: Annotated[float | None, typer.Option("--elevation", help="Camera elevation, degrees.")] = None,
    azimuth: Annotated[float | None, typer.Option("--azimuth", help="Camera azimuth, degrees.")] = None,
    jobs: Annotated[int | None, typer.Option("--jobs", "-j", min=1, help="Worker processes (default: all cores).")] = None,
    quiet: Annotated[bool, typer.Option("--quiet", "-q", help="No progress bar.")] = False,
    quality: QualityOpt = None,
    out_dir: Annotated[Path | None, typer.Option("--out", help="Write the video, plot.png and poster.png to this folder instead of replacing the run's.")] = None,
) -> None:
    """Re-render a finished run from its trajectory.csv, without solving (other size, view, fps or format).

    Example: [bold]armanim render outputs/notes-arm --size 640x360 --format gif[/bold]
    """
    from armanim.pipeline import rerender_run

    overrides = render_overrides(size, fps, fmt, elevation, azimuth, quality)
    jobs = usable_jobs(jobs)
    with _Bars(enabled=not quiet and err.is_terminal) as bars:
        files = rerender_run(folder, out=out_dir, jobs=jobs, render_overrides=overrides, progress=bars)
    if not quiet:
        out.print("wrote " + ", ".join(str(p) for p in files.values()), highlight=False)


# ---------------------------------------------------------------- golden trajectories


AtolDeg = Annotated[float, typer.Option("--atol-deg", min=0, help="Tolerance on joint angles, degrees.")]
Atol = Annotated[float, typer.Option("--atol", min=0, help="Tolerance on positions, distances, clearances (scene units).")]


@app.command()
@handle_errors
def compare(
    expected: Annotated[Path, typer.Argument(help="The expected trajectory.csv (e.g. a golden file).", show_default=False)],
    actual: Annotated[Path, typer.Argument(help="The trajectory.csv to check.", show_default=False)],
    atol_deg: AtolDeg = 1e-6,
    atol: Atol = 1e-6,
) -> None:
    """Compare two trajectories: exit 0 if they agree, 1 if they differ, 2 on bad input.

    Example: [bold]armanim compare tests/golden/notes-arm.csv outputs/notes-arm/trajectory.csv[/bold]
    """
    from armanim.output.compare import compare_csv_files

    result = compare_csv_files(expected, actual, atol_deg=atol_deg, atol=atol)
    out.print(result.report, markup=False, highlight=False, soft_wrap=True)
    if not result.equal:
        raise typer.Exit(EXIT_CHECK_FAILED)


@app.command()
@handle_errors
def check(
    scenes: Annotated[list[Path], typer.Argument(help="Scene files to run and check.", show_default=False)],
    golden: Annotated[Path, typer.Option("--golden", help="Folder of golden files <name>.csv (+ <name>.json).")],
    update: Annotated[bool, typer.Option("--update", help="(Re)write the golden files instead of checking.")] = False,
    atol_deg: AtolDeg = 1e-6,
    atol: Atol = 1e-6,
    quiet: Annotated[bool, typer.Option("--quiet", "-q", help="No table: only the report of each difference.")] = False,
) -> None:
    """Run scenes without video and compare each with its golden trajectory; exit 1 on any difference.

    Example: [bold]armanim check scenes/*.yaml --golden tests/golden[/bold]

    After a deliberate change: [bold]armanim check scenes/*.yaml --golden tests/golden --update[/bold]
    """
    from armanim.golden import check_scene, update_golden

    if golden.exists() and not golden.is_dir():
        raise UsageError(f"--golden: {golden} is a file (expected a folder of golden files <name>.csv and <name>.json)")
    table = Table(title=f"golden trajectories in {golden}", title_justify="left")
    for col in ("scene", "golden file", "result"):
        table.add_column(col)
    failed = False
    reports = []
    for path in scenes:
        if update:
            result = update_golden(path, golden)
            style = {"new": "cyan", "changed": "yellow", "unchanged": "green"}[result.status]
        else:
            result = check_scene(path, golden, atol_deg=atol_deg, atol=atol)
            style = "green" if result.status == "pass" else "red"
            if result.status != "pass":
                failed = True
                reports.append(f"{result.scene.name}: {result.report}")
        table.add_row(result.scene.name, str(result.golden), f"[{style}]{result.status}[/{style}]")
    if not quiet:
        out.print(table)
    for report in reports:
        out.print(report, markup=False, highlight=False, soft_wrap=True)
    if failed:
        raise typer.Exit(EXIT_CHECK_FAILED)


def unreached_reason(problem, target: np.ndarray, converged: bool) -> str | None:
    """Why ``armanim ik`` did not converge, when it can be told: the goal out of reach."""
    from armanim.trajectory import beyond_reach

    if converged:
        return None
    away = float(np.linalg.norm(target - problem.arm.base))
    if beyond_reach(problem, target):
        return f"out of reach: the goal is {away:.4g} from the base, the arm is {problem.arm.reach:.4g} long (the tip is as close as it gets)"
    return "no pose found within the iterations (a local minimum, a limit or an obstacle in the way: try --from other angles)"


def print_notes(scene) -> None:
    """A scene's notes (not errors) on stderr, as ``note: FILE:LINE: field: message``."""
    for note in scene.notes:
        err.print("note: " + note.format(str(scene.path)), markup=False, highlight=False, soft_wrap=True)


def plural(count: int, word: str) -> str:
    """``1 obstacle``, ``3 obstacles``.

    >>> plural(1, "goal"), plural(0, "obstacle")
    ('1 goal', '0 obstacles')
    """
    return f"{count} {word}" + ("" if count == 1 else "s")


def _terminate(signum, frame):
    raise KeyboardInterrupt  # SIGTERM takes the same clean-up path as Ctrl-C


def main() -> None:
    """Entry point of the ``armanim`` console script."""
    import signal

    signal.signal(signal.SIGTERM, _terminate)
    app()


if __name__ == "__main__":
    main()
