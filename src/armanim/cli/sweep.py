"""``armanim sweep``: one scene under every combination of settings, compared in one table."""

from __future__ import annotations

import functools
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from armanim.cli.app import app, err, handle_errors, out, say
from armanim.cli.interrupts import ignore_until_exit
from armanim.cli.options import JobsOpt, SchedulerOpt, usable_jobs
from armanim.cli.reports import batch_exit_code, print_batch_problems

if TYPE_CHECKING:
    from rich.table import Table


@app.command()
@handle_errors
def sweep(
    scene: Annotated[Path, typer.Argument(help="The scene to vary.", show_default=False)],
    settings: Annotated[
        list[str],
        typer.Option(
            "--set", help="FIELD.PATH=V1,V2,... (repeatable); the product of all values is run.", show_default=False
        ),
    ],
    out_root: Annotated[
        Path, typer.Option("--out", help="Variants go to OUT/<variant name>/, the table to OUT/<scene>-sweep.csv.")
    ] = Path("outputs"),
    video: Annotated[
        bool,
        typer.Option(
            "--video/--no-video", help="Render each variant's video (off by default: sweeps compare numbers)."
        ),
    ] = False,
    quiet: Annotated[bool, typer.Option("--quiet", "-q", help="No progress bar and no table.")] = False,
    jobs: JobsOpt = None,
    scheduler: SchedulerOpt = None,
) -> None:
    """Run a scene under every combination of settings (at most 1,000) and compare the results.

    Example: [bold]armanim sweep scenes/notes-arm.yaml --set solver.step=0.05,0.1,0.2 --set solver.method=pinv,dls[/bold]
    """
    from armanim.output.rundir import refuse_in_run_folder
    from armanim.runs.sweep import parse_setting, run_sweep, variant_count

    refuse_in_run_folder(out_root, "--out", itself=True)
    jobs = usable_jobs(jobs)
    parsed = [parse_setting(text) for text in settings]
    count = variant_count(parsed)  # at most MAX_VARIANTS, said before anything is built or run
    if not quiet:
        say(f"sweep of {scene}: {count} variants ({' x '.join(s.path for s in parsed)})", err)
    from armanim.cli.progress import bars

    with bars(quiet) as shown:
        result = run_sweep(
            scene,
            parsed,
            out_root,
            jobs=jobs,
            scheduler=scheduler,
            video=video,
            progress=functools.partial(shown, "variants"),
        )
    ignore_until_exit()  # every variant, the table and index.csv are in place: the sweep has its outcome
    if not quiet:
        title = f"sweep of {scene.name}: {len(result.variants)} variants"
        out.print(sweep_screen_table(title, result.header, result.rows, len(parsed)))
        say(f"table (every column, the variants' folder names): {result.table}")
    print_batch_problems(result.entries)
    raise typer.Exit(batch_exit_code(result.entries, strict=False))


SWEEP_SCREEN_COLUMNS = {
    "status": "status",
    "reached": "reached",
    "missed": "missed",
    "frames": "frames",
    "min_clearance": "min clear.",
}
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
    from rich.table import Table

    table = Table(title=title, title_justify="left")
    for _, label in shown:
        table.add_column(label, overflow="fold")
    for row in rows:
        table.add_row(*(str(row[i]) for i, _ in shown))
    return table
