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

from armanim.arm.kernel import JIT, TURN, _capsule_ends_one, compiled
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
from armanim.motion.kernels.layout import BUFFER, DLS, GAMMA, KEPT, KEPT_SELF, LEVER_NORM, PINV, World
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
    rows: np.ndarray,
    root: np.ndarray,
    floats: np.ndarray,
    method: int,
    phi: np.ndarray,
    points: np.ndarray,
    frames: np.ndarray,
    axes: np.ndarray,
    goal: np.ndarray,
    kind: int,
    goal_rot: np.ndarray | None,
    goal_axis: np.ndarray | None,
    lower: np.ndarray,
    upper: np.ndarray,
    caps_step: np.ndarray,
    caps: np.ndarray,
    link: np.ndarray,
    part_radius: np.ndarray,
    levers: np.ndarray,
    cl_d: np.ndarray,
    cl_t: np.ndarray,
    cl_normal: np.ndarray,
    world: World,
    influence: np.ndarray,
    first: np.ndarray,
    second: np.ndarray,
    pair_radii: np.ndarray,
    pair_lever_rows: np.ndarray,
    pair_levers: np.ndarray,
    gap: np.ndarray,
    gap_t: np.ndarray,
    gap_s: np.ndarray,
    gap_normal: np.ndarray,
    least: float,
    dphi: np.ndarray,
    step: np.ndarray,
    lo: np.ndarray,
    hi: np.ndarray,
    cons: np.ndarray,
    cons_lower: np.ndarray,
    cand: np.ndarray,
    new_points: np.ndarray,
    new_frames: np.ndarray,
    new_axes: np.ndarray,
    tool: np.ndarray,
    new_d: np.ndarray,
    new_t: np.ndarray,
    new_normal: np.ndarray,
    new_gap: np.ndarray,
    new_gap_t: np.ndarray,
    new_gap_s: np.ndarray,
    new_gap_normal: np.ndarray,
    out: np.ndarray,
) -> int:
    """One frame from the state (``phi``, its pose, clearances and gaps): the proposal into
    ``dphi``, the step capped to the joints' caps ``caps_step`` (the filter's nominal step) into ``step`` and
    the joint bounds into ``lo``, ``hi``. Returns

    - :data:`NUMPY`: an inverse failed; :data:`FILTER`: the proposal is not finite, or zero;
    - :data:`QP`: a row or a bound is broken: the filter's rows (as
      :func:`~armanim.motion.filter.barrier.filter_constraints` builds them, in its order) into
      ``cons`` and ``cons_lower``, their count into ``out[2]``;
    - :data:`NOMINAL`: the filter takes the step as it is, but its exact check failed: the
      halvings are left to :func:`settle`;
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
            tool[r, col] = (
                f0 * rows[last, TURN + col] + f1 * rows[last, TURN + 3 + col] + f2 * rows[last, TURN + 6 + col]
            )
    if not frame_proposal(
        floats,
        method,
        phi,
        points,
        axes,
        goal,
        kind,
        goal_rot,
        goal_axis,
        tool,
        lower,
        upper,
        a,
        b,
        link,
        cl_d,
        cl_t,
        cl_normal,
        influence,
        first,
        second,
        gap,
        gap_t,
        gap_s,
        gap_normal,
        least,
        dphi,
    ):
        return NUMPY
    biggest = 0.0
    for j in range(n):
        v = abs(dphi[j])
        if not v <= biggest:  # a NaN sticks
            biggest = v
    if not biggest < np.inf or biggest == 0.0:
        return FILTER
    gamma = floats[GAMMA]
    buffer = floats[BUFFER]
    shrink = step_shrink(caps_step, dphi)
    travel = 0.0
    length = 0.0
    inside = True
    for j in range(n):
        step[j] = dphi[j] * shrink
        length += step[j] * step[j]
        lo[j], hi[j] = step_bounds(phi[j], lower[j], upper[j], caps_step[j], gamma, buffer)
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
        clear = pair_rows_met(
            points,
            axes,
            a,
            b,
            link,
            first,
            second,
            gap_t,
            gap_s,
            gap_normal,
            gap,
            floats[KEPT_SELF],
            gamma,
            pair_lever_rows,
            step,
            slack,
            BOUND_SLACK * travel + 1e-12,
            VIOLATION,
        )
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
                point_jacobian(points, axes, link[part], q, jac)
                change = 0.0
                for j in range(n):
                    cons[count, j] = (
                        cl_normal[part, k, 0] * jac[0, j]
                        + cl_normal[part, k, 1] * jac[1, j]
                        + cl_normal[part, k, 2] * jac[2, j]
                    )
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
    if not pose_exactly_safe(
        rows,
        root,
        floats,
        phi,
        cand,
        lower,
        upper,
        caps,
        link,
        part_radius,
        cl_d,
        world,
        first,
        second,
        pair_radii,
        least,
        new_points,
        new_frames,
        new_axes,
        tool,
        new_d,
        new_t,
        new_normal,
        new_gap,
        new_gap_t,
        new_gap_s,
        new_gap_normal,
        out,
    ):
        return NOMINAL
    return TAKEN


@compiled(**JIT)
def settle(
    rows: np.ndarray,
    root: np.ndarray,
    floats: np.ndarray,
    halvings: int,
    phi: np.ndarray,
    step: np.ndarray,
    lower: np.ndarray,
    upper: np.ndarray,
    caps: np.ndarray,
    link: np.ndarray,
    part_radius: np.ndarray,
    cl_d: np.ndarray,
    world: World,
    first: np.ndarray,
    second: np.ndarray,
    pair_radii: np.ndarray,
    least: float,
    cand: np.ndarray,
    new_points: np.ndarray,
    new_frames: np.ndarray,
    new_axes: np.ndarray,
    tool: np.ndarray,
    new_d: np.ndarray,
    new_t: np.ndarray,
    new_normal: np.ndarray,
    new_gap: np.ndarray,
    new_gap_t: np.ndarray,
    new_gap_s: np.ndarray,
    new_gap_normal: np.ndarray,
    out: np.ndarray,
) -> float:
    """The filter's exact check and halvings of ``step`` from ``phi``: the first of
    ``phi + 0.5^i step``, i = 0 .. ``halvings``, that keeps every guarantee, its state in the
    ``new_`` arrays as :func:`frame_loop`'s, the length of its step into ``out[0]``; returns its
    scale 0.5^i, or -1 where none does."""
    n = phi.shape[0]
    scale = 1.0
    for _ in range(halvings + 1):
        length = 0.0
        for j in range(n):
            cand[j] = phi[j] + scale * step[j]
            length += (scale * step[j]) ** 2
        if pose_exactly_safe(
            rows,
            root,
            floats,
            phi,
            cand,
            lower,
            upper,
            caps,
            link,
            part_radius,
            cl_d,
            world,
            first,
            second,
            pair_radii,
            least,
            new_points,
            new_frames,
            new_axes,
            tool,
            new_d,
            new_t,
            new_normal,
            new_gap,
            new_gap_t,
            new_gap_s,
            new_gap_normal,
            out,
        ):
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
    cl = state.clearance
    cl_d, cl_t, cl_normal = _EMPTY_CL if cl is None else (cl.d, cl.t, cl.normal)
    gaps = state.self_gaps
    gap, gap_t, gap_s, gap_normal = _EMPTY_GAPS if gaps is None else (gaps.d, gaps.t, gaps.s, gaps.normal)
    least = np.inf if gaps is None else float(gaps.least)
    pose = state.pose
    n = problem.arm.n
    dphi, step, lo, hi, cand = np.empty(n), np.empty(n), np.empty(n), np.empty(n), np.empty(n)
    pairs = len(k.first)
    cons, cons_lower = (
        np.empty((cl_d.shape[0] * cl_d.shape[1] + pairs, n)),
        np.empty(cl_d.shape[0] * cl_d.shape[1] + pairs),
    )
    new = _new_state_arrays(n, cl_d.shape, pairs)
    out = np.empty(3)
    assert pose.axes is not None  # the frame loop's poses come from the compiled kinematics
    kind = 0 if orientation is None else (1 if orientation.rotation is not None else 2)
    goal_rot: np.ndarray | None = None  # a scene without orientations: the kernels compiled without the rotation task
    goal_axis: np.ndarray | None = None
    if orientation is not None or any(g.orientation is not None for g in problem.goals):  # one machine code a scene
        goal_rot = np.ascontiguousarray(orientation.rotation if kind == 1 else _NO_ROTATION, dtype=float)  # type: ignore[union-attr]  # kind 1: a rotation
        goal_axis = np.ascontiguousarray(orientation.axis if kind == 2 else _NO_AXIS, dtype=float)  # type: ignore[union-attr]  # kind 2: a tool axis
    status = frame_loop(
        k.rows,
        k.root,
        k.floats,
        DLS if method == "dls" else PINV,
        state.phi,
        pose.points,
        pose.frames,
        kind_axes(problem.arm, pose.axes),
        np.ascontiguousarray(goal, dtype=float),
        kind,
        goal_rot,
        goal_axis,
        k.lower,
        k.upper,
        k.step_caps,
        k.caps,
        k.link,
        k.part_radius,
        k.levers,
        cl_d,
        cl_t,
        cl_normal,
        k.world,
        k.influence,
        k.first,
        k.second,
        k.pair_radii,
        k.pair_lever_rows,
        k.pair_levers,
        gap,
        gap_t,
        gap_s,
        gap_normal,
        least,
        dphi,
        step,
        lo,
        hi,
        cons,
        cons_lower,
        cand,
        *new,
        out,
    )
    if status == NUMPY:
        return None, None
    if status == FILTER:
        return None, dphi
    proposed = float(np.sqrt(dphi @ dphi))
    if status == TAKEN:
        return SafeStep(
            _state(problem, cand, new, out, cl is not None), _fraction(float(out[0]), proposed, step, dphi), None
        ), dphi
    nominal = step
    constraints = None
    if status == QP:
        count = int(out[2])
        constraints = Constraints(cons[:count], cons_lower[:count], lo, hi)
        step = filtered_step(nominal, constraints)
    scale = settle(
        k.rows,
        k.root,
        k.floats,
        problem.tunables.filter.halvings,
        state.phi,
        step,
        k.lower,
        k.upper,
        k.caps,
        k.link,
        k.part_radius,
        cl_d,
        k.world,
        k.first,
        k.second,
        k.pair_radii,
        least,
        cand,
        *new,
        out,
    )
    if scale < 0.0:  # no halving kept the guarantees: the arm stays
        return SafeStep(state, 0.0, blocker(nominal, constraints)), dphi
    blocked = None if step is nominal and scale == 1.0 else blocker(nominal, constraints)
    return SafeStep(
        _state(problem, cand, new, out, cl is not None), _fraction(float(out[0]), proposed, scale * step, dphi), blocked
    ), dphi


def _fraction(length: float, proposed: float, taken: np.ndarray, dphi: np.ndarray) -> float:
    """|taken| / |dphi| from the lengths the kernel found, or :func:`~armanim.motion.filter.barrier.step_fraction`'s
    where the proposal's squares underflow or overflow."""
    return length / proposed if 0.0 < proposed < np.inf else step_fraction(taken, dphi)


_NewState = tuple[
    np.ndarray,
    np.ndarray,
    np.ndarray,
    np.ndarray,
    np.ndarray,
    np.ndarray,
    np.ndarray,
    np.ndarray,
    np.ndarray,
    np.ndarray,
    np.ndarray,
]
"""A new state's arrays as the kernels fill them (:func:`_new_state_arrays`)."""


def _new_state_arrays(n: int, clearances: tuple[int, ...], pairs: int) -> _NewState:
    """The kernel's arrays of a new state: points, frames, axes, tool; clearances d, t, normal;
    the pairs' gaps, t, s, normal."""
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


def _state(problem: Problem, cand: np.ndarray, new: _NewState, out: np.ndarray, obstacles: bool) -> ArmState:
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
