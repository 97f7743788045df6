"""Fuzzing the scene loader and a short run (issue 7, item 3).

Valid scenes (``strategies.scene_texts``) and valid scenes mutated (keys dropped,
renamed, retyped; values made extreme: NaN, infinities, huge, negative, empty, strings)
go through :func:`armanim.scene.validate_scene_text`; the valid ones are then solved
for a few frames. The only allowed outcomes are a result or armanim's own SceneError
(exit 2): any other exception fails the test.

A bounded number of examples runs in CI; for a long run set ARMANIM_FUZZ_EXAMPLES,
e.g. ``ARMANIM_FUZZ_EXAMPLES=20000 python -m pytest tests/test_fuzz.py`` (see
docs/reliability.md).
"""

from __future__ import annotations

import copy
import math
import os

import numpy as np
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from strategies import scene_texts

from armanim.errors import EXIT_BAD_INPUT, SceneError
from armanim.scene import scene_to_problem, validate_scene_text
from armanim.trajectory import solve_trajectory

EXAMPLES = int(os.environ.get("ARMANIM_FUZZ_EXAMPLES", "60"))
FUZZ = settings(max_examples=EXAMPLES, deadline=None, database=None,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much, HealthCheck.data_too_large])
MAX_FRAMES = 20  # frames per goal of the short runs

EXTREMES = [
    math.nan, math.inf, -math.inf, 1e308, -1e308, 1e-320, 10**400, -(10**30), 0, -1, -0.0, 2**63,
    "", "abc", "1.5", "nan", True, False, None, [], {}, [[]], [1, 2], {"a": 1}, [math.nan] * 3,
    [1e308, 1e308, 1e308], list(range(100)),
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
            target[key] = copy.deepcopy(draw(st.sampled_from([str(value), [value], {"value": value}, None, bool(value) if not isinstance(value, (list, dict)) else 1])))
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
