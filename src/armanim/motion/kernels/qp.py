"""The safety filter's QP, compiled: the step closest to the nominal that meets the joints' bounds
and the rows of the arm's own pairs near enough for it, solved exactly by a dual active-set
method (:func:`closest_step`), with the rows built only where the answer breaks them
(:func:`filtered_with_pairs`); and the lever-arm bounds that show a pair's row met without
building it (:func:`pairs_far`).

The numpy reference: :func:`armanim.motion.filter.barrier.filtered_step` (DAQP). Pure core:
numpy and numba only, radians.
"""

from __future__ import annotations

import numpy as np

from armanim.arm.kernel import INLINE, JIT, compiled
from armanim.motion.filter.barrier import VIOLATION
from armanim.motion.kernels.layout import GAMMA, KEPT_SELF, SLACK
from armanim.motion.kernels.linalg import cholesky
from armanim.world.compiled import link_twists, pair_rate, pair_row

QP_ITERATIONS = 100
"""Most iterations of :func:`closest_step` (each adds or drops one constraint; a 7-joint step
takes a few)."""

QP_FEASIBLE = 1e-13
"""A constraint of the filter's QP counts as met by :func:`closest_step`'s answer when it is broken
by no more than this (rounding; the filter's own test allows ``VIOLATION``)."""


@compiled(**JIT)
def gram_solve(
    cmat: np.ndarray, active: np.ndarray, w: int, rhs: np.ndarray, out: np.ndarray, gram: np.ndarray
) -> bool:
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
    if not cholesky(gram, w, 1e-24):
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


@compiled(**JIT)
def closest_step(
    nominal: np.ndarray, cmat: np.ndarray, cb: np.ndarray, count: int, x: np.ndarray, bounds: int = 0
) -> int:
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
    negative, one of each sign a joint (:func:`bound_rows`). The method then starts from the clip
    of ``nominal`` with the bounds it breaks active (their multipliers the clip's distances, >= 0:
    the least point of those equalities, so a start the method allows), where it would have added
    them one by one: the same answer (the QP's only one) in fewer iterations.

    The stages are inlined (:func:`clip_start`, :func:`most_broken`, :func:`meet_constraint`,
    :func:`projected_answer`): a call in the iteration would count the references of its arrays."""
    n = nominal.shape[0]
    active = np.empty(n, dtype=np.int64)
    u = np.empty(n)
    in_set = np.zeros(count, dtype=np.bool_)
    r = np.empty(n)
    z = np.empty(n)
    rhs = np.empty(n)
    gram = np.empty((n, n))
    w = clip_start(nominal, cmat, cb, bounds, x, active, u, in_set)
    for _ in range(QP_ITERATIONS):
        p = most_broken(cmat, cb, count, in_set, x)
        if p < 0:
            return projected_answer(nominal, cmat, cb, count, x, active, u, w, rhs, gram)
        w = meet_constraint(cmat, cb, p, x, active, u, in_set, w, r, z, rhs, gram)
        if w < 0:
            return w + 1  # -1: no x meets the constraints (0); -2: dependent rows or no progress (-1)
    return -1


@compiled(**INLINE)
def clip_start(
    nominal: np.ndarray,
    cmat: np.ndarray,
    cb: np.ndarray,
    bounds: int,
    x: np.ndarray,
    active: np.ndarray,
    u: np.ndarray,
    in_set: np.ndarray,
) -> int:
    """:func:`closest_step`'s start: ``x`` (n,) the clip of ``nominal`` to the first ``bounds`` rows
    (unit rows: :func:`bound_rows`), the rows it breaks active (``active``, ``in_set``) with their
    multipliers ``u`` the clip's distances. Returns how many are active."""
    n = nominal.shape[0]
    for j in range(n):
        x[j] = nominal[j]
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
    return w


@compiled(**INLINE)
def most_broken(cmat: np.ndarray, cb: np.ndarray, count: int, in_set: np.ndarray, x: np.ndarray) -> int:
    """The inactive row of ``cmat[:count] x >= cb[:count]`` that ``x`` breaks most, by more than
    :data:`QP_FEASIBLE` (the first of equals); -1 where none is."""
    n = x.shape[0]
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
    return p


@compiled(**INLINE)
def meet_constraint(
    cmat: np.ndarray,
    cb: np.ndarray,
    p: int,
    x: np.ndarray,
    active: np.ndarray,
    u: np.ndarray,
    in_set: np.ndarray,
    w: int,
    r: np.ndarray,
    z: np.ndarray,
    rhs: np.ndarray,
    gram: np.ndarray,
) -> int:
    """One iteration of :func:`closest_step`: row ``p`` met by steps along ``z`` (its row less its
    part in the ``w`` active rows' span) that keep the active rows met, each active row whose
    multiplier in ``u`` reaches 0 on the way leaving, until ``p`` joins them. Returns how many rows
    are then active; -1 where no x meets the rows (the dual step unbounded), -2 where the active
    rows turned dependent to rounding, all n are active or the steps ran out. ``r``, ``z``, ``rhs``
    (n,) and the Gram matrix ``gram`` (n, n): work space."""
    n = x.shape[0]
    up = 0.0
    for _ in range(QP_ITERATIONS):
        for i in range(w):
            s = 0.0
            for j in range(n):
                s += cmat[active[i], j] * cmat[p, j]
            rhs[i] = s
        if w > 0 and not gram_solve(cmat, active, w, rhs, r, gram):
            return -2
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
            return -1
        t = min(full, partial)
        if full < np.inf:
            for j in range(n):
                x[j] += t * z[j]
        for i in range(w):
            u[i] -= t * r[i]
        up += t
        if t == full:
            if w == n:
                return -2
            active[w] = p
            u[w] = up
            in_set[p] = True
            return w + 1
        in_set[active[k]] = False  # the partial step: constraint k leaves
        active[k] = active[w - 1]
        u[k] = u[w - 1]
        w -= 1
    return -2


@compiled(**INLINE)
def projected_answer(
    nominal: np.ndarray,
    cmat: np.ndarray,
    cb: np.ndarray,
    count: int,
    x: np.ndarray,
    active: np.ndarray,
    u: np.ndarray,
    w: int,
    rhs: np.ndarray,
    gram: np.ndarray,
) -> int:
    """:func:`closest_step`'s answer: ``x`` the least-squares point of the ``w`` active rows from
    ``nominal``, x = nominal + C_W^T u (the KKT conditions to rounding), checked. Returns 1; -1
    where the active rows turned dependent, a multiplier is negative or a row is broken (by more
    than :data:`QP_FEASIBLE`). ``rhs`` (n,), ``gram`` (n, n): work space."""
    n = nominal.shape[0]
    for i in range(w):
        s = -cb[active[i]]
        for j in range(n):
            s += cmat[active[i], j] * nominal[j]
        rhs[i] = -s
    if w > 0 and not gram_solve(cmat, active, w, rhs, u, gram):
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


@compiled(**JIT)
def bound_rows(n: int, pairs: int) -> np.ndarray:
    """The filter QP's rows (2 n + P, n), its first 2 n the joints' bounds (I, then -I: x >= low,
    -x >= -high); the pairs' rows are written per step."""
    cmat = np.zeros((2 * n + pairs, n))
    for j in range(n):
        cmat[j, j] = 1.0
        cmat[n + j, j] = -1.0
    return cmat


@compiled(**JIT)
def filtered_with_pairs(
    floats: np.ndarray,
    pose: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray],
    pairs: tuple[np.ndarray, np.ndarray, np.ndarray],
    nominal: np.ndarray,
    nominal_length: float,
    bounds: tuple[np.ndarray, np.ndarray],
    work: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray],
    step: np.ndarray,
) -> bool:
    """With the pairs' exact ``gaps`` at the pose and ``step`` (n,) holding the nominal clipped to
    the joints' bounds ``low``, ``high``: the filter's step into ``step``, as
    :func:`armanim.motion.filter.barrier.filtered_step` takes it, the closest to ``nominal``
    meeting those bounds and the rows of the pairs near enough for the step
    (:func:`armanim.motion.filter.barrier.self_pair_rows`: n . (J_A - J_B) dPhi >= -gamma (d -
    d_kept)). ``nominal`` itself where it meets them all (to ``VIOLATION``), else the QP solved
    exactly (:func:`closest_step`), clipped to the bounds as the numpy filter clips DAQP's answer;
    where no step meets the rows, the QP again with each row's bound no more than 0 (closing no
    gap further), as the numpy filter relaxes it.

    A row that the QP's answer meets does not change the answer: so the QP is solved with the
    rows its answer breaks, from the clip (the answer with no row) on, each added as the answer
    breaks it, until the answer meets every row (the pairs' rates by the links' twists,
    :func:`armanim.world.compiled.pair_rate`, a few products a pair where a row costs n cross
    products: a pair's row is built only where it acts). False (hand back) where the QP fails.

    Parameters
    ----------
    floats : (FLOATS,) array
        The settings (:mod:`~armanim.motion.kernels.layout`).
    pose : tuple of arrays
        The pose: joint points (n + 1, 3), world axes (n, 3), each capsule's joint (c,), the
        capsules' ends (2, c, 3) (metres), the pairs' closest points (P, 5) (t, s, normal) and
        their exact gaps (P,) (metres) (:func:`armanim.motion.kernels.check.pair_gaps`).
    pairs : tuple of arrays
        The pairs' capsules ``first``, ``second`` (P,) and their lever arms' norms (P,).
    nominal : (n,) array
        The filter's nominal step, radians (metres for a prismatic joint); ``nominal_length`` its norm.
    bounds : tuple of two (n,) arrays
        The step's joint bounds ``low``, ``high``.
    work : tuple of arrays
        ``cmat`` (2 n + P, n), ``cb`` (2 n + P,): the QP's rows and bounds, its first 2 n rows
        the joints' (:func:`bound_rows`); ``twists`` (n, 6), ``in_rows`` (P,).
    step : (n,) array
        In: the nominal clipped to the bounds; out: the filter's step.
    """
    points, axes, caps_link, ends, near, gaps = pose
    first, second, pair_levers = pairs
    low, high = bounds
    cmat, cb, twists, in_rows = work
    n, gamma, kept = nominal.shape[0], floats[GAMMA], floats[KEPT_SELF]
    a, b, t, s, normal = ends[0], ends[1], near[:, 0], near[:, 1], near[:, 2:5]
    met = True
    for j in range(n):
        cb[j] = low[j]
        cb[n + j] = -high[j]
        if nominal[j] < low[j] - VIOLATION or nominal[j] > high[j] + VIOLATION:
            met = False
    # the rows the numpy filter builds: those of the pairs near enough for the step (its test); True: no row, or a row in the QP
    for q in range(gaps.shape[0]):
        in_rows[q] = not gaps[q] - kept < 2.0 * nominal_length * pair_levers[q] + 1e-9
    if met:
        link_twists(points, axes, nominal, twists)
        for q in range(gaps.shape[0]):
            if (
                not in_rows[q]
                and pair_rate(twists, a, b, caps_link, first, second, t, s, normal, q)
                < -gamma * (gaps[q] - kept) - VIOLATION
            ):
                met = False
                break
        if met:
            for j in range(n):
                step[j] = nominal[j]
            return True
    count = 2 * n
    relaxed = False
    for _ in range(gaps.shape[0] + 1):
        link_twists(points, axes, step, twists)
        added = False
        for q in range(gaps.shape[0]):
            if in_rows[q]:
                continue
            room = -gamma * (gaps[q] - kept)
            if relaxed:
                room = min(room, 0.0)
            if pair_rate(twists, a, b, caps_link, first, second, t, s, normal, q) < room:
                pair_row(points, axes, a, b, caps_link, first, second, t, s, normal, q, cmat[count])
                cb[count] = room
                in_rows[q] = True
                count += 1
                added = True
        if not added:
            break
        solved = closest_step(nominal, cmat, cb, count, step, 2 * n)
        if solved == 0 and not relaxed:  # no step meets these rows: as the numpy filter, closing no gap further
            relaxed = True
            solved = relaxed_step(nominal, cmat, cb, count, step, 2 * n)
        if solved == 0:
            for j in range(n):
                step[j] = 0.0
            return True
        if solved < 0:
            return False
    for j in range(n):
        step[j] = min(max(step[j], low[j]), high[j])
    return True


@compiled(**JIT)
def relaxed_step(
    nominal: np.ndarray, cmat: np.ndarray, cb: np.ndarray, count: int, step: np.ndarray, first: int
) -> int:
    """:func:`closest_step` again with the bounds ``cb`` of the rows ``first`` .. ``count`` no
    more than 0, closing no gap further (:func:`filtered_with_pairs`' relaxed QP, as the numpy
    filter relaxes it); ``cmat`` (rows, n) the QP's rows, ``step`` (n,) its answer."""
    for c in range(first, count):
        cb[c] = min(cb[c], 0.0)
    return closest_step(nominal, cmat, cb, count, step, first)


@compiled(**INLINE)
def lever_travel(levers: np.ndarray, q: int, step: np.ndarray, scale: float) -> float:
    """The most pair q's gap changes under the joint change ``scale * step``: its lever arms . |scale step|."""
    travel = 0.0
    for j in range(step.shape[0]):
        travel += levers[q, j] * abs(scale * step[j])
    return travel


@compiled(**JIT)
def pairs_far(floats: np.ndarray, bound: np.ndarray, levers: np.ndarray, step: np.ndarray) -> bool:
    """Whether every pair's gap bound shows its row of the filter met by ``step`` whatever the row
    (gamma (d - d_target) >= the pair's lever arms . |step|)."""
    slack = floats[SLACK]
    for q in range(bound.shape[0]):
        if (
            not floats[GAMMA] * (bound[q] - floats[KEPT_SELF])
            >= lever_travel(levers, q, step, 1.0) * (1.0 + 1e-9) + slack
        ):
            return False
    return True
