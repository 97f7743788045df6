"""A scene with cylinders runs: ``armanim run`` on a UR5 reaching past a standing can and a lying
bar writes its trajectory, and every frame keeps solver.clearance from every cylinder by coal's
distances (an independent check of the arm's capsules against coal's cylinders); summary.json names
the nearest obstacle by its scene name; random scenes with cylinders keep every invariant."""

from __future__ import annotations

import csv

import numpy as np
import pytest
from hypothesis import given, settings
from invariants import assert_trajectory_invariants, small_planning_budget
from strategies import shaped_problems

from armanim.motion.trajectory import solve_trajectory

coal = pytest.importorskip("coal")  # the oracle (the test extra)

SCENE = """\
version: 1
name: ur5-cans
arm:
  robot: ur5
obstacles:
  - {cylinder: {center: [0.5, 0.0, 0.25], length: 0.3, radius: 0.04}, influence: 0.05, name: can1}
  - {cylinder: {center: [0.35, -0.25, 0.45], length: 0.3, radius: 0.03, rpy: [0, 90, 30]}, influence: 0.05, name: bar}
floor: 0.0
goals:
  - {position: [0.45, 0.2, 0.25], hold: 0.2}
  - [0.45, -0.25, 0.25]
solver:
  method: dls
  tolerance: 0.005
  clearance: 0.02
  max_step: 0.02
"""


def coal_capsule(a, b, radius):
    """coal's capsule (axis along its local z, centred) around the segment a-b (a sphere where a == b)."""
    axis = b - a
    length = float(np.linalg.norm(axis))
    if length == 0.0:
        return coal.Sphere(radius), coal.Transform3s(np.eye(3), a)
    z = axis / length
    x = np.cross(z, [1.0, 0, 0] if abs(z[0]) < 0.9 else [0, 1.0, 0])
    x /= np.linalg.norm(x)
    return coal.Capsule(radius, length), coal.Transform3s(np.stack([x, np.cross(z, x), z], axis=1), (a + b) / 2)


def test_a_cylinder_scene_runs_and_every_frame_keeps_its_clearance_by_coal(tmp_path, cli):
    from armanim.arm.capsules import capsule_ends
    from armanim.arm.kinematics import forward
    from armanim.scene import load_scene, scene_to_problem

    scene = tmp_path / "cans.yaml"
    scene.write_text(SCENE, encoding="utf-8")
    result = cli("run", scene, "--no-video", "--jobs", "1", "--out", tmp_path / "out", "-q")
    assert result.exit_code == 0, result.output
    with open(tmp_path / "out" / "ur5-cans" / "trajectory.csv", newline="", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    problem = scene_to_problem(load_scene(scene).model)
    n = problem.arm.n
    phi = np.radians([[float(r[f"phi{j + 1}_deg"]) for j in range(n)] for r in rows])
    assert {int(r["reached"]) for r in rows} == {0, 1} and len(rows) > 30
    cyl, caps = problem.obstacles.cylinders, problem.capsules
    cylinders = [
        (
            coal.Cylinder(float(cyl.radius[k]), float(2 * cyl.half_length[k])),
            coal.Transform3s(cyl.rotations[k], cyl.centers[k]),
        )
        for k in range(len(cyl))
    ]
    request = coal.DistanceRequest()
    request.gjk_tolerance = 1e-12
    each = np.full(len(cylinders), np.inf)  # the least over the frames, per cylinder
    for frame in range(len(rows)):
        a, b = capsule_ends(caps, forward(problem.arm, phi[frame]))
        for i in range(len(a)):
            shape, tf = coal_capsule(a[i], b[i], float(caps.radius[i]))
            for k, (cylinder, place) in enumerate(cylinders):
                each[k] = min(each[k], coal.distance(cylinder, place, shape, tf, request, coal.DistanceResult()))
    least = each.min()
    # coal's distance is the arm's clearance (its own column in the file agrees) and it never falls below solver.clearance
    assert least >= problem.solver.clearance - 1e-9, least
    assert least < 0.1  # the arm does pass near them: the check is not vacuous
    recorded = np.array([float(r["clearance"]) for r in rows])
    assert recorded.min() >= problem.solver.clearance - 1e-12
    assert recorded.min() <= least + 1e-9  # the file's clearance also counts the floor
    # summary.json names the obstacle of the least clearance by its scene name
    import json

    summary = json.loads((tmp_path / "out" / "ur5-cans" / "summary.json").read_text(encoding="utf-8"))
    assert summary["min_clearance"] == pytest.approx(recorded.min(), abs=1e-9)
    expected = ["can1", "bar"][int(np.argmin(each))] if least <= recorded.min() + 1e-9 else "floor"
    assert summary["min_clearance_obstacle"] == expected


@given(shaped_problems(max_links=5, max_goals=2, max_frames=60, cylinders=True))
@settings(max_examples=6)
def test_scenes_with_cylinders_keep_every_invariant(problem):
    # spheres, boxes, capsules and cylinders across the paths (the planner on): every frame keeps its clearance
    assert_trajectory_invariants(problem, solve_trajectory(small_planning_budget(problem)))


def test_the_summary_names_an_unnamed_obstacle_by_its_place_and_none_without_obstacles():
    from armanim.output.summary import nearest_obstacle
    from armanim.scene import scene_model, scene_to_problem

    def solved(obstacles):
        problem = scene_to_problem(
            scene_model(
                {
                    "version": 1,
                    "arm": {"links": [2, 3, 3], "axes": ["z", "y", "y"]},
                    "obstacles": obstacles,
                    "goals": [[3, 2, 4]],
                }
            )
        )
        return problem, solve_trajectory(problem).trajectory

    problem, traj = solved(
        [{"center": [-5, -5, 9], "radius": 0.5}, {"cylinder": {"center": [4, -1, 3], "length": 2, "radius": 0.5}}]
    )
    assert nearest_obstacle(problem, traj) == "obstacles[1]"
    problem, traj = solved([])
    assert nearest_obstacle(problem, traj) is None
