"""Fuzzing the scene loader and a short run (issue 7, item 3), trajectory.csv inputs and
``--set`` values (issue 12).

Valid scenes (``strategies.scene_texts``) and valid scenes mutated (keys dropped,
renamed, retyped; values made extreme: NaN, infinities, huge, negative, empty, strings)
go through :func:`armanim.scene.validate_scene_text`; the valid ones are then solved
for a few frames. The only allowed outcomes are a result or armanim's own SceneError
(exit 2): any other exception fails the test.

A bounded number of examples runs in CI; for a long run set ARMANIM_FUZZ_EXAMPLES,
e.g. ``ARMANIM_FUZZ_EXAMPLES=20000 python -m pytest tests/system/test_fuzz.py`` (see
docs/reliability.md).
"""

from __future__ import annotations

import copy
import math
import os
import tempfile
from pathlib import Path

import numpy as np
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from strategies import scene_texts

from armanim.errors import EXIT_BAD_INPUT, SceneError, UsageError
from armanim.motion.trajectory import solve_trajectory
from armanim.scene import scene_to_problem, validate_scene_text

EXAMPLES = int(os.environ.get("ARMANIM_FUZZ_EXAMPLES", "60"))
FUZZ = settings(
    max_examples=EXAMPLES,
    deadline=None,
    database=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much, HealthCheck.data_too_large],
)
MAX_FRAMES = 20  # frames per goal of the short runs

EXTREMES = [
    math.nan,
    math.inf,
    -math.inf,
    1e308,
    -1e308,
    1e-320,
    10**400,
    -(10**30),
    0,
    -1,
    -0.0,
    2**63,
    "",
    "abc",
    "1.5",
    "nan",
    True,
    False,
    None,
    [],
    {},
    [[]],
    [1, 2],
    {"a": 1},
    [math.nan] * 3,
    [1e308, 1e308, 1e308],
    list(range(100)),
]
NEW_KEYS = ["links", "widht", "position", "hold", "method", "max_frames_per_goal", "<<", "version", "x" * 300]


def _containers(data, path=()):
    """Every (path, container) of a plain-data tree."""
    yield path, data
    items = data.items() if isinstance(data, dict) else enumerate(data) if isinstance(data, list) else ()
    for key, value in items:
        if isinstance(value, (dict, list)):
            yield from _containers(value, (*path, key))


@st.composite
def mutated_scenes(draw) -> dict:
    """A valid scene's data with 1-3 mutations."""
    data = yaml.safe_load(draw(scene_texts()))

    def extreme():
        return copy.deepcopy(draw(st.sampled_from(EXTREMES)))  # never the shared objects of EXTREMES

    for _ in range(draw(st.integers(1, 3))):
        containers = list(_containers(data))
        _, target = containers[draw(st.integers(0, len(containers) - 1))]
        keys = list(target.keys()) if isinstance(target, dict) else list(range(len(target)))
        op = draw(st.sampled_from(["drop", "rename", "retype", "extreme", "add", "empty"]))
        if not keys or op == "add":
            if isinstance(target, dict):
                target[draw(st.sampled_from(NEW_KEYS))] = extreme()
            else:
                target.append(extreme())
            continue
        key = draw(st.sampled_from(keys))
        if op == "drop":
            del target[key]
        elif op == "rename" and isinstance(target, dict):
            target[draw(st.sampled_from(NEW_KEYS)) + draw(st.sampled_from(["", "s", "_"]))] = target.pop(key)
        elif op == "retype":
            value = target[key]
            target[key] = copy.deepcopy(
                draw(
                    st.sampled_from(
                        [
                            str(value),
                            [value],
                            {"value": value},
                            None,
                            bool(value) if not isinstance(value, (list, dict)) else 1,
                        ]
                    )
                )
            )
        elif op == "empty":
            target[key] = copy.deepcopy(draw(st.sampled_from([[], {}, "", None])))
        else:
            target[key] = extreme()
    return data


def clamp_frames(data) -> None:
    """Keep the runs short: at most MAX_FRAMES frames per goal (extreme values are kept)."""
    solver = data.get("solver") if isinstance(data, dict) else None
    if isinstance(solver, dict):
        value = solver.get("max_frames_per_goal")
        if isinstance(value, int) and not isinstance(value, bool) and MAX_FRAMES < value <= 100_000:
            solver["max_frames_per_goal"] = MAX_FRAMES


def check_outcome(text: str) -> None:
    """A model and a short, finite run, or a SceneError that names the file: nothing else."""
    try:
        model = validate_scene_text(text, "fuzz.yaml")
    except SceneError as exc:
        assert exc.exit_code == EXIT_BAD_INPUT
        assert exc.problems and exc.report().startswith("fuzz.yaml"), exc.report()
        return
    problem = scene_to_problem(model)
    solution = solve_trajectory(problem)
    traj = solution.trajectory
    assert traj.frames >= 1
    assert np.all(np.isfinite(traj.phi)) and np.all(np.isfinite(traj.tip)) and np.all(np.isfinite(traj.distance))
    assert len(solution.goals) == len(problem.goals)


@FUZZ
@given(scene_texts())
def test_valid_scenes_load_and_run(text):
    check_outcome(text)


@FUZZ
@given(mutated_scenes())
def test_mutated_scenes_give_a_result_or_a_scene_error(data):
    clamp_frames(data)
    text = yaml.safe_dump(data, sort_keys=False, allow_unicode=True)
    check_outcome(text)


@FUZZ
@given(st.text(max_size=300))
def test_arbitrary_text_gives_a_scene_error(text):
    check_outcome(text)


# ------------------------------------------------------------------ trajectory.csv inputs (issue 12)

GOLDEN_ROWS = (Path(__file__).parents[1] / "golden" / "notes-arm.csv").read_text().splitlines()[:12]
CSV_FIELDS = [
    "",
    "nan",
    "NaN",
    "inf",
    "-inf",
    "1e308",
    "-1e308",
    "1e-400",
    "abc",
    "0x10",
    "1_000",
    " 1",
    "-0.0",
    "9" * 400,
    "\x00",
    '"quoted, comma"',
    '"open quote',
    "ik",
    "plan",
    "\r",
    "1e9",
    "1e10",
]
COLUMN_NAMES = ["x", "reached", "phiX_deg", "phi9_deg", "mode", "iterations", "", "frame", "goal"]


@st.composite
def mutated_csv_texts(draw) -> str:
    """The start of a golden trajectory.csv with 1-4 mutations: fields made extreme, columns
    dropped, renamed or repeated, rows cut short or doubled, the text truncated."""
    rows = [line.split(",") for line in GOLDEN_ROWS]
    for _ in range(draw(st.integers(1, 4))):
        op = draw(
            st.sampled_from(
                ["field", "field", "drop column", "rename column", "add column", "short row", "double row", "no rows"]
            )
        )
        r = draw(st.integers(0, len(rows) - 1))
        c = draw(st.integers(0, len(rows[0]) - 1))
        if op == "field" and r > 0 and c < len(rows[r]):
            rows[r][c] = draw(st.sampled_from(CSV_FIELDS))
        elif op == "drop column":
            rows = [row[:c] + row[c + 1 :] for row in rows]
        elif op == "rename column":
            rows[0][c] = draw(st.sampled_from(COLUMN_NAMES))
        elif op == "add column":
            rows = [
                row + ([draw(st.sampled_from(COLUMN_NAMES))] if i == 0 else [draw(st.sampled_from(CSV_FIELDS))])
                for i, row in enumerate(rows)
            ]
        elif op == "short row" and r > 0:
            rows[r] = rows[r][:c]
        elif op == "double row":
            rows.insert(r, list(rows[r]))
        elif op == "no rows":
            rows = rows[:1]
    text = "\n".join(",".join(row) for row in rows) + "\n"
    return text[: draw(st.integers(0, len(text)))] if draw(st.booleans()) else text


def check_csv_outcome(text: str) -> None:
    """A table (drawable or with a named problem, equal to itself by file and by table) or a SceneError."""
    from armanim.output.compare import compare_csv_files, compare_trajectories
    from armanim.output.csvfile import EMPTY_ALLOWED, TEXT_COLUMNS, parse_trajectory_csv
    from armanim.runs.reload import drawable_problem

    try:
        table = parse_trajectory_csv(text, "fuzz.csv")
    except SceneError as exc:
        assert exc.exit_code == EXIT_BAD_INPUT and exc.report().startswith("fuzz.csv"), exc.report()
        return
    problem = drawable_problem(table, goals=3)
    if problem is None:
        numbers = table.data[:, [i for i, c in enumerate(table.columns) if c not in (*EMPTY_ALLOWED, *TEXT_COLUMNS)]]
        assert np.all(np.isfinite(numbers))
    else:
        assert problem.message and problem.line is not None
    assert compare_trajectories(table, table).equal
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "t.csv"
        path.write_text(text)
        assert compare_csv_files(path, path).equal


@FUZZ
@given(mutated_csv_texts())
def test_mutated_trajectory_csvs_give_a_table_or_a_scene_error(text):
    check_csv_outcome(text)


@FUZZ
@given(st.text(max_size=300).map(lambda t: "frame,time_s,goal,phi1_deg,x,y,z,goal_distance,clearance,reached\n" + t))
def test_arbitrary_rows_give_a_table_or_a_scene_error(text):
    check_csv_outcome(text)


# ------------------------------------------------------------------ --set values (issue 12)

SET_PATHS = ["solver.step", "solver.method", "goals[0].hold", "arm.links", "render.fps", "name", "arm.links[1]"]
SET_VALUES = st.one_of(
    st.text(max_size=60),
    st.sampled_from(
        [
            "1e400",
            "9" * 500,
            "[&a [1,1], *a]",
            "&a [1, *a]",
            "!!python/object:os.system",
            "{a: 1}",
            "[1,2",
            "..",
            "~",
            "0.0001",
            "-1",
            "nan",
            ".inf",
            "1e-300",
            "[[[[[[1]]]]]]",
        ]
    ),
)


@FUZZ
@given(st.sampled_from(SET_PATHS), st.lists(SET_VALUES, min_size=1, max_size=3))
def test_set_values_give_variants_or_a_usage_error(path, values):
    from armanim.runs.sweep import parse_setting, variants

    try:
        setting = parse_setting(f"{path}={','.join(values)}")
    except UsageError as exc:
        assert exc.exit_code == EXIT_BAD_INPUT and str(exc).startswith("--set")
        return
    try:
        items = variants(Path(__file__).parents[2] / "scenes" / "notes-arm.yaml", [setting])
    except UsageError as exc:
        assert str(exc).startswith("--set")
        return
    for item in items:
        assert (item.task is None) != (item.rejected is None)
        if item.rejected is not None:
            assert item.rejected.status == "invalid" and item.rejected.message
