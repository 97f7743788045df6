"""Framing a scene: the floor under it and the camera view that makes it fill the frame.

Pure numpy: what must be in the picture (every joint the pictures show, or the
settings' bounds box; the base, the spheres, the goals and the floor) is fitted into
the frame's scene rectangle by :func:`armanim.render.camera.projection.fit_view`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from armanim.motion.problem import Problem
from armanim.render.camera.bounds import goal_points, path_points, resolve_bounds, shape_extent
from armanim.render.camera.projection import fit_view
from armanim.render.camera.view import View
from armanim.render.paint import scenery
from armanim.render.paint.style import BASE_SCALE, RING_POINTS
from armanim.render.settings import RenderSettings

MIN_FLOOR_ELEVATION = 5.0  # degrees: a floor seen more edge-on than this is not drawn


@dataclass(frozen=True)
class Floor:
    """A horizontal rectangle a little under the scene.

    Attributes
    ----------
    z : float
        Height, world units.
    lo, hi : (2,) arrays
        Opposite corners (x, y), world units.
    """

    z: float
    lo: np.ndarray
    hi: np.ndarray

    def quad(self) -> np.ndarray:
        """(4, 3) world corners, counter-clockwise seen from above."""
        lo, hi, z = self.lo, self.hi, self.z
        return np.array([[lo[0], lo[1], z], [hi[0], lo[1], z], [hi[0], hi[1], z], [lo[0], hi[1], z]])


@dataclass(frozen=True)
class Framing:
    """Where the camera puts the scene.

    Attributes
    ----------
    view : View
        World to screen.
    ppu : float
        Pixels per world unit.
    floor : Floor or None
        None when the camera is within ``MIN_FLOOR_ELEVATION`` degrees of level.
    """

    view: View
    ppu: float
    floor: Floor | None


def frame_scene(
    problem: Problem,
    settings: RenderSettings,
    extent: np.ndarray | None,
    rotation: np.ndarray,
    elevation: float,
    layout: scenery.Layout,
) -> Framing:
    """The floor (at the scene's ``floor`` when it has one), then the view that fits everything into ``layout.scene``.

    Parameters
    ----------
    problem : Problem
    settings : RenderSettings
        Its ``bounds``, if given, replace ``extent``.
    extent : (..., 3) array or None
        Every joint position the pictures show.
    rotation : (3, 3) array
        The camera's rotation (:func:`armanim.render.camera.projection.camera_rotation`).
    elevation : float
        The camera's elevation, degrees.
    layout : Layout
        The frame's layout.
    """
    points, radii = scene_content(problem, settings, extent)
    lo, hi = (points - radii[:, None]).min(axis=0), (points + radii[:, None]).max(axis=0)
    floor = None
    if elevation >= MIN_FLOOR_ELEVATION:
        given = problem.obstacles.floor
        z = scenery.floor_height(lo[2], float(np.max(hi - lo))) if given is None else float(given)
        floor = Floor(z, *scenery.floor_rect(lo[:2], hi[:2]))
        points, radii = np.vstack([points, floor.quad()]), np.concatenate([radii, np.zeros(4)])
    x0, y0, x1, y1 = layout.scene
    m = RING_POINTS / 2 * layout.dpi / 72.0  # room for the current goal's ring at the edges
    view = fit_view(rotation, points, radii, (x0 + m, y0 + m, x1 - m, y1 - m), (layout.width, layout.height))
    return Framing(view=view, ppu=float(view.pixels_per_unit.mean()), floor=floor)


def scene_content(
    problem: Problem, settings: RenderSettings, extent: np.ndarray | None
) -> tuple[np.ndarray, np.ndarray]:
    """World points (P, 3) that must be in the picture and a radius (P,) around each.

    The settings' bounds box if given, else every joint in ``extent`` (or, without it,
    the box the arm can reach); then the base, the spheres, the goals and their paths.
    """
    hw = max(problem.half_width, float(problem.capsules.radius.max(initial=0.0)))
    if settings.bounds is not None or extent is None:
        box = resolve_bounds(problem, settings, None)
        joints = np.array([[x, y, z] for x in box[0] for y in box[1] for z in box[2]])
    else:
        joints = np.asarray(extent, dtype=float).reshape(-1, 3)
    base = problem.arm.stand
    goals = np.vstack([goal_points(problem), path_points(problem)])
    obs = problem.obstacles
    r = BASE_SCALE * problem.half_width
    foot = base - [0.0, 0.0, 2 * problem.half_width] + r * np.array([[1.0, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0]])
    shapes, shape_radii = shape_extent(obs.boxes, obs.rods, obs.cylinders)
    points = np.vstack([joints, base, foot, obs.centers.reshape(-1, 3), shapes, goals])
    radii = np.concatenate(
        [np.full(len(joints), hw), [r], np.zeros(len(foot)), obs.radii, shape_radii, np.zeros(len(goals))]
    )
    return points, radii
