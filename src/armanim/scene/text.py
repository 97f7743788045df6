"""Text as a tool path: a string laid out on a board in the bundled single-stroke font.

The font is the Hershey Roman simplex (``fonts/futural.json``, written by
``tools/bundle_font.py``; its notice is in ``fonts/README.md``): each character's strokes in
integer font units, x from its left side, y up from the baseline, capitals ``cap_height``
units tall. :func:`text_path` scales them so that a capital is ``height`` tall and lays them
on the board: x along ``right`` from ``origin`` (the baseline's left end), y along ``up``.
The board's front is the side ``right x up`` points to: the text reads correctly from there,
and the pen lifts off the board toward it between strokes.

>>> p = text_path("I", np.zeros(3), 2.1, np.array([0.0, -1, 0]), np.array([0.0, 0, 1]), 0.5)
>>> [piece.ink for piece in p.pieces], np.round(p.start, 12).tolist(), np.round(p.end, 12).tolist()
([True], [0.0, -0.4, 2.1], [0.0, -0.4, 0.0])
"""

from __future__ import annotations

import functools
import json
from dataclasses import dataclass
from importlib import resources

import numpy as np

from armanim.motion.toolpath import Piece, ToolPath

FONT_FILE = "futural.json"


@dataclass(frozen=True)
class Font:
    """A single-stroke font.

    Attributes
    ----------
    cap_height : float
        Height of a capital letter, font units.
    advances : dict of str to float
        Each character's advance width, font units.
    strokes : dict of str to tuple of (m, 2) arrays
        Each character's strokes, font units: x from its left side, y up from the baseline.
    """

    cap_height: float
    advances: dict[str, float]
    strokes: dict[str, tuple[np.ndarray, ...]]


@functools.cache
def bundled_font() -> Font:
    """The bundled Hershey Roman simplex font (printable ASCII, 32..126)."""
    text = resources.files("armanim.scene").joinpath("fonts", FONT_FILE).read_text(encoding="utf-8")
    data = json.loads(text)
    glyphs = data["glyphs"]
    return Font(
        cap_height=float(data["cap_height"]),
        advances={c: float(g["advance"]) for c, g in glyphs.items()},
        strokes={c: tuple(np.array(s, dtype=float).reshape(-1, 2) for s in g["strokes"]) for c, g in glyphs.items()},
    )


def missing_characters(string: str, font: Font | None = None) -> list[str]:
    """The characters of ``string`` the font lacks, each once, in order of first appearance.

    >>> missing_characters("café\\tcafé")
    ['é', '\\t']
    """
    font = font or bundled_font()
    return list(dict.fromkeys(c for c in string if c not in font.advances))


def text_strokes(string: str, font: Font | None = None) -> list[np.ndarray]:
    """The strokes of ``string`` laid left to right, in font units (each (m, 2): x from the
    text's left end, y up from the baseline); spaces and strokes without length left out.

    >>> [s.tolist() for s in text_strokes("-")]
    [[[4.0, 9.0], [22.0, 9.0]]]
    """
    font = font or bundled_font()
    out, x = [], 0.0
    for c in string:
        for stroke in font.strokes[c]:
            if len(stroke) >= 2 and np.any(stroke != stroke[0]):
                out.append(stroke + [x, 0.0])
        x += font.advances[c]
    return out


def text_width(string: str, height: float, font: Font | None = None) -> float:
    """How far the text's advances reach along ``right`` at ``height`` (scene units).

    >>> text_width("II", 2.1)
    1.6
    """
    font = font or bundled_font()
    return float(sum(font.advances[c] for c in string)) * height / font.cap_height


def board_normal(right: np.ndarray, up: np.ndarray) -> np.ndarray:
    """(3,) the unit normal of the board's front, ``right x up``: the side the text reads from.

    >>> board_normal(np.array([0.0, -1, 0]), np.array([0.0, 0, 1])).tolist()
    [-1.0, 0.0, 0.0]
    """
    n = np.cross(right, up)
    return n / np.linalg.norm(n)


def text_path(
    string: str,
    origin: np.ndarray,
    height: float,
    right: np.ndarray,
    up: np.ndarray,
    lift: float,
    font: Font | None = None,
) -> ToolPath:
    """``string`` written on the board as one tool path.

    Parameters
    ----------
    string : str
        Characters the font has (:func:`missing_characters` is empty), at least one stroke.
    origin : (3,) array
        The baseline's left end, on the board.
    height : float
        A capital letter's height, scene units (> 0).
    right, up : (3,) arrays
        Unit directions on the board, square to each other: the text runs along ``right``,
        its letters stand along ``up``.
    lift : float
        How far the pen lifts off the board between strokes, toward its front
        (:func:`board_normal`), scene units.
    font : Font, optional
        Default the bundled font.

    Returns
    -------
    ToolPath
        Starts at the first stroke's first point and ends at the last stroke's end, pen down;
        each stroke a polyline that leaves ink; between strokes the pen goes up by ``lift``,
        straight to above the next stroke's start, and down (three pieces without ink; none
        when the next stroke starts where the last ended).
    """
    font = font or bundled_font()
    origin, right, up = (np.asarray(v, dtype=float) for v in (origin, right, up))
    scale = height / font.cap_height
    lifted = lift * board_normal(right, up)
    pieces: list[Piece] = []
    for stroke in text_strokes(string, font):
        points = origin + scale * (stroke[:, :1] * right + stroke[:, 1:] * up)
        if pieces and np.any(pieces[-1].end != points[0]):
            pieces += ToolPath.polyline(
                np.array([pieces[-1].end, pieces[-1].end + lifted, points[0] + lifted, points[0]]), ink=False
            ).pieces
        pieces += ToolPath.polyline(points).pieces
    return ToolPath(tuple(pieces))
