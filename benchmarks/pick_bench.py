"""Issue 54's benchmark: pick and place.

Seeded scenes (``--scenes``, half a Franka Panda's, half a UR5's): a box or an upright cylinder of
random size stands on a table (touching it) at a random place beside the arm; the tool comes down
onto it (``approach``), takes it (``grasp``), lifts it off the table along a straight line
(``retreat``), carries it to a random place on a shelf board of random height in front of the arm,
comes down along a straight line (``approach``) and puts it on the board (``release``, touching
it), and lifts away; half the scenes have a post (a capsule) standing between. A scene armanim's
validation refuses is drawn again (counted).

Each place goal is labelled feasible or not by an oracle of its own: pinocchio's kinematics of the
bundled URDF (not armanim's), a least-squares search for a pose inside the limits that puts the
tool at the release pose (many seeded starts), and coal's distances (not armanim's) from that
pose's link capsules and from the carried solid itself (box or cylinder, not its cover, placed at
that tool pose times the grasp offset the grasp goal implies) to every obstacle: feasible when
some pose found keeps every clearance the run must keep there (the solid may touch the board,
never enter it).

Measured on armanim's runs (solve, then the clock), each again by the oracle's own code:

- frames where the carried solid (coal, its own shape) comes under ``solver.clearance`` of an
  obstacle or the floor, or under ``self_clearance`` of a link that is not a touch link (coal
  capsules): target 0; but along the grasp's retreat (off the table) and the release's approach
  (onto the board), the only frames where it may touch them, the solid's distance to that table or
  board must only be >= 0 (-1e-9: rounding; it must never enter it), and it keeps
  ``solver.clearance`` from everything else;
- the placed pose against pinocchio's tool pose at the release frame times the offset from its
  tool pose at the grasp frame: target exact to 1e-9;
- feasible place goals reached: target at least 95 %;
- the planner's CPU time with the object (the carrying world) over its time without it (the same
  arm, start and goal, the object left out): target at most 1.5x (min of 3 each, interleaved).

Run: ``python benchmarks/pick_bench.py [--seed 0] [--scenes 20]``.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "benchmarks"))

from armanim.arm.capsules import capsule_ends  # noqa: E402
from armanim.arm.kinematics import forward  # noqa: E402
from armanim.motion.carry import World, goal_problems, touch_links, world_problem  # noqa: E402
from armanim.motion.timing.retime import retime  # noqa: E402
from armanim.motion.trajectory import solve_trajectory  # noqa: E402
from armanim.scene import scene_model, scene_to_problem  # noqa: E402
from armanim.scene.checks import scene_problems  # noqa: E402
from armanim.world.carried import Body, obstacle_body, with_bodies  # noqa: E402
from armanim.world.obstacles import BOX, CYLINDER, FLOOR, SPHERE  # noqa: E402

DOWN = {"orientation": {"rpy": [180, 0, 0]}}
LINE = 0.1  # the grasp's and the release's straight lines (approach and retreat), metres
INSIDE = 1e-9  # how far coal may find the solid inside its table or board (rounding of a box set on it)


def draw_scene(rng: np.random.Generator, robot: str, index: int) -> dict:
    """One scene mapping: a table, an object on it, a shelf board, perhaps a post, six goals."""
    clearance = 0.02 if robot == "panda" else 0.01
    kind = "box" if rng.random() < 0.6 else "cylinder"
    height = float(
        rng.uniform(0.11, 0.15) if robot == "panda" else rng.uniform(0.05, 0.1)
    )  # the Panda's hand 9 cm above the table
    if kind == "box":
        width = float(rng.uniform(0.03, 0.05))
        shape = {"box": {"center": [0, 0, 0], "size": [width, width, height]}}
    else:
        radius = float(rng.uniform(0.015, 0.024))
        shape = {"cylinder": {"center": [0, 0, 0], "length": height, "radius": radius}}
    side = 1 if rng.random() < 0.5 else -1
    table = np.array([rng.uniform(0.2, 0.35), side * rng.uniform(0.35, 0.5)])
    rest = 0.2 + height / 2  # standing on the table
    top = rest + height / 2
    grasp = top - (0.02 if robot == "panda" else 0.0)  # the Panda's fingers round the top, the UR5's flange on it
    shape[kind]["center"] = [float(table[0]), float(table[1]), rest]
    board = float(rng.uniform(0.25, 0.38))
    place = np.array([rng.uniform(0.5, 0.62), rng.uniform(-0.15, 0.15)])
    placed_top = board + height  # standing on the board
    release = placed_top - (top - grasp)
    obstacles = [
        {"box": {"center": [0.65, 0.0, board - 0.01], "size": [0.3, 0.7, 0.02]}},
        {"box": {"center": [float(table[0]), float(table[1]), 0.1], "size": [0.25, 0.25, 0.2]}, "name": "table"},
        {**shape, "name": "object"},
    ]
    if rng.random() < 0.5:
        post = [float(rng.uniform(0.3, 0.45)), float(side * rng.uniform(0.1, 0.2))]
        obstacles.append({"capsule": {"from": [*post, 0.0], "to": [*post, 0.45], "radius": 0.03}, "name": "post"})
    above = max(grasp, release) + LINE + 0.05
    line = {"approach": {"distance": LINE}, "retreat": {"distance": LINE}}
    arm = {"robot": robot, **({"joint_values": {"panda_finger_joint1": 0.04}} if robot == "panda" else {})}
    goals = [
        {"position": [float(table[0]), float(table[1]), grasp + LINE], **DOWN},
        {"position": [float(table[0]), float(table[1]), grasp], **DOWN, "grasp": "object", **line},
        {"position": [float(table[0]), float(table[1]), above], **DOWN},
        {"position": [float(place[0]), float(place[1]), above], **DOWN},
        {"position": [float(place[0]), float(place[1]), release], **DOWN, "release": True, **line},
        {"position": [float(place[0]), float(place[1]), release + LINE + 0.05], **DOWN},
    ]
    return {
        "version": 1,
        "name": f"pick-{robot}-{index}",
        "arm": arm,
        "obstacles": obstacles,
        "floor": 0.0,
        "goals": goals,
        "solver": {"method": "dls", "tolerance": 0.005, "clearance": clearance, "max_step": 0.02},
    }


def indices(problem) -> dict[str, int]:
    """The problem goals of the drawn scene's: the grasp, the lift above it, the way over the
    board, the release (after the goal to its approach's start) and the grasp's retreat (the
    scene's retreats and the ways to an approach are goals of their own)."""
    goals = problem.goals
    grasp = next(k for k, g in enumerate(goals) if g.grasp is not None)
    release = next(k for k, g in enumerate(goals) if g.release)
    return {"grasp": grasp, "retreat": grasp + 1, "lift": grasp + 2, "over": grasp + 3, "release": release}


def goal_point(goal) -> np.ndarray:
    """Where a goal puts the tool: a path goal's (an approach's) line's end."""
    return goal.path.end if goal.path is not None else goal.position


# ---- the oracle: pinocchio's kinematics, scipy's search, coal's distances ------------------


class Oracle:
    """A bundled robot as pinocchio sees it: the tool frame and the link capsules of a pose."""

    def __init__(self, robot: str, scene):
        import pinocchio as pin
        from oracles.robots import robot_model

        self.pin = pin
        self.model, self.capsules = robot_model(robot)
        self.data = self.model.createData()
        arm = scene.arm.urdf_arm
        self.tool = self.model.getFrameId(arm.tip_link)
        self.frames = [self.model.getFrameId(c.link) for c in self.capsules]
        self.lower, self.upper = self.model.lowerPositionLimit.copy(), self.model.upperPositionLimit.copy()

    def placements(self, q: np.ndarray) -> None:
        self.pin.framesForwardKinematics(self.model, self.data, q)

    def tool_pose(self, q: np.ndarray) -> np.ndarray:
        """(4, 4) world-from-tool at ``q``."""
        self.placements(q)
        return np.array(self.data.oMf[self.tool].homogeneous)

    def link_capsules(self, q: np.ndarray) -> list[tuple[str, np.ndarray, np.ndarray, float]]:
        """(link, a, b, radius) of each capsule at ``q``, world."""
        self.placements(q)
        out = []
        for c, f in zip(self.capsules, self.frames):
            m = self.data.oMf[f]
            out.append(
                (
                    c.link,
                    m.rotation @ np.asarray(c.start) + m.translation,
                    m.rotation @ np.asarray(c.end) + m.translation,
                    float(c.radius),
                )
            )
        return out

    def ik(self, target: np.ndarray, rng: np.random.Generator, starts: int = 24) -> list[np.ndarray]:
        """Poses inside the limits whose tool is at ``target`` (4, 4) to 1e-6 m and 1e-5 rad."""
        from scipy.optimize import least_squares

        def residual(q):
            pose = self.tool_pose(q)
            rot = self.pin.log3(target[:3, :3].T @ pose[:3, :3])
            return np.concatenate([pose[:3, 3] - target[:3, 3], 0.3 * rot])

        found = []
        for _ in range(starts):
            q0 = rng.uniform(self.lower, self.upper)
            fit = least_squares(residual, q0, bounds=(self.lower, self.upper), xtol=1e-12, ftol=1e-12, gtol=1e-12)
            r = residual(fit.x)
            if np.linalg.norm(r[:3]) < 1e-6 and np.linalg.norm(r[3:]) < 1e-5 * 0.3:
                found.append(fit.x)
        return found


def coal_solid(body: Body):
    """coal's shape and placement of a solid (a capsule along coal's z)."""
    import coal

    if body.kind == BOX:
        return coal.Box(*(2 * body.half)), coal.Transform3s(body.rotation, body.center)
    if body.kind == CYLINDER:
        return coal.Cylinder(body.radius, 2 * body.half[2]), coal.Transform3s(body.rotation, body.center)
    if body.kind == SPHERE:
        return coal.Sphere(body.radius), coal.Transform3s(np.eye(3), body.center)
    turn = np.array([[0, 0, 1], [0, 1, 0], [-1, 0, 0.0]])  # coal's capsule along z; the body's along x
    return coal.Capsule(body.radius, 2 * body.half[0]), coal.Transform3s(body.rotation @ turn, body.center)


def coal_capsule(a: np.ndarray, b: np.ndarray, radius: float):
    from oracles.geometry import coal_capsule as made

    return made(a, b, radius)


def gap(one, two) -> float:
    import coal

    return float(coal.distance(*one, *two, coal.DistanceRequest(), coal.DistanceResult()))


def floor_gap(body: Body, floor: float) -> float:
    """The lowest point of the solid above the floor (its own corners or rim)."""
    if body.kind == BOX:
        corners = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]) * body.half
        return float((corners @ body.rotation.T + body.center)[:, 2].min() - floor)
    axis = body.rotation[:, 2] if body.kind == CYLINDER else body.rotation[:, 0]
    half = body.half[2] if body.kind == CYLINDER else body.half[0]
    rim = body.radius * np.sqrt(max(0.0, 1 - axis[2] ** 2)) if body.kind == CYLINDER else body.radius
    return float(body.center[2] - abs(axis[2]) * half - rim - floor)


def world_solids(obstacles) -> list:
    """coal's shapes of every obstacle but the floor."""
    return [coal_solid(obstacle_body(obstacles, c)) for c in range(len(obstacles.kinds)) if obstacles.kinds[c] != FLOOR]


def place_feasible(oracle: Oracle, problem, rng: np.random.Generator) -> bool:
    """Whether, at each of three points (the ends and the middle) of the grasp's straight line and of
    the release's (their approaches, which the scene asks the tool to follow), some pose inside the
    limits puts the tool there, the object standing (along the grasp's) or carried at the offset the
    grasp goal implies (along the release's), with every link capsule ``solver.clearance`` from
    every obstacle and the floor and ``self_clearance`` from the object's solid (but the touch
    links), and the carried solid itself ``solver.clearance`` from every obstacle and the floor but
    the board, which it may touch, by coal (what armanim promises of every frame): a place the arm
    can only reach along lines it cannot follow, or with an object it cannot take, is not one it
    can make. The lines' other points are not searched: a label, not a proof."""
    from armanim.arm.rotations import rpy_rotation

    goals, at = problem.goals, indices(problem)
    down = rpy_rotation(np.radians([180, 0, 0]))

    def tool_at(k, up=0.0):
        return np.block([[down, (goal_point(goals[k]) + [0.0, 0.0, up])[:, None]], [np.zeros((1, 3)), np.ones((1, 1))]])

    column = goals[at["grasp"]].grasp
    body = obstacle_body(problem.obstacles, column)
    offset = np.linalg.inv(tool_at(at["grasp"])) @ body.matrix()
    others = with_bodies(problem.obstacles, {column: None})
    solids = world_solids(others)
    d_safe, self_safe = problem.solver.clearance, problem.self_pairs.clearance
    board = 0  # the shelf board, the scene's first obstacle: the solid may touch it there, never enter it
    touch = set(touch_links(problem, goals[at["grasp"]].touch_links))

    def free(tool: np.ndarray, held) -> bool:
        for q in oracle.ik(tool, rng):
            caps = [(link, coal_capsule(a, b, r), min(a[2], b[2]) - r) for link, a, b, r in oracle.link_capsules(q)]
            if (
                all(gap(c, s) >= d_safe for _, c, _ in caps for s in solids)
                and all(low - problem.obstacles.floor >= d_safe for link, _, low in caps if link not in STANDING)
                and all(gap(c, held) >= self_safe for link, c, _ in caps if link not in touch)
            ):
                return True
        return False

    standing = coal_solid(body)
    for up in (0.0, LINE / 2, LINE):
        if not free(tool_at(at["grasp"], up), standing):
            return False
        placed = body.moved(tool_at(at["release"], up) @ offset)
        carried = coal_solid(placed)
        if (
            any(gap(carried, s) < (-INSIDE if c == board else d_safe) for c, s in enumerate(solids))
            or floor_gap(placed, problem.obstacles.floor) < d_safe
            or not free(tool_at(at["release"], up), carried)
        ):
            return False
    return True


STANDING = {"panda_link0", "panda_link1", "base_link", "shoulder_link"}
"""The links on the base and those the first joint carries: they stand on the floor (the contract exempts them)."""


# ---- the measures -------------------------------------------------------------------------


def carried_violations(problem, timed) -> tuple[int, int, float, float, int]:
    """Frames where the carried solid (coal) is under clearance of an obstacle or the floor, or
    under self_clearance of a non-touch link capsule, but along the grasp's retreat and the
    release's approach (the benchmark's own goals, not armanim's worlds) the table or the board
    only under 0 (inside it); the frames held; the least gap seen elsewhere; the least gap to the
    table or board along those lines; the frames on them."""
    traj, carry = timed.trajectory, timed.carry
    problems = goal_problems(problem, carry)
    at = indices(problem)
    names = problem.obstacles.names
    lines = {at["retreat"]: "table", at["release"]: None}  # the board: the scene's first obstacle, unnamed
    bad, held, least, touching, along = 0, 0, np.inf, np.inf, 0
    tool = tool_poses(problem, traj.phi)
    a, b = capsule_ends(problem.capsules, forward(problem.arm, traj.phi))
    names = problem.capsules.names
    for f in range(traj.frames):
        world = carry.worlds[int(traj.goal[f])]
        if world.held is None:
            continue
        held += 1
        solid = world.held.body.moved(tool[f] @ world.held.offset)
        shape = coal_solid(solid)
        obstacles = problems[int(traj.goal[f])].obstacles
        columns = [c for c in range(len(obstacles.kinds)) if obstacles.kinds[c] != FLOOR]
        gaps = [gap(shape, s) for s in world_solids(obstacles)]
        k = int(traj.goal[f])
        support = None
        if k in lines:
            along += 1
            wanted = lines[k]
            support = next(
                i for i, c in enumerate(columns) if (obstacles.names[c] if obstacles.names else None) == wanted
            )
            touching = min(touching, gaps[support])
            if gaps[support] < -INSIDE:
                bad += 1
        d_obstacles = min([g for i, g in enumerate(gaps) if i != support] + [floor_gap(solid, problem.obstacles.floor)])
        d_links = min(
            (
                gap(shape, coal_capsule(a[f, i], b[f, i], float(problem.capsules.radius[i])))
                for i, name in enumerate(names)
                if name not in world.held.touch
            ),
            default=np.inf,
        )
        least = min(least, d_obstacles)
        if d_obstacles < problem.solver.clearance * (1 - 1e-9) or d_links < problem.self_pairs.clearance * (1 - 1e-9):
            bad += 1
    return bad, held, least, touching, along


def tool_poses(problem, phi: np.ndarray) -> np.ndarray:
    """armanim's tool transforms (F, 4, 4) (the run's own frames; the oracle's are pinocchio's)."""
    from armanim.motion.carry import tool_transform

    return tool_transform(problem, forward(problem.arm, phi))


def placed_error(oracle: Oracle, problem, timed) -> float:
    """The largest entry of the placed pose less pinocchio's release tool pose times the offset
    from its grasp tool pose (nan where the grasp or the release was missed)."""
    goals, traj, at = timed.goals, timed.trajectory, indices(problem)
    if not (goals[at["grasp"]].reached and goals[at["release"]].reached):
        return float("nan")
    grasp = oracle.tool_pose(traj.phi[goals[at["grasp"]].last_frame])
    release = oracle.tool_pose(traj.phi[goals[at["release"]].last_frame])
    column = problem.goals[at["grasp"]].grasp
    body = obstacle_body(problem.obstacles, column)
    expected = release @ np.linalg.inv(grasp) @ body.matrix()
    return float(np.abs(timed.carry.final.moved[column].matrix() - expected).max())


def planner_ratio(problem, solved, repeats: int = 3) -> tuple[float, float] | None:
    """CPU seconds of the planner from the lift pose to the place pose: in the carrying world, and
    with the object left out (min of ``repeats`` each, interleaved); None if the lift was missed."""
    from armanim.motion.planning import plan_motion

    goals, at = solved.goals, indices(problem)
    if not goals[at["lift"]].reached:
        return None
    start = solved.trajectory.phi[goals[at["lift"]].last_frame]
    carrying = goal_problems(problem, solved.carry)[at["over"]]
    empty = world_problem(problem, World(moved={problem.goals[at["grasp"]].grasp: None}))
    target, orientation = problem.goals[at["over"]].position, problem.goals[at["over"]].orientation
    times = {"with": [], "without": []}
    for _ in range(repeats):
        for name, p in (("with", carrying), ("without", empty)):
            t0 = time.process_time()
            plan_motion(p, start, target, seed=0, orientation=orientation)
            times[name].append(time.process_time() - t0)
    return min(times["with"]), min(times["without"])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--scenes", type=int, default=20)
    args = parser.parse_args()
    rng = np.random.default_rng(args.seed)
    rows, refused = [], 0
    started = time.process_time()
    for k in range(args.scenes):
        robot = "panda" if k % 2 == 0 else "ur5"
        while True:
            mapping = draw_scene(rng, robot, k)
            scene = scene_model(mapping)
            if not scene_problems(scene):
                break
            refused += 1
        problem = scene_to_problem(scene)
        oracle = Oracle(robot, scene)
        feasible = place_feasible(oracle, problem, np.random.default_rng(args.seed * 1000 + k))
        solved = solve_trajectory(problem)
        timed = retime(problem, solved, problem.fps)
        bad, held, least, touching, along = carried_violations(problem, timed)
        ratio = planner_ratio(problem, solved)
        release = timed.goals[indices(problem)["release"]]
        put = (
            release.reached and timed.carry.released(indices(problem)["release"]) is not None
        )  # reached, and the object put down
        rows.append(
            {
                "robot": robot,
                "feasible": feasible,
                "reached": put,
                "reason": release.reason
                if not release.reached
                else None
                if put
                else "nothing held (the grasp was missed)",
                "bad": bad,
                "held": held,
                "least": least,
                "touching": touching,
                "along": along,
                "placed": placed_error(oracle, problem, timed),
                "planner": ratio,
            }
        )
        r = rows[-1]
        print(
            f"{k:3d} {robot:5s} feasible={feasible!s:5s} place reached={r['reached']!s:5s} ({r['reason']}) "
            f"held frames {held:3d}, under clearance {bad}, least gap {least:.4f} (on the lines {touching:.1e}), "
            f"placed error {r['placed']:.1e}, "
            f"planner {'-' if ratio is None else f'{ratio[0] * 1e3:.1f} / {ratio[1] * 1e3:.1f} ms'}",
            flush=True,
        )
    feasible = [r for r in rows if r["feasible"]]
    reached = sum(r["reached"] for r in feasible)
    placed = np.array([r["placed"] for r in rows])
    ratios = [r["planner"][0] / r["planner"][1] for r in rows if r["planner"] is not None and r["planner"][1] > 0]
    total_with = sum(r["planner"][0] for r in rows if r["planner"] is not None)
    total_without = sum(r["planner"][1] for r in rows if r["planner"] is not None)
    print()
    print(
        f"scenes {len(rows)} ({refused} drawn again: refused by validation), CPU {time.process_time() - started:.0f} s"
    )
    print(
        f"frames with the carried solid under clearance or a non-touch link's self_clearance, or inside its table or "
        f"board along the lines (coal): {sum(r['bad'] for r in rows)} of {sum(r['held'] for r in rows)} held   (target 0)"
    )
    print(
        f"least distance of the solid to its table or board along the lines (coal): "
        f"{min(r['touching'] for r in rows):.1e} over {sum(r['along'] for r in rows)} frames   (target >= -1e-9: touching, never inside)"
    )
    print(
        f"placed pose against pinocchio's tool poses: worst {np.nanmax(placed):.1e}   (target <= 1e-9; "
        f"{int(np.isnan(placed).sum())} scenes missed the grasp or the release)"
    )
    print(
        f"feasible place goals reached: {reached} of {len(feasible)} = {100 * reached / max(1, len(feasible)):.0f} %   "
        f"(target >= 95 %; the oracle labels {len(rows) - len(feasible)} infeasible; reached among those: "
        f"{sum(r['reached'] for r in rows if not r['feasible'])})"
    )
    print(
        f"planner CPU with the object / without: median {np.median(ratios):.2f}x, worst {max(ratios):.2f}x, "
        f"total {total_with / total_without:.2f}x   (target <= 1.5x)"
    )


if __name__ == "__main__":
    main()
