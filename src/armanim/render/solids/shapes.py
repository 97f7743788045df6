"""The obstacle boxes, capsules and cylinders on screen: shaded solids, what they hide, their shells and shadows.

A box is drawn as its front faces (a convex solid's front faces never overlap each other),
flat-shaded in the obstacle colour; a capsule like a link (a prism and two end discs) in
the obstacle colour; a cylinder as the front faces of a prism of :data:`CIRCLE_SIDES` sides
with its two caps (a convex solid too). They never move: their polygons are projected once. The painter's
order puts a box against another part by the depth of that part's samples against the box
along the viewing rays through them (:meth:`ShapeSolids.box_ahead`): the camera is
orthographic, so a box is a parallelepiped in screen space too and the ray's entry and exit
depths are slab intervals in the box's own frame.
"""

from __future__ import annotations

import numpy as np

from armanim.render.camera.bounds import box_corners, shape_extent
from armanim.render.camera.view import LIGHT, View, lambert
from armanim.render.paint.style import CIRCLE_SIDES, JOINT_HIGHLIGHT, OBSTACLE_COLOR, PRISM_SIDES, with_alpha
from armanim.render.solids.arm import Part, point_samples, segment_samples
from armanim.render.solids.mesh import prism_face_normals, prism_faces, prism_vertices, unit_circle
from armanim.world.obstacles import BOX, CYLINDER, ROD, Cylinders

BOX_FACES = np.array([[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]])
"""Corner indices of the six faces (corner j at signs (-1)^bits of j: x bit 2, y bit 1, z bit 0)."""
BOX_NORMALS = np.array([[-1.0, 0, 0], [1, 0, 0], [0, -1, 0], [0, 1, 0], [0, 0, -1], [0, 0, 1]])
"""The faces' outward normals in the box's frame."""


def convex_hull(points: np.ndarray) -> np.ndarray:
    """(k, 2) corners of the convex hull of (P, 2) points, counter-clockwise (Andrew's monotone chain).

    >>> convex_hull(np.array([[0.0, 0], [1, 0], [1, 1], [0, 1], [0.5, 0.5]])).tolist()
    [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
    """
    pts = sorted({(float(x), float(y)) for x, y in points})
    if len(pts) <= 2:
        return np.array(pts)

    def half(chain):
        out: list = []
        for p in chain:
            while (
                len(out) >= 2
                and (out[-1][0] - out[-2][0]) * (p[1] - out[-2][1]) - (out[-1][1] - out[-2][1]) * (p[0] - out[-2][0])
                <= 0
            ):
                out.pop()
            out.append(p)
        return out[:-1]

    return np.array(half(pts) + half(pts[::-1]))


def stadium(a: np.ndarray, b: np.ndarray, radius: float, sides: int = CIRCLE_SIDES) -> np.ndarray:
    """(k, 2) outline of every point within ``radius`` of the 2-D segment a-b."""
    circle = radius * unit_circle(sides)
    return convex_hull(np.vstack([a[:2] + circle, b[:2] + circle]))


class ShapeSolids:
    """The boxes, capsule obstacles and cylinders as one camera sees them.

    Parameters
    ----------
    obstacles : Obstacles
    view : View
    ppu : float
        Pixels per world unit.

    Attributes
    ----------
    parts : list of Part
        One per box (its front faces), then per capsule a prism and its two end discs, then
        one per cylinder (its front faces).
    box_of : (k,) int array
        For each part, the box it draws (-1: a capsule's or a cylinder's part).
    bbox : (k, 4) array
        Each part's screen box (x0, y0, x1, y1).
    """

    def __init__(self, obstacles, view: View, ppu: float):
        self.view, self.ppu = view, ppu
        boxes, rods = obstacles.boxes, obstacles.rods
        influence = obstacles.influence
        self.box_influence = influence[obstacles.columns(BOX)]
        self.rod_influence = influence[obstacles.columns(ROD)]
        self.cylinder_influence = influence[obstacles.columns(CYLINDER)]
        self.boxes, self.rods, self.cylinders = boxes, rods, obstacles.cylinders
        parts, box_of = [], []
        for k in range(len(boxes)):
            parts.append(self._box_part(boxes.centers[k], boxes.half[k], boxes.rotations[k]))
            box_of.append(k)
        for k in range(len(rods)):
            parts += self._rod_parts(rods.start[k], rods.end[k], float(rods.radius[k]))
            box_of += [-1, -1, -1]
        bottoms, tops = self.cylinders.ends()
        for k in range(len(self.cylinders)):
            parts.append(self._cylinder_part(bottoms[k], tops[k], float(self.cylinders.radius[k])))
            box_of.append(-1)
        self.parts, self.box_of = parts, np.array(box_of, dtype=int)
        self.bbox = np.array([_part_box(p) for p in parts]).reshape(-1, 4)
        # screen -> box frame: local = K (screen - centre on screen), one K per box
        linear = view.linear
        self.to_box = np.array([np.linalg.inv(linear @ r) for r in boxes.rotations]).reshape(-1, 3, 3)
        self.box_screen = view.project(boxes.centers) if len(boxes) else np.zeros((0, 3))
        self.rod_screen = (view.project(rods.start), view.project(rods.end)) if len(rods) else (np.zeros((0, 3)),) * 2
        self.cylinder_screen = (view.project(bottoms), view.project(tops)) if len(bottoms) else (np.zeros((0, 3)),) * 2

    def __len__(self) -> int:
        return len(self.parts)

    def _box_part(self, center, half, rotation) -> Part:
        corners = self.view.project(box_corners(center, half, rotation))
        normals = self.view.screen_normals(BOX_NORMALS @ rotation.T)
        front = np.flatnonzero(normals[:, 2] > 1e-9)
        c = self.view.project(center)
        return Part(
            samples=point_samples(c),
            radius=0.0,
            polygons=[corners[BOX_FACES[f], :2] for f in front],
            colors=with_alpha(lambert(normals[front], OBSTACLE_COLOR), 1.0),
        )

    def _rod_parts(self, start, end, radius) -> list[Part]:
        a, b = start[None], end[None]
        if not np.linalg.norm(end - start) > 0:
            b = start[None] + [0.0, 0.0, 1e-9 * max(radius, 1.0)]
        verts = self.view.project(prism_vertices(a, b, np.array([radius]), PRISM_SIDES)[0])
        normals = self.view.screen_normals(prism_face_normals(a, b, PRISM_SIDES)[0])
        front = np.flatnonzero(normals[:, 2] > 1e-9)
        faces = prism_faces(PRISM_SIDES)
        ends = self.view.project(np.vstack([start, end]))
        r = radius * self.ppu
        prism = Part(
            samples=segment_samples(ends[0], ends[1]),
            radius=r,
            polygons=[verts[faces[f], :2] for f in front],
            colors=with_alpha(lambert(normals[front], OBSTACLE_COLOR), 1.0),
        )
        circle = unit_circle(CIRCLE_SIDES)
        shade = with_alpha(
            np.array(
                [lambert(np.array([0.0, 0, 1]), OBSTACLE_COLOR), 0.5 * (np.array(OBSTACLE_COLOR) + JOINT_HIGHLIGHT)]
            ),
            1.0,
        )
        discs = [
            Part(
                samples=point_samples(e),
                radius=r,
                polygons=[e[:2] + r * circle, e[:2] + 0.45 * r * circle + 0.25 * r * LIGHT[:2]],
                colors=shade,
            )
            for e in ends
        ]
        return [prism, *discs]

    def _cylinder_part(self, bottom, top, radius) -> Part:
        """A cylinder as the front faces of a prism of CIRCLE_SIDES sides (its caps among them)."""
        a, b = bottom[None], top[None]
        verts = self.view.project(prism_vertices(a, b, np.array([radius]), CIRCLE_SIDES)[0])
        normals = self.view.screen_normals(prism_face_normals(a, b, CIRCLE_SIDES)[0])
        front = np.flatnonzero(normals[:, 2] > 1e-9)
        faces = prism_faces(CIRCLE_SIDES)
        ends = self.view.project(np.vstack([bottom, top]))
        return Part(
            samples=segment_samples(ends[0], ends[1]),
            radius=radius * self.ppu,
            polygons=[verts[faces[f], :2] for f in front],
            colors=with_alpha(lambert(normals[front], OBSTACLE_COLOR), 1.0),
        )

    # ----- depth --------------------------------------------------------------------------

    def box_intervals(self, screen: np.ndarray) -> np.ndarray:
        """(P, b, 2) nearness where the viewing ray through each screen point (P, 3) enters
        and leaves each box (near side last); NaN where the ray misses the box."""
        if not len(self.boxes):
            return np.zeros((len(screen), 0, 2))
        offset = screen[:, None, :2] - self.box_screen[None, :, :2]  # (P, b, 2)
        base = np.einsum("bij,pbj->pbi", self.to_box[:, :, :2], offset)  # local at the centre's depth
        rate = self.to_box[:, :, 2][None]  # d local / d near
        half = self.boxes.half[None]
        safe = np.where(rate != 0, rate, 1.0)
        one, two = (-half - base) / safe, (half - base) / safe
        lo = np.where(rate != 0, np.minimum(one, two), np.where(np.abs(base) <= half, -np.inf, np.inf)).max(axis=-1)
        hi = np.where(rate != 0, np.maximum(one, two), np.where(np.abs(base) <= half, np.inf, -np.inf)).min(axis=-1)
        hit = lo <= hi
        depth = self.box_screen[None, :, 2]
        return np.where(hit[..., None], np.stack([lo + depth, hi + depth], axis=-1), np.nan)

    def box_ahead(self, samples: np.ndarray) -> np.ndarray:
        """(N, b): how far each part's samples (N, S, 3) lie in front of each box along the rays
        through them (negative: behind), summed over the samples the box covers; 0 if none."""
        if not len(self.boxes):
            return np.zeros((len(samples), 0))
        n, s = samples.shape[:2]
        spans = self.box_intervals(samples.reshape(-1, 3)).reshape(n, s, -1, 2)
        near = samples[..., 2][..., None]
        score = np.where(
            near > spans[..., 1], near - spans[..., 1], np.where(near < spans[..., 0], near - spans[..., 0], 0.0)
        )
        return np.where(np.isnan(spans[..., 0]), 0.0, score).sum(axis=1)

    def behind(self, screen: np.ndarray) -> np.ndarray:
        """(P,) bool: screen points (P, 3) hidden by a box, a capsule obstacle or a cylinder."""
        hidden = np.zeros(len(screen), dtype=bool)
        spans = self.box_intervals(screen)
        hidden |= np.any(screen[:, None, 2] < np.nan_to_num(spans[..., 1], nan=-np.inf), axis=1)
        return hidden | self._rod_cover(screen, nearer=False)

    def in_front(self, screen: np.ndarray) -> np.ndarray:
        """(P,) bool: screen points (P, 3) over a box, a capsule or a cylinder and nearer than it."""
        spans = self.box_intervals(screen)
        front = np.any(screen[:, None, 2] > np.nan_to_num(spans[..., 1], nan=np.inf), axis=1)
        return front | self._rod_cover(screen, nearer=True)

    def _rod_cover(self, screen: np.ndarray, nearer: bool) -> np.ndarray:
        """(P,) bool: points on a capsule's screen outline (a cylinder's: within its radius of its
        axis on screen, which holds its outline), nearer (or farther) than its axis there."""
        a, b = (np.vstack([r, c]) for r, c in zip(self.rod_screen, self.cylinder_screen))
        if not len(a):
            return np.zeros(len(screen), dtype=bool)
        radius = np.concatenate([self.rods.radius, self.cylinders.radius])
        ab = (b - a)[None]
        denom = np.maximum((ab[..., :2] ** 2).sum(-1), 1e-12)
        t = np.clip(((screen[:, None, :2] - a[None, :, :2]) * ab[..., :2]).sum(-1) / denom, 0.0, 1.0)
        axis = a[None] + t[..., None] * ab
        on = np.linalg.norm(screen[:, None, :2] - axis[..., :2], axis=-1) < radius[None] * self.ppu
        side = screen[:, None, 2] > axis[..., 2] if nearer else screen[:, None, 2] <= axis[..., 2]
        return np.any(on & side, axis=1)

    # ----- once -----------------------------------------------------------------------------

    def shells(self) -> list[np.ndarray]:
        """Influence outlines ((k, 2) pixel polygons): each box grown by its influence, each capsule's outline at radius + influence,
        each cylinder's grown by its influence (radius and half length)."""
        out = []
        for k in range(len(self.boxes)):
            if self.box_influence[k] > 0:
                grown = box_corners(
                    self.boxes.centers[k], self.boxes.half[k] + self.box_influence[k], self.boxes.rotations[k]
                )
                out.append(convex_hull(self.view.project(grown)[:, :2]))
        a, b = self.rod_screen
        for k in range(len(self.rods)):
            if self.rod_influence[k] > 0:
                out.append(stadium(a[k], b[k], (self.rods.radius[k] + self.rod_influence[k]) * self.ppu))
        for k in range(len(self.cylinders)):
            if self.cylinder_influence[k] > 0:
                out.append(
                    convex_hull(self.view.project(cylinder_rings(self.cylinders, k, self.cylinder_influence[k]))[:, :2])
                )
        return out

    def floor_shadows(self, z: float) -> list[np.ndarray]:
        """World polygons (k, 3) on the floor under every box, capsule and cylinder (light overhead)."""
        out = []
        for k in range(len(self.boxes)):
            hull = convex_hull(box_corners(self.boxes.centers[k], self.boxes.half[k], self.boxes.rotations[k])[:, :2])
            out.append(np.column_stack([hull, np.full(len(hull), z)]))
        for k in range(len(self.rods)):
            hull = stadium(self.rods.start[k], self.rods.end[k], float(self.rods.radius[k]))
            out.append(np.column_stack([hull, np.full(len(hull), z)]))
        for k in range(len(self.cylinders)):
            hull = convex_hull(cylinder_rings(self.cylinders, k)[:, :2])
            out.append(np.column_stack([hull, np.full(len(hull), z)]))
        return out

    def extent(self) -> tuple[np.ndarray, np.ndarray]:
        """World points (P, 3) and radii (P,) that hold every box, capsule and cylinder."""
        return shape_extent(self.boxes, self.rods, self.cylinders)


def cylinder_rings(cylinders: Cylinders, k: int, grow: float = 0.0, sides: int = CIRCLE_SIDES) -> np.ndarray:
    """(2 sides, 3) world points on the rims of cylinder ``k`` grown by ``grow`` (radius and half
    length): their convex hull is the (grown) cylinder's polygon.

    >>> rings = cylinder_rings(Cylinders(np.zeros((1, 3)), np.eye(3)[None], np.ones(1), np.full(1, 2.0)), 0, sides=4)
    >>> rings[:, 2].tolist(), float(np.abs(rings[:, :2]).max())
    ([-1.0, -1.0, -1.0, -1.0, 1.0, 1.0, 1.0, 1.0], 2.0)
    """
    rotation = cylinders.rotations[k]
    circle = (cylinders.radius[k] + grow) * unit_circle(sides)
    ring = circle[:, :1] * rotation[:, 0] + circle[:, 1:] * rotation[:, 1]
    along = (cylinders.half_length[k] + grow) * rotation[:, 2]
    return np.vstack([cylinders.centers[k] - along + ring, cylinders.centers[k] + along + ring])


def _part_box(part: Part) -> np.ndarray:
    pts = np.vstack([p for p in part.polygons] + [part.samples[:, :2]])
    return np.concatenate([pts.min(axis=0), pts.max(axis=0)])
