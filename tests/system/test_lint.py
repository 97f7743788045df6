"""The code passes ruff's rules (and the reason for every ignore: pyproject.toml [tool.ruff]) and is as
ruff formats it (`ruff format src tests benchmarks tools` before a commit)."""

from __future__ import annotations

import subprocess
import sys

import pytest
from conftest import ROOT


def test_ruff_finds_nothing():
    pytest.importorskip("ruff")  # in the test extra; skipped only outside it
    result = subprocess.run(
        [sys.executable, "-m", "ruff", "check", "--no-cache", "src", "tests", "benchmarks"],
        cwd=ROOT,
        capture_output=True,
        text=True,
    )
    assert result.returncode == 0, result.stdout + result.stderr


def test_ruff_format_changes_nothing():
    pytest.importorskip("ruff")
    result = subprocess.run(
        [sys.executable, "-m", "ruff", "format", "--check", "--no-cache", "src", "tests", "benchmarks", "tools"],
        cwd=ROOT,
        capture_output=True,
        text=True,
    )
    assert result.returncode == 0, "run: ruff format src tests benchmarks tools\n" + result.stdout + result.stderr
