"""Directions of any finite size normalised exactly (issue 36).

Each test is named in docs/reliability.md, which it keeps true.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from armanim.arm.geometry import unit_vector
from armanim.motion.orientation import Orientation


@pytest.mark.parametrize(
    "vector",
    [
        [1e-320, 0, 0],
        [1e-200, 1e-200, 0],
        [1e308, 0, 1e308],
        [-1e308, -1e308, -1e308],
        [5e-324, 5e-324, 0],
        [0, -0.0, 3e-310],
    ],
)
def test_a_direction_of_any_finite_size_is_normalised_exactly(vector):
    unit = unit_vector(vector)
    exact = np.sign(vector) * (np.array(vector) != 0) / math.sqrt(sum(v != 0 for v in vector))  # equal components here
    assert np.all(np.isfinite(unit)) and np.allclose(unit, exact, atol=1e-15)
    assert np.allclose(Orientation(axis=np.array(vector, dtype=float)).axis, exact, atol=1e-15)
