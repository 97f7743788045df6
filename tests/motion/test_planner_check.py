"""The planner's compiled checks (motion/planning/check.py) against their numpy references:
poses' margins against split_clearances to rounding, and a motion's certificate against
motion_is_free (the same answer; fewer poses, by tighter bounds, whose soundness is checked by forward
kinematics), on the bundled robots and an arm
of links among random spheres, boxes, capsules and a floor, from a fixed grid of seeds."""

from __future__ import annotations

import numpy as np
import pytest

from armanim.arm.capsules import capsule_ends, capsule_lever_rows, next_axis_reach
from armanim.arm.kinematics import forward
from armanim.motion.filter.clearance import split_clearances, within_limits
from armanim.motion.planning.check import CompiledCheck, frame_margins, pair_capsule_rows
from armanim.motion.planning.path import motion_is_free
from armanim.scene import scene_model
from armanim.scene.convert import scene_to_problem
from armanim.world.distances import min_link_clearance
from armanim.world.selfdistances import self_gaps

ARMS = {
    "panda": ({"robot": "panda"}, 0.5),
    "ur5": ({"robot": "ur5"}, 0.5),
    "links": ({"links": [2, 5, 5, 5], "base": [5, 5, 0], "limits": [None, [-100, 100], [-150, 150], [-150, 150]]}, 8.0),
}


def random_problem(arm: str, seed: int):
    """A scene of the arm among a random sphere, box and capsule near its reach, and a floor."""
    spec, reach = ARMS[arm]
    rng = np.random.default_rng(seed)
    base = np.array(spec.get("base", [0, 0, 0]), dtype=float)

    def near() -> list[float]:
        return [float(v) for v in base + rng.uniform([-reach, -reach, 0.1 * reach], [reach, reach, reach])]

    scene = {
        "version": 1,
        "arm": spec,
        "floor": float(base[2]) - 0.01 * reach,
        "obstacles": [
            {"center": near(), "radius": float(rng.uniform(0.05, 0.2) * reach)},
            {
                "box": {
                    "center": near(),
                    "size": [float(v) for v in rng.uniform(0.05, 0.4, 3) * reach],
                    "rpy": [float(v) for v in rng.uniform(-180, 180, 3)],
                }
            },
            {"capsule": {"from": near(), "to": near(), "radius": float(rng.uniform(0.02, 0.1) * reach)}},
        ],
        "goals": [[float(v) for v in base + [0.5 * reach, 0, 0.5 * reach]]],
        "solver": {"clearance": 0.02 * reach},
    }
    return scene_to_problem(scene_model(scene)), rng


def random_poses(problem, rng, count: int) -> np.ndarray:
    lower = np.where(problem.limits.limited, problem.limits.lower, -np.pi)
    upper = np.where(problem.limits.limited, problem.limits.upper, np.pi)
    return lower + rng.random((count, problem.arm.n)) * (upper - lower)


def assert_exact_below_far(compiled: np.ndarray, reference: np.ndarray, far: float, scale: float) -> None:
    """The compiled margins equal the reference where they are below ``far``, and are lower bounds
    of at least ``far`` elsewhere (the bounding spheres' bound where those are ``far`` apart)."""
    tolerance = 1e-12 * scale
    near = compiled < far
    np.testing.assert_allclose(compiled[near], reference[near], rtol=0, atol=tolerance)
    assert np.all(compiled[~near] <= reference[~near] + tolerance)
    assert np.all(reference[~near] >= far - tolerance)


@pytest.mark.parametrize("arm", sorted(ARMS))
@pytest.mark.parametrize("seed", range(4))
def test_margins_equal_the_numpy_clearances_below_far(arm, seed):
    problem, rng = random_problem(arm, seed)
    poses = random_poses(problem, rng, 64)
    check = CompiledCheck.of(problem)
    clear, own = check.margins(poses)
    ref_clear, ref_own = split_clearances(problem, poses)
    scale = ARMS[arm][1]
    assert_exact_below_far(clear, ref_clear, check.far, scale)
    if ref_own is None:
        assert own.shape == (64, 0)
    else:
        assert_exact_below_far(own, ref_own, check.far, scale)


@pytest.mark.parametrize("arm", sorted(ARMS))
def test_frame_margins_are_the_numpy_clearances_and_gaps(arm):
    """What trajectory.csv writes of every frame, compiled: min_link_clearance's clearances and
    self_gaps' gaps (unshifted), exact at every distance (no bound beyond ``far``)."""
    problem, rng = random_problem(arm, 21)
    poses = random_poses(problem, rng, 64)
    clear, gaps = frame_margins(problem, poses)
    pose = forward(problem.arm, poses)
    scale = ARMS[arm][1]
    np.testing.assert_allclose(
        clear, min_link_clearance(pose, problem.obstacles, problem.capsules), rtol=0, atol=1e-12 * scale
    )
    if len(problem.self_pairs):
        np.testing.assert_allclose(
            gaps, self_gaps(pose, problem.capsules, problem.self_pairs).d, rtol=0, atol=1e-12 * scale
        )
        assert gaps.max() > CompiledCheck.of(problem).far  # far pairs too, measured exactly
    else:
        assert gaps.shape == (64, 0)


def test_margins_of_a_spherized_robot_with_cylinders():
    """VAMP's spherized Panda (every capsule a sphere: the point forms) on MotionBenchMaker's first
    box problem (boxes and a cylinder), against the numpy clearances, poses near the shelf's can."""
    from pathlib import Path

    from armanim.scene.loader import scene_from_bytes
    from armanim.scene.moveitscene import RobotSource, moveit_scene

    data = Path(__file__).parent.parent / "data" / "mbm"
    files = sorted(data.glob("*scene*.yaml"))
    requests = sorted(data.glob("*request*.yaml"))
    assert files and requests, data
    out = Path(__file__).parent / "_unused.yaml"  # the import is not written: only its folder is read
    imported = moveit_scene(
        files[0], requests[0], RobotSource(urdf=data / "panda_spherized.urdf", srdf=data / "panda.srdf"), out
    )
    problem = scene_to_problem(scene_from_bytes(imported.text.encode(), out).model)
    assert len(problem.obstacles.cylinders) and np.all(problem.capsules.start == problem.capsules.end)
    check = CompiledCheck.of(problem, closed=True)
    rng = np.random.default_rng(5)
    goal = problem.goals[0].joints
    poses = np.concatenate(
        [problem.home + (goal - problem.home) * rng.random((40, 1)), goal + rng.normal(0, 0.05, (40, problem.arm.n))]
    )
    clear, own = check.margins(poses)
    ref_clear, ref_own = split_clearances(problem, poses)
    assert_exact_below_far(clear, ref_clear, check.far, 1.0)
    assert_exact_below_far(own, ref_own, check.far, 1.0)
    assert (
        np.sum(clear < check.far) > 40 and np.any(own < check.far) and np.any(own >= check.far)
    )  # both sides asked for


@pytest.mark.parametrize("arm", sorted(ARMS))
@pytest.mark.parametrize("closed", [False, True])
def test_motion_certificate_answers_as_motion_is_free(arm, closed):
    """The same answer as the numpy check (the poses checked may differ: far apart, the bounds
    stand in for the exact values), and a motion certified free keeps the floor at 400 poses
    along it by the numpy clearances."""
    answers = set()
    for seed in range(100, 104):
        problem, rng = random_problem(arm, seed)
        check = CompiledCheck.of(problem, closed=closed)
        poses = random_poses(problem, rng, 31)
        floor = problem.solver.clearance
        for a, b in zip(poses[:-1], poses[1:]):
            b = a + rng.choice([0.05, 0.3, 1.0]) * (b - a)  # short, middling and long motions
            free, _ = check.motion_free(a, b, floor)
            assert free == motion_is_free(problem, a, b, floor, closed)[0], (seed, a.tolist(), b.tolist())
            if free:
                along = a + np.linspace(0, 1, 400)[:, None] * (b - a)
                clear, own = split_clearances(problem, along)
                least = clear if own is None else np.minimum(clear, own.min(axis=1))
                assert least.min() >= floor * (1 - problem.tunables.planner.certify_to), (seed, least.min())
            answers.add(free)
    assert answers == {True, False}  # both answers were asked for


def test_a_pose_on_a_limit_is_free_only_with_closed_limits():
    problem, _ = random_problem("panda", 7)
    pose = problem.home.copy()
    pose[1] = problem.limits.lower[1]
    floor = 0.0
    assert within_limits(problem, pose[None], closed=True)[0] and not within_limits(problem, pose[None])[0]
    assert CompiledCheck.of(problem, closed=True).pose_free(pose, floor) == bool(
        split_clearances(problem, pose[None])[0][0] >= floor
    )
    assert not CompiledCheck.of(problem).pose_free(pose, floor)


@pytest.mark.parametrize("arm", sorted(ARMS))
def test_lever_rows_bound_how_far_points_and_gaps_move(arm):
    """Along a straight joint-space step dPhi, no point of capsule i moves more than
    rows[i] . |dPhi| (the chord of its path, by forward kinematics), and no enabled pair's
    gap changes more than its pair row . |dPhi| (by the numpy pair gaps): the bounds the
    certificate's groups use; and each row is at most the arm's lever arms."""
    problem, rng = random_problem(arm, 11)
    caps = problem.capsules
    rows = capsule_lever_rows(problem.arm, caps)
    assert np.all(rows <= problem.lever_arms + 1e-12)
    pair_rows = pair_capsule_rows(
        caps.link, problem.self_pairs.first, problem.self_pairs.second, rows, next_axis_reach(problem.arm, caps)
    )
    assert np.all(pair_rows <= problem.pair_lever_rows + 1e-12)
    tight = 0
    for a in random_poses(problem, rng, 40):
        step = rng.normal(size=problem.arm.n) * rng.choice([1e-3, 0.05, 0.5])
        a_ends, b_ends = (capsule_ends(caps, forward(problem.arm, phi)) for phi in (a, a + step))
        moved = np.maximum(
            np.linalg.norm(b_ends[0] - a_ends[0], axis=-1), np.linalg.norm(b_ends[1] - a_ends[1], axis=-1)
        )
        bound = rows @ np.abs(step)
        assert np.all(moved <= bound + 1e-12)
        tight += np.any(moved > 0.5 * bound)
        if len(problem.self_pairs):
            gaps = [self_gaps(forward(problem.arm, phi), caps, problem.self_pairs).d for phi in (a, a + step)]
            assert np.all(np.abs(gaps[1] - gaps[0]) <= pair_rows @ np.abs(step) + 1e-12)
    assert tight  # the bound is not vacuous: some capsule moves at least half of it
