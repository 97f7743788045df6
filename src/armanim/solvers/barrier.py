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

HALVINGS = 30
CONTACT = 1e-9  # clearance that counts as touching: kept strictly positive


@dataclass(frozen=True)
class Shortened:
    """Result of :func:`shorten_step`.

    Attributes
    ----------
    phi : (n,) array
        The new, safe angles (unlimited joints wrapped to (-pi, pi]).
    scale : float
        Fraction of the proposed step taken (1 = all of it, 0 = none).
    blocked_by : str or None
        What shortened the step beyond the joint-step cap: ``"obstacle"``,
        ``"limit"``, ``"nan"`` (the proposal was not finite), or None.
    """

    phi: np.ndarray
    scale: float
    blocked_by: str | None


def wrap_unlimited(problem: Problem, phi: np.ndarray) -> np.ndarray:
    """Wrap the unlimited joints into (-pi, pi]; limited joints stay as they are."""
    return np.where(problem.limits.limited, phi, wrap_angle(phi))


def violations(problem: Problem, candidates: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For (k, n) candidate poses: (k,) bool of limit violations and of obstacle contact."""
    lim = problem.limits
    limit_bad = np.any((candidates <= lim.lower) | (candidates >= lim.upper), axis=-1)
    clearance = min_link_clearance(forward(problem.arm, candidates), problem.obstacles, problem.half_width)
    return limit_bad, ~(clearance > CONTACT)


def shorten_step(problem: Problem, phi: np.ndarray, dphi: np.ndarray) -> Shortened:
    """Take as much of ``dphi`` as the barriers allow (see the module docstring)."""
    if not np.all(np.isfinite(dphi)):
        return Shortened(phi.copy(), 0.0, "nan")
    biggest = np.max(np.abs(dphi), initial=0.0)
    cap = min(1.0, problem.solver.max_joint_step / biggest) if biggest > 0 else 1.0
    full = phi + cap * dphi
    limit_bad, contact = violations(problem, full[None, :])
    if not (limit_bad[0] or contact[0]):
        return Shortened(wrap_unlimited(problem, full), cap, None)
    blocked_by = "obstacle" if contact[0] else "limit"
    scales = cap * 0.5 ** np.arange(1, HALVINGS + 1)
    limit_bad, contact = violations(problem, phi + scales[:, None] * dphi)
    safe = np.nonzero(~(limit_bad | contact))[0]
    if len(safe) == 0:
        return Shortened(phi.copy(), 0.0, blocked_by)
    scale = float(scales[safe[0]])
    return Shortened(wrap_unlimited(problem, phi + scale * dphi), scale, blocked_by)
