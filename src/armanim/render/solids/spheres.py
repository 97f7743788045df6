"""The obstacle spheres on screen: exact discs, shaded once, and what overlaps them.

The camera is orthographic, so a sphere is an exact disc. Each disc is shaded per
pixel once into a sprite (Lambert plus a highlight) and composited wherever the
painter's order puts it: all of them into the background, far first, and each frame
again only those that a moving part overlaps on screen.
"""

from __future__ import annotations

import numpy as np

from armanim.render.camera.view import LIGHT, View
from armanim.render.paint.pixels import Sprite, composite
from armanim.render.paint.style import CIRCLE_SIDES, OBSTACLE_COLOR
from armanim.render.solids.mesh import unit_circle
from armanim.world.obstacles import SPHERE


def sphere_sprite(center: np.ndarray, radius: float, size: tuple[int, int]) -> Sprite | None:
    """A sphere's disc shaded per pixel, as a sprite of a ``size`` (width, height) frame.

    Parameters
    ----------
    center : (3,) array
        Screen point (x px, y px, near) of the centre.
    radius : float
        Pixels.
    size : (int, int)
        The frame's width and height.

    Returns
    -------
    Sprite or None
        None if the disc is outside the frame.
    """
    width, height = size
    x0 = max(int(np.floor(center[0] - radius - 1)), 0)
    x1 = min(int(np.ceil(center[0] + radius + 1)), width)
    y0 = max(int(np.floor(center[1] - radius - 1)), 0)
    y1 = min(int(np.ceil(center[1] + radius + 1)), height)
    if x1 <= x0 or y1 <= y0 or radius <= 0:
        return None
    ys = np.arange(y1 - 1, y0 - 1, -1) + 0.5  # buffer rows run top to bottom
    xs = np.arange(x0, x1) + 0.5
    dx, dy = np.meshgrid((xs - center[0]) / radius, (ys - center[1]) / radius)
    r2 = dx**2 + dy**2
    dz = np.sqrt(np.clip(1.0 - r2, 0.0, None))
    normal = np.stack([dx, dy, dz], axis=-1)
    diffuse = np.clip(normal @ LIGHT, 0.0, 1.0)
    half = LIGHT + np.array([0.0, 0.0, 1.0])
    spec = np.clip(normal @ (half / np.linalg.norm(half)), 0.0, 1.0) ** 40
    rgb = np.asarray(OBSTACLE_COLOR) * (0.32 + 0.68 * diffuse)[..., None] + 0.45 * spec[..., None]
    alpha = np.clip((1.0 - np.sqrt(r2)) * radius + 0.5, 0.0, 1.0)[..., None]
    rows = slice(height - y1, height - y0)
    cols = slice(x0, x1)
    return rows, cols, (np.clip(rgb, 0, 1) * 255 * alpha).astype(np.float32), (1.0 - alpha).astype(np.float32)


class SphereDiscs:
    """The obstacle spheres as one camera sees them.

    Parameters
    ----------
    obstacles : Obstacles
        Centres (m, 3), radii (m,) and influence distances (m,), world units.
    view : View
        The camera.
    ppu : float
        Pixels per world unit.

    Attributes
    ----------
    centers : (m, 3) array
        Screen points (x px, y px, near) of the centres.
    radii, shell_radii : (m,) arrays
        Pixels: the discs, and their influence shells (radius plus influence).
    order : (m,) int array
        Far first.
    """

    def __init__(self, obstacles, view: View, ppu: float):
        influence = obstacles.influence[obstacles.columns(SPHERE)]
        self.centers = view.project(obstacles.centers) if len(obstacles.radii) else np.zeros((0, 3))
        self.radii = obstacles.radii * ppu
        self.shell_radii = (obstacles.radii + influence) * ppu
        self.has_shell = influence > 0
        self.sprites = [sphere_sprite(c, r, (view.width, view.height)) for c, r in zip(self.centers, self.radii)]
        self.order = np.argsort(self.centers[:, 2], kind="stable")
        gap = np.linalg.norm(self.centers[:, None, :2] - self.centers[None, :, :2], axis=-1)
        self.overlap = gap < self.radii[:, None] + self.radii[None, :]
        np.fill_diagonal(self.overlap, False)

    def __len__(self) -> int:
        return len(self.radii)

    def shells(self) -> list[np.ndarray]:
        """The influence shells of the spheres that have one, as (k, 2) pixel polygons."""
        circle = unit_circle(CIRCLE_SIDES)
        return [self.centers[i, :2] + self.shell_radii[i] * circle for i in range(len(self)) if self.has_shell[i]]

    def composite(self, buffer: np.ndarray, indices) -> None:
        """Stamp the discs ``indices``, in that order, into an (H, W, 4) frame buffer."""
        for i in indices:
            composite(buffer, self.sprites[i])

    def touched(self, boxes: list) -> np.ndarray:
        """Indices of the spheres whose discs meet any of ``boxes`` (x0, y0, x1, y1; None
        for no box) and of the spheres in front of those, which must be redrawn over them;
        far first."""
        if not len(self):
            return np.zeros(0, dtype=int)
        hit = np.zeros(len(self), dtype=bool)
        c, r = self.centers, self.radii
        for b in boxes:
            if b is not None:
                hit |= (c[:, 0] + r >= b[0]) & (c[:, 0] - r <= b[2]) & (c[:, 1] + r >= b[1]) & (c[:, 1] - r <= b[3])
        while True:
            nearer = (self.overlap[hit].any(axis=0)) & ~hit
            nearer &= c[:, 2] > c[hit, 2].min() if hit.any() else False
            if not nearer.any():
                break
            hit |= nearer
        return self.order[hit[self.order]]

    def behind(self, screen: np.ndarray) -> np.ndarray:
        """(P,) bool: screen points (P, 3) hidden by a sphere (on its disc and farther than its centre)."""
        inside, nearer = self._on_discs(screen)
        return np.any(inside & ~nearer, axis=1)

    def in_front(self, screen: np.ndarray) -> np.ndarray:
        """(P,) bool: screen points (P, 3) on a sphere's disc and nearer than its centre."""
        inside, nearer = self._on_discs(screen)
        return np.any(inside & nearer, axis=1)

    def _on_discs(self, screen: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(P, m) masks: point inside a sphere's disc, and nearer than its centre."""
        gap = np.linalg.norm(screen[:, None, :2] - self.centers[None, :, :2], axis=-1)
        inside = gap < self.radii[None, :]
        nearer = screen[:, None, 2] > self.centers[None, :, 2]
        return inside, nearer
