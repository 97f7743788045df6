"""Path goals in the scene file (issue 39, item 1): every form read into the solver's problem,
every rejection with its field path, its line and exit 2, through the loader and the command."""

from __future__ import annotations

import math

import numpy as np
import pytest
from test_scene import rejected, write

from armanim.scene import load_scene, scene_to_problem
from armanim.scene.checks import frame_budget

PATHS = """\
version: 1
arm:
  links: [2, 3, 3]
  axes: [z, y, y]
  home: [0, 10, 20]
goals:
  - path: {line: [[4, -2, 3], [4, 2, 3]]}
    speed: 0.5
    tool_axis: [0, 0, -1]
  - path: {arc: {center: [4, 0, 3], start: [5, 0, 3], angle: 270, normal: [0, 0, 1]}}
    speed: 0.25
    hold: 1
  - path: {polyline: [[3, 0, 2], [3, 1, 2], [3, 1, 2], [4, 1, 2]]}
    speed: 0.25
  - path:
      text:
        string: "armanim"
        origin: [5, 1, 4]
        height: 0.6
        right: [0, -1, 0]
        up: [0, 0, 1]
    speed: 0.5
    tool_axis: [1, 0, 0]
  - [3, 2, 4]
solver:
  tolerance: 0.02
render:
  fps: 30
"""
# line numbers of PATHS
L = {
    "goal0": 7,
    "line": 7,
    "speed0": 8,
    "tool_axis0": 9,
    "arc": 10,
    "speed1": 11,
    "polyline": 13,
    "path3": 15,
    "text": 16,
    "string": 17,
    "origin": 18,
    "height": 19,
    "right": 20,
    "up": 21,
    "speed3": 22,
    "tool_axis3": 23,
    "goal4": 24,
    "solver": 25,
    "tolerance": 26,
}


def edit(line: int, new: str, text: str = PATHS) -> str:
    lines = text.splitlines()
    lines[line - 1] = new
    return "\n".join(lines) + "\n"


def test_every_path_form_becomes_a_goal_at_its_start(tmp_path):
    problem = scene_to_problem(load_scene(write(tmp_path, PATHS)).model)
    line, arc, polyline, text, point = problem.goals
    assert np.array_equal(line.position, [4, -2, 3]) and line.speed == 0.5 and line.path.length == pytest.approx(4.0)
    assert line.orientation is not None and np.allclose(line.orientation.axis, [0, 0, -1])
    assert np.array_equal(arc.position, [5, 0, 3]) and arc.hold == 1.0
    assert arc.path.length == pytest.approx(1.5 * math.pi)  # radius 1, 270 degrees in radians
    assert np.allclose(arc.path.end, [4, -1, 3])
    assert len(polyline.path.pieces) == 2 and polyline.path.length == pytest.approx(2.0)
    assert np.array_equal(text.position, text.path.start) and text.path.pieces[0].ink
    assert not all(p.ink for p in text.path.pieces)
    assert point.path is None and point.speed == 0.0 and np.array_equal(point.position, [3, 2, 4])
    assert problem.solver.path_tolerance == 0.02  # solver.tolerance when path_tolerance is left out


def test_path_tolerance_is_the_scenes(tmp_path):
    problem = scene_to_problem(load_scene(write(tmp_path, edit(L["tolerance"], "  path_tolerance: 0.001"))).model)
    assert problem.solver.path_tolerance == 0.001 and problem.solver.tolerance == 0.01


def test_a_path_goal_counts_its_frames_along_the_path(tmp_path):
    model = load_scene(write(tmp_path, PATHS)).model
    point_only = load_scene(
        write(
            tmp_path, "\n".join(PATHS.splitlines()[:6] + ["  - [3, 2, 4]", "render:", "  fps: 30"]) + "\n", "point.yaml"
        )
    ).model
    per_goal = model.solver.max_frames_per_goal
    along = [4.0 / 0.5 * 30, 1.5 * math.pi / 0.25 * 30, 2.0 / 0.25 * 30]
    assert frame_budget(model) - frame_budget(point_only) >= 4 * per_goal + 30 + sum(math.ceil(a - 1e-9) for a in along)


@pytest.mark.parametrize(
    "line, new, field, fragments",
    [
        (
            "line",
            "  - path: {line: [[4, -2, 3], [4, -2, 3]]}",
            "goals[0].path.line",
            ("length 0", "two different points"),
        ),
        ("speed0", "    speed: 0", "goals[0].speed", ("must be > 0",)),
        ("speed0", "    speed: -1", "goals[0].speed", ("must be > 0",)),
        (
            "arc",
            "  - path: {arc: {center: [4, 0, 3], start: [4, 0, 3], angle: 270, normal: [0, 0, 1]}}",
            "goals[1].path.arc.start",
            ("radius 0",),
        ),
        (
            "arc",
            "  - path: {arc: {center: [4, 0, 3], start: [4, 0, 5], angle: 270, normal: [0, 0, 1]}}",
            "goals[1].path.arc.normal",
            ("parallel", "on the arc's axis"),
        ),
        (
            "arc",
            "  - path: {arc: {center: [4, 0, 3], start: [5, 0, 3], angle: 0, normal: [0, 0, 1]}}",
            "goals[1].path.arc.angle",
            ("nonzero",),
        ),
        (
            "arc",
            "  - path: {arc: {center: [4, 0, 3], start: [5, 0, 3], angle: 400, normal: [0, 0, 1]}}",
            "goals[1].path.arc.angle",
            ("must be <= 360",),
        ),
        (
            "arc",
            "  - path: {arc: {center: [4, 0, 3], start: [5, 0, 3], angle: 90, normal: [0, 0, 0]}}",
            "goals[1].path.arc.normal",
            ("zero vector",),
        ),
        (
            "polyline",
            "  - path: {polyline: [[3, 0, 2], [3, 0, 2], [3, 0, 2]]}",
            "goals[2].path.polyline",
            ("length 0",),
        ),
        ("polyline", "  - path: {polyline: [[3, 0, 2]]}", "goals[2].path.polyline", ("has 1 items", "at least 2")),
        ("string", '        string: "armanim é"', "goals[3].path.text.string", ("the font lacks: 'é'",)),
        ("string", '        string: "tab\\there"', "goals[3].path.text.string", ("the font lacks: '\\t'",)),
        ("string", '        string: ""', "goals[3].path.text.string", ("is empty",)),
        ("string", '        string: "   "', "goals[3].path.text.string", ("only spaces",)),
        ("height", "        height: 0", "goals[3].path.text.height", ("must be > 0",)),
        ("height", "        height: -0.1", "goals[3].path.text.height", ("must be > 0",)),
        ("right", "        right: [0, -2, 0]", "goals[3].path.text.right", ("has length 2", "unit vector")),
        ("up", "        up: [0, 0.6, 0.8]", "goals[3].path.text.up", ("not square to right", "dot product is -0.6")),
        ("up", "        up: [0, -1, 0]", "goals[3].path.text.up", ("not square to right",)),
        ("up", "        up: [0, 0, 1.01]", "goals[3].path.text.up", ("has length 1.01",)),
        (
            "tool_axis3",
            "    tool_axis: [-1, 0, 0]",
            "goals[3].tool_axis",
            ("out of the board's front", "right x up = [-1, 0, 0]", "tool_axis: [1, 0, 0]"),
        ),
        ("goal4", "  - {position: [3, 2, 4], speed: 1}", "goals[4].speed", ("belongs to a path goal",)),
        (
            "goal4",
            "  - {position: [3, 2, 4], path: {line: [[0, 0, 1], [0, 1, 1]]}, speed: 1}",
            "goals[4]",
            ("both position and path",),
        ),
        ("goal4", "  - {speed: 1, hold: 2}", "goals[4]", ("neither position, path nor joints",)),
        (
            "goal4",
            "  - {path: {line: [[0, 0, 1], [0, 1, 1]], arc: {center: [0, 0, 0], start: [1, 0, 0], angle: 9, normal: [0, 0, 1]}}, speed: 1}",
            "goals[4].path",
            ("one form (got line and arc)",),
        ),
        ("goal4", "  - {path: {circle: [0, 0, 0]}, speed: 1}", "goals[4].path.circle", ("unknown key 'circle'",)),
    ],
)
def test_bad_path_goals_are_named_with_their_line(tmp_path, cli, line, new, field, fragments):
    rejected(tmp_path, cli, edit(L[line], new), field, L[line], *fragments)


def test_a_path_goal_without_speed_is_named_at_its_goal(tmp_path, cli):
    rejected(
        tmp_path,
        cli,
        edit(L["speed0"], "    hold: 0"),
        "goals[0].speed",
        L["goal0"],
        "is required on a path goal",
        "scene units per second",
    )


def test_a_tiny_path_tolerance_is_too_small(tmp_path, cli):
    rejected(
        tmp_path,
        cli,
        edit(L["tolerance"], "  path_tolerance: 1e-12"),
        "solver.path_tolerance",
        L["tolerance"],
        "too small",
    )


def test_a_path_too_slow_for_the_frame_limit_names_its_speed(tmp_path, cli):
    rejected(
        tmp_path,
        cli,
        edit(L["speed0"], "    speed: 1e-9"),
        "goals[0].speed",
        L["speed0"],
        "along this goal's path",
        "raise the speed",
    )


def test_a_path_too_far_away_is_too_large(tmp_path, cli):
    rejected(
        tmp_path,
        cli,
        edit(L["line"], "  - path: {line: [[4, -2, 3], [4, 2e10, 3]]}"),
        "goals[0].path.line[1][1]",
        L["line"],
        "too large",
    )


def test_path_scenes_validate_from_the_command(tmp_path, cli):
    path = write(tmp_path, PATHS)
    result = cli("validate", path)
    assert result.exit_code == 0, result.output
    assert "5 goals" in result.stdout


def test_a_text_of_more_than_a_thousand_characters_is_too_long(tmp_path, cli):
    rejected(
        tmp_path,
        cli,
        edit(L["string"], f'        string: "{"a" * 1001}"'),
        "goals[3].path.text.string",
        L["string"],
        "has 1,001 characters (expected at most 1,000)",
    )


def test_a_polyline_of_more_than_a_thousand_points_is_too_long(tmp_path, cli):
    points = ", ".join(f"[3, {k * 1e-3:g}, 2]" for k in range(1001))
    rejected(
        tmp_path,
        cli,
        edit(L["polyline"], f"  - path: {{polyline: [{points}]}}"),
        "goals[2].path.polyline",
        L["polyline"],
        "has 1001 items (expected at most 1000)",
    )


def test_a_tiny_text_height_is_too_small(tmp_path, cli):
    text = rejected(
        tmp_path,
        cli,
        edit(L["height"], "        height: 1e-12"),
        "goals[3].path.text.height",
        L["height"],
        "too small",
        "choose a larger unit",
    )
    assert "lift" not in text  # the default lift, 0.3 x height, is not the user's to fix


def test_a_tiny_lift_is_too_small(tmp_path, cli):
    content = edit(L["origin"], "        origin: [5, 1, 4]\n        lift: 1e-12")
    rejected(tmp_path, cli, content, "goals[3].path.text.lift", L["origin"] + 1, "too small", "choose a larger unit")


def test_a_line_shorter_than_the_smallest_length_has_length_zero(tmp_path, cli):
    rejected(
        tmp_path,
        cli,
        edit(L["line"], "  - path: {line: [[4, -2, 3], [4, -2, 3.0000000000001]]}"),
        "goals[0].path.line",
        L["line"],
        "length 0",
    )


def test_the_documented_path_goals_validate_on_a_ur5_with_a_pen(tmp_path):
    from conftest import DOCS

    text = (DOCS / "scene-format.md").read_text(encoding="utf-8")
    block = text.split("## Path goals", 1)[1].split("```yaml\n", 1)[1].split("```", 1)[0]
    scene = "version: 1\narm:\n  robot: ur5\n  tool: {xyz: [0, 0, 0.12], pen: {length: 0.12, radius: 0.008}}\n" + block
    problem = scene_to_problem(load_scene(write(tmp_path, scene)).model)
    assert [g.path is not None for g in problem.goals] == [True] * 4
    assert problem.goals[3].path.length > problem.goals[3].path.inked_length > 0


def test_a_text_goals_orientation_must_point_the_tool_into_the_board(tmp_path, cli):
    # R = Ry(pitch): the tool's z is [sin pitch, 0, cos pitch]; the board's front is -x
    into = edit(L["tool_axis3"], "    orientation: {rpy: [0, 90, 0]}")
    assert scene_to_problem(load_scene(write(tmp_path, into, "into.yaml")).model).goals[3].orientation is not None
    rejected(
        tmp_path,
        cli,
        edit(L["tool_axis3"], "    orientation: {rpy: [0, -90, 0]}"),
        "goals[3].orientation",
        L["tool_axis3"],
        "out of the board's front",
    )


BACK_AND_FORTH = (
    "version: 1\nname: pl\narm: {links: [1, 1, 1, 1]}\ngoals:\n  - {path: {polyline: [%s]}, speed: %s}\n"
    "render: {size: [160, 90]}\nsolver: {path_tolerance: %s}\n"
)


@pytest.mark.parametrize(
    "points, tolerance",
    [
        ("[1, 1, 2], [1, 1.3, 2]", "1e-9"),
        (",".join(["[1, 1, 2], [1, 1.3, 2]"] * 500), "1e-6"),
        (",".join(["[1, 1, 2], [1, 1.3, 2]"] * 500), "1e-9"),
    ],
)
def test_a_path_tolerance_near_its_floor_is_refused_at_validate_with_its_remedy(tmp_path, cli, points, tolerance):
    """The campaign's scenes (issue 50, item 4): a 0.3 line at 1e-9, a 300-unit polyline at 1e-6
    and 1e-9. validate said ok; run gave a MemoryError traceback after 5.6 GB, or blamed --fps and
    the holds. The path's samples are counted in closed form, the run's frame bound checked at
    validate, naming solver.path_tolerance and the value that fits; that value validates."""
    text = BACK_AND_FORTH % (points, 5, tolerance)
    message = rejected(
        tmp_path,
        cli,
        text,
        "solver.path_tolerance",
        7,
        "too fine for the frame limit",
        "raise solver.path_tolerance to at least about",
    )
    need = message.split("at least about ")[1].split(",")[0]
    assert float(need) > float(tolerance)
    assert cli("validate", write(tmp_path, BACK_AND_FORTH % (points, 5, need))).exit_code == 0
    assert "MemoryError" not in message and "--fps" not in message
    run = cli("run", write(tmp_path, text), "--no-video", "--quiet", "--out", tmp_path / "o")
    assert run.exit_code == 2 and "solver.path_tolerance" in run.stderr and "--fps" not in run.stderr


def test_a_path_whose_samples_at_its_speed_overflow_the_limit_names_its_speed(tmp_path, cli):
    """300 units at 0.1 a second and 30 fps: 90,000 frames along it (within the limit), but the
    run may halve each sample's step 4 times: 1.44 million. Refused at validate, at the speed."""
    points = ",".join(["[1, 1, 2], [1, 1.3, 2]"] * 500)
    rejected(
        tmp_path,
        cli,
        BACK_AND_FORTH % (points, 0.1, 0.01),
        "goals[0].speed",
        5,
        "too slow for the frame limit",
        "raise the speed or shorten the path",
    )


LINE_GOAL = (
    "version: 1\nname: p\narm: {links: [1, 1, 1], axes: [z, y, y]}\nrender: {size: [160, 90], fps: 30}\n"
    "solver: {path_tolerance: %s}\ngoals:\n  - position: [1, 0, 1]\n    %s: {distance: 1, axis: %s, speed: 0.5}\n"
)


@pytest.mark.parametrize("line, axis", [("approach", "[0, 0, -1]"), ("retreat", "[0, 0, 1]")])
def test_an_approach_or_retreat_at_a_fine_path_tolerance_is_refused_at_validate(tmp_path, cli, line, axis):
    """Campaign 18: an approach (or a retreat) of 1 m at path_tolerance 1e-9 is a path the run
    follows: validate said ok, and run refused it, `the scene may run up to 1,600,001,202 frames
    (...; run armanim validate on it for the field to change)`. Validate counts the lines' samples
    as the path goals' and names solver.path_tolerance with the value that fits; that validates,
    and the run is refused at its line as validate's."""
    message = rejected(
        tmp_path,
        cli,
        LINE_GOAL % ("1e-9", line, axis),
        "solver.path_tolerance",
        5,
        f"following goals[0]'s {line} (1 long)",
        "raise solver.path_tolerance to at least about",
    )
    need = message.split("at least about ")[1].split(",")[0]
    assert cli("validate", write(tmp_path, LINE_GOAL % (need, line, axis))).exit_code == 0
    run = cli(
        "run", write(tmp_path, LINE_GOAL % ("1e-9", line, axis)), "--no-video", "--quiet", "--out", tmp_path / "o"
    )
    assert run.exit_code == 2 and "solver.path_tolerance" in run.stderr and "run armanim validate" not in run.stderr


def test_many_slow_approaches_whose_sum_overflows_the_limit_name_a_speed(tmp_path, cli):
    """Four approaches of 0.2 m at 0.0025 m/s and 240 fps: 19,200 frames each along the line, and
    the run may halve each sample's step 4 times (307,201 each, 1.2 million in all). Campaign 18:
    validate said ok (it counted 19,200 frames a line); now refused at an approach's speed."""
    text = (
        "version: 1\nname: p\narm: {links: [1, 1, 1], axes: [z, y, y]}\nrender: {size: [160, 90], fps: 240}\n"
        "solver: {path_tolerance: 1e-3}\ngoals:\n"
        + "  - position: [1, 0, 1]\n    approach: {distance: 0.2, axis: [0, 0, -1], speed: 0.0025}\n"
        * 4
    )
    rejected(tmp_path, cli, text, "goals[0].approach.speed", 8, "too slow for the frame limit", "raise the speed")


def test_the_sample_count_is_the_samples_length():
    """ToolPath.sample_count, in closed form, against the samples themselves (random polylines and spacings)."""
    from armanim.motion.toolpath import ToolPath

    rng = np.random.default_rng(50)
    for _ in range(200):
        path = ToolPath.polyline(rng.normal(size=(int(rng.integers(2, 12)), 3)))
        spacing = float(10 ** rng.uniform(-3, 1))
        assert path.sample_count(spacing) == len(path.samples(spacing))


@pytest.mark.parametrize("field", ["path_tolerance", "tolerance"])
def test_a_subnormal_tolerance_is_refused_without_a_traceback(tmp_path, cli, field):
    """Campaign 5: ``solver.tolerance`` (which a path goal follows without a path_tolerance) or
    ``path_tolerance`` of 5e-324 made the path's sample count infinite, and validate ended in
    ``OverflowError: cannot convert float infinity to integer``. Now: too small, with its line."""
    text = BACK_AND_FORTH.replace("path_tolerance", field) % ("[1, 1, 2], [1, 1.3, 2]", 5, "5e-324")
    result = cli("validate", write(tmp_path, text))
    assert result.exit_code == 2 and f"scene.yaml:7: solver.{field}: 4.94066e-324 is too small" in result.stderr, (
        result.stderr
    )
    assert "more than 10^15 frames" in result.stderr
