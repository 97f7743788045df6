"""The rasteriser's compiled loops (numba): filling a triangle's samples and laying a sample
grid over a frame; a robot's mesh placed, projected and lit; a video frame's soft strokes (the arm's shadow on the floor); and a frame's yuv420p planes for the video's encoder
(:mod:`armanim.render.video.planes`). Imported by :mod:`armanim.render.solids.raster` when it first draws, so that
a picture of an arm of links never loads numba."""

from __future__ import annotations

import math
import sys

import numpy as np

from armanim.world.compiled import compiled

_JIT = dict(error_model="numpy", nogil=True)


@compiled(**_JIT)
def fill_samples(
    points: np.ndarray,
    faces: np.ndarray,
    rgb: np.ndarray,
    x0: float,
    y0: float,
    ss: int,
    depth: np.ndarray,
    color: np.ndarray,
) -> None:
    """Fill the sample grids ``depth`` (H, W) (-inf where empty) and ``color`` (H, W, 3) with the
    triangles ``faces`` (k, 3) of ``points`` (V, 3: x px, y px up, near) coloured ``rgb`` (V, 3).
    Sample (i, j) sits at x = x0 + (j + 0.5) / ss, y = y0 + (i + 0.5) / ss; a sample on an edge
    shared by two triangles belongs to one of them (the top-left rule), so no sample is left
    out between them and none is drawn twice. ``x0`` and ``y0`` are whole pixels, and a sample's
    weights, nearness and colour do not depend on them (each corner is placed on the frame's
    grid of samples, then moved by a whole number of samples, which is exact): a grid filled in
    one box is, sample for sample, part of a larger box's (:class:`armanim.render.solids.raster.StillLayer`)."""
    rows, cols = depth.shape
    left, bottom = x0 * ss, y0 * ss
    for f in range(faces.shape[0]):
        a, b, c = faces[f, 0], faces[f, 1], faces[f, 2]
        ax, ay = (points[a, 0] * ss - 0.5) - left, (points[a, 1] * ss - 0.5) - bottom
        bx, by = (points[b, 0] * ss - 0.5) - left, (points[b, 1] * ss - 0.5) - bottom
        cx, cy = (points[c, 0] * ss - 0.5) - left, (points[c, 1] * ss - 0.5) - bottom
        area = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
        if area == 0.0 or area != area:
            continue
        if area < 0.0:  # either winding: b and c swapped
            b, c, bx, by, cx, cy, area = c, b, cx, cy, bx, by, -area
        inverse = 1.0 / area
        j0, j1 = max(int(math.ceil(min(ax, bx, cx))), 0), min(int(math.floor(max(ax, bx, cx))), cols - 1)
        i0, i1 = max(int(math.ceil(min(ay, by, cy))), 0), min(int(math.floor(max(ay, by, cy))), rows - 1)
        for i in range(i0, i1 + 1):
            lo, hi = j0, j1
            lo, hi = _row_span(lo, hi, i, bx, by, cx - bx, cy - by)
            lo, hi = _row_span(lo, hi, i, cx, cy, ax - cx, ay - cy)
            lo, hi = _row_span(lo, hi, i, ax, ay, bx - ax, by - ay)
            for j in range(lo, hi + 1):
                w0 = (cx - bx) * (i - by) - (cy - by) * (j - bx)  # weight of a: the edge b -> c
                w1 = (ax - cx) * (i - cy) - (ay - cy) * (j - cx)  # of b: the edge c -> a
                w2 = (bx - ax) * (i - ay) - (by - ay) * (j - ax)  # of c: the edge a -> b
                if not (
                    _inside(w0, cx - bx, cy - by) and _inside(w1, ax - cx, ay - cy) and _inside(w2, bx - ax, by - ay)
                ):
                    continue
                w0, w1, w2 = w0 * inverse, w1 * inverse, w2 * inverse  # barycentric weights
                near = w0 * points[a, 2] + w1 * points[b, 2] + w2 * points[c, 2]
                if near > depth[i, j]:
                    depth[i, j] = near
                    for k in range(3):
                        color[i, j, k] = w0 * rgb[a, k] + w1 * rgb[b, k] + w2 * rgb[c, k]


@compiled(**_JIT)
def corner_span(points: np.ndarray, faces: np.ndarray, span: np.ndarray) -> None:
    """The least and greatest x and y of the corners of ``faces`` (k >= 1, 3) among ``points`` (V, 3:
    x px, y px, near) into ``span`` (4,: x min, y min, x max, y max); NaN where a corner's is NaN, as
    numpy's min and max give."""
    x0 = x1 = points[faces[0, 0], 0]
    y0 = y1 = points[faces[0, 0], 1]
    for f in range(faces.shape[0]):
        for c in range(3):
            x0, x1 = _widened(points[faces[f, c], 0], x0, x1)
            y0, y1 = _widened(points[faces[f, c], 1], y0, y1)
    span[0], span[1], span[2], span[3] = x0, y0, x1, y1


@compiled(inline="always", **_JIT)
def _widened(v: float, lo: float, hi: float) -> tuple[float, float]:
    """(lo, hi) widened to hold ``v``; NaN for both once ``v`` or ``lo`` is NaN."""
    if v != v or lo != lo:
        return np.nan, np.nan
    return min(lo, v), max(hi, v)


@compiled(inline="always", **_JIT)
def _pixel_sums(depth: np.ndarray, color: np.ndarray, ss: int, i: int, j: int) -> tuple[int, float, float, float]:
    """Pixel (i, j)'s covered samples: how many, and the sums of their red, green and blue."""
    hits, r, g, b = 0, 0.0, 0.0, 0.0
    for a in range(ss):
        for c in range(ss):
            y, x = i * ss + a, j * ss + c
            if depth[y, x] > -np.inf:
                hits += 1
                r += color[y, x, 0]
                g += color[y, x, 1]
                b += color[y, x, 2]
    return hits, r, g, b


@compiled(**_JIT)
def resolve_samples(
    depth: np.ndarray, color: np.ndarray, ss: int, premultiplied: np.ndarray, clear: np.ndarray
) -> None:
    """Average each pixel's ``ss`` x ``ss`` samples: ``premultiplied`` (h, w, 3) RGB 0-255 times
    cover and ``clear`` (h, w, 1) 1 - cover, rows top to bottom (the sample grid's rows run up)."""
    h, w = premultiplied.shape[0], premultiplied.shape[1]
    share = 1.0 / (ss * ss)
    for i in range(h):
        row = h - 1 - i
        for j in range(w):
            hits, r, g, b = _pixel_sums(depth, color, ss, i, j)
            premultiplied[row, j, 0] = min(r * share, 1.0) * 255.0  # (interpolation may round a hair past 1)
            premultiplied[row, j, 1] = min(g * share, 1.0) * 255.0
            premultiplied[row, j, 2] = min(b * share, 1.0) * 255.0
            clear[row, j, 0] = 1.0 - hits * share


@compiled(**_JIT)
def blend_samples(depth: np.ndarray, color: np.ndarray, ss: int, buffer: np.ndarray, top: int, left: int) -> None:
    """Average each pixel's ``ss`` x ``ss`` samples and lay them over ``buffer`` (H, W, 4 uint8,
    rows top to bottom) at row ``top``, column ``left`` (the sample grid's rows run up): a pixel
    covered by a share c of its samples becomes its old colour times 1 - c plus theirs, as
    :func:`armanim.render.paint.pixels.composite` lays a sprite."""
    h, w = depth.shape[0] // ss, depth.shape[1] // ss
    if ss == 2:  # the pictures' grid: its four samples read straight from two rows
        _blend_2x2(depth, color, buffer, top, left)
        return
    share = 1.0 / (ss * ss)
    for i in range(h):
        row = top + h - 1 - i
        for j in range(w):
            hits, r, g, b = _pixel_sums(depth, color, ss, i, j)
            if hits == 0:
                continue
            keep = 1.0 - hits * share
            for k, v in ((0, r), (1, g), (2, b)):
                buffer[row, left + j, k] = np.uint8(buffer[row, left + j, k] * keep + min(v * share, 1.0) * 255.0 + 0.5)


@compiled(**_JIT)
def resolve_cover(depth: np.ndarray, color: np.ndarray, ss: int, hits: np.ndarray, adds: np.ndarray) -> None:
    """Each pixel's ``ss`` x ``ss`` samples summed once, as :func:`blend_samples` sums them: how many
    are covered (``hits`` (h, w)) and what they add to the pixel (``adds`` (h, w, 3): min(sum / ss^2,
    1) x 255), rows as the sample grid's (up)."""
    share = 1.0 / (ss * ss)
    for i in range(hits.shape[0]):
        for j in range(hits.shape[1]):
            n, r, g, b = _pixel_sums(depth, color, ss, i, j)
            hits[i, j] = n
            adds[i, j, 0] = min(r * share, 1.0) * 255.0
            adds[i, j, 1] = min(g * share, 1.0) * 255.0
            adds[i, j, 2] = min(b * share, 1.0) * 255.0


@compiled(**_JIT)
def blend_cover(
    hits: np.ndarray, adds: np.ndarray, ss: int, buffer: np.ndarray, top: int, left: int, skip: np.ndarray
) -> None:
    """Lay pixels summed by :func:`resolve_cover` over ``buffer`` at row ``top``, column ``left`` with
    :func:`blend_samples`' arithmetic (the same bytes), but those of rows ``skip[0]`` to ``skip[1]`` and
    columns ``skip[2]`` to ``skip[3]`` (half open, in ``hits``' rows and columns)."""
    h, w = hits.shape[0], hits.shape[1]
    share = 1.0 / (ss * ss)
    for i in range(h):
        out = buffer[top + h - 1 - i]
        cut = skip[0] <= i < skip[1]
        for j in range(w):
            n = hits[i, j]
            if n == 0 or (cut and skip[2] <= j < skip[3]):
                continue
            keep = 1.0 - n * share
            p = left + j
            out[p, 0] = np.uint8(out[p, 0] * keep + adds[i, j, 0] + 0.5)
            out[p, 1] = np.uint8(out[p, 1] * keep + adds[i, j, 1] + 0.5)
            out[p, 2] = np.uint8(out[p, 2] * keep + adds[i, j, 2] + 0.5)


@compiled(**_JIT)
def _blend_2x2(depth: np.ndarray, color: np.ndarray, buffer: np.ndarray, top: int, left: int) -> None:
    """:func:`blend_samples` of a grid of 2 x 2 samples a pixel (the same sums, in the same order,
    the same bytes), two sample rows at a time: it was a third of a robot frame's z-buffer."""
    h, w = depth.shape[0] // 2, depth.shape[1] // 2
    for i in range(h):
        out = buffer[top + h - 1 - i]
        d0, d1 = depth[2 * i], depth[2 * i + 1]
        c0, c1 = color[2 * i], color[2 * i + 1]
        for j in range(w):
            x = 2 * j
            hits, r, g, b = 0, 0.0, 0.0, 0.0
            if d0[x] > -np.inf:
                hits, r, g, b = hits + 1, r + c0[x, 0], g + c0[x, 1], b + c0[x, 2]
            if d0[x + 1] > -np.inf:
                hits, r, g, b = hits + 1, r + c0[x + 1, 0], g + c0[x + 1, 1], b + c0[x + 1, 2]
            if d1[x] > -np.inf:
                hits, r, g, b = hits + 1, r + c1[x, 0], g + c1[x, 1], b + c1[x, 2]
            if d1[x + 1] > -np.inf:
                hits, r, g, b = hits + 1, r + c1[x + 1, 0], g + c1[x + 1, 1], b + c1[x + 1, 2]
            if hits == 0:
                continue
            keep = 1.0 - hits * 0.25
            p = left + j
            out[p, 0] = np.uint8(out[p, 0] * keep + min(r * 0.25, 1.0) * 255.0 + 0.5)
            out[p, 1] = np.uint8(out[p, 1] * keep + min(g * 0.25, 1.0) * 255.0 + 0.5)
            out[p, 2] = np.uint8(out[p, 2] * keep + min(b * 0.25, 1.0) * 255.0 + 0.5)


@compiled(inline="always", **_JIT)
def _row_span(lo: int, hi: int, i: int, px: float, py: float, dx: float, dy: float) -> tuple[int, int]:
    """The columns [lo, hi] of row ``i`` narrowed to where the edge from (px, py) along (dx, dy)
    can leave a sample inside (its weight dx (i - py) - dy (j - px) not below 0), a column wider
    each side than the algebra says so that rounding never drops one (the exact test decides)."""
    c = dx * (i - py) + dy * px
    if dy > 0.0:
        return lo, min(hi, int(math.floor(c / dy)) + 1)
    if dy < 0.0:
        return max(lo, int(math.ceil(c / dy)) - 1), hi
    return (lo, hi) if c >= 0.0 else (lo, lo - 1)


@compiled(inline="always", **_JIT)
def _inside(w: float, dx: float, dy: float) -> bool:
    """A sample with edge weight ``w`` is the triangle's: inside, or on a top or left edge
    (direction dx, dy, counter-clockwise triangle, y up)."""
    if w > 0.0:
        return True
    if w < 0.0:
        return False
    return dy < 0.0 or (dy == 0.0 and dx > 0.0)


@compiled(**_JIT)
def seen_vertices(
    mesh: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray],
    points: np.ndarray,
    frames: np.ndarray,
    view: tuple[np.ndarray, np.ndarray],
    lighting: tuple[np.ndarray, float, float],
    screen: np.ndarray,
    rgb: np.ndarray,
    facing: np.ndarray,
) -> None:
    """A robot's mesh as the camera sees it at one pose, in one pass: each vertex placed by the
    joint that carries it and projected by the view into ``screen``; its normal turned alike,
    mapped to the screen and lit into ``rgb``; and which faces face the camera (counter-clockwise
    on the screen) into ``facing``. numpy's :func:`~armanim.arm.visuals.mesh_vertices`,
    :meth:`~armanim.render.camera.view.View.project` and :func:`~armanim.render.camera.view.lambert`
    compute the same to the last bits (1.2 ms of a ur5-pen frame as their dozen array operations).

    Parameters
    ----------
    mesh : tuple of arrays
        ``vertices`` (V, 3), metres in their carrier's frame; ``carrier`` (V,), the joint that
        carries each (-1: the world); ``normals`` (V, 3); ``colors`` (V, 3), 0-1; ``faces`` (F, 3).
    points, frames : (n + 1, 3), (n, 3, 3) arrays
        The pose: the joints' points (metres) and frames.
    view : tuple of arrays
        The view's ``matrix`` (3, 4) and its ``normal_map`` (3, 3, row vectors) to the screen.
    lighting : tuple
        ``light`` (3,), the direction to the light; ``ambient`` and ``diffuse``: the colour is
        scaled by ambient plus diffuse times the normal's cosine to the light.
    screen, rgb : (V, 3) arrays
        Filled with the vertices on the screen (pixels, depth) and their lit colours.
    facing : (F,) bool array
        Filled with whether each face faces the camera.
    """
    vertices, carrier, normals, colors, faces = mesh
    matrix, normal_map = view
    light, ambient, diffuse = lighting
    for v in range(vertices.shape[0]):
        k = carrier[v]
        x, y, z = vertices[v, 0], vertices[v, 1], vertices[v, 2]
        nx, ny, nz = normals[v, 0], normals[v, 1], normals[v, 2]
        if k >= 0:
            r = frames[k]
            x, y, z = (
                points[k, 0] + (r[0, 0] * x + r[0, 1] * y + r[0, 2] * z),
                points[k, 1] + (r[1, 0] * x + r[1, 1] * y + r[1, 2] * z),
                points[k, 2] + (r[2, 0] * x + r[2, 1] * y + r[2, 2] * z),
            )
            nx, ny, nz = (
                r[0, 0] * nx + r[0, 1] * ny + r[0, 2] * nz,
                r[1, 0] * nx + r[1, 1] * ny + r[1, 2] * nz,
                r[2, 0] * nx + r[2, 1] * ny + r[2, 2] * nz,
            )
        for a in range(3):
            screen[v, a] = x * matrix[a, 0] + y * matrix[a, 1] + z * matrix[a, 2] + matrix[a, 3]
        sx = nx * normal_map[0, 0] + ny * normal_map[1, 0] + nz * normal_map[2, 0]
        sy = nx * normal_map[0, 1] + ny * normal_map[1, 1] + nz * normal_map[2, 1]
        sz = nx * normal_map[0, 2] + ny * normal_map[1, 2] + nz * normal_map[2, 2]
        length = max(math.sqrt(sx * sx + sy * sy + sz * sz), 1e-12)
        lit = ambient + diffuse * min(max((sx * light[0] + sy * light[1] + sz * light[2]) / length, 0.0), 1.0)
        for c in range(3):
            rgb[v, c] = min(max(colors[v, c] * lit, 0.0), 1.0)
    for f in range(faces.shape[0]):
        a, b, c = faces[f, 0], faces[f, 1], faces[f, 2]
        across = (screen[b, 0] - screen[a, 0]) * (screen[c, 1] - screen[a, 1])
        facing[f] = across - (screen[b, 1] - screen[a, 1]) * (screen[c, 0] - screen[a, 0]) > 0.0


@compiled(**_JIT)
def soft_strokes(buffer: np.ndarray, ends: np.ndarray, radii: np.ndarray, passes: np.ndarray, rgb: np.ndarray) -> None:
    """Stroke segments ``ends`` (k, 2, 2: pixels, y up) with round caps into ``buffer`` (H, W, 4 uint8,
    rows top to bottom), once per pass (scale, alpha) of ``passes`` (p, 2): half ``radii`` (k,) x
    scale wide, in ``rgb`` (3,) 0-255 at alpha, each stroke laid over what is there. A pixel's cover
    is its centre's distance from the stroke's edge, clipped to 0-1 (matplotlib's Agg strokes within
    a few levels); a stroke's passes are laid at once (one colour: the order does not matter)."""
    height, width = buffer.shape[0], buffer.shape[1]
    grow = 0.0
    for p in range(passes.shape[0]):
        grow = max(grow, passes[p, 0])
    for s in range(ends.shape[0]):
        ax, ay, bx, by = ends[s, 0, 0], ends[s, 0, 1], ends[s, 1, 0], ends[s, 1, 1]
        dx, dy = bx - ax, by - ay
        ll = dx * dx + dy * dy
        inverse = 0.0 if ll == 0.0 else 1.0 / ll
        reach = radii[s] * grow + 0.5
        for y in range(max(int(math.floor(min(ay, by) - reach)), 0), min(int(math.ceil(max(ay, by) + reach)), height)):
            py = y + 0.5
            lo, hi = _stadium_cut(py, ax, ay, bx, by, reach)
            if lo > hi:
                continue
            out = buffer[height - 1 - y]
            qy = py - ay
            for x in range(max(int(math.floor(lo - 0.5)), 0), min(int(math.ceil(hi + 0.5)), width)):
                qx = x + 0.5 - ax
                t = min(max((qx * dx + qy * dy) * inverse, 0.0), 1.0)
                ex, ey = qx - t * dx, qy - t * dy
                d = math.sqrt(ex * ex + ey * ey)
                keep = 1.0
                for p in range(passes.shape[0]):
                    keep *= 1.0 - passes[p, 1] * min(max(radii[s] * passes[p, 0] + 0.5 - d, 0.0), 1.0)
                if keep < 1.0:
                    for c in range(3):
                        out[x, c] = np.uint8(rgb[c] + (out[x, c] - rgb[c]) * keep + 0.5)


@compiled(**_JIT)
def _stadium_cut(y: float, ax: float, ay: float, bx: float, by: float, r: float) -> tuple[float, float]:
    """The x interval (lo > hi: none) where the row at height ``y`` crosses the points within ``r``
    of the segment a-b: the hull of its crossings of the two end discs and of the band between them
    (the stadium is convex, so its crossing is one interval)."""
    lo, hi = np.inf, -np.inf
    for cx, cy in ((ax, ay), (bx, by)):
        h = y - cy
        if h * h <= r * r:
            half = math.sqrt(r * r - h * h)
            lo, hi = min(lo, cx - half), max(hi, cx + half)
    dx, dy = bx - ax, by - ay
    length = math.sqrt(dx * dx + dy * dy)
    if length == 0.0:
        return lo, hi
    ux, uy = dx / length, dy / length
    x0, x1 = -np.inf, np.inf
    across = (y - ay) * ux  # the band: (x - ax) uy - (y - ay) ux within [-r, r] ...
    if uy != 0.0:
        s, t = (across - r) / uy + ax, (across + r) / uy + ax
        x0, x1 = max(x0, min(s, t)), min(x1, max(s, t))
    elif abs(across) > r:
        return lo, hi
    along = (y - ay) * uy  # ... and (x - ax) ux + (y - ay) uy within [0, length]
    if ux != 0.0:
        s, t = -along / ux + ax, (length - along) / ux + ax
        x0, x1 = max(x0, min(s, t)), min(x1, max(s, t))
    elif along < 0.0 or along > length:
        return lo, hi
    if x0 <= x1:
        lo, hi = min(lo, x0), max(hi, x1)
    return lo, hi


_ONE = 1 << 16  # fixed point: coefficients times 2^16
_LUMA = 219.0 / 255.0  # limited range: 0-255 -> 16-235
_CHROMA = 224.0 / 255.0  # 0-255 -> 16-240 about 128
YR, YG, YB = (round(c * _LUMA * _ONE) for c in (0.299, 0.587, 0.114))
UR, UG, UB = (round(c * _CHROMA * _ONE) for c in (-0.168736, -0.331264, 0.5))
VR, VG, VB = (round(c * _CHROMA * _ONE) for c in (0.5, -0.418688, -0.081312))
Y_OFFSET = (16 << 16) + (1 << 15)  # + 16, and a half for rounding
C_OFFSET = (128 << 18) + (1 << 17)  # a chroma sum is of 4 pixels: 2^18
RED, GREEN, BLUE = (0, 8, 16) if sys.byteorder == "little" else (24, 16, 8)
"""Where a pixel's red, green and blue bytes sit in it read as one 32-bit word."""


@compiled(**_JIT)
def yuv420_planes(pixels: np.ndarray, width: int, out: np.ndarray) -> None:
    """:func:`armanim.render.video.planes.yuv420` of the frame's ``pixels`` (H W,) read as 32-bit words, ``width`` a row."""
    count = pixels.size
    for p in range(count):
        v = np.int32(pixels[p])
        r, g, b = (v >> RED) & 255, (v >> GREEN) & 255, (v >> BLUE) & 255  # type: ignore[operator,unused-ignore]  # numpy 2.5 stubs: int32 >> int
        out[p] = np.uint8((YR * r + YG * g + YB * b + Y_OFFSET) >> 16)  # (16-235: never past a byte)
    half = width // 2
    rows = count // width // 2
    reds, greens, blues = np.empty(half, np.int32), np.empty(half, np.int32), np.empty(half, np.int32)
    for i in range(rows):
        top = pixels[2 * i * width : (2 * i + 1) * width]
        bottom = pixels[(2 * i + 1) * width : (2 * i + 2) * width]
        for j in range(half):  # each block's sums first, then each plane: loops the compiler vectorises
            a, b, c, d = (
                np.int32(top[2 * j]),
                np.int32(top[2 * j + 1]),
                np.int32(bottom[2 * j]),
                np.int32(bottom[2 * j + 1]),
            )
            reds[j] = ((a >> RED) & 255) + ((b >> RED) & 255) + ((c >> RED) & 255) + ((d >> RED) & 255)  # type: ignore[operator,unused-ignore]  # numpy 2.5 stubs: int32 >> int
            greens[j] = ((a >> GREEN) & 255) + ((b >> GREEN) & 255) + ((c >> GREEN) & 255) + ((d >> GREEN) & 255)  # type: ignore[operator,unused-ignore]  # numpy 2.5 stubs: int32 >> int
            blues[j] = ((a >> BLUE) & 255) + ((b >> BLUE) & 255) + ((c >> BLUE) & 255) + ((d >> BLUE) & 255)  # type: ignore[operator,unused-ignore]  # numpy 2.5 stubs: int32 >> int
        cb = out[count + i * half : count + (i + 1) * half]
        for j in range(half):
            cb[j] = np.uint8((UR * reds[j] + UG * greens[j] + UB * blues[j] + C_OFFSET) >> 18)
        cr = out[count + (rows + i) * half : count + (rows + i + 1) * half]
        for j in range(half):
            cr[j] = np.uint8((VR * reds[j] + VG * greens[j] + VB * blues[j] + C_OFFSET) >> 18)
