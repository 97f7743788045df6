"""Issue 19: the holes the second attack campaign found (research/redteam-2026-12.md), each
held by a test that failed before its fix.

Each test is named in docs/reliability.md, which it keeps true. No test asserts how long
anything takes (benchmarks/reliability_bench.py measures that); waits are hang guards only.
"""

from __future__ import annotations

import ast
import re
import threading
from pathlib import Path

import pytest
from conftest import DOCS, TESTS
from signals import Command, Sweep

from armanim.errors import INTERRUPTED, UsageError

# ------------------------------------------------------------------ 4. a scheduler that never answers


def test_a_scheduler_that_never_answers_is_given_up_after_the_deadline():
    """The client is made on a thread that is given up: Client(timeout=...) does not bound the handshake."""
    from armanim.runs.executors import connect_client

    release = threading.Event()

    def silent_client(address, timeout):
        release.wait()  # accepts, never answers

    try:
        with pytest.raises(UsageError, match=r"the Dask scheduler at tcp://127.0.0.1:9 did not answer within 0.2 s"):
            connect_client(silent_client, "tcp://127.0.0.1:9", seconds=0.2)
    finally:
        release.set()


@pytest.mark.parametrize("error, words", [(ValueError("bad"), "is not a scheduler address"),
                                          (OSError("refused"), "cannot reach the Dask scheduler at")])
def test_a_scheduler_that_fails_is_exit_2_with_its_reason(error, words):
    from armanim.runs.executors import connect_client

    def failing_client(address, timeout):
        raise error

    with pytest.raises(UsageError, match=words):
        connect_client(failing_client, "tcp://127.0.0.1:9", seconds=30)


# ------------------------------------------------------------------ 7, 8. signals over each command's life

TINY = ("version: 1\nname: tiny\narm:\n  links: [1, 1]\ngoals:\n  - [1, 1, 0]\n  - {{position: [0, 1.5, 0.5], hold: 3}}\n"
        "solver: {{step: {step}}}\nrender: {{fps: 10, size: [96, 64]}}\n")  # about 70 frames: two render workers


def _scenes(folder: Path, count: int = 1) -> tuple[list[str], list[str]]:
    """``count`` new scenes and their previous versions (same names, another step: other bytes)."""
    folder.mkdir(parents=True, exist_ok=True)
    new, old = [], []
    for i in range(count):
        for step, paths in ((0.1, new), (0.3, old)):
            path = folder / f"{'new' if step == 0.1 else 'old'}{i}.yaml"
            path.write_text(TINY.format(step=step).replace("name: tiny", f"name: tiny{i}"))
            paths.append(str(path))
    return new, old


def _commands(folder: Path) -> dict:
    new, old = _scenes(folder / "scenes", 2)
    run_folder = ["out/tiny0"]
    batch = ["out/tiny0", "out/tiny1"]
    sweep = ["out/tiny0_step-0.1", "out/tiny0_step-0.2"]
    return {
        "run": Command("run", ["run", new[0], "--out", "{out}", "--jobs", "2"], run_folder,
                       [["run", old[0], "--out", "{out}", "--jobs", "2"]]),
        "batch": Command("batch", ["run", *new, "--out", "{out}", "--jobs", "2"], [*batch, "out/index.csv"],
                         [["run", *old, "--out", "{out}", "--jobs", "2", "--no-video"]]),
        "sweep": Command("sweep", ["sweep", new[0], "--set", "solver.step=0.1,0.2", "--out", "{out}", "--jobs", "2"],
                         [*sweep, "out/new0-sweep.csv"],
                         [["sweep", old[0], "--set", "solver.step=0.1,0.2", "--set", "solver.max_step=0.4", "--out", "{out}", "--jobs", "2"]]),
        "check --update": Command("check", ["check", *new, "--golden", "{golden}", "--update"], ["golden"],
                                  [["check", *old, "--golden", "{golden}", "--update"]]),
        "render": Command("render", ["render", "{out}/tiny0", "--jobs", "2", "--size", "80x48"], run_folder,
                          [["run", new[0], "--out", "{out}", "--no-video"]]),
    }


MOMENTS = {  # a handful per command (each attempt is a real process); benchmarks/signal_campaign.py sweeps many more
    "run": [("start", 0.0, "SIGTERM"), ("ffmpeg", 0.2, "SIGINT"), ("commit", 0.0, "SIGINT")],
    "batch": [("workers", 0.0, "SIGINT"), ("commit", 0.0, "SIGTERM")],
    "sweep": [("workers", 0.0, "SIGTERM")],
    "check --update": [("start", 0.5, "SIGINT")],
    "render": [("ffmpeg", 0.0, "SIGINT")],
}


@pytest.mark.slow
@pytest.mark.parametrize("name", MOMENTS)
def test_a_signal_at_any_moment_ends_with_0_or_130_and_old_or_new_outputs(tmp_path, name):
    """Ctrl-C (to the group) and SIGTERM (to armanim) over each command's life, at the commit too:
    exit 0 or 130, no traceback, each folder (golden pair) old or whole new, no litter, no process left."""
    sweep = Sweep(_commands(tmp_path)[name], tmp_path / "sweep")
    outcomes = [sweep.attempt(moment, delay, signame) for moment, delay, signame in MOMENTS[name]]
    wrong = {o.moment + " " + o.signame: o.problems() + [o.stderr[-2000:]] for o in outcomes if o.problems()}
    assert wrong == {}
    for o in outcomes:
        interrupted = o.code == 130
        assert o.stderr.strip().splitlines()[-1:] == ([INTERRUPTED] if interrupted else o.stderr.strip().splitlines()[-1:])


# ------------------------------------------------------------------ the page of promises


def named_tests(page: str) -> set[tuple[str, str]]:
    r"""(test file, test name) of every test docs/reliability.md names.

    A name is ``tests/FILE.py::test_x``; ``::test_x`` (in the file named last on the page);
    or a bare ``test_x`` (in the file named before it on its line, else ``tests/test_hardening.py``).

    >>> sorted(named_tests("| `test_a` | `tests/test_b.py::test_c`, `::test_d[x]` |\n| `test_e`, `::test_f` |"))
    [('test_b.py', 'test_c'), ('test_b.py', 'test_d'), ('test_b.py', 'test_f'), ('test_hardening.py', 'test_a'), ('test_hardening.py', 'test_e')]
    """
    found, last = set(), "test_hardening.py"
    for line in page.splitlines():
        on_line = "test_hardening.py"
        for ref in re.findall(r"`([^`]*test_\w+[^`]*)`", line):
            match = re.fullmatch(r"(tests/(test_\w+\.py))?(::)?(test_\w+)(?:\[.*\])?", ref.strip())
            if match is None:
                continue
            if match.group(2):
                last = on_line = match.group(2)
            found.add((match.group(2) or (last if match.group(3) else on_line), match.group(4)))
    return found


def test_every_test_the_reliability_page_names_exists():
    named = named_tests((DOCS / "reliability.md").read_text(encoding="utf-8"))
    defined = {(path.name, node.name) for path in TESTS.glob("test_*.py")
               for node in ast.parse(path.read_text()).body if isinstance(node, ast.FunctionDef)}
    assert len(named) > 50 and named <= defined, sorted(named - defined)


def test_the_reliability_page_names_every_test_of_this_file():
    named = {name for file, name in named_tests((DOCS / "reliability.md").read_text(encoding="utf-8"))
             if file == Path(__file__).name}
    here = {name for name in globals() if name.startswith("test_") and "reliability_page" not in name}
    assert here <= named, sorted(here - named)
