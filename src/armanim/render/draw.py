"""Draw frames of an arm scene: a matplotlib Figure on the Agg canvas, no pyplot, no 3-D axes.

The scene is projected by armanim's own camera (:mod:`armanim.render.camera`, orthographic)
and drawn with 2-D artists in pixel coordinates. What never changes is drawn once and
kept as a pixel background: the floor (a light grid under the scene) with the soft
shadows of the spheres and the base, the obstacle spheres themselves (far first), their
influence shells, the world axes in a corner, the title and the legend. Each frame
restores that background and draws what moves, straight into the Agg buffer:

1. the arm's soft shadow on the floor, and the tip's trail (hidden where it runs
   behind a sphere);
2. the solid parts in painter's order (link prisms, joints, base, and the spheres the
   arm or its shadow overlaps on screen this frame; see :mod:`armanim.render.order`).
   Spheres are exact orthographic discs shaded per pixel once (sprites), then
   alpha-composited in their place in the order; the other spheres stay in the
   background, so a scene with a thousand obstacles costs little more per frame;
3. the trail again where it passes in front of a sphere;
4. the numbered goal markers (a goal behind a sphere is drawn through it, dimmed and
   open) and the caption.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import LineCollection, PolyCollection
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patheffects import withStroke
from matplotlib.text import Text
from matplotlib.transforms import Affine2D, IdentityTransform

from armanim.kinematics import Pose, forward
from armanim.problem import Problem, RenderSettings
from armanim.render import scenery
from armanim.render.bounds import resolve_bounds
from armanim.render.camera import camera_rotation, fit_view, view_angles
from armanim.render.caption import CURRENT, MISSED, PENDING, REACHED
from armanim.render.glyphs import GlyphAtlas
from armanim.render.mesh import perpendicular_basis, prism_faces, prism_local, prism_world
from armanim.render.order import paint_order
from armanim.render.view import LIGHT, lambert

BACKGROUND = (1.0, 1.0, 1.0)
FLOOR_COLOR = (0.955, 0.96, 0.97)
GRID_COLOR = (0.84, 0.85, 0.88)
SHADOW_COLOR = (0.25, 0.27, 0.32)
ARM_COLOR = (0.16, 0.42, 0.80)
JOINT_COLOR = (0.16, 0.17, 0.20)
JOINT_HIGHLIGHT = (0.55, 0.57, 0.62)
BASE_COLOR = (0.50, 0.52, 0.56)
OBSTACLE_COLOR = (0.85, 0.30, 0.25)
TRAIL_COLOR = (0.95, 0.55, 0.05)
TEXT_COLOR = (0.12, 0.12, 0.15)
AXIS_COLORS = ((0.80, 0.20, 0.20), (0.15, 0.60, 0.20), (0.20, 0.35, 0.85))
GOAL_COLORS = {
    "pending": (0.45, 0.47, 0.52),
    "current": (1.00, 0.76, 0.00),
    "reached": (0.13, 0.62, 0.28),
    "missed": (0.85, 0.10, 0.10),
}
STATUS_NAMES = ("pending", "current", "reached", "missed")

PRISM_SIDES = 10  # faces around a link
JOINT_SCALE = 1.45  # joint dot radius / link half width
BASE_SCALE = 3.0  # pedestal radius / link half width
SAMPLES = 7  # points per part for the painter's order
RING_POINTS = 27  # diameter of the ring around the current goal
FACE_EDGE_PX = 0.7  # faces are outlined in their own colour to close seams
GHOST_FADE = 0.7  # a poster's faint poses: the arm's colours this much toward white
GHOST_COLOR = tuple(np.array(ARM_COLOR) * (1 - GHOST_FADE) + GHOST_FADE)
HIDDEN_ALPHA = 0.55  # opacity of a goal marker seen through a sphere
MIN_FLOOR_ELEVATION = 5.0  # degrees: a floor seen more edge-on than this is not drawn
CAPTION_TEMPLATE = "t = 0000.00 s   goal 00 (of 0-00)   distance 000000.000   missed: blocked by obstacle"
FONT = {"title": 13, "caption": 10.5, "legend": 9, "goal": 9, "axis": 8}  # points


@dataclass(frozen=True)
class FrameState:
    """What one frame shows, beyond the static scene.

    Attributes
    ----------
    pose : Pose
        Joint points (n+1, 3) and frames (n, 3, 3) of a single pose.
    trail_end : int
        Number of trail points shown (the tips of frames 0 .. trail_end-1); 0 for none.
    goal_status : (N,) int array
        One of PENDING, CURRENT, REACHED, MISSED per goal.
    caption : str
        The dynamic caption line (time, goal, distance, state).
    ghosts : tuple of Pose
        Poses drawn faintly (a poster's strobe), in the same painter's order.
    """

    pose: Pose
    trail_end: int
    goal_status: np.ndarray
    caption: str
    ghosts: tuple = field(default=())


def make_figure(width: int, height: int, dpi: float) -> tuple[Figure, FigureCanvasAgg]:
    """A Figure whose Agg buffer is exactly ``width`` x ``height`` pixels.

    The inch sizes get a thousandth of a pixel extra so float rounding cannot lose a pixel.
    """
    fig = Figure(figsize=((width + 1e-3) / dpi, (height + 1e-3) / dpi), dpi=dpi, facecolor=BACKGROUND)
    return fig, FigureCanvasAgg(fig)


def with_alpha(rgb: np.ndarray, alpha: float) -> np.ndarray:
    """(..., 3) colours -> (..., 4) with a constant alpha."""
    rgb = np.atleast_2d(rgb)
    return np.concatenate([rgb, np.full(rgb.shape[:-1] + (1,), alpha)], axis=-1)


class SceneCanvas:
    """A scene drawn once, ready to draw frames fast.

    Parameters
    ----------
    problem : Problem
    settings : RenderSettings
        Size, view, bounds and trail.
    title : str
        Shown top left on every frame.
    tips : (F, 3) array, optional
        The tip of every frame, for the trail.
    extent : (..., 3) array, optional
        Every joint position the pictures will show: ``render.bounds: auto`` fits them.
    picture : {"video", "pose", "poster"}
        What is drawn: the legend lists only what it shows (a pose: no states, no
        path; a poster: final states, the path and the faint poses on each goal).
    caption_template : str
        The longest caption the frames will show: the caption's box is sized for it.
    outcomes : set of str
        The goal outcomes the pictures show (``"reached"``, ``"missed"``): only those are in
        the legend.
    """

    def __init__(self, problem: Problem, settings: RenderSettings, *, title: str,
                 tips: np.ndarray | None = None, extent: np.ndarray | None = None, picture: str = "video",
                 caption_template: str = CAPTION_TEMPLATE, outcomes: frozenset = frozenset({"reached", "missed"})):
        self.problem = problem
        self.settings = settings
        self.picture = picture
        self.outcomes = outcomes
        self.width, self.height = (int(v) for v in settings.size)
        self.layout = scenery.frame_layout(self.width, self.height)
        self.fig, self.canvas = make_figure(self.width, self.height, self.layout.dpi)
        self.pt = 72.0 / self.fig.dpi  # points per pixel
        self.renderer = self.canvas.get_renderer()
        self.elevation, self.azimuth = view_angles(problem.arm, settings.elevation, settings.azimuth)
        self.rotation = camera_rotation(self.elevation, self.azimuth)
        self._fit(extent)
        self.text_boxes: dict[str, tuple] = {}
        self._prepare_arm()
        self._prepare_obstacles()
        self._prepare_base()
        self._prepare_goals()
        self._prepare_trail(tips if settings.trail else None)
        self._make_artists()
        self._draw_background(title, caption_template)

    # ----- camera and floor ------------------------------------------------------------

    def _fit(self, extent: np.ndarray | None) -> None:
        """Floor height and footprint, then the view that makes everything fill the frame."""
        points, radii = self._content(extent)
        lo, hi = (points - radii[:, None]).min(axis=0), (points + radii[:, None]).max(axis=0)
        self.floor_z = scenery.floor_height(lo[2], float(np.max(hi - lo)))
        self.floor_lo, self.floor_hi = scenery.floor_rect(lo[:2], hi[:2])
        self.has_floor = self.elevation >= MIN_FLOOR_ELEVATION
        if self.has_floor:
            flo, fhi = self.floor_lo, self.floor_hi
            corners = np.array([[x, y, self.floor_z] for x in (flo[0], fhi[0]) for y in (flo[1], fhi[1])])
            points, radii = np.vstack([points, corners]), np.concatenate([radii, np.zeros(4)])
        x0, y0, x1, y1 = self.layout.scene
        m = RING_POINTS / 2 * self.layout.dpi / 72.0  # room for the current goal's ring at the edges
        self.view = fit_view(self.rotation, points, radii, (x0 + m, y0 + m, x1 - m, y1 - m), (self.width, self.height))
        self.ppu = float(self.view.pixels_per_unit.mean())

    def _content(self, extent: np.ndarray | None) -> tuple[np.ndarray, np.ndarray]:
        """World points that must be in the picture and a radius around each: the
        settings' bounds box if given, else every joint the pictures show (or, without
        them, the cube the arm can reach), the base, the spheres and the goals."""
        problem, hw = self.problem, self.problem.half_width
        if self.settings.bounds is not None or extent is None:
            box = resolve_bounds(problem, self.settings, None)
            joints = np.array([[x, y, z] for x in box[0] for y in box[1] for z in box[2]])
        else:
            joints = np.asarray(extent, dtype=float).reshape(-1, 3)
        base = problem.arm.base
        goals = np.array([g.position for g in problem.goals], dtype=float).reshape(-1, 3)
        obs = problem.obstacles
        points = np.vstack([joints, base, base - [0.0, 0.0, 2 * hw], obs.centers.reshape(-1, 3), goals])
        radii = np.concatenate([np.full(len(joints), hw), [BASE_SCALE * hw] * 2, obs.radii, np.zeros(len(goals))])
        return points, radii

    # ----- per-part preparation -------------------------------------------------------

    def _prepare_arm(self) -> None:
        arm, hw = self.problem.arm, self.problem.half_width
        self.prism_local = prism_local(arm, hw, PRISM_SIDES)
        self.faces = prism_faces(PRISM_SIDES)
        u, v = perpendicular_basis(arm.direction)
        mid = 2 * np.pi * (np.arange(PRISM_SIDES) + 1.0) / PRISM_SIDES
        side_normals = np.cos(mid)[:, None] * u + np.sin(mid)[:, None] * v
        self.face_normals_local = np.vstack([side_normals, -arm.direction, arm.direction])
        self.joint_radius = JOINT_SCALE * hw * self.ppu
        circle = np.linspace(0, 2 * np.pi, 24, endpoint=False)
        self.unit_circle = np.column_stack([np.cos(circle), np.sin(circle)])

    def _prepare_obstacles(self) -> None:
        obs = self.problem.obstacles
        self.sphere_centers = self.view.project(obs.centers) if len(obs) else np.zeros((0, 3))
        self.sphere_radii = obs.radii * self.ppu
        self.sprites = [self._sphere_sprite(c, r) for c, r in zip(self.sphere_centers, self.sphere_radii)]
        self.sphere_order = np.argsort(self.sphere_centers[:, 2], kind="stable")  # far first
        gap = np.linalg.norm(self.sphere_centers[:, None, :2] - self.sphere_centers[None, :, :2], axis=-1)
        self.sphere_overlap = gap < self.sphere_radii[:, None] + self.sphere_radii[None, :]
        np.fill_diagonal(self.sphere_overlap, False)

    def _sphere_sprite(self, center: np.ndarray, radius: float):
        """A sphere's disc shaded per pixel: (rows, cols, premultiplied RGB, 1 - alpha)."""
        x0 = max(int(np.floor(center[0] - radius - 1)), 0)
        x1 = min(int(np.ceil(center[0] + radius + 1)), self.width)
        y0 = max(int(np.floor(center[1] - radius - 1)), 0)
        y1 = min(int(np.ceil(center[1] + radius + 1)), self.height)
        if x1 <= x0 or y1 <= y0 or radius <= 0:
            return None
        ys = np.arange(y1 - 1, y0 - 1, -1) + 0.5  # buffer rows run top to bottom
        xs = np.arange(x0, x1) + 0.5
        dx, dy = np.meshgrid((xs - center[0]) / radius, (ys - center[1]) / radius)
        r2 = dx**2 + dy**2
        dz = np.sqrt(np.clip(1.0 - r2, 0.0, None))
        normal = np.stack([dx, dy, dz], axis=-1)
        diffuse = np.clip(normal @ LIGHT, 0.0, 1.0)
        half = LIGHT + np.array([0.0, 0.0, 1.0])
        spec = np.clip(normal @ (half / np.linalg.norm(half)), 0.0, 1.0) ** 40
        rgb = np.asarray(OBSTACLE_COLOR) * (0.32 + 0.68 * diffuse)[..., None] + 0.45 * spec[..., None]
        alpha = np.clip((1.0 - np.sqrt(r2)) * radius + 0.5, 0.0, 1.0)[..., None]
        rows = slice(self.height - y1, self.height - y0)
        cols = slice(x0, x1)
        return rows, cols, (np.clip(rgb, 0, 1) * 255 * alpha).astype(np.float32), (1.0 - alpha).astype(np.float32)

    def _prepare_base(self) -> None:
        """A pedestal under joint 1: a short vertical cylinder, static, culled once."""
        hw = self.problem.half_width
        radius, height = BASE_SCALE * hw, 2.0 * hw
        top = self.problem.arm.base
        theta = np.linspace(0, 2 * np.pi, 24, endpoint=False)
        ring = radius * np.column_stack([np.cos(theta), np.sin(theta), np.zeros_like(theta)])
        upper, lower = top + ring, top + ring - [0, 0, height]
        polys = [np.array([lower[i], lower[(i + 1) % 24], upper[(i + 1) % 24], upper[i]]) for i in range(24)]
        normals = [[np.cos(t + np.pi / 24), np.sin(t + np.pi / 24), 0.0] for t in theta]
        polys += [upper, lower[::-1]]
        normals += [[0, 0, 1.0], [0, 0, -1.0]]
        screen_n = self.view.screen_normals(np.array(normals))
        front = screen_n[:, 2] > 0
        self.base_polys = [self.view.project(p)[:, :2] for p, f in zip(polys, front) if f]
        self.base_colors = with_alpha(lambert(screen_n[front], BASE_COLOR), 1.0)
        ends = self.view.project(np.array([top - [0, 0, height], top]))
        self.base_samples = ends[0] + np.linspace(0, 1, SAMPLES)[:, None] * (ends[1] - ends[0])
        self.base_radius = radius * self.ppu
        self.base_shadow = scenery.floor_circle(top, radius * 1.1, self.floor_z)

    def _prepare_goals(self) -> None:
        goals = np.array([g.position for g in self.problem.goals], dtype=float).reshape(-1, 3)
        screen = self.view.project(goals)
        self.goal_xy = screen[:, :2]
        self.goal_hidden = self._behind_spheres(screen)

    def _prepare_trail(self, tips: np.ndarray | None) -> None:
        if tips is None or len(tips) == 0:
            self.trail_xy = np.zeros((0, 2))
            self.trail_front_xy = np.zeros((0, 2))
            return
        screen = self.view.project(np.asarray(tips, dtype=float))
        self.trail_xy = np.where(self._behind_spheres(screen)[:, None], np.nan, screen[:, :2])
        self.trail_front_xy = np.where(self._over_spheres(screen)[:, None], screen[:, :2], np.nan)

    def _on_discs(self, screen: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(P, m) masks: point inside a sphere's disc, and nearer than its centre."""
        gap = np.linalg.norm(screen[:, None, :2] - self.sphere_centers[None, :, :2], axis=-1)
        inside = gap < self.sphere_radii[None, :]
        nearer = screen[:, None, 2] > self.sphere_centers[None, :, 2]
        return inside, nearer

    def _behind_spheres(self, screen: np.ndarray) -> np.ndarray:
        inside, nearer = self._on_discs(screen)
        return np.any(inside & ~nearer, axis=1)

    def _over_spheres(self, screen: np.ndarray) -> np.ndarray:
        inside, nearer = self._on_discs(screen)
        return np.any(inside & nearer, axis=1)

    def _make_artists(self) -> None:
        ident = IdentityTransform()

        def own(artist):
            artist.set_figure(self.fig)
            artist.set_transform(ident)
            return artist

        self.solids = own(PolyCollection([], linewidths=FACE_EDGE_PX * self.pt, antialiased=True))
        self.solids.set_offset_transform(ident)
        self.shadow = own(LineCollection([], color=SHADOW_COLOR, capstyle="round"))
        self.trail = own(Line2D([], [], color=TRAIL_COLOR, linewidth=2.0, solid_capstyle="round", alpha=0.95))
        self.trail_front = own(Line2D([], [], color=TRAIL_COLOR, linewidth=2.0, alpha=0.95))
        style = {
            PENDING: dict(marker="o", markersize=9, markerfacecolor="white",
                          markeredgecolor=GOAL_COLORS["pending"], markeredgewidth=1.8),
            CURRENT: dict(marker="*", markersize=19, markerfacecolor=GOAL_COLORS["current"],
                          markeredgecolor=(0.2, 0.15, 0.0), markeredgewidth=0.9),
            REACHED: dict(marker="o", markersize=10, markerfacecolor=GOAL_COLORS["reached"],
                          markeredgecolor="white", markeredgewidth=1.2),
            MISSED: dict(marker="X", markersize=12, markerfacecolor=GOAL_COLORS["missed"],
                         markeredgecolor="white", markeredgewidth=1.0),
        }
        self.goal_marks = {k: own(Line2D([], [], linestyle="none", **s)) for k, s in style.items()}
        self.hidden_marks = {k: own(Line2D([], [], linestyle="none", alpha=HIDDEN_ALPHA,
                                           **{**s, "markerfacecolor": "none",
                                              "markeredgecolor": s["markerfacecolor"] if k != PENDING
                                              else s["markeredgecolor"]}))
                             for k, s in style.items()}
        self.goal_ring = own(Line2D([], [], linestyle="none", marker="o", markersize=RING_POINTS, markerfacecolor="none",
                                    markeredgecolor=GOAL_COLORS["current"], markeredgewidth=1.8, alpha=0.8))
        lay = self.layout
        self.caption = own(Text(*lay.caption_xy, "", ha="left", va="top", fontsize=FONT["caption"],
                                family="DejaVu Sans Mono", color=TEXT_COLOR,
                                bbox=dict(boxstyle="round,pad=0.3", facecolor="white",
                                          edgecolor=(0.8, 0.8, 0.84), alpha=0.92)))
        self.goal_labels = [own(Text(0, 0, str(i), ha="left", va="bottom", fontsize=FONT["goal"], fontweight="bold",
                                     path_effects=[withStroke(linewidth=2.5, foreground="white")]))
                            for i in range(len(self.goal_xy))]

    # ----- the background, drawn once -------------------------------------------------

    def _draw_background(self, title: str, caption_template: str) -> None:
        r = self.renderer
        r.clear()
        self.fig.draw(r)  # the white figure
        if self.has_floor:
            self._draw_floor()
        self._draw_static_spheres()
        self._draw_gizmo()
        lay = self.layout
        heading = Text(*lay.title_xy, title, ha="left", va="top", fontsize=FONT["title"], fontweight="bold",
                       color=TEXT_COLOR)
        self._draw_text("title", heading)
        self._draw_legend()
        self._draw_caption_box(caption_template)
        self._place_goal_labels()
        self.background = self.canvas.copy_from_bbox(self.fig.bbox)
        self.scratch = self._scratch_canvas()
        self.glyphs = GlyphAtlas(self.scratch, FONT["caption"], TEXT_COLOR)
        self.goal_stamps: dict[tuple[int, int], tuple | None] = {}  # (goal, state) -> sprite, made when first shown

    def _scratch_canvas(self) -> FigureCanvasAgg:
        """A small canvas of the same dpi to draw sprites on (clearing the whole frame
        for each of hundreds of sprites was slow at large sizes)."""
        label = max((lab.get_window_extent(self.renderer) for lab in self.goal_labels),
                    key=lambda box: box.width, default=None)
        extent = RING_POINTS / self.pt + (max(label.width, label.height) if label is not None else 0.0)
        side = int(np.ceil(2 * extent + 3 * FONT["caption"] / self.pt)) + 8
        return make_figure(side, side, self.fig.dpi)[1]

    def _goal_stamp(self, i: int, code: int):
        """Goal ``i``'s marker and number in one state as a sprite, drawn the first time it is asked for."""
        key = (int(i), int(code))
        if key not in self.goal_stamps:
            self.goal_stamps[key] = self._stamp_goal(self.scratch, *key)
        return self.goal_stamps[key]

    def _stamp_goal(self, scratch: FigureCanvasAgg, i: int, code: int):
        """Goal ``i``'s marker and number in one state, drawn into a sprite on the
        ``scratch`` canvas (drawing markers and text every frame was a third of a frame's time)."""
        hidden, xy = bool(self.goal_hidden[i]), self.goal_xy[i]
        label = self.goal_labels[i]
        label.set_color(GOAL_COLORS[STATUS_NAMES[code]] if code != PENDING else TEXT_COLOR)
        label.set_alpha(1.0)  # the number stays readable; only the marker of a hidden goal is dimmed
        artists = [(self.hidden_marks if hidden else self.goal_marks)[code], label]
        if code == CURRENT and not hidden:
            artists.insert(0, self.goal_ring)
        side = int(scratch.figure.bbox.width)
        x0, y0 = int(np.floor(xy[0])) - side // 2, int(np.floor(xy[1])) - side // 2
        shift = Affine2D().translate(-x0, -y0)
        renderer = scratch.get_renderer()
        renderer.clear()
        for artist in artists:
            if isinstance(artist, Line2D):
                artist.set_data([xy[0]], [xy[1]])
            artist.set_transform(shift)
            artist.draw(renderer)
            artist.set_transform(IdentityTransform())
        drawn = np.asarray(scratch.buffer_rgba())  # rows top to bottom
        used_rows = np.flatnonzero(drawn[..., 3].any(axis=1))
        used_cols = np.flatnonzero(drawn[..., 3].any(axis=0))
        if not len(used_rows):
            return None
        top = self.height - (y0 + side)  # the scratch's first row, in frame rows
        rows = slice(max(top + used_rows[0], 0), min(top + used_rows[-1] + 1, self.height))
        cols = slice(max(x0 + used_cols[0], 0), min(x0 + used_cols[-1] + 1, self.width))
        if cols.stop <= cols.start or rows.stop <= rows.start:
            return None
        patch = drawn[rows.start - top : rows.stop - top, cols.start - x0 : cols.stop - x0].astype(np.float32)
        alpha = patch[..., 3:] / 255.0
        return rows, cols, patch[..., :3] * alpha, 1.0 - alpha

    def _draw_text(self, name: str, text: Text) -> None:
        text.set_figure(self.fig)
        text.set_transform(IdentityTransform())
        text.draw(self.renderer)
        box = text.get_window_extent(self.renderer)
        if text.get_bbox_patch() is not None:
            box = text.get_bbox_patch().get_window_extent(self.renderer)
        self.text_boxes[name] = tuple(box.extents)

    def _draw_floor(self) -> None:
        lo, hi, z = self.floor_lo, self.floor_hi, self.floor_z
        quad = np.array([[lo[0], lo[1], z], [hi[0], lo[1], z], [hi[0], hi[1], z], [lo[0], hi[1], z]])
        floor = PolyCollection([self.view.project(quad)[:, :2]], facecolors=[FLOOR_COLOR], edgecolors="none")
        grid = LineCollection(self.view.project(scenery.floor_grid(lo, hi, z))[..., :2], colors=[GRID_COLOR],
                              linewidths=0.6)
        shadows = [self.base_shadow] + [scenery.floor_circle(c, r, z) for c, r in
                                        zip(self.problem.obstacles.centers, self.problem.obstacles.radii)]
        soft = []
        for scale, alpha in ((1.12, 0.05), (1.0, 0.06), (0.85, 0.07)):
            for ring in shadows:
                center = ring.mean(axis=0)
                soft.append((self.view.project(center + scale * (ring - center))[:, :2], alpha))
        shade = PolyCollection([p for p, _ in soft], facecolors=[(*SHADOW_COLOR, a) for _, a in soft],
                               edgecolors="none")
        for artist in (floor, grid, shade):
            self._draw_pixels(artist)

    def _draw_pixels(self, artist) -> None:
        artist.set_figure(self.fig)
        artist.set_transform(IdentityTransform())
        if hasattr(artist, "set_offset_transform"):
            artist.set_offset_transform(IdentityTransform())
        artist.draw(self.renderer)

    def _draw_static_spheres(self) -> None:
        """Every sphere into the background, far first, with its influence shell behind it."""
        obs = self.problem.obstacles
        shells = [self.sphere_centers[i, :2] + (obs.radii[i] + obs.influence[i]) * self.ppu * self.unit_circle
                  for i in range(len(obs)) if obs.influence[i] > 0]
        if shells:
            self._draw_pixels(PolyCollection(shells, facecolors="none", edgecolors=[(*OBSTACLE_COLOR, 0.35)],
                                             linestyles=[(0, (4, 4))], linewidths=0.8))
        buffer = np.asarray(self.canvas.buffer_rgba())
        for i in self.sphere_order:
            self._composite(buffer, self.sprites[i])

    def _draw_gizmo(self) -> None:
        """Small world axes top right: x, y and z as the camera sees them."""
        lay = self.layout
        origin = np.array(lay.gizmo_xy)
        directions = self.rotation[:2].T  # rows: world x, y, z on screen
        for axis, (d, color) in enumerate(zip(directions, AXIS_COLORS)):
            tip = origin + lay.gizmo_len * d
            self._draw_pixels(Line2D([origin[0], tip[0]], [origin[1], tip[1]], color=color, linewidth=1.6,
                                     solid_capstyle="round"))
            length = np.linalg.norm(d)
            if length > 0.3:
                place = origin + lay.gizmo_len * d * 1.45
            else:  # an axis along the line of sight: a dot, labelled beside it
                self._draw_pixels(Line2D([origin[0]], [origin[1]], marker="o", markersize=5, markerfacecolor="none",
                                         markeredgecolor=color, markeredgewidth=1.4))
                place = origin - 0.5 * lay.gizmo_len
            label = Text(*place, "xyz"[axis], ha="center", va="center", fontsize=FONT["axis"], color=color,
                         fontweight="bold")
            self._draw_text(f"axis {'xyz'[axis]}", label)

    def _legend_entries(self) -> tuple[list, list]:
        marker = dict(linestyle="none", markersize=8)
        entries = [("arm", Line2D([], [], color=ARM_COLOR, linewidth=5))]
        if self.picture == "poster":
            entries.append(("arm on each goal", Line2D([], [], color=GHOST_COLOR, linewidth=5)))
        if self.settings.trail and self.picture != "pose":
            entries.append(("tip path", Line2D([], [], color=TRAIL_COLOR, linewidth=2)))
        if len(self.problem.obstacles):
            entries.append(("obstacle", Line2D([], [], marker="o", markerfacecolor=OBSTACLE_COLOR,
                                               markeredgecolor="none", **marker)))
        pending = Line2D([], [], marker="o", markerfacecolor="white", markeredgecolor=GOAL_COLORS["pending"],
                         markeredgewidth=1.5, **marker)
        if self.picture == "pose":
            entries.append(("goal", pending))
        else:
            if self.picture == "video":
                entries += [
                    ("current goal", Line2D([], [], marker="*", markerfacecolor=GOAL_COLORS["current"],
                                            markeredgecolor="k", markeredgewidth=0.6, **{**marker, "markersize": 12})),
                    ("next goal", pending),
                ]
            outcomes = [
                ("reached", Line2D([], [], marker="o", markerfacecolor=GOAL_COLORS["reached"],
                                   markeredgecolor="white", **marker)),
                ("missed", Line2D([], [], marker="X", markerfacecolor=GOAL_COLORS["missed"],
                                  markeredgecolor="white", **marker)),
            ]
            entries += [entry for entry in outcomes if entry[0] in self.outcomes]
        if self.goal_hidden.any():
            entries.append(("behind a sphere", Line2D([], [], marker="o", markerfacecolor="none", alpha=HIDDEN_ALPHA,
                                                      markeredgecolor=GOAL_COLORS["pending"], **marker)))
        return [h for _, h in entries], [label for label, _ in entries]

    def _draw_legend(self) -> None:
        handles, labels = self._legend_entries()
        y = self.layout.legend_y / self.height
        legend = self.fig.legend(handles, labels, loc="center", bbox_to_anchor=(0.5, y), ncols=len(labels),
                                 frameon=False, fontsize=FONT["legend"], handlelength=1.5, columnspacing=1.1,
                                 handletextpad=0.6, borderaxespad=0.0)
        legend.draw(self.renderer)
        for i, text in enumerate(legend.get_texts()):
            self.text_boxes[f"legend {i}"] = tuple(text.get_window_extent(self.renderer).extents)

    def _place_goal_labels(self) -> None:
        """Goal numbers beside their markers, clear of each other and of every other text."""
        if not len(self.goal_labels):
            return
        sizes = []
        for label in self.goal_labels:
            box = label.get_window_extent(self.renderer)
            sizes.append((box.width, box.height))
        keep_out = list(self.text_boxes.values())
        gap = 0.45 * RING_POINTS / self.pt  # clear of the current goal's ring
        corners = scenery.place_labels(self.goal_xy, np.array(sizes), gap, keep_out, self.layout.scene)
        for label, (x, y), (w, h) in zip(self.goal_labels, corners, sizes):
            label.set_position((x, y))
            self.text_boxes[f"goal {label.get_text()}"] = (x, y, x + w, y + h)

    def _draw_caption_box(self, template: str) -> None:
        """The caption's box, sized for ``template``; its text is stamped every frame."""
        self.caption.set_text(template)
        self.caption.set_color((0.0, 0.0, 0.0, 0.0))
        self.caption.draw(self.renderer)
        self.text_boxes["caption"] = tuple(self.caption.get_bbox_patch().get_window_extent(self.renderer).extents)

    # ----- per frame ------------------------------------------------------------------

    def draw(self, state: FrameState) -> np.ndarray:
        """Draw one frame and return the canvas buffer.

        Parameters
        ----------
        state : FrameState

        Returns
        -------
        (height, width, 4) uint8 array
            RGBA, rows top to bottom. It is the live Agg buffer: consume it (encode
            or copy) before the next call.
        """
        self.canvas.restore_region(self.background)
        renderer = self.renderer
        shadow = self._draw_shadow(state.pose)
        if state.trail_end > 1:
            self.trail.set_data(self.trail_xy[: state.trail_end].T)
            self.trail.draw(renderer)
        touched = self._draw_solids(state, shadow)
        if state.trail_end > 1 and touched:
            self.trail_front.set_data(self.trail_front_xy[: state.trail_end].T)
            self.trail_front.draw(renderer)
        self._draw_goals(state.goal_status)
        self.glyphs.stamp(np.asarray(self.canvas.buffer_rgba()), state.caption, *self.layout.caption_xy)
        return np.asarray(self.canvas.buffer_rgba())

    def _draw_shadow(self, pose: Pose) -> np.ndarray | None:
        """The arm's soft shadow on the floor; returns its screen box (x0, y0, x1, y1)."""
        if not self.has_floor:
            return None
        drop = self.view.project(scenery.on_floor(pose.points, self.floor_z))[:, :2]
        segments = np.stack([drop[:-1], drop[1:]], axis=1)
        width = 2 * self.problem.half_width * self.ppu * self.pt
        self.shadow.set_segments(segments)
        for scale, alpha in ((1.7, 0.06), (1.0, 0.10)):
            self.shadow.set_linewidth(width * scale)
            self.shadow.set_alpha(alpha)
            self.shadow.draw(self.renderer)
        pad = width / self.pt
        return np.concatenate([drop.min(axis=0) - pad, drop.max(axis=0) + pad])

    def _spheres_touched(self, boxes: list) -> np.ndarray:
        """Indices of the spheres whose discs meet any of ``boxes`` (and the spheres in
        front of those, which must be redrawn over them), far first."""
        m = len(self.sphere_radii)
        if not m:
            return np.zeros(0, dtype=int)
        hit = np.zeros(m, dtype=bool)
        c, r = self.sphere_centers, self.sphere_radii
        for b in boxes:
            if b is not None:
                hit |= (c[:, 0] + r >= b[0]) & (c[:, 0] - r <= b[2]) & (c[:, 1] + r >= b[1]) & (c[:, 1] - r <= b[3])
        while True:
            nearer = (self.sphere_overlap[hit].any(axis=0)) & ~hit
            nearer &= c[:, 2] > c[hit, 2].min() if hit.any() else False
            if not nearer.any():
                break
            hit |= nearer
        return self.sphere_order[hit[self.sphere_order]]

    def _draw_solids(self, state: FrameState, shadow) -> bool:
        """The poster's faint poses, then the arm, each with the spheres it overlaps, in
        painter's order (so faint poses never cover the arm). Returns whether any sphere
        was redrawn."""
        touched = False
        for ghost in state.ghosts:
            touched |= self._draw_parts(self._arm_parts(ghost, ghost=True), None)
        return self._draw_parts(self._arm_parts(state.pose), shadow) or touched

    def _draw_parts(self, parts: list, shadow) -> bool:
        """Parts and the spheres they (or ``shadow``'s box) overlap on screen, far first."""
        allpts = np.concatenate([p[0][:, :2] for p in parts])
        widest = max(p[1] for p in parts)
        arm_box = np.concatenate([allpts.min(axis=0) - widest, allpts.max(axis=0) + widest])
        spheres = self._spheres_touched([arm_box, shadow])
        samples = [p[0] for p in parts] + [np.repeat(self.sphere_centers[i][None, :], SAMPLES, axis=0)
                                           for i in spheres]
        radii = [p[1] for p in parts] + [self.sphere_radii[i] for i in spheres]
        kinds = [p[2] for p in parts] + [("sphere", i) for i in spheres]
        order = paint_order(np.array(samples), np.array(radii))
        polys: list[np.ndarray] = []
        colors: list[np.ndarray] = []
        buffer = np.asarray(self.canvas.buffer_rgba())
        for k in order:
            kind = kinds[k]
            if kind[0] == "sphere":
                self._flush(polys, colors)
                polys, colors = [], []
                self._composite(buffer, self.sprites[kind[1]])
            else:
                polys.extend(kind[1])
                colors.append(kind[2])
        self._flush(polys, colors)
        return bool(len(spheres))

    def _arm_parts(self, pose: Pose, ghost: bool = False) -> list[tuple[np.ndarray, float, tuple]]:
        """Screen samples, radius and (polygons, RGBA colours) of the base, every link and every joint;
        a ghost (a poster's faint pose) has no base and its colours faded toward white."""
        fade = (lambda rgb: with_alpha(rgb * (1 - GHOST_FADE) + GHOST_FADE, 1.0)) if ghost else \
            (lambda rgb: with_alpha(rgb, 1.0))
        view = self.view
        verts = view.project(prism_world(pose, self.prism_local))  # (n, V, 3)
        normals = view.screen_normals(np.einsum("nab,fb->nfa", pose.frames, self.face_normals_local))
        joints = view.project(pose.points)  # (n+1, 3)
        t = np.linspace(0.0, 1.0, SAMPLES)[:, None]
        parts = []
        if not ghost:
            parts.append((self.base_samples, self.base_radius, ("solid", self.base_polys, self.base_colors)))
        link_radius = self.problem.half_width * self.ppu
        for i in range(len(verts)):
            front = np.flatnonzero(normals[i, :, 2] > 1e-9)
            polys = [verts[i, self.faces[f], :2] for f in front]
            shade = fade(lambert(normals[i, front], ARM_COLOR))
            samples = joints[i] + t * (joints[i + 1] - joints[i])
            parts.append((samples, link_radius, ("solid", polys, shade)))
        r = self.joint_radius
        joint_shade = fade(np.array([JOINT_COLOR, JOINT_HIGHLIGHT]))
        for i in range(len(verts)):
            center = joints[i]
            disc = center[:2] + r * self.unit_circle
            glint = center[:2] + 0.45 * r * self.unit_circle + 0.25 * r * LIGHT[:2]
            parts.append((np.repeat(center[None, :], SAMPLES, axis=0), r, ("solid", [disc, glint], joint_shade)))
        return parts

    def _flush(self, polys: list[np.ndarray], colors: list[np.ndarray]) -> None:
        if not polys:
            return
        color = np.concatenate(colors)
        self.solids.set_verts(polys)
        self.solids.set_facecolor(color)
        self.solids.set_edgecolor(color)
        self.solids.draw(self.renderer)

    @staticmethod
    def _composite(buffer: np.ndarray, sprite) -> None:
        if sprite is None:
            return
        rows, cols, premultiplied, transparency = sprite
        region = buffer[rows, cols, :3]
        region[...] = (region * transparency + premultiplied + 0.5).astype(np.uint8)

    def _draw_goals(self, status: np.ndarray) -> None:
        """Every goal: its marker (open and dimmed behind a sphere) and its number, pending goals first."""
        buffer = np.asarray(self.canvas.buffer_rgba())
        for i in np.argsort(status == CURRENT, kind="stable"):
            self._composite(buffer, self._goal_stamp(i, status[i]))


def pose_caption(problem: Problem, phi: np.ndarray) -> str:
    """Caption of a single pose: its joint angles in degrees and its tip."""
    tip = forward(problem.arm, phi).tip
    angles = ", ".join(f"{a:.1f}" for a in np.degrees(phi))
    return f"phi = [{angles}] deg   tip = ({tip[0]:.3f}, {tip[1]:.3f}, {tip[2]:.3f})"


def render_pose_png(problem: Problem, phi: np.ndarray, settings: RenderSettings, path, *, title: str) -> None:
    """Draw one pose of the arm to a PNG of ``settings.size`` pixels.

    Parameters
    ----------
    problem : Problem
        The arm, its obstacles and goals (all goals drawn as pending).
    phi : (n,) array
        Joint angles, radians.
    settings : RenderSettings
        Size, view and bounds (``trail``, ``fps`` and ``format`` are not used).
    path : str or Path
        The PNG to write; written to a temporary file beside it, then moved in place.
    title : str
        Shown top left.
    """
    phi = np.asarray(phi, dtype=float)
    pose = forward(problem.arm, phi)
    caption = pose_caption(problem, phi)
    scene = SceneCanvas(problem, settings, title=title, extent=pose.points, picture="pose", caption_template=caption)
    state = FrameState(pose=pose, trail_end=0, goal_status=np.full(len(problem.goals), PENDING), caption=caption)
    write_png(scene.draw(state), path)


def goal_outcomes(reports) -> frozenset:
    """The outcomes among a run's goal reports: ``{"reached"}``, ``{"missed"}`` or both.

    >>> from types import SimpleNamespace
    >>> sorted(goal_outcomes([SimpleNamespace(reached=True), SimpleNamespace(reached=False)]))
    ['missed', 'reached']
    """
    return frozenset("reached" if r.reached else "missed" for r in reports)


def write_png(rgba: np.ndarray, path) -> None:
    """Write an (H, W, 4) uint8 image to a PNG atomically (temporary file, then replace);
    a write failure is an OutputError (exit 3)."""
    from matplotlib.image import imsave

    from armanim.output.atomic import temporary_beside

    with temporary_beside(Path(path)) as tmp:
        imsave(tmp, np.ascontiguousarray(rgba), format="png")
