"""trajectory.csv: the one place that formats a row, and its reader.

Columns (the contract's first, then extras):
``frame, time_s, goal, phi1_deg .. phiN_deg, x, y, z, goal_distance, clearance,
reached, step_scale, iterations, mode, qw, qx, qy, qz, orientation_error_deg, self_clearance,
self_pair, path_s, path_error, dphi1_deg_s .. dphiN_deg_s`` (mode: ``ik`` where the method stepped,
``plan`` where the arm followed a planned path, ``path`` where a path goal's tool followed its path;
``qw .. qz`` the tool frame's unit quaternion, w >= 0;
``orientation_error_deg`` the tool's angle to the frame's goal orientation, empty for a
position-only goal; ``self_clearance`` the least gap of an enabled pair of the arm's own capsules
and ``self_pair`` that pair's links ``a|b``, both empty without enabled pairs; ``path_s`` the arc
length of the path done and ``path_error`` the tool's distance from the path, on frames of mode
``path`` only; ``dphiK_deg_s``
joint K's velocity on the clock). A prismatic joint's columns are in metres: ``qK_m`` in place of
``phiK_deg`` and ``dqK_m_s`` in place of ``dphiK_deg_s``. Floats are written with ``repr`` (shortest
round-trip form), so reading the file back gives the same numbers bit for bit.
"""

from __future__ import annotations

import contextlib
import csv
import io
import math
import re
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import BinaryIO

import numpy as np

from armanim.arm.kinematics import joints_in_si, joints_shown
from armanim.errors import Diagnostic, OutputError, SceneError
from armanim.motion.solution import Trajectory
from armanim.output.atomic import write_chunks_atomic, write_target
from armanim.output.files import open_regular
from armanim.output.marks import as_marked, file_mark, foreign_mark, other_kind, refuse_write_protected
from armanim.output.solved import SolvedRun

BASE_COLUMNS = ("frame", "time_s", "goal")
TAIL_COLUMNS = (
    "x",
    "y",
    "z",
    "goal_distance",
    "clearance",
    "reached",
    "step_scale",
    "iterations",
    "mode",
    "qw",
    "qx",
    "qy",
    "qz",
    "orientation_error_deg",
    "self_clearance",
    "self_pair",
    "path_s",
    "path_error",
)
EMPTY_ALLOWED = ("clearance", "orientation_error_deg", "self_clearance", "path_s", "path_error", "carried_clearance")
"""Numeric columns that may be empty: no obstacles; a position-only goal; no enabled pair of the arm's own links;
a frame not along a path."""
MODES = ("ik", "plan", "path")
"""Values of the ``mode`` column (the reader refuses others)."""


def header(n_joints: int, slides: np.ndarray | None = None) -> list[str]:
    """Column names for an arm of ``n_joints`` joints (``slides``: which are prismatic)."""
    return [*BASE_COLUMNS, *joint_columns(n_joints, slides), *TAIL_COLUMNS, *velocity_columns(n_joints, slides)]


def joint_columns(n_joints: int, slides: np.ndarray | None = None) -> list[str]:
    """The joint columns: ``phiK_deg``, or ``qK_m`` for a prismatic joint (metres).

    >>> joint_columns(2, np.array([True, False]))
    ['q1_m', 'phi2_deg']
    """
    return [f"q{i}_m" if slides is not None and slides[i - 1] else f"phi{i}_deg" for i in range(1, n_joints + 1)]


def velocity_columns(n_joints: int, slides: np.ndarray | None = None) -> list[str]:
    """The joint-velocity columns (the clock's, degrees per second; metres per second for a
    prismatic joint), after the contract's.

    >>> velocity_columns(2)
    ['dphi1_deg_s', 'dphi2_deg_s']
    >>> velocity_columns(2, np.array([True, False]))
    ['dq1_m_s', 'dphi2_deg_s']
    """
    return [f"dq{i}_m_s" if slides is not None and slides[i - 1] else f"dphi{i}_deg_s" for i in range(1, n_joints + 1)]


def _texts(values: np.ndarray) -> list[str]:
    """Each number as trajectory.csv writes it: the shortest text that reads back as the same float
    (``repr``), and ``0.0`` for both zeros (no ``-0.0``: identical poses give identical text).

    >>> _texts(np.array([0.1, -0.0, 2.5e-07, np.nan]))
    ['0.1', '0.0', '2.5e-07', 'nan']
    """
    return ["0.0" if v == 0.0 else repr(v) for v in np.asarray(values, dtype=float).tolist()]


def _finite_texts(values: np.ndarray | None, frames: int) -> list[str]:
    """:func:`_texts`, empty where a value is not finite or the column is absent (None).

    >>> _finite_texts(np.array([1.0, np.inf, np.nan]), 3), _finite_texts(None, 2)
    (['1.0', '', ''], ['', ''])
    """
    if values is None:
        return [""] * frames
    return [
        text if math.isfinite(v) else "" for v, text in zip(np.asarray(values, dtype=float).tolist(), _texts(values))
    ]


def trajectory_rows(
    traj: Trajectory, time_s: np.ndarray, slides: np.ndarray | None = None, frames: slice = slice(None)
) -> list[tuple[str, ...]]:
    """The CSV fields of the frames ``frames`` (default all; a step of 1), at ``time_s`` (F,)
    (angles in degrees, a prismatic joint's values in metres; empty clearance without obstacles,
    empty orientation error for a position-only goal), built a column at a time."""
    first, stop, _ = frames.indices(traj.frames)
    count = max(stop - first, 0)

    def cut(values):
        return None if values is None else values[first:stop]

    quaternion = cut(traj.tool_quaternion) if traj.tool_quaternion is not None else np.full((count, 4), np.nan)
    velocity = cut(traj.velocity) if traj.velocity is not None else np.zeros((count, traj.phi.shape[1]))
    angle = None if traj.orientation_error is None else np.degrees(cut(traj.orientation_error))
    self_pair = cut(traj.self_pair)
    columns = [
        [str(i) for i in range(first, first + count)],
        _texts(time_s[first:stop]),
        [str(g) for g in cut(traj.goal).tolist()],
        *(_texts(c) for c in joints_shown(cut(traj.phi), slides).T),
        *(_texts(c) for c in cut(traj.tip).T),
        _texts(cut(traj.distance)),
        _finite_texts(cut(traj.clearance), count),
        ["1" if r else "0" for r in cut(traj.reached).tolist()],
        _texts(cut(traj.step_scale)),
        [str(k) for k in cut(traj.iterations).tolist()],
        [str(m) for m in cut(traj.modes)],
        *(_finite_texts(c, count) for c in quaternion.T),
        _finite_texts(angle, count),
        _texts(cut(traj.self_clearance)) if traj.self_clearance is not None else [""] * count,
        [str(p) for p in self_pair] if self_pair is not None else [""] * count,
        _finite_texts(cut(traj.path_s), count),
        _finite_texts(cut(traj.path_error), count),
        *(_texts(c) for c in joints_shown(velocity, slides).T),
    ]
    return list(zip(*columns))


def table_csv_text(columns, rows, text_cells: bool = False) -> str:
    """CSV text (LF line ends) of a header and rows: trajectory.csv, index.csv, sweep tables.

    With ``text_cells`` (tables that hold free text: index.csv, the sweep tables), a text cell that a spreadsheet would run as a formula (it starts with ``=``, ``+``, ``-``,
    ``@``, a tab or a carriage return, and is not a number) is written with a leading ``'``
    (OWASP's rule for CSV injection): a scene file named ``=HYPERLINK(...).yaml`` stays text.

    >>> print(table_csv_text(["file", "x"], [["=1+1.yaml", "-0.5"], ["@a", -2]], text_cells=True), end="")
    file,x
    '=1+1.yaml,-0.5
    '@a,-2
    """
    return rows_csv_text([columns]) + rows_csv_text(rows, text_cells)


def rows_csv_text(rows, text_cells: bool = False) -> str:
    """CSV text (LF line ends) of ``rows`` alone: :func:`table_csv_text`'s lines after its header.

    >>> rows_csv_text([["a", 1.5], ["b,c", ""]])
    'a,1.5\\n"b,c",\\n'
    """
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerows(([spreadsheet_text(cell) for cell in row] for row in rows) if text_cells else rows)
    return buffer.getvalue()


FORMULA_STARTS = ("=", "+", "-", "@", "\t", "\r")
PLAIN_NUMBER = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?|[+-]?inf|nan")


def spreadsheet_text(cell):
    """``cell``, with a ``'`` before a text a spreadsheet would take for a formula."""
    if isinstance(cell, str) and cell.startswith(FORMULA_STARTS) and not PLAIN_NUMBER.fullmatch(cell):
        return "'" + cell
    return cell


def check_table_replaceable(path: Path, is_ours: Callable[[str], bool], kind: str) -> None:
    """An OutputError (exit 3) if a file at ``path`` is not a table armanim wrote (``index.csv``,
    a sweep's table: its mark's ``kind``), recognised by ``is_ours(first line)``; absent, or armanim's, is fine.

    Raises
    ------
    OutputError
        The file is someone else's (it is left as it was), or not a regular file.
    """
    target = write_target(path)  # a folder, device or FIFO there: exit 3
    try:
        with open(target, "rb") as handle:
            first = handle.readline(MAX_LINE_BYTES).decode("utf-8", "replace").rstrip("\r\n")
    except FileNotFoundError:
        foreign = foreign_mark(target)  # a new table's mark must not replace a file of yours
        if foreign is not None:
            raise OutputError(f"{path}: {foreign} (move it away, or choose another folder with --out)") from None
        return
    except OSError as exc:
        raise OutputError(f"{path}: cannot be read to tell whether armanim wrote it ({exc.strerror or exc})") from None
    if not is_ours(first):
        raise OutputError(
            f"{path}: this file was not written by armanim (its first line is not armanim's header), "
            "so it is not replaced (move it away, or choose another folder with --out)"
        )
    other = other_kind(target, kind)
    if other is not None:
        raise OutputError(f"{path}: {other} (move it away, or choose another folder with --out)")
    if not as_marked(target, kind):
        raise OutputError(
            f"{path}: has changed since armanim wrote it (it is not what {file_mark(path).name} beside it "
            "records, or that mark is missing), so it is not replaced (move it away, or choose another folder with --out)"
        )
    refuse_write_protected(path)  # armanim's own table, made read-only since


CSV_CHUNK_ROWS = 2_000
"""Rows of trajectory.csv formatted at once (about 3 MB of text for a 7-joint arm, some 25 MB as Python strings while formatted): the file is
written a chunk at a time, so an hour at 240 fps (864,000 rows) never holds its text whole."""


def trajectory_csv_chunks(
    traj: Trajectory,
    slides: np.ndarray | None = None,
    carried: tuple[np.ndarray, np.ndarray] | None = None,
    fingers: np.ndarray | None = None,
    chunk_rows: int = CSV_CHUNK_ROWS,
) -> Iterator[str]:
    """trajectory.csv's text: its header line, then ``chunk_rows`` rows at a time (``slides``:
    which joints are prismatic, the arm's ``prismatic``; None: all revolute; ``carried``: a run
    that grasps, each frame's held object's name and its clearance, the columns ``held`` and
    ``carried_clearance``; ``fingers``: such a run's gripper value in each frame, metres per
    finger, the last column ``gripper_m``). Joined, the chunks are the file byte for byte
    whatever ``chunk_rows`` is."""
    names = header(traj.phi.shape[1], slides)
    if carried is not None:
        names += ["held", "carried_clearance"] + (["gripper_m"] if fingers is not None else [])
    yield rows_csv_text([names])
    time = traj.time
    for first in range(0, traj.frames, chunk_rows):
        part = slice(first, min(first + chunk_rows, traj.frames))
        rows = trajectory_rows(traj, time, slides, part)
        if carried is not None:
            held, clear = carried[0][part], carried[1][part]
            more: list[tuple[str, ...]] = [(str(h), c) for h, c in zip(held, _finite_texts(clear, len(rows)))]
            if fingers is not None:
                more = [m + (f,) for m, f in zip(more, _texts(fingers[part]))]
            rows = [row + extra for row, extra in zip(rows, more)]
        yield rows_csv_text(rows)


def trajectory_csv_text(
    traj: Trajectory,
    slides: np.ndarray | None = None,
    carried: tuple[np.ndarray, np.ndarray] | None = None,
    fingers: np.ndarray | None = None,
) -> str:
    """The whole trajectory.csv as text (:func:`trajectory_csv_chunks` joined; for tests and
    goldens: a run writes the chunks, :func:`write_trajectory_csv`)."""
    return "".join(trajectory_csv_chunks(traj, slides, carried, fingers))


def write_trajectory_csv(run: SolvedRun, path: Path, chunk_rows: int = CSV_CHUNK_ROWS) -> None:
    """Write the run's trajectory.csv atomically (it has no options: every run writes it whole),
    ``chunk_rows`` rows at a time into its temporary file (:func:`trajectory_csv_chunks`)."""
    carry, traj = run.solution.carry, run.trajectory
    carried, fingers = None, None
    if carry is not None:
        from armanim.motion.carry import carried_clearance, frame_fingers

        carried = (carry.held_names(traj.goal), carried_clearance(run.problem, carry, traj.phi, traj.goal))
        fingers = frame_fingers(run.problem, carry, traj.goal, traj.fps)
    chunks = trajectory_csv_chunks(traj, run.problem.arm.prismatic, carried, fingers, chunk_rows)
    write_chunks_atomic(path, (chunk.encode("utf-8") for chunk in chunks))


REQUIRED_TAIL = ("x", "y", "z", "goal_distance", "clearance", "reached")
"""The contract's columns after the angles; every reader needs them."""
TEXT_COLUMNS = {"mode": MODES, "self_pair": None, "held": None}
"""Columns whose values are words, not numbers, and the words each allows (None: any)."""
MAX_LINE_BYTES = 100_000  # a row of 64 joints is under 2,000 bytes
BLOCK_ROWS = 16_384  # rows parsed at once when a file is streamed


@dataclass(frozen=True)
class TrajectoryTable:
    """A trajectory.csv (or a block of its rows) read back: its header, a float array per
    column (NaN in text columns) and the text columns' words."""

    columns: tuple[str, ...]
    data: np.ndarray  # (F, C), NaN where a field is empty
    text: dict[str, np.ndarray] = field(default_factory=dict)  # column -> (F,) str
    first_line: int = 2  # file line of row 0, for messages

    @property
    def n_joints(self) -> int:
        """Number of joint columns (``phiK_deg``, or ``qK_m`` for a prismatic joint)."""
        return sum(1 for c in self.columns if _JOINT_COLUMN.fullmatch(c))

    @property
    def slides(self) -> np.ndarray:
        """(n,) bool: which joints are prismatic (their columns ``qK_m``)."""
        return np.array([f"q{i}_m" in self.columns for i in range(1, self.n_joints + 1)], dtype=bool)

    def column(self, name: str) -> np.ndarray:
        """(F,) values of a column."""
        return self.data[:, self.columns.index(name)]

    @property
    def angles_deg(self) -> np.ndarray:
        """(F, n) joint values as written: degrees, metres for a prismatic joint."""
        return np.stack([self.column(c) for c in joint_columns(self.n_joints, self.slides)], axis=1)

    @property
    def joints_si(self) -> np.ndarray:
        """(F, n) joint values in the chain's units: radians, metres for a prismatic joint."""
        return joints_in_si(self.angles_deg, self.slides)


_JOINT_COLUMN = re.compile(r"phi[0-9]+_deg|q[0-9]+_m")


def _problem(file: str, message: str, line: int | None = None) -> SceneError:
    return SceneError(file, [Diagnostic("", message, line)])


def check_header(row: list[str], file: str) -> tuple[str, ...]:
    """The columns of a trajectory.csv header, checked against the contract.

    Raises
    ------
    SceneError
        Not ``frame,time_s,goal,phi1_deg..phiN_deg,`` then x, y, z, goal_distance,
        clearance and reached (exit 2); extra columns may follow.
    """
    expected = "expected a header frame,time_s,goal,phi1_deg,...,phiN_deg,x,y,z,goal_distance,clearance,reached"
    if row[:3] != list(BASE_COLUMNS):
        raise _problem(file, f"is not an armanim trajectory ({expected})", 1)
    n = 0
    while 3 + n < len(row) and row[3 + n] in (f"phi{n + 1}_deg", f"q{n + 1}_m"):
        n += 1
    stray = [c for c in row[3 + n :] if c.startswith("phi") or _JOINT_COLUMN.fullmatch(c)]
    if n == 0 or stray:
        found = f"the column {stray[0]!r} is out of place; " if stray else ""
        raise _problem(
            file,
            f"{found}joint columns must be phi1_deg (or q1_m for a prismatic joint), phi2_deg, ... "
            f"right after goal ({expected})",
            1,
        )
    missing = [c for c in REQUIRED_TAIL if c not in row]
    if missing:
        raise _problem(file, f"lacks the column(s) {', '.join(missing)} ({expected})", 1)
    twice = sorted({c for c in row if row.count(c) > 1})
    if twice:
        raise _problem(
            file,
            f"has the column(s) {', '.join(twice[:8])}{f' and {len(twice) - 8:,} more' if len(twice) > 8 else ''} more than once",
            1,
        )
    return tuple(row)


def _lines(handle: BinaryIO, file: str) -> Iterator[str]:
    """Decoded lines of a file, each at most MAX_LINE_BYTES (a file without newlines is not read whole)."""
    number = 0
    while True:
        raw = handle.readline(MAX_LINE_BYTES + 1)
        number += 1
        if not raw:
            return
        if len(raw) > MAX_LINE_BYTES:
            raise _problem(file, f"line is longer than {MAX_LINE_BYTES:,} bytes (not a trajectory.csv)", number)
        try:
            yield raw.decode("utf-8")
        except UnicodeDecodeError as exc:
            raise _problem(file, f"byte 0x{raw[exc.start]:02x} is not UTF-8 (not a trajectory.csv)", number) from None


def _parse_block(rows: list[tuple[int, list[str]]], columns: tuple[str, ...], file: str) -> TrajectoryTable:
    text_at = [i for i, c in enumerate(columns) if c in TEXT_COLUMNS]
    for line, row in rows:
        if len(row) != len(columns):
            raise _problem(file, f"row has {len(row)} fields (expected {len(columns)}, as the header)", line)
    fields = np.array([row for _, row in rows], dtype=object).reshape(len(rows), len(columns))
    text = {columns[i]: fields[:, i].astype(str) for i in text_at}
    for column, words in text.items():
        allowed_words = TEXT_COLUMNS[column]
        if allowed_words is None:
            continue
        bad = np.nonzero(~np.isin(words, allowed_words))[0]
        if len(bad):
            allowed = " or ".join(allowed_words)
            raise _problem(file, f"{column}: {words[bad[0]][:40]!r} is not {allowed}", rows[bad[0]][0])
    fields[:, text_at] = "nan"
    fields[fields == ""] = "nan"
    try:
        data = fields.astype(float)
    except ValueError:  # find the first field that is not a number, to name its line
        for line, row in rows:
            not_numbers = [i for i, v in enumerate(row) if i not in text_at and v != "" and not _is_float(v)]
            if not_numbers:
                raise _problem(
                    file, f"{columns[not_numbers[0]]}: {row[not_numbers[0]][:40]!r} is not a number", line
                ) from None
        raise
    return TrajectoryTable(columns, data, text, rows[0][0] if rows else 2)


def _is_float(value: str) -> bool:
    try:
        float(value)
        return True
    except ValueError:
        return False


def table_blocks(
    lines: Iterable[str], file: str, block_rows: int = BLOCK_ROWS
) -> tuple[tuple[str, ...], Iterator[TrajectoryTable]]:
    """The checked header of trajectory.csv lines, and its rows as tables of ``block_rows`` rows.

    Rows are parsed as the blocks are taken, so a file of any length is read in bounded memory.
    """
    reader = csv.reader(lines)
    try:
        head = next(reader, None)
    except csv.Error as exc:
        raise _problem(file, f"is not a CSV file: {exc}", 1) from None
    if head is None:
        raise _problem(file, "is empty (expected a trajectory.csv written by armanim run)")
    columns = check_header(head, file)

    def blocks() -> Iterator[TrajectoryTable]:
        rows: list[tuple[int, list[str]]] = []
        try:
            for row in reader:
                rows.append((reader.line_num, row))
                if len(rows) == block_rows:
                    yield _parse_block(rows, columns, file)
                    rows = []
        except csv.Error as exc:
            raise _problem(file, f"is not a CSV file: {exc}", reader.line_num) from None
        if rows:
            yield _parse_block(rows, columns, file)

    return columns, blocks()


def concat_tables(columns: tuple[str, ...], tables: Iterable[TrajectoryTable]) -> TrajectoryTable:
    """One table of every block's rows."""
    tables = list(tables)
    if not tables:
        return TrajectoryTable(
            columns, np.empty((0, len(columns))), {c: np.array([], dtype=str) for c in columns if c in TEXT_COLUMNS}
        )
    text = {c: np.concatenate([t.text[c] for t in tables]) for c in tables[0].text}
    return TrajectoryTable(columns, np.concatenate([t.data for t in tables]), text)


@contextlib.contextmanager
def open_trajectory_csv(
    path: Path, block_rows: int = BLOCK_ROWS
) -> Iterator[tuple[tuple[str, ...], Iterator[TrajectoryTable]]]:
    """Stream a trajectory.csv: ``with open_trajectory_csv(p) as (columns, blocks): ...``.

    Raises
    ------
    SceneError
        The file is missing, not a regular file, or not an armanim trajectory (exit 2).
    """
    with open_regular(path, "a trajectory.csv written by armanim run") as handle:
        yield table_blocks(_lines(handle, str(path)), str(path), block_rows)


def read_trajectory_csv(path: Path, max_rows: float | None = None) -> TrajectoryTable:
    """Read a whole trajectory.csv written by armanim.

    Parameters
    ----------
    path : Path
    max_rows : int, optional
        More rows than this are an error (a bound on the memory used).

    Raises
    ------
    SceneError
        If the file is missing, unreadable, too long or not an armanim trajectory (exit 2).
    """
    with open_trajectory_csv(path) as (columns, blocks):
        tables, rows = [], 0
        for table in blocks:
            rows += len(table.data)
            if max_rows is not None and rows > max_rows:
                raise _problem(str(path), f"has more than {max_rows:,} rows (a run has at most that many frames)")
            tables.append(table)
    return concat_tables(columns, tables)


def parse_trajectory_csv(text: str, file: str) -> TrajectoryTable:
    """Parse trajectory.csv text; ``file`` only names it in messages."""
    columns, blocks = table_blocks(io.StringIO(text), file)
    return concat_tables(columns, blocks)
