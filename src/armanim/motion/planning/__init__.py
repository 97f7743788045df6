"""The planner the frame loop calls when a local method stalls (``solver.planner: auto``).

1. goal poses: many IK solves from deterministic seeds (:mod:`.poses`), kept when
   inside the limits and at least the planning floor (what the safety filter keeps) from
   every obstacle, the roomy ones first;
2. a path to them, keeping that margin: the straight joint-space segment, or OMPL's
   RRT-Connect and its simplification (:mod:`.path`);
3. frames along it, no joint above ``max_joint_step`` per frame, smooth start and stop,
   and slower where the safety filter's damper would bend the path (:mod:`.follow`).

Pure core: numpy and OMPL, no files, no printing.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from armanim.motion.orientation import Orientation
from armanim.motion.planning.follow import damper_paced, path_lengths, path_schedule, poses_along
from armanim.motion.planning.path import Searched, plan_path, search_path
from armanim.motion.planning.poses import goal_poses
from armanim.motion.problem import Problem
from armanim.names import MissReason, PathSource

if TYPE_CHECKING:
    from armanim.motion.planning.check import CompiledCheck


@dataclass(frozen=True)
class Plan:
    """Result of :func:`plan_motion`.

    Attributes
    ----------
    frames : (F, n) array or None
        Poses to follow, one per frame; None when there is no plan.
    reason : MissReason or None
        Why there is none: ``"out_of_reach"``, ``"orientation_unreachable"`` (the position is
        reachable, the orientation there is not), ``"no_free_pose"`` or ``"no_path"``.
    poses : int
        Free goal poses found.
    source : PathSource
        ``"straight"``, ``"rrt_connect"`` or ``"none"``.
    checks : int
        Poses checked for collisions while searching a path.
    self_pair : str or None
        For ``no_free_pose``: the arm's own pair (``a|b``) that kept the goal's poses out, if one did.
    """

    frames: np.ndarray | None
    reason: MissReason | None
    poses: int
    source: PathSource
    checks: int
    self_pair: str | None = None


def plan_motion(
    problem: Problem,
    phi_now: np.ndarray,
    goal: np.ndarray,
    seed: int = 0,
    orientation: Orientation | None = None,
    searched: Searched | None = None,
    frames_left: int | None = None,
) -> Plan:
    """Plan from the pose ``phi_now`` to a free pose whose tip is at ``goal`` (and whose tool
    meets ``orientation``, when the goal has one).

    Parameters
    ----------
    problem : Problem
    phi_now : (n,) array
        The current pose, radians.
    goal : (3,) array
    seed : int
        Seed of the IK starts (the frame loop passes the goal's index and attempt).
    orientation : Orientation, optional
    searched : callable, optional
        ``searched(done, most)``: the path search's iterations, as it goes
        (:data:`armanim.motion.planning.path.Searched`).
    frames_left : int, optional
        Frames the goal may still take; default ``solver.max_frames_per_goal``. A path that
        needs more is followed as far as they go (nothing its length would take is allocated).

    Returns
    -------
    Plan
    """
    found = goal_poses(problem, phi_now, goal, seed, orientation)
    if not found.reachable:
        return Plan(None, "out_of_reach", 0, "none", 0)
    if not found.orientable:
        return Plan(None, "orientation_unreachable", 0, "none", 0)
    if not len(found.poses):
        return Plan(None, "no_free_pose", 0, "none", 0, found.self_pair)
    path = plan_path(problem, phi_now, found.poses, searched)
    if path.waypoints is None:
        return Plan(None, "no_path", len(found.poses), path.source, path.checks)
    most = problem.solver.max_frames_per_goal if frames_left is None else frames_left
    schedule = path_schedule(path.waypoints, problem.solver.max_joint_step, most)  # at most the frames left
    frames = poses_along(path.waypoints, damper_paced(problem, path.waypoints, schedule, most))
    return Plan(frames, None, len(found.poses), path.source, path.checks)


def plan_joint_motion(
    problem: Problem, phi_now: np.ndarray, goal: np.ndarray, searched: Searched | None = None
) -> Plan:
    """Plan from the pose ``phi_now`` to the joint goal ``goal`` (both (n,), radians), ending on it exactly.

    The straight joint-space segment if the compiled certificate
    (:class:`~armanim.motion.planning.check.CompiledCheck`, :func:`~.path.motion_is_free`'s proof)
    takes it, else OMPL's RRT-Connect, shortened by vertex reduction and rope shortcuts and smoothed by a
    pass of B-spline corner cutting, every
    piece certified by the same proof: every pose keeps ``solver.clearance`` from the obstacles and
    the enabled pairs ``solver.self_clearance`` apart, and every joint within its limits, their
    ends included (a start or goal may rest on a limit), certified at :func:`joint_path_floor`.
    With ``solver.planner: off`` only the straight segment is tried. The frames follow
    :func:`joint_path_frames` (no joint above ``max_joint_step`` a frame, every waypoint a frame,
    at most ``max_frames_per_goal``); the last one is ``goal`` itself when they reach it.

    Returns
    -------
    Plan
        ``source`` ``"straight"`` or ``"rrt_connect"``; ``reason`` ``"no_path"`` without one.
    """
    from armanim.motion.planning.check import CompiledCheck  # numba: imported where a joint goal plans

    check = CompiledCheck.of(problem, closed=True)
    floor = joint_path_floor(problem, min(check.pose_clearance(phi_now), check.pose_clearance(goal)))
    source: PathSource
    if problem.solver.planner == "off":
        free, checks = check.motion_free(phi_now, goal, floor)
        waypoints, source = (np.stack([phi_now, goal]), "straight") if free else (None, "none")
    else:
        waypoints, source, checks = joint_goal_search(problem, phi_now, goal[None], floor, searched, check)
    if waypoints is None:
        return Plan(None, "no_path", 1, source, checks)
    frames = np.clip(
        joint_path_frames(waypoints, problem.solver.max_joint_step, problem.solver.max_frames_per_goal),
        problem.limits.lower,
        problem.limits.upper,
    )  # a + u (b - a) toward a limit may round an ulp past it
    if len(frames) and np.array_equal(frames[-1], waypoints[-1]):
        frames[-1] = goal  # the waypoint is the goal (OMPL's copy of it may round)
    return Plan(frames, None, 1, source, checks)


def joint_path_frames(waypoints: np.ndarray, max_joint_step: float, most: int) -> np.ndarray:
    """(F, n) frames along ``waypoints`` (k, n): :func:`~.follow.path_schedule`'s, and every
    waypoint itself, so that the chord between two frames lies on one straight piece of the
    certified path (never across a corner); at most ``most`` frames.

    >>> joint_path_frames(np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]]), 0.5, 100)[[2, 3, -1]].tolist()
    [[1.0, 0.0], [1.0, 0.4814814814814814], [1.0, 1.0]]
    """
    at = path_lengths(waypoints)
    s = np.union1d(path_schedule(waypoints, max_joint_step, most), at[1:])[:most]
    frames = poses_along(waypoints, s)
    corners = np.searchsorted(s, at[1:])  # each waypoint exactly, not a + (b - a) rounded
    kept = corners < len(s)
    frames[corners[kept]] = waypoints[1:][kept]
    return frames


def joint_path_floor(problem: Problem, ends: float) -> float:
    """The floor a path between two poses is certified at: ``solver.clearance`` raised by what the
    certification may miss (half its ``certify_to`` clearances, :func:`~.path.motion_is_free`),
    so that every pose between the solved frames keeps ``solver.clearance`` and the clock never
    has to leave the path; no more than ``ends``, the two poses' own least clearance
    (:func:`~armanim.motion.filter.clearance.pose_clearance`), allows."""
    d_safe = problem.solver.clearance
    return float(max(d_safe, min(d_safe * (1 + problem.tunables.planner.certify_to / 2), ends)))


def joint_goal_search(
    problem: Problem,
    start: np.ndarray,
    goals: np.ndarray,
    floor: float,
    searched: Searched | None,
    check: CompiledCheck,
) -> tuple[np.ndarray | None, PathSource, int]:
    """:func:`~.path.search_path` by the compiled ``check`` (its limits closed), telling ``searched``
    its iterations."""
    most = problem.tunables.planner.plan_iterations
    tick = (lambda done: searched(done, most)) if searched is not None else None
    found = search_path(problem, start, goals, floor, tick, check=check, thorough=False)
    if searched is not None and found[1] != "straight":
        searched(most, most)
    return found


__all__ = ["Plan", "plan_joint_motion", "plan_motion"]
