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

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import LineCollection, PolyCollection
from matplotlib.lines import Line2D
from matplotlib.text import Text
from matplotlib.transforms import IdentityTransform

from armanim.kinematics import Pose, forward
from armanim.problem import Problem, RenderSettings
from armanim.render import scenery
from armanim.render.bounds import resolve_bounds
from armanim.render.camera import camera_rotation, fit_view, view_angles
from armanim.render.caption import PENDING
from armanim.render.glyphs import GlyphAtlas
from armanim.render.markers import GoalMarkers
from armanim.render.order import paint_order
from armanim.render.pixels import make_figure, write_png
from armanim.render.solids import ArmSolids, Part, point_samples
from armanim.render.spheres import SphereDiscs
from armanim.render.style import (
    ARM_COLOR,
    AXIS_COLORS,
    BASE_SCALE,
    FACE_EDGE_PX,
    FLOOR_COLOR,
    FONT,
    GHOST_COLOR,
    GOAL_COLORS,
    GRID_COLOR,
    HIDDEN_ALPHA,
    OBSTACLE_COLOR,
    RING_POINTS,
    SHADOW_COLOR,
    TEXT_COLOR,
    TRAIL_COLOR,
)

MIN_FLOOR_ELEVATION = 5.0  # degrees: a floor seen more edge-on than this is not drawn
CAPTION_TEMPLATE = "t = 0000.00 s   goal 00 (of 0-00)   distance 000000.000   missed: blocked by obstacle"


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
        self.arm = ArmSolids(problem.arm, problem.half_width, self.view, self.ppu)
        self.spheres = SphereDiscs(problem.obstacles, self.view, self.ppu)
        self._prepare_trail(tips if settings.trail else None)
        self._make_artists()
        self._prepare_goals()
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

    def _prepare_goals(self) -> None:
        goals = np.array([g.position for g in self.problem.goals], dtype=float).reshape(-1, 3)
        screen = self.view.project(goals)
        self.goals = GoalMarkers(self.fig, screen, self.spheres.behind(screen), (self.width, self.height))

    def _prepare_trail(self, tips: np.ndarray | None) -> None:
        if tips is None or len(tips) == 0:
            self.trail_xy = np.zeros((0, 2))
            self.trail_front_xy = np.zeros((0, 2))
            return
        screen = self.view.project(np.asarray(tips, dtype=float))
        self.trail_xy = np.where(self.spheres.behind(screen)[:, None], np.nan, screen[:, :2])
        self.trail_front_xy = np.where(self.spheres.in_front(screen)[:, None], screen[:, :2], np.nan)

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
        lay = self.layout
        self.caption = own(Text(*lay.caption_xy, "", ha="left", va="top", fontsize=FONT["caption"],
                                family="DejaVu Sans Mono", color=TEXT_COLOR,
                                bbox=dict(boxstyle="round,pad=0.3", facecolor="white",
                                          edgecolor=(0.8, 0.8, 0.84), alpha=0.92)))

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
        gap = 0.45 * RING_POINTS / self.pt  # clear of the current goal's ring
        self.text_boxes.update(self.goals.place_labels(self.renderer, gap, list(self.text_boxes.values()),
                                                       self.layout.scene))
        self.background = self.canvas.copy_from_bbox(self.fig.bbox)
        self.scratch = self._scratch_canvas()
        self.glyphs = GlyphAtlas(self.scratch, FONT["caption"], TEXT_COLOR)

    def _scratch_canvas(self) -> FigureCanvasAgg:
        """A small canvas of the same dpi to draw sprites on (clearing the whole frame
        for each of hundreds of sprites was slow at large sizes)."""
        reach = RING_POINTS / self.pt + self.goals.largest_label(self.renderer)
        side = int(np.ceil(2 * reach + 3 * FONT["caption"] / self.pt)) + 8
        return make_figure(side, side, self.fig.dpi)[1]

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
        base_shadow = scenery.floor_circle(self.problem.arm.base, BASE_SCALE * self.problem.half_width * 1.1, z)
        shadows = [base_shadow] + [scenery.floor_circle(c, r, z) for c, r in
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
        shells = self.spheres.shells()
        if shells:
            self._draw_pixels(PolyCollection(shells, facecolors="none", edgecolors=[(*OBSTACLE_COLOR, 0.35)],
                                             linestyles=[(0, (4, 4))], linewidths=0.8))
        self.spheres.composite(np.asarray(self.canvas.buffer_rgba()), self.spheres.order)

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
        if self.goals.hidden.any():
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
        self.goals.draw(np.asarray(self.canvas.buffer_rgba()), state.goal_status, self.scratch)
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

    def _draw_solids(self, state: FrameState, shadow) -> bool:
        """The poster's faint poses, then the arm, each with the spheres it overlaps, in
        painter's order (so faint poses never cover the arm). Returns whether any sphere
        was redrawn."""
        touched = False
        for ghost in state.ghosts:
            touched |= self._draw_parts(self.arm.parts(ghost, ghost=True), None)
        return self._draw_parts(self.arm.parts(state.pose), shadow) or touched

    def _draw_parts(self, parts: list[Part], shadow) -> bool:
        """Parts and the spheres they (or ``shadow``'s box) overlap on screen, far first."""
        allpts = np.concatenate([p.samples[:, :2] for p in parts])
        reach = max(p.radius for p in parts)
        arm_box = np.concatenate([allpts.min(axis=0) - reach, allpts.max(axis=0) + reach])
        spheres = self.spheres.touched([arm_box, shadow])
        samples = [p.samples for p in parts] + [point_samples(self.spheres.centers[i]) for i in spheres]
        radii = [p.radius for p in parts] + [self.spheres.radii[i] for i in spheres]
        polys: list[np.ndarray] = []
        colors: list[np.ndarray] = []
        buffer = np.asarray(self.canvas.buffer_rgba())
        for k in paint_order(np.array(samples), np.array(radii)):
            if k < len(parts):
                polys.extend(parts[k].polygons)
                colors.append(parts[k].colors)
            else:  # a sphere's sprite covers what was painted before it
                self._flush(polys, colors)
                polys, colors = [], []
                self.spheres.composite(buffer, [spheres[k - len(parts)]])
        self._flush(polys, colors)
        return bool(len(spheres))

    def _flush(self, polys: list[np.ndarray], colors: list[np.ndarray]) -> None:
        if not polys:
            return
        color = np.concatenate(colors)
        self.solids.set_verts(polys)
        self.solids.set_facecolor(color)
        self.solids.set_edgecolor(color)
        self.solids.draw(self.renderer)



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
