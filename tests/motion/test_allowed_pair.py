"""A capsule allowed to touch one obstacle (a carried object and its support, issue 54): that pair's
clearance is +inf and every other pair's is unchanged, in the numpy references and in the compiled
kernels (the cost's and the filter's clearances, the planner's margins and frame margins)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from armanim.arm.kinematics import forward
from armanim.motion.filter.clearance import split_clearances
from armanim.motion.kernels.layout import kernel_problem, world_arrays
from armanim.motion.planning.check import CompiledCheck, frame_margins
from armanim.scene import scene_model, scene_to_problem
from armanim.world.distances import clearances, min_link_clearance

SCENE = {
    "version": 1,
    "arm": {"robot": "panda"},
    "floor": -0.02,
    "goals": [[0.4, 0.0, 0.5]],
    "obstacles": [
        {"box": {"center": [0.5, 0.0, 0.1], "size": [0.3, 0.6, 0.02]}},
        {"center": [0.3, -0.3, 0.5], "radius": 0.06},
        {"cylinder": {"center": [0.4, 0.3, 0.3], "length": 0.2, "radius": 0.04}},
        {"box": {"center": [0.0, 0.5, 0.4], "size": [0.1, 0.1, 0.4]}},
    ],
}


def _allowed_problem(seed: int):
    problem = scene_to_problem(scene_model(SCENE))
    rng = np.random.default_rng(seed)
    caps = problem.capsules
    allowed = np.full(len(caps), -1)
    some = rng.choice(len(caps), size=len(caps) // 2, replace=False)
    allowed[some] = rng.integers(0, len(problem.obstacles), size=len(some))  # every kind's column, the floor's too
    return problem, replace(problem, capsules=replace(caps, allowed=allowed)), rng


def _kernel_d(problem, pose):
    """The compiled kernel's clearances of one pose, given writable arrays as the compiled check
    gives it (capsule_ends' are read-only: another signature, compiled for this test alone)."""
    from armanim.arm.capsules import capsule_ends
    from armanim.motion.kernels.check import obstacle_clearances

    a, b = capsule_ends(problem.capsules, pose)
    m = len(problem.obstacles)
    d, t, n = np.empty((len(a) + 1, m)), np.empty((len(a) + 1, m)), np.empty((len(a) + 1, m, 3))
    part_radius = kernel_problem(problem).part_radius
    obstacle_clearances(pose.points, np.array(a), np.array(b), part_radius, world_arrays(problem), d, t, n)
    return d


@pytest.mark.parametrize("seed", range(3))
def test_an_allowed_pair_is_left_out_and_every_other_pair_kept(seed):
    plain, allowed, rng = _allowed_problem(seed)
    mask = np.zeros((len(allowed.capsules) + 1, len(allowed.obstacles)), dtype=bool)
    parts = np.nonzero(allowed.capsules.part_allowed >= 0)[0]
    mask[parts, allowed.capsules.part_allowed[parts]] = True
    assert mask.any()
    poses = plain.home + rng.normal(size=(16, plain.arm.n)) * 0.6
    for phi in poses:
        pose = forward(plain.arm, phi)
        full = clearances(pose, plain.obstacles, plain.capsules).d
        left = clearances(forward(plain.arm, phi), allowed.obstacles, allowed.capsules).d
        assert np.all(np.isinf(left[mask])) and np.array_equal(left[~mask], full[~mask])
        np.testing.assert_allclose(_kernel_d(allowed, forward(plain.arm, phi)), left, rtol=0, atol=1e-12)
    pose = forward(plain.arm, poses)
    every = clearances(pose, plain.obstacles, plain.capsules).links
    least = np.where(mask[:-1], np.inf, every).min(axis=(-1, -2))
    assert np.any(least > every.min(axis=(-1, -2)))  # an allowed pair was some pose's least: left out, it matters
    np.testing.assert_array_equal(
        min_link_clearance(forward(plain.arm, poses), allowed.obstacles, allowed.capsules), least
    )
    clear, _ = frame_margins(allowed, poses)
    np.testing.assert_allclose(clear, least, rtol=0, atol=1e-12)
    check = CompiledCheck.of(allowed)
    margins, _ = check.margins(poses)
    reference = split_clearances(allowed, poses)[0]
    near = reference < check.far
    np.testing.assert_allclose(margins[near], reference[near], rtol=0, atol=1e-12)
    assert np.all(margins[~near] >= check.far - 1e-12) and np.all(margins <= reference + 1e-12)
