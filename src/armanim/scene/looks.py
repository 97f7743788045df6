"""What the pictures draw as meshes for a scene: its robot's look (a bundled robot's shipped
meshes, or a user's URDF visuals: :mod:`armanim.scene.visuals`), the tool ``arm.tool`` draws (a
pen, a mesh file, Franka's hand) and the furniture ``render.furniture`` draws, placed on the arm's
chain or in the world. Drawing only: nothing here is checked for clearance.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np

from armanim.arm.chain import transform
from armanim.arm.visuals import ArmMeshes, LinkMesh, LinkPlaces, placed_meshes
from armanim.errors import shown_path
from armanim.output.files import is_regular_file
from armanim.scene.convert import tool_frame
from armanim.scene.meshfiles import mesh_format, raise_if_interrupted
from armanim.scene.robots import bundled_robot
from armanim.scene.urdf import read_urdf
from armanim.scene.visuals import (
    MeshReader,
    VisualSpec,
    bundled_link_meshes,
    default_package_dirs,
    finite_part,
    link_meshes,
    mesh_file_triangles,
    not_a_file,
    placed_link_meshes,
    simplified,
    unreadable_reason,
    visual_specs,
)


def scene_meshes(
    arm,
    places: LinkPlaces | None,
    package_dirs: list[Path] | None = None,
    triangles: int | None = None,
    scene_dir: Path | None = None,
    furniture=(),
    robot: bool = True,
    urdf_dir: Path | None = None,
) -> tuple[ArmMeshes | None, list[str]]:
    """What the pictures draw as meshes: the look of a scene's URDF arm (``arm``: a validated
    :class:`~armanim.scene.armmodel.ArmModel` with its files read; left out when ``robot`` is
    False) and the scene's ``furniture`` (``render.furniture``: boxes in the world).

    ``places``: where each of the arm's links sits on the problem's arm
    (:attr:`armanim.scene.convert.ConvertedScene.places`, made with the problem: the arm is not
    converted again here); None for an arm of links.

    The arm's look is a bundled robot's shipped meshes, or the visuals of a user's URDF found
    under ``package_dirs`` (default: the URDF's folder and its parents), simplified to about
    ``triangles`` (None: as read, at most :data:`TRIANGLE_BUDGET`), with the tool ``arm.tool``
    draws (a pen, or a mesh file relative to ``scene_dir``), placed on the arm's chain as the
    scene mounts it. Returns them (None: nothing to draw as meshes) and a note per visual that
    could not be read. ``urdf_dir``: the folder the URDF's mesh names start from (default: the
    URDF's own; a run folder's copy of a URDF gives its original's)."""
    fixed = furniture_meshes(furniture)
    urdf = arm.urdf_arm if robot and arm.is_urdf else None
    if urdf is None or urdf.robot is None:
        return (placed_meshes(fixed, [-1] * len(fixed), [np.eye(4)] * len(fixed)) if fixed else None), []
    notes: list[str] = []
    reader = MeshReader()  # one for the robot and its tool: each file read once, the bytes bounded in all
    if urdf.bundled is not None:
        meshes = bundled_link_meshes(urdf.bundled.urdf.parent)
    else:
        folder = urdf_dir or urdf.folder or Path(".")
        specs = visual_specs(urdf.robot.raw, urdf.file, notes.append)
        meshes = link_meshes(specs, folder, package_dirs or default_package_dirs(folder), notes.append, reader=reader)
    notes = [f"{urdf.file}: {note}" for note in notes]
    total = sum(m.triangles for m in meshes)
    if triangles is not None and total > triangles:
        meshes = [simplified(m, max(12, round(m.triangles * triangles / total))) for m in meshes]
    meshes += tool_meshes(arm.tool, urdf.tip_link, scene_dir or Path("."), notes.append, reader)
    assert places is not None, "a URDF arm's links have their places (convert_scene)"
    placed = placed_link_meshes(meshes, urdf.robot, places, fixed)
    return (placed if placed.triangles else None), notes


def furniture_meshes(furniture) -> list[LinkMesh]:
    """Each ``render.furniture`` box as a mesh in the world (its 12 triangles, its colour)."""
    out = []
    for item in furniture:
        box = item.box
        corners = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]) * np.asarray(box.size) / 2
        turn = transform(box.center, np.radians(box.rpy))
        faces = np.array(
            [
                [0, 1, 3],
                [0, 3, 2],
                [4, 6, 7],
                [4, 7, 5],
                [0, 4, 5],
                [0, 5, 1],
                [2, 3, 7],
                [2, 7, 6],
                [0, 2, 6],
                [0, 6, 4],
                [1, 5, 7],
                [1, 7, 3],
            ]
        )
        out.append(LinkMesh("furniture", corners @ turn[:3, :3].T + turn[:3, 3], faces, np.tile(item.color, (12, 1))))
    return out


PEN_BODY_RGB = (0.55, 0.27, 0.68)
"""The pen's body, purple: no colour of the tool triad it lies along (a blue pen on the triad's
blue z axis read as one line, issue 50), nor of the ink, the tip path, the near tint or the
obstacles; its nib is :data:`PEN_NIB_RGB`."""
PEN_NIB_RGB = (0.15, 0.15, 0.17)
NIB_SHARE = 0.18
"""The share of the pen's length that is its tapering nib."""


PEN_SECTIONS = 20
"""Wedges around the pen's nib and body."""


def revolved(profile: np.ndarray, sections: int) -> tuple[np.ndarray, np.ndarray]:
    """A solid of revolution about z: ``profile`` (k, 2), each point's (radius, height), turned a full
    turn in ``sections`` wedges. Returns vertices (V, 3) and faces (F, 3), outward for a profile that
    runs counter-clockwise: the very arrays ``trimesh.creation.revolve`` makes (its zero-area triangles
    left out, the points on the axis merged, vertices in the order first met), without importing trimesh
    (some 0.7 s of CPU, which a video of a pen paid for its two shapes)."""
    per = len(profile)
    theta = np.linspace(0, 2 * np.pi, sections + 1)
    ring = np.column_stack((np.cos(theta), np.sin(theta)))
    vertices = np.column_stack(
        (
            np.tile(ring, (1, per)).reshape((-1, 2)) * np.tile(profile[:, 0], len(ring)).reshape((-1, 1)),
            np.tile(profile[:, 1], len(ring)),
        )
    )[:-per]  # the last ring is the first
    wedge = np.tile(np.array([0, per, 1, 1, per, per + 1]), per - 1).reshape((-1, 3))
    wedge += np.tile(np.arange(per - 1), (2, 1)).T.reshape((-1, 1))
    a, b, c = (vertices[wedge[:, i]] for i in range(3))
    wedge = wedge[np.linalg.norm(np.cross(b - a, c - a), axis=1) / 2.0 > 10.0**-MERGE_DIGITS]
    offset = np.tile(np.arange(sections) * per, (len(wedge), 1)).T.reshape((-1, 1))
    faces = (np.tile(wedge.ravel(), sections).reshape((-1, 3)) + offset) % len(vertices)
    _, first, inverse = np.unique(
        np.round(vertices * 10.0**MERGE_DIGITS).astype(np.int64), axis=0, return_index=True, return_inverse=True
    )
    order = np.argsort(first)  # the merged vertices in the order first met
    rank = np.empty_like(order)
    rank[order] = np.arange(len(order))
    return vertices[first[order]], rank[inverse.ravel()][faces]


MERGE_DIGITS = 8
"""Vertices equal to this many decimals are one, and a triangle of less area than 10^-this is none
(trimesh's ``tol.merge``)."""


def tool_meshes(
    tool, tip_link: str, scene_dir: Path, warn: Callable[[str], None], reader: MeshReader | None = None
) -> list[LinkMesh]:
    """What ``tool`` (``arm.tool``, or None) draws, in the tip link's frame: a pen (its nib at the
    tool point, its body back along the tool frame's -z) and a mesh file in the tool frame, read
    by ``reader`` (the robot's, so the bounds are the look's in all)."""
    if tool is None or (tool.pen is None and tool.mesh is None and tool.gripper is None):
        return []
    frame = tool_frame(tool)
    parts = []
    if tool.pen is not None:
        length, radius = tool.pen.length, tool.pen.radius
        nib_length, body_length = NIB_SHARE * length, (1 - NIB_SHARE) * length
        half = abs(float(body_length)) / 2.0
        nib = revolved(np.array([[0.0, 0.0], [radius, 0.0], [0.0, nib_length]]), PEN_SECTIONS)
        body = revolved(np.array([[0.0, -half], [radius, -half], [radius, half], [0.0, half]]), PEN_SECTIONS)
        for (vertices, faces), shift, rgb in (
            (nib, -nib_length, PEN_NIB_RGB),  # its apex at the tool point
            (body, -nib_length - body_length / 2, PEN_BODY_RGB),
        ):
            parts.append(
                LinkMesh(tip_link, vertices + np.array([0.0, 0.0, shift]), faces, np.tile(rgb, (len(faces), 1)))
            )
    if (
        tool.mesh is not None
        and (mesh := _tool_file(tool.mesh, tip_link, scene_dir / tool.mesh, warn, reader)) is not None
    ):
        parts.append(mesh)
    placed = [LinkMesh(tip_link, m.vertices @ frame[:3, :3].T + frame[:3, 3], m.faces, m.colors) for m in parts]
    return placed + (panda_gripper(tip_link) if tool.gripper == "panda" else [])


def _tool_file(
    name: str, tip_link: str, path: Path, warn: Callable[[str], None], reader: MeshReader | None
) -> LinkMesh | None:
    """``arm.tool.mesh`` (``name``, at ``path``) read, in the tool frame; None and a note when it
    cannot be (a FIFO, a folder or a device there is never opened: it is not a regular file)."""
    if mesh_format(path.name) is None:
        reason = "could not be read (not a format armanim reads (STL, OBJ or COLLADA .dae; archives are never opened))"
    elif not is_regular_file(path):
        reason = not_a_file([path]) or "not found (it is relative to the scene file's folder)"
    else:
        try:
            return finite_part(
                mesh_file_triangles(
                    VisualSpec(tip_link, np.eye(4), "mesh", name, (1.0, 1.0, 1.0), (), None, 0),
                    path,
                    reader or MeshReader(),
                )
            )
        except Exception as error:  # a user's file: any reader error is a note, never a failed run
            raise_if_interrupted()  # ... unless it is an interrupt a library turned into an error
            reason = f"could not be read ({unreadable_reason(error)})"
    warn(f"arm.tool.mesh: {shown_path(str(path))} {reason}: the tool is not drawn")
    return None


def panda_gripper(tip_link: str) -> list[LinkMesh]:
    """Franka's hand and closed fingers (the bundled Panda's meshes) on ``tip_link``'s frame, as the
    Panda's URDF mounts them on its flange (its hand and finger joints' origins, at zero)."""
    panda = bundled_robot("panda")
    joints = read_urdf(panda.urdf).joints
    hand = joints["panda_hand_joint"].origin
    at = {
        "panda_hand": hand,
        "panda_leftfinger": hand @ joints["panda_finger_joint1"].origin,
        "panda_rightfinger": hand @ joints["panda_finger_joint2"].origin,
    }
    return [
        LinkMesh(tip_link, m.vertices @ at[m.link][:3, :3].T + at[m.link][:3, 3], m.faces, m.colors)
        for m in bundled_link_meshes(panda.urdf.parent)
        if m.link in at
    ]


__all__ = ["furniture_meshes", "panda_gripper", "scene_meshes", "tool_meshes"]
