"""The compiled pose-solve attempt (:mod:`armanim.motion.kernels.attempt`) whole: its solves meet the
tolerances by the numpy chain's FK, inside the limits and with the arm's own pairs apart, and
end as the numpy solves; a singular damped inverse, a near pair kept inside the call, a step
handed back to the numpy path and taken up again. Step by step, the attempt is held to the numpy
steps by the lockstep harness (tests/motion/kernels/test_lockstep.py)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from test_lockstep import ARMS, numpy_only, pair_qp, problem_of, robot, target_of

from armanim.arm.kinematics import forward, tool_rotation
from armanim.motion import ik
from armanim.motion.filter.clearance import within_limits
from armanim.motion.kernels import attempt
from armanim.motion.kernels.layout import PINV
from armanim.motion.orientation import orientation_angle
from armanim.motion.problem import Goal, Limits, Problem
from armanim.motion.solvers import solver_method
from armanim.motion.solvers.common import arm_state
from armanim.scene import default_solver_settings
from armanim.world.obstacles import Obstacles
from armanim.world.selfdistances import self_gaps


@settings(max_examples=30, deadline=None)
@given(
    name=st.sampled_from(sorted(ARMS)),
    method=st.sampled_from(["pinv", "dls"]),
    seed=st.integers(0, 2**31),
    kind=st.sampled_from(["pose", "axis", "position"]),
)
def test_compiled_solves_meet_the_tolerances_by_the_numpy_chain(name, method, seed, kind):
    problem = problem_of(name, method)
    goal, orientation, _ = target_of(problem, seed, kind)
    solution = ik.solve_pose(problem, goal, problem.home, 2000, orientation=orientation)
    if not solution.converged:
        return  # a miss is allowed (the notes' arm cannot hold every orientation); what converges must be right
    pose = forward(problem.arm, solution.phi)  # the numpy chain, not the kernel
    assert np.linalg.norm(pose.tip - goal) < problem.solver.tolerance
    np.testing.assert_allclose(solution.tip, pose.tip, atol=1e-12 * problem.arm.reach, rtol=0)
    if orientation is not None:
        assert (
            float(orientation_angle(orientation, tool_rotation(problem.arm, pose)))
            < problem.solver.orientation_tolerance
        )
    assert within_limits(problem, solution.phi[None])[0]
    if len(problem.self_pairs):
        assert self_gaps(pose, problem.capsules, problem.self_pairs).least >= problem.self_pairs.clearance


@pytest.mark.parametrize("name", ["panda", "ur5", "iiwa", "notes"])
@pytest.mark.parametrize("method", ["pinv", "dls"])
def test_compiled_solves_end_as_the_numpy_solves(name, method):
    problem = problem_of(name, method)
    oracle = numpy_only(problem)
    same = 0
    for seed in range(8):
        goal, orientation, _ = target_of(problem, seed, "position" if name == "notes" else "pose")
        got = ik.solve_pose(problem, goal, problem.home, 2000, orientation=orientation)
        expected = ik.solve_pose(oracle, goal, problem.home, 2000, orientation=orientation)
        assert got.status == expected.status
        if (got.steps, got.restarts, got.found_by) == (expected.steps, expected.restarts, expected.found_by):
            np.testing.assert_allclose(got.phi, expected.phi, atol=1e-7, rtol=0)
            same += 1
    assert same >= 7  # rounding may tip a stall test late in a long solve, rarely


def test_a_singular_damped_inverse_is_numerical_in_both():
    # dls without damping at the straight planar arm: J J^T is singular, numpy's solve raises,
    # the compiled elimination meets a zero pivot; both report the attempt as numerical
    from armanim.arm.kinematics import Arm

    problem = Problem(
        arm=Arm.from_names([1.0] * 3, axes=["z"] * 3, direction="x"),
        half_width=0.1,
        home=np.zeros(3),
        limits=Limits.unlimited(3, 0.1),
        obstacles=Obstacles.none(),
        goals=(Goal(np.array([1.0, 1.0, 0.0]), hold=0.0),),
        solver=default_solver_settings(method="dls", tolerance=1e-3, damping=0.0),
        fps=30.0,
    )
    for p in (problem, numpy_only(problem)):
        result = ik.solve_pose(p, np.array([1.0, 1.0, 0.0]), np.zeros(3), max_iterations=50)
        assert result.status == "numerical" and result.restarts == 4


def test_the_compiled_attempt_keeps_a_near_pair_inside_the_call():
    # from the Panda's home, link3 and link5 are 2.8 cm apart: the filter's row of that pair acts on
    # the first large step; the compiled loop solves that QP itself (it handed the attempt back before)
    problem = ik.solving_problem(robot("panda", "pinv"))
    goal, orientation, _ = target_of(problem, 0, "pose")
    state = arm_state(problem, problem.home)
    assert pair_qp(numpy_only(problem), solver_method("pinv"), goal, orientation, state) is not None
    ran = attempt.run_attempt(problem, PINV, True, goal, problem.home, 1, orientation)
    assert not ran.handed_back and ran.steps == 1


def test_a_numpy_step_hands_the_attempt_back_to_the_compiled_loop(monkeypatch):
    # the numpy path takes only the handed-back step: the compiled loop goes on from there
    problem = robot("panda", "pinv")
    calls = []
    run = attempt.run_attempt

    def spy(*args, **kwargs):
        calls.append(args[4])
        return run(*args, **kwargs)

    monkeypatch.setattr(ik, "_RUN_ATTEMPT", [spy])
    goal, orientation, _ = target_of(problem, 0, "pose")
    ik.solve_pose(problem, goal, problem.home, 2000, orientation=orientation)
    assert len(calls) > 1 and np.array_equal(calls[0], problem.home)
    state = arm_state(problem, calls[1])
    assert np.all(np.isfinite(state.phi))


def test_a_pose_solution_made_at_once_is_the_dataclasss():
    import dataclasses

    fields = dict(
        phi=np.zeros(2),
        tip=np.ones(3),
        distance=0.5,
        status="converged",
        steps=3,
        iterations=3,
        newton_iterations=0,
        restarts=1,
        found_by="method",
        orientation_error=None,
    )
    made, expected = ik._pose_solution(**fields), ik.PoseSolution(**fields)
    assert repr(made) == repr(expected) and made.converged and dataclasses.fields(made) == dataclasses.fields(expected)
    assert {f.name for f in dataclasses.fields(expected)} == set(fields)  # every field given
    with pytest.raises(dataclasses.FrozenInstanceError):
        made.steps = 4  # type: ignore[misc]
