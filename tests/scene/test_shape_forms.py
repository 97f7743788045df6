"""The scene's shape forms (boxes, capsules, a floor): loaded in the scene's order, every field
checked with its line, home and goals clear of every shape."""

from __future__ import annotations

import numpy as np
import pytest

from armanim.world.obstacles import BOX, FLOOR, ROD, SPHERE

SHAPES = """\
version: 1
arm:
  base: [0, 0, 0]
  links: [2, 3, 3]
  axes: [z, y, y]
obstacles:
  - {center: [5, 5, 5], radius: 1}
  - box: {center: [4, -4, 1], size: [1, 2, 2], rpy: [0, 0, 30]}
  - capsule: {from: [-4, 0, 0], to: [-4, 0, 3], radius: 0.5}
floor: 0
goals:
  - [3, 2, 4]
"""


# line numbers of SHAPES
S = {"sphere": 7, "box": 8, "capsule": 9, "floor": 10, "goal0": 12}


@pytest.fixture
def scene_rejected(tmp_path, cli):
    from test_scene import rejected

    return lambda content, field, line, *fragments: rejected(tmp_path, cli, content, field, line, *fragments)


def test_shapes_load_in_scene_order(tmp_path):
    from test_scene import write

    from armanim.scene import load_scene, scene_to_problem

    problem = scene_to_problem(load_scene(write(tmp_path, SHAPES)).model)
    obstacles = problem.obstacles
    assert obstacles.kinds.tolist() == [SPHERE, BOX, ROD, FLOOR]
    assert obstacles.influence.tolist() == [1.0, 0.5, 0.5, 0.0]  # the defaults: radius, half the shortest edge, radius
    np.testing.assert_allclose(obstacles.boxes.half, [[0.5, 1, 1]])
    np.testing.assert_allclose(obstacles.boxes.rotations[0] @ [1, 0, 0], [np.cos(np.pi / 6), 0.5, 0], atol=1e-15)
    assert obstacles.floor == 0.0 and obstacles.rods.radius.tolist() == [0.5]


@pytest.mark.parametrize(
    "line, new, field, fragment",
    [
        (S["box"], "  - box: {center: [4, -4, 1], size: [1, 0, 2]}", "obstacles[1].box.size[1]", "must be > 0 (got 0)"),
        (
            S["capsule"],
            "  - capsule: {from: [-4, 0, 0], to: [-4, 0, 3], radius: -0.5}",
            "obstacles[2].capsule.radius",
            "must be > 0",
        ),
        (
            S["box"],
            "  - box: {center: [4, -4, 1], size: [1, 2, 2], rpy: [0, .nan, 0]}",
            "obstacles[1].box.rpy[1]",
            "finite",
        ),
        (
            S["box"],
            "  - box: {center: [4, -4, 1], size: [1, 2, 2], rpy: [0, 400, 0]}",
            "obstacles[1].box.rpy[1]",
            "<= 360",
        ),
        (
            S["box"],
            "  - {box: {center: [4, -4, 1], size: [1, 2, 2]}, radius: 1}",
            "obstacles[1]",
            "a sphere, which needs a center",
        ),
        (
            S["box"],
            "  - {box: {center: [4, -4, 1], size: [1, 2, 2]}, center: [1, 1, 1], radius: 1}",
            "obstacles[1]",
            "got center and box",
        ),
        (S["box"], "  - box: {center: [4, -4, 1], sizes: [1, 2, 2]}", "obstacles[1].box.sizes", "did you mean 'size'"),
        (S["floor"], "floor: 0.5", "floor", "above the arm's base"),
        (S["floor"], "floor: 3.9", "floor", "above the arm's base"),
    ],
)
def test_shape_fields_are_checked(scene_rejected, line, new, field, fragment):
    from test_scene import edit

    scene_rejected(edit(line, new, SHAPES), field, line, fragment)


def test_home_and_goals_clear_of_every_shape(scene_rejected):
    from test_scene import edit

    # the home pose (straight up along z from the origin) inside a box, closer than the clearance to a capsule
    scene_rejected(
        edit(S["box"], "  - box: {center: [0, 0, 4], size: [1, 1, 1]}", SHAPES),
        "obstacles[1]",
        S["box"],
        "home pose is inside this obstacle",
    )
    scene_rejected(
        edit(S["capsule"], "  - capsule: {from: [0.3, -1, 0], to: [0.3, 1, 9], radius: 0.04}", SHAPES),
        "obstacles[2]",
        S["capsule"],
        "closer to it than solver.clearance",
    )
    scene_rejected(edit(S["goal0"], "  - [4, -4, 1.5]", SHAPES), "goals[0]", S["goal0"], "inside obstacles[1]")
    scene_rejected(
        edit(S["goal0"], "  - [-4, 0.6, 2]", SHAPES), "goals[0]", S["goal0"], "from the surface of obstacles[2]"
    )
    scene_rejected(edit(S["goal0"], "  - [3, 2, -0.5]", SHAPES), "goals[0]", S["goal0"], "lies below the floor")
    scene_rejected(edit(S["goal0"], "  - [3, 2, 0.2]", SHAPES), "goals[0]", S["goal0"], "is 0.2 from the floor")
    # the home pose tilted so that link 3 dips into the floor (link 1 stands on the base: it may touch it)
    tilted = SHAPES.replace("  axes: [z, y, y]\n", "  axes: [z, y, y]\n  home: [0, 120, 0]\n")
    scene_rejected(tilted, "floor", S["floor"] + 1, "link 3 of the arm's home pose is inside the floor")
