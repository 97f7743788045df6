"""The arm's solid parts, ready for the painter's order: capsule prisms, joint discs, the base.

Each part is summarised for :func:`armanim.render.solids.order.paint_order` as screen samples
along its axis and a pixel radius, and carries the flat-shaded polygons that draw it.
Capsule prisms are culled (back faces dropped) for every pose; the base pedestal (and the
column up to joint 1 of a robot whose first joint sits above its base) never moves, so it
is projected and culled once.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from armanim.arm.capsules import Capsules, capsule_ends, carrier_frames
from armanim.arm.kinematics import Arm, Pose
from armanim.render.camera.view import LIGHT, View, lambert
from armanim.render.paint.style import (
    ARM_COLOR,
    BASE_COLOR,
    BASE_SCALE,
    CIRCLE_SIDES,
    GHOST_FADE,
    JOINT_COLOR,
    JOINT_HIGHLIGHT,
    JOINT_SCALE,
    PRISM_SIDES,
    SELF_NEAR_COLOR,
    with_alpha,
)
from armanim.render.solids.mesh import (
    prism_face_normals,
    prism_faces,
    prism_local,
    prism_vertices,
    prism_world,
    unit_circle,
)

SAMPLES = 7  # points per part for the painter's order


@dataclass(frozen=True)
class Part:
    """One solid as the painter's order sees it.

    Attributes
    ----------
    samples : (SAMPLES, 3) array
        Screen points (x px, y px, near) along the part's axis.
    radius : float
        Pixels around the samples that the part covers.
    polygons : list of (k, 2) arrays
        Pixel polygons that draw it, in drawing order.
    colors : (len(polygons), 4) array
        RGBA of each polygon.
    raster : (points, faces, rgb, mode, still) or None
        Triangles drawn by the rasteriser instead of polygons (a robot link's mesh): screen
        points (V, 3), the part's faces (k, 3) into them, per-vertex colours (V, 3),
        ``"fill"``, or ``"outline"`` (a ghost: the outline of the pose alone), and triangles
        filled once that are drawn with them (a :class:`~armanim.render.solids.raster.StillLayer`:
        the furniture) or None; parts that follow each other in the painter's order and share
        ``points`` are drawn as one.
    """

    samples: np.ndarray
    radius: float
    polygons: list
    colors: np.ndarray
    raster: tuple | None = None


_ALONG = np.linspace(0.0, 1.0, SAMPLES)[:, None]  # (SAMPLES, 1): made once, a part a frame used to make it


def segment_samples(start: np.ndarray, end: np.ndarray) -> np.ndarray:
    """(SAMPLES, 3) points evenly from ``start`` to ``end``, both included."""
    return start + _ALONG * (end - start)


def point_samples(point: np.ndarray) -> np.ndarray:
    """(SAMPLES, 3): ``point`` repeated, the samples of a round part."""
    return np.repeat(point[None, :], SAMPLES, axis=0)


def solid_colors(rgb: np.ndarray, ghost: bool) -> np.ndarray:
    """(k, 3) shades -> (k, 4) opaque RGBA; a ghost's (a poster's faint pose) faded toward white."""
    if ghost:
        rgb = rgb * (1 - GHOST_FADE) + GHOST_FADE
    return with_alpha(rgb, 1.0)


def pedestal(base: np.ndarray, half_width: float, view: View, ppu: float) -> Part:
    """The base under joint 1: a short vertical cylinder, projected and culled once."""
    radius, height = BASE_SCALE * half_width, 2.0 * half_width
    theta = np.linspace(0, 2 * np.pi, CIRCLE_SIDES, endpoint=False)
    ring = radius * np.column_stack([np.cos(theta), np.sin(theta), np.zeros_like(theta)])
    upper, lower = base + ring, base + ring - [0, 0, height]
    sides = len(theta)
    polys = [np.array([lower[i], lower[(i + 1) % sides], upper[(i + 1) % sides], upper[i]]) for i in range(sides)]
    normals = [[np.cos(t + np.pi / sides), np.sin(t + np.pi / sides), 0.0] for t in theta]
    polys += [upper, lower[::-1]]
    normals += [[0, 0, 1.0], [0, 0, -1.0]]
    screen_n = view.screen_normals(np.array(normals))
    front = screen_n[:, 2] > 0
    ends = view.project(np.array([base - [0, 0, height], base]))
    return Part(
        samples=segment_samples(ends[0], ends[1]),
        radius=radius * ppu,
        polygons=[view.project(p)[:, :2] for p, f in zip(polys, front) if f],
        colors=with_alpha(lambert(screen_n[front], BASE_COLOR), 1.0),
    )


def column(arm: Arm, radius: float, view: View, ppu: float) -> list[Part]:
    """The fixed column from where the robot stands up to joint 1 (none for an arm of links),
    projected and culled once."""
    start, end = arm.stand[None, :], arm.base[None, :]
    if not np.linalg.norm(end - start) > 0:
        return []
    verts = view.project(prism_vertices(start, end, np.array([radius]), PRISM_SIDES)[0])
    normals = view.screen_normals(prism_face_normals(start, end, PRISM_SIDES)[0])
    front = np.flatnonzero(normals[:, 2] > 1e-9)
    faces = prism_faces(PRISM_SIDES)
    ends = view.project(np.vstack([start, end]))
    return [
        Part(
            samples=segment_samples(ends[0], ends[1]),
            radius=radius * ppu,
            polygons=[verts[faces[f], :2] for f in front],
            colors=with_alpha(lambert(normals[front], BASE_COLOR), 1.0),
        )
    ]


class ArmSolids:
    """The arm's parts in screen space, pose by pose.

    Parameters
    ----------
    arm : Arm
    capsules : Capsules
        The solids drawn: the arm's collision capsules.
    half_width : float
        Half the arm's drawn thickness (joint discs and the base), world units.
    view : View
        The camera.
    ppu : float
        Pixels per world unit.
    """

    def __init__(self, arm: Arm, capsules: Capsules, half_width: float, view: View, ppu: float):
        self.view = view
        self.capsules = capsules
        self.prism_local = prism_local(capsules, PRISM_SIDES)
        self.faces = prism_faces(PRISM_SIDES)
        self.face_normals_local = prism_face_normals(capsules.start, capsules.end, PRISM_SIDES)
        self.link_radius = capsules.radius * ppu
        self.joint_radius = JOINT_SCALE * half_width * ppu
        self.circle = unit_circle(CIRCLE_SIDES)
        first = capsules.radius[capsules.link == 0]
        self.base = [pedestal(arm.stand, half_width, view, ppu)]
        self.base += column(arm, float(first.max()) if len(first) else half_width, view, ppu)

    def parts(self, pose: Pose, ghost: bool = False, near: np.ndarray | None = None) -> list[Part]:
        """The base, every capsule and every joint of ``pose``; a ghost (a poster's faint pose)
        has no base and its colours faded toward white; the capsules ``near`` marks ((c,) bool:
        a pair of the arm's own links close together) are tinted."""
        joints = self.view.project(pose.points)  # (n+1, 3)
        base = [] if ghost else list(self.base)
        return base + self.links(pose, ghost, near) + self._joints(joints[:-1], ghost)

    def links(self, pose: Pose, ghost: bool = False, near: np.ndarray | None = None) -> list[Part]:
        """One prism per capsule, its back faces culled."""
        rotations, origins = carrier_frames(self.capsules, pose)  # the base's capsules: in the world
        verts = self.view.project(prism_world(rotations, origins, self.prism_local))  # (c, V, 3)
        normals = self.view.screen_normals(np.einsum("cab,cfb->cfa", rotations, self.face_normals_local))
        a, b = (self.view.project(end) for end in capsule_ends(self.capsules, pose))
        parts = []
        for i in range(len(verts)):
            front = np.flatnonzero(normals[i, :, 2] > 1e-9)
            parts.append(
                Part(
                    samples=segment_samples(a[i], b[i]),
                    radius=float(self.link_radius[i]),
                    polygons=[verts[i, self.faces[f], :2] for f in front],
                    colors=solid_colors(
                        lambert(normals[i, front], SELF_NEAR_COLOR if near is not None and near[i] else ARM_COLOR),
                        ghost,
                    ),
                )
            )
        return parts

    def _joints(self, centers: np.ndarray, ghost: bool) -> list[Part]:
        """One dark disc with a lighter glint per joint (screen centres (n, 3))."""
        r = self.joint_radius
        shade = solid_colors(np.array([JOINT_COLOR, JOINT_HIGHLIGHT]), ghost)
        parts = []
        for center in centers:
            disc = center[:2] + r * self.circle
            glint = center[:2] + 0.45 * r * self.circle + 0.25 * r * LIGHT[:2]
            parts.append(Part(samples=point_samples(center), radius=r, polygons=[disc, glint], colors=shade))
        return parts


NEAR_FACTOR = 2.0
"""A pair of the arm's own links is tinted within this many ``self_clearance`` (as the cost's field reaches)."""


def near_capsules(problem, pose: Pose) -> np.ndarray | None:
    """(c,) bool: the capsules in an enabled pair of the arm's own links closer than
    :data:`NEAR_FACTOR` x ``self_clearance`` at ``pose`` (one pose); None without enabled pairs."""
    pairs = problem.self_pairs
    if not len(pairs):
        return None
    from armanim.world.selfdistances import self_gaps

    close = self_gaps(pose, problem.capsules, pairs).d < NEAR_FACTOR * pairs.clearance
    near = np.zeros(len(problem.capsules), dtype=bool)
    near[pairs.first[close]] = True
    near[pairs.second[close]] = True
    return near
