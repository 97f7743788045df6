"""Runs made up for the viewer's tests: long trajectories without solving them.

A synthesised run has a real arm, real obstacles and goals, and a smooth made-up motion,
so the page's size and its loading can be measured at sizes no bundled scene reaches
(docs/viewer.md: a 700-frame 4-joint run, a 3,000-frame 7-joint run).
"""

from __future__ import annotations

import numpy as np

from armanim.arm.kinematics import forward
from armanim.motion.solution import GoalReport, Trajectory


def synthetic_scene(joints: int) -> dict:
    """A valid scene document with ``joints`` links, three spheres and four goals."""
    links = [2.0] + [12.0 / (joints - 1)] * (joints - 1)
    return {
        "version": 1,
        "name": f"synthetic-{joints}",
        "arm": {"base": [5, 5, 0], "links": links},
        "obstacles": [
            {"center": [12, 9, 8], "radius": 2},
            {"center": [8, 2, 11], "radius": 1.5},
            {"center": [3, 10, 9], "radius": 1.2},
        ],
        "goals": [[14, 5, 6], [6, 15, 9], [2, 3, 12], [10, 10, 10]],
    }


def synthetic_run(frames: int, joints: int, seed: int = 0):
    """(problem, trajectory, reports, settings) of a made-up run of ``frames`` frames."""
    from armanim.scene import SceneModel, render_settings, scene_to_problem

    model = SceneModel.model_validate(synthetic_scene(joints))
    problem = scene_to_problem(model)
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 1.0, frames)[:, None]
    amplitude, speed, phase = rng.uniform(0.3, 1.5, joints), rng.uniform(1, 6, joints), rng.uniform(0, 6, joints)
    phi = amplitude * np.sin(2 * np.pi * speed * t + phase)  # radians, smooth
    tip = forward(problem.arm, phi).tip
    goals = len(problem.goals)
    goal = np.minimum((np.arange(frames) * goals) // frames, goals - 1)
    targets = np.array([g.position for g in problem.goals])
    distance = np.linalg.norm(tip - targets[goal], axis=1)
    trajectory = Trajectory(
        phi=phi,
        tip=tip,
        goal=goal,
        distance=distance,
        clearance=rng.uniform(0.1, 3.0, frames),
        reached=np.zeros(frames, bool),
        iterations=np.ones(frames, int),
        step_scale=np.ones(frames),
        fps=30.0,
    )
    reports = []
    for k in range(goals):
        span = np.nonzero(goal == k)[0]
        reports.append(
            GoalReport(
                index=k,
                position=targets[k],
                reached=k % 2 == 0,
                reason=None if k % 2 == 0 else "stalled",
                frames=len(span),
                first_frame=int(span[0]),
                last_frame=int(span[-1]),
                final_distance=float(distance[span[-1]]),
                iterations=len(span),
            )
        )
    return problem, trajectory, tuple(reports), render_settings(model)
