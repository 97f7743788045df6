"""The robot as it looks: each link's visual mesh as one part of the painter's order.

Each link's triangles are placed by the pose (as :func:`armanim.arm.visuals.mesh_vertices` places
them), projected, the ones facing away dropped, shaded per vertex (one light plus ambient, as the
capsules are; these three in one compiled pass, :func:`~armanim.render.solids.rasterloops.seen_vertices`) and drawn into a sprite by the z-buffer rasteriser
(:mod:`armanim.render.solids.raster`): within a link the nearest surface wins each pixel; between
links, obstacles and the arm's other parts the painter's order decides, as it does for the
capsules, from a segment and a radius that bound the link (computed once from its vertices).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from armanim.arm.kinematics import Pose
from armanim.arm.visuals import ArmMeshes
from armanim.motion.problem import Problem
from armanim.render.camera.view import AMBIENT, DIFFUSE, LIGHT, View, lambert
from armanim.render.paint.style import GHOST_FADE, SELF_NEAR_COLOR
from armanim.render.solids.arm import ArmSolids, Part, segment_samples
from armanim.render.solids.raster import StillLayer, draw_outline, draw_triangles

NEAR_TINT = 0.4
FURNITURE = "furniture"
"""The link name of the scene's furniture (:func:`armanim.scene.looks.furniture_meshes`): what a
path's ink is drawn on (:meth:`RobotMeshes.parts`' ``decal``)."""
GHOST_OUTLINE = (0.52, 0.58, 0.70)
"""The outline a poster draws of the robot on each goal."""
"""How far a link in a close pair of the arm's own links is tinted toward the warning colour."""


class RobotMeshes:
    """The robot's links as the camera sees them, pose by pose.

    Parameters
    ----------
    meshes : ArmMeshes
    capsule_links : (c,) int array
        The link (index into ``meshes.links``) of each of the arm's capsules, -1 for none: a
        link is tinted when one of its capsules is in a close pair.
    view : View
    ppu : float
        Pixels per world unit.
    size : (int, int)
        The frame's width and height in pixels.
    """

    def __init__(self, meshes: ArmMeshes, capsule_links: np.ndarray, view: View, ppu: float, size: tuple[int, int]):
        self.meshes, self.view, self.ppu, self.size = meshes, view, ppu, size
        self.capsule_links = capsule_links
        self.link_faces = [np.flatnonzero(meshes.part == k) for k in range(len(meshes.links))]
        self.link_triangles = [meshes.faces[f] for f in self.link_faces]
        """Each link's triangles (k, 3), vertex indices: the same every frame."""
        self.link_carriers = np.array([int(meshes.carrier[t[0, 0]]) if len(t) else -1 for t in self.link_triangles])
        """(L,) the joint that carries each link (-1: none, the world)."""
        self.normals = vertex_normals(meshes)
        self.normal_map = np.linalg.inv(view.linear)
        """(3, 3) world normals (row vectors) to the screen's, before their length is one
        (:meth:`~armanim.render.camera.view.View.screen_normals`)."""
        vertex_color = np.zeros((len(meshes.vertices), 3))
        vertex_color[meshes.faces.ravel()] = np.repeat(meshes.colors, 3, axis=0)
        self.vertex_color = lifted(vertex_color)
        self.bounds = [bounding_segment(meshes.vertices[np.unique(meshes.faces[f])]) for f in self.link_faces]
        self.bound_ends = np.array([[start, end] for start, end, _ in self.bounds]).reshape(-1, 2, 3)
        """(L, 2, 3) each link's bounding segment's ends in its carrier's frame."""
        self.furniture = meshes.links.index(FURNITURE) if FURNITURE in meshes.links else None
        """The furniture's link (None: the scene has none): a ``decal`` is drawn with it."""
        self.still = self._still_furniture()
        """The furniture's triangles filled once (:class:`~armanim.render.solids.raster.StillLayer`):
        it never moves, so every frame lays the same samples (None: no furniture)."""

    def _still_furniture(self) -> StillLayer | None:
        """The furniture as the camera sees it, lit and filled once (it is carried by no joint)."""
        if self.furniture is None:
            return None
        tri = self.meshes.faces[self.link_faces[self.furniture]]
        if len(tri) and np.any(self.meshes.carrier[tri] >= 0):  # (never: furniture stands in the world)
            return None
        screen = self.view.project(self.meshes.vertices)  # the furniture's vertices are where they stand
        rgb = lambert(self.view.screen_normals(self.normals), np.ones(3)) * self.vertex_color
        return StillLayer(screen, tri[_signed_areas(screen, tri) > 0.0], rgb, self.size)

    def parts(
        self,
        pose: Pose,
        ghost: bool = False,
        near: np.ndarray | None = None,
        decal: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None,
    ) -> list[Part]:
        """One part per link: its sprite, and the segment and radius that order it.

        ``decal``: triangles drawn with the furniture, in its z-buffer (a path's ink on a
        whiteboard: hidden by the links in front of it, over the board behind it): screen points
        (K, 3), faces (k, 3) into them and colours (K, 3); left out without furniture."""
        screen, rgb, facing = self._seen(pose)
        if ghost:
            rgb = rgb * (1 - GHOST_FADE) + GHOST_FADE
        for k in self._tinted_links(near):
            used = self.meshes.faces[self.link_faces[k]].ravel()
            rgb[used] = rgb[used] * (1 - NEAR_TINT) + np.asarray(SELF_NEAR_COLOR) * NEAR_TINT
        extra = np.zeros((0, 3), dtype=int)
        if decal is not None and self.furniture is not None and len(decal[1]):
            extra = np.asarray(decal[1], dtype=int) + len(screen)
            screen, rgb = np.vstack([screen, decal[0]]), np.vstack([rgb, decal[2]])
        link_ends = self.view.project(_placed_ends(self.bound_ends, pose, self.link_carriers))
        parts = []
        for k, faces in enumerate(self.link_faces):
            tri = self.link_triangles[k]
            radius = self.bounds[k][2]
            ends = link_ends[k]
            still = None
            if k == self.furniture and not ghost and self.still is not None:  # filled once: only the decal is new
                front, still = extra, self.still
            else:
                front = tri[facing[faces]]
                if k == self.furniture:
                    front = np.vstack([front, extra])
            raster = (
                screen,
                front,
                rgb,
                "outline" if ghost else "fill",
                still,
            )  # a ghost: the whole pose's outline only
            parts.append(
                Part(
                    samples=segment_samples(ends[0], ends[1]),
                    radius=radius * self.ppu,
                    polygons=[],
                    colors=np.zeros((0, 4)),
                    raster=raster,
                )
            )
        return parts

    def _seen(self, pose: Pose) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The mesh at ``pose`` as the camera sees it: screen points (V, 3), each vertex's colour lit
        (V, 3; its normal turned by its carrier) and which faces face the camera (F,), in one
        compiled pass (:func:`~armanim.render.solids.rasterloops.seen_vertices`)."""
        from armanim.render.solids.rasterloops import seen_vertices  # compiled: numba is imported here

        meshes = self.meshes
        screen, rgb = np.empty((len(meshes.vertices), 3)), np.empty((len(meshes.vertices), 3))
        facing = np.empty(len(meshes.faces), dtype=bool)
        seen_vertices(
            (meshes.vertices, meshes.carrier, self.normals, self.vertex_color, meshes.faces),
            np.ascontiguousarray(pose.points, dtype=float),
            np.ascontiguousarray(pose.frames, dtype=float),
            (self.view.matrix, self.normal_map),
            (LIGHT, AMBIENT, DIFFUSE),
            screen,
            rgb,
            facing,
        )
        return screen, rgb, facing

    def _tinted_links(self, near: np.ndarray | None) -> set[int]:
        """The links with a capsule in a close pair."""
        if near is None:
            return set()
        return {int(k) for k in self.capsule_links[near] if k >= 0}


MESH_LIFT = 0.3
"""The share of white every mesh colour is lifted by before it is lit (:func:`lifted`)."""


def lifted(rgb: np.ndarray, lift: float = MESH_LIFT) -> np.ndarray:
    """Mesh colours (..., 3) in 0-1 lifted toward white by ``lift``: the light a viewer's ambient
    adds (RViz's), so that dark materials keep their shape. The UR5's vendored greys of 13-107/255
    read as a black silhouette at 960 x 540 (issue 50); a white shell barely changes.

    >>> lifted(np.array([0.0, 0.5, 1.0])).round(3).tolist()
    [0.3, 0.65, 1.0]
    """
    return lift + (1.0 - lift) * np.asarray(rgb, dtype=float)


CAPSULE_ALPHA = 0.35
"""Opacity of the capsules drawn over the meshes (``render.robot: both``)."""


class MeshesAndCapsules:
    """The robot's meshes and some of its capsules: those of links without a mesh (opaque: a
    link whose mesh could not be read is drawn as its capsules), or all of them translucent over
    the meshes (``render.robot: both``)."""

    def __init__(self, meshes: RobotMeshes, capsules: ArmSolids, shown: np.ndarray, alpha: float = 1.0):
        self.meshes, self.capsules, self.shown, self.alpha = meshes, capsules, shown, alpha

    @property
    def furniture(self) -> int | None:
        """The furniture's link among the meshes (:attr:`RobotMeshes.furniture`)."""
        return self.meshes.furniture

    @property
    def still(self) -> StillLayer | None:
        """The furniture filled once (:attr:`RobotMeshes.still`)."""
        return self.meshes.still

    def parts(
        self,
        pose: Pose,
        ghost: bool = False,
        near: np.ndarray | None = None,
        decal: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None,
    ) -> list[Part]:
        """The links' meshes (``decal`` drawn with the furniture, :meth:`RobotMeshes.parts`) and
        the ``shown`` capsules, their colours at ``alpha``; with no link meshed (the meshes are the
        scene's furniture), the arm whole: base, capsules and joints."""
        meshes = self.meshes.parts(pose, ghost, near, decal)
        if self.shown.all() and self.alpha == 1.0:
            return meshes + self.capsules.parts(pose, ghost, near)
        capsules = [
            replace(p, colors=np.column_stack([p.colors[:, :3], np.full(len(p.colors), self.alpha)]))
            for p, shown in zip(self.capsules.links(pose, ghost, near), self.shown)
            if shown
        ]
        return meshes + capsules


class RasterQueue:
    """Mesh parts that follow each other in the painter's order, drawn as one (one z-buffer: the
    links among themselves are then drawn as they occlude each other; a ghost's parts as one
    outline)."""

    def __init__(self, size: tuple[int, int]):
        self.size = size
        self.points: np.ndarray | None = None
        self.rgb: np.ndarray | None = None
        self.mode = "fill"
        self.faces: list[np.ndarray] = []
        self.still: StillLayer | None = None

    def add(self, raster: tuple, buffer: np.ndarray) -> None:
        """Queue one part's triangles (drawing the queue first if they are another pose's)."""
        points, faces, rgb, mode, still = raster
        if self.points is not None and (points is not self.points or mode != self.mode):
            self.flush(buffer)
        self.points, self.rgb, self.mode = points, rgb, mode
        self.faces.append(faces)
        self.still = still if still is not None else self.still

    def flush(self, buffer: np.ndarray) -> None:
        """Draw the queued triangles into ``buffer``: filled (with the still layer of one of them),
        or a ghost's outline."""
        if self.faces and self.points is not None and self.rgb is not None:
            faces = np.concatenate(self.faces)
            if self.mode == "outline":
                draw_outline(buffer, self.points, faces, GHOST_OUTLINE, width=2)
            else:
                draw_triangles(buffer, self.points, faces, self.rgb, still=self.still)
        self.points, self.rgb, self.faces, self.still = None, None, [], None


def arm_solids(
    problem: Problem, meshes: ArmMeshes | None, view, ppu: float, size: tuple[int, int], look: str = "mesh"
) -> ArmSolids | RobotMeshes | MeshesAndCapsules:
    """The arm as the pictures draw it (``render.robot``): its visual meshes when it has some,
    its capsules, or both; an arm without meshes is its capsules (``meshes`` may hold only the
    scene's furniture, drawn with them)."""
    capsules = ArmSolids(problem.arm, problem.capsules, problem.half_width, view, ppu)
    if meshes is None or not meshes.triangles:
        return capsules
    index = {name: k for k, name in enumerate(meshes.links)}
    capsule_links = np.array([index.get(name, -1) for name in problem.capsules.names], dtype=int)
    robot = RobotMeshes(meshes, capsule_links, view, ppu, size)
    every = np.ones(len(problem.capsules.radius), dtype=bool)
    if not robot_meshed(problem, meshes):  # the meshes are the furniture alone: the arm is drawn whole
        return MeshesAndCapsules(robot, capsules, every)
    if look == "both":
        return MeshesAndCapsules(robot, capsules, every, CAPSULE_ALPHA)
    uncovered = capsule_links < 0  # a link without a mesh (none given, or not read) is drawn as its capsules
    return MeshesAndCapsules(robot, capsules, uncovered) if uncovered.any() else robot


def robot_meshed(problem: Problem, meshes: ArmMeshes | None) -> bool:
    """Whether ``meshes`` draw some link of the arm (and not only the scene's furniture)."""
    return meshes is not None and bool(set(meshes.links) & set(problem.capsules.names))


def vertex_normals(meshes: ArmMeshes) -> np.ndarray:
    """(V, 3) unit normals, each the area-weighted mean of its faces' (in the carrier's frame)."""
    v = meshes.vertices
    a, b, c = (v[meshes.faces[:, i]] for i in range(3))
    face = np.cross(b - a, c - a)  # length: twice the area
    out = np.zeros_like(v)
    for i in range(3):
        np.add.at(out, meshes.faces[:, i], face)
    length = np.linalg.norm(out, axis=1, keepdims=True)
    return np.divide(out, length, out=np.zeros_like(out), where=length > 0)


def bounding_segment(points: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """A segment along ``points``' (k, 3) longest spread and the radius around it that holds them
    all: the link as the painter's order sees it."""
    if not len(points):
        return np.zeros(3), np.zeros(3), 0.0
    center = points.mean(axis=0)
    _, _, axes = np.linalg.svd(points - center, full_matrices=False)
    along = (points - center) @ axes[0]
    start, end = center + along.min() * axes[0], center + along.max() * axes[0]
    t = np.clip(along - along.min(), 0.0, None)[:, None] / max(float(np.ptp(along)), 1e-12)
    radius = float(np.linalg.norm(points - (start + t * (end - start)), axis=1).max())
    return start, end, radius


def _placed_ends(ends: np.ndarray, pose: Pose, carriers: np.ndarray) -> np.ndarray:
    """(L, 2, 3) each link's ``ends`` (L, 2, 3), in the frame of its joint in ``carriers`` (L,; -1:
    the world), placed at ``pose``."""
    moving = carriers >= 0
    out = ends.copy()
    k = carriers[moving]
    out[moving] = pose.points[k][:, None, :] + ends[moving] @ pose.frames[k].transpose(0, 2, 1)
    return out


def _signed_areas(screen: np.ndarray, tri: np.ndarray) -> np.ndarray:
    """(k,) twice the signed screen area of each triangle (positive: counter-clockwise, facing the camera)."""
    a, b, c = (screen[tri[:, i], :2] for i in range(3))
    return (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])


__all__ = [
    "CAPSULE_ALPHA",
    "MeshesAndCapsules",
    "RasterQueue",
    "RobotMeshes",
    "arm_solids",
    "robot_meshed",
    "bounding_segment",
    "vertex_normals",
]
