"""Issue 34's benchmark: the clock on every bundled scene and on the motion benchmark's robot
families (seeded random scenes no one tuned for).

For each scene: solve (the path), retime (the clock), then measure

- the peak finite-difference speed and acceleration ratios of every frame against the limits
  the run used (target: <= 1.0 everywhere);
- each goal's duration against toppra's time-optimal one on the same path (toppra 0.6, 4000
  grid points; target: <= 1.05x in total);
- the clock's time against the solve's (target: under 5 %), in a process where the clock has
  run once: loading its compiled passes (numba's cached machine code) is a cost paid once per
  process, like an import, and is printed on its own.

Run: ``python benchmarks/timing_bench.py [--seed 0] [--scenes 6] [--fps 30]`` (needs the test
extra: toppra is the oracle).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path[:0] = [str(ROOT / "benchmarks"), str(ROOT / "tests")]  # the toppra oracle is the tests' own (one owner)

from toppra_oracle import toppra_trajectory  # noqa: E402

from armanim.arm.geometry import wrap_angle  # noqa: E402
from armanim.motion.timing.jointpath import joint_path  # noqa: E402
from armanim.motion.timing.retime import retime  # noqa: E402
from armanim.motion.trajectory import hold_frames, solve_trajectory  # noqa: E402
from armanim.scene import load_scene, scene_model, scene_to_problem  # noqa: E402


def toppra_duration(path, speed: np.ndarray, acceleration: np.ndarray) -> float:
    """toppra's time-optimal duration along ``path`` (the clock's own geometry): the tests' oracle
    (:func:`toppra_oracle.toppra_trajectory`), on 4000 grid points."""
    return float(toppra_trajectory(path, speed, acceleration, gridpoints=4000).duration)


def measure(name: str, problem, fps: float) -> dict:
    """One scene's figures."""
    t0 = time.process_time()
    solved = solve_trajectory(problem)
    t1 = time.process_time()
    timed = retime(problem, solved, fps)
    t2 = time.process_time()
    phi = timed.trajectory.phi
    steps = wrap_angle(np.diff(phi, axis=0))
    rates = problem.rates
    speed = float((np.abs(steps) * fps / rates.speed).max(initial=0.0))
    accel = float((np.abs(np.diff(steps, axis=0)) * fps**2 / rates.acceleration).max(initial=0.0))
    ours = optimum = 0.0
    start = 0
    for g, report in zip(timed.goals, solved.goals):
        poses = solved.trajectory.phi[start : start + report.frames + 1]
        path = joint_path(poses, problem.limits.limited)
        if path.length > 0:
            ours += g.timing.duration
            optimum += toppra_duration(path, rates.speed, rates.acceleration)
        start += report.frames + (hold_frames(problem, problem.goals[report.index]) if report.reached else 0)
    return {
        "name": name,
        "goals": len(timed.goals),
        "frames": timed.trajectory.frames,
        "speed": speed,
        "accel": accel,
        "ours": ours,
        "optimum": optimum,
        "solve": t1 - t0,
        "clock": t2 - t1,
    }


def bundled(fps: float) -> list[dict]:
    """Every bundled scene."""
    return [
        measure(p.stem, scene_to_problem(load_scene(p).model), fps) for p in sorted((ROOT / "scenes").glob("*.yaml"))
    ]


def families(seed: int, count: int, fps: float) -> list[dict]:
    """The motion benchmark's robot and robot-shapes families, ``count`` scenes each."""
    from generators.families import make_scene, scene_name

    rows = []
    for family in ("robots", "robot-shapes"):
        for index in range(count):
            draft = make_scene(seed, index, family)
            name = scene_name(seed, index)
            problem = scene_to_problem(scene_model(draft.as_scene_dict(name)))
            rows.append(measure(f"{family}/{index}", problem, fps))
    return rows


def report(rows: list[dict]) -> None:
    print(f"{'scene':<22} {'goals':>5} {'frames':>6} {'speed':>6} {'accel':>6} {'x optimum':>9} {'clock/solve':>11}")
    for r in rows:
        ratio = r["ours"] / r["optimum"] if r["optimum"] else float("nan")
        print(
            f"{r['name']:<22} {r['goals']:>5} {r['frames']:>6} {r['speed']:>6.3f} {r['accel']:>6.3f} {ratio:>9.3f} "
            f"{100 * r['clock'] / r['solve']:>10.1f}%"
        )
    ours, optimum = sum(r["ours"] for r in rows), sum(r["optimum"] for r in rows)
    print(
        f"peak speed ratio {max(r['speed'] for r in rows):.4f}, peak acceleration ratio "
        f"{max(r['accel'] for r in rows):.4f}, duration {ours / optimum:.4f}x toppra's optimum, clock "
        f"{100 * sum(r['clock'] for r in rows) / sum(r['solve'] for r in rows):.1f} % of the solve"
    )


def warm_up(fps: float) -> float:
    """Run the clock once on the smallest bundled scene; seconds its first run took beyond its
    second (loading the compiled passes)."""
    problem = scene_to_problem(load_scene(ROOT / "scenes" / "singular-start.yaml").model)
    solved = solve_trajectory(problem)
    times = []
    for _ in range(2):
        t0 = time.process_time()
        retime(problem, solved, fps)
        times.append(time.process_time() - t0)
    return times[0] - times[1]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--scenes", type=int, default=6, help="scenes per robot family (0: the bundled scenes only)")
    parser.add_argument("--fps", type=float, default=30.0)
    args = parser.parse_args()
    print(f"loading the clock's compiled passes: {1000 * warm_up(args.fps):.0f} ms once per process")
    rows = bundled(args.fps)
    if args.scenes:
        rows += families(args.seed, args.scenes, args.fps)
    report(rows)


if __name__ == "__main__":
    main()
