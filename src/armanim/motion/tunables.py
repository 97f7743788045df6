"""The safety filter's and cost's gains, the stall test's, planner's, single-pose IK's, path following's and the clock's
tunables, as small frozen objects.

Each carries its own documented defaults, the way mink's limits and pink's barriers carry
their gains: a :class:`~armanim.motion.problem.Problem` holds one :class:`Tunables`
(``problem.tunables``, the defaults unless a caller gives others: a test's smaller planning
budget, a benchmark's variant) and every function reads its numbers from there, never from a
module global. No scene field sets them (the scene's own numbers are
:class:`~armanim.motion.problem.SolverSettings`). Module constants are left only for true
constants (math, units, a library's sentinel).

>>> Tunables().planner.ompl_iterations, Tunables().filter.gamma
(15000, 0.5)
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass(frozen=True)
class FilterGains:
    """The safety filter's gains (:mod:`armanim.motion.filter.barrier`).

    Attributes
    ----------
    gamma : float
        Fraction of the remaining gap to a surface or a limit that one frame may close.
    filter_margin : float
        The filter aims at d_safe (1 + filter_margin): sliding along a curved surface drops
        below the tangent plane the QP sees, and the margin absorbs that without shortening.
    settle_margin : float
        The planner prefers goal poses at d_safe (1 + settle_margin): what the filter keeps and
        as much again, room for the method to settle to the tolerance without the filter
        pinning a link.
    limit_buffer : float
        Joints keep this fraction of ``arm.limit_margin`` from their limits (0.5 degrees by default).
    halvings : int
        Halvings of a step the filter tries before it holds the arm still.
    """

    gamma: float = 0.5
    filter_margin: float = 0.1
    settle_margin: float = 0.2
    limit_buffer: float = 0.05
    halvings: int = 30


@dataclass(frozen=True)
class StallOptions:
    """When a goal has stalled (:mod:`armanim.motion.stalls`).

    Attributes
    ----------
    seconds : float
        A goal has stalled when this long makes less progress than the tolerance ...
    progress : float
        ... or less than this fraction of the distance still to go, whichever is larger.
    min_frames : int
        The window is at least this many frames, whatever the frame rate.
    stretch : float
        Toward a goal beyond the arm's reach, pinv and dls step down the gradient of the tip's
        distance, this fraction of the step that the gradient line's linear model says comes
        closest (the Cauchy step; the whole one zigzags across the stretched poses' valley).
    """

    seconds: float = 0.5
    progress: float = 0.05
    min_frames: int = 5
    stretch: float = 0.5


@dataclass(frozen=True)
class PlannerOptions:
    """The joint-space planner's tunables (:mod:`armanim.motion.planning`) and the frame loop's
    use of it (:mod:`armanim.motion.trajectory`).

    Attributes
    ----------
    coarse : int
        Clearances between the first samples of a motion (see ``motion_is_free``).
    coarse_reach : float
        Of the arm's reach: the least travel between the first samples of a motion, where
        ``coarse`` clearances are less. At 1, a motion's first samples are its ends (and a
        sample every reach of travel), and the halving measures only where the lever-arm bounds
        ask it to: on MotionBenchMaker's Panda problems (a 0.5 mm clearance) 3 to 10 times fewer
        poses than samples every 2 % of the reach, with the same answers; the bundled scenes'
        motions come out the same (their goldens are unchanged).
    exact_within : float
        Of the arm's reach: the planner's compiled checks measure capsule by capsule only where a
        group's bounding sphere comes this close to an obstacle or another group, and take the
        spheres' lower bound beyond it (:mod:`armanim.motion.planning.check`).
    max_samples : int
        Poses one motion check may take (a clearance tiny beside the arm: the motion is not taken).
    max_halvings : int
        Levels of halving in a motion check (2^-40 of a coarse piece).
    certify_to : float
        Of ``solver.clearance``: a piece of motion this short is certified by its ends.
    escape_travels : tuple of int
        Clearances of arm travel tried for the step away from a surface.
    straight_tries : int
        Nearest goal poses tried with a straight segment.
    ompl_goals : int
        Goal poses handed to RRT-Connect.
    ompl_iterations : int
        Planner iterations per search: the budget, counted so that it is deterministic.
    ompl_searches : int
        Searches with different random numbers at the planning floor before a goal has no path.
    settle_searches : int
        Searches at the settle floor before the planning floor's (one: where the room to
        settle cuts the way off, as a pair of the arm's own links folding past each other can,
        more searches there only spend their whole budgets; measured on a UR5 goal, two of them
        took 0.47 M pose checks and found nothing, the planning floor's a path in 10,000).
    tick_iterations : int
        How often a search reports its iterations (see ``Searched``).
    rrt_range : float
        Radians: RRT-Connect's longest edge (measured on six hard cases: 0.13 rad found 1,
        0.6 found 3, 1.2 found 5).
    ompl_seed : int
        OMPL's process-wide generator is re-seeded with this before every plan, so a plan
        depends only on its problem.
    max_splits : int
        Halvings of one frame interval when the filter holds a planned frame back (at most
        256 frames in its place).
    max_plans : int
        Plans per goal before it is given up as stalled.
    arrived : float
        Radians: the arm is at a planned pose.
    """

    coarse: int = 8
    coarse_reach: float = 1.0
    exact_within: float = 0.04
    max_samples: int = 100_000
    max_halvings: int = 40
    certify_to: float = 0.05
    escape_travels: tuple[int, ...] = (1, 2, 4, 8, 16)
    straight_tries: int = 4
    ompl_goals: int = 64
    ompl_iterations: int = 15000
    ompl_searches: int = 2
    settle_searches: int = 1
    tick_iterations: int = 500
    rrt_range: float = 1.2
    ompl_seed: int = 20251123
    max_splits: int = 8
    max_plans: int = 3
    arrived: float = 1e-9

    @property
    def plan_iterations(self) -> int:
        """The most RRT-Connect iterations one plan may take: it searches at two floors.

        >>> PlannerOptions().plan_iterations
        45000
        """
        return (self.settle_searches + self.ompl_searches) * self.ompl_iterations


@dataclass(frozen=True)
class PoseSearchOptions:
    """The planner's search for free goal poses (:mod:`armanim.motion.planning.poses`).

    Attributes
    ----------
    seeds : int
        Random starts of the batched damped least-squares solves.
    iterations : int
        Iterations of each solve.
    turn_per_iteration : float
        Radians: larger steps jump between branches and oscillate.
    damping_per_reach : float
        lambda as a fraction of the arm's length.
    hit : float
        A solve counts when its tip is within this fraction of the tolerance.
    max_turn_joints : int
        Unlimited joints whose long way round is offered too (2^3 variants per pose).
    """

    seeds: int = 128
    iterations: int = 80
    turn_per_iteration: float = 0.4
    damping_per_reach: float = 1e-3
    hit: float = 0.25
    max_turn_joints: int = 3


@dataclass(frozen=True)
class CostGains:
    """Gains of the cost's terms that no scene field sets (:mod:`armanim.motion.cost`).

    Attributes
    ----------
    self_influence : float
        R of the field between two of the arm's own capsules, in ``self_clearance``: a pair
        nearer than twice its clearance is pushed apart (the pictures tint such a pair too).
    priority_weight : float
        For an arm that cannot hold every orientation at a position, the cost methods weigh the
        orientation term by this fraction: position first, the angle minimised with what is left
        (the linear methods do it exactly, in the null space).
    """

    self_influence: float = 2.0
    priority_weight: float = 1e-4


@dataclass(frozen=True)
class IkOptions:
    """Solving one pose to convergence (:mod:`armanim.motion.ik`, ``armanim ik``).

    Attributes
    ----------
    full_turn_per_iteration : float
        Radians: the least joint step a solve allows itself (``solver.max_joint_step`` when larger).
    stall_iterations : int
        Steps without progress before a restart.
    restarts : int
        Random restarts after the first attempt.
    seed : int
        Of the random restarts: the same solve always restarts from the same poses.
    solving : bool
        True in the problem :func:`armanim.motion.ik.solving_problem` makes: there ``pinv`` and
        ``dls`` solve a pose goal the arm can hold (:func:`armanim.motion.orientation.holds_orientation`)
        as one stacked task, one inverse of the (3 + k) x n Jacobian per step, instead of the
        rotation in the position's null space (four inverses). The frame loop keeps the task
        priority (False), so trajectories are what they were.
    compiled : bool
        A pose solve's ``pinv`` and ``dls`` attempts run compiled where they mean the same
        (:mod:`armanim.motion.kernels.attempt`: no obstacles, the analytic Jacobian); False:
        the numpy steps everywhere (the tests' oracle).
    compiled_frames : bool
        The frame loop's ``pinv`` and ``dls`` frames run compiled
        (:mod:`armanim.motion.kernels.frame`: the proposal, the filter's rows, its exact
        check and halvings; its QP stays DAQP's; the same steps to rounding); False: the numpy
        frames everywhere (the tests' oracle).
    """

    full_turn_per_iteration: float = float(np.radians(30.0))
    stall_iterations: int = 15
    restarts: int = 4
    seed: int = 0
    solving: bool = False
    compiled: bool = True
    compiled_frames: bool = True


@dataclass(frozen=True)
class PathOptions:
    """Following a path goal's tool path (:mod:`armanim.motion.paths.following`).

    Attributes
    ----------
    spacing_per_tolerance : float
        Most path tolerances between two samples, whatever the speed.
    max_splits : int
        Times a failing sample's step is halved before the path is reported blocked.
    sample_steps : int
        Most filtered steps of one sample's solve.
    sample_tolerance : float
        A sample's tool within this fraction of the path tolerance of its point.
    midpoint_tolerance : float
        The midpoint between two samples within this fraction of the path tolerance of the path.
    other_starts : int
        Other free poses at a path's start tried when the path stops short from the first.
    branches_apart : float
        Radians: two start poses whose joints all lie closer than this count as one branch.
    route_plans : int
        Planned ways to a better start pose tried (the farthest-following one).
    route_iterations : int
        RRT-Connect iterations of one such plan.
    """

    spacing_per_tolerance: float = 10.0
    max_splits: int = 4
    sample_steps: int = 30
    sample_tolerance: float = 0.1
    midpoint_tolerance: float = 0.5
    other_starts: int = 16
    branches_apart: float = 0.5
    route_plans: int = 1
    route_iterations: int = 500


@dataclass(frozen=True)
class ClockOptions:
    """The clock's grid (:mod:`armanim.motion.timing.clock`).

    Attributes
    ----------
    grid_per_step : int
        TOPP grid points per solved step of the path (its knot and evenly spaced points inside it).
    collocation : tuple of float
        Fractions of each grid interval where the time law keeps the limits (1.0: the end of the
        interval, approached from inside it).
    grid_min : int
        Fewest grid intervals of a path (a short path's steps are split further).
    check_per_step : int
        Points per grid interval where the scaled time law is checked against the limits.
    """

    grid_per_step: int = 16
    collocation: tuple[float, ...] = (0.0, 0.5, 1.0)
    grid_min: int = 512
    check_per_step: int = 4


@dataclass(frozen=True)
class Tunables:
    """Every tunable of the filter, the cost, the stall test, the planner, single-pose IK, path
    following and the clock (``problem.tunables``)."""

    filter: FilterGains = field(default_factory=FilterGains)
    stalls: StallOptions = field(default_factory=StallOptions)
    planner: PlannerOptions = field(default_factory=PlannerOptions)
    poses: PoseSearchOptions = field(default_factory=PoseSearchOptions)
    cost: CostGains = field(default_factory=CostGains)
    ik: IkOptions = field(default_factory=IkOptions)
    path: PathOptions = field(default_factory=PathOptions)
    clock: ClockOptions = field(default_factory=ClockOptions)


DEFAULTS = Tunables()
"""The defaults (frozen, shared): what every problem holds unless told otherwise."""
