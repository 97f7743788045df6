"""One motion at any frame rate: a solved run sampled at another fps.

A scene's motion is solved at the scene's own ``render.fps`` (its clock: one filtered
step per frame of it). At another rate the same motion is sampled in time, goal by goal:
the frames toward a goal are spread evenly over the seconds the solved motion took (never
farther apart than 1 / fps), the goal's last solved pose is always one of them, and
between two solved frames the joint angles are interpolated linearly (unlimited joints the
short way round); a reached goal's hold is then its seconds at the new rate, as in the
frame loop. So the arm moves at the same speed in seconds at 15, 30 or 60 fps, reaches
and misses the same goals, and a higher rate only adds in-between frames.

Every sampled pose is checked as a solved one is: an in-between pose that would come
closer than ``solver.clearance`` to an obstacle (the chord between two safe poses can cut
a curved surface) shows the nearer solved pose instead. Limits hold by convexity (both
ends keep the filter's buffer), and no joint turns faster than between the solved frames
(but for such a frame, which turns by at most one solved step). Pure core: numpy only.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from armanim.arm.geometry import wrap_angle
from armanim.arm.kinematics import forward
from armanim.motion.orientation import frame_orientations
from armanim.motion.problem import Problem
from armanim.motion.solution import GoalReport, Solution, Trajectory
from armanim.motion.trajectory import hold_frames
from armanim.world.distances import min_link_clearance


def sample_times(steps: int, fps_from: float, fps_to: float) -> np.ndarray:
    """(K,) where the frames of ``steps`` solved frames fall at ``fps_to``, in solved frames
    after the start (fractional): K is rounded up from the seconds, so frames are never
    farther apart than ``1 / fps_to``, and the last one is the last solved frame.

    >>> sample_times(4, 30.0, 15.0)
    array([2., 4.])
    >>> sample_times(2, 30.0, 60.0)
    array([0.5, 1. , 1.5, 2. ])
    """
    count = math.ceil(steps * fps_to / fps_from - 1e-9)  # 1e-9: 64.000000001 intervals are 64
    # k * steps / count, not k * (steps / count): whole solved frames (the last above all) come out exact
    return np.arange(1, count + 1) * steps / count if count else np.zeros(0)


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


def resample(problem: Problem, solution: Solution, fps: float) -> Solution:
    """``solution`` (solved at ``problem.fps``) as frames at ``fps``; itself when the rates agree.

    Parameters
    ----------
    problem : Problem
        The problem the solution was solved for (its ``fps`` is the solved rate).
    solution : Solution
    fps : float
        Frames per second of the result.

    Returns
    -------
    Solution
        The same motion in seconds, valid for ``at_fps(problem, fps)``: per-goal frame
        counts and first and last frames in the new frames; iterations (each solved
        frame's counted once), final distances and reasons as solved.
    """
    if fps == problem.fps:
        return solution
    src, out = solution.trajectory, at_fps(problem, fps)
    at, held, goal = [np.zeros(1)], [np.zeros(1, dtype=bool)], [np.zeros(1, dtype=int)]  # frame 0, home
    start = 0
    for g in solution.goals:
        hold = hold_frames(out, problem.goals[g.index]) if g.reached else 0
        moves = start + sample_times(g.frames, problem.fps, fps)
        start += g.frames
        at += [moves, np.full(hold, float(start))]
        held += [np.zeros(len(moves), dtype=bool), np.ones(hold, dtype=bool)]
        goal.append(np.full(len(moves) + hold, g.index))
        start += hold_frames(problem, problem.goals[g.index]) if g.reached else 0
    at, held, goal = np.concatenate(at), np.concatenate(held), np.concatenate(goal)
    phi, source = _interpolated(problem, src.phi, at)
    pose = forward(problem.arm, phi)
    distance = np.linalg.norm(pose.tip - np.array([g.position for g in problem.goals])[goal], axis=-1)
    spent = np.concatenate([[0], np.cumsum(src.iterations)])[np.floor(at).astype(int) + 1]
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
        mode=np.where(held, "ik", src.mode[source]),
        orientation_error=angle,
        tool_quaternion=quaternions,
    )
    moving = np.zeros(len(at), dtype=bool)
    moving[1:] = ~held[1:]
    return Solution(trajectory, tuple(_report(g, trajectory, moving) for g in solution.goals))


def _interpolated(problem: Problem, phi: np.ndarray, at: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(K, n) poses at the fractional frames ``at`` and (K,) the solved frame each one heads for."""
    if len(phi) == 1:
        return phi[np.zeros(len(at), dtype=int)], np.zeros(len(at), dtype=int)
    i = np.minimum(np.floor(at).astype(int), len(phi) - 2)
    a = at - i
    offset = phi[i + 1] - phi[i]
    offset = np.where(problem.limits.limited, offset, wrap_angle(offset))
    a = _safe_fractions(problem, phi[i], offset, a)
    out = phi[i] + a[:, None] * offset
    out = np.where(problem.limits.limited, out, wrap_angle(out))
    out[a == 0] = phi[i][a == 0]  # solved poses exactly as solved (frame 0 may be any home)
    out[a == 1] = phi[i + 1][a == 1]
    return out, np.where(a > 0, i + 1, i)


def _safe_fractions(problem: Problem, start: np.ndarray, offset: np.ndarray, a: np.ndarray) -> np.ndarray:
    """``a``, with each in-between fraction whose pose comes closer than ``solver.clearance`` to an
    obstacle moved to the nearer solved pose (0 or 1): the chord of that solved step cuts a
    curved surface, and the clearance is kept before the joint speed (that frame then turns
    by up to one solved step)."""
    between = np.nonzero((a > 0) & (a < 1))[0]
    if len(problem.obstacles) == 0 or len(between) == 0:
        return a
    d = min_link_clearance(forward(problem.arm, start[between] + a[between, None] * offset[between]),
                           problem.obstacles, problem.capsules)
    unsafe = between[d < problem.solver.clearance]
    a = a.copy()
    a[unsafe] = np.round(a[unsafe])
    return a


def _report(g: GoalReport, trajectory: Trajectory, moving: np.ndarray) -> GoalReport:
    """A goal's report with its frames counted in the resampled trajectory."""
    mine = np.nonzero(trajectory.goal == g.index)[0]
    planning = g.planning
    if planning is not None:
        planning = replace(planning, frames=int(np.sum(trajectory.mode[mine] == "plan")))
    return replace(
        g,
        frames=int(moving[mine].sum()),
        first_frame=int(mine[0]) if len(mine) else -1,
        last_frame=int(mine[-1]) if len(mine) else -1,
        planning=planning,
    )


__all__ = ["at_fps", "resample", "sample_times"]
