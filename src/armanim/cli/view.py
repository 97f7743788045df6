"""``armanim view``: (re)write a finished run's viewer.html, the interactive 3-D page."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from armanim.cli.app import app, err, handle_errors, message_lines, say
from armanim.cli.options import file_path


@app.command()
@handle_errors
def view(
    folder: Annotated[
        Path, typer.Argument(help="An output folder of armanim run, e.g. outputs/notes-arm.", show_default=False)
    ],
    out: Annotated[
        Path | None,
        typer.Option(
            "--out",
            parser=file_path,
            metavar="<path>",
            help="Write the page to this file instead of the run's viewer.html (an existing file is replaced only if it is a page armanim wrote).",
            show_default=False,
        ),
    ] = None,
    open_page: Annotated[bool, typer.Option("--open", help="Open the page in the default web browser.")] = False,
) -> None:
    """Write the run's viewer.html from its trajectory.csv, without solving, and print its path.

    One offline HTML file: turn the scene, scrub the timeline, play at 0.25x-4x, read the joint angles at any frame (see docs/viewer.md). Without --out the page goes into the run folder, staged and swapped in like a run.

    Examples:

    [bold]armanim view outputs/notes-arm[/bold]

    [bold]armanim view outputs/notes-arm --out ~/notes-arm.html --open[/bold]
    """
    from armanim.runs.pipeline import write_run_viewer

    notes: list[str] = []
    path = write_run_viewer(folder, out=out, notes=notes.append)
    for note in notes:  # a page that does not show the run's meshes (not found)
        say(message_lines("note: " + note), err)
    say(str(path))
    if open_page:
        import webbrowser

        try:
            opened = webbrowser.open(path.resolve().as_uri())
        except webbrowser.Error:
            opened = False
        if not opened:
            say(f"note: no web browser could be started here; open {path} in one", err)
