"""summary.json: per goal and totals, reproducible (no times, no absolute paths)."""

from __future__ import annotations

from dataclasses import asdict
from pathlib import Path

import numpy as np

from armanim import __version__
from armanim.motion.problem import Problem
from armanim.motion.solution import MISS_REASONS, GoalReport, PlanningReport, Solution, max_joint_step
from armanim.output.atomic import write_text_atomic
from armanim.output.jsontext import json_text


def _round(value: float) -> float | None:
    return float(value) if np.isfinite(value) else None


def min_limit_margin_deg(problem: Problem, phi: np.ndarray) -> float | None:
    """Smallest distance (degrees) of any limited joint to its limits over all frames."""
    limited = problem.limits.limited
    if not limited.any():
        return None
    gaps = np.minimum(phi[:, limited] - problem.limits.lower[limited], problem.limits.upper[limited] - phi[:, limited])
    return float(np.degrees(gaps.min()))


def goal_report_dict(g: GoalReport) -> dict:
    """One goal of summary.json (read back by :func:`goal_report_from_dict`)."""
    return {
        "index": g.index,
        "position": [float(v) for v in g.position],
        "reached": g.reached,
        "reason": g.reason,
        "reason_text": MISS_REASONS.get(g.reason) if g.reason else None,
        "frames": g.frames,
        "first_frame": g.first_frame,
        "last_frame": g.last_frame,
        "final_distance": float(g.final_distance),
        "final_orientation_error_deg": None if g.final_orientation_error is None else float(np.degrees(g.final_orientation_error)),
        "iterations": g.iterations,
        "newton_iterations": g.newton_iterations,
        "planned": g.planned,
        "planning": asdict(g.planning) if g.planning else None,
    }


def goal_report_from_dict(g: dict) -> GoalReport:
    """The GoalReport of one goal of summary.json; KeyError, TypeError or ValueError if it is not one."""
    return GoalReport(
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
        final_orientation_error=None if g.get("final_orientation_error_deg") is None else float(np.radians(g["final_orientation_error_deg"])),
    )


def summary_dict(problem: Problem, solution: Solution, *, name: str, scene_file: str, sha256: str) -> dict:
    """The summary as plain data (see docs/outputs in the README)."""
    traj = solution.trajectory
    goals = [goal_report_dict(g) for g in solution.goals]
    return {
        "armanim_version": __version__,
        "scene": {"name": name, "file": scene_file, "sha256": sha256},
        "joints": list(problem.arm.joint_names) or None,  # a URDF arm's joints, phi1 first; None for an arm of links
        "method": problem.solver.method,
        "planner": problem.solver.planner,
        "clearance": problem.solver.clearance,
        "fps": problem.fps,
        "totals": {
            "goals": len(goals),
            "reached": solution.reached,
            "missed": len(goals) - solution.reached,
            "frames": traj.frames,
            "duration_s": traj.frames / traj.fps,
            "iterations": int(traj.iterations.sum()),
            "planned_goals": sum(g.planned for g in solution.goals),
            "plan_frames": int(np.count_nonzero(traj.mode == "plan")),
        },
        "min_clearance": _round(traj.clearance.min()) if traj.frames else None,
        "min_limit_margin_deg": min_limit_margin_deg(problem, traj.phi),
        "max_joint_step_deg": float(np.degrees(max_joint_step(traj.phi))),
        "goals": goals,
    }


def write_summary(summary: dict, path: Path) -> None:
    """Write summary.json atomically (sorted keys stay in the order above; 2-space indent)."""
    write_text_atomic(path, json_text(summary, indent=2) + "\n")
