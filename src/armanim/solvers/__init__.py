"""The four solver methods behind one registry, and the barrier every step goes through.

A method owns only its step: given the problem, the current angles and the goal, it
proposes a joint update. The frame loop (:mod:`armanim.trajectory`) owns termination,
holds and reached/missed, and passes every proposal through
:func:`armanim.solvers.barrier.safe_step` (the safety filter).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from armanim.problem import Problem
from armanim.solvers.common import ArmState, Step, arm_state
from armanim.solvers.gradient import gradient_step
from armanim.solvers.linear import dls_step, pinv_step
from armanim.solvers.newton import newton_step

StepFunction = Callable[[Problem, ArmState, np.ndarray], Step]
"""step(problem, state, goal) -> Step: a method's proposal for one frame."""

METHODS: dict[str, StepFunction] = {
    "pinv": pinv_step,
    "dls": dls_step,
    "newton": newton_step,
    "gradient": gradient_step,
}


def step_function(method: str) -> StepFunction:
    """The step function registered for a ``solver.method`` name."""
    try:
        return METHODS[method]
    except KeyError:
        raise ValueError(f"unknown solver method {method!r} (expected one of {', '.join(METHODS)})") from None


__all__ = ["METHODS", "ArmState", "Step", "StepFunction", "arm_state", "step_function"]
