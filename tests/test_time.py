"""Time has one owner: the fps the run is solved at (``render.fps`` or ``--fps``)."""

from __future__ import annotations

import json

import numpy as np

from armanim.output.csvfile import read_trajectory_csv
from armanim.runs.reload import load_run

SCENE = """\
version: 1
name: held
arm: {links: [2, 5, 5, 5]}
goals:
  - {position: [6, 0, 10], hold: 2}
  - [0, 6, 10]
render: {fps: 10, size: [64, 48]}
"""


def _held_frames(table, goal: int) -> int:
    rows = table.column("goal") == goal
    return int(np.count_nonzero(table.column("reached")[rows] == 1)) - 1  # the reaching frame, then the hold


def test_run_fps_override_holds_for_the_scenes_seconds(cli, tmp_path):
    scene = tmp_path / "held.yaml"
    scene.write_text(SCENE, encoding="utf-8")
    for fps in (10, 40):
        result = cli("run", scene, "--out", tmp_path / f"at{fps}", "--no-video", "--quiet", "--fps", fps)
        assert result.exit_code == 0, result.output
        table = read_trajectory_csv(tmp_path / f"at{fps}" / "held" / "trajectory.csv")
        assert _held_frames(table, 0) == 2 * fps  # two seconds, whatever the fps
        np.testing.assert_allclose(table.column("time_s"), np.arange(len(table.data)) / fps)
        summary = json.loads((tmp_path / f"at{fps}" / "held" / "summary.json").read_text())
        assert summary["fps"] == fps and summary["totals"]["duration_s"] == len(table.data) / fps


def test_a_finished_run_keeps_its_own_clock(cli, tmp_path):
    # solved at --fps 40 on a 10 fps scene: reading it back must not retime it at 10 fps
    scene = tmp_path / "held.yaml"
    scene.write_text(SCENE, encoding="utf-8")
    assert cli("run", scene, "--out", tmp_path, "--no-video", "--quiet", "--fps", "40").exit_code == 0
    run = load_run(tmp_path / "held")
    table = read_trajectory_csv(tmp_path / "held" / "trajectory.csv")
    assert run.solution.trajectory.fps == 40
    np.testing.assert_array_equal(run.solution.trajectory.time, table.column("time_s"))
