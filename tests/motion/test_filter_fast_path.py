"""The safety filter's fast path (:func:`armanim.motion.filter.barrier.clearly_allowed`): when it
says a proposal meets every constraint by bounds alone, the constraints it did not build agree."""

from __future__ import annotations

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from strategies import cluttered_problems, robot_problems

from armanim.motion.filter.barrier import clearly_allowed, filter_constraints, filtered_step
from armanim.motion.solvers.common import arm_state


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(st.one_of(cluttered_problems(), robot_problems()), st.data())
def test_a_clearly_allowed_step_is_the_step_the_filter_takes(problem, data):
    rng = np.random.default_rng(data.draw(st.integers(0, 2**32 - 1)))
    for _ in range(20):
        phi = np.clip(
            problem.home + rng.normal(0.0, 0.3, problem.arm.n), problem.limits.lower + 1e-3, problem.limits.upper - 1e-3
        )
        state = arm_state(problem, phi)
        nominal = rng.normal(0.0, 1.0, problem.arm.n) * problem.solver.max_joint_step * rng.choice([1e-3, 0.1, 1.0])
        nominal *= min(1.0, problem.solver.max_joint_step / np.abs(nominal).max())
        cons = filter_constraints(problem, state, nominal)
        if clearly_allowed(problem, state, nominal):
            assert cons.violated_by(nominal) is None
            assert filtered_step(nominal, cons) is nominal


def test_the_fast_path_is_taken_far_from_every_barrier_and_not_at_one():
    from armanim.arm.kinematics import Arm
    from armanim.motion.problem import Goal, Limits, Problem
    from armanim.scene import default_solver_settings
    from armanim.world.obstacles import Obstacles

    arm = Arm.from_names([2, 5, 5, 5], base=(5, 5, 0))
    limits = Limits(np.radians([-170.0, -100, -150, -150]), np.radians([170.0, 100, 150, 150]), np.radians(15.0))
    far = Obstacles(np.array([[30.0, 30, 30]]), np.ones(1), np.full(1, 2.0))
    problem = Problem(
        arm=arm,
        half_width=0.3,
        home=np.zeros(4),
        limits=limits,
        obstacles=far,
        goals=(Goal(np.array([8.0, 8, 8]), hold=0.0),),
        solver=default_solver_settings(clearance=0.05),
        fps=30.0,
    )
    state = arm_state(problem, np.radians([0.0, 20, 30, 30]))
    small = np.full(4, 1e-3)
    assert clearly_allowed(problem, state, small)
    near_limit = arm_state(problem, np.radians([0.0, 99.5, 30, 30]))
    assert not clearly_allowed(problem, near_limit, np.array([0.0, 1e-2, 0, 0]))  # toward the limit, inside its buffer
