"""Read a finished run back (scene.yaml, trajectory.csv, summary.json) for re-rendering."""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from armanim.errors import Diagnostic, SceneError
from armanim.output.csvfile import MODES, read_trajectory_csv
from armanim.problem import Problem
from armanim.scene import LoadedScene, load_scene, scene_to_problem
from armanim.trajectory import GoalReport, PlanningReport, Solution, Trajectory

SCENE_COPY = "scene.yaml"


@dataclass(frozen=True)
class FinishedRun:
    """A run read back from its folder."""

    scene: LoadedScene
    problem: Problem
    solution: Solution


def _read_summary(summary_path: Path) -> dict:
    try:
        summary = json.loads(summary_path.read_text(encoding="utf-8"))
        if not isinstance(summary, dict) or not isinstance(summary.get("goals"), list):
            raise ValueError("no list of goals")
        return summary
    except FileNotFoundError:
        raise SceneError(str(summary_path), [Diagnostic("", "no such file (expected the summary.json of an armanim run)")]) from None
    except (OSError, ValueError) as exc:
        raise SceneError(str(summary_path), [Diagnostic("", f"is not an armanim summary: {exc}")]) from None


def _reports(summary: dict, summary_path: Path) -> tuple[GoalReport, ...]:
    try:
        return tuple(
            GoalReport(
                index=g["index"],
                position=np.array(g["position"], dtype=float),
                reached=g["reached"],
                reason=g["reason"],
                frames=g["frames"],
                first_frame=g["first_frame"],
                last_frame=g["last_frame"],
                final_distance=g["final_distance"],
                iterations=g["iterations"],
                newton_iterations=g.get("newton_iterations", 0),
                planning=PlanningReport(**g["planning"]) if g.get("planning") else None,
            )
            for g in summary["goals"]
        )
    except (ValueError, KeyError, TypeError) as exc:
        raise SceneError(str(summary_path), [Diagnostic("", f"is not an armanim summary: {exc}")]) from None


def _run_fps(summary: dict, scene: LoadedScene) -> float:
    """The fps the run was solved at (``run --fps`` may differ from the scene's)."""
    fps = summary.get("fps")
    return float(fps) if isinstance(fps, (int, float)) and not isinstance(fps, bool) and 0 < fps <= 240 else scene.model.render.fps


def load_run(folder: str | Path) -> FinishedRun:
    """Read a run folder written by ``armanim run``.

    Raises
    ------
    SceneError
        A file is missing or does not fit the others (exit 2).
    """
    folder = Path(folder)
    if not folder.is_dir():
        raise SceneError(str(folder), [Diagnostic("", "no such folder (expected an output folder of armanim run, e.g. outputs/notes-arm)")])
    missing = [name for name in (SCENE_COPY, "trajectory.csv", "summary.json") if not (folder / name).is_file()]
    if missing:
        raise SceneError(str(folder), [Diagnostic("", f"is not a complete armanim run: {', '.join(missing)} missing (run armanim run first)")])
    scene = load_scene(folder / SCENE_COPY)
    summary = _read_summary(folder / "summary.json")
    problem = scene_to_problem(scene.model, fps=_run_fps(summary, scene))
    table = read_trajectory_csv(folder / "trajectory.csv")
    if table.n_joints != problem.arm.n:
        raise SceneError(str(folder / "trajectory.csv"), [Diagnostic("", f"has {table.n_joints} joints, the scene's arm has {problem.arm.n}")])
    clearance = table.column("clearance")
    traj = Trajectory(
        phi=np.radians(table.angles_deg),
        tip=np.stack([table.column(c) for c in ("x", "y", "z")], axis=1),
        goal=table.column("goal").astype(int),
        distance=table.column("goal_distance"),
        clearance=np.where(np.isnan(clearance), np.inf, clearance),
        reached=table.column("reached") == 1,
        iterations=table.column("iterations").astype(int),
        step_scale=table.column("step_scale"),
        fps=problem.fps,
        mode=np.array(MODES)[table.column("mode").astype(int)] if "mode" in table.columns else None,
    )
    return FinishedRun(scene=scene, problem=problem, solution=Solution(traj, _reports(summary, folder / "summary.json")))
