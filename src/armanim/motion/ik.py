"""One pose solved to convergence (``armanim ik``), with the methods of the frame loop.

One attempt loop serves every method: what it must know of a method is data on the
method's registry entry (:class:`armanim.motion.solvers.Method`). Solving is not animating, so
the steps are full ones: a method that solves with a full step takes beta = 1 (``pinv``
and ``dls``: Newton-Raphson on the tip; ``newton``: the assignment's GDLS + NM solved to
the goal, its regulariser re-anchored at each answer until the tip is within tolerance),
and joints may turn up to 30 degrees per iteration, or without a cap where the method's
own line searches bound its steps. Every step passes the same barrier as in the frame
loop, so limits and obstacles hold. An attempt that stalls, e.g. pinned between two
limits, restarts from the mirrored elbow and then from seeded random poses: the planner's
starts (:func:`armanim.motion.planning.poses.seed_poses`). A step that
fails in linear algebra ends its attempt, and an unconverged solve that met one says
``numerical``. When no attempt converges (and none failed so), the planner's free-pose search (many damped
least-squares solves at once, :func:`armanim.motion.planning.poses.goal_poses`) looks for a
free pose at the goal, nearest to the start, as a run does when its method stalls; the
result says which one found the pose. A goal with an orientation is solved as a pose
(every method's pose task, :mod:`armanim.motion.orientation`) and converges when both the
distance and the angle are within their tolerances. Pure core: no I/O.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from armanim.motion.orientation import Orientation, pose_distance, tool_residual
from armanim.motion.planning.poses import goal_poses, seed_poses
from armanim.motion.problem import Problem
from armanim.motion.solvers import ArmState, Method, arm_state, proposed_step, solver_method
from armanim.motion.solvers.barrier import safe_step
from armanim.names import PoseFinder, PoseStatus


@dataclass(frozen=True)
class PoseSolution:
    """Result of :func:`solve_pose`.

    Attributes
    ----------
    phi : (n,) array, radians
    tip : (3,) array
    distance : float
        |e - g| at the end.
    status : PoseStatus
        ``"converged"`` (distance < tolerance), ``"not_converged"``, or ``"numerical"``
        when a step failed in linear algebra and no attempt converged.
    steps : int
        Steps (proposals through the filter) over all attempts: what ``max_iterations`` bounds.
    iterations : int
        Inner iterations over all attempts, Newton's aside (as :class:`armanim.motion.solvers.Step`
        counts them: one per step of ``pinv`` and ``dls``, line-search trials for
        ``gradient``, gradient-descent iterations for ``newton``).
    newton_iterations : int
        Newton iterations (newton only).
    restarts : int
        Attempts after the first.
    found_by : PoseFinder
        ``"method"``, or ``"free_pose_search"`` when the method's attempts did not converge
        and the planner's free-pose search found the pose.
    orientation_error : float or None
        Radians from the tool frame to the goal's orientation at the end; None without one.
    """

    phi: np.ndarray
    tip: np.ndarray
    distance: float
    status: PoseStatus
    steps: int
    iterations: int
    newton_iterations: int = 0
    restarts: int = 0
    found_by: PoseFinder = "method"
    orientation_error: float | None = None

    @property
    def converged(self) -> bool:
        """Whether the tip ended within the tolerance."""
        return self.status == "converged"


@dataclass(frozen=True)
class _Attempt:
    """Where one attempt ended and what it spent."""

    state: ArmState
    distance: float  # the progress measure: pose_distance for a goal with an orientation
    steps: int
    iterations: int
    newton_iterations: int
    numerical: bool


def solving_problem(problem: Problem) -> Problem:
    """The problem with the settings of solving rather than animating (see the module docstring)."""
    s = problem.solver
    method = solver_method(s.method)
    beta = 1.0 if method.full_step_solves else s.beta
    turn = 2 * np.pi if method.bounds_own_steps else max(s.max_joint_step, problem.tunables.ik.full_turn_per_iteration)
    tunables = replace(problem.tunables, ik=replace(problem.tunables.ik, solving=True))
    return replace(problem, solver=replace(s, beta=beta, max_step=np.inf, max_joint_step=turn), tunables=tunables)


def pose_errors(problem: Problem, state: ArmState, goal: np.ndarray, orientation: Orientation | None) -> tuple[float, float | None, float]:
    """|e - g|, the tool's angle to ``orientation`` (None without one), and the two as one
    progress measure (:func:`armanim.motion.orientation.pose_distance`)."""
    distance = float(np.linalg.norm(state.tip - goal))
    if orientation is None:
        return distance, None, distance
    angle = float(np.linalg.norm(tool_residual(orientation, problem.arm, state.pose), axis=-1))  # orientation_angle, kept for the next step's task
    s = problem.solver
    return distance, angle, float(pose_distance(distance, angle, s.tolerance, s.orientation_tolerance))


def solve_pose(
    problem: Problem, goal: np.ndarray, start: np.ndarray, max_iterations: int = 1000, orientation: Orientation | None = None
) -> PoseSolution:
    """Solve for one pose whose tip is at ``goal`` (and whose tool meets ``orientation``, if
    given), starting from ``start`` (radians).

    Parameters
    ----------
    problem : Problem
        Its arm, limits, obstacles and solver settings (``method``, ``tolerance``).
    goal : (3,) array
    start : (n,) array
        First pose tried; the restarts are the planner's next starts from it
        (:func:`armanim.motion.planning.poses.seed_poses`).
    max_iterations : int
        Bound on the steps over all attempts.
    orientation : Orientation, optional
        The tool frame's target rotation, or its z axis's target direction.

    Returns
    -------
    PoseSolution
        The pose of the attempt that came closest, and how the solve ended.
    """
    goal = np.asarray(goal, dtype=float)
    solving = solving_problem(problem)
    method = solver_method(problem.solver.method)
    tolerance = problem.solver.tolerance
    attempts: list[_Attempt] = []
    opts = problem.tunables.ik
    for first in seed_poses(problem, np.asarray(start, dtype=float), 1 + opts.restarts, opts.seed):
        attempts.append(_attempt(solving, method, goal, first, max_iterations - sum(a.steps for a in attempts), orientation))
        if attempts[-1].distance < tolerance or sum(a.steps for a in attempts) >= max_iterations:
            break
    best = min(attempts, key=lambda a: a.distance)  # the first of equals
    status: PoseStatus
    if best.distance < tolerance:
        status = "converged"
    else:
        status = "numerical" if any(a.numerical for a in attempts) else "not_converged"
    newton_iterations = sum(a.newton_iterations for a in attempts)
    searched = free_pose(problem, goal, best.state.phi, orientation) if status == "not_converged" else None
    if searched is not None:
        best, status = _Attempt(searched, pose_errors(problem, searched, goal, orientation)[2], 0, 0, 0, False), "converged"
    distance, angle, _ = pose_errors(problem, best.state, goal, orientation)
    return PoseSolution(
        phi=best.state.phi,
        tip=best.state.tip,
        distance=distance,
        status=status,
        steps=sum(a.steps for a in attempts),
        iterations=sum(a.iterations for a in attempts) - newton_iterations,
        newton_iterations=newton_iterations,
        restarts=len(attempts) - 1,
        found_by="method" if searched is None else "free_pose_search",
        orientation_error=angle,
    )


def free_pose(problem: Problem, goal: np.ndarray, near: np.ndarray, orientation: Orientation | None = None) -> ArmState | None:
    """The planner's free pose at ``goal`` nearest to ``near`` (inside the limits, every link
    ``solver.clearance`` from every obstacle, the tip within the tolerance, the tool at
    ``orientation`` if given); None if none is found."""
    found = goal_poses(problem, near, goal, orientation=orientation)
    return arm_state(problem, found.poses[0]) if len(found.poses) else None


def _attempt(
    problem: Problem, method: Method, goal: np.ndarray, start: np.ndarray, budget: int, orientation: Orientation | None = None
) -> _Attempt:
    """Filtered steps from ``start`` until the tip is within tolerance (and the tool within the
    orientation tolerance), the attempt stalls, its steps (``budget`` or the method's
    ``attempt_steps``) run out, or a step is refused outright."""
    state = arm_state(problem, start)
    distance = pose_errors(problem, state, goal, orientation)[2]
    best, since_best, steps, iterations, newton_iterations = distance, 0, 0, 0, 0
    steps_cap = min(budget, method.attempt_steps or budget)
    while distance >= problem.solver.tolerance and steps < steps_cap:
        proposal = proposed_step(problem, method, state, goal, orientation)
        moved = safe_step(problem, state, proposal.dphi, proposal.ahead)
        steps, iterations = steps + 1, iterations + proposal.iterations
        newton_iterations += proposal.newton_iterations
        if moved.scale == 0.0:  # nothing moved: the same pose would propose the same again
            return _Attempt(state, distance, steps, iterations, newton_iterations, moved.blocked_by == "nan")
        state = moved.state
        distance = pose_errors(problem, state, goal, orientation)[2]
        if distance < best - 0.1 * problem.solver.tolerance:
            best, since_best = distance, 0
        elif (since_best := since_best + 1) >= problem.tunables.ik.stall_iterations:
            break
    return _Attempt(state, distance, steps, iterations, newton_iterations, False)
