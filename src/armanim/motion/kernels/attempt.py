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

from armanim.arm.kernel import INLINE, JIT, _forward_one, compiled
from armanim.arm.kernel import KIND as KIND_COLUMN
from armanim.motion.filter.barrier import VIOLATION
from armanim.motion.kernels.check import pair_gaps
from armanim.motion.kernels.layout import (
    BUFFER,
    DONE,
    GAMMA,
    HALVINGS,
    HANDED_BACK,
    INTS,
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

PHI, POSE_PHI, CAND, DPHI, STEP, NOMINAL, LOW, HIGH, PAIR_PUSH, VECTORS = range(10)
"""Rows of an attempt's joint vectors, one (VECTORS, n) array (radians; metres for a prismatic
joint): the pose now (its unlimited joints wrapped), the angles its kinematics were computed at
(before wrapping), the candidate pose, the proposal, the filter's step, the nominal step (the
proposal scaled to the joints' caps), each joint's step bounds low and high, the pairs' push."""

GAPS, BOUND, CAND_BOUND, GAP_ROWS = 0, 2, 3, 4
"""Rows of an attempt's pairs' gaps, one (GAP_ROWS, P) array (metres): the exact gaps of the pose
in slot s at row ``GAPS + s`` (where computed: :data:`EXACT`), then a lower bound of each pair's
gap at the pose now and at the candidate."""

PROGRESS, BEST, LEAST, NUMBERS = 0, 1, 2, 4
"""Places in an attempt's floats (NUMBERS,): the progress measure now and the best so far, and the
least pair gap of the pose in slot s at ``LEAST + s`` (metres, where computed)."""

NOW, EXACT, COUNTS = INTS, INTS + 1, INTS + 3
"""Places of an attempt's own counters in its int array (COUNTS,), after the settings'
(:data:`~armanim.motion.kernels.layout.INTS`; the steps and the steps since the best progress are
the settings' :data:`STEPS` and :data:`SINCE_BEST`): the slot of the pose now (0 or 1), and
whether the pairs' gaps of the pose in slot s are computed (1) at ``EXACT + s``."""

KEPT, UNSURE, NONE_KEPT = 1, 2, 3
"""What :func:`first_kept` finds: a scale kept, the gaps' bounds cannot tell, no scale kept."""

GO = 3
"""What :func:`proposal_status` and :func:`halving_status` answer where the step goes on (else the
attempt's end: :data:`DONE`, :data:`NUMERICAL` or :data:`HANDED_BACK`)."""

Slots = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]
"""An attempt's poses, two slots of each array (the pose now and the candidate, swapped by index,
:data:`NOW`): the joints' ``points`` (2, n + 1, 3) (metres), ``frames`` (2, n, 3, 3), world
``axes`` (2, n, 3; with each joint's kind in a fourth column where one slides:
:func:`~armanim.arm.kernel.joint_slides`) and the ``tool`` frame (2, 3, 3)."""

PairSlots = tuple[np.ndarray, np.ndarray, np.ndarray]
"""An attempt's pairs: the gaps' rows (GAP_ROWS, P) (:data:`GAPS`), and for the pose in each slot
the capsules' world ``ends`` (2, 2, c, 3) and the pairs' closest points ``near`` (2, P, 5): t, s
and the normal (:func:`~armanim.motion.kernels.check.pair_gaps`), where computed."""

State = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]
"""An attempt's own numbers: its joint vectors (VECTORS, n) (:data:`PHI`), floats (NUMBERS,)
(:data:`PROGRESS`), ints (COUNTS,) (:data:`NOW`), the orientation's residual (3,) and the pose's
distance and angle (2,) (:func:`~armanim.motion.kernels.tasks.progress_measure`)."""


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
    """The attempt from ``start`` (n,); into ``out`` (2 n + 9,): the pose it ends at (n), its tip (3),
    the distance, the angle, the progress measure, the best progress, the steps taken and the steps
    since the best progress, and the angles its kinematics were computed at (n: before wrapping).
    Returns :data:`DONE`, :data:`NUMERICAL` or :data:`HANDED_BACK` (the numpy path takes over from
    that pose with those counters).

    ``problem``: the first nine fields of the problem's
    :class:`~armanim.motion.kernels.layout.KernelProblem` (the chain ... each capsule's joint);
    ``pair_arrays``: its ``first``, ``second``, ``pair_lever_rows`` and ``pair_levers``;
    ``target``: the tip's goal (3,), the goal's rotation (3, 3) and tool axis (3,) (placeholders
    where ``kind`` is another). The call's own settings (the method, whether the pose task is
    stacked, the attempt's steps, the orientation's kind, the counters so far) are numbers: a
    number crosses into the call for less than an array's copy and writes.

    The attempt's state is a few merged arrays, their rows and places named by this module's
    constants (:data:`State`, :data:`Slots`, :data:`PairSlots`), so that each of the step's helpers
    takes a few arrays: numba counts the references of each array handed to a helper (each member
    of a tuple) where it cannot prove them paired, and helpers handed some 35 arrays, some in
    tuples, made the attempt 3-38 % slower (in-process A/B against main, 2026-12-07). The small
    helpers make no array and are compiled on their own (their counts pruned, then inlined by
    LLVM); :func:`exact_gaps`, which takes views, is inlined by numba; the tuples cross once an
    attempt, into :func:`attempt_steps`."""
    rows, root, floats, caps = problem[0], problem[1], problem[5], problem[7]
    pairs, n = pair_arrays[0].shape[0], start.shape[0]
    ints = attempt_ints(problem[6], method, stacked, steps_cap, kind, steps_so_far, since_so_far)
    vec = np.empty((VECTORS, n))
    for j in range(n):
        vec[PHI, j] = vec[POSE_PHI, j] = start[j]
    slots = pose_slots(rows, n)
    points, _, _, tool = slots
    pair_slots = (np.full((GAP_ROWS, pairs), -np.inf), np.empty((2, 2, caps.shape[0], 3)), np.empty((2, pairs, 5)))
    nums, residual, errors = np.empty(NUMBERS), np.empty(3), np.empty(2)
    _forward_one(rows, root, vec[PHI], points[0], slots[1][0], slots[2][0], tool[0])
    nums[PROGRESS] = progress_measure(
        floats, kind, target[0], target[1], target[2], points[0], tool[0], residual, errors
    )
    nums[BEST] = nums[PROGRESS] if best_so_far != best_so_far else best_so_far
    status = attempt_steps(problem, pair_arrays, target, (vec, nums, ints, residual, errors), slots, pair_slots)
    ended(vec, points[ints[NOW]], errors, nums, ints, out)
    return status


@compiled(**JIT)
def attempt_steps(
    problem: tuple[np.ndarray, ...],
    pair_arrays: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray],
    target: tuple[np.ndarray, np.ndarray, np.ndarray],
    state: State,
    slots: Slots,
    pair_slots: PairSlots,
) -> int:
    """The attempt's steps until the pose is within tolerance, the attempt stalls or its steps run
    out. Each step: the pairs' push where a pair may be inside its influence, the proposal, the
    filter's step on the joints' bounds (with the pairs' rows where one could act), the halvings,
    the pose taken.

    Parameters
    ----------
    problem, pair_arrays, target : tuples of arrays
        As :func:`attempt_loop` takes them.
    state : State
        The attempt's joint vectors, floats, ints, residual and errors (:data:`State`), updated:
        the pose (radians), the progress and the counters where the attempt ends.
    slots : Slots
        The two poses' kinematics (:data:`Slots`; the pose now's computed), updated.
    pair_slots : PairSlots
        The pairs' gaps, bounds, ends and closest points (:data:`PairSlots`; metres), updated.

    Returns
    -------
    int
        :data:`DONE`, :data:`NUMERICAL` or :data:`HANDED_BACK`.

    Notes
    -----
    The pairs' blocks call their pieces here, with the arrays themselves, and test whether the
    exact gaps are computed before calling: helpers handed them as tuples, or called only to find
    them computed, cost some 0.3 us a step (10 % of a small arm's step).
    """
    rows, root, lower, upper, caps_step, floats, _, caps, caps_link = problem  # KernelProblem's order
    first, second, levers, pair_levers = pair_arrays
    goal, goal_rot, goal_axis = target
    vec, nums, ints, residual, errors = state
    points, frames, axes, tool = slots
    gap_rows, ends, near = pair_slots
    phi, cand, dphi, step, push = vec[PHI], vec[CAND], vec[DPHI], vec[STEP], vec[PAIR_PUSH]
    pairs, method, limits, bound = first.shape[0], ints[METHOD], (lower, upper), gap_rows[BOUND]
    qp_work, nominal, bounds = filter_work(phi.shape[0], pairs), vec[NOMINAL], (vec[LOW], vec[HIGH])
    while nums[PROGRESS] >= floats[TOL] and ints[STEPS] < ints[STEPS_CAP]:
        now, other, pushing = ints[NOW], 1 - ints[NOW], 0
        if pairs and pairs_within(floats, bound):  # the exact gaps, where a bound cannot show none inside
            if not ints[EXACT + now]:
                exact_gaps(now, ints, nums, caps, caps_link, first, second, points, frames, gap_rows, ends, near)
                bounds_from_gaps(floats, gap_rows, now)
            if nums[LEAST + now] < floats[SELF_INFLUENCE]:  # a pair inside: its push (-1: the numpy step's)
                gap_now, ends_now, near_now = gap_rows[GAPS + now], ends[now], near[now]
                pushing = self_pair_push(
                    floats, method, gap_now, points[now], axes[now], caps_link, ends_now, near_now, first, second, push
                )
                if pushing < 0:
                    return HANDED_BACK
        proposed = attempt_proposal(
            floats, ints, phi, points[now], axes[now], tool[now], goal, residual, limits, push, pushing == 1, dphi
        )
        status = proposal_status(proposed, dphi, ints)
        if status != GO:
            return status
        length = nominal_step(floats, vec, dphi, lower, upper, caps_step)
        if pairs and not pairs_far(floats, bound, levers, step):  # a pair's row could act: the QP with the rows
            if not ints[EXACT + now]:
                exact_gaps(now, ints, nums, caps, caps_link, first, second, points, frames, gap_rows, ends, near)
                bounds_from_gaps(floats, gap_rows, now)
            pose = (points[now], axes[now], caps_link, ends[now], near[now], gap_rows[GAPS + now])
            if not filtered_with_pairs(
                floats, pose, (first, second, pair_levers), nominal, length, bounds, qp_work, step
            ):
                return HANDED_BACK
        scale, tries, kept = first_kept(floats, vec, step, lower, upper, gap_rows, levers, 1.0, ints[HALVINGS] + 1)
        while kept == UNSURE:  # the gaps' bounds cannot tell: the exact gaps of both poses
            if not ints[EXACT + now]:
                exact_gaps(now, ints, nums, caps, caps_link, first, second, points, frames, gap_rows, ends, near)
            _forward_one(rows, root, cand, points[other], frames[other], axes[other], tool[other])
            exact_gaps(other, ints, nums, caps, caps_link, first, second, points, frames, gap_rows, ends, near)
            kept = exact_kept(floats, nums, ints, gap_rows)
            if kept == 0:
                scale, tries, kept = first_kept(floats, vec, step, lower, upper, gap_rows, levers, scale * 0.5, tries)
        status = halving_status(kept, scale, step, ints)
        if status != GO:
            return status
        if not ints[EXACT + other]:
            _forward_one(rows, root, cand, points[other], frames[other], axes[other], tool[other])
        taken(vec, ints, gap_rows, lower)
        nums[PROGRESS] = progress_measure(
            floats, ints[KIND], goal, goal_rot, goal_axis, points[other], tool[other], residual, errors
        )
        if stalled(floats, nums, ints):
            return DONE
    return DONE


@compiled(**INLINE)
def attempt_ints(
    settings: np.ndarray, method: int, stacked: bool, steps_cap: int, kind: int, steps: int, since_best: int
) -> np.ndarray:
    """An attempt's ints (COUNTS,): the problem's int ``settings`` (INTS,), the call's own, the pose
    now in slot 0, no gaps computed."""
    ints = np.zeros(COUNTS, dtype=np.int64)
    for i in range(INTS):
        ints[i] = settings[i]
    ints[METHOD], ints[STACKED], ints[STEPS_CAP], ints[KIND], ints[STEPS], ints[SINCE_BEST] = (
        method,
        stacked,
        steps_cap,
        kind,
        steps,
        since_best,
    )
    return ints


@compiled(**INLINE)
def pose_slots(rows: np.ndarray, n: int) -> Slots:
    """The two slots of an attempt's poses (:data:`Slots`) for a chain of ``rows`` (n, WIDTH), the
    axes' kind column set where a joint slides."""
    slides = False
    for j in range(n):
        slides = slides or rows[j, KIND_COLUMN] != 0.0
    axes = np.zeros((2, n, 4 if slides else 3))
    if slides:
        for j in range(n):
            axes[0, j, 3] = axes[1, j, 3] = rows[j, KIND_COLUMN]
    return np.empty((2, n + 1, 3)), np.empty((2, n, 3, 3)), axes, np.empty((2, 3, 3))


@compiled(**INLINE)
def filter_work(n: int, pairs: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The filter QP's work space for n joints and ``pairs`` pairs
    (:func:`~armanim.motion.kernels.qp.filtered_with_pairs`)."""
    return bound_rows(n, pairs), np.empty(2 * n + pairs), np.empty((n, 6)), np.empty(pairs, dtype=np.bool_)


@compiled(**JIT)
def pairs_within(floats: np.ndarray, bound: np.ndarray) -> bool:
    """Whether a pair's gap bound ``bound`` (P,; metres) cannot show it outside its push's
    influence (``self_influence``)."""
    for q in range(bound.shape[0]):
        if not bound[q] >= floats[SELF_INFLUENCE] + floats[SLACK]:
            return True
    return False


@compiled(**INLINE)
def exact_gaps(
    slot: int,
    ints: np.ndarray,
    nums: np.ndarray,
    caps: np.ndarray,
    caps_link: np.ndarray,
    first: np.ndarray,
    second: np.ndarray,
    points: np.ndarray,
    frames: np.ndarray,
    gap_rows: np.ndarray,
    ends: np.ndarray,
    near: np.ndarray,
) -> None:
    """The pairs' exact gaps of the pose in slot ``slot`` (:func:`~armanim.motion.kernels.check.pair_gaps`).

    Parameters
    ----------
    slot : int
        0 or 1 (:data:`NOW`).
    ints, nums : arrays
        The attempt's ints (COUNTS,), the slot marked computed at :data:`EXACT`, and floats
        (NUMBERS,), the slot's least gap (metres) into :data:`LEAST`.
    caps, caps_link, first, second : arrays
        The capsules (c, 8), each one's joint (c,), the pairs' capsules (P,) each.
    points, frames : arrays
        The two poses' joint points (2, n + 1, 3) (metres) and frames (2, n, 3, 3) (:data:`Slots`).
    gap_rows, ends, near : arrays
        Into their slot's rows: the gaps (GAP_ROWS, P) (metres), the capsules' world ends
        (2, 2, c, 3) and the pairs' closest points and normals (2, P, 5) (:data:`PairSlots`).

    Notes
    -----
    The callers test the mark first, and it is inlined: a call would count the references of each
    array handed in.
    """
    nums[LEAST + slot] = pair_gaps(
        points[slot], frames[slot], caps, caps_link, first, second, ends[slot], gap_rows[GAPS + slot], near[slot]
    )
    ints[EXACT + slot] = 1


@compiled(**JIT)
def bounds_from_gaps(floats: np.ndarray, gap_rows: np.ndarray, slot: int) -> None:
    """Each pair's gap bound (``gap_rows``' :data:`BOUND` row) its exact gap at the pose in slot
    ``slot`` less the ``slack`` (metres)."""
    for q in range(gap_rows.shape[1]):
        gap_rows[BOUND, q] = gap_rows[GAPS + slot, q] - floats[SLACK]


@compiled(**JIT)
def proposal_status(proposed: int, dphi: np.ndarray, ints: np.ndarray) -> int:
    """What the attempt does with the proposal ``dphi`` (n,) whose proposal answered ``proposed``:
    :data:`GO` on; else it ends, :data:`HANDED_BACK` (no step counted), :data:`NUMERICAL` (an
    inverse failed or an entry is not finite) or :data:`DONE` (all zero: the same pose would propose
    the same again), a step counted in ``ints``' :data:`STEPS`."""
    if proposed == HANDED_BACK:
        return HANDED_BACK
    biggest = 0.0
    for j in range(dphi.shape[0]):
        v = abs(dphi[j])
        if not v <= biggest:  # a NaN sticks
            biggest = v
    if proposed != DONE or not biggest < np.inf:
        ints[STEPS] += 1
        return NUMERICAL
    if biggest == 0.0:
        ints[STEPS] += 1
        return DONE
    return GO


@compiled(**JIT)
def nominal_step(
    floats: np.ndarray, vec: np.ndarray, dphi: np.ndarray, lower: np.ndarray, upper: np.ndarray, caps: np.ndarray
) -> float:
    """The filter's step on the joints' bounds alone, into ``vec``'s rows: the proposal ``dphi``
    (its :data:`DPHI` row) scaled to the joints' ``caps`` (n,) into :data:`NOMINAL`, each joint's
    step bounds into :data:`LOW` and :data:`HIGH` (the ``lower``, ``upper`` limits' dampers), and
    the nominal clipped to them (the bounds' QP's answer) into :data:`STEP`. Returns the nominal
    step's length."""
    shrink = step_shrink(caps, dphi)
    length = 0.0
    inside = True  # the nominal step within the joints' bounds, as the filter judges it (to VIOLATION)
    for j in range(dphi.shape[0]):
        vec[NOMINAL, j] = vec[STEP, j] = dphi[j] * shrink
        length += vec[STEP, j] * vec[STEP, j]
        vec[LOW, j], vec[HIGH, j] = step_bounds(vec[PHI, j], lower[j], upper[j], caps[j], floats[GAMMA], floats[BUFFER])
        if vec[STEP, j] < vec[LOW, j] - VIOLATION or vec[STEP, j] > vec[HIGH, j] + VIOLATION:
            inside = False
    if not inside:
        for j in range(dphi.shape[0]):
            vec[STEP, j] = min(max(vec[STEP, j], vec[LOW, j]), vec[HIGH, j])
    return math.sqrt(length)


@compiled(**JIT)
def first_kept(
    floats: np.ndarray,
    vec: np.ndarray,
    step: np.ndarray,
    lower: np.ndarray,
    upper: np.ndarray,
    gap_rows: np.ndarray,
    levers: np.ndarray,
    scale: float,
    tries: int,
) -> tuple[float, int, int]:
    """The filter's exact check and halvings: from ``scale`` on, at most ``tries`` scales (each half
    the last), the first whose candidate phi + scale ``step`` keeps the joints' limits and, by the
    gaps' bounds, every pair no nearer than ``self_clearance``.

    Parameters
    ----------
    floats : (FLOATS,) array
        The settings: ``buffer``, ``slack``, ``self_clearance``.
    vec : (VECTORS, n) array
        The joint vectors: :data:`PHI` read, the candidate into :data:`CAND` (radians).
    step : (n,) array
        The filter's step (its :data:`STEP` row; radians, metres for a prismatic joint).
    lower, upper : (n,) arrays
        The joints' limits.
    gap_rows : (GAP_ROWS, P) array
        The gaps' rows: :data:`BOUND` read, the candidate's bounds into :data:`CAND_BOUND` (metres).
    levers : (P, n) array
        The pairs' lever arms (a step dphi changes a gap by at most levers @ |dphi|; metres a radian).
    scale : float
        The first scale to try.
    tries : int
        How many scales are left to try.

    Returns
    -------
    tuple of (float, int, int)
        The scale, the tries left after it, and :data:`KEPT`; :data:`UNSURE` where the bounds
        cannot tell (the exact gaps must: :func:`exact_kept`); :data:`NONE_KEPT` where no scale
        keeps the limits.
    """
    for t in range(tries):
        if limits_kept(floats[BUFFER], vec, step, lower, upper, scale):
            if gap_rows.shape[1] == 0 or bounds_certain(floats, gap_rows, levers, step, scale):
                return scale, tries - t - 1, KEPT
            return scale, tries - t - 1, UNSURE
        scale *= 0.5
    return scale, 0, NONE_KEPT


@compiled(**JIT)
def limits_kept(
    buffer: float, vec: np.ndarray, step: np.ndarray, lower: np.ndarray, upper: np.ndarray, scale: float
) -> bool:
    """Whether the candidate ``phi`` + ``scale`` ``step`` (n,; into ``vec``'s :data:`CAND` row) is
    finite and keeps each joint inside its limits, no nearer to one than ``buffer`` (or than it
    was)."""
    safe = True
    for j in range(step.shape[0]):
        phi = vec[PHI, j]
        cand = vec[CAND, j] = phi + scale * step[j]
        if not (cand - cand == 0.0):  # NaN or infinity
            safe = False
        gap = min(cand - lower[j], upper[j] - cand)
        gap_now = min(phi - lower[j], upper[j] - phi)
        if gap <= 0.0 or gap < min(buffer, gap_now):
            safe = False
    return safe


@compiled(**JIT)
def bounds_certain(
    floats: np.ndarray, gap_rows: np.ndarray, levers: np.ndarray, step: np.ndarray, scale: float
) -> bool:
    """Whether the gaps' bounds show every pair no nearer than ``self_clearance`` after ``scale``
    ``step`` (n,), the lever arms ``levers`` (P, n) bounding each gap's change; the candidate's
    bounds into ``gap_rows``' :data:`CAND_BOUND` row."""
    certain = True
    for q in range(gap_rows.shape[1]):
        travel = lever_travel(levers, q, step, scale) * (1.0 + 1e-9)
        gap_rows[CAND_BOUND, q] = gap_rows[BOUND, q] - travel - floats[SLACK]
        certain = certain and gap_rows[CAND_BOUND, q] >= floats[SELF_CLEARANCE]
    return certain


@compiled(**JIT)
def exact_kept(floats: np.ndarray, nums: np.ndarray, ints: np.ndarray, gap_rows: np.ndarray) -> int:
    """Whether every pair stays no nearer than ``self_clearance`` (or than it was) at the candidate,
    by the exact gaps of both poses.

    Parameters
    ----------
    floats : (FLOATS,) array
        The settings: ``self_clearance``, ``slack`` (metres).
    nums : (NUMBERS,) array
        The attempt's floats: both slots' least gaps (:data:`LEAST`, metres).
    ints : (COUNTS,) array
        The attempt's ints: the slot now (:data:`NOW`; the candidate's is the other), the other's
        mark (:data:`EXACT`) cleared where not kept.
    gap_rows : (GAP_ROWS, P) array
        The gaps' rows: the candidate's gaps read, its bounds into :data:`CAND_BOUND` (metres).

    Returns
    -------
    int
        1 where every pair keeps its clearance, 0 where not, -1 where a gap is too near its floor
        to tell as numpy would.
    """
    now = ints[NOW]
    other = 1 - now
    slack = floats[SLACK]
    floor = min(floats[SELF_CLEARANCE], nums[LEAST + now])
    least = nums[LEAST + other]
    if not (least >= floor + slack or least < floor - slack):
        return -1
    for q in range(gap_rows.shape[1]):
        gap_rows[CAND_BOUND, q] = gap_rows[GAPS + other, q] - slack
    if least >= floor:
        return 1
    ints[EXACT + other] = 0  # the next halving's candidate is another pose
    return 0


@compiled(**JIT)
def halving_status(kept: int, scale: float, step: np.ndarray, ints: np.ndarray) -> int:
    """What the attempt does with the halvings' answer ``kept`` (:func:`first_kept`, :func:`exact_kept`)
    at ``scale``: :data:`GO` on, ``scale`` ``step`` (n,) taken; else it ends, :data:`HANDED_BACK`
    (a gap too near its floor to tell as numpy would: no step counted) or :data:`DONE` (no scale
    kept the guarantees, or ``scale`` ``step`` moves nothing: the same pose would propose the same
    again). A step counted in ``ints``' :data:`STEPS` but where handed back."""
    if kept < 0:
        return HANDED_BACK
    ints[STEPS] += 1
    if kept == NONE_KEPT:
        return DONE
    length = 0.0
    for j in range(step.shape[0]):
        length += (scale * step[j]) ** 2
    return GO if length != 0.0 else DONE


@compiled(**JIT)
def taken(vec: np.ndarray, ints: np.ndarray, gap_rows: np.ndarray, lower: np.ndarray) -> None:
    """The candidate taken (its kinematics in the other slot than the pose now's, which it becomes):
    the gaps' bounds the candidate's, the old slot's gaps no longer computed, ``vec``'s :data:`PHI`
    the candidate with each unlimited joint (``lower`` -inf) wrapped into [-pi, pi) where any joint
    passed pi, :data:`POSE_PHI` the candidate as its pose was computed."""
    for q in range(gap_rows.shape[1]):
        gap_rows[BOUND, q] = gap_rows[CAND_BOUND, q]
    ints[EXACT + ints[NOW]] = 0
    ints[NOW] = 1 - ints[NOW]
    wrap = False
    for j in range(vec.shape[1]):
        wrap = wrap or abs(vec[CAND, j]) > np.pi
    for j in range(vec.shape[1]):
        cand = vec[CAND, j]
        vec[PHI, j] = vec[POSE_PHI, j] = cand
        if wrap and not lower[j] > -np.inf:
            wrapped = (cand + np.pi) % (2.0 * np.pi) - np.pi
            vec[PHI, j] = np.pi if wrapped == -np.pi else wrapped


@compiled(**JIT)
def stalled(floats: np.ndarray, nums: np.ndarray, ints: np.ndarray) -> bool:
    """The attempt's stall test after a step: the best progress and the steps since it
    (:data:`BEST`, :data:`SINCE_BEST`) updated with the progress now; True where no progress of
    0.1 ``tol`` (metres) came in ``ints``' :data:`STALL` steps."""
    if nums[PROGRESS] < nums[BEST] - 0.1 * floats[TOL]:
        nums[BEST] = nums[PROGRESS]
        ints[SINCE_BEST] = 0
        return False
    ints[SINCE_BEST] += 1
    window_out: bool = ints[SINCE_BEST] >= ints[STALL]
    return window_out


@compiled(**INLINE)
def ended(
    vec: np.ndarray, points: np.ndarray, errors: np.ndarray, nums: np.ndarray, ints: np.ndarray, out: np.ndarray
) -> None:
    """Where the attempt ended into ``out`` (2 n + 9,): ``vec``'s :data:`PHI` (n), the tip (the last
    of ``points`` (n + 1, 3)), the distance and angle (``errors``), the progress and the best, the
    steps and the steps since the best, :data:`POSE_PHI` (n)."""
    n = vec.shape[1]
    for j in range(n):
        out[j] = vec[PHI, j]
        out[n + 9 + j] = vec[POSE_PHI, j]
    for a in range(3):
        out[n + a] = points[n, a]
    out[n + 3] = errors[0]
    out[n + 4] = errors[1]
    out[n + 5] = nums[PROGRESS]
    out[n + 6] = nums[BEST]
    out[n + 7] = ints[STEPS]
    out[n + 8] = ints[SINCE_BEST]


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
