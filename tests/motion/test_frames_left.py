"""The planner's schedules within the frames left (issue 36): a path or plan longer than the
frames left is followed as far as they go, the damper never lengthens a schedule, and seeds stay
within a joint range narrower than the planner's buffer.

Each test is named in docs/reliability.md, which it keeps true.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from armanim.motion.planning.follow import damper_paced, path_schedule
from armanim.scene import scene_to_problem


@pytest.mark.parametrize("length", [3.0, 300.0, 1e300])
def test_a_path_longer_than_the_frames_left_is_followed_as_far_as_they_go(length):
    waypoints = np.array([[0.0, 0.0], [length, -length]])
    for step, most in ((np.radians(0.001), 600), (1e-300, 10**6)):  # a count of 1e306, or inf: never allocated
        s = path_schedule(waypoints, step, most=most)
        assert len(s) == most and np.all(np.diff(s) >= 0) and np.all(np.diff(s) <= step / 0.66) and s[-1] < length
    short = path_schedule(np.array([[0.0], [0.5]]), 0.1, most=600)
    assert len(short) == 8 and short[-1] == 0.5


def test_the_damper_never_makes_a_schedule_longer_than_the_frames_left():
    from armanim.scene import load_scene  # a scene with obstacles, so the damper has work

    problem = scene_to_problem(load_scene(Path(__file__).parents[2] / "scenes" / "planning-wall.yaml").model)
    start = problem.home
    waypoints = np.stack([start, start + 2.0])
    schedule = path_schedule(waypoints, problem.solver.max_joint_step)
    assert len(damper_paced(problem, waypoints, schedule, most=len(schedule) + 3)) <= len(schedule) + 3


def test_a_plan_longer_than_the_frames_left_stops_where_they_end():
    from armanim.motion.planning import plan_motion
    from armanim.scene import load_scene

    problem = scene_to_problem(load_scene(Path(__file__).parents[2] / "scenes" / "planning-wall.yaml").model)
    goal = problem.goals[1].position
    free = plan_motion(problem, problem.home, goal)
    assert free.frames is not None and len(free.frames) <= problem.solver.max_frames_per_goal
    tight = plan_motion(problem, problem.home, goal, frames_left=3)
    assert len(tight.frames) == 3
    assert not np.allclose(
        tight.frames[-1], free.frames[-1]
    )  # short of the goal pose: the goal ends too_slow at its cap


def test_the_planner_seeds_within_a_range_narrower_than_its_buffer():
    from types import SimpleNamespace

    from armanim.motion.planning.poses import seed_poses
    from armanim.motion.problem import Limits
    from armanim.motion.tunables import DEFAULTS

    narrow = SimpleNamespace(
        limits=Limits(np.array([-0.007, -np.inf]), np.array([0.007, np.inf]), margin=np.radians(10)), tunables=DEFAULTS
    )
    seeds = seed_poses(narrow, np.zeros(2), 16, seed=1)
    assert np.all(np.abs(seeds[:, 0]) <= 0.007)
