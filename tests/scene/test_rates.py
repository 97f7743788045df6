"""Joint rate limits in the scene (issue 34): every validation message with its field path and
line, the URDF's <limit velocity> against pinocchio, the defaults (robot.yaml, URDF, links),
degrees becoming radians once, and the notes for limits above the robot's own."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from armanim.errors import SceneError
from armanim.motion.problem import LINK_ACCELERATION_PER_SPEED
from armanim.scene import load_scene, scene_to_problem
from armanim.scene.fields import RATE_BOUNDS
from armanim.scene.limits import URDF_SPEED, rate_note_lines, rate_notes
from armanim.scene.robots import RATE_UNITS, ROBOTS, bundled_robot, published_joint_names
from armanim.scene.urdf import read_urdf

TORTURE = Path(__file__).resolve().parents[1] / "urdf" / "torture.urdf"

LINKS = """\
version: 1
arm:
  links: [2, 3, 3]
  RATES
goals:
  - [3, 2, 4]
solver:
  max_joint_step: 5
render:
  fps: 24
"""

ROBOT = """\
version: 1
arm:
  robot: ROBOT
  RATES
goals:
  - [0.4, 0.1, 0.4]
"""

RATE_LINE = 4  # the line RATES stands on, in both


def scene_text(rates: str, template: str = LINKS, robot: str = "panda") -> str:
    return template.replace("RATES", rates or "width: null").replace("ROBOT", robot)


def write(tmp_path: Path, text: str, name: str = "scene.yaml") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def rejected(tmp_path, cli, text: str, field: str, line: int, *fragments: str) -> str:
    """load_scene refuses it naming ``field`` at ``line``, and ``armanim validate`` exits 2 with
    ``FILE:LINE: field: message`` (each fragment in it), no traceback."""
    path = write(tmp_path, text)
    with pytest.raises(SceneError) as info:
        load_scene(path)
    assert any(p.path == field and p.line == line for p in info.value.problems), info.value.report()
    result = cli("validate", path)
    assert result.exit_code == 2, result.output
    assert f"{path}:{line}: {field}: " in result.stderr, result.stderr
    for fragment in fragments:
        assert fragment in result.stderr, (fragment, result.stderr)
    assert "Traceback" not in result.output and f"ok {path}" not in result.stdout
    return result.stderr


def rates_deg(text: str, tmp_path: Path, fps: float | None = None):
    """The problem's rate limits in degrees: (speed, acceleration, jerk or None)."""
    rates = scene_to_problem(load_scene(write(tmp_path, text)).model, fps=fps).rates
    return (
        np.degrees(rates.speed),
        np.degrees(rates.acceleration),
        None if rates.jerk is None else np.degrees(rates.jerk),
    )


# ------------------------------------------------------------ validation messages


@pytest.mark.parametrize(
    ("rates", "field", "fragments"),
    [
        ("max_joint_speed: [100, 100, -1]", "arm.max_joint_speed[2]", ("must be > 0 (got -1)",)),
        ("max_joint_speed: 0", "arm.max_joint_speed", ("must be > 0 (got 0)",)),
        ("max_joint_acceleration: -5", "arm.max_joint_acceleration", ("must be > 0 (got -5)",)),
        (
            "max_joint_acceleration: [1, .nan, 1]",
            "arm.max_joint_acceleration[1]",
            ("must be a finite number (got nan)",),
        ),
        ("max_joint_speed: .inf", "arm.max_joint_speed", ("must be a finite number (got inf)",)),
        ("max_joint_jerk: [1, 1, -.inf]", "arm.max_joint_jerk[2]", ("must be a finite number",)),
        ("max_joint_speed: 1e6", "arm.max_joint_speed", (f"must be <= {RATE_BOUNDS['max_joint_speed']:g}",)),
        (
            "max_joint_acceleration: 2e7",
            "arm.max_joint_acceleration",
            (f"must be <= {RATE_BOUNDS['max_joint_acceleration']:g}",),
        ),
        ("max_joint_jerk: 2e10", "arm.max_joint_jerk", (f"must be <= {RATE_BOUNDS['max_joint_jerk']:g}",)),
        ("max_joint_speed: fast", "arm.max_joint_speed", ("must be a number (got 'fast')",)),
        ("max_joint_speed: true", "arm.max_joint_speed", ("must be a number (got true)",)),
        ("max_joint_acceleration: robot", "arm.max_joint_acceleration", ("must be a number (got 'robot')",)),
        ("max_joint_jerk: robt", "arm.max_joint_jerk", ("'robt' is not allowed (expected 'robot')",)),
        (
            "max_joint_speed: [100, 100, 100, 100]",
            "arm.max_joint_speed",
            ("has 4 values, the arm has 3 joints (give one per joint, or one number for all)",),
        ),
        ("max_joint_acceleration: []", "arm.max_joint_acceleration", ("has 0 values, the arm has 3 joints",)),
        ("max_joint_jerk: [1, 2]", "arm.max_joint_jerk", ("has 2 values, the arm has 3 joints",)),
        ("max_joint_jerk: robot", "arm.max_joint_jerk", ("this arm is not a bundled robot",)),
    ],
)
def test_bad_rates_are_clear_errors(tmp_path, cli, rates, field, fragments):
    rejected(tmp_path, cli, scene_text(rates), field, RATE_LINE, *fragments)


def test_urdf_arm_rate_lengths_and_published_jerk(tmp_path, cli):
    rejected(
        tmp_path,
        cli,
        scene_text("max_joint_speed: [100, 100, 100]", ROBOT, "panda"),
        "arm.max_joint_speed",
        RATE_LINE,
        "has 3 values, the arm has 7 joints (give one per joint, or one number for all)",
    )
    rejected(
        tmp_path,
        cli,
        scene_text("max_joint_jerk: robot", ROBOT, "ur5"),
        "arm.max_joint_jerk",
        RATE_LINE,
        "robot ur5's maker publishes no jerk limits for these joints",
    )


def test_published_rates_go_by_joint_name(tmp_path):
    """A bundled robot cut short (tip_link) keeps each of its joints' own published limits."""
    text = scene_text("tip_link: panda_link5\n  home: [0, -45, 0, -135, 0]\n  max_joint_jerk: robot", ROBOT, "panda")
    rates = scene_to_problem(load_scene(write(tmp_path, text)).model).rates
    np.testing.assert_allclose(rates.speed, [2.175] * 4 + [2.61])
    np.testing.assert_allclose(rates.acceleration, FRANKA_ACCELERATION[:5])
    np.testing.assert_allclose(rates.jerk, FRANKA_JERK[:5])
    text = scene_text("base_link: panda_link2\n  home: [0, -135, 0, 90, 45]", ROBOT, "panda")
    rates = scene_to_problem(load_scene(write(tmp_path, text)).model).rates
    np.testing.assert_allclose(rates.acceleration, FRANKA_ACCELERATION[2:])


def test_every_problem_is_reported_at_once(tmp_path):
    text = scene_text("max_joint_speed: [1, -1, 1]\n  max_joint_acceleration: 0\n  max_joint_jerk: .nan")
    with pytest.raises(SceneError) as info:
        load_scene(write(tmp_path, text))
    assert {p.path for p in info.value.problems} >= {
        "arm.max_joint_speed[1]",
        "arm.max_joint_acceleration",
        "arm.max_joint_jerk",
    }


# ------------------------------------------------------------ the URDF's velocities


@pytest.mark.parametrize("path", [*(bundled_robot(r).urdf for r in ROBOTS), TORTURE], ids=lambda p: p.stem)
def test_urdf_velocity_matches_pinocchio(path):
    pin = pytest.importorskip("pinocchio")
    robot = read_urdf(path)
    model = pin.buildModelFromUrdf(str(path))
    moving = [j for j in robot.joints.values() if j.kind in ("revolute", "continuous")]
    assert moving
    for joint in moving:
        pin_joint = model.joints[model.getJointId(joint.name)]
        expected = model.velocityLimit[pin_joint.idx_v]
        assert (joint.velocity if joint.velocity is not None else np.inf) == expected, (
            joint.name
        )  # none given: pinocchio's inf


def test_scene_speeds_default_to_the_urdf_velocity(tmp_path):
    """A user's URDF: each joint's <limit velocity>, URDF_SPEED where it gives none, and
    acceleration LINK_ACCELERATION_PER_SPEED x the speed per second."""
    scene = write(
        tmp_path,
        f"version: 1\narm:\n  urdf: {TORTURE}\n  base_link: world\n  tip_link: tool\ngoals:\n  - [0.3, 0.1, 0.3]\n",
    )
    problem = scene_to_problem(load_scene(scene).model)
    assert problem.arm.joint_names == ("spin", "skew", "noaxis", "wrist")
    np.testing.assert_allclose(np.degrees(problem.rates.speed), [URDF_SPEED, *np.degrees([1.0, 1.0, 1.0])], rtol=1e-15)
    np.testing.assert_allclose(
        problem.rates.acceleration, LINK_ACCELERATION_PER_SPEED * problem.rates.speed, rtol=1e-15
    )
    assert problem.rates.jerk is None


def urdf_with_velocity(tmp_path: Path, velocity: str, joint: str = "j1") -> Path:
    """A two-joint URDF whose joint ``joint``'s <limit velocity> is ``velocity`` (line 6 for j1); an
    off-path branch has a joint ``grip`` too."""
    v1 = velocity if joint == "j1" else "1"
    v3 = velocity if joint == "grip" else "1"
    text = f"""<robot name="r">
  <link name="base"/><link name="l1"/><link name="l2"/><link name="finger"/>
  <joint name="j1" type="revolute">
    <parent link="base"/><child link="l1"/>
    <axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="5" velocity="{v1}"/>
  </joint>
  <joint name="j2" type="continuous">
    <parent link="l1"/><child link="l2"/><origin xyz="0 0 0.5"/><axis xyz="0 1 0"/>
  </joint>
  <joint name="grip" type="revolute">
    <parent link="base"/><child link="finger"/>
    <limit lower="0" upper="1" effort="5" velocity="{v3}"/>
  </joint>
</robot>
"""
    path = tmp_path / "r.urdf"
    path.write_text(text, encoding="utf-8")
    return path


@pytest.mark.parametrize(
    ("velocity", "fragment"),
    [
        ("0", "<limit> velocity 0 is not a speed (expected rad/s > 0"),
        ("-2", "<limit> velocity -2 is not a speed"),
        ("nan", "velocity='nan' (expected 1 finite numbers"),
        ("inf", "velocity='inf'"),
        ("fast", "velocity='fast'"),
    ],
)
def test_bad_urdf_velocity_names_its_line(tmp_path, cli, velocity, fragment):
    urdf = urdf_with_velocity(tmp_path, velocity)
    scene = write(tmp_path, "version: 1\narm:\n  urdf: r.urdf\n  tip_link: l2\ngoals:\n  - [0.2, 0.1, 0.3]\n")
    with pytest.raises(SceneError) as info:
        load_scene(scene)
    assert info.value.file == str(urdf) and info.value.problems[0].line == 6, info.value.report()
    result = cli("validate", scene)
    assert result.exit_code == 2 and f"{urdf}:6: " in result.stderr and fragment in result.stderr, result.stderr


def test_off_path_zero_velocity_is_no_error(tmp_path):
    """A gripper's velocity="0" off the arm's path (common in real files) does not stop the arm."""
    urdf_with_velocity(tmp_path, "0", joint="grip")
    scene = write(tmp_path, "version: 1\narm:\n  urdf: r.urdf\n  tip_link: l2\ngoals:\n  - [0.2, 0.1, 0.3]\n")
    speed, _, _ = rates_deg(scene.read_text(), tmp_path)
    np.testing.assert_allclose(speed, [np.degrees(1.0), URDF_SPEED])


# ------------------------------------------------------------ defaults and units


def test_link_arm_defaults_use_the_scenes_own_fps(tmp_path):
    """max_joint_step x render.fps, whatever fps the frames are sampled at (run --fps)."""
    for fps in (None, 60.0):
        speed, acceleration, jerk = rates_deg(scene_text(""), tmp_path, fps=fps)
        np.testing.assert_allclose(speed, 5 * 24.0)
        np.testing.assert_allclose(acceleration, LINK_ACCELERATION_PER_SPEED * 5 * 24.0)
        assert jerk is None


def test_scene_values_become_radians_once(tmp_path):
    text = scene_text(
        "max_joint_speed: [90, 45, 30]\n  max_joint_acceleration: 400\n  max_joint_jerk: [4000, 5000, 6000]"
    )
    rates = scene_to_problem(load_scene(write(tmp_path, text)).model).rates
    np.testing.assert_allclose(rates.speed, [np.pi / 2, np.pi / 4, np.pi / 6], rtol=1e-15)
    np.testing.assert_allclose(rates.acceleration, np.full(3, 400 * np.pi / 180), rtol=1e-15)
    np.testing.assert_allclose(rates.jerk, np.array([4000, 5000, 6000]) * np.pi / 180, rtol=1e-15)
    speed_only = rates_deg(scene_text("max_joint_speed: 50"), tmp_path)
    np.testing.assert_allclose(speed_only[1], LINK_ACCELERATION_PER_SPEED * 50)  # 4 x the scene's speed


FRANKA_ACCELERATION = [15, 7.5, 10, 12.5, 15, 20, 20]  # rad/s^2, frankaemika.github.io/docs/control_parameters.html
FRANKA_JERK = [7500, 3750, 5000, 6250, 7500, 10000, 10000]  # rad/s^3, the same page


def test_bundled_robots_published_limits(tmp_path):
    panda = scene_to_problem(load_scene(write(tmp_path, scene_text("", ROBOT, "panda"))).model).rates
    np.testing.assert_allclose(panda.speed, [2.175] * 4 + [2.61] * 3)  # the URDF's, Franka's own
    np.testing.assert_allclose(panda.acceleration, FRANKA_ACCELERATION)
    assert panda.jerk is None  # jerk-bounded only when the scene asks
    jerk = scene_to_problem(
        load_scene(write(tmp_path, scene_text("max_joint_jerk: robot", ROBOT, "panda"))).model
    ).rates.jerk
    np.testing.assert_allclose(jerk, FRANKA_JERK)
    ur5 = rates_deg(scene_text("", ROBOT, "ur5"), tmp_path)
    np.testing.assert_allclose(ur5[0], 180.0)
    np.testing.assert_allclose(ur5[1], np.degrees(5.0))
    iiwa = rates_deg(scene_text("", ROBOT, "iiwa"), tmp_path)  # the datasheet's, not the URDF's placeholder 10 rad/s
    np.testing.assert_allclose(iiwa[0], [98, 98, 100, 130, 140, 180, 180])
    np.testing.assert_allclose(iiwa[1], LINK_ACCELERATION_PER_SPEED * iiwa[0])  # KUKA publishes none


@pytest.mark.parametrize("name", ROBOTS)
def test_robot_yaml_rates_are_whole_and_sourced(name):
    robot = bundled_robot(name)
    joints = len(published_joint_names(name))
    assert scene_to_problem(load_scene_of(name)).arm.joint_names == published_joint_names(name)
    for field, rate in robot.rates:
        assert rate.unit in RATE_UNITS[field]
        assert len(rate.values) == joints and all(v > 0 for v in rate.values)
        assert len(rate.source) > 40 and ("http" in rate.source or "/" in rate.source), rate.source


def load_scene_of(robot: str):
    from armanim.scene import scene_model

    return scene_model({"version": 1, "arm": {"robot": robot}, "goals": [[0.4, 0.1, 0.4]]})


# ------------------------------------------------------------ notes


def test_limits_above_the_robots_are_noted_not_refused(tmp_path, cli):
    text = scene_text("max_joint_speed: 200\n  max_joint_acceleration: [300, 300, 300, 300, 300, 100]", ROBOT, "ur5")
    path = write(tmp_path, text)
    result = cli("validate", path)
    assert result.exit_code == 0, result.output
    notes = [line for line in result.stderr.splitlines() if line.startswith("note: ")]
    assert f"note: {path}:4: arm.max_joint_speed: 200 deg/s is above the robot's own limit for joints 1-6" in notes[0]
    assert (
        f"note: {path}:5: arm.max_joint_acceleration: is above the robot's own limit for joints 1-5 (shoulder_pan_joint 300 > 286.5"
        in notes[1]
    )
    assert len(notes) == 2


@pytest.mark.parametrize("rates", ["", "max_joint_speed: 100\n  max_joint_acceleration: 200", "max_joint_jerk: robot"])
def test_limits_within_the_robots_have_no_notes(tmp_path, rates):
    assert rate_notes(load_scene(write(tmp_path, scene_text(rates, ROBOT, "panda"))).model) == []


def test_link_arms_and_unknown_urdf_speeds_have_no_notes(tmp_path):
    assert rate_notes(load_scene(write(tmp_path, scene_text("max_joint_speed: 10000"))).model) == []
    scene = write(
        tmp_path,
        f"version: 1\narm:\n  urdf: {TORTURE}\n  base_link: world\n  tip_link: tool\n"
        "  max_joint_speed: [500, 60, 60, 60]\ngoals:\n  - [0.3, 0.1, 0.3]\n",
    )
    notes = rate_notes(load_scene(scene).model)
    assert len(notes) == 1 and "joints 2-4" in notes[0][1] and "spin" not in notes[0][1]  # spin gives no velocity


def test_summary_lists_the_rate_notes(tmp_path):
    from armanim.motion.trajectory import solve_trajectory
    from armanim.output.summary import summary_dict

    scene = load_scene(write(tmp_path, scene_text("max_joint_speed: 150", ROBOT, "panda")))
    problem = scene_to_problem(scene.model)
    solution = solve_trajectory(problem)
    summary = summary_dict(
        problem, solution, name="s", scene_file="scene.yaml", sha256="0", rate_notes=rate_note_lines(scene.model)
    )
    assert len(summary["rate_notes"]) == 1
    assert summary["rate_notes"][0].startswith(
        "arm.max_joint_speed: 150 deg/s is above the robot's own limit for joints 1-7"
    )
    assert json.loads(json.dumps(summary))["rate_notes"] == summary["rate_notes"]
    plain = summary_dict(problem, solution, name="s", scene_file="scene.yaml", sha256="0")
    assert plain["rate_notes"] == []


@pytest.mark.parametrize(
    ("rates", "field", "least"),
    [
        ("max_joint_speed: 1e-300", "arm.max_joint_speed", "raise it to at least 2.4e-05 deg/s"),
        ("max_joint_speed: [1e-9, 300, 300]", "arm.max_joint_speed", "24,000,000,000 frames at 24 fps"),
        ("max_joint_acceleration: 1e-12", "arm.max_joint_acceleration", "raise it to at least 2.4e-09 deg/s^2"),
        ("max_joint_jerk: 1e-300", "arm.max_joint_jerk", "raise it to at least 4.5e-13 deg/s^3"),
    ],
)
def test_rates_too_slow_for_the_frame_limit_are_refused_at_validate(tmp_path, cli, rates, field, least):
    """Issue 50, item 11: a rate under which moving a joint one degree takes more frames than
    the limit was refused only by run, without a line, and a tiny jerk was blamed on the speed.
    Now validate names the field that is too slow, with its line and the least value that fits."""
    message = rejected(tmp_path, cli, scene_text(rates), field, RATE_LINE, "is too slow for the frame limit", least)
    assert message.count("too slow") == 1  # a default made from the speed is not named again


@pytest.mark.parametrize(
    ("rates", "field", "fragments", "advised"),
    [
        (
            "max_joint_jerk: 1.0e-6",
            "arm.max_joint_jerk",
            (
                "with arm.max_joint_speed and arm.max_joint_acceleration as they are",
                "raise it to at least 0.024 deg/s^3",
            ),
            "max_joint_jerk: 0.024",
        ),
        (
            "max_joint_speed: 3.0e-5\n  max_joint_acceleration: 3.0e-9",
            "arm.max_joint_speed",
            ("with arm.max_joint_acceleration as they are", "1,040,000 frames", "raise it to at least 3.3e-05 deg/s"),
            "max_joint_speed: 3.3e-5\n  max_joint_acceleration: 3.0e-9",
        ),
    ],
)
def test_rates_each_fitting_alone_but_not_together_are_refused_at_validate(
    tmp_path, cli, rates, field, fragments, advised
):
    """Campaign 10: each rate passed its own floor, so validate said ok, and run refused the clock
    (``max_joint_jerk: 1e-6``, a million times its floor alone, made 7.2e10 frames: the clock
    smooths with a window of 2 a / j; a speed and an acceleration each near its floor, the ramps
    added to the cruise). The smallest move is timed as the clock times it, the three together,
    and the value advised fits."""
    rejected(tmp_path, cli, scene_text(rates), field, RATE_LINE, "is too slow for the frame limit", *fragments)
    result = cli("validate", write(tmp_path, scene_text(advised), "fixed.yaml"))
    assert result.exit_code == 0, result.output


def test_a_clock_too_long_at_run_names_the_field_and_its_line(tmp_path, cli):
    """Rates that pass validate, but not for this motion: run says the field with its line, and
    names --fps only when one was given."""
    scene = write(tmp_path, scene_text("max_joint_speed: 1e-4"))
    result = cli("run", scene, "--no-video", "--quiet", "--out", tmp_path / "o")
    assert result.exit_code == 2, result.output
    assert f"{scene}:{RATE_LINE}: arm.max_joint_speed: the clock would make" in result.stderr, result.stderr
    assert "--fps" not in result.stderr
    faster = cli("run", scene, "--no-video", "--quiet", "--out", tmp_path / "o", "--fps", 48)
    assert faster.exit_code == 2 and "or lower --fps" in faster.stderr, faster.stderr


def test_a_prismatic_joint_s_rates_are_told_in_metres(tmp_path, cli):
    """Campaign 5: the rail of ur5_rail (m/s) was told in degrees: ``max_joint_speed: [1e-9, ...]``
    refused as ``5.72958e-08 deg/s ... moving a joint 1 degree``, and a speed above the rail's own
    noted as ``rail_joint 9 > 57.3`` (1 m/s read as radians). Both now in metres, the joint named."""
    slow = write(
        tmp_path,
        "version: 1\nname: rr\narm:\n  robot: ur5_rail\n  max_joint_speed: [1e-9, 10, 10, 10, 10, 10, 10]\n"
        "goals: [[0.2, 0.45, 0.6]]\n",
    )
    result = cli("validate", slow)
    assert result.exit_code == 2, result.output
    assert (
        f"{slow}:5: arm.max_joint_speed: joint 1's 1e-09 m/s is too slow for the frame limit: moving it 0.0175 m "
        "from rest to rest would take 523,598,776 frames at 30 fps"
    ) in result.stderr, result.stderr
    assert "raise it to at least 5.3e-07 m/s" in result.stderr and "deg" not in result.stderr
    fast = write(
        tmp_path,
        "version: 1\nname: rr\narm:\n  robot: ur5_rail\n  max_joint_speed: [9, 10, 10, 10, 10, 10, 10]\n"
        "goals: [[0.2, 0.45, 0.6]]\n",
    )
    result = cli("validate", fast)
    assert result.exit_code == 0 and "(rail_joint 9 > 1 m/s: the URDF's <limit velocity>)" in result.stderr, (
        result.stderr
    )
