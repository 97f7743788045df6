"""``newton``: the n-link assignment's solver, gradient descent with backtracking line
search (GDLS) then Newton's method (NM), NM kept only where it lowers f.

f(Phi) = 1/2 w_tar |e(Phi) - e*|^2 + 1/2 w_reg |Phi - Phi_rest|^2
g(Phi) = w_tar P'^T (e - e*) + w_reg (Phi - Phi_rest)
H(Phi) = w_tar (P'^T P' + (e - e*) . P'') + w_reg I

In the frame loop e* is the frame's target e + de and Phi_rest the previous frame's
angles; ``armanim ik`` solves to the goal itself from a rest pose.

A goal with an orientation adds 1/2 w_rot |r|^2, r = log(R* R^T) (or the tool axis's
alignment, :mod:`armanim.motion.orientation`), to f, with

g += -w_rot J_w^T r (exact),   H += w_rot (B J_w)^T (B J_w) (Gauss-Newton),

w_rot = w_tar w^2 for the orientation weight w (length per radian), so that a radian weighs
as w of distance. For an arm that cannot hold the orientation at every position
(:func:`~armanim.motion.orientation.holds_orientation` False), w_rot is scaled by
:attr:`~armanim.motion.tunables.CostGains.priority_weight`: position first.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import cast

import numpy as np

from armanim.arm.kinematics import Arm, Pose, link_point, point_hessian, tip_jacobian, tool_rotation
from armanim.motion.orientation import (
    Orientation,
    holds_orientation,
    orientation_gradient,
    orientation_residual,
    orientation_task,
    partial_orientation,
)
from armanim.motion.problem import Problem
from armanim.motion.solvers.common import ArmState, Step, rotation_displacement, task_displacement


@dataclass(frozen=True)
class NewtonOptions:
    """Iteration settings of GDLS and NM (the assignment's parameter list).

    Attributes
    ----------
    gd_iterations, nm_iterations : int
        Caps on GDLS and NM iterations.
    tolerance : float
        Both stop when |g| falls below it (the assignment's 1e-3).
    alpha : float
        Initial GDLS step (the assignment's 1e0 for small arms).
    shrink : float
        Backtracking factor of the line searches.
    halvings : int
        Line-search trials before giving up on a direction.
    max_turn : float
        Largest joint change (radians) a line search starts from: with w_tar = 1e3
        the raw gradient step would spin joints by whole turns into another branch.
    handover : float
        GDLS hands over to NM once an iteration lowers f by less than this fraction:
        in the narrow valley that w_tar = 1e3 makes, gradient descent only crawls.
    """

    gd_iterations: int = 20
    nm_iterations: int = 20
    tolerance: float = 1e-3
    alpha: float = 1.0
    shrink: float = 0.5
    halvings: int = 40
    max_turn: float = 0.5
    handover: float = 0.01


@dataclass(frozen=True)
class NewtonResult:
    """Outcome of :func:`newton_solve`: angles, objective, and iteration counts."""

    phi: np.ndarray
    f: float
    gd_iterations: int
    nm_iterations: int
    newton_kept: bool


def _pose(arm: Arm, phi: np.ndarray) -> Pose:
    """One pose's kinematics, compiled (:func:`armanim.arm.kernel.forward`, within 1e-12 of
    :func:`~armanim.arm.kinematics.forward`): a Newton step evaluates f some 40 times in its line
    searches, and numpy's fixed cost per small call made those evaluations most of a cluttered
    ``newton`` run's time (issue 50 item 10)."""
    from armanim.arm import kernel  # numba: imported where a solve starts, never by fk or validate

    return kernel.forward(arm, phi)


def objective(
    arm: Arm,
    phi: np.ndarray,
    target: np.ndarray,
    rest: np.ndarray,
    w_tar: float,
    w_reg: float,
    orientation: Orientation | None = None,
    w_rot: float = 0.0,
) -> float:
    """f(Phi), the assignment's objective (plus 1/2 w_rot |r|^2 with an ``orientation``)."""
    pose = _pose(arm, phi)
    dp = pose.tip - target
    dtheta = phi - rest
    f = 0.5 * w_tar * dp @ dp + 0.5 * w_reg * dtheta @ dtheta
    if orientation is not None:
        r = orientation_residual(orientation, tool_rotation(arm, pose))
        f = f + 0.5 * w_rot * r @ r
    return cast(float, f)


def objective_derivatives(
    arm: Arm,
    phi: np.ndarray,
    target: np.ndarray,
    rest: np.ndarray,
    w_tar: float,
    w_reg: float,
    hessian: bool = True,
    orientation: Orientation | None = None,
    w_rot: float = 0.0,
) -> tuple[float, np.ndarray, np.ndarray | None]:
    """f, its gradient g (n,) and Hessian H (n, n), as the assignment writes them, with the
    orientation term (exact gradient, Gauss-Newton Hessian) when ``orientation`` is given.

    With ``hessian=False`` (gradient descent needs none) H is returned as None.

    >>> arm = Arm.from_names([1, 1], axes=["z", "z"], direction="x")
    >>> f, g, H = objective_derivatives(arm, np.zeros(2), np.array([1.0, 1, 0]), np.zeros(2), 1e3, 1.0)
    >>> float(f), g.tolist(), H.tolist()
    (1000.0, [-2000.0, -1000.0], [[2001.0, 1000.0], [1000.0, 1.0]])
    """
    pose = _pose(arm, phi)
    dp = pose.tip - target
    dtheta = phi - rest
    jac = tip_jacobian(arm, pose)
    f = 0.5 * w_tar * dp @ dp + 0.5 * w_reg * dtheta @ dtheta
    g = w_tar * dp @ jac + w_reg * dtheta
    if orientation is not None:
        r, grad = orientation_gradient(orientation, arm, pose)
        f, g = f + 0.5 * w_rot * r @ r, g + w_rot * grad
    if not hessian:
        return float(f), g, None
    hess = point_hessian(arm, pose, arm.n - 1, link_point(pose, arm.n - 1, 1.0))
    H = w_tar * (jac.T @ jac + np.einsum("a,aij->ij", dp, hess)) + w_reg * np.eye(arm.n)
    if orientation is not None:
        _, jac_r = orientation_task(orientation, arm, pose)
        H = H + w_rot * jac_r.T @ jac_r
    return float(f), g, H


def newton_direction(H: np.ndarray, g: np.ndarray) -> np.ndarray | None:
    """-H^-1 g, with H's eigenvalues raised to a small positive floor where needed.

    Far from the target the term (e - e*) . P'' can make H indefinite; clamping its
    eigenvalues (a modified Newton step) keeps the step a descent direction instead
    of giving up. Returns None if H is not finite.
    """
    if not np.all(np.isfinite(H)):
        return None
    eigenvalues, vectors = np.linalg.eigh(H)
    floor = 1e-8 * max(float(np.abs(eigenvalues).max()), 1e-12)
    return cast("np.ndarray | None", -(vectors @ ((vectors.T @ g) / np.maximum(eigenvalues, floor))))


def _line_search(
    fun: Callable[[np.ndarray], float],
    x: np.ndarray,
    f0: float,
    direction: np.ndarray,
    slope: float,
    alpha: float,
    opts: NewtonOptions,
) -> tuple[np.ndarray | None, float, float]:
    """Backtrack from ``alpha`` until f(x + a d) <= f0 + 1e-4 a slope (Armijo).

    Returns the new point, its f and the step length taken (None, f0, a on failure).
    """
    biggest = np.max(np.abs(direction), initial=0.0)
    a = min(alpha, opts.max_turn / biggest) if biggest > 0 else alpha
    for _ in range(opts.halvings):
        candidate = x + a * direction
        fc = fun(candidate)
        if fc <= f0 + 1e-4 * a * slope:
            return candidate, fc, a
        a *= opts.shrink
    return None, f0, a


@dataclass(frozen=True)
class Objective:
    """The f of one solve: the arm, the target e*, the rest pose and the weights, bound once
    (and the target orientation with its weight w_rot, for a goal with one)."""

    arm: Arm
    target: np.ndarray
    rest: np.ndarray
    w_tar: float
    w_reg: float
    orientation: Orientation | None = None
    w_rot: float = 0.0

    def value(self, phi: np.ndarray) -> float:
        """f(Phi)."""
        return objective(self.arm, phi, self.target, self.rest, self.w_tar, self.w_reg, self.orientation, self.w_rot)

    def derivatives(self, phi: np.ndarray, hessian: bool = True) -> tuple[float, np.ndarray, np.ndarray | None]:
        """f, g and H (None without ``hessian``) at Phi: :func:`objective_derivatives`."""
        return objective_derivatives(
            self.arm, phi, self.target, self.rest, self.w_tar, self.w_reg, hessian, self.orientation, self.w_rot
        )


def gradient_descent(f: Objective, phi: np.ndarray, options: NewtonOptions) -> tuple[np.ndarray, float, int]:
    """GDLS from ``phi``: steepest descent with a warm-started Armijo line search, until |g| is
    below the tolerance, a search fails, or an iteration lowers f by less than the handover
    fraction. Returns the angles, their f and the iterations."""
    x = np.asarray(phi, dtype=float).copy()
    value = f.value(x)
    alpha = options.alpha
    iterations = 0
    for iterations in range(1, options.gd_iterations + 1):  # noqa: B007 (the count is returned after the loop)
        value, g, _ = f.derivatives(x, hessian=False)
        if np.linalg.norm(g) < options.tolerance:
            break
        x_new, f_new, alpha = _line_search(f.value, x, value, -g, -(g @ g), alpha, options)
        if x_new is None:
            break
        slow = value - f_new < options.handover * value
        x, value = x_new, f_new
        if slow:
            break
        alpha = min(options.alpha, 2.0 * alpha)  # warm start: the next search begins near this one
    return x, value, iterations


def newton_method(f: Objective, phi: np.ndarray, options: NewtonOptions) -> tuple[np.ndarray, int]:
    """NM from ``phi``: modified Newton directions (:func:`newton_direction`) with an Armijo line
    search from the full step, until |g| is below the tolerance or a direction or a search
    fails. Returns the angles and the iterations."""
    x = phi
    iterations = 0
    for iterations in range(1, options.nm_iterations + 1):  # noqa: B007 (the count is returned after the loop)
        value, g, H = f.derivatives(x)
        if np.linalg.norm(g) < options.tolerance:
            break
        assert H is not None  # derivatives() with the Hessian
        direction = newton_direction(H, g)
        if direction is None:
            break
        x_new, _, _ = _line_search(f.value, x, value, direction, g @ direction, 1.0, options)
        if x_new is None:
            break
        x = x_new
    return x, iterations


def newton_solve(
    arm: Arm,
    phi: np.ndarray,
    target: np.ndarray,
    rest: np.ndarray,
    w_tar: float,
    w_reg: float,
    options: NewtonOptions = NewtonOptions(),
    orientation: Orientation | None = None,
    w_rot: float = 0.0,
) -> NewtonResult:
    """Minimise f by GDLS, then NM from the GDLS answer, kept only if it lowers f.

    Angles are returned unwrapped; callers wrap unlimited joints.
    """
    f = Objective(arm, target, rest, w_tar, w_reg, orientation, w_rot)
    x_gd, f_gd, gd_its = gradient_descent(f, phi, options)
    x_nm, nm_its = newton_method(f, x_gd, options)
    f_nm = f.value(x_nm)
    kept = f_nm < f_gd
    return NewtonResult(
        phi=x_nm if kept else x_gd,
        f=f_nm if kept else f_gd,
        gd_iterations=gd_its,
        nm_iterations=nm_its,
        newton_kept=bool(kept),
    )


def rotation_weight(problem: Problem, orientation: Orientation) -> float:
    """w_rot = w_tar w^2, scaled by the cost gains' ``priority_weight`` for an arm that cannot hold the orientation."""
    s = problem.solver
    w_rot = s.w_target * s.orientation_weight**2
    return w_rot if holds_orientation(problem.arm, orientation) else problem.tunables.cost.priority_weight * w_rot


def frame_orientation(problem: Problem, state: ArmState, orientation: Orientation) -> Orientation:
    """The frame's target orientation: the tool turned part of the way to the goal's, as the
    frame's target position e + de is (beta of the rotation, as long as ``max_step`` allows)."""
    rot = tool_rotation(problem.arm, state.pose)
    r = orientation_residual(orientation, rot)
    w = problem.solver.orientation_weight
    return partial_orientation(orientation, rot, rotation_displacement(problem, r) / w)


def newton_step(problem: Problem, state: ArmState, goal: np.ndarray, orientation: Orientation | None = None) -> Step:
    """One frame: solve f to the frame target e* = e + de (and the frame's orientation),
    regularised to the current pose."""
    arm, s = problem.arm, problem.solver
    phi, tip = state.phi, state.tip
    target = tip + task_displacement(problem, tip, goal)
    if orientation is None:
        result = newton_solve(arm, phi, target, phi, s.w_target, s.w_regularizer)
    else:
        result = newton_solve(
            arm,
            phi,
            target,
            phi,
            s.w_target,
            s.w_regularizer,
            orientation=frame_orientation(problem, state, orientation),
            w_rot=rotation_weight(problem, orientation),
        )
    return Step(
        dphi=result.phi - phi,
        iterations=result.gd_iterations + result.nm_iterations,
        newton_iterations=result.nm_iterations,
    )
