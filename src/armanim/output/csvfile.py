"""trajectory.csv: the one place that formats a row, and its reader.

Columns (the contract's first, then extras):
``frame, time_s, goal, phi1_deg .. phiN_deg, x, y, z, goal_distance, clearance,
reached, step_scale, iterations, mode`` (mode: ``ik`` where the method stepped,
``plan`` where the arm followed a planned path). Floats are written with ``repr`` (shortest
round-trip form), so reading the file back gives the same numbers bit for bit.
"""

from __future__ import annotations

import csv
import io
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from armanim.errors import Diagnostic, SceneError
from armanim.output.atomic import write_text_atomic
from armanim.trajectory import Trajectory

BASE_COLUMNS = ("frame", "time_s", "goal")
TAIL_COLUMNS = ("x", "y", "z", "goal_distance", "clearance", "reached", "step_scale", "iterations", "mode")
MODES = ("ik", "plan")
"""Values of the ``mode`` column; a :class:`TrajectoryTable` holds their index."""


def header(n_joints: int) -> list[str]:
    """Column names for an arm of ``n_joints`` joints."""
    return [*BASE_COLUMNS, *(f"phi{i}_deg" for i in range(1, n_joints + 1)), *TAIL_COLUMNS]


def _num(value: float) -> str:
    value = float(value)
    if value == 0.0:
        return "0.0"  # no "-0.0": identical poses give identical text
    return repr(value)


def format_row(traj: Trajectory, i: int, time_s: float) -> list[str]:
    """The CSV fields of frame ``i`` at ``time_s`` (angles in degrees; empty clearance without obstacles)."""
    clearance = traj.clearance[i]
    return [
        str(i),
        _num(time_s),
        str(int(traj.goal[i])),
        *(_num(v) for v in np.degrees(traj.phi[i])),
        *(_num(v) for v in traj.tip[i]),
        _num(traj.distance[i]),
        _num(clearance) if np.isfinite(clearance) else "",
        "1" if traj.reached[i] else "0",
        _num(traj.step_scale[i]),
        str(int(traj.iterations[i])),
        str(traj.mode[i]),
    ]


def table_csv_text(columns, rows) -> str:
    """CSV text (LF line ends) of a header and rows: trajectory.csv, index.csv, sweep tables."""
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(columns)
    writer.writerows(rows)
    return buffer.getvalue()


def trajectory_csv_text(traj: Trajectory) -> str:
    """The whole trajectory.csv as text."""
    time = traj.time
    return table_csv_text(header(traj.phi.shape[1]), (format_row(traj, i, time[i]) for i in range(traj.frames)))


def write_trajectory_csv(traj: Trajectory, path: Path) -> None:
    """Write trajectory.csv atomically."""
    write_text_atomic(path, trajectory_csv_text(traj))


@dataclass(frozen=True)
class TrajectoryTable:
    """A trajectory.csv read back: its header and a float array per column."""

    columns: tuple[str, ...]
    data: np.ndarray  # (F, C), NaN where a field is empty

    @property
    def n_joints(self) -> int:
        """Number of ``phiK_deg`` columns."""
        return sum(1 for c in self.columns if c.startswith("phi") and c.endswith("_deg"))

    def column(self, name: str) -> np.ndarray:
        """(F,) values of a column."""
        return self.data[:, self.columns.index(name)]

    @property
    def angles_deg(self) -> np.ndarray:
        """(F, n) joint angles in degrees."""
        return np.stack([self.column(f"phi{i}_deg") for i in range(1, self.n_joints + 1)], axis=1)


def read_trajectory_csv(path: Path) -> TrajectoryTable:
    """Read a trajectory.csv written by armanim.

    Raises
    ------
    SceneError
        If the file is missing, unreadable or not an armanim trajectory (exit 2).
    """
    file = str(path)
    try:
        if Path(path).is_dir():
            raise SceneError(file, [Diagnostic("", "is a folder (expected a trajectory.csv file)")])
        text = Path(path).read_text(encoding="utf-8")
    except FileNotFoundError:
        raise SceneError(file, [Diagnostic("", "no such file (expected a trajectory.csv written by armanim run)")]) from None
    except (OSError, UnicodeDecodeError) as exc:
        raise SceneError(file, [Diagnostic("", f"cannot be read as a text CSV: {exc}")]) from None
    return parse_trajectory_csv(text, file)


def _field(text: str, column: str) -> float:
    if column == "mode":
        return float(MODES.index(text))  # ValueError when it is not a known mode
    return float(text) if text != "" else np.nan


def parse_trajectory_csv(text: str, file: str) -> TrajectoryTable:
    """Parse trajectory.csv text; ``file`` only names it in messages."""
    try:
        rows = list(csv.reader(io.StringIO(text)))
    except csv.Error as exc:
        raise SceneError(file, [Diagnostic("", f"is not a CSV file: {exc}")]) from None
    if not rows or rows[0][:3] != list(BASE_COLUMNS) or not any(c.startswith("phi") for c in rows[0]):
        raise SceneError(file, [Diagnostic("", "is not an armanim trajectory (expected a header starting frame,time_s,goal,phi1_deg,...)", 1)])
    columns = tuple(rows[0])
    data = np.empty((len(rows) - 1, len(columns)))
    for r, row in enumerate(rows[1:], start=2):
        if len(row) != len(columns):
            raise SceneError(file, [Diagnostic("", f"row has {len(row)} fields (expected {len(columns)}, as the header)", r)])
        try:
            data[r - 2] = [_field(v, c) for v, c in zip(row, columns)]
        except ValueError:
            raise SceneError(file, [Diagnostic("", "a field is not a number (or, in column mode, not ik or plan)", r)]) from None
    return TrajectoryTable(columns=columns, data=data)
