"""Golden trajectories: run a scene without video and compare it with a stored CSV.

A golden file ``DIR/<name>.csv`` has beside it ``DIR/<name>.json`` with the armanim
version and the scene's sha256 at the time it was written, so a failure can say
that the scene itself changed.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

from armanim import __version__
from armanim.errors import OutputError, SceneError
from armanim.output.atomic import advised, write_all_or_none, write_target
from armanim.output.compare import Comparison, compare_trajectories
from armanim.output.csvfile import BASE_COLUMNS, parse_trajectory_csv, read_trajectory_csv, trajectory_csv_text
from armanim.output.files import open_regular, protection_kind, read_bounded, unprotecting, write_protected
from armanim.output.jsontext import json_text, parse_json
from armanim.output.rundir import directory_lock, refuse_in_run_folder
from armanim.runs.pipeline import timed_solution
from armanim.scene import LoadedScene, scene_to_problem

MAX_META_BYTES = 100_000  # the metadata beside a golden CSV is a few lines


@dataclass(frozen=True)
class GoldenResult:
    """Outcome of checking one scene against its golden file.

    Attributes
    ----------
    scene : LoadedScene
    golden : Path
    status : str
        ``pass``, ``fail``, ``missing`` (no golden file), or after ``update``:
        ``new``, ``changed``, ``unchanged``.
    report : str
    scene_changed : bool
        The scene's sha256 differs from the one recorded with the golden file.
    """

    scene: LoadedScene
    golden: Path
    status: str
    report: str
    scene_changed: bool = False


def solve_csv_text(scene: LoadedScene) -> str:
    """The trajectory.csv text a run of ``scene`` writes (no files, no video)."""
    problem = scene_to_problem(scene.model)
    return trajectory_csv_text(timed_solution(scene, problem, problem.fps).trajectory, problem.arm.prismatic)


def golden_paths(golden_dir: Path, name: str) -> tuple[Path, Path]:
    """(``DIR/<name>.csv``, ``DIR/<name>.json``)."""
    return golden_dir / f"{name}.csv", golden_dir / f"{name}.json"


def _recorded_sha(meta_path: Path) -> str | None:
    """The scene sha256 recorded beside a golden file; None if it is missing or not one."""
    try:
        sha = parse_json(read_bounded(meta_path, MAX_META_BYTES, "a golden .json file")).get("scene_sha256")
    except (SceneError, ValueError, AttributeError):
        return None
    return sha if isinstance(sha, str) else None


def scene_change_note(scene: LoadedScene, meta_path: Path) -> str | None:
    """What to say when ``scene`` is not the scene recorded beside its golden file, else None."""
    recorded = _recorded_sha(meta_path)
    if recorded is None or recorded == scene.sha256:
        return None
    return (
        f"{scene.path.name} changed since the golden file was written (sha256 {recorded[:12]}... then, "
        f"{scene.sha256[:12]}... now); --update records it"
    )


def check_scene(scene: LoadedScene, golden_dir: Path, *, atol_deg: float = 1e-6, atol: float = 1e-6) -> GoldenResult:
    """Run a scene and compare its trajectory with its golden file."""
    csv_path, meta_path = golden_paths(Path(golden_dir), scene.name)
    if not csv_path.exists():
        return GoldenResult(scene, csv_path, "missing", f"no golden file {csv_path} (create it with --update)")
    expected = read_trajectory_csv(csv_path)
    actual = parse_trajectory_csv(solve_csv_text(scene), f"{scene.path} (this run)")
    result: Comparison = compare_trajectories(
        expected,
        actual,
        atol_deg=atol_deg,
        atol=atol,
        names=("golden", "actual"),
        files=(str(csv_path), f"{scene.path} (this run)"),
    )
    note = scene_change_note(scene, meta_path)
    report = result.report + (f"\nnote: {note}" if note else "")
    return GoldenResult(scene, csv_path, "pass" if result.equal else "fail", report, note is not None)


def update_golden(scene: LoadedScene, golden_dir: Path) -> GoldenResult:
    """(Re)write a scene's golden CSV and metadata; status says new, changed or unchanged.

    The pair is written all or none (:func:`armanim.output.atomic.write_all_or_none`): a
    failure on either file leaves both as they were. Two updates of the same golden folder
    at once take turns (a lock on the folder), so a pair never mixes two updates.
    """
    try:
        return _update_golden(scene, Path(golden_dir))
    except OutputError as exc:
        raise advised(exc, "choose another folder with --golden") from None


def _update_golden(scene: LoadedScene, golden_dir: Path) -> GoldenResult:
    csv_path, meta_path = golden_paths(golden_dir, scene.name)
    for path in (csv_path, meta_path):  # a folder or device at either: exit 3 before the solve
        write_target(path)
        # a link at either into a run folder (its summary.json begins as a golden .json does) is
        # exit 2, as --golden there is: written through, it changed the run, whose next run stopped
        refuse_in_run_folder(path, "--golden")
    refuse_foreign_golden(csv_path, meta_path)
    data = solve_csv_text(scene).encode("utf-8")
    meta = {"armanim_version": __version__, "scene_file": scene.path.name, "scene_sha256": scene.sha256}
    files = {meta_path: (json_text(meta, indent=2) + "\n").encode("utf-8")}
    with directory_lock(csv_path.parent):
        status = golden_status(csv_path, data)
        files = {csv_path: data, **files}
        files = {path: new for path, new in files.items() if golden_status(path, new) != "unchanged"}
        refuse_write_protected_golden(*files)
        if files:
            write_all_or_none(files)
    return GoldenResult(scene, csv_path, status, f"{status}: {csv_path}")


def refuse_write_protected_golden(*paths: Path) -> None:
    """An OutputError (exit 3) if a file at any of ``paths`` (golden files about to be replaced) is
    write-protected (:func:`~armanim.output.files.write_protected`: a user's ``chmod a-w``, which root's
    writes would otherwise pass, or a file this process may not write). Campaign 16: ``check --update`` replaced a user's golden at mode 0444 with a new
    file at 0644, exit 0. A file whose bytes do not change is not written, protected or not.

    Raises
    ------
    OutputError
        Naming the file and the remedy; the pair is left as it was.
    """
    for path in paths:
        if path.is_file() and write_protected(path):
            kind = protection_kind(path)
            raise OutputError(
                f"{path}: is write-protected ({kind}), so --update does not replace it: {unprotecting(kind, path)}, "
                "or choose another --golden folder"
            )


GOLDEN_BEGINNINGS = {
    ".csv": ",".join(BASE_COLUMNS[:3]).encode() + b",",
    ".json": b'{\n  "armanim_version": ',
}
"""How every golden file armanim writes begins, by its suffix: a trajectory CSV's first columns,
and the metadata's first key (:func:`update_golden` writes it first, indented by two)."""


def refuse_foreign_golden(*paths: Path) -> None:
    """An OutputError (exit 3) if a file at any of ``paths`` (a golden pair) does not begin as
    every such file armanim writes (:data:`GOLDEN_BEGINNINGS`). Absent is fine.

    Campaign 11: ``check --update`` replaced a user's own ``g/tiny.csv`` (``time_s`` and one row)
    with exit 0, and would have a ``g/tiny.json`` of theirs. A golden file armanim wrote, edited
    or not UTF-8 since, is still replaced.

    Raises
    ------
    OutputError
        A file is someone else's; the pair is left as it was.
    """
    for path in paths:
        begins = GOLDEN_BEGINNINGS[path.suffix]
        try:
            with open_regular(path, f"a golden {path.suffix} file") as handle:
                first = handle.read(len(begins))
        except SceneError:
            continue  # absent (a folder or device there was refused already)
        if first != begins:
            raise OutputError(
                f"{path}: is not a golden {path.suffix} file armanim wrote (it does not begin "
                f"{begins.decode()!r}), so --update does not replace it (move it away, or choose another --golden folder)"
            )


def golden_status(csv_path: Path, data: bytes) -> str:
    """``new``, ``unchanged`` or ``changed``: the golden file at ``csv_path`` (either of a pair) against ``data``.

    Bytes are compared, never decoded (a file that is not UTF-8 has simply changed), and at
    most ``len(data)`` bytes are read: a file of another size has changed without reading it.
    """
    try:
        with open_regular(csv_path, f"a golden {csv_path.suffix} file") as handle:
            if os.fstat(handle.fileno()).st_size != len(data):
                return "changed"
            return "unchanged" if handle.read(len(data) + 1) == data else "changed"
    except SceneError:
        return "new" if not csv_path.exists() and not csv_path.is_symlink() else "changed"
