"""The cost C(Phi) of the notes (Eqs. 10-12): its pieces' values and its gradient."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st
from strategies import problems

from armanim.arm.capsules import joint_capsules
from armanim.arm.kinematics import Arm, forward
from armanim.motion.cost import (
    goal_term,
    limit_barrier,
    limit_barrier_gradient,
    obstacle_field,
    obstacle_field_slope,
    total_cost,
    total_cost_gradient,
)
from armanim.motion.problem import Goal, Limits, Problem
from armanim.scene import default_solver_settings
from armanim.world.distances import clearances, min_link_clearance
from armanim.world.obstacles import Obstacles

# ------------------------------------------------------------ F_R (Eq. 11)


@pytest.mark.parametrize(
    "d, R, expected",
    [
        (1.0, np.e, 1.0),
        (0.5, 2.0, np.log(4.0)),
        (2.0, 2.0, 0.0),  # d = R: ln 1
        (2.5, 2.0, 0.0),  # beyond R: vanishes
        (10.0, 10.0, 0.0),
        (1e-6, 1.0, np.log(1e6)),
    ],
)
def test_obstacle_field_values(d, R, expected):
    assert float(obstacle_field(np.array(d), np.array(R))) == pytest.approx(expected, abs=1e-12)


@pytest.mark.parametrize("d", [0.0, -0.1, -5.0])
def test_obstacle_field_is_infinite_at_and_inside_contact(d):
    assert float(obstacle_field(np.array(d), np.array(1.0))) == np.inf


def test_obstacle_field_broadcasts_over_obstacles():
    d = np.array([[0.5, 3.0], [1.0, 0.25]])
    R = np.array([1.0, 1.0])
    np.testing.assert_allclose(obstacle_field(d, R), [[np.log(2), 0.0], [0.0, np.log(4)]])


@given(st.floats(0.01, 5.0), st.floats(0.1, 5.0))
def test_obstacle_field_slope_is_its_derivative(d, R):
    assume(abs(d - R) > 1e-3)
    h = 1e-7
    fd = (obstacle_field(np.array(d + h), np.array(R)) - obstacle_field(np.array(d - h), np.array(R))) / (2 * h)
    assert float(obstacle_field_slope(np.array(d), np.array(R))) == pytest.approx(float(fd), rel=1e-5, abs=1e-7)


# ------------------------------------------------------------ L (Eq. 12)


def one_joint(lo, hi, delta):
    return Limits(np.array([lo]), np.array([hi]), margin=delta)


@pytest.mark.parametrize(
    "phi, expected",
    [
        (1.25, np.log(0.5 / 0.25)),  # near min: ln(delta / (phi - phi_min)) = ln 2, NOT ln(phi/(phi-min)) = ln 5
        (1.1, np.log(0.5 / 0.1)),
        (1.5, 0.0),  # exactly delta from min
        (2.0, 0.0),  # middle
        (2.5, 0.0),  # exactly delta from max
        (2.9, np.log(0.5 / 0.1)),  # near max: ln(delta / (phi_max - phi))
        (2.75, np.log(2.0)),
    ],
)
def test_limit_barrier_values_follow_the_notes_not_the_notebook(phi, expected):
    lim = one_joint(1.0, 3.0, 0.5)
    assert float(limit_barrier(np.array([phi]), lim)) == pytest.approx(expected, abs=1e-12)


def test_limit_barrier_is_not_the_notebook_formula():
    lim = one_joint(1.0, 3.0, 0.5)
    buggy = np.log(1.25 / (1.25 - 1.0))  # the notebook's phi / (phi - phi_min)
    assert float(limit_barrier(np.array([1.25]), lim)) != pytest.approx(buggy)


@pytest.mark.parametrize("phi", [1.0, 0.9, -4.0, 3.0, 3.2])
def test_limit_barrier_is_infinite_at_and_past_a_limit(phi):
    assert float(limit_barrier(np.array([phi]), one_joint(1.0, 3.0, 0.5))) == np.inf


def test_limit_barrier_sums_limited_joints_and_ignores_unlimited():
    lim = Limits(np.array([-1.0, -np.inf, 0.0]), np.array([1.0, np.inf, 2.0]), margin=0.5)
    phi = np.array([0.75, 100.0, 0.25])
    assert float(limit_barrier(phi, lim)) == pytest.approx(np.log(2.0) + np.log(2.0))
    batch = np.array([phi, [0.0, -50.0, 1.0]])
    np.testing.assert_allclose(limit_barrier(batch, lim), [2 * np.log(2.0), 0.0])


@given(st.floats(-0.999, 0.999), st.floats(0.05, 0.8))
def test_limit_barrier_gradient_matches_central_differences(phi, delta):
    lim = one_joint(-1.0, 1.0, delta)
    gap = min(phi + 1.0, 1.0 - phi)
    assume(abs(gap - delta) > 1e-4)
    h = 1e-8
    fd = (limit_barrier(np.array([phi + h]), lim) - limit_barrier(np.array([phi - h]), lim)) / (2 * h)
    assert float(limit_barrier_gradient(np.array([phi]), lim)[0]) == pytest.approx(float(fd), rel=1e-5, abs=1e-6)


# ------------------------------------------------------------ clearances


def test_clearance_of_capsules_and_tip():
    arm = Arm.from_names([2.0], axes=["z"], direction="x")  # one link from (0,0,0) to (2,0,0)
    obstacles = Obstacles(np.array([[1.0, 3.0, 0.0], [4.0, 0.0, 0.0]]), np.array([1.0, 0.5]), np.array([1.0, 1.0]))
    cl = clearances(forward(arm, np.zeros(1)), obstacles, joint_capsules(arm, 0.25))
    # link capsule: distance from segment minus obstacle radius minus half width
    np.testing.assert_allclose(cl.d[0], [3.0 - 1.0 - 0.25, 2.0 - 0.5 - 0.25])
    # the tip is a point: no half width
    np.testing.assert_allclose(cl.d[1], [np.hypot(1.0, 3.0) - 1.0, 2.0 - 0.5])
    np.testing.assert_allclose(cl.t[0], [0.5, 1.0])
    np.testing.assert_allclose(cl.normal[0, 0], [0.0, -1.0, 0.0])
    assert float(min_link_clearance(forward(arm, np.zeros(1)), obstacles, joint_capsules(arm, 0.25))) == pytest.approx(
        1.25
    )


def test_min_link_clearance_without_obstacles_is_infinite():
    arm = Arm.from_names([1.0, 1.0])
    assert np.all(
        np.isinf(min_link_clearance(forward(arm, np.zeros((3, 2))), Obstacles.none(), joint_capsules(arm, 0.1)))
    )


# ------------------------------------------------------------ the total cost


def notes_problem(**solver):
    arm = Arm.from_names([2, 5, 5, 5], base=(5, 5, 0))
    return Problem(
        arm=arm,
        half_width=0.3,
        home=np.zeros(4),
        limits=Limits(
            np.radians([-np.inf, -100, -150, -150]), np.radians([np.inf, 100, 150, 150]), float(np.radians(15))
        ),
        obstacles=Obstacles(np.array([[12.0, 9, 8]]), np.array([2.0]), np.array([2.0])),
        goals=(Goal(np.array([14.0, 5, 6]), hold=0.0),),
        solver=default_solver_settings(**solver),
        fps=30.0,
    )


def test_total_cost_is_the_sum_of_its_weighted_terms():
    problem = notes_problem(w_goal=2.0, w_obstacles=3.0, w_limits=5.0)
    goal = problem.goals[0].position
    phi = np.radians([30.0, 40.0, 60.0, 140.0])
    pose = forward(problem.arm, phi)
    cl = clearances(pose, problem.obstacles, problem.capsules)
    expected = (
        2.0 * np.linalg.norm(pose.tip - goal)
        + 3.0 * obstacle_field(cl.d, problem.obstacles.influence).sum()
        + 5.0 * float(limit_barrier(phi, problem.limits))
    )
    assert float(total_cost(problem, phi, goal)) == pytest.approx(expected, rel=1e-12)
    assert float(limit_barrier(phi, problem.limits)) > 0  # the limit term is active at 140 of 150 deg
    assert float(goal_term(pose.tip, goal)) == pytest.approx(np.linalg.norm(pose.tip - goal))


def test_total_cost_is_infinite_past_a_limit_and_in_contact():
    problem = notes_problem()
    goal = problem.goals[0].position
    assert float(total_cost(problem, np.radians([0.0, 100.0, 0, 0]), goal)) == np.inf
    # put an obstacle on the home pose's tip
    inside = replace(problem, obstacles=Obstacles(np.array([[5.0, 5, 17]]), np.array([0.5]), np.array([1.0])))
    assert float(total_cost(inside, np.zeros(4), goal)) == np.inf


def smooth_at(problem: Problem, phi: np.ndarray, goal: np.ndarray, margin: float = 1e-3) -> bool:
    """False near the kinks of C: an influence edge, a limit margin edge, the goal itself."""
    pose = forward(problem.arm, phi)
    if np.linalg.norm(pose.tip - goal) < margin:
        return False
    if len(problem.obstacles):
        d = clearances(pose, problem.obstacles, problem.capsules).d
        if np.any(d <= 0.05) or np.any(np.abs(d - problem.obstacles.influence) < margin):
            return False
    lim = problem.limits
    for gap in (phi - lim.lower, lim.upper - phi):
        if np.any(gap <= 0.02) or np.any(np.abs(gap - lim.margin) < margin):
            return False
    return True


@given(problems(), st.data())
def test_total_cost_gradient_matches_central_differences(problem, data):
    phi = problem.home + np.array(
        data.draw(st.lists(st.floats(-0.3, 0.3), min_size=problem.arm.n, max_size=problem.arm.n))
    )
    goal = problem.goals[0].position
    assume(smooth_at(problem, phi, goal))
    analytic = total_cost_gradient(problem, phi, goal)
    h = 1e-6
    numeric = np.array(
        [
            (total_cost(problem, phi + h * e, goal) - total_cost(problem, phi - h * e, goal)) / (2 * h)
            for e in np.eye(problem.arm.n)
        ]
    )
    scale = max(1.0, float(np.abs(numeric).max()))
    np.testing.assert_allclose(analytic, numeric, atol=1e-5 * scale)


def test_total_cost_gradient_with_active_obstacle_and_limit():
    """A fixed pose where all three terms contribute (not left to chance)."""
    problem = notes_problem()
    arm = problem.arm
    phi = np.radians([10.0, 50.0, 40.0, 140.0])
    pose = forward(arm, phi)
    # an obstacle 0.5 from link 3's capsule, inside its influence
    mid = 0.5 * (pose.points[2] + pose.points[3])
    normal = np.cross(pose.points[3] - pose.points[2], [0.0, 0.0, 1.0])
    normal /= np.linalg.norm(normal)
    obstacles = Obstacles((mid + (1.0 + 0.3 + 0.5) * normal)[None], np.array([1.0]), np.array([2.0]))
    problem = replace(problem, obstacles=obstacles)
    goal = problem.goals[0].position
    assert smooth_at(problem, phi, goal)
    cl = clearances(pose, obstacles, problem.capsules)
    assert np.any(cl.d < obstacles.influence)
    h = 1e-6
    numeric = np.array(
        [(total_cost(problem, phi + h * e, goal) - total_cost(problem, phi - h * e, goal)) / (2 * h) for e in np.eye(4)]
    )
    np.testing.assert_allclose(total_cost_gradient(problem, phi, goal), numeric, atol=1e-5)
