"""toppra (TOPP-RA's maintained implementation, the test extra) as the clock's oracle: the time-optimal
trajectory of the clock's own joint path under the same speed and acceleration limits."""

from __future__ import annotations

import numpy as np
import pytest


def toppra_trajectory(path, speed: np.ndarray, acceleration: np.ndarray, gridpoints: int = 8000):
    """toppra's trajectory along ``path`` (a :func:`armanim.motion.timing.clock.joint_path`: both time
    exactly the same geometry) within ``speed`` and ``acceleration`` (n,), from rest to rest, on
    ``gridpoints`` grid points; the test skips where toppra is not installed."""
    pytest.importorskip("toppra")
    import toppra
    import toppra.algorithm
    import toppra.constraint

    class ClockPath(toppra.interpolator.AbstractGeometricPath):
        def __call__(self, s, order=0):
            return path.evaluate(np.atleast_1d(np.asarray(s, dtype=float)), order)

        @property
        def dof(self):
            return path.poses.shape[1]

        @property
        def path_interval(self):
            return np.array([0.0, path.length])

    toppra.setup_logging("WARNING")
    constraints = [
        toppra.constraint.JointVelocityConstraint(np.stack([-speed, speed], axis=1)),
        toppra.constraint.JointAccelerationConstraint(np.stack([-acceleration, acceleration], axis=1)),
    ]
    return toppra.algorithm.TOPPRA(
        constraints,
        ClockPath(),
        gridpoints=np.linspace(0, path.length, gridpoints),
        parametrizer="ParametrizeConstAccel",
    ).compute_trajectory(0, 0)
