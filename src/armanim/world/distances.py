"""Exact distances from the arm's parts to the obstacles' surfaces.

The parts are the arm's collision capsules (:mod:`armanim.arm.capsules`; today's arms: one
per link of radius ``width / 2``) and the tip as a point. For each part and obstacle
(sphere, box, capsule, cylinder, or the floor): the clearance, the least signed distance of the
part's segment to the solid less the part's radius (negative inside), where on the
segment that least point lies, and the unit normal there (the gradient of the solid's
signed distance, out of the solid) that the safety filter's constraints and the cost's
gradient need; closed forms in :mod:`armanim.world.closest`. One pose or a
batch of poses. Pure core: numpy only, no I/O.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import cast

import numpy as np

from armanim.arm.capsules import Capsules, capsule_ends
from armanim.arm.geometry import closest_on_segment
from armanim.arm.kinematics import Pose
from armanim.world.closest import (
    excess_beyond,
    segment_box_grid,
    segment_box_pairs,
    segment_cylinder_grid,
    segment_cylinder_pairs,
)
from armanim.world.obstacles import CYLINDER, FLOOR, SPHERE, Cylinders, Obstacles


@dataclass(frozen=True)
class Clearances:
    """Clearance of every arm part to every obstacle, for one pose or a batch.

    Parts are the c capsules (indices 0..c-1) and the tip as a point (index c).

    Attributes
    ----------
    d : (..., c+1, m) array
        Clearance to each obstacle's surface (negative inside).
    t : (..., c+1, m) array
        Fraction along the part's segment of its point closest to the obstacle.
    normal : (..., c+1, m, 3) array
        Unit vector out of the obstacle at that closest point (for a sphere: from its centre).
    """

    d: np.ndarray
    t: np.ndarray
    normal: np.ndarray

    @property
    def links(self) -> np.ndarray:
        """(..., c, m): clearances of the capsules only (the arm's solid parts)."""
        return self.d[..., :-1, :]

    @property
    def tip(self) -> int:
        """Index of the tip among the parts (after the capsules)."""
        return cast(int, self.d.shape[-2] - 1)


def clearances(pose: Pose, obstacles: Obstacles, capsules: Capsules) -> Clearances:
    """Clearances of the capsules and of the tip to every obstacle (and the floor).

    Parameters
    ----------
    pose : Pose
        One pose or a batch (points of shape (..., n+1, 3)).
    obstacles : Obstacles
    capsules : Capsules
        The arm's collision capsules.

    Returns
    -------
    Clearances
        One column per obstacle in the order of ``obstacles.kinds``. The floor's column is
        +inf for the capsules the first joint carries (they stand on the base), and a capsule's
        column of the obstacle it may touch (:attr:`~armanim.arm.capsules.Capsules.allowed`) +inf.
    """
    a, b = capsule_ends(capsules, pose)
    tip = pose.points[..., -1:, :]
    pts = np.concatenate([a, tip], axis=-2)
    ends = np.concatenate([b, tip], axis=-2)  # the tip: a zero-length segment
    radius = capsules.part_radius  # the tip is a point: 0
    if obstacles.spheres_only:
        return allowed_apart(sphere_clearances(pts, ends, radius, obstacles), capsules)
    kinds = []  # (d, t, normal) of the spheres, the solids, the cylinders, the floor: the columns in that order
    if len(obstacles.radii):
        kinds.append(astuple(sphere_clearances(pts, ends, radius, obstacles)))
    if len(obstacles.solid_radius):
        kinds.append(solid_clearances(pts, ends, radius, obstacles))
    if len(obstacles.cylinders):
        kinds.append(cylinder_clearances(pts, ends, radius, obstacles.cylinders))
    if obstacles.floor is not None:
        kinds.append(floor_clearances(pts, ends, radius, obstacles.floor, capsules.on_base))
    d, t, normal = (
        kinds[0] if len(kinds) == 1 else (np.concatenate(c, axis=axis) for c, axis in zip(zip(*kinds), (-1, -1, -2)))
    )
    order = obstacles.scene_order
    if order is not None:
        # C order, as the spheres-only path and the kernels give them (numpy lays a last-axis take out
        # in Fortran order, and each kernel would be compiled for that order too)
        d, t, normal = (np.ascontiguousarray(x) for x in (d[..., order], t[..., order], normal[..., order, :]))
    return allowed_apart(Clearances(d=d, t=t, normal=normal), capsules)


def allowed_apart(cl: Clearances, capsules: Capsules) -> Clearances:
    """``cl`` with +inf in each part's column of the obstacle it may touch
    (:attr:`~armanim.arm.capsules.Capsules.part_allowed`); ``cl`` itself where none may."""
    if not capsules.allows:
        return cl
    parts = np.nonzero(capsules.part_allowed >= 0)[0]
    d = np.array(cl.d)
    d[..., parts, capsules.part_allowed[parts]] = np.inf
    return Clearances(d=d, t=cl.t, normal=cl.normal)


def astuple(cl: Clearances) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(d, t, normal) of clearances."""
    return cl.d, cl.t, cl.normal


def sphere_clearances(
    pts: np.ndarray, ends: np.ndarray, radius: np.ndarray, obstacles: Obstacles, tip: bool = True
) -> Clearances:
    """Clearances of the parts (segments pts-ends, (..., p, 3), of radius (p,), the last the tip
    unless ``tip`` is False) to the spheres, (..., p, s)."""
    ab = (ends - pts)[..., None, :]  # (..., c+1, 1, 3)
    t = closest_on_segment(pts[..., :, None, :], ends[..., :, None, :], obstacles.centers)  # (..., c+1, m)
    if tip:
        t[..., -1, :] = 1.0  # the tip sits at the end of its zero-length segment
    dist, normal = length_and_direction(pts[..., :, None, :] + t[..., None] * ab - obstacles.centers)
    return Clearances(d=dist - obstacles.radii - radius[:, None], t=t, normal=normal)


def length_and_direction(offset: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """|offset| (...) and the unit vector offset / |offset| (..., 3), 0 where the offset is 0:
    the distance between two closest points and the normal from the solid's to the part's."""
    dist = np.sqrt((offset * offset).sum(axis=-1))
    return dist, offset / np.where(dist > 0, dist, 1.0)[..., None]


def solid_clearances(
    pts: np.ndarray, ends: np.ndarray, radius: np.ndarray, obstacles: Obstacles
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(d, t, normal) of the parts to the solids (the boxes and capsule obstacles, in the scene's order), (..., p, k):
    the least signed distance of each part's segment to each solid's box (a capsule's: its
    axis, :meth:`~armanim.world.obstacles.Rods.axes`) less both radii
    (:func:`~armanim.world.closest.segment_box`), the normal out of the solid."""
    solids = obstacles.solids
    t, dist, normal = segment_box_grid(pts, ends, solids.centers, solids.half, solids.rotations)
    t[..., -1, :] = 1.0
    return dist - obstacles.solid_radius - radius[:, None], t, normal


def solid_pairs(
    pts: np.ndarray, ends: np.ndarray, radius: np.ndarray, obstacles: Obstacles, where: tuple[np.ndarray, ...]
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(d, t, normal) of the part-solid pairs at the indices ``where`` of (..., p, k) only, each (K,)
    or (K, 3): the same numbers as :func:`solid_clearances` at those places (bit for bit)."""
    *pose, part, solid = where
    segment = np.ravel_multi_index(tuple(pose) + (part,), pts.shape[:-1])
    solids = obstacles.solids
    t, dist, normal = segment_box_pairs(
        pts.reshape(-1, 3), ends.reshape(-1, 3), solids.centers, solids.half, solids.rotations, segment, solid
    )
    return dist - obstacles.solid_radius[solid] - radius[part], t, normal


def cylinder_clearances(
    pts: np.ndarray, ends: np.ndarray, radius: np.ndarray, cylinders: Cylinders, tip: bool = True
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(d, t, normal) of the parts (segments pts-ends, (..., p, 3), of radius (p,), the last the
    tip unless ``tip`` is False) to the solid cylinders, (..., p, k): the least signed distance
    of each segment to each cylinder less the part's radius, the normal out of the cylinder
    (compiled: :func:`~armanim.world.closest.segment_cylinder_grid`)."""
    t, dist, normal = segment_cylinder_grid(
        pts, ends, cylinders.centers, cylinders.rotations, cylinders.half_length, cylinders.radius
    )
    if tip:
        t[..., -1, :] = 1.0
    return dist - radius[:, None], t, normal


def cylinder_signed_distance(p: np.ndarray, half_length: np.ndarray, radius: np.ndarray) -> np.ndarray:
    """Signed distance (...) of points ``p`` (cylinder frame, (..., 3)) to the solid cylinder
    x^2 + y^2 <= radius^2, |z| <= half_length (negative inside: minus the depth to the nearest
    surface). Closed form.

    >>> cylinder_signed_distance(np.array([[2.0, 0, 2], [0, 0, 0.5]]), np.ones(1), np.ones(1)).tolist()
    [1.4142135623730951, -0.5]
    """
    dr = np.sqrt(p[..., 0] * p[..., 0] + p[..., 1] * p[..., 1]) - radius
    dz = np.abs(p[..., 2]) - half_length
    outside = np.sqrt(np.maximum(dr, 0.0) ** 2 + np.maximum(dz, 0.0) ** 2)
    return cast(np.ndarray, np.where((dr > 0) | (dz > 0), outside, np.maximum(dr, dz)))


def segment_cylinder(
    a: np.ndarray, b: np.ndarray, center: np.ndarray, rotation: np.ndarray, half_length: np.ndarray, radius: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Least signed distance of segments a-b to solid cylinders, in numpy: (t, distance, normal),
    shapes (N,), (N,), (N, 3); the reference the compiled form
    (:func:`armanim.world.compiled.segment_cylinder_grid`) is held to.

    The signed distance f(t) of a + t (b - a) to the cylinder (:func:`cylinder_signed_distance`,
    axis the local z) is convex. Exact in closed form where the least point lies beside the side
    (the closest approach to the axis), beside a cap (an end, or where the segment crosses the
    side or a cap's plane) or inside (where the depths below the side and below a cap are
    equal, a quadratic in t; the closest approach to the axis; z = 0; an end): those fractions
    are the candidates. Beyond the rim (beside both the side and a cap: the distance to a
    circle along a line has no closed form) the root of the convex distance's slope is
    bisected on the pieces beside the best candidate, to the spacing of floats in t (the
    distance then to rounding: it is flat there). Ties: the fraction nearest b. The normal is
    f's gradient at the least point (out of the cylinder; inside, the nearest surface's).

    Parameters
    ----------
    a, b : (N, 3) arrays
        The segments' ends, world (a point: a == b).
    center : (N, 3) array
        The middles of the cylinders' axes, world.
    rotation : (N, 3, 3) array
        World-from-cylinder rotations.
    half_length, radius : (N,) arrays
        Half the height along the axis and the radius (> 0).

    >>> t, d, n = segment_cylinder(np.array([[-3.0, 0, 2]]), np.array([[3.0, 0, 2]]), np.zeros((1, 3)), np.eye(3)[None],
    ...                            np.ones(1), np.ones(1))
    >>> float(t[0]), float(d[0]), n[0].tolist()
    (0.6666666666666666, 1.0, [0.0, 0.0, 1.0])
    """
    a, b, center = (np.asarray(v, dtype=float).reshape(-1, 3) for v in (a, b, center))
    rotation = np.asarray(rotation, dtype=float).reshape(-1, 3, 3)
    h, r = np.asarray(half_length, dtype=float).reshape(-1), np.asarray(radius, dtype=float).reshape(-1)
    x = np.einsum("nji,nj->ni", rotation, a - center)  # R^T (a - c)
    u = np.einsum("nji,nj->ni", rotation, b - a)
    uu = u[:, 0] ** 2 + u[:, 1] ** 2
    pu = x[:, 0] * u[:, 0] + x[:, 1] * u[:, 1]
    pp = x[:, 0] ** 2 + x[:, 1] ** 2
    with np.errstate(divide="ignore", invalid="ignore"):
        candidates = [np.ones(len(a)), np.zeros(len(a)), np.where(uu > 0, -pu / uu, np.nan)]
        candidates += [np.where(u[:, 2] != 0, (level - x[:, 2]) / u[:, 2], np.nan) for level in (h, -h, 0.0)]
        candidates += _quadratic_roots(uu, 2 * pu, pp - r * r)
        for side in (1.0, -1.0):
            w = r - h + side * x[:, 2]
            candidates += _quadratic_roots(uu - u[:, 2] ** 2, 2 * (pu - side * u[:, 2] * w), pp - w * w)
    ts = np.clip(np.stack(candidates, axis=1), 0.0, 1.0)  # (N, C), NaN: no such candidate
    depth = cylinder_signed_distance(x[:, None] + ts[..., None] * u[:, None], h[:, None], r[:, None])
    depth = np.where(np.isnan(ts), np.inf, depth)
    best = depth.min(axis=1)
    t = np.where(depth == best[:, None], ts, -1.0).max(axis=1)  # ties: nearest b
    left = np.where(ts < t[:, None], ts, 0.0).max(axis=1, initial=0.0)
    right = np.where(ts > t[:, None], ts, 1.0).min(axis=1, initial=1.0)
    for lo, hi in ((left, t), (t, right)):
        mid = x + (0.5 * (lo + hi))[:, None] * u
        rim = (best > 0) & (hi > lo) & (mid[:, 0] ** 2 + mid[:, 1] ** 2 > r * r) & (np.abs(mid[:, 2]) > h)
        if np.any(rim):
            found = _bisected_rim(
                lo[rim], hi[rim], x[rim], u[rim], h[rim], r[rim], np.where(mid[rim, 2] > 0, 1.0, -1.0)
            )
            d = cylinder_signed_distance(x[rim] + found[:, None] * u[rim], h[rim], r[rim])
            better = d < best[rim]
            idx = np.flatnonzero(rim)[better]
            best[idx], t[idx] = d[better], found[better]
    return t, best, np.einsum("nij,nj->ni", rotation, _cylinder_normal(x + t[:, None] * u, h, r))


def _quadratic_roots(qa: np.ndarray, qb: np.ndarray, qc: np.ndarray) -> list[np.ndarray]:
    """The vertex and the real roots of qa t^2 + qb t + qc (a linear root where qa = 0), NaN where none."""
    root = np.sqrt(qb * qb - 4 * qa * qc)  # NaN where no real root
    q = -0.5 * (qb + np.where(qb >= 0, root, -root))
    linear = qa == 0
    return [
        np.where(linear, -qc / qb, -qb / (2 * qa)),
        np.where(linear, np.nan, q / qa),
        np.where(linear | (q == 0), np.nan, qc / q),
    ]


def _bisected_rim(
    lo: np.ndarray, hi: np.ndarray, x: np.ndarray, u: np.ndarray, h: np.ndarray, r: np.ndarray, side: np.ndarray
) -> np.ndarray:
    """The t in [lo, hi] (K,) nearest the rim at z = side h, for segments x + t u (cylinder frame)
    beyond the side and that cap there: the slope of the squared distance bisected."""

    def slope(t: np.ndarray) -> np.ndarray:
        p = x + t[:, None] * u
        rho = np.sqrt(p[:, 0] ** 2 + p[:, 1] ** 2)
        rate: np.ndarray = (rho - r) * (p[:, 0] * u[:, 0] + p[:, 1] * u[:, 1]) / rho + (side * p[:, 2] - h) * side * u[
            :, 2
        ]
        return rate

    start, end = lo, hi
    at_start, at_end = slope(start) >= 0, slope(end) <= 0
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        rising = slope(mid) > 0
        hi, lo = np.where(rising, mid, hi), np.where(rising, lo, mid)
    return np.where(at_start, start, np.where(at_end, end, 0.5 * (lo + hi)))


def _cylinder_normal(p: np.ndarray, h: np.ndarray, r: np.ndarray) -> np.ndarray:
    """The gradient (N, 3) of the cylinder's signed distance at points ``p`` (cylinder frame):
    outside from the nearest surface point; inside the nearest surface's normal (the side's
    where as near, the radial x axis on the axis itself)."""
    rho = np.sqrt(p[:, 0] ** 2 + p[:, 1] ** 2)
    radial = np.where((rho > 0)[:, None], p[:, :2] / np.where(rho > 0, rho, 1.0)[:, None], [1.0, 0.0])
    up = np.where(p[:, 2] >= 0, 1.0, -1.0)
    dr, dz = rho - r, np.abs(p[:, 2]) - h
    ra, za = np.maximum(dr, 0.0), np.maximum(dz, 0.0)
    length = np.sqrt(ra * ra + za * za)
    outside = (dr > 0) | (dz > 0)
    scale = np.where(outside, length, 1.0)
    out = np.column_stack([ra[:, None] * radial / scale[:, None], za * up / scale])
    side = np.column_stack([radial, np.zeros(len(p))])
    cap = np.column_stack([np.zeros((len(p), 2)), up])
    return np.where(outside[:, None], out, np.where((dr > dz)[:, None], side, cap))


def floor_clearances(
    pts: np.ndarray, ends: np.ndarray, radius: np.ndarray, floor: float, exempt: np.ndarray, tip: bool = True
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(d, t, normal) of the parts to the plane z = ``floor``, (..., p, 1): the lower end's
    height above it less the radius; +inf for the ``exempt`` parts ((p,) bool); the last part
    is the tip unless ``tip`` is False."""
    lower_end = ends[..., 2] <= pts[..., 2]  # a level part: its far end, the one its joint moves most
    height = np.minimum(pts[..., 2], ends[..., 2]) - floor - radius
    d = np.where(exempt, np.inf, height)[..., None]
    t = np.where(lower_end, 1.0, 0.0)
    if tip:
        t[..., -1] = 1.0
    normal = np.zeros(d.shape + (3,))
    normal[..., 2] = 1.0
    return d, t[..., None], normal


def point_clearances(points: np.ndarray, obstacles: Obstacles) -> np.ndarray:
    """(k, m) signed distance of each of the (k, 3) points to every obstacle's surface (the
    floor: the height above it), negative inside: how far a goal lies from each solid.

    >>> obs = Obstacles(np.zeros((1, 3)), np.ones(1), np.ones(2), floor=-2.0)
    >>> point_clearances(np.array([[3.0, 0, 0]]), obs).tolist()
    [[2.0, 2.0]]
    """
    points = np.asarray(points, dtype=float).reshape(-1, 3)
    d = np.empty((len(points), len(obstacles)))
    spheres = obstacles.columns(SPHERE)
    if len(spheres):
        d[:, spheres] = np.linalg.norm(points[:, None, :] - obstacles.centers, axis=-1) - obstacles.radii
    if len(obstacles.solid_radius):
        solids = obstacles.solids
        dist = segment_box_grid(points, points, solids.centers, solids.half, solids.rotations)[1]
        d[:, obstacles.solid_columns] = dist - obstacles.solid_radius
    if len(obstacles.cylinders):
        cyl = obstacles.cylinders
        local = np.einsum("kji,pkj->pki", cyl.rotations, points[:, None, :] - cyl.centers)
        d[:, obstacles.columns(CYLINDER)] = cylinder_signed_distance(local, cyl.half_length, cyl.radius)
    if obstacles.floor is not None:
        d[:, obstacles.columns(FLOOR)] = points[:, 2:] - obstacles.floor
    return d


def min_link_clearance(pose: Pose, obstacles: Obstacles, capsules: Capsules) -> np.ndarray:
    """Smallest clearance of any capsule to any obstacle, shape (...); +inf if none.

    The same number as the least of :func:`clearances`' links, found with less work among
    boxes, capsules and cylinders (the planner asks it of thousands of poses): each box's,
    capsule obstacle's and cylinder's exact clearance is computed only where a cheap lower bound
    (:func:`solid_bounds`, :func:`cylinder_bounds`) is below a pose's best upper bound (the same
    functions', or an exact sphere's or the floor's clearance).
    """
    if len(obstacles) == 0:
        return np.full(pose.points.shape[:-2], np.inf)
    if pose.points.ndim == 3 and len(pose.points) > CLEARANCE_CHUNK:
        return np.concatenate(
            [
                min_link_clearance(
                    Pose(points=pose.points[i : i + CLEARANCE_CHUNK], frames=pose.frames[i : i + CLEARANCE_CHUNK]),
                    obstacles,
                    capsules,
                )
                for i in range(0, len(pose.points), CLEARANCE_CHUNK)
            ]
        )
    if obstacles.spheres_only or capsules.allows:  # a pair allowed to touch: every pair measured, that one left out
        least: np.ndarray = clearances(pose, obstacles, capsules).links.min(axis=(-1, -2))
        return least
    a, b = capsule_ends(capsules, pose)
    radius = capsules.radius
    best = np.full(a.shape[:-2], np.inf)
    if len(obstacles.radii):
        best = np.minimum(best, sphere_clearances(a, b, radius, obstacles, tip=False).d.min(axis=(-1, -2)))
    if obstacles.floor is not None:
        height = floor_clearances(a, b, radius, obstacles.floor, capsules.on_base[:-1], tip=False)[0]
        best = np.minimum(best, height.min(axis=(-1, -2)))
    if len(obstacles.cylinders):
        best = _least_cylinder_clearance(a, b, radius, obstacles.cylinders, best)
    if len(obstacles.solid_radius):
        low, high = solid_bounds(a, b, radius, obstacles)
        best = np.minimum(best, high.min(axis=(-1, -2)))
        doubt = low <= best[..., None, None]
        if np.any(doubt):
            where = np.nonzero(doubt)
            found = np.full(doubt.shape, np.inf)
            found[where] = solid_pairs(a, b, radius, obstacles, where)[0]
            best = np.minimum(best, found.min(axis=(-1, -2)))
    return best


CLEARANCE_CHUNK = 128
"""Poses :func:`min_link_clearance` takes at a time: its bounds' arrays for a batch of a clocked
run's frames (hundreds of poses, dozens of capsules, each solid) outgrow the caches, and a
UR5's 600 frames took 5x the time of the same frames 128 at a time. Each pose's number is the same
either way (every operation is pose by pose)."""

EXACT_CYLINDER_PAIRS = 4096
"""Capsule-cylinder pairs a batch may have for :func:`min_link_clearance` to measure every one
exactly (compiled, some 0.4 us a pair) rather than bound them first: the bounds' numpy calls cost
some 100 us whatever the batch (a planner's single pose)."""


def _least_cylinder_clearance(
    a: np.ndarray, b: np.ndarray, radius: np.ndarray, cylinders: Cylinders, best: np.ndarray
) -> np.ndarray:
    """``best`` (...) lowered to the least clearance of the capsules (segments a-b, (..., c, 3),
    radii (c,)) to the cylinders: every pair's exact clearance in a small batch
    (:data:`EXACT_CYLINDER_PAIRS`), else only where :func:`cylinder_bounds`' lower bound is not
    above a pose's best upper bound."""
    if a[..., 0].size * len(cylinders) <= EXACT_CYLINDER_PAIRS:
        return cast(
            np.ndarray, np.minimum(best, cylinder_clearances(a, b, radius, cylinders, tip=False)[0].min(axis=(-1, -2)))
        )
    low, high = cylinder_bounds(a, b, radius, cylinders)
    best = np.minimum(best, high.min(axis=(-1, -2)))
    doubt = low <= best[..., None, None]
    if np.any(doubt):
        *pose, part, cylinder = np.nonzero(doubt)
        segment = np.ravel_multi_index(tuple(pose) + (part,), a.shape[:-1])
        dist = segment_cylinder_pairs(
            a.reshape(-1, 3),
            b.reshape(-1, 3),
            cylinders.centers,
            cylinders.rotations,
            cylinders.half_length,
            cylinders.radius,
            segment,
            cylinder,
        )[1]
        found = np.full(doubt.shape, np.inf)
        found[np.nonzero(doubt)] = dist - radius[part]
        best = np.minimum(best, found.min(axis=(-1, -2)))
    return best


def cylinder_bounds(
    a: np.ndarray, b: np.ndarray, radius: np.ndarray, cylinders: Cylinders
) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper bounds (..., c, k) of the capsules' clearances to the cylinders: the
    cylinder lies inside the box of half edges (r, r, h) in its frame (its
    :func:`solid_bounds`-like gap to the segment's bounding box is a lower bound; overlapping,
    minus the deepest a point can be, min(r, h)) and holds the box of half edges
    (r / sqrt 2, r / sqrt 2, h) (the distance of the segment's ends and middle to it is an upper
    bound); both less the part's radius."""
    k = len(cylinders)
    axes = np.ascontiguousarray(cylinders.rotations.transpose(0, 2, 1).reshape(-1, 3))
    origins = np.einsum("kba,kb->ka", cylinders.rotations, cylinders.centers)[:, :, None]
    x0 = (axes @ a.reshape(-1, 3).T).reshape(k, 3, -1) - origins
    x1 = (axes @ b.reshape(-1, 3).T).reshape(k, 3, -1) - origins
    outer = np.column_stack([cylinders.radius, cylinders.radius, cylinders.half_length])[:, :, None]
    inner = np.column_stack([cylinders.radius / np.sqrt(2.0), cylinders.radius / np.sqrt(2.0), cylinders.half_length])[
        :, :, None
    ]
    gap = np.maximum(np.maximum(np.minimum(x0, x1) - outer, -outer - np.maximum(x0, x1)), 0.0)
    apart = _length(gap)
    grown = np.broadcast_to(radius, a.shape[:-1]).reshape(1, -1)
    low = np.where(apart > 0, apart, -np.minimum(cylinders.radius, cylinders.half_length)[:, None]) - grown
    high = np.minimum(np.minimum(_outside(x0, inner), _outside(x1, inner)), _outside(0.5 * (x0 + x1), inner)) - grown
    return tuple(np.moveaxis(v.reshape((k,) + a.shape[:-1]), 0, -1) for v in (low, high))


def solid_bounds(
    a: np.ndarray, b: np.ndarray, radius: np.ndarray, obstacles: Obstacles
) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper bounds (..., c, k) of the capsules' clearances to the solids: in each
    solid's box frame, the gap between the box and the segment's bounding box (the segment lies
    inside that; when they overlap, minus the box's inradius, the deepest a point can be
    inside), and the distance of the segment's ends and middle to the box; both less the radii.

    The ends go into every box frame by one matrix product (:attr:`Obstacles.solid_axes`),
    rotated before the centre is taken off: bounds, so rounding at 1e-15 of the coordinates
    does not matter (the callers allow 1e-9). Laid out solid, coordinate, then the segments
    (k, 3, M), each operation runs along all of a batch's segments."""
    solids = obstacles.solids
    k = len(solids.half)
    x0 = (obstacles.solid_axes @ a.reshape(-1, 3).T).reshape(k, 3, -1) - obstacles.solid_origins
    x1 = (obstacles.solid_axes @ b.reshape(-1, 3).T).reshape(k, 3, -1) - obstacles.solid_origins
    half = obstacles.solid_half
    gap = np.maximum(np.maximum(np.minimum(x0, x1) - half, -half - np.maximum(x0, x1)), 0.0)
    apart = _length(gap)
    grown = obstacles.solid_radius[:, None] + np.broadcast_to(radius, a.shape[:-1]).reshape(1, -1)
    low = (
        np.where(apart > 0, apart, -solids.half.min(axis=-1)[:, None]) - grown
    )  # overlapping: as deep as the box allows
    high = np.minimum(np.minimum(_outside(x0, half), _outside(x1, half)), _outside(0.5 * (x0 + x1), half)) - grown
    return tuple(np.moveaxis(v.reshape((k,) + a.shape[:-1]), 0, -1) for v in (low, high))


def _length(v: np.ndarray) -> np.ndarray:
    """Length (k, M) of vectors laid out (k, 3, M)."""
    squares = v * v
    return cast(np.ndarray, np.sqrt(squares[:, 0] + squares[:, 1] + squares[:, 2]))


def _outside(p: np.ndarray, half: np.ndarray) -> np.ndarray:
    """Distance (k, M) of points ``p`` (each solid's frame, (k, 3, M)) to the box (0 inside)."""
    return _length(excess_beyond(p, -half, half))
