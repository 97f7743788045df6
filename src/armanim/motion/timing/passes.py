"""The clock's two sequential passes over the path's grid, compiled (numba).

Each pass is a recursion from one grid point to the next over a few dozen bounds: in numpy it
cost some 30 us a point in call overhead alone, compiled it is a few dozen floating-point
operations. Imported by :func:`armanim.motion.timing.clock.time_optimal` when a clock is computed.
Pure core: numpy and numba only.
"""

from __future__ import annotations

import numpy as np

from armanim.world.compiled import compiled

_JIT = dict(error_model="numpy", nogil=True)  # inf + finite is inf, as the bounds expect


@compiled(**_JIT)
def backward_pass(x_cap: np.ndarray, w: np.ndarray, base: np.ndarray, hi: np.ndarray) -> None:
    """Fill ``hi`` (N,), whose last entry is the end's (0: at rest), with each grid point's
    largest controllable squared speed: hi[i] = max(0, min(x_cap[i], min_p hi[i+1] w[i, p] + base[i, p]))."""
    for i in range(len(x_cap) - 1, -1, -1):
        best = x_cap[i]
        for p in range(w.shape[1]):
            value = hi[i + 1] * w[i, p] + base[i, p]
            if value < best:
                best = value
        hi[i] = max(0.0, best)


@compiled(**_JIT)
def forward_pass(hi_b: np.ndarray, hi_k: np.ndarray, h: np.ndarray, hi: np.ndarray, x: np.ndarray) -> None:
    """Fill ``x`` (N,), whose first entry is the start's (0: at rest), greedily: on each interval
    the largest path acceleration u <= hi_b[i, p] + hi_k[i, p] x[i] that keeps x[i+1] within hi[i+1]."""
    for i in range(len(h)):
        most = (hi[i + 1] - x[i]) / (2 * h[i])
        for p in range(hi_b.shape[1]):
            value = hi_b[i, p] + hi_k[i, p] * x[i]
            if value < most:
                most = value
        x[i + 1] = min(max(x[i] + 2 * h[i] * most, 0.0), hi[i + 1])


@compiled(inline="always", **_JIT)
def _basis(t: float, h: float, derivative: int) -> tuple[float, float, float, float, float]:
    """The cubic Hermite basis (b0, b1, b2, b3) at a step's fraction ``t``, or its
    ``derivative`` (0 to 3) in s, and the factor 1 / h**derivative that goes with it."""
    if derivative == 0:
        return 2 * t**3 - 3 * t**2 + 1, t**3 - 2 * t**2 + t, -2 * t**3 + 3 * t**2, t**3 - t**2, 1.0
    if derivative == 1:
        return 6 * t**2 - 6 * t, 3 * t**2 - 4 * t + 1, -6 * t**2 + 6 * t, 3 * t**2 - 2 * t, 1 / h
    if derivative == 2:
        return 12 * t - 6, 6 * t - 4, 6 - 12 * t, 6 * t - 2, 1 / h**2
    return 12.0, 6.0, -12.0, 6.0, 1 / h**3


@compiled(inline="always", **_JIT)
def _step(knots: np.ndarray, s: float) -> int:
    """The step of ``knots`` that arc length ``s`` falls in (from the right at a knot)."""
    k = int(np.searchsorted(knots, s, side="right")) - 1
    return min(max(k, 0), len(knots) - 2)


@compiled(inline="always", **_JIT)
def _hermite_at(
    knots: np.ndarray, poses: np.ndarray, slopes: np.ndarray, k: int, t: float, derivative: int, j: int
) -> float:
    """Joint j of the path, or its ``derivative``, at fraction ``t`` of step k."""
    h = knots[k + 1] - knots[k]
    b0, b1, b2, b3, scale = _basis(t, h, derivative)
    return float(scale * (b0 * poses[k, j] + b1 * h * slopes[k, j] + b2 * poses[k + 1, j] + b3 * h * slopes[k + 1, j]))


@compiled(**_JIT)
def hermite(
    knots: np.ndarray, poses: np.ndarray, slopes: np.ndarray, s: np.ndarray, derivative: int, out: np.ndarray
) -> None:
    """Fill ``out`` (k, n) with the piecewise cubic Hermite path through ``poses`` (m, n) with
    ``slopes`` (m, n) at ``knots`` (m,), or its ``derivative`` (0 to 3) in s, at ``s`` (k,); each
    point in the step it falls in (from the right at a knot), as
    :meth:`armanim.motion.timing.jointpath.JointPath.evaluate` defines it."""
    for i in range(len(s)):
        k = _step(knots, s[i])
        t = (s[i] - knots[k]) / (knots[k + 1] - knots[k])
        for j in range(poses.shape[1]):
            out[i, j] = _hermite_at(knots, poses, slopes, k, t, derivative, j)


@compiled(**_JIT)
def law_excess(
    law_t: np.ndarray,
    law_s: np.ndarray,
    law_speed: np.ndarray,
    law_accel: np.ndarray,
    knots: np.ndarray,
    poses: np.ndarray,
    slopes: np.ndarray,
    fractions: np.ndarray,
    speed: np.ndarray,
    acceleration: np.ndarray,
) -> tuple[float, float]:
    """The largest ratio of any joint's speed to its limit, and of its acceleration to its
    limit, of the time law (grid times ``law_t``, points ``law_s``, path speeds ``law_speed``
    and constant path accelerations ``law_accel`` on its intervals) along the path, at the
    ``fractions`` of every grid interval: what :class:`armanim.motion.timing.clock.TimeLaw`'s ``at``
    and :func:`hermite` give there, without their arrays (NaN for both if any is NaN)."""
    last, i, k = len(law_accel) - 1, 0, 0
    most_v, most_a, nan = 0.0, 0.0, False
    for g in range(len(law_t) - 1):
        dt = law_t[g + 1] - law_t[g]
        for f in fractions:
            t = law_t[g] + f * dt
            while i < last and law_t[i + 1] <= t:  # the times only grow: searchsorted's answer, found by walking
                i += 1
            tau = t - law_t[i]
            u = law_accel[i]
            s = max(min(law_s[i] + law_speed[i] * tau + 0.5 * u * tau**2, law_s[i + 1]), law_s[i])
            sd = max(law_speed[i] + u * tau, 0.0)
            while k < len(knots) - 2 and knots[k + 1] <= s:  # and so do the arc lengths
                k += 1
            frac = (s - knots[k]) / (knots[k + 1] - knots[k])
            for j in range(poses.shape[1]):
                d1 = _hermite_at(knots, poses, slopes, k, frac, 1, j)
                d2 = _hermite_at(knots, poses, slopes, k, frac, 2, j)
                v, a = abs(d1 * sd) / speed[j], abs(d1 * u + d2 * sd**2) / acceleration[j]
                nan |= v != v or a != a
                most_v, most_a = max(most_v, v), max(most_a, a)
    return (np.nan, np.nan) if nan else (most_v, most_a)


@compiled(**_JIT)
def pass_bounds(
    h: np.ndarray,
    lo_b: np.ndarray,
    lo_k: np.ndarray,
    hi_b: np.ndarray,
    hi_k: np.ndarray,
    x_cap: np.ndarray,
    w: np.ndarray,
    base: np.ndarray,
) -> None:
    """Lower ``x_cap`` (N,) where u >= -x / 2h (the next point's x is not negative) would pass an
    upper bound, and fill the backward pass's ``w``, ``base`` (N, P): u <= (hi[i+1] - x) / 2h
    against each lower bound p is x <= hi[i+1] w + base (w = 0, base = inf where every x keeps it)."""
    for i in range(len(h)):
        least = -1 / (2 * h[i])
        for q in range(hi_b.shape[1]):
            slope = least - hi_k[i, q]
            if slope > 0:
                x_cap[i] = min(x_cap[i], (hi_b[i, q] - 0.0) / slope)
        inverse = 1 / (2 * h[i])
        for p in range(lo_b.shape[1]):
            slope = lo_k[i, p] + inverse
            if slope > 0:
                w[i, p] = 1 / (2 * h[i] * slope)
                base[i, p] = -lo_b[i, p] / slope
            else:
                w[i, p], base[i, p] = 0.0, np.inf


@compiled(**_JIT)
def interval_bounds(
    d1: np.ndarray,
    d2: np.ndarray,
    h: np.ndarray,
    fractions: np.ndarray,
    speed: np.ndarray,
    acceleration: np.ndarray,
    lo_b: np.ndarray,
    lo_k: np.ndarray,
    hi_b: np.ndarray,
    hi_k: np.ndarray,
    x_cap: np.ndarray,
) -> None:
    """Fill the bounds of :func:`armanim.motion.timing.clock.time_optimal` on each grid interval i from the
    path's derivatives ``d1``, ``d2`` (C, N, n) at its C collocation points (``fractions`` of h[i]):
    each joint's acceleration a1 u + d2 x within +-a (a1 = d1 + 2 f h d2) as lo_b + lo_k x <= u <=
    hi_b + hi_k x (columns c n + j), each joint's speed as x + 2 f h u <= (v / |d1|)^2 (one upper
    bound per point inside the interval, the last columns; at f = 0 a cap on x), and x_cap (N,)
    the largest x at which every lower bound stays below every upper bound (the grid's maximum
    velocity curve), found by Newton's method on their concave gap from the right."""
    count, n = d1.shape[0], d1.shape[2]
    for i in range(len(h)):
        cap = np.inf
        for c in range(count):
            reach = 2 * fractions[c] * h[i]
            v2 = np.inf
            for j in range(n):
                a1 = d1[c, i, j] + reach * d2[c, i, j]
                col = c * n + j
                if a1 != 0:
                    top = acceleration[j] / abs(a1)
                    lo_b[i, col], hi_b[i, col] = -top, top
                    lo_k[i, col] = hi_k[i, col] = -d2[c, i, j] / a1
                else:
                    lo_b[i, col], hi_b[i, col] = -np.inf, np.inf
                    lo_k[i, col] = hi_k[i, col] = 0.0
                    if d2[c, i, j] != 0:
                        cap = min(cap, acceleration[j] / abs(d2[c, i, j]))
                if d1[c, i, j] != 0:
                    v2 = min(v2, (speed[j] / abs(d1[c, i, j])) ** 2)
            col = count * n + c
            if reach == 0:
                cap = min(cap, v2)
                hi_b[i, col], hi_k[i, col] = np.inf, 0.0
            else:
                hi_b[i, col], hi_k[i, col] = v2 / reach, -1 / reach
        x = _largest_feasible(lo_b[i], lo_k[i], hi_b[i], hi_k[i], cap if cap < np.inf else 1e300)
        x_cap[i] = x


@compiled(inline="always", **_JIT)
def _largest_feasible(lo_b: np.ndarray, lo_k: np.ndarray, hi_b: np.ndarray, hi_k: np.ndarray, x: float) -> float:
    """The largest x at most ``x`` where every lower bound lo_b + lo_k x stays below every upper
    bound hi_b + hi_k x: Newton's method from the right on their gap (concave, piecewise linear:
    a few steps)."""
    for _ in range(len(hi_b) + len(lo_b)):
        low, p = -np.inf, -1
        for q in range(len(lo_b)):
            value = lo_b[q] + lo_k[q] * x
            if value > low:
                low, p = value, q
        high, r = np.inf, -1
        for q in range(len(hi_b)):
            value = hi_b[q] + hi_k[q] * x
            if value < high:
                high, r = value, q
        gap = high - low
        if gap >= 0 or p < 0 or r < 0:
            break
        slope = hi_k[r] - lo_k[p]
        if slope >= 0:
            return 0.0
        step = max(x - gap / slope, 0.0)
        if step == x:  # at the root up to rounding: the gap stays a hair below 0 where x can no longer move
            break
        x = step
    return float(x)
