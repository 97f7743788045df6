"""Run a scene end to end: load, solve, write trajectory.csv and summary.json, render.

A silent, importable API: progress is a callback, nothing is printed here.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path

from armanim.arm.visuals import LinkPlaces
from armanim.errors import OutputError, UsageError
from armanim.motion.carry import touch_allowed
from armanim.motion.problem import Problem
from armanim.motion.solution import Solution
from armanim.motion.timing.clock import ClockTooLong
from armanim.motion.timing.retime import at_fps, retime
from armanim.motion.trajectory import frame_budget, solve_trajectory
from armanim.output.atomic import write_bytes_atomic, write_text_atomic
from armanim.output.csvfile import write_trajectory_csv
from armanim.output.files import resolved
from armanim.output.jsontext import json_text, parse_json
from armanim.output.rundir import check_replaceable, folder_lock, refuse_in_run_folder, staged_folder
from armanim.output.selfcollision import SELF_COLLISION_FILE, write_self_collision
from armanim.output.solved import RunTiming, SolvedRun
from armanim.output.summary import run_summary, write_summary
from armanim.output.timing import TIMING_FILE, write_timing
from armanim.render.settings import OutputOptions, RenderOverrides, RenderSettings
from armanim.runs.options import RunOptions, output_choice
from armanim.runs.reload import ROBOT_COPY, SCENE_COPY, SRDF_COPY, FinishedRun
from armanim.runs.resample import resample_run, resampled_frames
from armanim.runs.stopwatch import Stopwatch, stopwatch
from armanim.scene import LoadedScene, load_scene
from armanim.scene.convert import convert_scene
from armanim.scene.limits import rate_note_lines
from armanim.scene.looks import scene_meshes
from armanim.scene.models import LIMITS
from armanim.scene.robots import CAPSULES_FILE, capsules_text

Progress = Callable[[str, int, int], None]
"""progress(stage, done, total): stage is "solve", "plan" (a plan's path search, in iterations,
counting from 0 again for each plan, between two solve frames), "path" (a path goal followed, in
thousandths of its path, counting from 0 again for each trial) or "render"."""


@dataclass(frozen=True)
class RunResult:
    """What a run produced.

    Attributes
    ----------
    scene : LoadedScene
    problem : Problem
    solution : Solution
    folder : Path
        The run's output folder.
    files : dict[str, Path]
        Written outputs by kind: ``scene``, ``robot`` (a copy of a user's URDF), ``trajectory``, ``summary``, ``timing``, ``viewer``, ``video``, ``plot``, ``poster``.
    summary : dict
    notes : tuple of str
        What the pictures could not show as asked (a robot mesh that could not be read).
    """

    scene: LoadedScene
    problem: Problem
    solution: Solution
    folder: Path
    files: dict[str, Path]
    summary: dict
    notes: tuple[str, ...] = ()
    timing: Stopwatch | None = None
    """How long the run took from reading the scene to its outputs in place, and numba's compiling in that."""


def run_scene(
    path: str | Path,
    out_root: str | Path = "outputs",
    options: RunOptions | None = None,
    *,
    progress: Progress | None = None,
) -> RunResult:
    """Solve a scene and write its outputs under ``out_root/<name>/``.

    The folder is replaced whole when every output is complete (see
    :mod:`armanim.output.rundir`); it also keeps a copy of the scene as ``scene.yaml``
    so that ``armanim render`` can redraw the run later.

    Parameters
    ----------
    path : scene file
    out_root : folder that receives one folder per scene
    options : the outputs asked and how they are drawn, e.g. ``RunOptions(video=False)`` or
        ``RunOptions(render=RenderOverrides(size=(320, 240)))`` (default: ``RunOptions()``, every output)
    progress : optional callback ``progress(stage, done, total)``

    Raises
    ------
    SceneError
        The scene is invalid (nothing is written).
    OutputError
        An output could not be written (the previous outputs stay as they were).
    """
    with stopwatch() as watch:  # from the scene file (and its URDF) to the outputs in place
        scene = load_scene(path)
        folder = Path(out_root) / scene.name
        with staged_folder(folder) as staged:
            produced = produce_outputs(scene, staged, options, progress=progress)
    files = {kind: folder / name for kind, name in produced.names.items()}
    return RunResult(
        scene, produced.run.problem, produced.run.solution, folder, files, produced.summary, produced.notes, watch
    )


@dataclass(frozen=True)
class Produced:
    """What :func:`produce_outputs` made: the solved run and its file names by kind."""

    run: SolvedRun
    summary: dict
    names: dict[str, str]
    notes: tuple[str, ...] = ()


def produce_outputs(
    scene: LoadedScene, folder: Path, asked: RunOptions | None = None, *, progress: Progress | None = None
) -> Produced:
    """Solve a validated scene and write every output into ``folder`` (which must exist), as
    ``asked`` (default: every output).

    The one place a run is produced: used by :func:`run_scene` (into its staged
    folder) and by batch workers (into a temporary folder whose files travel back).
    """
    fps, options = output_choice(scene, asked or RunOptions())
    run = solve_scene(scene, fps, progress)
    solved = time.perf_counter()
    notes: tuple[str, ...] = ()
    if options.video or options.viewer:
        run, notes = with_meshes(run, scene, options.render)
    names = {"scene": SCENE_COPY, "trajectory": "trajectory.csv", "summary": "summary.json"}
    names.update(write_sources(scene, folder))
    write_self_collision(
        run.problem.self_pairs
        if run.solution.carry is None
        else touch_allowed(run.problem.self_pairs, run.solution.carry),
        folder / SELF_COLLISION_FILE,
    )
    names["self_collision"] = SELF_COLLISION_FILE
    if (
        scene.model.arm.is_urdf
    ):  # the capsules solved with, in arm.collision's format (a user copies them into the scene)
        write_text_atomic(folder / CAPSULES_FILE, capsules_text(scene.model.arm.urdf_arm))
        names["capsules"] = CAPSULES_FILE
    write_trajectory_csv(run, folder / names["trajectory"])
    write_summary(run, folder / names["summary"])
    viewer_page: Callable[[], None] | None = None
    if options.viewer:
        from armanim.render.viewer import VIEWER_FILE, write_viewer

        def write_page() -> None:
            write_viewer(run, options, folder / VIEWER_FILE)

        viewer_page = write_page
        names["viewer"] = VIEWER_FILE
    if options.video:  # the page is written while the video's workers draw
        rendered = render_outputs(run, options, folder, progress=progress, also=viewer_page)
        names.update({kind: path.name for kind, path in rendered.items()})
    elif viewer_page is not None:
        viewer_page()
    if run.timing is not None:
        write_timing(run.timing, time.perf_counter() - solved, folder / TIMING_FILE)
        names["timing"] = TIMING_FILE
    return Produced(run, run_summary(run), names, notes)


MESH_TRIANGLES = 5_000
"""Triangles of a robot drawn in a 1280 x 720 frame (in proportion to a frame's pixels, at least
3,000): finer than a pixel's worth on screen is time spent for nothing (docs/rendering.md)."""


def with_meshes(run: SolvedRun, scene: LoadedScene, settings: RenderSettings) -> tuple[SolvedRun, tuple[str, ...]]:
    """``run`` with what its pictures draw as meshes with ``settings``: its robot's look (none for
    ``render.robot: capsules``), placed on ``run.problem.arm`` by ``run.places``, and the scene's
    furniture (:func:`armanim.scene.looks.scene_meshes`), and a note per visual mesh that could
    not be read (its link is drawn as its capsules)."""
    meshes, notes = look_meshes(scene.model, run.places, settings, *look_folders(scene))
    return replace(run, meshes=meshes), tuple(notes)


def look_meshes(
    model, places: LinkPlaces | None, settings: RenderSettings, scene_dir: Path, urdf_dir: Path | None = None
):
    """(meshes or None, notes): what a scene ``model``'s pictures draw as meshes at ``settings``'
    size (:func:`armanim.scene.looks.scene_meshes`), its links where ``places`` puts them on the
    problem's arm (:attr:`armanim.scene.convert.ConvertedScene.places`), its file names starting
    from ``scene_dir`` (and ``urdf_dir``, default the URDF's own folder)."""
    width, height = settings.size
    budget = max(3_000, round(MESH_TRIANGLES * width * height / (1280 * 720)))
    arm = model.arm
    dirs = [scene_dir / d for d in arm.package_dirs] if arm.package_dirs else None
    return scene_meshes(
        arm,
        places,
        dirs,
        triangles=budget,
        scene_dir=scene_dir,
        urdf_dir=urdf_dir,
        furniture=model.render.furniture,
        robot=settings.robot != "capsules",
    )


LOOK_FOLDERS_FILE = "look-folders.json"
"""A run folder's record of where its scene and its user's URDF were (absolute), written when the
look names files beside them (a URDF's meshes, a tool's mesh): ``render`` and ``view`` find the
meshes there again, not beside the run folder's copies."""
MAX_LOOK_FOLDERS_BYTES = 100_000


def needs_look_folders(scene: LoadedScene) -> bool:
    """Whether the scene's look names files relative to its own folders (a user's URDF, a tool mesh)."""
    arm = scene.model.arm
    return arm.urdf_source is not None or (arm.tool is not None and arm.tool.mesh is not None)


def look_folders_text(scene: LoadedScene) -> str:
    """The :data:`LOOK_FOLDERS_FILE` of a scene read from its own folder."""
    urdf = scene.model.arm.urdf_arm if scene.model.arm.is_urdf else None
    folder = urdf.folder if urdf is not None and urdf.bundled is None else None
    data = {
        "scene_folder": str(scene.path.parent.resolve()),
        "urdf_folder": str(Path(folder).resolve()) if folder is not None else None,
    }
    return json_text(data, indent=2) + "\n"


def look_folders(scene: LoadedScene) -> tuple[Path, Path | None]:
    """(scene folder, URDF folder or None: the URDF's own) the look's file names start from: the
    scene's own, or for a run folder's copies the originals' its :data:`LOOK_FOLDERS_FILE` records
    (when they are still folders)."""
    own = scene.path.parent
    record = own / LOOK_FOLDERS_FILE
    try:
        if not record.is_file():  # (a FIFO or a folder there is no record)
            return own, None
        with open(record, "rb") as f:
            raw = f.read(MAX_LOOK_FOLDERS_BYTES + 1)
        if len(raw) > MAX_LOOK_FOLDERS_BYTES:
            return own, None
        data = parse_json(raw.decode("utf-8"))
    except (OSError, ValueError, UnicodeDecodeError, RecursionError):
        return own, None
    if not isinstance(data, dict):
        return own, None
    folders = [
        Path(v) if isinstance(v, str) and Path(v).is_dir() else None
        for v in (data.get("scene_folder"), data.get("urdf_folder"))
    ]
    return folders[0] or own, folders[1]


def solve_scene(scene: LoadedScene, fps: float, progress: Progress | None = None) -> SolvedRun:
    """Solve a validated scene at its own rate and put it on the clock at ``fps``.

    Raises
    ------
    UsageError
        The run would make more than the total frame limit at ``fps`` (exit 2).
    """
    started = time.perf_counter()
    converted = convert_scene(scene.model)  # the motion is solved at the scene's own fps, its clock
    solved = converted.problem
    convert_s = time.perf_counter() - started
    frames = frame_budget(solved) * fps / solved.fps
    if frames > LIMITS["total_frames"]:  # a higher fps samples the same seconds with more frames
        if fps == solved.fps:  # validate refuses such a scene (scene/checks.py): a safety net
            raise UsageError(
                f"{scene.path}: the scene may run up to {int(frames):,} frames "
                f"(at most {LIMITS['total_frames']:,}; run armanim validate on it for the field to change)"
            )
        raise UsageError(
            f"--fps {fps:g}: the holds would make up to {int(frames):,} frames "
            f"(at most {LIMITS['total_frames']:,}; lower --fps or the scene's hold times)"
        )
    goals: list[float] = []
    started = time.perf_counter()
    solution = timed_solution(scene, solved, fps, progress, timer=lambda _, seconds: goals.append(seconds))
    solve_s = sum(goals)
    timing = RunTiming(convert_s, solve_s, time.perf_counter() - started - solve_s, tuple(goals))
    return replace(solved_run(scene, solved, solution, fps, converted.places), timing=timing)


def write_sources(scene: LoadedScene, folder: Path) -> dict[str, str]:
    """Copy the scene (and a user's URDF and SRDF) into ``folder``, so the run re-renders and
    reloads without the user's folder (render, view, a moved run); their names by kind."""
    write_bytes_atomic(folder / SCENE_COPY, scene.raw)
    names = {}
    if needs_look_folders(scene):
        write_text_atomic(folder / LOOK_FOLDERS_FILE, look_folders_text(scene))
        names["look_folders"] = LOOK_FOLDERS_FILE
    for kind, name, source in (
        ("robot", ROBOT_COPY, scene.model.arm.urdf_source),
        ("srdf", SRDF_COPY, scene.model.arm.srdf_source),
    ):
        if source is not None:
            write_bytes_atomic(folder / name, source)
            names[kind] = name
    return names


def solved_run(
    scene: LoadedScene, problem: Problem, solution: Solution, fps: float, places: LinkPlaces | None = None
) -> SolvedRun:
    """The one maker of a :class:`SolvedRun`: ``solution`` of ``problem`` (a fresh solve on the
    clock, or a finished run read back) as frames at ``fps``, with the problem at that rate
    (``places``: its URDF links' on the problem's arm, made with it, :func:`armanim.scene.convert.convert_scene`).

    A solution already at ``fps`` is kept as it is; another rate samples the same motion in
    the same seconds (:func:`armanim.runs.resample.resample_run`).
    """
    solution = resample_run(problem, solution, fps)
    return SolvedRun(
        scene.name,
        at_fps(problem, fps),
        solution,
        scene_file=scene.path.name,
        sha256=scene.sha256,
        rate_notes=tuple(rate_note_lines(scene.model)),
        places=places,
    )


def timed_solution(
    scene: LoadedScene,
    problem: Problem,
    fps: float,
    progress: Progress | None = None,
    timer: Callable[[int, float], None] | None = None,
) -> Solution:
    """The scene's path solved at ``problem.fps`` and put on the clock at ``fps`` (``timer``:
    :func:`~armanim.motion.trajectory.solve_trajectory`'s, told each goal's wall time).

    Raises
    ------
    UsageError
        The clock would make more than the total frame limit (joint limits far too low).
    """
    solution = solve_trajectory(
        problem,
        (lambda done, total: progress("solve", done, total)) if progress else None,
        (lambda done, most: progress("plan", done, most)) if progress else None,
        (lambda done, most: progress("path", done, most)) if progress else None,
        timer,
    )
    try:
        return retime(problem, solution, fps, most_frames=LIMITS["total_frames"])
    except ClockTooLong as exc:
        from armanim.errors import Diagnostic, SceneError
        from armanim.scene.loader import field_line

        arm = scene.model.arm
        fields = ["max_joint_speed", "max_joint_acceleration"] + (
            ["max_joint_jerk"] if arm.max_joint_jerk is not None else []
        )
        named = [f for f in fields if getattr(arm, f) is not None] or fields[
            :1
        ]  # the ones the scene sets, else speed's default
        field = f"arm.{named[0]}"
        also = f" (with {', '.join(f'arm.{f}' for f in named[1:])})" if len(named) > 1 else ""
        remedy = "raise the limits" + (", or lower --fps" if fps != problem.fps else "")
        raise SceneError(
            str(scene.path),
            [
                Diagnostic(
                    field, f"the clock would make {exc} at {fps:g} fps{also} ({remedy})", field_line(scene, field)
                )
            ],
        ) from None


def rerender_run(
    folder: str | Path,
    *,
    out: str | Path | None = None,
    jobs: int | None = None,
    render_overrides: RenderOverrides | None = None,
    progress: Progress | None = None,
    notes: Callable[[str], None] | None = None,
) -> dict[str, Path]:
    """Re-render a finished run from its folder (scene.yaml, trajectory.csv, summary.json)
    without solving: another size, view, fps or format.

    ``out``: write the video, plot.png and poster.png into this folder instead of replacing
    the run's own. It must be new, empty or one armanim marked (an earlier ``render --out``,
    whose other files are kept), and not inside the run folder.

    Returns the written files by kind (``video``, ``plot``, ``poster``). ``notes`` is called with
    each note of the look (a mesh that could not be read: its link is drawn as its capsules).

    The run folder is locked, staged and swapped as a run does, so a render never mixes
    with a run of the same folder, and a failed render leaves the folder as it was; with
    ``out``, the run is read under its lock and ``out`` is staged and swapped the same way.

    Raises
    ------
    SceneError
        The folder is not a complete armanim run (exit 2).
    OutputError
        The folder (or ``out``) was not made by armanim, or an output could not be written (exit 3).
    UsageError
        ``out`` is inside the run folder (exit 2).
    """
    from armanim.runs.reload import load_run

    folder = Path(folder)
    first = load_run(folder)  # says what is wrong with it (exit 2) before anything is locked, staged or refused
    asked = RunOptions(jobs=jobs, render=render_overrides or RenderOverrides())
    _check_resampled_frames(first.solution.trajectory, output_choice(first.scene, asked)[0])
    if out is not None and resolved(out) != resolved(folder):
        target = Path(out)
        if resolved(target).is_relative_to(resolved(folder)):
            raise UsageError(
                f"--out: {target} is inside the run folder {folder}, which the next run replaces "
                "whole (choose a folder outside it)"
            )
        refuse_in_run_folder(target, "--out", itself=True)  # another run's folder, or a folder inside one
        check_replaceable(target)  # a folder it may not replace: refused before any work (and again when staged)
        with folder_lock(folder):  # read the run whole, never half replaced by a run of it
            run = load_run(folder)
        # staged and swapped like a run folder: into a new, empty or armanim-marked folder only, its
        # other files kept; another fps samples the run's motion at its own times (the same seconds)
        solved, options = redrawn(run, asked, notes)
        with staged_folder(target, keep_files=True) as staged:
            rendered = render_outputs(solved, options, staged, progress=progress)
        return {kind: target / path.name for kind, path in rendered.items()}
    with staged_folder(folder, keep_files=True) as staged:  # the same lock and swap as a run
        run = load_run(folder)  # under the lock: no run is changing it
        solved, options = redrawn(run, asked, notes)
        rendered = render_outputs(solved, options, staged, progress=progress)
    return {kind: folder / path.name for kind, path in rendered.items()}


def redrawn(
    run: FinishedRun, asked: RunOptions, notes: Callable[[str], None] | None = None
) -> tuple[SolvedRun, OutputOptions]:
    """A finished run as a solved run at the command's fps, and the options to draw it again
    (``asked``: the command's render overrides and jobs); the look's notes go to ``notes``."""
    fps, options = output_choice(run.scene, asked)
    solved = solved_run(run.scene, run.problem, run.solution, fps, run.places)
    meshed, said = with_meshes(solved, run.scene, options.render)
    if notes is not None:
        for note in said:
            notes(note)
    return meshed, options


def _check_resampled_frames(trajectory, fps: float) -> None:
    """A UsageError (exit 2) when the run at ``fps`` would make more frames than a run may."""
    frames = resampled_frames(trajectory.frames, trajectory.fps, fps)
    if frames > LIMITS["total_frames"]:
        raise UsageError(
            f"--fps: the run's {trajectory.frames:,} frames at {trajectory.fps:g} fps are {frames:,} frames at "
            f"{fps:g} fps (expected at most {LIMITS['total_frames']:,}: choose a lower --fps or --quality)"
        )


def write_run_viewer(
    folder: str | Path, *, out: str | Path | None = None, notes: Callable[[str], None] | None = None
) -> Path:
    """(Re)write the viewer page of a finished run from its folder, without solving.

    Parameters
    ----------
    folder : an output folder of ``armanim run`` (scene.yaml, trajectory.csv, summary.json)
    out : write the page to this file instead of the run's own ``viewer.html``; an existing
        file is replaced only if it is a viewer page armanim wrote
    notes : called with each note of the look (a mesh that could not be read)

    Returns
    -------
    Path
        The page written (:func:`write_run_file`).
    """
    from armanim.render.viewer import VIEWER_FILE, write_viewer
    from armanim.render.viewer.page import replace_problem
    from armanim.runs.reload import load_run

    def page(folder: Path):
        run = load_run(folder)
        _, options = output_choice(run.scene, RunOptions())  # the scene's own settings, every output
        solved, said = with_meshes(
            solved_run(run.scene, run.problem, run.solution, run.solution.trajectory.fps, run.places),
            run.scene,
            options.render,
        )
        if notes is not None:
            for note in said:
                notes(note)
        return lambda path: write_viewer(solved, options, path)  # at its own rate

    return write_run_file(folder, VIEWER_FILE, out, page, replace_problem)


def write_run_file(
    folder: str | Path,
    name: str,
    out: str | Path | None,
    read: Callable[[Path], Callable[[Path], object]],
    replace_problem: Callable[[Path], str | None],
) -> Path:
    """Write a file made from a finished run, without solving: the run folder's own ``name``, or
    ``out`` outside the folder. ``read(folder)`` reads the run and returns ``write(path)``.

    Without ``out`` (or with the folder's own ``name``) the run folder is locked, staged and
    swapped as a run does, and its marker lists ``name``; with ``out`` the run is read under its
    lock and the file written atomically, replacing only what ``replace_problem(path)`` (the
    reason it must not be replaced, or None) allows.

    Raises
    ------
    SceneError
        The folder is not a complete armanim run (exit 2).
    UsageError
        ``out`` is inside the run folder but not its ``name`` (exit 2).
    OutputError
        The folder was not made by armanim, something ``replace_problem`` refuses stands at
        ``out``, or the file could not be written (exit 3).
    """
    from armanim.output.atomic import output_error
    from armanim.runs.reload import load_run

    folder = Path(folder)
    load_run(folder)  # says what is wrong with it (exit 2) before anything is locked or staged
    own = folder / name
    if out is None or resolved(out) == resolved(own):
        with staged_folder(folder, keep_files=True) as staged:  # the same lock and swap as a run
            read(folder)(staged / name)
        return own
    target = Path(out)
    if resolved(target).is_relative_to(resolved(folder)):
        raise UsageError(
            f"--out {target}: is inside the run folder {folder}, which holds only the files armanim lists "
            f"in it (leave --out out to write {own}, or choose a file outside the folder)"
        )
    refuse_in_run_folder(target, "--out")  # another run's folder
    refuse_unless_replaceable(target, replace_problem)
    with folder_lock(folder):  # read the run whole, never half replaced by a run of it
        write = read(folder)
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise output_error(target.parent, exc) from None
    write(target)
    return target


def refuse_unless_replaceable(target: Path, replace_problem: Callable[[Path], str | None]) -> None:
    """An OutputError (exit 3) when ``replace_problem(target)`` gives a reason not to write ``target``
    (a ``--out`` of :func:`write_run_file`), said with how to proceed."""
    problem = replace_problem(target)
    if problem is not None:
        raise OutputError(f"{target}: {problem} (move it away, or choose another file with --out)")


def render_outputs(
    run: SolvedRun,
    options: OutputOptions,
    folder: Path,
    *,
    progress: Progress | None = None,
    also: Callable[[], None] | None = None,
) -> dict[str, Path]:
    """Render the video, plot.png and poster.png of a solved run into ``folder``; the plot, the
    poster and ``also`` (the viewer page) are drawn while the video's workers draw its frames."""
    from armanim.render.pictures.plot import plot_run
    from armanim.render.pictures.poster import render_poster
    from armanim.render.video.movie import render_video

    video_path = folder / f"animation.{options.render.format}"
    plot_path = folder / "plot.png"
    poster_path = folder / "poster.png"
    total = run.trajectory.frames

    def pictures() -> None:
        if also is not None:
            also()
        plot_run(run, options, plot_path)
        render_poster(run, options, poster_path)

    render_video(
        run,
        options,
        video_path,
        progress=(lambda done: progress("render", done, total)) if progress else None,
        meanwhile=pictures,
    )
    return {"video": video_path, "plot": plot_path, "poster": poster_path}
