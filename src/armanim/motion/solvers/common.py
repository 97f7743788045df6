"""What the solver methods share: the step record, the frame's task-space target and
the Jacobians chosen by ``solver.jacobian``."""

from __future__ import annotations

from dataclasses import dataclass
from typing import cast

import numpy as np

from armanim.arm.capsules import capsule_point, capsule_point_jacobian
from armanim.arm.kinematics import Pose, forward, link_point, numeric_jacobian, tip_jacobian
from armanim.motion.problem import Problem
from armanim.world.distances import Clearances, clearances
from armanim.world.selfdistances import SelfGaps, self_gaps, self_jacobians


@dataclass(frozen=True)
class ArmState:
    """A pose with what every step needs of it, computed once per frame.

    Attributes
    ----------
    phi : (n,) array
        Joint angles, radians.
    pose : Pose
        Its joint points and frames.
    clearance : Clearances or None
        Clearances of every part to every obstacle (None without obstacles).
    self_gaps : SelfGaps or None
        Gaps of the enabled pairs of the arm's own capsules (None without enabled pairs).
    """

    phi: np.ndarray
    pose: Pose
    clearance: Clearances | None
    self_gaps: SelfGaps | None = None

    @property
    def tip(self) -> np.ndarray:
        """(3,) the end effector."""
        return self.pose.tip

    @property
    def min_clearance(self) -> float:
        """Smallest capsule clearance (+inf without obstacles)."""
        return float(self.clearance.links.min()) if self.clearance is not None else np.inf

    @property
    def min_self_gap(self) -> float:
        """Smallest gap of an enabled pair of the arm's own capsules (+inf without one)."""
        return float(self.self_gaps.least) if self.self_gaps is not None else np.inf


def arm_state(problem: Problem, phi: np.ndarray) -> ArmState:
    """Forward kinematics (compiled: :mod:`armanim.arm.kernel`), clearances and self gaps of one pose."""
    from armanim.arm import kernel  # numba: imported where a solve starts, never by fk or validate

    phi = np.asarray(phi, dtype=float)
    pose = kernel.forward(problem.arm, phi)
    cl = clearances(pose, problem.obstacles, problem.capsules) if len(problem.obstacles) else None
    gaps = self_gaps(pose, problem.capsules, problem.self_pairs) if len(problem.self_pairs) else None
    return ArmState(phi, pose, cl, gaps)


@dataclass(frozen=True)
class Step:
    """A method's proposed joint update for one frame.

    Attributes
    ----------
    dphi : (n,) array
        Proposed change of the joint angles, radians (before barrier shortening).
    iterations : int
        Inner iterations spent (1 for the linear methods; gradient-descent plus
        Newton iterations for ``newton``; line-search trials for ``gradient``).
    newton_iterations : int
        Of those, Newton iterations (``newton`` only).
    ahead : ArmState or None
        The state at ``phi + dphi`` when the method computed it (``gradient`` prices the
        whole step), so that the filter's exact check of that very pose need not compute
        its kinematics and clearances again; None otherwise.
    """

    dphi: np.ndarray
    iterations: int = 1
    newton_iterations: int = 0
    ahead: ArmState | None = None


def task_displacement(problem: Problem, tip: np.ndarray, goal: np.ndarray) -> np.ndarray:
    """de = beta (g - e), its length capped at ``solver.max_step`` (notes' Eq. 22)."""
    de = problem.solver.beta * (goal - tip)
    length = np.linalg.norm(de)
    cap = problem.solver.max_step
    return cast(np.ndarray, de * (cap / length) if length > cap else de)


def rotation_displacement(problem: Problem, error: np.ndarray) -> np.ndarray:
    """The frame's step of the rotation task: beta w B r, its length (a length, like the
    tip's) capped at ``solver.max_step``."""
    s = problem.solver
    step = s.beta * s.orientation_weight * error
    length = np.linalg.norm(step)
    return step * (s.max_step / length) if length > s.max_step else step


def jacobian_of_tip(problem: Problem, phi: np.ndarray, pose: Pose) -> np.ndarray:
    """(3, n) Jacobian of the tip: analytic, or forward differences (Eq. 15) when the
    scene says ``jacobian: numeric``."""
    arm = problem.arm
    if problem.solver.jacobian == "numeric":
        return numeric_jacobian(lambda p: link_point(forward(arm, p), arm.n - 1, 1.0), phi)
    return tip_jacobian(arm, pose)


def jacobian_of_capsule_point(
    problem: Problem, phi: np.ndarray, pose: Pose, capsule: int | np.ndarray, t: float | np.ndarray
) -> np.ndarray:
    """(3, n) Jacobian of the point at fraction ``t`` along a capsule: analytic, or forward
    differences (Eq. 15) when the scene says ``jacobian: numeric``; for (k,) arrays ``capsule``
    and ``t``, the k points' Jacobians, (k, 3, n)."""
    caps = problem.capsules
    if problem.solver.jacobian == "numeric":
        if np.ndim(capsule):
            return np.array(
                [
                    jacobian_of_capsule_point(problem, phi, pose, c, s)
                    for c, s in zip(np.asarray(capsule), np.asarray(t))
                ]
            ).reshape(-1, 3, len(phi))
        return numeric_jacobian(lambda p: capsule_point(caps, forward(problem.arm, p), capsule, t), phi)
    return capsule_point_jacobian(problem.arm, caps, pose, capsule, t)


def self_pair_jacobians(problem: Problem, phi: np.ndarray, pose: Pose, gaps: SelfGaps, which: np.ndarray) -> np.ndarray:
    """(k, 3, n) J_A - J_B of the enabled pairs ``which`` (k,): how fast the first capsule's
    closest point moves away from the second's (analytic, or as ``solver.jacobian`` says)."""
    pairs = problem.self_pairs
    if problem.solver.jacobian != "numeric":
        return self_jacobians(problem.arm, problem.capsules, pose, pairs, gaps, which)
    first = jacobian_of_capsule_point(problem, phi, pose, pairs.first[which], gaps.t[which])
    second = jacobian_of_capsule_point(problem, phi, pose, pairs.second[which], gaps.s[which])
    return cast(np.ndarray, first - second)
