"""The documentation's code runs as written."""

from __future__ import annotations

import contextlib
import io
import os
import re

import pytest
from conftest import ROOT


def python_blocks(text: str) -> list[str]:
    return re.findall(r"^```python\n(.*?)^```$", text, flags=re.M | re.S)


@pytest.mark.slow
def test_every_python_api_example_runs_in_order(tmp_path):
    (tmp_path / "scenes").symlink_to(ROOT / "scenes")
    blocks = python_blocks((ROOT / "docs" / "python-api.md").read_text(encoding="utf-8"))
    assert len(blocks) >= 5
    namespace: dict = {"__name__": "__main__"}  # as when run as a script
    printed = io.StringIO()
    cwd = os.getcwd()
    os.chdir(tmp_path)
    try:
        for block in blocks:
            with contextlib.redirect_stdout(printed):
                exec(compile(block, "docs/python-api.md", "exec"), namespace)  # noqa: S102 (our own documentation)
    finally:
        os.chdir(cwd)
    text = printed.getvalue()
    assert "outputs/notes-arm\n" in text and "converged" in text and "notes-arm-sweep.csv" in text
    assert (tmp_path / "outputs" / "index.csv").is_file()  # the batch and the sweep wrote theirs
    assert (tmp_path / "outputs" / "notes-arm-side" / "poster.png").is_file()
    assert "outputs/notes-arm-viewer.html\n" in text and (tmp_path / "outputs" / "notes-arm-viewer.html").is_file()
    assert (
        "{'box': {'center': [0.62, 0.0, 0.19], 'size': [0.3, 0.7, 0.02], 'rpy': [0.0, 0.0, 0.0]}, 'name': 'board'}"
        in text
    )
    assert (tmp_path / "outputs" / "shelf.yaml").read_text().startswith("# armanim import moveit:")


@pytest.mark.slow
def test_a_script_without_the_main_guard_is_told_why_its_workers_died(tmp_path):
    import subprocess
    import sys

    (tmp_path / "scenes").symlink_to(ROOT / "scenes")
    (tmp_path / "unguarded.py").write_text(
        "from armanim import RunOptions, run_batch\n"
        "entries = run_batch(['scenes/planar-nlink.yaml', 'scenes/out-of-reach.yaml'], 'outputs', RunOptions(video=False, jobs=2))\n"
        "print('\\n'.join(e.status + ' ' + e.message for e in entries))\n"
    )
    proc = subprocess.run([sys.executable, "unguarded.py"], cwd=tmp_path, capture_output=True, text=True, timeout=240)
    lines = proc.stdout.splitlines()
    assert len(lines) == 2 and all(line.startswith("failed") for line in lines), proc.stdout
    assert all('keep the call under `if __name__ == "__main__":`' in line for line in lines)
