"""Golden trajectories: armanim's own suite (every bundled scene) and the compare/check
commands that users put in their CI."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest
from typer.testing import CliRunner

from armanim.cli import app
from armanim.testing import assert_trajectory_matches

ROOT = Path(__file__).resolve().parents[2]
SCENES = sorted((ROOT / "scenes").glob("*.yaml"))
GOLDEN = Path(__file__).resolve().parents[1] / "golden"
runner = CliRunner()


@pytest.mark.parametrize("scene", SCENES, ids=lambda p: p.stem)
def test_bundled_scene_matches_its_golden_trajectory(scene):
    # Regenerate after a deliberate change: armanim check scenes/*.yaml --golden tests/golden --update
    assert_trajectory_matches(scene, GOLDEN / f"{scene.stem}.csv", atol_deg=1e-6, atol=1e-6)


def test_every_bundled_scene_has_a_golden_file():
    assert {p.stem for p in SCENES} == {p.stem for p in GOLDEN.glob("*.csv")}


def _csv(tmp_path, name, text):
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


@pytest.fixture
def golden_csv():
    return GOLDEN / "out-of-reach.csv"


def _edit_line(text: str, line: int, column: str, value: str) -> str:
    rows = text.splitlines()
    header = rows[0].split(",")
    fields = rows[line].split(",")
    fields[header.index(column)] = value
    rows[line] = ",".join(fields)
    return "\n".join(rows) + "\n"


def test_compare_identical_files_exit_0(golden_csv):
    result = runner.invoke(app, ["compare", str(golden_csv), str(golden_csv)])
    assert result.exit_code == 0
    assert "trajectories agree" in result.output


def test_compare_names_first_differing_frame_and_column(tmp_path, golden_csv):
    text = golden_csv.read_text()
    changed = _csv(tmp_path, "changed.csv", _edit_line(text, 41, "phi3_deg", "12.5"))
    result = runner.invoke(app, ["compare", str(golden_csv), str(changed)])
    assert result.exit_code == 1
    assert "first difference: frame 40, column phi3_deg" in result.output
    assert "actual 12.5" in result.output
    assert "phi3_deg:" in result.output.split("largest deviation")[1]


def test_compare_respects_tolerances(tmp_path, golden_csv):
    text = golden_csv.read_text()
    original = float(text.splitlines()[11].split(",")[3])
    nudged = _csv(tmp_path, "nudged.csv", _edit_line(text, 11, "phi1_deg", repr(original + 1e-4)))
    assert runner.invoke(app, ["compare", str(golden_csv), str(nudged)]).exit_code == 1
    assert runner.invoke(app, ["compare", str(golden_csv), str(nudged), "--atol-deg", "1e-3"]).exit_code == 0


def test_compare_changed_position_column(tmp_path, golden_csv):
    text = golden_csv.read_text()
    changed = _csv(tmp_path, "x.csv", _edit_line(text, 5, "x", "99.0"))
    result = runner.invoke(app, ["compare", str(golden_csv), str(changed)])
    assert result.exit_code == 1
    assert "frame 4, column x" in result.output


def test_compare_different_lengths_says_so_plainly(tmp_path, golden_csv):
    rows = golden_csv.read_text().splitlines()
    shorter = _csv(tmp_path, "short.csv", "\n".join(rows[:-14]) + "\n")
    result = runner.invoke(app, ["compare", str(golden_csv), str(shorter)])
    assert result.exit_code == 1
    assert f"expected {len(rows) - 1} frames, got {len(rows) - 15}" in result.output


def test_compare_different_joint_counts_is_bad_input():
    result = runner.invoke(app, ["compare", str(GOLDEN / "notes-arm.csv"), str(GOLDEN / "singular-start.csv")])
    assert result.exit_code == 2
    assert "has 3 joints" in result.output and "has 4" in result.output


@pytest.mark.parametrize(
    "content",
    ["", "not,a,trajectory\n1,2,3\n", "\x00\x01binary", "frame,time_s,goal,phi1_deg\n0,0.0,0,abc\n"],
    ids=["empty", "other-csv", "binary", "non-number"],
)
def test_compare_garbage_is_bad_input(tmp_path, golden_csv, content):
    garbage = _csv(tmp_path, "garbage.csv", content)
    result = runner.invoke(app, ["compare", str(golden_csv), str(garbage)])
    assert result.exit_code == 2
    assert "garbage.csv" in result.output
    assert "Traceback" not in result.output


def test_compare_missing_file_is_bad_input(tmp_path, golden_csv):
    result = runner.invoke(app, ["compare", str(golden_csv), str(tmp_path / "nope.csv")])
    assert result.exit_code == 2
    assert "no such file" in result.output


def test_check_update_then_check_passes_then_scene_edit_fails(tmp_path):
    scene = tmp_path / "reach.yaml"
    shutil.copy(ROOT / "scenes" / "out-of-reach.yaml", scene)
    golden = tmp_path / "golden"
    first = runner.invoke(app, ["check", str(scene), "--golden", str(golden), "--update"])
    assert first.exit_code == 0 and "new" in first.output
    again = runner.invoke(app, ["check", str(scene), "--golden", str(golden), "--update"])
    assert "unchanged" in again.output
    assert runner.invoke(app, ["check", str(scene), "--golden", str(golden)]).exit_code == 0

    scene.write_text(scene.read_text().replace("[10, 9, 7]", "[10, 8, 7]"))
    failed = runner.invoke(app, ["check", str(scene), "--golden", str(golden)])
    assert failed.exit_code == 1
    assert "fail" in failed.output
    assert "changed since the golden file was written" in failed.output

    updated = runner.invoke(app, ["check", str(scene), "--golden", str(golden), "--update"])
    assert "changed" in updated.output
    assert runner.invoke(app, ["check", str(scene), "--golden", str(golden)]).exit_code == 0


def test_two_updates_of_one_golden_folder_take_turns_and_leave_no_lock_file(tmp_path):
    import threading

    from armanim.output.rundir import directory_lock
    from armanim.runs.golden import update_golden
    from armanim.scene import load_scene

    golden = tmp_path / "golden"
    done = threading.Event()
    with directory_lock(golden):  # another `check --update` of this folder is writing
        worker = threading.Thread(
            target=lambda: (update_golden(load_scene(ROOT / "scenes" / "out-of-reach.yaml"), golden), done.set())
        )
        worker.start()
        assert not done.wait(1.0)  # it waits for the folder (a solve of this scene takes ~0.1 s)
        assert not list(golden.iterdir())
    worker.join(timeout=120)  # a hang guard
    assert done.is_set()
    assert sorted(p.name for p in golden.iterdir()) == ["out-of-reach.csv", "out-of-reach.json"]


def test_check_without_golden_file_fails(tmp_path):
    result = runner.invoke(app, ["check", str(ROOT / "scenes" / "out-of-reach.yaml"), "--golden", str(tmp_path)])
    assert result.exit_code == 1
    assert "missing" in result.output


def test_assert_trajectory_matches_raises_with_report(tmp_path, golden_csv):
    text = golden_csv.read_text()
    changed = _csv(tmp_path, "changed.csv", _edit_line(text, 3, "phi2_deg", "7.0"))
    with pytest.raises(AssertionError, match="first difference: frame 2, column phi2_deg"):
        assert_trajectory_matches(ROOT / "scenes" / "out-of-reach.yaml", changed)


def test_assert_trajectory_matches_finds_the_golden_file_by_the_scenes_name(tmp_path):
    # the file is named after `name:`, not the file's stem: give the folder, as the docs do
    scene = tmp_path / "renamed-file.yaml"
    scene.write_text((ROOT / "scenes" / "out-of-reach.yaml").read_text(encoding="utf-8"), encoding="utf-8")
    assert_trajectory_matches(scene, GOLDEN, atol_deg=1e-6, atol=1e-6)
    with pytest.raises(AssertionError, match="first difference"):
        assert_trajectory_matches(scene, GOLDEN / "planar-nlink.csv")


def test_check_quiet_prints_nothing_when_every_trajectory_matches(tmp_path):
    scene = ROOT / "scenes" / "out-of-reach.yaml"
    quiet = runner.invoke(app, ["check", str(scene), "--golden", str(GOLDEN), "--quiet"])
    assert quiet.exit_code == 0 and quiet.stdout == "", quiet.output
    other = tmp_path / "golden"
    other.mkdir()
    shutil.copy(GOLDEN / "planar-nlink.csv", other / "out-of-reach.csv")
    failed = runner.invoke(app, ["check", str(scene), "--golden", str(other), "-q"])
    assert failed.exit_code == 1 and "out-of-reach:" in failed.stdout and "golden trajectories in" not in failed.stdout


def test_a_pass_with_an_edited_scene_says_the_scene_changed(tmp_path):
    # before: `pass` and nothing else, so the golden file seemed to describe the edited scene
    scene = tmp_path / "reach.yaml"
    shutil.copy(ROOT / "scenes" / "out-of-reach.yaml", scene)
    golden = tmp_path / "golden"
    assert runner.invoke(app, ["check", str(scene), "--golden", str(golden), "--update"]).exit_code == 0

    def table_text(result) -> str:  # the table's cells wrap at the terminal's width
        return " ".join(re.sub(r"[│┃]", " ", result.output).split())

    clean = runner.invoke(app, ["check", str(scene), "--golden", str(golden)])
    assert clean.exit_code == 0 and "scene changed" not in table_text(clean)
    scene.write_text(scene.read_text() + "# a comment: the trajectory stays the same\n")
    edited = runner.invoke(app, ["check", str(scene), "--golden", str(golden)])
    assert edited.exit_code == 0, edited.output
    assert re.search(r"pass \(scene changed since .*the golden .*file; .*--update .*records .*it\)", table_text(edited))
    assert runner.invoke(app, ["check", str(scene), "--golden", str(golden), "--update"]).exit_code == 0
    assert "scene changed" not in table_text(runner.invoke(app, ["check", str(scene), "--golden", str(golden)]))


def test_the_pytest_helper_says_the_scene_changed_in_its_failure(tmp_path):
    from armanim.testing import assert_trajectory_matches

    scene = tmp_path / "reach.yaml"
    shutil.copy(ROOT / "scenes" / "out-of-reach.yaml", scene)
    golden = tmp_path / "golden"
    assert runner.invoke(app, ["check", str(scene), "--golden", str(golden), "--update"]).exit_code == 0
    assert_trajectory_matches(scene, golden)  # the same scene: passes, no note needed
    scene.write_text(scene.read_text().replace("[10, 9, 7]", "[10, 8, 7]"))
    for where in (golden, golden / "out-of-reach.csv"):  # the folder or the file itself
        with pytest.raises(AssertionError) as info:
            assert_trajectory_matches(scene, where)
        assert "note: reach.yaml changed since the golden file was written" in str(info.value)
        assert "--update records it" in str(info.value)
