"""The four solver methods behind one registry; every step then goes through the filter (:mod:`armanim.motion.filter`).

A method owns only its step: given the problem, the current angles and the goal, its
step function proposes a joint update (a :class:`Step`). The drivers own the loop: the
frame loop (:mod:`armanim.motion.trajectory`) owns termination, holds and reached/missed, the
pose solver (:mod:`armanim.motion.ik`) owns attempts and restarts; both pass every proposal
through :func:`armanim.motion.filter.barrier.safe_step` (the safety filter). What a driver must
know of a method is data on its registry entry (:class:`Method`), never a test of its name.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal, Protocol

import numpy as np

from armanim.motion.orientation import Orientation
from armanim.motion.problem import Problem
from armanim.motion.solvers.common import ArmState, Step, arm_state
from armanim.motion.solvers.gradient import gradient_step
from armanim.motion.solvers.linear import dls_step, pinv_step
from armanim.motion.solvers.newton import newton_step
from armanim.names import MethodName


class StepFunction(Protocol):
    """A method's proposal for one frame toward the goal position (and the goal's
    :class:`~armanim.motion.orientation.Orientation`, when it has one)."""

    def __call__(
        self, problem: Problem, state: ArmState, goal: np.ndarray, orientation: Orientation | None = None
    ) -> Step:
        """The proposal from ``state`` toward ``goal`` (3,), scene units."""
        ...


@dataclass(frozen=True)
class Method:
    """A solver method: its step function and how a pose is solved to convergence with it.

    Attributes
    ----------
    step_function : StepFunction
        The method's proposal for one frame (one iteration of a solve).
    full_step_solves : bool
        Solving takes beta = 1, so that each step aims at the goal itself (Newton-Raphson
        on the tip for ``pinv`` and ``dls``; ``newton`` solves f to the goal). False
        where beta is a descent rate rather than a fraction of the way (``gradient``).
    bounds_own_steps : bool
        The method's own line searches bound its joint steps (``newton``): solving lifts
        the joint-step cap, and the filter only guards limits and obstacles.
    attempt_steps : int or None
        Steps of one attempt before a solve restarts elsewhere; None: the whole budget.
        Full linear steps converge in a handful, so a slow crawl is better restarted;
        a ``newton`` step is a whole solve (one re-anchoring of its regulariser).
    compiled_inverse : {"pinv", "dls"} or None
        The inverse with which the compiled attempt (:mod:`armanim.motion.kernels.attempt`)
        takes this method's steps, where a pose solve may use it; None: the numpy steps only.
    inverts_the_jacobian : bool
        Its steps invert the tip's Jacobian (``pinv``, ``dls``): across the stretched, singular
        pose nearest a goal beyond reach they alternate between two poses, so the frame loop steps
        down the distance's gradient there instead (:func:`armanim.motion.trajectory._stretched`).
    """

    step_function: StepFunction
    full_step_solves: bool
    bounds_own_steps: bool
    attempt_steps: int | None
    compiled_inverse: Literal["pinv", "dls"] | None = None
    inverts_the_jacobian: bool = False


METHODS: dict[MethodName, Method] = {
    "pinv": Method(
        pinv_step,
        full_step_solves=True,
        bounds_own_steps=False,
        attempt_steps=25,
        compiled_inverse="pinv",
        inverts_the_jacobian=True,
    ),
    "dls": Method(
        dls_step,
        full_step_solves=True,
        bounds_own_steps=False,
        attempt_steps=25,
        compiled_inverse="dls",
        inverts_the_jacobian=True,
    ),
    "newton": Method(newton_step, full_step_solves=True, bounds_own_steps=True, attempt_steps=12),
    "gradient": Method(gradient_step, full_step_solves=False, bounds_own_steps=False, attempt_steps=None),
}
"""The registry: ``solver.method`` name -> :class:`Method`."""


def solver_method(name: MethodName) -> Method:
    """The registry entry of a ``solver.method`` name.

    >>> solver_method("dls").attempt_steps
    25
    """
    try:
        return METHODS[name]
    except KeyError:
        raise ValueError(f"unknown solver method {name!r} (expected one of {', '.join(METHODS)})") from None


def step_function(name: MethodName) -> StepFunction:
    """The step function registered for a ``solver.method`` name."""
    return solver_method(name).step_function


def proposed_step(
    problem: Problem, method: Method, state: ArmState, goal: np.ndarray, orientation: Orientation | None = None
) -> Step:
    """The method's proposal; a linear-algebra failure (a singular matrix, an SVD that does
    not converge) is a NaN proposal, which the filter refuses (``blocked_by == "nan"``) and
    the drivers report as ``numerical``."""
    try:
        if orientation is None:  # position-only goals call the methods exactly as before
            return method.step_function(problem, state, goal)
        return method.step_function(problem, state, goal, orientation)
    except np.linalg.LinAlgError:
        return Step(dphi=np.full(problem.arm.n, np.nan))


__all__ = [
    "METHODS",
    "ArmState",
    "Method",
    "Step",
    "StepFunction",
    "arm_state",
    "proposed_step",
    "solver_method",
    "step_function",
]
