"""Mesh files' bytes to triangles: STL, OBJ and COLLADA, the formats the docs name, and no other.

Each reader takes the bytes armanim has already read (bounded, a regular file: see
:mod:`armanim.scene.visuals`) and never opens another file: an OBJ's material library and
textures and a COLLADA file's images are not read (an OBJ takes its URDF colour, a COLLADA
geometry its material's colour, a textured one its URDF colour). An archive is never inflated
(a ``.dae`` that is a zip, as pycollada would open it, is refused), and a file's triangles are
counted before any array of them is built: an OBJ face's fan, a COLLADA scene's instances
(nodes that instance nodes, weighted by their triangles) are refused past
:data:`MAX_FILE_TRIANGLES` before they are expanded.

STL and OBJ are read here with numpy; COLLADA with pycollada, which is given the bytes (so it
reads no file) and whose scene graph is walked here. pycollada, as trimesh, catches
BaseException in places, which would swallow a KeyboardInterrupt: after it returns, an
interrupt that came meanwhile is raised again (:func:`raise_if_interrupted`).
"""

from __future__ import annotations

import io
import re
import warnings
import zipfile

import numpy as np

from armanim.procs.interrupted import signal_came

MESH_FORMATS = (".stl", ".obj", ".dae")
"""The mesh files armanim reads (the suffix, any case): STL, OBJ and COLLADA."""
MAX_FILE_TRIANGLES = 2_000_000
"""Most triangles one mesh file may place, counted before they are built (a 64 MB binary STL
holds 1.34 million): an OBJ face of a million corners, or COLLADA nodes that instance each other
ten times seven levels deep, are refused instead of filling memory."""
MAX_DAE_ELEMENTS = 100_000
"""Most XML elements (counted in the file's bytes, before it is parsed) of one COLLADA file.
pycollada builds an object for each, in one call that an interrupt cannot stop: a file of 300,000
nodes (18 MB, within every other bound) took some 30 s of CPU, and a Ctrl-C 10 s into it was
answered 4 s later (campaign 9). A link's mesh holds a few hundred; 100,000 is parsed in about a
second."""
VISUAL_COLOR = -1.0
"""The colour value of a triangle that takes its visual's colour (its URDF ``<material>``)."""


def raise_if_interrupted() -> None:
    """Raise KeyboardInterrupt if Ctrl-C or SIGTERM came while the command ran: a library that
    catches BaseException (trimesh, pycollada) may have swallowed the one its handler raised."""
    if signal_came():
        raise KeyboardInterrupt


def mesh_format(name: str) -> str | None:
    """The format of a mesh file by its suffix (``stl``, ``obj``, ``dae``), or None when armanim
    does not read it.

    >>> mesh_format("a.STL"), mesh_format("arm.dae"), mesh_format("a.zip"), mesh_format("a.gltf")
    ('stl', 'dae', None, None)
    """
    suffix = "." + name.rsplit(".", 1)[-1].lower() if "." in name else ""
    return suffix[1:] if suffix in MESH_FORMATS else None


def read_mesh(data: bytes, kind: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A mesh file's triangles from its bytes.

    Parameters
    ----------
    data : bytes
    kind : str
        ``stl``, ``obj`` or ``dae`` (:func:`mesh_format`).

    Returns
    -------
    vertices : (n, 3) float array
        In the file's units, placed by its own transforms (COLLADA's nodes); a COLLADA file's in
        metres, its ``<unit>`` applied (:func:`_unit_metres`; STL and OBJ declare none).
    faces : (m, 3) int array
        Every triangle with finite corners (one with a NaN or infinite corner is left out).
    colors : (m, 3) float array
        RGB in 0..1, or :data:`VISUAL_COLOR` where the triangle takes its visual's colour.

    Raises
    ------
    ValueError
        The bytes are not such a file, or place more than :data:`MAX_FILE_TRIANGLES`.
    """
    vertices, faces, colors = {"stl": _stl, "obj": _obj, "dae": _dae}[kind](data)
    finite = np.isfinite(vertices).all(axis=1)
    given = len(faces)
    if given and not finite.all():
        kept = finite[faces].all(axis=1)
        faces, colors = faces[kept], colors[kept]
    if not len(faces):
        raise ValueError(
            f"no triangle with finite corners ({given:,} left out: each has a NaN or infinite corner)"
            if given
            else "no triangles"
        )
    return vertices, faces, colors


def finite_vertices(vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``vertices`` without the ones that are not finite, and ``faces`` (which name none of them)
    renumbered: no NaN or infinite corner is kept, even one no triangle uses (campaign 18: an OBJ's
    ``v nan nan nan`` beside a good triangle reached the viewer's JSON, a ValueError traceback).

    >>> v, f = finite_vertices(np.array([[0.0, 0, 0], [np.nan, 0, 0], [1, 0, 0], [0, 1, 0]]), np.array([[0, 2, 3]]))
    >>> v.tolist(), f.tolist()
    ([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], [[0, 1, 2]])
    """
    finite = np.isfinite(vertices).all(axis=1)
    if finite.all():
        return vertices, faces
    number = np.cumsum(finite) - 1
    return vertices[finite], number[faces].reshape(-1, 3)


def _too_many(count: int) -> ValueError:
    return ValueError(f"places {count:,} triangles or more (at most {MAX_FILE_TRIANGLES:,} from one mesh file)")


def _plain(vertices: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Triangles given as (m, 3, 3) corners, in the visual's colour."""
    faces = np.arange(3 * len(vertices)).reshape(-1, 3)
    return vertices.reshape(-1, 3), faces, np.full((len(faces), 3), VISUAL_COLOR)


_STL_RECORD = np.dtype([("normal", "<f4", 3), ("corners", "<f4", 9), ("attribute", "<u2")])
_NUMBER = rb"([-+0-9.eEinfINFaA]+)"
_STL_VERTEX = re.compile(rb"vertex\s+" + _NUMBER + rb"\s+" + _NUMBER + rb"\s+" + _NUMBER)


def _stl(data: bytes) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A binary STL (80-byte header, a count, 50 bytes a triangle) or an ASCII one.

    >>> import struct
    >>> v, f, c = _stl(bytes(80) + struct.pack("<I", 1) + np.array([0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0], "<f4").tobytes() + bytes(2))
    >>> v.tolist(), f.tolist()
    ([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], [[0, 1, 2]])
    >>> _stl(b"solid t\\nfacet normal 0 0 1\\nouter loop\\nvertex 0 0 0\\nvertex 1 0 0\\nvertex 0 1 0\\nendloop\\nendfacet\\nendsolid")[1].tolist()
    [[0, 1, 2]]
    """
    if len(data) >= 84:
        count = int(np.frombuffer(data, "<u4", 1, 80)[0])
        if 84 + 50 * count == len(data):
            if count > MAX_FILE_TRIANGLES:
                raise _too_many(count)
            corners = np.frombuffer(data, _STL_RECORD, count, 84)["corners"].astype(float)
            return _plain(corners.reshape(-1, 3, 3))
    if not data.lstrip()[:5].lower() == b"solid":
        raise ValueError(
            "not an STL file (neither a binary STL, whose size must be 84 + 50 bytes a triangle, "
            "nor an ASCII one, which starts with 'solid')"
        )
    if data.count(b"vertex") > 3 * MAX_FILE_TRIANGLES:
        raise _too_many(MAX_FILE_TRIANGLES)
    try:
        corners = np.array(_STL_VERTEX.findall(data), dtype=float)
    except ValueError:
        raise ValueError("an ASCII STL 'vertex' line holds something other than three numbers") from None
    if len(corners) % 3:
        raise ValueError(f"an ASCII STL with {len(corners)} vertices, not three a facet")
    return _plain(corners.reshape(-1, 3, 3))


_OBJ_VERTEX = re.compile(rb"^v[ \t]+([^\n]*)", re.MULTILINE)
"""An OBJ's vertex line: what follows ``v`` (its numbers, and whatever else the line holds)."""
_OBJ_FACE = re.compile(rb"^f[ \t]+([^\n#]*)", re.MULTILINE)
"""An OBJ's face line: its vertex references, up to a comment."""


def _obj(data: bytes) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A Wavefront OBJ's vertices (``v``) and faces (``f``, fans of any size, ``i/j/k`` and
    negative indices); its material library and textures are not read.

    >>> v, f, c = _obj(b"mtllib m.mtl\\nv 0 0 0\\nv 1 0 0\\nv 1 1 0\\nv 0 1 0\\nusemtl x\\nf 1/1 2/2 3/3 -1\\n")
    >>> len(v), f.tolist()
    (4, [[0, 1, 2], [0, 2, 3]])
    >>> _obj(b"v 0 0 0\\nv 1 0 0\\nv 0 1 0 1\\nf 1\\nf 1 2\\nf\\t3 1 2 # a comment\\nfo 1 2 3\\n")[1].tolist()
    [[2, 0, 1]]
    """
    # the lines found by regular expressions (C's speed) and each split once: a Python loop over
    # every line took 60 s for 64 MB of 'f 1' lines (campaign 18), which make no triangle
    points = [line.split()[:3] for line in _OBJ_VERTEX.findall(data)]
    fans, corners = [], 0
    for fan in map(bytes.split, _OBJ_FACE.findall(data)):
        if len(fan) > 2:  # (fewer vertices make no triangle)
            corners += len(fan) - 2
            if corners > MAX_FILE_TRIANGLES:  # before the next: its fans are held as they are read
                raise _too_many(corners)
            fans.append(fan)
    try:
        vertices = np.array(points, dtype=float).reshape(-1, 3) if not points else np.array(points, dtype=float)
    except ValueError:
        raise ValueError("a 'v' line of the OBJ file does not hold three numbers") from None
    if vertices.ndim != 2 or vertices.shape[1] != 3:
        # every 'v' line of two numbers (or none) is not reshaped into other corners (campaign 19:
        # six 'v x y' lines were read as four corners of three, and the face drawn from them)
        raise ValueError("a 'v' line of the OBJ file does not hold three numbers")
    faces: list[list[int]] = []
    for fan in fans:
        try:
            ids = [int(token.split(b"/", 1)[0]) for token in fan]
        except ValueError:
            raise ValueError("an 'f' line of the OBJ file holds something other than vertex numbers") from None
        if any(abs(i) > len(vertices) for i in ids):  # before numpy, which cannot hold a number of 20 digits
            raise ValueError(f"a face names a vertex the OBJ file does not have (it has {len(vertices):,})")
        ids = [i - 1 if i > 0 else len(vertices) + i for i in ids]  # 1-based, or counted back from the last
        faces.extend([ids[0], ids[k], ids[k + 1]] for k in range(1, len(ids) - 1))
    faces_array = np.array(faces, dtype=np.int64).reshape(-1, 3)
    if len(faces_array) and (np.min(faces_array) < 0 or np.max(faces_array) >= len(vertices)):
        raise ValueError(f"a face names a vertex the OBJ file does not have (it has {len(vertices):,})")
    return vertices, faces_array, np.full((len(faces_array), 3), VISUAL_COLOR)


def _dae(data: bytes) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A COLLADA file's triangles, each geometry placed by its nodes' transforms, counted
    (instances weighted by their triangles) before any is placed."""
    import collada

    if zipfile.is_zipfile(io.BytesIO(data)):  # pycollada inflates the .dae inside a zip: a zip bomb's door
        raise ValueError("is a zip archive (a .zae); armanim does not inflate archives: give the .dae itself")
    if b"<!DOCTYPE" in data or b"<!ENTITY" in data:
        raise ValueError("has a DTD (<!DOCTYPE> or <!ENTITY>): entity expansion is refused")
    elements = data.count(b"<") - data.count(b"</") - data.count(b"<?") - data.count(b"<!")
    if elements > MAX_DAE_ELEMENTS:
        raise ValueError(
            f"holds {elements:,} XML elements (at most {MAX_DAE_ELEMENTS:,} in one COLLADA file: "
            "its reader cannot be interrupted while it builds them; merge its nodes, or export it as STL)"
        )
    broken = [
        collada.common.DaeError,
        collada.common.DaeIncompleteError,
        collada.common.DaeMalformedError,
        collada.common.DaeBrokenRefError,
        collada.common.DaeUnsupportedError,
    ]
    with warnings.catch_warnings():
        # pycollada sets arrays' shapes, which NumPy 2.5 deprecates: under -W error (PYTHONWARNINGS=error)
        # every .dae was "could not be read (DeprecationWarning: ...)"; the warning is the library's, not the file's
        warnings.simplefilter("ignore", DeprecationWarning)
        try:
            document = collada.Collada(io.BytesIO(data), ignore=broken)
        finally:
            raise_if_interrupted()
        unit = _unit_metres(document)
        roots = list(document.scene.nodes) if document.scene is not None else []
        count = _placed_count(roots)
        if count > MAX_FILE_TRIANGLES:
            raise ValueError(
                f"its nodes place {count:,} triangles and instances once expanded (at most "
                f"{MAX_FILE_TRIANGLES:,} from one mesh file; nodes instancing nodes are counted, not expanded)"
            )
        parts: list[tuple[np.ndarray, np.ndarray]] = []
        for node in roots:
            _place(node, np.eye(4), parts, {})
    raise_if_interrupted()
    if not parts:
        return np.zeros((0, 3)), np.zeros((0, 3), dtype=int), np.zeros((0, 3))
    corners = np.concatenate([p for p, _ in parts]) * unit
    colors = np.concatenate([np.tile(rgb, (len(p), 1)) for p, rgb in parts])
    return corners.reshape(-1, 3), np.arange(3 * len(corners)).reshape(-1, 3), colors


def _unit_metres(document) -> float:
    """Metres per unit of a COLLADA document: its ``<asset><unit meter="...">`` (1 without one,
    COLLADA's default), applied to every placed corner as RViz and Gazebo apply it (trimesh and
    pycollada only record it; assimp as coal builds it, and so pinocchio, ignores it). Its
    ``<up_axis>`` is not applied, as RViz does not: a URDF's link frame is the file's frame.

    Raises
    ------
    ValueError
        The unit is not a decimal number (as XML writes one) within :data:`UNIT_METRES`.
    """
    import collada

    asset = document.assetInfo
    node = asset.xmlnode.find(collada.tag("unit")) if asset is not None and asset.xmlnode is not None else None
    text = node.get("meter") if node is not None else None
    if text is None:
        return 1.0
    unit = float(text) if _DECIMAL.fullmatch(text.strip()) else None  # not Python's float(): no "1_000", "inf", "nan"
    low, high = UNIT_METRES
    if unit is None or not low <= unit <= high:
        raise ValueError(
            f"its <unit meter={text[:40]!r}> is not a number of metres per unit from {low:g} (micrometres) "
            f'to {high:g} (kilometres) (millimetres are meter="0.001"; fix the file\'s <asset>)'
        )
    return unit


_DECIMAL = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")
"""A decimal number as XML Schema writes one (xs:double without INF and NaN)."""
UNIT_METRES = (1e-6, 1e3)
"""The COLLADA units armanim applies, metres per unit: micrometres to kilometres (a robot's mesh in
another unit is a mistake; 1e-300 or 1e300 would make its corners vanish or overflow)."""


def _placed_count(roots: list) -> int:
    """The instances and triangles the scene below ``roots`` places once expanded, counted over
    the graph (each node once, remembered), never by expanding it.

    Raises
    ------
    ValueError
        Nodes instance each other in a cycle.
    """
    import collada

    memo: dict[int, int] = {}
    visiting: set[int] = set()

    def weight(node) -> int:
        if isinstance(node, collada.scene.GeometryNode):
            key = id(node.geometry)
            if key not in memo:
                memo[key] = sum(_triangle_count(p) for p in node.geometry.primitives)
            return 1 + memo[key]
        if not isinstance(node, collada.scene.Node):
            return 1
        target = node.node if isinstance(node, collada.scene.NodeNode) else node
        key = id(target)
        if key in visiting:
            raise ValueError(f"its node {target.id!r} instances itself (a cycle of instance_node)")
        if key not in memo:
            visiting.add(key)
            memo[key] = 1 + sum(weight(child) for child in (target.children or ()))
            visiting.discard(key)
        return memo[key]

    return sum(weight(node) for node in roots)


def _triangle_count(primitive) -> int:
    """How many triangles a COLLADA primitive makes (polygons as fans; lines none)."""
    import collada

    if isinstance(primitive, collada.triangleset.TriangleSet):
        return len(primitive)
    if isinstance(primitive, collada.polylist.Polylist):
        return int(np.maximum(np.asarray(primitive.vcounts) - 2, 0).sum())
    return 0


def _place(node, matrix: np.ndarray, parts: list, cache: dict) -> None:
    """Append each triangle set below ``node``, placed by ``matrix`` and the nodes' own, with its
    material's colour (a count already bounds how many are placed)."""
    import collada

    if isinstance(node, collada.scene.GeometryNode):
        symbols = {m.symbol: m.target for m in node.materials}
        for primitive in node.geometry.primitives:
            corners = cache.get(id(primitive))
            if corners is None:
                corners = cache[id(primitive)] = _corners(primitive)
            if len(corners):
                placed = corners @ matrix[:3, :3].T + matrix[:3, 3]
                parts.append((placed, _material_rgb(symbols.get(primitive.material))))
    elif isinstance(node, collada.scene.Node):
        inner = matrix @ np.asarray(node.matrix, dtype=float)
        for child in node.children or ():
            _place(child, inner, parts, cache)


def _corners(primitive) -> np.ndarray:
    """A primitive's triangles as (m, 3, 3) corners."""
    import collada

    if isinstance(primitive, collada.polylist.Polylist):
        primitive = primitive.triangleset()
    if not isinstance(primitive, collada.triangleset.TriangleSet) or primitive.vertex is None or not len(primitive):
        return np.zeros((0, 3, 3))
    return np.asarray(primitive.vertex, dtype=float)[np.asarray(primitive.vertex_index)].reshape(-1, 3, 3)


def _material_rgb(material) -> tuple[float, float, float]:
    """A COLLADA material's diffuse colour (RGB 0..1), or :data:`VISUAL_COLOR` (a texture, none)."""
    diffuse = getattr(getattr(material, "effect", None), "diffuse", None)
    if isinstance(diffuse, (tuple, list)) and len(diffuse) >= 3:
        rgb = np.clip(np.asarray(diffuse[:3], dtype=float), 0.0, 1.0)
        if np.isfinite(rgb).all():
            red, green, blue = (float(v) for v in rgb)
            return red, green, blue
    return (VISUAL_COLOR,) * 3


__all__ = [
    "MAX_FILE_TRIANGLES",
    "MESH_FORMATS",
    "VISUAL_COLOR",
    "finite_vertices",
    "mesh_format",
    "raise_if_interrupted",
    "read_mesh",
]
