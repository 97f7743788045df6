"""The motion keeps every shape (boxes, capsules, a floor): the filter slides along and around
them, a goal below the floor is missed, the invariants hold on random shaped scenes, and a
shaped run is the same bytes in two processes."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from invariants import assert_trajectory_invariants, small_planning_budget
from strategies import shaped_problems

from armanim.arm.chain import rpy_rotation
from armanim.arm.kinematics import forward
from armanim.motion.trajectory import solve_trajectory
from armanim.world.distances import clearances
from armanim.world.obstacles import BOX, ROD, Boxes, Obstacles, Rods


def notes_among(goals, boxes=(), rods=(), floor=None, method="pinv", planner="off"):
    """The notes' arm at the origin (straight up) among boxes (centre, size, rpy radians) and capsules."""
    from dataclasses import replace

    from strategies import with_floor
    from test_motion import notes_problem

    problem = notes_problem(goals=goals, method=method, planner=planner)
    kinds = [BOX] * len(boxes) + [ROD] * len(rods)
    obstacles = Obstacles(
        np.zeros((0, 3)),
        np.zeros(0),
        np.full(len(kinds), 0.5),
        Boxes(
            np.array([c for c, _, _ in boxes], float).reshape(-1, 3),
            np.array([s for _, s, _ in boxes], float).reshape(-1, 3) / 2,
            np.array([rpy_rotation(r) for _, _, r in boxes]).reshape(-1, 3, 3),
        ),
        Rods(
            np.array([a for a, _, _ in rods], float).reshape(-1, 3),
            np.array([b for _, b, _ in rods], float).reshape(-1, 3),
            np.array([r for _, _, r in rods], float),
        ),
        kinds=np.array(kinds, dtype=int),
    )
    return replace(problem, obstacles=with_floor(obstacles, floor))


@pytest.mark.parametrize("method", ["pinv", "dls"])
@pytest.mark.parametrize("rpy, goal", [((0.0, 0.0, 0.0), 9.0), ((0.0, 0.0, np.pi / 4), 10.0)], ids=["edge", "corner"])
def test_filter_slides_along_a_box_and_around_its_edge(method, rpy, goal):
    """Planner off: the arm comes down over a block, slides along its top face, round its far
    edge (or, the block turned 45 degrees, over its top's corners and round its vertical edge) and down its side to a goal beside it, never stopping."""
    problem = notes_among(((goal, 0.0, 1.0),), boxes=[((6.0, 0.0, 2.0), (4.0, 4.0, 4.0), rpy)], method=method)
    solution = solve_trajectory(problem)
    assert [g.reached for g in solution.goals] == [True]
    assert_trajectory_invariants(problem, solution)
    clearance = solution.trajectory.clearance
    assert clearance.min() >= problem.solver.clearance
    assert clearance.min() < 2 * problem.solver.clearance  # it did run along the surface


def test_filter_slides_instead_of_stopping_at_a_box_face():
    from armanim.motion.filter.barrier import safe_step
    from armanim.motion.solvers.common import arm_state

    # a wall whose face is exactly solver.clearance (0.05) beyond the straight arm's capsules (radius 0.25)
    problem = notes_among(((7.0, 0.0, 9.0),), boxes=[((1.3, 0.0, 10.0), (2.0, 4.0, 8.0), (0.0, 0.0, 0.0))])
    state = arm_state(problem, problem.home)
    assert state.min_clearance == pytest.approx(0.05)
    sideways = safe_step(problem, state, np.array([0.2, 0.3, 0.0, 0.0]))  # into the wall, with a turn about the base
    assert sideways.blocked_by == "obstacle" and sideways.phi[0] > 0.1  # the free direction is kept
    assert sideways.state.min_clearance >= problem.solver.clearance


def test_goal_below_the_floor_is_missed_not_passed_through():
    problem = notes_among(((9.0, 0.0, -1.0),), floor=0.0, planner="auto")
    solution = solve_trajectory(problem)
    report = solution.goals[0]
    assert not report.reached and report.reason == "no_free_pose"
    pose = forward(problem.arm, solution.trajectory.phi)
    assert np.all(
        pose.points[:, 2:, 2] >= 0.25 + problem.solver.clearance - 1e-12
    )  # every joint past link 1 stayed above
    assert np.all(pose.tip[:, 2] >= problem.solver.clearance)


def test_floor_is_kept_with_the_planner_off():
    problem = notes_among(((12.0, 0.0, 0.6),), floor=0.0, method="dls")
    solution = solve_trajectory(problem)
    cl = clearances(forward(problem.arm, solution.trajectory.phi), problem.obstacles, problem.capsules)
    assert cl.d[..., -1].min() >= problem.solver.clearance


@given(shaped_problems(max_links=5, max_goals=2, max_frames=60))
@settings(max_examples=5)
def test_shaped_scene_trajectory_invariants(problem):
    # a goal with no path would spend the whole RRT budget
    assert_trajectory_invariants(problem, solve_trajectory(small_planning_budget(problem)))


def test_a_shapes_run_is_byte_identical_in_two_processes():
    """ur5-table plans round its post: the same CSV bytes from a fresh process and from one
    that planned it once already (OMPL's random numbers must not leak between plans)."""
    import subprocess
    import sys

    from conftest import ROOT

    program = (
        "import sys\n"
        "from armanim.scene import load_scene, scene_to_problem\n"
        "from armanim.output.csvfile import trajectory_csv_text\n"
        "from armanim.motion.trajectory import solve_trajectory\n"
        "solve = lambda name: solve_trajectory(scene_to_problem(load_scene(sys.argv[1] + '/scenes/' + name + '.yaml').model))\n"
        "if sys.argv[2] == 'warm':\n"
        "    solve('ur5-table')\n"
        "print(trajectory_csv_text(solve('ur5-table').trajectory), end='')\n"
    )
    runs = [
        subprocess.run([sys.executable, "-c", program, str(ROOT), how], capture_output=True, text=True, check=True)
        for how in ("cold", "warm")
    ]
    assert ",plan" in runs[0].stdout
    assert runs[0].stdout == runs[1].stdout
