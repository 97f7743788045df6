"""URDF arms: the chain against pinocchio (an independent URDF implementation), derivatives
against finite differences, every broken file a clear FILE:LINE message, and the trajectory
invariants on random Panda and UR5 scenes."""

from __future__ import annotations

import shutil
import time
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from invariants import assert_trajectory_invariants, small_planning_budget
from strategies import robot_problems

from armanim.arm.capsules import capsule_point, capsule_point_jacobian
from armanim.arm.chain import serial_chain, transform
from armanim.arm.kinematics import forward, numeric_jacobian, tip_jacobian
from armanim.errors import SceneError
from armanim.motion.trajectory import solve_trajectory
from armanim.output.csvfile import trajectory_csv_text
from armanim.scene import load_scene, scene_to_problem
from armanim.scene.robots import ROBOTS, bundled_robot
from armanim.scene.urdf import chain_joints, parse_urdf, read_urdf

HERE = Path(__file__).resolve().parents[1]
TORTURE = HERE / "urdf" / "torture.urdf"
CASES = [(TORTURE, "world", "tool")] + [
    (bundled_robot(r).urdf, bundled_robot(r).base_link, bundled_robot(r).tip_link) for r in ROBOTS
]


def chain_of(path, base, tip, mount=None, tool=None):
    robot = read_urdf(Path(path))
    return serial_chain(
        np.eye(4) if mount is None else mount, chain_joints(robot, base, tip), np.eye(4) if tool is None else tool
    )


def tip_transform(arm, phi):
    """The tool frame as a 4x4: FK's last joint frame turned by the tip's offset rotation."""
    pose = forward(arm, phi)
    t = np.eye(4)
    t[:3, :3] = pose.frames[-1] @ arm.turns[-1]
    t[:3, 3] = pose.tip
    return t


@pytest.mark.parametrize(("path", "base", "tip"), CASES, ids=lambda v: Path(v).stem if isinstance(v, Path) else None)
def test_fk_and_jacobian_match_pinocchio(path, base, tip):
    pin = pytest.importorskip("pinocchio")
    arm = chain_of(path, base, tip).arm
    model = pin.buildModelFromUrdf(str(path))
    data = model.createData()
    frame = model.getFrameId(tip)
    joints = [model.joints[model.getJointId(name)] for name in arm.joint_names]
    rng = np.random.default_rng(20251201)
    for _ in range(8):
        phi = rng.uniform(-np.pi, np.pi, arm.n)
        q = pin.neutral(model)
        for j, angle in zip(joints, phi):
            q[j.idx_q : j.idx_q + j.nq] = (
                [np.cos(angle), np.sin(angle)] if j.nq == 2 else [angle]
            )  # continuous: (cos, sin)
        pin.framesForwardKinematics(model, data, q)
        np.testing.assert_allclose(tip_transform(arm, phi), data.oMf[frame].homogeneous, atol=1e-12, rtol=0)
        jac = pin.computeFrameJacobian(model, data, q, frame, pin.LOCAL_WORLD_ALIGNED)[:3]
        np.testing.assert_allclose(
            tip_jacobian(arm, forward(arm, phi)), jac[:, [j.idx_v for j in joints]], atol=1e-12, rtol=0
        )


def test_torture_chain_reads_the_traps_right():
    robot = read_urdf(TORTURE)
    assert robot.joints["noaxis"].axis.tolist() == [1.0, 0.0, 0.0]  # URDF's default axis
    arm = chain_of(TORTURE, "world", "tool").arm
    assert arm.joint_names == ("spin", "skew", "noaxis", "wrist")  # l3 has two children: the tip's branch is taken
    np.testing.assert_allclose(np.linalg.norm(arm.axes, axis=1), 1.0)  # "0 1 1" and "0 0 -2" normalised
    np.testing.assert_allclose(arm.axes[3], [0, 0, -1])


def test_mount_and_tool_move_the_chain():
    mount, tool = transform([1, 2, 3], [0, 0, np.pi / 2]), transform([0, 0, 0.1])
    plain, placed = chain_of(TORTURE, "world", "tool").arm, chain_of(TORTURE, "world", "tool", mount, tool).arm
    phi = np.array([0.3, -0.4, 0.5, 0.6])
    expected = mount @ tip_transform(plain, phi) @ tool
    np.testing.assert_allclose(tip_transform(placed, phi), expected, atol=1e-12)


@pytest.mark.parametrize(("path", "base", "tip"), CASES[:3], ids=["torture", "panda", "ur5"])
def test_analytic_jacobians_match_finite_differences(path, base, tip):
    arm = chain_of(path, base, tip).arm
    phi = np.random.default_rng(3).uniform(-2, 2, arm.n)
    h = 1e-6
    central = lambda f: (f(phi + h * np.eye(arm.n)) - f(phi - h * np.eye(arm.n))).T / (2 * h)  # noqa: E731
    np.testing.assert_allclose(tip_jacobian(arm, forward(arm, phi)), central(lambda p: forward(arm, p).tip), atol=1e-8)
    assert (
        np.abs(numeric_jacobian(lambda p: forward(arm, p).tip, phi) - tip_jacobian(arm, forward(arm, phi))).max() < 1e-5
    )


def test_capsule_point_jacobian_matches_finite_differences():
    problem = scene_to_problem(load_scene(_scene_file("ur5")).model)
    caps, arm = problem.capsules, problem.arm
    phi = problem.home + 0.3
    for c in range(len(caps)):
        numeric = numeric_jacobian(lambda p, c=c: capsule_point(caps, forward(arm, p), c, 0.7), phi, h=1e-7)
        np.testing.assert_allclose(capsule_point_jacobian(arm, caps, forward(arm, phi), c, 0.7), numeric, atol=1e-6)


def test_capsule_point_jacobians_in_one_call_are_each_the_one_alone():
    # the filter's rows and the cost's gradient take every pair's Jacobian in one call: bit for bit
    # what one point alone gives (the goldens depend on it), contiguous like it
    problem = scene_to_problem(load_scene(_scene_file("panda")).model)
    caps, arm = problem.capsules, problem.arm
    rng = np.random.default_rng(22)
    for _ in range(20):
        pose = forward(arm, rng.uniform(-2, 2, arm.n))
        which, t = rng.integers(0, len(caps), 6), rng.uniform(0, 1, 6)
        together = capsule_point_jacobian(arm, caps, pose, which, t)
        assert together.shape == (6, 3, arm.n) and together[0].flags.c_contiguous
        for k in range(6):
            np.testing.assert_array_equal(together[k], capsule_point_jacobian(arm, caps, pose, which[k], t[k]))
    assert capsule_point_jacobian(arm, caps, pose, which[:0], t[:0]).shape == (0, 3, arm.n)


_SCENES: dict = {}


def _scene_file(robot: str) -> Path:
    return (
        HERE.parent
        / "scenes"
        / {"panda": "panda-clutter.yaml", "ur5": "ur5-around.yaml", "iiwa": "iiwa-redundancy.yaml"}[robot]
    )


# ------------------------------------------------------------------ broken URDFs

ROBOT = b'<robot name="r"><link name="a"/><link name="b"/>%s</robot>'
JOINT = b'<joint name="j" type="revolute"><parent link="a"/><child link="b"/>%s<limit lower="-1" upper="1"/></joint>'


def broken(raw: bytes) -> str:
    with pytest.raises(SceneError) as info:
        parse_urdf(raw, "bad.urdf")
    return info.value.report()


@pytest.mark.parametrize(
    ("raw", "expected"),
    [
        (b"<robot><link name='a'>", "bad.urdf:1: is not well-formed XML"),
        (b"not xml at all", "is not well-formed XML"),
        (
            b'<?xml version="1.0"?>\n<!DOCTYPE r [<!ENTITY a "aaaa"><!ENTITY b "&a;&a;&a;&a;">]>\n<robot>&b;</robot>',
            "bad.urdf:2: declares a DTD",
        ),
        (b"<robot>&lol;</robot>", "undefined entity"),
        (
            ROBOT % b'<joint name="j" type="fixed"><parent link="a"/><child link="c"/></joint>',
            "child link 'c' is not defined",
        ),
        (ROBOT % (JOINT % b'<origin xyz="0 nan 0"/>'), "<origin>: xyz='0 nan 0' (expected 3 finite numbers"),
        (ROBOT % (JOINT % b'<axis xyz="0 0 0"/>'), "has the axis 0 0 0"),
        (
            ROBOT % b'<joint name="j" type="revolute"><parent link="a"/><child link="b"/></joint>',
            "is revolute but has no <limit",
        ),
        (
            b'<robot><link name="a"/><link name="b"/><link name="c"/><joint name="x" type="fixed"><parent link="a"/><child link="c"/></joint>'
            b'<joint name="y" type="fixed"><parent link="b"/><child link="c"/></joint></robot>',
            "link 'c' is the child of joints 'x' (line 1) and 'y'",
        ),
        (
            b'<robot><link name="r"/><link name="a"/><link name="b"/><joint name="x" type="fixed"><parent link="a"/><child link="b"/></joint>'
            b'<joint name="y" type="fixed"><parent link="b"/><child link="a"/></joint></robot>',
            "cycle through link",
        ),
        (b"<urdf/>", "the top element is <urdf>"),
        (b"<robot>" + b"<a>" * 40 + b"</a>" * 40 + b"</robot>", "nests elements more than 32 deep"),
    ],
)
def test_broken_urdf_is_one_clear_message(raw, expected):
    assert expected in broken(raw)


def test_no_path_and_unsupported_joints_name_the_joint_and_line():
    raw = (
        b'<robot name="r">\n<link name="a"/><link name="b"/><link name="c"/>\n'
        b'<joint name="p" type="planar"><parent link="a"/><child link="b"/><limit lower="0" upper="1"/></joint>\n'
        b'<joint name="q" type="continuous"><parent link="a"/><child link="c"/></joint>\n</robot>'
    )
    robot = parse_urdf(raw, "r.urdf")
    with pytest.raises(SceneError, match=r"r.urdf:3: joint 'p' between 'a' and 'b' is of type 'planar'"):
        chain_joints(robot, "a", "b")
    with pytest.raises(SceneError, match="no path from base_link 'b' down to tip_link 'c'"):
        chain_joints(robot, "b", "c")
    assert [j.name for j in chain_joints(robot, "a", "c")] == ["q"]  # the planar joint is off this path
    sliding = parse_urdf(
        raw.replace(b'type="planar"', b'type="prismatic"'), "r.urdf"
    )  # prismatic: on a path, in metres
    assert [(j.name, j.prismatic) for j in chain_joints(sliding, "a", "b")] == [("p", True)]


def test_ten_thousand_joints_are_refused_quickly(tmp_path):
    n = 10_000
    links = b"".join(b'<link name="l%d"/>' % i for i in range(n + 1))
    joints = b"".join(
        b'<joint name="j%d" type="continuous"><parent link="l%d"/><child link="l%d"/></joint>' % (i, i, i + 1)
        for i in range(n)
    )
    robot = parse_urdf(b"<robot>" + links + joints + b"</robot>", "big.urdf")
    with pytest.raises(SceneError, match="10,000 moving joints"):
        chain_joints(robot, "l0", f"l{n}")


def test_huge_file_is_refused_unread(tmp_path):
    path = tmp_path / "huge.urdf"
    with open(path, "wb") as f:
        f.truncate(100 * 1024 * 1024)  # 100 MB, sparse
    with pytest.raises(SceneError, match="huge.urdf"):
        read_urdf(path)


# ------------------------------------------------------------------ URDF arms in scenes


def _write(tmp_path, arm: str, goals="[[0.4, 0, 0.4]]") -> Path:
    path = tmp_path / "s.yaml"
    path.write_text(f"version: 1\narm:\n{arm}\ngoals: {goals}\n", encoding="utf-8")
    return path


@pytest.mark.parametrize(
    ("arm", "expected"),
    [
        ("  robot: pandaa", "s.yaml:2: arm: robot 'pandaa' is not bundled (expected one of: panda, ur5, iiwa"),
        ("  robot: panda\n  links: [1, 1]", "gives links and robot (expected exactly one"),
        ("  robot: panda\n  axes: [z]", "axes does not apply to a URDF arm"),
        (
            "  robot: panda\n  tip_link: panda_hand_tc",
            "tip_link 'panda_hand_tc' is not a link of robot panda's URDF (did you mean 'panda_hand_tcp'?",
        ),
        ("  robot: panda\n  home: [0, 0]", "arm.home: has 2 entries, the arm has 7 joints"),
        ("  urdf: missing.urdf", "missing.urdf: no such file"),
    ],
)
def test_bad_urdf_arm_in_a_scene(tmp_path, arm, expected):
    with pytest.raises(SceneError) as info:
        load_scene(_write(tmp_path, arm))
    assert expected in info.value.report()


@pytest.mark.parametrize("kind", ["missing", "a folder", "a FIFO", "too large"])
def test_a_urdf_file_that_cannot_be_read_is_reported_at_the_scene_s_field(tmp_path, kind):
    """Campaign 11: ``arm.urdf`` naming a folder, a FIFO or a missing file said only ``sub: is a
    folder, not a regular file (...)``: neither the scene, nor its line, nor the field, where an
    SRDF that cannot be read is reported at ``self_collision.srdf``. Now the same, at ``arm``."""
    import os

    from armanim.scene.urdf import MAX_URDF_BYTES

    urdf = tmp_path / "r.urdf"
    if kind == "a folder":
        urdf.mkdir()
    elif kind == "a FIFO":
        os.mkfifo(urdf)
    elif kind == "too large":
        with open(urdf, "wb") as handle:
            handle.truncate(MAX_URDF_BYTES + 1)
    with pytest.raises(SceneError) as info:
        load_scene(_write(tmp_path, "  urdf: r.urdf"))
    report = info.value.report()
    assert report.startswith(f"{tmp_path / 's.yaml'}:2: arm: urdf: {urdf}: "), report
    assert "expected a URDF robot description" in report or "may be at most" in report


def test_the_yaml_is_validated_without_reading_a_file_and_the_loader_reads_it_after(tmp_path):
    from armanim.scene import scene_model
    from armanim.scene.models import SceneModel

    data = {"version": 1, "arm": {"urdf": "missing.urdf"}, "goals": [[0.4, 0, 0.4]]}
    model = SceneModel.model_validate(data)  # no file is read by validation
    with pytest.raises(RuntimeError, match="file was not read"):
        _ = model.arm.joint_count
    with pytest.raises(ValueError, match="urdf: .*missing.urdf: no such file"):  # the scene's field, as an SRDF's
        scene_model(data, tmp_path)
    assert scene_model(data | {"arm": {"robot": "panda"}}).arm.joint_count == 7


def test_a_link_the_urdf_lacks_is_reported_with_the_yamls_own_problems(tmp_path):
    path = _write(tmp_path, "  robot: panda\n  tip_link: panda_hand_tc", goals="[[0.4, 0, 0.4]]\nsolver: {step: 2}")
    with pytest.raises(SceneError) as info:
        load_scene(path)
    lines = info.value.report().splitlines()
    assert any("s.yaml:2: arm: tip_link 'panda_hand_tc' is not a link" in line for line in lines)
    assert any("solver.step" in line for line in lines)


def test_own_urdf_relative_to_the_scene_with_auto_capsules_and_a_note(tmp_path):
    (tmp_path / "robots").mkdir()
    (tmp_path / "robots" / "t.urdf").write_bytes(TORTURE.read_bytes())
    scene = load_scene(_write(tmp_path, "  urdf: robots/t.urdf\n  tip_link: tool\n  width: 0.04", "[[0.3, 0.2, 0.6]]"))
    problem = scene_to_problem(scene.model)
    assert problem.arm.joint_names == ("spin", "skew", "noaxis", "wrist")
    caps = problem.capsules
    # l1's cylinder, l2's box, l2b's sphere (carried by skew); l3 (an empty <collision>) and l4 (none) fall back to joint-to-joint
    assert caps.names == ("l1", "l2", "l2b", "l3", "l4")
    np.testing.assert_allclose(caps.radius, [0.04, np.hypot(0.025, 0.03), 0.05, 0.02, 0.02])
    assert caps.joint_segment.tolist() == [False, False, False, True, True]
    assert any("links l3, l4 have no collision geometry" in n.message for n in scene.notes)
    with pytest.raises(SceneError, match=r"has 2 leaf links \(sidearm, tool\)"):
        load_scene(_write(tmp_path, "  urdf: robots/t.urdf"))


def test_a_run_of_your_own_urdf_renders_and_views_after_the_scene_folder_is_gone(tmp_path, cli):
    """The run folder keeps the robot (robot.urdf): `render` and `view` of a moved run need
    neither the scene's folder nor its relative `arm.urdf` path."""
    project = tmp_path / "project"
    (project / "robots").mkdir(parents=True)
    (project / "robots" / "t.urdf").write_bytes(TORTURE.read_bytes())
    scene = _write(project, "  urdf: robots/t.urdf\n  tip_link: tool\n  width: 0.04", "[[0.3, 0.2, 0.6]]")
    assert cli("run", scene, "--out", tmp_path / "out", "--no-video", "--quiet").exit_code == 0
    run = tmp_path / "out" / "s"
    assert (run / "robot.urdf").read_bytes() == TORTURE.read_bytes()
    moved = tmp_path / "elsewhere" / "s"
    moved.parent.mkdir()
    run.rename(moved)
    shutil.rmtree(project)
    result = cli("render", moved, "--out", tmp_path / "figures", "--size", "64x48", "--format", "gif", "--quiet")
    assert result.exit_code == 0, result.output
    assert (tmp_path / "figures" / "poster.png").stat().st_size > 0
    assert cli("view", moved).exit_code == 0
    assert (moved / "viewer.html").exists()


def test_the_run_keeps_the_urdf_it_solved_with_even_if_the_file_changes_meanwhile(tmp_path, cli, monkeypatch):
    """The robot.urdf of a run is the bytes that were read and solved with, not a second read
    of a file the user may be editing while the arm is solved."""
    import armanim.runs.pipeline as pipeline

    (tmp_path / "t.urdf").write_bytes(TORTURE.read_bytes())
    scene = _write(tmp_path, "  urdf: t.urdf\n  tip_link: tool\n  width: 0.04", "[[0.3, 0.2, 0.6]]")
    solve = pipeline.solve_trajectory

    def edited_while_solving(*args, **kwargs):
        (tmp_path / "t.urdf").write_text("<robot name='edited'/>")
        return solve(*args, **kwargs)

    monkeypatch.setattr(pipeline, "solve_trajectory", edited_while_solving)
    assert cli("run", scene, "--out", tmp_path / "out", "--no-video", "--quiet").exit_code == 0
    assert (tmp_path / "out" / "s" / "robot.urdf").read_bytes() == TORTURE.read_bytes()


# ------------------------------------------------------------------ motion


@settings(max_examples=6, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(robot_problems())
def test_robot_trajectories_keep_every_invariant(problem):
    assert_trajectory_invariants(problem, solve_trajectory(small_planning_budget(problem)))


def test_panda_run_is_byte_identical_on_rerun():
    problem = scene_to_problem(load_scene(_scene_file("panda")).model)
    first = trajectory_csv_text(solve_trajectory(problem).trajectory)
    assert trajectory_csv_text(solve_trajectory(problem).trajectory) == first


def test_unloaded_urdf_parse_is_fast_enough_to_guard_against_hangs():
    start = time.process_time()
    read_urdf(bundled_robot("panda").urdf)
    assert time.process_time() - start < 5.0  # ~5 ms unloaded: a hang guard, 1000x over


def test_robots_command_and_fk_robot_agree_with_the_chain():
    import json

    from typer.testing import CliRunner

    from armanim.cli import app

    runner = CliRunner()
    listed = runner.invoke(app, ["robots"])
    assert listed.exit_code == 0 and "panda_joint7" in listed.stdout and "shoulder_pan_joint" in listed.stdout
    home = "0,-45,0,-135,0,90,45"
    fk = runner.invoke(app, ["fk", "--robot", "panda", f"--angles={home}", "--json"])
    assert fk.exit_code == 0, fk.output
    problem = scene_to_problem(load_scene(_scene_file("panda")).model)
    np.testing.assert_allclose(json.loads(fk.stdout)["tip"], forward(problem.arm, problem.home).tip, atol=1e-12)
    bad = runner.invoke(app, ["fk", "--robot", "pand", "--angles", "0"])
    assert bad.exit_code == 2 and "robot 'pand' is not bundled" in bad.stderr
