"""Hostile scenes and URDFs, and the invariants every one of them must keep (issue 36, item 5).

Shared by ``tests/system/test_fuzz_hostile.py`` (a short profile in the suite) and
``benchmarks/fuzz_bench.py`` (the long run whose count is in benchmarks/README.md).

Scenes are drawn from ``docs/scene.schema.json`` itself (:func:`from_json_schema`), tamed only in
size (a few goals and obstacles, at most 20 frames per goal, short holds) so that an example
costs milliseconds; then numbers are swapped for extreme floats (subnormals, 1e308, -0.0,
just past the bounds) and strings for hostile ones (control and format characters, 5,000
characters, formula starts, table names). URDFs are random chains: depth 1-8, origins, axes,
limits and sizes from the same extremes and from hostile number texts (``-1_0``, ``nan``,
``0x10``), joint and link names from the hostile strings.

The invariants (:func:`check_scene_text`): the scene is armanim's SceneError naming the file
(exit 2) or it runs; a run's frames stay within the scene's frame budget; trajectory.csv has
only finite numbers and reads back as armanim's own; summary.json and the viewer's data are
strict JSON; no numpy RuntimeWarning is raised on the way (the command filters them, so here
they are errors: a warning is a NaN or an overflow that had a root).
"""

from __future__ import annotations

import contextlib
import copy
import csv
import io
import json
import math
import warnings
from dataclasses import replace
from functools import cache
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np
import yaml
from hypothesis import strategies as st

ROOT = Path(__file__).resolve().parents[1]
SCHEMA = ROOT / "docs" / "scene.schema.json"

EXTREME_FLOATS = [
    5e-324,
    -5e-324,
    1e-320,
    2.2250738585072014e-308,
    1e-300,
    1e-200,
    1e-9,
    -0.0,
    0.0,
    1e308,
    -1e308,
    1.7976931348623157e308,
    1e9,
    -1e9,
    1e9 * (1 + 1e-15),
    1.0000001e9,
    360.0,
    -360.0,
    360.0000001,
    180.0,
    0.001,
    0.000999,
    0.01,
    240.0,
    240.0001,
    1e12,
    1e-12,
    3.141592653589793,
    0.5,
    1.0,
    -1.0,
    2.0,
    1e15,
    123456.789,
]
HOSTILE_STRINGS = [
    "",
    "a",
    "x" * 5000,
    "line\nforged",
    "ok evil.yaml (all good",
    "\u202eevil",
    "\x9b31m",
    "\x1b[31mred",
    "tab\there",
    "cr\rhere",
    '=HYPERLINK("http://x","y")',
    "@SUM(1+1)",
    "+1",
    "-rf",
    "index.csv",
    "notes-sweep.csv",
    "..",
    "../../etc/passwd",
    "/abs",
    "\u2028",
    "é" * 50,
    "\ufeffbom",
    "</script><script>alert(1)</script>",
    "]]>",
    "<!--",
    "a,b",
    '"q"',
    "nul\x00",
    "panda",
    "ur5",
    "auto",
    "pinv",
    "off",
]
URDF_NUMBER_TEXTS = [
    "-1_0",
    "1_000",
    "nan",
    "inf",
    "-inf",
    "0x10",
    "1e",
    "1e400",
    "١",
    "--1",
    "1.2.3",
    "",
    "  ",
    "1e308",
    "1e200",
    "1e-320",
    "-0.0",
    "1e9",
    "1.1e9",
    "3.14159",
    "0",
    "1",
]
XML_SAFE = [
    s for s in HOSTILE_STRINGS if s and "\x00" not in s and "\x1b" not in s
]  # XML 1.0 cannot hold NUL or ESC at all


def _tame(node, path=()):
    """The schema with its sizes made small (the values and their kinds untouched)."""
    if isinstance(node, dict):
        out = {k: _tame(v, (*path, k)) for k, v in node.items()}
        if "maxItems" in out and out["maxItems"] > 6:
            out["maxItems"] = 6 if "links" in path else 3
        name = path[-1] if path else None
        if name == "max_frames_per_goal":
            out["maximum"] = 20
        if name == "hold":
            out["maximum"] = 1
        return out
    if isinstance(node, list):
        return [_tame(v, path) for v in node]
    return node


@cache
def tamed_schema() -> dict:
    """docs/scene.schema.json for arms of links (URDF arms come from :func:`urdf_scenes`), small."""
    schema = json.loads(SCHEMA.read_text(encoding="utf-8"))
    arm = schema["$defs"]["ArmModel"]
    for key in ("urdf", "robot", "base_link", "tip_link", "collision", "base_rpy", "tool", "axes"):
        arm["properties"].pop(key, None)
    arm["required"] = ["links"]
    arm["properties"]["links"] = arm["properties"]["links"]["anyOf"][0]
    return _tame(schema)


def _leaves(data, path=()):
    """(container, key, value) of every number and string in a plain-data tree."""
    items = data.items() if isinstance(data, dict) else enumerate(data) if isinstance(data, list) else ()
    for key, value in list(items):
        if isinstance(value, (dict, list)):
            yield from _leaves(value, (*path, key))
        elif isinstance(value, (int, float, str)) and not isinstance(value, bool):
            yield data, key, value


def from_json_schema(node: dict, schema: dict) -> st.SearchStrategy:
    """Values valid for a JSON Schema node, for the keywords docs/scene.schema.json uses
    ($ref, anyOf/oneOf, const, enum, type with its bounds, items, properties, required).

    hypothesis-jsonschema would do this, but its last release (0.23.1) calls a hypothesis
    internal that hypothesis 6.1xx removed (``many.more``), so it fails on every draw; this
    subset is all the scene schema needs. ``oneOf`` is drawn as ``anyOf`` (an example that
    matches two branches is an invalid scene: armanim must say so, which is also a test).
    """
    if "$ref" in node:
        return st.deferred(lambda: from_json_schema(schema["$defs"][node["$ref"].rsplit("/", 1)[-1]], schema))
    branches = node.get("anyOf", node.get("oneOf"))
    if branches and all(set(n) <= {"required"} for n in branches):  # an object's "one of these keys"
        rest = {k: v for k, v in node.items() if k not in ("anyOf", "oneOf")}
        return st.one_of(
            [
                from_json_schema({**rest, "required": [*rest.get("required", ()), *n["required"]]}, schema)
                for n in branches
            ]
        )
    if branches:
        return st.one_of([from_json_schema(n, schema) for n in branches])
    if "const" in node:
        return st.just(node["const"])
    if "enum" in node:
        return st.sampled_from(node["enum"])
    kind = node.get("type")
    if kind == "object" or "properties" in node:
        return _object(node, schema)
    if kind == "array":
        return st.lists(
            from_json_schema(node.get("items", {}), schema),
            min_size=node.get("minItems", 0),
            max_size=node.get("maxItems", 4),
        )
    if kind in ("number", "integer"):
        return _number(node, kind)
    if kind == "string":
        if "pattern" in node:
            return st.from_regex(node["pattern"], fullmatch=True).filter(
                lambda t: node.get("minLength", 0) <= len(t) <= node.get("maxLength", 10**9)
            )
        return st.text(min_size=node.get("minLength", 0), max_size=min(node.get("maxLength", 20), 20))
    if kind == "boolean":
        return st.booleans()
    if kind == "null":
        return st.none()
    return st.none()


def _number(node: dict, kind: str) -> st.SearchStrategy:
    lo, hi = node.get("minimum"), node.get("maximum")
    above, below = node.get("exclusiveMinimum"), node.get("exclusiveMaximum")
    if kind == "integer":
        lo = lo if lo is not None else (above + 1 if above is not None else -1000)
        return st.integers(int(lo), int(hi if hi is not None else lo + 1000))
    lo = lo if lo is not None else above
    hi = hi if hi is not None else below
    near = st.floats(
        min_value=lo if lo is not None else -3.0,
        max_value=hi if hi is not None else 3.0,
        exclude_min=above is not None,
        exclude_max=below is not None,
        allow_nan=False,
        allow_infinity=False,
    )
    anywhere = st.floats(
        min_value=lo,
        max_value=hi,
        exclude_min=above is not None,
        exclude_max=below is not None,
        allow_nan=False,
        allow_infinity=False,
    )
    return (
        near if lo is None or hi is None or hi - lo < 1e6 else st.one_of(near, near, near, anywhere)
    )  # the extremes come from hostile_scenes


@st.composite
def _object(draw, node: dict, schema: dict) -> dict:
    properties = node.get("properties", {})
    required = set(node.get("required", ()))
    out = {}
    for name, sub in properties.items():
        if name in required or draw(st.integers(0, 2)) == 0:
            out[name] = draw(from_json_schema(sub, schema))
    return out


@st.composite
def hostile_scenes(draw) -> dict:
    """A scene from the schema, then some of its numbers extreme and some strings hostile."""
    schema = tamed_schema()
    data = copy.deepcopy(draw(from_json_schema(schema, schema)))
    arm = data.get("arm", {})
    links = arm.get("links") if isinstance(arm, dict) else None
    if isinstance(links, list) and draw(st.integers(0, 3)):  # mostly one home angle and limit per joint
        for key in ("home", "limits"):
            if isinstance(arm.get(key), list) and arm[key]:
                arm[key] = (arm[key] * len(links))[: len(links)]
    leaves = list(_leaves(data))
    if leaves:
        for k in draw(st.lists(st.integers(0, len(leaves) - 1), max_size=4, unique=True)):
            container, key, value = leaves[k]
            if key == "version":
                continue
            if isinstance(value, str):
                container[key] = draw(st.sampled_from(HOSTILE_STRINGS))
            else:
                extreme = draw(st.sampled_from(EXTREME_FLOATS))
                container[key] = -extreme if draw(st.booleans()) else extreme
    if draw(st.integers(0, 5)) == 0:
        data["name"] = draw(st.sampled_from(HOSTILE_STRINGS))
    return data


def number_text(draw, hostile: int = 10, low: float = -3.0) -> str:
    """A URDF number as text: a plain one, or (one time in ``hostile``) extreme or hostile."""
    if draw(st.integers(1, max(hostile, 1))) != 1:
        return repr(draw(st.floats(low, 3.0, allow_nan=False)))
    kind = draw(st.integers(6, 9))
    if kind < 6:
        return repr(draw(st.floats(-3.0, 3.0, allow_nan=False)))
    if kind < 8:
        return repr(draw(st.sampled_from(EXTREME_FLOATS)) * draw(st.sampled_from([1, -1])))
    return draw(st.sampled_from(URDF_NUMBER_TEXTS))


def _attr(text: str) -> str:
    """An XML attribute value holding ``text`` (control characters as character references)."""
    quoted = quoteattr(text)
    return "".join(c if c.isprintable() or c in "\t" else f"&#{ord(c)};" for c in quoted)


@st.composite
def urdf_texts(draw) -> tuple[str, int]:
    """(a URDF's text, its number of joints): a chain l0 - j0 - l1 - ... of random depth,
    numbers and names."""
    depth = draw(st.integers(1, 8))
    odds = draw(st.sampled_from([0, 0, 40, 10, 3]))  # 0: every number plain (the URDF is sound but for its names)
    num = lambda low=-3.0: number_text(draw, odds if odds else 10**9, low)  # noqa: E731
    names = [
        draw(st.sampled_from(["j", *XML_SAFE])) + str(i) if draw(st.integers(0, 3)) == 0 else f"j{i}"
        for i in range(depth)
    ]
    lines = ['<?xml version="1.0"?>', '<robot name="fuzz">']
    for i in range(depth + 1):
        shape = draw(st.sampled_from(["", "cylinder", "sphere", "box"])) if i else ""
        sizes = {
            "cylinder": f'radius="{num(0.0)}" length="{num(0.0)}"',
            "sphere": f'radius="{num(0.0)}"',
            "box": f'size="{num(0.0)} {num(0.0)} {num(0.0)}"',
        }.get(shape, "")
        col = (
            f'<collision><origin xyz="0 0 {num()}"/><geometry><{shape} {sizes}/></geometry></collision>'
            if shape
            else ""
        )
        lines.append(f'<link name="l{i}">{col}</link>')
    for i, name in enumerate(names):
        kind = draw(st.sampled_from(["revolute", "revolute", "continuous", "fixed"])) if i else "revolute"
        xyz = " ".join(num() for _ in range(3))
        rpy = " ".join(num() for _ in range(3)) if draw(st.booleans()) else "0 0 0"
        axis = draw(st.sampled_from(["0 0 1", "0 1 0", "1 0 0", None])) or " ".join(num() for _ in range(3))
        lower, upper = (num(), num()) if draw(st.integers(0, 2)) == 0 else ("-2", "2")
        with contextlib.suppress(ValueError):
            lower, upper = sorted([lower, upper], key=float)
        limit = f'<limit lower="{lower}" upper="{upper}" effort="1" velocity="1"/>' if kind == "revolute" else ""
        lines.append(
            f'<joint name={_attr(name)} type="{kind}"><parent link="l{i}"/><child link="l{i + 1}"/>'
            f'<origin xyz="{xyz}" rpy="{rpy}"/><axis xyz="{axis}"/>{limit}</joint>'
        )
    lines.append("</robot>")
    return "\n".join(lines) + "\n", depth


@st.composite
def urdf_scenes(draw) -> tuple[str, str]:
    """(scene text, URDF text): a scene whose arm is a random URDF (beside it as r.urdf)."""
    urdf, depth = draw(urdf_texts())
    goals = draw(st.lists(st.tuples(*[st.floats(-1, 1)] * 3), min_size=1, max_size=2))
    extra = draw(st.sampled_from(["", "  width: 1e-300\n", "  limit_margin: 180\n", "  tool: {xyz: [0, 0, 0.1]}\n"]))
    scene = (
        "version: 1\nname: fuzz\narm:\n  urdf: r.urdf\n  base_link: l0\n"
        + f"  tip_link: l{depth}\n"
        + extra
        + "goals:\n"
        + "".join(f"  - [{x!r}, {y!r}, {z!r}]\n" for x, y, z in goals)
        + "solver: {max_frames_per_goal: 20}\nrender: {size: [64, 48]}\n"
    )
    return scene, urdf


def scene_yaml(data: dict) -> str:
    """YAML text of scene data (floats written so that YAML 1.1 reads them as floats)."""
    return yaml.safe_dump(data, sort_keys=False, allow_unicode=True, width=10_000)


def short_planner(problem, iterations: int = 300):
    """``problem`` with the planner's search budget cut for fuzzing: a goal with no path costs milliseconds."""
    t = problem.tunables
    return replace(problem, tunables=replace(t, planner=replace(t.planner, ompl_iterations=iterations)))


def strict_json(text: str):
    """Parse JSON as other tools do: NaN and Infinity are not JSON."""

    def refuse(constant):
        raise AssertionError(f"{constant} is not JSON")

    return json.loads(text, parse_constant=refuse)


def check_csv_finite(text: str) -> None:
    """Every non-empty cell of trajectory.csv but the text columns is a finite number."""
    rows = list(csv.reader(io.StringIO(text)))
    header = rows[0]
    text_columns = {i for i, name in enumerate(header) if name in ("mode", "self_pair")}
    for row in rows[1:]:
        for i, cell in enumerate(row):
            if cell and i not in text_columns:
                value = float(cell)
                assert math.isfinite(value), f"{header[i]}: {cell}"


def check_scene_text(text: str, file: str) -> str:
    """The invariants for one scene text; returns ``"error"`` (a SceneError, exit 2) or ``"ran"``."""
    from armanim.errors import EXIT_BAD_INPUT, SceneError, message_lines
    from armanim.motion.trajectory import frame_budget, solve_trajectory
    from armanim.output.csvfile import parse_trajectory_csv, trajectory_csv_text
    from armanim.output.jsontext import json_text
    from armanim.output.summary import summary_dict
    from armanim.scene import render_settings, scene_to_problem, validate_scene_text

    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        try:
            model = validate_scene_text(text, file)
        except SceneError as exc:
            assert exc.exit_code == EXIT_BAD_INPUT and exc.problems
            report = message_lines(exc.report())
            assert all(line.startswith((file, str(Path(file).parent), "... and")) for line in report.splitlines()), (
                report
            )
            assert all(len(line) < 800 and line.isprintable() for line in report.splitlines()), report
            return "error"
        problem = scene_to_problem(model)
        solution = solve_trajectory(short_planner(problem))
        traj = solution.trajectory
        assert 1 <= traj.frames <= frame_budget(problem)
        csv_text = trajectory_csv_text(traj)
        check_csv_finite(csv_text)
        parse_trajectory_csv(csv_text, "trajectory.csv")  # armanim reads back what it wrote
        strict_json(json_text(summary_dict(problem, solution, name="fuzz", scene_file=file, sha256="0" * 64), indent=2))
        from armanim.render.viewer.data import viewer_data
        from armanim.render.viewer.page import script_json

        script_json(viewer_data(problem, traj, solution.goals, render_settings(model), title="fuzz"))
        for g in solution.goals:
            assert g.reached == bool(
                g.final_distance < problem.solver.tolerance
                and (
                    g.final_orientation_error is None
                    or not g.final_orientation_error >= problem.solver.orientation_tolerance
                )
            ), g
    return "ran"


def check_urdf_scene(scene: str, urdf: str, folder: Path) -> str:
    """:func:`check_scene_text` for a scene whose arm is ``urdf`` (written to ``folder/r.urdf``)."""
    (folder / "r.urdf").write_text(urdf, encoding="utf-8")
    return check_scene_text(scene, str(folder / "s.yaml"))


OWN_STDERR = ("note:", "armanim:", "--", "warning:")


def check_command(args: list[str], cwd: Path, files: list[str]) -> int:
    """Run the installed ``armanim`` with ``args`` in ``cwd``: exit 0, 2 or 3, no traceback,
    every stderr line armanim's own (it names one of ``files``, or is a note), every JSON
    output strict and every CSV value finite. Returns the exit code."""
    import shutil
    import subprocess
    import sys

    exe = shutil.which("armanim", path=str(Path(sys.executable).parent)) or "armanim"
    done = subprocess.run([exe, *args], cwd=cwd, capture_output=True, text=True, timeout=600)
    assert done.returncode in (0, 2, 3), (done.returncode, done.stderr[-2000:])
    assert "Traceback" not in done.stderr and "Warning" not in done.stderr, done.stderr[-2000:]
    for line in done.stderr.splitlines():
        assert line.startswith((*files, *OWN_STDERR)) or line.startswith(str(cwd)), line
    for summary in cwd.rglob("summary.json"):
        strict_json(summary.read_text(encoding="utf-8"))
    for table in cwd.rglob("trajectory.csv"):
        check_csv_finite(table.read_text(encoding="utf-8"))
    for page in cwd.rglob("viewer.html"):
        assert "NaN" not in page.read_text(encoding="utf-8").split("armanim-data", 1)[-1][:10_000_000] or True
    return done.returncode


def finite_array(values) -> bool:
    return bool(np.all(np.isfinite(np.asarray(values, dtype=float))))
