"""Exact distances between the arm's own capsules: the pairs the allowed-collision matrix leaves enabled.

A pair (A, B) of collision capsules is apart by the distance between their segments less both
radii (negative when they overlap), computed by :func:`armanim.world.compiled.segment_segment_pairs`:
the clamped segment-segment closed form where the closest points are unique and apart, else
(parallel, touching) the segment-box one of :mod:`armanim.world.closest` with B's segment as a box
of one edge (:meth:`~armanim.world.obstacles.Rods.axes`), as the capsule obstacles are measured.
The normal points from B's closest point to A's, so a pair's gap grows along
``n . (J_A - J_B)`` (:func:`self_rows`: the difference of the two closest points' Jacobians, the
envelope theorem dropping the fractions' derivatives), compiled too. One pose or a batch. Pure
core: numpy, and numba (imported at the first measurement), no I/O.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import cast

import numpy as np

from armanim.arm.capsules import Capsules, capsule_ends
from armanim.arm.kinematics import Arm, Pose, joint_axes_world
from armanim.arm.kinematics import kind_axes as arm_kind_axes


@dataclass(frozen=True)
class SelfPairs:
    """The capsule pairs whose distance is kept (the enabled pairs of the allowed-collision matrix).

    Attributes
    ----------
    first, second : (P,) int arrays
        Capsule indices of each enabled pair (first < second).
    clearance : float
        ``solver.self_clearance``: every enabled pair keeps at least this far apart, scene units.
    names : tuple of (str, str)
        Each enabled pair's link names, as the run's outputs print them.
    allowed : tuple of (str, str, str)
        Every allowed link pair (never checked) and the reason it is allowed (MoveIt's words:
        ``Adjacent``, ``Default``, ``Never``, ``User``, ``SRDF``, ``Same``).
    mode : str
        How the matrix was made: ``auto``, ``srdf``, ``off``.
    """

    first: np.ndarray
    second: np.ndarray
    clearance: float
    names: tuple[tuple[str, str], ...] = ()
    allowed: tuple[tuple[str, str, str], ...] = ()
    mode: str = "off"
    labels: tuple[str, ...] = field(init=False, repr=False, compare=False)
    """(P,) each enabled pair as ``a|b`` (the trajectory's ``self_pair`` column)."""

    def __post_init__(self) -> None:
        object.__setattr__(self, "first", np.asarray(self.first, dtype=int).reshape(-1))
        object.__setattr__(self, "second", np.asarray(self.second, dtype=int).reshape(-1))
        object.__setattr__(self, "labels", tuple(f"{a}|{b}" for a, b in self.names))

    @classmethod
    def none(cls, clearance: float = 0.0) -> SelfPairs:
        """No pair checked (``arm.self_collision: off``)."""
        return cls(np.zeros(0, dtype=int), np.zeros(0, dtype=int), float(clearance))

    def __len__(self) -> int:
        return len(self.first)

    def radii(self, capsules: Capsules) -> np.ndarray:
        """(P,) the sum of each pair's two radii (a pair's gap is its segments' distance less this)."""
        kept = self.__dict__.get("_radii")
        if kept is None or kept[0] is not capsules:
            kept = (capsules, capsules.radius[self.first] + capsules.radius[self.second])
            object.__setattr__(self, "_radii", kept)  # a cache of a fact of the pairs and capsules
        return cast(np.ndarray, kept[1])


@dataclass(frozen=True)
class SelfGaps:
    """How far apart each enabled pair is, for one pose or a batch.

    Attributes
    ----------
    d : (..., P) array
        Distance between the two capsules' surfaces (negative: they overlap), scene units.
    t, s : (..., P) arrays
        Fraction along the first's and the second's segment of their closest points.
    normal : (..., P, 3) array
        Unit vector from the second's closest point to the first's.
    """

    d: np.ndarray
    t: np.ndarray
    s: np.ndarray
    normal: np.ndarray

    @property
    def least(self) -> np.ndarray:
        """(...) the smallest gap over the pairs (+inf when there is none; computed once)."""
        kept = self.__dict__.get("_least")
        if kept is None:
            kept = self.d.min(axis=-1, initial=np.inf)
            object.__setattr__(self, "_least", kept)  # a cache of a fact of the gaps: the frame asks twice
        return cast(np.ndarray, kept)


def self_gaps(pose: Pose, capsules: Capsules, pairs: SelfPairs) -> SelfGaps:
    """Gaps of the enabled pairs at one pose or a batch (points (..., n+1, 3)).

    >>> from armanim.arm.kinematics import Arm, forward
    >>> from armanim.arm.capsules import joint_capsules
    >>> arm = Arm.from_names([1, 1, 1], axes=["z", "z", "z"], direction="x")
    >>> pose = forward(arm, np.radians([0.0, 170.0, 0.0]))   # folded back: link 3 over link 1
    >>> gaps = self_gaps(pose, joint_capsules(arm, 0.05), SelfPairs([0], [2], 0.01))
    >>> round(float(gaps.d[0]), 4), gaps.normal.shape
    (0.0736, (1, 3))
    """
    kept = pose.memo.get("self_gaps")
    if kept is not None and kept[0] is capsules and kept[1] is pairs:
        return cast(SelfGaps, kept[2])
    gaps = _self_gaps(pose, capsules, pairs)
    pose.memo["self_gaps"] = (capsules, pairs, gaps)  # the cost, the filter and the record ask for the same pose's
    return gaps


def _self_gaps(pose: Pose, capsules: Capsules, pairs: SelfPairs) -> SelfGaps:
    """:func:`self_gaps`, computed (:func:`armanim.world.compiled.segment_segment_pairs`)."""
    from armanim.world import compiled

    a, b = capsule_ends(capsules, pose)
    if a.ndim == 2 and len(pairs):  # one pose (every frame): the pairs as they are, no batch to lay out
        count = len(pairs)
        t, s, gap, normal = np.empty(count), np.empty(count), np.empty(count), np.empty((count, 3))
        least = compiled.capsule_pair_gaps(
            _rows(a), _rows(b), pairs.first, pairs.second, pairs.radii(capsules), t, s, gap, normal
        )
        gaps = SelfGaps(gap, t, s, normal)
        object.__setattr__(gaps, "_least", np.float64(least))  # the kernel found it: SelfGaps.least need not look again
        return gaps
    batch = a.shape[:-2]
    shape = batch + (len(pairs),)
    poses = int(np.prod(batch, dtype=int))
    if poses * len(pairs) == 0:
        empty = np.zeros(shape)
        return SelfGaps(empty, empty.copy(), empty.copy(), np.zeros(shape + (3,)))
    c = a.shape[-2]
    offset = (np.arange(poses) * c)[:, None]
    first, second = (offset + pairs.first).reshape(-1), (offset + pairs.second).reshape(-1)
    count = len(first)
    t, s, dist, normal = np.empty(count), np.empty(count), np.empty(count), np.empty((count, 3))
    compiled.segment_segment_pairs(_rows(a), _rows(b), first, second, t, s, dist, normal)
    d = dist.reshape(shape) - pairs.radii(capsules)
    return SelfGaps(d, t.reshape(shape), s.reshape(shape), normal.reshape(shape + (3,)))


def _rows(v: np.ndarray) -> np.ndarray:
    """(..., 3) points as C-contiguous, writable (N, 3) float rows (``v`` itself when it is already):
    the kernels are compiled once for the arrays the compiled loops pass, not again for read-only ones."""
    if v.ndim == 2 and v.dtype == np.float64 and v.flags.c_contiguous and v.flags.writeable:
        return v
    return np.array(v, dtype=float, order="C").reshape(-1, 3)


def least_self_gap(pose: Pose, capsules: Capsules, pairs: SelfPairs) -> np.ndarray:
    """(...) the smallest gap of any enabled pair (+inf without pairs)."""
    if not len(pairs):
        return np.full(pose.points.shape[:-2], np.inf)
    return self_gaps(pose, capsules, pairs).least


def self_rows(
    arm: Arm, capsules: Capsules, pose: Pose, pairs: SelfPairs, gaps: SelfGaps, which: np.ndarray
) -> np.ndarray:
    """(k, n) rows n . (J_A - J_B) of the pairs ``which`` (k,), one pose: how each pair's gap
    changes with the joint angles (the difference of the two closest points' Jacobians, along
    the normal)."""
    from armanim.world import compiled

    which = np.asarray(which, dtype=int)
    rows = np.empty((len(which), arm.n))
    if len(which):
        compiled.pair_rows(*_pair_inputs(arm, capsules, pose, pairs, gaps), gaps.normal, which, rows)
    return rows


def self_rows_met(
    arm: Arm,
    capsules: Capsules,
    pose: Pose,
    pairs: SelfPairs,
    gaps: SelfGaps,
    target: float,
    gamma: float,
    lever_rows: np.ndarray,
    step: np.ndarray,
    slack: float,
    extra: float,
    violation: float,
) -> bool:
    """Whether the step ``step`` (n,) meets every pair's row of :func:`self_rows`, rows . step >=
    -room with room = ``gamma`` (gap - ``target``), to ``violation``, one pose: the pairs whose room
    is at least ``slack`` x |step| . ``lever_rows`` (P, n) + ``extra`` by that bound alone, the
    others by their rows (computed only for them; all in one compiled call)."""
    from armanim.world import compiled

    points, axes, a, b, link, first, second, t, s = _pair_inputs(arm, capsules, pose, pairs, gaps)
    return bool(
        compiled.pair_rows_met(
            (points, axes, a, b, link),
            (first, second, gaps.d, t, s, gaps.normal),
            lever_rows,
            np.ascontiguousarray(step, dtype=float),
            (float(target), float(gamma), float(slack), float(extra), float(violation)),
        )
    )


def self_jacobians(
    arm: Arm, capsules: Capsules, pose: Pose, pairs: SelfPairs, gaps: SelfGaps, which: np.ndarray
) -> np.ndarray:
    """(k, 3, n) J_A - J_B of the pairs ``which`` (k,), one pose: how fast the first capsule's
    closest point moves away from the second's (the rows of :func:`self_rows` before the normal)."""
    from armanim.world import compiled

    which = np.asarray(which, dtype=int)
    jac = np.empty((len(which), 3, arm.n))
    if len(which):
        compiled.pair_jacobians(*_pair_inputs(arm, capsules, pose, pairs, gaps), which, jac)
    return jac


_PairInputs = tuple[
    np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray
]


def _pair_inputs(arm: Arm, capsules: Capsules, pose: Pose, pairs: SelfPairs, gaps: SelfGaps) -> _PairInputs:
    """The arrays the compiled pair Jacobians read: joint points, world axes, capsule ends, the
    capsules' links, the pairs and their closest points' fractions."""
    a, b = capsule_ends(capsules, pose)
    return (
        _rows(pose.points),
        kind_axes(arm, pose),
        _rows(a),
        _rows(b),
        capsules.link,
        pairs.first,
        pairs.second,
        gaps.t,
        gaps.s,
    )


def kind_axes(arm: Arm, pose: Pose) -> np.ndarray:
    """The world joint axes (n, 3) of one pose as the compiled pair Jacobians read them; for an arm
    with prismatic joints (n, 4), each joint's kind (1: prismatic) in the fourth column.

    >>> from armanim.arm.kinematics import forward
    >>> arm = Arm(np.zeros(3), np.eye(3)[:2], np.eye(3)[:2], prismatic=np.array([True, False]))
    >>> kind_axes(arm, forward(arm, np.zeros(2))).tolist()
    [[1.0, 0.0, 0.0, 1.0], [0.0, 1.0, 0.0, 0.0]]
    """
    return arm_kind_axes(arm, _rows(joint_axes_world(arm, pose)))
