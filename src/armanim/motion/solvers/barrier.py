"""The names :mod:`armanim.motion.kernels` imports from the filter's old place: the filter is
:mod:`armanim.motion.filter.barrier`, its clearance policy :mod:`armanim.motion.filter.clearance`. Kept only until the kernels import it from there (the one
import back up that :data:`tests.system.test_core_imports.MOTION_UPWARD` allows)."""

from armanim.motion.filter.barrier import (
    BOUND_SLACK,
    VIOLATION,
    Constraints,
    SafeStep,
    blocker,
    filtered_step,
    step_fraction,
    wrap_unlimited,
)
from armanim.motion.filter.clearance import kept_clearance, kept_self_clearance, limit_buffer

__all__ = ["BOUND_SLACK", "VIOLATION", "Constraints", "SafeStep", "blocker", "filtered_step", "kept_clearance",
           "kept_self_clearance", "limit_buffer", "step_fraction", "wrap_unlimited"]
