"""The arm of ``fk`` and ``ik``: from ``--scene``, or from the arm flags through the scene
model, so that every default (width, home, limits, solver, render) is the scene file's."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from armanim.cli.options import parse_lengths
from armanim.errors import UsageError

SceneOpt = Annotated[Path | None, typer.Option("--scene", help="Take the arm (and its limits) from a scene file.")]
LinksOpt = Annotated[str | None, typer.Option("--links", help="Link lengths, e.g. 2,5,5,5 (default: four unit links).")]
BaseOpt = Annotated[str | None, typer.Option("--base", help="Base position x,y,z (default 0,0,0).")]
AxesOpt = Annotated[str | None, typer.Option("--axes", help="Joint axes, e.g. z,y,y,y (default: z, then y).")]
RobotOpt = Annotated[
    str | None, typer.Option("--robot", help="A bundled robot (armanim robots lists them), e.g. panda.")
]
DirOpt = Annotated[
    str | None, typer.Option("--direction", help="Local axis the links extend along: x, y or z (default z).")
]


def arm_scene(
    scene: Path | None,
    links: str | None,
    base: str | None,
    axes: str | None,
    direction: str | None,
    robot: str | None = None,
):
    """The scene model of ``fk``/``ik``: loaded from ``--scene``, a bundled ``--robot``, or made
    of the arm flags (one of the three).

    Returns the model and the loaded scene (None when the arm came from flags: its goal
    is a placeholder and it has no file).
    """
    if scene is not None or robot is not None:
        flags = [
            f for f, v in (("--links", links), ("--base", base), ("--axes", axes), ("--direction", direction)) if v
        ]
        chosen = "--scene" if scene is not None else "--robot"
        if scene is not None and robot is not None:
            flags.append("--robot")
        if flags:
            raise UsageError(f"{', '.join(flags)} cannot be combined with {chosen} (it defines the arm)")
    if robot is not None:
        return flag_scene({"robot": robot}), None
    if scene is not None:
        from armanim.scene import load_scene

        loaded = load_scene(scene)
        return loaded.model, loaded
    lengths = _links(links)
    arm = {"links": lengths, "direction": _direction(direction)} | _base(base) | _axes(axes, len(lengths))
    return flag_scene(arm), None


def _links(links: str | None) -> list[float]:
    import numpy as np

    from armanim.scene.models import LIMITS

    lengths = parse_lengths(links, "--links") if links else np.ones(4)
    if np.any(lengths <= 0):
        raise UsageError(f"--links: every length must be > 0 (got {links!r})")
    if np.any(lengths < LIMITS["smallest"]):  # as a scene file's links: smaller ones underflow the solver's damping
        raise UsageError(
            f"--links: a length is too small (expected at least {LIMITS['smallest']:g}: choose a larger unit; "
            f"got {links!r})"
        )
    if len(lengths) > LIMITS["links"]:
        raise UsageError(f"--links: {len(lengths)} links (expected at most {LIMITS['links']})")
    return [float(v) for v in lengths]


def _direction(direction: str | None) -> str:
    name = (direction or "z").lower()
    if name not in ("x", "y", "z"):
        raise UsageError(f"--direction: expected x, y or z (got {direction!r})")
    return name


def _base(base: str | None) -> dict:
    return {"base": [float(v) for v in parse_lengths(base, "--base", 3)]} if base else {}


def _axes(axes: str | None, n: int) -> dict:
    if not axes:
        return {}
    names = [a.strip().lower() for a in axes.split(",")]
    if len(names) != n or any(a not in ("x", "y", "z") for a in names):
        raise UsageError(f"--axes: expected {n} of x, y, z separated by commas, one per link (got {axes!r})")
    return {"axes": names}


def flag_scene(arm: dict):
    """The scene model of the arm flags alone, with a placeholder goal; a flag the model
    rejects is a UsageError naming it."""
    from pydantic import ValidationError

    from armanim.scene.models import SceneModel
    from armanim.scene.robots import read_scene_files

    goal = [float(v) + 1.0 for v in arm.get("base", [0.0, 0.0, 0.0])]
    try:
        model = SceneModel.model_validate({"version": 1, "arm": arm, "goals": [goal]})
    except ValidationError as exc:
        first = exc.errors()[0]
        flag = first["loc"][1] if len(first["loc"]) > 1 else next(iter(arm))
        message = first["ctx"]["error"] if first["type"] == "value_error" else first["msg"]
        raise UsageError(f"--{flag}: {message}") from None
    return read_scene_files(model)  # a bundled robot's URDF
