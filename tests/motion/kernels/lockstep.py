"""The lockstep harness of the compiled motion kernels: each piece (the inverses, the proposal,
the filter's QP, the exact check's gaps, the attempt's step, the frame) computed by each line,
numpy and compiled, through one adapter per piece, and held to the numpy oracle by one
tolerance helper (:func:`assert_agree`).

The numpy line runs through the same test bodies as the compiled one (toppra's way with its
backends): what the body asks of a line is then asked of the reference too, so a tolerance or an
adapter that hid a difference would show on the numpy line first. Its answers are the oracle's
bit for bit except where the body says otherwise (the filter's QP, whose oracle is its KKT
conditions).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from armanim.arm.kinematics import forward, tip_jacobian
from armanim.arm.linalg import PINV_RTOL, pseudo_inverse
from armanim.motion.cost import self_influence
from armanim.motion.orientation import Orientation, orientation_task
from armanim.motion.problem import Problem
from armanim.motion.solvers.common import ArmState, jacobian_of_capsule_point, self_pair_jacobians

LINES = ("numpy", "compiled")
"""The two lines every piece is computed by."""


def agree(got: np.ndarray, want: np.ndarray, tol: float) -> bool:
    """Whether ``got`` is ``want`` to ``tol`` times the size of ``want`` (its largest finite
    entry, at least 1), with the same entries not finite (those not compared)."""
    a, b = np.asarray(got, dtype=float), np.asarray(want, dtype=float)
    if a.shape != b.shape or not np.array_equal(np.isfinite(a), np.isfinite(b)):
        return False
    both = np.isfinite(a)
    scale = max(1.0, float(np.abs(np.where(both, b, 0.0)).max(initial=0.0)))
    with np.errstate(invalid="ignore"):  # inf - inf where neither is finite: not compared
        return bool(np.all(np.abs(np.where(both, a - b, 0.0)) <= tol * scale))


def assert_agree(got: np.ndarray, want: np.ndarray, tol: float, what: object = "") -> None:
    """The harness's one tolerance: :func:`agree`, with the largest difference in the message."""
    if not agree(got, want, tol):
        a, b = np.asarray(got, dtype=float), np.asarray(want, dtype=float)
        worst = float(np.nanmax(np.abs(a - b))) if a.shape == b.shape else float("nan")
        raise AssertionError(f"{what}: differ by {worst:.3g} (allowed {tol:.3g} x scale)\n got {a!r}\nwant {b!r}")


def numpy_only(problem: Problem) -> Problem:
    """The problem with both compiled lines off (the oracle: the IK attempt's and the frame's)."""
    ik = replace(problem.tunables.ik, compiled=False, compiled_frames=False)
    return replace(problem, tunables=replace(problem.tunables, ik=ik))


def condition(matrix: np.ndarray, scale: float = 0.0) -> float:
    """Largest singular value over the least one the pseudo-inverse keeps (1 at least); with
    ``scale``, the size its entries' rounding is relative to, at least ``scale`` over that least
    value: a matrix made from a larger one (the rotation task in the tip task's null space, whose
    projector rounds at the rotation task's size) can keep a singular value far below that
    rounding's scale, and its inverse carries the rounding up by their ratio (27e8a7b: a 4-joint
    arm with a tool axis, 5.9e-4 against 6.0)."""
    d = np.linalg.svd(matrix, compute_uv=False)
    kept = d[d > PINV_RTOL * d[0]] if len(d) and d[0] > 0 else d[:0]
    return max(1.0, float(kept[0] / kept[-1]), float(scale / kept[-1])) if len(kept) else 1.0


def damped_condition(matrix: np.ndarray, damping: float) -> float:
    """Condition number of M M^T + lambda^2 I, what the damped inverse solves with (m x m)."""
    d = np.linalg.svd(matrix, compute_uv=False)
    eig = np.zeros(matrix.shape[0])
    eig[: len(d)] = d * d
    return float((eig.max() + damping**2) / (eig.min() + damping**2))


def conditioning(problem: Problem, state: ArmState, orientation: Orientation | None) -> float:
    """Of the tasks a step inverts, in turn: the tip's Jacobian; for a goal with an orientation,
    the rotation task in the tip task's null space (w B J_w (I - J^+ J)), which acts on the first's
    rounding; the Jacobians of the points the obstacles and the arm's own pairs push, projected
    through both. Each stage's condition number (for ``dls`` also its damped Gram matrix's; for
    the rotation task, relative to its size before the projection: :func:`condition`), their
    product: what rounding in one stage may be multiplied by in the next."""
    dls = problem.solver.method == "dls"

    def stage(tasks: list[np.ndarray], scale: float = 0.0) -> float:
        kappa = max((condition(task, scale) for task in tasks), default=1.0)
        if dls:
            kappa = max([kappa] + [damped_condition(task, problem.solver.damping) for task in tasks])
        return kappa

    jac = tip_jacobian(problem.arm, state.pose)
    kappa = stage([jac])
    if orientation is not None:
        _, jac_w = orientation_task(orientation, problem.arm, state.pose)
        jac_r = problem.solver.orientation_weight * jac_w
        kappa *= stage([jac_r @ (np.eye(problem.arm.n) - pseudo_inverse(jac) @ jac)], float(np.linalg.norm(jac_r, 2)))
    pushed = []
    cl = state.clearance
    if cl is not None:  # the links pushed off obstacles: each point's Jacobian is inverted
        parts, columns = np.nonzero((cl.d[:-1] > 0) & (cl.d[:-1] < problem.obstacles.influence))
        pushed.extend(jacobian_of_capsule_point(problem, state.phi, state.pose, parts, cl.t[parts, columns]))
    gaps = state.self_gaps
    if gaps is not None:  # the pairs pushed apart: each J_A - J_B is inverted
        which = np.nonzero((gaps.d > 0) & (gaps.d < self_influence(problem)))[0]
        pushed.extend(self_pair_jacobians(problem, state.phi, state.pose, gaps, which))
    return kappa * stage(pushed)


def tip_condition(problem: Problem, phi: np.ndarray) -> float:
    """The condition number of the tip's Jacobian at ``phi`` (its singular values that the
    pseudo-inverse keeps), at least 1: how much a step's rounding may grow."""
    return condition(tip_jacobian(problem.arm, forward(problem.arm, phi)))
