"""What a robot scene's video costs: ``armanim run SCENE`` against ``armanim run SCENE --no-video``.

Run: ``python benchmarks/video_bench.py`` (a few minutes on two cores; ``--scenes`` to choose,
``--repeat N`` for more pairs, ``--against SRC`` to measure another source tree, e.g. main's
``git archive main src | tar -x -C /tmp/main``, in the same run: ``--against /tmp/main/src``;
``--render``: ``armanim render`` of one solved run, the trees alternated, for the video's own CPU
without the solve). Issue 55's target: a robot scene with video, at its own size and
with its default jobs, at most **2x** its ``--no-video`` time.

Each scene is run as the whole command a user types, in a fresh process, alternately without
and with video (``--repeat`` pairs), so a change in the machine's load hits both alike; the
ratio is the mean with-video time over the mean ``--no-video`` time of the same run. The load
average is printed before and after, since the machine may be shared. Beside the wall time, the
CPU time of the process and its children (workers, ffmpeg) says how much work the video is.
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SCENES = ("scenes/panda-shelf.yaml", "scenes/ur5-pen.yaml")


def whole_process(cmd: list[str], src: str | None = None) -> tuple[float, float]:
    """(wall seconds, CPU seconds of the process and everything it started) of a fresh process;
    ``src``: the armanim sources it imports (default: the installed ones)."""
    env = dict(os.environ, PYTHONPATH=src) if src else None
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    subprocess.run(cmd, check=True, capture_output=True, text=True, cwd=ROOT, env=env)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu


def load() -> str:
    return " ".join(f"{x:.2f}" for x in os.getloadavg())


def measure(scene: str, out: Path, repeat: int, src: str | None) -> tuple[list, list]:
    """``repeat`` pairs of (wall, CPU) of the scene without and with video, after one untimed warm-up."""
    base = [sys.executable, "-m", "armanim", "run", scene, "--out", str(out), "--quiet"]
    whole_process([*base, "--no-video"], src)  # numba's cache loaded (or compiled) once, not timed
    plain, video = [], []
    for _ in range(repeat):
        plain.append(whole_process([*base, "--no-video"], src))
        video.append(whole_process(base, src))
    return plain, video


def rerender(scene: str, out: Path, repeat: int, srcs: dict[str, str | None]) -> dict[str, list]:
    """(wall, CPU) of ``armanim render RUN --out DIR`` of one solved run of ``scene``, each tree in
    ``srcs`` in turn, ``repeat`` rounds: the video, plot, poster and their start-up, without the solve."""
    base = [sys.executable, "-m", "armanim", "run", scene, "--out", str(out), "--quiet", "--no-video"]
    whole_process(base, next(iter(srcs.values())))
    run = out / Path(scene).stem
    times: dict[str, list] = {name: [] for name in srcs}
    for name, src in srcs.items():  # an untimed render each: numba's cache loaded (or compiled) once
        whole_process([sys.executable, "-m", "armanim", "render", str(run), "--out", str(out / f"warm-{name}")], src)
    for k in range(repeat):
        for name, src in srcs.items():
            target = out / f"render-{name}-{k}"
            times[name].append(
                whole_process([sys.executable, "-m", "armanim", "render", str(run), "--out", str(target)], src)
            )
    return times


def report(name: str, plain: list, video: list) -> float:
    mean = lambda xs, i: sum(x[i] for x in xs) / len(xs)  # noqa: E731
    ratio = mean(video, 0) / mean(plain, 0)
    print(
        f"  {name:8s} --no-video {mean(plain, 0):6.2f} s ({mean(plain, 1):6.2f} s CPU), with video {mean(video, 0):6.2f} s "
        f"({mean(video, 1):6.2f} s CPU): {ratio:4.2f}x  (target <= 2x; walls "
        f"{', '.join(f'{w:.1f}' for w, _ in plain)} / {', '.join(f'{w:.1f}' for w, _ in video)})"
    )
    return ratio


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", nargs="+", default=list(SCENES))
    parser.add_argument("--repeat", type=int, default=2, help="pairs of runs per scene (default 2)")
    parser.add_argument("--against", help="another armanim source folder (its src/) measured the same way")
    parser.add_argument(
        "--render",
        action="store_true",
        help="time `armanim render` of one solved run instead (the video's own cost), alternating the trees",
    )
    args = parser.parse_args()
    print(f"load average before: {load()} ({os.cpu_count()} cores)")
    with tempfile.TemporaryDirectory() as tmp:
        if args.render:
            srcs = ({"against": args.against} if args.against else {}) | {"this": None}
            for scene in args.scenes:
                print(f"{scene}: armanim render of one run")
                for name, xs in rerender(scene, Path(tmp) / Path(scene).stem, args.repeat, srcs).items():
                    print(
                        f"  {name:8s} CPU {', '.join(f'{c:.2f}' for _, c in xs)} s (mean {sum(c for _, c in xs) / len(xs):.2f}),"
                        f" wall {', '.join(f'{w:.1f}' for w, _ in xs)} s"
                    )
            print(f"load average after: {load()}")
            return
        for scene in args.scenes:
            print(f"{scene}:")
            if args.against:
                report("against", *measure(scene, Path(tmp) / "against", args.repeat, args.against))
            report("this", *measure(scene, Path(tmp) / "this", args.repeat, None))
    print(f"load average after: {load()}")


if __name__ == "__main__":
    main()
