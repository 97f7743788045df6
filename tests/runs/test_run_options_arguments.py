"""What a program asks of a run (:class:`armanim.RunOptions`) is refused as the command's flags are
(campaign 16): an ArmanimError with exit code 2 naming the field, never a ZeroDivisionError from
the pictures or a worker count taken silently."""

from __future__ import annotations

import pytest

from armanim import RenderOverrides, RunOptions, run_scene
from armanim.errors import UsageError


@pytest.mark.parametrize(
    "options, says",
    [
        (dict(jobs=0), "jobs: expected at least 1"),
        (dict(jobs=-3), "jobs: expected at least 1"),
        (dict(render=RenderOverrides(size=(0, 0))), "RenderOverrides.size: must be >= 16"),
        (dict(render=RenderOverrides(fps=float("nan"))), "RenderOverrides.fps: must be a finite number"),
        (dict(render=RenderOverrides(fps=0.0)), "RenderOverrides.fps"),
        (dict(render=RenderOverrides(azimuth=float("inf"))), "RenderOverrides.azimuth"),
    ],
)
def test_run_options_no_run_can_use_are_refused(options, says):
    with pytest.raises(UsageError, match=says) as raised:
        RunOptions(**options)
    assert raised.value.exit_code == 2


def test_a_run_at_a_size_of_0_is_refused_before_it_solves(tmp_path):
    """Campaign 16: ``run_scene(..., RunOptions(render=RenderOverrides(size=(0, 0))))`` solved the
    scene and ended in a ZeroDivisionError while drawing the plot."""
    scene = tmp_path / "s.yaml"
    scene.write_text("version: 1\nname: s\narm: {links: [1, 1, 1]}\ngoals: [[1, 1, 1]]\n")
    with pytest.raises(UsageError):
        run_scene(scene, tmp_path / "o", RunOptions(render=RenderOverrides(size=(0, 0))))
    assert not (tmp_path / "o").exists()
