"""collision: auto of your own URDF fits capsules to its meshes (scene.meshcapsules): every vertex of
the meshes as the URDF places them is held (trimesh reads them here, an independent transform and
point-to-segment distance check them), the fit is the same twice and from the cache, meshes over
the reader's limits and missing meshes are errors at their line, a run writes capsules.yaml, which
a scene takes back as its arm.collision, and `armanim robots --fit` prints it."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import trimesh
import yaml
from scipy.spatial.transform import Rotation

from armanim.errors import SceneError
from armanim.scene import load_scene, scene_to_problem

BASE_RPY, BASE_XYZ, BASE_SCALE = (0.3, -0.2, 0.5), (0.01, -0.02, 0.03), (1.5, 1.0, 0.5)
ARM_RPY, ARM_XYZ = (0.0, 0.4, 0.0), (0.0, 0.0, 0.2)

URDF = f"""<robot name="meshy">
  <link name="base"><collision><origin xyz="{" ".join(map(str, BASE_XYZ))}" rpy="{" ".join(map(str, BASE_RPY))}"/>
    <geometry><mesh filename="meshes/base.stl" scale="{" ".join(map(str, BASE_SCALE))}"/></geometry></collision></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="upper"/><origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <link name="upper"><collision><origin xyz="{" ".join(map(str, ARM_XYZ))}" rpy="{" ".join(map(str, ARM_RPY))}"/>
    <geometry><mesh filename="package://meshy/meshes/upper.obj"/></geometry></collision>
    <collision><origin xyz="0 0 0.45"/><geometry><sphere radius="0.04"/></geometry></collision></link>
  <joint name="j2" type="revolute"><parent link="upper"/><child link="fore"/><origin xyz="0 0 0.45"/><axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <link name="fore"><visual><geometry><mesh filename="meshes/fore.stl"/></geometry></visual></link>
  <joint name="j3" type="revolute"><parent link="fore"/><child link="tip"/><origin xyz="0 0 0.3"/><axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <link name="tip"><collision><geometry><sphere radius="0.02"/></geometry></collision></link>
</robot>
"""


def _meshes() -> dict[str, trimesh.Trimesh]:
    return {
        "base.stl": trimesh.creation.cylinder(radius=0.08, height=0.06, sections=24),
        "upper.obj": trimesh.creation.capsule(height=0.3, radius=0.05, count=[12, 12]),
        "fore.stl": trimesh.creation.box(
            extents=(0.06, 0.07, 0.3), transform=trimesh.transformations.translation_matrix((0, 0, 0.15))
        ),
    }


LINKS = ("base", "upper", "fore")
"""The links whose meshes are fitted (fore's from its visual mesh)."""


def _package(root: Path) -> Path:
    """The package folder `meshy` under ``root``: the URDF and its meshes."""
    folder = root / "meshy"
    (folder / "meshes").mkdir(parents=True)
    for name, mesh in _meshes().items():
        mesh.export(folder / "meshes" / name)
    (folder / "meshy.urdf").write_text(URDF)
    return folder


@pytest.fixture(scope="module")
def meshy_fits(tmp_path_factory) -> Path:
    """A cache folder holding the fits of meshy's three meshes, fitted once for the module (a few
    seconds of CPU each time): the tests of what a scene of the robot does read them from there, as
    a second run does; the tests of the fit and of the cache itself fit afresh."""
    from armanim.scene.meshcapsules import mesh_capsules
    from armanim.scene.urdf import read_urdf

    root = tmp_path_factory.mktemp("meshy-fits")
    folder = _package(root)
    fits = mesh_capsules(read_urdf(folder / "meshy.urdf"), LINKS, folder, [root], cache=root / "cache")
    assert fits.cached == 0 and len(list((root / "cache").glob("*.json"))) == len(LINKS)
    return root / "cache"


@pytest.fixture()
def robot_dir(tmp_path, monkeypatch, meshy_fits):
    """A package folder `meshy` with the URDF and its meshes; the fit cache in its own folder, holding
    the fits of the meshes as written (:func:`meshy_fits`)."""
    shutil.copytree(meshy_fits, tmp_path / "cache")
    monkeypatch.setenv("ARMANIM_CACHE_DIR", str(tmp_path / "cache"))
    return _package(tmp_path)


def _scene(folder: Path, extra: str = "", name: str = "s.yaml") -> Path:
    path = folder / name
    path.write_text(f"version: 1\narm:\n  urdf: meshy.urdf\n  tip_link: tip\n{extra}goals:\n  - [0.3, 0.1, 0.5]\n")
    return path


def _placed(name: str, xyz, rpy, scale=(1.0, 1.0, 1.0)) -> np.ndarray:
    """The mesh file's vertices as the URDF places them in the link's frame: scaled, then
    turned by R = Rz(yaw) Ry(pitch) Rx(roll) and moved (scipy's rotation, not armanim's)."""
    mesh = trimesh.load(str(name), force="mesh")
    return (np.asarray(mesh.vertices) * scale) @ Rotation.from_euler("xyz", rpy).as_matrix().T + np.asarray(xyz)


def _distance(points: np.ndarray, a, b) -> np.ndarray:
    a, b = np.asarray(a, float), np.asarray(b, float)
    ab = b - a
    t = np.clip(((points - a) @ ab) / max(ab @ ab, 1e-300), 0.0, 1.0)
    return np.sqrt(((points - (a + t[:, None] * ab)) ** 2).sum(axis=1))


def _held(points: np.ndarray, capsules) -> float:
    """The largest excess of a point over the nearest of ``capsules`` (<= 0: every point held)."""
    return float(np.min([_distance(points, c.start, c.end) - c.radius for c in capsules], axis=0).max())


def test_auto_fits_every_links_meshes_and_holds_every_vertex(robot_dir):
    scene = load_scene(_scene(robot_dir))
    robot = scene.model.arm.urdf_arm
    by_link = {}
    for c in robot.capsules:
        by_link.setdefault(c.link, []).append(c)
    assert set(by_link) == {"base", "upper", "fore", "tip"}
    assert robot.fitted_links == ("base", "upper", "fore") and robot.from_visuals == ("fore",)
    assert (
        1 <= len(by_link["base"]) <= 3 and 2 <= len(by_link["upper"]) <= 4
    )  # the sphere primitive kept beside the fit
    meshes = robot_dir / "meshes"
    assert _held(_placed(meshes / "base.stl", BASE_XYZ, BASE_RPY, BASE_SCALE), by_link["base"]) <= 1e-9
    assert _held(_placed(meshes / "upper.obj", ARM_XYZ, ARM_RPY), by_link["upper"][1:]) <= 1e-9
    assert by_link["upper"][0].radius == 0.04  # primitives keep today's rule (a sphere: a zero-length capsule)
    assert _held(_placed(meshes / "fore.stl", (0, 0, 0), (0, 0, 0)), by_link["fore"]) <= 1e-9
    notes = [n.message for n in scene.notes]
    assert any("links fore have no <collision>: their capsules are fitted to their visual meshes" in n for n in notes)
    assert not robot.fallback_links
    problem = scene_to_problem(scene.model)
    assert len(problem.capsules) == len(robot.capsules)


def test_the_fit_is_the_same_twice_and_from_the_cache(robot_dir, tmp_path, meshy_fits):
    """A fit without a cache is bit for bit the fit another one kept in its cache (the module's
    first fit of the same meshes, :func:`meshy_fits`, into an empty cache), read back."""
    from armanim.scene.meshcapsules import mesh_capsules
    from armanim.scene.urdf import read_urdf

    robot = read_urdf(robot_dir / "meshy.urdf")
    fresh = mesh_capsules(robot, LINKS, robot_dir, [tmp_path], cache=None)
    shutil.copytree(meshy_fits, tmp_path / "c")
    again = mesh_capsules(robot, LINKS, robot_dir, [tmp_path], cache=tmp_path / "c")
    assert (fresh.cached, again.cached) == (0, 3)

    def rows(fits):
        return [(link, c.start.tobytes(), c.end.tobytes(), c.radius) for link, c in fits.capsules]

    assert rows(fresh) == rows(again)
    entries = sorted((tmp_path / "c").glob("*.json"))
    # a damaged cache entry is fitted again, never trusted (each time another one; the others are read)
    entries[0].write_text('{"key": "x", "capsules": [{"from": [0, 0, 0], "to": [0, 0, 0], "radius": 0}]}')
    damaged = mesh_capsules(robot, LINKS, robot_dir, [tmp_path], cache=tmp_path / "c")
    assert (rows(damaged), damaged.cached) == (rows(fresh), 2)
    entries[1].write_text(
        "[" * 49_000 + "]" * 49_000
    )  # campaign 9: JSON nested within the size bound was a RecursionError
    nested = mesh_capsules(robot, LINKS, robot_dir, [tmp_path], cache=tmp_path / "c")
    assert (rows(nested), nested.cached) == (rows(fresh), 2)


def test_a_link_in_the_cache_is_never_written_through(robot_dir, tmp_path, meshy_fits):
    """Campaign 10: a cache entry that was a link to a user's file (or a hard link to one) was
    replaced by a fit through the link: the user's file held capsules. A link there is left as it
    is and the fit not kept; a hard link is replaced by a new file, the user's one as it was."""
    from armanim.scene.meshcapsules import mesh_capsules
    from armanim.scene.urdf import read_urdf

    robot = read_urdf(robot_dir / "meshy.urdf")
    shutil.copytree(meshy_fits, tmp_path / "c")  # the three fits, as a fit of them keeps them
    mine, hard = tmp_path / "mine.json", tmp_path / "hard.json"
    mine.write_text('{"mine": 1}')
    hard.write_text('{"mine": 2}')
    soft_entry, hard_entry, *_ = sorted((tmp_path / "c").glob("*.json"))
    soft_entry.unlink()
    soft_entry.symlink_to(mine)
    hard_entry.unlink()
    os.link(hard, hard_entry)
    again = mesh_capsules(robot, LINKS, robot_dir, [tmp_path], cache=tmp_path / "c")
    assert again.cached == 1  # the third entry; the two others are fitted again
    assert (mine.read_text(), hard.read_text()) == ('{"mine": 1}', '{"mine": 2}')
    assert soft_entry.is_symlink() and os.readlink(soft_entry) == str(mine)
    assert not hard_entry.samefile(hard)  # a fit kept at a new file


def test_an_unwritable_cache_folder_means_no_cache(tmp_path, monkeypatch):
    from armanim.scene.meshcapsules import cache_folder

    blocker = tmp_path / "file"
    blocker.write_text("")
    monkeypatch.setenv("ARMANIM_CACHE_DIR", str(blocker / "cache"))
    assert cache_folder() is None
    monkeypatch.setenv("ARMANIM_CACHE_DIR", str(tmp_path / "ok"))
    assert cache_folder() == tmp_path / "ok"
    monkeypatch.delenv("ARMANIM_CACHE_DIR")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert cache_folder() == tmp_path / "xdg" / "armanim" / "capsules"


def test_a_cache_folder_inside_the_run_folder_is_named_as_the_cause(robot_dir, tmp_path, monkeypatch, meshy_fits):
    """ARMANIM_CACHE_DIR inside the run folder (issue 50, after campaign 13): the fit's cache makes
    the folder hold a file its marker does not list, so the run refuses it (exit 3), as any file the
    user put there; the message said "holds files armanim did not write", though they are
    armanim's own. It now names the cache and the remedy; a user's own folder is told as before."""
    from armanim.errors import OutputError
    from armanim.runs.options import RunOptions
    from armanim.runs.pipeline import run_scene

    out = tmp_path / "out"
    run_folder = out / "s"
    monkeypatch.setenv("ARMANIM_CACHE_DIR", str(run_folder / "cache"))
    for _ in range(2):  # the first run makes the cache, in the folder it will swap: refused at once, and again
        with pytest.raises(OutputError) as refused:
            run_scene(_scene(robot_dir), out, RunOptions(video=False))
        message = str(refused.value)
        assert "ARMANIM_CACHE_DIR" in message and "outside every run folder" in message, message
        assert str(run_folder / "cache") in message and "capsule-fit cache" in message
    shutil.copytree(meshy_fits, tmp_path / "elsewhere")  # the fits, as a cache outside kept them: none fitted again
    monkeypatch.setenv("ARMANIM_CACHE_DIR", str(tmp_path / "elsewhere"))
    assert "ARMANIM_CACHE_DIR" not in _refusal(robot_dir, out)  # the cache is no longer there: a plain refusal


def _refusal(robot_dir: Path, out: Path) -> str:
    from armanim.errors import OutputError
    from armanim.runs.options import RunOptions
    from armanim.runs.pipeline import run_scene

    with pytest.raises(OutputError) as refused:
        run_scene(_scene(robot_dir), out, RunOptions(video=False))
    return str(refused.value)


def test_a_missing_collision_mesh_is_an_error_at_its_line(robot_dir):
    (robot_dir / "meshes" / "base.stl").unlink()
    with pytest.raises(SceneError) as info:
        load_scene(_scene(robot_dir))
    report = info.value.report()
    assert "meshy.urdf:2: link 'base': collision mesh 'meshes/base.stl' not found" in report


@pytest.mark.parametrize("scale", ["nan 1 1", "1 1", "inf 1 1", "1 one 1"])
def test_a_collision_mesh_whose_scale_cannot_be_read_is_an_error_at_its_line(robot_dir, scale):
    """Campaign 5: a collision mesh with ``scale="nan 1 1"`` or ``"1 1"`` was left out without a
    word, and its link got a joint-to-joint capsule of arm.width / 2 (the note blamed "no primitive,
    no mesh"): a collision model that is not the robot. Now an error at its URDF line."""
    (robot_dir / "meshy.urdf").write_text(URDF.replace('scale="1.5 1.0 0.5"', f'scale="{scale}"'))
    with pytest.raises(SceneError) as info:
        load_scene(_scene(robot_dir))
    assert (
        f"meshy.urdf:2: link 'base': collision mesh 'meshes/base.stl': its scale={scale!r}, origin xyz='0.01 -0.02 0.03', "
        "origin rpy='0.3 -0.2 0.5' must be three finite numbers each"
    ) in info.value.report()


@pytest.mark.parametrize(
    ("corners", "words"),
    [
        (
            "nan",
            "the file holds corners that are not finite numbers",
        ),  # the sixth campaign: blamed on a scale it did not have
        (
            "far",
            "its vertices lie up to 1.34e+30 from the link's frame (expected at most 1e+09",
        ),  # a capsule of 8e28 m (scaled, turned)
    ],
)
def test_a_collision_mesh_whose_corners_cannot_be_a_link_is_an_error_at_its_line(robot_dir, corners, words):
    box = trimesh.creation.box(extents=(0.06, 0.06, 0.3))
    vertices = box.vertices.copy()
    vertices[0] = np.nan if corners == "nan" else 1e30
    trimesh.Trimesh(vertices, box.faces, process=False).export(robot_dir / "meshes" / "base.stl")
    with pytest.raises(SceneError) as info:
        load_scene(_scene(robot_dir))
    assert f"meshy.urdf:2: link 'base': collision mesh 'meshes/base.stl': {words}" in info.value.report()


@pytest.mark.parametrize("kind", ["fifo", "folder"])
def test_a_collision_mesh_that_is_no_regular_file_is_said_so_at_its_line(robot_dir, kind):
    """The sixth campaign: a FIFO or a folder was "not found", with advice about package_dirs."""
    import os

    target = robot_dir / "meshes" / "base.stl"
    target.unlink()
    os.mkfifo(target) if kind == "fifo" else target.mkdir()
    with pytest.raises(SceneError) as info:
        load_scene(_scene(robot_dir))
    assert "meshy.urdf:2: link 'base': collision mesh 'meshes/base.stl' is not a regular file (" in info.value.report()


def _collada(mesh: trimesh.Trimesh, unit: str, per_metre: float) -> str:
    """``mesh`` as a COLLADA file whose numbers are ``per_metre`` units a metre, declared as ``<unit meter="unit">``."""
    points = " ".join(repr(float(v)) for v in (np.asarray(mesh.vertices) * per_metre).ravel())
    faces = " ".join(str(int(i)) for i in np.asarray(mesh.faces).ravel())
    return f"""<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
<asset><unit name="u" meter="{unit}"/><up_axis>Y_UP</up_axis></asset>
<library_geometries><geometry id="g"><mesh>
<source id="p"><float_array id="pa" count="{3 * len(mesh.vertices)}">{points}</float_array>
<technique_common><accessor source="#pa" count="{len(mesh.vertices)}" stride="3"><param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source>
<vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
<triangles count="{len(mesh.faces)}"><input semantic="VERTEX" source="#v" offset="0"/><p>{faces}</p></triangles>
</mesh></geometry></library_geometries>
<library_visual_scenes><visual_scene id="s"><node id="n"><instance_geometry url="#g"/></node></visual_scene></library_visual_scenes>
<scene><instance_visual_scene url="#s"/></scene>
</COLLADA>
"""


def _capsule_rows(scene, link: str) -> list[tuple]:
    return [(tuple(c.start), tuple(c.end), c.radius) for c in scene.model.arm.urdf_arm.capsules if c.link == link]


def test_a_collada_mesh_in_millimetres_is_fitted_in_metres(robot_dir):
    """The sixth campaign: ``<unit meter="0.001">`` was ignored and a millimetre mesh read as metres
    (a base 1,000 times its size). The base as a COLLADA file in millimetres, and in inches, gets
    the capsules of the same base in metres (as an STL, the fixture's); its ``<up_axis>`` (Y_UP) is
    not applied, as RViz does not; pinocchio's loader (assimp, as coal builds it) reads such a
    file's numbers as they are written (measured: 100 of a mm file is 100), so the oracle is the
    STL."""
    metres = _capsule_rows(load_scene(_scene(robot_dir)), "base")
    base = _meshes()["base.stl"]
    for unit, per_metre in (("0.001", 1000.0), ("0.0254", 1 / 0.0254), ("1", 1.0)):
        (robot_dir / "meshes" / "base.dae").write_text(_collada(base, unit, per_metre))
        (robot_dir / "meshy.urdf").write_text(URDF.replace("meshes/base.stl", "meshes/base.dae"))
        rows = _capsule_rows(load_scene(_scene(robot_dir, name=f"s{unit}.yaml")), "base")
        assert len(rows) == len(metres), unit
        np.testing.assert_allclose(
            np.array([[*a, *b, r] for a, b, r in rows]),
            np.array([[*a, *b, r] for a, b, r in metres]),
            rtol=0,
            atol=1e-9,
            err_msg=unit,
        )


@pytest.mark.parametrize("unit", ["0", "-0.001", "nan", "1e300", "1e-300", "abc", "", "1_000"])
def test_a_collada_unit_that_is_no_unit_is_an_error_at_its_line(robot_dir, unit):
    (robot_dir / "meshes" / "base.dae").write_text(_collada(_meshes()["base.stl"], unit, 1.0))
    (robot_dir / "meshy.urdf").write_text(URDF.replace("meshes/base.stl", "meshes/base.dae"))
    with pytest.raises(SceneError) as info:
        load_scene(_scene(robot_dir))
    assert (
        f"meshy.urdf:2: link 'base': collision mesh 'meshes/base.dae' could not be read (ValueError: its <unit meter={unit!r}> is not "
        "a number of metres per unit from 1e-06 (micrometres) to 1000 (kilometres)"
    ) in info.value.report()


def test_an_obj_face_of_a_twenty_digit_vertex_number_is_an_error_at_its_line(robot_dir):
    """The sixth campaign: numpy's OverflowError was the message."""
    text = (robot_dir / "meshes" / "upper.obj").read_text()
    (robot_dir / "meshes" / "upper.obj").write_text(text + "f 1 2 99999999999999999999\n")
    with pytest.raises(SceneError) as info:
        load_scene(_scene(robot_dir))
    assert "a face names a vertex the OBJ file does not have" in info.value.report()
    assert "OverflowError" not in info.value.report()


def test_a_collision_mesh_of_another_format_is_an_error(robot_dir):
    (robot_dir / "meshy.urdf").write_text(URDF.replace("meshes/base.stl", "meshes/base.ply"))
    with pytest.raises(
        SceneError, match=r"meshy.urdf:2: link 'base': collision mesh 'meshes/base.ply' is not a format armanim reads"
    ):
        load_scene(_scene(robot_dir))


def test_meshes_over_the_readers_limits_are_errors(robot_dir, monkeypatch):
    import armanim.scene.visuals as visuals

    monkeypatch.setattr(visuals, "MAX_MESH_BYTES", 1000)
    with pytest.raises(
        SceneError, match=r"meshy.urdf:2: link 'base': collision mesh 'meshes/base.stl' could not be read \(.*more than"
    ):
        load_scene(_scene(robot_dir))
    monkeypatch.undo()
    monkeypatch.setattr(visuals, "MAX_LOOK_TRIANGLES", 60)  # the base's 92 triangles are over
    with pytest.raises(SceneError, match=r"the robot's meshes hold more than 60 triangles in all"):
        load_scene(_scene(robot_dir))


def test_a_missing_visual_mesh_falls_back_to_the_joint_capsule_with_notes(robot_dir):
    (robot_dir / "meshes" / "fore.stl").unlink()
    scene = load_scene(_scene(robot_dir))
    assert scene.model.arm.urdf_arm.fallback_links == ("fore",)
    notes = " ".join(n.message for n in scene.notes)
    assert (
        "link 'fore': visual mesh 'meshes/fore.stl' not found" in notes
        and "links fore have no collision geometry" in notes
    )


def test_a_run_writes_capsules_yaml_that_a_scene_takes_as_its_collision(robot_dir, tmp_path):
    from armanim.runs.options import RunOptions
    from armanim.runs.pipeline import run_scene

    result = run_scene(_scene(robot_dir), tmp_path / "out", RunOptions(video=False))
    text = (result.folder / "capsules.yaml").read_text()
    listed = yaml.safe_load(text)["collision"]
    solved = result.problem.capsules
    assert len(listed) == len(solved) == len(load_scene(_scene(robot_dir)).model.arm.urdf_arm.capsules)
    block = "  collision:\n" + "".join(f"    - {line[4:]}\n" for line in text.splitlines() if line.startswith("  - "))
    copied = load_scene(_scene(robot_dir, block, "copied.yaml"))
    again = scene_to_problem(copied.model).capsules
    for name in ("link", "start", "end", "radius"):
        np.testing.assert_array_equal(getattr(again, name), getattr(solved, name))
    moved = tmp_path / "moved"  # the run folder alone, away from the meshes: render and view read capsules.yaml back
    result.folder.rename(moved)
    from armanim.runs.reload import load_run

    back = load_run(moved)
    np.testing.assert_array_equal(back.problem.capsules.radius, solved.radius)


def test_collision_fitted_is_a_bundled_robots_own_and_an_error_for_your_urdf(robot_dir):
    from armanim.scene import scene_model

    panda = scene_model({"version": 1, "arm": {"robot": "panda", "collision": "fitted"}, "goals": [[0.5, 0, 0.5]]})
    names = {c.link for c in panda.arm.urdf_arm.capsules}
    assert {"panda_link0", "panda_link7", "panda_hand", "panda_leftfinger"} <= names
    with pytest.raises(SceneError, match="collision: fitted is a bundled robot's set"):
        load_scene(_scene(robot_dir, "  collision: fitted\n"))


def test_the_bundled_fitted_sets_hold_their_shipped_meshes():
    """Each bundled robot's fitted-capsules.yaml holds every vertex of the meshes it ships."""
    from importlib import resources

    from armanim.scene.robots import bundled_fitted
    from armanim.scene.visuals import bundled_link_meshes

    for name in ("panda", "ur5", "iiwa"):
        capsules = bundled_fitted(name)
        folder = Path(str(resources.files("armanim.arm").joinpath("robots", name)))
        for mesh in bundled_link_meshes(folder):
            mine = [
                type("C", (), {"start": c["from"], "end": c["to"], "radius": c["radius"]})
                for c in capsules
                if c["link"] == mesh.link
            ]
            assert 1 <= len(mine) <= 3, (name, mesh.link)
            assert _held(mesh.vertices, mine) <= 1e-9, (name, mesh.link)


@pytest.mark.slow
def test_robots_fit_through_the_installed_command(robot_dir):
    exe = Path(sys.executable).parent / "armanim"
    command = [str(exe)] if exe.exists() else [sys.executable, "-m", "armanim"]
    proc = subprocess.run(
        [*command, "robots", "--fit", str(robot_dir / "meshy.urdf")], capture_output=True, text=True, timeout=120
    )
    assert proc.returncode == 0, proc.stderr
    listed = yaml.safe_load(proc.stdout)["collision"]
    assert {c["link"] for c in listed} == {"base", "upper", "fore", "tip"}
    assert proc.stdout.startswith("# Collision capsules of meshy.urdf")
    missing = subprocess.run(
        [*command, "robots", "--fit", str(robot_dir / "nope.urdf")], capture_output=True, text=True, timeout=120
    )
    assert missing.returncode == 2 and "nope.urdf: no such file" in missing.stderr
    helped = subprocess.run([*command, "robots", "--help"], capture_output=True, text=True, timeout=120)
    assert "--fit" in helped.stdout and "armanim robots --fit" in helped.stdout


def test_a_urdf_link_in_an_obstacle_is_named_by_its_link(robot_dir):
    path = robot_dir / "hit.yaml"
    path.write_text(
        "version: 1\narm:\n  urdf: meshy.urdf\n  tip_link: tip\ngoals:\n  - [0.3, 0.1, 0.5]\n"
        "obstacles:\n  - {center: [0, 0, 0.4], radius: 0.01}\n"
    )
    with pytest.raises(
        SceneError, match=r"hit.yaml:8: obstacles\[0\]: link 'upper' of the arm's home pose is inside this obstacle"
    ):
        load_scene(path)
