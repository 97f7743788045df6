"""The fixed camera of a video as one affine map: world -> (pixel x, pixel y, nearness).

The camera is orthographic (:mod:`armanim.render.camera.projection` builds the map), so world to
display pixels is affine: one matrix product projects a whole batch of points.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

LIGHT = np.array([-0.45, 0.6, 0.66])  # in screen space: x right, y up, z toward the viewer
LIGHT = LIGHT / np.linalg.norm(LIGHT)


@dataclass(frozen=True)
class View:
    """World-to-screen map of a fixed orthographic camera.

    Attributes
    ----------
    matrix : (3, 4) array
        Affine map of homogeneous world points to (x, y, near): display pixels
        (origin bottom left, y up) and a depth that grows toward the viewer.
    width, height : int
        Canvas size in pixels.
    """

    matrix: np.ndarray
    width: int
    height: int

    @property
    def linear(self) -> np.ndarray:
        """(3, 3): the linear part of the map."""
        return self.matrix[:, :3]

    @property
    def pixels_per_unit(self) -> np.ndarray:
        """(2,): display pixels per world unit along screen x and y."""
        return np.linalg.norm(self.linear[:2], axis=1)

    def project(self, points: np.ndarray) -> np.ndarray:
        """(..., 3) world points -> (..., 3) screen points (x px, y px, near)."""
        return points @ self.linear.T + self.matrix[:, 3]

    def screen_normals(self, normals: np.ndarray) -> np.ndarray:
        """(..., 3) world normals -> unit normals in screen space (z toward viewer)."""
        n = normals @ np.linalg.inv(self.linear)  # inverse transpose, row vectors
        return n / np.maximum(np.linalg.norm(n, axis=-1, keepdims=True), 1e-12)


AMBIENT, DIFFUSE = 0.38, 0.62
"""The light every surface gets, and the most the light adds facing it."""


def lambert(normals: np.ndarray, color, ambient: float = AMBIENT, diffuse: float = DIFFUSE) -> np.ndarray:
    """Flat shading of faces with screen-space unit normals, (..., 3) -> (..., 3) RGB."""
    intensity = ambient + diffuse * np.clip(normals @ LIGHT, 0.0, 1.0)
    return np.clip(np.asarray(color)[:3] * intensity[..., None], 0.0, 1.0)
