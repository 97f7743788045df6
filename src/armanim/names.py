"""The words of settings and results, each a ``Literal`` written once.

The scene model (:mod:`armanim.scene.models`) validates a scene's words against them, the
pure core types its settings and results with them; this module imports neither side.

>>> from typing import get_args
>>> get_args(MethodName)
('pinv', 'dls', 'newton', 'gradient')
"""

from __future__ import annotations

from typing import Literal

MethodName = Literal["pinv", "dls", "newton", "gradient"]
"""``solver.method``: the solver methods (the registry is :data:`armanim.motion.solvers.METHODS`)."""

JacobianMode = Literal["analytic", "numeric"]
"""``solver.jacobian``: analytic derivatives, or forward differences (the course notes' Eq. 15)."""

PlannerMode = Literal["auto", "off"]
"""``solver.planner``: plan a way out of a stall, or keep the pure local method."""

VideoFormat = Literal["mp4", "gif"]
RobotLook = Literal["mesh", "capsules", "both"]
"""How a robot with visual meshes is drawn (``render.robot``)."""
"""``render.format``."""

MissReason = Literal[
    "out_of_reach",
    "no_free_pose",
    "no_path",
    "blocked_by_obstacle",
    "blocked_by_limit",
    "stalled",
    "too_slow",
    "numerical",
    "orientation_unreachable",
    "path_blocked",
]
"""Why a goal of a run was missed (explained by :data:`armanim.motion.solution.MISS_REASONS`)."""

PoseStatus = Literal["converged", "not_converged", "numerical"]

PoseFinder = Literal["method", "free_pose_search"]
"""Who found the pose of ``armanim ik``: the scene's method, or the planner's free-pose search after it."""
"""How one pose solved to convergence (``armanim ik``) ended: within the tolerance; not
within it when the iterations or restarts ran out; or a linear-algebra failure (NaN, a
singular matrix, an SVD that did not converge) kept it from getting there."""

PathCause = Literal["out_of_reach", "joint_limit", "obstacle", "self_collision", "singular", "jump", "orientation"]
"""Why a path goal's tool stopped short of the path's end (``path_blocked``; explained by
:data:`armanim.motion.solution.PATH_CAUSES`)."""

Blocker = Literal["obstacle", "limit", "nan"]
"""What made the safety filter change a method's proposal (``nan``: it was not finite)."""

PathSource = Literal["straight", "rrt_connect", "none"]
"""How a plan connected the arm to a goal pose."""
