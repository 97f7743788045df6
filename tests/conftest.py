"""Shared fixtures of the armanim test suite.

Tests find their data through ``Path(__file__).parent``, never the working directory.
"""

from __future__ import annotations

import os
import sys
from functools import cache
from pathlib import Path

# The bundled goldens were written with OpenBLAS's Haswell kernels and numpy's loops without
# AVX-512. A machine picks its own at load time (an AVX-512 Xeon: OpenBLAS's SkylakeX kernels),
# and a goal beyond reach turned a last-bit difference into other frames while pinv chattered
# there (scenes/out-of-reach: 152 frames against 155; since the arm stretches down the distance's
# gradient, 77 frames on Haswell's, Sandybridge's and Prescott's kernels, 1.4e-6 deg/s apart at
# most): the suite asks every machine for the same kernels, set before numpy loads OpenBLAS.
# docs/golden-tests.md says it.
os.environ.setdefault("OPENBLAS_CORETYPE", "Haswell")
os.environ.setdefault(
    "NPY_DISABLE_CPU_FEATURES",
    "AVX512F AVX512CD AVX512_KNL AVX512_KNM AVX512_SKX AVX512_CLX AVX512_CNL AVX512_ICL AVX512_SPR",
)
if "numpy" in sys.modules:  # too late for the line above: a plugin imported numpy first
    sys.stderr.write("tests/conftest.py: numpy was imported before OPENBLAS_CORETYPE was set\n")

# Where PYTHONDONTWRITEBYTECODE is set (it was on the machines this suite was timed on), every
# `armanim` a test starts as a subprocess compiled armanim's modules from source again, some 0.4 s
# of CPU each. The suite writes bytecode as Python does by default, into the __pycache__ folders
# beside the sources, where numba's cache of armanim's kernels already lies.
if os.environ.pop("PYTHONDONTWRITEBYTECODE", None):
    sys.dont_write_bytecode = False

import signal

import pytest
from hypothesis import HealthCheck, settings

# A pytest started in the background of a non-interactive shell (``cmd &``, nohup, a CI step run so)
# inherits SIGINT ignored: Python then installs no handler, and every process a test starts inherits
# the ignored disposition too, so a Ctrl-C a test sends (or raises in itself) passes unseen: 21 tests
# of tests/cli/test_interrupts.py and tests/procs/test_worker_signals.py failed so, alone or in the
# whole suite, never in a terminal. The suite runs with Ctrl-C as Python sets it in a terminal.
if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
    signal.signal(signal.SIGINT, signal.default_int_handler)

TESTS = Path(__file__).resolve().parent
ROOT = TESTS.parent
SCENES = ROOT / "scenes"
DOCS = ROOT / "docs"

ROOMS = ("arm", "world", "motion", "procs", "scene", "output", "render", "runs", "cli", "system")
"""The folders of tests/, one per room of src/armanim (system: what deliberately crosses rooms)."""

# The shared helpers (strategies.py, invariants.py, ...) sit at tests/ top, and a few tests use
# another file's helpers by its name (``from test_scene import write``): --import-mode=importlib
# puts none of these folders on sys.path. Test file names are unique across the rooms
# (tests/system/test_layout.py) so that a name means one file.
# A room's tests may have folders of their own (tests/motion/kernels): on sys.path too.
for folder in [
    TESTS,
    *(TESTS / room for room in ROOMS),
    *sorted(p for room in ROOMS for p in (TESTS / room).glob("*/") if p.is_dir() and p.name != "__pycache__"),
]:
    if str(folder) not in sys.path:
        sys.path.insert(0, str(folder))

# Hypothesis profiles (issue 50, item 13). "armanim", by hand: a fresh random search each run.
# "ci": the same examples on every run of one commit (derandomize: each test's draws follow from its
# own source), so a commit passes or fails CI by itself, never by chance; loaded when CI=true, and
# by .ci/run. "explore": ten times the examples of every test (each test's own max_examples too),
# random, for a search by hand: ARMANIM_HYPOTHESIS_PROFILE=explore python -m pytest tests/motion.
# A failure any of them finds is pinned in its test as an @example.
settings.register_profile(
    "armanim",
    max_examples=30,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much],
    print_blob=True,
    database=None,  # no .hypothesis folder in the repository; runs are reproducible from the seed
)
settings.register_profile("ci", parent=settings.get_profile("armanim"), derandomize=True)
EXPLORE_FACTOR = 10
settings.register_profile("explore", parent=settings.get_profile("armanim"), max_examples=30 * EXPLORE_FACTOR)


def hypothesis_profile(environ) -> str:
    """The profile a run loads: ``ARMANIM_HYPOTHESIS_PROFILE`` if set, else ``ci`` where CI=true,
    else ``armanim`` (pytest's own ``--hypothesis-profile`` overrides either).

    >>> hypothesis_profile({"CI": "true"}), hypothesis_profile({}), hypothesis_profile({"CI": "true", "ARMANIM_HYPOTHESIS_PROFILE": "explore"})
    ('ci', 'armanim', 'explore')
    """
    return environ.get("ARMANIM_HYPOTHESIS_PROFILE") or ("ci" if environ.get("CI") == "true" else "armanim")


settings.load_profile(hypothesis_profile(os.environ))


def pytest_collection_modifyitems(config, items):
    """Under the ``explore`` profile, every Hypothesis test runs EXPLORE_FACTOR times its own
    ``@settings(max_examples=...)`` (a test's count overrides the profile's, so the profile alone
    would leave it as it is)."""
    if settings.default.max_examples != settings.get_profile("explore").max_examples:
        return
    scaled = set()
    for item in items:
        test = getattr(item, "obj", None)
        own = getattr(test, "_hypothesis_internal_use_settings", None)
        if own is None or id(test) in scaled:
            continue
        scaled.add(id(test))
        test._hypothesis_internal_use_settings = settings(own, max_examples=own.max_examples * EXPLORE_FACTOR)


BUNDLED = sorted(SCENES.glob("*.yaml"))


@cache
def solved_scene(path: Path):
    """(problem, solution) of a bundled scene, solved once per session."""
    from armanim.motion.trajectory import solve_trajectory
    from armanim.scene import load_scene, scene_to_problem

    problem = scene_to_problem(load_scene(path).model)
    return problem, solve_trajectory(problem)


@pytest.fixture(scope="session", autouse=True)
def capsule_cache(tmp_path_factory):
    """Fitted capsules are cached in a folder of the session's, never the user's cache folder
    (ARMANIM_CACHE_DIR; commands run in subprocesses inherit it)."""
    before = os.environ.get("ARMANIM_CACHE_DIR")
    os.environ["ARMANIM_CACHE_DIR"] = str(tmp_path_factory.mktemp("capsule-cache"))
    yield
    if before is None:
        os.environ.pop("ARMANIM_CACHE_DIR", None)
    else:
        os.environ["ARMANIM_CACHE_DIR"] = before


@pytest.fixture(scope="session")
def scenes_dir() -> Path:
    assert SCENES.is_dir(), SCENES
    return SCENES


@pytest.fixture(scope="session")
def bundled_scenes() -> list[Path]:
    assert BUNDLED, f"no scenes in {SCENES}"
    return BUNDLED


@pytest.fixture()
def ctrl_c_raises():
    """Ctrl-C raises KeyboardInterrupt in this process for the test's duration (Python's own handler),
    whatever handler the process holds (see the SIGINT note at this file's top): a signal the test
    raises in itself is then never passed unseen."""
    import signal

    old = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, old)


@pytest.fixture()
def runner():
    from typer.testing import CliRunner

    return CliRunner()


@pytest.fixture()
def cli(runner):
    """Invoke the armanim Typer app in-process: cli("fk", "--angles", "0,0,0,0")."""
    from armanim.cli import app

    def invoke(*args: str):
        result = runner.invoke(app, [str(a) for a in args])
        assert "Traceback" not in result.output, result.output
        if result.exception is not None and not isinstance(result.exception, SystemExit):
            raise result.exception
        return result

    return invoke
