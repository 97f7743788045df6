"""THE frame loop: the arm visits the goals in turn, one solver step per frame.

Frame 0 is the home pose. For each goal the loop steps until |e - g| < tolerance,
then holds the pose for the goal's hold frames; a goal not reached within
``max_frames_per_goal`` is reported missed with a reason and the loop moves on.
Not converging is a result (a :class:`GoalReport`), never an exception.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from armanim.geometry import wrap_angle
from armanim.problem import Problem
from armanim.solvers import ArmState, arm_state, step_function
from armanim.solvers.barrier import shorten_step

STALL_WINDOW = 30  # frames over which a missed goal's progress is judged

MISS_REASONS = {
    "out_of_reach": "out of reach: the goal is farther from the base than the arm's length",
    "blocked_by_obstacle": "blocked by an obstacle",
    "blocked_by_limit": "blocked by a joint limit",
    "stalled": "stalled at a local minimum",
    "too_slow": "still moving when max_frames_per_goal ran out",
    "numerical": "the solver produced NaN or infinity; the arm held its last safe pose",
}


@dataclass(frozen=True)
class GoalReport:
    """How one goal went.

    Attributes
    ----------
    index : int
        0-based index into the scene's goals.
    position : (3,) array
    reached : bool
    reason : str or None
        For a missed goal, a key of :data:`MISS_REASONS`.
    frames : int
        Solver frames spent moving toward this goal (holds not counted).
    first_frame, last_frame : int
        Frame range of this goal in the trajectory, holds included (-1 if none).
    final_distance : float
        |e - g| when the goal was left.
    iterations : int
        Inner solver iterations summed over its frames.
    newton_iterations : int
        Of those, Newton iterations (``newton`` only).
    """

    index: int
    position: np.ndarray
    reached: bool
    reason: str | None
    frames: int
    first_frame: int
    last_frame: int
    final_distance: float
    iterations: int
    newton_iterations: int = 0


@dataclass(frozen=True)
class Trajectory:
    """Every frame of a run, as arrays (radians inside).

    Attributes
    ----------
    phi : (F, n) array
    tip : (F, 3) array
    goal : (F,) int array
    distance : (F,) array
        |e - g| to the frame's goal.
    clearance : (F,) array
        Smallest link-capsule clearance to any obstacle (+inf without obstacles).
    reached : (F,) bool array
        The frame's goal is within tolerance.
    iterations : (F,) int array
    step_scale : (F,) array
        Fraction of the proposed step the barrier let through (0 on frame 0 and holds).
    fps : float
    """

    phi: np.ndarray
    tip: np.ndarray
    goal: np.ndarray
    distance: np.ndarray
    clearance: np.ndarray
    reached: np.ndarray
    iterations: np.ndarray
    step_scale: np.ndarray
    fps: float

    @property
    def frames(self) -> int:
        """Number of frames F."""
        return len(self.phi)

    @property
    def time(self) -> np.ndarray:
        """(F,) seconds: frame / fps."""
        return np.arange(self.frames) / self.fps


@dataclass(frozen=True)
class Solution:
    """A solved run: the trajectory and one report per goal."""

    trajectory: Trajectory
    goals: tuple[GoalReport, ...]

    @property
    def reached(self) -> int:
        """Number of goals reached."""
        return sum(g.reached for g in self.goals)


@dataclass
class _Recorder:
    """Rows of the trajectory as the loop produces them."""

    phi: list = field(default_factory=list)
    tip: list = field(default_factory=list)
    clearance: list = field(default_factory=list)
    goal: list = field(default_factory=list)
    distance: list = field(default_factory=list)
    iterations: list = field(default_factory=list)
    step_scale: list = field(default_factory=list)

    def add(self, state: ArmState, goal, distance, iterations=0, step_scale=0.0):
        self.phi.append(state.phi)
        self.tip.append(state.tip)
        self.clearance.append(state.min_clearance)  # the barrier computed it for this very pose
        self.goal.append(goal)
        self.distance.append(distance)
        self.iterations.append(iterations)
        self.step_scale.append(step_scale)

    def __len__(self) -> int:
        return len(self.phi)


def frame_budget(problem: Problem) -> int:
    """Most frames a run can have: frame 0, every goal's frame cap and its hold."""
    return 1 + sum(problem.solver.max_frames_per_goal + g.hold_frames for g in problem.goals)


def solve_trajectory(problem: Problem, progress: Callable[[int, int], None] | None = None) -> Solution:
    """Run the frame loop over every goal.

    Parameters
    ----------
    problem : Problem
    progress : callable, optional
        Called after every frame with the frames produced so far and the most the
        run can still have in all (that bound shrinks as goals are reached early, and
        equals the frame count at the end).

    Returns
    -------
    Solution
    """
    s = problem.solver
    step = step_function(s.method)
    rec = _Recorder()
    state = arm_state(problem, problem.home)
    first_goal = problem.goals[0].position
    rec.add(state, 0, float(np.linalg.norm(state.tip - first_goal)))
    reports = []
    later = frame_budget(problem) - 1  # frames the goals not yet started may still add
    for k, goal in enumerate(problem.goals):
        later -= s.max_frames_per_goal + goal.hold_frames
        target = goal.position
        first = len(rec) if k else 0
        frames = iterations = newton_its = 0
        blocked: list[str | None] = []
        distances = [float(np.linalg.norm(state.tip - target))]
        while distances[-1] >= s.tolerance and frames < s.max_frames_per_goal:
            proposal = step(problem, state, target)
            moved = shorten_step(problem, state, proposal.dphi)
            state = moved.state
            distances.append(float(np.linalg.norm(state.tip - target)))
            blocked.append(moved.blocked_by)
            frames += 1
            iterations += proposal.iterations
            newton_its += proposal.newton_iterations
            rec.add(state, k, distances[-1], proposal.iterations, moved.scale)
            if progress:
                progress(len(rec), len(rec) + s.max_frames_per_goal - frames + goal.hold_frames + later)
        reached = distances[-1] < s.tolerance
        if reached:
            for _ in range(goal.hold_frames):
                rec.add(state, k, distances[-1])
        if progress:
            progress(len(rec), len(rec) + later)
        reports.append(
            GoalReport(
                index=k,
                position=target,
                reached=reached,
                reason=None if reached else miss_reason(problem, state, target, distances, blocked),
                frames=frames,
                first_frame=first if len(rec) > first else -1,
                last_frame=len(rec) - 1 if len(rec) > first else -1,
                final_distance=distances[-1],
                iterations=iterations,
                newton_iterations=newton_its,
            )
        )
    return Solution(trajectory=_finish(problem, rec), goals=tuple(reports))


def _finish(problem: Problem, rec: _Recorder) -> Trajectory:
    distance = np.array(rec.distance)
    return Trajectory(
        phi=np.array(rec.phi),
        tip=np.array(rec.tip),
        goal=np.array(rec.goal, dtype=int),
        distance=distance,
        clearance=np.array(rec.clearance),
        reached=distance < problem.solver.tolerance,
        iterations=np.array(rec.iterations, dtype=int),
        step_scale=np.array(rec.step_scale),
        fps=problem.fps,
    )


def miss_reason(
    problem: Problem, state: ArmState, goal: np.ndarray, distances: list[float], blocked: list[str | None]
) -> str:
    """Why a goal was missed: a key of :data:`MISS_REASONS`.

    Judged in order: out of reach; NaN proposals; then, if the last
    ``STALL_WINDOW`` frames made less progress than the tolerance, an obstacle or a
    limit that shortened those steps or whose barrier is active, else a local minimum;
    otherwise the arm was still moving.
    """
    arm = problem.arm
    if np.linalg.norm(goal - arm.base) > arm.reach + problem.solver.tolerance:
        return "out_of_reach"
    recent = blocked[-STALL_WINDOW:]
    if recent and recent.count("nan") > len(recent) // 2:
        return "numerical"
    window = distances[-STALL_WINDOW - 1 :]
    if window[0] - window[-1] >= problem.solver.tolerance:
        return "too_slow"
    if "obstacle" in recent or _near_obstacle(problem, state):
        return "blocked_by_obstacle"
    if "limit" in recent or _near_limit(problem, state.phi):
        return "blocked_by_limit"
    return "stalled"


def _near_obstacle(problem: Problem, state: ArmState) -> bool:
    cl = state.clearance
    return cl is not None and bool(np.any(cl.d <= problem.obstacles.influence))


def _near_limit(problem: Problem, phi: np.ndarray) -> bool:
    lim = problem.limits
    gaps = np.minimum(phi - lim.lower, lim.upper - phi)
    return bool(np.any(gaps < lim.margin))


def max_joint_step(phi: np.ndarray) -> float:
    """Largest per-frame turn of any joint (radians), wrap-aware."""
    if len(phi) < 2:
        return 0.0
    return float(np.max(np.abs(wrap_angle(np.diff(phi, axis=0)))))
