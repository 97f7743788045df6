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
        "panda_joint1",
        "panda_joint2",
    ]
    limits = [t.get_text() for t in angles.texts]
    assert any(t.endswith("max 166") for t in limits) and not any("166.0" in t for t in limits)
    twins = [
        ax
        for ax in fig.axes
        if ax is not top and ax.get_shared_x_axes().joined(ax, top) and ax.get_ylabel() == "degrees"
    ]
    assert len(twins) == 1 and twins[0].get_lines()[0].get_label() == "orientation error (deg)"
    assert "orientation error (deg)" in [t.get_text() for t in top.get_legend().get_texts()]


def test_an_arm_of_links_keeps_phi_names_and_no_orientation_axis():
    fig = _figure("notes-arm")
    labels = [line.get_label() for line in fig.axes[1].get_lines() if not line.get_label().startswith("_")]
    assert labels[0] == "phi1" and not any(ax.get_ylabel() == "degrees" for ax in fig.axes)


def test_limit_labels_and_the_joint_legend_never_overlap():
    """Issue 50: panda-place's legend covered ``panda_joint6 max 215`` and the 166 line, and
    ``... min -166`` printed on ``panda_joint4 min -176``, ``max -4`` on ``min -1``."""
    from armanim.render.pictures.plot import separate_labels

    fig = _figure("panda-place")
    canvas = fig.canvas
    canvas.draw()
    angles = fig.axes[1]
    separate_labels(angles, canvas.get_renderer())
    canvas.draw()
    renderer = canvas.get_renderer()
    labels = [t for t in angles.texts if getattr(t, "limit_label", False)]
    boxes = [t.get_window_extent(renderer) for t in labels]
    assert len(boxes) == 8  # the Panda's 14 limits: 166 and -166 shared by four joints
    for i in range(len(boxes)):
        for j in range(i):
            assert not boxes[i].overlaps(boxes[j]), (labels[i].get_text(), labels[j].get_text())
    legend = angles.get_legend().get_window_extent(renderer)
    assert not any(legend.overlaps(box) for box in boxes)
    assert legend.x0 >= angles.get_window_extent(renderer).x1  # beside the panel, not over its lines
