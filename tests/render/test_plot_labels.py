"""plot.png names a URDF's joints as the URDF does, rounds its limits, and draws the tool's
orientation error where goals have an orientation (issue 38's legibility list)."""

from __future__ import annotations

from pathlib import Path

from armanim.motion.trajectory import solve_trajectory
from armanim.render.pictures.plot import plot_figure
from armanim.scene import load_scene, scene_to_problem

SCENES = Path(__file__).resolve().parents[2] / "scenes"


def _figure(name: str):
    problem = scene_to_problem(load_scene(SCENES / f"{name}.yaml").model)
    solution = solve_trajectory(problem)
    return plot_figure(problem, solution.trajectory, solution.goals, title=name).figure


def test_a_robots_plot_names_its_joints_rounds_its_limits_and_shows_the_orientation_error():
    fig = _figure("panda-place")
    top, angles = fig.axes[0], fig.axes[1]
    assert [line.get_label() for line in angles.get_lines() if not line.get_label().startswith("_")][:2] == [
        "panda_joint1", "panda_joint2"]
    limits = [t.get_text() for t in angles.texts]
    assert any(t.endswith("max 166") for t in limits) and not any("166.0" in t for t in limits)
    twins = [ax for ax in fig.axes if ax is not top and ax.get_shared_x_axes().joined(ax, top) and ax.get_ylabel() == "degrees"]
    assert len(twins) == 1 and twins[0].get_lines()[0].get_label() == "orientation error (deg)"
    assert "orientation error (deg)" in [t.get_text() for t in top.get_legend().get_texts()]


def test_an_arm_of_links_keeps_phi_names_and_no_orientation_axis():
    fig = _figure("notes-arm")
    labels = [line.get_label() for line in fig.axes[1].get_lines() if not line.get_label().startswith("_")]
    assert labels[0] == "phi1" and not any(ax.get_ylabel() == "degrees" for ax in fig.axes)
