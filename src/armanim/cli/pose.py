"""``armanim fk`` and ``armanim ik``: one pose of an arm, forward or inverse.

Thin commands: the flags' text is parsed here, and :mod:`armanim.runs.pose` answers
(silently, with values); this module only prints the answer.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from armanim.cli.app import app, err, fmt, handle_errors, out, say, tell_first_compile
from armanim.cli.arm import AxesOpt, BaseOpt, DirOpt, LinksOpt, RobotOpt, SceneOpt, arm_scene
from armanim.cli.options import file_path, parse_lengths, parse_numbers
from armanim.errors import UsageError
from armanim.output.jsontext import json_text
from armanim.output.numbers import number

if TYPE_CHECKING:
    import numpy as np
    from rich.table import Table


@app.command()
@handle_errors
def fk(
    angles: Annotated[
        str,
        typer.Option(
            "--angles",
            help="Joint angles, comma-separated (degrees unless --radians). Negative first value: --angles=-30,10.",
        ),
    ],
    scene: SceneOpt = None,
    links: LinksOpt = None,
    base: BaseOpt = None,
    axes: AxesOpt = None,
    direction: DirOpt = None,
    robot: RobotOpt = None,
    radians: Annotated[bool, typer.Option("--radians", help="Angles are in radians.")] = False,
    as_json: Annotated[
        bool,
        typer.Option(
            "--json", help="Print JSON: angles_deg, joints (base to tip), tip, tip_quaternion_wxyz, tip_rpy_deg."
        ),
    ] = False,
    png: Annotated[
        Path | None,
        typer.Option("--png", help="Also draw the pose to this PNG file.", parser=file_path, metavar="<path>"),
    ] = None,
) -> None:
    """Forward kinematics of one pose: joint positions and the tip.

    Example: [bold]armanim fk --angles 0,30,45,10 --links 2,5,5,5 --base 5,5,0[/bold], or [bold]armanim fk --robot panda --angles=0,-45,0,-135,0,90,45[/bold]
    """
    from armanim.runs.pose import forward_pose

    if png is not None:
        from armanim.output.marks import check_marked_replaceable
        from armanim.output.rundir import refuse_in_run_folder

        refuse_in_run_folder(png, "--png")
        check_marked_replaceable(png, "--png", "fk --png")  # a picture of yours there: exit 3 before any work
    model, loaded = arm_scene(scene, links, base, axes, direction, robot)
    values = parse_numbers(angles, "--angles", model.arm.joint_count)
    answer = forward_pose(model, values, in_radians=radians, with_notes=loaded is not None)
    if as_json:
        print(
            json_text(
                {
                    "angles_deg": answer.angles_deg.tolist(),
                    "joints": answer.joints.tolist(),
                    "tip": answer.tip.tolist(),
                    "tip_quaternion_wxyz": answer.tip_quaternion_wxyz.tolist(),
                    "tip_rpy_deg": answer.tip_rpy_deg.tolist(),
                }
            )
        )
    else:
        out.print(pose_table(answer.joints, answer.joint_degrees, answer.problem.arm.reach))
        say(
            "tool rpy (deg): "
            + ", ".join(fmt(v, 360) for v in answer.tip_rpy_deg)
            + "; quaternion wxyz: "
            + ", ".join(fmt(v) for v in answer.tip_quaternion_wxyz)
        )
    for note in answer.notes:
        say(f"note: {note}", err)
    if png is not None:
        from armanim.errors import OutputError
        from armanim.output.atomic import advised
        from armanim.output.marks import check_marked_replaceable, write_marked
        from armanim.render.paint.pixels import png_bytes
        from armanim.render.pictures.pose import draw_pose

        # a pose has no goal: the scene's (or the flags' placeholder) are not drawn, nor named in the legend;
        # the picture tints the arm's own pairs near each other, so it takes the problem with them
        from armanim.runs.pipeline import look_meshes
        from armanim.scene import render_settings
        from armanim.scene.convert import convert_scene

        settings = render_settings(model)
        converted = convert_scene(model)  # the problem and its links' places, from one chain
        meshes, notes = look_meshes(
            model, converted.places, settings, loaded.path.parent if loaded is not None else Path(".")
        )
        for note in notes:  # a mesh not found: its link is drawn as its capsules, as in a run
            say(f"note: {note}", err)
        drawn = draw_pose(replace(converted.problem, goals=()), answer.phi, settings, title="armanim fk", meshes=meshes)
        try:
            write_marked(
                png, png_bytes(drawn), "fk --png", recheck=lambda: check_marked_replaceable(png, "--png", "fk --png")
            )
        except OutputError as exc:
            raise advised(exc, "choose another file with --png") from None
        if not as_json:
            say(f"wrote {png}")


def pose_table(points: np.ndarray, degrees: np.ndarray, reach: float = 1.0) -> Table:
    """Joint positions (base to tip) with each joint's angle ``degrees`` (lengths to the
    precision of an arm of ``reach``)."""
    from rich.table import Table

    table = Table(title="Forward kinematics", title_justify="left")
    for col in ("point", "angle (deg)", "x", "y", "z"):
        table.add_column(col, justify="right" if col != "point" else "left")
    for i, p in enumerate(points):
        label = f"joint {i + 1}" if i < len(degrees) else "tip"
        angle = fmt(degrees[i], 360) if i < len(degrees) else ""
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
    method: Annotated[
        str | None, typer.Option("--method", help="pinv, dls, newton or gradient (default: the scene's, else pinv).")
    ] = None,
    start: Annotated[
        str | None, typer.Option("--from", help="Starting angles in degrees (default: the scene's home, else all 0).")
    ] = None,
    tolerance: Annotated[
        float | None,
        typer.Option("--tolerance", help="Stop when |e - g| < tolerance (default: the scene's, else 0.001)."),
    ] = None,
    max_iterations: Annotated[
        int, typer.Option("--max-iterations", min=1, help="Give up after this many steps.")
    ] = 2000,
    orientation: Annotated[
        str | None,
        typer.Option(
            "--orientation",
            help="The tool's orientation too (degrees): rpy=R,P,Y (URDF's fixed axes), quat=W,X,Y,Z, axis=X,Y,Z,ANGLE, or tool_axis=X,Y,Z (only the tool's z, roll free).",
        ),
    ] = None,
    orientation_tolerance: Annotated[
        float | None,
        typer.Option(
            "--orientation-tolerance",
            help="Degrees: converged when the tool's angle is below it too (default: the scene's, else 1).",
        ),
    ] = None,
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON.")] = False,
) -> None:
    """Solve one pose to convergence: angles, tip, error and iteration counts.

    Example: [bold]armanim ik --goal 3,1,0 --links 1,1,1,1 --axes z,z,z,z --direction x --method newton[/bold], or [bold]armanim ik --robot panda --goal 0.5,0,0.3 --orientation rpy=180,0,0[/bold]
    """
    from armanim.runs.pose import ik_problem, ik_report, solve_ik, with_orientation_tolerance

    model, loaded = arm_scene(scene, links, base, axes, direction, robot)
    problem = ik_problem(model, method, tolerance, from_flags=loaded is None)
    target = parse_lengths(goal, "--goal", 3)
    wanted = parse_orientation(orientation) if orientation is not None else None
    if orientation_tolerance is not None:
        problem = with_orientation_tolerance(problem, orientation_tolerance)
    start_deg = parse_numbers(start, "--from", problem.arm.n) if start else None
    tell_first_compile("ik", problem)
    answer = solve_ik(problem, target, start_deg, max_iterations, orientation=wanted)
    data = ik_report(answer)
    if as_json:
        print(json_text(data))
    else:
        print_ik_report(data, problem.solver.tolerance, answer.orientation_tolerance_deg, problem.arm.reach)


ORIENTATION_FORMS = {"rpy": 3, "quat": 4, "axis": 4, "tool_axis": 3}
"""``ik --orientation`` forms and how many numbers each takes."""


def parse_orientation(text: str):
    """``--orientation FORM=NUMBERS`` as an :class:`~armanim.motion.orientation.Orientation`,
    through the scene's own model and conversion (:func:`armanim.scene.convert.orientation_flag`).

    >>> parse_orientation("axis=0,0,1,90").rotation.round(12).tolist()[0]
    [0.0, -1.0, 0.0]
    """
    from pydantic import ValidationError

    from armanim.scene.convert import orientation_flag

    form, _, numbers = text.partition("=")
    form = form.strip()
    if form not in ORIENTATION_FORMS or not numbers:
        raise UsageError(
            f"--orientation: expected rpy=R,P,Y, quat=W,X,Y,Z, axis=X,Y,Z,ANGLE or tool_axis=X,Y,Z (got {text!r})"
        )
    values = parse_numbers(numbers, f"--orientation {form}", ORIENTATION_FORMS[form]).tolist()
    try:
        return orientation_flag(form, values)
    except ValidationError as exc:
        message = exc.errors()[0]["msg"].removeprefix("Value error, ")
        raise UsageError(f"--orientation: {message}") from None


def print_ik_report(data: dict, tolerance: float, orientation_tolerance: float = 1.0, reach: float = 1.0) -> None:
    """:func:`ik_report` for a terminal (``orientation_tolerance`` in degrees; lengths to the
    precision of an arm of ``reach``)."""
    status = "[green]converged[/green]" if data["converged"] else "[red]not converged[/red]"
    out.print(f"{data['method']}: {status}, error {number(data['error'], reach, 3)} (tolerance {tolerance:g})")
    if "orientation_error_deg" in data:
        say(
            f"orientation error {number(data['orientation_error_deg'], 360, 3)} deg (tolerance {orientation_tolerance:g})"
        )
    if data["found_by"] == "free_pose_search":
        say("found by the planner's free-pose search: the method alone did not converge from the start pose")
    if "reason" in data:
        say(f"why: {data['reason']}")
    say("angles (deg): " + ", ".join(fmt(v, 360) for v in data["angles_deg"]))
    say("tip: " + ", ".join(fmt(v, reach) for v in data["tip"]))
    if "self_clearance" in data:
        say(f"self clearance: {fmt(data['self_clearance'], reach)} ({data['self_pair'].replace('|', ' to ')})")
    if "newton_iterations" in data:
        say(
            f"steps: {data['steps']} (gradient descent {data['gd_iterations']}, Newton {data['newton_iterations']} iterations)"
        )
    else:
        say(f"steps: {data['steps']} ({data['iterations']} iterations)")
