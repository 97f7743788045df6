"""The obstacles of the world: solid spheres, each with an influence shell.

Pure core: numpy only, scene units, no I/O.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Obstacles:
    """Solid spheres with an influence shell.

    Attributes
    ----------
    centers : (m, 3) array
    radii : (m,) array
        Radius of each solid sphere (0 allowed: the notes' point obstacle).
    influence : (m,) array
        R of the field F_R: how far beyond the surface the penalty reaches.
    """

    centers: np.ndarray
    radii: np.ndarray
    influence: np.ndarray

    @classmethod
    def none(cls) -> Obstacles:
        """No obstacles."""
        return cls(np.zeros((0, 3)), np.zeros(0), np.zeros(0))

    def __len__(self) -> int:
        return len(self.radii)
