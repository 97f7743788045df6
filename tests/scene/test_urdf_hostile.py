"""Hostile URDF files (issue 36): numbers bounded as a scene's with their line, written as URDF
writes them, axes of any finite size, ranges narrower than the planner's buffer, and names from
the file printed escaped.

Each test is named in docs/reliability.md, which it keeps true.
"""

from __future__ import annotations

import numpy as np
import pytest

from armanim.arm.geometry import unit_vector
from armanim.errors import SceneError
from armanim.scene.urdf import parse_urdf


def urdf(origin="0 0 0.3", axis="0 1 0", lower="-2", upper="2", size='radius="0.03" length="0.3"') -> bytes:
    links = "".join(
        f'<link name="l{i}"><collision><geometry><cylinder {size}/></geometry></collision></link>' for i in range(3)
    )
    joints = "".join(
        f'<joint name="j{i}" type="revolute"><parent link="l{i}"/><child link="l{i + 1}"/><origin xyz="{origin}"/>'
        f'<axis xyz="{axis}"/><limit lower="{lower}" upper="{upper}"/></joint>\n'
        for i in range(2)
    )
    return f'<robot name="r">\n{links}\n{joints}</robot>'.encode()


@pytest.mark.parametrize(
    "kwargs",
    [
        {"origin": "1e200 0 0"},
        {"origin": "0 0 -2e9"},
        {"lower": "-1e308"},
        {"upper": "1e10"},
        {"size": 'radius="1e300" length="1"'},
        {"axis": "0 1e10 0"},
    ],
)
def test_urdf_numbers_are_bounded_as_a_scene_s_with_their_line(kwargs):
    with pytest.raises(SceneError, match=r"^r\.urdf:[23]: .*above 1e\+09 in size") as caught:
        parse_urdf(urdf(**kwargs), "r.urdf")
    assert len(caught.value.report()) < 300


@pytest.mark.parametrize("number", ["-1_0", "1_000", "0x10", "inf", "nan", "Infinity", "1e", "--1", "1.2.3", "١"])
def test_a_urdf_number_is_written_as_urdf_writes_it(number):
    with pytest.raises(SceneError, match="finite numbers"):
        parse_urdf(urdf(origin=f"0 0 {number}"), "r.urdf")


@pytest.mark.parametrize("axis", ["1e-200 0 0", "1e9 1e9 0", "0 0 -5e-324"])
def test_a_urdf_axis_of_any_finite_size_is_its_direction(axis):
    from armanim.arm.chain import serial_chain
    from armanim.scene.urdf import chain_joints

    robot = parse_urdf(urdf(axis=axis), "r.urdf")
    arm = serial_chain(np.eye(4), chain_joints(robot, "l0", "l2"), np.eye(4)).arm
    assert np.allclose(arm.axes, unit_vector([float(v) for v in axis.split()]))


def test_a_urdf_range_narrower_than_the_buffer_names_the_joint(tmp_path):
    (tmp_path / "r.urdf").write_bytes(urdf(lower="-1e-300", upper="1e-300"))
    (tmp_path / "s.yaml").write_text(
        "version: 1\narm: {urdf: r.urdf, base_link: l0, tip_link: l2}\ngoals: [[0.1, 0.1, 0.4]]\n"
    )
    from armanim.scene import load_scene

    with pytest.raises(SceneError, match=r"arm.limit_margin: the URDF's joint 'j0' has a range of 1.14592e-298 deg"):
        load_scene(tmp_path / "s.yaml")


def names_urdf(name: str) -> bytes:
    return urdf().replace(b'name="j1"', f'name="{name}"'.encode())


@pytest.mark.parametrize("name", ["j1)&#10;ok evil.yaml (all good", "a&#x202e;b", "c&#x9b;31m", "d&#13;e", "x" * 5000])
def test_names_from_files_are_printed_escaped(cli, tmp_path, name):
    (tmp_path / "r.urdf").write_bytes(names_urdf(name))
    (tmp_path / "s.yaml").write_text(
        "version: 1\narm: {urdf: r.urdf, base_link: l0, tip_link: l2}\ngoals: [[0.1, 0.1, 0.4]]\n"
    )
    result = cli("validate", tmp_path / "s.yaml")
    assert result.exit_code == 0 and len(result.stdout.splitlines()) == 1, result.stdout
    assert result.stdout.isprintable() or result.stdout[:-1].isprintable()
    assert len(result.stdout) < 700
