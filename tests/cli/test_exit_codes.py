"""The contract's exit codes (README): 0 done, 1 a check failed, 2 bad input or usage,
3 output could not be written; and the scene's errors survive the way back from a worker.

Each test is named in the table of docs/reliability.md, which it keeps true.
"""

from __future__ import annotations

import pytest
from conftest import SCENES
from runfolders import one_line_error

from armanim.errors import SceneError
from armanim.scene import validate_scene_text

PLANAR = SCENES / "planar-nlink.yaml"


SMALL = "version: 1\narm:\n  links: [1, 1]\ngoals:\n  - [1, 0, 0]\n"


def test_exit_0_success(cli):
    result = cli("validate", PLANAR)
    assert result.exit_code == 0 and "ok" in result.stdout


def test_exit_1_check_failed(cli, tmp_path):
    header = "frame,time_s,goal,phi1_deg,x,y,z,goal_distance,clearance,reached\n"
    (tmp_path / "a.csv").write_text(header + "0,0.0,0,0.0,1.0,0.0,0.0,1.0,,0\n")
    (tmp_path / "b.csv").write_text(header + "0,0.0,0,5.0,1.0,0.0,0.0,1.0,,0\n")
    result = cli("compare", tmp_path / "a.csv", tmp_path / "b.csv")
    assert result.exit_code == 1, result.output
    assert "phi1_deg" in result.output


@pytest.mark.parametrize(
    "args", [("validate", "MISSING"), ("run", "SCENE", "--size", "huge"), ("fk", "--angles", "a,b")]
)
def test_exit_2_bad_input_or_usage(cli, tmp_path, args):
    (tmp_path / "bad.yaml").write_text(SMALL.replace("[1, 1]", "[1, -1]"))
    args = [
        str(tmp_path / "missing.yaml") if a == "MISSING" else str(tmp_path / "bad.yaml") if a == "SCENE" else a
        for a in args
    ]
    result = cli(*args)
    assert result.exit_code == 2, result.output
    assert "Traceback" not in result.output and result.stderr.strip()


def test_exit_3_output_folder_is_a_file(cli, tmp_path):
    blocker = tmp_path / "out"
    blocker.write_text("not a folder\n")
    result = cli("run", PLANAR, "--out", blocker, "--no-video", "--quiet")
    assert result.exit_code == 3, result.output
    assert "a file stands where a folder is needed" in one_line_error(result)
    assert blocker.read_text() == "not a folder\n"


def test_scene_error_survives_pickling():
    """Batch workers send SceneErrors back to the parent pickled."""
    import pickle

    with pytest.raises(SceneError) as info:
        validate_scene_text(SMALL.replace("[1, 1]", "[1, -1]"), "bad.yaml")
    again = pickle.loads(pickle.dumps(info.value))
    assert again.report() == info.value.report() and again.problems == info.value.problems


@pytest.mark.parametrize(
    "args",
    [
        ("schema", "--out", "{d}/figures/"),
        ("fk", "--angles", "0,30,45,10", "--png", "{d}/figures/"),
        ("export", "{d}/run", "--out", "{d}/figures/"),
        ("view", "{d}/run", "--out", "{d}/figures/"),
        ("import", "moveit", "{d}/w.scene", "--robot", "panda", "--out", "{d}/figures/"),
    ],
)
def test_a_file_named_with_a_trailing_slash_is_a_usage_error(cli, tmp_path, args):
    """Campaign 9: ``export --out exports/`` (a folder meant) wrote a file named ``exports``, exit 0;
    so did every option that names a file to write. Now exit 2, and nothing is made."""
    result = cli(*(a.replace("{d}", str(tmp_path)) for a in args))
    assert result.exit_code == 2, result.output
    assert "ends with '/', so it names a folder: give a file's name" in " ".join(result.output.split())
    assert list(tmp_path.iterdir()) == []
