"""Self-collision in the pure core: capsule-capsule distances (against coal and brute force),
the pair rows against finite differences, the allowed-collision matrix's rules and the bundled
matrices they give (the scene's fields and SRDF: tests/scene/test_self_collision_fields.py; runs
that keep the pairs apart: tests/motion/test_self_collision_runs.py; the run folder:
tests/runs/test_self_collision_outputs.py)."""

from __future__ import annotations

import numpy as np
import pytest

from armanim.arm.capsules import Capsules, capsule_ends, joint_capsules
from armanim.arm.kinematics import Arm, forward
from armanim.world import selfcollision
from armanim.world.selfdistances import SelfPairs, self_gaps, self_rows


def random_capsules(rng, count: int) -> Capsules:
    """``count`` capsules on one frame (joint 0), random ends and radii."""
    start = rng.normal(size=(count, 3))
    end = start + rng.normal(size=(count, 3)) * rng.uniform(0.0, 1.5, (count, 1))
    return Capsules(np.zeros(count, dtype=int), start, end, rng.uniform(0.01, 0.3, count))


def brute_segment_distance(a0, a1, b0, b1, samples: int = 2001) -> float:
    """The test's own segment-segment distance: the least over a fine grid on one segment of
    the exact point-segment distance to the other."""
    u = np.linspace(0.0, 1.0, samples)[:, None]
    p = a0 + u * (a1 - a0)
    along = b1 - b0
    length2 = along @ along
    s = np.clip(((p - b0) @ along) / length2, 0.0, 1.0) if length2 > 0 else np.zeros(samples)
    return float(np.linalg.norm(p - (b0 + s[:, None] * along), axis=-1).min())


def test_pair_gaps_match_brute_force_and_their_closest_points():
    rng = np.random.default_rng(35)
    caps = random_capsules(rng, 12)
    arm = Arm.from_names([1.0])
    pairs = SelfPairs(*np.triu_indices(12, 1), 0.0)
    pose = forward(arm, np.zeros(1))
    gaps = self_gaps(pose, caps, pairs)
    a, b = capsule_ends(caps, pose)
    for k, (i, j) in enumerate(zip(pairs.first, pairs.second)):
        segment = brute_segment_distance(a[i], b[i], a[j], b[j])
        expected = segment - caps.radius[i] - caps.radius[j]
        assert gaps.d[k] <= expected + 1e-12  # the exact least is at most any sampled one
        assert gaps.d[k] >= expected - 2e-3  # and the grid is fine to 1/2000 of a segment
        p = a[i] + gaps.t[k] * (b[i] - a[i])
        q = a[j] + gaps.s[k] * (b[j] - a[j])
        assert np.linalg.norm(p - q) == pytest.approx(segment + 0.0, abs=2e-3)  # the closest points realise it
        if segment > 1e-6:
            assert np.allclose((p - q) / np.linalg.norm(p - q), gaps.normal[k], atol=1e-6)


def test_pair_gaps_match_coal():
    coal = pytest.importorskip("coal")  # the oracle (the test extra)
    rng = np.random.default_rng(7)
    caps = random_capsules(rng, 10)
    pose = forward(Arm.from_names([1.0]), np.zeros(1))
    pairs = SelfPairs(*np.triu_indices(10, 1), 0.0)
    gaps = self_gaps(pose, caps, pairs)
    a, b = capsule_ends(caps, pose)

    def shape(k):
        axis = b[k] - a[k]
        length = float(np.linalg.norm(axis))
        z = axis / length
        x = np.cross(z, [1.0, 0, 0] if abs(z[0]) < 0.9 else [0, 1.0, 0])
        x /= np.linalg.norm(x)
        return coal.Capsule(caps.radius[k], length), coal.Transform3s(np.stack([x, np.cross(z, x), z], axis=1), (a[k] + b[k]) / 2)

    compared = 0
    for k, (i, j) in enumerate(zip(pairs.first, pairs.second)):
        request, result = coal.DistanceRequest(), coal.DistanceResult()
        request.gjk_tolerance = 1e-13
        distance = coal.distance(*shape(i), *shape(j), request, result)
        if distance > 1e-6:  # coal reports overlaps differently (penetration depth); apart pairs compare exactly
            assert gaps.d[k] == pytest.approx(distance, abs=1e-7)
            compared += 1
        else:
            assert gaps.d[k] <= 1e-6
    assert compared > 20


def test_pair_gaps_batched_equal_one_pose_each():
    arm = Arm.from_names([1.0, 0.8, 0.6, 0.4], axes=["z", "y", "y", "x"])
    caps = joint_capsules(arm, 0.05)
    pairs = SelfPairs([0, 0, 1], [2, 3, 3], 0.01)
    rng = np.random.default_rng(3)
    phis = rng.uniform(-np.pi, np.pi, (20, 4))
    batch = self_gaps(forward(arm, phis), caps, pairs)
    for k, phi in enumerate(phis):
        one = self_gaps(forward(arm, phi), caps, pairs)
        assert np.array_equal(one.d, batch.d[k])
        assert np.array_equal(one.normal, batch.normal[k])


def test_pair_rows_match_finite_differences():
    arm = Arm.from_names([1.0, 0.8, 0.7, 0.5, 0.4], axes=["z", "y", "y", "x", "y"])
    caps = joint_capsules(arm, 0.04)
    pairs = SelfPairs([0, 0, 1, 1, 2], [2, 4, 3, 4, 4], 0.01)
    rng = np.random.default_rng(11)
    checked = 0
    for _ in range(30):
        phi = rng.uniform(-2.5, 2.5, 5)
        pose = forward(arm, phi)
        gaps = self_gaps(pose, caps, pairs)
        rows = self_rows(arm, caps, pose, pairs, gaps, np.arange(len(pairs)))
        h = 1e-6
        numeric = np.empty_like(rows)
        for j in range(5):
            up, down = phi.copy(), phi.copy()
            up[j] += h
            down[j] -= h
            numeric[:, j] = (self_gaps(forward(arm, up), caps, pairs).d - self_gaps(forward(arm, down), caps, pairs).d) / (2 * h)
        apart = gaps.d > 1e-3  # touching segments have no derivative
        assert np.allclose(rows[apart], numeric[apart], atol=1e-5)
        checked += int(apart.sum())
    assert checked > 100


def planar_chain(links=(1.0, 1.0, 1.0, 1.0, 0.3)) -> Arm:
    return Arm.from_names(list(links), axes=["z"] * len(links), direction="x")


def test_matrix_rules_on_a_hand_made_chain():
    arm = planar_chain()
    caps = joint_capsules(arm, 0.05)
    lower, upper = np.radians([-170.0, -170, -170, -170, -5]), np.radians([170.0, 170, 170, 170, 5])
    home = np.radians([0.0, 0, 0, 0, 0])
    folded = np.radians([0.0, 0, 175, 0, 0])  # link 3 back over link 2, link 4 over link 1: a default pose where they touch
    allowed = selfcollision.automatic_matrix(arm, caps, lower, upper, [home, folded], 0.01, samples=2000)
    adjacent = {("link1", "link2"), ("link2", "link3"), ("link3", "link4"), ("link4", "link5")}
    assert {p for p, r in allowed.items() if r == "Adjacent"} == adjacent
    poses = selfcollision.random_poses(lower, upper, 2000)
    kinds = set()
    for a, b in selfcollision.link_pairs(caps):
        if (a, b) in adjacent:
            continue
        i, j = int(a[4:]) - 1, int(b[4:]) - 1  # the brute-force oracle on the joint points
        def gap(phi, i=i, j=j):
            points = forward(arm, phi).points
            return brute_segment_distance(points[i], points[i + 1], points[j], points[j + 1], 401) - 0.1
        expected = "Default" if min(gap(home), gap(folded)) < 0.01 else "Never" if min(gap(p) for p in poses[:300]) >= 0.01 else None
        if expected != "Never":  # 300 brute-force poses may miss a near pose that 2000 find: "Never" is checked one way only
            assert allowed.get((a, b)) == expected, (a, b)
        kinds.add(allowed.get((a, b)))
    assert {"Default", "Never", None} <= kinds  # every rule fired, and some pairs stay checked
    assert ("link1", "link4") in allowed and allowed[("link1", "link4")] == "Default"
    # deterministic: the same arm, the same matrix
    assert allowed == selfcollision.automatic_matrix(arm, caps, lower, upper, [home, folded], 0.01, samples=2000)


def test_allow_and_check_lists_change_the_enabled_pairs():
    arm = planar_chain()
    caps = joint_capsules(arm, 0.05)
    allowed = {("link1", "link2"): "Adjacent", ("link1", "link3"): "Never"}
    base = selfcollision.enabled_pairs(caps, allowed, 0.01, "auto")
    assert ("link1", "link3") not in base.names and ("link1", "link2") not in base.names
    more = selfcollision.enabled_pairs(caps, {**allowed, ("link2", "link5"): "User"}, 0.01, "auto", check=[("link3", "link1")])
    assert ("link1", "link3") in more.names and ("link2", "link5") not in more.names
    assert ("link2", "link5", "User") in more.allowed and all(p[:2] != ("link1", "link3") for p in more.allowed)


def test_bundled_matrices_are_what_the_rules_give():
    import subprocess
    import sys
    from pathlib import Path

    tool = Path(__file__).resolve().parents[2] / "tools" / "self_collision_matrix.py"
    done = subprocess.run([sys.executable, str(tool), "--check"], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
