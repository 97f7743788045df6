"""``armanim import moveit``: a MoveIt planning scene and motion plan request as an armanim scene."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from armanim.cli.app import app, err, handle_errors, message_lines, say
from armanim.cli.options import file_path

import_app = typer.Typer(
    name="import",
    help="Write an armanim scene from another program's files (MoveIt).\n\n"
    "Example: [bold]armanim import moveit scene.yaml --request request.yaml --urdf panda.urdf --srdf panda.srdf --out panda-scene.yaml[/bold]",
    rich_markup_mode="rich",
    no_args_is_help=True,
    context_settings={"help_option_names": ["-h", "--help"]},
)
app.add_typer(import_app, name="import")


@import_app.command()
@handle_errors
def moveit(
    scene: Annotated[
        Path,
        typer.Argument(
            help="A MoveIt planning scene: moveit_msgs/PlanningScene as YAML, or a .scene file "
            "RViz's Motion Planning panel exported.",
            show_default=False,
        ),
    ],
    out: Annotated[
        Path,
        typer.Option(
            "--out",
            parser=file_path,
            metavar="<path>",
            help="The armanim scene to write (an existing file is replaced only if this command wrote it).",
            show_default=False,
        ),
    ],
    request: Annotated[
        Path | None,
        typer.Option(
            "--request",
            help="A moveit_msgs/MotionPlanRequest as YAML: the start "
            "state and the goal (joint constraints, or a position "
            "and orientation constraint on a link).",
            show_default=False,
        ),
    ] = None,
    robot: Annotated[
        str | None, typer.Option("--robot", help="A bundled robot (armanim robots lists them).", show_default=False)
    ] = None,
    urdf: Annotated[
        Path | None, typer.Option("--urdf", help="The robot's URDF file (instead of --robot).", show_default=False)
    ] = None,
    srdf: Annotated[
        Path | None,
        typer.Option(
            "--srdf",
            help="The robot's SRDF: its planning group gives the chain, its disabled pairs the self-collision rules.",
            show_default=False,
        ),
    ] = None,
    tip_link: Annotated[
        str | None,
        typer.Option(
            "--tip-link",
            help="The link the arm ends at (default: the SRDF's planning group, else the request's joints).",
            show_default=False,
        ),
    ] = None,
) -> None:
    """Write an armanim scene from a MoveIt planning scene and motion plan request, and print its path.

    Objects' boxes, spheres and cylinders become obstacles named after their ids; the start state becomes arm.home (degrees) and arm.joint_values; joint constraints a joint goal, a position and orientation constraint a pose goal. Paths in the scene are relative to its folder. A mesh, cone or plane, an unknown joint or link, or a malformed file is FILE:LINE: message and exit 2 (see docs/moveit-import.md).

    Example: [bold]armanim import moveit scene0001.yaml --request request0001.yaml --urdf panda_spherized.urdf --srdf panda.srdf --out bookshelf.yaml[/bold], then [bold]armanim run bookshelf.yaml[/bold]

    With a bundled robot: [bold]armanim import moveit shelf.scene --robot panda --out shelf.yaml[/bold]
    """
    from armanim.output.rundir import refuse_in_run_folder
    from armanim.scene.moveitscene import RobotSource, import_moveit

    refuse_in_run_folder(out, "--out")
    imported = import_moveit(scene, request, RobotSource(robot=robot, urdf=urdf, srdf=srdf, tip_link=tip_link), out)
    for note in imported.notes:
        say(message_lines(note), err)
    say(str(out))
