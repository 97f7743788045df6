"""The numbered goal markers: drawn once per goal and state into a sprite, then stamped.

Pending goals are grey rings, the current goal a gold star in a ring, reached goals
green dots, missed goals red crosses. A goal behind a sphere is drawn through it: its
marker open and dimmed, its number plain. Drawing markers and text every frame was a
third of a frame's time, so each (goal, state) is drawn the first time it is shown, on
a small scratch canvas, and kept as a sprite.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patheffects import withStroke
from matplotlib.text import Text
from matplotlib.transforms import Affine2D, IdentityTransform

from armanim.render.overlay.caption import CURRENT, MISSED, PENDING, REACHED
from armanim.render.paint import scenery
from armanim.render.paint.pixels import Sprite, composite, crop_sprite, in_pixels
from armanim.render.paint.style import FONT, GOAL_COLORS, HIDDEN_ALPHA, RING_POINTS, STATUS_NAMES, TEXT_COLOR

MARKER_STYLES: dict[int, dict[str, Any]] = {
    PENDING: dict(
        marker="o", markersize=9, markerfacecolor="white", markeredgecolor=GOAL_COLORS["pending"], markeredgewidth=1.8
    ),
    CURRENT: dict(
        marker="*",
        markersize=19,
        markerfacecolor=GOAL_COLORS["current"],
        markeredgecolor=(0.2, 0.15, 0.0),
        markeredgewidth=0.9,
    ),
    REACHED: dict(
        marker="o", markersize=10, markerfacecolor=GOAL_COLORS["reached"], markeredgecolor="white", markeredgewidth=1.2
    ),
    MISSED: dict(
        marker="X", markersize=12, markerfacecolor=GOAL_COLORS["missed"], markeredgecolor="white", markeredgewidth=1.0
    ),
}


def open_style(code: int) -> dict[str, Any]:
    """The marker of a path goal, at its path's start, once it is current, reached or missed: open,
    in the state's colour, so that the ink it stands on shows through it (a filled dot hid the
    first letter of ur5-pen's word)."""
    style = MARKER_STYLES[code]
    edge = style["markerfacecolor"] if code != PENDING else style["markeredgecolor"]
    return {**style, "markerfacecolor": "none", "markeredgecolor": edge, "markeredgewidth": 2.0}


def hidden_style(code: int) -> dict[str, Any]:
    """The marker of a goal behind a sphere: open, dimmed, edged in the state's colour."""
    style = MARKER_STYLES[code]
    edge = style["markerfacecolor"] if code != PENDING else style["markeredgecolor"]
    return {**style, "markerfacecolor": "none", "markeredgecolor": edge}


def shared_numbers(xy: np.ndarray, within: float = 0.5) -> list[str]:
    """Each goal's label: its number, or, where goals stand at one place on the screen (``xy``
    (N, 2) pixels, at most ``within`` apart; a goal that leads to a release's approach line
    stands where the line starts), all their numbers on the first of them and none on the others.

    >>> shared_numbers(np.array([[0.0, 0], [5, 5], [5, 5.2], [9, 0]]))
    ['0', '1, 2', '', '3']
    """
    texts = [str(i) for i in range(len(xy))]
    for i in range(len(xy)):
        if not texts[i]:
            continue
        same = [j for j in range(i + 1, len(xy)) if texts[j] and np.all(np.abs(xy[j] - xy[i]) <= within)]
        if same:
            texts[i] = ", ".join(str(k) for k in (i, *same))
            for j in same:
                texts[j] = ""
    return texts


class GoalMarkers:
    """Every goal's marker and number, for one camera and frame.

    Parameters
    ----------
    fig : Figure
        The frame's figure (its dpi sizes the text).
    screen : (N, 3) array
        Screen points (x px, y px, near) of the goals.
    hidden : (N,) bool array
        Goals behind a sphere.
    size : (int, int)
        The frame's width and height in pixels.
    open_goals : (N,) bool array, optional
        Goals drawn open (:func:`open_style`): path goals, whose marker stands on their ink.

    Attributes
    ----------
    xy : (N, 2) array
        Pixel positions of the markers.
    stamps : dict
        (goal, state code) -> sprite, filled as states are first shown.
    """

    def __init__(
        self,
        fig: Figure,
        screen: np.ndarray,
        hidden: np.ndarray,
        size: tuple[int, int],
        open_goals: np.ndarray | None = None,
    ):
        self.xy = screen[:, :2]
        self.hidden = hidden
        self.open = np.zeros(len(self.xy), dtype=bool) if open_goals is None else np.asarray(open_goals, dtype=bool)
        self.open_marks = {k: in_pixels(Line2D([], [], linestyle="none", **open_style(k)), fig) for k in MARKER_STYLES}
        self.size = size
        self.marks = {k: in_pixels(Line2D([], [], linestyle="none", **s), fig) for k, s in MARKER_STYLES.items()}
        self.hidden_marks = {
            k: in_pixels(Line2D([], [], linestyle="none", alpha=HIDDEN_ALPHA, **hidden_style(k)), fig)
            for k in MARKER_STYLES
        }
        self.ring = in_pixels(
            Line2D(
                [],
                [],
                linestyle="none",
                marker="o",
                markersize=RING_POINTS,
                markerfacecolor="none",
                markeredgecolor=GOAL_COLORS["current"],
                markeredgewidth=1.8,
                alpha=0.8,
            ),
            fig,
        )
        self.labels = [
            in_pixels(
                Text(
                    0,
                    0,
                    text,
                    ha="left",
                    va="bottom",
                    fontsize=FONT["goal"],
                    fontweight="bold",
                    path_effects=[withStroke(linewidth=2.5, foreground="white")],
                ),
                fig,
            )
            for text in shared_numbers(self.xy)
        ]
        self.stamps: dict[tuple[int, int], Sprite | None] = {}

    def place_labels(self, renderer, gap: float, keep_out: list, inside) -> dict[str, tuple]:
        """Put the numbers beside their markers, ``gap`` pixels out, clear of each other, of the
        ``keep_out`` boxes and inside the box ``inside``; returns their boxes by name ("goal 3")."""
        shown = [
            i for i, label in enumerate(self.labels) if label.get_text()
        ]  # a goal sharing its place is named on the first
        sizes = [(box.width, box.height) for box in (self.labels[i].get_window_extent(renderer) for i in shown)]
        if not sizes:
            return {}
        corners = scenery.place_labels(self.xy[shown], np.array(sizes), gap, keep_out, inside)
        boxes = {}
        for i, (x, y), (w, h) in zip(shown, corners, sizes):
            self.labels[i].set_position((x, y))
            boxes[f"goal {self.labels[i].get_text()}"] = (x, y, x + w, y + h)
        return boxes

    def largest_label(self, renderer) -> float:
        """Pixels: the width or the height, whichever is larger, of the widest goal number (0 without goals)."""
        label = max((lab.get_window_extent(renderer) for lab in self.labels), key=lambda box: box.width, default=None)
        return max(label.width, label.height) if label is not None else 0.0

    def draw(self, buffer: np.ndarray, status: np.ndarray, scratch: FigureCanvasAgg) -> None:
        """Stamp every goal in its state ``status`` (N,) into the frame ``buffer``, the current
        goal last; new sprites are drawn on ``scratch``, a square canvas at the frame's dpi."""
        for i in np.argsort(status == CURRENT, kind="stable"):
            key = (int(i), int(status[i]))
            if key not in self.stamps:
                self.stamps[key] = self._stamp(scratch, *key)
            composite(buffer, self.stamps[key])

    def _stamp(self, scratch: FigureCanvasAgg, i: int, code: int) -> Sprite | None:
        """Goal ``i``'s marker and number in state ``code``, drawn around the scratch's centre."""
        xy = self.xy[i]
        side = int(scratch.figure.bbox.width)
        x0, y0 = int(np.floor(xy[0])) - side // 2, int(np.floor(xy[1])) - side // 2
        shift = Affine2D().translate(-x0, -y0)
        renderer = scratch.get_renderer()
        renderer.clear()
        for artist in self._artists(i, code):
            if isinstance(artist, Line2D):
                artist.set_data([xy[0]], [xy[1]])
            artist.set_transform(shift)
            artist.draw(renderer)
            artist.set_transform(IdentityTransform())
        top = self.size[1] - (y0 + side)  # the scratch's first row, in frame rows
        return crop_sprite(np.asarray(scratch.buffer_rgba()), x0, top, self.size)

    def _artists(self, i: int, code: int) -> list:
        """What shows goal ``i`` in state ``code``: (the current goal's ring,) its marker and its number."""
        hidden = bool(self.hidden[i])
        label = self.labels[i]
        label.set_color(GOAL_COLORS[STATUS_NAMES[code]] if code != PENDING else TEXT_COLOR)
        label.set_alpha(1.0)  # the number stays readable; only the marker of a hidden goal is dimmed
        # a path goal still pending has drawn no ink: its ring is every pending goal's
        marks = self.hidden_marks if hidden else self.open_marks if self.open[i] and code != PENDING else self.marks
        artists = [marks[code], label]
        if code == CURRENT and not hidden:
            artists.insert(0, self.ring)
        return artists
