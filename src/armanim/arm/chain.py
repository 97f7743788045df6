"""A serial chain from its joints' origins: URDF's convention folded into an :class:`Arm`.

Each joint has a fixed origin transform from the previous frame (xyz, then rpy in URDF's
fixed-axis convention R = Rz(yaw) Ry(pitch) Rx(roll)) and, if it moves, a unit axis.
Fixed joints fold into the next origin; what follows the last moving joint (fixed joints,
the tool frame) becomes the tip's offset. Pure core: numpy only, radians and metres (or
any one length unit), no I/O.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from armanim.arm.geometry import unit_vector
from armanim.arm.kinematics import Arm
from armanim.arm.rotations import rpy_rotation  # the one owner of rpy (re-exported here for URDF code)


def transform(xyz: ArrayLike = (0.0, 0.0, 0.0), rpy: Sequence[float] | np.ndarray = (0.0, 0.0, 0.0)) -> np.ndarray:
    """The 4x4 homogeneous transform of a URDF ``<origin xyz rpy>``.

    >>> transform([1, 2, 3])[:3, 3].tolist()
    [1.0, 2.0, 3.0]
    """
    t = np.eye(4)
    t[:3, :3] = rpy_rotation(rpy)
    t[:3, 3] = np.asarray(xyz, dtype=float)
    return t


@dataclass(frozen=True)
class ChainJoint:
    """One joint on the path from the base link to the tip link.

    Attributes
    ----------
    name : str
    origin : (4, 4) array
        From the parent link's frame to the joint's frame (and its child link's).
    axis : (3,) array or None
        Rotation axis in the joint's frame (any length > 0; normalised here); None for a fixed joint.
    prismatic : bool
        Whether the joint slides along its axis (metres) instead of turning about it.
    """

    name: str
    origin: np.ndarray
    axis: np.ndarray | None
    prismatic: bool = False


@dataclass(frozen=True)
class SerialChain:
    """An :class:`Arm` and where each link of its path sits on it.

    Attributes
    ----------
    arm : Arm
    carriers : tuple of int
        Per joint of the path (its child link): the moving joint whose frame carries it,
        -1 for links before the first moving joint (they never move).
    link_offsets : tuple of (4, 4) arrays
        Per joint of the path: the child link's frame in its carrier's (turned) frame, or in
        the world for carrier -1.
    """

    arm: Arm
    carriers: tuple[int, ...]
    link_offsets: tuple[np.ndarray, ...]


def serial_chain(mount: np.ndarray, joints: list[ChainJoint], tool: np.ndarray) -> SerialChain:
    """Fold a path of joints into an :class:`Arm`.

    Parameters
    ----------
    mount : (4, 4) array
        The base link's frame in the world.
    joints : list of ChainJoint
        From the base link to the tip link, in order; at least one moves.
    tool : (4, 4) array
        The tool frame in the tip link's frame (the tip is its origin).

    Examples
    --------
    Two revolute joints about z, half a metre apart, then a fixed 0.25 m flange:

    >>> up = lambda z: transform([0, 0, z])
    >>> z = np.array([0.0, 0, 1])
    >>> path = [ChainJoint("a", up(0.1), z), ChainJoint("b", up(0.5), z), ChainJoint("f", up(0.25), None)]
    >>> chain = serial_chain(np.eye(4), path, np.eye(4))
    >>> chain.arm.base.tolist(), chain.arm.offsets.tolist(), chain.carriers
    ([0.0, 0.0, 0.1], [[0.0, 0.0, 0.5], [0.0, 0.0, 0.25]], (0, 1, 1))
    """
    moving = [j for j in joints if j.axis is not None]
    if not moving:
        raise ValueError("the chain has no moving joint")
    rel = np.array(mount, dtype=float)  # the current link's frame, in the carrier's frame
    carrier = -1
    start: np.ndarray | None = None
    axes, offsets, turns, carriers, placed = [], [], [], [], []
    for joint in joints:
        rel = rel @ joint.origin
        if joint.axis is not None:
            if carrier < 0:
                start = rel
            else:
                offsets.append(rel[:3, 3].copy())
                turns.append(rel[:3, :3].copy())
            axes.append(unit_vector(joint.axis))
            carrier += 1
            rel = np.eye(4)
        carriers.append(carrier)
        placed.append(rel.copy())
    assert start is not None  # the chain has a moving joint (checked above)
    rel = rel @ tool
    offsets.append(rel[:3, 3].copy())
    turns.append(rel[:3, :3].copy())
    arm = Arm(
        base=start[:3, 3].copy(),
        axes=np.array(axes),
        offsets=np.array(offsets),
        base_rotation=start[:3, :3].copy(),
        turns=np.array(turns),
        joint_names=tuple(j.name for j in moving),
        mount=np.array(mount, dtype=float)[:3, 3].copy(),
        prismatic=np.array([j.prismatic for j in moving]) if any(j.prismatic for j in moving) else None,
    )
    return SerialChain(arm, tuple(carriers), tuple(placed))
