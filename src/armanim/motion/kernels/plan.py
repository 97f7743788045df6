"""Whether a step runs compiled, decided in one place (:func:`compiled_plan`).

Pure core: no numba is loaded here (the kernels are imported where a solve starts).
"""

from __future__ import annotations

from typing import Literal, NamedTuple

from armanim.motion.kernels.layout import DLS, PINV
from armanim.motion.orientation import Orientation
from armanim.motion.problem import Problem
from armanim.motion.solvers import Method
from armanim.motion.solvers.linear import arm_holds_orientation, stacks_the_pose_task

Loop = Literal["attempt", "frame"]
"""The two compiled loops: an IK attempt's steps (:mod:`armanim.motion.kernels.attempt`) and a frame
of the frame loop (:mod:`armanim.motion.kernels.frame`)."""


class CompiledPlan(NamedTuple):
    """How a step runs compiled: the inverse (:data:`~armanim.motion.kernels.layout.PINV` or
    :data:`~armanim.motion.kernels.layout.DLS`) and whether the pose task is stacked (position and
    rotation in one pseudo-inverse, :func:`armanim.motion.solvers.linear.stacks_the_pose_task`)."""

    step: int
    stacked: bool


def compiled_plan(problem: Problem, method: Method, orientation: Orientation | None, loop: Loop) -> CompiledPlan | None:
    """How a step of ``method`` toward a goal of this kind (``orientation``: None, a rotation or a
    tool axis) runs compiled in ``loop``, or None where the numpy line takes it. Judged once per
    problem, method, kind of goal and loop (kept in :attr:`~armanim.motion.problem.Problem.compiled_plans`).

    Both loops need a method with a compiled inverse (``pinv``, ``dls``) and the analytic Jacobian
    (an arm's prismatic joints included: the kernels read each joint's kind,
    :func:`armanim.arm.kernel.joint_slides`, and cap its step in metres).

    - ``attempt``: ``tunables.ik.compiled``, no obstacles, and an arm that can hold the goal's
      orientation (one that cannot turns the tool second, in what the position leaves: near its
      rank drops the numpy steps amplify rounding, and no other arithmetic could follow them there);
    - ``frame``: ``tunables.ik.compiled_frames``, and the rotation second in priority (not a ``pinv``
      solve's stacked pose task).
    """
    memo = problem.compiled_plans
    key = (loop, method.compiled_inverse, 0 if orientation is None else orientation.rows)
    if key not in memo:
        memo[key] = _plan(problem, method, orientation, loop)
    return memo[key]


def _plan(problem: Problem, method: Method, orientation: Orientation | None, loop: Loop) -> CompiledPlan | None:
    """:func:`compiled_plan`, judged."""
    if method.compiled_inverse is None or problem.solver.jacobian == "numeric":
        return None
    step = PINV if method.compiled_inverse == "pinv" else DLS
    stacked = step == PINV and orientation is not None and stacks_the_pose_task(problem, orientation)
    if loop == "frame":
        return CompiledPlan(step, False) if problem.tunables.ik.compiled_frames and not stacked else None
    if not problem.tunables.ik.compiled or len(problem.obstacles):
        return None
    if orientation is not None and not arm_holds_orientation(problem, orientation):
        return None
    return CompiledPlan(step, stacked)
