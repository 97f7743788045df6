"""The robot's look (issue 38): a URDF's <visual> meshes and shapes read, coloured and placed on
the chain's frames, checked against pinocchio's frame placements and trimesh's own geometry."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from armanim.arm.chain import serial_chain, transform
from armanim.arm.kinematics import forward
from armanim.arm.visuals import LinkMesh, mesh_vertices
from armanim.scene.urdf import chain_joints, read_urdf
from armanim.scene.visuals import DEFAULT_RGB, chain_meshes, link_meshes, simplified, visual_specs

trimesh = pytest.importorskip("trimesh")
ROBOTS = Path(__file__).resolve().parents[2] / "src" / "armanim" / "arm" / "robots"


def _probe_meshes(robot, points: np.ndarray) -> list[LinkMesh]:
    """One mesh per link of the URDF whose vertices are ``points`` (k, 3) in the link's frame."""
    return [LinkMesh(name, points, np.zeros((0, 3), dtype=int), np.zeros((0, 3))) for name in robot.links]


@pytest.mark.parametrize(
    "name, base, tip",
    [
        ("panda", "panda_link0", "panda_hand_tcp"),
        ("ur5", "base_link", "tool0"),
        ("iiwa", "lbr_iiwa_link_0", "lbr_iiwa_link_7"),
    ],
)
def test_every_links_frame_is_where_pinocchio_puts_it(name, base, tip):
    """A point fixed in each link's frame lands where pinocchio's frame placement of that link puts it,
    for the links on the arm's path, the base and the links hanging below the tip (the Panda's
    hand and fingers, at their joints' zero)."""
    pin = pytest.importorskip("pinocchio")
    urdf = ROBOTS / name / f"{name}.urdf"
    robot = read_urdf(urdf)
    mount = transform([0.1, -0.2, 0.05], [0.0, 0.0, 0.3])
    chain = serial_chain(mount, chain_joints(robot, base, tip), np.eye(4))
    points = np.array([[0.0, 0.0, 0.0], [0.1, -0.2, 0.3]])
    placed = chain_meshes(_probe_meshes(robot, points), robot, base, tip, chain, mount)
    model = pin.buildModelFromUrdf(str(urdf))
    data = model.createData()
    rng = np.random.default_rng(7)
    for _ in range(5):
        phi = rng.uniform(-1.5, 1.5, chain.arm.n)
        q = pin.neutral(model)
        for k, joint in enumerate(chain.arm.joint_names):
            q[model.joints[model.getJointId(joint)].idx_q] = phi[k]
        pin.framesForwardKinematics(model, data, q)
        world = mesh_vertices(placed, forward(chain.arm, phi)).reshape(len(placed.links), len(points), 3)
        for i, link in enumerate(placed.links):
            frame = data.oMf[model.getFrameId(link)]
            expected = (mount[:3, :3] @ (frame.rotation @ points.T + frame.translation[:, None])).T + mount[:3, 3]
            assert np.allclose(world[i], expected, atol=1e-12), link
    assert base in placed.links and tip in placed.links
    if name == "panda":
        assert {"panda_hand", "panda_leftfinger", "panda_rightfinger"} <= set(placed.links)


def _urdf(tmp_path: Path, visuals: str) -> Path:
    path = tmp_path / "r.urdf"
    path.write_text(
        f'<robot name="r"><material name="blue"><color rgba="0 0 1 1"/></material>'
        f'<link name="a">{visuals}</link></robot>'
    )
    return path


def _read(path: Path, package_dirs=()):
    warnings: list[str] = []
    meshes = link_meshes(visual_specs(path.read_bytes(), str(path)), path.parent, list(package_dirs), warnings.append)
    return meshes, warnings


@pytest.mark.parametrize("suffix", ["stl", "obj", "dae"])
def test_a_mesh_file_is_read_scaled_and_placed_by_its_origin(tmp_path, suffix):
    box = trimesh.creation.box(extents=[1.0, 2.0, 3.0])
    box.export(tmp_path / f"box.{suffix}")
    path = _urdf(
        tmp_path,
        f'<visual><origin xyz="1 0 0" rpy="0 0 1.5707963267948966"/><geometry>'
        f'<mesh filename="box.{suffix}" scale="2 1 1"/></geometry><material name="blue"/></visual>',
    )
    (mesh,), warnings = _read(path)
    assert not warnings and mesh.link == "a" and mesh.triangles == 12
    lo, hi = mesh.vertices.min(axis=0), mesh.vertices.max(axis=0)
    # scaled to 2 x 2 x 3, turned 90 degrees about z (x <-> y), moved 1 along x
    assert np.allclose(hi - lo, [2.0, 2.0, 3.0]) and np.allclose((hi + lo) / 2, [1.0, 0.0, 0.0])
    if suffix != "dae":  # COLLADA keeps its own material; the others take the URDF's colour
        assert np.allclose(mesh.colors, [0.0, 0.0, 1.0])


def test_the_shapes_are_their_sizes_and_a_colourless_one_is_grey(tmp_path):
    path = _urdf(
        tmp_path,
        '<visual><geometry><box size="1 2 3"/></geometry></visual>'
        '<visual><origin xyz="0 0 5"/><geometry><sphere radius="0.5"/></geometry></visual>'
        '<visual><origin xyz="0 0 -5"/><geometry><cylinder radius="0.25" length="2"/></geometry>'
        '<material name="x"><color rgba="1 0 0 1"/></material></visual>',
    )
    (mesh,), _ = _read(path)
    z = mesh.vertices[:, 2]
    assert np.isclose(z.max(), 5.5) and np.isclose(z.min(), -6.0)
    assert np.allclose(np.ptp(mesh.vertices[np.abs(z) <= 1.5], axis=0), [1.0, 2.0, 3.0])
    reds = np.all(np.isclose(mesh.colors, [1.0, 0.0, 0.0]), axis=1)
    assert reds.any() and np.allclose(mesh.colors[~reds], DEFAULT_RGB)


def test_package_names_resolve_under_the_package_dirs_and_a_missing_file_is_a_warning(tmp_path):
    (tmp_path / "pkgs" / "arm_description" / "meshes").mkdir(parents=True)
    trimesh.creation.box().export(tmp_path / "pkgs" / "arm_description" / "meshes" / "a.stl")
    path = _urdf(
        tmp_path,
        '<visual><geometry><mesh filename="package://arm_description/meshes/a.stl"/></geometry></visual>'
        '<visual><geometry><mesh filename="package://arm_description/meshes/gone.stl"/></geometry></visual>'
        '<visual><geometry><mesh filename="broken.stl"/></geometry></visual>',
    )
    (tmp_path / "broken.stl").write_bytes(b"solid nothing here\nthis is not an STL")
    (mesh,), warnings = _read(path, [tmp_path / "pkgs"])
    assert mesh.triangles == 12
    assert len(warnings) == 2
    assert "gone.stl" in warnings[0] and "'a'" in warnings[0] and "arm.package_dirs" in warnings[0]
    assert "broken.stl" in warnings[1]
    _, unresolved = _read(path, [])
    assert len(unresolved) == 3


@pytest.mark.parametrize("scale", ["0 0 0", "0 1 0", "-0 0 2"])
def test_a_mesh_scaled_to_a_line_or_a_point_is_a_note_not_an_invisible_link(tmp_path, scale):
    """Campaign 8: a visual mesh with ``scale="0 0 0"`` was drawn as nothing, without a word (the
    link vanished from the video and the viewer); a scale with one zero is a flat mesh, drawn."""
    trimesh.creation.box().export(tmp_path / "box.stl")
    visual = '<visual><geometry><mesh filename="box.stl" scale="{}"/></geometry></visual>'
    meshes, warnings = _read(_urdf(tmp_path, visual.format(scale)))
    assert not meshes and len(warnings) == 1, (meshes, warnings)
    assert "'a'" in warnings[0] and "no area (a line or a point): drawn as its capsules" in warnings[0]
    (flat,), none = _read(_urdf(tmp_path, visual.format("1 1 0")))
    assert not none and flat.triangles == 12 and np.ptp(flat.vertices[:, 2]) == 0


def test_simplifying_keeps_the_budget_the_colours_and_the_shape():
    sphere = trimesh.creation.icosphere(subdivisions=4)  # 5,120 triangles
    colors = np.where(sphere.triangles_center[:, 2:3] > 0, [1.0, 0.0, 0.0], [0.0, 0.0, 1.0])
    mesh = LinkMesh("a", np.asarray(sphere.vertices), np.asarray(sphere.faces), colors)
    small = simplified(mesh, 500)
    assert 400 <= small.triangles <= 600
    assert {tuple(c) for c in small.colors} == {(1.0, 0.0, 0.0), (0.0, 0.0, 1.0)}
    radius = np.linalg.norm(small.vertices, axis=1)
    assert 0.95 < radius.min() and radius.max() < 1.02  # quadric collapse keeps the surface within 2 %


def _panda_meshes():
    from armanim.scene.visuals import bundled_link_meshes

    robot = read_urdf(ROBOTS / "panda" / "panda.urdf")
    chain = serial_chain(np.eye(4), chain_joints(robot, "panda_link0", "panda_hand_tcp"), np.eye(4))
    return chain, chain_meshes(
        bundled_link_meshes(ROBOTS / "panda"), robot, "panda_link0", "panda_hand_tcp", chain, np.eye(4)
    )


def test_the_bundled_panda_has_every_link_its_hand_and_fingers_within_budget():
    _, meshes = _panda_meshes()
    assert meshes.links == (
        "panda_link0",
        *(f"panda_link{k}" for k in range(1, 8)),
        "panda_hand",
        "panda_leftfinger",
        "panda_rightfinger",
    )
    assert 5_000 <= meshes.triangles <= 15_000
    assert np.all((meshes.colors >= 0) & (meshes.colors <= 1)) and len(np.unique(meshes.colors, axis=0)) >= 2


def test_the_viewer_data_places_every_vertex_where_the_kinematics_does():
    """Rebuilt from the page's data as the page does (each group's vertices turned by its carrier's
    quaternion and moved to its joint), every vertex is where mesh_vertices puts it, to the data's rounding."""
    from armanim.arm.rotations import quaternion_rotation
    from armanim.render.viewer.data import mesh_entries, plain

    chain, meshes = _panda_meshes()
    phi = np.random.default_rng(3).uniform(-1.5, 1.5, (4, chain.arm.n))
    pose = forward(chain.arm, phi)
    data = plain(mesh_entries(meshes, lambda start, stop: forward(chain.arm, phi[start:stop]), len(phi), 5))
    expected = mesh_vertices(meshes, pose)
    placement = np.reshape(data["frames"], (len(phi), len(data["carriers"]), 7))
    for group in data["groups"]:
        local = np.reshape(group["positions"], (-1, 3))
        mine = meshes.carrier == group["carrier"]
        assert len(local) == mine.sum() and len(group["colors"]) == 3 * len(local)
        assert max(group["indices"]) < len(local) and len(group["indices"]) % 3 == 0
        for f in range(len(phi)):
            if group["carrier"] < 0:
                world = local
            else:
                at = placement[f, data["carriers"].index(group["carrier"])]
                world = local @ quaternion_rotation(at[3:]).T + at[:3]
            assert np.allclose(world, expected[f][mine], atol=5e-5)
    assert sum(len(g["indices"]) for g in data["groups"]) == 3 * meshes.triangles


def test_a_pen_is_drawn_from_the_tool_point_back_along_the_tool_frame(tmp_path):
    """Nib apex at the tool point, the body back along the tool frame's -z, its length and radius;
    a tool mesh that cannot be read is a note."""
    from types import SimpleNamespace

    from armanim.scene.looks import tool_meshes

    pen = SimpleNamespace(length=0.12, radius=0.008)
    tool = SimpleNamespace(xyz=[0.0, 0.0, 0.1], rpy=[0.0, 90.0, 0.0], pen=pen, mesh="missing.stl", gripper=None)
    notes: list[str] = []
    nib, body = tool_meshes(tool, "flange", tmp_path, notes.append)
    points = np.vstack([nib.vertices, body.vertices])
    # the tool frame turned 90 degrees about y: its -z is the tip link's -x; the tool point at z = 0.1
    assert np.isclose(points[:, 0].max(), 0.0, atol=1e-12) and np.isclose(points[:, 0].min(), -0.12)
    assert np.allclose(nib.vertices[np.argmax(nib.vertices[:, 0])], [0.0, 0.0, 0.1], atol=1e-12)
    assert np.isclose(np.abs(points[:, 1]).max(), 0.008, rtol=1e-3) and np.isclose(
        np.ptp(points[:, 2]), 0.016, rtol=1e-2
    )
    assert len(notes) == 1 and "arm.tool.mesh" in notes[0] and "missing.stl" in notes[0]


@pytest.mark.parametrize("radius, length", [(0.008, 0.12), (0.0123, 0.137), (0.05, 0.5), (0.001, 0.011)])
def test_a_pen_s_shapes_are_trimesh_s_cone_and_cylinder_without_trimesh(radius, length):
    """The pen's nib and body, turned without trimesh (its import cost a video of a pen 0.7 s of CPU), are
    trimesh's own cone and cylinder array for array (so every frame of a pen is drawn as before)."""
    from armanim.scene.looks import PEN_SECTIONS, revolved

    half = length / 2.0
    for shape, profile in (
        (
            trimesh.creation.cone(radius=radius, height=length, sections=PEN_SECTIONS),
            [[0, 0], [radius, 0], [0, length]],
        ),
        (
            trimesh.creation.cylinder(radius=radius, height=length, sections=PEN_SECTIONS),
            [[0, -half], [radius, -half], [radius, half], [0, half]],
        ),
    ):
        vertices, faces = revolved(np.array(profile, dtype=float), PEN_SECTIONS)
        assert np.array_equal(vertices, shape.vertices) and np.array_equal(faces, shape.faces)


def test_a_pen_s_look_does_not_import_trimesh():
    """Reading a pen's look leaves trimesh unimported (a fresh process: the other tests import it)."""
    import subprocess
    import sys

    code = (
        "import sys; from types import SimpleNamespace; from pathlib import Path;"
        "from armanim.scene.looks import tool_meshes;"
        "pen = SimpleNamespace(length=0.12, radius=0.008);"
        "tool = SimpleNamespace(xyz=[0, 0, 0.1], rpy=[0, 0, 0], pen=pen, mesh=None, gripper=None);"
        "assert len(tool_meshes(tool, 'flange', Path('.'), print)) == 2;"
        "print('trimesh' in sys.modules)"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "False"


def test_a_panda_gripper_is_drawn_on_the_flange_as_the_panda_mounts_it(tmp_path):
    """``gripper: panda`` on any arm: Franka's hand and fingers on the tip link, where the Panda's
    own URDF puts them relative to its flange (checked against pinocchio's placement on the Panda)."""
    from types import SimpleNamespace

    pin = pytest.importorskip("pinocchio")
    from armanim.scene.looks import tool_meshes

    tool = SimpleNamespace(xyz=[0.0, 0.0, 0.1], rpy=[0.0, 0.0, 0.0], pen=None, mesh=None, gripper="panda")
    parts = tool_meshes(tool, "flange", tmp_path, print)
    assert len(parts) == 3 and all(p.link == "flange" for p in parts) and sum(p.triangles for p in parts) > 500
    # the left finger's mesh: where the bundled Panda draws panda_leftfinger relative to panda_link8
    model = pin.buildModelFromUrdf(str(ROBOTS / "panda" / "panda.urdf"))
    data = model.createData()
    pin.framesForwardKinematics(model, data, pin.neutral(model))
    flange, finger = data.oMf[model.getFrameId("panda_link8")], data.oMf[model.getFrameId("panda_leftfinger")]
    relative = flange.inverse() * finger
    from armanim.scene.visuals import bundled_link_meshes

    own = next(m for m in bundled_link_meshes(ROBOTS / "panda") if m.link == "panda_leftfinger")
    expected = own.vertices @ relative.rotation.T + relative.translation
    assert np.allclose(parts[1].vertices, expected, atol=1e-6)


def test_a_tool_capsule_rides_on_the_tool_frame_and_is_checked_as_the_tips_link(tmp_path):
    """``arm.tool.collision``: a capsule from the flange to the tip in the tool frame; at any pose its
    end is where the kinematics puts the tip, it carries the name of the link that carries the tip
    (so the allowed-collision rules of that link apply), and the run's clearance counts it."""
    from armanim.arm.capsules import capsule_ends
    from armanim.scene import load_scene, scene_to_problem

    scene = tmp_path / "pen.yaml"
    scene.write_text(
        "version: 1\narm:\n  robot: ur5\n  tool: {xyz: [0, 0, 0.12], rpy: [0, 30, 0],"
        " collision: {from: [0, 0, -0.12], to: [0, 0, 0], radius: 0.01}}\ngoals:\n  - [0.4, 0.2, 0.3]\n"
    )
    problem = scene_to_problem(load_scene(scene).model)
    assert problem.capsules.names[-1] == "wrist_3_link" and problem.capsules.radius[-1] == 0.01
    rng = np.random.default_rng(4)
    pose = forward(problem.arm, rng.uniform(-2, 2, (6, problem.arm.n)))
    a, b = capsule_ends(problem.capsules, pose)
    assert np.allclose(b[:, -1], pose.tip, atol=1e-12)
    assert np.allclose(np.linalg.norm(a[:, -1] - b[:, -1], axis=-1), 0.12)
    from armanim.world.distances import min_link_clearance
    from armanim.world.obstacles import Obstacles

    home = forward(problem.arm, problem.home)
    ball = home.tip + np.array([0.0, 0.0, -0.05])  # 5 cm below the tip: nearer the tool than any link
    near = Obstacles(ball[None], np.array([0.02]), np.array([0.02]))
    clear = float(min_link_clearance(home, near, problem.capsules))
    start, end = (e[-1] for e in capsule_ends(problem.capsules, home))
    along = start + np.linspace(0, 1, 20001)[:, None] * (end - start)
    assert np.isclose(clear, np.linalg.norm(along - ball, axis=1).min() - 0.02 - 0.01, atol=1e-6)  # the tool's
