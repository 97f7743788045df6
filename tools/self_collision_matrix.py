"""Regenerate the bundled robots' allowed-collision matrices (maintainers only).

    python tools/self_collision_matrix.py            # writes src/armanim/arm/robots/<robot>/self-collision.yaml
    python tools/self_collision_matrix.py --check    # exit 1 if a committed file differs

Each file lists every link pair never checked and MoveIt's reason for it (Adjacent, Default,
Always, Never: :mod:`armanim.world.selfcollision`), computed at :data:`CLEARANCE` metres, so that it serves
every scene whose ``solver.self_clearance`` is at most that; runs then never sample.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from armanim.arm.kinematics import joints_shown
from armanim.scene import scene_model
from armanim.scene.convert import scene_to_problem
from armanim.scene.robots import ROBOTS, SELF_COLLISION_FILE
from armanim.world import selfcollision

CLEARANCE = 0.02
"""Metres: how near counts as touching for the committed matrices (a scene's self_clearance up to this uses them)."""
ROBOTS_DIR = Path(__file__).resolve().parent.parent / "src" / "armanim" / "arm" / "robots"


def matrix_text(robot: str) -> str:
    """The committed file of bundled robot ``robot``."""
    scene = scene_model({"version": 1, "arm": {"robot": robot, "self_collision": "off"}, "goals": [[0.5, 0.0, 0.5]]})
    problem = scene_to_problem(scene)
    lim = problem.limits
    allowed = selfcollision.automatic_matrix(
        problem.arm, problem.capsules, lim.lower, lim.upper, [problem.home], CLEARANCE
    )
    order = {pair: k for k, pair in enumerate(selfcollision.link_pairs(problem.capsules))}
    lines = [
        f"# {robot}'s allowed-collision matrix: written by tools/self_collision_matrix.py, do not edit.",
        "# Every link pair listed is never checked (MoveIt's reasons: Adjacent, Default, Always, Never);",
        "# every other pair of links keeps solver.self_clearance. Computed at clearance (metres) from",
        "# the robot's home and `samples` random in-limit poses drawn from `seed`.",
        f"robot: {robot}",
        f"clearance: {CLEARANCE}",
        f"samples: {selfcollision.NEVER_SAMPLES}",
        f"seed: {selfcollision.NEVER_SEED}",
        f"home_deg: [{', '.join(f'{v:g}' for v in joints_shown(problem.home, problem.arm.prismatic).round(6))}]",
        "allowed:",
    ]
    lines += [
        f"  - [{a}, {b}, {reason}]" for (a, b), reason in sorted(allowed.items(), key=lambda item: order[item[0]])
    ]
    return "\n".join(lines) + "\n"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="compare with the committed files instead of writing them")
    args = parser.parse_args()
    stale = []
    for robot in ROBOTS:
        path = ROBOTS_DIR / robot / SELF_COLLISION_FILE
        text = matrix_text(robot)
        if args.check:
            if not path.exists() or path.read_text(encoding="utf-8") != text:
                stale.append(str(path))
        else:
            path.write_text(text, encoding="utf-8")
            print(f"wrote {path}")
    for path in stale:
        print(f"{path} differs from what the rules give (run tools/self_collision_matrix.py)", file=sys.stderr)
    return 1 if stale else 0


if __name__ == "__main__":
    sys.exit(main())
