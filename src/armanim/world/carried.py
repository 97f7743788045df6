"""Objects the arm carries: a named obstacle taken off the world at a grasp, fixed to the tool
frame, and put back at a release.

A carried object is a :class:`Body` (a box, sphere, capsule or cylinder in its own frame, at a
pose). While it is carried the arm's clearances are measured from collision capsules, so the
object is represented by a *cover*: capsules whose union contains the whole solid
(:func:`cover_capsules`; exact for a sphere and a capsule, a little larger for a box or a
cylinder). Every clearance measured from the cover is therefore at most the solid's own: a
carried object kept ``clearance`` away by its cover is at least that far away itself.

The pose arithmetic (:func:`grasp_offset`, :func:`placed_body`) is one composition of rigid
transforms: the object's pose in the tool frame at the grasp, and the tool's pose at the release
times that offset. Pure core: numpy only, scene units, no I/O.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import cast

import numpy as np

from armanim.world.obstacles import BOX, CYLINDER, FLOOR, ROD, SPHERE, Boxes, Cylinders, Obstacles, Rods

CELLS_PER_SIDE = 2
"""A box's cover splits its two shorter sides into cells of at most half the shorter one (2 per
side of a square section): each cell is one capsule along the box's longest axis, whose radius
reaches the cell's corners. The cover then lies within 0.37 of the shorter half side beyond the
box everywhere (a 5 cm cube: 4.6 mm)."""


@dataclass(frozen=True)
class Body:
    """A solid at a pose: what a named obstacle is while it moves.

    Attributes
    ----------
    kind : int
        :data:`~armanim.world.obstacles.SPHERE`, ``BOX``, ``ROD`` (a capsule) or ``CYLINDER``.
    rotation : (3, 3) array
        World-from-body rotation.
    center : (3,) array
        The body's centre in the world.
    half : (3,) array
        Half the box's edges along its own axes; a capsule's half segment length along its x
        (its axis), a cylinder's half height along its z; 0 for a sphere.
    radius : float
        A sphere's, capsule's or cylinder's radius; 0 for a box.
    """

    kind: int
    rotation: np.ndarray
    center: np.ndarray
    half: np.ndarray
    radius: float = 0.0

    def matrix(self) -> np.ndarray:
        """(4, 4) the world-from-body transform.

        >>> Body(SPHERE, np.eye(3), np.array([1.0, 2, 3]), np.zeros(3), 0.5).matrix()[:3, 3].tolist()
        [1.0, 2.0, 3.0]
        """
        out = np.eye(4)
        out[:3, :3], out[:3, 3] = self.rotation, self.center
        return out

    def moved(self, matrix: np.ndarray) -> Body:
        """The same solid at the world-from-body transform ``matrix`` (4, 4)."""
        return replace(self, rotation=np.array(matrix[:3, :3]), center=np.array(matrix[:3, 3]))

    def width(self) -> float:
        """The solid's least width across, scene units: what a gripper's opening must take.

        >>> Body(BOX, np.eye(3), np.zeros(3), np.array([0.02, 0.05, 0.1])).width()
        0.04
        """
        if self.kind == BOX:
            return float(2.0 * self.half.min())
        return 2.0 * self.radius

    def extent(self, direction: np.ndarray) -> float:
        """The solid's width along the unit world ``direction`` (3,): the distance between its two
        supporting planes across it (what fingers closing along it meet).

        >>> box = Body(BOX, np.eye(3), np.zeros(3), np.array([0.02, 0.05, 0.1]))
        >>> round(box.extent(np.array([0.0, 1.0, 0.0])), 12), round(box.extent(np.array([0.6, 0.8, 0.0])), 12)
        (0.1, 0.104)
        """
        local = np.abs(self.rotation.T @ direction)
        if self.kind == BOX:
            return float(2.0 * local @ self.half)
        axis = 0 if self.kind == ROD else 2  # a capsule's segment along x, a cylinder's height along z
        if self.kind == CYLINDER:
            return float(
                2.0 * (self.radius * np.sqrt(max(0.0, 1.0 - local[axis] ** 2)) + self.half[axis] * local[axis])
            )
        return float(2.0 * (self.radius + self.half[axis] * local[axis]))


def obstacle_body(obstacles: Obstacles, column: int) -> Body:
    """The solid of clearance column ``column`` (not the floor) as a :class:`Body`.

    >>> obs = Obstacles(np.array([[1.0, 0, 0]]), np.array([0.1]), np.ones(1))
    >>> b = obstacle_body(obs, 0)
    >>> b.kind == SPHERE, b.center.tolist(), b.radius
    (True, [1.0, 0.0, 0.0], 0.1)
    """
    kind = int(obstacles.kinds[column])
    index = int(np.searchsorted(obstacles.columns(kind), column))
    if kind == SPHERE:
        return Body(SPHERE, np.eye(3), obstacles.centers[index].copy(), np.zeros(3), float(obstacles.radii[index]))
    if kind == BOX:
        b = obstacles.boxes
        return Body(BOX, b.rotations[index].copy(), b.centers[index].copy(), b.half[index].copy())
    if kind == ROD:
        axis = obstacles.rods.axes()
        return Body(
            ROD,
            axis.rotations[index].copy(),
            axis.centers[index].copy(),
            axis.half[index].copy(),
            float(obstacles.rods.radius[index]),
        )
    if kind == CYLINDER:
        c = obstacles.cylinders
        return Body(
            CYLINDER,
            c.rotations[index].copy(),
            c.centers[index].copy(),
            np.array([0.0, 0.0, c.half_length[index]]),
            float(c.radius[index]),
        )
    raise ValueError(f"column {column} is the floor, which no arm carries")


def with_bodies(obstacles: Obstacles, bodies: dict[int, Body | None]) -> Obstacles:
    """``obstacles`` with the solids of some columns moved (a :class:`Body`) or taken away (None),
    every other column as it was, in the same order (the floor last).

    >>> obs = Obstacles(np.zeros((2, 3)), np.ones(2), np.full(2, 0.5), names=("a", "b"))
    >>> out = with_bodies(obs, {0: None})
    >>> len(out), out.names
    (1, ('b',))
    """
    solids: list[tuple[Body, float, str | None]] = []
    for column, kind in enumerate(obstacles.kinds.tolist()):
        if kind == FLOOR:
            continue
        body = bodies[column] if column in bodies else obstacle_body(obstacles, column)
        if body is not None:
            solids.append((body, float(obstacles.influence[column]), obstacles.name(column)))
    return solids_obstacles(solids, obstacles.floor)


def solids_obstacles(solids: list[tuple[Body, float, str | None]], floor: float | None = None) -> Obstacles:
    """Obstacles of solids (each a :class:`Body`, its influence and its name) in order, and the floor last."""
    spheres = [b for b, _, _ in solids if b.kind == SPHERE]
    boxes = [b for b, _, _ in solids if b.kind == BOX]
    rods = [b for b, _, _ in solids if b.kind == ROD]
    cylinders = [b for b, _, _ in solids if b.kind == CYLINDER]
    kinds = [b.kind for b, _, _ in solids] + ([FLOOR] if floor is not None else [])
    influence = [i for _, i, _ in solids] + ([0.0] if floor is not None else [])
    names = [n for _, _, n in solids]
    ends = [(b.center - b.rotation[:, 0] * b.half[0], b.center + b.rotation[:, 0] * b.half[0]) for b in rods]
    return Obstacles(
        centers=np.array([b.center for b in spheres], dtype=float).reshape(-1, 3),
        radii=np.array([b.radius for b in spheres], dtype=float),
        influence=np.array(influence, dtype=float),
        boxes=Boxes(
            np.array([b.center for b in boxes]).reshape(-1, 3),
            np.array([b.half for b in boxes]).reshape(-1, 3),
            np.array([b.rotation for b in boxes]).reshape(-1, 3, 3),
        ),
        rods=Rods(
            np.array([a for a, _ in ends]).reshape(-1, 3),
            np.array([b for _, b in ends]).reshape(-1, 3),
            np.array([b.radius for b in rods], dtype=float),
        ),
        floor=floor,
        kinds=np.array(kinds, dtype=int),
        cylinders=Cylinders(
            np.array([b.center for b in cylinders]).reshape(-1, 3),
            np.array([b.rotation for b in cylinders]).reshape(-1, 3, 3),
            np.array([b.half[2] for b in cylinders], dtype=float),
            np.array([b.radius for b in cylinders], dtype=float),
        ),
        names=tuple(names) if any(n is not None for n in names) else (),
    )


def cover_capsules(body: Body) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Capsules whose union contains the solid, in the body's own frame: starts (k, 3), ends
    (k, 3), radii (k,).

    A sphere is one capsule of no length and a capsule itself (both exact). A box is split
    across its two shorter sides into cells (:data:`CELLS_PER_SIDE`), one capsule per cell along
    the longest side: each cell is a prism of half sides u, v (across) and h (along); its capsule
    runs along the prism's axis to ``e = min(h, max(u, v))`` short of each end face, with radius
    sqrt(u^2 + v^2 + e^2), which reaches the prism's corners (its farthest points from that
    segment). A cylinder as tall as it is wide or taller is one capsule along its axis, stopping
    ``e = min(h, r)`` short of each face, of radius sqrt(r^2 + e^2); a flatter cylinder is covered
    as the box around it.

    >>> s, e, r = cover_capsules(Body(BOX, np.eye(3), np.zeros(3), np.array([0.1, 0.02, 0.02])))
    >>> len(r), round(float(r[0]), 6), e[0].round(6).tolist()
    (4, 0.017321, [0.09, -0.01, -0.01])
    """
    if body.kind == SPHERE:
        return np.zeros((1, 3)), np.zeros((1, 3)), np.array([body.radius])
    if body.kind == ROD:
        along = np.array([body.half[0], 0.0, 0.0])
        return -along[None], along[None], np.array([body.radius])
    if body.kind == CYLINDER:
        h, r = float(body.half[2]), body.radius
        if h >= r:
            e = min(h, r)
            along = np.array([0.0, 0.0, h - e])
            return -along[None], along[None], np.array([math.hypot(r, e)])
        return _box_cover(np.array([r, r, h]))
    return _box_cover(body.half)


def _box_cover(half: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`cover_capsules` of a box of half edges ``half`` (3,) centred at the origin."""
    axis = int(np.argmax(half))
    across = [i for i in range(3) if i != axis]
    u, v = half[across[0]], half[across[1]]
    cell = min(u, v) / CELLS_PER_SIDE
    nu, nv = max(1, math.ceil(u / cell - 1e-9)), max(1, math.ceil(v / cell - 1e-9))
    cu, cv = u / nu, v / nv
    e = min(float(half[axis]), max(cu, cv))
    radius = math.sqrt(cu * cu + cv * cv + e * e)
    starts, ends = [], []
    for i in range(nu):
        for j in range(nv):
            point = np.zeros(3)
            point[across[0]] = -u + cu * (2 * i + 1)
            point[across[1]] = -v + cv * (2 * j + 1)
            a, b = point.copy(), point.copy()
            a[axis], b[axis] = -(half[axis] - e), half[axis] - e
            starts.append(a)
            ends.append(b)
    return np.array(starts), np.array(ends), np.full(len(starts), radius)


def grasp_offset(tool: np.ndarray, body: Body) -> np.ndarray:
    """(4, 4) the object's pose in the tool frame: tool^-1 . object, ``tool`` the world-from-tool
    transform (4, 4) at the grasp.

    >>> tool = np.eye(4); tool[:3, 3] = [1.0, 0, 0]
    >>> grasp_offset(tool, Body(SPHERE, np.eye(3), np.array([1.0, 0, -0.1]), np.zeros(3), 0.05))[:3, 3].tolist()
    [0.0, 0.0, -0.1]
    """
    rotation = tool[:3, :3].T
    out = np.eye(4)
    out[:3, :3] = rotation @ body.rotation
    out[:3, 3] = rotation @ (body.center - tool[:3, 3])
    return out


def placed_body(tool: np.ndarray, offset: np.ndarray, body: Body) -> Body:
    """The carried ``body`` where a tool at ``tool`` (4, 4, world-from-tool) holding it at
    ``offset`` (4, 4, :func:`grasp_offset`) puts it: tool . offset.

    >>> tool = np.eye(4); tool[:3, 3] = [0.0, 1, 0]
    >>> off = np.eye(4); off[:3, 3] = [0.0, 0, -0.1]
    >>> placed_body(tool, off, Body(SPHERE, np.eye(3), np.zeros(3), np.zeros(3), 0.05)).center.tolist()
    [0.0, 1.0, -0.1]
    """
    return body.moved(cast(np.ndarray, tool @ offset))


def tool_matrix(rotation: np.ndarray, point: np.ndarray) -> np.ndarray:
    """(..., 4, 4) world-from-tool transforms from the tool's rotation (..., 3, 3) and point (..., 3)."""
    out = np.zeros(np.shape(point)[:-1] + (4, 4))
    out[..., :3, :3], out[..., :3, 3], out[..., 3, 3] = rotation, point, 1.0
    return out


def cover_margin(body: Body) -> float:
    """The most :func:`cover_capsules` lies beyond the solid, scene units (0: exact).

    >>> round(cover_margin(Body(BOX, np.eye(3), np.zeros(3), np.array([0.02, 0.02, 0.02]))), 6)
    0.007321
    """
    if body.kind in (SPHERE, ROD):
        return 0.0
    if body.kind == CYLINDER and body.half[2] >= body.radius:
        return math.hypot(body.radius, body.radius) - body.radius
    half = np.array([body.radius, body.radius, body.half[2]]) if body.kind == CYLINDER else body.half
    axis = int(np.argmax(half))
    u, v = (half[i] for i in range(3) if i != axis)
    cell = min(u, v) / CELLS_PER_SIDE
    cu, cv = u / max(1, math.ceil(u / cell - 1e-9)), v / max(1, math.ceil(v / cell - 1e-9))
    e = min(float(half[axis]), max(cu, cv))
    beyond = (
        (math.sqrt(2.0) - 1.0) * body.radius if body.kind == CYLINDER else 0.0
    )  # the box round a flat cylinder: its corners
    return float(math.sqrt(cu * cu + cv * cv + e * e) - min(cu, cv, e) + beyond)


def world_cover(body: Body) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`cover_capsules` in the world: starts (k, 3), ends (k, 3), radii (k,)."""
    start, end, radius = cover_capsules(body)
    return start @ body.rotation.T + body.center, end @ body.rotation.T + body.center, radius


def cover_clearances(body: Body, obstacles: Obstacles) -> np.ndarray:
    """(m,) the least clearance of ``body``'s cover to each column of ``obstacles`` (the floor: its
    lowest point's height above it)."""
    from armanim.arm.capsules import Capsules
    from armanim.arm.kinematics import Pose
    from armanim.world.distances import clearances

    start, end, radius = world_cover(body)
    caps = Capsules(np.zeros(len(radius), dtype=int), start, end, radius)
    at_origin = Pose(
        points=np.zeros((2, 3)), frames=np.eye(3)[None]
    )  # one joint at the world's origin: its frame is the world
    d = clearances(at_origin, obstacles, caps).links.min(axis=0) if len(obstacles) else np.zeros(0)
    if obstacles.floor is not None:  # the parts of joint 1 stand on the base, which the floor exempts: measured here
        d[obstacles.columns(FLOOR)] = float(np.min(np.minimum(start[:, 2], end[:, 2]) - radius)) - obstacles.floor
    return cast(np.ndarray, d)


def resting_clearances(obstacles: Obstacles, column: int) -> np.ndarray:
    """(m,) how far the cover of the object in ``column`` lies from every column of ``obstacles``
    where it rests (+inf for its own column): what it keeps once the tool takes it there."""
    body = obstacle_body(obstacles, column)
    others = with_bodies(obstacles, {column: None})
    d = np.full(len(obstacles), np.inf)
    d[np.arange(len(obstacles)) != column] = cover_clearances(body, others)
    return d


def bodies_obstacles(bodies: list[Body]) -> Obstacles:
    """The solids ``bodies`` as :class:`~armanim.world.obstacles.Obstacles` (no floor, no
    influence), in order: what a picture draws of the objects that move."""
    return solids_obstacles([(b, 0.0, None) for b in bodies])
