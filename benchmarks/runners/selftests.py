"""The motion benchmark's start-up self-tests: the oracles' kinematics and clearances (its own
chain, pinocchio's, coal's) equal armanim's to 1e-9 on random arms and poses. They check the two
sides; they are not a source of the oracles' numbers.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from generators.arms import Draft
from oracles.geometry import AXES, AXIS_INDEX, Geometry, joint_points, solid_gaps
from oracles.robots import ROBOT_NAMES, base_geometry, min_clearance

from armanim.arm.capsules import joint_capsules
from armanim.arm.kinematics import Arm, forward, tool_rotation
from armanim.scene import scene_model
from armanim.scene.convert import scene_to_problem
from armanim.world.distances import clearances, min_link_clearance
from armanim.world.obstacles import Obstacles


def self_test_geometry(rng: np.random.Generator, poses: int = 200) -> None:
    """Assert that the oracle's geometry is armanim's: joint points and capsule clearances agree to 1e-9.

    Raises
    ------
    AssertionError
        When the two forward kinematics or clearances differ on any random arm and pose.
    """
    for trial in range(12):
        n = int(rng.integers(1, 8))
        axes = tuple(rng.choice(["x", "y", "z"], size=n))
        direction = str(rng.choice(["x", "y", "z"]))
        geo = Geometry(
            base=rng.uniform(-5, 5, 3),
            links=rng.uniform(0.5, 5, n),
            axes=axes,
            direction=AXES[AXIS_INDEX[direction]],
            half_width=float(rng.uniform(0.1, 0.4)),
            lower=np.full(n, -np.inf),
            upper=np.full(n, np.inf),
            centers=rng.uniform(-8, 8, (3, 3)),
            radii=rng.uniform(0.2, 2, 3),
            home=np.zeros(n),
        )
        arm = Arm.from_names(list(geo.links), base=tuple(geo.base), axes=list(axes), direction=direction)
        phi = rng.uniform(-np.pi, np.pi, (poses, n))
        ours = joint_points(geo, phi)
        theirs = forward(arm, phi).points
        assert np.max(np.abs(ours - theirs)) < 1e-9, f"oracle FK differs from armanim's (trial {trial})"
        single = forward(arm, phi[0]).points
        assert np.max(np.abs(ours[0] - single)) < 1e-9, "oracle FK differs from armanim's single-pose FK"
        obstacles = Obstacles(centers=geo.centers, radii=geo.radii, influence=geo.radii)
        armanim_cl = min_link_clearance(forward(arm, phi), obstacles, joint_capsules(arm, geo.half_width))
        assert np.max(np.abs(min_clearance(geo, phi) - armanim_cl)) < 1e-9, "oracle clearance differs from armanim's"


def self_test_robots(rng: np.random.Generator, poses: int = 40) -> None:
    """Assert that pinocchio's tool point and the oracle's capsule clearances equal armanim's (1e-9) on
    every bundled robot: a check of the two sides, not a source of the oracle's numbers."""
    for robot in ROBOT_NAMES:
        geo = base_geometry(robot)
        centers, radii = rng.uniform(-0.6, 0.6, (4, 3)), rng.uniform(0.03, 0.1, 4)
        geo = replace(geo, centers=centers, radii=radii)
        model = scene_model({"version": 1, "name": "probe", "arm": {"robot": robot}, "goals": [[0.3, 0.0, 0.4]]})
        problem = scene_to_problem(model)
        phi = rng.uniform(np.maximum(geo.lower, -np.pi), np.minimum(geo.upper, np.pi), (poses, len(geo.lower)))
        pose = forward(problem.arm, phi)
        assert np.max(np.abs(geo.tip(phi) - pose.tip)) < 1e-9, f"{robot}: pinocchio's tool point differs from armanim's"
        rotations = tool_rotation(problem.arm, pose)
        assert max(np.abs(geo.rotation(q) - r).max() for q, r in zip(phi[:8], rotations)) < 1e-9, (
            f"{robot}: pinocchio's tool frame differs from armanim's"
        )
        obstacles = Obstacles(centers=centers, radii=radii, influence=radii)
        theirs = min_link_clearance(pose, obstacles, problem.capsules)
        assert np.max(np.abs(min_clearance(geo, phi) - theirs)) < 1e-9, (
            f"{robot}: the oracle's capsule clearance differs from armanim's"
        )


def self_test_solids(rng: np.random.Generator, poses: int = 60) -> None:
    """Assert that the oracle's clearances (coal) to boxes, capsules and a floor equal armanim's closed
    forms to 1e-9 on random arms and poses where every part is clear (inside, the two measure
    penetration differently), robots included."""
    from armanim.arm.chain import rpy_rotation
    from armanim.world.obstacles import BOX, FLOOR, ROD, Boxes, Rods

    for trial in range(6):
        n = int(rng.integers(2, 7))
        arm = Arm.from_names(
            list(rng.uniform(1, 4, n)), base=tuple(rng.uniform(-2, 2, 3)), axes=list(rng.choice(["x", "y", "z"], n))
        )
        boxes = [(rng.uniform(-8, 8, 3), rng.uniform(0.5, 3, 3), rng.uniform(-180, 180, 3)) for _ in range(2)]
        rods = [(a, a + rng.normal(size=3) * 2, float(rng.uniform(0.2, 1))) for a in rng.uniform(-8, 8, (2, 3))]
        floor = float(arm.base[2] - 1.0)
        draft = Draft(
            kind="test",
            base=arm.base,
            links=arm.links,
            axes=[],
            direction="z",
            width=0.4,
            home=np.zeros(n),
            limits=[],
            boxes=boxes,
            rods=rods,
            floor=floor,
        )
        solids = draft.solids()
        obstacles = Obstacles(
            np.zeros((0, 3)),
            np.zeros(0),
            np.ones(5),
            Boxes(
                np.array([c for c, _, _ in boxes]),
                np.array([sz for _, sz, _ in boxes]) / 2,
                np.array([rpy_rotation(np.radians(r)) for _, _, r in boxes]),
            ),
            Rods(
                np.array([a for a, _, _ in rods]), np.array([b for _, b, _ in rods]), np.array([r for _, _, r in rods])
            ),
            floor,
            np.array([BOX, BOX, ROD, ROD, FLOOR]),
        )
        phi = rng.uniform(-np.pi, np.pi, (poses, n))
        pose = forward(arm, phi)
        ours = clearances(pose, obstacles, joint_capsules(arm, 0.2)).links
        theirs = solid_gaps(solids, pose.points[:, :-1], pose.points[:, 1:], np.full(n, 0.2), np.arange(n) == 0)
        clear = np.all(ours > 1e-6, axis=(-1, -2)) & np.all(theirs > 1e-6, axis=(-1, -2))
        assert clear.sum() >= 5, "too few clear poses to compare"
        both_inf = np.isinf(ours) & np.isinf(theirs)  # the floor's column of the first link: left out by both
        with np.errstate(invalid="ignore"):  # inf - inf where both are infinite, replaced by 0
            diff = np.abs(np.where(both_inf, 0.0, ours - theirs))
        assert np.max(diff[clear]) < 1e-9, (
            f"trial {trial}: the oracle's solid clearances differ from armanim's by {np.max(diff[clear]):.3g}"
        )
