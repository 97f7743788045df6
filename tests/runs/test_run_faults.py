"""A run under faults and interruption (issue 7): a failed render, a signal mid-render, a
full disk, a denied rename, a missing ffmpeg, two runs of one folder, a killed run, a solver
step of NaN: the previous outputs stay whole and nothing temporary is left.

Each test is named in the table of docs/reliability.md, which it keeps true.
"""

from __future__ import annotations

import errno
import json
import os
import shutil
import signal
import subprocess
import threading
import time
from dataclasses import replace
from pathlib import Path

import numpy as np
import psutil
import pytest
from conftest import SCENES
from runfolders import armanim_exe, leftovers, one_line_error, snapshot

from armanim.errors import RenderError
from armanim.output.rundir import MARKER

NOTES = SCENES / "notes-arm.yaml"


PLANAR = SCENES / "planar-nlink.yaml"


SMALL = "version: 1\narm:\n  links: [1, 1]\ngoals:\n  - [1, 0, 0]\n"


TINY = "version: 1\narm:\n  links: [1, 1]\ngoals:\n  - [1, 1, 0]\n  - [0, 1.5, 0.5]\nrender: {fps: 10}\n"


@pytest.fixture(scope="module")
def previous_notes(tmp_path_factory) -> Path:
    """A complete earlier run of notes-arm (CSV, summary, scene copy), made once, in-process."""
    from armanim.runs.options import RunOptions
    from armanim.runs.pipeline import run_scene

    out = tmp_path_factory.mktemp("previous")
    run_scene(NOTES, out, RunOptions(video=False))
    return out


@pytest.fixture(scope="module")
def tiny_scene(tmp_path_factory) -> Path:
    """A scene that solves in a few frames (the fault tests are about files, not motion)."""
    path = tmp_path_factory.mktemp("scene") / "tiny.yaml"
    path.write_text(TINY)
    return path


@pytest.fixture(scope="module")
def previous_tiny(tiny_scene, tmp_path_factory) -> Path:
    """A complete earlier run of the tiny scene (CSV, summary, scene copy), made once."""
    from armanim.runs.options import RunOptions
    from armanim.runs.pipeline import run_scene

    out = tmp_path_factory.mktemp("previous-tiny")
    run_scene(tiny_scene, out, RunOptions(video=False))
    return out


@pytest.fixture()
def previous_run(previous_tiny, tmp_path) -> tuple[Path, dict]:
    """A copy of the earlier tiny run in tmp_path/out, and its snapshot."""
    out = tmp_path / "out"
    shutil.copytree(previous_tiny, out)
    return out, snapshot(out / "tiny")


def test_exit_3_a_file_stands_at_the_scene_folder(cli, tmp_path, tiny_scene):
    """OUT/<name> is a file: an error before any work, never moved aside."""
    out = tmp_path / "out"
    out.mkdir()
    (out / "tiny").write_text("mine\n")
    result = cli("run", tiny_scene, "--out", out, "--no-video", "--quiet")
    assert result.exit_code == 3, result.output
    assert "a file stands where a folder is needed" in one_line_error(result)
    assert (out / "tiny").read_text() == "mine\n"
    assert leftovers(out) == []


def test_exit_130_interrupted_in_process(cli, tmp_path, monkeypatch, tiny_scene, previous_run):
    out, before = previous_run

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr("armanim.runs.pipeline.solve_trajectory", interrupted)
    result = cli("run", tiny_scene, "--out", out, "--no-video", "--quiet")
    assert result.exit_code == 130, result.output
    assert "interrupted" in one_line_error(result)
    assert snapshot(out / "tiny") == before
    assert leftovers(out) == []


def test_failed_render_leaves_previous_outputs_untouched(cli, monkeypatch, tiny_scene, previous_run):
    from armanim.render.video import encode

    out, before = previous_run
    calls = []

    def failing_write(self, rgba):
        calls.append(1)
        if len(calls) == 5:
            raise RenderError("simulated: the encoder broke mid-way")

    monkeypatch.setattr(encode.FrameWriter, "write", failing_write)
    result = cli("run", tiny_scene, "--out", out, "--size", "64x48", "--jobs", "1", "--quiet")
    assert result.exit_code == 3, result.output
    assert "simulated" in result.stderr
    assert snapshot(out / "tiny") == before
    assert leftovers(out) == []


def _name_or_empty(child: psutil.Process) -> str:
    """A child's name, or "" when it ended between listing and asking (a short-lived worker)."""
    try:
        return child.name()
    except psutil.NoSuchProcess:
        return ""


def _wait_for_rendering(proc, out: Path, timeout: float = 60.0) -> list[psutil.Process]:
    """Wait until the run's staging folder holds video work and ffmpeg runs; its children then."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline and proc.poll() is None:
        staged = list(out.glob(".notes-arm.*.partial"))
        if staged and any("animation" in p.name for p in staged[0].iterdir()):
            children = psutil.Process(proc.pid).children(recursive=True)
            if any("ffmpeg" in _name_or_empty(c) for c in children):
                return children
        time.sleep(0.05)
    pytest.fail(f"rendering never started (exit {proc.poll()})")


@pytest.mark.parametrize("signame, to_group", [("SIGINT", True), ("SIGTERM", False), ("SIGHUP", True)])
def test_interrupt_mid_render_leaves_nothing_behind(previous_notes, tmp_path, signame, to_group):
    """Ctrl-C (SIGINT to the whole process group, as a terminal sends it), SIGTERM (to
    armanim only, as `kill` does) or SIGHUP (to the group, as a closing terminal or ssh session
    sends it; campaign 13: armanim died by it, exit -1, its staging folder left) while two
    workers and their ffmpeg render."""
    out = tmp_path / "out"
    shutil.copytree(previous_notes, out)
    before = snapshot(out / "notes-arm")
    proc = subprocess.Popen(
        [armanim_exe(), "run", str(NOTES), "--out", str(out), "--size", "320x180", "--jobs", "2"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
    )
    try:
        children = _wait_for_rendering(proc, out)
        time.sleep(0.3)
        sig = getattr(signal, signame)
        os.killpg(proc.pid, sig) if to_group else proc.send_signal(sig)
        _, stderr = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:  # pragma: no cover
            os.killpg(proc.pid, signal.SIGKILL)
    assert proc.returncode == 130, stderr
    assert "Traceback" not in stderr
    assert stderr.strip().splitlines() == ["armanim: interrupted; nothing half-written was left behind"], stderr
    assert snapshot(out / "notes-arm") == before
    assert leftovers(out) == []
    assert sorted(p.name for p in out.iterdir()) == [".notes-arm.lock", "notes-arm"]
    gone, alive = psutil.wait_procs(children, timeout=60)  # a hang guard; the promptness is benchmarked
    assert not [p for p in alive if p.status() != psutil.STATUS_ZOMBIE], alive
    strays = [
        p.info for p in psutil.process_iter(["pid", "cmdline"]) if any(str(out) in c for c in p.info["cmdline"] or [])
    ]
    assert strays == []


def test_a_run_under_nohup_goes_on_when_the_terminal_closes(tmp_path):
    """Started with SIGHUP ignored (``nohup``), a run keeps it ignored: a SIGHUP to the group while
    its workers render changes nothing, and the run finishes (exit 0, its folder whole)."""
    out = tmp_path / "out"

    def nohup() -> None:
        signal.signal(signal.SIGHUP, signal.SIG_IGN)

    proc = subprocess.Popen(
        [armanim_exe(), "run", str(NOTES), "--out", str(out), "--size", "160x90", "--jobs", "2", "-q"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
        preexec_fn=nohup,
    )
    try:
        _wait_for_rendering(proc, out)
        os.killpg(proc.pid, signal.SIGHUP)
        _, stderr = proc.communicate(timeout=600)
    finally:
        if proc.poll() is None:  # pragma: no cover
            os.killpg(proc.pid, signal.SIGKILL)
    assert proc.returncode == 0, stderr
    assert (out / "notes-arm" / MARKER).is_file() and (out / "notes-arm" / "animation.mp4").is_file()
    assert leftovers(out) == []


def test_two_runs_of_the_same_folder_never_interleave(tmp_path):
    """staged_folder's lock: the second writer waits until the first has swapped its folder in."""
    from armanim.output.rundir import staged_folder

    final = tmp_path / "out" / "scene"
    events: list[str] = []
    first_inside = threading.Event()

    def writer(tag: str, hold: float):
        with staged_folder(final) as staged:
            events.append(f"{tag} in")
            first_inside.set()
            for i in range(3):
                (staged / f"part{i}.txt").write_text(tag)
                time.sleep(hold)
            events.append(f"{tag} out")

    a = threading.Thread(target=writer, args=("a", 0.1))
    a.start()
    assert first_inside.wait(120)
    b = threading.Thread(target=writer, args=("b", 0.0))
    b.start()
    a.join(120)
    b.join(120)
    assert events == ["a in", "a out", "b in", "b out"]
    assert {p.read_text() for p in final.iterdir() if p.name != MARKER} == {"b"}
    assert leftovers(tmp_path) == []


def test_two_processes_running_the_same_scene_at_once(tmp_path):
    out = tmp_path / "out"
    scene = tmp_path / "small.yaml"
    scene.write_text(SMALL.replace("[1, 0, 0]", "[1, 1, 0]\n  - [0, 1.5, 0.5]"))
    cmd = [armanim_exe(), "run", str(scene), "--out", str(out), "--no-video", "--quiet"]
    procs = [subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) for _ in range(2)]
    for p in procs:
        _, err = p.communicate(timeout=120)
        assert p.returncode == 0, err
    folder = out / "small"
    summary = json.loads((folder / "summary.json").read_text())
    rows = (folder / "trajectory.csv").read_text().splitlines()
    assert len(rows) - 1 == summary["totals"]["frames"]
    assert leftovers(out) == []


def test_killed_run_is_tidied_by_the_next(cli, tmp_path, tiny_scene, previous_run):
    """A run killed outright mid-swap: the next run puts the old folder back, then removes leftovers."""
    from armanim.output.rundir import staged_folder

    out, before = previous_run
    os.rename(out / "tiny", out / ".tiny.old-99999")
    (out / ".tiny.abcdefgh.partial").mkdir()
    with pytest.raises(RuntimeError):
        with staged_folder(out / "tiny"):
            raise RuntimeError("fails after recovery")
    assert snapshot(out / "tiny") == before
    assert leftovers(out) == []


@pytest.mark.parametrize("name", [".tiny.old-1", ".tiny.abcdefgh.partial"])
@pytest.mark.parametrize("with_run_folder", [True, False])
def test_a_user_folder_named_as_a_leftover_is_never_removed(cli, tiny_scene, previous_run, name, with_run_folder):
    """Campaign 9: a folder of the user's that bears a staging or moved-aside name (a copy kept as
    ``.tiny.old-1``) was removed with all it held by the next run, or, with no run folder, moved
    into its place (and the run refused). Only a leftover armanim made is tidied."""
    out, _ = previous_run
    if not with_run_folder:
        shutil.rmtree(out / "tiny")
    mine = out / name
    mine.mkdir()
    (mine / "thesis.txt").write_text("mine\n")
    result = cli("run", tiny_scene, "--out", out, "--no-video", "--quiet")
    assert result.exit_code == 0, result.output
    assert sorted(os.listdir(mine)) == ["thesis.txt"]
    assert (mine / "thesis.txt").read_text() == "mine\n"
    assert (out / "tiny" / MARKER).is_file()


def test_a_killed_run_s_staging_folder_with_its_files_is_removed_by_the_next(tmp_path, previous_run):
    """What a run killed mid-write leaves (its staging folder, some files written) is still armanim's,
    and removed; so is one killed after its marker was written."""
    from armanim.output.rundir import staged_folder

    out, before = previous_run
    kept = []
    with pytest.raises(RuntimeError):
        with staged_folder(out / "tiny") as staged:
            (staged / "trajectory.csv").write_text("frame\n")
            shutil.copytree(staged, out / ".tiny.killed01.partial")  # as a kill -9 here leaves it
            kept.append(staged)
            raise RuntimeError("stop")
    shutil.copytree(out / "tiny", out / ".tiny.killed02.partial")  # killed after the marker, before the swap
    with pytest.raises(RuntimeError):
        with staged_folder(out / "tiny"):
            raise RuntimeError("fails after recovery")
    assert snapshot(out / "tiny") == before
    assert leftovers(out) == []
    assert not kept[0].exists()


def test_os_replace_permission_denied(cli, monkeypatch, tiny_scene, previous_run):
    out, before = previous_run

    def denied(src, dst):
        raise PermissionError(errno.EACCES, "Permission denied", str(dst))

    monkeypatch.setattr("armanim.output.atomic.os.replace", denied)
    result = cli("run", tiny_scene, "--out", out, "--no-video", "--quiet")
    assert result.exit_code == 3, result.output
    assert "cannot write here: permission denied" in one_line_error(result)
    monkeypatch.undo()
    assert snapshot(out / "tiny") == before
    assert leftovers(out) == []


@pytest.mark.parametrize("command", ["run", "render", "export", "view"])
def test_a_write_protected_run_folder_is_refused_and_left_whole(cli, monkeypatch, tiny_scene, previous_run, command):
    """Campaign 16, as a user (not root): a run folder made read-only (chmod 555) was replaced
    anyway, exit 0, and its moved-aside copy ``.tiny.old-PID``, which nobody could remove, was left
    beside it for ever. Root writes through modes, so the user's view of the folder is simulated."""
    out, before = previous_run

    def as_its_owner(path, mode, **kwargs):  # what os.access answers a user who is not root
        return not (mode & os.W_OK) or bool(os.stat(path).st_mode & 0o200)

    monkeypatch.setattr("armanim.output.rundir.os.access", as_its_owner)
    (out / "tiny").chmod(0o555)
    args = {
        "run": ("run", tiny_scene, "--out", out, "--no-video", "--quiet"),
        "render": ("render", out / "tiny", "--size", "64x36"),
        "export": ("export", out / "tiny"),
        "view": ("view", out / "tiny"),
    }[command]
    result = cli(*args)
    (out / "tiny").chmod(0o755)
    assert result.exit_code == 3, result.output
    assert "is write-protected" in one_line_error(result) and "chmod -R u+w" in one_line_error(result)
    assert snapshot(out / "tiny") == before
    assert leftovers(out) == []


@pytest.mark.parametrize("protected", ["tiny", "tiny/summary.json"])
def test_a_run_folder_made_read_only_is_refused_by_its_modes_as_root_too(cli, tiny_scene, previous_run, protected):
    """Left from campaign 16's fix: a run folder's protection was asked of ``os.access``, which root
    passes, while a golden's was read from its mode bits: as root, a ``chmod 555`` run folder was
    replaced, exit 0. One rule now (``files.write_protected``): no write bit left, or not writable by
    this process; a file in the folder made read-only protects it as well. Real modes, whoever runs
    the suite."""
    out, before = previous_run
    path = out / protected
    mode = path.stat().st_mode & 0o777
    path.chmod(mode & ~0o222)
    result = cli("run", tiny_scene, "--out", out, "--no-video", "--quiet")
    path.chmod(mode)
    assert result.exit_code == 3, result.output
    shown = "the folder" if protected == "tiny" else "'summary.json'"
    assert f"is write-protected ({shown} is read-only)" in one_line_error(result)
    assert snapshot(out / "tiny") == before
    assert leftovers(out) == []


@pytest.mark.parametrize("readable", [True, False])
def test_another_user_s_lock_file_is_used_or_named(cli, monkeypatch, tiny_scene, previous_run, readable):
    """Campaign 16, as a user who is not root: OUT/.tiny.lock left by another user (root's, 0644,
    in a shared folder) stopped the run with exit 3, "OUT/tiny: cannot write here: permission
    denied", naming the run folder the user could write. A lock only read is locked all the same
    (flock); one that cannot be opened at all is named. Root opens anything: the modes are simulated."""
    out, before = previous_run
    lock = out / ".tiny.lock"
    lock.touch()
    real_open = os.open

    def as_another_user_s(path, flags, *args, **kwargs):
        if str(path) == str(lock) and (flags & (os.O_WRONLY | os.O_RDWR) or not readable):
            raise PermissionError(errno.EACCES, "Permission denied", str(path))
        return real_open(path, flags, *args, **kwargs)

    monkeypatch.setattr("armanim.output.rundir.os.open", as_another_user_s)
    result = cli("run", tiny_scene, "--out", out, "--no-video", "--quiet")
    if readable:
        assert result.exit_code == 0, result.output
        assert (out / "tiny" / "summary.json").is_file()
    else:
        assert result.exit_code == 3, result.output
        assert one_line_error(result).startswith(f"{lock}: the lock of {out / 'tiny'} cannot be opened")
        assert snapshot(out / "tiny") == before
    assert leftovers(out) == []


def test_disk_full(cli, monkeypatch, tiny_scene, previous_run):
    out, before = previous_run
    real_fsync = os.fsync
    written = []

    def full(fd):
        written.append(fd)
        if len(written) >= 2:  # the scene copy fits, the trajectory does not
            raise OSError(errno.ENOSPC, "No space left on device")
        real_fsync(fd)

    monkeypatch.setattr("armanim.output.atomic.os.fsync", full)
    result = cli("run", tiny_scene, "--out", out, "--no-video", "--quiet")
    assert result.exit_code == 3, result.output
    assert "the disk is full" in one_line_error(result)
    monkeypatch.undo()
    assert snapshot(out / "tiny") == before
    assert leftovers(out) == []


def _fake_ffmpeg(tmp_path: Path) -> Path:
    script = tmp_path / "ffmpeg-broken"
    script.write_text(
        "#!/bin/sh\necho 'first line of ffmpeg noise' >&2\necho 'Error: simulated encoder crash' >&2\nexit 1\n"
    )
    script.chmod(0o755)
    return script


@pytest.mark.parametrize("kind", ["missing", "failing"])
def test_ffmpeg_missing_or_failing(cli, tmp_path, monkeypatch, tiny_scene, previous_run, kind):
    import imageio_ffmpeg

    out, before = previous_run
    exe = tmp_path / "no-such-ffmpeg" if kind == "missing" else _fake_ffmpeg(tmp_path)
    monkeypatch.setattr(imageio_ffmpeg, "get_ffmpeg_exe", lambda: str(exe))
    result = cli("run", tiny_scene, "--out", out, "--size", "64x48", "--jobs", "1", "--quiet")
    assert result.exit_code == 3, result.output
    assert "Traceback" not in result.output
    if kind == "missing":
        assert "ffmpeg could not be started" in result.stderr and str(exe) in result.stderr
    else:
        assert "ffmpeg failed while writing animation.mp4" in result.stderr
        assert "Error: simulated encoder crash" in result.stderr
    assert snapshot(out / "tiny") == before  # CSV and summary of the previous run intact
    assert leftovers(out) == []


def test_solver_step_producing_nan(cli, tmp_path, monkeypatch):
    from armanim.motion.solvers import METHODS, Step

    def nan_step(problem, state, goal):
        return Step(dphi=np.full(problem.arm.n, np.nan))

    monkeypatch.setitem(METHODS, "newton", replace(METHODS["newton"], step_function=nan_step))
    scene = tmp_path / "nan.yaml"
    scene.write_text(
        PLANAR.read_text().replace("  tolerance: 0.01\n", "  tolerance: 0.01\n  max_frames_per_goal: 40\n")
    )
    result = cli("run", scene, "--out", tmp_path / "out", "--no-video", "--quiet")
    assert result.exit_code == 0, result.output
    folder = tmp_path / "out" / "planar-nlink"
    summary = json.loads((folder / "summary.json").read_text())
    reachable = [g for g in summary["goals"] if g["index"] in (0, 1, 2)]
    assert reachable and all(not g["reached"] and g["reason"] == "numerical" for g in reachable), summary["goals"]
    text = (folder / "trajectory.csv").read_text().lower()
    assert "nan" not in text and "inf" not in text
