"""Boxes, capsules and a floor: exact distances (against coal and brute force) and their
Jacobian rows (the scene's shape forms: tests/scene/test_shape_forms.py; the motion among them:
tests/motion/test_motion_among_shapes.py; their pictures: tests/render/test_shape_pictures.py)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from armanim.arm.capsules import capsule_point_jacobian, joint_capsules
from armanim.arm.chain import rpy_rotation
from armanim.arm.kinematics import Arm, forward
from armanim.world.closest import segment_box
from armanim.world.distances import clearances, point_clearances, sphere_clearances
from armanim.world.obstacles import BOX, FLOOR, ROD, SPHERE, Boxes, Cylinders, Obstacles, Rods

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
    t, dist, normal = segment_to_axis(
        np.array([-1.0, 0, 0]), np.array([1.0, 0, 0]), np.array([0.0, -1, 0]), np.array([0.0, 1, 0])
    )
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
        grad = [
            (
                segment_box(p + h * e, p + h * e, center, half, rotation)[1]
                - segment_box(p - h * e, p - h * e, center, half, rotation)[1]
            )
            / (2 * h)
            for e in np.eye(3)
        ]
        if abs(dist) > 1e-3:
            np.testing.assert_allclose(grad, normal, atol=1e-5)


def mixed_obstacles(floor=0.0) -> Obstacles:
    boxes = Boxes(
        np.array([[8.0, 5, 3], [3.0, 2, 6]]),
        np.array([[1.0, 2, 0.5], [0.5, 0.5, 0.5]]),
        np.stack([rpy_rotation([0.2, 0.1, 0.5]), np.eye(3)]),
    )
    rods = Rods(np.array([[2.0, 8, 0]]), np.array([[2.0, 8, 6]]), np.array([0.3]))
    kinds = np.array([BOX, SPHERE, ROD, BOX, FLOOR])
    return Obstacles(
        np.array([[9.0, 9, 9]]), np.array([1.0]), np.array([0.5, 1, 0.3, 0.25, 0.0]), boxes, rods, floor, kinds
    )


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
    ref = sphere_clearances(
        np.concatenate([pose.points[:-1], tip]),
        np.concatenate([pose.points[1:], tip]),
        np.append(caps.radius, 0.0),
        obstacles,
    )
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
            numeric = [
                (
                    clearances(forward(arm, phi + h * e), obstacles, caps).d[part, column]
                    - clearances(forward(arm, phi - h * e), obstacles, caps).d[part, column]
                )
                / (2 * h)
                for e in np.eye(4)
            ]
            np.testing.assert_allclose(row, numeric, atol=2e-5)
            checked += 1
    assert checked >= 5


def test_point_clearances():
    obstacles = mixed_obstacles(floor=-1.0)
    d = point_clearances(np.array([[8.0, 5, 6], [2.0, 8, 3]]), obstacles)
    assert d.shape == (2, 5)
    assert d[1, 2] == pytest.approx(-0.3)  # on the post's axis: inside by its radius
    assert d[0, 4] == 7.0


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


def test_the_least_clearance_of_a_batch_is_the_same_bytes_taken_in_chunks(monkeypatch):
    """A clocked run's frames are measured CLEARANCE_CHUNK at a time (the caches): each frame's
    number is the very one of the whole batch at once (trajectory.csv writes every digit)."""
    from armanim.world import distances

    arm = Arm.from_names([2, 5, 5, 5], base=(5, 5, 0))
    caps = joint_capsules(arm, 0.25)
    rng = np.random.default_rng(12)
    cylinders = Cylinders(
        rng.uniform(0, 12, (3, 3)),
        np.array([rpy_rotation(rng.uniform(-np.pi, np.pi, 3)) for _ in range(3)]),
        rng.uniform(0.5, 2.0, 3),
        rng.uniform(0.2, 1.0, 3),
    )
    obstacles = replace(mixed_obstacles(floor=-1.0), cylinders=cylinders)
    pose = forward(arm, rng.uniform(-np.pi, np.pi, (3 * distances.CLEARANCE_CHUNK + 7, 4)))
    chunked = distances.min_link_clearance(pose, obstacles, caps)
    monkeypatch.setattr(distances, "CLEARANCE_CHUNK", 10**9)
    whole = distances.min_link_clearance(pose, obstacles, caps)
    assert chunked.tobytes() == whole.tobytes() and np.sum(whole < 0) > 10


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
    box = Boxes(
        centers,
        rng.uniform(0.05, 2.5, (boxes, 3)),
        np.stack([rpy_rotation(rng.uniform(-np.pi, np.pi, 3)) for _ in range(boxes)]),
    )
    start = rng.uniform([-2, -2, 0], [12, 12, 14], (rods, 3))
    rod = Rods(
        start, start + rng.normal(size=(rods, 3)) * rng.choice([0.0, 3.0], (rods, 1)), rng.uniform(0.05, 1.0, rods)
    )
    kinds = rng.permutation(np.repeat([BOX, ROD, SPHERE], [boxes, rods, 1]))
    kinds = np.append(kinds, FLOOR) if floor else kinds
    influence = np.where(kinds == FLOOR, 0.0, rng.uniform(0.1, 4.0, len(kinds)))
    return Obstacles(
        rng.uniform(0, 10, (1, 3)), rng.uniform(0, 1, 1), influence, box, rod, -1.0 if floor else None, kinds
    )


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
    exact = solid_clearances(
        np.concatenate([a, tip], -2), np.concatenate([b, tip], -2), np.append(caps.radius, 0.0), obstacles
    )[0][..., :-1, :]
    assert np.all(low <= exact + 1e-12) and np.all(exact <= high + 1e-12)
    assert np.mean(high - low) > 0  # the bounds are not all tight
    # a link through a box: its clearance is negative, and still between the bounds
    middle = 0.5 * (a[0, 1] + b[0, 1])
    crossed = Obstacles(
        np.zeros((0, 3)), np.zeros(0), np.ones(1), Boxes(middle[None], np.full((1, 3), 0.2), np.eye(3)[None])
    )
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
            shape = (
                (coal.Box(*(2 * boxes.half[k])), coal.Transform3s(boxes.rotations[k], boxes.centers[k]))
                if kind == BOX
                else coal_capsule(rods.start[k], rods.end[k], float(rods.radius[k]))
                if np.any(rods.start[k] != rods.end[k])
                else None
            )
            for part in range(4):
                d = cl.d[part, column]
                if shape is None or not 1e-3 < d < np.inf:
                    continue
                a, b = pose.points[part], pose.points[part + 1]
                expected, _ = coal_distance(*shape, *coal_capsule(a, b, 0.25))
                assert abs(d - expected) < 1e-9
                compared += 1
    assert compared > 20
