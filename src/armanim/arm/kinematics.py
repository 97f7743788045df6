"""THE forward kinematics of armanim and its Jacobians (the pseudo-inverse is in :mod:`armanim.arm.linalg`).

The chain (:class:`Arm`): joint i sits at p_i with world rotation
R_i = R_{i-1} T_{i-1} Rot(a_i, phi_i), p_1 = base and p_{i+1} = p_i + R_i o_i. The tip
is e = p_{n+1}. For the default arm (o_i = l_i d, no T) this is the course notes' chain
T01 = [Rz(phi1), p1], T12 = [Ry(phi2), t_z(l1)], ...

A prismatic joint (:attr:`Arm.prismatic`) slides its frame along its axis: its value is in
metres, a revolute joint's in radians. Pure core: numpy only, radians and metres, no I/O. Everything that needs joint
positions (solvers, cost, renderer, CLI) calls :func:`forward`.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any, cast

import numpy as np
from numpy.typing import ArrayLike

from armanim.arm.geometry import axis_vector, cross, skew

_IDENTITY = np.eye(3)


@dataclass(frozen=True)
class Arm:
    """A serial chain of revolute joints: each joint turns about its own axis, then a fixed
    transform carries its frame to the next joint (or, after the last, to the tip).

    Joint i sits at p_i with world rotation R_i = R_{i-1} T_{i-1} Rot(a_i, phi_i), where
    R_0 = ``base_rotation`` and T_i = ``turns[i]``; p_1 = ``base`` and
    p_{i+1} = p_i + R_i o_i with o_i = ``offsets[i]``. The tip is p_{n+1}. Today's arms
    (:meth:`from_names`) are the special case o_i = l_i d, no turns, no base rotation; a URDF
    chain (fixed joints folded into the next origin) is the general one.

    Parameters
    ----------
    base : (3,) array
        World position of joint 1.
    axes : (n, 3) array
        Unit rotation axis of each joint, in the joint's own frame.
    offsets : (n, 3) array
        From joint i to joint i+1 (the last: to the tip), in joint i's frame, after it turned.
    base_rotation : (3, 3) array or None
        World rotation of joint 1's frame before it turns; None: the identity.
    turns : (n, 3, 3) array or None
        Rotation from joint i's frame to joint i+1's (the last: to the tool frame); None: all identity.
    joint_names : tuple of str
        One name per joint (a URDF's), or empty.
    mount : (3,) array or None
        World position of the robot's base link, where it stands (a URDF arm's first joint
        may sit above it); None: ``base``.
    prismatic : (n,) bool array or None
        Which joints slide along their axis instead of turning about it (a rail, a lift): joint
        i's frame keeps R_i = R_{i-1} T_{i-1} and its origin moves to p_i + q_i R_i a_i, q_i in
        metres. None (or all False, which becomes None): every joint is revolute, and the
        arithmetic is exactly that of an arm without the field.
    stroke : (n,) array or None
        How far each prismatic joint may slide from 0, metres (its larger limit in size; 0 for a
        revolute joint): what :attr:`reach` and the lever arms add for it. None: all 0.
    """

    base: np.ndarray
    axes: np.ndarray
    offsets: np.ndarray
    base_rotation: np.ndarray | None = None
    turns: np.ndarray | None = None
    joint_names: tuple[str, ...] = ()
    mount: np.ndarray | None = None
    prismatic: np.ndarray | None = None
    stroke: np.ndarray | None = None
    _k: np.ndarray = field(init=False, repr=False, compare=False)
    _k2: np.ndarray = field(init=False, repr=False, compare=False)
    _links: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        for name in ("base", "axes", "offsets", "base_rotation", "turns", "mount", "stroke"):
            value = getattr(self, name)
            if value is not None:
                object.__setattr__(self, name, np.asarray(value, dtype=float))
        if self.prismatic is not None:
            slides = np.asarray(self.prismatic, dtype=bool).reshape(len(self.axes))
            object.__setattr__(self, "prismatic", slides if slides.any() else None)
        k = np.stack([skew(a) for a in self.axes])
        object.__setattr__(self, "_k", k)
        object.__setattr__(self, "_k2", k @ k)
        object.__setattr__(self, "_links", np.sqrt((self.offsets * self.offsets).sum(axis=1)))

    @property
    def n(self) -> int:
        """Number of joints."""
        return len(self.axes)

    @property
    def slides(self) -> np.ndarray:
        """(n,) bool: which joints are prismatic (all False for an arm of revolute joints).

        >>> Arm.from_names([1, 1]).slides.tolist()
        [False, False]
        """
        return np.zeros(self.n, dtype=bool) if self.prismatic is None else self.prismatic

    @property
    def stand(self) -> np.ndarray:
        """(3,) where the robot stands: ``mount``, or joint 1 for an arm of links."""
        return self.base if self.mount is None else self.mount

    @property
    def links(self) -> np.ndarray:
        """(n,) |o_i|: the distance from joint i to joint i+1 (the last: to the tip)."""
        return self._links

    @property
    def reach(self) -> float:
        """Sum of the link lengths and the prismatic joints' strokes: no tip is farther than this
        from joint 1 at its 0 (``base``)."""
        if self.stroke is None:
            return float(self.links.sum())
        return float(self.links.sum() + self.stroke.sum())

    @classmethod
    def from_names(
        cls,
        links: Sequence[float] | np.ndarray,
        base: ArrayLike = (0.0, 0.0, 0.0),
        axes: list[str] | None = None,
        direction: str = "z",
    ) -> Arm:
        """Build an arm of straight links along ``direction``, with the contract's default axes (z, then y).

        >>> Arm.from_names([2, 5, 5, 5], base=(5, 5, 0)).n
        4
        """
        n = len(links)
        names = axes if axes is not None else default_axes(n)
        return cls(
            base=np.asarray(base, dtype=float),
            axes=np.stack([axis_vector(a) for a in names]),
            offsets=np.asarray(links, dtype=float)[:, None] * axis_vector(direction)[None, :],
        )


def default_axes(n: int) -> list[str]:
    """The contract's default joint axes: z for the base joint, y for every other.

    >>> default_axes(4)
    ['z', 'y', 'y', 'y']
    """
    return ["z"] + ["y"] * (n - 1)


@dataclass(frozen=True, init=False)
class Pose:
    """Joint points and frames of one or many poses.

    Attributes
    ----------
    points : (..., n+1, 3) array
        p_1 .. p_{n+1}: the joints from the base to the tip.
    frames : (..., n, 3, 3) array
        R_1 .. R_n: each joint's world rotation.
    axes : (..., n, 3) array or None
        w_j = R_j a_j, each joint's axis in the world (kept by single-pose FK, which the
        Jacobians of a frame reuse); None where not computed.
    memo : dict
        What has been computed from this pose and is asked for again within a frame (the
        capsules' world ends, the Jacobians of points on them), filled by their functions in
        :mod:`armanim.arm.capsules`: each is computed once per pose, however many consumers
        (clearances, the method's pushes, the filter's rows, the cost's gradient) ask.
    """

    points: np.ndarray
    frames: np.ndarray
    axes: np.ndarray | None = None  # (..., n, 3) world joint axes, when forward computed them
    memo: dict[str, Any] = field(default_factory=dict, init=False, repr=False, compare=False)

    def __init__(self, points: np.ndarray, frames: np.ndarray, axes: np.ndarray | None = None) -> None:
        # Every solver step builds a pose: filling the instance's dict at once costs a third of
        # the dataclass's frozen __init__ (one object.__setattr__ per field; single-pose FK's
        # budget is a few microseconds). The instance stays frozen to assignment.
        self.__dict__.update(points=points, frames=frames, axes=axes, memo={})

    @property
    def tip(self) -> np.ndarray:
        """(..., 3): the end effector e = p_{n+1}."""
        return self.points[..., -1, :]


def forward(arm: Arm, phi: np.ndarray) -> Pose:
    """Forward kinematics of one pose or a batch of poses.

    Parameters
    ----------
    arm : Arm
    phi : (..., n) array
        Joint angles in radians; any leading batch shape, e.g. (F, n).

    Returns
    -------
    Pose
        ``points`` of shape (..., n+1, 3) and ``frames`` of shape (..., n, 3, 3).

    Examples
    --------
    The course notes' arm at home stands straight up from its base:

    >>> arm = Arm.from_names([2, 5, 5, 5], base=(5, 5, 0))
    >>> forward(arm, np.zeros(4)).tip
    array([ 5.,  5., 17.])
    >>> forward(arm, np.zeros((10, 4))).points.shape
    (10, 5, 3)
    """
    phi = np.asarray(phi, dtype=float)
    if phi.ndim == 1:
        return _forward_one(arm, phi)
    batch = phi.shape[:-1]
    local = joint_rotations(arm, phi)
    frames = np.empty(batch + (arm.n, 3, 3))
    points = np.empty(batch + (arm.n + 1, 3))
    points[..., 0, :] = arm.base
    rot = np.broadcast_to(_start_rotation(arm), batch + (3, 3))
    for i in range(arm.n):
        rot = rot @ local[..., i, :, :]
        frames[..., i, :, :] = rot
        if arm.prismatic is not None and arm.prismatic[i]:  # the joint's frame slides along its axis
            points[..., i, :] += phi[..., i, None] * (rot @ arm.axes[i])
        points[..., i + 1, :] = points[..., i, :] + rot @ arm.offsets[i]
        if arm.turns is not None:
            rot = rot @ arm.turns[i]
    return Pose(points=points, frames=frames)


def _start_rotation(arm: Arm) -> np.ndarray:
    """R_0: the world rotation of joint 1's frame before it turns."""
    return _IDENTITY if arm.base_rotation is None else arm.base_rotation


def joint_rotations(arm: Arm, phi: np.ndarray) -> np.ndarray:
    """Rot(a_i, phi_i) of every joint, shape (..., n, 3, 3), by Rodrigues' formula
    I + sin(phi) K + (1 - cos(phi)) K^2; for the coordinate axes these are the notes'
    Eqs. 23-25. A prismatic joint's is the identity.

    >>> arm = Arm.from_names([1.0], axes=["z"])
    >>> np.round(joint_rotations(arm, np.array([np.pi / 2]))[0], 12) + 0.0
    array([[ 0., -1.,  0.],
           [ 1.,  0.,  0.],
           [ 0.,  0.,  1.]])
    """
    if arm.prismatic is not None:  # a prismatic joint does not turn: Rot(a, 0) = I exactly
        phi = np.where(arm.prismatic, 0.0, phi)
    s = np.sin(phi)[..., None, None]
    c = np.cos(phi)[..., None, None]
    return cast(np.ndarray, _IDENTITY + s * arm._k + (1.0 - c) * arm._k2)


def _forward_one(arm: Arm, phi: np.ndarray) -> Pose:
    """:func:`forward` for a single pose: the same chain without batch overhead (hot path)."""
    local = joint_rotations(arm, phi)
    frames = np.empty((arm.n, 3, 3))
    points = np.empty((arm.n + 1, 3))
    points[0] = arm.base
    rot = _start_rotation(arm)
    for i in range(arm.n):
        rot = rot @ local[i]
        frames[i] = rot
        if arm.prismatic is not None and arm.prismatic[i]:  # the joint's frame slides along its axis
            points[i] += phi[i] * (rot @ arm.axes[i])
        points[i + 1] = points[i] + rot @ arm.offsets[i]
        if arm.turns is not None:
            rot = rot @ arm.turns[i]
    return Pose(points=points, frames=frames, axes=(frames @ arm.axes[:, :, None])[:, :, 0])


def joint_axes_world(arm: Arm, pose: Pose) -> np.ndarray:
    """World direction w_j = R_j a_j of every joint axis, shape (..., n, 3)."""
    if pose.axes is not None:
        return pose.axes
    return cast(np.ndarray, np.einsum("...jab,jb->...ja", pose.frames, arm.axes))


def kind_axes(arm: Arm, axes: np.ndarray) -> np.ndarray:
    """World joint ``axes`` (..., n, 3) as the compiled kernels read them
    (:func:`armanim.arm.kernel.joint_slides`): as they are for an arm of revolute joints, and
    (..., n, 4) with each joint's kind (1: prismatic) in a fourth column for an arm with a
    prismatic joint.

    >>> arm = Arm(np.zeros(3), np.eye(3)[:2], np.eye(3)[:2], prismatic=np.array([True, False]))
    >>> kind_axes(arm, np.eye(3)[:2]).tolist()
    [[1.0, 0.0, 0.0, 1.0], [0.0, 1.0, 0.0, 0.0]]
    """
    if arm.prismatic is None:
        return axes
    kinds = np.broadcast_to(arm.prismatic.astype(float)[:, None], axes.shape[:-1] + (1,))
    return np.ascontiguousarray(np.concatenate([axes, kinds], axis=-1))


def _columns(arm: Arm, w: np.ndarray, lever: np.ndarray) -> np.ndarray:
    """Linear Jacobian columns (..., j, 3) of a point at ``lever`` = q - p_j from joints of world
    axes ``w`` (..., j, 3) (the first j of the arm's): w_j x (q - p_j) for a revolute joint, w_j
    for a prismatic one (the point slides with it)."""
    columns = cross(w, lever)
    if arm.prismatic is None:
        return columns
    slides = arm.prismatic[: w.shape[-2], None]
    return np.where(slides, np.broadcast_to(w, columns.shape), columns)


def link_point(pose: Pose, link: int, t: float) -> np.ndarray:
    """The point at fraction ``t`` along link ``link`` (0-based), shape (..., 3)."""
    a = pose.points[..., link, :]
    return cast(np.ndarray, a + t * (pose.points[..., link + 1, :] - a))


def point_jacobian(arm: Arm, pose: Pose, link: int, point: np.ndarray) -> np.ndarray:
    """Analytic Jacobian d q / d phi of a point q carried by joint ``link``'s frame.

    Column j is w_j x (q - p_j) for the joints j <= link that move the point (w_j for a
    prismatic joint: the point slides along its axis), and 0 for the joints after it.

    Parameters
    ----------
    arm, pose : the arm and its pose from :func:`forward` (single or batched).
    link : int or (k,) int array
        0-based index of the joint whose frame carries the point (link i runs from joint i);
        an array: one per point, for k points of a single pose.
    point : (..., 3) array, or (k, 3) with an array ``link``
        Where the point is, in the world (e.g. ``link_point(pose, link, t)``).

    Returns
    -------
    (..., 3, n) array, or (k, 3, n) with an array ``link`` (the same columns, every point's in one call)

    >>> arm = Arm.from_names([1, 1], axes=["z", "z"], direction="x")
    >>> pose = forward(arm, np.zeros(2))
    >>> point_jacobian(arm, pose, 1, pose.tip) + 0.0
    array([[0., 0.],
           [2., 1.],
           [0., 0.]])
    """
    w = joint_axes_world(arm, pose)
    if np.ndim(link):
        lever = point[:, None, :] - pose.points[:-1, :]  # (k, n, 3)
        moves = np.arange(arm.n) <= np.asarray(link)[:, None]  # (k, n): the joints that move point i
        return np.ascontiguousarray(
            np.swapaxes(np.where(moves[..., None], _columns(arm, w, lever), 0.0), -1, -2)
        )  # laid out as one alone
    jac = np.zeros(pose.points.shape[:-2] + (3, arm.n))
    lever = point[..., None, :] - pose.points[..., : link + 1, :]
    jac[..., :, : link + 1] = np.swapaxes(_columns(arm, w[..., : link + 1, :], lever), -1, -2)
    return jac


def tip_jacobian(arm: Arm, pose: Pose) -> np.ndarray:
    """Analytic Jacobian of the tip, (..., 3, n): the course notes' Eq. 14.

    :func:`point_jacobian` at the tip, where every joint moves the point, written
    without the masking (it runs every frame).
    """
    lever = pose.tip[..., None, :] - pose.points[..., :-1, :]
    return np.swapaxes(_columns(arm, joint_axes_world(arm, pose), lever), -1, -2)


def tool_rotation(arm: Arm, pose: Pose) -> np.ndarray:
    """World rotation of the tool frame, (..., 3, 3): R_n T_n, the last joint's frame carried
    by its fixed turn to the tool (the last joint's own frame for an arm without turns).

    >>> arm = Arm.from_names([1.0], axes=["z"])
    >>> np.round(tool_rotation(arm, forward(arm, np.array([np.pi / 2]))) @ [1, 0, 0], 12) + 0.0
    array([0., 1., 0.])
    """
    last = pose.frames[..., -1, :, :]
    return last if arm.turns is None else last @ arm.turns[-1]


def angular_jacobian(arm: Arm, pose: Pose) -> np.ndarray:
    """Geometric angular Jacobian of the tool frame, (..., 3, n): column j is w_j, the world
    axis of joint j (the tool's angular velocity per joint rate); 0 for a prismatic joint.

    >>> arm = Arm.from_names([1, 1], axes=["z", "y"])
    >>> angular_jacobian(arm, forward(arm, np.zeros(2))).tolist()
    [[0.0, 0.0], [0.0, 1.0], [1.0, 0.0]]
    """
    w = joint_axes_world(arm, pose)
    if arm.prismatic is not None:
        w = np.where(arm.prismatic[:, None], 0.0, w)
    return np.swapaxes(w, -1, -2)


def point_hessian(arm: Arm, pose: Pose, link: int, point: np.ndarray) -> np.ndarray:
    """Second derivatives d^2 q / d phi_i d phi_j of a point carried by joint ``link``'s frame,
    shape (3, n, n); ``point`` (3,) is where it is in the world.

    For i <= j <= link: w_i x D_j with D_j the Jacobian's column j (w_j x (q - p_j), or w_j
    for a prismatic joint), symmetric in i, j; zero where joint i is prismatic (sliding moves
    q, p_j and w_j alike) and for joints after ``link``. These are the n-link assignment's P''
    blocks. Single pose only.
    """
    w = joint_axes_world(arm, pose)
    k = link + 1
    d = _columns(arm, w[:k], point - pose.points[:k])  # (k, 3): column j of the Jacobian
    turning = w[:k] if arm.prismatic is None else np.where(arm.prismatic[:k, None], 0.0, w[:k])
    second = cross(turning[:, None, :], d[None, :, :])  # [i, j] = w_i x D_j
    upper = np.triu(np.ones((k, k), dtype=bool))  # i <= j
    block = np.where(upper[..., None], second, np.swapaxes(second, 0, 1))
    hess = np.zeros((3, arm.n, arm.n))
    hess[:, :k, :k] = np.moveaxis(block, -1, 0)
    return hess


def numeric_jacobian(fun: Callable[[np.ndarray], np.ndarray], phi: np.ndarray, h: float = 1e-6) -> np.ndarray:
    """Forward-difference Jacobian of a vector function: the course notes' Eq. 15.

    Column i is (fun(phi + h e_i) - fun(phi)) / h. All n displaced poses are
    evaluated as one batch, so ``fun`` must accept (..., n).

    >>> numeric_jacobian(lambda p: np.stack([p[..., 0] ** 2], -1), np.array([3.0])).round(4)
    array([[6.]])
    """
    phi = np.asarray(phi, dtype=float)
    displaced = phi + h * np.eye(len(phi))
    f0 = fun(phi)
    return cast(np.ndarray, (fun(displaced) - f0).T / h)


def joints_in_si(values: ArrayLike, slides: np.ndarray | None) -> np.ndarray:
    """Joint values as a user writes them (degrees; metres for a prismatic joint), (..., n), in
    the chain's units (radians; metres): exactly ``np.radians`` where no joint slides.

    >>> joints_in_si([90.0, 0.25], np.array([False, True])).round(6).tolist()
    [1.570796, 0.25]
    """
    si = np.radians(values)
    if slides is None or not np.any(slides):
        return si
    return np.where(slides, np.asarray(values, dtype=float), si)


def joints_shown(values: ArrayLike, slides: np.ndarray | None) -> np.ndarray:
    """:func:`joints_in_si`'s inverse: radians (metres for a prismatic joint), (..., n), as a user
    reads them, degrees (metres); exactly ``np.degrees`` where no joint slides.

    >>> joints_shown([np.pi / 2, 0.25], np.array([False, True])).round(6).tolist()
    [90.0, 0.25]
    """
    shown = np.degrees(values)
    if slides is None or not np.any(slides):
        return shown
    return np.where(slides, np.asarray(values, dtype=float), shown)
