"""How the pictures look: colours, sizes and fonts of the frames, the poster and the plot.

Colours are RGB in 0..1. Sizes in points scale with the frame (see
:func:`armanim.render.paint.scenery.frame_layout`); the others are ratios or pixels, as noted.
"""

from __future__ import annotations

import numpy as np

BACKGROUND = (1.0, 1.0, 1.0)
FLOOR_COLOR = (0.955, 0.96, 0.97)
GRID_COLOR = (0.84, 0.85, 0.88)
SHADOW_COLOR = (0.25, 0.27, 0.32)
ARM_COLOR = (0.16, 0.42, 0.80)
SELF_NEAR_COLOR = (0.93, 0.66, 0.12)
"""Both capsules of an enabled pair of the arm's own links within twice ``self_clearance``: why the
elbow swings out."""
JOINT_COLOR = (0.16, 0.17, 0.20)
JOINT_HIGHLIGHT = (0.55, 0.57, 0.62)
BASE_COLOR = (0.50, 0.52, 0.56)
OBSTACLE_COLOR = (0.85, 0.30, 0.25)
TRAIL_COLOR = (0.95, 0.55, 0.05)
TEXT_COLOR = (0.12, 0.12, 0.15)
INK_COLOR = (0.06, 0.08, 0.24)
"""A path goal's ink: the path behind the tool, pen down (blue-black, as a marker's)."""
INK_POINTS = 1.4  # the ink's width: about 2 px in a 960 x 540 frame, scaling with the frame
AHEAD_ALPHA = 0.6  # the path still ahead of the tool: the ink's colour, this opaque ...
AHEAD_POINTS = 1.0  # ... this thin ...
AHEAD_DASHES = (3.0, 2.0)  # ... and dashed (lengths in line widths)
AXIS_COLORS = ((0.80, 0.20, 0.20), (0.15, 0.60, 0.20), (0.20, 0.35, 0.85))
GOAL_COLORS = {
    "pending": (0.45, 0.47, 0.52),
    "current": (1.00, 0.76, 0.00),
    "reached": (0.13, 0.62, 0.28),
    "missed": (0.85, 0.10, 0.10),
}
STATUS_NAMES = ("pending", "current", "reached", "missed")  # by status code (armanim.render.overlay.caption)

PRISM_SIDES = 10  # faces around a link
CIRCLE_SIDES = 24  # polygon sides of a drawn circle (joints, base, influence shells)
JOINT_SCALE = 1.45  # joint dot radius / link half width
BASE_SCALE = 3.0  # pedestal radius / link half width
RING_POINTS = 27  # diameter of the ring around the current goal
FACE_EDGE_PX = 0.7  # faces are outlined in their own colour to close seams
GHOST_FADE = 0.7  # a poster's faint poses: the arm's colours this much toward white
GHOST_COLOR = tuple(np.array(ARM_COLOR) * (1 - GHOST_FADE) + GHOST_FADE)
HIDDEN_ALPHA = 0.55  # opacity of a goal marker seen through a sphere
FONT = {"title": 13, "caption": 10.5, "legend": 9, "goal": 9, "axis": 8}  # points


def with_alpha(rgb: np.ndarray, alpha: float) -> np.ndarray:
    """(..., 3) colours -> (..., 4) with a constant alpha.

    >>> with_alpha(np.array([1.0, 0.5, 0.0]), 0.25).tolist()
    [[1.0, 0.5, 0.0, 0.25]]
    """
    rgb = np.atleast_2d(rgb)
    return np.concatenate([rgb, np.full(rgb.shape[:-1] + (1,), alpha)], axis=-1)
