"""``gradient``: Breen's cost minimisation, plain gradient descent on the whole cost C.

dPhi = -beta grad C(Phi), with grad C analytic or by forward differences
(``jacobian: numeric``), the tip's travel capped at ``max_step``, and the step halved
until C decreases (C is +inf past a barrier, so a barrier is never crossed).
"""

from __future__ import annotations

from typing import cast

import numpy as np

from armanim.arm.kinematics import numeric_jacobian, tip_jacobian
from armanim.motion.cost import total_cost, total_cost_gradient
from armanim.motion.orientation import Orientation
from armanim.motion.problem import Problem
from armanim.motion.solvers.common import ArmState, Step, arm_state

HALVINGS = 30  # line-search trials: 2**-30 of a step is below any useful resolution


def cost_gradient(
    problem: Problem, state: ArmState, goal: np.ndarray, orientation: Orientation | None = None
) -> np.ndarray:
    """grad C at the state's pose: analytic, or the forward-difference gradient when numeric."""
    if problem.solver.jacobian == "numeric":
        return cast(
            np.ndarray,
            numeric_jacobian(lambda p: total_cost(problem, p, goal, orientation=orientation)[..., None], state.phi)[0],
        )
    return total_cost_gradient(problem, state.phi, goal, state.pose, state.clearance, orientation)


def gradient_step(problem: Problem, state: ArmState, goal: np.ndarray, orientation: Orientation | None = None) -> Step:
    """One frame of gradient descent on C (with the goal's orientation term) with a backtracking line search."""
    s = problem.solver
    phi = state.phi
    dphi = -s.beta * cost_gradient(problem, state, goal, orientation)
    travel = np.linalg.norm(tip_jacobian(problem.arm, state.pose) @ dphi)
    if travel > s.max_step:
        dphi = dphi * (s.max_step / travel)
    now = total_cost(problem, phi, goal, state.pose, state.clearance, orientation)
    whole = arm_state(problem, phi + dphi)  # the filter checks this very pose next: it is handed on
    if (
        total_cost(problem, whole.phi, goal, whole.pose, whole.clearance, orientation) < now
    ):  # the whole step is usually taken
        return Step(dphi=dphi, iterations=1, ahead=whole)
    scales = 0.5 ** np.arange(1, HALVINGS)
    better = np.nonzero(total_cost(problem, phi + scales[:, None] * dphi, goal, orientation=orientation) < now)[0]
    if len(better) == 0:
        return Step(dphi=np.zeros_like(phi), iterations=HALVINGS)
    first = int(better[0])
    return Step(dphi=scales[first] * dphi, iterations=first + 2)
