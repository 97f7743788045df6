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

import numpy as np

from armanim.motion.orientation import Orientation
from armanim.motion.planning.follow import damper_paced, path_schedule, poses_along
from armanim.motion.planning.path import Searched, plan_path
from armanim.motion.planning.poses import goal_poses
from armanim.motion.problem import Problem
from armanim.names import MissReason, PathSource


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
    problem: Problem, phi_now: np.ndarray, goal: np.ndarray, seed: int = 0, orientation: Orientation | None = None,
    searched: Searched | None = None, frames_left: int | None = None,
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


__all__ = ["Plan", "plan_motion"]
