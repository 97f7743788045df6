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
        return coal.Capsule(caps.radius[k], length), coal.Transform3s(
            np.stack([x, np.cross(z, x), z], axis=1), (a[k] + b[k]) / 2
        )

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
            numeric[:, j] = (
                self_gaps(forward(arm, up), caps, pairs).d - self_gaps(forward(arm, down), caps, pairs).d
            ) / (2 * h)
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
    folded = np.radians(
        [0.0, 0, 175, 0, 0]
    )  # link 3 back over link 2, link 4 over link 1: a default pose where they touch
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

        expected = (
            "Default"
            if min(gap(home), gap(folded)) < 0.01
            else "Never"
            if min(gap(p) for p in poses[:300]) >= 0.01
            else None
        )
        if (
            expected != "Never"
        ):  # 300 brute-force poses may miss a near pose that 2000 find: "Never" is checked one way only
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
    more = selfcollision.enabled_pairs(
        caps, {**allowed, ("link2", "link5"): "User"}, 0.01, "auto", check=[("link3", "link1")]
    )
    assert ("link1", "link3") in more.names and ("link2", "link5") not in more.names
    assert ("link2", "link5", "User") in more.allowed and all(p[:2] != ("link1", "link3") for p in more.allowed)


def test_bundled_matrices_are_what_the_rules_give():
    import subprocess
    import sys
    from pathlib import Path

    tool = Path(__file__).resolve().parents[2] / "tools" / "self_collision_matrix.py"
    done = subprocess.run([sys.executable, str(tool), "--check"], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr


def random_segments(rng, count: int) -> tuple[np.ndarray, np.ndarray]:
    """``count`` random segments (rows of a-b), with parallel, collinear, crossing, touching and
    zero-length ones among them (the cases the closed form leaves to the box form)."""
    a = rng.normal(size=(count, 3))
    b = a + rng.normal(size=(count, 3)) * rng.uniform(0.0, 1.5, (count, 1))
    a[1], b[1] = a[0] + 0.3, b[0] + 0.3  # parallel to segment 0
    a[2], b[2] = a[0] + 0.5 * (b[0] - a[0]), b[0] + 2.0 * (b[0] - a[0])  # collinear, overlapping 0
    a[3], b[3] = (
        a[0] + 0.5 * (b[0] - a[0]) - 0.5 * (b[4] - a[4]),
        a[0] + 0.5 * (b[0] - a[0]) + 0.5 * (b[4] - a[4]),
    )  # crosses 0
    a[5], b[5] = b[0], b[0] + rng.normal(size=3)  # touches 0 at its end
    b[6] = a[6]  # a point
    return a, b


def test_segment_segment_closed_form_equals_the_box_form():
    # the fast form (Ericson's clamped closed form) and the box form (the capsule obstacles' own,
    # kept for parallel and touching pairs) give the same closest points where those are unique
    from armanim.world import compiled

    rng = np.random.default_rng(53)
    for _ in range(40):
        a, b = random_segments(rng, 24)
        first, second = (np.ascontiguousarray(v) for v in np.triu_indices(24, 1))
        count = len(first)
        fast = [np.empty(count), np.empty(count), np.empty(count), np.empty((count, 3))]
        box = [np.empty(count), np.empty(count), np.empty(count), np.empty((count, 3))]
        compiled.segment_segment_pairs(a, b, first, second, *fast)
        compiled.segment_segment_boxes(a, b, first, second, *box)
        assert np.allclose(fast[2], box[2], rtol=0, atol=1e-12)  # the distance, every pair
        for k, (i, j) in enumerate(zip(first, second)):  # every closest pair of points realises it
            p, q = a[i] + fast[0][k] * (b[i] - a[i]), a[j] + fast[1][k] * (b[j] - a[j])
            assert np.linalg.norm(p - q) == pytest.approx(fast[2][k], abs=1e-12)
        u, v = (b - a)[first], (b - a)[second]
        cross2, lengths2 = (np.cross(u, v) ** 2).sum(axis=1), (u * u).sum(axis=1) * (v * v).sum(axis=1)
        apart = (cross2 > 1e-3 * lengths2) & (box[2] > 1e-6)  # well apart from parallel and from touching
        for out, ref in zip(fast[:2] + fast[3:], box[:2] + box[3:]):
            assert np.allclose(out[apart], ref[apart], rtol=0, atol=1e-9)
        parallel = ~(cross2 > compiled.PARALLEL * lengths2)
        assert parallel.sum() >= 3
        for out, ref in zip(fast, box):  # parallel pairs and points: the box form itself
            assert np.array_equal(out[parallel], ref[parallel])


def test_pair_jacobians_and_the_rows_test_agree_with_the_numpy_point_jacobians():
    # the compiled J_A - J_B, its rows and the filter's test of a step against them, held to
    # the numpy Jacobians of the two closest points (capsule_point_jacobian) on a Panda
    from armanim.arm import kernel
    from armanim.arm.capsules import capsule_point_jacobian
    from armanim.scene import scene_model
    from armanim.scene.convert import scene_to_problem
    from armanim.world.selfdistances import self_jacobians, self_rows_met

    problem = scene_to_problem(scene_model({"version": 1, "arm": {"robot": "panda"}, "goals": [[0.4, 0.0, 0.4]]}))
    caps, pairs, arm = problem.capsules, problem.self_pairs, problem.arm
    rng = np.random.default_rng(8)
    decided = set()
    for _ in range(60):
        pose = kernel.forward(arm, rng.uniform(problem.limits.lower, problem.limits.upper))
        gaps = self_gaps(pose, caps, pairs)
        which = np.arange(len(pairs))
        expected = capsule_point_jacobian(arm, caps, pose, pairs.first, gaps.t) - capsule_point_jacobian(
            arm, caps, pose, pairs.second, gaps.s
        )
        jac = self_jacobians(arm, caps, pose, pairs, gaps, which)
        assert np.array_equal(jac, expected)
        rows = self_rows(arm, caps, pose, pairs, gaps, which)
        assert np.allclose(rows, np.einsum("ka,kan->kn", gaps.normal, expected), rtol=0, atol=1e-15)
        step = rng.normal(0, 0.05, arm.n)
        target, gamma = rng.uniform(-0.2, 0.1), rng.uniform(0.1, 1.0)
        rooms = gamma * (gaps.d - target)
        met = self_rows_met(
            arm, caps, pose, pairs, gaps, target, gamma, problem.pair_lever_rows, step, 1.0 + 1e-9, 1e-12, 1e-12
        )
        assert met == bool(np.all(rows @ step >= -rooms - 1e-12))  # the bound only ever spares rows that hold
        decided.add(met)
    assert decided == {True, False}


def test_one_pose_capsule_ends_equal_a_batchs_bit_for_bit():
    # one pose's ends come from the compiled kernel (once a solve loaded it), a batch's from numpy:
    # the same sums in the same order
    from armanim.arm import kernel
    from armanim.scene import scene_model
    from armanim.scene.convert import scene_to_problem

    rng = np.random.default_rng(2)
    for robot in ("panda", "ur5", "iiwa"):
        problem = scene_to_problem(scene_model({"version": 1, "arm": {"robot": robot}, "goals": [[0.4, 0.0, 0.4]]}))
        phis = rng.uniform(-3.0, 3.0, (50, problem.arm.n))
        batch = forward(problem.arm, phis)
        a, b = capsule_ends(problem.capsules, batch)
        caps = problem.capsules
        for k, phi in enumerate(phis):
            one = forward(problem.arm, phi)
            compiled = kernel.capsule_ends_one(
                caps.link, caps.start, caps.end, caps.joint_segment, one.points, one.frames
            )
            assert all(np.array_equal(x, y[k]) for x, y in zip(compiled, (a, b)))
            assert all(np.array_equal(x, y[k]) for x, y in zip(capsule_ends(caps, one), (a, b)))


def test_pair_rates_by_the_links_twists_are_the_rows_times_the_step():
    # the compiled IK filter tests a step against a pair's row by the links' twists under the
    # step (link_twists, pair_rate), without the row: held to the row times the step (the rows
    # themselves are held to the numpy point Jacobians above) and to the gaps' central differences
    import numba

    from armanim.scene import scene_model
    from armanim.scene.convert import scene_to_problem
    from armanim.world import compiled
    from armanim.world.selfdistances import _pair_inputs

    @numba.njit
    def rates(points, axes, a, b, link, first, second, t, s, normal, x):
        twists = np.empty((axes.shape[0], 6))
        compiled.link_twists(points, axes, x, twists)
        out = np.empty(first.shape[0])
        for p in range(first.shape[0]):
            out[p] = compiled.pair_rate(twists, a, b, link, first, second, t, s, normal, p)
        return out

    rng = np.random.default_rng(40)
    for robot in ("panda", "ur5", "iiwa"):
        problem = scene_to_problem(scene_model({"version": 1, "arm": {"robot": robot}, "goals": [[0.4, 0.0, 0.4]]}))
        caps, pairs, arm = problem.capsules, problem.self_pairs, problem.arm
        checked = 0
        for _ in range(20):
            phi = rng.uniform(problem.limits.lower, problem.limits.upper)
            pose = forward(arm, phi)
            gaps = self_gaps(pose, caps, pairs)
            x = rng.normal(0.0, 0.3, arm.n)
            got = rates(*_pair_inputs(arm, caps, pose, pairs, gaps), gaps.normal, x)
            rows = self_rows(arm, caps, pose, pairs, gaps, np.arange(len(pairs)))
            scale = np.abs(rows) @ np.abs(x)
            assert np.all(np.abs(got - rows @ x) <= 1e-14 * (1.0 + scale) * (1.0 + np.abs(pose.points).max()))
            h = 1e-6
            numeric = (
                self_gaps(forward(arm, phi + h * x), caps, pairs).d
                - self_gaps(forward(arm, phi - h * x), caps, pairs).d
            ) / (2 * h)
            apart = gaps.d > 1e-3  # touching segments have no derivative
            assert np.allclose(got[apart], numeric[apart], rtol=0, atol=1e-6)
            checked += int(apart.sum())
        assert checked >= 20  # every pose's pairs apart, most of them (the UR5 has one pair)
