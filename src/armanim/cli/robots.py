"""``armanim robots``: the bundled robots, their joints, limits and reach."""

from __future__ import annotations

from dataclasses import dataclass

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


def robot_summaries() -> list[RobotSummary]:
    """Every bundled robot: its joints, their limits, its reach from joint 1 and its capsules.

    >>> [s.name for s in robot_summaries()]
    ['panda', 'ur5', 'iiwa']
    """
    import numpy as np

    from armanim.scene import scene_model, scene_to_problem  # the scene room: pydantic, the URDF reader
    from armanim.scene.robots import ROBOTS, bundled_robot

    summaries = []
    for name in ROBOTS:
        problem = scene_to_problem(scene_model({"version": 1, "arm": {"robot": name}, "goals": [[0.5, 0, 0.5]]}))
        lim = problem.limits
        limits = tuple((float(np.degrees(lo)), float(np.degrees(hi))) if np.isfinite(lo) else None
                       for lo, hi in zip(lim.lower, lim.upper))
        summaries.append(RobotSummary(name, bundled_robot(name).title, problem.arm.joint_names, limits,
                                      problem.arm.reach, len(problem.capsules)))
    return summaries


@app.command()
@handle_errors
def robots() -> None:
    """List the bundled robots a scene can name with [bold]arm: {robot: NAME}[/bold] (or fk/ik [bold]--robot NAME[/bold]).

    Example: [bold]armanim robots[/bold]
    """
    from rich.table import Table

    for robot in robot_summaries():
        table = Table(title=f"{robot.name}: {robot.title}, reach {robot.reach:.3f} m from joint 1, {robot.capsules} collision capsules",
                      title_justify="left")
        table.add_column("phi")
        table.add_column("joint")
        table.add_column("limits (deg)")
        for k, (joint, limits) in enumerate(zip(robot.joints, robot.limits_deg)):
            table.add_row(f"phi{k + 1}", joint, f"[{limits[0]:.1f}, {limits[1]:.1f}]" if limits else "unlimited")
        out.print(table)
