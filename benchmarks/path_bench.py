"""Path goals against an independent oracle (issue 39).

    python benchmarks/path_bench.py [--paths 100] [--seed 0] [--quick] [--cases 3,84] [--rows FILE]

``--cases`` solves only the cases of those indices (every case before them is still drawn, so each
is the case of the full run); ``--rows`` appends every case's row to FILE as a JSON line.

Seeded random lines and arcs of 10-40 cm (:mod:`generators.paths`) on a bundled Panda and UR5
(alternately), the tool pointing down all along, among 0-4 spheres (drawn again until armanim's
checks accept the scene: the robot's home clear of every sphere). Each path is labelled by the
oracle (:mod:`oracles.paths`: a dense continuous inverse kinematics by pinocchio from twenty-four
starts, each followed by the least-norm step and by drifts through the null space that widen the
nearest gaps): feasible when it follows the whole path, else the share it follows. armanim solves each
as a scene with that one path goal (``solver.path_tolerance`` 1 mm, speed 10 cm/s) and is judged
on its own timed frames, by pinocchio's forward kinematics:

- feasible paths (the oracle with the scene's floors follows them whole): followed whole
  (fraction 1.0); target 100 %;
- the tool's greatest distance from the path at every frame along it and at every midpoint
  between two frames (each joint halfway): target <= 1 mm;
- joint speeds over the robot's limits (first differences over 1/fps): target 0;
- infeasible paths: the reported fraction within 0.02 of the oracle's with the floors armanim's
  filter keeps by design (``kept_clearance``, 1.1 x ``solver.clearance``, and
  ``kept_self_clearance``): a path open only between the scene's floor and the kept one is one
  armanim never takes, so the fraction it reports is judged against the oracle that keeps what it
  keeps. Beside it, the same count against the oracle with the scene's floors (``solver.clearance``,
  ``self_clearance``), reported, not the target.

Needs pinocchio (``pip install -e .[test]``).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))

from generators.families import armanim_rejects  # noqa: E402
from generators.paths import DrawnPath, draw_path  # noqa: E402
from oracles.paths import STEP, check_gaps, followed_fraction  # noqa: E402
from oracles.robots import robot_geometry  # noqa: E402

from armanim.arm.geometry import wrap_angle  # noqa: E402
from armanim.motion.filter.clearance import kept_clearance, kept_self_clearance  # noqa: E402
from armanim.motion.orientation import Orientation  # noqa: E402
from armanim.motion.problem import Goal, Problem  # noqa: E402
from armanim.motion.solution import Solution  # noqa: E402
from armanim.motion.timing.retime import retime  # noqa: E402
from armanim.motion.trajectory import solve_trajectory  # noqa: E402
from armanim.scene import scene_model, scene_to_problem  # noqa: E402

DOWN = np.array([0.0, 0.0, -1.0])
SPEED = 0.1
PATH_TOLERANCE = 0.001
SOLVER = {"tolerance": 0.005, "clearance": 0.02}


def case_scene(case: DrawnPath) -> dict:
    """The scene of a case (its one goal the path's start, for armanim's checks of the scene)."""
    obstacles = [
        {"center": c.tolist(), "radius": float(r), "influence": 0.05} for c, r in zip(case.centers, case.radii)
    ]
    return {
        "version": 1,
        "arm": {"robot": case.robot},
        "obstacles": obstacles,
        "goals": [case.path.start.tolist()],
        "solver": SOLVER,
    }


def drawn_case(rng: np.random.Generator, robot: str) -> DrawnPath:
    """A case whose scene armanim accepts (the robot's home pose clear of every sphere), drawn again until it does."""
    while True:
        case = draw_path(rng, robot)
        if not armanim_rejects(case_scene(case)):
            return case


def case_problem(case: DrawnPath) -> Problem:
    """armanim's problem of a case: the robot, the spheres, one path goal."""
    problem = scene_to_problem(scene_model(case_scene(case)))
    goal = Goal(case.path.start, 0.0, Orientation(axis=DOWN), case.path, SPEED)
    return replace(problem, goals=(goal,), solver=replace(problem.solver, path_tolerance=PATH_TOLERANCE))


def judged(problem: Problem, solution: Solution, geo) -> dict:
    """armanim's fraction, its worst distance from the path at frames and midpoints (pinocchio's
    FK against 0.05 mm samples of the path), and its frames over a joint's speed limit."""
    traj, report = solution.trajectory, solution.goals[0]
    frames = np.nonzero(traj.mode == "path")[0]
    worst = 0.0
    if len(frames):
        before = traj.phi[frames - 1]
        middle = before + wrap_angle(traj.phi[frames] - before) / 2
        dense = problem.goals[0].path.points(
            np.linspace(0, problem.goals[0].path.length, int(problem.goals[0].path.length / 5e-5) + 2)
        )
        for phi in (traj.phi[frames], middle):
            tips = geo.tip(phi)
            d = np.sqrt(((tips[:, None, :] - dense[None, :, :]) ** 2).sum(-1)).min(axis=1)
            worst = max(worst, float(d.max()))
    speeds = np.abs(wrap_angle(np.diff(traj.phi, axis=0))) * traj.fps
    over = int(np.sum(np.any(speeds > problem.rates.speed * (1 + 1e-6), axis=1)))
    return {
        "fraction": report.path.fraction,
        "worst": worst,
        "over": over,
        "cause": report.path.cause,
        "reason": report.reason,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--paths", type=int, default=100)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--quick", action="store_true", help="10 paths")
    parser.add_argument("--cases", help="only these case indices (comma-separated), drawn as in the full run")
    parser.add_argument("--rows", type=Path, help="write every case's row here (JSON lines)")
    args = parser.parse_args()
    count = 10 if args.quick else args.paths
    only = None if args.cases is None else {int(c) for c in args.cases.split(",")}
    if only is not None:
        count = max(count, max(only) + 1)
    rng = np.random.default_rng(args.seed)
    rows = []
    checked: dict[str, int] = {}  # robots whose numpy gaps were checked (and whether with spheres)
    for i in range(count):
        case = drawn_case(rng, ("panda", "ur5")[i % 2])
        if only is not None and i not in only:
            continue
        problem = case_problem(case)
        geo = robot_geometry(case.robot, case.centers, case.radii, clearance=problem.solver.clearance)
        if case.robot not in checked or (len(case.radii) and checked[case.robot] == 0):
            worst = check_gaps(geo, problem)
            assert worst < 1e-9, (
                f"{case.robot}: the oracle's numpy gaps differ from coal's / pinocchio's by {worst:.2e} m"
            )
            checked[case.robot] = len(case.radii)
        dense = case.path.points(np.linspace(0, case.path.length, int(case.path.length / STEP) + 2))
        oracle = followed_fraction(
            geo, dense, DOWN, problem.solver.max_joint_step, problem.solver.clearance, seed=i, problem=problem
        )
        kept = followed_fraction(
            geo,
            dense,
            DOWN,
            problem.solver.max_joint_step,
            kept_clearance(problem),
            seed=i,
            problem=problem,
            self_floor=kept_self_clearance(problem),
        )
        t0 = time.perf_counter()
        solution = retime(problem, solve_trajectory(problem), problem.fps)
        seconds = time.perf_counter() - t0
        row = {
            "i": i,
            "robot": case.robot,
            "kind": case.kind,
            "length": case.path.length,
            "spheres": len(case.radii),
            "oracle": oracle,
            "kept": kept,
            "seconds": seconds,
            **judged(problem, solution, geo),
        }
        rows.append(row)
        print(
            f"{i:3d} {case.robot:5s} {case.kind:4s} {case.path.length:.3f} m {len(case.radii)} spheres  oracle {oracle:.3f} "
            f"(kept floors {kept:.3f})  "
            f"armanim {row['fraction']:.3f} ({row['reason'] or 'whole'}{'/' + row['cause'] if row['cause'] else ''})  "
            f"worst {row['worst'] * 1e3:.3f} mm  over {row['over']}  {seconds:.2f} s",
            flush=True,
        )
        if args.rows is not None:
            with args.rows.open("a") as out:
                out.write(json.dumps(row) + "\n")
    report(rows)


def report(rows: list[dict]) -> None:
    """The benchmark's verdicts against its targets."""
    feasible = [r for r in rows if r["oracle"] == 1.0]
    infeasible = [r for r in rows if r["oracle"] < 1.0]
    whole = sum(r["fraction"] == 1.0 for r in feasible)
    close = sum(abs(r["fraction"] - r["oracle"]) <= 0.02 for r in infeasible)
    close_kept = sum(abs(r["fraction"] - r["kept"]) <= 0.02 for r in infeasible)
    worst = max(r["worst"] for r in rows)
    over = sum(r["over"] for r in rows)
    print()
    print(f"feasible paths followed whole: {whole}/{len(feasible)} (target 100 %)")
    print(f"greatest distance from the path at any frame or midpoint: {worst * 1e3:.3f} mm (target <= 1 mm)")
    print(f"frames over a joint's speed limit: {over} (target 0)")
    print(
        f"infeasible paths whose fraction is within 0.02 of the oracle's with the floors armanim's filter keeps "
        f"(1.1 x clearance, self_clearance + that margin): {close_kept}/{len(infeasible)} (target all)"
    )
    print(
        f"... of the oracle's with the scene's floors (clearance, self_clearance; not the target): {close}/{len(infeasible)}"
    )
    narrow = [r["i"] for r in feasible if r["kept"] < 1.0]
    if narrow:
        print(
            f"feasible paths the oracle with the kept floors does not follow whole (still judged as feasible): {narrow}"
        )
    for r in infeasible:
        if max(abs(r["fraction"] - r["oracle"]), abs(r["fraction"] - r["kept"])) > 0.02:
            print(
                f"  #{r['i']} {r['robot']} {r['kind']}: armanim {r['fraction']:.3f}, oracle {r['oracle']:.3f}, "
                f"kept floors {r['kept']:.3f} ({r['cause']})"
            )
    print(f"armanim's solve + clock per path: median {np.median([r['seconds'] for r in rows]):.2f} s")


if __name__ == "__main__":
    main()
