"""A robot's gripper: the fingers off the arm's chain that open and close on what the tool takes.

A URDF robot has a gripper when exactly one prismatic joint is held off the arm's chain and not a
mimic (the Panda's ``panda_finger_joint1``); the prismatic joints that mimic it move with it
(``panda_finger_joint2``). Its value ``q`` (metres per finger) moves every capsule of a finger
along a straight line in the frame of the joint that carries it: a point of a finger is at
``p0 + rate (q - q0)``, ``q0`` the value its capsules were built at (``arm.joint_values``), and
``rate`` the sum over the finger's sliding joints of their axis in the carrier's frame times
their multiplier. The gripper's opening is ``span q`` (the sum of the multipliers: the Panda's 2).

The fingers move only while the arm stands still, at the end of a goal's hold (:func:`ramp`),
at the joint's velocity limit. Pure core: numpy only, no I/O.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from armanim.arm.capsules import Capsules
from armanim.arm.visuals import ArmMeshes


@dataclass(frozen=True)
class Gripper:
    """The fingers of a robot.

    Attributes
    ----------
    joint : str
        The driving finger joint (its value is the gripper's, metres per finger).
    lower, upper : float
        Its limits, metres (``upper``: open).
    speed : float
        Its velocity limit, m/s (the URDF's ``<limit velocity>``).
    rest : float
        The value the capsules were built at (``arm.joint_values`` or the joint's default), metres.
    rate : (c, 3) array
        Each capsule's displacement per metre of the joint, in its carrier's frame (0 off the fingers).
    span : float
        The opening per metre of the joint (the sum of the finger joints' multipliers).
    links : tuple of str
        The links the joint moves (the fingers), for their drawing.
    link_rate : (len(links), 3) array
        Each such link's displacement per metre of the joint, in its carrier's frame.
    """

    joint: str
    lower: float
    upper: float
    speed: float
    rest: float
    rate: np.ndarray
    span: float
    links: tuple[str, ...] = ()
    link_rate: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))

    def grip(self, width: float) -> float:
        """The value that closes the fingers on an object ``width`` across between them, within the limits.

        >>> g = Gripper("f", 0.0, 0.04, 0.2, 0.04, np.zeros((0, 3)), 2.0)
        >>> g.grip(0.05), g.grip(0.1)
        (0.025, 0.04)
        """
        return float(np.clip(width / self.span, self.lower, self.upper))

    def ramp_frames(self, start: float, end: float, fps: float) -> int:
        """Frames the fingers take from ``start`` to ``end`` at the velocity limit (at least 1 where they move).

        >>> Gripper("f", 0.0, 0.04, 0.2, 0.04, np.zeros((0, 3)), 2.0).ramp_frames(0.04, 0.02, 30.0)
        3
        """
        if start == end:
            return 0
        return max(1, int(np.ceil(abs(end - start) / self.speed * fps - 1e-9)))

    def most_frames(self, fps: float) -> int:
        """Frames of the longest move (closed to open): what a goal's hold gains for its fingers."""
        return self.ramp_frames(self.lower, self.upper, fps)


def moved_fingers(capsules: Capsules, gripper: Gripper, value: float, at: float | None = None) -> Capsules:
    """``capsules``, whose fingers are at ``at`` (default ``gripper.rest``), with the fingers at
    ``value`` (metres; the first ``len(gripper.rate)`` capsules are the robot's own, any after
    them, a carried object's, stay).

    >>> caps = Capsules(np.array([0, 0]), np.zeros((2, 3)), np.ones((2, 3)), np.array([0.1, 0.1]))
    >>> g = Gripper("f", 0.0, 0.04, 0.2, 0.04, np.array([[0.0, 0.0, 0.0], [0.0, 1.0, 0.0]]), 2.0)
    >>> moved_fingers(caps, g, 0.01).start.tolist()
    [[0.0, 0.0, 0.0], [0.0, -0.03, 0.0]]
    """
    at = gripper.rest if at is None else at
    if value == at:
        return capsules
    shift = np.zeros_like(capsules.start)
    shift[: len(gripper.rate)] = gripper.rate * (value - at)
    return replace(capsules, start=capsules.start + shift, end=capsules.end + shift)


def moved_meshes(meshes: ArmMeshes, gripper: Gripper, value: float) -> ArmMeshes:
    """``meshes`` (drawn at ``gripper.rest``) with the fingers' triangles at ``value`` (metres).

    >>> from armanim.arm.visuals import LinkMesh, placed_meshes
    >>> tri = LinkMesh("f", np.eye(3), np.array([[0, 1, 2]]), np.ones((1, 3)))
    >>> g = Gripper("j", 0.0, 0.04, 0.2, 0.04, np.zeros((0, 3)), 2.0, ("f",), np.array([[0.0, 1.0, 0.0]]))
    >>> moved_meshes(placed_meshes([tri], [0], [np.eye(4)]), g, 0.01).vertices[:, 1].tolist()
    [-0.03, 0.97, -0.03]
    """
    if value == gripper.rest or not gripper.links:
        return meshes
    vertex_part = np.zeros(len(meshes.vertices), dtype=int)
    vertex_part[meshes.faces] = meshes.part[:, None]
    shift = np.zeros((len(meshes.links), 3))
    for name, rate in zip(gripper.links, gripper.link_rate):
        shift[[k for k, link in enumerate(meshes.links) if link == name]] = rate * (value - gripper.rest)
    return replace(meshes, vertices=meshes.vertices + shift[vertex_part])


def ramp(start: float, end: float, frames: int, count: int) -> np.ndarray:
    """(count,) the gripper's value over the last ``count`` frames of a goal whose fingers go from
    ``start`` to ``end`` in its last ``frames`` frames, at constant speed, reaching ``end`` at the
    goal's last frame.

    >>> ramp(0.04, 0.01, 3, 5).tolist()
    [0.04, 0.04, 0.03, 0.02, 0.01]
    """
    out = np.full(count, float(start))
    if frames and count:
        moving = start + (end - start) * np.arange(1, frames + 1) / frames
        moving[-1] = end
        kept = min(frames, count)
        out[count - kept :] = moving[frames - kept :]
    return out
