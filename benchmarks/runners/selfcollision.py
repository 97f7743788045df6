"""The self-collision family's run (issue 35): every method with self_collision auto and off,
every frame's enabled pairs measured by coal, and the bundled scenes' cost per frame.
"""

from __future__ import annotations

import sys
from collections import Counter, defaultdict
from dataclasses import replace
from pathlib import Path

import numpy as np
from generators.selfcollision import SELF_ROBOTS, SELF_STREAM, chain_urdf_text, draw_self_goals, self_scene_problem
from oracles.robots import coal_pair_gaps

from armanim.arm.kinematics import forward
from armanim.scene.convert import scene_to_problem
from runners.motion import ROUNDING, timed_solve
from runners.report import print_table


def self_breaks(problem, trajectory, gaps: np.ndarray) -> list[str]:
    """The invariants a self-collision run breaks: NaN, a joint on or past its limit, a joint turning more
    than max_joint_step, an enabled pair under self_clearance (coal)."""
    phi = trajectory.phi
    if not np.all(np.isfinite(phi)):
        return ["NaN in phi"]
    breaks = []
    lim = problem.limits
    if np.any((phi <= lim.lower) | (phi >= lim.upper)):
        breaks.append("a joint on or past its limit")
    if (
        len(phi) > 1
        and np.abs(np.mod(np.diff(phi, axis=0) + np.pi, 2 * np.pi) - np.pi).max()
        > problem.solver.max_joint_step + ROUNDING
    ):
        breaks.append("a joint turned more than max_joint_step")
    if gaps.min() < problem.self_pairs.clearance - ROUNDING:
        breaks.append(f"an enabled pair {gaps.min():.3g} apart (self_clearance {problem.self_pairs.clearance:g})")
    return breaks


def self_family(args) -> int:
    """``--family self``: per robot and method, goals reached (of the oracle-feasible ones), frames with
    an enabled pair under self_clearance and invariants broken, with self_collision auto and off, and
    the CPU time per frame of each (the best of ``--timing-rounds``, the two modes solved in turn)."""
    import tempfile

    from armanim.world.selfdistances import SelfPairs

    rows: dict = defaultdict(lambda: Counter())
    broken = 0
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        (folder / "chain.urdf").write_text(chain_urdf_text())
        for k in range(args.scenes):
            robot = SELF_ROBOTS[k % len(SELF_ROBOTS)]
            rng = np.random.default_rng([args.seed, k, SELF_STREAM])
            base = self_scene_problem(robot, folder, [[0.4, 0.0, 0.4]])
            poses, tried = draw_self_goals(base, rng)
            if not poses:
                print(f"scene {k} ({robot}): no goal crossing the body in {tried} draws", file=sys.stderr)
                continue
            tips = forward(base.arm, np.array(poses)).tip
            problem = self_scene_problem(robot, folder, [[float(v) for v in t] for t in tips])
            for method in args.methods:
                on = replace(problem, solver=replace(problem.solver, method=method))
                modes = (("auto", on), ("off", replace(on, self_pairs=SelfPairs.none())))
                best = {"auto": np.inf, "off": np.inf}
                for _ in range(
                    args.timing_rounds - 1
                ):  # --timing-rounds: the two modes in turn, the best CPU time of each
                    for mode, prob in modes:
                        best[mode] = min(best[mode], timed_solve(prob)[3])
                for mode, prob in modes:
                    solution, _, _, cpu = timed_solve(prob)
                    cpu = min(cpu, best[mode])
                    gaps = coal_pair_gaps(problem, solution.trajectory.phi)
                    row = rows[(robot, method, mode)]
                    row["goals"] += len(poses)
                    row["reached"] += solution.reached
                    row["frames"] += solution.trajectory.frames
                    row["under"] += int((gaps < problem.self_pairs.clearance - ROUNDING).sum())
                    row["cpu_us"] += int(cpu * 1e6)
                    if mode == "auto":
                        found = self_breaks(problem, solution.trajectory, gaps)
                        row["breaks"] += len(found)
                        broken += len(found)
            print(
                f"[{k + 1}/{args.scenes}] scene {k} ({robot}, {len(poses)} goals crossing the body, {tried} draws)",
                file=sys.stderr,
                flush=True,
            )
    print(
        f"motion_bench --family self --seed {args.seed} --scenes {args.scenes} --methods {','.join(args.methods)} --planner auto"
    )
    header = [
        "robot",
        "method",
        "reached (auto)",
        "frames under (auto)",
        "broken",
        "ms/frame (auto)",
        "reached (off)",
        "frames under (off)",
        "ms/frame (off)",
        "time ratio",
    ]
    table = []
    for robot in SELF_ROBOTS:
        for method in args.methods:
            a, o = rows.get((robot, method, "auto")), rows.get((robot, method, "off"))
            if not a:
                continue
            ms_a, ms_o = a["cpu_us"] / 1e3 / a["frames"], o["cpu_us"] / 1e3 / o["frames"]
            table.append(
                [
                    robot,
                    method,
                    f"{a['reached']}/{a['goals']}",
                    f"{a['under']}/{a['frames']}",
                    str(a["breaks"]),
                    f"{ms_a:.2f}",
                    f"{o['reached']}/{o['goals']}",
                    f"{o['under']}/{o['frames']}",
                    f"{ms_o:.2f}",
                    f"{ms_a / ms_o:.2f}",
                ]
            )
    print_table(header, table)
    print("\nframe cost of the enabled pairs on the bundled scenes (CPU ms per frame, best of 3; issue 35's bar: 1.5x)")
    print_table(["scene", "enabled pairs", "ms/frame (auto)", "ms/frame (off)", "ratio"], bundled_frame_costs())
    if broken:
        print(f"{broken} invariant(s) broken", file=sys.stderr)
    return 1 if broken else 0


BUNDLED_SCENES = (
    "panda-place",
    "panda-clutter",
    "panda-shelf",
    "ur5-table",
    "ur5-pen",
    "ur5-around",
    "iiwa-redundancy",
)


def bundled_frame_costs(rounds: int = 3) -> list[list[str]]:
    """CPU time per frame of each bundled robot scene with ``self_collision`` auto and off."""
    from armanim.scene.loader import load_scene
    from armanim.world.selfdistances import SelfPairs

    rows = []
    for name in BUNDLED_SCENES:
        problem = scene_to_problem(load_scene(Path(__file__).resolve().parents[2] / "scenes" / f"{name}.yaml").model)
        best = {}
        for mode, prob in (("auto", problem), ("off", replace(problem, self_pairs=SelfPairs.none()))) * rounds:
            solution, _, _, cpu = timed_solve(prob)
            best[mode] = min(best.get(mode, np.inf), cpu / solution.trajectory.frames)
        rows.append(
            [
                name,
                str(len(set(problem.self_pairs.names))),
                f"{best['auto'] * 1e3:.2f}",
                f"{best['off'] * 1e3:.2f}",
                f"{best['auto'] / best['off']:.2f}",
            ]
        )
    return rows
