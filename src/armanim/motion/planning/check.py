"""The planner's collision checks, compiled (numba): poses' margins and a motion's certificate.

RRT-Connect asks thousands of poses and motions whether they are free. In numpy each pose costs
some 400 microseconds of calls (:func:`~armanim.motion.filter.clearance.split_clearances`); here
one pose is its kinematics (:mod:`armanim.arm.kernel`), its capsules' clearances to every obstacle
and the floor (:func:`armanim.motion.kernels.check.obstacle_clearances`, in the scene's order)
and its enabled pairs' gaps (:func:`armanim.world.compiled.capsule_pair_gaps`) in one call, and a
whole motion check (:func:`armanim.motion.planning.path.motion_is_free`: the coarse samples, then
the halving, level by level) is one call too. The motion check bounds each group of capsules by its
own lever arms (:func:`~armanim.arm.capsules.capsule_lever_rows`) where numpy's takes the arm's
farthest point for all: the same answers, fewer poses measured.

The margins are the numpy path's to rounding (other summation orders); the numpy functions stay
the reference, and the tests hold the two to each other. Pure core: numpy and numba only.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from armanim.arm.capsules import Capsules, capsule_lever_rows, next_axis_reach
from armanim.arm.kernel import INLINE, JIT, _capsule_ends_one, _forward_one, compiled, packed_chain
from armanim.motion.filter.clearance import limit_buffer, self_shift
from armanim.motion.kernels.layout import World, world_arrays
from armanim.motion.planning.path import coarse_spacing
from armanim.motion.problem import Problem
from armanim.world.compiled import (
    CYLINDER_SCRATCH,
    SCRATCH,
    _cylinder_depth,
    _cylinder_pair,
    _pair,
    kind_count,
    segment_segment_pairs,
)

Measured = tuple[
    tuple[np.ndarray, np.ndarray],
    tuple[np.ndarray, np.ndarray, np.ndarray],
    World,
    tuple[np.ndarray, ...],
    tuple[np.ndarray, np.ndarray, np.ndarray],
    tuple[float, float],
]
"""What the compiled measures read of a problem (:attr:`CompiledCheck.measured`): ((rows, root) of
the chain, (packed capsules, their carriers, their radii), the world's arrays, the groups, the
enabled pairs, (shift, far)); one argument, so that each function says what it adds."""


@compiled(**INLINE)
def _point_segment(px: float, py: float, pz: float, a: np.ndarray, b: np.ndarray, c: int) -> float:
    """Distance from the point (px, py, pz) to the segment a[c]-b[c]."""
    ab0, ab1, ab2 = b[c, 0] - a[c, 0], b[c, 1] - a[c, 1], b[c, 2] - a[c, 2]
    denom = ab0 * ab0 + ab1 * ab1 + ab2 * ab2
    f = 0.0
    if denom > 0.0:
        f = min(max(((px - a[c, 0]) * ab0 + (py - a[c, 1]) * ab1 + (pz - a[c, 2]) * ab2) / denom, 0.0), 1.0)
    o0, o1, o2 = a[c, 0] + f * ab0 - px, a[c, 1] + f * ab1 - py, a[c, 2] + f * ab2 - pz
    return math.sqrt(o0 * o0 + o1 * o1 + o2 * o2)


@compiled(**INLINE)
def _point_box(px: float, py: float, pz: float, center: np.ndarray, half: np.ndarray, rotation: np.ndarray) -> float:
    """Signed distance of a point to a solid box (its centre, half edges, world-from-box rotation):
    the distance outside, minus the depth to its nearest face inside."""
    outside = 0.0
    deepest = -np.inf
    for i in range(3):
        x = (px - center[0]) * rotation[0, i] + (py - center[1]) * rotation[1, i] + (pz - center[2]) * rotation[2, i]
        excess = abs(x) - half[i]
        deepest = max(deepest, excess)
        if excess > 0.0:
            outside += excess * excess
    return math.sqrt(outside) if outside > 0.0 else deepest


@compiled(**INLINE)
def _point_cylinder(
    px: float, py: float, pz: float, center: np.ndarray, rotation: np.ndarray, h: float, r: float
) -> float:
    """Signed distance of a point to a solid cylinder (axis local z, half length ``h``, radius ``r``)."""
    x0, y0, z0 = px - center[0], py - center[1], pz - center[2]
    x = x0 * rotation[0, 0] + y0 * rotation[1, 0] + z0 * rotation[2, 0]
    y = x0 * rotation[0, 1] + y0 * rotation[1, 1] + z0 * rotation[2, 1]
    z = x0 * rotation[0, 2] + y0 * rotation[1, 2] + z0 * rotation[2, 2]
    return float(_cylinder_depth(x, y, z, h, r))


@compiled(**JIT)
def _bounding_spheres(
    a: np.ndarray,
    b: np.ndarray,
    radius: np.ndarray,
    members: tuple[np.ndarray, np.ndarray],
    center: np.ndarray,
    reach: np.ndarray,
) -> None:
    """Each group's bounding sphere (``members``: CSR start (G+1,) and capsule indices): the middle
    of its capsules' ends' box into ``center`` (G, 3), and the farthest capsule surface from it
    into ``reach`` (G,)."""
    start, caps = members
    for g in range(start.shape[0] - 1):
        lo0 = lo1 = lo2 = np.inf  # scalars, not arrays: this runs for every group of every pose
        hi0 = hi1 = hi2 = -np.inf
        for m in range(start[g], start[g + 1]):
            c = caps[m]
            lo0, hi0 = min(lo0, a[c, 0], b[c, 0]), max(hi0, a[c, 0], b[c, 0])
            lo1, hi1 = min(lo1, a[c, 1], b[c, 1]), max(hi1, a[c, 1], b[c, 1])
            lo2, hi2 = min(lo2, a[c, 2], b[c, 2]), max(hi2, a[c, 2], b[c, 2])
        center[g, 0], center[g, 1], center[g, 2] = 0.5 * (lo0 + hi0), 0.5 * (lo1 + hi1), 0.5 * (lo2 + hi2)
        far = 0.0
        for m in range(start[g], start[g + 1]):
            c = caps[m]
            da = math.sqrt(
                (a[c, 0] - center[g, 0]) ** 2 + (a[c, 1] - center[g, 1]) ** 2 + (a[c, 2] - center[g, 2]) ** 2
            )
            db = math.sqrt(
                (b[c, 0] - center[g, 0]) ** 2 + (b[c, 1] - center[g, 1]) ** 2 + (b[c, 2] - center[g, 2]) ** 2
            )
            far = max(far, max(da, db) + radius[c])
        reach[g] = far


@compiled(**JIT)
def _obstacle_least(
    ends: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray],
    world: World,
    groups: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray],
    far: float,
    scratch: tuple[np.ndarray, np.ndarray],
    groups_least: np.ndarray,
) -> float:
    """The least clearance of any capsule to any obstacle or the floor, measured exactly where a
    group's bounding sphere comes within ``far`` of the obstacle, else that sphere's lower bound
    (so the result is exact when below ``far``, and at most the exact least otherwise); each
    group's own least into ``groups_least`` (G,). ``ends``: the capsules' ends a, b (c, 3), radii
    (c,) and which are points (c,); ``groups``: CSR start (G+1,) and capsule indices, and the
    groups' bounding spheres' centres (G, 3) and reaches (G,); ``scratch``: the closed forms'.

    Each kind of obstacle is one call for all groups, not one per group: a call passes every
    array again, which cost the planner a third of its time."""
    centers, radii, solid_centers, solid_half, solid_rotations, solid_radius, on_base = world[:7]
    cyl_centers, cyl_rotations, cyl_half, cyl_radius, allowed = world[9:14]
    spheres, solids = radii.shape[0], kind_count(solid_radius)
    _spheres_least(groups_least, ends, centers, radii, groups, far, allowed)
    _solids_least(
        groups_least,
        ends,
        solid_centers,
        solid_half,
        solid_rotations,
        solid_radius,
        groups,
        far,
        scratch,
        allowed,
        spheres,
    )
    _cylinders_least(
        groups_least,
        ends,
        cyl_centers,
        cyl_rotations,
        cyl_half,
        cyl_radius,
        groups,
        far,
        scratch,
        allowed,
        spheres + solids,
    )
    _floor_least(groups_least, ends, world[8], on_base, groups[:2], allowed, spheres + solids + kind_count(cyl_radius))
    least = np.inf
    for g in range(groups_least.shape[0]):
        if groups_least[g] < least or groups_least[g] != groups_least[g]:
            least = groups_least[g]
    return least


@compiled(**JIT)
def _spheres_least(
    groups_least: np.ndarray,
    ends: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray],
    centers: np.ndarray,
    radii: np.ndarray,
    groups: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray],
    far: float,
    allowed: np.ndarray,
) -> None:
    """Each group's least clearance to the spheres (``centers`` (S, 3), ``radii`` (S,)) into
    ``groups_least`` (G,), exact where its bounding sphere comes within ``far`` of a sphere, else
    that bound (:func:`_obstacle_least`'s arguments; a capsule's ``allowed`` sphere left out)."""
    a, b, radius, _ = ends
    start, caps, center, reach = groups
    for g in range(start.shape[0] - 1):
        least = np.inf
        for k in range(radii.shape[0]):
            bound = (
                math.sqrt(
                    (center[g, 0] - centers[k, 0]) ** 2
                    + (center[g, 1] - centers[k, 1]) ** 2
                    + (center[g, 2] - centers[k, 2]) ** 2
                )
                - radii[k]
                - reach[g]
            )
            if bound >= far:
                least = min(least, bound)
                continue
            for m in range(start[g], start[g + 1]):
                c = caps[m]
                if allowed[c] == k:
                    continue
                d = _point_segment(centers[k, 0], centers[k, 1], centers[k, 2], a, b, c) - radii[k] - radius[c]
                if d < least or d != d:
                    least = d
        groups_least[g] = least


@compiled(**JIT)
def _floor_least(
    groups_least: np.ndarray,
    ends: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray],
    floor: np.ndarray,
    on_base: np.ndarray,
    members: tuple[np.ndarray, np.ndarray],
    allowed: np.ndarray,
    column: int,
) -> None:
    """``groups_least`` (G,) lowered by each group's capsules' height above the floor (``floor``:
    its height (1,), or (0,) without one), but for the capsules on the base (``on_base`` (c,)) and
    a capsule allowed to touch it (the floor's kind ``column``)."""
    if not floor.shape[0]:
        return
    a, b, radius, _ = ends
    start, caps = members
    for g in range(start.shape[0] - 1):
        least = groups_least[g]
        for m in range(start[g], start[g + 1]):
            c = caps[m]
            if not on_base[c] and allowed[c] != column:
                d = min(a[c, 2], b[c, 2]) - floor[0] - radius[c]
                if d < least or d != d:
                    least = d
        groups_least[g] = least


@compiled(**JIT)
def _solids_least(
    groups_least: np.ndarray,
    ends: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray],
    solid_centers: np.ndarray | None,
    solid_half: np.ndarray | None,
    solid_rotations: np.ndarray | None,
    solid_radius: np.ndarray | None,
    groups: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray],
    far: float,
    scratch: tuple[np.ndarray, np.ndarray],
    allowed: np.ndarray,
    first: int,
) -> None:
    """:func:`_obstacle_least`'s ``groups_least`` (G,) lowered by the solids, each group's exactly
    where its bounding sphere comes within ``far`` of a solid, else by that sphere's bound; nothing
    without solids (their centres (B, 3), half edges (B, 3), rotations (B, 3, 3) and radii (B,),
    each None without any, by its own argument: numba prunes a branch on an argument's None). A capsule's pair with the
    obstacle it may touch (``allowed``, a kind column; the solids' from ``first`` on) is left out."""
    if solid_centers is None or solid_half is None or solid_rotations is None or solid_radius is None:
        return
    a, b, radius, sphere = ends
    start, caps, center, reach = groups
    s, normal = scratch
    for g in range(start.shape[0] - 1):
        least = groups_least[g]
        for k in range(solid_radius.shape[0]):
            bound = (
                _point_box(
                    center[g, 0], center[g, 1], center[g, 2], solid_centers[k], solid_half[k], solid_rotations[k]
                )
                - solid_radius[k]
                - reach[g]
            )
            if bound >= far:
                least = min(least, bound)
                continue
            for m in range(start[g], start[g + 1]):
                c = caps[m]
                if allowed[c] == first + k:
                    continue
                if sphere[c] and solid_radius[k] == 0.0:
                    d = _point_box(a[c, 0], a[c, 1], a[c, 2], solid_centers[k], solid_half[k], solid_rotations[k])
                else:
                    _, d = _pair(a[c], b[c], solid_centers[k], solid_half[k], solid_rotations[k], s, normal)
                d = d - solid_radius[k] - radius[c]
                if d < least or d != d:
                    least = d
        groups_least[g] = least


@compiled(**JIT)
def _cylinders_least(
    groups_least: np.ndarray,
    ends: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray],
    cyl_centers: np.ndarray | None,
    cyl_rotations: np.ndarray | None,
    cyl_half: np.ndarray | None,
    cyl_radius: np.ndarray | None,
    groups: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray],
    far: float,
    scratch: tuple[np.ndarray, np.ndarray],
    allowed: np.ndarray,
    first: int,
) -> None:
    """:func:`_solids_least` for the cylinders."""
    if cyl_centers is None or cyl_rotations is None or cyl_half is None or cyl_radius is None:
        return
    a, b, radius, sphere = ends
    start, caps, center, reach = groups
    s, normal = scratch
    for g in range(start.shape[0] - 1):
        least = groups_least[g]
        for k in range(cyl_radius.shape[0]):
            bound = (
                _point_cylinder(
                    center[g, 0],
                    center[g, 1],
                    center[g, 2],
                    cyl_centers[k],
                    cyl_rotations[k],
                    cyl_half[k],
                    cyl_radius[k],
                )
                - reach[g]
            )
            if bound >= far:
                least = min(least, bound)
                continue
            for m in range(start[g], start[g + 1]):
                c = caps[m]
                if allowed[c] == first + k:
                    continue
                if sphere[c]:
                    d = _point_cylinder(
                        a[c, 0], a[c, 1], a[c, 2], cyl_centers[k], cyl_rotations[k], cyl_half[k], cyl_radius[k]
                    )
                else:
                    _, d = _cylinder_pair(
                        a[c], b[c], cyl_centers[k], cyl_rotations[k], cyl_half[k], cyl_radius[k], s, normal
                    )
                d = d - radius[c]
                if d < least or d != d:
                    least = d
        groups_least[g] = least


@compiled(**JIT)
def _margins(measured: Measured, phi: np.ndarray, clear: np.ndarray, own: np.ndarray, clear_groups: np.ndarray) -> None:
    """For poses ``phi`` (k, n): the least clearance of any capsule to any obstacle or the floor
    into ``clear`` (k,) (+inf without any), each group's into ``clear_groups`` (k, G), and every
    enabled pair's gap plus ``shift`` into ``own`` (k, P); each exact where it is below ``far``, else a lower bound of at least ``far``
    (a pair of groups, or a group and an obstacle, whose bounding spheres are ``far`` apart is not
    measured capsule by capsule). ``measured``: :data:`Measured`, whose groups are the capsules by
    the joint that carries them (CSR start and indices), and the enabled pairs by their two groups
    (the groups' indices, and CSR start and indices of the pairs)."""
    (rows, root), (caps, link, part_radius), world, groups, pairs, (shift, far) = measured
    k, n = phi.shape
    c = link.shape[0]
    start, members = groups[:2]
    count = pairs[0].shape[0]
    g_count = start.shape[0] - 1
    points = np.empty((n + 1, 3))
    frames = np.empty((n, 3, 3))
    axes = np.empty((n, 3))
    tool = np.empty((3, 3))
    a = np.empty((c, 3))
    b = np.empty((c, 3))
    radius = part_radius[:c]
    center = np.empty((g_count, 3))
    reach = np.empty(g_count)
    near_first = np.empty(count, dtype=np.int64)
    near_second = np.empty(count, dtype=np.int64)
    near_index = np.empty(count, dtype=np.int64)
    gap_t = np.empty(count)
    gap_s = np.empty(count)
    gap = np.empty(count)
    gap_normal = np.empty((count, 3))
    joint_segment = caps[:, 7] > 0.5
    sphere = np.empty(c, dtype=np.bool_)
    s = np.empty(max(SCRATCH, CYLINDER_SCRATCH))
    normal = np.empty(3)
    for i in range(k):
        _forward_one(rows, root, phi[i], points, frames, axes, tool)
        _capsule_ends_one(points, frames, link, caps[:, 0:3], caps[:, 3:6], joint_segment, a, b)
        _bounding_spheres(a, b, radius, (start, members), center, reach)
        for u in range(c):
            sphere[u] = a[u, 0] == b[u, 0] and a[u, 1] == b[u, 1] and a[u, 2] == b[u, 2]
        clear[i] = _obstacle_least(
            (a, b, radius, sphere), world, (start, members, center, reach), far, (s, normal), clear_groups[i]
        )
        _pair_gaps(
            (a, b, sphere),
            (center, reach),
            groups[2:],
            pairs,
            (shift, far),
            (near_first, near_second, near_index, gap_t, gap_s, gap, gap_normal),
            own[i],
        )


@compiled(**JIT)
def _pair_gaps(
    ends: tuple[np.ndarray, np.ndarray, np.ndarray],
    spheres: tuple[np.ndarray, np.ndarray],
    pair_groups: tuple[np.ndarray, ...],
    pairs: tuple[np.ndarray, np.ndarray, np.ndarray],
    shift_far: tuple[float, float],
    scratch: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray],
    own: np.ndarray,
) -> None:
    """One pose's every enabled pair's gap plus ``shift`` into ``own`` (P,): exact where its two
    groups' bounding spheres (``spheres``: centres (G, 3), reaches (G,)) come within ``far``, else
    the spheres' bound. ``ends``: the capsules' ends a, b (c, 3) and which are points (c,);
    ``pair_groups``: each pair of groups' two groups (L,), (L,) and its pairs (CSR start (L+1,),
    indices); ``pairs``: each pair's capsules (P,), (P,) and summed radii (P,); ``scratch``: the
    near pairs' two capsules and index (P,) each, and the segment closed form's outputs."""
    a, b, sphere = ends
    center, reach = spheres
    group_a, group_b, pair_start, pair_members = pair_groups
    first, second, pair_radii = pairs
    shift, far = shift_far
    near_first, near_second, near_index, gap_t, gap_s, gap, gap_normal = scratch
    near = 0
    for lp in range(group_a.shape[0]):
        ga, gb = group_a[lp], group_b[lp]
        bound = (
            math.sqrt(
                (center[ga, 0] - center[gb, 0]) ** 2
                + (center[ga, 1] - center[gb, 1]) ** 2
                + (center[ga, 2] - center[gb, 2]) ** 2
            )
            - reach[ga]
            - reach[gb]
        )
        for m in range(pair_start[lp], pair_start[lp + 1]):
            p = pair_members[m]
            if bound >= far:
                own[p] = bound + shift
                continue
            u, v = first[p], second[p]
            if sphere[u]:  # a sphere and a sphere or a segment: the closed form of a point
                own[p] = _point_segment(a[u, 0], a[u, 1], a[u, 2], a, b, v) - pair_radii[p] + shift
            elif sphere[v]:
                own[p] = _point_segment(a[v, 0], a[v, 1], a[v, 2], a, b, u) - pair_radii[p] + shift
            else:
                near_first[near], near_second[near], near_index[near] = u, v, p
                near += 1
    if near:
        segment_segment_pairs(
            a, b, near_first[:near], near_second[:near], gap_t[:near], gap_s[:near], gap[:near], gap_normal[:near]
        )
        for r in range(near):
            p = near_index[r]
            own[p] = gap[r] - pair_radii[p] + shift


@compiled(**JIT)
def _group_least(own: np.ndarray, pair_start: np.ndarray, pair_members: np.ndarray) -> np.ndarray:
    """(k, L) the least shifted gap of each pose's pairs in each pair of groups (``own`` (k, P);
    the groups' pairs as CSR start (L+1,) and pair indices (P,)); NaN wins, as in ``_least``."""
    out = np.full((own.shape[0], pair_start.shape[0] - 1), np.inf)
    for i in range(own.shape[0]):
        for lp in range(pair_start.shape[0] - 1):
            for m in range(pair_start[lp], pair_start[lp + 1]):
                g = own[i, pair_members[m]]
                if g < out[i, lp] or g != g:
                    out[i, lp] = g
    return out


@compiled(**JIT)
def _least(clear: np.ndarray, own: np.ndarray) -> np.ndarray:
    """(k,) the least of each pose's obstacle clearance and shifted gaps (``own`` (k, any))."""
    out = clear.copy()
    for i in range(own.shape[0]):
        for p in range(own.shape[1]):
            if own[i, p] < out[i] or own[i, p] != own[i, p]:
                out[i] = own[i, p]
    return out


@compiled(**JIT)
def _inside(phi: np.ndarray, lower: np.ndarray, upper: np.ndarray, buffer: float) -> bool:
    """Whether every joint of the pose is within [lower + buffer, upper - buffer] (unlimited: +-inf)."""
    for j in range(phi.shape[0]):
        if not (phi[j] >= lower[j] + buffer and phi[j] <= upper[j] - buffer):
            return False
    return True


@compiled(**JIT)
def _certified(
    lo: np.ndarray, hi: np.ndarray, c_lo: np.ndarray, c_hi: np.ndarray, levers: np.ndarray, floor: float
) -> bool:
    """Whether every group's clearance (or every pair of groups' gap) at the ends of the piece
    lo-hi (n,), ``c_lo`` and ``c_hi`` (G,), is more than the most it can change on the way
    (``levers`` (n, G): its points' lever arms): c_lo + c_hi >= travel + 2 floor."""
    for g in range(c_lo.shape[0]):
        reach = 0.0
        for j in range(lo.shape[0]):
            reach += abs(hi[j] - lo[j]) * levers[j, g]
        if not c_lo[g] + c_hi[g] >= reach + 2 * floor:
            return False
    return True


@compiled(**JIT)
def _pairs_certified(
    lo: np.ndarray,
    hi: np.ndarray,
    g_lo: np.ndarray,
    g_hi: np.ndarray,
    levers: np.ndarray,
    p_lo: np.ndarray,
    p_hi: np.ndarray,
    rows: np.ndarray,
    pair_start: np.ndarray,
    pair_members: np.ndarray,
    floor: float,
) -> bool:
    """:func:`_certified` for the pairs of groups (``g_lo``, ``g_hi`` (L,), ``levers`` (n, L)); where
    a pair of groups' least gap does not certify the piece, each of its pairs by its own gaps
    (``p_lo``, ``p_hi`` (P,)) and lever arms (``rows`` (P, n); CSR ``pair_start``, ``pair_members``):
    a group's least gap may belong to a pair near the joint whose far neighbours set its levers."""
    n = lo.shape[0]
    for g in range(g_lo.shape[0]):
        reach = 0.0
        for j in range(n):
            reach += abs(hi[j] - lo[j]) * levers[j, g]
        if g_lo[g] + g_hi[g] >= reach + 2 * floor:
            continue
        for m in range(pair_start[g], pair_start[g + 1]):
            p = pair_members[m]
            reach = 0.0
            for j in range(n):
                reach += abs(hi[j] - lo[j]) * rows[p, j]
            if not p_lo[p] + p_hi[p] >= reach + 2 * floor:
                return False
    return True


@compiled(**JIT)
def _measured(measured: Measured, poses: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(k,) the least margin of poses (k, n), (k, G) each group's clearance, (k, L) each pair of
    groups' least shifted gap and (k, P) each pair's (:func:`_margins`)."""
    groups, pairs = measured[3], measured[4]
    k = poses.shape[0]
    clear = np.empty(k)
    own = np.empty((k, pairs[0].shape[0]))
    clear_groups = np.empty((k, groups[0].shape[0] - 1))
    _margins(measured, poses, clear, own, clear_groups)
    gaps = _group_least(own, groups[4], groups[5])
    return _least(clear, gaps), clear_groups, gaps, own


@compiled(**JIT)
def _pose_free(
    measured: Measured, lower: np.ndarray, upper: np.ndarray, buffer: float, phi: np.ndarray, floor: float
) -> bool:
    """Whether the pose ``phi`` (n,) is within [lower + buffer, upper - buffer] and its least margin
    (:func:`_measured`) is at least ``floor``: the planner's state check in one call."""
    if not _inside(phi, lower, upper, buffer):
        return False
    least = _measured(measured, phi.reshape((1, phi.shape[0])))[0]
    return bool(least[0] >= floor)


@compiled(**JIT)
def _motion_free(
    measured: Measured,
    limits: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray],
    settings: np.ndarray,
    a: np.ndarray,
    b: np.ndarray,
    floor: float,
) -> tuple[bool, int]:
    """:func:`armanim.motion.planning.path.motion_is_free` of the segment a-b, compiled.

    ``limits``: (lower, upper, levers (n,), each group's lever arms (n, G), each pair of groups'
    (n, L), each pair's (P, n)); ``settings``: (d_safe, the coarse samples' spacing, certify_to, max_halvings,
    max_samples, buffer). Returns (free, poses checked).

    A piece is certified group by group: each group's clearance at both ends against the most its
    own points move (the numpy check takes the least clearance of all against the farthest any
    point moves), and each pair of groups' least gap against the most the joints between them
    change it (every pair of two groups has those lever arms), and where that fails, each of its
    pairs against its own (a pair beside the joint between them moves less than the group's
    farthest: the UR5's base and its upper arm near the shoulder). Each bound is one the numpy
    check's implies, or tighter: the same answers, with fewer poses measured where the part
    near an obstacle moves less than the arm's farthest point."""
    lower, upper, levers = limits[:3]
    pair_start, pair_members = measured[3][4], measured[3][5]
    d_safe, spacing, certify_to = settings[0], settings[1], settings[2]
    max_halvings, max_samples, buffer = int(settings[3]), settings[4], settings[5]
    n = a.shape[0]
    travel = 0.0
    for j in range(n):
        travel += abs(b[j] - a[j]) * levers[j]
    count = travel / spacing
    if not count <= max_samples:
        return False, 0
    samples = max(int(math.ceil(count)) + 1, 2)
    poses = _coarse_poses(a, b, samples)
    least, clear, gaps, own = _measured(measured, poses)
    checks = samples
    for i in range(samples):
        if not least[i] >= floor:
            return False, checks
    if not (_inside(poses[0], lower, upper, buffer) and _inside(poses[samples - 1], lower, upper, buffer)):
        return False, checks
    lo, hi = poses[:-1].copy(), poses[1:].copy()
    c_lo, c_hi = clear[:-1].copy(), clear[1:].copy()
    o_lo, o_hi = gaps[:-1].copy(), gaps[1:].copy()
    p_lo, p_hi = own[:-1].copy(), own[1:].copy()
    for _ in range(max_halvings):
        pieces = lo.shape[0]
        if pieces == 0:
            return True, checks
        doubtful = _doubtful(
            (lo, hi),
            (c_lo, c_hi),
            (o_lo, o_hi),
            (p_lo, p_hi),
            limits[2:],
            (pair_start, pair_members),
            floor,
            certify_to * d_safe,
        )
        kept = np.nonzero(doubtful)[0]
        left = kept.shape[0]
        if left == 0:
            return True, checks
        mid = np.empty((left, n))
        for r in range(left):
            for j in range(n):
                mid[r, j] = 0.5 * (lo[kept[r], j] + hi[kept[r], j])
        least, c_mid, o_mid, p_mid = _measured(measured, mid)
        checks += left
        for r in range(left):
            if not least[r] >= floor:
                return False, checks
        lo, hi = _halves(lo, hi, mid, kept)
        c_lo, c_hi = _halves(c_lo, c_hi, c_mid, kept)
        o_lo, o_hi = _halves(o_lo, o_hi, o_mid, kept)
        p_lo, p_hi = _halves(p_lo, p_hi, p_mid, kept)
        if 2 * left > max_samples:
            return False, checks
    return lo.shape[0] == 0, checks


@compiled(**JIT)
def _coarse_poses(a: np.ndarray, b: np.ndarray, samples: int) -> np.ndarray:
    """(samples, n) poses evenly spaced from ``a`` to ``b`` (n,), both ends included."""
    u = np.linspace(0.0, 1.0, samples)
    poses = np.empty((samples, a.shape[0]))
    for i in range(samples):
        for j in range(a.shape[0]):
            poses[i, j] = a[j] + u[i] * (b[j] - a[j])
    return poses


@compiled(**JIT)
def _doubtful(
    pieces: tuple[np.ndarray, np.ndarray],
    clear: tuple[np.ndarray, np.ndarray],
    gaps: tuple[np.ndarray, np.ndarray],
    own: tuple[np.ndarray, np.ndarray],
    levers: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray],
    pair_groups: tuple[np.ndarray, np.ndarray],
    floor: float,
    settled: float,
) -> np.ndarray:
    """(pieces,) which pieces lo-hi (``pieces``: (pieces, n) each) the margins at their ends do not
    certify (:func:`_motion_free`): each group's clearance (``clear``: (pieces, G) at lo and at hi),
    each pair of groups' least gap (``gaps``: (pieces, L)), each pair's (``own``: (pieces, P));
    ``levers``: the arm's (n,), each group's (n, G), each pair of groups' (n, L), each pair's
    (P, n); ``pair_groups``: each pair of groups' pairs (CSR start (L+1,), indices). A piece
    whose farthest point moves at most ``settled`` is never doubtful."""
    lo, hi = pieces
    arm_levers, obstacle_levers, pair_levers, pair_rows = levers
    pair_start, pair_members = pair_groups
    doubtful = np.zeros(lo.shape[0], dtype=np.bool_)
    for i in range(lo.shape[0]):
        travel = 0.0
        for j in range(lo.shape[1]):
            travel += abs(hi[i, j] - lo[i, j]) * arm_levers[j]
        if not travel > settled:
            continue
        doubtful[i] = not (
            _certified(lo[i], hi[i], clear[0][i], clear[1][i], obstacle_levers, floor)
            and _pairs_certified(
                lo[i],
                hi[i],
                gaps[0][i],
                gaps[1][i],
                pair_levers,
                own[0][i],
                own[1][i],
                pair_rows,
                pair_start,
                pair_members,
                floor,
            )
        )
    return doubtful


@compiled(**JIT)
def _halves(lo: np.ndarray, hi: np.ndarray, mid: np.ndarray, kept: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The rows of two halves of the ``kept`` pieces lo-hi (pieces, m) split at ``mid`` (left, m):
    first every kept piece's lower half, then every upper half."""
    left = kept.shape[0]
    new_lo = np.empty((2 * left, lo.shape[1]))
    new_hi = np.empty((2 * left, lo.shape[1]))
    for r in range(left):
        i = kept[r]
        new_lo[r], new_hi[r], new_lo[left + r], new_hi[left + r] = lo[i], mid[r], mid[r], hi[i]
    return new_lo, new_hi


def _link_of(caps: Capsules) -> np.ndarray:
    """(c,) int: which link each capsule belongs to, the finest grouping the capsules tell: their
    URDF link's name where they have names, else the joint that carries them."""
    if not caps.names:
        return np.asarray(caps.link, dtype=np.int64)
    return np.unique(np.array(caps.names), return_inverse=True)[1].astype(np.int64)


def carrier_groups(
    link: np.ndarray, first: np.ndarray, second: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The capsules grouped by the joint that carries them (``link`` (c,), the base's -1 a group
    too), and the pairs (``first``, ``second`` (P,)) by their two groups: (CSR start (G+1,),
    capsule indices (c,), each group pair's two groups (L,) and (L,), CSR start (L+1,), pair
    indices (P,)).

    >>> [v.tolist() for v in carrier_groups(np.array([0, 0, 1, -1]), np.array([0, 1, 3]), np.array([2, 2, 0]))]
    [[0, 1, 3, 4], [3, 0, 1, 2], [0, 1], [1, 2], [0, 1, 3], [2, 0, 1]]
    """
    carriers, group = np.unique(link, return_inverse=True)
    members = np.argsort(group, kind="stable")
    start = np.searchsorted(group[members], np.arange(len(carriers) + 1))
    ga, gb = np.minimum(group[first], group[second]), np.maximum(group[first], group[second])
    keys, pair_group = np.unique(ga * len(carriers) + gb, return_inverse=True)
    pair_members = np.argsort(pair_group, kind="stable")
    pair_start = np.searchsorted(pair_group[pair_members], np.arange(len(keys) + 1))
    groups = max(len(carriers), 1)
    start, members, low, high, pair_start, pair_members = (
        np.ascontiguousarray(v, dtype=np.int64)
        for v in (start, members, keys // groups, keys % groups, pair_start, pair_members)
    )
    return start, members, low, high, pair_start, pair_members


def pair_capsule_rows(
    link: np.ndarray, first: np.ndarray, second: np.ndarray, rows: np.ndarray, reach: np.ndarray | None = None
) -> np.ndarray:
    """(P, n) the most each pair's gap changes per radian of joint j: the joints between the two
    capsules' carriers (``link`` (c,)) move the later one's points against the earlier one's
    frame, at most its ``rows`` (c, n) (:func:`~armanim.arm.capsules.capsule_lever_rows`); the
    others move both alike. For the first joint between them, at most the earlier capsule's
    ``reach`` (c,) too (:func:`~armanim.arm.capsules.next_axis_reach`, where given).

    >>> pair_capsule_rows(np.array([-1, 0, 1]), np.array([0, 1]), np.array([2, 2]), np.array([[0.0, 0], [1, 0], [3, 2]])).tolist()
    [[3.0, 2.0], [0.0, 2.0]]
    >>> pair_capsule_rows(np.array([-1, 0, 1]), np.array([0, 1]), np.array([2, 2]), np.array([[0.0, 0], [1, 0], [3, 2]]),
    ...                   np.array([0.5, 4.0, np.inf])).tolist()
    [[0.5, 2.0], [0.0, 2.0]]
    """
    lo, hi = np.minimum(link[first], link[second]), np.maximum(link[first], link[second])
    later = np.where(link[first] >= link[second], first, second)
    earlier = np.where(link[first] >= link[second], second, first)
    joint = np.arange(rows.shape[1])
    out = np.where((joint > lo[:, None]) & (joint <= hi[:, None]), rows[later], 0.0)
    if reach is not None:
        apart = np.nonzero(hi > lo)[0]
        out[apart, lo[apart] + 1] = np.minimum(out[apart, lo[apart] + 1], reach[earlier[apart]])
    return out


def group_levers(rows: np.ndarray, start: np.ndarray, members: np.ndarray) -> np.ndarray:
    """(n, G) the lever arms of each group of ``rows`` (m, n) (CSR ``start`` (G+1,) and row
    indices ``members``): the most of its members', joint by joint. For the pairs of groups
    (:func:`carrier_groups`) the members' rows are the same (the joints between the two groups).

    >>> rows = np.array([[0.0, 1.0], [0.0, 2.0], [3.0, 0.0]])
    >>> group_levers(rows, np.array([0, 2, 3]), np.array([0, 1, 2])).tolist()
    [[0.0, 3.0], [2.0, 0.0]]
    """
    if not len(members):
        return np.zeros((rows.shape[1], len(start) - 1))
    return np.ascontiguousarray(np.maximum.reduceat(rows[members], start[:-1], axis=0).T, dtype=float)


@dataclass(frozen=True)
class CompiledCheck:
    """One problem's arrays as the compiled checks read them, packed once per plan.

    ``closed``: a motion's ends may rest on the limits (a joint goal's path), else they keep the
    filter's buffer inside them, as :func:`~armanim.motion.filter.clearance.within_limits`.
    Clearances and gaps are exact below ``far`` (the planner's ``exact_within`` of the arm's
    reach) and lower bounds of at least ``far``
    beyond it: a motion certified by them is certified.
    """

    chain: tuple[np.ndarray, np.ndarray]
    body: tuple[np.ndarray, np.ndarray, np.ndarray]
    world: World
    groups: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]
    pairs: tuple[np.ndarray, np.ndarray, np.ndarray]
    shift: float
    far: float
    limits: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]
    settings: np.ndarray

    @classmethod
    def of(cls, problem: Problem, closed: bool = False, exact: bool = False) -> CompiledCheck:
        """The checks of ``problem``; ``exact``: every clearance and gap measured (no ``far``)."""
        caps, pairs, opts = problem.capsules, problem.self_pairs, problem.tunables.planner
        packed = caps.packed()
        spacing = coarse_spacing(problem)
        first = np.ascontiguousarray(pairs.first, dtype=np.int64)
        second = np.ascontiguousarray(pairs.second, dtype=np.int64)
        groups = carrier_groups(_link_of(caps), first, second)
        rows = capsule_lever_rows(problem.arm, caps)
        pair_rows = np.ascontiguousarray(
            pair_capsule_rows(caps.link, first, second, rows, next_axis_reach(problem.arm, caps))
        )
        return cls(
            chain=packed_chain(problem.arm),
            body=(
                np.ascontiguousarray(packed),
                np.ascontiguousarray(caps.link, dtype=np.int64),
                np.ascontiguousarray(caps.part_radius, dtype=float),
            ),
            world=world_arrays(problem),
            groups=groups,
            pairs=(first, second, np.ascontiguousarray(pairs.radii(caps), dtype=float)),
            shift=self_shift(problem) if len(pairs) else 0.0,
            far=np.inf if exact else max(opts.exact_within * problem.arm.reach, 4 * problem.solver.clearance),
            limits=(
                np.ascontiguousarray(problem.limits.lower, dtype=float),
                np.ascontiguousarray(problem.limits.upper, dtype=float),
                np.ascontiguousarray(problem.lever_arms, dtype=float),
                group_levers(rows, groups[0], groups[1]),
                group_levers(pair_rows, groups[4], groups[5]),
                pair_rows,
            ),
            settings=np.array(
                [
                    problem.solver.clearance,
                    spacing,
                    opts.certify_to,
                    opts.max_halvings,
                    opts.max_samples,
                    0.0 if closed else limit_buffer(problem),
                ]
            ),
        )

    @property
    def measured(self) -> Measured:
        """The arrays the compiled measures read (:data:`Measured`)."""
        return self.chain, self.body, self.world, self.groups, self.pairs, (float(self.shift), float(self.far))

    def margins(self, phi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(k,) the least obstacle clearance and (k, P) the shifted pair gaps of poses ``phi`` (k, n):
        :func:`~armanim.motion.filter.clearance.split_clearances`, compiled."""
        phi = np.ascontiguousarray(np.atleast_2d(phi), dtype=float)
        clear = np.empty(len(phi))
        own = np.empty((len(phi), len(self.pairs[0])))
        groups = np.empty((len(phi), len(self.groups[0]) - 1))
        _margins(self.measured, phi, clear, own, groups)
        return clear, own

    def pose_clearances(self, phi: np.ndarray) -> np.ndarray:
        """(k,) :func:`~armanim.motion.filter.clearance.pose_clearance` of poses ``phi`` (k, n), compiled."""
        clear, own = self.margins(phi)
        return clear if not own.shape[1] else np.minimum(clear, own.min(axis=1))

    def pose_clearance(self, phi: np.ndarray) -> float:
        """One pose's :func:`~armanim.motion.filter.clearance.pose_clearance` (n,), compiled."""
        clear, own = self.margins(phi)
        return float(min(clear[0], own.min())) if own.size else float(clear[0])

    def pose_free(self, phi: np.ndarray, floor: float) -> bool:
        """Whether the pose (n,) is within the limits (by the buffer, unless closed) and keeps ``floor``."""
        return bool(
            _pose_free(
                self.measured,
                self.limits[0],
                self.limits[1],
                float(self.settings[5]),
                np.ascontiguousarray(phi, dtype=float),
                float(floor),
            )
        )

    def motion_free(self, a: np.ndarray, b: np.ndarray, floor: float) -> tuple[bool, int]:
        """:func:`~armanim.motion.planning.path.motion_is_free` of the segment a-b, compiled."""
        free, checks = _motion_free(
            self.measured,
            self.limits,
            self.settings,
            np.ascontiguousarray(a, dtype=float),
            np.ascontiguousarray(b, dtype=float),
            float(floor),
        )
        return bool(free), int(checks)


def frame_margins(problem: Problem, phi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(F,) each pose's least clearance to any obstacle or the floor (+inf without any) and (F, P)
    every enabled pair's gap, of poses ``phi`` (F, n), exact: the numbers of
    :func:`~armanim.world.distances.min_link_clearance` and
    :func:`~armanim.world.selfdistances.self_gaps` to rounding (the tests hold them to each other),
    compiled, for a tenth of their time: what trajectory.csv writes of every frame."""
    return replace(CompiledCheck.of(problem, exact=True), shift=0.0).margins(phi)


__all__ = ["CompiledCheck", "frame_margins"]
