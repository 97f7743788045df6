"""Outputs on file systems that are not a plain writable folder (campaign 17): read-only mounts,
mount points, file names that are not UTF-8. Each test is named in docs/reliability.md."""

from __future__ import annotations

import errno
import os
import subprocess
from pathlib import Path

import pytest

from armanim.errors import OutputError
from armanim.output.atomic import output_error, write_text_atomic
from armanim.output.marks import write_marked
from armanim.output.rundir import check_replaceable


@pytest.fixture
def mounted(tmp_path):
    """A small tmpfs mounted at ``tmp_path/m`` (root only; skipped where it cannot be), unmounted after."""
    point = tmp_path / "m"
    point.mkdir()
    done = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=256k", "tmpfs", str(point)], capture_output=True)
    if done.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs here: {done.stderr.decode().strip()}")
    yield point
    subprocess.run(["umount", "-l", str(point)], check=False)


def test_a_read_only_file_system_is_named_as_one_not_as_permission_denied():
    """Campaign 17: a write onto a read-only mount said ``permission denied``, which chmod cannot mend."""
    said = str(output_error(Path("ro/e.json"), OSError(errno.EROFS, "Read-only file system")))
    assert said == "ro/e.json: cannot write here: the file system is read-only (choose another folder with --out)"
    assert "permission" in str(output_error(Path("x"), OSError(errno.EACCES, "Permission denied")))


def test_a_write_onto_a_read_only_mount_says_so(mounted):
    subprocess.run(["mount", "-o", "remount,ro", str(mounted)], check=True)
    with pytest.raises(OutputError, match="the file system is read-only"):
        write_text_atomic(mounted / "e.json", "{}")
    assert os.listdir(mounted) == []


def test_a_run_folder_on_a_read_only_mount_is_named_so_with_advice_that_helps(mounted):
    """A run folder on a read-only mount, then a run into it (root passes every mode there): its
    protection was told ``immutable or append-only`` and ``chattr -i`` (before: ``read-only`` and
    ``chmod -R u+w``), neither of which a read-only file system lets anyone do."""
    from armanim.output.rundir import replace_problem, write_marker

    run = mounted / "tiny"
    run.mkdir()
    (run / "trajectory.csv").write_text("frame,time_s,goal\n")
    write_marker(run)
    assert replace_problem(run) is None
    subprocess.run(["mount", "-o", "remount,ro", str(mounted)], check=True)
    said = replace_problem(run)
    assert said is not None and "(the folder is on a read-only file system)" in said, said
    assert "mount this one read-write" in said and "chmod" not in said and "chattr" not in said


def test_a_mount_point_is_never_swapped_for_a_new_folder(mounted):
    """Campaign 17: ``render --out`` a mounted disk staged its outputs beside it and ended ``Device or
    resource busy`` at the swap; it is refused before any work, naming the mount point."""
    with pytest.raises(OutputError, match="is a mount point"):
        check_replaceable(mounted)


def test_a_file_name_that_is_not_utf8_is_written_back_as_its_bytes(tmp_path):
    """Campaign 17: under LANG=C a batch into ``o\\xe9t\\xe9`` ended in a UnicodeEncodeError writing
    index.csv, which names the folder: the name's bytes are written back as they were."""
    folder = os.fsdecode(b"o\xe9t\xe9")
    write_marked(tmp_path / "index.csv", f"name,folder\ntiny,{folder}/tiny\n", "index.csv")
    assert (tmp_path / "index.csv").read_bytes() == b"name,folder\ntiny,o\xe9t\xe9/tiny\n"
