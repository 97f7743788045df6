"""One run's frames at its output rate: each goal's solved path on the clock.

A scene's motion is solved at the scene's own ``render.fps``: one filtered step per frame,
which fixes *where* the arm goes. :func:`retime` then gives it *when*: each goal's solved
poses, from the pose the arm is at to the goal's last solved pose, are one path, timed by
:mod:`armanim.motion.clock` from rest to rest within each joint's speed and acceleration
limits (``problem.rates``) and sampled at the output fps; a reached goal's hold is then its
seconds at rest at that rate. The clock is the same at any fps, so the arm moves the same
in seconds at 15, 30 or 60 fps, and reaches and misses the same goals.

Every sampled pose keeps the guarantees a solved one does: limits by the path's shape (each
joint monotone between two solved poses), clearance by checking the path between solved
poses (:func:`safe_pose`). Pure core: numpy only.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any, cast

import numpy as np

from armanim.arm.geometry import wrap_angle
from armanim.arm.kinematics import forward
from armanim.motion.clock import ClockTooLong, goal_motion
from armanim.motion.orientation import frame_orientations
from armanim.motion.problem import Problem
from armanim.motion.solution import GoalReport, GoalTiming, Solution, Trajectory
from armanim.motion.solvers.barrier import pair_lever_rows, pose_clearance, split_clearances
from armanim.motion.trajectory import hold_frames, with_self_clearance
from armanim.world.distances import min_link_clearance


def at_fps(problem: Problem, fps: float) -> Problem:
    """The problem as its frames at ``fps`` describe it: the per-frame bounds a trajectory
    keeps (``max_joint_step``, ``max_frames_per_goal``) expressed at that rate.

    >>> from armanim.scene import SceneModel, scene_to_problem
    >>> p = scene_to_problem(SceneModel.model_validate({"version": 1, "arm": {"links": [1, 1]}, "goals": [[1, 1, 0]]}))
    >>> q = at_fps(p, 2 * p.fps)
    >>> bool(np.isclose(q.solver.max_joint_step, p.solver.max_joint_step / 2)), q.solver.max_frames_per_goal
    (True, 1200)
    """
    if fps == problem.fps:
        return problem
    ratio = fps / problem.fps
    solver = replace(problem.solver, max_joint_step=problem.solver.max_joint_step / ratio,
                     max_frames_per_goal=math.ceil(problem.solver.max_frames_per_goal * ratio - 1e-9))
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
    """
    src, out = solution.trajectory, at_fps(problem, fps)
    n = src.phi.shape[1]
    rates = problem.rates
    # each name holds its goals' parts, then (np.concatenate) the joined array: typed Any for both
    phi: Any
    velocity: Any
    source: Any
    held: Any
    goal: Any
    phi, velocity, source, held, goal = [src.phi[:1]], [np.zeros((1, n))], [np.zeros(1, dtype=int)], [[False]], [[0]]
    timings = []
    start = made = 0
    for g in solution.goals:
        poses = src.phi[start:start + g.frames + 1]
        motion = goal_motion(poses, problem.limits.limited, rates.speed, rates.acceleration, fps,
                             clear=lambda p: safe_pose(problem, p), most_frames=most_frames - made,
                             jerk=rates.jerk, certified=certified_steps(problem, poses))
        heads_for = start + motion.heads_for
        if len(heads_for):
            heads_for[-1] = start + g.frames  # the last solved frame, repeated poses or not
        hold = hold_frames(out, problem.goals[g.index]) if g.reached else 0
        made += len(motion.phi) + hold
        if made > most_frames:
            raise ClockTooLong(f"{made:,} frames with the holds (at most {most_frames:,.0f})")
        phi += [motion.phi, np.repeat(poses[-1:], hold, axis=0)]
        velocity += [motion.velocity, np.zeros((hold, n))]
        source += [heads_for, np.full(hold, start + g.frames)]
        held += [np.zeros(len(motion.phi), dtype=bool), np.ones(hold, dtype=bool)]
        goal += [np.full(len(motion.phi) + hold, g.index)]
        timings.append(motion.timing(poses[0], rates.speed, rates.acceleration, fps))
        start += g.frames + (hold_frames(problem, problem.goals[g.index]) if g.reached else 0)
    phi, velocity = np.concatenate(phi), np.concatenate(velocity)
    source, held, goal = np.concatenate(source), np.concatenate(held), np.concatenate(goal)
    pose = forward(problem.arm, phi)
    distance = np.linalg.norm(pose.tip - np.array([g.position for g in problem.goals])[goal], axis=-1)
    spent = np.concatenate([[0], np.cumsum(src.iterations)])[source + 1]
    angle, quaternions = frame_orientations(problem.arm, [g.orientation for g in problem.goals], phi, goal)
    turned = True if angle is None else ~(angle >= problem.solver.orientation_tolerance)
    trajectory = Trajectory(
        phi=phi,
        tip=pose.tip,
        goal=goal,
        distance=distance,
        clearance=min_link_clearance(pose, problem.obstacles, problem.capsules),
        reached=(distance < problem.solver.tolerance) & turned,
        iterations=np.where(held, 0, np.diff(spent, prepend=0)),  # each solved frame's counted once
        step_scale=np.where(held, 0.0, src.step_scale[source]),
        fps=fps,
        mode=np.where(held, "ik", src.mode[source]),  # type: ignore[index]  # a solved trajectory has its modes
        orientation_error=angle,
        tool_quaternion=quaternions,
        velocity=velocity,
    )
    moving = np.zeros(len(phi), dtype=bool)
    moving[1:] = ~held[1:]
    trajectory = with_self_clearance(problem, trajectory)
    return Solution(trajectory, tuple(_report(g, trajectory, moving, t) for g, t in zip(solution.goals, timings)))


def certified_steps(problem: Problem, poses: np.ndarray) -> np.ndarray:
    """(m - 1,) bool: the solved steps between ``poses`` (m, n) every pose between whose ends
    (each joint within the range of its two values, as the clock's path keeps it) keeps
    ``solver.clearance`` from the obstacles and ``self_clearance`` between the arm's enabled
    pairs: no point of the capsules moves farther from either end than the sum of each joint's
    lever arm times its turn, and no pair's gap changes by more than that sum over the joints
    between its two capsules (:func:`~armanim.motion.solvers.barrier.pair_lever_rows`), so the
    farther end's clearance less that is a lower bound."""
    clear, own = split_clearances(problem, poses)
    step = np.abs(wrap_angle(np.diff(poses, axis=0)))
    floor = problem.solver.clearance
    certified = np.maximum(clear[:-1], clear[1:]) - step @ problem.lever_arms >= floor
    if own is not None:
        certified &= np.all(np.maximum(own[:-1], own[1:]) - step @ pair_lever_rows(problem).T >= floor, axis=1)
    return cast(np.ndarray, certified)


def safe_pose(problem: Problem, phi: np.ndarray) -> np.ndarray:
    """(k,) bool: which poses ``phi`` (k, n) keep ``solver.clearance`` from every obstacle and
    ``self_clearance`` between every enabled pair of the arm's own capsules."""
    if len(problem.obstacles) == 0 and len(problem.self_pairs) == 0:
        return np.ones(len(phi), dtype=bool)
    return pose_clearance(problem, phi) >= problem.solver.clearance


def _report(g: GoalReport, trajectory: Trajectory, moving: np.ndarray, timing: GoalTiming) -> GoalReport:
    """A goal's report with its frames counted in the retimed trajectory, and its timing."""
    mine = np.nonzero(trajectory.goal == g.index)[0]
    planning = g.planning
    if planning is not None:
        planning = replace(planning, frames=int(np.sum(trajectory.mode[mine] == "plan")))  # type: ignore[index]  # the retimed trajectory has its modes
    return replace(
        g,
        frames=int(moving[mine].sum()),
        first_frame=int(mine[0]) if len(mine) else -1,
        last_frame=int(mine[-1]) if len(mine) else -1,
        planning=planning,
        timing=timing,
    )


__all__ = ["at_fps", "retime", "safe_pose"]
