"""A joint-space path as frames: no joint faster than ``max_joint_step`` per frame,
starting and stopping smoothly. Pure core: numpy only."""

from __future__ import annotations

import numpy as np

PEAK_SPEED = 1.5  # the smoothstep's peak slope: the middle frames run at max_joint_step


def smoothstep(u: np.ndarray) -> np.ndarray:
    """3u^2 - 2u^3: 0 to 1 with zero speed at both ends.

    >>> smoothstep(np.array([0.0, 0.5, 1.0]))
    array([0. , 0.5, 1. ])
    """
    return u * u * (3.0 - 2.0 * u)


def path_frames(waypoints: np.ndarray, max_joint_step: float) -> np.ndarray:
    """(F, n) poses along the piecewise-linear path ``waypoints``, the first one excluded
    (it is the current pose) and the last one included.

    Progress along the path is measured in the largest joint change, so that no joint
    turns by more than ``max_joint_step`` between consecutive frames.

    >>> frames = path_frames(np.array([[0.0], [1.0]]), 0.1)
    >>> len(frames), float(frames[-1, 0]), bool(np.abs(np.diff(frames[:, 0])).max() <= 0.1)
    (15, 1.0, True)
    """
    legs = np.abs(np.diff(waypoints, axis=0)).max(axis=1)
    at = np.concatenate([[0.0], np.cumsum(legs)])
    length = at[-1]
    if length == 0.0:
        return waypoints[-1:].copy()
    count = int(np.ceil(PEAK_SPEED * length / max_joint_step))
    s = length * smoothstep(np.arange(1, count + 1) / count)
    leg = np.clip(np.searchsorted(at, s, side="right") - 1, 0, len(legs) - 1)
    fraction = np.where(legs[leg] > 0, (s - at[leg]) / np.where(legs[leg] > 0, legs[leg], 1.0), 1.0)
    return waypoints[leg] + fraction[:, None] * (waypoints[leg + 1] - waypoints[leg])
