"""A URDF's ``<visual>`` elements, read for drawing the robot (never for clearance).

Each link's visuals (meshes in STL, OBJ or COLLADA with their ``scale``, read by
:mod:`armanim.scene.meshfiles`; ``box``, ``cylinder`` and ``sphere`` shapes made by trimesh) are
placed by their ``<origin>`` in the link's frame, and coloured: a COLLADA file keeps the colours
of the materials it was authored with, any other visual (and a textured COLLADA material) takes
its URDF ``<material>`` colour (named inline or at the top of the file), else
:data:`DEFAULT_RGB`. A robot of more than :data:`TRIANGLE_BUDGET` triangles is simplified
(quadric decimation, fast-simplification), each link in proportion to its share.

Every read is bounded (:class:`MeshReader`): only the three formats, by suffix; each file a
regular file opened without blocking, read once however many visuals name it, at most
:data:`MAX_MESH_BYTES` and :data:`MAX_LOOK_BYTES` in all; no file a mesh names (an OBJ's
material library, textures) is opened, no archive inflated; a file's triangles (COLLADA's
instances included) are counted before they are built.

Mesh files are found as ROS users expect: ``package://NAME/rest`` in ``NAME/rest`` under any
of ``package_dirs`` (or ``rest`` under a folder of those named ``NAME``), ``file://`` as a path,
anything else relative to the URDF's folder. A visual that cannot be read is left out with a
warning naming the link and the file (its link is then drawn as its capsules); never an error.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from armanim.arm.chain import SerialChain, transform
from armanim.arm.visuals import ArmMeshes, LinkMesh, LinkPlaces, placed_meshes
from armanim.errors import SceneError, shown_path
from armanim.output.files import is_regular_file, read_bounded, special_kind
from armanim.scene.meshfiles import VISUAL_COLOR, finite_vertices, mesh_format, raise_if_interrupted, read_mesh
from armanim.scene.urdf import Element, Robot, _parse_xml

DEFAULT_RGB = (0.72, 0.74, 0.78)
"""The colour of a visual that names none (a light grey, as RViz draws one)."""
TRIANGLE_BUDGET = 60_000
"""Most triangles drawn for one robot: the renderer draws every one each frame."""
WELD = 1e-3
"""Vertices closer than this share of their mesh's size are one (0.4 mm on a UR5 link): COLLADA
exports repeat a vertex with rounding apart, and decimation cannot collapse an edge between copies."""
SMALLEST_SIZE, LARGEST_SIZE = 1e-9, 1e9
"""A visual's ``box``, ``cylinder`` and ``sphere`` sizes are drawn within these (the bounds of the
URDF's other lengths), and a mesh's ``scale`` at most the largest in size."""
MAX_MESH_BYTES = 64 * 1024 * 1024
"""Largest mesh file read (the Panda's largest COLLADA is 1.7 MB, a detailed arm's 23 MB in all)."""
MAX_LOOK_BYTES = 256 * 1024 * 1024
"""Most bytes of mesh files read for one robot's look, its tool included (each file counted once)."""
MAX_LOOK_TRIANGLES = 2_000_000
"""Most triangles kept for one robot's look before it is simplified to its budget (each visual's
copy counted: a file's triangles are simplified as it is read when there are more than the look draws)."""


@dataclass(frozen=True)
class VisualSpec:
    """One ``<visual>`` as the URDF writes it.

    Attributes
    ----------
    link : str
    origin : (4, 4) array
        The visual's frame in its link's.
    kind : str
        ``mesh``, ``box``, ``cylinder`` or ``sphere``.
    filename : str or None
        A mesh's ``filename`` as written.
    scale : (3,) tuple of float
        A mesh's ``scale`` (1 1 1 when not given).
    size : tuple of float
        box (x, y, z); cylinder (radius, length); sphere (radius,).
    rgb : (3,) tuple of float or None
        Its ``<material>`` colour, if it names one with a colour.
    line : int
    """

    link: str
    origin: np.ndarray
    kind: str
    filename: str | None
    scale: tuple[float, ...]
    size: tuple[float, ...]
    rgb: tuple[float, float, float] | None
    line: int


def visual_specs(raw: bytes, file: str, warn: Callable[[str], None] | None = None) -> list[VisualSpec]:
    """Every ``<visual>`` of every link, in file order (the bytes were parsed as a URDF before,
    so only what drawing needs is read here; a visual it cannot use is skipped).

    >>> specs = visual_specs(b'<robot name="r"><material name="red"><color rgba="1 0 0 1"/></material>'
    ...     b'<link name="a"><visual><origin xyz="0 0 1"/><geometry><box size="1 2 3"/></geometry>'
    ...     b'<material name="red"/></visual></link></robot>', "r.urdf")
    >>> [(s.link, s.kind, s.size, s.rgb, float(s.origin[2, 3])) for s in specs]
    [('a', 'box', (1.0, 2.0, 3.0), (1.0, 0.0, 0.0), 1.0)]
    """
    root = _parse_xml(raw, file)
    named = {m.attrib.get("name"): _rgb(m) for m in root.findall("material")}
    specs = []
    for link in root.findall("link"):
        for visual in link.findall("visual"):
            spec = _visual(link.attrib.get("name", ""), visual, named)
            if spec is not None:
                specs.append(spec)
            elif (
                warn is not None and (shape := _shape_of(visual)) is not None
            ):  # a geometry it names, whose numbers cannot be read
                part = "scale" if shape.tag == "mesh" else "size"
                warn(
                    f"link {link.attrib.get('name', '')!r}: the visual of line {visual.line} cannot be read (its origin or "
                    f"{part} is not the finite numbers it needs): drawn as its capsules if it has no other"
                )
    return specs


def _shape_of(el: Element) -> Element | None:
    """The geometry of a ``<visual>`` when it is one armanim draws (mesh, box, cylinder, sphere), else None."""
    geometry = el.find("geometry")
    shape = geometry.children[0] if geometry is not None and geometry.children else None
    return shape if shape is not None and shape.tag in ("mesh", "box", "cylinder", "sphere") else None


def _visual(link: str, el: Element, named: dict) -> VisualSpec | None:
    """One visual's spec, or None when its geometry is missing or unreadable."""
    geometry = el.find("geometry")
    shape = geometry.children[0] if geometry is not None and geometry.children else None
    if shape is None or shape.tag not in ("mesh", "box", "cylinder", "sphere"):
        return None
    origin = el.find("origin")
    try:
        xyz, rpy = (
            _floats(origin.attrib.get(k, "0 0 0") if origin is not None else "0 0 0", 3) for k in ("xyz", "rpy")
        )
        scale = _floats(shape.attrib.get("scale", "1 1 1"), 3) if shape.tag == "mesh" else (1.0, 1.0, 1.0)
        keys = {"mesh": (), "box": ("size",), "cylinder": ("radius", "length"), "sphere": ("radius",)}[shape.tag]
        size = tuple(v for k in keys for v in _floats(shape.attrib[k], 3 if k == "size" else 1))
        # drawn only: sizes within the URDF's bounds (a sphere of 1e-300 made NaN vertices), a scale at most 1e9
        size = tuple(float(np.clip(v, SMALLEST_SIZE, LARGEST_SIZE)) for v in size)
        scale = tuple(float(np.clip(v, -LARGEST_SIZE, LARGEST_SIZE)) for v in scale)
    except (KeyError, ValueError):
        return None
    material = el.find("material")
    rgb = None
    if material is not None:
        rgb = _rgb(material) or named.get(material.attrib.get("name"))
    return VisualSpec(link, transform(xyz, rpy), shape.tag, shape.attrib.get("filename"), scale, size, rgb, el.line)


def _floats(text: str, count: int) -> tuple[float, ...]:
    """``count`` finite numbers from a space-separated attribute."""
    values = tuple(float(v) for v in text.split())
    if len(values) != count or not all(np.isfinite(values)):
        raise ValueError(text)
    return values


def _rgb(material: Element) -> tuple[float, float, float] | None:
    """A ``<material>``'s ``<color rgba>`` as RGB in 0..1, or None."""
    color = material.find("color")
    try:
        rgba = _floats(color.attrib["rgba"], 4) if color is not None else None
    except (KeyError, ValueError):
        return None
    if rgba is None:
        return None
    red, green, blue = (float(np.clip(v, 0.0, 1.0)) for v in rgba[:3])
    return red, green, blue


def mesh_path(filename: str, urdf_dir: Path, package_dirs: list[Path]) -> Path | None:
    """Where a mesh ``filename`` is: ``package://NAME/rest`` under ``package_dirs`` (``NAME/rest``
    in one of them, or ``rest`` in one named ``NAME``), ``file://`` a path, else relative to
    ``urdf_dir``; None when no such file exists.

    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     (Path(d) / "pkg" / "meshes").mkdir(parents=True)
    ...     _ = (Path(d) / "pkg" / "meshes" / "a.stl").write_bytes(b"")
    ...     found = mesh_path("package://pkg/meshes/a.stl", Path(d) / "x", [Path(d)])
    ...     str(found.relative_to(d))
    'pkg/meshes/a.stl'
    """
    return next((c for c in mesh_candidates(filename, urdf_dir, package_dirs) if is_regular_file(c)), None)


def not_a_file(candidates: Iterable[Path]) -> str | None:
    """Why a mesh named at ``candidates`` (:func:`mesh_candidates`; a tool mesh's one path) is not
    read, when :func:`mesh_path` finds no file there: the phrase ``is not a regular file (PATH is a
    FIFO (named pipe): ...)`` for the first that exists as something else, None when nothing is there
    (it is not found). The one check of all three kinds of mesh (visual, collision, tool); nothing is
    opened (a FIFO would block).

    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     not_a_file([Path(d) / "none.stl", Path(d)]).startswith("is not a regular file")
    True
    """
    for candidate in candidates:
        try:
            kind = special_kind(os.stat(candidate).st_mode)
        except (OSError, ValueError):  # absent, a dangling link, a loop, a NUL in the name
            continue
        if kind is not None:
            return f"is not a regular file ({candidate} is {kind}: never read; name a mesh file)"
    return None


def mesh_candidates(filename: str, urdf_dir: Path, package_dirs: list[Path]) -> Iterator[Path]:
    """The paths a mesh ``filename`` may name, in :func:`mesh_path`'s order."""
    if filename.startswith("package://"):
        name, _, rest = filename[len("package://") :].partition("/")
        for folder in package_dirs:
            yield folder / name / rest
            if folder.name == name:
                yield folder / rest
        return
    yield Path(filename[len("file://") :]) if filename.startswith("file://") else urdf_dir / filename


def default_package_dirs(urdf_dir: Path) -> list[Path]:
    """The URDF's folder and each of its parents, nearest first (where a ROS package's
    ``package://`` names usually resolve)."""
    folder = urdf_dir.resolve()
    return [folder, *folder.parents]


def link_meshes(
    specs: list[VisualSpec],
    urdf_dir: Path,
    package_dirs: list[Path],
    warn: Callable[[str], None],
    budget: int | None = TRIANGLE_BUDGET,
    reader: MeshReader | None = None,
) -> list[LinkMesh]:
    """Each link's visuals as one :class:`LinkMesh` in its frame (links in the order they come),
    simplified to ``budget`` triangles in all (None: as read); a visual that cannot be read is
    left out and ``warn`` told why. ``reader`` reads the mesh files (a new one by default: each
    file once, every read bounded)."""
    reader = reader or MeshReader(budget)
    parts: dict[str, list[LinkMesh]] = {}
    for spec in specs:
        mesh = _spec_mesh(spec, urdf_dir, package_dirs, warn, reader)
        if mesh is not None and mesh.triangles:
            if not reader.keep(mesh.triangles):
                warn(
                    f"link {spec.link!r}: the visual of line {spec.line} is left out: the robot's visuals hold more than "
                    f"{MAX_LOOK_TRIANGLES:,} triangles in all (drawn as its capsules if it has no other)"
                )
                continue
            parts.setdefault(spec.link, []).append(mesh)
    meshes = [_joined(link, pieces) for link, pieces in parts.items()]
    total = sum(m.triangles for m in meshes)
    if budget is not None and total > budget:
        meshes = [simplified(m, max(12, int(m.triangles * budget / total))) for m in meshes]
    return meshes


def _spec_mesh(
    spec: VisualSpec, urdf_dir: Path, package_dirs: list[Path], warn: Callable[[str], None], reader: MeshReader
) -> LinkMesh | None:
    """One visual's triangles in its link's frame, or None (and a warning) when unreadable."""
    import trimesh

    if spec.kind == "mesh":
        if sum(v == 0 for v in spec.scale) >= 2:  # a line or a point: nothing to see, said rather than drawn
            warn(
                f"link {spec.link!r}: mesh {shown_path(spec.filename or '')} (line {spec.line}) has scale "
                f"{' '.join(f'{v:g}' for v in spec.scale)}, which leaves it no area (a line or a point): "
                "drawn as its capsules"
            )
            return None
        if mesh_format(spec.filename or "") is None:
            warn(
                f"link {spec.link!r}: mesh {shown_path(spec.filename or '')} (line {spec.line}) is not a format armanim reads "
                "(STL, OBJ or COLLADA .dae; archives are never opened): drawn as its capsules"
            )
            return None
        path = mesh_path(spec.filename or "", urdf_dir, package_dirs)
        if path is None:
            other = not_a_file(mesh_candidates(spec.filename or "", urdf_dir, package_dirs))
            warn(
                f"link {spec.link!r}: mesh {shown_path(spec.filename or '')} "
                + (
                    f"{other} (line {spec.line})"
                    if other
                    else f"not found (line {spec.line}; set arm.package_dirs to the folders its package:// names live in)"
                )
                + ": drawn as its capsules"
            )
            return None
        try:
            mesh = mesh_file_triangles(spec, path, reader)
        except Exception as error:  # a user's file: any reader error is a warning, never a failed run
            raise_if_interrupted()  # ... unless it is an interrupt a library turned into an error
            warn(
                f"link {spec.link!r}: mesh {shown_path(str(path))} could not be read ({unreadable_reason(error)}): "
                "drawn as its capsules"
            )
            return None
    else:
        shape = {
            "box": lambda: trimesh.creation.box(extents=spec.size),
            "cylinder": lambda: trimesh.creation.cylinder(radius=spec.size[0], height=spec.size[1], sections=24),
            "sphere": lambda: trimesh.creation.icosphere(subdivisions=2, radius=spec.size[0]),
        }[spec.kind]()
        raise_if_interrupted()  # trimesh catches BaseException in places
        mesh = LinkMesh(
            spec.link,
            np.asarray(shape.vertices, dtype=float),
            np.asarray(shape.faces, dtype=int),
            np.tile(spec.rgb or DEFAULT_RGB, (len(shape.faces), 1)),
        )
    with np.errstate(invalid="ignore", over="ignore"):  # such corners are dropped just below, not warned of
        vertices = mesh.vertices @ spec.origin[:3, :3].T + spec.origin[:3, 3]
    return finite_part(LinkMesh(spec.link, vertices, mesh.faces, mesh.colors))  # a huge scale or origin may overflow


def finite_part(mesh: LinkMesh) -> LinkMesh:
    """``mesh`` without its triangles that have a corner that is not finite, and without every such
    corner, used or not (the faces renumbered): what is drawn, and what the viewer writes as JSON
    (campaign 18: an OBJ's unused ``v nan nan nan``, or a corner a scale of 1e9 made infinite, ended
    ``run --viewer`` in a ValueError traceback)."""
    finite = np.isfinite(mesh.vertices).all(axis=1)
    if finite.all():
        return mesh
    kept = finite[mesh.faces].all(axis=1)
    vertices, faces = finite_vertices(mesh.vertices, mesh.faces[kept])
    return LinkMesh(mesh.link, vertices, faces, mesh.colors[kept])


def unreadable_reason(error: Exception) -> str:
    """Why a mesh file could not be read, in one phrase (a SceneError's message without its file)."""
    if isinstance(error, SceneError):
        return "; ".join(d.message for d in error.problems)
    return f"{type(error).__name__}: {error}"


class MeshReader:
    """Reads mesh files for one robot's look: each file once (by its device and inode, size and
    modification time: three links naming one STL, by any spelling, a symbolic or a hard link,
    read it once), every read a
    regular file opened without blocking, at most :data:`MAX_MESH_BYTES` a file and
    :data:`MAX_LOOK_BYTES` in all; a file of more than ``simplify_above`` triangles is
    simplified as it is read (None: kept as read), and at most :data:`MAX_LOOK_TRIANGLES` are
    kept in all (:meth:`keep`).

    Parameters
    ----------
    simplify_above : int or None
    """

    def __init__(self, simplify_above: int | None = TRIANGLE_BUDGET) -> None:
        self.simplify_above = simplify_above
        self.bytes_read = 0
        self.triangles_kept = 0
        self._files: dict[tuple, LinkMesh] = {}

    def triangles(self, path: Path) -> LinkMesh:
        """The file's triangles as read (colours :data:`~armanim.scene.meshfiles.VISUAL_COLOR`
        where the visual's colour applies), from the cache when read before.

        Raises
        ------
        SceneError
            Not a regular file, too large, or the look's bytes are spent.
        ValueError
            Not a mesh of its format, or too many triangles.
        """
        kind = mesh_format(path.name)
        if kind is None:
            raise ValueError(
                f"{path.suffix or 'a file without a suffix'} is not a format armanim reads (STL, OBJ or COLLADA .dae)"
            )
        stat = path.stat()
        # the file, not its name: hard links (and every spelling or symbolic link) of one file are
        # one key (campaign 18: five hard links of a 60 MB OBJ were read five times, past 256 MB)
        key = (stat.st_dev, stat.st_ino, stat.st_size, stat.st_mtime_ns)
        if key in self._files:
            return self._files[key]
        limit = min(MAX_MESH_BYTES, MAX_LOOK_BYTES - self.bytes_read)
        if stat.st_size > limit:
            raise ValueError(
                f"{stat.st_size:,} bytes, more than the {limit:,} left to read "
                f"(at most {MAX_MESH_BYTES // 2**20} MB a file, {MAX_LOOK_BYTES // 2**20} MB in all)"
            )
        data = read_bounded(path, limit, "a mesh file")
        self.bytes_read += len(data)
        vertices, faces, colors = read_mesh(data, kind)
        raise_if_interrupted()
        mesh = LinkMesh("", vertices, faces, colors)
        if self.simplify_above is not None and mesh.triangles > self.simplify_above:
            mesh = simplified(mesh, self.simplify_above)
        self._files[key] = mesh
        return mesh

    def keep(self, triangles: int) -> bool:
        """Whether ``triangles`` more fit in the look's :data:`MAX_LOOK_TRIANGLES` (counted if so)."""
        if self.triangles_kept + triangles > MAX_LOOK_TRIANGLES:
            return False
        self.triangles_kept += triangles
        return True


def mesh_file_triangles(spec: VisualSpec, path: Path, reader: MeshReader | None = None) -> LinkMesh:
    """A mesh file's triangles, scaled, in the visual's frame, coloured as the module says."""
    mesh = (reader or MeshReader(None)).triangles(path)
    colors = mesh.colors
    own = colors[:, 0] != VISUAL_COLOR  # COLLADA carries authored materials; STL and OBJ take the URDF's colour
    colors = np.where(own[:, None], colors, np.asarray(spec.rgb or DEFAULT_RGB, dtype=float))
    flip = np.prod(spec.scale) < 0  # a mirroring scale turns every triangle inside out
    with np.errstate(invalid="ignore", over="ignore"):  # a huge scale: corners past a float, dropped when placed
        scaled = mesh.vertices * np.asarray(spec.scale)
    return LinkMesh(spec.link, scaled, mesh.faces[:, ::-1] if flip else mesh.faces, colors)


def _joined(link: str, pieces: list[LinkMesh]) -> LinkMesh:
    """One link's visuals as one mesh."""
    offsets = np.cumsum([0] + [len(p.vertices) for p in pieces])[:-1]
    return LinkMesh(
        link,
        np.concatenate([p.vertices for p in pieces]),
        np.concatenate([p.faces + o for p, o in zip(pieces, offsets)]),
        np.concatenate([p.colors for p in pieces]),
    )


def simplified(mesh: LinkMesh, triangles: int) -> LinkMesh:
    """``mesh`` decimated to about ``triangles`` (fast-simplification's quadric edge collapse),
    one colour at a time so that the colours' borders stay; unchanged when it has no more."""
    if mesh.triangles <= triangles:
        return mesh
    import fast_simplification

    pieces = []
    colors, which = np.unique(np.round(mesh.colors, 4), axis=0, return_inverse=True)
    for c, rgb in enumerate(colors):
        points, kept = welded(mesh.vertices, mesh.faces[which.reshape(-1) == c])
        share = max(4, int(round(triangles * len(kept) / mesh.triangles)))
        points, kept = points.astype(np.float32), kept.astype(np.int32)
        if len(kept) > share:
            points, kept = fast_simplification.simplify(points, kept, target_reduction=1.0 - share / len(kept))
        pieces.append(
            LinkMesh(
                mesh.link, np.asarray(points, dtype=float), np.asarray(kept, dtype=int), np.tile(rgb, (len(kept), 1))
            )
        )
    return _joined(mesh.link, pieces)


def bundled_link_meshes(folder: Path) -> list[LinkMesh]:
    """A bundled robot's simplified visual meshes (``visual.npz`` in its ``folder``, written by
    tools/bundle_meshes.py), each in its link's frame; none when the robot ships none."""
    path = folder / "visual.npz"
    if not path.is_file():
        return []
    with np.load(path) as arrays:
        links = dict.fromkeys(key.split("/")[0] for key in arrays.files)  # in the file's order
        return [
            LinkMesh(
                link,
                arrays[f"{link}/vertices"].astype(float),
                arrays[f"{link}/faces"].astype(int),
                arrays[f"{link}/colors"].astype(float) / 255.0,
            )
            for link in links
        ]


def welded(vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The vertices ``faces`` use, each position once (files often repeat a vertex per face for
    its normals, or nearly: which leaves decimation no edge to collapse), vertices within
    :data:`WELD` of the mesh's size taken as one, and the faces on them without the ones that
    become degenerate.

    >>> v = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]])
    >>> points, faces = welded(v, np.array([[0, 1, 2], [3, 5, 4]]))
    >>> len(points), faces.tolist()
    (4, [[0, 2, 1], [2, 3, 1]])
    """
    span = float(np.ptp(vertices, axis=0).max()) if len(vertices) else 1.0
    cells = np.round(vertices / (WELD * span if span > 0 else 1.0))
    _, first, inverse = np.unique(cells, axis=0, return_index=True, return_inverse=True)
    points = vertices[first]
    faces = inverse.reshape(-1)[faces]
    good = (faces[:, 0] != faces[:, 1]) & (faces[:, 1] != faces[:, 2]) & (faces[:, 0] != faces[:, 2])
    used, local = np.unique(faces[good], return_inverse=True)
    return points[used], local.reshape(-1, 3)


def chain_meshes(
    meshes: list[LinkMesh],
    robot: Robot,
    base: str,
    tip: str,
    chain: SerialChain,
    mount: np.ndarray,
    fixed: Sequence[LinkMesh] = (),
    places: dict | None = None,
) -> ArmMeshes:
    """The links' meshes placed on the chain's frames: a link on the path from ``base`` to
    ``tip`` on its carrier, the base link where the chain is mounted, and a link hanging off
    the path (a gripper below the tip) where ``places`` puts it (the collision model's places,
    :func:`armanim.scene.convert.link_places`: at the held joint values), else where its joints'
    zero puts it below the nearest link on the path. ``mount`` (4, 4) is the base link's frame in
    the world. Links not below the base (a ``world`` link above it) are not drawn. ``fixed``
    meshes are already in the world."""
    path = robot.path(base, tip)
    place = {base: (-1, np.asarray(mount, dtype=float))}
    for i, joint in enumerate(path):
        place[joint.child] = (chain.carriers[i], np.asarray(chain.link_offsets[i]))
    if places is not None:
        place.update(places)
    return placed_link_meshes(meshes, robot, place, fixed)


def placed_link_meshes(
    meshes: list[LinkMesh], robot: Robot, places: LinkPlaces, fixed: Sequence[LinkMesh] = ()
) -> ArmMeshes:
    """The links' meshes placed where ``places`` puts their links (carrier, (4, 4) the link's
    frame in the carrier's; :func:`armanim.scene.convert.link_places`, made with the problem's
    arm), a link not in it below the nearest link that is, at its joints' zero. Links not below
    a placed one are not drawn; ``fixed`` meshes are already in the world."""
    place = places
    up = robot.parent_joint
    kept, carriers, offsets = [], [], []
    for mesh in meshes:
        link, hang = mesh.link, np.eye(4)
        while link not in place and link in up:
            hang = up[link].origin @ hang
            link = up[link].parent
        if link not in place:
            continue
        carrier, offset = place[link]
        kept.append(mesh)
        carriers.append(carrier)
        offsets.append(offset @ hang)
    return placed_meshes(kept + list(fixed), carriers + [-1] * len(fixed), offsets + [np.eye(4)] * len(fixed))


__all__ = [
    "DEFAULT_RGB",
    "MAX_LOOK_BYTES",
    "MAX_LOOK_TRIANGLES",
    "MAX_MESH_BYTES",
    "TRIANGLE_BUDGET",
    "MeshReader",
    "VisualSpec",
    "bundled_link_meshes",
    "chain_meshes",
    "default_package_dirs",
    "finite_part",
    "link_meshes",
    "placed_link_meshes",
    "mesh_path",
    "simplified",
    "visual_specs",
]
