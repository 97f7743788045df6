"""``armanim robots``: the bundled robots, their joints, limits and reach."""

from __future__ import annotations

import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Annotated

import typer

from armanim.cli.app import app, handle_errors, out


@dataclass(frozen=True)
class RobotSummary:
    """What ``armanim robots`` shows of a bundled robot (degrees and metres)."""

    name: str
    title: str
    joints: tuple[str, ...]
    limits_deg: tuple[tuple[float, float] | None, ...]
    reach: float
    capsules: int
    held: tuple[tuple[str, str, float], ...] = ()
    """The joints off the chain, held (``arm.joint_values``): (name, how, default in degrees or metres)."""
    prismatic: tuple[bool, ...] = ()
    """Per joint of the chain: prismatic (its ``limits_deg`` in metres)."""


def robot_summaries() -> list[RobotSummary]:
    """Every bundled robot: its joints, their limits, its reach from joint 1, its capsules and the
    joints held off its chain (the Panda's fingers) with their defaults.

    >>> [s.name for s in robot_summaries()]
    ['panda', 'ur5', 'iiwa', 'ur5_rail']
    """
    import numpy as np

    from armanim.scene import scene_model, scene_to_problem  # the scene room: pydantic, the URDF reader
    from armanim.scene.robots import ROBOTS, bundled_robot, default_held_value

    summaries = []
    for name in ROBOTS:
        problem = scene_to_problem(scene_model({"version": 1, "arm": {"robot": name}, "goals": [[0.5, 0, 0.5]]}))
        lim = problem.limits
        slides = problem.arm.slides
        limits = tuple(
            ((float(lo), float(hi)) if slide else (float(np.degrees(lo)), float(np.degrees(hi))))
            if np.isfinite(lo)
            else None
            for lo, hi, slide in zip(lim.lower, lim.upper, slides)
        )
        urdf = scene_model({"version": 1, "arm": {"robot": name}, "goals": [[0.5, 0, 0.5]]}).arm.urdf_arm
        held = tuple(_held_row(j, default_held_value(j)) for j in urdf.held)
        summaries.append(
            RobotSummary(
                name,
                bundled_robot(name).title,
                problem.arm.joint_names,
                limits,
                problem.arm.reach,
                len(problem.capsules),
                held,
                tuple(bool(v) for v in slides),
            )
        )
    return summaries


def _held_row(joint, default: float) -> tuple[str, str, float]:
    """(name, how it is held, default in the scene's unit: degrees, or metres for a prismatic joint)."""
    import math

    if joint.follows is not None:
        other, multiplier, offset = joint.follows
        return joint.name, f"mimics {other} (x {multiplier:g} + {offset:g})", math.nan
    unit = "m" if joint.kind == "prismatic" else "deg"
    value = default if joint.kind == "prismatic" else math.degrees(default)
    return joint.name, f"{joint.kind}, arm.joint_values ({unit})", value


@app.command()
@handle_errors
def robots(
    fit: Annotated[
        Path | None,
        typer.Option(
            "--fit",
            metavar="URDF",
            help="Print the collision capsules of this URDF instead "
            "(its primitives, and capsules fitted to its meshes), as a scene's arm.collision list.",
        ),
    ] = None,
    package_dir: Annotated[
        list[Path] | None,
        typer.Option(
            "--package-dir",
            help="A folder package:// mesh names are found in "
            "(repeat for several); default the URDF's folder and its parents.",
        ),
    ] = None,
) -> None:
    """List the bundled robots a scene can name with [bold]arm: {robot: NAME}[/bold] (or fk/ik [bold]--robot NAME[/bold]) with their reach (from joint 1), and the joints off each chain a scene holds with [bold]arm.joint_values[/bold] (the Panda's fingers).

    Example: [bold]armanim robots[/bold]; [bold]armanim robots --fit my_arm.urdf > capsules.yaml[/bold] prints the capsules [bold]collision: auto[/bold] fits to its meshes
    """
    if fit is not None:
        from armanim.scene.robots import fitted_collision_text

        sys.stdout.write(fitted_collision_text(fit, package_dir))
        return
    from rich.table import Table
    from rich.text import Text

    for robot in robot_summaries():
        # the header on a line of its own: as a table's title it wrapped to the table's width
        out.print(Text(f"{robot.name}: {robot.title}, reach {robot.reach:.3f} m, {robot.capsules} collision capsules"))
        table = Table()
        table.add_column("phi")
        table.add_column("joint")
        table.add_column("limits (deg; m)" if any(robot.prismatic) else "limits (deg)")
        for k, (joint, limits) in enumerate(zip(robot.joints, robot.limits_deg)):
            slides = bool(robot.prismatic and robot.prismatic[k])
            shown = (
                (
                    f"[{limits[0]:.3f}, {limits[1]:.3f}] m, prismatic"
                    if slides
                    else f"[{limits[0]:.1f}, {limits[1]:.1f}]"
                )
                if limits
                else "unlimited"
            )
            table.add_row(f"q{k + 1}" if slides else f"phi{k + 1}", joint, shown)
        for joint, how, default in robot.held:
            table.add_row("held", joint, how if default != default else f"{how}, default {default:g}")
        out.print(table)
