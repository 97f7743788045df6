"""viewer.html written a few frames at a time: the same page, in memory bounded by the chunk and
not by the run's length, and a run longer than MAX_PAGE_FRAMES shown one frame in ``step`` (the
sixth campaign: the page of an hour-long grasp at 240 fps passed 9.7 GB)."""

from __future__ import annotations

import tracemalloc
from pathlib import Path

import numpy as np
import pytest
from viewer_runs import synthetic_run

import armanim.render.viewer.data as viewer_module
from armanim.arm.kinematics import forward
from armanim.motion.solution import Solution
from armanim.output.solved import SolvedRun
from armanim.render.settings import OutputOptions
from armanim.render.viewer import write_viewer
from armanim.render.viewer.data import viewer_data
from armanim.render.viewer.page import is_unchanged_page, viewer_html

DATA = Path(__file__).resolve().parents[1] / "data"


def synthetic(frames: int, joints: int = 5) -> tuple[SolvedRun, OutputOptions]:
    problem, trajectory, reports, settings = synthetic_run(frames, joints)
    return SolvedRun("synthetic", problem, Solution(trajectory, tuple(reports))), OutputOptions(settings)


def test_a_page_written_in_chunks_is_the_page_of_the_whole_data(tmp_path, monkeypatch):
    """Cut every 7 frames, the page is byte for byte the one made of the data as whole lists
    (the chunks' borders leave no trace) and its digest line holds."""
    run, options = synthetic(300)
    traj = run.solution.trajectory
    whole = viewer_html(viewer_data(run.problem, traj, run.solution.goals, options.render, title="synthetic"))
    monkeypatch.setattr(viewer_module, "SERIES_CHUNK", 7)
    path = write_viewer(run, options, tmp_path / "viewer.html")
    assert path.read_bytes() == whole.encode("utf-8")
    assert is_unchanged_page(path) and '"frames":300,' in whole and '"run_frames"' not in whole


def test_a_grasping_panda_s_page_is_the_same_cut_in_chunks(tmp_path, monkeypatch):
    """A run that grasps (carried object, fingers, tool orientation, self pairs): the same page
    with every list cut every 5 frames."""
    from armanim.runs.options import RunOptions
    from armanim.runs.pipeline import run_scene

    whole = run_scene(DATA / "pick-box.yaml", tmp_path / "whole", RunOptions(video=False, viewer=True))
    monkeypatch.setattr(viewer_module, "SERIES_CHUNK", 5)
    cut = run_scene(DATA / "pick-box.yaml", tmp_path / "cut", RunOptions(video=False, viewer=True))
    page = (whole.folder / "viewer.html").read_text(encoding="utf-8")
    assert '"carried":' in page and '"fingers":' in page and '"quaternion_wxyz":' in page and '"near":' in page
    assert (cut.folder / "viewer.html").read_text(encoding="utf-8") == page


def _written_peak(run: SolvedRun, options: OutputOptions, path: Path, warm: bool = True) -> tuple[int, int]:
    """(Python's peak allocation while ``run``'s page is written to ``path``, the page's size);
    ``warm``: the page written once before, so that the assets' caches are not counted (once a
    process is enough: the caches do not depend on the run)."""
    if warm:
        write_viewer(run, options, path.with_name("warm.html"))
    tracemalloc.start()
    try:
        write_viewer(run, options, path)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    return peak, path.stat().st_size


def test_a_long_run_s_page_is_written_in_memory_bounded_by_its_chunk(tmp_path):
    """Four times the frames (6,000 -> 24,000) add under a fifth of the page's growth to Python's
    peak allocation while it is written (built whole, the peak grew twelve times as fast as the
    page: every number a Python float, then the JSON, its escaped copies and the page as text)."""
    short, short_size = _written_peak(*synthetic(6_000, 7), tmp_path / "short.html")
    run, options = synthetic(24_000, 7)
    long, long_size = _written_peak(run, options, tmp_path / "viewer.html", warm=False)
    assert long_size > 3 * short_size and long_size > 8_000_000
    assert long - short < (long_size - short_size) / 5, (short, long, short_size, long_size)
    assert is_unchanged_page(tmp_path / "viewer.html")


def test_past_the_frame_bound_the_page_shows_one_frame_in_step(tmp_path, monkeypatch):
    """A run of 4,000 and one of 16,000 frames with the bound at 1,000: each page holds at most
    1,000 frames, the run's first and last among them, each page frame f the run's frame
    f x step (its joint positions those of the kinematics there), the goals' spans mapped; the
    longer run's page is about as large and its writing peaks no higher (within 2 MB)."""
    monkeypatch.setattr(viewer_module, "MAX_PAGE_FRAMES", 1_000)
    sizes, peaks = [], []
    for frames in (4_000, 16_000):
        run, options = synthetic(frames)
        traj = run.solution.trajectory
        data = viewer_data(run.problem, traj, run.solution.goals, options.render, title="t")
        step = data["step"]
        assert data["run_frames"] == frames and data["frames"] <= 1_000 and step == -(-(frames - 1) // 999)
        assert data["fps"] == traj.fps  # the run's rate: the page plays one frame in step
        kept = np.append(np.arange(0, frames, step)[: data["frames"] - 1], frames - 1)
        points = np.reshape(data["points"], (data["frames"], -1, 3))
        expected = forward(run.problem.arm, traj.phi[kept]).points
        np.testing.assert_allclose(points, expected, atol=10.0 ** -data["decimals"])
        for entry, report in zip(data["goals"], run.solution.goals):
            assert kept[entry["first"]] >= report.first_frame and kept[entry["last"]] <= report.last_frame
            assert entry["first"] == 0 or kept[entry["first"] - 1] < report.first_frame
        for key in ("goal", "distance", "clearance", "reached", "activity"):
            assert len(data[key]) == data["frames"], key
        peak, size = _written_peak(run, options, tmp_path / f"{frames}.html")
        sizes.append(size)
        peaks.append(peak)
    assert sizes[1] <= sizes[0] * 1.2  # (800 frames shown, then 942)
    assert peaks[1] - peaks[0] < 2_000_000, peaks


@pytest.mark.parametrize(
    ("frames", "limit", "step"),
    [(10, 10, 1), (11, 10, 2), (19, 10, 2), (20, 10, 3), (865_066, 36_000, 25), (5, 1, 4), (1, 1, 1)],
)
def test_the_step_is_the_smallest_that_keeps_the_frames_within_the_bound(frames, limit, step):
    from armanim.render.viewer.data import frame_step, page_frames

    kept = page_frames(frames, limit)
    assert frame_step(frames, limit) == step and len(kept) <= max(limit, 2) and kept[0] == 0 and kept[-1] == frames - 1
    if step > 1 and limit > 1:  # (a bound under 2 keeps the first and the last frame)
        smaller = np.arange(0, frames, step - 1)
        assert len(smaller) + (smaller[-1] != frames - 1) > limit


def test_an_interrupt_while_the_page_is_written_leaves_the_page_that_was_there(tmp_path, monkeypatch):
    """Ctrl-C after some of a page's blocks are written (the page now streams into its temporary
    file): the page that was there is as it was, byte for byte, and no temporary is left."""
    run, options = synthetic(3_000)
    path = write_viewer(run, options, tmp_path / "viewer.html")
    before = path.read_bytes()
    calls = []

    def interrupted(chunk: list) -> str:
        calls.append(1)
        if len(calls) == 200:  # inside the data, blocks of it already in the temporary file
            raise KeyboardInterrupt
        return real(chunk)

    import armanim.render.viewer.page as page_module

    real = page_module.json_text
    monkeypatch.setattr(page_module, "json_text", interrupted)
    monkeypatch.setattr(viewer_module, "SERIES_CHUNK", 100)
    monkeypatch.setattr(page_module, "WRITE_BLOCK", 1_000)  # blocks reach the file before the interrupt
    with pytest.raises(KeyboardInterrupt):
        write_viewer(run, options, path)
    assert path.read_bytes() == before and [p.name for p in tmp_path.iterdir()] == ["viewer.html"]
