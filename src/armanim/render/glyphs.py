"""Fast monospaced text: every printable ASCII character drawn once, then stamped.

Drawing a line of text with matplotlib lays it out and rasterises every glyph again
(about 8 ms for a caption at 1280x720, half a frame's drawing). A caption in a
monospaced font needs neither: each character sits at ``i x advance``. A
:class:`GlyphAtlas` rasterises the 95 printable characters once, with matplotlib,
into alpha sprites, and :meth:`GlyphAtlas.stamp` composites a string from them.
"""

from __future__ import annotations

import string

import numpy as np
from matplotlib.text import Text
from matplotlib.transforms import IdentityTransform

CHARACTERS = string.printable[:95]  # digits, letters, punctuation, space


class GlyphAtlas:
    """The printable characters of one monospaced font, size and colour, as sprites.

    Parameters
    ----------
    canvas : FigureCanvasAgg
        Its buffer is cleared while the atlas is built: build atlases before the
        first frame, then restore the background.
    fontsize : float
        Points.
    color : RGB tuple
    family : str
        A monospaced family.

    Attributes
    ----------
    advance : float
        Pixels from one character to the next.
    height : int
        Pixels of one line (a cell's height).
    """

    def __init__(self, canvas, fontsize: float, color, family: str = "DejaVu Sans Mono"):
        fig, renderer = canvas.figure, canvas.get_renderer()
        probe = Text(0, 0, "M" * 40, fontsize=fontsize, family=family, transform=IdentityTransform())
        probe.set_figure(fig)
        box = probe.get_window_extent(renderer)
        self.advance = box.width / 40.0
        self.height = int(np.ceil(box.height))
        cell = int(np.ceil(self.advance)) + 2
        self.sprites: dict[str, np.ndarray] = {}
        buffer_height = int(renderer.height)
        for char in CHARACTERS:
            renderer.clear()
            glyph = Text(1, 1, char, fontsize=fontsize, family=family, color=color, va="bottom", ha="left",
                         transform=IdentityTransform())
            glyph.set_figure(fig)
            glyph.draw(renderer)
            rgba = np.asarray(canvas.buffer_rgba())[buffer_height - 1 - self.height : buffer_height, :cell]
            self.sprites[char] = rgba.astype(np.float32) / 255.0
        renderer.clear()

    def width(self, text: str) -> float:
        """Pixels a one-line string takes."""
        return len(text) * self.advance

    def stamp(self, buffer: np.ndarray, text: str, x: float, top: float) -> None:
        """Composite ``text`` into an (H, W, 4) uint8 buffer (rows top to bottom),
        its first cell's left edge at pixel ``x`` and its top at ``top`` (origin bottom left)."""
        height, width = buffer.shape[:2]
        row0 = int(round(height - top))
        for i, char in enumerate(text):
            sprite = self.sprites.get(char)
            if sprite is None or char == " ":
                continue
            col0 = int(round(x + i * self.advance)) - 1
            rows = slice(max(row0, 0), min(row0 + sprite.shape[0], height))
            cols = slice(max(col0, 0), min(col0 + sprite.shape[1], width))
            if rows.stop <= rows.start or cols.stop <= cols.start:
                continue
            part = sprite[rows.start - row0 : rows.stop - row0, cols.start - col0 : cols.stop - col0]
            alpha = part[..., 3:]
            region = buffer[rows, cols, :3]
            region[...] = (region * (1.0 - alpha) + part[..., :3] * 255.0 * alpha + 0.5).astype(np.uint8)
