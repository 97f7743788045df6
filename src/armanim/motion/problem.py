"""The solver's view of a scene: radians, numpy arrays, every default resolved.

Built from a validated scene by :func:`armanim.scene.scene_to_problem` (the one place
where degrees become radians). No field has a default: defaults are written once, in the
scene model, and :mod:`armanim.scene.convert` builds default settings through it. Pure
core: no I/O.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING, cast

import numpy as np

from armanim.arm.capsules import Capsules, joint_capsules
from armanim.arm.capsules import lever_arms as capsule_lever_arms
from armanim.arm.geometry import wrap_angle
from armanim.arm.gripper import Gripper
from armanim.arm.kinematics import Arm
from armanim.motion.orientation import Orientation
from armanim.motion.toolpath import ToolPath
from armanim.motion.tunables import DEFAULTS, Tunables
from armanim.names import JacobianMode, MethodName, PlannerMode
from armanim.world.obstacles import Obstacles
from armanim.world.selfdistances import SelfPairs

if TYPE_CHECKING:
    from armanim.motion.kernels.layout import KernelProblem
    from armanim.motion.kernels.plan import CompiledPlan


@dataclass(frozen=True)
class Limits:
    """Joint limits in radians; unlimited joints have -inf / +inf.

    Attributes
    ----------
    lower, upper : (n,) arrays
    margin : float
        delta of the limit barrier L, radians.
    """

    lower: np.ndarray
    upper: np.ndarray
    margin: float

    @classmethod
    def unlimited(cls, n: int, margin: float) -> Limits:
        """Limits for an arm whose joints all turn freely (``margin`` in radians)."""
        return cls(np.full(n, -np.inf), np.full(n, np.inf), margin)

    @property
    def limited(self) -> np.ndarray:
        """(n,) bool: joints that have limits."""
        limited: np.ndarray = np.isfinite(self.lower)
        return limited

    def notes(self, phi: np.ndarray) -> list[str]:
        """One line per joint of the pose ``phi`` (radians) outside its limits.

        >>> Limits(np.radians([-90.0, -90.0]), np.radians([90.0, 90.0]), 0.1).notes(np.radians([0.0, 120.0]))
        ['joint 2 at 120 deg is outside its limits [-90, 90]']
        """
        outside = self.limited & ((phi < self.lower) | (phi > self.upper))
        return [
            f"joint {i + 1} at {np.degrees(phi[i]):.6g} deg is outside its limits "
            f"[{np.degrees(self.lower[i]):g}, {np.degrees(self.upper[i]):g}]"
            for i in np.nonzero(outside)[0]
        ]


@dataclass(frozen=True)
class Goal:
    """A goal position, the tool's orientation there if the goal sets one, and how long to stay
    once it is reached.

    Attributes
    ----------
    position : (3,) array
    hold : float
        Seconds (turned into frames at the run's fps by :func:`frames_in`, the one rule
        for it: the frame loop's holds and the scene's frame budget both use it).
    orientation : Orientation or None
        A full rotation or a tool axis (:mod:`armanim.motion.orientation`); None: position only.
        A path goal holds it along the whole path.
    path : ToolPath or None
        A path goal's path (:mod:`armanim.motion.toolpath`): the arm goes to its start
        (``position``) as to any goal, then the tool follows it; None: a point goal.
    speed : float
        A path goal's tool speed along its path, scene units per second (0 for a point goal).
    joints : (n,) array or None
        A joint goal's pose (radians; metres for a prismatic joint): the arm plans its way there
        and ends on it exactly; ``position`` is then its tool point, for reports and pictures.
        None: a point or path goal.
    blend : float or None
        Pass within this of the goal without stopping (:mod:`armanim.motion.timing.blend`): scene units,
        or radians in every joint for a joint goal; 0 passes through it. None: stop at it.
    grasp : int or None
        The clearance column of the named obstacle the tool takes once this goal is reached
        (:mod:`armanim.motion.carry`); None: none.
    release : bool
        Put down what the tool holds once this goal is reached.
    touch_links : tuple of str or None
        The links allowed to touch the object this goal grasps; None: those the last joint carries.
    retreat : bool
        This goal is the scene goal before it's ``retreat``: the straight line out of it, a path
        goal the scene does not list (:func:`armanim.scene.convert.with_retreats`).
    to_approach : bool
        This goal is the way to the start of the next goal's ``approach`` (a release's: the
        object may touch what it is put on only along the line, :mod:`armanim.motion.carry`), a
        point or pose goal the scene does not list (:func:`armanim.scene.convert.with_retreats`).
    """

    position: np.ndarray
    hold: float
    orientation: Orientation | None = None
    path: ToolPath | None = None
    speed: float = 0.0
    joints: np.ndarray | None = None
    blend: float | None = None
    grasp: int | None = None
    release: bool = False
    touch_links: tuple[str, ...] | None = None
    retreat: bool = False
    to_approach: bool = False


def joint_offset(problem: Problem, phi: np.ndarray, target: np.ndarray) -> np.ndarray:
    """target - phi (radians, (..., n)), unlimited joints the short way round.

    >>> from types import SimpleNamespace
    >>> p = SimpleNamespace(limits=SimpleNamespace(limited=np.array([True, False])))
    >>> np.round(joint_offset(p, np.array([3.0, 3.0]), np.array([-3.0, -3.0])), 4).tolist()
    [-6.0, 0.2832]
    """
    offset = target - phi
    return np.where(problem.limits.limited, offset, wrap_angle(offset))


def frames_in(seconds: float, fps: float) -> int:
    """Whole frames in ``seconds`` at ``fps``, rounded to the nearest.

    >>> frames_in(2.0, 40.0), frames_in(0.5, 25.0)
    (80, 12)
    """
    return int(round(seconds * fps))  # noqa: RUF046 (numpy < 2 rounds to a float)


LINK_ACCELERATION_PER_SPEED = 4.0
"""1/s: a link arm's default ``max_joint_acceleration`` is its speed times this (full speed in a
quarter of a second); a URDF arm's comes from its robot (``robot.yaml``) or the scene."""


@dataclass(frozen=True)
class RateLimits:
    """How fast each joint may move: the clock's limits (radians and seconds).

    Attributes
    ----------
    speed : (n,) array
        rad/s, each joint's ``max_joint_speed``.
    acceleration : (n,) array
        rad/s^2, each joint's ``max_joint_acceleration``.
    jerk : (n,) array or None
        rad/s^3, each joint's ``max_joint_jerk``; None: the clock bounds speed and
        acceleration only.
    """

    speed: np.ndarray
    acceleration: np.ndarray
    jerk: np.ndarray | None = None


def link_arm_rates(n: int, max_joint_step: float, fps: float) -> RateLimits:
    """A link arm's default limits: ``max_joint_step`` (radians per frame) at ``fps`` as a speed,
    and :data:`LINK_ACCELERATION_PER_SPEED` times that as an acceleration.

    >>> r = link_arm_rates(2, np.radians(10.0), 30.0)
    >>> np.degrees(r.speed).round(6).tolist(), np.degrees(r.acceleration).round(6).tolist(), r.jerk
    ([300.0, 300.0], [1200.0, 1200.0], None)
    """
    speed = np.full(n, max_joint_step * fps)
    return RateLimits(speed, LINK_ACCELERATION_PER_SPEED * speed)


@dataclass(frozen=True)
class SolverSettings:
    """Every number of the solvers, from the scene's ``solver`` section (radians).

    The names are the scene's (``solver.max_step`` is ``max_step``, ``weights.goal`` is
    ``w_goal``) except ``beta``, the scene's ``solver.step``: a step is what a method
    proposes, a change of the joint angles.

    Attributes
    ----------
    method : MethodName
    beta : float
        The frame's task-space target is e + beta (g - e) (``gradient``: the descent rate).
    max_step : float
        Cap on the tip's travel per frame, |beta (g - e)|; inf for none.
    max_joint_step : float
        Radians any joint may turn in one frame.
    max_slide_step : float
        Metres any prismatic joint may slide in one frame (:func:`step_caps`).
    clearance : float
        d_safe, resolved (``arm.width / 10`` when the scene leaves it out).
    orientation_weight : float
        w, length per radian: the pose task is [p_g - p ; w r] (resolved: the arm's reach / 4
        when the scene leaves it out).
    orientation_tolerance : float
        Radians: a goal with an orientation is reached when its angle is below this too.
    joint_tolerance : float
        Radians: a joint goal is reached when every joint is within this of it.
    path_tolerance : float
        The most a path goal's tool may stray from its path, at every frame and between frames
        (scene units).
    """

    method: MethodName
    beta: float
    max_step: float
    tolerance: float
    max_frames_per_goal: int
    jacobian: JacobianMode
    damping: float
    max_joint_step: float
    clearance: float
    planner: PlannerMode
    w_goal: float
    w_obstacles: float
    w_limits: float
    w_target: float
    w_regularizer: float
    orientation_weight: float
    orientation_tolerance: float
    joint_tolerance: float
    path_tolerance: float
    max_slide_step: float = 0.05


def step_caps(problem: Problem) -> float | np.ndarray:
    """The most each joint may move in one frame: ``solver.max_joint_step`` (radians), a prismatic
    joint's ``solver.max_slide_step`` (metres), (n,); the one number for an arm of revolute joints."""
    if problem.arm.prismatic is None:
        return problem.solver.max_joint_step
    return np.where(problem.arm.prismatic, problem.solver.max_slide_step, problem.solver.max_joint_step)


@dataclass(frozen=True)
class Problem:
    """Everything the frame loop needs, in radians and numpy arrays.

    Attributes
    ----------
    arm : Arm
    half_width : float
        Half the scene's ``arm.width``: how thick the renderer draws joints and the base,
        and the radius of today's joint-to-joint capsules.
    home : (n,) array
        Frame 0's joint angles.
    limits : Limits
    obstacles : Obstacles
    goals : tuple of Goal
    solver : SolverSettings
    fps : float
        Frames per second of the frames the problem describes: the scene's own ``render.fps``
        while the motion is solved (the one owner of time: ``time_s``, holds, the stall window),
        the output rate (``--fps``) once the solution is on the clock
        (:func:`armanim.motion.timing.retime.at_fps`).
    capsules : Capsules
        The arm's collision capsules, which every guarantee is about. Left out (None), they
        are today's: one per link from joint to joint, of radius ``half_width``.
    rates : RateLimits
        Each joint's speed, acceleration (and jerk) limits, which the clock keeps. Left out
        (None): :func:`link_arm_rates` of ``solver.max_joint_step`` at ``fps``.
    self_pairs : SelfPairs
        The pairs of those capsules kept ``self_pairs.clearance`` apart (the enabled pairs of
        the allowed-collision matrix). Left out (None): none (``arm.self_collision: off``).
    tunables : Tunables
        The safety filter's gains and the stall test's and planner's tunables
        (:mod:`armanim.motion.tunables`); left out, their documented defaults.
    gripper : Gripper or None
        The robot's fingers (:mod:`armanim.arm.gripper`), which open before a grasp and close on
        the object; None: none (a grasped object simply attaches).
    """

    arm: Arm
    half_width: float
    home: np.ndarray
    limits: Limits
    obstacles: Obstacles
    goals: tuple[Goal, ...]
    solver: SolverSettings
    fps: float
    capsules: Capsules = cast(Capsules, None)  # None: joint_capsules(arm, half_width), filled by __post_init__
    rates: RateLimits = cast(RateLimits, None)  # None: link_arm_rates(n, max_joint_step, fps)
    self_pairs: SelfPairs = cast(SelfPairs, None)  # None: SelfPairs.none()
    tunables: Tunables = DEFAULTS
    gripper: Gripper | None = None
    _lever_arms: np.ndarray = field(init=False, repr=False, compare=False)  # set by __post_init__
    _pair_lever_rows: np.ndarray = field(init=False, repr=False, compare=False)
    _pair_levers: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if self.capsules is None:
            object.__setattr__(self, "capsules", joint_capsules(self.arm, self.half_width))
        if self.rates is None:
            object.__setattr__(self, "rates", link_arm_rates(len(self.home), self.solver.max_joint_step, self.fps))
        if self.self_pairs is None:
            object.__setattr__(self, "self_pairs", SelfPairs.none())
        object.__setattr__(self, "_lever_arms", capsule_lever_arms(self.arm, self.capsules))  # asked for every frame
        rows = pair_lever_rows(self.self_pairs, self.capsules, self._lever_arms)
        object.__setattr__(self, "_pair_lever_rows", rows)
        object.__setattr__(self, "_pair_levers", np.sqrt((rows**2).sum(axis=1)))

    @property
    def lever_arms(self) -> np.ndarray:
        """(n,) lever arm of each joint, scene units: the farthest any point of the capsules
        it moves lies from joint j (:func:`armanim.arm.capsules.lever_arms`, computed once)."""
        return self._lever_arms

    @property
    def pair_lever_rows(self) -> np.ndarray:
        """(P, n) each enabled pair's lever arms (:func:`pair_lever_rows`, computed once)."""
        return self._pair_lever_rows

    @property
    def pair_levers(self) -> np.ndarray:
        """(P,) the 2-norm of each enabled pair's lever arms: a step dPhi changes the pair's gap by
        at most |dPhi| times this (computed once)."""
        return self._pair_levers

    @cached_property
    def kernel(self) -> KernelProblem:
        """The problem as the compiled kernels read it (:func:`armanim.motion.kernels.layout.kernel_problem`),
        made at its first use, once per problem (a problem never changes: ``dataclasses.replace``
        makes another, with its own)."""
        from armanim.motion.kernels.layout import kernel_problem

        return kernel_problem(self)

    @cached_property
    def compiled_plans(self) -> dict[tuple[str, str | None, int], CompiledPlan | None]:
        """Whether and how each loop's steps run compiled, per method and kind of goal, as they are
        judged (:func:`armanim.motion.kernels.plan.compiled_plan`)."""
        return {}


def pair_lever_rows(pairs: SelfPairs, capsules: Capsules, lever_arms: np.ndarray) -> np.ndarray:
    """(P, n) each enabled pair's lever arms: joint j's (``lever_arms`` (n,)) where it lies between
    the pair's two capsules' joints, else 0 (the joints up to the first move both alike): a change
    dPhi moves the pair's gap by at most |dPhi| . row."""
    link = capsules.link
    lo, hi = np.minimum(link[pairs.first], link[pairs.second]), np.maximum(link[pairs.first], link[pairs.second])
    joint = np.arange(len(lever_arms))
    return np.where((joint > lo[:, None]) & (joint <= hi[:, None]), lever_arms, 0.0)
