"""The camera: world points to pixels, computed here instead of by a 3-D plot.

The camera is **orthographic** (parallel projection): sizes do not shrink with
distance, a sphere is an exact disc and a whole video's map is one affine matrix.
It looks at the scene from ``elevation`` degrees above the xy plane and from the
``azimuth`` direction (measured from +x toward +y), the angles matplotlib's
``view_init`` takes, so scene files keep their meaning:

- toward the viewer  w = (cos e cos a, cos e sin a, sin e),
- screen right       r = (-sin a, cos a, 0),
- screen up          u = w x r.

:func:`fit_view` then scales and shifts that rotation so the given points fill a
rectangle of the frame. Pure numpy: nothing is drawn here.
"""

from __future__ import annotations

import numpy as np

from armanim.arm.kinematics import Arm, forward
from armanim.render.camera.view import View

DEFAULT_ELEVATION = 25.0
DEFAULT_AZIMUTH = -60.0
PLANAR_TOL = 1e-9


def camera_rotation(elevation: float, azimuth: float) -> np.ndarray:
    """Rows: screen right, screen up and toward the viewer, as world unit vectors.

    Parameters
    ----------
    elevation, azimuth : float
        Degrees.

    Returns
    -------
    (3, 3) array
        An orthonormal, right-handed rotation (right x up = toward).

    Examples
    --------
    Looking from +x, level: y is to the right, z is up.

    >>> camera_rotation(0.0, 0.0).round(12) + 0.0
    array([[0., 1., 0.],
           [0., 0., 1.],
           [1., 0., 0.]])
    """
    e, a = np.radians(elevation), np.radians(azimuth)
    toward = np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])
    right = np.array([-np.sin(a), np.cos(a), 0.0])
    return np.stack([right, np.cross(toward, right), toward])


def fit_view(rotation: np.ndarray, points: np.ndarray, radii: np.ndarray, rect, size) -> View:
    """The view that fits discs around ``points`` into ``rect``, centred, same scale on x and y.

    Parameters
    ----------
    rotation : (3, 3) array
        From :func:`camera_rotation`.
    points : (P, 3) array
        World points that must be in the picture.
    radii : (P,) array
        World radius around each point (a sphere's radius, a link's half width).
    rect : (x0, y0, x1, y1)
        Pixel rectangle to fill (origin bottom left, y up).
    size : (int, int)
        Canvas width and height in pixels.

    Returns
    -------
    View
        Screen x, y in pixels and a depth (pixels, growing toward the viewer).

    Examples
    --------
    A unit cube seen from +x fills a 100 px square:

    >>> cube = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], float)
    >>> v = fit_view(camera_rotation(0, 0), cube, np.zeros(8), (0, 0, 100, 100), (100, 100))
    >>> v.project(np.array([[0.0, 0, 0], [0, 1, 1]])).round(6) + 0.0
    array([[  0.,   0.,   0.],
           [100., 100.,   0.]])
    """
    points = np.asarray(points, dtype=float).reshape(-1, 3)
    radii = np.broadcast_to(np.asarray(radii, dtype=float), (len(points),))
    screen = points @ rotation.T
    lo = (screen[:, :2] - radii[:, None]).min(axis=0)
    hi = (screen[:, :2] + radii[:, None]).max(axis=0)
    x0, y0, x1, y1 = (float(v) for v in rect)
    span = np.maximum(hi - lo, 1e-9)
    scale = min((x1 - x0) / span[0], (y1 - y0) / span[1])
    center_world = (lo + hi) / 2.0
    center_pixel = np.array([(x0 + x1) / 2.0, (y0 + y1) / 2.0])
    linear = scale * rotation
    offset = np.append(center_pixel - scale * center_world, 0.0)
    return View(np.column_stack([linear, offset]), int(size[0]), int(size[1]))


def planar_normal(arm: Arm) -> np.ndarray | None:
    """The unit normal of a planar arm's plane, or None if the arm is not planar.

    Planar: every joint axis is parallel (in the world, at home; rotations about
    parallel axes keep them parallel) and every link is perpendicular to them, so
    the links stay in one plane whatever the angles.

    Examples
    --------
    >>> planar_normal(Arm.from_names([1, 1], axes="zz", direction="x"))
    array([0., 0., 1.])
    >>> planar_normal(Arm.from_names([2, 5, 5, 5])) is None
    True
    """
    pose = forward(arm, np.zeros(arm.n))
    world_axes = np.einsum("nab,nb->na", pose.frames, arm.axes)
    n = world_axes[0] / np.linalg.norm(world_axes[0])
    if np.any(np.linalg.norm(np.cross(world_axes, n), axis=1) > PLANAR_TOL):
        return None
    links = np.einsum("nab,nb->na", pose.frames, arm.offsets)
    if np.any(np.abs(links @ n) > PLANAR_TOL * np.maximum(arm.links, 1.0)):
        return None
    return n + 0.0


def face_on_angles(normal: np.ndarray) -> tuple[float, float]:
    """Elevation and azimuth (degrees) of a camera looking straight at the plane of ``normal``.

    Of the two sides, the one seen from above (or, for an upright plane, the one
    nearer the default view) is chosen. Looking straight down, +x is to the right.

    >>> face_on_angles(np.array([0.0, 0, 1]))
    (90.0, -90.0)
    >>> face_on_angles(np.array([0.0, 1, 0]))
    (0.0, -90.0)
    """
    default = camera_rotation(DEFAULT_ELEVATION, DEFAULT_AZIMUTH)[2]
    n = np.asarray(normal, dtype=float)
    n = n if n @ default >= 0 else -n
    elevation = float(np.degrees(np.arcsin(np.clip(n[2], -1.0, 1.0)))) + 0.0
    if abs(n[2]) > 1 - 1e-9:
        return elevation, -90.0
    return elevation, float(np.degrees(np.arctan2(n[1], n[0])))


def view_angles(arm: Arm, elevation: float | None, azimuth: float | None) -> tuple[float, float]:
    """The camera angles to use: the given ones, else face-on for a planar arm, else the default.

    >>> view_angles(Arm.from_names([1, 1], axes="zz", direction="x"), None, None)
    (90.0, -90.0)
    >>> view_angles(Arm.from_names([1, 1], axes="zz", direction="x"), 10.0, None)
    (10.0, -60.0)
    """
    if elevation is None and azimuth is None:
        normal = planar_normal(arm)
        if normal is not None:
            return face_on_angles(normal)
    return (
        DEFAULT_ELEVATION if elevation is None else float(elevation),
        DEFAULT_AZIMUTH if azimuth is None else float(azimuth),
    )
