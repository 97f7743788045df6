"""Painter's order of the solid parts of a frame: what is behind is drawn first.

Every part (a link prism, a joint, the base, an obstacle) is summarised as a capsule
on screen: sample points along a segment with their depth, and a radius in pixels.
Two parts that overlap on screen get an edge "far one first", decided by the depth
of their overlapping samples; parts that do not overlap are not ordered. The graph
is then sorted topologically, far parts first among the free ones. An obstacle is
never entered by the arm, so an arm part overlapping a sphere on screen lies wholly
in front of it or wholly behind it along every ray: the order is exact there.
"""

from __future__ import annotations

import heapq

import numpy as np


def paint_order(samples: np.ndarray, radii: np.ndarray) -> list[int]:
    """Order in which to draw parts so nearer ones cover farther ones.

    Parameters
    ----------
    samples : (N, S, 3) array
        S screen points (x px, y px, near) along each part's axis.
    radii : (N,) array
        Each part's half thickness on screen, pixels.

    Returns
    -------
    list of int
        Part indices, farthest first. A cycle (parts interleaved in depth) is broken
        by drawing the farthest remaining part.

    Examples
    --------
    A near disc over a far one, and a third one apart from both:

    >>> s = np.array([[[0, 0, 5.0]], [[1, 0, -5.0]], [[50, 0, 0.0]]])
    >>> paint_order(s, np.array([2.0, 2.0, 2.0]))
    [1, 2, 0]
    """
    return order_by(overlap_ahead(samples, radii), samples[..., 2].mean(axis=1))


def overlap_ahead(samples: np.ndarray, radii: np.ndarray) -> np.ndarray:
    """(N, N): ahead[a, b] > 0 when part a is nearer than part b where they overlap on screen
    (the summed depth differences of their overlapping samples; 0 when they do not overlap)."""
    xy = samples[..., :2]
    near = samples[..., 2]
    gap = np.linalg.norm(xy[:, :, None, None, :] - xy[None, None, :, :, :], axis=-1)  # (N,S,N,S)
    overlap = gap < (radii[:, None, None, None] + radii[None, None, :, None])
    ahead = np.where(overlap, near[:, :, None, None] - near[None, None, :, :], 0.0).sum(axis=(1, 3))
    np.fill_diagonal(ahead, 0.0)
    return ahead


def order_by(ahead: np.ndarray, mean_near: np.ndarray) -> list[int]:
    """Topological order of the "far one first" graph of ``ahead`` (:func:`overlap_ahead`),
    the farthest free part first; a cycle is broken by drawing the farthest part left."""
    n = len(ahead)
    before = ahead > 1e-9  # before[a, b]: a is nearer than b, so b is drawn first
    indegree = before.sum(axis=1)  # how many parts must be drawn before each one
    heap = [(mean_near[i], i) for i in range(n) if indegree[i] == 0]
    heapq.heapify(heap)
    done = np.zeros(n, dtype=bool)
    order: list[int] = []
    while len(order) < n:
        if not heap:  # a cycle: draw the farthest part left
            rest = np.flatnonzero(~done)
            heap = [(mean_near[rest].min(), int(rest[np.argmin(mean_near[rest])]))]
        _, i = heapq.heappop(heap)
        if done[i]:
            continue
        done[i] = True
        order.append(i)
        for j in np.flatnonzero(before[:, i] & ~done):
            indegree[j] -= 1
            if indegree[j] == 0:
                heapq.heappush(heap, (mean_near[j], int(j)))
    return order
