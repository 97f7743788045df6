"""The shapes families (issue 22): tables, shelves, walls with a gap, posts and a floor around
the notes' arms and the bundled robots; the poses family (issue 21).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from oracles.geometry import joint_points, solid_gaps
from oracles.robots import ROBOT_GEN_CLEARANCE, ROBOT_NAMES, base_geometry

from generators.arms import GEN_CLEARANCE, Draft, draw_arm, draw_robot_scene, poses_clear, random_pose, robot_pose


def along_rpy(along: np.ndarray, roll: float) -> list:
    """rpy (degrees) of a box whose own x axis points along ``along`` (R = Rz(yaw) Ry(pitch) Rx(roll))."""
    along = along / max(np.linalg.norm(along), 1e-12)
    return [
        roll,
        float(np.degrees(-np.arcsin(np.clip(along[2], -1, 1)))),
        float(np.degrees(np.arctan2(along[1], along[0]))),
    ]


def shape_table(rng, tip, scale: dict) -> dict:
    """A table under a goal tip: its top ``scale['gap']`` and a little more below the tip."""
    thick = rng.uniform(*scale["thick"])
    gap = scale["gap"] + rng.uniform(0.1, 1.0) * scale["slack"]
    center = tip - [0.0, 0.0, gap + thick / 2]
    size = [rng.uniform(*scale["top"]), rng.uniform(*scale["top"]), thick]
    return {"boxes": [(center, size, [0.0, 0.0, rng.uniform(-45, 45)])]}


def shape_shelf(rng, tip, scale: dict) -> dict:
    """Two boards above and below a goal tip (a shelf's compartment around it)."""
    thick = rng.uniform(*scale["board"])
    half_gap = scale["gap"] + rng.uniform(0.2, 1.0) * scale["slack"]
    size = [rng.uniform(*scale["top"]), rng.uniform(*scale["top"]), thick]
    yaw = rng.uniform(-45, 45)
    return {"boxes": [(tip + [0.0, 0.0, s * (half_gap + thick / 2)], size, [0.0, 0.0, yaw]) for s in (-1.0, 1.0)]}


def shape_wall(rng, a, b, scale: dict) -> dict:
    """A wall across the path a-b with a gap in it: two slabs either side of the path."""
    from armanim.arm.chain import rpy_rotation

    rpy = along_rpy(b - a, rng.uniform(-90, 90))
    side = rpy_rotation(np.radians(rpy))[:, 1]
    middle = a + rng.uniform(0.35, 0.65) * (b - a)
    size = [rng.uniform(*scale["board"]), rng.uniform(*scale["wall"]), rng.uniform(*scale["wall"])]
    half_gap = rng.uniform(*scale["passage"])
    return {"boxes": [(middle + s * (half_gap + size[1] / 2) * side, size, rpy) for s in (-1.0, 1.0)]}


def shape_post(rng, a, b, scale: dict) -> dict:
    """A vertical capsule across the path a-b."""
    center = a + rng.uniform(0.35, 0.65) * (b - a) + rng.normal(size=3) * scale["jitter"]
    half = rng.uniform(*scale["post_half"]) * np.array([0.0, 0.0, 1.0])
    return {"rods": [(center - half, center + half, rng.uniform(*scale["post_r"]))]}


def rounded_shapes(shapes: dict) -> dict:
    """The shapes with their numbers rounded as a scene file writes them."""
    return {
        "boxes": [
            (np.round(c, 4), [round(float(v), 4) for v in sz], [round(float(v), 3) for v in r])
            for c, sz, r in shapes.get("boxes", [])
        ],
        "rods": [(np.round(a, 4), np.round(b, 4), round(float(r), 4)) for a, b, r in shapes.get("rods", [])],
    }


def place_shapes(rng, draft: Draft, poses: list, tips: list, scale: dict, keep: float, count: int) -> None:
    """Add ``count`` shapes (tables, shelves, walls with a gap, posts), each kept only when
    every pose stays ``keep`` clear of it (and of the base: ``scale['base']``)."""
    for _ in range(count):
        for _ in range(30):
            kind = rng.choice(["table", "shelf", "wall", "post"])
            k = int(rng.integers(1, len(tips)))
            shapes = rounded_shapes(
                shape_table(rng, tips[k], scale)
                if kind == "table"
                else shape_shelf(rng, tips[k], scale)
                if kind == "shelf"
                else shape_wall(rng, tips[k - 1], tips[k], scale)
                if kind == "wall"
                else shape_post(rng, tips[k - 1], tips[k], scale)
            )
            trial = replace(draft, spheres=[], boxes=shapes["boxes"], rods=shapes["rods"], floor=None)
            if poses_clear(trial, poses, keep) and base_clear(trial, scale["base"]):
                draft.boxes.extend(shapes["boxes"])
                draft.rods.extend(shapes["rods"])
                break


def base_clear(draft: Draft, room: float) -> bool:
    """Whether no shape comes within ``room`` of the segment from the base 0.3 m (or a link length) down."""
    base = draft.base if draft.robot is None else np.zeros(3)
    solids = replace(draft.solids(), floor=None)
    if not len(solids):
        return True
    drop = np.array([0.0, 0.0, 0.3 if draft.robot else float(draft.links[0])])
    return bool(np.all(solid_gaps(solids, (base - drop)[None], base[None], np.array([room]), np.zeros(1, bool)) > 0))


LINK_SCALE = {
    "thick": (0.1, 0.3),
    "board": (0.1, 0.2),
    "top": (1.0, 3.0),
    "wall": (1.0, 3.0),
    "passage": (0.8, 1.5),
    "post_half": (1.0, 3.0),
    "post_r": (0.15, 0.4),
    "jitter": 0.2,
    "base": 0.5,
}


ROBOT_SCALE = {
    "thick": (0.03, 0.06),
    "board": (0.02, 0.03),
    "top": (0.3, 0.6),
    "wall": (0.2, 0.5),
    "passage": (0.12, 0.25),
    "post_half": (0.15, 0.3),
    "post_r": (0.02, 0.04),
    "jitter": 0.02,
    "base": 0.12,
}


def poses_above(rng, draft: Draft, draw_pose, count: int, keep: float) -> list:
    """``count`` poses (from ``draw_pose()``) that keep ``keep`` from the draft's floor (60 tries each)."""
    poses = []
    for _ in range(count):
        for _ in range(60):
            pose = draw_pose()
            if poses_clear(draft, [pose], keep):
                poses.append(pose)
                break
    return poses


def draw_shapes_scene(rng: np.random.Generator) -> Draft:
    """One candidate scene of the shapes family (issue 22): an arm of the standard family (the notes'
    kind, planar, mixed; 3-7 links), a floor under its base in 60 % of the scenes, 3-6 goal poses
    above it, then 2-5 tables, shelves, walls with a gap and posts across and around the goals."""
    draft = draw_arm(rng)
    size = float(np.mean(draft.links))
    if rng.random() < 0.6:
        draft.floor = round(float(draft.base[2] - rng.uniform(0.0, 0.5) * size), 4)
        if not poses_clear(draft, [draft.home], GEN_CLEARANCE):
            draft.floor = None
    goal_poses = poses_above(rng, draft, lambda: random_pose(rng, draft), int(rng.integers(3, 7)), GEN_CLEARANCE)
    tips = [joint_points(draft.geometry(), p)[-1] for p in [draft.home] + goal_poses]
    scale = {k: tuple(v * size for v in val) if isinstance(val, tuple) else val * size for k, val in LINK_SCALE.items()}
    scale.update(gap=draft.width / 2 + GEN_CLEARANCE, slack=0.3 * size, passage=(1.25 * draft.width, 2.5 * draft.width))
    place_shapes(rng, draft, [draft.home] + goal_poses, tips, scale, GEN_CLEARANCE, int(rng.integers(2, 6)))
    draft.influence = round(0.3 * size, 4)
    draft.goals = [np.round(t, 4) for t in tips[1:]]
    draft.witnesses = list(goal_poses)
    return draft


def draw_robot_shapes_scene(rng: np.random.Generator) -> Draft:
    """One candidate scene of the robot-shapes family (issue 22): a bundled Panda, UR5 or iiwa
    standing on the floor (z = 0), 3-5 goals (tool points of poses above the floor), 2-4 tables,
    shelves, walls with a gap and posts across and around them (metres)."""
    robot = ROBOT_NAMES[int(rng.integers(0, len(ROBOT_NAMES)))]
    geo = base_geometry(robot)
    draft = Draft(
        kind=robot,
        base=np.zeros(3),
        links=np.array([geo.reach]),
        axes=[],
        direction="z",
        width=0.1,
        home=geo.home,
        limits=[],
        robot=robot,
        floor=0.0,
        influence=0.05,
    )
    goal_poses = poses_above(rng, draft, lambda: robot_pose(rng, geo), int(rng.integers(3, 6)), ROBOT_GEN_CLEARANCE)
    tips = list(geo.placements(np.array([geo.home] + goal_poses))[0])
    tip_room = 0.07 + ROBOT_GEN_CLEARANCE  # the largest tool capsule radius of the bundled robots, and the margin
    scale = dict(ROBOT_SCALE, gap=tip_room, slack=0.05)
    place_shapes(rng, draft, [geo.home] + goal_poses, tips, scale, ROBOT_GEN_CLEARANCE, int(rng.integers(2, 5)))
    draft.goals = [np.round(t, 4) for t in tips[1:]]
    draft.witnesses = list(goal_poses)
    return draft


def draw_pose_scene(rng: np.random.Generator) -> Draft:
    """One candidate scene of the poses family (issue 21): the robot family's scene, each goal with
    the tool's orientation of its generator pose as well (a 6-D goal)."""
    draft = draw_robot_scene(rng)
    geo = base_geometry(draft.robot)
    draft.orientations = [geo.rotation(pose) for pose in draft.witnesses]
    draft.kind = f"{draft.robot}-pose"
    return draft
