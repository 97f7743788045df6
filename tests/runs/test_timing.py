"""timing.json (issue 49): each run's wall times, the one file that differs from rerun to rerun,
so that summary.json and trajectory.csv stay the same bytes."""

from __future__ import annotations

import json

from runfolders import small_scene

from armanim.output.rundir import MARKER


def test_timing_json_holds_the_run_s_times_and_summary_none(cli, tmp_path):
    scene = small_scene(tmp_path, "t")
    runs = []
    for out in ("a", "b"):
        assert cli("run", scene, "--out", tmp_path / out, "--no-video", "-q").exit_code == 0
        runs.append(tmp_path / out / "t")
    timing = json.loads((runs[0] / "timing.json").read_text())
    summary = json.loads((runs[0] / "summary.json").read_text())
    assert len(timing["goals"]) == len(summary["goals"]) and [g["goal"] for g in timing["goals"]] == list(
        range(len(summary["goals"]))
    )
    parts = [timing[k] for k in ("convert_s", "solve_s", "clock_s")]
    assert all(v >= 0 for v in parts + [timing["outputs_s"]] + [g["plan_time_s"] for g in timing["goals"]])
    assert abs(sum(parts) - timing["scene_to_trajectory_s"]) <= 2e-6  # each rounded to the microsecond
    assert abs(sum(g["plan_time_s"] for g in timing["goals"]) - timing["solve_s"]) <= 1e-6 * (1 + len(timing["goals"]))
    assert "timing.json" in (runs[0] / MARKER).read_text()  # armanim's file: a rerun may replace it
    for name in ("summary.json", "trajectory.csv"):
        assert (runs[0] / name).read_bytes() == (runs[1] / name).read_bytes()
    assert (
        "_time" not in (runs[0] / "summary.json").read_text()
        and "plan_time_s" not in (runs[0] / "summary.json").read_text()
    )
