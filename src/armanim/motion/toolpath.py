"""Paths for the tool to follow: straight pieces and circular arcs, inked or not, end to end.

A :class:`ToolPath` is a chain of :class:`Piece` s, each starting where the one before ends:
a line, an arc, a polyline (lines) or written text (each stroke a polyline, the pen lifted,
carried and lowered between strokes by pieces that leave no ink). Everything is a function of
the arc length ``s`` (scene units) along the whole path, from 0 to :attr:`ToolPath.length`.
Pure core: numpy only.

>>> p = ToolPath.polyline(np.array([[0.0, 0, 0], [1, 0, 0], [1, 1, 0]]))
>>> p.length, p.points(np.array([0.5, 1.5])).tolist()
(2.0, [[0.5, 0.0, 0.0], [1.0, 0.5, 0.0]])
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import cast

import numpy as np


@dataclass(frozen=True)
class Piece:
    """One piece of a tool path: a line from ``start`` to ``end``, or an arc.

    Attributes
    ----------
    start : (3,) array
        Where the piece starts.
    end : (3,) array
        Where it ends.
    ink : bool
        Whether a pen on the tool draws along it (False: the pen is lifted).
    center : (3,) array or None
        An arc's center; None for a line.
    u, v : (3,) arrays or None
        An arc's in-plane unit vectors: ``start = center + radius u``, and the arc turns from
        ``u`` toward ``v`` (``v = normal x u``, the right-hand rule about the normal; negated
        for a negative angle).
    angle : float
        An arc's angle swept, radians (> 0); 0 for a line.
    """

    start: np.ndarray
    end: np.ndarray
    ink: bool = True
    center: np.ndarray | None = None
    u: np.ndarray | None = None
    v: np.ndarray | None = None
    angle: float = 0.0

    @classmethod
    def line(cls, start: np.ndarray, end: np.ndarray, ink: bool = True) -> Piece:
        """A straight piece from ``start`` to ``end`` (3,)."""
        return cls(np.asarray(start, dtype=float), np.asarray(end, dtype=float), ink)

    @classmethod
    def arc(cls, center: np.ndarray, start: np.ndarray, angle: float, normal: np.ndarray, ink: bool = True) -> Piece:
        """An arc about ``center`` from ``start`` through ``angle`` radians (negative: clockwise)
        about ``normal`` (3,), which need not be unit nor square to ``start - center``: the arc
        lies in the plane through ``center`` square to ``normal``, through the projection of ``start``.

        >>> a = Piece.arc(np.zeros(3), np.array([1.0, 0, 0]), np.pi / 2, np.array([0, 0, 1.0]))
        >>> np.round(a.end, 12).tolist(), round(a.length, 12)
        ([0.0, 1.0, 0.0], 1.570796326795)
        """
        center, normal = np.asarray(center, dtype=float), np.asarray(normal, dtype=float)
        normal = normal / np.linalg.norm(normal)
        offset = np.asarray(start, dtype=float) - center
        offset = offset - (offset @ normal) * normal
        radius = float(np.linalg.norm(offset))
        u = offset / radius
        v = np.cross(normal, u) * (1.0 if angle > 0 else -1.0)
        sweep = abs(float(angle))
        start_point = center + radius * u
        end = center + radius * (math.cos(sweep) * u + math.sin(sweep) * v)
        return cls(start_point, end, ink, center, u, v, sweep)

    def reversed(self) -> Piece:
        """The same piece run from its end to its start (an arc: the same circle, swept back).

        >>> a = Piece.arc(np.zeros(3), np.array([1.0, 0, 0]), np.pi / 2, np.array([0, 0, 1.0])).reversed()
        >>> np.round(a.points(np.array([0.0, np.pi / 2])), 12).tolist()
        [[0.0, 1.0, 0.0], [1.0, 0.0, 0.0]]
        """
        if self.center is None:
            return Piece.line(self.end, self.start, self.ink)
        assert self.u is not None and self.v is not None
        c, s = math.cos(self.angle), math.sin(self.angle)  # point(L - t): u' = c u + s v, v' = s u - c v
        return Piece(
            self.end, self.start, self.ink, self.center, c * self.u + s * self.v, s * self.u - c * self.v, self.angle
        )

    @property
    def radius(self) -> float:
        """An arc's radius (0 for a line)."""
        return 0.0 if self.center is None else float(np.linalg.norm(self.start - self.center))

    @property
    def length(self) -> float:
        """Arc length of the piece, scene units."""
        if self.center is None:
            return float(np.linalg.norm(self.end - self.start))
        return self.radius * self.angle

    def points(self, t: np.ndarray) -> np.ndarray:
        """(k, 3) the points at arc lengths ``t`` (k,) from the piece's start (clipped to it)."""
        t = np.clip(np.asarray(t, dtype=float), 0.0, self.length)
        if self.center is None:
            f = t / self.length if self.length > 0 else np.zeros_like(t)
            return cast(np.ndarray, self.start + f[:, None] * (self.end - self.start))
        assert self.u is not None and self.v is not None
        theta = t / self.radius
        return cast(
            np.ndarray, self.center + self.radius * (np.cos(theta)[:, None] * self.u + np.sin(theta)[:, None] * self.v)
        )

    def nearest(self, points: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The nearest point of the piece's part between arc lengths ``lo`` and ``hi`` (k,) to
        each of ``points`` (k, 3): its arc length from the piece's start (k,) and its distance (k,).

        >>> a = Piece.line(np.zeros(3), np.array([2.0, 0, 0]))
        >>> t, d = a.nearest(np.array([[0.5, 1.0, 0.0], [3.0, 0, 0]]), np.zeros(2), np.full(2, 1.0))
        >>> t.tolist(), d.tolist()
        ([0.5, 1.0], [1.0, 2.0])
        """
        points = np.asarray(points, dtype=float)
        lo, hi = np.clip(lo, 0.0, self.length), np.clip(hi, 0.0, self.length)
        if self.center is None:
            direction = self.end - self.start
            t = (points - self.start) @ direction / max(self.length, 1e-300)
            t = np.clip(t, lo, hi)
        else:
            assert self.u is not None and self.v is not None
            w = points - self.center
            theta = np.arctan2(w @ self.v, w @ self.u)
            along = np.where(theta < 0, theta + 2 * np.pi, theta) * self.radius  # the point's angle as arc length
            # the distance falls toward theta round the circle and rises away from it: a point whose
            # angle lies outside the part is nearest one of the part's ends (the nearer, which by
            # arc length need not be the one round the circle)
            nearer = np.linalg.norm(points - self.points(lo), axis=-1) <= np.linalg.norm(
                points - self.points(hi), axis=-1
            )
            t = np.where((along >= lo) & (along <= hi), along, np.where(nearer, lo, hi))
        return t, np.linalg.norm(points - self.points(t), axis=-1)


@dataclass(frozen=True)
class ToolPath:
    """Pieces end to end, as one function of arc length.

    Attributes
    ----------
    pieces : tuple of Piece
        Each starting where the one before ends.
    """

    pieces: tuple[Piece, ...]

    @classmethod
    def polyline(cls, vertices: np.ndarray, ink: bool = True) -> ToolPath:
        """Straight pieces through ``vertices`` (m, 3), m >= 2; zero-length pieces are left out."""
        vertices = np.asarray(vertices, dtype=float)
        pieces = [Piece.line(a, b, ink) for a, b in zip(vertices[:-1], vertices[1:]) if np.any(a != b)]
        return cls(tuple(pieces))

    @property
    def start(self) -> np.ndarray:
        """(3,) where the path starts."""
        return self.pieces[0].start

    @property
    def end(self) -> np.ndarray:
        """(3,) where the path ends."""
        return self.pieces[-1].end

    def reversed(self) -> ToolPath:
        """The path run from its end to its start: the point at ``s`` is this one's at ``length - s``.

        >>> p = ToolPath.polyline(np.array([[0.0, 0, 0], [1, 0, 0], [1, 1, 0]]))
        >>> p.reversed().points(np.array([0.5, 1.5])).tolist()
        [[1.0, 0.5, 0.0], [0.5, 0.0, 0.0]]
        """
        return ToolPath(tuple(piece.reversed() for piece in reversed(self.pieces)))

    @functools.cached_property
    def corners(self) -> np.ndarray:
        """(P + 1,) arc lengths where the pieces start, and the path's end (made once: every
        sample looks pieces up in it, and a path has up to some 10,000 pieces)."""
        corners = np.concatenate([[0.0], np.cumsum([p.length for p in self.pieces])])
        corners.flags.writeable = False
        return corners

    @functools.cached_property
    def length(self) -> float:
        """Arc length of the whole path, scene units."""
        return float(self.corners[-1])

    @property
    def inked_length(self) -> float:
        """Arc length of the pieces that leave ink."""
        return float(sum(p.length for p in self.pieces if p.ink))

    def piece_of(self, s: np.ndarray) -> np.ndarray:
        """(k,) the index of the piece each arc length ``s`` (k,) lies in (the last for the end)."""
        return np.clip(np.searchsorted(self.corners, s, side="right") - 1, 0, len(self.pieces) - 1)

    def points(self, s: np.ndarray) -> np.ndarray:
        """(k, 3) the points at arc lengths ``s`` (k,), clipped to the path."""
        s = np.clip(np.asarray(s, dtype=float), 0.0, self.length)
        out = np.empty((len(s), 3))
        which = self.piece_of(s)
        corners = self.corners
        for i in np.unique(which):
            at = which == i
            out[at] = self.pieces[i].points(s[at] - corners[i])
        return out

    def inked(self, s: np.ndarray) -> np.ndarray:
        """(k,) bool: whether the piece at each arc length ``s`` (k,) leaves ink."""
        return cast(np.ndarray, np.array([p.ink for p in self.pieces])[self.piece_of(np.asarray(s, dtype=float))])

    def samples(self, spacing: float) -> np.ndarray:
        """Arc lengths that split every piece evenly into steps of at most ``spacing``: every
        corner is one, so a sampled polyline keeps its corners.

        >>> ToolPath.polyline(np.array([[0.0, 0, 0], [1, 0, 0], [1, 0.5, 0]])).samples(0.4).tolist()
        [0.0, 0.3333333333333333, 0.6666666666666666, 1.0, 1.25, 1.5]
        """
        corners = self.corners
        out = [np.zeros(1)]
        for a, b in zip(corners[:-1], corners[1:]):
            steps = _steps(b - a, spacing)
            out.append(a + (b - a) * np.arange(1, steps + 1) / steps)
        return np.concatenate(out)

    def sample_count(self, spacing: float) -> int:
        """How many arc lengths :meth:`samples` gives for ``spacing``, counted without making them
        (a path of 300 units at a spacing of 1e-8 has 3e10 samples: an array of them is 240 GB).

        >>> ToolPath.polyline(np.array([[0.0, 0, 0], [1, 0, 0], [1, 0.5, 0]])).sample_count(0.4)
        6
        >>> ToolPath.polyline(np.array([[0.0, 0, 0], [300, 0, 0]])).sample_count(1e-8)
        30000000001
        """
        return 1 + sum(_steps(p.length, spacing) for p in self.pieces)

    def nearest(
        self, points: np.ndarray, lo: np.ndarray | None = None, hi: np.ndarray | None = None
    ) -> tuple[np.ndarray, np.ndarray]:
        """The nearest point of the path between arc lengths ``lo`` and ``hi`` (k,; the whole
        path by default) to each of ``points`` (k, 3): its arc length (k,) and its distance (k,).

        >>> p = ToolPath.polyline(np.array([[0.0, 0, 0], [1, 0, 0], [1, 1, 0]]))
        >>> s, d = p.nearest(np.array([[0.2, 0.1, 0.0], [1.3, 0.6, 0.0]]))
        >>> np.round(s, 12).tolist(), np.round(d, 12).tolist()
        ([0.2, 1.6], [0.1, 0.3])
        """
        points = np.asarray(points, dtype=float).reshape(-1, 3)
        k = len(points)
        lo = np.zeros(k) if lo is None else np.broadcast_to(np.asarray(lo, dtype=float), (k,))
        hi = np.full(k, self.length) if hi is None else np.broadcast_to(np.asarray(hi, dtype=float), (k,))
        best_s, best_d = np.zeros(k), np.full(k, np.inf)
        corners = self.corners
        if not k:
            return best_s, best_d
        # only the pieces between the least lo and the largest hi can be touched: a sample's
        # look between its neighbours costs a few pieces, not all of a 10,000-piece text's
        first = int(np.searchsorted(corners[1:], float(np.min(lo)), side="left"))
        last = int(np.searchsorted(corners[:-1], hi.max(), side="right"))
        for i in range(first, last):
            corner, piece, following = corners[i], self.pieces[i], corners[i + 1]
            touched = (lo <= following) & (hi >= corner)
            if not touched.any():
                continue
            t, d = piece.nearest(points[touched], lo[touched] - corner, hi[touched] - corner)
            closer = d < best_d[touched]
            idx = np.nonzero(touched)[0][closer]
            best_s[idx], best_d[idx] = corner + t[closer], d[closer]
        return best_s, best_d

    def distance(self, points: np.ndarray) -> np.ndarray:
        """(k,) each point's (k, 3) distance from the whole path."""
        return self.nearest(points)[1]


def _steps(length: float, spacing: float) -> int:
    """Equal steps of at most ``spacing`` that cover ``length`` (at least one).

    >>> _steps(1.0, 0.4), _steps(1.2, 0.4), _steps(0.0, 0.4)
    (3, 3, 1)
    """
    return max(1, math.ceil(length / spacing - 1e-9))


__all__ = ["Piece", "ToolPath"]
