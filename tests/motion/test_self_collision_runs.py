"""Runs keep every enabled pair of the arm's own capsules apart: random goals near the body,
the Panda's shelf scene, a goal whose only poses fold the arm, and the certified motion checks."""

from __future__ import annotations

import numpy as np
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from invariants import assert_trajectory_invariants, small_planning_budget

from armanim.arm.capsules import joint_capsules
from armanim.arm.kinematics import Arm, forward
from armanim.motion.problem import Goal
from armanim.motion.solvers import METHODS
from armanim.motion.trajectory import solve_trajectory
from armanim.scene import scene_model
from armanim.scene.convert import default_solver_settings, scene_to_problem
from armanim.scene.loader import load_scene
from armanim.world import selfcollision
from armanim.world.selfdistances import SelfPairs, self_gaps


def robot_problem(robot: str, **solver):
    """A bundled robot's problem with its own allowed-collision matrix, in metres."""
    from dataclasses import replace

    base = scene_to_problem(scene_model({"version": 1, "arm": {"robot": robot}, "goals": [[0.4, 0, 0.4]]}))
    return replace(
        base,
        solver=default_solver_settings(
            **{"max_step": 0.02, "tolerance": 0.005, "max_frames_per_goal": 120, "clearance": 0.02, **solver}
        ),
    )


@st.composite
def near_body_problems(draw):
    """Panda or UR5, its self pairs enabled (self_clearance 0.01), goals at the tool point of
    random in-limit poses close to the body (within 0.3 m of the base's vertical axis), so that
    straight joint paths and random free poses cross or fold the arm onto itself."""
    from dataclasses import replace

    robot = draw(st.sampled_from(["panda", "ur5"]))
    problem = robot_problem(robot, method=draw(st.sampled_from(sorted(METHODS))))
    lim = problem.limits
    lo, hi = np.maximum(lim.lower, -np.pi) + 0.1, np.minimum(lim.upper, np.pi) - 0.1
    poses = np.array(
        [
            np.array(draw(st.lists(st.floats(0.0, 1.0), min_size=problem.arm.n, max_size=problem.arm.n))) * (hi - lo)
            + lo
            for _ in range(draw(st.integers(1, 2)))
        ]
    )
    tips = forward(problem.arm, poses).tip
    assume(np.all(tips[:, 2] > 0.1) and np.all(np.linalg.norm(tips[:, :2] - problem.arm.base[:2], axis=1) < 0.3))
    return replace(problem, goals=tuple(Goal(tip, hold=0.0) for tip in tips))


@settings(max_examples=8, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(near_body_problems())
def test_runs_near_the_body_keep_every_enabled_pair_apart(problem):
    solution = solve_trajectory(small_planning_budget(problem))
    assert_trajectory_invariants(problem, solution)  # every frame: every enabled pair >= self_clearance


def test_panda_shelf_has_no_frame_under_self_clearance():
    from pathlib import Path

    scene = (
        Path(__file__).resolve().parents[1] / "data" / "panda-two-boards.yaml"
    )  # panda-shelf before it carried a box
    problem = scene_to_problem(load_scene(scene).model)
    assert ("panda_link5", "panda_link7") in problem.self_pairs.names  # the pair the run used to pass through
    solution = solve_trajectory(problem)
    assert_trajectory_invariants(problem, solution)
    assert solution.trajectory.self_clearance.min() >= problem.self_pairs.clearance
    assert solution.reached == len(problem.goals)
    off = solve_trajectory(
        replace_pairs(problem)
    )  # the same scene with self_collision: off passes link 5 through link 7
    gaps = self_gaps(forward(problem.arm, off.trajectory.phi), problem.capsules, problem.self_pairs).d
    assert (gaps.min(axis=1) < 0).sum() > 100


def replace_pairs(problem):
    from dataclasses import replace

    return replace(problem, self_pairs=SelfPairs.none())


def test_a_goal_whose_only_poses_fold_the_arm_is_a_no_free_pose_miss_naming_the_pair():
    """A planar chain whose only pose at the goal folds link 4 onto link 1: planner on, no free pose."""
    from dataclasses import replace

    from armanim.motion.problem import Limits
    from armanim.world.obstacles import Obstacles

    arm = Arm.from_names([1.0, 1.0, 1.0], axes=["z", "z", "z"], direction="x")
    caps = joint_capsules(arm, 0.1)
    pairs = selfcollision.enabled_pairs(
        caps, {("link1", "link2"): "Adjacent", ("link2", "link3"): "Adjacent"}, 0.05, "auto"
    )
    limits = Limits(np.radians([-10.0, -170, -170]), np.radians([10.0, 170, 170]), np.radians(10.0))
    goal = np.array([0.4, 0.0, 0.0])  # only reached with link 3 folded back over link 1
    from armanim.motion.problem import Problem

    problem = Problem(
        arm=arm,
        half_width=0.1,
        home=np.zeros(3),
        limits=limits,
        obstacles=Obstacles.none(),
        goals=(Goal(goal, 0.0),),
        solver=default_solver_settings(tolerance=0.01, max_frames_per_goal=200, clearance=0.1),
        fps=30.0,
        capsules=caps,
        self_pairs=pairs,
    )
    solution = solve_trajectory(small_planning_budget(problem))
    assert_trajectory_invariants(problem, solution)
    report = solution.goals[0]
    assert not report.reached and report.reason == "no_free_pose"
    assert report.planning.self_pair == "link1|link3"
    free = solve_trajectory(replace(problem, self_pairs=SelfPairs.none()))
    assert free.goals[0].reached  # without the pair the goal is reached, through the arm


def test_certified_motion_checks_cover_the_arms_own_pairs():
    """motion_is_free's step bound covers pairs that move relative to each other: whatever it
    certifies, a fine sampling of the same straight motion keeps the floor (to its certification slack)."""
    from armanim.motion.filter.clearance import pose_clearance
    from armanim.motion.planning.path import motion_is_free
    from armanim.motion.problem import Limits, Problem
    from armanim.motion.tunables import DEFAULTS
    from armanim.world.obstacles import Obstacles

    arm = Arm.from_names([1.0, 0.8, 0.8, 0.6, 0.4], axes=["z", "y", "y", "x", "y"])
    caps = joint_capsules(arm, 0.05)
    allowed = {(f"link{k}", f"link{k + 1}"): "Adjacent" for k in range(1, 5)}
    pairs = selfcollision.enabled_pairs(caps, allowed, 0.02, "auto")
    problem = Problem(
        arm=arm,
        half_width=0.05,
        home=np.zeros(5),
        limits=Limits.unlimited(5, np.radians(10.0)),
        obstacles=Obstacles.none(),
        goals=(Goal(np.array([1.0, 0, 1.0]), 0.0),),
        solver=default_solver_settings(clearance=0.04),
        fps=30.0,
        capsules=caps,
        self_pairs=pairs,
    )
    rng = np.random.default_rng(35)
    certified = refused = 0
    for _ in range(60):
        a, b = rng.uniform(-2.5, 2.5, (2, 5))
        floor = 0.044
        free, _ = motion_is_free(problem, a, b, floor)
        fine = pose_clearance(problem, a + np.linspace(0, 1, 2001)[:, None] * (b - a))
        if free:
            certified += 1
            assert fine.min() >= floor - DEFAULTS.planner.certify_to * problem.solver.clearance / 2 - 1e-9
        else:
            refused += 1
    assert certified >= 5 and refused >= 5  # both answers were exercised
