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
distance and the angle are within their tolerances. A ``pinv`` or ``dls`` attempt on a problem
without obstacles runs compiled (:mod:`armanim.motion.kernels.attempt`: the same steps to
rounding, the arm's own pairs' push and filter rows included, the filter's QP solved exactly
where DAQP solves it to its tolerance; handed back to the numpy steps where rounding could tell
a step apart); ``tunables.ik.compiled`` off, the numpy steps everywhere. Pure core: no I/O.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any, NamedTuple, cast

import numpy as np

from armanim.motion.filter.barrier import safe_step
from armanim.motion.kernels.plan import compiled_plan
from armanim.motion.orientation import Orientation, pose_distance, tool_residual
from armanim.motion.planning.poses import goal_poses, seed_poses
from armanim.motion.problem import Problem
from armanim.motion.solvers import ArmState, Method, arm_state, proposed_step, solver_method
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


class _Attempt(NamedTuple):
    """Where one attempt ended and what it spent (a named tuple: a pose solve makes one per
    attempt, in a tenth of a frozen dataclass's time)."""

    phi: np.ndarray
    tip: np.ndarray
    errors: tuple[float, float | None, float]  # pose_errors at phi: |e - g|, the angle, the progress measure
    steps: int
    iterations: int
    newton_iterations: int
    numerical: bool

    @property
    def distance(self) -> float:
        """The progress measure: :func:`~armanim.motion.orientation.pose_distance` for a goal with an orientation."""
        return self.errors[2]


def solving_problem(problem: Problem) -> Problem:
    """The problem with the settings of solving rather than animating (see the module docstring),
    made once per problem (kept on it: a problem is frozen, and making one costs some 50 us)."""
    kept = problem.__dict__.get("_solving")
    if kept is None:
        kept = _solving_problem(problem)
        object.__setattr__(problem, "_solving", kept)  # a cache of a value of the problem: it stays what it was
    return cast(Problem, kept)


def _solving_problem(problem: Problem) -> Problem:
    """:func:`solving_problem`, made."""
    s = problem.solver
    method = solver_method(s.method)
    beta = 1.0 if method.full_step_solves else s.beta
    turn = 2 * np.pi if method.bounds_own_steps else max(s.max_joint_step, problem.tunables.ik.full_turn_per_iteration)
    tunables = replace(problem.tunables, ik=replace(problem.tunables.ik, solving=True))
    return replace(problem, solver=replace(s, beta=beta, max_step=np.inf, max_joint_step=turn), tunables=tunables)


def pose_errors(
    problem: Problem, state: ArmState, goal: np.ndarray, orientation: Orientation | None
) -> tuple[float, float | None, float]:
    """|e - g|, the tool's angle to ``orientation`` (None without one), and the two as one
    progress measure (:func:`armanim.motion.orientation.pose_distance`)."""
    distance = float(np.linalg.norm(state.tip - goal))
    if orientation is None:
        return distance, None, distance
    angle = float(
        np.linalg.norm(tool_residual(orientation, problem.arm, state.pose), axis=-1)
    )  # orientation_angle, kept for the next step's task
    s = problem.solver
    return distance, angle, float(pose_distance(distance, angle, s.tolerance, s.orientation_tolerance))


def solve_pose(
    problem: Problem,
    goal: np.ndarray,
    start: np.ndarray,
    max_iterations: int = 1000,
    orientation: Orientation | None = None,
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

    Raises
    ------
    ValueError
        ``goal`` is not 3 numbers, or ``start`` not one angle a joint.
    """
    goal = np.asarray(goal, dtype=float)
    start = np.asarray(start, dtype=float)
    if goal.shape != (3,):  # (campaign 16: numpy's "operands could not be broadcast" from deep inside)
        raise ValueError(f"goal: expected a point, 3 numbers (x, y, z); got shape {goal.shape}")
    if start.shape != problem.home.shape:
        raise ValueError(f"start: expected the angles of the arm's {len(problem.home)} joints; got shape {start.shape}")
    solving = solving_problem(problem)
    method = solver_method(problem.solver.method)
    tolerance = problem.solver.tolerance
    best = _attempt(solving, method, goal, start, max_iterations, orientation)
    attempts = [best]
    steps = best.steps  # over the attempts so far
    if not (best.distance < tolerance or steps >= max_iterations):
        for first in _restarts(problem, start):
            attempts.append(_attempt(solving, method, goal, first, max_iterations - steps, orientation))
            steps += attempts[-1].steps
            if attempts[-1].distance < tolerance or steps >= max_iterations:
                break
        best = min(attempts, key=lambda a: a.distance)  # the first of equals
    status: PoseStatus
    if best.distance < tolerance:
        status = "converged"
    else:
        status = "numerical" if any(a.numerical for a in attempts) else "not_converged"
    if len(attempts) == 1:  # most solves: one attempt (a generator's sum costs a microsecond)
        newton_iterations, iterations = best.newton_iterations, best.iterations
    else:
        newton_iterations, iterations = sum(a.newton_iterations for a in attempts), sum(a.iterations for a in attempts)
    searched = free_pose(problem, goal, best.phi, orientation) if status == "not_converged" else None
    if searched is not None:
        best = _Attempt(searched.phi, searched.tip, pose_errors(problem, searched, goal, orientation), 0, 0, 0, False)
        status = "converged"
    distance, angle, _ = best.errors
    return _pose_solution(
        phi=best.phi,
        tip=best.tip,
        distance=distance,
        status=status,
        steps=steps,
        iterations=iterations - newton_iterations,
        newton_iterations=newton_iterations,
        restarts=len(attempts) - 1,
        found_by="method" if searched is None else "free_pose_search",
        orientation_error=angle,
    )


def _pose_solution(**fields: object) -> PoseSolution:
    """A :class:`PoseSolution` of every field, its instance dict filled at once (the frozen
    dataclass's ``__init__`` sets each field by ``object.__setattr__``: some 4 us of a 90 us solve);
    the same object, still frozen to assignment."""
    made = object.__new__(PoseSolution)
    made.__dict__.update(fields)
    return made


def free_pose(
    problem: Problem, goal: np.ndarray, near: np.ndarray, orientation: Orientation | None = None
) -> ArmState | None:
    """The planner's free pose at ``goal`` nearest to ``near`` (inside the limits, every link
    ``solver.clearance`` from every obstacle, the tip within the tolerance, the tool at
    ``orientation`` if given); None if none is found."""
    found = goal_poses(problem, near, goal, orientation=orientation)
    return arm_state(problem, found.poses[0]) if len(found.poses) else None


def _restarts(problem: Problem, start: np.ndarray) -> np.ndarray:
    """The restarts' starts, after ``start`` itself: the rest of the planner's
    (:func:`armanim.motion.planning.poses.seed_poses`, whose first is ``start``), drawn only
    when the first attempt did not converge."""
    opts = problem.tunables.ik
    return seed_poses(problem, start, 1 + opts.restarts, opts.seed)[1:]


def _attempt(
    problem: Problem,
    method: Method,
    goal: np.ndarray,
    start: np.ndarray,
    budget: int,
    orientation: Orientation | None = None,
) -> _Attempt:
    """Filtered steps from ``start`` until the tip is within tolerance (and the tool within the
    orientation tolerance), the attempt stalls, its steps (``budget`` or the method's
    ``attempt_steps``) run out, or a step is refused outright.

    A ``pinv`` or ``dls`` attempt on a problem without obstacles runs compiled
    (:mod:`armanim.motion.kernels.attempt`), the same steps to rounding, unless the goal has an
    orientation that the arm cannot hold (the arm's own pairs' push and filter rows inside it;
    the filter's QP solved exactly). Where rounding could tell a step apart (a pair's gap at 0, a
    step's exact check at its floor), the compiled loop hands the attempt back: the numpy step
    takes that step, and the compiled loop goes on from there with the attempt's counters."""
    steps_cap = min(budget, method.attempt_steps or budget)
    plan = compiled_plan(problem, method, orientation, "attempt")
    if plan is None:
        return _steps(problem, method, goal, arm_state(problem, start), steps_cap, orientation)[0]
    run_attempt = _compiled_attempt()
    step, stacked = plan
    phi = start
    counters: tuple[int, float | None, int] = (0, None, 0)  # steps, best progress (None: not yet), steps since
    state: ArmState | None = None  # the numpy steps' last state, when they took the last step
    while True:
        ran = run_attempt(problem, step, stacked, goal, phi, steps_cap, orientation, counters)
        if not ran.handed_back:
            return _Attempt(
                ran.phi, ran.tip, (ran.distance, ran.angle, ran.progress), ran.steps, ran.steps, 0, ran.numerical
            )
        if (
            state is None or ran.steps != counters[0]
        ):  # the compiled loop took steps: its very pose (angles wrapped after)
            computed = arm_state(problem, ran.pose_phi)
            state = ArmState(ran.phi, computed.pose, computed.clearance, computed.self_gaps)
        attempt, best, since_best, stopped, state = _steps(
            problem, method, goal, state, ran.steps + 1, orientation, ran.steps, ran.steps, ran.best, ran.since_best
        )
        if stopped or attempt.steps >= steps_cap:
            return attempt
        phi, counters = attempt.phi, (attempt.steps, best, since_best)


_RUN_ATTEMPT: list[
    Callable[..., Any]
] = []  # the compiled attempt once imported (numba loads with it: not at this module's import)


def _compiled_attempt() -> Callable[..., Any]:
    """:func:`armanim.motion.kernels.attempt.run_attempt`, imported on the first compiled attempt
    and kept (an import statement per attempt costs some 1 us of a 40 us solve)."""
    if not _RUN_ATTEMPT:
        from armanim.motion.kernels.attempt import run_attempt

        _RUN_ATTEMPT.append(run_attempt)
    return _RUN_ATTEMPT[0]


def _steps(
    problem: Problem,
    method: Method,
    goal: np.ndarray,
    state: ArmState,
    steps_cap: int,
    orientation: Orientation | None = None,
    steps: int = 0,
    iterations: int = 0,
    best: float | None = None,
    since_best: int = 0,
) -> tuple[_Attempt, float, int, bool, ArmState]:
    """The numpy steps of an attempt from ``state`` up to ``steps_cap`` steps in all: a whole
    attempt, or a step of one that the compiled loop handed back with its counters (``steps``,
    ``iterations``, the ``best`` progress and the steps ``since_best``). Returns where it ended,
    the best progress and the steps since, whether the attempt stopped (within tolerance,
    stalled, or nothing moved) rather than ran out of steps, and its last state."""
    errors = pose_errors(problem, state, goal, orientation)
    distance = errors[2]
    best = distance if best is None else best
    newton_iterations = 0
    while distance >= problem.solver.tolerance and steps < steps_cap:
        proposal = proposed_step(problem, method, state, goal, orientation)
        moved = safe_step(problem, state, proposal.dphi, proposal.ahead)
        steps, iterations = steps + 1, iterations + proposal.iterations
        newton_iterations += proposal.newton_iterations
        if moved.scale == 0.0:  # nothing moved: the same pose would propose the same again
            numerical = moved.blocked_by == "nan"
            return (
                _Attempt(state.phi, state.tip, errors, steps, iterations, newton_iterations, numerical),
                best,
                since_best,
                True,
                state,
            )
        state = moved.state
        errors = pose_errors(problem, state, goal, orientation)
        distance = errors[2]
        if distance < best - 0.1 * problem.solver.tolerance:
            best, since_best = distance, 0
        elif (since_best := since_best + 1) >= problem.tunables.ik.stall_iterations:
            return (
                _Attempt(state.phi, state.tip, errors, steps, iterations, newton_iterations, False),
                best,
                since_best,
                True,
                state,
            )
    stopped = not distance >= problem.solver.tolerance
    return (
        _Attempt(state.phi, state.tip, errors, steps, iterations, newton_iterations, False),
        best,
        since_best,
        stopped,
        state,
    )
