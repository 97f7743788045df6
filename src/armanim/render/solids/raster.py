"""Triangles into a sprite: a small z-buffer rasteriser, compiled (numba).

A robot's link is a few hundred to a few thousand triangles; drawn as matplotlib polygons
they cost some 25 us each (a path per polygon), compiled they cost what their pixels do.
Each triangle is filled on a grid of ``ss`` x ``ss`` samples per pixel (the anti-aliasing: a
pixel's cover is the share of its samples some triangle covers), the nearest triangle wins
each sample (``near`` interpolated across the triangle, larger is nearer, as
:class:`armanim.render.camera.view.View` gives it), and its colour is interpolated from the
three vertices' (Gouraud shading). The result is a :data:`armanim.render.paint.pixels.Sprite`,
composited like a sphere's disc.
"""

from __future__ import annotations

import numpy as np

from armanim.render.paint.pixels import Sprite

SUPERSAMPLE = 2
"""Samples per pixel along each axis (2: four samples a pixel)."""


def triangle_sprite(
    points: np.ndarray, faces: np.ndarray, rgb: np.ndarray, size: tuple[int, int], ss: int = SUPERSAMPLE
) -> Sprite | None:
    """Triangles drawn into a sprite of a frame ``size`` (width, height): ``points`` (V, 3) on the
    screen (x px, y px up, near), ``faces`` (k, 3) into them, ``rgb`` (V, 3) colours 0 to 1.

    Returns None when nothing falls inside the frame.

    >>> square = np.array([[1.0, 1.0, 0.0], [3.0, 1.0, 0.0], [3.0, 3.0, 0.0], [1.0, 3.0, 0.0]])
    >>> rows, cols, rgb, clear = triangle_sprite(square, np.array([[0, 1, 2], [0, 2, 3]]), np.ones((4, 3)), (4, 4))
    >>> (rows, cols), (1.0 - clear[..., 0]).round(3).tolist()
    ((slice(1, 3, None), slice(1, 3, None)), [[1.0, 1.0], [1.0, 1.0]])
    """
    width, height = size
    box = _box(points, faces, width, height)
    if box is None:
        return None
    from armanim.render.solids.rasterloops import resolve_samples  # compiled: numba is imported here

    x0, y0, x1, y1 = box
    depth, color = _samples(points, faces, rgb, box, ss, float)
    premultiplied, clear = (
        np.empty((y1 - y0, x1 - x0, 3), dtype=np.float32),
        np.empty((y1 - y0, x1 - x0, 1), dtype=np.float32),
    )
    resolve_samples(depth, color, ss, premultiplied, clear)
    return slice(height - y1, height - y0), slice(x0, x1), premultiplied, clear


class StillLayer:
    """Triangles that never move on screen (the scene's furniture: a whiteboard), filled once on
    the frame's grid of samples and laid into every frame's z-buffer they are drawn in, instead of
    filled again each frame (ur5-pen's board was two thirds of its frames' samples).

    A sample's nearness and colour do not depend on the box it is filled in
    (:func:`armanim.render.solids.rasterloops.fill_samples`), so the frame is the one filling
    these triangles first would draw.

    Parameters
    ----------
    points : (V, 3) array
        Screen points (x px, y px up, near).
    faces : (k, 3) int array
        The triangles into them (those facing the camera).
    rgb : (V, 3) array
        Colours 0 to 1.
    size : (int, int)
        The frame's width and height.
    """

    def __init__(
        self, points: np.ndarray, faces: np.ndarray, rgb: np.ndarray, size: tuple[int, int], ss: int = SUPERSAMPLE
    ):
        self.ss = ss
        self.box = _box(points, faces, *size)
        self.depth = self.color = None
        if self.box is not None:
            from armanim.render.solids.rasterloops import resolve_cover  # compiled: numba is imported here

            self.depth, self.color = _samples(points, faces, rgb, self.box, ss, np.float32)
            x0, y0, x1, y1 = self.box
            self.hits = np.empty((y1 - y0, x1 - x0), dtype=np.uint8)
            self.adds = np.empty((y1 - y0, x1 - x0, 3))
            resolve_cover(self.depth, self.color, ss, self.hits, self.adds)
            """Each pixel's covered samples and what they add to it (:func:`blend_outside`), rows up."""

    def lay(self, depth: np.ndarray, color: np.ndarray, box: tuple[int, int, int, int]) -> None:
        """Copy the layer's samples inside pixel ``box`` (x0, y0, x1, y1; y up) into that box's sample
        grids ``depth`` and ``color``."""
        if self.box is None:
            return
        x0, y0 = max(self.box[0], box[0]), max(self.box[1], box[1])
        x1, y1 = min(self.box[2], box[2]), min(self.box[3], box[3])
        if x1 <= x0 or y1 <= y0:
            return
        assert self.depth is not None and self.color is not None  # (filled with the box)
        ss, own = self.ss, self.box
        into = slice((y0 - box[1]) * ss, (y1 - box[1]) * ss), slice((x0 - box[0]) * ss, (x1 - box[0]) * ss)
        laid = slice((y0 - own[1]) * ss, (y1 - own[1]) * ss), slice((x0 - own[0]) * ss, (x1 - own[0]) * ss)
        depth[into] = self.depth[laid]
        color[into] = self.color[laid]

    def hidden_prefix(self, polyline: np.ndarray, reach: float) -> int:
        """How many leading points of a screen ``polyline`` (k, 2: x px, y px up; a NaN row breaks it)
        the layer hides wholly: every pixel within ``reach`` pixels of each point and of every
        segment between them is one all of whose samples the layer covers, so that a frame whose
        z-buffer holds the layer (its pixels laid over whatever was drawn there, keeping none of it)
        shows nothing of a stroke drawn along them under it."""
        if self.box is None or not len(polyline):
            return 0
        x0, y0 = self.box[:2]
        m = int(np.ceil(reach + 0.25))  # (+ the samples' spacing along a segment)
        full = np.pad(self.hits == self.ss * self.ss, m).astype(np.int32)
        sums = np.pad(full.cumsum(axis=0).cumsum(axis=1), ((1, 0), (1, 0)))
        k = 2 * m + 1
        eroded = (sums[k:, k:] - sums[:-k, k:] - sums[k:, :-k] + sums[:-k, :-k]) == k * k  # (h, w): all within m
        p = np.asarray(polyline, dtype=float)
        a, b = np.vstack([p[:1], p[:-1]]), p  # each point's segment from the one before
        a = np.where(np.isfinite(a[:, :1]), a, b)  # (the first, or one after a break: the point alone)
        count = np.where(np.isfinite(a[:, 0]) & np.isfinite(b[:, 0]), np.ceil(np.hypot(*(b - a).T) * 4.0), 0)
        t = np.concatenate([np.linspace(0.0, 1.0, int(c) + 1) for c in count])
        owner = np.repeat(np.arange(len(p)), (count + 1).astype(int))
        at = a[owner] + t[:, None] * (b[owner] - a[owner])  # every 0.25 px along each segment, its ends too
        ok = ~np.isfinite(at[:, 0])  # a break draws nothing
        i, j = np.floor(at[~ok, 1]).astype(int) - y0, np.floor(at[~ok, 0]).astype(int) - x0
        inside = (i >= 0) & (i < eroded.shape[0]) & (j >= 0) & (j < eroded.shape[1])
        ok[~ok] = inside & eroded[np.clip(i, 0, eroded.shape[0] - 1), np.clip(j, 0, eroded.shape[1] - 1)]
        hidden = np.ones(len(p), dtype=bool)
        np.logical_and.at(hidden, owner, ok)
        return int(np.argmin(hidden)) if not hidden.all() else len(p)

    def blend_outside(self, buffer: np.ndarray, box: tuple[int, int, int, int] | None) -> None:
        """Lay the layer's pixels outside pixel ``box`` (None: all of them) over the frame ``buffer``
        (H, W, 4 uint8) as :func:`~armanim.render.solids.rasterloops.blend_samples` lays a z-buffer
        that holds only the layer there: their samples were summed once."""
        if self.box is None:
            return
        from armanim.render.solids.rasterloops import blend_cover  # compiled: numba is imported here

        x0, y0 = self.box[:2]
        skip = (
            np.zeros(4, dtype=np.int64)
            if box is None
            else np.array([box[1] - y0, box[3] - y0, box[0] - x0, box[2] - x0], dtype=np.int64)
        )
        blend_cover(self.hits, self.adds, self.ss, buffer, buffer.shape[0] - self.box[3], x0, skip)


def draw_triangles(
    buffer: np.ndarray,
    points: np.ndarray,
    faces: np.ndarray,
    rgb: np.ndarray,
    ss: int = SUPERSAMPLE,
    still: StillLayer | None = None,
) -> None:
    """Draw triangles straight into a frame ``buffer`` (H, W, 4 uint8): what
    :func:`triangle_sprite` draws, composited, without the sprite in between; with ``still``, its
    triangles too, in the same z-buffer, the layer's samples laid first. The z-buffer spans only
    the box of ``faces``: the layer's pixels outside it hold none of their samples, so they are laid
    as the layer alone draws them (ur5-pen's board was two fifths of its frames' z-buffer)."""
    height, width = buffer.shape[:2]
    box = _box(points, faces, width, height)
    if still is not None:
        still.blend_outside(buffer, box)
    if box is None:
        return
    from armanim.render.solids.rasterloops import blend_samples  # compiled: numba is imported here

    depth, color = _samples(points, faces, rgb, box, ss, np.float32, still)
    blend_samples(depth, color, ss, buffer, height - box[3], box[0])


def draw_outline(
    buffer: np.ndarray,
    points: np.ndarray,
    faces: np.ndarray,
    rgb: tuple[float, float, float],
    width: int = 1,
    alpha: float = 0.9,
) -> None:
    """Draw only the outline of the triangles' union into a frame ``buffer`` (H, W, 4 uint8): the
    covered pixels with an uncovered neighbour (4-neighbourhood), grown by ``width`` - 1 pixels,
    in ``rgb`` at ``alpha`` (a poster's faint pose, which must not hide the one it is drawn under)."""
    height, width_px = buffer.shape[:2]
    box = _box(points, faces, width_px, height)
    if box is None:
        return
    x0, y0, x1, y1 = box
    ss = SUPERSAMPLE
    depth, _ = _samples(points, faces, np.zeros((len(points), 3)), box, ss, np.float32)
    inside = np.pad(np.isfinite(depth).reshape(y1 - y0, ss, x1 - x0, ss).mean(axis=(1, 3))[::-1] >= 0.5, 1)
    edge = inside[1:-1, 1:-1] & ~(inside[:-2, 1:-1] & inside[2:, 1:-1] & inside[1:-1, :-2] & inside[1:-1, 2:])
    for _ in range(width - 1):
        grown = np.pad(edge, 1)
        edge = edge | grown[:-2, 1:-1] | grown[2:, 1:-1] | grown[1:-1, :-2] | grown[1:-1, 2:]
    region = buffer[height - y1 : height - y0, x0:x1, :3]
    region[edge] = (region[edge] * (1 - alpha) + np.asarray(rgb) * 255 * alpha + 0.5).astype(np.uint8)


def _samples(
    points: np.ndarray,
    faces: np.ndarray,
    rgb: np.ndarray,
    box: tuple[int, int, int, int],
    ss: int,
    dtype,
    still: StillLayer | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """The triangles filled on the sample grid of pixel ``box`` (x0, y0, x1, y1; y up), ``ss`` x ``ss``
    samples a pixel: each sample's nearness (-inf where empty) and colour, in ``dtype``; ``still``'s
    samples laid first."""
    from armanim.render.solids.rasterloops import fill_samples  # compiled: numba is imported here

    x0, y0, x1, y1 = box
    depth = np.full(((y1 - y0) * ss, (x1 - x0) * ss), -np.inf, dtype=dtype)
    color = np.empty(depth.shape + (3,), dtype=dtype)  # read only where a triangle set the depth: never cleared
    if still is not None:
        still.lay(depth, color, box)
    if not len(faces):
        return depth, color
    fill_samples(
        np.ascontiguousarray(points, dtype=float),
        np.ascontiguousarray(faces, dtype=np.int64),
        np.ascontiguousarray(rgb, dtype=float),
        float(x0),
        float(y0),
        ss,
        depth,
        color,
    )
    return depth, color


def _box(points: np.ndarray, faces: np.ndarray, width: int, height: int) -> tuple[int, int, int, int] | None:
    """The pixels (x0, y0, x1, y1; y up) the triangles' corners span inside the frame, or None."""
    if not len(faces):
        return None
    from armanim.render.solids.rasterloops import corner_span  # compiled: numba is imported here

    span = np.empty(4)  # (the corners gathered by numpy were 0.1 ms of a robot frame's 2,000 triangles)
    corner_span(np.ascontiguousarray(points, dtype=float), np.ascontiguousarray(faces, dtype=np.int64), span)
    x0, y0 = max(int(np.floor(span[0])), 0), max(int(np.floor(span[1])), 0)
    x1, y1 = min(int(np.ceil(span[2])), width), min(int(np.ceil(span[3])), height)
    return (x0, y0, x1, y1) if x1 > x0 and y1 > y0 else None


__all__ = ["SUPERSAMPLE", "StillLayer", "draw_outline", "draw_triangles", "triangle_sprite"]
