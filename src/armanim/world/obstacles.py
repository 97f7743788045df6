"""The obstacles of the world: solid spheres, boxes, capsules, cylinders and a floor, each (but the
floor) with an influence shell.

Clearances (:mod:`armanim.world.distances`) have one column per obstacle, in the order of
:attr:`Obstacles.columns` (the scene's order), then one for the floor when there is one.
Pure core: numpy only, scene units, no I/O.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, cast

import numpy as np

SPHERE, BOX, ROD, FLOOR, CYLINDER = 0, 1, 2, 3, 4
"""Kinds of obstacle (:attr:`Obstacles.kinds`)."""


@dataclass(frozen=True)
class Boxes:
    """Solid boxes.

    Attributes
    ----------
    centers : (k, 3) array
    half : (k, 3) array
        Half the edge lengths along the box's own axes (> 0).
    rotations : (k, 3, 3) array
        World-from-box rotation of each box (its columns are the box's axes in the world).
    """

    centers: np.ndarray
    half: np.ndarray
    rotations: np.ndarray

    @classmethod
    def none(cls) -> Boxes:
        """No boxes."""
        return cls(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros((0, 3, 3)))

    def __len__(self) -> int:
        return len(self.centers)

    def corners(self) -> np.ndarray:
        """(k, 8, 3) world corners of every box, corner j at signs (-1)^bits of j (x: bit 2, y: bit 1, z: bit 0).

        >>> Boxes(np.zeros((1, 3)), np.array([[1.0, 2, 3]]), np.eye(3)[None]).corners()[0, 7].tolist()
        [1.0, 2.0, 3.0]
        """
        signs = np.array([[1 if j & 4 else -1, 1 if j & 2 else -1, 1 if j & 1 else -1] for j in range(8)], dtype=float)
        local = signs[None] * self.half[:, None, :]
        return cast(np.ndarray, self.centers[:, None, :] + np.einsum("kab,kjb->kja", self.rotations, local))


@dataclass(frozen=True)
class Rods:
    """Solid capsules (posts, bars): every point within ``radius`` of the segment ``start``-``end``.

    Attributes
    ----------
    start, end : (k, 3) arrays
    radius : (k,) array
        > 0.
    """

    start: np.ndarray
    end: np.ndarray
    radius: np.ndarray

    @classmethod
    def none(cls) -> Rods:
        """No capsules."""
        return cls(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0))

    def __len__(self) -> int:
        return len(self.radius)

    def axes(self) -> Boxes:
        """Each capsule's axis as a box with one edge (half edges (length / 2, 0, 0), its x axis
        along start-end): the capsule is every point within ``radius`` of that box.

        >>> axis = Rods(np.zeros((1, 3)), np.array([[0.0, 0, 2]]), np.ones(1)).axes()
        >>> axis.centers.tolist(), axis.half.tolist(), axis.rotations[0, :, 0].tolist()
        ([[0.0, 0.0, 1.0]], [[1.0, 0.0, 0.0]], [0.0, 0.0, 1.0])
        """
        along = self.end - self.start
        length = np.sqrt((along * along).sum(axis=-1))
        x = np.where(length[:, None] > 0, along / np.where(length > 0, length, 1.0)[:, None], [1.0, 0.0, 0.0])
        helper = np.where(np.abs(x[:, :1]) < 0.9, [1.0, 0.0, 0.0], [0.0, 1.0, 0.0])
        y = np.cross(x, helper)
        y /= np.sqrt((y * y).sum(axis=-1))[:, None]
        half = np.zeros((len(self), 3))
        half[:, 0] = 0.5 * length
        return Boxes(0.5 * (self.start + self.end), half, np.stack([x, y, np.cross(x, y)], axis=-1))


@dataclass(frozen=True)
class Cylinders:
    """Solid cylinders (cans, posts, pipes): the axis is each cylinder's local z, as in MoveIt and URDF.

    Attributes
    ----------
    centers : (k, 3) array
        The middle of each axis, world.
    rotations : (k, 3, 3) array
        World-from-cylinder rotation (its third column is the axis in the world).
    half_length : (k,) array
        Half the height along the axis (> 0).
    radius : (k,) array
        > 0.
    """

    centers: np.ndarray
    rotations: np.ndarray
    half_length: np.ndarray
    radius: np.ndarray

    @classmethod
    def none(cls) -> Cylinders:
        """No cylinders."""
        return cls(np.zeros((0, 3)), np.zeros((0, 3, 3)), np.zeros(0), np.zeros(0))

    def __len__(self) -> int:
        return len(self.radius)

    def ends(self) -> tuple[np.ndarray, np.ndarray]:
        """The centres of the two caps, (k, 3) each: the bottom (local z = -length / 2), the top.

        >>> bottom, top = Cylinders(np.zeros((1, 3)), np.eye(3)[None], np.ones(1), np.ones(1)).ends()
        >>> bottom.tolist(), top.tolist()
        ([[0.0, 0.0, -1.0]], [[0.0, 0.0, 1.0]])
        """
        along = self.rotations[:, :, 2] * self.half_length[:, None]
        return self.centers - along, self.centers + along


@dataclass(frozen=True)
class Obstacles:
    """The world's solids.

    Attributes
    ----------
    centers : (s, 3) array
        The spheres' centres.
    radii : (s,) array
        Radius of each solid sphere (0 allowed: the notes' point obstacle).
    influence : (m,) array
        R of the field F_R of every column of the clearances: how far beyond the surface
        the penalty reaches (the floor's is 0: it has no field, the safety filter alone keeps it).
    boxes : Boxes
    rods : Rods
        Capsule obstacles.
    floor : float or None
        Height of the plane z = floor that every link but those the first joint carries
        keeps its clearance above; None: no floor.
    kinds : (m,) int array or None
        Kind of each column (:data:`SPHERE`, :data:`BOX`, :data:`ROD`, :data:`CYLINDER`,
        :data:`FLOOR`), the floor last; None: the spheres, then the boxes, then the rods, then
        the cylinders, then the floor.
    cylinders : Cylinders
        Solid cylinders (measured apart from the solids: a cylinder is no grown box).
    names : tuple of (str or None)
        Each obstacle's name in the scene's order (None: unnamed; empty: none named), for
        messages and pictures.

    Derived (set on construction, read on every clearance computation)
    ------------------------------------------------------------------
    solids : Boxes
        The boxes and the capsule obstacles' axes (:meth:`Rods.axes`) in the scene's order:
        one pass of :func:`~armanim.world.closest.segment_box` measures both.
    solid_radius : (k,) array
        What each solid is grown by: 0 for a box, the radius for a capsule.
    solid_columns : (k,) int array
        The solids' columns of the clearances.
    solid_axes : (3k, 3) array
        Every solid's transposed rotation stacked: it times a (3, M) column of world points
        gives the points in every solid's frame, (k, 3, M) (less :attr:`solid_origins`), one
        product for all.
    solid_origins : (k, 3, 1) array
        Each solid's centre in its own frame's axes (R^T c).
    solid_half : (k, 3, 1) array
        The solids' half edges laid out as :attr:`solid_axes`' products.
    scene_order : (m,) int array or None
        The columns in the scene's order taken from those of the spheres, the solids, the
        cylinders, then the floor (None: the same order).
    """

    centers: np.ndarray
    radii: np.ndarray
    influence: np.ndarray
    boxes: Boxes = field(default_factory=Boxes.none)
    rods: Rods = field(default_factory=Rods.none)
    floor: float | None = None
    kinds: np.ndarray = cast(np.ndarray, None)  # None: __post_init__ fills it from the counts
    cylinders: Cylinders = field(default_factory=Cylinders.none)
    names: tuple[str | None, ...] = ()
    # derived: set by __post_init__ (see the docstring), never passed
    solids: Boxes = field(init=False, repr=False, compare=False)
    solid_radius: np.ndarray = field(init=False, repr=False, compare=False)
    solid_columns: np.ndarray = field(init=False, repr=False, compare=False)
    solid_axes: np.ndarray = field(init=False, repr=False, compare=False)
    solid_origins: np.ndarray = field(init=False, repr=False, compare=False)
    solid_half: np.ndarray = field(init=False, repr=False, compare=False)
    scene_order: np.ndarray | None = field(init=False, repr=False, compare=False)
    _columns: dict[int, np.ndarray] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if self.kinds is None:
            counts = (
                len(self.radii),
                len(self.boxes),
                len(self.rods),
                len(self.cylinders),
                int(self.floor is not None),
            )
            object.__setattr__(self, "kinds", np.repeat([SPHERE, BOX, ROD, CYLINDER, FLOOR], counts))
        columns = {kind: np.nonzero(self.kinds == kind)[0] for kind in (SPHERE, BOX, ROD, CYLINDER, FLOOR)}
        object.__setattr__(self, "_columns", columns)  # asked for on every clearance computation
        for name, value in _derived_solids(self.boxes, self.rods, columns).items():
            object.__setattr__(self, name, value)

    @classmethod
    def none(cls) -> Obstacles:
        """No obstacles."""
        return cls(np.zeros((0, 3)), np.zeros(0), np.zeros(0))

    def __len__(self) -> int:
        """Columns of the clearances: every obstacle and the floor."""
        return len(self.kinds)

    @property
    def spheres_only(self) -> bool:
        """Whether every obstacle is a sphere and there is no floor (the clearances of old)."""
        return len(self.boxes) == 0 and len(self.rods) == 0 and len(self.cylinders) == 0 and self.floor is None

    def name(self, column: int) -> str | None:
        """The scene's name of the obstacle of clearance column ``column`` (None: unnamed, or the floor).

        >>> Obstacles(np.zeros((2, 3)), np.ones(2), np.ones(2), names=("can1", None)).name(0)
        'can1'
        """
        return self.names[column] if column < len(self.names) else None

    def columns(self, kind: int) -> np.ndarray:
        """Indices of the clearances' columns of one kind, in the order of that kind's arrays.

        >>> Obstacles(np.zeros((1, 3)), np.ones(1), np.ones(2), floor=0.0).columns(FLOOR).tolist()
        [1]
        """
        return self._columns[kind]


def _derived_solids(boxes: Boxes, rods: Rods, columns: dict[int, np.ndarray]) -> dict[str, Any]:
    """:class:`Obstacles`' derived fields (``solids`` ... ``scene_order``, see its docstring) from
    its boxes, capsules and each kind's columns."""
    axes = rods.axes()
    solid_columns = np.concatenate([columns[BOX], columns[ROD]])
    order = np.argsort(solid_columns, kind="stable")  # the solids in the scene's order
    solids = Boxes(
        *(np.concatenate([getattr(boxes, f), getattr(axes, f)])[order] for f in ("centers", "half", "rotations"))
    )
    canonical = np.concatenate([columns[SPHERE], solid_columns[order], columns[CYLINDER], columns[FLOOR]])
    in_order = bool(np.all(canonical == np.arange(len(canonical))))
    return {
        "solids": solids,
        "solid_radius": np.concatenate([np.zeros(len(boxes)), rods.radius])[order],
        "solid_columns": solid_columns[order],
        "solid_axes": np.ascontiguousarray(solids.rotations.transpose(0, 2, 1).reshape(-1, 3)),
        "solid_origins": np.einsum("kba,kb->ka", solids.rotations, solids.centers)[:, :, None],
        "solid_half": solids.half[:, :, None],
        "scene_order": None if in_order else np.argsort(canonical),
    }
