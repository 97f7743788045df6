"""The hostile fuzzer's short profile (issue 36, item 5): scenes from docs/scene.schema.json
with extreme floats and hostile strings, random URDFs, and fk/ik flags, each held to the
invariants of :mod:`fuzz_scenes`. In-process (milliseconds an example); a few examples go
through the installed command, whose stderr and files are checked as a user sees them.

The long profile is ``benchmarks/fuzz_bench.py`` (its count is in benchmarks/README.md);
``ARMANIM_FUZZ_EXAMPLES`` sets this one's count.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import pytest
from fuzz_scenes import (
    EXTREME_FLOATS,
    HOSTILE_STRINGS,
    check_command,
    check_scene_text,
    check_urdf_scene,
    hostile_scenes,
    scene_yaml,
    strict_json,
    urdf_scenes,
)
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

EXAMPLES = int(os.environ.get("ARMANIM_FUZZ_EXAMPLES", "150"))
HOSTILE = settings(max_examples=EXAMPLES, deadline=None, database=None, suppress_health_check=list(HealthCheck))


@HOSTILE
@given(hostile_scenes())
@example(  # Hypothesis 6.170.27's draw: the frame budget's path length overflowed (a RuntimeWarning, raised here)
    {
        "version": 1,
        "arm": {"links": [1.0], "max_joint_acceleration": 1.0, "self_collision": "auto"},
        "obstacles": [{"capsule": {"from": [0.0, 0.0, 0.0], "to": [0.0, 0.0, 0.0], "radius": 1.0}}],
        "goals": [
            {
                "path": {"line": [[1e308, 0.0, 0.0], [0.0, 0.0, 0.0]]},
                "speed": 1.0,
                "hold": 0.0,
                "retreat": {"distance": 1.0, "speed": 1.0},
            }
        ],
        "name": "",
    }
)
def test_schema_scenes_with_extreme_values_keep_the_invariants(data):
    check_scene_text(scene_yaml(data), "fuzz.yaml")


@HOSTILE
@given(urdf_scenes())
def test_random_urdfs_keep_the_invariants(pair):
    with tempfile.TemporaryDirectory() as tmp:
        check_urdf_scene(*pair, Path(tmp))


def _number() -> st.SearchStrategy:
    return st.one_of(
        st.floats(-3, 3),
        st.sampled_from(EXTREME_FLOATS).map(repr),
        st.sampled_from(["nan", "inf", "1e400", "-0.0", "1_0"]),
    )


@st.composite
def pose_flags(draw) -> list[str]:
    """fk or ik with random --links, --angles, --goal and --orientation values, and --json."""
    links = ",".join(str(draw(_number())) for _ in range(draw(st.integers(1, 4))))
    if draw(st.booleans()):
        angles = ",".join(str(draw(_number())) for _ in range(links.count(",") + 1))
        return ["fk", "--links", links, f"--angles={angles}", "--json"]
    goal = ",".join(str(draw(_number())) for _ in range(3))
    args = ["ik", "--links", links, f"--goal={goal}", "--json", "--max-iterations", "20"]
    if draw(st.booleans()):
        form = draw(st.sampled_from(["axis", "tool_axis", "rpy", "quat"]))
        count = {"axis": 4, "tool_axis": 3, "rpy": 3, "quat": 4}[form]
        args.append(f"--orientation={form}=" + ",".join(str(draw(_number())) for _ in range(count)))
    return args


@settings(max_examples=max(EXAMPLES // 3, 10), deadline=None, database=None, suppress_health_check=list(HealthCheck))
@given(pose_flags())
def test_fk_and_ik_json_is_strict_or_a_one_line_error(args):
    from typer.testing import CliRunner

    from armanim.cli import app

    result = CliRunner().invoke(app, args)
    assert result.exit_code in (0, 2), (args, result.output, result.exception)
    assert result.exception is None or isinstance(result.exception, SystemExit), (args, result.exception)
    if result.exit_code == 0:
        strict_json(result.stdout)
    else:
        assert len(result.stderr.strip().splitlines()) <= 3 and "Traceback" not in result.stderr, result.stderr


@pytest.mark.slow
@pytest.mark.parametrize(
    "form",
    [
        "tool_axis: [1e-320, 0, 0]",
        "tool_axis: [1e308, 0, 1e308]",
        "orientation: {axis: [1e-200, 1e-200, 0], angle: 30}",
    ],
)
def test_the_installed_command_keeps_the_invariants(tmp_path, form):
    scene = tmp_path / "s.yaml"
    scene.write_text(
        "version: 1\narm: {links: [1, 1, 1, 1]}\ngoals:\n  - {position: [1, 1, 2], " + form + "}\n"
        "solver: {max_frames_per_goal: 40}\nrender: {fps: 10, size: [64, 48]}\n"
    )
    assert check_command(["run", "s.yaml", "--out", "o", "--no-video", "--viewer"], tmp_path, ["s.yaml", "o"]) == 0


@pytest.mark.slow
def test_the_installed_command_with_a_hostile_urdf(tmp_path):
    name = HOSTILE_STRINGS[3]  # a newline in a joint name
    urdf = (
        '<robot name="r"><link name="a"/><link name="b"/><link name="c"/>'
        f'<joint name="{name.replace(chr(10), "&#10;")}" type="continuous"><parent link="a"/><child link="b"/>'
        '<origin xyz="0 0 0.3"/><axis xyz="0 1e-300 0"/></joint>'
        '<joint name="k" type="revolute"><parent link="b"/><child link="c"/><origin xyz="0 0 0.3"/>'
        '<axis xyz="0 1 0"/><limit lower="-2" upper="2"/></joint></robot>'
    )
    (tmp_path / "r.urdf").write_text(urdf)
    (tmp_path / "s.yaml").write_text(
        "version: 1\narm: {urdf: r.urdf}\ngoals: [[0.2, 0.1, 0.4]]\n"
        "solver: {max_frames_per_goal: 30}\nrender: {fps: 10, size: [64, 48]}\n"
    )
    assert check_command(["validate", "s.yaml"], tmp_path, ["s.yaml", "r.urdf"]) == 0
    assert check_command(["run", "s.yaml", "--out", "o", "--no-video"], tmp_path, ["s.yaml", "o"]) == 0
