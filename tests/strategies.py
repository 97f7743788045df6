"""Hypothesis strategies for random arms, poses and scenes (all in this one module).

Every strategy builds objects of the pure core (``Arm``, ``Problem``) directly, so the
property tests need neither YAML nor pydantic, except :func:`scene_texts` which
writes a valid scene file for the loader.
"""

from __future__ import annotations

import numpy as np
from hypothesis import assume
from hypothesis import strategies as st

from armanim.arm.capsules import joint_capsules
from armanim.arm.kinematics import Arm, forward
from armanim.motion.problem import Goal, Limits, Problem
from armanim.scene import default_solver_settings
from armanim.world.obstacles import Obstacles

AXES = ("x", "y", "z")
METHODS = ("pinv", "dls", "newton", "gradient")

lengths = st.floats(0.3, 3.0, allow_nan=False, allow_infinity=False)
coords = st.floats(-5.0, 5.0, allow_nan=False, allow_infinity=False)
angles = st.floats(-np.pi, np.pi, allow_nan=False, allow_infinity=False)


@st.composite
def arms(draw, min_links: int = 1, max_links: int = 6, planar: bool = False) -> Arm:
    """A random serial arm: 1-6 links, any axes and link direction, any base."""
    n = draw(st.integers(min_links, max_links))
    links = draw(st.lists(lengths, min_size=n, max_size=n))
    base = draw(st.tuples(coords, coords, coords))
    if planar:
        return Arm.from_names(links, base=base, axes=["z"] * n, direction="x")
    axes = draw(st.lists(st.sampled_from(AXES), min_size=n, max_size=n))
    direction = draw(st.sampled_from(AXES))
    return Arm.from_names(links, base=base, axes=axes, direction=direction)


def poses(n: int):
    """Joint angles (n,) in radians."""
    return st.lists(angles, min_size=n, max_size=n).map(np.array)


@st.composite
def arm_and_pose(draw, **kwargs):
    arm = draw(arms(**kwargs))
    return arm, draw(poses(arm.n))


@st.composite
def limits_for(draw, home: np.ndarray, margin_deg: float | None = None) -> Limits:
    """Limits around ``home`` (strictly inside), some joints unlimited."""
    n = len(home)
    lower, upper = np.full(n, -np.inf), np.full(n, np.inf)
    for j in range(n):
        if draw(st.booleans()):
            lower[j] = home[j] - draw(st.floats(0.05, 2.0))
            upper[j] = home[j] + draw(st.floats(0.05, 2.0))
    margin = np.radians(margin_deg if margin_deg is not None else draw(st.floats(2.0, 30.0)))
    return Limits(lower=lower, upper=upper, margin=float(margin))


@st.composite
def sliding(draw, arm: Arm, home: np.ndarray, limits: Limits) -> tuple[Arm, Limits]:
    """``arm`` with some of its joints prismatic (at least one, any of them): each slides along its
    axis (metres: ``home``'s value, the links' scale) between limits 0.05-1 m either side of home,
    its stroke the larger limit in size (what the lever arms and the reach add for it), as a URDF's
    prismatic joint is read; the revolute joints keep their limits."""
    from dataclasses import replace

    n = arm.n
    slides = np.array(draw(st.lists(st.booleans(), min_size=n, max_size=n)))
    slides[draw(st.integers(0, n - 1))] = True
    lower, upper = limits.lower.copy(), limits.upper.copy()
    for j in np.nonzero(slides)[0]:
        lower[j] = home[j] - draw(st.floats(0.05, 1.0))
        upper[j] = home[j] + draw(st.floats(0.05, 1.0))
    stroke = np.where(slides, np.maximum(np.abs(lower), np.abs(upper)), 0.0)
    return replace(arm, prismatic=slides, stroke=stroke), replace(limits, lower=lower, upper=upper)


@st.composite
def obstacles_clear_of(draw, arm: Arm, home: np.ndarray, half_width: float, max_count: int = 3) -> Obstacles:
    """0-3 spheres, each clear of the home pose's link capsules by at least 0.05."""
    from armanim.world.distances import clearances

    m = draw(st.integers(0, max_count))
    if m == 0:
        return Obstacles.none()
    reach = arm.reach
    centers = np.array(
        [arm.base + np.array(draw(st.tuples(*(st.floats(-reach, reach) for _ in range(3))))) for _ in range(m)]
    )
    radii = np.array([draw(st.floats(0.0, 1.0)) for _ in range(m)])
    influence = np.array([draw(st.floats(0.2, 2.0)) for _ in range(m)])
    obstacles = Obstacles(centers=centers, radii=radii, influence=influence)
    cl = clearances(forward(arm, home), obstacles, joint_capsules(arm, half_width))
    assume(np.all(cl.links > 0.05))
    return obstacles


@st.composite
def problems(
    draw, methods=METHODS, max_links: int = 5, max_goals: int = 2, max_frames: int = 40, slides: bool = False
) -> Problem:
    """A random, valid problem: home clear of obstacles and inside its limits, goals
    outside every obstacle (some may be out of reach); ``slides``: some joints prismatic (:func:`sliding`)."""
    arm = draw(arms(max_links=max_links))
    home = draw(poses(arm.n)) * 0.5
    half_width = draw(st.floats(0.05, 0.3))
    limits = draw(limits_for(home))
    if slides:
        arm, limits = draw(sliding(arm, home, limits))
    obstacles = draw(obstacles_clear_of(arm, home, half_width))
    goals = []
    for _ in range(draw(st.integers(1, max_goals))):
        target = forward(arm, draw(poses(arm.n))).tip + np.array(
            draw(st.tuples(*(st.floats(-0.5, 0.5) for _ in range(3))))
        )
        if len(obstacles):
            gap = np.linalg.norm(target - obstacles.centers, axis=1) - obstacles.radii
            assume(np.all(gap > 0.05))
        goals.append(Goal(target, draw(st.sampled_from([0.0, 0.05, 0.1]))))
    solver = default_solver_settings(
        method=draw(st.sampled_from(methods)),
        beta=draw(st.floats(0.05, 0.5)),
        max_step=draw(st.sampled_from([np.inf, 0.3, 1.0])),
        tolerance=draw(st.sampled_from([0.01, 0.05])),
        max_frames_per_goal=max_frames,
        jacobian=draw(st.sampled_from(["analytic", "numeric"])),
        damping=draw(st.floats(0.01, 0.5)),
        max_joint_step=np.radians(draw(st.floats(1.0, 20.0))),
    )
    return Problem(
        arm=arm,
        half_width=half_width,
        home=home,
        limits=limits,
        obstacles=obstacles,
        goals=tuple(goals),
        solver=solver,
        fps=draw(st.sampled_from([10.0, 24.0, 30.0])),
    )


@st.composite
def scene_texts(draw) -> str:
    """A valid scene YAML text (no obstacles, unlimited joints, reachable goals)."""
    arm = draw(arms(max_links=4))
    n = arm.n
    links = [float(v) for v in arm.links]
    base = [float(v) for v in arm.base]
    goal = [float(v) for v in forward(arm, draw(poses(n))).tip]
    method = draw(st.sampled_from(METHODS))
    axes = ", ".join(draw(st.lists(st.sampled_from(AXES), min_size=n, max_size=n)))
    num = lambda v: f"{v:.12f}"  # noqa: E731  (PyYAML reads 1e-05, without a dot, as a string)
    return (
        "version: 1\n"
        "arm:\n"
        f"  base: [{num(base[0])}, {num(base[1])}, {num(base[2])}]\n"
        f"  links: [{', '.join(num(v) for v in links)}]\n"
        f"  axes: [{axes}]\n"
        "goals:\n"
        f"  - [{num(goal[0])}, {num(goal[1])}, {num(goal[2])}]\n"
        "solver:\n"
        f"  method: {method}\n"
        "  max_frames_per_goal: 30\n"
    )


@st.composite
def cluttered_problems(draw, max_links: int = 6, max_goals: int = 3, slides: bool = False) -> Problem:
    """A cluttered scene as users write them: 3-6 links, limits on about half the joints,
    1-4 spheres placed across the straight path between consecutive goals (pushed off
    the arm's home capsules and the goals by solver.clearance), every method, planner on;
    ``slides``: some joints prismatic (:func:`sliding`)."""
    from armanim.world.distances import clearances

    arm = draw(arms(min_links=3, max_links=max_links))
    home = draw(poses(arm.n)) * 0.3
    half_width = draw(st.floats(0.1, 0.3))
    limits = draw(limits_for(home, margin_deg=10.0))
    if slides:
        arm, limits = draw(sliding(arm, home, limits))
    solver = default_solver_settings(
        method=draw(st.sampled_from(METHODS)), max_step=0.5, max_frames_per_goal=150, clearance=0.05
    )
    goal_poses = [
        np.clip(draw(poses(arm.n)), limits.lower + 0.02, limits.upper - 0.02)
        for _ in range(draw(st.integers(1, max_goals)))
    ]
    tips = forward(arm, np.array([home, *goal_poses])).tip
    centers, radii = [], []
    for a, b in zip(tips[:-1], tips[1:]):
        t = draw(st.floats(0.3, 0.7))
        centers.append(a + t * (b - a) + np.array(draw(st.tuples(*(st.floats(-0.3, 0.3) for _ in range(3))))))
        radii.append(draw(st.floats(0.1, 0.4)) * max(np.linalg.norm(b - a), 0.5))
    obstacles = Obstacles(np.array(centers), np.array(radii), np.array(radii) + 0.5)
    keep = half_width + solver.clearance
    cl = clearances(forward(arm, home), obstacles, joint_capsules(arm, half_width))
    assume(np.all(cl.links > solver.clearance))
    goal_gap = np.linalg.norm(tips[1:, None, :] - obstacles.centers, axis=-1) - obstacles.radii
    assume(np.all(goal_gap > keep))
    return Problem(
        arm=arm,
        half_width=half_width,
        home=home,
        limits=limits,
        obstacles=obstacles,
        goals=tuple(Goal(tip, hold=0.0) for tip in tips[1:]),
        solver=solver,
        fps=30.0,
    )


@st.composite
def robot_problems(draw, robots=("panda", "ur5"), max_goals: int = 2) -> Problem:
    """A bundled robot (Panda or UR5) among 1-3 spheres, in metres: goals at the tool point of
    random poses inside the limits, spheres near the straight paths between them, kept clear
    of the home capsules and the goals; every method, planner on."""
    from armanim.scene import scene_model, scene_to_problem
    from armanim.world.distances import clearances

    robot = draw(st.sampled_from(robots))
    base = scene_to_problem(scene_model({"version": 1, "arm": {"robot": robot}, "goals": [[0.4, 0, 0.4]]}))
    arm, lim = base.arm, base.limits
    lo, hi = np.maximum(lim.lower, -np.pi) + 0.1, np.minimum(lim.upper, np.pi) - 0.1
    goal_poses = [
        np.array(draw(st.lists(st.floats(0.0, 1.0), min_size=arm.n, max_size=arm.n))) * (hi - lo) + lo
        for _ in range(draw(st.integers(1, max_goals)))
    ]
    tips = forward(arm, np.array([base.home, *goal_poses])).tip
    assume(np.all(tips[1:, 2] > 0.05))  # above the floor the robot stands on
    centers, radii = [], []
    for a, b in zip(tips[:-1], tips[1:]):
        t = draw(st.floats(0.3, 0.7))
        centers.append(a + t * (b - a) + np.array(draw(st.tuples(*(st.floats(-0.1, 0.1) for _ in range(3))))))
        radii.append(draw(st.floats(0.03, 0.08)))
    obstacles = Obstacles(np.array(centers), np.array(radii), np.array(radii) + 0.05)
    solver = default_solver_settings(
        method=draw(st.sampled_from(METHODS)), max_step=0.02, tolerance=0.005, max_frames_per_goal=120, clearance=0.02
    )
    cl = clearances(forward(arm, base.home), obstacles, base.capsules)
    assume(np.all(cl.links > solver.clearance))
    goal_gap = np.linalg.norm(tips[1:, None, :] - obstacles.centers, axis=-1) - obstacles.radii
    assume(np.all(goal_gap > 0.1 + solver.clearance))
    return Problem(
        arm=arm,
        half_width=base.half_width,
        home=base.home,
        limits=lim,
        obstacles=obstacles,
        goals=tuple(Goal(tip, hold=0.0) for tip in tips[1:]),
        solver=solver,
        fps=30.0,
        capsules=base.capsules,
        rates=base.rates,
    )  # the robot's own speed and acceleration limits


@st.composite
def shapes_across(draw, tips: np.ndarray, scale: float, spread: float, cylinders: bool = False) -> Obstacles:
    """Obstacles across the straight paths between consecutive ``tips``: for each, a sphere, a
    box (any orientation) or a capsule (any direction) of about ``scale`` times the path's
    length (or, with ``cylinders``, a cylinder in any orientation: the first always), moved off
    the path by up to ``spread``; the kinds in a drawn order."""
    from armanim.arm.chain import rpy_rotation
    from armanim.world.obstacles import BOX, CYLINDER, ROD, SPHERE, Boxes, Cylinders, Rods

    spheres, boxes, rods, cans, kinds, influence = [], [], [], [], [], []
    for a, b in zip(tips[:-1], tips[1:]):
        t = draw(st.floats(0.3, 0.7))
        center = a + t * (b - a) + np.array(draw(st.tuples(*(st.floats(-spread, spread) for _ in range(3)))))
        size = draw(st.floats(0.1, 0.4)) * max(np.linalg.norm(b - a), 0.5) * scale
        kind = (
            CYLINDER
            if cylinders and not kinds
            else draw(st.sampled_from([SPHERE, BOX, ROD, CYLINDER] if cylinders else [SPHERE, BOX, ROD]))
        )
        kinds.append(kind)
        influence.append(size + 0.5 * scale)
        if kind == SPHERE:
            spheres.append((center, size))
        elif kind == CYLINDER:
            cans.append(
                (
                    center,
                    rpy_rotation(draw(st.tuples(angles, angles, angles))),
                    size * draw(st.floats(0.2, 1.5)),
                    size * draw(st.floats(0.2, 1.0)),
                )
            )
        elif kind == BOX:
            half = size * np.array(draw(st.tuples(*(st.floats(0.2, 1.0) for _ in range(3)))))
            boxes.append((center, half, rpy_rotation(draw(st.tuples(angles, angles, angles)))))
        else:
            direction = np.array(draw(st.tuples(*(st.floats(-1.0, 1.0) for _ in range(3)))))
            assume(np.linalg.norm(direction) > 0.1)
            half_length = size * draw(st.floats(0.0, 2.0)) * direction / np.linalg.norm(direction)
            rods.append((center - half_length, center + half_length, size * draw(st.floats(0.2, 0.6))))
    return Obstacles(
        np.array([c for c, _ in spheres]).reshape(-1, 3),
        np.array([r for _, r in spheres]),
        np.array(influence),
        Boxes(
            np.array([c for c, _, _ in boxes]).reshape(-1, 3),
            np.array([h for _, h, _ in boxes]).reshape(-1, 3),
            np.array([r for _, _, r in boxes]).reshape(-1, 3, 3),
        ),
        Rods(
            np.array([a for a, _, _ in rods]).reshape(-1, 3),
            np.array([b for _, b, _ in rods]).reshape(-1, 3),
            np.array([r for _, _, r in rods]),
        ),
        kinds=np.array(kinds, dtype=int),
        cylinders=Cylinders(
            np.array([c for c, _, _, _ in cans]).reshape(-1, 3),
            np.array([m for _, m, _, _ in cans]).reshape(-1, 3, 3),
            np.array([h for _, _, h, _ in cans]),
            np.array([r for _, _, _, r in cans]),
        ),
    )


def with_floor(obstacles: Obstacles, floor: float | None) -> Obstacles:
    """The same obstacles with a floor plane (its column last, no field)."""
    from dataclasses import replace

    from armanim.world.obstacles import FLOOR

    if floor is None:
        return obstacles
    return replace(
        obstacles,
        influence=np.append(obstacles.influence, 0.0),
        floor=float(floor),
        kinds=np.append(obstacles.kinds, FLOOR),
    )


@st.composite
def shaped_problems(
    draw, max_links: int = 6, max_goals: int = 3, max_frames: int = 80, cylinders: bool = False
) -> Problem:
    """:func:`cluttered_problems` with spheres, boxes and capsules mixed (and cylinders, with
    ``cylinders``), and a floor below the base or none; the home capsules and the goals kept
    clear of every shape."""
    from armanim.world.distances import clearances, point_clearances

    arm = draw(arms(min_links=3, max_links=max_links))
    home = draw(poses(arm.n)) * 0.3
    half_width = draw(st.floats(0.1, 0.3))
    limits = draw(limits_for(home, margin_deg=10.0))
    solver = default_solver_settings(
        method=draw(st.sampled_from(METHODS)), max_step=0.5, max_frames_per_goal=max_frames, clearance=0.05
    )
    goal_poses = [
        np.clip(draw(poses(arm.n)), limits.lower + 0.02, limits.upper - 0.02)
        for _ in range(draw(st.integers(1, max_goals)))
    ]
    tips = forward(arm, np.array([home, *goal_poses])).tip
    obstacles = draw(shapes_across(tips, scale=1.0, spread=0.3, cylinders=cylinders))
    floor = draw(st.one_of(st.none(), st.floats(0.0, 1.0).map(lambda drop: float(arm.base[2]) - drop)))
    obstacles = with_floor(obstacles, floor)
    capsules = joint_capsules(arm, half_width)
    cl = clearances(forward(arm, home), obstacles, capsules)
    assume(np.all(cl.links > solver.clearance))
    assume(np.all(point_clearances(tips[1:], obstacles) > half_width + solver.clearance))
    return Problem(
        arm=arm,
        half_width=half_width,
        home=home,
        limits=limits,
        obstacles=obstacles,
        goals=tuple(Goal(tip, hold=0.0) for tip in tips[1:]),
        solver=solver,
        fps=30.0,
    )


@st.composite
def joint_goal_problems(draw, max_links: int = 5, max_goals: int = 3) -> Problem:
    """An arm of links among spheres, boxes, capsules and cylinders (and a floor or none), with
    joint goals: random poses inside the limits (some on a limit) whose capsules keep the clearance,
    as a scene's checks ask of them; the home clear too."""
    from armanim.world.distances import clearances

    arm = draw(arms(min_links=3, max_links=max_links))
    home = draw(poses(arm.n)) * 0.3
    half_width = draw(st.floats(0.1, 0.3))
    limits = draw(limits_for(home, margin_deg=10.0))
    solver = default_solver_settings(method=draw(st.sampled_from(METHODS)), max_frames_per_goal=200, clearance=0.05)
    goal_poses = []
    for _ in range(draw(st.integers(1, max_goals))):
        pose = np.clip(draw(poses(arm.n)), limits.lower, limits.upper)
        if draw(st.booleans()):  # a goal resting on one of its joint's limits
            j = draw(st.integers(0, arm.n - 1))
            bound = limits.lower[j] if draw(st.booleans()) else limits.upper[j]
            if np.isfinite(bound):
                pose[j] = bound
        goal_poses.append(pose)
    tips = forward(arm, np.array([home, *goal_poses])).tip
    obstacles = with_floor(
        draw(shapes_across(tips, scale=1.0, spread=0.3, cylinders=True)),
        draw(st.one_of(st.none(), st.floats(0.0, 1.0).map(lambda drop: float(arm.base[2]) - drop))),
    )
    capsules = joint_capsules(arm, half_width)
    assume(
        np.all(clearances(forward(arm, np.array([home, *goal_poses])), obstacles, capsules).links > solver.clearance)
    )
    return Problem(
        arm=arm,
        half_width=half_width,
        home=home,
        limits=limits,
        obstacles=obstacles,
        goals=tuple(Goal(tip, hold=0.0, joints=pose) for tip, pose in zip(tips[1:], goal_poses)),
        solver=solver,
        fps=30.0,
    )


@st.composite
def ros_poses(draw) -> tuple[list[float], list[float]]:
    """A ROS pose as a MoveIt file writes it: a position and a unit x-y-z-w quaternion (any rotation)."""
    position = [draw(st.floats(-2.0, 2.0, allow_nan=False, allow_infinity=False)) for _ in range(3)]
    q = np.array([draw(st.floats(-1.0, 1.0, allow_nan=False, allow_infinity=False)) for _ in range(4)])
    assume(np.linalg.norm(q) > 0.1)
    return position, (q / np.linalg.norm(q)).tolist()
