"""A finished run's frames at another frame rate, for ``armanim render --fps`` / ``--quality``.

The motion is kept in seconds: the video at 60 fps of a run solved at 30 fps lasts as long as
the run, with twice the frames. Each new frame is taken at its time, k / fps, from the run's
frames by linear interpolation between the two around it (unlimited joints the short way
round); the run's last frame is always kept. What a frame says besides its pose (its goal,
``reached``, ``mode``) is the run's frame it heads for; the tip, the goal distance, the
clearance, the arm's own closest pair and the tool's orientation are computed for the new pose,
the joints' velocities interpolated as the poses are. Goal reports keep their
results, with their first and last frames counted in the new frames.

This only draws a run again; ``run --fps`` solves the scene anew (always at its own
``render.fps``) and puts that motion on the clock at the other rate.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from armanim.arm.geometry import wrap_angle
from armanim.arm.kinematics import forward
from armanim.motion.carry import world_clearance
from armanim.motion.orientation import frame_orientations
from armanim.motion.problem import Problem
from armanim.motion.solution import Solution, Trajectory
from armanim.motion.trajectory import with_self_clearance, with_world_self_clearance


def frame_times(duration: float, fps: float) -> np.ndarray:
    """(K,) seconds of the frames at ``fps`` over ``duration`` seconds: 0, 1/fps, ... and the
    end itself (so the last pose is shown even when the duration is not a whole number of frames).

    >>> frame_times(1.0, 4.0).tolist(), frame_times(0.5, 3.0).tolist()
    ([0.0, 0.25, 0.5, 0.75, 1.0], [0.0, 0.3333333333333333, 0.5])
    """
    whole = math.floor(duration * fps + 1e-9)
    times = np.arange(whole + 1) / fps
    return times if duration - times[-1] <= 1e-9 / fps else np.append(times, duration)


def resampled_frames(frames: int, fps_from: float, fps_to: float) -> int:
    """How many frames a run of ``frames`` frames at ``fps_from`` has at ``fps_to``.

    >>> resampled_frames(339, 30.0, 60.0), resampled_frames(339, 30.0, 15.0)
    (677, 170)
    """
    duration = (frames - 1) / fps_from
    whole = math.floor(duration * fps_to + 1e-9)
    return whole + 1 + (1 if duration - whole / fps_to > 1e-9 / fps_to else 0)


def interpolate_poses(
    problem: Problem, times: np.ndarray, phi: np.ndarray, at: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """(K, n) poses at the seconds ``at`` of a motion through ``phi`` (F, n) at ``times`` (F,),
    and (K,) the index of the frame each one heads for (the later of the two around it, or
    the frame itself when it falls on one).

    Linear in time between neighbouring frames; an unlimited joint turns the short way round.

    >>> from armanim.motion.problem import Limits
    >>> from types import SimpleNamespace
    >>> free = SimpleNamespace(limits=Limits.unlimited(1, margin=0.1))
    >>> phi = np.array([[3.0], [-3.0]])   # 0.28 rad apart the short way, across +-pi
    >>> poses, heads = interpolate_poses(free, np.array([0.0, 1.0]), phi, np.array([0.0, 0.5, 1.0]))
    >>> np.round(poses[:, 0], 4).tolist(), heads.tolist()
    ([3.0, 3.1416, -3.0], [0, 1, 1])
    """
    if len(phi) == 1:
        zero = np.zeros(len(at), dtype=int)
        return phi[zero], zero
    i = np.clip(np.searchsorted(times, at, side="right") - 1, 0, len(phi) - 2)
    span = times[i + 1] - times[i]
    a = np.clip(np.where(span > 0, (at - times[i]) / np.where(span > 0, span, 1.0), 1.0), 0.0, 1.0)
    offset = phi[i + 1] - phi[i]
    limited = problem.limits.limited
    offset = np.where(limited, offset, wrap_angle(offset))
    out = phi[i] + a[:, None] * offset
    out = np.where(limited, out, wrap_angle(out))
    out[a == 0] = phi[i][a == 0]  # the run's own poses exactly as they were
    out[a == 1] = phi[i + 1][a == 1]
    return out, np.where(a > 0, i + 1, i)


def resample_run(problem: Problem, solution: Solution, fps: float) -> Solution:
    """``solution``'s motion as frames at ``fps``, in the same seconds; itself when the rate is its own.

    Parameters
    ----------
    problem : Problem
        The run's problem (its arm, goals and obstacles).
    solution : Solution
        The run as read back from its folder (``solution.trajectory.fps`` is its rate).
    fps : float
        Frames per second of the result.
    """
    src = solution.trajectory
    if fps == src.fps:
        return solution
    times = src.time
    at = frame_times(float(times[-1]), fps)
    phi, head = interpolate_poses(problem, times, src.phi, at)
    pose = forward(problem.arm, phi)
    goal = src.goal[head]
    targets = np.array([g.position for g in problem.goals])
    angle, quaternions = frame_orientations(problem.arm, [g.orientation for g in problem.goals], phi, goal)
    trajectory = Trajectory(
        phi=phi,
        tip=pose.tip,
        goal=goal,
        distance=np.linalg.norm(pose.tip - targets[goal], axis=-1),
        clearance=world_clearance(problem, solution.carry, pose, goal, fps),
        reached=src.reached[head],
        iterations=np.where(np.diff(head, prepend=-1) > 0, src.iterations[head], 0),  # each run frame's counted once
        step_scale=src.step_scale[head],
        fps=fps,
        mode=src.modes[head],
        orientation_error=angle,
        tool_quaternion=quaternions,
        velocity=None if src.velocity is None else np.stack([np.interp(at, times, v) for v in src.velocity.T], axis=1),
    )
    if solution.carry is not None:
        trajectory = with_world_self_clearance(problem, solution.carry, trajectory, pose)
    else:
        trajectory = with_self_clearance(problem, trajectory)  # the pictures tint pairs near each other
    reports = []
    for g in solution.goals:
        mine = np.nonzero(goal == g.index)[0]
        reports.append(
            replace(g, first_frame=int(mine[0]) if len(mine) else -1, last_frame=int(mine[-1]) if len(mine) else -1)
        )
    return Solution(trajectory, tuple(reports), solution.rest_to_rest_duration, solution.carry)


__all__ = ["frame_times", "interpolate_poses", "resample_run", "resampled_frames"]
