"""The notice before a solve whose kernels numba compiles first (runs/warmth.py, cli/app.py)."""

from __future__ import annotations

import io
import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest
from rich.console import Console

CHECK = textwrap.dedent("""
    import numpy as np
    from armanim.arm.kernel import compiled, machine_code_cached

    @compiled()
    def twice(x):
        return 2.0 * x

    print(machine_code_cached(twice))
    twice(np.ones(2))
    print(machine_code_cached(twice))
""")


def test_machine_code_is_cached_after_the_first_call_and_in_the_next_process(tmp_path):
    # numba's own cache folder, empty: the first process compiles and saves, the next one finds it
    script = tmp_path / "probe.py"
    script.write_text(CHECK)
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache")}
    first = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, env=env, timeout=300)
    assert first.returncode == 0, first.stderr
    assert first.stdout.split() == ["False", "True"]
    again = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, env=env, timeout=300)
    assert again.stdout.split() == ["True", "True"]


def test_the_notice_is_said_at_a_terminal_only_and_only_before_a_first_compile(monkeypatch):
    import importlib

    from armanim.runs import warmth

    cli_app = importlib.import_module("armanim.cli.app")  # the module (the package's ``app`` is the Typer app)

    for terminal, cold, said in ((True, True, True), (True, False, False), (False, True, False)):
        stream = io.StringIO()
        monkeypatch.setattr(cli_app, "err", Console(file=stream, force_terminal=terminal, width=200))
        monkeypatch.setattr(warmth, "compiles_first", lambda command, problem=None, cold=cold: cold)
        cli_app.tell_first_compile("run")
        assert (warmth.FIRST_COMPILE in stream.getvalue()) is said


def test_a_first_compile_counts_each_kernel_it_compiles_at_a_terminal(monkeypatch):
    """After the notice, a line for each kernel numba starts to compile from Python (its count and name);
    the kernels it calls compile inside it and are not counted apart; a kernel already compiled says nothing."""
    import importlib

    import numba
    from numba.core import event

    from armanim.runs import warmth

    cli_app = importlib.import_module("armanim.cli.app")
    stream = io.StringIO()
    monkeypatch.setattr(cli_app, "err", Console(file=stream, force_terminal=True, width=200))
    monkeypatch.setattr(warmth, "compiles_first", lambda command, problem=None: True)
    listeners = list(event._registered["numba:compile"])
    cli_app.tell_first_compile("run")
    counter = next(x for x in event._registered["numba:compile"] if x not in listeners)
    try:

        @numba.njit(cache=False)
        def inner(x):
            return x + 1.0

        @numba.njit(cache=False)
        def outer(x):
            return 2.0 * inner(x)

        outer(1.0), outer(np.ones(2)), outer(3.0)
    finally:
        event.unregister("numba:compile", counter)
    lines = stream.getvalue().splitlines()
    assert lines[0] == warmth.FIRST_COMPILE
    assert [line.split(" (")[0] for line in lines[1:]] == [
        "armanim: compiling 1: " + outer.__qualname__,
        "armanim: compiling 2: " + outer.__qualname__,
    ]


def test_compiles_first_answers_for_both_commands():
    from armanim.runs.pose import ik_problem
    from armanim.runs.warmth import compiles_first
    from armanim.scene import scene_model

    problem = ik_problem(
        scene_model({"version": 1, "arm": {"robot": "panda"}, "goals": [[0.4, 0.0, 0.4]]}), None, None, from_flags=False
    )
    assert {type(compiles_first("run")), type(compiles_first("ik", problem))} == {bool}


def test_armanim_warm_solves_every_warm_scene_and_leaves_the_run_s_kernels_cached(tmp_path):
    """``armanim warm`` (the installed command): every scene it warms solves, nothing is written in
    the folder it runs in, and afterwards a run's kernels are in numba's cache (no notice before a run)."""
    from armanim.runs.warm import warm_scenes
    from armanim.runs.warmth import compiles_first

    done = subprocess.run(
        [sys.executable, "-m", "armanim", "warm"], cwd=tmp_path, capture_output=True, text=True, timeout=900
    )
    assert done.returncode == 0, done.stderr
    assert f"armanim warm: {len(warm_scenes()) + 2} solves" in done.stdout.replace("\n", " ")
    assert list(tmp_path.iterdir()) == []
    assert not compiles_first("run")


@pytest.mark.parametrize("quiet", [False, True])
def test_warm_where_numba_keeps_nothing_says_so_and_never_that_the_cache_keeps_it(cli, monkeypatch, quiet):
    """Campaign 16: ``armanim warm`` with numba's cache on a full disk compiled for 261 s and said
    "numba's cache keeps it until armanim changes"; nothing was kept, the next run compiled again."""
    from armanim.runs.warm import Warmed

    # what the workers answered: numba kept none of their machine code
    monkeypatch.setattr("armanim.runs.warm.warm", lambda progress, jobs: Warmed(solves=25, compiling=261.0, kept=False))
    result = cli("warm", *(["--quiet"] if quiet else []))
    assert result.exit_code == 0, result.output
    assert "cache keeps it" not in result.output
    assert "every command compiles it again" in result.stderr and "NUMBA_CACHE_DIR" in result.stderr
