"""Judging the frame loop's progress toward a goal: when it has stalled, and why a goal was missed.

A goal has stalled when half a second of frames brought the tip closer by less than the
tolerance (or than a small fraction of the distance still to go): ``problem.tunables.stalls``
(:class:`~armanim.motion.tunables.StallOptions`). The frame loop
(:mod:`armanim.motion.trajectory`) then plans or gives up; :func:`miss_reason` names what kept
the arm from the goal. Pure core: no I/O.
"""

from __future__ import annotations

from typing import cast

import numpy as np

from armanim.motion.cost import self_influence
from armanim.motion.orientation import Orientation, holds_orientation
from armanim.motion.problem import Problem, frames_in
from armanim.motion.solvers import ArmState
from armanim.motion.tunables import DEFAULTS
from armanim.names import Blocker, MissReason


def stall_frames(problem: Problem) -> int:
    """Frames over which progress is judged: the stall options' ``seconds`` (half a second), at
    least their ``min_frames``."""
    stalls = problem.tunables.stalls
    return max(stalls.min_frames, frames_in(stalls.seconds, problem.fps))


def has_stalled(
    distances: list[float],
    window: int,
    tolerance: float,
    floor: float = 0.0,
    progress: float = DEFAULTS.stalls.progress,
) -> bool:
    """Whether the last ``window`` frames brought the tip closer by less than the tolerance,
    or than ``progress`` (``problem.tunables.stalls.progress``) of what is left above ``floor``
    (the least distance possible; +inf judges by the tolerance alone), whichever is larger.

    >>> has_stalled([5.0, 4.0, 3.0], 2, 0.01), has_stalled([5.0, 5.0, 5.0], 2, 0.01)
    (False, True)
    """
    if len(distances) <= window:
        return False
    now = distances[-1]
    return distances[-window - 1] - now < max(tolerance, progress * max(now - floor, 0.0))


def pose_stalled(
    distances: list[float],
    angles: list[float | None],
    window: int,
    tolerance: float,
    angle_tolerance: float,
    floor: float = 0.0,
    progress: float = DEFAULTS.stalls.progress,
) -> bool:
    """:func:`has_stalled` for a goal that may have an orientation: the tip's distance has stalled
    and so has the angle (in lengths: ``angle_tolerance`` counts as ``tolerance``), so that an
    orientation the arm cannot improve does not cut short a tip still on its way. A position-only
    goal (``angles`` None) is judged on its distances alone, as :func:`has_stalled`.

    >>> pose_stalled([5.0, 4.0, 3.0], [1.0, 1.0, 1.0], 2, 0.01, 0.01), pose_stalled([5.0, 5.0, 5.0], [1.0, 1.0, 1.0], 2, 0.01, 0.01)
    (False, True)
    """
    if not angles or angles[-1] is None:
        return has_stalled(distances, window, tolerance, floor, progress)
    scaled = [cast(float, a) * (tolerance / angle_tolerance) for a in angles]  # a goal's angles: all None or none
    return has_stalled(distances, window, tolerance, floor, progress) and has_stalled(
        scaled, window, tolerance, 0.0 if np.isfinite(floor) else floor, progress
    )


def beyond_reach(problem: Problem, goal: np.ndarray) -> bool:
    """Whether ``goal`` is farther from the base than the arm is long (its reach)."""
    return bool(np.linalg.norm(goal - problem.arm.base) > problem.arm.reach + problem.solver.tolerance)


def miss_reason(
    problem: Problem, state: ArmState, goal: np.ndarray, distances: list[float], blocked: list[Blocker | None]
) -> MissReason:
    """Why the local method missed a goal (explained by :data:`armanim.motion.solution.MISS_REASONS`).

    Judged in order: out of reach; NaN proposals; then, if the last stall window
    made less progress than the tolerance, an obstacle or a limit that changed those
    steps or whose barrier is active, else a local minimum; otherwise the arm was
    still moving when ``max_frames_per_goal`` ran out.
    """
    if beyond_reach(problem, goal):
        return "out_of_reach"
    window = stall_frames(problem)
    recent = blocked[-window:]
    if recent and recent.count("nan") > len(recent) // 2:
        return "numerical"
    if not has_stalled(
        distances, min(window, len(distances) - 1), problem.solver.tolerance, progress=problem.tunables.stalls.progress
    ):
        return "too_slow"
    if "obstacle" in recent or _near_obstacle(problem, state):
        return "blocked_by_obstacle"
    if "limit" in recent or _near_limit(problem, state.phi):
        return "blocked_by_limit"
    return "stalled"


def orientation_unreachable(
    problem: Problem, orientation: Orientation | None, distance: float, angle: float | None
) -> bool:
    """Whether a goal is missed for its orientation alone on an arm that cannot hold it: the
    tip within the tolerance, the angle not, and too few joints for the orientation
    (:func:`armanim.motion.orientation.holds_orientation`). (The planner also finds it so, from
    many starts, for arms that have the joints.)"""
    if orientation is None or angle is None:
        return False
    s = problem.solver
    return (
        distance < s.tolerance and angle >= s.orientation_tolerance and not holds_orientation(problem.arm, orientation)
    )


def _near_obstacle(problem: Problem, state: ArmState) -> bool:
    """Whether a part is within an obstacle's influence, or an enabled pair of the arm's own
    parts within theirs (the arm blocked by itself counts as blocked by an obstacle)."""
    cl = state.clearance
    if cl is not None and bool(np.any((cl.d <= problem.obstacles.influence) & problem.capsules.moving[:, None])):
        return True
    return state.self_gaps is not None and bool(np.any(state.self_gaps.d <= self_influence(problem)))


def _near_limit(problem: Problem, phi: np.ndarray) -> bool:
    lim = problem.limits
    gaps = np.minimum(phi - lim.lower, lim.upper - phi)
    return bool(np.any(gaps < lim.margin))
