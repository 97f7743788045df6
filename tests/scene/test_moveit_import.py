"""``armanim import moveit``: MoveIt planning scenes (YAML and ``.scene``) and motion plan requests as scenes.

Oracles: scipy's Rotation for every pose composed (independent of armanim's rotations), the request's own
radians for the degrees written, the MotionBenchMaker files as VAMP ships them, and the scene loader for
the forms this branch validates (the joint goal, cylinder, ``name`` and ``joint_values`` forms come with
the other parts of issue 49: their dicts are asserted).
"""

from __future__ import annotations

import os
import subprocess
import tarfile
from pathlib import Path

import numpy as np
import pytest
import yaml
from conftest import ROOT
from hypothesis import given
from hypothesis import strategies as st
from runfolders import armanim_exe
from scipy.spatial.transform import Rotation
from strategies import ros_poses

from armanim.errors import SceneError, UsageError
from armanim.scene import load_scene
from armanim.scene.moveitscene import MARKER, RobotSource, import_moveit, moveit_scene, scene_text

DATA = Path(__file__).parent.parent / "data" / "mbm"
SHARED_MBM = Path(os.environ.get("ARMANIM_MBM_DATA", ROOT.parent / "shared" / "data" / "mbm"))

TOY_URDF = """<robot name="toy">
  <link name="base"><collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link>
  <link name="l1"/><link name="l2"/><link name="l3"/><link name="hand"/><link name="finger"/>
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="l1"/><origin xyz="0 0 0.1"/>
    <axis xyz="0 0 1"/><limit lower="-3" upper="3" velocity="1" effort="1"/></joint>
  <joint name="elbow" type="revolute"><parent link="l1"/><child link="l2"/><origin xyz="0 0 0.3"/>
    <axis xyz="0 1 0"/><limit lower="-2" upper="2" velocity="1" effort="1"/></joint>
  <joint name="wrist" type="continuous"><parent link="l2"/><child link="l3"/><origin xyz="0 0 0.3"/>
    <axis xyz="0 1 0"/></joint>
  <joint name="flange" type="fixed"><parent link="l3"/><child link="hand"/><origin xyz="0 0 0.1"/></joint>
  <joint name="finger_joint" type="prismatic"><parent link="hand"/><child link="finger"/>
    <axis xyz="0 1 0"/><limit lower="0" upper="0.04" velocity="1" effort="1"/></joint>
</robot>
"""

SHAPES_SCENE = """name: shapes
world:
  collision_objects:
    - id: rack
      header: {frame_id: world}
      pose:
        position: {x: 1.0, y: 0.5, z: 0.2}
        orientation: {x: 0.0, y: 0.0, z: 0.3826834323650898, w: 0.9238795325112867}
      primitives:
        - {type: 1, dimensions: [0.4, 0.2, 0.1]}
        - {type: 2, dimensions: [0.05]}
        - {type: 3, dimensions: [0.3, 0.02]}
      primitive_poses:
        - {position: {x: 0.1, y: 0.0, z: 0.0}, orientation: {x: 0.0, y: 0.0, z: 0.0, w: 1.0}}
        - {position: {x: 0.0, y: 0.2, z: 0.1}}
        - position: [0.0, -0.1, 0.3]
          orientation: [0.2588190451025208, 0.0, 0.0, 0.9659258262890683]
    - id: ball
      primitives:
        - type: sphere
          dimensions: [0.1]
      primitive_poses:
        - position: [-1.0, 0.0, 0.5]
robot_state:
  joint_state:
    name: [elbow, finger_joint, shoulder]
    position: [-0.5, 0.02, 0.25]
"""


def _toy(folder: Path) -> Path:
    urdf = folder / "robot" / "toy.urdf"
    urdf.parent.mkdir(exist_ok=True)
    urdf.write_text(TOY_URDF)
    return urdf


def _write(folder: Path, name: str, text: str) -> Path:
    path = folder / name
    path.write_text(text)
    return path


def _pose(position, quaternion_xyzw) -> tuple[np.ndarray, Rotation]:
    return np.array(position, dtype=float), Rotation.from_quat(quaternion_xyzw)  # scipy: x, y, z, w


def _expected(object_pose, primitive_pose) -> tuple[np.ndarray, Rotation]:
    """The primitive's centre and rotation in the world: the object's pose times the primitive's (scipy)."""
    (p0, r0), (p1, r1) = object_pose, primitive_pose
    return p0 + r0.apply(p1), r0 * r1


def _assert_placed(shape: dict, centre: np.ndarray, rotation: Rotation) -> None:
    np.testing.assert_allclose(shape["center"], centre, atol=1e-12)
    written = Rotation.from_euler("xyz", shape["rpy"], degrees=True)  # extrinsic x, y, z: R = Rz Ry Rx, URDF's rpy
    np.testing.assert_allclose(written.as_matrix(), rotation.as_matrix(), atol=1e-12)


# ------------------------------------------------------------ shapes


def test_every_primitive_with_an_object_pose_and_primitive_poses(tmp_path):
    urdf = _toy(tmp_path)
    imported = moveit_scene(
        _write(tmp_path, "s.yaml", SHAPES_SCENE), None, RobotSource(urdf=urdf, tip_link="hand"), tmp_path / "out.yaml"
    )
    box, sphere, cylinder, ball = imported.data["obstacles"]
    rack = _pose([1.0, 0.5, 0.2], [0, 0, 0.3826834323650898, 0.9238795325112867])  # 45 degrees about z
    _assert_placed(box["box"], *_expected(rack, _pose([0.1, 0, 0], [0, 0, 0, 1])))
    assert box["box"]["size"] == [0.4, 0.2, 0.1] and box["name"] == "rack"
    centre, _ = _expected(rack, _pose([0, 0.2, 0.1], [0, 0, 0, 1]))
    np.testing.assert_allclose(sphere["center"], centre, atol=1e-12)
    assert sphere["radius"] == 0.05 and sphere["name"] == "rack-2"
    _assert_placed(
        cylinder["cylinder"], *_expected(rack, _pose([0, -0.1, 0.3], [0.2588190451025208, 0, 0, 0.9659258262890683]))
    )
    assert (cylinder["cylinder"]["length"], cylinder["cylinder"]["radius"]) == (
        0.3,
        0.02,
    )  # CYLINDER_HEIGHT=0, RADIUS=1
    assert cylinder["name"] == "rack-3"
    assert ball == {"center": [-1.0, 0.0, 0.5], "radius": 0.1, "name": "ball"}


def test_a_planning_scene_world_reads_as_a_planning_scenes_world(tmp_path):
    world = "\n".join(line[2:] for line in BOXES_SCENE.splitlines()[1:]) + "\n"  # collision_objects at the top
    source = RobotSource(urdf=_toy(tmp_path), tip_link="l3")
    alone = moveit_scene(_write(tmp_path, "w.yaml", world), None, source, tmp_path / "a.yaml").data["obstacles"]
    assert (
        alone
        == moveit_scene(_write(tmp_path, "s.yaml", BOXES_SCENE), None, source, tmp_path / "b.yaml").data["obstacles"]
    )
    assert [o["name"] for o in alone] == ["table", "lamp"]


def test_the_rotated_cylinder_axis_is_its_local_z(tmp_path):
    """A cylinder turned 90 degrees about x lies along -y: its axis is the rotation's third column."""
    text = SHAPES_SCENE.replace(
        "[0.2588190451025208, 0.0, 0.0, 0.9659258262890683]", "[0.7071067811865476, 0.0, 0.0, 0.7071067811865476]"
    )
    imported = moveit_scene(
        _write(tmp_path, "s.yaml", text), None, RobotSource(urdf=_toy(tmp_path), tip_link="hand"), tmp_path / "o.yaml"
    )
    cylinder = imported.data["obstacles"][2]["cylinder"]
    axis = Rotation.from_euler("xyz", cylinder["rpy"], degrees=True).apply([0, 0, 1])
    np.testing.assert_allclose(axis, Rotation.from_euler("z", 45, degrees=True).apply([0, -1, 0]), atol=1e-12)


@given(ros_poses(), ros_poses(), st.sampled_from(["box", "cylinder"]))
def test_any_object_pose_composes_with_any_primitive_pose_as_scipy_says(tmp_path_factory, whole, part, kind):
    """The YAML's pose times the primitive's, and the newer .scene format's, against scipy's composition."""
    folder = tmp_path_factory.mktemp("poses")
    dims, words = ("[0.3, 0.2, 0.1]", "box\n0.3 0.2 0.1") if kind == "box" else ("[0.3, 0.02]", "cylinder\n0.02 0.3")
    yaml_text = (
        f"world:\n  collision_objects:\n    - id: thing\n      pose: {{position: {whole[0]}, orientation: {whole[1]}}}\n"
        f"      primitives: [{{type: {kind}, dimensions: {dims}}}]\n"
        f"      primitive_poses: [{{position: {part[0]}, orientation: {part[1]}}}]\n"
    )
    number_lines = lambda pose: " ".join(map(repr, pose[0])) + "\n" + " ".join(map(repr, pose[1]))  # noqa: E731
    scene_text_ = f"s\n* thing\n{number_lines(whole)}\n1\n{words}\n{number_lines(part)}\n0 0 0 0\n0\n.\n"
    source = RobotSource(urdf=_toy(folder), tip_link="l3")
    expected = _expected(_pose(*whole), _pose(*part))
    for name, text in (("s.yaml", yaml_text), ("s.scene", scene_text_)):
        shape = moveit_scene(_write(folder, name, text), None, source, folder / "o.yaml").data["obstacles"][0][kind]
        _assert_placed(shape, *expected)


SCENE_TEXT_NEWER = """shapes
* rack
1 0.5 0.2
0 0 0.3826834323650898 0.9238795325112867
3
box
0.4 0.2 0.1
0.1 0 0
0 0 0 1
0 0 0 0
sphere
0.05
0 0.2 0.1
0 0 0 1
0.5 0.5 0.5 1
cylinder
0.02 0.3
0 -0.1 0.3
0.2588190451025208 0 0 0.9659258262890683
0 0 0 0
0
* ball
0 0 0
0 0 0 1
1
sphere
0.1
-1 0 0.5
0 0 0 1
0 0 0 0
1
grasp
0 0 0
0 0 0 1
.
"""


def _older() -> str:
    """The same scene in MoveIt's older .scene format: no object poses (each shape's pose in the world,
    composed here with scipy), no subframes."""
    rack = _pose([1.0, 0.5, 0.2], [0, 0, 0.3826834323650898, 0.9238795325112867])
    shapes = [
        ("box\n0.4 0.2 0.1", _pose([0.1, 0, 0], [0, 0, 0, 1])),
        ("sphere\n0.05", _pose([0, 0.2, 0.1], [0, 0, 0, 1])),
        ("cylinder\n0.02 0.3", _pose([0, -0.1, 0.3], [0.2588190451025208, 0, 0, 0.9659258262890683])),
    ]
    lines = ["shapes", "* rack", "3"]
    for text, pose in shapes:
        centre, rotation = _expected(rack, pose)
        lines += [
            text,
            " ".join(repr(float(v)) for v in centre),
            " ".join(repr(float(v)) for v in rotation.as_quat()),
            "0 0 0 0",
        ]
    lines += ["* ball", "1", "sphere", "0.1", "-1 0 0.5", "0 0 0 1", "0 0 0 0", "."]
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize("form", ["newer", "older"])
def test_a_scene_file_gives_the_same_obstacles_as_the_yaml(tmp_path, form):
    urdf = _toy(tmp_path)
    source = RobotSource(urdf=urdf, tip_link="hand")
    from_yaml = moveit_scene(_write(tmp_path, "s.yaml", SHAPES_SCENE), None, source, tmp_path / "a.yaml").data[
        "obstacles"
    ]
    text = SCENE_TEXT_NEWER if form == "newer" else _older()
    from_text = moveit_scene(_write(tmp_path, "s.scene", text), None, source, tmp_path / "b.yaml").data["obstacles"]
    assert [o["name"] for o in from_text] == [o["name"] for o in from_yaml]
    for a, b in zip(from_text, from_yaml):
        shape_a, shape_b = a.get("box") or a.get("cylinder") or a, b.get("box") or b.get("cylinder") or b
        np.testing.assert_allclose(shape_a["center"], shape_b["center"], atol=1e-12)
        if "rpy" in shape_b:
            np.testing.assert_allclose(
                Rotation.from_euler("xyz", shape_a["rpy"], degrees=True).as_matrix(),
                Rotation.from_euler("xyz", shape_b["rpy"], degrees=True).as_matrix(),
                atol=1e-12,
            )


# ------------------------------------------------------------ joints


def test_joints_are_matched_by_name(tmp_path):
    """The start state in any order: the chain's joints become home (degrees, in the chain's order), the
    request's values over the scene's; a prismatic joint off the chain becomes joint_values in metres."""
    request = _write(
        tmp_path,
        "r.yaml",
        """start_state:
  joint_state:
    name: [wrist, elbow, finger_joint]
    position: [1.0, -0.25, 0.03]
goal_constraints:
  - joint_constraints:
      - {joint_name: elbow, position: 0.5}
      - {joint_name: wrist, position: -3.5}
      - {joint_name: shoulder, position: 1.5}
""",
    )
    imported = moveit_scene(
        _write(tmp_path, "s.yaml", SHAPES_SCENE), request, RobotSource(urdf=_toy(tmp_path)), tmp_path / "o.yaml"
    )
    arm = imported.data["arm"]
    assert (arm["base_link"], arm["tip_link"]) == ("base", "l3")  # the deepest joint of the goal: wrist
    np.testing.assert_allclose(np.radians(arm["home"]), [0.25, -0.25, 1.0], rtol=0, atol=1e-15)
    assert arm["joint_values"] == {"finger_joint": 0.03}
    np.testing.assert_allclose(np.radians(imported.data["goals"][0]["joints"]), [1.5, 0.5, -3.5], rtol=0, atol=1e-15)
    assert arm["urdf"] == "robot/toy.urdf"  # relative to the output's folder


def test_a_continuous_joint_beyond_a_turn_is_taken_within_one(tmp_path):
    request = _write(tmp_path, "r.yaml", POSE_REQUEST.replace("[0.1, 0.2, 0.3]", "[0.1, 0.2, 7.0]"))
    imported = moveit_scene(
        _write(tmp_path, "s.yaml", BOXES_SCENE), request, RobotSource(urdf=_toy(tmp_path)), tmp_path / "o.yaml"
    )
    wrist = imported.data["arm"]["home"][2]
    assert -180 <= wrist <= 180 and np.isclose(np.radians(wrist) % (2 * np.pi), 7.0 % (2 * np.pi), rtol=0, atol=1e-12)
    assert any("continuous joint 'wrist'" in n for n in imported.notes)


def test_a_joint_off_the_chain_outside_its_limits_is_moved_within_them_and_noted(tmp_path):
    text = SHAPES_SCENE.replace("position: [-0.5, 0.02, 0.25]", "position: [-0.5, 0.065, 0.25]")
    imported = moveit_scene(
        _write(tmp_path, "s.yaml", text), None, RobotSource(urdf=_toy(tmp_path), tip_link="l3"), tmp_path / "o.yaml"
    )
    assert imported.data["arm"]["joint_values"] == {"finger_joint": 0.04}
    assert any("finger_joint" in n and "outside its limits" in n and n.startswith("note: ") for n in imported.notes)
    assert imported.data["goals"] == [{"joints": imported.data["arm"]["home"]}]  # no request: stay


def test_the_srdf_group_gives_the_chain(tmp_path):
    srdf = _write(
        tmp_path,
        "toy.srdf",
        '<robot name="toy"><group name="hand_group"><link name="finger"/></group>'
        '<group name="arm"><joint name="shoulder"/><joint name="elbow"/></group></robot>',
    )
    request = _write(tmp_path, "r.yaml", "group_name: arm\n")
    imported = moveit_scene(
        _write(tmp_path, "s.yaml", SHAPES_SCENE),
        request,
        RobotSource(urdf=_toy(tmp_path), srdf=srdf),
        tmp_path / "o.yaml",
    )
    assert imported.data["arm"]["tip_link"] == "l2"  # the child of the group's last joint
    assert imported.data["arm"]["self_collision"] == {"srdf": "toy.srdf"}
    assert len(imported.data["arm"]["home"]) == 2


# ------------------------------------------------------------ a pose goal, validated now


POSE_REQUEST = """start_state:
  joint_state:
    name: [shoulder, elbow, wrist]
    position: [0.1, 0.2, 0.3]
goal_constraints:
  - position_constraints:
      - header: {frame_id: base}
        link_name: hand
        target_point_offset: {x: 0.0, y: 0.0, z: 0.05}
        constraint_region:
          primitives:
            - {type: 2, dimensions: [0.01]}
          primitive_poses:
            - position: {x: 0.3, y: 0.1, z: 0.5}
    orientation_constraints:
      - header: {frame_id: ""}
        link_name: hand
        orientation: {x: 0.0, y: 0.7071067811865476, z: 0.0, w: 0.7071067811865476}
        absolute_x_axis_tolerance: 0.01
"""

BOXES_SCENE = """world:
  collision_objects:
    - id: table
      primitives:
        - {type: box, dimensions: [0.5, 0.5, 0.02]}
      primitive_poses:
        - {position: [1.2, 0.0, 0.3]}
    - id: lamp
      primitives:
        - {type: sphere, dimensions: [0.05]}
      primitive_poses:
        - {position: [-1.0, 0.3, 0.6]}
"""


def test_a_pose_constraint_becomes_a_pose_goal_that_validates(tmp_path):
    out = tmp_path / "scenes" / "imported.yaml"
    imported = import_moveit(
        _write(tmp_path, "s.yaml", BOXES_SCENE),
        _write(tmp_path, "r.yaml", POSE_REQUEST),
        RobotSource(urdf=_toy(tmp_path)),
        out,
    )
    assert imported.data["goals"] == [
        {
            "position": [0.3, 0.1, 0.5],
            "orientation": {"quaternion_wxyz": [0.7071067811865476, 0.0, 0.7071067811865476, 0.0]},
        }
    ]
    assert imported.data["arm"]["tool"] == {"xyz": [0.0, 0.0, 0.05]}  # the constraint's point on the link
    assert imported.data["arm"]["tip_link"] == "hand"  # the constrained link, fixed to the chain's end
    scene = _loaded_without_names(imported, out)
    assert scene.model.arm.urdf == "../robot/toy.urdf"
    np.testing.assert_allclose(np.radians(scene.model.arm.home), [0.1, 0.2, 0.3], rtol=0, atol=1e-15)
    assert [o.kind for o in scene.model.obstacles] == ["box", "sphere"]


@pytest.mark.parametrize(
    ("scene", "request_", "expected"),
    [
        (POSE_REQUEST, None, "r.yaml:1: start_state: is not a field of a MoveIt planning scene"),
        ("version: 1\nname: s\narm: {links: [1, 1]}\ngoals: [[1, 0, 1]]\n", None, "looks like an armanim scene"),
        (BOXES_SCENE + "goals: [[1, 0, 1]]\n", None, "r.yaml:13: goals: is not a field of a MoveIt planning scene"),
        (BOXES_SCENE, BOXES_SCENE, "q.yaml:1: world: is not a field of a MoveIt motion plan request"),
    ],
)
def test_a_file_of_another_kind_is_refused_at_its_first_foreign_key(tmp_path, scene, request_, expected):
    """Campaign 11: a motion plan request, or an armanim scene, given as the planning scene was read as an
    empty world (its keys ignored), exit 0; a planning scene given as the request, as no goal. A planning
    scene's top-level keys are PlanningScene's (or PlanningSceneWorld's) fields; a request has at least one
    of MotionPlanRequest's."""
    with pytest.raises(SceneError) as info:
        import_moveit(
            _write(tmp_path, "r.yaml", scene),
            _write(tmp_path, "q.yaml", request_) if request_ else None,
            RobotSource(urdf=_toy(tmp_path)),
            tmp_path / "out.yaml",
        )
    assert expected in info.value.report(), info.value.report()
    assert not (tmp_path / "out.yaml").exists()


def _loaded_without_names(imported, out: Path):
    """The imported scene through the loader, its obstacles' ``name`` left out: the one form here that another
    part of issue 49 adds (boxes, spheres, a pose goal, the tool, the SRDF are on this branch already)."""
    data = {
        **imported.data,
        "obstacles": [{k: v for k, v in o.items() if k != "name"} for o in imported.data["obstacles"]],
    }
    plain = out.with_name("plain.yaml")
    plain.write_text(scene_text(data, ["s.yaml"]))
    return load_scene(plain)


def test_a_pose_goal_on_a_bundled_robot_validates(tmp_path):
    request = (
        POSE_REQUEST.replace(
            "[shoulder, elbow, wrist]",
            "[panda_joint1, panda_joint2, panda_joint3, panda_joint4, panda_joint5, panda_joint6, panda_joint7]",
        )
        .replace("[0.1, 0.2, 0.3]", "[0, -0.785, 0, -2.356, 0, 1.571, 0.785]")
        .replace("hand", "panda_link8")
        .replace("base", "world")
    )
    out = tmp_path / "panda.yaml"
    imported = import_moveit(
        _write(tmp_path, "s.yaml", BOXES_SCENE), _write(tmp_path, "r.yaml", request), RobotSource(robot="panda"), out
    )
    assert imported.data["arm"]["robot"] == "panda" and imported.data["arm"]["tip_link"] == "panda_link8"
    assert "base_link" not in imported.data["arm"]  # the robot's own
    assert _loaded_without_names(imported, out).model.arm.joint_count == 7


def test_an_output_file_whose_stem_is_no_run_name_gets_a_name(tmp_path):
    out = tmp_path / "my shelf.yaml"
    imported = import_moveit(
        _write(tmp_path, "s.yaml", BOXES_SCENE),
        _write(tmp_path, "r.yaml", POSE_REQUEST),
        RobotSource(urdf=_toy(tmp_path)),
        out,
    )
    assert imported.data["name"] == "my-shelf"
    assert _loaded_without_names(imported, out).name == "my-shelf"


def test_a_scene_file_on_a_bundled_robot_starts_at_the_robots_own_home(tmp_path):
    imported = moveit_scene(
        _write(tmp_path, "s.scene", SCENE_TEXT_NEWER), None, RobotSource(robot="panda"), tmp_path / "o.yaml"
    )
    assert imported.data["arm"]["home"] == [
        0.0,
        -45.0,
        0.0,
        -135.0,
        0.0,
        90.0,
        45.0,
    ]  # robot.yaml's, not MoveIt's zeros
    assert imported.data["goals"] == [{"joints": imported.data["arm"]["home"]}]
    assert [n for n in imported.notes if "no start value" in n] == [
        "note: no start value for 'panda_joint1', 'panda_joint2', 'panda_joint3', 'panda_joint4', 'panda_joint5', "
        "'panda_joint6', 'panda_joint7': 0, -45, 0, -135, 0, 90, 45 degrees (the robot's own home)"
    ]


def test_the_text_reads_back_as_the_scene(tmp_path):
    imported = moveit_scene(
        _write(tmp_path, "s.yaml", SHAPES_SCENE),
        _write(tmp_path, "r.yaml", POSE_REQUEST),
        RobotSource(urdf=_toy(tmp_path)),
        tmp_path / "o.yaml",
    )
    assert imported.text.startswith(MARKER)
    assert yaml.safe_load(imported.text) == imported.data  # every float exactly


# ------------------------------------------------------------ the real MotionBenchMaker files


def test_a_vendored_mbm_problem_with_vamps_panda(tmp_path):
    imported = moveit_scene(
        DATA / "bookshelf_small_panda-scene0001.yaml",
        DATA / "bookshelf_small_panda-request0001.yaml",
        RobotSource(urdf=DATA / "panda_spherized.urdf", srdf=DATA / "panda.srdf"),
        tmp_path / "o.yaml",
    )
    _assert_mbm(
        imported.data, DATA / "bookshelf_small_panda-scene0001.yaml", DATA / "bookshelf_small_panda-request0001.yaml"
    )
    assert imported.data["arm"]["tip_link"] == "panda_link8"  # panda.srdf's panda_arm chain
    assert sum("fixed in" in n for n in imported.notes) == 2  # VAMP's fingers are fixed joints


def _assert_mbm(data: dict, scene: Path, request: Path) -> None:
    """The written scene against the MBM files read with plain PyYAML: home and goal in degrees equal to the
    request's radians, one obstacle per primitive, cylinders where the scene has them."""
    raw_scene, raw_request = yaml.safe_load(scene.read_text()), yaml.safe_load(request.read_text())
    start = dict(
        zip(raw_request["start_state"]["joint_state"]["name"], raw_request["start_state"]["joint_state"]["position"])
    )
    names = [f"panda_joint{k}" for k in range(1, 8)]
    assert len(data["arm"]["home"]) == 7
    np.testing.assert_allclose(np.radians(data["arm"]["home"]), [start[n] for n in names], rtol=0, atol=1e-15)
    goal = {c["joint_name"]: c["position"] for c in raw_request["goal_constraints"][0]["joint_constraints"]}
    np.testing.assert_allclose(np.radians(data["goals"][0]["joints"]), [goal[n] for n in names], rtol=0, atol=1e-15)
    kinds = [p["type"] for o in raw_scene["world"]["collision_objects"] for p in o["primitives"]]
    assert [("cylinder" if "cylinder" in o else "box" if "box" in o else "sphere") for o in data["obstacles"]] == kinds
    assert "cylinder" in kinds
    ids = [o["id"] for o in raw_scene["world"]["collision_objects"]]
    assert [o["name"] for o in data["obstacles"]] == ids
    assert data["solver"] == {"clearance": 0.0005, "self_clearance": 0.0005}


@pytest.mark.skipif(
    not (SHARED_MBM / "panda" / "problems.tar.bz2").is_file(), reason="the shared MBM archives are not here"
)
def test_a_problem_from_the_mbm_archive(tmp_path):
    with tarfile.open(SHARED_MBM / "panda" / "problems.tar.bz2") as archive:
        for name in ("scene", "request"):
            member = archive.getmember(f"problems/bookshelf_thin_panda/{name}0042.yaml")
            (tmp_path / f"{name}.yaml").write_bytes(archive.extractfile(member).read())
    urdf, srdf = SHARED_MBM / "panda" / "panda_spherized.urdf", SHARED_MBM / "panda" / "panda.srdf"
    out = tmp_path / "out" / "thin.yaml"
    imported = import_moveit(tmp_path / "scene.yaml", tmp_path / "request.yaml", RobotSource(urdf=urdf, srdf=srdf), out)
    _assert_mbm(imported.data, tmp_path / "scene.yaml", tmp_path / "request.yaml")
    assert yaml.safe_load(out.read_text()) == imported.data
    assert imported.data["arm"]["urdf"] == os.path.relpath(urdf, out.parent)


def test_the_vendored_problems_are_the_archives(tmp_path):
    if not (SHARED_MBM / "panda" / "problems.tar.bz2").is_file():
        pytest.skip("the shared MBM archives are not here")
    for robot, family in (("panda", "bookshelf_small_panda"), ("ur5", "box_ur5")):
        with tarfile.open(SHARED_MBM / robot / "problems.tar.bz2") as archive:
            for name in ("scene", "request"):
                member = archive.extractfile(f"problems/{family}/{name}0001.yaml").read()
                assert (DATA / f"{family}-{name}0001.yaml").read_bytes() == member


def test_the_ur5_problem_starts_at_the_urdfs_root(tmp_path):
    if not (SHARED_MBM / "ur5" / "ur5_spherized.urdf").is_file():
        pytest.skip("the shared MBM robots are not here")
    imported = moveit_scene(
        DATA / "box_ur5-scene0001.yaml",
        DATA / "box_ur5-request0001.yaml",
        RobotSource(urdf=SHARED_MBM / "ur5" / "ur5_spherized.urdf", srdf=SHARED_MBM / "ur5" / "ur5.srdf"),
        tmp_path / "o.yaml",
    )
    arm = imported.data["arm"]
    assert (arm["base_link"], arm["tip_link"]) == ("offset_link", "ee_link")  # no joint moves offset_link -> base_link
    assert "base" not in arm and len(arm["home"]) == 6 and len(imported.data["goals"][0]["joints"]) == 6


# ------------------------------------------------------------ errors


@pytest.fixture()
def moveit_command(cli, tmp_path, monkeypatch):
    """``armanim import moveit ARGS`` through the Typer app in-process, run from ``tmp_path`` (the
    files named relative to it, as from a shell there); :func:`_run` is the installed command."""
    monkeypatch.chdir(tmp_path)
    return lambda *args: cli("import", "moveit", *args)


def _run(*args, cwd: Path) -> subprocess.CompletedProcess:
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src"))
    return subprocess.run(
        [armanim_exe(), "import", "moveit", *map(str, args)],
        cwd=cwd,
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )


MESH = (
    BOXES_SCENE
    + """    - id: bowl
      meshes:
        - {triangles: [], vertices: []}
"""
)
CONE = BOXES_SCENE.replace("{type: sphere, dimensions: [0.05]}", "{type: 4, dimensions: [0.1, 0.05]}")
PLANE = (
    BOXES_SCENE
    + """    - id: floor
      planes:
        - {coef: [0, 0, 1, 0]}
"""
)
BROKEN = BOXES_SCENE.replace(
    "      primitive_poses:\n        - {position: [1.2", "     primitive_poses: [\n        - {position: [1.2"
)
UNKNOWN_JOINT = POSE_REQUEST.replace("[shoulder, elbow, wrist]", "[shoulder, elbow, wirst]")
UNKNOWN_LINK = POSE_REQUEST.replace("link_name: hand", "link_name: hnad")
CONE_TEXT = SCENE_TEXT_NEWER.replace("sphere\n0.1\n", "cone\n0.1 0.2\n")
BAD_NUMBER_TEXT = SCENE_TEXT_NEWER.replace("0.4 0.2 0.1", "0.4 wide 0.1")


@pytest.mark.parametrize(
    "case, scene, motion, file, line, words",
    [
        ("mesh", MESH, POSE_REQUEST, "s.yaml", 14, "has a mesh"),
        ("cone", CONE, POSE_REQUEST, "s.yaml", 10, "has a cone"),
        ("plane", PLANE, POSE_REQUEST, "s.yaml", 14, "has a plane"),
        ("malformed yaml", BROKEN, POSE_REQUEST, "s.yaml", None, "not valid YAML"),
        ("unknown joint", BOXES_SCENE, UNKNOWN_JOINT, "r.yaml", 3, "joint 'wirst' is not a joint of"),
        ("unknown link", BOXES_SCENE, UNKNOWN_LINK, "r.yaml", 8, "link 'hnad' is not a link of"),
        ("cone in a .scene", CONE_TEXT, POSE_REQUEST, "s.scene", 26, "has a cone"),
        ("not a number in a .scene", BAD_NUMBER_TEXT, POSE_REQUEST, "s.scene", 7, "'wide' is not a number"),
    ],
)
def test_bad_input_is_file_line_message_and_exit_2(moveit_command, tmp_path, case, scene, motion, file, line, words):
    name = "s.scene" if file == "s.scene" else "s.yaml"
    _write(tmp_path, name, scene)
    _write(tmp_path, "r.yaml", motion)
    _toy(tmp_path)
    result = moveit_command(name, "--request", "r.yaml", "--urdf", "robot/toy.urdf", "--out", "o.yaml")
    assert result.exit_code == 2, result.stderr
    assert "Traceback" not in result.stderr and words in result.stderr, result.stderr
    first = result.stderr.strip().splitlines()[0]
    assert first.startswith(f"{file}:{line}:" if line is not None else f"{file}:"), first
    assert not (tmp_path / "o.yaml").exists()


def test_a_file_it_did_not_write_is_not_replaced(moveit_command, tmp_path):
    _write(tmp_path, "s.yaml", BOXES_SCENE)
    _write(tmp_path, "r.yaml", POSE_REQUEST)
    _toy(tmp_path)
    mine = _write(tmp_path, "mine.yaml", "version: 1\n# my own scene\n")
    result = moveit_command("s.yaml", "--request", "r.yaml", "--urdf", "robot/toy.urdf", "--out", "mine.yaml")
    assert result.exit_code == 3 and "did not write" in result.stderr, result.stderr
    assert mine.read_text() == "version: 1\n# my own scene\n"
    first = moveit_command("s.yaml", "--request", "r.yaml", "--urdf", "robot/toy.urdf", "--out", "o.yaml")
    again = moveit_command("s.yaml", "--request", "r.yaml", "--urdf", "robot/toy.urdf", "--out", "o.yaml")
    assert first.exit_code == again.exit_code == 0, first.stderr + again.stderr
    assert again.stdout.strip() == "o.yaml" and (tmp_path / "o.yaml").read_text().startswith(MARKER)
    edited = (tmp_path / "o.yaml").read_text().replace("version: 1", "version: 1\nname: mine")
    (tmp_path / "o.yaml").write_text(edited)  # the user's edit, the first line kept
    result = moveit_command("s.yaml", "--request", "r.yaml", "--urdf", "robot/toy.urdf", "--out", "o.yaml")
    assert result.exit_code == 3 and "changed since" in result.stderr, result.stderr
    assert (tmp_path / "o.yaml").read_text() == edited
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".")] == []  # no temporary left


def test_an_out_under_a_folder_that_is_a_link_to_itself_is_refused_without_a_traceback(moveit_command, tmp_path):
    """Campaign 18: ``--out x/o.yaml``, ``x`` a link to itself, with ``--urdf`` (whose path the
    scene names relative to the output's folder): ``RuntimeError: Symlink loop from '.../x'``
    (Python 3.11's Path.resolve), exit 1. Now the write is refused (exit 3), the link as it was."""
    _write(tmp_path, "s.yaml", BOXES_SCENE)
    _write(tmp_path, "r.yaml", POSE_REQUEST)
    _toy(tmp_path)
    os.symlink("x", tmp_path / "x")
    result = moveit_command("s.yaml", "--request", "r.yaml", "--urdf", "robot/toy.urdf", "--out", "x/o.yaml")
    assert result.exit_code == 3 and "x/o.yaml" in result.stderr, result.output
    assert "Traceback" not in result.output and "RuntimeError" not in result.output
    assert os.readlink(tmp_path / "x") == "x"


def test_the_command_prints_the_path_and_its_notes_on_stderr(tmp_path):
    result = _run(
        DATA / "bookshelf_small_panda-scene0001.yaml",
        "--request",
        DATA / "bookshelf_small_panda-request0001.yaml",
        "--urdf",
        DATA / "panda_spherized.urdf",
        "--srdf",
        DATA / "panda.srdf",
        "--out",
        "shelf.yaml",
        cwd=tmp_path,
    )
    assert result.returncode == 0, result.stderr
    assert result.stdout == "shelf.yaml\n"
    notes = result.stderr.splitlines()
    assert len(notes) == 2 and all(n.startswith("note: ") and "is fixed in" in n for n in notes), notes
    written = yaml.safe_load((tmp_path / "shelf.yaml").read_text())
    assert written["arm"]["urdf"] == os.path.relpath(DATA / "panda_spherized.urdf", tmp_path)


def test_a_goal_joint_off_the_chain_and_a_missing_one_are_errors(tmp_path):
    scene = _write(tmp_path, "s.yaml", BOXES_SCENE)
    request = _write(
        tmp_path,
        "r.yaml",
        "goal_constraints:\n  - joint_constraints:\n      - {joint_name: shoulder, position: 0}\n"
        "      - {joint_name: finger_joint, position: 0.01}\n",
    )
    with pytest.raises(SceneError, match="'finger_joint' is not one of the chain's joints"):
        moveit_scene(scene, request, RobotSource(urdf=_toy(tmp_path), tip_link="l3"), tmp_path / "o.yaml")
    request.write_text("goal_constraints:\n  - joint_constraints:\n      - {joint_name: shoulder, position: 0}\n")
    with pytest.raises(SceneError, match="sets no position for 'elbow', 'wrist'"):
        moveit_scene(scene, request, RobotSource(urdf=_toy(tmp_path), tip_link="l3"), tmp_path / "o.yaml")


def test_a_start_beyond_a_limit_of_the_chain_is_an_error_with_its_line(tmp_path):
    request = _write(tmp_path, "r.yaml", POSE_REQUEST.replace("[0.1, 0.2, 0.3]", "[0.1, 2.5, 0.3]"))
    with pytest.raises(SceneError) as info:
        moveit_scene(
            _write(tmp_path, "s.yaml", BOXES_SCENE), request, RobotSource(urdf=_toy(tmp_path)), tmp_path / "o.yaml"
        )
    assert info.value.report().startswith(
        f"{request}:3: start_state.joint_state.name[1]: joint 'elbow' at 2.5 is outside its limits [-2.0, 2.0]"
    )


def test_a_start_on_a_limit_is_kept_exactly(tmp_path):
    request = _write(tmp_path, "r.yaml", POSE_REQUEST.replace("[0.1, 0.2, 0.3]", "[0.1, -2.0, 0.3]"))
    imported = moveit_scene(
        _write(tmp_path, "s.yaml", BOXES_SCENE), request, RobotSource(urdf=_toy(tmp_path)), tmp_path / "o.yaml"
    )
    assert np.radians(imported.data["arm"]["home"][1]) == -2.0  # MoveIt's bounds are inclusive


def test_a_group_the_srdf_lacks_and_a_frame_that_moves_are_errors_with_their_lines(tmp_path):
    srdf = _write(
        tmp_path,
        "toy.srdf",
        '<robot name="toy"><group name="arm"><chain base_link="base" tip_link="l3"/></group></robot>',
    )
    request = _write(tmp_path, "r.yaml", "start_state: {}\ngroup_name: manipulator\n")
    scene = _write(tmp_path, "s.yaml", BOXES_SCENE)
    with pytest.raises(SceneError) as info:
        moveit_scene(scene, request, RobotSource(urdf=_toy(tmp_path), srdf=srdf), tmp_path / "o.yaml")
    assert info.value.report().startswith(f"{request}:2: group_name: group 'manipulator' is not a group of")
    moving = _write(
        tmp_path, "m.yaml", BOXES_SCENE.replace("    - id: lamp\n", "    - id: lamp\n      header: {frame_id: l2}\n")
    )
    with pytest.raises(SceneError) as info:
        moveit_scene(moving, None, RobotSource(urdf=_toy(tmp_path), tip_link="l3"), tmp_path / "o.yaml")
    assert info.value.report().startswith(
        f"{moving}:9: world.collision_objects[1].header.frame_id: frame 'l2' is not the planning frame"
    )
    fixed = _write(
        tmp_path, "f.yaml", BOXES_SCENE.replace("    - id: lamp\n", "    - id: lamp\n      header: {frame_id: base}\n")
    )
    assert moveit_scene(fixed, None, RobotSource(urdf=_toy(tmp_path), tip_link="l3"), tmp_path / "o.yaml").data[
        "obstacles"
    ][1]["center"] == [-1.0, 0.3, 0.6]


def test_a_scene_file_without_its_end_is_an_error(tmp_path):
    scene = _write(tmp_path, "s.scene", SCENE_TEXT_NEWER[: SCENE_TEXT_NEWER.index("* ball")])
    with pytest.raises(SceneError, match="a .scene file ends with a line '.'"):
        moveit_scene(scene, None, RobotSource(urdf=_toy(tmp_path), tip_link="l3"), tmp_path / "o.yaml")


def test_the_robot_flags_must_fit(tmp_path):
    scene = _write(tmp_path, "s.yaml", BOXES_SCENE)
    with pytest.raises(UsageError, match="exactly one of --robot"):
        moveit_scene(scene, None, RobotSource(), tmp_path / "o.yaml")
    with pytest.raises(UsageError, match="not bundled"):
        moveit_scene(scene, None, RobotSource(robot="r2d2"), tmp_path / "o.yaml")
    with pytest.raises(UsageError, match="tip_link 'nowhere' is not a link of"):
        moveit_scene(
            scene,
            _write(tmp_path, "r.yaml", POSE_REQUEST),
            RobotSource(urdf=_toy(tmp_path), tip_link="nowhere"),
            tmp_path / "o.yaml",
        )


def test_import_moveit_help_shows_an_example(cli):
    result = cli("import", "moveit", "--help")
    assert result.exit_code == 0
    assert "Example: armanim import moveit" in " ".join(result.stdout.split())


def test_a_prismatic_joint_on_the_chain_keeps_metres(tmp_path):
    """A lift on the arm's path: its start value, its MoveIt default and its joint goal are written in
    metres (home and the goal's joints: degrees for the others), as the request gives them; the
    scene loads and its home is the request's pose."""
    urdf = tmp_path / "robot" / "lift.urdf"
    urdf.parent.mkdir()
    urdf.write_text(
        TOY_URDF.replace('<joint name="elbow" type="revolute"', '<joint name="elbow" type="prismatic"').replace(
            '<axis xyz="0 1 0"/><limit lower="-2" upper="2"', '<axis xyz="0 0 1"/><limit lower="-0.2" upper="0.3"'
        )
    )
    request = _write(
        tmp_path,
        "r.yaml",
        """start_state:
  joint_state:
    name: [shoulder, elbow]
    position: [0.5, 0.125]
goal_constraints:
  - joint_constraints:
      - {joint_name: elbow, position: -0.15}
      - {joint_name: wrist, position: 1.0}
      - {joint_name: shoulder, position: -1.0}
""",
    )
    out = tmp_path / "scenes" / "lift.yaml"
    imported = import_moveit(_write(tmp_path, "s.yaml", BOXES_SCENE), request, RobotSource(urdf=urdf), out)
    arm = imported.data["arm"]
    assert arm["home"][1] == 0.125 and arm["home"][2] == 0.0  # metres; the wrist's default 0 (no start value)
    np.testing.assert_allclose(np.radians(arm["home"][0]), 0.5, rtol=0, atol=1e-15)
    joints = imported.data["goals"][0]["joints"]
    assert joints[1] == -0.15
    np.testing.assert_allclose(np.radians([joints[0], joints[2]]), [-1.0, 1.0], rtol=0, atol=1e-15)
    scene = _loaded_without_names(imported, out)
    assert scene.model.arm.home[1] == 0.125 and scene.model.goals[0].joints[1] == -0.15
