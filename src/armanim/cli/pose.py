"""``armanim fk`` and ``armanim ik``: one pose of an arm, forward or inverse."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import Annotated

import numpy as np
import typer
from rich.table import Table

from armanim.cli.app import app, err, fmt, handle_errors, out, say
from armanim.cli.arm import AxesOpt, BaseOpt, DirOpt, LinksOpt, RobotOpt, SceneOpt, arm_scene
from armanim.cli.options import parse_lengths, parse_numbers
from armanim.errors import UsageError
from armanim.output.jsontext import json_text
from armanim.output.numbers import number


@app.command()
@handle_errors
def fk(
    angles: Annotated[str, typer.Option("--angles", help="Joint angles, comma-separated (degrees unless --radians). Negative first value: --angles=-30,10.")],
    scene: SceneOpt = None,
    links: LinksOpt = None,
    base: BaseOpt = None,
    axes: AxesOpt = None,
    direction: DirOpt = None,
    robot: RobotOpt = None,
    radians: Annotated[bool, typer.Option("--radians", help="Angles are in radians.")] = False,
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON: angles_deg, joints (base to tip), tip, tip_quaternion_wxyz, tip_rpy_deg.")] = False,
    png: Annotated[Path | None, typer.Option("--png", help="Also draw the pose to this PNG file.")] = None,
) -> None:
    """Forward kinematics of one pose: joint positions and the tip.

    Example: [bold]armanim fk --angles 0,30,45,10 --links 2,5,5,5 --base 5,5,0[/bold], or [bold]armanim fk --robot panda --angles=0,-45,0,-135,0,90,45[/bold]
    """
    from armanim.arm.kinematics import forward, tool_rotation
    from armanim.arm.rotations import rotation_quaternion, rotation_rpy
    from armanim.scene import scene_to_problem

    model, loaded = arm_scene(scene, links, base, axes, direction, robot)
    problem = scene_to_problem(model)
    values = parse_numbers(angles, "--angles", problem.arm.n)
    phi = values if radians else np.radians(values)
    pose = forward(problem.arm, phi)
    if as_json:
        angles_deg = np.degrees(values) if radians else values  # as typed, not round-tripped through radians
        rot = tool_rotation(problem.arm, pose)
        print(json_text({
            "angles_deg": angles_deg.tolist(), "joints": pose.points.tolist(), "tip": pose.tip.tolist(),
            "tip_quaternion_wxyz": rotation_quaternion(rot).tolist(), "tip_rpy_deg": np.degrees(rotation_rpy(rot)).tolist(),
        }))
    else:
        out.print(pose_table(pose.points, phi, problem.arm.reach))
        rot = tool_rotation(problem.arm, pose)
        say("tool rpy (deg): " + ", ".join(fmt(v, 360) for v in np.degrees(rotation_rpy(rot)))
            + "; quaternion wxyz: " + ", ".join(fmt(v) for v in rotation_quaternion(rot)))
    for note in problem.limits.notes(phi) if loaded else []:
        say(f"note: {note}", err)
    if png is not None:
        from armanim.render.pictures.pose import render_pose_png
        from armanim.scene import render_settings

        # a pose has no goal: the scene's (or the flags' placeholder) are not drawn, nor named in the legend
        render_pose_png(replace(problem, goals=()), phi, render_settings(model), png, title="armanim fk")
        if not as_json:
            say(f"wrote {png}")


def pose_table(points: np.ndarray, phi: np.ndarray, reach: float = 1.0) -> Table:
    """Joint positions (base to tip) with each joint's angle in degrees (lengths to the
    precision of an arm of ``reach``)."""
    table = Table(title="Forward kinematics", title_justify="left")
    for col in ("point", "angle (deg)", "x", "y", "z"):
        table.add_column(col, justify="right" if col != "point" else "left")
    for i, p in enumerate(points):
        label = f"joint {i + 1}" if i < len(phi) else "tip"
        angle = fmt(np.degrees(phi[i]), 360) if i < len(phi) else ""
        table.add_row(label, angle, *(fmt(v, reach) for v in p))
    return table


@app.command()
@handle_errors
def ik(
    goal: Annotated[str, typer.Option("--goal", help="Goal position x,y,z. Negative first value: --goal=-3,1,0.")],
    scene: SceneOpt = None,
    links: LinksOpt = None,
    base: BaseOpt = None,
    axes: AxesOpt = None,
    direction: DirOpt = None,
    robot: RobotOpt = None,
    method: Annotated[str | None, typer.Option("--method", help="pinv, dls, newton or gradient (default: the scene's, else pinv).")] = None,
    start: Annotated[str | None, typer.Option("--from", help="Starting angles in degrees (default: the scene's home, else all 0).")] = None,
    tolerance: Annotated[float | None, typer.Option("--tolerance", help="Stop when |e - g| < tolerance (default: the scene's, else 0.001).")] = None,
    max_iterations: Annotated[int, typer.Option("--max-iterations", min=1, help="Give up after this many steps.")] = 2000,
    orientation: Annotated[str | None, typer.Option(
        "--orientation",
        help="The tool's orientation too (degrees): rpy=R,P,Y (URDF's fixed axes), quat=W,X,Y,Z, axis=X,Y,Z,ANGLE, or tool_axis=X,Y,Z (only the tool's z, roll free).",
    )] = None,
    orientation_tolerance: Annotated[float | None, typer.Option(
        "--orientation-tolerance", help="Degrees: converged when the tool's angle is below it too (default: the scene's, else 1).")] = None,
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON.")] = False,
) -> None:
    """Solve one pose to convergence: angles, tip, error and iteration counts.

    Example: [bold]armanim ik --goal 3,1,0 --links 1,1,1,1 --axes z,z,z,z --direction x --method newton[/bold], or [bold]armanim ik --robot panda --goal 0.5,0,0.3 --orientation rpy=180,0,0[/bold]
    """
    from armanim.motion.ik import solve_pose

    model, loaded = arm_scene(scene, links, base, axes, direction, robot)
    problem = ik_problem(model, method, tolerance, from_flags=loaded is None)
    target = parse_lengths(goal, "--goal", 3)
    wanted = parse_orientation(orientation) if orientation is not None else None
    if orientation_tolerance is not None:
        from armanim.scene.models import MIN_DEGREES

        if not MIN_DEGREES <= orientation_tolerance <= 180:
            raise UsageError(f"--orientation-tolerance: expected degrees in [{MIN_DEGREES:g}, 180] (got {orientation_tolerance:g})")
        problem = replace(problem, solver=replace(problem.solver, orientation_tolerance=float(np.radians(orientation_tolerance))))
    phi0 = np.radians(parse_numbers(start, "--from", problem.arm.n)) if start else problem.home
    result = solve_pose(problem, target, phi0, max_iterations, orientation=wanted)
    data = ik_report(problem, target, result)
    if as_json:
        print(json_text(data))
    else:
        print_ik_report(data, problem.solver.tolerance, np.degrees(problem.solver.orientation_tolerance), problem.arm.reach)


ORIENTATION_FORMS = {"rpy": 3, "quat": 4, "axis": 4, "tool_axis": 3}
"""``ik --orientation`` forms and how many numbers each takes."""


def parse_orientation(text: str):
    """``--orientation FORM=NUMBERS`` as an :class:`~armanim.motion.orientation.Orientation`,
    through the scene's own model and conversion (one validation, one place for degrees).

    >>> parse_orientation("axis=0,0,1,90").rotation.round(12).tolist()[0]
    [0.0, -1.0, 0.0]
    """
    from pydantic import ValidationError

    from armanim.motion.orientation import Orientation
    from armanim.scene.convert import orientation_rotation
    from armanim.scene.models import GoalModel, OrientationModel

    form, _, numbers = text.partition("=")
    form = form.strip()
    if form not in ORIENTATION_FORMS or not numbers:
        raise UsageError(f"--orientation: expected rpy=R,P,Y, quat=W,X,Y,Z, axis=X,Y,Z,ANGLE or tool_axis=X,Y,Z (got {text!r})")
    values = parse_numbers(numbers, f"--orientation {form}", ORIENTATION_FORMS[form]).tolist()
    try:
        if form == "tool_axis":
            GoalModel(position=[0.0, 0.0, 0.0], tool_axis=values)
            return Orientation(axis=np.array(values))
        fields = {"rpy": values} if form == "rpy" else {"quaternion_wxyz": values} if form == "quat" else {"axis": values[:3], "angle": values[3]}
        return Orientation(rotation=orientation_rotation(OrientationModel(**fields)))
    except ValidationError as exc:
        message = exc.errors()[0]["msg"].removeprefix("Value error, ")
        raise UsageError(f"--orientation: {message}") from None


def ik_problem(model, method: str | None, tolerance: float | None, from_flags: bool):
    """The scene's problem with ``--method`` and ``--tolerance`` applied (an arm made of
    flags solves to 0.001 unless told otherwise: the scene default suits animation, not one pose)."""
    from armanim.motion.solvers import METHODS
    from armanim.scene import scene_to_problem

    problem = scene_to_problem(model)
    settings = problem.solver
    if method is not None:
        if method not in METHODS:
            raise UsageError(f"--method: {method!r} is not a method (expected one of {', '.join(METHODS)})")
        settings = replace(settings, method=method)
    if tolerance is not None and not tolerance > 0:
        raise UsageError(f"--tolerance: must be > 0 (got {tolerance})")
    if tolerance is not None or from_flags:
        settings = replace(settings, tolerance=tolerance or 1e-3)
    return replace(problem, solver=settings)


def ik_report(problem, target: np.ndarray, result) -> dict:
    """``armanim ik --json``'s fields: the method, the outcome, the pose, why it was not reached."""
    data = {
        "method": problem.solver.method,
        "converged": result.converged,
        "status": result.status,
        "angles_deg": np.degrees(result.phi).tolist(),
        "tip": result.tip.tolist(),
        "error": result.distance,
        "steps": result.steps,
        "iterations": result.iterations,
        "found_by": result.found_by,
    }
    if result.orientation_error is not None:
        data["orientation_error_deg"] = float(np.degrees(result.orientation_error))
    if len(problem.self_pairs):  # the arm's own enabled pairs: the least gap and its pair
        from armanim.arm.kinematics import forward
        from armanim.world.selfdistances import self_gaps

        gaps = self_gaps(forward(problem.arm, result.phi), problem.capsules, problem.self_pairs).d
        data["self_clearance"] = float(gaps.min())
        data["self_pair"] = problem.self_pairs.labels[int(gaps.argmin())]
    reason = unreached_reason(problem, target, result.status)
    if reason and result.orientation_error is not None and result.distance < problem.solver.tolerance:
        reason = (f"orientation_unreachable: the tip is at the goal, the tool {np.degrees(result.orientation_error):.3g} deg from its "
                  "orientation, the closest these attempts found (an arm with fewer than 6 joints cannot hold every orientation)")
    if reason:
        data["reason"] = reason
    if problem.solver.method == "newton":
        data["gd_iterations"] = data.pop("iterations")
        data["newton_iterations"] = result.newton_iterations
    return data


def print_ik_report(data: dict, tolerance: float, orientation_tolerance: float = 1.0, reach: float = 1.0) -> None:
    """:func:`ik_report` for a terminal (``orientation_tolerance`` in degrees; lengths to the
    precision of an arm of ``reach``)."""
    status = "[green]converged[/green]" if data["converged"] else "[red]not converged[/red]"
    out.print(f"{data['method']}: {status}, error {number(data['error'], reach, 3)} (tolerance {tolerance:g})")
    if "orientation_error_deg" in data:
        say(f"orientation error {number(data['orientation_error_deg'], 360, 3)} deg (tolerance {orientation_tolerance:g})")
    if data["found_by"] == "free_pose_search":
        say("found by the planner's free-pose search: the method alone did not converge from the start pose")
    if "reason" in data:
        say(f"why: {data['reason']}")
    say("angles (deg): " + ", ".join(fmt(v, 360) for v in data["angles_deg"]))
    say("tip: " + ", ".join(fmt(v, reach) for v in data["tip"]))
    if "self_clearance" in data:
        say(f"self clearance: {fmt(data['self_clearance'], reach)} ({data['self_pair'].replace('|', ' to ')})")
    if "newton_iterations" in data:
        say(f"steps: {data['steps']} (gradient descent {data['gd_iterations']}, Newton {data['newton_iterations']} iterations)")
    else:
        say(f"steps: {data['steps']} ({data['iterations']} iterations)")


def unreached_reason(problem, target: np.ndarray, status: str) -> str | None:
    """Why ``armanim ik`` did not converge, when it can be told: the goal out of reach, or
    the linear algebra failing."""
    from armanim.motion.stalls import beyond_reach

    if status == "converged":
        return None
    away = float(np.linalg.norm(target - problem.arm.base))
    if beyond_reach(problem, target):
        return f"out of reach: the goal is {away:.4g} from the base, the arm is {problem.arm.reach:.4g} long (the tip is as close as it gets)"
    if status == "numerical":
        return "numerical: a step failed in linear algebra (a singular matrix or a NaN); try another --method or --from other angles"
    return "no pose found within the iterations (a local minimum, a limit or an obstacle in the way: try --from other angles)"
