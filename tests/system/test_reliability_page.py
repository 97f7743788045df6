"""docs/reliability.md names tests that exist, and every test of the files that hold its promises."""

from __future__ import annotations

import ast
import re
from functools import cache

import pytest
from conftest import DOCS, TESTS

PROMISE_FILES = (
    "arm/test_geometry.py",
    "cli/test_exit_codes.py",
    "cli/test_interrupts.py",
    "runs/test_batch_limits.py",
    "runs/test_golden_update.py",
    "runs/test_run_faults.py",
    "runs/test_run_folder.py",
    "procs/test_worker_signals.py",
    "scene/test_hostile_yaml.py",
    "system/test_signal_moments.py",
)
"""Files of tests (below tests/) that exist for the page's promises: the page names each of their tests."""


def named_tests(page: str) -> set[tuple[str | None, str]]:
    r"""(test file below tests/, test name) of every test docs/reliability.md names.

    A name is ``tests/ROOM/FILE.py::test_x``; ``::test_x`` (in the file named last on the page);
    or a bare ``test_x`` (in the file named before it on its line, else ``None``: in whichever
    file of the suite defines it).

    >>> sorted(named_tests("| `test_a` | `tests/b/test_b.py::test_c`, `::test_d[x]`, `test_g` |\n| `test_e`, `::test_f` |"), key=str)
    [('b/test_b.py', 'test_c'), ('b/test_b.py', 'test_d'), ('b/test_b.py', 'test_f'), ('b/test_b.py', 'test_g'), (None, 'test_a'), (None, 'test_e')]
    """
    found, last = set(), None
    for line in page.splitlines():
        on_line = None
        for ref in re.findall(r"`([^`]*test_\w+[^`]*)`", line):
            match = re.fullmatch(r"(tests/((?:\w+/)*test_\w+\.py))?(::)?(test_\w+)(?:\[.*\])?", ref.strip())
            if match is None:
                continue
            if match.group(2):
                last = on_line = match.group(2)
            found.add((match.group(2) or (last if match.group(3) else on_line), match.group(4)))
    return found


@cache  # the suite's files do not change during a run; parsing them all took 0.4 s a test
def defined_tests() -> frozenset[tuple[str, str]]:
    """(test file below tests/, test name) of every test function of the suite."""
    return frozenset(
        (path.relative_to(TESTS).as_posix(), node.name)
        for path in TESTS.rglob("test_*.py")
        for node in ast.parse(path.read_text()).body
        if isinstance(node, ast.FunctionDef) and node.name.startswith("test_")
    )


def test_every_test_the_reliability_page_names_exists():
    named = named_tests((DOCS / "reliability.md").read_text(encoding="utf-8"))
    defined = defined_tests() | {(None, name) for _, name in defined_tests()}
    assert len(named) > 50 and named <= defined, sorted(named - defined, key=str)


def test_test_names_the_page_names_alone_are_unique_in_the_suite():
    named = {name for file, name in named_tests((DOCS / "reliability.md").read_text(encoding="utf-8")) if file is None}
    files = {}
    for file, name in defined_tests():
        files.setdefault(name, []).append(file)
    assert {name: files[name] for name in named if len(files.get(name, [])) > 1} == {}


@pytest.mark.parametrize("file", PROMISE_FILES)
def test_the_reliability_page_names_every_test_of_the_promise_files(file):
    page = named_tests((DOCS / "reliability.md").read_text(encoding="utf-8"))
    named = {name for named_file, name in page if named_file in (file, None)}
    here = {name for path, name in defined_tests() if path == file}
    assert here and here <= named, sorted(here - named)
