"""trajectory.csv written a chunk of rows at a time: the same bytes, in memory bounded by the chunk,
not by the run's length (the sixth campaign: an hour-long grasp at 240 fps passed 4 GB
building the file as one string)."""

from __future__ import annotations

import tracemalloc
from dataclasses import fields, replace
from pathlib import Path

import numpy as np
import pytest

from armanim.output.csvfile import read_trajectory_csv, trajectory_csv_chunks, trajectory_csv_text, write_trajectory_csv
from armanim.output.solved import SolvedRun
from armanim.runs.options import RunOptions
from armanim.runs.pipeline import run_scene

DATA = Path(__file__).resolve().parents[1] / "data"


@pytest.fixture(scope="module")
def pick_run(tmp_path_factory):
    """A run that grasps (the columns held, carried_clearance, gripper_m) and the file it wrote."""
    result = run_scene(DATA / "pick-box.yaml", tmp_path_factory.mktemp("pick"), RunOptions(video=False))
    return SolvedRun("pick-box", result.problem, result.solution), result.files["trajectory"]


def test_a_grasping_run_written_in_chunks_is_the_file_the_run_wrote(pick_run, tmp_path):
    """Cut every row, every 13 rows or not at all, the bytes are the run's (and the text the goldens are
    compared with): the chunks' borders leave no trace."""
    run, written = pick_run
    traj = run.solution.trajectory
    assert run.solution.carry is not None and traj.frames > 50
    for rows in (1, 13, traj.frames):
        write_trajectory_csv(run, tmp_path / "t.csv", chunk_rows=rows)
        assert (tmp_path / "t.csv").read_bytes() == written.read_bytes(), rows
    whole = trajectory_csv_text(traj, run.problem.arm.prismatic)
    assert len(list(trajectory_csv_chunks(traj, run.problem.arm.prismatic, chunk_rows=13))) == 1 + -(-traj.frames // 13)
    assert "".join(trajectory_csv_chunks(traj, run.problem.arm.prismatic, chunk_rows=13)) == whole
    assert [p.name for p in tmp_path.iterdir()] == ["t.csv"]  # no temporary left


def stretched(run: SolvedRun, frames: int) -> SolvedRun:
    """``run`` with its frames repeated to ``frames`` (each array field indexed alike)."""
    traj = run.solution.trajectory
    index = np.arange(frames) % traj.frames
    long = replace(
        traj,
        **{f.name: getattr(traj, f.name)[index] for f in fields(traj) if isinstance(getattr(traj, f.name), np.ndarray)},
    )
    return replace(run, solution=replace(run.solution, trajectory=long))


def _written_peak(run: SolvedRun, path: Path) -> tuple[int, int]:
    """(Python's peak allocation while ``run``'s trajectory.csv is written to ``path``, the file's size)."""
    tracemalloc.start()
    try:
        write_trajectory_csv(run, path)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    return peak, path.stat().st_size


def test_a_long_run_is_written_in_memory_bounded_by_its_chunk(pick_run, tmp_path):
    """Four times the frames of a grasping run (10,000 -> 40,000: 5 and 20 chunks) add under a tenth of the file's
    growth to Python's peak allocation while its trajectory.csv is written (built whole, the peak
    grew seven times as fast as the file: 233 MB for a 32 MB file)."""
    short, short_size = _written_peak(stretched(pick_run[0], 10_000), tmp_path / "short.csv")
    run = stretched(pick_run[0], 40_000)
    long, long_size = _written_peak(run, tmp_path / "trajectory.csv")
    assert long_size > 20_000_000 and long_size > 3.9 * short_size
    assert long - short < (long_size - short_size) / 10, (short, long, short_size, long_size)
    table = read_trajectory_csv(tmp_path / "trajectory.csv")
    np.testing.assert_array_equal(table.column("frame"), np.arange(40_000))
    np.testing.assert_array_equal(
        np.radians(table.angles_deg)[-1], np.radians(np.degrees(run.solution.trajectory.phi[-1]))
    )
