"""Collision capsules fitted to a URDF's meshes (``arm.collision: auto`` of your own URDF).

A link's ``<collision>`` meshes (STL, OBJ, COLLADA; with their ``scale`` and ``<origin>``) are read
by :class:`armanim.scene.visuals.MeshReader` (every file bounded in size and triangles, each read
once), joined in the link's frame and fitted with 1 to 3 capsules that hold every vertex
(:func:`armanim.arm.fitting.fit_capsules`). A link without ``<collision>`` elements is fitted to its
``<visual>`` meshes instead. A collision mesh that is missing, of another format or unreadable is
an error at its URDF line: its link's capsules would not be the robot.

Fits are kept in a cache folder by the content of the meshes as placed (the vertices' and
triangles' bytes, and :data:`FIT_VERSION`), so the second run of a robot reads them back: the folder is
``ARMANIM_CACHE_DIR``, else the user's cache folder (``XDG_CACHE_HOME`` or ``~/.cache``) under
``armanim/capsules``; when none is writable there is no cache and each run fits again. Never in the
package.
"""

from __future__ import annotations

import functools
import hashlib
import json
import os
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from armanim.arm.fitting import CHUNK, FittedCapsule, fit_capsules
from armanim.errors import Diagnostic, SceneError, shown_path
from armanim.output.cachedir import capsule_cache_path
from armanim.scene import visuals
from armanim.scene.fields import LIMITS
from armanim.scene.meshfiles import mesh_format, raise_if_interrupted
from armanim.scene.urdf import Robot, _parse_xml
from armanim.scene.visuals import (
    MeshReader,
    VisualSpec,
    _visual,
    mesh_file_triangles,
    mesh_path,
    unreadable_reason,
)

FIT_VERSION = 5
"""Changes whenever the fit would give other capsules: older cached fits are then not read."""
MAX_CACHE_BYTES = 100_000
"""A cached fit is a few hundred bytes; anything larger is not one."""


@dataclass(frozen=True)
class MeshCapsules:
    """The capsules fitted to a robot's meshes, per link (in the link's frame, metres).

    Attributes
    ----------
    capsules : tuple of (link, FittedCapsule)
    from_visuals : tuple of str
        The links without ``<collision>`` fitted to their visual meshes.
    unread : tuple of str
        Why a link's visual meshes could not be read (their links get no fitted capsule).
    """

    capsules: tuple[tuple[str, FittedCapsule], ...] = ()
    from_visuals: tuple[str, ...] = ()
    unread: tuple[str, ...] = ()
    cached: int = field(default=0, compare=False)
    """How many links' fits were read from the cache."""


def geometry_specs(robot: Robot, tag: str) -> dict[str, list[VisualSpec]]:
    """Each link's ``<collision>`` or ``<visual>`` (``tag``) geometries as written, by link name.

    >>> from armanim.scene.urdf import parse_urdf
    >>> robot = parse_urdf(b'<robot name="r"><link name="a"><collision><origin xyz="0 0 1"/><geometry>'
    ...     b'<mesh filename="a.stl" scale="2 2 2"/></geometry></collision></link></robot>', "r.urdf")
    >>> [(s.kind, s.filename, s.scale) for s in geometry_specs(robot, "collision")["a"]]
    [('mesh', 'a.stl', (2.0, 2.0, 2.0))]
    """
    return {name: list(specs) for name, specs in _specs(robot.raw, robot.file, tag)}


@functools.lru_cache(maxsize=16)
def _specs(raw: bytes, file: str, tag: str) -> tuple[tuple[str, tuple[VisualSpec, ...]], ...]:
    """:func:`geometry_specs` of a URDF's bytes, kept for the last few (a batch on one robot)."""
    root = _parse_xml(raw, file)
    out: dict[str, list[VisualSpec]] = {}
    for link in root.findall("link"):
        name = link.attrib.get("name", "")
        for element in link.findall(tag):
            spec = _visual(name, element, {})
            if spec is not None:
                out.setdefault(name, []).append(spec)
            elif tag == "collision" and _mesh_of(element) is not None:
                # left out, the link would get a joint-to-joint capsule, not the robot's shape
                mesh, origin = _mesh_of(element), element.find("origin")
                given = {
                    f"scale={mesh.attrib.get('scale')!r}": "scale" in mesh.attrib,
                    **{
                        f"origin {k}={origin.attrib[k]!r}": True
                        for k in ("xyz", "rpy")
                        if origin is not None and k in origin.attrib
                    },
                }
                raise SceneError(
                    file,
                    [
                        Diagnostic(
                            "",
                            f"link {name!r}: collision mesh {shown_path(mesh.attrib.get('filename') or '')}: its "
                            f"{', '.join(k for k, v in given.items() if v) or 'numbers'} must be three "
                            "finite numbers each",
                            element.line,
                        )
                    ],
                )
    return tuple((name, tuple(specs)) for name, specs in out.items())


def _mesh_of(element):
    """The ``<mesh>`` of a ``<collision>`` or ``<visual>`` element, or None."""
    geometry = element.find("geometry")
    shape = geometry.children[0] if geometry is not None and geometry.children else None
    return shape if shape is not None and shape.tag == "mesh" else None


def has_collision_elements(robot: Robot, link: str) -> bool:
    """Whether ``link`` has any ``<collision>`` element (usable or not)."""
    return bool(robot.links.get(link))


def mesh_capsules(
    robot: Robot,
    links: tuple[str, ...],
    urdf_dir: Path,
    package_dirs: list[Path],
    max_capsules: int = 3,
    cache: Path | None | bool = True,
) -> MeshCapsules:
    """Capsules fitted to the meshes of ``links``: each link's ``<collision>`` meshes, or for a link
    with no ``<collision>`` at all its ``<visual>`` meshes.

    Parameters
    ----------
    robot : Robot
    links : tuple of str
        The links of the arm's body (base, path, hanging).
    urdf_dir, package_dirs : Path, list of Path
        Where mesh files are found (:func:`armanim.scene.visuals.mesh_path`).
    cache : Path, None or True
        The cache folder; True: :func:`cache_folder`; None: no cache.

    Raises
    ------
    SceneError
        A collision mesh is missing, not a format armanim reads, unreadable, or over the reader's
        limits, at its URDF line (exit 2).
    """
    folder = cache_folder() if cache is True else (cache or None)
    out: list[tuple[str, FittedCapsule]] = []
    from_visuals: list[str] = []
    unread: list[str] = []
    cached = 0
    for link, vertices, faces, visual in link_meshes(robot, links, urdf_dir, package_dirs, unread):
        if visual:
            from_visuals.append(link)
        capsules, hit = fitted(vertices, faces, max_capsules, folder)
        cached += hit
        out += [(link, c) for c in capsules]
    return MeshCapsules(tuple(out), tuple(from_visuals), tuple(unread), cached)


def link_meshes(
    robot: Robot, links: tuple[str, ...], urdf_dir: Path, package_dirs: list[Path], unread: list[str]
) -> Iterator[tuple[str, np.ndarray, np.ndarray, bool]]:
    """Each of ``links`` with meshes to fit: (link, vertices (N, 3), faces (M, 3), whether they are its
    visual meshes), its ``<collision>`` meshes joined in its frame, or for a link with no
    ``<collision>`` at all its ``<visual>`` meshes (why those cannot be read is added to ``unread``).

    Raises
    ------
    SceneError
        A collision mesh is missing, not a format armanim reads, unreadable, or over the reader's limits.
    """
    collisions, visuals = geometry_specs(robot, "collision"), None
    reader = MeshReader(None)
    for link in links:
        specs = [s for s in collisions.get(link, []) if s.kind == "mesh"]
        if specs:
            mesh = _link_mesh(specs, urdf_dir, package_dirs, reader, _raise(robot), "collision")
            visual = False
        elif not has_collision_elements(robot, link):
            visuals = geometry_specs(robot, "visual") if visuals is None else visuals
            specs = [s for s in visuals.get(link, []) if s.kind == "mesh"]
            mesh = _link_mesh(specs, urdf_dir, package_dirs, reader, _noted(unread), "visual") if specs else None
            visual = True
        else:
            continue
        if mesh is not None:
            yield link, mesh[0], mesh[1], visual


def _noted(notes: list[str]) -> Callable[[str, int], None]:
    def note(message: str, line: int) -> None:
        notes.append(f"{message} (line {line})")

    return note


def _raise(robot: Robot) -> Callable[[str, int], None]:
    def fail(message: str, line: int) -> None:
        raise robot.error(message, line)

    return fail


def _link_mesh(
    specs: list[VisualSpec],
    urdf_dir: Path,
    package_dirs: list[Path],
    reader: MeshReader,
    problem: Callable[[str, int], None],
    what: str,
) -> tuple[np.ndarray, np.ndarray] | None:
    """One link's meshes joined in its frame (vertices (N, 3), faces (M, 3)); a mesh that cannot
    be read is told to ``problem`` (message, line) and left out. ``what``: collision or visual."""
    parts, offset = [], 0
    for spec in specs:
        where = f"link {spec.link!r}: {what} mesh {shown_path(spec.filename or '')}"
        if mesh_format(spec.filename or "") is None:
            problem(
                f"{where} is not a format armanim reads (STL, OBJ or COLLADA .dae): give arm.collision for this link",
                spec.line,
            )
            continue
        path = mesh_path(spec.filename or "", urdf_dir, package_dirs)
        if path is None:
            other = visuals.not_a_file(visuals.mesh_candidates(spec.filename or "", urdf_dir, package_dirs))
            problem(
                f"{where} {other}"
                if other
                else f"{where} not found (set arm.package_dirs to the folders its "
                "package:// names live in, or give arm.collision)",
                spec.line,
            )
            continue
        try:
            mesh = mesh_file_triangles(spec, path, reader)
        except Exception as error:  # a user's file: its reader's error, said at the URDF's line
            raise_if_interrupted()
            problem(f"{where} could not be read ({unreadable_reason(error)})", spec.line)
            continue
        if not reader.keep(mesh.triangles):
            problem(
                f"{where}: the robot's meshes hold more than {visuals.MAX_LOOK_TRIANGLES:,} triangles in all "
                "(give arm.collision, or simpler collision meshes)",
                spec.line,
            )
            continue
        if not np.isfinite(mesh.vertices).all():
            problem(
                f"{where}: the file holds corners that are not finite numbers (NaN or infinity; fix or re-export the mesh)",
                spec.line,
            )
            continue
        vertices = placed(mesh.vertices, spec.origin)
        finite = np.isfinite(vertices).all(axis=1)
        if not finite.all():
            problem(f"{where}: its scale or origin puts vertices beyond the finite numbers", spec.line)
            continue
        farthest = float(np.abs(vertices).max(initial=0.0))
        if farthest > LIMITS["magnitude"]:
            problem(
                f"{where}: its vertices lie up to {farthest:.3g} from the link's frame (expected at most "
                f"{LIMITS['magnitude']:g}, as every length of a scene: check its scale and the file's units)",
                spec.line,
            )
            continue
        parts.append((vertices, mesh.faces + offset))
        offset += len(vertices)
    if not parts or not offset:
        return None
    return np.concatenate([p[0] for p in parts]), np.concatenate([p[1] for p in parts])


def placed(vertices: np.ndarray, origin: np.ndarray) -> np.ndarray:
    """(N, 3) the vertices turned and moved by the 4x4 ``origin``, a chunk of rows at a time by
    broadcast products (numpy's (N, 3) @ (3, 3) took 1-3 s for a 65 MB STL in one call, which a
    Ctrl-C waits for).

    >>> placed(np.array([[1.0, 2, 3]]), np.array([[0.0, -1, 0, 1], [1, 0, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])).tolist()
    [[-1.0, 1.0, 3.0]]
    """
    turn, move = np.asarray(origin, dtype=float)[:3, :3], np.asarray(origin, dtype=float)[:3, 3]
    out = np.empty((len(vertices), 3))
    for k in range(0, len(vertices), CHUNK):
        chunk = np.asarray(vertices[k : k + CHUNK], dtype=float)
        out[k : k + CHUNK] = chunk[:, :1] * turn[:, 0] + chunk[:, 1:2] * turn[:, 1] + chunk[:, 2:3] * turn[:, 2] + move
    return out


def fitted(
    vertices: np.ndarray, faces: np.ndarray, max_capsules: int, folder: Path | None
) -> tuple[list[FittedCapsule], bool]:
    """The fit of one link's mesh, from the cache ``folder`` when it holds it (then True), else
    fitted and kept there."""
    key = content_key(vertices, faces, max_capsules)
    known = _cached(folder, key) if folder is not None else None
    if known is not None:
        return known, True
    capsules = fit_capsules(vertices, faces, max_capsules)
    if folder is not None:
        _keep(folder, key, capsules)
    return capsules, False


def content_key(vertices: np.ndarray, faces: np.ndarray, max_capsules: int) -> str:
    """The cache's name for a fit: the SHA-256 of the fit's version, its settings and the mesh as placed.

    >>> content_key(np.zeros((1, 3)), np.zeros((0, 3), int), 3)[:12]
    '62825dc65b02'
    """
    digest = hashlib.sha256(f"armanim capsules v{FIT_VERSION} max {max_capsules}\n".encode())
    digest.update(np.ascontiguousarray(vertices, dtype="<f8").tobytes())
    digest.update(np.ascontiguousarray(faces, dtype="<i8").tobytes())
    return digest.hexdigest()


def cache_folder() -> Path | None:
    """The writable folder fits are kept in (``ARMANIM_CACHE_DIR``, else the user's cache folder's
    ``armanim/capsules``: :func:`armanim.output.cachedir.capsule_cache_path`), made if missing; None
    when none is writable (no cache)."""
    folder = capsule_cache_path()
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError:
        return None
    return folder if os.access(folder, os.W_OK | os.X_OK) else None


def _cached(folder: Path, key: str) -> list[FittedCapsule] | None:
    """The fit kept under ``key``, or None (absent, or not a fit armanim wrote: then fitted again)."""
    from armanim.output.files import read_bounded
    from armanim.output.jsontext import parse_json

    path = folder / f"{key}.json"
    try:
        data = parse_json(read_bounded(path, MAX_CACHE_BYTES, "a cached capsule fit"))  # (nested deep: ValueError)
        capsules = [
            FittedCapsule(np.array(c["from"], dtype=float), np.array(c["to"], dtype=float), float(c["radius"]))
            for c in data["capsules"]
        ]
    except (OSError, SceneError, ValueError, KeyError, TypeError):
        return None
    good = (
        data.get("key") == key
        and 1 <= len(capsules) <= 3
        and all(
            c.start.shape == (3,)
            and c.end.shape == (3,)
            and np.isfinite([*c.start, *c.end, c.radius]).all()
            and c.radius >= 0
            for c in capsules
        )
    )
    return capsules if good else None


def _keep(folder: Path, key: str, capsules: list[FittedCapsule]) -> None:
    """Write a fit into the cache (atomically); a cache that cannot be written is left alone, and
    so is a link at the entry's name: armanim writes regular files there, and a write would go
    through the link to a file that is not the cache's (campaign 10: a user's file held the fit)."""
    from armanim.output.atomic import write_text_atomic

    if os.path.islink(folder / f"{key}.json"):
        return

    text = json.dumps(
        {
            "key": key,
            "capsules": [{"from": c.start.tolist(), "to": c.end.tolist(), "radius": c.radius} for c in capsules],
        }
    )
    try:
        write_text_atomic(folder / f"{key}.json", text + "\n")
    except Exception:  # noqa: BLE001  a full disk or a read-only cache: the run goes on without keeping it
        raise_if_interrupted()


def collision_yaml(capsules, header: str = "") -> str:
    """Capsules as the scene's ``arm.collision`` list (YAML: one flow mapping a line), each
    ``(link, start, end, radius)`` in metres, ``header`` as comment lines above it.

    >>> print(collision_yaml([("l1", [0, 0, 0.5], [0, 0, 1.0], 0.05)], "fitted"), end="")
    # fitted
    collision:
      - {link: "l1", from: [0.0, 0.0, 0.5], to: [0.0, 0.0, 1.0], radius: 0.05}
    """
    lines = [f"# {line}" if line else "#" for line in header.splitlines()]
    lines.append("collision:" + ("" if capsules else " []"))
    for link, start, end, radius in capsules:
        lines.append(
            f"  - {{link: {json.dumps(link)}, from: {_vector(start)}, to: {_vector(end)}, radius: {_number(radius)}}}"
        )
    return "\n".join(lines) + "\n"


def _vector(v) -> str:
    return "[" + ", ".join(_number(x) for x in np.asarray(v, dtype=float)) + "]"


def _number(x) -> str:
    """A float as the shortest decimal that reads back to it, without an exponent (YAML 1.1
    readers take ``7e-06`` for a string).

    >>> _number(7e-06), _number(-0.0), _number(2.0)
    ('0.000007', '0.0', '2.0')
    """
    return np.format_float_positional(float(x) + 0.0, unique=True, trim="0")
