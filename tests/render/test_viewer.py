"""viewer.html without a browser: the bundle, the data, the escaping, the sizes, and the
``run``/``view`` commands under the run folder's rules (the browser tests are in
test_viewer_browser.py)."""

from __future__ import annotations

import hashlib
import json
import re
from pathlib import Path

import numpy as np
import pytest
from conftest import ROOT, SCENES
from viewer_runs import synthetic_run

from armanim.arm.kinematics import forward
from armanim.motion.solution import Solution
from armanim.output.rundir import MARKER
from armanim.output.solved import SolvedRun
from armanim.render.settings import OutputOptions
from armanim.render.viewer import write_viewer
from armanim.render.viewer.data import viewer_data
from armanim.render.viewer.page import GENERATOR, bundle_info, script_json, three_bundle, viewer_html

ASSETS = ROOT / "src" / "armanim" / "render" / "viewer" / "assets"
SMALL = """version: 1
name: small
arm: {links: [2, 2, 2, 2]}
obstacles: [{center: [3, 0, 3], radius: 0.5}]
goals: [[2, 2, 4], [20, 0, 0]]
solver: {max_frames_per_goal: 40}
render: {fps: 10, size: [64, 48]}
"""


# ------------------------------------------------------------------ the bundled three.js


def test_the_bundle_is_the_recorded_three_js_version_and_sha256():
    info = bundle_info()
    raw = (ASSETS / info["file"]).read_bytes()
    assert hashlib.sha256(raw).hexdigest() == info["sha256"] and len(raw) == info["bytes"]
    pinned = json.loads((ROOT / "tools" / "viewer-js" / "package.json").read_text())["devDependencies"]
    assert info["three"] == pinned["three"] and info["esbuild"] == pinned["esbuild"]
    locked = json.loads((ROOT / "tools" / "viewer-js" / "package-lock.json").read_text())["packages"]
    assert locked["node_modules/three"]["version"] == info["three"]
    assert "Three.js Authors" in raw[:300].decode() and "SPDX-License-Identifier: MIT" in raw[:300].decode()


def test_the_inlined_scripts_are_the_files_byte_for_byte():
    from armanim.render.viewer.page import asset_text, inline_script

    for code in (three_bundle(), asset_text("page.js")):  # nothing in them needs the </script guard
        assert inline_script(code) == code


def test_the_bundle_is_package_data():
    pyproject = (ROOT / "pyproject.toml").read_text()
    assert '"render/viewer/assets/*"' in pyproject
    assert three_bundle().startswith("(()=>{")


# ------------------------------------------------------------------ the page and its escaping


def test_script_json_cannot_end_its_script_element():
    hostile = {"title": "</script><script>alert(1)</script><!-- -->", "q": "\"'&<>\u2028\u2029"}
    text = script_json(hostile)
    assert "<" not in text and ">" not in text and "&" not in text and "\u2028" not in text
    assert json.loads(text) == hostile
    with pytest.raises(ValueError):
        script_json({"x": float("nan")})


def test_a_hostile_title_and_joint_names_are_escaped_in_the_page():
    hostile = "</script><script>alert(1)</script><!-- \"'&"
    problem, trajectory, reports, settings = synthetic_run(20, 4)
    page = viewer_html(viewer_data(problem, trajectory, reports, settings, title=hostile, joint_names=[hostile] * 4))
    assert page.count("<script") == 3 and page.count("</script>") == 3  # the page's own three, nothing more
    assert "alert(1)" in page and "<script>alert" not in page
    assert (
        "<title>&lt;/script&gt;&lt;script&gt;alert(1)&lt;/script&gt;&lt;!-- &quot;&#x27;&amp; - armanim</title>" in page
    )
    assert page.count("<!--") == 0
    assert f'<meta name="generator" content="{GENERATOR}">' in page[:400]


def test_the_page_asks_for_nothing_from_the_network():
    problem, trajectory, reports, settings = synthetic_run(20, 4)
    page = viewer_html(viewer_data(problem, trajectory, reports, settings, title="t"))
    page_own = "".join((ASSETS / name).read_text() for name in ("page.html", "page.css", "page.js"))
    assert not re.search(r"https?://", page_own)  # no CDN, font or script address in the page's own code
    assert not re.search(r"""(src|href)=["'](?!data:)""", page)  # every src/href is inline data


# ------------------------------------------------------------------ the data


def test_joint_positions_are_armanim_s_forward_kinematics_rounded():
    from conftest import solved_scene

    problem, solution = solved_scene(SCENES / "notes-arm.yaml")
    from armanim.scene import load_scene, render_settings

    settings = render_settings(load_scene(SCENES / "notes-arm.yaml").model)
    data = viewer_data(problem, solution.trajectory, solution.goals, settings, title="notes-arm")
    frames, joints = solution.trajectory.frames, problem.arm.n
    points = np.array(data["points"], dtype=float).reshape(frames, joints + 1, 3)
    np.testing.assert_allclose(
        points, forward(problem.arm, solution.trajectory.phi).points, atol=0.5 * 10.0 ** -data["decimals"] + 1e-12
    )
    angles = np.array(data["angles_deg"]).reshape(frames, joints)
    np.testing.assert_allclose(angles, np.degrees(solution.trajectory.phi), atol=0.005 + 1e-9)
    assert data["goal"] == solution.trajectory.goal.tolist()
    assert [g["reached"] for g in data["goals"]] == [g.reached for g in solution.goals]
    assert data["view"]["elevation"] == 25 and data["view"]["azimuth"] == -60
    json.dumps(data, allow_nan=False)  # plain JSON: no NaN or infinity


def test_a_planar_arm_starts_face_on():
    from conftest import solved_scene

    from armanim.scene import load_scene, render_settings

    problem, solution = solved_scene(SCENES / "planar-nlink.yaml")
    data = viewer_data(
        problem,
        solution.trajectory,
        solution.goals,
        render_settings(load_scene(SCENES / "planar-nlink.yaml").model),
        title="p",
    )
    assert data["view"]["planar"] and data["view"]["elevation"] == 90
    assert all(c is None for c in data["clearance"])  # no obstacles: no clearance, never infinity


@pytest.mark.parametrize(("frames", "joints", "bound"), [(700, 4, 1_000_000), (3000, 7, 3_000_000)])
def test_the_page_stays_under_its_size_bound(tmp_path, frames, joints, bound):
    problem, trajectory, reports, settings = synthetic_run(frames, joints)
    run = SolvedRun("synthetic", problem, Solution(trajectory, tuple(reports)))
    path = write_viewer(run, OutputOptions(settings), tmp_path / "viewer.html")
    assert path.stat().st_size <= bound, path.stat().st_size


# ------------------------------------------------------------------ armanim run and armanim view


@pytest.fixture()
def scene(tmp_path) -> Path:
    path = tmp_path / "small.yaml"
    path.write_text(SMALL)
    return path


def listed(folder: Path) -> list[str]:
    """The names the run folder's marker lists (it records each file's size and time)."""
    return sorted(json.loads((folder / MARKER).read_text())["files"])


def test_run_no_video_writes_no_viewer_unless_asked(cli, scene, tmp_path):
    assert cli("run", scene, "--out", tmp_path / "a", "--no-video", "-q").exit_code == 0
    assert not (tmp_path / "a" / "small" / "viewer.html").exists()
    assert cli("run", scene, "--out", tmp_path / "b", "--no-video", "--viewer", "-q").exit_code == 0
    folder = tmp_path / "b" / "small"
    assert "viewer.html" in listed(folder)
    assert (folder / "viewer.html").read_text().startswith("<!doctype html>")


def test_run_writes_the_viewer_beside_the_video_unless_told_not_to(cli, scene, tmp_path, monkeypatch):
    import armanim.runs.pipeline as pipeline

    def video(run, options, folder, also=None, **kwargs):  # a stand-in: the flags, not the drawing
        (folder / "animation.mp4").write_bytes(b"video")
        if also is not None:  # the page, written while the video's workers draw
            also()
        return {"video": folder / "animation.mp4"}

    monkeypatch.setattr(
        pipeline, "render_outputs", video
    )  # the real video beside it: tests/runs/test_render_command.py
    assert cli("run", scene, "--out", tmp_path / "a", "-q", "--jobs", "1").exit_code == 0
    assert {"viewer.html", "animation.mp4"} <= set(listed(tmp_path / "a" / "small"))
    assert cli("run", scene, "--out", tmp_path / "b", "-q", "--jobs", "1", "--no-viewer").exit_code == 0
    assert (
        "viewer.html" not in listed(tmp_path / "b" / "small") and (tmp_path / "b" / "small" / "animation.mp4").is_file()
    )


def test_a_batch_writes_a_viewer_per_scene(cli, scene, tmp_path):
    other = tmp_path / "other.yaml"
    other.write_text(SMALL.replace("name: small", "name: other"))
    result = cli("run", scene, other, "--out", tmp_path / "out", "--no-video", "--viewer", "-q", "--jobs", "1")
    assert result.exit_code == 0, result.output
    assert all("viewer.html" in listed(tmp_path / "out" / name) for name in ("small", "other"))


@pytest.fixture()
def run_folder(cli, scene, tmp_path) -> Path:
    assert cli("run", scene, "--out", tmp_path / "out", "--no-video", "-q").exit_code == 0
    return tmp_path / "out" / "small"


def test_view_writes_the_run_s_viewer_and_lists_it(cli, run_folder):
    result = cli("view", run_folder)
    assert result.exit_code == 0, result.output
    assert result.stdout.strip() == str(run_folder / "viewer.html")
    assert sorted(p.name for p in run_folder.iterdir() if p.name != MARKER) == listed(run_folder)
    assert "viewer.html" in listed(run_folder)
    first = (run_folder / "viewer.html").read_bytes()
    assert cli("view", run_folder).exit_code == 0  # again: replaced, the same bytes
    assert (run_folder / "viewer.html").read_bytes() == first
    assert sorted(p.name for p in run_folder.parent.iterdir()) == [".small.lock", "small"]  # nothing staged is left


def test_view_out_writes_elsewhere_and_replaces_only_its_own_pages(cli, run_folder, tmp_path):
    target = tmp_path / "pages" / "small.html"
    assert cli("view", run_folder, "--out", target).exit_code == 0
    assert target.is_file() and not (run_folder / "viewer.html").exists()
    assert cli("view", run_folder, "--out", target).exit_code == 0  # armanim's own page: replaced
    mine = tmp_path / "notes.html"
    mine.write_text("<html>my notes</html>")
    result = cli("view", run_folder, "--out", mine)
    assert result.exit_code == 3 and "armanim did not write" in result.stderr
    assert mine.read_text() == "<html>my notes</html>"
    result = cli("view", run_folder, "--out", tmp_path)
    assert result.exit_code == 3 and "is a folder" in result.stderr


def test_view_out_never_replaces_a_page_edited_since(cli, run_folder, tmp_path):
    """Campaign 5: ``view --out`` took any file with armanim's generator tag for its own, so a page
    a user had annotated since (a comment, a paragraph) was replaced, their notes lost, exit 0. The
    page's last line records the sha256 of the rest: an edited page (at its head or its end) is exit
    3 and left as it was; the page as armanim wrote it is still replaced."""
    import hashlib

    target = tmp_path / "page.html"
    assert cli("view", run_folder, "--out", target).exit_code == 0
    body, last = target.read_bytes().rsplit(b"\n", 2)[0] + b"\n", target.read_bytes().splitlines()[-1]
    assert last == f'<meta name="armanim-sha256" content="{hashlib.sha256(body).hexdigest()}">'.encode()
    assert cli("view", run_folder, "--out", target).exit_code == 0
    for edit in (lambda page: page + b"<p>my notes</p>\n", lambda page: page.replace(b"<title>", b"<title>mine: ", 1)):
        edited = edit(target.read_bytes())
        target.write_bytes(edited)
        result = cli("view", run_folder, "--out", target)
        assert result.exit_code == 3 and "changed since armanim wrote it" in result.stderr, result.output
        assert target.read_bytes() == edited
        target.unlink()
        assert cli("view", run_folder, "--out", target).exit_code == 0


def test_view_refuses_what_is_not_an_armanim_run(cli, run_folder, tmp_path):
    result = cli("view", tmp_path / "nowhere")
    assert result.exit_code == 2 and "no such folder" in result.stderr
    result = cli("view", tmp_path)
    assert result.exit_code == 2 and "is not a complete armanim run" in result.stderr
    (run_folder / "thesis.txt").write_text("mine")
    result = cli("view", run_folder)
    assert result.exit_code == 3 and "thesis.txt" in result.stderr
    assert not (run_folder / "viewer.html").exists() and (run_folder / "thesis.txt").read_text() == "mine"


def test_view_open_hands_the_page_to_the_browser(cli, run_folder, monkeypatch):
    import webbrowser

    opened = []
    monkeypatch.setattr(webbrowser, "open", lambda url: opened.append(url) or True)
    assert cli("view", run_folder, "--open").exit_code == 0
    assert opened == [(run_folder / "viewer.html").resolve().as_uri()]
    monkeypatch.setattr(webbrowser, "open", lambda url: False)
    result = cli("view", run_folder, "--open")
    assert result.exit_code == 0 and "no web browser could be started" in result.stderr


@pytest.mark.slow
@pytest.mark.parametrize("ci", ["", "true"])
def test_without_a_browser_the_browser_tests_skip_saying_how_to_install_one_or_fail_in_ci(ci):
    import os
    import subprocess
    import sys

    env = {**os.environ, "ARMANIM_BROWSER": "/nonexistent/chromium", "CI": ci}
    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "pytest",
            "-q",
            "-n",
            "0",
            "-rs",
            "-p",
            "no:cacheprovider",
            "tests/render/test_viewer_browser.py",
            "-k",
            "frame_count",
        ],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )
    if ci:
        assert proc.returncode == 1 and "1 error" in proc.stdout and "CI=true" in proc.stdout, proc.stdout
    else:
        assert proc.returncode == 0 and "1 skipped" in proc.stdout, proc.stdout
    assert "apt-get install chromium-headless-shell" in proc.stdout
