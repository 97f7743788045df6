"""Scene (validated, degrees) -> Problem (radians, numpy): the one place degrees become radians.

The scene model is also the one place defaults are written: the core's settings have
none, and code that wants the defaults without a scene file (tests, benchmarks, the
command line's arm flags) builds them here, through the model (:func:`default_solver_settings`,
:func:`default_render_settings`, :func:`unlimited_limits`).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from armanim.arm.kinematics import Arm, default_axes
from armanim.motion.problem import Goal, Limits, Problem, RenderSettings, SolverSettings
from armanim.scene.models import ArmModel, RenderModel, SceneModel, SolverModel
from armanim.world.obstacles import Obstacles


def axis_names(scene: SceneModel) -> list[str]:
    """The scene's joint axes, or the contract's default (z, then y)."""
    return list(scene.arm.axes) if scene.arm.axes is not None else default_axes(len(scene.arm.links))


def _limits(arm: ArmModel) -> Limits:
    n = len(arm.links)
    pairs = arm.limits if arm.limits is not None else [None] * n
    lower = np.array([np.radians(p[0]) if p is not None else -np.inf for p in pairs])
    upper = np.array([np.radians(p[1]) if p is not None else np.inf for p in pairs])
    return Limits(lower=lower, upper=upper, margin=float(np.radians(arm.limit_margin)))


def _obstacles(scene: SceneModel) -> Obstacles:
    if not scene.obstacles:
        return Obstacles.none()
    return Obstacles(
        centers=np.array([o.center for o in scene.obstacles], dtype=float),
        radii=np.array([o.radius for o in scene.obstacles], dtype=float),
        influence=np.array([o.influence if o.influence is not None else o.radius for o in scene.obstacles], dtype=float),
    )


CLEARANCE_PER_WIDTH = 0.1
"""Default ``solver.clearance`` as a fraction of ``arm.width``: a tenth of the arm's thickness."""


def clearance(solver: SolverModel, width: float) -> float:
    """d_safe: the scene's ``solver.clearance``, or ``arm.width / 10``."""
    return float(solver.clearance) if solver.clearance is not None else CLEARANCE_PER_WIDTH * width


def solver_settings(s: SolverModel, width: float) -> SolverSettings:
    """The scene's ``solver`` section as the solvers' settings (radians; ``width`` is the arm's,
    for the default clearance). ``solver.step`` becomes ``beta``."""
    return SolverSettings(
        method=s.method,
        beta=s.step,
        max_step=s.max_step if s.max_step is not None else np.inf,
        tolerance=s.tolerance,
        max_frames_per_goal=s.max_frames_per_goal,
        jacobian=s.jacobian,
        damping=s.damping,
        max_joint_step=float(np.radians(s.max_joint_step)),
        clearance=clearance(s, width),
        planner=s.planner,
        w_goal=s.weights.goal,
        w_obstacles=s.weights.obstacles,
        w_limits=s.weights.limits,
        w_target=s.weights.target,
        w_regularizer=s.weights.regularizer,
    )


def scene_to_problem(scene: SceneModel, fps: float | None = None) -> Problem:
    """Convert a validated scene to the solver's problem (radians, numpy arrays).

    Parameters
    ----------
    scene : SceneModel
    fps : float, optional
        Frames per second of the frames the problem describes, when they are not the
        scene's own (a finished run shown at ``run --fps``). The motion is always solved at
        ``render.fps`` and sampled at another rate (:func:`armanim.motion.resample.resample`).

    Returns
    -------
    Problem
    """
    arm = scene.arm
    n = len(arm.links)
    fps = scene.render.fps if fps is None else fps
    return Problem(
        arm=Arm.from_names(arm.links, base=arm.base, axes=axis_names(scene), direction=arm.direction),
        half_width=arm.width / 2.0,
        home=np.radians(np.array(arm.home if arm.home is not None else [0.0] * n, dtype=float)),
        limits=_limits(arm),
        obstacles=_obstacles(scene),
        goals=tuple(Goal(np.array(g.position, dtype=float), g.hold) for g in scene.goals),
        solver=solver_settings(scene.solver, arm.width),
        fps=fps,
    )


def render_settings(scene: SceneModel) -> RenderSettings:
    """The scene's render section as plain settings."""
    return render_section_settings(scene.render)


def render_section_settings(r: RenderModel) -> RenderSettings:
    """A ``render`` section as plain settings (camera angles None where the section leaves them out)."""
    return RenderSettings(
        fps=r.fps,
        size=(int(r.size[0]), int(r.size[1])),
        elevation=r.view.elevation if "elevation" in r.view.model_fields_set else None,
        azimuth=r.view.azimuth if "azimuth" in r.view.model_fields_set else None,
        bounds=None if r.bounds == "auto" else np.array(r.bounds, dtype=float),
        trail=r.trail,
        format=r.format,
    )


def default_solver_settings(**changes) -> SolverSettings:
    """The solver settings of a scene that leaves ``solver`` and ``arm.width`` out, with
    ``changes`` (the settings' own names and units: ``beta``, radians) applied.

    >>> settings = default_solver_settings(method="dls")
    >>> settings.method, settings.beta, settings.clearance
    ('dls', 0.1, 0.05)
    """
    return replace(solver_settings(SolverModel(), _arm_default("width")), **changes)


def default_render_settings(**changes) -> RenderSettings:
    """The render settings of a scene that leaves ``render`` out, with ``changes`` applied.

    >>> default_render_settings(size=(320, 240)).fps
    30.0
    """
    return replace(render_section_settings(RenderModel()), **changes)


def unlimited_limits(n: int) -> Limits:
    """Limits of ``n`` freely turning joints, with the scene's default ``arm.limit_margin``."""
    return Limits.unlimited(n, margin=float(np.radians(_arm_default("limit_margin"))))


def _arm_default(name: str):
    return ArmModel.model_fields[name].default
