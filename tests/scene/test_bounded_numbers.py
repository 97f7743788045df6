"""One bounded reading of every number of a scene (issue 36): floors for steps, angles and
lengths, extreme vectors meaning their direction, joint ranges narrower than the planner's
buffer, fixed-length lists, armanim's own table names, and every problem of a file in one pass.

Each test is named in docs/reliability.md, which it keeps true.
"""

from __future__ import annotations

import numpy as np
import pytest

from armanim.arm.geometry import unit_vector
from armanim.errors import SceneError
from armanim.scene import scene_to_problem, validate_scene_text

ARM = "version: 1\narm: {links: [1, 1, 1, 1]}\n"


def scene_error(text: str) -> str:
    """The report of the SceneError ``text`` must raise."""
    with pytest.raises(SceneError) as caught:
        validate_scene_text(text, "s.yaml")
    return caught.value.report()


@pytest.mark.parametrize("step", ["1e-9", "1e-6", "1e-300", "0.0009"])
def test_a_max_joint_step_below_the_floor_is_refused_with_its_line(step):
    report = scene_error(ARM + f"goals: [[1, 1, 2]]\nsolver: {{max_joint_step: {step}}}\n")
    assert report.startswith("s.yaml:4: solver.max_joint_step: ") and "0.001" in report


@pytest.mark.parametrize(
    "form",
    [
        "tool_axis: [1e-320, 0, 0]",
        "tool_axis: [1e308, 0, 1e308]",
        "orientation: {axis: [1e-200, 1e-200, 0], angle: 30}",
        "orientation: {axis: [1e308, 1e308, 1e308], angle: 30}",
    ],
)
def test_extreme_orientation_vectors_mean_their_direction(form):
    model = validate_scene_text(ARM + f"goals:\n  - {{position: [1, 1, 2], {form}}}\n", "s.yaml")
    goal = scene_to_problem(model).goals[0].orientation
    if goal.axis is not None:
        assert np.allclose(goal.axis, unit_vector([1, 0, 0] if "1e-320" in form else [1, 0, 1]))
    else:  # 30 degrees about the vector's direction, never the identity or NaN
        assert np.isclose(np.degrees(np.arccos((np.trace(goal.rotation) - 1) / 2)), 30.0)


@pytest.mark.parametrize(
    "field",
    [
        "orientation: {axis: [0, 0, 1], angle: 1e308}",
        "orientation: {rpy: [1e308, 0, 0]}",
        "orientation: {rpy: [0, 361, 0]}",
    ],
)
def test_goal_angles_are_bounded_like_every_other_angle(field):
    report = scene_error(ARM + f"goals:\n  - {{position: [1, 1, 2], {field}}}\n")
    assert "s.yaml:4: goals[0].orientation." in report and "360" in report


@pytest.mark.parametrize(
    "limits,margin", [("[[-0.4, 0.4], null, null, null]", ""), ("[[-5, 5], null, null, null]", "  limit_margin: 180\n")]
)
def test_a_joint_range_narrower_than_the_planner_s_buffer_is_refused_with_the_field(limits, margin):
    report = scene_error(f"version: 1\narm:\n  links: [1, 1, 1, 1]\n  limits: {limits}\n{margin}goals: [[1, 1, 2]]\n")
    assert report.startswith("s.yaml:4: arm.limits[0]: a range of ") and "limit_margin" in report


SMALL = ARM + "goals: [[1, 1, 2]]\nrender: {fps: 10, size: [64, 48]}\nsolver: {max_frames_per_goal: 40}\n"


@pytest.mark.parametrize("name", ["index.csv", "INDEX.CSV", "notes-sweep.csv", "a-Sweep.CSV"])
def test_names_of_armanim_s_own_tables_are_refused_at_validate(name):
    report = scene_error(SMALL + f"name: {name}\n")
    assert report.startswith("s.yaml:6: name: ") and "table armanim writes" in report


def test_validate_reports_every_problem_of_a_file_in_one_pass():
    text = (
        "version: 1\narm:\n  links: [1, 1, 1, 1]\n  limits: [[10, -10], null, null, null]\n"
        "obstacles:\n  - {center: [0, 0, 1], radius: 0.3}\ngoals: [[1, 1, 2]]\nrender: {size: [10, 10000000]}\n"
    )
    report = scene_error(text)
    for expected in (
        "s.yaml:4: arm.limits[0]: min must be below max",
        "s.yaml:6: obstacles[0]: link 1 of the arm's home pose is inside",
        "s.yaml:8: render.size[0]: must be >= 16",
        "s.yaml:8: render.size[1]: must be <= 7680",
    ):
        assert expected in report, report


@pytest.mark.parametrize(
    "field,exact",
    [
        ("goals: [{position: [1, 1, 2], tool_axis: [1, 0]}]", "goals[0].tool_axis: has 2 items (expected exactly 3)"),
        ("goals: [[1, 1, 2]]\nrender: {size: [64]}", "render.size: has 1 items (expected exactly 2)"),
        ("goals: [{position: [1, 1, 2], orientation: {quaternion_wxyz: [1, 0, 0]}}]", "(expected exactly 4)"),
    ],
)
def test_a_list_of_a_fixed_length_says_exactly(field, exact):
    assert exact in scene_error(ARM + field + "\n")


@pytest.mark.parametrize(
    "field",
    [
        "solver: {orientation_tolerance: 5e-324}",
        "solver: {orientation_tolerance: 1e-300}",
        "arm: {links: [1, 1, 1, 1], limit_margin: 5e-324}",
    ],
)
def test_angles_that_would_be_zero_radians_are_refused(field):
    text = "version: 1\n" + (field + "\n" if field.startswith("arm") else "arm: {links: [1, 1, 1, 1]}\n" + field + "\n")
    report = scene_error(text + "goals:\n  - {position: [1, 1, 2], tool_axis: [0, 0, 1]}\n")
    assert "must be >= 1e-06" in report  # found by benchmarks/fuzz_bench.py: a ZeroDivisionError in pose_distance


@pytest.mark.parametrize("field", ["links: [1, 1e-300, 1]", "links: [1, 1, 1], width: 5e-324"])
def test_lengths_below_the_smallest_are_refused(field):
    assert "is too small (expected at least 1e-09: choose a larger unit)" in scene_error(
        "version: 1\narm: {" + field + "}\ngoals: [[1, 1, 1]]\n"
    )


@pytest.mark.parametrize("value", ["1e300", "-1.7976931348623157e308", "360.5"])
def test_a_joint_goal_is_bounded_as_arm_home_is(value):
    """Campaign 5: a joint goal of 1e300 degrees on an unlimited joint was accepted (and wrapped to
    whatever radians(1e300) mod 2 pi rounds to); arm.home is within [-360, 360], and so is a joint goal."""
    report = scene_error(ARM + f"goals:\n  - joints: [{value}, 0, 0, 0]\n")
    assert report.startswith("s.yaml:4: goals[0].joints[0]: must be ") and "360" in report, report


@pytest.mark.parametrize(
    "field, value, word",
    [
        ("self_clearance", "1e300", "too large"),
        ("self_clearance", "1e-300", "too small"),
        ("orientation_weight", "1e300", "too large"),
        ("orientation_weight", "1e-300", "too small"),
    ],
)
def test_self_clearance_and_orientation_weight_are_bounded_as_lengths(field, value, word):
    """Campaign 5: ``solver.orientation_weight: 1e300`` validated, and a Panda's reachable pose goal
    then ended ``orientation_unreachable`` (the weight squared is infinite); ``self_clearance: 1e300``
    validated too, while ``clearance: 1e300`` was refused. Both are lengths: within [1e-9, 1e9]."""
    report = scene_error(ARM + f"goals: [[1, 1, 2]]\nsolver: {{{field}: {value}}}\n")
    assert report.startswith(f"s.yaml:4: solver.{field}: ") and word in report, report
