"""The path the clock times: a piecewise cubic through a goal's solved poses, in order.

Parametrised by joint-space arc length, with Fritsch-Carlson (PCHIP) slopes, so each joint
moves monotonically between two solved poses: the path never leaves the box of two neighbouring
poses and stays inside the joint limits as they do (:mod:`armanim.motion.timing.clock` times it). Pure
core: numpy only (the evaluation is compiled: :func:`armanim.motion.timing.passes.hermite`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from armanim.arm.geometry import wrap_angle


@dataclass(frozen=True)
class JointPath:
    """A path through solved poses: knots at arc length ``s``, PCHIP slopes ``slopes``.

    Attributes
    ----------
    s : (m,) array
        Arc length of each knot (radians of joint space, strictly increasing from 0).
    poses : (m, n) array
        The knots: the solved poses, repeated ones dropped, unlimited joints unwrapped.
    slopes : (m, n) array
        dq/ds at each knot.
    frames : (m,) int array
        The solved frame each knot is (offset from the first pose of the goal).
    """

    s: np.ndarray
    poses: np.ndarray
    slopes: np.ndarray
    frames: np.ndarray

    @property
    def length(self) -> float:
        """Arc length of the whole path (0 for a path that does not move)."""
        return float(self.s[-1])

    def evaluate(self, s: np.ndarray, derivative: int = 0) -> np.ndarray:
        """(k, n) the path, or its first, second or third derivative in ``s``, at arc lengths ``s`` (k,).

        The second and third derivatives are the ones of the step ``s`` falls in (from the right
        at a knot).

        >>> p = joint_path(np.array([[0.0], [1.0], [2.0]]), np.array([True]))
        >>> p.evaluate(np.array([0.5, 1.5])).ravel().tolist(), p.evaluate(np.array([0.25]), 1).ravel().tolist()
        ([0.5, 1.5], [1.0])
        """
        from armanim.motion.timing.passes import hermite  # compiled: a path is evaluated at thousands of points

        out = np.empty((len(s), self.poses.shape[1]))
        hermite(self.s, self.poses, self.slopes, np.ascontiguousarray(s, dtype=float), derivative, out)
        return out

    def step_of(self, s: np.ndarray) -> np.ndarray:
        """(k,) the solved frame each arc length ``s`` heads for (the knot itself at a knot)."""
        k = np.searchsorted(self.s, s - 1e-12 * max(self.length, 1.0), side="left")
        return self.frames[np.clip(k, 0, len(self.s) - 1)]


def unwrapped(poses: np.ndarray, limited: np.ndarray) -> np.ndarray:
    """(m, n) ``poses`` with each unlimited joint's turn from pose to pose the short way round.

    >>> unwrapped(np.array([[3.0], [-3.0]]), np.array([False])).round(4).tolist()
    [[3.0], [3.2832]]
    """
    steps = np.diff(poses, axis=0)
    steps = np.where(limited, steps, wrap_angle(steps))
    return np.concatenate([poses[:1], poses[:1] + np.cumsum(steps, axis=0)])


def pchip_slopes(s: np.ndarray, poses: np.ndarray) -> np.ndarray:
    """(m, n) Fritsch-Carlson slopes at the knots ``s`` (m,) of ``poses`` (m, n), as scipy's
    ``PchipInterpolator`` chooses them: each joint monotone between two knots.

    >>> pchip_slopes(np.array([0.0, 1.0, 2.0]), np.array([[0.0], [1.0], [1.0]])).ravel().tolist()
    [1.5, 0.0, 0.0]
    """
    h = np.diff(s)[:, None]
    m = np.diff(poses, axis=0) / h
    d = np.zeros_like(poses)
    if len(s) == 2:
        return np.repeat(m, 2, axis=0)
    w1, w2 = 2 * h[1:] + h[:-1], h[1:] + 2 * h[:-1]
    same = (np.sign(m[:-1]) * np.sign(m[1:])) > 0
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):  # a slope of a few ulps: w/m is inf, d 0
        d[1:-1] = np.where(same, (w1 + w2) / (w1 / m[:-1] + w2 / m[1:]), 0.0)
    d[0] = _end_slope(h[0], h[1], m[0], m[1])
    d[-1] = _end_slope(h[-1], h[-2], m[-1], m[-2])
    return d


def _end_slope(h0: np.ndarray, h1: np.ndarray, m0: np.ndarray, m1: np.ndarray) -> np.ndarray:
    """scipy's shape-preserving three-point slope at an end of a PCHIP."""
    d = ((2 * h0 + h1) * m0 - h0 * m1) / (h0 + h1)
    d = np.where(np.sign(d) != np.sign(m0), 0.0, d)
    return np.where((np.sign(m0) != np.sign(m1)) & (np.abs(d) > np.abs(3 * m0)), 3 * m0, d)


def joint_path(poses: np.ndarray, limited: np.ndarray, chords: np.ndarray | None = None) -> JointPath:
    """The smooth path through ``poses`` (m, n), radians, in order.

    Parameters
    ----------
    poses : (m, n) array
        The solved poses, first to last; repeated poses are dropped.
    limited : (n,) bool array
        Joints with limits (the others turn the short way round between poses).
    chords : (m - 1,) bool array, optional
        Solved steps to take along their straight chord, at rest at both ends.

    Returns
    -------
    JointPath
    """
    poses = unwrapped(poses, limited)
    lengths = np.linalg.norm(np.diff(poses, axis=0), axis=1)
    moves = lengths > 1e-12
    keep = np.concatenate([[True], moves])
    frames = np.nonzero(keep)[0]
    s = np.concatenate([[0.0], np.cumsum(lengths[moves])])
    knots = poses[keep]
    if len(s) < 2:
        return JointPath(s, knots, np.zeros_like(knots), frames)
    slopes = pchip_slopes(s, knots)
    if chords is not None and np.any(chords[moves]):
        straight = np.nonzero(chords[moves])[0]
        slopes[straight] = 0.0
        slopes[straight + 1] = 0.0
    return JointPath(s, knots, slopes, frames)


__all__ = ["JointPath", "joint_path", "pchip_slopes", "unwrapped"]
