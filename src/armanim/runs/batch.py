"""Many scenes at once, on all local cores or on a Dask cluster, with the same results.

Scenes are validated on the client first (a bad scene is reported, never sent). Each
valid scene travels as its bytes to a worker, which produces its outputs in a
temporary folder and sends the files back; the client writes them atomically under
``ROOT/<name>/`` (workers need no shared filesystem). A scene that fails on a worker
is reported and the others finish. ``ROOT/index.csv`` lists every scene.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from collections.abc import Callable, Iterable
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass, field, replace
from pathlib import Path

from armanim.errors import ArmanimError, SceneError, UsageError
from armanim.output.atomic import write_bytes_atomic
from armanim.output.csvfile import check_table_replaceable, table_csv_text
from armanim.output.marks import marks_locked, write_marked
from armanim.output.rundir import staged_folder
from armanim.procs.executors import executor_for
from armanim.procs.workers import temp_prefix, undone_on_stop
from armanim.runs.options import RunOptions
from armanim.scene import LoadedScene, load_scene, scene_from_bytes

WORKER_PRELOAD = ("armanim.runs.pipeline", "armanim.render.pictures.canvas", "armanim.render.video.movie")
"""What a batch's local workers import once, in the pool's forkserver, before any scene."""

INDEX_COLUMNS = (
    "name",
    "status",
    "scene_file",
    "goals",
    "reached",
    "missed",
    "frames",
    "min_clearance",
    "folder",
    "message",
)


@dataclass(frozen=True)
class SceneTask:
    """A validated scene as it travels to a worker: its bytes, its path (for messages) and name,
    and for a run in this process the scene as validated (``loaded``: not sent to a worker
    process, which validates ``raw`` again)."""

    raw: bytes
    path: str
    name: str
    loaded: LoadedScene | None = field(default=None, compare=False, repr=False)

    @classmethod
    def from_scene(cls, scene: LoadedScene) -> SceneTask:
        """The task for a loaded scene."""
        return cls(scene.raw, str(scene.path), scene.name, scene)

    def __getstate__(self) -> dict:
        return {"raw": self.raw, "path": self.path, "name": self.name, "loaded": None}

    def __setstate__(self, state: dict) -> None:
        for key, value in state.items():
            object.__setattr__(self, key, value)


@dataclass(frozen=True)
class RemoteRun:
    """What a worker sends back: every output file's bytes and the summary, or the
    report of armanim's own error (sent as text: a deterministic failure is a result,
    never retried, and needs no exception pickled across versions)."""

    name: str
    files: dict[str, bytes]
    summary: dict | None
    error: str | None = None
    status: str = "ok"


@dataclass(frozen=True)
class BatchEntry:
    """One row of ``index.csv``.

    ``status`` is ``ok``, ``invalid`` (the scene was rejected: exit 2) or ``failed``
    (producing its outputs failed: exit 3).
    """

    name: str
    status: str
    scene_file: str
    goals: int = 0
    reached: int = 0
    missed: int = 0
    frames: int = 0
    min_clearance: float | None = None
    folder: str = ""
    message: str = ""
    summary: dict | None = None


def run_task(task: SceneTask, options: RunOptions) -> RemoteRun:
    """Worker side: produce a scene's outputs in a temporary folder, as ``options`` ask (its video
    drawn in this one process), and return their bytes."""
    from armanim.runs.pipeline import produce_outputs

    try:
        scene = task.loaded if task.loaded is not None else scene_from_bytes(task.raw, task.path, task.name)
        with tempfile.TemporaryDirectory(prefix=temp_prefix()) as tmp:
            with undone_on_stop(lambda: shutil.rmtree(tmp, ignore_errors=True)):  # a SIGTERM'd worker removes it
                produced = produce_outputs(scene, Path(tmp), replace(options, jobs=1))
                files = {name: (Path(tmp) / name).read_bytes() for name in produced.names.values()}
    except SceneError as exc:
        return RemoteRun(task.name, {}, None, exc.report(), "invalid")
    except ArmanimError as exc:
        return RemoteRun(task.name, {}, None, exc.report(), "failed")
    return RemoteRun(task.name, files, produced.summary)


def write_remote_run(run: RemoteRun, out_root: Path) -> Path:
    """Client side: write a worker's files into ``out_root/<name>/``, replaced whole."""
    folder = Path(out_root) / run.name
    with staged_folder(folder) as staged:
        for name, data in run.files.items():
            write_bytes_atomic(staged / name, data)
    return folder


def shared_name_message(path: Path, name: str) -> str:
    """What a scene named as one before it in a batch or check is told."""
    return f"{path}: another scene in this batch is also named {name!r} (names must differ: set name:)"


def scenes_or_errors(paths: Iterable[Path]) -> list[LoadedScene | SceneError]:
    """Each of ``paths`` loaded once, or the SceneError that says why it does not load (for a command
    that reports a bad scene at its turn, after the scenes before it)."""
    loaded: list[LoadedScene | SceneError] = []
    for path in paths:
        try:
            loaded.append(load_scene(path))
        except SceneError as exc:
            loaded.append(exc)
    return loaded


def refuse_shared_names(scenes: Iterable[LoadedScene | SceneError]) -> None:
    """Exit 2 at the first of ``scenes`` (the same file given twice counts once) named as a scene
    before it: ``check`` keeps each scene's golden pair at ``<golden>/<name>.csv``, so two scenes of
    one name would share one pair (campaign 12: ``check --update`` wrote both, the second over the
    first, exit 0, and every later ``check`` of the two failed). A scene that does not load is
    left to the command, which reports it as before.

    Raises
    ------
    UsageError
        Two scenes of one name (exit 2).
    """
    names: set[str] = set()
    paths: set[Path] = set()
    for scene in scenes:
        if isinstance(scene, SceneError) or scene.path in paths:
            continue
        paths.add(scene.path)
        if scene.name in names:
            raise UsageError(shared_name_message(scene.path, scene.name))
        names.add(scene.name)


def load_tasks(paths: Iterable[Path]) -> tuple[list[SceneTask], list[BatchEntry]]:
    """Validate scene files on the client: tasks for the valid ones, entries for the rest."""
    tasks, rejected, names = [], [], set()
    for path in paths:
        try:
            scene = load_scene(path)
        except SceneError as exc:
            rejected.append(BatchEntry(Path(path).stem, "invalid", str(path), message=exc.report()))
            continue
        if scene.name in names:
            rejected.append(BatchEntry(scene.name, "invalid", str(path), message=shared_name_message(path, scene.name)))
            continue
        names.add(scene.name)
        tasks.append(SceneTask.from_scene(scene))
    return tasks, rejected


def _entry(task: SceneTask, run: RemoteRun, folder: Path) -> BatchEntry:
    s = run.summary
    assert s is not None  # a run that finished sends its summary
    totals = s["totals"]
    return BatchEntry(
        name=task.name,
        status="ok",
        scene_file=task.path,
        goals=totals["goals"],
        reached=totals["reached"],
        missed=totals["missed"],
        frames=totals["frames"],
        min_clearance=s["min_clearance"],
        folder=str(folder),
        summary=s,
    )


BROKEN_POOL_HINT = (
    " (a worker process died; if armanim is called from a Python script, keep the call under "
    '`if __name__ == "__main__":`, because each worker imports the script again; jobs=1 needs no workers)'
)


def _failed(task: SceneTask, exc: BaseException) -> BatchEntry:
    message = exc.report() if isinstance(exc, ArmanimError) else f"{task.path}: {type(exc).__name__}: {exc}"
    if isinstance(exc, BrokenProcessPool):
        message += BROKEN_POOL_HINT
    return BatchEntry(task.name, "failed", task.path, message=message)


def run_tasks(
    tasks: list[SceneTask],
    out_root: Path,
    options: RunOptions | None = None,
    *,
    scheduler: str | None = None,
    progress: Callable[..., None] | None = None,
) -> list[BatchEntry]:
    """Run validated tasks and write their outputs, as ``options`` ask (default: every output;
    ``options.jobs`` scenes at a time); one entry per task, in task order.

    ``progress(done, total, running)`` is called at the start and after each scene, with
    the names of the scenes that are running (the first unfinished ones, one per worker).
    """
    options = options or RunOptions()
    workers = options.jobs or os.cpu_count() or 1
    executor = executor_for(workers, scheduler, WORKER_PRELOAD)
    entries: dict[str, BatchEntry] = {}
    unfinished = [t.name for t in tasks]
    done = 0
    if progress:
        progress(0, len(tasks), tuple(unfinished[:workers]))
    for task, run, exc in executor.map(run_task, tasks, options):
        if exc is None and run.error is not None:
            entries[task.name] = BatchEntry(task.name, run.status, task.path, message=run.error)
        elif exc is None:
            try:
                entries[task.name] = _entry(task, run, write_remote_run(run, out_root))
            except ArmanimError as write_exc:
                entries[task.name] = _failed(task, write_exc)
        else:
            entries[task.name] = _failed(task, exc)
        done += 1
        unfinished.remove(task.name)
        if progress:
            progress(done, len(tasks), tuple(unfinished[:workers]))
    return [entries[t.name] for t in tasks]


def is_index_header(line: str) -> bool:
    """Whether ``line`` is the first line of an index.csv armanim wrote.

    >>> is_index_header(",".join(INDEX_COLUMNS)), is_index_header("my,own,table")
    (True, False)
    """
    return line == ",".join(INDEX_COLUMNS)


def index_csv_text(entries: list[BatchEntry]) -> str:
    """index.csv: one row per scene."""
    rows = (
        [
            e.name,
            e.status,
            e.scene_file,
            e.goals,
            e.reached,
            e.missed,
            e.frames,
            "" if e.min_clearance is None else repr(float(e.min_clearance)),
            e.folder,
            e.message,
        ]
        for e in entries
    )
    return table_csv_text(INDEX_COLUMNS, rows, text_cells=True)


def run_batch(
    paths: Iterable[Path],
    out_root: Path,
    options: RunOptions | None = None,
    *,
    scheduler: str | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> list[BatchEntry]:
    """Run many scene files in parallel, as ``options`` ask (default: every output, on every
    core); write their outputs and ``ROOT/index.csv``.

    Returns the entries in the order of ``paths`` (invalid scenes included).
    """
    paths = list(dict.fromkeys(Path(p) for p in paths))  # the same file twice runs once
    index = Path(out_root) / "index.csv"
    with marks_locked(index.parent):  # (another batch into OUT may be writing it and its mark)
        check_table_replaceable(index, is_index_header, "index.csv")  # a user's index.csv: exit 3 before any work
    tasks, rejected = load_tasks(paths)
    done = run_tasks(tasks, out_root, options, scheduler=scheduler, progress=progress)
    by_file = {e.scene_file: e for e in [*done, *rejected]}
    entries = [by_file[str(p)] for p in paths if str(p) in by_file]
    write_index(index, entries)
    return entries


def write_index(path: Path, entries: list[BatchEntry]) -> None:
    """Write ``index.csv``, replacing only an index.csv armanim wrote (checked under the lock of
    the marked files in its folder: another batch or sweep into the same OUT takes turns)."""
    write_marked(
        path,
        index_csv_text(entries),
        "index.csv",
        recheck=lambda: check_table_replaceable(path, is_index_header, "index.csv"),
    )
