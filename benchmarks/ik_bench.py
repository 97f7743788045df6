"""Single-pose IK benchmark: armanim's four methods, robotics-toolbox ``ik_LM`` and ikpy, on
6-D pose targets (issue 21) or, with ``--position-only``, on the targets' positions alone (issue 20).

    python benchmarks/ik_bench.py [--targets 500] [--robots panda,ur5] [--methods pinv,dls,newton,gradient]
                                  [--quick] [--seed 0] [--no-references] [--position-only]
    python benchmarks/ik_bench.py --compare [--quick]     # issue 40's comparison (benchmarks/ik_compare.py)

N random reachable 6-D targets per robot (the tool frame of random poses drawn uniformly inside
the joint limits, so every target has a solution), solved cold from the robot's home pose, with
no obstacles. A solve succeeds when the returned angles are inside the limits and, by armanim's
forward kinematics, the tool is within 1e-4 m and 0.1 degree of the target.

- armanim: ``armanim.motion.ik.solve_pose(problem, p, home, orientation=R)``, what ``armanim ik
  --orientation`` does: its restarts from the planner's seeds and, when they fail, the planner's
  free-pose search (many damped least-squares solves of the stacked pose task at once);
- robotics-toolbox: ``Robot.ik_LM(T, q0=home, joint_limits=True)`` on the same URDF;
- ikpy: ``Chain.inverse_kinematics(p, R, orientation_mode="all", initial_position=home)`` on the
  same URDF.

The references are optional (install them into a separate venv: benchmarks/README.md); without
them their rows say why they are skipped. Before timing, the script checks that each reference's
forward kinematics equals armanim's on random poses. Times are wall-clock per solve on this
machine, printed for scale: compare rows of one run, not runs.
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path

import numpy as np

from armanim.arm.kinematics import forward, tool_rotation
from armanim.motion.filter.clearance import within_limits
from armanim.motion.ik import solve_pose
from armanim.motion.orientation import Orientation, orientation_angle
from armanim.scene import scene_model, scene_to_problem
from armanim.scene.robots import bundled_robot

POSITION_TOLERANCE = 1e-4  # metres
ANGLE_TOLERANCE_DEG = 0.1
MAX_ITERATIONS = 2000  # armanim ik's default --max-iterations
TARGET_SUCCESS = 0.995
LIMIT_MARGIN = 0.05  # radians: targets' poses are drawn this far inside the limits


def robot_problem(robot: str, method: str):
    """The bundled robot with armanim ik's settings at the benchmark's tolerances."""
    scene = scene_model(
        {
            "version": 1,
            "arm": {"robot": robot},
            "goals": [[0.3, 0.0, 0.4]],
            "solver": {
                "method": method,
                "tolerance": POSITION_TOLERANCE * 0.5,
                "orientation_tolerance": ANGLE_TOLERANCE_DEG * 0.5,
            },
        }
    )
    return scene_to_problem(scene)


def targets(problem, count: int, seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(count, n) source poses, (count, 3) tool positions and (count, 3, 3) tool rotations."""
    rng = np.random.default_rng(seed)
    lo = np.where(problem.limits.limited, problem.limits.lower + LIMIT_MARGIN, -np.pi)
    hi = np.where(problem.limits.limited, problem.limits.upper - LIMIT_MARGIN, np.pi)
    phi = rng.uniform(lo, hi, size=(count, problem.arm.n))
    pose = forward(problem.arm, phi)
    return phi, pose.tip, tool_rotation(problem.arm, pose)


def judged(problem, phi: np.ndarray, position: np.ndarray, rotation: np.ndarray | None) -> bool:
    """Success: inside the limits, the tool within 1e-4 m and (unless ``rotation`` is None: a
    position target) 0.1 degree, by armanim's FK."""
    phi = np.asarray(phi, dtype=float)
    if not np.all(np.isfinite(phi)) or not within_limits(problem, phi[None])[0]:
        return False
    pose = forward(problem.arm, phi)
    if rotation is None:
        return bool(np.linalg.norm(pose.tip - position) < POSITION_TOLERANCE)
    angle = orientation_angle(Orientation(rotation=rotation), tool_rotation(problem.arm, pose))
    return bool(np.linalg.norm(pose.tip - position) < POSITION_TOLERANCE and np.degrees(angle) < ANGLE_TOLERANCE_DEG)


# ----------------------------------------------------------------------------- references


def kinematic_urdf(path: Path) -> Path:
    """A copy of a URDF without its visual and collision elements (their package:// meshes stop
    robotics-toolbox's xacro step), in a temporary folder: the kinematics are the same."""
    import re
    import tempfile

    text = Path(path).read_text(encoding="utf-8")
    text = re.sub(r"<(visual|collision)\b.*?</\1>", "", text, flags=re.S)
    out = Path(tempfile.mkdtemp(prefix="ik_bench_")) / Path(path).name
    out.write_text(text, encoding="utf-8")
    return out


def urdf_path_elements(info) -> list[str]:
    """base link, joint, link, joint, ... tip link: the path ikpy is told to follow."""
    from armanim.scene.urdf import read_urdf

    elements = [info.base_link]
    for joint in read_urdf(Path(info.urdf)).path(info.base_link, info.tip_link):
        elements += [joint.name, joint.child]
    return elements


def rtb_solver(robot: str, problem):
    """robotics-toolbox's ik_LM on the bundled URDF, or the reason it is skipped."""
    try:
        import roboticstoolbox as rtb
        from spatialmath import SE3
    except ImportError as exc:
        return None, f"robotics-toolbox not installed ({exc.name}); see benchmarks/README.md"
    info = bundled_robot(robot)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            model = rtb.Robot.URDF(str(kinematic_urdf(info.urdf)))
    except Exception as exc:  # noqa: BLE001 (a reference that cannot load is skipped, with why)
        return None, f"robotics-toolbox cannot load {info.urdf.name}: {exc}"
    end, start = info.tip_link, info.base_link

    def fk(phi):
        return np.asarray(model.fkine(phi, end=end, start=start).A)

    def solve(position, rotation, q0):
        t = np.eye(4)
        t[:3, :3], t[:3, 3] = np.eye(3) if rotation is None else rotation, position
        mask = [1, 1, 1, 0, 0, 0] if rotation is None else [1, 1, 1, 1, 1, 1]  # a position target weighs no rotation
        sol = model.ik_LM(
            SE3(t, check=False),
            end=end,
            start=start,
            q0=q0,
            joint_limits=True,
            tol=1e-12,
            ilimit=100,
            slimit=100,
            mask=mask,
        )
        return np.asarray(sol[0], dtype=float)

    return (fk, solve), None


def ikpy_solver(robot: str, problem):
    """ikpy's inverse_kinematics (orientation_mode="all") on the bundled URDF, or the reason it is skipped."""
    try:
        from ikpy.chain import Chain
    except ImportError as exc:
        return None, f"ikpy not installed ({exc.name}); see benchmarks/README.md"
    info = bundled_robot(robot)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            chain = Chain.from_urdf_file(str(info.urdf), base_elements=urdf_path_elements(info), last_link_vector=None)
        except Exception as exc:  # noqa: BLE001
            return None, f"ikpy cannot load {info.urdf.name}: {exc}"
    names = [link.name for link in chain.links]
    moving = [i for i, link in enumerate(chain.links) if getattr(link, "joint_type", "fixed") != "fixed" and i > 0]
    mask = [i in moving for i in range(len(names))]
    chain.active_links_mask = np.array(mask)
    if len(moving) != problem.arm.n:
        return None, f"ikpy's chain has {len(moving)} moving joints, armanim's {problem.arm.n}"

    def full(phi):
        q = np.zeros(len(names))
        q[moving] = phi
        return q

    def fk(phi):
        return np.asarray(chain.forward_kinematics(full(phi)))

    def solve(position, rotation, q0):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            if rotation is None:
                q = chain.inverse_kinematics(position, initial_position=full(q0))
            else:
                q = chain.inverse_kinematics(position, rotation, orientation_mode="all", initial_position=full(q0))
        return np.asarray(q)[moving]

    return (fk, solve), None


def fk_agrees(fk, problem, seed: int) -> float:
    """Largest difference of a reference's tool transform from armanim's over random poses."""
    rng = np.random.default_rng(seed)
    worst = 0.0
    for phi in rng.uniform(-1.5, 1.5, size=(10, problem.arm.n)):
        pose = forward(problem.arm, phi)
        ours = np.eye(4)
        ours[:3, :3], ours[:3, 3] = tool_rotation(problem.arm, pose), pose.tip
        worst = max(worst, float(np.abs(fk(phi) - ours).max()))
    return worst


# ----------------------------------------------------------------------------- the run


def run_armanim(robot: str, method: str, goals) -> tuple[float, float, dict]:
    """Success rate, seconds per solve and how solves ended, of one armanim method."""
    problem = robot_problem(robot, method)
    ok, spent, finders = 0, 0.0, {"method": 0, "free_pose_search": 0, "failed": 0}
    for position, rotation in zip(*goals):
        start = time.perf_counter()
        orientation = None if rotation is None else Orientation(rotation=rotation)
        result = solve_pose(problem, position, problem.home, MAX_ITERATIONS, orientation=orientation)
        spent += time.perf_counter() - start
        good = judged(problem, result.phi, position, rotation)
        ok += good
        finders[result.found_by if good else "failed"] += 1
    return ok / len(goals[0]), spent / len(goals[0]), finders


def run_reference(solver, problem, goals) -> tuple[float, float]:
    fk, solve = solver
    ok, spent = 0, 0.0
    for position, rotation in zip(*goals):
        start = time.perf_counter()
        try:
            phi = solve(position, rotation, problem.home)
        except Exception:  # noqa: BLE001 (a solve that raises is a failure)
            phi = np.full(problem.arm.n, np.nan)
        spent += time.perf_counter() - start
        ok += judged(problem, phi, position, rotation)
    return ok / len(goals[0]), spent / len(goals[0])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--targets", type=int, default=500)
    parser.add_argument("--robots", default="panda,ur5")
    parser.add_argument("--methods", default="pinv,dls,newton,gradient")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--quick", action="store_true", help="20 targets per robot")
    parser.add_argument("--no-references", action="store_true", help="armanim's methods only")
    parser.add_argument("--position-only", action="store_true", help="the same targets' positions alone (3-D goals)")
    parser.add_argument(
        "--compare",
        action="store_true",
        help="issue 40's comparison: FK, 6-D Panda and notes' arm IK "
        "against rtb, pinocchio and ikpy, start-up (benchmarks/ik_compare.py; --quick: fewer targets)",
    )
    parser.add_argument(
        "--parts", default=None, help="with --compare: which parts, of fk,pose,self-free,position,startup (all)"
    )
    args = parser.parse_args()
    if args.compare:
        import ik_compare

        parts = tuple(args.parts.split(",")) if args.parts else ik_compare.PARTS
        ik_compare.main(args.quick, parts, args.targets if "--targets" in sys.argv else None)
        return
    count = 20 if args.quick else args.targets
    kind = "3-D position" if args.position_only else "6-D"
    judge = f"{POSITION_TOLERANCE:g} m" + ("" if args.position_only else f" and {ANGLE_TOLERANCE_DEG:g} deg")
    print(
        f"{count} random reachable {kind} targets per robot, cold start from home; success: "
        f"inside the limits, {judge} (armanim's FK)"
    )
    print(f"{'robot':6} {'solver':24} {'success':>9} {'ms/solve':>9}   notes")
    for robot in args.robots.split(","):
        base = robot_problem(robot, "pinv")
        _, positions, rotations = targets(base, count, args.seed)
        goals = (positions, [None] * count if args.position_only else rotations)
        for method in args.methods.split(","):
            rate, seconds, finders = run_armanim(robot, method, goals)
            verdict = "met" if rate >= TARGET_SUCCESS else "not met"
            print(
                f"{robot:6} {'armanim ' + method:24} {100 * rate:8.1f}% {1e3 * seconds:9.2f}   "
                f"target >= {100 * TARGET_SUCCESS:g} %: {verdict}; by the method {finders['method']}, "
                f"free-pose search {finders['free_pose_search']}, failed {finders['failed']}"
            )
        if args.no_references:
            continue
        ikpy_name = "ikpy (position)" if args.position_only else "ikpy (orientation all)"
        for name, make in (("robotics-toolbox ik_LM", rtb_solver), (ikpy_name, ikpy_solver)):
            solver, why = make(robot, base)
            if solver is None:
                print(f"{robot:6} {name:24} {'skipped':>9}   {why}")
                continue
            gap = fk_agrees(solver[0], base, args.seed)
            if gap > 1e-9:
                print(
                    f"{robot:6} {name:24} {'skipped':>9}   its forward kinematics differs from armanim's by {gap:.3g}"
                )
                continue
            rate, seconds = run_reference(solver, base, goals)
            print(f"{robot:6} {name:24} {100 * rate:8.1f}% {1e3 * seconds:9.2f}")


if __name__ == "__main__":
    main()
