"""The pure core's functions of docs/python-api.md given arguments no answer fits (campaign 16):
a clear ValueError saying what was expected, never an error from deep inside."""

from __future__ import annotations

import numpy as np
import pytest

from armanim.motion.ik import solve_pose
from armanim.motion.timing.retime import retime
from armanim.motion.trajectory import solve_trajectory
from armanim.scene import SceneModel, scene_to_problem

PROBLEM = scene_to_problem(
    SceneModel.model_validate({"version": 1, "arm": {"links": [1, 1, 1]}, "goals": [[1, 1, 1], [0.5, -1, 1]]})
)


@pytest.mark.parametrize("goal", [[1.0, 1.0], [1.0, 1.0, 1.0, 1.0], [[1.0, 1.0, 1.0]], 2.0])
def test_solve_pose_refuses_a_goal_that_is_not_a_point(goal):
    """Campaign 16: a goal of 2 or 4 numbers ended in numpy's "operands could not be broadcast
    together with shapes (3,) (2,)" from the pose error's code."""
    with pytest.raises(ValueError, match=r"goal: expected a point, 3 numbers"):
        solve_pose(PROBLEM, np.array(goal), PROBLEM.home)


@pytest.mark.parametrize("start", [np.zeros(2), np.zeros(4), np.zeros((1, 3)), np.float64(0.0)])
def test_solve_pose_refuses_a_start_that_is_not_one_angle_a_joint(start):
    with pytest.raises(ValueError, match=r"start: expected the angles of the arm's 3 joints"):
        solve_pose(PROBLEM, np.array([1.0, 1.0, 1.0]), start)


@pytest.mark.parametrize("fps", [0.0, -1.0, float("nan"), float("inf")])
def test_retime_refuses_a_rate_that_is_not_a_positive_finite_number(fps):
    """Campaign 16: ``retime(problem, solution, 0.0)`` ended in a ZeroDivisionError."""
    solution = solve_trajectory(PROBLEM)
    with pytest.raises(ValueError, match=r"fps: expected a positive, finite number"):
        retime(PROBLEM, solution, fps)
