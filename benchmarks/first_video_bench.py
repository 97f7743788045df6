"""Issue 52, item 5: the time from a vendor URDF to a first video, numba's first compile apart.

For each vendor URDF of :mod:`onboarding_bench` (as their makers ship them, mesh collisions, from
the example-robot-data wheel), a scene is written that names nothing but the URDF and three goals
(the tool points of three random in-limit poses, so every goal is feasible; no collision line, so
``collision: auto`` fits the capsules to the meshes) and ``armanim run`` runs it as a user would,
640 x 360, with a fresh capsule cache (the fit is paid, as on a first run). The run prints its own
time (``time: ... s from the scene and its URDF to the video``, :mod:`armanim.runs.stopwatch`),
which leaves out numba's compiling (printed apart); this script collects those lines, and the CPU
seconds of the whole process (Python's start and imports included: a figure a busy machine does
not inflate as it does wall time).

    python benchmarks/first_video_bench.py --erd /tmp/erd/wheel/cmeel.prefix/share/example-robot-data
"""

from __future__ import annotations

import argparse
import os
import re
import resource
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import yaml

sys.path.insert(0, str(Path(__file__).resolve().parent))
from onboarding_bench import VENDOR  # noqa: E402

from armanim.arm.kinematics import forward  # noqa: E402
from armanim.scene import scene_model, scene_to_problem  # noqa: E402

TIPS = {
    "UR10": "tool0",
    "xArm7": "link_eef",
    "Z1": "gripperStator",
    "SO-101": "gripper_frame_link",
    "Panda (franka_description)": "panda_hand_tcp",
}
"""The link each arm ends at (``arm.tip_link``: a user names it where the URDF has several leaves)."""

TIME = re.compile(
    r"time: ([0-9.]+) s from the scene and its URDF to the video(?: \(numba compiled its code for ([0-9.]+) s)?"
)


def middle_home(arm: dict) -> list[float] | None:
    """``arm.home`` where 0 is outside a joint's limits (the Panda's joint 4): each joint's middle, degrees."""
    problem = scene_to_problem(scene_model({"version": 1, "arm": arm, "goals": [[0.3, 0.0, 0.3]]}), own_pairs=False)
    lim = problem.limits
    if np.all((lim.lower <= 0) & (0 <= lim.upper)):
        return None
    return [round(float(v), 3) for v in np.degrees(np.where(lim.limited, (lim.lower + lim.upper) / 2, 0.0))]


def feasible_goals(arm: dict, count: int = 3, seed: int = 52) -> list[list[float]]:
    """The tool points of ``count`` random poses within the URDF's limits (continuous joints: any angle)."""
    problem = scene_to_problem(scene_model({"version": 1, "arm": arm, "goals": [[0.3, 0.0, 0.3]]}), own_pairs=False)
    rng = np.random.default_rng(seed)
    lower = np.where(problem.limits.limited, problem.limits.lower, -np.pi)
    upper = np.where(problem.limits.limited, problem.limits.upper, np.pi)
    inside = lower + 0.2 * (upper - lower), upper - 0.2 * (upper - lower)
    return [[round(float(v), 4) for v in forward(problem.arm, rng.uniform(*inside)).tip] for _ in range(count)]


def one(name: str, urdf: Path, work: Path) -> tuple[str, str]:
    arm: dict = {"urdf": str(urdf), "tip_link": TIPS[name]}
    home = middle_home(arm)
    if home is not None:
        arm["home"] = home
    scene = {
        "version": 1,
        "name": re.sub(r"[^a-z0-9]+", "-", name.lower()).strip("-"),
        "arm": arm,
        "goals": feasible_goals(arm),
        "render": {"size": [640, 360]},
    }
    path = work / f"{scene['name']}.yaml"
    path.write_text(yaml.safe_dump(scene, sort_keys=False), encoding="utf-8")
    env = dict(
        os.environ, ARMANIM_CACHE_DIR=str(work / f"cache-{scene['name']}")
    )  # a fresh capsule cache: the fit is paid
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    proc = subprocess.run(
        [sys.executable, "-m", "armanim", "run", str(path), "--out", str(work / "out"), "--jobs", "1"],
        capture_output=True,
        text=True,
        env=env,
    )
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (
        after.ru_stime - before.ru_stime
    )  # the whole process, compiling included
    found = TIME.search(proc.stdout + proc.stderr)
    reached = re.search(r"(\d+) of (\d+) goals reached", proc.stdout)
    if proc.returncode not in (0, 1) or found is None:
        return (
            name,
            f"| {name} | failed (exit {proc.returncode}): {(proc.stderr or proc.stdout).strip().splitlines()[-1:]} | | | |",
        )
    compile_s = found.group(2) or "0"
    return (
        name,
        f"| {name} | {found.group(1)} s | {compile_s} s | {cpu:.1f} s | {reached.group(0) if reached else '?'} |",
    )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--erd", type=Path, required=True, help="example-robot-data's share folder (holds robots/)")
    parser.add_argument("--only", action="append", help="this robot alone (repeat for more); default all")
    args = parser.parse_args(argv)
    print("| robot | URDF to video (numba's compiling apart) | numba compiling | CPU of the whole process | goals |")
    print("|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for name, relative in VENDOR.items():
            if args.only and name not in args.only:
                continue
            print(one(name, args.erd / relative, Path(tmp))[1], flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
