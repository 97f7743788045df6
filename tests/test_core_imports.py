"""The pure core imports no edge library (design.md: imports point one way)."""

from __future__ import annotations

import json
import subprocess
import sys

CORE = ["armanim", "armanim.kinematics", "armanim.cost", "armanim.solvers", "armanim.trajectory", "armanim.ik",
        "armanim.geometry", "armanim.problem", "armanim.linalg", "armanim.names", "armanim.stalls", "armanim.solution",
        "armanim.planning", "armanim.overrides"]
FORBIDDEN = ["matplotlib", "yaml", "pydantic", "typer", "rich", "click", "imageio"]


def test_core_loads_no_edge_library():
    code = (
        "import importlib, json, sys\n"
        f"for m in {CORE!r}: importlib.import_module(m)\n"
        f"print(json.dumps(sorted(m for m in {FORBIDDEN!r} if m in sys.modules)))\n"
        "print(json.dumps(sorted(sys.modules)))\n"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr
    loaded, modules = (json.loads(line) for line in proc.stdout.splitlines())
    assert loaded == [], loaded
    assert "armanim.kinematics" in modules and "numpy" in modules  # the imports did happen
    assert not [m for m in modules if m.startswith(("armanim.scene", "armanim.render", "armanim.cli", "armanim.pipeline"))]
