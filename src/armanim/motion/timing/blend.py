"""Goals the arm passes without stopping: which may, and how near a frame passes each.

A goal with a ``blend`` radius (:attr:`armanim.motion.problem.Goal.blend`) that is reached, has no
``hold``, is not the last and is followed by a goal that moves the arm (a path goal: to its
path's start, which the arm reaches at rest) is a *via* goal: its
solved path and the next goal's become one path, which the clock times as one
(:func:`armanim.motion.timing.retime.retime`), its speed at the via free. Every other goal ends at
rest, as without ``blend``; :func:`blend_reason` says why.

That path is made short and smooth (:mod:`armanim.motion.timing.smoothing`): shortcut between the
part's first pose, each via goal's solved pose and its last pose, every corner rounded by a
certified curve, a via's passing within ``ENTRY`` of its radius.

A via goal is *passed* when a frame comes within its judged radius (:func:`judged_radius`: the
blend radius, at least the tolerance that reaches it). The clock caps the path's speed in the
radius so that the frames are dense enough there (:func:`pass_speed_caps`); the caller checks the
frames by forward kinematics and slows further, or stops at the goal, where they are not. Pure
core: numpy only.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from armanim.arm.geometry import wrap_angle
from armanim.arm.kinematics import forward
from armanim.motion.problem import Goal, Problem, joint_offset
from armanim.motion.solution import BLEND_REASONS, BlendReport, GoalReport, KindPass
from armanim.motion.timing.jointpath import unwrapped

ENTRY = 0.8
"""A via's curve passes within this fraction of its radius of the goal (the rest of the radius is
the frames' margin)."""
PASS_TOLERANCES = 2.0
"""A frame passes a via goal of a smaller radius (0 included) within this many tolerances."""


def blend_reason(problem: Problem, goals: tuple[GoalReport, ...] | list[GoalReport], k: int) -> str | None:
    """Why goal ``k`` (which has a ``blend``) ends at rest, or None when it may be a via goal.
    ``next_path`` before a path goal: the clock lets the goal flow into that goal's approach to its
    path's start where the arm moves there (:func:`armanim.motion.timing.retime.retime`).

    >>> from types import SimpleNamespace
    >>> p = SimpleNamespace(goals=[Goal(np.zeros(3), 0.0, blend=0.1), Goal(np.zeros(3), 1.0, blend=0.1)])
    >>> r = [SimpleNamespace(reached=True, frames=3), SimpleNamespace(reached=True, frames=3)]
    >>> blend_reason(p, r, 0), blend_reason(p, r, 1)
    (None, 'last')
    """
    goal = problem.goals[k]
    if k == len(problem.goals) - 1:
        return "last"
    if goal.hold > 0:
        return "hold"
    if not goals[k].reached:
        return "missed"
    if problem.goals[k + 1].path is not None:
        return "next_path"
    if goals[k + 1].frames == 0:
        return "next_still"
    return None


def judged_radius(problem: Problem, goal: Goal) -> float:
    """The distance within which a frame passes ``goal``: its blend radius, at least
    :data:`PASS_TOLERANCES` times the tolerance that reaches it (``solver.tolerance``; a joint goal's
    ``solver.joint_tolerance``, radians): the solved pose a path through the goal passes is itself
    only within the tolerance, and the frames sample the path around it."""
    assert goal.blend is not None
    floor = problem.solver.joint_tolerance if goal.joints is not None else problem.solver.tolerance
    return max(goal.blend, PASS_TOLERANCES * floor)


def kind_pass(problem: Problem, goal: Goal, phi: np.ndarray, velocity: np.ndarray | None) -> KindPass | None:
    """A joint goal's pass at pose ``phi`` (n,) moving at ``velocity`` (n,; None: at rest), each
    joint kind in its own unit (:class:`~armanim.motion.solution.KindPass`); None for another goal
    or an arm without a prismatic joint."""
    slides = problem.arm.slides
    if goal.joints is None or not slides.any():
        return None
    offset = np.abs(joint_offset(problem, np.asarray(phi, dtype=float), goal.joints))
    speed = np.zeros(len(slides)) if velocity is None else np.abs(np.asarray(velocity, dtype=float))
    return KindPass(
        float(offset[~slides].max(initial=0.0)),
        float(speed[~slides].max(initial=0.0)),
        float(offset[slides].max()),
        float(speed[slides].max()),
    )


def via_distances(problem: Problem, goal: Goal, phi: np.ndarray) -> np.ndarray:
    """(k,) how far each pose ``phi`` (k, n) is from ``goal``: the tool's distance (scene units),
    or for a joint goal the largest joint offset (radians, unlimited joints the short way round)."""
    phi = np.atleast_2d(phi)
    if goal.joints is not None:
        offset = phi - goal.joints
        return np.asarray(np.abs(np.where(problem.limits.limited, offset, wrap_angle(offset))).max(axis=1))
    return np.asarray(np.linalg.norm(forward(problem.arm, phi).tip - goal.position, axis=1))


@dataclass(frozen=True)
class ShapedPart:
    """A part through via goals as the clock is given it (:mod:`armanim.motion.timing.smoothing`'s path).

    Attributes
    ----------
    poses : (m', n) array
        The poses, radians (unlimited joints wrapped).
    origin : (m',) int array
        The solved pose of the part each is or heads for (offset from its first).
    clearance : (m',) array
        Every pose's clearance (an added one's measured).
    certified : (m' - 1,) bool array
        The steps known to keep the floor throughout (every step the smoothing made is).
    """

    poses: np.ndarray
    origin: np.ndarray
    clearance: np.ndarray
    certified: np.ndarray


def pass_speed_caps(
    problem: Problem, goal: Goal, poses: np.ndarray, zone: tuple[int, int], fps: float, slow: float = 1.0
) -> tuple[np.ndarray, np.ndarray]:
    """The most ds/dt on each step of ``poses`` (m, n) (inf: no cap) so that near the via goal
    the frames at ``fps`` lie close enough together to pass within :func:`judged_radius`, and the
    steps capped ((m - 1,) each). ``slow`` divides the caps (the caller's retries).

    The capped steps are those of the curve's ``zone`` with an end inside the radius, and the steps
    either side of its nearest pose; on each, a frame moves the tool (a joint goal: its joints) by
    at most 0.9 of the stretch of path inside the radius round the nearest pose (so that a frame
    lands in it), at least 1.2 (r - d) (d the nearest pose's distance, r the judged radius), over
    ``slow``: the caller checks the frames and slows further where none did."""
    flat = unwrapped(poses, problem.limits.limited)
    steps = np.diff(flat, axis=0)
    h = np.maximum(np.linalg.norm(steps, axis=1), 1e-300)
    first, last = zone
    lo, hi = max(first - 1, 0), min(last + 1, len(poses) - 1)
    dist = via_distances(problem, goal, flat[lo : hi + 1])
    near = int(np.argmin(dist))
    radius = judged_radius(problem, goal)
    moved = h.copy()  # how far each step moves the goal's measure (the tool; a joint goal's joints): on the zone's
    near_steps = slice(max(lo - 1, 0), hi)
    if goal.joints is not None:
        moved[near_steps] = np.abs(steps[near_steps]).max(axis=1)
    else:
        tips = forward(problem.arm, flat[near_steps.start : hi + 1]).tip
        moved[near_steps] = np.linalg.norm(np.diff(tips, axis=0), axis=1)
    inside = dist < radius
    a = b = near
    while a > 0 and inside[a - 1]:
        a -= 1
    while b < len(inside) - 1 and inside[b + 1]:
        b += 1
    per_frame = max(0.9 * float(moved[lo + a : lo + b].sum()), 1.2 * max(radius - float(dist[near]), 0.0))
    capped = np.zeros(len(steps), dtype=bool)
    capped[lo:hi] = inside[:-1] | inside[1:]  # the zone's steps with an end inside the radius
    nearest = lo + near
    capped[max(nearest - 1, 0) : min(nearest + 1, len(steps))] = True
    caps = np.where(capped, per_frame * fps / (np.maximum(moved / h, 1e-300) * slow), np.inf)
    return caps, capped


__all__ = [
    "BLEND_REASONS",
    "BlendReport",
    "KindPass",
    "kind_pass",
    "ShapedPart",
    "blend_reason",
    "judged_radius",
    "pass_speed_caps",
    "via_distances",
]
