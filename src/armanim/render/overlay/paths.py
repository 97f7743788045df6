"""What the pictures show of path goals: the ink behind the tool and the path still ahead of it.

A path goal's path (:class:`~armanim.motion.toolpath.ToolPath`) is sampled once
(:func:`sampled_paths`: corners kept, arcs split finely, lines left whole) into a
:class:`SampledPath`. At a frame, the *ink* of a path goal is the pen-down part of its path
from 0 to the farthest arc length the tool reached along it on that goal's frames so far
(:func:`path_progress`); the path *ahead* is the pen-down part from there to the end, shown
faintly while the goal is the frame's goal (the arm approaching it, then following it). Pen-up
travel (``ink: False`` pieces, between a text's strokes) is never drawn, neither as ink nor
ahead: the same rule in the video, the poster and the viewer page. Pure numpy.

>>> from armanim.motion.toolpath import Piece, ToolPath
>>> path = ToolPath((Piece.line(np.zeros(3), np.array([1.0, 0, 0])),
...                  Piece.line(np.array([1.0, 0, 0]), np.array([1.0, 1, 0]), ink=False),
...                  Piece.line(np.array([1.0, 1, 0]), np.array([2.0, 1, 0]))))
>>> sampled = SampledPath.of(0, path, spacing=0.5)
>>> sampled.between(0.0, 2.5)[:, :2].tolist()  # the first piece whole, half the third
[[0.0, 0.0], [1.0, 0.0], [nan, nan], [1.0, 1.0], [1.5, 1.0]]
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

MAX_SAMPLES = 20_000
"""At most this many samples of one path: a longer path is sampled more coarsely."""


def piece_samples(path, spacing: float) -> np.ndarray:
    """Arc lengths along ``path`` (a ToolPath) at every corner and, within each arc, at most
    ``spacing`` apart (a line needs only its ends). Increasing, from 0 to the path's length.

    >>> from armanim.motion.toolpath import Piece, ToolPath
    >>> arc = Piece.arc(np.zeros(3), np.array([1.0, 0, 0]), np.pi, np.array([0, 0, 1.0]))
    >>> line = Piece.line(arc.end, np.array([-1.0, -2, 0]))
    >>> np.round(piece_samples(ToolPath((arc, line)), 1.0), 3).tolist()
    [0.0, 0.785, 1.571, 2.356, 3.142, 5.142]
    """
    corners = path.corners
    spacing = max(float(spacing), path.length / MAX_SAMPLES, 1e-12)
    out = [np.zeros(1)]
    for a, b, piece in zip(corners[:-1], corners[1:], path.pieces):
        steps = 1 if piece.center is None else max(1, math.ceil((b - a) / spacing - 1e-9))
        out.append(a + (b - a) * np.arange(1, steps + 1) / steps)
    return np.concatenate(out)


def arc_spacing(path, chord_error: float) -> float:
    """The spacing along ``path``'s arcs at which a chord strays at most ``chord_error`` from the
    arc (sagitta ``spacing^2 / (8 radius)``), for its tightest arc; inf without arcs.

    >>> from armanim.motion.toolpath import Piece, ToolPath
    >>> arc = Piece.arc(np.zeros(3), np.array([2.0, 0, 0]), 1.0, np.array([0, 0, 1.0]))
    >>> arc_spacing(ToolPath((arc,)), 0.01)
    0.4
    """
    radii = [p.radius for p in path.pieces if p.center is not None]
    return math.sqrt(8.0 * min(radii) * chord_error) if radii else math.inf


@dataclass(frozen=True)
class SampledPath:
    """One path goal's path as a polyline, in the world or on the screen.

    Attributes
    ----------
    goal : int
        The goal's index.
    s : (m,) array
        Arc length of each sample (scene units), increasing from 0 to the path's length.
    points : (m, d) array
        The samples (d = 3: world x, y, z, or screen x px, y px, near).
    ink : (m - 1,) bool array
        Whether the pen is down from each sample to the next.
    """

    goal: int
    s: np.ndarray
    points: np.ndarray
    ink: np.ndarray

    @classmethod
    def of(cls, goal: int, path, spacing: float) -> SampledPath:
        """``path`` (a ToolPath) of goal ``goal`` sampled by :func:`piece_samples` at ``spacing``."""
        s = piece_samples(path, spacing)
        return cls(goal, s, path.points(s), path.inked(0.5 * (s[:-1] + s[1:])))

    def mapped(self, points: np.ndarray) -> SampledPath:
        """The same samples at other coordinates (m, d'): e.g. projected on the screen (the camera
        is affine, so a point between two samples maps to the point between theirs)."""
        return SampledPath(self.goal, self.s, np.asarray(points, dtype=float), self.ink)

    @property
    def length(self) -> float:
        """The path's arc length."""
        return float(self.s[-1])

    def at(self, s: np.ndarray) -> np.ndarray:
        """(k, d) the points at arc lengths ``s`` (k,), linear between samples (clipped to the path)."""
        s = np.minimum(np.maximum(np.asarray(s, dtype=float), 0.0), self.s[-1])  # (np.clip's values, in half its time)
        i = np.minimum(np.maximum(np.searchsorted(self.s, s, side="right") - 1, 0), len(self.s) - 2)
        step = self.s[i + 1] - self.s[i]
        t = np.divide(s - self.s[i], step, out=np.zeros_like(s), where=step > 0)[:, None]
        return self.points[i] + t * (self.points[i + 1] - self.points[i])

    def between(self, lo: float, hi: float) -> np.ndarray:
        """(k, d) the pen-down part of the path from arc length ``lo`` to ``hi`` as one polyline,
        a row of NaN between its separate runs (where the pen is up); (0, d) when there is none.

        The rows of the pen-down segments wholly inside are those of the whole path's
        (:attr:`_pen_down`, made once): only the first row and the last are placed here (a video's
        frames ask for the ink and the path ahead every frame)."""
        if not lo < hi:
            return np.zeros((0, self.points.shape[1]))
        segments, end_rows, rows = self._pen_down
        first = int(np.searchsorted(segments, np.searchsorted(self.s[1:], lo, side="right")))  # ends past lo
        stop = int(np.searchsorted(segments, np.searchsorted(self.s[:-1], hi, side="left")))  # starts before hi
        if stop <= first:
            return np.zeros((0, self.points.shape[1]))
        head, tail = self.at(np.array([max(self.s[segments[first]], lo), min(self.s[segments[stop - 1] + 1], hi)]))
        return np.concatenate([head[None], rows[end_rows[first] : end_rows[stop - 1]], tail[None]])

    @cached_property
    def _pen_down(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The whole pen-down polyline: its segments (q,; the sample each starts at), the row of
        each one's end (q,) in the rows (k, d; a run's start, a NaN row before every run but the
        first)."""
        d = self.points.shape[1]
        segments = np.flatnonzero(self.ink)
        if not len(segments):
            return segments, segments, np.zeros((0, d))
        starts = np.ones(len(segments), dtype=bool)
        starts[1:] = np.diff(segments) != 1
        first = self.at(self.s[segments[starts]])  # where each run starts
        ends = self.at(self.s[segments + 1])  # where each segment ends
        rows = np.concatenate([np.full((int(starts.sum()), d), np.nan), first, ends])
        slot = np.concatenate(
            [3 * np.flatnonzero(starts), 3 * np.flatnonzero(starts) + 1, 3 * np.arange(len(segments)) + 2]
        )
        rows, slot = rows[1:], slot[1:]  # no break before the first run
        end_rows = np.arange(len(segments)) + 2 * np.cumsum(starts) - 1
        return segments, end_rows, rows[np.argsort(slot, kind="stable")]


def sampled_paths(goals, spacing_of) -> list[SampledPath]:
    """Every path goal's path sampled (:meth:`SampledPath.of`), in goal order; ``spacing_of`` maps
    a ToolPath to the spacing its arcs are split at."""
    return [
        SampledPath.of(k, g.path, spacing_of(g.path))
        for k, g in enumerate(goals)
        if getattr(g, "path", None) is not None
    ]


def path_progress(goal: np.ndarray, path_s: np.ndarray | None, goals: int) -> np.ndarray:
    """(F, G) the arc length done along each goal's path by each frame: the farthest ``path_s``
    reached on that goal's frames up to the frame (0 before its first; a goal left behind keeps
    what it reached).

    Parameters
    ----------
    goal : (F,) int array
        Each frame's goal (``Trajectory.goal``).
    path_s : (F,) array or None
        ``Trajectory.path_s``: the arc length done on frames that follow a path, NaN elsewhere;
        None when no goal is a path (then nothing is done anywhere).
    goals : int
        G, the number of goals.

    >>> path_progress(np.array([0, 1, 1, 1, 2]), np.array([np.nan, 0.0, 0.5, 0.4, np.nan]), 3).tolist()
    [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.5, 0.0], [0.0, 0.5, 0.0], [0.0, 0.5, 0.0]]
    """
    goal = np.asarray(goal)
    done = np.zeros((len(goal), goals))
    if path_s is None:
        return done
    path_s = np.asarray(path_s, dtype=float)
    for g in range(goals):
        reached = np.where((goal == g) & np.isfinite(path_s), path_s, 0.0)
        done[:, g] = np.maximum.accumulate(np.maximum(reached, 0.0)) if len(goal) else reached
    return done


@dataclass(frozen=True)
class PathView:
    """What a frame shows of one sampled path: its ink up to ``done`` and, if ``ahead``, the rest faintly.

    Attributes
    ----------
    path : SampledPath
    done : float
        Arc length inked.
    ahead : bool
        Whether the path still to do is shown.
    """

    path: SampledPath
    done: float
    ahead: bool

    def ink(self) -> np.ndarray:
        """(k, d) the inked polyline (NaN rows between runs)."""
        return self.path.between(0.0, self.done)

    def rest(self) -> np.ndarray:
        """(k, d) the pen-down path still to do (NaN rows between runs); none unless ``ahead``."""
        if not self.ahead:
            return np.zeros((0, self.path.points.shape[1]))
        return self.path.between(self.done, np.inf)


def frame_paths(paths: list[SampledPath], done: np.ndarray, goal: int, *, ahead: bool = True) -> tuple[PathView, ...]:
    """Each sampled path at a frame: its ink up to ``done`` (G,: the frame's row of
    :func:`path_progress`), and the rest faintly for the frame's goal ``goal`` (when ``ahead``)."""
    return tuple(PathView(p, float(done[p.goal]), ahead and p.goal == goal) for p in paths)


def ribbon(polyline: np.ndarray, width: float, lift: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """A screen polyline (k, 3: x px, y px, near; NaN rows break it) as a ribbon of triangles
    ``width`` pixels wide, for a z-buffer: each segment one quad, grown by half the width at both
    ends (so that corners close), its nearness raised by ``lift``.

    Returns
    -------
    points : (4 q, 3) array
    faces : (2 q, 3) int array
        Indices into ``points``; q is the number of segments of nonzero length.

    >>> pts, faces = ribbon(np.array([[0.0, 0, 1], [4, 0, 1]]), 2.0, 0.5)
    >>> pts.tolist(), faces.tolist()
    ([[-1.0, 1.0, 1.5], [-1.0, -1.0, 1.5], [5.0, -1.0, 1.5], [5.0, 1.0, 1.5]], [[0, 1, 2], [0, 2, 3]])
    """
    a, b = polyline[:-1], polyline[1:]
    step = b[:, :2] - a[:, :2]
    length = np.linalg.norm(step, axis=1)
    ok = np.isfinite(length) & (length > 0)
    a, b, step, length = a[ok], b[ok], step[ok], length[ok]
    along = step / length[:, None] * (0.5 * width)
    across = np.column_stack([-along[:, 1], along[:, 0]])
    start, end = a[:, :2] - along, b[:, :2] + along
    xy = np.stack([start + across, start - across, end - across, end + across], axis=1)  # (q, 4, 2)
    near = np.repeat(np.column_stack([a[:, 2], b[:, 2]]), 2, axis=1) + lift  # a, a, b, b
    points = np.concatenate([xy, near[..., None]], axis=-1).reshape(-1, 3)
    base = 4 * np.arange(len(a))[:, None]
    faces = np.concatenate([base + [0, 1, 2], base + [0, 2, 3]], axis=1).reshape(-1, 3)
    return points, faces.astype(int)


def path_normal(points: np.ndarray, toward: np.ndarray) -> np.ndarray:
    """(3,) the unit normal of the plane a ribbon of ink along ``points`` (m, 3) lies in: the
    normal of the points' best-fit plane (a board's, a table's), or, for points on a line, that of
    the plane through the line that faces ``toward`` (3,; the camera) the most. Its sign is
    the one toward ``toward``.

    >>> (path_normal(np.array([[0.0, 0, 1], [1, 0, 1], [1, 1, 1]]), np.array([0.2, 0, -1.0])) + 0.0).tolist()
    [0.0, 0.0, -1.0]
    >>> np.round(path_normal(np.array([[0.0, 0, 0], [1, 0, 0]]), np.array([1.0, 1, 0])), 12).tolist()
    [0.0, 1.0, 0.0]
    """
    toward = np.asarray(toward, dtype=float)
    centered = np.asarray(points, dtype=float) - np.mean(points, axis=0)
    _, spread, axes = np.linalg.svd(centered, full_matrices=True)
    if len(spread) > 1 and spread[1] > 1e-9 * max(spread[0], 1e-300):
        normal = axes[2]
    else:  # a line (or a point): the plane through it most square to the camera
        along = axes[0]
        normal = toward - (toward @ along) * along
        if np.linalg.norm(normal) < 1e-9:
            normal = axes[1]
    normal = normal / np.linalg.norm(normal)
    return -normal if normal @ toward < 0 else normal


def joined(polylines) -> np.ndarray:
    """Polylines (each (k, d)) as one, a NaN row between them; (0, 3) for none."""
    parts = [p for p in polylines if len(p)]
    if not parts:
        return np.zeros((0, 3))
    d = parts[0].shape[1]
    out: list[np.ndarray] = []
    for p in parts:
        out += [np.full((1, d), np.nan), p] if out else [p]
    return np.concatenate(out)


__all__ = [
    "PathView",
    "SampledPath",
    "arc_spacing",
    "frame_paths",
    "joined",
    "path_normal",
    "path_progress",
    "piece_samples",
    "ribbon",
    "sampled_paths",
]
