"""A blended sequence's path shortened and smoothed (:mod:`armanim.motion.timing.smoothing`), checked in a
plane of two joints among discs, where the clearance is known exactly: every step the smoothing
calls certified keeps the floor everywhere on the clock's path through it (evaluated densely, the
discs' exact distances), the kept poses stay (ends exact, each via's curve within its test), and the
path never gets longer (a shortcut is a chord, a corner's curve lies inside its triangle)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from armanim.motion.timing.jointpath import joint_path
from armanim.motion.timing.smoothing import Certifier, certified_samples, line, smoothed_poses

FLOOR = 0.05


def disc_clearance(centers: np.ndarray, radii: np.ndarray):
    """(k, 2) poses -> (k,) the distance to the nearest disc (inf without discs): 1-Lipschitz in the
    Euclidean norm, so within the lever-arm bound of 1 a joint (|dq|_2 <= |dq|_1)."""

    def clearance(poses: np.ndarray) -> np.ndarray:
        poses = np.atleast_2d(poses)
        if not len(centers):
            return np.full(len(poses), np.inf)
        return (np.linalg.norm(poses[:, None] - centers[None], axis=2) - radii).min(axis=1)

    return clearance


def polyline_length(poses: np.ndarray) -> float:
    return float(np.linalg.norm(np.diff(poses, axis=0), axis=1).sum())


@st.composite
def walks_among_discs(draw):
    """A wandering path of solved poses in a plane of two joints, discs it keeps clear of, and the poses kept."""
    m = draw(st.integers(4, 30))
    steps = np.array(
        draw(st.lists(st.tuples(st.floats(-0.3, 0.3), st.floats(-0.3, 0.3)), min_size=m - 1, max_size=m - 1))
    )
    flat = np.concatenate([np.zeros((1, 2)), np.cumsum(steps, axis=0)])
    discs = draw(st.lists(st.tuples(st.floats(-2, 2), st.floats(-2, 2), st.floats(0.05, 0.6)), max_size=5))
    fine = np.concatenate([a + np.linspace(0, 1, 9)[:, None] * (b - a) for a, b in zip(flat[:-1], flat[1:])])
    kept_discs = [d for d in discs if np.linalg.norm(fine - d[:2], axis=1).min() - d[2] > FLOOR + 0.01]
    centers = np.array([d[:2] for d in kept_discs]).reshape(-1, 2)
    radii = np.array([d[2] for d in kept_discs])
    inner = sorted(draw(st.sets(st.integers(1, m - 2), max_size=3)))
    return (
        flat,
        centers,
        radii,
        [0, *inner, m - 1],
        draw(st.lists(st.booleans(), min_size=len(inner), max_size=len(inner))),
    )


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(walks_among_discs())
@example(
    (
        np.array([[0.0, 0.0], [0.3, 0.0], [0.6, 0.0], [0.6, 0.3], [0.6, 0.6]]),
        np.array([[0.2, 0.45]]),
        np.array([0.2]),
        [0, 4],
        [],
    )
)  # an L round a disc inside its corner: the curve must stay tight
@example(
    (
        np.array([[0.0, 0.0], [0.25, 0.0], [0.5, 0.0], [0.25, 0.0], [0.0, 0.0], [1e-05, 0.0]]),
        np.zeros((0, 2)),
        np.zeros(0),
        [0, 1, 5],
        [False],
    )
)  # found: a segment's end was a + 1 * (b - a), not b (the last pose moved by an ulp)
def test_smoothed_paths_keep_the_floor_the_kept_poses_and_get_no_longer(case):
    flat, centers, radii, keep, rounded = case
    measure = disc_clearance(centers, radii)
    cert = Certifier(measure, np.ones(2), FLOOR)
    clear = measure(flat)
    certified = np.zeros(len(flat) - 1, dtype=bool)  # the solved steps: never trusted here
    reach = 0.3
    near = {
        k: (lambda poses, k=k: np.abs(poses - flat[k]).max(axis=1) <= reach) if r else None
        for k, r in zip(keep[1:-1], rounded)
    }
    out = smoothed_poses(flat, clear, certified, keep, cert, near)

    np.testing.assert_array_equal(out.poses[0], flat[0])
    np.testing.assert_array_equal(out.poses[-1], flat[-1])
    assert polyline_length(out.poses) <= polyline_length(flat) + 1e-9
    assert np.all(np.diff(out.position) >= 0) and out.position[0] == 0 and out.position[-1] == len(flat) - 1
    np.testing.assert_allclose(out.clearance, measure(out.poses))
    for k in keep[1:-1]:  # each kept pose: passed exactly, or its curve within the via's test
        (first, last), curve = out.corners[k]
        if curve:
            assert near[k] is not None and np.abs(out.poses[first : last + 1] - flat[k]).max(axis=1).min() <= reach
        else:
            np.testing.assert_array_equal(out.poses[first], flat[k])
    path = joint_path(out.poses, np.array([True, True]))
    for q in range(len(path.s) - 1):  # the clock's path on each certified step (repeated poses dropped), densely
        if out.certified[path.frames[q] : path.frames[q + 1]].all():
            at = path.s[q] + np.linspace(0.0, 1.0, 41) * (path.s[q + 1] - path.s[q])
            assert measure(path.evaluate(at)).min() >= FLOOR - 1e-12, q


def test_a_segment_through_a_disc_is_refused_and_one_past_it_is_certified():
    measure = disc_clearance(np.array([[0.5, 0.0]]), np.array([0.2]))
    cert = Certifier(measure, np.ones(2), FLOOR)
    a, b = np.array([0.0, 0.0]), np.array([1.0, 0.0])
    assert certified_samples(line(a, b), float(measure(a)[0]), float(measure(b)[0]), cert) is None
    c = np.array([1.0, 0.6])
    done = certified_samples(line(a, c), float(measure(a)[0]), float(measure(c)[0]), cert)
    assert done is not None
    t, poses, clearance = done
    assert t[0] == 0 and t[-1] == 1 and np.all(np.diff(t) > 0) and len(t) > 2
    np.testing.assert_allclose(clearance, measure(poses))


def test_a_path_of_one_or_two_poses_is_kept_as_it_is():
    """Found by the blended joint goals' property: a goal already reached is a part of one pose."""
    cert = Certifier(disc_clearance(np.zeros((0, 2)), np.zeros(0)), np.ones(2), FLOOR)
    for flat in (np.zeros((1, 2)), np.array([[0.0, 0.0], [0.5, 0.1]])):
        out = smoothed_poses(
            flat, np.full(len(flat), np.inf), np.ones(len(flat) - 1, dtype=bool), [0, len(flat) - 1], cert, {}
        )
        np.testing.assert_array_equal(out.poses, flat)
        assert out.position.tolist() == list(range(len(flat)))


def test_an_unlimited_joint_s_long_turn_stays_the_long_way_round_on_the_clock():
    """Found by blend_bench (a random arm's base turning 5 rad in one shortcut, free of obstacles): the
    clock takes an unlimited joint's turn between two poses the short way round, so no two poses it
    is given may be pi apart; the path it makes of the wrapped poses turns the whole 5 rad."""
    from armanim.arm.geometry import wrap_angle

    flat = np.array([[0.0, 0.0], [2.5, 0.1], [5.0, 0.0]])
    cert = Certifier(disc_clearance(np.zeros((0, 2)), np.zeros(0)), np.ones(2), FLOOR)
    out = smoothed_poses(flat, np.full(3, np.inf), np.ones(2, dtype=bool), [0, 2], cert, {})
    assert np.abs(np.diff(out.poses, axis=0)).max() <= 1.0 + 1e-9
    path = joint_path(wrap_angle(out.poses), np.array([False, False]))
    assert path.poses[-1, 0] == pytest.approx(5.0) and path.length == pytest.approx(5.0)
