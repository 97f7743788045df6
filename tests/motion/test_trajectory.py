"""Invariants of every trajectory: bundled scenes and random problems."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import BUNDLED, SCENES, solved_scene
from hypothesis import given, settings
from invariants import assert_trajectory_invariants
from strategies import problems

from armanim.motion.trajectory import frame_budget, solve_trajectory


@pytest.mark.parametrize("path", BUNDLED, ids=lambda p: p.stem)
def test_bundled_scene_trajectory_invariants(path):
    problem, solution = solved_scene(path)
    assert_trajectory_invariants(problem, solution)


@given(problems(max_frames=30))
@settings(max_examples=30)
def test_random_problem_trajectory_invariants(problem):
    solution = solve_trajectory(problem)
    assert_trajectory_invariants(problem, solution)


@given(problems(methods=("pinv", "dls"), max_frames=25))
@settings(max_examples=20)
def test_progress_callback_counts_frames(problem):
    seen = []
    solution = solve_trajectory(problem, progress=lambda done, total: seen.append((done, total)))
    done = [d for d, _ in seen]
    totals = [t for _, t in seen]
    assert seen and seen[-1] == (solution.trajectory.frames, solution.trajectory.frames)
    assert done == sorted(done)
    assert totals == sorted(totals, reverse=True)  # the bound only shrinks
    assert all(d <= t <= frame_budget(problem) for d, t in seen)


def test_planning_is_told_between_frames_and_changes_nothing():
    """planning-wall's first goal is planned round the wall: the search is told as it goes, each
    plan ending full, and the trajectory is the one solved without being told."""
    problem, quiet = solved_scene(SCENES / "planning-wall.yaml")
    seen = []
    solution = solve_trajectory(problem, progress=lambda *call: seen.append(("solve", *call)),
                                planning=lambda *call: seen.append(("plan", *call)))
    np.testing.assert_array_equal(solution.trajectory.phi, quiet.trajectory.phi)
    plans = [call for call in seen if call[0] == "plan"]
    assert solution.goals[0].planning.path == "rrt_connect" and plans
    ends = [k for k, call in enumerate(seen) if call[0] == "plan" and call[1] == call[2]]
    assert ends and all(seen[k + 1][0] == "solve" for k in ends)  # a plan ends before the next frame


def test_trajectory_is_deterministic_in_process():
    problem, solution = solved_scene(BUNDLED[0])
    again = solve_trajectory(problem)
    np.testing.assert_array_equal(again.trajectory.phi, solution.trajectory.phi)
    np.testing.assert_array_equal(again.trajectory.tip, solution.trajectory.tip)


def test_every_miss_reason_is_explained():
    from typing import get_args

    from armanim.motion.solution import MISS_REASONS
    from armanim.names import MissReason

    assert tuple(MISS_REASONS) == get_args(MissReason)
