"""A joint-space path as frames: no joint faster than ``max_joint_step`` per frame,
starting and stopping smoothly. Pure core: numpy only."""

from __future__ import annotations

from typing import cast

import numpy as np

from armanim.motion.problem import Problem

PEAK_SPEED = (
    1.5  # the smoothstep's peak slope (d/du of 3u^2 - 2u^3 at u = 1/2): the middle frames run at max_joint_step
)


def smoothstep(u: np.ndarray) -> np.ndarray:
    """3u^2 - 2u^3: 0 to 1 with zero speed at both ends.

    >>> smoothstep(np.array([0.0, 0.5, 1.0]))
    array([0. , 0.5, 1. ])
    """
    return cast(np.ndarray, u * u * (3.0 - 2.0 * u))


def path_frames(waypoints: np.ndarray, max_joint_step: float) -> np.ndarray:
    """(F, n) poses along the piecewise-linear path ``waypoints``, the first one excluded
    (it is the current pose) and the last one included.

    Progress along the path is measured in the largest joint change, so that no joint
    turns by more than ``max_joint_step`` between consecutive frames.

    >>> frames = path_frames(np.array([[0.0], [1.0]]), 0.1)
    >>> len(frames), float(frames[-1, 0]), bool(np.abs(np.diff(frames[:, 0])).max() <= 0.1)
    (15, 1.0, True)
    """
    return poses_along(waypoints, path_schedule(waypoints, max_joint_step))


def path_lengths(waypoints: np.ndarray) -> np.ndarray:
    """(k,) where each waypoint lies along the path, in the largest joint change from the first."""
    return np.concatenate([[0.0], np.cumsum(np.abs(np.diff(waypoints, axis=0)).max(axis=1))])


def path_schedule(waypoints: np.ndarray, max_joint_step: float, most: int | None = None) -> np.ndarray:
    """(F,) how far along the path each frame is: a smoothstep over the path's length, no
    joint above ``max_joint_step`` per frame; the first frame after the start to the end.

    At most ``most`` frames (the frames left to the goal): a longer path is followed as far
    as they go (the goal is then missed as ``too_slow`` at its frame cap), and only those
    frames are made, so a long path is never a huge array.

    >>> s = path_schedule(np.array([[0.0], [3.0]]), 1e-6, most=1000)
    >>> len(s), bool(s[-1] < 1e-3)
    (1000, True)
    """
    length = path_lengths(waypoints)[-1]
    if length == 0.0:
        return np.array([0.0])
    with np.errstate(over="ignore"):
        count = np.ceil(PEAK_SPEED * length / max_joint_step)  # may be huge, or inf: only ``most`` are made
    made = int(min(count, most)) if most is not None else int(count)
    return cast(np.ndarray, length * smoothstep(np.arange(1, made + 1) / count))


def poses_along(waypoints: np.ndarray, s: np.ndarray) -> np.ndarray:
    """(F, n) the poses ``s`` along the piecewise-linear path ``waypoints`` (see :func:`path_lengths`)."""
    at = path_lengths(waypoints)
    legs = np.diff(at)
    if at[-1] == 0.0:
        return np.repeat(waypoints[-1:], len(s), axis=0)
    leg = np.clip(np.searchsorted(at, s, side="right") - 1, 0, len(legs) - 1)
    fraction = np.where(legs[leg] > 0, (s - at[leg]) / np.where(legs[leg] > 0, legs[leg], 1.0), 1.0)
    return cast(np.ndarray, waypoints[leg] + fraction[:, None] * (waypoints[leg + 1] - waypoints[leg]))


def damper_paced(problem: Problem, waypoints: np.ndarray, s: np.ndarray, most: int | None = None) -> np.ndarray:
    """The schedule ``s`` (see :func:`path_schedule`) with frames inserted wherever the safety
    filter would not take a frame's step as it is.

    The filter's velocity damper lets a frame close at most ``gamma`` of what is left of the gap
    of each link to each surface and of each joint to its limits, as its linear constraints see
    it (:mod:`armanim.motion.filter.barrier`): a path that approaches faster is bent by the
    filter, and the arm leaves it. Each such frame interval is halved, the new frames on the
    path itself (not on chords across its corners), so the arm slows near surfaces and limits
    and stays on the path.

    Parameters
    ----------
    problem : Problem
    waypoints : (k, n) array
        The path, from the arm's pose.
    s : (F,) array
        How far along the path each frame is, increasing.
    most : int, optional
        The frames left to the goal: no halving makes the schedule longer than that (the arm
        then waits on the path where the filter holds it back).

    Returns
    -------
    (F',) array, F' >= F: the same frames with others in between.
    """
    from armanim.motion.filter.barrier import takes_unchanged
    from armanim.motion.solvers.common import arm_state

    s = np.concatenate([[0.0], s])
    settled = np.zeros(len(s) - 1, dtype=bool)  # intervals the filter takes as they are
    for _ in range(problem.tunables.planner.max_splits):
        poses = poses_along(waypoints, s)
        for k in np.flatnonzero(~settled).tolist():
            settled[k] = takes_unchanged(problem, arm_state(problem, poses[k]), poses[k + 1] - poses[k])
        too_fast = np.nonzero(~settled)[0]
        if not len(too_fast) or (most is not None and len(s) - 1 + len(too_fast) > most):
            break
        s = np.insert(s, too_fast + 1, 0.5 * (s[too_fast] + s[too_fast + 1]))
        settled = np.insert(settled, too_fast + 1, False)
        settled[too_fast] = False
    return s[1:]
