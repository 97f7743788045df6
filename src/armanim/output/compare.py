"""Compare two trajectories: the report behind ``armanim compare``, ``armanim check``
and :func:`armanim.testing.assert_trajectory_matches`.

Angles are compared in degrees with ``atol_deg``; positions, distances and
clearances in scene units with ``atol``; frame, goal, reached and mode exactly. The
diagnostic columns ``step_scale`` and ``iterations`` are not compared.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from armanim.errors import Diagnostic, SceneError
from armanim.output.csvfile import TrajectoryTable

EXACT = ("frame", "goal", "reached", "mode")
LENGTHS = ("x", "y", "z", "goal_distance", "clearance")
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
    if column in EXACT:
        return 0.0
    if column.startswith("phi") and column.endswith("_deg"):
        return atol_deg
    if column == "time_s":
        return 1e-9
    return atol


def _first_reached(table: TrajectoryTable) -> dict[int, int]:
    goal, reached = table.column("goal"), table.column("reached")
    firsts: dict[int, int] = {}
    for frame in np.nonzero(reached == 1)[0]:
        firsts.setdefault(int(goal[frame]), int(frame))
    return firsts


def _frame_count_note(expected: TrajectoryTable, actual: TrajectoryTable) -> str:
    fe, fa = len(expected.data), len(actual.data)
    note = f"expected {fe} frames, got {fa}"
    e_first, a_first = _first_reached(expected), _first_reached(actual)
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
) -> Comparison:
    """Compare two trajectory tables column by column.

    Raises
    ------
    SceneError
        If the two do not describe the same arm (different joint counts) or lack a
        required column (exit 2: not comparable).
    """
    if expected.n_joints != actual.n_joints:
        raise SceneError(names[1], [Diagnostic("", f"has {actual.n_joints} joints, {names[0]} has {expected.n_joints} (not the same arm)")])
    columns = [c for c in expected.columns if c not in NOT_COMPARED]
    missing = [c for c in columns if c not in actual.columns]
    if missing:
        raise SceneError(names[1], [Diagnostic("", f"lacks the column(s) {', '.join(missing)}")])
    frames = min(len(expected.data), len(actual.data))
    lines: list[str] = []
    first: tuple[int, str] | None = None
    worst: list[tuple[str, float, float]] = []
    for column in columns:
        e = expected.column(column)[:frames]
        a = actual.column(column)[:frames]
        both_empty = np.isnan(e) & np.isnan(a)
        dev = np.where(both_empty, 0.0, np.abs(e - a))
        dev = np.where(np.isnan(dev), np.inf, dev)  # one empty, the other not
        tol = _tolerance(column, atol_deg, atol)
        bad = np.nonzero(dev > tol)[0]
        if len(bad):
            worst.append((column, float(dev.max()), tol))
            if first is None or bad[0] < first[0]:
                first = (int(bad[0]), column)
    equal = not worst and len(expected.data) == len(actual.data)
    if equal:
        return Comparison(True, f"trajectories agree: {frames} frames, {len(columns)} columns within tolerance")
    if len(expected.data) != len(actual.data):
        lines.append(_frame_count_note(expected, actual))
    if first is not None:
        frame, column = first
        e_val = expected.column(column)[frame]
        a_val = actual.column(column)[frame]
        lines.append(f"first difference: frame {frame}, column {column}: {names[0]} {_show(e_val)}, {names[1]} {_show(a_val)}")
        lines.append("largest deviation per column (over the common frames):")
        for column, dev, tol in worst:
            lines.append(f"  {column}: {_show(dev)} (tolerance {tol:g})")
    return Comparison(False, "\n".join(lines))


def _show(value: float) -> str:
    return "empty" if np.isnan(value) else f"{value:.10g}"
