"""Read a finished run back (scene.yaml, trajectory.csv, summary.json) for re-rendering."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from pydantic import ValidationError

from armanim.arm.kinematics import joints_in_si
from armanim.arm.visuals import LinkPlaces
from armanim.errors import Diagnostic, SceneError
from armanim.motion.carry import replayed_carry
from armanim.motion.orientation import frame_orientations
from armanim.motion.problem import Problem
from armanim.motion.solution import GoalReport, Solution, Trajectory
from armanim.motion.trajectory import with_self_clearance, with_world_self_clearance
from armanim.output.csvfile import EMPTY_ALLOWED, TEXT_COLUMNS, TrajectoryTable, read_trajectory_csv, velocity_columns
from armanim.output.files import read_bounded
from armanim.output.jsontext import parse_json
from armanim.output.summary import goal_report_from_dict
from armanim.scene import LoadedScene, load_scene
from armanim.scene.convert import convert_scene
from armanim.scene.models import LIMITS, RenderModel

SCENE_COPY = "scene.yaml"
ROBOT_COPY = "robot.urdf"
SRDF_COPY = "robot.srdf"
"""A run of a user's URDF arm keeps a copy of the file (the scene's ``arm.urdf`` names the original)."""
MAX_SUMMARY_BYTES = 10_000_000  # a summary of 1,000 goals is about 400 kB


@dataclass(frozen=True)
class FinishedRun:
    """A run read back from its folder (``places``: its URDF links' on ``problem.arm``, made with
    it: :attr:`armanim.scene.convert.ConvertedScene.places`)."""

    scene: LoadedScene
    problem: Problem
    solution: Solution
    places: LinkPlaces | None = None


def _read_summary(summary_path: Path) -> dict:
    try:
        summary = parse_json(read_bounded(summary_path, MAX_SUMMARY_BYTES, "an armanim summary.json"))
        if not isinstance(summary, dict) or not isinstance(summary.get("goals"), list):
            raise ValueError("no list of goals")
        return summary
    except ValueError as exc:
        raise SceneError(str(summary_path), [Diagnostic("", f"is not an armanim summary: {exc}")]) from None


def _reports(summary: dict, summary_path: Path) -> tuple[GoalReport, ...]:
    try:
        return tuple(goal_report_from_dict(g, summary.get("joints") or ()) for g in summary["goals"])
    except (ValueError, KeyError, TypeError) as exc:
        raise SceneError(str(summary_path), [Diagnostic("", f"is not an armanim summary: {exc}")]) from None


def _run_fps(summary: dict, scene: LoadedScene) -> float:
    """The rate of the run's frames, as summary.json records it (``run --fps`` may differ from
    the scene's, at which the motion was solved); the scene's when the summary's is not one a
    scene could have (the render model judges)."""
    try:
        return RenderModel.model_validate({"fps": summary.get("fps")}).fps
    except ValidationError:
        return scene.model.render.fps


def _first_bad(table: TrajectoryTable, column: str, bad: np.ndarray, message: str) -> Diagnostic | None:
    rows = np.nonzero(bad)[0]
    if not len(rows):
        return None
    value = table.column(column)[rows[0]]
    shown = "empty or NaN" if np.isnan(value) else f"{value:g}"
    return Diagnostic("", f"{column}: {shown} {message}", table.first_line + int(rows[0]))


def drawable_problem(table: TrajectoryTable, goals: int) -> Diagnostic | None:
    """The first value of a trajectory table that cannot be drawn, or None.

    Frames must count 0, 1, 2, ...; goals index the scene's goals; ``reached`` is 0 or 1;
    every number is finite (``clearance`` and ``orientation_error_deg`` may be empty) and at most LIMITS["magnitude"] in size.
    """
    if not len(table.data):
        return Diagnostic("", "has a header but no rows (a run writes at least frame 0)", 2)
    frame, goal, reached = table.column("frame"), table.column("goal"), table.column("reached")
    limit = LIMITS["magnitude"]
    checks = [
        (c, ~np.isfinite(table.column(c)), "is not a finite number")
        for c in table.columns
        if c not in TEXT_COLUMNS and c not in EMPTY_ALLOWED
    ]
    checks += [
        (c, np.abs(table.column(c)) > limit, f"is too large (at most {limit:g} in size)")
        for c in table.columns
        if c not in TEXT_COLUMNS
    ]
    checks += [
        (
            "clearance",
            np.isinf(table.column("clearance")),
            "is not a finite number (empty when there are no obstacles)",
        ),
        ("frame", frame != np.arange(len(frame)), "is out of order (expected frames 0, 1, 2, ... one per row)"),
        (
            "goal",
            (goal != np.round(goal)) | (goal < 0) | (goal >= goals),
            f"is not a goal of the scene (expected 0 to {goals - 1})",
        ),
        ("time_s", table.column("time_s") < 0, "is negative (times count from 0 s)"),
        ("reached", (reached != 0) & (reached != 1), "is not 0 or 1"),
    ]
    with np.errstate(invalid="ignore"):
        for column, bad, message in checks:
            found = _first_bad(table, column, bad, message)
            if found is not None:
                return found
    return None


def _read_trajectory(csv_path: Path, problem: Problem) -> Trajectory:
    """A run's trajectory.csv as the :class:`Trajectory` it was written from (angles in radians;
    the self gaps are measured again from the angles)."""
    table = read_trajectory_csv(csv_path, max_rows=LIMITS["total_frames"])
    if table.n_joints != problem.arm.n:
        raise SceneError(
            str(csv_path), [Diagnostic("", f"has {table.n_joints} joints, the scene's arm has {problem.arm.n}")]
        )
    problem_found = drawable_problem(table, len(problem.goals))
    if problem_found is not None:
        raise SceneError(str(csv_path), [problem_found])
    clearance = table.column("clearance")
    frames = len(table.data)
    angle, quaternions = frame_orientations(
        problem.arm, [g.orientation for g in problem.goals], table.joints_si, table.column("goal").astype(int)
    )
    if "orientation_error_deg" in table.columns and angle is not None:
        angle = np.radians(table.column("orientation_error_deg"))
    if all(c in table.columns for c in ("qw", "qx", "qy", "qz")):
        quaternions = np.stack([table.column(c) for c in ("qw", "qx", "qy", "qz")], axis=1)
    along = [table.column(c) if c in table.columns else None for c in ("path_s", "path_error")]
    if not any(g.path is not None for g in problem.goals):
        along = [None, None]
    speeds = velocity_columns(problem.arm.n, problem.arm.prismatic)
    velocity = (
        joints_in_si(np.stack([table.column(c) for c in speeds], axis=1), problem.arm.prismatic)
        if all(c in table.columns for c in speeds)
        else None
    )  # a run from before the clock has none
    return Trajectory(
        phi=table.joints_si,
        tip=np.stack([table.column(c) for c in ("x", "y", "z")], axis=1),
        goal=table.column("goal").astype(int),
        distance=table.column("goal_distance"),
        clearance=np.where(np.isnan(clearance), np.inf, clearance),
        reached=table.column("reached") == 1,
        iterations=table.column("iterations").astype(int) if "iterations" in table.columns else np.zeros(frames, int),
        step_scale=table.column("step_scale") if "step_scale" in table.columns else np.ones(frames),
        fps=problem.fps,
        mode=table.text.get("mode"),
        orientation_error=angle,
        tool_quaternion=quaternions,
        velocity=velocity,
        path_s=along[0],
        path_error=along[1],
    )


def load_run(folder: str | Path) -> FinishedRun:
    """Read a run folder written by ``armanim run``.

    Raises
    ------
    SceneError
        A file is missing or does not fit the others (exit 2).
    """
    folder = Path(folder)
    if not folder.is_dir():
        raise SceneError(
            str(folder),
            [Diagnostic("", "no such folder (expected an output folder of armanim run, e.g. outputs/notes-arm)")],
        )
    missing = [
        name
        for name in (SCENE_COPY, "trajectory.csv", "summary.json")
        if not (folder / name).exists() and not (folder / name).is_symlink()
    ]  # a device there is named when read
    if missing:
        raise SceneError(
            str(folder),
            [Diagnostic("", f"is not a complete armanim run: {', '.join(missing)} missing (run armanim run first)")],
        )
    robot, srdf = folder / ROBOT_COPY, folder / SRDF_COPY
    scene = load_scene(
        folder / SCENE_COPY,
        urdf_file=robot if robot.exists() or robot.is_symlink() else None,
        srdf_file=srdf if srdf.exists() or srdf.is_symlink() else None,
    )
    summary = _read_summary(folder / "summary.json")
    recorded = (summary.get("scene") or {}).get("sha256") if isinstance(summary.get("scene"), dict) else None
    if recorded is not None and recorded != scene.sha256:
        raise SceneError(
            str(folder / SCENE_COPY),
            [
                Diagnostic(
                    "",
                    f"is not the scene this run solved (sha256 {scene.sha256[:12]}..., "
                    f"summary.json records {str(recorded)[:12]}...): run armanim run again",
                )
            ],
        )
    converted = convert_scene(scene.model, fps=_run_fps(summary, scene))
    problem = converted.problem
    traj = _read_trajectory(folder / "trajectory.csv", problem)
    reports = _reports(summary, folder / "summary.json")
    carry = replayed_carry(
        problem, traj.phi, traj.goal, [g.reached for g in reports]
    )  # a run that grasps: its worlds again
    traj = (
        with_self_clearance(problem, traj) if carry is None else with_world_self_clearance(problem, carry, traj)
    )  # the pictures tint near pairs
    totals = summary.get("totals")
    rest = totals.get("rest_to_rest_duration_s") if isinstance(totals, dict) else None  # a run with blend's
    return FinishedRun(
        scene=scene,
        problem=problem,
        solution=Solution(traj, reports, float(rest) if isinstance(rest, (int, float)) else None, carry),
        places=converted.places,
    )
