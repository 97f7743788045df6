"""Motion benchmark for armanim (issue 11, item 6): does the arm reach every goal it can?

    python benchmarks/motion_bench.py                     # 40 scenes, every method, planner auto and off
    python benchmarks/motion_bench.py --quick             # 8 scenes, for development
    python benchmarks/motion_bench.py --scenes 100 --seed 3 --jobs 2
    python benchmarks/motion_bench.py --methods pinv,dls --planner off
    python benchmarks/motion_bench.py --list-misses       # one line per feasible goal that was missed
    python benchmarks/motion_bench.py --dump-scene 7 /tmp/scenes   # scene 7 as YAML, for `armanim run`
    python benchmarks/motion_bench.py --family hard --scenes 24 --planner auto   # the hard family
    python benchmarks/motion_bench.py --family robots --scenes 12 --planner auto   # Panda, UR5, iiwa (issue 20)
    python benchmarks/motion_bench.py --family poses --scenes 12 --planner auto    # their goals with orientations (issue 21)
    python benchmarks/motion_bench.py --family self --scenes 12                    # goals across the body (issue 35)

Scenes. A seeded generator (numpy ``Generator`` from ``--seed`` and the scene's index, so
scene K is the same whatever ``--scenes`` is) draws random cluttered scenes: arms of 3-7
links (the course notes' arm: axes z, y, y, ..., links along z; planar or planar-ish arms:
axes z, links along x; arms with mixed axes), random link lengths and width, limits on
about half the joints (home strictly inside them), 2-8 spheres (some across the straight
line between consecutive goals, some next to the arm, some anywhere), and 3-6 goals that
are the tips of random poses inside the limits and clear of the spheres, plus now and then
a goal out of reach. Every scene is validated by armanim itself (``SceneModel`` and
``scene_problems``); a scene that fails is redrawn. Each scene is solved with every
method, with ``solver.planner`` ``auto`` and ``off`` when armanim has that field.

Oracle. Each goal is labelled feasible or not WITHOUT armanim's solvers: a forward
kinematics written here (the contract's chain, checked against
``armanim.arm.kinematics.forward`` at start), then a multi-start search
(``scipy.optimize.least_squares`` with the joint limits as bounds, deterministic starts)
for a pose whose tip is within tolerance/2 of the goal, with every joint inside its
limits and every link capsule (radius width/2) at least ``clearance`` from every sphere's
surface (``clearance`` = the scene's ``solver.clearance`` when armanim has that field,
else 0.05). The oracle says nothing about whether a path to that pose exists: a planar
arm can have goal poses that are clear but cut off from it by a sphere in its plane.

Robot family (``--family robots``, issue 20). One bundled robot per scene, chosen by the
scene's rng: Franka Panda, UR5 or KUKA LBR iiwa (``arm: {robot: ...}``, metres), at its
home pose, among 3-10 spheres (radius 0.03-0.1 m, influence 0.1 m), with 3-5 goals that are
the tool points of random poses inside the URDF limits (10 degrees in, within +-180, tool
0.1 m above the base) and ``solver`` tolerance 0.005, clearance 0.02, max_step 0.02 as the
bundled robot scenes. Its oracle's kinematics is pinocchio's (``pin.buildModelFromUrdf`` of
the bundled URDF, reduced to the chain's joints; ``forwardKinematics`` and
``updateFramePlacements`` give the tool point and every link frame), and its clearances are
armanim's capsule *data* (link, two points in the link frame, radius) placed by pinocchio's
frames; a start-up self-test checks both against armanim's FK and clearances (1e-9) on random
poses. The same multi-start bounded least-squares search as above labels every goal, with
pinocchio's tool point and these clearances in its residual (no reach shortcut: a robot's
reach here is only sampled). Every drawn goal is the tool point of a clear pose, so all are
feasible by construction, the search is checked against the generator's poses ("generator
poses the oracle failed to match") and "reached infeasible" has nothing to count. Like the
other families' oracle, it says nothing about whether a path exists, nor about
self-collision or a floor (armanim checks neither).

Self-collision family (``--family self``, issue 35). Panda, UR5, iiwa and a 6-joint URDF chain of
the benchmark's own (cylinders whose axes alternate z, y: it folds onto itself), one per scene in turn,
no obstacles, the bundled robot scenes' solver settings (self_clearance = clearance / 2 = 0.01 m),
``self_collision: auto``. Three goals per scene: tool points of random poses inside the limits
(10 degrees in) whose straight line from the previous tool point (home's first) passes within
0.15 m of the base's vertical axis, through the body, each pose free (every enabled pair at least
self_clearance + 0.2 x clearance apart, by coal; the tool 0.1 m above the base): feasible by
construction (no path claimed). Every method runs with ``self_collision`` auto and off (planner
auto); coal measures every frame's enabled pairs (capsules placed by armanim's forward kinematics,
which tests/arm/test_urdf.py checks against pinocchio). Reported per robot and method: goals reached,
frames with an enabled pair under self_clearance, invariants broken (NaN, a limit, max_joint_step,
a pair under self_clearance), CPU ms per frame of each and their ratio.

Report. Per method and planner setting: feasible goals reached, goals reached that the
oracle called infeasible (an oracle bug if not 0), the share of frames within 1e-3 of an
obstacle surface, time per frame and per planned goal, and broken invariants (NaN, a
limited joint on or past its limit, clearance below the setting, a joint turning more
than ``max_joint_step`` in one frame). The exit code is 1 when an invariant is broken,
else 0. Nothing here asserts on times. See benchmarks/README.md.
"""

from __future__ import annotations

import argparse
import multiprocessing
import sys
import time
from pathlib import Path

import numpy as np
import yaml
from generators.families import FAMILIES, SHAPE_FAMILIES, make_scene, scene_name
from runners.motion import METHODS, SceneResult, bench_scene, label_scene, oracle_geometry, planner_field_exists
from runners.report import print_report
from runners.selfcollision import self_family
from runners.selftests import self_test_geometry, self_test_robots, self_test_solids


def dump_scene(seed: int, index: int, folder: Path, methods: list, planners: list, family: str = "standard") -> None:
    """Write scene ``index`` as YAML, one file per method (and planner setting when armanim has it)."""
    folder.mkdir(parents=True, exist_ok=True)
    draft = make_scene(seed, index, family)
    geo = oracle_geometry(draft, seed, index)
    verdicts, _ = label_scene(draft, geo, seed, index)
    for method in methods:
        for planner in planners if planner_field_exists() else [None]:
            name = scene_name(seed, index, method, planner)
            text = (
                f"# motion_bench.py --seed {seed}, scene {index} ({draft.kind} arm); oracle: "
                + ", ".join(f"goals[{k}] {v.why}" for k, v in enumerate(verdicts))
                + "\n"
            )
            text += yaml.safe_dump(draft.as_scene_dict(name, method, planner), sort_keys=False, default_flow_style=None)
            path = folder / f"{name}.yaml"
            path.write_text(text)
            print(f"wrote {path}   (armanim run {path})")


def parse_args(argv=None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(
        description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--scenes", type=int, default=40, help="number of random scenes (default 40)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the scene generator (default 0)")
    parser.add_argument("--methods", default=",".join(METHODS), help="comma-separated methods (default all four)")
    parser.add_argument("--planner", default="auto,off", help="comma-separated planner settings (default auto,off)")
    parser.add_argument("--jobs", type=int, default=1, help="processes over scenes (default 1)")
    parser.add_argument(
        "--family",
        choices=sorted([*FAMILIES, "self"]),
        default="standard",
        help="scene distribution: standard, hard (issue 18: tight limits, passages, dense clutter, 8-12 goals), "
        "robots (issue 20: bundled Panda, UR5, iiwa; pinocchio oracle, witness labels), "
        "shapes or robot-shapes (issue 22: tables, shelves, walls with a gap, posts, a floor; coal oracle)",
    )
    parser.add_argument(
        "--timing-rounds",
        type=int,
        default=1,
        metavar="R",
        help="shape families: time each solve and its spheres-only twin's R times in turn and keep the "
        "best of each; self family: the same with self_collision auto and off "
        "(default 1; 3 steadies the ratio on a shared machine)",
    )
    parser.add_argument("--quick", action="store_true", help="8 scenes, for development")
    parser.add_argument("--list-misses", action="store_true", help="print every feasible goal that was missed")
    parser.add_argument("--dump-scene", nargs=2, metavar=("K", "DIR"), help="write scene K as YAML into DIR and exit")
    args = parser.parse_args(argv)
    args.methods = [m for m in args.methods.split(",") if m]
    unknown = set(args.methods) - set(METHODS)
    if unknown:
        parser.error(f"unknown method(s) {sorted(unknown)}; expected some of {', '.join(METHODS)}")
    args.planner = [p for p in args.planner.split(",") if p]
    if args.quick:
        args.scenes = 8
    return args


def effective_planners(requested: list) -> list:
    """The planner settings to run: as asked when armanim has ``solver.planner``, else just ``off``."""
    if planner_field_exists():
        return requested
    if requested != ["off"]:
        print(
            "note: this armanim has no solver.planner; running the current behaviour, labelled 'off'", file=sys.stderr
        )
    return ["off"]


def main(argv=None) -> int:
    args = parse_args(argv)
    began = time.perf_counter()
    planners = effective_planners(args.planner)
    if args.dump_scene:
        dump_scene(args.seed, int(args.dump_scene[0]), Path(args.dump_scene[1]), args.methods, planners, args.family)
        return 0
    if args.family == "self":
        return self_family(args)
    self_test_geometry(np.random.default_rng(12345))
    print("self-test: the oracle's forward kinematics and clearances equal armanim's (1e-9)", file=sys.stderr)
    if args.family in SHAPE_FAMILIES:
        self_test_solids(np.random.default_rng(12345))
        print(
            "self-test: the oracle's (coal's) clearances to boxes, capsules and the floor equal armanim's (1e-9)",
            file=sys.stderr,
        )
    if args.family in ("robots", "poses", "robot-shapes"):
        self_test_robots(np.random.default_rng(12345))
        print(
            "self-test: pinocchio's tool point and the oracle's robot capsule clearances equal armanim's (1e-9)",
            file=sys.stderr,
        )
    tasks = [
        (args.seed, k, args.methods, planners, args.family, max(1, args.timing_rounds)) for k in range(args.scenes)
    ]
    results = []
    if args.jobs > 1:
        with multiprocessing.get_context("forkserver").Pool(args.jobs) as pool:
            for result in pool.imap_unordered(bench_scene, tasks):
                results.append(result)
                report_progress(result, len(results), args.scenes, began)
    else:
        for task in tasks:
            results.append(bench_scene(task))
            report_progress(results[-1], len(results), args.scenes, began)
    results.sort(key=lambda r: r.index)
    print(
        f"motion_bench --family {args.family} --seed {args.seed} --scenes {args.scenes} --methods {','.join(args.methods)} --planner {','.join(planners)}"
    )
    broken = print_report(results, args.methods, planners, args.list_misses)
    print(f"\nbenchmark took {time.perf_counter() - began:.1f} s ({args.jobs} job(s))")
    if broken:
        print(f"{broken} invariant(s) broken", file=sys.stderr)
    return 1 if broken else 0


def report_progress(result: SceneResult, done: int, total: int, began: float) -> None:
    """One line on stderr per finished scene."""
    feasible = sum(v.feasible for v in result.verdicts)
    reached = " ".join(
        f"{run.method[:2]}/{run.planner}:{sum(v.feasible and ok for v, ok in zip(result.verdicts, run.reached))}"
        for run in result.runs
    )
    print(
        f"[{done}/{total} {time.perf_counter() - began:6.1f}s] scene {result.index} ({result.kind}, "
        f"{len(result.verdicts)} goals, {feasible} feasible) {reached}",
        file=sys.stderr,
        flush=True,
    )


if __name__ == "__main__":
    sys.exit(main())
