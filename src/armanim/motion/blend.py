"""Goals the arm passes without stopping: which may, and the corner it cuts near each.

A goal with a ``blend`` radius (:attr:`armanim.motion.problem.Goal.blend`) that is reached, has no
``hold``, is not the last and is followed by a point, pose or joint goal is a *via* goal: its
solved path and the next goal's become one path, which the clock times as one
(:func:`armanim.motion.retime.retime`), its speed at the via free. Every other goal ends at
rest, as without ``blend``; :func:`blend_reason` says why.

Near a via goal the solved corner is replaced, inside the radius, by a joint-space blend
(:func:`cut_corner`): the quadratic Bezier curve from the pose where the path enters the radius,
with the goal's solved pose as its control point, to the pose where it leaves. The curve's
poses are convex combinations of three poses inside the joint limits, so they are inside too;
the clock's path keeps each joint monotone between two of them, so it never leaves the box of
two neighbouring poses; and every such step is certified clear by the lever-arm bound the
planner's and the clock's proofs use (:func:`~armanim.motion.goalmotion.two_sided_bound` of the
two poses' measured clearances, obstacles and the arm's own pairs judged by one floor). Where a
curve of up to :data:`MOST_SAMPLES` poses cannot be certified, the corner is kept: the arm passes
through the goal's solved pose itself (still without stopping).

A via goal is *passed* when a frame comes within its judged radius (:func:`judged_radius`: the
blend radius, at least the tolerance that reaches it). The clock caps the path's speed in the
radius so that the frames are dense enough there (:func:`pass_speed_caps`); the caller checks the
frames by forward kinematics and slows further, or stops at the goal, where they are not. Pure
core: numpy only.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np

from armanim.arm.geometry import wrap_angle
from armanim.arm.kinematics import forward
from armanim.motion.goalmotion import two_sided_bound
from armanim.motion.jointpath import unwrapped
from armanim.motion.problem import Goal, Problem
from armanim.motion.solution import BLEND_REASONS, BlendReport, GoalReport

ENTRY = 0.8
"""The blend's curve starts and ends where the path is this fraction of the radius from the goal
(the rest of the radius is the frames' margin)."""
PASS_TOLERANCES = 2.0
"""A frame passes a via goal of a smaller radius (0 included) within this many tolerances."""
MOST_SAMPLES = 512
"""Most poses on a corner's curve: a curve these cannot certify keeps the corner."""
def blend_reason(problem: Problem, goals: tuple[GoalReport, ...] | list[GoalReport], k: int) -> str | None:
    """Why goal ``k`` (which has a ``blend``) ends at rest, or None when it may be a via goal.

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


def via_distances(problem: Problem, goal: Goal, phi: np.ndarray) -> np.ndarray:
    """(k,) how far each pose ``phi`` (k, n) is from ``goal``: the tool's distance (scene units),
    or for a joint goal the largest joint offset (radians, unlimited joints the short way round)."""
    phi = np.atleast_2d(phi)
    if goal.joints is not None:
        offset = phi - goal.joints
        return np.asarray(np.abs(np.where(problem.limits.limited, offset, wrap_angle(offset))).max(axis=1))
    return np.asarray(np.linalg.norm(forward(problem.arm, phi).tip - goal.position, axis=1))


@dataclass(frozen=True)
class Corner:
    """A part's poses with a via goal's corner replaced.

    Attributes
    ----------
    poses : (m', n) array
        The poses, radians (unlimited joints wrapped).
    origin : (m',) int array
        The pose of the original part each is (or, inside the curve, heads for).
    inserted : (m',) bool array
        The poses the curve added (measured, not solved).
    clearance : (m',) array
        Every pose's clearance (an inserted one's measured).
    certified : (m' - 1,) bool array
        The steps known to keep the floor throughout (every step the curve made is).
    zone : tuple of int
        The first and last pose of the curve's stretch (the via's own pose for a corner kept).
    curve : bool
        Whether the corner was replaced.
    """

    poses: np.ndarray
    origin: np.ndarray
    inserted: np.ndarray
    clearance: np.ndarray
    certified: np.ndarray
    zone: tuple[int, int]
    curve: bool


def cut_corner(problem: Problem, goal: Goal, part: Corner, via: int, lo: int, hi: int,
               measure: Callable[[np.ndarray], np.ndarray], floor: float) -> Corner:
    """The corner at pose ``via`` of ``poses`` (m, n) replaced inside ``goal``'s blend radius by a
    certified curve (see the module), or kept.

    Parameters
    ----------
    problem, goal : the run's problem and the via goal (``goal.blend`` set).
    part : Corner
        The part so far (its solved poses, or with a later via's corner cut already).
    via : int
        The goal's solved pose in ``poses``.
    lo, hi : int
        The curve stays within poses ``lo`` .. ``hi`` (the neighbouring vias' halves are theirs).
    measure : callable
        (k, n) poses -> (k,) clearances (obstacles and own pairs, one floor).
    floor : float
        The clearance every pose between two of the curve's keeps.
    """
    assert goal.blend is not None
    poses, origin, inserted, clearance = part.poses, part.origin, part.inserted, part.clearance
    keep = replace(part, zone=(via, via), curve=False)
    rho = ENTRY * goal.blend
    if goal.blend <= 0 or hi - lo < 2:
        return keep
    flat = unwrapped(poses, problem.limits.limited)
    dist = via_distances(problem, goal, flat[lo:hi + 1])
    if dist[via - lo] >= rho:
        return keep
    first = _edge(problem, goal, flat, dist, via, lo, -1, rho)
    last = _edge(problem, goal, flat, dist, via, lo, +1, rho)
    if first is None or last is None:
        return keep
    (i_a, a), (i_b, b) = first, last  # a on the step i_a -> i_a + 1, b on the step i_b - 1 -> i_b
    c = flat[via]
    lever = problem.lever_arms
    ends = np.array([clearance[i_a], clearance[i_b]])
    fine = _bezier(a, c, b, np.linspace(0.0, 1.0, 257))
    margin = float(min(ends.min(), np.min(measure(_wrapped(problem, fine[::16])))) - floor)
    if margin <= 0:
        return keep
    for piece in margin * 0.5 ** np.arange(6):  # the most a piece may move the arm: a margin's worth, then halves
        curve = _even(fine, lever, piece)
        chain = np.concatenate([_densified(np.stack([flat[i_a], a]), lever, piece), curve[1:-1],
                                _densified(np.stack([b, flat[i_b]]), lever, piece)])
        if len(chain) - 2 > MOST_SAMPLES:
            return keep
        new = chain[1:-1]
        new = np.where(problem.limits.limited, np.clip(new, problem.limits.lower, problem.limits.upper), new)
        c_new = np.asarray(measure(_wrapped(problem, new)))
        clear = np.concatenate([ends[:1], c_new, ends[1:]])
        reach = np.abs(np.diff(np.concatenate([chain[:1], new, chain[-1:]]), axis=0)) @ lever
        if np.all(two_sided_bound(clear[:-1], clear[1:], reach) >= floor):
            break
    else:
        return keep
    where = _path_position(np.concatenate([chain[:1], new, chain[-1:]]))[1:-1]  # 0 at a, 1 at b (entry pieces < 0)
    new_origin = np.where(where <= 0, origin[min(i_a + 1, via)], np.where(where < 0.5, origin[via], origin[i_b]))
    return Corner(
        poses=np.concatenate([poses[:i_a + 1], _wrapped(problem, new), poses[i_b:]]),
        origin=np.concatenate([origin[:i_a + 1], np.maximum.accumulate(new_origin), origin[i_b:]]),
        inserted=np.concatenate([inserted[:i_a + 1], np.ones(len(new), dtype=bool), inserted[i_b:]]),
        clearance=np.concatenate([clearance[:i_a + 1], c_new, clearance[i_b:]]),
        certified=np.concatenate([part.certified[:i_a], np.ones(len(new) + 1, dtype=bool), part.certified[i_b:]]),
        zone=(i_a + 1, i_a + len(new)),
        curve=True,
    )


def _bezier(a: np.ndarray, c: np.ndarray, b: np.ndarray, t: np.ndarray) -> np.ndarray:
    """(k, n) the quadratic Bezier curve from ``a`` to ``b`` (n,) with control point ``c`` at ``t`` (k,)."""
    t = t[:, None]
    return np.asarray((1 - t) ** 2 * a + 2 * t * (1 - t) * c + t**2 * b)


def _even(fine: np.ndarray, lever: np.ndarray, piece: float) -> np.ndarray:
    """Poses evenly spaced (by joint-space length) along the finely sampled curve ``fine`` (k, n),
    its ends included, no two consecutive moving the arm by more than ``piece``."""
    length = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(fine, axis=0), axis=1))])
    moves = np.concatenate([[0.0], np.cumsum(np.abs(np.diff(fine, axis=0)) @ lever)])
    count = max(2, math.ceil(2 * moves[-1] / piece))  # twice: a piece of the chord may move more than the curve's
    at = np.linspace(0.0, length[-1], count + 1)
    return np.stack([np.interp(at, length, fine[:, j]) for j in range(fine.shape[1])], axis=1)


def _wrapped(problem: Problem, phi: np.ndarray) -> np.ndarray:
    """``phi`` (..., n) with its unlimited joints wrapped into (-pi, pi]."""
    return np.where(problem.limits.limited, phi, wrap_angle(phi))


def _densified(points: np.ndarray, lever: np.ndarray, piece: float) -> np.ndarray:
    """``points`` (k, n) with poses added evenly along each chord between two, so that no piece
    moves any point of the arm by more than ``piece`` (by the lever arms ``lever`` (n,))."""
    out = [points[:1]]
    for p, q in zip(points[:-1], points[1:]):
        count = max(1, math.ceil(float(np.abs(q - p) @ lever) / piece))
        f = np.arange(1, count + 1)[:, None] / count
        out.append(p + f * (q - p))
    return np.concatenate(out)


def _path_position(chain: np.ndarray) -> np.ndarray:
    """(k,) where each pose of ``chain`` (k, n) (its second pose is the curve's start a, its
    last but one the curve's end b) lies: 0 at a, 1 at b, by joint-space length; below 0 before a."""
    length = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(chain, axis=0), axis=1))])
    return np.asarray((length - length[1]) / max(length[-2] - length[1], 1e-300))


def _edge(problem: Problem, goal: Goal, flat: np.ndarray, dist: np.ndarray, via: int, lo: int, way: int, rho: float
          ) -> tuple[int, np.ndarray] | None:
    """Where the path from the via pose, walking ``way`` (-1: back, +1: on), first leaves distance
    ``rho`` of the goal: (the first pose outside, and the point on the chord from the last pose
    inside to it at about ``rho``); where the stretch ``dist`` covers (from pose ``lo``) ends inside,
    its end pose (twice); None when the via pose is the stretch's end."""
    i = via
    while True:
        j = i + way
        if j - lo < 0 or j - lo >= len(dist):  # inside to the stretch's end: the curve starts (or ends) there
            return (i, flat[i]) if i != via else None
        if dist[j - lo] >= rho:
            break
        i = j
    inside, outside = flat[i], flat[j]
    t_in, t_out = 0.0, 1.0  # bisect the chord inside -> outside for the point at rho
    for _ in range(20):
        mid = 0.5 * (t_in + t_out)
        if via_distances(problem, goal, inside + mid * (outside - inside))[0] < rho:
            t_in = mid
        else:
            t_out = mid
    return j, inside + t_in * (outside - inside)


def pass_speed_caps(problem: Problem, goal: Goal, poses: np.ndarray, zone: tuple[int, int], fps: float,
                    slow: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """The most ds/dt on each step of ``poses`` (m, n) (inf: no cap) so that near the via goal
    the frames at ``fps`` lie close enough together to pass within :func:`judged_radius`, and the
    steps capped ((m - 1,) each). ``slow`` divides the caps (the caller's retries).

    The capped steps are the curve's ``zone`` and the steps either side of its nearest pose; on
    each, a frame moves the tool by at most 1.8 (r - d) / ``slow`` (d the nearest pose's distance,
    r the judged radius), bounded by the lever arms (or, for a joint goal, by the joints)."""
    flat = unwrapped(poses, problem.limits.limited)
    steps = np.diff(flat, axis=0)
    h = np.maximum(np.linalg.norm(steps, axis=1), 1e-300)
    first, last = zone
    lo, hi = max(first - 1, 0), min(last + 1, len(poses) - 1)
    dist = via_distances(problem, goal, flat[lo:hi + 1])
    nearest = lo + int(np.argmin(dist))
    room = judged_radius(problem, goal) - float(dist.min())
    per_unit = (np.abs(steps).max(axis=1) if goal.joints is not None else np.abs(steps) @ problem.lever_arms) / h
    capped = np.zeros(len(steps), dtype=bool)
    capped[max(first - 1, 0):last] = True
    capped[max(nearest - 1, 0):min(nearest + 1, len(steps))] = True
    caps = np.where(capped, 1.8 * max(room, 0.0) * fps / (1.5 * np.maximum(per_unit, 1e-300) * slow), np.inf)
    return caps, capped


__all__ = ["BLEND_REASONS", "BlendReport", "Corner", "blend_reason", "cut_corner", "judged_radius", "pass_speed_caps",
           "via_distances"]
