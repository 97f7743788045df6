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
from matplotlib.transforms import IdentityTransform

from armanim.render.paint.style import BACKGROUND

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


def png_bytes(rgba: np.ndarray) -> bytes:
    """An (H, W, 4) uint8 image encoded as a PNG file's bytes."""
    import io

    from matplotlib.image import imsave

    buffer = io.BytesIO()
    imsave(buffer, np.ascontiguousarray(rgba), format="png")
    return buffer.getvalue()


def write_png(rgba: np.ndarray, path) -> None:
    """Write an (H, W, 4) uint8 image to a PNG atomically (temporary file, then replace);
    a write failure is an OutputError (exit 3)."""
    from armanim.output.atomic import write_bytes_atomic

    write_bytes_atomic(Path(path), png_bytes(rgba))


def in_pixels(artist, fig: Figure):
    """``artist``, attached to ``fig``, with its coordinates in the frame's pixels (origin bottom left)."""
    artist.set_figure(fig)
    artist.set_transform(IdentityTransform())
    return artist


def crop_sprite(drawn: np.ndarray, left: int, top: int, size: tuple[int, int]) -> Sprite | None:
    """A sprite of what is drawn on a scratch buffer, cropped to its drawn pixels and to the frame.

    Parameters
    ----------
    drawn : (h, w, 4) uint8 array
        The scratch canvas's RGBA buffer, rows top to bottom.
    left, top : int
        The frame column and row (from the top) of the scratch's top left pixel.
    size : (int, int)
        The frame's width and height.
    """
    width, height = size
    used_rows = np.flatnonzero(drawn[..., 3].any(axis=1))
    used_cols = np.flatnonzero(drawn[..., 3].any(axis=0))
    if not len(used_rows):
        return None
    rows = slice(max(top + used_rows[0], 0), min(top + used_rows[-1] + 1, height))
    cols = slice(max(left + used_cols[0], 0), min(left + used_cols[-1] + 1, width))
    if cols.stop <= cols.start or rows.stop <= rows.start:
        return None
    patch = drawn[rows.start - top : rows.stop - top, cols.start - left : cols.stop - left].astype(np.float32)
    alpha = patch[..., 3:] / 255.0
    return rows, cols, patch[..., :3] * alpha, 1.0 - alpha
