"""A run draws its robot with the URDF's meshes (issue 38): found under package_dirs, a missing
one a note (never a failed run), render.robot choosing the look, the bundled robots' own."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest

trimesh = pytest.importorskip("trimesh")

URDF = """<?xml version="1.0"?>
<robot name="two">
  <link name="base"><visual><geometry><mesh filename="package://two_description/meshes/base.stl"/></geometry></visual></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="1" velocity="2"/></joint>
  <link name="l1">
    <visual><origin xyz="0 0 0.15"/><geometry><box size="0.05 0.05 0.3"/></geometry><material name="red"><color rgba="0.8 0.1 0.1 1"/></material></visual>
    <collision><origin xyz="0 0 0.15"/><geometry><cylinder radius="0.03" length="0.3"/></geometry></collision>
  </link>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/><origin xyz="0 0 0.3"/><axis xyz="0 1 0"/>
    <limit lower="-3" upper="3" effort="1" velocity="2"/></joint>
  <link name="l2">
    <visual><geometry><mesh filename="package://two_description/meshes/gone.stl"/></geometry></visual>
    <collision><origin xyz="0 0 0.1"/><geometry><cylinder radius="0.03" length="0.2"/></geometry></collision>
  </link>
  <joint name="tip" type="fixed"><parent link="l2"/><child link="hand"/><origin xyz="0 0 0.2"/></joint>
  <link name="hand"/>
</robot>
"""


def _scene(tmp_path: Path, look: str = "mesh", package_dirs: str = "[pkgs]") -> Path:
    (tmp_path / "pkgs" / "two_description" / "meshes").mkdir(parents=True, exist_ok=True)
    trimesh.creation.cylinder(radius=0.08, height=0.1, sections=24).export(
        tmp_path / "pkgs" / "two_description" / "meshes" / "base.stl"
    )
    (tmp_path / "robots").mkdir(exist_ok=True)
    (tmp_path / "robots" / "two.urdf").write_text(URDF)
    scene = tmp_path / "two.yaml"
    scene.write_text(
        f"version: 1\narm: {{urdf: robots/two.urdf, package_dirs: {package_dirs}}}\n"
        f"goals:\n  - [0.2, 0.1, 0.4]\nrender: {{size: [160, 120], fps: 10, robot: {look}}}\n"
    )
    return scene


def _viewer_data(page: Path) -> dict:
    text = page.read_text()
    return json.loads(
        re.search(r'<script type="application/json" id="armanim-data">(.*?)</script>', text, re.S).group(1)
    )


def test_a_users_urdf_is_drawn_with_its_meshes_and_a_missing_one_is_a_note(cli, tmp_path):
    result = cli("run", str(_scene(tmp_path)), "--out", str(tmp_path / "out"), "--no-video", "--viewer")
    assert result.exit_code == 0, result.output
    assert "note:" in result.stderr and "'l2'" in result.stderr and "gone.stl" in result.stderr, result.stderr
    assert "arm.package_dirs" in result.stderr and "Traceback" not in result.output
    data = _viewer_data(tmp_path / "out" / "two" / "viewer.html")
    triangles = sum(len(g["indices"]) for g in data["meshes"]["groups"]) // 3
    assert triangles == 12 + 24 * 4  # the box and the STL cylinder (24 sections: 4 triangles each)
    assert data["meshes"]["look"] == "mesh"
    # the base has no <collision>: its capsule is fitted to its visual mesh (issue 52) and comes first
    assert data["meshes"]["uncovered"] == [2]  # l2's capsule: its mesh is missing, so the capsule is drawn
    assert data["meshes"]["capsule_group"][1:] == [1, -1]  # l1's capsule tints the group of joint 1 (after the base's)


def test_without_the_package_dirs_the_meshes_are_notes_and_capsules_draw_the_robot(cli, tmp_path):
    result = cli(
        "run",
        str(_scene(tmp_path, package_dirs="[elsewhere]")),
        "--out",
        str(tmp_path / "out"),
        "--no-video",
        "--viewer",
    )
    assert result.exit_code == 0, result.output
    # base.stl and gone.stl: the box alone is drawn as a mesh; base.stl is not fitted either (the base has no <collision>)
    assert result.stderr.count("note:") == 3 and result.stderr.count("drawn as its capsules") == 2
    data = _viewer_data(tmp_path / "out" / "two" / "viewer.html")
    assert sum(len(g["indices"]) for g in data["meshes"]["groups"]) // 3 == 12


def test_a_link_whose_mesh_is_missing_is_drawn_as_its_capsule(tmp_path):
    """In the pictures, the robot is its meshes and, for l2 (whose mesh is missing), its capsule."""
    import numpy as np

    from armanim.arm.kinematics import forward
    from armanim.render.camera.view import View
    from armanim.render.solids.robot import MeshesAndCapsules, arm_solids
    from armanim.runs.options import RunOptions, output_choice
    from armanim.runs.pipeline import solve_scene, with_meshes
    from armanim.scene import load_scene

    scene = load_scene(_scene(tmp_path))
    run, notes = with_meshes(solve_scene(scene, 10.0), scene, output_choice(scene, RunOptions())[1].render)
    assert len(notes) == 1
    view = View(np.hstack([np.eye(3) * 100, np.array([[80.0], [60.0], [0.0]])]), 160, 120)
    solids = arm_solids(run.problem, run.meshes, view, 100.0, (160, 120))
    assert isinstance(solids, MeshesAndCapsules) and solids.shown.tolist() == [
        False,
        False,
        True,
    ]  # the base's fitted capsule first
    parts = solids.parts(forward(run.problem.arm, run.problem.home))
    assert (
        sum(p.raster is not None for p in parts) == len(run.meshes.links) and sum(p.raster is None for p in parts) == 1
    )


def test_render_robot_capsules_reads_no_mesh(cli, tmp_path):
    result = cli(
        "run", str(_scene(tmp_path, look="capsules")), "--out", str(tmp_path / "out"), "--no-video", "--viewer"
    )
    assert result.exit_code == 0, result.output
    assert "drawn as its capsules" not in result.stderr  # only the fit of the base's capsule read its visual mesh
    assert "meshes" not in _viewer_data(tmp_path / "out" / "two" / "viewer.html")


def test_a_bundled_robot_brings_its_own_meshes_and_the_poster_draws_them(cli, tmp_path):
    scene = tmp_path / "panda.yaml"
    scene.write_text(
        "version: 1\narm: {robot: panda}\ngoals:\n  - [0.5, 0.2, 0.4]\nrender: {size: [160, 120], fps: 5}\n"
    )
    result = cli("run", str(scene), "--out", str(tmp_path / "out"), "--jobs", "1")
    assert result.exit_code == 0, result.output
    data = _viewer_data(tmp_path / "out" / "panda" / "viewer.html")
    assert len(data["meshes"]["groups"]) == 8  # the base and seven joints' links (the hand rides on the seventh)
    assert (tmp_path / "out" / "panda" / "poster.png").stat().st_size > 0


def test_furniture_is_drawn_never_checked_and_an_arm_of_links_keeps_its_capsules(cli, tmp_path):
    """A whiteboard a goal touches: no clearance check refuses it; the viewer holds its 12
    triangles in the world, the arm of links is still drawn whole as capsules, joints and base."""
    import numpy as np

    from armanim.arm.kinematics import forward
    from armanim.render.camera.view import View
    from armanim.render.solids.robot import MeshesAndCapsules, arm_solids, robot_meshed
    from armanim.runs.options import RunOptions, output_choice
    from armanim.runs.pipeline import solve_scene, with_meshes
    from armanim.scene import load_scene

    scene_file = tmp_path / "board.yaml"
    scene_file.write_text(
        "version: 1\narm: {links: [1, 1]}\ngoals:\n  - [1.2, 0.5, 0]\n"
        "render:\n  size: [160, 120]\n  fps: 10\n  furniture:\n"
        "    - {box: {center: [1.21, 0.5, 0], size: [0.02, 1, 1]}, color: [1, 1, 1]}\n"
    )
    result = cli("run", str(scene_file), "--out", str(tmp_path / "out"), "--no-video", "--viewer")
    assert result.exit_code == 0, result.output
    data = _viewer_data(tmp_path / "out" / "board" / "viewer.html")
    assert data["meshes"]["robot"] is False and [g["carrier"] for g in data["meshes"]["groups"]] == [-1]
    assert len(data["meshes"]["groups"][0]["indices"]) == 36
    scene = load_scene(scene_file)
    run, _ = with_meshes(solve_scene(scene, 10.0), scene, output_choice(scene, RunOptions())[1].render)
    assert not robot_meshed(run.problem, run.meshes)
    solids = arm_solids(
        run.problem,
        run.meshes,
        View(np.hstack([np.eye(3) * 40, np.array([[80.0], [60.0], [0.0]])]), 160, 120),
        40.0,
        (160, 120),
    )
    parts = solids.parts(forward(run.problem.arm, run.problem.home))
    assert isinstance(solids, MeshesAndCapsules) and sum(p.raster is not None for p in parts) == 1
    assert sum(p.raster is None for p in parts) == 1 + 2 + 2  # the base, two capsules, two joint discs


def test_furniture_colours_are_checked(cli, tmp_path):
    scene_file = tmp_path / "bad.yaml"
    scene_file.write_text(
        "version: 1\narm: {links: [1, 1]}\ngoals:\n  - [1, 1, 0]\n"
        "render:\n  furniture:\n    - {box: {center: [2, 0, 0], size: [1, 1, 1]}, color: [1, 2, 1]}\n"
    )
    result = cli("validate", str(scene_file))
    assert result.exit_code == 2 and "render.furniture[0].color" in result.stderr, result.stderr


TINY_AND_HUGE = URDF.replace(
    '<visual><origin xyz="0 0 0.15"/><geometry><box size="0.05 0.05 0.3"/></geometry>',
    '<visual><geometry><sphere radius="1e-300"/></geometry></visual><visual><geometry><box size="1e-300 0 -1"/></geometry></visual>'
    '<visual><geometry><cylinder radius="1e-300" length="1e-300"/></geometry></visual>'
    '<visual><geometry><mesh filename="package://two_description/meshes/base.stl" scale="1e300 1e300 1e300"/></geometry></visual>'
    '<visual><origin xyz="0 0 0.15"/><geometry><box size="0.05 0.05 0.3"/></geometry>',
)


def test_tiny_and_huge_visuals_are_drawn_without_a_traceback(cli, tmp_path):
    """A visual sphere of radius 1e-300 (trimesh's icosphere made its vertices NaN), a box and a
    cylinder of 1e-300, a mesh scaled by 1e300: run, view and render end 0 (issue 50, item 8),
    every number of the viewer's data finite, the tiny shapes drawn at the smallest size."""
    scene = _scene(tmp_path)
    (tmp_path / "robots" / "two.urdf").write_text(TINY_AND_HUGE)
    out = tmp_path / "out"
    result = cli("run", scene, "--out", out, "--no-video", "--viewer", "--quiet")
    assert result.exit_code == 0, result.output
    data = _viewer_data(out / "two" / "viewer.html")  # strict JSON: a NaN would not have been written
    positions = [v for g in data["meshes"]["groups"] for v in g["positions"]]
    assert positions and all(abs(v) < 1e10 for v in positions)
    assert cli("view", out / "two").exit_code == 0
    rendered = cli("render", out / "two", "--out", tmp_path / "r", "--quiet")
    assert rendered.exit_code == 0, rendered.output
    assert (tmp_path / "r" / "poster.png").is_file()


def test_render_and_view_of_a_run_elsewhere_draw_the_users_meshes_or_say_why_not(cli, tmp_path, monkeypatch):
    """A run written away from the user's URDF re-renders and re-views with its meshes (the run folder
    records where the scene and the URDF were); moved away, each mesh is a note, never silence (issue 50).
    In-process, from a folder that is neither the scene's nor the run's."""
    import shutil

    monkeypatch.chdir(tmp_path)
    scene = _scene(tmp_path / "ws", package_dirs="[pkgs]")
    out = tmp_path / "elsewhere"
    assert cli("run", scene, "--out", out, "--no-video", "--viewer", "--quiet").exit_code == 0
    run = out / "two"
    viewed = cli("view", run, "--out", tmp_path / "again.html")
    assert viewed.exit_code == 0 and "base.stl" not in viewed.stderr, viewed.stderr  # found: no note about it
    assert "gone.stl" in viewed.stderr  # the one missing in the user's folder too is still a note
    data = _viewer_data(tmp_path / "again.html")
    assert sum(len(g["indices"]) for g in data["meshes"]["groups"]) // 3 == 12 + 24 * 4  # the box and the base's STL
    shutil.move(tmp_path / "ws", tmp_path / "moved")
    rendered = cli("render", run, "--out", tmp_path / "r", "--quiet", "--jobs", "1")
    assert rendered.exit_code == 0, rendered.stderr
    assert "base.stl" in rendered.stderr and "drawn as its capsules" in rendered.stderr  # said even with --quiet
    viewed = cli("view", run, "--out", tmp_path / "moved.html")
    assert viewed.exit_code == 0 and "base.stl" in viewed.stderr, viewed.stderr


def _blue_share(png: Path) -> float:
    """Share of a picture's pixels in the capsules' blue (blue well above red and green)."""
    import imageio.v3 as iio

    rgb = iio.imread(png)[..., :3].astype(int)
    return float(np.mean((rgb[..., 2] - rgb[..., 0] > 80) & (rgb[..., 2] - rgb[..., 1] > 40)))


def test_fk_png_draws_the_robot_as_its_run_does(cli, tmp_path):
    """``fk --png`` of a bundled robot draws its meshes (the Panda's white shells), not the blue capsules
    (issue 50); a user's URDF with a missing mesh says so."""
    pose = tmp_path / "pose.png"
    done = cli("fk", "--robot", "panda", "--angles=0,-45,0,-135,0,90,45", "--png", pose)
    assert done.exit_code == 0, done.stderr
    assert _blue_share(pose) < 0.001  # the capsules' blue covered 2 % of this picture
    scene = _scene(tmp_path, look="mesh")
    done = cli("fk", "--scene", scene, "--angles=10,20", "--png", pose)
    assert done.exit_code == 0 and "gone.stl" in done.stderr, done.stderr


def test_the_ur5_is_not_drawn_as_a_black_silhouette(cli, tmp_path):
    """Issue 50: the UR5's vendored greys (13-107/255) read almost black. Mesh colours are lifted
    toward white before they are lit, as a viewer's ambient light does: few pixels of its picture are
    near black (1.5 % of them were, darker than 40/255; the title and caption text remain)."""
    import imageio.v3 as iio

    from armanim.render.solids.robot import MESH_LIFT, lifted

    assert lifted(np.zeros(3)).min() == MESH_LIFT and lifted(np.ones(3)).max() == 1.0
    pose = tmp_path / "ur5.png"
    done = cli("fk", "--robot", "ur5", "--angles=0,-90,90,0,90,0", "--png", pose)
    assert done.exit_code == 0, done.stderr
    rgb = iio.imread(pose)[..., :3]
    assert np.mean(rgb.max(axis=-1) < 40) < 0.007
