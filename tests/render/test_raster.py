"""The z-buffer rasteriser (issue 38) against closed forms: a triangle covers its area, a mesh
has no holes and no double-drawn edge, the nearer surface wins whatever the order, colours
interpolate, and a rerun draws the same bytes."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from armanim.render.solids.raster import triangle_sprite


def _cross(a: np.ndarray, b: np.ndarray) -> float:
    return float(a[0] * b[1] - a[1] * b[0])


def _cover(sprite) -> np.ndarray:
    return 1.0 - sprite[3][..., 0].astype(float)


@settings(max_examples=60, deadline=None)
@given(points=st.lists(st.tuples(st.floats(2, 60), st.floats(2, 40)), min_size=3, max_size=3))
def test_a_triangle_covers_its_area(points):
    """Summed cover is the triangle's area, to the samples' resolution along its outline."""
    xy = np.array(points)
    area = 0.5 * abs(_cross(xy[1] - xy[0], xy[2] - xy[0]))
    pts = np.column_stack([xy, np.zeros(3)])
    sprite = triangle_sprite(pts, np.array([[0, 1, 2]]), np.ones((3, 3)), (64, 48), ss=4)
    perimeter = sum(np.linalg.norm(xy[k] - xy[k - 1]) for k in range(3))
    covered = 0.0 if sprite is None else _cover(sprite).sum()
    assert abs(covered - area) <= perimeter / 4 + 1.0


@settings(max_examples=40, deadline=None)
@given(sides=st.integers(3, 12), seed=st.integers(0, 10**6))
def test_a_fan_has_no_hole_and_no_edge_drawn_twice(sides, seed):
    """A convex polygon cut into a fan of triangles: every pixel wholly inside it is covered
    exactly once (cover 1, a single colour), its summed cover is its area."""
    rng = np.random.default_rng(seed)
    angles = (
        (np.arange(sides) + rng.uniform(-0.2, 0.2, sides)) * 2 * np.pi / sides
    )  # gaps under 180 degrees: the centre is inside
    radius = rng.uniform(8, 20)
    centre = np.array([32.0, 24.0]) + rng.uniform(-3, 3, 2)
    ring = centre + radius * np.column_stack([np.cos(angles), np.sin(angles)])
    pts = np.column_stack([np.vstack([centre, ring]), np.zeros(sides + 1)])
    faces = np.array([[0, 1 + k, 1 + (k + 1) % sides] for k in range(sides)])
    rows, cols, premultiplied, clear = triangle_sprite(pts, faces, np.ones((sides + 1, 3)), (64, 48), ss=2)
    cover = 1.0 - clear[..., 0]
    assert cover.max() <= 1.0 + 1e-6 and premultiplied.max() <= 255.0 + 1e-3
    area = 0.5 * abs(sum(_cross(ring[k], ring[(k + 1) % sides]) for k in range(sides)))
    perimeter = sum(np.linalg.norm(ring[k] - ring[k - 1]) for k in range(sides))
    assert abs(cover.sum() - area) <= perimeter / 2 + 1.0
    ys = 48 - (np.arange(rows.start, rows.stop) + 0.5)  # pixel centres, y up
    xs = np.arange(cols.start, cols.stop) + 0.5
    gx, gy = np.meshgrid(xs, ys)
    deep = np.ones_like(gx, dtype=bool)  # pixels whose whole square lies inside the polygon
    for k in range(sides):
        a, b = ring[k], ring[(k + 1) % sides]
        normal = np.array([b[1] - a[1], a[0] - b[0]]) / np.linalg.norm(b - a)
        inward = -np.sign(normal @ (centre - a)) * normal
        deep &= ((np.stack([gx, gy], -1) - a) @ -inward) >= 0.75
    assert np.all(cover[deep] == 1.0)


def test_the_nearer_surface_wins_whatever_the_order():
    square = np.array([[4.0, 4, 0], [20, 4, 0], [20, 20, 0], [4, 20, 0]])
    near = square + [6, 6, 1.0]
    pts = np.vstack([square, near])
    rgb = np.array([[1.0, 0, 0]] * 4 + [[0, 0, 1.0]] * 4)
    faces = np.array([[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]])
    one = triangle_sprite(pts, faces, rgb, (32, 32))
    other = triangle_sprite(pts, faces[::-1], rgb, (32, 32))
    assert all(np.array_equal(a, b) for a, b in zip(one[2:], other[2:])) and one[:2] == other[:2]
    rows, cols, premultiplied, _ = one
    overlap = premultiplied[32 - 18 - rows.start, 15 - cols.start]  # pixel (15, 17): both squares there
    assert overlap[2] == 255.0 and overlap[0] == 0.0


def test_colours_interpolate_across_a_triangle():
    pts = np.array([[0.0, 0, 0], [60, 0, 0], [0, 60, 0]])
    rgb = np.eye(3)
    rows, cols, premultiplied, clear = triangle_sprite(pts, np.array([[0, 1, 2]]), rgb, (64, 64))
    at = premultiplied[64 - 20 - 1 - rows.start, 20 - cols.start] / 255.0  # the pixel at (20.5, 20.5)
    assert np.allclose(at, [1 - 41 / 60, 20.5 / 60, 20.5 / 60], atol=0.02)
    again = triangle_sprite(pts, np.array([[0, 1, 2]]), rgb, (64, 64))
    assert again[2].tobytes() == premultiplied.tobytes() and again[3].tobytes() == clear.tobytes()


def test_triangles_outside_the_frame_draw_nothing():
    pts = np.array([[-20.0, -20, 0], [-5, -20, 0], [-5, -5, 0]])
    assert triangle_sprite(pts, np.array([[0, 1, 2]]), np.ones((3, 3)), (32, 32)) is None
    assert triangle_sprite(pts, np.zeros((0, 3), dtype=int), np.ones((3, 3)), (32, 32)) is None


def test_drawing_into_the_frame_is_compositing_the_sprite():
    from armanim.render.paint.pixels import composite
    from armanim.render.solids.raster import draw_triangles

    rng = np.random.default_rng(5)
    pts = np.column_stack([rng.uniform(0, 40, (30, 2)), rng.uniform(-1, 1, 30)])
    faces = rng.integers(0, 30, (20, 3))
    rgb = rng.uniform(0, 1, (30, 3))
    frame = rng.integers(0, 256, (32, 40, 4)).astype(np.uint8)
    direct, laid = frame.copy(), frame.copy()
    draw_triangles(direct, pts, faces, rgb)
    composite(laid, triangle_sprite(pts, faces, rgb, (40, 32)))
    assert np.abs(direct.astype(int) - laid.astype(int)).max() <= 1  # float32 samples against float64
    assert (direct != frame).any()


def test_an_outline_is_the_union_s_border_only():
    """Two triangles making a 20 x 20 square: its border pixels turn the outline's colour, the
    inside and the outside stay as they were."""
    from armanim.render.solids.raster import draw_outline

    square = np.array([[10.0, 10.0, 0.0], [30.0, 10.0, 0.0], [30.0, 30.0, 0.0], [10.0, 30.0, 0.0]])
    frame = np.full((40, 40, 4), 255, dtype=np.uint8)
    draw_outline(frame, square, np.array([[0, 1, 2], [0, 2, 3]]), (0.0, 0.0, 0.0), width=1, alpha=1.0)
    dark = frame[..., 0] == 0
    rows, cols = np.nonzero(dark)
    assert (rows.min(), rows.max(), cols.min(), cols.max()) == (10, 29, 10, 29)  # y up: rows 40 - 30 .. 40 - 10 - 1
    assert dark.sum() == 4 * 20 - 4  # the square's ring of pixels, nothing inside
    assert not dark[12:28, 12:28].any()


def test_a_still_layer_draws_what_filling_its_triangles_with_the_others_draws():
    """The furniture filled once and laid into each frame's z-buffer (StillLayer) gives the frame's
    bytes exactly: a sample's nearness and colour do not depend on the box it is filled in."""
    from armanim.render.solids.raster import StillLayer, draw_triangles

    rng = np.random.default_rng(11)
    pts = np.column_stack([rng.uniform(-5, 70, (40, 2)), rng.uniform(-1, 1, 40)])
    faces = rng.integers(0, 40, (30, 3))
    rgb = rng.uniform(0, 1, (40, 3))
    board = np.array([[10.3, 7.7, -0.2], [52.9, 9.1, 0.3], [47.2, 41.6, 0.1], [8.4, 38.8, -0.4]])
    pts = np.vstack([pts, board])
    still_faces = np.array([[40, 41, 42], [40, 42, 43]])
    frame = rng.integers(0, 256, (48, 64, 4)).astype(np.uint8)
    together, laid = frame.copy(), frame.copy()
    draw_triangles(together, pts, np.vstack([still_faces, faces]), rgb=np.vstack([rgb, np.full((4, 3), 0.8)]))
    draw_triangles(
        laid,
        pts,
        faces,
        np.vstack([rgb, np.full((4, 3), 0.8)]),
        still=StillLayer(pts, still_faces, np.vstack([rgb, np.full((4, 3), 0.8)]), (64, 48)),
    )
    assert (together != frame).any() and together.tobytes() == laid.tobytes()
    alone = frame.copy()  # the layer with no other triangle: the board by itself
    draw_triangles(
        alone,
        pts,
        np.zeros((0, 3), dtype=int),
        np.vstack([rgb, np.full((4, 3), 0.8)]),
        still=StillLayer(pts, still_faces, np.vstack([rgb, np.full((4, 3), 0.8)]), (64, 48)),
    )
    by_itself = frame.copy()
    draw_triangles(by_itself, pts, still_faces, np.vstack([rgb, np.full((4, 3), 0.8)]))
    assert alone.tobytes() == by_itself.tobytes()


@settings(max_examples=25, deadline=None)
@given(
    ends=st.lists(st.tuples(st.floats(20, 100), st.floats(20, 80)), min_size=2, max_size=8),
    radius=st.floats(3, 10),
)
def test_soft_strokes_are_matplotlib_s_round_capped_strokes(ends, radius):
    """The compiled strokes of the arm's shadow against matplotlib's Agg drawing the same segments
    (round caps, the shadow's two passes, each stroke over the last): every pixel within 6 levels
    of 255, the darkening summed over the frame within 6 % (Agg rounds the opacities to 1/255 and
    its round caps to polygons). The strokes inside the frame (matplotlib clips a line at the
    frame's edge before stroking it, which moves its cap there), and Agg unsnapped: it moves a
    stroke that runs along a row or a column by up to half a pixel onto the grid, which a floor's
    shadow seen from a camera above the floor practically never is. Strokes some pixels wide, as a
    shadow is (20-35 px at 960 x 540): a cover from the distance to the edge is the area's to a
    pixel's width, not for a stroke thinner than a pixel."""
    from matplotlib.collections import LineCollection

    from armanim.render.paint.pixels import in_pixels, make_figure
    from armanim.render.pictures.canvas import SHADOW_PASSES, SHADOW_RGB
    from armanim.render.solids.rasterloops import soft_strokes

    xy = np.array(ends, dtype=float)
    segments = np.stack([xy[:-1], xy[1:]], axis=1)
    segments = segments[np.hypot(*(segments[:, 1] - segments[:, 0]).T) > 0.01]  # (Agg leaves points out)
    radii = np.full(len(segments), radius) * np.linspace(1.0, 0.6, len(segments))
    fig, canvas = make_figure(120, 100, 100.0)
    renderer = canvas.get_renderer()
    fig.draw(renderer)
    blank = np.asarray(canvas.buffer_rgba()).copy()
    strokes = in_pixels(LineCollection(segments, color=SHADOW_RGB / 255.0, capstyle="round", snap=False), fig)
    for scale, alpha in SHADOW_PASSES:
        strokes.set_linewidth(2 * radii * scale * 72.0 / fig.dpi)
        strokes.set_alpha(alpha)
        strokes.draw(renderer)
    agg = np.asarray(canvas.buffer_rgba())[..., :3].astype(int)
    ours = blank.copy()
    soft_strokes(ours, segments, radii, SHADOW_PASSES, SHADOW_RGB)
    assert np.abs(ours[..., :3].astype(int) - agg).max() <= 6
    white = blank[..., :3].astype(float)
    assert abs((white - ours[..., :3]).sum() - (white - agg).sum()) <= 0.06 * (white - agg).sum() + 200


def test_a_stroke_of_no_length_is_a_disc_and_none_outside_the_frame_draws():
    """A segment whose ends meet strokes a disc of its radius; strokes off the frame leave it as it was."""
    from armanim.render.solids.rasterloops import soft_strokes

    frame = np.full((40, 40, 4), 255, dtype=np.uint8)
    soft_strokes(
        frame, np.array([[[200.0, 20.0], [260.0, 30.0]]]), np.array([5.0]), np.array([[1.0, 1.0]]), np.zeros(3)
    )
    assert (frame == 255).all()
    soft_strokes(frame, np.array([[[20.0, 20.0], [20.0, 20.0]]]), np.array([8.0]), np.array([[1.0, 1.0]]), np.zeros(3))
    dark = frame[..., 0] < 128
    assert abs(dark.sum() - np.pi * 64) <= 2 * np.pi * 8
    rows, cols = np.nonzero(dark)
    assert abs(rows.mean() - 19.5) < 0.1 and abs(cols.mean() - 19.5) < 0.1  # (the centre, y up, at pixel 20)


@settings(max_examples=20, deadline=None)
@given(seed=st.integers(0, 10**6))
def test_a_robot_s_mesh_is_seen_as_numpy_places_projects_and_lights_it(seed):
    """The compiled pass of a robot's mesh (placed, projected, lit, its faces facing the camera or
    not) against numpy's mesh_vertices, View.project, View.screen_normals and lambert, and the
    faces' signed areas: random meshes on the links of a random arm and one in the world, a random
    pose and camera; to 1e-9 px and 1e-12 of a colour, and the same faces facing."""
    from armanim.arm.kinematics import Arm, forward
    from armanim.arm.visuals import LinkMesh, mesh_vertices, placed_meshes
    from armanim.render.camera.projection import camera_rotation
    from armanim.render.camera.view import View, lambert
    from armanim.render.solids.robot import RobotMeshes, vertex_normals

    rng = np.random.default_rng(seed)
    arm = Arm.from_names(rng.uniform(0.2, 1.0, 3))
    meshes = [
        LinkMesh(f"l{k}", rng.normal(size=(12, 3)), rng.integers(0, 12, (20, 3)), rng.uniform(0, 1, (20, 3)))
        for k in range(4)
    ]
    offsets = [np.eye(4) for _ in meshes]
    placed = placed_meshes(meshes, [-1, 0, 1, 2], offsets)
    rotation = camera_rotation(rng.uniform(-60, 60), rng.uniform(-180, 180)) * rng.uniform(50, 200)
    view = View(np.hstack([rotation, rng.uniform(0, 300, (3, 1))]), 320, 240)
    robot = RobotMeshes(placed, np.full(3, -1), view, 100.0, (320, 240))
    pose = forward(arm, rng.uniform(-3, 3, arm.n))
    screen, rgb, facing = robot._seen(pose)

    expected = view.project(mesh_vertices(placed, pose))
    moving = placed.carrier >= 0
    normals = vertex_normals(placed)
    normals[moving] = np.einsum("vab,vb->va", pose.frames[placed.carrier[moving]], normals[moving])
    lit = lambert(view.screen_normals(normals), np.ones(3)) * robot.vertex_color
    a, b, c = (expected[placed.faces[:, i], :2] for i in range(3))
    areas = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    assert np.abs(screen - expected).max() <= 1e-9
    assert np.abs(rgb - lit).max() <= 1e-12
    sure = np.abs(areas) > 1e-6  # (a sliver's sign is its rounding's)
    assert np.array_equal(facing[sure], areas[sure] > 0.0)


def test_the_parts_of_one_z_buffer_draw_the_same_bytes_in_any_order():
    """A robot's mesh parts at one pose fill one z-buffer (the canvas skips their painter's order):
    drawn in their order, reversed or shuffled, the frame is the same bytes; another pose's parts
    or a part without a mesh among them is not one z-buffer."""
    from armanim.arm.kinematics import Arm, forward
    from armanim.arm.visuals import LinkMesh, placed_meshes
    from armanim.render.camera.projection import camera_rotation
    from armanim.render.camera.view import View
    from armanim.render.pictures.canvas import one_z_buffer
    from armanim.render.solids.arm import Part
    from armanim.render.solids.robot import RasterQueue, RobotMeshes

    rng = np.random.default_rng(5)
    arm = Arm.from_names([0.5, 0.4, 0.3])
    meshes = [
        LinkMesh(f"l{k}", rng.normal(scale=0.3, size=(30, 3)), rng.integers(0, 30, (60, 3)), rng.uniform(0, 1, (60, 3)))
        for k in range(4)
    ]
    placed = placed_meshes(meshes, [-1, 0, 1, 2], [np.eye(4)] * 4)
    view = View(np.hstack([camera_rotation(25.0, -60.0) * 90.0, np.array([[160.0], [120.0], [0.0]])]), 320, 240)
    robot = RobotMeshes(placed, np.full(3, -1), view, 90.0, (320, 240))
    pose = forward(arm, np.array([0.3, -0.8, 1.1]))
    parts = robot.parts(pose)
    assert one_z_buffer(parts)
    assert not one_z_buffer(parts + robot.parts(forward(arm, np.zeros(3))))
    assert not one_z_buffer(parts + [Part(parts[0].samples, 1.0, [], np.zeros((0, 4)))])
    frames = []
    for order in (range(len(parts)), reversed(range(len(parts))), rng.permutation(len(parts))):
        frame = np.full((240, 320, 4), 255, dtype=np.uint8)
        queue = RasterQueue((320, 240))
        for k in order:
            queue.add(parts[k].raster, frame)
        queue.flush(frame)
        frames.append(frame)
    assert (frames[0][..., 0] < 255).sum() > 1000  # (the robot is in the frame)
    assert all(np.array_equal(frames[0], f) for f in frames[1:])


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 10**6), nan=st.booleans())
def test_the_corners_span_is_numpy_s_least_and_greatest(seed, nan):
    """corner_span (a frame's triangles' pixel box) gives the corners' min and max that numpy gives
    (a vertex that no face uses is left out; a NaN corner makes its axis NaN)."""
    from armanim.render.solids.rasterloops import corner_span

    rng = np.random.default_rng(seed)
    points = rng.normal(0.0, 300.0, (40, 3))
    faces = rng.integers(0, 30, (int(rng.integers(1, 20)), 3))  # vertices 30-39 unused
    points[30:, :2] = 1e6
    if nan:
        points[faces[-1, 1], int(rng.integers(0, 2))] = np.nan
    span = np.empty(4)
    corner_span(points, faces, span)
    corners = points[faces.ravel(), :2]
    want = np.concatenate([corners.min(axis=0), corners.max(axis=0)])
    assert np.array_equal(span, want, equal_nan=True)


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 10**6), spread=st.floats(2.0, 40.0))
def test_a_still_layer_beside_a_small_mesh_draws_what_filling_them_together_draws(seed, spread):
    """A few triangles over part of a still layer, or beside it, or none: the z-buffer spans only
    their box and the layer's pixels outside it are laid from its sums, the same bytes as the layer's
    triangles and theirs filled in one z-buffer."""
    from armanim.render.solids.raster import StillLayer, draw_triangles

    rng = np.random.default_rng(seed)
    centre = rng.uniform(-10, 75, 2)
    pts = np.column_stack([centre + rng.uniform(-spread, spread, (12, 2)), rng.uniform(-1, 1, 12)])
    board = np.array([[10.3, 7.7, -0.2], [52.9, 9.1, 0.3], [47.2, 41.6, 0.1], [8.4, 38.8, -0.4]])
    pts = np.vstack([pts, board])
    rgb = np.vstack([rng.uniform(0, 1, (12, 3)), rng.uniform(0, 1, (4, 3))])
    faces = rng.integers(0, 12, (int(rng.integers(0, 8)), 3))
    still_faces = np.array([[12, 13, 14], [12, 14, 15]])
    frame = rng.integers(0, 256, (48, 64, 4)).astype(np.uint8)
    together, laid = frame.copy(), frame.copy()
    draw_triangles(together, pts, np.vstack([still_faces, faces]), rgb)
    draw_triangles(laid, pts, faces, rgb, still=StillLayer(pts, still_faces, rgb, (64, 48)))
    assert together.tobytes() == laid.tobytes()


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 10**6), width=st.floats(1.0, 6.0))
def test_a_stroke_the_still_layer_hides_leaves_no_pixel_of_it(seed, width):
    """hidden_prefix: a round-capped Agg stroke along the points it names, drawn under the layer, leaves
    the same bytes as no stroke once the layer is laid (every pixel it touched wholly covered); a
    stroke wholly inside the layer is hidden whole, one that leaves it is not."""
    from matplotlib.lines import Line2D

    from armanim.render.paint.pixels import in_pixels, make_figure
    from armanim.render.solids.raster import StillLayer

    rng = np.random.default_rng(seed)
    board = np.array([[12.3, 9.7, 0.0], [70.9, 11.1, 0.0], [66.2, 52.6, 0.0], [10.4, 49.8, 0.0]])
    still = StillLayer(board, np.array([[0, 1, 2], [0, 2, 3]]), rng.uniform(0, 1, (4, 3)), (80, 60))
    points = np.cumsum(rng.normal(0.0, 3.0, (30, 2)), axis=0) + rng.uniform(20, 60, 2)
    points[rng.random(30) < 0.1] = np.nan  # breaks
    reach = width / 2 + 2.0
    hidden = still.hidden_prefix(points, reach)
    fig, canvas = make_figure(80, 60, 72.0)  # one point a pixel
    line = in_pixels(Line2D([], [], color="k", linewidth=width, solid_capstyle="round", alpha=0.95), fig)
    canvas.draw()
    background = canvas.copy_from_bbox(fig.bbox)
    for end in range(2, len(points) + 1):
        canvas.restore_region(background)
        line.set_data(points[:end].T)
        line.draw(canvas.get_renderer())
        stroked = np.asarray(canvas.buffer_rgba()).copy()
        still.blend_outside(stroked, None)
        canvas.restore_region(background)
        bare = np.asarray(canvas.buffer_rgba()).copy()
        still.blend_outside(bare, None)
        if end <= hidden:
            assert stroked.tobytes() == bare.tobytes(), end
    inside = np.array([[30.0, 30.0], [40.0, 35.0], [50.0, 25.0]])
    assert still.hidden_prefix(inside, reach) == 3
    assert still.hidden_prefix(np.vstack([inside, [[75.0, 30.0]]]), reach) == 3
    assert still.hidden_prefix(np.vstack([[[np.nan, np.nan]], inside]), reach) == 4
