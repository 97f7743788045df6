"""Helpers for users' own pytest suites.

>>> from armanim.testing import assert_trajectory_matches  # doctest: +SKIP
>>> assert_trajectory_matches("scenes/arm.yaml", "tests/golden/arm.csv")  # doctest: +SKIP
"""

from __future__ import annotations

from pathlib import Path

from armanim.output.compare import compare_trajectories
from armanim.output.csvfile import parse_trajectory_csv, read_trajectory_csv
from armanim.runs.golden import golden_paths, scene_change_note, solve_csv_text
from armanim.scene import load_scene


def assert_trajectory_matches(
    scene: str | Path, golden: str | Path, *, atol_deg: float = 1e-6, atol: float = 1e-6
) -> None:
    """Run ``scene`` (no video) and assert its trajectory matches the ``golden`` CSV.

    Parameters
    ----------
    scene : path of the scene file
    golden : path of the expected trajectory.csv, or the golden folder of ``armanim check
        --update``, where the file is named after the scene's ``name:`` (default: its stem)
    atol_deg : tolerance on joint angles, degrees
    atol : tolerance on positions, distances and clearances, scene units

    Raises
    ------
    AssertionError
        With the same report as ``armanim compare``: the first differing frame and
        column, the largest deviation per column, a frame-count mismatch; and, as
        ``armanim check`` says it, a note when the scene changed since the golden file
        was written (its ``.json`` beside it records the scene's sha256).
    """
    loaded = load_scene(scene)
    if Path(golden).is_dir():
        golden = golden_paths(Path(golden), loaded.name)[0]
    expected = read_trajectory_csv(Path(golden))
    actual = parse_trajectory_csv(solve_csv_text(loaded), f"{scene} (this run)")
    result = compare_trajectories(expected, actual, atol_deg=atol_deg, atol=atol, names=("golden", "actual"))
    if not result.equal:
        note = scene_change_note(loaded, Path(golden).with_suffix(".json"))
        raise AssertionError(f"{scene} does not match {golden}:\n{result.report}" + (f"\nnote: {note}" if note else ""))
