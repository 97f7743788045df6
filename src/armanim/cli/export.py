"""``armanim export``: a finished run in another program's format (a ROS joint trajectory)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from armanim.cli.app import app, handle_errors, say
from armanim.cli.options import file_path


@app.command()
@handle_errors
def export(
    folder: Annotated[
        Path, typer.Argument(help="An output folder of armanim run, e.g. outputs/panda-shelf.", show_default=False)
    ],
    fmt: Annotated[
        str,
        typer.Option(
            "--format", help="What to write: joint-trajectory (a ROS trajectory_msgs/JointTrajectory in JSON)."
        ),
    ] = "joint-trajectory",
    out: Annotated[
        Path | None,
        typer.Option(
            "--out",
            parser=file_path,
            metavar="<path>",
            help="Write to this file (outside the run folder; an existing file is replaced only if it is an exported trajectory) instead of the run's joint_trajectory.json.",
            show_default=False,
        ),
    ] = None,
) -> None:
    """Write the run as a ROS joint trajectory, without solving, and print the file's path.

    The JSON is a trajectory_msgs/JointTrajectory: joint_names (a URDF arm's, or phi1 .. phiN), and one point per frame of trajectory.csv with positions (rad), velocities (rad/s) and time_from_start {sec, nanosec}. Any ROS 2 tool can load it; no ROS install is needed to write it (see docs/export.md). Without --out it goes into the run folder, staged and swapped in like a run.

    Examples:

    [bold]armanim export outputs/panda-shelf --format joint-trajectory[/bold]

    [bold]armanim export outputs/panda-shelf --out ~/panda-shelf.json[/bold]
    """
    from armanim.runs.export import export_run

    say(str(export_run(folder, fmt, out=out)))
