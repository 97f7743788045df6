"""Issue 52's MotionBenchMaker count: how many of the 700 Panda problems each of the bundled Panda's
collision sets admits (the hand-made capsules of its URDF, ``collision: auto``, against the capsules
fitted to its shipped meshes, ``collision: fitted``).

Every problem of VAMP's ``panda/problems.tar.bz2`` is imported with ``armanim import moveit``'s API
(:func:`armanim.scene.moveitscene.moveit_scene`, ``--robot panda``, so the bundled Panda with its
fingers as the request holds them and the importer's 0.5 mm clearance), the scene's ``arm.collision``
set to each mode, and checked as ``armanim validate`` checks it (:func:`armanim.scene.checks.scene_problems`:
every capsule at home at least ``solver.clearance`` from every obstacle, every enabled pair of links
``solver.self_clearance`` apart, the same at the joint goal). A start is admitted when no problem names
the home pose; a problem when nothing at all is wrong.

Run: ``python benchmarks/mbm_starts_bench.py /work/shared/data/mbm`` (the folder of ``panda/``); some
minutes on one core. ``--limit N`` runs the first N problems; ``--solve`` also solves each admitted
problem (planning and the clock, as ``mbm_bench.py`` does) and counts those that reach their joint goal.
"""

from __future__ import annotations

import argparse
import copy
import sys
import tarfile
import tempfile
import time
from collections import Counter
from pathlib import Path

from armanim.errors import SceneError
from armanim.scene import scene_model
from armanim.scene.checks import scene_problems
from armanim.scene.moveitscene import RobotSource, moveit_scene

MODES = ("auto", "fitted")


def check(data: dict, mode: str) -> tuple[bool, bool, str, object]:
    """(start admitted, problem admitted, the first problem's field path and message, the validated
    scene) of one imported scene."""
    data = copy.deepcopy(data)
    data["arm"]["collision"] = mode
    scene = scene_model(data)
    problems = scene_problems(scene)
    start = [p for p in problems if not p[0].startswith("goals")]
    first = f"{problems[0][0]}: {problems[0][1]}" if problems else ""
    return not start, not problems, first, scene


def solved(scene) -> bool:
    """Whether the admitted problem's solve (planning, then the clock) reaches its joint goal."""
    from armanim.motion.timing.retime import retime
    from armanim.motion.trajectory import solve_trajectory
    from armanim.scene.convert import scene_to_problem

    problem = scene_to_problem(scene)
    return bool(retime(problem, solve_trajectory(problem), problem.fps).goals[0].reached)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder", type=Path, help="the folder of panda/problems.tar.bz2")
    parser.add_argument("--limit", type=int, default=None)
    parser.add_argument("--solve", action="store_true", help="also solve each admitted problem and count those solved")
    parser.add_argument(
        "--urdf",
        type=Path,
        default=None,
        help="a Panda URDF instead of the bundled one (VAMP's mesh panda.urdf: its meshes fitted by collision: auto)",
    )
    parser.add_argument("--srdf", type=Path, default=None, help="that URDF's SRDF (its allowed pairs)")
    args = parser.parse_args(argv)
    robot = RobotSource(robot="panda") if args.urdf is None else RobotSource(urdf=args.urdf, srdf=args.srdf)
    modes = MODES if args.urdf is None else ("auto",)
    counts = {mode: Counter() for mode in modes}
    refused: dict[str, Counter] = {mode: Counter() for mode in modes}
    unimported: Counter = Counter()
    reasons: Counter = Counter()
    started = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp, tarfile.open(args.folder / "panda" / "problems.tar.bz2") as archive:
        archive.extractall(tmp, filter="data")
        scenes = sorted(Path(tmp).glob("problems/*/scene*.yaml"))[: args.limit]
        for scene in scenes:
            request = scene.with_name(scene.name.replace("scene", "request"))
            family = scene.parent.name
            try:
                data = moveit_scene(scene, request, robot, Path(tmp) / "out.yaml").data
                if (
                    args.urdf is not None
                ):  # the scene's files relative to where it would be written; checked here from the cwd
                    data["arm"]["urdf"] = str(args.urdf.resolve())
                    if args.srdf is not None:
                        data["arm"]["self_collision"]["srdf"] = str(args.srdf.resolve())
            except SceneError as error:  # a start or goal outside the bundled Panda's limits (Franka's own)
                unimported[family] += 1
                reasons[error.problems[0].message.split(" at ")[0] + " outside its limits"] += 1
                continue
            for mode in modes:
                start, whole, first, checked = check(data, mode)
                counts[mode][("start", family)] += start
                counts[mode][("problem", family)] += whole
                if whole and args.solve:
                    counts[mode][("solved", family)] += solved(checked)
                if not whole:
                    refused[mode][first.split(":")[0] + ": " + first.split("(")[0].split(": ", 1)[-1][:70]] += 1
    families = sorted({f for _, f in counts["auto"]})
    total = len(scenes)
    print(f"{total} Panda problems, {time.perf_counter() - started:.0f} s")
    kinds = ("start", "problem", "solved") if args.solve else ("start", "problem")
    words = {"start": "starts admitted", "problem": "problems admitted", "solved": "admitted and solved"}
    print("| family | " + " | ".join(f"{words[k]}, {m}" for k in kinds for m in modes) + " |")
    print("|---|" + "---|" * (len(kinds) * len(modes)))
    for family in families:
        per = sum(1 for s in scenes if s.parent.name == family)
        row = [f"{counts[m][(k, family)]}/{per}" for k in kinds for m in modes]
        print(f"| {family} | " + " | ".join(row) + " |")
    row = [f"**{sum(v for (c, _), v in counts[m].items() if c == k)}/{total}**" for k in kinds for m in modes]
    print("| all | " + " | ".join(row) + " |")
    print(
        f"not imported: {sum(unimported.values())} ({', '.join(f'{f} {n}' for f, n in sorted(unimported.items()))}): "
        + "; ".join(f"{n} x {why}" for why, n in reasons.most_common(3))
    )
    for mode in modes:
        print(f"{mode}: problems refused by " + "; ".join(f"{n} x {why}" for why, n in refused[mode].most_common(5)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
