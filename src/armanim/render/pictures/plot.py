"""``plot.png``: how a run went, over time (matplotlib Figure + Agg, no pyplot)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from armanim.motion.problem import Limits, Problem
from armanim.motion.solution import GoalReport, Trajectory
from armanim.output.numbers import length_unit
from armanim.output.solved import SolvedRun
from armanim.render.paint.pixels import write_png
from armanim.render.paint.style import GOAL_COLORS
from armanim.render.settings import OutputOptions

PLOT_SIZE = (1200, 800)  # pixels
PLOT_DPI = 100


def plot_run(run: SolvedRun, options: OutputOptions, path) -> None:
    """Plot goal distance, clearance and joint angles over time to a PNG.

    Top: distance of the tip to the current goal, and (with obstacles) the smallest
    clearance of the arm to any obstacle, with the goals' spans shaded, numbered from 0
    as in the video and the files, and marked reached or missed. Middle: every joint
    angle in degrees, with its limits dashed in the joint's colour and labelled. Bottom:
    every joint's speed as a share of its limit.

    Parameters
    ----------
    run : SolvedRun
        The run; its name is the title.
    options : OutputOptions
        Not used: the plot has its own size (``PLOT_SIZE`` pixels).
    path : str or Path
        The PNG, written atomically.
    """
    canvas = plot_figure(run.problem, run.trajectory, run.reports, title=run.name)
    canvas.figure.draw_without_rendering()  # the layout and the texts' boxes, without a third of a draw's time
    separate_labels(canvas.figure.axes[1], canvas.get_renderer())
    canvas.draw()
    write_png(np.asarray(canvas.buffer_rgba()), path)


LABEL_GAP_PX = 1.0


def separate_labels(ax, renderer) -> bool:
    """Move the limit labels of ``ax`` (drawn once: their boxes are known) up or down, fewest pixels,
    until no two overlap: labels of close limits were printed on top of each other
    (``panda_joint4 max -4`` over ``panda_joint6 min -1``, issue 50). Returns whether any moved.

    Each label keeps its side of its line where it can; the overlaps are removed in order from the
    bottom, each box pushed just above the one below it, then the stack shifted down as a whole where
    it ran past the axes' top."""
    texts = [t for t in ax.texts if getattr(t, "limit_label", False)]
    if len(texts) < 2:
        return False
    boxes = [t.get_window_extent(renderer) for t in texts]
    order = sorted(range(len(texts)), key=lambda k: boxes[k].y0)
    y0 = np.array([boxes[k].y0 for k in order])
    height = np.array([boxes[k].height for k in order])
    placed = y0.copy()
    for i in range(1, len(order)):
        placed[i] = max(placed[i], placed[i - 1] + height[i - 1] + LABEL_GAP_PX)
    top = ax.get_window_extent(renderer).y1
    overshoot = placed[-1] + height[-1] - top
    if overshoot > 0:  # the stack ran off the top: push it down, never below the axes' bottom
        placed = np.maximum(placed - overshoot, np.minimum(y0, placed))
        for i in range(len(order) - 2, -1, -1):
            placed[i] = min(placed[i], placed[i + 1] - height[i] - LABEL_GAP_PX)
    moved = placed - y0
    if not np.any(np.abs(moved) > 0.01):
        return False
    from matplotlib.transforms import ScaledTranslation

    fig = ax.figure
    for k, dy in zip(order, moved):
        texts[k].set_transform(ax.get_yaxis_transform() + ScaledTranslation(0.0, dy / fig.dpi, fig.dpi_scale_trans))
    return True


def plot_figure(
    problem: Problem, trajectory: Trajectory, reports: Sequence[GoalReport], *, title: str
) -> FigureCanvasAgg:
    """The figure of :func:`plot_run`, on its Agg canvas, not yet drawn."""
    width, height = PLOT_SIZE
    fig = Figure(figsize=((width + 1e-3) / PLOT_DPI, (height + 1e-3) / PLOT_DPI), dpi=PLOT_DPI, layout="constrained")
    canvas = FigureCanvasAgg(fig)
    top, bottom, speeds = fig.subplots(3, 1, sharex=True, height_ratios=(1, 1, 0.7))
    fig.suptitle(title, fontweight="bold")
    t = trajectory.time
    _goal_spans(top, trajectory, reports)
    top.plot(t, trajectory.distance, color="C0", label="distance to goal")
    if len(problem.obstacles) and np.isfinite(trajectory.clearance).any():
        top.plot(t, trajectory.clearance, color="C3", label="clearance to obstacles")
        top.axhline(0.0, color="C3", linewidth=0.8, linestyle=":")
    top.set_ylabel("metres" if length_unit(problem.arm) == "m" else "scene units")
    handles = _orientation_curve(top, trajectory)
    named = [line for line in top.get_lines() if not line.get_label().startswith("_")]  # not the goals' span edges
    top.legend(handles=named + handles, loc="upper right", fontsize=9)
    top.grid(alpha=0.3)
    degrees = np.degrees(trajectory.phi)
    names = joint_labels(problem.arm.joint_names, degrees.shape[1])
    slides = problem.arm.slides
    for j in np.nonzero(~slides)[0]:
        bottom.plot(t, degrees[:, j], color=f"C{j % 10}", label=names[j])
    limits, joint_handles = problem.limits, None
    if slides.any():  # the prismatic joints in metres, on the right axis
        limits = Limits(np.where(slides, -np.inf, limits.lower), np.where(slides, np.inf, limits.upper), limits.margin)
        joint_handles = bottom.get_lines() + _slide_curves(bottom, t, trajectory.phi, problem, names)
    _limit_lines(bottom, limits, names)
    bottom.set_ylabel("joint angle (deg)")
    # beside the panel, not in it: inside, its rows covered the limit labels at the right (issue 50);
    # past the right axis's metres where prismatic joints have one
    bottom.legend(
        handles=joint_handles,
        loc="upper left",
        bbox_to_anchor=(1.07 if slides.any() else 1.005, 1.0),
        fontsize=8,
        ncols=max(1, -(-degrees.shape[1] // 12)),
        borderaxespad=0.0,
    )
    bottom.grid(alpha=0.3)
    _speed_panel(speeds, problem, trajectory)
    _passes(speeds, trajectory, reports)
    speeds.set_xlabel("time (s)")
    return canvas


def _slide_curves(ax, t: np.ndarray, phi: np.ndarray, problem: Problem, names: list[str]) -> list:
    """The prismatic joints' values (metres) on a right axis of the joint panel, dashed, their limits
    dotted and labelled at the left end; their curves (the legend's handles)."""
    right = ax.twinx()
    curves = []
    for j in np.nonzero(problem.arm.slides)[0]:
        curves += right.plot(t, phi[:, j], color=f"C{j % 10}", linestyle="--", label=f"{names[j]} (m, right)")
        for value, side in ((problem.limits.lower[j], "min"), (problem.limits.upper[j], "max")):
            if np.isfinite(value):
                right.axhline(value, color=f"C{j % 10}", linewidth=1.0, alpha=0.8, linestyle=":")
                right.text(
                    0.005,
                    value,
                    f"{names[j]} {side} {value:.3g} m",
                    transform=right.get_yaxis_transform(),
                    ha="left",
                    va="bottom",
                    fontsize=8,
                    color=f"C{j % 10}",
                )
    right.set_ylabel("prismatic joint (m)")
    return curves


def joint_labels(joint_names, n: int) -> list[str]:
    """The joints' names in the plot: a URDF's own (``panda_joint1``), else ``phi1`` ...

    >>> joint_labels(("a", "b"), 2), joint_labels((), 2)
    (['a', 'b'], ['phi1', 'phi2'])
    """
    return list(joint_names) if len(joint_names) == n else [f"phi{j + 1}" for j in range(n)]


def _orientation_curve(ax, trajectory: Trajectory) -> list:
    """The tool's angle to its goal's orientation (degrees, right axis) where goals have one;
    its legend handles (none in a run without oriented goals)."""
    if trajectory.orientation_error is None or not np.isfinite(trajectory.orientation_error).any():
        return []
    right = ax.twinx()
    right.plot(
        trajectory.time,
        np.degrees(trajectory.orientation_error),
        color="C4",
        linewidth=1.0,
        label="orientation error (deg)",
    )
    right.set_ylabel("degrees")
    right.set_ylim(bottom=0.0)
    return right.get_lines()


def _speed_panel(ax, problem: Problem, trajectory: Trajectory) -> None:
    """Each joint's speed as a percentage of its ``max_joint_speed`` (the clock's velocities; the
    frames' differences for a run from before the clock), the limit at 100 %."""
    if trajectory.velocity is not None:
        velocity = trajectory.velocity
    else:
        velocity = np.vstack([np.zeros((1, trajectory.phi.shape[1])), np.diff(trajectory.phi, axis=0) * trajectory.fps])
    share = 100 * np.abs(velocity) / problem.rates.speed
    for j in range(share.shape[1]):
        ax.plot(trajectory.time, share[:, j], color=f"C{j % 10}", linewidth=1.0)
    ax.axhline(100.0, color="0.25", linewidth=1.0, linestyle="--")
    ax.text(
        0.995,
        100.0,
        "speed limit",
        transform=ax.get_yaxis_transform(),
        ha="right",
        va="bottom",
        fontsize=8,
        color="0.25",
    )
    ax.set_ylim(0, max(110.0, float(share.max()) * 1.05))
    ax.set_ylabel("joint speed (% of limit)")
    ax.grid(alpha=0.3)


def _passes(ax, trajectory: Trajectory, reports: Sequence[GoalReport]) -> None:
    """Each goal passed without stopping (``blend``): a dotted line at its pass frame, labelled
    ``passing k``, where the speed panel shows the joints still moving."""
    for r in reports:
        blend = getattr(r, "blend", None)
        if blend is None or not blend.blended or r.last_frame < 0:
            continue
        at = float(trajectory.time[r.last_frame])
        ax.axvline(at, color="C2", linewidth=0.9, linestyle=":")
        ax.text(
            at,
            0.97,
            f" passing {r.index}",
            transform=ax.get_xaxis_transform(),
            ha="left",
            va="top",
            fontsize=8,
            color="C2",
        )


def limit_groups(lower: np.ndarray, upper: np.ndarray) -> list[tuple[float, str, list[int]]]:
    """Every finite limit as (degrees, "min" or "max", joints sharing it), 0-based joints.

    >>> limit_groups(np.radians([-np.inf, -100, -150, -150]), np.radians([np.inf, 100, 150, 150]))
    [(-150.0, 'min', [2, 3]), (-100.0, 'min', [1]), (100.0, 'max', [1]), (150.0, 'max', [2, 3])]
    """
    groups: dict[tuple[float, str], list[int]] = {}
    for side, values in (("min", lower), ("max", upper)):
        for j, v in enumerate(values):
            if np.isfinite(v):
                groups.setdefault((round(float(np.degrees(v)), 6), side), []).append(j)
    return [(value, side, joints) for (value, side), joints in sorted(groups.items())]


def _limit_lines(ax, limits, names: list[str]) -> None:
    """Each limit dashed in its joint's colour (joints sharing a value take turns along
    the dashes) and labelled at the right end, rounded to 0.1 degree, e.g. "phi3, phi4 max 150"."""
    dash = 5.0
    for value, side, joints in limit_groups(limits.lower, limits.upper):
        k = len(joints)
        for i, j in enumerate(joints):
            ax.axhline(
                value, color=f"C{j % 10}", linewidth=1.0, alpha=0.8, linestyle=(i * dash, (dash, dash * (2 * k - 1)))
            )
        label = ", ".join(names[j] for j in joints)
        color = f"C{joints[0] % 10}" if k == 1 else "0.25"
        text = ax.text(
            0.995,
            value,
            f"{label} {side} {round(value, 1):g}",
            transform=ax.get_yaxis_transform(),
            ha="right",
            va="bottom" if side == "max" else "top",
            fontsize=8,
            color=color,
            bbox=dict(facecolor="white", alpha=0.75, edgecolor="none", pad=0.4),
        )  # readable over a line
        text.limit_label = True  # (moved apart from its neighbours once drawn: separate_labels)


def _goal_spans(ax, trajectory: Trajectory, reports: Sequence[GoalReport]) -> None:
    """Shade each goal's frames, green if reached, red if missed, and label it."""
    fps = trajectory.fps
    for r in reports:
        if r.first_frame < 0:
            continue
        color = GOAL_COLORS["reached" if r.reached else "missed"]
        ax.axvspan(r.first_frame / fps, (r.last_frame + 1) / fps, color=color, alpha=0.08, linewidth=0)
        ax.axvline(r.first_frame / fps, color=color, linewidth=0.8, alpha=0.6)
        label = f"goal {r.index}" + ("" if r.reached else " (missed)")
        ax.text(
            r.first_frame / fps, 1.0, " " + label, transform=ax.get_xaxis_transform(), va="top", fontsize=8, color=color
        )
