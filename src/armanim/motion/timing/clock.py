"""The clock: when the arm is where, within each joint's speed and acceleration limits.

The frame loop decides *where* the arm goes: for each goal its solved poses (the method's
steps, the planner's path, the finishing steps) are a path in joint space. The clock decides
*when*: the fastest motion along exactly that path that starts and ends at rest and keeps
every joint within ``problem.rates`` (:class:`armanim.motion.problem.RateLimits`).

1. **The path** (:func:`armanim.motion.timing.jointpath.joint_path`): a piecewise cubic through every solved pose, in order,
   parametrised by joint-space arc length, with Fritsch-Carlson (PCHIP) slopes: each joint
   moves monotonically between two solved poses, so the path never leaves the box of two
   neighbouring poses and stays inside the joint limits as they do.
2. **The time law** (:func:`time_optimal`): TOPP-RA (Pham and Pham, IEEE T-RO 2018) on a grid
   over the path: a backward pass of controllable sets of the squared path speed, then a
   greedy forward pass, for box limits on each joint's speed and acceleration.
3. **The check** (:func:`sampled_motion`): the time law is scaled by the least factor that
   keeps every joint's speed and acceleration, evaluated densely, within the limits and
   rounds the motion to whole frames; the frames are then checked as the contract states
   them (differences over ``1 / fps``) and the time is stretched further if one is over.
   So every frame's finite-difference speed and acceleration are within the limits, with
   the first and last step at most half the acceleration's reach (the arm starts and stops
   at rest: two goals' motions meet without a jump of acceleration).

Where the smooth path between two solved poses would pass closer to an obstacle than
``solver.clearance``, that piece of path is the straight chord between them (stopping at
its ends); where even the chord cuts the clearance, the frame shows the nearer solved pose,
as before the clock. Pure core: numpy only.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import cast

import numpy as np

from armanim.arm.geometry import wrap_angle
from armanim.motion.solution import GoalTiming
from armanim.motion.timing.jointpath import JointPath
from armanim.motion.tunables import DEFAULTS, ClockOptions


class ClockTooLong(ValueError):
    """The clock would make more frames than allowed (limits far too low for the path)."""


def too_long(frames: float, most_frames: float) -> ClockTooLong:
    """The error of one goal's motion that would take ``frames`` frames, more than ``most_frames``,
    both told whole (campaign 10: ``1e+06 frames ... (at most 1e+06)`` said 1,000,008 as 1e+06).

    >>> str(too_long(1000007.5, 1_000_000))
    "1,000,008 frames for one goal's motion (at most 1,000,000)"
    """
    told = f"{math.ceil(frames):,}" if frames < 1e18 else "more than 10^18"  # inf and NaN: unbounded
    return ClockTooLong(f"{told} frames for one goal's motion (at most {most_frames:,.0f})")


@dataclass(frozen=True)
class TimeLaw:
    """A time law s(t) on a grid: constant path acceleration between grid points.

    Attributes
    ----------
    s : (N,) array
        Grid points (arc length).
    t : (N,) array
        Seconds at which the motion passes each grid point (t[0] = 0).
    speed : (N,) array
        ds/dt at each grid point (0 at both ends).
    accel : (N - 1,) array
        d2s/dt2 on each grid interval.
    """

    s: np.ndarray
    t: np.ndarray
    speed: np.ndarray
    accel: np.ndarray

    @property
    def duration(self) -> float:
        """Seconds from rest to rest."""
        return float(self.t[-1])

    def integral(self, t: np.ndarray) -> np.ndarray:
        """(k,) the integral of s over time from 0 to ``t`` (k,), at rest at s = 0 before the
        start and at the end after it (path length times seconds)."""
        dt = np.diff(self.t)
        pieces = self.s[:-1] * dt + self.speed[:-1] * dt**2 / 2 + self.accel * dt**3 / 6
        before = np.concatenate([[0.0], np.cumsum(pieces)])
        i = np.clip(np.searchsorted(self.t, t, side="right") - 1, 0, len(self.accel) - 1)
        tau = np.clip(t, 0.0, self.t[-1]) - self.t[i]
        inside = before[i] + self.s[i] * tau + self.speed[i] * tau**2 / 2 + self.accel[i] * tau**3 / 6
        return np.where(t <= 0, 0.0, inside + self.s[-1] * np.maximum(t - self.t[-1], 0.0))

    def at(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(s, ds/dt, d2s/dt2) at times ``t`` (k,), each (k,)."""
        i = np.clip(np.searchsorted(self.t, t, side="right") - 1, 0, len(self.accel) - 1)
        tau = t - self.t[i]
        u = self.accel[i]
        s = np.minimum(self.s[i] + self.speed[i] * tau + 0.5 * u * tau**2, self.s[i + 1])
        return np.maximum(s, self.s[i]), np.maximum(self.speed[i] + u * tau, 0.0), u


def time_optimal(
    path: JointPath,
    speed: np.ndarray,
    acceleration: np.ndarray,
    path_speed: np.ndarray | None = None,
    clock: ClockOptions = DEFAULTS.clock,
) -> TimeLaw:
    """The fastest time law along ``path`` from rest to rest within box limits (TOPP-RA).

    Parameters
    ----------
    path : JointPath
        A path that moves (``path.length > 0``).
    speed, acceleration : (n,) arrays
        Each joint's limits, rad/s and rad/s^2.
    path_speed : (m - 1,) array, optional
        The most ds/dt (radians of joint space per second) on each solved step of the path
        (indexed by the step's first frame; inf: no cap): a path goal's tool speed.
    clock : ClockOptions, optional
        The grid (``problem.tunables.clock``).

    Returns
    -------
    TimeLaw
        The limits hold at ``clock.collocation`` points of every grid interval; between them
        :func:`sampled_motion` checks and scales.

    Notes
    -----
    With x = (ds/dt)^2 and u = d2s/dt2 constant on a grid interval [s_i, s_i + h], the
    squared speed at a fraction f of it is x + 2 f h u, so each joint's speed and acceleration
    (q'(s) u + q''(s) x there) at every collocation point is linear in (u, x): a lower and an
    upper bound on u, affine in x. The backward pass finds the largest x at each grid point
    from which the end can still be reached at rest (the controllable set [0, hi]: resting is
    always allowed); the forward pass takes the largest u that stays in the next set.

    >>> from armanim.motion.timing.jointpath import joint_path
    >>> p = joint_path(np.array([[0.0], [1.0]]), np.array([True]))
    >>> law = time_optimal(p, np.array([10.0]), np.array([1.0]))
    >>> round(law.duration, 6)  # bang-bang over one radian at 1 rad/s^2: 2 s
    2.0
    """
    from armanim.motion.timing.passes import (  # compiled: numba here
        backward_pass,
        forward_pass,
        interval_bounds,
        pass_bounds,
    )

    s = _grid(path.s, clock)
    h = np.diff(s)
    fractions = np.array(clock.collocation)
    at = (s[:-1] + fractions[:, None] * h * (1 - 1e-9)).ravel()
    d1, d2 = (path.evaluate(at, k).reshape(len(fractions), len(h), -1) for k in (1, 2))
    n = d1.shape[2]
    lo_b, lo_k = np.empty((len(h), len(fractions) * n)), np.empty((len(h), len(fractions) * n))
    hi_b, hi_k = np.empty((len(h), len(fractions) * (n + 1))), np.empty((len(h), len(fractions) * (n + 1)))
    x_cap, w, base = np.empty(len(h)), np.empty_like(lo_b), np.empty_like(lo_b)
    interval_bounds(d1, d2, h, fractions, speed, acceleration, lo_b, lo_k, hi_b, hi_k, x_cap)
    if path_speed is not None:  # a lower squared speed at a grid point is always allowed
        x_cap = np.minimum(x_cap, path_speed[path.step_of(s[:-1] + h / 2) - 1] ** 2)
    pass_bounds(h, lo_b, lo_k, hi_b, hi_k, x_cap, w, base)
    hi = np.zeros_like(s)
    backward_pass(x_cap, w, base, hi)
    x = np.zeros_like(s)
    forward_pass(hi_b, hi_k, h, hi, x)
    u = np.diff(x) / (2 * h)
    v = np.sqrt(x)
    dt = 2 * h / np.maximum(v[:-1] + v[1:], 1e-300)
    return TimeLaw(s, np.concatenate([[0.0], np.cumsum(dt)]), v, u)


def _grid(knots: np.ndarray, clock: ClockOptions) -> np.ndarray:
    """(N,) the knots and evenly spaced points inside each step: ``clock.grid_per_step`` per
    step, or more, so that there are at least ``clock.grid_min`` intervals."""
    per = max(clock.grid_per_step, math.ceil(clock.grid_min / (len(knots) - 1)))
    f = np.arange(per) / per
    inner = knots[:-1, None] + f * np.diff(knots)[:, None]
    return np.concatenate([inner.ravel(), knots[-1:]])


@dataclass(frozen=True)
class Motion:
    """One goal's motion sampled at the frame rate.

    Attributes
    ----------
    phi : (K, n) array
        Poses at 1/fps, 2/fps, ... K/fps after the start (the last is the path's end); radians.
    velocity : (K, n) array
        Each joint's speed there, rad/s (0 on the last frame).
    heads_for : (K,) int array
        The solved frame (offset from the start pose) each frame heads for.
    duration : float
        K / fps seconds.
    """

    phi: np.ndarray
    velocity: np.ndarray
    heads_for: np.ndarray
    duration: float

    def timing(self, start: np.ndarray, speed: np.ndarray, acceleration: np.ndarray, fps: float) -> GoalTiming:
        """The motion's :class:`GoalTiming` from its frames, starting at rest at ``start`` (n,)."""
        if len(self.phi) == 0:
            return GoalTiming(0.0, 0.0, 0.0, None, None)
        steps = wrap_angle(np.diff(np.concatenate([start[None], start[None], self.phi, self.phi[-1:]]), axis=0))
        v = np.max(np.abs(steps), axis=0) * fps / speed
        a = np.max(np.abs(np.diff(steps, axis=0)), axis=0) * fps**2 / acceleration
        return GoalTiming(self.duration, float(v.max()), float(a.max()), int(np.argmax(v)), int(np.argmax(a)))


Excess = Callable[[np.ndarray], float]
"""excess(frames) -> the factor by which time must stretch for the frames (k + 1, n), the start pose
first, to keep a limit the clock does not know (a path goal's tool speed): 1 when they do; a
stretch by k divides that speed by k."""


def sampled_motion(
    path: JointPath,
    law: TimeLaw,
    speed: np.ndarray,
    acceleration: np.ndarray,
    fps: float,
    most_frames: float = np.inf,
    excess: Excess | None = None,
    clock: ClockOptions = DEFAULTS.clock,
) -> Motion:
    """The time law slowed by the least factor that keeps every limit, sampled at ``fps``.

    The factor covers the limits checked densely on the continuous motion (the grid's
    constraints hold only at its points) and a whole number of frames; then the frames
    themselves are checked as the contract states the limits (first and second differences
    over 1/fps, with the arm at rest before the first frame and after the last) and the
    time is stretched again if one is over (or ``excess`` of the frames is). ``clock``: where the
    continuous motion is checked (``problem.tunables.clock``).

    Raises
    ------
    ClockTooLong
        The motion would take more than ``most_frames`` frames.
    """
    from armanim.motion.timing.passes import law_excess

    q_vel, q_acc = law_excess(
        law.t,
        law.s,
        law.speed,
        law.accel,
        path.s,
        path.poses,
        path.slopes,
        _check_fractions(clock),
        speed,
        acceleration,
    )
    scale = max(1.0, q_vel, math.sqrt(q_acc))
    start, end = path.poses[0], path.poses[-1]
    for _ in range(32):
        frames = law.duration * scale * fps
        if not frames <= most_frames:  # inf and NaN: unbounded
            raise too_long(frames, most_frames)
        count = max(1, math.ceil(frames - 1e-9))
        scale = count / (fps * law.duration)
        times = np.arange(1, count + 1) / fps / scale
        s, sd, _ = law.at(np.minimum(times, law.duration))
        s[-1] = path.length
        phi = path.evaluate(s)
        phi[-1] = end
        velocity = path.evaluate(s, 1) * (sd / scale)[:, None]
        shown = np.concatenate([start[None], phi])
        over = max(
            _frame_excess(shown, speed, acceleration, fps=fps),
            _velocity_excess(velocity, speed),
            excess(shown) if excess else 1.0,
        )
        if over <= 1.0 + 1e-9:  # rounding: a bang-bang step is exactly at its limit
            break
        scale *= over * (1 + 1e-9)
    velocity[-1] = 0.0
    return Motion(phi, velocity, path.step_of(s), count / fps)


def _check_fractions(clock: ClockOptions) -> np.ndarray:
    """Fractions of every grid interval (its start, inside it, and just before its end) where the
    limits are checked: ``clock.check_per_step`` intervals."""
    f = np.arange(clock.check_per_step + 1) / clock.check_per_step
    f[-1] = 1 - 1e-9
    return f


def _velocity_excess(velocity: np.ndarray, speed: np.ndarray) -> float:
    """The factor by which time must stretch for the clock's own velocities at the frames (k, n),
    rad/s, to keep each joint's ``speed``: 1 when they do (a stretch by k divides them by k). The
    averaged law of a jerk limit can pass a joint's limit between the grid's points by a hair
    (1.0004x, found by the tests' random robots) where the frames' differences do not."""
    return max(1.0, float(np.max(np.abs(velocity) / speed, initial=0.0)))


def _frame_excess(
    phi: np.ndarray, speed: np.ndarray, acceleration: np.ndarray, jerk: np.ndarray | None = None, fps: float = 1.0
) -> float:
    """The factor by which time must stretch for frames ``phi`` (rest pose first, at rest
    after the last) to keep the limits: 1 when they do. A stretch by k divides speeds by k,
    accelerations by k**2 and jerks (third differences, at rest before and after) by k**3."""
    v = np.diff(phi, axis=0) * fps
    a = np.diff(np.concatenate([phi, phi[-1:]]), 2, axis=0) * fps**2 if len(phi) > 1 else np.zeros((0, len(speed)))
    ends = np.abs(np.stack([phi[1] - phi[0], phi[-1] - phi[-2]])) * 2 * fps**2 if len(phi) > 1 else a
    ratio_v = float(np.max(np.abs(v) / speed, initial=0.0))
    ratio_a = max(float(np.max(np.abs(a) / acceleration, initial=0.0)), float(np.max(ends / acceleration, initial=0.0)))
    if jerk is None:
        return max(1.0, ratio_v, math.sqrt(ratio_a))
    third = np.diff(np.concatenate([phi[:1], phi[:1], phi, phi[-1:], phi[-1:]]), 3, axis=0) * fps**3
    ratio_j = float(np.max(np.abs(third) / jerk, initial=0.0))
    return cast(float, max(1.0, ratio_v, math.sqrt(ratio_a), ratio_j ** (1 / 3)))


def jerk_window(acceleration: np.ndarray, jerk: np.ndarray) -> float:
    """The window tau (seconds) a jerk-limited motion's path speed is averaged over, which adds
    tau to its duration: max_j 2 a_j / j_j over the joints' accelerations (n,) and jerks (n,).

    >>> jerk_window(np.array([1.0, 3.0]), np.array([100.0, 20.0]))
    0.3
    """
    return float(np.max(2 * acceleration / jerk))


def jerk_limited_motion(
    path: JointPath,
    speed: np.ndarray,
    acceleration: np.ndarray,
    jerk: np.ndarray,
    fps: float,
    most_frames: float = np.inf,
    path_speed: np.ndarray | None = None,
    excess: Excess | None = None,
    clock: ClockOptions = DEFAULTS.clock,
) -> Motion:
    """A jerk-limited motion along ``path`` from rest to rest, sampled at ``fps``: the
    time-optimal law (:func:`time_optimal`) with its path speed averaged over a sliding window of
    tau = max_j 2 a_j / j_j seconds, which makes the path acceleration continuous and its jerk at
    most 2 A / tau (the window adds tau to the motion and keeps its length), then stretched to
    whole frames and checked on the frames (differences over 1/fps up to the third, at rest before
    and after) as :func:`sampled_motion` does. ``path_speed``: as for :func:`time_optimal` (the
    window's mean of a capped speed keeps the cap); ``excess`` and ``clock`` as for :func:`sampled_motion`.

    >>> from armanim.motion.timing.jointpath import joint_path
    >>> p = joint_path(np.array([[0.0], [1.0]]), np.array([True]))
    >>> m = jerk_limited_motion(p, np.array([10.0]), np.array([1.0]), np.array([100.0]), 10.0)
    >>> float(m.phi[-1, 0]), 2.0 < m.duration < 2.5  # a little longer than bang-bang's 2 s
    (1.0, True)
    """
    law = time_optimal(path, speed, acceleration, path_speed, clock)
    tau = jerk_window(acceleration, jerk)

    def smoothed(t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """s and ds/dt of the averaged law at times ``t``: the window's mean of s's speed is
        (s(t) - s(t - tau)) / tau, its integral (I(t) - I(t - tau)) / tau, both exact."""
        position = (law.integral(t) - law.integral(t - tau)) / tau
        ahead, behind = (law.at(np.clip(u, 0.0, law.duration))[0] for u in (t, t - tau))
        return np.minimum(position, path.length), (ahead - behind) / tau  # s = 0 before the start

    duration = law.duration + tau
    scale = 1.0
    start, end = path.poses[0], path.poses[-1]
    for _ in range(32):
        frames = duration * scale * fps
        if not frames <= most_frames:
            raise too_long(frames, most_frames)
        count = max(1, math.ceil(frames - 1e-9))
        scale = count / (fps * duration)
        times = np.arange(1, count + 1) / fps / scale
        at, sd = smoothed(times)
        at[-1] = path.length
        phi = path.evaluate(at)
        phi[-1] = end
        velocity = path.evaluate(at, 1) * (sd / scale)[:, None]
        shown = np.concatenate([start[None], phi])
        over = max(
            _frame_excess(shown, speed, acceleration, jerk, fps),
            _velocity_excess(velocity, speed),
            excess(shown) if excess else 1.0,
        )
        if over <= 1.0 + 1e-9:
            break
        scale *= over * (1 + 1e-9)
    velocity[-1] = 0.0
    return Motion(phi, velocity, path.step_of(at), count / fps)


__all__ = ["ClockTooLong", "Motion", "TimeLaw", "jerk_limited_motion", "sampled_motion", "time_optimal"]
