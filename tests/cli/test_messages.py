"""What the command prints (issues 19 and 36): a closed pipe keeps the command's own exit code,
huge flag values are cut, names from files are escaped, every line of a message is short and
printable, numpy's warnings never reach the terminal, numbers zero to the arm's precision print
as 0.

Each test is named in docs/reliability.md, which it keeps true.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import SCENES, TESTS

NOTES = SCENES / "notes-arm.yaml"


@pytest.mark.parametrize(
    "args, code",
    [
        (["validate", NOTES], 0),
        (["check", NOTES, "--golden", TESTS / "golden"], 0),
        (["fk", "--angles", "0,0,0,0"], 0),
        (["check", "BROKEN", "--golden", "GOLDEN"], 1),
    ],
)
def test_a_closed_pipe_keeps_the_command_s_own_exit_code(tmp_path, args, code):
    """``armanim validate s.yaml | head -0``: exit 0 (a failed check stays 1), never click's 1 for EPIPE, no message."""
    import subprocess
    import sys

    if "BROKEN" in args:  # a golden file that differs: the check fails whether or not anyone reads
        (tmp_path / "notes-arm.csv").write_text(
            (TESTS / "golden" / "notes-arm.csv").read_text().replace(",0,", ",1,", 1)
        )
        args = ["check", NOTES, "--golden", tmp_path]
    proc = subprocess.Popen(
        [sys.executable, "-m", "armanim", *map(str, args)], stdout=subprocess.PIPE, stderr=subprocess.PIPE
    )
    proc.stdout.close()  # the reader is gone before armanim writes
    stderr = proc.stderr.read().decode()
    assert proc.wait(timeout=300) == code, stderr
    assert "Traceback" not in stderr and "Broken pipe" not in stderr


def test_a_huge_flag_value_is_cut_in_the_message(cli):
    result = cli("fk", "--angles", ",".join(["1"] * 60_000))
    assert result.exit_code == 2 and "(got 60,000:" in result.stderr and "(119,999 characters)" in result.stderr
    assert len(result.stderr) < 300, len(result.stderr)


ARM = "version: 1\narm: {links: [1, 1, 1, 1]}\n"


def test_numpy_warnings_never_reach_the_terminal(tmp_path):
    scene = tmp_path / "w.yaml"
    scene.write_text(
        ARM + "goals:\n  - {position: [1, 1, 2], tool_axis: [0, 0, -1]}\n"
        "solver: {orientation_weight: 1e-9, max_frames_per_goal: 30}\nrender: {size: [64, 48]}\n"
    )
    done = subprocess.run(
        [sys.executable, "-m", "armanim", "run", str(scene), "--out", str(tmp_path / "o"), "--no-video", "--quiet"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert done.returncode == 0 and "Warning" not in done.stderr, done.stderr
    json.loads(
        (tmp_path / "o" / "w" / "summary.json").read_text(),
        parse_constant=lambda c: pytest.fail(f"{c} in summary.json"),
    )


@pytest.mark.parametrize("columns", ["0", "00"])
def test_a_terminal_width_of_zero_still_shows_every_message(tmp_path, columns):
    """COLUMNS=0 (campaign 13): rich took it for a width of 0 and printed nothing at all, the error
    of a bad scene (exit 2 and no word), fk's table and --help alike. Each is shown as without it."""
    scene = tmp_path / "b.yaml"
    scene.write_text("version: 1\narm: {links: [1, 1, x]}\ngoals: [[1, 1, 1]]\n")
    env = {**os.environ, "COLUMNS": columns}

    def armanim(*args: str) -> subprocess.CompletedProcess:
        return subprocess.run(
            [sys.executable, "-m", "armanim", *args], capture_output=True, text=True, timeout=300, env=env
        )

    bad = armanim("validate", str(scene))
    assert bad.returncode == 2 and "b.yaml:2: arm.links[2]: must be a number" in bad.stderr, bad
    fk = armanim("fk", "--angles", "0,0,0,0")
    assert fk.returncode == 0 and "Forward kinematics" in fk.stdout, fk
    assert "Usage" in armanim("--help").stdout


def test_numba_told_not_to_compile_still_gives_the_answer(tmp_path):
    """NUMBA_DISABLE_JIT=1 (campaign 15): numba ran armanim's kernels as plain Python, where x / 0
    raises instead of giving inf as numba's numpy error model does, and validate (and run) of a
    plain scene ended in a ZeroDivisionError traceback. The kernels run compiled whatever it says,
    and a note says the variable was ignored."""
    scene = tmp_path / "s.yaml"
    scene.write_text("version: 1\nname: s\narm: {links: [1, 1, 1]}\ngoals: [[1, 1, 1], [0.5, -1, 1]]\n")
    env = {**os.environ, "NUMBA_DISABLE_JIT": "1"}
    done = subprocess.run(
        [sys.executable, "-m", "armanim", "validate", str(scene)], capture_output=True, text=True, timeout=600, env=env
    )
    assert done.returncode == 0 and "Traceback" not in done.stderr, done
    assert "NUMBA_DISABLE_JIT ignored" in done.stderr


def test_every_line_of_a_message_is_short_and_printable():
    from armanim.errors import message_lines

    text = message_lines("a.yaml:1: " + "x\u202e\x9b" * 10_000 + "\nsecond")
    first, second = text.split("\n")
    assert len(first) < 700 and first.isprintable() and second == "second"


@pytest.mark.parametrize(
    "args,noise",
    [
        (["ik", "--robot", "ur5", "--goal", "0.4,0.2,0.3"], "e-1"),
        (["fk", "--robot", "panda", "--angles", "0,0,0,-90,0,90,45"], "e-1"),
        (["fk", "--robot", "ur5", "--angles", "0,-90,90,-90,-90,0"], "e-1"),
    ],
)
def test_numbers_zero_to_the_arm_s_precision_print_as_0(cli, args, noise):
    result = cli(*args)
    assert result.exit_code == 0 and noise not in result.stdout and "-0 " not in result.stdout, result.stdout


def test_jobs_0_is_a_one_line_message(cli):
    result = cli("run", Path(__file__).parents[2] / "scenes" / "notes-arm.yaml", "--jobs", "0", "--no-video")
    assert result.exit_code == 2 and result.stderr.strip().splitlines() == [
        "--jobs: expected at least 1 worker process (got 0; leave it out to use every core)"
    ]


def test_a_run_whose_compiled_code_numba_cannot_keep_never_says_once_after_installing():
    """Campaign 16, a user with no writable home running a read-only install: each run compiled
    for 87 s and said "numba compiled its code for 86.7 s more, once after installing". Where
    numba keeps nothing the time line says so, and what to do."""
    from armanim.cli.reports import run_time_line
    from armanim.runs.stopwatch import Stopwatch

    line = run_time_line(Stopwatch(90.0, 86.7), False, False, kept=False)
    assert "once after installing" not in line
    assert "every command compiles it again" in line and "NUMBA_CACHE_DIR" in line
    assert "once after installing" in run_time_line(Stopwatch(90.0, 86.7), False, False)


def test_a_long_line_is_cut_in_its_middle_keeping_what_went_wrong(tmp_path):
    """Campaign 16: ``run --out`` a path past PATH_MAX (4,266 characters) said only the path and
    "... (cut: the line has 4,365 characters)": the reason and the remedy, at the end, were cut."""
    long = "/".join(["p" * 250] * 17)
    scene = tmp_path / "s.yaml"
    scene.write_text("version: 1\nname: s\narm: {links: [1, 1, 1]}\ngoals: [[1, 1, 1]]\n")
    done = subprocess.run(
        [sys.executable, "-m", "armanim", "run", str(scene), "--out", long, "--no-video", "-q"],
        capture_output=True,
        text=True,
        timeout=600,
        cwd=tmp_path,
    )
    assert done.returncode == 3, done.stderr
    line = done.stderr.strip().splitlines()[-1]
    assert len(line) < 700 and line.startswith("ppp") and "characters cut" in line
    assert line.endswith("choose another folder with --out)"), line


def _words(text: str) -> set[str]:
    """The words of a command's output, its boxes' lines taken away."""
    import re

    return set(re.findall(r"[-\w]{3,}", re.sub(r"[│╭╮╰╯─┃┏┓┗┛━┡┩╇┳┻╋┠┨┼┬┴├┤┌┐└┘]", " ", text)))


@pytest.mark.parametrize(
    "args, columns",
    [(["ik", "--help"], "80"), (["ik", "--help"], "20"), (["run", "--help"], "20"), (["robots"], "20")],
)
def test_a_narrow_terminal_loses_no_word_of_the_help_or_a_table(args, columns):
    """Campaign 17: at 80 columns ``ik --help`` cut the last letters of its help's lines ("default:
    fo" for "four"); at 20 every option's help text was dropped and the robots' table showed only
    ellipses. Every word of the output at 200 columns is there at the narrow width."""

    def at(width: str) -> str:
        done = subprocess.run(
            [sys.executable, "-m", "armanim", *args],
            capture_output=True,
            text=True,
            timeout=300,
            env={**os.environ, "COLUMNS": width},
        )
        assert done.returncode == 0, done.stderr
        return done.stdout

    assert _words(at("200")) - _words(at(columns)) == set()


@pytest.mark.parametrize("args", [["schema"], ["--help"], ["--version"], ["robots"]])
def test_no_standard_output_at_all_is_a_closed_reader(args):
    """``armanim schema >&-`` (campaign 17: an AttributeError traceback, exit 1): as ``| head -0``,
    exit 0 and no word."""
    done = subprocess.run(
        [sys.executable, "-m", "armanim", *args],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
        timeout=300,
        preexec_fn=lambda: os.close(1),
    )
    assert (done.returncode, done.stderr) == (0, "")


@pytest.mark.parametrize("args", [["--help"], ["run", "--help"], ["--version"], ["schema"]])
def test_a_full_standard_output_is_an_output_error(args):
    """``armanim --help > /dev/full`` (campaign 17: a traceback, exit 1; ``--version`` exit 0 having
    written nothing): exit 3 and the reason, as any command's output error."""
    with open("/dev/full", "w") as full:
        done = subprocess.run(
            [sys.executable, "-m", "armanim", *args], stdout=full, stderr=subprocess.PIPE, text=True, timeout=300
        )
    assert done.returncode == 3, done.stderr
    assert done.stderr == "armanim: output: No space left on device\n"
