"""The first run's second process (armanim.runs.beside): it calls the very kernels, with the very
argument types, that a run calls after its solve (else its compiling is lost and the run compiles
them again), and it never outlives the run."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
from pathlib import Path

import psutil
import pytest

from armanim.runs import beside

ROOT = Path(__file__).resolve().parents[2]

DUMP = """
import sys
from numba.core import dispatcher
called = set()
compile_for_args = dispatcher.Dispatcher._compile_for_args
def recorded(self, *args, **kws):  # a call from Python with argument types new to this process
    types = tuple(self.typeof_pyval(a) for a in args)
    called.add(self.py_func.__module__ + "." + self.py_func.__qualname__ + " | " + str(types))
    return compile_for_args(self, *args, **kws)
dispatcher.Dispatcher._compile_for_args = recorded
exec(sys.argv[1])
print("\\n".join(sorted(called)))
"""

PANDA = """version: 1
arm: {robot: panda}
floor: 0.0
obstacles:
  - box: {center: [0.6, -0.4, 0.6], size: [0.1, 0.1, 0.1]}
  - {center: [0.2, 0.5, 0.6], radius: 0.05}
goals: [[0.45, -0.1, 0.5]]
render: {size: [160, 90]}
"""


def kernels_called(code: str) -> set[tuple[str, str]]:
    """(kernel, argument types) of every armanim kernel a fresh process called from Python while it ran
    ``code`` (the kernels they call inside are compiled or loaded with them; numba's cache warm or not)."""
    done = subprocess.run(
        [sys.executable, "-c", DUMP, code], capture_output=True, text=True, timeout=600, check=True, cwd=ROOT
    )
    called = {tuple(part.strip() for part in line.split("|", 1)) for line in done.stdout.splitlines() if "|" in line}
    return {(name, types) for name, types in called if name.startswith("armanim.")}


AFTER_SOLVE = ("armanim.motion.timing.passes.", "armanim.motion.planning.check._margins", "armanim.render.solids.")


@pytest.mark.parametrize("scene", ["notes-arm", "panda"])
def test_the_second_process_calls_what_the_run_calls_after_its_solve(tmp_path, scene):
    path = ROOT / "scenes/notes-arm.yaml" if scene == "notes-arm" else tmp_path / "panda.yaml"
    if scene == "panda":
        path.write_text(PANDA)
    run = kernels_called(
        "from armanim.runs.options import RunOptions, RenderOverrides\n"
        "from armanim.runs.pipeline import run_scene\n"
        f"run_scene({str(path)!r}, {str(tmp_path / 'out')!r}, RunOptions(jobs=1,"
        " render=RenderOverrides(size=(160, 90))))"
    )
    ahead = kernels_called(
        f"from armanim.runs.beside import compile_after_solve\ncompile_after_solve({str(path)!r}, video=True)"
    )
    after = {kernel for kernel in run if kernel[0].startswith(AFTER_SOLVE)}
    assert {name for name, _ in after} >= {
        "armanim.motion.timing.passes.backward_pass",
        "armanim.motion.planning.check._margins",
    }
    assert after <= ahead, "the run calls these after its solve, and the second process does not"
    drawn = {kernel for kernel in ahead if kernel[0].startswith("armanim.render.")}
    assert ahead - drawn <= run, "the second process compiles kernels the run does not call"
    assert drawn, "the second process compiles the video's rasteriser"


def test_a_second_process_is_started_only_for_a_first_run_on_two_cores_of_a_scene_file(tmp_path, monkeypatch):
    scene = ROOT / "scenes/notes-arm.yaml"
    monkeypatch.setattr("armanim.runs.warmth.compiles_first", lambda command, problem=None: True)
    assert beside.should_compile_beside(scene, 2)
    assert not beside.should_compile_beside(scene, 1)
    fifo = tmp_path / "scene.yaml"
    os.mkfifo(fifo)
    assert not beside.should_compile_beside(fifo, 2)  # a pipe is read by the run alone
    assert not beside.should_compile_beside(tmp_path / "missing.yaml", 2)
    monkeypatch.setattr("armanim.runs.warmth.compiles_first", lambda command, problem=None: False)
    assert not beside.should_compile_beside(scene, 2)  # the kernels are compiled: nothing to do


def _children() -> set[psutil.Process]:
    """This process's children now (an xdist worker may have others of its own: a pool, a tracker)."""
    return set(psutil.Process().children())


def test_the_second_process_ends_with_the_run(monkeypatch):
    monkeypatch.setattr(beside, "should_compile_beside", lambda path, jobs: True)
    monkeypatch.setattr(beside, "beside_command", lambda path, video: ["sleep", "600"])  # it would outlive the run
    before = _children()
    with beside.compiling_beside(Path("scene.yaml"), video=False, jobs=2):
        (child,) = _children() - before
        assert child.cmdline() == ["sleep", "600"]
    assert not child.is_running()  # ended (SIGTERM) and reaped as the run ended
    assert _children() - before == set()


def test_the_second_process_says_nothing_and_fails_quietly(tmp_path):
    done = subprocess.run(
        [sys.executable, "-m", "armanim.runs.beside", str(tmp_path / "missing.yaml"), str(os.getpid())],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert (done.returncode, done.stdout, done.stderr) == (1, "", "")


def test_the_second_process_ends_when_the_run_is_killed():
    """Promise 14 of docs/reliability.md: no process outlives armanim, even one killed with kill -9."""
    parent = subprocess.Popen(["sleep", "600"])
    stalled = (
        "import sys, time\nfrom armanim.runs import beside\nbeside.compile_after_solve = lambda *a: time.sleep(600)\n"
    )
    child = subprocess.Popen(
        [sys.executable, "-c", stalled + "sys.exit(beside.main(sys.argv[1:]))", "scene.yaml", str(parent.pid)]
    )
    parent.kill()
    parent.wait()
    assert child.wait(timeout=60) == 128 + signal.SIGTERM


def test_a_second_process_that_cannot_start_leaves_the_run_to_compile_alone(monkeypatch):
    monkeypatch.setattr(beside, "should_compile_beside", lambda path, jobs: True)
    monkeypatch.setattr(beside, "beside_command", lambda path, video: ["/nonexistent/python"])
    before = _children()
    with beside.compiling_beside(Path("scene.yaml"), video=False, jobs=2):
        assert _children() - before == set()
