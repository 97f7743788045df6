"""The motion benchmark's own geometry, written apart from armanim's: the contract's chain
(forward kinematics), link capsules and their clearances to spheres, and coal's distances to
boxes, capsules and a floor. A start-up self-test checks it against armanim's (1e-9).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

DEFAULT_CLEARANCE = 0.05  # the oracle's clearance when armanim has no solver.clearance


AXES = np.eye(3)


AXIS_INDEX = {"x": 0, "y": 1, "z": 2}


@dataclass(frozen=True)
class Solids:
    """Boxes, capsule obstacles and a floor as the oracle knows them (issue 22): their
    distances to the arm's capsules are coal's (the FCL successor, GJK), not armanim's
    closed forms; the floor's is the capsule's lower end's height (the capsules the first
    joint carries are left out, as the contract says).

    Attributes
    ----------
    boxes : tuple of (center (3,), half (3,), rotation (3, 3))
    rods : tuple of (a (3,), b (3,), radius)
    floor : float or None
    """

    boxes: tuple = ()
    rods: tuple = ()
    floor: float | None = None

    def __len__(self) -> int:
        return len(self.boxes) + len(self.rods) + int(self.floor is not None)

    def coal_shapes(self) -> list:
        """(coal geometry, coal transform) of every box and capsule (built once per call site)."""
        import coal

        shapes = [
            (coal.Box(*(2 * np.asarray(h))), coal.Transform3s(np.asarray(r), np.asarray(c))) for c, h, r in self.boxes
        ]
        shapes += [coal_capsule(np.asarray(a), np.asarray(b), float(r)) for a, b, r in self.rods]
        return shapes


def coal_capsule(a: np.ndarray, b: np.ndarray, radius: float):
    """coal's capsule (its axis along its local z, centred) around the segment a-b."""
    import coal

    axis = b - a
    length = float(np.linalg.norm(axis))
    z = axis / length if length > 0 else np.array([0.0, 0.0, 1.0])
    x = np.cross(z, [1.0, 0, 0] if abs(z[0]) < 0.9 else [0, 1.0, 0])
    x /= np.linalg.norm(x)
    return coal.Capsule(radius, length), coal.Transform3s(np.stack([x, np.cross(z, x), z], axis=1), (a + b) / 2)


def solid_gaps(solids: Solids, a: np.ndarray, b: np.ndarray, radius: np.ndarray, first: np.ndarray) -> np.ndarray:
    """Clearances (..., k, s) of capsules with ends a, b (..., k, 3) and radii (k,) to the boxes,
    the capsule obstacles (coal, one call per pair) and the floor; ``first`` (k,) marks the
    capsules the floor leaves out (+inf)."""
    import coal

    batch = a.shape[:-1]
    flat_a, flat_b = a.reshape(-1, 3), b.reshape(-1, 3)
    k = len(radius)
    shapes = solids.coal_shapes()
    out = np.empty((len(flat_a), len(solids)))
    request = coal.DistanceRequest()
    request.gjk_tolerance = 1e-13
    for row, (p, q) in enumerate(zip(flat_a, flat_b)):
        r = float(radius[row % k])
        capsule, tf = (
            coal_capsule(p, q, r) if np.linalg.norm(q - p) > 0 else (coal.Sphere(r), coal.Transform3s(np.eye(3), p))
        )
        for col, (shape, placement) in enumerate(shapes):
            out[row, col] = coal.distance(shape, placement, capsule, tf, request, coal.DistanceResult())
        if solids.floor is not None:
            out[row, -1] = np.inf if first[row % k] else min(p[2], q[2]) - solids.floor - r
    return out.reshape(batch + (len(solids),))


NO_SOLIDS = Solids()


@dataclass(frozen=True)
class Geometry:
    """What the oracle knows of a scene, radians and scene units.

    Attributes
    ----------
    base : (3,) array
    links : (n,) array
    axes : tuple of str
        Joint axis names (x, y, z), each in its joint's own frame.
    direction : (3,) array
        Unit vector along which every link extends, in its joint's frame.
    half_width : float
    lower, upper : (n,) arrays
        Limits in radians, -inf / +inf for a free joint.
    centers : (m, 3) array
    radii : (m,) array
    home : (n,) array
    tolerance, clearance : float
    """

    base: np.ndarray
    links: np.ndarray
    axes: tuple
    direction: np.ndarray
    half_width: float
    lower: np.ndarray
    upper: np.ndarray
    centers: np.ndarray
    radii: np.ndarray
    home: np.ndarray
    tolerance: float = 0.01
    clearance: float = DEFAULT_CLEARANCE
    solids: Solids = NO_SOLIDS

    @property
    def reach(self) -> float:
        """Sum of the link lengths."""
        return float(self.links.sum())


def axis_rotation(axis: str, angle: np.ndarray) -> np.ndarray:
    """Rot(axis, angle) for a named coordinate axis, shape angle.shape + (3, 3)."""
    c, s = np.cos(angle), np.sin(angle)
    o, z = np.ones_like(c), np.zeros_like(c)
    rows = {
        "x": [[o, z, z], [z, c, -s], [z, s, c]],
        "y": [[c, z, s], [z, o, z], [-s, z, c]],
        "z": [[c, -s, z], [s, c, z], [z, z, o]],
    }[axis]
    return np.moveaxis(np.array(rows), (0, 1), (-2, -1))


def joint_points(geo: Geometry, phi: np.ndarray) -> np.ndarray:
    """The contract's chain, written independently of armanim: p_1 .. p_{n+1}, shape (..., n+1, 3).

    R_i = R_{i-1} Rot(axis_i, phi_i) with R_0 = I; p_1 = base; p_{i+1} = p_i + R_i (l_i d).
    """
    phi = np.asarray(phi, dtype=float)
    batch = phi.shape[:-1]
    rot = np.broadcast_to(np.eye(3), batch + (3, 3))
    points = [np.broadcast_to(geo.base, batch + (3,))]
    for i, axis in enumerate(geo.axes):
        rot = rot @ axis_rotation(axis, phi[..., i])
        points.append(points[-1] + rot @ (geo.links[i] * geo.direction))
    return np.stack(points, axis=-2)


def capsule_clearances(geo: Geometry, points: np.ndarray) -> np.ndarray:
    """Clearance of every link capsule to every sphere's surface, then to every solid (boxes,
    capsules, the floor), shape (..., n, m + s); negative inside."""
    a = points[..., :-1, None, :]
    ab = points[..., 1:, None, :] - a
    t = np.clip(((geo.centers - a) * ab).sum(-1) / np.maximum((ab * ab).sum(-1), 1e-300), 0.0, 1.0)
    gap = a + t[..., None] * ab - geo.centers
    spheres = np.sqrt((gap * gap).sum(-1)) - geo.radii - geo.half_width
    if not len(geo.solids):
        return spheres
    n = len(geo.links)
    first = np.arange(n) == 0
    solids = solid_gaps(geo.solids, points[..., :-1, :], points[..., 1:, :], np.full(n, geo.half_width), first)
    return np.concatenate([spheres, solids], axis=-1)


def has_obstacles(geo) -> bool:
    """Whether the oracle has anything to keep the arm from: spheres or solids."""
    return bool(len(geo.radii) or len(geo.solids))
