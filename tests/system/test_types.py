"""The code passes mypy: strict on the pure core (arm, world, motion), the default checks on the
edges (the settings and the reason for each: pyproject.toml [tool.mypy]), in one run of mypy."""

from __future__ import annotations

import re
import subprocess
import sys
import tomllib

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


def strict_flags() -> list[str]:
    """The flags mypy's ``--strict`` enables, as its own ``--help`` lists them."""
    text = subprocess.run(
        [sys.executable, "-m", "mypy", "--help"], capture_output=True, text=True, timeout=120, check=True
    ).stdout
    listing = text.split("--strict ", 1)[1].split("enables the following flags:", 1)[1]
    listing = listing.split("\n  --", 1)[0]  # the next option's line ends the listing
    return re.findall(r"--[a-z]+(?:-\s*[a-z]+)*", listing)


def test_the_core_is_checked_with_every_flag_of_strict():
    """The core's settings (pyproject.toml: the global ones and the core's override) are mypy's
    whole ``--strict``, flag for flag as this mypy lists it, so that :func:`test_mypy_finds_nothing`
    is a ``--strict`` run of the core (one mypy run, not two: each took 20-40 s of the suite)."""
    pytest.importorskip("mypy")
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["mypy"]
    core = next(o for o in config["overrides"] if "armanim.motion.*" in o["module"])
    settings = {**{k: v for k, v in config.items() if k != "overrides"}, **core}
    flags = [re.sub(r"\s+", "", f) for f in strict_flags()]
    assert len(flags) >= 10, flags  # the listing was found
    for flag in flags:
        name = flag.removeprefix("--").replace("-", "_")
        inverted = name.removeprefix("no_")
        on = settings.get(name) is True or (name != inverted and settings.get(inverted) is False)
        assert on, f"{flag} (mypy --strict) is not set for the core in pyproject.toml [tool.mypy]"
