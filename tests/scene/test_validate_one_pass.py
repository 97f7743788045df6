"""``armanim validate`` reports every problem of a scene in one pass (issue 50): the field errors
(types, bounds, unknown keys), the arm's files, and the cross-field checks (counts, sizes, slow
rates, frame budgets, duplicate names, goals inside obstacles) of every part that did validate.

The oracle: a scene with many independent defects is reported with exactly the problems each
defect gives alone, each at its line and field; through the command (the Typer app in-process;
tests/system/test_e2e.py runs the installed one on a bad scene), exit 2.
"""

from __future__ import annotations

import pytest

from armanim.errors import SceneError
from armanim.scene import validate_scene_text

TEMPLATE = """version: 1
name: one-pass
arm:
  links: {links}
  axes: [z, y, y]
  home: {home}
  max_joint_speed: {speed}
obstacles:
  - center: [3, 0, 2]
    radius: 1
    name: a
  - center: {far}
    radius: 0.5
    name: {name}
  - center: [-3, -3, 2]
    radius: {radius}
goals:
  - {goal0}
  - position: {goal1}
    hold: {hold}
  - path: {{line: [[0, 3, 3], [0, 3, 4]]}}
    speed: {pathspeed}
  - joints: {joints}
  - [0, 3, 3]
solver:
  step: {step}
  {extra}: 1
render:
  format: {format}
"""
GOOD = dict(
    links="[2, 2, 2]",
    home="[0, 10, 10]",
    speed="90",
    name="b",
    far="[10, 10, 10]",
    radius="1",
    goal0="[0, 3, 3]",
    goal1="[1, 0, 3]",
    hold="0",
    pathspeed="1",
    joints="[0, 30, 30]",
    step="0.1",
    extra="damping",
    format="mp4",
)
BAD = dict(
    links='[2, 2, "x"]',
    home="[0, 10, 10, 5]",
    speed="1e-300",
    name="a",
    far="[1e10, 0, 2]",
    radius='"big"',
    goal0="[3, 0, 2]",
    goal1='[1, "x", 3]',
    hold="-1",
    pathspeed="1e-9",
    joints="[0, 30]",
    step='"fast"',
    extra="dampnig",
    format="avi",
)
"""Each defect alone is one problem: of a field (a type, a bound, an unknown key) or across fields."""


def problems(text: str) -> set[str]:
    """``FILE:LINE: field`` of each problem validation reports (the messages' frame counts depend on
    the goals that could be counted)."""
    try:
        validate_scene_text(text, "s.yaml")
    except SceneError as exc:
        return {": ".join(line.split(": ")[:2]) for line in exc.report().splitlines()}
    return set()


def test_every_problem_of_a_scene_is_reported_in_one_pass(cli, tmp_path, monkeypatch):
    assert problems(TEMPLATE.format(**GOOD)) == set()
    alone = {key: problems(TEMPLATE.format(**{**GOOD, key: value})) for key, value in BAD.items()}
    assert all(len(found) == 1 for found in alone.values()), alone
    (tmp_path / "s.yaml").write_text(TEMPLATE.format(**BAD))
    monkeypatch.chdir(tmp_path)
    result = cli("validate", "s.yaml")  # the command in-process (its lines name the file as given)
    assert result.exit_code == 2 and "Traceback" not in result.stderr + result.stdout
    reported = {": ".join(line.split(": ")[:2]) for line in result.stderr.splitlines()}
    assert reported == set().union(*alone.values()), result.stderr
    assert (
        "goals[0]: lies inside obstacles[0] ('a')" in result.stderr
    )  # the goals after a left-out one keep their index
    assert "s.yaml:22: goals[2].speed: the scene may run" in result.stderr


@pytest.mark.parametrize(
    "arm", ['links: [2, 2, "x"]', "urdf: missing.urdf", "urdf: bad.urdf", "urdf: r.urdf\n  tip_link: nowhere"]
)
def test_an_arm_that_cannot_be_read_still_lets_the_rest_be_checked(cli, tmp_path, monkeypatch, arm):
    """The arm's own problem (a field, its URDF file, a link the URDF lacks) and the rest's: a goal
    inside an obstacle needs no arm, a bad goal field, an obstacle too large."""
    joint = '<joint name="j" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" velocity="{v}"/></joint>'
    for name, velocity in (("r", "1"), ("bad", "zz")):
        (tmp_path / f"{name}.urdf").write_text(
            f'<robot name="r"><link name="a"/><link name="b"/>{joint.format(v=velocity)}</robot>'
        )
    (tmp_path / "s.yaml").write_text(
        f"version: 1\narm:\n  {arm}\nobstacles:\n  - {{center: [0.5, 0, 0.5], radius: 0.2}}\n"
        "  - {center: [2e9, 0, 0], radius: 1}\ngoals:\n  - [0.5, 0, 0.5]\n  - {position: [1, 1, 1], hold: -1}\n"
    )
    monkeypatch.chdir(tmp_path)
    result = cli("validate", "s.yaml")
    assert result.exit_code == 2 and "Traceback" not in result.stderr + result.stdout, result.stderr
    lines = result.stderr.splitlines()
    assert any(
        line.startswith(
            ("s.yaml:2: arm", "s.yaml:3: arm.links[2]", "bad.urdf:1: joint 'j'", "missing.urdf: no such file")
        )
        for line in lines
    ), lines
    for expected in (
        "goals[0]: lies inside obstacles[0]",
        "obstacles[1].center[0]: 2e+09 is too large",
        "goals[1].hold: must be >= 0",
    ):
        assert any(expected in line for line in lines), (expected, lines)


def test_without_an_arm_a_goal_inside_an_obstacle_keeps_its_own_index():
    """The arm unusable, the goal points are checked alone: a joint goal before them and a grasp
    (whose point lies in the object it takes) are skipped, and the messages name each goal by its
    index in the file."""
    found = problems(
        "version: 1\narm: {links: [2, 5, -5, 5], base: [5, 5, 0]}\n"
        "obstacles:\n  - {center: [12, 9, 8], radius: 2, name: ball}\n"
        "goals:\n  - {joints: [0, 10, 10, 10]}\n  - {position: [12, 9, 8], grasp: ball}\n  - [12, 9, 8]\n"
    )
    assert found == {"s.yaml:2: arm.links[2]", "s.yaml:8: goals[2]"}, found
