"""Goal poses: many inverse-kinematics solves at once, from deterministic seeds.

Damped least squares on the tip, vectorised over the seeds (one batched forward
kinematics and one batched Jacobian per iteration), limited joints clipped into their
limits at every iteration. A goal with an orientation solves the stacked pose task
[p_g - p ; w B r] with [J_v ; w B J_w] instead, and a pose counts only when it meets the
orientation too. The poses kept are inside the limits with every link at
least the planning floor from every obstacle (what the safety filter keeps,
:func:`armanim.motion.filter.clearance.planning_floor`): the roomy ones first (at least
:func:`~armanim.motion.filter.clearance.settle_clearance`, room to settle), then the others,
each group nearest to the current pose first.
Pure core: numpy only.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import cast

import numpy as np

from armanim.arm.geometry import wrap_angle
from armanim.arm.kinematics import Pose, forward, tip_jacobian, tool_rotation
from armanim.motion.filter.clearance import (
    limit_buffer,
    planning_floor,
    pose_clearance,
    self_shift,
    settle_clearance,
    within_limits,
)
from armanim.motion.orientation import Orientation, orientation_angle, orientation_task
from armanim.motion.problem import Problem
from armanim.world.selfdistances import self_gaps


@dataclass(frozen=True)
class GoalPoses:
    """Result of :func:`goal_poses`.

    Attributes
    ----------
    poses : (k, n) array
        Free poses whose tip is at the goal: those with room to settle first, each group
        nearest to the current pose first (unlimited joints taken the short way round).
    reachable : bool
        Whether any solve reached the goal at all, limits and obstacles aside: False
        means the goal is out of this arm's reach.
    orientable : bool
        For a goal with an orientation: False when solves reach the position but none
        (limits and obstacles aside) meets the orientation there (``orientation_unreachable``).
    self_pair : str or None
        When no pose is free and some were kept out by the arm's own enabled pairs: the pair
        (``a|b``) nearest in most of them.
    """

    poses: np.ndarray
    reachable: bool
    orientable: bool = True
    self_pair: str | None = None


def seed_poses(problem: Problem, phi_now: np.ndarray, count: int, seed: int) -> np.ndarray:
    """(count, n) starts of solves from ``phi_now``: the current pose, its mirrored elbow (every
    joint after the first negated), then seeded uniform poses inside :func:`joint_ranges`.

    The planner's goal-pose seeds and ``armanim ik``'s restarts (:mod:`armanim.motion.ik`).
    The random poses are rows 2.. of one ``(count, n)`` draw, so that a seed always gives
    the planner the same starts.

    >>> from types import SimpleNamespace
    >>> from armanim.motion.problem import Limits
    >>> from armanim.motion.tunables import DEFAULTS
    >>> free = SimpleNamespace(limits=Limits.unlimited(2, margin=0.1), tunables=DEFAULTS)
    >>> seed_poses(free, np.array([0.5, 1.0]), 3, seed=0)[:2].tolist()
    [[0.5, 1.0], [0.5, -1.0]]
    """
    lo, hi = joint_ranges(problem)
    rng = np.random.default_rng(seed)
    starts = rng.uniform(lo, hi, size=(count, len(phi_now)))
    starts[0] = phi_now
    mirrored = phi_now.copy()
    mirrored[1:] = -mirrored[1:]
    starts[1] = np.clip(mirrored, lo, hi)
    return starts


def joint_ranges(problem: Problem) -> tuple[np.ndarray, np.ndarray]:
    """Where a joint may be: its limits less the buffer, or (-pi, pi] when unlimited."""
    lim = problem.limits
    buffer = limit_buffer(problem)
    lo = np.where(lim.limited, lim.lower + buffer, -np.pi)
    hi = np.where(lim.limited, lim.upper - buffer, np.pi)
    middle = 0.5 * (lo + hi)  # a range narrower than twice the buffer: its midpoint
    return np.minimum(lo, middle), np.maximum(hi, middle)


def pose_task(
    problem: Problem, pose: Pose, goal: np.ndarray, orientation: Orientation | None
) -> tuple[np.ndarray, np.ndarray]:
    """The batched task error (S, m) and Jacobian (S, m, n): the tip's (m = 3), stacked with
    the weighted rotation rows w B r and w B J_w for a goal with an orientation."""
    error = goal - pose.tip  # (S, 3)
    jac = tip_jacobian(problem.arm, pose)  # (S, 3, n)
    if orientation is None:
        return error, jac
    w = problem.solver.orientation_weight
    rot_error, rot_jac = orientation_task(orientation, problem.arm, pose)
    return np.concatenate([error, w * rot_error], -1), np.concatenate([jac, w * rot_jac], -2)


def hits(
    problem: Problem, phi: np.ndarray, goal: np.ndarray, orientation: Orientation | None, fraction: float | None = None
) -> np.ndarray:
    """(S,) bool: poses whose tip is within ``fraction`` (default the pose search's ``hit``) of the
    tolerance of the goal, and whose tool is within that fraction of the orientation tolerance of
    its orientation (if any)."""
    fraction = problem.tunables.poses.hit if fraction is None else fraction
    pose = forward(problem.arm, phi)
    hit = np.linalg.norm(pose.tip - goal, axis=-1) < fraction * problem.solver.tolerance
    if orientation is not None:
        angle = orientation_angle(orientation, tool_rotation(problem.arm, pose))
        hit &= angle < fraction * problem.solver.orientation_tolerance
    return cast(np.ndarray, hit)


def solve_many(
    problem: Problem, starts: np.ndarray, goal: np.ndarray, clip: bool = True, orientation: Orientation | None = None
) -> np.ndarray:
    """Damped least-squares IK from every start at once; returns (S, n) poses.

    With ``clip`` the limited joints are kept inside their limits at every iteration; with an
    ``orientation`` the whole pose task is solved (:func:`pose_task`).
    """
    arm = problem.arm
    lo, hi = joint_ranges(problem)
    opts = problem.tunables.poses
    damping2 = (opts.damping_per_reach * arm.reach) ** 2
    phi = starts.copy()
    rows = 3 if orientation is None else 3 + orientation.rows
    for _ in range(opts.iterations):
        pose = forward(arm, phi)
        error, jac = pose_task(problem, pose, goal, orientation)
        gram = jac @ np.swapaxes(jac, -1, -2) + damping2 * np.eye(rows)
        dphi = np.einsum("sji,sj->si", jac, np.linalg.solve(gram, error[..., None])[..., 0])
        biggest = np.abs(dphi).max(axis=-1, keepdims=True)
        dphi *= np.minimum(1.0, opts.turn_per_iteration / np.maximum(biggest, 1e-300))
        phi = phi + dphi
        if clip:
            phi = np.clip(phi, lo, hi)
    return phi


def goal_poses(
    problem: Problem, phi_now: np.ndarray, goal: np.ndarray, seed: int = 0, orientation: Orientation | None = None
) -> GoalPoses:
    """Free poses whose tip is at ``goal`` (with the tool at ``orientation``, if given), nearest
    to ``phi_now`` first.

    Parameters
    ----------
    problem : Problem
    phi_now : (n,) array
        The current pose, radians.
    goal : (3,) array
    seed : int
        Seed of the random starts (the same seed gives the same poses).
    orientation : Orientation, optional
        The goal's orientation: the poses meet it too.

    Returns
    -------
    GoalPoses
    """
    starts = seed_poses(problem, phi_now, problem.tunables.poses.seeds, seed)
    solved = solve_many(problem, starts, goal, orientation=orientation)
    hit = hits(problem, solved, goal, orientation)
    reachable = bool(hit.any()) or _reachable_without_limits(problem, starts, goal, orientation)
    orientable = True
    if not reachable and orientation is not None:  # the position alone may still be reachable
        reachable = _reachable_without_limits(problem, starts, goal, None)
        orientable = not reachable
    clear = pose_clearance(problem, solved)
    floor = planning_floor(problem, phi_now)
    free = hit & within_limits(problem, solved) & (clear >= floor)
    roomy = clear >= settle_clearance(problem)
    poses = [nearest_first(problem, phi_now, solved[free & room]) for room in (roomy, ~roomy)]
    pair = (
        blocking_pair(problem, solved[hit & within_limits(problem, solved) & ~free], floor) if not free.any() else None
    )
    return GoalPoses(poses=np.concatenate(poses), reachable=reachable, orientable=orientable, self_pair=pair)


def blocking_pair(problem: Problem, poses: np.ndarray, floor: float) -> str | None:
    """The enabled pair (``a|b``) nearest in most of the ``poses`` (k, n) that the arm's own
    pairs keep below ``floor``, or None when none is."""
    pairs = problem.self_pairs
    if not len(pairs) or not len(poses):
        return None
    gaps = self_gaps(forward(problem.arm, poses), problem.capsules, pairs).d
    kept_out = gaps.min(axis=1) + self_shift(problem) < floor
    if not kept_out.any():
        return None
    return pairs.labels[int(np.argmax(np.bincount(np.argmin(gaps[kept_out], axis=1))))]


def _reachable_without_limits(
    problem: Problem, starts: np.ndarray, goal: np.ndarray, orientation: Orientation | None
) -> bool:
    solved = solve_many(problem, starts, goal, clip=False, orientation=orientation)
    return bool(np.any(hits(problem, solved, goal, orientation)))


def turn_variants(problem: Problem, phi_now: np.ndarray, poses: np.ndarray) -> np.ndarray:
    """Each pose with every unlimited joint reached the short way round from ``phi_now``
    and the long way round (a joint at a and at a + 2 pi is the same pose, but the straight
    path to one may pass an obstacle that the path to the other misses): (k 2^u, n) for u
    unlimited joints, at most the pose search's ``max_turn_joints`` of them varied."""
    short = np.where(problem.limits.limited, poses, phi_now + wrap_angle(poses - phi_now))
    variants = [short]
    for j in np.nonzero(~problem.limits.limited)[0][: problem.tunables.poses.max_turn_joints]:
        longer = [v.copy() for v in variants]
        for v in longer:
            v[:, j] -= 2 * np.pi * np.sign(v[:, j] - phi_now[j])
        variants += longer
    return np.concatenate(variants)


def nearest_first(problem: Problem, phi_now: np.ndarray, poses: np.ndarray) -> np.ndarray:
    """Poses and their :func:`turn_variants`, sorted by joint-space distance from
    ``phi_now``; near-duplicates (within 1e-3 rad) dropped."""
    if not len(poses):
        return poses
    poses = turn_variants(problem, phi_now, poses)
    order = np.argsort(np.linalg.norm(poses - phi_now, axis=-1), kind="stable")
    kept: list[np.ndarray] = []
    for pose in poses[order]:
        if all(np.abs(pose - other).max() > 1e-3 for other in kept):
            kept.append(pose)
    return np.array(kept)
