"""One filtered step of a method: its proposal through the safety filter, compiled where it can be.

The frame loop (:mod:`armanim.motion.trajectory`) and a path's samples
(:mod:`armanim.motion.following`) take each step as the method's proposal
(:func:`armanim.motion.solvers.proposed_step`) through the filter
(:func:`armanim.motion.solvers.barrier.safe_step`); for ``pinv`` and ``dls`` with the analytic
Jacobian, the compiled frame (:mod:`armanim.motion.solvers.compiled_frame`) takes the same step
to rounding, unless ``tunables.ik.compiled_frames`` is off. Pure core: no I/O; numba is imported
at the first compiled step, not with this module.
"""

from __future__ import annotations

import numpy as np

from armanim.motion.orientation import Orientation
from armanim.motion.problem import Problem
from armanim.motion.solvers import ArmState, Method, proposed_step
from armanim.motion.solvers.barrier import SafeStep, safe_step
from armanim.motion.solvers.linear import stacks_the_pose_task


def steps_compiled(problem: Problem, method: Method, orientation: Orientation | None = None) -> bool:
    """Whether the method's steps toward a goal (with ``orientation``) run compiled: a method with
    a compiled step (``pinv``, ``dls``), the analytic Jacobian, ``tunables.ik.compiled_frames``, and
    the rotation second in priority (not a ``pinv`` solve's stacked pose task,
    :func:`~armanim.motion.solvers.linear.stacks_the_pose_task`), on an arm of revolute joints
    (a prismatic joint's steps are the numpy ones)."""
    if (method.compiled_inverse is None or problem.solver.jacobian == "numeric" or not problem.tunables.ik.compiled_frames
            or problem.arm.prismatic is not None):
        return False
    return orientation is None or method.compiled_inverse != "pinv" or not stacks_the_pose_task(problem, orientation)


def method_step(problem: Problem, method: Method, state: ArmState, goal: np.ndarray,
                orientation: Orientation | None = None) -> tuple[SafeStep, int, int]:
    """The method's proposal toward ``goal`` (and ``orientation``) through the filter, and its
    iterations and Newton iterations."""
    if steps_compiled(problem, method, orientation):
        from armanim.motion.solvers.compiled_frame import frame_step  # numba: imported where a solve starts

        assert method.compiled_inverse is not None  # steps_compiled
        moved, dphi = frame_step(problem, method.compiled_inverse, state, goal, orientation)
        if moved is not None:
            return moved, 1, 0
        if dphi is not None:  # the numpy filter takes the compiled proposal
            return safe_step(problem, state, dphi), 1, 0
    proposal = proposed_step(problem, method, state, goal, orientation)
    return safe_step(problem, state, proposal.dphi, proposal.ahead), proposal.iterations, proposal.newton_iterations
