"""``armanim export``: a finished run in another program's format, without solving.

``joint-trajectory``: the run as a ROS ``trajectory_msgs/JointTrajectory`` in JSON
(:mod:`armanim.output.jointtrajectory`): the joints' names (a URDF arm's, else ``phi1`` ..
``phiN``), and at every frame of ``trajectory.csv`` the positions (radians), velocities
(rad/s) and ``time_from_start`` (its ``time_s``).

An export outside the run folder (``--out FILE``) is marked as every single file armanim writes at
a name it does not own: the message may hold no key of armanim's own (ROS refuses unknown keys), so
the mark is a small file beside it, ``.FILE.armanim.json`` (:mod:`armanim.output.marks`), holding
the export's size and sha256. An existing ``FILE`` is replaced only when its mark is there and it
is, byte for byte, what armanim wrote: a user's own trajectory, one edited since, or a link is
never replaced.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from armanim.arm.kinematics import joints_in_si
from armanim.errors import Diagnostic, SceneError, UsageError
from armanim.output.atomic import write_text_atomic
from armanim.output.csvfile import TrajectoryTable, read_trajectory_csv
from armanim.output.csvfile import velocity_columns as csv_velocity_columns
from armanim.output.files import protection_kind, resolved, unprotecting, write_protected
from armanim.output.jointtrajectory import (
    finite_difference_velocities,
    joint_trajectory,
    joint_trajectory_text,
    unwrapped,
)
from armanim.output.marks import as_marked, file_mark, foreign_mark, other_kind, write_marked
from armanim.scene.models import LIMITS

EXPORT_FORMATS = ("joint-trajectory",)
"""What ``armanim export --format`` writes."""
JOINT_TRAJECTORY_FILE = "joint_trajectory.json"
"""The file ``export --format joint-trajectory`` writes into the run folder (without ``--out``)."""


def velocity_columns(n: int, slides: np.ndarray | None = None) -> list[str]:
    """The trajectory.csv columns of the joints' velocities (deg/s; m/s for a prismatic joint),
    ``dphi1_deg_s`` (``dq1_m_s``) first.

    >>> velocity_columns(2)
    ['dphi1_deg_s', 'dphi2_deg_s']
    """
    return csv_velocity_columns(n, slides)


def run_velocities(table: TrajectoryTable, time_s: np.ndarray, positions: np.ndarray, file: str) -> np.ndarray:
    """(F, n) rad/s (m/s for a prismatic joint): the clock's velocities from ``dphiK_deg_s``
    (``dqK_m_s``); a run written before those columns existed gets central finite differences of
    its positions over ``time_s``.

    Raises
    ------
    SceneError
        Some velocity columns but not all of them (exit 2).
    """
    columns = velocity_columns(positions.shape[1], table.slides)
    present = [c for c in columns if c in table.columns]
    if not present:
        return finite_difference_velocities(time_s, positions)
    if len(present) != len(columns):
        missing = [c for c in columns if c not in table.columns]
        raise SceneError(
            file,
            [
                Diagnostic(
                    "",
                    f"has {', '.join(present[:3])} but not {', '.join(missing[:3])} "
                    "(expected a velocity column for every joint: dphi1_deg_s ..)",
                    1,
                )
            ],
        )
    return joints_in_si(np.stack([table.column(c) for c in columns], axis=1), table.slides)


def _increasing_times(table: TrajectoryTable, file: str) -> np.ndarray:
    """``time_s``, which a trajectory message needs strictly increasing."""
    time_s = table.column("time_s")
    bad = np.nonzero(np.diff(time_s) <= 0)[0]
    if len(bad):
        row = int(bad[0]) + 1
        raise SceneError(
            file,
            [
                Diagnostic(
                    "",
                    f"time_s: {time_s[row]:g} does not come after {time_s[row - 1]:g} "
                    "(a joint trajectory needs increasing times)",
                    table.first_line + row,
                )
            ],
        )
    return time_s


def run_joint_trajectory(folder: Path) -> str:
    """The JSON text of the run in ``folder`` as a JointTrajectory message (read the folder under its lock)."""
    from armanim.runs.reload import load_run

    run = load_run(folder)
    csv_path = folder / "trajectory.csv"
    table = read_trajectory_csv(csv_path, max_rows=LIMITS["total_frames"])
    slides = table.slides if table.slides is not None else np.zeros(table.joints_si.shape[1], dtype=bool)
    unlimited = np.isneginf(run.problem.limits.lower) & np.isposinf(run.problem.limits.upper) & ~slides
    positions = unwrapped(table.joints_si, unlimited)
    time_s = _increasing_times(table, str(csv_path))
    velocities = run_velocities(table, time_s, positions, str(csv_path))
    names = list(run.problem.arm.joint_names) or [f"phi{i}" for i in range(1, positions.shape[1] + 1)]
    return joint_trajectory_text(joint_trajectory(names, time_s, positions, velocities))


def _replace_problem(target: Path) -> str | None:
    """Why the export must not be written at ``target``, or None: nothing there (and nothing
    but armanim's mark at the mark's place), or the export armanim wrote there, unchanged."""
    foreign = foreign_mark(target)
    if foreign is not None:
        return foreign
    if os.path.islink(target):
        return (
            "is a link, which armanim does not write through for an export (the file it names may be yours)"
            if os.path.exists(target)
            else "is a link to nothing, which armanim did not make"
        )
    try:
        os.stat(target)
    except FileNotFoundError:
        return None
    except OSError as exc:
        return f"cannot be inspected ({exc.strerror or exc})"
    if os.path.isdir(target):
        return f"is a folder (expected a file name, e.g. {JOINT_TRAJECTORY_FILE})"
    if not os.path.isfile(target):
        return "is not a regular file, so armanim does not write there"
    mark = file_mark(target)
    if not os.path.lexists(mark):
        return f"is a file armanim did not write (no mark {mark.name} beside it), so it is not replaced"
    other = other_kind(target, "export")
    if other is not None:
        return other
    if not as_marked(target, "export"):
        return f"has changed since armanim exported it (it is not what {mark.name} records), so it is not replaced"
    if write_protected(target):  # armanim's own export, made read-only since (campaign 19)
        kind = protection_kind(target)
        return f"is write-protected ({kind}), so it is not replaced: {unprotecting(kind, target)}"
    return None


def _inside_a_run_folder(target: Path) -> Path | None:
    """The run folder (a folder holding armanim's marker) that ``target`` would be written into, if any."""
    from armanim.output.rundir import MARKER

    for folder in Path(os.path.abspath(target)).parents:
        if os.path.lexists(folder / MARKER):
            return folder
    return None


def export_run(folder: str | Path, fmt: str = "joint-trajectory", *, out: str | Path | None = None) -> Path:
    """Write a finished run in another format, without solving; return the file written.

    Parameters
    ----------
    folder : an output folder of ``armanim run``
    fmt : one of :data:`EXPORT_FORMATS`
    out : the file to write; default the run folder's own ``joint_trajectory.json``, staged and
        swapped in like a run (the folder's marker lists it). A file elsewhere is written
        atomically, replacing only a joint trajectory; another file inside the run folder is
        refused, since a run folder holds only what armanim lists in it.

    Raises
    ------
    UsageError
        An unknown format, or ``out`` inside the run folder under another name (exit 2).
    SceneError
        The folder is not a complete armanim run, or its trajectory cannot be exported (exit 2).
    OutputError
        Something other than an exported trajectory stands at ``out``, or it could not be written (exit 3).
    """
    if fmt not in EXPORT_FORMATS:
        raise UsageError(
            f"--format {fmt!r} is not a format armanim exports (expected one of: {', '.join(EXPORT_FORMATS)})"
        )
    from armanim.runs.pipeline import refuse_unless_replaceable, write_run_file

    other = _inside_a_run_folder(Path(out)) if out is not None else None
    if other is not None and resolved(other) != resolved(folder):
        raise UsageError(
            f"--out {out}: is inside the run folder {other}, which holds only the files armanim lists in it "
            f"(its next run would stop at it; export that run itself, or choose a file outside any run folder)"
        )

    own = out is None or resolved(out) == resolved(Path(folder) / JOINT_TRAJECTORY_FILE)

    def trajectory(folder: Path):
        text = run_joint_trajectory(folder)

        def write(path: Path) -> None:
            if own:  # the run folder's own file is listed by its marker
                write_text_atomic(path, text)
            else:  # a file elsewhere gets its mark (checked again under the lock of marked files)
                write_marked(path, text, "export", recheck=lambda: refuse_unless_replaceable(path, _replace_problem))

        return write

    return write_run_file(folder, JOINT_TRAJECTORY_FILE, out, trajectory, _replace_problem)
