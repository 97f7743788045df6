"""The hostile fuzzer's long profile (issue 36, item 5): many examples of every strategy of
``tests/fuzz_scenes.py``, each held to its invariants, in one process; then a few through the
installed command. Prints the examples tried, how many were errors (exit 2) and runs, the
failures (0 is the target), the time and the peak memory.

    nice -n 10 .venv/bin/python benchmarks/fuzz_bench.py --examples 10000

``--examples`` is per in-process strategy (schema scenes, URDF scenes); the result goes in
benchmarks/README.md. A failure prints its example and traceback, and the script exits 1.
"""

from __future__ import annotations

import argparse
import resource
import sys
import tempfile
import time
import traceback
from collections import Counter
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from fuzz_scenes import check_command, check_scene_text, check_urdf_scene, hostile_scenes, scene_yaml, urdf_scenes  # noqa: E402
from hypothesis import HealthCheck, given, seed, settings  # noqa: E402


def run_strategy(name: str, strategy, check, examples: int, base_seed: int, outcomes: Counter, failures: list) -> None:
    """Draw ``examples`` examples of ``strategy`` and ``check`` each; failures are collected, not raised."""

    @seed(base_seed)
    @settings(
        max_examples=examples,
        deadline=None,
        database=None,
        suppress_health_check=list(HealthCheck),
        phases=["generate"],
    )
    @given(strategy)
    def one(example):
        try:
            outcomes[f"{name} {check(example)}"] += 1
        except Exception:
            outcomes[f"{name} FAILED"] += 1
            failures.append((name, example, traceback.format_exc()))

    one()


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--examples", type=int, default=10_000, help="examples per in-process strategy")
    parser.add_argument("--commands", type=int, default=20, help="examples through the installed command")
    parser.add_argument("--seed", type=int, default=36)
    args = parser.parse_args()
    outcomes: Counter = Counter()
    failures: list = []
    start = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        run_strategy(
            "scene",
            hostile_scenes(),
            lambda data: check_scene_text(scene_yaml(data), "fuzz.yaml"),
            args.examples,
            args.seed,
            outcomes,
            failures,
        )
        run_strategy(
            "urdf",
            urdf_scenes(),
            lambda pair: check_urdf_scene(*pair, folder),
            args.examples,
            args.seed + 1,
            outcomes,
            failures,
        )
        counter = [0]

        def through_the_command(data) -> str:
            counter[0] += 1
            where = folder / f"cmd{counter[0]}"
            where.mkdir()
            (where / "s.yaml").write_text(scene_yaml(data), encoding="utf-8")
            code = check_command(["run", "s.yaml", "--out", "o", "--no-video", "--viewer"], where, ["s.yaml", "o"])
            return {0: "ran", 2: "error", 3: "output error"}[code]

        run_strategy("command", hostile_scenes(), through_the_command, args.commands, args.seed + 2, outcomes, failures)
    seconds = time.perf_counter() - start
    tried = sum(outcomes.values())
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(
        f"examples tried: {tried:,}; failures: {len(failures)}; {seconds:.0f} s ({1000 * seconds / max(tried, 1):.1f} ms an example); "
        f"peak memory {peak:.0f} MB"
    )
    for key in sorted(outcomes):
        print(f"  {key}: {outcomes[key]:,}")
    seen = set()
    for name, example, trace in failures:
        last = trace.strip().splitlines()[-1][:120]
        if last in seen:
            continue
        seen.add(last)
        print(f"--- {name}: {str(example)[:2000]}\n{trace[-3000:]}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
