"""Link solids as polygon meshes: each link's prism is built in its own frame.

A link of length l_i is a prism with ``sides`` faces around the local axis
``direction`` (d), running from 0 to l_i * d in joint i's frame, then moved to the
world by that joint's frame: x_world = p_i + R_i x_local (the course notes'
section 2.2). Pure numpy: no drawing here.
"""

from __future__ import annotations

import numpy as np

from armanim.arm.kinematics import Arm, Pose


def perpendicular_basis(direction: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors u, v with (u, v, d) right-handed and orthonormal.

    >>> u, v = perpendicular_basis(np.array([0.0, 0.0, 1.0]))
    >>> np.cross(u, v)
    array([0., 0., 1.])
    """
    d = direction / np.linalg.norm(direction)
    helper = np.array([1.0, 0.0, 0.0]) if abs(d[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    u = np.cross(helper, d)
    u /= np.linalg.norm(u)
    return u, np.cross(d, u)


def prism_local(arm: Arm, radius: float, sides: int) -> np.ndarray:
    """Vertices of every link's prism in its joint's frame, shape (n, 2 * sides, 3).

    Ring 0 (the first ``sides`` vertices) lies around the joint, ring 1 around the
    link's far end.
    """
    u, v = perpendicular_basis(arm.direction)
    theta = 2 * np.pi * (np.arange(sides) + 0.5) / sides
    ring = radius * (np.cos(theta)[:, None] * u + np.sin(theta)[:, None] * v)  # (sides, 3)
    ends = arm.links[:, None, None] * arm.direction  # (n, 1, 3)
    return np.concatenate([np.broadcast_to(ring, ends.shape[:1] + ring.shape), ring + ends], axis=1)


def prism_world(pose: Pose, local: np.ndarray) -> np.ndarray:
    """Move local prism vertices to the world: p_i + R_i x, shape (..., n, V, 3)."""
    rotated = np.einsum("...nab,nvb->...nva", pose.frames, local)
    return rotated + pose.points[..., :-1, None, :]


def prism_faces(sides: int) -> list[np.ndarray]:
    """Vertex indices of the faces of a prism: ``sides`` quads, then the two caps.

    Every face is ordered counter-clockwise seen from outside (outward normals).
    """
    quads = [np.array([i, (i + 1) % sides, sides + (i + 1) % sides, sides + i]) for i in range(sides)]
    near_cap = np.arange(sides)[::-1]
    far_cap = sides + np.arange(sides)
    return quads + [near_cap, far_cap]


def prism_face_normals(arm: Arm, sides: int) -> np.ndarray:
    """Outward unit normals of :func:`prism_faces`, in the joint's frame, shape (sides + 2, 3)."""
    u, v = perpendicular_basis(arm.direction)
    mid = 2 * np.pi * (np.arange(sides) + 1.0) / sides
    side_normals = np.cos(mid)[:, None] * u + np.sin(mid)[:, None] * v
    return np.vstack([side_normals, -arm.direction, arm.direction])


def unit_circle(sides: int) -> np.ndarray:
    """(sides, 2) points of a regular polygon on the unit circle, the first at angle 0.

    >>> unit_circle(4).round(12) + 0.0
    array([[ 1.,  0.],
           [ 0.,  1.],
           [-1.,  0.],
           [ 0., -1.]])
    """
    theta = np.linspace(0, 2 * np.pi, sides, endpoint=False)
    return np.column_stack([np.cos(theta), np.sin(theta)])
