"""Draw frames of an arm scene: a matplotlib Figure on the Agg canvas, no pyplot.

What never changes (the figure, the 3D axes with panes, grid and ticks, the title,
the legend, the goals' faint influence shells) is drawn once and kept as a pixel
background. Each frame restores that background and draws only what moves, straight
into the Agg buffer: the tip's trail, the solid parts in painter's order (link
prisms, joints, base, obstacle spheres; see :mod:`armanim.render.order`), the goal
markers and the caption. Obstacle spheres are exact orthographic discs shaded per
pixel once (sprites), then alpha-composited in their place in the order.

The camera is orthographic and fixed for a whole video (:class:`~armanim.render.view.View`).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

import mpl_toolkits.mplot3d  # noqa: F401  (registers the "3d" projection)
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import PolyCollection
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Circle
from matplotlib.text import Text
from matplotlib.transforms import IdentityTransform

from armanim.kinematics import Pose, forward
from armanim.problem import Problem, RenderSettings
from armanim.render.bounds import resolve_bounds
from armanim.render.mesh import perpendicular_basis, prism_faces, prism_local, prism_world
from armanim.render.order import paint_order
from armanim.render.view import LIGHT, View, lambert

BACKGROUND = (1.0, 1.0, 1.0)
PANE_COLOR = (0.94, 0.95, 0.97, 1.0)
ARM_COLOR = (0.16, 0.42, 0.80)
JOINT_COLOR = (0.16, 0.17, 0.20)
JOINT_HIGHLIGHT = (0.55, 0.57, 0.62)
BASE_COLOR = (0.50, 0.52, 0.56)
OBSTACLE_COLOR = (0.85, 0.30, 0.25)
TRAIL_COLOR = (0.95, 0.55, 0.05)
GOAL_COLORS = {
    "pending": (0.45, 0.47, 0.52),
    "current": (1.00, 0.76, 0.00),
    "reached": (0.13, 0.62, 0.28),
    "missed": (0.85, 0.10, 0.10),
}
PENDING, CURRENT, REACHED, MISSED = 0, 1, 2, 3
STATUS_NAMES = ("pending", "current", "reached", "missed")

PRISM_SIDES = 10  # faces around a link
JOINT_SCALE = 1.45  # joint dot radius / link half width
BASE_SCALE = 3.0  # pedestal radius / link half width
SAMPLES = 7  # points per part for the painter's order
INCHES_HIGH = 7.2  # figure height in inches: fonts scale with the frame height
FACE_EDGE_PX = 0.7  # faces are outlined in their own colour to close seams


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
        The dynamic caption line (time, goal k of N, distance, state).
    """

    pose: Pose
    trail_end: int
    goal_status: np.ndarray
    caption: str


def make_figure(width: int, height: int) -> tuple[Figure, FigureCanvasAgg]:
    """A Figure whose Agg buffer is exactly ``width`` x ``height`` pixels.

    The figure is always ``INCHES_HIGH`` inches tall, so text keeps its proportion to
    the frame at every size; the inch sizes get a thousandth of a pixel extra so
    float rounding cannot lose a pixel.
    """
    dpi = height / INCHES_HIGH
    fig = Figure(figsize=((width + 1e-3) / dpi, (height + 1e-3) / dpi), dpi=dpi, facecolor=BACKGROUND)
    return fig, FigureCanvasAgg(fig)


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
        Every joint position the video will show: ``render.bounds: auto`` fits them.
    still : bool
        One picture, not a video: the legend lists only what a single pose shows.
    """

    def __init__(
        self,
        problem: Problem,
        settings: RenderSettings,
        *,
        title: str,
        tips: np.ndarray | None = None,
        extent: np.ndarray | None = None,
        still: bool = False,
    ):
        self.problem = problem
        self.settings = settings
        self.still = still
        self.width, self.height = (int(v) for v in settings.size)
        self.fig, self.canvas = make_figure(self.width, self.height)
        self.pt = 72.0 / self.fig.dpi  # points per pixel
        self.bounds = resolve_bounds(problem, settings, extent)
        self.ax = self._axes()
        self._static_decor(title)
        self.canvas.draw()
        self.renderer = self.canvas.get_renderer()
        self.background = self.canvas.copy_from_bbox(self.fig.bbox)
        self.view = View.from_axes(self.ax, self.width, self.height)
        self.ppu = float(self.view.pixels_per_unit.mean())
        self._prepare_arm()
        self._prepare_obstacles()
        self._prepare_base()
        self._prepare_goals()
        self._prepare_trail(tips if settings.trail else None)
        self._make_artists()

    # ----- static scene ---------------------------------------------------------------

    def _axes(self):
        ax = self.fig.add_axes((0.0, 0.075, 1.0, 0.9), projection="3d", proj_type="ortho")
        b = self.bounds
        ax.set_xlim(*b[0])
        ax.set_ylim(*b[1])
        ax.set_zlim(*b[2])
        ax.set_box_aspect(b[:, 1] - b[:, 0], zoom=1.12)
        ax.view_init(elev=self.settings.elevation, azim=self.settings.azimuth)
        ax.set_facecolor(BACKGROUND)
        size = 9
        for axis, name in ((ax.xaxis, "x"), (ax.yaxis, "y"), (ax.zaxis, "z")):
            axis.set_pane_color(PANE_COLOR)
            axis.set_tick_params(labelsize=size - 1, pad=1, colors=(0.35, 0.35, 0.4))
            axis._axinfo["grid"].update(color=(0.82, 0.83, 0.86), linewidth=0.6)
        ax.set_xlabel("x", fontsize=size, labelpad=-2, color=(0.3, 0.3, 0.35))
        ax.set_ylabel("y", fontsize=size, labelpad=-2, color=(0.3, 0.3, 0.35))
        ax.set_zlabel("z", fontsize=size, labelpad=-2, color=(0.3, 0.3, 0.35))
        return ax

    def _static_decor(self, title: str) -> None:
        fig = self.fig
        fig.text(0.012, 0.985, title, ha="left", va="top", fontsize=14, fontweight="bold", color=(0.1, 0.1, 0.12))
        marker = dict(linestyle="none", markersize=8)
        handles = [
            Line2D([], [], color=ARM_COLOR, linewidth=5),
            Line2D([], [], marker="o", markerfacecolor=OBSTACLE_COLOR, markeredgecolor="none", **marker),
            Line2D([], [], marker="*", markerfacecolor=GOAL_COLORS["current"], markeredgecolor="k",
                   markeredgewidth=0.6, **{**marker, "markersize": 12}),
            Line2D([], [], marker="o", markerfacecolor="none", markeredgecolor=GOAL_COLORS["pending"],
                   markeredgewidth=1.5, **marker),
            Line2D([], [], marker="o", markerfacecolor=GOAL_COLORS["reached"], markeredgecolor="white", **marker),
            Line2D([], [], marker="X", markerfacecolor=GOAL_COLORS["missed"], markeredgecolor="white", **marker),
        ]
        labels = ["arm", "obstacle", "current goal", "next goals", "reached", "missed"]
        if self.still:  # a single pose: the arm, the obstacles and the goals, no states or path
            keep = [0, 3] if not len(self.problem.obstacles) else [0, 1, 3]
            handles = [handles[i] for i in keep]
            labels = [labels[i] if labels[i] != "next goals" else "goals" for i in keep]
        elif self.settings.trail:
            handles.insert(1, Line2D([], [], color=TRAIL_COLOR, linewidth=2))
            labels.insert(1, "tip path")
        fig.legend(handles, labels, loc="lower center", ncols=len(labels), frameon=False, fontsize=9,
                   handlelength=1.6, columnspacing=1.2, borderaxespad=0.3)

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
        for center, radius, reach in zip(self.sphere_centers, obs.radii, obs.influence):
            if reach > 0:  # the influence shell: a faint dashed outline, in the background
                shell = Circle(center[:2], (radius + reach) * self.ppu, transform=IdentityTransform(),
                               fill=False, linestyle=(0, (4, 4)), linewidth=0.8, edgecolor=OBSTACLE_COLOR,
                               alpha=0.35)
                shell.set_figure(self.fig)
                shell.draw(self.renderer)
        if len(obs):
            self.background = self.canvas.copy_from_bbox(self.fig.bbox)

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
        polys, normals = [], []
        for i in range(len(theta)):
            j = (i + 1) % len(theta)
            polys.append(np.array([lower[i], lower[j], upper[j], upper[i]]))
            mid = (theta[i] + theta[j]) / 2
            normals.append([np.cos(mid), np.sin(mid), 0.0])
        polys += [upper, lower[::-1]]
        normals += [[0, 0, 1.0], [0, 0, -1.0]]
        screen_n = self.view.screen_normals(np.array(normals))
        front = screen_n[:, 2] > 0
        self.base_polys = [self.view.project(p)[:, :2] for p, f in zip(polys, front) if f]
        self.base_colors = lambert(screen_n[front], BASE_COLOR)
        ends = self.view.project(np.array([top - [0, 0, height], top]))
        self.base_samples = ends[0] + np.linspace(0, 1, SAMPLES)[:, None] * (ends[1] - ends[0])
        self.base_radius = radius * self.ppu

    def _prepare_goals(self) -> None:
        goals = np.array([g.position for g in self.problem.goals], dtype=float).reshape(-1, 3)
        screen = self.view.project(goals)
        self.goal_xy = screen[:, :2]
        self.goal_visible = ~self._behind_spheres(screen)

    def _prepare_trail(self, tips: np.ndarray | None) -> None:
        if tips is None or len(tips) == 0:
            self.trail_xy = np.zeros((0, 2))
            self.trail_front_xy = np.zeros((0, 2))
            return
        screen = self.view.project(np.asarray(tips, dtype=float))
        self.trail_xy = screen[:, :2].copy()
        front = self._over_spheres(screen)
        self.trail_front_xy = np.where(front[:, None], screen[:, :2], np.nan)

    def _on_discs(self, screen: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(P, m) masks: point inside a sphere's disc, and nearer than its centre."""
        if not len(self.sphere_radii):
            empty = np.zeros((len(screen), 0), dtype=bool)
            return empty, empty
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
        def own(artist):
            artist.set_figure(self.fig)
            return artist

        ident = IdentityTransform()
        self.solids = own(PolyCollection([], transform=ident, linewidths=FACE_EDGE_PX * self.pt, antialiased=True))
        self.solids.set_offset_transform(ident)
        self.trail = own(Line2D([], [], color=TRAIL_COLOR, linewidth=2.0, transform=ident, solid_capstyle="round",
                                alpha=0.95))
        self.trail_front = own(Line2D([], [], color=TRAIL_COLOR, linewidth=2.0, transform=ident, alpha=0.95))
        style = {
            PENDING: dict(marker="o", markersize=9, markerfacecolor="none",
                          markeredgecolor=GOAL_COLORS["pending"], markeredgewidth=1.6),
            CURRENT: dict(marker="*", markersize=19, markerfacecolor=GOAL_COLORS["current"],
                          markeredgecolor=(0.2, 0.15, 0.0), markeredgewidth=0.9),
            REACHED: dict(marker="o", markersize=10, markerfacecolor=GOAL_COLORS["reached"],
                          markeredgecolor="white", markeredgewidth=1.2),
            MISSED: dict(marker="X", markersize=12, markerfacecolor=GOAL_COLORS["missed"],
                         markeredgecolor="white", markeredgewidth=1.0),
        }
        self.goal_marks = {k: own(Line2D([], [], linestyle="none", transform=ident, **s)) for k, s in style.items()}
        self.goal_ring = own(Line2D([], [], linestyle="none", marker="o", markersize=27, markerfacecolor="none",
                                    markeredgecolor=GOAL_COLORS["current"], markeredgewidth=1.8, alpha=0.7,
                                    transform=ident))
        self.caption = own(Text(0.012, 0.925, "", ha="left", va="top", fontsize=11, family="DejaVu Sans Mono",
                                color=(0.12, 0.12, 0.15), transform=self.fig.transFigure,
                                bbox=dict(boxstyle="round,pad=0.35", facecolor="white", edgecolor=(0.8, 0.8, 0.84),
                                          alpha=0.9)))

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
        if state.trail_end > 1:
            self.trail.set_data(self.trail_xy[: state.trail_end].T)
            self.trail.draw(renderer)
        self._draw_solids(state.pose)
        if state.trail_end > 1 and len(self.sphere_radii):
            self.trail_front.set_data(self.trail_front_xy[: state.trail_end].T)
            self.trail_front.draw(renderer)
        self._draw_goals(state.goal_status)
        self.caption.set_text(state.caption)
        self.caption.draw(renderer)
        return np.asarray(self.canvas.buffer_rgba())

    def _draw_solids(self, pose: Pose) -> None:
        parts = self._arm_parts(pose)
        samples = [p[0] for p in parts]
        radii = [p[1] for p in parts]
        kinds = [p[2] for p in parts]
        for i, c in enumerate(self.sphere_centers):
            samples.append(np.repeat(c[None, :], SAMPLES, axis=0))
            radii.append(self.sphere_radii[i])
            kinds.append(("sphere", i))
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

    def _arm_parts(self, pose: Pose) -> list[tuple[np.ndarray, float, tuple]]:
        """Screen samples, radius and polygons of the base, every link and every joint."""
        view = self.view
        verts = view.project(prism_world(pose, self.prism_local))  # (n, V, 3)
        normals = view.screen_normals(np.einsum("nab,fb->nfa", pose.frames, self.face_normals_local))
        joints = view.project(pose.points)  # (n+1, 3)
        t = np.linspace(0.0, 1.0, SAMPLES)[:, None]
        parts = [(self.base_samples, self.base_radius, ("solid", self.base_polys, self.base_colors))]
        link_radius = self.problem.half_width * self.ppu
        for i in range(len(verts)):
            front = np.flatnonzero(normals[i, :, 2] > 1e-9)
            polys = [verts[i, self.faces[f], :2] for f in front]
            shade = lambert(normals[i, front], ARM_COLOR)
            samples = joints[i] + t * (joints[i + 1] - joints[i])
            parts.append((samples, link_radius, ("solid", polys, shade)))
        r = self.joint_radius
        for i in range(len(verts)):
            center = joints[i]
            disc = center[:2] + r * self.unit_circle
            glint = center[:2] + 0.45 * r * self.unit_circle + 0.25 * r * LIGHT[:2]
            polys = [disc, glint]
            shade = np.array([JOINT_COLOR, JOINT_HIGHLIGHT])
            parts.append((np.repeat(center[None, :], SAMPLES, axis=0), r, ("solid", polys, shade)))
        return parts

    def _flush(self, polys: list[np.ndarray], colors: list[np.ndarray]) -> None:
        if not polys:
            return
        color = np.concatenate([np.atleast_2d(c) for c in colors])
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
        visible = self.goal_visible
        for code, artist in self.goal_marks.items():
            mask = (status == code) & visible
            if code == CURRENT:
                self.goal_ring.set_data(self.goal_xy[mask].T)
                self.goal_ring.draw(self.renderer)
            artist.set_data(self.goal_xy[mask].T)
            artist.draw(self.renderer)


def grab_rgb(buffer: np.ndarray) -> np.ndarray:
    """A contiguous (H, W, 3) uint8 copy of an RGBA canvas buffer."""
    return np.ascontiguousarray(buffer[..., :3])


def pose_caption(problem: Problem, phi: np.ndarray) -> str:
    """Caption of a single pose: its joint angles in degrees and its tip."""
    tip = forward(problem.arm, phi).tip
    angles = ", ".join(f"{a:.1f}" for a in np.degrees(phi))
    return f"phi = [{angles}] deg\ntip = ({tip[0]:.3f}, {tip[1]:.3f}, {tip[2]:.3f})"


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
    scene = SceneCanvas(problem, settings, title=title, extent=pose.points, still=True)
    state = FrameState(
        pose=pose,
        trail_end=0,
        goal_status=np.full(len(problem.goals), PENDING),
        caption=pose_caption(problem, phi),
    )
    write_png(scene.draw(state), path)


def write_png(rgba: np.ndarray, path) -> None:
    """Write an (H, W, 4) uint8 image to a PNG atomically (temporary file, then replace);
    a write failure is an OutputError (exit 3)."""
    from matplotlib.image import imsave

    from armanim.output.atomic import temporary_beside

    with temporary_beside(Path(path)) as tmp:
        imsave(tmp, np.ascontiguousarray(rgba), format="png")
