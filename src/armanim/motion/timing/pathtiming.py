"""Path goals on the clock: the tool's speed cap, and where the timed frames are on the path.

A path goal's frames along its path (mode ``path``) are timed from rest to rest as a part of
their own (:func:`armanim.motion.timing.retime.retime`), with the tool's speed along the path capped at
the goal's ``speed`` (:func:`part_path_speed`): the clock runs the tool at that speed where the
joints allow, slower where they cannot keep up, never faster. Once timed, every frame along the
path gets its arc length done and its distance from the path (:func:`traced_paths`), and each
path goal's report the largest distance at any frame and between frames (:func:`path_reported`).
Pure core: numpy only.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from typing import cast

import numpy as np

from armanim.arm.kinematics import forward
from armanim.motion.problem import Goal, Problem, joint_offset
from armanim.motion.solution import GoalReport, GoalTiming, Trajectory
from armanim.motion.timing.clock import Excess, Motion

ALONG = "path"
"""The mode of a frame along a path goal's path."""


def joined_timing(timings: list[GoalTiming]) -> GoalTiming:
    """One goal's timing from its parts' (in order): the durations added, the peaks the largest.

    >>> a, b = GoalTiming(1.0, 0.5, 0.9, 2, 1), GoalTiming(2.0, 0.8, 0.3, 0, 4)
    >>> joined_timing([a, b])
    GoalTiming(duration=3.0, peak_speed_ratio=0.8, peak_acceleration_ratio=0.9, speed_joint=0, acceleration_joint=1)
    """
    if len(timings) == 1:
        return timings[0]
    fastest = max(timings, key=lambda t: t.peak_speed_ratio)
    hardest = max(timings, key=lambda t: t.peak_acceleration_ratio)
    return GoalTiming(
        sum(t.duration for t in timings),
        fastest.peak_speed_ratio,
        hardest.peak_acceleration_ratio,
        fastest.speed_joint,
        hardest.acceleration_joint,
    )


def part_path_speed(problem: Problem, solved: Trajectory, goal: Goal, first: int, stop: int) -> np.ndarray:
    """(stop - first - 1,) the most ds/dt (radians of joint space per second) on each solved step
    of the part ``first:stop`` of ``solved`` along ``goal``'s path: the goal's speed times the
    step's joint-space length over the tool's travel along the path (inf where it does not travel)."""
    assert solved.path_s is not None
    poses = solved.phi[first:stop]
    length = np.linalg.norm(joint_offset(problem, poses[:-1], poses[1:]), axis=1)
    travel = np.diff(np.nan_to_num(solved.path_s[first:stop], nan=0.0))  # the part's first pose is the path's start
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(travel > 0, goal.speed * length / np.where(travel > 0, travel, 1.0), np.inf)


def tool_speed_excess(problem: Problem, goal: Goal, fps: float) -> Excess:
    """For a part along ``goal``'s path timed at ``fps``: the factor by which its frames (the start
    pose first) must slow for the tool to keep the goal's speed from frame to frame (1 when it does).
    The clock's cap on each solved step takes the tool's travel as even along the step; the smooth
    motion through the samples is not quite, and passes the speed by a few per cent on a curve."""

    def excess(frames: np.ndarray) -> float:
        travel = np.linalg.norm(np.diff(forward(problem.arm, frames).tip, axis=0), axis=1)
        return max(1.0, float(np.max(travel, initial=0.0)) * fps / goal.speed)

    return excess


def stray_frames(
    problem: Problem, solved: Trajectory, goal: Goal, first: int, stop: int
) -> Callable[[Motion], np.ndarray]:
    """For the part ``first:stop`` of ``solved`` along ``goal``'s path: a function of its timed motion
    giving (K,) bool, the frames whose tool, or the tool halfway (each joint) from the frame before,
    lies farther than ``solver.path_tolerance`` from the path between the frame's two samples (the
    clock's smooth path through the samples can bulge where a sample turns the joints much and
    moves the tool little)."""
    assert goal.path is not None and solved.path_s is not None
    path, along, start = goal.path, np.nan_to_num(solved.path_s[first:stop], nan=0.0), solved.phi[first]
    tolerance = problem.solver.path_tolerance

    def strays(motion: Motion) -> np.ndarray:
        heads = np.maximum(motion.heads_for, 1)
        lo, hi = along[heads - 1], along[heads]
        before = np.concatenate([start[None], motion.phi[:-1]])
        middle = before + joint_offset(problem, before, motion.phi) / 2
        tips = forward(problem.arm, np.concatenate([motion.phi, middle])).tip
        k = len(heads)
        _, error = path.nearest(tips, np.concatenate([lo, np.concatenate([lo[:1], lo[:-1]])]), np.concatenate([hi, hi]))
        return cast(np.ndarray, (error[:k] > tolerance) | (error[k:] > tolerance))

    return strays


def traced_paths(
    problem: Problem,
    solved: Trajectory,
    phi: np.ndarray,
    tip: np.ndarray,
    source: np.ndarray,
    goal: np.ndarray,
    held: np.ndarray,
) -> tuple[np.ndarray, np.ndarray] | None:
    """Per timed frame (F,): the arc length done along its goal's path and the tool's distance from
    it, on the frames along a path and the hold at its end (NaN elsewhere); None when no goal is a path.

    Parameters
    ----------
    solved : Trajectory
        The solved frames, with their ``path_s``.
    phi, tip : (F, n), (F, 3) arrays
        The timed frames and their tool points.
    source, goal, held : (F,) arrays
        The solved frame each timed frame heads for, its goal, and whether it is a hold.
    """
    if solved.path_s is None:
        return None
    along = ~np.isnan(solved.path_s[source]) & ((solved.modes[source] == ALONG) | held)
    done, error = np.full(len(phi), np.nan), np.full(len(phi), np.nan)
    for k in np.unique(goal[along]):
        mine = along & (goal == k)
        path = problem.goals[k].path
        assert path is not None
        lo, hi = _window(solved.path_s, source[mine])
        done[mine], error[mine] = path.nearest(tip[mine], lo, hi)
    return done, error


def _window(path_s: np.ndarray, heads_for: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The arc lengths between the solved frame before each of ``heads_for`` and it (a path's first
    frame's predecessor is its start)."""
    return np.nan_to_num(path_s[heads_for - 1], nan=0.0), path_s[heads_for]


def path_reported(problem: Problem, report: GoalReport, trajectory: Trajectory) -> GoalReport:
    """``report`` with its path's account measured on the timed ``trajectory``: the largest distance
    from the path at its frames along the path and at the midpoints between them (each joint
    halfway), and the mean tool speed over the time spent along the path."""
    if report.path is None or trajectory.path_s is None or trajectory.path_error is None:
        return report
    frames = np.nonzero((trajectory.goal == report.index) & (trajectory.mode == ALONG))[0]
    if not len(frames):
        return report
    path = problem.goals[report.index].path
    assert path is not None
    before = trajectory.phi[frames - 1]
    middle = before + joint_offset(problem, before, trajectory.phi[frames]) / 2
    lo = np.nan_to_num(trajectory.path_s[frames - 1], nan=0.0)
    _, between = path.nearest(forward(problem.arm, middle).tip, lo, trajectory.path_s[frames])
    worst = float(max(np.max(trajectory.path_error[frames]), np.max(between)))
    seconds = len(frames) / trajectory.fps
    return replace(report, path=replace(report.path, max_path_error=worst, mean_speed=report.path.done / seconds))


__all__ = [
    "ALONG",
    "joined_timing",
    "part_path_speed",
    "path_reported",
    "stray_frames",
    "tool_speed_excess",
    "traced_paths",
]
