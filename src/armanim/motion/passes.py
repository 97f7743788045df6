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
def pairwise_cap(lo_b: np.ndarray, lo_k: np.ndarray, hi_b: np.ndarray, hi_k: np.ndarray, x_cap: np.ndarray) -> None:
    """Lower ``x_cap`` (N,) to the largest x at which every lower bound lo_b + lo_k x on the
    path acceleration stays below every upper bound hi_b + hi_k x, on each interval."""
    for i in range(len(x_cap)):
        for p in range(lo_b.shape[1]):
            for q in range(hi_b.shape[1]):
                slope = lo_k[i, p] - hi_k[i, q]
                if slope > 0:
                    value = (hi_b[i, q] - lo_b[i, p]) / slope
                    if value < x_cap[i]:
                        x_cap[i] = value
