"""MotionBenchMaker benchmark for armanim (issue 49): the field's shared motion problems, as VAMP ships them.

    python benchmarks/mbm_bench.py                               # every Panda and UR5 problem (1,400)
    python benchmarks/mbm_bench.py --robots panda --families box,cage --limit 10
    python benchmarks/mbm_bench.py --data ~/vamp/resources       # a clone of KavrakiLab/vamp
    python benchmarks/mbm_bench.py --csv /tmp/mbm.csv            # one row per problem
    python benchmarks/mbm_bench.py --batch 20                    # also: 20 problems in one `armanim run --no-video --jobs 1`

Data. ``--data`` is a folder with ``<robot>/problems.tar.bz2``, ``<robot>/<robot>_spherized.urdf`` and
``<robot>/<robot>.srdf``, as VAMP's ``resources/`` folder has them (Apache-2.0; the problems are
MotionBenchMaker's, Chamzas et al., RA-L 2022): ``git clone https://github.com/KavrakiLab/vamp`` and pass
``--data vamp/resources``. The default is ``../shared/data/mbm`` beside this repository (a copy of those
files). The archives are read with :mod:`tarfile`, member by member, never extracted to disk.

Per problem, in one process after the first compile:

1. ``armanim import moveit`` (its Python API, :func:`armanim.scene.moveitscene.moveit_scene`) turns the
   planning scene and request into an armanim scene, the robot's URDF and SRDF beside it;
2. the scene is validated (:func:`armanim.scene.loader.scene_from_bytes`): a problem is **valid** when
   its start and goal are free under the robot's collision model (every capsule at least
   ``solver.clearance`` from every object, every enabled pair ``self_clearance`` apart, as the
   importer writes them); any other problem with the scene is a failure of armanim and is counted so;
3. the **solve**: the scene to a timed trajectory (:func:`~armanim.motion.trajectory.solve_trajectory`
   and the clock, :func:`~armanim.motion.timing.retime.retime`), wall time and this process's CPU time
   measured around it (on a busy machine the CPU time is the fairer figure: other processes inflate
   it less);
4. an **independent check** of every frame: the clearances of the numpy reference
   (:func:`armanim.motion.filter.clearance.split_clearances`, not the compiled checks the planner used)
   against ``solver.clearance`` and ``self_clearance``, and the last frame against the goal.

It prints, per robot and family: valid, solved, median and p95 solve time, median joint path length
(the Euclidean joint-space length of the motion, radians, as VAMP's "simplified path" cost), median
motion duration (the clock's, within the robot's own speed and acceleration limits), and frames under
a clearance. VAMP's and cuRobo's published figures are printed beside them, quoted, not rerun.
"""

from __future__ import annotations

import argparse
import csv
import math
import os
import resource
import sys
import tarfile
import tempfile
import time
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
DEFAULT_DATA = ROOT.parent / "shared" / "data" / "mbm"
FAMILIES = ("bookshelf_small", "bookshelf_tall", "bookshelf_thin", "box", "cage", "table_pick", "table_under_pick")

PUBLISHED = {
    "panda": "VAMP (one AMD Ryzen 9 7950X core, C++ SIMD; its resources/README.md): 699/699 valid solved, "
    "median total 99 us, median simplified path 4.90 rad",
    "ur5": "VAMP (same machine): 608/608 valid solved, median total 111 us, median simplified path 6.55 rad",
    "all": "cuRobo v0.7.6 (NVIDIA RTX 6000 Ada GPU; its benchmark page): 100 % of MotionBenchMaker's 800, "
    "42 ms mean planning, 1.36 s mean motion, 3.8 rad mean path",
}
VAMP_PATH = {"panda": 4.90, "ur5": 6.55}


@dataclass
class Outcome:
    """One problem's result."""

    robot: str
    family: str
    index: int
    valid: bool
    solved: bool = False
    reason: str = ""
    solve_s: float = math.nan
    solve_cpu_s: float = math.nan
    path_rad: float = math.nan
    duration_s: float = math.nan
    under_clearance: int = 0
    under_self_clearance: int = 0
    goal_error_deg: float = math.nan
    source: str = ""
    checks: int = 0


def problem_files(
    archive: Path, robot: str, families: list[str], limit: int | None
) -> dict[tuple[str, int], dict[str, bytes]]:
    """{(family, index): {"scene": bytes, "request": bytes}} from a VAMP problems archive."""
    found: dict[tuple[str, int], dict[str, bytes]] = {}
    with tarfile.open(archive, "r:bz2") as tar:
        for member in tar:
            if not member.isfile() or member.size > 10_000_000:
                continue
            parts = Path(member.name).parts
            if len(parts) < 2 or not parts[-2].endswith(f"_{robot}"):
                continue
            family = parts[-2][: -len(robot) - 1]
            stem = Path(parts[-1]).stem
            kind = "scene" if stem.startswith("scene") else "request" if stem.startswith("request") else None
            if family not in families or kind is None:
                continue
            index = int(stem[len(kind) :])
            if limit is not None and index > limit:
                continue
            handle = tar.extractfile(member)
            assert handle is not None
            found.setdefault((family, index), {})[kind] = handle.read()
    return {key: files for key, files in sorted(found.items()) if len(files) == 2}


def solve_problem(robot: str, family: str, index: int, files: dict[str, bytes], data: Path, work: Path) -> Outcome:
    """Import, validate, solve and check one problem (see the module's docstring)."""
    from armanim.errors import SceneError
    from armanim.motion.filter.clearance import split_clearances
    from armanim.motion.timing.retime import retime
    from armanim.motion.trajectory import solve_trajectory
    from armanim.scene.convert import scene_to_problem
    from armanim.scene.loader import scene_from_bytes
    from armanim.scene.moveitscene import RobotSource, moveit_scene

    scene_file, request_file = work / "scene.yaml", work / "request.yaml"
    scene_file.write_bytes(files["scene"])
    request_file.write_bytes(files["request"])
    source = RobotSource(urdf=data / robot / f"{robot}_spherized.urdf", srdf=data / robot / f"{robot}.srdf")
    out = work / f"{family}-{index}.yaml"
    imported = moveit_scene(scene_file, request_file, source, out)
    try:
        scene = scene_from_bytes(imported.text.encode(), out)
    except SceneError as error:
        text = str(error)
        free = ("arm.home" not in text and "goals[0]" not in text) or not any(
            words in text for words in ("inside", "closer", "overlapping")
        )
        if free:
            raise  # not a start or goal in collision: armanim's own failure
        return Outcome(robot, family, index, valid=False, reason="start or goal in collision")
    started, cpu = time.perf_counter(), time.process_time()
    problem = scene_to_problem(scene.model)
    solution = solve_trajectory(problem)
    timed = retime(problem, solution, problem.fps)
    solve_s, solve_cpu_s = time.perf_counter() - started, time.process_time() - cpu
    goal = timed.goals[0]
    traj = timed.trajectory
    clear, own = split_clearances(problem, traj.phi)
    shift = problem.solver.clearance - problem.self_pairs.clearance
    under = int(np.sum(clear < problem.solver.clearance - 1e-9))
    under_self = 0 if own is None else int(np.sum(own.min(axis=1) - shift < problem.self_pairs.clearance - 1e-9))
    target = problem.goals[0].joints
    error = float(np.degrees(np.abs(traj.phi[-1] - target).max())) if target is not None else math.nan
    steps = np.linalg.norm(np.diff(traj.phi, axis=0), axis=1)
    planning = goal.planning
    return Outcome(
        robot,
        family,
        index,
        valid=True,
        solved=goal.reached,
        reason=goal.reason or "",
        solve_s=solve_s,
        solve_cpu_s=solve_cpu_s,
        path_rad=float(steps.sum()),
        duration_s=traj.frames / traj.fps,
        under_clearance=under,
        under_self_clearance=under_self,
        goal_error_deg=error,
        source=planning.path if planning else "",
        checks=planning.checks if planning else 0,
    )


def warm_up(data: Path, robot: str, problems: dict, work: Path) -> None:
    """Solve one problem first, so that numba's compile (or cache load) is not in the figures."""
    (family, index), files = next(iter(problems.items()))
    solve_problem(robot, family, index, files, data, work)


def summary_rows(outcomes: list[Outcome]) -> list[list[str]]:
    """Per robot and family, then per robot: the printed table's rows."""
    rows = []
    groups: dict[tuple[str, str], list[Outcome]] = {}
    for o in outcomes:
        groups.setdefault((o.robot, o.family), []).append(o)
        groups.setdefault((o.robot, "all"), []).append(o)
    for (robot, family), group in sorted(groups.items(), key=lambda kv: (kv[0][0], kv[0][1] == "all", kv[0][1])):
        valid = [o for o in group if o.valid]
        solved = [o for o in valid if o.solved]
        times = np.array([o.solve_s for o in valid])
        cpu = np.array([o.solve_cpu_s for o in valid])
        paths = np.array([o.path_rad for o in solved])
        durations = np.array([o.duration_s for o in solved])
        rows.append(
            [
                robot,
                family,
                f"{len(valid)}/{len(group)}",
                f"{len(solved)}/{len(valid)}",
                f"{100 * len(solved) / max(len(valid), 1):.1f} %",
                _ms(np.median(times)) if len(times) else "-",
                _ms(np.percentile(times, 95)) if len(times) else "-",
                _ms(np.median(cpu)) if len(cpu) else "-",
                _ms(np.percentile(cpu, 95)) if len(cpu) else "-",
                f"{np.median(paths):.2f}" if len(paths) else "-",
                f"{np.median(paths) / VAMP_PATH[robot]:.2f}x" if len(paths) and robot in VAMP_PATH else "-",
                f"{np.median(durations):.2f}" if len(durations) else "-",
                str(sum(o.under_clearance for o in valid)),
                str(sum(o.under_self_clearance for o in valid)),
            ]
        )
    return rows


def _ms(seconds: float) -> str:
    return f"{1e3 * seconds:.0f} ms"


HEADER = [
    "robot",
    "family",
    "valid",
    "solved",
    "solved %",
    "median solve",
    "p95 solve",
    "median CPU",
    "p95 CPU",
    "median path rad",
    "vs VAMP",
    "median motion s",
    "frames < clearance",
    "frames < self_clearance",
]


def print_table(rows: list[list[str]]) -> None:
    widths = [max(len(r[i]) for r in [HEADER, *rows]) for i in range(len(HEADER))]
    for row in [HEADER, ["-" * w for w in widths], *rows]:
        print("  ".join(cell.rjust(w) if i > 1 else cell.ljust(w) for i, (cell, w) in enumerate(zip(row, widths))))


def batch_run(data: Path, robot: str, problems: dict, count: int, work: Path) -> tuple[float, float]:
    """Wall and CPU seconds per problem of ``count`` imported problems in one ``armanim run
    --no-video --jobs 1`` (its own process, start-up and writing included; the first compile is
    warm from this process's cache)."""
    import subprocess

    from armanim.scene.moveitscene import RobotSource, import_moveit

    folder = work / f"batch-{robot}"
    folder.mkdir()
    scenes = []
    for (family, index), files in list(problems.items())[:count]:
        (folder / "s.yaml").write_bytes(files["scene"])
        (folder / "r.yaml").write_bytes(files["request"])
        out = folder / f"{family}-{index}.yaml"
        import_moveit(
            folder / "s.yaml",
            folder / "r.yaml",
            RobotSource(urdf=data / robot / f"{robot}_spherized.urdf", srdf=data / robot / f"{robot}.srdf"),
            out,
        )
        scenes.append(str(out))
    command = [
        sys.executable,
        "-m",
        "armanim",
        "run",
        *scenes,
        "--no-video",
        "--no-viewer",
        "--jobs",
        "1",
        "--quiet",
        "--out",
        str(work / f"runs-{robot}"),
    ]
    started, children = time.perf_counter(), resource.getrusage(resource.RUSAGE_CHILDREN)
    done = subprocess.run(command, capture_output=True, text=True, check=False)
    seconds = time.perf_counter() - started
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = after.ru_utime + after.ru_stime - children.ru_utime - children.ru_stime
    if done.returncode not in (0, 1):
        print(done.stderr[-2000:], file=sys.stderr)
    return seconds / len(scenes), cpu / len(scenes)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        description=__doc__.splitlines()[0],
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog=__doc__.split("\n\n", 1)[0],
    )
    parser.add_argument(
        "--data", type=Path, default=DEFAULT_DATA, help="folder with <robot>/problems.tar.bz2 (VAMP's resources/)"
    )
    parser.add_argument("--robots", default="panda,ur5")
    parser.add_argument("--families", default=",".join(FAMILIES))
    parser.add_argument("--limit", type=int, default=None, help="problems 1..LIMIT of each family (default all 100)")
    parser.add_argument("--csv", type=Path, default=None, help="write one row per problem here")
    parser.add_argument(
        "--batch", type=int, default=0, help="also time this many problems in one `armanim run` per robot"
    )
    args = parser.parse_args(argv)
    families = [f for f in args.families.split(",") if f]
    outcomes: list[Outcome] = []
    batches = {}
    os.environ.setdefault("PYTHONHASHSEED", "0")
    with tempfile.TemporaryDirectory(prefix="mbm-bench-") as tmp:
        work = Path(tmp)
        for robot in [r for r in args.robots.split(",") if r]:
            archive = args.data / robot / "problems.tar.bz2"
            if not archive.is_file():
                print(
                    f"mbm_bench: {archive}: not found (pass --data, a folder like VAMP's resources/)", file=sys.stderr
                )
                return 2
            problems = problem_files(archive, robot, families, args.limit)
            warm_up(args.data, robot, problems, work)
            for k, ((family, index), files) in enumerate(problems.items()):
                outcome = solve_problem(robot, family, index, files, args.data, work)
                outcomes.append(outcome)
                print(
                    f"\r{robot} {k + 1}/{len(problems)} {family} {index}: "
                    f"{'invalid' if not outcome.valid else 'solved' if outcome.solved else outcome.reason} "
                    f"{1e3 * outcome.solve_s:.0f} ms      ",
                    end="",
                    file=sys.stderr,
                    flush=True,
                )
            print(file=sys.stderr)
            if args.batch:
                batches[robot] = batch_run(args.data, robot, problems, args.batch, work)
    if args.csv is not None:
        with args.csv.open("w", newline="") as handle:
            writer = csv.DictWriter(handle, fieldnames=list(asdict(outcomes[0])))
            writer.writeheader()
            writer.writerows(asdict(o) for o in outcomes)
    print_table(summary_rows(outcomes))
    print(
        f"load average at the end: {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores (solve: wall time; CPU: this process's, "
        "which other processes on a busy machine inflate less)"
    )
    for robot, (seconds, cpu) in batches.items():
        print(
            f"{robot}: {args.batch} problems in one `armanim run --no-video --jobs 1`: {seconds:.3f} s a problem "
            f"({cpu:.3f} s of CPU), start-up and writing included"
        )
    failures = [o for o in outcomes if o.valid and not o.solved]
    if failures:
        print("missed: " + ", ".join(f"{o.robot} {o.family} {o.index} ({o.reason})" for o in failures[:40]))
    print("\nPublished, quoted (not rerun here):")
    for line in PUBLISHED.values():
        print(f"  {line}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
