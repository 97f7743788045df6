"""A path goal's tool along its path: one warm-started pose solve per sample of the path.

Once the arm is at a path's start (reached as any goal is), the path is sampled every
``speed / fps`` of arc length (at most ``tunables.path.spacing_per_tolerance`` path tolerances apart;
every corner a sample), and each sample is solved from the pose of the one before: the
scene's method with full steps, aiming at the sample's point (and the goal's orientation),
every step through the safety filter, so obstacles, limits and the arm's own body are kept
in the null space of the path task. A sample is accepted when

- the tool is within a tenth of ``solver.path_tolerance`` of its point (and within half the
  orientation tolerance of the goal's orientation),
- no joint turned more than ``solver.max_joint_step`` from the sample before (no jump to
  another branch of the arm's poses), and
- the pose halfway between the two samples (each joint halfway) puts the tool within half the
  path tolerance of the path between them (MoveIt's midpoint test, PR #2916), and within the
  orientation tolerance.

A sample the scene's method cannot solve though nothing holds the arm back is solved again with ``newton`` (the assignment's
gradient descent and Newton's method, which gets through poses where a linear method's step
turns against its own task); a sample that still fails is split in two, down to ``tunables.path.max_splits`` halvings; a piece that still
fails stops the path at the last accepted sample, with the cause (:data:`armanim.motion.solution.PATH_CAUSES`).
Never a silent jump.

How far the tool gets can depend on the pose the arm starts the path in (the elbow, the wrist's
branch). When the path stops short from the pose the arm reached its start in, the planner's free
poses at the start (:func:`armanim.motion.planning.poses.goal_poses`) are tried too, up to
``tunables.path.other_starts``, and the arm is carried by a planned path to the one that follows farthest
(:func:`followed_route`). Pure core: no I/O.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field, replace

import numpy as np

from armanim.arm.kinematics import forward, tool_rotation
from armanim.motion.framestep import method_step
from armanim.motion.ik import pose_errors, solving_problem
from armanim.motion.orientation import orientation_angle
from armanim.motion.problem import Goal, Problem, joint_offset, step_caps
from armanim.motion.solvers import ArmState, Method, arm_state, solver_method
from armanim.motion.stalls import beyond_reach
from armanim.motion.toolpath import ToolPath
from armanim.names import Blocker, PathCause, PathSource


@dataclass
class Followed:
    """The samples a path goal's tool followed, one frame each.

    Attributes
    ----------
    states : list of ArmState
        The accepted samples' poses, in order (the first is the path's start).
    s : list of float
        Their arc lengths along the path, scene units.
    errors : list of float
        The tool's distance from the path at each, scene units.
    iterations, step_scale : lists
        The solver's inner iterations spent on each, and the last step's scale through the filter.
    newton_iterations : int
        Newton iterations over all samples (``newton`` only).
    midpoint_error : float
        The largest distance from the path at the accepted steps' midpoints.
    cause : PathCause or None
        Why the path stopped short of its end (None: it did not).
    """

    states: list[ArmState] = field(default_factory=list)
    s: list[float] = field(default_factory=list)
    errors: list[float] = field(default_factory=list)
    iterations: list[int] = field(default_factory=list)
    step_scale: list[float] = field(default_factory=list)
    newton_iterations: int = 0
    midpoint_error: float = 0.0
    cause: PathCause | None = None


@dataclass(frozen=True)
class Route:
    """How a path goal's path is followed: the planned poses that carry the arm from where it reached
    the path's start to the start pose chosen (none when it stays), then the samples along the path.

    Attributes
    ----------
    to_start : (k, n) array
        Planned poses, one a frame, radians (k = 0: the arm starts where it is).
    followed : Followed
    poses : int
        Free poses at the start the planner offered (0 when none was asked for).
    checks : int
        Poses the planner checked for collisions on the way to the chosen start.
    source : PathSource
        How the planner connected the arm to that start (``"none"``: it stays).
    """

    to_start: np.ndarray
    followed: Followed
    poses: int = 0
    checks: int = 0
    source: PathSource = "none"


Along = Callable[[int, int], None]
"""``along(done, most)``: a path's progress while it is followed, in thousandths (``most`` is
:data:`PER_PATH`); each trial from another start counts from 0 again."""

PER_PATH = 1000


def followed_route(
    problem: Problem, method: Method, state: ArmState, goal: Goal, seed: int = 0, along: Along | None = None
) -> Route:
    """The route along ``goal``'s path from ``state`` (the arm at its start) that gets farthest:
    from ``state`` itself, or, when that stops short (or cannot take the start to the path's
    tolerance), from the best of ``tunables.path.other_starts`` free poses at the start, or else
    along the path walked backward from a free pose at its end (:func:`_followed_backward`), each
    reachable by a short planned search (:func:`_quick_planner`; the first that follows the whole
    path ends the trials). ``along(done, most)``: each trial's progress, in thousandths of the
    path, after every sample (:data:`Along`)."""
    from armanim.motion.planning.follow import damper_paced, path_schedule, poses_along
    from armanim.motion.planning.path import plan_path
    from armanim.motion.planning.poses import goal_poses

    assert goal.path is not None
    best = _farther_follow(problem, method, state, goal, along)
    stay = np.zeros((0, len(state.phi)))
    if best.cause is None:
        return Route(stay, best)
    found = goal_poses(problem, state.phi, goal.path.start, seed, goal.orientation)
    trials: list[tuple[np.ndarray, Followed]] = []
    for pose in _other_branches(problem, found.poses, [state.phi]):
        trial = _farther_follow(problem, method, arm_state(problem, pose), goal, along)
        if _done(trial) > _done(best) + sample_spacing(problem, goal):
            trials.append((pose, trial))
            if trial.cause is None:
                break
    offered = len(found.poses)
    if not any(trial.cause is None for _, trial in trials):
        ends, backward = _followed_backward(problem, method, state, goal, seed, along)
        offered += ends
        if backward is not None:
            trials.append((backward.states[0].phi, backward))
    route = Route(stay, best, offered)
    quick = _quick_planner(problem)
    for pose, trial in sorted(trials, key=lambda t: -_done(t[1]))[: problem.tunables.path.route_plans]:
        planned = plan_path(quick, state.phi, pose[None])
        route = replace(route, checks=route.checks + planned.checks)
        if planned.waypoints is not None:
            step, most = problem.solver.max_joint_step, problem.solver.max_frames_per_goal
            schedule = path_schedule(planned.waypoints, step, most)
            frames = poses_along(planned.waypoints, damper_paced(problem, planned.waypoints, schedule, most))
            if np.abs(frames[-1] - pose).max() <= 1e-9:  # a plan cut short by the frame cap would leave a jump
                return Route(frames, trial, offered, route.checks, planned.source)
    return route


def _followed_backward(
    problem: Problem, method: Method, state: ArmState, goal: Goal, seed: int = 0, along: Along | None = None
) -> tuple[int, Followed | None]:
    """The free poses offered at the end of ``goal``'s path, and the whole path as followed from the
    first of up to ``tunables.path.other_starts`` of them (each ``tunables.path.branches_apart`` from
    the others) that walks it backward to its start, turned round to run forward (None: none did).

    Following forward keeps the arm in the branch it starts in, and a branch free at the start may
    meet an obstacle before the end (the arm's elbow against a post as the tool comes down): the
    oracle of ``pick_bench`` finds other poses free all along. Walking back from a free pose at the
    end finds the branch that ends free. Each sample of the walk is solved and checked as forward
    (the same filter, jumps and midpoints), and a step's joint motion is the same segment either way."""
    from armanim.motion.planning.poses import goal_poses

    assert goal.path is not None
    back = replace(goal, path=goal.path.reversed())
    ends = goal_poses(problem, state.phi, goal.path.end, seed, goal.orientation)
    for pose in _other_branches(problem, ends.poses, []):
        trial = _farther_follow(problem, method, arm_state(problem, pose), back, along)
        if trial.cause is None:
            return len(ends.poses), _turned_round(trial, goal.path)
    return len(ends.poses), None


def _turned_round(back: Followed, path: ToolPath) -> Followed:
    """A whole follow of ``path`` reversed (:meth:`ToolPath.reversed`) as the follow of ``path``
    itself: its samples in the other order, their arc lengths and distances from the path again."""
    states = back.states[::-1]
    s = [min(path.length, max(0.0, path.length - x)) for x in back.s[::-1]]
    tips = np.array([state.tip for state in states])
    before = np.array([s[0], *s[:-1]])
    errors = path.nearest(tips, before, np.array(s))[1]
    return Followed(
        states=states,
        s=s,
        errors=[float(e) for e in errors],
        iterations=back.iterations[::-1],
        step_scale=back.step_scale[::-1],
        newton_iterations=back.newton_iterations,
        midpoint_error=back.midpoint_error,
    )


def _farther_follow(
    problem: Problem, method: Method, state: ArmState, goal: Goal, along: Along | None = None
) -> Followed:
    """The path followed from ``state`` with every push of the null space; when the filter stops it
    short (held by an obstacle or the arm's own links) where a joint came inside its limit's margin,
    followed again with the limits' push left to the filter alone (:func:`sampling_problem`), and
    the farther of the two.

    Near a limit, the limits' push turns the arm away from it through the null space, and that turn
    can fold the arm onto its own links: a Panda line held by a pair of its links at 12 % (the pair
    at its floor, joint 2 pushed off its limit) goes to 15 % without it, as far as the benchmark's
    oracle; the filter keeps every joint its buffer inside its limits either way."""
    pushed = follow_path(problem, method, state, goal, along=along)
    if pushed.cause not in ("obstacle", "self_collision") or not _near_limits(problem, pushed):
        return pushed
    unpushed = follow_path(problem, method, state, goal, limit_push=False, along=along)
    return unpushed if _done(unpushed) > _done(pushed) else pushed


def _near_limits(problem: Problem, followed: Followed) -> bool:
    """Whether some sample had a limited joint inside its limit's margin (where the limits' push acts)."""
    if not followed.states:
        return False
    lim = problem.limits
    phi = np.array([state.phi for state in followed.states])
    inside = np.minimum(phi - lim.lower, lim.upper - phi) < lim.margin
    return bool(np.any(inside & lim.limited))


def _other_branches(problem: Problem, poses: np.ndarray, taken: list[np.ndarray]) -> list[np.ndarray]:
    """Up to ``tunables.path.other_starts`` of ``poses`` (k, n), nearest first, each at least
    ``tunables.path.branches_apart`` (the largest joint's turn) from those ``taken`` (the arm's own
    pose, or none) and from those taken before it."""
    opts = problem.tunables.path
    chosen: list[np.ndarray] = []
    for pose in poses:
        if all(np.abs(joint_offset(problem, other, pose)).max() >= opts.branches_apart for other in taken + chosen):
            chosen.append(pose)
            if len(chosen) >= opts.other_starts:
                break
    return chosen


def _quick_planner(problem: Problem) -> Problem:
    """The problem with the planner's search cut to ``tunables.path.route_iterations`` (one search): a way to a
    better start is worth a short search, not the budget of a stalled goal."""
    planner = replace(problem.tunables.planner, ompl_searches=1, ompl_iterations=problem.tunables.path.route_iterations)
    return replace(problem, tunables=replace(problem.tunables, planner=planner))


def _done(followed: Followed) -> float:
    """Arc length a follow got to (0 when it did not start)."""
    return followed.s[-1] if followed.states else 0.0


def sample_spacing(problem: Problem, goal: Goal) -> float:
    """Arc length between two samples of ``goal``'s path: a frame's travel at its speed, at most
    ``tunables.path.spacing_per_tolerance`` path tolerances.

    >>> from types import SimpleNamespace
    >>> from armanim.motion.tunables import DEFAULTS
    >>> p = SimpleNamespace(fps=25.0, solver=SimpleNamespace(path_tolerance=0.001), tunables=DEFAULTS)
    >>> sample_spacing(p, SimpleNamespace(speed=0.05)), sample_spacing(p, SimpleNamespace(speed=1.0))
    (0.002, 0.01)
    """
    return path_spacing(
        goal.speed, problem.fps, problem.solver.path_tolerance, problem.tunables.path.spacing_per_tolerance
    )


def path_spacing(speed: float, fps: float, path_tolerance: float, per_tolerance: float) -> float:
    """:func:`sample_spacing` of a path followed at ``speed`` and ``fps`` to ``path_tolerance``,
    at most ``per_tolerance`` path tolerances (``tunables.path.spacing_per_tolerance``).

    >>> path_spacing(0.05, 25.0, 0.001, 10.0), path_spacing(1.0, 25.0, 0.001, 10.0)
    (0.002, 0.01)
    """
    return min(speed / fps, per_tolerance * path_tolerance)


def most_path_frames(problem: Problem, goal: Goal) -> int:
    """Most frames following ``goal``'s path can take (:func:`most_following_frames`; 0 for a point goal)."""
    if goal.path is None:
        return 0
    return most_following_frames(
        goal.path, sample_spacing(problem, goal), problem.solver.max_frames_per_goal, problem.tunables.path.max_splits
    )


def most_following_frames(path: ToolPath, spacing: float, max_frames_per_goal: int, max_splits: int) -> int:
    """Most frames following ``path`` sampled every ``spacing`` can take: a planned way to another
    start pose (``max_frames_per_goal``), then every sample's step halved ``max_splits`` times
    (``tunables.path.max_splits``); the samples counted, never made (:meth:`ToolPath.sample_count`).

    >>> most_following_frames(ToolPath.polyline(np.array([[0.0, 0, 0], [1, 0, 0]])), 0.25, 100, 4)
    165
    """
    return int(max_frames_per_goal + (path.sample_count(spacing) - 1) * 2**max_splits + 1)


def sampling_problem(problem: Problem, limit_push: bool = True) -> Problem:
    """The problem as one sample is solved: full steps (:func:`armanim.motion.ik.solving_problem`)
    to a tenth of the path tolerance and half the orientation tolerance, the null space's pushes
    (away from obstacles, the arm's own links and limits) as strong as in one frame of the scene's
    animation. A full step's beta = 1 would make them ten times that (beta 0.1): a push that large
    beside a sample's tiny task turns the arm so far that its curvature throws the tool off the
    path, and the next step back, without end. ``limit_push`` False: no push from the limits
    (``w_limits`` 0), the filter alone keeping the joints inside them."""
    solving = solving_problem(problem)
    s = problem.solver
    gain = s.beta / solving.solver.beta
    return replace(
        solving,
        solver=replace(
            solving.solver,
            tolerance=problem.tunables.path.sample_tolerance * s.path_tolerance,
            orientation_tolerance=0.5 * s.orientation_tolerance,
            w_obstacles=gain * s.w_obstacles,
            w_limits=gain * s.w_limits if limit_push else 0.0,
        ),
    )


def follow_path(
    problem: Problem, method: Method, state: ArmState, goal: Goal, limit_push: bool = True, along: Along | None = None
) -> Followed:
    """The tool along ``goal.path`` from ``state`` (the arm at, or near, the path's start);
    ``limit_push`` as :func:`sampling_problem`'s; ``along(done, most)`` told the thousandths of
    the path done after each sample tried (:data:`Along`).

    Returns
    -------
    Followed
        Every accepted sample (the path's start first); ``cause`` set when the path stopped short.
    """
    assert goal.path is not None, "a path goal"
    path, sampling = goal.path, sampling_problem(problem, limit_push)
    fallback = solver_method("newton")
    out = Followed()
    first = _solved_sample(sampling, method, state, path, goal, 0.0)
    if first.cause is not None:
        out.cause = first.cause
        return out
    _accept(out, first, 0.0, path)
    pending = list(path.samples(sample_spacing(problem, goal))[:0:-1])  # a stack: the next sample last
    smallest = sample_spacing(problem, goal) / 2**problem.tunables.path.max_splits
    while pending:
        s_to = pending.pop()
        s_from = out.s[-1]
        tried = _solved_sample(sampling, method, out.states[-1], path, goal, s_to)
        if tried.cause == "singular" and method is not fallback:  # a pose the method cannot leave: Newton's solve may
            tried = _solved_sample(sampling, fallback, out.states[-1], path, goal, s_to)
        cause = tried.cause or _step_fault(problem, goal, out.states[-1], tried.state, s_from, s_to, out)
        if along is not None:
            along(int(PER_PATH * (s_to if cause is None else s_from) / max(path.length, 1e-300)), PER_PATH)
        if cause is None:
            _accept(out, tried, s_to, path)
        elif s_to - s_from > smallest * (1 + 1e-9):
            pending += [s_to, (s_from + s_to) / 2]
        else:
            out.cause = cause
            break
    return out


@dataclass(frozen=True)
class _Sample:
    """One sample's solve: where it ended, what it spent, and why it failed (None: it did not)."""

    state: ArmState
    iterations: int
    newton_iterations: int
    scale: float
    cause: PathCause | None


def _accept(out: Followed, sample: _Sample, s: float, path: ToolPath) -> None:
    """Note ``sample`` as the path's next frame, at arc length ``s``; its error is the tool's distance
    from the path between the sample before and it (as the clock measures its frames)."""
    before = np.array([out.s[-1] if out.s else s])
    out.states.append(sample.state)
    out.s.append(s)
    out.errors.append(float(path.nearest(sample.state.tip[None], before, np.array([s]))[1][0]))
    out.iterations.append(sample.iterations)
    out.step_scale.append(sample.scale)
    out.newton_iterations += sample.newton_iterations


def _solved_sample(sampling: Problem, method: Method, state: ArmState, path: ToolPath, goal: Goal, s: float) -> _Sample:
    """Filtered full steps from ``state`` toward the path's point at ``s`` until the tool is there
    (:func:`sampling_problem`'s tolerances), at most ``tunables.path.sample_steps``."""
    point = path.points(np.array([s]))[0]
    tolerance = sampling.solver.tolerance
    blocked: list[Blocker | None] = []
    iterations = newton_iterations = 0
    scale = 1.0
    for _ in range(sampling.tunables.path.sample_steps):
        distance, angle, progress = pose_errors(sampling, state, point, goal.orientation)
        if progress < tolerance:
            return _Sample(state, iterations, newton_iterations, scale, None)
        moved, its, newton_its = method_step(sampling, method, state, point, goal.orientation)
        iterations += its
        newton_iterations += newton_its
        blocked.append(moved.blocked_by)
        scale = moved.scale
        if moved.scale == 0.0:
            break
        state = moved.state
    distance, angle, progress = pose_errors(sampling, state, point, goal.orientation)
    if progress < tolerance:
        return _Sample(state, iterations, newton_iterations, scale, None)
    return _Sample(state, iterations, newton_iterations, scale, _cause(sampling, state, point, distance, blocked))


def _cause(
    problem: Problem, state: ArmState, point: np.ndarray, distance: float, blocked: list[Blocker | None]
) -> PathCause:
    """Why a sample's solve did not get the tool to ``point``: out of reach, the filter holding it
    back (an obstacle, the arm's own links, a limit), only the orientation left, else a singular pose."""
    if beyond_reach(problem, point):
        return "out_of_reach"
    if "obstacle" in blocked:  # the filter's surfaces: whichever kind is nearer its floor holds the arm
        own = state.min_self_gap - problem.self_pairs.clearance
        return "self_collision" if own < state.min_clearance - problem.solver.clearance else "obstacle"
    limits = problem.limits
    if "limit" in blocked or bool(
        np.any(np.minimum(state.phi - limits.lower, limits.upper - state.phi) < limits.margin)
    ):
        return "joint_limit"
    if distance < problem.solver.tolerance:
        return "orientation"
    center, radius = (
        reach_sphere(state) if problem.arm.prismatic is None else (problem.arm.base, np.inf)
    )  # a slide moves every point
    if np.linalg.norm(point - center) >= radius - REACH_SHARE * problem.solver.tolerance:
        return "out_of_reach"  # stretched out to the point on the edge of its reach, or past it
    return "singular"


REACH_SHARE = 10.0
"""A sample that fails within this many sample tolerances (one path tolerance) of the arm's
reach (:func:`reach_sphere`), or beyond it, is out of reach: the path leaves the reach there."""


def reach_sphere(state: ArmState) -> tuple[np.ndarray, float]:
    """The tightest sphere the tool point cannot leave whatever the joints do, read off the pose:
    about the last joint point that no joint before it moves (it lies on every earlier joint's
    axis, as a shoulder on the base joint's axis), of radius the rigid lengths from there to the
    tool point.

    >>> from types import SimpleNamespace
    >>> from armanim.arm.kinematics import Arm, forward
    >>> pose = forward(Arm.from_names([1.0, 1.0, 1.0, 1.0]), np.radians([30.0, 40.0, -20.0, 10.0]))
    >>> center, radius = reach_sphere(SimpleNamespace(pose=pose, tip=pose.points[-1]))
    >>> (center.round(12) + 0.0).tolist(), round(radius, 12)
    ([0.0, 0.0, 1.0], 3.0)
    """
    pose = state.pose
    points, axes = pose.points, pose.axes
    lengths = np.linalg.norm(np.diff(points, axis=0), axis=1)
    tool = float(np.linalg.norm(state.tip - points[-1]))
    size = max(1.0, float(lengths.sum()) + tool)
    fixed = 0
    if axes is None:  # a pose without its axes: the reach from the base
        return points[0].copy(), float(lengths.sum()) + tool
    for j in range(1, len(axes)):
        offsets = points[j] - points[:j]  # from each earlier joint to p_j, off its axis:
        off_axis = offsets - np.sum(offsets * axes[:j], axis=1)[:, None] * axes[:j]
        if np.all(np.linalg.norm(off_axis, axis=1) <= 1e-9 * size):
            fixed = j
    return points[fixed].copy(), float(lengths[fixed:].sum()) + tool


def _step_fault(
    problem: Problem, goal: Goal, before: ArmState, after: ArmState, s_from: float, s_to: float, out: Followed
) -> PathCause | None:
    """Whether the step between two solved samples jumps (a joint turns more than
    ``max_joint_step``) or strays from the path at its midpoint; notes the midpoint's error."""
    assert goal.path is not None
    turn = joint_offset(problem, before.phi, after.phi)
    if problem.arm.prismatic is not None and np.any(np.abs(turn) > step_caps(problem)):
        return "jump"
    if float(np.abs(turn).max(initial=0.0)) > problem.solver.max_joint_step and problem.arm.prismatic is None:
        return "jump"
    middle = forward(problem.arm, before.phi + turn / 2)
    error = float(goal.path.nearest(middle.tip[None], np.array([s_from]), np.array([s_to]))[1][0])
    if error > problem.tunables.path.midpoint_tolerance * problem.solver.path_tolerance:
        return "jump"
    if goal.orientation is not None:
        angle = float(orientation_angle(goal.orientation, tool_rotation(problem.arm, middle)))
        if angle > problem.solver.orientation_tolerance:
            return "jump"
    out.midpoint_error = max(out.midpoint_error, error)
    return None


__all__ = [
    "Followed",
    "Route",
    "follow_path",
    "followed_route",
    "most_following_frames",
    "most_path_frames",
    "path_spacing",
    "sample_spacing",
    "sampling_problem",
]
