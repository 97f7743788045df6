"""Batches, sweeps and schedulers under hostile conditions (issue 19): a user's table at an
index or sweep name stops them before any work, their size is said first and bounded, a
scheduler that never answers, fails or refuses is exit 2 with its reason.

Each test is named in docs/reliability.md, which it keeps true.
"""

from __future__ import annotations

import re
import socket
import threading

import pytest
from conftest import SCENES
from runfolders import small_scene

from armanim.errors import UsageError

NOTES = SCENES / "notes-arm.yaml"


def test_a_user_index_csv_stops_a_batch_before_any_work(cli, tmp_path):
    a, b = small_scene(tmp_path, "a"), small_scene(tmp_path, "b")
    out = tmp_path / "proj"
    out.mkdir()
    (out / "index.csv").write_text("my precious index\n")
    result = cli("run", a, b, "--out", out, "--no-video", "-q", "--jobs", "1")
    assert result.exit_code == 3, result.output
    assert "index.csv: this file was not written by armanim" in result.stderr and "move it away" in result.stderr
    assert (out / "index.csv").read_text() == "my precious index\n"
    assert sorted(p.name for p in out.iterdir()) == ["index.csv"]  # refused before any scene ran
    (out / "index.csv").unlink()
    for _ in range(2):  # armanim's own index.csv is replaced
        assert cli("run", a, b, "--out", out, "--no-video", "-q", "--jobs", "1").exit_code == 0
    assert (out / "index.csv").read_text().startswith("name,status,")


def test_an_index_csv_edited_since_is_never_replaced(cli, tmp_path):
    """Campaign 5: index.csv was replaced whenever its first line was armanim's header, so a row a
    user had added to it (a note) was lost at the next batch, exit 0. Its size and sha256 are now
    recorded beside it (``.index.csv.armanim.json``): an edited table, or one whose mark is missing
    or is not armanim's, stops the batch before any scene runs (exit 3) and is left as it was."""
    a, b = small_scene(tmp_path, "a"), small_scene(tmp_path, "b")
    out = tmp_path / "proj"
    assert cli("run", a, b, "--out", out, "--no-video", "-q", "--jobs", "1").exit_code == 0
    index, mark = out / "index.csv", out / ".index.csv.armanim.json"
    assert mark.is_file() and '"sha256"' in mark.read_text()
    with index.open("a") as handle:
        handle.write("my note,,,\n")
    edited = index.read_bytes()
    for spoil in (lambda: None, lambda: mark.unlink(), lambda: mark.write_text("[" * 100_000)):
        spoil()
        result = cli("run", a, b, "--out", out, "--no-video", "-q", "--jobs", "1")
        assert result.exit_code == 3 and "has changed since armanim wrote it" in result.stderr, result.output
        assert index.read_bytes() == edited


def test_two_batches_writing_one_index_csv_at_once_take_turns(tmp_path, monkeypatch):
    """Campaign 18: two batches into one OUT ending at once (1 in 25 tries by hand): the second read
    the first's index.csv between the file and its mark being written, and ended "index.csv: has
    changed since armanim wrote it", exit 3, though nobody had touched it. The check and the two
    writes now happen under a lock of the folder: the second batch waits for the first's pair,
    then replaces it, and the pair left is its own."""
    from armanim.output import marks
    from armanim.runs import batch

    index = tmp_path / "index.csv"
    first = [batch.BatchEntry("a", "ok", "a.yaml", 1, 1, 0, 10, None, "a")]
    second = [batch.BatchEntry("b", "ok", "b.yaml", 1, 1, 0, 12, None, "b")]
    checked, failed = threading.Event(), []
    real_check = batch.check_table_replaceable

    def check(*args):
        try:
            return real_check(*args)
        finally:
            if threading.current_thread() is other:
                checked.set()

    def other_batch():
        try:
            batch.write_index(index, second)
        except Exception as exc:  # the race: the second batch refused the first's half-written pair
            failed.append(exc)

    real_write = marks.write_chunks_atomic
    other = threading.Thread(target=other_batch)

    def write_chunks(path, chunks):
        real_write(path, chunks)
        if path == index and threading.current_thread() is not other and not checked.is_set():
            # the first batch's file is written, not yet its mark: the second batch comes now
            other.start()
            checked.wait(2)  # the second checks now (unless it waits its turn)

    monkeypatch.setattr(batch, "check_table_replaceable", check)
    monkeypatch.setattr(marks, "write_chunks_atomic", write_chunks)
    batch.write_index(index, first)
    other.join()
    assert not failed, failed
    assert index.read_text() == batch.index_csv_text(second)
    assert marks.as_marked(index, "index.csv")


def test_a_user_file_at_a_new_index_csv_s_mark_stops_the_batch(cli, tmp_path):
    """No index.csv yet, but a file of the user's at its mark's name (``.index.csv.armanim.json``):
    writing the mark would replace it, so the batch stops before any scene runs (exit 3), every
    byte left."""
    a, b = small_scene(tmp_path, "a"), small_scene(tmp_path, "b")
    out = tmp_path / "proj"
    out.mkdir()
    (out / ".index.csv.armanim.json").write_text("my notes\n")
    result = cli("run", a, b, "--out", out, "--no-video", "-q", "--jobs", "1")
    assert result.exit_code == 3 and "is not a mark armanim wrote" in result.stderr, result.output
    assert (out / ".index.csv.armanim.json").read_text() == "my notes\n"
    assert sorted(p.name for p in out.iterdir()) == [".index.csv.armanim.json"]


@pytest.mark.parametrize("name", ["notes-arm-sweep.csv", "index.csv"])
def test_a_user_file_at_a_sweep_table_stops_the_sweep(cli, tmp_path, name):
    (tmp_path / name).write_text("mine\n")
    result = cli("sweep", NOTES, "--set", "solver.step=0.1,0.2", "--out", tmp_path, "-q", "--jobs", "1")
    assert result.exit_code == 3 and "was not written by armanim" in result.stderr, result.output
    assert sorted(p.name for p in tmp_path.iterdir()) == [name] and (tmp_path / name).read_text() == "mine\n"


@pytest.fixture
def listening_port():
    """A port on 127.0.0.1 that accepts connections (the kernel's backlog) and never answers."""
    with socket.create_server(("127.0.0.1", 0)) as server:
        yield server.getsockname()[1]


@pytest.fixture
def closed_port():
    """A port on 127.0.0.1 that nothing listens on: bound and released."""
    with socket.create_server(("127.0.0.1", 0)) as server:
        port = server.getsockname()[1]
    return port


def test_a_scheduler_that_never_answers_is_given_up_after_the_deadline(listening_port):
    """The client is made on a thread that is given up: Client(timeout=...) does not bound the handshake."""
    from armanim.procs.executors import connect_client

    release = threading.Event()

    def silent_client(address, timeout):
        release.wait()  # accepts, never answers

    address = f"tcp://127.0.0.1:{listening_port}"
    try:
        with pytest.raises(UsageError, match=rf"the Dask scheduler at {address} did not answer within 0.2 s"):
            connect_client(silent_client, address, seconds=0.2)
    finally:
        release.set()


@pytest.mark.parametrize(
    "error, words",
    [(ValueError("bad"), "is not a scheduler address"), (OSError("refused"), "cannot reach the Dask scheduler at")],
)
def test_a_scheduler_that_fails_is_exit_2_with_its_reason(error, words, listening_port):
    from armanim.procs.executors import connect_client

    def failing_client(address, timeout):
        raise error

    with pytest.raises(UsageError, match=words):
        connect_client(failing_client, f"tcp://127.0.0.1:{listening_port}", seconds=30)


@pytest.mark.parametrize(
    "address, words",
    [
        ("tcp://127.0.0.1:{closed}", r"connection refused: nothing listens on port {closed}"),
        ("127.0.0.1:{closed}", r"connection refused"),
        ("tcp://no-such-host.invalid:8786", r"no such host 'no-such-host.invalid'"),
    ],
)
def test_a_refused_scheduler_is_reported_at_once_not_after_the_timeout(address, words, closed_port):
    """Dask's client retries a refused port for its whole timeout and then calls it a timeout;
    armanim asks the port first, so the client is never made and the reason is the real one."""
    from armanim.procs.executors import connect_client

    def client_that_must_not_be_made(address, timeout):
        raise AssertionError("the client was made for a port that refuses")

    address = address.format(closed=closed_port)
    with pytest.raises(
        UsageError,
        match=rf"cannot reach the Dask scheduler at {re.escape(address)} \({words.format(closed=closed_port)}",
    ):
        connect_client(client_that_must_not_be_made, address, seconds=30)


def test_a_sweep_beyond_the_limit_is_exit_2_before_anything_is_built(cli, tmp_path):
    from armanim.runs.sweep import MAX_VARIANTS

    steps = ",".join(str(0.001 * (i + 1)) for i in range(50))
    tolerances = ",".join(str(0.0001 * (i + 1)) for i in range(MAX_VARIANTS // 50 + 1))
    result = cli(
        "sweep", NOTES, "--set", f"solver.step={steps}", "--set", f"solver.tolerance={tolerances}", "--out", tmp_path
    )
    assert result.exit_code == 2, result.output
    assert f"--set: 1,050 variants (50 x 21 values; at most {MAX_VARIANTS:,} in one sweep" in result.stderr
    assert list(tmp_path.iterdir()) == []


def test_a_set_path_deeper_than_a_scene_is_exit_2(cli, tmp_path):
    """Campaign 9: ``--set arm.a.a.a...`` of 5,000 parts built a variant nested 5,000 deep and ended in
    a RecursionError traceback (exit 1) while it was written out; a path deeper than a scene may nest
    is exit 2 before anything is built. 64 parts is a scene's own bound: refused by the scene's check."""
    from armanim.scene.yamlread import MAX_DEPTH

    scene = small_scene(tmp_path, "s")
    result = cli("sweep", scene, "--set", "arm." + ".".join(["a"] * 5_000) + "=1", "--out", tmp_path / "o")
    assert result.exit_code == 2 and "the path is 5,001 fields deep (a scene nests at most 64)" in result.stderr, (
        result.output
    )
    assert "Traceback" not in result.output and not (tmp_path / "o").exists()
    result = cli("sweep", scene, "--set", "arm." + ".".join(["a"] * (MAX_DEPTH - 1)) + "=1", "--out", tmp_path / "o")
    assert result.exit_code == 2 and "Traceback" not in result.output, result.output


def test_a_sweep_and_a_batch_say_their_size_first(cli, tmp_path):
    result = cli(
        "sweep", small_scene(tmp_path, "s"), "--set", "solver.step=0.1,0.2,0.1", "--out", tmp_path / "o", "--jobs", "1"
    )
    assert result.exit_code == 0, result.output
    assert result.stderr.splitlines()[0] == f"sweep of {tmp_path / 's.yaml'}: 2 variants (solver.step)"
    result = cli(
        "run",
        small_scene(tmp_path, "a"),
        small_scene(tmp_path, "b"),
        "--out",
        tmp_path / "o",
        "--no-video",
        "--jobs",
        "1",
    )
    assert result.exit_code == 0 and result.stderr.splitlines()[0] == "batch: 2 scenes", result.output


def test_an_index_csv_made_read_only_is_not_replaced(tmp_path):
    """Campaign 19: a batch's index.csv (a sweep's table alike) its user made read-only (``chmod
    444``) was replaced by the next batch as root, exit 0, the new file 0644. Now refused (exit 3,
    before any scene runs), the file as it was."""
    from armanim.errors import OutputError
    from armanim.output.csvfile import check_table_replaceable
    from armanim.runs import batch

    index = tmp_path / "index.csv"
    batch.write_index(index, [batch.BatchEntry("a", "ok", "a.yaml", 1, 1, 0, 10, None, "a")])
    index.chmod(0o444)
    before = index.read_bytes()
    with pytest.raises(OutputError, match="is write-protected"):
        check_table_replaceable(index, batch.is_index_header, "index.csv")
    with pytest.raises(OutputError, match="is write-protected"):
        batch.write_index(index, [batch.BatchEntry("b", "ok", "b.yaml", 1, 1, 0, 12, None, "b")])
    assert index.read_bytes() == before and index.stat().st_mode & 0o777 == 0o444
