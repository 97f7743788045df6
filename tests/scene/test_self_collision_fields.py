"""The scene's self-collision fields: their forms, unknown link names as scene errors, and SRDF
parsing (against pinocchio)."""

from __future__ import annotations

import pytest

from armanim.errors import SceneError
from armanim.scene.convert import scene_to_problem
from armanim.scene.loader import load_scene


def scene_dict(**arm):
    return {
        "version": 1,
        "arm": {"links": [1.0, 1.0, 1.0, 1.0], "axes": ["z", "z", "z", "z"], "direction": "x", **arm},
        "goals": [[2.0, 1.0, 0.0]],
        "solver": {"clearance": 0.02},
    }


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
    listed = scene_to_problem(
        load_scene(
            write_scene(tmp_path, scene_dict(self_collision={"auto": True, "allow": [["link1", "link3"]]}))
        ).model
    )
    assert ("link1", "link3") not in listed.self_pairs.names and ("link1", "link3", "User") in listed.self_pairs.allowed
    checked = scene_to_problem(
        load_scene(
            write_scene(
                tmp_path,
                scene_dict(self_collision={"auto": True, "allow": [["link1", "link3"]], "check": [["link3", "link1"]]}),
            )
        ).model
    )
    assert ("link1", "link3") in checked.self_pairs.names  # check wins over allow
    # checking an adjacent pair, which touches at its joint: the home pose is an error naming the pair
    with pytest.raises(SceneError, match=r"arm: the home pose has link1 and link2 overlapping \(gap -0.5"):
        load_scene(write_scene(tmp_path, scene_dict(self_collision={"auto": True, "check": [["link1", "link2"]]})))


def test_unknown_link_names_are_scene_errors(tmp_path):
    with pytest.raises(SceneError, match=r"self_collision.allow\[0\] names 'link9'"):
        load_scene(write_scene(tmp_path, scene_dict(self_collision={"auto": True, "allow": [["link1", "link9"]]})))
    (tmp_path / "arm.srdf").write_text(
        '<robot name="r">\n<disable_collisions link1="link1" link2="link3"/>\n'
        '<disable_collisions link1="link1" link2="nope" reason="Never"/>\n</robot>\n'
    )
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
        for k in range(count)
    )
    joints = "\n".join(
        f'  <joint name="j{k}" type="revolute"><parent link="{"base" if k == 0 else f"l{k - 1}"}"/><child link="l{k}"/>'
        f'<origin xyz="0 0 {0.0 if k == 0 else 0.4}"/><axis xyz="{"0 0 1" if k % 2 == 0 else "0 1 0"}"/>'
        f'<limit lower="-2.9" upper="2.9" effort="1" velocity="1"/></joint>'
        for k in range(count)
    )
    return CHAIN_URDF.format(links=links, joints=joints)


def test_srdf_pairs_match_pinocchio(tmp_path):
    pin = pytest.importorskip("pinocchio")
    (tmp_path / "chain.urdf").write_text(chain_urdf())
    (tmp_path / "chain.srdf").write_text(
        '<?xml version="1.0"?>\n<robot name="chain">\n'
        '  <group name="arm"><chain base_link="base" tip_link="l4"/></group>\n'
        '  <disable_collisions link1="l0" link2="l1" reason="Adjacent"/>\n'
        '  <disable_collisions link1="l1" link2="l2" reason="Adjacent"/>\n'
        '  <disable_collisions link1="l2" link2="l3" reason="Adjacent"/>\n'
        '  <disable_collisions link1="l2" link2="l0" reason="Never"/>\n'
        '  <disable_collisions link1="l3" link2="l4"/>\n'
        '  <disable_collisions link1="base" link2="l4" reason="Never"/>\n</robot>\n'
    )
    scene = {
        "version": 1,
        "arm": {"urdf": "chain.urdf", "self_collision": {"srdf": "chain.srdf"}},
        "goals": [[0.3, 0.0, 0.8]],
    }
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
