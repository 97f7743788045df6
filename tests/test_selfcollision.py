"""Self-collision: capsule-capsule distances (against coal and brute force), the pair rows
against finite differences, the allowed-collision matrix's rules, SRDF parsing (against
pinocchio), and runs that keep every enabled pair apart."""

from __future__ import annotations

import numpy as np
import pytest

from armanim.arm.capsules import Capsules, capsule_ends, joint_capsules
from armanim.arm.kinematics import Arm, forward
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


# --- the allowed-collision matrix ---------------------------------------------------------

from armanim.errors import SceneError  # noqa: E402
from armanim.scene.convert import scene_to_problem  # noqa: E402
from armanim.scene.loader import load_scene  # noqa: E402
from armanim.world import selfcollision  # noqa: E402


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


def scene_dict(**arm):
    return {"version": 1, "arm": {"links": [1.0, 1.0, 1.0, 1.0], "axes": ["z", "z", "z", "z"], "direction": "x", **arm},
            "goals": [[2.0, 1.0, 0.0]], "solver": {"clearance": 0.02}}


def write_scene(tmp_path, data) -> str:
    import yaml

    path = tmp_path / "scene.yaml"
    path.write_text(yaml.safe_dump(data))
    return str(path)


def test_scene_field_forms(tmp_path):
    off = scene_to_problem(load_scene(write_scene(tmp_path, scene_dict(self_collision=False))).model)
    assert len(off.self_pairs) == 0
    auto = scene_to_problem(load_scene(write_scene(tmp_path, scene_dict())).model)
    assert auto.self_pairs.clearance == pytest.approx(0.01) and ("link1", "link3") in auto.self_pairs.names
    listed = scene_to_problem(load_scene(write_scene(tmp_path, scene_dict(
        self_collision={"auto": True, "allow": [["link1", "link3"]]}))).model)
    assert ("link1", "link3") not in listed.self_pairs.names and ("link1", "link3", "User") in listed.self_pairs.allowed
    checked = scene_to_problem(load_scene(write_scene(tmp_path, scene_dict(
        self_collision={"auto": True, "allow": [["link1", "link3"]], "check": [["link3", "link1"]]}))).model)
    assert ("link1", "link3") in checked.self_pairs.names  # check wins over allow
    # checking an adjacent pair, which touches at its joint: the home pose is an error naming the pair
    with pytest.raises(SceneError, match=r"arm: the home pose has link1 and link2 overlapping \(gap -0.5"):
        load_scene(write_scene(tmp_path, scene_dict(self_collision={"auto": True, "check": [["link1", "link2"]]})))


def test_unknown_link_names_are_scene_errors(tmp_path):
    with pytest.raises(SceneError, match=r"self_collision.allow\[0\] names 'link9'"):
        load_scene(write_scene(tmp_path, scene_dict(self_collision={"auto": True, "allow": [["link1", "link9"]]})))
    (tmp_path / "arm.srdf").write_text('<robot name="r">\n<disable_collisions link1="link1" link2="link3"/>\n'
                                       '<disable_collisions link1="link1" link2="nope" reason="Never"/>\n</robot>\n')
    with pytest.raises(SceneError) as err:
        load_scene(write_scene(tmp_path, scene_dict(self_collision={"srdf": "arm.srdf"})))
    assert f"{tmp_path / 'arm.srdf'}:3:" in str(err.value) and "'nope' is not a link" in str(err.value)
    (tmp_path / "arm.srdf").write_text('<!DOCTYPE robot [<!ENTITY a "b">]><robot/>')
    with pytest.raises(SceneError, match="DTD"):
        load_scene(write_scene(tmp_path, scene_dict(self_collision={"srdf": "arm.srdf"})))


CHAIN_URDF = """<robot name="chain">
  <link name="base"/>
{links}
{joints}
</robot>
"""


def chain_urdf(count: int = 5) -> str:
    links = "\n".join(
        f'  <link name="l{k}"><collision><origin xyz="0 0 0.2"/><geometry><cylinder radius="0.04" length="0.4"/></geometry></collision></link>'
        for k in range(count))
    joints = "\n".join(
        f'  <joint name="j{k}" type="revolute"><parent link="{"base" if k == 0 else f"l{k - 1}"}"/><child link="l{k}"/>'
        f'<origin xyz="0 0 {0.0 if k == 0 else 0.4}"/><axis xyz="{"0 0 1" if k % 2 == 0 else "0 1 0"}"/>'
        f'<limit lower="-2.9" upper="2.9" effort="1" velocity="1"/></joint>'
        for k in range(count))
    return CHAIN_URDF.format(links=links, joints=joints)


def test_srdf_pairs_match_pinocchio(tmp_path):
    pin = pytest.importorskip("pinocchio")
    (tmp_path / "chain.urdf").write_text(chain_urdf())
    (tmp_path / "chain.srdf").write_text('<?xml version="1.0"?>\n<robot name="chain">\n'
                                         '  <group name="arm"><chain base_link="base" tip_link="l4"/></group>\n'
                                         '  <disable_collisions link1="l0" link2="l1" reason="Adjacent"/>\n'
                                         '  <disable_collisions link1="l1" link2="l2" reason="Adjacent"/>\n'
                                         '  <disable_collisions link1="l2" link2="l3" reason="Adjacent"/>\n'
                                         '  <disable_collisions link1="l2" link2="l0" reason="Never"/>\n'
                                         '  <disable_collisions link1="l3" link2="l4"/>\n'
                                         '  <disable_collisions link1="base" link2="l4" reason="Never"/>\n</robot>\n')
    scene = {"version": 1, "arm": {"urdf": "chain.urdf", "self_collision": {"srdf": "chain.srdf"}}, "goals": [[0.3, 0.0, 0.8]]}
    problem = scene_to_problem(load_scene(write_scene(tmp_path, scene)).model)
    ours = {frozenset(p) for p in problem.self_pairs.names}
    model = pin.buildModelFromUrdf(str(tmp_path / "chain.urdf"))
    geom = pin.buildGeomFromUrdf(model, str(tmp_path / "chain.urdf"), pin.GeometryType.COLLISION)
    geom.addAllCollisionPairs()
    pin.removeCollisionPairs(model, geom, str(tmp_path / "chain.srdf"))
    link = [model.frames[o.parentFrame].name for o in geom.geometryObjects]
    theirs = {frozenset((link[p.first], link[p.second])) for p in geom.collisionPairs}
    assert ours == theirs
    assert frozenset(("l0", "l2")) not in ours and frozenset(("l0", "l3")) in ours
    assert ("l2", "l0", "Never") in problem.self_pairs.allowed and ("l3", "l4", "SRDF") in problem.self_pairs.allowed


def test_bundled_matrices_are_what_the_rules_give():
    import subprocess
    import sys
    from pathlib import Path

    tool = Path(__file__).resolve().parent.parent / "tools" / "self_collision_matrix.py"
    done = subprocess.run([sys.executable, str(tool), "--check"], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr


# --- runs keep every enabled pair apart -------------------------------------------------------

from hypothesis import HealthCheck, assume, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402
from invariants import assert_trajectory_invariants, small_planning_budget  # noqa: E402

from armanim.motion.problem import Goal  # noqa: E402
from armanim.motion.solvers import METHODS  # noqa: E402
from armanim.motion.trajectory import solve_trajectory  # noqa: E402
from armanim.scene import scene_model  # noqa: E402
from armanim.scene.convert import default_solver_settings  # noqa: E402


def robot_problem(robot: str, **solver):
    """A bundled robot's problem with its own allowed-collision matrix, in metres."""
    from dataclasses import replace

    base = scene_to_problem(scene_model({"version": 1, "arm": {"robot": robot}, "goals": [[0.4, 0, 0.4]]}))
    return replace(base, solver=default_solver_settings(**{"max_step": 0.02, "tolerance": 0.005, "max_frames_per_goal": 120,
                                                           "clearance": 0.02, **solver}))


@st.composite
def near_body_problems(draw):
    """Panda or UR5, its self pairs enabled (self_clearance 0.01), goals at the tool point of
    random in-limit poses close to the body (within 0.3 m of the base's vertical axis), so that
    straight joint paths and random free poses cross or fold the arm onto itself."""
    from dataclasses import replace

    robot = draw(st.sampled_from(["panda", "ur5"]))
    problem = robot_problem(robot, method=draw(st.sampled_from(sorted(METHODS))))
    lim = problem.limits
    lo, hi = np.maximum(lim.lower, -np.pi) + 0.1, np.minimum(lim.upper, np.pi) - 0.1
    poses = np.array([np.array(draw(st.lists(st.floats(0.0, 1.0), min_size=problem.arm.n, max_size=problem.arm.n))) * (hi - lo) + lo
                      for _ in range(draw(st.integers(1, 2)))])
    tips = forward(problem.arm, poses).tip
    assume(np.all(tips[:, 2] > 0.1) and np.all(np.linalg.norm(tips[:, :2] - problem.arm.base[:2], axis=1) < 0.3))
    return replace(problem, goals=tuple(Goal(tip, hold=0.0) for tip in tips))


@settings(max_examples=8, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(near_body_problems())
def test_runs_near_the_body_keep_every_enabled_pair_apart(problem):
    solution = solve_trajectory(small_planning_budget(problem))
    assert_trajectory_invariants(problem, solution)  # every frame: every enabled pair >= self_clearance


def test_panda_shelf_has_no_frame_under_self_clearance():
    from pathlib import Path

    scene = Path(__file__).resolve().parent.parent / "scenes" / "panda-shelf.yaml"
    problem = scene_to_problem(load_scene(scene).model)
    assert ("panda_link5", "panda_link7") in problem.self_pairs.names  # the pair the run used to pass through
    solution = solve_trajectory(problem)
    assert_trajectory_invariants(problem, solution)
    assert solution.trajectory.self_clearance.min() >= problem.self_pairs.clearance
    assert solution.reached == len(problem.goals)
    off = solve_trajectory(replace_pairs(problem))  # the same scene with self_collision: off passes link 5 through link 7
    gaps = self_gaps(forward(problem.arm, off.trajectory.phi), problem.capsules, problem.self_pairs).d
    assert (gaps.min(axis=1) < 0).sum() > 100


def replace_pairs(problem):
    from dataclasses import replace

    return replace(problem, self_pairs=SelfPairs.none())


def test_a_goal_whose_only_poses_fold_the_arm_is_a_no_free_pose_miss_naming_the_pair():
    """A planar chain whose only pose at the goal folds link 4 onto link 1: planner on, no free pose."""
    from dataclasses import replace

    from armanim.motion.problem import Limits
    from armanim.world.obstacles import Obstacles

    arm = Arm.from_names([1.0, 1.0, 1.0], axes=["z", "z", "z"], direction="x")
    caps = joint_capsules(arm, 0.1)
    pairs = selfcollision.enabled_pairs(caps, {("link1", "link2"): "Adjacent", ("link2", "link3"): "Adjacent"}, 0.05, "auto")
    limits = Limits(np.radians([-10.0, -170, -170]), np.radians([10.0, 170, 170]), np.radians(10.0))
    goal = np.array([0.4, 0.0, 0.0])  # only reached with link 3 folded back over link 1
    from armanim.motion.problem import Problem

    problem = Problem(arm=arm, half_width=0.1, home=np.zeros(3), limits=limits, obstacles=Obstacles.none(),
                      goals=(Goal(goal, 0.0),), solver=default_solver_settings(tolerance=0.01, max_frames_per_goal=200, clearance=0.1),
                      fps=30.0, capsules=caps, self_pairs=pairs)
    solution = solve_trajectory(small_planning_budget(problem))
    assert_trajectory_invariants(problem, solution)
    report = solution.goals[0]
    assert not report.reached and report.reason == "no_free_pose"
    assert report.planning.self_pair == "link1|link3"
    free = solve_trajectory(replace(problem, self_pairs=SelfPairs.none()))
    assert free.goals[0].reached  # without the pair the goal is reached, through the arm


# --- outputs -----------------------------------------------------------------------------------


def test_run_folder_says_what_was_checked_and_reloads_with_its_srdf(cli, tmp_path):
    import csv
    import json
    import shutil

    import yaml

    from armanim.runs.reload import load_run

    (tmp_path / "chain.urdf").write_text(chain_urdf())
    (tmp_path / "chain.srdf").write_text('<robot name="chain">\n'
                                         + "".join(f'  <disable_collisions link1="l{k}" link2="l{k + 1}" reason="Adjacent"/>\n' for k in range(4))
                                         + '  <disable_collisions link1="l0" link2="l4" reason="Never"/>\n</robot>\n')
    scene = {"version": 1, "name": "chain", "arm": {"urdf": "chain.urdf", "self_collision": {"srdf": "chain.srdf"}, "home": [0, 20, 0, 20, 0]},
             "goals": [[0.3, 0.2, 0.9]], "solver": {"max_frames_per_goal": 60}}
    path = write_scene(tmp_path, scene)
    assert cli("run", path, "--out", tmp_path / "out", "--no-video", "-q").exit_code == 0
    folder = tmp_path / "out" / "chain"
    matrix = yaml.safe_load((folder / "self-collision.yaml").read_text())
    assert matrix["mode"] == "srdf" and ["l0", "l4", "Never"] in matrix["allowed"] and ["l0", "l2"] in matrix["enabled"]
    summary = json.loads((folder / "summary.json").read_text())
    assert summary["self_collision"] == {"mode": "srdf", "self_clearance": pytest.approx(0.005), "enabled_pairs": len(matrix["enabled"]),
                                         "allowed_pairs": 5}
    rows = list(csv.DictReader((folder / "trajectory.csv").open()))
    n = sum(c.startswith("dphi") for c in rows[0])  # the joints' velocities come last
    assert list(rows[0])[-2 - n:-n] == ["self_clearance", "self_pair"] and n == sum(c.startswith("phi") for c in rows[0])
    least = min(float(r["self_clearance"]) for r in rows)
    assert least == summary["min_self_clearance"] >= 0.005
    assert summary["min_self_pair"] in {r["self_pair"] for r in rows}
    assert (folder / "robot.srdf").read_bytes() == (tmp_path / "chain.srdf").read_bytes()
    moved = shutil.move(str(folder), str(tmp_path / "elsewhere"))  # the user's files no longer beside it
    (tmp_path / "chain.srdf").unlink()
    run = load_run(moved)
    assert run.problem.self_pairs.mode == "srdf" and run.solution.trajectory.self_clearance.min() == least


def test_off_leaves_the_self_columns_empty(cli, tmp_path):
    import csv
    import json

    path = write_scene(tmp_path, scene_dict(self_collision="off"))
    assert cli("run", path, "--out", tmp_path / "out", "--no-video", "-q").exit_code == 0
    folder = tmp_path / "out" / "scene"
    rows = list(csv.DictReader((folder / "trajectory.csv").open()))
    assert all(r["self_clearance"] == "" and r["self_pair"] == "" for r in rows)
    summary = json.loads((folder / "summary.json").read_text())
    assert summary["min_self_clearance"] is None and summary["self_collision"]["mode"] == "off"
    assert "enabled: []" in (folder / "self-collision.yaml").read_text()


def test_certified_motion_checks_cover_the_arms_own_pairs():
    """motion_is_free's step bound covers pairs that move relative to each other: whatever it
    certifies, a fine sampling of the same straight motion keeps the floor (to its certification slack)."""
    from armanim.motion.planning.path import motion_is_free
    from armanim.motion.problem import Limits, Problem
    from armanim.motion.solvers.barrier import pose_clearance
    from armanim.motion.tunables import DEFAULTS
    from armanim.world.obstacles import Obstacles

    arm = Arm.from_names([1.0, 0.8, 0.8, 0.6, 0.4], axes=["z", "y", "y", "x", "y"])
    caps = joint_capsules(arm, 0.05)
    allowed = {(f"link{k}", f"link{k + 1}"): "Adjacent" for k in range(1, 5)}
    pairs = selfcollision.enabled_pairs(caps, allowed, 0.02, "auto")
    problem = Problem(arm=arm, half_width=0.05, home=np.zeros(5), limits=Limits.unlimited(5, np.radians(10.0)),
                      obstacles=Obstacles.none(), goals=(Goal(np.array([1.0, 0, 1.0]), 0.0),),
                      solver=default_solver_settings(clearance=0.04), fps=30.0, capsules=caps, self_pairs=pairs)
    rng = np.random.default_rng(35)
    certified = refused = 0
    for _ in range(60):
        a, b = rng.uniform(-2.5, 2.5, (2, 5))
        floor = 0.044
        free, _ = motion_is_free(problem, a, b, floor)
        fine = pose_clearance(problem, a + np.linspace(0, 1, 2001)[:, None] * (b - a))
        if free:
            certified += 1
            assert fine.min() >= floor - DEFAULTS.planner.certify_to * problem.solver.clearance / 2 - 1e-9
        else:
            refused += 1
    assert certified >= 5 and refused >= 5  # both answers were exercised
