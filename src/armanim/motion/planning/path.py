"""A joint-space path from the current pose to one of the goal poses.

First the straight segment to each of the nearest goal poses; otherwise OMPL's
RRT-Connect to any of them, then OMPL's path simplification. A motion is free when no
pose along it comes closer than half of ``solver.clearance`` to an obstacle, certified
from sampled clearances (:func:`motion_is_free`), and its ends are free poses
(:func:`armanim.motion.solvers.barrier.pose_is_free`). The frames that follow the path go
through the safety filter, which keeps the full clearance.

OMPL's random numbers come from one process-wide generator; it is re-seeded with
:data:`OMPL_SEED` before every plan, so a plan depends only on its problem, not on what
the process planned before (a batch worker gives the same trajectory as a fresh run).
"""

from __future__ import annotations

import gc
from dataclasses import dataclass

import numpy as np

from armanim.motion.problem import Problem
from armanim.motion.solvers.barrier import point_travel_bound, pose_clearance, pose_is_free, within_limits
from armanim.names import PathSource

COARSE = 8  # clearances between the first samples of a motion (see motion_is_free)
STRAIGHT_TRIES = 4  # nearest goal poses tried with a straight segment
OMPL_GOALS = 64  # goal poses handed to RRT-Connect
OMPL_ITERATIONS = 15000  # planner iterations per search: the budget, counted so that it is deterministic
OMPL_SEARCHES = 2  # searches with different random numbers before a goal has no path
RRT_RANGE = 1.2  # radians: RRT-Connect's longest edge (measured on six hard cases: 0.13 rad found 1, 0.6 found 3, 1.2 found 5)
OMPL_SEED = 20251123
UNLIMITED_SPAN = 2 * np.pi  # an unlimited joint plans within +-2 pi


@dataclass(frozen=True)
class JointPath:
    """Result of :func:`plan_path`.

    Attributes
    ----------
    waypoints : (k, n) array or None
        From the current pose to a goal pose; None when no path was found.
    source : PathSource
        ``"straight"``, ``"rrt_connect"`` or ``"none"``.
    checks : int
        Poses checked for collisions (a machine-independent measure of the planning effort).
    """

    waypoints: np.ndarray | None
    source: PathSource
    checks: int


def motion_samples(problem: Problem, a: np.ndarray, b: np.ndarray, spacing: float) -> np.ndarray:
    """(k, n) poses along the segment a-b (both ends included), no arm point moving more
    than ``spacing`` between neighbours."""
    count = int(np.ceil(point_travel_bound(problem, b - a) / spacing)) + 1
    t = np.linspace(0.0, 1.0, max(count, 2))[:, None]
    return a + t * (b - a)


def motion_is_free(problem: Problem, a: np.ndarray, b: np.ndarray) -> tuple[bool, int]:
    """Whether the segment a-b is free, and how many poses were checked.

    Poses are checked :data:`COARSE` clearances apart first. Clearance changes no faster than
    the arm's points move, so two neighbours with clearances c1, c2 whose points move at most
    S between them certify every pose between them when c1 + c2 >= S + d_safe (nothing there
    comes closer than d_safe / 2 to a surface). Only the others are sampled finely, no point
    moving more than d_safe between samples. The limits are a box: free ends keep them.
    """
    d_safe = problem.solver.clearance
    coarse = motion_samples(problem, a, b, COARSE * d_safe)
    clear = pose_clearance(problem, coarse)
    if not np.all(clear >= d_safe) or not within_limits(problem, coarse[[0, -1]]).all():
        return False, len(coarse)
    step = point_travel_bound(problem, coarse[1] - coarse[0])
    doubtful = np.nonzero(clear[:-1] + clear[1:] < step + d_safe)[0]
    if not len(doubtful):
        return True, len(coarse)
    fine = np.concatenate([motion_samples(problem, coarse[i], coarse[i + 1], d_safe)[1:-1] for i in doubtful])
    return bool(np.all(pose_clearance(problem, fine) >= d_safe)), len(coarse) + len(fine)


def plan_path(problem: Problem, start: np.ndarray, goals: np.ndarray) -> JointPath:
    """A free path from ``start`` to one of ``goals`` (nearest first), or none.

    Parameters
    ----------
    problem : Problem
    start : (n,) array
        The current pose, radians.
    goals : (k, n) array
        Free goal poses, nearest first.
    """
    checks = 0
    for goal in goals[:STRAIGHT_TRIES]:
        free, used = motion_is_free(problem, start, goal)
        checks += used
        if free:
            return JointPath(np.stack([start, goal]), "straight", checks)
    for search in range(OMPL_SEARCHES):
        waypoints, used = rrt_connect(problem, start, goals[:OMPL_GOALS], search)
        gc.collect()  # OMPL's Python callbacks form cycles with its objects: free them now, not at exit
        checks += used
        if waypoints is not None:
            return JointPath(waypoints, "rrt_connect", checks)
    return JointPath(None, "none", checks)


def rrt_connect(problem: Problem, start: np.ndarray, goals: np.ndarray, search: int = 0) -> tuple[np.ndarray | None, int]:
    """OMPL's RRT-Connect from ``start`` to any of ``goals``, simplified; (path or None, checks).

    ``search`` picks the random numbers: each value gives another, always the same, search.
    """
    from ompl import base as ob
    from ompl import geometric as og

    _seed_ompl(search)
    n = len(start)
    checks = [0]
    space, si, _validator = _space_information(ob, problem, start, checks)  # OMPL borrows the validator: keep it
    pdef = ob.ProblemDefinition(si)
    pdef.addStartState(_state(space, start))
    targets = ob.GoalStates(si)
    for goal in goals:
        targets.addState(_state(space, goal))
    pdef.setGoal(targets)
    planner = og.RRTConnect(si)
    planner.setRange(RRT_RANGE)
    planner.setProblemDefinition(pdef)
    planner.setup()
    iterations = [0]

    def out_of_budget() -> bool:
        iterations[0] += 1
        return iterations[0] > OMPL_ITERATIONS

    planner.solve(ob.PlannerTerminationCondition(out_of_budget))
    if not pdef.hasExactSolution():
        return None, checks[0]
    path = pdef.getSolutionPath()
    og.PathSimplifier(si).simplifyMax(path)
    waypoints = np.array([_array(path.getState(k), n) for k in range(path.getStateCount())])
    return waypoints, checks[0]


def _seed_ompl(search: int) -> None:
    """Make OMPL's next RNGs the same every time for this ``search`` number."""
    from ompl import util as ou

    ou.setLogLevel(ou.LOG_NONE)
    ou.RNG.setSeed(OMPL_SEED)  # re-seeds the generator of every RNG OMPL creates from here on
    for _ in range(search):
        ou.RNG()  # each RNG made takes the next seed: the planner's RNGs get later ones


def _space_information(ob, problem: Problem, start: np.ndarray, checks: list):
    """OMPL's joint space for the arm, with the free-pose test and the sampled motion check
    (both counting poses checked into ``checks[0]``); returns (space, si, validator)."""
    n = len(start)
    space = ob.RealVectorStateSpace(n)
    space.setBounds(_bounds(ob, problem, start))
    si = ob.SpaceInformation(space)

    def state_is_free(state) -> bool:
        checks[0] += 1
        return bool(pose_is_free(problem, _array(state, n))[0])

    class SampledMotions(ob.MotionValidator):
        def checkMotion(self, s1, s2, *_):
            free, used = motion_is_free(problem, _array(s1, n), _array(s2, n))
            checks[0] += used
            return free

    si.setStateValidityChecker(state_is_free)
    validator = SampledMotions(si)
    si.setMotionValidator(validator)
    si.setup()
    return space, si, validator


def _bounds(ob, problem: Problem, start: np.ndarray):
    lim = problem.limits
    bounds = ob.RealVectorBounds(len(start))
    for j in range(len(start)):
        if lim.limited[j]:
            bounds.setLow(j, float(lim.lower[j]))
            bounds.setHigh(j, float(lim.upper[j]))
        else:
            bounds.setLow(j, float(start[j] - UNLIMITED_SPAN))
            bounds.setHigh(j, float(start[j] + UNLIMITED_SPAN))
    return bounds


def _state(space, phi: np.ndarray):
    state = space.allocState()
    for j, value in enumerate(phi):
        state[j] = float(value)
    return state


def _array(state, n: int) -> np.ndarray:
    return np.array([state[j] for j in range(n)])
