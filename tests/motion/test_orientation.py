"""Goals with an orientation (issue 21): the rotation conventions, the pose error and its
Jacobian, every method reaching 6-D and tool-axis goals, and arms with too few joints."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from armanim.arm.chain import serial_chain
from armanim.arm.kinematics import Arm, angular_jacobian, forward, tool_rotation
from armanim.arm.rotations import (
    alignment_vector,
    axis_angle_rotation,
    quaternion_rotation,
    rotation_exp,
    rotation_log,
    rotation_quaternion,
    rotation_rpy,
    rpy_rotation,
)
from armanim.errors import SceneError
from armanim.motion.orientation import (
    Orientation,
    holds_orientation,
    orientation_angle,
    orientation_gradient,
    orientation_residual,
    orientation_task,
)
from armanim.scene import load_scene, scene_to_problem
from armanim.scene.urdf import chain_joints, read_urdf

RNG = np.random.default_rng(2112)
ROTATIONS = Rotation.random(40, random_state=2112)


# ------------------------------------------------------------------ conventions, against scipy


def test_rpy_is_urdfs_fixed_axis_convention():
    for rpy in RNG.uniform(-np.pi, np.pi, (20, 3)):
        expected = Rotation.from_euler("xyz", rpy).as_matrix()  # lower case: extrinsic x, then y, then z
        np.testing.assert_allclose(rpy_rotation(rpy), expected, atol=1e-12)
        np.testing.assert_allclose(rpy_rotation(rotation_rpy(rpy_rotation(rpy))), expected, atol=1e-12)


def test_quaternions_are_scalar_first_and_agree_with_scipy():
    for rot in ROTATIONS:
        xyzw = rot.as_quat()
        wxyz = np.roll(xyzw, 1) * np.sign(xyzw[3])
        np.testing.assert_allclose(quaternion_rotation(wxyz), rot.as_matrix(), atol=1e-12)
        np.testing.assert_allclose(rotation_quaternion(rot.as_matrix()), wxyz, atol=1e-12)
    batch = rotation_quaternion(ROTATIONS.as_matrix())
    assert batch.shape == (40, 4) and np.all(batch[:, 0] >= 0)


def test_exp_and_log_agree_with_scipy_at_every_angle_including_pi():
    vectors = ROTATIONS.as_rotvec()
    near_pi = RNG.normal(size=(10, 3))
    near_pi = near_pi / np.linalg.norm(near_pi, axis=1, keepdims=True) * (np.pi - RNG.uniform(0, 1e-6, (10, 1)))
    tiny = RNG.normal(size=(5, 3)) * 1e-9
    for v in np.concatenate([vectors, near_pi, tiny]):
        np.testing.assert_allclose(rotation_exp(v), Rotation.from_rotvec(v).as_matrix(), atol=1e-12)
        np.testing.assert_allclose(rotation_log(Rotation.from_rotvec(v).as_matrix()), v, atol=1e-8)
    np.testing.assert_allclose(rotation_log(ROTATIONS.as_matrix()), vectors, atol=1e-10)


def test_axis_angle_and_alignment():
    np.testing.assert_allclose(
        axis_angle_rotation([1, 1, 0], 0.7),
        Rotation.from_rotvec(0.7 * np.array([1, 1, 0]) / np.sqrt(2)).as_matrix(),
        atol=1e-12,
    )
    for _ in range(20):
        a, b = (v / np.linalg.norm(v) for v in RNG.normal(size=(2, 3)))
        r = alignment_vector(a, b)
        np.testing.assert_allclose(rotation_exp(r) @ a, b, atol=1e-12)
        assert abs(r @ a) < 1e-12  # never about the vector itself: the roll stays free
    z = np.array([0.0, 0, 1])
    np.testing.assert_allclose(rotation_exp(alignment_vector(z, -z)) @ z, -z, atol=1e-12)


URDF_FIXED = """<robot name="r">
  <link name="base"/><link name="l1"/><link name="tool"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/>
    <origin xyz="0 0 0.1"/><limit lower="-3" upper="3"/></joint>
  <joint name="fix" type="fixed"><parent link="l1"/><child link="tool"/><origin xyz="0.2 0 0" rpy="{rpy}"/></joint>
</robot>"""


def test_goal_rpy_means_what_a_urdf_fixed_joint_with_the_same_rpy_means(tmp_path):
    """A goal's rpy (degrees) and a URDF <origin rpy> (radians) are one convention: the tool frame
    of a chain ending in a fixed joint with that rpy is exactly the goal's rotation."""
    for degrees in ([180, 0, 90], [30, -45, 120], [-10, 80, 5]):
        path = tmp_path / "fixed.urdf"
        path.write_text(URDF_FIXED.format(rpy=" ".join(repr(float(v)) for v in np.radians(degrees))), encoding="utf-8")
        arm = serial_chain(np.eye(4), chain_joints(read_urdf(path), "base", "tool"), np.eye(4)).arm
        scene = tmp_path / "s.yaml"
        scene.write_text(
            f"version: 1\narm: {{urdf: fixed.urdf}}\ngoals: [{{position: [0.2, 0, 0.1], orientation: {{rpy: {degrees}}}}}]\n",
            encoding="utf-8",
        )
        goal = scene_to_problem(load_scene(scene).model).goals[0]
        tool = tool_rotation(arm, forward(arm, np.zeros(1)))
        np.testing.assert_allclose(goal.orientation.rotation, tool, atol=1e-12)
        wxyz = np.roll(Rotation.from_matrix(tool).as_quat(), 1)
        scene.write_text(
            f"version: 1\narm: {{urdf: fixed.urdf}}\ngoals: [{{position: [0.2, 0, 0.1], orientation: {{quaternion_wxyz: {wxyz.tolist()}}}}}]\n",
            encoding="utf-8",
        )
        goal = scene_to_problem(load_scene(scene).model).goals[0]
        assert orientation_angle(goal.orientation, tool) < 1e-7


# ------------------------------------------------------------------ the pose error and its Jacobian

NOTES = Arm.from_names([2, 5, 5, 5], base=(5, 5, 0))


def _six_joint_arm() -> Arm:
    """A 6-joint custom arm of links (z y y x y x: a spherical-ish wrist)."""
    return Arm.from_names([1.0, 2.0, 2.0, 0.5, 0.5, 0.3], axes=["z", "y", "y", "x", "y", "z"])


@pytest.mark.parametrize("kind", ["rotation", "axis"])
def test_orientation_gradient_is_exact_against_finite_differences(kind):
    arm = _six_joint_arm()
    for _ in range(5):
        goal = (
            Orientation(rotation=Rotation.random(random_state=RNG.integers(1 << 30)).as_matrix())
            if kind == "rotation"
            else Orientation(axis=RNG.normal(size=3))
        )
        phi = RNG.uniform(-2, 2, arm.n)
        r, grad = orientation_gradient(goal, arm, forward(arm, phi))

        def half_square(p, goal=goal):
            return 0.5 * np.sum(orientation_residual(goal, tool_rotation(arm, forward(arm, p))) ** 2, axis=-1)

        h = 1e-6
        numeric = np.array([(half_square(phi + h * e) - half_square(phi - h * e)) / (2 * h) for e in np.eye(arm.n)])
        if np.linalg.norm(r) < np.pi - 1e-3:
            np.testing.assert_allclose(grad, numeric, atol=1e-6)


@pytest.mark.parametrize("kind", ["rotation", "axis"])
def test_geometric_jacobian_is_the_derivative_of_the_error_at_the_goal(kind):
    """At the goal, d(B r)/dPhi = -B J_w exactly (J_r^-1(0) = I): the task Jacobian the solvers
    use; the Gauss-Newton Hessian of 1/2 |r|^2 then equals the finite-difference Hessian."""
    arm = _six_joint_arm()
    phi = RNG.uniform(-2, 2, arm.n)
    pose = forward(arm, phi)
    rot = tool_rotation(arm, pose)
    goal = Orientation(rotation=rot) if kind == "rotation" else Orientation(axis=rot[:, 2])
    _, jac = orientation_task(goal, arm, pose)
    h = 1e-6
    numeric = np.stack(
        [
            (
                orientation_task(goal, arm, forward(arm, phi + h * e))[0]
                - orientation_task(goal, arm, forward(arm, phi - h * e))[0]
            )
            / (2 * h)
            for e in np.eye(arm.n)
        ],
        -1,
    )
    rows = jac.shape[0]
    assert rows == (3 if kind == "rotation" else 2)
    np.testing.assert_allclose(numeric, -jac, atol=1e-7)

    def half_square(p):
        return 0.5 * np.sum(orientation_residual(goal, tool_rotation(arm, forward(arm, p))) ** 2)

    hess = np.array(
        [
            [
                (
                    half_square(phi + h * (a + b))
                    - half_square(phi + h * (a - b))
                    - half_square(phi - h * (a - b))
                    + half_square(phi - h * (a + b))
                )
                / (4 * h * h)
                for b in np.eye(arm.n)
            ]
            for a in np.eye(arm.n)
        ]
    )
    np.testing.assert_allclose(hess, jac.T @ jac, atol=1e-4)


def test_angular_jacobian_against_finite_differences_of_the_tool_frame():
    arm = _six_joint_arm()
    phi = RNG.uniform(-2, 2, arm.n)
    pose = forward(arm, phi)
    rot = tool_rotation(arm, pose)
    h = 1e-7
    for j, e in enumerate(np.eye(arm.n)):
        moved = tool_rotation(arm, forward(arm, phi + h * e))
        np.testing.assert_allclose(rotation_log(moved @ rot.T) / h, angular_jacobian(arm, pose)[:, j], atol=1e-6)


def test_which_arms_hold_an_orientation():
    six = _six_joint_arm()
    assert holds_orientation(six, Orientation(rotation=np.eye(3)))
    assert holds_orientation(six, Orientation(axis=np.array([0.0, 0, 1])))
    assert not holds_orientation(NOTES, Orientation(rotation=np.eye(3)))
    planar = Arm.from_names([1, 1, 1], axes=["z", "z", "z"], direction="x")
    assert not holds_orientation(planar, Orientation(axis=np.array([1.0, 0, 0])))


# ------------------------------------------------------------------ scene forms


def _scene(tmp_path, goals: str, solver: str = "") -> Path:
    path = tmp_path / "s.yaml"
    path.write_text(f"version: 1\narm: {{robot: panda}}\ngoals:\n{goals}\n{solver}", encoding="utf-8")
    return path


def test_the_three_orientation_forms_and_tool_axis_convert_to_radians(tmp_path):
    goals = (
        "  - {position: [0.5, 0.1, 0.3], orientation: {rpy: [180, 0, 90]}}\n"
        "  - {position: [0.4, -0.2, 0.3], orientation: {quaternion_wxyz: [0, 1, 0, 0.0001]}}\n"
        "  - {position: [0.4, 0.2, 0.4], orientation: {axis: [0, 0, 2], angle: 30}}\n"
        "  - {position: [0.3, 0.0, 0.5], tool_axis: [0, 0, -3]}\n"
        "  - [0.3, 0.0, 0.5]"
    )
    problem = scene_to_problem(load_scene(_scene(tmp_path, goals, "solver: {orientation_tolerance: 0.5}\n")).model)
    g = problem.goals
    np.testing.assert_allclose(
        g[0].orientation.rotation, Rotation.from_euler("xyz", np.radians([180, 0, 90])).as_matrix(), atol=1e-12
    )
    np.testing.assert_allclose(g[1].orientation.rotation, np.diag([1.0, -1, -1]), atol=1e-3)
    np.testing.assert_allclose(
        g[2].orientation.rotation, Rotation.from_rotvec([0, 0, np.radians(30)]).as_matrix(), atol=1e-12
    )
    np.testing.assert_allclose(g[3].orientation.axis, [0, 0, -1])
    assert g[4].orientation is None
    assert problem.solver.orientation_tolerance == pytest.approx(np.radians(0.5))
    assert problem.solver.orientation_weight == pytest.approx(0.25 * problem.arm.reach)


@pytest.mark.parametrize(
    ("goal", "expected"),
    [
        (
            "{position: [0.4, 0, 0.4], orientation: {quaternion_wxyz: [0, 0.9, 0, 0]}}",
            "s.yaml:4: goals[0].orientation: quaternion_wxyz has length 0.9",
        ),
        (
            "{position: [0.4, 0, 0.4], tool_axis: [0, 0, 0]}",
            "s.yaml:4: goals[0].tool_axis: tool_axis is the zero vector",
        ),
        (
            "{position: [0.4, 0, 0.4], orientation: {axis: [0, 0, 0], angle: 5}}",
            "s.yaml:4: goals[0].orientation: axis is the zero vector",
        ),
        (
            "{position: [0.4, 0, 0.4], tool_axis: [0, 0, 1], orientation: {rpy: [0, 0, 0]}}",
            "s.yaml:4: goals[0]: sets both orientation and tool_axis",
        ),
        (
            "{position: [0.4, 0, 0.4], orientation: {rpy: [0, 0, .inf]}}",
            "goals[0].orientation.rpy[2]: must be a finite number",
        ),
        (
            "{position: [0.4, 0, 0.4], orientation: {rpy: [0, 0, 0], axis: [0, 0, 1], angle: 3}}",
            "sets rpy and axis (expected exactly one",
        ),
        ("{position: [0.4, 0, 0.4], orientation: {axis: [0, 0, 1]}}", "axis and angle go together"),
    ],
)
def test_bad_orientations_are_clear_errors_with_field_and_line(tmp_path, goal, expected):
    with pytest.raises(SceneError) as info:
        load_scene(_scene(tmp_path, f"  - {goal}"))
    assert expected in info.value.report()


# ------------------------------------------------------------------ every method reaches pose goals

from dataclasses import replace  # noqa: E402

from armanim.motion.filter.clearance import within_limits  # noqa: E402
from armanim.motion.ik import solve_pose  # noqa: E402
from armanim.motion.orientation import orientation_rows  # noqa: E402
from armanim.motion.problem import Goal  # noqa: E402
from armanim.motion.trajectory import solve_trajectory  # noqa: E402
from armanim.output.csvfile import trajectory_csv_text  # noqa: E402
from armanim.output.summary import goal_report_dict  # noqa: E402
from armanim.scene import scene_model  # noqa: E402

METHODS = ["pinv", "dls", "newton", "gradient"]
ARMS = {
    "panda": {"robot": "panda"},
    "ur5": {"robot": "ur5"},
    "iiwa": {"robot": "iiwa"},
    "six": {"links": [1.0, 2.0, 2.0, 0.5, 0.5, 0.3], "axes": ["z", "y", "y", "x", "y", "z"]},
}


def _problem(arm: dict, method: str, **solver):
    scene = scene_model(
        {
            "version": 1,
            "arm": arm,
            "goals": [[0.3, 0.0, 0.4]],
            "solver": {"method": method, "tolerance": 1e-3, **solver},
        }
    )
    return scene_to_problem(scene)


def _free_pose_goal(problem, seed: int, kind: str) -> Goal:
    """A goal made from the tool frame of a random free pose inside the limits."""
    rng = np.random.default_rng(seed)
    lo = np.where(problem.limits.limited, problem.limits.lower, -np.pi)
    hi = np.where(problem.limits.limited, problem.limits.upper, np.pi)
    while True:
        phi = rng.uniform(lo + 0.2 * (hi - lo), hi - 0.2 * (hi - lo))
        pose = forward(problem.arm, phi)
        if within_limits(problem, phi[None])[0] and pose.tip[2] > 0.1 * problem.arm.reach:
            break
    rot = tool_rotation(problem.arm, pose)
    orientation = Orientation(rotation=rot) if kind == "rotation" else Orientation(axis=rot[:, 2])
    return Goal(pose.tip.copy(), 0.0, orientation)


@pytest.mark.parametrize("arm", list(ARMS))
@pytest.mark.parametrize("method", METHODS)
def test_every_method_reaches_a_pose_goal_from_a_free_pose(arm, method):
    problem = _problem(ARMS[arm], method)
    goals = (_free_pose_goal(problem, 7, "rotation"), _free_pose_goal(problem, 8, "axis"))
    solution = solve_trajectory(replace(problem, goals=goals))
    for goal in solution.goals:
        assert goal.reached, (goal.reason, goal.final_distance, np.degrees(goal.final_orientation_error))
        assert goal.final_distance < 1e-3 and np.degrees(goal.final_orientation_error) < 1.0
    assert np.all(within_limits(problem, solution.trajectory.phi))


@pytest.mark.parametrize("method", METHODS)
def test_solve_pose_meets_position_and_orientation(method):
    problem = _problem(ARMS["panda"], method)
    goal = _free_pose_goal(problem, 11, "rotation")
    result = solve_pose(problem, goal.position, problem.home, orientation=goal.orientation)
    assert result.converged and result.distance < 1e-3 and np.degrees(result.orientation_error) < 1.0


def test_tool_axis_goals_leave_the_roll_free():
    """Turning a tool frame about its own z changes nothing of a tool-axis goal's error, and the
    task has only the two rows perpendicular to the tool's z."""
    problem = _problem(ARMS["ur5"], "pinv")
    goal = _free_pose_goal(problem, 3, "axis")
    rot = rotation_exp(RNG.normal(size=3))
    goal = Orientation(axis=rot[:, 2])
    for roll in np.linspace(-np.pi, np.pi, 9):
        assert orientation_angle(goal, rot @ rotation_exp(np.array([0.0, 0.0, roll]))) < 1e-9
    rows = orientation_rows(goal, rot)
    assert rows.shape == (2, 3) and np.allclose(rows @ rot[:, 2], 0.0)
    # reached from home, the roll ends wherever the motion took it, not at the source pose's
    goal = _free_pose_goal(problem, 3, "axis")
    end = solve_trajectory(replace(problem, goals=(goal,)))
    assert end.goals[0].reached


@pytest.mark.parametrize("method", METHODS)
def test_four_joints_reach_the_position_and_report_the_orientation_unreachable(method):
    scene = scene_model(
        {
            "version": 1,
            "arm": {"links": [2, 5, 5, 5], "base": [5, 5, 0]},
            "goals": [{"position": [12, 5, 8], "orientation": {"rpy": [90, 0, 45]}}, [5, 12, 9]],
            "solver": {"method": method},
        }
    )
    problem = scene_to_problem(scene)
    solution = solve_trajectory(problem)
    first, second = solution.goals
    assert not first.reached and first.reason == "orientation_unreachable"
    assert first.final_distance < problem.solver.tolerance
    assert 85.0 < np.degrees(first.final_orientation_error) < 115.0  # at least 90 degrees can never go
    report = goal_report_dict(first)
    assert report["final_orientation_error_deg"] == pytest.approx(np.degrees(first.final_orientation_error))
    assert goal_report_dict(second)["final_orientation_error_deg"] is None and second.reached


def test_planar_arm_with_a_tool_axis_out_of_its_plane():
    scene = scene_model(
        {
            "version": 1,
            "arm": {"links": [1, 1, 1], "axes": ["z", "z", "z"], "direction": "x"},
            "goals": [{"position": [1.5, 1.0, 0.0], "tool_axis": [1, 0, 1]}],
            "solver": {"planner": "off"},
        }
    )
    goal = solve_trajectory(scene_to_problem(scene)).goals[0]
    assert goal.reason == "orientation_unreachable" and np.degrees(goal.final_orientation_error) == pytest.approx(
        45.0, abs=0.5
    )


def test_pose_goal_runs_are_byte_identical_and_log_the_tool_frame():
    problem = _problem(ARMS["panda"], "dls")
    goals = (_free_pose_goal(problem, 5, "rotation"), Goal(np.array([0.3, 0.2, 0.5]), 0.0))
    problem = replace(problem, goals=goals)
    first = trajectory_csv_text(solve_trajectory(problem).trajectory)
    assert trajectory_csv_text(solve_trajectory(problem).trajectory) == first
    lines = first.splitlines()
    header = lines[0].split(",")
    assert header[-16:-11] == [
        "qw",
        "qx",
        "qy",
        "qz",
        "orientation_error_deg",
    ]  # then self_clearance, self_pair, path_s, path_error, 7 velocities
    rows = [dict(zip(header, line.split(","))) for line in lines[1:]]
    for row in rows:
        phi = np.radians([float(row[f"phi{i}_deg"]) for i in range(1, 8)])
        rot = tool_rotation(problem.arm, forward(problem.arm, phi))
        np.testing.assert_allclose(
            quaternion_rotation([float(row[c]) for c in ("qw", "qx", "qy", "qz")]), rot, atol=1e-12
        )
        assert (row["orientation_error_deg"] == "") == (row["goal"] == "1")


# ------------------------------------------------------------------ pictures


def test_pictures_draw_triads_and_the_caption_the_angle_only_with_orientations(tmp_path):
    from matplotlib.image import imread

    from armanim.render.overlay.caption import frame_caption
    from armanim.render.pictures.pose import render_pose_png
    from armanim.scene import default_render_settings

    problem = _problem(ARMS["panda"], "pinv")
    oriented = replace(problem, goals=(_free_pose_goal(problem, 2, "rotation"), _free_pose_goal(problem, 4, "axis")))
    plain = replace(oriented, goals=tuple(replace(g, orientation=None) for g in oriented.goals))
    settings = default_render_settings(size=(160, 120))
    for name, p in (("with", oriented), ("without", plain)):
        render_pose_png(p, p.home, settings, tmp_path / f"{name}.png", title="t")
    assert not np.array_equal(imread(tmp_path / "with.png"), imread(tmp_path / "without.png"))
    solution = solve_trajectory(replace(oriented, goals=oriented.goals[:1]))
    assert " deg   " in frame_caption(solution.trajectory, 1, 1, "moving")
    assert "angle" not in frame_caption(
        solve_trajectory(replace(plain, goals=plain.goals[:1])).trajectory, 1, 1, "moving"
    )


def test_viewer_data_carries_orientations_only_for_oriented_runs():
    from armanim.render.viewer.data import viewer_data
    from armanim.scene import default_render_settings

    problem = _problem(ARMS["ur5"], "pinv")
    oriented = replace(problem, goals=(_free_pose_goal(problem, 2, "rotation"), _free_pose_goal(problem, 4, "axis")))
    solution = solve_trajectory(oriented)
    data = viewer_data(oriented, solution.trajectory, solution.goals, default_render_settings(), title="o")
    frames = solution.trajectory.frames
    assert len(data["orientation"]["quaternion_wxyz"]) == 4 * frames and len(data["orientation"]["angle_deg"]) == frames
    assert "rotation" in data["goals"][0] and "tool_axis" in data["goals"][1]
    plain = replace(oriented, goals=tuple(replace(g, orientation=None) for g in oriented.goals))
    solution = solve_trajectory(plain)
    data = viewer_data(plain, solution.trajectory, solution.goals, default_render_settings(), title="p")
    assert "orientation" not in data and "rotation" not in data["goals"][0]


def test_pose_goal_trajectories_keep_every_invariant():
    from invariants import assert_trajectory_invariants

    scene = scene_model(
        {
            "version": 1,
            "arm": {"links": [2, 5, 5, 5], "base": [5, 5, 0]},
            "goals": [
                {"position": [12, 5, 8], "orientation": {"rpy": [90, 0, 45]}},
                {"position": [10, 8, 9], "tool_axis": [1, 0, 0]},
                [5, 12, 9],
            ],
            "obstacles": [{"center": [9, 9, 12], "radius": 1.0}],
        }
    )
    problem = scene_to_problem(scene)
    assert_trajectory_invariants(problem, solve_trajectory(problem))


@pytest.mark.parametrize("method", ["pinv", "dls"])
def test_an_arm_whose_position_takes_every_joint_turns_nothing_for_the_rotation(method):
    # a 2-joint planar arm with a 6-D goal: the position's null space leaves the rotation task only
    # rounding; inverting that proposed 1e17 rad in directions rounding set (the joint-step cap
    # hid it). The step is the position's alone, and so is the projector the pushes go through.
    from armanim.arm.linalg import pseudo_inverse
    from armanim.motion.problem import Problem
    from armanim.motion.solvers import linear
    from armanim.motion.solvers.common import arm_state
    from armanim.scene import default_solver_settings, unlimited_limits
    from armanim.world.obstacles import Obstacles

    goal = Goal(
        np.array([1.2, 0.9, 0.0]),
        0.0,
        Orientation(rotation=Rotation.from_euler("xyz", [10.0, 20.0, 30.0], degrees=True).as_matrix()),
    )
    problem = Problem(
        arm=Arm.from_names([1.0, 1.0], axes=["z", "z"], direction="x"),
        half_width=0.05,
        home=np.radians([20.0, 30.0]),
        limits=unlimited_limits(2),
        obstacles=Obstacles.none(),
        goals=(goal,),
        solver=default_solver_settings(method=method),
        fps=30.0,
    )
    state = arm_state(problem, problem.home)
    jac = linear.jacobian_of_tip(problem, state.phi, state.pose)
    step, projector = linear.orientation_in_null_space(
        problem, state, goal.orientation, jac, np.zeros(2), pseudo_inverse
    )
    assert np.array_equal(step, np.zeros(2))
    assert np.abs(projector).max() < 1e-12  # the tip's null space: nothing
    with_rotation = linear.linear_step(problem, state, goal.position, pseudo_inverse, goal.orientation).dphi
    without = linear.linear_step(problem, state, goal.position, pseudo_inverse).dphi
    assert np.allclose(with_rotation, without, rtol=0, atol=1e-12)
