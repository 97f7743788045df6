"""A joint-space path from the current pose to one of the goal poses.

First the straight segment to each of the nearest goal poses; otherwise OMPL's
RRT-Connect to any of them, then OMPL's path simplification. A path keeps room above what
the safety filter keeps (:func:`plan_path`): every pose on it, certified from sampled
clearances (:func:`motion_is_free`), so that the frames that follow it through the filter
are not held back.

Its tunables (the budget, the certification's steps, OMPL's seed) are ``problem.tunables.planner``
(:class:`~armanim.motion.tunables.PlannerOptions`). OMPL's random numbers come from one
process-wide generator; it is re-seeded with the options' ``ompl_seed`` before every plan, so a plan depends only on its problem, not on what
the process planned before (a batch worker gives the same trajectory as a fresh run).
"""

from __future__ import annotations

import atexit
import gc
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, cast

import numpy as np

from armanim.motion.filter.barrier import obstacle_rows, point_travel_bound, self_pair_rows
from armanim.motion.filter.clearance import (
    kept_clearance,
    planning_floor,
    pose_clearance,
    settle_clearance,
    split_clearances,
    within_limits,
)
from armanim.motion.problem import Problem
from armanim.motion.solvers.common import arm_state
from armanim.motion.tunables import DEFAULTS, PlannerOptions
from armanim.names import PathSource

if TYPE_CHECKING:
    from armanim.motion.planning.check import CompiledCheck

UNLIMITED_SPAN = 2 * np.pi  # an unlimited joint plans within +-2 pi


Searched = Callable[[int, int], None]
"""``searched(done, most)``: a plan's RRT-Connect iterations so far and the most it may take
(:func:`plan_iterations`), called as its searches go on and with ``done == most`` when the plan
ends, so that a caller can show the minute a goal with no path may take."""


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


def motion_samples(problem: Problem, a: np.ndarray, b: np.ndarray, spacing: float) -> np.ndarray | None:
    """(k, n) poses along the segment a-b (both ends included), no arm point moving more
    than ``spacing`` between neighbours; None when that takes more than the planner's ``max_samples``
    (a clearance far below the arm's size: the motion cannot be certified, and is not taken)."""
    with np.errstate(over="ignore", divide="ignore"):
        count = point_travel_bound(problem, b - a) / spacing
    if not count <= problem.tunables.planner.max_samples:
        return None
    t = np.linspace(0.0, 1.0, max(int(np.ceil(count)) + 1, 2))[:, None]
    return cast("np.ndarray | None", a + t * (b - a))


def coarse_spacing(problem: Problem) -> float:
    """The most any arm point travels between the first samples of a motion check: ``coarse``
    clearances, or ``coarse_reach`` of the arm's reach where that is more (the planner's options)."""
    opts = problem.tunables.planner
    return max(opts.coarse * problem.solver.clearance, opts.coarse_reach * problem.arm.reach)


def motion_is_free(
    problem: Problem, a: np.ndarray, b: np.ndarray, floor: float, closed: bool = False
) -> tuple[bool, int]:
    """Whether no pose on the segment a-b comes closer than ``floor`` to an obstacle (to within
    ``certify_to * solver.clearance / 2``, the planner's options), and how many poses were checked.

    Clearance changes no faster than the arm's points move, so two poses with clearances
    c1, c2 whose points move at most S between them certify every pose between them when
    c1 + c2 >= S + 2 floor. Poses :func:`coarse_spacing` apart are checked first; a pair
    they do not certify is halved, level by level, until every piece is certified or shorter
    than ``certify_to`` clearances, or a pose below ``floor`` is found. The limits are a
    box: free ends keep them (by the filter's buffer, or ``closed``: the ends of the limits included).

    The enabled pairs of the arm's own capsules are judged alike, each by its own travel: a
    pair's gap (shifted by ``clearance - self_clearance``) depends only on the joints between its
    two capsules, and in the first one's frame the second's points move no faster than the sum
    of |dphi_j| times joint j's lever arm over those joints (:attr:`Problem.pair_lever_rows`), so a
    wrist pair is not held to the whole arm's travel.
    """
    coarse = motion_samples(problem, a, b, coarse_spacing(problem))
    if coarse is None:
        return False, 0
    clear, own = split_clearances(problem, coarse)
    checks = len(coarse)
    if not np.all(_least(clear, own) >= floor) or not within_limits(problem, coarse[[0, -1]], closed).all():
        return False, checks
    return _certified(problem, coarse, clear, own, floor, checks)


def _certified(
    problem: Problem, coarse: np.ndarray, clear: np.ndarray, own: np.ndarray | None, floor: float, checks: int
) -> tuple[bool, int]:
    """:func:`motion_is_free`'s halving: the pieces between the ``coarse`` poses (k, n), with
    their clearances ``clear`` (k,) and shifted pair gaps ``own`` (k, P) or None, halved level by
    level until each is certified; (free, checks) with the poses checked added to ``checks``."""
    d_safe, opts = problem.solver.clearance, problem.tunables.planner
    levers = problem.lever_arms
    pair_levers = problem.pair_lever_rows.T if own is not None else None  # (n, P)
    lo, hi, c_lo, c_hi = coarse[:-1], coarse[1:], clear[:-1], clear[1:]
    o_lo, o_hi = (own[:-1], own[1:]) if own is not None else (None, None)
    for _ in range(opts.max_halvings):
        if not len(lo):
            return True, checks
        step = np.abs(hi - lo)
        travel = step @ levers
        doubtful = c_lo + c_hi < travel + 2 * floor
        if own is not None:  # each pair by the joints between its capsules alone
            assert o_lo is not None and o_hi is not None and pair_levers is not None  # set with own
            doubtful |= np.any(o_lo + o_hi < step @ pair_levers + 2 * floor, axis=1)
        doubtful &= travel > opts.certify_to * d_safe
        lo, hi, c_lo, c_hi = lo[doubtful], hi[doubtful], c_lo[doubtful], c_hi[doubtful]
        if own is not None:
            assert o_lo is not None and o_hi is not None  # set with own
            o_lo, o_hi = o_lo[doubtful], o_hi[doubtful]
        if not len(lo):
            break
        mid = 0.5 * (lo + hi)
        c_mid, o_mid = split_clearances(problem, mid)
        checks += len(mid)
        if not np.all(_least(c_mid, o_mid) >= floor):
            return False, checks
        lo, hi = np.concatenate([lo, mid]), np.concatenate([mid, hi])
        c_lo, c_hi = np.concatenate([c_lo, c_mid]), np.concatenate([c_mid, c_hi])
        if own is not None:
            o_lo, o_hi = np.concatenate([o_lo, o_mid]), np.concatenate([o_mid, o_hi])
        if len(lo) > opts.max_samples:
            return False, checks  # more pieces in doubt than a motion may take: not certified
    return not len(lo), checks


def _least(clear: np.ndarray, own: np.ndarray | None) -> np.ndarray:
    """(k,) the least of the obstacle clearances and the shifted pair gaps (:func:`pose_clearance`)."""
    return clear if own is None else np.minimum(clear, own.min(axis=-1))


def plan_iterations(planner: PlannerOptions = DEFAULTS.planner) -> int:
    """The most RRT-Connect iterations one :func:`plan_path` may take with ``planner``
    (``problem.tunables.planner``): it searches at two floors.

    >>> plan_iterations() == (DEFAULTS.planner.settle_searches + DEFAULTS.planner.ompl_searches) * DEFAULTS.planner.ompl_iterations
    True
    """
    return planner.plan_iterations


def plan_path(problem: Problem, start: np.ndarray, goals: np.ndarray, searched: Searched | None = None) -> JointPath:
    """A free path from ``start`` to one of ``goals`` (nearest first), or none.

    First with room: to the goal poses with room to settle, every pose of the path at least
    :func:`~armanim.motion.filter.clearance.settle_clearance` from every obstacle, so that the
    filter (which slows every approach to what it keeps) lets the arm follow it; an arm resting
    closer than that first steps straight away from the surfaces (:func:`escape_pose`). Then,
    if that finds nothing, to any goal pose at the planning floor.

    Parameters
    ----------
    problem : Problem
    start : (n,) array
        The current pose, radians.
    goals : (k, n) array
        Free goal poses, the roomy ones first, each group nearest first.
    searched : callable, optional
        Told the RRT-Connect iterations as they go (see :data:`Searched`); not called for a
        plan that needs no search.
    """
    most, ticked = plan_iterations(problem.tunables.planner), False

    def tick(done: int) -> None:
        nonlocal ticked
        ticked = True
        assert searched is not None  # tick is handed on only with searched
        searched(done, most)

    from armanim.motion.planning.check import CompiledCheck  # numba: imported where a plan starts

    path = _path_at_two_floors(problem, start, goals, tick if searched else None, CompiledCheck.of(problem))
    if ticked and searched is not None:  # ticked: searched was given
        searched(most, most)
    return path


def _path_at_two_floors(
    problem: Problem, start: np.ndarray, goals: np.ndarray, tick: Callable[[int], None] | None, check: CompiledCheck
) -> JointPath:
    """:func:`plan_path`'s search: with room to settle first (``settle_searches`` searches), then
    at the planning floor (``ompl_searches``); ``tick(done)`` counts the iterations of both, the
    second's after the first's whole budget; every pose and motion judged by ``check`` (the
    compiled checks, the filter's buffer inside the limits)."""
    room = settle_clearance(problem)
    roomy = goals[pose_clearance(problem, goals) >= room]
    begin: np.ndarray | None = start
    checks = 0
    if len(roomy) and pose_clearance(problem, start)[0] < room:
        begin, checks = escape_pose(problem, start, room)
    if len(roomy) and begin is not None:
        waypoints, source, used = search_path(
            problem, begin, roomy, room, tick, searches=problem.tunables.planner.settle_searches, check=check
        )
        checks += used
        if waypoints is not None:
            head = [start] if begin is not start else []
            return JointPath(np.concatenate([np.array(head).reshape(-1, len(start)), waypoints]), source, checks)
    waypoints, source, used = search_path(
        problem,
        start,
        goals,
        planning_floor(problem, start),
        tick,
        first=problem.tunables.planner.settle_searches,
        check=check,
    )
    return JointPath(waypoints, source, checks + used)


def search_path(
    problem: Problem,
    start: np.ndarray,
    goals: np.ndarray,
    floor: float,
    tick: Callable[[int], None] | None = None,
    first: int = 0,
    searches: int | None = None,
    check: CompiledCheck | None = None,
    thorough: bool = True,
) -> tuple[np.ndarray | None, PathSource, int]:
    """(waypoints or None, source, checks): the straight segment to one of the first goals,
    else RRT-Connect to any of them (``searches`` searches, default ``ompl_searches``), every
    pose at least ``floor`` from every obstacle. ``tick(done)`` is told the iterations, counted
    as though ``first`` searches had run before. ``check``: the compiled checks to judge poses
    and motions by (:class:`~armanim.motion.planning.check.CompiledCheck`, whose ``closed``
    limits a joint goal's path keeps), else the numpy ones with the filter's buffer; ``thorough``:
    how the path is simplified (:func:`simplify`)."""
    checks, opts = 0, problem.tunables.planner
    for goal in goals[: opts.straight_tries]:
        free, used = (
            check.motion_free(start, goal, floor) if check is not None else motion_is_free(problem, start, goal, floor)
        )
        checks += used
        if free:
            return np.stack([start, goal]), "straight", checks
    for search in range(opts.ompl_searches if searches is None else searches):
        before = (first + search) * opts.ompl_iterations
        counted = (lambda done, before=before: tick(before + done)) if tick else None
        waypoints, used = rrt_connect(problem, start, goals[: opts.ompl_goals], floor, search, counted, check, thorough)
        _collect_before_exit()
        checks += used
        if waypoints is not None:
            return waypoints, "rrt_connect", checks
    return None, "none", checks


def _collect_before_exit() -> None:
    """Free OMPL's objects before the interpreter ends (once a process). Its Python callbacks form
    cycles with its objects, a dozen a search, which nanobind reports as leaks if they are still
    there at exit; a full collection takes 0.1 s in a process that has loaded numba, so it runs
    once, at exit, not after every search."""
    global _COLLECTING
    if not _COLLECTING:
        atexit.register(gc.collect)
        _COLLECTING = True


_COLLECTING = False


def escape_pose(problem: Problem, start: np.ndarray, floor: float) -> tuple[np.ndarray | None, int]:
    """(pose or None, checks): a pose one short straight move from ``start`` with every link at
    least ``floor`` from every obstacle, the arm moved along the sum of the clearance gradients
    of its links closer than that (away from the surfaces it rests at), its points travelling
    the planner's ``escape_travels`` clearances at most; the move itself keeps the planning floor."""
    state = arm_state(problem, start)
    rows, _ = obstacle_rows(problem, state, floor - kept_clearance(problem))
    own, _ = self_pair_rows(problem, state, floor - kept_clearance(problem))
    direction = rows.sum(axis=0) + own.sum(axis=0)
    travel = point_travel_bound(problem, direction)
    checks = 0
    if not travel > 0:
        return None, checks
    for clearances in problem.tunables.planner.escape_travels:
        pose = start + direction * (clearances * problem.solver.clearance / travel)
        checks += 1
        if not (within_limits(problem, pose[None])[0] and pose_clearance(problem, pose[None])[0] >= floor):
            continue
        free, used = motion_is_free(problem, start, pose, planning_floor(problem, start))
        checks += used
        if free:
            return pose, checks
    return None, checks


def rrt_connect(
    problem: Problem,
    start: np.ndarray,
    goals: np.ndarray,
    floor: float,
    search: int = 0,
    tick: Callable[[int], None] | None = None,
    check: CompiledCheck | None = None,
    thorough: bool = True,
) -> tuple[np.ndarray | None, int]:
    """OMPL's RRT-Connect from ``start`` to any of ``goals``, simplified (``thorough``: see
    :func:`simplify`); (path or None, checks). Every pose of the path keeps ``floor`` from every
    obstacle, by ``check`` where given (:class:`~armanim.motion.planning.check.CompiledCheck`),
    else the numpy checks.

    ``search`` picks the random numbers: each value gives another, always the same, search.
    ``tick(iterations)`` is called as the search starts and every ``tick_iterations`` (the
    planner's options, whose ``ompl_iterations`` is the budget).
    """
    from ompl import base as ob
    from ompl import geometric as og

    opts = problem.tunables.planner
    _seed_ompl(search, opts.ompl_seed)
    n = len(start)
    checks = [0]
    space, si, _validator = _space_information(
        ob, problem, start, floor, checks, check
    )  # OMPL borrows the validator: keep it
    pdef = ob.ProblemDefinition(si)
    pdef.addStartState(_state(space, start))
    targets = ob.GoalStates(si)
    for goal in goals:
        targets.addState(_state(space, goal))
    pdef.setGoal(targets)
    planner = og.RRTConnect(si)
    planner.setRange(opts.rrt_range)
    planner.setProblemDefinition(pdef)
    planner.setup()
    if tick:
        tick(0)
    planner.solve(ob.PlannerTerminationCondition(_budget(opts, tick)))
    if not pdef.hasExactSolution():
        return None, checks[0]
    path = pdef.getSolutionPath()
    simplify(og.PathSimplifier(si), path, thorough)
    waypoints = np.array([_array(path.getState(k), n) for k in range(path.getStateCount())])
    return waypoints, checks[0]


def simplify(simplifier: Any, path: Any, thorough: bool) -> None:
    """Shorten and smooth an OMPL ``path`` in place, every new piece certified by the search's
    motion check.

    ``thorough``: OMPL's ``simplifyMax`` (vertex reduction, shortcuts, B-spline smoothing and
    collapsing, repeated until nothing improves: the pose-goal planner's, whose paths the filter
    follows). Else vertex reduction, rope shortcuts (each waypoint joined to the farthest one a
    free straight piece reaches, and again), then one pass of B-spline smoothing (each corner
    cut at its neighbours' midpoints where that stays free): on MotionBenchMaker's Panda problems
    as short as ``simplifyMax`` with a fifth to a third of its motion checks; the smoothing pass
    shortens a UR5 path by some 3 % (7.94 to 7.68 rad, median of 30) for 4 ms.
    """
    if thorough:
        simplifier.simplifyMax(path)
        return
    simplifier.reduceVertices(path)
    simplifier.ropeShortcutPath(path)
    simplifier.smoothBSpline(path, 1)


def _budget(opts: PlannerOptions, tick: Callable[[int], None] | None) -> Callable[[], bool]:
    """OMPL's termination test for one search: true once it was asked more than ``ompl_iterations``
    times (the budget, counted so that it is deterministic), telling ``tick`` every ``tick_iterations``."""
    iterations = [0]

    def out_of_budget() -> bool:
        iterations[0] += 1
        if tick and iterations[0] % opts.tick_iterations == 0:
            tick(iterations[0])
        return iterations[0] > opts.ompl_iterations

    return out_of_budget


def _seed_ompl(search: int, seed: int) -> None:
    """Make OMPL's next RNGs the same every time for this ``search`` number (from ``seed``)."""
    from ompl import util as ou

    ou.setLogLevel(ou.LOG_NONE)
    ou.RNG.setSeed(seed)  # re-seeds the generator of every RNG OMPL creates from here on
    for _ in range(search):
        ou.RNG()  # each RNG made takes the next seed: the planner's RNGs get later ones


def _space_information(
    ob: Any, problem: Problem, start: np.ndarray, floor: float, checks: list[int], check: CompiledCheck | None = None
) -> tuple[Any, Any, Any]:
    """OMPL's joint space for the arm, with the free-pose test and the certified motion check
    at ``floor`` (both counting poses checked into ``checks[0]``; by ``check`` where given, else
    numpy's); returns (space, si, validator)."""
    n = len(start)
    space = ob.RealVectorStateSpace(n)
    space.setBounds(_bounds(ob, problem, start))
    si = ob.SpaceInformation(space)

    def state_is_free(state: Any) -> bool:
        checks[0] += 1
        phi = _array(state, n)[None]
        if check is not None:
            return check.pose_free(phi[0], floor)
        return bool(within_limits(problem, phi)[0] and pose_clearance(problem, phi)[0] >= floor)

    def check_motion(validator: Any, s1: Any, s2: Any, *_: Any) -> bool:
        a, b = _array(s1, n), _array(s2, n)
        free, used = check.motion_free(a, b, floor) if check is not None else motion_is_free(problem, a, b, floor)
        checks[0] += used
        return free

    # OMPL's bindings ship no types (the base is Any, which a class statement may not subclass
    # under strict mypy): the subclass is made by its base's metaclass, as a class statement would
    SampledMotions = type(ob.MotionValidator)("SampledMotions", (ob.MotionValidator,), {"checkMotion": check_motion})

    si.setStateValidityChecker(state_is_free)
    validator = SampledMotions(si)
    si.setMotionValidator(validator)
    si.setup()
    return space, si, validator


def _bounds(ob: Any, problem: Problem, start: np.ndarray) -> Any:
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


def _state(space: Any, phi: np.ndarray) -> Any:
    state = space.allocState()
    for j, value in enumerate(phi):
        state[j] = float(value)
    return state


def _array(state: Any, n: int) -> np.ndarray:
    return np.array([state[j] for j in range(n)])
