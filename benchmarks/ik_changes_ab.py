"""Issue 40's changes to ``armanim ik``, before against after in one process:

    python benchmarks/ik_changes_ab.py [--targets 60] [--compiled] [--self-collision off]

Per target, interleaved (the order alternating), the same ``solve_pose`` with the changes on, and
switched off from outside: the compiled FK in ``arm_state`` (the numpy chain instead), ``pinv``'s
stacked pose task (the task priority instead), the filter's fast path and the compiled attempt
(:mod:`armanim.motion.solvers.compiled`, the numpy steps instead). ``--compiled``: only the
compiled attempt is switched (the numpy steps with the other changes on, against the compiled
attempt). The rotation-log memo and the solving problem's memo cannot be switched off from
outside and are on in both. Panda 6-D targets
from home (the tool frames of random poses 0.05 rad inside the limits) and the notes' arm's
position targets from the straight pose (self-collision as the scene's default). Printed: median
per solve, converged solves, time per step (over all solves), after / before.
"""

from __future__ import annotations

import argparse
import gc
import statistics
import time

import numpy as np

import armanim.motion.filter.barrier as barrier
import armanim.motion.ik as ik
import armanim.motion.solvers.linear as linear
from armanim.arm import kernel, kinematics
from armanim.arm.kinematics import forward, tool_rotation
from armanim.motion.ik import solve_pose
from armanim.motion.orientation import Orientation
from armanim.scene import scene_model, scene_to_problem

ON = (kernel.forward, linear.stacks_the_pose_task, barrier.clearly_allowed, ik._runs_compiled)
ONLY_COMPILED = False


def switch(on: bool) -> None:
    ik._runs_compiled = ON[3] if on else (lambda problem, method: False)
    if ONLY_COMPILED:
        return
    kernel.forward = ON[0] if on else kinematics.forward
    linear.stacks_the_pose_task = ON[1] if on else (lambda problem, orientation: False)
    barrier.clearly_allowed = ON[2] if on else (lambda *args: False)


def compare(name: str, problem, cases: list) -> None:
    runs: dict[bool, list] = {True: [], False: []}
    for k, case in enumerate(cases):
        for on in (True, False) if k % 2 else (False, True):
            switch(on)
            gc.disable()
            start = time.perf_counter()
            solution = solve_pose(problem, *case)
            spent = time.perf_counter() - start
            gc.enable()
            runs[on].append((spent, solution.steps, solution.status == "converged"))
    switch(True)
    (before, after) = (runs[False], runs[True])
    med = [statistics.median(r[0] for r in side) for side in (before, after)]
    step = [sum(r[0] for r in side) / max(1, sum(r[1] for r in side)) for side in (before, after)]
    done = [sum(r[2] for r in side) for side in (before, after)]
    print(
        f"{name:24s} before {med[0] * 1e3:8.2f} ms ({done[0]}/{len(before)}, {step[0] * 1e6:5.0f} us/step)   "
        f"after {med[1] * 1e3:8.2f} ms ({done[1]}/{len(after)}, {step[1] * 1e6:5.0f} us/step)   "
        f"after/before: median {med[1] / med[0]:.2f}, per step {step[1] / step[0]:.2f}"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--targets", type=int, default=60)
    parser.add_argument("--compiled", action="store_true", help="switch only the compiled attempt")
    parser.add_argument("--self-collision", default="auto", help="the Panda's arm.self_collision (auto, off)")
    args = parser.parse_args()
    global ONLY_COMPILED
    ONLY_COMPILED = args.compiled
    count = args.targets
    rng = np.random.default_rng(0)
    for method in ("pinv", "dls"):
        panda = scene_to_problem(
            scene_model(
                {
                    "version": 1,
                    "arm": {"robot": "panda", "self_collision": args.self_collision},
                    "goals": [[0.3, 0, 0.4]],
                    "solver": {"method": method, "tolerance": 0.001, "orientation_tolerance": 1},
                }
            )
        )
        source = rng.uniform(panda.limits.lower + 0.05, panda.limits.upper - 0.05, (count, panda.arm.n))
        pose = forward(panda.arm, source)
        rotations = tool_rotation(panda.arm, pose)
        compare(
            f"Panda 6-D {method}",
            panda,
            [(pose.tip[k], panda.home, 2000, Orientation(rotation=rotations[k])) for k in range(count)],
        )
        notes = scene_to_problem(
            scene_model(
                {
                    "version": 1,
                    "arm": {
                        "links": [2, 5, 5, 5],
                        "base": [5, 5, 0],
                        "limits": [None, [-100, 100], [-150, 150], [-150, 150]],
                    },
                    "goals": [[8, 8, 8]],
                    "solver": {"method": method, "tolerance": 0.001},
                }
            )
        )
        tips = forward(notes.arm, rng.uniform(-1.2, 1.2, (2 * count, 4))).tip
        compare(f"notes' arm position {method}", notes, [(tip, np.zeros(4), 2000) for tip in tips])


if __name__ == "__main__":
    main()
