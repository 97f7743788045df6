"""Scene loading: every rejection class with its field path, line and exit 2; valid scenes."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from conftest import BUNDLED, DOCS
from hypothesis import given, settings
from strategies import scene_texts

from armanim.errors import SceneError
from armanim.scene import load_scene, scene_to_problem

BASE = """\
version: 1
arm:
  base: [0, 0, 0]
  links: [2, 3, 3]
  axes: [z, y, y]
  home: [0, 10, 20]
  limits: [null, [-90, 90], [-120, 120]]
obstacles:
  - center: [5, 5, 5]
    radius: 1
goals:
  - [3, 2, 4]
solver:
  method: pinv
render:
  fps: 30
  size: [320, 240]
"""
# line numbers of BASE
L = {
    "version": 1,
    "arm": 2,
    "base": 3,
    "links": 4,
    "axes": 5,
    "home": 6,
    "limits": 7,
    "center": 9,
    "radius": 10,
    "goals": 11,
    "goal0": 12,
    "method": 14,
    "fps": 16,
    "size": 17,
}


def edit(line: int, new: str, text: str = BASE) -> str:
    lines = text.splitlines()
    lines[line - 1] = new
    return "\n".join(lines) + "\n"


def write(tmp_path: Path, content: str | bytes, name: str = "scene.yaml") -> Path:
    path = tmp_path / name
    if isinstance(content, bytes):
        path.write_bytes(content)
    else:
        path.write_text(content, encoding="utf-8")
    return path


def rejected(tmp_path, cli, content, field: str, line: int | None, *fragments: str) -> str:
    """The scene is rejected by load_scene and by `armanim validate` (exit 2) with
    ``FILE:LINE: field: message`` naming the field and line."""
    path = write(tmp_path, content)
    with pytest.raises(SceneError) as info:
        load_scene(path)
    matching = [p for p in info.value.problems if p.path == field]
    assert matching, f"no problem at {field!r}: {info.value.report()}"
    if line is not None:
        assert any(p.line == line for p in matching), info.value.report()
    result = cli("validate", path)
    assert result.exit_code == 2, result.output
    where = f"{path}:{line}: " if line is not None else f"{path}"
    prefix = f"{where}{field}: " if field else where
    text = result.stderr
    assert prefix in text, text
    for fragment in fragments:
        assert fragment in text, (fragment, text)
    assert "Traceback" not in result.output
    assert f"ok {path}" not in result.stdout
    return text


def test_base_scene_is_valid(tmp_path):
    scene = load_scene(write(tmp_path, BASE))
    assert scene.name == "scene"
    problem = scene_to_problem(scene.model)
    np.testing.assert_allclose(problem.home, np.radians([0, 10, 20]))
    np.testing.assert_allclose(problem.limits.lower[1:], np.radians([-90, -120]))
    assert np.isinf(problem.limits.lower[0])


# ------------------------------------------------------------ file-level problems


def test_empty_file(tmp_path, cli):
    rejected(tmp_path, cli, "", "", 1, "empty")


def test_comment_only_file_is_empty(tmp_path, cli):
    rejected(tmp_path, cli, "# nothing here\n", "", 1, "empty")


def test_binary_file(tmp_path, cli):
    rejected(tmp_path, cli, b"version: 1\n\x00\x01\x02binary", "", 2, "binary")


def test_non_utf8_bytes(tmp_path, cli):
    rejected(tmp_path, cli, b"version: 1\nname: caf\xe9\n", "", 2, "not UTF-8", "0xe9")


@pytest.mark.parametrize("content, kind", [("- 1\n- 2\n", "list"), ("42\n", "int"), ("just a string\n", "str")])
def test_non_mapping_root(tmp_path, cli, content, kind):
    rejected(tmp_path, cli, content, "", 1, f"top level is a {kind}", "expected a mapping")


def test_broken_yaml(tmp_path, cli):
    rejected(tmp_path, cli, edit(L["links"], "  links: [2, 3, 3"), "", None, "not valid YAML")
    path = tmp_path / "scene.yaml"
    with pytest.raises(SceneError) as info:
        load_scene(path)
    assert info.value.problems[0].line is not None and info.value.problems[0].line >= L["links"]


def test_python_tag_is_rejected_and_never_executed(tmp_path, cli):
    marker = tmp_path / "pwned"
    content = BASE + f'name: !!python/object/apply:os.system ["touch {marker}"]\n'
    rejected(tmp_path, cli, content, "name", 18, "unsupported YAML tag", "python/object/apply:os.system")
    assert not marker.exists()


def test_duplicate_keys_name_both_lines(tmp_path, cli):
    content = BASE.replace("  method: pinv\n", "  method: pinv\n  method: dls\n")
    text = rejected(tmp_path, cli, content, "solver.method", 15, "duplicate key 'method'", "line 14", "line 15")
    assert "first on line 14" in text


def test_unknown_key_with_did_you_mean(tmp_path, cli):
    content = edit(L["axes"], "  axes: [z, y, y]\n  widht: 0.4")
    rejected(tmp_path, cli, content, "arm.widht", 6, "unknown key 'widht'", "did you mean 'width'?")


def test_unknown_top_level_key(tmp_path, cli):
    rejected(tmp_path, cli, BASE + "goal: [1, 2, 3]\n", "goal", 18, "unknown key 'goal'", "did you mean 'goals'?")


@pytest.mark.parametrize(
    "line, new, field, fragment",
    [
        (L["links"], "  links: [2, three, 3]", "arm.links[1]", "must be a number"),
        (L["links"], "  links: 5", "arm.links", "must be a list"),
        (L["method"], "  method: simplex", "solver.method", "'simplex' is not allowed"),
        (L["fps"], "  fps: fast", "render.fps", "must be a number"),
        (L["size"], "  size: [320.5, 240]", "render.size[0]", "(got 320.5)"),
        (L["axes"], "  axes: [z, w, y]", "arm.axes[1]", "'w' is not allowed"),
    ],
)
def test_wrong_types(tmp_path, cli, line, new, field, fragment):
    rejected(tmp_path, cli, edit(line, new), field, line, fragment)


def test_section_of_wrong_type(tmp_path, cli):
    rejected(tmp_path, cli, "version: 1\narm: 3\ngoals:\n  - [1, 2, 3]\n", "arm", 2, "must be a mapping")


@pytest.mark.parametrize(
    "line, new, field",
    [
        (L["base"], "  base: [0, .nan, 0]", "arm.base[1]"),
        (L["base"], "  base: [.inf, 0, 0]", "arm.base[0]"),
        (L["radius"], "    radius: .inf", "obstacles[0].radius"),
        (L["links"], "  links: [2, .nan, 3]", "arm.links[1]"),
        (L["home"], "  home: [0, -.inf, 20]", "arm.home[1]"),
    ],
)
def test_nan_and_inf(tmp_path, cli, line, new, field):
    rejected(tmp_path, cli, edit(line, new), field, line, "finite")


@pytest.mark.parametrize(
    "line, new, field, fragment",
    [
        (L["links"], "  links: [2, 0, 3]", "arm.links[1]", "must be > 0 (got 0)"),
        (L["links"], "  links: [2, -3, 3]", "arm.links[1]", "must be > 0 (got -3)"),
        (L["radius"], "    radius: -1", "obstacles[0].radius", "must be >= 0 (got -1)"),
        (L["axes"], "  axes: [z, y, y]\n  width: 0", "arm.width", "must be > 0"),
    ],
)
def test_non_positive_lengths_and_radii(tmp_path, cli, line, new, field, fragment):
    expected_line = line + 1 if "width" in new else line
    rejected(tmp_path, cli, edit(line, new), field, expected_line, fragment)


@pytest.mark.parametrize("pair", ["[90, -90]", "[30, 30]"])
def test_limits_min_not_below_max(tmp_path, cli, pair):
    content = edit(L["limits"], f"  limits: [null, {pair}, [-120, 120]]")
    text = rejected(tmp_path, cli, content, "arm.limits[1]", L["limits"], "min must be below max")
    assert "arm.home" not in text  # no follow-on complaint about the home pose


def test_home_outside_limits(tmp_path, cli):
    content = edit(L["home"], "  home: [0, 95, 20]")
    rejected(tmp_path, cli, content, "arm.home[1]", L["home"], "95 deg is outside joint 2's limits", "[-90, 90]")


def test_home_beyond_a_limit_is_outside(tmp_path, cli):
    rejected(tmp_path, cli, edit(L["home"], "  home: [0, 90.5, 20]"), "arm.home[1]", L["home"], "the ends included")


def test_home_on_a_limit_is_taken(tmp_path, cli):
    # limits are closed for what the user gives (MoveIt's bounds are): a start may rest on one
    path = tmp_path / "on-limit.yaml"
    path.write_text(edit(L["home"], "  home: [0, 90, 20]"))
    result = cli("validate", path)
    assert result.exit_code == 0, result.output


def test_default_home_outside_the_limits_is_rejected(tmp_path, cli):
    # home left out means all zeros; limits that exclude 0 need a home (the run used to start outside them)
    content = edit(L["limits"], "  limits: [null, [10, 90], [-120, 120]]").replace("  home: [0, 10, 20]\n", "")
    rejected(
        tmp_path,
        cli,
        content,
        "arm.home",
        L["arm"],
        "not given",
        "joint 2 starts at 0 deg",
        "arm.limits[1] = [10, 90]",
        "give arm.home",
    )


def test_home_closer_than_the_clearance_is_rejected(tmp_path, cli):
    # the home pose's links pass about 1.3 from the surface of a sphere at (0, 0, 9) (out of
    # the arm's plane): clear at the default clearance, too close for a clearance of 3
    content = BASE.replace("  method: pinv\n", "  method: pinv\n  clearance: 3\n")
    content = edit(L["center"], "  - center: [0, 0, 9]", content)
    rejected(
        tmp_path,
        cli,
        content,
        "obstacles[0]",
        L["center"],
        "closer to it than solver.clearance",
        "lower solver.clearance",
    )


def test_goal_closer_than_the_clearance_is_rejected(tmp_path, cli):
    # 0.3 from the sphere's surface: the last link (radius 0.25) plus clearance 0.05 would touch it
    content = edit(L["goal0"], "  - [5, 5, 6.29]")
    rejected(
        tmp_path,
        cli,
        content,
        "goals[0]",
        L["goal0"],
        "from the surface of obstacles[0]",
        "arm.width / 2 + solver.clearance = 0.3",
    )


def test_goal_with_two_coordinates_needs_exactly_three(tmp_path, cli):
    rejected(
        tmp_path, cli, edit(L["goal0"], "  - [6, 15]"), "goals[0].position", L["goal0"], "has 2 items", "exactly 3"
    )


def test_goals_written_as_one_flat_list_get_a_hint(tmp_path, cli):
    content = BASE.replace("goals:\n  - [3, 2, 4]\n", "goals: [3, 2, 4]\n")
    rejected(tmp_path, cli, content, "goals[0]", L["goals"], "must be a point [x, y, z]", "goals: [[x, y, z]]")


def test_clearance_must_be_positive(tmp_path, cli):
    content = BASE.replace("  method: pinv\n", "  method: pinv\n  clearance: 0\n")
    rejected(tmp_path, cli, content, "solver.clearance", L["method"] + 1, "must be > 0")


@pytest.mark.parametrize(
    "line, new, field",
    [
        (L["axes"], "  axes: [z, y]", "arm.axes"),
        (L["home"], "  home: [0, 10, 20, 30]", "arm.home"),
        (L["limits"], "  limits: [null, [-90, 90]]", "arm.limits"),
    ],
)
def test_length_mismatch_with_links(tmp_path, cli, line, new, field):
    rejected(tmp_path, cli, edit(line, new), field, line, "the arm has 3 links")


def test_no_goals(tmp_path, cli):
    content = BASE.replace("goals:\n  - [3, 2, 4]\n", "goals: []\n")
    rejected(tmp_path, cli, content, "goals", L["goals"], "has 0 items", "at least 1")


def test_missing_goals(tmp_path, cli):
    content = BASE.replace("goals:\n  - [3, 2, 4]\n", "")
    rejected(tmp_path, cli, content, "goals", 1, "required")


def test_home_pose_inside_an_obstacle(tmp_path, cli):
    content = edit(L["center"], "  - center: [0, 0, 3]")
    rejected(tmp_path, cli, content, "obstacles[0]", L["center"], "home pose is inside this obstacle")


def test_goal_inside_an_obstacle(tmp_path, cli):
    content = edit(L["goal0"], "  - [5, 5, 5.5]")
    rejected(tmp_path, cli, content, "goals[0]", L["goal0"], "inside obstacles[0]")


@pytest.mark.parametrize(
    "fps, fragment",
    [("0", "must be >= 0.01"), ("-5", "must be >= 0.01"), ("1e-300", "must be >= 0.01"), ("241", "must be <= 240")],
)
def test_fps_out_of_range(tmp_path, cli, fps, fragment):
    rejected(tmp_path, cli, edit(L["fps"], f"  fps: {fps}"), "render.fps", L["fps"], fragment)


def test_fps_240_is_allowed(tmp_path):
    load_scene(write(tmp_path, edit(L["fps"], "  fps: 240")))


@pytest.mark.parametrize(
    "size, field, fragment",
    [("[15, 240]", "render.size[0]", "must be >= 16"), ("[320, 7681]", "render.size[1]", "must be <= 7680")],
)
def test_size_out_of_range(tmp_path, cli, size, field, fragment):
    rejected(tmp_path, cli, edit(L["size"], f"  size: {size}"), field, L["size"], fragment)


def test_size_bounds_are_inclusive(tmp_path):
    load_scene(write(tmp_path, edit(L["size"], "  size: [16, 7680]")))


def test_version_2_says_which_version_is_read(tmp_path, cli):
    rejected(tmp_path, cli, edit(L["version"], "version: 2"), "version", 1, "version 2", "reads version 1")


def test_missing_version(tmp_path, cli):
    content = BASE.replace("version: 1\n", "")
    rejected(tmp_path, cli, content, "version", 1, "required", "version: 1")


def test_every_problem_is_reported_at_once(tmp_path):
    content = edit(L["fps"], "  fps: 0", edit(L["links"], "  links: [2, -1, 3]"))
    with pytest.raises(SceneError) as info:
        load_scene(write(tmp_path, content))
    paths = {p.path for p in info.value.problems}
    assert {"arm.links[1]", "render.fps"} <= paths
    lines = [p.line for p in info.value.problems]
    assert lines == sorted(lines)


def test_missing_file_is_a_scene_error(tmp_path, cli):
    with pytest.raises(SceneError, match="no such file"):
        load_scene(tmp_path / "nope.yaml")
    result = cli("validate", tmp_path / "nope.yaml")
    assert result.exit_code == 2 and "no such file" in result.stderr


# ------------------------------------------------------------ valid scenes


@pytest.mark.parametrize("path", BUNDLED, ids=lambda p: p.stem)
def test_bundled_scenes_load(path):
    scene = load_scene(path)
    assert scene.name == path.stem
    import hashlib

    assert scene.sha256 == hashlib.sha256(path.read_bytes()).hexdigest()
    problem = scene_to_problem(scene.model)
    assert problem.arm.n == scene.model.arm.joint_count


def test_goal_list_and_mapping_forms_and_defaults(tmp_path):
    content = "version: 1\narm:\n  links: [1, 2]\ngoals:\n  - [1, 0, 1]\n  - position: [0, 1, 1]\n    hold: 0.5\n"
    scene = load_scene(write(tmp_path, content, "defaults.yaml"))
    problem = scene_to_problem(scene.model)
    assert scene.name == "defaults"
    assert [g.hold for g in problem.goals] == [0, 0.5]
    np.testing.assert_allclose(problem.arm.axes, [[0, 0, 1], [0, 1, 0]])
    np.testing.assert_allclose(problem.arm.offsets, [[0, 0, 1], [0, 0, 2]])
    np.testing.assert_allclose(problem.home, 0.0)
    assert not problem.limits.limited.any()
    assert problem.half_width == 0.25
    assert problem.limits.margin == pytest.approx(np.radians(10.0))
    assert problem.solver.method == "pinv" and problem.solver.beta == 0.1
    assert len(problem.obstacles) == 0
    assert problem.fps == 30.0


def test_obstacle_influence_defaults_to_radius(tmp_path):
    content = BASE
    problem = scene_to_problem(load_scene(write(tmp_path, content)).model)
    assert problem.obstacles.influence[0] == problem.obstacles.radii[0] == 1.0


@given(scene_texts())
@settings(max_examples=25)
def test_random_valid_scenes_load(text):
    import tempfile

    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "random.yaml"
        path.write_text(text, encoding="utf-8")
        problem = scene_to_problem(load_scene(path).model)
    assert problem.solver.max_frames_per_goal == 30
    assert len(problem.goals) == 1


def test_schema_command_equals_committed_schema(cli):
    result = cli("schema")
    assert result.exit_code == 0
    committed = json.loads((DOCS / "scene.schema.json").read_text(encoding="utf-8"))
    assert json.loads(result.stdout) == committed


def test_schema_out_writes_file(cli, tmp_path):
    target = tmp_path / "schema.json"
    assert cli("schema", "--out", target).exit_code == 0
    assert json.loads(target.read_text()) == json.loads((DOCS / "scene.schema.json").read_text())


@pytest.mark.parametrize("path", BUNDLED, ids=lambda p: p.stem)
def test_bundled_scenes_validate_against_json_schema(path):
    jsonschema = pytest.importorskip("jsonschema")
    import yaml

    schema = json.loads((DOCS / "scene.schema.json").read_text(encoding="utf-8"))
    jsonschema.validate(yaml.safe_load(path.read_text(encoding="utf-8")), schema)


def test_exponent_numbers_are_numbers(tmp_path):
    content = BASE.replace("  method: pinv\n", "  method: newton\n  tolerance: 1e-3\n  weights: {target: 1e3}\n")
    problem = scene_to_problem(load_scene(write(tmp_path, content)).model)
    assert problem.solver.tolerance == 1e-3 and problem.solver.w_target == 1e3


@pytest.mark.parametrize("written, read", [("off", "off"), ("'off'", "off"), ("auto", "auto"), ("false", "off")])
def test_planner_off_as_yaml_reads_it(tmp_path, written, read):
    # YAML 1.1 reads a bare off as false: the scene still means the planner is off
    content = BASE.replace("  method: pinv\n", f"  method: pinv\n  planner: {written}\n")
    assert load_scene(write(tmp_path, content)).model.solver.planner == read


def test_planner_rejects_other_values(tmp_path, cli):
    content = BASE.replace("  method: pinv\n", "  method: pinv\n  planner: maybe\n")
    rejected(tmp_path, cli, content, "solver.planner", L["method"] + 1, "'maybe' is not allowed", "'auto' or 'off'")


def test_angles_that_look_like_radians_get_a_note_not_an_error(tmp_path, cli):
    path = write(tmp_path, edit(L["home"], "  home: [0.5, 1.2, -0.3]"))
    result = cli("validate", path)
    assert result.exit_code == 0 and f"ok {path}" in result.stdout
    assert f"note: {path}:{L['home']}: arm.home: these angles look like radians" in result.stderr
    assert "0.5 rad would be 28.65" in result.stderr
    quiet = cli("validate", write(tmp_path, BASE, "degrees.yaml"))  # whole degrees: no note
    assert "note:" not in quiet.stderr
