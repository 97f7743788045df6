"""What a solved run is: the trajectory's arrays and one report per goal (pure data).

Made by the frame loop (:mod:`armanim.motion.trajectory`), read by the outputs and the renderer.
"""

from __future__ import annotations

from dataclasses import dataclass, fields, replace
from typing import TYPE_CHECKING

import numpy as np

from armanim.arm.geometry import wrap_angle
from armanim.names import MissReason, PathCause, PathSource

if TYPE_CHECKING:
    from armanim.motion.carry import CarryReport

MISS_REASONS: dict[MissReason, str] = {
    "out_of_reach": "out of reach: no pose of this arm puts the tip there, whatever the limits and obstacles",
    "no_free_pose": "no pose inside the limits and 1.1 x solver.clearance (what the filter keeps) away from every obstacle, with every enabled pair of the arm's own links self_clearance apart, puts the tip there",
    "no_path": "no path to a free pose at the goal was found within the planning budget",
    "blocked_by_obstacle": "blocked by an obstacle",
    "blocked_by_limit": "blocked by a joint limit",
    "stalled": "stalled at a local minimum",
    "too_slow": "still moving when max_frames_per_goal ran out",
    "numerical": "the solver produced NaN or infinity; the arm held its last safe pose",
    "orientation_unreachable": "the tip reached the position, but no pose of this arm turns the tool to the goal's orientation there; the angle left is reported",
    "path_blocked": "the tool stopped short of the path's end, at the last point it could follow the path within solver.path_tolerance; the cause, the fraction done and that point are reported",
}

PATH_CAUSES: dict[PathCause, str] = {
    "out_of_reach": "the path leaves the arm's reach",
    "joint_limit": "a joint would have to pass its limit to go on",
    "obstacle": "an obstacle is in the way (the filter keeps solver.clearance)",
    "self_collision": "the arm's own links would come closer than solver.self_clearance",
    "singular": "the arm is at a singular pose and cannot move the tool along the path",
    "jump": "the next point of the path needs a joint to turn more than solver.max_joint_step at once (another branch of the arm's poses)",
    "orientation": "the arm cannot hold the tool's orientation there",
}


@dataclass(frozen=True)
class PathReport:
    """How far a path goal's tool followed its path.

    Attributes
    ----------
    length : float
        The path's whole arc length, scene units.
    done : float
        Arc length followed, scene units (``length`` when the whole path was followed).
    max_path_error : float
        The tool's greatest distance from the path at any frame and between frames (at every
        step's midpoint), scene units; NaN before the path was started.
    mean_speed : float
        Arc length followed over the seconds it took on the clock (scene units per second; 0
        before the solution is retimed or when nothing was followed).
    stop_point : (3,) array or None
        Where the tool stopped short of the end; None when it followed the whole path.
    cause : PathCause or None
        Why it stopped there (explained by :data:`PATH_CAUSES`); None when it did not.
    """

    length: float
    done: float
    max_path_error: float
    mean_speed: float = 0.0
    stop_point: np.ndarray | None = None
    cause: PathCause | None = None

    @property
    def fraction(self) -> float:
        """The share of the path followed, 0..1."""
        return self.done / self.length if self.length > 0 else 1.0

    @property
    def cause_text(self) -> str | None:
        """What :data:`PATH_CAUSES` says of ``cause`` (None without one)."""
        return PATH_CAUSES[self.cause] if self.cause else None


BLEND_REASONS = {
    "last": "the last goal ends at rest",
    "hold": "a goal with hold ends at rest",
    "missed": "a missed goal ends at rest",
    "next_path": "the next goal is a path goal whose path starts here, at rest",
    "next_still": "the next goal needs no motion: the arm rests here",
    "radius": "the frames could not pass within the radius without stopping",
    "slower": "passing it without stopping took longer than stopping at it",
}
"""Why a goal with ``blend`` ends at rest after all (summary.json's ``blend_reason``)."""


@dataclass(frozen=True)
class BlendReport:
    """How a goal with ``blend`` was passed.

    Attributes
    ----------
    radius : float
        The goal's blend radius (scene units; radians for a joint goal).
    blended : bool
        Whether the arm passed it without stopping.
    reason : str or None
        Why not (a key of :data:`BLEND_REASONS`), None when it did.
    corner : str or None
        ``"curve"``: the corner at the goal's solved pose was replaced by a certified curve that passes
        within the radius (:mod:`armanim.motion.timing.smoothing`); ``"through"``: the path passes the goal's
        solved pose itself (radius 0, no certified curve, or a curve slower than the corner); None
        when not blended.
    pass_distance : float
        The least distance of a frame from the goal (the tool's, scene units; a joint goal's: the
        largest joint offset, radians).
    pass_speed : float
        The tool's speed at that frame (scene units per second; a joint goal's: the fastest joint's,
        radians per second); 0 at rest.
    joint : bool
        Whether the goal is a joint goal (its radius, distance and speed in radians).
    by_kind : KindPass or None
        A joint goal on an arm with a prismatic joint: ``pass_distance`` and ``pass_speed`` split
        into its revolute joints' (radians) and its prismatic joints' (metres); None otherwise.
    """

    radius: float
    blended: bool
    reason: str | None
    corner: str | None
    pass_distance: float
    pass_speed: float
    joint: bool = False
    by_kind: KindPass | None = None


@dataclass(frozen=True)
class KindPass:
    """How a joint goal was passed, each joint kind in its own unit: the largest offset from the
    goal and the fastest speed at the pass frame of the revolute joints (radians, rad/s; 0 for
    none) and of the prismatic joints (metres, m/s). :attr:`BlendReport.pass_distance` and
    :attr:`BlendReport.pass_speed` are the larger of each pair (the blend radius is one number
    for every joint: its radians are a rail's metres)."""

    turn_distance: float
    turn_speed: float
    slide_distance: float
    slide_speed: float


@dataclass(frozen=True)
class GoalReport:
    """How one goal went.

    Attributes
    ----------
    index : int
        0-based index into the scene's goals.
    position : (3,) array
    reached : bool
    reason : MissReason or None
        For a missed goal, why (explained by :data:`MISS_REASONS`).
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
    planning : PlanningReport or None
        What the planner did for this goal; None if it never planned.
    final_orientation_error : float or None
        Radians: the angle from the tool frame to the goal's orientation (or of the tool's z to
        its tool axis) when the goal was left; None for a position-only goal.
    timing : GoalTiming or None
        The clock's account of the goal's motion; None before the solution is retimed.
    path : PathReport or None
        A path goal's account of its path; None for a point goal.
    blend : BlendReport or None
        How a goal with ``blend`` was passed (:mod:`armanim.motion.timing.blend`); None for one without.
    """

    index: int
    position: np.ndarray
    reached: bool
    reason: MissReason | None
    frames: int
    first_frame: int
    last_frame: int
    final_distance: float
    iterations: int
    newton_iterations: int = 0
    planning: PlanningReport | None = None
    final_orientation_error: float | None = None
    timing: GoalTiming | None = None
    path: PathReport | None = None
    blend: BlendReport | None = None

    @property
    def reason_text(self) -> str | None:
        """What :data:`MISS_REASONS` says of ``reason`` (None for a reached goal)."""
        return MISS_REASONS[self.reason] if self.reason else None

    @property
    def planned(self) -> bool:
        """Whether the planner ran for this goal."""
        return self.planning is not None


@dataclass(frozen=True)
class GoalTiming:
    """How long a goal's motion took on the clock, and how near its limits it came.

    Attributes
    ----------
    duration : float
        Seconds from rest to rest (holds not counted).
    peak_speed_ratio, peak_acceleration_ratio : float
        The largest of any joint's frame-to-frame speed (first differences over 1/fps) and
        acceleration (second differences over 1/fps^2, at rest before and after) over its
        limit: at most 1. 0 for a goal the arm did not move toward.
    speed_joint, acceleration_joint : int or None
        0-based index of the joint with that peak (None when the arm did not move).
    """

    duration: float
    peak_speed_ratio: float
    peak_acceleration_ratio: float
    speed_joint: int | None
    acceleration_joint: int | None


@dataclass(frozen=True)
class PlanningReport:
    """What the planner did for one goal (deterministic: no wall-clock times).

    Attributes
    ----------
    plans : int
        Times it planned (the goal stalled that often).
    poses : int
        Free goal poses the last plan found.
    path : PathSource
        How the last plan connected: ``"straight"``, ``"rrt_connect"`` or ``"none"``.
    frames : int
        Frames spent following planned paths (mode ``plan``).
    checks : int
        Poses checked for collisions while searching paths, over all plans.
    self_pair : str or None
        When the last plan found no free pose because of the arm's own pair: that pair, ``a|b``.
    """

    plans: int = 0
    poses: int = 0
    path: PathSource = "none"
    frames: int = 0
    checks: int = 0
    self_pair: str | None = None


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
        |step taken| / |step proposed| (0 on frame 0 and holds).
    fps : float
    mode : (F,) array of str
        ``"ik"`` where the method stepped (and on frame 0 and holds), ``"plan"`` where the
        arm followed a planned path, ``"path"`` where a path goal's tool followed its path.
    orientation_error : (F,) array or None
        Radians from the tool frame to the frame's goal orientation, NaN where that goal has
        none; None: no goal of the run has one.
    tool_quaternion : (F, 4) array or None
        The tool frame's world rotation as a unit quaternion (w, x, y, z), w >= 0; None where
        not computed.
    velocity : (F, n) array or None
        Each joint's speed at the frame on the clock, rad/s (0 at rest); None for a solution
        not yet retimed (the solver's own frames).
    self_clearance : (F,) array or None
        The least gap of any enabled pair of the arm's own capsules; None without enabled pairs.
    self_pair : (F,) array of str or None
        That pair's links, ``a|b``; None without enabled pairs.
    path_s : (F,) array or None
        On a path goal's frames of mode ``path`` and the hold at the path's end, the arc length of
        the path done (scene units), NaN elsewhere; None: no goal of the run is a path.
    path_error : (F,) array or None
        On those frames, the tool's distance from the path (scene units; ``distance`` there too),
        NaN elsewhere.
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
    mode: np.ndarray | None = None
    orientation_error: np.ndarray | None = None
    tool_quaternion: np.ndarray | None = None
    velocity: np.ndarray | None = None
    self_clearance: np.ndarray | None = None
    self_pair: np.ndarray | None = None
    path_s: np.ndarray | None = None
    path_error: np.ndarray | None = None

    def __post_init__(self) -> None:
        if self.mode is None:
            object.__setattr__(self, "mode", np.full(len(self.phi), "ik"))

    @property
    def modes(self) -> np.ndarray:
        """(F,) :attr:`mode`, which construction fills (all ``"ik"`` where none was given)."""
        assert self.mode is not None, "filled by __post_init__"
        return self.mode

    @property
    def frames(self) -> int:
        """Number of frames F."""
        return len(self.phi)

    @property
    def time(self) -> np.ndarray:
        """(F,) seconds: frame / fps."""
        return np.arange(self.frames) / self.fps

    def at_frames(self, index: np.ndarray) -> Trajectory:
        """The trajectory of the frames ``index`` (K,) only, in that order: every per-frame array
        indexed alike, ``fps`` kept (a decimated trajectory's frames are no longer 1/fps apart)."""
        index = np.asarray(index, dtype=np.intp)
        per_frame = {
            f.name: value[index]
            for f in fields(self)
            if isinstance(value := getattr(self, f.name), np.ndarray) and len(value) == self.frames
        }
        return replace(self, **per_frame)


@dataclass(frozen=True)
class Solution:
    """A solved run: the trajectory and one report per goal."""

    trajectory: Trajectory
    goals: tuple[GoalReport, ...]
    rest_to_rest_duration: float | None = None
    """With ``blend``: the run's seconds had every goal been reached at rest (the same solved path
    timed goal by goal); None without."""
    carry: CarryReport | None = None
    """With goals that grasp or release (:mod:`armanim.motion.carry`): the world each goal was
    solved in and the world after the last; None without."""

    @property
    def reached(self) -> int:
        """Number of goals reached."""
        return sum(g.reached for g in self.goals)


def max_joint_step(phi: np.ndarray) -> float:
    """Largest per-frame turn of any joint (radians), wrap-aware."""
    if len(phi) < 2:
        return 0.0
    return float(np.max(np.abs(wrap_angle(np.diff(phi, axis=0)))))
