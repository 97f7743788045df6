"""The self-collision family's scenes (issue 35): Panda, UR5, iiwa and a folding URDF chain, with
goals whose straight line from the previous tool point passes through the body.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from oracles.robots import ROBOT_SOLVER, coal_pair_gaps

from armanim.arm.kinematics import forward
from armanim.scene import scene_model
from armanim.scene.convert import scene_to_problem
from armanim.world.selfdistances import self_gaps

SELF_ROBOTS = ("panda", "ur5", "iiwa", "chain")
"""Bundled robots, and a URDF chain of this file's own (:data:`CHAIN_URDF`): one per scene in turn."""


SELF_GOALS = 3


SELF_DRAWS = 4000  # random poses tried per scene for goals that cross the body


SELF_STREAM = 6


CHAIN_URDF = """<robot name="fold-chain">
  <link name="base"/>
{links}
{joints}
</robot>
"""


def chain_urdf_text(count: int = 6) -> str:
    """A 6-joint chain of 0.3 m cylinders (radius 0.04) whose axes alternate z, y: it folds onto itself."""
    links = "\n".join(
        f'  <link name="c{k}"><collision><origin xyz="0 0 0.15"/><geometry><cylinder radius="0.04" '
        f'length="0.3"/></geometry></collision></link>'
        for k in range(count)
    )
    joints = "\n".join(
        f'  <joint name="q{k}" type="revolute"><parent link="{"base" if k == 0 else f"c{k - 1}"}"/>'
        f'<child link="c{k}"/><origin xyz="0 0 {0.05 if k == 0 else 0.3}"/>'
        f'<axis xyz="{"0 0 1" if k % 2 == 0 else "0 1 0"}"/>'
        f'<limit lower="-2.8" upper="2.8" effort="1" velocity="1"/></joint>'
        for k in range(count)
    )
    return CHAIN_URDF.format(links=links, joints=joints)


def self_scene_problem(robot: str, folder: Path, goals: list, self_collision="auto"):
    """The problem of a self-collision scene: a bundled robot or the chain, no obstacles, the bundled
    robot scenes' solver settings (self_clearance: clearance / 2 = 0.01 m)."""
    arm = {"robot": robot} if robot != "chain" else {"urdf": str(folder / "chain.urdf"), "home": [0, 30, 60, 0, 30, 0]}
    scene = {
        "version": 1,
        "arm": {**arm, "self_collision": self_collision},
        "goals": goals,
        "solver": dict(ROBOT_SOLVER),
    }
    return scene_to_problem(scene_model(scene, folder))


SELF_THROUGH = 0.15
"""Metres: a goal's straight line from the previous tool point (home's first) passes this near the base's
vertical axis, through the robot's body."""


def segment_axis_distance(a: np.ndarray, b: np.ndarray, base: np.ndarray) -> float:
    """Least horizontal distance of the segment a-b (above z = base + 0.05) to the vertical line through ``base``."""
    t = np.linspace(0.0, 1.0, 101)[:, None]
    points = a + t * (b - a)
    high = points[:, 2] > base[2] + 0.05
    if not high.any():
        return np.inf
    return float(np.linalg.norm(points[high, :2] - base[:2], axis=1).min())


def draw_self_goals(problem, rng: np.random.Generator) -> tuple[list, int]:
    """Goal poses whose tool point lies across the body from the previous one (home's first): the
    straight line between them passes within :data:`SELF_THROUGH` of the base's vertical axis,
    so the arm must swing round or fold past itself; each pose free (every enabled pair at least
    self_clearance + 0.2 x clearance apart by coal, the planner's room to settle; the tool 0.1 m
    above the base): feasible by construction. Returns (poses, draws tried)."""
    lim = problem.limits
    lo, hi = np.maximum(lim.lower, -np.pi) + np.radians(10), np.minimum(lim.upper, np.pi) - np.radians(10)
    keep = problem.self_pairs.clearance + 0.2 * problem.solver.clearance
    base = problem.arm.base
    found, tried = [], 0
    previous = forward(problem.arm, problem.home).tip
    while len(found) < SELF_GOALS and tried < SELF_DRAWS:
        tried += 1
        pose = lo + (hi - lo) * rng.random(problem.arm.n)
        tip = forward(problem.arm, pose).tip
        if tip[2] < base[2] + 0.1 or segment_axis_distance(previous, tip, base) > SELF_THROUGH:
            continue
        if self_gaps(forward(problem.arm, pose), problem.capsules, problem.self_pairs).least < keep:
            continue
        if coal_pair_gaps(problem, pose)[0] >= keep + 1e-6:
            found.append(pose)
            previous = tip
    return found, tried
