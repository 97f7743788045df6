"""The segment-box closed form of :mod:`armanim.world.closest`, compiled (numba); the
segment-cylinder distance (:func:`segment_cylinder_grid`, its numpy reference
:func:`armanim.world.distances.segment_cylinder`); and the arm's own capsule pairs:
segment-segment closest points, their rows and Jacobians.

One pose's clearances to a table, a shelf and a floor are a few dozen segment-box pairs;
written with numpy they were some 45 array operations, each a fixed 0.3-0.8 us whatever the
number of pairs, so a robot frame spent 50 us on them. Compiled, a pair is a few dozen
floating-point operations: the same pose's pairs take some 2 us. Every pair is computed by
the one function :func:`_pair`, whether it comes from a grid of segments and boxes or a list
of pairs, so a pair's numbers do not depend on the batch it is in (bit for bit). numba
compiles on first use and caches the machine code beside this file (or in the user's cache
folder when that is not writable, or nowhere when neither is: then each process compiles
again); it is imported only when a scene has a box, a capsule obstacle or a cylinder. Pure core: numpy
and numba only, scene units.

The work space of a pair is one scratch array, read at fixed offsets, and the helpers are plain
compiled functions called by the loops: LLVM inlines the small ones into them where it pays, and a
call to the others costs a few nanoseconds of a pair's hundreds (a box pair: some 240 ns either
way). numba's own inlining (``inline="always"``) gave the same machine code's speed and the same
bits, but copied and typed each helper's code again at every call site: it was a fifth of the first
run's compile (issue 55). The arm's
own pairs (:mod:`armanim.world.selfdistances`) are measured by the segment-segment closed form
where their closest points are unique and apart, by the box form (a segment as a box of one
edge) where they are not.
"""

from __future__ import annotations

import numpy as np

from armanim.arm.kernel import (
    compiled as compiled,  # numba.njit, cached where it can write (re-exported: the passes and the rasteriser use it)
)
from armanim.arm.kernel import joint_slides

TOUCHING = 1e-9
"""Scene units: a segment whose least outside distance to a box is this or less may enter it
(rounding puts a point on the surface a little either side), so its depth is searched for."""

_JIT = dict(error_model="numpy", nogil=True)  # numpy's error model: x / 0 is inf or NaN, as the closed form expects
_INLINE = dict(inline="always", **_JIT)  # the pieces of one closed form, inlined into it (numbers in and out)


@compiled(**_JIT)
def kind_count(rows: np.ndarray | None) -> int:
    """How many obstacles of one kind an array of theirs holds (its rows), 0 for None: a kind the
    scene has none of is passed as None (:func:`armanim.motion.kernels.layout.world_arrays`), so
    that the closed forms of that shape are not compiled."""
    if rows is None:
        return 0
    return int(rows.shape[0])


X0, U, KNOTS, GAP, CANDIDATES, SCRATCH = 0, 3, 6, 14, 6, 24
"""Offsets into a pair's scratch array: its start x0 and direction u in the box frame (3 each),
the knots (8), the gap to the box (3); the deepest point's 18 candidates reuse the knots' place."""


@compiled(**_JIT)
def _clamp(x: float, low: float, high: float) -> float:
    """min(max(x, low), high), as numpy's maximum and minimum compute it (x is never NaN here)."""
    return min(max(x, low), high)


@compiled(**_JIT)
def _least_outside(s: np.ndarray, h: np.ndarray) -> float:
    """The largest t in [0, 1] that minimises the squared distance of x0 + t u (box frame,
    in the scratch ``s``) to the box [-h, h]: where its derivative, sum_i u_i e_i(t) with e
    the excess beyond the box, stops being <= 0 (0 inside the box).

    The derivative is piecewise linear and nondecreasing, with knots where the segment
    crosses the box's six slab planes: it is evaluated at each knot and at both ends; on the
    piece where it turns positive the same coordinates lie beyond the box, and that piece's
    root is its minimiser.
    """
    for i in range(3):
        inverse = 1.0 / s[U + i]  # u_i = 0: +-inf, no crossing (its knots go to an end)
        k = (h[i] - s[X0 + i]) * inverse
        s[KNOTS + i] = min(1.0, 0.0 if k != k else max(k, 0.0))  # a NaN (0/0) goes to 0
        k = (-h[i] - s[X0 + i]) * inverse
        s[KNOTS + 3 + i] = min(1.0, 0.0 if k != k else max(k, 0.0))
    s[KNOTS + 6] = 1.0  # the ends, the far end first
    s[KNOTS + 7] = 0.0
    right = 2.0  # the first knot where the squared distance rises (2: none)
    for j in range(8):
        knot = s[KNOTS + j]
        slope = 0.0
        for i in range(3):
            x = knot * s[U + i] + s[X0 + i]
            slope += (x - _clamp(x, -h[i], h[i])) * s[U + i]
        if slope > 0.0 and knot < right:
            right = knot
    left = 0.0  # the knot before it
    for j in range(8):
        knot = s[KNOTS + j]
        if knot < right and knot > left:
            left = knot
    right = min(right, 1.0)
    middle = 0.5 * (left + right)
    offset = 0.0
    rate = 0.0
    for i in range(3):
        x = middle * s[U + i] + s[X0 + i]
        near = _clamp(x, -h[i], h[i])
        if x != near:  # beyond the box on this piece
            offset += s[U + i] * (s[X0 + i] - near)
            rate += s[U + i] * s[U + i]
    root = -offset / rate  # where the piece's derivative is 0; 0/0 on a flat piece
    t = right if root != root else min(root, right)  # a flat piece takes its right end
    return max(t, left)


@compiled(**_JIT)
def _signed_distance(s: np.ndarray, t: float, h: np.ndarray) -> float:
    """Signed distance of x0 + t u (box frame, in the scratch ``s``) to the box [-h, h]."""
    beyond = 0.0
    deepest = -np.inf
    for i in range(3):
        q = abs(t * s[U + i] + s[X0 + i]) - h[i]
        beyond += max(q, 0.0) ** 2
        deepest = max(deepest, q)
    return np.sqrt(beyond) + min(deepest, 0.0)  # type: ignore[no-any-return]  # numba compiles this: no typing.cast in nopython mode


@compiled(**_JIT)
def _deepest(s: np.ndarray, h: np.ndarray, t_outside: float) -> tuple[float, float]:
    """(t, signed distance) of the segment's deepest point in the box: its depth (the least
    of the six face functions h_i -+ x_i(t)) is concave and piecewise linear, so its greatest
    value lies where two of them cross, at an end, or at ``t_outside``. Ties: the first of
    the crossings (faces in the order +x, +y, +z, -x, -y, -z), the far end, the near end."""
    n = CANDIDATES
    for i in range(6):
        for j in range(i + 1, 6):
            si = 1.0 if i < 3 else -1.0
            sj = 1.0 if j < 3 else -1.0
            level_i = h[i % 3] - si * s[X0 + i % 3]
            level_j = h[j % 3] - sj * s[X0 + j % 3]
            den = (-si * s[U + i % 3]) - (-sj * s[U + j % 3])
            ratio = (level_j - level_i) / den if den != 0.0 else 0.0
            s[n] = min(max(ratio, 0.0), 1.0)
            n += 1
    s[n] = 1.0
    s[n + 1] = 0.0
    s[n + 2] = t_outside
    best_t = s[CANDIDATES]
    best = _signed_distance(s, best_t, h)
    for k in range(CANDIDATES + 1, n + 3):
        d = _signed_distance(s, s[k], h)
        if d < best:
            best, best_t = d, s[k]
    return best_t, best


@compiled(**_JIT)
def _gap(s: np.ndarray, t: float, h: np.ndarray) -> float:
    """Writes x0 + t u less its nearest point of the box into the scratch; returns its squared length."""
    squares = 0.0
    for i in range(3):
        x = t * s[U + i] + s[X0 + i]
        s[GAP + i] = x - _clamp(x, -h[i], h[i])
        squares += s[GAP + i] * s[GAP + i]
    return squares


@compiled(**_JIT)
def _pair(
    a: np.ndarray,
    b: np.ndarray,
    center: np.ndarray,
    h: np.ndarray,
    rotation: np.ndarray,
    s: np.ndarray,
    normal: np.ndarray,
) -> tuple[float, float]:
    """Segment a-b ((3,) each) against one box: writes the world unit normal into ``normal``
    (3,) and returns (t, signed distance); ``s``: the (SCRATCH,) work space."""
    for i in range(3):  # the box frame: R^T (a - c) and R^T (b - a)
        s[X0 + i] = (
            (a[0] - center[0]) * rotation[0, i]
            + (a[1] - center[1]) * rotation[1, i]
            + (a[2] - center[2]) * rotation[2, i]
        )
        s[U + i] = (b[0] - a[0]) * rotation[0, i] + (b[1] - a[1]) * rotation[1, i] + (b[2] - a[2]) * rotation[2, i]
    t = _least_outside(s, h)
    dist = np.sqrt(_gap(s, t, h))
    if dist > TOUCHING:
        for i in range(3):
            s[GAP + i] /= dist
    else:  # the segment reaches the box: its deepest point, and the deepest face's normal
        t, dist = _deepest(s, h, t)
        squares = _gap(s, t, h)
        if squares > 0.0:
            outside = np.sqrt(squares)
            for i in range(3):
                s[GAP + i] /= outside
        else:
            axis = 0
            deepest = -np.inf
            for i in range(3):
                q = abs(t * s[U + i] + s[X0 + i]) - h[i]
                if q > deepest:
                    deepest, axis = q, i
            for i in range(3):
                s[GAP + i] = 0.0
            s[GAP + axis] = 1.0 if t * s[U + axis] + s[X0 + axis] >= 0.0 else -1.0
    for c in range(3):  # back to the world: R n
        normal[c] = rotation[c, 0] * s[GAP] + rotation[c, 1] * s[GAP + 1] + rotation[c, 2] * s[GAP + 2]
    return t, dist


@compiled(**_JIT)
def segment_box_grid(
    a: np.ndarray,
    b: np.ndarray,
    centers: np.ndarray,
    half: np.ndarray,
    rotations: np.ndarray,
    t: np.ndarray,
    dist: np.ndarray,
    normal: np.ndarray,
) -> None:
    """Every segment a_m-b_m ((M, 3) each) against every box ((K, 3), (K, 3), (K, 3, 3)):
    fills t and dist (M, K) and normal (M, K, 3)."""
    s = np.empty(SCRATCH)
    for m in range(a.shape[0]):
        for k in range(centers.shape[0]):
            t[m, k], dist[m, k] = _pair(a[m], b[m], centers[k], half[k], rotations[k], s, normal[m, k])


@compiled(**_JIT)
def segment_box_pairs(
    a: np.ndarray,
    b: np.ndarray,
    centers: np.ndarray,
    half: np.ndarray,
    rotations: np.ndarray,
    segment: np.ndarray,
    box: np.ndarray,
    t: np.ndarray,
    dist: np.ndarray,
    normal: np.ndarray,
) -> None:
    """Segment ``segment[p]`` against box ``box[p]`` for each pair p: fills t and dist (P,)
    and normal (P, 3)."""
    s = np.empty(SCRATCH)
    for p in range(segment.shape[0]):
        m, k = segment[p], box[p]
        t[p], dist[p] = _pair(a[m], b[m], centers[k], half[k], rotations[k], s, normal[p])


# ----------------------------------------------------------------------------- segment-cylinder

CYLINDER_SCRATCH = 16
"""Room for a segment-cylinder pair's candidate fractions (:func:`_cylinder_pair`: 15 at most)."""


@compiled(**_JIT)
def _cylinder_depth(x: float, y: float, z: float, h: float, r: float) -> float:
    """Signed distance of the point (x, y, z) (cylinder frame) to the solid cylinder
    x^2 + y^2 <= r^2, |z| <= h: the distance to it outside, minus the depth to its nearest
    surface inside."""
    dr = np.sqrt(x * x + y * y) - r
    dz = abs(z) - h
    if dr > 0.0 and dz > 0.0:  # beyond the rim
        return np.sqrt(dr * dr + dz * dz)  # type: ignore[no-any-return]  # numba compiles this
    if dr > 0.0:  # beside the side (sqrt(dr^2) is dr exactly)
        return dr  # type: ignore[no-any-return]  # numba compiles this
    return dz if dz > 0.0 else max(dr, dz)  # beside a cap, or inside


@compiled(**_JIT)
def _add_roots(qa: float, qb: float, qc: float, s: np.ndarray, n: int) -> int:
    """Appends to ``s`` from place ``n`` the real roots of qa t^2 + qb t + qc (and the vertex
    -qb / (2 qa), where a double root rounds away), clamped to [0, 1]; returns the new count."""
    if qa == 0.0:
        if qb != 0.0:
            s[n] = _clamp(-qc / qb, 0.0, 1.0)
            n += 1
        return n
    s[n] = _clamp(-qb / (2.0 * qa), 0.0, 1.0)
    n += 1
    disc = qb * qb - 4.0 * qa * qc
    if disc >= 0.0:
        q = -0.5 * (qb + np.sqrt(disc)) if qb >= 0.0 else -0.5 * (qb - np.sqrt(disc))
        s[n] = _clamp(q / qa, 0.0, 1.0)
        n += 1
        if q != 0.0:
            s[n] = _clamp(qc / q, 0.0, 1.0)
            n += 1
    return n


@compiled(**_JIT)
def _rim_slope(
    t: float, x0: float, y0: float, z0: float, ux: float, uy: float, uz: float, h: float, r: float, side: float
) -> float:
    """Half the derivative in t of the squared distance of x0 + t u to the rim at z = side h
    (where the point is beyond the side and that cap): (rho - r) rho' + (side z - h) side u_z."""
    px = x0 + t * ux
    py = y0 + t * uy
    rho = np.sqrt(px * px + py * py)
    return (rho - r) * (px * ux + py * uy) / rho + (side * (z0 + t * uz) - h) * side * uz  # type: ignore[no-any-return]


@compiled(**_JIT)
def _rim_curvature(t: float, x0: float, y0: float, ux: float, uy: float, uz: float, r: float) -> float:
    """The derivative in t of :func:`_rim_slope`: rho'^2 + (rho - r) rho'' + u_z^2, with
    rho' = (p . u) / rho and rho'' = (|u|^2 - rho'^2) / rho in the plane across the axis (> 0
    beyond the side: the slope rises)."""
    px = x0 + t * ux
    py = y0 + t * uy
    rho = np.sqrt(px * px + py * py)
    rate = (px * ux + py * uy) / rho
    return rate * rate + (rho - r) * (ux * ux + uy * uy - rate * rate) / rho + uz * uz  # type: ignore[no-any-return]


@compiled(**_JIT)
def _rim_minimum(
    lo: float,
    hi: float,
    x0: float,
    y0: float,
    z0: float,
    ux: float,
    uy: float,
    uz: float,
    h: float,
    r: float,
    side: float,
) -> float:
    """The t in [lo, hi] nearest the rim on a piece where the segment lies beyond the side and
    the cap ``side``: the root of :func:`_rim_slope` (nondecreasing: the distance to the circle
    is convex there), by Newton's steps kept inside a bracket that each step shrinks, a
    bisection wherever a step would leave it or gain less than half, to the spacing of floats;
    an end where the slope does not change sign."""
    if _rim_slope(lo, x0, y0, z0, ux, uy, uz, h, r, side) >= 0.0:
        return lo
    if _rim_slope(hi, x0, y0, z0, ux, uy, uz, h, r, side) <= 0.0:
        return hi
    t = 0.5 * (lo + hi)
    last = hi - lo
    for _ in range(100):
        slope = _rim_slope(t, x0, y0, z0, ux, uy, uz, h, r, side)
        if slope == 0.0:
            return t
        if slope > 0.0:
            hi = t
        else:
            lo = t
        step = slope / _rim_curvature(t, x0, y0, ux, uy, uz, r)
        if abs(step) <= 4e-16:  # t to a few spacings of floats: the distance is flat there
            return _clamp(t - step, lo, hi)
        nxt = t - step
        if not (nxt > lo and nxt < hi) or abs(step) > 0.5 * last:  # off the bracket, or slow: bisect
            nxt = 0.5 * (lo + hi)
        last = abs(nxt - t)
        if nxt == t or not (hi > lo):
            return nxt
        t = nxt
    return t


@compiled(**_JIT)
def _cylinder_pair(
    a: np.ndarray,
    b: np.ndarray,
    center: np.ndarray,
    rotation: np.ndarray,
    h: float,
    r: float,
    s: np.ndarray,
    normal: np.ndarray,
) -> tuple[float, float]:
    """Segment a-b ((3,) each) against one solid cylinder (centre, world-from-cylinder
    ``rotation``, half length ``h``, radius ``r``; axis local z): writes the world unit normal
    (the cylinder's signed distance's gradient at the segment's least point, out of it) into
    ``normal`` (3,) and returns (t, signed distance); ``s``: (CYLINDER_SCRATCH,) work space.

    The signed distance f(t) of a + t (b - a) is convex (the solid is). Its pieces change where
    the segment crosses the side (rho = r, a quadratic) or a cap's plane (z = +-h); on a piece
    beside the side f is rho - r, least at the segment's closest approach to the axis; beside a
    cap it is linear; inside it is max(rho - r, |z| - h), least where those are equal (a
    quadratic in t once squared), at the closest approach to the axis, at z = 0 or at an end.
    Those fractions are the candidates (the inside ones only where the others come within
    :data:`TOUCHING`: a segment that enters crosses the surface at one of the others, where f is
    0 to rounding); the least f among them is the minimum, exact, unless
    the least point lies beyond the rim (beside both the side and a cap), where the distance to
    the circle has no closed form along a line: there the slope's root is found on the piece
    beside the best candidate that holds it (:func:`_rim_minimum`: Newton's steps in a bracket,
    to a few spacings of floats in t, where the distance is flat to rounding: exact to rounding,
    not in closed form). Ties: the fraction nearest b."""
    x0 = (a[0] - center[0]) * rotation[0, 0] + (a[1] - center[1]) * rotation[1, 0] + (a[2] - center[2]) * rotation[2, 0]
    y0 = (a[0] - center[0]) * rotation[0, 1] + (a[1] - center[1]) * rotation[1, 1] + (a[2] - center[2]) * rotation[2, 1]
    z0 = (a[0] - center[0]) * rotation[0, 2] + (a[1] - center[1]) * rotation[1, 2] + (a[2] - center[2]) * rotation[2, 2]
    ux = (b[0] - a[0]) * rotation[0, 0] + (b[1] - a[1]) * rotation[1, 0] + (b[2] - a[2]) * rotation[2, 0]
    uy = (b[0] - a[0]) * rotation[0, 1] + (b[1] - a[1]) * rotation[1, 1] + (b[2] - a[2]) * rotation[2, 1]
    uz = (b[0] - a[0]) * rotation[0, 2] + (b[1] - a[1]) * rotation[1, 2] + (b[2] - a[2]) * rotation[2, 2]
    uu = ux * ux + uy * uy
    pu = x0 * ux + y0 * uy
    pp = x0 * x0 + y0 * y0
    s[0] = 1.0  # the far end first: ties go to it
    s[1] = 0.0
    n = 2
    if uu > 0.0:  # the closest approach to the axis
        s[n] = _clamp(-pu / uu, 0.0, 1.0)
        n += 1
    if uz != 0.0:  # the caps' planes
        s[n] = _clamp((h - z0) / uz, 0.0, 1.0)
        s[n + 1] = _clamp((-h - z0) / uz, 0.0, 1.0)
        n += 2
    n = _add_roots(uu, 2.0 * pu, pp - r * r, s, n)  # through the side
    line = (x0, y0, z0, ux, uy, uz)
    best_t = s[0]
    best = _cylinder_depth(x0 + best_t * ux, y0 + best_t * uy, z0 + best_t * uz, h, r)
    for k in range(1, n):
        tk = s[k]
        d = _cylinder_depth(x0 + tk * ux, y0 + tk * uy, z0 + tk * uz, h, r)
        if d < best or (d == best and tk > best_t):
            best, best_t = d, tk
    if (
        not best > TOUCHING
    ):  # it may enter: where it crosses the middle plane, and as deep below the side as below a cap
        first = n
        if uz != 0.0:
            s[n] = _clamp(-z0 / uz, 0.0, 1.0)
            n += 1
        for side in (1.0, -1.0):  # rho = r - h + side z, squared
            w = r - h + side * z0
            n = _add_roots(uu - uz * uz, 2.0 * (pu - side * uz * w), pp - w * w, s, n)
        for k in range(first, n):
            tk = s[k]
            d = _cylinder_depth(x0 + tk * ux, y0 + tk * uy, z0 + tk * uz, h, r)
            if d < best or (d == best and tk > best_t):
                best, best_t = d, tk
    if best > 0.0:  # apart: the least point may lie beyond the rim, on a piece beside the best candidate
        left, right = 0.0, 1.0
        for k in range(n):
            if s[k] < best_t and s[k] > left:
                left = s[k]
            if s[k] > best_t and s[k] < right:
                right = s[k]
        best, best_t = _beyond_rim((left, best_t, right), line, h, r, best)
    ex, ey, ez = _cylinder_normal(line, best_t, h, r)
    for c in range(3):  # back to the world: R e
        normal[c] = rotation[c, 0] * ex + rotation[c, 1] * ey + rotation[c, 2] * ez
    return best_t, best


@compiled(**_INLINE)
def _beyond_rim(
    bracket: tuple[float, float, float],
    line: tuple[float, float, float, float, float, float],
    h: float,
    r: float,
    best: float,
) -> tuple[float, float]:
    """(``best``, its fraction), or the least distance beyond the rim where the least point lies
    there. ``bracket``: the nearest candidates left of the best one's fraction, that fraction,
    the nearest right of it; on each piece between, where its middle is beside both the side and
    a cap, the slope's root by :func:`_rim_minimum`. ``line``: the segment's start x0, y0, z0 and
    direction ux, uy, uz in the frame of the cylinder (half length ``h``, radius ``r``, metres)
    (:func:`_cylinder_pair`). Numbers in and out: an array handed to a helper costs its
    reference counts, a pair at a time."""
    x0, y0, z0, ux, uy, uz = line
    left, best_t, right = bracket
    for piece in range(2):
        lo, hi = (left, best_t) if piece == 0 else (best_t, right)
        if not hi > lo:
            continue
        mid = 0.5 * (lo + hi)
        px, py, pz = x0 + mid * ux, y0 + mid * uy, z0 + mid * uz
        if px * px + py * py > r * r and abs(pz) > h:
            tk = _rim_minimum(lo, hi, x0, y0, z0, ux, uy, uz, h, r, 1.0 if pz > 0.0 else -1.0)
            d = _cylinder_depth(x0 + tk * ux, y0 + tk * uy, z0 + tk * uz, h, r)
            if d < best:
                best, best_t = d, tk
    return best, best_t


@compiled(**_INLINE)
def _cylinder_normal(
    line: tuple[float, float, float, float, float, float], t: float, h: float, r: float
) -> tuple[float, float, float]:
    """The unit normal, in the cylinder's frame, at the point ``t`` of the segment ``line`` (as
    :func:`_beyond_rim`'s) of the cylinder of half length ``h`` and radius ``r``: the signed
    distance's gradient, out of the cylinder (:func:`_cylinder_pair`)."""
    x0, y0, z0, ux, uy, uz = line
    px, py, pz = x0 + t * ux, y0 + t * uy, z0 + t * uz
    rho = np.sqrt(px * px + py * py)
    cx, cy = (px / rho, py / rho) if rho > 0.0 else (1.0, 0.0)  # the radial direction (any on the axis)
    cz = 1.0 if pz >= 0.0 else -1.0
    dr, dz = rho - r, abs(pz) - h
    if dr > 0.0 or dz > 0.0:  # outside: from the nearest point of the surface
        ra, za = max(dr, 0.0), max(dz, 0.0)
        length = np.sqrt(ra * ra + za * za)
        return ra * cx / length, ra * cy / length, za * cz / length
    if dr > dz:  # inside, nearer the side
        return cx, cy, 0.0
    return 0.0, 0.0, cz  # inside, nearer a cap


@compiled(**_JIT)
def segment_cylinder_grid(
    a: np.ndarray,
    b: np.ndarray,
    centers: np.ndarray,
    rotations: np.ndarray,
    half_length: np.ndarray,
    radius: np.ndarray,
    t: np.ndarray,
    dist: np.ndarray,
    normal: np.ndarray,
) -> None:
    """Every segment a_m-b_m ((M, 3) each) against every cylinder ((K, 3), (K, 3, 3), (K,), (K,)):
    fills t and dist (M, K) and normal (M, K, 3) (:func:`_cylinder_pair`)."""
    s = np.empty(CYLINDER_SCRATCH)
    for m in range(a.shape[0]):
        for k in range(centers.shape[0]):
            t[m, k], dist[m, k] = _cylinder_pair(
                a[m], b[m], centers[k], rotations[k], half_length[k], radius[k], s, normal[m, k]
            )


@compiled(**_JIT)
def segment_cylinder_pairs(
    a: np.ndarray,
    b: np.ndarray,
    centers: np.ndarray,
    rotations: np.ndarray,
    half_length: np.ndarray,
    radius: np.ndarray,
    segment: np.ndarray,
    cylinder: np.ndarray,
    t: np.ndarray,
    dist: np.ndarray,
    normal: np.ndarray,
) -> None:
    """Segment ``segment[p]`` against cylinder ``cylinder[p]`` for each pair p: fills t and dist
    (P,) and normal (P, 3), each pair's numbers those of :func:`segment_cylinder_grid`."""
    s = np.empty(CYLINDER_SCRATCH)
    for p in range(segment.shape[0]):
        m, k = segment[p], cylinder[p]
        t[p], dist[p] = _cylinder_pair(a[m], b[m], centers[k], rotations[k], half_length[k], radius[k], s, normal[p])


PARALLEL = 1e-10
"""Two segments whose directions' cross product, squared, is this fraction of |d1|^2 |d2|^2 or
less count as parallel: their closest points are not unique, and :func:`segment_segment_pairs`
leaves them to the box form's tie rules."""


@compiled(**_JIT)
def _segments_apart(
    a: np.ndarray, b: np.ndarray, i: int, j: int, normal: np.ndarray, p: int
) -> tuple[float, float, float]:
    """Closest points of segments i and j (rows of a-b) where they are unique and apart: (t on i,
    s on j, distance), the unit normal from j's point to i's into row p of ``normal`` (an index, not a
    row view: a view per pair costs more than the closed form); distance -1 where
    they are not (parallel, a segment of no length, or touching): the caller measures those by
    the box form. The clamped closed form of Ericson, *Real-Time Collision Detection* 5.1.9."""
    d10, d11, d12 = b[i, 0] - a[i, 0], b[i, 1] - a[i, 1], b[i, 2] - a[i, 2]
    d20, d21, d22 = b[j, 0] - a[j, 0], b[j, 1] - a[j, 1], b[j, 2] - a[j, 2]
    r0, r1, r2 = a[i, 0] - a[j, 0], a[i, 1] - a[j, 1], a[i, 2] - a[j, 2]
    aa = d10 * d10 + d11 * d11 + d12 * d12
    ee = d20 * d20 + d21 * d21 + d22 * d22
    bb = d10 * d20 + d11 * d21 + d12 * d22
    denom = aa * ee - bb * bb
    if not (aa > 0.0 and ee > 0.0 and denom > PARALLEL * aa * ee):
        return 0.0, 0.0, -1.0
    c = d10 * r0 + d11 * r1 + d12 * r2
    f = d20 * r0 + d21 * r1 + d22 * r2
    t = _clamp((bb * f - c * ee) / denom, 0.0, 1.0)
    s = (bb * t + f) / ee
    if s < 0.0:
        s = 0.0
        t = _clamp(-c / aa, 0.0, 1.0)
    elif s > 1.0:
        s = 1.0
        t = _clamp((bb - c) / aa, 0.0, 1.0)
    return _apart((r0, r1, r2), (d10, d11, d12), (d20, d21, d22), t, s, normal, p)


@compiled(**_JIT)
def _points_apart(
    a: np.ndarray, b: np.ndarray, i: int, j: int, normal: np.ndarray, p: int
) -> tuple[float, float, float]:
    """Segments i and j (rows of a-b) of which one or both have no length (a sphere's capsule):
    (t on i, s on j, distance), the unit normal from j's point to i's into row p of ``normal``;
    a point's fraction is 0. Distance -1 where neither is a point or they touch (left to the box
    form). The box form of :func:`segment_segment_pairs` gives these pairs (their closest points
    unique) to rounding, in some 160 ns a pair against 20 here; the compiled IK attempt measures
    them so (the frame loop keeps the box form, which its goldens were written with)."""
    d10, d11, d12 = b[i, 0] - a[i, 0], b[i, 1] - a[i, 1], b[i, 2] - a[i, 2]
    d20, d21, d22 = b[j, 0] - a[j, 0], b[j, 1] - a[j, 1], b[j, 2] - a[j, 2]
    aa = d10 * d10 + d11 * d11 + d12 * d12
    ee = d20 * d20 + d21 * d21 + d22 * d22
    r0, r1, r2 = a[i, 0] - a[j, 0], a[i, 1] - a[j, 1], a[i, 2] - a[j, 2]
    t = 0.0
    s = 0.0
    if aa == 0.0 and ee > 0.0:  # i a point: the nearest point of j
        s = min(max((r0 * d20 + r1 * d21 + r2 * d22) / ee, 0.0), 1.0)
    elif ee == 0.0 and aa > 0.0:  # j a point: the nearest point of i
        t = min(max(-(r0 * d10 + r1 * d11 + r2 * d12) / aa, 0.0), 1.0)
    elif not (aa == 0.0 and ee == 0.0):
        return 0.0, 0.0, -1.0
    return _apart((r0, r1, r2), (d10, d11, d12), (d20, d21, d22), t, s, normal, p)


@compiled(**_JIT)
def _apart(
    r: tuple[float, float, float],
    d1: tuple[float, float, float],
    d2: tuple[float, float, float],
    t: float,
    s: float,
    normal: np.ndarray,
    p: int,
) -> tuple[float, float, float]:
    """The closest points at fractions t of segment i (direction d1) and s of segment j (d2),
    r = a_i - a_j: (t, s, distance), their unit normal from j's point to i's into row p of
    ``normal``; distance -1 where they touch (:data:`TOUCHING`). The vectors as tuples of
    numbers (passed as the numbers are: no array, no reference count)."""
    r0, r1, r2 = r
    d10, d11, d12 = d1
    d20, d21, d22 = d2
    g0 = r0 + t * d10 - s * d20
    g1 = r1 + t * d11 - s * d21
    g2 = r2 + t * d12 - s * d22
    dist = np.sqrt(g0 * g0 + g1 * g1 + g2 * g2)
    if not dist > TOUCHING:
        return 0.0, 0.0, -1.0
    normal[p, 0], normal[p, 1], normal[p, 2] = g0 / dist, g1 / dist, g2 / dist
    return t, s, dist


@compiled(**_JIT)
def segment_segment_pairs(
    a: np.ndarray,
    b: np.ndarray,
    first: np.ndarray,
    second: np.ndarray,
    t: np.ndarray,
    s_out: np.ndarray,
    dist: np.ndarray,
    normal: np.ndarray,
) -> None:
    """Segment ``first[p]`` against segment ``second[p]`` (rows of a-b, (M, 3) each) for each pair
    p. Fills t (the first's fraction), s_out (the second's fraction of its point nearest the
    first's), dist (P,) and normal (P, 3) (out of the second). Where the closest points are unique
    and apart, by the segment-segment closed form (:func:`_segments_apart`, some 20 ns a pair);
    else (parallel, touching) by the segment-box closed form (:func:`_pair`) with the second
    segment as a box of one edge (half edges (length / 2, 0, 0) along it, as
    :meth:`armanim.world.obstacles.Rods.axes` builds a capsule obstacle's axis), whose tie
    rules and deepest point the capsule obstacles share."""
    for p in range(first.shape[0]):
        t[p], s_out[p], dist[p] = _segments_apart(a, b, first[p], second[p], normal, p)  # dist -1: left to the box form
    segment_box_pairs_of_segments(a, b, first, second, t, s_out, dist, normal)


@compiled(**_JIT)
def capsule_pair_gaps(
    a: np.ndarray,
    b: np.ndarray,
    first: np.ndarray,
    second: np.ndarray,
    radii: np.ndarray,
    t: np.ndarray,
    s_out: np.ndarray,
    gap: np.ndarray,
    normal: np.ndarray,
) -> float:
    """:func:`segment_segment_pairs`, less each pair's two ``radii`` (P,): the capsules' gaps into
    ``gap``; returns the least (NaN if any is)."""
    segment_segment_pairs(a, b, first, second, t, s_out, gap, normal)
    least = np.inf
    for p in range(gap.shape[0]):
        gap[p] -= radii[p]
        if gap[p] < least or gap[p] != gap[p]:  # numpy's min: a NaN anywhere is the least (nothing compares below it)
            least = gap[p]
    return least


@compiled(**_JIT)
def segment_segment_boxes(
    a: np.ndarray,
    b: np.ndarray,
    first: np.ndarray,
    second: np.ndarray,
    t: np.ndarray,
    s_out: np.ndarray,
    dist: np.ndarray,
    normal: np.ndarray,
) -> None:
    """:func:`segment_segment_pairs` by the segment-box closed form alone, every pair (the
    reference the tests hold the segment-segment form to)."""
    dist[:] = -1.0
    segment_box_pairs_of_segments(a, b, first, second, t, s_out, dist, normal)


@compiled(**_JIT)
def segment_box_pairs_of_segments(
    a: np.ndarray,
    b: np.ndarray,
    first: np.ndarray,
    second: np.ndarray,
    t: np.ndarray,
    s_out: np.ndarray,
    dist: np.ndarray,
    normal: np.ndarray,
) -> None:
    """The pairs whose ``dist`` is still negative (not measured yet), by the segment-box closed
    form (:func:`segment_segment_pairs`)."""
    s = np.empty(SCRATCH)
    center = np.empty(3)
    half = np.zeros(3)
    rotation = np.empty((3, 3))
    x = np.empty(3)
    y = np.empty(3)
    for p in range(first.shape[0]):
        if dist[p] >= 0.0:
            continue
        i, j = first[p], second[p]
        length2 = 0.0
        for c in range(3):
            x[c] = b[j, c] - a[j, c]
            length2 += x[c] * x[c]
        length = np.sqrt(length2)
        if length > 0.0:
            for c in range(3):
                x[c] /= length
        else:
            x[0], x[1], x[2] = 1.0, 0.0, 0.0
        if abs(x[0]) < 0.9:  # y = x cross the helper axis (e_x, or e_y when x is near e_x)
            y[0], y[1], y[2] = 0.0, x[2], -x[1]
        else:
            y[0], y[1], y[2] = -x[2], 0.0, x[0]
        norm = np.sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2])
        for c in range(3):
            y[c] /= norm
            rotation[c, 0] = x[c]
            rotation[c, 1] = y[c]
            center[c] = 0.5 * (a[j, c] + b[j, c])
        rotation[0, 2] = x[1] * y[2] - x[2] * y[1]
        rotation[1, 2] = x[2] * y[0] - x[0] * y[2]
        rotation[2, 2] = x[0] * y[1] - x[1] * y[0]
        half[0] = 0.5 * length
        tp, dp = _pair(a[i], b[i], center, half, rotation, s, normal[p])
        t[p], dist[p] = tp, dp
        back = dp if dp > TOUCHING else 0.0
        along = 0.0
        for c in range(3):
            other = a[i, c] + tp * (b[i, c] - a[i, c]) - back * normal[p, c]
            along += (other - a[j, c]) * (b[j, c] - a[j, c])
        s_out[p] = _clamp(along / length2, 0.0, 1.0) if length2 > 0.0 else 0.0


@compiled(**_JIT)
def pair_rows(
    points: np.ndarray,
    axes: np.ndarray,
    a: np.ndarray,
    b: np.ndarray,
    link: np.ndarray,
    first: np.ndarray,
    second: np.ndarray,
    t: np.ndarray,
    s: np.ndarray,
    normal: np.ndarray,
    which: np.ndarray,
    rows: np.ndarray,
) -> None:
    """Rows n . (J_A - J_B) (k, n) of the capsule pairs ``which`` (k,) at one pose: A the point at
    fraction t along capsule ``first[p]`` (segment a-b, (C, 3) each), B at s along ``second[p]``,
    n the pair's normal (P, 3); column m of a point's Jacobian is w_m x (q - p_m) for the joints
    m <= the capsule's ``link`` (``points`` (n+1, 3), world ``axes`` (n, 3)), 0 after."""
    for r in range(which.shape[0]):
        pair_row(points, axes, a, b, link, first, second, t, s, normal, which[r], rows[r])


@compiled(**_JIT)
def pair_row(
    points: np.ndarray,
    axes: np.ndarray,
    a: np.ndarray,
    b: np.ndarray,
    link: np.ndarray,
    first: np.ndarray,
    second: np.ndarray,
    t: np.ndarray,
    s: np.ndarray,
    normal: np.ndarray,
    p: int,
    row: np.ndarray,
) -> None:
    """Pair p's row n . (J_A - J_B) into ``row`` (n,) (:func:`pair_rows`)."""
    i, j = first[p], second[p]
    la, lb = link[i], link[j]
    tp, sp = t[p], s[p]
    qa0, qa1, qa2 = (
        a[i, 0] + tp * (b[i, 0] - a[i, 0]),
        a[i, 1] + tp * (b[i, 1] - a[i, 1]),
        a[i, 2] + tp * (b[i, 2] - a[i, 2]),
    )
    qb0, qb1, qb2 = (
        a[j, 0] + sp * (b[j, 0] - a[j, 0]),
        a[j, 1] + sp * (b[j, 1] - a[j, 1]),
        a[j, 2] + sp * (b[j, 2] - a[j, 2]),
    )
    n0, n1, n2 = normal[p, 0], normal[p, 1], normal[p, 2]
    for m in range(axes.shape[0]):
        c0, c1, c2 = _pair_column(
            (axes[m, 0], axes[m, 1], axes[m, 2]),
            (points[m, 0], points[m, 1], points[m, 2]),
            (m <= la, m <= lb),
            (qa0, qa1, qa2),
            (qb0, qb1, qb2),
            joint_slides(axes, m),
        )
        row[m] = n0 * c0 + n1 * c1 + n2 * c2


@compiled(**_JIT)
def _pair_column(
    w: tuple[float, float, float],
    p: tuple[float, float, float],
    on: tuple[bool, bool],
    qa: tuple[float, float, float],
    qb: tuple[float, float, float],
    slides: bool,
) -> tuple[float, float, float]:
    """Joint m's column of J_A - J_B: w_m x (q_A - p_m) where joint m moves link A's point, less
    w_m x (q_B - p_m) where it moves B's (w_m for each where the joint ``slides``: prismatic).
    Numbers in and out (no small arrays, no array taken: their reference counts cost some 0.6 us
    a row; tuples of numbers, ``w_m``, ``p_m``, whether the joint moves A's and B's point, ``q_A``,
    ``q_B``, pass as the numbers do); :func:`pair_row` and :func:`pair_jacobians`."""
    w0, w1, w2 = w
    p0, p1, p2 = p
    on_a, on_b = on
    qa0, qa1, qa2 = qa
    qb0, qb1, qb2 = qb
    if slides:
        s0 = (w0 if on_a else 0.0) - (w0 if on_b else 0.0)
        s1 = (w1 if on_a else 0.0) - (w1 if on_b else 0.0)
        s2 = (w2 if on_a else 0.0) - (w2 if on_b else 0.0)
        return s0, s1, s2
    c0 = c1 = c2 = 0.0
    if on_a:
        l0, l1, l2 = qa0 - p0, qa1 - p1, qa2 - p2
        c0, c1, c2 = w1 * l2 - w2 * l1, w2 * l0 - w0 * l2, w0 * l1 - w1 * l0
    if on_b:
        l0, l1, l2 = qb0 - p0, qb1 - p1, qb2 - p2
        c0 -= w1 * l2 - w2 * l1
        c1 -= w2 * l0 - w0 * l2
        c2 -= w0 * l1 - w1 * l0
    return c0, c1, c2


@compiled(**_JIT)
def pair_jacobians(
    points: np.ndarray,
    axes: np.ndarray,
    a: np.ndarray,
    b: np.ndarray,
    link: np.ndarray,
    first: np.ndarray,
    second: np.ndarray,
    t: np.ndarray,
    s: np.ndarray,
    which: np.ndarray,
    jac: np.ndarray,
) -> None:
    """J_A - J_B (k, 3, n) of the capsule pairs ``which`` (k,) at one pose (the points and columns
    of :func:`pair_rows`, before the normal)."""
    for r in range(which.shape[0]):
        p = which[r]
        i, j = first[p], second[p]
        la, lb = link[i], link[j]
        tp, sp = t[p], s[p]
        qa0, qa1, qa2 = (
            a[i, 0] + tp * (b[i, 0] - a[i, 0]),
            a[i, 1] + tp * (b[i, 1] - a[i, 1]),
            a[i, 2] + tp * (b[i, 2] - a[i, 2]),
        )
        qb0, qb1, qb2 = (
            a[j, 0] + sp * (b[j, 0] - a[j, 0]),
            a[j, 1] + sp * (b[j, 1] - a[j, 1]),
            a[j, 2] + sp * (b[j, 2] - a[j, 2]),
        )
        for m in range(axes.shape[0]):
            jac[r, 0, m], jac[r, 1, m], jac[r, 2, m] = _pair_column(
                (axes[m, 0], axes[m, 1], axes[m, 2]),
                (points[m, 0], points[m, 1], points[m, 2]),
                (m <= la, m <= lb),
                (qa0, qa1, qa2),
                (qb0, qb1, qb2),
                joint_slides(axes, m),
            )


@compiled(**_JIT)
def link_twists(points: np.ndarray, axes: np.ndarray, x: np.ndarray, twists: np.ndarray) -> None:
    """Each link's twist under the joint rates ``x`` (n,) into ``twists`` (n, 6): link l's angular
    rate Omega_l = sum_{m <= l} x_m w_m and its linear term V_l = sum_{m <= l} x_m p_m x w_m
    (x_m w_m and no angular rate for a prismatic joint m, :func:`~armanim.arm.kernel.joint_slides`), so
    that a point q that link l carries moves at Omega_l x q + V_l (its Jacobian's columns
    w_m x (q - p_m) of :func:`pair_row`, summed against ``x``). O(n) once; a pair's rate then
    costs a few products (:func:`pair_rate`) where its row costs n cross products."""
    o0 = o1 = o2 = v0 = v1 = v2 = 0.0
    for m in range(axes.shape[0]):
        w0, w1, w2 = axes[m, 0], axes[m, 1], axes[m, 2]
        p0, p1, p2 = points[m, 0], points[m, 1], points[m, 2]
        xm = x[m]
        if joint_slides(axes, m):  # a prismatic joint: every point it carries moves at x_m w_m
            v0 += xm * w0
            v1 += xm * w1
            v2 += xm * w2
            twists[m, 0], twists[m, 1], twists[m, 2], twists[m, 3], twists[m, 4], twists[m, 5] = o0, o1, o2, v0, v1, v2
            continue
        o0 += xm * w0
        o1 += xm * w1
        o2 += xm * w2
        v0 += xm * (p1 * w2 - p2 * w1)
        v1 += xm * (p2 * w0 - p0 * w2)
        v2 += xm * (p0 * w1 - p1 * w0)
        twists[m, 0], twists[m, 1], twists[m, 2], twists[m, 3], twists[m, 4], twists[m, 5] = o0, o1, o2, v0, v1, v2


@compiled(**_JIT)
def pair_rate(
    twists: np.ndarray,
    a: np.ndarray,
    b: np.ndarray,
    link: np.ndarray,
    first: np.ndarray,
    second: np.ndarray,
    t: np.ndarray,
    s: np.ndarray,
    normal: np.ndarray,
    p: int,
) -> float:
    """Pair p's row times the joint rates whose links' twists are ``twists`` (:func:`link_twists`):
    n . (J_A - J_B) x = n . ((Omega_A x q_A + V_A) - (Omega_B x q_B + V_B)), the points and normal
    of :func:`pair_row`; equal to its row . x to rounding, without the row. A capsule on the
    base (carrier -1) moves at 0."""
    i, j = first[p], second[p]
    la, lb = link[i], link[j]
    tp, sp = t[p], s[p]
    qa0, qa1, qa2 = (
        a[i, 0] + tp * (b[i, 0] - a[i, 0]),
        a[i, 1] + tp * (b[i, 1] - a[i, 1]),
        a[i, 2] + tp * (b[i, 2] - a[i, 2]),
    )
    qb0, qb1, qb2 = (
        a[j, 0] + sp * (b[j, 0] - a[j, 0]),
        a[j, 1] + sp * (b[j, 1] - a[j, 1]),
        a[j, 2] + sp * (b[j, 2] - a[j, 2]),
    )
    va0 = va1 = va2 = 0.0  # a capsule on the base (carrier -1) never moves
    if la >= 0:
        va0 = twists[la, 1] * qa2 - twists[la, 2] * qa1 + twists[la, 3]
        va1 = twists[la, 2] * qa0 - twists[la, 0] * qa2 + twists[la, 4]
        va2 = twists[la, 0] * qa1 - twists[la, 1] * qa0 + twists[la, 5]
    vb0 = vb1 = vb2 = 0.0
    if lb >= 0:
        vb0 = twists[lb, 1] * qb2 - twists[lb, 2] * qb1 + twists[lb, 3]
        vb1 = twists[lb, 2] * qb0 - twists[lb, 0] * qb2 + twists[lb, 4]
        vb2 = twists[lb, 0] * qb1 - twists[lb, 1] * qb0 + twists[lb, 5]
    rate: float = normal[p, 0] * (va0 - vb0) + normal[p, 1] * (va1 - vb1) + normal[p, 2] * (va2 - vb2)
    return rate


@compiled(**_JIT)
def pair_rows_met(
    placed: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray],
    pairs: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray],
    lever_rows: np.ndarray,
    step: np.ndarray,
    bounds: tuple[float, float, float, float, float],
) -> bool:
    """Whether the step dPhi ``step`` (n,) meets every pair's row n . (J_A - J_B) dPhi >= -room.

    Parameters
    ----------
    placed : tuple of arrays
        The pose: joint points (n + 1, 3), world axes (n, 3), capsule ends a, b (C, 3) (metres),
        each capsule's ``link`` (C,) (as :func:`pair_rows` reads them).
    pairs : tuple of arrays
        The pairs: ``first``, ``second`` (P,), their gaps (P,) (metres), closest points' fractions
        t, s (P,) and normals (P, 3).
    lever_rows : (P, n) array
        Each pair's lever arms, metres.
    step : (n,) array
        dPhi, radians (metres for a prismatic joint).
    bounds : tuple of floats
        ``target``, ``gamma``, ``slack``, ``extra``, ``violation``: room = gamma (gap - target)
        (metres); a pair whose room is at least ``slack`` x its bound |dPhi| . ``lever_rows[p]``
        plus ``extra`` meets it by that bound alone; any other has its row (:func:`pair_rows`)
        computed and tested to ``violation``.
    """
    points, axes, a, b, link = placed
    first, second, gap, t, s, normal = pairs
    target, gamma, slack, extra, violation = bounds
    row = np.empty(step.shape[0])
    for p in range(gap.shape[0]):
        room = gamma * (gap[p] - target)
        bound = 0.0
        for m in range(step.shape[0]):
            bound += lever_rows[p, m] * abs(step[m])
        if room >= bound * slack + extra:
            continue
        pair_row(points, axes, a, b, link, first, second, t, s, normal, p, row)
        change = 0.0
        for m in range(step.shape[0]):
            change += row[m] * step[m]
        if change < -room - violation:
            return False
    return True
