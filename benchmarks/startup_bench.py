"""The first minute (issue 55): a first run's compile, a small run's start-up, ``--version``.

Run: ``python benchmarks/startup_bench.py`` (a few minutes on two cores), and to compare with
another checkout in the same run (today's main, say)::

    git worktree add /tmp/armanim-main main
    python benchmarks/startup_bench.py --baseline-src /tmp/armanim-main/src

Every figure is a whole process, ``python -m armanim ...`` started from this script, measured in
CPU seconds (the process's user + system time: other work on a shared machine slows the wall
clock but adds little CPU) and in wall seconds for scale:

1. **first run's compile**: the README's first scene (``scenes/notes-arm.yaml --no-video``) in an
   empty numba cache (``NUMBA_CACHE_DIR``, a temporary folder), less the same run once its cache is
   warm: the CPU numba spends compiling armanim's kernels once after installing (target: at most a
   third of the baseline's, and at most 15 s);
2. **a small run**: the same scene with its cache warm against ``python -c 'import numpy,
   scipy.linalg, pydantic, yaml, typer, rich, numba'`` (the stack every run imports) in the same
   rounds: the run as a multiple of its stack's imports (target: at most 1.5x);
3. **--version**: as the baseline's (target: no slower).

The rounds run the candidates in a rotated order after a warm-up round (Python's own bytecode
cache written: a user's install has it; this script's children write it even where
``PYTHONDONTWRITEBYTECODE`` is set), and the medians are compared. With ``--baseline-src`` each
line is printed for both sources and as their ratio; both runs' outputs must be byte-identical.
"""

from __future__ import annotations

import argparse
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SCENE = "scenes/notes-arm.yaml"
STACK_MODULES = "numpy, scipy.linalg, pydantic, yaml, typer, rich, numba"
"""What every ``armanim run`` imports by design (the chosen dependencies): the floor of a small run's time."""


def timed(command: list[str], env: dict[str, str]) -> tuple[float, float]:
    """(CPU seconds, wall seconds) of one child process run to its end (its exit checked)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    done = subprocess.run(command, cwd=ROOT, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode != 0:
        sys.exit(f"startup_bench: {' '.join(command)} failed:\n{done.stderr}")
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime), wall


class Source:
    """One checkout's armanim (``src`` None: the installed one), with its own numba cache folders."""

    def __init__(self, label: str, src: str | None, work: Path):
        self.label = label
        self.env = {k: v for k, v in os.environ.items() if k not in ("PYTHONDONTWRITEBYTECODE", "NUMBA_CACHE_DIR")}
        if src is not None:
            self.env["PYTHONPATH"] = os.pathsep.join([src, *filter(None, [os.environ.get("PYTHONPATH")])])
        self.work = work / label
        self.work.mkdir(parents=True)
        self.warm_cache = self.work / "warm-cache"

    def armanim(self, *args: str) -> list[str]:
        return [sys.executable, "-m", "armanim", *args]

    def run(self, out: str) -> list[str]:
        return self.armanim("run", SCENE, "--no-video", "-q", "--out", str(self.work / out))

    def with_cache(self, cache: Path) -> dict[str, str]:
        return {**self.env, "NUMBA_CACHE_DIR": str(cache)}

    def where(self) -> str:
        probe = [sys.executable, "-c", "import armanim, os; print(os.path.dirname(armanim.__file__))"]
        return subprocess.run(probe, env=self.env, capture_output=True, text=True, check=True).stdout.strip()


def first_compile(source: Source, repeat: int) -> tuple[float, float]:
    """CPU and wall seconds of the scene's first run in an empty cache: the first one fills the
    cache the start-up part then runs with, each other one a cache of its own, deleted after."""
    cache = source.warm_cache if repeat == 0 else source.work / f"cold-cache-{repeat}"
    cpu, wall = timed(source.run(f"cold-{repeat}"), source.with_cache(cache))
    if repeat:
        shutil.rmtree(cache, ignore_errors=True)
    return cpu, wall


def median(values: list[float]) -> float:
    return statistics.median(values) if values else float("nan")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--baseline-src", default=None, help="another checkout's src folder, measured in the same run")
    parser.add_argument("--rounds", type=int, default=7, help="rounds of the start-up part (after a warm-up round)")
    parser.add_argument("--cold", type=int, default=1, help="first runs in an empty cache, per source")
    parser.add_argument("--skip-cold", action="store_true", help="only the start-up part (no first compile)")
    args = parser.parse_args()

    work = Path(tempfile.mkdtemp(prefix="startup_bench-"))
    try:
        sources = [Source("this", None, work)]
        if args.baseline_src:
            sources.append(Source("baseline", str(Path(args.baseline_src).resolve()), work))
        for source in sources:
            print(f"{source.label}: {source.where()}")
        print(f"machine: {os.cpu_count()} cores, load {' '.join(f'{x:.2f}' for x in os.getloadavg())} at the start")

        results: dict[str, dict[str, tuple[list[float], list[float]]]] = {s.label: {} for s in sources}
        if not args.skip_cold:
            print(
                f"1. the first run's compile: {SCENE} --no-video in an empty numba cache ({args.cold} each) ...",
                flush=True,
            )
            for r in range(args.cold):
                for source in sources if r % 2 == 0 else sources[::-1]:
                    cpu, wall = first_compile(source, r)
                    old = results[source.label].get("cold", ([], []))
                    results[source.label]["cold"] = (old[0] + [cpu], old[1] + [wall])

        stack = [sys.executable, "-c", f"import {STACK_MODULES}"]
        cases: list[tuple[str, Source | None, list[str]]] = [("stack", None, stack)]
        for source in sources:
            cases += [("run", source, source.run("warm")), ("version", source, source.armanim("--version"))]
        times: dict[tuple[str, str], tuple[list[float], list[float]]] = {}
        print(f"2-3. start-up, whole processes, {args.rounds} rotated rounds after a warm-up round ...", flush=True)
        for r in range(args.rounds + 1):
            for name, source, command in cases[r % len(cases) :] + cases[: r % len(cases)]:
                env = source.with_cache(source.warm_cache) if source else dict(sources[0].env)
                c, w = timed(command, env)
                if r:
                    key = (name, source.label if source else "")
                    cpu, wall = times.setdefault(key, ([], []))
                    cpu.append(c)
                    wall.append(w)

        print(f"machine: load {' '.join(f'{x:.2f}' for x in os.getloadavg())} at the end")
        stack_cpu, stack_wall = times[("stack", "")]
        print(
            f"\n   python -c 'import {STACK_MODULES}': CPU {median(stack_cpu):.3f} s, wall {median(stack_wall):.3f} s (medians)"
        )
        summary: dict[str, dict[str, float]] = {}
        for source in sources:
            s = summary[source.label] = {}
            run_cpu, run_wall = times[("run", source.label)]
            ver_cpu, ver_wall = times[("version", source.label)]
            s["run_cpu"], s["version_cpu"], s["version_wall"] = median(run_cpu), median(ver_cpu), median(ver_wall)
            s["run_x_stack"] = median([a / b for a, b in zip(run_cpu, stack_cpu, strict=True)])
            s["run_x_stack_wall"] = median([a / b for a, b in zip(run_wall, stack_wall, strict=True)])
            print(f"\n   [{source.label}]")
            if "cold" in results[source.label]:
                cold_cpu, cold_wall = results[source.label]["cold"]
                s["compile_cpu"] = median(cold_cpu) - s["run_cpu"]
                print(
                    f"   1. first run, empty cache: CPU {median(cold_cpu):.1f} s (wall {median(cold_wall):.1f} s); "
                    f"compiling: {s['compile_cpu']:.1f} s of CPU (the first run less a warm one)"
                )
            print(
                f"   2. small run --no-video: CPU {s['run_cpu']:.3f} s, wall {median(run_wall):.3f} s: "
                f"{s['run_x_stack']:.2f}x its stack's imports in CPU ({s['run_x_stack_wall']:.2f}x in wall time)"
            )
            print(f"   3. --version: CPU {s['version_cpu']:.3f} s, wall {s['version_wall']:.3f} s")
        if len(sources) == 2:
            this, base = summary["this"], summary["baseline"]
            print("\n   this / baseline (same run):")
            if "compile_cpu" in this and "compile_cpu" in base:
                print(
                    f"   1. first run's compile CPU: {this['compile_cpu']:.1f} s / {base['compile_cpu']:.1f} s = "
                    f"{this['compile_cpu'] / base['compile_cpu']:.2f}x (target <= 0.33x and <= 15 s)"
                )
            print(
                f"   2. small run, x its stack's imports: {this['run_x_stack']:.2f}x / {base['run_x_stack']:.2f}x (target <= 1.5x)"
            )
            print(
                f"   3. --version CPU: {this['version_cpu']:.3f} s / {base['version_cpu']:.3f} s = "
                f"{this['version_cpu'] / base['version_cpu']:.2f}x (target: as today)"
            )
            same = all(
                (work / "this" / "warm" / "notes-arm" / name).read_bytes()
                == (work / "baseline" / "warm" / "notes-arm" / name).read_bytes()
                for name in ("trajectory.csv", "summary.json")
            )
            print(f"   outputs byte-identical between the two: {same}")
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
