"""``pinv`` and ``dls``: one linear step per frame (the course notes' Algorithm 2).

dPhi = J^+ (de + v_tip)  +  (I - J^+ J) (sum over concerned link points of J_q^+ v_q  +  z)

- de: the frame's task-space step toward the goal;
- v_q: the obstacle repulsion of a point closer than R to an obstacle, along the
  outward normal, R (R/d - 1) long (scaled by beta and w_obstacles): the field's
  slope shifted so that the push fades to zero at the edge of the influence shell;
- z: the joint-limit push delta (delta/gap - 1) (scaled by beta and w_limits).

The tip's own repulsion (the notes' term) acts in task space beside de, so the tip
steers around obstacles; the links' repulsion and the limit push are moved into the
null space of J, so they reshape the arm without pulling the tip off its goal (a goal
next to an obstacle stays reachable).

The two methods differ only in the inverse: the pseudo-inverse
(:func:`armanim.arm.linalg.pseudo_inverse`) or the damped least-squares inverse
J^T (J J^T + lambda^2 I)^-1. The links' pushes are inverted in one call (a stack of
Jacobians), each bit for bit as alone.

A goal with an orientation adds the rotation task [w B r] with Jacobian w B J_w
(:func:`armanim.motion.orientation.orientation_task`), second in priority (task-priority IK):

dPhi_2 = (J_2 N_1)^+ (beta w B r - J_2 dPhi_1),   N_1 = I - J^+ J

so the tip's task is never traded for the orientation: an arm with too few joints reaches
the position and turns the tool as close as the rest of its freedom allows. The obstacle and
limit pushes then act in the null space of both tasks.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import cast

import numpy as np

from armanim.arm.linalg import pseudo_inverse
from armanim.motion.cost import self_influence
from armanim.motion.orientation import Orientation, holds_orientation, orientation_task
from armanim.motion.problem import Problem
from armanim.motion.solvers.common import (
    ArmState,
    Step,
    jacobian_of_capsule_point,
    jacobian_of_tip,
    rotation_displacement,
    self_pair_jacobians,
    task_displacement,
)


def damped_inverse(jac: np.ndarray, damping: float) -> np.ndarray:
    """J^T (J J^T + lambda^2 I)^-1, the damped least-squares inverse of a (3, n) Jacobian, or
    of each of a stack (..., 3, n), each bit for bit as alone: (..., n, 3)."""
    gram = np.matmul(jac, np.swapaxes(jac, -1, -2)) + damping**2 * np.eye(jac.shape[-2])
    return np.swapaxes(np.linalg.solve(gram, jac), -1, -2)


CLOSEST_GAP = 1e-12
"""Of the influence: the push is computed for gaps no smaller than this (R / gap stays below 1e12)."""


def repulsion(gap: np.ndarray, influence: np.ndarray | float) -> np.ndarray:
    """Length of a push away from a barrier: R (R/gap - 1) for a gap inside the influence R, else 0.

    R is an obstacle's influence, or a limit's margin delta.

    >>> repulsion(np.array([0.5, 1.0, 2.0]), 1.0)
    array([1., 0., 0.])
    """
    gap = np.asarray(gap, dtype=float)
    inside = (gap > 0) & (gap < influence)
    gap = np.maximum(
        gap, np.multiply(influence, CLOSEST_GAP)
    )  # a pose a hair's breadth from its barrier: a finite push
    return np.where(inside, influence * (influence / np.where(inside, gap, 1.0) - 1.0), 0.0)


def limit_push(problem: Problem, phi: np.ndarray) -> np.ndarray | None:
    """Joint-space push z (n,) away from nearby limits, radians; None when no joint is near one."""
    limits = problem.limits
    lo_gap, hi_gap = phi - limits.lower, limits.upper - phi
    if min(lo_gap.min(), hi_gap.min()) >= limits.margin:
        return None
    scale = problem.solver.beta * problem.solver.w_limits
    return cast("np.ndarray | None", scale * (repulsion(lo_gap, limits.margin) - repulsion(hi_gap, limits.margin)))


ROUNDING_TASK = 1e-6
"""Where the rotation comes second and |w B J_w N|_F, what the position's null space N leaves of
the rotation task, is below this fraction of |w B J_w|_F, what is left is rounding (an arm whose
position takes every joint, or whose free joints do not turn the goal's directions): there is
nothing to turn, and inverting it (a pseudo-inverse's cut-off is relative to the matrix's own
largest singular value) would propose steps of 1e17 rad in directions rounding sets."""


def orientation_in_null_space(
    problem: Problem,
    state: ArmState,
    orientation: Orientation,
    jac: np.ndarray,
    dphi: np.ndarray,
    invert: Callable[[np.ndarray], np.ndarray],
) -> tuple[np.ndarray, np.ndarray]:
    """The step with the rotation task added in the null space of the tip's, and the projector
    (n, n) onto the null space of both (where the secondary pushes go).

    The projectors are exact (from the pseudo-inverse) for both methods: the damped inverse's
    I - J^T (J J^T + lambda^2 I)^-1 J lets a secondary task move the tip along a singular
    direction (the straight arm at home), where the tip's task is weakest; ``invert`` (damped
    for ``dls``) only solves the rotation task inside that null space. Where that null space
    leaves the rotation only rounding (:data:`ROUNDING_TASK`), the step and the projector are
    the tip's alone."""
    w = problem.solver.orientation_weight
    error, jac_w = orientation_task(orientation, problem.arm, state.pose)
    jac_r = w * jac_w
    null_tip = np.eye(len(dphi)) - pseudo_inverse(jac) @ jac
    restricted = jac_r @ null_tip
    if np.sum(restricted * restricted) < ROUNDING_TASK * ROUNDING_TASK * np.sum(
        jac_r * jac_r
    ):  # only rounding is left to turn
        return dphi, null_tip
    dphi = dphi + invert(restricted) @ (rotation_displacement(problem, error) - jac_r @ dphi)
    return dphi, null_tip - pseudo_inverse(restricted) @ restricted


def linear_step(
    problem: Problem,
    state: ArmState,
    goal: np.ndarray,
    invert: Callable[[np.ndarray], np.ndarray],
    orientation: Orientation | None = None,
    stackable: bool = False,
) -> Step:
    """One frame of Algorithm 2 with obstacle and limit terms, for a given inverse (of a
    (3, n) Jacobian or a stack of them), and the rotation task second when the goal has an
    ``orientation`` (or, ``stackable`` and :func:`stacks_the_pose_task`, both as one task)."""
    s = problem.solver
    phi, pose = state.phi, state.pose
    jac = jacobian_of_tip(problem, phi, pose)
    target = task_displacement(problem, pose.tip, goal)
    if orientation is not None and stackable and stacks_the_pose_task(problem, orientation):
        error, jac_w = orientation_task(orientation, problem.arm, pose)
        jac = np.concatenate([jac, s.orientation_weight * jac_w])
        target = np.concatenate([target, rotation_displacement(problem, error)])
        orientation = None  # the rotation is in the task: the pushes go into the null space of both
    jac_inv = invert(jac)
    dphi = jac_inv @ target

    secondary = limit_push(problem, phi)
    cl = state.clearance
    if cl is not None and np.any(cl.d < problem.obstacles.influence):
        obstacles = problem.obstacles
        push = (
            s.beta * s.w_obstacles * repulsion(cl.d, obstacles.influence) * problem.capsules.moving[:, None]
        )  # the base: never pushed
        pushing = np.nonzero(push)
        on_links = pushing[0] != cl.tip
        inverses = iter(
            invert(jacobian_of_capsule_point(problem, phi, pose, pushing[0][on_links], cl.t[pushing][on_links]))
        )
        for part, obs in zip(*pushing):
            v = push[part, obs] * cl.normal[part, obs]
            if part == cl.tip:  # the tip itself: the notes' term, in task space
                dphi = dphi + jac_inv[:, :3] @ v
            else:
                pushed = next(inverses) @ v
                secondary = pushed if secondary is None else secondary + pushed
    gaps = state.self_gaps
    if gaps is not None and gaps.least < self_influence(
        problem
    ):  # the arm's own pairs: pushed apart along their normal
        push = s.beta * s.w_obstacles * repulsion(gaps.d, self_influence(problem))
        which = np.nonzero(push)[0]
        if len(which):
            relative = self_pair_jacobians(problem, phi, pose, gaps, which)
            for k, inverse in zip(which, invert(relative)):
                pushed = inverse @ (push[k] * gaps.normal[k])
                secondary = pushed if secondary is None else secondary + pushed
    if orientation is not None:
        dphi, null_both = orientation_in_null_space(problem, state, orientation, jac, dphi, invert)
        if secondary is not None:
            dphi = dphi + null_both @ secondary
    elif secondary is not None:
        dphi = dphi + secondary - jac_inv @ (jac @ secondary)
    return Step(dphi=dphi)


def stacks_the_pose_task(problem: Problem, orientation: Orientation) -> bool:
    """Whether a ``pinv`` step solves the position and the orientation as one stacked task
    [J_v; w B J_w]: in a solve to convergence (``tunables.ik.solving``, :func:`armanim.motion.ik.solving_problem`)
    of a goal the arm can hold (:func:`armanim.motion.orientation.holds_orientation`, judged once per
    arm and kind of goal). Elsewhere the rotation comes second (:func:`orientation_in_null_space`).

    Where the stacked Jacobian has full row rank, its pseudo-inverse step is the task-priority
    step (both are the least-norm solution of the two tasks at once), in one SVD instead of
    four. ``dls`` keeps the priority: its damping on the stacked task measured twice the steps."""
    if not problem.tunables.ik.solving:
        return False
    return arm_holds_orientation(problem, orientation)


def arm_holds_orientation(problem: Problem, orientation: Orientation) -> bool:
    """:func:`armanim.motion.orientation.holds_orientation` of the problem's arm and this kind of
    goal, judged once per arm and kind (kept on the arm)."""
    memo = problem.arm.__dict__.setdefault(
        "_holds_orientation", {}
    )  # a cache of a fact of the arm: it stays what it was
    if orientation.rows not in memo:
        memo[orientation.rows] = holds_orientation(problem.arm, orientation)
    return cast(bool, memo[orientation.rows])


def pinv_step(problem: Problem, state: ArmState, goal: np.ndarray, orientation: Orientation | None = None) -> Step:
    """``pinv``: the course notes' Algorithm 2 with the pseudo-inverse (Eqs. 19-20)."""
    return linear_step(problem, state, goal, pseudo_inverse, orientation, stackable=True)


def dls_step(problem: Problem, state: ArmState, goal: np.ndarray, orientation: Orientation | None = None) -> Step:
    """``dls``: damped least squares with ``solver.damping``; smooth near singular poses."""
    damping = problem.solver.damping
    return linear_step(problem, state, goal, lambda jac: damped_inverse(jac, damping), orientation)
