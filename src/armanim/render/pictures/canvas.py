"""Draw frames of an arm scene: a matplotlib Figure on the Agg canvas, no pyplot, no 3-D axes.

The scene is projected by armanim's own camera (:mod:`armanim.render.camera.projection`, orthographic;
:mod:`armanim.render.camera.framing` fits it into the frame) and drawn with 2-D artists in pixel
coordinates. What never changes is drawn once and kept as a pixel background
(:mod:`armanim.render.pictures.backdrop`): the floor (a light grid under the scene, at the scene's
``floor`` when it has one) with the soft shadows of the obstacles and the base, the obstacles
themselves (far first: sphere sprites, boxes, capsules and cylinders as shaded solids,
:mod:`armanim.render.solids.shapes`), their influence shells, the world axes in a corner, the title and the legend. Each frame
restores that background and draws what moves, straight into the Agg buffer:

1. the arm's soft shadow on the floor, and the tip's trail (hidden where it runs
   behind a sphere; left out while all of it lies under the scene's furniture, which covers it);
2. the solid parts (:mod:`armanim.render.solids.arm`) in painter's order (link prisms,
   joints, base, and the spheres the arm or its shadow overlaps on screen this frame;
   see :mod:`armanim.render.solids.order`). Spheres are exact orthographic discs shaded per
   pixel once (sprites, :mod:`armanim.render.solids.spheres`), then alpha-composited in their
   place in the order; the other spheres stay in the background, so a scene with a
   thousand obstacles costs little more per frame;
3. the trail again where it passes in front of a sphere;
4. the path still ahead of the tool, faintly, over everything but the markers;
5. the numbered goal markers (:mod:`armanim.render.overlay.markers`; a goal behind a sphere is
   drawn through it, dimmed and open) and the caption (:mod:`armanim.render.overlay.glyphs`).

A path goal's ink (:mod:`armanim.render.overlay.paths`: the pen-down path behind the tool)
is drawn with the trail, under the solids (again where it passes in front of a sphere); in a
scene with furniture (a whiteboard) it is drawn with the furniture instead, in the meshes'
z-buffer, so the board does not cover it and the links in front of it do.

When a goal has an orientation, the tool's RGB triad is drawn at the tip every frame and each
oriented goal's faint triad (a blue arrow for a tool-axis goal) with the background
(:mod:`armanim.render.overlay.triads`).

:func:`armanim.render.pictures.pose.render_pose_png` draws one pose this way (``armanim fk --png``).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np
from matplotlib.collections import LineCollection, PolyCollection
from matplotlib.lines import Line2D
from matplotlib.text import Text
from matplotlib.transforms import IdentityTransform

from armanim.arm.capsules import capsule_ends
from armanim.arm.kinematics import Pose, tool_rotation
from armanim.arm.visuals import ArmMeshes
from armanim.motion.carry import frame_bodies, moving_columns
from armanim.motion.problem import Problem
from armanim.render.camera.bounds import goal_points
from armanim.render.camera.framing import frame_scene
from armanim.render.camera.projection import camera_rotation, view_angles
from armanim.render.overlay.glyphs import GlyphAtlas
from armanim.render.overlay.markers import GoalMarkers
from armanim.render.overlay.paths import SampledPath, arc_spacing, frame_paths, joined, ribbon, sampled_paths
from armanim.render.overlay.triads import (
    GOAL_ALPHA,
    TRIAD_PER_REACH,
    arrow_heads,
    frame_segments,
    goal_segments,
    has_orientations,
    screen_lines,
)
from armanim.render.paint import scenery
from armanim.render.paint.pixels import in_pixels, make_figure
from armanim.render.paint.style import (
    AHEAD_ALPHA,
    AHEAD_DASHES,
    AHEAD_POINTS,
    BASE_SCALE,
    FACE_EDGE_PX,
    FONT,
    INK_COLOR,
    INK_POINTS,
    RING_POINTS,
    SHADOW_COLOR,
    TEXT_COLOR,
    TRAIL_COLOR,
)
from armanim.render.pictures import backdrop
from armanim.render.settings import RenderSettings
from armanim.render.solids.arm import Part, near_capsules, point_samples
from armanim.render.solids.obstacle_order import ObstacleOrder
from armanim.render.solids.order import paint_order
from armanim.render.solids.robot import MeshesAndCapsules, RasterQueue, RobotMeshes, arm_solids, robot_meshed
from armanim.render.solids.shapes import ShapeSolids
from armanim.render.solids.spheres import SphereDiscs
from armanim.world.carried import Body, bodies_obstacles, with_bodies
from armanim.world.obstacles import ROD, SPHERE, Obstacles

CHORD_PX = 0.25  # the most a drawn arc's chords stray from the arc, pixels
SHADOW_PASSES = np.array([(1.7, 0.06), (1.0, 0.10)])
"""The arm's soft shadow: its strokes' (width as a share of the capsule's, opacity), wide and faint first."""
SHADOW_RGB = np.asarray(SHADOW_COLOR) * 255.0
DEGENERATE_STROKE = 1e-3
"""Pixels: a capsule whose shadow is shorter than this (a vertical link's) leaves none, as matplotlib's
strokes of no length did (the floor's ring under the base is its shadow)."""
TRAIL_POINTS = 2.0
"""The trail's width, points."""
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
    path_done : (N,) array or None
        Arc length inked along each goal's path (a row of
        :func:`~armanim.render.overlay.paths.path_progress`); None: no ink.
    path_ahead : int
        The goal whose path still to do is drawn faintly (the frame's goal); -1: none.
    carried : Obstacles or None
        The objects a run moves (pick and place), where they are in this frame: drawn with the
        arm, in its painter's order; None: none.
    fingers : float or None
        The gripper's value in this frame (metres per finger, :mod:`armanim.arm.gripper`): its
        fingers are drawn there; None: where ``arm.joint_values`` holds them.
    """

    pose: Pose
    trail_end: int
    goal_status: np.ndarray
    caption: str
    ghosts: tuple = field(default=())
    path_done: np.ndarray | None = None
    path_ahead: int = -1
    carried: Obstacles | None = None
    fingers: float | None = None


def caption_points(template: str, width: float, fig, renderer) -> float:
    """The caption's font size in points: ``FONT["caption"]``, or less where the longest caption
    ``template``, at the whole-pixel advance the glyphs are stamped at (:class:`GlyphAtlas`), and its
    box's padding (0.3 em each side) would not fit ``width`` pixels (a goal with an orientation at
    960 x 540 cut the caption's last word to ``reac``), down to :data:`SMALLEST_CAPTION` of it."""
    points = float(FONT["caption"])
    for _ in range(20):
        probe = Text(0, 0, "M" * 40, fontsize=points, family="DejaVu Sans Mono", transform=IdentityTransform())
        probe.set_figure(fig)
        advance = max(round(probe.get_window_extent(renderer).width / 40.0), 1)
        need = len(template) * advance + 0.6 * points / (72.0 / fig.dpi)
        if need <= width or points <= SMALLEST_CAPTION * FONT["caption"]:
            return points
        points = max(points * 0.97 * width / need, SMALLEST_CAPTION * FONT["caption"])
    return points


def near_in_frames(problem: Problem, self_clearance: np.ndarray | None) -> bool:
    """Whether some frame tints links as close to the arm's own others (the least gap of each frame,
    (F,); None: not checked): within NEAR_FACTOR x ``self_clearance``, as each frame decides."""
    from armanim.render.solids.arm import NEAR_FACTOR

    if self_clearance is None or not len(problem.self_pairs):
        return False
    gaps = np.asarray(self_clearance, dtype=float)
    return bool(np.any(gaps[np.isfinite(gaps)] < NEAR_FACTOR * problem.self_pairs.clearance))


SMALLEST_CAPTION = 0.6
"""The caption never shrinks below this share of its size (a thumbnail of 80 x 60 keeps a cut
caption rather than an unreadable one, or a font size FreeType refuses)."""


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
    meshes : ArmMeshes, optional
        The robot's look and the scene's furniture (None: the arm's capsules).
    near_self : bool
        Some frame tints links close to the arm's own others (:func:`near_in_frames`): the
        legend names the tint.
    """

    def __init__(
        self,
        problem: Problem,
        settings: RenderSettings,
        *,
        title: str,
        tips: np.ndarray | None = None,
        extent: np.ndarray | None = None,
        picture: str = "video",
        caption_template: str = CAPTION_TEMPLATE,
        outcomes: frozenset = frozenset({"reached", "missed"}),
        meshes: ArmMeshes | None = None,
        near_self: bool = False,
    ):
        self.problem = problem
        self.picture = picture
        self.width, self.height = (int(v) for v in settings.size)
        self.layout = scenery.frame_layout(self.width, self.height)
        self.fig, self.canvas = make_figure(self.width, self.height, self.layout.dpi)
        self.pt = 72.0 / self.fig.dpi  # points per pixel
        self.renderer = self.canvas.get_renderer()
        elevation, azimuth = view_angles(problem.arm, settings.elevation, settings.azimuth)
        self.rotation = camera_rotation(elevation, azimuth)
        framing = frame_scene(problem, settings, extent, self.rotation, elevation, self.layout)
        self.view, self.ppu, self.floor = framing.view, framing.ppu, framing.floor
        self.arm = arm_solids(problem, meshes, self.view, self.ppu, (self.width, self.height), settings.robot)
        self._arms: dict[float, object] = {}  # the arm drawn with its fingers elsewhere, per gripper value
        self._meshes, self._look = meshes, settings.robot
        self.spheres = SphereDiscs(problem.obstacles, self.view, self.ppu)
        obstacles = problem.obstacles
        shaped = len(obstacles.boxes) + len(obstacles.rods) + len(obstacles.cylinders)
        self.shapes = ShapeSolids(obstacles, self.view, self.ppu) if shaped else None
        self.obstacle_order = ObstacleOrder(self.spheres, self.shapes, self.view) if self.shapes is not None else None
        goals = self.view.project(goal_points(problem))
        paths = np.array([getattr(g, "path", None) is not None for g in problem.goals], dtype=bool)
        self.goals = GoalMarkers(self.fig, goals, self._behind(goals), (self.width, self.height), open_goals=paths)
        self.triads = has_orientations(problem.goals)
        self.triad_length = TRIAD_PER_REACH * problem.arm.reach
        self._prepare_trail(tips if settings.trail else None)
        still = getattr(self.arm, "still", None)
        self.trail_hidden = 0 if still is None else still.hidden_prefix(self.trail_xy, TRAIL_POINTS / self.pt / 2 + 2.0)
        """The trail's leading points under the scene's furniture (drawn over every pixel of their
        stroke, keeping none): a frame with no more is drawn without it (ur5-pen's whiteboard)."""
        self.paths = self._prepare_paths()
        self.on_furniture = bool(self.paths) and getattr(self.arm, "furniture", None) is not None
        self._make_artists()
        solids = len(obstacles.radii) + shaped  # the floor is no red solid
        legend = backdrop.legend_entries(
            picture,
            trail=settings.trail,
            obstacles=bool(solids),
            paths=bool(self.paths),
            outcomes=outcomes,
            hidden_goal=bool(self.goals.hidden.any()),
            hidden_by="a sphere" if self.shapes is None else "an obstacle",
            goals=bool(len(problem.goals)),
            robot=robot_meshed(problem, meshes),
            near_self=near_self,
        )
        self.caption_points = caption_points(
            caption_template, self.width - 2 * self.layout.caption_xy[0], self.fig, self.renderer
        )
        self._draw_background(title, legend, caption_template)
        self.scratch = self._scratch_canvas()
        self.glyphs = GlyphAtlas(self.scratch, self.caption_points, TEXT_COLOR)

    # ----- drawn once -----------------------------------------------------------------

    def _prepare_trail(self, tips: np.ndarray | None) -> None:
        """The tip's path on screen: where it runs behind a sphere and where in front of one."""
        if tips is None or len(tips) == 0:
            self.trail_xy = np.zeros((0, 2))
            self.trail_front_xy = np.zeros((0, 2))
            return
        screen = self.view.project(np.asarray(tips, dtype=float))
        self.trail_xy = np.where(self._behind(screen)[:, None], np.nan, screen[:, :2])
        front = self.spheres.in_front(screen)
        if self.shapes is not None:
            front = front | self.shapes.in_front(screen)
        self.trail_front_xy = np.where(front[:, None], screen[:, :2], np.nan)

    def _prepare_paths(self) -> list[SampledPath]:
        """Every path goal's path on screen, its arcs split finely enough to look round."""
        paths = sampled_paths(self.problem.goals, lambda path: arc_spacing(path, CHORD_PX / self.ppu))
        return [p.mapped(self.view.project(p.points)) for p in paths]

    def _unhidden(self, screen: np.ndarray) -> np.ndarray:
        """(k, 2) the pixels of screen points (k, 3; NaN rows allowed), NaN where an obstacle hides them."""
        xy = screen[:, :2].copy()
        ok = np.isfinite(screen[:, 0])
        hidden = np.zeros(len(screen), dtype=bool)
        hidden[ok] = self._behind(screen[ok])
        xy[hidden] = np.nan
        return xy

    def _in_front(self, screen: np.ndarray) -> np.ndarray:
        """(k, 2) the pixels of screen points (k, 3; NaN rows allowed) in front of an obstacle, NaN elsewhere."""
        ok = np.isfinite(screen[:, 0])
        front = np.zeros(len(screen), dtype=bool)
        front[ok] = self.spheres.in_front(screen[ok])
        if self.shapes is not None:
            front[ok] |= self.shapes.in_front(screen[ok])
        return np.where(front[:, None], screen[:, :2], np.nan)

    def _behind(self, screen: np.ndarray) -> np.ndarray:
        """(P,) bool: screen points (P, 3) hidden by an obstacle (a sphere, a box, a capsule, a cylinder)."""
        hidden = self.spheres.behind(screen)
        return hidden | self.shapes.behind(screen) if self.shapes is not None else hidden

    def _make_artists(self) -> None:
        """The artists every frame draws again with new data."""
        self.faces = in_pixels(PolyCollection([], linewidths=FACE_EDGE_PX * self.pt, antialiased=True), self.fig)
        self.faces.set_offset_transform(IdentityTransform())
        self.shadow = in_pixels(LineCollection([], color=SHADOW_COLOR, capstyle="round"), self.fig)
        self.trail = in_pixels(
            Line2D([], [], color=TRAIL_COLOR, linewidth=TRAIL_POINTS, solid_capstyle="round", alpha=0.95), self.fig
        )
        self.trail_front = in_pixels(Line2D([], [], color=TRAIL_COLOR, linewidth=TRAIL_POINTS, alpha=0.95), self.fig)
        self.ink = in_pixels(
            Line2D([], [], color=INK_COLOR, linewidth=INK_POINTS, solid_capstyle="round", solid_joinstyle="round"),
            self.fig,
        )
        self.ahead = in_pixels(
            Line2D([], [], color=INK_COLOR, linewidth=AHEAD_POINTS, alpha=AHEAD_ALPHA, linestyle=(0, AHEAD_DASHES)),
            self.fig,
        )

    def _draw_background(self, title: str, legend: list, caption_template: str) -> None:
        """Draw what never changes and keep it as the pixel background of every frame."""
        self.renderer.clear()
        self.fig.draw(self.renderer)  # the white figure
        sheet = backdrop.Sheet(self.fig, self.renderer)
        if self.floor is not None:
            backdrop.draw_floor(sheet, self.view, self.floor, self._floor_shadows())
        backdrop.draw_shells(sheet, self.spheres.shells() + (self.shapes.shells() if self.shapes is not None else []))
        if self.shapes is None:
            self.spheres.composite(np.asarray(self.canvas.buffer_rgba()), self.spheres.order)
        else:
            self._draw_obstacles(self._shape_order.order)
        if self.triads:
            self._draw_goal_triads(sheet)
        backdrop.draw_gizmo(sheet, self.layout, self.rotation)
        backdrop.draw_title(sheet, self.layout, title)
        backdrop.draw_legend(sheet, self.layout, legend)
        backdrop.draw_caption_box(sheet, self.layout, caption_template, self.caption_points)
        gap = 0.45 * RING_POINTS / self.pt  # clear of the current goal's ring
        sheet.text_boxes.update(
            self.goals.place_labels(self.renderer, gap, list(sheet.text_boxes.values()), self.layout.scene)
        )
        self.text_boxes = sheet.text_boxes
        self.background = self.canvas.copy_from_bbox(self.fig.bbox)

    def _draw_goal_triads(self, sheet) -> None:
        """Each oriented goal's faint triad, or its tool axis as one arrow."""
        segments, colors = goal_segments(self.problem.goals, self.triad_length)
        sheet.draw(screen_lines(self.view, segments, colors, GOAL_ALPHA, 1.6))
        arrows = [k for k, g in enumerate(_segment_goals(self.problem.goals)) if g.orientation.axis is not None]
        if arrows:
            sheet.draw(arrow_heads(self.view, segments[arrows], [colors[k] for k in arrows], GOAL_ALPHA, 7.0))

    def _draw_tool_triad(self, pose: Pose) -> None:
        """The tool frame's RGB axes at the tip (one collection made once, its segments moved each frame)."""
        segments, colors = frame_segments(pose.tip, tool_rotation(self.problem.arm, pose), self.triad_length)
        if getattr(self, "_triad", None) is None:
            self._triad = in_pixels(screen_lines(self.view, segments, colors, 1.0, 2.2), self.fig)
            self._triad.set_offset_transform(IdentityTransform())
        else:
            self._triad.set_segments(self.view.project(segments)[..., :2])
        self._triad.draw(self.renderer)

    @property
    def _shape_order(self) -> ObstacleOrder:
        """:attr:`obstacle_order`, which a scene with boxes, capsules or cylinders has."""
        assert self.obstacle_order is not None, "a canvas with shapes has their order"
        return self.obstacle_order

    def _floor_shadows(self) -> list[np.ndarray]:
        """Rings on the floor under the base and under every sphere (light straight overhead)."""
        assert self.floor is not None  # drawn only with a floor
        z, obstacles = self.floor.z, self.problem.obstacles
        base = scenery.floor_circle(self.problem.arm.stand, BASE_SCALE * self.problem.half_width * 1.1, z)
        rings = [base] + [scenery.floor_circle(c, r, z) for c, r in zip(obstacles.centers, obstacles.radii)]
        return rings + (self.shapes.floor_shadows(z) if self.shapes is not None else [])

    def _scratch_canvas(self):
        """A small canvas of the same dpi to draw sprites on (clearing the whole frame
        for each of hundreds of sprites was slow at large sizes)."""
        extent = RING_POINTS / self.pt + self.goals.largest_label(self.renderer)
        side = int(np.ceil(2 * extent + 3 * max(FONT["caption"], self.caption_points) / self.pt)) + 8
        return make_figure(side, side, self.fig.dpi)[1]

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
        if state.trail_end > max(1, self.trail_hidden):
            self.trail.set_data(self.trail_xy[: state.trail_end].T)
            self.trail.draw(renderer)
        views = frame_paths(self.paths, state.path_done, state.path_ahead) if state.path_done is not None else ()
        ink = joined([v.ink() for v in views])
        if len(ink) and not self.on_furniture:
            self.ink.set_data(self._unhidden(ink).T)
            self.ink.draw(renderer)
        touched = self._draw_solids(state, shadow, self._ink_decal(ink) if len(ink) and self.on_furniture else None)
        if state.trail_end > 1 and touched:
            self.trail_front.set_data(self.trail_front_xy[: state.trail_end].T)
            self.trail_front.draw(renderer)
        if len(ink) and touched and not self.on_furniture:
            self.ink.set_data(self._in_front(ink).T)
            self.ink.draw(renderer)
        ahead = joined([v.rest() for v in views])
        if len(ahead):
            self.ahead.set_data(self._unhidden(ahead).T)
            self.ahead.draw(renderer)
        if self.triads:
            self._draw_tool_triad(state.pose)
        self.goals.draw(np.asarray(self.canvas.buffer_rgba()), state.goal_status, self.scratch)
        self.glyphs.stamp(np.asarray(self.canvas.buffer_rgba()), state.caption, *self.layout.caption_xy)
        return np.asarray(self.canvas.buffer_rgba())

    def _draw_shadow(self, pose: Pose) -> np.ndarray | None:
        """The arm's soft shadow on the floor; returns its screen box (x0, y0, x1, y1).

        A video's frames lay it with the compiled strokes
        (:func:`~armanim.render.solids.rasterloops.soft_strokes`: 1.5 -> 0.7 ms of a ur5-pen frame at load 8);
        the other pictures with matplotlib's, so that a picture of an arm of links never loads numba.
        Both draw the same strokes within a few levels of 255."""
        if self.floor is None:
            return None
        caps = self.problem.capsules
        a, b = (self.view.project(scenery.on_floor(end, self.floor.z))[:, :2] for end in capsule_ends(caps, pose))
        half = caps.radius * self.ppu  # pixels
        if self.picture == "video":
            from armanim.render.solids.rasterloops import soft_strokes  # compiled: numba is imported here

            drawn = np.hypot(*(b - a).T) > DEGENERATE_STROKE  # as Agg's, which leaves them out
            ends = np.stack([a[drawn], b[drawn]], axis=1)
            soft_strokes(np.asarray(self.canvas.buffer_rgba()), ends, half[drawn], SHADOW_PASSES, SHADOW_RGB)
        else:
            self.shadow.set_segments(np.stack([a, b], axis=1))
            for scale, alpha in SHADOW_PASSES:
                self.shadow.set_linewidth(2 * half * scale * self.pt)
                self.shadow.set_alpha(alpha)
                self.shadow.draw(self.renderer)
        pad = 2 * float(np.max(half))
        drop = np.vstack([a, b])
        return np.concatenate([drop.min(axis=0) - pad, drop.max(axis=0) + pad])

    def _ink_decal(self, ink: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The ink (a screen polyline, NaN rows between runs) as triangles drawn with the furniture,
        lifted a little toward the viewer so that a board it lies on does not hide it."""
        width = INK_POINTS / self.pt
        points, faces = ribbon(ink, width, lift=2.0 * width)
        return points, faces, np.tile(INK_COLOR, (len(points), 1))

    def _draw_solids(self, state: FrameState, shadow, decal=None) -> bool:
        """The poster's faint poses, then the arm (``decal``: the ink, drawn with the furniture),
        each with the spheres it overlaps, in painter's order (so faint poses never cover the arm).
        Returns whether any sphere was redrawn."""
        touched = False
        for ghost in state.ghosts:
            touched |= self._draw_parts(self.arm.parts(ghost, ghost=True), None)
        near = near_capsules(self.problem, state.pose)
        arm = self._arm_at(state.fingers)
        if decal is not None and isinstance(arm, (RobotMeshes, MeshesAndCapsules)):  # (only these draw furniture)
            parts = arm.parts(state.pose, near=near, decal=decal)
        else:
            parts = arm.parts(state.pose, near=near)
        if state.carried is not None and len(state.carried):
            parts = parts + ShapeSolids(state.carried, self.view, self.ppu).parts
        return self._draw_parts(parts, shadow) or touched

    def _arm_at(self, fingers: float | None):
        """The arm's drawing with the gripper at ``fingers`` (made once per value; None or its rest: :attr:`arm`)."""
        from armanim.arm.gripper import moved_fingers, moved_meshes

        gripper = self.problem.gripper
        if fingers is None or gripper is None or fingers == gripper.rest:
            return self.arm
        if fingers not in self._arms:
            problem = replace(self.problem, capsules=moved_fingers(self.problem.capsules, gripper, fingers))
            meshes = None if self._meshes is None else moved_meshes(self._meshes, gripper, fingers)
            self._arms[fingers] = arm_solids(
                problem, meshes, self.view, self.ppu, (self.width, self.height), self._look
            )
        return self._arms[fingers]

    def _draw_parts(self, parts: list[Part], shadow) -> bool:
        """Parts and the spheres they (or ``shadow``'s box) overlap on screen, far first."""
        allpts = np.concatenate([p.samples[:, :2] for p in parts])
        widest = max(p.radius for p in parts)
        arm_box = np.concatenate([allpts.min(axis=0) - widest, allpts.max(axis=0) + widest])
        if self.shapes is not None:
            return self._draw_parts_among_shapes(parts, [arm_box, shadow])
        spheres = self.spheres.touched([arm_box, shadow])
        samples = [p.samples for p in parts] + [point_samples(self.spheres.centers[i]) for i in spheres]
        radii = [p.radius for p in parts] + [self.spheres.radii[i] for i in spheres]
        polys: list[np.ndarray] = []
        colors: list[np.ndarray] = []
        buffer = np.asarray(self.canvas.buffer_rgba())
        meshes = RasterQueue((self.width, self.height))
        if not len(spheres) and one_z_buffer(parts):  # drawn as one whatever their order (0.4 ms a ur5-pen frame)
            order: list[int] | range = range(len(parts))
        else:
            order = paint_order(np.array(samples), np.array(radii))
        for k in order:
            raster = parts[k].raster if k < len(parts) else None
            if raster is not None:  # a mesh link's pixels cover what was painted before
                self._flush(polys, colors)
                polys, colors = [], []
                meshes.add(raster, buffer)
                continue
            meshes.flush(buffer)
            if k < len(parts):
                polys.extend(parts[k].polygons)
                colors.append(parts[k].colors)
            else:  # a sphere's sprite covers what was painted before it
                self._flush(polys, colors)
                polys, colors = [], []
                self.spheres.composite(buffer, [spheres[k - len(parts)]])
        self._flush(polys, colors)
        meshes.flush(buffer)
        return bool(len(spheres))

    def _draw_parts_among_shapes(self, parts: list[Part], boxes: list) -> bool:
        """Parts and the obstacles they overlap, in one painter's order (boxes by ray depth)."""
        touched = self._shape_order.touched(boxes)
        spheres = len(self.spheres)
        obstacle_parts = [self._shape_order.item(i) for i in touched]
        samples = np.array([p.samples for p in parts] + [p.samples for p in obstacle_parts])
        radii = np.array([p.radius for p in parts] + [p.radius for p in obstacle_parts])
        assert self.shapes is not None  # obstacle parts are the shapes'
        box_of = np.concatenate(
            [np.full(len(parts), -1), [self.shapes.box_of[i - spheres] if i >= spheres else -1 for i in touched]]
        ).astype(int)
        order = self._shape_order.paint_order(samples, radii, box_of)
        self._paint([*parts, *obstacle_parts], order, len(parts), touched)
        return bool(len(touched))

    def _draw_obstacles(self, indices) -> None:
        """Obstacles ``indices`` (spheres, then the shapes' parts), in that order."""
        items = [self._shape_order.item(i) for i in indices]
        self._paint(items, list(range(len(items))), 0, np.asarray(indices, dtype=int))

    def _paint(self, items: list[Part], order: list[int], moving: int, obstacles: np.ndarray) -> None:
        """Draw ``items`` in ``order``; the first ``moving`` are the arm's, the rest the
        ``obstacles`` (indices among spheres then shape parts; a sphere is its sprite)."""
        polys: list[np.ndarray] = []
        colors: list[np.ndarray] = []
        buffer = np.asarray(self.canvas.buffer_rgba())
        meshes = RasterQueue((self.width, self.height))
        for k in order:
            raster = items[k].raster
            if raster is not None:
                self._flush(polys, colors)
                polys, colors = [], []
                meshes.add(raster, buffer)
                continue
            meshes.flush(buffer)
            if k >= moving and obstacles[k - moving] < len(self.spheres):
                self._flush(polys, colors)
                polys, colors = [], []
                self.spheres.composite(buffer, [obstacles[k - moving]])
            else:
                polys.extend(items[k].polygons)
                colors.append(items[k].colors)
        self._flush(polys, colors)
        meshes.flush(buffer)

    def _flush(self, polys: list[np.ndarray], colors: list[np.ndarray]) -> None:
        """Draw the faces gathered since the last sphere, in order, as one collection."""
        if not polys:
            return
        color = np.concatenate(colors)
        self.faces.set_verts(polys)
        self.faces.set_facecolor(color)
        self.faces.set_edgecolor(color)
        self.faces.draw(self.renderer)


def one_z_buffer(parts: list[Part]) -> bool:
    """Whether ``parts`` are all filled into one z-buffer (:class:`RasterQueue`: every one a mesh
    of the same pose's points): there the nearest surface wins each sample whatever the parts'
    painter's order (but for samples at exactly the same depth in two parts)."""
    first = parts[0].raster if parts else None
    return first is not None and all(
        p.raster is not None and p.raster[0] is first[0] and p.raster[3] == first[3] for p in parts
    )


def _segment_goals(goals) -> list:
    """The goal each segment of :func:`~armanim.render.overlay.triads.goal_segments` belongs to, in order."""
    owners = []
    for g in goals:
        if g.orientation is not None:
            owners += [g] * (3 if g.orientation.rotation is not None else 1)
    return owners


def run_fingers(problem: Problem, solution) -> np.ndarray | None:
    """(F,) the gripper's value in each frame of a run that grasps with a gripper
    (:func:`~armanim.motion.carry.frame_fingers`); None otherwise."""
    from armanim.motion.carry import frame_fingers

    if solution.carry is None or problem.gripper is None:
        return None
    traj = solution.trajectory
    return frame_fingers(problem, solution.carry, traj.goal, traj.fps)


def moving_objects(problem: Problem, solution) -> tuple[Problem, list[Obstacles] | None]:
    """The scene without the objects a run moves (drawn once, in the background), and each frame's
    moving objects where they are (:func:`~armanim.motion.carry.frame_bodies`; a sphere as a capsule
    of no length, which the shapes draw); ``problem`` and None for a run that grasps nothing."""
    carry = solution.carry
    if carry is None or not moving_columns(carry):
        return problem, None
    columns = moving_columns(carry)
    traj = solution.trajectory
    static = replace(problem, obstacles=with_bodies(problem.obstacles, {c: None for c in columns}))
    frames = frame_bodies(problem, carry, traj.phi, traj.goal)
    drawn = [
        [b if b.kind != SPHERE else Body(ROD, np.eye(3), b.center, np.zeros(3), b.radius) for b in bodies]
        for bodies in frames
    ]
    return static, [bodies_obstacles(bodies) for bodies in drawn]
