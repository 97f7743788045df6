"""armanim: batch animator for articulated arms.

The package root stays light: importing :mod:`armanim` loads nothing heavy, so the
pure core (``armanim.arm.kinematics``, ``armanim.motion.cost``, ``armanim.motion.solvers``) can be used
without YAML, pydantic, typer or matplotlib. The public API (documented in docs/python-api.md) is loaded on first use.
"""

from __future__ import annotations

__version__ = "0.1.0"

_LAZY = {
    "load_scene": ("armanim.scene", "load_scene"),
    "scene_to_problem": ("armanim.scene", "scene_to_problem"),
    "run_scene": ("armanim.runs.pipeline", "run_scene"),
    "rerender_run": ("armanim.runs.pipeline", "rerender_run"),
    "write_run_viewer": ("armanim.runs.pipeline", "write_run_viewer"),
    "export_run": ("armanim.runs.export", "export_run"),
    "run_batch": ("armanim.runs.batch", "run_batch"),
    "run_sweep": ("armanim.runs.sweep", "run_sweep"),
    "parse_setting": ("armanim.runs.sweep", "parse_setting"),
    "RenderOverrides": ("armanim.render.settings", "RenderOverrides"),
    "RunOptions": ("armanim.runs.options", "RunOptions"),
    "solve_pose": ("armanim.motion.ik", "solve_pose"),
    "forward": (
        "armanim.arm.kernel",
        "forward",
    ),  # compiled (numba, loaded on first use); numpy's is arm.kinematics.forward
    "Arm": ("armanim.arm.kinematics", "Arm"),
    "solve_trajectory": ("armanim.motion.trajectory", "solve_trajectory"),
    "import_moveit": ("armanim.scene.moveitscene", "import_moveit"),
    "RobotSource": ("armanim.scene.moveitscene", "RobotSource"),
}

__all__ = ["__version__", *_LAZY]


def __getattr__(name: str):
    if name in _LAZY:
        import importlib

        module, attr = _LAZY[name]
        return getattr(importlib.import_module(module), attr)
    raise AttributeError(f"module 'armanim' has no attribute {name!r}")
