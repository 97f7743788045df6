"""What surrounds the arm: the frame's layout, the floor, shadows and label placement.

Pure numpy geometry (no matplotlib): :mod:`armanim.render.pictures.backdrop` and
:mod:`armanim.render.overlay.markers` turn it into artists.
Sizes are fractions of the frame, so a picture looks the same at every size.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

INCHES_HIGH = 5.0  # figure height in inches: fonts scale with the frame
INCHES_WIDE = INCHES_HIGH * 16 / 9  # ... or with its width, for frames narrower than 16:9
LEAST_DPI = 10.0
"""The figure's least dots per inch. FreeType draws no glyph under one pixel a em, and matplotlib
hands it the dpi as a whole number: at a frame's own dpi, 16 x 16 to 48 x 27 (or 200 x 16) made the
smallest caption (6.3 points, its glyphs some 4.5) less than half a pixel and ended the run in a
RuntimeError (campaign 9). At 10, text is at least 0.6 pixels a em; a frame this small shows its
text larger than its share, cut, while the layout keeps its proportions."""
FLOOR_DROP = 0.02  # the floor sits this fraction of the scene's size under its lowest point
FLOOR_PAD = 0.05  # the floor reaches this fraction of the scene's size beyond its footprint
GRID_LINES = 8  # about this many grid lines across the floor


@dataclass(frozen=True)
class Layout:
    """Where things go in a frame, in pixels (origin bottom left, y up).

    Attributes
    ----------
    width, height : int
    dpi : float
        Dots per inch of the figure: text sizes in points scale with it (at least :data:`LEAST_DPI`).
    scene : (x0, y0, x1, y1)
        The rectangle the scene is fitted into.
    title_xy, caption_xy : (x, y)
        Top left corners of the title and of the caption.
    gizmo_xy : (x, y)
        Centre of the world axes.
    gizmo_len : float
        Length of one world axis, pixels.
    legend_y : float
        Centre line of the legend.
    """

    width: int
    height: int
    dpi: float
    scene: tuple[float, float, float, float]
    title_xy: tuple[float, float]
    caption_xy: tuple[float, float]
    gizmo_xy: tuple[float, float]
    gizmo_len: float
    legend_y: float


def frame_layout(width: int, height: int, *, legend: bool = True) -> Layout:
    """The layout of a ``width`` x ``height`` frame: title and caption top left, world
    axes top right, legend along the bottom, the scene in between.

    >>> lay = frame_layout(1280, 720)
    >>> lay.dpi, lay.scene[1] < lay.scene[3] < lay.caption_xy[1]
    (144.0, True)
    """
    unit = min(height / INCHES_HIGH, width / INCHES_WIDE) * INCHES_HIGH  # the height of a 16:9 frame of this text size
    dpi = max(unit / INCHES_HIGH, LEAST_DPI)
    top = height - 0.025 * unit
    caption_top = top - 0.1 * unit
    scene_top = caption_top - 0.085 * unit
    scene_bottom = (0.085 if legend else 0.03) * unit
    side = 0.02 * unit
    return Layout(
        width=width,
        height=height,
        dpi=dpi,
        scene=(side, scene_bottom, width - side, scene_top),
        title_xy=(0.015 * unit, top),
        caption_xy=(0.015 * unit, caption_top),
        gizmo_xy=(width - 0.06 * unit, height - 0.052 * unit),
        gizmo_len=0.028 * unit,
        legend_y=0.04 * unit,
    )


def floor_height(lowest: float, size: float) -> float:
    """z of the floor: a little under the lowest point of the scene.

    >>> floor_height(0.0, 10.0)
    -0.2
    """
    return lowest - FLOOR_DROP * size


def floor_rect(low: np.ndarray, high: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The floor's xy rectangle: the scene's footprint, padded; (2,) lows and highs.

    >>> floor_rect(np.array([0.0, 0]), np.array([10.0, 5]))
    (array([-0.5, -0.5]), array([10.5,  5.5]))
    """
    pad = FLOOR_PAD * float(np.max(high - low))
    return low - pad, high + pad


def nice_step(span: float, lines: int = GRID_LINES) -> float:
    """A 1, 2 or 5 times a power of ten near ``span / lines``.

    >>> nice_step(17.0), nice_step(3.0), nice_step(0.9)
    (2.0, 0.5, 0.1)
    """
    raw = max(span, 1e-12) / lines
    power = 10.0 ** np.floor(np.log10(raw))
    for m in (1.0, 2.0, 5.0, 10.0):
        if raw <= m * power * 1.5:
            return float(m * power)
    return float(10.0 * power)


def floor_grid(low: np.ndarray, high: np.ndarray, z: float) -> np.ndarray:
    """Grid lines on the floor rectangle at height ``z``: (L, 2, 3) world segments.

    >>> floor_grid(np.array([0.0, 0]), np.array([1.0, 1]), 0.0).shape
    (22, 2, 3)
    """
    step = nice_step(float(np.max(high - low)))
    xs = np.arange(np.ceil(low[0] / step), np.floor(high[0] / step) + 1) * step
    ys = np.arange(np.ceil(low[1] / step), np.floor(high[1] / step) + 1) * step
    along_y = [[[x, low[1], z], [x, high[1], z]] for x in xs]
    along_x = [[[low[0], y, z], [high[0], y, z]] for y in ys]
    return np.array(along_y + along_x, dtype=float).reshape(-1, 2, 3)


def on_floor(points: np.ndarray, z: float) -> np.ndarray:
    """Points dropped straight down onto the floor (the light is overhead).

    >>> on_floor(np.array([[1.0, 2, 3]]), -1.0)
    array([[ 1.,  2., -1.]])
    """
    dropped = np.array(points, dtype=float, copy=True)
    dropped[..., 2] = z
    return dropped


def floor_circle(center: np.ndarray, radius: float, z: float, sides: int = 32) -> np.ndarray:
    """A circle of ``radius`` on the floor under ``center``: (sides, 3) world points."""
    theta = np.linspace(0.0, 2 * np.pi, sides, endpoint=False)
    ring = np.column_stack([np.cos(theta), np.sin(theta), np.zeros(sides)]) * radius
    return on_floor(center[None, :], z) + ring


def boxes_overlap(a, b, pad: float = 0.0) -> bool:
    """Whether two (x0, y0, x1, y1) boxes intersect (touching counts, grown by ``pad``).

    >>> boxes_overlap((0, 0, 1, 1), (1, 1, 2, 2)), boxes_overlap((0, 0, 1, 1), (1.5, 0, 2, 1))
    (True, False)
    """
    return not (a[2] + pad < b[0] or b[2] + pad < a[0] or a[3] + pad < b[1] or b[3] + pad < a[1])


LABEL_DIRECTIONS = np.array([[1, 1], [-1, 1], [1, -1], [-1, -1], [1, 0], [-1, 0], [0, 1], [0, -1]], dtype=float)


def place_labels(anchors: np.ndarray, sizes: np.ndarray, gap: float, keep_out: list, inside) -> np.ndarray:
    """Put one label beside each anchor so that no two labels (nor a label and a
    ``keep_out`` box or another anchor's marker) overlap.

    Parameters
    ----------
    anchors : (N, 2) array
        Marker centres, pixels.
    sizes : (N, 2) array
        Width and height of each label, pixels.
    gap : float
        Distance from a marker's centre to its label's nearest corner, and the
        half size of a marker.
    keep_out : list of (x0, y0, x1, y1)
        Boxes no label may touch (titles, legend...).
    inside : (x0, y0, x1, y1)
        Labels stay in this box when they can.

    Returns
    -------
    (N, 2) array
        The lower-left corner of every label. When no direction is free, the
        first one is used (the least bad is not searched for).

    Examples
    --------
    Two anchors close together get labels on different sides:

    >>> place_labels(np.array([[50.0, 50], [60, 50]]), np.full((2, 2), 8.0), 4.0, [], (0, 0, 100, 100))
    array([[38., 54.],
           [64., 54.]])
    """
    markers = [(x - gap, y - gap, x + gap, y + gap) for x, y in anchors]
    taken = list(keep_out) + markers
    corners = np.zeros((len(anchors), 2))
    for i, ((x, y), (w, h)) in enumerate(zip(anchors, sizes)):
        options = []
        for dx, dy in LABEL_DIRECTIONS:
            cx = x + dx * (gap + w / 2) if dx else x
            cy = y + dy * (gap + h / 2) if dy else y
            options.append((cx - w / 2, cy - h / 2, cx + w / 2, cy + h / 2))
        own = markers[i]
        free = [
            b for b in options if all(not boxes_overlap(b, t) for t in taken if t is not own) and _within(b, inside)
        ]
        box = free[0] if free else options[0]
        taken.append(box)
        corners[i] = box[:2]
    return corners


def _within(box, outer) -> bool:
    return box[0] >= outer[0] and box[1] >= outer[1] and box[2] <= outer[2] and box[3] <= outer[3]
