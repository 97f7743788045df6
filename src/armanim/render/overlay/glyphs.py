"""Fast monospaced text: every printable ASCII character drawn once, then stamped.

Drawing a line of text with matplotlib lays it out and rasterises every glyph again
(about 8 ms for a caption at 1280x720, half a frame's drawing). A caption in a
monospaced font needs neither: each character sits at ``i x advance``. A
:class:`GlyphAtlas` rasterises each printable character once, when first used, with matplotlib,
at a font size nudged so that the advance is a whole number of pixels; a line is
then one gather of character cells and one alpha blend.
"""

from __future__ import annotations

import numpy as np
from matplotlib.text import Text
from matplotlib.transforms import IdentityTransform

FIRST, LAST = 32, 126  # printable ASCII: space to tilde


class GlyphAtlas:
    """The printable characters of one monospaced font, size and colour, as cells.

    Parameters
    ----------
    canvas : FigureCanvasAgg
        A scratch canvas at the frame's dpi, at least one line high and a few
        characters wide; kept, and cleared whenever a character is first drawn (each
        character is drawn the first time a line uses it).
    fontsize : float
        Points; nudged (by less than half a pixel per character) so the advance is whole.
    color : RGB tuple
    family : str
        A monospaced family.

    Attributes
    ----------
    advance : int
        Pixels from one character to the next.
    height : int
        Pixels of one line (a cell's height).
    """

    def __init__(self, canvas, fontsize: float, color, family: str = "DejaVu Sans Mono"):
        self.canvas = canvas
        fig, renderer = canvas.figure, canvas.get_renderer()

        def text(s: str, size: float) -> Text:
            t = Text(
                0,
                0,
                s,
                fontsize=size,
                family=family,
                color=color,
                va="bottom",
                ha="left",
                transform=IdentityTransform(),
            )
            t.set_figure(fig)
            return t

        advance = text("M" * 40, fontsize).get_window_extent(renderer).width / 40.0
        self.advance = max(int(round(advance)), 1)
        size = fontsize * self.advance / advance
        self.height = int(np.ceil(text("Mg", size).get_window_extent(renderer).height))
        self._glyph = lambda char: text(char, size)
        self.cells = np.zeros((LAST - FIRST + 2, self.height, self.advance, 4), dtype=np.float32)  # last: unknown
        self.known = np.zeros(len(self.cells), dtype=bool)
        self.known[0] = True  # the space is empty
        self._draw_cells(np.array([ord("?") - FIRST]))
        self.cells[-1] = self.cells[ord("?") - FIRST]
        self.known[-1] = True
        self._last: tuple | None = None
        """The last stamp: (its row, column and length, the pixels under it, its text, its pixels,
        each (position, character) cell as blended over those pixels)."""

    def _draw_cells(self, codes: np.ndarray) -> None:
        """Rasterise the characters ``codes`` (offsets from the space) into their cells."""
        renderer = self.canvas.get_renderer()
        rows = int(renderer.height)
        for code in np.unique(codes):
            renderer.clear()
            self._glyph(chr(FIRST + int(code))).draw(renderer)
            rgba = np.asarray(self.canvas.buffer_rgba())[rows - self.height : rows, : self.advance].astype(np.float32)
            alpha = rgba[..., 3:] / 255.0
            self.cells[code] = np.concatenate([rgba[..., :3] * alpha, alpha], axis=-1)
            self.known[code] = True

    def line(self, text: str) -> np.ndarray:
        """(height, len(text) x advance, 4) premultiplied RGB (0-255) and alpha (0-1) of a line.

        Characters outside printable ASCII show as ``?``.
        """
        codes = np.frombuffer(text.encode("ascii", "replace"), dtype=np.uint8).astype(int) - FIRST
        codes[(codes < 0) | (codes > LAST - FIRST)] = len(self.cells) - 1
        if not self.known[codes].all():
            self._draw_cells(codes[~self.known[codes]])
        cells = self.cells[codes]  # (L, h, a, 4)
        return cells.transpose(1, 0, 2, 3).reshape(self.height, -1, 4)

    def width(self, text: str) -> int:
        """Pixels a one-line string takes."""
        return len(text) * self.advance

    def stamp(self, buffer: np.ndarray, text: str, x: float, top: float) -> None:
        """Blend ``text`` into an (H, W, 4) uint8 buffer (rows top to bottom), its left
        edge at pixel ``x`` and its top at ``top`` (origin bottom left).

        A video's caption changes a few characters a frame (the time, the distance) over the same
        pixels: while the pixels under a line wholly inside the buffer are the last stamp's, the
        last stamp's pixels are laid again and each changed character's cell is laid as it was
        blended there before (blended once), the same bytes (each pixel is blended on its own)."""
        height, width = buffer.shape[:2]
        row0, col0 = int(round(height - top)), int(round(x))
        rows = slice(max(row0, 0), min(row0 + self.height, height))
        cols = slice(max(col0, 0), min(col0 + self.width(text), width))
        if rows.stop <= rows.start or cols.stop <= cols.start:
            return
        region = buffer[rows, cols, :3]
        words = buffer[rows, cols].view(np.uint32)  # (the same pixels, a word each: compared and copied fast)
        inside = (rows.start, rows.stop, cols.start, cols.stop) == (
            row0,
            row0 + self.height,
            col0,
            col0 + self.width(text),
        )
        last = self._last
        if inside and last is not None and last[0] == (row0, col0, len(text)) and np.array_equal(words, last[1]):
            words[...] = last[3]
            under, blended, a = last[1], last[4], self.advance
            for k, (before, char) in enumerate(zip(last[2], text)):
                if before != char:
                    cell = blended.get((k, char))
                    if cell is None:
                        part = self.line(char)
                        below = under[:, k * a : (k + 1) * a].view(np.uint8)[..., :3]  # (its RGB bytes)
                        cell = (below * (1.0 - part[..., 3:]) + part[..., :3] + 0.5).astype(np.uint8)
                        blended[(k, char)] = cell
                    region[:, k * a : (k + 1) * a] = cell
            self._last = (last[0], under, text, words.copy(), blended)
            return
        under = words.copy()
        image = self.line(text)
        part = image[rows.start - row0 : rows.stop - row0, cols.start - col0 : cols.stop - col0]
        region[...] = (region * (1.0 - part[..., 3:]) + part[..., :3] + 0.5).astype(np.uint8)
        self._last = ((row0, col0, len(text)), under, text, words.copy(), {}) if inside else None
