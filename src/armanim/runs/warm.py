"""``armanim warm``: compile armanim's numerical code ahead of its first real use.

numba compiles each kernel at its first call after installing or upgrading and keeps the machine
code in its cache (stamped by armanim's sources, :mod:`armanim.arm.kernel`). A run then compiles
only what its scene calls first: the kinematics and the frame loop for any scene, the pair kernels
for a robot, a box's, a capsule's or a cylinder's distances where a scene has one, the planner's
checks where a goal plans, the IK attempt for ``armanim ik``. :func:`warm` solves small scenes
that call every one of them, in memory (nothing is written), so that the first real run starts
like the hundredth.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

SHAPES = [
    {"center": [6.0, 4.0, 9.0], "radius": 0.8},
    {"box": {"center": [3.0, 8.0, 6.0], "size": [1.0, 1.0, 1.0], "rpy": [10, 20, 30]}},
    {"capsule": {"from": [9.0, 9.0, 2.0], "to": [9.0, 9.0, 5.0], "radius": 0.4}},
    {"cylinder": {"center": [1.0, 1.0, 3.0], "length": 2.0, "radius": 0.5}},
]
"""One obstacle of each shape, away from the notes' arm's motion (each shape's distances compile)."""


def warm_scenes() -> list[tuple[str, dict[str, Any]]]:
    """(label, scene as YAML would give it), for each compiled method (``pinv``, ``dls``): the notes'
    arm among spheres alone (a world of spheres takes its own path) and among every shape and a
    floor, with a point, a tool-axis and a joint goal (the planner's checks); a Panda with its self
    pairs among spheres alone, among every shape and a floor (a point, a pose and a joint goal), and
    between two boards (boxes alone) with a path goal, taking a box from a table and putting it down
    (pick and place: a carried object's capsules); each world again with position goals only (a scene
    without any orientation compiles its frames without the rotation task); and the notes' arm by ``gradient``.

    >>> [label for label, _ in warm_scenes()][:3]
    ['arm of links among spheres, pinv', 'arm of links among every shape, pinv', 'Panda among spheres, pinv']
    >>> len(warm_scenes())
    16
    """
    spheres = [{"center": [6.0, 4.0, 9.0], "radius": 0.8}, {"center": [2.0, 8.0, 7.0], "radius": 0.5}]
    panda_spheres = [{"center": [0.6, -0.4, 0.2], "radius": 0.05}, {"center": [0.2, 0.5, 0.6], "radius": 0.05}]
    panda_shapes = [
        *panda_spheres,
        {"box": {"center": [0.6, -0.4, 0.6], "size": [0.1, 0.1, 0.1], "rpy": [0, 0, 20]}},
        {"capsule": {"from": [-0.4, 0.4, 0.0], "to": [-0.4, 0.4, 0.4], "radius": 0.03}},
        {"cylinder": {"center": [0.6, 0.4, 0.2], "length": 0.2, "radius": 0.03}},
    ]
    boards = [{"box": {"center": [0.62, 0.0, z], "size": [0.3, 0.7, 0.02]}} for z in (0.19, 0.53)]
    pick = [
        {
            "box": {"center": [0.25, -0.45, 0.1], "size": [0.3, 0.3, 0.2]},
            "name": "table",
        },  # panda-shelf's: a carried box
        {"box": {"center": [0.25, -0.45, 0.272], "size": [0.04, 0.04, 0.08]}, "name": "box"},
    ]
    links = {"links": [2, 5, 5, 5], "base": [5, 5, 0]}
    link_goals = [[8, 5, 12], {"position": [5, 9, 12], "tool_axis": [0, 0, 1]}, {"joints": [10, 10, 10, 10]}]
    panda_goals = [
        [0.45, -0.1, 0.5],
        {"position": [0.45, 0.1, 0.5], "orientation": {"rpy": [180, 0, 0]}},
        {"joints": [0, -40, 0, -130, 0, 95, 45]},
    ]
    scenes = []
    for method in ("pinv", "dls"):
        solver = {"method": method}
        scenes += [
            (
                f"arm of links among spheres, {method}",
                {"version": 1, "arm": links, "obstacles": spheres, "goals": link_goals, "solver": solver},
            ),
            (
                f"arm of links among every shape, {method}",
                {"version": 1, "arm": links, "floor": -0.5, "obstacles": SHAPES, "goals": link_goals, "solver": solver},
            ),
            (
                f"Panda among spheres, {method}",
                {
                    "version": 1,
                    "arm": {"robot": "panda"},
                    "obstacles": panda_spheres,
                    "goals": panda_goals,
                    "solver": solver,
                },
            ),
            (
                f"Panda among every shape, {method}",
                {
                    "version": 1,
                    "arm": {"robot": "panda"},
                    "floor": -0.01,
                    "obstacles": panda_shapes,
                    "goals": panda_goals,
                    "solver": solver,
                },
            ),
            (
                f"Panda between boards, along an arc, picking and placing, {method}",
                {
                    "version": 1,
                    "arm": {"robot": "panda"},
                    "floor": 0.0,
                    "obstacles": boards + pick,
                    "goals": [
                        {"position": [0.52, 0.15, 0.36]},
                        {
                            "path": {
                                "arc": {
                                    "center": [0.5, 0.0, 0.36],
                                    "start": [0.56, 0.0, 0.36],
                                    "angle": 90,
                                    "normal": [0, 0, 1],
                                }
                            },
                            "speed": 0.1,
                        },
                        {"position": [0.25, -0.45, 0.292], "orientation": {"rpy": [180, 0, 0]}, "grasp": "box"},
                        {"position": [0.25, -0.45, 0.36], "orientation": {"rpy": [180, 0, 0]}, "release": True},
                    ],
                    "solver": solver,
                },
            ),
        ]
    for (
        label,
        arm,
        obstacles,
        floor,
        goal,
    ) in (  # a scene without any orientation compiles its frames without the rotation task
        ("arm of links among spheres", links, spheres, None, link_goals[0]),
        ("arm of links among every shape", links, SHAPES, -0.5, link_goals[0]),
        ("Panda among spheres", {"robot": "panda"}, panda_spheres, None, panda_goals[0]),
        ("Panda among every shape", {"robot": "panda"}, panda_shapes, -0.01, panda_goals[0]),
        ("Panda between boards", {"robot": "panda"}, boards, 0.0, [0.52, 0.15, 0.36]),
    ):
        scene: dict[str, Any] = {"version": 1, "arm": arm, "obstacles": obstacles, "goals": [goal]}
        if floor is not None:
            scene["floor"] = floor
        scenes.append((f"{label}, positions only", scene))
    scenes.append(
        (
            "arm of links, gradient",
            {
                "version": 1,
                "arm": links,
                "obstacles": spheres,
                "goals": link_goals[:1],
                "solver": {"method": "gradient"},
            },
        )
    )
    return scenes


def warm(progress: Callable[[str, int, int], None] | None = None) -> int:
    """Solve every :func:`warm_scenes` scene and put it on the clock, and solve one pose of the
    Panda by each compiled method (the IK attempt), in memory; ``progress(label, done, total)``
    before each. Returns how many solves ran."""
    import numpy as np

    from armanim.motion.ik import solve_pose
    from armanim.motion.timing.retime import retime
    from armanim.motion.trajectory import solve_trajectory
    from armanim.scene import scene_model, scene_to_problem

    scenes = warm_scenes()
    total = len(scenes) + 2
    for done, (label, scene) in enumerate(scenes):
        if progress:
            progress(label, done, total)
        problem = scene_to_problem(scene_model(scene))
        retime(problem, solve_trajectory(problem), problem.fps)
    for k, method in enumerate(("pinv", "dls")):
        if progress:
            progress(f"Panda IK, {method}", len(scenes) + k, total)
        problem = scene_to_problem(
            scene_model(
                {"version": 1, "arm": {"robot": "panda"}, "goals": [[0.5, 0, 0.5]], "solver": {"method": method}}
            )
        )
        solve_pose(problem, np.array([0.45, 0.1, 0.5]), problem.home)
    if progress:
        progress("done", total, total)
    return total
