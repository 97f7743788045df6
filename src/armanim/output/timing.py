"""timing.json: how long a run took, the one output that differs from run to run.

``summary.json`` and ``trajectory.csv`` are the same bytes on every rerun of a scene, so no wall
time goes in them; this file holds them instead (README, "Run folder").
"""

from __future__ import annotations

from pathlib import Path

from armanim.output.atomic import write_text_atomic
from armanim.output.jsontext import json_text
from armanim.output.solved import RunTiming

TIMING_FILE = "timing.json"


def timing_record(timing: RunTiming, outputs_s: float) -> dict:
    """timing.json's content: the solve's wall times (``timing``) and the files' and pictures'
    (``outputs_s``), seconds to the microsecond.

    >>> timing_record(RunTiming(0.01, 0.2, 0.03, (0.05, 0.15)), 1.5)["goals"]
    [{'goal': 0, 'plan_time_s': 0.05}, {'goal': 1, 'plan_time_s': 0.15}]
    """
    return {
        "scene_to_trajectory_s": round(timing.scene_to_trajectory_s, 6),
        "convert_s": round(timing.convert_s, 6),
        "solve_s": round(timing.solve_s, 6),
        "clock_s": round(timing.clock_s, 6),
        "outputs_s": round(outputs_s, 6),
        "goals": [{"goal": k, "plan_time_s": round(seconds, 6)} for k, seconds in enumerate(timing.goals)],
    }


def write_timing(timing: RunTiming, outputs_s: float, path: Path) -> None:
    """Write timing.json atomically (2-space indent)."""
    write_text_atomic(path, json_text(timing_record(timing, outputs_s), indent=2) + "\n")
