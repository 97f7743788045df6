"""Issue 36: the holes the third attack campaign found (research/redteam-2026-12-04.md), by
their roots. Each test failed on main 3ddd2c2; the values are of the kinds the campaign tried,
not only its examples.

1. one bounded reading of every number (scene and URDF): a floor for max_joint_step, the
   planner's schedule capped by the frames left, safe normalisation, URDF magnitudes, narrow
   limits, strict JSON out;
2. every file read back is read with a depth guard;
3. output hygiene (index.csv cells, names escaped, reserved names, short messages).
"""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from armanim.arm.geometry import unit_vector
from armanim.errors import SceneError
from armanim.motion.orientation import Orientation
from armanim.motion.planning.follow import damper_paced, path_schedule
from armanim.output.jsontext import json_text, parse_json
from armanim.scene import scene_to_problem, validate_scene_text
from armanim.scene.urdf import parse_urdf

ARM = "version: 1\narm: {links: [1, 1, 1, 1]}\n"


def scene_error(text: str) -> str:
    """The report of the SceneError ``text`` must raise."""
    with pytest.raises(SceneError) as caught:
        validate_scene_text(text, "s.yaml")
    return caught.value.report()


# ------------------------------------------------------------------ 1. numbers


@pytest.mark.parametrize("step", ["1e-9", "1e-6", "1e-300", "0.0009"])
def test_a_max_joint_step_below_the_floor_is_refused_with_its_line(step):
    report = scene_error(ARM + f"goals: [[1, 1, 2]]\nsolver: {{max_joint_step: {step}}}\n")
    assert report.startswith("s.yaml:4: solver.max_joint_step: ") and "0.001" in report


@pytest.mark.parametrize("length", [3.0, 300.0, 1e300])
def test_a_path_longer_than_the_frames_left_is_followed_as_far_as_they_go(length):
    waypoints = np.array([[0.0, 0.0], [length, -length]])
    for step, most in ((np.radians(0.001), 600), (1e-300, 10**6)):  # a count of 1e306, or inf: never allocated
        s = path_schedule(waypoints, step, most=most)
        assert len(s) == most and np.all(np.diff(s) >= 0) and np.all(np.diff(s) <= step / 0.66) and s[-1] < length
    short = path_schedule(np.array([[0.0], [0.5]]), 0.1, most=600)
    assert len(short) == 8 and short[-1] == 0.5


def test_the_damper_never_makes_a_schedule_longer_than_the_frames_left():
    from armanim.scene import load_scene  # a scene with obstacles, so the damper has work

    problem = scene_to_problem(load_scene(Path(__file__).parents[1] / "scenes" / "planning-wall.yaml").model)
    start = problem.home
    waypoints = np.stack([start, start + 2.0])
    schedule = path_schedule(waypoints, problem.solver.max_joint_step)
    assert len(damper_paced(problem, waypoints, schedule, most=len(schedule) + 3)) <= len(schedule) + 3


def test_a_plan_longer_than_the_frames_left_stops_where_they_end():
    from armanim.motion.planning import plan_motion
    from armanim.scene import load_scene

    problem = scene_to_problem(load_scene(Path(__file__).parents[1] / "scenes" / "planning-wall.yaml").model)
    goal = problem.goals[1].position
    free = plan_motion(problem, problem.home, goal)
    assert free.frames is not None and len(free.frames) <= problem.solver.max_frames_per_goal
    tight = plan_motion(problem, problem.home, goal, frames_left=3)
    assert len(tight.frames) == 3
    assert not np.allclose(tight.frames[-1], free.frames[-1])  # short of the goal pose: the goal ends too_slow at its cap


@pytest.mark.parametrize("vector", [[1e-320, 0, 0], [1e-200, 1e-200, 0], [1e308, 0, 1e308], [-1e308, -1e308, -1e308],
                                    [5e-324, 5e-324, 0], [0, -0.0, 3e-310]])
def test_a_direction_of_any_finite_size_is_normalised_exactly(vector):
    unit = unit_vector(vector)
    exact = np.sign(vector) * (np.array(vector) != 0) / math.sqrt(sum(v != 0 for v in vector))  # equal components here
    assert np.all(np.isfinite(unit)) and np.allclose(unit, exact, atol=1e-15)
    assert np.allclose(Orientation(axis=np.array(vector, dtype=float)).axis, exact, atol=1e-15)


@pytest.mark.parametrize("form", ["tool_axis: [1e-320, 0, 0]", "tool_axis: [1e308, 0, 1e308]",
                                  "orientation: {axis: [1e-200, 1e-200, 0], angle: 30}",
                                  "orientation: {axis: [1e308, 1e308, 1e308], angle: 30}"])
def test_extreme_orientation_vectors_mean_their_direction(form):
    model = validate_scene_text(ARM + f"goals:\n  - {{position: [1, 1, 2], {form}}}\n", "s.yaml")
    goal = scene_to_problem(model).goals[0].orientation
    if goal.axis is not None:
        assert np.allclose(goal.axis, unit_vector([1, 0, 0] if "1e-320" in form else [1, 0, 1]))
    else:  # 30 degrees about the vector's direction, never the identity or NaN
        assert np.isclose(np.degrees(np.arccos((np.trace(goal.rotation) - 1) / 2)), 30.0)


@pytest.mark.parametrize("field", ["orientation: {axis: [0, 0, 1], angle: 1e308}", "orientation: {rpy: [1e308, 0, 0]}",
                                   "orientation: {rpy: [0, 361, 0]}"])
def test_goal_angles_are_bounded_like_every_other_angle(field):
    report = scene_error(ARM + f"goals:\n  - {{position: [1, 1, 2], {field}}}\n")
    assert "s.yaml:4: goals[0].orientation." in report and "360" in report


def urdf(origin="0 0 0.3", axis="0 1 0", lower="-2", upper="2", size='radius="0.03" length="0.3"') -> bytes:
    links = "".join(f'<link name="l{i}"><collision><geometry><cylinder {size}/></geometry></collision></link>' for i in range(3))
    joints = "".join(
        f'<joint name="j{i}" type="revolute"><parent link="l{i}"/><child link="l{i + 1}"/><origin xyz="{origin}"/>'
        f'<axis xyz="{axis}"/><limit lower="{lower}" upper="{upper}"/></joint>\n' for i in range(2))
    return f'<robot name="r">\n{links}\n{joints}</robot>'.encode()


@pytest.mark.parametrize("kwargs", [{"origin": "1e200 0 0"}, {"origin": "0 0 -2e9"}, {"lower": "-1e308"},
                                    {"upper": "1e10"}, {"size": 'radius="1e300" length="1"'}, {"axis": "0 1e10 0"}])
def test_urdf_numbers_are_bounded_as_a_scene_s_with_their_line(kwargs):
    with pytest.raises(SceneError, match=r"^r\.urdf:[23]: .*above 1e\+09 in size") as caught:
        parse_urdf(urdf(**kwargs), "r.urdf")
    assert len(caught.value.report()) < 300


@pytest.mark.parametrize("number", ["-1_0", "1_000", "0x10", "inf", "nan", "Infinity", "1e", "--1", "1.2.3", "١"])
def test_a_urdf_number_is_written_as_urdf_writes_it(number):
    with pytest.raises(SceneError, match="finite numbers"):
        parse_urdf(urdf(origin=f"0 0 {number}"), "r.urdf")


@pytest.mark.parametrize("axis", ["1e-200 0 0", "1e9 1e9 0", "0 0 -5e-324"])
def test_a_urdf_axis_of_any_finite_size_is_its_direction(axis):
    from armanim.arm.chain import serial_chain
    from armanim.scene.urdf import chain_joints

    robot = parse_urdf(urdf(axis=axis), "r.urdf")
    arm = serial_chain(np.eye(4), chain_joints(robot, "l0", "l2"), np.eye(4)).arm
    assert np.allclose(arm.axes, unit_vector([float(v) for v in axis.split()]))


@pytest.mark.parametrize("limits,margin", [("[[-0.4, 0.4], null, null, null]", ""), ("[[-5, 5], null, null, null]", "  limit_margin: 180\n")])
def test_a_joint_range_narrower_than_the_planner_s_buffer_is_refused_with_the_field(limits, margin):
    report = scene_error(f"version: 1\narm:\n  links: [1, 1, 1, 1]\n  limits: {limits}\n{margin}goals: [[1, 1, 2]]\n")
    assert report.startswith("s.yaml:4: arm.limits[0]: a range of ") and "limit_margin" in report


def test_a_urdf_range_narrower_than_the_buffer_names_the_joint(tmp_path):
    (tmp_path / "r.urdf").write_bytes(urdf(lower="-1e-300", upper="1e-300"))
    (tmp_path / "s.yaml").write_text("version: 1\narm: {urdf: r.urdf, base_link: l0, tip_link: l2}\ngoals: [[0.1, 0.1, 0.4]]\n")
    from armanim.scene import load_scene

    with pytest.raises(SceneError, match=r"arm.limit_margin: the URDF's joint 'j0' has a range of 1.14592e-298 deg"):
        load_scene(tmp_path / "s.yaml")


def test_the_planner_seeds_within_a_range_narrower_than_its_buffer():
    from types import SimpleNamespace

    from armanim.motion.planning.poses import seed_poses
    from armanim.motion.problem import Limits
    from armanim.motion.tunables import DEFAULTS

    narrow = SimpleNamespace(limits=Limits(np.array([-0.007, -np.inf]), np.array([0.007, np.inf]), margin=np.radians(10)),
                             tunables=DEFAULTS)
    seeds = seed_poses(narrow, np.zeros(2), 16, seed=1)
    assert np.all(np.abs(seeds[:, 0]) <= 0.007)


def test_json_is_written_strictly_and_read_with_a_depth_guard():
    with pytest.raises(ValueError):
        json_text({"final_distance": math.inf})
    for deep in ("[" * 1500 + "]" * 1500, '{"a":' * 100_000 + "1" + "}" * 100_000):
        with pytest.raises(ValueError, match="nested too deep"):
            parse_json(deep)


def test_numpy_warnings_never_reach_the_terminal(tmp_path):
    scene = tmp_path / "w.yaml"
    scene.write_text(ARM + "goals:\n  - {position: [1, 1, 2], tool_axis: [0, 0, -1]}\n"
                     "solver: {orientation_weight: 1e-300, max_frames_per_goal: 30}\nrender: {size: [64, 48]}\n")
    done = subprocess.run([sys.executable, "-m", "armanim", "run", str(scene), "--out", str(tmp_path / "o"), "--no-video", "--quiet"],
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0 and "Warning" not in done.stderr, done.stderr
    json.loads((tmp_path / "o" / "w" / "summary.json").read_text(), parse_constant=lambda c: pytest.fail(f"{c} in summary.json"))


# ------------------------------------------------------------------ 2. files read back


SMALL = ARM + "goals: [[1, 1, 2]]\nrender: {fps: 10, size: [64, 48]}\nsolver: {max_frames_per_goal: 40}\n"


@pytest.fixture()
def finished_run(cli, tmp_path) -> Path:
    (tmp_path / "deep.yaml").write_text(SMALL + "name: deep\n")
    cli("run", tmp_path / "deep.yaml", "--out", tmp_path / "o", "--no-video", "--quiet")
    return tmp_path / "o" / "deep"


@pytest.mark.parametrize("text", ["[" * 1500 + "]" * 1500, '{"goals":' * 50_000 + "1" + "}" * 50_000])
@pytest.mark.parametrize("command", ["view", "render"])
def test_a_deeply_nested_summary_is_one_line_and_exit_2(cli, finished_run, text, command):
    (finished_run / "summary.json").write_text(text)
    result = cli(command, finished_run)
    assert result.exit_code == 2
    assert result.stderr.strip() == f"{finished_run / 'summary.json'}: is not an armanim summary: nested too deep"


def test_a_deeply_nested_golden_json_is_ignored(cli, tmp_path):
    (tmp_path / "deep.yaml").write_text(SMALL + "name: deep\n")
    assert cli("check", tmp_path / "deep.yaml", "--golden", tmp_path / "g", "--update", "--quiet").exit_code == 0
    (tmp_path / "g" / "deep.json").write_text("[" * 40_000 + "]" * 40_000)
    assert cli("check", tmp_path / "deep.yaml", "--golden", tmp_path / "g").exit_code == 0


# ------------------------------------------------------------------ 3. output hygiene


def test_index_csv_cells_never_start_a_formula(cli, tmp_path):
    import csv

    names = ['=HYPERLINK("http:__x","open")+1', "@SUM(1+1)", "+1", "-cmd", "\tx"]
    for k, stem in enumerate(names):
        (tmp_path / f"{stem}.yaml").write_text(SMALL + f"name: s{k}\n" + ("goals: [[1, 1, 99]]\n" if k == 1 else ""))  # k=1: invalid
    (tmp_path / "-bad.yaml").write_text("version: 1\n")  # an invalid scene: its stem and message are cells too
    result = cli("run", *sorted(tmp_path.glob("*.yaml")), "--out", tmp_path / "o", "--no-video", "--jobs", "1", "--quiet")
    assert result.exit_code == 2
    cells = [c for row in csv.reader((tmp_path / "o" / "index.csv").open(newline="")) for c in row]
    assert not [c for c in cells if c[:1] in ("=", "+", "-", "@", "\t", "\r")]
    assert {"'-bad", "'@SUM(1+1)"} <= set(cells)  # the stems of the invalid scenes, kept as text


def names_urdf(name: str) -> bytes:
    return urdf().replace(b'name="j1"', f'name="{name}"'.encode())


@pytest.mark.parametrize("name", ["j1)&#10;ok evil.yaml (all good", "a&#x202e;b", "c&#x9b;31m", "d&#13;e", "x" * 5000])
def test_names_from_files_are_printed_escaped(cli, tmp_path, name):
    (tmp_path / "r.urdf").write_bytes(names_urdf(name))
    (tmp_path / "s.yaml").write_text("version: 1\narm: {urdf: r.urdf, base_link: l0, tip_link: l2}\ngoals: [[0.1, 0.1, 0.4]]\n")
    result = cli("validate", tmp_path / "s.yaml")
    assert result.exit_code == 0 and len(result.stdout.splitlines()) == 1, result.stdout
    assert result.stdout.isprintable() or result.stdout[:-1].isprintable()
    assert len(result.stdout) < 700


@pytest.mark.parametrize("name", ["index.csv", "INDEX.CSV", "notes-sweep.csv", "a-Sweep.CSV"])
def test_names_of_armanim_s_own_tables_are_refused_at_validate(name):
    report = scene_error(SMALL + f"name: {name}\n")
    assert report.startswith("s.yaml:6: name: ") and "table armanim writes" in report


def test_view_out_inside_the_run_folder_is_refused(cli, finished_run):
    result = cli("view", finished_run, "--out", finished_run / "extra.html")
    assert result.exit_code == 2 and "inside the run folder" in result.stderr
    assert not (finished_run / "extra.html").exists()
    assert cli("view", finished_run, "--out", finished_run / "viewer.html").exit_code == 0


def test_a_golden_csv_with_thousands_of_extra_columns_is_a_short_message_naming_the_file(cli, tmp_path):
    (tmp_path / "wide.yaml").write_text(SMALL + "name: wide\n")
    cli("check", tmp_path / "wide.yaml", "--golden", tmp_path / "g", "--update", "--quiet")
    golden = tmp_path / "g" / "wide.csv"
    rows = golden.read_text().splitlines()
    extra = 12_000
    golden.write_text("\n".join([rows[0] + "," + ",".join(f"c{i}" for i in range(extra))]
                                + [r + "," + ",".join(["0"] * extra) for r in rows[1:]]) + "\n")
    result = cli("check", tmp_path / "wide.yaml", "--golden", tmp_path / "g")
    assert result.exit_code == 2 and len(result.stderr) < 400 and str(golden) in result.stderr and "11,992 more" in result.stderr


def test_every_line_of_a_message_is_short_and_printable():
    from armanim.errors import message_lines

    text = message_lines("a.yaml:1: " + "x\u202e\x9b" * 10_000 + "\nsecond")
    first, second = text.split("\n")
    assert len(first) < 700 and first.isprintable() and second == "second"


def test_validate_reports_every_problem_of_a_file_in_one_pass():
    text = ("version: 1\narm:\n  links: [1, 1, 1, 1]\n  limits: [[10, -10], null, null, null]\n"
            "obstacles:\n  - {center: [0, 0, 1], radius: 0.3}\ngoals: [[1, 1, 2]]\nrender: {size: [10, 10000000]}\n")
    report = scene_error(text)
    for expected in ("s.yaml:4: arm.limits[0]: min must be below max", "s.yaml:6: obstacles[0]: link 1 of the arm's home pose is inside",
                     "s.yaml:8: render.size[0]: must be >= 16", "s.yaml:8: render.size[1]: must be <= 7680"):
        assert expected in report, report


@pytest.mark.parametrize("field,exact", [("goals: [{position: [1, 1, 2], tool_axis: [1, 0]}]", "goals[0].tool_axis: has 2 items (expected exactly 3)"),
                                         ("goals: [[1, 1, 2]]\nrender: {size: [64]}", "render.size: has 1 items (expected exactly 2)"),
                                         ("goals: [{position: [1, 1, 2], orientation: {quaternion_wxyz: [1, 0, 0]}}]", "(expected exactly 4)")])
def test_a_list_of_a_fixed_length_says_exactly(field, exact):
    assert exact in scene_error(ARM + field + "\n")


# ------------------------------------------------------------------ 4. render keeps the run's seconds


def test_resampled_frames_keep_the_run_s_poses_at_its_own_times():
    from armanim.motion.trajectory import solve_trajectory
    from armanim.runs.resample import resample_run

    problem = scene_to_problem(validate_scene_text(SMALL.replace("[[1, 1, 2]]", "[[1, 1, 2], [-1, 1, 2]]"), "s.yaml"))
    solution = solve_trajectory(problem)
    src = solution.trajectory
    double = resample_run(problem, solution, 2 * src.fps)
    assert double.trajectory.frames == 2 * src.frames - 1
    assert np.allclose(double.trajectory.time[-1], src.time[-1])
    assert np.allclose(double.trajectory.phi[::2], src.phi)  # the run's own poses, at their own seconds
    assert np.allclose(double.trajectory.phi[1::2], 0.5 * (src.phi[:-1] + src.phi[1:]))  # limited-free here: none wrap
    assert np.allclose(double.trajectory.tip[::2], src.tip) and np.array_equal(double.trajectory.goal[::2], src.goal)
    for before, after in zip(solution.goals, double.goals):
        heads = 2 * before.first_frame - (1 if before.index else 0)  # the in-between frame heads for the next goal's first
        assert (after.first_frame, after.last_frame, after.reached) == (heads, 2 * before.last_frame, before.reached)
    half = resample_run(problem, solution, src.fps / 2)
    assert np.isclose(half.trajectory.time[-1], src.time[-1]) and np.allclose(half.trajectory.phi[-1], src.phi[-1])


@pytest.mark.slow
def test_render_at_another_fps_keeps_the_run_s_real_time(cli, finished_run):
    import imageio_ffmpeg

    own = imageio_ffmpeg.count_frames_and_secs(str(finished_run / "animation.mp4")) if (finished_run / "animation.mp4").exists() else None
    frames = len((finished_run / "trajectory.csv").read_text().splitlines()) - 1
    for fps in (25, 5):
        assert cli("render", finished_run, "--fps", fps, "--out", finished_run.parent / f"r{fps}", "--quiet").exit_code == 0
        count, seconds = imageio_ffmpeg.count_frames_and_secs(str(finished_run.parent / f"r{fps}" / "animation.mp4"))
        assert abs(count / fps - frames / 10) <= 2 / fps, (count, frames, own)


def test_render_at_an_fps_beyond_the_frame_limit_is_refused_before_drawing(cli, tmp_path):
    (tmp_path / "slow.yaml").write_text(ARM + "name: slow\ngoals: [{position: [1, 1, 2], hold: 3600}]\nrender: {fps: 0.01, size: [64, 48]}\n")
    assert cli("run", tmp_path / "slow.yaml", "--out", tmp_path / "o", "--no-video", "--quiet").exit_code == 0
    result = cli("render", tmp_path / "o" / "slow", "--fps", 240, "--out", tmp_path / "r")
    assert result.exit_code == 2 and "expected at most 1,000,000" in result.stderr and not (tmp_path / "r").exists()


@pytest.mark.parametrize("field", ["solver: {orientation_tolerance: 5e-324}", "solver: {orientation_tolerance: 1e-300}",
                                   "arm: {links: [1, 1, 1, 1], limit_margin: 5e-324}"])
def test_angles_that_would_be_zero_radians_are_refused(field):
    text = "version: 1\n" + (field + "\n" if field.startswith("arm") else "arm: {links: [1, 1, 1, 1]}\n" + field + "\n")
    report = scene_error(text + "goals:\n  - {position: [1, 1, 2], tool_axis: [0, 0, 1]}\n")
    assert "must be >= 1e-06" in report  # found by benchmarks/fuzz_bench.py: a ZeroDivisionError in pose_distance


@pytest.mark.parametrize("field", ["links: [1, 1e-300, 1]", "links: [1, 1, 1], width: 5e-324"])
def test_lengths_below_the_smallest_are_refused(field):
    assert "is too small (expected at least 1e-09: choose a larger unit)" in scene_error(
        "version: 1\narm: {" + field + "}\ngoals: [[1, 1, 1]]\n")


def test_fk_png_draws_no_goal_and_names_none_in_the_legend():
    from armanim.render.backdrop import legend_entries

    labels = [label for label, _ in legend_entries("pose", trail=True, obstacles=False, outcomes=frozenset(), hidden_goal=False, goals=False)]
    assert labels == ["arm"]


@pytest.mark.parametrize("args,noise", [(["ik", "--robot", "ur5", "--goal", "0.4,0.2,0.3"], "e-1"),
                                        (["fk", "--robot", "panda", "--angles", "0,0,0,-90,0,90,45"], "e-1"),
                                        (["fk", "--robot", "ur5", "--angles", "0,-90,90,-90,-90,0"], "e-1")])
def test_numbers_zero_to_the_arm_s_precision_print_as_0(cli, args, noise):
    result = cli(*args)
    assert result.exit_code == 0 and noise not in result.stdout and "-0 " not in result.stdout, result.stdout


def test_jobs_0_is_a_one_line_message(cli):
    result = cli("run", Path(__file__).parents[1] / "scenes" / "notes-arm.yaml", "--jobs", "0", "--no-video")
    assert result.exit_code == 2 and result.stderr.strip().splitlines() == [
        "--jobs: expected at least 1 worker process (got 0; leave it out to use every core)"]
