"""armanim: batch animator for articulated arms.

The package root stays light: importing :mod:`armanim` loads nothing heavy, so the
pure core (``armanim.kinematics``, ``armanim.cost``, ``armanim.solvers``) can be used
without YAML, pydantic, typer or matplotlib. The public API (documented in docs/python-api.md) is loaded on first use.
"""

from __future__ import annotations

__version__ = "0.1.0"

_LAZY = {
    "load_scene": ("armanim.scene", "load_scene"),
    "scene_to_problem": ("armanim.scene", "scene_to_problem"),
    "run_scene": ("armanim.pipeline", "run_scene"),
    "rerender_run": ("armanim.pipeline", "rerender_run"),
    "run_batch": ("armanim.batch", "run_batch"),
    "run_sweep": ("armanim.sweep", "run_sweep"),
    "parse_setting": ("armanim.sweep", "parse_setting"),
    "RenderOverrides": ("armanim.overrides", "RenderOverrides"),
    "solve_pose": ("armanim.ik", "solve_pose"),
    "forward": ("armanim.kinematics", "forward"),
    "Arm": ("armanim.kinematics", "Arm"),
    "solve_trajectory": ("armanim.trajectory", "solve_trajectory"),
}

__all__ = ["__version__", *_LAZY]


def __getattr__(name: str):
    if name in _LAZY:
        import importlib

        module, attr = _LAZY[name]
        return getattr(importlib.import_module(module), attr)
    raise AttributeError(f"module 'armanim' has no attribute {name!r}")
