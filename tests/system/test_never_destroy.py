"""Issue 12: armanim never destroys what it did not make, and hostile inputs, special
files and signals end with a message and the contract's exit code.

Each test is named in docs/reliability.md, which it keeps true.
"""

from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import time
import tracemalloc
from pathlib import Path

import psutil
import pytest
from conftest import SCENES

from armanim.output.rundir import MARKER

NOTES = SCENES / "notes-arm.yaml"
SMALL = "version: 1\narm:\n  links: [1, 1, 1, 1]\ngoals:\n  - [1, 1, 2]\n"
CSV_HEADER = "frame,time_s,goal,phi1_deg,phi2_deg,x,y,z,goal_distance,clearance,reached,step_scale,iterations"


def armanim(*args, timeout: float = 120, **kwargs) -> subprocess.CompletedProcess:
    """Run ``python -m armanim ARGS`` as a real process."""
    return subprocess.run(
        [sys.executable, "-m", "armanim", *map(str, args)], capture_output=True, text=True, timeout=timeout, **kwargs
    )


def no_traceback(result) -> str:
    """stderr, after checking it is a message and not a traceback."""
    text = result.stderr if hasattr(result, "stderr") else result.output
    assert "Traceback" not in text and "Error:" not in text.split(":", 1)[0], text
    return text


def lock_is_free(path: Path) -> bool:
    """Whether nobody holds the folder lock at ``path`` (tried without waiting)."""
    import fcntl

    with open(path, "a") as handle:
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            return False
        fcntl.flock(handle, fcntl.LOCK_UN)
    return True


def user_files(root: Path) -> dict[str, bytes]:
    return {str(p.relative_to(root)): p.read_bytes() for p in sorted(root.rglob("*")) if p.is_file()}


# ------------------------------------------------------------------ 1. names


@pytest.mark.parametrize("stem", ["..", ".", ".notes-arm.old-1", ".notes-arm.abcdefgh.partial", "a" * 101, "bell\x07"])
def test_unsafe_file_stems_are_rejected_with_the_name_field(cli, tmp_path, stem):
    out = tmp_path / "out"
    (out / "mine").mkdir(parents=True)
    (out / "mine" / "thesis.txt").write_text("x")
    scene = tmp_path / f"{stem}.yaml"
    scene.write_text(SMALL)
    before = user_files(tmp_path)
    result = cli("run", scene, "--out", out, "--no-video", "--quiet")
    assert result.exit_code == 2, result.output
    assert ":1: name: not set, so the file name gives the name" in result.stderr
    assert user_files(tmp_path) == before


@pytest.mark.parametrize("name", ["..", ".hidden", "a/b", "x" * 101])
def test_unsafe_name_fields_are_rejected(cli, tmp_path, name):
    scene = tmp_path / "scene.yaml"
    scene.write_text(SMALL + f"name: {json.dumps(name)}\n")
    result = cli("validate", scene)
    assert result.exit_code == 2 and ":6: name:" in result.stderr, result.output


def test_dot_dot_yaml_with_out_dot_is_exit_2(cli, tmp_path, monkeypatch):
    (tmp_path / "..yaml").write_text(SMALL)
    (tmp_path / "keep.txt").write_text("x")
    monkeypatch.chdir(tmp_path)
    result = cli("run", "..yaml", "--out", ".", "--no-video", "-q")
    assert result.exit_code == 2 and "name:" in no_traceback(result)
    assert (tmp_path / "keep.txt").read_text() == "x"


# ------------------------------------------------------------------ 2. folders armanim did not make


def test_a_user_folder_at_the_run_folder_is_never_replaced(cli, tmp_path):
    (tmp_path / "src").mkdir()
    (tmp_path / "src" / "main.py").write_text("print('mine')\n")
    scene = tmp_path / "scene.yaml"
    scene.write_text(SMALL + "name: src\n")
    result = cli("run", scene, "--out", tmp_path, "--no-video", "--quiet")
    assert result.exit_code == 3, result.output
    assert "not made by armanim" in result.stderr and "main.py" in result.stderr and "--out" in result.stderr
    assert (tmp_path / "src" / "main.py").read_text() == "print('mine')\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["scene.yaml", "src"]  # refused before a .src.lock is made


def test_a_user_file_added_to_a_run_folder_stops_the_next_run(cli, tmp_path):
    scene = tmp_path / "notes.yaml"
    scene.write_text(SMALL)
    assert cli("run", scene, "--out", tmp_path / "out", "--no-video", "-q").exit_code == 0
    folder = tmp_path / "out" / "notes"
    assert sorted(json.loads((folder / MARKER).read_text())["files"]) == [
        "scene.yaml",
        "self-collision.yaml",
        "summary.json",
        "timing.json",
        "trajectory.csv",
    ]
    (folder / "thesis.txt").write_text("mine")
    result = cli("run", scene, "--out", tmp_path / "out", "--no-video", "-q")
    assert result.exit_code == 3 and "thesis.txt" in result.stderr, result.output
    assert (folder / "thesis.txt").read_text() == "mine"
    (folder / "thesis.txt").unlink()
    assert cli("run", scene, "--out", tmp_path / "out", "--no-video", "-q").exit_code == 0


def test_an_empty_folder_is_taken_and_a_link_is_refused(cli, tmp_path):
    scene = tmp_path / "notes.yaml"
    scene.write_text(SMALL)
    (tmp_path / "out" / "notes").mkdir(parents=True)
    assert cli("run", scene, "--out", tmp_path / "out", "--no-video", "-q").exit_code == 0
    (tmp_path / "elsewhere").mkdir()
    (tmp_path / "out2").mkdir()
    (tmp_path / "out2" / "notes").symlink_to(tmp_path / "elsewhere")
    result = cli("run", scene, "--out", tmp_path / "out2", "--no-video", "-q")
    assert result.exit_code == 3 and "is a link" in result.stderr
    assert (tmp_path / "out2" / "notes").is_symlink()


# ------------------------------------------------------------------ 3. special files and links


def test_a_write_through_a_link_replaces_its_target(cli, tmp_path):
    assert cli("schema", "--out", tmp_path / "real.json").exit_code == 0  # armanim's own, marked
    (tmp_path / "link.json").symlink_to("real.json")
    assert cli("schema", "--out", tmp_path / "link.json").exit_code == 0
    assert (tmp_path / "link.json").is_symlink()
    assert json.loads((tmp_path / "real.json").read_text())["title"] == "armanim scene"
    assert not (tmp_path / ".link.json.armanim.json").exists()  # the mark is the file's, beside it


@pytest.mark.parametrize("flag", ["schema", "fk"])
def test_a_single_file_replaces_only_what_armanim_wrote(cli, tmp_path, flag):
    """schema --out and fk --png (the sixth campaign: they replaced a user's own file, exit 0)
    rewrite their own file, but never a file of yours, one you edited since, or one through a
    link to a file of yours: exit 3, every byte left."""
    target = tmp_path / ("s.json" if flag == "schema" else "pose.png")
    args = ("schema", "--out", target) if flag == "schema" else ("fk", "--angles", "0,30,45,10", "--png", target)
    assert cli(*args).exit_code == 0
    assert cli(*args).exit_code == 0  # its own, unchanged: replaced
    with open(target, "ab") as handle:  # edited since
        handle.write(b" ")
    edited = target.read_bytes()
    result = cli(*args)
    assert result.exit_code == 3 and "did not write, or that has changed since" in result.stderr
    assert target.read_bytes() == edited
    mine = tmp_path / "mine"
    mine.write_bytes(b"my notes")
    (tmp_path / "link").symlink_to(mine)
    for where in (mine, tmp_path / "link"):
        other = ("schema", "--out", where) if flag == "schema" else ("fk", "--angles", "0,30,45,10", "--png", where)
        result = cli(*other)
        assert result.exit_code == 3, result.output
        assert mine.read_bytes() == b"my notes"
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(
        ["link", "mine", target.name, f".{target.name}.armanim.json"]
    )


@pytest.mark.parametrize("flag", ["schema", "fk", "export"])
@pytest.mark.parametrize("kind", ["file", "link", "nested"])
def test_what_stands_at_a_mark_s_name_is_never_replaced(cli, tmp_path, flag, kind):
    """A new file whose mark's name (``.NAME.armanim.json``) holds a file of yours, a link to
    one, or JSON nested 200,000 deep: exit 3, nothing written, every byte left (writing the
    mark would have replaced it; export and the other marked files share one reader of marks)."""
    target = tmp_path / ("s.json" if flag != "fk" else "pose.png")
    mark = tmp_path / f".{target.name}.armanim.json"
    mine = tmp_path / "mine.txt"
    mine.write_text("my notes")
    if kind == "link":
        mark.symlink_to(mine)
    else:
        mark.write_text("my notes" if kind == "file" else "[" * 200_000 + "]" * 200_000)
    before = mark.read_bytes()
    if flag == "export":
        scene = tmp_path / "small.yaml"
        scene.write_text(SMALL)
        assert cli("run", scene, "--out", tmp_path / "out", "--no-video", "-q").exit_code == 0
        args: tuple = ("export", next((tmp_path / "out").iterdir()), "--out", target)
    elif flag == "schema":
        args = ("schema", "--out", target)
    else:
        args = ("fk", "--angles", "0,30,45,10", "--png", target)
    result = cli(*args)
    assert result.exit_code == 3 and "is not a mark armanim wrote" in result.stderr, result.output
    assert "Traceback" not in result.output and not target.exists()
    assert mark.read_bytes() == before and mine.read_text() == "my notes" and mark.is_symlink() == (kind == "link")


@pytest.mark.parametrize("kind", ["fifo", "device", "folder"])
def test_special_files_at_a_target_are_an_error(cli, tmp_path, kind):
    target = tmp_path / "target"
    if kind == "fifo":
        os.mkfifo(target)
    elif kind == "folder":
        target.mkdir()
    else:
        target = Path("/dev/null")
    before = os.stat(target)
    for args in (("schema", "--out", target), ("fk", "--angles", "0,0,0,0", "--png", target)):
        result = cli(*args)
        assert result.exit_code == 3, result.output
        assert "not a regular file" in result.stderr
    after = os.stat(target)
    assert (before.st_ino, before.st_mode) == (after.st_ino, after.st_mode)


# ------------------------------------------------------------------ 4. unbounded reads, FIFOs, devices


def _golden() -> Path:
    return Path(__file__).parents[1] / "golden" / "notes-arm.csv"


@pytest.mark.parametrize("kind", ["dev-zero", "fifo", "link-to-dev-zero"])
def test_devices_and_fifos_are_refused_fast(tmp_path, kind):
    special = tmp_path / "special.yaml"
    if kind == "fifo":
        os.mkfifo(special)
    else:
        special.symlink_to("/dev/zero") if kind == "link-to-dev-zero" else None
        special = special if kind == "link-to-dev-zero" else Path("/dev/zero")
    for args in (
        ("validate", special),
        ("compare", special, _golden()),
        ("compare", _golden(), special),
        ("run", special, "--out", tmp_path / "out", "--no-video"),
    ):
        result = armanim(*args, timeout=120)  # a hang guard: a FIFO opened blocking would wait forever
        assert result.returncode == 2, result.stderr
        assert "not a regular file" in no_traceback(result)


def test_a_golden_csv_linked_to_dev_zero_is_refused(tmp_path):
    (tmp_path / "notes-arm.csv").symlink_to("/dev/zero")
    result = armanim("check", NOTES, "--golden", tmp_path, timeout=60)
    assert result.returncode == 2 and "is a character device, not a regular file" in no_traceback(result)


def test_a_growing_file_is_read_only_to_its_bound(tmp_path):
    """A scene whose reported size lies (it grows while read) is still read to the bound only."""
    from armanim.errors import SceneError
    from armanim.output.files import read_bounded

    path = tmp_path / "big.yaml"
    path.write_bytes(b"#" * 2000)
    with pytest.raises(SceneError, match="at most 1,000 bytes"):
        read_bounded(path, 1000, "a scene")
    assert read_bounded(path, 2000, "a scene") == b"#" * 2000


def test_a_csv_without_newlines_is_not_read_whole(cli, tmp_path):
    path = tmp_path / "one-line.csv"
    path.write_bytes(b"frame,time_s,goal," + b"9" * 300_000)
    result = cli("compare", path, _golden())
    assert result.exit_code == 2 and "longer than 100,000 bytes" in result.stderr


# ------------------------------------------------------------------ 7. render takes the run's lock and stages


@pytest.fixture()
def run_folder(cli, tmp_path) -> Path:
    scene = tmp_path / "r.yaml"
    scene.write_text(SMALL + "render: {fps: 10, size: [64, 48]}\n")
    assert cli("run", scene, "--out", tmp_path / "out", "--no-video", "-q").exit_code == 0
    return tmp_path / "out" / "r"


def test_render_waits_for_the_folder_lock_and_swaps_whole(run_folder):
    from armanim.output.rundir import folder_lock

    before = user_files(run_folder)
    with folder_lock(run_folder):
        proc = subprocess.Popen(
            [sys.executable, "-m", "armanim", "render", str(run_folder), "-q", "--jobs", "1"],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        time.sleep(2.0)
        assert proc.poll() is None  # waiting for the lock, not writing
        assert user_files(run_folder) == before
    _, stderr = proc.communicate(timeout=120)
    assert proc.returncode == 0, stderr
    listed = sorted(json.loads((run_folder / MARKER).read_text())["files"])
    assert sorted(p.name for p in run_folder.iterdir() if p.name != MARKER) == listed
    assert {"animation.mp4", "plot.png"} <= set(listed)
    assert [p.name for p in run_folder.parent.iterdir() if p.name.startswith(".r.") and p.name != ".r.lock"] == []


def test_a_failed_render_leaves_the_run_folder_as_it_was(cli, run_folder, monkeypatch):
    import armanim.render.pictures.plot as plot

    def broken(*args, **kwargs):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(plot, "plot_run", broken)
    before = user_files(run_folder)
    result = cli("render", run_folder, "-q", "--jobs", "1")
    assert result.exit_code == 3, result.output
    assert user_files(run_folder) == before
    assert sorted(p.name for p in run_folder.parent.iterdir()) == [".r.lock", "r"]


def test_render_refuses_a_folder_armanim_did_not_make(cli, run_folder):
    (run_folder / MARKER).unlink()
    before = user_files(run_folder)
    result = cli("render", run_folder, "-q")
    assert result.exit_code == 3 and "not made by armanim" in result.stderr
    assert user_files(run_folder) == before


@pytest.mark.parametrize("command", ["export", "view", "render"])
def test_an_out_that_is_a_link_to_itself_is_refused_without_a_traceback(cli, run_folder, command):
    """Campaign 18: ``export --out l.json`` and ``view --out l.json``, l.json a link to itself,
    ended in ``RuntimeError: Symlink loop from ...`` (Path.resolve in Python 3.11), exit 1. Now the
    loop is refused as any link armanim did not make (exit 3), and left as it was."""
    loop = run_folder.parent.parent / "l.json"
    os.symlink("l.json", loop)
    extra = ("--format", "gif") if command == "render" else ()
    result = cli(command, run_folder, "--out", loop, *extra)
    assert result.exit_code == 3 and "l.json" in result.stderr, result.output
    assert "Traceback" not in result.output and "RuntimeError" not in result.output
    assert os.readlink(loop) == "l.json"


@pytest.mark.parametrize("command", ["export", "schema", "fk --png"])
def test_a_marked_file_made_read_only_is_not_replaced(cli, run_folder, command):
    """Campaign 19: ``export --out x.json`` (``schema --out``, ``fk --png`` alike), its earlier file
    made read-only by its user (``chmod 444``), was replaced as root, exit 0, and left 0644 (root's
    writes pass the mode). Now refused, exit 3, as a read-only run folder or golden file is."""
    target = run_folder.parent.parent / ("p.png" if command == "fk --png" else "x.json")
    args = {
        "export": ("export", run_folder, "--out", target),
        "schema": ("schema", "--out", target),
        "fk --png": ("fk", "--angles", "0,0,0", "--links", "1,1,1", "--png", target),
    }[command]
    assert cli(*args).exit_code == 0
    target.chmod(0o444)
    before = target.read_bytes()
    result = cli(*args)
    assert result.exit_code == 3 and "is write-protected" in result.stderr, result.output
    assert target.read_bytes() == before and target.stat().st_mode & 0o777 == 0o444
    target.chmod(0o644)
    assert cli(*args).exit_code == 0  # writable again: replaced as before


def _immutable(path: Path, on: bool) -> bool:
    """``chattr +i`` (or ``-i``) on ``path``: False where it cannot be (not root, a file system without it)."""
    done = subprocess.run(["chattr", "+i" if on else "-i", str(path)], capture_output=True, check=False)
    return done.returncode == 0


def test_an_immutable_output_is_refused_with_the_advice_that_lifts_it(cli, run_folder):
    """Campaign 19 left: a file made immutable (``chattr +i``, which root's writes do not pass) was
    refused rightly, but told ``chmod u+w``, which does not lift it. Now named and advised as such,
    for a marked file (``export --out``) and a run folder's file."""
    if shutil.which("chattr") is None or os.geteuid() != 0:
        pytest.skip("chattr as root is needed to make a file immutable")
    target = run_folder.parent.parent / "x.json"
    assert cli("export", run_folder, "--out", target).exit_code == 0
    if not _immutable(target, True):
        pytest.skip("this file system has no immutable files")
    try:
        result = cli("export", run_folder, "--out", target)
    finally:
        _immutable(target, False)
    assert result.exit_code == 3, result.output
    assert f"is write-protected (immutable or append-only), so it is not replaced: lift it (chattr -i -a {target})" in (
        result.stderr
    )
    assert "chmod" not in result.stderr

    summary = run_folder / "summary.json"
    before = summary.read_bytes()
    assert _immutable(summary, True)
    try:
        result = cli("render", run_folder, "--size", "64x36")
    finally:
        _immutable(summary, False)
    assert result.exit_code == 3, result.output
    assert "('summary.json' is immutable or append-only)" in result.stderr and "chattr -R -i -a" in result.stderr
    assert summary.read_bytes() == before


def test_leftovers_of_a_killed_render_are_removed(tmp_path):
    from armanim.render.video.movie import remove_dead_leftovers

    dead = psutil.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    mine = tmp_path / f"..animation.mp4.{os.getpid()}.part.abcd1234"
    stale = tmp_path / f"..animation.mp4.{dead.pid}.part.abcd1234"
    for folder in (mine, stale):
        folder.mkdir()
        (folder / "segment000.mp4").write_bytes(b"x")
    (tmp_path / f".animation.mp4.{dead.pid}.part").write_bytes(b"x")
    (tmp_path / f"..animation.mp4.{dead.pid}.part.x1y2z3w4.palette.png").write_bytes(b"x")
    (tmp_path / "keep.txt").write_text("x")
    remove_dead_leftovers(tmp_path / "animation.mp4")
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([mine.name, "keep.txt"])


# ------------------------------------------------------------------ 8. bad trajectory.csv, streaming compare


def _edit_csv(path: Path, edit) -> None:
    import csv

    rows = list(csv.reader(path.open()))
    edit(rows)
    with path.open("w", newline="") as handle:
        csv.writer(handle, lineterminator="\n").writerows(rows)


def _drop(rows: list[list[str]], column: str) -> None:
    at = rows[0].index(column)
    for row in rows:
        row.pop(at)


BAD_ROWS = {
    "no x": (lambda rows: _drop(rows, "x"), ":1: lacks the column(s) x"),
    "no reached": (lambda rows: _drop(rows, "reached"), ":1: lacks the column(s) reached"),
    "phiX_deg": (lambda rows: rows[0].__setitem__(4, "phiX_deg"), "'phiX_deg' is out of place"),
    "NaN": (lambda rows: rows[2].__setitem__(7, "nan"), ":3: x: empty or NaN is not a finite number"),
    "inf": (lambda rows: rows[2].__setitem__(7, "inf"), ":3: x: inf is not a finite number"),
    "1e308": (lambda rows: rows[2].__setitem__(7, "1e308"), ":3: x: 1e+308 is too large"),
    "header only": (lambda rows: rows.__delitem__(slice(1, None)), "has a header but no rows"),
    "a word": (lambda rows: rows[2].__setitem__(1, "soon"), ":3: time_s: 'soon' is not a number"),
    "ragged": (lambda rows: rows[2].pop(), ":3: row has"),
    "unknown mode": (
        lambda rows: rows[2].__setitem__(rows[0].index("mode"), "walk"),
        ":3: mode: 'walk' is not ik or plan",
    ),
}


@pytest.mark.parametrize("name", BAD_ROWS)
def test_render_of_a_bad_trajectory_is_exit_2_with_its_line(cli, run_folder, name):
    edit, message = BAD_ROWS[name]
    _edit_csv(run_folder / "trajectory.csv", edit)
    before = user_files(run_folder)
    result = cli("render", run_folder, "-q", "--jobs", "1")
    assert result.exit_code == 2, result.output
    assert message in result.stderr and "Traceback" not in result.output
    assert user_files(run_folder) == before


def test_render_without_the_diagnostic_columns_still_draws(cli, run_folder):
    def drop_extras(rows):
        for column in ("step_scale", "iterations", "mode"):
            if column in rows[0]:
                _drop(rows, column)

    from armanim.output.rundir import write_marker

    _edit_csv(run_folder / "trajectory.csv", drop_extras)
    write_marker(run_folder)  # as an older armanim, which wrote no such columns, left it
    assert cli("render", run_folder, "-q", "--jobs", "1").exit_code == 0


def test_compare_needs_the_contract_columns_in_both_files(cli, tmp_path):
    expected = tmp_path / "expected.csv"
    expected.write_bytes(_golden().read_bytes())
    _edit_csv(expected, lambda rows: _drop(rows, "reached"))
    result = cli("compare", expected, _golden())
    assert result.exit_code == 2 and "lacks the column(s) reached" in result.stderr


def test_identical_files_with_inf_and_a_mode_column_agree(cli, tmp_path):
    path = tmp_path / "t.csv"
    path.write_bytes(_golden().read_bytes())

    def add_mode_and_inf(rows):
        if "mode" not in rows[0]:
            for i, row in enumerate(rows):
                row.append("mode" if i == 0 else "ik")
        at = rows[0].index("mode")
        for row in rows[1:]:
            row[at] = "ik"
        rows[3][7] = "inf"

    _edit_csv(path, add_mode_and_inf)
    assert cli("compare", path, path).exit_code == 0
    other = tmp_path / "u.csv"
    other.write_bytes(path.read_bytes())
    _edit_csv(other, lambda rows: rows[5].__setitem__(rows[0].index("mode"), "plan"))
    result = cli("compare", path, other)
    assert result.exit_code == 1 and "frame 4, column mode: expected 'ik', actual 'plan'" in result.stdout


def test_compare_streams_long_files_in_flat_memory(tmp_path):
    """200,000 rows against a copy differing in the last row: found, in memory far below the file's."""
    rows = _golden().read_text().splitlines()
    header, row = rows[0], rows[1].split(",")
    path, other = tmp_path / "long.csv", tmp_path / "other.csv"
    reached = header.split(",").index("reached")
    with path.open("w") as handle, other.open("w") as changed:
        for out in (handle, changed):
            out.write(header + "\n")
        for i in range(200_000):
            row[0] = str(i)
            handle.write(",".join(row) + "\n")
            changed.write(",".join(row[:reached] + ["1" if i == 199_999 else row[reached]] + row[reached + 1 :]) + "\n")
    proc = psutil.Popen(
        [sys.executable, "-m", "armanim", "compare", str(path), str(other)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    peak = 0
    while proc.poll() is None:
        with contextlib_suppress():
            peak = max(peak, proc.memory_info().rss)
        time.sleep(0.05)
    out, err = proc.communicate()
    assert proc.returncode == 1, err
    assert "frame 199999" in out
    assert peak < 250e6  # the rows as Python lists would take well over 1 GB


def contextlib_suppress():
    import contextlib

    return contextlib.suppress(psutil.Error)


# ------------------------------------------------------------------ 9. no tracebacks


@pytest.mark.parametrize("address", ["garbage", "xyz://127.0.0.1:1", "tcp://[::1"])
def test_a_bad_scheduler_address_is_exit_2(tmp_path, address):
    pytest.importorskip("dask.distributed")
    # a real process: Dask's IO-loop thread stays behind in the process that tried the address
    result = armanim(
        "run", NOTES, SCENES / "planar-nlink.yaml", "--out", tmp_path, "--no-video", "-q", "--scheduler", address
    )
    assert result.returncode == 2, result.stderr
    assert no_traceback(result).startswith("--scheduler: ") and "not a scheduler address" in result.stderr


BAD_SETS = {
    "5000 digits": ("solver.step=" + "9" * 5000, "5000-digit integer is too large"),
    "alias bomb": (
        "solver.step=[&a [1,1,1,1,1,1,1,1,1], &b [*a,*a,*a,*a,*a,*a,*a,*a,*a], &c [*b,*b,*b,*b,*b,*b,*b,*b,*b], "
        "&d [*c,*c,*c,*c,*c,*c,*c,*c,*c], &e [*d,*d,*d,*d,*d,*d,*d,*d,*d]]",
        "alias bomb",
    ),
    "python tag": ("solver.method=!!python/object/apply:os.system [echo hi]", "unsupported YAML tag"),
}


@pytest.mark.parametrize("name", BAD_SETS)
def test_set_values_go_through_the_bounded_reader(cli, tmp_path, name):
    setting, message = BAD_SETS[name]
    tracemalloc.start()
    try:
        result = cli("sweep", NOTES, "--set", setting, "--out", tmp_path, "-q")
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert result.exit_code == 2 and message in result.stderr, result.output
    assert peak < 32 * 2**20, f"peak {peak / 2**20:.1f} MiB"  # bounded, not expanded (its time: reliability_bench.py)
    assert list(tmp_path.iterdir()) == []


def test_a_golden_json_that_is_not_armanim_s_is_ignored(cli, tmp_path):
    (tmp_path / "notes-arm.csv").write_bytes((Path(__file__).parents[1] / "golden" / "notes-arm.csv").read_bytes())
    _edit_csv(tmp_path / "notes-arm.csv", lambda rows: rows[3].__setitem__(4, "1"))
    for meta in ('{"scene_sha256": 5}', "[1, 2]", "not json"):
        (tmp_path / "notes-arm.json").write_text(meta)
        result = cli("check", NOTES, "--golden", tmp_path)
        assert result.exit_code == 1 and "first difference" in result.stdout


@pytest.mark.parametrize(
    "args, flag",
    [
        (("fk", "--angles", "0,0,0,0", "--links", "1e300,1,1,1", "--png", "P"), "--links"),
        (("ik", "--goal", "1,1,1", "--links", "1e308,1e308,1,1"), "--links"),
        (("ik", "--goal", "1e300,1,1"), "--goal"),
        (("fk", "--angles", "0,0", "--links", "1,1", "--base", "0,0,1e12"), "--base"),
    ],
)
def test_huge_arm_flags_are_exit_2(cli, tmp_path, args, flag):
    result = cli(*[str(tmp_path / "p.png") if a == "P" else a for a in args])
    assert result.exit_code == 2, result.output
    assert result.stderr.startswith(f"{flag}: ") and "too large" in result.stderr
    assert list(tmp_path.iterdir()) == []


# ------------------------------------------------------------------ 10. fps, jobs, golden folder


@pytest.mark.parametrize("where", ["scene", "flag"])
def test_an_fps_ffmpeg_cannot_encode_is_exit_2(cli, tmp_path, where):
    scene = tmp_path / "s.yaml"
    scene.write_text(SMALL + ("render: {fps: 1.0e-300}\n" if where == "scene" else ""))
    args = ("run", scene, "--out", tmp_path / "out", "-q") + (("--fps", "0.0001") if where == "flag" else ())
    result = cli(*args)
    assert result.exit_code == 2 and "must be >= 0.01" in result.stderr, result.output
    assert not (tmp_path / "out").exists()


def test_jobs_beyond_the_cores_are_lowered_with_a_note(cli, tmp_path):
    cores = len(os.sched_getaffinity(0))
    result = cli("run", NOTES, "--out", tmp_path, "--no-video", "-q", "--jobs", cores + 46)
    assert result.exit_code == 0, result.stderr
    assert f"note: --jobs {cores + 46} is more than the {cores} cores here; using {cores}" in result.stderr


def test_check_golden_that_is_a_file_is_exit_2(cli, tmp_path):
    (tmp_path / "golden").write_text("x")
    result = cli("check", NOTES, "--golden", tmp_path / "golden")
    assert result.exit_code == 2 and "is a file (expected a folder" in result.stderr


def test_update_never_writes_half_a_golden_pair(cli, tmp_path):
    (tmp_path / "notes-arm.json").mkdir()
    result = cli("check", NOTES, "--golden", tmp_path, "--update")
    assert result.exit_code == 3 and "notes-arm.json: is a folder" in result.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["notes-arm.json"]


# ------------------------------------------------------------------ 5-6. stray processes, batch stop


def _start(args, tmp_path: Path) -> psutil.Popen:
    """armanim ARGS in its own session (so a group signal reaches only it), temporary files under tmp_path/tmp."""
    (tmp_path / "tmp").mkdir(exist_ok=True)
    env = {**os.environ, "TMPDIR": str(tmp_path / "tmp")}
    return psutil.Popen(
        [sys.executable, "-m", "armanim", *map(str, args)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
        env=env,
    )


def _wait_for_ffmpeg(proc: psutil.Popen, workers: int, timeout: float = 60.0) -> list[psutil.Process]:
    """Every descendant, once ``workers`` python workers (not the forkserver or the resource
    tracker) and at least one ffmpeg that encodes run."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        assert proc.poll() is None, proc.communicate()
        with contextlib_suppress():
            kids = proc.children(recursive=True)
            lines = [(k.name(), " ".join(k.cmdline()), k.ppid()) for k in kids]
            encoding = any("ffmpeg" in name and "rawvideo" in line for name, line, _ in lines)
            helper = ("multiprocessing.forkserver import main", "resource_tracker")  # the pool's own, not workers
            busy = sum(
                "python" in name and not (parent == proc.pid and any(h in line for h in helper))
                for name, line, parent in lines
            )
            if encoding and busy >= workers:
                return kids
        time.sleep(0.05)
    raise AssertionError("rendering did not start")


def _batch_scenes(tmp_path: Path, count: int = 8) -> list[Path]:
    text = NOTES.read_text()
    paths = []
    for i in range(count):
        path = tmp_path / f"s{i}.yaml"
        path.write_text(text.replace("name: notes-arm", f"name: s{i}") if "name: notes-arm" in text else text)
        paths.append(path)
    return paths


def test_a_worker_finds_its_temporary_folder_before_a_signal_can_stop_it():
    """Python finds its temporary folder on first use by writing and removing a probe file
    there; a worker stopped (os._exit) between the two left that file in $TMPDIR (the signal
    sweep's "litter: $TMPDIR/dqu801b3" at render's ffmpeg moment, under load). init_worker,
    run with the signals still blocked, must have done it already."""
    program = (
        "import os, tempfile\n"
        "from armanim.procs.workers import init_worker\n"
        "tempfile.tempdir = None  # as in a worker whose parent never asked\n"
        "init_worker(os.getppid())\n"
        "print(tempfile.tempdir)\n"
    )
    proc = subprocess.run([sys.executable, "-c", program], capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr
    import tempfile

    assert proc.stdout.strip() == tempfile.gettempdir()


def test_a_killed_run_takes_its_render_workers_and_ffmpeg_with_it(cli, tmp_path):
    out = tmp_path / "out"
    proc = _start(["run", NOTES, "--out", out, "--jobs", "2", "--size", "480x360", "-q"], tmp_path)
    kids = _wait_for_ffmpeg(proc, workers=2)
    proc.kill()
    proc.wait()
    _, alive = psutil.wait_procs(kids, timeout=60)  # a hang guard; how soon they go: reliability_bench.py
    assert alive == []
    assert lock_is_free(out / ".notes-arm.lock")  # no stray worker holds it
    result = cli("run", NOTES, "--out", out, "--no-video", "-q")  # the next run, in-process
    assert result.exit_code == 0, result.stderr
    assert sorted(p.name for p in out.iterdir()) == [".notes-arm.lock", "notes-arm"]


def test_a_killed_render_leaves_nothing_the_next_render_does_not_remove(cli, tmp_path):
    out = tmp_path / "out"
    assert cli("run", NOTES, "--out", out, "--no-video", "-q").exit_code == 0  # the run to render, in-process
    folder = out / "notes-arm"
    before = user_files(folder)
    proc = _start(["render", folder, "--jobs", "2", "--size", "480x360", "-q"], tmp_path)
    kids = _wait_for_ffmpeg(proc, workers=2)
    proc.kill()
    proc.wait()
    _, alive = psutil.wait_procs(kids, timeout=60)
    assert alive == []
    assert user_files(folder) == before  # the render worked on a staged copy
    result = cli("render", folder, "--jobs", "1", "--size", "64x48", "--fps", "10", "-q")  # the next, in-process
    assert result.exit_code == 0, result.stderr
    assert sorted(p.name for p in out.iterdir()) == [".notes-arm.lock", "notes-arm"]
    assert not [p for p in folder.iterdir() if ".part" in p.name]


def test_a_killed_batch_takes_its_workers_with_it(tmp_path):
    proc = _start(
        ["run", *_batch_scenes(tmp_path), "--out", tmp_path / "out", "--jobs", "2", "--size", "480x360", "-q"], tmp_path
    )
    kids = _wait_for_ffmpeg(proc, workers=2)
    proc.kill()
    proc.wait()
    _, alive = psutil.wait_procs(kids, timeout=60)  # the forkserver and resource tracker too (a hang guard)
    assert alive == []


@pytest.mark.parametrize("signame", ["SIGINT", "SIGTERM"])
def test_a_batch_stops_without_a_traceback(tmp_path, signame):
    """How soon it stops (the promise: a second or two) is measured by benchmarks/reliability_bench.py."""
    out = tmp_path / "out"
    proc = _start(["run", *_batch_scenes(tmp_path), "--out", out, "--jobs", "2", "--size", "480x360", "-q"], tmp_path)
    kids = _wait_for_ffmpeg(proc, workers=2)
    if signame == "SIGINT":
        os.killpg(proc.pid, signal.SIGINT)  # as a terminal's Ctrl-C: to the whole group
    else:
        proc.send_signal(signal.SIGTERM)
    _, stderr = proc.communicate(timeout=120)  # a hang guard
    assert proc.returncode == 130
    assert stderr == "armanim: interrupted; nothing half-written was left behind\n"
    _, alive = psutil.wait_procs(kids, timeout=60)
    assert alive == []  # workers, their ffmpeg, the forkserver and the resource tracker
    assert list((tmp_path / "tmp").iterdir()) == []  # workers removed their temporary folders
    assert [p.name for p in out.glob(".*") if not p.name.endswith(".lock")] == []


def test_fps_flag_that_makes_the_holds_too_long_is_exit_2(cli, tmp_path):
    scene = tmp_path / "s.yaml"
    scene.write_text(
        "version: 1\narm: {links: [1, 1, 1, 1]}\ngoals:\n  - {position: [1, 1, 2], hold: 3600}\n"
        "  - {position: [1, 1, 2.5], hold: 3600}\nrender: {fps: 10}\n"
    )
    result = cli("run", scene, "--out", tmp_path / "out", "--no-video", "-q", "--fps", "240")
    assert result.exit_code == 2 and "--fps 240: the holds would make up to" in result.stderr, result.output
    assert not (tmp_path / "out" / "s").exists()
