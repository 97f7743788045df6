"""What a frame says: each goal's marker state and the caption line.

Goals are numbered from 0 everywhere a person reads them (caption, markers, plot,
tables), as in trajectory.csv, summary.json and the scene's field paths (``goals[0]``).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

STILL = 1e-4  # radians: a frame whose joints all turn less than this is a still arm
PENDING, CURRENT, REACHED, MISSED = 0, 1, 2, 3


def goal_status(trajectory, reports: Sequence, frame: int, goals: int) -> np.ndarray:
    """Status code of every goal at ``frame`` (PENDING, CURRENT, REACHED or MISSED).

    Goals before the frame's goal are reached or missed as their reports say, the
    frame's goal is current (or reached once within tolerance), later ones pending.

    >>> import types
    >>> t = types.SimpleNamespace(goal=np.array([0, 1]), reached=np.array([False, False]))
    >>> r = [types.SimpleNamespace(reached=False)]
    >>> goal_status(t, r, 1, 3).tolist()
    [3, 1, 0]
    """
    k = int(trajectory.goal[frame])
    status = np.full(goals, PENDING)
    for j in range(min(k, goals)):
        status[j] = REACHED if j >= len(reports) or reports[j].reached else MISSED
    if k < goals:
        status[k] = REACHED if trajectory.reached[frame] or _passes(trajectory, reports, frame) else CURRENT
    return status


def _passes(trajectory, reports: Sequence, frame: int) -> bool:
    """Whether ``frame`` passes its goal without stopping: the goal's report says it was blended
    (``blend``) and the tool is within the goal's radius (a joint goal's: its pass frame)."""
    k = int(trajectory.goal[frame])
    blend = getattr(reports[k], "blend", None) if k < len(reports) else None
    if blend is None or not blend.blended:
        return False
    if blend.joint:  # its radius is in the joints, the distance column the tool's
        return frame == reports[k].last_frame
    return bool(trajectory.distance[frame] <= max(blend.radius, blend.pass_distance))


def passing_frames(trajectory, reports: Sequence) -> np.ndarray:
    """(F,) bool: the frames that pass a via goal within its radius (:func:`goal_status` draws the
    goal as passed there, the caption says "passing")."""
    out = np.zeros(len(trajectory.phi), dtype=bool)
    for r in reports:
        blend = getattr(r, "blend", None)
        if blend is not None and blend.blended and r.last_frame >= 0:
            mine = np.arange(r.first_frame, r.last_frame + 1)
            out[mine] = [_passes(trajectory, reports, int(f)) for f in mine]
    return out


def frame_modes(trajectory) -> np.ndarray:
    """(F,) "ik" or "plan" per frame; a trajectory without a ``mode`` is all "ik"."""
    mode = getattr(trajectory, "mode", None)
    if mode is None:
        return np.full(trajectory.frames, "ik")
    return np.asarray(mode).astype(str)


def arm_still(phi: np.ndarray) -> np.ndarray:
    """(F,) bool: no joint turned more than ``STILL`` since the previous frame (frame 0 moves).

    >>> arm_still(np.array([[0.0], [0.5], [0.5]])).tolist()
    [False, False, True]
    """
    still = np.zeros(len(phi), dtype=bool)
    still[1:] = np.abs(np.diff(phi, axis=0)).max(axis=1, initial=0.0) < STILL
    return still


def frame_activity(trajectory, reports: Sequence) -> np.ndarray:
    """What the arm does at every frame: planning, following (a path goal's tool along its path),
    holding, reached, passing (a goal with ``blend`` passed within its radius without stopping),
    moving, stalled or "missed: <reason>" (during the last second of a goal its report says was missed).

    Returns
    -------
    (F,) array of str
    """
    still = arm_still(trajectory.phi)
    mode = frame_modes(trajectory)
    activity = np.where(
        trajectory.reached, np.where(still, "holding", "reached"), np.where(still, "stalled", "moving")
    ).astype(object)
    activity[mode == "plan"] = "planning"
    activity[(mode == "path") & ~still] = (
        "following"  # on the path, not at a goal: the pen writes (a path's hold still says holding)
    )
    activity[passing_frames(trajectory, reports)] = "passing"  # a via goal: within its radius, not stopping
    for r in reports:
        if r.reached or r.last_frame < 0:
            continue
        first = max(r.first_frame, int(np.floor(r.last_frame - trajectory.fps)) + 1)
        activity[first : r.last_frame + 1] = "missed: " + (r.reason or "not reached").replace("_", " ")
    return activity


def frame_caption(trajectory, frame: int, goals: int, activity: str, speed_limits: np.ndarray | None = None) -> str:
    """The caption of a frame: time, goal (0-based, of how many), distance, the tool's angle to
    the goal's orientation (only while the goal has one), the limiting joint's speed as a share
    of its limit (with ``speed_limits``, rad/s, on a trajectory with velocities) and activity.

    >>> import types
    >>> t = types.SimpleNamespace(goal=np.array([1]), distance=np.array([0.5]), fps=30.0)
    >>> frame_caption(t, 0, 4, "moving")
    't =   0.00 s   goal 1 (of 0-3)   distance    0.500   moving'
    >>> t.velocity = np.array([[0.5, -1.5]])
    >>> frame_caption(t, 0, 4, "moving", np.array([1.0, 2.0]))
    't =   0.00 s   goal 1 (of 0-3)   distance    0.500   speed  75% (phi2)   moving'
    """
    k = int(trajectory.goal[frame])
    angles = getattr(trajectory, "orientation_error", None)
    angle = (
        f"angle {np.degrees(angles[frame]):6.1f} deg   " if angles is not None and np.isfinite(angles[frame]) else ""
    )
    return (
        f"t = {frame / trajectory.fps:6.2f} s   goal {k} (of 0-{goals - 1})   "
        f"distance {trajectory.distance[frame]:8.3f}   {angle}{_speed_share(trajectory, frame, speed_limits)}{activity}"
    )


def _speed_share(trajectory, frame: int, speed_limits: np.ndarray | None) -> str:
    """ "speed  75% (phi2)   ": the joint nearest its speed limit at the frame ("" without velocities)."""
    velocity = getattr(trajectory, "velocity", None)
    if velocity is None or speed_limits is None:
        return ""
    share = np.abs(velocity[frame]) / speed_limits
    j = int(np.argmax(share))
    return f"speed {100 * share[j]:3.0f}% (phi{j + 1})   "


def goal_outcomes(reports) -> frozenset:
    """The outcomes among a run's goal reports: ``{"reached"}``, ``{"missed"}`` or both.

    >>> from types import SimpleNamespace
    >>> sorted(goal_outcomes([SimpleNamespace(reached=True), SimpleNamespace(reached=False)]))
    ['missed', 'reached']
    """
    return frozenset("reached" if r.reached else "missed" for r in reports)
