"""One frame of the frame loop with ``pinv`` or ``dls``, compiled (numba): the method's proposal
and the safety filter's answer, in one or two calls.

A frame of :func:`armanim.motion.trajectory.solve_trajectory` is the method's proposal
(:func:`armanim.motion.solvers.linear.linear_step`) through the filter
(:func:`armanim.motion.filter.barrier.safe_step`): in numpy and Python some 500 calls and a few
hundred microseconds. Here the same frame is written as loops over small arrays, with the
kinematics of :mod:`armanim.arm.kernel`, the distances of :mod:`armanim.world.compiled` and the
pieces of :mod:`armanim.motion.kernels` (the inverses of its ``linalg``, the tasks and pushes of
its ``tasks``, the exact checks of its ``check``):

- the proposal: the tip's task, the goal's orientation second in priority (in the tip task's
  null space, as :func:`~armanim.motion.solvers.linear.orientation_in_null_space`), the
  joint-limit push, the obstacles' pushes (the tip's in task space, the links' in the null
  space), the pushes of the arm's own pairs (in the null space), from the clearances and gaps of
  the state the frame starts from;
- the filter: the step capped to ``max_joint_step`` (a prismatic joint's to ``max_slide_step``), the joint bounds, the bounds of
  :func:`~armanim.motion.filter.barrier.clearly_allowed`, else the rows of
  :func:`~armanim.motion.filter.barrier.filter_constraints`, built in its order; where one is
  broken, the QP is DAQP's as before (:func:`~armanim.motion.filter.barrier.filtered_step`,
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
from typing import Literal

import numpy as np

from armanim.arm.kernel import INLINE, JIT, TURN, _capsule_ends_one, compiled
from armanim.arm.kinematics import Pose, kind_axes
from armanim.motion.filter.barrier import (
    BOUND_SLACK,
    VIOLATION,
    Constraints,
    SafeStep,
    blocker,
    filtered_step,
    step_fraction,
    wrap_unlimited,
)
from armanim.motion.kernels.check import pose_exactly_safe
from armanim.motion.kernels.layout import (
    BUFFER,
    DLS,
    GAMMA,
    KEPT,
    KEPT_SELF,
    LEVER_NORM,
    PINV,
    Fields,
    FrameGoal,
    FrameWork,
    KernelProblem,
    Measures,
    Near,
    Pairs,
    Placed,
    PoseState,
)
from armanim.motion.kernels.tasks import frame_proposal, point_jacobian, step_bounds, step_shrink
from armanim.motion.orientation import Orientation
from armanim.motion.problem import Problem
from armanim.motion.solvers.common import ArmState
from armanim.world.compiled import pair_row, pair_rows_met
from armanim.world.distances import Clearances
from armanim.world.selfdistances import SelfGaps

TAKEN, NOMINAL, QP, FILTER, NUMPY = 0, 1, 2, 3, 4
"""How a compiled frame ended (:func:`frame_loop`): the step taken (the new state is in the outputs);
the filter takes the proposal as it is, its exact check still to do; the filter's QP to solve;
the proposal made but the numpy filter needed; nothing done (the numpy proposal and filter)."""


@compiled(**JIT)
def frame_loop(
    problem: Fields, method: int, now: PoseState, goal: FrameGoal, work: FrameWork, new: Measures, out: np.ndarray
) -> int:
    """One frame from the state ``now``: the proposal, the filter's nominal step and bounds, its
    rows where a bound or a row may break, the exact check of the step as it is.

    Parameters
    ----------
    problem : tuple
        The fields of the problem's :class:`~armanim.motion.kernels.layout.KernelProblem`, in order
        (plain tuples cost numba's dispatch less than named ones).
    method : int
        :data:`~armanim.motion.kernels.layout.PINV` or :data:`~armanim.motion.kernels.layout.DLS`.
    now, goal, work, new : tuples
        A :data:`~armanim.motion.kernels.layout.PoseState`, a
        :data:`~armanim.motion.kernels.layout.FrameGoal`, a
        :data:`~armanim.motion.kernels.layout.FrameWork` (the proposal into ``dphi``, the step
        capped to the joints' caps, the filter's nominal step, into ``step``, the joint bounds into
        ``lo``, ``hi``) and a :data:`~armanim.motion.kernels.layout.Measures` (the new state).
    out : (3,) array
        The step's length (radians or metres), the new least gap (metres), the count of the rows.

    Returns
    -------
    int
        :data:`NUMPY`: an inverse failed; :data:`FILTER`: the proposal is not finite, or zero;
        :data:`QP`: a row or a bound is broken: the filter's rows (as
        :func:`~armanim.motion.filter.barrier.filter_constraints` builds them, in its order) in
        ``cons`` and ``cons_lower``, their count in ``out[2]``; :data:`NOMINAL`: the filter takes
        the step as it is, but its exact check failed (the halvings are left to :func:`settle`);
        :data:`TAKEN`: the step is taken: the new pose ``cand`` (before wrapping) and its state in
        ``new``, the step's length in ``out[0]``, the new least gap in ``out[1]``.
    """
    k = KernelProblem(*problem)
    rows, lower, upper, caps_step, floats, caps, link = k.rows, k.lower, k.upper, k.step_caps, k.floats, k.caps, k.link
    levers, influence, lever_rows, pair_levers = k.levers, k.influence, k.pair_lever_rows, k.pair_levers
    phi, points, frames, axes, d, t, normal, gap, gap_t, gap_s, gap_normal, least = now  # PoseState's order
    dphi, step, lo, hi, cons, cons_lower, cand = work  # FrameWork's order
    a, b = capsule_ends(caps, link, points, frames)
    placed, near, pairs = (points, axes, a, b, link), (d, t, normal), (k.first, k.second, gap, gap_t, gap_s, gap_normal)
    tool = tool_frame(rows, frames)
    if not frame_proposal(floats, method, phi, (lower, upper), placed, near, influence, pairs, least, goal, tool, dphi):
        return NUMPY
    if not moves(dphi):
        return FILTER
    inside, travel, length = nominal_step(floats, lower, upper, caps_step, levers, phi, dphi, step, lo, hi)
    out[0] = length
    if not clearly_allowed(floats, placed, pairs, lever_rows, step, inside, travel, d):
        count, broken = obstacle_rows(floats, placed, near, step, length, cons, cons_lower)
        count, broken_pair = self_rows(floats, placed, pairs, pair_levers, step, length, cons, cons_lower, count)
        if broken or broken_pair or not inside:
            out[2] = count
            return QP
    for j in range(phi.shape[0]):
        cand[j] = phi[j] + step[j]
    if not pose_exactly_safe(k, phi, cand, d, least, new, out):
        return NOMINAL
    return TAKEN


@compiled(**INLINE)
def capsule_ends(
    caps: np.ndarray, link: np.ndarray, points: np.ndarray, frames: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The capsules' world ends (c, 3) each, metres, of the pose whose joints' points and frames
    are ``points`` (n + 1, 3) and ``frames`` (n, 3, 3) (:func:`~armanim.arm.kernel._capsule_ends_one`);
    ``caps`` (c, 8), ``link`` (c,): the capsules as :class:`~armanim.motion.kernels.layout.KernelProblem` holds them."""
    c = caps.shape[0]
    a = np.empty((c, 3))
    b = np.empty((c, 3))
    _capsule_ends_one(points, frames, link, caps[:, 0:3], caps[:, 3:6], caps[:, 7] > 0.5, a, b)
    return a, b


@compiled(**INLINE)
def tool_frame(rows: np.ndarray, frames: np.ndarray) -> np.ndarray:
    """The tool frame (3, 3) of the pose whose joints' frames are ``frames`` (n, 3, 3): the last
    joint's frame times its fixed turn (the chain's ``rows`` (n, 34)), as the kinematics kernel
    makes it."""
    tool = np.empty((3, 3))
    last = frames.shape[0] - 1
    for r in range(3):
        f0, f1, f2 = frames[last, r, 0], frames[last, r, 1], frames[last, r, 2]
        for col in range(3):
            tool[r, col] = (
                f0 * rows[last, TURN + col] + f1 * rows[last, TURN + 3 + col] + f2 * rows[last, TURN + 6 + col]
            )
    return tool


@compiled(**INLINE)
def moves(dphi: np.ndarray) -> bool:
    """Whether the proposal ``dphi`` (n,) is finite and not zero (a NaN anywhere: False)."""
    biggest = 0.0
    for j in range(dphi.shape[0]):
        v = abs(dphi[j])
        if not v <= biggest:  # a NaN sticks
            biggest = v
    return biggest < np.inf and biggest != 0.0


@compiled(**INLINE)
def nominal_step(
    floats: np.ndarray,
    lower: np.ndarray,
    upper: np.ndarray,
    caps: np.ndarray,
    levers: np.ndarray,
    phi: np.ndarray,
    dphi: np.ndarray,
    step: np.ndarray,
    lo: np.ndarray,
    hi: np.ndarray,
) -> tuple[bool, float, float]:
    """The filter's nominal step from the pose ``phi``: the proposal ``dphi`` capped to the
    joints' caps ``caps`` into ``step``, the joint bounds (from the limits ``lower``, ``upper``)
    into ``lo``, ``hi``; all (n,), radians (metres for a prismatic joint).

    Returns
    -------
    inside : bool
        Whether the step keeps its bounds (to :data:`~armanim.motion.filter.barrier.VIOLATION`).
    travel : float
        sum_j |step_j| ``levers``_j, metres: the most a point of the arm moves, to first order.
    length : float
        |step|.
    """
    gamma = floats[GAMMA]
    buffer = floats[BUFFER]
    shrink = step_shrink(caps, dphi)
    travel = 0.0
    length = 0.0
    inside = True
    for j in range(phi.shape[0]):
        step[j] = dphi[j] * shrink
        length += step[j] * step[j]
        lo[j], hi[j] = step_bounds(phi[j], lower[j], upper[j], caps[j], gamma, buffer)
        if step[j] < lo[j] - VIOLATION or step[j] > hi[j] + VIOLATION:
            inside = False
        travel += abs(step[j]) * levers[j]
    return inside, travel, math.sqrt(length)


@compiled(**INLINE)
def clearly_allowed(
    floats: np.ndarray,
    placed: Placed,
    pairs: Pairs,
    lever_rows: np.ndarray,
    step: np.ndarray,
    inside: bool,
    travel: float,
    d: np.ndarray,
) -> bool:
    """:func:`~armanim.motion.filter.barrier.clearly_allowed`: whether the step ``step`` (n,) keeps
    its bounds (``inside``) and meets every row of the filter by the bound ``travel`` (metres)
    alone (the links' clearances ``d`` (parts, m), metres), or the pairs' rows where computed
    (:func:`~armanim.world.compiled.pair_rows_met`; ``lever_rows`` (P, n): each pair's lever arms)."""
    gamma = floats[GAMMA]
    slack = 1.0 + BOUND_SLACK
    clear = inside
    if clear and d.shape[1] > 0:
        lowest = np.inf
        for part in range(d.shape[0] - 1):
            for col in range(d.shape[1]):
                lowest = min(lowest, d[part, col])
        clear = gamma * (lowest - floats[KEPT]) >= travel * slack + 1e-12
    if clear and lever_rows.shape[0]:
        bounds = (floats[KEPT_SELF], gamma, slack, BOUND_SLACK * travel + 1e-12, VIOLATION)
        clear = pair_rows_met(placed, pairs, lever_rows, step, bounds)
    return clear


@compiled(**INLINE)
def obstacle_rows(
    floats: np.ndarray,
    placed: Placed,
    near: Near,
    step: np.ndarray,
    length: float,
    cons: np.ndarray,
    cons_lower: np.ndarray,
) -> tuple[int, bool]:
    """The obstacles' rows of :func:`~armanim.motion.filter.barrier.filter_constraints`, in its
    order, into ``cons`` (rows, n) and ``cons_lower`` (rows,): n . J_q dphi >= -gamma (d - kept)
    for each part off the base and obstacle whose clearance d (metres) is within the reach of the
    step ``step`` (n,) (its ``length`` times the levers' norm, twice). Returns their count and
    whether ``step`` breaks one."""
    points, axes, a, b, link = placed
    d, t, normal = near
    n = step.shape[0]
    gamma = floats[GAMMA]
    target = floats[KEPT]
    reach = 2.0 * (length * floats[LEVER_NORM]) + 1e-9
    q = np.empty(3)
    jac = np.empty((3, n))
    count = 0
    broken = False
    for part in range(d.shape[0] - 1):
        if link[part] < 0:  # on the base: no row (it never moves)
            continue
        for col in range(d.shape[1]):
            if not d[part, col] - target < reach:
                continue
            f = t[part, col]
            for i in range(3):
                q[i] = a[part, i] + f * (b[part, i] - a[part, i])
            point_jacobian(points, axes, link[part], q, jac)
            for j in range(n):
                cons[count, j] = (
                    normal[part, col, 0] * jac[0, j]
                    + normal[part, col, 1] * jac[1, j]
                    + normal[part, col, 2] * jac[2, j]
                )
            broken = row_broken(cons, cons_lower, count, step, -gamma * (d[part, col] - target)) or broken
            count += 1
    return count, broken


@compiled(**INLINE)
def self_rows(
    floats: np.ndarray,
    placed: Placed,
    pairs: Pairs,
    levers: np.ndarray,
    step: np.ndarray,
    length: float,
    cons: np.ndarray,
    cons_lower: np.ndarray,
    count: int,
) -> tuple[int, bool]:
    """The pairs' rows of :func:`~armanim.motion.filter.barrier.filter_constraints`, after the
    obstacles' ``count``, into ``cons`` (rows, n) and ``cons_lower`` (rows,):
    n . (J_A - J_B) dphi >= -gamma (gap - kept) for each pair whose gap (metres) is within the
    reach of the step ``step`` (n,) (its ``length`` times the pair's levers' norm ``levers`` (P,),
    twice). Returns the count of all rows and whether ``step`` breaks one of the pairs'."""
    points, axes, a, b, link = placed
    first, second, gap, t, s, normal = pairs
    gamma = floats[GAMMA]
    kept = floats[KEPT_SELF]
    broken = False
    for p in range(gap.shape[0]):
        if not gap[p] - kept < 2.0 * length * levers[p] + 1e-9:
            continue
        pair_row(points, axes, a, b, link, first, second, t, s, normal, p, cons[count])
        broken = row_broken(cons, cons_lower, count, step, -gamma * (gap[p] - kept)) or broken
        count += 1
    return count, broken


@compiled(**INLINE)
def row_broken(cons: np.ndarray, cons_lower: np.ndarray, count: int, step: np.ndarray, lower: float) -> bool:
    """The bound ``lower`` of the filter's row ``count`` (its coefficients already in ``cons``
    (rows, n)) into ``cons_lower`` (rows,); whether ``step`` (n,) breaks the row,
    ``cons[count] . step < lower`` by more than :data:`~armanim.motion.filter.barrier.VIOLATION`."""
    cons_lower[count] = lower
    change = 0.0
    for j in range(step.shape[0]):
        change += cons[count, j] * step[j]
    return change < lower - VIOLATION


@compiled(**JIT)
def settle(
    problem: Fields, halvings: int, now: PoseState, step: np.ndarray, cand: np.ndarray, new: Measures, out: np.ndarray
) -> float:
    """The filter's exact check and halvings of ``step`` from the state ``now``: the first of
    ``phi + 0.5^i step``, i = 0 .. ``halvings``, that keeps every guarantee.

    Parameters
    ----------
    problem, now, new : tuples
        As :func:`frame_loop`'s.
    halvings : int
        The most halvings.
    step : (n,) array
        The filter's step, radians (metres for a prismatic joint).
    cand : (n,) array
        Filled with the pose taken (before wrapping).
    out : (3,) array
        The length of the step taken into ``out[0]``, the new least gap into ``out[1]``.

    Returns
    -------
    float
        The scale 0.5^i of the step taken, or -1 where none keeps the guarantees.
    """
    k = KernelProblem(*problem)
    phi, d, least = now[0], now[4], now[11]  # PoseState's
    scale = 1.0
    for _ in range(halvings + 1):
        length = 0.0
        for j in range(phi.shape[0]):
            cand[j] = phi[j] + scale * step[j]
            length += (scale * step[j]) ** 2
        if pose_exactly_safe(k, phi, cand, d, least, new, out):
            out[0] = math.sqrt(length)
            return scale
        scale *= 0.5
    return -1.0


# ----------------------------------------------------------------------------- from Python


_EMPTY_CL = (np.zeros((0, 0)), np.zeros((0, 0)), np.zeros((0, 0, 3)))
_NO_ROTATION = np.eye(3)
_NO_AXIS = np.array([0.0, 0.0, 1.0])
_EMPTY_GAPS = (np.zeros(0), np.zeros(0), np.zeros(0), np.zeros((0, 3)))


def frame_step(
    problem: Problem,
    method: Literal["pinv", "dls"],
    state: ArmState,
    goal: np.ndarray,
    orientation: Orientation | None = None,
) -> tuple[SafeStep | None, np.ndarray | None]:
    """One frame of ``method`` toward ``goal`` (a position, and its ``orientation``) from ``state``: (the
    filter's answer, the proposal), or (None, the proposal) where the numpy filter must take it (a
    proposal that is not finite or zero: :func:`~armanim.motion.filter.barrier.safe_step`), or
    (None, None) where the numpy path must make the proposal too (an inverse failed).

    The filter's QP, where a row is broken, is DAQP's (:func:`~armanim.motion.filter.barrier.filtered_step`)
    on the rows the kernel built; the exact check and the halvings are compiled (:func:`settle`)."""
    k = problem.kernel
    kp = tuple(k)  # a plain tuple: numba's dispatch types it faster than the named one
    now = _pose_state(problem, state)
    cl_d = now[4]
    n, pairs = problem.arm.n, len(k.first)
    dphi, step, lo, hi, cand = np.empty(n), np.empty(n), np.empty(n), np.empty(n), np.empty(n)
    cons, cons_lower = np.empty((cl_d.size + pairs, n)), np.empty(cl_d.size + pairs)
    new = _new_state_arrays(n, cl_d.shape, pairs)
    out = np.empty(3)
    work = (dphi, step, lo, hi, cons, cons_lower, cand)
    status = frame_loop(
        kp, DLS if method == "dls" else PINV, now, _frame_goal(problem, goal, orientation), work, new, out
    )
    if status == NUMPY:
        return None, None
    if status == FILTER:
        return None, dphi
    proposed = float(np.sqrt(dphi @ dphi))
    if status == TAKEN:
        return SafeStep(
            _state(problem, cand, new, out, state.clearance is not None),
            _fraction(float(out[0]), proposed, step, dphi),
            None,
        ), dphi
    nominal = step
    constraints = None
    if status == QP:
        count = int(out[2])
        constraints = Constraints(cons[:count], cons_lower[:count], lo, hi)
        step = filtered_step(nominal, constraints)
    scale = settle(kp, problem.tunables.filter.halvings, now, step, cand, new, out)
    if scale < 0.0:  # no halving kept the guarantees: the arm stays
        return SafeStep(state, 0.0, blocker(nominal, constraints)), dphi
    blocked = None if step is nominal and scale == 1.0 else blocker(nominal, constraints)
    return SafeStep(
        _state(problem, cand, new, out, state.clearance is not None),
        _fraction(float(out[0]), proposed, scale * step, dphi),
        blocked,
    ), dphi


def _pose_state(problem: Problem, state: ArmState) -> PoseState:
    """The fields of ``state``'s :data:`~armanim.motion.kernels.layout.PoseState`, in order, as a
    plain tuple (empty clearances and gaps where the state has none)."""
    cl, gaps, pose = state.clearance, state.self_gaps, state.pose
    assert pose.axes is not None  # the frame loop's poses come from the compiled kinematics
    cl_d, cl_t, cl_normal = _EMPTY_CL if cl is None else (cl.d, cl.t, cl.normal)
    gap, gap_t, gap_s, gap_normal = _EMPTY_GAPS if gaps is None else (gaps.d, gaps.t, gaps.s, gaps.normal)
    least = np.inf if gaps is None else float(gaps.least)
    axes = kind_axes(problem.arm, pose.axes)
    return (state.phi, pose.points, pose.frames, axes, cl_d, cl_t, cl_normal, gap, gap_t, gap_s, gap_normal, least)


def _frame_goal(problem: Problem, goal: np.ndarray, orientation: Orientation | None) -> FrameGoal:
    """The fields of the :data:`~armanim.motion.kernels.layout.FrameGoal` toward ``goal`` (3,),
    metres, and ``orientation``, in order: in a scene without orientations anywhere, the rotation
    and the axis None (the kernels compiled without the rotation task); else both arrays (one
    machine code a scene), the kind's own and a placeholder."""
    kind = 0 if orientation is None else (1 if orientation.rotation is not None else 2)
    goal_rot: np.ndarray | None = None
    goal_axis: np.ndarray | None = None
    if orientation is not None or any(g.orientation is not None for g in problem.goals):
        goal_rot = np.ascontiguousarray(orientation.rotation if kind == 1 else _NO_ROTATION, dtype=float)  # type: ignore[union-attr]  # kind 1: a rotation
        goal_axis = np.ascontiguousarray(orientation.axis if kind == 2 else _NO_AXIS, dtype=float)  # type: ignore[union-attr]  # kind 2: a tool axis
    return (np.ascontiguousarray(goal, dtype=float), kind, goal_rot, goal_axis)


def _fraction(length: float, proposed: float, taken: np.ndarray, dphi: np.ndarray) -> float:
    """|taken| / |dphi| from the lengths the kernel found, or :func:`~armanim.motion.filter.barrier.step_fraction`'s
    where the proposal's squares underflow or overflow."""
    return length / proposed if 0.0 < proposed < np.inf else step_fraction(taken, dphi)


def _new_state_arrays(n: int, clearances: tuple[int, ...], pairs: int) -> Measures:
    """The kernel's arrays of a new state (:data:`~armanim.motion.kernels.layout.Measures`), for
    ``n`` joints, ``clearances`` (parts, m) and ``pairs`` pairs."""
    parts, m = clearances
    return (
        np.empty((n + 1, 3)),
        np.empty((n, 3, 3)),
        np.empty((n, 3)),
        np.empty((3, 3)),
        np.empty((parts, m)),
        np.empty((parts, m)),
        np.empty((parts, m, 3)),
        np.empty(pairs),
        np.empty(pairs),
        np.empty(pairs),
        np.empty((pairs, 3)),
    )


def _state(problem: Problem, cand: np.ndarray, new: Measures, out: np.ndarray, obstacles: bool) -> ArmState:
    """The new state the kernel measured at ``cand`` (unlimited joints wrapped, as the filter's states)."""
    points, frames, axes, _, d, t, normal, gap, gap_t, gap_s, gap_normal = new
    gaps = None
    if len(gap):
        gaps = SelfGaps(gap, gap_t, gap_s, gap_normal)
        object.__setattr__(
            gaps, "_least", np.float64(out[1])
        )  # the kernel found it: SelfGaps.least need not look again
    return ArmState(
        wrap_unlimited(problem, cand),
        Pose(points=points, frames=frames, axes=axes),
        Clearances(d=d, t=t, normal=normal) if obstacles else None,
        gaps,
    )
