"""Goals passed without stopping (``blend``, issue 53): each via goal passed within its radius by
forward kinematics measured again, every frame within the rate limits (finite differences),
clearance and self-clearance held (the invariants' oracles), the clock's duration on the
blended path against toppra's, and a run with ``blend`` never longer than the same run at rest."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from invariants import assert_trajectory_invariants, small_planning_budget
from runfolders import assert_reruns_byte_identical
from strategies import joint_goal_problems
from toppra_oracle import toppra_trajectory

from armanim.motion.timing.clock import time_optimal
from armanim.motion.timing.jointpath import joint_path
from armanim.motion.timing.retime import at_fps, retime, via_paths
from armanim.motion.trajectory import solve_trajectory
from armanim.scene import scene_model
from armanim.scene.convert import scene_to_problem

SCENES = Path(__file__).parents[2] / "scenes"
UR5_JOINT_GOALS = [
    [40, -60, 80, -110, -90, 0],
    [0, -80, 60, -70, -90, 30],
    [-40, -60, 90, -120, -90, 0],
    [30, -90, 100, -100, -90, 0],
]


def _notes_arm(blend: float | None) -> dict:
    """The notes' arm scene, its holds dropped (a goal with hold rests), with ``solver.blend``."""
    scene = yaml.safe_load((SCENES / "notes-arm.yaml").read_text())
    scene["goals"] = [g["position"] if isinstance(g, dict) else g for g in scene["goals"]]
    if blend is not None:
        scene["solver"]["blend"] = blend
    return scene


def _ur5_joints(blend: float | None) -> dict:
    scene = {
        "version": 1,
        "arm": {"robot": "ur5"},
        "obstacles": [{"center": [0.55, 0.0, 0.25], "radius": 0.12}],
        "goals": [{"joints": j} for j in UR5_JOINT_GOALS],
        "solver": {"clearance": 0.02},
    }
    if blend is not None:
        scene["solver"]["blend"] = blend
    return scene


@pytest.fixture(scope="module")
def notes_solved():
    problem = scene_to_problem(scene_model(_notes_arm(2.0)))
    return problem, solve_trajectory(problem)


@pytest.fixture(scope="module")
def ur5_solved():
    problem = scene_to_problem(scene_model(_ur5_joints(10.0)))
    return problem, solve_trajectory(problem)


@pytest.mark.parametrize("fps", [15.0, 30.0, 60.0])
def test_the_notes_arm_passes_its_goals_within_the_radius_at_every_fps(notes_solved, fps):
    problem, solution = notes_solved
    timed = retime(problem, solution, fps)
    out = at_fps(problem, fps)
    assert_trajectory_invariants(out, timed)  # rates, clearance, limits; each via's pass frame within its radius by FK
    blends = [g.blend for g in timed.goals]
    assert all(b is not None for b in blends)
    assert blends[-1].reason == "last" and not blends[-1].blended
    assert any(b.blended for b in blends[:-1])
    assert timed.rest_to_rest_duration is not None
    assert (
        timed.trajectory.frames / fps <= 0.8 * timed.rest_to_rest_duration
    )  # the shortened, smoothed path flows (0.65x)
    for b in blends:
        if b.blended:
            assert b.pass_speed > 0 and b.corner in ("curve", "through")
        else:
            assert b.reason in ("last", "slower", "radius", "missed")


def test_the_same_goals_are_reached_as_at_rest(notes_solved):
    problem, solution = notes_solved
    at_rest = retime(
        replace(problem, goals=tuple(replace(g, blend=None) for g in problem.goals)), solution, problem.fps
    )
    blended = retime(problem, solution, problem.fps)
    assert [g.reached for g in blended.goals] == [g.reached for g in at_rest.goals]
    assert blended.rest_to_rest_duration == pytest.approx(at_rest.trajectory.frames / problem.fps)
    assert at_rest.rest_to_rest_duration is None and all(g.blend is None for g in at_rest.goals)


def test_a_ur5_flows_through_joint_goals_on_certified_curves(ur5_solved):
    problem, solution = ur5_solved
    timed = retime(problem, solution, problem.fps)
    assert_trajectory_invariants(problem, timed)
    blends = [g.blend for g in timed.goals]
    assert sum(b.blended for b in blends) >= 2 and any(b.corner == "curve" for b in blends if b.blended)
    assert timed.trajectory.frames / problem.fps < timed.rest_to_rest_duration  # it does not stop: faster
    traj = timed.trajectory
    for k, b in enumerate(blends):
        if b.blended:  # the arm is moving at the pass frame: its clock velocity is not 0
            last = np.nonzero(traj.goal == k)[0][-1]
            assert np.abs(traj.velocity[last]).max() > 0.05


def test_with_a_jerk_limit_the_flow_keeps_it_on_every_frame():
    """arm.max_joint_jerk: the blended sequence's frames keep the jerk too (third differences, in
    the invariants), and still pass the goals faster than at rest."""
    scene = _ur5_joints(10.0)
    scene["arm"]["max_joint_jerk"] = 20000
    problem = scene_to_problem(scene_model(scene))
    timed = retime(problem, solve_trajectory(problem), problem.fps)
    assert problem.rates.jerk is not None
    assert_trajectory_invariants(problem, timed)
    assert sum(g.blend.blended for g in timed.goals) >= 2
    assert timed.trajectory.frames / problem.fps < timed.rest_to_rest_duration


def test_with_hold_on_every_goal_each_rests_at_its_solved_pose_no_later():
    """A goal with hold ends at rest, at the pose it rests at without blend (bit for bit), and holds
    as long; its path there may be shortened and smoothed, so it comes no later."""
    scene = _notes_arm(None)
    scene["goals"] = [{"position": g, "hold": 0.2} for g in scene["goals"]]
    plain = scene_to_problem(scene_model(scene))
    solution = solve_trajectory(plain)
    held = replace(plain, goals=tuple(replace(g, blend=0.5) for g in plain.goals))
    a, b = retime(plain, solution, plain.fps), retime(held, solution, plain.fps)
    assert_trajectory_invariants(held, b)
    assert [g.blend.reason for g in b.goals] == ["hold"] * 3 + ["last"]
    for ga, gb in zip(a.goals, b.goals):
        np.testing.assert_array_equal(a.trajectory.phi[ga.last_frame], b.trajectory.phi[gb.last_frame])
        assert gb.last_frame - gb.first_frame <= ga.last_frame - ga.first_frame
        assert np.all(
            np.abs(np.diff(b.trajectory.phi[gb.last_frame - round(0.2 * plain.fps) + 1 : gb.last_frame + 1], axis=0))
            == 0
        )
    assert b.trajectory.frames <= a.trajectory.frames


def test_the_blended_paths_duration_is_toppras(ur5_solved):
    """The clock's time law on the whole blended path (every goal's solved poses, corners cut) is
    within 2 % of toppra's on the same path, velocity free at the vias."""
    problem, solution = ur5_solved
    (poses,) = via_paths(problem, solution)
    path = joint_path(poses, problem.limits.limited)
    speed, acceleration = problem.rates.speed, problem.rates.acceleration
    oracle = toppra_trajectory(path, speed, acceleration)
    law = time_optimal(path, speed, acceleration)
    assert law.duration == pytest.approx(oracle.duration, rel=0.02)
    solved = solution.trajectory.phi  # the path was shortened: no longer in joint space than the solved one, same ends
    assert np.abs(np.diff(poses, axis=0)).sum() <= np.abs(np.diff(solved, axis=0)).sum() + 1e-9
    np.testing.assert_array_equal(poses[[0, -1]], solved[[0, -1]])
    knots = path.s[1:-1]  # the speed at the vias' poses is free: nowhere inside does the law stop
    assert np.interp(knots, law.s, law.speed).min() > 0


@pytest.mark.parametrize(
    "goal, field, words",
    [
        (
            {"path": {"line": [[0.4, 0, 0.3], [0.4, 0.1, 0.3]]}, "speed": 0.1, "blend": 0.02},
            "goals[0].blend",
            "belongs to a point",
        ),
        ({"joints": [0, -45, 0, -135, 0, 90, 45], "blend": 200}, "goals[0].blend", "at most 180"),
        ({"position": [0.4, 0, 0.3], "blend": -0.1}, "goals[0].blend", "must be >= 0"),
    ],
)
def test_bad_blends_are_refused_at_their_line(tmp_path, cli, goal, field, words):
    path = tmp_path / "bad.yaml"
    path.write_text(
        yaml.safe_dump({"version": 1, "arm": {"robot": "panda"}, "goals": [goal, [0.4, 0.2, 0.4]]}, sort_keys=False)
    )
    result = cli("validate", path)
    assert result.exit_code == 2, result.output
    assert field in result.output and words in result.output and f"{path.name}:" in result.output, result.output


def test_blended_runs_are_byte_identical(tmp_path, cli):
    scene = tmp_path / "flow.yaml"
    scene.write_text(yaml.safe_dump({**_ur5_joints(10.0), "name": "flow"}, sort_keys=False))
    outs = assert_reruns_byte_identical(cli, scene, "flow")
    import json

    summary = json.loads((outs[0] / "summary.json").read_text())
    assert summary["totals"]["duration_s"] <= summary["totals"]["rest_to_rest_duration_s"]
    assert [g["blended"] for g in summary["goals"]][-1] is False and summary["goals"][-1]["blend_reason"] == "last"
    assert {"pass_distance", "pass_speed", "corner"} <= set(summary["goals"][0])
    from armanim.output.summary import goal_report_dict
    from armanim.runs.reload import load_run

    back = load_run(outs[0]).solution  # read back: the same blend reports and the run at rest
    assert back.rest_to_rest_duration == summary["totals"]["rest_to_rest_duration_s"]
    assert [goal_report_dict(g)["pass_distance"] for g in back.goals] == [
        g.get("pass_distance") for g in summary["goals"]
    ]
    assert [g.blend.blended for g in back.goals] == [g["blended"] for g in summary["goals"]]


@settings(max_examples=10, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(problem=joint_goal_problems(max_goals=4), radius=st.sampled_from([0.0, 0.05, 0.2, 0.5]))
def test_random_blended_joint_goals_keep_every_invariant(problem, radius):
    """Random arms among every shape, joint goals with a blend (radians): every invariant of the
    timed trajectory, each via passed within its radius, and never longer than at rest."""
    problem = small_planning_budget(replace(problem, goals=tuple(replace(g, blend=radius) for g in problem.goals)))
    solution = retime(problem, solve_trajectory(problem), problem.fps)
    assert_trajectory_invariants(problem, solution)
    assert solution.trajectory.frames / problem.fps <= solution.rest_to_rest_duration + 1e-9


def test_a_passed_goal_is_drawn_passed_and_captioned_passing(ur5_solved):
    """The video's markers and captions: a via goal's pass frame says "passing" (not "reached"),
    its marker is drawn as passed there; the last goal, reached at rest, is "holding"/"reached"."""
    from armanim.render.overlay.caption import CURRENT, REACHED, frame_activity, goal_status

    problem, solution = ur5_solved
    timed = retime(problem, solution, problem.fps)
    traj, reports = timed.trajectory, timed.goals
    activity = frame_activity(traj, reports)
    via = next(r for r in reports if r.blend.blended)
    assert activity[via.last_frame] == "passing"
    assert goal_status(traj, reports, via.last_frame, len(reports))[via.index] == REACHED
    assert goal_status(traj, reports, via.first_frame, len(reports))[via.index] == CURRENT
    assert "passing" not in set(activity[traj.goal == reports[-1].index])


def test_a_path_goal_starts_and_ends_at_rest_among_blended_goals():
    """solver.blend leaves a path goal's path out (it starts and ends at rest, at the goal's speed);
    the goal before it flows into the path goal's approach to its start (issue 53, item 1: the
    approach, not the path), and the goals after it flow too."""
    scene = _notes_arm(2.0)
    scene["goals"].insert(1, {"path": {"line": [[14, 5, 6], [14, 8, 6]]}, "speed": 2.0})
    problem = scene_to_problem(scene_model(scene))
    timed = retime(problem, solve_trajectory(problem), problem.fps)
    assert_trajectory_invariants(problem, timed)
    assert timed.goals[1].blend is None and timed.goals[0].blend.blended, timed.goals[0].blend
    traj = timed.trajectory
    along = np.nonzero(traj.mode == "path")[0]
    first, last = along[0], along[-1]
    np.testing.assert_array_equal(traj.velocity[[first - 1, last]], 0.0)  # at rest at the path's start and end
    assert np.abs(traj.velocity[timed.goals[0].last_frame]).max() > 0  # passing goal 0 on the way there
    assert traj.frames / problem.fps <= 0.8 * timed.rest_to_rest_duration


def test_the_plot_marks_each_pass_where_the_joints_still_move(ur5_solved):
    """The plot's speed panel: a "passing k" mark at each via goal's pass frame, where the clock's
    fastest joint is not at rest (the arm does not stop there)."""
    from armanim.render.pictures.plot import plot_figure

    problem, solution = ur5_solved
    timed = retime(problem, solution, problem.fps)
    speeds = plot_figure(problem, timed.trajectory, timed.goals, title="flow").figure.axes[2]
    marks = {t.get_text().strip(): t.get_position()[0] for t in speeds.texts if "passing" in t.get_text()}
    vias = [g for g in timed.goals if g.blend.blended]
    assert sorted(marks) == sorted(f"passing {g.index}" for g in vias)
    for g in vias:
        assert marks[f"passing {g.index}"] == pytest.approx(timed.trajectory.time[g.last_frame])
        share = np.abs(timed.trajectory.velocity[g.last_frame]) / problem.rates.speed
        assert share.max() > 0.05


RAIL_BLEND = {
    "version": 1,
    "name": "rail-blend",
    "arm": {"robot": "ur5_rail", "home": [0.4, 0, -100, 100, -90, -90, 0]},
    "goals": [
        {"joints": [-0.6, 0, -100, 100, -90, -90, 0]},
        {"joints": [0.2, 20, -90, 90, -90, -90, 0], "blend": 10},
        {"joints": [1.0, 40, -100, 100, -90, -90, 0]},
    ],
}


def test_a_rail_joint_goal_s_pass_is_reported_in_each_joint_s_own_unit(tmp_path, cli):
    """A via joint goal on ur5_rail (its rail passing at about 1 m/s): summary.json's
    pass_distance and pass_speed are the revolute joints' (degrees, as trajectory.csv's at the pass
    frame), and the rail's metres and m/s are apart (pass_distance_m, pass_speed_m_s, blend_m); read
    back, the same (the rail's 0.99 m/s was written as 56.8 "degrees per second")."""
    import csv
    import json

    from armanim.output.summary import goal_report_dict
    from armanim.runs.reload import load_run

    scene = tmp_path / "rail-blend.yaml"
    scene.write_text(yaml.safe_dump(RAIL_BLEND, sort_keys=False))
    result = cli("run", scene, "--no-video", "--out", tmp_path / "out", "-q")
    assert result.exit_code == 0, result.output
    folder = tmp_path / "out" / "rail-blend"
    via = json.loads((folder / "summary.json").read_text())["goals"][1]
    assert via["blended"] and via["blend_units"] == "deg" and via["blend"] == pytest.approx(10.0)
    with open(folder / "trajectory.csv", newline="") as handle:
        row = list(csv.DictReader(handle))[via["last_frame"]]  # the pass frame
    goal = RAIL_BLEND["goals"][1]["joints"]
    turns = [f"phi{k}_deg" for k in range(2, 8)]
    assert via["pass_speed"] == pytest.approx(max(abs(float(row["d" + c + "_s"])) for c in turns), abs=1e-3)
    assert via["pass_distance"] == pytest.approx(max(abs(float(row[c]) - g) for c, g in zip(turns, goal[1:])), abs=1e-3)
    assert via["pass_speed_m_s"] == pytest.approx(abs(float(row["dq1_m_s"])), abs=1e-5) and via["pass_speed_m_s"] > 0.5
    assert via["pass_distance_m"] == pytest.approx(abs(float(row["q1_m"]) - goal[0]), abs=1e-5)
    assert via["blend_m"] == pytest.approx(np.radians(10.0))
    assert via["pass_speed"] < 40  # not the rail's m/s as degrees (56.8)
    back = load_run(folder).solution.goals[1]
    assert {k: goal_report_dict(back)[k] for k in via if "pass" in k or "blend" in k} == {
        k: v for k, v in via.items() if "pass" in k or "blend" in k
    }
    assert "pass_distance_m" not in json.loads((folder / "summary.json").read_text())["goals"][0]
