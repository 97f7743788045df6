"""One goal's motion on the clock, kept clear of the obstacles and of the arm itself.

:mod:`armanim.motion.timing.clock` times a path through a goal's solved poses; this module keeps
that path as safe as the poses are. The smooth path between two solved poses bulges a little
beyond their straight chord, so a step that might come closer to an obstacle (or bring two
of the arm's own capsules closer) than the floor is probed, and a step whose probes do not
keep the floor is taken along its chord. Where a frame on a chord still does not (the chord
cuts a curved surface between two safe poses), the step is replaced by a certified way between
its two poses (:attr:`PathSafety.detour`: straight pieces each proved clear, around the
obstacle) and the motion timed again, so that every frame stays within the rate limits: no
frame ever jumps.

Probing is bounded by lever arms (:func:`two_sided_bound`): on a step each joint moves
monotonically between its two values, so a pose's clearance is within lever . |dPhi| of the
clearance at either end of any piece of the step. A step is certified from its ends'
clearances, or from its midpoint's, or from its quarter points'; only a step none of these
certify has its frames measured. Pure core: numpy only.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import cast

import numpy as np

from armanim.arm.geometry import wrap_angle
from armanim.motion.timing.clock import Excess, Motion, jerk_limited_motion, sampled_motion, time_optimal
from armanim.motion.timing.jointpath import JointPath, joint_path
from armanim.motion.tunables import DEFAULTS, ClockOptions


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
    detour : callable, optional
        ``detour(a, b)`` for two poses (n,) whose chord comes under the floor: (k, n) poses, k >= 1,
        the straight pieces a -> p_1 -> ... -> p_k -> b each certified clear, or None if no such
        way is found (the chord's frames then keep the rate limits and the clearance they have).
    chord_free : callable, optional
        ``chord_free(a, b)``: whether the straight chord between two poses (n,) keeps the floor
        throughout (halved until each piece is certified by :func:`two_sided_bound`), so that a
        chord that passes an obstacle between two frames is caught too.
    """

    clearance: Callable[[np.ndarray], np.ndarray]
    floor: float
    lever: np.ndarray
    at_poses: np.ndarray
    certified: np.ndarray
    detour: Callable[[np.ndarray, np.ndarray], np.ndarray | None] | None = None
    chord_free: Callable[[np.ndarray, np.ndarray], bool] | None = None


def two_sided_bound(c0: np.ndarray, c1: np.ndarray, reach: np.ndarray) -> np.ndarray:
    """(k,) the least clearance anywhere between two poses of clearances ``c0`` and ``c1`` (k,)
    between which no point moves by more than ``reach`` (k,) in all.

    A pose that has moved d0 from one end has reach - d0 left to the other, so its clearance
    is at least max(c0 - d0, c1 - (reach - d0)), whose least value over d0 in [0, reach] is
    max(max(c0, c1) - reach, (c0 + c1 - reach) / 2).

    >>> two_sided_bound(np.array([1.0, 1.0]), np.array([1.0, 0.0]), np.array([1.5, 0.5]))
    array([0.25, 0.5 ])
    """
    return cast(np.ndarray, np.maximum(np.maximum(c0, c1) - reach, (c0 + c1 - reach) / 2))


def probed_steps(path: JointPath, safety: PathSafety, asked: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Measure the ``asked`` (K,) steps of ``path`` inside: (K,) bool each, the steps a probe
    found under the floor (to take along their chords), and the steps their probes and ends
    certify throughout (their frames need no measuring while the path keeps its shape).

    Each step is probed at its midpoint (of arc length); a step whose two halves that does not
    certify, and whose midpoint keeps the floor, at its quarter points too.
    """
    return probed_paths([path], [safety], [asked])[0]


def probed_paths(
    paths: list[JointPath], safeties: list[PathSafety], asked: list[np.ndarray]
) -> list[tuple[np.ndarray, np.ndarray]]:
    """:func:`probed_steps` for several paths at once, their probes measured in two batches (the
    midpoints, then the quarter points) by the first safety's ``clearance``."""
    out = [(np.zeros(len(a), dtype=bool), np.zeros(len(a), dtype=bool)) for a in asked]
    steps = [np.nonzero(a)[0] for a in asked]
    live = [i for i in range(len(paths)) if len(steps[i])]
    if not live:
        return out
    measure, floor = safeties[live[0]].clearance, safeties[live[0]].floor
    h = [np.diff(path.s) for path in paths]
    mid = {i: paths[i].evaluate(paths[i].s[steps[i]] + 0.5 * h[i][steps[i]]) for i in live}
    c_mid = dict(zip(live, _measured(measure, [mid[i] for i in live])))
    more = {}
    for i in live:
        unsafe, proven = out[i]
        halves = _pieces_clear(paths[i], safeties[i], steps[i], [mid[i]], [c_mid[i]])
        proven[steps[i][halves]] = True
        unsafe[steps[i][~halves & ~(c_mid[i] >= floor)]] = True
        if np.any(~halves & (c_mid[i] >= floor)):
            more[i] = ~halves & (c_mid[i] >= floor)
    quarter = {
        i: [paths[i].evaluate(paths[i].s[steps[i][m]] + f * h[i][steps[i][m]]) for f in (0.25, 0.75)]
        for i, m in more.items()
    }
    measured = iter(_measured(measure, [q for i in more for q in quarter[i]]))
    for i, m in more.items():
        unsafe, proven = out[i]
        c_quarter = [next(measured), next(measured)]
        kept = (c_quarter[0] >= floor) & (c_quarter[1] >= floor)
        unsafe[steps[i][m][~kept]] = True
        inner, cleared = [quarter[i][0], mid[i][m], quarter[i][1]], [c_quarter[0], c_mid[i][m], c_quarter[1]]
        proven[steps[i][m][kept & _pieces_clear(paths[i], safeties[i], steps[i][m], inner, cleared)]] = True
    return out


def _measured(measure: Callable[[np.ndarray], np.ndarray], groups: list[np.ndarray]) -> list[np.ndarray]:
    """Each group of poses' clearances, measured in one call."""
    if not groups:
        return []
    return np.split(measure(np.concatenate(groups)), np.cumsum([len(g) for g in groups])[:-1])


def _pieces_clear(
    path: JointPath, safety: PathSafety, steps: np.ndarray, inner: list[np.ndarray], cleared: list[np.ndarray]
) -> np.ndarray:
    """(len(steps),) bool: every piece of each step between its ends and the ``inner`` poses
    (each (len(steps), n), in order along the step, with clearances ``cleared``) certified by
    :func:`two_sided_bound`."""
    ends = safety.at_poses[path.frames]
    poses = [path.poses[steps]] + inner + [path.poses[steps + 1]]
    clear = [ends[steps]] + cleared + [ends[steps + 1]]
    ok = np.ones(len(steps), dtype=bool)
    for a in range(len(poses) - 1):
        reach = np.abs(poses[a + 1] - poses[a]) @ safety.lever
        ok &= two_sided_bound(clear[a], clear[a + 1], reach) >= safety.floor
    return ok


def goal_motion(
    poses: np.ndarray,
    limited: np.ndarray,
    speed: np.ndarray,
    acceleration: np.ndarray,
    fps: float,
    safety: PathSafety | None = None,
    most_frames: float = np.inf,
    jerk: np.ndarray | None = None,
) -> Motion:
    """The motion through one goal's solved ``poses`` (m, n) from rest to rest at ``fps``
    (:func:`goal_motions` for one goal).

    >>> m = goal_motion(np.array([[0.0], [1.0]]), np.array([True]), np.array([10.0]), np.array([1.0]), 10.0)
    >>> len(m.phi), float(m.phi[-1, 0]), m.duration
    (20, 1.0, 2.0)
    """
    return goal_motions(
        [poses], limited, speed, acceleration, fps, None if safety is None else [safety], most_frames, jerk
    )[0]


def goal_motions(
    poses: list[np.ndarray],
    limited: np.ndarray,
    speed: np.ndarray,
    acceleration: np.ndarray,
    fps: float,
    safeties: list[PathSafety] | None = None,
    most_frames: float = np.inf,
    jerk: np.ndarray | None = None,
    holds: list[int] | None = None,
    path_speeds: list[np.ndarray | None] | None = None,
    strays: list[Callable[[Motion], np.ndarray] | None] | None = None,
    excesses: list[Excess | None] | None = None,
    clock: ClockOptions = DEFAULTS.clock,
) -> list[Motion]:
    """The motions through each goal's solved ``poses`` (m_i, n), one after the other, each from
    rest to rest at ``fps``.

    The first pose of each is where the arm already is (it is not a frame of the result); a
    path that does not move takes no frames. With ``safeties`` (one a goal), a solved step not
    certified clear whose smooth path comes under the floor at a probe (:func:`probed_steps`) or
    at a frame is taken along its chord (and that motion timed again); a step whose chord still
    does not at a frame is replaced by its safety's ``detour`` (chords, certified) and timed
    again. Every frame keeps the rate limits. The goals' probes and frames are measured
    together, a few calls in all. Raises :class:`~armanim.motion.timing.clock.ClockTooLong` where a
    goal's motion would pass ``most_frames`` less the frames (and ``holds``, one a goal) of the
    goals before it. ``path_speeds`` (one a goal, each (m_i - 1,) or None): the most ds/dt on each
    solved step (:func:`~armanim.motion.timing.clock.time_optimal`). ``strays`` (one a goal, or None):
    ``strays(motion)`` -> (K,) bool, the frames of a timed motion that leave a path goal's path;
    the steps they lie in are taken along their chords too. ``excesses`` (one a goal, or None):
    a limit of the frames the clock does not know (:data:`~armanim.motion.timing.clock.Excess`).
    ``clock``: the clock's grid (``problem.tunables.clock``).
    """
    holds = [0] * len(poses) if holds is None else holds
    goals = [_Goal.start(p, limited, None if safeties is None else safeties[i]) for i, p in enumerate(poses)]
    for g, cap in zip(goals, path_speeds or []):
        g.path_speed = cap
    for g, excess in zip(goals, excesses or []):
        g.excess = excess
    probing = [(g, g.safety) for g in goals if g.safety is not None and len(g.path.s) > 2 and np.any(g.asked)]
    for (g, _), (unsafe, proven) in zip(
        probing,
        probed_paths([g.path for g, _ in probing], [safety for _, safety in probing], [g.asked for g, _ in probing]),
    ):
        g.proven = proven
        g.chords[g.solved_step[unsafe]] = True
    pending = [i for i, g in enumerate(goals) if g.path.length > 0]
    while pending:  # a step whose frames come too close (or stray) is taken along its chord, and its motion timed again
        for i in pending:
            goals[i].time(
                speed, acceleration, fps, most_frames - sum(g.frames + h for g, h in zip(goals[:i], holds)), jerk, clock
            )
        again = {
            i
            for i in pending
            if (stray := (strays or [None] * len(goals))[i]) is not None
            and goals[i].chord_frames(stray(goals[i].solved_motion))
        }
        checked = [i for i in pending if goals[i].safety is not None and np.any(goals[i].timed_check)]
        if checked and safeties is not None:
            found = _measured(safeties[0].clearance, [goals[i].timed.phi[goals[i].timed_check] for i in checked])
            again |= {i for i, c in zip(checked, found) if goals[i].chord_bad_frames(~(c >= safeties[0].floor))}
        again |= {i for i in pending if i not in again and goals[i].safety is not None and goals[i].detoured()}
        pending = sorted(again)
    return [g.finished() for g in goals]


@dataclass
class _Goal:
    """One goal's path while it is timed: its chords, the steps its probes proved, its motion."""

    poses: np.ndarray
    limited: np.ndarray
    path: JointPath
    safety: PathSafety | None
    doubtful: np.ndarray
    chords: np.ndarray
    proven: np.ndarray
    motion: Motion | None = None
    bad: np.ndarray | None = None
    check: np.ndarray | None = None
    """The motion's frames to measure (set by :meth:`time`)."""
    path_speed: np.ndarray | None = None
    """The most ds/dt on each solved step (a path goal's tool speed), or None."""
    excess: Excess | None = None
    """A limit of the frames the clock does not know (a path goal's tool speed), or None."""
    origin: np.ndarray | None = None
    """The solved pose each of :attr:`poses` is or heads for (a detour's poses inserted), or None
    while there is none."""
    no_way: set[int] = field(default_factory=set)
    """The steps (by their solved poses) whose detour was asked for in vain."""
    free_chords: set[int] = field(default_factory=set)
    """The steps whose chord :attr:`PathSafety.chord_free` certified."""

    @classmethod
    def start(cls, poses: np.ndarray, limited: np.ndarray, safety: PathSafety | None) -> _Goal:
        """The smooth path through ``poses``, no step along its chord yet."""
        path = joint_path(poses, limited)
        steps = len(poses) - 1
        doubtful = np.zeros(steps, dtype=bool) if safety is None else ~safety.certified
        return cls(
            poses, limited, path, safety, doubtful, np.zeros(steps, dtype=bool), np.zeros(len(path.s) - 1, dtype=bool)
        )

    @property
    def timed(self) -> Motion:
        """The motion (after :meth:`time`)."""
        assert self.motion is not None, "the path is timed first"
        return self.motion

    @property
    def timed_check(self) -> np.ndarray:
        """:attr:`check` (after :meth:`time`)."""
        assert self.check is not None, "the path is timed first"
        return self.check

    @property
    def frames(self) -> int:
        """Frames of the motion so far (0 before it is timed)."""
        return 0 if self.motion is None else len(self.motion.phi)

    @property
    def solved_step(self) -> np.ndarray:
        """The solved step each step of the path is (repeated poses dropped)."""
        return self.path.frames[1:] - 1

    @property
    def asked(self) -> np.ndarray:
        """The path's steps not certified clear."""
        return cast(np.ndarray, self.doubtful[self.solved_step])

    @property
    def frame_step(self) -> np.ndarray:
        """The solved step each frame of the motion lies in."""
        return cast(np.ndarray, np.maximum(self.timed.heads_for, 1) - 1)

    def time(
        self,
        speed: np.ndarray,
        acceleration: np.ndarray,
        fps: float,
        most_frames: float,
        jerk: np.ndarray | None,
        clock: ClockOptions,
    ) -> None:
        """Put the path, with its chords, on the clock, and note the motion's frames to measure
        (:attr:`check`: in a doubtful step its probes have not proved, or whose shape a chord has
        changed since)."""
        if self.chords.any():
            self.path = joint_path(self.poses, self.limited, self.chords)
        path_speed = (
            self.path_speed if self.origin is None or self.path_speed is None else self.path_speed[self.origin[1:] - 1]
        )
        self.motion = _timed(self.path, speed, acceleration, fps, most_frames, jerk, path_speed, self.excess, clock)
        self.bad = np.zeros(len(self.motion.phi), dtype=bool)
        proven = _still_proven(self.proven, self.chords[self.solved_step], self.solved_step, len(self.poses) - 1)
        self.check = (self.doubtful & ~proven)[self.frame_step]

    def chord_bad_frames(self, under: np.ndarray) -> bool:
        """Note which checked frames came ``under`` the floor; take the steps they lie in along
        their chords. True if that adds a chord (the motion must be timed again)."""
        bad = np.zeros(self.frames, dtype=bool)
        bad[self.timed_check] = under
        self.bad = bad
        step = self.frame_step
        again = bool(np.any(bad & ~self.chords[step]))
        if again:
            self.chords[step[bad]] = True
        return again

    @property
    def solved_motion(self) -> Motion:
        """:attr:`timed` with each frame heading for a solved pose (a detour's heads for the
        step's last)."""
        if self.origin is None:
            return self.timed
        return replace(self.timed, heads_for=self.origin[self.timed.heads_for])

    def detoured(self) -> bool:
        """Replace each step on its chord whose frames still came under the floor by its safety's
        detour (each piece a chord, certified). True if one was (the motion must be timed again)."""
        assert self.safety is not None
        cut = set() if self.bad is None else {int(k) for k in self.frame_step[self.bad]}
        cut |= self._uncertified_chords()
        steps = sorted(cut - self.no_way)
        if not steps or self.safety.detour is None:
            return False
        origin = np.arange(len(self.poses)) if self.origin is None else self.origin
        ways = {}
        for k in steps:
            way = self.safety.detour(self.poses[k], self.poses[k + 1])
            if way is None or not len(way):
                self.no_way.add(k)
            else:
                ways[k] = way
        if not ways:
            return False
        poses, chords, doubtful, origins = [self.poses[:1]], [], [], [origin[:1]]
        for k in range(len(self.poses) - 1):
            way = ways.get(k, self.poses[:0])
            poses += [way, self.poses[k + 1 : k + 2]]
            origins += [np.full(len(way), origin[k + 1]), origin[k + 1 : k + 2]]
            pieces = len(way) + 1
            chords.append(np.full(pieces, True) if k in ways else self.chords[k : k + 1])
            doubtful.append(np.full(pieces, False) if k in ways else self.doubtful[k : k + 1])
        shift = np.cumsum([0] + [len(ways.get(k, ())) for k in range(len(self.poses) - 1)])
        self.no_way = {int(k + shift[k]) for k in self.no_way}
        self.free_chords = {int(k + shift[k]) for k in self.free_chords}
        self.poses, self.origin = np.concatenate(poses), np.concatenate(origins)
        self.chords, self.doubtful = np.concatenate(chords), np.concatenate(doubtful)
        self.path = joint_path(self.poses, self.limited, self.chords)
        self.proven = np.zeros(len(self.path.s) - 1, dtype=bool)
        return True

    def _uncertified_chords(self) -> set[int]:
        """The doubtful steps on their chords (a path of one step is one) that
        :attr:`PathSafety.chord_free` does not certify (each asked once): a chord can pass an
        obstacle between two frames that both keep the floor."""
        assert self.safety is not None
        if self.safety.chord_free is None:
            return set()
        out: set[int] = set()
        straight = self.chords | (len(self.path.s) == 2)  # a path of one step is its chord
        for k in (int(j) for j in np.nonzero(straight & self.doubtful)[0]):
            if k in self.free_chords or k in self.no_way or np.array_equal(self.poses[k], self.poses[k + 1]):
                continue
            if self.safety.chord_free(self.poses[k], self.poses[k + 1]):
                self.free_chords.add(k)
            else:
                out.add(k)
        return out

    def chord_frames(self, off: np.ndarray) -> bool:
        """Take the steps the frames ``off`` (K,) bool lie in along their chords. True if that adds
        a chord (the motion must be timed again)."""
        step = self.frame_step
        again = bool(np.any(off & ~self.chords[step]))
        self.chords[step[off]] = True
        return again

    def finished(self) -> Motion:
        """The motion's frames, each heading for a solved pose, unlimited joints wrapped, the last
        frame the last solved pose."""
        n = self.poses.shape[1]
        if self.motion is None:
            return Motion(np.zeros((0, n)), np.zeros((0, n)), np.zeros(0, dtype=int), 0.0)
        motion = self.solved_motion
        phi = np.where(self.limited, motion.phi, wrap_angle(motion.phi))
        phi[-1] = self.poses[-1]  # the goal's last solved pose itself, not its unwrapped copy
        return Motion(phi, motion.velocity, motion.heads_for, motion.duration)


def _timed(
    path: JointPath,
    speed: np.ndarray,
    acceleration: np.ndarray,
    fps: float,
    most_frames: float,
    jerk: np.ndarray | None,
    path_speed: np.ndarray | None = None,
    excess: Excess | None = None,
    clock: ClockOptions = DEFAULTS.clock,
) -> Motion:
    """The path on the clock: time-optimal, or jerk-limited with ``jerk``."""
    if jerk is None:
        law = time_optimal(path, speed, acceleration, path_speed, clock)
        return sampled_motion(path, law, speed, acceleration, fps, most_frames, excess, clock)
    return jerk_limited_motion(path, speed, acceleration, jerk, fps, most_frames, path_speed, excess, clock)


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
