"""The clock's two sequential passes over the path's grid, compiled (numba).

Each pass is a recursion from one grid point to the next over a few dozen bounds: in numpy it
cost some 30 us a point in call overhead alone, compiled it is a few dozen floating-point
operations. Imported by :func:`armanim.motion.clock.time_optimal` when a clock is computed.
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


@compiled(**_JIT)
def hermite(knots: np.ndarray, poses: np.ndarray, slopes: np.ndarray, s: np.ndarray, derivative: int,
            out: np.ndarray) -> None:
    """Fill ``out`` (k, n) with the piecewise cubic Hermite path through ``poses`` (m, n) with
    ``slopes`` (m, n) at ``knots`` (m,), or its ``derivative`` (0 to 3) in s, at ``s`` (k,); each
    point in the step it falls in (from the right at a knot), as
    :meth:`armanim.motion.clock.JointPath.evaluate` defines it."""
    last = len(knots) - 2
    for i in range(len(s)):
        k = np.searchsorted(knots, s[i], side="right") - 1
        k = min(max(k, 0), last)
        h = knots[k + 1] - knots[k]
        t = (s[i] - knots[k]) / h
        if derivative == 0:
            b0, b1, b2, b3, scale = 2 * t**3 - 3 * t**2 + 1, t**3 - 2 * t**2 + t, -2 * t**3 + 3 * t**2, t**3 - t**2, 1.0
        elif derivative == 1:
            b0, b1, b2, b3, scale = 6 * t**2 - 6 * t, 3 * t**2 - 4 * t + 1, -6 * t**2 + 6 * t, 3 * t**2 - 2 * t, 1 / h
        elif derivative == 2:
            b0, b1, b2, b3, scale = 12 * t - 6, 6 * t - 4, 6 - 12 * t, 6 * t - 2, 1 / h**2
        else:
            b0, b1, b2, b3, scale = 12.0, 6.0, -12.0, 6.0, 1 / h**3
        for j in range(poses.shape[1]):
            out[i, j] = scale * (b0 * poses[k, j] + b1 * h * slopes[k, j] + b2 * poses[k + 1, j]
                                 + b3 * h * slopes[k + 1, j])


@compiled(**_JIT)
def interval_bounds(d1: np.ndarray, d2: np.ndarray, h: np.ndarray, fractions: np.ndarray, speed: np.ndarray,
                    acceleration: np.ndarray, lo_b: np.ndarray, lo_k: np.ndarray, hi_b: np.ndarray, hi_k: np.ndarray,
                    x_cap: np.ndarray) -> None:
    """Fill the bounds of :func:`armanim.motion.clock.time_optimal` on each grid interval i from the
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
        x = cap if cap < np.inf else 1e300
        for _ in range(hi_b.shape[1] + lo_b.shape[1]):  # a concave piecewise-linear gap: a few steps
            low, p = -np.inf, -1
            for q in range(lo_b.shape[1]):
                value = lo_b[i, q] + lo_k[i, q] * x
                if value > low:
                    low, p = value, q
            high, r = np.inf, -1
            for q in range(hi_b.shape[1]):
                value = hi_b[i, q] + hi_k[i, q] * x
                if value < high:
                    high, r = value, q
            gap = high - low
            if gap >= 0 or p < 0 or r < 0:
                break
            slope = hi_k[i, r] - lo_k[i, p]
            if slope >= 0:
                x = 0.0
                break
            x = max(x - gap / slope, 0.0)
        x_cap[i] = x
