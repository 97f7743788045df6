"""The course notes' cost C(Phi) and its analytic gradient (Eqs. 10-12).

C(Phi) = w_goal |e - g| + w_obstacles sum F_R(d) + w_limits sum L(phi_j)

(the sum over F_R runs over every arm part and obstacle, and over every enabled pair of the
arm's own capsules, d their gap and R twice ``self_clearance``)

and, for a goal with an orientation, + w_goal w |r|: the angle still to turn (radians) times the
orientation weight w (length per radian), a length like |e - g| (scaled by
:attr:`~armanim.motion.tunables.CostGains.priority_weight` for an arm that cannot hold the orientation).

where d is the clearance of each arm part to each obstacle's surface: the tip as a
point (the notes' term) and every link as a capsule of radius width/2. Functions
accept a batch of poses where their docstring says so. Pure core: no I/O.
"""

from __future__ import annotations

from typing import cast

import numpy as np

from armanim.arm.capsules import Capsules, capsule_point_jacobian
from armanim.arm.kinematics import Arm, Pose, forward, link_point, point_jacobian, tip_jacobian, tool_rotation
from armanim.motion.orientation import (
    Orientation,
    holds_orientation,
    orientation_angle,
    orientation_gradient,
)
from armanim.motion.problem import Limits, Problem
from armanim.world.distances import Clearances, clearances
from armanim.world.obstacles import Obstacles
from armanim.world.selfdistances import SelfGaps, self_gaps, self_rows


def obstacle_field(d: np.ndarray, influence: float | np.ndarray) -> np.ndarray:
    """F_R(d) = ln(R/d) for 0 < d <= R, 0 for d > R, +inf for d <= 0 (Eq. 11); R is the influence.

    >>> obstacle_field(np.array([0.5, 1.0, 2.0, 0.0]), np.array(1.0))
    array([0.69314718, 0.        , 0.        ,        inf])
    """
    d = np.asarray(d, dtype=float)
    inside = (d > 0) & (d <= influence)
    safe = np.where(inside, d, 1.0)
    value = np.where(inside, np.log(np.where(inside, influence, 1.0) / safe), 0.0)
    return np.where(d <= 0, np.inf, value)


def obstacle_field_slope(d: np.ndarray, influence: float | np.ndarray) -> np.ndarray:
    """dF_R/dd: -1/d inside the influence shell, 0 beyond it."""
    d = np.asarray(d, dtype=float)
    inside = (d > 0) & (d <= influence)
    return np.where(inside, -1.0 / np.where(inside, d, 1.0), 0.0)


def limit_barrier(phi: np.ndarray, limits: Limits) -> np.ndarray:
    """Sum over limited joints of L(phi_j) (Eq. 12), for (..., n) angles in radians.

    Infinite at or past a limit: the barrier is never crossed.

    >>> lim = Limits(np.array([-1.0]), np.array([1.0]), margin=0.5)
    >>> limit_barrier(np.array([[0.0], [0.75], [1.0]]), lim)
    array([0.        , 0.69314718,        inf])
    """
    lo_gap, hi_gap = limit_gaps(phi, limits)
    delta = limits.margin
    with np.errstate(divide="ignore", invalid="ignore"):
        lo = np.where(lo_gap <= 0, np.inf, np.where(lo_gap < delta, np.log(delta / lo_gap), 0.0))
        hi = np.where(hi_gap <= 0, np.inf, np.where(hi_gap < delta, np.log(delta / hi_gap), 0.0))
    barrier: np.ndarray = (lo + hi).sum(axis=-1)
    return barrier


def limit_barrier_gradient(phi: np.ndarray, limits: Limits) -> np.ndarray:
    """dL/dphi for each joint (n,): -1/(phi - min) near min, 1/(max - phi) near max."""
    lo_gap, hi_gap = limit_gaps(phi, limits)
    delta = limits.margin
    with np.errstate(divide="ignore", invalid="ignore"):
        lo = np.where((lo_gap > 0) & (lo_gap < delta), -1.0 / lo_gap, 0.0)
        hi = np.where((hi_gap > 0) & (hi_gap < delta), 1.0 / hi_gap, 0.0)
    return lo + hi


def limit_gaps(phi: np.ndarray, limits: Limits) -> tuple[np.ndarray, np.ndarray]:
    """Distances (radians) of each joint to its lower and upper limit (inf if unlimited)."""
    return phi - limits.lower, limits.upper - phi


def goal_term(tip: np.ndarray, goal: np.ndarray) -> np.ndarray:
    """|e - g| for (..., 3) tips."""
    return cast(np.ndarray, np.linalg.norm(tip - goal, axis=-1))


def orientation_cost_weight(problem: Problem, orientation: Orientation) -> float:
    """The weight of the angle |r| in C: w_goal w, or a ``priority_weight`` (the cost gains') of it for an arm
    that cannot hold the orientation."""
    s = problem.solver
    weight = s.w_goal * s.orientation_weight
    return weight if holds_orientation(problem.arm, orientation) else problem.tunables.cost.priority_weight * weight


def total_cost(
    problem: Problem,
    phi: np.ndarray,
    goal: np.ndarray,
    pose: Pose | None = None,
    cl: Clearances | None = None,
    orientation: Orientation | None = None,
) -> np.ndarray:
    """C(Phi) for one pose or a batch (..., n); +inf where a barrier is crossed.

    ``pose`` and ``cl`` may be passed when already known for ``phi``; ``orientation`` adds
    the goal's orientation term.
    """
    s = problem.solver
    pose = pose if pose is not None else forward(problem.arm, phi)
    cost = s.w_goal * goal_term(pose.tip, goal)
    if orientation is not None:
        angle = orientation_angle(orientation, tool_rotation(problem.arm, pose))
        cost = cost + orientation_cost_weight(problem, orientation) * angle
    if len(problem.obstacles):
        obstacles = problem.obstacles
        cl = cl if cl is not None else clearances(pose, obstacles, problem.capsules)
        field = obstacle_field(cl.d, obstacles.influence)
        cost = cost + s.w_obstacles * field.sum(axis=(-1, -2))
    gaps = pair_gaps(problem, pose)
    if gaps is not None and np.any(
        gaps.least <= self_influence(problem)
    ):  # the arm's own pairs: the same field between two of its parts (0 beyond R)
        cost = cost + s.w_obstacles * obstacle_field(gaps.d, self_influence(problem)).sum(axis=-1)
    return cost + s.w_limits * limit_barrier(phi, problem.limits)


def obstacle_cost_gradient(
    arm: Arm, capsules: Capsules, pose: Pose, cl: Clearances, obstacles: Obstacles
) -> np.ndarray:
    """Gradient (n,) of sum F_R(d) over parts and obstacles, for a single pose.

    Each concerned part contributes F_R'(d) n^T J_q, with J_q the Jacobian of its
    closest point (fixed t: the envelope theorem makes dt/dphi drop out).
    """
    grad = np.zeros(arm.n)
    slope = obstacle_field_slope(cl.d, obstacles.influence)
    parts, obs = np.nonzero(slope)
    for k, jac in enumerate(part_jacobians(arm, capsules, pose, cl, parts, obs)):
        grad += slope[parts[k], obs[k]] * (cl.normal[parts[k], obs[k]] @ jac)
    return grad


def self_influence(problem: Problem) -> float:
    """R of the field between an enabled pair: the cost gains' ``self_influence`` x ``self_clearance``."""
    return problem.tunables.cost.self_influence * problem.self_pairs.clearance


def pair_gaps(problem: Problem, pose: Pose) -> SelfGaps | None:
    """The enabled pairs' gaps of ``pose`` (one or a batch), or None without pairs."""
    return self_gaps(pose, problem.capsules, problem.self_pairs) if len(problem.self_pairs) else None


def self_cost_gradient(problem: Problem, pose: Pose, gaps: SelfGaps) -> np.ndarray:
    """Gradient (n,) of sum F_R(d) over the enabled pairs, one pose: F_R'(d) n . (J_A - J_B)."""
    if not gaps.least <= self_influence(problem):  # every pair beyond the field's reach
        return np.zeros(problem.arm.n)
    slope = obstacle_field_slope(gaps.d, self_influence(problem))
    which = np.nonzero(slope)[0]
    if not len(which):
        return np.zeros(problem.arm.n)
    return cast(
        np.ndarray, slope[which] @ self_rows(problem.arm, problem.capsules, pose, problem.self_pairs, gaps, which)
    )


def part_jacobians(
    arm: Arm, capsules: Capsules, pose: Pose, cl: Clearances, parts: np.ndarray, obs: np.ndarray
) -> np.ndarray:
    """(k, 3, n) Jacobians of the points of parts ``parts`` (k,) closest to obstacles ``obs`` (k,),
    one pose: on a capsule, or the tip (the end of the last link)."""
    jacs = np.empty((len(parts), 3, arm.n))
    at_tip = parts == cl.tip
    if np.any(at_tip):
        jacs[at_tip] = point_jacobian(arm, pose, arm.n - 1, link_point(pose, arm.n - 1, 1.0))
    if not np.all(at_tip):
        jacs[~at_tip] = capsule_point_jacobian(arm, capsules, pose, parts[~at_tip], cl.t[parts[~at_tip], obs[~at_tip]])
    return jacs


def total_cost_gradient(
    problem: Problem,
    phi: np.ndarray,
    goal: np.ndarray,
    pose: Pose | None = None,
    cl: Clearances | None = None,
    orientation: Orientation | None = None,
) -> np.ndarray:
    """Analytic gradient of :func:`total_cost` for one pose, shape (n,).

    ``pose`` and ``cl`` may be passed when already known for ``phi``. The orientation term's
    gradient is -(r / |r|)^T J_w (:func:`armanim.motion.orientation.orientation_gradient`).
    """
    s = problem.solver
    arm = problem.arm
    pose = pose if pose is not None else forward(arm, phi)
    diff = pose.tip - goal
    dist = np.linalg.norm(diff)
    grad = np.zeros(arm.n)
    if dist > 0:
        grad += s.w_goal * (diff / dist) @ tip_jacobian(arm, pose)
    if orientation is not None:
        r, half_square_gradient = orientation_gradient(orientation, arm, pose)
        angle = np.linalg.norm(r)
        if angle > 0:
            grad += orientation_cost_weight(problem, orientation) * half_square_gradient / angle
    if len(problem.obstacles):
        cl = cl if cl is not None else clearances(pose, problem.obstacles, problem.capsules)
        grad += s.w_obstacles * obstacle_cost_gradient(arm, problem.capsules, pose, cl, problem.obstacles)
    gaps = pair_gaps(problem, pose)
    if gaps is not None:
        grad += s.w_obstacles * self_cost_gradient(problem, pose, gaps)
    return grad + s.w_limits * limit_barrier_gradient(phi, problem.limits)
