"""``armanim robots``: the bundled robots, their joints, limits and reach."""

from __future__ import annotations

from armanim.cli.app import app, handle_errors, out


@app.command()
@handle_errors
def robots() -> None:
    """List the bundled robots a scene can name with [bold]arm: {robot: NAME}[/bold] (or fk/ik [bold]--robot NAME[/bold]).

    Example: [bold]armanim robots[/bold]
    """
    from rich.table import Table

    from armanim.scene.robots import robot_summaries

    for robot in robot_summaries():
        table = Table(title=f"{robot.name}: {robot.title}, reach {robot.reach:.3f} m from joint 1, {robot.capsules} collision capsules",
                      title_justify="left")
        table.add_column("phi")
        table.add_column("joint")
        table.add_column("limits (deg)")
        for k, (joint, limits) in enumerate(zip(robot.joints, robot.limits_deg)):
            table.add_row(f"phi{k + 1}", joint, f"[{limits[0]:.1f}, {limits[1]:.1f}]" if limits else "unlimited")
        out.print(table)
