"""One pose solved to convergence (``armanim ik``), with the methods of the frame loop.

Solving is not animating, so the steps are full ones: ``pinv`` and ``dls`` take
beta = 1 (Newton-Raphson on the tip) and joints may turn up to 30 degrees per
iteration, through the same barrier as the frame loop. ``newton`` runs the
assignment's GDLS + NM, re-anchoring its regulariser at each answer until the tip is
within tolerance (the regulariser alone would hold it a little short of the goal);
each answer also passes the barrier, so limits hold.
A solve that stalls, e.g. pinned between two limits, restarts from the mirrored
elbow and then from seeded random poses. Pure core: no I/O.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, replace

import numpy as np

from armanim.problem import Problem
from armanim.solvers import ArmState, arm_state, step_function
from armanim.solvers.barrier import safe_step
from armanim.solvers.newton import newton_solve

FULL_TURN_PER_ITERATION = np.radians(30.0)
STALL_ITERATIONS = 15  # iterations without progress before a restart
ATTEMPT_ITERATIONS = 25  # full steps converge in a handful; a slow crawl is better restarted
NEWTON_ROUNDS = 12  # re-anchorings of newton's regulariser per attempt
RESTARTS = 4


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
        Steps taken over all attempts (for newton: gradient-descent iterations).
    newton_iterations : int
        Newton iterations (newton only).
    restarts : int
        Attempts after the first.
    """

    phi: np.ndarray
    tip: np.ndarray
    distance: float
    converged: bool
    iterations: int
    newton_iterations: int = 0
    restarts: int = 0


def solving_settings(problem: Problem) -> Problem:
    """The problem with full steps for solving (see the module docstring)."""
    s = problem.solver
    step = 1.0 if s.method in ("pinv", "dls") else s.step
    return replace(problem, solver=replace(s, step=step, max_step=np.inf, max_joint_step=max(s.max_joint_step, FULL_TURN_PER_ITERATION)))


def restart_poses(problem: Problem, start: np.ndarray, count: int) -> Iterator[np.ndarray]:
    """Starts to try in turn: ``start``, its mirrored elbow, then seeded random poses
    inside the limits (made only when asked for: most solves need just the first)."""
    yield start
    lim = problem.limits
    mirrored = start.copy()
    mirrored[1:] = -mirrored[1:]
    yield np.clip(mirrored, lim.lower + lim.margin, lim.upper - lim.margin)
    rng = np.random.default_rng(0)
    lo = np.where(lim.limited, lim.lower + lim.margin, -np.pi)
    hi = np.where(lim.limited, lim.upper - lim.margin, np.pi)
    for _ in range(count - 2):
        yield rng.uniform(lo, hi)


def solve_pose(problem: Problem, goal: np.ndarray, start: np.ndarray, max_iterations: int = 1000) -> PoseSolution:
    """Solve for one pose whose tip is at ``goal``, starting from ``start`` (radians).

    ``max_iterations`` bounds the steps over all attempts.
    """
    goal = np.asarray(goal, dtype=float)
    start = np.asarray(start, dtype=float)
    attempt = _newton_attempt if problem.solver.method == "newton" else _step_attempt
    best = None
    used = newton_used = 0
    starts = restart_poses(problem, start, 1 + RESTARTS)
    for restarts, first in enumerate(starts):  # noqa: B007 (the count is reported after the loop)
        state, its, nm_its = attempt(problem, goal, first, max_iterations - used)
        used += its
        newton_used += nm_its
        distance = float(np.linalg.norm(state.tip - goal))
        if best is None or distance < best[2]:
            best = (state.phi, state.tip, distance)
        if distance < problem.solver.tolerance or used >= max_iterations:
            break
    phi, tip, distance = best
    return PoseSolution(phi, tip, distance, distance < problem.solver.tolerance, used, newton_used, restarts)


def _step_attempt(problem: Problem, goal: np.ndarray, start: np.ndarray, budget: int) -> tuple[ArmState, int, int]:
    fast = solving_settings(problem)
    step = step_function(fast.solver.method)
    state = arm_state(fast, start)
    best, since_best, iterations = np.inf, 0, 0
    limit = min(budget, ATTEMPT_ITERATIONS) if fast.solver.method in ("pinv", "dls") else budget
    while iterations < limit:
        distance = float(np.linalg.norm(state.tip - goal))
        if distance < fast.solver.tolerance:
            break
        if distance < best - 0.1 * fast.solver.tolerance:
            best, since_best = distance, 0
        elif (since_best := since_best + 1) >= STALL_ITERATIONS:
            break
        state = safe_step(fast, state, step(fast, state, goal).dphi).state
        iterations += 1
    return state, iterations, 0


def _newton_attempt(problem: Problem, goal: np.ndarray, start: np.ndarray, budget: int) -> tuple[ArmState, int, int]:
    # newton's own line searches bound its steps: the barrier only guards limits and obstacles
    fast = replace(problem, solver=replace(problem.solver, max_joint_step=2 * np.pi))
    s = fast.solver
    state = arm_state(fast, start)
    gd = nm = 0
    for _ in range(NEWTON_ROUNDS):
        if gd + nm >= budget:
            break
        result = newton_solve(fast.arm, state.phi, goal, state.phi, s.w_target, s.w_regularizer)
        gd += result.gd_iterations
        nm += result.nm_iterations
        moved = safe_step(fast, state, result.phi - state.phi)  # limits and obstacles, as in the frame loop
        if moved.scale == 0.0:
            break
        state = moved.state
        if np.linalg.norm(state.tip - goal) < s.tolerance:
            break
    return state, gd, nm
