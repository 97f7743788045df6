"""One pose solved to convergence (``armanim ik``): the methods' steps repeated until
the tip is within tolerance, through the same barrier as the frame loop.

``newton`` solves the goal itself at once, as the n-link assignment does, and reports
its gradient-descent and Newton iteration counts. Pure core: no I/O.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from armanim.kinematics import forward
from armanim.problem import Problem
from armanim.solvers import step_function
from armanim.solvers.barrier import shorten_step, wrap_unlimited
from armanim.solvers.newton import newton_solve


@dataclass(frozen=True)
class PoseSolution:
    """Result of :func:`solve_pose`.

    Attributes
    ----------
    phi : (n,) array, radians
    tip : (3,) array
    distance : float
        |e - g| at the end.
    converged : bool
        distance < tolerance.
    iterations : int
        Steps taken (for newton: gradient-descent iterations).
    newton_iterations : int
        Newton iterations (newton only).
    """

    phi: np.ndarray
    tip: np.ndarray
    distance: float
    converged: bool
    iterations: int
    newton_iterations: int = 0


def solve_pose(problem: Problem, goal: np.ndarray, start: np.ndarray, max_iterations: int = 1000) -> PoseSolution:
    """Solve for one pose whose tip is at ``goal``, starting from ``start`` (radians)."""
    arm, s = problem.arm, problem.solver
    goal = np.asarray(goal, dtype=float)
    if s.method == "newton":
        result = newton_solve(arm, start, goal, start, s.w_target, s.w_regularizer)
        phi = wrap_unlimited(problem, result.phi)
        tip = forward(arm, phi).tip
        distance = float(np.linalg.norm(tip - goal))
        return PoseSolution(phi, tip, distance, distance < s.tolerance, result.gd_iterations, result.nm_iterations)
    step = step_function(s.method)
    phi = np.asarray(start, dtype=float)
    tip = forward(arm, phi).tip
    iterations = 0
    while np.linalg.norm(tip - goal) >= s.tolerance and iterations < max_iterations:
        phi = shorten_step(problem, phi, step(problem, phi, goal).dphi).phi
        tip = forward(arm, phi).tip
        iterations += 1
    distance = float(np.linalg.norm(tip - goal))
    return PoseSolution(phi, tip, distance, distance < s.tolerance, iterations)
