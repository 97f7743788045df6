"""``armanim warm``: compile armanim's numerical code ahead of its first real use.

numba compiles each kernel at its first call after installing or upgrading and keeps the machine
code in its cache (stamped by armanim's sources, :mod:`armanim.arm.kernel`). A run then compiles
only what its scene calls first: the kinematics and the frame loop for any scene, the pair kernels
for a robot, a box's, a capsule's or a cylinder's distances where a scene has one, the planner's
checks where a goal plans, the IK attempt for ``armanim ik``, the rasteriser's loops for a first
video. :func:`warm` solves small scenes that call every one of them and draws a tiny frame, in memory
(nothing is written), so that the first real run starts like the hundredth.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

SHAPES = [
    {"center": [6.0, 4.0, 9.0], "radius": 0.8},
    {"box": {"center": [3.0, 8.0, 6.0], "size": [1.0, 1.0, 1.0], "rpy": [10, 20, 30]}},
    {"capsule": {"from": [9.0, 9.0, 2.0], "to": [9.0, 9.0, 5.0], "radius": 0.4}},
    {"cylinder": {"center": [1.0, 1.0, 3.0], "length": 2.0, "radius": 0.5}},
]
"""One obstacle of each shape, away from the notes' arm's motion (each shape's distances compile)."""

CYLINDERS = [
    SHAPES[3],
    {"cylinder": {"center": [9.0, 9.0, 4.0], "length": 2.0, "radius": 0.4, "rpy": [90, 0, 0]}},
]
"""Cylinders alone, away from the notes' arm's motion: a world without boxes or capsules compiles its own
kernels (the suite's lockstep cylinders compiled the frame loop twice more after ``warm``)."""


def warm_scenes() -> list[tuple[str, dict[str, Any]]]:
    """(label, scene as YAML would give it), for each compiled method (``pinv``, ``dls``): the notes'
    arm among spheres alone (a world of spheres takes its own path) and among every shape and a
    floor, with a point, a tool-axis and a joint goal (the planner's checks); a Panda with its self
    pairs among spheres alone, among every shape and a floor (a point, a pose and a joint goal), and
    between two boards (boxes alone) with a path goal, taking a box from a table and putting it down
    (pick and place: a carried object's capsules); the notes' arm among cylinders alone; each world again
    with position goals only (a scene without any orientation compiles its frames without the rotation
    task); and the notes' arm by ``gradient``.

    >>> [label for label, _ in warm_scenes()][:3]
    ['arm of links among spheres, pinv', 'arm of links among every shape, pinv', 'Panda among spheres, pinv']
    >>> len(warm_scenes())
    25
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
        ("arm of links among cylinders", links, CYLINDERS, None, link_goals[0]),
    ):
        scene: dict[str, Any] = {"version": 1, "arm": arm, "obstacles": obstacles, "goals": [goal]}
        if floor is not None:
            scene["floor"] = floor
        scenes.append((f"{label}, positions only", scene))
    scenes.append(  # cylinders without boxes or capsules: a world of its own kind (with a tool axis and planning)
        (
            "arm of links among cylinders",
            {"version": 1, "arm": links, "obstacles": CYLINDERS, "goals": link_goals, "solver": {"method": "pinv"}},
        )
    )
    scenes += kinds_of_the_bundled_scenes()
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


def kinds_of_the_bundled_scenes() -> list[tuple[str, dict[str, Any]]]:
    """(label, scene) for the kinds of world, arm and goal of the bundled scenes that the other warm
    scenes leave out (measured: after them, these compiled at their first run): an arm of links in an
    empty world, with a goal out of its reach (out-of-reach: its frames and settle) and planar by
    ``newton`` (planar-nlink: the planner's checks); a UR5 on a rail among boxes on a floor (ur5-rail:
    the frames of a prismatic joint); a Panda at a bookshelf of cylinders and boxes with a joint goal
    (panda-bookshelf: the planner's pose check); a UR5 with a pen in an empty world along a path with a
    tool axis (ur5-pen: its frames); a Panda among spheres with position goals by ``dls``
    (panda-clutter: settle); an arm of links planning around a wall of spheres (planning-wall: the
    pose check). Each is its scene or the same kinds made small (fewer, nearer goals).

    >>> [label for label, _ in kinds_of_the_bundled_scenes()][:2]
    ['arm of links in an empty world, out of reach', 'planar arm of links in an empty world, newton']
    """
    links = {"base": [5, 5, 0], "links": [2, 5, 5, 5], "limits": [None, [-100, 100], [-150, 150], [-150, 150]]}
    wall = [{"center": [9, 5, z], "radius": 1.5} for z in (8.5, 12, 15.5)] + [
        {"center": [9, y, 12], "radius": 1.5} for y in (2, 8)
    ]
    turn = [0.0, 0.0, -63.1]
    cans = [{"center": [x, y, 0.298]} for x, y in ((0.248, -1.074), (0.739, -0.6), (0.156, -0.672))]
    shelf = [
        {"center": [0.59, -1.012, 0.218], "size": [1.2, 1.0, 0.04]},
        {"center": [0.59, -1.012, 0.518], "size": [1.2, 1.0, 0.04]},
        {"center": [0.144, -1.238, 0.368], "size": [1.2, 0.04, 0.34]},
        {"center": [1.036, -0.786, 0.368], "size": [1.2, 0.04, 0.34]},
    ]
    return [
        (
            "arm of links in an empty world, out of reach",
            {
                "version": 1,
                "arm": links,
                "goals": [[30, 5, 5], [10, 9, 7]],  # the first one's stall at the limits takes the filter's halvings
                "solver": {"max_step": 0.5, "max_frames_per_goal": 150},
            },
        ),
        (
            "planar arm of links in an empty world, newton",
            {
                "version": 1,
                "arm": {"links": [1, 1, 1, 1], "axes": ["z", "z", "z", "z"], "direction": "x", "width": 0.2},
                "goals": [[3, 1, 0], [1, 1, 0], [-2, 2.5, 0], [0.5, -3, 0]],  # (the last ones plan)
                "solver": {
                    "method": "newton",
                    "step": 0.2,
                    "max_step": 0.3,
                    "tolerance": 0.01,
                    "weights": {"target": 1000, "regularizer": 1},
                },
            },
        ),
        (
            "UR5 on a rail among boxes, dls",
            {
                "version": 1,
                "arm": {"robot": "ur5_rail"},
                "floor": 0.0,
                "obstacles": [
                    {"box": {"center": [0.0, 0.62, 0.275], "size": [2.8, 0.5, 0.05]}, "influence": 0.04},
                    {"box": {"center": [-0.45, 0.62, 0.36], "size": [0.12, 0.12, 0.12]}, "influence": 0.04},
                ],
                "goals": [[-0.05, 0.62, 0.45]],
                "solver": {"method": "dls", "tolerance": 0.005, "clearance": 0.02, "max_step": 0.02},
            },
        ),
        (
            "Panda at a bookshelf of cylinders and boxes, a joint goal",
            {
                "version": 1,
                "arm": {
                    "robot": "panda",
                    "home": [0.0, -45.0, 0.0, -135.0, 0.0, 90.0, 45.0],
                    "joint_values": {"panda_finger_joint1": 0.04},
                },
                "obstacles": [
                    *({"cylinder": {**can, "length": 0.14, "radius": 0.03, "rpy": turn}} for can in cans),
                    *({"box": {**board, "rpy": turn}} for board in shelf),
                ],
                "goals": [{"joints": [85.3, -8.4, -165.3, -124.6, 155.3, 134.8, 60.8]}],
                "solver": {"clearance": 0.0005, "self_clearance": 0.0005},
            },
        ),
        (
            "UR5 with a pen in an empty world, along an arc square to it",
            {
                "version": 1,
                "arm": {"robot": "ur5", "tool": {"xyz": [0, 0, 0.12], "pen": {"length": 0.12, "radius": 0.008}}},
                "goals": [
                    {
                        "path": {
                            "arc": {
                                "center": [0.55, 0.2, 0.4],
                                "start": [0.55, 0.23, 0.4],
                                "angle": 90,
                                "normal": [1, 0, 0],
                            }
                        },
                        "speed": 0.08,
                        "tool_axis": [1, 0, 0],
                    },
                    {"position": [0.4, 0.0, 0.62], "tool_axis": [1, 0, 0]},
                ],
                "solver": {
                    "method": "pinv",
                    "tolerance": 0.003,
                    "path_tolerance": 0.001,
                    "orientation_tolerance": 0.5,
                    "max_step": 0.02,
                },
            },
        ),
        (
            "Panda among spheres, positions only, dls",
            {
                "version": 1,
                "arm": {"robot": "panda"},
                "obstacles": [
                    {"center": [0.45, 0.15, 0.25], "radius": 0.07, "influence": 0.08},
                    {"center": [0.40, -0.20, 0.30], "radius": 0.06, "influence": 0.08},
                ],
                "goals": [[0.50, 0.30, 0.30]],
                "solver": {"method": "dls", "tolerance": 0.005, "clearance": 0.02, "max_step": 0.02},
            },
        ),
        (
            "arm of links around a wall of spheres, planning",
            {
                "version": 1,
                "arm": {**links, "limits": [None, [-110, 110], [-150, 150], [-150, 150]]},
                "obstacles": wall,
                "goals": [{"position": [13, 5, 10], "hold": 0.5}, {"position": [5, 12, 7], "hold": 0.5}, [5, 5, 16.5]],
                "solver": {"method": "pinv", "max_step": 0.5, "clearance": 0.05, "planner": "auto"},
            },
        ),
    ]


def draw_in_memory() -> None:
    """Call the rasteriser's compiled loops as a video's frames call them, on a frame of 8 x 8 pixels in
    memory (nothing is written): a robot's mesh placed, lit and culled at a pose, triangles filled over a
    furniture's layer and laid over the frame, a pose's outline, a sprite, an arm's soft shadow on a
    floor, and the frame's yuv420p planes for the encoder."""
    import numpy as np

    from armanim.render.camera.view import AMBIENT, DIFFUSE, LIGHT
    from armanim.render.pictures.canvas import SHADOW_PASSES, SHADOW_RGB
    from armanim.render.solids.raster import StillLayer, draw_outline, draw_triangles, triangle_sprite
    from armanim.render.solids.rasterloops import seen_vertices, soft_strokes
    from armanim.render.video.planes import yuv420

    points = np.array([[1.0, 1.0, 0.0], [6.0, 1.0, 0.0], [6.0, 6.0, 1.0], [1.0, 6.0, 1.0]])
    faces = np.array([[0, 1, 2], [0, 2, 3]])
    rgb = np.full((4, 3), 0.5)
    frame = np.zeros((8, 8, 4), dtype=np.uint8)
    mesh = (points, np.zeros(4, dtype=np.int64), np.tile([0.0, 0.0, 1.0], (4, 1)), rgb, faces)
    pose = (np.zeros((2, 3)), np.tile(np.eye(3), (1, 1, 1)))
    view = (np.eye(3, 4), np.eye(3))
    seen_vertices(mesh, *pose, view, (LIGHT, AMBIENT, DIFFUSE), np.empty((4, 3)), np.empty((4, 3)), np.empty(2, bool))
    draw_triangles(frame, points, faces, rgb, still=StillLayer(points, faces[:1], rgb, (8, 8)))
    draw_outline(frame, points, faces, (0.5, 0.5, 0.5))
    triangle_sprite(points, faces, rgb, (8, 8))
    soft_strokes(frame, np.array([[[1.0, 1.0], [6.0, 5.0]]]), np.array([1.5]), SHADOW_PASSES, SHADOW_RGB)
    yuv420(frame)


@dataclass(frozen=True)
class WarmTask:
    """One piece of :func:`warm`'s work, ``name`` saying which: the solve of the ``scene``-th
    :func:`warm_scenes` scene, the Panda's IK by ``method``, or (neither) the rasteriser's frame."""

    name: str
    scene: int | None = None
    method: str | None = None


@dataclass(frozen=True)
class Warmed:
    """What :func:`warm` did: its solves, numba's compiling in seconds (summed over the processes,
    each outermost compile once), and whether numba kept every process's machine code."""

    solves: int
    compiling: float
    kept: bool


def warm_tasks() -> list[WarmTask]:
    """Every :class:`WarmTask`, in the order they are handed out: the Panda's IK and the rasteriser
    (kernels of their own) between the first scenes, so that a second worker compiles them while the
    first compiles the scenes' kernels instead of waiting for them.

    >>> [task.name for task in warm_tasks()][:4]
    ['arm of links among spheres, pinv', 'Panda IK, pinv', 'arm of links among every shape, pinv', 'the rasteriser, a frame in memory']
    >>> tasks = warm_tasks()
    >>> sorted(t.scene for t in tasks if t.scene is not None) == list(range(len(warm_scenes()))), len(tasks) - len(warm_scenes())
    (True, 3)
    """
    scenes = [WarmTask(label, scene=index) for index, (label, _) in enumerate(warm_scenes())]
    own = [WarmTask("Panda IK, pinv", method="pinv"), WarmTask(RASTERISER), WarmTask("Panda IK, dls", method="dls")]
    return [scenes[0], own[0], scenes[1], own[1], scenes[2], own[2], *scenes[3:]]


RASTERISER = "the rasteriser, a frame in memory"


def warm_one(task: WarmTask) -> tuple[float, bool]:
    """Do ``task`` in memory: a warm scene solved and put on the clock, a Panda pose solved by one
    compiled method (the IK attempt), or the tiny frame (:func:`draw_in_memory`). Returns numba's
    compiling in it (seconds) and whether numba kept the machine code (a worker's answer for the
    process that asked)."""
    import numpy as np

    from armanim.arm import kernel
    from armanim.motion.ik import solve_pose
    from armanim.motion.timing.retime import retime
    from armanim.motion.trajectory import solve_trajectory
    from armanim.runs.stopwatch import stopwatch
    from armanim.scene import scene_model, scene_to_problem

    with stopwatch() as watch:
        if task.scene is not None:
            problem = scene_to_problem(scene_model(warm_scenes()[task.scene][1]))
            retime(problem, solve_trajectory(problem), problem.fps)
        elif task.method is not None:
            panda = {
                "version": 1,
                "arm": {"robot": "panda"},
                "goals": [[0.5, 0, 0.5]],
                "solver": {"method": task.method},
            }
            problem = scene_to_problem(scene_model(panda))
            solve_pose(problem, np.array([0.45, 0.1, 0.5]), problem.home)
        else:
            draw_in_memory()
    return watch.compiling, kernel.CODE_KEPT


def warm(progress: Callable[[str, int, int], None] | None = None, jobs: int = 1) -> Warmed:
    """Do every :func:`warm_tasks` task (:func:`warm_one`), in this process (``jobs`` 1) or in
    ``jobs`` worker processes that share numba's cache (each kernel is compiled by one of them, the
    others load it: :func:`armanim.arm.kernel.held_alone`); ``progress(name, done, total)`` as each
    task ends, and once before the first."""
    from armanim.procs.executors import local_executor

    tasks = warm_tasks()
    total = len(tasks)
    if progress:
        progress("started", 0, total)
    compiling, kept = 0.0, True
    for done, (task, answer, error) in enumerate(local_executor(jobs).map(warm_one, tasks), start=1):
        if error is not None:
            raise error
        compiling, kept = compiling + answer[0], kept and answer[1]
        if progress:
            progress(task.name, done, total)
    return Warmed(solves=total - 1, compiling=compiling, kept=kept)
