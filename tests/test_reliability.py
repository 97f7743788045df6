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

from armanim.errors import UsageError

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
