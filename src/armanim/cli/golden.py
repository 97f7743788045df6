"""``armanim compare`` and ``armanim check``: trajectories against golden files."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from armanim.cli.app import app, handle_errors, out, say
from armanim.errors import EXIT_CHECK_FAILED, SceneError, UsageError

AtolDeg = Annotated[float, typer.Option("--atol-deg", min=0, help="Tolerance on joint angles, degrees.")]
Atol = Annotated[
    float, typer.Option("--atol", min=0, help="Tolerance on positions, distances, clearances (scene units).")
]


@app.command()
@handle_errors
def compare(
    expected: Annotated[
        Path, typer.Argument(help="The expected trajectory.csv (e.g. a golden file).", show_default=False)
    ],
    actual: Annotated[Path, typer.Argument(help="The trajectory.csv to check.", show_default=False)],
    atol_deg: AtolDeg = 1e-6,
    atol: Atol = 1e-6,
) -> None:
    """Compare two trajectories: exit 0 if they agree, 1 if they differ, 2 on bad input.

    Example: [bold]armanim compare tests/golden/notes-arm.csv outputs/notes-arm/trajectory.csv[/bold]
    """
    from armanim.output.compare import compare_csv_files

    result = compare_csv_files(expected, actual, atol_deg=atol_deg, atol=atol)
    say(result.report)
    if not result.equal:
        raise typer.Exit(EXIT_CHECK_FAILED)


STYLES = {"new": "cyan", "changed": "yellow", "unchanged": "green", "pass": "green"}
"""The colour of each outcome of ``check`` (any other outcome is a failure, in red)."""


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
    from rich.table import Table

    from armanim.runs.batch import refuse_shared_names, scenes_or_errors
    from armanim.runs.golden import check_scene, update_golden

    if golden.exists() and not golden.is_dir():
        raise UsageError(f"--golden: {golden} is a file (expected a folder of golden files <name>.csv and <name>.json)")
    if update:
        from armanim.output.rundir import refuse_in_run_folder

        refuse_in_run_folder(golden, "--golden", itself=True)
    loaded = scenes_or_errors(scenes)
    refuse_shared_names(loaded)
    table = Table(title=f"golden trajectories in {golden}", title_justify="left")
    for col in ("scene", "golden file", "result"):
        table.add_column(col)
    failures = []
    for scene in loaded:
        if isinstance(scene, SceneError):
            raise scene
        result = update_golden(scene, golden) if update else check_scene(scene, golden, atol_deg=atol_deg, atol=atol)
        style = STYLES.get(result.status, "red")
        if style == "red":
            failures.append(f"{result.scene.name}: {result.report}")
        shown = result.status + (
            " (scene changed since the golden file; --update records it)"
            if result.status == "pass" and result.scene_changed
            else ""
        )
        table.add_row(result.scene.name, str(result.golden), f"[{style}]{shown}[/{style}]")
    if not quiet:
        out.print(table)
    for failure in failures:
        say(failure)
    if failures:
        raise typer.Exit(EXIT_CHECK_FAILED)
