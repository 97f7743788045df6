"""Pictures of boxes, capsules and a floor: goals hidden behind a box, the sphere path kept for
spheres, the poster and pose of every shape, the viewer's data."""

from __future__ import annotations

import numpy as np
from test_motion_among_shapes import notes_among

from armanim.arm.chain import rpy_rotation
from armanim.arm.kinematics import forward
from armanim.motion.trajectory import solve_trajectory


def shelf_problem():
    from conftest import ROOT

    from armanim.scene import load_scene, scene_to_problem

    return scene_to_problem(
        load_scene(ROOT / "tests" / "data" / "panda-two-boards.yaml").model
    )  # panda-shelf before issue 54


def test_goal_behind_a_box_is_drawn_through_it():
    from armanim.render.pictures.canvas import SceneCanvas
    from armanim.scene import default_render_settings

    problem = shelf_problem()
    canvas = SceneCanvas(
        problem, default_render_settings(size=(96, 64)), title="t", extent=forward(problem.arm, problem.home).points
    )
    # goal 0 sits between the boards under the upper one; goal 1 shows under its front edge; 2 and 3 are above
    assert canvas.goals.hidden.tolist() == [True, False, False, False]
    assert canvas.shapes is not None and len(canvas.shapes.parts) == 2


def test_spheres_only_pictures_take_the_sphere_path():
    from test_cost import notes_problem

    from armanim.render.pictures.canvas import SceneCanvas
    from armanim.scene import default_render_settings

    problem = notes_problem()
    assert SceneCanvas(problem, default_render_settings(size=(64, 48)), title="t").shapes is None


def test_poster_and_pose_of_every_shape(tmp_path):
    from armanim.output.solved import SolvedRun
    from armanim.render.pictures.pose import render_pose_png
    from armanim.render.pictures.poster import render_poster
    from armanim.render.settings import OutputOptions
    from armanim.scene import default_render_settings

    problem = notes_among(
        ((9.0, 0.0, 1.0),),
        boxes=[((6.0, 0.0, 2.0), (4.0, 4.0, 4.0), (0.0, 0.0, 0.5))],
        rods=[((-4.0, 0.0, 0.0), (-4.0, 0.0, 8.0), 0.5)],
        floor=-0.5,
    )
    solution = solve_trajectory(problem)
    settings = default_render_settings(size=(64, 48))
    render_poster(SolvedRun("shapes", problem, solution), OutputOptions(settings), tmp_path / "poster.png")
    render_pose_png(problem, problem.home, settings, tmp_path / "pose.png", title="shapes")
    assert (tmp_path / "poster.png").stat().st_size > 0 and (tmp_path / "pose.png").stat().st_size > 0


def test_viewer_data_carries_boxes_capsules_and_the_floor():
    from armanim.render.viewer.data import shape_entries, viewer_data
    from armanim.scene import default_render_settings

    problem = notes_among(
        ((9.0, 0.0, 1.0),),
        boxes=[((6.0, 0.0, 2.0), (4.0, 4.0, 4.0), (0.0, 0.0, 0.5))],
        rods=[((-4.0, 0.0, 0.0), (-4.0, 0.0, 8.0), 0.5)],
        floor=-0.5,
    )
    solution = solve_trajectory(problem)
    data = viewer_data(problem, solution.trajectory, solution.goals, default_render_settings(size=(64, 48)), title="t")
    assert data["obstacles"] == [] and data["view"]["floor"]["z"] == -0.5
    (box,) = data["boxes"]
    assert box["size"] == [4.0, 4.0, 4.0] and box["influence"] == 0.5
    np.testing.assert_allclose(box["rotation"], rpy_rotation([0.0, 0.0, 0.5]))
    assert data["obstacle_capsules"] == [
        {"from": [-4.0, 0.0, 0.0], "to": [-4.0, 0.0, 8.0], "radius": 0.5, "influence": 0.5}
    ]
    from test_cost import notes_problem

    assert shape_entries(notes_problem().obstacles) == {}  # spheres: the page's data as it always was


def cans_problem():
    """The notes' arm beside a standing can (named) and a lying one, with a floor."""
    from dataclasses import replace

    from strategies import with_floor
    from test_motion import notes_problem

    from armanim.world.obstacles import CYLINDER, Cylinders, Obstacles

    problem = notes_problem(goals=((9.0, 0.0, 1.0),), method="pinv", planner="off")
    cylinders = Cylinders(
        np.array([[6.0, 0.0, 2.0], [-4.0, 0.0, 3.0]]),
        np.array([np.eye(3), rpy_rotation([np.pi / 2, 0.0, 0.0])]),
        np.array([2.0, 1.5]),
        np.array([1.5, 0.5]),
    )
    obstacles = Obstacles(
        np.zeros((0, 3)),
        np.zeros(0),
        np.array([0.5, 0.25]),
        kinds=np.array([CYLINDER, CYLINDER]),
        cylinders=cylinders,
        names=("can1", None),
    )
    return replace(problem, obstacles=with_floor(obstacles, -0.5))


def test_a_cylinder_hides_what_is_behind_it_and_not_what_is_in_front():
    from armanim.render.pictures.canvas import SceneCanvas
    from armanim.scene import default_render_settings

    problem = cans_problem()
    canvas = SceneCanvas(
        problem, default_render_settings(size=(96, 64)), title="t", extent=forward(problem.arm, problem.home).points
    )
    assert canvas.shapes is not None and len(canvas.shapes.parts) == 2  # one solid per cylinder
    toward = np.linalg.solve(canvas.view.linear, [0.0, 0.0, 1.0])  # the world direction to the camera (screen z grows)
    toward /= np.linalg.norm(toward)
    center = np.array([6.0, 0.0, 2.0])
    behind, in_front = canvas.view.project(np.array([center - 3.0 * toward, center + 3.0 * toward]))
    assert canvas.shapes.behind(behind[None]).tolist() == [True]
    assert canvas.shapes.behind(in_front[None]).tolist() == [False] and canvas.shapes.in_front(
        in_front[None]
    ).tolist() == [True]
    aside = canvas.view.project(center + [0.0, 9.0, 0.0])  # beside the can on screen, nowhere over it
    assert canvas.shapes.behind(aside[None]).tolist() == [False]


def test_poster_and_pose_with_cylinders(tmp_path):
    from armanim.output.solved import SolvedRun
    from armanim.render.pictures.pose import render_pose_png
    from armanim.render.pictures.poster import render_poster
    from armanim.render.settings import OutputOptions
    from armanim.scene import default_render_settings

    problem = cans_problem()
    solution = solve_trajectory(problem)
    settings = default_render_settings(size=(64, 48))
    render_poster(SolvedRun("cans", problem, solution), OutputOptions(settings), tmp_path / "poster.png")
    render_pose_png(problem, problem.home, settings, tmp_path / "pose.png", title="cans")
    assert (tmp_path / "poster.png").stat().st_size > 0 and (tmp_path / "pose.png").stat().st_size > 0


def test_viewer_data_carries_cylinders_and_names():
    from armanim.render.viewer.data import viewer_data
    from armanim.scene import default_render_settings

    problem = cans_problem()
    solution = solve_trajectory(problem)
    data = viewer_data(problem, solution.trajectory, solution.goals, default_render_settings(size=(64, 48)), title="t")
    can, bar = data["cylinders"]
    assert can == {
        "center": [6.0, 0.0, 2.0],
        "length": 4.0,
        "radius": 1.5,
        "rotation": np.eye(3).tolist(),
        "influence": 0.5,
        "name": "can1",
    }
    assert "name" not in bar and bar["length"] == 3.0
    np.testing.assert_allclose(bar["rotation"], rpy_rotation([np.pi / 2, 0.0, 0.0]))
