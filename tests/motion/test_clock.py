"""The clock (issue 34): the fastest motion along a solved path within each joint's speed and
acceleration limits, checked against toppra (TOPP-RA's maintained implementation), scipy's
PCHIP and the limits' own definition on the frames (finite differences)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.interpolate import PchipInterpolator
from toppra_oracle import toppra_trajectory

from armanim.motion.timing.clock import sampled_motion, time_optimal
from armanim.motion.timing.goalmotion import PathSafety, goal_motion, probed_steps, two_sided_bound
from armanim.motion.timing.jointpath import joint_path, pchip_slopes


def _random_path(seed: int, n: int, steps: int, jitter: float) -> np.ndarray:
    rng = np.random.default_rng(seed)
    drift = rng.normal(size=n) * 0.05
    return np.concatenate([np.zeros((1, n)), np.cumsum(drift + rng.normal(size=(steps, n)) * jitter, axis=0)])


def _limits(seed: int, n: int) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed + 1)
    return rng.uniform(0.5, 3.0, n), rng.uniform(2.0, 20.0, n)


def _frame_ratios(start: np.ndarray, phi: np.ndarray, speed, acceleration, fps) -> tuple[float, float]:
    """The largest finite-difference speed and acceleration over their limits, at rest before and after."""
    seq = np.concatenate([start[None], start[None], phi, phi[-1:]])
    v = np.abs(np.diff(seq, axis=0)) * fps / speed
    a = np.abs(np.diff(seq, 2, axis=0)) * fps**2 / acceleration
    return float(v.max()), float(a.max())


@settings(max_examples=40, deadline=None)
@given(
    seed=st.integers(0, 10**6),
    n=st.integers(1, 7),
    steps=st.integers(1, 60),
    jitter=st.sampled_from([0.0, 0.002, 0.02, 0.1]),
    fps=st.sampled_from([7.0, 15.0, 30.0, 60.0]),
)
def test_every_frame_keeps_every_joints_speed_and_acceleration(seed, n, steps, jitter, fps):
    poses = _random_path(seed, n, steps, jitter)
    speed, acceleration = _limits(seed, n)
    motion = goal_motion(poses, np.ones(n, dtype=bool), speed, acceleration, fps)
    v, a = _frame_ratios(poses[0], motion.phi, speed, acceleration, fps)
    assert v <= 1 + 1e-9 and a <= 1 + 1e-9
    np.testing.assert_array_equal(motion.phi[-1], poses[-1])  # ends on the last solved pose, at rest
    assert np.all(motion.velocity[-1] == 0) and motion.duration == pytest.approx(len(motion.phi) / fps)
    # where a frame moves little, its velocity agrees with the frames around it (the clock's own, not a guess)
    central = (motion.phi[2:] - motion.phi[:-2]) * fps / 2
    assert np.all(np.abs(motion.velocity[1:-1] - central) <= acceleration / fps + 1e-9)


@settings(max_examples=20, deadline=None)
@given(seed=st.integers(0, 10**6), n=st.integers(1, 7), steps=st.integers(2, 40))
def test_the_path_passes_every_solved_pose_in_order_and_stays_between_neighbours(seed, n, steps):
    poses = _random_path(seed, n, steps, 0.05)
    path = joint_path(poses, np.ones(n, dtype=bool))
    np.testing.assert_allclose(path.evaluate(path.s), poses[path.frames], atol=1e-12)
    assert np.all(np.diff(path.s) > 0) and path.frames[0] == 0 and path.frames[-1] == steps
    s = np.linspace(0, path.length, 2001)
    q = path.evaluate(s)
    k = np.clip(np.searchsorted(path.s, s, side="right") - 1, 0, len(path.s) - 2)
    low = np.minimum(path.poses[k], path.poses[k + 1]) - 1e-12
    high = np.maximum(path.poses[k], path.poses[k + 1]) + 1e-12
    assert np.all((q >= low) & (q <= high))  # so a path between poses inside the limits stays inside them


def test_the_slopes_are_scipys_pchip():
    poses = _random_path(3, 4, 25, 0.05)
    s = np.concatenate([[0], np.cumsum(np.linalg.norm(np.diff(poses, axis=0), axis=1))])
    expected = PchipInterpolator(s, poses, axis=0).derivative()(s)
    np.testing.assert_allclose(pchip_slopes(s, poses), expected, rtol=1e-10, atol=1e-12)
    path = joint_path(poses, np.ones(4, dtype=bool))
    grid = np.linspace(0, path.length, 777)
    for order in (0, 1, 2):
        oracle = PchipInterpolator(s, poses, axis=0).derivative(order) if order else PchipInterpolator(s, poses, axis=0)
        inside = ~np.isin(grid, s)  # the second derivative jumps at a knot
        np.testing.assert_allclose(path.evaluate(grid, order)[inside], oracle(grid)[inside], rtol=1e-9, atol=1e-9)


def test_an_unlimited_joint_turns_the_short_way_round():
    poses = np.radians([[170.0], [-170.0]])  # 20 degrees through 180, not 340 back through 0
    motion = goal_motion(poses, np.array([False]), np.array([1.0]), np.array([5.0]), 30.0)
    assert np.all(np.abs(motion.phi) >= np.radians(170.0) - 1e-12)
    assert motion.phi[-1, 0] == poses[-1, 0]


def test_a_path_that_does_not_move_takes_no_time():
    motion = goal_motion(np.zeros((5, 3)), np.ones(3, dtype=bool), np.ones(3), np.ones(3), 30.0)
    assert len(motion.phi) == 0 and motion.duration == 0.0


def test_one_radian_at_rest_both_ends_is_the_textbook_profile():
    # speed-limited: accelerate to 1 rad/s in 0.5 s (0.25 rad), cruise 0.5 rad, brake: 1.5 s in all
    law = time_optimal(joint_path(np.array([[0.0], [1.0]]), np.array([True])), np.array([1.0]), np.array([2.0]))
    assert law.duration == pytest.approx(1.5, rel=1e-9)
    # acceleration-limited: bang-bang, 2 sqrt(1 / 2) s
    law = time_optimal(joint_path(np.array([[0.0], [1.0]]), np.array([True])), np.array([10.0]), np.array([2.0]))
    assert law.duration == pytest.approx(2 * np.sqrt(0.5), rel=1e-9)


@pytest.mark.parametrize("seed", range(8))
def test_the_duration_is_toppras_time_optimal_one(seed):
    """Within 2 % of toppra on the same path (8000 grid points), and never more than its own
    discretisation below it: toppra keeps the limits at its grid points only (its time law
    breaks the accelerations between them, measured here), the clock everywhere."""
    n = 1 + seed % 7
    poses = _random_path(seed, n, 10 + 7 * seed, 0.02)
    speed, acceleration = _limits(seed, n)
    path = joint_path(poses, np.ones(n, dtype=bool))
    oracle = toppra_trajectory(path, speed, acceleration)
    t = np.linspace(0, oracle.duration, 100_000)
    oracle_excess = max(1.0, float(np.max(np.abs(oracle(t, 2)) / acceleration)))
    law = time_optimal(path, speed, acceleration)
    motion = sampled_motion(path, law, speed, acceleration, 1000.0)
    assert law.duration <= 1.02 * oracle.duration
    assert motion.duration <= 1.02 * oracle.duration + 1e-3
    assert law.duration >= oracle.duration / np.sqrt(oracle_excess) - 1e-9  # never faster than the limits allow


@settings(max_examples=25, deadline=None)
@given(
    seed=st.integers(0, 10**6),
    n=st.integers(1, 7),
    steps=st.integers(1, 40),
    jitter=st.sampled_from([0.0, 0.002, 0.02]),
    fps=st.sampled_from([15.0, 30.0, 60.0]),
)
def test_with_a_jerk_limit_every_frame_keeps_speed_acceleration_and_jerk(seed, n, steps, jitter, fps):
    poses = _random_path(seed, n, steps, jitter)
    speed, acceleration = _limits(seed, n)
    jerk = np.random.default_rng(seed + 2).uniform(20.0, 500.0, n)
    motion = goal_motion(poses, np.ones(n, dtype=bool), speed, acceleration, fps, jerk=jerk)
    v, a = _frame_ratios(poses[0], motion.phi, speed, acceleration, fps)
    seq = np.concatenate([poses[:1]] * 3 + [motion.phi] + [motion.phi[-1:]] * 2)
    j = float((np.abs(np.diff(seq, 3, axis=0)) * fps**3 / jerk).max())
    assert v <= 1 + 1e-9 and a <= 1 + 1e-9 and j <= 1 + 1e-9
    np.testing.assert_array_equal(motion.phi[-1], poses[-1])


def test_a_jerk_limit_makes_the_motion_no_faster():
    poses = _random_path(5, 3, 20, 0.01)
    speed, acceleration = _limits(5, 3)
    free = goal_motion(poses, np.ones(3, dtype=bool), speed, acceleration, 30.0)
    smooth = goal_motion(poses, np.ones(3, dtype=bool), speed, acceleration, 30.0, jerk=np.full(3, 50.0))
    assert smooth.duration >= free.duration


def test_a_jerk_limited_motion_is_never_faster_than_ruckigs_time_optimal_one():
    """On a straight path one joint's jerk-limited optimum is ruckig's (the maintained
    state-to-state library): the clock may take longer (it smooths the speed-and-acceleration
    optimum over 2 a / j seconds, which costs most where the jerk limit dominates), never less."""
    ruckig = pytest.importorskip("ruckig")
    for distance, v, a, j in ((1.0, 2.0, 5.0, 50.0), (0.3, 1.0, 10.0, 40.0), (2.0, 0.5, 1.0, 1000.0)):
        otg, profile, goal = ruckig.Ruckig(1), ruckig.Trajectory(1), ruckig.InputParameter(1)
        goal.current_position, goal.target_position = [0.0], [distance]
        goal.max_velocity, goal.max_acceleration, goal.max_jerk = [v], [a], [j]
        otg.calculate(goal, profile)
        motion = goal_motion(
            np.array([[0.0], [distance]]), np.array([True]), np.array([v]), np.array([a]), 1000.0, jerk=np.array([j])
        )
        assert profile.duration - 1e-3 <= motion.duration <= 1.5 * profile.duration + 1e-3, (distance, v, a, j)


@settings(max_examples=60, deadline=None)
@given(c0=st.floats(-1, 1), c1=st.floats(-1, 1), reach=st.floats(0, 2))
def test_the_two_sided_bound_is_the_least_clearance_a_lever_allows(c0, c1, reach):
    """Against brute force over where between the ends the pose is: max(c0 - d, c1 - (reach - d))."""
    d = np.linspace(0.0, reach, 20001)
    least = float(np.min(np.maximum(c0 - d, c1 - (reach - d))))
    bound = float(two_sided_bound(np.array([c0]), np.array([c1]), np.array([reach]))[0])
    assert bound <= least + 1e-12
    assert bound >= least - 2 * reach / 20000 - 1e-12


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 10**6), n=st.integers(1, 6), steps=st.integers(2, 30))
def test_a_step_its_probes_certify_keeps_the_floor_everywhere(seed, n, steps):
    """A clearance with lever arms L (|c(q) - c(q')| <= L . |q - q'|): every point of a step
    probed_steps certifies, sampled densely on the smooth path, keeps the floor; a step it finds
    unsafe has a point under it."""
    rng = np.random.default_rng(seed)
    poses = _random_path(seed, n, steps, 0.1)
    lever = rng.uniform(0.1, 1.0, n)
    centre = poses[rng.integers(len(poses))] + rng.normal(size=n) * 0.05

    def clearance(phi):
        return np.abs(phi - centre) @ lever

    floor = float(np.quantile(clearance(poses), 0.3))
    path = joint_path(poses, np.ones(n, dtype=bool))
    safety = PathSafety(clearance, floor, lever, clearance(poses), np.zeros(len(poses) - 1, dtype=bool))
    asked = np.ones(len(path.s) - 1, dtype=bool)
    unsafe, proven = probed_steps(path, safety, asked)
    assert not np.any(unsafe & proven)
    for k in range(len(path.s) - 1):
        dense = clearance(path.evaluate(np.linspace(path.s[k], path.s[k + 1], 400)))
        if proven[k]:
            assert dense.min() >= floor - 1e-12
        if unsafe[k]:
            assert dense.min() < floor


def test_a_joint_that_barely_moves_gives_slopes_without_an_overflow_warning():
    """Found on Python 3.13 (a random draw of the smoothing test): a joint whose steps are a few
    hundred ulps of zero overflowed the harmonic mean's ``w / m`` (a RuntimeWarning on stderr, a
    traceback under ``-W error``); the slope there is 0, as scipy's PCHIP gives."""
    s = np.array([0.0, 1.0, 2.0, 3.0])
    poses = np.array([[0.0, 0.0], [1e-310, 1.0], [3e-310, 1.5], [4e-310, 3.0]])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        slopes = pchip_slopes(s, poses)
    with np.errstate(over="ignore"):  # scipy's own harmonic mean overflows there too
        expected = PchipInterpolator(s, poses, axis=0).derivative()(s)
    np.testing.assert_allclose(slopes, expected, rtol=1e-10, atol=1e-300)
