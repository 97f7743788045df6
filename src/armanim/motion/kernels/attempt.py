"""One attempt of a pose solve with ``pinv`` or ``dls``, compiled (numba): the whole loop of
steps in one call, where the safety filter's only rows are the joints' own bounds.

:func:`armanim.motion.ik.solve_pose`'s attempt takes steps from a start until the pose is
within tolerance, the attempt stalls or its steps run out. Each step is the method's
proposal (:func:`armanim.motion.solvers.linear.linear_step`) through the filter
(:func:`armanim.motion.filter.barrier.safe_step`); in numpy and Python that is some 500 calls
and a few hundred microseconds a step. Here the same step is written as loops over small
arrays, with the kinematics of :mod:`armanim.arm.kernel` and the pieces of
:mod:`armanim.motion.kernels` (tasks, qp, check):

- the proposal: the Jacobian, the position task (and the rotation task: stacked into one
  pseudo-inverse where the arm holds every orientation, else second in priority, in the
  position's null space), the joint-limit push in the null space;
- the inverses of :mod:`armanim.motion.kernels.linalg`;
- the filter: the proposal scaled to the joints' step caps (radians; metres for a prismatic joint,
  whose columns the kinematics' world axes mark: :func:`armanim.arm.kernel.joint_slides`), clipped to the joints' velocity
  damper (the filter's QP when its only rows are bounds: its answer is the clip), the limits
  checked exactly, halved when they fail;
- the progress measure and the stall test of the attempt;
- the arm's own pairs: each pair's push inside its influence (``self_influence``: the method's
  inverse of J_A - J_B, in the null space with the limits'), and the filter's rows of the pairs
  near enough for the step, n . (J_A - J_B) dPhi >= -gamma (d - d_kept); where the proposal
  breaks one, the filter's QP (joint bounds and those rows) is solved exactly in the call by a
  dual active-set method (:func:`armanim.motion.kernels.qp.closest_step`), relaxed as the numpy filter relaxes it where
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
from typing import NamedTuple

import numpy as np

from armanim.arm.kernel import JIT, _forward_one, compiled
from armanim.arm.kernel import KIND as KIND_COLUMN
from armanim.motion.filter.barrier import VIOLATION
from armanim.motion.kernels.check import pair_gaps
from armanim.motion.kernels.layout import (
    BUFFER,
    DONE,
    GAMMA,
    HALVINGS,
    HANDED_BACK,
    KIND,
    METHOD,
    NUMERICAL,
    SELF_CLEARANCE,
    SELF_INFLUENCE,
    SINCE_BEST,
    SLACK,
    STACKED,
    STALL,
    STEPS,
    STEPS_CAP,
    TOL,
)
from armanim.motion.kernels.qp import bound_rows, filtered_with_pairs, lever_travel, pairs_far
from armanim.motion.kernels.tasks import attempt_proposal, progress_measure, self_pair_push, step_bounds, step_shrink
from armanim.motion.orientation import Orientation
from armanim.motion.problem import Problem


@compiled(**JIT)
def attempt_loop(
    problem: tuple[np.ndarray, ...],
    pair_arrays: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray],
    target: tuple[np.ndarray, np.ndarray, np.ndarray],
    start: np.ndarray,
    method: int,
    stacked: bool,
    steps_cap: int,
    kind: int,
    steps_so_far: int,
    since_so_far: int,
    best_so_far: float,
    out: np.ndarray,
) -> int:
    """The attempt from ``start``; into ``out`` (2 n + 9,): the pose it ends at (n), its tip (3), the
    distance, the angle, the progress measure, the best progress, the steps taken and the steps
    since the best progress, and the angles its kinematics were computed at (n: before wrapping).
    Returns :data:`DONE`, :data:`NUMERICAL` or :data:`HANDED_BACK` (the numpy path takes over from
    that pose with those counters).

    ``problem``: the first nine fields of the problem's
    :class:`~armanim.motion.kernels.layout.KernelProblem` (the chain ... each capsule's joint);
    ``pair_arrays``: its ``first``, ``second``, ``pair_lever_rows`` and ``pair_levers``;
    ``target``: the tip's goal (3,), the goal's rotation (3, 3) and tool axis (3,) (placeholders
    where ``kind`` is another). All three are plain tuples, unpacked here once. ``settings``: the
    problem's int settings (:attr:`~armanim.motion.kernels.layout.KernelProblem.ints`), the call's
    own (the method, whether the pose task is stacked, the attempt's steps, the orientation's
    kind, the counters so far) given as numbers: a number crosses into the call for less than an
    array's copy and writes.

    The loop's body stays in one piece: a helper handed the pose's arrays (or a tuple of them)
    counts their references at each call; the pairs' blocks moved into helpers handed the pose as
    tuples made the attempt 5-25 % slower (in-process A/B against main, 2026-12-07)."""
    rows, root, lower, upper, caps_step, floats, settings, caps, caps_link = problem  # KernelProblem's order
    first, second, levers, pair_levers = pair_arrays
    goal, goal_rot, goal_axis = target
    n = start.shape[0]
    ints = settings.copy()
    ints[METHOD], ints[STACKED], ints[STEPS_CAP], ints[KIND], ints[STEPS], ints[SINCE_BEST] = (
        method,
        stacked,
        steps_cap,
        kind,
        steps_so_far,
        since_so_far,
    )
    kind = ints[KIND]
    tol = floats[TOL]
    gamma = floats[GAMMA]
    buffer = floats[BUFFER]
    slack = floats[SLACK]
    pairs = first.shape[0]
    points = np.empty((2, n + 1, 3))  # the pose now and the candidate: slots swapped by index
    frames = np.empty((2, n, 3, 3))
    slides = False
    for j in range(n):
        slides = slides or rows[j, KIND_COLUMN] != 0.0
    axes = np.zeros(
        (2, n, 4 if slides else 3)
    )  # with each joint's kind in a fourth column where one slides (joint_slides)
    if slides:
        for j in range(n):
            axes[0, j, 3] = axes[1, j, 3] = rows[j, KIND_COLUMN]
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
    progress = progress_measure(floats, kind, goal, goal_rot, goal_axis, points[now], tool[now], residual, errors)
    best = progress if best_so_far != best_so_far else best_so_far
    since_best = ints[SINCE_BEST]
    steps = ints[STEPS]
    status = DONE
    dphi = np.empty(n)
    step = np.empty(n)
    nominal = np.empty(n)
    low = np.empty(n)
    high = np.empty(n)
    pair_push = np.empty(n)
    cmat = bound_rows(n, pairs)
    cb = np.empty(2 * n + pairs)
    twists = np.empty((n, 6))
    in_rows = np.empty(pairs, dtype=np.bool_)
    # the filter QP's work space (:func:`~armanim.motion.kernels.qp.filtered_with_pairs`)
    qp_work = (cmat, cb, twists, in_rows)
    limits = (lower, upper)
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
                    least[now] = pair_gaps(
                        points[now], frames[now], caps, caps_link, first, second, ends[now], gaps[now], near[now]
                    )
                    exact[now] = True
                    for q in range(pairs):
                        bound[q] = gaps[now, q] - slack
                within = (
                    least[now] < floats[SELF_INFLUENCE]
                )  # the exact gaps: a pair inside R (else no push, and none near 0)
            if within:
                pushing = self_pair_push(
                    floats,
                    ints[METHOD],
                    gaps[now],
                    points[now],
                    axes[now],
                    caps_link,
                    ends[now],
                    near[now],
                    first,
                    second,
                    pair_push,
                )
                if pushing < 0:
                    status = HANDED_BACK
                    break
                pairs_push = pushing == 1
        proposed = attempt_proposal(
            floats,
            ints,
            phi,
            points[now],
            axes[now],
            tool[now],
            goal,
            residual,
            limits,
            pair_push,
            pairs_push,
            dphi,
        )
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
        shrink = step_shrink(caps_step, dphi)
        nominal_length = 0.0
        inside = True  # the nominal step within the joints' bounds, as the filter judges it (to VIOLATION)
        for j in range(n):
            nominal[j] = dphi[j] * shrink
            step[j] = nominal[j]
            nominal_length += step[j] * step[j]
            low[j], high[j] = step_bounds(phi[j], lower[j], upper[j], caps_step[j], gamma, buffer)
            if step[j] < low[j] - VIOLATION or step[j] > high[j] + VIOLATION:
                inside = False
        nominal_length = math.sqrt(nominal_length)
        if not inside:  # the filter's QP on bounds alone: its answer is the clip
            for j in range(n):
                step[j] = min(max(step[j], low[j]), high[j])
        if pairs and not pairs_far(
            floats, bound, levers, step
        ):  # a pair's row could act: the filter's QP with the pairs' rows
            if not exact[now]:
                least[now] = pair_gaps(
                    points[now], frames[now], caps, caps_link, first, second, ends[now], gaps[now], near[now]
                )
                exact[now] = True
                for q in range(pairs):
                    bound[q] = gaps[now, q] - slack
            pose = (points[now], axes[now], caps_link, ends[now], near[now], gaps[now])
            if not filtered_with_pairs(
                floats, pose, (first, second, pair_levers), nominal, nominal_length, (low, high), qp_work, step
            ):
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
                    cand_bound[q] = bound[q] - lever_travel(levers, q, step, scale) * (1.0 + 1e-9) - slack
                    certain = certain and cand_bound[q] >= floats[SELF_CLEARANCE]
                if not certain:
                    if not exact[now]:
                        least[now] = pair_gaps(
                            points[now], frames[now], caps, caps_link, first, second, ends[now], gaps[now], near[now]
                        )
                        exact[now] = True
                    _forward_one(rows, root, cand, points[other], frames[other], axes[other], tool[other])
                    least[other] = pair_gaps(
                        points[other],
                        frames[other],
                        caps,
                        caps_link,
                        first,
                        second,
                        ends[other],
                        gaps[other],
                        near[other],
                    )
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
        progress = progress_measure(floats, kind, goal, goal_rot, goal_axis, points[now], tool[now], residual, errors)
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


_NO_ROTATION = np.eye(3)
_NO_AXIS = np.array([0.0, 0.0, 1.0])


def run_attempt(
    problem: Problem,
    step: int,
    stacked: bool,
    goal: np.ndarray,
    start: np.ndarray,
    steps_cap: int,
    orientation: Orientation | None,
    counters: tuple[int, float | None, int] = (0, None, 0),
) -> CompiledAttempt:
    """One attempt from ``start`` (radians) with the compiled ``step`` (:data:`PINV` or :data:`DLS`);
    ``stacked``: the pose task as one (:func:`armanim.motion.solvers.linear.stacks_the_pose_task`);
    ``counters``: where an attempt goes on, its steps so far, its best progress and the steps since.

    Only for a problem without obstacles and with the analytic Jacobian (the caller's test)."""
    k = problem.kernel
    kind = 0 if orientation is None else (1 if orientation.rotation is not None else 2)
    steps, best, since_best = counters
    n = len(k.lower)
    out = np.empty(2 * n + 9)
    goal_rot = orientation.rotation if kind == 1 else _NO_ROTATION  # type: ignore[union-attr]  # kind 1: a rotation
    goal_axis = orientation.axis if kind == 2 else _NO_AXIS  # type: ignore[union-attr]  # kind 2: a tool axis
    status = attempt_loop(
        k[:9],  # a plain tuple (numba's dispatch types it at C speed): the chain ... each capsule's joint
        (k.first, k.second, k.pair_lever_rows, k.pair_levers),
        (
            np.ascontiguousarray(goal, dtype=float),
            np.ascontiguousarray(goal_rot, dtype=float),
            np.ascontiguousarray(goal_axis, dtype=float),
        ),
        np.ascontiguousarray(start, dtype=float),
        step,
        stacked,
        steps_cap,
        kind,
        steps,
        since_best,
        np.nan if best is None else best,
        out,
    )
    numbers = out[n : n + 9].tolist()
    return CompiledAttempt(
        out[:n],
        out[n : n + 3],
        numbers[3],
        None if kind == 0 else numbers[4],
        numbers[5],
        int(numbers[7]),
        status == NUMERICAL,
        status == HANDED_BACK,
        numbers[6],
        int(numbers[8]),
        out[n + 9 :],
    )
