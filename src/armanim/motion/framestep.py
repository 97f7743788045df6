"""One filtered step of a method: its proposal through the safety filter, compiled where it can be.

The frame loop (:mod:`armanim.motion.trajectory`) and a path's samples
(:mod:`armanim.motion.paths.following`) take each step as the method's proposal
(:func:`armanim.motion.solvers.proposed_step`) through the filter
(:func:`armanim.motion.filter.barrier.safe_step`); for ``pinv`` and ``dls`` with the analytic
Jacobian, the compiled frame (:mod:`armanim.motion.kernels.frame`) takes the same step
to rounding, unless ``tunables.ik.compiled_frames`` is off (:func:`armanim.motion.kernels.plan.compiled_plan`). Pure core: no I/O; numba is imported
at the first compiled step, not with this module.
"""

from __future__ import annotations

import numpy as np

from armanim.motion.filter.barrier import SafeStep, safe_step
from armanim.motion.kernels.plan import compiled_plan
from armanim.motion.orientation import Orientation
from armanim.motion.problem import Problem
from armanim.motion.solvers import ArmState, Method, proposed_step


def method_step(
    problem: Problem, method: Method, state: ArmState, goal: np.ndarray, orientation: Orientation | None = None
) -> tuple[SafeStep, int, int]:
    """The method's proposal toward ``goal`` (and ``orientation``) through the filter, and its
    iterations and Newton iterations."""
    if compiled_plan(problem, method, orientation, "frame") is not None:
        from armanim.motion.kernels.frame import frame_step  # numba: imported where a solve starts

        assert method.compiled_inverse is not None  # a compiled plan
        moved, dphi = frame_step(problem, method.compiled_inverse, state, goal, orientation)
        if moved is not None:
            return moved, 1, 0
        if dphi is not None:  # the numpy filter takes the compiled proposal
            return safe_step(problem, state, dphi), 1, 0
    proposal = proposed_step(problem, method, state, goal, orientation)
    return safe_step(problem, state, proposal.dphi, proposal.ahead), proposal.iterations, proposal.newton_iterations
