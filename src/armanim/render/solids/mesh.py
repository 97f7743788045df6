"""Capsule solids as polygon meshes: each capsule's prism is built in its joint's frame.

A capsule from s to e (radius r) is drawn as a prism with ``sides`` faces around the axis
e - s, in the frame of the joint that carries it, then moved to the world by that joint's
frame: x_world = p_k + R_k x_local (the course notes' section 2.2). Today's arms have one
capsule per link, from 0 to l_i d. Pure numpy: no drawing here.
"""

from __future__ import annotations

import numpy as np

from armanim.arm.capsules import Capsules


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


def capsule_axes(start: np.ndarray, end: np.ndarray) -> np.ndarray:
    """(c, 3) unit axis of every segment; z for a zero-length one (a sphere)."""
    axis = end - start
    length = np.linalg.norm(axis, axis=-1, keepdims=True)
    return np.where(length > 0, axis / np.where(length > 0, length, 1.0), [0.0, 0.0, 1.0])


def prism_vertices(start: np.ndarray, end: np.ndarray, radius: np.ndarray, sides: int) -> np.ndarray:
    """Vertices of a prism around every segment, shape (c, 2 * sides, 3), in the segments' frame.

    Ring 0 (the first ``sides`` vertices) lies around ``start``, ring 1 around ``end``.
    """
    theta = 2 * np.pi * (np.arange(sides) + 0.5) / sides
    out = []
    for s, e, r, d in zip(start, end, radius, capsule_axes(start, end)):
        u, v = perpendicular_basis(d)
        ring = r * (np.cos(theta)[:, None] * u + np.sin(theta)[:, None] * v)  # (sides, 3)
        out.append(np.concatenate([ring + s, ring + e]))
    return np.array(out).reshape(-1, 2 * sides, 3)


def prism_local(capsules: Capsules, sides: int) -> np.ndarray:
    """Vertices of every capsule's prism in its joint's frame, shape (c, 2 * sides, 3)."""
    return prism_vertices(capsules.start, capsules.end, capsules.radius, sides)


def prism_world(rotations: np.ndarray, origins: np.ndarray, local: np.ndarray) -> np.ndarray:
    """Move local prism vertices to the world: p_k + R_k x, shape (..., c, V, 3), for each capsule's
    frame (rotations (..., c, 3, 3), origins (..., c, 3): :func:`armanim.arm.capsules.carrier_frames`)."""
    rotated = np.einsum("...cab,cvb->...cva", rotations, local)
    return rotated + origins[..., None, :]


def prism_faces(sides: int) -> list[np.ndarray]:
    """Vertex indices of the faces of a prism: ``sides`` quads, then the two caps.

    Every face is ordered counter-clockwise seen from outside (outward normals).
    """
    quads = [np.array([i, (i + 1) % sides, sides + (i + 1) % sides, sides + i]) for i in range(sides)]
    near_cap = np.arange(sides)[::-1]
    far_cap = sides + np.arange(sides)
    return quads + [near_cap, far_cap]


def prism_face_normals(start: np.ndarray, end: np.ndarray, sides: int) -> np.ndarray:
    """Outward unit normals of :func:`prism_faces` of every segment, shape (c, sides + 2, 3)."""
    mid = 2 * np.pi * (np.arange(sides) + 1.0) / sides
    out = []
    for d in capsule_axes(start, end):
        u, v = perpendicular_basis(d)
        side_normals = np.cos(mid)[:, None] * u + np.sin(mid)[:, None] * v
        out.append(np.vstack([side_normals, -d, d]))
    return np.array(out).reshape(-1, sides + 2, 3)


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
