"""The run folder of a self-collision run: it says what was checked and reloads with its SRDF,
and `self_collision: off` leaves the self columns empty."""

from __future__ import annotations

import pytest
from test_self_collision_fields import chain_urdf, scene_dict, write_scene


def test_run_folder_says_what_was_checked_and_reloads_with_its_srdf(cli, tmp_path):
    import csv
    import json
    import shutil

    import yaml

    from armanim.runs.reload import load_run

    (tmp_path / "chain.urdf").write_text(chain_urdf())
    (tmp_path / "chain.srdf").write_text(
        '<robot name="chain">\n'
        + "".join(f'  <disable_collisions link1="l{k}" link2="l{k + 1}" reason="Adjacent"/>\n' for k in range(4))
        + '  <disable_collisions link1="l0" link2="l4" reason="Never"/>\n</robot>\n'
    )
    scene = {
        "version": 1,
        "name": "chain",
        "arm": {"urdf": "chain.urdf", "self_collision": {"srdf": "chain.srdf"}, "home": [0, 20, 0, 20, 0]},
        "goals": [[0.3, 0.2, 0.9]],
        "solver": {"max_frames_per_goal": 60},
    }
    path = write_scene(tmp_path, scene)
    assert cli("run", path, "--out", tmp_path / "out", "--no-video", "-q").exit_code == 0
    folder = tmp_path / "out" / "chain"
    matrix = yaml.safe_load((folder / "self-collision.yaml").read_text())
    assert matrix["mode"] == "srdf" and ["l0", "l4", "Never"] in matrix["allowed"] and ["l0", "l2"] in matrix["enabled"]
    summary = json.loads((folder / "summary.json").read_text())
    assert summary["self_collision"] == {
        "mode": "srdf",
        "self_clearance": pytest.approx(0.005),
        "enabled_pairs": len(matrix["enabled"]),
        "allowed_pairs": 5,
    }
    rows = list(csv.DictReader((folder / "trajectory.csv").open()))
    n = sum(c.startswith("dphi") for c in rows[0])  # the joints' velocities come last
    assert list(rows[0])[-4 - n : -2 - n] == ["self_clearance", "self_pair"] and n == sum(
        c.startswith("phi") for c in rows[0]
    )
    least = min(float(r["self_clearance"]) for r in rows)
    assert least == summary["min_self_clearance"] >= 0.005
    assert summary["min_self_pair"] in {r["self_pair"] for r in rows}
    assert (folder / "robot.srdf").read_bytes() == (tmp_path / "chain.srdf").read_bytes()
    moved = shutil.move(str(folder), str(tmp_path / "elsewhere"))  # the user's files no longer beside it
    (tmp_path / "chain.srdf").unlink()
    run = load_run(moved)
    # the CSV holds degrees: the reloaded radians are the run's to the last bit or two, and so is the least gap
    assert run.problem.self_pairs.mode == "srdf" and run.solution.trajectory.self_clearance.min() == pytest.approx(
        least, rel=0, abs=1e-12
    )


def test_off_leaves_the_self_columns_empty(cli, tmp_path):
    import csv
    import json

    path = write_scene(tmp_path, scene_dict(self_collision="off"))
    assert cli("run", path, "--out", tmp_path / "out", "--no-video", "-q").exit_code == 0
    folder = tmp_path / "out" / "scene"
    rows = list(csv.DictReader((folder / "trajectory.csv").open()))
    assert all(r["self_clearance"] == "" and r["self_pair"] == "" for r in rows)
    summary = json.loads((folder / "summary.json").read_text())
    assert summary["min_self_clearance"] is None and summary["self_collision"]["mode"] == "off"
    assert "enabled: []" in (folder / "self-collision.yaml").read_text()
