"""The run folder's rules (issue 19): a user's file or folder at a listed name stops the next run,
`render --out` writes only into a new, empty or armanim folder, `render` refuses a scene or goal
that is not the run's, full disks and dangling links are named as such.

Each test is named in docs/reliability.md, which it keeps true.
"""

from __future__ import annotations

import errno
import json
import os
from pathlib import Path

import pytest
from conftest import SCENES
from runfolders import SMALL, small_scene
from signals import snapshot

from armanim.output.rundir import MARKER

NOTES = SCENES / "notes-arm.yaml"


@pytest.fixture()
def finished_run(cli, tmp_path) -> Path:
    assert cli("run", small_scene(tmp_path, "r"), "--out", tmp_path / "out", "--no-video", "-q").exit_code == 0
    return tmp_path / "out" / "r"


def test_render_out_writes_only_into_a_new_empty_or_armanim_folder(cli, tmp_path, finished_run):
    figures = tmp_path / "figures"
    figures.mkdir()
    (figures / "plot.png").write_text("my figure")
    beside = sorted(p.name for p in tmp_path.iterdir())
    result = cli("render", finished_run, "--out", figures, "-q", "--jobs", "1")
    assert result.exit_code == 3 and "not made by armanim" in result.stderr and "plot.png" in result.stderr
    assert (
        sorted(p.name for p in figures.iterdir()) == ["plot.png"] and (figures / "plot.png").read_text() == "my figure"
    )
    assert sorted(p.name for p in tmp_path.iterdir()) == beside  # the sixth campaign: a .figures.lock was made first
    fresh = tmp_path / "fresh"
    for _ in range(2):  # a new folder, then the folder armanim marked: replaced
        assert cli("render", finished_run, "--out", fresh, "-q", "--jobs", "1").exit_code == 0
    assert sorted(p.name for p in fresh.iterdir()) == [MARKER, "animation.mp4", "plot.png", "poster.png"]


def test_render_out_inside_the_run_folder_is_refused(cli, finished_run):
    before = snapshot(finished_run)
    result = cli("render", finished_run, "--out", finished_run / "small", "-q", "--jobs", "1")
    assert result.exit_code == 2 and "is inside the run folder" in result.stderr, result.output
    assert snapshot(finished_run) == before


def test_a_user_folder_at_a_listed_name_stops_the_next_run(cli, tmp_path, finished_run):
    (finished_run / "summary.json").unlink()
    (finished_run / "summary.json").mkdir()
    (finished_run / "summary.json" / "notes.txt").write_text("notes")
    result = cli("run", tmp_path / "r.yaml", "--out", tmp_path / "out", "--no-video", "-q")
    assert result.exit_code == 3, result.output
    assert "changed since armanim wrote them (summary.json" in result.stderr
    assert (finished_run / "summary.json" / "notes.txt").read_text() == "notes"


def test_a_listed_file_edited_since_stops_the_next_run(cli, tmp_path, finished_run):
    with (finished_run / "trajectory.csv").open("a") as handle:
        handle.write("# my note\n")
    before = snapshot(finished_run)
    result = cli("run", tmp_path / "r.yaml", "--out", tmp_path / "out", "--no-video", "-q")
    assert result.exit_code == 3 and "trajectory.csv" in result.stderr, result.output
    assert snapshot(finished_run) == before


@pytest.mark.parametrize("name", ["trajectory.csv", "summary.json"])
def test_a_listed_file_edited_with_its_size_and_time_kept_stops_the_next_run(cli, tmp_path, finished_run, name):
    # campaign 18: a digit changed in place and the time put back (touch -r; or an edit within the
    # second on a disk of 1 s times) was replaced by the next run, exit 0: the marker held size and time only
    path = finished_run / name
    before_stat = path.stat()
    data = bytearray(path.read_bytes())
    at = max(i for i, byte in enumerate(data) if chr(byte).isdigit())
    data[at] = ord("7") if data[at] != ord("7") else ord("3")
    path.write_bytes(bytes(data))
    os.utime(path, ns=(before_stat.st_atime_ns, before_stat.st_mtime_ns))
    assert (path.stat().st_size, path.stat().st_mtime_ns) == (before_stat.st_size, before_stat.st_mtime_ns)
    before = snapshot(finished_run)
    result = cli("run", tmp_path / "r.yaml", "--out", tmp_path / "out", "--no-video", "-q")
    assert result.exit_code == 3 and f"changed since armanim wrote them ({name}" in result.stderr, result.output
    assert snapshot(finished_run) == before


def test_a_marker_without_digests_still_lets_the_next_run_replace_its_unchanged_folder(cli, tmp_path, finished_run):
    marker = json.loads((finished_run / MARKER).read_text())
    assert all(len(stamp["sha256"]) == 64 for stamp in marker["files"].values())
    for stamp in marker["files"].values():  # as an armanim before 2026-12-07 wrote it
        del stamp["sha256"]
    (finished_run / MARKER).write_text(json.dumps(marker))
    result = cli("run", tmp_path / "r.yaml", "--out", tmp_path / "out", "--no-video", "-q")
    assert result.exit_code == 0, result.output


@pytest.mark.parametrize("marker", ['{"made_by": "armanim", "files": null}', "not json"])
def test_an_unreadable_marker_is_named_as_such(cli, tmp_path, finished_run, marker):
    (finished_run / MARKER).write_text(marker)
    result = cli("run", tmp_path / "r.yaml", "--out", tmp_path / "out", "--no-video", "-q")
    assert result.exit_code == 3 and f"its {MARKER} cannot be read as armanim's marker" in result.stderr, result.output
    assert "no .armanim-run.json" not in result.stderr


def test_render_refuses_a_scene_yaml_that_is_not_the_run_s(cli, finished_run):
    (finished_run / "scene.yaml").write_text(SMALL.replace("[1, 1, 2]", "[1, 2, 1]") + "name: r\n")
    result = cli("render", finished_run, "-q", "--jobs", "1")
    assert result.exit_code == 2 and "scene.yaml: is not the scene this run solved" in result.stderr, result.output


@pytest.mark.parametrize(
    "column, value, message",
    [("goal", "1", "goal: 1 is not a goal of the scene (expected 0 to 0)"), ("time_s", "-5", "time_s: -5 is negative")],
)
def test_render_refuses_a_goal_past_the_last_and_a_negative_time(cli, finished_run, column, value, message):
    lines = (finished_run / "trajectory.csv").read_text().splitlines()
    at = lines[0].split(",").index(column)
    row = lines[2].split(",")
    row[at] = value
    lines[2] = ",".join(row)
    (finished_run / "trajectory.csv").write_text("\n".join(lines) + "\n")
    result = cli("render", finished_run, "-q", "--jobs", "1")
    assert result.exit_code == 2 and f"trajectory.csv:3: {message}" in result.stderr, result.output


def test_a_scene_yaml_linked_to_a_device_is_named_as_one(cli, finished_run):
    (finished_run / "scene.yaml").unlink()
    (finished_run / "scene.yaml").symlink_to("/dev/zero")
    result = cli("render", finished_run, "-q")
    assert result.exit_code == 2 and "is a character device, not a regular file" in result.stderr, result.output


def test_a_disk_full_message_names_the_run_folder_not_its_staging(cli, tmp_path, monkeypatch):
    import os

    real_fsync = os.fsync

    def full(fd):
        if ".partial/" in os.readlink(f"/proc/self/fd/{fd}"):  # OUT is full (not TMPDIR: that message names TMPDIR)
            raise OSError(errno.ENOSPC, "No space left on device")
        real_fsync(fd)

    monkeypatch.setattr("armanim.output.atomic.os.fsync", full)
    result = cli(
        "run",
        small_scene(tmp_path, "a"),
        small_scene(tmp_path, "b"),
        "--out",
        tmp_path / "out",
        "--no-video",
        "-q",
        "--jobs",
        "1",
    )
    assert result.exit_code == 3, result.output
    assert f"{tmp_path / 'out' / 'a'}/scene.yaml: the disk is full" in result.stderr and ".partial" not in result.stderr


def test_a_fifo_at_the_lock_is_refused_never_waited_on(cli, tmp_path, finished_run):
    """Campaign 9: a FIFO at ``OUT/.NAME.lock`` made `run` and `render` wait for ever for a reader
    (the lock was opened blocking); with a reader there, the FIFO was taken as the lock. Either way
    it is the user's thing: exit 3, naming it, and it is left as it was."""
    import os
    import subprocess
    import sys

    lock = finished_run.parent / ".r.lock"
    lock.unlink()
    os.mkfifo(lock)
    before = snapshot(finished_run)
    reader = os.open(lock, os.O_RDONLY | os.O_NONBLOCK)  # someone reads it: the open would succeed
    try:
        for args in (("run", tmp_path / "r.yaml", "--out", finished_run.parent), ("render", finished_run)):
            result = cli(*args, "--no-video" if args[0] == "run" else "--size=64x48", "-q")
            assert result.exit_code == 3 and ".r.lock: is a FIFO (named pipe)" in result.stderr, result.output
    finally:
        os.close(reader)
    # nobody reads it: the open must not wait (a guard against a hang, not a bound on time)
    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "armanim",
            "run",
            str(tmp_path / "r.yaml"),
            "--out",
            str(finished_run.parent),
            "--no-video",
            "-q",
        ],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert proc.returncode == 3 and ".r.lock: is a FIFO (named pipe)" in proc.stderr, proc.stderr
    assert snapshot(finished_run) == before
    assert os.path.lexists(lock) and not os.path.isfile(lock)


def test_a_dangling_link_at_the_lock_is_refused_not_followed(cli, tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / ".a.lock").symlink_to(tmp_path / "elsewhere")
    result = cli("run", small_scene(tmp_path, "a"), "--out", out, "--no-video", "-q")
    assert result.exit_code == 3 and ".a.lock: is a link" in result.stderr, result.output
    assert not (tmp_path / "elsewhere").exists()


def test_nothing_is_written_into_another_run_s_folder(cli, tmp_path, finished_run):
    """Campaign 5: ``view A --out B/viewer.html`` replaced B's page (armanim's), ``view --out B/page.html``,
    ``render A --out B/sub``, ``schema --out B/s.json``, ``run --out B`` (a run folder inside B) and
    ``check --update --golden B`` each wrote into run B's folder, exit 0, and B's next run then stopped
    with exit 3 ("holds files armanim did not write"). Each is now exit 2 naming B, B untouched; through
    the installed command, and by a link to B as well."""
    import subprocess

    from runfolders import armanim_exe

    other = tmp_path / "other"
    assert cli("run", small_scene(tmp_path, "b"), "--out", other, "--no-video", "-q").exit_code == 0
    b = other / "b"
    (tmp_path / "to-b").symlink_to(b)
    before = snapshot(b)
    attempts = [
        ["view", finished_run, "--out", b / "viewer.html"],
        ["view", finished_run, "--out", tmp_path / "to-b" / "page.html"],
        ["render", finished_run, "--out", b / "sub", "-q"],
        ["render", finished_run, "--out", b, "-q"],
        ["schema", "--out", b / "s.json"],
        ["run", tmp_path / "r.yaml", "--out", b, "--no-video", "-q"],
        ["check", tmp_path / "r.yaml", "--golden", b, "--update", "-q"],
        ["fk", "--links", "1,1", "--angles", "0,0", "--png", b / "pose.png"],
    ]
    installed = subprocess.run([armanim_exe(), *map(str, attempts[0])], capture_output=True, text=True, timeout=120)
    assert installed.returncode == 2 and "Traceback" not in installed.stderr, installed.stderr
    assert f"is inside the run folder {b}" in installed.stderr
    for args in attempts[1:]:
        result = cli(*args)
        assert result.exit_code == 2 and (
            "is inside the run folder" in result.stderr or "is the run folder" in result.stderr
        ), (args, result.output)
    assert snapshot(b) == before and sorted(p.name for p in other.iterdir()) == sorted(["b", ".b.lock"])
    assert cli("run", tmp_path / "b.yaml", "--out", other, "--no-video", "-q").exit_code == 0  # B's next run goes on
