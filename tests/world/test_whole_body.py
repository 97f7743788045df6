"""The whole robot is the body: the base link and the links hanging off the arm's path (a
gripper's fingers) carry their collision geometry, checked against pinocchio's kinematics and
pinocchio's own reading of the URDF's collision spheres; held joints (``arm.joint_values``) and
their errors; runs that keep a finger off an obstacle and the hand out of the base."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from armanim.arm.capsules import BASE, capsule_ends
from armanim.arm.kinematics import forward
from armanim.errors import SceneError
from armanim.motion.trajectory import solve_trajectory
from armanim.scene import scene_model
from armanim.scene.convert import link_places, scene_arm, scene_to_problem
from armanim.scene.loader import load_scene
from armanim.world.selfdistances import self_gaps

VAMP = Path(__file__).resolve().parents[1] / "data" / "vamp"
PANDA_URDF = Path(__file__).resolve().parents[2] / "src" / "armanim" / "arm" / "robots" / "panda" / "panda.urdf"


def _model(arm: dict, **scene):
    return scene_model({"version": 1, "arm": arm, "goals": [[0.5, 0.0, 0.5]], **scene}, VAMP)


def _pin_q(pin, model, names, phi, extra=None):
    q = pin.neutral(model)
    for name, value in [*zip(names, phi), *(extra or {}).items()]:
        q[model.joints[model.getJointId(name)].idx_q] = value
    return q


def _world(places, pose, link):
    """(4, 4) a link's frame in the world from its carrier's frame at ``pose``."""
    carrier, place = places[link]
    if carrier == BASE:
        return place
    frame = np.eye(4)
    frame[:3, :3], frame[:3, 3] = pose.frames[carrier], pose.points[carrier]
    return frame @ place


@pytest.mark.parametrize("robot, tip", [("panda", "panda_hand"), ("panda", "panda_link8"), ("ur5", "ee_link")])
def test_every_vamp_sphere_is_in_the_model_where_pinocchio_puts_it(robot, tip):
    """Every <collision> sphere of VAMP's spherized robots (the Panda's 59, the base's and the
    fingers' among them) is a capsule of the model, named after its link, at the world centre and
    radius pinocchio's geometry model gives it, at random poses and a turned, moved base."""
    pin = pytest.importorskip("pinocchio")
    urdf = VAMP / f"{robot}_spherized.urdf"
    base = {"panda": "panda_link0", "ur5": "base_link"}[robot]
    arm = {"urdf": urdf.name, "base_link": base, "tip_link": tip, "base": [0.1, -0.2, 0.05], "base_rpy": [0, 0, 30]}
    scene = _model(arm)
    chain, caps = scene_arm(scene.arm, [])
    xml = urdf.read_text()
    model = pin.buildModelFromXML(xml)
    geometry = pin.buildGeomFromUrdfString(model, xml, pin.GeometryType.COLLISION)
    data, gdata = model.createData(), pin.GeometryData(geometry)
    spheres = [
        g for g in geometry.geometryObjects if hasattr(g.geometry, "radius") and not hasattr(g.geometry, "halfLength")
    ]
    if robot == "panda":
        assert len(spheres) == 59
    mount = np.eye(4)
    mount[:3, :3] = np.array(
        [[np.cos(np.pi / 6), -np.sin(np.pi / 6), 0], [np.sin(np.pi / 6), np.cos(np.pi / 6), 0], [0, 0, 1]]
    )
    mount[:3, 3] = [0.1, -0.2, 0.05]
    pin.framesForwardKinematics(model, data, pin.neutral(model))
    mount = mount @ data.oMf[model.getFrameId(base)].inverse().homogeneous  # the UR5's base_link sits below a root link
    rng = np.random.default_rng(49)
    for _ in range(3):
        phi = rng.uniform(-1.5, 1.5, chain.n)
        pin.updateGeometryPlacements(model, data, geometry, gdata, _pin_q(pin, model, chain.joint_names, phi))
        a, b = capsule_ends(caps, forward(chain, phi))
        names = np.array(caps.names)
        for sphere, placed in zip(geometry.geometryObjects, gdata.oMg):
            if sphere not in spheres:
                continue
            link = model.frames[sphere.parentFrame].name
            centre = mount[:3, :3] @ placed.translation + mount[:3, 3]
            mine = (
                (names == link)
                & np.all(np.abs(a - centre) < 1e-12, axis=1)
                & np.all(np.abs(b - centre) < 1e-12, axis=1)
            )
            assert np.any(mine & (np.abs(caps.radius - sphere.geometry.radius) < 1e-15)), (link, centre)
    assert np.all(caps.link[np.array(caps.names) == base] == BASE)


def test_off_path_link_frames_equal_pinocchios():
    """The bundled Panda with its fingers held open (``joint_values``, the mimic finger following):
    the frames of the base, the hand and both fingers, composed through the fixed and held joints,
    are pinocchio's to 1e-12, with the tip at the flange (the hand and fingers off the path)."""
    pin = pytest.importorskip("pinocchio")
    arm = {
        "robot": "panda",
        "tip_link": "panda_link8",
        "base": [0.3, 0.1, -0.2],
        "base_rpy": [10, -20, 40],
        "joint_values": {"panda_finger_joint1": 0.031},
    }
    scene = _model(arm)
    chain, _ = scene_arm(scene.arm, [])
    from armanim.scene.convert import urdf_chain, urdf_mount

    places = link_places(scene.arm, urdf_chain(scene.arm))
    mount = urdf_mount(scene.arm)
    model = pin.buildModelFromXML(PANDA_URDF.read_text())
    data = model.createData()
    rng = np.random.default_rng(3)
    for _ in range(4):
        phi = rng.uniform(-1.5, 1.5, chain.n)
        q = _pin_q(pin, model, chain.joint_names, phi, {"panda_finger_joint1": 0.031, "panda_finger_joint2": 0.031})
        pin.framesForwardKinematics(model, data, q)
        pose = forward(chain, phi)
        for link in (
            "panda_link0",
            "panda_link5",
            "panda_hand",
            "panda_hand_tcp",
            "panda_leftfinger",
            "panda_rightfinger",
        ):
            expected = mount @ data.oMf[model.getFrameId(link)].homogeneous
            np.testing.assert_allclose(_world(places, pose, link), expected, atol=1e-12, rtol=0, err_msg=link)


@pytest.mark.parametrize(
    "values, fragment",
    [
        ({"panda_joint3": 10}, "'panda_joint3' is a joint of the arm's chain"),
        ({"panda_finger_joint": 0.01}, "'panda_finger_joint' is not a joint of"),
        ({"panda_finger_joint1": 0.05}, "0.05 is outside the limits of joint 'panda_finger_joint1', [0, 0.04] m"),
        ({"panda_finger_joint2": 0.01}, "mimics 'panda_finger_joint1'"),
        ({"panda_hand_joint": 0.0}, "joint 'panda_hand_joint' is fixed"),
    ],
)
def test_joint_values_errors_name_the_entry_and_its_line(tmp_path, values, fragment):
    lines = ["version: 1", "arm:", "  robot: panda", "  joint_values:"]
    lines += [f"    {name}: {value}" for name, value in values.items()]
    lines += ["goals:", "  - [0.5, 0.0, 0.5]"]
    path = tmp_path / "s.yaml"
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(SceneError) as info:
        load_scene(path)
    text = str(info.value)
    assert fragment in text
    assert f"{path}:5: arm.joint_values.{next(iter(values))}" in text


@pytest.mark.parametrize("value", [".nan", ".inf"])
def test_joint_values_must_be_finite(tmp_path, value):
    path = tmp_path / "s.yaml"
    path.write_text(
        f"version: 1\narm:\n  robot: panda\n  joint_values:\n    panda_finger_joint1: {value}\ngoals:\n  - [0.5, 0, 0.5]\n"
    )
    with pytest.raises(SceneError) as info:
        load_scene(path)
    assert f"{path}:5: arm.joint_values.panda_finger_joint1" in str(info.value)


def test_joint_values_do_not_apply_to_an_arm_of_links():
    with pytest.raises(Exception, match="joint_values does not apply to an arm of links"):
        scene_model({"version": 1, "arm": {"links": [1, 1], "joint_values": {"a": 1}}, "goals": [[0.5, 0, 0.5]]})


def test_held_joints_default_to_zero_or_their_lower_limit_and_mimics_follow():
    """The Panda's fingers: closed (0) by default, 0.04 m open when asked, the mimic finger beside."""

    def finger_gap(arm):
        scene = _model(arm)
        chain, caps = scene_arm(scene.arm, [])
        a, _ = capsule_ends(caps, forward(chain, np.zeros(chain.n)))
        names = np.array(caps.names)
        left, right = a[names == "panda_leftfinger"][0], a[names == "panda_rightfinger"][0]
        return float(np.linalg.norm(left - right))

    closed = finger_gap({"robot": "panda"})
    opened = finger_gap({"robot": "panda", "joint_values": {"panda_finger_joint1": 0.04}})
    assert closed == pytest.approx(0.03, abs=1e-12)  # the screw mounts' own offsets, 15 mm each side
    assert opened - closed == pytest.approx(0.08, abs=1e-12)


def _finger_scene(tmp_path: Path, obstacle_centre, radius: float) -> Path:
    scene = f"""version: 1
arm:
  urdf: {VAMP / "panda_spherized.urdf"}
  base_link: panda_link0
  tip_link: panda_hand
  home: [0, -30, 0, -150, 0, 120, 45]
  self_collision: {{srdf: {VAMP / "panda.srdf"}}}
obstacles:
  - {{center: {list(map(float, obstacle_centre))}, radius: {radius}}}
goals:
  - position: [0.45, 0.0, 0.35]
    orientation: {{rpy: [180, 0, 0]}}
solver:
  clearance: 0.01
  max_frames_per_goal: 300
render:
  fps: 10
"""
    path = tmp_path / "finger.yaml"
    path.write_text(scene)
    return path


def test_a_run_keeps_the_finger_off_an_obstacle_only_the_finger_would_touch(tmp_path):
    """The goal (the hand's origin, pointing down) would put the left finger's tip sphere 12 mm into a
    small sphere that every other part of the hand clears there; the run keeps the finger at least
    ``clearance`` away in every frame, measured by pinocchio's FK of the fingers' spheres."""
    pin = pytest.importorskip("pinocchio")
    xml = (VAMP / "panda_spherized.urdf").read_text()
    model = pin.buildModelFromXML(xml)
    geometry = pin.buildGeomFromUrdfString(model, xml, pin.GeometryType.COLLISION)
    data, gdata = model.createData(), pin.GeometryData(geometry)
    hand = model.getFrameId("panda_hand")
    goal = np.array([0.45, 0.0, 0.35])
    down = np.diag([1.0, -1.0, -1.0])  # rpy [180, 0, 0]

    def local(frame_name):
        """The spheres of a link, (k, 3) centres in the hand's frame and (k,) radii (at any pose)."""
        pin.updateGeometryPlacements(model, data, geometry, gdata, pin.neutral(model))
        pin.updateFramePlacements(model, data)
        to_hand = data.oMf[hand].inverse()
        objs = [
            (to_hand * placed).translation
            for g, placed in zip(geometry.geometryObjects, gdata.oMg)
            if model.frames[g.parentFrame].name == frame_name
        ]
        radii = [g.geometry.radius for g in geometry.geometryObjects if model.frames[g.parentFrame].name == frame_name]
        return np.array(objs), np.array(radii)

    finger, finger_r = local("panda_leftfinger")
    tip = finger[np.argmax(finger[:, 2])]  # the fingertip's sphere, farthest down the hand's z
    radius = 0.02
    outward = np.array([0.0, 0.0, 1.0])
    centre_local = tip + outward * (finger_r.max() + radius - 0.012)  # 12 mm into the fingertip's sphere
    centre = goal + down @ centre_local
    for link in ("panda_hand", "panda_link7", "panda_rightfinger"):  # only the finger would touch at the goal
        spheres, radii = local(link)
        assert np.min(np.linalg.norm(spheres - centre_local, axis=1) - radii - radius) > 0.01, link
    path = _finger_scene(tmp_path, centre, radius)
    problem = scene_to_problem(load_scene(path).model)
    solution = solve_trajectory(problem)
    names = problem.arm.joint_names
    fingers = [
        k
        for k, g in enumerate(geometry.geometryObjects)
        if model.frames[g.parentFrame].name in ("panda_leftfinger", "panda_rightfinger")
    ]
    least = np.inf
    for phi in solution.trajectory.phi:
        pin.updateGeometryPlacements(model, data, geometry, gdata, _pin_q(pin, model, names, phi))
        for k in fingers:
            gap = (
                np.linalg.norm(gdata.oMg[k].translation - centre) - geometry.geometryObjects[k].geometry.radius - radius
            )
            least = min(least, gap)
    assert least >= 0.01 - 1e-9
    assert least < 0.03  # the finger came near: the obstacle was in its way


def test_the_hand_is_kept_out_of_the_base(tmp_path):
    """A goal behind the Panda's base, low: solved without the arm's own pairs, the motion folds the
    hand into ``panda_link0``. With the base in the self pairs (the bundled matrix checks it against
    the hand and the fingers) no frame has any part within ``self_clearance`` of the base's capsules."""
    from dataclasses import replace

    from armanim.world.selfdistances import SelfPairs

    path = tmp_path / "base.yaml"
    path.write_text(
        "version: 1\narm:\n  robot: panda\ngoals:\n  - [-0.18, 0.0, 0.1]\n"
        "solver:\n  max_frames_per_goal: 200\n  self_clearance: 0.01\nrender:\n  fps: 10\n"
    )
    problem = scene_to_problem(load_scene(path).model)
    pairs = problem.self_pairs
    caps = problem.capsules
    on_base = caps.link[pairs.first] == BASE
    hand = on_base & np.isin(
        np.array(caps.names)[pairs.second], ["panda_hand", "panda_leftfinger", "panda_rightfinger"]
    )

    def gaps(solved):
        return self_gaps(forward(problem.arm, solve_trajectory(solved).trajectory.phi), caps, pairs).d

    assert gaps(replace(problem, self_pairs=SelfPairs.none(pairs.clearance)))[:, hand].min() < 0.0  # into the base
    assert gaps(problem)[:, on_base].min() >= 0.01 - 1e-9


def test_a_base_standing_in_an_obstacle_is_an_error_at_the_obstacle(tmp_path):
    """The Panda's base inside a box, its arm clear of it: refused when the scene is read, the
    message at the obstacle's line naming the base link (no pose could move it out)."""
    path = tmp_path / "s.yaml"
    path.write_text(
        "version: 1\narm:\n  robot: panda\nobstacles:\n  - {box: {center: [0.0, 0.0, 0.0], size: [0.2, 0.2, 0.05]}}\n"
        "goals:\n  - [0.5, 0, 0.5]\n"
    )
    with pytest.raises(SceneError) as info:
        load_scene(path)
    assert (
        f"{path}:5: obstacles[0]: the robot's base (link 'panda_link0', which never moves) is inside this obstacle"
        in str(info.value)
    )


def test_the_base_carrier_in_numpy_and_compiled_alike():
    """Carrier -1 (the base) in every path that indexes a capsule by its joint: the compiled
    capsule ends equal numpy's bit for bit (the base's are its own ends), a base point's Jacobian
    is zero, and a base pair's rows (compiled) are minus the moving capsule's point Jacobian
    (numpy's :func:`point_jacobian`) along the normal, and its rate from the links' twists is
    that row times the rates."""
    from armanim.arm import kernel
    from armanim.arm.capsules import capsule_point
    from armanim.arm.kinematics import point_jacobian
    from armanim.world import compiled
    from armanim.world.selfdistances import _pair_inputs, self_rows

    problem = scene_to_problem(_model({"robot": "panda"}))
    caps, pairs = problem.capsules, problem.self_pairs
    phi = problem.home + np.linspace(-0.4, 0.4, problem.arm.n)
    batch = forward(problem.arm, phi[None])  # a batch: the numpy ends
    one = forward(problem.arm, phi)
    a, b = kernel.capsule_ends_one(caps.link, caps.start, caps.end, caps.joint_segment, one.points, one.frames)
    na, nb = capsule_ends(caps, batch)
    assert np.array_equal(a, na[0]) and np.array_equal(b, nb[0])
    base = caps.link == BASE
    assert base.any() and np.array_equal(a[base], caps.start[base]) and np.array_equal(b[base], caps.end[base])
    assert not point_jacobian(problem.arm, one, -1, a[base][0]).any()
    which = np.flatnonzero(caps.link[pairs.first] == BASE)
    assert len(which)
    gaps = self_gaps(one, caps, pairs)
    rows = self_rows(problem.arm, caps, one, pairs, gaps, which)
    second = pairs.second[which]
    q = capsule_point(caps, one, second, gaps.s[which])
    expected = np.array(
        [
            -gaps.normal[p] @ point_jacobian(problem.arm, one, int(caps.link[c]), q[k])
            for k, (p, c) in enumerate(zip(which, second))
        ]
    )
    np.testing.assert_allclose(rows, expected, atol=1e-12, rtol=0)
    rates = np.random.default_rng(1).normal(size=problem.arm.n)
    twists = np.empty((problem.arm.n, 6))
    inputs = _pair_inputs(problem.arm, caps, one, pairs, gaps)
    compiled.link_twists(inputs[0], inputs[1], rates, twists)
    for k, p in enumerate(which):
        rate = compiled.pair_rate(
            twists, inputs[2], inputs[3], caps.link, pairs.first, pairs.second, gaps.t, gaps.s, gaps.normal, p
        )
        assert rate == pytest.approx(rows[k] @ rates, abs=1e-12)


def test_always_colliding_pairs_are_allowed_as_always_where_the_default_rule_is_off():
    """Three short links with fat capsules: links 1 and 3 overlap in every pose. MoveIt's order
    names the pair ``Default`` (it overlaps at the default pose too); with the rules an SRDF's
    scene applies (``Adjacent``, ``Always``) it is ``Always``; links 1 and 2 are ``Adjacent``."""
    from armanim.arm.capsules import joint_capsules
    from armanim.arm.kinematics import Arm
    from armanim.world import selfcollision

    arm = Arm.from_names([0.1, 0.1, 0.1])
    caps = joint_capsules(arm, 0.5)
    lim = np.radians([-170.0] * 3), np.radians([170.0] * 3)
    auto = selfcollision.automatic_matrix(arm, caps, *lim, [np.zeros(3)], 0.01, samples=200)
    srdf = selfcollision.automatic_matrix(
        arm, caps, *lim, [], 0.01, samples=200, rules=(selfcollision.ADJACENT, selfcollision.ALWAYS)
    )
    assert auto[("link1", "link3")] == "Default" and srdf[("link1", "link3")] == "Always"
    assert srdf[("link1", "link2")] == "Adjacent"
    thin = selfcollision.automatic_matrix(
        arm,
        joint_capsules(arm, 0.001),
        *lim,
        [],
        0.001,
        samples=200,
        rules=(selfcollision.ADJACENT, selfcollision.ALWAYS),
    )
    assert ("link1", "link3") not in thin  # a pair apart in some pose stays checked


def test_an_srdf_scene_adds_moveits_adjacent_and_always_where_the_srdf_is_silent():
    """VAMP's UR5 with its SRDF: the SRDF's own pairs keep its reasons, wrist_2_link/fts_robotside
    (which its SRDF leaves enabled, their spheres overlapping in every pose) is allowed as
    ``Adjacent``, and base_link/upper_arm_link (within 2.5 mm at some poses) is checked."""
    scene = _model(
        {
            "urdf": "ur5_spherized.urdf",
            "base_link": "base_link",
            "tip_link": "ee_link",
            "home": [0, -90, 90, -90, -90, 0],
            "self_collision": {"srdf": "ur5.srdf"},
        },
        solver={"self_clearance": 0.001},
    )
    pairs = scene_to_problem(scene).self_pairs
    allowed = {frozenset((a, b)): reason for a, b, reason in pairs.allowed}
    assert allowed[frozenset(("wrist_2_link", "fts_robotside"))] == "Adjacent"
    assert allowed[frozenset(("base_link", "shoulder_link"))] == "Adjacent"  # the SRDF's own reason
    assert allowed[frozenset(("ee_link", "wrist_1_link"))] == "Never"  # the SRDF's own reason
    assert {frozenset(p) for p in pairs.names} >= {frozenset(("base_link", "upper_arm_link"))}


def test_the_capsule_pictures_stand_the_base_where_it_is():
    """The drawn prisms (render.robot: capsules) of every capsule, the base's among them, lie on
    their capsules' world segments (each vertex within the radius of its segment), not on a joint's
    frame read at index -1."""
    from armanim.arm.capsules import carrier_frames
    from armanim.render.solids.mesh import prism_local, prism_world

    problem = scene_to_problem(_model({"robot": "panda", "base": [0.2, 0.1, 0.0]}))
    caps = problem.capsules
    pose = forward(problem.arm, problem.home)
    rotations, origins = carrier_frames(caps, pose)
    verts = prism_world(rotations, origins, prism_local(caps, 8))
    a, b = capsule_ends(caps, pose)
    ab = b - a
    length2 = np.maximum((ab * ab).sum(-1), 1e-300)[:, None]
    t = np.clip(((verts - a[:, None]) * ab[:, None]).sum(-1) / length2, 0, 1)
    dist = np.linalg.norm(verts - (a[:, None] + t[..., None] * ab[:, None]), axis=-1)
    assert np.all(dist <= caps.radius[:, None] * 1.0001 + 1e-12)
    assert np.any(caps.link == BASE)


HELD = """<robot name="held">
  <link name="base"/><link name="upper"/><link name="hand"/>
  <link name="camera"><collision><origin xyz="0.1 0 0"/><geometry><sphere radius="0.02"/></geometry></collision></link>
  <link name="twin"><collision><origin xyz="0.1 0 0"/><geometry><sphere radius="0.01"/></geometry></collision></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="upper"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="upper"/><child link="hand"/><origin xyz="0 0 0.5"/><axis xyz="0 1 0"/>
    <limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="pan" type="revolute"><parent link="hand"/><child link="camera"/><origin xyz="0 0 0.2"/><axis xyz="0 0 1"/>
    <limit lower="0.2" upper="1.5" effort="1" velocity="1"/></joint>
  <joint name="follow" type="revolute"><parent link="hand"/><child link="twin"/><origin xyz="0 0 0.3"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="1" velocity="1"/><mimic joint="pan" multiplier="-2" offset="0.1"/></joint>
</robot>
"""


@pytest.mark.parametrize("given, pan", [(None, 0.2), (60.0, np.radians(60.0))])
def test_a_held_revolute_joint_in_degrees_and_its_mimic(tmp_path, given, pan):
    """A camera on a revolute joint off the path (limits [0.2, 1.5] rad: held at its lower limit by
    default, or at ``joint_values`` degrees) and a mimic of it (-2 x pan + 0.1): their spheres where
    the closed form puts them, on the hand's joint (carrier 1)."""
    (tmp_path / "held.urdf").write_text(HELD)
    arm = {"urdf": "held.urdf", "base_link": "base", "tip_link": "hand", "home": [0, 0]}
    if given is not None:
        arm["joint_values"] = {"pan": given}
    scene = scene_model({"version": 1, "arm": arm, "goals": [[0.3, 0, 0.3]]}, tmp_path)
    chain, caps = scene_arm(scene.arm, [])
    names = list(caps.names)
    for link, angle, height in (("camera", pan, 0.2), ("twin", -2 * pan + 0.1, 0.3)):
        k = names.index(link)
        assert caps.link[k] == 1
        expected = np.array([0.1 * np.cos(angle), 0.1 * np.sin(angle), height])
        np.testing.assert_allclose(caps.start[k], expected, atol=1e-15)
    with pytest.raises(Exception, match="outside the limits of joint 'pan', \\[11.4592, 85.9437\\] degrees"):
        scene_model({"version": 1, "arm": {**arm, "joint_values": {"pan": 5.0}}, "goals": [[0.3, 0, 0.3]]}, tmp_path)


def test_the_base_stands_on_the_floor():
    """The Panda's panda_link0 capsule reaches 3 cm below its mount: with the floor at the mount the
    scene is valid and the base's floor clearance is +inf (it stands there, as the first joint's links do)."""
    from armanim.world.distances import clearances

    problem = scene_to_problem(_model({"robot": "panda"}, floor=0.0))
    caps = problem.capsules
    a, b = capsule_ends(caps, forward(problem.arm, problem.home))
    base = caps.link == BASE
    assert np.min(np.minimum(a[base, 2], b[base, 2]) - caps.radius[base]) < -0.02
    floor = clearances(forward(problem.arm, problem.home), problem.obstacles, caps).d[:-1, -1]
    assert np.all(np.isinf(floor[base]))


@settings(max_examples=20, deadline=None)
@given(
    opening=st.floats(0.0, 0.04),
    base=st.lists(st.floats(-1, 1), min_size=3, max_size=3),
    rpy=st.lists(st.floats(-170, 170), min_size=3, max_size=3),
    seed=st.integers(0, 2**31),
)
def test_any_finger_opening_and_mount_place_the_fingers_as_pinocchio_does(opening, base, rpy, seed):
    """Any opening of the Panda's fingers, any mount, the tip at panda_link7 (the hand off the path):
    the hand's, the fingers' and the base's frames are pinocchio's (the mimic finger at the same
    opening) to 1e-12."""
    pin = pytest.importorskip("pinocchio")
    from armanim.scene.convert import urdf_chain, urdf_mount

    arm = {
        "robot": "panda",
        "tip_link": "panda_link7",
        "base": base,
        "base_rpy": rpy,
        "joint_values": {"panda_finger_joint1": opening},
    }
    scene = _model(arm)
    chain = urdf_chain(scene.arm)
    places = link_places(scene.arm, chain)
    model = pin.buildModelFromXML(PANDA_URDF.read_text())
    data = model.createData()
    phi = np.random.default_rng(seed).uniform(-1.5, 1.5, chain.arm.n)
    q = _pin_q(pin, model, chain.arm.joint_names, phi, {"panda_finger_joint1": opening, "panda_finger_joint2": opening})
    pin.framesForwardKinematics(model, data, q)
    pose = forward(chain.arm, phi)
    for link in ("panda_hand", "panda_leftfinger", "panda_rightfinger", "panda_link0"):
        expected = urdf_mount(scene.arm) @ data.oMf[model.getFrameId(link)].homogeneous
        np.testing.assert_allclose(_world(places, pose, link), expected, atol=1e-12, rtol=0, err_msg=link)
