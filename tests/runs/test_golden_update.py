"""`check --update` (issue 19): a failure on the second golden file leaves the pair as it was,
a golden CSV that is not UTF-8 is replaced, the old CSV is compared without reading it whole.

Each test is named in docs/reliability.md, which it keeps true.
"""

from __future__ import annotations

import errno
import json
import tracemalloc
from pathlib import Path

import pytest
from conftest import SCENES

NOTES = SCENES / "notes-arm.yaml"


SMALL = "version: 1\narm:\n  links: [1, 1, 1, 1]\ngoals:\n  - [1, 1, 2]\n"


def _pair(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir())}


@pytest.mark.parametrize("previous", [False, True])
def test_a_failure_on_the_second_golden_file_leaves_the_pair_as_it_was(cli, tmp_path, monkeypatch, previous):
    import os

    golden = tmp_path / "golden"
    golden.mkdir()
    scene = tmp_path / "g.yaml"
    scene.write_text(SMALL + "name: g\n")
    if previous:
        assert cli("check", scene, "--golden", golden, "--update", "-q").exit_code == 0
        scene.write_text(SMALL.replace("[1, 1, 2]", "[1, 1.5, 2]") + "name: g\n")
    before = _pair(golden)
    real_replace = os.replace

    def full_on_json(src, dst):
        if str(dst).endswith("g.json"):
            raise OSError(errno.ENOSPC, "No space left on device")
        real_replace(src, dst)

    monkeypatch.setattr("armanim.output.atomic.os.replace", full_on_json)
    result = cli("check", scene, "--golden", golden, "--update", "-q")
    assert result.exit_code == 3 and "g.json: the disk is full" in result.stderr, result.output
    assert _pair(golden) == before  # old/old (or nothing), never a new CSV beside an old JSON; no temporary file


def test_update_with_a_golden_csv_that_is_not_utf8_replaces_it(cli, tmp_path):
    (tmp_path / "notes-arm.csv").write_bytes(b"frame,time_s,goal,\xff\xfe\n")  # armanim's, then broken
    result = cli("check", NOTES, "--golden", tmp_path, "--update")
    assert result.exit_code == 0 and "changed" in result.stdout, result.output
    assert (tmp_path / "notes-arm.csv").read_bytes().startswith(b"frame,time_s,")


FOREIGN = [
    *(("csv", theirs) for theirs in (b"time_s\n0\n", b"", b"frame\n0\n", b"\xff" * 100)),
    *(("json", theirs) for theirs in (b'{"mine": 1}\n', b"", b"[1, 2]\n", b"\xff" * 100)),
]
"""Files of a user's at a golden pair's names (by suffix): none begins as armanim's golden files do."""


@pytest.mark.parametrize("suffix, theirs", FOREIGN)
def test_a_golden_file_that_is_not_armanims_is_never_replaced(cli, tmp_path, suffix, theirs):
    """Campaign 11: ``check --update`` replaced a user's own CSV at the golden's name (``time_s``
    and one row) with exit 0, and would have a JSON of theirs at the pair's other name. A file at
    either name that does not begin as armanim's golden files do is exit 3, the pair left as it
    was (the other file not written either), before the scene is solved."""
    golden = tmp_path / "golden"
    golden.mkdir()
    (golden / f"notes-arm.{suffix}").write_bytes(theirs)
    result = cli("check", NOTES, "--golden", golden, "--update", "-q")
    assert result.exit_code == 3 and f"is not a golden .{suffix} file armanim wrote" in result.stderr, result.output
    assert _pair(golden) == {f"notes-arm.{suffix}": theirs}


def test_a_golden_json_armanim_wrote_is_replaced(cli, tmp_path):
    """The metadata armanim wrote (its first key first, indented by two) is replaced, whatever it says."""
    (tmp_path / "notes-arm.json").write_bytes(b'{\n  "armanim_version": "0.0.1",\n  "scene_sha256": "x"\n}\n')
    assert cli("check", NOTES, "--golden", tmp_path, "--update", "-q").exit_code == 0
    assert json.loads((tmp_path / "notes-arm.json").read_text())["scene_file"] == "notes-arm.yaml"


def test_the_old_golden_csv_is_compared_without_reading_it_whole(tmp_path):
    from armanim.runs.golden import golden_status

    big = tmp_path / "big.csv"
    with big.open("wb") as handle:
        handle.truncate(2**31)  # 2 GiB, sparse
    tracemalloc.start()
    try:
        status = golden_status(big, b"frame,time_s\n0,0.0\n")
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert status == "changed" and peak < 2**20
    same = tmp_path / "same.csv"
    same.write_bytes(b"frame\n0\n")
    assert golden_status(same, b"frame\n0\n") == "unchanged" and golden_status(tmp_path / "none.csv", b"x") == "new"


@pytest.mark.parametrize("update", [True, False])
def test_two_scenes_of_one_name_are_refused_before_any_golden_is_written(cli, tmp_path, update):
    # campaign 12: check --update wrote both to golden/g.csv, the second over the first, exit 0
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    (tmp_path / "a" / "s.yaml").write_text(SMALL + "name: g\n")
    (tmp_path / "b" / "s.yaml").write_text(SMALL.replace("[1, 1, 2]", "[1, 1.5, 2]") + "name: g\n")
    golden = tmp_path / "golden"
    args = ("check", tmp_path / "a" / "s.yaml", tmp_path / "b" / "s.yaml", "--golden", golden, "-q")
    result = cli(*args, *(("--update",) if update else ()))
    assert result.exit_code == 2
    assert "b/s.yaml: another scene in this batch is also named 'g'" in result.output
    assert not golden.exists()
    # the same file twice is one scene
    assert (
        cli(
            "check", tmp_path / "a" / "s.yaml", tmp_path / "a" / "s.yaml", "--golden", golden, "--update", "-q"
        ).exit_code
        == 0
    )


@pytest.mark.parametrize("name, target", [("s.json", "summary.json"), ("s.csv", "trajectory.csv")])
def test_a_golden_file_linked_into_a_run_folder_is_refused(cli, tmp_path, name, target):
    """Campaign 14: ``g/s.json`` a link to a run's ``summary.json`` (which begins as a golden .json
    does) was written through by ``check --update``, exit 0: the run folder changed, and its next
    run stopped (exit 3). A golden file whose link leads into a run folder is exit 2, as
    ``--golden`` there is; the run folder and the link are left as they were."""
    from signals import snapshot

    scene = tmp_path / "s.yaml"
    scene.write_text(SMALL + "render: {fps: 10}\n")
    assert cli("run", scene, "--out", tmp_path / "o", "--no-video", "-q").exit_code == 0
    run = tmp_path / "o" / "s"
    before = snapshot(run)
    golden = tmp_path / "g"
    golden.mkdir()
    (golden / name).symlink_to(run / target)
    result = cli("check", scene, "--golden", golden, "--update", "-q")
    assert result.exit_code == 2 and "is inside the run folder" in result.stderr, result.output
    assert snapshot(run) == before and (golden / name).is_symlink()
    assert cli("run", scene, "--out", tmp_path / "o", "--no-video", "-q").exit_code == 0


@pytest.mark.parametrize("command", ["check", "fk"])
def test_a_folder_that_cannot_be_written_is_advised_by_the_command_s_own_flag(cli, tmp_path, monkeypatch, command):
    """Campaign 16, as a user who is not root: ``check --update`` into a read-only golden folder, and
    ``fk --png`` into a read-only folder, said "(choose another folder with --out)", a flag neither
    command has. Root writes through modes: the denied rename is simulated."""

    def denied(src, dst):
        raise PermissionError(errno.EACCES, "Permission denied", str(dst))

    monkeypatch.setattr("armanim.output.atomic.os.replace", denied)
    scene = tmp_path / "g.yaml"
    scene.write_text(SMALL + "name: g\n")
    if command == "check":
        result = cli("check", scene, "--golden", tmp_path / "golden", "--update", "-q")
        flag = "choose another folder with --golden"
    else:
        result = cli("fk", "--links", "1,1", "--angles", "0,10", "--png", tmp_path / "p.png")
        flag = "choose another file with --png"
    assert result.exit_code == 3, result.output
    assert "permission denied" in result.stderr and flag in result.stderr and "--out" not in result.stderr


def test_a_write_protected_golden_is_never_replaced_and_an_unchanged_one_never_written(cli, tmp_path):
    """Campaign 16 (as a user who is not root): ``check --update`` replaced a golden CSV at mode 0444
    with a new file at 0644, exit 0. A golden file no one may write is exit 3 when its bytes would
    change, the pair left as it was with its modes; an unchanged pair is not written at all, so a
    protected, up-to-date golden passes."""
    scene = tmp_path / "small.yaml"
    scene.write_text(SMALL)
    golden = tmp_path / "golden"
    assert cli("check", scene, "--golden", golden, "--update", "-q").exit_code == 0
    for path in golden.iterdir():
        path.chmod(0o444)
    before = {path.name: (path.read_bytes(), path.stat().st_mtime_ns) for path in golden.iterdir()}
    result = cli("check", scene, "--golden", golden, "--update")
    assert result.exit_code == 0 and "unchanged" in result.output, result.output
    assert {path.name: (path.read_bytes(), path.stat().st_mtime_ns) for path in golden.iterdir()} == before

    scene.write_text(SMALL.replace("[1, 1, 2]", "[1, 2, 1]"))  # the trajectory changes
    result = cli("check", scene, "--golden", golden, "--update", "-q")
    assert result.exit_code == 3, result.output
    assert "small.csv: is write-protected (read-only), so --update does not replace it" in result.stderr
    assert {path.name: (path.read_bytes(), path.stat().st_mtime_ns) for path in golden.iterdir()} == before
    assert {path.stat().st_mode & 0o777 for path in golden.iterdir()} == {0o444}


def test_a_golden_folder_that_cannot_be_flocked_is_updated_unlocked(cli, tmp_path, monkeypatch):
    """NFS emulates ``flock`` by a byte-range lock, which needs a file open for writing: on a folder
    (open only for reading) LOCK_EX is EBADF. Campaign 19: ``check --update --golden`` there ended
    ``armanim: output: Bad file descriptor``, exit 3, and no golden could ever be written."""
    import fcntl
    import os

    real_flock = fcntl.flock

    def nfs_flock(fd, operation):
        if operation & fcntl.LOCK_EX and fcntl.fcntl(fd, fcntl.F_GETFL) & os.O_ACCMODE == os.O_RDONLY:
            raise OSError(errno.EBADF, "Bad file descriptor")
        return real_flock(fd, operation)

    monkeypatch.setattr("armanim.output.rundir.fcntl.flock", nfs_flock)
    scene = tmp_path / "g.yaml"
    scene.write_text(SMALL + "name: g\n")
    result = cli("check", scene, "--golden", tmp_path / "golden", "--update", "-q")
    assert result.exit_code == 0, result.output
    assert sorted(p.name for p in (tmp_path / "golden").iterdir()) == ["g.csv", "g.json"]
    assert cli("check", scene, "--golden", tmp_path / "golden", "-q").exit_code == 0
