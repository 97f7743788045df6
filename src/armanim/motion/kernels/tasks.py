"""The tasks and pushes of a compiled step: the pose task (position, rotation or tool axis), the
joint limits' push, the obstacles' and the arm's own pairs' pushes, and the proposals of the IK
attempt (:func:`attempt_proposal`) and of the frame (:func:`frame_proposal`) made of them, both of
the same stages in the same order: the tip's task (:func:`tip_task`: :func:`tip_rows`,
:func:`tip_target`, the method's inverse; the attempt's stacked with the rotation's where the arm
holds every orientation), the pushes (the limits', and the pairs' or the obstacles': summed in
each proposal's own order), then (:func:`pushed_in_null_space`) the rotation
second in priority with the pushes in the null space of both (:func:`rotation_task`,
:func:`rotation_second`: where only rounding is left of the rotation, the frame takes the tip's
step and the attempt hands it back), or the pushes in the tip task's null space
(:func:`null_push`).

The numpy references: :func:`armanim.motion.solvers.linear.linear_step`,
:func:`~armanim.motion.solvers.linear.orientation_in_null_space`,
:func:`~armanim.motion.solvers.linear.limit_push`, :func:`armanim.motion.orientation.orientation_residual`.
A prismatic joint's columns are its axis w_j and no turn wherever the world ``axes`` carry its
kind (:func:`armanim.arm.kernel.joint_slides`). Pure core: numpy and numba only, radians (metres
for a prismatic joint).
"""

from __future__ import annotations

import math

import numpy as np

from armanim.arm.kernel import INLINE, JIT, _log, compiled, joint_slides
from armanim.motion.kernels.layout import (
    ANGLE_TOL,
    BETA,
    DAMPING,
    DONE,
    HANDED_BACK,
    KIND,
    MARGIN,
    MAX_STEP,
    METHOD,
    NUMERICAL,
    PINV,
    SELF_INFLUENCE,
    SLACK,
    STACKED,
    TOL,
    W_LIMITS,
    W_OBSTACLES,
    WEIGHT,
    FrameGoal,
    Near,
    Pairs,
    Placed,
)
from armanim.motion.kernels.linalg import damped, invert, matvec, pseudo_inverse
from armanim.motion.solvers.linear import CLOSEST_GAP, ROUNDING_TASK
from armanim.world.compiled import pair_jacobians


@compiled(**INLINE)
def least_axis(v0: float, v1: float, v2: float) -> int:
    """The coordinate axis least along (v0, v1, v2) (numpy's argmin of |v|: the first of equals)."""
    best = 0
    least = abs(v0)
    if abs(v1) < least:
        best, least = 1, abs(v1)
    if abs(v2) < least:
        best = 2
    return best


@compiled(**INLINE)
def cross_axis(v: np.ndarray, axis: int, out: np.ndarray) -> None:
    """v x e_axis into ``out``."""
    e0 = 1.0 if axis == 0 else 0.0
    e1 = 1.0 if axis == 1 else 0.0
    e2 = 1.0 if axis == 2 else 0.0
    out[0] = v[1] * e2 - v[2] * e1
    out[1] = v[2] * e0 - v[0] * e2
    out[2] = v[0] * e1 - v[1] * e0


@compiled(**JIT)
def orientation_residual(
    kind: int, goal_rot: np.ndarray, goal_axis: np.ndarray, tool: np.ndarray, out: np.ndarray
) -> None:
    """r (3,): log(R_g R^T) for a rotation, the alignment vector of the tool's z onto the goal's
    axis for a tool axis (:func:`armanim.motion.orientation.orientation_residual`)."""
    if kind == 1:
        rel = np.empty((3, 3))
        for a in range(3):
            for b in range(3):
                rel[a, b] = goal_rot[a, 0] * tool[b, 0] + goal_rot[a, 1] * tool[b, 1] + goal_rot[a, 2] * tool[b, 2]
        _log(rel, out)
        return
    z = np.empty(3)
    for a in range(3):
        z[a] = tool[a, 2]
    n0 = z[1] * goal_axis[2] - z[2] * goal_axis[1]
    n1 = z[2] * goal_axis[0] - z[0] * goal_axis[2]
    n2 = z[0] * goal_axis[1] - z[1] * goal_axis[0]
    sin = math.sqrt(n0 * n0 + n1 * n1 + n2 * n2)
    cos = z[0] * goal_axis[0] + z[1] * goal_axis[1] + z[2] * goal_axis[2]
    angle = math.atan2(sin, cos)
    if sin < 1e-12:
        cross_axis(z, least_axis(z[0], z[1], z[2]), out)
    else:
        out[0], out[1], out[2] = n0, n1, n2
    length = math.sqrt(out[0] * out[0] + out[1] * out[1] + out[2] * out[2])
    for a in range(3):
        out[a] = angle * (out[a] / length)


@compiled(**JIT)
def orientation_rows(kind: int, tool: np.ndarray, rows: np.ndarray) -> int:
    """The goal's rotation directions B into ``rows`` (3, 3): the identity for a rotation (3
    rows), the two directions perpendicular to the tool's z for a tool axis
    (:func:`armanim.motion.orientation.orientation_rows`); returns their count."""
    if kind == 1:
        for a in range(3):
            for b in range(3):
                rows[a, b] = 1.0 if a == b else 0.0
        return 3
    z = np.empty(3)
    for a in range(3):
        z[a] = tool[a, 2]
    first = np.empty(3)
    cross_axis(z, least_axis(z[0], z[1], z[2]), first)
    length = math.sqrt(first[0] * first[0] + first[1] * first[1] + first[2] * first[2])
    for a in range(3):
        first[a] /= length
        rows[0, a] = first[a]
    rows[1, 0] = z[1] * first[2] - z[2] * first[1]
    rows[1, 1] = z[2] * first[0] - z[0] * first[2]
    rows[1, 2] = z[0] * first[1] - z[1] * first[0]
    return 2


@compiled(**JIT)
def progress_measure(
    floats: np.ndarray,
    kind: int,
    goal: np.ndarray,
    goal_rot: np.ndarray,
    goal_axis: np.ndarray,
    points: np.ndarray,
    tool: np.ndarray,
    residual: np.ndarray,
    errors: np.ndarray,
) -> float:
    """|e - g|, the angle |r| (into ``errors`` (2,)) and the progress measure max(|e - g|, |r| tol /
    angle_tol) (:func:`armanim.motion.ik.pose_errors`); the residual r into ``residual``."""
    n = points.shape[0] - 1
    s = 0.0
    for a in range(3):
        d = points[n, a] - goal[a]
        s += d * d
    distance = math.sqrt(s)
    errors[0] = distance
    if kind == 0:
        errors[1] = 0.0
        return distance
    orientation_residual(kind, goal_rot, goal_axis, tool, residual)
    angle = math.sqrt(residual[0] * residual[0] + residual[1] * residual[1] + residual[2] * residual[2])
    errors[1] = angle
    scaled: float = angle * (floats[TOL] / floats[ANGLE_TOL])
    return max(distance, scaled)


@compiled(**INLINE)
def capped(v: np.ndarray, scale: float, cap: float) -> None:
    """v <- scale v, its length capped at ``cap`` (:func:`~armanim.motion.solvers.common.task_displacement`)."""
    s = 0.0
    for a in range(v.shape[0]):
        v[a] = scale * v[a]
        s += v[a] * v[a]
    length = math.sqrt(s)
    if length > cap:
        for a in range(v.shape[0]):
            v[a] = v[a] * (cap / length)


@compiled(**INLINE)
def step_shrink(caps: np.ndarray, dphi: np.ndarray) -> float:
    """The scale that brings the proposal ``dphi`` (n,; finite, not all 0) within each joint's
    cap ``caps`` (n,: radians, metres for a prismatic joint), at most 1: min(1, min_j cap_j / |dphi_j|)
    (:func:`armanim.motion.filter.barrier.safe_step`; with equal caps the numbers of
    min(1, cap / max_j |dphi_j|), rounding being monotone)."""
    shrink = 1.0
    for j in range(dphi.shape[0]):
        shrink = min(shrink, caps[j] / max(abs(dphi[j]), 1e-300))
    return shrink


@compiled(**INLINE)
def step_bounds(phi: float, lower: float, upper: float, cap: float, gamma: float, buffer: float) -> tuple[float, float]:
    """One joint's bounds on its step in the filter (:func:`armanim.motion.filter.barrier.joint_bounds`):
    the joint-step cap and, for a limited joint, the velocity damper toward each limit less its
    buffer; each bound no nearer than 0 (a joint inside its buffer may stand still)."""
    low, high = -cap, cap
    if lower > -np.inf:
        low = max(-cap, -gamma * (phi - (lower + buffer)))
        high = min(cap, gamma * ((upper - buffer) - phi))
    return min(low, 0.0), max(high, 0.0)


@compiled(**JIT)
def limit_push(floats: np.ndarray, phi: np.ndarray, lower: np.ndarray, upper: np.ndarray, push: np.ndarray) -> bool:
    """The joint-limit push z into ``push``; False when no joint is within the margin of a limit
    (:func:`armanim.motion.solvers.linear.limit_push`)."""
    margin = floats[MARGIN]
    near = False
    for j in range(phi.shape[0]):
        if phi[j] - lower[j] < margin or upper[j] - phi[j] < margin:
            near = True
    if not near:
        return False
    scale = floats[BETA] * floats[W_LIMITS]
    for j in range(phi.shape[0]):
        push[j] = scale * (repulsion(phi[j] - lower[j], margin) - repulsion(upper[j] - phi[j], margin))
    return True


@compiled(**INLINE)
def repulsion(gap: float, influence: float) -> float:
    """R (R / gap - 1) inside the influence, else 0 (:func:`armanim.motion.solvers.linear.repulsion`)."""
    if not (gap > 0.0 and gap < influence):
        return 0.0
    return influence * (influence / max(gap, influence * 1e-12) - 1.0)


@compiled(**INLINE)
def null_space_task(
    jac: np.ndarray, pinv_tip: np.ndarray, jac_r: np.ndarray, null: np.ndarray, restricted: np.ndarray
) -> tuple[float, float]:
    """The rotation task second in priority: the tip task's null-space projector I - J^+ J into
    ``null`` (n, n) (``jac`` its first 3 rows the tip's, ``pinv_tip`` (n, 3) their
    pseudo-inverse), and the rotation rows ``jac_r`` (k, n) restricted to it, jac_r (I - J^+ J),
    into ``restricted`` (k, n). Returns |restricted|_F^2 and |jac_r|_F^2, whose ratio tells a
    task with only rounding left (:data:`ROUNDING_TASK`)."""
    n = null.shape[0]
    for i in range(n):
        for j in range(n):
            null[i, j] = (1.0 if i == j else 0.0) - (
                pinv_tip[i, 0] * jac[0, j] + pinv_tip[i, 1] * jac[1, j] + pinv_tip[i, 2] * jac[2, j]
            )
    left = 0.0
    size = 0.0
    for i in range(restricted.shape[0]):
        for j in range(n):
            v = 0.0
            for q in range(n):
                v += jac_r[i, q] * null[q, j]
            restricted[i, j] = v
            left += v * v
            size += jac_r[i, j] * jac_r[i, j]
    return left, size


@compiled(**INLINE)
def tip_rows(points: np.ndarray, axes: np.ndarray, jac: np.ndarray) -> None:
    """The tip's Jacobian into the first 3 rows of ``jac`` (m >= 3, n): column j is w_j x (e - p_j),
    w_j for a prismatic joint (:func:`~armanim.arm.kernel.joint_slides`; :func:`armanim.arm.kinematics.tip_jacobian`)."""
    n = axes.shape[0]
    tip = points.shape[0] - 1
    for j in range(n):
        w0, w1, w2 = axes[j, 0], axes[j, 1], axes[j, 2]
        if joint_slides(axes, j):  # the tip slides along the axis
            jac[0, j], jac[1, j], jac[2, j] = w0, w1, w2
            continue
        l0, l1, l2 = points[tip, 0] - points[j, 0], points[tip, 1] - points[j, 1], points[tip, 2] - points[j, 2]
        jac[0, j] = w1 * l2 - w2 * l1
        jac[1, j] = w2 * l0 - w0 * l2
        jac[2, j] = w0 * l1 - w1 * l0


@compiled(**INLINE)
def tip_target(floats: np.ndarray, points: np.ndarray, goal: np.ndarray, target: np.ndarray) -> None:
    """The tip task's step into the first 3 entries of ``target``: beta (g - e), its length capped
    at ``max_step`` (:func:`~armanim.motion.solvers.common.task_displacement`)."""
    tip = points.shape[0] - 1
    for a in range(3):
        target[a] = goal[a] - points[tip, a]
    capped(target[:3], floats[BETA], floats[MAX_STEP])


@compiled(**INLINE)
def rotation_task(
    floats: np.ndarray, kind: int, tool: np.ndarray, residual: np.ndarray, axes: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The goal's orientation as a task: its rows w B J_w (k, n) (B: :func:`orientation_rows`;
    a prismatic joint's column 0: it does not turn the tool) and its step w B r (k,) (r: the
    ``residual``), capped as the tip's (:func:`~armanim.motion.orientation.orientation_task`)."""
    n = axes.shape[0]
    brows = np.empty((3, 3))
    k = orientation_rows(kind, tool, brows)
    weight = floats[WEIGHT]
    jac_r = np.empty((k, n))
    rot_step = np.empty(k)
    for i in range(k):
        rot_step[i] = weight * (brows[i, 0] * residual[0] + brows[i, 1] * residual[1] + brows[i, 2] * residual[2])
        for j in range(n):  # a prismatic joint does not turn the tool: its column 0
            jac_r[i, j] = (
                0.0
                if joint_slides(axes, j)
                else weight * (brows[i, 0] * axes[j, 0] + brows[i, 1] * axes[j, 1] + brows[i, 2] * axes[j, 2])
            )
    capped(rot_step, floats[BETA], floats[MAX_STEP])
    return jac_r, rot_step


@compiled(**JIT)
def rotation_second(
    floats: np.ndarray,
    method: int,
    jac_r: np.ndarray,
    rot_step: np.ndarray,
    jac: np.ndarray,
    jac_inv: np.ndarray,
    pushed: bool,
    push: np.ndarray,
    dphi: np.ndarray,
) -> int:
    """The rotation task (``jac_r`` (k, n), its step ``rot_step``: :func:`rotation_task`) added to
    ``dphi`` in the null space N of the tip's task ``jac`` (3, n) (``jac_inv``: the method's inverse
    of it), then the push ``push`` (where ``pushed``) in the null space of both
    (:func:`armanim.motion.solvers.linear.orientation_in_null_space`): the exact projectors
    (pseudo-inverses) for both methods, the method's inverse for the rotation. Returns :data:`DONE`;
    :data:`NUMERICAL` where an inverse failed; :data:`HANDED_BACK` where N leaves the rotation only
    rounding (:data:`ROUNDING_TASK`): then the step and the projector are the tip's alone (the
    frame takes that step, the IK attempt hands it back to the numpy path)."""
    n = dphi.shape[0]
    k = jac_r.shape[0]
    pinv_tip = np.empty((n, 3))
    if method == PINV:
        for i in range(n):
            for c in range(3):
                pinv_tip[i, c] = jac_inv[i, c]
    else:
        pseudo_inverse(jac, pinv_tip)  # invert's PINV, called so: a constant method would compile invert once more
    null = np.empty((n, n))  # I - J^+ J, then I - J^+ J - R^+ R
    restricted = np.empty((k, n))
    left, size = null_space_task(jac, pinv_tip, jac_r, null, restricted)
    rounding = left < ROUNDING_TASK * ROUNDING_TASK * size
    if not rounding:
        inverse = np.empty((n, k))
        if not invert(restricted, method, floats[DAMPING], inverse):
            return NUMERICAL
        wanted = np.empty(k)
        for i in range(k):
            v = 0.0
            for j in range(n):
                v += jac_r[i, j] * dphi[j]
            wanted[i] = rot_step[i] - v
        for j in range(n):
            v = 0.0
            for i in range(k):
                v += inverse[j, i] * wanted[i]
            dphi[j] = dphi[j] + v
        if pushed:
            if method != PINV:
                pseudo_inverse(restricted, inverse)
            for i in range(n):
                for j in range(n):
                    v = 0.0
                    for q in range(k):
                        v += inverse[i, q] * restricted[q, j]
                    null[i, j] -= v
    if pushed:
        for i in range(n):
            v = 0.0
            for j in range(n):
                v += null[i, j] * push[j]
            dphi[i] = dphi[i] + v
    return HANDED_BACK if rounding else DONE


@compiled(**INLINE)
def null_push(jac: np.ndarray, jac_inv: np.ndarray, push: np.ndarray, dphi: np.ndarray) -> None:
    """dphi + (I - J^+ J) z: the push z (n,) in the null space of the task ``jac`` (m, n), whose
    method's inverse is ``jac_inv`` (n, m)."""
    n = dphi.shape[0]
    task = np.empty(jac.shape[0])
    matvec(jac, push, task)
    back = np.empty(n)
    matvec(jac_inv, task, back)
    for j in range(n):
        dphi[j] = dphi[j] + push[j] - back[j]


@compiled(**INLINE)
def attempt_proposal(
    floats: np.ndarray,
    ints: np.ndarray,
    phi: np.ndarray,
    points: np.ndarray,
    axes: np.ndarray,
    tool: np.ndarray,
    goal: np.ndarray,
    residual: np.ndarray,
    limits: tuple[np.ndarray, np.ndarray],
    pair_push: np.ndarray,
    pairs_push: bool,
    dphi: np.ndarray,
) -> int:
    """The method's step (:func:`armanim.motion.solvers.linear.linear_step` without obstacles; the
    pairs' push ``pair_push`` (n,), where ``pairs_push``, beside the limits' in the null space) into ``dphi``: :data:`DONE`, :data:`NUMERICAL` when its inverse failed, or
    :data:`HANDED_BACK` where the rotation second in priority has only rounding left to act on
    (:data:`ROUNDING_TASK`). The frame's proposal's stages (:func:`frame_proposal`): the tip's task
    (stacked with the rotation's where ``ints[STACKED]``), the pushes, the rotation second.
    ``limits``: the joints' lower and upper limits (n,) each. Inlined into the attempt's loop, which
    calls it each step (the limits as a tuple handed to a compiled call were some 1 % slower)."""
    n = phi.shape[0]
    method = ints[METHOD]
    kind = ints[KIND]
    if kind != 0:
        jac_r, rot_step = rotation_task(floats, kind, tool, residual, axes)
    else:
        jac_r, rot_step = np.empty((0, n)), np.empty(0)
    stacked = ints[STACKED] == 1 and kind != 0
    m = 3 + rot_step.shape[0] if stacked else 3
    jac = np.empty((m, n))
    jac_inv = np.empty((n, m))
    if not tip_task(floats, method, points, axes, goal, jac_r, rot_step, jac, jac_inv, dphi):
        return NUMERICAL
    push = np.empty(n)
    pushed = limit_push(floats, phi, limits[0], limits[1], push)
    if pairs_push:
        for j in range(n):
            push[j] = (push[j] if pushed else 0.0) + pair_push[j]
        pushed = True
    second = kind != 0 and not stacked
    return pushed_in_null_space(floats, method, jac, jac_inv, jac_r, rot_step, second, pushed, push, dphi)


@compiled(**INLINE)
def tip_task(
    floats: np.ndarray,
    method: int,
    points: np.ndarray,
    axes: np.ndarray,
    goal: np.ndarray,
    jac_r: np.ndarray,
    rot_step: np.ndarray,
    jac: np.ndarray,
    jac_inv: np.ndarray,
    dphi: np.ndarray,
) -> bool:
    """The proposals' first stage: the tip's task, stacked with the rotation's where ``jac`` has
    more than 3 rows, through the method's inverse.

    Parameters
    ----------
    floats : (FLOATS,) array
        The settings: ``beta``, ``max_step``, DLS's ``damping``.
    method : int
        ``PINV`` or ``DLS``.
    points, axes : arrays
        The joints' points (n + 1, 3) (metres) and world axes (n, 3).
    goal : (3,) array
        The tip's goal, metres.
    jac_r, rot_step : arrays
        The rotation task's rows (k, n) and step (k,) (:func:`rotation_task`); its first m - 3
        stacked under the tip's.
    jac : (m, n) array
        Filled with the task's rows: the tip's (:func:`tip_rows`), then the rotation's.
    jac_inv : (n, m) array
        Filled with the method's inverse of ``jac``.
    dphi : (n,) array
        Filled with ``jac_inv`` times the task's step, radians (metres for a prismatic joint).

    Returns
    -------
    bool
        False where the inverse failed.
    """
    n = dphi.shape[0]
    m = jac.shape[0]
    target = np.empty(m)
    tip_rows(points, axes, jac)
    tip_target(floats, points, goal, target)
    for i in range(m - 3):
        target[3 + i] = rot_step[i]
        for j in range(n):
            jac[3 + i, j] = jac_r[i, j]
    if not invert(jac, method, floats[DAMPING], jac_inv):
        return False
    matvec(jac_inv, target, dphi)
    return True


@compiled(**INLINE)
def pushed_in_null_space(
    floats: np.ndarray,
    method: int,
    jac: np.ndarray,
    jac_inv: np.ndarray,
    jac_r: np.ndarray,
    rot_step: np.ndarray,
    second: bool,
    pushed: bool,
    push: np.ndarray,
    dphi: np.ndarray,
) -> int:
    """The proposals' last stage: the rotation task second in priority and the push in the null
    space of both (:func:`rotation_second`, where ``second``), else the push in the tip task's
    null space (:func:`null_push`), added to ``dphi`` (n,).

    Parameters
    ----------
    floats : (FLOATS,) array
        The settings.
    method : int
        ``PINV`` or ``DLS``.
    jac, jac_inv : arrays
        The task's rows (m, n) and the method's inverse of them (n, m) (:func:`tip_task`); m is 3
        where ``second``.
    jac_r, rot_step : arrays
        The rotation task's rows (k, n) and step (k,) (:func:`rotation_task`).
    second : bool
        The rotation second in priority (the attempt's unless stacked; the frame's where the
        goal has an orientation).
    pushed : bool
        Whether ``push`` (n,) holds a push (radians; metres for a prismatic joint).
    push : (n,) array
        The pushes.
    dphi : (n,) array
        The tip task's step, updated.

    Returns
    -------
    int
        As :func:`rotation_second`: :data:`DONE`, :data:`NUMERICAL` or :data:`HANDED_BACK`.
    """
    if second:
        return rotation_second(floats, method, jac_r, rot_step, jac, jac_inv, pushed, push, dphi)
    if pushed:
        null_push(jac, jac_inv, push, dphi)
    return DONE


@compiled(**JIT)
def self_pair_push(
    floats: np.ndarray,
    method: int,
    gaps: np.ndarray,
    points: np.ndarray,
    axes: np.ndarray,
    caps_link: np.ndarray,
    ends: np.ndarray,
    near: np.ndarray,
    first: np.ndarray,
    second: np.ndarray,
    push: np.ndarray,
) -> int:
    """The pairs' push of the numpy step (:func:`armanim.motion.solvers.linear.linear_step`) into
    ``push`` (n,): for each pair whose gap d is inside the influence R (``self_influence``), the
    method's inverse of J_A - J_B times beta w_obstacles R (R / d - 1) along the pair's normal,
    summed. Returns 1 when some pair pushes, 0 when none, -1 when a gap is within rounding of 0
    (where the push's size turns on the gap's last bits: the numpy step takes that one) or an
    inverse fails."""
    n = push.shape[0]
    influence = floats[SELF_INFLUENCE]
    slack = floats[SLACK]
    scale = floats[BETA] * floats[W_OBSTACLES]
    for j in range(n):
        push[j] = 0.0
    which = np.empty(1, dtype=np.int64)
    jac = np.empty((1, 3, n))
    inverse = np.empty((n, 3))
    any_push = 0
    for q in range(gaps.shape[0]):
        d = gaps[q]
        if not d < influence:
            continue
        if abs(d) <= slack:
            return -1
        size = scale * repulsion(d, influence)
        if size == 0.0:
            continue
        which[0] = q
        pair_jacobians(points, axes, ends[0], ends[1], caps_link, first, second, near[:, 0], near[:, 1], which, jac)
        if method == PINV:
            pseudo_inverse(jac[0], inverse)
        elif not damped(jac[0], floats[DAMPING], inverse):
            return -1
        for j in range(n):
            push[j] += size * (inverse[j, 0] * near[q, 2] + inverse[j, 1] * near[q, 3] + inverse[j, 2] * near[q, 4])
        any_push = 1
    return any_push


@compiled(**JIT)
def point_jacobian(points: np.ndarray, axes: np.ndarray, link: int, q: np.ndarray, jac: np.ndarray) -> None:
    """(3, n) Jacobian of the world point ``q`` carried by joint ``link``'s frame into ``jac``:
    column j is w_j x (q - p_j) for j <= link (w_j for a prismatic joint: :func:`~armanim.arm.kernel.joint_slides`),
    0 after (:func:`armanim.arm.kinematics.point_jacobian`)."""
    n = axes.shape[0]
    for j in range(n):
        if j <= link and joint_slides(axes, j):
            jac[0, j], jac[1, j], jac[2, j] = axes[j, 0], axes[j, 1], axes[j, 2]
        elif j <= link:
            l0, l1, l2 = q[0] - points[j, 0], q[1] - points[j, 1], q[2] - points[j, 2]
            w0, w1, w2 = axes[j, 0], axes[j, 1], axes[j, 2]
            jac[0, j] = w1 * l2 - w2 * l1
            jac[1, j] = w2 * l0 - w0 * l2
            jac[2, j] = w0 * l1 - w1 * l0
        else:
            jac[0, j] = 0.0
            jac[1, j] = 0.0
            jac[2, j] = 0.0


@compiled(**JIT)
def goal_rotation_task(
    floats: np.ndarray,
    kind: int,
    goal_rot: np.ndarray | None,
    goal_axis: np.ndarray | None,
    tool: np.ndarray,
    axes: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """The frame's goal orientation as a task (:func:`rotation_task`, its residual from the tool
    frame ``tool`` (3, 3)): its rows (k, n) and step (k,); none (0 rows) where ``kind`` is 0.
    ``goal_rot`` and ``goal_axis`` None: a scene without an orientation anywhere, whose machine
    code leaves the rotation task out."""
    if goal_rot is None or goal_axis is None or kind == 0:
        return np.empty((0, axes.shape[0])), np.empty(0)
    residual = np.empty(3)
    orientation_residual(kind, goal_rot, goal_axis, tool, residual)
    return rotation_task(floats, kind, tool, residual, axes)


@compiled(**JIT)
def frame_proposal(
    floats: np.ndarray,
    method: int,
    phi: np.ndarray,
    limits: tuple[np.ndarray, np.ndarray],
    placed: Placed,
    near: Near,
    influence: np.ndarray,
    pairs: Pairs,
    least: float,
    goal: FrameGoal,
    tool: np.ndarray,
    dphi: np.ndarray,
) -> bool:
    """:func:`armanim.motion.solvers.linear.linear_step` into ``dphi``, the goal's orientation
    second in priority, in the null space of the tip's task
    (:func:`~armanim.motion.solvers.linear.orientation_in_null_space`).

    Parameters
    ----------
    floats : (FLOATS,) array
        The settings (:mod:`~armanim.motion.kernels.layout`).
    method : int
        :data:`~armanim.motion.kernels.layout.PINV` or :data:`~armanim.motion.kernels.layout.DLS`.
    phi : (n,) array
        The joints now, radians (metres for a prismatic joint).
    limits : tuple of two (n,) arrays
        The joints' lower and upper limits.
    placed, near, pairs : tuples of arrays
        The pose now, the obstacles near it, its pairs
        (:data:`~armanim.motion.kernels.layout.Placed`, ``Near``, ``Pairs``).
    influence : (m,) array
        Each obstacle's influence, metres.
    least : float
        The least gap now, metres.
    goal : FrameGoal
        The tip's goal (metres) and its orientation.
    tool : (3, 3) array
        The tool frame now.
    dphi : (n,) array
        Filled with the proposal, radians (metres for a prismatic joint).

    Returns
    -------
    bool
        False where an inverse failed (numpy raises there: the numpy path takes the frame).
    """
    points, axes = placed[0], placed[1]
    position, kind, rotation, axis = goal  # FrameGoal's order
    n = phi.shape[0]
    jac_r, rot_step = goal_rotation_task(floats, kind, rotation, axis, tool, axes)
    jac = np.empty((3, n))
    jac_inv = np.empty((n, 3))
    if not tip_task(floats, method, points, axes, position, jac_r, rot_step, jac, jac_inv, dphi):
        return False
    secondary = np.zeros(n)
    pushed = limit_push(floats, phi, limits[0], limits[1], secondary)
    obstacles = obstacle_pushes(floats, method, placed, near, influence, jac_inv, dphi, secondary)
    if obstacles < 0:
        return False
    by_pairs = pair_pushes(floats, method, placed, pairs, least, secondary)
    if by_pairs < 0:
        return False
    pushed = pushed or obstacles > 0 or by_pairs > 0
    ended = frame_null_space(floats, method, rotation, jac, jac_inv, jac_r, rot_step, pushed, secondary, dphi)
    return ended != NUMERICAL  # HANDED_BACK: only rounding left of the rotation, the tip's step taken


@compiled(**JIT)
def frame_null_space(
    floats: np.ndarray,
    method: int,
    rotation: np.ndarray | None,
    jac: np.ndarray,
    jac_inv: np.ndarray,
    jac_r: np.ndarray,
    rot_step: np.ndarray,
    pushed: bool,
    push: np.ndarray,
    dphi: np.ndarray,
) -> int:
    """The frame's last stage (:func:`pushed_in_null_space`): the rotation second where the goal has
    one (``rot_step`` has rows: :func:`goal_rotation_task`). ``rotation`` None: a scene without an
    orientation anywhere, whose machine code then leaves the rotation task out (numba prunes a
    branch on an argument's None: some 6 % of notes-arm's first compile)."""
    if rotation is None:
        if pushed:
            null_push(jac, jac_inv, push, dphi)
        return DONE
    second = rot_step.shape[0] > 0
    return pushed_in_null_space(floats, method, jac, jac_inv, jac_r, rot_step, second, pushed, push, dphi)


@compiled(**INLINE)
def obstacle_pushes(
    floats: np.ndarray,
    method: int,
    placed: Placed,
    near: Near,
    influence: np.ndarray,
    jac_inv: np.ndarray,
    dphi: np.ndarray,
    secondary: np.ndarray,
) -> int:
    """The obstacles' pushes of :func:`frame_proposal`: each part off the base and obstacle whose
    clearance d (metres) is inside the obstacle's ``influence`` R pushes beta w_obstacles R (R / d - 1)
    along the normal; the tip in task space, through the tip task's inverse ``jac_inv`` (n, 3), into
    ``dphi`` (n,); a link through the method's inverse of its point's Jacobian into ``secondary``
    (n,).

    Returns
    -------
    int
        1 where a link pushes, 0 where none does, -1 where an inverse failed.
    """
    points, axes, a, b, link = placed
    d, t, normal = near
    n = dphi.shape[0]
    gain = floats[BETA] * floats[W_OBSTACLES]
    damping = floats[DAMPING]
    parts = d.shape[0]
    q = np.empty(3)
    pj = np.empty((3, n))
    pinv = np.empty((n, 3))
    v = np.empty(3)
    pushed = 0
    for part in range(parts):
        if part < parts - 1 and link[part] < 0:  # on the base: never pushed
            continue
        for col in range(d.shape[1]):
            r = influence[col]
            g = d[part, col]
            if not (g > 0.0 and g < r):
                continue
            push = gain * (r * (r / max(g, r * CLOSEST_GAP) - 1.0))
            if push == 0.0:
                continue
            for i in range(3):
                v[i] = push * normal[part, col, i]
            if part == parts - 1:  # the tip itself: in task space
                for j in range(n):
                    dphi[j] = dphi[j] + (jac_inv[j, 0] * v[0] + jac_inv[j, 1] * v[1] + jac_inv[j, 2] * v[2])
                continue
            f = t[part, col]
            for i in range(3):
                q[i] = a[part, i] + f * (b[part, i] - a[part, i])
            point_jacobian(points, axes, link[part], q, pj)
            pushed = pushed_through(pj, method, damping, v, pinv, secondary)
            if pushed < 0:
                return pushed
    return pushed


@compiled(**INLINE)
def pair_pushes(
    floats: np.ndarray, method: int, placed: Placed, pairs: Pairs, least: float, secondary: np.ndarray
) -> int:
    """The arm's own pairs' pushes of :func:`frame_proposal` into ``secondary`` (n,): each pair
    whose gap d (metres) is inside the influence R (``self_influence``) pushes
    beta w_obstacles R (R / d - 1) along its normal, through the method's inverse of
    J_A - J_B; none where the least gap ``least`` (metres) is not inside R.

    Returns
    -------
    int
        1 where a pair pushes, 0 where none does, -1 where an inverse failed.
    """
    points, axes, a, b, link = placed
    first, second, gap, t, s, normal = pairs
    reach = floats[SELF_INFLUENCE]
    if first.shape[0] == 0 or not least < reach:
        return 0
    n = secondary.shape[0]
    gain = floats[BETA] * floats[W_OBSTACLES]
    damping = floats[DAMPING]
    qa = np.empty(3)
    qb = np.empty(3)
    ja = np.empty((3, n))
    jb = np.empty((3, n))
    pinv = np.empty((n, 3))
    v = np.empty(3)
    pushed = 0
    for p in range(first.shape[0]):
        g = gap[p]
        if not (g > 0.0 and g < reach):
            continue
        push = gain * (reach * (reach / max(g, reach * CLOSEST_GAP) - 1.0))
        if push == 0.0:
            continue
        fa, fb = first[p], second[p]
        for i in range(3):
            qa[i] = a[fa, i] + t[p] * (b[fa, i] - a[fa, i])
            qb[i] = a[fb, i] + s[p] * (b[fb, i] - a[fb, i])
        point_jacobian(points, axes, link[fa], qa, ja)
        point_jacobian(points, axes, link[fb], qb, jb)
        for i in range(3):
            for j in range(n):
                ja[i, j] -= jb[i, j]
            v[i] = push * normal[p, i]
        pushed = pushed_through(ja, method, damping, v, pinv, secondary)
        if pushed < 0:
            break
    return pushed


@compiled(**JIT)
def pushed_through(
    jac: np.ndarray, method: int, damping: float, v: np.ndarray, inverse: np.ndarray, secondary: np.ndarray
) -> int:
    """``secondary`` (n,) += J^+ ``v``, J^+ the method's inverse (into ``inverse`` (n, 3)) of the
    point's Jacobian ``jac`` (3, n) (``damping``: DLS's lambda).

    Returns
    -------
    int
        1 (pushed), or -1 where the inverse failed (``secondary`` untouched): the pushes' answer
        as :func:`obstacle_pushes` and :func:`pair_pushes` give it.
    """
    if not invert(jac, method, damping, inverse):
        return -1
    for j in range(secondary.shape[0]):
        secondary[j] += inverse[j, 0] * v[0] + inverse[j, 1] * v[1] + inverse[j, 2] * v[2]
    return 1
