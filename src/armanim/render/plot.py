"""``plot.png``: how a run went, over time (matplotlib Figure + Agg, no pyplot)."""

from __future__ import annotations

from typing import Sequence

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from armanim.problem import Problem
from armanim.render.draw import GOAL_COLORS, write_png
from armanim.trajectory import GoalReport, Trajectory

PLOT_SIZE = (1200, 800)  # pixels
PLOT_DPI = 100


def plot_run(problem: Problem, trajectory: Trajectory, reports: Sequence[GoalReport], path, *, title: str) -> None:
    """Plot goal distance, clearance and joint angles over time to a PNG.

    Top: distance of the tip to the current goal, and (with obstacles) the smallest
    clearance of the arm to any obstacle, with the goals' spans shaded and marked
    reached or missed. Bottom: every joint angle in degrees, with its limits dashed.

    Parameters
    ----------
    problem : Problem
    trajectory : Trajectory
    reports : sequence of GoalReport
    path : str or Path
        The PNG (``PLOT_SIZE`` pixels), written atomically.
    title : str
    """
    width, height = PLOT_SIZE
    fig = Figure(figsize=((width + 1e-3) / PLOT_DPI, (height + 1e-3) / PLOT_DPI), dpi=PLOT_DPI,
                 layout="constrained")
    canvas = FigureCanvasAgg(fig)
    top, bottom = fig.subplots(2, 1, sharex=True)
    fig.suptitle(title, fontweight="bold")
    t = trajectory.time
    _goal_spans(top, trajectory, reports)
    top.plot(t, trajectory.distance, color="C0", label="distance to goal")
    if len(problem.obstacles) and np.isfinite(trajectory.clearance).any():
        top.plot(t, trajectory.clearance, color="C3", label="clearance to obstacles")
        top.axhline(0.0, color="C3", linewidth=0.8, linestyle=":")
    top.set_ylabel("scene units")
    top.legend(loc="upper right", fontsize=9)
    top.grid(alpha=0.3)
    degrees = np.degrees(trajectory.phi)
    limits = problem.limits
    for j in range(degrees.shape[1]):
        color = f"C{j % 10}"
        bottom.plot(t, degrees[:, j], color=color, label=f"phi{j + 1}")
        if np.isfinite(limits.lower[j]):
            for bound in (limits.lower[j], limits.upper[j]):
                bottom.axhline(np.degrees(bound), color=color, linestyle="--", linewidth=0.8, alpha=0.7)
    bottom.set_ylabel("joint angle (deg)")
    bottom.set_xlabel("time (s)")
    bottom.legend(loc="upper right", fontsize=9, ncols=min(degrees.shape[1], 6))
    bottom.grid(alpha=0.3)
    canvas.draw()
    write_png(np.asarray(canvas.buffer_rgba()), path)


def _goal_spans(ax, trajectory: Trajectory, reports: Sequence[GoalReport]) -> None:
    """Shade each goal's frames, green if reached, red if missed, and label it."""
    fps = trajectory.fps
    for r in reports:
        if r.first_frame < 0:
            continue
        color = GOAL_COLORS["reached" if r.reached else "missed"]
        ax.axvspan(r.first_frame / fps, (r.last_frame + 1) / fps, color=color, alpha=0.08, linewidth=0)
        ax.axvline(r.first_frame / fps, color=color, linewidth=0.8, alpha=0.6)
        label = f"goal {r.index + 1}" + ("" if r.reached else " (missed)")
        ax.text(r.first_frame / fps, 1.0, " " + label, transform=ax.get_xaxis_transform(), va="top",
                fontsize=8, color=color)
