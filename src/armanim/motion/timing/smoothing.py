"""A blended sequence's path made short and smooth: shortcut, then its corners rounded, all certified.

The frame loop's path to a goal is the method's many small steps: it curves, and near a goal its
steps shrink and turn, so the clock, bound by the path's curvature, is slow nearly everywhere and
passing a goal without stopping saves little. Where goals are blended (:mod:`armanim.motion.timing.blend`)
the solved poses between two kept poses (the part's first pose, each via goal's solved pose, the
part's last pose: the same goals reached at the same poses) are replaced:

1. **Shortcut** (:func:`shortcut_hops`): from each kept pose, the farthest later solved pose (up to
   the next kept one) that a straight joint segment reaches, certified clear
   (:func:`certified_samples`); a solved step no segment skips stays as it was solved.
2. **Corners** (:func:`smoothed_poses`): where two straight segments meet, the corner is replaced by
   the quadratic Bezier curve from a point on the segment before to one on the segment after, the
   corner its control point, reaching at most half-way along each (neighbouring curves meet at most
   at a segment's midpoint: a C1 path). At a via goal the curve must also pass within ``ENTRY`` of
   its blend radius, checked by forward kinematics on the curve (joint goals: by the joints);
   ``blend: 0`` keeps the corner, the goal's pose itself passed. A curve that cannot be
   certified is made tighter (a smaller fraction of the segments), at last kept as a corner.

Certified: every pose added is measured (obstacles and the arm's own pairs, one floor), and every
piece between two consecutive poses keeps the floor by the lever-arm bound
(:func:`~armanim.motion.timing.goalmotion.two_sided_bound`), pieces halved until it does; the clock's path
keeps each joint monotone between two consecutive poses, so it stays in their box, which the bound
covers. A straight segment is given to the clock by its two first and two last samples only: through
collinear poses the clock's path is the segment itself, all of whose pieces were certified
(:func:`_thinned`). Straight segments and the curves' poses are convex combinations of poses inside
the joint limits, so inside too. Pure core: numpy only.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from armanim.motion.timing.goalmotion import two_sided_bound

FRACTIONS = (0.5, 0.3, 0.15, 0.06)
"""The fractions of the two segments a corner's curve may take, largest first."""
MOST_PIECES = 4096
"""Most poses on one certified segment or curve: one these cannot certify is refused."""
HALVINGS = 12
"""Most times a piece the bound does not certify is halved."""
CURVE_SAMPLES = 24
"""Least poses on a corner's curve (the clock's path through them follows the curve)."""
MOST_TURN = 1.0
"""Most radians any joint turns between two consecutive poses given to the clock (which takes an
unlimited joint's turn between two poses the short way round: below pi, it is the segment's)."""


@dataclass(frozen=True)
class Certifier:
    """What certifies a stretch of joint space clear.

    Attributes
    ----------
    measure : callable
        (k, n) poses, radians -> (k,) clearances (obstacles and own pairs judged by one floor).
    lever : (n,) array
        Each joint's lever arm (no point moves by more than lever . |dPhi|).
    floor : float
        The least clearance.
    """

    measure: Callable[[np.ndarray], np.ndarray]
    lever: np.ndarray
    floor: float


def certified_samples(
    curve: Callable[[np.ndarray], np.ndarray], c0: float, c1: float, cert: Certifier, least: int = 1
) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """Poses along ``curve`` (t in [0, 1] -> (k, n) poses) dense enough that every piece between two
    consecutive ones is certified, or None.

    Parameters
    ----------
    curve : callable
        (k,) parameters -> (k, n) poses; ``curve(0)`` and ``curve(1)`` are the ends.
    c0, c1 : float
        The ends' clearances (measured by the caller).
    cert : Certifier
    least : int
        Least pieces.

    Returns
    -------
    (t, poses, clearance) : ((k,), (k, n), (k,)) arrays, ends included, or None
        None where a pose is under the floor, or the pieces would be more than :data:`MOST_PIECES`.

    >>> one = line(np.array([0.0]), np.array([1.0]))  # a radian of a joint with a lever arm of 1
    >>> t, poses, clear = certified_samples(one, 1.0, 1.0, Certifier(lambda p: np.full(len(p), 1.0), np.array([1.0]), 0.5))
    >>> t.tolist()  # pieces of the margin: each certified by the bound
    [0.0, 0.5, 1.0]
    >>> certified_samples(one, 1.0, 1.0, Certifier(lambda p: np.full(len(p), 0.4), np.array([1.0]), 0.5)) is None
    True
    """
    if min(c0, c1) < cert.floor:
        return None
    ends = curve(np.array([0.0, 1.0]))
    fine = curve(np.linspace(0.0, 1.0, 33))
    travel = float(np.sum(np.abs(np.diff(fine, axis=0)) @ cert.lever))
    piece = max(min(c0, c1) - cert.floor, 1e-9)
    turn = float(np.abs(np.diff(fine, axis=0)).sum(axis=0).max())
    count = max(least, math.ceil(travel / piece), math.ceil(turn / MOST_TURN))
    if count > MOST_PIECES:
        return None
    t = np.linspace(0.0, 1.0, count + 1)
    poses = np.concatenate([ends[:1], curve(t[1:-1]), ends[1:]])
    clear = np.concatenate([[c0], cert.measure(poses[1:-1]) if count > 1 else np.zeros(0), [c1]])
    for _ in range(HALVINGS + 1):
        if np.any(clear < cert.floor):
            return None
        bad = two_sided_bound(clear[:-1], clear[1:], np.abs(np.diff(poses, axis=0)) @ cert.lever) < cert.floor
        if not bad.any():
            return t, poses, clear
        if len(t) + bad.sum() > MOST_PIECES:
            return None
        mids = 0.5 * (t[:-1][bad] + t[1:][bad])
        new_poses, new_clear = curve(mids), cert.measure(curve(mids))
        order = np.argsort(np.concatenate([t, mids]), kind="stable")
        t = np.concatenate([t, mids])[order]
        poses = np.concatenate([poses, new_poses])[order]
        clear = np.concatenate([clear, new_clear])[order]
    return None


def line(a: np.ndarray, b: np.ndarray) -> Callable[[np.ndarray], np.ndarray]:
    """The straight joint segment from ``a`` to ``b`` (n,) as a curve of t in [0, 1] (its ends exact).

    >>> line(np.array([0.1]), np.array([0.7]))(np.array([0.0, 1.0])).ravel().tolist()
    [0.1, 0.7]
    """

    def at(t: np.ndarray) -> np.ndarray:
        t = np.asarray(t)[:, None]
        return np.asarray((1 - t) * a + t * b)

    return at


def bezier(a: np.ndarray, c: np.ndarray, b: np.ndarray) -> Callable[[np.ndarray], np.ndarray]:
    """The quadratic Bezier curve from ``a`` to ``b`` (n,) with control point ``c`` as a curve of t."""

    def at(t: np.ndarray) -> np.ndarray:
        t = np.asarray(t)[:, None]
        return np.asarray((1 - t) ** 2 * a + 2 * t * (1 - t) * c + t**2 * b)

    return at


@dataclass(frozen=True)
class Hop:
    """One piece of the shortcut path: solved poses ``first`` to ``last`` (indices), and the
    certified poses of the segment between them (None: a solved step, kept as solved)."""

    first: int
    last: int
    poses: np.ndarray | None = None
    clearance: np.ndarray | None = None


def shortcut_hops(flat: np.ndarray, clear: np.ndarray, keep: list[int], cert: Certifier) -> list[Hop]:
    """The solved path ``flat`` (m, n) (unwrapped, clearances ``clear`` (m,)) from ``keep[0]`` to
    ``keep[-1]`` through every kept pose, as straight certified segments where one fits: from each
    pose, the farthest later pose up to the next kept one whose segment :func:`certified_samples`
    certifies (searched by bisection from the kept one), else the next solved step as solved."""
    hops: list[Hop] = []
    for start, stop in zip(keep[:-1], keep[1:]):
        i = start
        while i < stop:
            found = _segment(flat, clear, i, stop, cert)
            j = stop
            if found is None:
                lo, hi = i + 1, stop
                while hi - lo > 1:
                    mid = (lo + hi) // 2
                    tried = _segment(flat, clear, i, mid, cert)
                    if tried is None:
                        hi = mid
                    else:
                        lo, found = mid, tried
                j = lo
            if found is None or j == i + 1:
                hops.append(Hop(i, i + 1))
            else:
                hops.append(Hop(i, j, *found))
            i = j
    return hops


def _segment(
    flat: np.ndarray, clear: np.ndarray, i: int, j: int, cert: Certifier
) -> tuple[np.ndarray, np.ndarray] | None:
    """The certified poses and clearances of the straight segment from solved pose ``i`` to ``j``, or None."""
    if j == i + 1:
        return None
    done = certified_samples(line(flat[i], flat[j]), float(clear[i]), float(clear[j]), cert)
    return None if done is None else (done[1], done[2])


@dataclass(frozen=True)
class Smoothed:
    """A path through kept poses, shortcut and rounded (see the module).

    Attributes
    ----------
    poses : (k, n) array
        Unwrapped poses, radians.
    position : (k,) array
        Where each lies along the solved path, as a fractional solved index (monotone).
    clearance : (k,) array
    certified : (k - 1,) bool array
        The steps known to keep the floor (all but solved steps kept as solved, which keep their own).
    corners : dict
        Each kept pose's index (a key of ``near``) -> (first, last) poses of its curve, and
        whether the corner was rounded ((i, i), False: passed at pose i).
    """

    poses: np.ndarray
    position: np.ndarray
    clearance: np.ndarray
    certified: np.ndarray
    corners: dict[int, tuple[tuple[int, int], bool]]


def smoothed_poses(
    flat: np.ndarray,
    clear: np.ndarray,
    certified: np.ndarray,
    keep: list[int],
    cert: Certifier,
    near: dict[int, Callable[[np.ndarray], np.ndarray] | None],
) -> Smoothed:
    """The solved path ``flat`` (m, n) (unwrapped; clearances ``clear``; steps ``certified``) through
    the ``keep`` poses (first and last included), shortcut (:func:`shortcut_hops`) and its corners
    rounded (see the module).

    ``near``: for each kept pose inside (a via goal's), a test of a curve's poses (k, n) -> (k,)
    bool, whether each is close enough to the goal (None: the corner is kept, passed exactly); a
    corner at a kept pose is rounded only if some pose of its curve passes the test.
    """
    if len(flat) < 3:  # nothing to shortcut, no corner to round
        return Smoothed(flat, np.arange(len(flat), dtype=float), clear, certified, {k: ((k, k), False) for k in keep})
    hops = shortcut_hops(flat, clear, keep, cert)
    # each corner between two certified segments: its curve and fraction, largest that certifies
    curves: dict[int, tuple[float, tuple[np.ndarray, np.ndarray, np.ndarray]]] = {}
    for h in range(1, len(hops)):
        before, after = hops[h - 1], hops[h]
        corner = before.last
        if before.poses is None or after.poses is None or (corner in near and near[corner] is None):
            continue
        p, c, q = flat[before.first], flat[corner], flat[after.last]
        for f in FRACTIONS:
            a, b = c + f * (p - c), c + f * (q - c)
            curve = bezier(a, c, b)
            test = near.get(corner)
            if test is not None and not np.any(test(curve(np.linspace(0.0, 1.0, 129)))):
                continue
            ends = cert.measure(np.stack([a, b]))
            done = certified_samples(curve, float(ends[0]), float(ends[1]), cert, least=CURVE_SAMPLES)
            if done is not None:
                curves[corner] = (f, done)
                break
    return _joined(flat, clear, certified, hops, curves, cert)


def _joined(
    flat: np.ndarray,
    clear: np.ndarray,
    certified: np.ndarray,
    hops: list[Hop],
    curves: dict[int, tuple[float, tuple[np.ndarray, np.ndarray, np.ndarray]]],
    cert: Certifier,
) -> Smoothed:
    """The poses of ``hops`` with each corner in ``curves`` replaced by its curve: the straight
    stretch between two curves certified again (a piece of a certified segment; should it not
    certify, both curves are dropped and the segment's own poses kept)."""
    while True:
        poses, position, clearance, ok = (
            [flat[hops[0].first][None]],
            [np.array([float(hops[0].first)])],
            [clear[hops[0].first : hops[0].first + 1]],
            [],
        )
        corners: dict[int, tuple[tuple[int, int], bool]] = {}
        dropped = None
        for h, hop in enumerate(hops):
            i, j = hop.first, hop.last
            if hop.poses is None:
                poses.append(flat[j][None])
                position.append(np.array([float(j)]))
                clearance.append(clear[j : j + 1])
                ok.append(certified[i : i + 1])
                corners.setdefault(j, ((sum(len(p) for p in poses) - 1,) * 2, False))
                continue
            f0 = curves[i][0] if i in curves else 0.0
            f1 = curves[j][0] if j in curves else 0.0
            a, b = flat[i] + f0 * (flat[j] - flat[i]), flat[j] + f1 * (flat[i] - flat[j])
            if f0 or f1:
                ends = [clear[i] if not f0 else curves[i][1][2][-1], clear[j] if not f1 else curves[j][1][2][0]]
                if 1 - f0 - f1 > 1e-12:
                    done = certified_samples(line(a, b), float(ends[0]), float(ends[1]), cert)
                    if done is None:
                        dropped = (i, j)
                        break
                    t, seg, c = done
                else:  # two curves meet at the segment's midpoint
                    t, seg, c = np.zeros(1), a[None], np.array(ends[:1], dtype=float)
            else:
                assert hop.clearance is not None
                t, seg, c = np.linspace(0.0, 1.0, len(hop.poses)), hop.poses, hop.clearance
            u = f0 + t * (1 - f0 - f1)  # the fraction of the hop from i to j
            shown = _thinned(seg)
            poses.append(seg[shown][1:])
            position.append(i + u[shown][1:] * (j - i))
            clearance.append(c[shown][1:])
            ok.append(np.ones(len(shown) - 1, dtype=bool))
            if j in curves:  # the curve round the corner at j, into the next hop
                _, (tc, arc, carc) = curves[j]
                k = hops[h + 1].last
                first = sum(len(p) for p in poses) - 1
                poses.append(arc[1:])
                tc = tc[1:]
                position.append(
                    np.where(tc < 0.5, j - f1 * (1 - 2 * tc) * (j - i), j + curves[j][0] * (2 * tc - 1) * (k - j))
                )
                clearance.append(carc[1:])
                ok.append(np.ones(len(arc) - 1, dtype=bool))
                corners[j] = ((first, first + len(arc) - 1), True)
            elif h + 1 < len(hops):
                corners[j] = ((sum(len(p) for p in poses) - 1,) * 2, False)
        if dropped is None:
            break
        for end in dropped:
            curves.pop(end, None)
    pos = np.maximum.accumulate(np.concatenate(position))
    return Smoothed(np.concatenate(poses), pos, np.concatenate(clearance), np.concatenate(ok), corners)


def _thinned(seg: np.ndarray) -> np.ndarray:
    """The samples of a straight segment ``seg`` (k, n) the clock is given: its two first and two
    last, and between them only as many as keep every joint's turn from one to the next within
    :data:`MOST_TURN`. The clock's path through collinear poses is the segment itself (each joint's
    slope at an inner pose is the segment's, so the cubic between two is the chord), and every
    piece of the segment was certified; near its ends, where the path bends into a curve, it keeps
    the certified pieces' small boxes.

    >>> seg = np.linspace(0.0, 3.0, 31)[:, None]
    >>> _thinned(seg[:3]).tolist(), _thinned(seg).tolist()
    ([0, 1, 2], [0, 1, 11, 21, 29, 30])
    """
    count = len(seg)
    if count <= 4:
        return np.arange(count)
    kept = [0, 1]
    while kept[-1] < count - 2:
        turns = np.abs(seg[kept[-1] + 1 : count - 1] - seg[kept[-1]]).max(axis=1)
        kept.append(kept[-1] + 1 + max(int(np.searchsorted(turns > MOST_TURN, True)) - 1, 0))
    return np.array(kept + [count - 1])


__all__ = ["Certifier", "Hop", "Smoothed", "bezier", "certified_samples", "line", "shortcut_hops", "smoothed_poses"]
