"""What a frame shows that never changes, drawn once per scene into the background.

The floor (a light quad with a grid) and the soft shadows on it, the spheres'
influence shells, small world axes top right, the title, the legend (only what the
picture can show) and the caption's box. :class:`Sheet` draws artists given in pixel
coordinates and keeps the box of every text, so that goal numbers can be placed clear
of them.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from matplotlib.collections import LineCollection, PolyCollection
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.text import Text
from matplotlib.transforms import IdentityTransform

from armanim.render.camera.framing import Floor
from armanim.render.camera.view import View
from armanim.render.paint import scenery
from armanim.render.paint.style import (
    ARM_COLOR,
    AXIS_COLORS,
    FLOOR_COLOR,
    FONT,
    GHOST_COLOR,
    GOAL_COLORS,
    GRID_COLOR,
    HIDDEN_ALPHA,
    INK_COLOR,
    OBSTACLE_COLOR,
    SELF_NEAR_COLOR,
    SHADOW_COLOR,
    TEXT_COLOR,
    TRAIL_COLOR,
)
from armanim.render.solids.robot import GHOST_OUTLINE, NEAR_TINT

SHADOW_LAYERS = ((1.12, 0.05), (1.0, 0.06), (0.85, 0.07))  # (scale, opacity): nested discs of a soft shadow


class Sheet:
    """A figure being drawn on, artist by artist, in pixel coordinates.

    Attributes
    ----------
    text_boxes : dict
        Name -> (x0, y0, x1, y1) pixel box of every text drawn so far.
    """

    def __init__(self, fig: Figure, renderer):
        self.fig = fig
        self.renderer = renderer
        self.text_boxes: dict[str, tuple] = {}

    def draw(self, artist) -> None:
        """Draw ``artist``, whose coordinates (and offsets) are pixels."""
        artist.set_figure(self.fig)
        artist.set_transform(IdentityTransform())
        if hasattr(artist, "set_offset_transform"):
            artist.set_offset_transform(IdentityTransform())
        artist.draw(self.renderer)

    def text(self, name: str, text: Text) -> None:
        """Draw ``text`` and keep its box (its frame's, if it has one) as ``name``."""
        text.set_figure(self.fig)
        text.set_transform(IdentityTransform())
        text.draw(self.renderer)
        box = text.get_window_extent(self.renderer)
        patch = text.get_bbox_patch()
        if patch is not None:
            box = patch.get_window_extent(self.renderer)
        self.text_boxes[name] = tuple(box.extents)


def draw_floor(sheet: Sheet, view: View, floor: Floor, shadows: list[np.ndarray]) -> None:
    """The floor, its grid and soft shadows (nested translucent copies of each (k, 3) ring in ``shadows``)."""
    quad = PolyCollection([view.project(floor.quad())[:, :2]], facecolors=[FLOOR_COLOR], edgecolors="none")
    grid = LineCollection(
        list(view.project(scenery.floor_grid(floor.lo, floor.hi, floor.z))[..., :2]),
        colors=[GRID_COLOR],
        linewidths=0.6,
    )
    soft = []
    for scale, alpha in SHADOW_LAYERS:
        for ring in shadows:
            center = ring.mean(axis=0)
            soft.append((view.project(center + scale * (ring - center))[:, :2], alpha))
    shade = PolyCollection([p for p, _ in soft], facecolors=[(*SHADOW_COLOR, a) for _, a in soft], edgecolors="none")
    for artist in (quad, grid, shade):
        sheet.draw(artist)


def draw_shells(sheet: Sheet, shells: list[np.ndarray]) -> None:
    """The spheres' influence shells ((k, 2) pixel polygons), dashed and faint."""
    if shells:
        sheet.draw(
            PolyCollection(
                shells,
                facecolors="none",
                edgecolors=[(*OBSTACLE_COLOR, 0.35)],
                linestyles=[(0, (4, 4))],
                linewidths=0.8,
            )
        )


def draw_gizmo(sheet: Sheet, layout: scenery.Layout, rotation: np.ndarray) -> None:
    """Small world axes top right: x, y and z as the camera (``rotation``) sees them."""
    origin = np.array(layout.gizmo_xy)
    directions = rotation[:2].T  # rows: world x, y, z on screen
    for axis, (d, color) in enumerate(zip(directions, AXIS_COLORS)):
        tip = origin + layout.gizmo_len * d
        sheet.draw(Line2D([origin[0], tip[0]], [origin[1], tip[1]], color=color, linewidth=1.6, solid_capstyle="round"))
        if np.linalg.norm(d) > 0.3:
            place = origin + layout.gizmo_len * d * 1.45
        else:  # an axis along the line of sight: a dot, labelled beside it
            sheet.draw(
                Line2D(
                    [origin[0]],
                    [origin[1]],
                    marker="o",
                    markersize=5,
                    markerfacecolor="none",
                    markeredgecolor=color,
                    markeredgewidth=1.4,
                )
            )
            place = origin - 0.5 * layout.gizmo_len
        label = Text(
            float(place[0]),
            float(place[1]),
            "xyz"[axis],
            ha="center",
            va="center",
            fontsize=FONT["axis"],
            color=color,
            fontweight="bold",
        )
        sheet.text(f"axis {'xyz'[axis]}", label)


def draw_title(sheet: Sheet, layout: scenery.Layout, title: str) -> None:
    """The title, top left."""
    sheet.text(
        "title",
        Text(*layout.title_xy, title, ha="left", va="top", fontsize=FONT["title"], fontweight="bold", color=TEXT_COLOR),
    )


def draw_caption_box(sheet: Sheet, layout: scenery.Layout, template: str, points: float = FONT["caption"]) -> None:
    """The caption's box, sized for ``template`` at ``points``; the caption itself is stamped every frame."""
    sheet.text(
        "caption",
        Text(
            *layout.caption_xy,
            template,
            ha="left",
            va="top",
            fontsize=points,
            family="DejaVu Sans Mono",
            color=(0.0, 0.0, 0.0, 0.0),
            bbox=dict(boxstyle="round,pad=0.3", facecolor="white", edgecolor=(0.8, 0.8, 0.84), alpha=0.92),
        ),
    )


def draw_legend(sheet: Sheet, layout: scenery.Layout, entries: list[tuple[str, Line2D]]) -> None:
    """The legend, one row along the bottom, from (label, handle) ``entries``."""
    labels = [label for label, _ in entries]
    legend = sheet.fig.legend(
        [handle for _, handle in entries],
        labels,
        loc="center",
        bbox_to_anchor=(0.5, layout.legend_y / layout.height),
        ncols=len(labels),
        frameon=False,
        fontsize=FONT["legend"],
        handlelength=1.5,
        columnspacing=1.1,
        handletextpad=0.6,
        borderaxespad=0.0,
    )
    legend.draw(sheet.renderer)
    for i, text in enumerate(legend.get_texts()):
        sheet.text_boxes[f"legend {i}"] = tuple(text.get_window_extent(sheet.renderer).extents)


ROBOT_LEGEND_COLOR = (0.62, 0.64, 0.68)
"""The legend's swatch of a robot drawn with its meshes (their light grey, shaded)."""


def legend_entries(
    picture: str,
    *,
    trail: bool,
    obstacles: bool,
    outcomes: frozenset,
    hidden_goal: bool,
    hidden_by: str = "a sphere",
    goals: bool = True,
    robot: bool = False,
    paths: bool = False,
    near_self: bool = False,
) -> list[tuple[str, Line2D]]:
    """(label, handle) of what a picture shows.

    Parameters
    ----------
    picture : {"video", "pose", "poster"}
        A pose has no goal states and no path; a poster has final states, the path and
        the arm faintly on each goal; a video has a current and next goals.
    trail : bool
        The tip's path is drawn.
    obstacles : bool
        The scene has spheres.
    outcomes : set of str
        The goal outcomes shown, ``"reached"`` and / or ``"missed"``.
    hidden_goal : bool
        Some goal is behind a sphere (or a box or capsule).
    hidden_by : str
        What hides it, in the legend: ``"a sphere"``, or ``"an obstacle"`` among boxes, capsules and cylinders.
    goals : bool
        The picture has goals (``fk --png`` draws none, and names none).
    robot : bool
        The arm is drawn with its meshes: "robot", in the meshes' grey, names it.
    paths : bool
        Some goal is a path: its ink is drawn, named "ink" (a video's path ahead, dashed and
        faint in the ink's colour, is not named: a row of ten entries overflows a 640 px frame).
    near_self : bool
        Some link the picture shows is tinted amber, close to another link of the arm: named
        "near itself" (a tinted Panda read as a colour glitch without it).
    """
    marker: dict[str, Any] = dict(linestyle="none", markersize=8)
    name = "robot" if robot else "arm"
    entries = [(name, Line2D([], [], color=ROBOT_LEGEND_COLOR if robot else ARM_COLOR, linewidth=5))]
    if picture == "poster":
        ghost = (
            Line2D([], [], color=GHOST_OUTLINE, linewidth=2)
            if robot
            else Line2D([], [], color=GHOST_COLOR, linewidth=5)
        )
        entries.append((f"{name} on each goal", ghost))  # a robot's faint poses are outlines
    if near_self:
        tint = (
            (np.asarray(ROBOT_LEGEND_COLOR) * (1 - NEAR_TINT) + np.asarray(SELF_NEAR_COLOR) * NEAR_TINT)
            if robot
            else SELF_NEAR_COLOR
        )
        entries.append(("near itself", Line2D([], [], color=tuple(tint), linewidth=5)))  # as a mesh link is tinted
    if trail and picture != "pose":
        entries.append(("tip path", Line2D([], [], color=TRAIL_COLOR, linewidth=2)))
    if paths and picture != "pose":
        entries.append(("ink", Line2D([], [], color=INK_COLOR, linewidth=2)))
    if obstacles:
        entries.append(
            ("obstacle", Line2D([], [], marker="o", markerfacecolor=OBSTACLE_COLOR, markeredgecolor="none", **marker))
        )
    pending = Line2D(
        [],
        [],
        marker="o",
        markerfacecolor="white",
        markeredgecolor=GOAL_COLORS["pending"],
        markeredgewidth=1.5,
        **marker,
    )
    if picture == "pose":
        entries += [("goal", pending)] if goals else []
    else:
        entries += goal_entries(picture, outcomes, pending, marker)
    if hidden_goal:
        entries.append(
            (
                f"behind {hidden_by}",
                Line2D(
                    [],
                    [],
                    marker="o",
                    markerfacecolor="none",
                    alpha=HIDDEN_ALPHA,
                    markeredgecolor=GOAL_COLORS["pending"],
                    **marker,
                ),
            )
        )
    return entries


def goal_entries(
    picture: str, outcomes: frozenset, pending: Line2D, marker: dict[str, Any]
) -> list[tuple[str, Line2D]]:
    """The goal states a video or a poster shows: current and next (a video's), reached, missed."""
    entries = []
    if picture == "video":
        entries += [
            (
                "current goal",
                Line2D(
                    [],
                    [],
                    marker="*",
                    markerfacecolor=GOAL_COLORS["current"],
                    markeredgecolor="k",
                    markeredgewidth=0.6,
                    **{**marker, "markersize": 12},
                ),
            ),
            ("next goal", pending),
        ]
    shown = [
        (
            "reached",
            Line2D([], [], marker="o", markerfacecolor=GOAL_COLORS["reached"], markeredgecolor="white", **marker),
        ),
        (
            "missed",
            Line2D([], [], marker="X", markerfacecolor=GOAL_COLORS["missed"], markeredgecolor="white", **marker),
        ),
    ]
    return entries + [entry for entry in shown if entry[0] in outcomes]
