"""Boxes, capsules and a floor: exact distances (against coal and brute force), their
Jacobian rows, and the scene's shape forms and their checks."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from invariants import assert_trajectory_invariants, small_planning_budget
from strategies import shaped_problems

from armanim.arm.capsules import capsule_point_jacobian, joint_capsules
from armanim.arm.chain import rpy_rotation
from armanim.arm.kinematics import Arm, forward
from armanim.motion.trajectory import solve_trajectory
from armanim.world.closest import segment_box
from armanim.world.distances import clearances, point_clearances, sphere_clearances
from armanim.world.obstacles import BOX, FLOOR, ROD, SPHERE, Boxes, Obstacles, Rods

coal = pytest.importorskip("coal")  # the oracle (the test extra)


def box_signed_distance(p: np.ndarray, half: np.ndarray) -> np.ndarray:
    """The test's own signed distance of points ``p`` (box frame, (..., 3)) to the box of half
    edges ``half`` (negative inside), written apart from the compiled one."""
    q = np.abs(p) - half
    return np.linalg.norm(np.maximum(q, 0.0), axis=-1) + np.minimum(q.max(axis=-1), 0.0)


def coal_request():
    request = coal.DistanceRequest()
    request.gjk_tolerance = 1e-13
    return request


def coal_capsule(a, b, radius):
    """coal's capsule (axis along its local z, centred) around the segment a-b."""
    axis = b - a
    length = float(np.linalg.norm(axis))
    z = axis / length
    x = np.cross(z, [1.0, 0, 0] if abs(z[0]) < 0.9 else [0, 1.0, 0])
    x /= np.linalg.norm(x)
    return coal.Capsule(radius, length), coal.Transform3s(np.stack([x, np.cross(z, x), z], axis=1), (a + b) / 2)


def coal_distance(shape1, tf1, shape2, tf2):
    result = coal.DistanceResult()
    distance = coal.distance(shape1, tf1, shape2, tf2, coal_request(), result)
    return distance, result


def random_box(rng):
    return rng.normal(size=3), rng.uniform(0.05, 1.0, 3), rpy_rotation(rng.uniform(-np.pi, np.pi, 3))


def test_segment_box_matches_coal():
    rng = np.random.default_rng(22)
    compared = 0
    for _ in range(400):
        center, half, rotation = random_box(rng)
        a = center + rng.normal(size=3) * 1.5
        b = a + rng.normal(size=3)
        radius = 0.03
        t, dist, normal = segment_box(a, b, center, half, rotation)
        if dist - radius < 1e-3:
            continue  # coal's penetration depth is another measure than ours inside
        capsule, tf = coal_capsule(a, b, radius)
        expected, result = coal_distance(coal.Box(*(2 * half)), coal.Transform3s(rotation, center), capsule, tf)
        assert abs((dist - radius) - expected) < 1e-9
        on_box = a + t * (b - a) - dist * normal  # the box point closest to the segment
        np.testing.assert_allclose(on_box, result.getNearestPoint1(), atol=1e-6)
        np.testing.assert_allclose(normal, result.normal, atol=1e-6)
        compared += 1
    assert compared > 200


def segment_to_axis(a, b, start, end):
    """(t, distance, normal) of segment a-b to the capsule obstacle start-end's axis (:meth:`Rods.axes`)."""
    axis = Rods(np.asarray(start, float)[None], np.asarray(end, float)[None], np.ones(1)).axes()
    return segment_box(np.asarray(a, float), np.asarray(b, float), axis.centers[0], axis.half[0], axis.rotations[0])


def test_segment_to_a_capsule_axis_matches_coal():
    rng = np.random.default_rng(7)
    compared = 0
    for _ in range(400):
        a, c = rng.normal(size=3), rng.normal(size=3)
        b, e = a + rng.normal(size=3), c + rng.normal(size=3)
        t, dist, normal = segment_to_axis(a, b, c, e)
        clearance = float(dist) - 0.05 - 0.02
        if clearance < 1e-3:
            continue
        one, tf1 = coal_capsule(c, e, 0.05)
        two, tf2 = coal_capsule(a, b, 0.02)
        expected, result = coal_distance(one, tf1, two, tf2)
        assert abs(clearance - expected) < 1e-9
        np.testing.assert_allclose(a + t * (b - a) - 0.02 * normal, result.getNearestPoint2(), atol=1e-6)
        np.testing.assert_allclose(normal, result.normal, atol=1e-6)
        compared += 1
    assert compared > 200


def test_parallel_and_point_segments():
    # parallel segments: any pair along the overlap is closest; the distance is exact, the far end's point taken
    t, dist, normal = segment_to_axis(np.zeros(3), np.array([2.0, 0, 0]), np.array([1.0, 1, 0]), np.array([3.0, 1, 0]))
    assert float(dist) == pytest.approx(1.0, abs=1e-15) and float(t) == 1.0
    np.testing.assert_allclose(normal, [0.0, -1.0, 0.0], atol=1e-15)
    # a point (the tip) against a segment, and a point against a point
    t, dist, normal = segment_to_axis(np.array([1.0, 5, 0]), np.array([1.0, 5, 0]), np.zeros(3), np.array([2.0, 0, 0]))
    assert float(dist) == pytest.approx(5.0, abs=1e-15)
    np.testing.assert_allclose(normal, [0.0, 1.0, 0.0], atol=1e-15)
    t, dist, normal = segment_to_axis(np.ones(3), np.ones(3), np.zeros(3), np.zeros(3))
    assert float(dist) == pytest.approx(np.sqrt(3.0), abs=1e-15)
    np.testing.assert_allclose(normal, np.ones(3) / np.sqrt(3.0), atol=1e-15)
    # a capsule obstacle that is a sphere (from == to) against a link
    t, dist, normal = segment_to_axis(np.zeros(3), np.array([4.0, 0, 0]), np.array([1.0, 2, 0]), np.array([1.0, 2, 0]))
    assert float(t) == pytest.approx(0.25, abs=1e-15) and float(dist) == pytest.approx(2.0, abs=1e-15)
    np.testing.assert_allclose(normal, [0.0, -1.0, 0.0], atol=1e-15)
    # segments that cross: distance 0, and a unit normal (no division by zero)
    t, dist, normal = segment_to_axis(np.array([-1.0, 0, 0]), np.array([1.0, 0, 0]), np.array([0.0, -1, 0]), np.array([0.0, 1, 0]))
    assert float(dist) == 0.0 and float(t) == pytest.approx(0.5) and float(np.linalg.norm(normal)) == pytest.approx(1.0)


def test_a_segment_through_a_box_is_found_inside_at_every_angle():
    # the least outside point of a segment that passes through a box lies on its surface,
    # where rounding puts it either side: its depth must be searched for, never read as 0
    rng = np.random.default_rng(11)
    for _ in range(300):
        center, half, rotation = random_box(rng)
        inside = center + rotation @ (rng.uniform(-0.9, 0.9, 3) * half)
        direction = rng.normal(size=3)
        a, b = inside - 3 * direction, inside + 3 * direction * rng.uniform(0.5, 1.5)
        t, dist, normal = segment_box(a, b, center, half, rotation)
        point = (a + t * (b - a) - center) @ rotation
        assert float(dist) < 0 and float(dist) == pytest.approx(float(box_signed_distance(point, half)), abs=1e-12)
        depth = box_signed_distance((inside - center) @ rotation, half)
        assert float(dist) <= float(depth) + 1e-12  # at least as deep as the point it passes through


def sample_box_surface(center, half, rotation, per_edge=41):
    """Points on the six faces of a box (a grid per face), world."""
    g = np.linspace(-1.0, 1.0, per_edge)
    u, v = np.meshgrid(g, g)
    faces = []
    for axis in range(3):
        others = [k for k in range(3) if k != axis]
        for sign in (-1.0, 1.0):
            local = np.zeros(u.shape + (3,))
            local[..., axis] = sign * half[axis]
            local[..., others[0]] = u * half[others[0]]
            local[..., others[1]] = v * half[others[1]]
            faces.append(local.reshape(-1, 3))
    return center + np.concatenate(faces) @ rotation.T


def test_segment_box_against_surface_sampling():
    rng = np.random.default_rng(3)
    edge, along = 25, 401  # samples per box edge and along the segment
    for _ in range(12):
        center, half, rotation = random_box(rng)
        a = center + rng.normal(size=3) * 1.5
        b = a + rng.normal(size=3)
        t, dist, normal = segment_box(a, b, center, half, rotation)
        points = a + np.linspace(0, 1, along)[:, None] * (b - a)
        sdf = box_signed_distance((points - center) @ rotation, half)
        step = np.linalg.norm(b - a) / (along - 1)
        assert dist <= sdf.min() + 1e-12  # ours is the least (sampling can only miss it)
        assert sdf.min() - dist < step + 1e-12
        if dist > 0:
            surface = sample_box_surface(center, half, rotation, edge)
            gaps = np.sqrt(((points[:, None, :] - surface[None, :, :]) ** 2).sum(axis=-1)).min()
            assert dist <= gaps + 1e-12 and gaps - dist < 2 * np.linalg.norm(half) / (edge - 1) + step


def test_inside_a_box_is_negative_the_deepest_point():
    half = np.array([1.0, 2.0, 3.0])
    # a point inside: minus its distance to the nearest face, the normal out of that face
    t, dist, normal = segment_box(np.array([0.5, 0, 0]), np.array([0.5, 0, 0]), np.zeros(3), half, np.eye(3))
    assert float(dist) == -0.5 and normal.tolist() == [1.0, 0.0, 0.0]
    # a segment through the box: its deepest points (depth 1, all of |z| <= 2: t in [0.3, 0.7])
    t, dist, normal = segment_box(np.array([0.0, 0, -5]), np.array([0.0, 0, 5]), np.zeros(3), half, np.eye(3))
    assert 0.3 <= float(t) <= 0.7 and float(dist) == -1.0


def test_box_normal_is_the_gradient_of_the_distance():
    rng = np.random.default_rng(5)
    center, half, rotation = random_box(rng)
    for _ in range(30):
        p = center + rng.normal(size=3) * 1.5
        t, dist, normal = segment_box(p, p, center, half, rotation)
        h = 1e-6
        grad = [(segment_box(p + h * e, p + h * e, center, half, rotation)[1] - segment_box(p - h * e, p - h * e, center, half, rotation)[1]) / (2 * h) for e in np.eye(3)]
        if abs(dist) > 1e-3:
            np.testing.assert_allclose(grad, normal, atol=1e-5)


def mixed_obstacles(floor=0.0) -> Obstacles:
    boxes = Boxes(np.array([[8.0, 5, 3], [3.0, 2, 6]]), np.array([[1.0, 2, 0.5], [0.5, 0.5, 0.5]]),
                  np.stack([rpy_rotation([0.2, 0.1, 0.5]), np.eye(3)]))
    rods = Rods(np.array([[2.0, 8, 0]]), np.array([[2.0, 8, 6]]), np.array([0.3]))
    kinds = np.array([BOX, SPHERE, ROD, BOX, FLOOR])
    return Obstacles(np.array([[9.0, 9, 9]]), np.array([1.0]), np.array([0.5, 1, 0.3, 0.25, 0.0]), boxes, rods, floor, kinds)


def test_clearances_columns_follow_the_scene_and_batch():
    arm = Arm.from_names([2, 5, 5, 5], base=(5, 5, 0))
    caps = joint_capsules(arm, 0.25)
    obstacles = mixed_obstacles()
    phi = np.random.default_rng(0).uniform(-2, 2, (6, 4))
    batch = clearances(forward(arm, phi), obstacles, caps)
    assert batch.d.shape == (6, 5, 5) and batch.normal.shape == (6, 5, 5, 3)
    for k in range(6):
        one = clearances(forward(arm, phi[k]), obstacles, caps)
        np.testing.assert_array_equal(one.d, batch.d[k])
    pose = forward(arm, phi[0])
    spheres = clearances(pose, Obstacles(obstacles.centers, obstacles.radii, np.ones(1)), caps)
    np.testing.assert_array_equal(batch.d[0][:, 1], spheres.d[:, 0])
    # the floor: the first link (it stands on the base) is left out, the others are measured from their lower end
    assert batch.d[0, 0, 4] == np.inf
    lower = np.minimum(pose.points[1:-1, 2], pose.points[2:, 2]) - 0.25
    np.testing.assert_allclose(batch.d[0, 1:4, 4], lower)
    assert batch.d[0, 4, 4] == pose.tip[2]


def test_spheres_only_clearances_are_the_old_ones():
    arm = Arm.from_names([2, 5, 5, 5], base=(5, 5, 0))
    caps = joint_capsules(arm, 0.25)
    obstacles = Obstacles(np.array([[9.0, 9, 9], [3, 3, 3]]), np.array([1.0, 0.0]), np.array([1.0, 1.0]))
    pose = forward(arm, np.array([0.3, 0.4, -0.5, 0.6]))
    cl = clearances(pose, obstacles, caps)
    tip = pose.points[-1:]
    ref = sphere_clearances(np.concatenate([pose.points[:-1], tip]), np.concatenate([pose.points[1:], tip]), np.append(caps.radius, 0.0), obstacles)
    np.testing.assert_array_equal(cl.d, ref.d)


@pytest.mark.parametrize("column", [0, 2, 3, 4])
def test_jacobian_rows_match_finite_differences(column):
    """n . J_q (the filter's row, the cost's gradient) is the derivative of the clearance."""
    arm = Arm.from_names([2, 5, 5, 5], base=(5, 5, 0))
    caps = joint_capsules(arm, 0.25)
    obstacles = mixed_obstacles()
    rng = np.random.default_rng(column)
    checked = 0
    for _ in range(40):
        phi = rng.uniform(-2, 2, 4)
        pose = forward(arm, phi)
        cl = clearances(pose, obstacles, caps)
        for part in range(1, 4):
            if not 0.05 < cl.d[part, column] < 5:
                continue
            row = cl.normal[part, column] @ capsule_point_jacobian(arm, caps, pose, part, cl.t[part, column])
            h = 1e-6
            numeric = [(clearances(forward(arm, phi + h * e), obstacles, caps).d[part, column]
                        - clearances(forward(arm, phi - h * e), obstacles, caps).d[part, column]) / (2 * h) for e in np.eye(4)]
            np.testing.assert_allclose(row, numeric, atol=2e-5)
            checked += 1
    assert checked >= 5


def test_point_clearances():
    obstacles = mixed_obstacles(floor=-1.0)
    d = point_clearances(np.array([[8.0, 5, 6], [2.0, 8, 3]]), obstacles)
    assert d.shape == (2, 5)
    assert d[1, 2] == pytest.approx(-0.3)  # on the post's axis: inside by its radius
    assert d[0, 4] == 7.0


# --- the scene's shape forms and their checks --------------------------------------------

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


@pytest.mark.parametrize("line, new, field, fragment", [
    (S["box"], "  - box: {center: [4, -4, 1], size: [1, 0, 2]}", "obstacles[1].box.size[1]", "must be > 0 (got 0)"),
    (S["capsule"], "  - capsule: {from: [-4, 0, 0], to: [-4, 0, 3], radius: -0.5}", "obstacles[2].capsule.radius", "must be > 0"),
    (S["box"], "  - box: {center: [4, -4, 1], size: [1, 2, 2], rpy: [0, .nan, 0]}", "obstacles[1].box.rpy[1]", "finite"),
    (S["box"], "  - box: {center: [4, -4, 1], size: [1, 2, 2], rpy: [0, 400, 0]}", "obstacles[1].box.rpy[1]", "<= 360"),
    (S["box"], "  - {box: {center: [4, -4, 1], size: [1, 2, 2]}, radius: 1}", "obstacles[1]", "a sphere, which needs a center"),
    (S["box"], "  - {box: {center: [4, -4, 1], size: [1, 2, 2]}, center: [1, 1, 1], radius: 1}", "obstacles[1]", "got center and box"),
    (S["box"], "  - box: {center: [4, -4, 1], sizes: [1, 2, 2]}", "obstacles[1].box.sizes", "did you mean 'size'"),
    (S["floor"], "floor: 0.5", "floor", "above the arm's base"),
    (S["floor"], "floor: 3.9", "floor", "above the arm's base"),
])
def test_shape_fields_are_checked(scene_rejected, line, new, field, fragment):
    from test_scene import edit

    scene_rejected(edit(line, new, SHAPES), field, line, fragment)


def test_home_and_goals_clear_of_every_shape(scene_rejected):
    from test_scene import edit

    # the home pose (straight up along z from the origin) inside a box, closer than the clearance to a capsule
    scene_rejected(edit(S["box"], "  - box: {center: [0, 0, 4], size: [1, 1, 1]}", SHAPES), "obstacles[1]", S["box"], "home pose is inside this obstacle")
    scene_rejected(edit(S["capsule"], "  - capsule: {from: [0.3, -1, 0], to: [0.3, 1, 9], radius: 0.04}", SHAPES), "obstacles[2]", S["capsule"], "closer to it than solver.clearance")
    scene_rejected(edit(S["goal0"], "  - [4, -4, 1.5]", SHAPES), "goals[0]", S["goal0"], "inside obstacles[1]")
    scene_rejected(edit(S["goal0"], "  - [-4, 0.6, 2]", SHAPES), "goals[0]", S["goal0"], "from the surface of obstacles[2]")
    scene_rejected(edit(S["goal0"], "  - [3, 2, -0.5]", SHAPES), "goals[0]", S["goal0"], "lies below the floor")
    scene_rejected(edit(S["goal0"], "  - [3, 2, 0.2]", SHAPES), "goals[0]", S["goal0"], "is 0.2 from the floor")
    # the home pose tilted so that link 3 dips into the floor (link 1 stands on the base: it may touch it)
    tilted = SHAPES.replace("  axes: [z, y, y]\n", "  axes: [z, y, y]\n  home: [0, 120, 0]\n")
    scene_rejected(tilted, "floor", S["floor"] + 1, "link 3 of the arm's home pose is inside the floor")


# --- the motion keeps every shape: the filter, the floor, the invariants --------------------


def notes_among(goals, boxes=(), rods=(), floor=None, method="pinv", planner="off"):
    """The notes' arm at the origin (straight up) among boxes (centre, size, rpy radians) and capsules."""
    from dataclasses import replace

    from strategies import with_floor
    from test_motion import notes_problem

    problem = notes_problem(goals=goals, method=method, planner=planner)
    kinds = [BOX] * len(boxes) + [ROD] * len(rods)
    obstacles = Obstacles(
        np.zeros((0, 3)), np.zeros(0), np.full(len(kinds), 0.5),
        Boxes(np.array([c for c, _, _ in boxes], float).reshape(-1, 3), np.array([s for _, s, _ in boxes], float).reshape(-1, 3) / 2,
              np.array([rpy_rotation(r) for _, _, r in boxes]).reshape(-1, 3, 3)),
        Rods(np.array([a for a, _, _ in rods], float).reshape(-1, 3), np.array([b for _, b, _ in rods], float).reshape(-1, 3),
             np.array([r for _, _, r in rods], float)),
        kinds=np.array(kinds, dtype=int),
    )
    return replace(problem, obstacles=with_floor(obstacles, floor))


@pytest.mark.parametrize("method", ["pinv", "dls"])
@pytest.mark.parametrize("rpy, goal", [((0.0, 0.0, 0.0), 9.0), ((0.0, 0.0, np.pi / 4), 10.0)], ids=["edge", "corner"])
def test_filter_slides_along_a_box_and_around_its_edge(method, rpy, goal):
    """Planner off: the arm comes down over a block, slides along its top face, round its far
    edge (or, the block turned 45 degrees, over its top's corners and round its vertical edge) and down its side to a goal beside it, never stopping."""
    problem = notes_among(((goal, 0.0, 1.0),), boxes=[((6.0, 0.0, 2.0), (4.0, 4.0, 4.0), rpy)], method=method)
    solution = solve_trajectory(problem)
    assert [g.reached for g in solution.goals] == [True]
    assert_trajectory_invariants(problem, solution)
    clearance = solution.trajectory.clearance
    assert clearance.min() >= problem.solver.clearance
    assert clearance.min() < 2 * problem.solver.clearance  # it did run along the surface


def test_filter_slides_instead_of_stopping_at_a_box_face():
    from armanim.motion.solvers.barrier import safe_step
    from armanim.motion.solvers.common import arm_state

    # a wall whose face is exactly solver.clearance (0.05) beyond the straight arm's capsules (radius 0.25)
    problem = notes_among(((7.0, 0.0, 9.0),), boxes=[((1.3, 0.0, 10.0), (2.0, 4.0, 8.0), (0.0, 0.0, 0.0))])
    state = arm_state(problem, problem.home)
    assert state.min_clearance == pytest.approx(0.05)
    sideways = safe_step(problem, state, np.array([0.2, 0.3, 0.0, 0.0]))  # into the wall, with a turn about the base
    assert sideways.blocked_by == "obstacle" and sideways.phi[0] > 0.1  # the free direction is kept
    assert sideways.state.min_clearance >= problem.solver.clearance


def test_goal_below_the_floor_is_missed_not_passed_through():
    problem = notes_among(((9.0, 0.0, -1.0),), floor=0.0, planner="auto")
    solution = solve_trajectory(problem)
    report = solution.goals[0]
    assert not report.reached and report.reason == "no_free_pose"
    pose = forward(problem.arm, solution.trajectory.phi)
    assert np.all(pose.points[:, 2:, 2] >= 0.25 + problem.solver.clearance - 1e-12)  # every joint past link 1 stayed above
    assert np.all(pose.tip[:, 2] >= problem.solver.clearance)


def test_floor_is_kept_with_the_planner_off():
    problem = notes_among(((12.0, 0.0, 0.6),), floor=0.0, method="dls")
    solution = solve_trajectory(problem)
    cl = clearances(forward(problem.arm, solution.trajectory.phi), problem.obstacles, problem.capsules)
    assert cl.d[..., -1].min() >= problem.solver.clearance


@given(shaped_problems(max_links=5, max_goals=2, max_frames=60))
@settings(max_examples=5)
def test_shaped_scene_trajectory_invariants(problem):
    # a goal with no path would spend the whole RRT budget
    assert_trajectory_invariants(problem, solve_trajectory(small_planning_budget(problem)))


# --- pictures ---------------------------------------------------------------------------------


def shelf_problem():
    from conftest import ROOT

    from armanim.scene import load_scene, scene_to_problem

    return scene_to_problem(load_scene(ROOT / "scenes" / "panda-shelf.yaml").model)


def test_goal_behind_a_box_is_drawn_through_it():
    from armanim.render.draw import SceneCanvas
    from armanim.scene import default_render_settings

    problem = shelf_problem()
    canvas = SceneCanvas(problem, default_render_settings(size=(96, 64)), title="t", extent=forward(problem.arm, problem.home).points)
    # goal 0 sits between the boards under the upper one; goal 1 shows under its front edge; 2 and 3 are above
    assert canvas.goals.hidden.tolist() == [True, False, False, False]
    assert canvas.shapes is not None and len(canvas.shapes.parts) == 2


def test_spheres_only_pictures_take_the_sphere_path():
    from test_cost import notes_problem

    from armanim.render.draw import SceneCanvas
    from armanim.scene import default_render_settings

    problem = notes_problem()
    assert SceneCanvas(problem, default_render_settings(size=(64, 48)), title="t").shapes is None


def test_poster_and_pose_of_every_shape(tmp_path):
    from armanim.render.draw import render_pose_png
    from armanim.render.poster import render_poster
    from armanim.scene import default_render_settings

    problem = notes_among(((9.0, 0.0, 1.0),), boxes=[((6.0, 0.0, 2.0), (4.0, 4.0, 4.0), (0.0, 0.0, 0.5))],
                          rods=[((-4.0, 0.0, 0.0), (-4.0, 0.0, 8.0), 0.5)], floor=-0.5)
    solution = solve_trajectory(problem)
    settings = default_render_settings(size=(64, 48))
    render_poster(problem, solution.trajectory, solution.goals, settings, tmp_path / "poster.png", title="shapes")
    render_pose_png(problem, problem.home, settings, tmp_path / "pose.png", title="shapes")
    assert (tmp_path / "poster.png").stat().st_size > 0 and (tmp_path / "pose.png").stat().st_size > 0


def test_viewer_data_carries_boxes_capsules_and_the_floor():
    from armanim.render.viewer.data import shape_entries, viewer_data
    from armanim.scene import default_render_settings

    problem = notes_among(((9.0, 0.0, 1.0),), boxes=[((6.0, 0.0, 2.0), (4.0, 4.0, 4.0), (0.0, 0.0, 0.5))],
                          rods=[((-4.0, 0.0, 0.0), (-4.0, 0.0, 8.0), 0.5)], floor=-0.5)
    solution = solve_trajectory(problem)
    data = viewer_data(problem, solution.trajectory, solution.goals, default_render_settings(size=(64, 48)), title="t")
    assert data["obstacles"] == [] and data["view"]["floor"]["z"] == -0.5
    (box,) = data["boxes"]
    assert box["size"] == [4.0, 4.0, 4.0] and box["influence"] == 0.5
    np.testing.assert_allclose(box["rotation"], rpy_rotation([0.0, 0.0, 0.5]))
    assert data["obstacle_capsules"] == [{"from": [-4.0, 0.0, 0.0], "to": [-4.0, 0.0, 8.0], "radius": 0.5, "influence": 0.5}]
    from test_cost import notes_problem

    assert shape_entries(notes_problem().obstacles) == {}  # spheres: the page's data as it always was


def test_smallest_clearance_is_the_least_of_all_clearances():
    """The pruned batch minimum (the planner's) equals the least of the full clearances."""
    from armanim.world.distances import min_link_clearance

    arm = Arm.from_names([2, 5, 5, 5], base=(5, 5, 0))
    caps = joint_capsules(arm, 0.25)
    obstacles = mixed_obstacles()
    phi = np.random.default_rng(4).uniform(-np.pi, np.pi, (500, 4))
    pose = forward(arm, phi)
    full = clearances(pose, obstacles, caps).links.min(axis=(-1, -2))
    np.testing.assert_allclose(min_link_clearance(pose, obstacles, caps), full, rtol=0, atol=1e-12)
    assert min_link_clearance(forward(arm, phi[0]), obstacles, caps).shape == ()


def test_a_shapes_run_is_byte_identical_in_two_processes():
    """ur5-table plans round its post: the same CSV bytes from a fresh process and from one
    that planned it once already (OMPL's random numbers must not leak between plans)."""
    import subprocess
    import sys

    from conftest import ROOT

    program = (
        "import sys\n"
        "from armanim.scene import load_scene, scene_to_problem\n"
        "from armanim.output.csvfile import trajectory_csv_text\n"
        "from armanim.motion.trajectory import solve_trajectory\n"
        "solve = lambda name: solve_trajectory(scene_to_problem(load_scene(sys.argv[1] + '/scenes/' + name + '.yaml').model))\n"
        "if sys.argv[2] == 'warm':\n"
        "    solve('ur5-table')\n"
        "print(trajectory_csv_text(solve('ur5-table').trajectory), end='')\n"
    )
    runs = [subprocess.run([sys.executable, "-c", program, str(ROOT), how], capture_output=True, text=True, check=True)
            for how in ("cold", "warm")]
    assert ",plan" in runs[0].stdout
    assert runs[0].stdout == runs[1].stdout


def test_boxes_are_measured_where_numba_finds_no_folder_to_cache_in():
    """A read-only install run by a user with no writable home leaves numba no cache folder:
    it refuses ``cache=True`` there, and the closed form must compile in memory instead of
    every box scene ending in a traceback."""
    import subprocess
    import sys

    program = (
        "import numba.core.caching as caching\n"
        "impl = getattr(caching, 'CacheImpl', None) or caching._CacheImpl  # its name in numba >= 0.61, before\n"
        "impl._locator_classes = []  # as numba finds none: no writable folder\n"
        "import numpy as np\n"
        "from armanim.world.closest import segment_box\n"
        "t, d, n = segment_box(np.array([3.0, 0, 0]), np.array([0.0, 0, 3]), np.zeros(3), np.ones(3), np.eye(3))\n"
        "print(float(t), round(float(d) ** 2, 12))\n"
    )
    proc = subprocess.run([sys.executable, "-c", program], capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.split() == ["0.5", "0.5"]


def random_shapes(rng, boxes=3, rods=2, floor=True) -> Obstacles:
    """Boxes, capsules, a sphere and a floor about the notes' arm (base (5, 5, 0), 17 long)."""
    centers = rng.uniform([-2, -2, 0], [12, 12, 14], (boxes, 3))
    box = Boxes(centers, rng.uniform(0.05, 2.5, (boxes, 3)), np.stack([rpy_rotation(rng.uniform(-np.pi, np.pi, 3)) for _ in range(boxes)]))
    start = rng.uniform([-2, -2, 0], [12, 12, 14], (rods, 3))
    rod = Rods(start, start + rng.normal(size=(rods, 3)) * rng.choice([0.0, 3.0], (rods, 1)), rng.uniform(0.05, 1.0, rods))
    kinds = rng.permutation(np.repeat([BOX, ROD, SPHERE], [boxes, rods, 1]))
    kinds = np.append(kinds, FLOOR) if floor else kinds
    influence = np.where(kinds == FLOOR, 0.0, rng.uniform(0.1, 4.0, len(kinds)))
    return Obstacles(rng.uniform(0, 10, (1, 3)), rng.uniform(0, 1, 1), influence, box, rod, -1.0 if floor else None, kinds)


@pytest.mark.parametrize("seed", range(6))
def test_a_pairs_numbers_do_not_depend_on_its_batch(seed):
    """The planner measures the pairs its bounds leave in doubt (``solid_pairs``), the frame
    every pair of one pose (``solid_clearances``): each pair has the same numbers, bit for bit,
    whichever way and in whatever batch it is computed."""
    from armanim.arm.capsules import capsule_ends
    from armanim.world.distances import solid_clearances, solid_pairs

    rng = np.random.default_rng([22, seed])
    arm = Arm.from_names(list(rng.uniform(1, 6, rng.integers(3, 7))), base=(5, 5, 0))
    caps = joint_capsules(arm, rng.uniform(0.05, 0.5))
    obstacles = random_shapes(rng, floor=bool(seed % 2))
    phi = rng.uniform(-np.pi, np.pi, (40, arm.n))
    a, b = capsule_ends(caps, forward(arm, phi))
    tip = forward(arm, phi).points[..., -1:, :]  # as clearances lays the parts out: the capsules, then the tip
    a, b = np.concatenate([a, tip], axis=-2), np.concatenate([b, tip], axis=-2)
    grid = solid_clearances(a, b, caps.part_radius, obstacles)
    where = np.nonzero(rng.random(grid[0].shape) < 0.3)
    picked = solid_pairs(a, b, caps.part_radius, obstacles, where)
    capsule = where[1] < len(caps)  # the tip's t is set to 1 by solid_clearances alone
    for n, (together, alone) in enumerate(zip(grid, picked)):
        keep = capsule if n == 1 else slice(None)
        np.testing.assert_array_equal(together[where][keep], alone[keep])
    for k in (0, 17, 39):  # one pose alone: its rows of the batch
        one = solid_clearances(a[k], b[k], caps.part_radius, obstacles)
        for together, alone in zip(grid, one):
            np.testing.assert_array_equal(together[k], alone)


@pytest.mark.parametrize("seed", range(4))
def test_solid_bounds_hold_the_exact_clearance_between_them(seed):
    """The planner and the line search trust these bounds to leave pairs out: every exact
    capsule clearance lies between them (batches of random arms, boxes, capsules and poses,
    boxes crossed by links included)."""
    from armanim.arm.capsules import capsule_ends
    from armanim.world.distances import solid_bounds, solid_clearances

    rng = np.random.default_rng([2205, seed])
    arm = Arm.from_names(list(rng.uniform(1, 6, rng.integers(3, 7))), base=(5, 5, 0))
    caps = joint_capsules(arm, rng.uniform(0.05, 0.5))
    obstacles = random_shapes(rng, floor=False)
    a, b = capsule_ends(caps, forward(arm, rng.uniform(-np.pi, np.pi, (300, arm.n))))
    low, high = solid_bounds(a, b, caps.radius, obstacles)
    tip = np.zeros(a.shape[:-2] + (1, 3))  # solid_clearances takes the parts with the tip last
    exact = solid_clearances(np.concatenate([a, tip], -2), np.concatenate([b, tip], -2), np.append(caps.radius, 0.0), obstacles)[0][..., :-1, :]
    assert np.all(low <= exact + 1e-12) and np.all(exact <= high + 1e-12)
    assert np.mean(high - low) > 0  # the bounds are not all tight
    # a link through a box: its clearance is negative, and still between the bounds
    middle = 0.5 * (a[0, 1] + b[0, 1])
    crossed = Obstacles(np.zeros((0, 3)), np.zeros(0), np.ones(1), Boxes(middle[None], np.full((1, 3), 0.2), np.eye(3)[None]))
    low, high = solid_bounds(a[0], b[0], caps.radius, crossed)
    exact = solid_clearances(a[0], b[0], caps.radius, crossed)[0]
    assert exact[1, 0] < 0 and np.all(low <= exact + 1e-12) and np.all(exact <= high + 1e-12)


def test_clearances_match_coal():
    """Every box and capsule-obstacle clearance of a pose is coal's distance too (where the part is clear)."""
    rng = np.random.default_rng(2212)
    arm = Arm.from_names([2, 5, 5, 5], base=(5, 5, 0))
    caps = joint_capsules(arm, 0.25)
    obstacles = random_shapes(rng, floor=False)
    boxes, rods = obstacles.boxes, obstacles.rods
    compared = 0
    for phi in rng.uniform(-np.pi, np.pi, (30, 4)):
        pose = forward(arm, phi)
        cl = clearances(pose, obstacles, caps)
        for column, kind in enumerate(obstacles.kinds):
            if kind not in (BOX, ROD):
                continue
            k = int(np.nonzero(obstacles.columns(kind) == column)[0][0])
            shape = (coal.Box(*(2 * boxes.half[k])), coal.Transform3s(boxes.rotations[k], boxes.centers[k])) if kind == BOX else \
                coal_capsule(rods.start[k], rods.end[k], float(rods.radius[k])) if np.any(rods.start[k] != rods.end[k]) else None
            for part in range(4):
                d = cl.d[part, column]
                if shape is None or not 1e-3 < d < np.inf:
                    continue
                a, b = pose.points[part], pose.points[part + 1]
                expected, _ = coal_distance(*shape, *coal_capsule(a, b, 0.25))
                assert abs(d - expected) < 1e-9
                compared += 1
    assert compared > 20
