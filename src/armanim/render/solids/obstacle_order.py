"""The painter's order of a scene with boxes or capsules: obstacles among themselves and among
the arm's parts.

Spheres and the shapes' parts (:mod:`armanim.render.solids.shapes`) are ordered once, with the
background; a frame then redraws only the obstacles a moving part touches on screen, and every
obstacle drawn over those, in the same order. Boxes join the order by their depth along the
viewing rays through the other parts' samples (:meth:`ShapeSolids.box_ahead`), the rest by
their overlapping samples (:mod:`armanim.render.solids.order`). Pure numpy: nothing is drawn
here.
"""

from __future__ import annotations

import numpy as np

from armanim.render.camera.bounds import box_corners
from armanim.render.camera.view import View
from armanim.render.solids.arm import SAMPLES, Part, point_samples
from armanim.render.solids.order import order_by, overlap_ahead
from armanim.render.solids.shapes import ShapeSolids
from armanim.render.solids.spheres import SphereDiscs


class ObstacleOrder:
    """Every obstacle's screen box, its painter's order and which obstacles cover which.

    Obstacles are indexed spheres first, then the shapes' parts.

    Parameters
    ----------
    spheres : SphereDiscs
    shapes : ShapeSolids
    view : View

    Attributes
    ----------
    bbox : (S + k, 4) array
        Each obstacle's screen box (x0, y0, x1, y1).
    order : list of int
        The painter's order of all obstacles, far first (the background's).
    covers : (S + k, S + k) bool array
        ``[i, j]``: obstacle j is drawn after i and over it on screen.
    """

    def __init__(self, spheres: SphereDiscs, shapes: ShapeSolids, view: View):
        self.spheres, self.shapes, self.view = spheres, shapes, view
        self._ahead_of_corners: dict[int, np.ndarray] = {}
        c, r = spheres.centers, spheres.radii
        sphere_boxes = np.column_stack([c[:, 0] - r, c[:, 1] - r, c[:, 0] + r, c[:, 1] + r]).reshape(-1, 4)
        self.bbox = np.vstack([sphere_boxes, shapes.bbox])
        items = [point_samples(c[i]) for i in range(len(spheres))] + [p.samples for p in shapes.parts]
        radii = np.concatenate([r, [p.radius for p in shapes.parts]])
        box_of = np.concatenate([np.full(len(spheres), -1), shapes.box_of])
        order = self.paint_order(np.array(items).reshape(-1, SAMPLES, 3), radii, box_of)
        self.order = order
        rank = np.empty(len(order), dtype=int)
        rank[order] = np.arange(len(order))
        b = self.bbox
        overlap = (
            (b[:, None, 0] <= b[None, :, 2])
            & (b[None, :, 0] <= b[:, None, 2])
            & (b[:, None, 1] <= b[None, :, 3])
            & (b[None, :, 1] <= b[:, None, 3])
        )
        self.covers = overlap & (rank[None, :] > rank[:, None])  # [i, j]: j is drawn after i over it

    def paint_order(self, samples: np.ndarray, radii: np.ndarray, box_of: np.ndarray) -> list[int]:
        """Painter's order of parts (samples (N, SAMPLES, 3), radii (N,)), boxes (``box_of`` >= 0)
        put by the depth along the rays through the other parts' samples, the rest by their
        overlapping samples."""
        ahead = overlap_ahead(samples, radii)
        boxes = np.flatnonzero(box_of >= 0)
        if len(boxes):
            scores = self.shapes.box_ahead(samples)[:, box_of[boxes]]  # (N, k): part ahead of box
            ahead[:, boxes] = scores
            ahead[boxes, :] = -scores.T
            ahead[np.ix_(boxes, boxes)] = 0.0
            for bi in boxes:  # box against box: the corners of one against the other
                scores = self._corners_ahead(int(box_of[bi]))
                for bj in boxes:
                    if bi != bj:
                        ahead[bi, bj] = scores[box_of[bj]]
            ahead = 0.5 * (ahead - ahead.T)
            np.fill_diagonal(ahead, 0.0)
        return order_by(ahead, samples[..., 2].mean(axis=1))

    def _corners_ahead(self, k: int) -> np.ndarray:
        """(B,) each box's score ahead of box ``k``'s corners on the screen (:meth:`ShapeSolids.box_ahead`):
        the boxes never move, so it is computed once per box (panda-shelf's frames computed it for
        each box the arm touched, every frame)."""
        if k not in self._ahead_of_corners:
            corners = self.view.project(box_corners(*self._box(k)))
            self._ahead_of_corners[k] = self.shapes.box_ahead(corners[None])[0]
        return self._ahead_of_corners[k]

    def _box(self, k: int):
        boxes = self.shapes.boxes
        return boxes.centers[k], boxes.half[k], boxes.rotations[k]

    def touched(self, boxes: list) -> np.ndarray:
        """Obstacles whose screen boxes meet any of ``boxes`` (each (4,) or None), and every one
        drawn over those; in their painter's order."""
        b = self.bbox
        hit = np.zeros(len(b), dtype=bool)
        for box in boxes:
            if box is not None:
                hit |= (b[:, 2] >= box[0]) & (b[:, 0] <= box[2]) & (b[:, 3] >= box[1]) & (b[:, 1] <= box[3])
        while True:
            more = self.covers[hit].any(axis=0) & ~hit
            if not more.any():
                break
            hit |= more
        return np.array([i for i in self.order if hit[i]], dtype=int)

    def item(self, i: int) -> Part:
        """Obstacle ``i`` as a part: a sphere (drawn by its sprite) or a shape's part."""
        spheres = len(self.spheres)
        if i < spheres:
            return Part(point_samples(self.spheres.centers[i]), float(self.spheres.radii[i]), [], np.zeros((0, 4)))
        return self.shapes.parts[i - spheres]
