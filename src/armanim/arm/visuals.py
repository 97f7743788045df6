"""How the arm looks: triangle meshes that ride on its joints' frames.

The capsules (:mod:`armanim.arm.capsules`) are what every clearance is measured on; these
meshes are only drawn. Each link's triangles are given in the link's own frame
(:class:`LinkMesh`, as a URDF's ``<visual>`` places them) and then placed once on the frame
of the moving joint that carries the link (:func:`placed_meshes`, with the same carriers and
offsets as the capsules), so a pose's world vertices are one rotation and one shift per
carrier (:func:`mesh_vertices`). Pure core: numpy only, scene units.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from armanim.arm.kinematics import Pose


@dataclass(frozen=True)
class LinkMesh:
    """One link's triangles in the link's own frame.

    Attributes
    ----------
    link : str
        The link's name (as the URDF writes it).
    vertices : (V, 3) float array
        Scene units, the link's frame.
    faces : (T, 3) int array
        Indices into ``vertices``, counter-clockwise seen from outside.
    colors : (T, 3) float array
        Each triangle's RGB colour, 0 to 1.
    """

    link: str
    vertices: np.ndarray
    faces: np.ndarray
    colors: np.ndarray

    @property
    def triangles(self) -> int:
        """Number of triangles."""
        return len(self.faces)


@dataclass(frozen=True)
class ArmMeshes:
    """Every drawn link's triangles, each vertex on the frame that carries it.

    Attributes
    ----------
    vertices : (V, 3) float array
        In the carrier's frame (the world for carrier -1: links that never move).
    carrier : (V,) int array
        The moving joint whose frame carries each vertex (its index in the arm), or -1.
    faces : (T, 3) int array
        Indices into ``vertices``.
    colors : (T, 3) float array
        RGB, 0 to 1.
    part : (T,) int array
        Each triangle's link, an index into ``links``.
    links : tuple of str
        The drawn links, in order.
    """

    vertices: np.ndarray
    carrier: np.ndarray
    faces: np.ndarray
    colors: np.ndarray
    part: np.ndarray
    links: tuple[str, ...]

    @property
    def triangles(self) -> int:
        """Number of triangles."""
        return len(self.faces)


LinkPlaces = dict[str, tuple[int, np.ndarray]]
"""Where each link of a robot sits on its arm: link name -> (carrier, (4, 4) the link's frame in
the carrier joint's frame, or in the world for carrier -1). Made once with the problem's arm
(:func:`armanim.scene.convert.link_places`); the robot's meshes are placed by it."""


def placed_meshes(meshes: list[LinkMesh], carriers: list[int], offsets: list[np.ndarray]) -> ArmMeshes:
    """The links' triangles placed on their carriers: ``meshes[i]`` moved by ``offsets[i]``
    (4, 4), its link's frame in the frame of joint ``carriers[i]`` (or in the world for -1).

    >>> square = LinkMesh("a", np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]]), np.array([[0, 1, 2]]), np.ones((1, 3)))
    >>> up = np.eye(4); up[2, 3] = 2.0
    >>> placed = placed_meshes([square], [0], [up])
    >>> placed.vertices[:, 2].tolist(), placed.carrier.tolist(), placed.links
    ([2.0, 2.0, 2.0], [0, 0, 0], ('a',))
    """
    vertices, carrier, faces, colors, part = [], [], [], [], []
    start = 0
    for i, (mesh, joint, offset) in enumerate(zip(meshes, carriers, offsets)):
        vertices.append(mesh.vertices @ offset[:3, :3].T + offset[:3, 3])
        carrier.append(np.full(len(mesh.vertices), joint, dtype=int))
        faces.append(np.asarray(mesh.faces, dtype=int) + start)
        colors.append(mesh.colors)
        part.append(np.full(len(mesh.faces), i, dtype=int))
        start += len(mesh.vertices)
    if not meshes:
        return ArmMeshes(
            np.zeros((0, 3)),
            np.zeros(0, dtype=int),
            np.zeros((0, 3), dtype=int),
            np.zeros((0, 3)),
            np.zeros(0, dtype=int),
            (),
        )
    return ArmMeshes(
        np.concatenate(vertices),
        np.concatenate(carrier),
        np.concatenate(faces),
        np.concatenate(colors),
        np.concatenate(part),
        tuple(m.link for m in meshes),
    )


def mesh_vertices(meshes: ArmMeshes, pose: Pose) -> np.ndarray:
    """(..., V, 3) the world position of every vertex at ``pose`` (one pose or a batch): x_world
    = p_k + R_k x for a vertex carried by joint k, as a capsule's ends are placed.

    >>> from armanim.arm.kinematics import Arm, forward
    >>> arm = Arm.from_names([1.0, 1.0], axes=["z", "z"], direction="x")
    >>> dot = LinkMesh("b", np.array([[0.5, 0.0, 0.0]]), np.zeros((0, 3), dtype=int), np.zeros((0, 3)))
    >>> placed = placed_meshes([dot], [1], [np.eye(4)])
    >>> mesh_vertices(placed, forward(arm, np.radians([90.0, 0.0]))).round(6).tolist()
    [[0.0, 1.5, 0.0]]
    """
    moving = meshes.carrier >= 0
    batch = pose.points.shape[:-2]
    out = np.broadcast_to(meshes.vertices, batch + meshes.vertices.shape).copy()
    if np.any(moving):
        k = meshes.carrier[moving]
        origin = pose.points[..., k, :]
        frames = pose.frames[..., k, :, :]
        out[..., moving, :] = origin + np.einsum("...vab,vb->...va", frames, meshes.vertices[moving])
    return out


__all__ = ["ArmMeshes", "LinkMesh", "LinkPlaces", "mesh_vertices", "placed_meshes"]
