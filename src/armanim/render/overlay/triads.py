"""Orientation triads: the tool frame's axes at the tip, and each oriented goal's, faintly.

Drawn only when a goal of the scene has an orientation (``orientation`` or ``tool_axis``), so
pictures of position-only scenes are as they were. The x, y and z axes are red, green and blue
(the world gizmo's colours); a tool-axis goal, which sets only the tool's z, is one blue arrow.
Lengths are a fraction of the arm's reach, in world units, so the projection foreshortens them
as it does the arm.
"""

from __future__ import annotations

import numpy as np
from matplotlib.collections import LineCollection

from armanim.render.paint.style import AXIS_COLORS

TRIAD_PER_REACH = 0.12
"""Length of a triad's axes as a fraction of the arm's reach."""
GOAL_ALPHA = 0.45
"""Opacity of a goal's triad: faint beside the tool's."""


def has_orientations(goals) -> bool:
    """Whether any goal sets an orientation (the pictures then show triads)."""
    return any(g.orientation is not None for g in goals)


def frame_segments(origin: np.ndarray, rot: np.ndarray, length: float) -> tuple[np.ndarray, list]:
    """World segments (3, 2, 3) of a frame's x, y, z axes from ``origin``, and their colours.

    >>> segments, colors = frame_segments(np.zeros(3), np.eye(3), 2.0)
    >>> segments[2].tolist(), len(colors)
    ([[0.0, 0.0, 0.0], [0.0, 0.0, 2.0]], 3)
    """
    ends = origin[None, :] + length * np.asarray(rot, dtype=float).T
    return np.stack([np.broadcast_to(origin, (3, 3)), ends], axis=1), list(AXIS_COLORS)


def goal_segments(goals, length: float) -> tuple[np.ndarray, list]:
    """World segments (k, 2, 3) and colours of every oriented goal's triad (one z arrow for a
    tool-axis goal)."""
    segments, colors = [], []
    for goal in goals:
        o = goal.orientation
        if o is None:
            continue
        if o.rotation is not None:
            seg, col = frame_segments(np.asarray(goal.position, dtype=float), o.rotation, length)
            segments.append(seg)
            colors += col
        else:
            segments.append(np.stack([goal.position, goal.position + length * o.axis])[None])
            colors.append(AXIS_COLORS[2])
    return (np.concatenate(segments) if segments else np.zeros((0, 2, 3))), colors


def screen_lines(view, segments: np.ndarray, colors: list, alpha: float, width_pt: float) -> LineCollection:
    """A collection of ``segments`` projected to pixels (its transform still to be set)."""
    xy = view.project(segments)[..., :2] if len(segments) else np.zeros((0, 2, 2))
    rgba = [(*c, alpha) for c in colors]
    return LineCollection(list(xy), colors=rgba, linewidths=width_pt, capstyle="round")


def arrow_heads(view, segments: np.ndarray, colors: list, alpha: float, size_px: float) -> LineCollection:
    """Two short strokes at each segment's far end, on screen: an arrow head."""
    xy = view.project(segments)[..., :2] if len(segments) else np.zeros((0, 2, 2))
    heads, rgba = [], []
    for (a, b), c in zip(xy, colors):
        d = b - a
        length = np.linalg.norm(d)
        if length < 1e-9:
            continue
        d = d / length
        n = np.array([-d[1], d[0]])
        for side in (1.0, -1.0):
            heads.append(np.stack([b, b - size_px * d + side * 0.5 * size_px * n]))
            rgba.append((*c, alpha))
    return LineCollection(heads, colors=rgba, linewidths=1.4, capstyle="round")
