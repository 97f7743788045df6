"""The arm's collision capsules: segments with a radius, each carried by one joint's frame.

A capsule is every point within ``radius`` of the segment from ``start`` to ``end``, both
given in the frame of the joint that carries it (the URDF link that joint moves), or, for the
carrier :data:`BASE` (-1: the robot's base and what is fixed to it before the first moving
joint), in the world: the base never moves, so its points' Jacobian columns are all zero. Today's
arms have one capsule per link, from the joint to the next joint, of radius ``width / 2``
(:func:`joint_capsules`); a URDF arm has the capsules of its collision model. Every
consumer (clearances, the cost, the safety filter, the planner, the renderer) takes the
capsules' world ends from :func:`capsule_ends`. Pure core: numpy only, no I/O.
"""

from __future__ import annotations

import sys
from dataclasses import dataclass, field
from typing import cast

import numpy as np
from numpy.typing import ArrayLike

from armanim.arm.kinematics import Arm, Pose, forward, joint_axes_world, point_jacobian

BASE = -1
"""The carrier (:attr:`Capsules.link`) of a capsule on the base: its ends are in the world."""


@dataclass(frozen=True)
class Capsules:
    """The collision capsules of an arm.

    Parameters
    ----------
    link : (c,) int array
        0-based index of the joint whose frame carries each capsule; :data:`BASE` (-1) for a
        capsule on the robot's base (before the first moving joint).
    start, end : (c, 3) arrays
        The ends of each capsule's segment in that frame (in the world for the base's; scene units).
    radius : (c,) array
        Each capsule's radius (scene units, >= 0).
    names : tuple of str
        A name per capsule (its URDF link), or empty.
    allowed : (c,) int array, optional
        The obstacle column (of the obstacles the capsules are measured against) each capsule may
        touch, -1 for none (the default): a carried object's cover and the board it is set down
        on (:mod:`armanim.motion.carry`). Every clearance of that pair is +inf, as the floor's of
        the parts on the base.
    """

    link: np.ndarray
    start: np.ndarray
    end: np.ndarray
    radius: np.ndarray
    names: tuple[str, ...] = ()
    joint_segment: np.ndarray = field(
        default=cast(np.ndarray, None), repr=False, compare=False
    )  # None: __post_init__ fills it
    allowed: np.ndarray = field(
        default=cast(np.ndarray, None), repr=False, compare=False
    )  # None: __post_init__ fills it (-1)
    part_radius: np.ndarray = field(init=False, repr=False, compare=False)
    """(c+1,) the radius of every part that clearances are measured from: the capsules', then
    the tip's, 0 (a point)."""
    on_base: np.ndarray = field(init=False, repr=False, compare=False)
    """(c+1,) bool: the parts on the base or carried by the first joint (they stand on the base); the tip never."""
    part_allowed: np.ndarray = field(init=False, repr=False, compare=False)
    """(c+1,) int: ``allowed`` of every part (the tip's -1)."""
    moving: np.ndarray = field(init=False, repr=False, compare=False)
    """(c+1,) bool: the parts a joint moves (every part but the base's capsules; the tip always): only
    these are pushed away from an obstacle or give the filter a row (a part on the base has none to give)."""

    def __post_init__(self) -> None:
        object.__setattr__(self, "link", np.asarray(self.link, dtype=int))
        for name in ("start", "end", "radius"):
            object.__setattr__(self, name, np.asarray(getattr(self, name), dtype=float))
        if self.joint_segment is None:
            object.__setattr__(self, "joint_segment", np.zeros(len(self.link), dtype=bool))
        allowed = np.full(len(self.link), -1) if self.allowed is None else np.asarray(self.allowed, dtype=int)
        object.__setattr__(self, "allowed", allowed)
        object.__setattr__(self, "part_allowed", np.append(allowed, -1))
        object.__setattr__(self, "part_radius", np.append(self.radius, 0.0))  # asked every frame: made once
        object.__setattr__(self, "on_base", np.append(self.link <= 0, False))
        object.__setattr__(self, "moving", np.append(self.link >= 0, True))
        self.part_radius.flags.writeable = self.on_base.flags.writeable = self.moving.flags.writeable = False
        self.part_allowed.flags.writeable = False  # shared by every clearance computation

    def packed(self) -> np.ndarray:
        """(c, 8) each capsule as the compiled kernels read it: its start, its end (in its joint's
        frame), its radius, and 1.0 where it runs joint to joint (``joint_segment``), else 0.0.

        >>> Capsules(np.array([1]), np.zeros((1, 3)), np.ones((1, 3)), np.array([0.5])).packed().tolist()
        [[0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 0.5, 0.0]]
        """
        return np.concatenate(
            [self.start, self.end, self.radius[:, None], self.joint_segment[:, None].astype(float)], axis=1
        )

    def __len__(self) -> int:
        return len(self.link)

    @property
    def allows(self) -> bool:
        """Whether any capsule may touch an obstacle (:attr:`allowed`)."""
        return bool(np.any(self.allowed >= 0))


def joint_capsules(arm: Arm, radius: float) -> Capsules:
    """Today's capsules: link i from joint i to joint i+1 (the last to the tip), all of one radius
    (an arm of links: no joint slides).

    >>> caps = joint_capsules(Arm.from_names([2, 5]), 0.25)
    >>> caps.link.tolist(), caps.end.tolist(), caps.radius.tolist()
    ([0, 1], [[0.0, 0.0, 2.0], [0.0, 0.0, 5.0]], [0.25, 0.25])
    """
    return Capsules(
        link=np.arange(arm.n),
        start=np.zeros((arm.n, 3)),
        end=arm.offsets.copy(),
        radius=np.full(arm.n, float(radius)),
        joint_segment=np.ones(arm.n, dtype=bool),
    )


def frame_capsules(
    arm: Arm, link: ArrayLike, start: ArrayLike, end: ArrayLike, radius: ArrayLike, names: tuple[str, ...] = ()
) -> Capsules:
    """Capsules in joint frames; those that run exactly from a joint to the next one are
    marked, so that their world ends are the chain's own joint points (bit for bit).

    >>> arm = Arm.from_names([2, 5])
    >>> frame_capsules(arm, [1], [[0, 0, 0]], [[0, 0, 5]], [0.1]).joint_segment.tolist()
    [True]
    """
    link = np.asarray(link, dtype=int)
    start, end = np.asarray(start, dtype=float).reshape(-1, 3), np.asarray(end, dtype=float).reshape(-1, 3)
    segment = (link >= 0) & np.all(start == 0.0, axis=1) & np.all(end == arm.offsets[np.maximum(link, 0)], axis=1)
    if (
        arm.prismatic is not None
    ):  # the next joint slides its point off: the capsule ends where its slide starts, in its own frame
        segment &= ~np.append(arm.prismatic[1:], False)[np.maximum(link, 0)]
    return Capsules(link, start, end, np.asarray(radius, dtype=float), tuple(names), segment)


def capsule_ends(capsules: Capsules, pose: Pose) -> tuple[np.ndarray, np.ndarray]:
    """World ends a, b of every capsule's segment, each of shape (..., c, 3), read-only.

    x_world = p_k + R_k x for a capsule carried by joint k; a joint-to-joint capsule takes
    the pose's joint points p_k, p_{k+1} themselves; a capsule on the base (:data:`BASE`) its
    own ends, already in the world. Computed once per pose and capsules
    (kept in :attr:`Pose.memo`).

    >>> from armanim.arm.kinematics import forward
    >>> arm = Arm.from_names([2, 5], base=(1, 0, 0))
    >>> a, b = capsule_ends(joint_capsules(arm, 0.1), forward(arm, np.zeros(2)))
    >>> a.tolist(), b.tolist()
    ([[1.0, 0.0, 0.0], [1.0, 0.0, 2.0]], [[1.0, 0.0, 2.0], [1.0, 0.0, 7.0]])
    """
    kept = pose.memo.get("capsule_ends")
    if kept is not None and kept[0] is capsules:
        return cast("tuple[np.ndarray, np.ndarray]", kept[1])
    ends = _world_ends(capsules, pose)
    for end in ends:
        end.flags.writeable = False  # shared by every consumer of the pose
    pose.memo["capsule_ends"] = (capsules, ends)
    return ends


def _world_ends(capsules: Capsules, pose: Pose) -> tuple[np.ndarray, np.ndarray]:
    """:func:`capsule_ends`, computed: one pose by the compiled kernel once a solve has loaded it
    (some 30 numpy calls less a frame), else numpy; the two give the same bits, and numba is never
    loaded for this alone (``fk``, ``validate`` and spheres-only clearances go without it)."""
    link = capsules.link
    kernel = sys.modules.get("armanim.arm.kernel")
    if kernel is not None and pose.points.ndim == 2 and len(link):
        return cast(
            "tuple[np.ndarray, np.ndarray]",
            kernel.capsule_ends_one(
                link, capsules.start, capsules.end, capsules.joint_segment, pose.points, pose.frames
            ),
        )
    if capsules.joint_segment.all():
        return pose.points[..., link, :], pose.points[..., link + 1, :]
    base = (link < 0)[:, None]
    link = np.maximum(link, 0)  # the base's rows are replaced by their own ends below
    origin = pose.points[..., link, :]
    frames = pose.frames[..., link, :, :]
    a = origin + _rotated(frames, capsules.start)
    b = origin + _rotated(frames, capsules.end)
    segment = capsules.joint_segment[:, None]
    a, b = np.where(segment, origin, a), np.where(segment, pose.points[..., link + 1, :], b)
    if base.any():
        a, b = np.where(base, capsules.start, a), np.where(base, capsules.end, b)
    return a, b


def carrier_frames(capsules: Capsules, pose: Pose) -> tuple[np.ndarray, np.ndarray]:
    """The world rotation (..., c, 3, 3) and origin (..., c, 3) of the frame each capsule is given
    in: its joint's, or the world's (identity, 0) for a capsule on the base (:data:`BASE`).

    >>> from armanim.arm.kinematics import forward
    >>> arm = Arm.from_names([2, 5], base=(1, 0, 0))
    >>> caps = frame_capsules(arm, [BASE, 1], np.zeros((2, 3)), np.zeros((2, 3)), [0.1, 0.1])
    >>> rot, origin = carrier_frames(caps, forward(arm, np.zeros(2)))
    >>> origin.tolist()
    [[0.0, 0.0, 0.0], [1.0, 0.0, 2.0]]
    """
    base = capsules.link < 0
    link = np.maximum(capsules.link, 0)
    rot, origin = pose.frames[..., link, :, :], pose.points[..., link, :]
    if base.any():
        rot = np.where(base[:, None, None], np.eye(3), rot)
        origin = np.where(base[:, None], 0.0, origin)
    return rot, origin


def _rotated(frames: np.ndarray, x: np.ndarray) -> np.ndarray:
    """(..., c, 3) R_c x_c for frames (..., c, 3, 3) and points (c, 3), each row's sum in the
    order the compiled kernel adds it (einsum's order is its own), so one pose's ends equal a
    batch's bit for bit."""
    return cast(
        np.ndarray, frames[..., 0] * x[:, None, 0] + frames[..., 1] * x[:, None, 1] + frames[..., 2] * x[:, None, 2]
    )


def capsule_point(capsules: Capsules, pose: Pose, capsule: int | np.ndarray, t: float | np.ndarray) -> np.ndarray:
    """The point at fraction ``t`` along capsule ``capsule``'s segment, in the world, (..., 3);
    for (k,) arrays ``capsule`` and ``t`` (a single pose), the k points, (k, 3)."""
    a, b = capsule_ends(capsules, pose)
    a, b = a[..., capsule, :], b[..., capsule, :]
    if np.ndim(capsule):
        t = np.asarray(t)[:, None]
    return cast(np.ndarray, a + t * (b - a))


def capsule_point_jacobian(
    arm: Arm, capsules: Capsules, pose: Pose, capsule: int | np.ndarray, t: float | np.ndarray
) -> np.ndarray:
    """(..., 3, n) analytic Jacobian of the point at fraction ``t`` along capsule ``capsule``;
    for (k,) arrays ``capsule`` and ``t`` (a single pose), the k points' Jacobians in one
    call, (k, 3, n), each the same as alone, each computed once per pose (a frame's pushes,
    filter rows and cost gradient ask for the same closest points: kept in :attr:`Pose.memo`).

    >>> from armanim.arm.kinematics import forward
    >>> arm = Arm.from_names([1, 1], axes=["z", "z"], direction="x")
    >>> capsule_point_jacobian(arm, joint_capsules(arm, 0.1), forward(arm, np.zeros(2)), 1, 0.5)[1].tolist()
    [1.5, 0.5]
    """
    if not np.ndim(capsule):
        return _point_jacobians(arm, capsules, pose, capsule, t)
    kept = pose.memo.get("capsule_point_jacobians")
    if kept is None or kept[0] is not arm or kept[1] is not capsules:
        kept = pose.memo["capsule_point_jacobians"] = (arm, capsules, {})
    known: dict[tuple[int, float], np.ndarray] = kept[2]
    points = list(zip(np.asarray(capsule).tolist(), np.asarray(t, dtype=float).tolist()))
    missing = [point for point in dict.fromkeys(points) if point not in known]
    if missing:
        fresh = _point_jacobians(
            arm, capsules, pose, np.array([c for c, _ in missing]), np.array([s for _, s in missing])
        )
        known.update(zip(missing, fresh))
    if not points:
        return np.zeros((0, 3, arm.n))
    return np.array([known[point] for point in points])  # a copy, as np.stack makes, at a third of its overhead


def _point_jacobians(
    arm: Arm, capsules: Capsules, pose: Pose, capsule: int | np.ndarray, t: float | np.ndarray
) -> np.ndarray:
    """:func:`capsule_point_jacobian`, computed."""
    point = capsule_point(capsules, pose, capsule, t)
    link = capsules.link[capsule] if np.ndim(capsule) else int(capsules.link[capsule])
    return point_jacobian(arm, pose, link, point)


def tip_radius(arm: Arm, capsules: Capsules) -> float:
    """The largest radius of the capsules the last joint carries (0 if none): how far the
    arm's solid reaches around its tip.

    >>> tip_radius(Arm.from_names([2, 5]), joint_capsules(Arm.from_names([2, 5]), 0.25))
    0.25
    """
    last = capsules.radius[capsules.link == arm.n - 1]
    return float(last.max()) if len(last) else 0.0


def lever_arms(arm: Arm, capsules: Capsules) -> np.ndarray:
    """(n,) the farthest any capsule point moved by joint j lies from joint j's origin.

    A capsule carried by joint k >= j lies within |o_j| + ... + |o_k| + pad of p_j, where
    pad is the radius plus how far its ends stick out (its start from p_k, or its end
    from p_{k+1}, whichever is nearer for each end); joint-to-joint capsules stick out by
    their radius alone. Capsules on the base (:data:`BASE`) never move: none counts. A
    prismatic joint k > j may hold the capsules up to its stroke farther off (add them all); a
    prismatic joint j moves every point it carries by exactly its own travel: its lever is 1.

    >>> lever_arms(Arm.from_names([2, 5]), joint_capsules(Arm.from_names([2, 5]), 0.25)).tolist()
    [7.25, 5.25]
    """
    tail = np.cumsum(arm.links[::-1])[::-1]
    moving = capsules.link >= 0
    link = capsules.link[moving]
    off = arm.offsets[link]
    start = np.minimum(_norm(capsules.start[moving]), _norm(capsules.start[moving] - off))
    end = np.minimum(_norm(capsules.end[moving]), _norm(capsules.end[moving] - off))
    pad = np.where(capsules.joint_segment[moving], 0.0, np.maximum(start, end)) + capsules.radius[moving]
    by_link = np.zeros(arm.n)
    np.maximum.at(by_link, link, pad)
    levers = tail + np.maximum.accumulate(by_link[::-1])[::-1]
    if arm.prismatic is None:
        return levers
    stroke = np.zeros(arm.n) if arm.stroke is None else arm.stroke
    after = np.concatenate([np.cumsum(stroke[::-1])[::-1][1:], [0.0]])  # the strokes of the joints after j
    return np.where(arm.prismatic, 1.0, levers + after)


def capsule_lever_rows(arm: Arm, capsules: Capsules) -> np.ndarray:
    """(c, n) the most any point of each capsule moves per radian of joint j, for the joints that
    move it (0 for the others, and for every joint on the base's capsules): a change dPhi moves
    capsule i's points by at most |dPhi| . row i.

    For the joints before its carrier, :func:`lever_arms`' bound for this one capsule (its chain
    cut at its carrier): how far it can lie from the joint's origin. For its carrier, how far it
    lies from that joint's axis, which its frame holds fixed (a sphere on a wrist's axis hardly
    moves as the wrist turns). A prismatic joint moves the points it carries by its travel (1 per
    metre), and the strokes of the prismatic joints after joint j up to the carrier add to j's.

    >>> arm = Arm.from_names([2, 5])
    >>> capsule_lever_rows(arm, joint_capsules(arm, 0.25)).tolist()
    [[0.25, 0.0], [7.25, 5.25]]
    """
    head = np.concatenate([[0.0], np.cumsum(arm.links)])
    link = capsules.link
    carried = np.maximum(link, 0)
    off = arm.offsets[carried]
    start = np.minimum(_norm(capsules.start), _norm(capsules.start - off))
    end = np.minimum(_norm(capsules.end), _norm(capsules.end - off))
    pad = np.where(capsules.joint_segment, 0.0, np.maximum(start, end)) + capsules.radius
    axis = arm.axes[carried]
    around = np.maximum(_off_axis(capsules.start, axis), _off_axis(capsules.end, axis)) + capsules.radius
    joint = np.arange(arm.n)
    moved = (link[:, None] >= 0) & (joint[None, :] <= link[:, None])
    rows = np.where(moved, head[carried + 1][:, None] - head[None, :-1] + pad[:, None], 0.0)
    own = link >= 0
    rows[own, link[own]] = around[own]
    if arm.prismatic is None:
        return rows
    stroke = (
        np.zeros(arm.n) if arm.stroke is None else arm.stroke
    )  # a slide between joint j and the carrier moves it farther off
    slid = np.concatenate([[0.0], np.cumsum(stroke)])
    rows = np.where(moved, rows + slid[carried + 1][:, None] - slid[None, 1:], 0.0)
    return np.where(moved & arm.prismatic[None, :], 1.0, rows)  # a slide moves every point it carries by its own travel


def next_axis_reach(arm: Arm, capsules: Capsules) -> np.ndarray:
    """(c,) the farthest each capsule's segment lies from the axis of the joint after its carrier
    (joint 0 for the base's capsules): a line its carrier's frame holds fixed, so the same at every
    pose; inf where that joint slides or there is none.

    It bounds how fast a gap changes: turning joint j moves a point B carried beyond it by
    w x (B - o), and the gap |B - A| to a point A of a capsule before it changes at the rate
    n . (w x (B - o)) with n the unit (B - A) / |B - A|, which equals n . (w x (A - o)): at most A's
    distance from the axis. A sphere on the axis of the joint after it (the UR5's base on its pan
    axis) keeps its gap to everything that joint turns.

    >>> arm = Arm.from_names([2, 5])
    >>> next_axis_reach(arm, joint_capsules(arm, 0.25)).tolist()  # joint 1 turns about y at the first link's top
    [2.0, inf]
    """
    pose = forward(arm, np.zeros(arm.n))
    a, b = capsule_ends(capsules, pose)
    after = capsules.link + 1
    slides = np.zeros(arm.n, dtype=bool) if arm.prismatic is None else arm.prismatic
    turns = after < arm.n
    turns[turns] = ~slides[after[turns]]
    origin, axis = pose.points[after[turns]], joint_axes_world(arm, pose)[after[turns]]
    reach = np.full(len(after), np.inf)
    reach[turns] = np.maximum(_off_axis(a[turns] - origin, axis), _off_axis(b[turns] - origin, axis))
    return reach


def _off_axis(v: np.ndarray, axis: np.ndarray) -> np.ndarray:
    """(c,) the distance of points ``v`` (c, 3) from the lines through the origin along the unit ``axis`` (c, 3)."""
    along = (v * axis).sum(axis=-1, keepdims=True)
    return _norm(v - along * axis)


def _norm(v: np.ndarray) -> np.ndarray:
    return cast(np.ndarray, np.sqrt((v * v).sum(axis=-1)))
