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

import math

import numpy as np

from armanim.render.paint.pixels import Sprite
from armanim.world.compiled import compiled

SUPERSAMPLE = 2
"""Samples per pixel along each axis (2: four samples a pixel)."""

_JIT = dict(error_model="numpy", nogil=True)


@compiled(**_JIT)
def fill_samples(points: np.ndarray, faces: np.ndarray, rgb: np.ndarray, x0: float, y0: float, ss: int,
                 depth: np.ndarray, color: np.ndarray) -> None:
    """Fill the sample grids ``depth`` (H, W) (-inf where empty) and ``color`` (H, W, 3) with the
    triangles ``faces`` (k, 3) of ``points`` (V, 3: x px, y px up, near) coloured ``rgb`` (V, 3).
    Sample (i, j) sits at x = x0 + (j + 0.5) / ss, y = y0 + (i + 0.5) / ss; a sample on an edge
    shared by two triangles belongs to one of them (the top-left rule), so no sample is left
    out between them and none is drawn twice."""
    rows, cols = depth.shape
    for f in range(faces.shape[0]):
        a, b, c = faces[f, 0], faces[f, 1], faces[f, 2]
        ax, ay = (points[a, 0] - x0) * ss - 0.5, (points[a, 1] - y0) * ss - 0.5
        bx, by = (points[b, 0] - x0) * ss - 0.5, (points[b, 1] - y0) * ss - 0.5
        cx, cy = (points[c, 0] - x0) * ss - 0.5, (points[c, 1] - y0) * ss - 0.5
        area = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
        if area == 0.0 or area != area:
            continue
        if area < 0.0:  # either winding: b and c swapped
            b, c, bx, by, cx, cy, area = c, b, cx, cy, bx, by, -area
        j0, j1 = max(int(math.ceil(min(ax, bx, cx))), 0), min(int(math.floor(max(ax, bx, cx))), cols - 1)
        i0, i1 = max(int(math.ceil(min(ay, by, cy))), 0), min(int(math.floor(max(ay, by, cy))), rows - 1)
        for i in range(i0, i1 + 1):
            for j in range(j0, j1 + 1):
                w0 = (cx - bx) * (i - by) - (cy - by) * (j - bx)  # weight of a: the edge b -> c
                w1 = (ax - cx) * (i - cy) - (ay - cy) * (j - cx)  # of b: the edge c -> a
                w2 = (bx - ax) * (i - ay) - (by - ay) * (j - ax)  # of c: the edge a -> b
                if not (_inside(w0, cx - bx, cy - by) and _inside(w1, ax - cx, ay - cy) and _inside(w2, bx - ax, by - ay)):
                    continue
                near = (w0 * points[a, 2] + w1 * points[b, 2] + w2 * points[c, 2]) / area
                if near > depth[i, j]:
                    depth[i, j] = near
                    for k in range(3):
                        color[i, j, k] = (w0 * rgb[a, k] + w1 * rgb[b, k] + w2 * rgb[c, k]) / area


@compiled(inline="always", **_JIT)
def _inside(w: float, dx: float, dy: float) -> bool:
    """A sample with edge weight ``w`` is the triangle's: inside, or on a top or left edge
    (direction dx, dy, counter-clockwise triangle, y up)."""
    if w > 0.0:
        return True
    if w < 0.0:
        return False
    return dy < 0.0 or (dy == 0.0 and dx > 0.0)


def triangle_sprite(points: np.ndarray, faces: np.ndarray, rgb: np.ndarray, size: tuple[int, int],
                    ss: int = SUPERSAMPLE) -> Sprite | None:
    """Triangles drawn into a sprite of a frame ``size`` (width, height): ``points`` (V, 3) on the
    screen (x px, y px up, near), ``faces`` (k, 3) into them, ``rgb`` (V, 3) colours 0 to 1.

    Returns None when nothing falls inside the frame.

    >>> square = np.array([[1.0, 1.0, 0.0], [3.0, 1.0, 0.0], [3.0, 3.0, 0.0], [1.0, 3.0, 0.0]])
    >>> rows, cols, rgb, clear = triangle_sprite(square, np.array([[0, 1, 2], [0, 2, 3]]), np.ones((4, 3)), (4, 4))
    >>> (rows, cols), (1.0 - clear[..., 0]).round(3).tolist()
    ((slice(1, 3, None), slice(1, 3, None)), [[1.0, 1.0], [1.0, 1.0]])
    """
    width, height = size
    used = points[np.unique(faces)] if len(faces) else points[:0]
    if not len(used):
        return None
    x0, y0 = max(int(np.floor(used[:, 0].min())), 0), max(int(np.floor(used[:, 1].min())), 0)
    x1, y1 = min(int(np.ceil(used[:, 0].max())), width), min(int(np.ceil(used[:, 1].max())), height)
    if x1 <= x0 or y1 <= y0:
        return None
    depth = np.full(((y1 - y0) * ss, (x1 - x0) * ss), -np.inf)
    color = np.zeros(depth.shape + (3,))
    fill_samples(np.ascontiguousarray(points, dtype=float), np.ascontiguousarray(faces, dtype=np.int64),
                 np.ascontiguousarray(rgb, dtype=float), float(x0), float(y0), ss, depth, color)
    h, w = y1 - y0, x1 - x0
    cover = np.isfinite(depth).reshape(h, ss, w, ss).mean(axis=(1, 3))[::-1]  # rows top to bottom
    premultiplied = color.reshape(h, ss, w, ss, 3).mean(axis=(1, 3))[::-1] * 255.0
    rows = slice(height - y1, height - y0)
    return rows, slice(x0, x1), premultiplied.astype(np.float32), (1.0 - cover)[..., None].astype(np.float32)


__all__ = ["SUPERSAMPLE", "fill_samples", "triangle_sprite"]
