"""Load a scene file: bytes -> YAML with lines -> pydantic models -> cross-field checks.

Every problem is collected and raised together as one :class:`SceneError` whose lines
read ``FILE:LINE: field.path: what is wrong (what is expected)``.
"""

from __future__ import annotations

import copy
import difflib
import functools
import hashlib
import re
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any, cast

from pydantic import BaseModel, ValidationError

from armanim import __version__
from armanim.errors import Diagnostic, SceneError
from armanim.output.files import read_bounded
from armanim.scene.armmodel import ArmModel
from armanim.scene.checks import as_diagnostics, fallback_notes, radian_notes, scene_problems
from armanim.scene.fieldpaths import YamlDocument, join_path
from armanim.scene.limits import rate_notes
from armanim.scene.models import SCENE_VERSION, SceneModel, name_problem
from armanim.scene.robots import read_arm_files, read_scene_files
from armanim.scene.yamlread import MAX_FILE_BYTES, read_yaml
from armanim.scene.yamlscalars import TooLarge

MAX_PROBLEMS = 30  # problems listed for one file; the rest are counted


@dataclass(frozen=True)
class LoadedScene:
    """A validated scene and where it came from.

    Attributes
    ----------
    model : SceneModel
    path : Path
    name : str
        ``name`` from the file, else the file's stem.
    sha256 : str
        Hex digest of the file's bytes.
    raw : bytes
        The file's bytes (copied into the run's output folder).
    notes : tuple of Diagnostic
        Things worth a second look that are not errors (angles that look like radians, joint rates
        above the robot's own).
    """

    model: SceneModel
    path: Path
    name: str
    sha256: str
    raw: bytes
    notes: tuple[Diagnostic, ...] = ()


def read_scene_bytes(path: Path) -> bytes:
    """Read a scene file's bytes, with clear errors for missing, unreadable, special or huge files."""
    return read_bounded(path, MAX_FILE_BYTES, "a scene")


def decode_scene(raw: bytes, file: str) -> str:
    """UTF-8 text of a scene's bytes; binary or non-UTF-8 bytes are errors with their line.

    >>> decode_scene("version: 1".encode("utf-16"), "s.yaml")
    Traceback (most recent call last):
    armanim.errors.SceneError: s.yaml:1: is UTF-16 text (save the file as UTF-8)
    """
    if raw.startswith((b"\xff\xfe", b"\xfe\xff")):  # a UTF-16 byte-order mark: text, not binary
        raise SceneError(file, [Diagnostic("", "is UTF-16 text (save the file as UTF-8)", 1)])
    if b"\x00" in raw:
        line = raw[: raw.index(b"\x00")].count(b"\n") + 1
        raise SceneError(file, [Diagnostic("", "is a binary file (expected a YAML text file)", line)])
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = raw[: exc.start].count(b"\n") + 1
        raise SceneError(
            file, [Diagnostic("", f"byte 0x{raw[exc.start]:02x} is not UTF-8 (save the file as UTF-8)", line)]
        ) from None


def load_scene(
    path: str | Path, *, urdf_file: str | Path | None = None, srdf_file: str | Path | None = None
) -> LoadedScene:
    """Read and validate a scene file.

    Parameters
    ----------
    path : str or Path
    urdf_file : str or Path, optional
        Read an ``arm.urdf`` arm from this file instead of the path the scene gives (a run
        folder keeps its own copy of the robot, so it re-renders wherever it is moved).
    srdf_file : str or Path, optional
        Likewise, an ``arm.self_collision.srdf`` file read in place of the scene's.

    Returns
    -------
    LoadedScene

    Raises
    ------
    SceneError
        With every problem found, each with its field path and line.
    """
    path = Path(path)
    return scene_from_bytes(read_scene_bytes(path), path, urdf_file=urdf_file, srdf_file=srdf_file)


def scene_from_bytes(
    raw: bytes,
    path: str | Path,
    name: str | None = None,
    *,
    urdf_file: str | Path | None = None,
    srdf_file: str | Path | None = None,
) -> LoadedScene:
    """Validate a scene given as bytes (e.g. sent to a worker); ``path`` names it.

    ``name`` overrides the scene's own name (sweep variants are named after their settings);
    ``urdf_file`` and ``srdf_file`` as for :func:`load_scene`.
    """
    path = Path(path)
    model, doc = _validated(decode_scene(raw, str(path)), str(path), urdf_file, srdf_file)
    name = name or model.name or stem_name(path)
    notes = tuple(as_diagnostics(radian_notes(model) + fallback_notes(model) + rate_notes(model), doc.line_of))
    return LoadedScene(model=model, path=path, name=name, sha256=hashlib.sha256(raw).hexdigest(), raw=raw, notes=notes)


def field_line(scene: LoadedScene, field: str) -> int | None:
    """The line of ``field`` (a path such as ``arm.max_joint_speed``, or its nearest parent) in
    the scene's file, for a problem found after validation (the bytes are read again, bounded)."""
    return read_yaml(decode_scene(scene.raw, str(scene.path)), str(scene.path)).line_of(field)


def stem_name(path: Path) -> str:
    """The run name a scene without ``name:`` takes from its file name, if it is a safe folder name.

    Raises
    ------
    SceneError
        ``..yaml`` would name the output root itself, ``.x.yaml`` a hidden staging folder.
    """
    problem = name_problem(path.stem)
    if problem is not None:
        hint = "add a line such as `name: my-arm` to the scene, or rename the file"
        raise SceneError(
            str(path), [Diagnostic("name", f"not set, so the file name gives the name, but {problem}: {hint}", 1)]
        )
    return path.stem


def validate_scene_text(text: str, file: str) -> SceneModel:
    """Validate YAML text as a scene; ``file`` only names it in messages."""
    return _validated(text, file)[0]


def _validated(text: str, file: str, urdf_file: str | Path | None = None, srdf_file: str | Path | None = None):
    """(model, parsed document) of a valid scene text; SceneError with every problem otherwise.

    One pass reports every problem it can: the YAML's, every field's type or bound, the arm's files
    (URDF, SRDF), and the cross-field checks (counts, sizes, rates, frame budgets, clearances) of
    every part that did validate, the bad parts left out (:func:`_salvaged`).
    """
    doc = read_yaml(text, file)
    problems = list(doc.problems)
    if doc.data is None and problems:
        raise SceneError(file, problems)
    if not isinstance(doc.data, dict):
        kind = type(doc.data).__name__ if doc.data is not None else "null"
        raise SceneError(
            file,
            problems
            + [Diagnostic("", f"the top level is a {kind} (expected a mapping with version, arm, goals, ...)", 1)],
        )
    files = (Path(file).parent, urdf_file, srdf_file)
    model, errors, file_errors = _validated_model(doc.data, files)
    found = problems + [_diagnostic(err, doc) for err in errors[: MAX_PROBLEMS + 1]]
    if model is None:
        found += _problems_beside(
            doc, [tuple(e["loc"]) for e in errors], files, {p.path for p in found}, bool(file_errors)
        )
    else:
        found += as_diagnostics(scene_problems(model), doc.line_of)
        if model.name is None:
            found += _stem_problems(file)
    if found:
        raise SceneError(file, _by_line(found, len(errors)), also=file_errors)
    if file_errors:
        raise (
            file_errors[0]
            if len(file_errors) == 1
            else SceneError(file_errors[0].file, file_errors[0].problems, also=file_errors[1:])
        )
    return model, doc


def _stem_problems(file: str) -> list[Diagnostic]:
    """The problem of a file name that cannot name the run (a scene without ``name:``)."""
    try:
        stem_name(Path(file))
    except SceneError as exc:
        return exc.problems
    return []


def _validated_model(data: dict, files: tuple) -> tuple[SceneModel | None, list[Any], list[SceneError]]:
    """(the scene with its arm's files read, [], []) or (None, pydantic's errors, the arm's files'
    errors): the YAML is validated first, then the URDF and SRDF are read (``files``: the scene's
    folder and the files read in their place, :func:`armanim.scene.robots.read_arm_files`) once
    the arm section is valid, whatever else is wrong, so that one pass reports every problem.

    A problem of the arm section that only its files tell (a link the URDF does not have) is
    one more error at ``arm``, after those of ``version`` and ``name``; a problem of a file
    itself is its SceneError (``FILE:LINE: message``), returned beside the scene's.
    """
    try:
        model, errors = SceneModel.model_validate(data), []
    except ValidationError as exc:
        model, errors = None, [e for e in exc.errors(include_url=False) if not isinstance(e.get("input"), TooLarge)]
    if any(e["loc"] and e["loc"][0] == "arm" for e in errors):
        return None, errors, []  # the arm is not known: its files are not read
    try:
        arm = read_arm_files(model.arm if model is not None else ArmModel.model_validate(data["arm"]), *files)
    except SceneError as exc:
        return None, errors, [exc]
    except ValueError as exc:
        at = sum(1 for e in errors if e["loc"] and e["loc"][0] in ("version", "name"))  # pydantic's order of fields
        error = {
            "type": "value_error",
            "loc": ("arm", *getattr(exc, "loc", ())),
            "msg": f"Value error, {exc}",
            "input": data.get("arm"),
            "ctx": {"error": exc},
        }
        return None, errors[:at] + [error] + errors[at:], []
    return (model.model_copy(update={"arm": arm}) if model is not None else None), errors, []


def scene_model(
    data: dict, scene_dir: str | Path = ".", urdf_file: str | Path | None = None, srdf_file: str | Path | None = None
) -> SceneModel:
    """A scene given as a mapping (not a file), validated, then its arm's files read
    (``arm.urdf`` relative to ``scene_dir``; see :func:`armanim.scene.robots.read_arm_files`).

    Raises
    ------
    pydantic.ValidationError
        The mapping is not a scene.
    ValueError
        The arm names something its URDF does not have.
    SceneError
        A URDF or SRDF file is bad.

    >>> scene_model({"version": 1, "arm": {"robot": "panda"}, "goals": [[0.5, 0, 0.5]]}).arm.joint_count
    7
    """
    return read_scene_files(SceneModel.model_validate(data), scene_dir, urdf_file, srdf_file)


SETTINGS = ("name", "floor", "render", "solver")
"""Top-level keys whose bad values can be left out (their defaults taken) to check the rest."""

LISTS = ("goals", "obstacles")
"""Top-level lists whose bad items can be left out to check the rest."""

STAND_IN_ARM = {"links": [1.0]}
"""The arm checked in place of one that cannot be read: no check that reads the arm is made with it."""

MAX_SALVAGE = 3
"""Rounds of leaving bad parts out (a field, then its item, then its section) before giving up."""


def _problems_beside(
    doc: YamlDocument, bad: list[tuple], files: tuple, known: set[str], arm_unread: bool
) -> list[Diagnostic]:
    """The cross-field problems of a scene with field errors, checked with the bad parts left out
    (:func:`_salvaged`), so that one pass reports every problem; a check that reads a part left
    out (or a default taken for it) is skipped. ``arm_unread``: the arm's files could not be read."""
    salvaged = _salvaged(cast(dict, doc.data), bad, files, arm_unread)  # _validated checked it is a mapping
    if salvaged is None:
        return []
    model, unknown, kept = salvaged
    found = as_diagnostics(
        [
            (_original_indices(path, kept), _original_indices(message, kept))
            for path, message in scene_problems(model, frozenset(unknown))
        ],
        doc.line_of,
    )
    return [
        p
        for p in found
        if p.path not in known and not any(p.path.startswith(k + ".") or p.path.startswith(k + "[") for k in known)
    ]


def _salvaged(data: dict, bad: list[tuple], files: tuple, arm_unread: bool):
    """(model, unknown field paths, kept indices of goals and obstacles) of the scene ``data`` with
    the parts at the error locations ``bad`` left out, or None when no scene is left.

    A bad field of a section (``solver.clearance``, ``arm.home``, ``goals[2].speed``) is left out
    and its default taken; if the section or item is still bad, a goal or obstacle is left out
    (the others keep their own indices in messages), a setting section takes its defaults, and an
    arm that cannot be read (or whose files cannot) is a stand-in that no check reads. Unknown top-level keys are dropped.
    """
    data = copy.deepcopy(data)
    unknown: set[str] = set()
    drop: dict[str, set[int]] = {"goals": set(), "obstacles": set()}
    stand_in = arm_unread or not isinstance(data.get("arm"), dict)
    data.setdefault("version", 1)
    for level in range(MAX_SALVAGE):
        for loc in bad:
            _leave_out(data, loc, level, unknown, drop)
        if level == 2 and any(loc and loc[0] == "arm" for loc in bad):
            stand_in = True
        kept = {
            key: [k for k in range(len(data[key])) if k not in drop[key]] if isinstance(data.get(key), list) else []
            for key in LISTS
        }
        trial = {**data, **{key: [data[key][k] for k in kept[key]] for key in LISTS if isinstance(data.get(key), list)}}
        if stand_in:
            trial["arm"], unknown = STAND_IN_ARM, unknown | {"arm"}
        if not isinstance(trial.get("goals"), list) or not trial["goals"]:
            trial["goals"], unknown = [[0.0, 0.0, 0.0]], unknown | {"goals"}
        try:
            model = SceneModel.model_validate(trial)
        except ValidationError as exc:
            bad = [_in_file(tuple(e["loc"]), kept) for e in exc.errors(include_url=False)]
            if any(not loc for loc in bad):
                return None
            continue
        if not stand_in:
            try:
                model = model.model_copy(update={"arm": read_arm_files(model.arm, *files)})
            except (ValueError, SceneError):
                stand_in, bad = True, []
                continue
        gone = {
            f"{key}[{k}]" for key in LISTS for k in drop[key]
        }  # a field of an item left out is no unknown of the rest
        return model, {u for u in unknown if u.split(".")[0] not in gone}, kept
    return None


def _in_file(loc: tuple, kept: dict[str, list[int]]) -> tuple:
    """An error location in a scene with items left out, as the file's location."""
    if len(loc) > 1 and loc[0] in LISTS and isinstance(loc[1], int) and loc[1] < len(kept[loc[0]]):
        return (loc[0], kept[loc[0]][loc[1]], *loc[2:])
    return loc


def _leave_out(data: dict, loc: tuple, level: int, unknown: set[str], drop: dict[str, set[int]]) -> None:
    """Leave out the part of ``data`` at the error location ``loc``: at ``level`` 0 the field of
    a section or of a goal or obstacle, at 1 the goal or obstacle, at 2 the section."""
    if not loc:
        return
    head = loc[0]
    if head in LISTS and len(loc) > 1 and isinstance(loc[1], int) and isinstance(data.get(head), list):
        item = data[head][loc[1]] if loc[1] < len(data[head]) else None
        if level == 0 and len(loc) > 2 and isinstance(loc[2], str) and isinstance(item, dict) and loc[2] in item:
            del item[loc[2]]
            unknown.add(f"{head}[{loc[1]}].{loc[2]}")
        elif level >= 1:
            drop[head].add(loc[1])
        return
    section = data.get(head)
    if head not in SceneModel.model_fields:
        data.pop(head, None)  # an unknown key
    elif (
        level == 0
        and loc[:2] == ("arm", "links")
        and isinstance(section, dict)
        and isinstance(section.get("links"), list)
    ):
        section["links"] = [1.0] * len(
            section["links"]
        )  # a stand-in of the same joint count: the arm's other fields are checked
        unknown.add("arm.links")
    elif level < 2 and len(loc) > 1 and isinstance(loc[1], str) and isinstance(section, dict) and loc[1] in section:
        del section[loc[1]]
        unknown.add(f"{head}.{loc[1]}")
    elif level >= 1 and head in data and (head in SETTINGS or head in LISTS):
        del data[head]
        unknown.add(head)
    elif head == "version":
        data["version"] = 1


def _original_indices(text: str, kept: dict[str, list[int]]) -> str:
    """``text`` with each ``goals[k]`` and ``obstacles[k]`` of the checked scene (its bad items left
    out) written as the file's index."""

    def original(match: re.Match) -> str:
        indices = kept[match.group(1)]
        k = int(match.group(2))
        return f"{match.group(1)}[{indices[k]}]" if k < len(indices) else match.group(0)

    return INDEXED.sub(original, text)


INDEXED = re.compile(r"\b(goals|obstacles)\[(\d+)\]")


def _by_line(problems: list[Diagnostic], model_errors: int = 0) -> list[Diagnostic]:
    """Problems sorted by line; past MAX_PROBLEMS, one line says how many more there are."""
    problems = sorted(problems, key=lambda p: p.line or 0)
    total = len(problems) + max(0, model_errors - (MAX_PROBLEMS + 1))
    if total <= MAX_PROBLEMS:
        return problems
    return problems[:MAX_PROBLEMS] + [Diagnostic("", f"... and {total - MAX_PROBLEMS} more problems (fix these first)")]


def _path(loc: tuple) -> str:
    path = ""
    for part in loc:
        if isinstance(part, str) and part.startswith(("function-", "list[", "literal[", "int", "float")) and path:
            continue  # pydantic's union-branch labels, not scene fields
        path = join_path(path, part)
    return path


def _diagnostic(err: dict, doc: YamlDocument) -> Diagnostic:
    loc = tuple(err["loc"])
    path = _path(loc)
    return Diagnostic(path, problem_message(err, loc), doc.line_of(path))


def _allowed_keys(loc: tuple) -> list[str]:
    model: type[BaseModel] = SceneModel
    for part in loc[:-1]:
        if isinstance(part, int):
            continue
        field = model.model_fields.get(part)
        if field is None:
            return []
        annotation = field.annotation
        candidates = [annotation, *getattr(annotation, "__args__", ())]
        for c in candidates:
            for inner in (c, *getattr(c, "__args__", ())):
                if isinstance(inner, type) and issubclass(inner, BaseModel):
                    model = inner
                    break
            else:
                continue
            break
    return list(model.model_fields)


POINT_FIELDS = ("base", "center", "position")
"""Fields that hold exactly three coordinates."""

_BOUND_SIGNS = {"greater_than": ">", "greater_than_equal": ">=", "less_than": "<", "less_than_equal": "<="}
_EXPECTED_TYPES = {
    **dict.fromkeys(("float_type", "int_type", "float_parsing", "int_from_float"), "a number"),
    "list_type": "a list",
    **dict.fromkeys(("model_type", "model_attributes_type", "dict_type"), "a mapping of keys"),
    "string_type": "a string",
    "bool_type": "true or false",
}
"""What ``must be`` of a value of the wrong type, by pydantic's error type."""


def problem_message(err: Mapping[str, Any], loc: tuple[int | str, ...]) -> str:
    """What is wrong, and what was expected, for one pydantic error at ``loc``."""
    kind = err["type"]
    got = err.get("input")
    ctx = err.get("ctx") or {}
    if kind == "extra_forbidden":
        return _unknown_key_message(loc)
    if kind == "missing":
        return "is required but missing" + (" (add `version: 1`)" if loc == ("version",) else "")
    if loc == ("version",) and isinstance(got, int) and not isinstance(got, bool) and got > SCENE_VERSION:
        return f"version {got} is newer than this armanim {__version__} reads (it reads version {SCENE_VERSION}; upgrade armanim)"
    if kind == "literal_error":
        return f"{got!r} is not allowed (expected {ctx.get('expected')})"
    if kind in _BOUND_SIGNS:
        return f"must be {_BOUND_SIGNS[kind]} {next(iter(ctx.values())):g} (got {_describe(got)})"
    if kind == "finite_number":
        return f"must be a finite number (got {_describe(got)})"
    if kind in ("too_short", "too_long"):
        return _length_message(loc, ctx)
    if len(loc) == 2 and loc[0] == "goals" and isinstance(got, (int, float)) and not isinstance(got, bool):
        return f"must be a point [x, y, z] or {{position: [x, y, z]}} (got {_describe(got)}; a single goal is written goals: [[x, y, z]])"
    if kind in _EXPECTED_TYPES:
        return f"must be {_EXPECTED_TYPES[kind]} (got {_describe(got)})"
    if kind == "value_error":  # a model's own check (e.g. arm.robot): its message says it all
        return str(ctx.get("error", err["msg"]))
    if kind == "string_pattern_mismatch":
        return name_problem(str(got)) or f"{got!r} is not a valid name"
    return f"{err['msg'][0].lower()}{err['msg'][1:]} (got {_describe(got)})"


def _unknown_key_message(loc: tuple) -> str:
    """The key at the end of ``loc`` is not a field there: say which are, and the closest."""
    key = loc[-1]
    allowed = _allowed_keys(loc)
    close = difflib.get_close_matches(str(key), allowed, n=1)
    hint = f"did you mean {close[0]!r}? " if close else ""
    return f"unknown key {key!r} ({hint}expected one of: {', '.join(allowed)})"


def _length_message(loc: tuple, ctx: dict) -> str:
    """Too few or too many items; a point names its three coordinates (pydantic names only the violated bound)."""
    if loc and loc[-1] in POINT_FIELDS:
        return f"has {ctx.get('actual_length')} items (expected exactly 3: a point [x, y, z])"
    return f"has {ctx.get('actual_length')} items (expected {_length_expectation(ctx, loc)})"


def _length_expectation(ctx: dict, loc: tuple = ()) -> str:
    lo, hi = ctx.get("min_length"), ctx.get("max_length")
    exact = _exact_length(loc)
    if exact is not None:
        return f"exactly {exact}"
    if lo is not None and lo == hi:
        return f"exactly {lo}"
    if lo is not None and hi is not None:
        return f"{lo} to {hi}"
    return f"at least {lo}" if lo is not None else f"at most {hi}"


@functools.cache
def _scene_schema() -> dict:
    return SceneModel.model_json_schema()


def _schema_nodes(nodes: list, schema: dict) -> list:
    """``nodes`` with every ``$ref`` resolved and every anyOf/oneOf/allOf spread out."""
    out = []
    for node in nodes:
        if "$ref" in node:
            node = schema["$defs"][node["$ref"].rsplit("/", 1)[-1]]
        out.append(node)
        for key in ("anyOf", "oneOf", "allOf"):
            out += _schema_nodes([n for n in node.get(key, ()) if isinstance(n, dict)], schema)
    return out


def _exact_length(loc: tuple) -> int | None:
    """The one length the list at ``loc`` must have (a point, an rpy, a limit pair), from the
    scene's schema; None when it may have several (pydantic's error names only the violated bound).

    >>> _exact_length(("goals", 0, "tool_axis")), _exact_length(("arm", "limits", 2)), _exact_length(("goals",))
    (3, 2, None)
    """
    schema = _scene_schema()
    nodes = [schema]
    for part in loc:
        nodes = _schema_nodes(nodes, schema)
        if isinstance(part, int):
            nodes = [n["items"] for n in nodes if isinstance(n.get("items"), dict)]
        else:
            nodes = [n["properties"][part] for n in nodes if part in n.get("properties", {})]
    lengths = {(n.get("minItems"), n.get("maxItems")) for n in _schema_nodes(nodes, schema) if n.get("type") == "array"}
    if len(lengths) == 1:
        lo, hi = next(iter(lengths))
        return lo if lo is not None and lo == hi else None
    return None


def _describe(value) -> str:
    if value is None:
        return "null"
    if isinstance(value, bool):
        return str(value).lower()
    if isinstance(value, str):
        return repr(value if len(value) <= 40 else value[:37] + "...")
    if isinstance(value, (list, dict)):
        return f"a {type(value).__name__}"
    if isinstance(value, int) and abs(value) >= 10**20:
        return f"a {len(str(abs(value)))}-digit integer"
    return repr(value)
