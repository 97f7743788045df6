"""Capsules fitted to a link's mesh: 1 to 3 capsules that enclose every vertex, claiming little space outside it.

The fit (:func:`fit_capsules`) is deterministic: the same vertices and triangles give the same
capsules, bit for bit. For one capsule it starts from the principal axes of the points' convex hull,
then searches the axis direction (a pattern search on the sphere of directions, the step halved down
to :data:`DIRECTION_TOL`); for each direction the axis line passes through the centre of the
smallest circle holding the points seen along it, and the radius is chosen by a 1-D search that
minimises the capsule's volume (a larger radius buys shorter ends). For 2 and 3 capsules the points
are cut by planes across one of the principal axes or of the mesh frame's axes (a CAD part is often
square to its link's frame), at :data:`CUTS` evenly spaced places, each piece fitted alone. Of one
capsule and the best cuts found, the fit kept is the one of least volume *outside the points'
convex hull* (counted once where capsules overlap, :class:`_Outside`) among those of at most
:data:`VOLUME_ALLOWANCE` times the least total volume found: least volume alone keeps one fat
capsule where two or three hug the link (VAMP's Panda wrist: its ``panda_link7`` capsule reached
2.4 cm below its flange where ``panda_link5`` comes within 2 cm, and 91 of MotionBenchMaker's 700
goals were refused for it); the allowance bounds what the closer fit costs in volume.
Each kept capsule is then refined (:func:`_refined`): its axis line moved off the smallest circle's
centre and tilted with it, each line with its own best radius, by Nelder and Mead's simplex (about
1 % less volume on the onboarding robots, 6-9 % on some wrists).
Then a cut's capsules are shrunk where a neighbour already holds their points (:func:`_shrunk`):
the mesh's triangles, cut small (:func:`_small_triangles`) and split by the cut's planes, each go
to the capsule that holds them deepest, and each capsule is fitted again to what it owns when that
is smaller: a slab's capsule reaches past its planes with its rounded ends, so the cut bends to the
link (1 to 3 % less volume on the onboarding robots, 3 % on a flange).

Only convex hulls' vertices are fitted: a capsule, the points within r of a segment, is convex (the
sum of a segment and a ball, both convex), so a capsule that holds a hull's vertices holds every
convex combination of them, which is the hull and every point and triangle inside it. A piece's
capsule is searched on its hull's vertices; where the plane cuts the mesh's edges, only the
vertices of those crossings' polygon in the plane are kept (the same reason). On a mesh of more
than :data:`SEARCH_POINTS` points the cuts are weighed on fewer points (the hull's vertices and one
point a grid cell, :func:`_search_points`): that only chooses the cuts; each kept piece is then
fitted to all its points, and its radius measured to every one of them.

Each capsule holds its piece's vertices and the points where the mesh's edges cross the piece's
cutting planes, so the pieces' capsules together hold every triangle, not only the vertices. The
ends are rounded to :data:`DECIMALS` places and the radius then measured from the rounded segment and
rounded up: the numbers written hold every vertex as written. A point on a cutting plane belongs to
both pieces, so an edge that ends there is held on both sides.

A mesh of more than :data:`LARGE_POINTS` points (a 65 MB STL of random triangles has 3.9 million)
is searched on one point a grid cell and its rows are handled :data:`CHUNK` at a time
(:func:`_fit_large`): its time grows with its rows, no step holds Ctrl-C up for long, and every
radius is still measured to every vertex and edge crossing. Pure core: numpy, scipy's convex hull
(imported at the first fit).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

DECIMALS = 6
"""Places kept of each end and radius (in the mesh's unit: 1 um for metres)."""
CUTS = 16
"""A piece is cut at CUTS - 1 evenly spaced places along each principal axis."""
VOLUME_ALLOWANCE = 1.1
"""The fit kept is the one of least volume outside the hull among the candidates of at most this
many times the least volume found (:func:`_search`)."""
OUTSIDE_GRID = 32
"""Cells along the longest side of the grid that weighs a fit's volume outside the hull (:class:`_Outside`)."""
DIRECTION_TOL = 0.004
"""The direction search stops when its step falls below this angle (radians)."""
COARSE_AXES = 1
"""Principal axes tried per piece when cuts are weighed (the kept pieces then try all three and search)."""
TRIED = 3
"""For each count of capsules, the cuts of least coarse volume fitted in full, and as many of least
coarse volume outside the hull (:func:`_best_splits`)."""
DIAGONALS = False
"""Also cut across the bisectors of each two principal axes (measured: at most 2.5 % less volume on
the onboarding robots, for about twice the fit time; off)."""
SEARCH_POINTS = 2000
"""A mesh of more points is weighed for its cuts on fewer (:func:`_search_points`); the kept pieces
are fitted to every point."""
SEARCH_GRID = 48
"""Cells along the mesh's longest side in :func:`_search_points`."""
RADII = 24
"""Radii tried per direction (then refined once around the best)."""
REFINE_EVALUATIONS = 120
"""Capsules tried by :func:`_refined` for each kept piece."""
REFINE_STEP = 0.05
"""Its first steps: radians of tilt, and radii of offset of the axis line."""
LARGE_POINTS = 100_000
"""A mesh of more distinct points (2.5 times the largest link of the onboarding robots, the
SO-101's 39,727) is searched on stand-ins (:func:`_fit_large`): its time then grows with its rows,
in bounded chunks. Below it the longest step is a convex hull of at most this many points (about
a second when every point is on the hull)."""
LARGE_ROWS = 600_000
"""A mesh of more vertex rows goes to :func:`_fit_large` without sorting them first."""
CHUNK = 200_000
"""Rows a step of :func:`_fit_large` handles at once (a small fraction of a second: Ctrl-C waits no longer)."""
LARGE_GRID = 32
"""Cells along the longest side of the grid of :func:`_stand_ins`."""
SHRINK_ROUNDS = 4
"""Rounds of :func:`_shrunk` (each gives the pieces' points to the capsules that hold them deepest, then fits again)."""
SHRINK_TRIANGLES = 200_000
"""At most this many small triangles in :func:`_small_triangles` (a mesh of more keeps its cut's capsules as fitted)."""
SHRINK_GRID = 12
""":func:`_small_triangles` cuts triangles to edges of at most the mesh's longest side over this."""


@dataclass(frozen=True)
class FittedCapsule:
    """A capsule: every point within ``radius`` of the segment from ``start`` to ``end`` (the mesh's frame and unit)."""

    start: np.ndarray
    end: np.ndarray
    radius: float

    @property
    def volume(self) -> float:
        """pi r^2 L + 4/3 pi r^3.

        >>> round(FittedCapsule(np.zeros(3), np.array([0.0, 0, 2]), 1.0).volume, 4)
        10.472
        """
        return capsule_volume(float(np.linalg.norm(self.end - self.start)), self.radius)


def capsule_volume(length: float, radius: float) -> float:
    """The volume of a capsule of segment ``length`` and ``radius``."""
    return math.pi * radius * radius * length + 4.0 / 3.0 * math.pi * radius**3


def segment_distances(points: np.ndarray, start: np.ndarray, end: np.ndarray) -> np.ndarray:
    """(N,) distance of each point (N, 3) to the segment from ``start`` to ``end``.

    >>> segment_distances(np.array([[0.0, 1, 0], [0, 0, 3]]), np.zeros(3), np.array([0.0, 0, 1])).tolist()
    [1.0, 2.0]
    """
    ab = end - start
    length2 = float(ab @ ab)
    t = np.zeros(len(points)) if length2 == 0.0 else np.clip((points - start) @ ab / length2, 0.0, 1.0)
    return np.asarray(np.linalg.norm(points - (start + t[:, None] * ab), axis=1))


def fit_capsules(vertices: np.ndarray, faces: np.ndarray | None = None, max_capsules: int = 3) -> list[FittedCapsule]:
    """1 to ``max_capsules`` capsules that together hold every vertex (and every triangle of
    ``faces``), of the least volume the search finds; none for no vertices.

    Parameters
    ----------
    vertices : (N, 3) array
        The mesh's points (any unit; the capsules are in it).
    faces : (F, 3) int array, optional
        Its triangles: the points where their edges cross a cut are held too.
    max_capsules : int
        1, 2 or 3.

    Returns
    -------
    list of FittedCapsule
        Ends rounded to :data:`DECIMALS` places, radii rounded up: every vertex lies within a
        radius of its capsule's segment.

    >>> box = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 4)], dtype=float)
    >>> [(c.start.tolist(), c.end.tolist(), c.radius) for c in fit_capsules(box, max_capsules=1)]
    [([0.5, 0.5, 0.106801], [0.5, 0.5, 3.893199], 0.715127)]

    Without triangles only the vertices count: the box's two ends are two capsules.

    >>> len(fit_capsules(box))
    2
    """
    vertices = np.asarray(vertices, dtype=float).reshape(-1, 3)
    if len(vertices) > LARGE_ROWS:  # not even sorted (np.unique): bounded steps from the start
        return _fit_large(vertices, faces, max_capsules)
    points, inverse = np.unique(vertices, axis=0, return_inverse=True)
    if len(points) > LARGE_POINTS:
        return _fit_large(vertices, faces, max_capsules)
    if not len(points):
        return []
    points, triangles, edges = _mesh(points, inverse, faces)
    return _finished(points, triangles, edges, _search(points, edges, max_capsules))


def candidate_fits(
    vertices: np.ndarray, faces: np.ndarray | None = None, max_capsules: int = 3
) -> tuple[list[list[FittedCapsule]], int]:
    """Every set of capsules :func:`fit_capsules` chooses among, each finished as the chosen one is
    (refined, a cut's shrunk, rounded), and the index of the one it keeps: for the benchmarks that
    weigh the choice (``benchmarks/mbm_fit_candidates.py``). Meshes of at most
    :data:`LARGE_POINTS` distinct points.

    >>> box = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 4)], dtype=float)
    >>> sets, kept = candidate_fits(box)
    >>> [len(c) for c in sets][:1], len(sets[kept])
    ([1], 2)
    """
    points, inverse = np.unique(np.asarray(vertices, dtype=float).reshape(-1, 3), axis=0, return_inverse=True)
    if not 0 < len(points) <= LARGE_POINTS:
        raise ValueError(f"candidate_fits takes 1 to {LARGE_POINTS} distinct points, not {len(points)}")
    points, triangles, edges = _mesh(points, inverse, faces)
    found, outside = candidates(points, edges, max_capsules)
    return [_finished(points, triangles, edges, _refined_pieces(points, edges, c)) for c in found], _chosen(
        found, outside
    )


def _mesh(
    points: np.ndarray, inverse: np.ndarray, faces: np.ndarray | None
) -> tuple[np.ndarray, np.ndarray | None, np.ndarray]:
    """The distinct points, their triangles (indices into them, or None) and their edges (E, 2, 3) each once."""
    triangles = None if faces is None else inverse.reshape(-1)[np.asarray(faces, dtype=np.int64)].reshape(-1, 3)
    return points, triangles, _edges(points, triangles)


def _finished(
    points: np.ndarray,
    triangles: np.ndarray | None,
    edges: np.ndarray,
    chosen: list[tuple[Fit, tuple[float, float], np.ndarray]],
) -> list[FittedCapsule]:
    """The chosen capsules of the distinct ``points`` (their triangles and edges) as written: a cut's
    shrunk (:func:`_shrunk`, when the mesh is small enough), then each rounded (:func:`_rounded`)."""
    if len(chosen) > 1 and (triangles is None or len(triangles) <= SHRINK_TRIANGLES):
        return [_rounded(fit, held) for fit, held in _shrunk(points, triangles, chosen)]
    return [_rounded(fit, _slab(points, edges, axis, lo, hi)) for fit, (lo, hi), axis in chosen]


def _search(
    points: np.ndarray, edges: np.ndarray, max_capsules: int
) -> list[tuple[Fit, tuple[float, float], np.ndarray]]:
    """The capsules chosen for the (distinct) ``points`` and ``edges`` (E, 2, 3): each fit with the
    slab (lo, hi) along its axis that it holds (the whole range for one).

    Of the candidates (:func:`candidates`) the one of least volume outside the points' convex hull
    (:class:`_Outside`) is kept, among those of at most :data:`VOLUME_ALLOWANCE` times the least
    volume found (on a tie, the lesser volume, then the first: one capsule before two, two before
    three); each of its capsules is then refined (:func:`_refined`)."""
    found, outside = candidates(points, edges, max_capsules)
    return _refined_pieces(points, edges, found[_chosen(found, outside)])


def _chosen(found: list[list[tuple[Fit, tuple[float, float], np.ndarray]]], outside: _Outside) -> int:
    """The index of the candidate :func:`_search` keeps (its docstring says which)."""
    volumes = [sum(p[0][0] for p in pieces) for pieces in found]
    least = min(volumes)
    kept = [k for k, volume in enumerate(volumes) if volume <= VOLUME_ALLOWANCE * least]
    return min(kept, key=lambda k: (outside.volume([p[0] for p in found[k]]), volumes[k], k))


def _refined_pieces(
    points: np.ndarray, edges: np.ndarray, pieces: list[tuple[Fit, tuple[float, float], np.ndarray]]
) -> list[tuple[Fit, tuple[float, float], np.ndarray]]:
    """Each piece's capsule refined (:func:`_refined`) on its slab's hull, with its slab and axis."""
    return [
        (_refined(hull_points(_slab(points, edges, axis, lo, hi)), fit), (lo, hi), axis)
        for fit, (lo, hi), axis in pieces
    ]


def candidates(
    points: np.ndarray, edges: np.ndarray, max_capsules: int
) -> tuple[list[list[tuple[Fit, tuple[float, float], np.ndarray]]], _Outside]:
    """The sets of capsules :func:`_search` chooses among, and the grid it weighs them on.

    One capsule and, for 2 and 3, the :data:`TRIED` cuts of least coarse volume and the
    :data:`TRIED` of least coarse volume outside the hull (among those within
    :data:`VOLUME_ALLOWANCE` of the least coarse volume), each piece fitted in full (not refined);
    each capsule with the slab (lo, hi) along its axis that it holds. Public for the benchmarks
    that weigh each candidate (``benchmarks/mbm_fit_candidates.py``)."""
    axes = principal_axes(points)
    one = (_piece_fit(points, fine=True), (-np.inf, np.inf), axes[0])
    search, search_edges = (
        (points, edges) if len(points) <= SEARCH_POINTS else (_search_points(points), np.zeros((0, 2, 3)))
    )
    outside = _Outside(search)
    found = [[one]]
    counts = range(2, max(1, min(int(max_capsules), 3)) + 1)
    splits = _best_splits(search, search_edges, cut_axes(axes), tuple(counts), outside) if len(counts) else {}
    for count in counts:
        for _, cuts, axis in splits.get(count, []):
            found.append(
                [(_piece_fit(_slab(points, edges, axis, lo, hi), fine=True), (lo, hi), axis) for lo, hi in cuts]
            )
    return found, outside


def _shrunk(
    points: np.ndarray, triangles: np.ndarray | None, chosen: list[tuple[Fit, tuple[float, float], np.ndarray]]
) -> list[tuple[Fit, np.ndarray]]:
    """The cut's capsules shrunk where their neighbours already hold their points: each capsule and
    the points it must hold (to measure its radius from), capsules left with none dropped.

    The mesh is split into atoms (:func:`_atoms`: each triangle's part in each slab, or each point
    without triangles), each to be held whole by one capsule, first its slab's. Each round gives
    every atom to the capsule that holds it deepest (its farthest point's distance over the radius,
    among the capsules that hold all its points; its owner's if none other does), then fits each
    capsule again to what it owns (:func:`_piece_fit`, :func:`_refined`) and keeps the new one when
    it is smaller, for at most :data:`SHRINK_ROUNDS` rounds. A slab's capsule reaches past its
    planes (its rounded ends), so the points there that the next capsule holds are given away and
    the cut bends to the link's shape; every atom stays held whole by its owner, so the capsules
    still hold every vertex and triangle, and the total volume never grows."""
    fits = [fit for fit, _, _ in chosen]
    atom_points, starts, owner = _atoms(points, triangles, chosen[0][2], [slab for _, slab, _ in chosen])
    for _ in range(SHRINK_ROUNDS):
        depth = np.stack([np.maximum.reduceat(_reach(atom_points, fit), starts) for fit in fits])  # (k, atoms)
        allowed = depth <= 1.0 + 1e-9
        allowed[owner, np.arange(len(owner))] = True
        moved = np.argmin(np.where(allowed, depth, np.inf), axis=0)
        changed = False
        for k in range(len(fits)):
            if not np.array_equal(moved == k, owner == k) and np.any(moved == k):
                hull = hull_points(_owned(atom_points, starts, moved == k))
                better = _refined(hull, _piece_fit(hull, fine=True, hulled=True))
                if better[0] < fits[k][0] * (1.0 - 1e-9):
                    fits[k], changed = better, True
        owner = moved
        if not changed:
            break
    return [(fits[k], _owned(atom_points, starts, owner == k)) for k in range(len(fits)) if np.any(owner == k)]


def _reach(points: np.ndarray, fit: Fit) -> np.ndarray:
    """(N,) each point's distance from the capsule's segment over its radius (inf beyond a radius 0)."""
    distance = segment_distances(points, fit[1], fit[2])
    if fit[3] > 0.0:
        return distance / fit[3]
    return np.where(distance > 0.0, np.inf, 0.0)


def _owned(atom_points: np.ndarray, starts: np.ndarray, mine: np.ndarray) -> np.ndarray:
    """The points of the atoms marked in ``mine`` (atoms are the runs of ``atom_points`` from ``starts``)."""
    sizes = np.diff(np.append(starts, len(atom_points)))
    return np.asarray(atom_points[np.repeat(mine, sizes)])


def _atoms(
    points: np.ndarray, triangles: np.ndarray | None, axis: np.ndarray, slabs: list[tuple[float, float]]
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The pieces of the mesh that a capsule must hold whole: each small triangle's part in each
    slab (lo <= t <= hi along ``axis``; the triangles cut to :func:`_small_triangles`): its corners in
    the slab and where its edges cross the slab's planes, the corners of that part (a convex
    polygon: a capsule that holds them holds it); without triangles, each point. Returns the atoms'
    points in runs (M, 3), where each run starts (A,), and each atom's slab (A,).

    >>> corners = np.array([[0.0, 0, 0], [2, 0, 0], [0, 2, 0]])
    >>> pts, starts, slab = _atoms(corners, None, np.array([1.0, 0, 0]), [(-np.inf, 1.0), (1.0, np.inf)])
    >>> starts.tolist(), slab.tolist()  # without triangles: each point, in the first slab that holds it
    ([0, 1, 2], [0, 1, 0])
    >>> pts, starts, slab = _atoms(corners, np.array([[0, 1, 2]]), np.array([1.0, 0, 0]), [(-np.inf, 1.0), (1.0, np.inf)])
    >>> len(starts), np.bincount(slab).tolist()  # 289 small triangles (17 steps of 2/17), the 17 between x = 16/17 and 18/17 on both sides
    (306, [225, 81])
    """
    if triangles is None:
        t = points @ axis
        slab = np.array([next(k for k, (lo, hi) in enumerate(slabs) if lo <= x <= hi) for x in t], dtype=np.int64)
        return points, np.arange(len(points)), slab
    corners = _small_triangles(points, triangles)  # (T, 3, 3)
    tt = corners @ axis  # (T, 3)
    ids, rows = [], []
    for s, (lo, hi) in enumerate(slabs):
        key = s * len(corners) + np.arange(len(corners))
        inside = (tt >= lo) & (tt <= hi)
        for c in range(3):
            ids.append(key[inside[:, c]])
            rows.append(corners[inside[:, c], c])
        for i, j in ((0, 1), (1, 2), (2, 0)):
            ta, tb = tt[:, i], tt[:, j]
            for plane in (lo, hi):
                if np.isfinite(plane):
                    cross = (np.minimum(ta, tb) < plane) & (np.maximum(ta, tb) > plane)
                    a, b = corners[cross, i], corners[cross, j]
                    f = (plane - ta[cross]) / (tb[cross] - ta[cross])
                    ids.append(key[cross])
                    rows.append(a + f[:, None] * (b - a))
    key = np.concatenate(ids)
    order = np.argsort(key, kind="stable")
    key = key[order]
    starts = np.flatnonzero(np.r_[True, key[1:] != key[:-1]])
    return np.concatenate(rows)[order], starts, key[starts] // len(corners)


def _small_triangles(points: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """(T, 3, 3) the triangles' corners, each triangle cut into n^2 alike ones (n steps along each
    edge) so that no edge is longer than the points' longest side over :data:`SHRINK_GRID` (longer
    where that would make more than :data:`SHRINK_TRIANGLES`): a CAD mesh's long thin triangles
    would otherwise tie its capsules together. Every point of a triangle is in one of its pieces.

    >>> len(_small_triangles(np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]]), np.array([[0, 1, 2]])))  # 17 steps of 1/12
    289
    """
    corners = points[triangles]
    side = float((points.max(axis=0) - points.min(axis=0)).max())
    longest = np.max(np.linalg.norm(corners - np.roll(corners, 1, axis=1), axis=2), axis=1)
    step = side / SHRINK_GRID if side > 0.0 else 1.0
    n = np.maximum(np.ceil(longest / step), 1.0)
    while float(np.sum(n * n)) > SHRINK_TRIANGLES and n.max() > 1:
        step *= 1.5
        n = np.maximum(np.ceil(longest / step), 1.0)
    out = [corners[n == 1]]
    for m in np.unique(n[n > 1]).astype(int):
        out.append(np.einsum("skc,tcd->tskd", _pieces(m), corners[n == m]).reshape(-1, 3, 3))
    return np.concatenate(out)


@functools.lru_cache(maxsize=64)
def _pieces(n: int) -> np.ndarray:
    """(n^2, 3, 3) the barycentric corners of the n^2 triangles that cut a triangle n steps an edge."""
    rows = []
    for i in range(n):
        for j in range(n - i):
            rows.append([(i, j), (i + 1, j), (i, j + 1)])
            if i + j < n - 1:
                rows.append([(i + 1, j), (i + 1, j + 1), (i, j + 1)])
    grid = np.array(rows, dtype=float) / n  # (n^2, 3, 2): weights of the second and third corner
    return np.concatenate([1.0 - grid.sum(axis=2, keepdims=True), grid], axis=2)


class _Outside:
    """The volume of a set of capsules outside the convex hull of ``points``, on a grid: the
    centres of the cells of a grid of :data:`OUTSIDE_GRID` cells along the longest side of the
    points' box widened by half that side each way, outside the hull (a capsule's volume inside
    the hull is the link's own; outside it is space the capsules claim that the link does not, so
    a fat capsule's rounded ends and the gaps it bridges count, and two capsules overlapping
    inside the hull cost nothing). Flat or collinear points (no hull) count nothing: the fit is
    then chosen by volume alone. Only the choice among candidate fits sees it."""

    def __init__(self, points: np.ndarray) -> None:
        self.cells, self.cell_volume = np.zeros((0, 3)), 0.0
        if len(points) < 5:
            return
        from scipy.spatial import ConvexHull, QhullError

        try:
            hull = ConvexHull(points)
        except (QhullError, ValueError):
            return
        low, high = points.min(axis=0), points.max(axis=0)
        side = float((high - low).max())
        cell = 2.0 * side / OUTSIDE_GRID
        ticks = [np.arange(low[k] - side / 2.0 + cell / 2.0, high[k] + side / 2.0, cell) for k in range(3)]
        grid = np.stack(np.meshgrid(*ticks, indexing="ij"), axis=-1).reshape(-1, 3)
        inside = np.arange(len(grid))
        for k in range(0, len(hull.equations), 64):  # a fine mesh's hull has thousands of faces: most cells leave early
            planes = hull.equations[k : k + 64]
            inside = inside[(grid[inside] @ planes[:, :3].T + planes[:, 3]).max(axis=1) <= 0.0]
        outside = np.ones(len(grid), dtype=bool)
        outside[inside] = False
        self.cells = grid[outside]
        self.cell_volume = cell**3

    def held(self, fit: Fit) -> np.ndarray:
        """(M,) bool: which of the outside cells' centres the capsule ``fit`` holds."""
        return segment_distances(self.cells, fit[1], fit[2]) <= fit[3]

    def volume(self, fits: list[Fit]) -> float:
        """The capsules' union's volume outside the hull (each cell counted once)."""
        held = np.zeros(len(self.cells), dtype=bool)
        for fit in fits:
            held |= self.held(fit)
        return float(np.count_nonzero(held)) * self.cell_volume


def _fit_large(vertices: np.ndarray, faces: np.ndarray | None, max_capsules: int) -> list[FittedCapsule]:
    """:func:`fit_capsules` of a mesh of more than :data:`LARGE_POINTS` points, in time and
    memory bounded by the rows and every step a bounded chunk (:data:`CHUNK` rows: an interrupt is
    answered between two): the capsules are searched on stand-ins (:func:`_stand_ins`: one point a
    grid cell, without sorting all the rows), then each capsule's radius
    is measured to every vertex of its piece and every point where an edge crosses its planes, so
    every vertex and triangle is held, as in the exact fit (up to a grid cell wider)."""
    stand_ins = _stand_ins(vertices)
    faces = np.zeros((0, 3), dtype=np.int64) if faces is None else np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    out = []
    for fit, (lo, hi), axis in _search(stand_ins, np.zeros((0, 2, 3)), max_capsules):
        start, end = _rounded_ends(fit)
        reach = 0.0
        for k in range(0, len(vertices), CHUNK):
            chunk = vertices[k : k + CHUNK]
            t = chunk @ axis
            inside = chunk[(t >= lo) & (t <= hi)]
            if len(inside):
                reach = max(reach, float(segment_distances(inside, start, end).max()))
        for k in range(0, len(faces), CHUNK):
            corners = vertices[faces[k : k + CHUNK]]  # (F, 3, 3)
            for i, j in ((0, 1), (1, 2), (2, 0)):
                a, b = corners[:, i], corners[:, j]
                ta, tb = a @ axis, b @ axis
                for plane in (lo, hi):
                    if np.isfinite(plane):
                        cross = (np.minimum(ta, tb) < plane) & (np.maximum(ta, tb) > plane)
                        if cross.any():
                            s = (plane - ta[cross]) / (tb[cross] - ta[cross])
                            at = a[cross] + s[:, None] * (b[cross] - a[cross])
                            reach = max(reach, float(segment_distances(at, start, end).max()))
        out.append(FittedCapsule(start, end, _rounded_up(reach)))
    return out


def _stand_ins(points: np.ndarray) -> np.ndarray:
    """Fewer points to search a large mesh's capsules on, chunk by chunk (:data:`CHUNK` rows): in
    each cell of a grid of :data:`LARGE_GRID` cells along the longest side, the point farthest from
    the points' middle (the first of equals), in the points' order. No convex hull: a round mesh's
    holds nearly every point, and qhull cannot be interrupted.

    >>> grid = np.array([[x, y, z] for x in range(100) for y in range(100) for z in range(100)], dtype=float)
    >>> stand_ins = _stand_ins(grid)
    >>> len(stand_ins) <= LARGE_GRID ** 3, [0.0, 0.0, 0.0] in stand_ins.tolist()
    (True, True)
    """
    starts = range(0, len(points), CHUNK)
    low = np.min([points[k : k + CHUNK].min(axis=0) for k in starts], axis=0)
    high = np.max([points[k : k + CHUNK].max(axis=0) for k in starts], axis=0)
    middle, cell = (low + high) / 2.0, float((high - low).max()) / LARGE_GRID or 1.0
    keys, reach, rows = [], [], []
    for k in starts:
        chunk = points[k : k + CHUNK]
        cells = np.minimum(np.floor((chunk - low) / cell).astype(np.int64), LARGE_GRID - 1)  # the far side in the last
        key = (cells[:, 0] * LARGE_GRID + cells[:, 1]) * LARGE_GRID + cells[:, 2]
        far = -np.einsum("ij,ij->i", chunk - middle, chunk - middle)
        keys.append(key)
        reach.append(far)
        rows.append(np.arange(k, k + len(chunk)))
        first = _first_per_key(keys[-1], reach[-1])  # each chunk's candidates only: the rest is dropped
        keys[-1], reach[-1], rows[-1] = keys[-1][first], reach[-1][first], rows[-1][first]
    key, far, row = np.concatenate(keys), np.concatenate(reach), np.concatenate(rows)
    return np.asarray(points[np.sort(row[_first_per_key(key, far)])])


def _first_per_key(key: np.ndarray, rank: np.ndarray) -> np.ndarray:
    """For each distinct key, the index of its least rank (the first of equals).

    >>> _first_per_key(np.array([5, 3, 5, 3]), np.array([0.0, 2, -1, 2])).tolist()
    [1, 2]
    """
    order = np.lexsort((np.arange(len(key)), rank, key))
    keep = np.ones(len(order), dtype=bool)
    keep[1:] = key[order][1:] != key[order][:-1]
    return np.asarray(order[keep])


def principal_axes(points: np.ndarray) -> np.ndarray:
    """(3, 3) the points' principal axes as rows, the longest spread first, each signed so that
    its largest component is positive (a deterministic choice among +-v).

    >>> principal_axes(np.array([[0.0, 0, 0], [0, 0, 5], [0, 1, 0], [0, 1, 5]]))[0].tolist()
    [0.0, 0.0, 1.0]
    """
    centred = points - points.mean(axis=0)
    _, vectors = np.linalg.eigh(centred.T @ centred)
    rows = vectors.T[::-1].copy()
    for row in rows:
        if row[np.argmax(np.abs(row))] < 0:
            row *= -1.0
    return rows


Fit = tuple[float, np.ndarray, np.ndarray, float]
"""(volume, start, end, radius) of one capsule."""


def _piece_fit(points: np.ndarray, fine: bool, hulled: bool = False) -> Fit:
    """The capsule of least volume found for ``points``: the best of the principal axes, then
    (``fine``) a pattern search of the direction from it. ``hulled``: the points are already few
    (slabs' hulls): no hull of them is taken."""
    hull = points if hulled else hull_points(points)
    if len(hull) == 1:
        return 0.0, hull[0].copy(), hull[0].copy(), 0.0
    axes = principal_axes(hull)
    fits = [(_along(hull, d), d) for d in (axes if fine else axes[:COARSE_AXES])]
    fit, d = min(fits, key=lambda f: f[0][0])
    if not fine:
        return fit
    if len(hull) > SEARCH_POINTS:  # searched on a grid's points first, then from there on all of them
        few = _grid_points(hull)
        d = _pattern_search(few, _along(few, d), d, 0.25)[1]
        return min(fit, _pattern_search(hull, _along(hull, d), d, 4.0 * DIRECTION_TOL)[0], key=lambda f: f[0])
    return _pattern_search(hull, fit, d, 0.25)[0]


def _pattern_search(hull: np.ndarray, fit: Fit, d: np.ndarray, step: float) -> tuple[Fit, np.ndarray]:
    """From the capsule ``fit`` along ``d``, a pattern search of the axis direction on the sphere
    (eight neighbours at ``step``, the step halved when none is better, down to
    :data:`DIRECTION_TOL`): the best capsule found and its direction."""
    u, v = _perpendiculars(d)
    while step >= DIRECTION_TOL:
        moved = False
        for a, b in ((1, 0), (-1, 0), (0, 1), (0, -1), (1, 1), (-1, -1), (1, -1), (-1, 1)):
            trial = d + step * (a * u + b * v)
            trial /= np.linalg.norm(trial)
            candidate = _along(hull, trial)
            if candidate[0] < fit[0] * (1.0 - 1e-9):
                fit, d, moved = candidate, trial, True
                u, v = _perpendiculars(d)
                break
        if not moved:
            step /= 2.0
    return fit, d


def _search_points(points: np.ndarray) -> np.ndarray:
    """Fewer points that stand for ``points`` while cuts are weighed: the vertices of their convex
    hull, and of the rest one point in each cell of a grid of :data:`SEARCH_GRID` cells along the
    longest side (the first in the points' order: deterministic). Only the choice of the cuts sees
    them: each kept piece is fitted to all its points, so no point is ever left out for them.

    >>> grid = np.array([[x, y, z] for x in range(100) for y in range(100) for z in (0, 1)], dtype=float)
    >>> len(_search_points(grid)) < len(grid) / 4
    True
    """
    return np.asarray(points[np.union1d(_grid_indices(points), _hull_indices(points))])


def _grid_points(points: np.ndarray) -> np.ndarray:
    """One point in each cell of a grid of :data:`SEARCH_GRID` cells along the longest side (the
    first in the points' order), in the points' order."""
    return np.asarray(points[_grid_indices(points)])


def _grid_indices(points: np.ndarray) -> np.ndarray:
    low = points.min(axis=0)
    cell = float((points.max(axis=0) - low).max()) / SEARCH_GRID or 1.0
    cells = np.floor((points - low) / cell).astype(np.int64)
    keys = (cells[:, 0] * (SEARCH_GRID + 2) + cells[:, 1]) * (SEARCH_GRID + 2) + cells[:, 2]
    return np.sort(np.unique(keys, return_index=True)[1])


def _hull_indices(points: np.ndarray) -> np.ndarray:
    """The indices of the points' convex hull's vertices, ascending (all when they span no volume)."""
    if len(points) < 5:
        return np.arange(len(points))
    from scipy.spatial import ConvexHull, QhullError

    try:
        return np.sort(ConvexHull(points).vertices)
    except (QhullError, ValueError):
        return np.arange(len(points))


def hull_points(points: np.ndarray) -> np.ndarray:
    """The vertices of the points' convex hull (a capsule holds a point set when it holds those),
    in the order given; all the points when they span no volume (flat or on a line).

    >>> len(hull_points(np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)] + [[0.5, 0.5, 0.5]], dtype=float)))
    8
    """
    if len(points) < 5:
        return points
    from scipy.spatial import ConvexHull, QhullError

    try:
        return np.asarray(points[np.sort(ConvexHull(points).vertices)])
    except (QhullError, ValueError):
        return points


def _along(points: np.ndarray, d: np.ndarray) -> Fit:
    """The least-volume capsule whose axis has direction ``d``: its line through the centre of the
    smallest circle holding the points seen along ``d``, its radius from a 1-D search."""
    u, v = _perpendiculars(d)
    centre = smallest_circle(np.stack([points @ u, points @ v], axis=1))
    return _through(points, d, centre[0] * u + centre[1] * v)


def _through(points: np.ndarray, d: np.ndarray, axis_point: np.ndarray) -> Fit:
    """The least-volume capsule on the line through ``axis_point`` along ``d``: its radius from a
    1-D search (at least the farthest point's distance from the line; a larger one buys shorter ends)."""
    t = points @ d
    rho = np.linalg.norm(points - axis_point - (t - float(axis_point @ d))[:, None] * d, axis=1)
    r_min = float(rho.max())
    span = float(t.max() - t.min())
    r_max = math.hypot(r_min, span / 2.0)
    radii = np.linspace(r_min, r_max, RADII)
    low, high = _frontier(t, rho), _frontier(-t, rho)  # the points that can set the lower / upper end
    volumes, lo, hi = _volumes(radii, (rho[low], t[low]), (rho[high], t[high]))
    k = int(np.argmin(volumes))
    fine = np.linspace(radii[max(k - 1, 0)], radii[min(k + 1, RADII - 1)], RADII)
    volumes2, lo2, hi2 = _volumes(fine, (rho[low], t[low]), (rho[high], t[high]))
    j = int(np.argmin(volumes2))
    if volumes2[j] <= volumes[k]:
        radius, a, b, volume = float(fine[j]), float(lo2[j]), float(hi2[j]), float(volumes2[j])
    else:
        radius, a, b, volume = float(radii[k]), float(lo[k]), float(hi[k]), float(volumes[k])
    base = axis_point - float(axis_point @ d) * d  # the line's point at t = 0
    return volume, base + a * d, base + b * d, radius


def _refined(points: np.ndarray, fit: Fit) -> Fit:
    """The capsule ``fit`` of ``points`` with its axis line moved off the smallest circle's centre
    and tilted together (4 numbers, Nelder and Mead's simplex from the fit, at most
    :data:`REFINE_EVALUATIONS` capsules, each with its own best radius, :func:`_through`): a
    larger radius on a line nearer the bulky end can shorten the capsule by more than it widens
    it. Deterministic (scipy's simplex has no randomness); never worse than ``fit``."""
    volume, start, end, radius = fit
    length = float(np.linalg.norm(end - start))
    if length == 0.0 or radius == 0.0 or len(points) < 4:
        return fit
    from scipy.optimize import minimize

    d0 = (end - start) / length
    u0, v0 = _perpendiculars(d0)

    def capsule(x: np.ndarray) -> Fit:
        d = d0 + x[0] * u0 + x[1] * v0
        d = d / np.linalg.norm(d)
        return _through(points, d, start + radius * (x[2] * u0 + x[3] * v0))

    simplex = np.vstack([np.zeros(4), REFINE_STEP * np.eye(4)])
    found = minimize(
        lambda x: capsule(x)[0],
        np.zeros(4),
        method="Nelder-Mead",
        options={"initial_simplex": simplex, "maxfev": REFINE_EVALUATIONS, "xatol": 1e-4, "fatol": 1e-7 * volume},
    )
    better = capsule(found.x)
    return better if better[0] < volume else fit


def _volumes(
    radii: np.ndarray, low: tuple[np.ndarray, np.ndarray], high: tuple[np.ndarray, np.ndarray]
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """For each radius r: the capsule's volume and its segment's ends along the axis.

    A point at axial t and distance rho from the axis is held by a segment [a, b] iff
    a <= t + h and b >= t - h, h = sqrt(r^2 - rho^2): so a = min(t + h), b = max(t - h), or
    their middle when a > b (a sphere). ``low`` and ``high`` are (rho, t) of the points that can
    set a and b (:func:`_frontier`: the others never reach the min or max)."""
    (rho_a, t_a), (rho_b, t_b) = low, high
    r2 = radii[:, None] ** 2
    a = (t_a[None, :] + np.sqrt(np.maximum(r2 - rho_a[None, :] ** 2, 0.0))).min(axis=1)
    b = (t_b[None, :] - np.sqrt(np.maximum(r2 - rho_b[None, :] ** 2, 0.0))).max(axis=1)
    middle = (a + b) / 2.0
    a, b = np.where(a > b, middle, a), np.where(a > b, middle, b)
    return np.pi * radii**2 * (b - a) + 4.0 / 3.0 * np.pi * radii**3, a, b


def _frontier(t: np.ndarray, rho: np.ndarray) -> np.ndarray:
    """The indices of the points that can hold the least t + sqrt(r^2 - rho^2) for some r: a point
    with another at no larger t and no smaller rho never does (its h is no smaller, its t no
    smaller, in floating point too: each step is monotone), so only the points whose rho exceeds
    that of every point before them in the order of t are kept (the same minimum, exactly).

    >>> _frontier(np.array([0.0, 1, 2, 3]), np.array([1.0, 2, 0.5, 3])).tolist()
    [0, 1, 3]
    """
    first, widest = int(np.argmin(t)), int(np.argmax(rho))
    # the point of least t dominates every point of no larger rho; the widest, every point of no smaller t
    maybe = np.flatnonzero(
        ((rho > rho[first]) & (t < t[widest])) | (np.arange(len(t)) == first) | (np.arange(len(t)) == widest)
    )
    order = maybe[np.argsort(t[maybe], kind="stable")]
    r = rho[order]
    keep = np.empty(len(r), dtype=bool)
    keep[:1] = True
    keep[1:] = r[1:] > np.maximum.accumulate(r)[:-1]
    return np.sort(order[keep])


def _perpendiculars(d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors that make a right-handed frame with the unit vector ``d``."""
    x, y, z = (float(c) for c in d)
    u = np.array([0.0, z, -y]) if abs(x) < 0.9 else np.array([-z, 0.0, x])  # d x e_x, or d x e_y
    u /= math.sqrt(float(u @ u))
    return u, np.array([y * u[2] - z * u[1], z * u[0] - x * u[2], x * u[1] - y * u[0]])


def smallest_circle(q: np.ndarray) -> np.ndarray:
    """The centre of the smallest circle holding the 2-D points ``q`` (N, 2), by Elzinga and
    Hearn's method (1972): a circle on a support set of at most three points is grown, each time
    by the point farthest from its centre, into the smallest circle holding the support and that
    point (which passes through it), until no point lies outside. Each step's radius is larger
    than the last and there are finitely many supports, so it ends, at the smallest circle (to
    rounding: the fit measures its radius from the centre to every point, so the rounding is
    never a point left out). One array pass a step, a handful of steps: no hull, no shuffle;
    deterministic.

    >>> smallest_circle(np.array([[0.0, 0], [2, 0], [1, 0.5], [1, -1]])).round(9).tolist()
    [1.0, 0.0]
    >>> smallest_circle(np.array([[0.0, 0], [4, 0], [2, 3]])).round(9).tolist()  # three on the circle
    [2.0, 0.833333333]
    """
    x, y = q[:, 0], q[:, 1]
    i = int(np.argmax((x - x[0]) ** 2 + (y - y[0]) ** 2))
    j = int(np.argmax((x - x[i]) ** 2 + (y - y[i]) ** 2))
    support = [(float(x[i]), float(y[i])), (float(x[j]), float(y[j]))]
    cx, cy, r2 = _diametral(support[0], support[1])
    for _ in range(10 * len(q) + 10):  # a bound never met: each step grows the circle
        d2 = (x - cx) ** 2 + (y - cy) ** 2
        k = int(np.argmax(d2))
        if d2[k] <= r2 * (1.0 + 1e-12) + 1e-30:
            break
        s = (float(x[k]), float(y[k]))
        grown = _smallest_through(support, s)
        if grown is None or grown[2] <= r2:  # rounding: no circle of the support and s holds them
            break
        cx, cy, r2 = grown
        support = [p for p in (*support, s) if (p[0] - cx) ** 2 + (p[1] - cy) ** 2 >= r2 * (1.0 - 1e-9)]
    return np.array([cx, cy])


def _diametral(a: tuple[float, float], b: tuple[float, float]) -> tuple[float, float, float]:
    """The circle on a and b as diameter (centre x, y, radius squared)."""
    cx, cy = (a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0
    return cx, cy, max((a[0] - cx) ** 2 + (a[1] - cy) ** 2, (b[0] - cx) ** 2 + (b[1] - cy) ** 2)


def _smallest_through(support: list[tuple[float, float]], s: tuple[float, float]) -> tuple[float, float, float] | None:
    """The smallest circle through ``s`` that holds ``support`` and ``s``: on s and one support point
    as diameter, or through s and two of them (None when rounding leaves none holding all)."""
    points = (*support, s)
    candidates = [_diametral(a, s) for a in support]
    candidates += [
        _circumcircle(support[i], support[j], s, (0.0, 0.0, 0.0))
        for i in range(len(support))
        for j in range(i + 1, len(support))
    ]
    best = None
    for cx, cy, r2 in candidates:
        limit = r2 * (1.0 + 1e-12) + 1e-30
        if (best is None or r2 < best[2]) and all((p[0] - cx) ** 2 + (p[1] - cy) ** 2 <= limit for p in points):
            best = (cx, cy, r2)
    return best


def _circumcircle(
    a: tuple[float, float], b: tuple[float, float], c: tuple[float, float], fallback: tuple[float, float, float]
) -> tuple[float, float, float]:
    """The circle through three points (centre x, y, radius squared); for three points on a line,
    the circle on the farthest two as diameter."""
    d = 2.0 * (a[0] * (b[1] - c[1]) + b[0] * (c[1] - a[1]) + c[0] * (a[1] - b[1]))
    if abs(d) < 1e-300:
        pairs = [(a, b), (a, c), (b, c)]
        p, q = max(pairs, key=lambda s: (s[0][0] - s[1][0]) ** 2 + (s[0][1] - s[1][1]) ** 2)
        cx, cy = (p[0] + q[0]) / 2.0, (p[1] + q[1]) / 2.0
        return cx, cy, max(fallback[2], (p[0] - cx) ** 2 + (p[1] - cy) ** 2)
    sa, sb, sc = a[0] ** 2 + a[1] ** 2, b[0] ** 2 + b[1] ** 2, c[0] ** 2 + c[1] ** 2
    cx = (sa * (b[1] - c[1]) + sb * (c[1] - a[1]) + sc * (a[1] - b[1])) / d
    cy = (sa * (c[0] - b[0]) + sb * (a[0] - c[0]) + sc * (b[0] - a[0])) / d
    return (
        cx,
        cy,
        max(
            (a[0] - cx) ** 2 + (a[1] - cy) ** 2,
            (b[0] - cx) ** 2 + (b[1] - cy) ** 2,
            (c[0] - cx) ** 2 + (c[1] - cy) ** 2,
        ),
    )


Split = tuple[float, list[tuple[float, float]], np.ndarray]
"""(total volume, the slabs (lo, hi) along the axis, the axis) of a cut into pieces."""


def _best_splits(
    points: np.ndarray, edges: np.ndarray, axes: np.ndarray, counts: tuple[int, ...], outside: _Outside
) -> dict[int, list[Split]]:
    """For each count of pieces, the cuts worth fitting in full: of every cut across a direction of
    ``axes`` at evenly spaced places (each piece fitted coarsely, along its first principal axis
    only, :data:`COARSE_AXES`), the :data:`TRIED` of least total volume and the :data:`TRIED` of
    least volume outside the hull (``outside``) among those within :data:`VOLUME_ALLOWANCE` of the
    least coarse volume (one coarse capsule's included), each once; a count is missing when no
    cut leaves every piece some points.

    The hull of a piece is the hull of its thin slabs' hulls (each slab between two neighbouring
    places, with where the edges cross its planes): each slab's hull is computed once."""
    found: dict[int, list[tuple[float, int, list[tuple[tuple[int, int, int], Fit]], Split]]] = {}
    order = 0
    for a, axis in enumerate(axes):
        t = points @ axis
        places = np.linspace(t.min(), t.max(), CUTS + 1)[1:-1]
        n = len(places)
        ends = [-np.inf, *places.tolist(), np.inf]
        along = (t, edges[:, 0] @ axis, edges[:, 1] @ axis)
        thin = [hull_points(_slab(points, edges, axis, ends[k], ends[k + 1], along)) for k in range(n + 1)]
        known: dict[tuple[int, int], Fit | None] = {}
        for count in counts:
            for cuts in _cut_sets(n, count - 1):
                bounds = (-1, *cuts, n)
                fits = [_piece_coarse(thin, bounds[k], bounds[k + 1], known) for k in range(count)]
                if all(fit is not None for fit in fits):
                    slabs = [(float(ends[bounds[k] + 1]), float(ends[bounds[k + 1] + 1])) for k in range(count)]
                    pieces = [((a, bounds[k], bounds[k + 1]), fit) for k, fit in enumerate(fits) if fit is not None]
                    total = float(sum(fit[0] for _, fit in pieces))
                    found.setdefault(count, []).append((total, order, pieces, (total, slabs, axis)))
                    order += 1
    least = min([_piece_fit(points, fine=False)[0], *(row[0] for rows in found.values() for row in rows)])
    masks: dict[tuple[int, int, int], np.ndarray] = {}

    def away(pieces: list[tuple[tuple[int, int, int], Fit]]) -> int:
        """Outside cells held by the pieces' coarse capsules (each piece's cells found once)."""
        held = np.zeros(len(outside.cells), dtype=bool)
        for key, fit in pieces:
            if key not in masks:
                masks[key] = outside.held(fit)
            held |= masks[key]
        return int(np.count_nonzero(held))

    out: dict[int, list[Split]] = {}
    for count, rows in found.items():
        by_volume = sorted(rows, key=lambda row: (row[0], row[1]))[:TRIED]
        near = [row for row in rows if row[0] <= VOLUME_ALLOWANCE * least]
        by_outside = sorted(near, key=lambda row: (away(row[2]), row[0], row[1]))[:TRIED] if len(outside.cells) else []
        chosen = {row[1]: row for row in by_volume + by_outside}
        out[count] = [row[3] for _, row in sorted(chosen.items())]
    return out


def cut_axes(axes: np.ndarray) -> np.ndarray:
    """The directions cuts are tried across: the principal axes, the mesh frame's axes (a CAD part
    is often square to its link's frame) and (:data:`DIAGONALS`) the bisectors of each two principal
    axes, each once (a direction within about 2.6 degrees of one before it is left out).

    >>> cut_axes(np.eye(3)).tolist() == np.eye(3).tolist()  # the frame's axes are the principal ones here
    True
    """
    rows = [*axes, *np.eye(3)]
    if DIAGONALS:
        rows += [
            (axes[i] + sign * axes[j]) / math.sqrt(2.0)
            for i in range(3)
            for j in range(i + 1, 3)
            for sign in (1.0, -1.0)
        ]
    kept: list[np.ndarray] = []
    for row in rows:
        if all(abs(float(row @ k)) < 0.999 for k in kept):
            kept.append(row)
    return np.array(kept)


def _piece_coarse(thin: list[np.ndarray], i: int, j: int, known: dict[tuple[int, int], Fit | None]) -> Fit | None:
    """The coarse capsule of the piece between cuts i and j (-1 and len(thin) - 1: the ends), made
    of the thin slabs i + 1 to j; None for no points; kept in ``known``."""
    if (i, j) not in known:
        inside = np.concatenate(thin[i + 1 : j + 1])
        known[(i, j)] = _piece_fit(inside, fine=False, hulled=True) if len(inside) else None
    return known[(i, j)]


def _cut_sets(n: int, k: int) -> list[tuple[int, ...]]:
    """Every increasing choice of ``k`` of the ``n`` cut places (k = 1 or 2)."""
    if k == 1:
        return [(i,) for i in range(n)]
    return [(i, j) for i in range(n) for j in range(i + 1, n)]


def _edges(vertices: np.ndarray, faces: np.ndarray | None) -> np.ndarray:
    """(E, 2, 3) the mesh's edges, each once (none without faces)."""
    if faces is None or not len(faces):
        return np.zeros((0, 2, 3))
    faces = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    pairs = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    pairs = np.sort(pairs, axis=1)
    keys = np.unique(pairs[:, 0] * np.int64(len(vertices)) + pairs[:, 1])  # (lo, hi) in lexicographic order, each once
    return np.asarray(vertices[np.stack([keys // len(vertices), keys % len(vertices)], axis=1)])


def _slab(
    points: np.ndarray,
    edges: np.ndarray,
    axis: np.ndarray,
    lo: float,
    hi: float,
    along: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None,
) -> np.ndarray:
    """The points with ``lo <= t <= hi`` along ``axis`` (every point for the whole range), and where
    the edges cross the planes t = lo and t = hi; ``along``: the points' and the edges' ends' t, if known."""
    t, ta, tb = along if along is not None else (points @ axis, edges[:, 0] @ axis, edges[:, 1] @ axis)
    inside = points[(t >= lo) & (t <= hi)]  # a point on a plane in both: an edge ending there is held on both sides
    crossings = [inside]
    for plane in (lo, hi):
        if np.isfinite(plane) and len(edges):
            cross = (np.minimum(ta, tb) < plane) & (np.maximum(ta, tb) > plane)
            s = (plane - ta[cross]) / (tb[cross] - ta[cross])
            crossings.append(_plane_hull(edges[cross, 0] + s[:, None] * (edges[cross, 1] - edges[cross, 0]), axis))
    return np.concatenate(crossings)


def _plane_hull(points: np.ndarray, axis: np.ndarray) -> np.ndarray:
    """Of points on one plane across ``axis``, the vertices of their convex hull in that plane (in
    the order given): a capsule, convex, that holds those holds the polygon and every point in it.
    All of them when they are few or on a line."""
    if len(points) < 8:
        return points
    from scipy.spatial import ConvexHull, QhullError

    u, v = _perpendiculars(axis)
    try:
        return np.asarray(points[np.sort(ConvexHull(np.stack([points @ u, points @ v], axis=1)).vertices)])
    except (QhullError, ValueError):
        return points


def _rounded(fit: Fit, points: np.ndarray) -> FittedCapsule:
    """The capsule with its ends rounded to :data:`DECIMALS` places and its radius measured from the
    rounded segment to the farthest of ``points``, rounded up (the written capsule holds them)."""
    start, end = _rounded_ends(fit)
    return FittedCapsule(
        start, end, _rounded_up(float(segment_distances(points, start, end).max()) if len(points) else 0.0)
    )


def _rounded_ends(fit: Fit) -> tuple[np.ndarray, np.ndarray]:
    """The fit's segment's ends rounded to :data:`DECIMALS` places."""
    return np.round(fit[1], DECIMALS) + 0.0, np.round(fit[2], DECIMALS) + 0.0  # + 0.0: no -0.0


def _rounded_up(reach: float) -> float:
    """A measured radius rounded up to :data:`DECIMALS` places (the written capsule holds what it measured)."""
    scale = 10.0**DECIMALS
    return math.ceil(reach * scale * (1.0 + 1e-12)) / scale
