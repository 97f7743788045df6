"""The problem as the compiled kernels read it: one :class:`KernelProblem`, made once per problem
(:attr:`armanim.motion.problem.Problem.kernel`), and the one enumeration of its settings' slots.

numba passes arrays and numbers into a compiled call; a problem's settings are packed into one
float array (:data:`FLOATS` slots) and one int array (:data:`INTS` slots), the same places in
every kernel (the IK attempt's and the frame's), so that the kernels' pieces are shared.
Pure core: numpy only (the kinematics kernel's packing and numba are imported where a kernel
problem is made).
"""

from __future__ import annotations

from typing import Any, NamedTuple, cast

import numpy as np

from armanim.motion.problem import Problem, step_caps

(
    TOL,
    ANGLE_TOL,
    WEIGHT,
    BETA,
    MAX_STEP,
    DAMPING,
    MARGIN,
    BUFFER,
    GAMMA,
    W_LIMITS,
    W_OBSTACLES,
    CLEARANCE,
    KEPT,
    SELF_CLEARANCE,
    KEPT_SELF,
    SELF_INFLUENCE,
    LEVER_NORM,
    SLACK,
    FLOATS,
) = range(19)
"""Places of the settings in :attr:`KernelProblem.floats`: the tolerances (position, angle), the
orientation's weight, beta, the task step's cap, the damping (each joint's step cap is
:attr:`KernelProblem.step_caps`), the limits'
margin and buffer, the filter's gain gamma, the weights of the limits and the obstacles, the
clearance and the clearance the filter keeps, the arm's own pairs' clearance, the one the
filter keeps and their push's influence, the 2-norm of the lever arms, and the slack of a gap's
bound (1e-9 of the reach)."""

METHOD, STACKED, STEPS_CAP, STALL, HALVINGS, KIND, STEPS, SINCE_BEST, INTS = range(9)
"""Places in the kernels' int array: the step (:data:`PINV`, :data:`DLS`), whether the pose task
is stacked, the attempt's steps, the stall window, the filter's halvings, the orientation's kind
(0 none, 1 a rotation, 2 a tool axis), and the attempt's counters so far: its steps and the
steps since its best progress. :attr:`KernelProblem.ints` holds the problem's own (the stall
window, the halvings); an attempt sets the rest per call."""

PINV, DLS = 0, 1
"""The compiled steps: the pseudo-inverse and the damped least-squares inverse."""

DONE, NUMERICAL, HANDED_BACK = 0, 1, 2
"""How a compiled attempt (or its proposal) ended: by the attempt's own tests, on a proposal that
was not finite, or handed back to the numpy path (:mod:`armanim.motion.kernels.attempt`)."""


Kind = tuple[np.ndarray | None, np.ndarray | None, np.ndarray | None, np.ndarray | None]
"""The four arrays of a kind of obstacle in :data:`World` (the solids', the cylinders'), each None
where the scene has none of that kind."""

World = tuple[np.ndarray, np.ndarray, *Kind, np.ndarray, np.ndarray, np.ndarray, *Kind, np.ndarray]
"""The obstacles as the kernels read them (:func:`world_arrays`): the solids' four arrays and the
cylinders' four are None where the scene has none of them."""


Fields = tuple[Any, ...]
"""The fields of a :class:`KernelProblem` as a plain tuple, in their order: the form a kernel is
called with from Python, since numba's dispatch types a plain tuple faster than a named one (some
2 us a call). The frame's state, goal and work space are plain tuples too (:data:`PoseState`,
:data:`FrameGoal`, :data:`FrameWork`, :data:`Measures`)."""


class KernelProblem(NamedTuple):
    """A problem's constants in the kernels' order (contiguous, float64 or int64).

    Attributes
    ----------
    rows, root : (n, 34), (12,) arrays
        The chain (:func:`armanim.arm.kernel.packed_chain`; its rows' last column each joint's kind).
    lower, upper : (n,) arrays
        The joint limits, radians (metres for a prismatic joint; infinite where unlimited).
    step_caps : (n,) array
        The most each joint moves in one step of the filter: ``max_joint_step`` (radians), a
        prismatic joint's ``max_slide_step`` (metres) (:func:`armanim.motion.problem.step_caps`).
    floats : (FLOATS,) array
        The settings, at :data:`TOL` ... :data:`SLACK`.
    ints : (INTS,) int array
        The stall window and the filter's halvings (:data:`STALL`, :data:`HALVINGS`).
    caps : (c, 8) array
        Each capsule's start, end, radius and whether it runs joint to joint (:meth:`~armanim.arm.capsules.Capsules.packed`).
    link, part_radius : (c,), (c + 1,) arrays
        Each capsule's joint (-1: the base), each part's radius (the tip's last).
    levers : (n,) array
        Each joint's lever arm (:attr:`~armanim.motion.problem.Problem.lever_arms`).
    world : tuple of arrays
        The obstacles as :func:`armanim.motion.kernels.check.obstacle_clearances` reads them (:func:`world_arrays`).
    influence : (m,) array
        Each obstacle's influence.
    first, second, pair_radii : (P,) arrays
        The enabled pairs' capsules and the sums of their radii.
    pair_lever_rows, pair_levers : (P, n), (P,) arrays
        Each pair's lever arms and their 2-norm (:attr:`~armanim.motion.problem.Problem.pair_lever_rows`).
    """

    rows: np.ndarray
    root: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    step_caps: np.ndarray
    floats: np.ndarray
    ints: np.ndarray
    caps: np.ndarray
    link: np.ndarray
    part_radius: np.ndarray
    levers: np.ndarray
    world: World
    influence: np.ndarray
    first: np.ndarray
    second: np.ndarray
    pair_radii: np.ndarray
    pair_lever_rows: np.ndarray
    pair_levers: np.ndarray


PoseState = tuple[Any, ...]
"""The state a compiled frame starts from, eleven arrays and a float (:class:`~armanim.motion.solvers.common.ArmState`'s
arrays), in this order: ``phi`` (n,), the joint values (radians, metres for a prismatic joint);
the pose's ``points`` (n + 1, 3) (metres), ``frames`` (n, 3, 3) and world ``axes`` (n, 3)
(:func:`armanim.arm.kinematics.kind_axes`); each part's clearance to each obstacle ``d``
(parts, m) (metres), its closest point's fraction ``t`` (parts, m) and unit ``normal``
(parts, m, 3) ((0, 0) and (0, 0, 3) without obstacles); the enabled pairs' ``gap``, ``gap_t``,
``gap_s`` (P,) and ``gap_normal`` (P, 3); the ``least`` gap (metres, inf without pairs)."""

Measures = tuple[np.ndarray, ...]
"""A new pose's measures as the exact check fills them, eleven arrays
(:func:`armanim.motion.kernels.check.pose_exactly_safe`), in this order: ``points``, ``frames``,
``axes`` and the ``tool`` frame (3, 3); ``d``, ``t``, ``normal``; ``gap``, ``gap_t``, ``gap_s``,
``gap_normal`` (shapes and units as :data:`PoseState`'s)."""

FrameGoal = tuple[np.ndarray, int, np.ndarray | None, np.ndarray | None]
"""A frame's goal, in this order: the tip's ``position`` (3,) (metres); the orientation's
``kind`` (0 none, 1 a rotation, 2 a tool axis); the goal ``rotation`` (3, 3) and tool ``axis``
(3,) (placeholders where ``kind`` is another), both None in a scene without orientations (the
kernels compiled without the rotation task)."""

FrameWork = tuple[np.ndarray, ...]
"""A frame's outputs and work space, seven arrays, in this order: the proposal ``dphi``, the nominal step
``step`` (capped), its bounds ``lo``, ``hi`` (n,) each (radians or metres per joint); the filter's
rows ``cons`` (rows, n) and their lower bounds ``cons_lower`` (rows,) (rows: at most parts x m +
P); the new pose ``cand`` (n,)."""

Placed = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]
"""A pose as the Jacobians of its points read it, built inside a kernel: the joints' points
(n + 1, 3) and world axes (n, 3), the capsules' world ends a, b (c, 3) (metres), each capsule's
joint (c,) (-1: the base). Kernels take such tuples, and unpack them at their top, rather than a
whole :class:`KernelProblem` or :data:`PoseState`: numba counts the references of every array
a call passes and of every field read off a tuple, a cost of some 5 % of a frame when it was so."""

Near = tuple[np.ndarray, np.ndarray, np.ndarray]
"""The obstacles near a pose: its clearances d (parts, m) (metres), their fractions t (parts, m)
and unit normals (parts, m, 3) (:data:`PoseState`'s ``d``, ``t``, ``normal``)."""

Pairs = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]
"""The arm's own pairs at a pose: their capsules ``first``, ``second`` (P,), their gaps (P,)
(metres), closest points' fractions t, s (P,) and unit normals (P, 3)."""


def kernel_problem(problem: Problem) -> KernelProblem:
    """``problem``'s :class:`KernelProblem` (read it as ``problem.kernel``: made once per problem)."""
    from armanim.arm.kernel import packed_chain  # numba: loaded where a kernel runs

    caps, pairs = problem.capsules, problem.self_pairs
    rows, root = packed_chain(problem.arm)
    return KernelProblem(
        rows,
        root,
        _floats(problem.limits.lower),
        _floats(problem.limits.upper),
        _floats(np.broadcast_to(step_caps(problem), (problem.arm.n,))),
        settings_floats(problem),
        settings_ints(problem),
        _floats(caps.packed()),
        _ints(caps.link),
        _floats(caps.part_radius),
        _floats(problem.lever_arms),
        world_arrays(problem),
        _floats(problem.obstacles.influence),
        _ints(pairs.first),
        _ints(pairs.second),
        _floats(pairs.radii(caps)),
        _floats(problem.pair_lever_rows.reshape(len(pairs), problem.arm.n)),
        _floats(problem.pair_levers),
    )


def settings_floats(problem: Problem) -> np.ndarray:
    """The float settings of ``problem`` at their slots (:data:`FLOATS`)."""
    from armanim.motion.cost import self_influence
    from armanim.motion.filter.clearance import kept_clearance, kept_self_clearance, limit_buffer

    s = problem.solver
    floats = np.empty(FLOATS)
    floats[[TOL, ANGLE_TOL, WEIGHT, BETA, MAX_STEP, DAMPING]] = (
        s.tolerance,
        s.orientation_tolerance,
        s.orientation_weight,
        s.beta,
        s.max_step,
        s.damping,
    )
    floats[[MARGIN, BUFFER, GAMMA, W_LIMITS, W_OBSTACLES]] = (
        problem.limits.margin,
        limit_buffer(problem),
        problem.tunables.filter.gamma,
        s.w_limits,
        s.w_obstacles,
    )
    floats[[CLEARANCE, KEPT, SELF_CLEARANCE, KEPT_SELF, SELF_INFLUENCE]] = (
        s.clearance,
        kept_clearance(problem),
        problem.self_pairs.clearance,
        kept_self_clearance(problem),
        self_influence(problem),
    )
    floats[LEVER_NORM] = float(np.linalg.norm(problem.lever_arms))
    floats[SLACK] = 1e-9 * max(problem.arm.reach, 1e-300)
    return floats


def settings_ints(problem: Problem) -> np.ndarray:
    """The int settings of ``problem`` at their slots (:data:`INTS`): the stall window and the
    filter's halvings (the rest is set per call)."""
    ints = np.zeros(INTS, dtype=np.int64)
    ints[STALL], ints[HALVINGS] = problem.tunables.ik.stall_iterations, problem.tunables.filter.halvings
    return ints


def world_arrays(problem: Problem) -> World:
    """The obstacles as :func:`armanim.motion.kernels.check.obstacle_clearances` reads them: the
    spheres' centres and radii, the solids' (boxes and capsule obstacles' axes) centres, half
    edges, rotations and radii, the parts the floor leaves out, the columns' scene order, the
    floor's height ((1,), or (0,) without one), the cylinders' centres, rotations, half
    lengths and radii, and each part's obstacle it may touch ((c+1,): its column among the
    kinds' columns, spheres, solids, cylinders, the floor, before the scene's order is taken; -1
    for none; :attr:`~armanim.arm.capsules.Capsules.part_allowed`).

    A scene without solids has None in their four places, one without cylinders in theirs: the
    kernels are compiled for the types they are called with, and a None leaves the closed forms of
    that shape out of the machine code (a sphere-only scene compiles neither the box's nor the
    cylinder's, most of the kernels' compile time).
    """
    obstacles, caps = problem.obstacles, problem.capsules
    solids, cylinders = obstacles.solids, obstacles.cylinders
    order = obstacles.scene_order if obstacles.scene_order is not None else np.arange(len(obstacles))
    floor = np.zeros(0) if obstacles.floor is None else np.array([float(obstacles.floor)])
    arrays = tuple(
        np.array(v, dtype=t, order="C")  # new writable arrays: see _floats
        for v, t in (
            (obstacles.centers.reshape(-1, 3), float),
            (obstacles.radii, float),
            (solids.centers.reshape(-1, 3), float),
            (solids.half.reshape(-1, 3), float),
            (solids.rotations.reshape(-1, 3, 3), float),
            (obstacles.solid_radius, float),
            (caps.on_base, np.bool_),
            (order, np.int64),
            (floor, float),
            (cylinders.centers.reshape(-1, 3), float),
            (cylinders.rotations.reshape(-1, 3, 3), float),
            (cylinders.half_length, float),
            (cylinders.radius, float),
        )
    )
    solid: tuple[np.ndarray | None, ...] = arrays[2:6] if len(arrays[5]) else (None,) * 4
    cylinder: tuple[np.ndarray | None, ...] = arrays[9:13] if len(arrays[12]) else (None,) * 4
    allowed = caps.part_allowed
    kind_column = np.where(allowed >= 0, np.asarray(order)[np.maximum(allowed, 0)], -1) if len(order) else allowed
    return cast(World, arrays[:2] + solid + arrays[6:9] + cylinder + (_ints(kind_column),))


def _floats(values: np.ndarray) -> np.ndarray:
    """``values`` as a new writable C array: the kernels are compiled per argument type, and a
    read-only or a strided array beside a writable one would compile each kernel twice."""
    return np.array(values, dtype=float, order="C")


def _ints(values: np.ndarray) -> np.ndarray:
    """``values`` as a new writable C int64 array (see :func:`_floats`)."""
    return np.array(values, dtype=np.int64, order="C")
