"""summary.json: per goal and totals, reproducible (no times, no absolute paths)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import asdict
from pathlib import Path

import numpy as np

from armanim import __version__
from armanim.arm.geometry import wrap_angle
from armanim.arm.kinematics import joints_shown
from armanim.motion.problem import Problem
from armanim.motion.solution import (
    BLEND_REASONS,
    MISS_REASONS,
    BlendReport,
    GoalReport,
    GoalTiming,
    KindPass,
    PathReport,
    PlanningReport,
    Solution,
    max_joint_step,
)
from armanim.output.atomic import write_text_atomic
from armanim.output.jsontext import json_text
from armanim.output.solved import SolvedRun


def _round(value: float) -> float | None:
    return float(value) if np.isfinite(value) else None


def min_limit_margin_deg(problem: Problem, phi: np.ndarray, slides: bool = False) -> float | None:
    """Smallest distance (degrees) of any limited revolute joint to its limits over all frames
    (``slides``: of any prismatic joint, metres)."""
    limited = problem.limits.limited & (problem.arm.slides == slides)
    if not limited.any():
        return None
    gaps = np.minimum(phi[:, limited] - problem.limits.lower[limited], problem.limits.upper[limited] - phi[:, limited])
    return float(gaps.min()) if slides else float(np.degrees(gaps.min()))


def prismatic_summary(problem: Problem, phi: np.ndarray) -> dict:
    """An arm with prismatic joints: which they are (1-based; their entries of the rate lists are in
    m/s and m/s^2), their least margin to a limit and largest step a frame, metres. {} otherwise."""
    slides = problem.arm.slides
    if not slides.any():
        return {}
    steps = np.abs(np.diff(phi[:, slides], axis=0))
    return {
        "prismatic_joints": [int(i) + 1 for i in np.nonzero(slides)[0]],
        "min_limit_margin_m": min_limit_margin_deg(problem, phi, slides=True),
        "max_slide_step_m": float(steps.max()) if len(steps) else 0.0,
    }


def goal_path_lengths(solution: Solution, limited: np.ndarray | None = None) -> list[float]:
    """Each goal's joint-space path length, radians: the sum of |phi_{i+1} - phi_i| (the Euclidean
    norm over the joints, as MotionBenchMaker's and VAMP's path costs) over the steps that end in
    the goal's frames (from the frame before its first one; holds add nothing). Joints not
    ``limited`` (n,) bool are measured the short way round (their frames wrap at 180 degrees).

    >>> from types import SimpleNamespace
    >>> traj = SimpleNamespace(phi=np.array([[0.0, 0.0], [3.0, 4.0], [3.0, 4.0], [3.0, 5.0]]), goal=np.array([0, 0, 1, 1]))
    >>> goal_path_lengths(SimpleNamespace(trajectory=traj, goals=[None, None]))
    [5.0, 1.0]
    """
    traj = solution.trajectory
    diff = np.diff(traj.phi, axis=0)
    if limited is not None:
        diff = np.where(limited, diff, wrap_angle(diff))
    steps = np.concatenate([[0.0], np.linalg.norm(diff, axis=1)])
    return [float(steps[traj.goal == k].sum()) for k in range(len(solution.goals))]


def goal_report_dict(g: GoalReport, joint_names: Sequence[str] = ()) -> dict:
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
        "final_orientation_error_deg": None
        if g.final_orientation_error is None
        else float(np.degrees(g.final_orientation_error)),
        "iterations": g.iterations,
        "newton_iterations": g.newton_iterations,
        "planned": g.planned,
        "planning": asdict(g.planning) if g.planning else None,
        **timing_dict(g.timing, joint_names),
        **path_dict(g.path),
        **blend_dict(g.blend),
    }


def blend_dict(blend: BlendReport | None) -> dict:
    """A goal with ``blend``'s fields of summary.json (read back by :func:`blend_from_dict`): its
    radius, whether it was passed without stopping and why not, the corner (``curve`` or
    ``through``), and how near and how fast it was passed (the tool's scene units and per second; a
    joint goal's in degrees: its largest joint offset and its fastest joint; on an arm with a
    prismatic joint, the revolute joints' in degrees and the prismatic joints' in metres, apart, with
    the radius a rail is held to in metres); nothing for a goal without."""
    if blend is None:
        return {}
    unit = float(np.degrees(1.0)) if blend.joint else 1.0
    kinds = blend.by_kind
    out = {
        "blend": blend.radius * unit,
        "blend_units": "deg" if blend.joint else "scene",
        "blended": blend.blended,
        "blend_reason": blend.reason,
        "blend_reason_text": BLEND_REASONS.get(blend.reason) if blend.reason else None,
        "corner": blend.corner,
        "pass_distance": _round((blend.pass_distance if kinds is None else kinds.turn_distance) * unit),
        "pass_speed": (blend.pass_speed if kinds is None else kinds.turn_speed) * unit,
    }
    if kinds is not None:  # each joint in its own unit: the rail's metres are never written as degrees
        out |= {
            "blend_m": blend.radius,
            "pass_distance_m": _round(kinds.slide_distance),
            "pass_speed_m_s": kinds.slide_speed,
        }
    return out


def blend_from_dict(g: dict) -> BlendReport | None:
    """The BlendReport of one goal of summary.json (None for a goal without ``blend``)."""
    if "blended" not in g:
        return None
    joint = g["blend_units"] == "deg"
    per = (
        float(np.degrees(1.0)) if joint else 1.0
    )  # divided by the factor blend_dict multiplied by: written again, the same digits
    near = np.nan if g["pass_distance"] is None else float(g["pass_distance"]) / per
    speed = float(g["pass_speed"]) / per
    kinds = None
    if "pass_distance_m" in g:  # a joint goal on an arm with a prismatic joint: the kinds apart
        slide_near = np.nan if g["pass_distance_m"] is None else float(g["pass_distance_m"])
        kinds = KindPass(near, speed, slide_near, float(g["pass_speed_m_s"]))
        near, speed = max(near, slide_near), max(speed, kinds.slide_speed)
    return BlendReport(
        float(g["blend"]) / per, bool(g["blended"]), g["blend_reason"], g["corner"], near, speed, joint, kinds
    )


def path_dict(path: PathReport | None) -> dict:
    """A path goal's ``path`` field of summary.json (read back by :func:`path_from_dict`); nothing
    for a point goal."""
    if path is None:
        return {}
    return {
        "path": {
            "length": path.length,
            "done": path.done,
            "fraction": path.fraction,
            "max_path_error": _round(path.max_path_error),
            "mean_speed": path.mean_speed,
            "stop_point": None if path.stop_point is None else [float(v) for v in path.stop_point],
            "cause": path.cause,
            "cause_text": path.cause_text,
        }
    }


def path_from_dict(g: dict) -> PathReport | None:
    """The PathReport of one goal of summary.json (None for a point goal)."""
    p = g.get("path")
    if p is None:
        return None
    error = p["max_path_error"]
    return PathReport(
        float(p["length"]),
        float(p["done"]),
        np.nan if error is None else float(error),
        float(p["mean_speed"]),
        None if p["stop_point"] is None else np.array(p["stop_point"], dtype=float),
        p["cause"],
    )


def timing_dict(timing: GoalTiming | None, joint_names: Sequence[str] = ()) -> dict:
    """A goal's clock fields of summary.json: ``duration_s``, ``peak_speed_ratio`` and
    ``peak_acceleration_ratio`` (each <= 1) with the joints that reach them (empty before the clock)."""
    if timing is None:
        return {}

    def name(j: int | None) -> str | None:
        return None if j is None else joint_label(joint_names, j)

    return {
        "duration_s": timing.duration,
        "peak_speed_ratio": timing.peak_speed_ratio,
        "peak_speed_joint": name(timing.speed_joint),
        "peak_acceleration_ratio": timing.peak_acceleration_ratio,
        "peak_acceleration_joint": name(timing.acceleration_joint),
    }


def timing_from_dict(g: dict, joint_names: Sequence[str] = ()) -> GoalTiming | None:
    """The GoalTiming of one goal of summary.json (None for a run from before the clock)."""
    if "duration_s" not in g:
        return None

    def index(name: str | None) -> int | None:
        if name is None or name in joint_names:
            return None if name is None else list(joint_names).index(name)
        return int(str(name).removeprefix("phi")) - 1  # ValueError: not a joint's name

    return GoalTiming(
        float(g["duration_s"]),
        float(g["peak_speed_ratio"]),
        float(g["peak_acceleration_ratio"]),
        index(g["peak_speed_joint"]),
        index(g["peak_acceleration_joint"]),
    )


def goal_report_from_dict(g: dict, joint_names: Sequence[str] = ()) -> GoalReport:
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
        final_orientation_error=None
        if g.get("final_orientation_error_deg") is None
        else float(np.radians(g["final_orientation_error_deg"])),
        timing=timing_from_dict(g, joint_names),
        path=path_from_dict(g),
        blend=blend_from_dict(g),
    )


def joint_label(joint_names: Sequence[str], j: int) -> str:
    """Joint ``j``'s (0-based) name in summary.json: the URDF's, or ``phi{j+1}`` for an arm of links.

    >>> joint_label((), 0), joint_label(("shoulder", "elbow"), 1)
    ('phi1', 'elbow')
    """
    return joint_names[j] if j < len(joint_names) else f"phi{j + 1}"


def joint_labels(problem: Problem) -> list[str]:
    """Every joint's :func:`joint_label`."""
    return [joint_label(problem.arm.joint_names, j) for j in range(problem.arm.n)]


def self_collision_summary(problem: Problem, traj) -> dict:
    """summary.json's self-collision keys: the least gap of an enabled pair over the frames, that
    pair, and the allowed-collision matrix's size (None where no pair is enabled)."""
    pairs = problem.self_pairs
    least = None
    if traj.self_clearance is not None and traj.frames:
        k = int(np.argmin(traj.self_clearance))
        least = (float(traj.self_clearance[k]), str(traj.self_pair[k]))
    return {
        "min_self_clearance": least[0] if least else None,
        "min_self_pair": least[1] if least else None,
        "self_collision": {
            "mode": pairs.mode,
            "self_clearance": pairs.clearance if pairs.mode != "off" else None,
            "enabled_pairs": len(set(pairs.names)),
            "allowed_pairs": len(pairs.allowed),
        },
    }


def nearest_obstacle(problem: Problem, traj, carry=None) -> str | None:
    """The obstacle of ``min_clearance``: at the frame of the least clearance, the one a link is
    nearest (its scene ``name``, else ``obstacles[k]``, or ``floor``), in that frame's world for a
    run that carries objects (``carry``); None without obstacles or frames."""
    if not traj.frames or not np.isfinite(traj.clearance).any():
        return None
    from armanim.arm.kinematics import forward
    from armanim.world.distances import clearances
    from armanim.world.obstacles import FLOOR

    frame = int(np.argmin(traj.clearance))
    scene_column = None
    if carry is not None:
        from armanim.motion.carry import frame_worlds, world_columns

        scene_column = world_columns(problem, carry.worlds[int(traj.goal[frame])])
        names = problem.obstacles
        problem = next(
            p for p, mine in frame_worlds(problem, carry, traj.goal, traj.fps) if mine[frame]
        )  # the fingers there
    if not len(problem.obstacles):
        return None
    links = clearances(forward(problem.arm, traj.phi[frame]), problem.obstacles, problem.capsules).links
    column = int(np.argmin(links.min(axis=0)))
    if problem.obstacles.kinds[column] == FLOOR:
        return "floor"
    if scene_column is not None:  # the world's columns leave out what it moved: the scene's own
        column = scene_column[column]
        return names.name(column) or f"obstacles[{column}]"
    return problem.obstacles.name(column) or f"obstacles[{column}]"


def retreat_of(problem: Problem, k: int) -> int | None:
    """The scene goal whose retreat problem goal ``k`` is (None: a scene goal itself).

    >>> from types import SimpleNamespace
    >>> p = SimpleNamespace(goals=[SimpleNamespace(retreat=r, to_approach=False) for r in (False, True, False, True)])
    >>> [retreat_of(p, k) for k in range(4)]
    [None, 0, None, 1]
    """
    if not problem.goals[k].retreat:
        return None
    return sum(1 for g in problem.goals[:k] if not g.retreat and not g.to_approach) - 1


def to_approach_of(problem: Problem, k: int) -> int | None:
    """The scene goal (a release with an ``approach``) to whose line's start problem goal ``k``
    goes (None: a scene goal itself, or a retreat).

    >>> from types import SimpleNamespace
    >>> p = SimpleNamespace(goals=[SimpleNamespace(retreat=r, to_approach=a) for r, a in ((0, 0), (0, 1), (0, 0), (1, 0))])
    >>> [to_approach_of(p, k) for k in range(4)]
    [None, 1, None, None]
    """
    if not problem.goals[k].to_approach:
        return None
    return sum(1 for g in problem.goals[:k] if not g.retreat and not g.to_approach)


def summary_dict(
    problem: Problem, solution: Solution, *, name: str, scene_file: str, sha256: str, rate_notes: Sequence[str] = ()
) -> dict:
    """The summary as plain data (see docs/outputs in the README); ``rate_notes``: the scene's
    joint rate limits above the robot's own (:func:`armanim.scene.limits.rate_note_lines`)."""
    traj = solution.trajectory
    lengths = goal_path_lengths(solution, problem.limits.limited)
    goals = [
        {**goal_report_dict(g, joint_labels(problem)), "path_length_rad": lengths[k]}
        for k, g in enumerate(solution.goals)
    ]
    if any(g.retreat for g in problem.goals):  # a scene's retreats are goals of their own: each says whose it is
        for k, g in enumerate(goals):
            g["retreat_of"] = retreat_of(problem, k)
    if any(g.to_approach for g in problem.goals):  # and so are the ways to a release's approach
        for k, g in enumerate(goals):
            g["to_approach_of"] = to_approach_of(problem, k)
    rates = problem.rates
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
            **(
                {}
                if solution.rest_to_rest_duration is None
                else {"rest_to_rest_duration_s": solution.rest_to_rest_duration}
            ),
            "iterations": int(traj.iterations.sum()),
            "planned_goals": sum(g.planned for g in solution.goals),
            "plan_frames": int(np.count_nonzero(traj.mode == "plan")),
        },
        "min_clearance": _round(traj.clearance.min()) if traj.frames else None,
        "min_clearance_obstacle": nearest_obstacle(problem, traj, solution.carry),
        **self_collision_summary(problem, traj),
        "min_limit_margin_deg": min_limit_margin_deg(problem, traj.phi),
        "max_joint_step_deg": float(np.degrees(max_joint_step(traj.phi[:, ~problem.arm.slides]))),
        "max_joint_speed_deg_s": [float(v) for v in joints_shown(rates.speed, problem.arm.prismatic)],
        "max_joint_acceleration_deg_s2": [float(v) for v in joints_shown(rates.acceleration, problem.arm.prismatic)],
        **prismatic_summary(problem, traj.phi),
        "goals": goals,
        "rate_notes": list(rate_notes),
        **carry_summary(problem, solution, goals),
    }


def carry_summary(problem: Problem, solution: Solution, goals: list[dict]) -> dict:
    """With goals that grasp or release: each goal's ``grasped`` and ``released`` (in ``goals``),
    the run's ``min_carried_clearance``, each moved object's final pose and, where an object
    touched what it stands on, ``min_support_distance`` (its solid's least signed distance to it
    in those frames); nothing without."""
    carry = solution.carry
    if carry is None:
        return {}
    from armanim.arm.rotations import rotation_quaternion
    from armanim.motion.carry import carried_clearance, final_poses, has_support, support_distance

    for k, g in enumerate(goals):
        g["grasped"], g["released"] = carry.grasped(k), carry.released(k)
    traj = solution.trajectory
    carried = carried_clearance(problem, carry, traj.phi, traj.goal)
    objects = {
        name: None
        if body is None
        else {
            "center": [float(v) for v in body.center],
            "quaternion_wxyz": [float(v) for v in rotation_quaternion(body.rotation)],
        }
        for name, body in final_poses(problem, carry).items()
    }
    out = {
        "min_carried_clearance": _round(np.nanmin(carried)) if np.isfinite(carried).any() else None,
        "objects": objects,
    }
    if has_support(carry):  # an object touched what it stands on: its solid's least distance to it there
        out["min_support_distance"] = _round(np.nanmin(support_distance(problem, carry, traj.phi, traj.goal)))
    return out


def run_summary(run: SolvedRun) -> dict:
    """The summary of a solved run as plain data (:func:`summary_dict`)."""
    return summary_dict(
        run.problem,
        run.solution,
        name=run.name,
        scene_file=run.scene_file,
        sha256=run.sha256,
        rate_notes=run.rate_notes,
    )


def write_summary(run: SolvedRun, path: Path) -> None:
    """Write the run's summary.json atomically (keys in the order above; 2-space indent; it has
    no options)."""
    write_text_atomic(path, json_text(run_summary(run), indent=2) + "\n")
