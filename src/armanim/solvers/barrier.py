"""The barrier guarantee, in one place for every method.

A proposed joint update is first scaled so that no joint turns by more than
``solver.max_joint_step`` in one frame, then halved until the new pose keeps every
link capsule out of every obstacle and every limited joint strictly inside its
limits. A step that never becomes safe is not taken: the arm holds still.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from armanim.cost import min_link_clearance
from armanim.geometry import wrap_angle
from armanim.kinematics import forward
from armanim.problem import Problem
from armanim.solvers.common import ArmState, arm_state

HALVINGS = 30
CONTACT = 1e-9  # clearance that counts as touching: kept strictly positive


@dataclass(frozen=True)
class Shortened:
    """Result of :func:`shorten_step`.

    Attributes
    ----------
    state : ArmState
        The new, safe pose (unlimited joints wrapped to (-pi, pi]), with its
        kinematics and clearances, ready for the next step.
    scale : float
        Fraction of the proposed step taken (1 = all of it, 0 = none).
    blocked_by : str or None
        What shortened the step beyond the joint-step cap: ``"obstacle"``,
        ``"limit"``, ``"nan"`` (the proposal was not finite), or None.
    """

    state: ArmState
    scale: float
    blocked_by: str | None

    @property
    def phi(self) -> np.ndarray:
        """The new angles."""
        return self.state.phi


def wrap_unlimited(problem: Problem, phi: np.ndarray) -> np.ndarray:
    """Wrap the unlimited joints into (-pi, pi]; limited joints stay as they are."""
    if np.abs(phi).max() <= np.pi:  # the usual case: nothing to wrap
        return phi
    return np.where(problem.limits.limited, phi, wrap_angle(phi))


def violations(problem: Problem, candidates: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For (k, n) candidate poses: (k,) bool of limit violations and of obstacle contact."""
    lim = problem.limits
    limit_bad = np.any((candidates <= lim.lower) | (candidates >= lim.upper), axis=-1)
    if not len(problem.obstacles):
        return limit_bad, np.zeros(len(candidates), dtype=bool)
    clearance = min_link_clearance(forward(problem.arm, candidates), problem.obstacles, problem.half_width)
    return limit_bad, ~(clearance > CONTACT)


def shorten_step(problem: Problem, state: ArmState, dphi: np.ndarray) -> Shortened:
    """Take as much of ``dphi`` from ``state`` as the barriers allow (see the module docstring)."""
    biggest = float(np.abs(dphi).max(initial=0.0))
    if not biggest < np.inf:  # NaN or infinity somewhere in the proposal
        return Shortened(state, 0.0, "nan")
    phi = state.phi
    cap = min(1.0, problem.solver.max_joint_step / biggest) if biggest > 0 else 1.0
    full = phi + cap * dphi
    lim = problem.limits
    limit_bad = bool(((full <= lim.lower) | (full >= lim.upper)).any())
    if not limit_bad:
        candidate = arm_state(problem, full)
        if candidate.min_clearance > CONTACT:
            return Shortened(_wrapped(problem, candidate), cap, None)
    blocked_by = "limit" if limit_bad else "obstacle"
    scales = cap * 0.5 ** np.arange(1, HALVINGS + 1)
    limit_bad, contact = violations(problem, phi + scales[:, None] * dphi)
    safe = np.nonzero(~(limit_bad | contact))[0]
    if len(safe) == 0:
        return Shortened(state, 0.0, blocked_by)
    scale = float(scales[safe[0]])
    return Shortened(_wrapped(problem, arm_state(problem, phi + scale * dphi)), scale, blocked_by)


def _wrapped(problem: Problem, state: ArmState) -> ArmState:
    """The same pose with unlimited joints wrapped (the kinematics do not change)."""
    return ArmState(wrap_unlimited(problem, state.phi), state.pose, state.clearance)
