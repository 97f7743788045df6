"""Compare two trajectories: the report behind ``armanim compare``, ``armanim check``
and :func:`armanim.testing.assert_trajectory_matches`.

Angles (joint angles, ``orientation_error_deg``) are compared in degrees with ``atol_deg``;
positions, distances, clearances and the tool quaternion ``qw .. qz`` with ``atol``; frame,
goal, reached and mode exactly. The diagnostic columns ``step_scale`` and ``iterations`` are
not compared. Only the expected file's columns are compared: a golden file written before a
column existed (the tool quaternion and orientation error came with goal orientations) still
checks every column it has.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from armanim.errors import Diagnostic, SceneError, shown, shown_list
from armanim.output.csvfile import TEXT_COLUMNS, TrajectoryTable, open_trajectory_csv

EXACT = ("frame", "goal", "reached", "mode")
NOT_COMPARED = ("step_scale", "iterations")


@dataclass(frozen=True)
class Comparison:
    """Outcome of :func:`compare_trajectories`.

    Attributes
    ----------
    equal : bool
        Same frame count and every compared column within tolerance.
    report : str
        Human-readable report: first differing frame and column, largest deviation
        per column, frame-count mismatch.
    """

    equal: bool
    report: str


def _tolerance(column: str, atol_deg: float, atol: float) -> float:
    if column in EXACT or column in TEXT_COLUMNS:
        return 0.0
    if (column.startswith("phi") and column.endswith("_deg")) or column == "orientation_error_deg":
        return atol_deg
    if column == "time_s":
        return 1e-9
    return atol


class _Comparer:
    """The running state of a comparison fed block by block (files of any length)."""

    def __init__(
        self,
        expected_columns,
        actual_columns,
        atol_deg: float,
        atol: float,
        names: tuple[str, str],
        files: tuple[str, str] | None = None,
    ):
        file = files[1] if files else names[1]
        n_e = sum(1 for c in expected_columns if c.startswith("phi") and c.endswith("_deg"))
        n_a = sum(1 for c in actual_columns if c.startswith("phi") and c.endswith("_deg"))
        if n_e != n_a:
            raise SceneError(file, [Diagnostic("", f"has {n_a} joints, {names[0]} has {n_e} (not the same arm)")])
        self.columns = [c for c in expected_columns if c not in NOT_COMPARED]
        missing = [c for c in self.columns if c not in actual_columns]
        if missing:
            other = files[0] if files else names[0]
            raise SceneError(file, [Diagnostic("", f"lacks {plural_columns(missing)} that {other} has")])
        self.tolerances = {c: _tolerance(c, atol_deg, atol) for c in self.columns}
        self.names = names
        self.rows = [0, 0]
        self.firsts: tuple[dict[int, int], dict[int, int]] = ({}, {})
        self.first: tuple[int, str, object, object] | None = None
        self.worst: dict[str, float] = {}

    def count(self, side: int, table: TrajectoryTable) -> None:
        """Count a block of one side's rows and note the frames where goals are first reached."""
        offset = self.rows[side]
        goal, reached = table.column("goal"), table.column("reached")
        for frame in np.nonzero(reached == 1)[0]:
            if np.isfinite(goal[frame]):
                self.firsts[side].setdefault(int(goal[frame]), offset + int(frame))
        self.rows[side] += len(table.data)

    def compare(self, expected: TrajectoryTable, actual: TrajectoryTable) -> None:
        """Compare two blocks that start at the same frame (the shorter sets the common rows)."""
        offset = min(self.rows)
        frames = min(len(expected.data), len(actual.data))
        for column in self.columns:
            if column in expected.text:
                e, a = expected.text[column][:frames], actual.text[column][:frames]
                dev = np.where(e == a, 0.0, np.inf)
            else:
                e, a = expected.column(column)[:frames], actual.column(column)[:frames]
                with np.errstate(invalid="ignore", over="ignore"):
                    dev = np.where((e == a) | (np.isnan(e) & np.isnan(a)), 0.0, np.abs(e - a))
                dev = np.where(np.isnan(dev), np.inf, dev)  # one empty, the other not
            bad = np.nonzero(dev > self.tolerances[column])[0]
            if len(bad):
                self.worst[column] = max(self.worst.get(column, 0.0), float(dev.max()))
                frame = offset + int(bad[0])
                if self.first is None or frame < self.first[0]:
                    self.first = (frame, column, e[bad[0]], a[bad[0]])

    def result(self) -> Comparison:
        """The comparison of everything fed so far."""
        fe, fa = self.rows
        if not self.worst and fe == fa:
            return Comparison(True, f"trajectories agree: {fe} frames, {len(self.columns)} columns within tolerance")
        lines = [] if fe == fa else [self._frame_count_note()]
        if self.first is not None:
            frame, column, e_val, a_val = self.first
            lines.append(
                f"first difference: frame {frame}, column {column}: {self.names[0]} {_show(e_val)}, {self.names[1]} {_show(a_val)}"
            )
            lines.append("largest deviation per column (over the common frames):")
            for column, dev in self.worst.items():
                if column in TEXT_COLUMNS:
                    lines.append(f"  {column}: the words differ")
                else:
                    lines.append(f"  {column}: {_show(dev)} (tolerance {self.tolerances[column]:g})")
        return Comparison(False, "\n".join(lines))

    def _frame_count_note(self) -> str:
        (fe, fa), (e_first, a_first) = self.rows, self.firsts
        note = f"expected {fe} frames, got {fa}"
        for goal in sorted(set(e_first) | set(a_first)):
            if goal not in a_first:
                return note + f"; goal {goal} not reached (expected at frame {e_first[goal]})"
            if goal not in e_first:
                return note + f"; goal {goal} reached at frame {a_first[goal]} (expected missed)"
            shift = e_first[goal] - a_first[goal]
            if shift:
                word = "earlier" if shift > 0 else "later"
                return note + f"; goal {goal} reached {abs(shift)} frames {word}"
        return note


def compare_trajectories(
    expected: TrajectoryTable,
    actual: TrajectoryTable,
    *,
    atol_deg: float = 1e-6,
    atol: float = 1e-6,
    names: tuple[str, str] = ("expected", "actual"),
    files: tuple[str, str] | None = None,
) -> Comparison:
    """Compare two trajectory tables column by column.

    Raises
    ------
    SceneError
        If the two do not describe the same arm (different joint counts) or lack a
        required column (exit 2: not comparable).
    """
    comparer = _Comparer(expected.columns, actual.columns, atol_deg, atol, names, files)
    comparer.compare(expected, actual)
    comparer.count(0, expected)
    comparer.count(1, actual)
    return comparer.result()


def compare_csv_files(expected: Path, actual: Path, *, atol_deg: float = 1e-6, atol: float = 1e-6) -> Comparison:
    """Compare two trajectory.csv files block by block, in memory that does not grow with their length.

    Raises
    ------
    SceneError
        A file is missing, not a trajectory, or the two are not comparable (exit 2).
    """
    with open_trajectory_csv(expected) as (e_columns, e_blocks), open_trajectory_csv(actual) as (a_columns, a_blocks):
        comparer = _Comparer(e_columns, a_columns, atol_deg, atol, ("expected", "actual"), (str(expected), str(actual)))
        pending: list[TrajectoryTable | None] = [None, None]
        streams = (e_blocks, a_blocks)
        while True:
            for side in (0, 1):  # keep a block of each side, aligned on the same frames
                held = pending[side]
                if held is None or len(held.data) == 0:
                    pending[side] = next(streams[side], None)
            e, a = pending
            if e is None or a is None:
                break
            frames = min(len(e.data), len(a.data))
            comparer.compare(e, a)
            comparer.count(0, _rows(e, 0, frames))
            comparer.count(1, _rows(a, 0, frames))
            pending = [_rows(e, frames, None), _rows(a, frames, None)]
        for side in (0, 1):  # the longer file's remaining rows are only counted
            held = pending[side]
            rest = [held] if held is not None else []
            for table in itertools.chain(rest, streams[side]):
                comparer.count(side, table)
    return comparer.result()


def plural_columns(columns: list[str]) -> str:
    """``the column 'x'``, or the first few of many and a count (a message stays one short line).

    >>> plural_columns(["c0"]), plural_columns([f"c{i}" for i in range(12000)])
    ("the column 'c0'", "the columns 'c0', 'c1', 'c2', 'c3', 'c4', 'c5', 'c6', 'c7' and 11,992 more")
    """
    return f"the column {shown(columns[0])}" if len(columns) == 1 else f"the columns {shown_list(columns)}"


def _rows(table: TrajectoryTable, start: int, stop: int | None) -> TrajectoryTable:
    return TrajectoryTable(table.columns, table.data[start:stop], {c: v[start:stop] for c, v in table.text.items()})


def _show(value) -> str:
    if isinstance(value, str):
        return repr(str(value))
    return "empty" if np.isnan(value) else f"{value:.10g}"
