"""``armanim validate`` and ``armanim schema``: scene files checked, and their JSON Schema."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Annotated

import typer

from armanim.cli.app import app, handle_errors, plural, print_notes, report, say
from armanim.cli.options import file_path
from armanim.errors import EXIT_BAD_INPUT, message_lines, shown_list
from armanim.output.jsontext import json_text


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
            report(exc)
            continue
        say(message_lines(f"ok {path} ({scene.name}: {scene_counts(scene.model)}, method {scene.model.solver.method})"))
        print_notes(scene)
    if failed:
        raise typer.Exit(EXIT_BAD_INPUT)


def scene_counts(model) -> str:
    """``4 links, 1 goal, 0 obstacles``; a URDF arm names its joints: ``7 joints (panda_joint1 .. panda_joint7), ...``."""
    arm = model.arm
    if arm.is_urdf:
        names = arm.urdf_arm.joint_names
        plain = all(
            n.isprintable() and len(n) <= 80 for n in names
        )  # else quoted and escaped: a name cannot forge a line
        first = f"{plural(len(names), 'joint')} ({', '.join(names) if plain else shown_list(names)})"
    else:
        first = plural(len(arm.links), "link")
    counts = ((len(model.goals), "goal"), (len(model.obstacles), "obstacle"))
    return ", ".join([first] + [plural(count, word) for count, word in counts])


@app.command()
@handle_errors
def schema(
    output: Annotated[
        Path | None,
        typer.Option(
            "--out", help="Write the schema to this file instead of stdout.", parser=file_path, metavar="<path>"
        ),
    ] = None,
) -> None:
    """Print the scene file's JSON Schema, for editors to complete and check scenes.

    Example: [bold]armanim schema --out scene.schema.json[/bold], then start a scene with [bold]# yaml-language-server: $schema=scene.schema.json[/bold]
    """
    from armanim.scene.models import SceneModel

    text = json_text(SceneModel.model_json_schema(), indent=2) + "\n"
    if output is None:
        sys.stdout.write(text)
    else:
        from armanim.output.marks import check_marked_replaceable, write_marked
        from armanim.output.rundir import refuse_in_run_folder

        refuse_in_run_folder(output, "--out")
        check_marked_replaceable(output, "--out", "schema")  # a file of yours there: exit 3, left as it was
        write_marked(output, text, "schema", recheck=lambda: check_marked_replaceable(output, "--out", "schema"))
