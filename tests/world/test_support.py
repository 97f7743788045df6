"""A carried solid's own distance to its support (issue 54): the box-box, sphere-box and
capsule-box distances against coal, and a cylinder's (the box round it) never above coal's."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from armanim.arm.rotations import quaternion_rotation
from armanim.world.carried import Body
from armanim.world.obstacles import BOX, CYLINDER, ROD, SPHERE
from armanim.world.support import box_box_distance, solid_box_distance

coal = pytest.importorskip("coal")


def _coal(body: Body):
    shape = {BOX: lambda: coal.Box(*(2 * body.half)), SPHERE: lambda: coal.Sphere(body.radius),
             ROD: lambda: coal.Capsule(body.radius, 2 * body.half[0]), CYLINDER: lambda: coal.Cylinder(body.radius, 2 * body.half[2])}[body.kind]()
    rotation = body.rotation if body.kind != ROD else body.rotation @ np.array([[0, 0, 1], [0, 1, 0], [-1, 0, 0.0]])  # coal's capsule along z
    return shape, coal.Transform3s(rotation, body.center)


def _coal_distance(one: Body, two: Body) -> float:
    return float(coal.distance(*_coal(one), *_coal(two), coal.DistanceRequest(), coal.DistanceResult()))


def _rotation(q) -> np.ndarray:
    q = np.asarray(q, dtype=float)
    return quaternion_rotation(q / np.linalg.norm(q)) if np.linalg.norm(q) > 1e-3 else np.eye(3)


sizes = st.lists(st.floats(0.005, 0.3), min_size=3, max_size=3)
quaternions = st.lists(st.floats(-1, 1), min_size=4, max_size=4)
offsets = st.lists(st.floats(-0.5, 0.5), min_size=3, max_size=3)


@settings(max_examples=300, deadline=None)
@given(sizes, quaternions, sizes, quaternions, offsets)
@example([0.02, 0.02, 0.02], [1, 0, 0, 0], [0.2, 0.2, 0.01], [1, 0, 0, 0], [0.05, 0.0, 0.03])  # a cube on a board: 0
@example([0.02, 0.02, 0.02], [1, 0, 0, 0], [0.2, 0.2, 0.01], [1, 0, 0, 0], [0.05, 0.0, 0.025])  # pushed 5 mm in
@example([0.1, 0.1, 0.1], [1, 0, 0, 0], [0.1, 0.1, 0.1], [0.9, 0.3, 0.1, 0.2], [0.25, 0.21, 0.0])  # edge against edge
def test_box_box_distance_is_coal_s(half_a, qa, half_b, qb, offset):
    """Apart, touching or overlapping (coal's signed distance: minus the penetration depth)."""
    a = Body(BOX, _rotation(qa), np.zeros(3), np.array(half_a))
    b = Body(BOX, _rotation(qb), np.array(offset), np.array(half_b))
    ours, theirs = box_box_distance(a, b), _coal_distance(a, b)
    assert ours == pytest.approx(theirs, abs=1e-6 + 1e-4 * abs(theirs))
    assert box_box_distance(b, a) == pytest.approx(ours, abs=1e-12)


@settings(max_examples=150, deadline=None)
@given(st.sampled_from([SPHERE, ROD, CYLINDER]), sizes, quaternions, sizes, offsets)
def test_a_round_solid_s_distance_to_a_box(kind, dims, q, half, offset):
    """A sphere and a capsule: coal's distance apart, and overlapping exactly where coal says so (a
    sphere: by coal's depth); a cylinder: the box round it, never above coal's distance of the
    cylinder itself."""
    body = Body(kind, _rotation(q), np.array(offset), np.array([dims[0], 0.0, dims[0]]), dims[1])
    box = Body(BOX, np.eye(3), np.zeros(3), np.array(half))
    ours, theirs = solid_box_distance(body, box), _coal_distance(body, box)
    if kind == CYLINDER:
        assert ours <= theirs + 1e-6
    elif theirs > 1e-6 or kind == SPHERE:
        assert ours == pytest.approx(theirs, abs=1e-6 + 1e-4 * abs(theirs))
    else:  # a capsule in the box: its axis' deepest point's depth less the radius, of coal's sign
        assert ours <= 1e-6 and (ours < -1e-6) == (theirs < -1e-6)


def test_a_cylinder_standing_on_a_board_touches_it_and_one_pushed_in_does_not():
    board = Body(BOX, np.eye(3), np.zeros(3), np.array([0.2, 0.2, 0.01]))
    for gap in (0.0, -0.005, 0.01):
        can = Body(CYLINDER, np.eye(3), np.array([0.03, -0.02, 0.01 + 0.03 + gap]), np.array([0.0, 0.0, 0.03]), 0.02)
        assert solid_box_distance(can, board) == pytest.approx(gap, abs=1e-12)
        assert _coal_distance(can, board) == pytest.approx(gap, abs=1e-6)
