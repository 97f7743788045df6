"""One goal's motion on the clock, kept clear of the obstacles and of the arm itself.

:mod:`armanim.motion.clock` times a path through a goal's solved poses; this module keeps
that path as safe as the poses are. The smooth path between two solved poses bulges a little
beyond their straight chord, so a step that might come closer to an obstacle (or bring two
of the arm's own capsules closer) than the floor is probed, and a step whose probes do not
keep the floor is taken along its chord; a frame on a chord that still does not (the chord
cuts a curved surface) shows the solved pose it heads for.

Probing is bounded by lever arms (:func:`two_sided_bound`): on a step each joint moves
monotonically between its two values, so a pose's clearance is within lever . |dPhi| of the
clearance at either end of any piece of the step. A step is certified from its ends'
clearances, or from its midpoint's, or from its quarter points'; only a step none of these
certify has its frames measured. Pure core: numpy only.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from armanim.arm.geometry import wrap_angle
from armanim.motion.clock import (
    JointPath,
    Motion,
    jerk_limited_motion,
    joint_path,
    sampled_motion,
    time_optimal,
    unwrapped,
)


@dataclass(frozen=True)
class PathSafety:
    """What keeps a goal's path clear, for :func:`goal_motion`.

    Attributes
    ----------
    clearance : callable
        (k, n) poses, radians -> (k,) their clearance (scene units; obstacles and the arm's own
        pairs judged by one floor).
    floor : float
        The least clearance a pose may have.
    lever : (n,) array
        Each joint's lever arm: no point of the arm moves by more than lever . |dPhi|, nor any
        pair's gap changes by more (scene units per radian).
    at_poses : (m,) array
        The solved poses' clearances.
    certified : (m - 1,) bool array
        The solved steps known to keep the floor throughout (never measured).
    """

    clearance: Callable[[np.ndarray], np.ndarray]
    floor: float
    lever: np.ndarray
    at_poses: np.ndarray
    certified: np.ndarray


def two_sided_bound(c0: np.ndarray, c1: np.ndarray, reach: np.ndarray) -> np.ndarray:
    """(k,) the least clearance anywhere between two poses of clearances ``c0`` and ``c1`` (k,)
    between which no point moves by more than ``reach`` (k,) in all.

    A pose that has moved d0 from one end has reach - d0 left to the other, so its clearance
    is at least max(c0 - d0, c1 - (reach - d0)), whose least value over d0 in [0, reach] is
    max(max(c0, c1) - reach, (c0 + c1 - reach) / 2).

    >>> two_sided_bound(np.array([1.0, 1.0]), np.array([1.0, 0.0]), np.array([1.5, 0.5]))
    array([0.25, 0.5 ])
    """
    return np.maximum(np.maximum(c0, c1) - reach, (c0 + c1 - reach) / 2)


def probed_steps(path: JointPath, safety: PathSafety, asked: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Measure the ``asked`` (K,) steps of ``path`` inside: (K,) bool each, the steps a probe
    found under the floor (to take along their chords), and the steps their probes and ends
    certify throughout (their frames need no measuring while the path keeps its shape).

    Each step is probed at its midpoint (of arc length); a step whose two halves that does not
    certify, and whose midpoint keeps the floor, at its quarter points too.
    """
    unsafe, proven = np.zeros(len(asked), dtype=bool), np.zeros(len(asked), dtype=bool)
    steps = np.nonzero(asked)[0]
    if len(steps) == 0:
        return unsafe, proven
    floor, ends, h = safety.floor, safety.at_poses[path.frames], np.diff(path.s)
    mid = path.evaluate(path.s[steps] + 0.5 * h[steps])
    c_mid = safety.clearance(mid)
    halves = _pieces_clear(path, safety, steps, ends, [mid], [c_mid])
    proven[steps[halves]] = True
    unsafe[steps[~halves & ~(c_mid >= floor)]] = True
    more = ~halves & (c_mid >= floor)
    if np.any(more):
        steps = steps[more]
        quarter = [path.evaluate(path.s[steps] + f * h[steps]) for f in (0.25, 0.75)]
        c_quarter = [safety.clearance(q) for q in quarter]
        kept = (c_quarter[0] >= floor) & (c_quarter[1] >= floor)
        unsafe[steps[~kept]] = True
        inner, cleared = [quarter[0], mid[more], quarter[1]], [c_quarter[0], c_mid[more], c_quarter[1]]
        proven[steps[kept & _pieces_clear(path, safety, steps, ends, inner, cleared)]] = True
    return unsafe, proven


def _pieces_clear(path: JointPath, safety: PathSafety, steps: np.ndarray, ends: np.ndarray, inner: list,
                  cleared: list) -> np.ndarray:
    """(len(steps),) bool: every piece of each step between its ends and the ``inner`` poses
    (each (len(steps), n), in order along the step, with clearances ``cleared``) certified by
    :func:`two_sided_bound`."""
    poses = [path.poses[steps]] + inner + [path.poses[steps + 1]]
    clear = [ends[steps]] + cleared + [ends[steps + 1]]
    ok = np.ones(len(steps), dtype=bool)
    for a in range(len(poses) - 1):
        reach = np.abs(poses[a + 1] - poses[a]) @ safety.lever
        ok &= two_sided_bound(clear[a], clear[a + 1], reach) >= safety.floor
    return ok


def goal_motion(poses: np.ndarray, limited: np.ndarray, speed: np.ndarray, acceleration: np.ndarray, fps: float,
                safety: PathSafety | None = None, most_frames: float = np.inf,
                jerk: np.ndarray | None = None) -> Motion:
    """The motion through one goal's solved ``poses`` (m, n) from rest to rest at ``fps``.

    The first pose is where the arm already is (it is not a frame of the result); a path
    that does not move takes no frames. With ``safety``, a solved step not certified clear
    whose smooth path comes under the floor at a probe (:func:`probed_steps`) or at a frame is
    taken along its chord (and the motion timed again); a frame on a chord that still does
    not shows the solved pose it heads for. Raises :class:`~armanim.motion.clock.ClockTooLong`
    past ``most_frames`` frames.

    >>> m = goal_motion(np.array([[0.0], [1.0]]), np.array([True]), np.array([10.0]), np.array([1.0]), 10.0)
    >>> len(m.phi), float(m.phi[-1, 0]), m.duration
    (20, 1.0, 2.0)
    """
    path = joint_path(poses, limited)
    n = poses.shape[1]
    if path.length == 0:
        return Motion(np.zeros((0, n)), np.zeros((0, n)), np.zeros(0, dtype=int), 0.0)
    solved_step = path.frames[1:] - 1  # the solved step each step of the path is (repeated poses dropped)
    doubtful = np.zeros(len(poses) - 1, dtype=bool) if safety is None else ~safety.certified
    chords, proven = np.zeros(len(poses) - 1, dtype=bool), np.zeros(len(path.s) - 1, dtype=bool)
    asked = doubtful[solved_step]
    if safety is not None and len(path.s) > 2 and np.any(asked):
        unsafe, proven = probed_steps(path, safety, asked)
        chords[solved_step[unsafe]] = True
    while True:  # a step whose frames come too close is taken along its chord, and the motion timed again
        if chords.any():
            path = joint_path(poses, limited, chords)
        motion = _timed(path, speed, acceleration, fps, most_frames, jerk)
        step = np.maximum(motion.heads_for, 1) - 1  # the solved step each frame lies in
        check = (doubtful & ~_still_proven(proven, chords[solved_step], solved_step, len(poses) - 1))[step]
        bad = np.zeros(len(motion.phi), dtype=bool)
        if safety is not None and np.any(check):
            bad[check] = ~(safety.clearance(motion.phi[check]) >= safety.floor)
        if not np.any(bad & ~chords[step]):
            break
        chords[step[bad]] = True
    phi = motion.phi
    if np.any(bad):  # even the chord cuts the clearance: the frame shows the solved pose it heads for
        phi = phi.copy()
        phi[bad] = unwrapped(poses, limited)[motion.heads_for[bad]]
    phi = np.where(limited, phi, wrap_angle(phi))
    phi[-1] = poses[-1]  # the goal's last solved pose itself, not its unwrapped copy
    return Motion(phi, motion.velocity, motion.heads_for, motion.duration)


def _timed(path: JointPath, speed: np.ndarray, acceleration: np.ndarray, fps: float, most_frames: float,
           jerk: np.ndarray | None) -> Motion:
    """The path on the clock: time-optimal, or jerk-limited with ``jerk``."""
    if jerk is None:
        return sampled_motion(path, time_optimal(path, speed, acceleration), speed, acceleration, fps, most_frames)
    return jerk_limited_motion(path, speed, acceleration, jerk, fps, most_frames)


def _still_proven(proven: np.ndarray, chorded: np.ndarray, solved_step: np.ndarray, steps: int) -> np.ndarray:
    """(steps,) bool by solved step: the path's steps its probes certified (``proven``, by step of
    the path) whose shape no chord has changed since (a chord zeroes the slopes at its two knots,
    which reshapes the steps on either side as well)."""
    reshaped = chorded.copy()
    reshaped[1:] |= chorded[:-1]
    reshaped[:-1] |= chorded[1:]
    out = np.zeros(steps, dtype=bool)
    out[solved_step] = proven & ~reshaped
    return out


__all__ = ["PathSafety", "goal_motion", "probed_steps", "two_sided_bound"]
