"""``armanim export --format joint-trajectory``: the run as a ROS JointTrajectory in JSON. The
round trip against the CSV itself (positions in radians, times equal time_s, the joints'
names), velocities from the dphi columns or, for older runs, central differences, and every
refusal with its exit code."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest

from armanim.output.jointtrajectory import MESSAGE_KEYS, POINT_KEYS
from armanim.output.rundir import MARKER, marked_files

LINKS = """\
version: 1
arm:
  links: [1, 1, 0.5]
goals:
  - [1, 0.5, 1]
  - position: [0.5, -1, 1.2]
    hold: 0.3
render:
  fps: 10
  size: [64, 48]
"""

PANDA = """\
version: 1
arm:
  robot: panda
goals:
  - [0.45, 0.1, 0.45]
render:
  fps: 10
  size: [64, 48]
"""


def solved_run(tmp_path: Path, cli, text: str, name: str = "tiny") -> Path:
    scene = tmp_path / f"{name}.yaml"
    scene.write_text(text, encoding="utf-8")
    result = cli("run", scene, "--no-video", "--quiet", "--out", tmp_path / "out")
    assert result.exit_code == 0, result.output
    return tmp_path / "out" / name


def csv_rows(folder: Path) -> tuple[list[str], list[dict]]:
    with open(folder / "trajectory.csv", newline="", encoding="utf-8") as handle:
        reader = csv.DictReader(handle)
        return list(reader.fieldnames), list(reader)


def seconds(duration: dict) -> float:
    assert set(duration) == {"sec", "nanosec"} and 0 <= duration["nanosec"] < 10**9
    return duration["sec"] + duration["nanosec"] * 1e-9


def assert_round_trip(message: dict, folder: Path, names: list[str]) -> None:
    """Positions equal the CSV's angles in radians, times its time_s (to the nanosecond), the
    message has exactly ROS's fields."""
    columns, rows = csv_rows(folder)
    n = len(names)
    assert tuple(message) == MESSAGE_KEYS and message["joint_names"] == names
    assert message["header"] == {"stamp": {"sec": 0, "nanosec": 0}, "frame_id": ""}
    assert len(message["points"]) == len(rows)
    for point, row in zip(message["points"], rows):
        assert tuple(point) == POINT_KEYS
        assert point["positions"] == [float(np.radians(float(row[f"phi{k}_deg"]))) for k in range(1, n + 1)]
        assert len(point["velocities"]) == n and point["accelerations"] == [] and point["effort"] == []
        assert abs(seconds(point["time_from_start"]) - float(row["time_s"])) <= 0.5e-9
    times = [seconds(p["time_from_start"]) for p in message["points"]]
    assert all(b > a for a, b in zip(times, times[1:]))


def test_link_arm_round_trip_into_the_run_folder(tmp_path, cli):
    folder = solved_run(tmp_path, cli, LINKS)
    result = cli("export", folder, "--format", "joint-trajectory")
    assert result.exit_code == 0, result.output
    path = folder / "joint_trajectory.json"
    assert result.stdout.strip() == str(path)
    message = json.loads(path.read_text(encoding="utf-8"))
    assert_round_trip(message, folder, ["phi1", "phi2", "phi3"])
    assert "joint_trajectory.json" in marked_files(folder)  # armanim's file: the next run replaces the folder whole
    rerun = cli("run", tmp_path / "tiny.yaml", "--no-video", "--quiet", "--out", tmp_path / "out")
    assert rerun.exit_code == 0, rerun.output


def test_urdf_arm_names_its_joints(tmp_path, cli):
    folder = solved_run(tmp_path, cli, PANDA, "ptiny")
    out = tmp_path / "elsewhere" / "panda.json"
    result = cli("export", folder, "--out", out)
    assert result.exit_code == 0, result.output
    assert_round_trip(json.loads(out.read_text()), folder, [f"panda_joint{k}" for k in range(1, 8)])
    assert not (folder / "joint_trajectory.json").exists()
    again = cli("export", folder, "--out", out)  # an exported trajectory is replaced
    assert again.exit_code == 0, again.output


def test_velocities_of_a_run_without_velocity_columns_are_central_differences(tmp_path, cli):
    folder = solved_run(tmp_path, cli, LINKS)
    columns, rows = csv_rows(folder)
    if any(c.startswith("dphi") for c in columns):  # this armanim logs the clock's velocities: drop them, as an old run
        kept = [c for c in columns if not c.startswith("dphi")]
        with open(folder / "trajectory.csv", "w", newline="", encoding="utf-8") as handle:
            writer = csv.DictWriter(handle, kept, extrasaction="ignore", lineterminator="\n")
            writer.writeheader()
            writer.writerows(rows)
    out = tmp_path / "old.json"
    assert cli("export", folder, "--out", out).exit_code == 0
    message = json.loads(out.read_text())
    t = np.array([float(r["time_s"]) for r in rows])
    phi = np.radians([[float(r[f"phi{k}_deg"]) for k in (1, 2, 3)] for r in rows])
    velocities = np.array([p["velocities"] for p in message["points"]])
    for i in range(1, len(rows) - 1):  # inside: (phi[i+1] - phi[i-1]) / (t[i+1] - t[i-1]) on these even steps
        np.testing.assert_allclose(
            velocities[i], (phi[i + 1] - phi[i - 1]) / (t[i + 1] - t[i - 1]), rtol=1e-9, atol=1e-12
        )
    np.testing.assert_allclose(velocities[0], (phi[1] - phi[0]) / (t[1] - t[0]), rtol=1e-9, atol=1e-12)


def test_velocity_columns_are_used_when_present(tmp_path, cli):
    """A run with ``dphiK_deg_s`` columns exports those, in rad/s (not a finite difference)."""
    folder = solved_run(tmp_path, cli, LINKS)
    columns, rows = csv_rows(folder)
    new = [c for c in columns if not c.startswith("dphi")] + ["dphi1_deg_s", "dphi2_deg_s", "dphi3_deg_s"]
    for i, row in enumerate(rows):
        row.update({"dphi1_deg_s": repr(float(i)), "dphi2_deg_s": "-90.0", "dphi3_deg_s": "0.0"})
    with open(folder / "trajectory.csv", "w", newline="", encoding="utf-8") as handle:
        writer = csv.DictWriter(handle, new, extrasaction="ignore", lineterminator="\n")
        writer.writeheader()
        writer.writerows(rows)
    out = tmp_path / "v.json"
    assert cli("export", folder, "--out", out).exit_code == 0
    velocities = np.array([p["velocities"] for p in json.loads(out.read_text())["points"]])
    np.testing.assert_allclose(velocities[:, 0], np.radians(np.arange(len(rows), dtype=float)), rtol=1e-15)
    np.testing.assert_allclose(velocities[:, 1], -np.pi / 2, rtol=1e-15)
    # some velocity columns but not all: a clear error, nothing written
    with open(folder / "trajectory.csv", "w", newline="", encoding="utf-8") as handle:
        writer = csv.DictWriter(handle, new[:-1], extrasaction="ignore", lineterminator="\n")
        writer.writeheader()
        writer.writerows(rows)
    bad = cli("export", folder, "--out", tmp_path / "partial.json")
    assert bad.exit_code == 2 and "dphi3_deg_s" in bad.stderr and not (tmp_path / "partial.json").exists()


@pytest.mark.parametrize("case", ["missing", "not-a-run", "format", "inside", "foreign", "folder"])
def test_refusals(tmp_path, cli, case):
    folder = solved_run(tmp_path, cli, LINKS)
    before = {p.name: p.read_bytes() for p in folder.iterdir() if p.is_file()}
    foreign = tmp_path / "notes.json"
    foreign.write_text('{"mine": true}\n', encoding="utf-8")
    args, code, fragment = {
        "missing": ((tmp_path / "nope",), 2, "no such folder"),
        "not-a-run": ((tmp_path,), 2, "is not a complete armanim run"),
        "format": (
            (folder, "--format", "csv"),
            2,
            "--format 'csv' is not a format armanim exports (expected one of: joint-trajectory)",
        ),
        "inside": ((folder, "--out", folder / "mine.json"), 2, "is inside the run folder"),
        "foreign": ((folder, "--out", foreign), 3, "is a file armanim did not write (no mark"),
        "folder": ((folder, "--out", tmp_path / "out"), 3, "is a folder"),
    }[case]
    result = cli("export", *args)
    assert result.exit_code == code, result.output
    assert fragment in result.stderr and "Traceback" not in result.output
    assert {p.name: p.read_bytes() for p in folder.iterdir() if p.is_file()} == before  # the run is as it was
    assert foreign.read_text() == '{"mine": true}\n'
    assert not (folder / "mine.json").exists() and MARKER in before


USERS_OWN = (
    '{"header": {"stamp": {"sec": 0, "nanosec": 0}, "frame_id": "base"}, "joint_names": ["my_joint"], '
    '"points": [{"positions": [0.5], "velocities": [], "accelerations": [], "effort": [], '
    '"time_from_start": {"sec": 1, "nanosec": 0}}]}\n'
)


def test_export_replaces_only_the_file_it_marked_and_never_a_users_trajectory(tmp_path, cli):
    """A user's own JointTrajectory (the message's keys, in order), a link to it, a file deeply
    nested JSON: exit 3, each left as it was (issue 50, items 5 and 6). An export armanim wrote
    there (its mark beside it) is replaced; edited since, it is the user's again."""
    import os

    folder = solved_run(tmp_path, cli, LINKS)
    mine = tmp_path / "mine"
    mine.mkdir()
    recorded = mine / "recorded.json"
    recorded.write_text(USERS_OWN, encoding="utf-8")
    (mine / "link.json").symlink_to(recorded)
    deep = mine / "deep.json"
    deep.write_text('{"header": ' + "[" * 200_000 + "]" * 200_000 + "}", encoding="utf-8")
    for target, fragment in (
        (recorded, "is a file armanim did not write (no mark .recorded.json.armanim.json"),
        (mine / "link.json", "is a link, which armanim does not write through"),
        (deep, "is a file armanim did not write"),
    ):
        before = target.read_bytes()
        result = cli("export", folder, "--out", target)
        assert result.exit_code == 3, result.output
        assert fragment in result.stderr and "Traceback" not in result.output
        assert target.read_bytes() == before and recorded.read_text(encoding="utf-8") == USERS_OWN
    assert sorted(p.name for p in mine.iterdir()) == ["deep.json", "link.json", "recorded.json"]
    # armanim's own export at --out: marked, and replaced by the next export
    exported = mine / "exported.json"
    assert cli("export", folder, "--out", exported).exit_code == 0
    mark = json.loads((mine / ".exported.json.armanim.json").read_text())
    assert mark["generator"] == "armanim" and mark["bytes"] == exported.stat().st_size
    assert tuple(json.loads(exported.read_text())) == MESSAGE_KEYS  # the message itself holds no key of armanim's
    assert cli("export", folder, "--out", exported).exit_code == 0
    exported.write_text(exported.read_text().replace('"frame_id": ""', '"frame_id": "base"'))  # the user edits it
    edited = exported.read_bytes()
    result = cli("export", folder, "--out", exported)
    assert result.exit_code == 3 and "has changed since armanim exported it" in result.stderr
    assert exported.read_bytes() == edited
    # a deeply nested file where the mark goes: not armanim's mark, no traceback
    (mine / ".fresh.json.armanim.json").write_text("[" * 200_000 + "]" * 200_000)
    result = cli("export", folder, "--out", mine / "fresh.json")
    assert result.exit_code == 3 and "is not a mark armanim wrote" in result.stderr and "Traceback" not in result.output
    assert not (mine / "fresh.json").exists()
    assert os.path.islink(mine / "link.json")


def test_export_into_another_run_folder_is_refused(tmp_path, cli):
    """``export RUN_A --out RUN_B/joint_trajectory.json``: exit 2, naming RUN_B (a file there
    would stop RUN_B's next run: issue 50, item 7); RUN_B's next run goes on."""
    first = solved_run(tmp_path, cli, LINKS, "a")
    second = solved_run(tmp_path, cli, LINKS, "b")
    for target in (second / "joint_trajectory.json", second / "sub" / "x.json"):
        result = cli("export", first, "--out", target)
        assert result.exit_code == 2, result.output
        assert "is inside the run folder" in result.stderr and str(second) in result.stderr
    assert sorted(p.name for p in second.iterdir()) == sorted([*marked_files(second), MARKER])
    rerun = cli("run", tmp_path / "b.yaml", "--no-video", "--quiet", "--out", tmp_path / "out")
    assert rerun.exit_code == 0, rerun.output


def test_a_marked_file_is_replaced_only_by_a_file_of_its_kind(tmp_path, cli):
    """Campaign 9: ``export A --out OUT/index.csv`` replaced a batch's table (armanim's, marked) with
    a trajectory, exit 0, and the next batch then stopped (exit 3, "a file of yours"); ``schema --out``
    and ``fk --png`` replaced an export the same way. A mark now records what armanim wrote, and a file
    is replaced only by one of its kind (exit 3 otherwise, every byte left); the batch goes on."""
    scenes = [tmp_path / f"{name}.yaml" for name in ("a", "b")]
    for scene in scenes:
        scene.write_text(LINKS, encoding="utf-8")
    out = tmp_path / "out"
    assert cli("run", *scenes, "--no-video", "--quiet", "--out", out, "--jobs", "1").exit_code == 0
    index = out / "index.csv"
    table = index.read_bytes()
    result = cli("export", out / "a", "--out", index)
    assert result.exit_code == 3 and "is a file armanim wrote as its index.csv, not as its export" in result.stderr, (
        result.output
    )
    assert index.read_bytes() == table
    exported = tmp_path / "exported.json"
    assert cli("export", out / "a", "--out", exported).exit_code == 0
    trajectory = exported.read_bytes()
    for args in (("schema", "--out", exported), ("fk", "--angles", "0,10,20", "--png", exported)):
        result = cli(*args)
        assert result.exit_code == 3 and "as its export, not as its" in result.stderr, result.output
        assert exported.read_bytes() == trajectory
    assert cli("export", out / "b", "--out", exported).exit_code == 0  # its own kind: replaced
    again = cli("run", *scenes, "--no-video", "--quiet", "--out", out, "--jobs", "1")
    assert again.exit_code == 0, again.output


def test_nothing_is_exported_into_a_folder_a_run_would_remove(tmp_path, cli):
    """Campaign 5: ``export A --out OUT/.b.abcdefgh.partial/x.json`` (a folder named as run b's staging
    folder) wrote there, exit 0, and the next run of b removed the folder with the export in it.
    Such a folder, or a moved-aside ``.b.old-PID``, is now refused as a run folder is (exit 2)."""
    first = solved_run(tmp_path, cli, LINKS, "a")
    for name in (".b.abcdefgh.partial", ".b.old-42"):
        result = cli("export", first, "--out", tmp_path / "out" / name / "x.json")
        assert result.exit_code == 2 and "named as a run's staging or moved-aside folder" in result.stderr, (
            result.output
        )
        assert not (tmp_path / "out" / name).exists()


def test_an_unlimited_joint_turning_past_180_degrees_is_exported_without_a_jump(tmp_path, cli):
    """Campaign 10: trajectory.csv writes an unlimited joint's angle wrapped to (-180, 180], and
    the export gave the same positions: joint 1 went 191.9 -> -168.1 degrees between two points
    of 1/10 s while its velocity said +25 deg/s, so a controller interpolating the positions would
    turn it a full turn back within a frame. The export's positions go on past 180, the way the
    joint turned; each step is the CSV's, wrapped, and agrees with the velocities."""
    folder = solved_run(
        tmp_path,
        cli,
        LINKS.replace("  links: [1, 1, 0.5]\n", "  links: [1, 1, 0.5]\n  home: [170, 45, 45]\n").replace(
            "  - [1, 0.5, 1]\n  - position: [0.5, -1, 1.2]\n    hold: 0.3\n", "  - [-1.1, -0.3, 0.8]\n"
        ),
    )
    out = tmp_path / "w.json"
    assert cli("export", folder, "--out", out).exit_code == 0
    points = json.loads(out.read_text())["points"]
    positions = np.degrees([p["positions"] for p in points])
    velocities = np.degrees([p["velocities"] for p in points])
    times = np.array([seconds(p["time_from_start"]) for p in points])
    _, rows = csv_rows(folder)
    wrapped = np.array([[float(r[f"phi{k}_deg"]) for k in (1, 2, 3)] for r in rows])
    assert np.abs(np.diff(wrapped[:, 0])).max() > 180  # the CSV's wrap is there (the scene does cross 180)
    steps = np.diff(positions, axis=0)
    assert np.abs(steps).max() < 30
    assert np.allclose(steps, np.mod(np.diff(wrapped, axis=0) + 180, 360) - 180, atol=1e-9)
    assert np.allclose(np.mod(positions - wrapped + 180, 360) - 180, 0, atol=1e-9)  # the same poses
    speeds = steps / np.diff(times)[:, None]
    assert np.abs(speeds - velocities[1:]).max() < 100  # no step contradicts the velocities by a full turn
