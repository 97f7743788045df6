"""Pixel buffers: Agg figures of an exact size, sprites stamped into a frame, PNG files.

A sprite is a small picture drawn once and composited into many frames:
``(rows, cols, premultiplied RGB (0-255), 1 - alpha)``, where ``rows`` and ``cols``
are the slices of the frame buffer (rows top to bottom) it covers. ``None`` is a
sprite that covers nothing (it lies outside the frame).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from armanim.render.style import BACKGROUND

Sprite = tuple[slice, slice, np.ndarray, np.ndarray]


def make_figure(width: int, height: int, dpi: float) -> tuple[Figure, FigureCanvasAgg]:
    """A Figure whose Agg buffer is exactly ``width`` x ``height`` pixels.

    The inch sizes get a thousandth of a pixel extra so float rounding cannot lose a pixel.
    """
    fig = Figure(figsize=((width + 1e-3) / dpi, (height + 1e-3) / dpi), dpi=dpi, facecolor=BACKGROUND)
    return fig, FigureCanvasAgg(fig)


def composite(buffer: np.ndarray, sprite: Sprite | None) -> None:
    """Alpha-composite ``sprite`` in place into an (H, W, 4) uint8 ``buffer``."""
    if sprite is None:
        return
    rows, cols, premultiplied, transparency = sprite
    region = buffer[rows, cols, :3]
    region[...] = (region * transparency + premultiplied + 0.5).astype(np.uint8)


def write_png(rgba: np.ndarray, path) -> None:
    """Write an (H, W, 4) uint8 image to a PNG atomically (temporary file, then replace);
    a write failure is an OutputError (exit 3)."""
    from matplotlib.image import imsave

    from armanim.output.atomic import temporary_beside

    with temporary_beside(Path(path)) as tmp:
        imsave(tmp, np.ascontiguousarray(rgba), format="png")
