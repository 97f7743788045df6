"""What a run reads back (issue 36): deeply nested summaries and golden JSON, golden CSVs with
thousands of columns, index.csv cells that could start a formula, `view --out` inside the run
folder, and `render` at another fps keeping the run's seconds.

Each test is named in docs/reliability.md, which it keeps true.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from armanim.scene import scene_to_problem, validate_scene_text

ARM = "version: 1\narm: {links: [1, 1, 1, 1]}\n"


SMALL = ARM + "goals: [[1, 1, 2]]\nrender: {fps: 10, size: [64, 48]}\nsolver: {max_frames_per_goal: 40}\n"


@pytest.fixture()
def finished_run(cli, tmp_path) -> Path:
    (tmp_path / "deep.yaml").write_text(SMALL + "name: deep\n")
    cli("run", tmp_path / "deep.yaml", "--out", tmp_path / "o", "--no-video", "--quiet")
    return tmp_path / "o" / "deep"


@pytest.mark.parametrize("text", ["[" * 1500 + "]" * 1500, '{"goals":' * 50_000 + "1" + "}" * 50_000])
@pytest.mark.parametrize("command", ["view", "render"])
def test_a_deeply_nested_summary_is_one_line_and_exit_2(cli, finished_run, text, command):
    (finished_run / "summary.json").write_text(text)
    result = cli(command, finished_run)
    assert result.exit_code == 2
    assert result.stderr.strip() == f"{finished_run / 'summary.json'}: is not an armanim summary: nested too deep"


def test_a_deeply_nested_golden_json_is_ignored(cli, tmp_path):
    (tmp_path / "deep.yaml").write_text(SMALL + "name: deep\n")
    assert cli("check", tmp_path / "deep.yaml", "--golden", tmp_path / "g", "--update", "--quiet").exit_code == 0
    (tmp_path / "g" / "deep.json").write_text("[" * 40_000 + "]" * 40_000)
    assert cli("check", tmp_path / "deep.yaml", "--golden", tmp_path / "g").exit_code == 0


def test_index_csv_cells_never_start_a_formula(cli, tmp_path):
    import csv

    names = ['=HYPERLINK("http:__x","open")+1', "@SUM(1+1)", "+1", "-cmd", "\tx"]
    for k, stem in enumerate(names):
        (tmp_path / f"{stem}.yaml").write_text(
            SMALL + f"name: s{k}\n" + ("goals: [[1, 1, 99]]\n" if k == 1 else "")
        )  # k=1: invalid
    (tmp_path / "-bad.yaml").write_text("version: 1\n")  # an invalid scene: its stem and message are cells too
    result = cli(
        "run", *sorted(tmp_path.glob("*.yaml")), "--out", tmp_path / "o", "--no-video", "--jobs", "1", "--quiet"
    )
    assert result.exit_code == 2
    cells = [c for row in csv.reader((tmp_path / "o" / "index.csv").open(newline="")) for c in row]
    assert not [c for c in cells if c[:1] in ("=", "+", "-", "@", "\t", "\r")]
    assert {"'-bad", "'@SUM(1+1)"} <= set(cells)  # the stems of the invalid scenes, kept as text


def test_view_out_inside_the_run_folder_is_refused(cli, finished_run):
    result = cli("view", finished_run, "--out", finished_run / "extra.html")
    assert result.exit_code == 2 and "inside the run folder" in result.stderr
    assert not (finished_run / "extra.html").exists()
    assert cli("view", finished_run, "--out", finished_run / "viewer.html").exit_code == 0


def test_a_golden_csv_with_thousands_of_extra_columns_is_a_short_message_naming_the_file(cli, tmp_path):
    (tmp_path / "wide.yaml").write_text(SMALL + "name: wide\n")
    cli("check", tmp_path / "wide.yaml", "--golden", tmp_path / "g", "--update", "--quiet")
    golden = tmp_path / "g" / "wide.csv"
    rows = golden.read_text().splitlines()
    extra = 12_000
    golden.write_text(
        "\n".join(
            [rows[0] + "," + ",".join(f"c{i}" for i in range(extra))]
            + [r + "," + ",".join(["0"] * extra) for r in rows[1:]]
        )
        + "\n"
    )
    result = cli("check", tmp_path / "wide.yaml", "--golden", tmp_path / "g")
    assert (
        result.exit_code == 2
        and len(result.stderr) < 400
        and str(golden) in result.stderr
        and "11,992 more" in result.stderr
    )


def test_resampled_frames_keep_the_run_s_poses_at_its_own_times():
    from armanim.motion.trajectory import solve_trajectory
    from armanim.runs.resample import resample_run

    problem = scene_to_problem(validate_scene_text(SMALL.replace("[[1, 1, 2]]", "[[1, 1, 2], [-1, 1, 2]]"), "s.yaml"))
    solution = solve_trajectory(problem)
    src = solution.trajectory
    double = resample_run(problem, solution, 2 * src.fps)
    assert double.trajectory.frames == 2 * src.frames - 1
    assert np.allclose(double.trajectory.time[-1], src.time[-1])
    assert np.allclose(double.trajectory.phi[::2], src.phi)  # the run's own poses, at their own seconds
    assert np.allclose(double.trajectory.phi[1::2], 0.5 * (src.phi[:-1] + src.phi[1:]))  # limited-free here: none wrap
    assert np.allclose(double.trajectory.tip[::2], src.tip) and np.array_equal(double.trajectory.goal[::2], src.goal)
    for before, after in zip(solution.goals, double.goals):
        heads = 2 * before.first_frame - (
            1 if before.index else 0
        )  # the in-between frame heads for the next goal's first
        assert (after.first_frame, after.last_frame, after.reached) == (heads, 2 * before.last_frame, before.reached)
    half = resample_run(problem, solution, src.fps / 2)
    assert np.isclose(half.trajectory.time[-1], src.time[-1]) and np.allclose(half.trajectory.phi[-1], src.phi[-1])


@pytest.mark.slow
def test_render_at_another_fps_keeps_the_run_s_real_time(cli, finished_run):
    import imageio_ffmpeg

    own = (
        imageio_ffmpeg.count_frames_and_secs(str(finished_run / "animation.mp4"))
        if (finished_run / "animation.mp4").exists()
        else None
    )
    frames = len((finished_run / "trajectory.csv").read_text().splitlines()) - 1
    for fps in (25, 5):
        assert (
            cli("render", finished_run, "--fps", fps, "--out", finished_run.parent / f"r{fps}", "--quiet").exit_code
            == 0
        )
        count, seconds = imageio_ffmpeg.count_frames_and_secs(str(finished_run.parent / f"r{fps}" / "animation.mp4"))
        assert abs(count / fps - frames / 10) <= 2 / fps, (count, frames, own)


def test_render_at_an_fps_beyond_the_frame_limit_is_refused_before_drawing(cli, tmp_path):
    (tmp_path / "slow.yaml").write_text(
        ARM + "name: slow\ngoals: [{position: [1, 1, 2], hold: 3600}]\nrender: {fps: 0.01, size: [64, 48]}\n"
    )
    assert cli("run", tmp_path / "slow.yaml", "--out", tmp_path / "o", "--no-video", "--quiet").exit_code == 0
    result = cli("render", tmp_path / "o" / "slow", "--fps", 240, "--out", tmp_path / "r")
    assert result.exit_code == 2 and "expected at most 1,000,000" in result.stderr and not (tmp_path / "r").exists()
