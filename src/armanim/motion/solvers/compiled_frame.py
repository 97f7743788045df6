"""One frame of the frame loop with ``pinv`` or ``dls``, compiled (numba): the method's proposal
and the safety filter's answer, in one or two calls.

A frame of :func:`armanim.motion.trajectory.solve_trajectory` is the method's proposal
(:func:`armanim.motion.solvers.linear.linear_step`) through the filter
(:func:`armanim.motion.solvers.barrier.safe_step`): in numpy and Python some 500 calls and a few
hundred microseconds. Here the same frame is written as loops over small arrays, with the
kinematics of :mod:`armanim.arm.kernel`, the distances of :mod:`armanim.world.compiled` and the
inverses of :mod:`armanim.motion.solvers.compiled` (the pseudo-inverse with
:func:`armanim.arm.linalg.pseudo_inverse`'s cut-off, the damped inverse):

- the proposal: the tip's task, the goal's orientation second in priority (in the tip task's
  null space, as :func:`~armanim.motion.solvers.linear.orientation_in_null_space`), the
  joint-limit push, the obstacles' pushes (the tip's in task space, the links' in the null
  space), the pushes of the arm's own pairs (in the null space), from the clearances and gaps of
  the state the frame starts from;
- the filter: the step capped to ``max_joint_step``, the joint bounds, the bounds of
  :func:`~armanim.motion.solvers.barrier.clearly_allowed`, else the rows of
  :func:`~armanim.motion.solvers.barrier.filter_constraints`, built in its order; where one is
  broken, the QP is DAQP's as before (:func:`~armanim.motion.solvers.barrier.filtered_step`,
  from Python, on those rows);
- the exact check of the new pose and its halvings: its kinematics, its clearances to every
  obstacle (spheres, boxes, capsules, cylinders, the floor, in the scene's order), its pairs' gaps, which
  become the next frame's state.

A proposal that is not finite or zero goes to the numpy filter; an inverse that fails (a zero
pivot) leaves the whole frame to the numpy path. The numeric Jacobian and the other methods
are not compiled here (the numpy path).

The numbers are the numpy path's to rounding (the same formulas, other summation orders; the
tests hold them to 1e-12 times the conditioning of the tasks inverted in turn). ``tunables.ik.compiled_frames`` off
gives the numpy frame everywhere (the tests' oracle). Pure core: numpy and numba only, radians.
"""

from __future__ import annotations

import math
from typing import Any, Literal, cast

import numpy as np

from armanim.arm.kernel import TURN, _capsule_ends_one, _forward_one, compiled, packed_chain
from armanim.arm.kinematics import Pose
from armanim.motion.cost import self_influence
from armanim.motion.orientation import Orientation
from armanim.motion.problem import Problem
from armanim.motion.solvers.barrier import (
    BOUND_SLACK,
    VIOLATION,
    Constraints,
    SafeStep,
    blocker,
    filtered_step,
    kept_clearance,
    kept_self_clearance,
    limit_buffer,
    step_fraction,
    wrap_unlimited,
)
from armanim.motion.solvers.common import ArmState
from armanim.motion.solvers.compiled import (
    _capped,
    _damped,
    _null_space_task,
    _orientation_rows,
    _pinv,
    _repulsion,
    _residual,
    _step_bounds,
)
from armanim.motion.solvers.linear import CLOSEST_GAP, ROUNDING_TASK
from armanim.world.compiled import capsule_pair_gaps, pair_row, pair_rows_met, segment_box_grid, segment_cylinder_grid
from armanim.world.distances import Clearances
from armanim.world.selfdistances import SelfGaps

_JIT = dict(error_model="numpy", nogil=True)

TAKEN, NOMINAL, QP, FILTER, NUMPY = 0, 1, 2, 3, 4
"""How a compiled frame ended (:func:`_frame`): the step taken (the new state is in the outputs);
the filter takes the proposal as it is, its exact check still to do; the filter's QP to solve;
the proposal made but the numpy filter needed; nothing done (the numpy proposal and filter)."""

PINV, DLS = 0, 1
"""The compiled steps: the pseudo-inverse and the damped least-squares inverse."""

(BETA, MAX_STEP, MAX_JOINT_STEP, DAMPING, MARGIN, BUFFER, GAMMA, W_LIMITS, W_OBSTACLES, KEPT, CLEARANCE,
 SELF_CLEARANCE, KEPT_SELF, SELF_INFLUENCE, LEVER_NORM, WEIGHT, FLOATS) = range(17)
"""Places of the settings in the kernel's float array (:func:`_constants`)."""


# ----------------------------------------------------------------------------- pieces


@compiled(**_JIT)
def _invert(jac: np.ndarray, method: int, damping: float, out: np.ndarray) -> bool:
    """The method's inverse of ``jac`` (m, n) into ``out`` (n, m); False where it fails."""
    if method == PINV:
        c = min(jac.shape[0], jac.shape[1])
        guess = np.zeros((c, c))
        for i in range(c):
            guess[i, i] = 1.0
        _pinv(jac, out, guess)
        return True
    return _damped(jac, damping, out)


@compiled(**_JIT)
def _point_jacobian(points: np.ndarray, axes: np.ndarray, link: int, q: np.ndarray, jac: np.ndarray) -> None:
    """(3, n) Jacobian of the world point ``q`` carried by joint ``link``'s frame into ``jac``:
    column j is w_j x (q - p_j) for j <= link, 0 after (:func:`armanim.arm.kinematics.point_jacobian`)."""
    n = axes.shape[0]
    for j in range(n):
        if j <= link:
            l0, l1, l2 = q[0] - points[j, 0], q[1] - points[j, 1], q[2] - points[j, 2]
            w0, w1, w2 = axes[j, 0], axes[j, 1], axes[j, 2]
            jac[0, j] = w1 * l2 - w2 * l1
            jac[1, j] = w2 * l0 - w0 * l2
            jac[2, j] = w0 * l1 - w1 * l0
        else:
            jac[0, j] = 0.0
            jac[1, j] = 0.0
            jac[2, j] = 0.0


@compiled(**_JIT)
def _sphere_clearances(points: np.ndarray, a: np.ndarray, b: np.ndarray, part_radius: np.ndarray, centers: np.ndarray,
                       radii: np.ndarray, d: np.ndarray, t: np.ndarray, normal: np.ndarray) -> None:
    """Clearances of the capsules (segments a-b) and the tip to the spheres into d, t (c+1, s)
    and normal (c+1, s, 3) (:func:`armanim.world.distances.sphere_clearances`)."""
    c = a.shape[0]
    n = points.shape[0] - 1
    pa = np.empty(3)
    pb = np.empty(3)
    for part in range(c + 1):
        for i in range(3):
            if part < c:
                pa[i] = a[part, i]
                pb[i] = b[part, i]
            else:
                pa[i] = points[n, i]
                pb[i] = points[n, i]
        ab0, ab1, ab2 = pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]
        denom = ab0 * ab0 + ab1 * ab1 + ab2 * ab2
        for k in range(centers.shape[0]):
            if part == c:
                f = 1.0
            elif denom > 0.0:
                f = ((centers[k, 0] - pa[0]) * ab0 + (centers[k, 1] - pa[1]) * ab1 + (centers[k, 2] - pa[2]) * ab2) / denom
                f = min(max(f, 0.0), 1.0)
            else:
                f = 0.0
            o0 = pa[0] + f * ab0 - centers[k, 0]
            o1 = pa[1] + f * ab1 - centers[k, 1]
            o2 = pa[2] + f * ab2 - centers[k, 2]
            dist = math.sqrt(o0 * o0 + o1 * o1 + o2 * o2)
            scale = dist if dist > 0.0 else 1.0
            normal[part, k, 0] = o0 / scale
            normal[part, k, 1] = o1 / scale
            normal[part, k, 2] = o2 / scale
            t[part, k] = f
            d[part, k] = dist - radii[k] - part_radius[part]


@compiled(**_JIT)
def _clearances(points: np.ndarray, a: np.ndarray, b: np.ndarray, part_radius: np.ndarray, world: tuple[np.ndarray, ...], d: np.ndarray, t: np.ndarray,
                normal: np.ndarray) -> None:
    """Clearances of the capsules (segments a-b) and the tip to every obstacle into d, t (c+1, m)
    and normal (c+1, m, 3): the spheres', the solids' (:func:`armanim.world.compiled.segment_box_grid`,
    the tip a segment of no length), the cylinders' (:func:`armanim.world.compiled.segment_cylinder_grid`)
    and the floor's, in the scene's order (:func:`armanim.world.distances.clearances`).
    ``world``: :func:`_world`'s arrays."""
    (centers, radii, solid_centers, solid_half, solid_rotations, solid_radius, on_base, order, floor,
     cyl_centers, cyl_rotations, cyl_half, cyl_radius) = world
    c = a.shape[0]
    n = points.shape[0] - 1
    count, solids, cylinders = centers.shape[0], solid_centers.shape[0], cyl_centers.shape[0]
    m = d.shape[1]
    pts = np.empty((c + 1, 3))
    ends = np.empty((c + 1, 3))
    for part in range(c + 1):
        for i in range(3):
            pts[part, i] = a[part, i] if part < c else points[n, i]
            ends[part, i] = b[part, i] if part < c else points[n, i]
    kd = np.empty((c + 1, m))
    kt = np.empty((c + 1, m))
    kn = np.empty((c + 1, m, 3))
    if count:
        _sphere_clearances(points, a, b, part_radius, centers, radii, kd[:, :count], kt[:, :count], kn[:, :count])
    if solids:
        sd = np.empty((c + 1, solids))
        st = np.empty((c + 1, solids))
        sn = np.empty((c + 1, solids, 3))
        segment_box_grid(pts, ends, solid_centers, solid_half, solid_rotations, st, sd, sn)
        for part in range(c + 1):
            for k in range(solids):
                kd[part, count + k] = sd[part, k] - solid_radius[k] - part_radius[part]
                kt[part, count + k] = 1.0 if part == c else st[part, k]
                for i in range(3):
                    kn[part, count + k, i] = sn[part, k, i]
    if cylinders:
        first = count + solids
        cd = np.empty((c + 1, cylinders))
        ct = np.empty((c + 1, cylinders))
        cn = np.empty((c + 1, cylinders, 3))
        segment_cylinder_grid(pts, ends, cyl_centers, cyl_rotations, cyl_half, cyl_radius, ct, cd, cn)
        for part in range(c + 1):
            for k in range(cylinders):
                kd[part, first + k] = cd[part, k] - part_radius[part]
                kt[part, first + k] = 1.0 if part == c else ct[part, k]
                for i in range(3):
                    kn[part, first + k, i] = cn[part, k, i]
    if floor.shape[0]:
        f = count + solids + cylinders
        for part in range(c + 1):
            height = min(pts[part, 2], ends[part, 2]) - floor[0] - part_radius[part]
            kd[part, f] = np.inf if on_base[part] else height
            kt[part, f] = 1.0 if (part == c or ends[part, 2] <= pts[part, 2]) else 0.0
            kn[part, f, 0] = 0.0
            kn[part, f, 1] = 0.0
            kn[part, f, 2] = 1.0
    for part in range(c + 1):
        for k in range(m):
            j = order[k]
            d[part, k] = kd[part, j]
            t[part, k] = kt[part, j]
            for i in range(3):
                normal[part, k, i] = kn[part, j, i]


@compiled(**_JIT)
def _orientation_second(floats: np.ndarray, method: int, kind: int, goal_rot: np.ndarray, goal_axis: np.ndarray, tool: np.ndarray,
                        axes: np.ndarray, jac: np.ndarray, jac_inv: np.ndarray, pushed: bool, secondary: np.ndarray,
                        dphi: np.ndarray) -> bool:
    """The rotation task added to ``dphi`` in the null space N of the tip's task, then the pushes
    ``secondary`` (where ``pushed``) in the null space of both
    (:func:`armanim.motion.solvers.linear.orientation_in_null_space`): with the exact projectors
    (pseudo-inverses) for both methods, the method's inverse for the rotation; where N leaves the
    rotation only rounding (:data:`~armanim.motion.solvers.linear.ROUNDING_TASK`), the step and
    the projector are the tip's alone. False where an inverse failed."""
    n = dphi.shape[0]
    brows = np.empty((3, 3))
    k = _orientation_rows(kind, tool, brows)
    residual = np.empty(3)
    _residual(kind, goal_rot, goal_axis, tool, residual)
    weight = floats[WEIGHT]
    jac_r = np.empty((k, n))  # w B J_w
    rot_step = np.empty(k)
    for i in range(k):
        rot_step[i] = weight * (brows[i, 0] * residual[0] + brows[i, 1] * residual[1] + brows[i, 2] * residual[2])
        for j in range(n):
            jac_r[i, j] = weight * (brows[i, 0] * axes[j, 0] + brows[i, 1] * axes[j, 1] + brows[i, 2] * axes[j, 2])
    _capped(rot_step, floats[BETA], floats[MAX_STEP])
    pinv_tip = np.empty((n, 3))
    if method == PINV:
        for i in range(n):
            for c in range(3):
                pinv_tip[i, c] = jac_inv[i, c]
    elif not _invert(jac, PINV, 0.0, pinv_tip):
        return False
    null = np.empty((n, n))  # I - J^+ J, then I - J^+ J - R^+ R
    restricted = np.empty((k, n))
    left, size = _null_space_task(jac, pinv_tip, jac_r, null, restricted)
    if not left < ROUNDING_TASK * ROUNDING_TASK * size:
        inverse = np.empty((n, k))
        if not _invert(restricted, method, floats[DAMPING], inverse):
            return False
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
            if method != PINV and not _invert(restricted, PINV, 0.0, inverse):
                return False
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
                v += null[i, j] * secondary[j]
            dphi[i] = dphi[i] + v
    return True


@compiled(**_JIT)
def _proposal(floats: np.ndarray, method: int, phi: np.ndarray, points: np.ndarray, axes: np.ndarray, goal: np.ndarray,
              kind: int, goal_rot: np.ndarray, goal_axis: np.ndarray, tool: np.ndarray,
              lower: np.ndarray, upper: np.ndarray, a: np.ndarray, b: np.ndarray, link: np.ndarray,
              cl_d: np.ndarray, cl_t: np.ndarray, cl_normal: np.ndarray, influence: np.ndarray,
              first: np.ndarray, second: np.ndarray, gap: np.ndarray, gap_t: np.ndarray, gap_s: np.ndarray,
              gap_normal: np.ndarray, least: float, dphi: np.ndarray) -> bool:
    """:func:`armanim.motion.solvers.linear.linear_step` into ``dphi``; the goal's orientation
    (``kind`` 0: none, 1: the rotation ``goal_rot``, 2: the tool axis ``goal_axis``; ``tool``: the
    tool frame now) second in priority, in the null space of the tip's task
    (:func:`~armanim.motion.solvers.linear.orientation_in_null_space`). False where an inverse
    failed (numpy raises there: the numpy path takes the frame)."""
    n = phi.shape[0]
    tip = points.shape[0] - 1
    jac = np.empty((3, n))
    for j in range(n):
        l0, l1, l2 = points[tip, 0] - points[j, 0], points[tip, 1] - points[j, 1], points[tip, 2] - points[j, 2]
        w0, w1, w2 = axes[j, 0], axes[j, 1], axes[j, 2]
        jac[0, j] = w1 * l2 - w2 * l1
        jac[1, j] = w2 * l0 - w0 * l2
        jac[2, j] = w0 * l1 - w1 * l0
    target = np.empty(3)
    for i in range(3):
        target[i] = goal[i] - points[tip, i]
    _capped(target, floats[BETA], floats[MAX_STEP])
    damping = floats[DAMPING]
    jac_inv = np.empty((n, 3))
    if not _invert(jac, method, damping, jac_inv):
        return False
    for j in range(n):
        dphi[j] = jac_inv[j, 0] * target[0] + jac_inv[j, 1] * target[1] + jac_inv[j, 2] * target[2]
    secondary = np.zeros(n)
    pushed = False
    margin = floats[MARGIN]
    near = False
    for j in range(n):
        if phi[j] - lower[j] < margin or upper[j] - phi[j] < margin:
            near = True
    if near:
        scale = floats[BETA] * floats[W_LIMITS]
        for j in range(n):
            secondary[j] = scale * (_repulsion(phi[j] - lower[j], margin) - _repulsion(upper[j] - phi[j], margin))
        pushed = True
    gain = floats[BETA] * floats[W_OBSTACLES]
    parts = cl_d.shape[0]
    q = np.empty(3)
    pj = np.empty((3, n))
    pinv = np.empty((n, 3))
    v = np.empty(3)
    for part in range(parts):
        if part < parts - 1 and link[part] < 0:  # on the base: never pushed
            continue
        for k in range(cl_d.shape[1]):
            r = influence[k]
            g = cl_d[part, k]
            if not (g > 0.0 and g < r):
                continue
            push = gain * (r * (r / max(g, r * CLOSEST_GAP) - 1.0))
            if push == 0.0:
                continue
            for i in range(3):
                v[i] = push * cl_normal[part, k, i]
            if part == parts - 1:  # the tip itself: in task space
                for j in range(n):
                    dphi[j] = dphi[j] + (jac_inv[j, 0] * v[0] + jac_inv[j, 1] * v[1] + jac_inv[j, 2] * v[2])
                continue
            f = cl_t[part, k]
            for i in range(3):
                q[i] = a[part, i] + f * (b[part, i] - a[part, i])
            _point_jacobian(points, axes, link[part], q, pj)
            if not _invert(pj, method, damping, pinv):
                return False
            for j in range(n):
                secondary[j] += pinv[j, 0] * v[0] + pinv[j, 1] * v[1] + pinv[j, 2] * v[2]
            pushed = True
    reach = floats[SELF_INFLUENCE]
    if first.shape[0] and least < reach:
        qa = np.empty(3)
        qb = np.empty(3)
        ja = np.empty((3, n))
        jb = np.empty((3, n))
        for p in range(first.shape[0]):
            g = gap[p]
            if not (g > 0.0 and g < reach):
                continue
            push = gain * (reach * (reach / max(g, reach * CLOSEST_GAP) - 1.0))
            if push == 0.0:
                continue
            fa, fb = first[p], second[p]
            for i in range(3):
                qa[i] = a[fa, i] + gap_t[p] * (b[fa, i] - a[fa, i])
                qb[i] = a[fb, i] + gap_s[p] * (b[fb, i] - a[fb, i])
            _point_jacobian(points, axes, link[fa], qa, ja)
            _point_jacobian(points, axes, link[fb], qb, jb)
            for i in range(3):
                for j in range(n):
                    ja[i, j] -= jb[i, j]
                v[i] = push * gap_normal[p, i]
            if not _invert(ja, method, damping, pinv):
                return False
            for j in range(n):
                secondary[j] += pinv[j, 0] * v[0] + pinv[j, 1] * v[1] + pinv[j, 2] * v[2]
            pushed = True
    if kind != 0:  # the rotation second; the pushes into the null space of both tasks
        return _orientation_second(floats, method, kind, goal_rot, goal_axis, tool, axes, jac, jac_inv, pushed, secondary, dphi)
    if pushed:  # dphi + (I - J^+ J) secondary
        moved = np.empty(3)
        for i in range(3):
            s = 0.0
            for j in range(n):
                s += jac[i, j] * secondary[j]
            moved[i] = s
        for j in range(n):
            dphi[j] = dphi[j] + secondary[j] - (jac_inv[j, 0] * moved[0] + jac_inv[j, 1] * moved[1] + jac_inv[j, 2] * moved[2])
    return True


@compiled(**_JIT)
def _exactly_safe(rows: np.ndarray, root: np.ndarray, floats: np.ndarray, phi: np.ndarray, cand: np.ndarray, lower: np.ndarray,
                  upper: np.ndarray, caps: np.ndarray, link: np.ndarray, part_radius: np.ndarray, cl_d: np.ndarray,
                  world: tuple[np.ndarray, ...], first: np.ndarray, second: np.ndarray, pair_radii: np.ndarray, least: float,
                  new_points: np.ndarray, new_frames: np.ndarray, new_axes: np.ndarray, tool: np.ndarray,
                  new_d: np.ndarray, new_t: np.ndarray, new_normal: np.ndarray,
                  new_gap: np.ndarray, new_gap_t: np.ndarray, new_gap_s: np.ndarray, new_gap_normal: np.ndarray, out: np.ndarray) -> bool:
    """Whether the pose ``cand`` keeps every guarantee from the pose ``phi`` (whose clearances are
    ``cl_d``, least gap ``least``) (:func:`~armanim.motion.solvers.barrier.exactly_safe`); its kinematics, clearances and gaps
    into the ``new_`` arrays (as far as the check went), its least gap into ``out[1]``."""
    n = phi.shape[0]
    buffer = floats[BUFFER]
    for j in range(n):
        if not (cand[j] - cand[j] == 0.0):  # NaN or infinity
            return False
        gap_new = min(cand[j] - lower[j], upper[j] - cand[j])
        gap_now = min(phi[j] - lower[j], upper[j] - phi[j])
        if gap_new <= 0.0 or gap_new < min(buffer, gap_now):
            return False
    _forward_one(rows, root, cand, new_points, new_frames, new_axes, tool)
    c = caps.shape[0]
    na = np.empty((c, 3))
    nb = np.empty((c, 3))
    _capsule_ends_one(new_points, new_frames, link, caps[:, 0:3], caps[:, 3:6], caps[:, 7] > 0.5, na, nb)
    parts = cl_d.shape[0]
    if cl_d.shape[1] > 0:
        _clearances(new_points, na, nb, part_radius, world, new_d, new_t, new_normal)
        now_links, now_tip, new_links, new_tip = np.inf, np.inf, np.inf, np.inf
        for part in range(parts):
            for k in range(cl_d.shape[1]):
                if part < parts - 1:
                    now_links = min(now_links, cl_d[part, k])
                    new_links = min(new_links, new_d[part, k])
                else:
                    now_tip = min(now_tip, cl_d[part, k])
                    new_tip = min(new_tip, new_d[part, k])
        if not new_links >= min(floats[CLEARANCE], now_links):
            return False
        if not new_tip >= min(floats[CLEARANCE], now_tip):
            return False
    out[1] = np.inf
    if first.shape[0]:
        out[1] = capsule_pair_gaps(na, nb, first, second, pair_radii, new_gap_t, new_gap_s, new_gap, new_gap_normal)
        if not out[1] >= min(floats[SELF_CLEARANCE], least):
            return False
    return True


@compiled(**_JIT)
def _frame(rows: np.ndarray, root: np.ndarray, floats: np.ndarray, method: int, phi: np.ndarray,
           points: np.ndarray, frames: np.ndarray, axes: np.ndarray, goal: np.ndarray, kind: int, goal_rot: np.ndarray,
           goal_axis: np.ndarray, lower: np.ndarray, upper: np.ndarray,
           caps: np.ndarray, link: np.ndarray, part_radius: np.ndarray, levers: np.ndarray,
           cl_d: np.ndarray, cl_t: np.ndarray, cl_normal: np.ndarray, world: tuple[np.ndarray, ...], influence: np.ndarray,
           first: np.ndarray, second: np.ndarray, pair_radii: np.ndarray, pair_lever_rows: np.ndarray, pair_levers: np.ndarray,
           gap: np.ndarray, gap_t: np.ndarray, gap_s: np.ndarray, gap_normal: np.ndarray, least: float,
           dphi: np.ndarray, step: np.ndarray, lo: np.ndarray, hi: np.ndarray, cons: np.ndarray, cons_lower: np.ndarray,
           cand: np.ndarray, new_points: np.ndarray, new_frames: np.ndarray, new_axes: np.ndarray, tool: np.ndarray,
           new_d: np.ndarray, new_t: np.ndarray, new_normal: np.ndarray,
           new_gap: np.ndarray, new_gap_t: np.ndarray, new_gap_s: np.ndarray, new_gap_normal: np.ndarray, out: np.ndarray) -> int:
    """One frame from the state (``phi``, its pose, clearances and gaps): the proposal into
    ``dphi``, the step capped to ``max_joint_step`` (the filter's nominal step) into ``step`` and
    the joint bounds into ``lo``, ``hi``. Returns

    - :data:`NUMPY`: an inverse failed; :data:`FILTER`: the proposal is not finite, or zero;
    - :data:`QP`: a row or a bound is broken: the filter's rows (as
      :func:`~armanim.motion.solvers.barrier.filter_constraints` builds them, in its order) into
      ``cons`` and ``cons_lower``, their count into ``out[2]``;
    - :data:`NOMINAL`: the filter takes the step as it is, but its exact check failed: the
      halvings are left to :func:`_settle`;
    - :data:`TAKEN`: the step is taken: the new pose ``cand`` (before wrapping), its
      kinematics, clearances and gaps in the ``new_`` arrays, into ``out`` the step's length and
      the new least gap."""
    n = phi.shape[0]
    c = caps.shape[0]
    a = np.empty((c, 3))
    b = np.empty((c, 3))
    _capsule_ends_one(points, frames, link, caps[:, 0:3], caps[:, 3:6], caps[:, 7] > 0.5, a, b)
    tool = np.empty((3, 3))  # the tool frame now, as the kinematics kernel makes it
    last = n - 1
    for r in range(3):
        f0, f1, f2 = frames[last, r, 0], frames[last, r, 1], frames[last, r, 2]
        for col in range(3):
            tool[r, col] = f0 * rows[last, TURN + col] + f1 * rows[last, TURN + 3 + col] + f2 * rows[last, TURN + 6 + col]
    if not _proposal(floats, method, phi, points, axes, goal, kind, goal_rot, goal_axis, tool, lower, upper, a, b, link, cl_d, cl_t, cl_normal, influence,
                     first, second, gap, gap_t, gap_s, gap_normal, least, dphi):
        return NUMPY
    biggest = 0.0
    for j in range(n):
        v = abs(dphi[j])
        if not v <= biggest:  # a NaN sticks
            biggest = v
    if not biggest < np.inf or biggest == 0.0:
        return FILTER
    cap = floats[MAX_JOINT_STEP]
    gamma = floats[GAMMA]
    buffer = floats[BUFFER]
    shrink = min(1.0, cap / biggest)
    travel = 0.0
    length = 0.0
    inside = True
    for j in range(n):
        step[j] = dphi[j] * shrink
        length += step[j] * step[j]
        lo[j], hi[j] = _step_bounds(phi[j], lower[j], upper[j], cap, gamma, buffer)
        if step[j] < lo[j] - VIOLATION or step[j] > hi[j] + VIOLATION:
            inside = False
        travel += abs(step[j]) * levers[j]
    length = math.sqrt(length)
    out[0] = length
    slack = 1.0 + BOUND_SLACK
    parts = cl_d.shape[0]
    obstacles = cl_d.shape[1] > 0
    pairs = first.shape[0]
    clear = inside  # clearly_allowed
    if clear and obstacles:
        lowest = np.inf
        for part in range(parts - 1):
            for k in range(cl_d.shape[1]):
                lowest = min(lowest, cl_d[part, k])
        clear = gamma * (lowest - floats[KEPT]) >= travel * slack + 1e-12
    if clear and pairs:
        clear = pair_rows_met(points, axes, a, b, link, first, second, gap_t, gap_s, gap_normal, gap, floats[KEPT_SELF], gamma,
                              pair_lever_rows, step, slack, BOUND_SLACK * travel + 1e-12, VIOLATION)
    if not clear:  # the rows of filter_constraints: each met, or the filter's QP
        broken = not inside
        count = 0
        target = floats[KEPT]
        reach = 2.0 * (length * floats[LEVER_NORM]) + 1e-9
        q = np.empty(3)
        jac = np.empty((3, n))
        for part in range(parts - 1):
            if link[part] < 0:  # on the base: no row (it never moves)
                continue
            for k in range(cl_d.shape[1]):
                if not cl_d[part, k] - target < reach:
                    continue
                f = cl_t[part, k]
                for i in range(3):
                    q[i] = a[part, i] + f * (b[part, i] - a[part, i])
                _point_jacobian(points, axes, link[part], q, jac)
                change = 0.0
                for j in range(n):
                    cons[count, j] = cl_normal[part, k, 0] * jac[0, j] + cl_normal[part, k, 1] * jac[1, j] + cl_normal[part, k, 2] * jac[2, j]
                    change += cons[count, j] * step[j]
                cons_lower[count] = -gamma * (cl_d[part, k] - target)
                if change < cons_lower[count] - VIOLATION:
                    broken = True
                count += 1
        if pairs:
            scratch = np.empty(9)
            kept = floats[KEPT_SELF]
            for p in range(pairs):
                if not gap[p] - kept < 2.0 * length * pair_levers[p] + 1e-9:
                    continue
                pair_row(points, axes, a, b, link, first, second, gap_t, gap_s, gap_normal, p, scratch, cons[count])
                change = 0.0
                for j in range(n):
                    change += cons[count, j] * step[j]
                cons_lower[count] = -gamma * (gap[p] - kept)
                if change < cons_lower[count] - VIOLATION:
                    broken = True
                count += 1
        if broken:
            out[2] = count
            return QP
    for j in range(n):
        cand[j] = phi[j] + step[j]
    if not _exactly_safe(rows, root, floats, phi, cand, lower, upper, caps, link, part_radius, cl_d, world, first, second,
                         pair_radii, least, new_points, new_frames, new_axes, tool, new_d, new_t, new_normal,
                         new_gap, new_gap_t, new_gap_s, new_gap_normal, out):
        return NOMINAL
    return TAKEN


@compiled(**_JIT)
def _settle(rows: np.ndarray, root: np.ndarray, floats: np.ndarray, halvings: int, phi: np.ndarray, step: np.ndarray,
            lower: np.ndarray, upper: np.ndarray, caps: np.ndarray, link: np.ndarray, part_radius: np.ndarray, cl_d: np.ndarray,
            world: tuple[np.ndarray, ...], first: np.ndarray, second: np.ndarray, pair_radii: np.ndarray, least: float,
            cand: np.ndarray, new_points: np.ndarray, new_frames: np.ndarray, new_axes: np.ndarray, tool: np.ndarray,
            new_d: np.ndarray, new_t: np.ndarray, new_normal: np.ndarray,
            new_gap: np.ndarray, new_gap_t: np.ndarray, new_gap_s: np.ndarray, new_gap_normal: np.ndarray, out: np.ndarray) -> float:
    """The filter's exact check and halvings of ``step`` from ``phi``: the first of
    ``phi + 0.5^i step``, i = 0 .. ``halvings``, that keeps every guarantee, its state in the
    ``new_`` arrays as :func:`_frame`'s, the length of its step into ``out[0]``; returns its
    scale 0.5^i, or -1 where none does."""
    n = phi.shape[0]
    scale = 1.0
    for _ in range(halvings + 1):
        length = 0.0
        for j in range(n):
            cand[j] = phi[j] + scale * step[j]
            length += (scale * step[j]) ** 2
        if _exactly_safe(rows, root, floats, phi, cand, lower, upper, caps, link, part_radius, cl_d, world, first, second,
                         pair_radii, least, new_points, new_frames, new_axes, tool, new_d, new_t, new_normal,
                         new_gap, new_gap_t, new_gap_s, new_gap_normal, out):
            out[0] = math.sqrt(length)
            return scale
        scale *= 0.5
    return -1.0


# ----------------------------------------------------------------------------- from Python


def _constants(problem: Problem) -> tuple[Any, ...]:
    """The kernel's constants of ``problem`` in its order, made once per problem (kept on it)."""
    kept = problem.__dict__.get("_compiled_frame_constants")
    if kept is not None:
        return cast("tuple[Any, ...]", kept)
    s = problem.solver
    floats = np.empty(FLOATS)
    floats[[BETA, MAX_STEP, MAX_JOINT_STEP, DAMPING, MARGIN, BUFFER, GAMMA, W_LIMITS, W_OBSTACLES]] = (
        s.beta, s.max_step, s.max_joint_step, s.damping, problem.limits.margin, limit_buffer(problem), problem.tunables.filter.gamma,
        s.w_limits, s.w_obstacles)
    floats[[KEPT, CLEARANCE, SELF_CLEARANCE, KEPT_SELF, SELF_INFLUENCE, LEVER_NORM, WEIGHT]] = (
        kept_clearance(problem), s.clearance, problem.self_pairs.clearance, kept_self_clearance(problem), self_influence(problem),
        float(np.linalg.norm(problem.lever_arms)), s.orientation_weight)
    caps, pairs, obstacles = problem.capsules, problem.self_pairs, problem.obstacles
    packed = caps.packed()
    rows, root = packed_chain(problem.arm)
    kept = (rows, root, floats) + tuple(np.ascontiguousarray(v, dtype=t) for v, t in (
        (problem.limits.lower, float), (problem.limits.upper, float), (packed, float), (caps.link, np.int64),
        (caps.part_radius, float), (problem.lever_arms, float)))
    kept += (_world(problem),) + tuple(np.ascontiguousarray(v, dtype=t) for v, t in (
        (obstacles.influence, float), (pairs.first, np.int64), (pairs.second, np.int64), (pairs.radii(caps), float),
        (problem.pair_lever_rows.reshape(len(pairs), problem.arm.n), float), (problem.pair_levers, float)))
    object.__setattr__(problem, "_compiled_frame_constants", kept)  # a cache of constants: the problem stays what it was
    return kept


def _world(problem: Problem) -> tuple[np.ndarray, ...]:
    """The obstacles as :func:`_clearances` reads them: the spheres' centres and radii, the solids'
    (boxes and capsule obstacles' axes) centres, half edges, rotations and radii, the parts the
    floor leaves out, the columns' scene order, the floor's height ((1,), or (0,) without one),
    and the cylinders' centres, rotations, half lengths and radii."""
    obstacles, caps = problem.obstacles, problem.capsules
    solids, cylinders = obstacles.solids, obstacles.cylinders
    order = obstacles.scene_order if obstacles.scene_order is not None else np.arange(len(obstacles))
    floor = np.zeros(0) if obstacles.floor is None else np.array([float(obstacles.floor)])
    return tuple(np.ascontiguousarray(v, dtype=t) for v, t in (
        (obstacles.centers.reshape(-1, 3), float), (obstacles.radii, float), (solids.centers.reshape(-1, 3), float),
        (solids.half.reshape(-1, 3), float), (solids.rotations.reshape(-1, 3, 3), float), (obstacles.solid_radius, float),
        (caps.on_base, np.bool_), (order, np.int64), (floor, float), (cylinders.centers.reshape(-1, 3), float),
        (cylinders.rotations.reshape(-1, 3, 3), float), (cylinders.half_length, float), (cylinders.radius, float)))


_EMPTY_CL = (np.zeros((0, 0)), np.zeros((0, 0)), np.zeros((0, 0, 3)))
_NO_ROTATION = np.eye(3)
_NO_AXIS = np.array([0.0, 0.0, 1.0])
_EMPTY_GAPS = (np.zeros(0), np.zeros(0), np.zeros(0), np.zeros((0, 3)))


def frame_step(problem: Problem, method: Literal["pinv", "dls"], state: ArmState, goal: np.ndarray,
               orientation: Orientation | None = None) -> tuple[SafeStep | None, np.ndarray | None]:
    """One frame of ``method`` toward ``goal`` (a position, and its ``orientation``) from ``state``: (the
    filter's answer, the proposal), or (None, the proposal) where the numpy filter must take it (a
    proposal that is not finite or zero: :func:`~armanim.motion.solvers.barrier.safe_step`), or
    (None, None) where the numpy path must make the proposal too (an inverse failed).

    The filter's QP, where a row is broken, is DAQP's (:func:`~armanim.motion.solvers.barrier.filtered_step`)
    on the rows the kernel built; the exact check and the halvings are compiled (:func:`_settle`)."""
    (rows, root, floats, lower, upper, caps, link, part_radius, levers, world, influence,
     first, second, pair_radii, pair_lever_rows, pair_levers) = _constants(problem)
    cl = state.clearance
    cl_d, cl_t, cl_normal = _EMPTY_CL if cl is None else (cl.d, cl.t, cl.normal)
    gaps = state.self_gaps
    gap, gap_t, gap_s, gap_normal = _EMPTY_GAPS if gaps is None else (gaps.d, gaps.t, gaps.s, gaps.normal)
    least = np.inf if gaps is None else float(gaps.least)
    pose = state.pose
    n = problem.arm.n
    dphi, step, lo, hi, cand = np.empty(n), np.empty(n), np.empty(n), np.empty(n), np.empty(n)
    pairs = len(first)
    cons, cons_lower = np.empty((cl_d.shape[0] * cl_d.shape[1] + pairs, n)), np.empty(cl_d.shape[0] * cl_d.shape[1] + pairs)
    new = _new_state_arrays(n, cl_d.shape, pairs)
    out = np.empty(3)
    assert pose.axes is not None  # the frame loop's poses come from the compiled kinematics
    kind = 0 if orientation is None else (1 if orientation.rotation is not None else 2)
    goal_rot = orientation.rotation if kind == 1 else _NO_ROTATION  # type: ignore[union-attr]  # kind 1: a rotation
    goal_axis = orientation.axis if kind == 2 else _NO_AXIS  # type: ignore[union-attr]  # kind 2: a tool axis
    status = _frame(rows, root, floats, DLS if method == "dls" else PINV, state.phi,
                    pose.points, pose.frames, pose.axes, np.ascontiguousarray(goal, dtype=float), kind,
                    np.ascontiguousarray(goal_rot, dtype=float), np.ascontiguousarray(goal_axis, dtype=float), lower, upper,
                    caps, link, part_radius, levers, cl_d, cl_t, cl_normal, world, influence,
                    first, second, pair_radii, pair_lever_rows, pair_levers, gap, gap_t, gap_s, gap_normal, least,
                    dphi, step, lo, hi, cons, cons_lower, cand, *new, out)
    if status == NUMPY:
        return None, None
    if status == FILTER:
        return None, dphi
    proposed = float(np.sqrt(dphi @ dphi))
    if status == TAKEN:
        return SafeStep(_state(problem, cand, new, out, cl is not None), _fraction(float(out[0]), proposed, step, dphi), None), dphi
    nominal = step
    constraints = None
    if status == QP:
        count = int(out[2])
        constraints = Constraints(cons[:count], cons_lower[:count], lo, hi)
        step = filtered_step(nominal, constraints)
    scale = _settle(rows, root, floats, problem.tunables.filter.halvings, state.phi, step, lower, upper, caps, link, part_radius,
                    cl_d, world, first, second, pair_radii, least, cand, *new, out)
    if scale < 0.0:  # no halving kept the guarantees: the arm stays
        return SafeStep(state, 0.0, blocker(nominal, constraints)), dphi
    blocked = None if step is nominal and scale == 1.0 else blocker(nominal, constraints)
    return SafeStep(_state(problem, cand, new, out, cl is not None), _fraction(float(out[0]), proposed, scale * step, dphi), blocked), dphi


def _fraction(length: float, proposed: float, taken: np.ndarray, dphi: np.ndarray) -> float:
    """|taken| / |dphi| from the lengths the kernel found, or :func:`~armanim.motion.solvers.barrier.step_fraction`'s
    where the proposal's squares underflow or overflow."""
    return length / proposed if 0.0 < proposed < np.inf else step_fraction(taken, dphi)


_NewState = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray,
                  np.ndarray, np.ndarray]
"""A new state's arrays as the kernels fill them (:func:`_new_state_arrays`)."""


def _new_state_arrays(n: int, clearances: tuple[int, ...], pairs: int) -> _NewState:
    """The kernel's arrays of a new state: points, frames, axes, tool; clearances d, t, normal;
    the pairs' gaps, t, s, normal."""
    parts, m = clearances
    return (np.empty((n + 1, 3)), np.empty((n, 3, 3)), np.empty((n, 3)), np.empty((3, 3)),
            np.empty((parts, m)), np.empty((parts, m)), np.empty((parts, m, 3)),
            np.empty(pairs), np.empty(pairs), np.empty(pairs), np.empty((pairs, 3)))


def _state(problem: Problem, cand: np.ndarray, new: _NewState, out: np.ndarray, obstacles: bool) -> ArmState:
    """The new state the kernel measured at ``cand`` (unlimited joints wrapped, as the filter's states)."""
    points, frames, axes, _, d, t, normal, gap, gap_t, gap_s, gap_normal = new
    gaps = None
    if len(gap):
        gaps = SelfGaps(gap, gap_t, gap_s, gap_normal)
        object.__setattr__(gaps, "_least", np.float64(out[1]))  # the kernel found it: SelfGaps.least need not look again
    return ArmState(wrap_unlimited(problem, cand), Pose(points=points, frames=frames, axes=axes),
                    Clearances(d=d, t=t, normal=normal) if obstacles else None, gaps)
