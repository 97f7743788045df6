"""Hardening (issue 7): hostile input, interruption and faults lose nothing and show no traceback.

Each test is named in the table of docs/reliability.md, which it keeps true.
"""

from __future__ import annotations

import errno
import hashlib
import json
import os
import shutil
import signal
import subprocess
import sys
import threading
import time
import tracemalloc
from dataclasses import replace
from pathlib import Path

import numpy as np
import psutil
import pytest
from conftest import SCENES

from armanim.errors import RenderError, SceneError
from armanim.output.rundir import MARKER
from armanim.scene import validate_scene_text
from armanim.scene.models import LIMITS
from armanim.scene.yamlread import MAX_DEPTH, MAX_FILE_BYTES, MAX_NODES

NOTES = SCENES / "notes-arm.yaml"
PLANAR = SCENES / "planar-nlink.yaml"
SMALL = "version: 1\narm:\n  links: [1, 1]\ngoals:\n  - [1, 0, 0]\n"
TINY = "version: 1\narm:\n  links: [1, 1]\ngoals:\n  - [1, 1, 0]\n  - [0, 1.5, 0.5]\nrender: {fps: 10}\n"
LEFTOVER_MARKS = (".partial", ".tmp", ".part", ".old-", ".concat")


def armanim_exe() -> str:
    exe = Path(sys.executable).parent / "armanim"
    return str(exe) if exe.exists() else shutil.which("armanim")


def snapshot(folder: Path) -> dict[str, str]:
    """sha256 of every file below ``folder``, by relative path."""
    return {str(p.relative_to(folder)): hashlib.sha256(p.read_bytes()).hexdigest() for p in sorted(folder.rglob("*")) if p.is_file()}


def leftovers(root: Path) -> list[str]:
    """Temporary files or folders anywhere below ``root`` (the lock file is meant to stay)."""
    return [str(p) for p in root.rglob("*") if any(mark in p.name for mark in LEFTOVER_MARKS)]


@pytest.fixture(scope="module")
def previous_notes(tmp_path_factory) -> Path:
    """A complete earlier run of notes-arm (CSV, summary, scene copy), made once."""
    out = tmp_path_factory.mktemp("previous")
    proc = subprocess.run([armanim_exe(), "run", str(NOTES), "--out", str(out), "--no-video", "--quiet"],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
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
    from armanim.runs.pipeline import run_scene

    out = tmp_path_factory.mktemp("previous-tiny")
    run_scene(tiny_scene, out, video=False)
    return out


@pytest.fixture()
def previous_run(previous_tiny, tmp_path) -> tuple[Path, dict]:
    """A copy of the earlier tiny run in tmp_path/out, and its snapshot."""
    out = tmp_path / "out"
    shutil.copytree(previous_tiny, out)
    return out, snapshot(out / "tiny")


def one_line_error(result) -> str:
    text = result.stderr.strip()
    assert "Traceback" not in result.output
    assert text and len(text.splitlines()) == 1, text
    return text


# ------------------------------------------------------------------ 1. exit codes


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


@pytest.mark.parametrize("args", [("validate", "MISSING"), ("run", "SCENE", "--size", "huge"), ("fk", "--angles", "a,b")])
def test_exit_2_bad_input_or_usage(cli, tmp_path, args):
    (tmp_path / "bad.yaml").write_text(SMALL.replace("[1, 1]", "[1, -1]"))
    args = [str(tmp_path / "missing.yaml") if a == "MISSING" else str(tmp_path / "bad.yaml") if a == "SCENE" else a for a in args]
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


def test_scene_error_survives_pickling():
    """Batch workers send SceneErrors back to the parent pickled."""
    import pickle

    with pytest.raises(SceneError) as info:
        validate_scene_text(SMALL.replace("[1, 1]", "[1, -1]"), "bad.yaml")
    again = pickle.loads(pickle.dumps(info.value))
    assert again.report() == info.value.report() and again.problems == info.value.problems


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


# ------------------------------------------------------------------ 2. hostile YAML


def _bomb(levels: int = 9, width: int = 9) -> str:
    lines = ["a0: &a0 [" + ", ".join(["lol"] * width) + "]"]
    for i in range(1, levels):
        lines.append(f"a{i}: &a{i} [" + ", ".join([f"*a{i - 1}"] * width) + "]")
    return "\n".join(lines) + "\n"


HOSTILE = {
    # name: (text, field path or "" for the file, line, words in the message)
    "alias bomb": (_bomb(), None, None, ["expands to more than", f"{MAX_NODES:,}", "alias bomb"]),
    "recursive alias": ("a: &a [1, *a]\n", "a[1]", 1, ["refers to a value that contains it"]),
    "deep block nesting": ("".join("  " * i + "a:\n" for i in range(100)) + "  " * 100 + "b: 1\n", None, MAX_DEPTH + 2, [f"nesting deeper than {MAX_DEPTH} levels"]),
    "deep flow nesting": ("a: " + "[" * 10_000 + "]" * 10_000 + "\n", None, 1, [f"nesting deeper than {MAX_DEPTH} levels"]),
    "deep dash nesting": ("a:\n" + "- " * 10_000 + "x\n", None, None, [f"nesting deeper than {MAX_DEPTH} levels"]),
    "many values": ("a: [" + ", ".join(["0"] * 200_000) + "]\n", None, 1, ["expands to more than"]),
    "1e400": (SMALL.replace("[1, 0, 0]", "[1e400, 0, 0]"), "goals[0].position[0]", 5, ["must be a finite number (got inf)"]),
    ".nan": (SMALL.replace("[1, 0, 0]", "[.nan, 0, 0]"), "goals[0].position[0]", 5, ["must be a finite number (got nan)"]),
    "10**400": (SMALL.replace("[1, 0, 0]", f"[{10**400}, 0, 0]"), "goals[0][0]", 5, ["401-digit integer is too large"]),
    "10**5000": (SMALL.replace("[1, 0, 0]", "[1" + "0" * 5000 + ", 0, 0]"), "goals[0][0]", 5, ["5001-digit integer is too large"]),
    "10,000 links": (SMALL.replace("[1, 1]", "[" + ", ".join(["1"] * 10_000) + "]"), "arm.links", 3, ["10000 items", f"at most {LIMITS['links']}"]),
    "1,001 goals": ("version: 1\narm:\n  links: [1, 1]\ngoals:\n" + "  - [1, 0, 0]\n" * 1001, "goals", 4, ["1001 items", "at most 1000"]),
    "tab indentation": (SMALL.replace("  links", "\tlinks"), "", 3, ["not valid YAML", "tab character", "spaces"]),
    "duplicate key": (SMALL + "version: 1\n", "version", 6, ["duplicate key 'version'", "first on line 1"]),
    "list as key": (SMALL + "[a, b]: 1\n", "", 6, ["mapping key must be a plain name (got a list)"]),
    "mapping as key": (SMALL + "? {a: 1}\n: 2\n", "", 6, ["mapping key must be a plain name (got a mapping)"]),
    "merge key": ("version: 1\narm:\n  <<: {links: [1, 1]}\ngoals:\n  - [1, 0, 0]\n", "arm", 3, ["merge keys (<<) are not supported"]),
    "timestamp": (SMALL + "name: 2001-12-14\n", "name", 6, ["unsupported YAML tag '!!timestamp'"]),
    "binary": (SMALL + "name: !!binary aGVsbG8=\n", "name", 6, ["unsupported YAML tag '!!binary'"]),
    "python object": (SMALL + "name: !!python/object/apply:os.system ['false']\n", "name", 6, ["unsupported YAML tag", "not executed"]),
    "string as number": (SMALL.replace("[1, 0, 0]", "['1', 0, 0]"), "goals[0].position[0]", 5, ["must be a number (got '1')"]),
    "bool as number": (SMALL.replace("[1, 0, 0]", "[true, 0, 0]"), "goals[0].position[0]", 5, ["must be a number (got true)"]),
    "control character": (SMALL + "name: a\x07b\n", "", 6, ["is not allowed in YAML"]),
    "too many frames": ("version: 1\narm:\n  links: [1, 1]\ngoals:\n" + "  - {position: [1, 0, 0], hold: 3600}\n" * 10 + "render: {fps: 240}\n",
                        "goals", 4, ["frames", f"at most {LIMITS['total_frames']:,}"]),
    "many unknown keys": (SMALL + "".join(f"k{i}: 1\n" for i in range(2000)), "", None, ["unknown key 'k0'", "more problems"]),
}


@pytest.mark.parametrize("name", HOSTILE)
def test_hostile_yaml_is_rejected_fast_with_bounded_memory(name):
    """Rejected with its FILE:LINE: path: message, in bounded memory (a tracemalloc peak, the
    same on any machine). How fast is measured by benchmarks/reliability_bench.py, not here:
    a wall-clock bound fails on a busy machine."""
    text, field, line, words = HOSTILE[name]
    with pytest.raises(SceneError) as info:
        validate_scene_text(text, "hostile.yaml")
    tracemalloc.start()
    try:
        with pytest.raises(SceneError):
            validate_scene_text(text, "hostile.yaml")
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 32 * 2**20, f"{name}: peak {peak / 2**20:.1f} MiB"
    report = info.value.report()
    assert len(report) < 20_000, report[:500]
    problems = info.value.problems
    if field is not None:
        assert any(p.path == field for p in problems), report
    if line is not None:
        assert any(p.line == line for p in problems), report
    for word in words:
        assert word in report, (word, report[:2000])
    for p in problems:
        assert p.format("hostile.yaml").startswith("hostile.yaml"), p


def test_hostile_yaml_through_the_cli_is_file_line_path_message(cli, tmp_path):
    path = tmp_path / "bomb.yaml"
    path.write_text(_bomb())
    result = cli("validate", path)
    assert result.exit_code == 2
    assert result.stderr.startswith(f"{path}:"), result.stderr
    path.write_text(HOSTILE["1e400"][0])
    result = cli("validate", path)
    assert result.exit_code == 2
    assert f"{path}:5: goals[0].position[0]: must be a finite number (got inf)" in result.stderr


def test_huge_file_is_rejected_before_reading(cli, tmp_path):
    from armanim.scene import load_scene

    path = tmp_path / "huge.yaml"
    path.write_text(SMALL + "#" * (MAX_FILE_BYTES + 10) + "\n")
    result = cli("validate", path)
    assert result.exit_code == 2
    assert f"a scene may be at most {MAX_FILE_BYTES:,} bytes" in result.stderr
    tracemalloc.start()
    try:
        with pytest.raises(SceneError):
            load_scene(path)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < MAX_FILE_BYTES / 10, f"peak {peak:,} bytes: the file was read"  # its size says no first


def test_non_utf8_bytes_name_their_line(cli, tmp_path):
    path = tmp_path / "latin1.yaml"
    path.write_bytes(SMALL.encode() + b"name: caf\xe9\n")
    result = cli("validate", path)
    assert result.exit_code == 2
    assert f"{path}:6: byte 0xe9 is not UTF-8" in result.stderr


def test_largest_valid_scene_still_loads(tmp_path):
    """The limits leave room for a maximal scene: 64 links, 1000 goals, 1000 obstacles."""
    links = ", ".join(["0.1"] * LIMITS["links"])
    goals = "".join(f"  - {{position: [1, {i % 7}, 2], hold: 0.1}}\n" for i in range(LIMITS["goals"]))
    obstacles = "".join(f"  - {{center: [{20 + i}, 30, 40], radius: 0.5, influence: 1}}\n" for i in range(LIMITS["obstacles"]))
    text = f"version: 1\narm:\n  links: [{links}]\nobstacles:\n{obstacles}goals:\n{goals}solver: {{max_frames_per_goal: 900}}\n"
    model = validate_scene_text(text, "big.yaml")  # its time: benchmarks/reliability_bench.py
    assert len(model.goals) == LIMITS["goals"] and len(model.obstacles) == LIMITS["obstacles"]


# ------------------------------------------------------------------ 4. nothing lost


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


@pytest.mark.parametrize("signame, to_group", [("SIGINT", True), ("SIGTERM", False)])
def test_interrupt_mid_render_leaves_nothing_behind(previous_notes, tmp_path, signame, to_group):
    """Ctrl-C (SIGINT to the whole process group, as a terminal sends it) or SIGTERM (to
    armanim only, as `kill` does) while two workers and their ffmpeg render."""
    out = tmp_path / "out"
    shutil.copytree(previous_notes, out)
    before = snapshot(out / "notes-arm")
    proc = subprocess.Popen([armanim_exe(), "run", str(NOTES), "--out", str(out), "--size", "320x180", "--jobs", "2"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
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
    strays = [p.info for p in psutil.process_iter(["pid", "cmdline"]) if any(str(out) in c for c in p.info["cmdline"] or [])]
    assert strays == []


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


# ------------------------------------------------------------------ 5. faults


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
    script.write_text("#!/bin/sh\necho 'first line of ffmpeg noise' >&2\necho 'Error: simulated encoder crash' >&2\nexit 1\n")
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
    scene.write_text(PLANAR.read_text().replace("  tolerance: 0.01\n", "  tolerance: 0.01\n  max_frames_per_goal: 40\n"))
    result = cli("run", scene, "--out", tmp_path / "out", "--no-video", "--quiet")
    assert result.exit_code == 0, result.output
    folder = tmp_path / "out" / "planar-nlink"
    summary = json.loads((folder / "summary.json").read_text())
    reachable = [g for g in summary["goals"] if g["index"] in (0, 1, 2)]
    assert reachable and all(not g["reached"] and g["reason"] == "numerical" for g in reachable), summary["goals"]
    text = (folder / "trajectory.csv").read_text().lower()
    assert "nan" not in text and "inf" not in text
