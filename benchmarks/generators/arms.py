"""Scene generators of the motion benchmark: a :class:`Draft` scene and the families of
arms among spheres (standard, hard: issue 18; robots: issue 20).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np
from oracles.geometry import AXES, AXIS_INDEX, DEFAULT_CLEARANCE, Geometry, Solids, joint_points
from oracles.robots import (
    ROBOT_BASE_KEEP_OUT,
    ROBOT_GEN_CLEARANCE,
    ROBOT_NAMES,
    ROBOT_SOLVER,
    RobotGeometry,
    base_geometry,
    min_clearance,
)

GEN_CLEARANCE = 0.3  # the generator keeps home and goal poses this far from every sphere


GEN_LIMIT_MARGIN = np.radians(20.0)  # ... and home and goal poses this far inside their limits


HARD_CLEARANCE = 0.12  # the hard family keeps home and goal poses only this far from every sphere


@dataclass
class Draft:
    """A scene being drawn, radians inside; ``as_scene_dict`` writes it in scene-file form."""

    kind: str
    base: np.ndarray
    links: np.ndarray
    axes: list
    direction: str
    width: float
    home: np.ndarray  # radians, rounded to 1e-3 degree
    limits: list  # per joint None or (lo, hi) in whole degrees
    spheres: list = field(default_factory=list)  # (center (3,), radius)
    goals: list = field(default_factory=list)  # (3,) arrays
    witnesses: list = field(default_factory=list)  # the generator's pose per goal (None: out of reach)
    orientations: list = field(
        default_factory=list
    )  # the tool's rotation (3, 3) per goal (the poses family), else empty
    robot: str | None = None  # a bundled robot (the robot family): base, links, axes, direction, limits unused
    boxes: list = field(default_factory=list)  # (center (3,), size (3,) full edges, rpy (3,) degrees)
    rods: list = field(default_factory=list)  # (from (3,), to (3,), radius)
    floor: float | None = None
    influence: float | None = None  # of the boxes and capsules (None: the scene's default)

    def solids(self) -> Solids:
        """The oracle's view of the boxes, capsules and floor."""
        from armanim.arm.chain import rpy_rotation  # a rotation is data here: the contract's formula of rpy

        boxes = tuple(
            (np.asarray(c, float), np.asarray(sz, float) / 2, rpy_rotation(np.radians(r))) for c, sz, r in self.boxes
        )
        return Solids(
            boxes, tuple((np.asarray(a, float), np.asarray(b, float), float(r)) for a, b, r in self.rods), self.floor
        )

    def geometry(self, clearance: float = DEFAULT_CLEARANCE, tolerance: float = 0.01) -> Geometry:
        """The oracle's view of this draft."""
        if self.robot is not None:
            centers = np.array([c for c, _ in self.spheres]).reshape(-1, 3)
            return replace(
                base_geometry(self.robot),
                centers=centers,
                radii=np.array([r for _, r in self.spheres]),
                tolerance=tolerance,
                clearance=clearance,
                solids=self.solids(),
            )
        lower = np.array([np.radians(p[0]) if p else -np.inf for p in self.limits])
        upper = np.array([np.radians(p[1]) if p else np.inf for p in self.limits])
        return Geometry(
            base=self.base,
            links=self.links,
            axes=tuple(self.axes),
            direction=AXES[AXIS_INDEX[self.direction]],
            half_width=self.width / 2,
            lower=lower,
            upper=upper,
            centers=np.array([c for c, _ in self.spheres]).reshape(-1, 3),
            radii=np.array([r for _, r in self.spheres]),
            home=self.home,
            tolerance=tolerance,
            clearance=clearance,
            solids=self.solids(),
        )

    def shape_entries(self) -> list:
        """The boxes and capsules as scene-file obstacles."""
        extra = {} if self.influence is None else {"influence": self.influence}
        boxes = [
            {"box": {"center": floats(c), "size": floats(sz), "rpy": floats(r, 3)}, **extra} for c, sz, r in self.boxes
        ]
        rods = [{"capsule": {"from": floats(a), "to": floats(b), "radius": float(r)}, **extra} for a, b, r in self.rods]
        return boxes + rods

    def with_floor(self, scene: dict) -> dict:
        """``scene`` with the draft's shapes appended to its obstacles and its floor."""
        scene["obstacles"] = scene["obstacles"] + self.shape_entries()
        if self.floor is not None:
            scene["floor"] = float(self.floor)
        return scene

    def spheres_twin(self) -> Draft:
        """The same scene with every box and capsule replaced by the largest sphere inside it (at
        its centre): a scene of spheres only, for timing frames against the shapes' cost."""
        inner = [(np.asarray(c, float), round(float(min(sz)) / 2, 4)) for c, sz, _ in self.boxes]
        inner += [((np.asarray(a, float) + np.asarray(b, float)) / 2, float(r)) for a, b, r in self.rods]
        return replace(self, spheres=list(self.spheres) + inner, boxes=[], rods=[], floor=None)

    def as_scene_dict(self, name: str, method: str = "pinv", planner: str | None = None) -> dict:
        """The draft as a scene file's mapping (degrees), ready for ``scene_model``."""
        solver = {"method": method}
        if planner is not None:
            solver["planner"] = planner
        if self.robot is not None:
            return self.with_floor(
                {
                    "version": 1,
                    "name": name,
                    "arm": {"robot": self.robot},
                    "obstacles": [{"center": floats(c), "radius": float(r), "influence": 0.1} for c, r in self.spheres],
                    "goals": [
                        goal_entry(g, self.orientations[k] if self.orientations else None)
                        for k, g in enumerate(self.goals)
                    ],
                    "solver": {**solver, **ROBOT_SOLVER},
                    "render": {"fps": 30},
                }
            )
        return self.with_floor(
            {
                "version": 1,
                "name": name,
                "arm": {
                    "base": floats(self.base),
                    "links": floats(self.links),
                    "axes": list(self.axes),
                    "direction": self.direction,
                    "home": floats(np.degrees(self.home), 3),
                    "limits": [None if p is None else [float(p[0]), float(p[1])] for p in self.limits],
                    "width": float(self.width),
                },
                "obstacles": [{"center": floats(c), "radius": float(r)} for c, r in self.spheres],
                "goals": [floats(g) for g in self.goals],
                "solver": solver,
                "render": {"fps": 30},
            }
        )


def goal_entry(position: np.ndarray, rotation: np.ndarray | None):
    """A goal of the scene file: the point, or the point and the tool's orientation as a quaternion
    (pinocchio's, written w first, 9 decimals)."""
    if rotation is None:
        return floats(position)
    import pinocchio as pin

    q = pin.Quaternion(np.asarray(rotation, dtype=float)).coeffs()  # x, y, z, w
    return {"position": floats(position), "orientation": {"quaternion_wxyz": floats([q[3], q[0], q[1], q[2]], 9)}}


def floats(values, decimals: int = 4) -> list:
    """Plain Python floats rounded for a readable scene file."""
    return [round(float(v), decimals) for v in np.asarray(values).ravel()]


def draw_arm(rng: np.random.Generator) -> Draft:
    """An arm of 3-7 links: the course notes' kind, a planar(-ish) one or one with mixed axes; home and limits."""
    n = int(rng.integers(3, 8))
    kind = str(rng.choice(["notes", "planar", "mixed"], p=[0.4, 0.3, 0.3]))
    if kind == "notes":
        axes, direction = ["z"] + ["y"] * (n - 1), "z"
        links = np.concatenate([[rng.uniform(1, 3)], rng.uniform(2, 6, n - 1)])
    elif kind == "planar":
        axes, direction = ["z"] * n, "x"
        if rng.random() < 0.4:  # planar-ish: one joint lifts the arm out of its plane
            axes[int(rng.integers(1, n))] = "y"
        links = rng.uniform(1.5, 5, n)
    else:
        direction = str(rng.choice(["x", "y", "z"]))
        choices = [a for a in "xyz" if a != direction]
        axes = ["z" if direction != "z" else "x"] + [str(rng.choice(choices)) for _ in range(n - 1)]
        links = rng.uniform(1, 5, n)
    home = np.zeros(n) if rng.random() < 0.5 else np.radians(np.round(rng.uniform(-60, 60, n), 3))
    limits = [draw_limit(rng, np.degrees(h)) if rng.random() < 0.5 else None for h in home]
    return Draft(
        kind=kind,
        base=np.round(rng.uniform(-5, 5, 3), 4),
        links=np.round(links, 4),
        axes=axes,
        direction=direction,
        width=round(float(rng.uniform(0.3, 0.6)), 3),
        home=home,
        limits=limits,
    )


def draw_limit(rng: np.random.Generator, home_deg: float) -> tuple[float, float]:
    """Whole-degree limits with home at least 25 degrees inside each, within [-175, 175]."""
    lo = float(np.floor(rng.uniform(max(-175.0, home_deg - 150), home_deg - 25)))
    hi = float(np.ceil(rng.uniform(home_deg + 25, min(175.0, home_deg + 150))))
    return lo, hi


def random_pose(rng: np.random.Generator, draft: Draft) -> np.ndarray:
    """A pose inside the limits, GEN_LIMIT_MARGIN away from them (free joints anywhere)."""
    geo = draft.geometry()
    lo = np.where(np.isfinite(geo.lower), geo.lower + GEN_LIMIT_MARGIN, -np.pi)
    hi = np.where(np.isfinite(geo.upper), geo.upper - GEN_LIMIT_MARGIN, np.pi)
    return rng.uniform(lo, hi)


def poses_clear(draft: Draft, poses: list, margin: float) -> bool:
    """True when every pose's capsules are at least ``margin`` from every sphere of the draft."""
    if not (draft.spheres or draft.boxes or draft.rods or draft.floor is not None) or not poses:
        return True
    return bool(np.all(min_clearance(draft.geometry(), np.array(poses)) >= margin))


def draw_goal_poses(rng: np.random.Generator, draft: Draft) -> list:
    """3-6 poses inside the limits whose tips will be the goals."""
    return [random_pose(rng, draft) for _ in range(int(rng.integers(3, 7)))]


def sphere_across(rng: np.random.Generator, a: np.ndarray, b: np.ndarray, size: float):
    """A sphere on the straight segment a-b, a little off its middle."""
    length = np.linalg.norm(b - a)
    radius = float(np.clip(rng.uniform(0.15, 0.35) * length, 0.3, size))
    offset = rng.normal(size=3) * 0.2 * radius
    return a + rng.uniform(0.35, 0.65) * (b - a) + offset, radius


def sphere_near_arm(rng: np.random.Generator, draft: Draft, pose: np.ndarray, size: float):
    """A sphere just beside a random point of the arm in ``pose``."""
    points = joint_points(draft.geometry(), pose)
    link = int(rng.integers(0, len(draft.links)))
    on_arm = points[link] + rng.uniform(0, 1) * (points[link + 1] - points[link])
    radius = float(rng.uniform(0.3, 1.0) * size)
    direction = rng.normal(size=3)
    direction /= np.linalg.norm(direction)
    gap = draft.width / 2 + GEN_CLEARANCE + rng.uniform(0.05, 0.8)
    return on_arm + (radius + gap) * direction, radius


def sphere_anywhere(rng: np.random.Generator, draft: Draft, size: float):
    """A sphere anywhere within the arm's reach."""
    direction = rng.normal(size=3)
    direction /= np.linalg.norm(direction)
    center = draft.base + direction * rng.uniform(0.3, 1.0) * draft.links.sum()
    return center, float(rng.uniform(0.3, 1.0) * size)


def place_spheres(rng: np.random.Generator, draft: Draft, goal_poses: list) -> None:
    """Add 2-8 spheres: across the paths between consecutive tips, beside the arm, anywhere.

    A sphere is kept only when home and every goal pose stay GEN_CLEARANCE clear of it.
    """
    geo = draft.geometry()
    tips = [joint_points(geo, p)[-1] for p in [draft.home] + goal_poses]
    size = float(np.mean(draft.links))
    wanted = int(rng.integers(2, 9))
    across = min(int(rng.integers(1, 5)), len(tips) - 1, wanted)
    near = min(int(rng.integers(0, 3)), wanted - across)
    kinds = ["across"] * across + ["near"] * near + ["anywhere"] * (wanted - across - near)
    segments = rng.permutation(len(tips) - 1)
    for i, kind in enumerate(kinds):
        for _ in range(30):
            if kind == "across":
                k = int(segments[i % len(segments)])
                candidate = sphere_across(rng, tips[k], tips[k + 1], size)
            elif kind == "near":
                pose = [draft.home] + goal_poses
                candidate = sphere_near_arm(rng, draft, pose[int(rng.integers(0, len(pose)))], size)
            else:
                candidate = sphere_anywhere(rng, draft, size)
            center = np.round(candidate[0], 4)
            trial = Draft(**{**draft.__dict__, "spheres": [(center, round(candidate[1], 4))]})
            if poses_clear(trial, [draft.home] + goal_poses, GEN_CLEARANCE):
                draft.spheres.append((center, round(candidate[1], 4)))
                break


def out_of_reach_goal(rng: np.random.Generator, draft: Draft) -> np.ndarray:
    """A point 1.1-1.5 times the arm's length from its base, outside every sphere."""
    while True:
        direction = rng.normal(size=3)
        direction /= np.linalg.norm(direction)
        goal = np.round(draft.base + direction * rng.uniform(1.1, 1.5) * draft.links.sum(), 4)
        if all(np.linalg.norm(goal - c) > r + 1.0 for c, r in draft.spheres):
            return goal


def draw_scene(rng: np.random.Generator) -> Draft:
    """One candidate scene (not yet validated by armanim)."""
    draft = draw_arm(rng)
    goal_poses = draw_goal_poses(rng, draft)
    place_spheres(rng, draft, goal_poses)
    geo = draft.geometry()
    draft.goals = [np.round(joint_points(geo, p)[-1], 4) for p in goal_poses]
    draft.witnesses = list(goal_poses)
    if rng.random() < 0.2:
        at = int(rng.integers(0, len(draft.goals) + 1))
        draft.goals.insert(at, out_of_reach_goal(rng, draft))
        draft.witnesses.insert(at, None)
    return draft


def draw_tight_arm(rng: np.random.Generator) -> Draft:
    """The hard family's arm: 7 links with mixed axes, a planar arm of 3-7, or the notes' kind;
    every joint limited, 70-160 degrees of range with home at least 25 inside."""
    draft = draw_arm(rng)
    kind = str(rng.choice(["mixed", "planar", "notes"], p=[0.4, 0.35, 0.25]))
    while draft.kind != kind or (kind == "mixed" and len(draft.links) != 7) or (kind == "planar" and "y" in draft.axes):
        draft = draw_arm(rng)
    home = np.degrees(draft.home)
    draft.limits = [(float(np.floor(h - rng.uniform(25, 80))), float(np.ceil(h + rng.uniform(25, 80)))) for h in home]
    draft.limits = [(max(lo, -175.0), min(hi, 175.0)) for lo, hi in draft.limits]
    return draft


def sphere_pair_across(rng: np.random.Generator, draft: Draft, a: np.ndarray, b: np.ndarray, size: float) -> list:
    """Two spheres either side of the segment a-b, leaving a passage 2.5-5 arm widths wide."""
    middle = a + rng.uniform(0.35, 0.65) * (b - a)
    along = (b - a) / max(np.linalg.norm(b - a), 1e-9)
    side = np.cross(along, rng.normal(size=3))
    side /= max(np.linalg.norm(side), 1e-9)
    radius = float(rng.uniform(0.4, 1.0) * size)
    half_gap = rng.uniform(1.25, 2.5) * draft.width
    return [(middle + s * (half_gap + radius) * side, radius) for s in (-1.0, 1.0)]


def sphere_near_goal(rng: np.random.Generator, draft: Draft, pose: np.ndarray, size: float):
    """A sphere beside the arm in a goal pose, only a few clearances away from it."""
    center, radius = sphere_near_arm(rng, draft, pose, size)
    points = joint_points(draft.geometry(), pose)
    pull = GEN_CLEARANCE + rng.uniform(0.05, 0.6)  # sphere_near_arm leaves this much more than needed
    direction = center - points[-1]
    return center - pull * direction / max(np.linalg.norm(direction), 1e-9), radius


def place_clutter(rng: np.random.Generator, draft: Draft, goal_poses: list) -> None:
    """6-12 spheres: passages across the paths, spheres close to goal poses, the rest anywhere.

    A sphere is kept only when home and every goal pose stay HARD_CLEARANCE clear of it."""
    geo = draft.geometry()
    tips = [joint_points(geo, p)[-1] for p in [draft.home] + goal_poses]
    size = float(np.mean(draft.links)) * 0.6
    poses = [draft.home] + goal_poses
    for _ in range(int(rng.integers(6, 13))):
        for _ in range(30):
            kind = rng.choice(["passage", "near_goal", "across", "anywhere"], p=[0.3, 0.3, 0.2, 0.2])
            k = int(rng.integers(0, len(tips) - 1))
            if kind == "passage":
                candidates = sphere_pair_across(rng, draft, tips[k], tips[k + 1], size)
            elif kind == "near_goal":
                candidates = [sphere_near_goal(rng, draft, goal_poses[int(rng.integers(0, len(goal_poses)))], size)]
            elif kind == "across":
                candidates = [sphere_across(rng, tips[k], tips[k + 1], size)]
            else:
                candidates = [sphere_anywhere(rng, draft, size)]
            rounded = [(np.round(c, 4), round(float(r), 4)) for c, r in candidates]
            trial = Draft(**{**draft.__dict__, "spheres": rounded})
            if poses_clear(trial, poses, HARD_CLEARANCE):
                draft.spheres.extend(rounded)
                break


def draw_hard_scene(rng: np.random.Generator) -> Draft:
    """One candidate scene of the hard family: tight limits, 8-12 goals (some at the edge of
    reach, some close to a sphere), dense clutter and narrow passages."""
    draft = draw_tight_arm(rng)
    goal_poses = [random_pose(rng, draft) for _ in range(int(rng.integers(8, 13)))]
    for k in range(len(goal_poses)):
        if rng.random() < 0.25:  # at the edge of reach: nearly straight (limits permitting)
            geo = draft.geometry()
            straight = np.clip(goal_poses[k] * 0.15, geo.lower + GEN_LIMIT_MARGIN, geo.upper - GEN_LIMIT_MARGIN)
            goal_poses[k] = np.where(np.isfinite(geo.lower), straight, goal_poses[k])
    place_clutter(rng, draft, goal_poses)
    draft.goals = [np.round(joint_points(draft.geometry(), p)[-1], 4) for p in goal_poses]
    draft.witnesses = list(goal_poses)
    return draft


def robot_pose(rng: np.random.Generator, geo: RobotGeometry) -> np.ndarray:
    """A pose inside the limits, 10 degrees away from them, within +-180 degrees, tool point 0.1 m above the base."""
    lo = np.maximum(geo.lower + np.radians(10.0), -np.pi)
    hi = np.minimum(geo.upper - np.radians(10.0), np.pi)
    while True:
        pose = rng.uniform(lo, hi)
        if geo.tip(pose)[2] > 0.1:
            return pose


def draw_robot_scene(rng: np.random.Generator) -> Draft:
    """One candidate scene of the robot family: a bundled robot (Panda, UR5 or iiwa) at its home
    pose, 3-5 goals that are the tool points of random poses inside the limits, 3-10 spheres
    (across the tool's straight paths between goals, beside the arm in a goal pose, anywhere
    within reach), each kept only when home and every goal pose stay ROBOT_GEN_CLEARANCE clear."""
    robot = ROBOT_NAMES[int(rng.integers(0, len(ROBOT_NAMES)))]
    geo = base_geometry(robot)
    goal_poses = [robot_pose(rng, geo) for _ in range(int(rng.integers(3, 6)))]
    poses = np.array([geo.home] + goal_poses)
    tips, ends_a, ends_b = geo.placements(poses)
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
    )
    for _ in range(int(rng.integers(3, 11))):
        for _ in range(30):
            kind = rng.choice(["across", "near", "anywhere"], p=[0.4, 0.3, 0.3])
            radius = float(rng.uniform(0.03, 0.1))
            if kind == "across":
                k = int(rng.integers(0, len(tips) - 1))
                center = tips[k] + rng.uniform(0.35, 0.65) * (tips[k + 1] - tips[k]) + rng.normal(size=3) * 0.3 * radius
            elif kind == "near":
                k, c = int(rng.integers(1, len(poses))), int(rng.integers(0, len(geo.cap_r)))
                on_arm = ends_a[k, c] + rng.uniform(0, 1) * (ends_b[k, c] - ends_a[k, c])
                direction = rng.normal(size=3)
                gap = geo.cap_r[c] + ROBOT_GEN_CLEARANCE + rng.uniform(0.01, 0.1)
                center = on_arm + (radius + gap) * direction / np.linalg.norm(direction)
            else:
                direction = rng.normal(size=3)
                center = direction / np.linalg.norm(direction) * rng.uniform(0.3, 1.0) * geo.reach / 1.1
            center, radius = np.round(center, 4), round(radius, 4)
            if np.linalg.norm(center) < ROBOT_BASE_KEEP_OUT + radius:
                continue
            trial = replace(geo, centers=center[None], radii=np.array([radius]))
            if np.all(min_clearance(trial, poses) >= ROBOT_GEN_CLEARANCE):
                draft.spheres.append((center, radius))
                break
    draft.goals = [np.round(t, 4) for t in tips[1:]]
    draft.witnesses = list(goal_poses)
    return draft
