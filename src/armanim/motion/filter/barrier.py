"""The safety filter: the closest safe step to a method's proposal, for every method.

A method proposes dPhi_nom. After scaling it so that no joint turns by more than
``solver.max_joint_step``, a small quadratic program returns the closest safe step

    minimise |dPhi - dPhi_nom|^2
    subject to  n . J_q dPhi >= -gamma (d - d_safe)      every link capsule near an obstacle
                -gamma (phi_j - lo_j) <= dPhi_j <= gamma (hi_j - phi_j)   every limited joint
                |dPhi_j| <= max_joint_step

(a velocity damper, the discrete control-barrier condition: each frame closes at most
the fraction gamma of what is left of a gap). The gains are ``problem.tunables.filter``
(:class:`~armanim.motion.tunables.FilterGains`). d is the capsule's clearance to the
obstacle (sphere, box, capsule, cylinder, or the floor), q the point of its segment nearest the
solid, n the solid's outward unit normal there, J_q that point's Jacobian;
d_safe is ``solver.clearance``; lo_j and hi_j are the limits moved inward by
:attr:`~armanim.motion.tunables.FilterGains.limit_buffer` of the limit margin. An arm touching a solid therefore slides
along it (a box: along a face, round an edge) instead of stopping, and never rests on a surface or a limit.

The constraints are linear, the true clearance is not, so the new pose is then
checked exactly; only a step that fails that check is shortened (halved). When no
constraint is active the method's own step is returned unchanged, without a QP.
The QP is solved with DAQP (a dual active-set solver for small dense problems). What the
filter keeps (the clearances, the limit buffer) is the policy it shares with the planner,
:mod:`armanim.motion.filter.clearance`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import cast

import numpy as np

from armanim.arm import capsules as arm_capsules
from armanim.arm.geometry import wrap_angle
from armanim.motion.filter.clearance import kept_clearance, kept_self_clearance, limit_buffer
from armanim.motion.problem import Problem, step_caps
from armanim.motion.solvers.common import ArmState, arm_state
from armanim.names import Blocker
from armanim.world.selfdistances import self_rows, self_rows_met

NO_BOUND = 1e30  # DAQP's "no upper bound"
VIOLATION = 1e-12
"""A constraint counts as broken by more than this (rounding)."""


@dataclass(frozen=True)
class SafeStep:
    """Result of :func:`safe_step`.

    Attributes
    ----------
    state : ArmState
        The new, safe pose (unlimited joints wrapped to (-pi, pi]), with its
        kinematics and clearances, ready for the next step.
    scale : float
        |dPhi| / |dPhi_nom| of the step taken: 1 = the proposal as it was, 0 = none.
    blocked_by : Blocker or None
        What changed the proposal beyond the joint-step cap: ``"obstacle"``,
        ``"limit"``, ``"nan"`` (the proposal was not finite), or None.
    """

    state: ArmState
    scale: float
    blocked_by: Blocker | None

    @property
    def phi(self) -> np.ndarray:
        """The new angles."""
        return self.state.phi


@dataclass(frozen=True)
class Constraints:
    """The filter's linear constraints lower <= A dPhi and lo <= dPhi <= hi.

    ``A`` has one row per (link, obstacle) pair near enough to matter.
    """

    rows: np.ndarray  # (k, n)
    lower: np.ndarray  # (k,)
    lo: np.ndarray  # (n,)
    hi: np.ndarray  # (n,)

    def violated_by(self, dphi: np.ndarray) -> Blocker | None:
        """Which constraint ``dphi`` breaks (to rounding): ``"obstacle"``, ``"limit"``, or None."""
        eps = VIOLATION
        if len(self.rows) and np.any(self.rows @ dphi < self.lower - eps):
            return "obstacle"
        if np.any(dphi < self.lo - eps) or np.any(dphi > self.hi + eps):
            return "limit"
        return None


def wrap_unlimited(problem: Problem, phi: np.ndarray) -> np.ndarray:
    """Wrap the unlimited joints into (-pi, pi]; limited joints stay as they are."""
    if np.abs(phi).max() <= np.pi:  # the usual case: nothing to wrap
        return phi
    return np.where(problem.limits.limited, phi, wrap_angle(phi))


def point_travel_bound(problem: Problem, dphi: np.ndarray) -> float:
    """Most any arm point can move under a joint change ``dphi`` (sum of |dphi_j| times its lever arm)."""
    return float(np.abs(dphi) @ problem.lever_arms)


def joint_bounds(problem: Problem, phi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per-joint bounds of dPhi: the joint-step cap and the limits' velocity damper."""
    cap = step_caps(problem)
    lim = problem.limits
    buffer = limit_buffer(problem)
    gamma = problem.tunables.filter.gamma
    with np.errstate(invalid="ignore"):
        lo = np.maximum(-cap, -gamma * (phi - (lim.lower + buffer)))
        hi = np.minimum(cap, gamma * ((lim.upper - buffer) - phi))
    lo = np.where(lim.limited, lo, -cap)
    hi = np.where(lim.limited, hi, cap)
    return np.minimum(lo, 0.0), np.maximum(hi, 0.0)  # inside the buffer: 0 is always allowed


def obstacle_rows(problem: Problem, state: ArmState, travel: float) -> tuple[np.ndarray, np.ndarray]:
    """Constraint rows n . J_q and lower bounds -gamma (d - d_target) of the capsule-obstacle
    pairs whose clearance is within ``travel`` (the most an arm point can move) of the target distance;
    none of the base's capsules (they never move: their clearance is checked when the scene is read)."""
    n = problem.arm.n
    if state.clearance is None:
        return np.zeros((0, n)), np.zeros(0)
    target = kept_clearance(problem)
    d = state.clearance.links
    parts, obstacles = np.nonzero(
        (d - target < travel) & problem.capsules.moving[:-1, None]
    )  # the base's capsules: no row
    if not len(parts):
        return np.zeros((0, n)), np.zeros(0)
    jacs = arm_capsules.capsule_point_jacobian(
        problem.arm, problem.capsules, state.pose, parts, state.clearance.t[parts, obstacles]
    )
    rows = np.matmul(state.clearance.normal[parts, obstacles][:, None, :], jacs)[
        :, 0, :
    ]  # each row n . J_q, as one alone
    return rows, -problem.tunables.filter.gamma * (d[parts, obstacles] - target)


def self_pair_rows(problem: Problem, state: ArmState, travel: float | np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Constraint rows n . (J_A - J_B) and lower bounds -gamma (d - d_target) of the enabled pairs
    of the arm's own capsules whose gap is within ``travel`` ((P,) per pair, or one bound) of
    :func:`kept_self_clearance`.

    A pair's gap depends only on the joints between its two capsules, and in the first one's frame
    the second's points move no more than the arm's points do: the arm's travel bounds its change too."""
    n = problem.arm.n
    gaps = state.self_gaps
    if gaps is None:
        return np.zeros((0, n)), np.zeros(0)
    target = kept_self_clearance(problem)
    which = np.nonzero(gaps.d - target < travel)[0]
    if not len(which):
        return np.zeros((0, n)), np.zeros(0)
    rows = self_rows(problem.arm, problem.capsules, state.pose, problem.self_pairs, gaps, which)
    return rows, -problem.tunables.filter.gamma * (gaps.d[which] - target)


def filter_constraints(
    problem: Problem, state: ArmState, nominal: np.ndarray, bounds: tuple[np.ndarray, np.ndarray] | None = None
) -> Constraints:
    """The constraints of the frame: only obstacle pairs that the QP's answer could reach.

    0 is feasible, so the answer is within |nominal| of the nominal step (2-norm), hence at
    most 2 |nominal| long, and no arm point moves more than that times |problem.lever_arms|.
    Pairs beyond are left out (the exact check still guards every pair). ``bounds``:
    :func:`joint_bounds` at ``state``, when the caller has them.
    """
    lo, hi = joint_bounds(problem, state.phi) if bounds is None else bounds
    travel = 2.0 * float(np.linalg.norm(nominal) * np.linalg.norm(problem.lever_arms)) + 1e-9
    rows, lower = obstacle_rows(problem, state, travel)
    if state.self_gaps is not None:
        own, own_lower = self_pair_rows(
            problem, state, 2.0 * float(np.linalg.norm(nominal)) * problem.pair_levers + 1e-9
        )
        if len(own):
            rows, lower = np.concatenate([rows, own]), np.concatenate([lower, own_lower])
    return Constraints(rows, lower, lo, hi)


def takes_unchanged(problem: Problem, state: ArmState, dphi: np.ndarray) -> bool:
    """Whether the filter takes the step ``dphi`` from ``state`` as it is: within the joint-step
    cap, every linear constraint met (the planner paces its paths with this)."""
    if problem.arm.prismatic is not None:
        if not np.all(np.abs(dphi) <= step_caps(problem) * (1 + 1e-9)):
            return False
    elif not np.abs(dphi).max(initial=0.0) <= problem.solver.max_joint_step * (1 + 1e-9):
        return False
    return filter_constraints(problem, state, dphi).violated_by(dphi) is None


def closest_safe_step(nominal: np.ndarray, cons: Constraints) -> np.ndarray | None:
    """Solve the filter's QP with DAQP; None when it has no solution."""
    import daqp  # imported here: only frames with an active constraint need it

    n = len(nominal)
    k = len(cons.rows)
    upper = np.concatenate([cons.hi, np.full(k, NO_BOUND)])
    lower = np.concatenate([cons.lo, cons.lower])
    x, _, flag, _ = daqp.solve(
        np.eye(n), -nominal, cons.rows.reshape(k, n), upper, lower, np.zeros(n + k, dtype=np.intc)
    )
    if flag < 1 or not np.all(np.isfinite(x)):
        return None
    return cast(
        "np.ndarray | None", np.clip(x, cons.lo, cons.hi)
    )  # DAQP meets bounds to its tolerance (~1e-7): the cap is exact


def filtered_step(nominal: np.ndarray, cons: Constraints) -> np.ndarray:
    """The closest step meeting ``cons``; if even that is infeasible (the pose already sits
    inside a margin), the closest step that does not close any gap further; else none."""
    if cons.violated_by(nominal) is None:
        return nominal
    dphi = closest_safe_step(nominal, cons)
    if dphi is None:
        relaxed = Constraints(cons.rows, np.minimum(cons.lower, 0.0), cons.lo, cons.hi)
        dphi = closest_safe_step(nominal, relaxed)
    return dphi if dphi is not None else np.zeros_like(nominal)


def exactly_safe(problem: Problem, now: ArmState, phi: np.ndarray, known: ArmState | None = None) -> ArmState | None:
    """The pose ``phi`` as a state if it keeps every guarantee exactly, else None.

    ``known``: that pose's state when the caller has it already (its angles bit for bit
    ``phi``); else it is computed here.

    Guarantees: every limited joint at least the limit buffer inside its limits (or no
    nearer than it already was), every link capsule and the tip at least ``solver.clearance``
    from every obstacle (or no nearer than they already were), every enabled pair of the arm's
    own capsules at least ``solver.self_clearance`` apart (or no nearer than it already was),
    and no NaN.
    """
    if not np.all(np.isfinite(phi)):
        return None
    lim = problem.limits
    buffer = limit_buffer(problem)
    gap_now = np.minimum(now.phi - lim.lower, lim.upper - now.phi)
    gap = np.minimum(phi - lim.lower, lim.upper - phi)
    if np.any(gap <= 0) or np.any(gap < np.minimum(buffer, gap_now)):
        return None
    candidate = known if known is not None else arm_state(problem, phi)
    if candidate.clearance is not None:
        floor = min(problem.solver.clearance, now.min_clearance)
        if not candidate.min_clearance >= floor:
            return None
        # the tip too: a robot's tool point can lie beyond its last capsule (a link-by-link arm's
        # tip ends its last capsule, at least clearance + width/2 away, so this never binds there)
        assert now.clearance is not None  # the same problem's states: both have clearances, or neither
        tip_floor = min(problem.solver.clearance, float(now.clearance.d[..., -1, :].min()))
        if not float(candidate.clearance.d[..., -1, :].min()) >= tip_floor:
            return None
    if candidate.self_gaps is not None:  # every enabled pair of the arm's own parts, likewise
        if not candidate.min_self_gap >= min(problem.self_pairs.clearance, now.min_self_gap):
            return None
    return candidate


def safe_step(problem: Problem, state: ArmState, dphi: np.ndarray, ahead: ArmState | None = None) -> SafeStep:
    """The closest safe step to the proposal ``dphi`` (see the module docstring).

    ``ahead``: the state at ``state.phi + dphi`` if the method computed it (:class:`Step`); it
    is used for the exact check of a candidate pose that is bit for bit that one.
    """
    biggest = float(np.abs(dphi).max(initial=0.0))
    if not biggest < np.inf:  # NaN or infinity somewhere in the proposal
        return SafeStep(state, 0.0, "nan")
    if biggest == 0.0:
        return SafeStep(state, 0.0, None)
    if problem.arm.prismatic is None:
        nominal = dphi * min(1.0, problem.solver.max_joint_step / biggest)
    else:  # each joint within its own cap: radians, or metres for a prismatic joint
        nominal = dphi * min(1.0, float(np.min(step_caps(problem) / np.maximum(np.abs(dphi), 1e-300))))
    bounds = joint_bounds(problem, state.phi)
    cons = (
        None
        if clearly_allowed(problem, state, nominal, bounds)
        else filter_constraints(problem, state, nominal, bounds)
    )
    step = nominal if cons is None else filtered_step(nominal, cons)
    for scale in 0.5 ** np.arange(problem.tunables.filter.halvings + 1):
        phi = state.phi + scale * step
        known = ahead if ahead is not None and ahead.phi.tobytes() == phi.tobytes() else None
        moved = exactly_safe(problem, state, phi, known)
        if moved is not None:
            blocked = None if step is nominal and scale == 1.0 else blocker(nominal, cons)
            return SafeStep(_wrapped(problem, moved), step_fraction(scale * step, dphi), blocked)
    return SafeStep(state, 0.0, blocker(nominal, cons))


BOUND_SLACK = 1e-9
"""Relative room :func:`clearly_allowed` leaves for rounding: the rows it bounds are computed
numbers, within some 1e-15 of the bound's."""


def clearly_allowed(
    problem: Problem, state: ArmState, nominal: np.ndarray, bounds: tuple[np.ndarray, np.ndarray] | None = None
) -> bool:
    """Whether ``nominal`` meets every constraint of :func:`filter_constraints` by bounds alone,
    without computing the rows (the filter's fast path: then :func:`filtered_step` would return
    ``nominal`` itself, so the step is the same, bit for bit).

    Within the joint bounds, and every gap far enough from its target for the step: an obstacle
    row n . J_q dPhi is at least -sum_j |dPhi_j| l_j (l: ``problem.lever_arms``, each column of
    J_q is w_j x (q - p_j), no longer than l_j), a pair's row at least -|dPhi| . its
    ``pair_lever_rows``; the row holds when gamma (d - d_target) is at least that much. A pair
    the bound leaves in doubt has its row computed (compiled, a few microseconds) and tested as
    :meth:`Constraints.violated_by` tests it.
    ``bounds``: :func:`joint_bounds` at ``state``, when the caller has them.
    """
    lo, hi = joint_bounds(problem, state.phi) if bounds is None else bounds
    if np.any(nominal < lo - VIOLATION) or np.any(nominal > hi + VIOLATION):  # as Constraints.violated_by judges it
        return False
    gamma = problem.tunables.filter.gamma
    slack = 1.0 + BOUND_SLACK
    travel = point_travel_bound(problem, nominal)
    if state.clearance is not None:
        room = gamma * (float(state.clearance.links.min()) - kept_clearance(problem))
        if not room >= travel * slack + 1e-12:
            return False
    if state.self_gaps is not None:  # the joints that move both capsules alike add rounding alone
        return self_rows_met(
            problem.arm,
            problem.capsules,
            state.pose,
            problem.self_pairs,
            state.self_gaps,
            kept_self_clearance(problem),
            gamma,
            problem.pair_lever_rows,
            nominal,
            slack,
            BOUND_SLACK * travel + 1e-12,
            VIOLATION,
        )
    return True


def step_fraction(taken: np.ndarray, proposed: np.ndarray) -> float:
    """|taken| / |proposed|, 0 when the proposal's length is not a positive finite number.

    >>> step_fraction(np.array([0.5, 0.0]), np.array([1.0, 0.0])), step_fraction(np.zeros(2), np.full(2, 1e-320))
    (0.5, 0.0)
    >>> round(step_fraction(np.array([1e190, 0.0]), np.array([1e200, 0.0])), 20)
    1e-10
    """
    with np.errstate(over="ignore"):
        length = float(np.linalg.norm(proposed))
    if length == np.inf:  # finite components whose squares overflow (a proposal of 1e200): scaled first
        biggest = float(np.abs(proposed).max())
        if biggest < np.inf:
            return float(np.linalg.norm(taken / biggest) / np.linalg.norm(proposed / biggest))
    return float(np.linalg.norm(taken)) / length if 0.0 < length < np.inf else 0.0


def blocker(nominal: np.ndarray, cons: Constraints | None) -> Blocker:
    """What kept the proposal from being taken as it was: ``"obstacle"`` or ``"limit"`` (``cons``
    None: the proposal met every constraint, :func:`clearly_allowed`)."""
    violated = None if cons is None else cons.violated_by(nominal)
    return violated or "obstacle"  # else the linear model allowed it, the exact clearance did not


def _wrapped(problem: Problem, state: ArmState) -> ArmState:
    """The same pose with unlimited joints wrapped (the kinematics do not change)."""
    return ArmState(wrap_unlimited(problem, state.phi), state.pose, state.clearance, state.self_gaps)
