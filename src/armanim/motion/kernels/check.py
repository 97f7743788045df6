"""The exact checks of a compiled step: the arm's own pairs' gaps (:func:`pair_gaps`), the
capsules' and the tip's clearances to every obstacle (:func:`obstacle_clearances`), and whether a
new pose keeps every guarantee (:func:`pose_exactly_safe`).

The numpy references: :func:`armanim.world.selfdistances.self_gaps`,
:func:`armanim.world.distances.clearances`, :func:`armanim.motion.filter.barrier.exactly_safe`.
Pure core: numpy and numba only.
"""

from __future__ import annotations

import math

import numpy as np

from armanim.arm.kernel import JIT, _capsule_ends_one, _forward_one, compiled
from armanim.motion.kernels.layout import BUFFER, CLEARANCE, SELF_CLEARANCE, KernelProblem, Measures, World
from armanim.world.compiled import (
    _points_apart,
    _segments_apart,
    capsule_pair_gaps,
    kind_count,
    segment_box_grid,
    segment_box_pairs_of_segments,
    segment_cylinder_grid,
)


@compiled(**JIT)
def pair_gaps(
    points: np.ndarray,
    frames: np.ndarray,
    caps: np.ndarray,
    caps_link: np.ndarray,
    first: np.ndarray,
    second: np.ndarray,
    ends: np.ndarray,
    gaps: np.ndarray,
    near: np.ndarray,
) -> float:
    """Every enabled pair's gap (distance less both radii) into ``gaps`` (P,), the capsules' world
    ends into ``ends`` (2, c, 3), each pair's closest points' fractions and normal into ``near``
    (P, 5): t, s, n (:func:`armanim.world.selfdistances.self_gaps`); returns the least gap."""
    _capsule_ends_one(
        points, frames, caps_link, caps[:, 0:3], caps[:, 3:6], caps[:, 7] > 0.5, ends[0], ends[1]
    )  # column 7: joint-to-joint
    p = first.shape[0]
    t = np.empty(p)
    s = np.empty(p)
    dist = np.empty(p)
    normal = np.empty((p, 3))
    a, b = ends[0], ends[1]
    rest = False
    for q in range(p):  # :func:`armanim.world.compiled.segment_segment_pairs`, its spheres' pairs in closed form here
        t[q], s[q], dist[q] = _segments_apart(a, b, first[q], second[q], normal, q)
        if dist[q] < 0.0:
            t[q], s[q], dist[q] = _points_apart(a, b, first[q], second[q], normal, q)
            rest = rest or dist[q] < 0.0
    if rest:  # parallel or touching: the shared box form
        segment_box_pairs_of_segments(a, b, first, second, t, s, dist, normal)
    least = np.inf
    for q in range(p):
        gaps[q] = dist[q] - (caps[first[q], 6] + caps[second[q], 6])
        least = min(least, gaps[q])
        near[q, 0] = t[q]
        near[q, 1] = s[q]
        for x in range(3):
            near[q, 2 + x] = normal[q, x]
    return least


@compiled(**JIT)
def sphere_clearances(
    points: np.ndarray,
    a: np.ndarray,
    b: np.ndarray,
    part_radius: np.ndarray,
    centers: np.ndarray,
    radii: np.ndarray,
    d: np.ndarray,
    t: np.ndarray,
    normal: np.ndarray,
) -> None:
    """Clearances of the capsules (segments a-b) and the tip to the spheres into d, t (c+1, s)
    and normal (c+1, s, 3) (:func:`armanim.world.distances.sphere_clearances`)."""
    c = a.shape[0]
    n = points.shape[0] - 1
    pa = np.empty(3)
    pb = np.empty(3)
    for part in range(c + 1):
        for i in range(3):
            if part < c:
                pa[i] = a[part, i]
                pb[i] = b[part, i]
            else:
                pa[i] = points[n, i]
                pb[i] = points[n, i]
        ab0, ab1, ab2 = pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]
        denom = ab0 * ab0 + ab1 * ab1 + ab2 * ab2
        for k in range(centers.shape[0]):
            if part == c:
                f = 1.0
            elif denom > 0.0:
                f = (
                    (centers[k, 0] - pa[0]) * ab0 + (centers[k, 1] - pa[1]) * ab1 + (centers[k, 2] - pa[2]) * ab2
                ) / denom
                f = min(max(f, 0.0), 1.0)
            else:
                f = 0.0
            o0 = pa[0] + f * ab0 - centers[k, 0]
            o1 = pa[1] + f * ab1 - centers[k, 1]
            o2 = pa[2] + f * ab2 - centers[k, 2]
            dist = math.sqrt(o0 * o0 + o1 * o1 + o2 * o2)
            scale = dist if dist > 0.0 else 1.0
            normal[part, k, 0] = o0 / scale
            normal[part, k, 1] = o1 / scale
            normal[part, k, 2] = o2 / scale
            t[part, k] = f
            d[part, k] = dist - radii[k] - part_radius[part]


@compiled(**JIT)
def obstacle_clearances(
    points: np.ndarray,
    a: np.ndarray,
    b: np.ndarray,
    part_radius: np.ndarray,
    world: World,
    d: np.ndarray,
    t: np.ndarray,
    normal: np.ndarray,
) -> None:
    """Clearances of the capsules (segments a-b) and the tip to every obstacle into d, t (c+1, m)
    and normal (c+1, m, 3): the spheres', the solids' (:func:`armanim.world.compiled.segment_box_grid`,
    the tip a segment of no length), the cylinders' (:func:`armanim.world.compiled.segment_cylinder_grid`)
    and the floor's, in the scene's order, +inf where a part may touch the obstacle
    (:func:`armanim.world.distances.clearances`).
    ``world``: :func:`~armanim.motion.kernels.layout.world_arrays`'s arrays (None for a kind the
    scene has none of: its closed form is not compiled)."""
    (
        centers,
        radii,
        solid_centers,
        solid_half,
        solid_rotations,
        solid_radius,
        on_base,
        order,
        floor,
        cyl_centers,
        cyl_rotations,
        cyl_half,
        cyl_radius,
        allowed,
    ) = world
    c = a.shape[0]
    n = points.shape[0] - 1
    count, solids, cylinders = centers.shape[0], kind_count(solid_radius), kind_count(cyl_radius)
    m = d.shape[1]
    pts = np.empty((c + 1, 3))
    ends = np.empty((c + 1, 3))
    for part in range(c + 1):
        for i in range(3):
            pts[part, i] = a[part, i] if part < c else points[n, i]
            ends[part, i] = b[part, i] if part < c else points[n, i]
    kd = np.empty((c + 1, m))
    kt = np.empty((c + 1, m))
    kn = np.empty((c + 1, m, 3))
    if count:
        sphere_clearances(points, a, b, part_radius, centers, radii, kd[:, :count], kt[:, :count], kn[:, :count])
    parts, columns = (pts, ends, part_radius), (kd, kt, kn)
    _kind_columns(parts, solid_centers, solid_rotations, solid_half, None, solid_radius, count, columns)
    _kind_columns(parts, cyl_centers, cyl_rotations, None, cyl_half, cyl_radius, count + solids, columns)
    if floor.shape[0]:
        f = count + solids + cylinders
        for part in range(c + 1):
            height = min(pts[part, 2], ends[part, 2]) - floor[0] - part_radius[part]
            kd[part, f] = np.inf if on_base[part] else height
            kt[part, f] = 1.0 if (part == c or ends[part, 2] <= pts[part, 2]) else 0.0
            kn[part, f, 0] = 0.0
            kn[part, f, 1] = 0.0
            kn[part, f, 2] = 1.0
    for part in range(c + 1):
        if allowed[part] >= 0:  # the obstacle this part may touch (a carried object's support)
            kd[part, allowed[part]] = np.inf
    for part in range(c + 1):
        for k in range(m):
            j = order[k]
            d[part, k] = kd[part, j]
            t[part, k] = kt[part, j]
            for i in range(3):
                normal[part, k, i] = kn[part, j, i]


@compiled(**JIT)
def _kind_columns(
    parts: tuple[np.ndarray, np.ndarray, np.ndarray],
    centers: np.ndarray | None,
    rotations: np.ndarray | None,
    box_half: np.ndarray | None,
    cylinder_half: np.ndarray | None,
    radius: np.ndarray | None,
    first: int,
    columns: tuple[np.ndarray, np.ndarray, np.ndarray],
) -> None:
    """One kind's columns, the solids' or the cylinders', ``first`` on of
    :func:`obstacle_clearances`' kd, kt (c+1, m) and kn (c+1, m, 3), the tip (the last part) a
    segment of no length.

    The kind is told by which half sizes are given, the other None: numba leaves a closed form
    out of the machine code only on an argument that is None, and one body typed with both
    kinds' arrays would not compile (a solid's half sizes are (k, 3), a cylinder's (k,)).

    Parameters
    ----------
    parts : tuple of arrays
        The parts' segments' ends (c+1, 3) each and radii (c+1,), metres.
    centers, rotations, radius : arrays or None
        The kind's obstacles' centres (k, 3), rotations (k, 3, 3) and radii (k,) (metres: a
        solid's rounding; a cylinder's distance is to its surface): None where the scene has
        none of the kind, and then nothing is written.
    box_half, cylinder_half : array or None
        The solids' half sizes (k, 3) with ``cylinder_half`` None (the boxes' closed form,
        :func:`armanim.world.compiled.segment_box_grid`), or the cylinders' half lengths (k,)
        with ``box_half`` None (:func:`armanim.world.compiled.segment_cylinder_grid`).
    first : int
        The kind's first column.
    columns : tuple of arrays
        kd, kt and kn, filled in the kind's columns: clearances (metres), the segments'
        parameters, the normals.
    """
    if centers is None or rotations is None or radius is None:
        return
    if box_half is None and cylinder_half is None:
        return
    pts, ends, part_radius = parts
    kd, kt, kn = columns
    count = radius.shape[0]
    if not count:
        return
    d = np.empty((pts.shape[0], count))
    t = np.empty((pts.shape[0], count))
    normal = np.empty((pts.shape[0], count, 3))
    if box_half is not None:
        segment_box_grid(pts, ends, centers, box_half, rotations, t, d, normal)
        _put_columns(d, t, normal, radius, part_radius, first, kd, kt, kn)
    if cylinder_half is not None:
        segment_cylinder_grid(pts, ends, centers, rotations, cylinder_half, radius, t, d, normal)
        _put_columns(d, t, normal, np.zeros(count), part_radius, first, kd, kt, kn)


@compiled(**JIT)
def _put_columns(
    d: np.ndarray,
    t: np.ndarray,
    n: np.ndarray,
    radius: np.ndarray,
    part_radius: np.ndarray,
    first: int,
    kd: np.ndarray,
    kt: np.ndarray,
    kn: np.ndarray,
) -> None:
    """One kind's distances ``d`` (c+1, k), less its ``radius`` (k,) and each part's, with their
    ``t`` and normals ``n``, into the columns ``first`` on of kd, kt and kn (the tip's t is 1)."""
    parts = d.shape[0]
    for part in range(parts):
        for k in range(d.shape[1]):
            kd[part, first + k] = d[part, k] - radius[k] - part_radius[part]
            kt[part, first + k] = 1.0 if part == parts - 1 else t[part, k]
            for i in range(3):
                kn[part, first + k, i] = n[part, k, i]


@compiled(**JIT)
def pose_exactly_safe(
    k: KernelProblem,
    phi: np.ndarray,
    cand: np.ndarray,
    cl_d: np.ndarray,
    least: float,
    new: Measures,
    out: np.ndarray,
) -> bool:
    """Whether the pose ``cand`` keeps every guarantee from the pose ``phi``
    (:func:`~armanim.motion.filter.barrier.exactly_safe`).

    Parameters
    ----------
    k : KernelProblem
        The problem's constants.
    phi, cand : (n,) arrays
        The pose now and the new one, radians (metres for a prismatic joint).
    cl_d : (parts, m) array
        The clearances now, metres.
    least : float
        The least gap now, metres.
    new : Measures
        Filled with
        the new pose's kinematics, clearances and gaps (as far as the check went).
    out : (3,) array
        ``out[1]``: the new least gap, metres (inf without pairs).

    Returns
    -------
    bool
        Whether every joint stays inside its limits as the filter demands, and neither the
        clearances nor the gaps fall below their floors (or below what they are now).
    """
    rows, root, floats, lower, upper, caps, link = k.rows, k.root, k.floats, k.lower, k.upper, k.caps, k.link
    part_radius, world, first, second, pair_radii = k.part_radius, k.world, k.first, k.second, k.pair_radii
    points, frames, axes, tool, d, t, normal, gap, gap_t, gap_s, gap_normal = new  # Measures' order
    n = phi.shape[0]
    buffer = floats[BUFFER]
    for j in range(n):
        if not (cand[j] - cand[j] == 0.0):  # NaN or infinity
            return False
        gap_new = min(cand[j] - lower[j], upper[j] - cand[j])
        gap_now = min(phi[j] - lower[j], upper[j] - phi[j])
        if gap_new <= 0.0 or gap_new < min(buffer, gap_now):
            return False
    _forward_one(rows, root, cand, points, frames, axes, tool)
    c = caps.shape[0]
    na = np.empty((c, 3))
    nb = np.empty((c, 3))
    _capsule_ends_one(points, frames, link, caps[:, 0:3], caps[:, 3:6], caps[:, 7] > 0.5, na, nb)
    parts = cl_d.shape[0]
    if cl_d.shape[1] > 0:
        obstacle_clearances(points, na, nb, part_radius, world, d, t, normal)
        now_links, now_tip, new_links, new_tip = np.inf, np.inf, np.inf, np.inf
        for part in range(parts):
            for col in range(cl_d.shape[1]):
                if part < parts - 1:
                    now_links = min(now_links, cl_d[part, col])
                    new_links = min(new_links, d[part, col])
                else:
                    now_tip = min(now_tip, cl_d[part, col])
                    new_tip = min(new_tip, d[part, col])
        if not new_links >= min(floats[CLEARANCE], now_links):
            return False
        if not new_tip >= min(floats[CLEARANCE], now_tip):
            return False
    out[1] = np.inf
    if first.shape[0]:
        out[1] = capsule_pair_gaps(na, nb, first, second, pair_radii, gap_t, gap_s, gap, gap_normal)
        if not out[1] >= min(floats[SELF_CLEARANCE], least):
            return False
    return True
