"""One attempt of a pose solve with ``pinv`` or ``dls``, compiled (numba): the whole loop of
steps in one call, where the safety filter's only rows are the joints' own bounds.

:func:`armanim.motion.ik.solve_pose`'s attempt takes steps from a start until the pose is
within tolerance, the attempt stalls or its steps run out. Each step is the method's
proposal (:func:`armanim.motion.solvers.linear.linear_step`) through the filter
(:func:`armanim.motion.solvers.barrier.safe_step`); in numpy and Python that is some 500 calls
and a few hundred microseconds a step. Here the same step is written as loops over small
arrays, with the kinematics of :mod:`armanim.arm.kernel`:

- the proposal: the Jacobian, the position task (and the rotation task: stacked into one
  pseudo-inverse where the arm holds every orientation, else second in priority, in the
  position's null space), the joint-limit push in the null space;
- the pseudo-inverse from a one-sided Jacobi SVD with the same cut-off as
  :func:`armanim.arm.linalg.pseudo_inverse` (singular values below ``PINV_RTOL`` times the
  largest count as zero), the damped inverse J^T (J J^T + lambda^2 I)^-1 by Gaussian
  elimination with partial pivoting, as LAPACK's ``gesv``;
- the filter: the proposal scaled to the joint-step cap, clipped to the joints' velocity
  damper (the filter's QP when its only rows are bounds: its answer is the clip), the limits
  checked exactly, halved when they fail;
- the progress measure and the stall test of the attempt;
- the arm's own pairs: each pair's push inside its influence (``self_influence``: the method's
  inverse of J_A - J_B, in the null space with the limits'), and the filter's rows of the pairs
  near enough for the step, n . (J_A - J_B) dPhi >= -gamma (d - d_kept); where the proposal
  breaks one, the filter's QP (joint bounds and those rows) is solved exactly in the call by a
  dual active-set method (:func:`_closest_step`), relaxed as the numpy filter relaxes it where
  no step meets the rows. The numpy filter solves it with DAQP, whose answer meets the KKT
  conditions to its tolerance (some 1e-7): there the two steps differ by up to some 1e-5 rad.
  Each pair's gap is bounded from below as the arm moves (a step dPhi changes it by at most
  ``pair_lever_rows @ |dPhi|``); only when a bound is too low to show a pair far are the
  pairs' gaps computed (:func:`armanim.world.compiled.segment_segment_pairs`).

Where the numpy path would do what the call cannot tell the same way, the call hands the
attempt back, at the pose it has reached and with its counters, so that the numpy path takes
the next step: a pair's gap within rounding of 0 (its push turns on the gap's last bits), a QP
whose active rows turn dependent, a step's exact check too near its floor to tell, a rotation
second in priority with only rounding left. The callers use it only without obstacles and with
the analytic Jacobian.

The numbers are the numpy path's to rounding where no pair's row is active in the filter (the
tests hold the iterates to 1e-9 there, and the steps where one is active to the QP's KKT
conditions): the same formulas, other summation orders. Pure core:
numpy and numba only, radians.
"""

from __future__ import annotations

import math
from typing import NamedTuple, cast

import numpy as np

from armanim.arm.kernel import _capsule_ends_one, _forward_one, _jacobian, _log, compiled, packed_chain
from armanim.arm.linalg import PINV_RTOL
from armanim.motion.cost import self_influence
from armanim.motion.orientation import Orientation
from armanim.motion.problem import Problem
from armanim.motion.solvers.barrier import VIOLATION, kept_self_clearance, limit_buffer
from armanim.motion.solvers.linear import ROUNDING_TASK
from armanim.world.compiled import (
    _points_apart,
    _segments_apart,
    link_twists,
    pair_jacobians,
    pair_rate,
    pair_row,
    segment_box_pairs_of_segments,
)

_JIT = dict(error_model="numpy", nogil=True)
_INLINE = dict(inline="always", **_JIT)

DONE, NUMERICAL, HANDED_BACK = 0, 1, 2
"""How a compiled attempt ended: by the attempt's own tests, on a proposal that was not finite,
or handed back to the numpy path (see the module docstring)."""

PINV, DLS = 0, 1
"""The compiled steps: the pseudo-inverse and the damped least-squares inverse."""

(TOL, ANGLE_TOL, WEIGHT, BETA, MAX_STEP, MAX_JOINT_STEP, DAMPING, MARGIN, BUFFER, GAMMA, W_LIMITS,
 SELF_CLEARANCE, KEPT_SELF, SELF_INFLUENCE, SLACK, W_OBSTACLES, FLOATS) = range(17)
"""Places of the settings in the kernel's float array (:func:`_settings`)."""

METHOD, STACKED, STEPS_CAP, STALL, HALVINGS, KIND, STEPS, SINCE_BEST, INTS = range(9)
"""Places in the kernel's int array: the step (:data:`PINV`, :data:`DLS`), whether the pose task
is stacked, the attempt's steps, the stall window, the filter's halvings, the orientation's kind
(0 none, 1 a rotation, 2 a tool axis), and the attempt's counters so far: its steps and the
steps since its best progress (the best progress itself is the call's ``best_so_far``, NaN at
the attempt's start)."""

JACOBI_SWEEPS = 60
"""Most sweeps of the one-sided Jacobi SVD (a 6 x 7 Jacobian takes 5 to 8)."""

WELL_CONDITIONED = 1e5
"""A Jacobian is inverted by its normal equations when trace(G) |G^-1|_F, a bound on its
condition number squared (G = J J^T or J^T J), is at most this: then every singular value is far
above the pseudo-inverse's cut-off, and the normal equations' rounding (kappa^2 eps) is below
1e-10."""


# ----------------------------------------------------------------------------- small linear algebra


@compiled(**_JIT)
def _orthogonalise(a: np.ndarray, w: np.ndarray) -> None:
    """One-sided Jacobi (Hestenes): rotates the columns of ``a`` (r, c) until they are
    orthogonal, the same rotations applied to the columns of ``w`` (c, c, orthogonal), so that
    a_in w_in^T = a_out w_out^T. The columns' lengths are then the singular values, each to
    high relative accuracy."""
    r, c = a.shape
    for _ in range(JACOBI_SWEEPS):
        rotated = False
        for i in range(c - 1):
            for j in range(i + 1, c):
                alpha = 0.0
                beta = 0.0
                gamma = 0.0
                for k in range(r):
                    alpha += a[k, i] * a[k, i]
                    beta += a[k, j] * a[k, j]
                    gamma += a[k, i] * a[k, j]
                if gamma == 0.0 or abs(gamma) <= 1e-15 * math.sqrt(alpha) * math.sqrt(beta):
                    continue
                rotated = True
                zeta = (beta - alpha) / (2.0 * gamma)
                t = (1.0 if zeta >= 0.0 else -1.0) / (abs(zeta) + math.hypot(1.0, zeta))
                cs = 1.0 / math.sqrt(1.0 + t * t)
                sn = cs * t
                for k in range(r):
                    ai = a[k, i]
                    aj = a[k, j]
                    a[k, i] = cs * ai - sn * aj
                    a[k, j] = sn * ai + cs * aj
                for k in range(c):
                    wi = w[k, i]
                    wj = w[k, j]
                    w[k, i] = cs * wi - sn * wj
                    w[k, j] = sn * wi + cs * wj
        if not rotated:
            return


@compiled(**_JIT)
def _pinv_by_normal_equations(jac: np.ndarray, out: np.ndarray) -> bool:
    """J^+ = J^T (J J^T)^-1 (m <= n) or (J^T J)^-1 J^T into ``out`` (n, m), where it can be shown
    cheaply that no singular value is cut (:data:`WELL_CONDITIONED`): the condition number
    squared of G is at most trace(G) |G^-1|_F, since lambda_max <= trace and 1 / lambda_min =
    |G^-1|_2 <= |G^-1|_F. False (``out`` untouched) where it cannot be shown."""
    m, n = jac.shape
    wide = m <= n
    c = m if wide else n
    r = n if wide else m
    g = np.empty((c, c))
    trace = 0.0
    for i in range(c):
        for j in range(i + 1):
            s = 0.0
            for k in range(r):
                s += (jac[i, k] * jac[j, k]) if wide else (jac[k, i] * jac[k, j])
            g[i, j] = s
        trace += g[i, i]
    if not _cholesky(g, c, 0.0):  # G = L L^T, in the lower triangle
        return False
    inverse = np.empty((c, c))  # G^-1, column by column: L y = e_col, L^T x = y
    for col in range(c):
        for i in range(c):
            s = 1.0 if i == col else 0.0
            for k in range(i):
                s -= g[i, k] * inverse[k, col]
            inverse[i, col] = s / g[i, i]
        for i in range(c - 1, -1, -1):
            s = inverse[i, col]
            for k in range(i + 1, c):
                s -= g[k, i] * inverse[k, col]
            inverse[i, col] = s / g[i, i]
    frobenius = 0.0
    for i in range(c):
        for j in range(c):
            frobenius += inverse[i, j] * inverse[i, j]
    if not trace * math.sqrt(frobenius) <= WELL_CONDITIONED:
        return False
    for i in range(n):
        for j in range(m):
            s = 0.0
            for k in range(c):
                s += (jac[k, i] * inverse[k, j]) if wide else (inverse[i, k] * jac[j, k])
            out[i, j] = s
    return True


@compiled(**_JIT)
def _pinv(jac: np.ndarray, out: np.ndarray, w: np.ndarray) -> None:
    """The Moore-Penrose pseudo-inverse of ``jac`` (m, n) into ``out`` (n, m): singular values
    below ``PINV_RTOL`` times the largest count as zero (:func:`armanim.arm.linalg.pseudo_inverse`).

    The columns orthogonalised are those of J^T (m <= n) or of J (c = min(m, n) of them),
    starting from the orthogonal ``w`` (c, c), which is left holding the rotation found: a
    guess for the next step's Jacobian, which differs little (the identity at the start).
    J^T W = Q gives J^+ = Q diag(1/sigma^2) W^T, J W = Q gives J^+ = W diag(1/sigma^2) Q^T.
    A well-conditioned Jacobian takes its normal equations instead (:func:`_pinv_by_normal_equations`)."""
    if _pinv_by_normal_equations(jac, out):
        return
    m, n = jac.shape
    wide = m <= n
    r = n if wide else m
    c = m if wide else n
    a = np.empty((r, c))
    for i in range(r):
        for j in range(c):
            s = 0.0
            for k in range(c):
                s += (jac[k, i] if wide else jac[i, k]) * w[k, j]
            a[i, j] = s
    _orthogonalise(a, w)
    inverse = np.empty(c)
    top = 0.0
    for j in range(c):
        s = 0.0
        for k in range(r):
            s += a[k, j] * a[k, j]
        inverse[j] = math.sqrt(s)
        top = max(top, inverse[j])
    for j in range(c):
        sigma = inverse[j]
        inverse[j] = 1.0 / (sigma * sigma) if (sigma > PINV_RTOL * top and top > 0.0) else 0.0
    for i in range(n):
        for j in range(m):
            s = 0.0
            for k in range(c):
                if wide:
                    s += a[i, k] * inverse[k] * w[j, k]
                else:
                    s += w[i, k] * inverse[k] * a[j, k]
            out[i, j] = s


@compiled(**_JIT)
def _damped(jac: np.ndarray, damping: float, out: np.ndarray) -> bool:
    """J^T (J J^T + lambda^2 I)^-1 of ``jac`` (m, n) into ``out`` (n, m), by Gaussian elimination
    with partial pivoting (the solve of :func:`armanim.motion.solvers.linear.damped_inverse`);
    False when a pivot is zero (a singular matrix: numpy raises there)."""
    m, n = jac.shape
    gram = np.empty((m, m))
    rhs = np.empty((m, n))
    for i in range(m):
        for j in range(m):
            s = 0.0
            for k in range(n):
                s += jac[i, k] * jac[j, k]
            gram[i, j] = s + (damping * damping if i == j else 0.0)
        for k in range(n):
            rhs[i, k] = jac[i, k]
    for col in range(m):
        pivot = col
        for i in range(col + 1, m):
            if abs(gram[i, col]) > abs(gram[pivot, col]):
                pivot = i
        if gram[pivot, col] == 0.0:
            return False
        if pivot != col:
            for j in range(m):
                gram[col, j], gram[pivot, j] = gram[pivot, j], gram[col, j]
            for k in range(n):
                rhs[col, k], rhs[pivot, k] = rhs[pivot, k], rhs[col, k]
        for i in range(col + 1, m):
            f = gram[i, col] / gram[col, col]
            for j in range(col, m):
                gram[i, j] -= f * gram[col, j]
            for k in range(n):
                rhs[i, k] -= f * rhs[col, k]
    for i in range(m - 1, -1, -1):
        for k in range(n):
            s = rhs[i, k]
            for j in range(i + 1, m):
                s -= gram[i, j] * rhs[j, k]
            rhs[i, k] = s / gram[i, i]
    for i in range(n):
        for j in range(m):
            out[i, j] = rhs[j, i]
    return True


@compiled(**_INLINE)
def _invert(jac: np.ndarray, method: int, damping: float, out: np.ndarray, w: np.ndarray) -> bool:
    """The method's inverse of ``jac`` into ``out`` (``w``: :func:`_pinv`'s guess); False where it
    fails (a NaN proposal)."""
    if method == PINV:
        _pinv(jac, out, w)
        return True
    return _damped(jac, damping, out)


# ----------------------------------------------------------------------------- the pose task


@compiled(**_INLINE)
def _least_axis(v0: float, v1: float, v2: float) -> int:
    """The coordinate axis least along (v0, v1, v2) (numpy's argmin of |v|: the first of equals)."""
    best = 0
    least = abs(v0)
    if abs(v1) < least:
        best, least = 1, abs(v1)
    if abs(v2) < least:
        best = 2
    return best


@compiled(**_INLINE)
def _cross_axis(v: np.ndarray, axis: int, out: np.ndarray) -> None:
    """v x e_axis into ``out``."""
    e0 = 1.0 if axis == 0 else 0.0
    e1 = 1.0 if axis == 1 else 0.0
    e2 = 1.0 if axis == 2 else 0.0
    out[0] = v[1] * e2 - v[2] * e1
    out[1] = v[2] * e0 - v[0] * e2
    out[2] = v[0] * e1 - v[1] * e0


@compiled(**_JIT)
def _residual(kind: int, goal_rot: np.ndarray, goal_axis: np.ndarray, tool: np.ndarray, out: np.ndarray) -> None:
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
        _cross_axis(z, _least_axis(z[0], z[1], z[2]), out)
    else:
        out[0], out[1], out[2] = n0, n1, n2
    length = math.sqrt(out[0] * out[0] + out[1] * out[1] + out[2] * out[2])
    for a in range(3):
        out[a] = angle * (out[a] / length)


@compiled(**_JIT)
def _orientation_rows(kind: int, tool: np.ndarray, rows: np.ndarray) -> int:
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
    _cross_axis(z, _least_axis(z[0], z[1], z[2]), first)
    length = math.sqrt(first[0] * first[0] + first[1] * first[1] + first[2] * first[2])
    for a in range(3):
        first[a] /= length
        rows[0, a] = first[a]
    rows[1, 0] = z[1] * first[2] - z[2] * first[1]
    rows[1, 1] = z[2] * first[0] - z[0] * first[2]
    rows[1, 2] = z[0] * first[1] - z[1] * first[0]
    return 2


@compiled(**_JIT)
def _progress(floats: np.ndarray, kind: int, goal: np.ndarray, goal_rot: np.ndarray, goal_axis: np.ndarray,
              points: np.ndarray, tool: np.ndarray, residual: np.ndarray, errors: np.ndarray) -> float:
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
    _residual(kind, goal_rot, goal_axis, tool, residual)
    angle = math.sqrt(residual[0] * residual[0] + residual[1] * residual[1] + residual[2] * residual[2])
    errors[1] = angle
    scaled: float = angle * (floats[TOL] / floats[ANGLE_TOL])
    return max(distance, scaled)


@compiled(**_INLINE)
def _capped(v: np.ndarray, scale: float, cap: float) -> None:
    """v <- scale v, its length capped at ``cap`` (:func:`~armanim.motion.solvers.common.task_displacement`)."""
    s = 0.0
    for a in range(v.shape[0]):
        v[a] = scale * v[a]
        s += v[a] * v[a]
    length = math.sqrt(s)
    if length > cap:
        for a in range(v.shape[0]):
            v[a] = v[a] * (cap / length)


@compiled(**_INLINE)
def _step_bounds(phi: float, lower: float, upper: float, cap: float, gamma: float, buffer: float) -> tuple[float, float]:
    """One joint's bounds on its step in the filter (:func:`armanim.motion.solvers.barrier.joint_bounds`):
    the joint-step cap and, for a limited joint, the velocity damper toward each limit less its
    buffer; each bound no nearer than 0 (a joint inside its buffer may stand still)."""
    low, high = -cap, cap
    if lower > -np.inf:
        low = max(-cap, -gamma * (phi - (lower + buffer)))
        high = min(cap, gamma * ((upper - buffer) - phi))
    return min(low, 0.0), max(high, 0.0)


@compiled(**_JIT)
def _limit_push(floats: np.ndarray, phi: np.ndarray, lower: np.ndarray, upper: np.ndarray, push: np.ndarray) -> bool:
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
        push[j] = scale * (_repulsion(phi[j] - lower[j], margin) - _repulsion(upper[j] - phi[j], margin))
    return True


@compiled(**_INLINE)
def _repulsion(gap: float, influence: float) -> float:
    """R (R / gap - 1) inside the influence, else 0 (:func:`armanim.motion.solvers.linear.repulsion`)."""
    if not (gap > 0.0 and gap < influence):
        return 0.0
    return influence * (influence / max(gap, influence * 1e-12) - 1.0)


@compiled(**_INLINE)
def _matvec(a: np.ndarray, x: np.ndarray, out: np.ndarray) -> None:
    for i in range(a.shape[0]):
        s = 0.0
        for k in range(a.shape[1]):
            s += a[i, k] * x[k]
        out[i] = s


@compiled(**_INLINE)
def _null_space_task(jac: np.ndarray, pinv_tip: np.ndarray, jac_r: np.ndarray, null: np.ndarray, restricted: np.ndarray) -> tuple[float, float]:
    """The rotation task second in priority: the tip task's null-space projector I - J^+ J into
    ``null`` (n, n) (``jac`` its first 3 rows the tip's, ``pinv_tip`` (n, 3) their
    pseudo-inverse), and the rotation rows ``jac_r`` (k, n) restricted to it, jac_r (I - J^+ J),
    into ``restricted`` (k, n). Returns |restricted|_F^2 and |jac_r|_F^2, whose ratio tells a
    task with only rounding left (:data:`ROUNDING_TASK`)."""
    n = null.shape[0]
    for i in range(n):
        for j in range(n):
            null[i, j] = (1.0 if i == j else 0.0) - (pinv_tip[i, 0] * jac[0, j] + pinv_tip[i, 1] * jac[1, j] + pinv_tip[i, 2] * jac[2, j])
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


@compiled(**_JIT)
def _proposal(floats: np.ndarray, ints: np.ndarray, phi: np.ndarray, points: np.ndarray, axes: np.ndarray, tool: np.ndarray,
              goal: np.ndarray, residual: np.ndarray, lower: np.ndarray, upper: np.ndarray, guesses: np.ndarray, pair_push: np.ndarray,
              pairs_push: bool, dphi: np.ndarray) -> int:
    """The method's step (:func:`armanim.motion.solvers.linear.linear_step` without obstacles; the
    pairs' push ``pair_push`` (n,), where ``pairs_push``, beside the limits' in the null space) into ``dphi``: :data:`DONE`, :data:`NUMERICAL` when its inverse failed, or
    :data:`HANDED_BACK` where the rotation second in priority has only rounding left to act on
    (:data:`ROUNDING_TASK`). ``guesses`` (3, 6, 6): the SVDs' rotations of the last step, of the
    task, of the tip's task and of the rotation in its null space."""
    n = phi.shape[0]
    method = ints[METHOD]
    kind = ints[KIND]
    damping = floats[DAMPING]
    jac6 = np.empty((6, n))
    _jacobian(points, axes, jac6)
    brows = np.empty((3, 3))
    k = _orientation_rows(kind, tool, brows) if kind != 0 else 0
    error = np.empty(3)
    for i in range(k):
        error[i] = brows[i, 0] * residual[0] + brows[i, 1] * residual[1] + brows[i, 2] * residual[2]
    jac_r = np.empty((k, n))  # w B J_w
    for i in range(k):
        for j in range(n):
            jac_r[i, j] = floats[WEIGHT] * (brows[i, 0] * jac6[3, j] + brows[i, 1] * jac6[4, j] + brows[i, 2] * jac6[5, j])
    rot_step = np.empty(k)
    for i in range(k):
        rot_step[i] = floats[WEIGHT] * error[i]
    _capped(rot_step, floats[BETA], floats[MAX_STEP])
    target3 = np.empty(3)
    for a in range(3):
        target3[a] = goal[a] - points[n, a]
    _capped(target3, floats[BETA], floats[MAX_STEP])
    stacked = ints[STACKED] == 1 and kind != 0
    m = 3 + k if stacked else 3
    jac = np.empty((m, n))
    target = np.empty(m)
    for a in range(3):
        target[a] = target3[a]
        for j in range(n):
            jac[a, j] = jac6[a, j]
    if stacked:
        for i in range(k):
            target[3 + i] = rot_step[i]
            for j in range(n):
                jac[3 + i, j] = jac_r[i, j]
    jac_inv = np.empty((n, m))
    if not _invert(jac, method, damping, jac_inv, guesses[0, :min(m, n), :min(m, n)]):
        return NUMERICAL
    _matvec(jac_inv, target, dphi)
    push = np.empty(n)
    pushed = _limit_push(floats, phi, lower, upper, push)
    if pairs_push:
        for j in range(n):
            push[j] = (push[j] if pushed else 0.0) + pair_push[j]
        pushed = True
    if kind != 0 and not stacked:  # the rotation second, in the null space of the tip's task
        pinv_tip = np.empty((n, 3))
        if method == PINV:
            for i in range(n):
                for a in range(3):
                    pinv_tip[i, a] = jac_inv[i, a]
        else:
            _pinv(jac, pinv_tip, guesses[1, :min(3, n), :min(3, n)])
        null_tip = np.empty((n, n))
        restricted = np.empty((k, n))
        left, rows_size = _null_space_task(jac, pinv_tip, jac_r, null_tip, restricted)
        if left < ROUNDING_TASK * ROUNDING_TASK * rows_size:
            return HANDED_BACK
        inv_r = np.empty((n, k))
        if not _invert(restricted, method, damping, inv_r, guesses[2, :min(k, n), :min(k, n)]):
            return NUMERICAL
        rest = np.empty(k)
        _matvec(jac_r, dphi, rest)
        for i in range(k):
            rest[i] = rot_step[i] - rest[i]
        turn = np.empty(n)
        _matvec(inv_r, rest, turn)
        for j in range(n):
            dphi[j] = dphi[j] + turn[j]
        if pushed:
            pinv_r = inv_r
            if method != PINV:
                pinv_r = np.empty((n, k))
                _pinv(restricted, pinv_r, guesses[2, :min(k, n), :min(k, n)])
            null_both = np.empty((n, n))
            for i in range(n):
                for j in range(n):
                    s = 0.0
                    for q in range(k):
                        s += pinv_r[i, q] * restricted[q, j]
                    null_both[i, j] = null_tip[i, j] - s
            moved = np.empty(n)
            _matvec(null_both, push, moved)
            for j in range(n):
                dphi[j] = dphi[j] + moved[j]
    elif pushed:
        task = np.empty(m)
        _matvec(jac, push, task)
        back = np.empty(n)
        _matvec(jac_inv, task, back)
        for j in range(n):
            dphi[j] = dphi[j] + push[j] - back[j]
    return DONE


# ----------------------------------------------------------------------------- the arm's own pairs


@compiled(**_JIT)
def _pair_gaps(points: np.ndarray, frames: np.ndarray, caps: np.ndarray, caps_link: np.ndarray, first: np.ndarray,
               second: np.ndarray, ends: np.ndarray, gaps: np.ndarray, near: np.ndarray) -> float:
    """Every enabled pair's gap (distance less both radii) into ``gaps`` (P,), the capsules' world
    ends into ``ends`` (2, c, 3), each pair's closest points' fractions and normal into ``near``
    (P, 5): t, s, n (:func:`armanim.world.selfdistances.self_gaps`); returns the least gap."""
    _capsule_ends_one(points, frames, caps_link, caps[:, 0:3], caps[:, 3:6], caps[:, 7], ends[0], ends[1])  # column 7: joint-to-joint
    p = first.shape[0]
    t = np.empty(p)
    s = np.empty(p)
    dist = np.empty(p)
    normal = np.empty((p, 3))
    a, b = ends[0], ends[1]
    rest = False
    for q in range(p):  # :func:`armanim.world.compiled.segment_segment_pairs`, its spheres' pairs in closed form here
        t[q], s[q], dist[q] = _segments_apart(a, b, first[q], second[q], normal, q)
        if dist[q] < 0.0:
            t[q], s[q], dist[q] = _points_apart(a, b, first[q], second[q], normal, q)
            rest = rest or dist[q] < 0.0
    if rest:  # parallel or touching: the shared box form
        segment_box_pairs_of_segments(a, b, first, second, t, s, dist, normal)
    least = np.inf
    for q in range(p):
        gaps[q] = dist[q] - (caps[first[q], 6] + caps[second[q], 6])
        least = min(least, gaps[q])
        near[q, 0] = t[q]
        near[q, 1] = s[q]
        for x in range(3):
            near[q, 2 + x] = normal[q, x]
    return least


@compiled(**_JIT)
def _pair_push(floats: np.ndarray, method: int, gaps: np.ndarray, points: np.ndarray, axes: np.ndarray, caps_link: np.ndarray,
               ends: np.ndarray, near: np.ndarray, first: np.ndarray, second: np.ndarray, push: np.ndarray) -> int:
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
    guess = np.eye(3)
    any_push = 0
    for q in range(gaps.shape[0]):
        d = gaps[q]
        if not d < influence:
            continue
        if abs(d) <= slack:
            return -1
        size = scale * _repulsion(d, influence)
        if size == 0.0:
            continue
        which[0] = q
        pair_jacobians(points, axes, ends[0], ends[1], caps_link, first, second, near[:, 0], near[:, 1], which, jac)
        if method == PINV:
            for a in range(3):
                for b in range(3):
                    guess[a, b] = 1.0 if a == b else 0.0
            _pinv(jac[0], inverse, guess[:min(3, n), :min(3, n)])
        elif not _damped(jac[0], floats[DAMPING], inverse):
            return -1
        for j in range(n):
            push[j] += size * (inverse[j, 0] * near[q, 2] + inverse[j, 1] * near[q, 3] + inverse[j, 2] * near[q, 4])
        any_push = 1
    return any_push


QP_ITERATIONS = 100
"""Most iterations of :func:`_closest_step` (each adds or drops one constraint; a 7-joint step
takes a few)."""

QP_FEASIBLE = 1e-13
"""A constraint of the filter's QP counts as met by :func:`_closest_step`'s answer when it is broken
by no more than this (rounding; the filter's own test allows ``VIOLATION``)."""


@compiled(**_INLINE)
def _cholesky(g: np.ndarray, size: int, floor: float) -> bool:
    """G = L L^T in place for the leading (size, size) block of ``g`` (its lower triangle read,
    L written there); False where a pivot is not above ``floor`` (G not positive definite)."""
    for j in range(size):
        s = g[j, j]
        for k in range(j):
            s -= g[j, k] * g[j, k]
        if not s > floor:
            return False
        g[j, j] = math.sqrt(s)
        for i in range(j + 1, size):
            s = g[i, j]
            for k in range(j):
                s -= g[i, k] * g[j, k]
            g[i, j] = s / g[j, j]
    return True


@compiled(**_JIT)
def _gram_solve(cmat: np.ndarray, active: np.ndarray, w: int, rhs: np.ndarray, out: np.ndarray, gram: np.ndarray) -> bool:
    """out (w,) solving (C_W C_W^T) out = rhs (w,), C_W the rows ``active[:w]`` of ``cmat``, by
    Cholesky (in ``gram``, (n, n) work space); False where C_W C_W^T is not positive definite
    (rows dependent to rounding)."""
    n = cmat.shape[1]
    for i in range(w):
        for j in range(i + 1):
            s = 0.0
            for k in range(n):
                s += cmat[active[i], k] * cmat[active[j], k]
            gram[i, j] = s
    if not _cholesky(gram, w, 1e-24):
        return False
    for i in range(w):
        s = rhs[i]
        for k in range(i):
            s -= gram[i, k] * out[k]
        out[i] = s / gram[i, i]
    for i in range(w - 1, -1, -1):
        s = out[i]
        for k in range(i + 1, w):
            s -= gram[k, i] * out[k]
        out[i] = s / gram[i, i]
    return True


@compiled(**_JIT)
def _closest_step(nominal: np.ndarray, cmat: np.ndarray, cb: np.ndarray, count: int, x: np.ndarray, bounds: int = 0) -> int:
    """The filter's QP, exactly: x (n,) minimising |x - nominal|^2 subject to ``cmat[:count] x >=
    cb[:count]``, by the dual active-set method of Goldfarb and Idnani (Hessian I): from x =
    ``nominal``, the most broken constraint is met by steps that keep the active ones met and
    their multipliers >= 0 (a constraint whose multiplier would turn negative leaves), until none
    is broken by more than :data:`QP_FEASIBLE`; then x is projected again onto the active
    constraints from ``nominal`` in one solve (the least-squares point, so the KKT conditions
    hold to rounding: DAQP meets them to its tolerances, some 1e-7). Returns 1 (solved), 0 (no x
    meets the constraints) or -1 (the active rows turned dependent to rounding, the iterations ran
    out, or the answer's checks failed: the numpy step takes that one).

    ``bounds``: how many of the first rows are the joints' bounds, rows of the identity or its
    negative, one of each sign a joint (:func:`_bound_rows`). The method then starts from the clip
    of ``nominal`` with the bounds it breaks active (their multipliers the clip's distances, >= 0:
    the least point of those equalities, so a start the method allows), where it would have added
    them one by one: the same answer (the QP's only one) in fewer iterations."""
    n = nominal.shape[0]
    for j in range(n):
        x[j] = nominal[j]
    active = np.empty(n, dtype=np.int64)
    u = np.empty(n)
    in_set = np.zeros(count, dtype=np.bool_)
    r = np.empty(n)
    z = np.empty(n)
    rhs = np.empty(n)
    gram = np.empty((n, n))
    w = 0
    for c in range(bounds):  # the bounds the nominal breaks, active at the clip
        sc = -cb[c]
        for j in range(n):
            sc += cmat[c, j] * nominal[j]
        if sc < -QP_FEASIBLE:
            active[w] = c
            u[w] = -sc  # a unit row: the multiplier is the distance
            in_set[c] = True
            w += 1
            for j in range(n):
                x[j] -= sc * cmat[c, j]
    solved = False
    for _ in range(QP_ITERATIONS):
        p = -1
        worst = -QP_FEASIBLE
        for c in range(count):
            if in_set[c]:
                continue
            sc = -cb[c]
            for j in range(n):
                sc += cmat[c, j] * x[j]
            if sc < worst:
                worst = sc
                p = c
        if p < 0:
            solved = True
            break
        up = 0.0
        added = False
        for _ in range(QP_ITERATIONS):
            for i in range(w):
                s = 0.0
                for j in range(n):
                    s += cmat[active[i], j] * cmat[p, j]
                rhs[i] = s
            if w > 0 and not _gram_solve(cmat, active, w, rhs, r, gram):
                return -1
            zz = 0.0
            cc = 0.0
            sp = -cb[p]
            for j in range(n):
                s = cmat[p, j]
                for i in range(w):
                    s -= cmat[active[i], j] * r[i]
                z[j] = s
                zz += s * s
                cc += cmat[p, j] * cmat[p, j]
                sp += cmat[p, j] * x[j]
            full = -sp / zz if zz > 1e-24 * cc else np.inf  # the primal step that meets constraint p
            partial = np.inf  # the dual step at which an active multiplier reaches 0
            k = -1
            for i in range(w):
                if r[i] > 0.0 and u[i] / r[i] < partial:
                    partial = u[i] / r[i]
                    k = i
            if partial == np.inf and full == np.inf:
                return 0
            t = min(full, partial)
            if full < np.inf:
                for j in range(n):
                    x[j] += t * z[j]
            for i in range(w):
                u[i] -= t * r[i]
            up += t
            if t == full:
                if w == n:
                    return -1
                active[w] = p
                u[w] = up
                w += 1
                in_set[p] = True
                added = True
                break
            in_set[active[k]] = False  # the partial step: constraint k leaves
            active[k] = active[w - 1]
            u[k] = u[w - 1]
            w -= 1
        if not added:
            return -1
    if not solved:
        return -1
    for i in range(w):  # the least-squares point of the active constraints, from the nominal: x = nominal + C_W^T u
        s = -cb[active[i]]
        for j in range(n):
            s += cmat[active[i], j] * nominal[j]
        rhs[i] = -s
    if w > 0 and not _gram_solve(cmat, active, w, rhs, u, gram):
        return -1
    for j in range(n):
        s = nominal[j]
        for i in range(w):
            s += cmat[active[i], j] * u[i]
        x[j] = s
    for i in range(w):
        if not u[i] >= -QP_FEASIBLE:
            return -1
    for c in range(count):
        sc = -cb[c]
        for j in range(n):
            sc += cmat[c, j] * x[j]
        if not sc >= -QP_FEASIBLE:
            return -1
    return 1


@compiled(**_JIT)
def _bound_rows(n: int, pairs: int) -> np.ndarray:
    """The filter QP's rows (2 n + P, n), its first 2 n the joints' bounds (I, then -I: x >= low,
    -x >= -high); the pairs' rows are written per step."""
    cmat = np.zeros((2 * n + pairs, n))
    for j in range(n):
        cmat[j, j] = 1.0
        cmat[n + j, j] = -1.0
    return cmat


@compiled(**_JIT)
def _filtered(floats: np.ndarray, gaps: np.ndarray, points: np.ndarray, axes: np.ndarray, caps_link: np.ndarray, ends: np.ndarray,
              near: np.ndarray, first: np.ndarray, second: np.ndarray, pair_levers: np.ndarray, nominal: np.ndarray,
              nominal_length: float, low: np.ndarray, high: np.ndarray, cmat: np.ndarray, cb: np.ndarray, twists: np.ndarray,
              in_rows: np.ndarray, step: np.ndarray) -> bool:
    """With the pairs' exact ``gaps`` at the pose and ``step`` (n,) holding the nominal clipped to
    the joints' bounds ``low``, ``high``: the filter's step into ``step``, as
    :func:`armanim.motion.solvers.barrier.filtered_step` takes it, the closest to ``nominal``
    meeting those bounds and the rows of the pairs near enough for the step
    (:func:`armanim.motion.solvers.barrier.self_pair_rows`: n . (J_A - J_B) dPhi >= -gamma (d -
    d_kept)). ``nominal`` itself where it meets them all (to ``VIOLATION``), else the QP solved
    exactly (:func:`_closest_step`), clipped to the bounds as the numpy filter clips DAQP's answer;
    where no step meets the rows, the QP again with each row's bound no more than 0 (closing no
    gap further), as the numpy filter relaxes it.

    A row that the QP's answer meets does not change the answer: so the QP is solved with the
    rows its answer breaks, from the clip (the answer with no row) on, each added as the answer
    breaks it, until the answer meets every row (the pairs' rates by the links' twists,
    :func:`armanim.world.compiled.pair_rate`, a few products a pair where a row costs n cross
    products: a pair's row is built only where it acts). ``cmat`` (2 n + P, n), ``cb`` (2 n + P,):
    work space for the QP's rows and bounds, its first 2 n rows the joints' (:func:`_bound_rows`);
    ``twists`` (n, 6), ``in_rows`` (P,): work space. False (hand back) where the QP fails."""
    n = nominal.shape[0]
    gamma = floats[GAMMA]
    kept = floats[KEPT_SELF]
    pairs = gaps.shape[0]
    a, b, t, s, normal = ends[0], ends[1], near[:, 0], near[:, 1], near[:, 2:5]
    met = True
    for j in range(n):
        cb[j] = low[j]
        cb[n + j] = -high[j]
        if nominal[j] < low[j] - VIOLATION or nominal[j] > high[j] + VIOLATION:
            met = False
    for q in range(pairs):  # the rows the numpy filter builds: those of the pairs near enough for the step (its test)
        in_rows[q] = not gaps[q] - kept < 2.0 * nominal_length * pair_levers[q] + 1e-9  # True: no row, or a row in the QP
    if met:
        link_twists(points, axes, nominal, twists)
        for q in range(pairs):
            if not in_rows[q] and pair_rate(twists, a, b, caps_link, first, second, t, s, normal, q) < -gamma * (gaps[q] - kept) - VIOLATION:
                met = False
                break
        if met:
            for j in range(n):
                step[j] = nominal[j]
            return True
    count = 2 * n
    relaxed = False
    scratch = np.empty(9)
    for _ in range(pairs + 1):
        link_twists(points, axes, step, twists)
        added = False
        for q in range(pairs):
            if in_rows[q]:
                continue
            room = -gamma * (gaps[q] - kept)
            if relaxed:
                room = min(room, 0.0)
            if pair_rate(twists, a, b, caps_link, first, second, t, s, normal, q) < room:
                pair_row(points, axes, a, b, caps_link, first, second, t, s, normal, q, scratch, cmat[count])
                cb[count] = room
                in_rows[q] = True
                count += 1
                added = True
        if not added:
            break
        solved = _closest_step(nominal, cmat, cb, count, step, 2 * n)
        if solved == 0 and not relaxed:  # no step meets these rows, nor so all of them: as the numpy filter, closing no gap further
            relaxed = True
            for c in range(2 * n, count):
                cb[c] = min(cb[c], 0.0)
            solved = _closest_step(nominal, cmat, cb, count, step, 2 * n)
        if solved == 0:
            for j in range(n):
                step[j] = 0.0
            return True
        if solved < 0:
            return False
    for j in range(n):
        step[j] = min(max(step[j], low[j]), high[j])
    return True


@compiled(**_INLINE)
def _lever_travel(levers: np.ndarray, q: int, step: np.ndarray, scale: float) -> float:
    """The most pair q's gap changes under the joint change ``scale * step``: its lever arms . |scale step|."""
    travel = 0.0
    for j in range(step.shape[0]):
        travel += levers[q, j] * abs(scale * step[j])
    return travel


@compiled(**_JIT)
def _pairs_far(floats: np.ndarray, bound: np.ndarray, levers: np.ndarray, step: np.ndarray) -> bool:
    """Whether every pair's gap bound shows its row of the filter met by ``step`` whatever the row
    (gamma (d - d_target) >= the pair's lever arms . |step|)."""
    slack = floats[SLACK]
    for q in range(bound.shape[0]):
        if not floats[GAMMA] * (bound[q] - floats[KEPT_SELF]) >= _lever_travel(levers, q, step, 1.0) * (1.0 + 1e-9) + slack:
            return False
    return True


# ----------------------------------------------------------------------------- the attempt


@compiled(**_JIT)
def _attempt(rows: np.ndarray, root: np.ndarray, start: np.ndarray, goal: np.ndarray, goal_rot: np.ndarray, goal_axis: np.ndarray,
             lower: np.ndarray, upper: np.ndarray, floats: np.ndarray, settings: np.ndarray, method: int, stacked: bool, steps_cap: int,
             kind: int, steps_so_far: int, since_so_far: int, best_so_far: float, caps: np.ndarray, caps_link: np.ndarray,
             first: np.ndarray, second: np.ndarray, levers: np.ndarray, pair_levers: np.ndarray, out: np.ndarray) -> int:
    """The attempt from ``start``; into ``out`` (2 n + 9,): the pose it ends at (n), its tip (3), the
    distance, the angle, the progress measure, the best progress, the steps taken and the steps
    since the best progress, and the angles its kinematics were computed at (n: before wrapping). Returns :data:`DONE`, :data:`NUMERICAL` or :data:`HANDED_BACK`
    (the numpy path takes over from that pose with those counters). ``settings``: the problem's
    int settings (:func:`_int_settings`), the call's own (the method, whether the pose task is
    stacked, the attempt's steps, the orientation's kind, the counters so far) given as numbers:
    a number crosses into the call for less than an array's copy and writes."""
    n = start.shape[0]
    ints = settings.copy()
    ints[METHOD], ints[STACKED], ints[STEPS_CAP], ints[KIND], ints[STEPS], ints[SINCE_BEST] = method, stacked, steps_cap, kind, steps_so_far, since_so_far
    kind = ints[KIND]
    tol = floats[TOL]
    cap = floats[MAX_JOINT_STEP]
    gamma = floats[GAMMA]
    buffer = floats[BUFFER]
    slack = floats[SLACK]
    pairs = first.shape[0]
    points = np.empty((2, n + 1, 3))  # the pose now and the candidate: slots swapped by index
    frames = np.empty((2, n, 3, 3))
    axes = np.empty((2, n, 3))
    tool = np.empty((2, 3, 3))
    gaps = np.empty((2, pairs))  # the pairs' gaps, capsule ends and closest points, where computed (``exact``)
    ends = np.empty((2, 2, caps.shape[0], 3))
    near = np.empty((2, pairs, 5))
    least = np.empty(2)
    exact = np.zeros(2, dtype=np.bool_)
    bound = np.full(pairs, -np.inf)  # a lower bound of each pair's gap at the pose now
    cand_bound = np.empty(pairs)
    now = 0
    phi = start.copy()
    pose_phi = start.copy()  # the angles the pose now was computed at (phi before the unlimited joints are wrapped)
    cand = np.empty(n)
    _forward_one(rows, root, phi, points[now], frames[now], axes[now], tool[now])
    residual = np.empty(3)
    errors = np.empty(2)
    progress = _progress(floats, kind, goal, goal_rot, goal_axis, points[now], tool[now], residual, errors)
    best = progress if best_so_far != best_so_far else best_so_far
    since_best = ints[SINCE_BEST]
    steps = ints[STEPS]
    status = DONE
    dphi = np.empty(n)
    guesses = np.zeros((3, 6, 6))
    for g in range(3):
        for i in range(6):
            guesses[g, i, i] = 1.0
    step = np.empty(n)
    nominal = np.empty(n)
    low = np.empty(n)
    high = np.empty(n)
    pair_push = np.empty(n)
    cmat = _bound_rows(n, pairs)
    cb = np.empty(2 * n + pairs)
    twists = np.empty((n, 6))
    in_rows = np.empty(pairs, dtype=np.bool_)
    while progress >= tol and steps < ints[STEPS_CAP]:
        pairs_push = False
        if pairs:  # a pair within its push's influence (R): its push joins the limits' (exact gaps, where a bound cannot show none)
            within = False
            for q in range(pairs):
                if not bound[q] >= floats[SELF_INFLUENCE] + slack:
                    within = True
                    break
            if within:
                if not exact[now]:
                    least[now] = _pair_gaps(points[now], frames[now], caps, caps_link, first, second, ends[now], gaps[now], near[now])
                    exact[now] = True
                    for q in range(pairs):
                        bound[q] = gaps[now, q] - slack
                within = least[now] < floats[SELF_INFLUENCE]  # the exact gaps: a pair inside R (else no push, and none near 0)
            if within:
                pushing = _pair_push(floats, ints[METHOD], gaps[now], points[now], axes[now], caps_link, ends[now], near[now], first,
                                     second, pair_push)
                if pushing < 0:
                    status = HANDED_BACK
                    break
                pairs_push = pushing == 1
        proposed = _proposal(floats, ints, phi, points[now], axes[now], tool[now], goal, residual, lower, upper, guesses, pair_push,
                             pairs_push, dphi)
        if proposed == HANDED_BACK:
            status = HANDED_BACK
            break
        finite = proposed == DONE
        biggest = 0.0
        for j in range(n):
            v = abs(dphi[j])
            if not v <= biggest:  # a NaN sticks
                biggest = v
        if not finite or not biggest < np.inf:
            steps += 1
            status = NUMERICAL
            break
        if biggest == 0.0:
            steps += 1
            break
        shrink = min(1.0, cap / biggest)
        nominal_length = 0.0
        inside = True  # the nominal step within the joints' bounds, as the filter judges it (to VIOLATION)
        for j in range(n):
            nominal[j] = dphi[j] * shrink
            step[j] = nominal[j]
            nominal_length += step[j] * step[j]
            low[j], high[j] = _step_bounds(phi[j], lower[j], upper[j], cap, gamma, buffer)
            if step[j] < low[j] - VIOLATION or step[j] > high[j] + VIOLATION:
                inside = False
        nominal_length = math.sqrt(nominal_length)
        if not inside:  # the filter's QP on bounds alone: its answer is the clip
            for j in range(n):
                step[j] = min(max(step[j], low[j]), high[j])
        if pairs and not _pairs_far(floats, bound, levers, step):  # a pair's row could act: the filter's QP with the pairs' rows
            if not exact[now]:
                least[now] = _pair_gaps(points[now], frames[now], caps, caps_link, first, second, ends[now], gaps[now], near[now])
                exact[now] = True
                for q in range(pairs):
                    bound[q] = gaps[now, q] - slack
            if not _filtered(floats, gaps[now], points[now], axes[now], caps_link, ends[now], near[now], first, second, pair_levers,
                             nominal, nominal_length, low, high, cmat, cb, twists, in_rows, step):
                status = HANDED_BACK
                break
        other = 1 - now
        taken = -1.0
        scale = 1.0
        for _ in range(ints[HALVINGS] + 1):
            safe = True
            for j in range(n):
                cand[j] = phi[j] + scale * step[j]
                if not (cand[j] - cand[j] == 0.0):  # NaN or infinity
                    safe = False
                gap = min(cand[j] - lower[j], upper[j] - cand[j])
                gap_now = min(phi[j] - lower[j], upper[j] - phi[j])
                if gap <= 0.0 or gap < min(buffer, gap_now):
                    safe = False
            exact[other] = False
            if safe and pairs:  # every pair no nearer than self_clearance (or than it was)
                certain = True
                for q in range(pairs):
                    cand_bound[q] = bound[q] - _lever_travel(levers, q, step, scale) * (1.0 + 1e-9) - slack
                    certain = certain and cand_bound[q] >= floats[SELF_CLEARANCE]
                if not certain:
                    if not exact[now]:
                        least[now] = _pair_gaps(points[now], frames[now], caps, caps_link, first, second, ends[now], gaps[now], near[now])
                        exact[now] = True
                    _forward_one(rows, root, cand, points[other], frames[other], axes[other], tool[other])
                    least[other] = _pair_gaps(points[other], frames[other], caps, caps_link, first, second, ends[other], gaps[other], near[other])
                    exact[other] = True
                    floor = min(floats[SELF_CLEARANCE], least[now])
                    if not (least[other] >= floor + slack or least[other] < floor - slack):
                        status = HANDED_BACK  # too near the floor to tell as numpy would
                        break
                    safe = least[other] >= floor
                    for q in range(pairs):
                        cand_bound[q] = gaps[other, q] - slack
            if safe:
                taken = scale
                break
            scale *= 0.5
        if status == HANDED_BACK:
            break
        if taken < 0.0:  # no halving kept the guarantees: the attempt ends where it is
            steps += 1
            break
        moved = 0.0
        for j in range(n):
            moved += (taken * step[j]) ** 2
        if moved == 0.0:  # nothing moved: the same pose would propose the same again
            steps += 1
            break
        if not exact[other]:
            _forward_one(rows, root, cand, points[other], frames[other], axes[other], tool[other])
        for q in range(pairs):
            bound[q] = cand_bound[q]
        exact[now] = False
        now = other
        wrap = False
        for j in range(n):
            wrap = wrap or abs(cand[j]) > np.pi
        for j in range(n):
            phi[j] = cand[j]
            pose_phi[j] = cand[j]
            if wrap and not lower[j] > -np.inf:
                wrapped = (cand[j] + np.pi) % (2.0 * np.pi) - np.pi
                phi[j] = np.pi if wrapped == -np.pi else wrapped
        steps += 1
        progress = _progress(floats, kind, goal, goal_rot, goal_axis, points[now], tool[now], residual, errors)
        if progress < best - 0.1 * tol:
            best = progress
            since_best = 0
        else:
            since_best += 1
            if since_best >= ints[STALL]:
                break
    for j in range(n):
        out[j] = phi[j]
        out[n + 9 + j] = pose_phi[j]
    for a in range(3):
        out[n + a] = points[now, n, a]
    out[n + 3] = errors[0]
    out[n + 4] = errors[1]
    out[n + 5] = progress
    out[n + 6] = best
    out[n + 7] = steps
    out[n + 8] = since_best
    return status


# ----------------------------------------------------------------------------- from Python


class CompiledAttempt(NamedTuple):
    """Where a compiled attempt ended (a named tuple: made in a tenth of a frozen dataclass's time).

    Attributes
    ----------
    phi : (n,) array
    tip : (3,) array
    distance, angle, progress : float
        |e - g|, the tool's angle to the goal's orientation (None without one) and the progress
        measure (:func:`armanim.motion.ik.pose_errors`), at ``phi``.
    steps : int
        Steps taken (proposals through the filter).
    numerical : bool
        The last proposal was not finite.
    handed_back : bool
        The numpy path must go on from ``phi`` (a pair of the arm's own capsules may be near).
    best, since_best :
        The attempt's stall test's state, for the numpy path to go on with.
    """

    phi: np.ndarray
    tip: np.ndarray
    distance: float
    angle: float | None
    progress: float
    steps: int
    numerical: bool
    handed_back: bool
    best: float
    since_best: int
    pose_phi: np.ndarray
    """The angles the pose at ``phi`` was computed at (``phi`` before its unlimited joints were
    wrapped): the numpy steps go on from the very pose."""


def _settings(problem: Problem) -> np.ndarray:
    """The kernel's float settings of ``problem``, made once per problem (kept on it)."""
    kept = problem.__dict__.get("_compiled_settings")
    if kept is not None:
        return cast(np.ndarray, kept)
    s = problem.solver
    floats = np.empty(FLOATS)
    floats[[TOL, ANGLE_TOL, WEIGHT, BETA, MAX_STEP, MAX_JOINT_STEP, DAMPING]] = (
        s.tolerance, s.orientation_tolerance, s.orientation_weight, s.beta, s.max_step, s.max_joint_step, s.damping)
    floats[[MARGIN, BUFFER, GAMMA, W_LIMITS]] = problem.limits.margin, limit_buffer(problem), problem.tunables.filter.gamma, s.w_limits
    floats[[SELF_CLEARANCE, KEPT_SELF, SELF_INFLUENCE]] = problem.self_pairs.clearance, kept_self_clearance(problem), self_influence(problem)
    floats[SLACK] = 1e-9 * max(problem.arm.reach, 1e-300)
    floats[W_OBSTACLES] = s.w_obstacles
    object.__setattr__(problem, "_compiled_settings", floats)  # a cache of constants: the problem stays what it was
    return floats


def _int_settings(problem: Problem) -> np.ndarray:
    """The kernel's int settings of ``problem`` (the stall window and the filter's halvings; the
    rest is set per call), made once per problem (kept on it)."""
    kept = problem.__dict__.get("_compiled_ints")
    if kept is None:
        kept = np.zeros(INTS, dtype=np.int64)
        kept[STALL], kept[HALVINGS] = problem.tunables.ik.stall_iterations, problem.tunables.filter.halvings
        object.__setattr__(problem, "_compiled_ints", kept)  # a cache of constants: the problem stays what it was
    return cast(np.ndarray, kept)


def _pair_constants(problem: Problem) -> tuple[np.ndarray, ...]:
    """The kernel's arrays of the arm's capsules and enabled pairs, made once per problem (kept on
    it): (c, 8) each capsule's start, end, radius and whether it runs joint to joint, (c,) its
    joint, (P,) each pair's first and second capsule, (P, n) its lever arms and (P,) their norm."""
    kept = problem.__dict__.get("_compiled_pairs")
    if kept is not None:
        return cast("tuple[np.ndarray, ...]", kept)
    caps, pairs = problem.capsules, problem.self_pairs
    packed = caps.packed()
    kept = tuple(np.ascontiguousarray(a, dtype=t) for a, t in (
        (packed, float), (caps.link, np.int64), (pairs.first, np.int64), (pairs.second, np.int64),
        (problem.pair_lever_rows, float), (problem.pair_levers, float)))
    object.__setattr__(problem, "_compiled_pairs", kept)  # a cache of constants: the problem stays what it was
    return kept


_NO_ROTATION = np.eye(3)
_NO_AXIS = np.array([0.0, 0.0, 1.0])


def run_attempt(problem: Problem, step: int, stacked: bool, goal: np.ndarray, start: np.ndarray, steps_cap: int,
                orientation: Orientation | None, counters: tuple[int, float | None, int] = (0, None, 0)) -> CompiledAttempt:
    """One attempt from ``start`` (radians) with the compiled ``step`` (:data:`PINV` or :data:`DLS`);
    ``stacked``: the pose task as one (:func:`armanim.motion.solvers.linear.stacks_the_pose_task`);
    ``counters``: where an attempt goes on, its steps so far, its best progress and the steps since.

    Only for a problem without obstacles and with the analytic Jacobian (the caller's test)."""
    kept = problem.__dict__.get("_compiled_constants")
    if kept is None:  # the problem's constants, in the kernel's order: made once per problem (kept on it)
        kept = (*packed_chain(problem.arm), problem.limits.lower, problem.limits.upper, _settings(problem), _int_settings(problem),
                *_pair_constants(problem))
        object.__setattr__(problem, "_compiled_constants", kept)  # a cache of constants: the problem stays what it was
    rows, root, lower, upper, floats, ints, caps, link, first, second, levers, pair_levers = kept
    kind = 0 if orientation is None else (1 if orientation.rotation is not None else 2)
    steps, best, since_best = counters
    n = len(lower)
    out = np.empty(2 * n + 9)
    goal_rot = orientation.rotation if kind == 1 else _NO_ROTATION  # type: ignore[union-attr]  # kind 1: a rotation
    goal_axis = orientation.axis if kind == 2 else _NO_AXIS  # type: ignore[union-attr]  # kind 2: a tool axis
    status = _attempt(rows, root, np.ascontiguousarray(start, dtype=float), np.ascontiguousarray(goal, dtype=float),
                      np.ascontiguousarray(goal_rot, dtype=float), np.ascontiguousarray(goal_axis, dtype=float),
                      lower, upper, floats, ints, step, stacked, steps_cap, kind, steps, since_best, np.nan if best is None else best,
                      caps, link, first, second, levers, pair_levers, out)
    numbers = out[n:n + 9].tolist()
    return CompiledAttempt(out[:n], out[n:n + 3], numbers[3], None if kind == 0 else numbers[4], numbers[5], int(numbers[7]),
                           status == NUMERICAL, status == HANDED_BACK, numbers[6], int(numbers[8]), out[n + 9:])
