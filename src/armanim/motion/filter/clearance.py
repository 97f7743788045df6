"""The clearance policy the filter and the planner share: what every link keeps from the
obstacles and every enabled pair of the arm's own capsules from each other, what a limited
joint keeps from its limits, and a pose's clearances and limits judged by them.

The filter (:mod:`armanim.motion.filter.barrier`) keeps :func:`kept_clearance` and
:func:`kept_self_clearance`; the planner (:mod:`armanim.motion.planning`) plans no closer than
:func:`planning_floor` and prefers goal poses at :func:`settle_clearance`. The margins are
``problem.tunables.filter`` (:class:`~armanim.motion.tunables.FilterGains`). Pure core: numpy only.
"""

from __future__ import annotations

from typing import cast

import numpy as np

from armanim.arm.kinematics import forward
from armanim.motion.problem import Problem
from armanim.world.distances import min_link_clearance
from armanim.world.selfdistances import self_gaps


def limit_buffer(problem: Problem) -> float:
    """Radians every limited joint keeps from its limits."""
    return problem.tunables.filter.limit_buffer * problem.limits.margin


def pose_clearance(problem: Problem, phi: np.ndarray) -> np.ndarray:
    """For (k, n) poses: (k,) smallest clearance of any link capsule to any obstacle and of any
    enabled pair of the arm's own capsules, the latter counted from ``self_clearance`` as the
    former from ``clearance`` (its gap plus :func:`self_shift`), so that one floor judges both
    (+inf if neither)."""
    clear, own = split_clearances(problem, phi)
    return clear if own is None else np.minimum(clear, own.min(axis=-1))


def split_clearances(problem: Problem, phi: np.ndarray) -> tuple[np.ndarray, np.ndarray | None]:
    """For (k, n) poses: (k,) the smallest obstacle clearance, and (k, P) every enabled pair's gap
    plus :func:`self_shift` (None without enabled pairs): :func:`pose_clearance`'s two parts."""
    pose = forward(problem.arm, np.atleast_2d(phi))
    clear = min_link_clearance(pose, problem.obstacles, problem.capsules)
    if not len(problem.self_pairs):
        return clear, None
    return clear, self_gaps(pose, problem.capsules, problem.self_pairs).d + self_shift(problem)


def self_shift(problem: Problem) -> float:
    """``clearance - self_clearance``: what a pair's gap is shifted by to be judged as a clearance."""
    return problem.solver.clearance - problem.self_pairs.clearance


def kept_self_clearance(problem: Problem) -> float:
    """The gap the filter keeps every enabled pair at: ``self_clearance`` and the filter's margin
    of ``clearance`` (:func:`kept_clearance` shifted by :func:`self_shift`)."""
    return kept_clearance(problem) - self_shift(problem)


def within_limits(problem: Problem, phi: np.ndarray, closed: bool = False) -> np.ndarray:
    """For (k, n) poses: (k,) bool, every limited joint at least the limit buffer inside its limits
    (``closed``: within its limits, the ends included, as a joint goal's path keeps them)."""
    lim = problem.limits
    buffer = 0.0 if closed else limit_buffer(problem)
    return cast(np.ndarray, np.all((phi >= lim.lower + buffer) & (phi <= lim.upper - buffer), axis=-1))


def kept_clearance(problem: Problem) -> float:
    """The clearance the filter keeps every link at, d_safe (1 + ``filter_margin``): a link closer
    than that is pushed out, so neither a goal pose nor a planned path may ask for less."""
    return problem.solver.clearance * (1.0 + problem.tunables.filter.filter_margin)


def settle_clearance(problem: Problem) -> float:
    """The clearance of the goal poses the planner tries first, d_safe (1 + ``settle_margin``)."""
    return problem.solver.clearance * (1.0 + problem.tunables.filter.settle_margin)


def planning_floor(problem: Problem, phi_now: np.ndarray) -> float:
    """The least clearance a plan from ``phi_now`` may come to: what the filter keeps, or the
    arm's own clearance now when that is less (a plan out of a pose resting at the margin)."""
    now = float(pose_clearance(problem, phi_now)[0])
    return min(kept_clearance(problem), max(now, problem.solver.clearance))


def pose_is_free(problem: Problem, phi: np.ndarray) -> np.ndarray:
    """For (k, n) poses: (k,) bool, inside the limits by the buffer and every link capsule
    at least ``solver.clearance`` from every obstacle (the planner's validity test)."""
    phi = np.atleast_2d(phi)
    return within_limits(problem, phi) & (pose_clearance(problem, phi) >= problem.solver.clearance)
