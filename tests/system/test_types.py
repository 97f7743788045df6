"""The code passes mypy: strict on the pure core (arm, world, motion), the default checks on the
edges (the settings and the reason for each: pyproject.toml [tool.mypy])."""

from __future__ import annotations

import subprocess
import sys

import pytest
from conftest import ROOT


def test_mypy_finds_nothing(tmp_path):
    pytest.importorskip("mypy")  # in the test extra; skipped only outside it
    result = subprocess.run(
        [sys.executable, "-m", "mypy", "--cache-dir", str(tmp_path / "cache")],  # files and settings: pyproject.toml
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert result.returncode == 0, result.stdout + result.stderr


def test_the_core_passes_mypy_strict_as_it_is(tmp_path):
    """The per-module settings of the core are mypy's whole --strict: checked against the flag itself."""
    pytest.importorskip("mypy")
    result = subprocess.run(
        [
            sys.executable,
            "-m",
            "mypy",
            "--strict",
            "--cache-dir",
            str(tmp_path / "cache"),
            "--ignore-missing-imports",
            "--follow-imports",
            "silent",
            "-p",
            "armanim.arm",
            "-p",
            "armanim.world",
            "-p",
            "armanim.motion",
        ],
        cwd=ROOT / "src",
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert result.returncode == 0, result.stdout + result.stderr
