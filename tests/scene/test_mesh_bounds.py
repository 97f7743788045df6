"""Mesh files and everything they name are bounded (issue 50, items 1, 2, 3 and 9): only the
documented formats, no archive inflated, no file a mesh names opened (a FIFO there cannot hang a
run), a COLLADA instance bomb counted and refused before it is expanded, one file read once
however many links name it, the bytes of a robot's look bounded in all, and an interrupt a
library swallows still ends the run with 130 and no outputs."""

from __future__ import annotations

import io
import os
import subprocess
import sys
import textwrap
import zipfile
from pathlib import Path

import numpy as np
import pytest

trimesh = pytest.importorskip("trimesh")

SRC = Path(__file__).resolve().parents[2] / "src"
HANG_GUARD = 300  # seconds: a subprocess that still waits then is hanging (it takes a few seconds)


def _urdf(folder: Path, visuals: str, links: int = 1) -> Path:
    """A URDF of ``links`` links, each with ``visuals``."""
    body = "".join(f'<link name="l{i}">{visuals}</link>' for i in range(links))
    path = folder / "r.urdf"
    path.write_text(f'<robot name="r">{body}</robot>')
    return path


def _read(path: Path):
    from armanim.scene.visuals import link_meshes, visual_specs

    notes: list[str] = []
    meshes = link_meshes(
        visual_specs(path.read_bytes(), str(path), notes.append), path.parent, [path.parent], notes.append
    )
    return meshes, notes


def _mesh(name: str) -> str:
    return f'<visual><geometry><mesh filename="{name}"/></geometry></visual>'


def test_only_the_documented_formats_are_read_and_no_archive_is_opened(tmp_path):
    box = trimesh.creation.box()
    box.export(tmp_path / "box.STL")  # the suffix in any case
    with zipfile.ZipFile(tmp_path / "a.zip", "w") as archive:
        archive.writestr("a.stl", box.export(file_type="stl"))
    with zipfile.ZipFile(tmp_path / "z.dae", "w") as archive:  # pycollada opens a zip named .dae and inflates it
        archive.writestr("inner.dae", box.export(file_type="dae"))
    box.export(tmp_path / "a.ply")
    box.export(tmp_path / "a.glb")
    names = ["box.STL", "a.zip", "z.dae", "a.ply", "a.glb"]
    (mesh,), notes = _read(_urdf(tmp_path, "".join(_mesh(n) for n in names)))
    assert mesh.triangles == 12  # the STL alone
    assert len(notes) == 4, notes
    for name, note in zip(names[1:], notes):
        assert name in note, (name, note)
    assert "not a format armanim reads" in notes[0] and "archives are never opened" in notes[0]
    assert "zip archive" in notes[1] and "does not inflate" in notes[1]


def _in_a_subprocess(script: str, cwd: Path) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": str(SRC)}
    return subprocess.run(
        [sys.executable, "-c", textwrap.dedent(script)],
        cwd=cwd,
        env=env,
        capture_output=True,
        text=True,
        timeout=HANG_GUARD,
    )


def test_a_fifo_a_mesh_names_is_never_opened(tmp_path):
    """An OBJ whose ``mtllib`` and texture are FIFOs, and the same OBJ as ``arm.tool.mesh``: the
    OBJ is drawn in its URDF colour and the FIFOs never opened (trimesh's resolver opened them
    and waited for a writer for ever); a glTF (whose buffer is a FIFO) is not a format armanim reads."""
    (tmp_path / "a.obj").write_text("mtllib m.mtl\nv 0 0 0\nv 0.05 0 0\nv 0 0.05 0\nusemtl x\nf 1 2 3\n")
    (tmp_path / "m.mtl").unlink(missing_ok=True)
    os.mkfifo(tmp_path / "m.mtl")
    os.mkfifo(tmp_path / "b.bin")
    (tmp_path / "a.gltf").write_text('{"asset":{"version":"2.0"},"buffers":[{"uri":"b.bin","byteLength":36}]}')
    _urdf(tmp_path, _mesh("a.obj") + _mesh("a.gltf"))
    done = _in_a_subprocess(
        """
        from pathlib import Path
        from types import SimpleNamespace
        from armanim.scene.looks import tool_meshes
        from armanim.scene.visuals import link_meshes, visual_specs
        path = Path("r.urdf")
        notes = []
        meshes = link_meshes(visual_specs(path.read_bytes(), str(path)), Path("."), [Path(".")], notes.append)
        tool = SimpleNamespace(xyz=[0, 0, 0], rpy=[0, 0, 0], pen=None, mesh="a.obj", gripper=None)
        parts = tool_meshes(tool, "l0", Path("."), notes.append)
        print(sum(m.triangles for m in meshes), sum(p.triangles for p in parts))
        print(*notes, sep="\\n")
        """,
        tmp_path,
    )
    assert done.returncode == 0, done.stderr
    counts, *notes = done.stdout.splitlines()
    assert counts == "1 1"
    assert len(notes) == 1 and "a.gltf" in notes[0] and "not a format armanim reads" in notes[0]


def test_a_visual_or_tool_mesh_that_is_no_regular_file_is_said_so_and_never_opened(tmp_path):
    """The sixth campaign: a FIFO, a folder or a device named as a visual mesh or as
    ``arm.tool.mesh`` was "not found" (and its note advised package_dirs); it is "not a regular
    file", as a collision mesh's is, and the FIFO is never opened (the subprocess would wait for a
    writer). A name with nothing there is still "not found"."""
    os.mkfifo(tmp_path / "pipe.stl")
    (tmp_path / "folder.stl").mkdir()
    os.symlink("/dev/null", tmp_path / "device.stl")
    names = ["pipe.stl", "folder.stl", "device.stl", "absent.stl"]
    _urdf(tmp_path, "".join(_mesh(n) for n in names))
    done = _in_a_subprocess(
        f"""
        from pathlib import Path
        from types import SimpleNamespace
        from armanim.scene.looks import tool_meshes
        from armanim.scene.visuals import link_meshes, visual_specs
        path = Path("r.urdf")
        notes = []
        link_meshes(visual_specs(path.read_bytes(), str(path)), Path("."), [Path(".")], notes.append)
        for name in {names!r}:
            tool = SimpleNamespace(xyz=[0, 0, 0], rpy=[0, 0, 0], pen=None, mesh=name, gripper=None)
            assert tool_meshes(tool, "l0", Path("."), notes.append) == []
        print(*notes, sep="\\n")
        """,
        tmp_path,
    )
    assert done.returncode == 0, done.stderr
    notes = done.stdout.splitlines()
    assert len(notes) == 8, notes
    kinds = {"pipe.stl": "a FIFO (named pipe)", "folder.stl": "a folder", "device.stl": "a character device"}
    for visual, tool, name in zip(notes[:4], notes[4:], names):
        assert visual.startswith(f"link 'l0': mesh {name!r} ") and visual.endswith(": drawn as its capsules"), visual
        assert tool.startswith(f"arm.tool.mesh: {name!r} ") and tool.endswith(": the tool is not drawn"), tool
        for note in (visual, tool):
            if name in kinds:
                assert (
                    f"is not a regular file ({name} is {kinds[name]}: never read" in note and "not found" not in note
                ), note
            else:
                assert "not found" in note and "regular" not in note, note
    assert "package_dirs" in notes[3] and "package_dirs" not in notes[0]


def _dae(nodes: str, top: str, triangles: int = 1) -> str:
    """A COLLADA file with one geometry of ``triangles`` triangles (``g``), the library nodes
    ``nodes`` and a scene of one node instancing ``top``."""
    points = " ".join(f"{i * 0.01} 0 0 {i * 0.01} 0.05 0 {i * 0.01 + 0.01} 0 0" for i in range(triangles))
    return f'''<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
<asset><unit name="meter" meter="1"/><up_axis>Z_UP</up_axis></asset>
<library_geometries><geometry id="g"><mesh>
<source id="p"><float_array id="pa" count="{9 * triangles}">{points}</float_array>
<technique_common><accessor source="#pa" count="{3 * triangles}" stride="3"><param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source>
<vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
<triangles count="{triangles}"><input semantic="VERTEX" source="#v" offset="0"/><p>{" ".join(map(str, range(3 * triangles)))}</p></triangles>
</mesh></geometry></library_geometries><library_nodes>{nodes}</library_nodes>
<library_visual_scenes><visual_scene id="s"><node id="top"><instance_node url="#{top}"/></node></visual_scene></library_visual_scenes>
<scene><instance_visual_scene url="#s"/></scene></COLLADA>'''


def _instancing(levels: int, copies: int) -> str:
    """Node ``n0`` holds the geometry; each ``n(k+1)`` instances ``n(k)`` ``copies`` times."""
    return '<node id="n0"><instance_geometry url="#g"/></node>' + "".join(
        f'<node id="n{k + 1}">' + f'<instance_node url="#n{k}"/>' * copies + "</node>" for k in range(levels)
    )


def test_a_collada_instance_bomb_is_refused_before_it_is_expanded(tmp_path, monkeypatch):
    """Nodes that instance each other are counted, weighted by their triangles, over the graph:
    1,000 copies of a 3,000-triangle geometry (3 million placed) and the campaign's 3 KB bomb
    (10 copies, 7 levels deep: 10 million) are refused without placing one triangle; 100 copies
    of 3,000 are placed, each where its nodes put it."""
    (tmp_path / "fine.dae").write_text(_dae(_instancing(2, 10), "n2", triangles=3000))
    (tmp_path / "big.dae").write_text(_dae(_instancing(3, 10), "n3", triangles=3000))
    (tmp_path / "bomb.dae").write_text(_dae(_instancing(7, 10), "n7"))
    from armanim.scene import meshfiles
    from armanim.scene.visuals import MeshReader

    meshes, notes = _read(_urdf(tmp_path, _mesh("big.dae")))
    assert meshes == [] and len(notes) == 1 and "place 3,002,112 triangles and instances" in notes[0], notes
    placed = []
    monkeypatch.setattr(meshfiles, "_place", lambda *args: placed.append(args))
    meshes, notes = _read(_urdf(tmp_path, _mesh("bomb.dae")))
    assert meshes == [] and len(notes) == 1 and "place 31,111,112 triangles and instances" in notes[0] and placed == []
    monkeypatch.undo()
    fine = MeshReader(None).triangles(tmp_path / "fine.dae")
    assert fine.triangles == 100 * 3000
    assert np.allclose(fine.vertices.min(axis=0), [0.0, 0.0, 0.0]) and np.allclose(
        fine.vertices.max(axis=0), [30.0, 0.05, 0.0]
    )


def test_a_collada_file_of_too_many_elements_is_refused_before_it_is_parsed(tmp_path, monkeypatch):
    """Campaign 9: a COLLADA file of 300,000 nodes (18 MB, 300,000 triangles: within every other
    bound) took some 30 s of CPU in pycollada and armanim's placing, and an interrupt waited for
    pycollada's one call (4 s late). Its elements are counted in its bytes first: more than
    MAX_DAE_ELEMENTS is a note, pycollada never called; a file at the bound is read."""
    import collada

    from armanim.scene.meshfiles import MAX_DAE_ELEMENTS, read_mesh

    nodes = '<node id="n0"><instance_geometry url="#g"/></node>'
    many = "".join(f'<node id="m{i}"><instance_node url="#n0"/></node>' for i in range(MAX_DAE_ELEMENTS // 2))
    (tmp_path / "many.dae").write_text(_dae(nodes + many, "n0"))
    parsed = []
    real = collada.Collada
    monkeypatch.setattr(collada, "Collada", lambda *args, **kwargs: parsed.append(1) or real(*args, **kwargs))
    meshes, notes = _read(_urdf(tmp_path, _mesh("many.dae")))
    assert meshes == [] and len(notes) == 1 and parsed == [], notes
    assert "its reader cannot be interrupted while it builds them" in notes[0]  # (the note is cut to one line)
    from xml.etree import ElementTree

    elements = sum(1 for _ in ElementTree.parse(tmp_path / "many.dae").iter())  # the parser's own count
    with pytest.raises(ValueError, match=f"holds {elements:,} XML elements \\(at most 100,000 in one COLLADA file"):
        read_mesh((tmp_path / "many.dae").read_bytes(), "dae")
    fewer = "".join(f'<node id="m{i}"><instance_node url="#n0"/></node>' for i in range(MAX_DAE_ELEMENTS // 2 - 20))
    (tmp_path / "fewer.dae").write_text(_dae(nodes + fewer, "n0"))
    meshes, notes = _read(_urdf(tmp_path, _mesh("fewer.dae")))
    assert notes == [] and parsed == [1]


def test_one_file_named_by_three_links_is_read_once(tmp_path, monkeypatch):
    """Three links name one STL of 100,000 triangles: it is read once, simplified as it is read
    (the look draws at most TRIANGLE_BUDGET), and each link draws it."""
    from armanim.scene import visuals

    sphere = trimesh.creation.icosphere(subdivisions=6)  # 81,920 triangles
    sphere.export(tmp_path / "big.stl")
    reads = []
    real = visuals.read_bounded
    monkeypatch.setattr(visuals, "read_bounded", lambda path, *args: reads.append(Path(path).name) or real(path, *args))
    meshes, notes = _read(_urdf(tmp_path, _mesh("big.stl") + _mesh("./big.stl"), links=3))
    assert notes == [] and reads == ["big.stl"]
    assert [m.link for m in meshes] == ["l0", "l1", "l2"]
    assert sum(m.triangles for m in meshes) <= visuals.TRIANGLE_BUDGET * 1.05
    assert all(np.allclose(np.linalg.norm(m.vertices, axis=1), 1.0, atol=0.03) for m in meshes)


def test_hard_links_of_one_file_are_read_once(tmp_path, monkeypatch):
    """Links naming one file by its hard links (one inode, several names) read it once, and its
    bytes count once against MAX_LOOK_BYTES (campaign 18: five hard links of a 60 MB OBJ were
    read five times, and the fifth was left out, past 256 MB)."""
    from armanim.scene import visuals

    trimesh.creation.box().export(tmp_path / "a.stl")  # 684 bytes
    for name in ("b.stl", "c.stl"):
        os.link(tmp_path / "a.stl", tmp_path / name)
    monkeypatch.setattr(visuals, "MAX_LOOK_BYTES", 684 + 100)
    reads = []
    real = visuals.read_bounded
    monkeypatch.setattr(visuals, "read_bounded", lambda path, *args: reads.append(Path(path).name) or real(path, *args))
    (mesh,), notes = _read(_urdf(tmp_path, _mesh("a.stl") + _mesh("b.stl") + _mesh("c.stl")))
    assert notes == [] and reads == ["a.stl"]
    assert mesh.triangles == 3 * 12


def test_the_bytes_of_a_look_are_bounded_in_all(tmp_path, monkeypatch):
    """Each file's size counts once against MAX_LOOK_BYTES: past it, a mesh is a note, unread."""
    from armanim.scene import visuals

    for name in ("a", "b", "c"):
        trimesh.creation.box().export(tmp_path / f"{name}.stl")  # 684 bytes each
    monkeypatch.setattr(visuals, "MAX_LOOK_BYTES", 2 * 684 + 100)
    (mesh,), notes = _read(_urdf(tmp_path, _mesh("a.stl") + _mesh("b.stl") + _mesh("a.stl") + _mesh("c.stl")))
    assert mesh.triangles == 3 * 12
    assert len(notes) == 1 and "c.stl" in notes[0] and "684 bytes, more than the 100 left to read" in notes[0], notes


@pytest.mark.filterwarnings("error")  # no numpy RuntimeWarning on stderr either (a traceback under -W error)
def test_no_corner_that_is_not_finite_is_kept_even_one_no_triangle_uses(tmp_path):
    """Campaign 18: an OBJ's ``v nan nan nan`` and ``v 1e309 0 0`` beside a good triangle, and a
    corner of 1e300 under a visual's scale of 1e9 (inf), left out their triangles but stayed among
    the mesh's vertices, and ``run --viewer`` ended in a traceback (``Out of range float values are
    not JSON compliant``). The corners no triangle keeps are dropped, the faces renumbered."""
    from armanim.render.viewer.page import json_text

    (tmp_path / "n.obj").write_text("v 0 0 0\nv .05 0 0\nv 0 .05 0\nf 1 2 3\nv nan nan nan\nv 1e309 0 0\nf 4 5 1\n")
    (tmp_path / "b.obj").write_text("v 0 0 0\nv .05 0 0\nv 0 .05 0\nv 1e300 0 0\nf 1 2 3\nf 1 2 4\n")
    scaled = '<visual><geometry><mesh filename="b.obj" scale="1e9 1e9 1e9"/></geometry></visual>'
    (mesh,), notes = _read(_urdf(tmp_path, _mesh("n.obj") + scaled))
    assert notes == [] and mesh.triangles == 2
    assert np.isfinite(mesh.vertices).all() and mesh.faces.max() < len(mesh.vertices)
    json_text(mesh.vertices.tolist())  # what the viewer writes: strict JSON
    from armanim.scene.looks import _tool_file

    tool = _tool_file("n.obj", "l0", tmp_path / "n.obj", notes.append, None)  # arm.tool.mesh, alike
    assert notes == [] and tool is not None and tool.triangles == 1 and np.isfinite(tool.vertices).all()


def test_obj_vertex_lines_of_two_numbers_are_a_note_never_other_corners(tmp_path):
    """Campaign 19: an OBJ whose six ``v`` lines hold two numbers each was read as four corners of
    three (the twelve numbers reshaped), and its face ``f 1 2 3`` drawn from them. Now a note, as a
    ``v`` line of two numbers among others of three always was; CRLF line ends and tabs still read."""
    (tmp_path / "two.obj").write_text("v 0 0\nv 1 0\nv 0 1\nv 1 1\nv 2 2\nv 3 3\nf 1 2 3\n")
    (tmp_path / "crlf.obj").write_bytes(b"v\t0\t0\t0\r\nv .05 0 0\r\nv 0 .05 0\r\nf 1 2 3\r\n")
    (mesh,), notes = _read(_urdf(tmp_path, _mesh("two.obj") + _mesh("crlf.obj")))
    assert mesh.triangles == 1 and len(notes) == 1 and "does not hold three numbers" in notes[0], notes


def test_special_and_broken_mesh_files_are_notes(tmp_path):
    """A FIFO or a folder named as the mesh, a garbage STL (no charset module named), an OBJ face
    naming a vertex it lacks, NaN corners (their triangles left out): notes or fewer triangles."""
    os.mkfifo(tmp_path / "f.stl")
    (tmp_path / "d.obj").mkdir()
    (tmp_path / "g.stl").write_bytes(bytes(range(256)) * 3)
    (tmp_path / "o.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n")
    (tmp_path / "n.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv nan 0 0\nf 1 2 3\nf 1 2 4\n")
    (mesh,), notes = _read(_urdf(tmp_path, "".join(_mesh(n) for n in ("f.stl", "d.obj", "g.stl", "o.obj", "n.obj"))))
    assert mesh.triangles == 1
    assert len(notes) == 4 and "is not a regular file" in notes[0] and "is not a regular file" in notes[1], notes
    assert "not an STL file" in notes[2] and "charset" not in notes[2]
    assert "names a vertex" in notes[3]


def test_an_interrupt_a_library_swallows_still_ends_the_run_with_130(tmp_path):
    """A Ctrl-C (a real SIGINT, to armanim's own handler) while pycollada reads a COLLADA file,
    swallowed by a library's ``except BaseException`` as trimesh's OBJ material read did: the run
    still ends as interrupted, exit 130, and writes nothing."""
    trimesh.creation.box().export(tmp_path / "a.dae")
    _urdf(tmp_path, _mesh("a.dae"))
    (tmp_path / "r.urdf").write_text(
        '<robot name="r"><link name="l0"/><joint name="j0" type="revolute"><parent link="l0"/><child link="l1"/>'
        '<origin xyz="0 0 0.1"/><axis xyz="0 0 1"/><limit lower="-2" upper="2" effort="1" velocity="1"/></joint>'
        f'<link name="l1">{_mesh("a.dae")}<collision><geometry><cylinder radius="0.03" length="0.3"/></geometry>'
        '<origin xyz="0 0 0.15"/></collision></link>'
        '<joint name="j1" type="revolute"><parent link="l1"/><child link="l2"/><origin xyz="0 0 0.3"/><axis xyz="0 1 0"/>'
        '<limit lower="-2" upper="2" effort="1" velocity="1"/></joint><link name="l2"><collision><geometry>'
        '<cylinder radius="0.03" length="0.3"/></geometry><origin xyz="0 0 0.15"/></collision></link></robot>'
    )
    (tmp_path / "s.yaml").write_text(
        "version: 1\nname: m\narm: {urdf: r.urdf}\ngoals: [[0.2, 0.1, 0.3]]\nrender: {size: [160, 90], fps: 10}\n"
    )
    done = _in_a_subprocess(
        """
        import os, signal, sys
        import collada
        real = collada.Collada.__init__
        def swallowing(self, *args, **kwargs):
            try:
                os.kill(os.getpid(), signal.SIGINT)  # armanim's handler raises KeyboardInterrupt here
            except BaseException:  # as trimesh and pycollada do in places
                pass
            real(self, *args, **kwargs)  # ... and the file is read all the same
        collada.Collada.__init__ = swallowing
        sys.argv = ["armanim", "run", "s.yaml", "--out", "o", "--no-video", "--viewer", "--quiet"]
        from armanim.__main__ import main
        main()
        """,
        tmp_path,
    )
    assert done.returncode == 130, (done.returncode, done.stderr)
    assert done.stderr.strip().splitlines()[-1] == "armanim: interrupted; nothing half-written was left behind"
    assert "Traceback" not in done.stderr
    out = tmp_path / "o"
    assert not (out / "m").exists() and not any(".partial" in p.name for p in out.glob(".*"))


def test_the_readers_agree_with_trimesh_on_its_own_exports(tmp_path):
    """STL (binary and ASCII), OBJ and COLLADA read by armanim give trimesh's triangles (the
    oracle: the same surface, area and bounds) for a shape with faces of every direction."""
    from armanim.scene.meshfiles import read_mesh

    shape = trimesh.creation.annulus(r_min=0.2, r_max=0.5, height=0.3, sections=17)
    for kind, data in (
        ("stl", shape.export(file_type="stl")),
        ("stl", shape.export(file_type="stl_ascii").encode()),
        ("obj", shape.export(file_type="obj").encode()),
        ("dae", shape.export(file_type="dae")),
    ):
        vertices, faces, _ = read_mesh(data if isinstance(data, bytes) else data.encode(), kind)
        mine = trimesh.Trimesh(vertices, faces, process=False)
        theirs = trimesh.load(io.BytesIO(data), file_type=kind, force="mesh")
        assert len(faces) == len(theirs.faces), kind
        assert np.isclose(mine.area, theirs.area, rtol=1e-6), kind
        assert np.allclose(mine.bounds, theirs.bounds, atol=1e-6), kind


def test_a_mesh_whose_every_corner_is_not_finite_says_so(tmp_path):
    """Campaign 5: an ASCII STL whose one triangle has NaN and infinite corners (``1e400``) was
    noted as ``no triangles``; it holds one, each corner left out for a reason the note now gives."""
    (tmp_path / "a.stl").write_text(
        "solid a\nfacet normal 0 0 1\nouter loop\nvertex nan 0 0\nvertex 1 1e400 0\nvertex 0 1 0\n"
        "endloop\nendfacet\nendsolid a\n"
    )
    (tmp_path / "e.stl").write_text("solid e\nendsolid e\n")
    _, notes = _read(_urdf(tmp_path, _mesh("a.stl") + _mesh("e.stl")))
    assert (
        len(notes) == 2
        and "no triangle with finite corners (1 left out: each has a NaN or infinite corner)" in notes[0]
    ), notes
    assert notes[1].endswith("no triangles)") or "no triangles" in notes[1], notes


def test_a_visual_whose_numbers_cannot_be_read_is_a_note(tmp_path):
    """Campaign 5: a ``<visual>`` mesh with ``scale="nan 1 1"`` or ``"1 1"``, or a box with two sizes,
    was skipped without a word: the picture was not what the URDF asked for, and nothing said so."""
    (tmp_path / "a.stl").write_bytes(trimesh.creation.box().export(file_type="stl"))
    visuals = (
        '<visual><geometry><mesh filename="a.stl" scale="nan 1 1"/></geometry></visual>'
        '<visual><geometry><mesh filename="a.stl" scale="1 1"/></geometry></visual>'
        '<visual><geometry><box size="1 1"/></geometry></visual>' + _mesh("a.stl")
    )
    meshes, notes = _read(_urdf(tmp_path, visuals))
    assert len(meshes) == 1 and meshes[0].triangles == 12  # the one readable visual
    assert len(notes) == 3 and all("cannot be read" in n and "drawn as its capsules" in n for n in notes), notes
    assert "(its origin or scale is not" in notes[0] and "(its origin or size is not" in notes[2]


def test_a_mesh_name_too_long_to_look_up_is_not_found_for_every_kind_of_mesh(cli, tmp_path, monkeypatch):
    """Campaign 10: a URDF mesh (visual or collision) or ``arm.tool.mesh`` named by 5,000
    characters ended ``robots --fit``, ``fk --png`` and ``run`` with ``armanim: aaa...: File name
    too long``, exit 3 (pathlib's is_file raises ENAMETOOLONG). It is a mesh not found, as any
    other name with nothing there: a note for a picture, the collision mesh's error at its line."""
    from types import SimpleNamespace

    from armanim.scene.looks import tool_meshes

    long = "a" * 5000 + ".stl"
    meshes, notes = _read(_urdf(tmp_path, _mesh(long) + _mesh("absent.stl")))
    assert meshes == []  # neither is read: the link is drawn as its capsules
    assert len(notes) == 2 and all("not found" in n for n in notes), notes
    tool = SimpleNamespace(xyz=[0, 0, 0], rpy=[0, 0, 0], pen=None, mesh=long, gripper=None)
    tool_notes: list[str] = []
    assert tool_meshes(tool, "l0", tmp_path, tool_notes.append) == []
    assert len(tool_notes) == 1 and "not found" in tool_notes[0], tool_notes
    (tmp_path / "r.urdf").write_text(
        f'<robot name="r"><link name="l0"/><link name="l1">'
        f'<collision><geometry><mesh filename="{long}"/></geometry></collision></link>'
        '<joint name="j" type="revolute"><parent link="l0"/><child link="l1"/><axis xyz="0 0 1"/>'
        '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>'
    )
    monkeypatch.chdir(tmp_path)
    done = cli("robots", "--fit", "r.urdf")
    assert done.exit_code == 2, done.stderr[-300:]
    assert done.stderr.startswith("r.urdf:1: link 'l1': collision mesh 'aaaa") and "not found" in done.stderr


def test_a_readers_deprecation_warning_under_w_error_is_not_a_broken_mesh(monkeypatch):
    """pycollada sets arrays' shapes, which NumPy 2.5 (what pip installs on Python 3.12 and newer)
    deprecates: under ``python -W error`` or ``PYTHONWARNINGS=error`` every ``.dae`` was "could not
    be read (DeprecationWarning: Setting the shape on a NumPy array ...)", exit 2. The warning is
    the library's, not the file's. Simulated here (on any NumPy) by a reader that warns as it reads."""
    import warnings

    import collada

    from armanim.scene.meshfiles import read_mesh

    real = collada.Collada

    def warning_reader(*args, **kwargs):
        warnings.warn(
            "Setting the shape on a NumPy array has been deprecated in NumPy 2.5.", DeprecationWarning, stacklevel=2
        )
        return real(*args, **kwargs)

    monkeypatch.setattr(collada, "Collada", warning_reader)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        _, faces, _ = read_mesh(_dae(_instancing(0, 1), "n0", triangles=2).encode(), "dae")
    assert len(faces) == 2
