"""``armanim ik``'s pinv step on a goal the arm can hold: the stacked pose task [J_v; w J_w] in one
pseudo-inverse is the task-priority step (position first, the rotation in its null space) it
replaces, to rounding, wherever the stacked Jacobian has full row rank."""

from __future__ import annotations

import numpy as np
import pytest

from armanim.arm.kinematics import forward, tool_rotation
from armanim.arm.linalg import pseudo_inverse
from armanim.motion.ik import solve_pose, solving_problem
from armanim.motion.orientation import Orientation
from armanim.motion.solvers.common import arm_state
from armanim.motion.solvers.linear import linear_step, pinv_step, stacks_the_pose_task
from armanim.scene import scene_model, scene_to_problem


def robot(name: str, method: str = "pinv"):
    return scene_to_problem(
        scene_model(
            {
                "version": 1,
                "arm": {"robot": name},
                "goals": [[0.4, 0.0, 0.4]],
                "solver": {"method": method, "tolerance": 0.001, "orientation_tolerance": 1},
            }
        )
    )


@pytest.mark.parametrize("name", ["panda", "ur5", "iiwa"])
def test_the_stacked_step_is_the_task_priority_step(name):
    problem = solving_problem(robot(name))
    rng = np.random.default_rng(40)
    lo, hi = np.maximum(problem.limits.lower, -np.pi) + 0.2, np.minimum(problem.limits.upper, np.pi) - 0.2
    compared = 0
    for _ in range(30):
        phi, target = rng.uniform(lo, hi), rng.uniform(lo, hi)
        goal = forward(problem.arm, target)
        orientation = Orientation(rotation=tool_rotation(problem.arm, goal))
        state = arm_state(problem, phi)
        assert stacks_the_pose_task(problem, orientation)
        stacked = linear_step(problem, state, goal.tip, pseudo_inverse, orientation, stackable=True).dphi
        priority = linear_step(problem, state, goal.tip, pseudo_inverse, orientation, stackable=False).dphi
        if _well_conditioned(problem, state):
            np.testing.assert_allclose(stacked, priority, atol=1e-9 * max(1.0, np.abs(priority).max()), rtol=0)
            compared += 1
        assert np.array_equal(pinv_step(problem, state, goal.tip, orientation).dphi, stacked)
    assert compared >= 20


def _well_conditioned(problem, state) -> bool:
    from armanim.arm import kernel

    jac = kernel.geometric_jacobian(state.pose)
    jac[3:] *= problem.solver.orientation_weight
    return bool(np.linalg.cond(jac) < 1e4)


def test_the_frame_loop_keeps_the_task_priority():
    problem = robot("panda")  # not a solve to convergence: trajectories are what they were
    assert not stacks_the_pose_task(problem, Orientation(rotation=np.eye(3)))


def test_an_arm_that_cannot_hold_every_orientation_keeps_the_priority():
    problem = solving_problem(
        scene_to_problem(scene_model({"version": 1, "arm": {"links": [2, 5, 5, 5]}, "goals": [[3, 3, 3]]}))
    )
    assert not stacks_the_pose_task(problem, Orientation(rotation=np.eye(3)))


def test_ik_reaches_6d_panda_goals_with_the_stacked_step():
    problem = robot("panda")
    rng = np.random.default_rng(7)
    lo, hi = problem.limits.lower + 0.3, problem.limits.upper - 0.3
    converged = 0
    for _ in range(6):
        target = forward(problem.arm, rng.uniform(lo, hi))
        orientation = Orientation(rotation=tool_rotation(problem.arm, target))
        solution = solve_pose(problem, target.tip, problem.home, 2000, orientation=orientation)
        if solution.status == "converged":
            converged += 1
            assert solution.distance < 1e-3 and solution.orientation_error < np.radians(1.0)
            reached = forward(problem.arm, solution.phi)  # judged by the numpy chain, not the solver's own
            assert np.linalg.norm(reached.tip - target.tip) < 1e-3
    assert converged >= 5
