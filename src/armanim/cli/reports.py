"""What ``run``, ``sweep`` and batches print when they finish, and their exit codes."""

from __future__ import annotations

from pathlib import Path

from armanim.cli.app import err, out, say
from armanim.errors import EXIT_BAD_INPUT, EXIT_CHECK_FAILED, EXIT_OUTPUT_FAILED
from armanim.output.numbers import number


def print_goal_table(result) -> None:
    """The per-goal table printed at the end of a run, then its output files."""
    import numpy as np
    from rich.table import Table

    sol = result.solution
    title = f"{result.scene.name}: {sol.reached} of {len(sol.goals)} goals reached, {sol.trajectory.frames} frames"
    table = Table(title=title, title_justify="left")
    oriented = any(g.final_orientation_error is not None for g in sol.goals)  # the angle column only then
    columns = ("goal", "position", "result", "frames", "distance") + (("angle (deg)",) if oriented else ())
    for col in columns:
        table.add_column(col, justify="left" if col in ("position", "result") else "right")
    reach, tolerance = result.problem.arm.reach, result.problem.solver.tolerance
    for g in sol.goals:
        outcome = "[green]reached[/green]" if g.reached else f"[red]missed[/red]: {g.reason_text}"
        rows = (
            g.last_frame - g.first_frame + 1 if g.first_frame >= 0 else 0
        )  # its hold (and frame 0) too: the rows add up
        row = [
            str(g.index),
            ", ".join(table_number(v, reach / 100) for v in g.position),
            outcome,
            str(rows),
            table_number(g.final_distance, tolerance / 100),
        ]
        if oriented:
            row.append(
                "" if g.final_orientation_error is None else number(np.degrees(g.final_orientation_error), 360, 3)
            )
        table.add_row(*row)
    out.print(table)
    say("outputs: " + ", ".join(str(p) for p in result.files.values()))
    if getattr(result, "timing", None) is not None:
        from armanim.runs.warmth import machine_code_kept

        say(
            run_time_line(
                result.timing, result.scene.model.arm.is_urdf, "video" in result.files, kept=machine_code_kept()
            )
        )


def run_time_line(timing, urdf: bool, video: bool, kept: bool = True) -> str:
    """How long the run took from its scene file (and its URDF) to its outputs, numba's compiling
    apart (:mod:`armanim.runs.stopwatch`); ``kept``: whether numba kept what it compiled (else the
    next run compiles again, and the line says why).

    >>> from armanim.runs.stopwatch import Stopwatch
    >>> run_time_line(Stopwatch(41.5, 30.25), True, True)
    'time: 11.2 s from the scene and its URDF to the video (numba compiled its code for 30.2 s more, once after installing)'
    """
    from armanim.runs.warmth import NOT_KEPT

    line = f"time: {timing.without_compiling:.1f} s from the scene{' and its URDF' if urdf else ''} to the {'video' if video else 'outputs'}"
    if timing.compiling >= 0.05:
        when = "once after installing" if kept else NOT_KEPT
        line += f" (numba compiled its code for {timing.compiling:.1f} s more, {when})"
    return line


def table_number(value: float, resolution: float) -> str:
    """``value`` in a table, to the decimal of ``resolution`` (a hundredth of the arm's reach for a
    position, a hundredth of ``solver.tolerance`` for a distance): no ``0.172857`` or ``1.21e-05`` noise.

    >>> table_number(0.17285714, 0.0085), table_number(1.21e-05, 0.0001), table_number(10.41384, 0.0001), table_number(-0.0, 1)
    ('0.173', '0', '10.4138', '0')
    """
    import math

    decimals = max(0, -math.floor(math.log10(abs(resolution)))) if resolution else 6
    if not math.isfinite(value):
        return str(value)
    text = f"{value:.{decimals}f}"
    text = text.rstrip("0").rstrip(".") if "." in text else text
    return "0" if text in ("-0", "") else text


def print_missed_goals(result, path: Path) -> None:
    """``--strict``: each missed goal of a run on stderr (also with --quiet)."""
    for goal in result.solution.goals:
        if not goal.reached:
            say(f"--strict: {path}: goal {goal.index} missed ({goal.reason})", err)


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
    """One line per scene of a batch, then where the index is."""
    from rich.table import Table

    parents = {str(Path(e.folder).parent) for e in entries if e.folder}
    shared = len(parents) == 1 and all(not e.folder or Path(e.folder).name == e.name for e in entries)
    where = (
        f", in {next(iter(parents))}" if shared else ""
    )  # each in OUT/<scene>: the folder column would repeat the name
    table = Table(
        title=f"{len(entries)} scenes: {sum(e.status == 'ok' for e in entries)} ok{where}", title_justify="left"
    )
    numbers = ("reached", "missed", "frames", "min clear.")
    widest = max([len("scene"), *(len(e.name) for e in entries)])
    for col in ("scene", "status", *numbers, *(() if shared else ("folder",))):  # a folder folds, never a scene's name
        table.add_column(
            col,
            justify="right" if col in numbers else "left",
            overflow="fold",
            no_wrap=col != "folder",
            min_width=widest if col == "scene" else None,
        )
    for e in entries:
        style = {"ok": "green", "invalid": "red", "failed": "red"}[e.status]
        clearance = "" if e.min_clearance is None else number(e.min_clearance, digits=3)
        table.add_row(
            e.name,
            f"[{style}]{e.status}[/{style}]",
            str(e.reached),
            str(e.missed),
            str(e.frames),
            clearance,
            *(() if shared else (e.folder,)),
        )
    out.print(table)
    say(f"index: {index_path}")


def print_batch_problems(entries) -> None:
    """Every invalid or failed scene's report on stderr (also with --quiet: errors are not chatter)."""
    for e in entries:
        if e.message:
            say(e.message, err)
