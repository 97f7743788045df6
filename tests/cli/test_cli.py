"""The armanim command through Typer's CliRunner: output, --json, exit codes."""

from __future__ import annotations

import csv
import hashlib
import io
import json
from pathlib import Path

import numpy as np
import pytest
from conftest import BUNDLED, SCENES

from armanim import __version__
from armanim.arm.kinematics import Arm, forward


def command_names():
    from armanim.cli import app

    return [c.name or c.callback.__name__ for c in app.registered_commands]


def test_version(cli):
    result = cli("--version")
    assert result.exit_code == 0
    assert result.stdout.strip() == f"armanim {__version__}"


def test_top_level_help_shows_an_example(cli):
    result = cli("--help")
    assert result.exit_code == 0 and "Example" in result.stdout
    for name in ("fk", "ik", "validate", "run", "schema"):
        assert name in result.stdout


@pytest.mark.parametrize("name", command_names())
def test_every_command_help_shows_an_example(cli, name):
    result = cli(name, "--help")
    assert result.exit_code == 0, result.output
    flat = " ".join(result.stdout.split())
    assert "Example: armanim" in flat or "Examples: armanim" in flat, result.stdout


# ------------------------------------------------------------ fk


def test_fk_json_default_arm(cli):
    result = cli("fk", "--angles", "0,30,45,10", "--json")
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    assert set(data) == {"angles_deg", "joints", "tip", "tip_quaternion_wxyz", "tip_rpy_deg"}
    np.testing.assert_allclose(data["angles_deg"], [0, 30, 45, 10], atol=1e-12)
    arm = Arm.from_names([1.0] * 4)  # default: four unit links, axes z, y, y, y
    pose = forward(arm, np.radians([0, 30, 45, 10]))
    assert len(data["joints"]) == 5
    np.testing.assert_allclose(data["joints"], pose.points, atol=1e-12)
    np.testing.assert_allclose(data["tip"], pose.tip, atol=1e-12)
    assert data["joints"][-1] == data["tip"]


def test_fk_json_with_arm_flags(cli):
    result = cli(
        "fk", "--angles", "90,0", "--links", "2,3", "--axes", "z,z", "--direction", "x", "--base", "1,1,0", "--json"
    )
    assert result.exit_code == 0, result.output
    np.testing.assert_allclose(json.loads(result.stdout)["tip"], [1.0, 6.0, 0.0], atol=1e-12)


def test_fk_table(cli):
    result = cli("fk", "--angles", "0,0,0,0", "--links", "2,5,5,5", "--base", "5,5,0")
    assert result.exit_code == 0, result.output
    out = result.stdout
    for label in ("joint 1", "joint 4", "tip"):
        assert label in out
    tip_row = next(line for line in out.splitlines() if "tip" in line)
    assert "17" in tip_row and "5" in tip_row


def test_fk_with_scene(cli):
    result = cli("fk", "--angles", "10,20,30,40", "--scene", SCENES / "notes-arm.yaml", "--json")
    assert result.exit_code == 0, result.output
    arm = Arm.from_names([2, 5, 5, 5], base=(5, 5, 0))
    np.testing.assert_allclose(
        json.loads(result.stdout)["tip"], forward(arm, np.radians([10, 20, 30, 40])).tip, atol=1e-12
    )
    assert "note:" not in result.stderr


def test_fk_radians(cli):
    result = cli("fk", "--angles", f"0,{np.pi / 2},0,0", "--radians", "--json")
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    np.testing.assert_allclose(data["angles_deg"], [0, 90, 0, 0], atol=1e-9)
    np.testing.assert_allclose(data["tip"], [3.0, 0.0, 1.0], atol=1e-12)


def test_fk_notes_a_joint_outside_the_scene_limits(cli):
    result = cli("fk", "--angles", "0,120,0,0", "--scene", SCENES / "notes-arm.yaml")
    assert result.exit_code == 0, result.output
    assert "joint 2" in result.stderr and "outside its limits" in result.stderr
    assert "-100, 100" in result.stderr


@pytest.mark.parametrize(
    "args, fragment",
    [
        (["fk", "--angles", "0,30,45"], "expected 4 numbers (got 3"),
        (["fk", "--angles", "0,30,abc,10"], "'abc' is not a number"),
        (["fk", "--angles", "0,30,nan,10"], "finite"),
        (
            ["fk", "--angles", "0,0,0,0", "--scene", str(SCENES / "notes-arm.yaml"), "--links", "1,1,1,1"],
            "cannot be combined with --scene",
        ),
        (["fk", "--angles", "0,0", "--links", "1,-1"], "--links"),
        # found by the hostile fuzzer: lengths a scene file refuses underflowed the pose search's damping (a traceback)
        (
            ["ik", "--links", "2.24e-169", "--goal=0,0,1", "--json"],
            "--links: a length is too small (expected at least 1e-09",
        ),
        (["fk", "--angles", "0,0", "--links", "1,1", "--axes", "z"], "--axes"),
        (["fk", "--angles", "0,0,0,0", "--direction", "w"], "--direction"),
        (["ik", "--goal", "1,2"], "expected 3 numbers"),
        (["ik", "--goal", "1,1,1", "--method", "simplex"], "'simplex' is not a method"),
        (["run", str(SCENES / "notes-arm.yaml"), "--size", "10x10", "--no-video"], "--size"),
        (["run", str(SCENES / "notes-arm.yaml"), "--fps", "0", "--no-video"], "--fps"),
    ],
)
def test_bad_usage_exits_2_with_a_clear_message(cli, args, fragment):
    result = cli(*args)
    assert result.exit_code == 2, result.output
    assert fragment in result.stderr, result.stderr
    assert "Traceback" not in result.output


def test_fk_with_an_invalid_scene_exits_2(cli, tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text("version: 1\narm:\n  links: [1, 0]\ngoals:\n  - [0, 0, 1]\n")
    result = cli("fk", "--angles", "0,0", "--scene", bad)
    assert result.exit_code == 2
    assert f"{bad}:3: arm.links[1]: must be > 0" in result.stderr


# ------------------------------------------------------------ ik


PLANAR = ["--links", "1,1,1,1", "--axes", "z,z,z,z", "--direction", "x"]


@pytest.mark.parametrize("method", ["pinv", "dls", "newton", "gradient"])
def test_ik_each_method_json(cli, method):
    result = cli("ik", "--goal", "3,1,0", *PLANAR, "--method", method, "--from", "10,10,10,10", "--json")
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    assert data["method"] == method and data["converged"] is True
    assert data["error"] < 1e-3
    tip = forward(Arm.from_names([1.0] * 4, axes=["z"] * 4, direction="x"), np.radians(data["angles_deg"])).tip
    np.testing.assert_allclose(tip, data["tip"], atol=1e-9)
    np.testing.assert_allclose(tip, [3, 1, 0], atol=1e-3)
    if method == "newton":
        assert data["gd_iterations"] >= 1 and "newton_iterations" in data
    else:
        assert data["iterations"] >= 1


def test_ik_newton_prints_both_iteration_counts(cli):
    result = cli("ik", "--goal", "3,1,0", *PLANAR, "--method", "newton")
    assert result.exit_code == 0, result.output
    assert "converged" in result.stdout
    line = next(text for text in result.stdout.splitlines() if text.startswith("steps"))
    assert "gradient descent" in line and "Newton" in line


def test_ik_says_when_linear_algebra_failed(cli, monkeypatch):
    import armanim.motion.ik
    import armanim.motion.solvers.linear

    def fails(jac):
        raise np.linalg.LinAlgError("SVD did not converge")

    monkeypatch.setattr(armanim.motion.solvers.linear, "pseudo_inverse", fails)
    monkeypatch.setattr(
        armanim.motion.ik, "compiled_plan", lambda *args: None
    )  # the numpy steps (the compiled have their own inverse)
    result = cli("ik", "--goal", "3,1,0", *PLANAR, "--from", "10,10,10,10", "--json")
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    assert data["status"] == "numerical" and data["reason"].startswith("numerical: a step failed in linear algebra")


def test_ik_with_scene_uses_its_method(cli):
    result = cli("ik", "--goal", "10,9,7", "--scene", SCENES / "out-of-reach.yaml", "--json")
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    assert data["method"] == "pinv" and data["converged"]


# ------------------------------------------------------------ validate


def test_validate_all_bundled_scenes_ok(cli):
    result = cli("validate", *BUNDLED)
    assert result.exit_code == 0, result.output
    for path in BUNDLED:
        assert f"ok {path}" in result.stdout


def test_validate_reports_each_bad_file_and_exits_2(cli, tmp_path):
    bad1 = tmp_path / "one.yaml"
    bad1.write_text("version: 1\narm:\n  links: [1, 0]\ngoals:\n  - [0, 0, 1]\n")
    bad2 = tmp_path / "two.yaml"
    bad2.write_text("version: 1\narm:\n  links: [1]\ngoals: []\n")
    good = BUNDLED[0]
    result = cli("validate", bad1, good, bad2)
    assert result.exit_code == 2
    assert f"ok {good}" in result.stdout
    assert f"{bad1}:3: arm.links[1]:" in result.stderr
    assert f"{bad2}:4: goals:" in result.stderr


# ------------------------------------------------------------ run


def test_run_no_video_writes_csv_and_summary_and_prints_table(cli, tmp_path):
    scene = SCENES / "out-of-reach.yaml"
    result = cli("run", scene, "--no-video", "--out", tmp_path)
    assert result.exit_code == 0, result.output
    folder = tmp_path / "out-of-reach"
    rows = list(csv.reader(io.StringIO((folder / "trajectory.csv").read_text())))
    expected = [
        "frame",
        "time_s",
        "goal",
        "phi1_deg",
        "phi2_deg",
        "phi3_deg",
        "phi4_deg",
        "x",
        "y",
        "z",
        "goal_distance",
        "clearance",
        "reached",
    ]
    assert rows[0][: len(expected)] == expected
    summary = json.loads((folder / "summary.json").read_text())
    assert summary["scene"]["sha256"] == hashlib.sha256(scene.read_bytes()).hexdigest()
    assert summary["armanim_version"] == __version__
    assert summary["totals"]["goals"] == 2 and summary["totals"]["reached"] == 1
    for g in summary["goals"]:
        assert {"reached", "reason", "frames", "final_distance", "iterations"} <= set(g)
    out = result.stdout
    assert "1 of 2 goals reached" in out
    assert "missed" in out and "out of reach" in out and "reached" in out
    assert not list(folder.glob("animation.*"))
    # issue 50's papercuts: the table's frames add up to the run's, and its numbers carry no noise
    table = [
        line.split("│") for line in out.splitlines() if line.startswith("│") and line.split("│")[1].strip().isdigit()
    ]
    assert sum(int(cells[4]) for cells in table) == len(rows) - 1  # the CSV's rows but its header
    distances = [cells[5].strip() for cells in table]
    assert all("e-" not in d and len(d.split(".")[-1]) <= 4 for d in distances), distances


def test_run_quiet_prints_no_table(cli, tmp_path):
    result = cli("run", SCENES / "singular-start.yaml", "--no-video", "--quiet", "--out", tmp_path)
    assert result.exit_code == 0, result.output
    assert "goals reached" not in result.stdout
    assert (tmp_path / "singular-start" / "trajectory.csv").exists()


def test_run_strict_exits_1_on_a_missed_goal(cli, tmp_path):
    result = cli("run", SCENES / "out-of-reach.yaml", "--no-video", "--quiet", "--strict", "--out", tmp_path)
    assert result.exit_code == 1, result.output
    assert (tmp_path / "out-of-reach" / "summary.json").exists()


def test_run_strict_exits_0_when_all_reached(cli, tmp_path):
    result = cli("run", SCENES / "singular-start.yaml", "--no-video", "--quiet", "--strict", "--out", tmp_path)
    assert result.exit_code == 0, result.output


def test_run_missed_goal_without_strict_is_success(cli, tmp_path):
    assert cli("run", SCENES / "out-of-reach.yaml", "--no-video", "--quiet", "--out", tmp_path).exit_code == 0


def test_run_invalid_scene_exits_2_and_writes_nothing(cli, tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text("version: 2\narm:\n  links: [1]\ngoals:\n  - [0, 0, 1]\n")
    result = cli("run", bad, "--no-video", "--out", tmp_path / "out")
    assert result.exit_code == 2
    assert f"{bad}:1: version:" in result.stderr and "reads version 1" in result.stderr
    assert not (tmp_path / "out").exists()


def test_no_args_shows_help(cli):
    result = cli()
    assert "Usage" in result.output


def test_progress_bars_render_on_a_terminal():
    """The bars only draw on a terminal, which the test runner is not: force one."""
    import io

    from rich.console import Console

    from armanim.cli.progress import Bars

    screen = io.StringIO()
    with Bars(enabled=True, console=Console(file=screen, force_terminal=True, width=100)) as bars:
        bars("solve", 0, 10)  # no speed measured yet
        bars.progress.refresh()
        for done in range(1, 11):
            bars("render", done, 10)
        bars.progress.refresh()
    text = screen.getvalue()
    assert "solver steps" in text and "render" in text and "10/10" in text  # steps, not the run's frames (issue 50)


def test_the_plan_bar_starts_over_for_each_plan(monkeypatch):
    """Each plan counts its search from 0: the bar's rate and time left are the new plan's, not the last one's."""
    import functools
    import io
    import itertools

    from rich.console import Console

    import armanim.cli.progress as progress_module

    clock = itertools.count(0.0, 1.0)  # a second between readings of the time
    monkeypatch.setattr(
        progress_module, "Progress", functools.partial(progress_module.Progress, get_time=lambda: next(clock))
    )
    with progress_module.Bars(
        enabled=True, console=Console(file=io.StringIO(), force_terminal=True, width=100)
    ) as bars:
        for done in (0, 500, 1000, 2000):
            bars("plan", done, 2000)
        task = bars.progress.tasks[0]
        assert task.speed and task.completed == 2000
        bars("plan", 0, 2000)  # the next plan
        assert task.completed == 0 and task.speed is None and not task.finished
        bars("plan", 500, 2000)
        assert task.completed == 500


def test_help_paragraphs_are_not_broken_mid_sentence():
    # rich keeps a docstring's line breaks: a paragraph must be one line, or help breaks sentences
    import ast

    from conftest import ROOT

    commands = 0
    for module in (ROOT / "src" / "armanim" / "cli").glob("*.py"):
        for node in ast.parse(module.read_text(encoding="utf-8")).body:
            if isinstance(node, ast.FunctionDef) and ast.get_docstring(node) and node.decorator_list:
                commands += 1
                for paragraph in ast.get_docstring(node).split("\n\n"):
                    assert "\n" not in paragraph, (module.name, node.name, paragraph)
    assert commands >= 9  # every command is seen: fk, ik, validate, schema, run, render, sweep, compare, check


def test_scheduler_help_shows_the_dask_extra(cli):
    assert "'.[dask]'" in cli("run", "--help").stdout  # rich markup ate [dask] once


def test_validate_counts_in_the_singular(cli, tmp_path):
    scene = tmp_path / "one.yaml"
    scene.write_text(
        "version: 1\narm: {links: [2, 5, 5, 5]}\nobstacles: [{center: [9, 9, 9], radius: 1}]\ngoals: [[6, 0, 10]]\n"
    )
    assert "4 links, 1 goal, 1 obstacle, method pinv" in cli("validate", scene).stdout


def test_ik_says_why_an_out_of_reach_goal_is_not_reached(cli):
    result = cli("ik", "--goal", "30,0,0", "--links", "1,1,1,1", "--json")
    data = json.loads(result.stdout)
    assert not data["converged"] and data["reason"].startswith(
        "out of reach: the goal is 30 units from the base, the arm is 4 units long"
    )


def test_ik_names_the_unit_of_a_robot_s_reach(cli):
    """A URDF arm's lengths are metres, and the message says so (issue 50: "2.015 from the base")."""
    done = cli("ik", "--robot", "iiwa", "--goal", "2,0,0.4")
    assert "the goal is 2.015 m from the base, the arm is 1.103 m long" in done.output, done.output


def test_strict_quiet_says_which_goal_was_missed_on_stderr(cli, tmp_path):
    from conftest import SCENES

    result = cli("run", SCENES / "out-of-reach.yaml", "--out", tmp_path, "--no-video", "--quiet", "--strict")
    assert result.exit_code == 1
    assert result.stdout == "" and "goal 0 missed (out_of_reach)" in result.stderr


POCKET = Path(__file__).parents[1] / "data" / "ik-pocket.yaml"


def test_ik_falls_back_on_the_planners_free_pose_search_and_says_so(cli, monkeypatch):
    # before: `ik --scene` gave up where `run` succeeded (the method stalls; the planner finds a pose)
    import armanim.motion.ik as ik
    from armanim import load_scene, scene_to_problem
    from armanim.arm.kinematics import forward
    from armanim.motion.filter.clearance import pose_is_free

    problem = scene_to_problem(load_scene(POCKET).model)
    goal = problem.goals[0].position
    result = cli("ik", "--scene", POCKET, "--goal", ",".join(map(str, goal)), "--json")
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    assert data["converged"] and data["found_by"] == "free_pose_search"
    phi = np.radians(data["angles_deg"])
    assert np.linalg.norm(forward(problem.arm, phi).tip - goal) < problem.solver.tolerance  # checked from scratch
    assert pose_is_free(problem, phi[None])[0]  # inside the limits, every link clear of every sphere
    text = cli("ik", "--scene", POCKET, "--goal", ",".join(map(str, goal)))
    assert "free-pose search" in text.stdout + text.stderr
    monkeypatch.setattr(ik, "free_pose", lambda *args: None)  # the method alone does not get there
    alone = ik.solve_pose(problem, goal, problem.home)
    assert alone.status == "not_converged" and alone.found_by == "method"


@pytest.mark.parametrize("name", command_names())
def test_help_shows_no_type_for_a_flag_and_arguments_in_capitals(cli, name):
    # issue 50's papercuts: typer 0.29 printed "--quiet -q <bool>" and "Usage: ... {folder}"
    text = cli(name, "--help").stdout
    assert "<bool>" not in text, text
    usage = next(line for line in text.splitlines() if "Usage:" in line)
    assert "{" not in usage and "}" not in usage, usage


def test_run_quiet_keeps_the_notes(cli, tmp_path):
    # issue 50: --quiet hid every note, a missing mesh and the collision fallback included; its
    # help promised only "no progress bars and no tables"
    scene = tmp_path / "radians.yaml"
    scene.write_text(
        "version: 1\nname: radians\narm:\n  links: [1, 1]\n  home: [0.5, 1.2]\ngoals:\n  - [1.2, 0.8, 0]\n"
    )
    quiet = cli("run", scene, "--out", tmp_path / "out", "--no-video", "--quiet")
    assert quiet.exit_code == 0, quiet.output
    assert "arm.home: these angles look like radians" in quiet.stderr
    assert "goal" not in quiet.stdout  # the table stays out


def _at_80_columns(*args, cwd=None) -> str:
    """What the installed command prints (stdout and stderr) in an 80-column terminal."""
    import os
    import subprocess

    from runfolders import armanim_exe

    env = dict(os.environ, COLUMNS="80", TERM="xterm")
    done = subprocess.run(
        [armanim_exe(), *map(str, args)], capture_output=True, text=True, env=env, cwd=cwd, timeout=600
    )
    return done.stdout + done.stderr


def test_at_80_columns_help_names_robots_headers_and_batch_scenes_are_whole(tmp_path):
    """Issue 50's papercuts: ``ik --help`` cut ``--orientation-tolera…``, ``robots`` wrapped its
    header to the table's width, the batch table split ``panda-clutt / er``."""
    helped = _at_80_columns("ik", "--help")
    assert "--orientation-tolerance " in helped and "…" not in helped, helped
    listed = _at_80_columns("robots")
    header = next(line for line in listed.splitlines() if line.startswith("panda:"))
    assert header.rstrip().endswith("collision capsules") and len(header) <= 80, listed
    for name in ("planning-wall-long", "panda-clutter-long"):
        (tmp_path / f"{name}.yaml").write_text(
            f"version: 1\nname: {name}\narm: {{links: [1, 1]}}\ngoals: [[1.2, 0.8, 0]]\n"
        )
    batch = _at_80_columns(
        "run", "planning-wall-long.yaml", "panda-clutter-long.yaml", "--no-video", "--out", "o", cwd=tmp_path
    )
    assert "│ planning-wall-long │" in batch and "│ panda-clutter-long │" in batch, batch


def test_validate_never_rounds_two_different_values_into_one(tmp_path):
    """Issue 50: six digits made ``min must be below max (got [10, 10])`` and ``90 deg is outside
    [-90, 90]`` of values that differ; a message keeps the digits that tell them apart."""
    scene = tmp_path / "close.yaml"
    scene.write_text(
        "version: 1\narm:\n  links: [2, 5, 5, 5]\n  limits: [[-150, 150], [-90, 89.99999], [10.0000001, 10.00000001], null]\n"
        "  home: [0, 89.999995, 0, 0]\ngoals:\n  - [6, 0, 10]\n"
    )
    said = _at_80_columns("validate", scene)
    assert "arm.limits[2]: min must be below max (got [10.0000001, 10])" in said, said  # 10.00000001 < 10.0000001
    assert "89.999995 deg is outside joint 2's limits" in said and "[-90, 89.99999]" in said, said
