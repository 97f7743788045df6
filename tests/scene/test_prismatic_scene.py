"""A prismatic joint on the arm's path, end to end (issue 52, item 3): the bundled rail robot's
scene keeps every trajectory invariant with its rail in metres and m/s, its files say so (CSV
columns ``q1_m``/``dq1_m_s``, the JointTrajectory export), scene values of a prismatic joint are
metres, and the joints armanim cannot move on a path are clear errors naming them."""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from invariants import assert_trajectory_invariants

from armanim.errors import SceneError
from armanim.motion.kernels.plan import compiled_plan
from armanim.motion.solvers import solver_method
from armanim.output.csvfile import read_trajectory_csv
from armanim.runs.pipeline import timed_solution
from armanim.runs.reload import load_run
from armanim.scene import load_scene, scene_model, scene_to_problem
from armanim.scene.checks import scene_problems

ROOT = Path(__file__).resolve().parents[2]
RAIL_SCENE = ROOT / "scenes" / "ur5-rail.yaml"


@pytest.fixture(scope="module", params=["compiled", "numpy"])
def rail_run(request):
    """The rail scene's run by the compiled frames (as armanim runs it) and by the numpy ones (their oracle)."""
    scene = load_scene(RAIL_SCENE)
    problem = scene_to_problem(scene.model)
    frames = compiled_plan(problem, solver_method(problem.solver.method), None, "frame")
    assert (
        frames is not None
    ) == problem.tunables.ik.compiled_frames  # a prismatic joint runs compiled, as a revolute one
    if request.param == "numpy":
        ik = replace(problem.tunables.ik, compiled=False, compiled_frames=False)
        problem = replace(problem, tunables=replace(problem.tunables, ik=ik))
    else:
        assert frames is not None
    return problem, timed_solution(scene, problem, problem.fps)


def test_the_rail_scene_keeps_every_invariant_with_its_rail_in_metres(rail_run):
    problem, solution = rail_run
    assert problem.arm.prismatic.tolist() == [True] + [False] * 6
    assert problem.limits.lower[0] == -1.25 and problem.limits.upper[0] == 1.25  # metres, as the URDF gives them
    assert problem.rates.speed[0] == 1.0  # m/s: the URDF's <limit velocity>, not a radian conversion
    assert_trajectory_invariants(problem, solution)
    traj = solution.trajectory
    assert solution.reached == len(problem.goals)
    rail = traj.phi[:, 0]
    assert rail.max() - rail.min() > 1.0  # the goals are farther apart than the UR5 alone reaches: the carriage travels
    assert np.abs(traj.velocity[:, 0]).max() <= 1.0 * (1 + 1e-9)  # never faster than 1 m/s
    # the tip moves with the carriage: its x follows the rail wherever the arm's own joints stand still
    still = np.all(np.abs(np.diff(traj.phi[:, 1:], axis=0)) < 1e-12, axis=1) & (np.abs(np.diff(rail)) > 1e-6)
    np.testing.assert_allclose(np.diff(traj.tip[:, 0])[still], np.diff(rail)[still], atol=1e-12)


def test_the_rail_runs_files_give_the_rail_in_metres(cli, tmp_path):
    assert cli("run", RAIL_SCENE, "--out", tmp_path, "--no-video", "--quiet").exit_code == 0
    folder = tmp_path / "ur5-rail"
    table = read_trajectory_csv(folder / "trajectory.csv")
    assert table.columns[3:5] == ("q1_m", "phi2_deg") and "dq1_m_s" in table.columns and "dphi2_deg_s" in table.columns
    assert table.slides.tolist() == [True] + [False] * 6
    rail = table.column("q1_m")
    assert rail.min() >= -1.25 and rail.max() <= 1.25 and rail.max() - rail.min() > 1.0
    assert np.abs(table.column("dq1_m_s")).max() <= 1.0 * (1 + 1e-9)
    summary = json.loads((folder / "summary.json").read_text())
    assert summary["prismatic_joints"] == [1] and summary["max_joint_speed_deg_s"][0] == 1.0
    assert 0 < summary["max_slide_step_m"] <= 0.05
    assert cli("export", folder, "--format", "joint-trajectory").exit_code == 0
    message = json.loads((folder / "joint_trajectory.json").read_text())
    positions = np.array([p["positions"] for p in message["points"]])
    assert message["joint_names"][0] == "rail_joint"
    np.testing.assert_allclose(positions[:, 0], rail, atol=1e-12)  # metres, as ROS gives a prismatic joint
    np.testing.assert_allclose(positions[:, 1], np.radians(table.column("phi2_deg")), atol=1e-12)
    run = load_run(folder)  # a redraw reads the metres back as they were solved
    np.testing.assert_allclose(run.solution.trajectory.phi[:, 0], rail, atol=0)


def test_home_and_joint_goals_give_a_prismatic_joint_in_metres():
    scene = scene_model(
        {
            "version": 1,
            "arm": {"robot": "ur5_rail", "home": [0.4, 0, -100, 100, -90, -90, 0]},
            "goals": [{"joints": [-0.3, 10, -100, 100, -90, -90, 0]}],
        }
    )
    problem = scene_to_problem(scene)
    assert problem.home[0] == 0.4 and problem.home[1] == 0.0
    np.testing.assert_allclose(problem.goals[0].joints[:2], [-0.3, np.radians(10.0)])
    far = scene_model(
        {
            "version": 1,
            "arm": {"robot": "ur5_rail", "home": [2, 0, -100, 100, -90, -90, 0]},
            "goals": [{"joints": [0.1, 10, -100, 200, -90, -90, 0]}],
        }
    )  # a joint goal lies in [-360, 360]
    problems = dict(scene_problems(far))
    assert problems["arm.home[0]"].startswith("2 m is outside joint 1's limits arm.limits[0] = [-1.25, 1.25]")
    assert problems["goals[0].joints[3]"].startswith("200 deg is outside joint 4's limits")


RAIL_URDF = """<robot name="r">
  <link name="a"/><link name="b"/><link name="c"/><link name="d"/>
  <joint name="turn" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" velocity="1"/></joint>
  <joint name="slide" type="prismatic"><parent link="b"/><child link="c"/><origin xyz="0 0 0.5"/><axis xyz="1 0 0"/>
    {limit}{mimic}</joint>
  <joint name="tip" type="fixed"><parent link="c"/><child link="d"/><origin xyz="0.2 0 0"/></joint>
</robot>"""


def _urdf_scene(tmp_path, limit='<limit lower="0" upper="0.4" velocity="0.2"/>', mimic=""):
    (tmp_path / "r.urdf").write_text(RAIL_URDF.format(limit=limit, mimic=mimic))
    (tmp_path / "s.yaml").write_text("version: 1\narm: {urdf: r.urdf, tip_link: d}\ngoals: [[0.3, 0.1, 0.5]]\n")
    return tmp_path / "s.yaml"


def test_a_prismatic_joint_of_your_own_urdf_slides_in_metres(tmp_path):
    problem = scene_to_problem(load_scene(_urdf_scene(tmp_path)).model)
    assert problem.arm.prismatic.tolist() == [False, True] and problem.arm.stroke.tolist() == [0.0, 0.4]
    assert problem.rates.speed.tolist() == [1.0, 0.2] and problem.arm.reach == pytest.approx(
        0.5 + 0.2 + 0.4
    )  # the links and the stroke


def test_a_mimic_joint_on_the_path_is_an_error_naming_it(tmp_path):
    scene = _urdf_scene(tmp_path, mimic='<mimic joint="turn" multiplier="0.1"/>')
    with pytest.raises(SceneError, match=r"joint 'slide' between 'a' and 'd' mimics another joint") as error:
        load_scene(scene)
    assert "r.urdf:5" in str(error.value)  # its line


def test_a_prismatic_joint_without_room_to_slide_is_an_error_naming_it(tmp_path):
    with pytest.raises(SceneError, match=r"joint 'slide' .* is prismatic without room to slide"):
        load_scene(_urdf_scene(tmp_path, limit=""))


@pytest.fixture(scope="module")
def rail_problem():
    return scene_to_problem(scene_model({"version": 1, "arm": {"robot": "ur5_rail"}, "goals": [[0.5, 0.5, 0.5]]}))


def test_the_pairs_rows_on_a_rail_are_the_derivatives_of_their_gaps(rail_problem):
    """n . (J_A - J_B) of every enabled pair (the compiled rows, the prismatic joint's column read
    from the axes' kind column) against central differences of the measured gaps."""
    from armanim.arm.kinematics import forward
    from armanim.world import compiled
    from armanim.world.selfdistances import _pair_inputs, self_gaps, self_jacobians, self_rows

    problem = rail_problem
    arm, capsules, pairs = problem.arm, problem.capsules, problem.self_pairs
    rng = np.random.default_rng(52)
    for _ in range(3):
        phi = problem.home + rng.uniform(-0.6, 0.6, arm.n)
        pose = forward(arm, phi)
        gaps = self_gaps(pose, capsules, pairs)
        which = np.arange(len(pairs))
        rows = self_rows(arm, capsules, pose, pairs, gaps, which)
        jac = self_jacobians(arm, capsules, pose, pairs, gaps, which)
        np.testing.assert_allclose(np.einsum("pk,pkn->pn", gaps.normal, jac), rows, atol=1e-12)
        h = 1e-6
        numeric = np.stack(
            [
                (
                    self_gaps(forward(arm, phi + h * e), capsules, pairs).d
                    - self_gaps(forward(arm, phi - h * e), capsules, pairs).d
                )
                / (2 * h)
                for e in np.eye(arm.n)
            ],
            axis=1,
        )
        apart = gaps.d > 1e-3  # a touching pair's normal is not smooth
        np.testing.assert_allclose(rows[apart], numeric[apart], atol=1e-5)
        as_turning = np.empty_like(rows)  # the same rows with the rail read as a revolute joint: wrong
        inputs = list(_pair_inputs(arm, capsules, pose, pairs, gaps))
        inputs[1] = np.ascontiguousarray(inputs[1][:, :3])
        compiled.pair_rows(*inputs, gaps.normal, which, as_turning)
        assert np.abs(as_turning[apart, 0] - numeric[apart, 0]).max() > 0.01


def test_the_lever_arms_bound_how_far_a_rail_moves_any_capsule(rail_problem):
    from armanim.arm.capsules import capsule_ends
    from armanim.arm.kinematics import forward

    problem = rail_problem
    rng = np.random.default_rng(53)
    lower, upper = problem.limits.lower, problem.limits.upper
    for _ in range(20):
        phi = rng.uniform(np.maximum(lower, -3), np.minimum(upper, 3))
        step = rng.normal(0, 0.05, problem.arm.n) * (rng.uniform(size=problem.arm.n) < 0.5)
        a0, b0 = capsule_ends(problem.capsules, forward(problem.arm, phi))
        for s in np.linspace(0, 1, 5)[1:]:  # along the straight step, not just its end
            a1, b1 = capsule_ends(problem.capsules, forward(problem.arm, phi + s * step))
            moved = max(np.linalg.norm(a1 - a0, axis=1).max(), np.linalg.norm(b1 - b0, axis=1).max())
            assert moved <= np.abs(s * step) @ problem.lever_arms + 1e-12
    assert problem.lever_arms[0] == 1.0  # a metre of rail moves every point a metre


def test_the_planners_lever_rows_bound_how_far_a_rail_moves_each_capsule(rail_problem):
    """capsule_lever_rows (the planner's certificate): each capsule moves at most |dPhi| . its row."""
    from armanim.arm.capsules import capsule_ends, capsule_lever_rows
    from armanim.arm.kinematics import forward

    problem = rail_problem
    rows = capsule_lever_rows(problem.arm, problem.capsules)
    moving = problem.capsules.link >= 0
    assert np.all(rows[moving, 0] == 1.0) and np.all(
        rows[~moving] == 0.0
    )  # the rail moves every capsule it carries a metre a metre
    rng = np.random.default_rng(54)
    for _ in range(20):
        phi = rng.uniform(np.maximum(problem.limits.lower, -3), np.minimum(problem.limits.upper, 3))
        step = rng.normal(0, 0.05, problem.arm.n)
        a0, b0 = capsule_ends(problem.capsules, forward(problem.arm, phi))
        for s in np.linspace(0, 1, 5)[1:]:
            a1, b1 = capsule_ends(problem.capsules, forward(problem.arm, phi + s * step))
            moved = np.maximum(np.linalg.norm(a1 - a0, axis=1), np.linalg.norm(b1 - b0, axis=1))
            assert np.all(moved <= np.abs(s * step) @ rows.T + 1e-12)


def test_a_link_before_a_slide_ends_where_the_slide_starts(tmp_path):
    """A joint-to-joint capsule whose next joint is prismatic is the fixed link, in its own frame: its
    end stays put as the next joint slides (and the slide's Jacobian column leaves it)."""
    from armanim.arm.capsules import capsule_ends, frame_capsules
    from armanim.arm.kinematics import Arm, forward

    arm = Arm(
        base=np.zeros(3),
        axes=np.array([[0, 0, 1.0], [1.0, 0, 0]]),
        offsets=np.array([[0, 0, 0.5], [0.2, 0, 0]]),
        prismatic=np.array([False, True]),
    )
    caps = frame_capsules(arm, [0, 1], np.zeros((2, 3)), arm.offsets, [0.05, 0.05])
    assert caps.joint_segment.tolist() == [False, True]
    a, b = capsule_ends(caps, forward(arm, np.array([0.0, 0.3])))
    np.testing.assert_allclose(b[0], [0, 0, 0.5]) and np.testing.assert_allclose(a[1], [0.3, 0, 0.5])
