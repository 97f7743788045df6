"""Batches, sweeps and Dask scale-out (issue 8): failures isolated, index.csv, exit codes,
the same bytes whatever runs the scenes.

Small scenes only (copies of scenes/out-of-reach.yaml and scenes/planar-nlink.yaml),
without video except one tiny, slow-marked video test.
"""

from __future__ import annotations

import csv
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

ROOT = Path(__file__).resolve().parents[2]
SCENES = ROOT / "scenes"

BAD_SCENE = "version: 1\narm:\n  links: [1, -1]\ngoals:\n  - [1, 0, 0]\n"
BAD_MESSAGE = "bad.yaml:3: arm.links[1]: must be > 0 (got -1)"
GOOD = {"out-of-reach": "a.yaml", "planar-nlink": "b.yaml"}
INDEX_HEADER = [
    "name",
    "status",
    "scene_file",
    "goals",
    "reached",
    "missed",
    "frames",
    "min_clearance",
    "folder",
    "message",
]


# ------------------------------------------------------------------ helpers


def make_scenes(folder: Path) -> Path:
    """a.yaml (out-of-reach: 1 reached, 1 missed), b.yaml (planar-nlink: 4 reached), bad.yaml."""
    folder.mkdir(parents=True, exist_ok=True)
    shutil.copy(SCENES / "out-of-reach.yaml", folder / "a.yaml")
    shutil.copy(SCENES / "planar-nlink.yaml", folder / "b.yaml")
    (folder / "bad.yaml").write_text(BAD_SCENE)
    return folder


def invoke(*args, env: dict | None = None):
    """The armanim Typer app in-process (stdout and stderr both in ``result.output``)."""
    from typer.testing import CliRunner

    from armanim.cli import app

    env = {"ARMANIM_SCHEDULER": None, **(env or {})}  # a scheduler in the caller's environment must not leak in
    result = CliRunner().invoke(app, [str(a) for a in args], env=env)
    assert "Traceback" not in result.output, result.output
    if result.exception is not None and not isinstance(result.exception, SystemExit):
        raise result.exception
    return result


def clean_env() -> dict:
    return {k: v for k, v in os.environ.items() if k != "ARMANIM_SCHEDULER"}


def armanim_exe() -> str:
    exe = Path(sys.executable).parent / "armanim"
    found = str(exe) if exe.exists() else shutil.which("armanim")
    if not found:
        pytest.skip("the armanim command is not installed")
    return found


def read_index(out: Path) -> dict[str, dict]:
    with open(out / "index.csv", newline="") as handle:
        reader = csv.DictReader(handle)
        assert reader.fieldnames == INDEX_HEADER
        rows = list(reader)
    by_name = {row["name"]: row for row in rows}
    assert len(by_name) == len(rows), rows
    return by_name


def trajectory_rows(folder: Path) -> int:
    with open(folder / "trajectory.csv", newline="") as handle:
        return sum(1 for _ in csv.reader(handle)) - 1  # minus the header


def outputs_bytes(out: Path, names=tuple(GOOD)) -> dict[str, bytes]:
    return {f"{n}/{f}": (out / n / f).read_bytes() for n in names for f in ("trajectory.csv", "summary.json")}


def assert_good_batch(out: Path, with_bad: bool = True) -> None:
    """index.csv: one row per scene, the right status and counts, frames = trajectory.csv rows."""
    index = read_index(out)
    assert set(index) == set(GOOD) | ({"bad"} if with_bad else set())
    for name, file in GOOD.items():
        row = index[name]
        assert row["status"] == "ok", row
        assert Path(row["scene_file"]).name == file
        summary = json.loads((out / name / "summary.json").read_text())
        assert int(row["frames"]) == trajectory_rows(out / name) == summary["totals"]["frames"]
        assert int(row["goals"]) == len(summary["goals"])
        assert int(row["reached"]) == sum(g["reached"] for g in summary["goals"])
        assert int(row["missed"]) == sum(not g["reached"] for g in summary["goals"])
        assert Path(row["folder"]) == out / name
        assert row["message"] == ""
    assert (index["out-of-reach"]["reached"], index["out-of-reach"]["missed"], index["out-of-reach"]["goals"]) == (
        "1",
        "1",
        "2",
    )
    assert (index["planar-nlink"]["reached"], index["planar-nlink"]["missed"], index["planar-nlink"]["goals"]) == (
        "4",
        "0",
        "4",
    )
    if with_bad:
        bad = index["bad"]
        assert bad["status"] == "invalid"
        assert bad["message"].endswith(BAD_MESSAGE)
        assert (bad["frames"], bad["folder"]) == ("0", "")
        assert not (out / "bad").exists()


def batch_args(src: Path, out: Path, jobs: int, *extra) -> list:
    return ["run", src / "a.yaml", src / "b.yaml", src / "bad.yaml", "--jobs", jobs, "--no-video", "--out", out, *extra]


# ------------------------------------------------------------------ the batch, two ways


@pytest.fixture(scope="module")
def src(tmp_path_factory) -> Path:
    return make_scenes(tmp_path_factory.mktemp("scenes"))


@pytest.fixture(scope="module")
def batch_j2(src, tmp_path_factory):
    """a, b and bad with --jobs 2 (a process pool): (result, out)."""
    out = tmp_path_factory.mktemp("j2")
    return invoke(*batch_args(src, out, 2)), out


@pytest.fixture(scope="module")
def batch_j1(src, tmp_path_factory):
    out = tmp_path_factory.mktemp("j1")
    return invoke(*batch_args(src, out, 1)), out


def test_a_bad_scene_is_reported_and_the_others_finish(batch_j2):
    result, out = batch_j2
    assert result.exit_code == 2, result.output
    assert BAD_MESSAGE in result.output
    assert_good_batch(out)


def test_the_printed_table_counts_the_scenes_and_names_the_index(batch_j2):
    result, out = batch_j2
    assert "3 scenes: 2 ok" in result.output
    assert "invalid" in result.output
    assert f"index: {out / 'index.csv'}" in result.output


def test_quiet_still_reports_a_bad_scene(src, tmp_path):
    result = invoke(*batch_args(src, tmp_path, 1, "--quiet"))
    assert result.exit_code == 2
    assert BAD_MESSAGE in result.output


def test_jobs_1_and_jobs_2_give_byte_identical_outputs(batch_j1, batch_j2):
    (r1, out1), (r2, out2) = batch_j1, batch_j2
    assert r1.exit_code == r2.exit_code == 2
    assert_good_batch(out1)
    assert outputs_bytes(out1) == outputs_bytes(out2)


def test_the_installed_command_runs_a_batch(src, tmp_path):
    """Also with a TMPDIR too long for the workers' socket path (AF_UNIX: 107 bytes)."""
    tmp = tmp_path / ("long-temporary-folder-" * 6)
    tmp.mkdir()
    proc = subprocess.run(
        [armanim_exe(), *map(str, batch_args(src, tmp_path / "out", 2))],
        capture_output=True,
        text=True,
        timeout=120,
        cwd=tmp_path,
        env={**clean_env(), "TMPDIR": str(tmp)},
    )
    assert proc.returncode == 2, proc.stderr
    assert BAD_MESSAGE in proc.stderr
    assert "Traceback" not in proc.stderr
    assert_good_batch(tmp_path / "out")


def test_a_good_batch_exits_0_and_strict_exits_1_on_a_missed_goal(src, tmp_path):
    good = [src / "a.yaml", src / "b.yaml"]
    assert invoke("run", *good, "--jobs", 1, "--no-video", "-q", "--out", tmp_path).exit_code == 0
    assert_good_batch(tmp_path, with_bad=False)
    assert invoke("run", *good, "--jobs", 1, "--no-video", "-q", "--out", tmp_path, "--strict").exit_code == 1


def test_a_scene_that_fails_on_its_worker_is_failed_exit_3(src, tmp_path, monkeypatch):
    import armanim.runs.batch
    from armanim.errors import OutputError

    real = armanim.runs.batch.run_task

    def flaky(task, *args):  # (task, video, overrides, viewer)
        if task.name == "planar-nlink":
            raise OutputError("disk on fire")
        return real(task, *args)

    monkeypatch.setattr(armanim.runs.batch, "run_task", flaky)  # --jobs 1 runs tasks in this process
    result = invoke("run", src / "a.yaml", src / "b.yaml", "--jobs", 1, "--no-video", "--out", tmp_path)
    assert result.exit_code == 3, result.output
    assert "disk on fire" in result.output
    index = read_index(tmp_path)
    assert index["planar-nlink"]["status"] == "failed"
    assert index["planar-nlink"]["message"] == "disk on fire"
    assert index["out-of-reach"]["status"] == "ok"
    assert trajectory_rows(tmp_path / "out-of-reach") == int(index["out-of-reach"]["frames"])
    assert not (tmp_path / "planar-nlink").exists()


def test_an_unexpected_worker_exception_is_failed_with_its_type(src, tmp_path, monkeypatch):
    import armanim.runs.batch

    def boom(task, *args):
        raise RuntimeError("worker bug")

    monkeypatch.setattr(armanim.runs.batch, "run_task", boom)
    result = invoke("run", src / "a.yaml", src / "bad.yaml", "--jobs", 1, "--no-video", "-q", "--out", tmp_path)
    assert result.exit_code == 3  # failed outranks invalid
    index = read_index(tmp_path)
    assert index["out-of-reach"]["status"] == "failed"
    assert "RuntimeError: worker bug" in index["out-of-reach"]["message"]
    assert index["bad"]["status"] == "invalid"


def test_an_unwritable_output_folder_fails_that_scene_only_exit_3(src, tmp_path):
    """The scene's lock file cannot be made (a folder stands there): a real OutputError on the client."""
    out = tmp_path / "out"
    (out / ".planar-nlink.lock").mkdir(parents=True)
    result = invoke("run", src / "a.yaml", src / "b.yaml", "--jobs", 1, "--no-video", "-q", "--out", out)
    assert result.exit_code == 3, result.output
    index = read_index(out)
    assert index["planar-nlink"]["status"] == "failed"
    assert "planar-nlink" in index["planar-nlink"]["message"]
    assert index["out-of-reach"]["status"] == "ok"
    assert (out / "out-of-reach" / "trajectory.csv").is_file()


def test_a_file_where_the_output_folder_goes_fails_that_scene_exit_3(src, tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / "planar-nlink").write_text("my notes, not an armanim folder\n")
    result = invoke("run", src / "a.yaml", src / "b.yaml", "--jobs", 1, "--no-video", "-q", "--out", out)
    index = read_index(out)
    assert index["out-of-reach"]["status"] == "ok"
    assert (out / "planar-nlink").read_text() == "my notes, not an armanim folder\n"
    assert index["planar-nlink"]["status"] == "failed"
    assert result.exit_code == 3


def test_duplicate_names_in_one_batch_are_reported(src, tmp_path):
    other = tmp_path / "other"
    other.mkdir()
    shutil.copy(src / "b.yaml", other / "b.yaml")  # another file, the same name: planar-nlink
    result = invoke(
        "run", src / "a.yaml", src / "b.yaml", other / "b.yaml", "--jobs", 1, "--no-video", "--out", tmp_path / "out"
    )
    assert result.exit_code == 2
    assert "also named 'planar-nlink'" in result.output
    with open(tmp_path / "out" / "index.csv", newline="") as handle:
        rows = list(csv.DictReader(handle))
    assert [(Path(r["scene_file"]), r["status"]) for r in rows] == [
        (src / "a.yaml", "ok"),
        (src / "b.yaml", "ok"),
        (other / "b.yaml", "invalid"),
    ]
    assert str(other / "b.yaml") in rows[2]["message"]


def test_the_same_file_twice_runs_once(src, tmp_path):
    result = invoke("run", src / "a.yaml", src / "a.yaml", "--jobs", 1, "--no-video", "-q", "--out", tmp_path)
    assert result.exit_code == 0
    assert list(read_index(tmp_path)) == ["out-of-reach"]


def test_a_scene_rejected_on_a_pool_worker_fails_alone(src, tmp_path):
    from armanim.runs.batch import SceneTask, run_tasks
    from armanim.runs.options import RunOptions
    from armanim.scene import load_scene

    good = [SceneTask.from_scene(load_scene(src / f)) for f in ("a.yaml", "b.yaml")]
    rejected = SceneTask(BAD_SCENE.encode(), "bad.yaml", "bad")  # e.g. a worker with another armanim version
    entries = run_tasks([good[0], rejected, good[1]], tmp_path, RunOptions(video=False, jobs=2))
    assert [e.status for e in entries] == ["ok", "invalid", "ok"], [e.message for e in entries]
    assert BAD_MESSAGE in entries[1].message


def test_scene_error_survives_pickling():
    import pickle

    from armanim.errors import Diagnostic, SceneError

    exc = SceneError("bad.yaml", [Diagnostic("arm.links[1]", "must be > 0 (got -1)", 3)])
    back = pickle.loads(pickle.dumps(exc))
    assert back.report() == BAD_MESSAGE


def test_a_task_keeps_its_validated_scene_in_process_and_sends_only_its_bytes(src):
    """--jobs 1 runs the scene the batch validated; a worker process gets the bytes alone and
    validates them itself (a LoadedScene is not sent across processes)."""
    import pickle

    from armanim.runs.batch import SceneTask
    from armanim.scene import load_scene

    loaded = load_scene(src / "a.yaml")
    task = SceneTask.from_scene(loaded)
    assert task.loaded is loaded
    sent = pickle.loads(pickle.dumps(task))
    assert sent.loaded is None and (sent.raw, sent.path, sent.name) == (task.raw, task.path, task.name)


@pytest.mark.slow
def test_a_tiny_video_batch_returns_video_and_plot(src, tmp_path):
    import imageio_ffmpeg

    result = invoke(
        "run", src / "b.yaml", src / "bad.yaml", "--jobs", 2, "--size", "64x48", "--fps", 10, "-q", "--out", tmp_path
    )
    assert result.exit_code == 2
    folder = tmp_path / "planar-nlink"
    assert sorted(p.name for p in folder.iterdir()) == [
        ".armanim-run.json",
        "animation.mp4",
        "plot.png",
        "poster.png",
        "scene.yaml",
        "self-collision.yaml",
        "summary.json",
        "timing.json",
        "trajectory.csv",
        "viewer.html",
    ]
    reader = imageio_ffmpeg.read_frames(str(folder / "animation.mp4"))
    meta = next(reader)
    frames = sum(1 for _ in reader)
    assert tuple(meta["size"]) == (64, 48)
    assert meta["fps"] == pytest.approx(10)
    assert frames == trajectory_rows(folder) == int(read_index(tmp_path)["planar-nlink"]["frames"])
    assert (folder / "plot.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


# ------------------------------------------------------------------ sweeps


def sweep_rows(path: Path) -> tuple[list[str], list[dict]]:
    with open(path, newline="") as handle:
        reader = csv.DictReader(handle)
        return list(reader.fieldnames), list(reader)


def test_a_2x2_sweep_runs_four_named_variants_and_compares_them(src, tmp_path):
    result = invoke(
        "sweep",
        src / "b.yaml",
        "--set",
        "solver.step=0.1,0.2",
        "--set",
        "solver.method=pinv,dls",
        "--jobs",
        2,
        "--out",
        tmp_path,
    )
    assert result.exit_code == 0, result.output
    combos = [(0.1, "pinv"), (0.1, "dls"), (0.2, "pinv"), (0.2, "dls")]
    names = [f"planar-nlink_step-{s}_method-{m}" for s, m in combos]
    assert sorted(p.name for p in tmp_path.iterdir() if p.is_dir()) == sorted(names)
    for (step, method), name in zip(combos, names):
        solver = yaml.safe_load((tmp_path / name / "scene.yaml").read_text())["solver"]
        assert (solver["step"], solver["method"]) == (step, method)
        assert solver["max_step"] == 0.3  # the rest of the scene is kept
    header, rows = sweep_rows(tmp_path / "b-sweep.csv")
    assert header == [
        "name",
        "solver.step",
        "solver.method",
        "status",
        "reached",
        "missed",
        "frames",
        "goal0_frames",
        "goal1_frames",
        "goal2_frames",
        "goal3_frames",
        "min_clearance",
        "max_joint_step_deg",
    ]
    assert [r["name"] for r in rows] == names
    for row, (step, method) in zip(rows, combos):
        summary = json.loads((tmp_path / row["name"] / "summary.json").read_text())
        assert (float(row["solver.step"]), row["solver.method"], row["status"]) == (step, method, "ok")
        assert [row[f"goal{k}_frames"] for k in range(4)] == [
            str(g["frames"]) if g["reached"] else "missed" for g in summary["goals"]
        ]
        assert int(row["missed"]) == summary["totals"]["missed"]
        assert int(row["frames"]) == trajectory_rows(tmp_path / row["name"])
        assert float(row["max_joint_step_deg"]) == pytest.approx(summary["max_joint_step_deg"], rel=1e-5)
        assert row["min_clearance"] == ""  # planar-nlink has no obstacles
    assert len(read_index(tmp_path)) == 4
    assert "sweep of b.yaml: 4 variants" in result.output


def test_a_sweep_over_a_scene_with_obstacles_reports_min_clearance(tmp_path):
    shutil.copy(SCENES / "notes-arm.yaml", tmp_path / "n.yaml")
    result = invoke(
        "sweep",
        tmp_path / "n.yaml",
        "--set",
        "solver.max_frames_per_goal=20",
        "--jobs",
        1,
        "-q",
        "--out",
        tmp_path / "o",
    )
    assert result.exit_code == 0, result.output
    _, rows = sweep_rows(tmp_path / "o" / "n-sweep.csv")
    assert len(rows) == 1 and float(rows[0]["min_clearance"]) > 0


def test_an_invalid_sweep_value_rejects_that_variant_only(src, tmp_path):
    result = invoke("sweep", src / "b.yaml", "--set", "solver.method=pinv,bogus", "--jobs", 1, "--out", tmp_path)
    assert result.exit_code == 2
    assert "solver.method: --set solver.method=bogus: 'bogus' is not allowed" in result.output
    _, rows = sweep_rows(tmp_path / "b-sweep.csv")
    assert [(r["name"], r["status"]) for r in rows] == [
        ("planar-nlink_method-pinv", "ok"),
        ("planar-nlink_method-bogus", "invalid"),
    ]
    assert (tmp_path / "planar-nlink_method-pinv" / "trajectory.csv").is_file()
    assert not (tmp_path / "planar-nlink_method-bogus").exists()
    message = read_index(tmp_path)["planar-nlink_method-bogus"]["message"]
    assert "--set solver.method=bogus: 'bogus' is not allowed" in message


@pytest.mark.parametrize(
    ("setting", "expected"),
    [
        ("solver.step", "expected FIELD.PATH=VALUE1,VALUE2"),
        ("solver.step=", "no values given"),
        ("=0.1,0.2", "expected FIELD.PATH=VALUE1,VALUE2"),
        ("solver..step=0.1", "expected FIELD.PATH=VALUE1,VALUE2"),
        ("solver.step=[1,", "not a plain number, word or list"),
        ("arm.links[9]=1", "[9] does not exist in the scene"),
        ("goals[0].x=1", "'x' is not inside a mapping"),
    ],
)
def test_bad_set_syntax_exits_2_with_a_clear_message(src, tmp_path, setting, expected):
    result = invoke("sweep", src / "b.yaml", "--set", setting, "-q", "--out", tmp_path)
    assert result.exit_code == 2
    assert expected in result.output
    assert "--set" in result.output
    assert not any(tmp_path.iterdir())  # nothing is run or written


def test_run_sweep_is_a_silent_api_that_returns_the_table_it_writes(src, tmp_path, capsys):
    from armanim.runs.sweep import parse_setting, run_sweep

    result = run_sweep(src / "b.yaml", [parse_setting("solver.method=pinv,bogus")], tmp_path, jobs=1)
    assert capsys.readouterr() == ("", "")  # results are returned; printing is the command's job
    assert [(e.name, e.status) for e in result.entries] == [
        ("planar-nlink_method-pinv", "ok"),
        ("planar-nlink_method-bogus", "invalid"),
    ]
    assert result.table == tmp_path / "b-sweep.csv"
    header, rows = sweep_rows(result.table)
    assert header == result.header and [r["name"] for r in rows] == [row[0] for row in result.rows]
    assert set(read_index(tmp_path)) == {"planar-nlink_method-pinv", "planar-nlink_method-bogus"}


def test_sweep_needs_a_set(src, tmp_path):
    assert invoke("sweep", src / "b.yaml", "--out", tmp_path).exit_code == 2


def test_sweep_variants_whose_labels_collide_keep_their_own_results(src, tmp_path):
    result = invoke(
        "sweep", src / "a.yaml", "--set", "goals[1]=[10,9,7],[1,0,97]", "--jobs", 1, "-q", "--out", tmp_path
    )
    _, rows = sweep_rows(tmp_path / "a-sweep.csv")
    assert [r["status"] for r in rows] == ["ok", "ok"], rows  # a missed goal is a result, not a failure
    assert len({r["name"] for r in rows}) == 2, rows  # distinct variants, distinct folders
    by_goal = {r["goals[1]"]: r["reached"] for r in rows}
    assert by_goal == {"[10, 9, 7]": "1", "[1, 0, 97]": "0"}, rows  # each variant has its own result
    assert result.exit_code == 0, result.output


def test_a_setting_named_like_a_table_column_gets_a_column_of_its_own(src, tmp_path):
    result = invoke(
        "sweep", src / "b.yaml", "--set", "name=mine", "--set", "status=1", "--jobs", 1, "-q", "--out", tmp_path
    )
    assert result.exit_code == 2, result.output  # status is no scene field: that variant is invalid
    with open(tmp_path / "b-sweep.csv", newline="") as handle:
        header, row = list(csv.reader(handle))
    assert len(set(header)) == len(header), header  # one name per column
    assert header[:4] == ["name", "set:name", "set:status", "status"]
    cells = dict(zip(header, row))
    assert cells["name"] == "planar-nlink_name-mine_status-1"  # the variant's folder name
    assert (cells["set:name"], cells["set:status"], cells["status"]) == ("mine", "1", "invalid")


@pytest.mark.parametrize(
    ("first", "second", "says"),
    [
        ("solver.step=0.1", "solver.step=0.2", "--set solver.step is given twice"),
        ("goals[0]=[1,1,1]", "goals[0].hold=1", "--set goals[0].hold is a field inside --set goals[0]"),
        ("solver.step=0.1", "solver=[1]", "--set solver.step is a field inside --set solver"),
    ],
)
def test_two_settings_of_one_field_are_refused_before_any_variant(src, tmp_path, first, second, says):
    result = invoke("sweep", src / "b.yaml", "--set", first, "--set", second, "-q", "--out", tmp_path)
    assert result.exit_code == 2, result.output
    assert says in result.output
    assert not any(tmp_path.iterdir())  # nothing is run or written


# ------------------------------------------------------------------ Dask


@pytest.fixture(scope="module")
def dask_distributed():
    return pytest.importorskip("dask.distributed")


def test_a_local_dask_cluster_gives_byte_identical_outputs(dask_distributed, src, batch_j2, tmp_path):
    _, local = batch_j2
    result = invoke(*batch_args(src, tmp_path, 2, "--scheduler", "local"))
    assert result.exit_code == 2, result.output
    assert BAD_MESSAGE in result.output
    assert_good_batch(tmp_path)
    assert outputs_bytes(tmp_path) == outputs_bytes(local)
    assert (tmp_path / "index.csv").read_text().replace(str(tmp_path), "OUT") == (
        local / "index.csv"
    ).read_text().replace(str(local), "OUT")


def test_armanim_scheduler_sends_a_batch_to_a_running_scheduler(dask_distributed, src, batch_j2, tmp_path):
    """ARMANIM_SCHEDULER=tcp://... (a LocalCluster started here stands in for a real cluster)."""
    _, local = batch_j2
    with dask_distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster:
        args = [a for a in batch_args(src, tmp_path, 2)]
        result = invoke(*args, env={"ARMANIM_SCHEDULER": cluster.scheduler_address})
        assert result.exit_code == 2, result.output
        with dask_distributed.Client(cluster) as client:  # the batch ran there, not in a local pool
            prefixes = client.run_on_scheduler(lambda dask_scheduler: [str(k) for k in dask_scheduler.task_prefixes])
            assert "armanim" in prefixes, prefixes
    assert_good_batch(tmp_path)
    assert outputs_bytes(tmp_path) == outputs_bytes(local)


def test_an_unreachable_scheduler_exits_2_with_a_clear_message(dask_distributed, src, tmp_path):
    proc = subprocess.run(
        [
            armanim_exe(),
            "run",
            str(src / "a.yaml"),
            "--no-video",
            "-q",
            "--out",
            str(tmp_path / "out"),
            "--scheduler",
            "tcp://127.0.0.1:1",
        ],
        capture_output=True,
        text=True,
        timeout=300,
        env=clean_env(),
    )
    assert proc.returncode == 2, proc.stderr
    assert "cannot reach the Dask scheduler at tcp://127.0.0.1:1" in proc.stderr
    assert "Traceback" not in proc.stderr
    assert not (tmp_path / "out" / "out-of-reach").exists()


@pytest.mark.parametrize("how", ["flag", "env"])
def test_without_dask_a_scheduler_exits_2_with_the_install_hint(src, tmp_path, monkeypatch, how):
    monkeypatch.setitem(sys.modules, "dask.distributed", None)  # import dask.distributed -> ImportError
    args = [*batch_args(src, tmp_path, 2)] + (["--scheduler", "local"] if how == "flag" else [])
    result = invoke(*args, env={"ARMANIM_SCHEDULER": "local"} if how == "env" else None)
    assert result.exit_code == 2
    assert "pip install -e '.[dask]'" in result.output
    assert not (tmp_path / "out-of-reach").exists()


def test_dask_is_imported_only_when_asked_for(src, tmp_path):
    code = (
        "import sys; from pathlib import Path; from armanim.runs.batch import run_batch; from armanim.runs.options import RunOptions\n"
        f"run_batch([Path({str(src / 'a.yaml')!r})], Path({str(tmp_path)!r}), RunOptions(video=False, jobs=1))\n"
        "print(any(m == 'dask' or m.startswith(('dask.', 'distributed')) for m in sys.modules))\n"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60, env=clean_env())
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "False"


def test_batch_progress_names_the_running_scenes(src, tmp_path):
    from armanim.runs.batch import run_batch
    from armanim.runs.options import RunOptions

    seen = []
    run_batch(
        [src / "a.yaml", src / "b.yaml"],
        tmp_path,
        RunOptions(video=False, jobs=1),
        progress=lambda *call: seen.append(call),
    )
    assert seen[0] == (0, 2, ("out-of-reach",)) and seen[1] == (1, 2, ("planar-nlink",)) and seen[-1] == (2, 2, ())


def test_sweep_and_batch_tables_fit_80_columns_without_cutting(src, tmp_path):
    from rich.console import Console

    from armanim.cli.sweep import sweep_screen_table

    header = [
        "name",
        "solver.step",
        "solver.method",
        "status",
        "reached",
        "missed",
        "frames",
        "goal0_frames",
        "goal1_frames",
        "min_clearance",
        "max_joint_step_deg",
    ]
    rows = [["notes-arm_step-0.05_method-pinv", 0.05, "pinv", "ok", 4, 0, 601, 145, 145, 0.138392, 10]]
    console = Console(width=80, record=True)
    console.print(sweep_screen_table("sweep", header, rows, 2))
    text = console.export_text()
    assert "…" not in text and "step" in text and "method" in text and "0.138392" in text
    result = invoke(
        "run",
        src / "a.yaml",
        src / "b.yaml",
        "--jobs",
        1,
        "--no-video",
        "--out",
        tmp_path / "a-rather-long-output-root-folder",
    )
    assert result.exit_code == 0 and "…" not in result.stdout, result.stdout


def test_a_bad_sweep_value_names_its_setting_not_a_line_of_the_generated_yaml(src, tmp_path):
    result = invoke("sweep", src / "a.yaml", "--set", "solver.step=0.1,5", "--out", tmp_path, "-q", "--jobs", 1)
    assert result.exit_code == 2
    line = next(text for text in result.stderr.splitlines() if "solver.step" in text)
    # no line number after the variant's name: it would point into the generated YAML
    assert line.endswith("a.yaml [out-of-reach_step-5]: solver.step: --set solver.step=5: must be <= 1 (got 5)"), line


@pytest.mark.parametrize(
    ("setting", "expected"),
    [
        # campaign 12: a problem at a key the setting made named no --set (s.yaml seemed to hold it)
        ("nosuch.field=1", "nosuch: --set nosuch.field=1: unknown key 'nosuch'"),
        ("s\u00f6lver.step=0.1", "s\u00f6lver: --set s\u00f6lver.step=0.1: unknown key 's\u00f6lver'"),
        # campaign 12: a list was shown stripped to the variant's label, 1e-091e-09
        ("arm.max_joint_speed=[1e-9, 1e-9, 1e-9, 1e-9]", "--set arm.max_joint_speed=[1e-09, 1e-09, 1e-09, 1e-09]: "),
    ],
)
def test_a_bad_sweep_setting_is_named_with_its_value_as_given(src, tmp_path, setting, expected):
    result = invoke("sweep", src / "a.yaml", "--set", setting, "--out", tmp_path, "-q", "--jobs", 1)
    assert result.exit_code == 2
    assert expected in result.stderr, result.stderr


class _Named(str):
    """A task for an executor: a string (``len`` is the work) with the ``name`` a task has."""

    @property
    def name(self) -> str:
        return str(self)


def _outcomes(results) -> list[tuple[str, object, str]]:
    return [(task.name, result, type(error).__name__ if error else "") for task, result, error in results]


def test_a_scheduler_without_workers_fails_the_scenes_after_its_wait(dask_distributed, monkeypatch):
    # campaign 17: a batch on a scheduler with no worker waited without end and without a word
    from armanim.procs import executors

    monkeypatch.setattr(executors, "NO_WORKERS_SECONDS", 3.0)
    with dask_distributed.LocalCluster(n_workers=0, processes=False, dashboard_address=None) as cluster:
        results = list(executors.executor_for(1, cluster.scheduler_address).map(len, [_Named("a"), _Named("bb")]))
    assert sorted(_outcomes(results)) == [("a", None, "SchedulerLost"), ("bb", None, "SchedulerLost")]
    assert "has had no worker for 3 s" in str(results[0][2])


def test_a_scheduler_lost_mid_batch_fails_the_scenes_left(dask_distributed, capfd):
    # campaign 17: a scheduler killed mid-batch ended the command in Dask's traceback (exit 1), and
    # then, failing the scenes, Dask's client still logged its reconnect's tracebacks
    import threading

    from armanim.procs import executors

    cluster = dask_distributed.LocalCluster(n_workers=0, processes=False, dashboard_address=None)
    executor = executors.executor_for(1, cluster.scheduler_address)
    threading.Timer(2.0, cluster.close).start()
    results = list(executor.map(len, [_Named("a")]))
    assert _outcomes(results) == [("a", None, "SchedulerLost")]
    assert "was lost mid-batch" in str(results[0][2]) and "\n" not in str(results[0][2])
    assert "Traceback" not in capfd.readouterr().err


def test_a_scheduler_with_a_worker_gives_each_task_its_answer(dask_distributed):
    from armanim.procs import executors

    with dask_distributed.LocalCluster(n_workers=1, processes=False, dashboard_address=None) as cluster:
        results = list(executors.executor_for(1, cluster.scheduler_address).map(len, [_Named("a"), _Named("bbb")]))
    assert sorted(_outcomes(results)) == [("a", 1, ""), ("bbb", 3, "")]
