"""Batch scale-out: 16 small scenes, jobs 1 vs jobs 2, and a Dask LocalCluster vs the pool.

Run: ``python benchmarks/batch_bench.py`` (about a minute and a half on two cores; needs
``pip install -e '.[dask]'`` for the Dask part, which is skipped with a message otherwise).

16 scenes are generated in a temporary folder: 8 variants of the planar 4-link arm and
8 of the course notes' arm (3 obstacles), each with 2 goals, rendered at 320x180 and
15 fps with video and plot, so that one scene takes about 1-2 s. Everything goes through
:func:`armanim.runs.batch.run_batch`, in one run:

1. ``jobs=1`` (in this process) against ``jobs=2`` (a spawn process pool):
   speed-up ratio, target >= 1.7x on 2 cores.
2. ``scheduler="local", jobs=2`` (a Dask LocalCluster, started and stopped inside the
   timed call, as ``armanim run --scheduler local`` does) against the pool with
   ``jobs=2``: overhead in %, target <= 15 %.

The candidates run in turn, ``--repeats`` times (default 2), and the best time of each is
compared (background load only ever adds time). A diagnostic candidate, the pool with
``OPENBLAS_NUM_THREADS=OMP_NUM_THREADS=MKL_NUM_THREADS=1`` in its workers' environment
(what Dask's nanny sets for its workers), shows what oversubscribed BLAS threads cost;
``--no-diagnosis`` skips it. The script then times the fixed costs
that the ratios include: starting a spawn worker and importing armanim in it, and starting
and stopping a LocalCluster, so a missed target can be explained. Results are checked to be
byte-identical (trajectory.csv, summary.json) between all candidates.
"""

from __future__ import annotations

import argparse
import multiprocessing
import os
import sys
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from unittest import mock

import yaml

from armanim.runs.batch import run_batch
from armanim.runs.options import RunOptions

PLANAR = {
    "version": 1,
    "arm": {"links": [1, 1, 1, 1], "axes": ["z", "z", "z", "z"], "direction": "x", "width": 0.2},
    "solver": {"method": "dls", "step": 0.2, "max_step": 0.3, "tolerance": 0.01, "max_frames_per_goal": 60},
    "render": {"size": [320, 180], "fps": 15, "view": {"elevation": 90, "azimuth": -90}},
}
NOTES = {
    "version": 1,
    "arm": {
        "base": [5, 5, 0],
        "links": [2, 5, 5, 5],
        "axes": ["z", "y", "y", "y"],
        "direction": "z",
        "limits": [None, [-100, 100], [-150, 150], [-150, 150]],
        "limit_margin": 15,
        "width": 0.6,
    },
    "obstacles": [
        {"center": [12, 9, 8], "radius": 2, "influence": 2},
        {"center": [4, 12, 11], "radius": 1.5, "influence": 2},
        {"center": [9, 2, 13], "radius": 1.2, "influence": 1.5},
    ],
    "solver": {"method": "pinv", "step": 0.15, "max_step": 0.5, "tolerance": 0.01, "max_frames_per_goal": 60},
    "render": {"size": [320, 180], "fps": 15, "view": {"elevation": 25, "azimuth": -60}},
}
PLANAR_GOALS = [
    [3, 1, 0],
    [1, 1, 0],
    [-2, 2.5, 0],
    [0.5, -3, 0],
    [2.5, -1.5, 0],
    [-1, 3, 0],
    [3.2, 0.5, 0],
    [-2.5, -1, 0],
]
NOTES_GOALS = [[14, 5, 6], [6, 15, 9], [0, 8, 4], [10, 10, 14], [13, 8, 4], [3, 12, 6], [8, 0, 10], [12, 4, 12]]


def write_scenes(folder: Path) -> list[Path]:
    """16 small scenes: planar-k and notes-k, k = 0..7, each with two of the goals above."""
    paths = []
    for family, base, goals in (("planar", PLANAR, PLANAR_GOALS), ("notes", NOTES, NOTES_GOALS)):
        for k in range(8):
            scene = {**base, "name": f"{family}-{k}", "goals": [goals[k], goals[(k + 3) % 8]]}
            path = folder / f"{family}-{k}.yaml"
            path.write_text(yaml.safe_dump(scene, sort_keys=False))
            paths.append(path)
    return paths


ONE_BLAS_THREAD = {"OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}


def timed_batch(paths, out: Path, environ: dict | None = None, jobs: int | None = None, **kwargs) -> float:
    """Seconds for run_batch; ``environ`` is set while it runs (spawned workers inherit it)."""
    with mock.patch.dict(os.environ, environ or {}):  # restored as it was, even on an error
        start = time.perf_counter()
        entries = run_batch(paths, out, RunOptions(video=True, jobs=jobs), **kwargs)
        elapsed = time.perf_counter() - start
    bad = [e for e in entries if e.status != "ok"]
    if bad:
        sys.exit(f"batch_bench: {len(bad)} scenes did not run: {bad[0].message}")
    return elapsed


def outputs(out: Path) -> dict[str, bytes]:
    return {
        str(p.relative_to(out)): p.read_bytes()
        for p in sorted(out.glob("*/*"))
        if p.name in ("trajectory.csv", "summary.json")
    }


def _import_armanim(_: int = 0) -> float:
    start = time.perf_counter()
    import matplotlib.backends.backend_agg  # noqa: F401  (what a worker imports for its first scene)
    import matplotlib.figure  # noqa: F401

    import armanim.render.pictures.canvas  # noqa: F401
    import armanim.render.pictures.plot  # noqa: F401
    import armanim.render.video.movie  # noqa: F401
    import armanim.runs.pipeline  # noqa: F401

    return time.perf_counter() - start


def spawn_startup() -> tuple[float, float]:
    """(seconds to start a 2-worker spawn pool and get a first answer, of which importing armanim)."""
    start = time.perf_counter()
    with ProcessPoolExecutor(max_workers=2, mp_context=multiprocessing.get_context("spawn")) as pool:
        imports = max(pool.map(_import_armanim, range(2), chunksize=1))
        first = time.perf_counter() - start
    return first, imports


def cluster_startup() -> tuple[float, float]:
    """(seconds to start a 2-worker LocalCluster and a Client, seconds to close both)."""
    from dask.distributed import Client, LocalCluster

    start = time.perf_counter()
    cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
    client = Client(cluster)
    up = time.perf_counter() - start
    start = time.perf_counter()
    client.close()
    cluster.close()
    return up, time.perf_counter() - start


def one_scene(paths, root: Path) -> float:
    """Seconds for the first scene alone, in this process (solve + video + plot)."""
    return timed_batch(paths[:1], root / "one", jobs=1)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--repeats", type=int, default=2, help="runs of each candidate; the best time counts (default 2)"
    )
    parser.add_argument("--no-dask", action="store_true", help="skip the Dask comparison")
    parser.add_argument(
        "--no-diagnosis",
        action="store_true",
        help="skip the extra pool run with one BLAS thread per worker and the fixed-cost timings",
    )
    args = parser.parse_args()

    try:
        import dask.distributed  # noqa: F401

        have_dask = not args.no_dask
    except ImportError:
        have_dask = False
        print("Dask is not installed (pip install -e '.[dask]'): the Dask comparison is skipped")

    print(f"{os.cpu_count()} CPUs, Python {sys.version.split()[0]}")
    with tempfile.TemporaryDirectory(prefix="armanim-batch-bench-") as tmp:
        root = Path(tmp)
        (root / "scenes").mkdir()
        paths = write_scenes(root / "scenes")
        one_scene(paths, root)  # warm this process (imports, matplotlib font cache) before timing
        candidates = {"jobs 1": {"jobs": 1}, "jobs 2 (pool)": {"jobs": 2}}
        if not args.no_diagnosis:  # what Dask's nanny does for its workers (distributed.nanny.pre-spawn-environ)
            candidates["jobs 2 (pool, 1 BLAS thread)"] = {"jobs": 2, "environ": ONE_BLAS_THREAD}
        if have_dask:
            candidates["jobs 2 (dask local)"] = {"jobs": 2, "scheduler": "local"}
        best = {name: float("inf") for name in candidates}
        reference = None
        for r in range(args.repeats):
            for name, kwargs in candidates.items():
                out = root / f"out-{r}-{len(best)}-{list(candidates).index(name)}"
                t = timed_batch(paths, out, **kwargs)
                best[name] = min(best[name], t)
                print(f"  run {r + 1}: {name:<30} {t:6.2f} s", flush=True)
                got = outputs(out)
                reference = reference or got
                if got != reference:
                    sys.exit(f"batch_bench: {name} gave different trajectory.csv / summary.json bytes")
        n = len(paths)
        per_scene = one_scene(paths, root)
        print()
        print(
            f"16 scenes, 320x180, 15 fps, with video; best of {args.repeats}; outputs byte-identical across candidates"
        )
        for name, t in best.items():
            print(f"  {name:<30} {t:6.2f} s   ({t / n:.2f} s per scene)")
        print(f"  one scene alone in this process: {per_scene:.2f} s")
        ratio = best["jobs 1"] / best["jobs 2 (pool)"]
        verdict = "ok" if ratio >= 1.7 else "MISSED"
        print()
        print(f"jobs 2 / jobs 1 speed-up: {ratio:.2f}x   (target >= 1.7x on 2 cores: {verdict})")
        if have_dask:
            overhead = best["jobs 2 (dask local)"] / best["jobs 2 (pool)"] - 1
            verdict = "ok" if overhead <= 0.15 else "MISSED"
            print(f"Dask LocalCluster overhead over the pool: {100 * overhead:+.1f} %   (target <= 15 %: {verdict})")

        if args.no_diagnosis:
            return
        if "jobs 2 (pool, 1 BLAS thread)" in best:
            print(
                f"  diagnosis: jobs 2 / jobs 1 with one BLAS thread per pool worker: "
                f"{best['jobs 1'] / best['jobs 2 (pool, 1 BLAS thread)']:.2f}x"
            )
        print()
        print("fixed costs inside those times:")
        first, imports = spawn_startup()
        print(
            f"  spawn pool of 2: answers after {first:.2f} s, of which importing the pipeline, renderer and matplotlib "
            f"{imports:.2f} s (armanim.runs.batch itself comes with this script's import in each worker)"
        )
        if have_dask:
            up, down = cluster_startup()
            print(f"  LocalCluster of 2: start + connect {up:.2f} s, close {down:.2f} s")
        ideal = best["jobs 1"] / 2
        print(f"  jobs 2 above the ideal half of jobs 1 ({ideal:.2f} s): {best['jobs 2 (pool)'] - ideal:+.2f} s")


if __name__ == "__main__":
    main()
