"""Issue 53's benchmark: goals passed without stopping (``blend``) against the same runs at rest.

40 seeded random multi-goal scenes (4-8 goals): half random arms of links among spheres (the
motion benchmark's ``standard`` family), half the bundled robots among spheres (``robots``),
each drawn until it has at least 4 goals (more than 8 are cut to 8; holds dropped). Each scene is
solved once (``blend`` changes when the arm moves, not where: the solve is the same) and put on
the clock twice, at rest and with ``solver.blend`` of 5 % of the arm's reach, at the scene's fps.

Per scene: the total duration with blends over the duration at rest (target: median <= 0.8x,
never above 1), and on the blended frames, measured again here:

- frames over any rate limit (finite differences over 1/fps of speed, acceleration and, where
  set, jerk; target 0);
- via goals not passed within their radius by forward kinematics (target 0);
- frames under the clearance (every link's, numpy's clearances; target 0: at least
  ``min(solver.clearance, home's)``, as the invariants) or the self-clearance;
- goals reached differently from the run at rest (target 0).

Where the time goes: each goal's own path is also shortened and smoothed alone and timed at rest
(the motion's ``shortened``): the share of the gain that the path's shape gives, the rest is
passing the goals without stopping. Times are CPU seconds of this process.

Run: ``python benchmarks/blend_bench.py [--seed 0] [--scenes 40] [--radius 0.05]``.
"""

from __future__ import annotations

import argparse
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "benchmarks"))

from armanim.arm.geometry import wrap_angle  # noqa: E402
from armanim.arm.kinematics import forward  # noqa: E402
from armanim.motion.timing.blend import judged_radius  # noqa: E402
from armanim.motion.timing.retime import retime  # noqa: E402
from armanim.motion.trajectory import solve_trajectory  # noqa: E402
from armanim.scene import scene_model, scene_to_problem  # noqa: E402
from armanim.world.distances import clearances  # noqa: E402
from armanim.world.selfdistances import self_gaps  # noqa: E402

RATE_TOLERANCE = 1e-6


def drafts(seed: int, count: int) -> list[tuple[str, dict]]:
    """``count`` scene mappings with 4-8 goals, half of each family, holds dropped."""
    from generators.families import make_scene, scene_name

    out = []
    for family in ("standard", "robots"):
        index, made = 0, 0
        while made < count // 2 + (count % 2 if family == "standard" else 0):
            draft = make_scene(seed, index, family)
            index += 1
            if len(draft.goals) < 4:
                continue
            scene = draft.as_scene_dict(scene_name(seed, index), method="dls")
            scene["goals"] = [
                g if isinstance(g, list) else {k: v for k, v in g.items() if k != "hold"} for g in scene["goals"]
            ][:8]
            out.append((f"{family}/{index - 1}", scene))
            made += 1
    return out


def rate_excess(problem, traj) -> int:
    """Frames over any rate limit (first, second and, with a jerk limit, third differences)."""
    steps = wrap_angle(np.diff(traj.phi, axis=0))
    over = np.abs(steps) * traj.fps > problem.rates.speed * (1 + RATE_TOLERANCE)
    count = int(over.any(axis=1).sum())
    accel = np.abs(np.diff(steps, axis=0)) * traj.fps**2 > problem.rates.acceleration * (1 + RATE_TOLERANCE)
    count += int(accel.any(axis=1).sum())
    if problem.rates.jerk is not None:
        jerk = np.abs(np.diff(steps, 2, axis=0)) * traj.fps**3 > problem.rates.jerk * (1 + RATE_TOLERANCE)
        count += int(jerk.any(axis=1).sum())
    return count


def vias_missed(problem, solution) -> tuple[int, int]:
    """(via goals, of those not passed within their radius by FK of their last frame)."""
    traj = solution.trajectory
    vias = missed = 0
    for report in solution.goals:
        if report.blend is None or not report.blend.blended:
            continue
        vias += 1
        goal = problem.goals[report.index]
        phi = traj.phi[report.last_frame]
        if goal.joints is not None:
            near = float(np.abs(wrap_angle(phi - goal.joints)).max())
        else:
            near = float(np.linalg.norm(forward(problem.arm, phi).tip - goal.position))
        missed += near > judged_radius(problem, goal) * (1 + 1e-9)
    return vias, missed


def under_clearance(problem, traj) -> int:
    """Frames with a link under ``min(solver.clearance, home's)`` or a pair under the self-clearance."""
    pose = forward(problem.arm, traj.phi)
    count = 0
    if len(problem.obstacles):
        links = clearances(pose, problem.obstacles, problem.capsules).links.min(axis=(-1, -2))
        count += int(np.sum(links < min(problem.solver.clearance, links[0]) - 1e-9))
    if len(problem.self_pairs):
        gaps = self_gaps(pose, problem.capsules, problem.self_pairs).d.min(axis=1)
        count += int(np.sum(gaps < min(problem.self_pairs.clearance, gaps[0]) - 1e-9))
    return count


def shortened_at_rest(problem, solution) -> float:
    """Seconds of the run at rest with each goal's path shortened and smoothed alone (no via: its
    ends kept), as a blended part's is: the share of the gain the path's shape gives."""
    from armanim.motion.timing.goalmotion import goal_motions
    from armanim.motion.timing.retime import (  # the clock's own steps, one goal at a time
        _parts,
        _shaped_part,
        path_safety,
    )

    src, rates = solution.trajectory, problem.rates
    safety = path_safety(problem, src)
    frames = 1
    for part in _parts(problem, solution, problem):
        if part.path_speed is not None:  # along a path goal's path: as solved
            poses, shaped_safety = (
                src.phi[part.frames],
                replace(
                    safety,
                    at_poses=safety.at_poses[part.frames],
                    certified=safety.certified[part.frames.start : part.frames.stop - 1],
                ),
            )
        else:
            shaped = _shaped_part(problem, src, safety, part)[0]
            poses, shaped_safety = shaped.poses, replace(safety, at_poses=shaped.clearance, certified=shaped.certified)
        motion = goal_motions(
            [poses],
            problem.limits.limited,
            rates.speed,
            rates.acceleration,
            problem.fps,
            [shaped_safety],
            jerk=rates.jerk,
            path_speeds=[part.path_speed],
        )[0]
        frames += len(motion.phi) + part.hold
    return frames / problem.fps


def measure(name: str, scene: dict, radius: float) -> dict:
    problem = scene_to_problem(scene_model(scene))
    t0 = time.process_time()
    solved = solve_trajectory(problem)
    solve_s = time.process_time() - t0
    rest = retime(problem, solved, problem.fps)
    r = radius * problem.arm.reach
    blended_problem = replace(
        problem, goals=tuple(replace(g, blend=r if g.joints is None else np.radians(5.0)) for g in problem.goals)
    )
    t0 = time.process_time()
    flow = retime(blended_problem, solved, problem.fps)
    clock_s = time.process_time() - t0
    shortened = shortened_at_rest(problem, solved)
    vias, missed = vias_missed(blended_problem, flow)
    return {
        "name": name,
        "goals": len(problem.goals),
        "rest": rest.trajectory.frames / problem.fps,
        "flow": flow.trajectory.frames / problem.fps,
        "rest_to_rest": flow.rest_to_rest_duration,
        "shortened": shortened,
        "vias": vias,
        "candidates": sum(1 for g in flow.goals if g.blend is not None and g.blend.reason not in ("last",)),
        "curves": sum(1 for g in flow.goals if g.blend is not None and g.blend.corner == "curve"),
        "over_rate": rate_excess(blended_problem, flow.trajectory),
        "missed_radius": missed,
        "under_clearance": under_clearance(blended_problem, flow.trajectory),
        "reached_differ": sum(a.reached != b.reached for a, b in zip(rest.goals, flow.goals)),
        "solve_s": solve_s,
        "clock_s": clock_s,
        "reasons": [g.blend.reason for g in flow.goals if g.blend is not None and not g.blend.blended],
    }


def report(rows: list[dict]) -> None:
    print(
        f"{'scene':<14} {'goals':>5} {'rest s':>7} {'short s':>7} {'blend s':>7} {'ratio':>6} {'vias':>9} {'curves':>6} {'rate':>4} "
        f"{'radius':>6} {'clear':>5} {'reach':>5}"
    )
    for r in rows:
        print(
            f"{r['name']:<14} {r['goals']:>5} {r['rest']:>7.2f} {r['shortened']:>7.2f} {r['flow']:>7.2f} {r['flow'] / r['rest']:>6.3f} "
            f"{r['vias']:>4}/{r['candidates']:<4} {r['curves']:>6} {r['over_rate']:>4} {r['missed_radius']:>6} "
            f"{r['under_clearance']:>5} {r['reached_differ']:>5}"
        )
    ratios = np.array([r["flow"] / r["rest"] for r in rows])
    print(
        f"\n{len(rows)} scenes: duration with blends / at rest: median {np.median(ratios):.3f}x "
        f"(target <= 0.8x), best {ratios.min():.3f}x, worst {ratios.max():.3f}x (target <= 1); "
        f"vias {sum(r['vias'] for r in rows)} of {sum(r['candidates'] for r in rows)} goals that could flow "
        f"({sum(r['curves'] for r in rows)} on a curve)"
    )
    short = np.array([r["shortened"] / r["rest"] for r in rows])
    print(
        f"where it goes: each goal's path shortened and smoothed alone, at rest: median {np.median(short):.3f}x; "
        f"passing the goals on that path: median {np.median(ratios / short):.3f}x of it"
    )
    print(
        f"frames over a rate limit {sum(r['over_rate'] for r in rows)}, vias outside their radius "
        f"{sum(r['missed_radius'] for r in rows)}, frames under the clearance {sum(r['under_clearance'] for r in rows)}, "
        f"goals reached differently {sum(r['reached_differ'] for r in rows)} (targets 0)"
    )
    from collections import Counter

    reasons = Counter(reason for r in rows for reason in r["reasons"])
    print("goals at rest, by reason: " + ", ".join(f"{k} {v}" for k, v in sorted(reasons.items())))
    print(
        f"rest_to_rest_duration_s equals the run at rest in {sum(abs(r['rest_to_rest'] - r['rest']) < 1e-9 for r in rows)}"
        f" of {len(rows)}; the blended clock took {sum(r['clock_s'] for r in rows):.1f} s of CPU, the solves "
        f"{sum(r['solve_s'] for r in rows):.1f} s"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--scenes", type=int, default=40)
    parser.add_argument("--radius", type=float, default=0.05, help="blend radius as a fraction of the arm's reach")
    args = parser.parse_args()
    rows = []
    for name, scene in drafts(args.seed, args.scenes):
        rows.append(measure(name, scene, args.radius))
        r = rows[-1]
        print(f"{name}: {r['rest']:.2f} s at rest, {r['flow']:.2f} s blended", file=sys.stderr, flush=True)
    report(rows)


if __name__ == "__main__":
    main()
