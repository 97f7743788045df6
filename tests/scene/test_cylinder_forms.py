"""The scene's cylinder form and obstacle names: loaded in the scene's order with their defaults,
every field checked with its line (a missing radius, a zero length, a duplicate name: FILE:LINE
and exit 2), the name in the messages, home and goals clear of every cylinder."""

from __future__ import annotations

import numpy as np
import pytest

from armanim.world.obstacles import BOX, CYLINDER, FLOOR, SPHERE

CANS = """\
version: 1
arm:
  base: [0, 0, 0]
  links: [2, 3, 3]
  axes: [z, y, y]
obstacles:
  - {center: [5, 5, 5], radius: 1, name: ball}
  - cylinder: {center: [4, -4, 1], length: 2, radius: 0.5}
  - {cylinder: {center: [-4, 0, 2], length: 3, radius: 0.25, rpy: [90, 0, 0]}, name: bar}
  - {box: {center: [0, 5, 1], size: [1, 1, 1]}, name: crate}
floor: 0
goals:
  - [3, 2, 4]
"""


# line numbers of CANS
S = {"sphere": 7, "can": 8, "bar": 9, "box": 10, "goal0": 13}


@pytest.fixture
def scene_rejected(tmp_path, cli):
    from test_scene import rejected

    return lambda content, field, line, *fragments: rejected(tmp_path, cli, content, field, line, *fragments)


def test_cylinders_load_in_scene_order_with_their_names(tmp_path):
    from test_scene import write

    from armanim.scene import load_scene, scene_to_problem

    problem = scene_to_problem(load_scene(write(tmp_path, CANS)).model)
    obstacles = problem.obstacles
    assert obstacles.kinds.tolist() == [SPHERE, CYLINDER, CYLINDER, BOX, FLOOR]
    assert obstacles.influence.tolist() == [
        1.0,
        0.5,
        0.25,
        0.5,
        0.0,
    ]  # a cylinder's default: its radius or half its length, the lesser
    assert obstacles.names == ("ball", None, "bar", "crate")
    cyl = obstacles.cylinders
    np.testing.assert_allclose(cyl.half_length, [1.0, 1.5])
    np.testing.assert_allclose(cyl.radius, [0.5, 0.25])
    np.testing.assert_allclose(cyl.rotations[1][:, 2], [0, -1, 0], atol=1e-15)  # roll 90: the axis (local z) along -y
    bottom, top = cyl.ends()
    np.testing.assert_allclose(top[1], [-4, -1.5, 2], atol=1e-15)
    np.testing.assert_allclose(bottom[0], [4, -4, 0], atol=1e-15)


def test_a_scene_without_names_has_none():
    from armanim.scene import scene_model, scene_to_problem

    problem = scene_to_problem(
        scene_model(
            {
                "version": 1,
                "arm": {"links": [1, 1]},
                "obstacles": [{"cylinder": {"center": [3, 3, 0], "length": 0.5, "radius": 0.2}}],
                "goals": [[1, 1, 0]],
            }
        )
    )
    assert problem.obstacles.names == () and problem.obstacles.name(0) is None
    assert problem.obstacles.influence.tolist() == [0.2]


@pytest.mark.parametrize(
    "line, new, field, fragment",
    [
        (S["can"], "  - cylinder: {center: [4, -4, 1], length: 2}", "obstacles[1].cylinder.radius", "required"),
        (
            S["can"],
            "  - cylinder: {center: [4, -4, 1], length: 0, radius: 0.5}",
            "obstacles[1].cylinder.length",
            "must be > 0 (got 0)",
        ),
        (
            S["can"],
            "  - cylinder: {center: [4, -4, 1], length: 2, radius: -0.5}",
            "obstacles[1].cylinder.radius",
            "must be > 0",
        ),
        (
            S["can"],
            "  - cylinder: {center: [4, -4, 1], length: 2, radius: 0.5, rpy: [0, .nan, 0]}",
            "obstacles[1].cylinder.rpy[1]",
            "finite",
        ),
        (
            S["can"],
            "  - cylinder: {center: [4, -4, 1], length: 2, radius: 0.5, rpy: [0, 0]}",
            "obstacles[1].cylinder.rpy",
            "expected exactly 3",
        ),
        (
            S["can"],
            "  - cylinder: {center: [4, -4, 1], length: 2, radius: 0.5, lenght: 3}",
            "obstacles[1].cylinder.lenght",
            "did you mean 'length'",
        ),
        (
            S["can"],
            "  - cylinder: {centre: [4, -4, 1], length: 2, radius: 0.5}",
            "obstacles[1].cylinder.centre",
            "did you mean 'center'",
        ),
        (
            S["can"],
            "  - {cylinder: {center: [4, -4, 1], length: 2, radius: 0.5}, box: {center: [0, 0, 9], size: [1, 1, 1]}}",
            "obstacles[1]",
            "got box and cylinder",
        ),
        (
            S["can"],
            "  - {cylinder: {center: [4, -4, 1], length: 2, radius: 0.5}, radius: 1}",
            "obstacles[1]",
            "a sphere, which needs a center",
        ),
        (
            S["can"],
            "  - cylinder: {center: [4, -4, 1], length: 1e-12, radius: 0.5}",
            "obstacles[1].cylinder.length",
            "too small",
        ),
        (
            S["can"],
            "  - {cylinder: {center: [4, -4, 1], length: 2, radius: 0.5}, name: ''}",
            "obstacles[1].name",
            "at least 1",
        ),
        (
            S["can"],
            "  - {cylinder: {center: [4, -4, 1], length: 2, radius: 0.5}, name: 7}",
            "obstacles[1].name",
            "string",
        ),
        (
            S["box"],
            "  - {box: {center: [0, 5, 1], size: [1, 1, 1]}, name: bar}",
            "obstacles[3].name",
            "'bar' already names obstacles[2]",
        ),
    ],
)
def test_cylinder_fields_and_names_are_checked(scene_rejected, line, new, field, fragment):
    from test_scene import edit

    scene_rejected(edit(line, new, CANS), field, line, fragment)


def test_home_and_goals_clear_of_every_cylinder_the_message_naming_it(scene_rejected):
    from test_scene import edit

    # the home pose (straight up along z from the origin) through a lying can; a goal inside a named can, one near an unnamed one
    scene_rejected(
        edit(
            S["bar"], "  - {cylinder: {center: [0, 0, 5], length: 3, radius: 0.25, rpy: [90, 0, 0]}, name: bar}", CANS
        ),
        "obstacles[2]",
        S["bar"],
        "home pose is inside 'bar'",
    )
    scene_rejected(edit(S["goal0"], "  - [-4, 1.2, 2]", CANS), "goals[0]", S["goal0"], "inside obstacles[2] ('bar')")
    scene_rejected(
        edit(S["goal0"], "  - [4.6, -4, 1]", CANS), "goals[0]", S["goal0"], "is 0.1 from the surface of obstacles[1]"
    )
    scene_rejected(
        edit(S["goal0"], "  - [4, -4, 2.05]", CANS), "goals[0]", S["goal0"], "from the surface of obstacles[1]"
    )


def test_the_schema_knows_the_cylinder_and_the_name():
    import json
    from pathlib import Path

    schema = json.loads(
        (Path(__file__).resolve().parents[2] / "docs" / "scene.schema.json").read_text(encoding="utf-8")
    )
    text = json.dumps(schema)
    assert '"cylinder"' in text and "CylinderModel" in text
    assert schema["$defs"]["CylinderModel"]["required"] == ["center", "length", "radius"]
    assert "name" in schema["$defs"]["ObstacleModel"]["properties"]
