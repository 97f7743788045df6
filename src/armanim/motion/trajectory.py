"""THE frame loop: the arm visits the goals in turn, one solver step per frame.

Frame 0 is the home pose. For each goal the loop steps until |e - g| < tolerance (and,
for a goal with an orientation, the tool's angle to it is below ``orientation_tolerance``),
then holds the pose for the goal's hold frames. Every frame's step is the method's
proposal passed through the safety filter (:func:`armanim.motion.filter.barrier.safe_step`).

When half a second of frames makes less progress than the tolerance (a local
minimum, a saddle, a singular pose, circling), the goal has stalled (:mod:`armanim.motion.stalls`): with
``solver.planner: auto`` the loop plans (:mod:`armanim.motion.planning`) and follows the
planned path (frames of mode ``plan``), then the method finishes to the tolerance;
with ``off`` the goal is missed at once. A goal is also missed when it is out of
reach, when no free pose reaches it (``no_free_pose``), when no path is found
(``no_path``), when the tip is at a goal but the arm cannot turn the tool to its
orientation there (``orientation_unreachable``, the angle left reported), or after
``max_frames_per_goal`` frames. Not converging is a result (a :class:`GoalReport`), never
an exception. Progress toward a goal with an orientation is judged on one number,
:func:`armanim.motion.orientation.pose_distance`.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import cast

import numpy as np

from armanim.arm.kinematics import Pose, forward, tip_jacobian, tool_rotation
from armanim.motion.carry import (
    FRAME_CHUNK,
    CarryReport,
    World,
    after_goal,
    frame_worlds,
    goal_problems,
    goal_world,
    needs_carrying,
    stopped_goal,
    world_problem,
)
from armanim.motion.filter.barrier import SafeStep, safe_step
from armanim.motion.framestep import method_step
from armanim.motion.orientation import frame_orientations, orientation_angle, pose_distance
from armanim.motion.paths.following import Along, Route, followed_route, most_path_frames
from armanim.motion.planning import plan_joint_motion, plan_motion
from armanim.motion.planning.path import Searched
from armanim.motion.problem import Goal, Problem, frames_in, joint_offset
from armanim.motion.solution import GoalReport, PathReport, PlanningReport, Solution, Trajectory
from armanim.motion.solvers import ArmState, Method, arm_state, solver_method
from armanim.motion.stalls import beyond_reach, miss_reason, orientation_unreachable, pose_stalled, stall_frames
from armanim.names import Blocker, MissReason
from armanim.world.selfdistances import self_gaps


@dataclass
class _Recorder:
    """Rows of the trajectory as the loop produces them."""

    phi: list[np.ndarray] = field(default_factory=list)
    tip: list[np.ndarray] = field(default_factory=list)
    clearance: list[float] = field(default_factory=list)
    goal: list[int] = field(default_factory=list)
    distance: list[float] = field(default_factory=list)
    iterations: list[int] = field(default_factory=list)
    step_scale: list[float] = field(default_factory=list)
    mode: list[str] = field(default_factory=list)
    angle: list[float] = field(default_factory=list)
    path_s: list[float] = field(default_factory=list)
    self_gap: list[float] = field(default_factory=list)
    self_pair: list[str] = field(default_factory=list)
    labels: tuple[str, ...] = ()  # the enabled pairs' labels of the problem being solved (its world's)

    def add(
        self,
        state: ArmState,
        goal: int,
        distance: float,
        iterations: int = 0,
        step_scale: float = 0.0,
        mode: str = "ik",
        angle: float | None = None,
        path_s: float = np.nan,
    ) -> None:
        """A row of ``state``: the clearance and pairs' gaps the filter measured for this very pose."""
        gaps = state.self_gaps.d if state.self_gaps is not None else None
        self.add_measured(
            state.phi, state.tip, state.min_clearance, goal, distance, gaps, mode, iterations, step_scale, angle, path_s
        )

    def add_measured(
        self,
        phi: np.ndarray,
        tip: np.ndarray,
        clearance: float,
        goal: int,
        distance: float,
        gaps: np.ndarray | None,
        mode: str,
        iterations: int = 0,
        step_scale: float = 0.0,
        angle: float | None = None,
        path_s: float = np.nan,
    ) -> None:
        """A row of a pose measured apart from a state: its tip, least clearance and every enabled
        pair's gap (P,) (None without pairs)."""
        self.phi.append(phi)
        self.tip.append(tip)
        self.clearance.append(clearance)
        self.goal.append(goal)
        self.distance.append(distance)
        self.iterations.append(iterations)
        self.step_scale.append(step_scale)
        self.mode.append(mode)
        self.angle.append(np.nan if angle is None else angle)
        self.path_s.append(path_s)
        if gaps is not None:
            self.self_gap.append(float(gaps.min()))
            self.self_pair.append(self.labels[int(np.argmin(gaps))])

    def __len__(self) -> int:
        return len(self.phi)


@dataclass
class _Visit:
    """What happens while the arm heads for one goal."""

    index: int
    goal: Goal
    distances: list[float]
    angles: list[float | None]  # radians to the goal's orientation; None entries for a position-only goal
    progress: list[float]  # pose_distance: the distances themselves for a position-only goal
    frames: int = 0
    iterations: int = 0
    newton_iterations: int = 0
    blocked: list[Blocker | None] = field(default_factory=list)
    path: list[np.ndarray] = field(default_factory=list)  # planned poses still to follow
    overrun: int = 0  # frames spent waiting for the arm to reach a pose of the path
    planning: PlanningReport | None = None
    reason: MissReason | None = None
    beyond: bool = False  # the goal lies beyond the arm's reach: the arm stretches toward it (:func:`_stretched`)


def hold_frames(problem: Problem, goal: Goal) -> int:
    """Frames a reached goal is held: its hold seconds at the run's fps.

    >>> from types import SimpleNamespace
    >>> hold_frames(SimpleNamespace(fps=40.0), Goal(np.zeros(3), hold=2.0))
    80
    """
    return frames_in(goal.hold, problem.fps)


def goal_budget(problem: Problem, goal: Goal) -> int:
    """Most frames one goal can have: its frame cap, its path's (:func:`most_path_frames`) and its hold."""
    return problem.solver.max_frames_per_goal + most_path_frames(problem, goal) + hold_frames(problem, goal)


def frame_budget(problem: Problem) -> int:
    """Most frames a run can have: frame 0 and every goal's :func:`goal_budget`."""
    return 1 + sum(goal_budget(problem, g) for g in problem.goals)


def goal_errors(problem: Problem, state: ArmState, goal: Goal) -> tuple[float, float | None, float]:
    """|e - g|, the tool's angle to the goal's orientation (None without one), and the two
    as one progress measure (:func:`armanim.motion.orientation.pose_distance`)."""
    distance = float(np.linalg.norm(state.tip - goal.position))
    if goal.orientation is None:
        return distance, None, distance
    angle = float(orientation_angle(goal.orientation, tool_rotation(problem.arm, state.pose)))
    s = problem.solver
    return distance, angle, float(pose_distance(distance, angle, s.tolerance, s.orientation_tolerance))


def solve_trajectory(
    problem: Problem,
    progress: Callable[[int, int], None] | None = None,
    planning: Searched | None = None,
    along: Along | None = None,
    timer: Callable[[int, float], None] | None = None,
) -> Solution:
    """Run the frame loop over every goal.

    Parameters
    ----------
    problem : Problem
    progress : callable, optional
        Called after every frame with the frames produced so far and the most the
        run can still have in all (that bound shrinks as goals are reached early, and
        equals the frame count at the end).
    planning : callable, optional
        ``planning(done, most)``: the iterations of a plan's path search as it goes, between two
        frames (:data:`armanim.motion.planning.path.Searched`); each plan counts from 0 again.
    along : callable, optional
        ``along(done, most)``: a path goal's progress in thousandths of its path while it is
        followed (:data:`armanim.motion.paths.following.Along`), between two frames; each trial counts
        from 0 again.
    timer : callable, optional
        ``timer(k, seconds)``: the wall time goal ``k`` took (its IK, planning and frames), as
        each goal is done (``run``'s timing.json; never in the solution, which reruns
        reproduce byte for byte).

    Returns
    -------
    Solution
    """
    method = solver_method(problem.solver.method)
    rec = _Recorder(labels=problem.self_pairs.labels)
    state = arm_state(problem, problem.home)
    distance, angle, _ = goal_errors(problem, state, problem.goals[0])
    rec.add(state, 0, distance, angle=angle)
    reports = []
    carrying = needs_carrying(problem)
    world, worlds, solved = World(), [], problem  # the world each goal is solved in (pick and place)
    made: dict[tuple[object, ...], Problem] = {World().key(): problem}
    later = frame_budget(problem) - 1  # frames the goals not yet started may still add
    for k, goal in enumerate(problem.goals):
        later -= goal_budget(problem, goal)

        def report_progress(visit: _Visit, goal: Goal = goal, later: int = later) -> None:
            if progress:
                progress(len(rec), len(rec) + goal_budget(problem, goal) - visit.frames + later)

        started = time.perf_counter()
        if carrying:
            world = goal_world(problem, world, k, state.pose)
            worlds.append(world)
            if world.key() not in made:
                made[world.key()] = world_problem(problem, world)
            before, solved = solved, made[world.key()]
            if solved is not before:
                state = arm_state(solved, state.phi)  # the same pose measured in this goal's world
            rec.labels = solved.self_pairs.labels
        state, report = _visit_goal(
            solved,
            method,
            rec,
            state,
            k,
            stopped_goal(goal, world) if carrying else goal,
            report_progress,
            planning,
            along,
        )
        if carrying:
            world = after_goal(problem, world, k, report.reached, state.pose)
        if timer:
            timer(k, time.perf_counter() - started)
        reports.append(report)
        if progress:
            progress(len(rec), len(rec) + later)
    carry = CarryReport(tuple(worlds), world) if carrying else None
    return Solution(trajectory=_finish(problem, rec, carry), goals=tuple(reports), carry=carry)


def _visit_goal(
    problem: Problem,
    method: Method,
    rec: _Recorder,
    state: ArmState,
    k: int,
    goal: Goal,
    on_frame: Callable[[_Visit], None],
    planning: Searched | None = None,
    along: Along | None = None,
) -> tuple[ArmState, GoalReport]:
    """Frames toward goal ``k`` and its hold; returns the last state and the goal's report."""
    if goal.joints is not None:
        return _visit_joint_goal(problem, rec, state, k, goal, on_frame, planning)
    s = problem.solver
    first = len(rec) if k else 0
    distance, angle, progress = goal_errors(problem, state, goal)
    visit = _Visit(k, goal, [distance], [angle], [progress], beyond=beyond_reach(problem, goal.position))
    window = stall_frames(problem)
    floor = max(0.0, float(np.linalg.norm(goal.position - problem.arm.base)) - problem.arm.reach)
    if s.planner == "off":
        floor = np.inf  # no planner to take over: only progress below the tolerance is a stall
    while visit.progress[-1] >= s.tolerance and visit.frames < s.max_frames_per_goal:
        state = _one_frame(problem, method, rec, state, visit)
        on_frame(visit)
        if not visit.path and pose_stalled(
            visit.distances,
            visit.angles,
            window,
            s.tolerance,
            s.orientation_tolerance,
            floor,
            problem.tunables.stalls.progress,
        ):
            visit.reason = _escape(problem, state, visit, planning)
            if visit.reason is not None:
                break
    reached = visit.progress[-1] < s.tolerance
    path_report = None
    if goal.path is not None:
        state, reached, path_report = _follow(problem, method, rec, state, visit, reached, along)
        on_frame(visit)
    if reached:
        rests_on = rec.path_s[-1] if goal.path is not None else np.nan  # a path's end, where its hold stays
        for _ in range(hold_frames(problem, goal)):
            rec.add(state, k, visit.distances[-1], angle=visit.angles[-1], path_s=rests_on)
    elif visit.reason is None:
        visit.reason = miss_reason(problem, state, goal.position, visit.progress, visit.blocked)
        if orientation_unreachable(problem, goal.orientation, visit.distances[-1], visit.angles[-1]):
            visit.reason = "orientation_unreachable"
    return state, GoalReport(
        index=k,
        position=goal.position,
        reached=reached,
        reason=None if reached else visit.reason,
        frames=visit.frames,
        first_frame=first if len(rec) > first else -1,
        last_frame=len(rec) - 1 if len(rec) > first else -1,
        final_distance=visit.distances[-1],
        iterations=visit.iterations,
        newton_iterations=visit.newton_iterations,
        planning=visit.planning,
        final_orientation_error=visit.angles[-1],
        path=path_report,
    )


def joint_error(phi: np.ndarray, goal: Goal) -> np.ndarray:
    """(...,) the largest |phi_j - goal_j| of each pose ``phi`` (..., n) from a joint goal (radians)."""
    assert goal.joints is not None
    return cast(np.ndarray, np.abs(phi - goal.joints).max(axis=-1))


def joint_goals_reached(problem: Problem, phi: np.ndarray, goal: np.ndarray, reached: np.ndarray) -> np.ndarray:
    """(F,) ``reached`` with the frames of joint goals judged by their joints instead: every joint
    within ``solver.joint_tolerance`` of the goal (a joint goal's tool point says nothing of it).
    ``phi`` (F, n) radians, ``goal`` (F,) each frame's goal index."""
    if all(g.joints is None for g in problem.goals):
        return reached
    reached = reached.copy()
    for k, g in enumerate(problem.goals):
        if g.joints is not None:
            mine = goal == k
            reached[mine] = joint_error(phi[mine], g) <= problem.solver.joint_tolerance
    return reached


def _visit_joint_goal(
    problem: Problem,
    rec: _Recorder,
    state: ArmState,
    k: int,
    goal: Goal,
    on_frame: Callable[[_Visit], None],
    planning: Searched | None = None,
) -> tuple[ArmState, GoalReport]:
    """Frames along a planned path to joint goal ``k`` (mode ``plan``: no method steps; the path
    is certified free, :func:`~armanim.motion.planning.plan_joint_motion`) and its hold."""
    assert goal.joints is not None
    first = len(rec) if k else 0
    distance, _, _ = goal_errors(problem, state, goal)
    visit = _Visit(k, goal, [distance], [None], [distance])  # a joint goal: no orientation, its distance its progress
    plan = None
    if joint_error(state.phi, goal) > problem.solver.joint_tolerance:
        plan = plan_joint_motion(problem, state.phi, goal.joints, planning)
        visit.planning = PlanningReport(
            plans=1,
            poses=plan.poses,
            path=plan.source,
            checks=plan.checks,
            frames=0 if plan.frames is None else len(plan.frames),
        )
    if plan is not None and plan.frames is not None and len(plan.frames):
        _record_plan(problem, rec, visit, plan.frames, on_frame)
        state = arm_state(problem, plan.frames[-1])
    reached = bool(joint_error(state.phi, goal) <= problem.solver.joint_tolerance)
    if reached:
        for _ in range(hold_frames(problem, goal)):
            rec.add(state, k, visit.distances[-1])
    elif plan is not None:
        visit.reason = plan.reason or "too_slow"  # a path longer than the goal's frames is followed as far as they go
    return state, GoalReport(
        index=k,
        position=goal.position,
        reached=reached,
        reason=visit.reason,
        frames=visit.frames,
        first_frame=first if len(rec) > first else -1,
        last_frame=len(rec) - 1 if len(rec) > first else -1,
        final_distance=visit.distances[-1],
        iterations=0,
        planning=visit.planning,
    )


def _record_plan(
    problem: Problem, rec: _Recorder, visit: _Visit, frames: np.ndarray, on_frame: Callable[[_Visit], None]
) -> None:
    """A joint goal's planned frames (F, n) (mode ``plan``), their clearances and pairs' gaps
    measured together (:func:`~armanim.motion.planning.check.frame_margins`: compiled, the
    numbers :func:`~armanim.motion.solvers.common.arm_state` gives to rounding)."""
    from armanim.arm import kernel  # numba, as the planner's checks
    from armanim.motion.planning.check import frame_margins

    clear, gaps = frame_margins(problem, frames)
    tips = kernel.forward(problem.arm, frames).tip
    assert visit.goal.position is not None
    for phi, tip, least, own in zip(frames, tips, clear, gaps):
        visit.distances.append(float(np.linalg.norm(tip - visit.goal.position)))
        visit.frames += 1
        rec.add_measured(
            phi, tip, float(least), visit.index, visit.distances[-1], own if len(problem.self_pairs) else None, "plan"
        )
        on_frame(visit)


def _follow(
    problem: Problem,
    method: Method,
    rec: _Recorder,
    state: ArmState,
    visit: _Visit,
    reached: bool,
    along: Along | None = None,
) -> tuple[ArmState, bool, PathReport]:
    """A path goal's frames along its path once the arm has reached its start (mode ``path``, one
    a sample); returns the last state, whether the whole path was followed, and the path's report.
    A goal whose start was missed keeps its reason and follows nothing."""
    path = visit.goal.path
    assert path is not None
    if not reached:
        return state, False, PathReport(path.length, 0.0, np.nan)
    route = followed_route(problem, method, state, visit.goal, visit.index, along)
    _record_route(problem, rec, visit, route)
    followed = route.followed
    state = followed.states[-1] if followed.states else state
    done = followed.s[-1] if followed.s else 0.0
    errors = followed.errors + [followed.midpoint_error]
    if followed.cause is None:
        return state, True, PathReport(path.length, path.length, max(errors))
    visit.reason = "path_blocked"
    return (
        state,
        False,
        PathReport(
            path.length, done, max(errors) if followed.s else np.nan, stop_point=state.tip.copy(), cause=followed.cause
        ),
    )


def _record_route(problem: Problem, rec: _Recorder, visit: _Visit, route: Route) -> None:
    """A path goal's frames from where it reached its start: the planned way to another start pose
    (mode ``plan``; noted as a plan of the goal), then the start (mode ``ik``) and the samples along
    the path (mode ``path``)."""
    if len(route.to_start):
        before = visit.planning or PlanningReport()
        visit.planning = replace(
            before, plans=before.plans + 1, poses=route.poses, path=route.source, checks=before.checks + route.checks
        )
        for phi in route.to_start:
            moved = arm_state(problem, phi)
            distance, angle, _ = goal_errors(problem, moved, visit.goal)
            rec.add(moved, visit.index, distance, mode="plan", angle=angle)
            visit.distances.append(distance)
            visit.angles.append(angle)
    followed = route.followed
    for i, moved in enumerate(followed.states):  # the first: the start itself, to the path's tolerance
        _, angle, _ = goal_errors(problem, moved, visit.goal)
        rec.add(
            moved,
            visit.index,
            followed.errors[i],
            followed.iterations[i],
            followed.step_scale[i],
            "path" if i else "ik",
            angle,
            followed.s[i] if i else np.nan,
        )
        visit.distances.append(followed.errors[i])
        visit.angles.append(angle)
        visit.iterations += followed.iterations[i]
    visit.frames += len(route.to_start) + len(followed.states)
    visit.newton_iterations += followed.newton_iterations


def _one_frame(problem: Problem, method: Method, rec: _Recorder, state: ArmState, visit: _Visit) -> ArmState:
    """One filtered step: along the planned path if there is one, else the method's."""
    if visit.path:  # (following it may end it: the last pose reached, or the arm held back too long)
        nominal, iterations, newton_its, mode = (
            joint_offset(problem, state.phi, _next_on_path(problem, state, visit)),
            0,
            0,
            "plan",
        )
        assert visit.planning is not None  # a path comes with its planning report
        visit.planning = replace(visit.planning, frames=visit.planning.frames + 1)
        moved = safe_step(problem, state, nominal)
    else:
        moved, iterations, newton_its = (
            _stretched(problem, state, visit.goal.position)
            if visit.beyond and method.inverts_the_jacobian
            else method_step(problem, method, state, visit.goal.position, visit.goal.orientation)
        )
        mode = "ik"
    distance, angle, progress = goal_errors(problem, moved.state, visit.goal)
    visit.distances.append(distance)
    visit.angles.append(angle)
    visit.progress.append(progress)
    visit.blocked.append(moved.blocked_by)
    visit.frames += 1
    visit.iterations += iterations
    visit.newton_iterations += newton_its
    rec.add(moved.state, visit.index, visit.distances[-1], iterations, moved.scale, mode, angle)
    return moved.state


def _stretched(problem: Problem, state: ArmState, goal: np.ndarray) -> tuple[SafeStep, int, int]:
    """A filtered step from ``state`` toward ``goal``, a point beyond the arm's reach: down the
    gradient of the tip's squared distance to it, ``g = J^T e`` (J the tip's (3, n) Jacobian, e
    the (3,) offset to the goal), the stall options' ``stretch`` (a half) of the step that the
    line's linear model says comes closest (the Cauchy step ``|g|^2 / |J g|^2``), at most
    ``max_joint_step``. Returns (step, 1, 0) as :func:`method_step` does (iterations, Newton's).

    The frame loop takes it for the methods that invert the Jacobian (``Method.inverts_the_jacobian``:
    ``pinv``, ``dls``; ``newton`` and ``gradient`` minimise the distance by themselves). Such a goal is missed whatever the arm does, and the stretched pose
    that comes closest is singular: there pinv and dls alternate between two poses, each a full
    step (scenes/out-of-reach shook for 19.6 s, about 100 turns back of each joint, before its
    miss). The gradient vanishes where the arm points at the goal, so the arm stretches toward it,
    slows and settles, and the goal stalls and is reported ``out_of_reach``. Half the Cauchy step:
    the whole one zigzags across the valley of the stretched poses (each joint turned back 28
    times on scenes/out-of-reach, against 3 at most by more than half a degree with half; a
    third stopped farther, 10.22 for 10.19).
    """
    e = goal - state.tip
    jac = tip_jacobian(problem.arm, state.pose)  # (3, n)
    g = jac.T @ e
    reach = jac @ g
    moved = float(reach @ reach)
    dphi = g * (float(g @ g) / moved * problem.tunables.stalls.stretch) if moved > 0.0 else np.zeros_like(g)
    return safe_step(problem, state, dphi), 1, 0


def _next_on_path(problem: Problem, state: ArmState, visit: _Visit) -> np.ndarray:
    """The target of this frame on the planned path.

    On schedule the path advances a pose per frame. It never runs ahead of the arm: when the
    filter holds the arm back (near a surface or a limit), the next pose is kept as the target
    until the arm is within a frame's step of it, and a path the arm cannot get near for a stall
    window is dropped (the method takes over, and a stall plans again from where the arm is).
    The last pose is kept as the target until the arm is there, for at most a stall window, so
    that the method takes over only at the goal pose."""
    head = visit.path[0]
    if len(visit.path) > 1:
        if np.abs(joint_offset(problem, state.phi, head)).max() <= problem.solver.max_joint_step * (1 + 1e-9):
            visit.overrun = 0
            return visit.path.pop(0)
        visit.overrun += 1  # the filter holds the arm back: wait for it
        if visit.overrun > stall_frames(problem):
            visit.path.clear()
        return head
    visit.overrun += 1
    if np.abs(
        joint_offset(problem, state.phi, head)
    ).max() < problem.tunables.planner.arrived or visit.overrun > stall_frames(problem):
        visit.path.clear()
    return head


def _escape(problem: Problem, state: ArmState, visit: _Visit, planning: Searched | None = None) -> MissReason | None:
    """A stalled goal: plan a way out (None) or give it up (the reason).

    A goal whose orientation the planner finds unreachable at its position is given up as
    ``orientation_unreachable`` once the tip is there; before that, the plan goes to the
    position alone (the position comes first)."""
    target, orientation = visit.goal.position, visit.goal.orientation
    if beyond_reach(problem, target):
        return "out_of_reach"
    local = miss_reason(problem, state, target, visit.progress, visit.blocked)
    if local != "numerical" and orientation_unreachable(problem, orientation, visit.distances[-1], visit.angles[-1]):
        local = "orientation_unreachable"
    if problem.solver.planner == "off" or local == "numerical":  # a method that fails is reported, not planned around
        return local
    done = visit.planning or PlanningReport()
    max_plans = problem.tunables.planner.max_plans
    if done.plans >= max_plans:
        return "stalled"
    seed = visit.index * max_plans + done.plans
    plan = plan_motion(problem, state.phi, target, seed=seed, orientation=orientation, searched=planning)
    if plan.reason == "orientation_unreachable":
        if visit.distances[-1] < problem.solver.tolerance:
            visit.planning = replace(done, plans=done.plans + 1)
            return plan.reason
        plan = plan_motion(problem, state.phi, target, seed=seed, searched=planning)
    visit.planning = replace(
        done,
        plans=done.plans + 1,
        poses=plan.poses,
        path=plan.source,
        checks=done.checks + plan.checks,
        self_pair=plan.self_pair,
    )
    if plan.frames is None:
        return plan.reason
    visit.path = list(plan.frames)
    visit.overrun = 0
    return None


def with_self_clearance(
    problem: Problem, traj: Trajectory, pose: Pose | None = None, gaps: np.ndarray | None = None
) -> Trajectory:
    """``traj`` with its frames' least self gap and pair (:attr:`Trajectory.self_clearance`):
    from ``gaps`` (F, P), every enabled pair's gap where the caller measured them
    (:func:`~armanim.motion.planning.check.frame_margins`), else measured from its angles (or
    their ``pose``); unchanged without enabled pairs."""
    if not len(problem.self_pairs) or not traj.frames:
        return replace(traj, self_clearance=None, self_pair=None)
    if gaps is None:
        gaps = self_gaps(
            forward(problem.arm, traj.phi) if pose is None else pose, problem.capsules, problem.self_pairs
        ).d
    least = gaps.min(axis=1)
    nearest = np.argmax(
        gaps <= (least + TIED * np.maximum(1.0, np.abs(least)))[:, None], axis=1
    )  # a tie: the first pair
    labels = np.array(problem.self_pairs.labels)
    return replace(traj, self_clearance=least, self_pair=labels[nearest])


TIED = 1e-9
"""Gaps this close (relative, at least 1) to a frame's least name the first such pair, so that
rounding never flips trajectory.csv's ``self_pair`` between two pairs at the same gap (a planar
arm's two link pairs at 0.8, each a kinematics rounding apart)."""


def with_world_self_clearance(
    problem: Problem, carry: CarryReport, traj: Trajectory, pose: Pose | None = None
) -> Trajectory:
    """:func:`with_self_clearance` of a run that carries objects: each frame's pairs measured in
    its goal's world (NaN and no pair where that world has none)."""
    problems = goal_problems(problem, carry)
    if not any(len(p.self_pairs) for p in problems) or not traj.frames:
        return replace(traj, self_clearance=None, self_pair=None)
    pose = forward(problem.arm, traj.phi) if pose is None else pose
    least, pair = np.full(traj.frames, np.nan), np.full(traj.frames, "", dtype=object)
    for solved, mine in frame_worlds(problem, carry, traj.goal, traj.fps):  # the fingers where they are
        if not len(solved.self_pairs) or not mine.any():
            continue
        rows = np.nonzero(mine)[0]
        for start in range(0, len(rows), FRAME_CHUNK):  # each capsule's world frame per frame: bounded memory
            some = rows[start : start + FRAME_CHUNK]
            part = with_self_clearance(
                solved,
                replace(traj, phi=traj.phi[some], goal=traj.goal[some]),
                type(pose)(pose.points[some], pose.frames[some]),
            )
            least[some], pair[some] = part.self_clearance, part.self_pair
    return replace(traj, self_clearance=least, self_pair=pair.astype(str))


def with_finger_clearance(problem: Problem, carry: CarryReport, traj: Trajectory) -> Trajectory:
    """``traj`` with the clearance of the frames where the gripper's fingers move (the last frames
    of a goal's hold, :func:`~armanim.motion.carry.frame_fingers`) measured with the fingers where
    they are (:func:`~armanim.motion.carry.world_clearance`): the frame loop measured them with the
    fingers where its goal's world holds them."""
    from armanim.motion.carry import frame_fingers, world_clearance

    fingers = frame_fingers(problem, carry, traj.goal, traj.fps)
    if fingers is None or problem.gripper is None or not traj.frames:
        return traj
    held = np.array([problem.gripper.rest if w.fingers is None else w.fingers for w in carry.worlds])[traj.goal]
    moving = fingers != held
    if not moving.any():
        return traj
    measured = world_clearance(
        problem, carry, forward(problem.arm, traj.phi), traj.goal, traj.fps
    )  # every frame: the ramps are per goal
    return replace(traj, clearance=np.where(moving, measured, traj.clearance))


def _finish(problem: Problem, rec: _Recorder, carry: CarryReport | None = None) -> Trajectory:
    distance = np.array(rec.distance)
    angle = np.array(rec.angle, dtype=float)
    turned = ~(angle >= problem.solver.orientation_tolerance)  # NaN (no orientation) counts as met
    phi, goal = np.array(rec.phi), np.array(rec.goal, dtype=int)
    path_s = np.array(rec.path_s) if any(g.path is not None for g in problem.goals) else None
    _, quaternions = frame_orientations(problem.arm, [g.orientation for g in problem.goals], phi, goal)
    traj = Trajectory(
        phi=np.array(rec.phi),
        tip=np.array(rec.tip),
        goal=np.array(rec.goal, dtype=int),
        distance=distance,
        clearance=np.array(rec.clearance),
        reached=(distance < problem.solver.tolerance) & turned,
        iterations=np.array(rec.iterations, dtype=int),
        step_scale=np.array(rec.step_scale),
        fps=problem.fps,
        mode=np.array(rec.mode),
        orientation_error=angle if any(g.orientation is not None for g in problem.goals) else None,
        tool_quaternion=quaternions,
        path_s=path_s,
        path_error=None if path_s is None else np.where(np.isnan(path_s), np.nan, distance),
    )
    traj = replace(traj, reached=joint_goals_reached(problem, phi, goal, traj.reached))
    if carry is not None:
        return with_world_self_clearance(problem, carry, with_finger_clearance(problem, carry, traj))
    if len(problem.self_pairs) and len(rec.self_gap) == len(rec):  # every frame's pairs were measured in the loop
        return replace(traj, self_clearance=np.array(rec.self_gap), self_pair=np.array(rec.self_pair))
    if not len(problem.self_pairs):
        return with_self_clearance(problem, traj)
    from armanim.motion.planning.check import frame_margins  # numba, as the planner's checks

    return with_self_clearance(problem, traj, gaps=frame_margins(problem, traj.phi)[1])


__all__ = [
    "frame_budget",
    "goal_budget",
    "hold_frames",
    "joint_goals_reached",
    "solve_trajectory",
    "with_self_clearance",
]
