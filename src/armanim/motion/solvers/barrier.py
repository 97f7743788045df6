"""The names :mod:`armanim.motion.kernels` imports from the filter's old place: the filter is
:mod:`armanim.motion.filter.barrier`. Kept only until the kernels import it from there (the one
import back up that :data:`tests.system.test_core_imports.MOTION_UPWARD` allows)."""

from armanim.motion.filter.barrier import (
    BOUND_SLACK,
    VIOLATION,
    Constraints,
    SafeStep,
    blocker,
    filtered_step,
    kept_clearance,
    kept_self_clearance,
    limit_buffer,
    step_fraction,
    wrap_unlimited,
)

__all__ = ["BOUND_SLACK", "VIOLATION", "Constraints", "SafeStep", "blocker", "filtered_step", "kept_clearance",
           "kept_self_clearance", "limit_buffer", "step_fraction", "wrap_unlimited"]
