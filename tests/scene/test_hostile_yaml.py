"""Hostile scene files (issue 7): alias bombs, deep nesting, huge files, bad bytes are refused
fast with bounded memory and a FILE:LINE message; the largest scene the limits allow loads.

Each test is named in the table of docs/reliability.md, which it keeps true.
"""

from __future__ import annotations

import tracemalloc

import pytest

from armanim.errors import SceneError
from armanim.scene import validate_scene_text
from armanim.scene.models import LIMITS
from armanim.scene.yamlread import MAX_DEPTH, MAX_FILE_BYTES, MAX_NODES

SMALL = "version: 1\narm:\n  links: [1, 1]\ngoals:\n  - [1, 0, 0]\n"


def _bomb(levels: int = 9, width: int = 9) -> str:
    lines = ["a0: &a0 [" + ", ".join(["lol"] * width) + "]"]
    for i in range(1, levels):
        lines.append(f"a{i}: &a{i} [" + ", ".join([f"*a{i - 1}"] * width) + "]")
    return "\n".join(lines) + "\n"


HOSTILE = {
    # name: (text, field path or "" for the file, line, words in the message)
    "alias bomb": (_bomb(), None, None, ["expands to more than", f"{MAX_NODES:,}", "alias bomb"]),
    "recursive alias": ("a: &a [1, *a]\n", "a[1]", 1, ["refers to a value that contains it"]),
    "deep block nesting": (
        "".join("  " * i + "a:\n" for i in range(100)) + "  " * 100 + "b: 1\n",
        None,
        MAX_DEPTH + 2,
        [f"nesting deeper than {MAX_DEPTH} levels"],
    ),
    "deep flow nesting": (
        "a: " + "[" * 10_000 + "]" * 10_000 + "\n",
        None,
        1,
        [f"nesting deeper than {MAX_DEPTH} levels"],
    ),
    "deep dash nesting": ("a:\n" + "- " * 10_000 + "x\n", None, None, [f"nesting deeper than {MAX_DEPTH} levels"]),
    "many values": ("a: [" + ", ".join(["0"] * 200_000) + "]\n", None, 1, ["expands to more than"]),
    "1e400": (
        SMALL.replace("[1, 0, 0]", "[1e400, 0, 0]"),
        "goals[0].position[0]",
        5,
        ["must be a finite number (got inf)"],
    ),
    ".nan": (
        SMALL.replace("[1, 0, 0]", "[.nan, 0, 0]"),
        "goals[0].position[0]",
        5,
        ["must be a finite number (got nan)"],
    ),
    "10**400": (SMALL.replace("[1, 0, 0]", f"[{10**400}, 0, 0]"), "goals[0][0]", 5, ["401-digit integer is too large"]),
    "10**5000": (
        SMALL.replace("[1, 0, 0]", "[1" + "0" * 5000 + ", 0, 0]"),
        "goals[0][0]",
        5,
        ["5001-digit integer is too large"],
    ),
    "10,000 links": (
        SMALL.replace("[1, 1]", "[" + ", ".join(["1"] * 10_000) + "]"),
        "arm.links",
        3,
        ["10000 items", f"at most {LIMITS['links']}"],
    ),
    "1,001 goals": (
        "version: 1\narm:\n  links: [1, 1]\ngoals:\n" + "  - [1, 0, 0]\n" * 1001,
        "goals",
        4,
        ["1001 items", "at most 1000"],
    ),
    "tab indentation": (SMALL.replace("  links", "\tlinks"), "", 3, ["not valid YAML", "tab character", "spaces"]),
    "duplicate key": (SMALL + "version: 1\n", "version", 6, ["duplicate key 'version'", "first on line 1"]),
    "list as key": (SMALL + "[a, b]: 1\n", "", 6, ["mapping key must be a plain name (got a list)"]),
    "mapping as key": (SMALL + "? {a: 1}\n: 2\n", "", 6, ["mapping key must be a plain name (got a mapping)"]),
    "merge key": (
        "version: 1\narm:\n  <<: {links: [1, 1]}\ngoals:\n  - [1, 0, 0]\n",
        "arm",
        3,
        ["merge keys (<<) are not supported"],
    ),
    "timestamp": (SMALL + "name: 2001-12-14\n", "name", 6, ["unsupported YAML tag '!!timestamp'"]),
    "binary": (SMALL + "name: !!binary aGVsbG8=\n", "name", 6, ["unsupported YAML tag '!!binary'"]),
    "python object": (
        SMALL + "name: !!python/object/apply:os.system ['false']\n",
        "name",
        6,
        ["unsupported YAML tag", "not executed"],
    ),
    "string as number": (
        SMALL.replace("[1, 0, 0]", "['1', 0, 0]"),
        "goals[0].position[0]",
        5,
        ["must be a number (got '1')"],
    ),
    "bool as number": (
        SMALL.replace("[1, 0, 0]", "[true, 0, 0]"),
        "goals[0].position[0]",
        5,
        ["must be a number (got true)"],
    ),
    "control character": (SMALL + "name: a\x07b\n", "", 6, ["is not allowed in YAML"]),
    "too many frames": (
        "version: 1\narm:\n  links: [1, 1]\ngoals:\n"
        + "  - {position: [1, 0, 0], hold: 3600}\n" * 10
        + "render: {fps: 240}\n",
        "goals",
        4,
        ["frames", f"at most {LIMITS['total_frames']:,}"],
    ),
    "many unknown keys": (
        SMALL + "".join(f"k{i}: 1\n" for i in range(2000)),
        "",
        None,
        ["unknown key 'k0'", "more problems"],
    ),
}


@pytest.mark.parametrize("name", HOSTILE)
def test_hostile_yaml_is_rejected_fast_with_bounded_memory(name):
    """Rejected with its FILE:LINE: path: message, in bounded memory (a tracemalloc peak, the
    same on any machine). How fast is measured by benchmarks/reliability_bench.py, not here:
    a wall-clock bound fails on a busy machine."""
    text, field, line, words = HOSTILE[name]
    with pytest.raises(SceneError) as info:
        validate_scene_text(text, "hostile.yaml")
    tracemalloc.start()
    try:
        with pytest.raises(SceneError):
            validate_scene_text(text, "hostile.yaml")
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 32 * 2**20, f"{name}: peak {peak / 2**20:.1f} MiB"
    report = info.value.report()
    assert len(report) < 20_000, report[:500]
    problems = info.value.problems
    if field is not None:
        assert any(p.path == field for p in problems), report
    if line is not None:
        assert any(p.line == line for p in problems), report
    for word in words:
        assert word in report, (word, report[:2000])
    for p in problems:
        assert p.format("hostile.yaml").startswith("hostile.yaml"), p


def test_hostile_yaml_through_the_cli_is_file_line_path_message(cli, tmp_path):
    path = tmp_path / "bomb.yaml"
    path.write_text(_bomb())
    result = cli("validate", path)
    assert result.exit_code == 2
    assert result.stderr.startswith(f"{path}:"), result.stderr
    path.write_text(HOSTILE["1e400"][0])
    result = cli("validate", path)
    assert result.exit_code == 2
    assert f"{path}:5: goals[0].position[0]: must be a finite number (got inf)" in result.stderr


def test_huge_file_is_rejected_before_reading(cli, tmp_path):
    from armanim.scene import load_scene

    path = tmp_path / "huge.yaml"
    path.write_text(SMALL + "#" * (MAX_FILE_BYTES + 10) + "\n")
    result = cli("validate", path)
    assert result.exit_code == 2
    assert f"a scene may be at most {MAX_FILE_BYTES:,} bytes" in result.stderr
    tracemalloc.start()
    try:
        with pytest.raises(SceneError):
            load_scene(path)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < MAX_FILE_BYTES / 10, f"peak {peak:,} bytes: the file was read"  # its size says no first


def test_non_utf8_bytes_name_their_line(cli, tmp_path):
    path = tmp_path / "latin1.yaml"
    path.write_bytes(SMALL.encode() + b"name: caf\xe9\n")
    result = cli("validate", path)
    assert result.exit_code == 2
    assert f"{path}:6: byte 0xe9 is not UTF-8" in result.stderr


@pytest.mark.parametrize("encoding", ["utf-16", "utf-16-be", "utf-16-le"])
def test_a_utf16_scene_is_said_to_be_utf16_not_binary(cli, tmp_path, encoding):
    """Campaign 8: a scene saved as UTF-16 (with its byte-order mark) was "a binary file"."""
    path = tmp_path / "wide.yaml"
    path.write_bytes(("\ufeff" if encoding != "utf-16" else "").encode(encoding) + SMALL.encode(encoding))
    result = cli("validate", path)
    assert result.exit_code == 2 and f"{path}:1: is UTF-16 text (save the file as UTF-8)" in result.stderr


def test_largest_valid_scene_still_loads(tmp_path):
    """The limits leave room for a maximal scene: 64 links, 1000 goals, 1000 obstacles."""
    links = ", ".join(["0.1"] * LIMITS["links"])
    goals = "".join(f"  - {{position: [1, {i % 7}, 2], hold: 0.1}}\n" for i in range(LIMITS["goals"]))
    obstacles = "".join(
        f"  - {{center: [{20 + i}, 30, 40], radius: 0.5, influence: 1}}\n" for i in range(LIMITS["obstacles"])
    )
    text = f"version: 1\narm:\n  links: [{links}]\nobstacles:\n{obstacles}goals:\n{goals}solver: {{max_frames_per_goal: 900}}\n"
    model = validate_scene_text(text, "big.yaml")  # its time: benchmarks/reliability_bench.py
    assert len(model.goals) == LIMITS["goals"] and len(model.obstacles) == LIMITS["obstacles"]
