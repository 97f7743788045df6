"""One run's frames at its output rate: each goal's solved path on the clock.

A scene's motion is solved at the scene's own ``render.fps``: one filtered step per frame,
which fixes *where* the arm goes. :func:`retime` then gives it *when*: each goal's solved
poses, from the pose the arm is at to the goal's last solved pose, are one path, timed by
:mod:`armanim.motion.timing.clock` from rest to rest within each joint's speed and acceleration
limits (``problem.rates``) and sampled at the output fps; a reached goal's hold is then its
seconds at rest at that rate. The clock is the same at any fps, so the arm moves the same
in seconds at 15, 30 or 60 fps, and reaches and misses the same goals.

Every sampled pose keeps the guarantees a solved one does: limits by the path's shape (each
joint monotone between two solved poses), clearance by checking the path between solved
poses (:func:`path_safety`). Pure core: numpy only.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import cast

import numpy as np

from armanim.arm.geometry import wrap_angle
from armanim.arm.kinematics import forward
from armanim.motion.carry import goal_problems, world_clearance
from armanim.motion.filter.clearance import pose_clearance, self_shift
from armanim.motion.orientation import frame_orientations
from armanim.motion.planning import joint_path_floor, plan_joint_motion
from armanim.motion.planning.path import motion_is_free
from armanim.motion.problem import Goal, Problem, joint_offset
from armanim.motion.solution import GoalReport, GoalTiming, KindPass, Solution, Trajectory
from armanim.motion.timing.blend import (
    ENTRY,
    BlendReport,
    ShapedPart,
    blend_reason,
    judged_radius,
    kind_pass,
    pass_speed_caps,
    via_distances,
)
from armanim.motion.timing.clock import ClockTooLong, Excess, Motion
from armanim.motion.timing.goalmotion import PathSafety, goal_motions, two_sided_bound
from armanim.motion.timing.jointpath import unwrapped
from armanim.motion.timing.pathtiming import (
    joined_timing,
    part_path_speed,
    path_reported,
    stray_frames,
    tool_speed_excess,
    traced_paths,
)
from armanim.motion.timing.smoothing import Certifier, smoothed_poses
from armanim.motion.trajectory import hold_frames, joint_goals_reached, with_self_clearance, with_world_self_clearance


def at_fps(problem: Problem, fps: float) -> Problem:
    """The problem as its frames at ``fps`` describe it: the per-frame bounds a trajectory
    keeps (``max_joint_step``, ``max_frames_per_goal``) expressed at that rate.

    >>> from armanim.scene import SceneModel, scene_to_problem
    >>> p = scene_to_problem(SceneModel.model_validate({"version": 1, "arm": {"links": [1, 1]}, "goals": [[1, 1, 0]]}))
    >>> q = at_fps(p, 2 * p.fps)
    >>> bool(np.isclose(q.solver.max_joint_step, p.solver.max_joint_step / 2)), q.solver.max_frames_per_goal
    (True, 1200)

    Raises
    ------
    ValueError
        ``fps`` is not a positive finite number (campaign 16: ``retime`` at 0 fps from Python
        ended in a ZeroDivisionError).
    """
    if not (math.isfinite(fps) and fps > 0):
        raise ValueError(f"fps: expected a positive, finite number of frames per second (got {fps!r})")
    if fps == problem.fps:
        return problem
    ratio = fps / problem.fps
    solver = replace(
        problem.solver,
        max_joint_step=problem.solver.max_joint_step / ratio,
        max_slide_step=problem.solver.max_slide_step / ratio,
        max_frames_per_goal=math.ceil(problem.solver.max_frames_per_goal * ratio - 1e-9),
    )
    return replace(problem, solver=solver, fps=fps)


def retime(problem: Problem, solution: Solution, fps: float, most_frames: float = np.inf) -> Solution:
    """``solution`` (solved at ``problem.fps``) on the clock, as frames at ``fps``.

    Parameters
    ----------
    problem : Problem
        The problem the solution was solved for (its ``fps`` is the solved rate, its
        ``rates`` the limits the clock keeps).
    solution : Solution
    fps : float
        Frames per second of the result.
    most_frames : float
        The most frames the result may have (its memory), holds included.

    Returns
    -------
    Solution
        The same path in time, valid for ``at_fps(problem, fps)``: per-goal frame counts,
        first and last frames and timing in the new frames; iterations (each solved frame's
        counted once), final distances and reasons as solved. The trajectory carries each
        frame's joint velocities (the clock's, rad/s).

    Raises
    ------
    ClockTooLong
        The motion would take more than ``most_frames`` frames.
    ValueError
        ``fps`` is not a positive finite number (:func:`at_fps`).
    """
    src, out = solution.trajectory, at_fps(problem, fps)
    rates = problem.rates
    parts = _parts(problem, solution, out)
    blending = any(g.blend is not None for g in problem.goals)
    passes: dict[int, _Pass | str] = {}
    rest_to_rest = None
    problems = goal_problems(problem, solution.carry) if solution.carry is not None else None
    if blending:
        parts, motions, passes, rest_to_rest = _blended_parts(problem, solution, parts, fps, most_frames)
    elif problems is not None:
        motions = _timed_parts(problem, src, parts, fps, most_frames, safeties=_world_safeties(problems, src, parts))
    else:
        motions = _timed_parts(problem, src, parts, fps, most_frames)
    made = sum(len(m.phi) for m in motions) + sum(p.hold for p in parts)
    if made > most_frames:
        raise ClockTooLong(f"{made:,} frames with the holds (at most {most_frames:,.0f})")
    frame_goals = [_frame_goals(p, m, passes) for p, m in zip(parts, motions)]
    phi, velocity, source, held, goal = _joined(
        src.phi, frame_goals, [p.frames for p in parts], motions, [p.hold for p in parts]
    )
    phi = within_closed_limits(problem, phi)
    part_timings = [
        (g, t)
        for m, p, mine in zip(motions, parts, frame_goals)
        for g, t in split_timing(m, mine, p.goal, src.phi[p.frames.start], rates.speed, rates.acceleration, fps)
    ]
    timings = [joined_timing([t for k, t in part_timings if k == g.index]) for g in solution.goals]
    from armanim.motion.planning.check import frame_margins  # numba, as the clock's passes

    pose = forward(problem.arm, phi)
    if problems is None:
        clear, gaps = frame_margins(problem, phi)
    else:  # a run that carries: each frame in its goal's world
        clear, gaps = world_clearance(problem, solution.carry, pose, goal, fps), None
    distance = np.linalg.norm(pose.tip - np.array([g.position for g in problem.goals])[goal], axis=-1)
    traced = traced_paths(problem, src, phi, pose.tip, source, goal, held)
    if traced is not None:
        distance = np.where(np.isnan(traced[1]), distance, traced[1])
    spent = np.concatenate([[0], np.cumsum(src.iterations)])[source + 1]
    angle, quaternions = frame_orientations(problem.arm, [g.orientation for g in problem.goals], phi, goal, pose)
    turned = True if angle is None else ~(angle >= problem.solver.orientation_tolerance)
    trajectory = Trajectory(
        phi=phi,
        tip=pose.tip,
        goal=goal,
        distance=distance,
        clearance=clear,
        reached=joint_goals_reached(problem, phi, goal, (distance < problem.solver.tolerance) & turned),
        iterations=np.where(held, 0, np.diff(spent, prepend=0)),  # each solved frame's counted once
        step_scale=np.where(held, 0.0, src.step_scale[source]),
        fps=fps,
        mode=np.where(held, "ik", src.modes[source]),
        orientation_error=angle,
        tool_quaternion=quaternions,
        velocity=velocity,
        path_s=None if traced is None else traced[0],
        path_error=None if traced is None else traced[1],
    )
    moving = np.zeros(len(phi), dtype=bool)
    moving[1:] = ~held[1:]
    if solution.carry is not None:
        trajectory = with_world_self_clearance(problem, solution.carry, trajectory, pose)
    else:
        trajectory = with_self_clearance(problem, trajectory, gaps=gaps)
    reports = (_report(g, trajectory, moving, t) for g, t in zip(solution.goals, timings))
    reports = (_blend_reported(problem, solution, r, trajectory, passes) for r in reports)
    return Solution(
        trajectory, tuple(path_reported(problem, r, trajectory) for r in reports), rest_to_rest, solution.carry
    )


def _world_safeties(problems: list[Problem], solved: Trajectory, parts: list[_Part]) -> list[PathSafety]:
    """Each part's :class:`PathSafety` in its goal's world (:func:`path_safety` of that world's
    problem, once per world): its lever arms, clearances, probes and checks are the carried object's too."""
    if solved.self_clearance is not None:  # a world without pairs has NaN there: nothing to keep
        solved = replace(
            solved, self_clearance=np.where(np.isnan(solved.self_clearance), np.inf, solved.self_clearance)
        )
    made: dict[int, PathSafety] = {}
    out = []
    for p in parts:
        world = problems[p.goal]
        if id(world) not in made:
            made[id(world)] = path_safety(world, solved)
        safety = made[id(world)]
        out.append(
            replace(
                safety,
                at_poses=safety.at_poses[p.frames],
                certified=safety.certified[p.frames.start : p.frames.stop - 1],
            )
        )
    return out


def within_closed_limits(problem: Problem, phi: np.ndarray) -> np.ndarray:
    """(F, n) ``phi`` with every limited joint clipped into its limits, ends included: a path that
    rests on a limit (a joint goal's) is evaluated on the clock to rounding, which may fall an ulp
    beyond it; inside the limits the values are unchanged, bit for bit.

    >>> from types import SimpleNamespace
    >>> p = SimpleNamespace(limits=SimpleNamespace(lower=np.array([-1.0, -np.inf]), upper=np.array([1.0, np.inf])))
    >>> within_closed_limits(p, np.array([[-1.0000000000000002, -5.0], [0.5, 5.0]])).tolist()
    [[-1.0, -5.0], [0.5, 5.0]]
    """
    return cast(np.ndarray, np.clip(phi, problem.limits.lower, problem.limits.upper))


@dataclass(frozen=True)
class _Part:
    """A piece of a goal's solved frames timed from rest to rest: a point goal's frames; a path
    goal's frames up to its path's start, then its frames along the path."""

    goal: int
    frames: slice
    hold: int
    path_speed: np.ndarray | None = None
    strays: Callable[[Motion], np.ndarray] | None = None
    excess: Excess | None = None
    vias: tuple[int, ...] = ()
    """The goals passed without stopping inside the part, in order (:mod:`armanim.motion.timing.blend`)."""
    via_frames: tuple[int, ...] = ()
    """Each via goal's last solved frame (an index of the solved trajectory)."""


def _timed_parts(
    problem: Problem,
    solved: Trajectory,
    parts: list[_Part],
    fps: float,
    most_frames: float,
    safety: PathSafety | None = None,
    safeties: list[PathSafety] | None = None,
) -> list[Motion]:
    """Each part's motion on the clock (:func:`~armanim.motion.timing.goalmotion.goal_motions`), kept clear
    by :func:`path_safety` (or ``safety``, its result; or ``safeties``, each part's own) and, along a
    path, on it at the goal's speed."""
    rates = problem.rates
    if safeties is None:
        safety = path_safety(problem, solved) if safety is None else safety
        safeties = [
            replace(
                safety,
                at_poses=safety.at_poses[p.frames],
                certified=safety.certified[p.frames.start : p.frames.stop - 1],
            )
            for p in parts
        ]
    return goal_motions(
        [solved.phi[p.frames] for p in parts],
        problem.limits.limited,
        rates.speed,
        rates.acceleration,
        fps,
        safeties,
        most_frames,
        rates.jerk,
        [p.hold for p in parts],
        [p.path_speed for p in parts],
        [p.strays for p in parts],
        [p.excess for p in parts],
        problem.tunables.clock,
    )


def _parts(problem: Problem, solution: Solution, out: Problem) -> list[_Part]:
    """The solved frames' parts, in order, each with the pose before it first, and the hold (at
    ``out``'s rate) after a reached goal's last part."""
    parts, start = [], 0
    src = solution.trajectory
    for g in solution.goals:
        goal = problem.goals[g.index]
        hold = hold_frames(out, goal) if g.reached else 0
        piece = slice(start, start + g.frames + 1)
        along = int(np.sum(src.modes[piece][1:] == "path")) if goal.path is not None else 0
        if along:
            split = piece.stop - 1 - along
            parts.append(_Part(g.index, slice(piece.start, split + 1), 0))
            parts.append(
                _Part(
                    g.index,
                    slice(split, piece.stop),
                    hold,
                    part_path_speed(problem, src, goal, split, piece.stop),
                    stray_frames(problem, src, goal, split, piece.stop),
                    tool_speed_excess(problem, goal, out.fps),
                )
            )
        else:
            parts.append(_Part(g.index, piece, hold))
        start += g.frames + (hold_frames(problem, goal) if g.reached else 0)
    return parts


def _joined(
    solved: np.ndarray, goals: list[np.ndarray], pieces: list[slice], motions: list[Motion], holds: list[int]
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The run's frames: the start pose, then each part's motion and its hold. Per frame (F,):
    the angles (F, n), the clock's velocities (F, n), the solved frame each heads for, whether it
    is held, and its goal (index into the problem's goals). ``goals``: each part's frames' goals
    (its motion's frames, then its hold's: the part's own goal)."""
    n = solved.shape[1]
    phi: list[np.ndarray] = [solved[:1]]
    velocity: list[np.ndarray] = [np.zeros((1, n))]
    source: list[np.ndarray] = [np.zeros(1, dtype=int)]
    held: list[np.ndarray] = [np.zeros(1, dtype=bool)]
    goal: list[np.ndarray] = [np.zeros(1, dtype=int)]
    for index, piece, motion, hold in zip(goals, pieces, motions, holds):
        heads_for = piece.start + motion.heads_for
        if len(heads_for):
            heads_for[-1] = piece.stop - 1  # the last solved frame, repeated poses or not
        phi += [motion.phi, np.repeat(solved[piece.stop - 1 : piece.stop], hold, axis=0)]
        velocity += [motion.velocity, np.zeros((hold, n))]
        source += [heads_for, np.full(hold, piece.stop - 1)]
        held += [np.zeros(len(motion.phi), dtype=bool), np.ones(hold, dtype=bool)]
        goal += [index]
    return (
        np.concatenate(phi),
        np.concatenate(velocity),
        np.concatenate(source),
        np.concatenate(held),
        np.concatenate(goal),
    )


def path_safety(problem: Problem, trajectory: Trajectory) -> PathSafety:
    """What keeps ``trajectory``'s solved path clear (:class:`~armanim.motion.timing.goalmotion.PathSafety`):
    :func:`pose_clearance` against ``solver.clearance``, the solved frames' clearances as the
    solve measured them, and the steps between frames certified from them by lever arms.

    No point of the capsules moves by more than L . |dPhi| (each joint's lever arm times its
    turn), and no pair's gap changes by more (the pair rows of
    :attr:`~armanim.motion.problem.Problem.pair_lever_rows` are at most the lever arms): so
    :func:`~armanim.motion.timing.goalmotion.two_sided_bound` of the two frames' clearances, obstacles
    and pairs each, bounds every pose between them on the clock's path (each joint within the
    range of its two values).
    """
    reach = np.abs(wrap_angle(np.diff(trajectory.phi, axis=0))) @ problem.lever_arms
    floor = problem.solver.clearance
    clear = trajectory.clearance
    certified = two_sided_bound(clear[:-1], clear[1:], reach) >= floor
    if trajectory.self_clearance is not None:
        own = trajectory.self_clearance + self_shift(problem)
        certified &= two_sided_bound(own[:-1], own[1:], reach) >= floor
        clear = np.minimum(clear, own)
    from armanim.motion.planning.check import CompiledCheck  # numba, as the clock's passes

    measure = CompiledCheck.of(
        problem, exact=True
    ).pose_clearances  # pose_clearance's numbers, compiled: the probes ask thousands
    return PathSafety(
        measure,
        floor,
        problem.lever_arms,
        clear,
        certified,
        lambda a, b: detour(problem, a, b),
        lambda a, b: chord_free(problem, a, b),
    )


def chord_free(problem: Problem, a: np.ndarray, b: np.ndarray) -> bool:
    """Whether the straight chord between the poses ``a`` and ``b`` (n,) keeps ``solver.clearance``
    (or, between poses closer than that, the nearer one's clearance) throughout:
    :func:`~armanim.motion.planning.path.motion_is_free`, the segment halved until each piece is
    certified by the lever-arm bound (to within its ``certify_to``)."""
    ends = float(pose_clearance(problem, np.stack([a, a + joint_offset(problem, a, b)])).min())
    return motion_is_free(
        problem, a, a + joint_offset(problem, a, b), min(problem.solver.clearance, ends), closed=True
    )[0]


def detour(problem: Problem, a: np.ndarray, b: np.ndarray) -> np.ndarray | None:
    """(k, n) poses between ``a`` and ``b`` (n,) whose straight pieces a -> ... -> b are each
    certified clear, or None: the long way round of one or more unlimited joints, where
    :func:`~armanim.motion.planning.path.motion_is_free` certifies it, else the planner's path
    (:func:`~armanim.motion.planning.plan_joint_motion`, on even where the scene turns it off:
    the arm must not pass through what the chord cuts).

    Only a path's corners are kept, and enough poses between them that no piece turns a joint by
    more than a radian (an unlimited joint's piece is then the short way round, as the clock takes
    it).
    """
    offset = joint_offset(problem, a, b)
    turning = np.nonzero(~problem.limits.limited & (np.abs(offset) > 0))[0][:3]
    floor = joint_path_floor(problem, float(pose_clearance(problem, np.stack([a, b])).min()))
    ways = []
    for mask in range(1, 2 ** len(turning)):
        long = offset.copy()
        flip = turning[[bool(mask >> i & 1) for i in range(len(turning))]]
        long[flip] -= np.sign(long[flip]) * 2 * np.pi
        ways.append(long)
    for long in sorted(ways, key=lambda w: float(np.abs(w).sum())):
        if motion_is_free(problem, a, a + long, floor)[0]:
            way = np.stack([a, a + long])
            break
    else:
        planning = replace(problem, solver=replace(problem.solver, planner="auto"))
        plan = plan_joint_motion(planning, a, b)
        if plan.frames is None or not len(plan.frames) or not np.array_equal(plan.frames[-1], b):
            return None
        way = np.concatenate([a[None], plan.frames])
    return _corners(problem, way)


def _corners(problem: Problem, way: np.ndarray) -> np.ndarray | None:
    """The poses strictly inside ``way`` (k, n) (its ends excluded) at its corners, and between
    them enough poses that no piece turns a joint by more than a radian."""
    steps = np.diff(way, axis=0)
    unit = steps / np.maximum(np.linalg.norm(steps, axis=1, keepdims=True), 1e-300)
    corners = [0] + [i for i in range(1, len(way) - 1) if np.linalg.norm(unit[i] - unit[i - 1]) > 1e-9] + [len(way) - 1]
    out = []
    for p, q in zip(way[corners[:-1]], way[corners[1:]]):
        count = max(1, int(np.ceil(np.abs(q - p).max() / 1.0)))
        out += [p + t * (q - p) for t in np.arange(count) / count]
    inner = np.array(out[1:]).reshape(-1, way.shape[1])
    return np.where(problem.limits.limited, inner, wrap_angle(inner)) if len(inner) else None


def _report(g: GoalReport, trajectory: Trajectory, moving: np.ndarray, timing: GoalTiming) -> GoalReport:
    """A goal's report with its frames counted in the retimed trajectory, and its timing."""
    mine = np.nonzero(trajectory.goal == g.index)[0]
    planning = g.planning
    if planning is not None:
        planning = replace(planning, frames=int(np.sum(trajectory.modes[mine] == "plan")))
    return replace(
        g,
        frames=int(moving[mine].sum()),
        first_frame=int(mine[0]) if len(mine) else -1,
        last_frame=int(mine[-1]) if len(mine) else -1,
        planning=planning,
        timing=timing,
    )


@dataclass(frozen=True)
class _Pass:
    """How a via goal was passed in its part's motion: the frame nearest it (an index of the
    motion), how near (:func:`~armanim.motion.timing.blend.via_distances`), how fast, and whether within
    its judged radius; ``corner`` as :attr:`~armanim.motion.timing.blend.BlendReport.corner`."""

    frame: int
    distance: float
    speed: float
    passed: bool
    corner: str
    by_kind: KindPass | None = None


def _why_rest(problem: Problem, solution: Solution, parts: list[_Part], k: int) -> str | None:
    """Why goal ``k`` (with ``blend``) rests (:func:`~armanim.motion.timing.blend.blend_reason`), or None: a
    goal before a path goal flows into that goal's approach to its path's start where the arm moves
    there (the path itself starts at rest), else it rests (``next_path``)."""
    why = blend_reason(problem, solution.goals, k)
    if why == "next_path":
        phi = solution.trajectory.phi
        if any(
            p.goal == k + 1 and p.path_speed is None and np.any(phi[p.frames] != phi[p.frames.start]) for p in parts
        ):
            return None
    return why


def _merged(parts: list[_Part], vias: set[int], src: Trajectory) -> list[_Part]:
    """``parts`` with each via goal's last part and the next part made one (a path of several
    goals, timed from rest to rest with free speed at the vias)."""
    out: list[_Part] = []
    for part in parts:
        if out and out[-1].goal in vias and out[-1].path_speed is None and part.goal == out[-1].goal + 1:
            before = out.pop()
            part = _Part(
                part.goal,
                slice(before.frames.start, part.frames.stop),
                part.hold,
                part.path_speed,
                part.strays,
                part.excess,
                before.vias + (before.goal,) + part.vias,
                before.via_frames + (before.frames.stop - 1,) + part.via_frames,
            )
        out.append(part)
    return out


def _blended_parts(
    problem: Problem, solution: Solution, parts: list[_Part], fps: float, most_frames: float
) -> tuple[list[_Part], list[Motion], dict[int, _Pass | str], float]:
    """The parts with every via goal's merged into the next (:func:`_merged`), their motions, how
    each goal with ``blend`` was passed (or why it rests: a key of
    :data:`~armanim.motion.timing.blend.BLEND_REASONS`), and the run's seconds had every goal rested.

    A via whose frames do not come within its judged radius is retimed slower near it (the
    caps of :func:`~armanim.motion.timing.blend.pass_speed_caps` divided by 4, then 16, 64), then made to
    rest (``radius``). A goal with ``blend`` that rests has its own path shortened and smoothed
    (:func:`_shaped_part`, its ends kept) where that is faster than as solved. A merged part that
    takes more frames than its goals' parts from rest to rest (each as fast as it can: shortened or
    as solved) makes its slowest via pass its solved pose instead of a curve (a curve round a corner
    that turns back is slower than the corner), or rest if it does already (``slower``), and is timed
    again: passing a goal is never slower than stopping at it on the same path, and blending never
    lengthens a run."""
    src = solution.trajectory
    outcome: dict[int, _Pass | str] = {}
    vias = set()
    for k, goal in enumerate(problem.goals):
        if goal.blend is not None:
            why = _why_rest(problem, solution, parts, k)
            if why is None:
                vias.add(k)
            else:
                outcome[k] = why
    safety = path_safety(problem, src)
    plain = _timed_parts(problem, src, parts, fps, most_frames, safety)
    rest_to_rest = (1 + sum(len(m.phi) for m in plain) + sum(p.hold for p in parts)) / fps
    at_rest = list(plain)  # a goal with blend that rests: its own path shortened and smoothed, where that is faster
    for i, part in enumerate(parts):
        if (
            problem.goals[part.goal].blend is not None
            and part.path_speed is None
            and part.frames.stop - part.frames.start > 2
        ):
            alone = _timed_via_part(problem, src, safety, part, fps, most_frames, {}, set())[0]
            if len(alone.phi) < len(plain[i].phi):
                at_rest[i] = alone
    slow = dict.fromkeys(vias, 1.0)
    through: set[int] = set()  # vias whose curve made their part slower: they pass their solved pose
    while True:
        merged = _merged(parts, vias, src)
        motions, passes, slower = [], {}, set()
        for part in merged:
            if not part.vias:
                motions.append(
                    next(m for q, m in zip(parts, at_rest) if q is part)
                )  # by identity: a part's arrays do not compare
                continue
            motion, found = _timed_via_part(problem, src, safety, part, fps, most_frames, slow, through)
            motions.append(motion)
            passes.update(found)
            covered = [
                m
                for q, m in zip(parts, at_rest)
                if part.frames.start <= q.frames.start and q.frames.stop <= part.frames.stop
            ]
            if len(motion.phi) > sum(len(m.phi) for m in covered):  # never slower than stopping: the slowest pass rests
                slower.add(min(part.vias, key=lambda k: found[k].speed))
        missed = {k for k, p in passes.items() if not p.passed}
        if not missed and not slower:
            break
        for k in missed:
            slow[k] *= 4
            if slow[k] > 64:
                vias.discard(k)
                outcome[k] = "radius"
        for k in slower - missed:
            if k in through or passes[k].corner == "through":
                vias.discard(k)
                outcome[k] = "slower"
            else:
                through.add(k)
    outcome.update(passes)
    return merged, motions, outcome, rest_to_rest


def _timed_via_part(
    problem: Problem,
    src: Trajectory,
    safety: PathSafety,
    part: _Part,
    fps: float,
    most_frames: float,
    slow: dict[int, float],
    through: set[int],
) -> tuple[Motion, dict[int, _Pass]]:
    """A part through via goals on the clock: each via's corner cut where a certified curve fits
    (:func:`~armanim.motion.timing.blend.cut_corner`), the path's speed capped near each
    (:func:`~armanim.motion.timing.blend.pass_speed_caps`, divided by ``slow`` by goal), and how each was
    passed. The motion's frames head for the part's solved frames (offsets from its first)."""
    corner, zones = _shaped_part(problem, src, safety, part, through)
    poses, origin = corner.poses, corner.origin
    shaped = replace(safety, at_poses=corner.clearance, certified=corner.certified)
    caps = np.full(len(poses) - 1, np.inf)
    for j, k in enumerate(part.vias):
        caps = np.minimum(caps, pass_speed_caps(problem, problem.goals[k], poses, zones[j][0], fps, slow[k])[0])
    rates = problem.rates
    motion = goal_motions(
        [poses],
        problem.limits.limited,
        rates.speed,
        rates.acceleration,
        fps,
        [shaped],
        most_frames,
        rates.jerk,
        [part.hold],
        [caps],
    )[0]
    start_tip = forward(problem.arm, poses[0]).tip
    tips = forward(problem.arm, motion.phi).tip
    found = {}
    last = -1
    for j, k in enumerate(part.vias):
        goal = problem.goals[k]
        (z0, z1), curve = zones[j]
        window = np.nonzero((motion.heads_for >= z0) & (motion.heads_for <= z1 + 1))[0]
        if not len(window):
            after = np.nonzero(motion.heads_for > z1 + 1)[0]
            window = np.array(
                [
                    after[0] - 1 if len(after) and after[0] > 0 else len(motion.phi) - 1,
                    after[0] if len(after) else len(motion.phi) - 1,
                ]
            )
        window = window[window > last]
        if not len(window):
            found[k] = _Pass(last, np.inf, 0.0, False, "curve" if curve else "through")
            continue
        distance = via_distances(problem, goal, motion.phi[window])
        f = int(window[np.argmin(distance)])
        last = f
        if goal.joints is not None:
            speed = float(np.abs(motion.velocity[f]).max())
        else:
            ahead, behind = tips[min(f + 1, len(tips) - 1)], tips[f - 1] if f else start_tip
            speed = float(np.linalg.norm(ahead - behind)) * fps / (min(f + 1, len(tips) - 1) - (f - 1))
        found[k] = _Pass(
            f,
            float(distance.min()),
            speed,
            bool(distance.min() <= judged_radius(problem, goal) * (1 + 1e-9)),
            "curve" if curve else "through",
            kind_pass(problem, goal, motion.phi[f], motion.velocity[f]),
        )
    return replace(motion, heads_for=origin[motion.heads_for]), found


def via_paths(problem: Problem, solution: Solution) -> list[np.ndarray]:
    """The poses (m_i, n) of each part of ``solution`` (solved, not yet retimed) through via goals,
    as the clock is first given them: every via goal's solved path and the next goal's one, each
    corner cut where a certified curve fits (before a via rests for its radius or its time)."""
    src = solution.trajectory
    parts = _parts(problem, solution, problem)
    vias = {
        k for k, g in enumerate(problem.goals) if g.blend is not None and _why_rest(problem, solution, parts, k) is None
    }
    safety = path_safety(problem, src)
    merged = _merged(parts, vias, src)
    return [_shaped_part(problem, src, safety, part)[0].poses for part in merged if part.vias]


def _shaped_part(
    problem: Problem, src: Trajectory, safety: PathSafety, part: _Part, through: set[int] | None = None
) -> tuple[ShapedPart, dict[int, tuple[tuple[int, int], bool]]]:
    """A part through via goals made short and smooth (:func:`~armanim.motion.timing.smoothing.smoothed_poses`):
    its solved path shortcut between its first pose, each via's solved pose and its last, the
    corners rounded, a via's within its radius (not the goals in ``through``, which pass their
    solved pose); and each via's (by its place in ``part.vias``) stretch of poses and whether its
    corner was rounded."""
    frames = part.frames
    limited = problem.limits.limited
    flat = unwrapped(src.phi[frames], limited)
    local = [f - frames.start for f in part.via_frames]
    keep = sorted({0, len(flat) - 1, *local})
    near: dict[int, Callable[[np.ndarray], np.ndarray] | None] = {}
    for k, at in zip(part.vias, local):
        goal = problem.goals[k]
        assert goal.blend is not None
        if goal.blend <= 0 or (through is not None and k in through) or at in near:
            near[at] = None
        else:
            near[at] = _close_to(problem, goal)
    cert = Certifier(safety.clearance, safety.lever, safety.floor)
    smooth = smoothed_poses(
        flat, safety.at_poses[frames], safety.certified[frames.start : frames.stop - 1], keep, cert, near
    )
    origin = np.minimum(np.maximum.accumulate(np.ceil(smooth.position - 1e-9).astype(int)), len(flat) - 1)
    corner = ShapedPart(_wrapped(problem, smooth.poses), origin, smooth.clearance, smooth.certified)
    zones = {j: smooth.corners[at] for j, at in enumerate(local)}
    return corner, zones


def _close_to(problem: Problem, goal: Goal) -> Callable[[np.ndarray], np.ndarray]:
    """poses (k, n), unwrapped -> (k,) bool: whether each is within ``ENTRY`` of ``goal``'s blend radius."""
    assert goal.blend is not None
    radius = ENTRY * goal.blend

    def close(poses: np.ndarray) -> np.ndarray:
        return via_distances(problem, goal, _wrapped(problem, poses)) <= radius

    return close


def _wrapped(problem: Problem, phi: np.ndarray) -> np.ndarray:
    """``phi`` (..., n) with its unlimited joints wrapped into (-pi, pi]."""
    return np.where(problem.limits.limited, phi, wrap_angle(phi))


def _frame_goals(part: _Part, motion: Motion, passes: dict[int, _Pass | str]) -> np.ndarray:
    """(len(motion.phi) + part.hold,) each frame's goal: a via goal's up to its nearest frame, then
    the next goal's; the part's own goal after the last via, and in the hold."""
    goals = np.full(len(motion.phi) + part.hold, part.goal)
    for k in reversed(part.vias):
        passed = passes[k]
        assert isinstance(passed, _Pass), "a part's vias were passed"
        goals[: passed.frame + 1] = k
    return goals


def split_timing(
    motion: Motion,
    goals: np.ndarray,
    last: int,
    start: np.ndarray,
    speed: np.ndarray,
    acceleration: np.ndarray,
    fps: float,
) -> list[tuple[int, GoalTiming]]:
    """Each goal's :class:`GoalTiming` in a motion (from rest at ``start`` (n,) to rest) whose frames'
    goals are ``goals`` (at least len(motion.phi),), the motion's own goal ``last``: a motion of one goal's is its
    :meth:`Motion.timing`; one through via goals gives each its frames' seconds and the peaks of its
    frames' speeds and accelerations (differences over 1/fps, at rest before and after the motion)."""
    mine = goals[: len(motion.phi)]
    if not len(mine) or np.all(mine == last):
        return [(last, motion.timing(start, speed, acceleration, fps))]
    steps = wrap_angle(np.diff(np.concatenate([start[None], start[None], motion.phi, motion.phi[-1:]]), axis=0))
    v = np.abs(steps[1:-1]) * fps / speed  # (K, n): the step into each frame
    a = np.abs(np.diff(steps, axis=0))[1:] * fps**2 / acceleration  # (K, n): about each frame
    a[-1] = np.maximum(a[-1], np.abs(np.diff(steps, axis=0))[-1] * fps**2 / acceleration)
    out = []
    for k in dict.fromkeys(int(g) for g in mine):
        rows = np.nonzero(mine == k)[0]
        vk, ak = v[rows].max(axis=0), a[rows].max(axis=0)
        out.append(
            (k, GoalTiming(len(rows) / fps, float(vk.max()), float(ak.max()), int(np.argmax(vk)), int(np.argmax(ak))))
        )
    if last not in mine:
        out.append((last, GoalTiming(0.0, 0.0, 0.0, None, None)))
    return out


def _blend_reported(
    problem: Problem, solution: Solution, report: GoalReport, trajectory: Trajectory, outcome: dict[int, _Pass | str]
) -> GoalReport:
    """A goal's report with its :class:`~armanim.motion.timing.blend.BlendReport` (a goal with ``blend``):
    a via goal's final distance and orientation error are its nearest frame's."""
    goal = problem.goals[report.index]
    if goal.blend is None:
        return report
    last = report.last_frame
    done = outcome.get(report.index, "missed")
    if isinstance(done, _Pass):
        angle = (
            None
            if trajectory.orientation_error is None or goal.orientation is None
            else float(trajectory.orientation_error[last])
        )
        return replace(
            report,
            final_distance=float(trajectory.distance[last]),
            final_orientation_error=angle,
            blend=BlendReport(
                goal.blend, True, None, done.corner, done.distance, done.speed, goal.joints is not None, done.by_kind
            ),
        )
    near = float(via_distances(problem, goal, trajectory.phi[last])[0]) if last >= 0 else float("nan")
    at_rest = kind_pass(problem, goal, trajectory.phi[last], None) if last >= 0 else None
    return replace(
        report, blend=BlendReport(goal.blend, False, done, None, near, 0.0, goal.joints is not None, at_rest)
    )


__all__ = ["at_fps", "path_safety", "retime", "split_timing", "via_paths"]
