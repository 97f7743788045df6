"""Checks of a scene that span several fields, each reported with its field path.

Run after the models validated, so every value has its type; every problem is
collected, none stops the others.
"""

from __future__ import annotations

import numpy as np

from armanim.cost import clearances
from armanim.errors import Diagnostic
from armanim.kinematics import forward
from armanim.scene.convert import scene_to_problem
from armanim.scene.models import SceneModel


def scene_problems(scene: SceneModel) -> list[tuple[str, str]]:
    """Every cross-field problem of a validated scene, as (field path, message) pairs.

    The collision checks run once the arm itself is consistent.
    """
    problems = list(_arm_problems(scene))
    if not problems:
        problems += list(_collision_problems(scene_to_problem(scene)))
    return problems


def _arm_problems(scene: SceneModel):
    arm = scene.arm
    n = len(arm.links)
    for field in ("axes", "home", "limits"):
        values = getattr(arm, field)
        if values is not None and len(values) != n:
            yield f"arm.{field}", f"has {len(values)} entries, the arm has {n} links (expected one per joint)"
    if arm.limits is not None:
        for i, pair in enumerate(arm.limits):
            if pair is not None and not pair[0] < pair[1]:
                yield f"arm.limits[{i}]", f"min must be below max (got [{pair[0]:g}, {pair[1]:g}])"
    if arm.home is not None and arm.limits is not None and len(arm.home) == n == len(arm.limits):
        for i, (angle, pair) in enumerate(zip(arm.home, arm.limits)):
            if pair is not None and pair[0] < pair[1] and not pair[0] < angle < pair[1]:
                yield f"arm.home[{i}]", f"{angle:g} deg is outside joint {i + 1}'s limits (expected strictly inside [{pair[0]:g}, {pair[1]:g}])"
    if scene.render.bounds != "auto":
        for axis, pair in zip("xyz", scene.render.bounds):
            if not pair[0] < pair[1]:
                yield "render.bounds", f"{axis} range must have min < max (got [{pair[0]:g}, {pair[1]:g}])"


def _collision_problems(problem):
    obstacles = problem.obstacles
    if not len(obstacles):
        return
    cl = clearances(forward(problem.arm, problem.home), obstacles, problem.half_width)
    for link, obs in zip(*np.nonzero(cl.links <= 0)):
        yield f"obstacles[{obs}]", (
            f"link {link + 1} of the arm's home pose is inside this obstacle (clearance {cl.links[link, obs]:.3g}; "
            "expected the home pose clear of every obstacle: move the obstacle or change arm.home)"
        )
    for k, goal in enumerate(problem.goals):
        gap = np.linalg.norm(goal.position - obstacles.centers, axis=1) - obstacles.radii
        for obs in np.nonzero(gap <= 0)[0]:
            yield f"goals[{k}]", f"lies inside obstacles[{obs}] (the tip can never reach it; move the goal or the obstacle)"


def as_diagnostics(pairs, line_of) -> list[Diagnostic]:
    """Attach line numbers to (path, message) pairs."""
    return [Diagnostic(path, message, line_of(path)) for path, message in pairs]
