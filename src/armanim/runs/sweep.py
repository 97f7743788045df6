"""Parameter sweeps: one scene, the product of several settings, compared in one table.

``--set solver.step=0.05,0.1 --set solver.method=pinv,dls`` makes four variants, each a
complete, validated scene named after its settings (``notes-arm_step-0.05_method-pinv``)
and run like any batch; the comparison goes to ``ROOT/<scene>-sweep.csv``.
"""

from __future__ import annotations

import copy
import itertools
import json
import math
import re
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import yaml

from armanim.errors import Diagnostic, SceneError, UsageError
from armanim.output.csvfile import check_table_replaceable, table_csv_text
from armanim.output.marks import marks_locked, write_marked
from armanim.runs.batch import BatchEntry, SceneTask, is_index_header, run_tasks, write_index
from armanim.runs.options import RunOptions
from armanim.scene import load_scene, scene_from_bytes
from armanim.scene.yamlread import MAX_DEPTH, read_yaml

MAX_VARIANTS = 1_000
"""The most variants one sweep runs (as a scene has at most 1,000 goals): more is a typo, or a job for a batch."""
_PATH = re.compile(r"^[A-Za-z_]\w*(\[\d+\])?(\.[A-Za-z_]\w*(\[\d+\])?)*$")


@dataclass(frozen=True)
class Setting:
    """One ``--set PATH=V1,V2,...``: a field path and the values to try."""

    path: str
    values: tuple

    @property
    def short(self) -> str:
        """The last part of the path, for variant names (``solver.step`` -> ``step``)."""
        return re.sub(r"\[(\d+)\]", r"\1", self.path.split(".")[-1])


def _split_values(text: str) -> list[str]:
    parts, depth, current = [], 0, ""
    for ch in text:
        if ch in "[{":
            depth += 1
        elif ch in "]}":
            depth -= 1
        if ch == "," and depth == 0:
            parts.append(current)
            current = ""
        else:
            current += ch
    return [p.strip() for p in [*parts, current] if p.strip()]


def parse_setting(text: str) -> Setting:
    """``"solver.step=0.05,0.1"`` -> Setting; values read as YAML (numbers, words, lists)."""
    path, sep, values = text.partition("=")
    path = path.strip()
    if not sep or not _PATH.match(path):
        raise UsageError(f"--set: expected FIELD.PATH=VALUE1,VALUE2,... e.g. --set solver.step=0.05,0.1 (got {text!r})")
    depth = len(re.findall(r"[A-Za-z_]\w*|\[\d+\]", path))
    if depth > MAX_DEPTH:  # campaign 9: 5,000 parts nested the variant 5,000 deep, a RecursionError
        raise UsageError(f"--set {path[:60]}...: the path is {depth:,} fields deep (a scene nests at most {MAX_DEPTH})")
    items = _split_values(values)
    if not items:
        raise UsageError(f"--set {path}: no values given (expected e.g. {path}=0.05,0.1)")
    return Setting(path, tuple(_read_value(path, v) for v in items))


def _read_value(path: str, text: str):
    """One ``--set`` value, read by the same bounded YAML reader as scene files (no alias bombs)."""
    try:
        doc = read_yaml(text, f"--set {path}")
    except SceneError as exc:
        raise UsageError(
            f"--set {path}: {text[:40]!r} is not a plain number, word or list ({exc.problems[0].message})"
        ) from None
    if doc.problems:
        raise UsageError(f"--set {path}: {text[:40]!r}: {doc.problems[0].message}")
    return doc.data


def _assign(data: dict, path: str, value) -> None:
    parts = re.findall(r"[A-Za-z_]\w*|\[\d+\]", path)
    node = data
    for i, part in enumerate(parts):
        last = i == len(parts) - 1
        if part.startswith("["):
            index = int(part[1:-1])
            if not isinstance(node, list) or index >= len(node):
                raise UsageError(f"--set {path}: {part} does not exist in the scene")
            if last:
                node[index] = value
            else:
                node = node[index]
        else:
            if not isinstance(node, dict):
                raise UsageError(f"--set {path}: {part!r} is not inside a mapping in the scene")
            if last:
                node[part] = value
            else:
                nxt = parts[i + 1]
                node = node.setdefault(part, [] if nxt.startswith("[") else {})


def _label(value) -> str:
    text = str(value).replace(" ", "")
    return re.sub(r"[^A-Za-z0-9_.-]", "", text) or "x"


@dataclass(frozen=True)
class Variant:
    """One combination: the values it was given and its task, or why it was rejected."""

    values: dict
    name: str
    task: SceneTask | None
    rejected: BatchEntry | None


def variants(scene_path: Path, settings: list[Setting]) -> list[Variant]:
    """Every combination of the settings as a validated scene (or its validation errors)."""
    base_scene = load_scene(scene_path)
    data0 = read_yaml(base_scene.raw.decode("utf-8"), str(scene_path)).data
    assert isinstance(data0, dict)  # load_scene validated it: a mapping
    result = []
    names: set[str] = set()
    for combo in unique_combinations(settings):
        data = copy.deepcopy(data0)
        for setting, value in zip(settings, combo):
            _assign(data, setting.path, value)
        name = _unique(
            "_".join([base_scene.name, *(f"{s.short}-{_label(v)}" for s, v in zip(settings, combo))])[:96], names
        )
        data["name"] = name
        text = f"# armanim sweep variant of {Path(scene_path).name}\n" + yaml.safe_dump(data, sort_keys=False)
        values = {s.path: v for s, v in zip(settings, combo)}
        try:
            scene = scene_from_bytes(text.encode("utf-8"), f"{scene_path} [{name}]", name)
        except SceneError as exc:
            report = variant_error(exc, values).report()
            result.append(Variant(values, name, None, BatchEntry(name, "invalid", str(scene_path), message=report)))
            continue
        result.append(Variant(values, name, SceneTask.from_scene(scene), None))
    return result


def variant_error(exc: SceneError, values: dict) -> SceneError:
    """A variant's problems without line numbers (they would point into the generated YAML,
    not the user's file), each naming the ``--set`` value it comes from, if one does: the
    setting at or above the problem's field, else the only setting below it (the base scene
    is valid, so a problem at ``nosuch`` comes from ``--set nosuch.field=1``: campaign 12)."""
    problems = []
    for p in exc.problems:
        setting = next((path for path in values if p.path == path or _inside(p.path, path)), None)
        below = [path for path in values if _inside(path, p.path)]
        if setting is None and len(below) == 1:
            setting = below[0]
        message = f"--set {setting}={_shown(values[setting])}: {p.message}" if setting else p.message
        problems.append(Diagnostic(p.path, message, None))
    return SceneError(exc.file, problems)


def _inside(path: str, outer: str) -> bool:
    """Whether field ``path`` lies inside field ``outer`` (``a.b`` and ``a[0]`` inside ``a``)."""
    return path.startswith(outer + ".") or path.startswith(outer + "[")


def _shown(value) -> str:
    """A ``--set`` value as a message shows it: a word as it is, anything else as JSON (a list
    stays a list; the variant's name strips it to a label: campaign 12 showed ``[1e-9, 1e-9]``
    as ``1e-091e-09``).

    >>> _shown("bogus"), _shown(5), _shown([1e-09, 1e-09]), _shown({"links": [1, 1]})
    ('bogus', '5', '[1e-09, 1e-09]', '{"links": [1, 1]}')
    """
    return value if isinstance(value, str) else json.dumps(value)


def variant_count(settings: list[Setting]) -> int:
    """How many variants the settings make, computed from the numbers of values before any is built.

    >>> variant_count([Setting("solver.step", (0.1, 0.2)), Setting("solver.method", ("pinv", "dls", "pinv"))])
    4

    Raises
    ------
    UsageError
        More than :data:`MAX_VARIANTS` combinations, or two settings of one field (or of a field
        and a field inside it) (exit 2).
    """
    overlapping = _overlapping_paths(settings)
    if overlapping:
        outer, inner = overlapping
        said = f"--set {inner} is given twice" if outer == inner else f"--set {inner} is a field inside --set {outer}"
        raise UsageError(f"{said}: the later would overwrite the earlier's values (give each field's values once)")
    product = math.prod(len(s.values) for s in settings)
    if product > MAX_VARIANTS:
        sizes = " x ".join(f"{len(s.values):,}" for s in settings)
        raise UsageError(
            f"--set: {product:,} variants ({sizes} values; at most {MAX_VARIANTS:,} in one sweep: give fewer values)"
        )
    return len(unique_combinations(settings))


def _overlapping_paths(settings: list[Setting]) -> tuple[str, str] | None:
    """The first two settings' paths (outer, inner) where one is the other or a field inside it, if any.

    >>> _overlapping_paths([Setting("goals[0].hold", (1,)), Setting("goals[0]", (2,))])
    ('goals[0]', 'goals[0].hold')
    >>> _overlapping_paths([Setting("goals[1]", (1,)), Setting("goals[10]", (2,))]) is None
    True
    """
    for i, first in enumerate(settings):
        for second in settings[i + 1 :]:
            outer, inner = sorted((first.path, second.path), key=len)
            if inner == outer or inner.startswith((outer + ".", outer + "[")):
                return outer, inner
    return None


def unique_combinations(settings: list[Setting]) -> list[tuple]:
    """The product of the settings' values, each combination once (``0.1,0.1`` runs once)."""
    seen, combos = set(), []
    for combo in itertools.product(*(s.values for s in settings)):
        key = repr(combo)
        if key not in seen:
            seen.add(key)
            combos.append(combo)
    return combos


def _unique(name: str, taken: set[str]) -> str:
    """``name``, or ``name-2``, ``name-3``... when labels that drop punctuation collide."""
    candidate, k = name, 1
    while candidate in taken:
        k += 1
        candidate = f"{name}-{k}"
    taken.add(candidate)
    return candidate


SWEEP_TAIL = ("min_clearance", "max_joint_step_deg")
SETTING_PREFIX = "set:"
"""Put before a setting's column name that is also the name of one of the table's own columns."""


def setting_columns(settings: list[Setting], own: list[str]) -> list[str]:
    """The sweep table's column of each setting: its path, or ``set:PATH`` where the path is
    the name of one of the table's ``own`` columns (``--set name=...`` would give two ``name``).

    >>> setting_columns([Setting("name", ("a",)), Setting("solver.step", (0.1,))], ["name", "status"])
    ['set:name', 'solver.step']
    """
    return [SETTING_PREFIX + s.path if s.path in own else s.path for s in settings]


def is_sweep_header(line: str) -> bool:
    """Whether ``line`` is the first line of a sweep table armanim wrote (its columns vary with the settings).

    >>> is_sweep_header("name,solver.step,status,reached,missed,frames,goal0_frames,min_clearance,max_joint_step_deg")
    True
    >>> is_sweep_header("name,notes")
    False
    """
    columns = line.split(",")
    return columns[:1] == ["name"] and tuple(columns[-2:]) == SWEEP_TAIL and "status" in columns


def comparison_rows(
    settings: list[Setting], items: list[Variant], entries: list[BatchEntry]
) -> tuple[list[str], list[list]]:
    """Header and rows of the sweep table: settings, goals, frames per goal, clearance, joint step.

    Every column name is distinct: a setting named like one of the table's own columns is
    ``set:PATH`` (:func:`setting_columns`).

    ``entries`` are the variants' batch entries, in the same order as ``items``.
    """
    n_goals = max((len(e.summary["goals"]) for e in entries if e.summary), default=0)
    outcome = ["status", "reached", "missed", "frames", *(f"goal{k}_frames" for k in range(n_goals)), *SWEEP_TAIL]
    header = ["name", *setting_columns(settings, ["name", *outcome]), *outcome]
    rows = []
    for variant, entry in zip(items, entries):
        s = entry.summary
        per_goal = [(g["frames"] if g["reached"] else "missed") for g in s["goals"]] if s else [""] * n_goals
        rows.append(
            [
                entry.name,
                *(variant.values[st.path] for st in settings),
                entry.status,
                entry.reached,
                entry.missed,
                entry.frames,
                *per_goal,
                "" if not s or s["min_clearance"] is None else f"{s['min_clearance']:.6g}",
                "" if not s else f"{s['max_joint_step_deg']:.6g}",
            ]
        )
    return header, rows


@dataclass(frozen=True)
class SweepResult:
    """What :func:`run_sweep` did.

    Attributes
    ----------
    variants : list of Variant
        Every combination, in the order of the settings' product.
    entries : list of BatchEntry
        Each variant's outcome, in the same order (rejected variants included).
    header, rows
        The comparison table, as written to ``table``.
    table : Path
        ``ROOT/<scene>-sweep.csv``.
    """

    variants: list[Variant]
    entries: list[BatchEntry]
    header: list[str]
    rows: list[list]
    table: Path


def run_sweep(
    scene_path: str | Path,
    settings: list[Setting],
    out_root: str | Path,
    *,
    jobs: int | None = None,
    scheduler: str | None = None,
    video: bool = False,
    progress: Callable[..., None] | None = None,
) -> SweepResult:
    """Run every combination of ``settings`` on a scene as a batch; write each variant's
    outputs under ``out_root/<variant name>/``, the comparison table and ``index.csv``.

    ``progress(done, total, running)`` is called as :func:`armanim.runs.batch.run_tasks` calls it.
    A variant the scene model rejects is reported in its entry and not run.

    Raises
    ------
    UsageError
        More than :data:`MAX_VARIANTS` variants (checked before any is built).
    """
    variant_count(settings)
    scene_path, out_root = Path(scene_path), Path(out_root)
    table = out_root / f"{scene_path.stem}-sweep.csv"
    with marks_locked(out_root):  # (another sweep or batch into OUT may be writing them and their marks)
        check_table_replaceable(
            table, is_sweep_header, "sweep table"
        )  # a user's file at these names: exit 3 before any work
        check_table_replaceable(out_root / "index.csv", is_index_header, "index.csv")
    items = variants(scene_path, settings)
    tasks = [v.task for v in items if v.task is not None]
    done = run_tasks(tasks, out_root, RunOptions(video=video, jobs=jobs), scheduler=scheduler, progress=progress)
    by_name = {e.name: e for e in done}
    entries = [v.rejected if v.rejected is not None else by_name[v.name] for v in items]
    header, rows = comparison_rows(settings, items, entries)
    write_marked(
        table,
        table_csv_text(header, rows, text_cells=True),
        "sweep table",
        recheck=lambda: check_table_replaceable(table, is_sweep_header, "sweep table"),
    )
    write_index(out_root / "index.csv", entries)
    return SweepResult(items, entries, header, rows, table)
