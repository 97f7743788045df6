"""The ninth to eighteenth attack campaigns (issue 50): hostile inputs, interrupts and outputs, as a script.

Run: ``python benchmarks/attack_campaign.py`` (some 20-40 minutes on two shared cores for the ninth),
``--only CLASS`` for one class (the ninth's: mesh, frames, export, nested, sizes, signals, folders,
inputs; the tenth's, new attacks on the same classes: mesh10, frames10, signals10, loss10,
inputs10, wrong10; the eleventh's, new again: mesh11, frames11, signals11, loss11, inputs11, wrong11;
the twelfth's: mesh12, frames12, signals12, loss12, inputs12, wrong12; the thirteenth's: mesh13,
frames13, signals13, loss13, inputs13, wrong13; the fourteenth's: mesh14 ... wrong14; the
fifteenth's: mesh15 ... wrong15; the sixteenth's, new angles: perms16 (as a user who is not root:
``--as-user NAME``, with ``--user-python`` an interpreter that user can run), env16 (full disks: run
as root, which mounts a small tmpfs), api16 (the Python API, by snippets)); the seventeenth's:
mesh17, frames17, signals17, wrong17 (new variants of the issue's classes) and ro17 (read-only
mounts), lock17 (the compile lock and ``warm``: give ``--warm-cache`` numba's cache of ``--src``,
warmed), dask17 (Dask schedulers), env17 (narrow terminals, odd standard outputs, LANG=C names));
the eighteenth's, part A (new angles): clock18 (the wall clock in 1970, 2039, 2100, ten times fast or
jumping mid-command, by libfaketime), between18 (a file changed between two commands: after
``validate``, in a run folder or a golden pair, a run folder's marker listing files outside it),
concur18 (two commands at once on one folder, golden, index or file); part B, new variants of the
issue's classes: mesh18, frames18, export18, signals18, inputs18, wrong18; the nineteenth's: var19
(new variants on what the eighteenth's fixes touched: the marker's sha256, the lock of a folder of
marked files, links into /proc, the OBJ reader, write protection as root)),
``--match TEXT ...`` for the attempts whose name holds one of the texts, ``--list``
to list them, ``--keep DIR`` to keep every attempt's folder.

Each attempt makes its inputs in a folder of its own, runs ``python -m armanim`` from this
checkout (``src`` first on ``PYTHONPATH``) under ``nice -n 10``, an address-space limit
(``--memory``, default 4 GB) and a timeout, and holds the outcome to what docs/reliability.md
promises:

- the exit code is one the attempt allows (2 for bad input, 3 for an output refused, 130 for an
  interrupt, ...), and the process ended before its timeout (else: a hang);
- no traceback, and no "Exception ignored", on either stream;
- every file the attempt marks as the user's is byte for byte as it was, with its type, and no
  litter (``.partial``, ``.old-``, ``.tmp``) is left where outputs go;
- the message says what the attempt expects (a pattern), when it names one.

It prints one line per attempt and a table by class, and exits 1 when any attempt went wrong.
The campaigns before this one were scripts kept in the sessions' scratch; their classes are the
ones of benchmarks/README.md ("Attack campaigns").
"""

from __future__ import annotations

import argparse
import contextlib
import hashlib
import os
import re
import resource
import shutil
import signal
import stat
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SCENES = ROOT / "scenes"
SRC = ROOT / "src"  # the armanim attacked: --src (a frozen copy, so that edits meanwhile change no verdict)
LITTER = re.compile(r"\.partial$|\.old-\d+$|\.tmp$|\.part$")
UNSET = "<unset>"  # an attempt's env value: the variable removed from armanim's environment


# ------------------------------------------------------------------ what an attempt is


@dataclass
class Attempt:
    """One hostile input or fault and what armanim must do with it."""

    kind: str  # the class
    name: str
    args: list[str]  # armanim's arguments; "{d}" is the attempt's folder
    setup: Callable[[Path], None] = lambda d: None
    codes: tuple[int, ...] = (2,)
    message: str | None = None  # a regex stderr + stdout must match
    keep: tuple[str, ...] = ()  # the user's paths (relative to the folder), left as they were
    timeout: float = 120.0
    interrupt: tuple[float, str] | None = (
        None  # (seconds, "SIGINT" to the group | "SIGTERM" to armanim | "SIGTERMG" to the group; SIGHUP(G), SIGQUITG alike)
    )
    also: tuple[tuple[float, str], ...] = ()  # more signals after the first, seconds from the start
    env: dict[str, str] = field(default_factory=dict)
    after: Callable[[Path], list[str]] | None = None  # more checks: a list of problems
    litter_in: tuple[str, ...] = ("o",)  # folders where outputs go: no staging or temporary file left
    message_if_2: str | None = None  # a regex stderr + stdout must match when the exit code is 2
    message_if_3: str | None = None  # a regex stderr + stdout must match when the exit code is 3
    not_message: str | None = None  # a regex stderr + stdout must not match
    linger: float = 0.0  # seconds after armanim ends within which nothing it started may still run
    user: bool = False  # run as the campaign's non-root user (--as-user): the folder is made theirs first
    root_owned: tuple[str, ...] = ()  # paths (relative to the folder) left root's when the folder is made the user's
    python: str | None = None  # a Python snippet run instead of ``-m armanim`` (after PRELUDE; args are its argv)
    fsize: int | None = None  # RLIMIT_FSIZE in bytes (a file past it: EFBIG; SIGXFSZ is Python's SIG_IGN)
    stdout: str = "pipe"  # "closed" (no fd 1), "full" (/dev/full), "head" (a reader gone after one line),
    # "stuck" (a pipe nobody reads: a writer blocks once its 64 KB are full)


def fingerprint(path: Path) -> object:
    """What a path is: its type and bytes (a file), target (a link) or listing (a folder), recursively."""
    if os.path.islink(path):
        return ("link", os.readlink(path))
    if not os.path.exists(path):
        return None
    mode = os.stat(path).st_mode
    if stat.S_ISDIR(mode):
        return ("dir", {child.name: fingerprint(child) for child in sorted(path.iterdir())})
    if stat.S_ISREG(mode):
        digest = hashlib.sha256()
        with open(path, "rb") as handle:
            for block in iter(lambda: handle.read(1 << 20), b""):
                digest.update(block)
        return ("file", os.stat(path).st_ino, digest.hexdigest())
    return ("special", stat.S_IFMT(mode), os.stat(path).st_ino)


AS_USER: tuple[int, int, str] | None = None  # --as-user: (uid, gid, home)
AS_USER_NAME = ""
USER_PYTHON = sys.executable  # --user-python: the interpreter a user attempt runs (it must reach it)


def _limits(
    memory: int, user: tuple[int, int, str] | None = None, fsize: int | None = None, close_stdout: bool = False
) -> Callable[[], None]:
    def apply() -> None:
        if close_stdout:  # armanim started with no standard output at all (``armanim ... >&-``)
            os.close(1)
        # a campaign started in the background has SIGINT ignored, and one started with nohup SIGHUP
        # (campaign 13's first signals13 pass: every SIGHUP attempt then measured nohup's armanim)
        for signum in (signal.SIGINT, signal.SIGHUP, signal.SIGQUIT):
            signal.signal(signum, signal.SIG_DFL)
        os.setsid()
        os.nice(10)
        resource.setrlimit(resource.RLIMIT_AS, (memory, memory))
        if fsize is not None:
            resource.setrlimit(resource.RLIMIT_FSIZE, (fsize, fsize))
        if user is not None:  # last: dropping root
            os.setgroups([])
            os.setgid(user[1])
            os.setuid(user[0])

    return apply


def make_users(folder: Path, attempt: Attempt) -> None:
    """Give ``folder`` (as the setup left it, modes kept) to the campaign's user, but ``root_owned``."""
    assert AS_USER is not None
    uid, gid, _ = AS_USER
    left = {os.path.normpath(folder / p) for p in attempt.root_owned}
    for where, dirs, files in os.walk(folder):
        for name in [*dirs, *files, ""] if where == str(folder) else [*dirs, *files]:
            path = os.path.join(where, name) if name else where
            if os.path.normpath(path) not in left and not os.path.ismount(path):
                os.lchown(path, uid, gid)


def run_attempt(attempt: Attempt, folder: Path, memory: int) -> tuple[str, list[str], float, int | None]:
    """Run one attempt in ``folder``: (verdict class, problems, seconds, exit code)."""
    folder.mkdir(parents=True)
    if attempt.user and AS_USER is None and os.geteuid() == 0:
        raise RuntimeError("a non-root attempt: give --as-user USER (root writes through read-only modes)")
    attempt.setup(folder)
    user = AS_USER if attempt.user and os.geteuid() == 0 else None
    if user is not None:
        make_users(folder, attempt)
    kept = {p: fingerprint(folder / p) for p in attempt.keep}
    args = [a.replace("{d}", str(folder)) for a in attempt.args]
    env = {**os.environ, "PYTHONPATH": str(SRC), "COLUMNS": "120"}
    if user is not None:
        env.update(HOME=user[2], USER=AS_USER_NAME, LOGNAME=AS_USER_NAME)
    env = {name: value for name, value in {**env, **attempt.env}.items() if value != UNSET}
    python = USER_PYTHON if user is not None else sys.executable
    command = [python, "-c", PRELUDE + attempt.python, *args] if attempt.python else [python, "-m", "armanim", *args]
    started = time.perf_counter()
    stuck_reader = None
    if attempt.stdout == "full":
        sink = open("/dev/full", "w")  # noqa: SIM115 (closed below)
    elif attempt.stdout == "stuck":
        stuck_reader, stuck_writer = os.pipe()
        sink = os.fdopen(stuck_writer, "w")
    else:
        sink = None
    proc = subprocess.Popen(
        command,
        cwd=folder,
        env=env,
        stdin=subprocess.DEVNULL,
        stdout=subprocess.PIPE if sink is None else sink,
        stderr=subprocess.PIPE,
        text=True,
        errors="replace",
        preexec_fn=_limits(memory, user, attempt.fsize, close_stdout=attempt.stdout == "closed"),
    )
    if sink is not None:
        sink.close()
    if attempt.stdout == "head" and proc.stdout is not None:
        first_line = proc.stdout.readline()
        proc.stdout.close()  # the reader goes: armanim's next writes meet a broken pipe
        proc.stdout = None
    else:
        first_line = ""
    for delay, signame in (attempt.interrupt, *attempt.also) if attempt.interrupt is not None else ():
        try:
            proc.wait(max(0.0, started + delay - time.perf_counter()))
        except subprocess.TimeoutExpired:
            if signame == "SIGINT":
                os.killpg(proc.pid, signal.SIGINT)
            elif signame.endswith("G"):  # SIGTERMG, SIGHUPG, SIGQUITG: to the group
                os.killpg(proc.pid, getattr(signal, signame[:-1]))
            else:  # SIGTERM, SIGHUP: to armanim alone
                proc.send_signal(getattr(signal, signame))
    hung = False
    try:
        out, err = proc.communicate(timeout=attempt.timeout)
    except subprocess.TimeoutExpired:
        hung = True
        os.killpg(proc.pid, signal.SIGKILL)
        out, err = proc.communicate()
    finally:
        if stuck_reader is not None:
            os.close(stuck_reader)
    out = first_line + (out or "")
    seconds = time.perf_counter() - started
    lingering = [] if hung or not attempt.linger else still_running(proc.pid, folder, attempt.linger)
    with contextlib.suppress(OSError):
        os.killpg(proc.pid, signal.SIGKILL)  # nothing of the attempt outlives it
    problems: list[str] = []
    verdict = "right"
    if hung:
        return "hang", [f"still running after {attempt.timeout:g} s"], seconds, None
    text = out + err
    if "Traceback" in text or "Exception ignored" in text:
        verdict = "traceback"
        problems.append("traceback: " + err.strip().splitlines()[-1][:300])
    if proc.returncode not in attempt.codes:
        problems.append(f"exit {proc.returncode}, expected {'/'.join(map(str, attempt.codes))}")
    if attempt.message is not None and not re.search(attempt.message, text, re.S):
        problems.append(f"message does not match {attempt.message!r}")
    if attempt.message_if_2 is not None and proc.returncode == 2 and not re.search(attempt.message_if_2, text):
        problems.append(f"exit 2 without FILE:LINE ({attempt.message_if_2!r})")
    if attempt.message_if_3 is not None and proc.returncode == 3 and not re.search(attempt.message_if_3, text):
        problems.append(f"exit 3 without naming the cause ({attempt.message_if_3!r})")
    if attempt.not_message is not None and re.search(attempt.not_message, text):
        problems.append(f"the message matches {attempt.not_message!r}")
    if lingering:
        problems.append(f"still running {attempt.linger:g} s after armanim ended: {', '.join(lingering[:4])}")
    for path, before in kept.items():
        if fingerprint(folder / path) != before:
            problems.append(f"{path} changed")
            verdict = "data loss"
    for where in attempt.litter_in:
        base = folder / where
        if base.is_dir():
            litter = [
                str(p.relative_to(folder))
                for p in base.rglob("*")
                if LITTER.search(p.name) and str(p.relative_to(folder)) not in attempt.keep  # the user's own: kept
            ]
            if litter:
                problems.append(f"litter: {litter[:4]}")
    if attempt.after is not None:
        problems += attempt.after(folder)
    if problems and verdict == "right":
        verdict = "wrong"
    if problems and not text.strip() == "":
        problems.append("said: " + " | ".join(text.strip().splitlines()[-3:])[:400])
    return verdict, problems, seconds, proc.returncode


def still_running(session: int, folder: Path, within: float) -> list[str]:
    """The processes of armanim's session, or working in ``folder`` (ffmpeg runs in a session of its
    own), still running ``within`` seconds after armanim ended (none, as soon as none is)."""
    deadline = time.perf_counter() + within
    while True:
        found = []
        for entry in os.listdir("/proc"):
            if not entry.isdigit():
                continue
            try:
                text = Path(f"/proc/{entry}/stat").read_text()
                fields = text[text.rindex(")") + 2 :].split()  # state, ppid, pgrp, session, ...
                cwd = os.readlink(f"/proc/{entry}/cwd")
            except (OSError, ValueError):
                continue
            if fields[0] != "Z" and (int(fields[3]) == session or cwd == str(folder) or cwd.startswith(f"{folder}/")):
                found.append(f"{text[text.index('(') + 1 : text.rindex(')')]} ({entry})")
        if not found or time.perf_counter() > deadline:
            return found
        time.sleep(0.2)


def unmount_under(folder: Path) -> None:
    """Unmount every file system an attempt mounted in its folder (a small tmpfs: a full disk)."""
    with contextlib.suppress(OSError):
        mounts = [line.split()[1] for line in Path("/proc/mounts").read_text().splitlines()]
        for point in sorted((m for m in mounts if m.startswith(f"{folder}/")), key=len, reverse=True):
            subprocess.run(["umount", "-l", point], check=False, capture_output=True)


# ------------------------------------------------------------------ inputs


def write(path: Path, text: str | bytes) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    if isinstance(text, bytes):
        path.write_bytes(text)
    else:
        path.write_text(text)
    return path


def fifo(path: Path) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    os.mkfifo(path)


def sparse(path: Path, size: int) -> None:
    with open(path, "wb") as handle:
        handle.truncate(size)


def stl(triangles: int = 2, size: float = 0.05) -> bytes:
    """A small binary STL of ``triangles`` triangles."""
    import numpy as np

    records = np.zeros(triangles, dtype=[("normal", "<f4", 3), ("v", "<f4", (3, 3)), ("attr", "<u2")])
    records["v"] = np.array([[0, 0, 0], [size, 0, 0], [0, size, 0]]) + np.arange(triangles)[:, None, None] * size / 10
    return b"\0" * 80 + np.uint32(triangles).tobytes() + records.tobytes()


def urdf_text(visual: str = "", collision: str | None = None) -> str:
    """A 3-joint URDF whose link l1 has ``visual`` and ``collision`` (default a cylinder)."""
    cylinder = (
        '<collision><geometry><cylinder radius="0.03" length="0.3"/></geometry><origin xyz="0 0 0.15"/></collision>'
    )
    lines = ['<?xml version="1.0"?>', '<robot name="r">']
    for i in range(4):
        col = (collision if (i == 1 and collision is not None) else cylinder) if i else ""
        vis = visual if i == 1 else ""
        lines.append(f'<link name="l{i}">{vis}{col}</link>')
    for i in range(3):
        origin = "0 0 0.3" if i else "0 0 0.1"
        axis = "0 1 0" if i else "0 0 1"
        lines.append(
            f'<joint name="j{i}" type="revolute"><parent link="l{i}"/><child link="l{i + 1}"/>'
            f'<origin xyz="{origin}"/><axis xyz="{axis}"/><limit lower="-2" upper="2" effort="1" velocity="1"/></joint>'
        )
    return "\n".join([*lines, "</robot>"]) + "\n"


URDF_SCENE = (
    "version: 1\nname: m\narm: {urdf: robot.urdf}\ngoals: [[0.3, 0.1, 0.4]]\nrender: {size: [160, 90], fps: 10}\n"
)
TOOL_SCENE = (
    "version: 1\nname: t\narm:\n  links: [1, 1, 1]\n  tool: {length: 0.2, mesh: TOOL}\n"
    "goals: [[1, 1, 1]]\nrender: {size: [160, 90], fps: 10}\n"
)
TINY = "version: 1\nname: tiny\narm: {links: [1, 1, 1]}\ngoals: [[1, 1, 1], [0.5, -1, 1]]\nrender: {size: [160, 90], fps: 10}\n"


def urdf_robot(
    visual: str = "", collision: str | None = None, files: dict[str, bytes | str | tuple | None] | None = None
):
    """Setup: robot.urdf and s.yaml, and ``files`` (None: a FIFO; ("->", target): a link)."""

    def setup(d: Path) -> None:
        write(d / "robot.urdf", urdf_text(visual, collision))
        write(d / "s.yaml", URDF_SCENE)
        for name, content in (files or {}).items():
            if content is None:
                fifo(d / name)
            elif isinstance(content, tuple):  # ("->", target): a symbolic link
                (d / name).parent.mkdir(parents=True, exist_ok=True)
                os.symlink(content[1], d / name)
            else:
                write(d / name, content)

    return setup


def mesh_tag(name: str, scale: str = "") -> str:
    return f'<geometry><mesh filename="{name}"{f" scale={scale!r}" if scale else ""}/></geometry>'


def vis(name: str) -> str:
    return f"<visual>{mesh_tag(name)}</visual>"


def col(name: str) -> str:
    return f"<collision>{mesh_tag(name)}</collision>"


def dae(geometries: int = 1, nodes: int = 1, instances_per_node: int = 1, extra: str = "") -> str:
    """A COLLADA file: ``geometries`` triangles geometries, ``nodes`` nodes each instancing geometry 0
    ``instances_per_node`` times."""
    tri = (
        '<geometry id="g{i}"><mesh><source id="p{i}"><float_array id="a{i}" count="9">0 0 0 0.05 0 0 0 0.05 0'
        '</float_array><technique_common><accessor source="#a{i}" count="3" stride="3"><param name="X" type="float"/>'
        '<param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source>'
        '<vertices id="v{i}"><input semantic="POSITION" source="#p{i}"/></vertices>'
        '<triangles count="1"><input semantic="VERTEX" source="#v{i}" offset="0"/><p>0 1 2</p></triangles></mesh></geometry>'
    )
    geoms = "".join(tri.format(i=i) for i in range(geometries))
    inst = '<instance_geometry url="#g0"/>' * instances_per_node
    node_text = "".join(f'<node id="n{i}">{inst}</node>' for i in range(nodes))
    return (
        '<?xml version="1.0"?><COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">'
        f'<asset><unit meter="1"/></asset><library_geometries>{geoms}</library_geometries>{extra}'
        f'<library_visual_scenes><visual_scene id="s">{node_text}</visual_scene></library_visual_scenes>'
        '<scene><instance_visual_scene url="#s"/></scene></COLLADA>'
    )


def tiny_scene(name: str = "s.yaml", text: str = TINY) -> Callable[[Path], None]:
    return lambda d: write(d / name, text) and None


def finished_run(d: Path, text: str = TINY, name: str = "s.yaml", video: bool = False) -> Path:
    """Run ``text`` into d/o (the campaign's own setup, checked); the run folder."""
    write(d / name, text)
    args = [sys.executable, "-m", "armanim", "run", name, "--out", "o", "-q"] + ([] if video else ["--no-video"])
    env = dict(os.environ, PYTHONPATH=str(SRC))
    done = subprocess.run(args, cwd=d, env=env, capture_output=True, text=True, timeout=600)
    if done.returncode != 0:
        raise RuntimeError(f"setup run failed: {done.stderr[-500:]}")
    return next(p for p in (d / "o").iterdir() if p.is_dir() and not p.name.startswith("."))


def export_of(d: Path, out: str) -> None:
    env = dict(os.environ, PYTHONPATH=str(SRC))
    done = subprocess.run(
        [sys.executable, "-m", "armanim", "export", "o/tiny", "--out", out],
        cwd=d,
        env=env,
        capture_output=True,
        text=True,
    )
    if done.returncode != 0:
        raise RuntimeError(f"setup export failed: {done.stderr[-500:]}")


def exists(*paths: str, present: bool = True) -> Callable[[Path], list[str]]:
    def check(d: Path) -> list[str]:
        return [f"{p} {'missing' if present else 'present'}" for p in paths if os.path.lexists(d / p) != present]

    return check


# ------------------------------------------------------------------ the classes

BOMB_DAE = (
    '<?xml version="1.0"?><COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">'
    + dae(1)[dae(1).index("<asset>") : dae(1).index("<library_visual_scenes>")]
    + "<library_nodes>"
    + '<node id="m0"><instance_geometry url="#g0"/></node>'
    + "".join(f'<node id="m{k}">' + f'<instance_node url="#m{k - 1}"/>' * 10 + "</node>" for k in range(1, 8))
    + "</library_nodes>"
    + '<library_visual_scenes><visual_scene id="s"><node id="top"><instance_node url="#m7"/></node></visual_scene>'
    + '</library_visual_scenes><scene><instance_visual_scene url="#s"/></scene></COLLADA>'
)


def mesh_attempts() -> list[Attempt]:
    """Files a mesh names, by commands the campaigns before did not aim at (robots --fit, import
    moveit, fk/ik --scene, check, sweep) and by new shapes of file."""
    k = "mesh"
    out = []
    # robots --fit: a collision mesh of every hostile kind is an error at its line (exit 2), at once
    for label, name, files in [
        ("a FIFO", "a.stl", {"a.stl": None}),
        ("a zip named .stl", "a.stl", {"a.stl": b"PK\x03\x04" + b"\0" * 200}),
        ("a 10 GB sparse STL", "big.stl", {}),
        ("the COLLADA instance bomb", "b.dae", {"b.dae": BOMB_DAE}),
        (
            "an OBJ whose mtllib is a FIFO",
            "a.obj",
            {"a.obj": "mtllib m.mtl\nv 0 0 0\nv .05 0 0\nv 0 .05 0\nf 1 2 3\n", "m.mtl": None},
        ),
        ("a .gltf", "a.gltf", {"a.gltf": '{"asset": {"version": "2.0"}}'}),
        ("a link loop", "loop.stl", {}),
        ("a folder", "dir.stl", {}),
    ]:

        def setup(d: Path, files=files, name=name) -> None:
            urdf_robot(collision=col(name), files=files)(d)
            if name == "big.stl":
                sparse(d / "big.stl", 10 << 30)
            if name == "loop.stl":
                os.symlink("loop.stl", d / "loop.stl")
            if name == "dir.stl":
                (d / "dir.stl").mkdir()

        ok_codes = (0,) if name == "a.obj" else (2,)
        out.append(
            Attempt(
                k,
                f"robots --fit, collision mesh {label}",
                ["robots", "--fit", "robot.urdf"],
                setup,
                ok_codes,
                timeout=90,
            )
        )
    out.append(
        Attempt(
            k,
            "robots --fit --package-dir a FIFO",
            ["robots", "--fit", "robot.urdf", "--package-dir", "pkg"],
            urdf_robot(collision=col("package://p/a.stl"), files={"pkg": None}),
            (2,),
            timeout=60,
        )
    )
    out.append(
        Attempt(
            k,
            "robots --fit --package-dir a file",
            ["robots", "--fit", "robot.urdf", "--package-dir", "pkg"],
            urdf_robot(collision=col("package://p/a.stl"), files={"pkg": "x"}),
            (2,),
            timeout=60,
        )
    )
    # a visual mesh of each kind, drawn by fk --png and checked by `check`, `sweep`, ik
    for label, name, files in [
        ("a FIFO", "a.stl", {"a.stl": None}),
        ("the instance bomb", "b.dae", {"b.dae": BOMB_DAE}),
        ("300,000 instance_geometry nodes", "n.dae", {"n.dae": dae(1, 300_000)}),
        (
            "an OBJ of 3,000 faces of 1,000 corners",
            "f.obj",
            {
                "f.obj": "".join(f"v {i % 7} {i % 5} {i % 3}\n" for i in range(1000))
                + ("f " + " ".join(str(i + 1) for i in range(1000)) + "\n") * 3000
            },
        ),
    ]:
        out.append(
            Attempt(
                k,
                f"fk --scene --png, visual {label}",
                ["fk", "--scene", "s.yaml", "--angles", "0,10,20", "--png", "p.png"],
                urdf_robot(vis(name), files=files),
                (0,),
                timeout=150,
            )
        )
    out.append(
        Attempt(
            k,
            "ik --scene, collision mesh a FIFO",
            ["ik", "--scene", "s.yaml", "--goal", "0.2,0.1,0.4"],
            urdf_robot(collision=col("a.stl"), files={"a.stl": None}),
            (2,),
            timeout=60,
        )
    )
    out.append(
        Attempt(
            k,
            "check, visual mesh a FIFO",
            ["check", "s.yaml", "--golden", "g", "--update"],
            urdf_robot(vis("a.stl"), files={"a.stl": None}),
            (0,),
            timeout=150,
        )
    )
    out.append(
        Attempt(
            k,
            "sweep, visual the instance bomb",
            ["sweep", "s.yaml", "--set", "solver.step=0.1,0.2", "--out", "o", "-q", "--video", "--jobs", "1"],
            urdf_robot(vis("b.dae"), files={"b.dae": BOMB_DAE}),
            (0,),
            timeout=300,
        )
    )
    # arm.tool.mesh through fk --png (the tool's look)
    for label, files, tool in [
        ("a FIFO", {"t.stl": None}, "t.stl"),
        ("the instance bomb", {"t.dae": BOMB_DAE}, "t.dae"),
        ("a link to /dev/zero named .stl", {}, "z.stl"),
        ("a 2 GB sparse STL", {}, "sp.stl"),
    ]:

        def setup(d: Path, files=files, tool=tool) -> None:
            write(d / "s.yaml", TOOL_SCENE.replace("TOOL", tool))
            for name, content in files.items():
                fifo(d / name) if content is None else write(d / name, content)
            if tool == "z.stl":
                os.symlink("/dev/zero", d / "z.stl")
            if tool == "sp.stl":
                sparse(d / "sp.stl", 2 << 30)

        out.append(
            Attempt(
                k,
                f"fk --png, tool mesh {label}",
                ["fk", "--scene", "s.yaml", "--angles", "0,10,20", "--png", "p.png"],
                setup,
                (0, 2),
                timeout=90,
            )
        )
    # import moveit with a URDF whose meshes are hostile
    out.append(
        Attempt(
            k,
            "import moveit --urdf whose collision mesh is a FIFO",
            ["import", "moveit", "w.scene", "--urdf", "robot.urdf", "--tip-link", "l3", "--out", "x.yaml"],
            lambda d: (
                urdf_robot(collision=col("a.stl"), files={"a.stl": None})(d),
                write(d / "w.scene", "w\n* box\n1\nbox\n0.1 0.1 0.1\n1 1 1\n0 0 0 1\n0 0 0 0\n.\n"),
            ),
            (0, 2),
            timeout=60,
        )
    )

    # the same STL by three names (a hard link, a link, its name) in one robot: read once, and bounded
    def three(d: Path) -> None:
        write(d / "a.stl", stl(50))
        os.link(d / "a.stl", d / "h.stl")
        os.symlink("a.stl", d / "s.stl")
        text = (
            urdf_text(vis("a.stl"))
            .replace('<link name="l2">', f'<link name="l2">{vis("h.stl")}')
            .replace('<link name="l3">', f'<link name="l3">{vis("s.stl")}')
        )
        write(d / "robot.urdf", text)
        write(d / "s.yaml", URDF_SCENE)

    out.append(
        Attempt(
            k,
            "run --viewer, one STL by a name, a hard link and a link",
            ["run", "s.yaml", "--out", "o", "--no-video", "--viewer", "-q"],
            three,
            (0,),
            timeout=200,
        )
    )

    # a mesh named through a link into a folder out of the URDF's: drawn or a note, never a hang
    def outside(d: Path) -> None:
        urdf_robot(vis("far/a.stl"))(d)
        os.symlink("/proc/self/fd", d / "far")

    out.append(
        Attempt(
            k,
            "run --viewer, a mesh under a link to /proc/self/fd",
            ["run", "s.yaml", "--out", "o", "--no-video", "--viewer", "-q"],
            outside,
            (0,),
            timeout=200,
        )
    )
    out.append(
        Attempt(
            k,
            "run --viewer, mesh file:///proc/self/fd/0.stl",
            ["run", "s.yaml", "--out", "o", "--no-video", "--viewer", "-q"],
            urdf_robot(vis("file:///proc/self/fd/0")),
            (0,),
            timeout=200,
        )
    )
    out.append(
        Attempt(
            k,
            "run --viewer, mesh /dev/stdin.stl via package dir",
            ["run", "s.yaml", "--out", "o", "--no-video", "--viewer", "-q"],
            urdf_robot(vis("file:///dev/stdin")),
            (0,),
            timeout=200,
        )
    )
    return out


PATH_SCENE = """version: 1
name: p
arm: {links: [1, 1, 1], axes: [z, y, y]}
goals:
  - path: {line: [[1, 0.5, 1], [1, -0.5, 1]]}
    speed: SPEED
solver: {path_tolerance: TOL}
render: {size: [160, 90], fps: 30}
"""


def frames_attempts() -> list[Attempt]:
    """path_tolerance near its floor and rates near theirs, reached through command-line
    overrides (--fps, --quality, sweep --set, render --fps) rather than the scene."""
    k = "frames"
    out = []

    def path(tol: str, speed: str = "0.5") -> Callable[[Path], None]:
        return tiny_scene(text=PATH_SCENE.replace("TOL", tol).replace("SPEED", speed))

    # the finest path_tolerance validate takes at 30 fps, then 8x the frames
    out.append(Attempt(k, "validate path_tolerance 1e-6 (the reference)", ["validate", "s.yaml"], path("1e-6"), (0, 2)))
    # 1e-6 is refused at validate (1,601,202 frames in all); 3e-6 is the finest taken at 30 fps
    for tol in ("1e-6", "3e-6", "1e-5"):
        for flag in (["--fps", "240"], ["--quality", "4k"], ["--fps", "0.01"]):
            out.append(
                Attempt(
                    k,
                    f"run path_tolerance {tol} {' '.join(flag)}",
                    ["run", "s.yaml", "--out", "o", "--no-video", "-q", *flag],
                    path(tol),
                    (2,) if tol == "1e-6" else (0, 2),
                    timeout=400,
                )
            )
    # a path whose frames at its speed fit at 30 fps (750,000) but not at 60 or 240: refused before solving
    for flag in (["--fps", "240"], ["--quality", "4k"], ["--quality", "high"]):
        out.append(
            Attempt(
                k,
                f"run a path at speed 4e-5 {' '.join(flag)}",
                ["run", "s.yaml", "--out", "o", "--no-video", "-q", *flag],
                path("1e-3", "4e-5"),
                (2,),
                timeout=120,
                message="1,000,000",
            )
        )
    out.append(
        Attempt(
            k,
            "sweep --set render.fps=30,240 on a path at speed 4e-5",
            ["sweep", "s.yaml", "--set", "render.fps=240,120", "--out", "o", "-q", "--jobs", "1"],
            path("1e-3", "4e-5"),
            (2,),
            timeout=120,
        )
    )
    out.append(
        Attempt(
            k,
            "sweep --set solver.path_tolerance=1e-9,1e-3",
            ["sweep", "s.yaml", "--set", "solver.path_tolerance=1e-9,1e-3", "--out", "o", "-q", "--jobs", "1"],
            path("1e-3"),
            (2,),
            timeout=300,
            message="path_tolerance",
        )
    )
    out.append(
        Attempt(
            k,
            "sweep --set render.fps=240 on a fine path",
            ["sweep", "s.yaml", "--set", "render.fps=30,240", "--out", "o", "-q", "--jobs", "1"],
            path("1e-6"),
            (0, 2),
            timeout=400,
        )
    )
    out.append(
        Attempt(
            k,
            "sweep --set goals[0].speed=1e-9",
            ["sweep", "s.yaml", "--set", "goals[0].speed=1e-9", "--out", "o", "-q", "--jobs", "1"],
            path("1e-3"),
            (2,),
            timeout=200,
        )
    )
    out.append(
        Attempt(
            k,
            "check path_tolerance 1e-9",
            ["check", "s.yaml", "--golden", "g", "--update"],
            path("1e-9"),
            (2,),
            timeout=100,
        )
    )
    rates = "version: 1\nname: r\narm: {links: [1, 1, 1], max_joint_speed: SPEED}\ngoals: [[1, 1, 1]]\nrender: {size: [160, 90], fps: 30}\n"
    for speed, flag in [("4e-5", ["--fps", "240"]), ("4e-5", ["--quality", "high"]), ("1e-3", ["--fps", "240"])]:
        out.append(
            Attempt(
                k,
                f"run max_joint_speed {speed} {' '.join(flag)}",
                ["run", "s.yaml", "--out", "o", "--no-video", "-q", *flag],
                tiny_scene(text=rates.replace("SPEED", speed)),
                (2,),
                timeout=200,
                message=r"max_joint_speed",
            )
        )
    jerk = rates.replace("max_joint_speed: SPEED", "max_joint_jerk: 1e-11")
    out.append(
        Attempt(
            k,
            "run max_joint_jerk 1e-11 --fps 240",
            ["run", "s.yaml", "--out", "o", "--no-video", "-q", "--fps", "240"],
            tiny_scene(text=jerk),
            (2,),
            timeout=200,
            message="max_joint_jerk",
        )
    )
    out.append(
        Attempt(
            k,
            "sweep --set arm.max_joint_speed=1e-300",
            ["sweep", "s.yaml", "--set", "arm.max_joint_speed=1e-300,1", "--out", "o", "-q", "--jobs", "1"],
            tiny_scene(text=rates.replace("SPEED", "10")),
            (2,),
            timeout=200,
        )
    )
    holds = (
        "version: 1\nname: h\narm: {links: [1, 1, 1]}\ngoals:\n"
        + "".join(f"  - {{position: [1, {i % 3}, 1], hold: 3600}}\n" for i in range(5))
        + "render: {size: [160, 90], fps: 10}\n"
    )
    out.append(
        Attempt(
            k,
            "run 5 one-hour holds --quality high",
            ["run", "s.yaml", "--out", "o", "--no-video", "-q", "--quality", "high"],
            tiny_scene(text=holds),
            (2,),
            timeout=100,
            message="1,000,000|frames",
        )
    )
    out.append(
        Attempt(
            k,
            "sweep --set render.fps=240 on 5 one-hour holds",
            ["sweep", "s.yaml", "--set", "render.fps=1,240", "--out", "o", "-q", "--jobs", "1"],
            tiny_scene(text=holds),
            (2,),
            timeout=200,
            message="1,000,000|frames",
        )
    )

    def long_run(d: Path) -> None:  # 72,000 frames at 10 fps: 1,728,000 at 240 (one hour is 864,000, a long render)
        finished_run(
            d,
            TINY.replace(
                "[[1, 1, 1], [0.5, -1, 1]]", "[{position: [1, 1, 1], hold: 3600}, {position: [0.5, -1, 1], hold: 3600}]"
            ),
        )

    out.append(
        Attempt(
            k,
            "render --fps 240 of a run with an hour's hold",
            ["render", "o/tiny", "--fps", "240", "-q"],
            long_run,
            (2,),
            timeout=200,
            keep=("o/tiny",),
        )
    )
    return out


def export_attempts() -> list[Attempt]:
    """export --out and the other single-file writers onto what is not theirs to replace."""
    k = "export"
    out = []
    base = ["export", "o/tiny", "--out"]
    user_json = '{"joint_names": ["j0"], "points": [{"positions": [0], "time_from_start": {"secs": 0, "nsecs": 0}}]}'

    def with_run(extra: Callable[[Path], None]) -> Callable[[Path], None]:
        def setup(d: Path) -> None:
            finished_run(d)
            extra(d)

        return setup

    out.append(
        Attempt(
            k, "export --out the scene file itself", [*base, "s.yaml"], with_run(lambda d: None), (3,), keep=("s.yaml",)
        )
    )
    out.append(
        Attempt(
            k,
            "export --out an existing folder",
            [*base, "dir"],
            with_run(lambda d: (d / "dir").mkdir()),
            (2, 3),
            keep=("dir",),
        )
    )
    out.append(
        Attempt(
            k, "export --out dir/ (a trailing slash, no folder)", [*base, "newdir/"], with_run(lambda d: None), (2, 3)
        )
    )
    out.append(
        Attempt(
            k, "export --out under a missing folder", [*base, "no/such/x.json"], with_run(lambda d: None), (0, 2, 3)
        )
    )
    out.append(
        Attempt(
            k, "export --out under a file", [*base, "s.yaml/x.json"], with_run(lambda d: None), (2, 3), keep=("s.yaml",)
        )
    )
    out.append(Attempt(k, "export --out /dev/stdout", [*base, "/dev/stdout"], with_run(lambda d: None), (0, 2, 3)))
    out.append(
        Attempt(
            k,
            "export --out the run's lock beside it",
            [*base, "o/.tiny.lock"],
            with_run(lambda d: None),
            (2, 3),
            keep=("o/.tiny.lock",),
        )
    )
    long = "e" * 245 + ".json"
    out.append(
        Attempt(
            k,
            "export --out a 250-character name (its mark's name too long)",
            [*base, long],
            with_run(lambda d: None),
            (0, 3),
            after=lambda d: (
                []
                if (not (d / long).exists()) or any(p.name.startswith(".e") for p in d.iterdir())
                else [f"{long[:10]}... written without its mark"]
            ),
        )
    )
    long_schema = "s" * 245 + ".json"
    out.append(
        Attempt(
            k,
            "schema --out a 250-character name",
            ["schema", "--out", long_schema],
            lambda d: None,
            (0, 3),
            after=lambda d: (
                []
                if not (d / long_schema).exists()
                else ["the schema was written without its mark (the next schema --out refuses it)"]
            ),
        )
    )
    out.append(
        Attempt(
            k,
            "fk --png a 250-character name",
            ["fk", "--angles", "0,10,20,30", "--png", "f" * 246 + ".png"],
            lambda d: None,
            (0, 3),
            after=lambda d: [] if not (d / ("f" * 246 + ".png")).exists() else ["the png was written without its mark"],
        )
    )

    def batch(d: Path) -> None:
        finished_run(d)
        write(d / "a.yaml", TINY.replace("name: tiny", "name: a"))
        write(d / "b.yaml", TINY.replace("name: tiny", "name: b"))
        env = dict(os.environ, PYTHONPATH=str(SRC))
        subprocess.run(
            [
                sys.executable,
                "-m",
                "armanim",
                "run",
                "a.yaml",
                "b.yaml",
                "--out",
                "o",
                "--no-video",
                "-q",
                "--jobs",
                "1",
            ],
            cwd=d,
            env=env,
            check=True,
            capture_output=True,
        )

    out.append(
        Attempt(k, "export --out a batch's index.csv", [*base, "o/index.csv"], batch, (2, 3), keep=("o/index.csv",))
    )

    def schema_file(d: Path) -> None:
        finished_run(d)
        env = dict(os.environ, PYTHONPATH=str(SRC))
        subprocess.run([sys.executable, "-m", "armanim", "schema", "--out", "schema.json"], cwd=d, env=env, check=True)

    out.append(
        Attempt(
            k, "export --out a schema armanim wrote", [*base, "schema.json"], schema_file, (3,), keep=("schema.json",)
        )
    )

    def marked(d: Path) -> None:
        finished_run(d)
        export_of(d, "x.json")

    out.append(
        Attempt(
            k,
            "export --out another export's mark",
            [*base, ".x.json.armanim.json"],
            marked,
            (2, 3),
            keep=(".x.json.armanim.json", "x.json"),
        )
    )
    out.append(
        Attempt(
            k,
            "export --out a hard link to its own export",
            [*base, "h.json"],
            lambda d: (marked(d), os.link(d / "x.json", d / "h.json")),
            (0, 3),
            keep=("x.json",),
        )
    )

    def user_hardlink(d: Path) -> None:
        marked(d)
        write(d / "mine.json", user_json)
        os.unlink(d / "x.json")
        os.link(d / "mine.json", d / "x.json")

    out.append(
        Attempt(
            k,
            "export --out x.json, now a hard link to a user's file",
            [*base, "x.json"],
            user_hardlink,
            (3,),
            keep=("mine.json",),
        )
    )

    def copied_mark(d: Path) -> None:
        marked(d)
        write(d / "mine.json", user_json)
        shutil.copy(d / ".x.json.armanim.json", d / ".mine.json.armanim.json")

    out.append(
        Attempt(
            k,
            "export --out a user file with another export's mark copied",
            [*base, "mine.json"],
            copied_mark,
            (3,),
            keep=("mine.json",),
        )
    )

    def link_dir(d: Path) -> None:
        finished_run(d)
        os.symlink("o/tiny", d / "lnk")

    out.append(
        Attempt(
            k, "export --out through a link to the run folder", [*base, "lnk/x.json"], link_dir, (2,), keep=("o/tiny",)
        )
    )
    out.append(
        Attempt(
            k,
            "view --out through a link to the run folder",
            ["view", "o/tiny", "--out", "lnk/x.html"],
            link_dir,
            (2,),
            keep=("o/tiny",),
        )
    )

    def dangling_into_run(d: Path) -> None:
        finished_run(d)
        os.symlink("o/tiny/new.json", d / "dl.json")

    out.append(
        Attempt(
            k,
            "export --out a dangling link into the run folder",
            [*base, "dl.json"],
            dangling_into_run,
            (2, 3),
            keep=("o/tiny", "dl.json"),
        )
    )
    out.append(
        Attempt(
            k,
            "schema --out a dangling link into a run folder",
            ["schema", "--out", "dl.json"],
            dangling_into_run,
            (2, 3),
            keep=("o/tiny", "dl.json"),
        )
    )
    out.append(
        Attempt(
            k,
            "fk --png a dangling link into a run folder",
            ["fk", "--angles", "0,0,0,0", "--png", "dl.png"],
            lambda d: (finished_run(d), os.symlink("o/tiny/new.png", d / "dl.png")),
            (2, 3),
            keep=("o/tiny", "dl.png"),
        )
    )

    def moveit_in(d: Path) -> None:
        finished_run(d)
        write(d / "w.scene", "w\n* box\n1\nbox\n0.1 0.1 0.1\n1 1 1\n0 0 0 1\n0 0 0 0\n.\n")

    out.append(
        Attempt(
            k,
            "import moveit --out into a run folder",
            ["import", "moveit", "w.scene", "--robot", "panda", "--out", "o/tiny/x.yaml"],
            moveit_in,
            (2,),
            keep=("o/tiny",),
        )
    )
    out.append(
        Attempt(
            k,
            "import moveit --out its own input",
            ["import", "moveit", "w.scene", "--robot", "panda", "--out", "w.scene"],
            moveit_in,
            (3,),
            keep=("w.scene",),
        )
    )
    return out


def nested_attempts() -> list[Attempt]:
    """Deeply nested JSON (and YAML, XML) at every file armanim reads back."""
    k = "nested"
    out = []
    deep = "[" * 49_000 + "]" * 49_000  # under every 100,000-byte bound

    def fitted_then(d: Path) -> None:
        write(d / "a.stl", stl(40))
        urdf_robot(collision=col("a.stl"))(d)
        (d / "cache").mkdir()
        env = dict(os.environ, PYTHONPATH=str(SRC), ARMANIM_CACHE_DIR=str(d / "cache"))
        subprocess.run(
            [sys.executable, "-m", "armanim", "validate", "s.yaml"], cwd=d, env=env, check=True, capture_output=True
        )
        fits = list((d / "cache").rglob("*.json"))
        if not fits:
            raise RuntimeError("no cached fit")
        for fit in fits:
            fit.write_text(deep)

    out.append(
        Attempt(
            k,
            "a cached capsule fit 49,000 deep (validate)",
            ["validate", "s.yaml"],
            fitted_then,
            (0,),
            env={"ARMANIM_CACHE_DIR": "{d}/cache"},
        )
    )
    out.append(
        Attempt(
            k,
            "a cached capsule fit 49,000 deep (robots --fit)",
            ["robots", "--fit", "robot.urdf"],
            fitted_then,
            (0,),
            env={"ARMANIM_CACHE_DIR": "{d}/cache"},
        )
    )

    def run_then(change: Callable[[Path], None]) -> Callable[[Path], None]:
        def setup(d: Path) -> None:
            change(finished_run(d))

        return setup

    out.append(
        Attempt(
            k,
            "a run's marker 200,000 deep, then run",
            ["run", "s.yaml", "--out", "o", "--no-video", "-q"],
            run_then(lambda r: write(r / ".armanim-run.json", "[" * 200_000 + "]" * 200_000)),
            (3,),
            keep=("o/tiny",),
        )
    )
    out.append(
        Attempt(
            k,
            "a run's marker 200,000 deep, then render",
            ["render", "o/tiny", "-q", "--size", "64x48"],
            run_then(lambda r: write(r / ".armanim-run.json", "[" * 200_000 + "]" * 200_000)),
            (2, 3),
            keep=("o/tiny",),
        )
    )
    out.append(
        Attempt(
            k,
            "a run's marker 200,000 deep, then view",
            ["view", "o/tiny"],
            run_then(lambda r: write(r / ".armanim-run.json", "{" * 200_000)),
            (2, 3),
            keep=("o/tiny",),
        )
    )
    out.append(
        Attempt(
            k,
            "a run's marker 200,000 deep, then export",
            ["export", "o/tiny"],
            run_then(lambda r: write(r / ".armanim-run.json", "[" * 200_000 + "]" * 200_000)),
            (2, 3),
            keep=("o/tiny",),
        )
    )
    out.append(
        Attempt(
            k,
            "look-folders.json 49,000 deep, then view",
            ["view", "o/tiny", "--out", "v.html"],
            run_then(lambda r: write(r / "look-folders.json", deep)),
            (0, 2, 3),
        )
    )
    out.append(
        Attempt(
            k,
            "summary.json with a 5,000-digit integer, then render",
            ["render", "o/tiny", "-q", "--size", "64x48"],
            run_then(
                lambda r: write(
                    r / "summary.json",
                    r.joinpath("summary.json")
                    .read_text()
                    .replace('"frames": ', '"frames": ' + "9" * 5000 + ', "x": ', 1),
                )
            ),
            (2,),
            keep=("o/tiny",),
        )
    )
    out.append(
        Attempt(
            k,
            "summary.json with a 5,000-digit integer, then export",
            ["export", "o/tiny", "--out", "e.json"],
            run_then(
                lambda r: write(
                    r / "summary.json",
                    r.joinpath("summary.json")
                    .read_text()
                    .replace('"frames": ', '"frames": ' + "9" * 5000 + ', "x": ', 1),
                )
            ),
            (0, 2),
        )
    )
    out.append(
        Attempt(
            k,
            "capsules.yaml 10,000 deep, then render",
            ["render", "o/tiny", "-q", "--size", "64x48"],
            run_then(lambda r: write(r / "capsules.yaml", "[" * 10_000 + "]" * 10_000)),
            (0, 2, 3),
            keep=("o/tiny",),
        )
    )
    out.append(
        Attempt(
            k,
            "a golden .json 49,000 deep, then check",
            ["check", "s.yaml", "--golden", "g"],
            lambda d: (write(d / "s.yaml", TINY), write(d / "g/tiny.json", deep), write(d / "g/tiny.csv", "x\n")),
            (1, 2),
        )
    )
    out.append(
        Attempt(
            k,
            "an export's mark 49,000 deep, then export over its file",
            ["export", "o/tiny", "--out", "x.json"],
            lambda d: (finished_run(d), export_of(d, "x.json"), write(d / ".x.json.armanim.json", deep)),
            (3,),
            keep=("x.json", ".x.json.armanim.json"),
        )
    )
    out.append(
        Attempt(
            k,
            "an index.csv's mark 49,000 deep, then a batch",
            ["run", "a.yaml", "b.yaml", "--out", "o", "--no-video", "-q", "--jobs", "1"],
            lambda d: (
                write(d / "a.yaml", TINY.replace("tiny", "a")),
                write(d / "b.yaml", TINY.replace("tiny", "b")),
                write(d / "o/index.csv", "x\n"),
                write(d / "o/.index.csv.armanim.json", deep),
            ),
            (3,),
            keep=("o/index.csv",),
        )
    )
    # YAML and XML that armanim reads itself
    out.append(
        Attempt(
            k,
            "import moveit, a request 10,000 deep",
            ["import", "moveit", "w.scene", "--robot", "panda", "--request", "r.yaml", "--out", "x.yaml"],
            lambda d: (write(d / "w.scene", "w\n.\n"), write(d / "r.yaml", "[" * 10_000 + "]" * 10_000)),
            (2,),
        )
    )
    out.append(
        Attempt(
            k,
            "import moveit, a request of 10,000 nested block mappings",
            ["import", "moveit", "w.scene", "--robot", "panda", "--request", "r.yaml", "--out", "x.yaml"],
            lambda d: (
                write(d / "w.scene", "w\n.\n"),
                write(d / "r.yaml", "".join(" " * i + f"k{i}:\n" for i in range(3000)) + " " * 3000 + "v\n"),
            ),
            (2,),
        )
    )
    out.append(
        Attempt(
            k,
            "import moveit, an SRDF 100,000 deep",
            ["import", "moveit", "w.scene", "--urdf", "robot.urdf", "--srdf", "r.srdf", "--out", "x.yaml"],
            lambda d: (
                urdf_robot()(d),
                write(d / "w.scene", "w\n.\n"),
                write(d / "r.srdf", "<robot name='r'>" + "<a>" * 100_000 + "</a>" * 100_000 + "</robot>"),
            ),
            (2,),
        )
    )
    out.append(
        Attempt(
            k,
            "robots --fit, a URDF 100,000 deep",
            ["robots", "--fit", "r.urdf"],
            lambda d: (
                write(d / "r.urdf", "<robot name='r'>" + "<a>" * 100_000 + "</a>" * 100_000 + "</robot>") and None
            ),
            (2,),
        )
    )
    out.append(
        Attempt(
            k,
            "sweep --set a value 10,000 deep",
            ["sweep", "s.yaml", "--set", "arm.links=" + "[" * 10_000 + "]" * 10_000, "--out", "o", "-q"],
            tiny_scene(),
            (2,),
        )
    )
    out.append(
        Attempt(
            k,
            "sweep --set a key 5,000 parts deep",
            ["sweep", "s.yaml", "--set", "arm." + ".".join(["a"] * 5000) + "=1", "--out", "o", "-q"],
            tiny_scene(),
            (2,),
        )
    )
    return out


def sizes_attempts() -> list[Attempt]:
    """Tiny, huge and NaN sizes on every command's numeric flags."""
    k = "sizes"
    out = []

    def run_setup(d: Path) -> None:
        finished_run(d)

    for flag in (
        ["--size", "1x1"],
        ["--size", "0x0"],
        ["--size", "99999999999999999999x16"],
        ["--size", "nanxnan"],
        ["--size", "16x7681"],
        ["--elevation", "nan"],
        ["--azimuth", "inf"],
        ["--elevation", "1e308"],
        ["--fps", "nan"],
        ["--fps", "inf"],
        ["--fps", "1e-300"],
        ["--fps", "-1"],
        ["--jobs", "0"],
        ["--jobs", "-5"],
        ["--jobs", "100000000"],
    ):
        out.append(
            Attempt(
                k,
                f"render {' '.join(flag)}",
                ["render", "o/tiny", "-q", "--size", "64x48", *flag]
                if flag[0] != "--size"
                else ["render", "o/tiny", "-q", *flag],
                run_setup,
                (0, 2),
                timeout=150,
                keep=() if flag[0] in ("--elevation", "--azimuth", "--jobs") else ("o/tiny",),
            )
        )
    for flag in (
        ["--fps", "nan"],
        ["--fps", "inf"],
        ["--fps", "1e-300"],
        ["--size", "16x16"],
        ["--jobs", "0"],
        ["--quality", "8k"],
    ):
        out.append(
            Attempt(
                k,
                f"run {' '.join(flag)}",
                ["run", "s.yaml", "--out", "o", "-q", *flag],
                tiny_scene(),
                (0, 2),
                timeout=200,
            )
        )
    for flag in (["--atol", "nan"], ["--atol", "inf"], ["--atol-deg", "nan"], ["--atol", "1e400"]):
        out.append(
            Attempt(
                k,
                f"compare {' '.join(flag)}",
                ["compare", "o/tiny/trajectory.csv", "o/tiny/trajectory.csv", *flag],
                run_setup,
                (0, 2),
            )
        )
    pose = ["--links", "1,1,1,1"]
    for flags in (
        ["--tolerance", "nan"],
        ["--tolerance", "-1"],
        ["--tolerance", "inf"],
        ["--tolerance", "1e-320"],
        ["--goal", "nan,0,0"],
        ["--goal", "1e308,0,0"],
        ["--from", "nan,0,0,0"],
        ["--from", "1e308,0,0,0"],
        ["--orientation", "rpy=nan,0,0"],
        ["--orientation-tolerance", "nan"],
        ["--orientation-tolerance", "-1"],
        ["--links", "1e308,1e308,1e308,1e308"],
        ["--links", "1e-320,1,1,1"],
        ["--base", "inf,0,0"],
        ["--method", "newton", "--tolerance", "0"],
    ):
        args = ["ik", *pose, "--goal", "2,1,1", *flags] if "--goal" not in flags else ["ik", *pose, *flags]
        if "--links" in flags:
            args = ["ik", "--goal", "2,1,1", *flags]
        out.append(Attempt(k, f"ik {' '.join(flags)}", args, lambda d: None, (0, 2), timeout=60))
    out.append(
        Attempt(
            k,
            "ik --max-iterations 2,000,000,000 --tolerance 1e-300 out of reach",
            ["ik", *pose, "--goal", "9,9,9", "--tolerance", "1e-300", "--max-iterations", "2000000000"],
            lambda d: None,
            (0, 2),
            timeout=120,
        )
    )
    out.append(
        Attempt(
            k,
            "ik --robot panda --max-iterations 2,000,000,000 --tolerance 1e-300",
            [
                "ik",
                "--robot",
                "panda",
                "--goal",
                "3,0,0",
                "--tolerance",
                "1e-300",
                "--max-iterations",
                "2000000000",
                "--method",
                "dls",
            ],
            lambda d: None,
            (0, 2),
            timeout=120,
        )
    )
    for flags in (
        ["--angles", "nan,0,0,0"],
        ["--angles", "1e308,0,0,0"],
        ["--links", "1e308,1e308,1e308,1e308", "--angles", "0,90,0,0"],
        ["--links", "5e-324,5e-324,1,1", "--angles", "0,0,0,0", "--png", "p.png"],
        ["--base", "1e308,1e308,1e308", "--angles", "0,0,0,0", "--png", "p.png"],
        ["--radians", "--angles", "1e300,0,0,0"],
        ["--angles", "0,0,0,0", "--links", "1,1,1,1", "--png", "p.png", "--base", "0,0,-1e9"],
    ):
        out.append(Attempt(k, f"fk {' '.join(flags)}", ["fk", *flags], lambda d: None, (0, 2), timeout=60))
    return out


def signal_attempts() -> list[Attempt]:
    """Ctrl-C (to the group) and SIGTERM (to armanim) in commands the signal campaign does not run."""
    k = "signals"
    out = []

    def big_fit(d: Path) -> None:
        sys.path.insert(0, str(ROOT / "benchmarks"))
        from reliability_bench import FIT_URDF, _random_stl

        _random_stl(d / "big.stl", 600_000)
        write(d / "robot.urdf", FIT_URDF)
        (d / "cache").mkdir()

    for delay in (0.5, 2.0, 5.0):
        for signame in ("SIGINT", "SIGTERM"):
            out.append(
                Attempt(
                    k,
                    f"robots --fit of a 30 MB random STL, {signame} at {delay:g} s",
                    ["robots", "--fit", "robot.urdf"],
                    big_fit,
                    (130,),
                    timeout=60,
                    interrupt=(delay, signame),
                    env={"ARMANIM_CACHE_DIR": "{d}/cache"},
                    after=lambda d: [
                        f"cache holds {p.name}" for p in (d / "cache").rglob("*") if LITTER.search(p.name)
                    ],
                )
            )
    # (ik stops where its steps stall: even 2,000,000,000 iterations at a tolerance of 1e-300 end in
    # seconds, so nothing long to interrupt there.) pycollada parsing 300,000 nodes: some 50 s
    for delay in (3.0, 10.0):
        for signame in ("SIGINT", "SIGTERM"):
            out.append(
                Attempt(
                    k,
                    f"fk --png, a visual of 300,000 COLLADA nodes, {signame} at {delay:g} s",
                    ["fk", "--scene", "s.yaml", "--angles", "0,10,20", "--png", "p.png"],
                    urdf_robot(vis("n.dae"), files={"n.dae": dae(1, 300_000)}),
                    (0, 130),  # since campaign 9 a note before it is parsed: the command may end first
                    timeout=60,
                    interrupt=(delay, signame),
                    after=lambda d: (
                        []
                        if os.path.exists(d / "p.png") == os.path.exists(d / ".p.png.armanim.json")
                        else ["a png without its mark, or a mark alone"]
                    ),
                )
            )
    for delay in (1.0, 3.0):
        for signame in ("SIGINT", "SIGTERM"):
            out.append(
                Attempt(
                    k,
                    f"warm, {signame} at {delay:g} s",
                    ["warm", "-q"],
                    lambda d: None,
                    (0, 130),
                    timeout=120,
                    interrupt=(delay, signame),
                )
            )

    def moveit(d: Path) -> None:
        write(
            d / "w.scene",
            "w\n"
            + "".join(f"* b{i}\n1\nbox\n0.1 0.1 0.1\n{i % 9} 1 1\n0 0 0 1\n0 0 0 0\n" for i in range(900))
            + ".\n",
        )

    for delay in (0.8, 1.6):
        for signame in ("SIGINT", "SIGTERM"):
            out.append(
                Attempt(
                    k,
                    f"import moveit of 900 boxes, {signame} at {delay:g} s",
                    ["import", "moveit", "w.scene", "--robot", "panda", "--out", "x.yaml"],
                    moveit,
                    (0, 130),
                    timeout=60,
                    interrupt=(delay, signame),
                    after=lambda d: [
                        f"litter {p.name}"
                        for p in d.iterdir()
                        if LITTER.search(p.name) or p.name.startswith(".x.yaml.")
                    ],
                )
            )

    def two_csvs(d: Path) -> None:
        header = "frame,time_s,phi1_deg\n"
        rows = "".join(f"{i},{i / 30:.6f},{i % 360}\n" for i in range(2_000_000))
        write(d / "a.csv", header + rows)
        write(d / "b.csv", header + rows)

    for signame in ("SIGINT", "SIGTERM"):
        out.append(
            Attempt(
                k,
                f"compare of two 2,000,000-row CSVs, {signame} at 1 s",
                ["compare", "a.csv", "b.csv"],
                two_csvs,
                (130,),
                timeout=60,
                interrupt=(1.0, signame),
            )
        )

    def golden(d: Path) -> None:
        write(d / "s.yaml", TINY)
        write(d / "t.yaml", TINY.replace("tiny", "tiny2"))

    for delay in (1.0, 2.5):
        for signame in ("SIGINT", "SIGTERM"):
            out.append(
                Attempt(
                    k,
                    f"check --update of two scenes, {signame} at {delay:g} s",
                    ["check", "s.yaml", "t.yaml", "--golden", "g", "--update"],
                    golden,
                    (0, 130),
                    timeout=120,
                    interrupt=(delay, signame),
                    litter_in=("g",),
                    after=lambda d: (
                        [f"half a pair: {sorted(p.name for p in (d / 'g').iterdir())}"]
                        if (d / "g").is_dir()
                        and len([p for p in (d / "g").iterdir() if not p.name.startswith(".")]) % 2
                        else []
                    ),
                )
            )
    return out


def folders_attempts() -> list[Attempt]:
    """Outputs folders holding the user's own things beside or inside a run folder."""
    k = "folders"
    out = []
    run = ["run", "s.yaml", "--out", "o", "--no-video", "-q"]

    def user_at(
        name: str, make: Callable[[Path], None] = lambda p: (p.mkdir(parents=True), write(p / "thesis.txt", "mine"))
    ) -> Callable[[Path], None]:
        def setup(d: Path) -> None:
            finished_run(d)
            if os.path.lexists(d / "o" / name) and not (d / "o" / name).is_dir():
                os.unlink(d / "o" / name)  # the run's own lock file: the user's thing replaces it
            make(d / "o" / name)

        return setup

    for name in (".tiny.old-1", ".tiny.old-99999999", ".tiny.backup01.partial", ".tiny.abcdefgh.partial"):
        out.append(
            Attempt(
                k,
                f"a user's folder {name} beside the run folder, then run",
                run,
                user_at(name),
                (0, 3),
                keep=(f"o/{name}",),
                litter_in=(),
            )
        )
    out.append(
        Attempt(
            k,
            "a user's folder .tiny.old-1 and no run folder, then run",
            run,
            lambda d: (
                write(d / "s.yaml", TINY),
                (d / "o/.tiny.old-1").mkdir(parents=True),
                write(d / "o/.tiny.old-1/thesis.txt", "mine"),
            ),
            (0, 3),
            keep=("o/.tiny.old-1",),
            litter_in=(),
        )
    )
    out.append(
        Attempt(
            k,
            "a user's folder .tiny.old-1, then render",
            ["render", "o/tiny", "-q", "--size", "64x48"],
            user_at(".tiny.old-1"),
            (0, 3),
            keep=("o/.tiny.old-1",),
            litter_in=(),
        )
    )
    out.append(
        Attempt(
            k,
            "a user's folder .tiny.old-1, then view",
            ["view", "o/tiny"],
            user_at(".tiny.old-1"),
            (0, 3),
            keep=("o/.tiny.old-1",),
            litter_in=(),
        )
    )
    out.append(
        Attempt(
            k,
            "a FIFO at the lock's name, then run",
            run,
            user_at(".tiny.lock", fifo),
            (0, 3),
            timeout=60,
            keep=("o/.tiny.lock",),
        )
    )
    out.append(
        Attempt(
            k,
            "a FIFO at the lock's name, then render",
            ["render", "o/tiny", "-q", "--size", "64x48"],
            user_at(".tiny.lock", fifo),
            (0, 3),
            timeout=60,
            keep=("o/.tiny.lock",),
        )
    )
    out.append(
        Attempt(
            k,
            "a user's file at the lock's name, then run",
            run,
            user_at(".tiny.lock", lambda p: write(p, "my notes\n")),
            (0, 3),
            keep=("o/.tiny.lock",),
        )
    )
    out.append(
        Attempt(
            k, "a user's subfolder inside the run folder, then run", run, user_at("tiny/extra"), (3,), keep=("o/tiny",)
        )
    )
    out.append(
        Attempt(
            k,
            "a user's FIFO inside the run folder, then run",
            run,
            user_at("tiny/pipe", fifo),
            (3,),
            keep=("o/tiny",),
            timeout=60,
        )
    )

    def marker_lists(names: list[str]) -> Callable[[Path], None]:
        def setup(d: Path) -> None:
            import json

            r = finished_run(d)
            marker = json.loads((r / ".armanim-run.json").read_text())
            key = "files"
            for extra in names:
                target = r / extra
                if not target.exists():
                    write(d / "o" / "outside.txt", "mine")
                st = os.stat(r / extra) if (r / extra).exists() else os.stat(d / "o" / "outside.txt")
                entry = {"name": extra, "bytes": st.st_size, "mtime_ns": st.st_mtime_ns}
                if isinstance(marker.get(key), list) and marker[key] and isinstance(marker[key][0], dict):
                    template = dict(marker[key][0])
                    template.update({kk: entry[kk2] for kk, kk2 in (("name", "name"),) if kk in template})
                    for size_key in ("bytes", "size"):
                        if size_key in template:
                            template[size_key] = st.st_size
                    for t_key in ("mtime_ns", "mtime"):
                        if t_key in template:
                            template[t_key] = st.st_mtime_ns if t_key == "mtime_ns" else st.st_mtime
                    marker[key].append(template)
                elif isinstance(marker.get(key), dict):
                    marker[key][extra] = next(iter(marker[key].values()))
            (r / ".armanim-run.json").write_text(json.dumps(marker))

        return setup

    out.append(
        Attempt(
            k,
            "a marker listing ../outside.txt, then run",
            run,
            marker_lists(["../outside.txt"]),
            (0, 3),
            keep=("o/outside.txt",),
        )
    )
    out.append(Attempt(k, "a marker listing itself, then run", run, marker_lists([".armanim-run.json"]), (0, 3)))
    out.append(Attempt(k, "a marker listing '.', then run", run, marker_lists(["."]), (0, 3)))

    def sweep_user(d: Path) -> None:
        write(d / "s.yaml", TINY)
        env = dict(os.environ, PYTHONPATH=str(SRC))
        subprocess.run(
            [
                sys.executable,
                "-m",
                "armanim",
                "sweep",
                "s.yaml",
                "--set",
                "solver.step=0.1,0.2",
                "--out",
                "o",
                "-q",
                "--jobs",
                "1",
            ],
            cwd=d,
            env=env,
            check=True,
            capture_output=True,
        )
        folders = [p for p in (d / "o").iterdir() if p.is_dir() and not p.name.startswith(".")]
        shutil.rmtree(folders[0])
        folders[0].mkdir()
        write(folders[0] / "thesis.txt", "mine")
        write(d / "which", folders[0].name)

    out.append(
        Attempt(
            k,
            "sweep where one variant's folder is now the user's",
            ["sweep", "s.yaml", "--set", "solver.step=0.1,0.2", "--out", "o", "-q", "--jobs", "1"],
            sweep_user,
            (3,),
            after=lambda d: (
                [] if (d / "o" / (d / "which").read_text() / "thesis.txt").exists() else ["the user's folder is gone"]
            ),
        )
    )
    out.append(
        Attempt(
            k,
            "check --update --golden a folder holding a user's tiny.json",
            ["check", "s.yaml", "--golden", "g", "--update"],
            lambda d: (write(d / "s.yaml", TINY), write(d / "g/tiny.json", '{"mine": true}')),
            (0, 3),
            after=lambda d: [],
        )
    )
    # documented: a golden file is replaced on --update, a link written through (docs/reliability.md 5)
    out.append(
        Attempt(
            k,
            "check --update --golden where tiny.csv is a link to a user's file",
            ["check", "s.yaml", "--golden", "g", "--update"],
            lambda d: (
                write(d / "s.yaml", TINY),
                write(d / "mine.csv", "mine\n"),
                (d / "g").mkdir(),
                os.symlink("../mine.csv", d / "g/tiny.csv"),
            ),
            (0, 3),
            keep=("g/tiny.csv",),
        )
    )
    out.append(
        Attempt(
            k,
            "render --out a folder holding a marker copied from a run and a user's file",
            ["render", "o/tiny", "-q", "--size", "64x48", "--out", "fig"],
            lambda d: (
                finished_run(d),
                (d / "fig").mkdir(),
                shutil.copy(d / "o/tiny/.armanim-run.json", d / "fig/.armanim-run.json"),
                write(d / "fig/plot.png", "my plot"),
            ),
            (3,),
            keep=("fig/plot.png",),
        )
    )
    return out


def inputs_attempts() -> list[Attempt]:
    """Every command's bad input, where the campaigns before did not try it."""
    k = "inputs"
    out = []
    w = "w\n* box\n1\nbox\n0.1 0.1 0.1\n1 1 1\n0 0 0 1\n0 0 0 0\n.\n"
    for label, make in [
        ("a FIFO", lambda p: fifo(p)),
        ("/dev/zero by a link", lambda p: os.symlink("/dev/zero", p)),
        ("a 2 GB sparse file", lambda p: sparse(p, 2 << 30)),
        (
            "latin-1 bytes",
            lambda p: write(p, "w\n* bo\xeete\n1\nbox\n0.1 0.1 0.1\n1 1 1\n0 0 0 1\n0 0 0 0\n.\n".encode("latin-1")),
        ),
        ("an empty file", lambda p: write(p, "")),
        ("NUL bytes", lambda p: write(p, b"w\n\0\0\0\n")),
        ("a box of size nan", lambda p: write(p, w.replace("0.1 0.1 0.1", "nan 0.1 0.1"))),
        ("a box of size 1e400", lambda p: write(p, w.replace("0.1 0.1 0.1", "1e400 0.1 0.1"))),
        ("a count of 10**9 shapes", lambda p: write(p, w.replace("\n1\nbox", "\n1000000000\nbox"))),
        ("a quaternion of zeros", lambda p: write(p, w.replace("0 0 0 1", "0 0 0 0"))),
    ]:
        out.append(
            Attempt(
                k,
                f"import moveit, a scene {label}",
                ["import", "moveit", "w.scene", "--robot", "panda", "--out", "x.yaml"],
                lambda d, make=make: make(d / "w.scene"),
                (0, 2),
                timeout=60,
            )
        )
    for label, text in [
        (
            "the goal 1e400",
            "goal_constraints:\n- position_constraints:\n  - link_name: panda_hand\n    constraint_region:\n      primitive_poses:\n      - position: {x: 1e400, y: 0, z: 0}\n",
        ),
        ("a FIFO", None),
        ("joint values NaN", "start_state:\n  joint_state:\n    name: [panda_joint1]\n    position: [.nan]\n"),
    ]:
        out.append(
            Attempt(
                k,
                f"import moveit, a request {label}",
                ["import", "moveit", "w.scene", "--robot", "panda", "--request", "r.yaml", "--out", "x.yaml"],
                lambda d, text=text: (
                    write(d / "w.scene", w),
                    fifo(d / "r.yaml") if text is None else write(d / "r.yaml", text),
                ),
                (0, 2),
                timeout=60,
            )
        )
    out.append(
        Attempt(
            k,
            "import moveit --robot nosuch",
            ["import", "moveit", "w.scene", "--robot", "nosuch", "--out", "x.yaml"],
            lambda d: write(d / "w.scene", w) and None,
            (2,),
        )
    )
    out.append(
        Attempt(
            k,
            "import moveit --urdf a FIFO",
            ["import", "moveit", "w.scene", "--urdf", "u.urdf", "--out", "x.yaml"],
            lambda d: (write(d / "w.scene", w), fifo(d / "u.urdf")),
            (2,),
            timeout=60,
        )
    )
    out.append(
        Attempt(
            k,
            "import moveit --srdf /dev/zero",
            ["import", "moveit", "w.scene", "--robot", "panda", "--srdf", "/dev/zero", "--out", "x.yaml"],
            lambda d: write(d / "w.scene", w) and None,
            (2,),
            timeout=60,
        )
    )
    for label, make in [
        ("a FIFO", fifo),
        ("/dev/zero by a link", lambda p: os.symlink("/dev/zero", p)),
        ("a folder", lambda p: p.mkdir()),
        ("empty", lambda p: write(p, "")),
        ("a 5 MB sparse file", lambda p: sparse(p, 5 << 20)),
        ("not XML", lambda p: write(p, "robot")),
        ("UTF-16", lambda p: write(p, urdf_text().encode("utf-16"))),
    ]:
        out.append(
            Attempt(
                k,
                f"robots --fit {label}",
                ["robots", "--fit", "u.urdf"],
                lambda d, make=make: make(d / "u.urdf"),
                (0,) if label == "UTF-16" else (2,),  # XML with its byte-order mark: a URDF like another
                timeout=60,
            )
        )
    header = "frame,time_s,phi1_deg\n"
    for label, a, b in [
        ("header only", header, header),
        ("a BOM and CRLF", "\ufeff" + header.replace("\n", "\r\n") + "0,0,1\r\n", header + "0,0,1\n"),
        ("other columns", header + "0,0,1\n", "frame,time_s,phi2_deg\n0,0,1\n"),
        ("NaN in both", header + "0,0,nan\n", header + "0,0,nan\n"),
        ("inf against 1e308", header + "0,0,inf\n", header + "0,0,1e308\n"),
        ("a 1,000-digit number", header + "0,0," + "9" * 1000 + "\n", header + "0,0,1\n"),
        ("a ragged row", header + "0,0,1,5\n", header + "0,0,1\n"),
        ("an empty file", "", ""),
        ("60,000 columns", ",".join(f"c{i}" for i in range(60_000)) + "\n", header),
        (
            "a duplicate column",
            "frame,time_s,phi1_deg,phi1_deg\n0,0,1,2\n",
            "frame,time_s,phi1_deg,phi1_deg\n0,0,1,3\n",
        ),
    ]:
        out.append(
            Attempt(
                k,
                f"compare, {label}",
                ["compare", "a.csv", "b.csv"],
                lambda d, a=a, b=b: (write(d / "a.csv", a), write(d / "b.csv", b)),
                (0, 1, 2),
                timeout=60,
            )
        )
    out.append(
        Attempt(
            k,
            "compare a folder and a FIFO",
            ["compare", "dir", "f.csv"],
            lambda d: ((d / "dir").mkdir(), fifo(d / "f.csv")),
            (2,),
            timeout=30,
        )
    )
    out.append(
        Attempt(
            k,
            "check --golden a file",
            ["check", "s.yaml", "--golden", "g"],
            lambda d: (write(d / "s.yaml", TINY), write(d / "g", "x")),
            (2, 3),
            keep=("g",),
        )
    )
    out.append(
        Attempt(k, "check --golden /dev/null", ["check", "s.yaml", "--golden", "/dev/null"], tiny_scene(), (2, 3))
    )
    out.append(
        Attempt(
            k,
            "check --update --golden /dev/null",
            ["check", "s.yaml", "--golden", "/dev/null", "--update"],
            tiny_scene(),
            (2, 3),
        )
    )
    out.append(
        Attempt(
            k,
            "check --golden a FIFO",
            ["check", "s.yaml", "--golden", "g"],
            lambda d: (write(d / "s.yaml", TINY), fifo(d / "g")),
            (2, 3),
            timeout=60,
        )
    )
    out.append(
        Attempt(
            k,
            "check, golden tiny.csv a FIFO",
            ["check", "s.yaml", "--golden", "g"],
            lambda d: (write(d / "s.yaml", TINY), fifo(d / "g/tiny.csv")),
            (1, 2),
            timeout=60,
        )
    )
    out.append(Attempt(k, "schema --out /dev/full", ["schema", "--out", "/dev/full"], lambda d: None, (3,)))
    out.append(
        Attempt(
            k,
            "schema --out a path under a file",
            ["schema", "--out", "f/x.json"],
            lambda d: write(d / "f", "x") and None,
            (2, 3),
            keep=("f",),
        )
    )
    out.append(
        Attempt(
            k, "fk --scene a folder", ["fk", "--scene", "dir", "--angles", "0"], lambda d: (d / "dir").mkdir(), (2,)
        )
    )
    out.append(
        Attempt(
            k,
            "ik --scene a FIFO",
            ["ik", "--scene", "f.yaml", "--goal", "1,1,1"],
            lambda d: fifo(d / "f.yaml"),
            (2,),
            timeout=30,
        )
    )
    out.append(
        Attempt(
            k,
            "export --format bogus",
            ["export", "o/tiny", "--format", "bogus"],
            lambda d: finished_run(d) and None,
            (2,),
        )
    )
    out.append(Attempt(k, "view of a folder without a run", ["view", "dir"], lambda d: (d / "dir").mkdir(), (2,)))
    out.append(Attempt(k, "render of /", ["render", "/", "-q"], lambda d: None, (2,)))
    out.append(
        Attempt(
            k,
            "view of a run whose trajectory.csv is a 2 GB sparse file",
            ["view", "o/tiny", "--out", "v.html"],
            lambda d: (
                finished_run(d),
                os.unlink(d / "o/tiny/trajectory.csv"),
                sparse(d / "o/tiny/trajectory.csv", 2 << 30),
            ),
            (2,),
            timeout=60,
        )
    )
    out.append(
        Attempt(
            k,
            "export of a run whose trajectory.csv has a NaN",
            ["export", "o/tiny", "--out", "e.json"],
            lambda d: (
                finished_run(d),
                write(
                    d / "o/tiny/trajectory.csv", (d / "o/tiny/trajectory.csv").read_text().replace("\n1,", "\n1,nan", 1)
                ),
            ),
            (2,),
            after=exists("e.json", present=False),
        )
    )
    for setting in (
        "name=../../x",
        "arm.urdf=/dev/zero",
        "version=2",
        "goals=1",
        "solver=[1]",
        "render.size=[1e400,1]",
        "goals[99].hold=1",
        "goals[-1].hold=1",
        "arm.links[0]=nan",
        "=1",
        "solver.step=",
    ):
        out.append(
            Attempt(
                k,
                f"sweep --set {setting}",
                ["sweep", "s.yaml", "--set", setting, "--out", "o", "-q", "--jobs", "1"],
                tiny_scene(),
                (0,)
                if setting.startswith("name=")
                else (2,),  # the variant's name is the sweep's own: o/tiny_name-....x
                timeout=60,
            )
        )
    for env_name, value in [
        ("ARMANIM_CACHE_DIR", "{d}/f"),
        ("ARMANIM_CACHE_DIR", "/dev/null"),
        ("ARMANIM_CACHE_DIR", "{d}/fifo"),
        ("TMPDIR", "{d}/nosuch"),
    ]:

        def setup(d: Path, env_name=env_name, value=value) -> None:
            write(d / "a.stl", stl(30))
            urdf_robot(collision=col("a.stl"))(d)
            write(d / "f", "x")
            fifo(d / "fifo")

        out.append(
            Attempt(
                k,
                f"validate a fitted URDF with {env_name}={value.replace('{d}/', '')}",
                ["validate", "s.yaml"],
                setup,
                (0,),
                env={env_name: value},
                timeout=120,
            )
        )
    out.append(
        Attempt(
            k,
            "run with TMPDIR missing (video)",
            ["run", "s.yaml", "--out", "o", "-q", "--jobs", "2"],
            tiny_scene(),
            (0, 3),
            env={"TMPDIR": "{d}/nosuch"},
            timeout=200,
        )
    )
    return out


# ------------------------------------------------------------------ the tenth campaign
#
# New attacks on the same classes (issue 50: "a fifth campaign on the same classes must find
# nothing"): none repeats an attempt above. Classes: mesh10, frames10, signals10, loss10,
# inputs10, wrong10 (``--only mesh10 ...``).

FK_PNG = ["fk", "--scene", "s.yaml", "--angles", "0,10,20", "--png", "p.png"]
FIT = ["robots", "--fit", "robot.urdf"]


def obj_text(vertices: int = 3, extra: str = "") -> str:
    return "".join(f"v {i * 0.01} {i % 2 * 0.05} {i % 3 * 0.05}\n" for i in range(vertices)) + "f 1 2 3\n" + extra


def tri_dae(p_indices: str = "0 1 2", count: int = 1, floats: str = "0 0 0 0.05 0 0 0 0.05 0", node: str = "") -> str:
    """A COLLADA file of one triangles geometry whose ``<p>``, count and corners are given."""
    return (
        '<?xml version="1.0"?><COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">'
        '<asset><unit meter="1"/></asset><library_geometries><geometry id="g0"><mesh><source id="p0">'
        f'<float_array id="a0" count="{len(floats.split())}">{floats}</float_array><technique_common>'
        f'<accessor source="#a0" count="{len(floats.split()) // 3}" stride="3"><param name="X" type="float"/>'
        '<param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source>'
        '<vertices id="v0"><input semantic="POSITION" source="#p0"/></vertices>'
        f'<triangles count="{count}"><input semantic="VERTEX" source="#v0" offset="0"/><p>{p_indices}</p></triangles>'
        "</mesh></geometry></library_geometries>"
        f'<library_visual_scenes><visual_scene id="s"><node id="n0">{node}<instance_geometry url="#g0"/></node>'
        '</visual_scene></library_visual_scenes><scene><instance_visual_scene url="#s"/></scene></COLLADA>'
    )


def stl_corners(corners: list[list[float]]) -> bytes:
    """A binary STL of the given triangles' corners ((m, 3, 3) nested lists, float32)."""
    import numpy as np

    array = np.asarray(corners, dtype="<f4").reshape(-1, 3, 3)
    records = np.zeros(len(array), dtype=[("normal", "<f4", 3), ("v", "<f4", (3, 3)), ("attr", "<u2")])
    records["v"] = array
    return b"\0" * 80 + np.uint32(len(array)).tobytes() + records.tobytes()


def big_stl(path: Path, triangles: int, seed: int = 0) -> None:
    import numpy as np

    rng = np.random.default_rng(seed)
    records = np.zeros(triangles, dtype=[("normal", "<f4", 3), ("v", "<f4", (3, 3)), ("attr", "<u2")])
    records["v"] = rng.random((triangles, 3, 3), dtype=np.float32) * 0.1
    with open(path, "wb") as handle:
        handle.write(b"\0" * 80 + np.uint32(triangles).tobytes())
        handle.write(records.tobytes())


def mesh10_attempts() -> list[Attempt]:
    """Mesh files and what they name: contents at the readers' edges, names at the resolver's."""
    k = "mesh10"
    out = []

    def both(label: str, name: str, files: dict, codes_fit=(0, 2), codes_png=(0,), timeout=120.0, scale=""):
        tag = f"<geometry><mesh filename={name!r}{f' scale={scale!r}' if scale else ''}/></geometry>"
        out.append(
            Attempt(
                k,
                f"robots --fit, collision {label}",
                FIT,
                urdf_robot(collision=f"<collision>{tag}</collision>", files=files),
                codes_fit,
                timeout=timeout,
            )
        )
        out.append(
            Attempt(
                k,
                f"fk --png, visual {label}",
                FK_PNG,
                urdf_robot(f"<visual>{tag}</visual>", files=files),
                codes_png,
                timeout=timeout,
            )
        )

    # OBJ at its edges
    both(
        "an OBJ of 64 MB of 'v 0 0 0' lines (8 million vertices)",
        "a.obj",
        {"a.obj": "v 0 0 0\n" * 8_300_000 + "f 1 2 3\n"},
        timeout=240,
    )
    both("an OBJ whose v lines hold two numbers", "a.obj", {"a.obj": "v 0 0\nv 1 0\nv 0 1\nf 1 2 3\n"})
    both("an OBJ whose v lines hold words", "a.obj", {"a.obj": "v a b c\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"})
    both("an OBJ of NaN corners only", "a.obj", {"a.obj": "v nan nan nan\nv nan 0 0\nv 0 nan 0\nf 1 2 3\n"})
    both("an OBJ face naming vertex 0", "a.obj", {"a.obj": obj_text(3, "f 0 1 2\n")})
    both("an OBJ face of a 30-digit index", "a.obj", {"a.obj": obj_text(3, "f 1 2 " + "9" * 30 + "\n")})
    both("an OBJ face of tokens '1/2/3/4' and '//'", "a.obj", {"a.obj": obj_text(3, "f 1/2/3/4 2// 3//\n")})
    both("an OBJ of CR line ends only", "a.obj", {"a.obj": obj_text(3).replace("\n", "\r")})
    both("an OBJ in UTF-16", "a.obj", {"a.obj": obj_text(3).encode("utf-16")})
    both("an OBJ of 1e300 corners", "a.obj", {"a.obj": "v 1e300 0 0\nv 0 1e300 0\nv 0 0 1e300\nf 1 2 3\n"})
    both("an OBJ face of two corners only", "a.obj", {"a.obj": "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n"})
    # STL at its edges
    both(
        "a binary STL of float32 corners near 3e38",
        "a.stl",
        {"a.stl": stl_corners([[[3e38, 0, 0], [0, 3e38, 0], [0, 0, -3e38]]])},
    )
    both("an STL of one triangle of three equal corners", "a.stl", {"a.stl": stl_corners([[[0.1, 0.1, 0.1]] * 3])})
    both("an STL of one collinear triangle", "a.stl", {"a.stl": stl_corners([[[0, 0, 0], [0.1, 0, 0], [0.2, 0, 0]]])})
    both(
        "an STL of 1,000 triangles all at one point",
        "a.stl",
        {"a.stl": stl_corners([[[0.05, 0.05, 0.05]] * 3] * 1000)},
    )
    both(
        "an ASCII STL of 60 MB of 'vertex 0 0 0' lines",
        "a.stl",
        {"a.stl": "solid s\n" + "vertex 0 0 0\n" * 4_800_000 + "endsolid\n"},
        timeout=240,
    )
    both(
        "an ASCII STL whose vertex holds 'infinity'",
        "a.stl",
        {"a.stl": "solid s\nvertex inf 0 0\nvertex 0 1 0\nvertex 0 0 1\nendsolid\n"},
    )
    both(
        "an ASCII STL whose vertex holds '1e99999'",
        "a.stl",
        {"a.stl": "solid s\nvertex 1e99999 0 0\nvertex 0 1 0\nvertex 0 0 1\nendsolid\n"},
    )
    # COLLADA at its edges
    both("a COLLADA <p> naming corner 99", "a.dae", {"a.dae": tri_dae("0 1 99")})
    both("a COLLADA <p> of a negative index", "a.dae", {"a.dae": tri_dae("0 1 -1")})
    both("a COLLADA triangles count 1,000,000,000 with one triangle", "a.dae", {"a.dae": tri_dae(count=1_000_000_000)})
    both("a COLLADA <p> of five indices", "a.dae", {"a.dae": tri_dae("0 1 2 0 1")})
    both("a COLLADA float_array of words", "a.dae", {"a.dae": tri_dae(floats="a b c d e f g h i")})
    both("a COLLADA node matrix of 15 numbers", "a.dae", {"a.dae": tri_dae(node="<matrix>" + "1 " * 15 + "</matrix>")})
    both("a COLLADA node matrix of NaN", "a.dae", {"a.dae": tri_dae(node="<matrix>" + "nan " * 16 + "</matrix>")})
    both("a COLLADA node rotate of 1e308 degrees", "a.dae", {"a.dae": tri_dae(node="<rotate>0 0 1 1e308</rotate>")})
    both("a COLLADA node scale 1e300", "a.dae", {"a.dae": tri_dae(node="<scale>1e300 1e300 1e300</scale>")})
    both(
        "a COLLADA in UTF-16 with an external entity on /dev/zero",
        "a.dae",
        {
            "a.dae": (
                '<?xml version="1.0" encoding="UTF-16"?><!DOCTYPE COLLADA [<!ENTITY z SYSTEM "/dev/zero">]>'
                + tri_dae()[tri_dae().index("<COLLADA") :].replace(
                    '<unit meter="1"/>', '<unit meter="1"/><contributor>&z;</contributor>'
                )
            ).encode("utf-16")
        },
        timeout=60,
    )
    laughs = "".join(f'<!ENTITY l{i} "{f"&l{i - 1};" * 10 if i else "lol"}">' for i in range(10))
    both(
        "a COLLADA in UTF-16 with a billion laughs",
        "a.dae",
        {
            "a.dae": (
                f'<?xml version="1.0" encoding="UTF-16"?><!DOCTYPE COLLADA [{laughs}]>'
                + tri_dae()[tri_dae().index("<COLLADA") :].replace("<asset>", "<asset><keywords>&l9;</keywords>")
            ).encode("utf-16")
        },
        timeout=60,
    )
    both(
        "a COLLADA of <lines> only",
        "a.dae",
        {"a.dae": tri_dae().replace("<triangles", "<lines").replace("</triangles>", "</lines>")},
    )
    both(
        "a COLLADA polylist of vcount -5",
        "a.dae",
        {
            "a.dae": tri_dae()
            .replace('<triangles count="1">', '<polylist count="1"><vcount>-5</vcount>')
            .replace("</triangles>", "</polylist>")
        },
    )
    # mesh names at the resolver's edges
    both("named by a 5,000-character file name", "a" * 5000 + ".stl", {}, codes_fit=(0, 2))
    both("named '.stl' in a folder of that name", "d/.stl", {}, codes_fit=(0, 2))
    both("named ''", "", {}, codes_fit=(0, 2))
    both("named 'package://'", "package://", {}, codes_fit=(0, 2))
    both("named 'package:///etc/hostname.stl'", "package:///etc/hostname.stl", {}, codes_fit=(0, 2))
    both("named 'file://' (nothing after)", "file://", {}, codes_fit=(0, 2))
    both("named with %20 for a space", "a%20b.stl", {"a b.stl": stl(4)}, codes_fit=(0, 2))
    both("named through a link loop of two", "x.stl", {}, codes_fit=(0, 2))
    both("a scale of 0 0 0", "a.stl", {"a.stl": stl(4)}, scale="0 0 0")
    both("a scale of 1e-300", "a.stl", {"a.stl": stl(4)}, scale="1e-300 1e-300 1e-300")
    both("a scale of -1 -1 -1", "a.stl", {"a.stl": stl(4)}, scale="-1 -1 -1")
    both("a scale of two numbers", "a.stl", {"a.stl": stl(4)}, scale="1 1", codes_png=(0, 2))
    both("a scale of nan", "a.stl", {"a.stl": stl(4)}, scale="nan 1 1", codes_png=(0, 2))

    # the loop of two and the socket: made here
    def loop_two(d: Path) -> None:
        urdf_robot(vis("x.stl"), col("x.stl"))(d)
        os.symlink("y.stl", d / "x.stl")
        os.symlink("x.stl", d / "y.stl")

    for attempt in out:
        if "link loop of two" in attempt.name:
            attempt.setup = loop_two
            attempt.codes = (2,)  # the same name is the collision mesh too: an error at its line
            attempt.message = r"robot\.urdf:\d+: link 'l1': collision mesh 'x\.stl' not found"

    def socket_mesh(d: Path) -> None:
        import socket

        urdf_robot(vis("s.stl"), col("s.stl"))(d)
        sock = socket.socket(socket.AF_UNIX)
        sock.bind(str(d / "s.stl"))  # left bound: a socket on disk, nobody accepting

    out.append(Attempt(k, "robots --fit, collision mesh a UNIX socket", FIT, socket_mesh, (2,), timeout=60))
    out.append(
        Attempt(k, "fk --png, visual mesh a UNIX socket", FK_PNG, socket_mesh, (2,), timeout=60, message="is a socket")
    )

    # five 60 MB STLs on one link: 300 MB in all, past the 256 MB of one robot's looks
    def five(d: Path) -> None:
        visuals = "".join(vis(f"b{i}.stl") for i in range(5))
        write(d / "robot.urdf", urdf_text(visuals))
        write(d / "s.yaml", URDF_SCENE)
        for i in range(5):
            big_stl(d / f"b{i}.stl", 1_200_000, seed=i)

    out.append(Attempt(k, "fk --png, five 60 MB STLs on one link (300 MB)", FK_PNG, five, (0,), timeout=300))
    # the tool's mesh: an OBJ at the readers' edges
    for label, text in [
        ("an OBJ of 64 MB of 'v 0 0 0'", "v 0 0 0\n" * 8_300_000 + "f 1 2 3\n"),
        ("an OBJ face of a 30-digit index", obj_text(3, "f 1 2 " + "9" * 30 + "\n")),
        ("an OBJ of 1e300 corners", "v 1e300 0 0\nv 0 1e300 0\nv 0 0 1e300\nf 1 2 3\n"),
    ]:
        out.append(
            Attempt(
                k,
                f"run --viewer, tool mesh {label}",
                ["run", "s.yaml", "--out", "o", "--no-video", "--viewer", "-q"],
                lambda d, text=text: (
                    write(d / "s.yaml", TOOL_SCENE.replace("TOOL", "t.obj")),
                    write(d / "t.obj", text),
                ),
                (0, 2),
                timeout=240,
            )
        )

    # a cached fit with finite but absurd capsules (the cache is read back: its values bounded?)
    def absurd_cache(d: Path) -> None:
        write(d / "a.stl", stl(30))
        urdf_robot(collision=col("a.stl"))(d)
        (d / "cache").mkdir()
        env = dict(os.environ, PYTHONPATH=str(SRC), ARMANIM_CACHE_DIR=str(d / "cache"))
        subprocess.run(
            [sys.executable, "-m", "armanim", "validate", "s.yaml"], cwd=d, env=env, check=True, capture_output=True
        )
        import json as _json

        for fit in (d / "cache").rglob("*.json"):
            data = _json.loads(fit.read_text())
            data["capsules"] = [{"from": [1e300, 0, 0], "to": [-1e300, 0, 0], "radius": 1e300}]
            fit.write_text(_json.dumps(data))

    for cmd in (["validate", "s.yaml"], ["run", "s.yaml", "--out", "o", "--no-video", "-q"]):
        out.append(
            Attempt(
                k,
                f"a cached fit of capsules 1e300 long and wide, then {cmd[0]}",
                cmd,
                absurd_cache,
                (0, 2),
                env={"ARMANIM_CACHE_DIR": "{d}/cache"},
                timeout=200,
            )
        )
    return out


SIMPLE = (
    "version: 1\nname: f\narm: {links: [1, 1, 1]ARM}\nGOALS\nsolver: {SOLVER}\nrender: {size: [160, 90], fps: FPS}\n"
)


def simple(goals: str = "goals: [[1, 1, 1], [0.5, -1, 1]]", arm: str = "", solver: str = "", fps: str = "10") -> str:
    return SIMPLE.replace("ARM", arm).replace("GOALS", goals).replace("SOLVER", solver).replace("FPS", fps)


def frames10_attempts() -> list[Attempt]:
    """Solver tolerances at their floors, frame budgets at their edges, rates at their bounds."""
    k = "frames10"
    out = []
    run = ["run", "s.yaml", "--out", "o", "--no-video", "-q"]
    cases = [
        ("solver.tolerance 1e-300", simple(solver="tolerance: 1e-300, max_frames_per_goal: 50")),
        ("solver.tolerance 5e-324", simple(solver="tolerance: 5e-324, max_frames_per_goal: 50")),
        (
            "joint_tolerance 1e-6 (its floor), newton",
            simple("goals: [{joints: [30, 40, 20]}]", solver="joint_tolerance: 1e-6, method: newton"),
        ),
        (
            "joint_tolerance 1e-6, gradient",
            simple("goals: [{joints: [30, 40, 20]}]", solver="joint_tolerance: 1e-6, method: gradient"),
        ),
        (
            "orientation_tolerance 1e-6 (its floor)",
            simple(
                "goals: [{position: [1, 0.5, 1.5], tool_axis: [1, 0, 0]}]",
                solver="orientation_tolerance: 1e-6, max_frames_per_goal: 200",
            ),
        ),
        (
            "max_joint_step 0.001 (its floor), a far goal",
            simple("goals: [[-1, -1, 1]]", solver="max_joint_step: 0.001, max_frames_per_goal: 300"),
        ),
        ("max_joint_step 180 (its bound), fps 0.01", simple(solver="max_joint_step: 180", fps="0.01")),
        (
            "max_joint_speed 1e5 and acceleration 1e7 at 0.01 fps",
            simple(arm=", max_joint_speed: 100000, max_joint_acceleration: 10000000", fps="0.01"),
        ),
        (
            "max_joint_speed 1e5, acceleration 1e7, jerk 1e10 at 240 fps",
            simple(
                arm=", max_joint_speed: 100000, max_joint_acceleration: 10000000, max_joint_jerk: 10000000000",
                fps="240",
            ),
        ),
        (
            "max_joint_acceleration at its least for 30 fps (3.6e-9)",
            simple("goals: [{joints: [1, 0, 0]}]", arm=", max_joint_acceleration: 3.6e-9", fps="30"),
        ),
        (
            "max_joint_acceleration just under its least (3.5e-9)",
            simple("goals: [{joints: [1, 0, 0]}]", arm=", max_joint_acceleration: 3.5e-9", fps="30"),
        ),
        (
            "max_joint_speed 3e-5 (its least at 30 fps), a 1-degree joint goal",
            simple("goals: [{joints: [1, 0, 0]}]", arm=", max_joint_speed: 3e-5", fps="30"),
        ),
        ("max_joint_speed 64 values on 3 joints", simple(arm=", max_joint_speed: [" + ",".join(["10"] * 64) + "]")),
        ("max_joint_speed 65 values", simple(arm=", max_joint_speed: [" + ",".join(["10"] * 65) + "]")),
        ("hold 1e308", simple("goals: [{position: [1, 1, 1], hold: 1e308}]")),
        ("hold 5e-324", simple("goals: [{position: [1, 1, 1], hold: 5e-324}]")),
        ("max_frames_per_goal 1,000,000", simple(solver="max_frames_per_goal: 1000000")),
        ("max_frames_per_goal 0", simple(solver="max_frames_per_goal: 0")),
        ("max_frames_per_goal 1e300 (a float)", simple(solver="max_frames_per_goal: 1e300")),
        (
            "1,000 goals (the most)",
            "version: 1\nname: f\narm: {links: [1, 1, 1]}\ngoals:\n"
            + "".join(f"  - [1, {(i % 2) * 0.2}, 1]\n" for i in range(1000))
            + "render: {size: [160, 90], fps: 10}\n",
        ),
        (
            "1,001 goals",
            "version: 1\nname: f\narm: {links: [1, 1, 1]}\ngoals:\n"
            + "".join(f"  - [1, {(i % 2) * 0.2}, 1]\n" for i in range(1001))
            + "render: {size: [160, 90], fps: 10}\n",
        ),
        (
            "blend 1e9 on every goal",
            simple("goals: [{position: [1, 1, 1], blend: 1e9}, {position: [0.5, -1, 1], blend: 1e9}, [1, 0, 2]]"),
        ),
        ("blend 5e-324", simple("goals: [{position: [1, 1, 1], blend: 5e-324}, [0.5, -1, 1]]")),
        (
            "a joint goal's blend of 180 degrees",
            simple("goals: [{joints: [30, 40, 20], blend: 180}, {joints: [-30, 10, 20]}]"),
        ),
        (
            "solver.blend 1e-12 with a path",
            simple(
                "goals: [[1, 0.5, 1], {path: {line: [[1, 0.5, 1], [1, -0.5, 1]]}, speed: 0.5}]", solver="blend: 1e-12"
            ),
        ),
        (
            "a polyline of 10,000 points",
            simple(
                "goals:\n  - path: {polyline: ["
                + ",".join(f"[1, {(i % 200) / 400 - 0.25:.4f}, {1 + (i // 200) / 400:.4f}]" for i in range(10000))
                + "]}\n    speed: 0.5"
            ),
        ),
        (
            "a polyline with a repeated point",
            simple("goals: [{path: {polyline: [[1, 0.5, 1], [1, 0.5, 1], [1, -0.5, 1]]}, speed: 0.5}]"),
        ),
        ("a line of two equal points", simple("goals: [{path: {line: [[1, 0.5, 1], [1, 0.5, 1]]}, speed: 0.5}]")),
        (
            "an arc of angle 1e-300",
            simple(
                "goals: [{path: {arc: {center: [1, 0, 1], start: [1, 0.3, 1], angle: 1e-300, normal: [1, 0, 0]}}, speed: 0.5}]"
            ),
        ),
        (
            "an arc of radius 0",
            simple(
                "goals: [{path: {arc: {center: [1, 0, 1], start: [1, 0, 1], angle: 90, normal: [1, 0, 0]}}, speed: 0.5}]"
            ),
        ),
        (
            "an arc whose normal is 1e-300 long",
            simple(
                "goals: [{path: {arc: {center: [1, 0, 1], start: [1, 0.3, 1], angle: 90, normal: [1e-300, 0, 0]}}, speed: 0.5}]"
            ),
        ),
        ("a path at speed 1e9", simple("goals: [{path: {line: [[1, 0.5, 1], [1, -0.5, 1]]}, speed: 1e9}]")),
        (
            "a text path of 2,000 characters",
            simple(
                'goals: [{path: {text: {string: "'
                + "W" * 2000
                + '", origin: [1, -0.5, 1], height: 0.05, right: [0, 1, 0], up: [0, 0, 1]}}, speed: 0.5}]'
            ),
        ),
        (
            "a text path of one space",
            simple(
                'goals: [{path: {text: {string: " ", origin: [1, -0.5, 1], height: 0.05, right: [0, 1, 0], up: [0, 0, 1]}}, speed: 0.5}]'
            ),
        ),
        (
            "a text path of height 1e-300",
            simple(
                'goals: [{path: {text: {string: "ab", origin: [1, -0.5, 1], height: 1e-300, right: [0, 1, 0], up: [0, 0, 1]}}, speed: 0.5}]'
            ),
        ),
        (
            "a text path whose right and up are parallel",
            simple(
                'goals: [{path: {text: {string: "ab", origin: [1, -0.5, 1], height: 0.05, right: [0, 0, 1], up: [0, 0, 1]}}, speed: 0.5}]'
            ),
        ),
    ]
    for label, text in cases:
        out.append(Attempt(k, f"run {label}", run, tiny_scene(text=text), (0, 2), timeout=300))

    # the frame budget at its edge: 1 + the goals' max_frames_per_goal + round(hold * fps) each
    def holds(last: str, fps: str, count: int) -> str:
        goals = [f"{{position: [1, {k % 2}, 1], hold: 3600}}" for k in range(count)]
        goals.append(f"{{position: [1, 1, 1], hold: {last}}}")
        return simple(f"goals: [{', '.join(goals)}]", solver="max_frames_per_goal: 10", fps=fps)

    for last, codes in (("2771.9", (0,)), ("2771.94", (0,)), ("2772", (2,))):  # 1,000,000 / 1,000,000 / 1,000,001
        out.append(
            Attempt(
                k,
                f"validate 28 holds of 1,000,000 frames and one more (last hold {last} s at 10 fps)",
                ["validate", "s.yaml"],
                tiny_scene(text=holds(last, "10", 27)),
                codes,
                timeout=60,
            )
        )
    edge = holds("925.8", "30", 9)  # 999,875 frames at 30 fps
    for flag in (["--fps", "30.01"], ["--fps", "240"], ["--quality", "high"]):
        out.append(
            Attempt(
                k,
                f"run 10 holds of 999,875 frames {' '.join(flag)} (past the frame limit)",
                [*run, *flag],
                tiny_scene(text=edge),
                (2,),
                timeout=120,
                message="1,000,000",
            )
        )
    out.append(
        Attempt(
            k,
            "render --fps 0.01 of a finished run",
            ["render", "o/tiny", "--fps", "0.01", "-q", "--size", "64x48"],
            lambda d: finished_run(d) and None,
            (0, 2),
            timeout=300,
        )
    )
    out.append(
        Attempt(
            k,
            "view of a run of 1,000 goals",
            ["view", "o/f", "--out", "v.html"],
            lambda d: finished_run(d, dict(cases)["1,000 goals (the most)"]) and None,
            (0,),
            timeout=400,
        )
    )
    return out


LONG = TINY.replace(
    "[[1, 1, 1], [0.5, -1, 1]]", "[{position: [1, 1, 1], hold: 3600}, {position: [0.5, -1, 1], hold: 400}]"
)
"""A tiny scene of some 40,000 frames (a long hold at 10 fps): long pages, exports and CSVs."""


def whole_or_none(*paths: str) -> Callable[[Path], list[str]]:
    """After an interrupt: each path absent, or whole (a run folder with its marker; a page that
    ends its document; a JSON file that parses)."""

    def check(d: Path) -> list[str]:
        import json as _json

        problems = []
        for name in paths:
            path = d / name
            if not os.path.lexists(path):
                continue
            if path.is_dir():
                if not (path / ".armanim-run.json").is_file():
                    problems.append(f"{name}: a folder without its marker")
            elif name.endswith(".html"):  # a page ends its document, then (armanim's) the mark's <meta> line
                if b"</html>" not in path.read_bytes()[-300:]:
                    problems.append(f"{name}: half a page")
            elif name.endswith(".json"):
                try:
                    _json.loads(path.read_text())
                except ValueError:
                    problems.append(f"{name}: half a JSON file")
            elif name.endswith(".csv"):
                import csv as _csv

                text = path.read_text()
                rows = list(_csv.reader(text.splitlines()))  # a cell may hold a quoted comma
                if not text.endswith("\n") or len({len(row) for row in rows}) > 1:
                    problems.append(f"{name}: half a CSV file")
            elif name.endswith(".yaml"):
                import yaml

                try:
                    yaml.safe_load(path.read_text())
                except yaml.YAMLError:
                    problems.append(f"{name}: half a YAML file")
        return problems

    return check


def signals10_attempts() -> list[Attempt]:
    """Interrupts at moments and in commands the campaigns before did not reach: view, export,
    validate's fit, a double Ctrl-C, SIGTERM to the whole group, a signal during start-up."""
    k = "signals10"
    out = []

    def with_long(d: Path) -> None:
        finished_run(d, LONG)

    for cmd, target, delays in [
        (["view", "o/tiny", "--out", "v.html"], "v.html", (1.0, 3.0)),
        (["export", "o/tiny", "--out", "e.json"], "e.json", (1.0, 2.5)),
        (["view", "o/tiny"], "o/tiny", (2.0,)),
    ]:
        for delay in delays:
            for signame in ("SIGINT", "SIGTERM", "SIGTERMG"):
                out.append(
                    Attempt(
                        k,
                        f"{' '.join(cmd[:2])} of a 40,000-frame run, {signame} at {delay:g} s",
                        cmd,
                        with_long,
                        (0, 130),
                        timeout=120,
                        interrupt=(delay, signame),
                        keep=("o/tiny",) if target != "o/tiny" else (),
                        after=whole_or_none(target),
                        litter_in=("o", "."),
                    )
                )

    def fit_setup(d: Path) -> None:
        big_stl(d / "big.stl", 600_000)
        urdf_robot(collision=col("big.stl"))(d)
        (d / "cache").mkdir()

    for cmd in (["validate", "s.yaml"], ["run", "s.yaml", "--out", "o", "--no-video", "-q"]):
        for delay, signame in ((1.5, "SIGINT"), (3.0, "SIGTERM"), (5.0, "SIGTERMG")):
            out.append(
                Attempt(
                    k,
                    f"{cmd[0]} fitting a 30 MB collision STL, {signame} at {delay:g} s",
                    cmd,
                    fit_setup,
                    (0, 130),
                    timeout=120,
                    interrupt=(delay, signame),
                    env={"ARMANIM_CACHE_DIR": "{d}/cache"},
                    after=whole_or_none("o/m"),
                    litter_in=("o", "cache"),
                )
            )
    run_video = ["run", "s.yaml", "--out", "o", "-q", "--jobs", "2"]
    for label, interrupt, also in [
        ("two Ctrl-C 0.2 s apart at 3 s", (3.0, "SIGINT"), ((3.2, "SIGINT"),)),
        ("two Ctrl-C 0.05 s apart at 6 s", (6.0, "SIGINT"), ((6.05, "SIGINT"),)),
        ("Ctrl-C then SIGTERM at 4 s", (4.0, "SIGINT"), ((4.3, "SIGTERM"),)),
        ("SIGTERM to the group at 4 s", (4.0, "SIGTERMG"), ()),
        ("SIGTERM to the group at 8 s", (8.0, "SIGTERMG"), ()),
        ("Ctrl-C at 0.15 s (start-up)", (0.15, "SIGINT"), ()),
        ("SIGTERM at 0.3 s (imports)", (0.3, "SIGTERM"), ()),
    ]:
        out.append(
            Attempt(
                k,
                f"run with video, {label}",
                run_video,
                tiny_scene(),
                (0, 130),
                timeout=200,
                interrupt=interrupt,
                also=also,
                after=whole_or_none("o/tiny"),
            )
        )
    for delay, signame in ((2.0, "SIGINT"), (5.0, "SIGTERMG"), (8.0, "SIGTERM")):
        out.append(
            Attempt(
                k,
                f"run writing a 40,000-frame CSV, {signame} at {delay:g} s",
                ["run", "s.yaml", "--out", "o", "--no-video", "-q"],
                tiny_scene(text=LONG),
                (0, 130),
                timeout=200,
                interrupt=(delay, signame),
                after=whole_or_none("o/tiny"),
            )
        )

    def rendered(d: Path) -> None:
        finished_run(d, video=False)

    for delay, signame in ((1.5, "SIGINT"), (4.0, "SIGTERMG"), (6.0, "SIGTERM")):
        out.append(
            Attempt(
                k,
                f"render --out fig, {signame} at {delay:g} s",
                ["render", "o/tiny", "--out", "fig", "-q", "--size", "320x180"],
                rendered,
                (0, 130),
                timeout=200,
                interrupt=(delay, signame),
                keep=("o/tiny",),
                after=whole_or_none("fig"),
                litter_in=("o", "fig", "."),
            )
        )
    for delay, signame in ((2.0, "SIGINT"), (5.0, "SIGTERMG")):
        out.append(
            Attempt(
                k,
                f"sweep of 4 variants with video, {signame} at {delay:g} s",
                [
                    "sweep",
                    "s.yaml",
                    "--set",
                    "solver.step=0.1,0.2",
                    "--set",
                    "render.fps=5,10",
                    "--out",
                    "o",
                    "-q",
                    "--video",
                    "--jobs",
                    "2",
                ],
                tiny_scene(),
                (0, 2, 130),
                timeout=300,
                interrupt=(delay, signame),
                after=lambda d: [
                    p
                    for name in (os.listdir(d / "o") if (d / "o").is_dir() else [])
                    if not name.startswith(".")
                    for p in whole_or_none(f"o/{name}")(d)
                ],
            )
        )
    for delay, signame in ((1.0, "SIGINT"), (3.0, "SIGTERMG")):
        out.append(
            Attempt(
                k,
                f"fk --png of a 60 MB visual STL, {signame} at {delay:g} s",
                FK_PNG,
                lambda d: (urdf_robot(vis("big.stl"))(d), big_stl(d / "big.stl", 1_200_000)),
                (0, 130),
                timeout=120,
                interrupt=(delay, signame),
                after=lambda d: (
                    []
                    if os.path.exists(d / "p.png") == os.path.exists(d / ".p.png.armanim.json")
                    else ["a png without its mark, or a mark alone"]
                ),
                litter_in=(".",),
            )
        )
    return out


def armanim_in(d: Path, *args: str, env: dict | None = None) -> None:
    """Run armanim in ``d`` as the setup of an attempt (checked)."""
    done = subprocess.run(
        [sys.executable, "-m", "armanim", *args],
        cwd=d,
        env=dict(os.environ, PYTHONPATH=str(SRC), **(env or {})),
        capture_output=True,
        text=True,
        timeout=600,
    )
    if done.returncode != 0:
        raise RuntimeError(f"setup armanim {' '.join(args)} failed: {done.stderr[-400:]}")


OTHER = TINY.replace("name: tiny", "name: other")


def then(*steps: Callable[[Path], object]) -> Callable[[Path], None]:
    """Setup: each step in turn."""

    def setup(d: Path) -> None:
        for step in steps:
            step(d)

    return setup


def edit(path: str, append: bytes = b" ") -> Callable[[Path], None]:
    def change(d: Path) -> None:
        with open(d / path, "ab") as handle:
            handle.write(append)

    return change


def hardlink(src: str, dst: str) -> Callable[[Path], None]:
    return lambda d: os.link(d / src, d / dst)


def symlink(target: str, at: str) -> Callable[[Path], None]:
    """Setup: a symbolic link ``at`` (its folder made if missing) to ``target``."""
    return lambda d: ((d / at).parent.mkdir(parents=True, exist_ok=True), os.symlink(target, d / at)) and None


def mine(name: str = "mine.txt", text: str = "my notes\n") -> Callable[[Path], None]:
    return lambda d: write(d / name, text) and None


def loss10_attempts() -> list[Attempt]:
    """Hard links, links at marks and caches, outputs aimed into other run folders, edited outputs."""
    k = "loss10"
    out = []
    run = ["run", "s.yaml", "--out", "o", "--no-video", "-q"]
    changed = TINY.replace("[0.5, -1, 1]", "[0.5, -1, 1.2]")

    base = finished_run
    out += [
        Attempt(
            k,
            "view --out a page armanim wrote, edited since",
            ["view", "o/tiny", "--out", "v.html"],
            then(base, lambda d: armanim_in(d, "view", "o/tiny", "--out", "v.html"), edit("v.html", b"<!-- mine -->")),
            (3,),
            keep=("v.html",),
        ),
        Attempt(
            k,
            "view --out v.html, hard-linked by the user as keep.html",
            ["view", "o/tiny", "--out", "v.html"],
            then(base, lambda d: armanim_in(d, "view", "o/tiny", "--out", "v.html"), hardlink("v.html", "keep.html")),
            (0, 3),
            keep=("keep.html",),
        ),
        Attempt(
            k,
            "export --out x.json, hard-linked by the user as keep.json",
            ["export", "o/tiny", "--out", "x.json"],
            then(base, lambda d: export_of(d, "x.json"), hardlink("x.json", "keep.json")),
            (0, 3),
            keep=("keep.json",),
        ),
        Attempt(
            k,
            "run again, trajectory.csv hard-linked by the user as mine.csv",
            run,
            then(base, hardlink("o/tiny/trajectory.csv", "mine.csv"), lambda d: write(d / "s.yaml", changed)),
            (0, 3),
            keep=("mine.csv",),
        ),
        Attempt(
            k,
            "render again, plot.png hard-linked by the user",
            ["render", "o/tiny", "-q", "--size", "64x48"],
            then(lambda d: finished_run(d, video=True), hardlink("o/tiny/plot.png", "mine.png")),
            (0, 3),
            keep=("mine.png",),
        ),
        Attempt(
            k,
            "check --update, the golden CSV hard-linked by the user",
            ["check", "s.yaml", "--golden", "g", "--update"],
            then(
                mine("s.yaml", TINY),
                lambda d: armanim_in(d, "check", "s.yaml", "--golden", "g", "--update"),
                hardlink("g/tiny.csv", "mine.csv"),
                lambda d: write(d / "s.yaml", changed),
            ),
            (0, 3),
            keep=("mine.csv",),
        ),
        Attempt(
            k,
            "run again, trajectory.csv now a link to the user's copy",
            run,
            then(
                base,
                lambda d: shutil.copy(d / "o/tiny/trajectory.csv", d / "mine.csv"),
                lambda d: os.unlink(d / "o/tiny/trajectory.csv"),
                symlink("../../mine.csv", "o/tiny/trajectory.csv"),
            ),
            (0, 3),
            keep=("mine.csv",),
        ),
        Attempt(
            k,
            "run --out a link to the user's folder of notes",
            ["run", "s.yaml", "--out", "lnk", "--no-video", "-q"],
            then(mine("s.yaml", TINY), mine("real/notes.txt"), symlink("real", "lnk")),
            (0, 3),
            keep=("real/notes.txt", "lnk"),
        ),
        Attempt(
            k,
            "run, OUT/NAME a link to another run folder",
            run,
            then(lambda d: finished_run(d, OTHER, "other.yaml"), mine("s.yaml", TINY), symlink("other", "o/tiny")),
            (3,),
            keep=("o/other", "o/tiny"),
        ),
        Attempt(
            k,
            "run, OUT/NAME a user's regular file",
            run,
            then(mine("s.yaml", TINY), mine("o/tiny")),
            (3,),
            keep=("o/tiny",),
        ),
        Attempt(
            k,
            "render --out a link to the user's empty folder",
            ["render", "o/tiny", "-q", "--size", "64x48", "--out", "fig"],
            then(base, lambda d: (d / "real").mkdir(), symlink("real", "fig")),
            (0, 2, 3),
            keep=("fig",),
        ),
        Attempt(
            k,
            "render --out a previous render's folder, plot.png edited since",
            ["render", "o/tiny", "-q", "--size", "64x48", "--out", "fig"],
            then(
                base,
                lambda d: armanim_in(d, "render", "o/tiny", "-q", "--size", "64x48", "--out", "fig"),
                edit("fig/plot.png"),
            ),
            (3,),
            keep=("fig",),
        ),
        Attempt(
            k,
            "render --out another run's folder",
            ["render", "o/tiny", "-q", "--size", "64x48", "--out", "o/other"],
            then(base, lambda d: finished_run(d, OTHER, "other.yaml")),
            (2, 3),
            keep=("o/other",),
        ),
        Attempt(
            k,
            "render --out the runs' root",
            ["render", "o/tiny", "-q", "--size", "64x48", "--out", "o"],
            base,
            (2, 3),
            keep=("o/tiny",),
        ),
        Attempt(
            k,
            "render --out . (the user's folder)",
            ["render", "o/tiny", "-q", "--size", "64x48", "--out", "."],
            base,
            (2, 3),
            keep=("s.yaml",),
        ),
        Attempt(
            k,
            "export --out into another run's folder",
            ["export", "o/tiny", "--out", "o/other/x.json"],
            then(base, lambda d: finished_run(d, OTHER, "other.yaml")),
            (2,),
            keep=("o/other",),
        ),
        Attempt(
            k,
            "view --out another run's viewer.html",
            ["view", "o/tiny", "--out", "o/other/viewer.html"],
            then(base, lambda d: finished_run(d, OTHER, "other.yaml")),
            (2,),
            keep=("o/other",),
        ),
        Attempt(
            k,
            "view --out the run's own trajectory.csv",
            ["view", "o/tiny", "--out", "o/tiny/trajectory.csv"],
            base,
            (2, 3),
            keep=("o/tiny",),
        ),
        Attempt(
            k,
            "schema --out an export armanim wrote",
            ["schema", "--out", "x.json"],
            then(base, lambda d: export_of(d, "x.json")),
            (3,),
            keep=("x.json",),
        ),
        Attempt(
            k,
            "fk --png onto a schema armanim wrote",
            ["fk", "--angles", "0,0,0,0", "--png", "s.json"],
            lambda d: armanim_in(d, "schema", "--out", "s.json"),
            (3,),
            keep=("s.json",),
        ),
        Attempt(
            k,
            "fk --png into a run folder",
            ["fk", "--angles", "0,0,0,0", "--png", "o/tiny/plot.png"],
            lambda d: finished_run(d, video=True) and None,
            (2, 3),
            keep=("o/tiny",),
        ),
        Attempt(
            k,
            "schema --out into a run folder's summary.json",
            ["schema", "--out", "o/tiny/summary.json"],
            base,
            (2, 3),
            keep=("o/tiny",),
        ),
        Attempt(
            k,
            "import moveit --out a batch's index.csv",
            ["import", "moveit", "w.scene", "--robot", "panda", "--out", "o/index.csv"],
            then(
                mine("a.yaml", TINY.replace("tiny", "a")),
                lambda d: (
                    armanim_in(d, "run", "a.yaml", "s.yaml", "--out", "o", "--no-video", "-q", "--jobs", "1")
                    if write(d / "s.yaml", TINY)
                    else None
                ),
                mine("w.scene", "w\n* box\n1\nbox\n0.1 0.1 0.1\n1 1 1\n0 0 0 1\n0 0 0 0\n.\n"),
            ),
            (2, 3),
            keep=("o/index.csv",),
        ),
        Attempt(
            k,
            "check --update --golden a run folder",
            ["check", "s.yaml", "--golden", "o/tiny", "--update"],
            base,
            (2, 3),
            keep=("o/tiny",),
        ),
        Attempt(
            k,
            "check --update --golden the runs' root holding a run",
            ["check", "s.yaml", "--golden", "o", "--update"],
            base,
            (0, 2, 3),
            keep=("o/tiny",),
        ),
        Attempt(
            k,
            "a batch of two scenes of one name",
            ["run", "s.yaml", "t.yaml", "--out", "o", "--no-video", "-q", "--jobs", "1"],
            then(mine("s.yaml", TINY), mine("t.yaml", changed)),
            (2,),
            message="also named 'tiny'",  # the first scene runs (a batch runs what it can), the second is named
        ),
        Attempt(
            k,
            "a batch of two names that differ in case only",
            ["run", "s.yaml", "t.yaml", "--out", "o", "--no-video", "-q", "--jobs", "1"],
            then(mine("s.yaml", TINY), mine("t.yaml", TINY.replace("tiny", "TINY"))),
            (0, 2),
            keep=(),
        ),
        Attempt(
            k,
            "export --out x.json, its mark a link to the user's file",
            ["export", "o/tiny", "--out", "x.json"],
            then(
                base,
                lambda d: export_of(d, "x.json"),
                mine(),
                lambda d: os.unlink(d / ".x.json.armanim.json"),
                symlink("mine.txt", ".x.json.armanim.json"),
            ),
            (0, 3),
            keep=("mine.txt",),
        ),
        Attempt(
            k,
            "schema --out s.json, its mark a hard link to the user's file",
            ["schema", "--out", "s.json"],
            then(
                lambda d: armanim_in(d, "schema", "--out", "s.json"),
                lambda d: shutil.copy(d / ".s.json.armanim.json", d / "mine.json"),
                lambda d: os.unlink(d / ".s.json.armanim.json"),
                hardlink("mine.json", ".s.json.armanim.json"),
            ),
            (0, 3),
            keep=("mine.json",),
        ),
        Attempt(
            k,
            "a batch again, index.csv's mark hard-linked by the user",
            ["run", "a.yaml", "s.yaml", "--out", "o", "--no-video", "-q", "--jobs", "1"],
            then(
                mine("a.yaml", TINY.replace("tiny", "a")),
                mine("s.yaml", TINY),
                lambda d: armanim_in(d, "run", "a.yaml", "s.yaml", "--out", "o", "--no-video", "-q", "--jobs", "1"),
                hardlink("o/.index.csv.armanim.json", "mine.json"),
                mine("a.yaml", TINY.replace("tiny", "a").replace("[0.5, -1, 1]", "[0.5, -1, 1.2]")),
            ),
            (0, 3),
            keep=("mine.json",),
        ),
        Attempt(
            k,
            "run, the lock hard-linked to the user's file",
            run,
            then(mine("s.yaml", TINY), mine(), lambda d: (d / "o").mkdir(), hardlink("mine.txt", "o/.tiny.lock")),
            (0, 3),
            keep=("mine.txt",),
        ),
        Attempt(
            k,
            "validate with ARMANIM_CACHE_DIR the user's folder of notes",
            ["validate", "s.yaml"],
            then(
                lambda d: write(d / "a.stl", stl(30)),
                urdf_robot(collision=col("a.stl")),
                mine("notes/a.txt"),
                mine("notes/b.json", "{}"),
            ),
            (0,),
            env={"ARMANIM_CACHE_DIR": "{d}/notes"},
            keep=("notes/a.txt", "notes/b.json"),
        ),
        Attempt(
            k,
            "fk --png a name with a newline",
            ["fk", "--angles", "0,0,0,0", "--png", "a\nb.png"],
            lambda d: None,
            (0, 2),
            after=lambda d: (
                []
                if not (d / "a\nb.png").exists() or (d / ".a\nb.png.armanim.json").exists()
                else ["a png without its mark"]
            ),
        ),
        Attempt(
            k,
            "run --out a folder of odd characters ('-rf', spaces, accents)",
            ["run", "s.yaml", "--out", "-rf é  x", "--no-video", "-q"],
            mine("s.yaml", TINY),
            (0,),
            after=exists("-rf é  x/tiny"),
        ),
        Attempt(
            k,
            "run, then a scene named tiny.old-1 (a leftover's look)",
            ["run", "t.yaml", "--out", "o", "--no-video", "-q"],
            then(base, mine("t.yaml", TINY.replace("name: tiny", "name: tiny.old-1"))),
            (0, 2),
            keep=("o/tiny",),
            litter_in=(),
        ),
        Attempt(
            k,
            "run of a scene named tiny.lock beside a run tiny",
            ["run", "t.yaml", "--out", "o", "--no-video", "-q"],
            then(base, mine("t.yaml", TINY.replace("name: tiny", "name: tiny.lock"))),
            (0, 2),
            keep=("o/tiny",),
        ),
    ]

    def cache_entry_as(link: Callable[[Path, Path], None]) -> Callable[[Path], None]:
        """A fitted URDF whose cache entries are then ``link(user's file, entry)``."""
        return then(
            lambda d: write(d / "a.stl", stl(30)),
            urdf_robot(collision=col("a.stl")),
            lambda d: (d / "cache").mkdir(),
            lambda d: armanim_in(d, "validate", "s.yaml", env={"ARMANIM_CACHE_DIR": str(d / "cache")}),
            mine("mine.json", '{"mine": 1}'),
            lambda d: [(os.unlink(p), link(d / "mine.json", p)) for p in (d / "cache").glob("*.json")],
        )

    for label, link in (("a link", os.symlink), ("a hard link", os.link)):
        out.append(
            Attempt(
                k,
                f"validate, a fitted cache entry {label} to the user's file",
                ["validate", "s.yaml"],
                cache_entry_as(link),
                (0,),
                env={"ARMANIM_CACHE_DIR": "{d}/cache"},
                keep=("mine.json",),
            )
        )
    return out


AT_LINE = r"(\.yaml|\.urdf|\.srdf|\.scene|--set [^:]+|\.xml):(\d+:)? "
"""What an input error names: the file and line (the field and message follow)."""

MINI_URDF = urdf_text()


def inputs10_attempts() -> list[Attempt]:
    """Malformed YAML, URDF, SRDF and scene fields the campaigns before did not write."""
    k = "inputs10"
    out = []
    good = "version: 1\nname: s\narm: {links: [1, 1, 1]}\ngoals: [[1, 1, 1]]\n"

    def goals_(goals: str) -> str:
        return good.replace("[[1, 1, 1]]", goals)

    def arm_(fields: str) -> str:
        return good.replace("links: [1, 1, 1]", "links: [1, 1, 1], " + fields)

    yaml_cases = [
        ("a duplicate key", "version: 1\nversion: 1\narm: {links: [1, 1, 1]}\ngoals: [[1, 1, 1]]\n"),
        ("a merge key <<", "base: &b {links: [1, 1, 1]}\nversion: 1\narm: {<<: *b}\ngoals: [[1, 1, 1]]\n"),
        ("a !!binary value", good.replace("name: s", "name: !!binary aGVsbG8=")),
        ("a !!set", good.replace("goals: [[1, 1, 1]]", "goals: !!set {a, b}")),
        ("a !!timestamp", good.replace("name: s", "name: 2020-01-01")),
        ("a !!omap", good.replace("arm: {links: [1, 1, 1]}", "arm: !!omap [links: [1, 1, 1]]")),
        ("a !!python/name tag", good.replace("name: s", "name: !!python/name:os.system")),
        ("a custom !tag", good.replace("name: s", "name: !mine s")),
        ("an integer key", good + "1: x\n"),
        ("a list as a key", good + "? [a, b]\n: x\n"),
        ("a null key", good + "~: x\n"),
        ("a boolean key", good + "true: x\n"),
        ("a document end then garbage", good + "...\n%%%\n"),
        ("CR line ends only", good.replace("\n", "\r")),
        ("a tab for indentation", "version: 1\narm:\n\tlinks: [1, 1, 1]\ngoals: [[1, 1, 1]]\n"),
        ("a 200,000-character line", good.replace("name: s", "name: " + "s" * 200_000)),
        ("a scalar document", "42\n"),
        ("a list document", "- 1\n- 2\n"),
        ("only a comment", "# nothing\n"),
        ("version '1'", good.replace("version: 1", "version: '1'")),
        ("name 123", good.replace("name: s", "name: 123")),
        ("name a list", good.replace("name: s", "name: [a]")),
        ("name with a newline", good.replace("name: s", 'name: "a\\nb"')),
        ("name with a right-to-left mark", good.replace("name: s", 'name: "a\\u202eb"')),
        ("name of NUL", good.replace("name: s", 'name: "\\0"')),
        ("goals {}", good.replace("goals: [[1, 1, 1]]", "goals: {}")),
        ("goals null", good.replace("goals: [[1, 1, 1]]", "goals: null")),
        ("a goal '1,1,1' as a string", goals_("['1,1,1']")),
        ("a goal of two numbers", goals_("[[1, 1]]")),
        ("a goal of .nan", goals_("[[.nan, 1, 1]]")),
        ("a goal of 1e400", goals_("[[1e400, 1, 1]]")),
        ("a goal of 1_000", goals_("[[1_000, 1, 1]]")),
        ("a goal of yes", goals_("[[yes, 1, 1]]")),
        ("a goal of 0o17", goals_("[[0o17, 1, 1]]")),
        ("a goal with position and joints", goals_("[{position: [1, 1, 1], joints: [0, 0, 0]}]")),
        (
            "a goal with path and position",
            goals_("[{position: [1, 1, 1], path: {line: [[1, 0, 1], [1, 1, 1]]}, speed: 1}]"),
        ),
        ("joints of 1e300", goals_("[{joints: [1e300, 0, 0]}]")),
        ("joints of four values on three joints", goals_("[{joints: [0, 0, 0, 0]}]")),
        (
            "an orientation of rpy nan",
            goals_("[{position: [1, 1, 1], orientation: {rpy: [.nan, 0, 0]}}]"),
        ),
        (
            "an orientation quaternion of zeros",
            goals_("[{position: [1, 1, 1], orientation: {quaternion: [0, 0, 0, 0]}}]"),
        ),
        (
            "an orientation quaternion of 1e-300",
            goals_("[{position: [1, 1, 1], orientation: {quaternion: [1e-300, 0, 0, 0]}}]"),
        ),
        ("a tool_axis of zeros", goals_("[{position: [1, 1, 1], tool_axis: [0, 0, 0]}]")),
        ("a tool_axis of 1e-320", goals_("[{position: [1, 1, 1], tool_axis: [1e-320, 0, 0]}]")),
        ("a box of negative size", good + "obstacles: [{box: {center: [3, 3, 3], size: [-1, 1, 1]}}]\n"),
        (
            "a capsule of equal ends and radius 0",
            good + "obstacles: [{capsule: {from: [3, 3, 3], to: [3, 3, 3], radius: 0}}]\n",
        ),
        ("a cylinder of length 0", good + "obstacles: [{cylinder: {center: [3, 3, 3], length: 0, radius: 1}}]\n"),
        ("a sphere of radius .inf", good + "obstacles: [{center: [3, 3, 3], radius: .inf}]\n"),
        ("a sphere of influence -1", good + "obstacles: [{center: [3, 3, 3], radius: 1, influence: -1}]\n"),
        (
            "an obstacle named with a slash and a newline",
            good + 'obstacles: [{center: [3, 3, 3], radius: 1, name: "a/b\\nc"}]\n',
        ),
        (
            "10,000 obstacles",
            good
            + "obstacles:\n"
            + "".join(f"  - {{center: [{5 + i % 100}, {5 + i // 100}, 5], radius: 0.1}}\n" for i in range(10_000)),
        ),
        ("floor .nan", good + "floor: .nan\n"),
        ("floor a list", good + "floor: [0]\n"),
        ("arm.links []", good.replace("[1, 1, 1]}", "[]}")),
        ("arm.links of 0", good.replace("links: [1, 1, 1]", "links: [1, 0, 1]")),
        ("arm.links of -1", good.replace("links: [1, 1, 1]", "links: [1, -1, 1]")),
        (
            "arm.links of 200 values",
            good.replace("links: [1, 1, 1]", "links: [" + ",".join(["0.01"] * 200) + "]").replace(
                "[[1, 1, 1]]", "[[0.5, 0.5, 0.5]]"
            ),
        ),
        ("arm.axes [w]", arm_("axes: [w, y, y]")),
        ("arm.axes ['-z']", arm_("axes: ['-z', y, y]")),
        ("arm.direction q", arm_("direction: q")),
        ("arm.home of two values", arm_("home: [0, 0]")),
        (
            "arm.limits min over max",
            arm_("limits: [null, [90, -90], null]"),
        ),
        (
            "arm.limits of -1e400",
            arm_("limits: [null, [-1e400, 1], null]"),
        ),
        (
            "arm.limits a home outside them",
            arm_("limits: [null, [10, 20], null]"),
        ),
        ("arm.limit_margin 0", arm_("limit_margin: 0")),
        ("arm.width 0", arm_("width: 0")),
        ("arm.width 1e9", arm_("width: 1e9")),
        ("self_collision maybe", arm_("self_collision: maybe")),
        (
            "self_collision allow a pair of one link",
            arm_("self_collision: {auto: true, allow: [[link1, link1]]}"),
        ),
        (
            "self_collision allow an unknown link",
            good.replace(
                "links: [1, 1, 1]", "links: [1, 1, 1], self_collision: {auto: true, allow: [[link1, nosuch]]}"
            ),
        ),
        (
            "self_collision srdf a FIFO",
            arm_("self_collision: {srdf: f.srdf}"),
        ),
        (
            "self_collision srdf a folder",
            arm_("self_collision: {srdf: sub}"),
        ),
        ("solver.step 0", good + "solver: {step: 0}\n"),
        ("solver.step 1.5", good + "solver: {step: 1.5}\n"),
        ("solver.damping -1", good + "solver: {method: dls, damping: -1}\n"),
        ("solver.weights goal -1", good + "solver: {weights: {goal: -1}}\n"),
        ("solver.weights an unknown key", good + "solver: {weights: {mine: 1}}\n"),
        ("solver.planner maybe", good + "solver: {planner: maybe}\n"),
        ("solver.jacobian numeric with newton", good + "solver: {jacobian: numeric, method: newton}\n"),
        ("render.size [16.5, 9]", good + "render: {size: [16.5, 9]}\n"),
        ("render.size '640x360'", good + "render: {size: '640x360'}\n"),
        ("render.format avi", good + "render: {format: avi}\n"),
        ("render an unknown key", good + "render: {camera: 1}\n"),
        ("an unknown top-level key near a real one", good + "obstacle: []\n"),
    ]
    for label, text in yaml_cases:

        def setup(d: Path, text=text) -> None:
            write(d / "s.yaml", text)
            fifo(d / "f.srdf")
            (d / "sub").mkdir()

        out.append(
            Attempt(k, f"validate, {label}", ["validate", "s.yaml"], setup, (0, 2), timeout=120, message_if_2=AT_LINE)
        )
    # URDF
    joint = '<joint name="j{i}" type="{t}"><parent link="l{i}"/><child link="l{n}"/><origin xyz="0 0 0.3" rpy="{rpy}"/><axis xyz="{axis}"/>{limit}</joint>'

    def urdf_with(
        t="revolute",
        axis="0 1 0",
        rpy="0 0 0",
        limit='<limit lower="-2" upper="2" effort="1" velocity="1"/>',
        extra="",
        links=4,
        mimic="",
    ) -> str:
        lines = ['<?xml version="1.0"?>', '<robot name="r">']
        lines += [f'<link name="l{i}"/>' for i in range(links)]
        for i in range(links - 1):
            lines.append(
                joint.format(
                    i=i,
                    n=i + 1,
                    t=t if i == 1 else "revolute",
                    axis=axis if i == 1 else "0 0 1",
                    rpy=rpy if i == 1 else "0 0 0",
                    limit=limit if i == 1 else '<limit lower="-2" upper="2" effort="1" velocity="1"/>',
                ).replace("</joint>", (mimic if i == 1 else "") + "</joint>")
            )
        return "\n".join([*lines, extra, "</robot>"]) + "\n"

    urdf_cases = [
        ("a floating joint", urdf_with(t="floating")),
        ("a planar joint", urdf_with(t="planar")),
        ("a continuous joint with a limit", urdf_with(t="continuous")),
        (
            "a prismatic joint of limits 1e300",
            urdf_with(t="prismatic", limit='<limit lower="-1e300" upper="1e300" effort="1" velocity="1"/>'),
        ),
        ("a revolute joint without a limit", urdf_with(limit="")),
        (
            "a revolute joint with lower over upper",
            urdf_with(limit='<limit lower="2" upper="-2" effort="1" velocity="1"/>'),
        ),
        (
            "a revolute joint with limit 'nan'",
            urdf_with(limit='<limit lower="nan" upper="2" effort="1" velocity="1"/>'),
        ),
        ("a revolute joint with velocity 0", urdf_with(limit='<limit lower="-2" upper="2" effort="1" velocity="0"/>')),
        (
            "a revolute joint with velocity -1",
            urdf_with(limit='<limit lower="-2" upper="2" effort="1" velocity="-1"/>'),
        ),
        (
            "a revolute joint with velocity 1e-300",
            urdf_with(limit='<limit lower="-2" upper="2" effort="1" velocity="1e-300"/>'),
        ),
        ("an axis of zeros", urdf_with(axis="0 0 0")),
        ("an axis of 1e-300", urdf_with(axis="1e-300 0 0")),
        ("an axis of two numbers", urdf_with(axis="0 1")),
        ("an axis of words", urdf_with(axis="a b c")),
        ("an rpy of 1e400", urdf_with(rpy="1e400 0 0")),
        ("an rpy of ${pi}", urdf_with(rpy="${pi} 0 0")),
        ("a mimic joint on the chain", urdf_with(mimic='<mimic joint="j0" multiplier="2"/>')),
        ("a mimic of itself", urdf_with(mimic='<mimic joint="j1"/>')),
        ("a joint naming a missing child", urdf_with().replace('<child link="l2"/>', '<child link="nosuch"/>')),
        ("a joint without a parent", urdf_with().replace('<parent link="l1"/>', "")),
        ("two joints of one name", urdf_with().replace('name="j2"', 'name="j1"')),
        ("two links of one name", urdf_with().replace('<link name="l3"/>', '<link name="l2"/>')),
        ("a cycle", urdf_with(extra='<joint name="jc" type="fixed"><parent link="l3"/><child link="l0"/></joint>')),
        ("two roots", urdf_with(extra='<link name="x"/>')),
        ("300 joints", urdf_with(links=301)),
        (
            "a DTD with an entity",
            urdf_with().replace('<robot name="r">', '<!DOCTYPE robot [<!ENTITY e "l1">]><robot name="r">'),
        ),
        ("an external entity on /dev/zero in UTF-16", None),
        ("latin-1 declared with a non-ASCII name", None),
        ("no <robot> root", "<?xml version='1.0'?><robo/>\n"),
        ("a <robot> of nothing", "<?xml version='1.0'?><robot name='r'/>\n"),
    ]
    for label, text in urdf_cases:

        def setup(d: Path, text=text, label=label) -> None:
            if label.startswith("an external entity"):
                data = (
                    urdf_with()
                    .replace(
                        '<?xml version="1.0"?>',
                        '<?xml version="1.0" encoding="UTF-16"?><!DOCTYPE robot [<!ENTITY z SYSTEM "/dev/zero">]>',
                    )
                    .replace('<link name="l3"/>', '<link name="l3">&z;</link>')
                    .encode("utf-16")
                )
            elif label.startswith("latin-1"):
                data = (
                    urdf_with()
                    .replace('<?xml version="1.0"?>', '<?xml version="1.0" encoding="latin-1"?>')
                    .replace("l3", "l\xe93")
                    .encode("latin-1")
                )
            else:
                data = text.encode()
            write(d / "robot.urdf", data)
            write(d / "s.yaml", "version: 1\nname: m\narm: {urdf: robot.urdf}\ngoals: [[0.1, 0.1, 0.7]]\n")

        out.append(
            Attempt(
                k,
                f"validate, a URDF with {label}",
                ["validate", "s.yaml"],
                setup,
                (0, 2),
                timeout=120,
                message_if_2=AT_LINE,
            )
        )
    # SRDF
    srdf_cases = [
        (
            "disable_collisions of unknown links",
            '<robot name="r"><disable_collisions link1="nosuch" link2="l1" reason="Never"/></robot>',
        ),
        ("disable_collisions without link2", '<robot name="r"><disable_collisions link1="l1" reason="Never"/></robot>'),
        (
            "another robot's name",
            '<robot name="other"><disable_collisions link1="l1" link2="l2" reason="Never"/></robot>',
        ),
        ("a root not robot", "<srdf/>"),
        (
            "a DTD with an entity",
            '<!DOCTYPE robot [<!ENTITY e "l1">]><robot name="r"><disable_collisions link1="&e;" link2="l2"/></robot>',
        ),
        (
            "10,000 pairs",
            '<robot name="r">' + '<disable_collisions link1="l1" link2="l2" reason="Never"/>' * 10_000 + "</robot>",
        ),
        ("empty", ""),
        ("NUL bytes", "\0\0\0"),
    ]
    for label, text in srdf_cases:
        out.append(
            Attempt(
                k,
                f"validate, an SRDF with {label}",
                ["validate", "s.yaml"],
                lambda d, text=text: (
                    write(d / "robot.urdf", urdf_text()),
                    write(d / "r.srdf", text),
                    write(
                        d / "s.yaml",
                        URDF_SCENE.replace("{urdf: robot.urdf}", "{urdf: robot.urdf, self_collision: {srdf: r.srdf}}"),
                    ),
                ),
                (0, 2),
                timeout=120,
                message_if_2=AT_LINE,
            )
        )
    return out


def _segments(phi_deg, links: list[float]):
    """Joint positions of an arm of links along z, axes z then y (the scene's defaults), from
    its angles in degrees: (n_frames, links + 1, 3). An oracle written here, not armanim's."""
    import numpy as np

    phi = np.radians(np.asarray(phi_deg, dtype=float))
    n = len(phi)
    rot = np.tile(np.eye(3), (n, 1, 1))
    points = [np.zeros((n, 3))]
    for j, length in enumerate(links):
        c, s = np.cos(phi[:, j]), np.sin(phi[:, j])
        turn = np.zeros((n, 3, 3))
        if j == 0:
            turn[:, 0, 0], turn[:, 0, 1], turn[:, 1, 0], turn[:, 1, 1], turn[:, 2, 2] = c, -s, s, c, 1
        else:
            turn[:, 0, 0], turn[:, 0, 2], turn[:, 2, 0], turn[:, 2, 2], turn[:, 1, 1] = c, s, -s, c, 1
        rot = rot @ turn
        points.append(points[-1] + rot[:, :, 2] * length)
    return np.stack(points, axis=1)


def _sphere_clearance(points, spheres, half_width: float):
    """Each frame's least distance from the arm's capsules to the spheres' surfaces."""
    import numpy as np

    best = np.full(len(points), np.inf)
    for center, radius in spheres:
        c = np.asarray(center, dtype=float)
        for a, b in zip(points[:, :-1].transpose(1, 0, 2), points[:, 1:].transpose(1, 0, 2)):
            ab = b - a
            t = np.clip(((c - a) * ab).sum(1) / np.maximum((ab * ab).sum(1), 1e-300), 0, 1)
            gap = np.linalg.norm(a + t[:, None] * ab - c, axis=1) - radius - half_width
            best = np.minimum(best, gap)
    return best


def trajectory_breaks(spec: dict) -> Callable[[Path], list[str]]:
    """The invariants a finished run of ``spec`` (the scene as made) must keep, from its
    trajectory.csv and its export, checked with the oracle above."""

    def check(d: Path) -> list[str]:
        import csv as _csv
        import json as _json

        import numpy as np

        folder = d / "o" / spec["name"]
        if not (folder / "trajectory.csv").is_file():
            return ["no trajectory.csv"]
        with open(folder / "trajectory.csv", newline="") as handle:
            rows = list(_csv.DictReader(handle))
        n = len(spec["links"])
        t = np.array([float(r["time_s"]) for r in rows])
        phi = np.array([[float(r[f"phi{j + 1}_deg"]) for j in range(n)] for r in rows])
        dphi = np.array([[float(r[f"dphi{j + 1}_deg_s"]) for j in range(n)] for r in rows])
        csv_clear = np.array([float(r["clearance"]) if r["clearance"] not in ("", "inf") else np.inf for r in rows])
        problems = []
        dt = np.diff(t)
        if len(dt) and (dt <= 0).any():
            problems.append("time_s does not increase")
            return problems
        step = np.diff(phi, axis=0)
        unlimited = np.array([lim is None for lim in spec["limits"]])
        step[:, unlimited] = np.mod(step[:, unlimited] + 180.0, 360.0) - 180.0  # wrapped to (-180, 180] (documented)
        v = step / dt[:, None]
        vmax, amax = np.asarray(spec["speed"], float), np.asarray(spec["accel"], float)
        over = np.abs(v) / vmax
        if over.max(initial=0) > 1 + 1e-6:
            f, j = np.unravel_index(np.argmax(over), over.shape)
            problems.append(
                f"speed: joint {j + 1} at {v[f, j]:.6g} deg/s on frame {f + 1} ({over[f, j]:.4g}x its limit)"
            )
        if len(v) > 1:
            a = np.diff(v, axis=0) / dt[1:, None]
            over = np.abs(a) / amax
            if over.max(initial=0) > 1 + 1e-6:
                f, j = np.unravel_index(np.argmax(over), over.shape)
                problems.append(
                    f"acceleration: joint {j + 1} at {a[f, j]:.6g} deg/s^2 on frame {f + 2} ({over[f, j]:.4g}x)"
                )
            if spec.get("jerk") and len(a) > 1:
                jk = np.diff(a, axis=0) / dt[2:, None]
                ratio = np.abs(jk).max() / spec["jerk"]
                if ratio > 1 + 1e-6:
                    problems.append(f"jerk {ratio:.4g}x its limit")
        gap = np.abs(v - dphi[1:]) - amax / spec["fps"] * (1 + 1e-6) - 1e-6
        if gap.max(initial=-1) > 0:
            f, j = np.unravel_index(np.argmax(gap), gap.shape)
            problems.append(f"dphi{j + 1}_deg_s {dphi[f + 1, j]:.6g} on frame {f + 1}, the positions say {v[f, j]:.6g}")
        for j, lim in enumerate(spec["limits"]):
            if lim is not None and ((phi[:, j] < lim[0] - 1e-9) | (phi[:, j] > lim[1] + 1e-9)).any():
                problems.append(f"joint {j + 1} leaves its limits {lim}: {phi[:, j].min():.6g}..{phi[:, j].max():.6g}")
        if spec["spheres"]:
            mine = _sphere_clearance(_segments(phi, spec["links"]), spec["spheres"], spec["width"] / 2)
            if mine.min() < spec["clearance"] - 1e-6:
                f = int(np.argmin(mine))
                problems.append(
                    f"clearance {mine[f]:.6g} on frame {f} (solver.clearance {spec['clearance']}; the CSV says {csv_clear[f]:.6g})"
                )
            off = np.abs(mine - csv_clear)
            if off.max() > 1e-6:
                f = int(np.argmax(off))
                problems.append(f"the CSV's clearance {csv_clear[f]:.9g} on frame {f}, the oracle's {mine[f]:.9g}")
        summary = _json.loads((folder / "summary.json").read_text())
        tips = _segments(phi, spec["links"])[:, -1]
        for k, ((kind, goal), said) in enumerate(zip(spec["goals"], summary["goals"])):
            if not said["reached"] or kind not in ("point", "hold", "joints"):
                continue
            frame = said["last_frame"]
            if kind == "joints":
                off = np.abs(np.mod(phi[frame] - np.asarray(goal) + 180.0, 360.0) - 180.0).max()
                if off > 0.01 + 1e-9:
                    problems.append(f"goal {k} reported reached, its joints {off:.6g} deg from it at frame {frame}")
            elif np.linalg.norm(tips[frame] - np.asarray(goal)) > 0.01 + 1e-9:
                gap = np.linalg.norm(tips[frame] - np.asarray(goal))
                problems.append(f"goal {k} reported reached, the tip {gap:.6g} from it at frame {frame}")
        done = subprocess.run(
            [sys.executable, "-m", "armanim", "export", f"o/{spec['name']}", "--out", "e.json"],
            cwd=d,
            env=dict(os.environ, PYTHONPATH=str(SRC)),
            capture_output=True,
            text=True,
        )
        if done.returncode != 0:
            return [*problems, f"export: exit {done.returncode}: {done.stderr[-200:]}"]
        points = _json.loads((d / "e.json").read_text())["points"]
        pos = np.degrees(np.array([p["positions"] for p in points]))
        vel = np.degrees(np.array([p["velocities"] for p in points]))
        stamps = np.array([p["time_from_start"]["sec"] + p["time_from_start"]["nanosec"] * 1e-9 for p in points])
        if pos.shape != phi.shape:
            return [*problems, "the export has not the CSV's frames"]
        off = pos - phi
        off[:, unlimited] = np.mod(off[:, unlimited] + 180.0, 360.0) - 180.0  # the same pose
        if np.abs(off).max() > 1e-9 or np.abs(vel - dphi).max() > 1e-9 or np.abs(stamps - t).max() > 1e-6:
            problems.append("the export's poses, velocities or times differ from trajectory.csv")
        told = np.abs(np.diff(pos, axis=0) / dt[:, None] - vel[1:]) - amax / spec["fps"] * (1 + 1e-6) - 1e-6
        if told.max(initial=-1) > 0:  # a controller reads the positions as they are: no wrap allowed there
            f, j = np.unravel_index(np.argmax(told), told.shape)
            problems.append(
                f"the export's joint {j + 1} moves {pos[f + 1, j] - pos[f, j]:.6g} deg at frame {f + 1}, its velocity says {vel[f + 1, j]:.6g} deg/s"
            )
        return problems

    return check


WRONG10_KINDS = ("point", "point", "joints", "hold", "blend", "line")
WRONG11_KINDS = ("point", "joints", "hold", "blend", "line", "arc", "polyline")


def wrong_scene(seed: int, goal_kinds: tuple[str, ...] = WRONG10_KINDS) -> tuple[str, dict]:
    """A random scene of a 3- or 4-link arm among spheres, with limits, rates and goals of
    ``goal_kinds``, made to pass validation (obstacles away from the goals, paths, home and joint
    poses); its spec."""
    import numpy as np

    rng = np.random.default_rng(1000 + seed)
    n = int(rng.integers(3, 5))
    links = [round(float(x), 2) for x in rng.uniform(0.6, 1.2, n)]
    reach = sum(links[1:])
    fps = float(rng.choice([5, 10, 24, 30, 60, 90]))
    speed = [round(float(x), 1) for x in rng.uniform(20, 150, n)]
    accel = [round(float(x), 1) for x in rng.uniform(40, 600, n)]
    jerk = float(rng.choice([0, 0, 2000, 20000]))
    limits = [None] + [[-round(float(x), 1), round(float(y), 1)] for x, y in rng.uniform(60, 170, (n - 1, 2))]
    width = round(float(rng.uniform(0.1, 0.4)), 2)
    clearance = round(float(rng.uniform(0.02, 0.1)), 3)
    method = str(rng.choice(["pinv", "dls", "newton", "gradient"]))
    goals, points, poses, kinds = [], [], [[0.0] * n], []
    for _ in range(int(rng.integers(2, 6))):
        kind = rng.choice(list(goal_kinds))
        if kind in ("joints", "edge"):  # edge: each limited joint a hundredth of a degree inside a limit
            pose = [round(float(rng.uniform(-150, 150)), 1)] + [
                round(float(rng.uniform(lo * 0.8, hi * 0.8)), 1)
                if kind == "joints"
                else round(float(rng.choice([lo + 0.01, hi - 0.01])), 2)
                for lo, hi in limits[1:]
            ]
            goals.append(f"{{joints: {pose}}}")
            poses.append(pose)
            kinds.append(("joints", pose))
            continue
        r = rng.uniform(0.3, 0.85) * reach
        az, el = rng.uniform(-np.pi, np.pi), rng.uniform(-0.3, 1.2)
        p = [
            round(float(v), 3)
            for v in (r * np.cos(el) * np.cos(az), r * np.cos(el) * np.sin(az), links[0] + r * np.sin(el))
        ]
        points.append(p)
        kinds.append((str(kind), p))
        if kind == "line":
            q = [round(p[0] + 0.2, 3), round(p[1] - 0.2, 3), p[2]]
            points.append(q)
            goals.append(f"{{path: {{line: [{p}, {q}]}}, speed: {round(float(rng.uniform(0.1, 0.6)), 2)}}}")
        elif kind == "arc":  # a quarter turn of radius 0.15 about p, from p + 0.15 x
            turn = [
                [round(p[0] + 0.15 * float(np.cos(a)), 3), round(p[1] + 0.15 * float(np.sin(a)), 3), p[2]]
                for a in np.linspace(0, np.pi / 2, 7)
            ]
            points += turn
            goals.append(
                f"{{path: {{arc: {{center: {p}, start: {turn[0]}, angle: 90, normal: [0, 0, 1]}}}}, speed: {round(float(rng.uniform(0.1, 0.6)), 2)}}}"
            )
        elif kind == "polyline":
            corners = [
                p,
                [round(p[0] + 0.2, 3), p[1], p[2]],
                [round(p[0] + 0.2, 3), round(p[1] + 0.2, 3), round(p[2] + 0.1, 3)],
            ]
            points += corners[1:]
            goals.append(f"{{path: {{polyline: {corners}}}, speed: {round(float(rng.uniform(0.1, 0.6)), 2)}}}")
        elif kind == "text":  # two letters 0.1 high from p, written along y: their box's corners kept clear
            points += [[p[0], round(p[1] + dy, 3), round(p[2] + dz, 3)] for dy in (0.1, 0.2) for dz in (0, 0.1)]
            goals.append(
                f"{{path: {{text: {{string: {str(rng.choice(['ab', 'IK', 'oz']))!r}, origin: {p}, height: 0.1, "
                f"right: [0, 1, 0], up: [0, 0, 1]}}}}, speed: {round(float(rng.uniform(0.1, 0.6)), 2)}}}"
            )
        elif kind == "hold":
            goals.append(f"{{position: {p}, hold: {round(float(rng.uniform(0.1, 1)), 2)}}}")
        elif kind == "blend":
            goals.append(f"{{position: {p}, blend: {round(float(rng.uniform(0.05, 0.3)), 2)}}}")
        else:
            goals.append(f"{p}")
    spheres = []
    pose_points = _segments(np.array(poses), links)
    for _ in range(int(rng.integers(1, 5))):
        c = [float(x) for x in rng.uniform(-reach, reach, 3)]
        c[2] = abs(c[2]) + 0.3
        radius = round(float(rng.uniform(0.1, 0.35)), 2)
        c = [round(x, 2) for x in c]
        far_goals = all(np.linalg.norm(np.subtract(c, p)) > radius + width + 3 * clearance + 0.15 for p in points)
        far_poses = _sphere_clearance(pose_points, [(c, radius)], width / 2).min() > clearance + 0.1
        if far_goals and far_poses:
            spheres.append((c, radius))
    obstacles = "".join(f"  - {{center: {c}, radius: {r}}}\n" for c, r in spheres)
    name = f"w{seed}"
    text = (
        f"version: 1\nname: {name}\narm:\n  links: {links}\n  limits: {limits}\n  width: {width}\n"
        f"  max_joint_speed: {speed}\n  max_joint_acceleration: {accel}\n"
        + (f"  max_joint_jerk: {jerk:g}\n" if jerk else "")
        + (f"obstacles:\n{obstacles}" if obstacles else "")
        + "goals:\n"
        + "".join(f"  - {g}\n" for g in goals)
        + f"solver: {{method: {method}, clearance: {clearance}, max_frames_per_goal: 300, tolerance: 0.01}}\n"
        + f"render: {{size: [160, 90], fps: {fps:g}}}\n"
    ).replace("None", "null")
    spec = {
        "name": name,
        "links": links,
        "fps": fps,
        "speed": speed,
        "accel": accel,
        "jerk": jerk,
        "limits": limits,
        "width": width,
        "clearance": clearance,
        "spheres": spheres,
        "goals": kinds,
    }
    return text, spec


def random_arm_runs(k: str, seeds, what: str = "", goal_kinds: tuple[str, ...] = WRONG10_KINDS) -> list[Attempt]:
    """A run of :func:`wrong_scene` of each seed, held to :func:`trajectory_breaks`."""
    return [
        Attempt(
            k,
            f"run a random arm among spheres{what} (seed {seed}), held to the invariants",
            ["run", "s.yaml", "--out", "o", "--no-video", "-q"],
            tiny_scene(text=text),
            (0,),
            timeout=400,
            after=trajectory_breaks(spec),
        )
        for seed in seeds
        for text, spec in [wrong_scene(seed, goal_kinds)]
    ]


def wrong10_attempts() -> list[Attempt]:
    """Runs that say they succeeded, held to the invariants by an oracle of their own (speed,
    acceleration, jerk, the velocity columns, limits, sphere clearance, the export)."""
    k = "wrong10"
    out = random_arm_runs(k, range(72))
    for scene in ("notes-arm", "out-of-reach"):
        out.append(
            Attempt(
                k,
                f"check --update then check of {scene} with two rows of its CSV swapped in between",
                ["check", f"{scene}.yaml", "--golden", "g"],
                lambda d, scene=scene: (
                    shutil.copy(SCENES / f"{scene}.yaml", d / f"{scene}.yaml"),
                    armanim_in(d, "check", f"{scene}.yaml", "--golden", "g", "--update"),
                    _swap_two_rows(d / "g" / f"{scene}.csv"),
                ),
                (1,),
                timeout=400,
                message="differ|difference",
            )
        )
    return out


# ------------------------------------------------------------------ the eleventh campaign


def fit_and_png(
    k: str,
    label: str,
    name: str,
    files: dict,
    codes_fit=(0, 2),
    codes_png=(0,),
    timeout: float = 120.0,
    scale: str = "",
    extra: Callable[[Path], None] | None = None,
) -> list[Attempt]:
    """A mesh named ``name`` (``files`` beside the URDF, see :func:`urdf_robot`) as link l1's collision
    mesh through ``robots --fit`` and as its visual through ``fk --png``; ``extra(d)`` after the setup."""
    tag = f"<geometry><mesh filename={name!r}{f' scale={scale!r}' if scale else ''}/></geometry>"

    def made(setup: Callable[[Path], None]) -> Callable[[Path], None]:
        return setup if extra is None else lambda d: (setup(d), extra(d)) and None

    return [
        Attempt(
            k,
            f"robots --fit, collision {label}",
            FIT,
            made(urdf_robot(collision=f"<collision>{tag}</collision>", files=files)),
            codes_fit,
            timeout=timeout,
            message_if_2=r"robot\.urdf:\d+: ",
        ),
        Attempt(
            k,
            f"fk --png, visual {label}",
            FK_PNG,
            made(urdf_robot(f"<visual>{tag}</visual>", files=files)),
            codes_png,
            timeout=timeout,
        ),
    ]


def ascii_stl(corners: list[list[float]], keywords: tuple[str, str, str] = ("solid", "vertex", "endsolid")) -> str:
    solid, vertex, end = keywords
    return f"{solid} s\n" + "".join(f"{vertex} {x} {y} {z}\n" for x, y, z in corners) + f"{end}\n"


COLLADA_UNITS = (
    '<unit meter="1e-6"/>',
    '<unit meter="9.9e-7"/>',
    '<unit meter="1000"/>',
    '<unit meter="1000.001"/>',
    '<unit meter="0"/>',
    '<unit meter="-1"/>',
    '<unit meter="1"/><unit meter="0.001"/>',
    '<unit meter="1"/><up_axis>X_UP</up_axis>',
)
"""COLLADA units at and past their bounds (1e-6 to 1000 metres), and two odd ones."""


def mesh11_attempts() -> list[Attempt]:
    """Mesh files at edges campaign 10 did not reach: binary STLs whose count lies, ASCII STLs in
    other spellings, OBJ's relative indices, polygons and line elements, COLLADA's cycles, external
    references, units at their bounds and other primitives, names that are URLs, devices and /proc
    files through links, the byte and triangle bounds to the byte and the triangle."""
    k = "mesh11"
    out: list[Attempt] = []
    tri = [[0, 0, 0], [0.05, 0, 0], [0, 0.05, 0]]
    one = stl_corners([tri])
    # fmt: off
    cases: list[tuple[str, str, dict]] = [
        ("a binary STL whose count says 1,000 for one triangle", "a.stl", {"a.stl": one[:80] + (1000).to_bytes(4, "little") + one[84:]}),
        ("a binary STL whose count says 0 over one triangle", "a.stl", {"a.stl": one[:80] + b"\0\0\0\0" + one[84:]}),
        ("a binary STL whose count is 2^32-1", "a.stl", {"a.stl": one[:80] + b"\xff\xff\xff\xff" + one[84:]}),
        ("a binary STL of 84 bytes (count 0, no triangle)", "a.stl", {"a.stl": b"\0" * 84}),
        ("a binary STL of 83 bytes", "a.stl", {"a.stl": b"\0" * 83}),
        ("a binary STL whose header starts 'solid'", "a.stl", {"a.stl": b"solid binary" + one[12:]}),
        ("a binary STL with 7 bytes after its triangles", "a.stl", {"a.stl": one + b"garbage"}),
        ("a binary STL of a NaN corner (float32)", "a.stl", {"a.stl": stl_corners([[[float("nan"), 0, 0], [0, 0.05, 0], [0, 0, 0.05]]])}),
        ("a binary STL of an infinite corner (float32)", "a.stl", {"a.stl": stl_corners([[[float("inf"), 0, 0], [0, 0.05, 0], [0, 0, 0.05]]])}),
        ("a binary STL of subnormal corners", "a.stl", {"a.stl": stl_corners([[[1e-45, 0, 0], [0, 1e-45, 0], [0, 0, 1e-45]]])}),
        ("an empty STL (0 bytes)", "a.stl", {"a.stl": b""}),
        ("an STL named .STL", "a.STL", {"a.STL": one}),
        ("an STL named .Stl.stl", "a.Stl.stl", {"a.Stl.stl": one}),
        ("an ASCII STL in capitals", "a.stl", {"a.stl": ascii_stl(tri, ("SOLID", "VERTEX", "ENDSOLID"))}),
        ("an ASCII STL with tabs and CRLF", "a.stl", {"a.stl": ascii_stl(tri).replace(" ", "\t").replace("\n", "\r\n")}),
        ("an ASCII STL of decimal commas", "a.stl", {"a.stl": "solid s\nvertex 0,5 0 0\nvertex 0 0,5 0\nvertex 0 0 0,5\nendsolid\n"}),
        ("an ASCII STL of four corners (a triangle and one left)", "a.stl", {"a.stl": ascii_stl([*tri, [1, 1, 1]])}),
        ("an ASCII STL of hex floats", "a.stl", {"a.stl": "solid s\nvertex 0x1p-4 0 0\nvertex 0 0x1p-4 0\nvertex 0 0 0x1p-4\nendsolid\n"}),
        ("an ASCII STL with a UTF-8 BOM", "a.stl", {"a.stl": "\ufeff" + ascii_stl(tri)}),
        ("an ASCII STL with a NUL in a number", "a.stl", {"a.stl": ascii_stl(tri).replace("0.05", "0.0\x005", 1)}),
        ("an ASCII STL of 'facet' lines without vertices", "a.stl", {"a.stl": "solid s\n" + "facet normal 0 0 1\nouter loop\nendloop\nendfacet\n" * 100 + "endsolid\n"}),
        ("an ASCII STL of one 10 MB line", "a.stl", {"a.stl": "solid " + "x" * 10_000_000 + "\nendsolid\n"}),
        ("an OBJ of relative (negative) indices", "a.obj", {"a.obj": obj_text(3).replace("f 1 2 3", "f -3 -2 -1")}),
        ("an OBJ face index -4 of three vertices", "a.obj", {"a.obj": obj_text(3).replace("f 1 2 3", "f -4 -2 -1")}),
        ("an OBJ face of 1,000 corners", "a.obj", {"a.obj": obj_text(1000).replace("f 1 2 3", "f " + " ".join(map(str, range(1, 1001))))}),
        ("an OBJ of four-number vertices (w)", "a.obj", {"a.obj": "v 0 0 0 1\nv 0.05 0 0 1\nv 0 0.05 0 1\nf 1 2 3\n"}),
        ("an OBJ of six-number vertices (colours)", "a.obj", {"a.obj": "v 0 0 0 1 0 0\nv 0.05 0 0 0 1 0\nv 0 0.05 0 0 0 1\nf 1 2 3\n"}),
        ("an OBJ of 'l' and 'p' elements only", "a.obj", {"a.obj": obj_text(3).replace("f 1 2 3", "l 1 2 3\np 1")}),
        ("an OBJ face before its vertices", "a.obj", {"a.obj": "f 1 2 3\nv 0 0 0\nv 0.05 0 0\nv 0 0.05 0\n"}),
        ("an OBJ face index 1.5", "a.obj", {"a.obj": obj_text(3).replace("f 1 2 3", "f 1.5 2 3")}),
        ("an OBJ of backslash line continuations", "a.obj", {"a.obj": "v 0 0 \\\n0\nv 0.05 0 0\nv 0 0.05 0\nf 1 2 \\\n3\n"}),
        ("an OBJ with a BOM and latin-1 in a comment", "a.obj", {"a.obj": b"\xef\xbb\xbf# caf\xe9\n" + obj_text(3).encode()}),
        ("an OBJ of NUL bytes between lines", "a.obj", {"a.obj": obj_text(3).replace("\n", "\n\0")}),
        ("an OBJ of 'vt' and 'vn' only", "a.obj", {"a.obj": "vt 0 0\nvn 0 0 1\nf 1/1/1 1/1/1 1/1/1\n"}),
        ("an OBJ usemtl of a material no file defines", "a.obj", {"a.obj": "usemtl steel\n" + obj_text(3)}),
        ("an OBJ mtllib of ../../etc/passwd", "a.obj", {"a.obj": "mtllib ../../../../etc/passwd\n" + obj_text(3)}),
        ("an OBJ mtllib of 300 names", "a.obj", {"a.obj": "mtllib " + " ".join(f"m{i}.mtl" for i in range(300)) + "\n" + obj_text(3)}),
        ("an OBJ of 'o', 'g' and 's' lines between faces", "a.obj", {"a.obj": "o a\ng b c\ns 1\n" + obj_text(3) + "s off\ng\n"}),
        ("an OBJ of 1e-300 corners", "a.obj", {"a.obj": "v 1e-300 0 0\nv 0 1e-300 0\nv 0 0 1e-300\nf 1 2 3\n"}),
        ("an OBJ of exactly 2,000,000 triangles", "a.obj", {"a.obj": obj_text(3) + "f 1 2 3\n" * 1_999_999}),
        ("an OBJ of 2,000,001 triangles", "a.obj", {"a.obj": obj_text(3) + "f 1 2 3\n" * 2_000_000}),
        ("a COLLADA node that instances itself", "a.dae", {"a.dae": tri_dae(node='<instance_node url="#n0"/>')}),
        ("a COLLADA pair of nodes instancing each other", "a.dae", { "a.dae": tri_dae() .replace("<library_visual_scenes>", '<library_nodes><node id="x"><instance_node url="#y"/></node><node id="y"><instance_node url="#x"/></node></library_nodes><library_visual_scenes>',) .replace('<instance_geometry url="#g0"/></node>', '<instance_geometry url="#g0"/><instance_node url="#x"/></node>',) }),
        ("a COLLADA instance_node of another file", "a.dae", {"a.dae": tri_dae(node='<instance_node url="other.dae#n0"/>'), "other.dae": None}),
        ("a COLLADA instance_geometry of a missing id", "a.dae", {"a.dae": tri_dae().replace('url="#g0"', 'url="#nosuch"')}),
        ("a COLLADA image init_from a FIFO", "a.dae", { "a.dae": tri_dae().replace("<library_geometries>", '<library_images><image id="i"><init_from>t.png</init_from></image></library_images><library_geometries>',), "t.png": None, }),
        ("a COLLADA XInclude of /etc/passwd", "a.dae", { "a.dae": tri_dae().replace("<asset>", '<asset><xi:include xmlns:xi="http://www.w3.org/2001/XInclude" href="/etc/passwd" parse="text"/>',) }),
        *((f"a COLLADA unit of {unit}", "a.dae", {"a.dae": tri_dae().replace('<unit meter="1"/>', unit)}) for unit in COLLADA_UNITS),
        *((f"a COLLADA of {kind}", "a.dae", {"a.dae": tri_dae().replace("triangles", kind)}) for kind in ("tristrips", "trifans")),
        ("a COLLADA of polygons with a hole", "a.dae", { "a.dae": tri_dae() .replace("<triangles", "<polygons") .replace("</triangles>", "</polygons>") .replace("<p>0 1 2</p>", "<ph><p>0 1 2</p><h>0 1 2</h></ph>") }),
        ("a COLLADA float_array count 10^9", "a.dae", {"a.dae": tri_dae().replace('count="9"', 'count="1000000000"')}),
        ("a COLLADA accessor stride 0", "a.dae", {"a.dae": tri_dae().replace('stride="3"', 'stride="0"')}),
        ("a COLLADA accessor stride 10^9", "a.dae", {"a.dae": tri_dae().replace('stride="3"', 'stride="1000000000"')}),
        ("a COLLADA of a singular node matrix", "a.dae", {"a.dae": tri_dae(node="<matrix>" + "0 " * 15 + "1</matrix>")}),
        ("a COLLADA of a lookat and a skew", "a.dae", {"a.dae": tri_dae(node="<lookat>0 0 0 0 0 0 0 0 0</lookat><skew>1e308 1 0 0 0 1 0</skew>")}),
        ("a COLLADA of two geometries of one id", "a.dae", { "a.dae": tri_dae().replace("</library_geometries>", tri_dae()[tri_dae().index('<geometry id="g0">') : tri_dae().index("</library_geometries>")] + "</library_geometries>",) }),
        ("a COLLADA without a scene", "a.dae", {"a.dae": tri_dae()[: tri_dae().index("<scene>")] + "</COLLADA>"}),
        ("a COLLADA gzip-compressed", "a.dae", {"a.dae": __import__("gzip").compress(tri_dae().encode())}),
        ("a COLLADA of 100,000 elements (its bound)", "a.dae", {"a.dae": tri_dae().replace("<asset>", "<asset>" + "<keywords/>" * 99_960)}),
        ("a COLLADA of 100,001 elements", "a.dae", {"a.dae": tri_dae().replace("<asset>", "<asset>" + "<keywords/>" * 100_001)}),
        ("a COLLADA declared EBCDIC (cp500)", "a.dae", { "a.dae": tri_dae() .replace('<?xml version="1.0"?>', '<?xml version="1.0" encoding="cp500"?>') .encode("cp500") }),
        ("a COLLADA of 1,000 nested nodes", "a.dae", {"a.dae": tri_dae(node='<node id="z">' * 1000 + "</node>" * 1000)}),
        ("named http://example.invalid/a.stl", "http://example.invalid/a.stl", {}),
        ("named model://a/a.stl", "model://a/a.stl", {}),
        ("named file:a.stl (no slashes)", "file:a.stl", {"a.stl": one}),
        ("named package://r/../../../../etc/a.stl", "package://r/../../../../etc/a.stl", {}),
        ("named package:///a.stl (an empty package)", "package:///a.stl", {"a.stl": one}),
        ("named ~/a.stl", "~/a.stl", {}),
        ("named C:\\meshes\\a.stl", "C:\\meshes\\a.stl", {}),
        ("named with a trailing space", "a.stl ", {"a.stl": one}),
        ("named %2e%2e/a.stl", "%2e%2e/a.stl", {}),
        ("a link to /dev/urandom named .stl", "z.stl", {"z.stl": ("->", "/dev/urandom")}),
        ("a link to /proc/self/status named .obj", "p.obj", {"p.obj": ("->", "/proc/self/status")}),
        ("a link to /proc/self/mounts named .dae", "p.dae", {"p.dae": ("->", "/proc/self/mounts")}),
        ("a link to /dev/stdin named .stl", "z.stl", {"z.stl": ("->", "/dev/stdin")}),
        ("a dangling link", "z.stl", {"z.stl": ("->", "nowhere/z.stl")}),
        ("a link to a folder", "z.stl", {"z.stl": ("->", ".")}),
        ("a link to the URDF itself named .obj", "z.obj", {"z.obj": ("->", "robot.urdf")}),
        ("a file of 64 MB exactly (sparse)", "z.stl", {}),
        ("a file of 64 MB and one byte (sparse)", "y.stl", {}),
    ]
    # fmt: on

    def sized(d: Path) -> None:
        if (d / "robot.urdf").read_text().find("z.stl") >= 0 and not os.path.lexists(d / "z.stl"):
            sparse(d / "z.stl", 64 * 2**20)
        if "y.stl" in (d / "robot.urdf").read_text():
            sparse(d / "y.stl", 64 * 2**20 + 1)

    for label, name, files in cases:
        slow = "2,000,00" in label or "100,00" in label or "10 MB" in label
        out += fit_and_png(k, label, name, files, timeout=240 if slow else 120, extra=sized)
    for label, scale in (
        ("1e9 1e9 1e9 (its bound)", "1e9 1e9 1e9"),
        ("1.0000001e9", "1.0000001e9 1 1"),
        ("1e-9", "1e-9 1e-9 1e-9"),
        ("0 1 1 (flat)", "0 1 1"),
        ("'1,1,1'", "1,1,1"),
        ("of four numbers", "1 1 1 1"),
    ):
        out += fit_and_png(k, f"a scale of {label}", "a.stl", {"a.stl": one}, scale=scale)
    # the tool's mesh and the look of a run: through run --viewer, render and view
    for label, files in [
        ("a binary STL whose count says 1,000", {"t.stl": one[:80] + (1000).to_bytes(4, "little") + one[84:]}),
        ("a link to /dev/urandom", {"t.stl": ("->", "/dev/urandom")}),
        ("a COLLADA node that instances itself", {"t.dae": tri_dae(node='<instance_node url="#n0"/>')}),
        ("an OBJ of relative indices", {"t.obj": obj_text(3).replace("f 1 2 3", "f -3 -2 -1")}),
    ]:
        (tool,) = files

        def setup(d: Path, files=files, tool=tool) -> None:
            write(d / "s.yaml", TOOL_SCENE.replace("TOOL", tool))
            urdf_robot(files=files)(d)
            write(d / "s.yaml", TOOL_SCENE.replace("TOOL", tool))

        out.append(
            Attempt(
                k,
                f"run --viewer, tool mesh {label}",
                ["run", "s.yaml", "--out", "o", "--no-video", "--viewer", "-q"],
                setup,
                (0, 2),
                timeout=240,
                message_if_2=AT_LINE,
            )
        )

    def moved_meshes(d: Path) -> None:
        write(d / "m/a.stl", one)
        write(d / "m/robot.urdf", urdf_text(vis("a.stl")))
        write(d / "s.yaml", URDF_SCENE.replace("robot.urdf", "m/robot.urdf"))
        armanim_in(d, "run", "s.yaml", "--out", "o", "--no-video", "-q")
        os.unlink(d / "m/a.stl")
        os.symlink("/dev/urandom", d / "m/a.stl")

    for cmd in (["render", "o/m", "-q", "--size", "64x48"], ["view", "o/m", "--out", "v.html"]):
        out.append(
            Attempt(
                k,
                f"{cmd[0]} of a run whose visual mesh is now a link to /dev/urandom",
                cmd,
                moved_meshes,
                (0,),
                timeout=240,
            )
        )
    return out


def render_flags_attempt(k: str, flags: list[str]) -> Attempt:
    """``render`` of a finished tiny run with ``flags``: exit 0, or 2 naming the flag."""
    return Attempt(
        k,
        f"render {' '.join(flags)}",
        ["render", "o/tiny", "-q", *flags],
        lambda d: finished_run(d) and None,
        (0, 2),
        timeout=300,
        message_if_2="--size|--fps|--format|--quality|--elevation|--azimuth",
    )


def frames11_attempts() -> list[Attempt]:
    """Frame and size bounds by the commands and flags campaign 10 did not take there: render
    sizes at the encoder's edges (odd, tiny, wide), cameras straight down, fk/ik at their bounds,
    sweeps at the variant limit, and scenes at each documented bound and just past it."""
    k = "frames11"
    out: list[Attempt] = []
    for flags in (
        ["--size", "17x9"],
        ["--size", "2x2"],
        ["--size", "3x1001"],
        ["--size", "4096x16"],
        ["--size", "64x48", "--format", "gif", "--fps", "100"],
        ["--size", "64x48", "--format", "gif", "--fps", "0.5"],
        ["--size", "64x48", "--elevation", "90"],
        ["--size", "64x48", "--elevation", "-90", "--azimuth", "720"],
        ["--size", "64x48", "--elevation", "1e-300"],
        ["--size", "64x48", "--fps", "1e9"],
        ["--size", "64x48", "--fps", "0.0001"],
        ["--size", "+64x+48"],
        ["--size", "64x48 "],
        ["--size", "６４x48"],
        ["--size", "0x48"],
        ["--size", "64x48", "--quality", "low"],
    ):
        out.append(render_flags_attempt(k, flags))
    run = ["run", "s.yaml", "--out", "o", "--no-video", "-q"]
    # fmt: off
    cases = [
        ("a coordinate of 1e9 (its bound)", simple("goals: [[1, 1, 1]]\nobstacles: [{center: [1e9, 0, 0], radius: 1}]")),
        ("a coordinate of 1.000001e9", simple("goals: [[1, 1, 1]]\nobstacles: [{center: [1.000001e9, 0, 0], radius: 1}]")),
        ("a link of 1e-9 (its floor?)", simple().replace("links: [1, 1, 1]", "links: [1, 1, 1, 1e-9]")),
        ("a hold of 3600 s (its bound) at 10 fps", simple("goals: [{position: [1, 1, 1], hold: 3600}]")),
        ("a hold of 3600.0001 s", simple("goals: [{position: [1, 1, 1], hold: 3600.0001}]")),
        ("render.fps 1e-9", simple(fps="1e-9")),
        ("render.fps 1000", simple(fps="1000")),
        ("render.size [16, 16]", simple().replace("size: [160, 90]", "size: [16, 16]")),
        ("render.size [7680, 4320]", simple().replace("size: [160, 90]", "size: [7680, 4320]")),
        ("render.size [7681, 4320]", simple().replace("size: [160, 90]", "size: [7681, 4320]")),
        ("render.size [1, 100000]", simple().replace("size: [160, 90]", "size: [1, 100000]")),
        ("an arc of 360 degrees (its bound)", simple("goals: [{path: {arc: {center: [1, 0, 1], start: [1, 0.3, 1], angle: 360, normal: [1, 0, 0]}}, speed: 0.5}]")),
        ("an arc of 360.0001 degrees", simple("goals: [{path: {arc: {center: [1, 0, 1], start: [1, 0.3, 1], angle: 360.0001, normal: [1, 0, 0]}}, speed: 0.5}]")),
        ("an arc of -360 degrees", simple("goals: [{path: {arc: {center: [1, 0, 1], start: [1, 0.3, 1], angle: -360, normal: [1, 0, 0]}}, speed: 0.5}]")),
        ("a path speed of 1e-9 (its floor)", simple("goals: [{path: {line: [[1, 0.5, 1], [1, 0.5, 1.000000001]]}, speed: 1e-9}]")),
        ("a path speed of 1e9 (its bound) on a 1e-9 line", simple("goals: [{path: {line: [[1, 0.5, 1], [1, 0.5, 1.000000001]]}, speed: 1e9}]")),
        ("a text path of a tab, a newline and an emoji", simple('goals: [{path: {text: {string: "a\\tb\\nc\U0001f600", origin: [1, -0.5, 1], height: 0.05, right: [0, 1, 0], up: [0, 0, 1]}}, speed: 0.5}]')),
        ("a text path of combining accents only", simple('goals: [{path: {text: {string: "\\u0301\\u0301\\u0301", origin: [1, -0.5, 1], height: 0.05, right: [0, 1, 0], up: [0, 0, 1]}}, speed: 0.5}]')),
        ("a text path of height 1e9", simple('goals: [{path: {text: {string: "a", origin: [1, -0.5, 1], height: 1e9, right: [0, 1, 0], up: [0, 0, 1]}}, speed: 0.5}]')),
        ("64 links (the joint bound?)", simple("goals: [[0.5, 0.5, 0.5]]").replace("links: [1, 1, 1]", "links: [" + ",".join(["0.02"] * 64) + "]")),
        ("65 links", simple("goals: [[0.5, 0.5, 0.5]]").replace("links: [1, 1, 1]", "links: [" + ",".join(["0.02"] * 65) + "]")),
        ("max_joint_speed 1e9 with acceleration 1e-6", simple(arm=", max_joint_speed: 1e9, max_joint_acceleration: 1e-6")),
        ("max_joint_jerk 1e15 (a large jerk)", simple(arm=", max_joint_jerk: 1e15")),
        ("solver.clearance 1e9", simple("goals: [[1, 1, 1]]\nobstacles: [{center: [3, 3, 3], radius: 0.1}]", solver="clearance: 1e9")),
        ("a sphere of radius 1e-9", simple("goals: [[1, 1, 1]]\nobstacles: [{center: [3, 3, 3], radius: 1e-9}]")),
        ("1,000 goals of joints, each a hold", "version: 1\nname: f\narm: {links: [1, 1, 1]}\ngoals:\n" + "".join(f"  - {{joints: [{i % 7}, 0, 0], hold: 0.1}}\n" for i in range(1000)) + "render: {size: [160, 90], fps: 10}\n"),
    ]
    # fmt: on
    for label, text in cases:
        out.append(
            Attempt(
                k,
                f"validate {label}",
                ["validate", "s.yaml"],
                tiny_scene(text=text),
                (0, 2),
                timeout=120,
                message_if_2=AT_LINE,
            )
        )
        out.append(Attempt(k, f"run {label}", run, tiny_scene(text=text), (0, 2), timeout=400, message_if_2=AT_LINE))
    for args in (
        ["fk", "--links", "1", "--angles", "45"],
        ["fk", "--links", ",".join(["0.1"] * 64), "--angles", ",".join(["1"] * 64), "--png", "p.png"],
        ["fk", "--links", ",".join(["0.1"] * 1000), "--angles", ",".join(["1"] * 1000)],
        ["fk", "--angles", "1e-320,0,0,0", "--png", "p.png"],
        ["fk", "--angles", "359.9999999999,0,0,0", "--radians"],
        ["fk", "--robot", "panda", "--angles", "1e9,0,0,0,0,0,0"],
        ["ik", "--goal", "0,0,4"],
        ["ik", "--goal", "0,0,4.000000001"],
        ["ik", "--goal", "0,0,0", "--method", "newton"],
        ["ik", "--goal", "1,1,1", "--max-iterations", "1"],
        ["ik", "--goal", "1,1,1", "--from", "1e-300,0,0,0", "--method", "gradient"],
        ["ik", "--robot", "ur5", "--goal", "0.3,0.2,0.4", "--orientation", "quat=1e-300,0,0,1e-300"],
        [
            "ik",
            "--robot",
            "panda",
            "--goal",
            "0.5,0,0.3",
            "--orientation",
            "rpy=180,0,0",
            "--orientation-tolerance",
            "1e-12",
        ],
    ):
        out.append(
            Attempt(k, " ".join(args)[:110], args, lambda d: None, (0, 1, 2), timeout=300, message_if_2="--[a-z-]+")
        )
    for sets, codes in (
        (["--set", "solver.step=" + ",".join(f"0.{i:03d}1" for i in range(1001))], (2,)),
        (
            [
                "--set",
                "solver.step=" + ",".join(f"0.{i:02d}1" for i in range(40)),
                "--set",
                "render.fps=" + ",".join(str(5 + i) for i in range(26)),
            ],
            (2,),
        ),
        (["--set", "solver.step=0.1,0.1"], (0, 2)),
    ):
        out.append(
            Attempt(
                k,
                f"sweep of {sets[1][:40]}... ({len(sets) // 2} sets)",
                ["sweep", "s.yaml", *sets, "--out", "o", "-q"],
                tiny_scene(),
                codes,
                timeout=300,
                message="1,000|variant|same|twice|duplicate" if codes == (2,) else None,
            )
        )
    return out


def at_moments(k: str, label: str, args: list[str], setup: Callable[[Path], None], moments, **more) -> list[Attempt]:
    """One attempt of ``args`` per moment ``(seconds, signal)`` (see :class:`Attempt`'s ``interrupt``),
    each ending with 0 or 130 unless ``codes`` says otherwise."""
    more.setdefault("codes", (0, 130))
    return [
        Attempt(k, f"{label}, {signame} at {delay:g} s", args, setup, interrupt=(delay, signame), **more)
        for delay, signame in moments
    ]


def signals11_attempts() -> list[Attempt]:
    """Interrupts during each output's write by the commands campaign 10 left out (check --update,
    import moveit, a batch table, a GIF's palette, a viewer page, a schema), during a pool's start
    (the forkserver's first milliseconds) in steps of 0.2 s, and in bursts of three."""
    k = "signals11"
    out: list[Attempt] = []
    batch = ["run", "a.yaml", "s.yaml", "--out", "o", "--no-video", "-q", "--jobs", "2"]

    def two_scenes(d: Path) -> None:
        write(d / "a.yaml", TINY.replace("name: tiny", "name: a"))
        write(d / "s.yaml", TINY)

    whole = {"timeout": 200, "after": whole_or_none("o/a", "o/tiny", "o/index.csv")}
    # 0.6 to 2.6 s: the pool's forkserver starts in there
    out += at_moments(k, "a --jobs 2 batch", batch, two_scenes, [(t / 10, "SIGINT") for t in range(6, 27, 2)], **whole)
    for delay in (1.0, 1.6, 2.2):
        burst = ((delay + 0.02, "SIGINT"), (delay + 0.04, "SIGINT"))
        out += at_moments(
            k, "a --jobs 2 batch, three Ctrl-C 20 ms apart", batch, two_scenes, [(delay, "SIGINT")], also=burst, **whole
        )
        out += at_moments(
            k,
            "a --jobs 2 batch, then Ctrl-C 0.1 s later",
            batch,
            two_scenes,
            [(delay, "SIGTERM")],
            also=((delay + 0.1, "SIGINT"),),
            **whole,
        )

    def variants_whole(d: Path) -> list[str]:
        names = os.listdir(d / "o") if (d / "o").is_dir() else []
        return [p for name in names if not name.startswith(".") for p in whole_or_none(f"o/{name}")(d)]

    sweep = ["sweep", "s.yaml", "--set", "solver.step=0.1,0.2", "--out", "o", "-q", "--video", "--jobs", "2"]
    moments = [(delay, "SIGINT") for delay in (1.4, 1.7, 2.3, 2.6)]
    out += at_moments(
        k, "sweep of 2 variants with video", sweep, tiny_scene(), moments, timeout=300, after=variants_whole
    )
    out += at_moments(
        k,
        "check --update of a 40,000-frame scene",
        ["check", "s.yaml", "--golden", "g", "--update"],
        tiny_scene(text=LONG),
        ((1.5, "SIGINT"), (3.0, "SIGTERM"), (4.5, "SIGTERMG"), (6.0, "SIGINT")),
        timeout=200,
        after=whole_or_none("g/tiny.csv"),
        litter_in=("g", "."),
    )

    def moveit_scene(d: Path) -> None:
        box = "* b{i}\n1\nbox\n0.05 0.05 0.05\n{x} {y} 1\n0 0 0 1\n0 0 0 0\n"
        write(
            d / "w.scene",
            "w\n" + "".join(box.format(i=i, x=2 + i % 10, y=i // 10 * 0.1) for i in range(15_000)) + ".\n",
        )

    out += at_moments(
        k,
        "import moveit of 15,000 boxes (under its 1 MB)",
        ["import", "moveit", "w.scene", "--robot", "panda", "--out", "m.yaml"],
        moveit_scene,
        ((0.8, "SIGINT"), (1.5, "SIGTERM"), (2.5, "SIGINT")),
        timeout=200,
        after=whole_or_none("m.yaml"),
        litter_in=(".",),
    )
    short = LONG.replace("hold: 3600", "hold: 30").replace("hold: 400", "hold: 30")
    out += at_moments(
        k,
        "render --format gif --out fig",
        ["render", "o/tiny", "--format", "gif", "--out", "fig", "-q", "--size", "320x180"],
        lambda d: finished_run(d, short) and None,
        ((2.0, "SIGINT"), (4.0, "SIGTERM")),
        timeout=300,
        keep=("o/tiny",),
        after=whole_or_none("fig"),
        litter_in=("o", "fig", "."),
    )
    out += at_moments(
        k,
        "run --viewer --no-video of a 40,000-frame scene",
        ["run", "s.yaml", "--out", "o", "--no-video", "--viewer", "-q"],
        tiny_scene(text=LONG),
        ((2.5, "SIGINT"), (5.0, "SIGTERMG")),
        timeout=200,
        after=whole_or_none("o/tiny"),
    )
    out += at_moments(
        k,
        "schema --out",
        ["schema", "--out", "x.json"],
        lambda d: None,
        [(delay, "SIGINT") for delay in (0.4, 0.7, 1.0)],
        timeout=60,
        after=whole_or_none("x.json"),
        litter_in=(".",),
    )
    out += at_moments(
        k,
        "validate of 200 scenes",
        ["validate", *[f"s{i}.yaml" for i in range(200)]],
        lambda d: [write(d / f"s{i}.yaml", TINY) for i in range(200)] and None,
        ((1.0, "SIGINT"), (2.0, "SIGTERM")),
        timeout=120,
    )
    out += at_moments(
        k,
        "ik --robot panda of an unreachable pose",
        ["ik", "--robot", "panda", "--goal", "5,5,5", "--max-iterations", "100000000", "--tolerance", "1e-300"],
        lambda d: None,
        ((1.5, "SIGINT"), (3.0, "SIGTERMG")),
        codes=(0, 1, 130),
        timeout=300,
    )
    out += at_moments(
        k,
        "run --jobs 2 with video (segment workers)",
        ["run", "s.yaml", "--out", "o", "-q", "--jobs", "2"],
        tiny_scene(text=TINY.replace("fps: 10", "fps: 30")),
        ((1.0, "SIGINT"), (2.5, "SIGTERMG"), (4.0, "SIGTERM")),
        timeout=300,
        after=whole_or_none("o/tiny"),
    )
    return out


def loss11_attempts() -> list[Attempt]:
    """What campaign 10 did not aim at: a scene, URDF or golden kept inside the run folder that a
    run replaces, links out of a run folder to the user's files, OUT itself a link into a run,
    scene names that are a batch's own files, and every writer aimed at the user's scene."""
    k = "loss11"
    run = ["run", "s.yaml", "--out", "o", "--no-video", "-q"]
    batch = ["run", "a.yaml", "s.yaml", "--out", "o", "--no-video", "-q", "--jobs", "1"]
    changed = mine("s.yaml", TINY.replace("[0.5, -1, 1]", "[0.5, -1, 1.2]"))
    scene = mine("s.yaml", TINY)
    other_a = mine("a.yaml", TINY.replace("name: tiny", "name: a"))
    urdf_run = then(urdf_robot(), lambda d: armanim_in(d, *run))
    urdf_changed = mine("s.yaml", URDF_SCENE.replace("0.4]", "0.45]"))
    video = lambda d: finished_run(d, video=True) and None  # noqa: E731
    sweep = ["sweep", "s.yaml", "--set", "solver.step=0.1,0.2", "-q", "--out"]

    def named(name: str) -> Callable[[Path], None]:
        return mine("s.yaml", TINY.replace("name: tiny", f"name: {name}"))

    def variant_to_mine(d: Path) -> None:
        variant = next(p for p in sorted((d / "o").iterdir()) if p.is_dir() and not p.name.startswith("."))
        shutil.rmtree(variant)
        os.symlink(os.path.abspath(d / "mine"), variant)

    def unlinked(path: str) -> Callable[[Path], None]:
        return lambda d: [os.unlink(p) for p in d.glob(path)] and None

    def linked(pattern: str, target: str) -> Callable[[Path], None]:
        return lambda d: [(os.unlink(p), os.symlink(target, p)) for p in d.glob(pattern)] and None

    # one attempt a row: label, arguments, setup, exit codes, the user's paths kept
    # fmt: off
    table: list[tuple] = [
        ("run a scene kept inside its own run folder", ["run", "o/tiny/s.yaml", "--out", "o", "--no-video", "-q"], then(finished_run, mine("o/tiny/s.yaml", TINY.replace("[0.5, -1, 1]", "[0.5, -1, 1.2]"))), (0, 3), ("o/tiny/s.yaml",)),
        ("run a scene whose URDF is kept inside the run folder", run, then(urdf_run, mine("o/m/mine.urdf", urdf_text()), mine("s.yaml", URDF_SCENE.replace("robot.urdf", "o/m/mine.urdf")),), (0, 2, 3), ("o/m/mine.urdf",)),
        ("check --update --golden inside the run folder", ["check", "s.yaml", "--golden", "o/tiny/g", "--update"], then(finished_run, mine("o/tiny/g/notes.txt")), (0, 2, 3), ("o/tiny/g/notes.txt",)),
        ("render --out a folder inside the run folder", ["render", "o/tiny", "-q", "--size", "64x48", "--out", "o/tiny/fig"], then(finished_run, mine("o/tiny/fig/notes.txt")), (2, 3), ("o/tiny/fig/notes.txt",)),
        ("run, the user's notes inside the run folder (a link to them)", run, then(finished_run, mine("notes.txt"), symlink("../../notes.txt", "o/tiny/notes.txt"), changed), (0, 3), ("notes.txt",)),
        ("run, the run folder's plot.png a link to the user's picture", ["run", "s.yaml", "--out", "o", "-q"], then(video, mine("mine.png", "not a png"), linked("o/tiny/plot.png", "../../mine.png"), changed), (0, 3), ("mine.png",)),
        ("render, the run's video a link to the user's video", ["render", "o/tiny", "-q", "--size", "64x48"], then(video, mine("mine.mp4", "mine"), linked("o/tiny/*.mp4", "../../mine.mp4")), (0, 3), ("mine.mp4",)),
        ("view, the run's viewer.html a hard link to the user's page", ["view", "o/tiny"], then(finished_run, mine("mine.html", "<html>mine</html>"), hardlink("mine.html", "o/tiny/viewer.html")), (0, 3), ("mine.html",)),
        ("run --out a link to the run folder itself", ["run", "s.yaml", "--out", "lnk", "--no-video", "-q"], then(finished_run, symlink("o/tiny", "lnk")), (0, 2, 3), ("o/tiny/trajectory.csv",)),
        ("run --out o/tiny (into the run folder)", ["run", "s.yaml", "--out", "o/tiny", "--no-video", "-q"], finished_run, (2, 3), ("o/tiny",)),
        ("run --out a link loop", ["run", "s.yaml", "--out", "lp", "--no-video", "-q"], then(scene, symlink("lp", "lp")), (2, 3), ("lp",)),
        ("run, OUT/NAME a dangling link", run, then(scene, lambda d: (d / "o").mkdir(), symlink("../gone", "o/tiny")), (0, 3), ("o/tiny",)),
        ("run --out o/../o (the same folder)", ["run", "s.yaml", "--out", "o/../o", "--no-video", "-q"], then(finished_run, changed), (0,), ()),
        ("a batch whose second scene is named index.csv", batch, then(other_a, named("index.csv")), (0, 2), ()),
        ("a batch of scenes named a and .a", batch, then(other_a, named(".a")), (0, 2), ()),
        ("a scene named .armanim-run.json", run, named(".armanim-run.json"), (0, 2), ()),
        ("a scene named ..", run, named("'..'"), (2,), ("s.yaml",)),
        ("a scene named with a slash a/b", run, named("a/b"), (0, 2), ()),
        ("a scene named 255 characters", run, named("n" * 255), (0, 2, 3), ()),
        ("a batch again with the user's file at index.csv (unmarked)", batch, then(other_a, scene, mine("o/index.csv", "mine,1\n")), (0, 3), ("o/index.csv",)),
        ("sweep --out the user's scene folder", [*sweep, "."], then(scene, mine("notes.txt")), (0, 2, 3), ("s.yaml", "notes.txt")),
        ("sweep, a variant's folder a link to the user's folder", [*sweep, "o"], then(scene, mine("mine/notes.txt"), lambda d: armanim_in(d, *sweep, "o"), variant_to_mine), (0, 3), ("mine",)),
        ("import moveit --out the user's scene", ["import", "moveit", "w.scene", "--robot", "panda", "--out", "s.yaml"], then(scene, mine("w.scene", "w\n* box\n1\nbox\n0.1 0.1 0.1\n1 1 1\n0 0 0 1\n0 0 0 0\n.\n")), (3,), ("s.yaml",)),
        ("view --out the user's scene", ["view", "o/tiny", "--out", "s.yaml"], finished_run, (2, 3), ("s.yaml",)),
        ("fk --png the user's scene", ["fk", "--angles", "0,0,0,0", "--png", "s.yaml"], scene, (2, 3), ("s.yaml",)),
        ("schema --out a link to the user's scene", ["schema", "--out", "x.json"], then(scene, symlink("s.yaml", "x.json")), (2, 3), ("s.yaml", "x.json")),
        ("export --out a link to the run's own trajectory.csv", ["export", "o/tiny", "--out", "x.json"], then(finished_run, symlink("o/tiny/trajectory.csv", "x.json")), (2, 3), ("o/tiny",)),
        ("check --update, the golden folder a link to the user's folder", ["check", "s.yaml", "--golden", "g", "--update"], then(scene, mine("mine/notes.txt"), symlink("mine", "g")), (0, 3), ("mine/notes.txt",)),
        ("check --update, g/tiny.csv the user's own CSV (unmarked)", ["check", "s.yaml", "--golden", "g", "--update"], then(scene, mine("g/tiny.csv", "time_s\n0\n")), (0, 3), ("g/tiny.csv",)),
        ("render --out the folder holding the scene and the URDF", ["render", "o/m", "-q", "--size", "64x48", "--out", "."], urdf_run, (2, 3), ("s.yaml", "robot.urdf")),
        ("run, a run folder's robot.urdf a link to the user's URDF", run, then(urdf_run, mine("mine.urdf", urdf_text()), linked("o/m/robot.urdf", "../../mine.urdf"), urdf_changed), (0, 3), ("mine.urdf",)),
        ("export --out a name whose mark is a folder", ["export", "o/tiny", "--out", "x.json"], then(finished_run, mine(".x.json.armanim.json/mine.txt")), (0, 3), (".x.json.armanim.json",)),
        ("fk --png, the PNG's mark a FIFO", ["fk", "--angles", "0,0,0,0", "--png", "p.png"], lambda d: fifo(d / ".p.png.armanim.json"), (0, 3), (".p.png.armanim.json",)),
        ("view --out v.html, v.html a folder of the user's", ["view", "o/tiny", "--out", "v.html"], then(finished_run, mine("v.html/mine.txt")), (2, 3), ("v.html",)),
        ("run, the scene itself a hard link inside the run folder", run, then(finished_run, hardlink("s.yaml", "o/tiny/scene-copy.yaml"), unlinked("s.yaml"), changed), (0, 3), ("o/tiny/scene-copy.yaml",)),
    ]
    # fmt: on
    out = [Attempt(k, label, args, setup, codes, keep=keep, timeout=300) for label, args, setup, codes, keep in table]
    out.append(
        Attempt(
            k,
            "run with ARMANIM_CACHE_DIR the run folder",
            run,
            then(
                lambda d: write(d / "a.stl", stl(30)), urdf_robot(collision=col("a.stl")), lambda d: armanim_in(d, *run)
            ),
            (0, 3),  # the fit kept in the run folder: the next run's replace refuses the folder, nothing lost
            env={"ARMANIM_CACHE_DIR": "{d}/o/m"},
            after=exists("o/m/trajectory.csv"),
        )
    )
    return out


def read_back_attempts(
    k: str, run_files: list[tuple], render_flags: list[str], codes: tuple[int, ...]
) -> list[Attempt]:
    """``render``, ``view`` and ``export`` of a finished tiny run whose file ``name`` was changed
    by hand (``(label, name, change)``: ``change`` of its text, None to delete it): exit ``codes``,
    2 naming the file."""
    out = []
    for label, name, change in run_files:

        def edited(d: Path, name=name, change=change) -> None:
            folder = finished_run(d)
            path = folder / name
            if change is None:
                if path.exists():
                    path.unlink()
                return
            new = change(path.read_text()) if path.exists() else change("")
            write(path, new)

        for cmd in (
            ["render", "o/tiny", "-q", *render_flags],
            ["view", "o/tiny", "--out", "v.html"],
            ["export", "o/tiny", "--out", "e.json"],
        ):
            out.append(
                Attempt(
                    k,
                    f"{cmd[0]} of a run whose {label}",
                    cmd,
                    edited,
                    codes,
                    timeout=200,
                    message_if_2=r"(trajectory\.csv|summary\.json|scene\.yaml|\.armanim-run\.json|o/tiny)",
                )
            )
    return out


def inputs11_attempts() -> list[Attempt]:
    """Hostile files and flags campaign 10 did not write: scene files that are devices, links, other
    encodings or too big; fields at their edges; a run folder's own files edited by hand and read
    back by render, view and export; CLI vectors; MoveIt scenes. Exit 0, or 2 naming file and line."""
    k = "inputs11"
    out: list[Attempt] = []
    good = "version: 1\nname: s\narm: {links: [1, 1, 1]}\ngoals: [[1, 1, 1]]\n"
    # fmt: off
    yaml_cases = [
        ("a UTF-8 BOM", "\ufeff" + good),
        ("UTF-16 with a BOM", good.encode("utf-16")),
        ("latin-1 bytes in the name", good.replace("name: s", "name: caf\xe9").encode("latin-1")),
        ("a NUL in the middle", good.replace("goals", "go\0als")),
        ("a form feed and vertical tab", good.replace("\n", "\n\f\v", 1)),
        ("a line separator U+2028 in a string", good.replace("name: s", 'name: "a\u2028b"')),
        ("key 'goals' twice in flow", good.replace("goals: [[1, 1, 1]]", "{goals: [[1, 1, 1]], goals: [[1, 1, 1]]}")),
        ("an anchor on the whole arm used twice", "version: 1\nname: s\narm: &a {links: [1, 1, 1]}\ngoals: [[1, 1, 1]]\nx: *a\n"),
        ("an undefined alias", good.replace("name: s", "name: *nope")),
        ("a flow mapping left open", good.replace("{links: [1, 1, 1]}", "{links: [1, 1, 1]")),
        ("a tag !!float on a string", good.replace("name: s", "name: !!float abc")),
        ("!!int 0b101", good.replace("version: 1", "version: !!int 0b101")),
        ("version +1", good.replace("version: 1", "version: +1")),
        ("version 2", good.replace("version: 1", "version: 2")),
        ("version 99999999999999999999", good.replace("version: 1", "version: 99999999999999999999")),
        ("a goal of .NaN and .Inf", good.replace("[[1, 1, 1]]", "[[.NaN, .Inf, -.INF]]")),
        ("a goal of 1e-400 (underflows to 0)", good.replace("[[1, 1, 1]]", "[[1e-400, 1, 1]]")),
        ("a goal of -0.0", good.replace("[[1, 1, 1]]", "[[-0.0, 1, 1]]")),
        ("a goal of '1e3' quoted", good.replace("[[1, 1, 1]]", "[['1e3', 1, 1]]")),
        ("a goal of 1:30 (sexagesimal)", good.replace("[[1, 1, 1]]", "[[1:30, 1, 1]]")),
        ("a goal of ~", good.replace("[[1, 1, 1]]", "[~]")),
        ("a goal of an empty mapping", good.replace("[[1, 1, 1]]", "[{}]")),
        ("a goal of a 10,000-number list", good.replace("[[1, 1, 1]]", "[[" + ", ".join(["1"] * 10_000) + "]]")),
        ("arm.base of four numbers", good.replace("links: [1, 1, 1]", "links: [1, 1, 1], base: [0, 0, 0, 0]")),
        ("arm.base .nan", good.replace("links: [1, 1, 1]", "links: [1, 1, 1], base: [.nan, 0, 0]")),
        ("arm.robot of an unknown name", good.replace("{links: [1, 1, 1]}", "{robot: pandaa}")),
        ("arm.robot ../../etc/passwd", good.replace("{links: [1, 1, 1]}", "{robot: ../../etc/passwd}")),
        ("arm.robot and arm.links both", good.replace("{links: [1, 1, 1]}", "{robot: panda, links: [1, 1]}")),
        ("arm.urdf a folder", good.replace("{links: [1, 1, 1]}", "{urdf: sub}")),
        ("arm.urdf a FIFO", good.replace("{links: [1, 1, 1]}", "{urdf: f.srdf}")),
        ("arm.urdf the scene itself", good.replace("{links: [1, 1, 1]}", "{urdf: s.yaml}")),
        ("arm.urdf an empty string", good.replace("{links: [1, 1, 1]}", "{urdf: ''}")),
        ("arm.urdf a link loop", good.replace("{links: [1, 1, 1]}", "{urdf: loop.urdf}")),
        ("arm.urdf /dev/zero by a link", good.replace("{links: [1, 1, 1]}", "{urdf: zero.urdf}")),
        ("arm.urdf a 5 MB sparse file", good.replace("{links: [1, 1, 1]}", "{urdf: big.urdf}")),
        ("arm.tip_link unknown", good.replace("{links: [1, 1, 1]}", "{robot: panda, tip_link: nosuch}")),
        ("arm.base_link unknown", good.replace("{links: [1, 1, 1]}", "{robot: panda, base_link: nosuch}")),
        ("arm.joint_values of an unknown joint", good.replace("{links: [1, 1, 1]}", "{robot: panda, joint_values: {nosuch: 0}}")),
        ("arm.joint_values of NaN", good.replace("{links: [1, 1, 1]}", "{robot: panda, joint_values: {panda_finger_joint1: .nan}}")),
        ("arm.package_dirs a file", good.replace("{links: [1, 1, 1]}", "{robot: panda, package_dirs: [s.yaml]}")),
        ("arm.package_dirs 1,000 entries", good.replace("{links: [1, 1, 1]}", "{robot: panda, package_dirs: [" + ", ".join(["sub"] * 1000) + "]}")),
        ("arm.tool length -1", good.replace("links: [1, 1, 1]", "links: [1, 1, 1], tool: {length: -1}")),
        ("arm.tool mesh a folder", good.replace("links: [1, 1, 1]", "links: [1, 1, 1], tool: {length: 0.1, mesh: sub}")),
        ("arm.tool mesh a .ply", good.replace("links: [1, 1, 1]", "links: [1, 1, 1], tool: {length: 0.1, mesh: t.ply}")),
        ("arm.tool an unknown key", good.replace("links: [1, 1, 1]", "links: [1, 1, 1], tool: {length: 0.1, colour: red}")),
        ("an orientation rpy of four numbers", good.replace("[[1, 1, 1]]", "[{position: [1, 1, 1], orientation: {rpy: [0, 0, 0, 0]}}]")),
        ("an orientation quaternion of three numbers", good.replace("[[1, 1, 1]]", "[{position: [1, 1, 1], orientation: {quaternion: [1, 0, 0]}}]")),
        ("an orientation of rpy and quaternion both", good.replace("[[1, 1, 1]]", "[{position: [1, 1, 1], orientation: {rpy: [0, 0, 0], quaternion: [1, 0, 0, 0]}}]")),
        ("an arc without a normal", good.replace("[[1, 1, 1]]", "[{path: {arc: {center: [1, 0, 1], start: [1, 0.3, 1], angle: 90}}, speed: 0.5}]")),
        ("an arc whose start is its centre", good.replace("[[1, 1, 1]]", "[{path: {arc: {center: [1, 0, 1], start: [1, 0, 1], angle: 90, normal: [0, 0, 1]}}, speed: 0.5}]",)),
        ("an arc whose normal lies along its radius", good.replace("[[1, 1, 1]]", "[{path: {arc: {center: [1, 0, 1], start: [1, 0.3, 1], angle: 90, normal: [0, 1, 0]}}, speed: 0.5}]",)),
        ("a path of two kinds", good.replace("[[1, 1, 1]]", "[{path: {line: [[1, 0, 1], [1, 1, 1]], polyline: [[1, 0, 1], [1, 1, 1]]}, speed: 0.5}]")),
        ("a polyline of one point", good.replace("[[1, 1, 1]]", "[{path: {polyline: [[1, 0, 1]]}, speed: 0.5}]")),
        ("a path without speed", good.replace("[[1, 1, 1]]", "[{path: {line: [[1, 0, 1], [1, 1, 1]]}}]")),
        ("a path speed .nan", good.replace("[[1, 1, 1]]", "[{path: {line: [[1, 0, 1], [1, 1, 1]]}, speed: .nan}]")),
        ("a path speed 0", good.replace("[[1, 1, 1]]", "[{path: {line: [[1, 0, 1], [1, 1, 1]]}, speed: 0}]")),
        ("a text of 10,001 characters", good.replace("[[1, 1, 1]]", '[{path: {text: {string: "' + "a" * 10_001 + '", origin: [1, -0.5, 1], height: 0.05, right: [0, 1, 0], up: [0, 0, 1]}}, speed: 0.5}]',)),
        ("a text string a number", good.replace("[[1, 1, 1]]", "[{path: {text: {string: 42, origin: [1, -0.5, 1], height: 0.05, right: [0, 1, 0], up: [0, 0, 1]}}, speed: 0.5}]",)),
        ("a hold of -1", good.replace("[[1, 1, 1]]", "[{position: [1, 1, 1], hold: -1}]")),
        ("a hold of 'forever'", good.replace("[[1, 1, 1]]", "[{position: [1, 1, 1], hold: forever}]")),
        ("a blend of -1", good.replace("[[1, 1, 1]]", "[{position: [1, 1, 1], blend: -1}, [1, 0, 1]]")),
        ("joints of null", good.replace("[[1, 1, 1]]", "[{joints: [null, 0, 0]}]")),
        ("joints as a mapping", good.replace("[[1, 1, 1]]", "[{joints: {a: 1}}]")),
        ("an obstacle of two shapes", good + "obstacles: [{center: [3, 3, 3], radius: 1, box: {center: [3, 3, 3], size: [1, 1, 1]}}]\n"),
        ("an obstacle of an unknown shape", good + "obstacles: [{cone: {center: [3, 3, 3]}}]\n"),
        ("an obstacle mesh", good + "obstacles: [{mesh: a.stl}]\n"),
        ("a box rotated by rpy nan", good + "obstacles: [{box: {center: [3, 3, 3], size: [1, 1, 1], rpy: [.nan, 0, 0]}}]\n"),
        ("two obstacles of one name", good + "obstacles: [{center: [3, 3, 3], radius: 1, name: a}, {center: [5, 5, 5], radius: 1, name: a}]\n"),
        ("render.view elevation 1e400", good + "render: {view: {elevation: 1e400, azimuth: 0}}\n"),
        ("render.bounds inverted", good + "render: {bounds: [[1, 1, 1], [-1, -1, -1]]}\n"),
        ("render.robot maybe", good + "render: {robot: maybe}\n"),
        ("render.trail -1", good + "render: {trail: -1}\n"),
        ("solver.method an unknown one", good + "solver: {method: lbfgs}\n"),
        ("solver.tolerance a string", good + "solver: {tolerance: small}\n"),
        ("solver.path_tolerance 0", good + "solver: {path_tolerance: 0}\n"),
        ("solver an empty mapping", good + "solver: {}\n"),
        ("solver null", good + "solver: null\n"),
    ]
    # fmt: on

    def beside(d: Path) -> None:
        fifo(d / "f.srdf")
        (d / "sub").mkdir()
        os.symlink("loop.urdf", d / "loop.urdf")
        os.symlink("/dev/zero", d / "zero.urdf")
        sparse(d / "big.urdf", 5 << 20)
        write(d / "t.ply", "ply\n")
        write(d / "a.stl", stl(4))

    for label, text in yaml_cases:
        out.append(
            Attempt(
                k,
                f"validate, {label}",
                ["validate", "s.yaml"],
                lambda d, text=text: (write(d / "s.yaml", text), beside(d)) and None,
                (0, 2),
                timeout=120,
                message_if_2=AT_LINE,
            )
        )
    for label, target in (
        ("a FIFO", "fifo"),
        ("/dev/zero by a link", "zero"),
        ("a folder", "sub"),
        ("a 300 MB sparse file", "big"),
        ("/proc/self/status by a link", "proc"),
    ):

        def scene_file(d: Path, target=target) -> None:
            if target == "fifo":
                fifo(d / "s.yaml")
            elif target == "zero":
                os.symlink("/dev/zero", d / "s.yaml")
            elif target == "sub":
                (d / "s.yaml").mkdir()
            elif target == "big":
                sparse(d / "s.yaml", 300 << 20)
            else:
                os.symlink("/proc/self/status", d / "s.yaml")

        for cmd in (
            ["validate", "s.yaml"],
            ["run", "s.yaml", "--out", "o", "--no-video", "-q"],
            ["sweep", "s.yaml", "--set", "solver.step=0.1,0.2", "--out", "o", "-q"],
        ):
            out.append(Attempt(k, f"{cmd[0]}, the scene {label}", cmd, scene_file, (2,), timeout=60))
    # a run folder's own files, edited by hand, read back
    # fmt: off
    run_files = [
        ("trajectory.csv with a row of text", "trajectory.csv", lambda t: t.replace("\n", "\nabc,def\n", 2)),
        ("trajectory.csv with its header shuffled", "trajectory.csv", lambda t: ",".join(reversed(t.split("\n", 1)[0].split(","))) + "\n" + t.split("\n", 1)[1]),
        ("trajectory.csv cut mid-row", "trajectory.csv", lambda t: t[: len(t) // 2]),
        ("trajectory.csv of its header only", "trajectory.csv", lambda t: t.split("\n", 1)[0] + "\n"),
        ("trajectory.csv with time going back", "trajectory.csv", lambda t: "\n".join(t.split("\n")[:3] + [t.split("\n")[1]] + t.split("\n")[3:])),
        ("trajectory.csv with an angle of 1e308", "trajectory.csv", lambda t: _set_cell(t, 2, 3, "1e308")),
        ("trajectory.csv with a goal index of 10^6", "trajectory.csv", lambda t: _set_cell(t, 2, 2, "1000000")),
        ("trajectory.csv with a frame of -1", "trajectory.csv", lambda t: _set_cell(t, 2, 0, "-1")),
        ("trajectory.csv in UTF-16", "trajectory.csv", lambda t: t.encode("utf-16")),
        ("summary.json not JSON", "summary.json", lambda t: "{not json"),
        ("summary.json a list", "summary.json", lambda t: "[]"),
        ("summary.json without goals", "summary.json", lambda t: "{}"),
        ("scene.yaml an alias bomb", "scene.yaml", lambda t: ("a: &a [x, x, x, x, x, x, x, x, x]\n" + "".join(f"{chr(98 + i)}: &{chr(98 + i)} [*{chr(97 + i)}, *{chr(97 + i)}, *{chr(97 + i)}, *{chr(97 + i)}, *{chr(97 + i)}, *{chr(97 + i)}, *{chr(97 + i)}, *{chr(97 + i)}, *{chr(97 + i)}]\n" for i in range(9)))),
        ("scene.yaml of another arm (4 links)", "scene.yaml", lambda t: t.replace("links: [1, 1, 1]", "links: [1, 1, 1, 1]")),
        ("scene.yaml missing", "scene.yaml", None),
        ("trajectory.csv missing", "trajectory.csv", None),
    ]
    # fmt: on
    out += read_back_attempts(k, run_files, ["--size", "64x48"], (0, 2))
    # fmt: off
    cli = [
        ["fk", "--angles", ""],
        ["fk", "--angles", "1,,2,3"],
        ["fk", "--angles", "1;2;3;4"],
        ["fk", "--angles", "0x10,0,0,0"],
        ["fk", "--links", "1,1", "--angles", "0,0,0,0"],
        ["fk", "--axes", "q,y,y,y", "--angles", "0,0,0,0"],
        ["fk", "--axes", "z,y", "--angles", "0,0,0,0"],
        ["fk", "--direction", "w", "--angles", "0,0,0,0"],
        ["fk", "--base", "1,2", "--angles", "0,0,0,0"],
        ["fk", "--robot", "panda", "--links", "1,1,1", "--angles", "0,0,0"],
        ["fk", "--robot", "", "--angles", "0"],
        ["ik", "--goal", "1,2"],
        ["ik", "--goal", "a,b,c"],
        ["ik", "--orientation", "rpy=1,2", "--goal", "1,1,1"],
        ["ik", "--orientation", "quat=0,0,0,0", "--goal", "1,1,1"],
        ["ik", "--orientation", "euler=1,2,3", "--goal", "1,1,1"],
        ["ik", "--from", "0,0", "--goal", "1,1,1"],
        ["ik", "--method", "lbfgs", "--goal", "1,1,1"],
        ["ik", "--max-iterations", "0", "--goal", "1,1,1"],
        ["render", "o/tiny", "--format", "webm"],
        ["render", "o/tiny", "--quality", "ultra"],
        ["run", "s.yaml", "--size", "x"],
        ["run", "s.yaml", "--jobs", "two"],
        ["run", "s.yaml", "--scheduler", "tcp://[::1"],
        ["sweep", "s.yaml", "--set", "solver.step"],
        ["sweep", "s.yaml", "--set", "nosuch.field=1,2"],
        ["sweep", "s.yaml", "--set", "goals[0]=[1,1]"],
        ["compare", "s.yaml", "s.yaml"],
        ["check", "s.yaml", "--golden", "s.yaml"],
        ["robots", "--fit", "s.yaml"],
        ["import", "moveit", "s.yaml", "--robot", "panda", "--out", "m.yaml"],
        ["view", "s.yaml"],
    ]
    # fmt: on
    for args in cli:
        setup = (lambda d: finished_run(d) and None) if args[0] == "render" else tiny_scene()
        out.append(Attempt(k, " ".join(args)[:100], args, setup, (2,), timeout=120))
    # fmt: off
    moveit_cases = [
        ("a count of -1 shapes", "w\n* b\n-1\nbox\n0.1 0.1 0.1\n1 1 1\n0 0 0 1\n0 0 0 0\n.\n"),
        ("a shape 'mesh' with 10^9 vertices", "w\n* b\n1\nmesh\n1000000000 1\n.\n"),
        ("a cylinder of one number", "w\n* b\n1\ncylinder\n0.1\n1 1 1\n0 0 0 1\n0 0 0 0\n.\n"),
        ("a box of four sizes", "w\n* b\n1\nbox\n0.1 0.1 0.1 0.1\n1 1 1\n0 0 0 1\n0 0 0 0\n.\n"),
        ("no terminating '.'", "w\n* b\n1\nbox\n0.1 0.1 0.1\n1 1 1\n0 0 0 1\n0 0 0 0\n"),
        ("an object name with a newline only", "w\n* \n1\nbox\n0.1 0.1 0.1\n1 1 1\n0 0 0 1\n0 0 0 0\n.\n"),
        ("a position of words", "w\n* b\n1\nbox\n0.1 0.1 0.1\na b c\n0 0 0 1\n0 0 0 0\n.\n"),
        ("a colour of 1e400", "w\n* b\n1\nbox\n0.1 0.1 0.1\n1 1 1\n0 0 0 1\n1e400 0 0 0\n.\n"),
    ]
    # fmt: on
    for label, text in moveit_cases:
        out.append(
            Attempt(
                k,
                f"import moveit, a scene with {label}",
                ["import", "moveit", "w.scene", "--robot", "panda", "--out", "m.yaml"],
                lambda d, text=text: write(d / "w.scene", text) and None,
                (0, 2),
                timeout=120,
                message_if_2=r"w\.scene:(\d+:)? ",
            )
        )
    return out


def _json_of(d: Path, *args: str) -> dict:
    """armanim's JSON answer to ``args`` (run in ``d``), or {"failed": what it said} (not "error":
    ik's answer has an ``error``, its distance to the goal)."""
    import json as _json

    done = subprocess.run(
        [sys.executable, "-m", "armanim", *args],
        cwd=d,
        env=dict(os.environ, PYTHONPATH=str(SRC)),
        capture_output=True,
        text=True,
        timeout=300,
    )
    try:
        return _json.loads(done.stdout)
    except ValueError:
        return {"failed": f"exit {done.returncode}: {(done.stdout + done.stderr)[-200:]}"}


def fk_args(links: list[float], angles: list[float], radians: bool = False) -> list[str]:
    """``fk``'s arguments for an arm of ``links`` at ``angles`` (degrees, or radians), answering in JSON."""
    return ["fk", "--links", _joined(links), "--angles", _joined(angles), *(["--radians"] if radians else []), "--json"]


def ik_args(links: list[float], goal: list[float], method: str, start: list[float] | None = None) -> list[str]:
    """``ik``'s arguments for an arm of ``links`` to ``goal`` by ``method`` (from ``start``), in JSON."""
    started = ["--from", _joined(start)] if start is not None else []
    return ["ik", "--links", _joined(links), "--goal", _joined(goal), "--method", method, *started, "--json"]


def _joined(numbers: list[float]) -> str:
    return ",".join(map(str, numbers))


def random_reachable_goal(rng) -> tuple[list[float], list[float]]:
    """A random arm of 3-5 links and a goal within 0.2-1.1 of its reach from joint 2's height."""
    import numpy as np

    links = [round(float(x), 3) for x in rng.uniform(0.3, 1.5, int(rng.integers(3, 6)))]
    direction = rng.normal(size=3)
    goal = [
        round(float(x), 4)
        for x in direction / np.linalg.norm(direction) * rng.uniform(0.2, 1.1) * sum(links[1:]) + [0, 0, links[0]]
    ]
    return links, goal


def fk_breaks(links: list[float], angles: list[float], radians: bool = False) -> Callable[[Path], list[str]]:
    """fk's joints and tip against the campaign's own forward kinematics (:func:`_segments`);
    ``angles`` in radians (``fk --radians``) if ``radians``."""

    def check(d: Path) -> list[str]:
        import numpy as np

        said = _json_of(d, *fk_args(links, angles, radians))
        if "failed" in said:
            return [said["failed"]]
        mine = _segments([np.degrees(angles) if radians else angles], links)[0]
        off = float(np.abs(np.asarray(said["joints"]) - mine).max())
        return [f"fk's joints differ from the oracle's by {off:.3g}"] if off > 1e-9 else []

    return check


def random_fk_attempt(k: str, i: int, rng, span: float, digits: int, radians: bool = False) -> Attempt:
    """fk of a random arm of 2-6 links at angles within +-``span`` (``digits`` decimals; radians
    if ``radians``), held to :func:`fk_breaks`."""
    links = [round(float(x), 3) for x in rng.uniform(0.2, 2.0, int(rng.integers(2, 7)))]
    angles = [round(float(x), digits) for x in rng.uniform(-span, span, len(links))]
    return Attempt(
        k,
        f"fk{' --radians' if radians else ''} of a random {len(links)}-link arm ({i}), held to the oracle",
        fk_args(links, angles, radians),
        lambda d: None,
        (0,),
        timeout=120,
        after=fk_breaks(links, angles, radians),
    )


def ik_breaks(
    links: list[float], goal: list[float], method: str, start: list[float] | None = None
) -> Callable[[Path], list[str]]:
    """ik's answer held to the oracle: the tip it reports is where its angles put the tip, its error
    is that tip's distance to the goal, and a converged answer is within the tolerance (0.001);
    from ``start`` (degrees, ``ik --from``) if given."""

    def check(d: Path) -> list[str]:
        import numpy as np

        said = _json_of(d, *ik_args(links, goal, method, start))
        if "failed" in said:
            return [said["failed"]]
        tip = _segments([said["angles_deg"]], links)[0][-1]
        problems = []
        if np.abs(tip - np.asarray(said["tip"])).max() > 1e-9:
            problems.append(f"ik's tip {said['tip']} is not where its angles put it {tip.tolist()}")
        if abs(np.linalg.norm(tip - np.asarray(goal)) - said["error"]) > 1e-9:
            problems.append(f"ik's error {said['error']:.6g}, the oracle's {np.linalg.norm(tip - goal):.6g}")
        if said["converged"] and np.linalg.norm(tip - np.asarray(goal)) > 0.001 + 1e-12:
            problems.append(f"ik says converged {np.linalg.norm(tip - goal):.6g} from the goal")
        return problems

    return check


def wrong11_attempts() -> list[Attempt]:
    """Random arms among spheres with arcs and polylines beside campaign 10's goals (new seeds),
    and fk and ik answers of random arms, each held to the campaign's own oracle."""
    import numpy as np

    k = "wrong11"
    out = random_arm_runs(k, range(200, 236), " with arcs and polylines", WRONG11_KINDS)
    rng = np.random.default_rng(11)
    out += [random_fk_attempt(k, i, rng, 720, 4) for i in range(14)]
    for i in range(14):
        links, goal = random_reachable_goal(rng)
        method = str(rng.choice(["pinv", "dls", "newton", "gradient"]))
        args = ik_args(links, goal, method)
        out.append(
            Attempt(
                k,
                f"ik of a random {len(links)}-link arm by {method} ({i}), held to the oracle",
                args,
                lambda d: None,
                (0, 1),
                timeout=200,
                after=ik_breaks(links, goal, method),
            )
        )
    return out


# ------------------------------------------------------------------ the twelfth campaign
#
# New attacks on the same classes again (issue 50's "fifth campaign"), none a repeat of the ninth,
# tenth or eleventh: mesh12, frames12, signals12, loss12, inputs12, wrong12.


def mesh12_attempts() -> list[Attempt]:
    """Mesh names the resolver had not met (relative paths with ``..``, ``package://`` through a
    package folder, unicode and escaped names, lengths past the system's), files of one format
    under another's suffix, readers' edges campaigns 10 and 11 left, and the look of a run whose
    copied URDF or look folders were edited by hand."""
    k = "mesh12"
    out: list[Attempt] = []
    tri = [[0, 0, 0], [0.05, 0, 0], [0, 0.05, 0]]
    one = stl_corners([tri])
    # fmt: off
    cases: list[tuple[str, str, dict]] = [
        ("named sub/../a.stl (a '..' back to the URDF's folder)", "sub/../a.stl", {"a.stl": one, "sub/x": ""}),
        ("named sub/../a.stl, sub missing", "sub/../a.stl", {"a.stl": one}),
        ("named m/../../a.stl (one '..' above the URDF's folder)", "m/../../a.stl", {"m/x": ""}),
        ("named ../../../../../../../../dev/zero.stl", "../../../../../../../../dev/zero.stl", {}),
        ("named a link to .. then a.stl", "up/a.stl", {"up": ("->", "..")}),
        ("named /proc/self/cwd/a.stl (the URDF's folder by /proc)", "/proc/self/cwd/a.stl", {"a.stl": one}),
        ("named in NFD, the file in NFC (u-umlaut)", "u\u0308.stl", {"\u00fc.stl": one}),
        ("named with an emoji", "\U0001f916.stl", {"\U0001f916.stl": one}),
        ("named with a right-to-left override", "&#8238;ltsa.stl", {"\u202eltsa.stl": one}),
        ("named with a newline inside", "a&#10;b.stl", {"a\nb.stl": one}),
        ("named with an escaped ampersand", "a&amp;b.stl", {"a&b.stl": one}),
        ("named a%20b.stl, the file 'a b.stl'", "a%20b.stl", {"a b.stl": one}),
        ("named with a NUL character reference", "a&#0;.stl", {"a.stl": one}),
        ("named 4,096 characters long", "d/" * 2046 + "a.stl", {}),
        ("named with one 256-character part", "n" * 252 + ".stl", {}),
        ("named file:///proc/self/cwd/a.stl", "file:///proc/self/cwd/a.stl", {"a.stl": one}),
        ("named package://r/a.stl?x=1", "package://r/a.stl?x=1", {}),
        ("an OBJ under the name .stl", "a.stl", {"a.stl": obj_text(3)}),
        ("a binary STL under the name .obj", "a.obj", {"a.obj": one}),
        ("a COLLADA under the name .obj", "a.obj", {"a.obj": tri_dae()}),
        ("an ASCII STL of two solids", "a.stl", {"a.stl": ascii_stl(tri) * 2}),
        ("an ASCII STL without endsolid", "a.stl", {"a.stl": ascii_stl(tri).replace("endsolid\n", "")}),
        ("an OBJ face of index 2^63", "a.obj", {"a.obj": obj_text(3, "f 1 2 9223372036854775808\n")}),
        ("a COLLADA <p> index 99 of three corners", "a.dae", {"a.dae": tri_dae(p_indices="0 1 99")}),
        ("a COLLADA <p> index -1", "a.dae", {"a.dae": tri_dae(p_indices="-1 0 1")}),
        ("a COLLADA float_array of 'nan inf -inf'", "a.dae", {"a.dae": tri_dae(floats="nan inf -inf 0 0 0 0 0.05 0")}),
        ("a COLLADA node translate 1e308", "a.dae", {"a.dae": tri_dae(node="<translate>1e308 1e308 1e308</translate>")}),
        ("a COLLADA instance_geometry of another file", "a.dae", {"a.dae": tri_dae().replace('url="#g0"', 'url="b.dae#g0"'), "b.dae": tri_dae()}),
        ("a COLLADA polylist of vcount 0", "a.dae", {"a.dae": tri_dae().replace("<triangles", "<polylist").replace("</triangles>", "</polylist>").replace("<p>", "<vcount>0</vcount><p>")}),
        ("a COLLADA comment of 1 MB", "a.dae", {"a.dae": tri_dae().replace("<asset>", "<!--" + "x" * 1_000_000 + "--><asset>")}),
    ]
    # fmt: on
    for label, name, files in cases:
        # "&#0;" is no XML character: the URDF is refused (exit 2, FILE:LINE) before any picture
        out += fit_and_png(k, label, name, files, codes_png=(0, 2) if "&#0;" in name else (0,))
    for label, scale in (
        ("with spaces around it", "  1  1  1  "),
        ("inf 1 1", "inf 1 1"),
        ("1e308 1e308 1e308", "1e308 1e308 1e308"),
        ("a single space", " "),
    ):
        out += fit_and_png(k, f"a scale of {label}", "a.stl", {"a.stl": one}, scale=scale)
    # package:// through a package folder: robots --fit's flag and a scene's arm.package_dirs
    pkg_names = [
        ("package://r/a.stl, r a folder there", "package://r/a.stl", {"pk/r/a.stl": one}),
        ("package://r/../../s.yaml.stl", "package://r/../../s.yaml.stl", {"pk/r/x": ""}),
        ("package://r/a.stl, r a link to /dev", "package://r/zero.stl", {"pk/r": ("->", "/dev")}),
        ("package://r/a.stl, r a link to /", "package://r/etc/hostname.stl", {"pk/r": ("->", "/")}),
        ("package://../a.stl", "package://../a.stl", {"a.stl": one, "pk/x": ""}),
        ("package://r/a.stl, a.stl a FIFO", "package://r/a.stl", {"pk/r/a.stl": None}),
    ]
    for label, name, files in pkg_names:
        tag = f"<geometry><mesh filename={name!r}/></geometry>"
        out.append(
            Attempt(
                k,
                f"robots --fit --package-dir pk, collision {label}",
                [*FIT, "--package-dir", "pk"],
                urdf_robot(collision=f"<collision>{tag}</collision>", files=files),
                (0, 2),
                timeout=120,
                message_if_2=r"robot\.urdf:\d+: |pk",
            )
        )
        out.append(
            Attempt(
                k,
                f"run, arm.package_dirs [pk], visual {label}",
                ["run", "s.yaml", "--out", "o", "--no-video", "-q"],
                then(
                    urdf_robot(f"<visual>{tag}</visual>", files=files),
                    mine("s.yaml", URDF_SCENE.replace("{urdf: robot.urdf}", "{urdf: robot.urdf, package_dirs: [pk]}")),
                ),
                (0, 2),
                timeout=120,
                message_if_2=AT_LINE,
            )
        )

    # the look of a run: its copied URDF or look-folders.json edited by hand, then render and view
    def look_run(change: Callable[[Path], None]) -> Callable[[Path], None]:
        def setup(d: Path) -> None:
            write(d / "a.stl", one)
            urdf_robot(vis("a.stl"))(d)
            armanim_in(d, "run", "s.yaml", "--out", "o", "--no-video", "-q")
            change(d / "o" / "m")

        return setup

    def urdf_mesh(name: str) -> Callable[[Path], None]:
        return lambda run: write(run / "robot.urdf", urdf_text(vis(name)))

    def looks(text: str) -> Callable[[Path], None]:
        return lambda run: write(run / "look-folders.json", text)

    edits = [
        ("copied URDF names /dev/zero.stl by a '..' chain", urdf_mesh("../../../../../../../../dev/zero.stl")),
        ("copied URDF names a FIFO beside it", lambda run: (urdf_mesh("f.stl")(run), fifo(run / "f.stl"))),
        (
            "copied URDF names a 1 GB sparse STL beside it",
            lambda run: (urdf_mesh("big.stl")(run), sparse(run / "big.stl", 1 << 30)),
        ),
        ("look-folders.json points at /dev", looks('{"scene_folder": "/dev", "urdf_folder": "/dev"}')),
        ("look-folders.json not JSON", looks("{")),
        (
            "look-folders.json a FIFO",
            lambda run: (os.unlink(run / "look-folders.json"), fifo(run / "look-folders.json")),
        ),
    ]
    for label, change in edits:
        for cmd in (["render", "o/m", "-q", "--size", "64x48", "--out", "fig"], ["view", "o/m", "--out", "v.html"]):
            out.append(
                Attempt(
                    k,
                    f"{cmd[0]} of a run whose {label}",
                    cmd,
                    look_run(change),
                    (0, 2),
                    timeout=200,
                    message_if_2=r"o/m|robot\.urdf|look-folders",
                )
            )
    return out


def frames12_attempts() -> list[Attempt]:
    """``sweep --set`` at the edges of its own syntax (spaces, empty and repeated values, lists and
    mappings as values, indices written oddly, a key twice, names that collide), render flags
    campaigns 10 and 11 did not give, and fields at their bounds set through a sweep."""
    k = "frames12"
    out: list[Attempt] = []
    sweep = ["sweep", "s.yaml", "--out", "o", "-q", "--jobs", "1"]
    # fmt: off
    sets: list[list[str]] = [
        ["solver.step=0.1"],
        ["solver.step=0.1, 0.2"],
        ["solver.step=0.1,"],
        ["solver.step=,0.1"],
        ["solver.step=1e-400,0.1"],
        ["solver.step=0x10"],
        ["solver.step=true"],
        ["solver.step=.nan"],
        ["solver.step=0.1", "solver.step=0.2"],
        ["render.fps=10,10.0"],
        ["render.size=[64,48],[32,24]"],
        ["goals[0]=[1,1,1],[0.5,0.5,0.5]"],
        ["goals[1]={joints: [0, 0, 0]}"],
        ["arm.links=[1,1,1],[0.5,0.5,0.5,0.5]"],
        ["name=a,a"],
        ["name=x/y,z"],
        ["name=\u00e9,e\u0301"],
        ["name=" + "n" * 300],
        ["sölver.step=0.1"],
        ["solver..step=0.1"],
        ["solver.step.=0.1"],
        ["goals[00].hold=1"],
        ["goals[1e0].hold=1"],
        ["goals[0].hold=1e-300"],
        ["goals[0].hold=3600,3600.0001"],
        ["arm.max_joint_speed=1e308"],
        ["arm.max_joint_speed=[1e-9, 1e-9, 1e-9]"],
        ["solver.step==0.1"],
        ["solver.step=\u0660.\u0661"],
        ["solver.step=0.1\u00a0,0.2"],
        ["solver.step=&a 0.1"],
        ["solver.step=*a"],
        ["solver={step: 0.1}"],
        ["arm={links: [1, 1, 1]},{links: [1, 1]}"],
    ]
    # fmt: on
    for values in sets:
        args = [*sweep, *(a for v in values for a in ("--set", v))]
        out.append(
            Attempt(
                k,
                f"sweep --set {' --set '.join(values)}"[:110],
                args,
                tiny_scene(),
                (0, 1, 2),
                timeout=300,
                message_if_2="--set|s\\.yaml:\\d+",
                after=lambda d: [p for p in whole_or_none(*(f"o/{n}" for n in _listing(d / "o")))(d)],
            )
        )
    for flags in (
        ["--size", "64X48"],
        ["--size", "1e2x48"],
        ["--size", "64x48x3"],
        ["--size", "64x48", "--fps", "-1"],
        ["--size", "64x48", "--fps", "29.97"],
        ["--size", "64x48", "--fps", "inf"],
        ["--size", "64x48", "--azimuth", "-1e308", "--elevation", "-1e308"],
        ["--size", "3x3", "--format", "gif"],
        ["--size", "64x48", "--format", "mp4 "],
        ["--quality", "low", "--size", "64x48", "--fps", "5"],
    ):
        out.append(render_flags_attempt(k, flags))
    return out


def _listing(folder: Path) -> list[str]:
    """The names in ``folder`` that are not hidden (none if it is absent)."""
    return [n for n in os.listdir(folder) if not n.startswith(".")] if folder.is_dir() else []


def signals12_attempts() -> list[Attempt]:
    """Interrupts while an output armanim wrote before is being replaced (a golden pair, an export,
    a page: the old one must stay whole), during a large mesh's fit, fk's picture and a sweep's
    pool, and at start-up."""
    k = "signals12"
    out: list[Attempt] = []
    out += at_moments(
        k,
        "check --update replacing a 40,000-frame golden",
        ["check", "s.yaml", "--golden", "g", "--update"],
        then(tiny_scene(text=LONG), lambda d: armanim_in(d, "check", "s.yaml", "--golden", "g", "--update")),
        ((2.0, "SIGINT"), (3.0, "SIGTERMG"), (4.5, "SIGTERM")),
        timeout=300,
        after=whole_or_none("g/tiny.csv", "g/tiny.json"),
        litter_in=("g", "."),
    )

    def long_run_and(*args: str) -> Callable[[Path], None]:
        return then(lambda d: finished_run(d, LONG), lambda d: armanim_in(d, *args))

    out += at_moments(
        k,
        "export replacing its own earlier export of a 40,000-frame run",
        ["export", "o/tiny", "--out", "e.json"],
        long_run_and("export", "o/tiny", "--out", "e.json"),
        ((0.5, "SIGINT"), (1.0, "SIGTERM"), (1.5, "SIGTERMG")),
        timeout=200,
        after=whole_or_none("e.json"),
        litter_in=("o", "."),
    )
    out += at_moments(
        k,
        "view replacing its own earlier page of a 40,000-frame run",
        ["view", "o/tiny", "--out", "v.html"],
        long_run_and("view", "o/tiny", "--out", "v.html"),
        ((1.0, "SIGINT"), (2.0, "SIGTERMG")),
        timeout=200,
        after=whole_or_none("v.html"),
        litter_in=("o", "."),
    )

    def big_collision(d: Path) -> None:
        big_stl(d / "a.stl", 1_500_000)
        urdf_robot(collision=col("a.stl"))(d)

    out += at_moments(
        k,
        "robots --fit of a 1.5-million-triangle STL",
        FIT,
        big_collision,
        ((1.0, "SIGINT"), (2.0, "SIGTERMG"), (3.0, "SIGINT")),
        codes=(0, 2, 130),
        timeout=200,
    )
    out += at_moments(
        k,
        "fk --robot panda --png",
        ["fk", "--robot", "panda", "--angles", "0,-20,0,-120,0,100,45", "--png", "p.png"],
        lambda d: None,
        ((0.5, "SIGINT"), (1.5, "SIGINT"), (2.5, "SIGTERMG")),
        timeout=120,
        litter_in=(".",),
    )
    out += at_moments(
        k,
        "sweep --jobs 2 of 4 variants",
        ["sweep", "s.yaml", "--set", "solver.step=0.05,0.1,0.15,0.2", "--out", "o", "-q", "--jobs", "2"],
        tiny_scene(),
        ((1.5, "SIGTERMG"), (3.0, "SIGTERMG"), (2.2, "SIGTERM")),
        timeout=300,
        after=lambda d: whole_or_none(*(f"o/{n}" for n in _listing(d / "o")))(d),
    )
    out += at_moments(
        k,
        "ik --robot ur5 at start-up",
        ["ik", "--robot", "ur5", "--goal", "0.3,0.2,0.4"],
        lambda d: None,
        ((0.2, "SIGTERM"), (0.4, "SIGINT")),
        codes=(0, 1, 130),
        timeout=120,
    )
    return out


def loss12_attempts() -> list[Attempt]:
    """Golden pairs with the user's files at either name (links, hard links, folders, FIFOs, files
    in the golden's shape), two scenes of one name into one golden folder, exports onto files
    armanim marked and the user changed since, and writers aimed into a run folder by paths
    that spell it another way."""
    k = "loss12"
    update = ["check", "s.yaml", "--golden", "g", "--update"]
    export = ["export", "o/tiny", "--out", "e.json"]
    scene = mine("s.yaml", TINY)
    golden = then(scene, lambda d: armanim_in(d, *update))
    exported = then(finished_run, lambda d: armanim_in(d, *export))
    head = "frame,time_s,goal,phi1_deg\n0,0.0,0,1.0\n"  # the shape of armanim's CSV, the user's numbers
    meta = '{\n  "armanim_version": "mine"\n}\n'

    def gone(path: str) -> Callable[[Path], None]:
        return lambda d: os.unlink(d / path)

    def two_of_one_name(d: Path) -> None:
        write(d / "a/s.yaml", TINY)
        write(d / "b/s.yaml", TINY.replace("[0.5, -1, 1]", "[0.5, -1, 1.3]"))

    # one attempt a row: label, arguments, setup, exit codes, the user's paths kept
    # fmt: off
    table: list[tuple] = [
        ("check --update, g/tiny.json a hard link to the user's JSON of armanim's shape", update, then(scene, mine("mine.json", meta), lambda d: (d / "g").mkdir(), hardlink("mine.json", "g/tiny.json")), (0, 3), ("mine.json",)),
        ("check --update, g/tiny.json a folder of the user's", update, then(scene, mine("g/tiny.json/notes.txt")), (2, 3), ("g/tiny.json",)),
        ("check --update, g/tiny.csv a folder of the user's", update, then(scene, mine("g/tiny.csv/notes.txt")), (2, 3), ("g/tiny.csv",)),
        ("check --update, g/tiny.json a FIFO", update, then(scene, lambda d: fifo(d / "g/tiny.json")), (2, 3), ("g/tiny.json",)),
        ("check --update, g/tiny.csv a FIFO", update, then(scene, lambda d: fifo(d / "g/tiny.csv")), (2, 3), ("g/tiny.csv",)),
        ("check --update, g/tiny.csv a dangling link", update, then(scene, symlink("../nowhere.csv", "g/tiny.csv")), (0, 3), ("g/tiny.csv",)),
        ("check --update, g/tiny.json the user's, g/tiny.csv absent", update, then(scene, mine("g/tiny.json", '{"mine": 1}\n')), (3,), ("g/tiny.json",)),
        ("check --update, the user's CSV in UTF-16 at g/tiny.csv", update, then(scene, lambda d: write(d / "g/tiny.csv", head.encode("utf-16")) and None), (3,), ("g/tiny.csv",)),
        ("check --update, the user's CSV with a BOM at g/tiny.csv", update, then(scene, mine("g/tiny.csv", "\ufeff" + head)), (3,), ("g/tiny.csv",)),
        ("check --update, the user's CSV of CRLF rows at g/tiny.csv", update, then(scene, mine("g/tiny.csv", "frame\r\n0\r\n")), (3,), ("g/tiny.csv",)),
        ("check --update, armanim's golden CSV beside the user's JSON", update, then(golden, mine("g/tiny.json", '{"mine": 1}\n')), (3,), ("g/tiny.json", "g/tiny.csv")),
        ("check --update, the user's empty g/tiny.json", update, then(scene, mine("g/tiny.json", "")), (0, 3), ("g/tiny.json",)),
        ("check --update, g a link to the user's file", update, then(scene, mine("mine.txt"), symlink("mine.txt", "g")), (2, 3), ("mine.txt",)),
        ("check --update, g/tiny.json a link to /dev/null", update, then(scene, symlink("/dev/null", "g/tiny.json")), (0, 2, 3), ()),
        ("check --update, the golden's first line armanim's and the rest the user's", update, then(golden, lambda d: write(d / "g/tiny.csv", (d / "g/tiny.csv").read_text().split("\n", 1)[0] + "\nmy,own,notes\n") and None), (0, 3), ()),
        ("check (no update), g/tiny.csv a link to /dev/zero", ["check", "s.yaml", "--golden", "g"], then(golden, gone("g/tiny.csv"), symlink("/dev/zero", "g/tiny.csv")), (1, 2), ()),
        ("export --out e.json, armanim's export edited by the user since", export, then(exported, edit("e.json", b"\n")), (3,), ("e.json",)),
        ("export --out e.json, armanim's export with its mark deleted", export, then(exported, gone(".e.json.armanim.json")), (3,), ("e.json",)),
        ("export --out e.json, the export replaced by the user's file of its size", export, then(exported, lambda d: write(d / "e.json", b" " * (d / "e.json").stat().st_size) and None), (3,), ("e.json",)),
        ("export --out e.json, its mark a hard link to the user's file", export, then(exported, mine("keep.json", "{}\n"), gone(".e.json.armanim.json"), hardlink("keep.json", ".e.json.armanim.json")), (0, 3), ("keep.json",)),
        ("export --out e.json, e.json a link to the user's JSON, its mark armanim's", export, then(exported, mine("keep.json", "{}\n"), gone("e.json"), symlink("keep.json", "e.json")), (0, 2, 3), ("keep.json",)),
        ("export --out o/tiny/./e.json (into the run folder)", ["export", "o/tiny", "--out", "o/tiny/./e.json"], finished_run, (2, 3), ("o/tiny",)),
        ("export --out o//tiny//e.json (into the run folder)", ["export", "o/tiny", "--out", "o//tiny//e.json"], finished_run, (2, 3), ("o/tiny",)),
        ("export --out o/x/../tiny/e.json (into the run folder)", ["export", "o/tiny", "--out", "o/x/../tiny/e.json"], then(finished_run, lambda d: (d / "o/x").mkdir()), (2, 3), ("o/tiny",)),
        ("export --out the run folder's .armanim-run.json", ["export", "o/tiny", "--out", "o/tiny/.armanim-run.json"], finished_run, (2, 3), ("o/tiny",)),
        ("export --out the golden CSV armanim wrote", ["export", "o/tiny", "--out", "g/tiny.csv"], then(finished_run, lambda d: armanim_in(d, *update)), (2, 3), ("g",)),
        ("export --out the user's ROS trajectory in YAML", ["export", "o/tiny", "--out", "mine.yaml"], then(finished_run, mine("mine.yaml", "joint_names: [a]\npoints: []\n")), (2, 3), ("mine.yaml",)),
        ("export --out the user's ROS trajectory of another name case E.json", ["export", "o/tiny", "--out", "E.json"], then(exported, mine("E.json", '{"joint_names": ["a"], "points": []}\n')), (3,), ("E.json",)),
        ("schema --out the golden JSON armanim wrote", ["schema", "--out", "g/tiny.json"], golden, (2, 3), ("g",)),
        ("view --out the golden CSV armanim wrote", ["view", "o/tiny", "--out", "g/tiny.csv"], then(finished_run, lambda d: armanim_in(d, *update)), (2, 3), ("g",)),
        ("import moveit --out an export armanim wrote", ["import", "moveit", "w.scene", "--robot", "panda", "--out", "e.json"], then(exported, mine("w.scene", "w\n* b\n1\nbox\n0.1 0.1 0.1\n1 1 1\n0 0 0 1\n0 0 0 0\n.\n")), (2, 3), ("e.json",)),
        ("fk --png onto an export armanim wrote", ["fk", "--angles", "0,0,0,0", "--png", "e.json"], exported, (2, 3), ("e.json",)),
        ("render --out a folder holding the user's tiny.mp4", ["render", "o/tiny", "-q", "--size", "64x48", "--out", "mine"], then(finished_run, mine("mine/tiny.mp4", "not a video")), (0, 2, 3), ("mine/tiny.mp4",)),
        ("run again, the run folder's trajectory.csv a hard link to the user's golden", ["run", "s.yaml", "--out", "o", "--no-video", "-q"], then(finished_run, lambda d: armanim_in(d, *update), gone("o/tiny/trajectory.csv"), hardlink("g/tiny.csv", "o/tiny/trajectory.csv"), mine("s.yaml", TINY.replace("[0.5, -1, 1]", "[0.5, -1, 1.2]"))), (0, 3), ("g/tiny.csv",)),
        ("check --update, the golden CSV a hard link to the run's trajectory", update, then(finished_run, lambda d: (d / "g").mkdir(), hardlink("o/tiny/trajectory.csv", "g/tiny.csv"), mine("s.yaml", TINY.replace("[0.5, -1, 1]", "[0.5, -1, 1.2]"))), (0, 3), ("o/tiny/trajectory.csv",)),
        ("sweep --out g (a golden folder)", ["sweep", "s.yaml", "--set", "solver.step=0.1,0.2", "-q", "--jobs", "1", "--out", "g"], golden, (0, 2, 3), ("g/tiny.csv", "g/tiny.json")),
        ("run --out g (a golden folder) of a scene named tiny.csv", ["run", "s.yaml", "--out", "g", "--no-video", "-q"], then(golden, mine("s.yaml", TINY.replace("name: tiny", "name: tiny.csv"))), (0, 2, 3), ("g/tiny.csv",)),
    ]
    # fmt: on
    out = [Attempt(k, label, args, setup, codes, keep=keep, timeout=300) for label, args, setup, codes, keep in table]
    # a link at a golden's name to a file of armanim's shape: written through, the link kept
    # (docs/reliability.md: "A symbolic link is written through: its target is replaced")
    for label, name, text in (("JSON", "tiny.json", meta), ("CSV", "tiny.csv", head)):
        out.append(
            Attempt(
                k,
                f"check --update, g/{name} a link to the user's {label} of armanim's shape",
                update,
                then(scene, mine(f"mine.{label.lower()}", text), symlink(f"../mine.{label.lower()}", f"g/{name}")),
                (0,),
                timeout=300,
                after=lambda d, name=name: [] if os.path.islink(d / "g" / name) else [f"g/{name} is no longer a link"],
            )
        )
    out.append(
        Attempt(
            k,
            "check --update of two scenes of one name into one golden folder",
            ["check", "a/s.yaml", "b/s.yaml", "--golden", "g", "--update"],
            two_of_one_name,
            (0, 2),
            timeout=300,
            after=golden_holds("a/s.yaml", "b/s.yaml"),
        )
    )
    return out


def golden_holds(*scenes: str) -> Callable[[Path], list[str]]:
    """After a ``check --update`` that said it wrote: a plain ``check`` of the same scenes passes."""

    def check(d: Path) -> list[str]:
        if not (d / "g").is_dir():
            return []
        done = subprocess.run(
            [sys.executable, "-m", "armanim", "check", *scenes, "--golden", "g", "-q"],
            cwd=d,
            env=dict(os.environ, PYTHONPATH=str(SRC)),
            capture_output=True,
            text=True,
            timeout=300,
        )
        return (
            []
            if done.returncode == 0
            else [f"the goldens just written fail check: exit {done.returncode}: {done.stdout[-200:]}"]
        )

    return check


MOVEIT_BOX = (
    "world:\n  collision_objects:\n    - id: b\n      header: {frame_id: panda_link0}\n"
    "      primitives:\n        - {type: box, dimensions: [0.1, 0.1, 0.1]}\n"
    "      primitive_poses:\n        - {position: [0.5, 0.3, 0.6], orientation: [0, 0, 0, 1]}\n"
    "robot_state:\n  joint_state: {name: [panda_joint1], position: [0.1]}\n"
)
"""A MoveIt planning scene (YAML) of one box, the base of inputs12's variants."""
MOVEIT_REQUEST = (
    "group_name: panda_arm\nstart_state:\n  joint_state: {name: [panda_joint1], position: [0.2]}\n"
    "goal_constraints:\n  - joint_constraints:\n"
    + "".join(
        f"      - {{joint_name: panda_joint{i}, position: {p}}}\n"
        for i, p in enumerate([0, -0.5, 0, -2, 0, 1.6, 0.8], 1)
    )
)
"""A MoveIt motion plan request: a joint goal of the Panda."""


def inputs12_attempts() -> list[Attempt]:
    """Hostile CSVs given to compare and check (as the golden), MoveIt planning scenes and requests
    in YAML at the edges of their messages, and a run folder's files edited by hand in ways
    campaign 11 did not (extra and missing columns, its marker, the scene's fields) read back by
    render, view and export. Exit 0 (or 1, a difference), or 2 naming the file."""
    k = "inputs12"
    out: list[Attempt] = []
    # fmt: off
    csv_edits: list[tuple[str, Callable[[str], str | bytes]]] = [
        ("one row fewer", lambda t: t[: t.rstrip("\n").rindex("\n") + 1]),
        ("spaces after the commas", lambda t: t.replace(",", ", ")),
        ("a trailing comma on every row", lambda t: t.replace("\n", ",\n")),
        ("its columns in another order", lambda t: "\n".join(",".join([r.split(",")[1], r.split(",")[0], *r.split(",")[2:]]) for r in t.rstrip("\n").split("\n")) + "\n"),
        ("numbers in quotes", lambda t: "\n".join([t.split("\n")[0]] + [",".join(f'"{c}"' for c in r.split(",")) for r in t.split("\n")[1:] if r]) + "\n"),
        ("-0.0 for every 0.0", lambda t: t.replace(",0.0,", ",-0.0,")),
        ("an angle of 1e-400", lambda t: _set_cell(t, 2, 3, "1e-400")),
        ("an angle of NaN on one side only", lambda t: _set_cell(t, 2, 3, "nan")),
        ("the header in capitals", lambda t: t.split("\n", 1)[0].upper() + "\n" + t.split("\n", 1)[1]),
        ("CR line ends only", lambda t: t.replace("\n", "\r")),
        ("latin-1 in an extra column's name", lambda t: t.replace("\n", ",caf\xe9\n", 1).encode("latin-1")),
        ("a NUL inside a number", lambda t: _set_cell(t, 2, 3, "0.\x005")),
        ("a gzip of itself", lambda t: __import__("gzip").compress(t.encode())),
        ("a 1 MB cell", lambda t: _set_cell(t, 2, 14, "x" * 1_000_000)),
    ]
    # fmt: on
    for label, change in csv_edits:

        def compared(d: Path, change=change) -> None:
            text = (finished_run(d) / "trajectory.csv").read_text()
            write(d / "a.csv", text)
            write(d / "e.csv", change(text))

        def golden(d: Path, change=change) -> None:
            write(d / "s.yaml", TINY)
            armanim_in(d, "check", "s.yaml", "--golden", "g", "--update")
            write(d / "g/tiny.csv", change((d / "g/tiny.csv").read_text()))

        out.append(
            Attempt(
                k,
                f"compare, {label}",
                ["compare", "a.csv", "e.csv"],
                compared,
                (0, 1, 2),
                timeout=120,
                message_if_2=r"[ae]\.csv\b",  # FILE:LINE, or "ACTUAL: lacks the column C that EXPECTED has"
            )
        )
        out.append(
            Attempt(
                k,
                f"check against a golden CSV of {label}",
                ["check", "s.yaml", "--golden", "g"],
                golden,
                (0, 1, 2),
                timeout=120,
                message_if_2=r"g/tiny\.csv\b",
            )
        )
    box = MOVEIT_BOX
    # fmt: off
    scenes = [
        ("a primitive of type 4 (a cone)", box.replace("type: box", "type: 4")),
        ("a primitive of type BOX in capitals", box.replace("type: box", "type: BOX")),
        ("a primitive of type 0", box.replace("type: box", "type: 0")),
        ("a primitive of type true", box.replace("type: box", "type: true")),
        ("a box of no dimensions", box.replace("[0.1, 0.1, 0.1]", "[]")),
        ("a box of a negative edge", box.replace("[0.1, 0.1, 0.1]", "[0.1, -0.1, 0.1]")),
        ("a sphere of radius 0", box.replace("{type: box, dimensions: [0.1, 0.1, 0.1]}", "{type: sphere, dimensions: [0]}")),
        ("a cylinder of three dimensions", box.replace("{type: box, dimensions: [0.1, 0.1, 0.1]}", "{type: cylinder, dimensions: [0.1, 0.1, 0.1]}")),
        ("two primitives and one pose", box.replace("        - {type: box", "        - {type: sphere, dimensions: [0.05]}\n        - {type: box")),
        ("no primitive and one pose", box.replace("        - {type: box, dimensions: [0.1, 0.1, 0.1]}\n", "").replace("primitives:\n", "primitives: []\n")),
        ("an orientation of zeros", box.replace("orientation: [0, 0, 0, 1]", "orientation: [0, 0, 0, 0]")),
        ("an orientation mapping without w", box.replace("orientation: [0, 0, 0, 1]", "orientation: {x: 0, y: 0, z: 0}")),
        ("a position mapping of x only", box.replace("position: [0.5, 0.3, 0.6]", "position: {x: 0.5}")),
        ("a frame_id no link has", box.replace("frame_id: panda_link0", "frame_id: nosuch")),
        ("an empty frame_id", box.replace("frame_id: panda_link0", "frame_id: ''")),
        ("two objects of one id", box.replace("    - id: b\n", "    - id: b\n      primitives: [{type: sphere, dimensions: [0.05]}]\n      primitive_poses: [{position: [0.5, -0.3, 0.6]}]\n    - id: b\n")),
        ("an id with a newline and a colon", box.replace("id: b", 'id: "b\\n: c"')),
        ("operation 1 (REMOVE)", box.replace("    - id: b\n", "    - id: b\n      operation: 1\n")),
        ("collision_objects null", "world:\n  collision_objects: null\n"),
        ("collision_objects a mapping", "world:\n  collision_objects: {id: b}\n"),
        ("a mesh and its pose", box.replace("      primitives:", "      meshes: [{triangles: [{vertex_indices: [0, 1, 2]}], vertices: [{x: 0, y: 0, z: 0}, {x: 1, y: 0, z: 0}, {x: 0, y: 1, z: 0}]}]\n      mesh_poses: [{position: [0, 0, 0]}]\n      primitives:")),
        ("joint positions longer than names", box.replace("position: [0.1]}", "position: [0.1, 0.2, 0.3]}")),
        ("a joint position of .inf", box.replace("position: [0.1]}", "position: [.inf]}")),
        ("world a list", "world: [1, 2]\n"),
        ("is_diff true and nothing else", "is_diff: true\n"),
    ]
    requests = [
        ("goal_constraints empty", MOVEIT_REQUEST.split("goal_constraints")[0] + "goal_constraints: []\n"),
        ("a joint constraint of an unknown joint", MOVEIT_REQUEST.replace("panda_joint7", "nosuch")),
        ("a joint constraint position .nan", MOVEIT_REQUEST.replace("position: 0.8", "position: .nan")),
        ("a group_name no SRDF has", MOVEIT_REQUEST.replace("group_name: panda_arm", "group_name: nosuch")),
        ("goal_constraints a mapping", MOVEIT_REQUEST.split("goal_constraints")[0] + "goal_constraints: {joint_constraints: []}\n"),
        ("a position constraint without a region", MOVEIT_REQUEST.split("goal_constraints")[0] + "goal_constraints:\n  - position_constraints:\n      - {link_name: panda_link8, header: {frame_id: panda_link0}}\n"),
        ("an orientation constraint of .nan", MOVEIT_REQUEST.split("goal_constraints")[0] + "goal_constraints:\n  - position_constraints:\n      - link_name: panda_link8\n        header: {frame_id: panda_link0}\n        constraint_region: {primitive_poses: [{position: [0.4, 0, 0.5]}]}\n    orientation_constraints:\n      - {link_name: panda_link8, orientation: {x: .nan, y: 0, z: 0, w: 1}}\n"),
    ]
    # fmt: on
    importing = ["import", "moveit", "w.yaml", "--robot", "panda", "--out", "m.yaml"]
    for label, text in scenes:
        out.append(
            Attempt(
                k,
                f"import moveit, a YAML planning scene with {label}",
                importing,
                lambda d, text=text: write(d / "w.yaml", text) and None,
                (0, 2),
                timeout=120,
                message_if_2=r"w\.yaml:(\d+:)? ",
            )
        )
    for label, text in requests:
        out.append(
            Attempt(
                k,
                f"import moveit, a request with {label}",
                [*importing, "--request", "r.yaml"],
                lambda d, text=text: (write(d / "w.yaml", MOVEIT_BOX), write(d / "r.yaml", text)) and None,
                (0, 2),
                timeout=120,
                message_if_2=r"(w|r)\.yaml:(\d+:)? ",
            )
        )
    # fmt: off
    run_files = [
        ("marker's made_by another program", ".armanim-run.json", lambda t: t.replace('"made_by": "armanim"', '"made_by": "me"')),
        ("marker deleted", ".armanim-run.json", None),
        ("trajectory.csv with a column of the user's added", "trajectory.csv", lambda t: "\n".join(r + (",mine" if r else "") for r in t.split("\n"))),
        ("trajectory.csv without its phi2_deg column", "trajectory.csv", lambda t: "\n".join(",".join(c for i, c in enumerate(r.split(",")) if i != 4) for r in t.split("\n"))),
        ("trajectory.csv of one row", "trajectory.csv", lambda t: "\n".join(t.split("\n")[:2]) + "\n"),
        ("trajectory.csv with a NaN angle", "trajectory.csv", lambda t: _set_cell(t, 3, 4, "nan")),
        ("scene.yaml with a sphere of radius 1e9 added", "scene.yaml", lambda t: t + "obstacles: [{center: [0, 0, 0], radius: 1e9}]\n"),
        ("scene.yaml naming arm.urdf /dev/zero", "scene.yaml", lambda t: t.replace("{links: [1, 1, 1]}", "{urdf: /dev/zero}")),
        ("scene.yaml in UTF-16", "scene.yaml", lambda t: t.encode("utf-16")),
        ("summary.json with 10,000 goals", "summary.json", lambda t: '{"goals": [' + ", ".join(['{"reached": true}'] * 10_000) + "]}"),
    ]
    # fmt: on
    # render --out fig reads the run without writing into it (the folder holds an edit: exit 3 there)
    out += read_back_attempts(k, run_files, ["--size", "64x48", "--out", "fig"], (0, 2, 3))
    return out


WRONG12_KINDS = ("edge", "joints", "text", "arc", "polyline", "hold")
"""wrong12's goal kinds: joint goals at their limits' edge and within, text, arcs, polylines, holds."""


def moved_cell(row: int, column: int, by: float | None) -> Callable[[Path], None]:
    """Setup: a finished run's CSV as a.csv, and e.csv with one cell moved by ``by`` (None: a
    ``reached`` 0 made 1)."""

    def setup(d: Path) -> None:
        text = (finished_run(d) / "trajectory.csv").read_text()
        write(d / "a.csv", text)
        cell = text.split("\n")[row].split(",")[column]
        write(d / "e.csv", _set_cell(text, row, column, "1" if by is None else repr(float(cell) + by)))

    return setup


def wrong12_attempts() -> list[Attempt]:
    """Random arms with joint goals at their limits' edge, text, arcs and polylines (new seeds);
    ik from given starts and fk in radians against the campaign's own kinematics; compare's
    verdict against the size of the difference it is given."""
    import numpy as np

    k = "wrong12"
    out = random_arm_runs(k, range(300, 316), " with joint goals at their limits and text", WRONG12_KINDS)
    rng = np.random.default_rng(12)
    out += [random_fk_attempt(k, i, rng, 13, 6, radians=True) for i in range(4)]
    for i in range(8):
        links, goal = random_reachable_goal(rng)
        start = [round(float(x), 2) for x in rng.uniform(-170, 170, len(links))]
        method = str(rng.choice(["pinv", "dls", "newton", "gradient"]))
        out.append(
            Attempt(
                k,
                f"ik of a random {len(links)}-link arm by {method} from a random start ({i}), held to the oracle",
                ik_args(links, goal, method, start),
                lambda d: None,
                (0, 1),
                timeout=200,
                after=ik_breaks(links, goal, method, start),
            )
        )
    # compare's verdict: the frame-2 cells of tiny's CSV moved by more or less than its tolerance
    for label, setup, flags, code in (
        ("phi1 moved by 2e-6 deg (twice its tolerance)", moved_cell(2, 3, 2e-6), [], 1),
        ("phi1 moved by 5e-7 deg (half its tolerance)", moved_cell(2, 3, 5e-7), [], 0),
        ("phi2 moved by 5e-4 deg under --atol-deg 1e-3", moved_cell(2, 4, 5e-4), ["--atol-deg", "1e-3"], 0),
        ("phi2 moved by 2e-3 deg under --atol-deg 1e-3", moved_cell(2, 4, 2e-3), ["--atol-deg", "1e-3"], 1),
        ("x moved by 2e-6 (twice its tolerance)", moved_cell(2, 6, 2e-6), [], 1),
        ("reached 0 made 1", moved_cell(2, 11, None), [], 1),
    ):
        out.append(Attempt(k, f"compare, {label}", ["compare", "a.csv", "e.csv", *flags], setup, (code,), timeout=120))
    return out


def _set_cell(text: str, row: int, column: int, value: str) -> str:
    """``text`` (a CSV) with one cell replaced."""
    lines = text.split("\n")
    cells = lines[row].split(",")
    cells[column] = value
    lines[row] = ",".join(cells)
    return "\n".join(lines)


def _swap_two_rows(path: Path) -> None:
    lines = path.read_text().splitlines(keepends=True)
    lines[5], lines[6] = lines[6], lines[5]
    path.write_text("".join(lines))


# ------------------------------------------------------------------ the thirteenth campaign
#
# New attacks on the same classes again (issue 50: "the next campaign must come back clean"), none
# a repeat of the ninth to twelfth: mesh13, frames13, signals13, loss13, inputs13, wrong13. Most of
# its attempts hold a result to an oracle (the same geometry read from every format fits the same
# capsules; the clock's times and frame counts agree with each other; a second command after a
# killed one works and tidies), so a silent wrong answer is a miss, not only a traceback.

BOX_CORNERS = [(x, y, z) for z in (0.0, 0.3) for y in (-0.05, 0.05) for x in (-0.05, 0.05)]
"""A 0.1 x 0.1 x 0.3 box's corners: index = x + 2 y + 4 z (each 0 or 1)."""
BOX_QUADS = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
"""The box's six faces, each a quad; its triangles are (a, b, c) and (a, c, d) of each quad (a fan)."""
BOX_TRIANGLES = [t for a, b, c, e in BOX_QUADS for t in ((a, b, c), (a, c, e))]


def box_points(scale: float = 1.0, shift: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> list[list[float]]:
    return [[(c + s) * scale for c, s in zip(corner, shift)] for corner in BOX_CORNERS]


def box_stl(scale: float = 1.0, shift=(0.0, 0.0, 0.0), normals: float = 0.0, attr: int = 0) -> bytes:
    """The box as a binary STL (``normals`` written in every normal, ``attr`` in every attribute)."""
    import numpy as np

    pts = box_points(scale, shift)
    records = np.zeros(len(BOX_TRIANGLES), dtype=[("normal", "<f4", 3), ("v", "<f4", (3, 3)), ("attr", "<u2")])
    records["v"] = [[pts[i] for i in t] for t in BOX_TRIANGLES]
    records["normal"] = normals
    records["attr"] = attr
    return b"\0" * 80 + np.uint32(len(BOX_TRIANGLES)).tobytes() + records.tobytes()


def box_ascii_stl(normal: str = "0 0 0") -> str:
    pts = box_points()
    return (
        "solid box\n"
        + "".join(
            f" facet normal {normal}\n  outer loop\n"
            + "".join("   vertex {} {} {}\n".format(*pts[i]) for i in t)
            + "  endloop\n endfacet\n"
            for t in BOX_TRIANGLES
        )
        + "endsolid box\n"
    )


def box_obj(faces: str = "tri", newline: str = "\n", sep: str = " ") -> str:
    """The box as an OBJ: ``faces`` tri (plain indices), quad (one face a quad), slash (v/vt/vn),
    negative (relative indices)."""
    lines = [sep.join(["v", *map(repr, p)]) for p in box_points()]
    if faces == "slash":
        lines += ["vt 0 0", "vn 0 0 1"]
    if faces == "quad":
        lines += [sep.join(["f", *(str(i + 1) for i in q)]) for q in BOX_QUADS]
    for t in BOX_TRIANGLES if faces != "quad" else []:
        if faces == "slash":
            lines.append(sep.join(["f", *(f"{i + 1}/1/1" for i in t)]))
        elif faces == "negative":  # every vertex precedes the faces: index -8 is vertex 1
            lines.append(sep.join(["f", *(str(i - 8) for i in t)]))
        else:
            lines.append(sep.join(["f", *(str(i + 1) for i in t)]))
    return newline.join(lines) + newline


def box_dae(kind: str = "triangles", unit: str = "1", scale: float = 1.0, node: str = "", shift=(0.0, 0.0, 0.0)) -> str:
    """The box as COLLADA: ``kind`` triangles, normals (a NORMAL input at offset 1), polylist (quads)."""
    floats = " ".join(repr(c) for p in box_points(scale, shift) for c in p)
    source = (
        f'<source id="p"><float_array id="a" count="24">{floats}</float_array><technique_common>'
        '<accessor source="#a" count="8" stride="3"><param name="X" type="float"/><param name="Y" type="float"/>'
        '<param name="Z" type="float"/></accessor></technique_common></source>'
    )
    normal = (
        '<source id="n"><float_array id="na" count="3">0 0 1</float_array><technique_common>'
        '<accessor source="#na" count="1" stride="3"><param name="X" type="float"/><param name="Y" type="float"/>'
        '<param name="Z" type="float"/></accessor></technique_common></source>'
    )
    vertex = '<input semantic="VERTEX" source="#v" offset="0"/>'
    if kind == "polylist":
        prim = (
            f'<polylist count="6">{vertex}<vcount>{" ".join(["4"] * 6)}</vcount>'
            f"<p>{' '.join(str(i) for q in BOX_QUADS for i in q)}</p></polylist>"
        )
    elif kind == "normals":
        prim = (
            f'<triangles count="12">{vertex}<input semantic="NORMAL" source="#n" offset="1"/>'
            f"<p>{' '.join(f'{i} 0' for t in BOX_TRIANGLES for i in t)}</p></triangles>"
        )
    else:
        prim = f'<triangles count="12">{vertex}<p>{" ".join(str(i) for t in BOX_TRIANGLES for i in t)}</p></triangles>'
    return (
        '<?xml version="1.0"?><COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">'
        f'<asset><unit meter="{unit}"/><up_axis>Z_UP</up_axis></asset><library_geometries><geometry id="g"><mesh>'
        f'{source}{normal if kind == "normals" else ""}<vertices id="v"><input semantic="POSITION" source="#p"/></vertices>'
        f"{prim}</mesh></geometry></library_geometries>"
        f'<library_visual_scenes><visual_scene id="s"><node id="n0">{node}<instance_geometry url="#g"/></node>'
        '</visual_scene></library_visual_scenes><scene><instance_visual_scene url="#s"/></scene></COLLADA>'
    )


def urdf_links(collisions: dict[int, str] | None = None, visuals: dict[int, str] | None = None) -> str:
    """:func:`urdf_text`'s robot with link ``i``'s collision and visual given (a cylinder elsewhere)."""
    text = urdf_text()
    for i, tag in (collisions or {}).items():
        old = text[text.index(f'<link name="l{i}">') :].split("</link>", 1)[0]
        text = text.replace(old, f'<link name="l{i}">{(visuals or {}).get(i, "")}{tag}')
    for i, tag in (visuals or {}).items():
        if i not in (collisions or {}):
            text = text.replace(f'<link name="l{i}">', f'<link name="l{i}">{tag}', 1)
    return text


def capsule_lines(text: str) -> list[list[float]]:
    """The numbers of each capsule line of ``robots --fit``'s answer."""
    return [
        [float(x) for x in re.findall(r"-?\d+(?:\.\d+)?(?:e-?\d+)?", line.split("from:", 1)[1])]
        for line in text.splitlines()
        if "from:" in line
    ]


def fit_of(d: Path, urdf: str, env: dict | None = None) -> str:
    done = subprocess.run(
        [sys.executable, "-m", "armanim", "robots", "--fit", urdf],
        cwd=d,
        env=dict(os.environ, PYTHONPATH=str(SRC), **(env or {})),
        capture_output=True,
        text=True,
        timeout=300,
    )
    return done.stdout if done.returncode == 0 else f"exit {done.returncode}: {done.stderr[-200:]}"


def same_fit(urdf: str, reference: str, tol: float = 2e-6, env: dict | None = None) -> Callable[[Path], list[str]]:
    """After: ``robots --fit URDF`` gives the capsules ``robots --fit REFERENCE`` gives (the same
    geometry written another way), number for number within ``tol``."""

    def check(d: Path) -> list[str]:
        got, want = fit_of(d, urdf, env), fit_of(d, reference, env)
        a, b = capsule_lines(got), capsule_lines(want)
        if not a or len(a) != len(b) or any(len(x) != len(y) for x, y in zip(a, b)):
            return [f"the fit of {urdf} is not the reference's: {got[-160:]!r} vs {want[-160:]!r}"]
        worst = max(abs(x - y) for u, v in zip(a, b) for x, y in zip(u, v))
        return [] if worst <= tol else [f"the fit of {urdf} differs from {reference}'s by {worst:.3g} m"]

    return check


def mesh13_attempts() -> list[Attempt]:
    """One box written in every way the readers take (STL binary and ASCII, OBJ of quads, slashes,
    relative indices, CRLF and tabs; COLLADA of normals at an offset, polylists, units, node
    transforms; URDF scales and origins) must fit the capsules of the plain STL; one file named at
    two scales; a cache folder or entry that is no regular file, or another mesh's; the URDF's and
    the scene's folder against a decoy in the working folder; the user's meshes changed after a run,
    read back by render and view."""
    k = "mesh13"
    out: list[Attempt] = []
    ref_files = {"ref.stl": box_stl()}

    def box_fit(label: str, name: str, files: dict, scale: str = "", origin: str = "") -> None:
        tag = f"<collision>{f'<origin xyz={origin!r}/>' if origin else ''}{mesh_tag(name, scale)}</collision>"

        def setup(d: Path) -> None:
            urdf_robot(collision=tag, files={**ref_files, **files})(d)
            write(d / "ref.urdf", urdf_text(collision=col("ref.stl")))

        out.append(
            Attempt(
                k,
                f"robots --fit, the box as {label}, fits as the plain STL",
                FIT,
                setup,
                (0,),
                timeout=200,
                env={"ARMANIM_CACHE_DIR": "{d}/cache"},
                after=same_fit("robot.urdf", "ref.urdf", env=None),
            )
        )

    # fmt: off
    box_fit("an ASCII STL", "a.stl", {"a.stl": box_ascii_stl()})
    box_fit("an ASCII STL of NaN normals", "a.stl", {"a.stl": box_ascii_stl("nan nan nan")})
    box_fit("a binary STL of NaN normals and attribute bytes", "a.stl", {"a.stl": box_stl(normals=float("nan"), attr=0xFFFF)})
    box_fit("an OBJ of triangles", "a.obj", {"a.obj": box_obj()})
    box_fit("an OBJ of quads", "a.obj", {"a.obj": box_obj("quad")})
    box_fit("an OBJ of v/vt/vn faces", "a.obj", {"a.obj": box_obj("slash")})
    box_fit("an OBJ of relative indices", "a.obj", {"a.obj": box_obj("negative")})
    box_fit("an OBJ of CRLF lines and tabs", "a.obj", {"a.obj": box_obj(newline="\r\n", sep="\t")})
    box_fit("a COLLADA of triangles", "a.dae", {"a.dae": box_dae()})
    box_fit("a COLLADA of a NORMAL input at offset 1", "a.dae", {"a.dae": box_dae("normals")})
    box_fit("a COLLADA polylist of quads", "a.dae", {"a.dae": box_dae("polylist")})
    box_fit("a COLLADA in millimetres (unit 0.001)", "a.dae", {"a.dae": box_dae(unit="0.001", scale=1000.0)})
    box_fit("a COLLADA in millimetres under a node scale 0.001", "a.dae", {"a.dae": box_dae(scale=1000.0, node="<scale>0.001 0.001 0.001</scale>")})
    box_fit("a COLLADA moved by +1 z and a node translate -1", "a.dae", {"a.dae": box_dae(shift=(0, 0, 1.0), node="<translate>0 0 -1</translate>")})
    box_fit("a COLLADA moved by +1 z and a node matrix -1", "a.dae", {"a.dae": box_dae(shift=(0, 0, 1.0), node="<matrix>1 0 0 0 0 1 0 0 0 0 1 -1 0 0 0 1</matrix>")})
    box_fit("an STL in millimetres at URDF scale 0.001", "a.stl", {"a.stl": box_stl(1000.0)}, scale="0.001 0.001 0.001")
    box_fit("an STL moved by +1 z and a collision origin -1", "a.stl", {"a.stl": box_stl(shift=(0, 0, 1.0))}, origin="0 0 -1")
    box_fit("an STL of twice the size at URDF scale 0.5", "a.STL", {"a.STL": box_stl(2.0)}, scale="0.5 0.5 0.5")
    # fmt: on

    # one file at two scales (or by two names, a hard link, a link), against two distinct copies
    two = [
        ("scales 1 and 2", {1: col("a.stl"), 2: f"<collision>{mesh_tag('a.stl', '2 2 2')}</collision>"}, {}),
        ("scales 1 and 1 1 2", {1: col("a.stl"), 2: f"<collision>{mesh_tag('a.stl', '1 1 2')}</collision>"}, {}),
        (
            "names a.stl and ./a.stl at scales 1 and 2",
            {1: col("a.stl"), 2: f"<collision>{mesh_tag('./a.stl', '2 2 2')}</collision>"},
            {},
        ),
        (
            "a.stl and its hard link h.stl at scales 1 and 2",
            {1: col("a.stl"), 2: f"<collision>{mesh_tag('h.stl', '2 2 2')}</collision>"},
            {"hard": True},
        ),
        (
            "a.stl and a link to it at scales 1 and 2",
            {1: col("a.stl"), 2: f"<collision>{mesh_tag('s.stl', '2 2 2')}</collision>"},
            {"soft": True},
        ),
        (
            "one with a collision origin, one without",
            {1: col("a.stl"), 2: "<collision><origin xyz='0 0 0.1'/>" + mesh_tag("a.stl") + "</collision>"},
            {},
        ),
    ]
    for label, cols, how in two:
        ref = {
            i: tag.replace("'a.stl'", "'b.stl'")
            .replace('"a.stl"', '"b.stl"')
            .replace("'./a.stl'", "'b.stl'")
            .replace("'h.stl'", "'b.stl'")
            .replace("'s.stl'", "'b.stl'")
            if i == 2
            else tag
            for i, tag in cols.items()
        }

        def setup(d: Path, cols=cols, ref=ref, how=how) -> None:
            write(d / "a.stl", box_stl())
            write(d / "b.stl", box_stl())
            if how.get("hard"):
                os.link(d / "a.stl", d / "h.stl")
            if how.get("soft"):
                os.symlink("a.stl", d / "s.stl")
            write(d / "robot.urdf", urdf_links(cols))
            write(d / "ref.urdf", urdf_links(ref))

        out.append(
            Attempt(
                k,
                f"robots --fit, one box file on two links, {label}",
                FIT,
                setup,
                (0,),
                timeout=200,
                after=same_fit("robot.urdf", "ref.urdf"),
            )
        )

    # a visual of the same file at another scale on the same link: the collision fit is at its own
    def vis_and_col(d: Path) -> None:
        write(d / "a.stl", box_stl())
        write(d / "b.stl", box_stl())
        write(d / "robot.urdf", urdf_links({1: col("a.stl")}, {1: f"<visual>{mesh_tag('a.stl', '3 3 3')}</visual>"}))
        write(d / "ref.urdf", urdf_links({1: col("b.stl")}))
        write(d / "s.yaml", URDF_SCENE)
        write(d / "r.yaml", URDF_SCENE.replace("robot.urdf", "ref.urdf").replace("name: m", "name: r"))

    def same_capsules(d: Path) -> list[str]:
        armanim_in(d, "run", "r.yaml", "--out", "o", "--no-video", "-q")
        a, b = d / "o/m/capsules.yaml", d / "o/r/capsules.yaml"
        if not a.is_file() or not b.is_file():
            return [f"no capsules.yaml to compare ({a.is_file()}, {b.is_file()})"]
        return (
            [] if a.read_text() == b.read_text() else ["capsules.yaml differs from the run without the visual's scale"]
        )

    out.append(
        Attempt(
            k,
            "run, link l1's visual a.stl at scale 3 and its collision a.stl at 1: the capsules of scale 1",
            ["run", "s.yaml", "--out", "o", "--no-video", "-q"],
            vis_and_col,
            (0,),
            timeout=300,
            after=same_capsules,
        )
    )

    # the folder a name is taken from: the URDF's (not the working folder's decoy)
    def decoy(d: Path) -> None:
        write(d / "sub/a.stl", box_stl())
        write(d / "a.stl", box_stl(3.0))
        write(d / "sub/robot.urdf", urdf_text(collision=col("a.stl")))
        write(d / "ref.stl", box_stl())
        write(d / "ref.urdf", urdf_text(collision=col("ref.stl")))

    out.append(
        Attempt(
            k,
            "robots --fit sub/robot.urdf naming a.stl, a larger a.stl in the working folder",
            ["robots", "--fit", "sub/robot.urdf"],
            decoy,
            (0,),
            timeout=200,
            after=same_fit("sub/robot.urdf", "ref.urdf"),
        )
    )

    def scene_decoy(d: Path) -> None:
        write(d / "sub/robot.urdf", urdf_text())
        write(d / "robot.urdf", urdf_text().replace('xyz="0 0 0.3"', 'xyz="0 0 0.5"'))
        write(d / "sub/s.yaml", URDF_SCENE)

    def copied_urdf_is_the_scene_s(d: Path) -> list[str]:
        copied = d / "o/m/robot.urdf"
        if not copied.is_file():
            return ["the run folder holds no robot.urdf"]
        return (
            []
            if copied.read_bytes() == (d / "sub/robot.urdf").read_bytes()
            else ["the run took the working folder's robot.urdf"]
        )

    out.append(
        Attempt(
            k,
            "run sub/s.yaml naming robot.urdf, another robot.urdf in the working folder",
            ["run", "sub/s.yaml", "--out", "o", "--no-video", "-q"],
            scene_decoy,
            (0,),
            timeout=300,
            after=copied_urdf_is_the_scene_s,
        )
    )

    # the capsule cache: a folder that is no folder, entries that are not armanim's fit of this mesh
    def fitted_then(change: Callable[[Path], None]) -> Callable[[Path], None]:
        def setup(d: Path) -> None:
            write(d / "ref.stl", box_stl())
            write(d / "ref.urdf", urdf_text(collision=col("ref.stl")))
            urdf_robot(collision=col("a.stl"), files={"a.stl": box_stl(1.5)})(d)
            armanim_in(d, *FIT, env={"ARMANIM_CACHE_DIR": str(d / "cache")})
            change(d)

        return setup

    def entries(d: Path) -> list[Path]:
        return sorted((d / "cache").rglob("*.json"))

    def other_mesh_entry(d: Path) -> None:  # the reference box's fit, written at a.stl's key
        before = set(entries(d))
        armanim_in(d, "robots", "--fit", "ref.urdf", env={"ARMANIM_CACHE_DIR": str(d / "cache")})
        (new,) = set(entries(d)) - before
        for entry in before:
            shutil.copy(new, entry)

    def each_entry(make: Callable[[Path], None]) -> Callable[[Path], None]:
        def change(d: Path) -> None:
            for entry in entries(d):
                entry.unlink()
                make(entry)

        return change

    cache_cases = [
        ("the cache folder a FIFO", lambda d: (shutil.rmtree(d / "cache"), fifo(d / "cache"))),
        ("the cache folder a regular file", lambda d: (shutil.rmtree(d / "cache"), write(d / "cache", "x"))),
        ("the cache entry a FIFO", each_entry(fifo)),
        ("the cache entry a folder", each_entry(lambda p: p.mkdir())),
        (
            "the cache entry cut in half",
            lambda d: [write(p, p.read_bytes()[: len(p.read_bytes()) // 2]) for p in entries(d)] and None,
        ),
        ("the cache entry another mesh's fit", other_mesh_entry),
    ]

    def fit_as_fresh(d: Path) -> list[str]:
        through = capsule_lines(fit_of(d, "robot.urdf", {"ARMANIM_CACHE_DIR": str(d / "cache")}))
        fresh = capsule_lines(fit_of(d, "robot.urdf", {"ARMANIM_CACHE_DIR": str(d / "fresh")}))
        return [] if through and through == fresh else ["the fit through the cache is not the mesh's own fit"]

    for label, change in cache_cases:
        out.append(
            Attempt(
                k,
                f"robots --fit again, {label}: the fit of the mesh itself",
                FIT,
                fitted_then(change),
                (0,),
                timeout=200,
                env={"ARMANIM_CACHE_DIR": "{d}/cache"},
                after=fit_as_fresh,
            )
        )

    # the user's mesh changed after a run: render and view draw from the run, never block or fail
    def run_then(change: Callable[[Path], None]) -> Callable[[Path], None]:
        def setup(d: Path) -> None:
            urdf_robot(vis("a.stl"), files={"a.stl": box_stl()})(d)
            armanim_in(d, "run", "s.yaml", "--out", "o", "--no-video", "-q")
            change(d)

        return setup

    after_run = [
        ("deleted", lambda d: os.unlink(d / "a.stl")),
        ("replaced by a FIFO", lambda d: (os.unlink(d / "a.stl"), fifo(d / "a.stl"))),
        ("replaced by a 2 GB sparse file", lambda d: (os.unlink(d / "a.stl"), sparse(d / "a.stl", 2 << 30))),
    ]
    for label, change in after_run:
        for cmd in (["render", "o/m", "-q", "--size", "64x48", "--out", "fig"], ["view", "o/m", "--out", "v.html"]):
            out.append(
                Attempt(
                    k,
                    f"{cmd[0]} of a run whose visual mesh, in the user's folder, was {label} since",
                    cmd,
                    run_then(change),
                    (0, 2),
                    timeout=300,
                    message_if_2=r"o/m|a\.stl",
                )
            )

    # a tool mesh in each format: drawn, no note that it could not be
    for label, name, text in (
        ("an ASCII STL", "t.stl", box_ascii_stl()),
        ("an OBJ of quads", "t.obj", box_obj("quad")),
        ("a COLLADA of normals at offset 1", "t.dae", box_dae("normals")),
        ("a COLLADA polylist", "t.dae", box_dae("polylist")),
    ):
        out.append(
            Attempt(
                k,
                f"fk --png, tool mesh {label}: no note",
                ["fk", "--scene", "s.yaml", "--angles", "0,10,20", "--png", "p.png"],
                lambda d, name=name, text=text: (
                    (
                        write(d / name, text),
                        urdf_robot()(d),
                        write(
                            d / "s.yaml",
                            URDF_SCENE.replace("{urdf: robot.urdf}", "{urdf: robot.urdf, tool: {mesh: " + name + "}}"),
                        ),
                    )
                    and None
                ),
                (0,),
                timeout=200,
                not_message=r"note",
                after=lambda d: [] if (d / "p.png").is_file() else ["no p.png"],
            )
        )
    return out


def clock_breaks(folder: str, fps: float) -> Callable[[Path], list[str]]:
    """After a run into ``folder``: the clock agrees with itself. Frames 0..N-1 in order, each at
    time frame / fps; summary.json's totals N frames and N / fps seconds; each goal's frames follow
    the one before's (the first after frame 0), and span its motion's ``frames`` and, reached, its
    hold's round(fps x hold) (docs/scene-format.md); the last ends at frame N-1; each row's
    ``goal`` is the goal whose frames hold it. (``solver.max_frames_per_goal`` bounds a goal's solved
    steps, not its frames once timed: docs/scene-format.md, "Frames and goals".)"""

    def check(d: Path) -> list[str]:
        import csv as _csv
        import json as _json

        import yaml

        run = d / folder
        if not (run / "trajectory.csv").is_file():
            return [f"no {folder}/trajectory.csv"]
        with open(run / "trajectory.csv", newline="") as handle:
            rows = list(_csv.DictReader(handle))
        summary = _json.loads((run / "summary.json").read_text())
        asked = yaml.safe_load((run / "scene.yaml").read_text())["goals"]
        n, problems = len(rows), []
        frames = [int(r["frame"]) for r in rows]
        if frames != list(range(n)):
            problems.append("the frame column is not 0..N-1")
        off = max(abs(float(r["time_s"]) - int(r["frame"]) / fps) for r in rows)
        if off > 1e-9 * max(1.0, n / fps):
            problems.append(f"time_s is {off:.3g} s off frame / fps ({fps:g})")
        totals = summary["totals"]
        if totals["frames"] != n or abs(totals["duration_s"] - n / fps) > 1e-9 * max(1.0, n / fps):
            problems.append(
                f"totals say {totals['frames']} frames, {totals['duration_s']} s; the CSV has {n} rows at {fps:g} fps"
            )
        start = 1
        for g, goal in zip(summary["goals"], asked):
            hold = round(fps * float(goal.get("hold", 0) if isinstance(goal, dict) else 0))
            first = 0 if g["index"] == 0 else start
            if g["first_frame"] != first:
                problems.append(f"goal {g['index']} starts at frame {g['first_frame']}, expected {first}")
                break
            spans = (g["frames"] + hold,) if g["reached"] else (g["frames"] + hold, g["frames"])
            if g["last_frame"] - start + 1 not in spans:
                problems.append(
                    f"goal {g['index']} spans frames {start}..{g['last_frame']}: not its {g['frames']} frames"
                    f" and a hold of {hold}"
                )
            held = {r["goal"] for r in rows[g["first_frame"] : g["last_frame"] + 1]}
            if held != {str(g["index"])}:
                problems.append(f"goal {g['index']}'s frames hold rows of goals {sorted(held)}")
            start = g["last_frame"] + 1
        if summary["goals"] and summary["goals"][-1]["last_frame"] != n - 1:
            problems.append(f"the last goal ends at frame {summary['goals'][-1]['last_frame']}, the CSV at {n - 1}")
        return problems

    return check


def both(*checks: Callable[[Path], list[str]]) -> Callable[[Path], list[str]]:
    return lambda d: [p for check in checks for p in check(d)]


def clock_attempt(k: str, label: str, args: list[str], text: str, fps: float) -> Attempt:
    """A run of ``text`` (named tiny) held to :func:`clock_breaks` at ``fps``."""
    return Attempt(k, label, args, tiny_scene(text=text), (0,), timeout=400, after=clock_breaks("o/tiny", fps))


def variants_clock(rates: tuple[float, ...]) -> Callable[[Path], list[str]]:
    """After a sweep of ``render.fps`` over ``rates``: one variant folder a rate, each at its rate
    (its summary's fps) and held to :func:`clock_breaks`."""

    def check(d: Path) -> list[str]:
        import json as _json

        runs = [n for n in _listing(d / "o") if (d / "o" / n).is_dir()]
        if len(runs) != len(rates):
            return [f"expected {len(rates)} variant folders, found {runs}"]
        problems = []
        for n in runs:
            fps = _json.loads((d / "o" / n / "summary.json").read_text())["fps"]
            if fps not in rates:
                problems.append(f"{n}: fps {fps}, not a value of the sweep")
            problems += clock_breaks(f"o/{n}", fps)(d)
        return problems

    return check


def given_up(folder: str, goal: int) -> Callable[[Path], list[str]]:
    """After a run into ``folder``: goal ``goal`` is reported missed, with a reason."""

    def check(d: Path) -> list[str]:
        import json as _json

        said = _json.loads((d / folder / "summary.json").read_text())["goals"][goal]
        return (
            []
            if not said["reached"] and said["reason"]
            else [f"goal {goal}: reached {said['reached']}, reason {said['reason']}"]
        )

    return check


HOLDS = (
    "version: 1\nname: tiny\narm: {links: [1, 1, 1]}\n"
    "goals: [{position: [1, 1, 1], hold: HOLD}, {position: [0.5, -1, 1], hold: HOLD}, {joints: [10, 20, 30], hold: HOLD}]\n"
    "render: {size: [160, 90], fps: FPS}\n"
)


def frames13_attempts() -> list[Attempt]:
    """The clock held to itself (times are frame / fps, the totals and each goal's frames add up)
    at odd rates (29.97, 23.976, 12.5, 7, 1/3, 0.5, 240), by the scene, --fps, --quality and a sweep,
    with holds of half frames; random arms at those rates held to the rate limits too; the frame
    budget at its exact edge for fps and holds campaigns 10-12 did not take; max_frames_per_goal
    of 1 to 3 on a far goal."""
    k = "frames13"
    out: list[Attempt] = []
    run = ["run", "s.yaml", "--out", "o", "--no-video", "-q"]
    for fps in ("29.97", "23.976", "12.5", "7", "0.3333333333333333", "0.5", "240", "0.01"):
        for hold in ("0", "0.05", "0.25"):
            if fps in ("0.01", "0.3333333333333333", "240") and hold != "0.25":
                continue
            text = HOLDS.replace("HOLD", hold).replace("FPS", fps)
            out.append(
                clock_attempt(
                    k, f"run at render.fps {fps}, holds of {hold} s: the clock adds up", run, text, float(fps)
                )
            )
    for flags, fps in ((["--fps", "59.94"], 59.94), (["--fps", "1.5"], 1.5), (["--quality", "low"], 15.0)):
        text = HOLDS.replace("HOLD", "0.5").replace("FPS", "10")
        out.append(
            clock_attempt(k, f"run {' '.join(flags)}: the clock adds up at {fps:g} fps", [*run, *flags], text, fps)
        )

    out.append(
        Attempt(
            k,
            "sweep --set render.fps=7,12.5: each variant's clock adds up",
            ["sweep", "s.yaml", "--set", "render.fps=7,12.5", "--out", "o", "-q", "--jobs", "1"],
            tiny_scene(text=HOLDS.replace("HOLD", "0.25").replace("FPS", "10")),
            (0,),
            timeout=400,
            after=variants_clock((7.0, 12.5)),
        )
    )
    # random arms among spheres at odd rates: the rate limits, the velocities, the export and the clock
    for seed, fps in zip(range(500, 510), (29.97, 12.5, 7.0, 120.0, 23.976, 0.5, 59.94, 2.0, 144.0, 11.0)):
        text, spec = wrong_scene(seed, WRONG11_KINDS)
        text = re.sub(r"fps: [0-9.]+\}", f"fps: {fps:g}}}", text)
        spec = dict(spec, fps=fps)
        out.append(
            Attempt(
                k,
                f"run a random arm among spheres at {fps:g} fps (seed {seed}), held to the rates and the clock",
                run,
                tiny_scene(text=text),
                (0,),
                timeout=500,
                after=both(trajectory_breaks(spec), clock_breaks(f"o/{spec['name']}", fps)),
            )
        )
    # the frame budget: 1 + the goals' (max_frames_per_goal + round(hold x fps)) at exactly 1,000,000
    for fps, goals in ((240.0, 3), (120.0, 7), (29.97, 9), (0.75, 11)):
        hold_frames = min(999_999 // goals - 50_000, int(3600 * fps))
        most = 999_999 // goals - hold_frames
        for extra in (0, 1):
            total = 1 + goals * (most + extra + hold_frames)
            text = (
                f"version: 1\nname: b\narm: {{links: [1, 1, 1]}}\n"
                f"goals: [{', '.join([f'{{position: [1, 1, 1], hold: {hold_frames / fps!r}}}'] * goals)}]\n"
                f"solver: {{max_frames_per_goal: {most + extra}}}\n"
                f"render: {{size: [160, 90], fps: {fps!r}}}\n"
            )
            out.append(
                Attempt(
                    k,
                    f"validate {goals} holds of {hold_frames:,} frames at {fps:g} fps, {total:,} frames in all",
                    ["validate", "s.yaml"],
                    tiny_scene(text=text),
                    (0,) if total <= 1_000_000 else (2,),
                    timeout=120,
                    message_if_2=r"s\.yaml:\d+: ",
                )
            )
    for flags in (["--fps", "240"], ["--quality", "4k"], ["--fps", "121"]):
        text = (
            "version: 1\nname: b\narm: {links: [1, 1, 1]}\ngoals: ["
            + ", ".join(
                ["{position: [1, 1, 1], hold: 3600}", "{position: [0.5, -1, 1], hold: 3600}"] * 2
                + ["{position: [1, 1, 1], hold: 3600}"]
            )
            + "]\nsolver: {max_frames_per_goal: 300}\nrender: {size: [160, 90], fps: 30}\n"
        )
        out.append(
            Attempt(
                k,
                f"run five one-hour holds {' '.join(flags)} (over the frame limit): refused before solving",
                [*run, *flags],
                tiny_scene(text=text),
                (2,),
                timeout=120,
                message=r"frame",
            )
        )
    for most in (1, 2, 3):
        text = TINY.replace("goals: [[1, 1, 1], [0.5, -1, 1]]", "goals: [[-1, 1, 2], [1, 1, 1]]").replace(
            "render:", f"solver: {{max_frames_per_goal: {most}}}\nrender:"
        )
        out.append(
            Attempt(
                k,
                f"run max_frames_per_goal {most} to a far goal: given up, the clock adds up",
                run,
                tiny_scene(text=text),
                (0,),
                timeout=300,
                after=both(clock_breaks("o/tiny", 10.0), given_up("o/tiny", 0)),
            )
        )
    return out


def again_tidy(
    *args: str, codes: tuple[int, ...] = (0,), where: tuple[str, ...] = ("o", ".")
) -> Callable[[Path], list[str]]:
    """After a command killed or interrupted: the same command again ends with ``codes`` and leaves
    no staging folder, temporary or moved-aside file in ``where`` (what the killed one left is
    tidied, promise 11)."""

    def check(d: Path) -> list[str]:
        done = subprocess.run(
            [sys.executable, "-m", "armanim", *args],
            cwd=d,
            env=dict(os.environ, PYTHONPATH=str(SRC)),
            capture_output=True,
            text=True,
            timeout=600,
        )
        problems = []
        if done.returncode not in codes:
            problems.append(f"the command again: exit {done.returncode}: {(done.stdout + done.stderr).strip()[-300:]}")
        for place in where:
            base = d / place
            if base.is_dir():
                found = [str(p.relative_to(d)) for p in base.rglob("*") if LITTER.search(p.name)]
                if found:
                    problems.append(f"left after the command again: {found[:4]}")
        return problems

    return check


PANDA = (
    "version: 1\nname: p\narm: {robot: panda}\ngoals: [{joints: [0, -20, 0, -120, 0, 100, 45]}, "
    "{joints: [30, 0, 0, -90, 0, 90, 0]}]\nrender: {size: [320, 180], fps: 10}\n"
)
"""A Panda (its meshes drawn) with two joint goals."""


def signals13_attempts() -> list[Attempt]:
    """SIGHUP (the terminal closes) to the group and to armanim alone, in every command that
    writes: it is an interruption (docs/reliability.md: "every interruption ... exit 130"), so
    exit 130, nothing half-written, and the command again works and leaves nothing behind.
    SIGQUIT (Ctrl-\\) ends the process as a kill does (old outputs whole, the next command tidies).
    Ctrl-C and SIGTERM in a robot's meshes drawn by render and view, a read-only check, the robot
    list, a run replacing its own earlier folder at six moments; SIGTERM to armanim alone in a
    pool, its workers held to end with it (``linger``)."""
    k = "signals13"
    out: list[Attempt] = []
    short = LONG.replace("hold: 3600", "hold: 30").replace("hold: 400", "hold: 30")
    video30 = TINY.replace("fps: 10", "fps: 30")
    batch = ["run", "a.yaml", "s.yaml", "--out", "o", "--no-video", "-q", "--jobs", "2"]

    def two_scenes(d: Path) -> None:
        write(d / "a.yaml", TINY.replace("name: tiny", "name: a"))
        write(d / "s.yaml", TINY)

    def long_run_and(*args: str) -> Callable[[Path], None]:
        return then(lambda d: finished_run(d, LONG), lambda d: armanim_in(d, *args))

    def big_collision(d: Path) -> None:
        big_stl(d / "a.stl", 1_200_000)  # 60 MB: under the 64 MB a mesh file may have
        urdf_robot(collision=col("a.stl"))(d)

    def moveit_scene(d: Path) -> None:
        box = "* b{i}\n1\nbox\n0.05 0.05 0.05\n{x} {y} 1\n0 0 0 1\n0 0 0 0\n"
        write(
            d / "w.scene",
            "w\n" + "".join(box.format(i=i, x=2 + i % 10, y=i // 10 * 0.1) for i in range(15_000)) + ".\n",
        )

    update = ["check", "s.yaml", "--golden", "g", "--update"]
    # (label, args, setup, moments, what must be whole, where litter may not be)
    writers: list[tuple] = [
        (
            "run with video",
            ["run", "s.yaml", "--out", "o", "-q", "--jobs", "1"],
            tiny_scene(text=video30),
            (2.0, 5.0),
            ("o/tiny",),
            ("o",),
        ),
        (
            "run --no-video of a 40,000-frame scene",
            ["run", "s.yaml", "--out", "o", "--no-video", "-q"],
            tiny_scene(text=LONG),
            (3.0,),
            ("o/tiny",),
            ("o",),
        ),
        ("a --jobs 2 batch", batch, two_scenes, (1.2, 2.5), ("o/a", "o/tiny", "o/index.csv"), ("o",)),
        (
            "render --out fig",
            ["render", "o/tiny", "--out", "fig", "-q", "--size", "320x180", "--jobs", "1"],
            lambda d: finished_run(d, short) and None,
            (2.0, 4.0),
            ("fig", "o/tiny"),
            ("o", "fig", "."),
        ),
        (
            "export replacing its earlier export of a 40,000-frame run",
            ["export", "o/tiny", "--out", "e.json"],
            long_run_and("export", "o/tiny", "--out", "e.json"),
            (1.0,),
            ("e.json",),
            ("o", "."),
        ),
        (
            "view replacing its earlier page of a 40,000-frame run",
            ["view", "o/tiny", "--out", "v.html"],
            long_run_and("view", "o/tiny", "--out", "v.html"),
            (1.5,),
            ("v.html",),
            ("o", "."),
        ),
        (
            "check --update of a 40,000-frame scene",
            update,
            tiny_scene(text=LONG),
            (2.0,),
            ("g/tiny.csv", "g/tiny.json"),
            ("g", "."),
        ),
        (
            "sweep --jobs 2 of 2 variants",
            ["sweep", "s.yaml", "--set", "solver.step=0.1,0.2", "--out", "o", "-q", "--jobs", "2"],
            tiny_scene(),
            (2.0,),
            (),
            ("o",),
        ),
        ("robots --fit of a 1.2-million-triangle STL", FIT, big_collision, (1.5,), (), (".",)),
        (
            "import moveit of 15,000 boxes",
            ["import", "moveit", "w.scene", "--robot", "panda", "--out", "m.yaml"],
            moveit_scene,
            (1.0,),
            ("m.yaml",),
            (".",),
        ),
    ]
    for label, args, setup, moments, whole, where in writers:
        for delay in moments:
            out.append(
                Attempt(
                    k,
                    f"{label}, SIGHUP to the group at {delay:g} s (the terminal closes)",
                    args,
                    setup,
                    (130,),
                    timeout=300,
                    interrupt=(delay, "SIGHUPG"),
                    litter_in=where,
                    linger=5.0,
                    message=r"interrupted",
                    after=both(whole_or_none(*whole), again_tidy(*args, where=where)),
                )
            )
    for label, args, setup, delay, whole, where in (
        ("a --jobs 2 batch", batch, two_scenes, 1.5, ("o/a", "o/tiny"), ("o",)),
        (
            "run --jobs 2 with video (segment workers)",
            ["run", "s.yaml", "--out", "o", "-q", "--jobs", "2"],
            tiny_scene(text=video30),
            2.5,
            ("o/tiny",),
            ("o",),
        ),
    ):
        out.append(
            Attempt(
                k,
                f"{label}, SIGHUP to armanim alone at {delay:g} s",
                args,
                setup,
                (130,),
                timeout=300,
                interrupt=(delay, "SIGHUP"),
                litter_in=where,
                linger=5.0,
                after=both(whole_or_none(*whole), again_tidy(*args, where=where)),
            )
        )
    for label, args, setup, moments, whole, where in (writers[0], writers[2], writers[3], writers[4], writers[6]):
        out.append(
            Attempt(
                k,
                f"{label}, SIGQUIT to the group at {moments[0]:g} s (Ctrl-\\): old outputs whole, the next tidies",
                args,
                setup,
                (130, -3),
                timeout=300,
                interrupt=(moments[0], "SIGQUITG"),
                litter_in=(),
                after=both(whole_or_none(*whole), again_tidy(*args, where=where)),
            )
        )

    def panda_run(d: Path) -> None:
        write(d / "s.yaml", PANDA)
        armanim_in(d, "run", "s.yaml", "--out", "o", "--no-video", "-q")

    out += at_moments(
        k,
        "render --out fig of a Panda run (its meshes)",
        ["render", "o/p", "--out", "fig", "-q", "--jobs", "1"],
        panda_run,
        ((2.0, "SIGINT"), (4.0, "SIGTERM"), (6.0, "SIGTERMG")),
        timeout=300,
        keep=("o/p",),
        after=whole_or_none("fig"),
        litter_in=("o", "fig", "."),
        linger=5.0,
    )
    out += at_moments(
        k,
        "view of a Panda run (its meshes), replacing the run's page",
        ["view", "o/p"],
        panda_run,
        ((1.5, "SIGINT"), (3.0, "SIGTERMG")),
        timeout=300,
        after=whole_or_none("o/p"),
    )
    out += at_moments(
        k,
        "run --viewer --no-video of a Panda",
        ["run", "s.yaml", "--out", "o", "--no-video", "--viewer", "-q"],
        tiny_scene(text=PANDA),
        ((3.0, "SIGINT"), (6.0, "SIGTERM")),
        timeout=300,
        after=whole_or_none("o/p"),
    )
    out += at_moments(
        k,
        "check (no update) of a 40,000-frame scene against its golden",
        ["check", "s.yaml", "--golden", "g"],
        then(tiny_scene(text=LONG), lambda d: armanim_in(d, *update)),
        ((2.0, "SIGINT"), (4.0, "SIGTERMG")),
        codes=(0, 130),
        timeout=300,
        keep=("g",),
        litter_in=("g", "."),
    )
    out += at_moments(
        k, "robots (the list)", ["robots"], lambda d: None, ((0.5, "SIGINT"), (1.0, "SIGTERM")), timeout=60
    )
    out += at_moments(
        k,
        "import moveit with a request",
        ["import", "moveit", "w.yaml", "--robot", "panda", "--request", "r.yaml", "--out", "m.yaml"],
        lambda d: (write(d / "w.yaml", MOVEIT_BOX), write(d / "r.yaml", MOVEIT_REQUEST)) and None,
        ((1.0, "SIGTERM"),),
        timeout=120,
        after=whole_or_none("m.yaml"),
        litter_in=(".",),
    )

    def earlier_run(d: Path) -> None:
        finished_run(d, video30, video=True)
        write(d / "s.yaml", video30.replace("[0.5, -1, 1]", "[0.5, -1, 1.2]"))

    def old_or_new(d: Path) -> list[str]:
        import json as _json

        marker = d / "o/tiny/.armanim-run.json"
        if not marker.is_file():
            return ["o/tiny has no marker"]
        listed = _json.loads(marker.read_text()).get("files", {})
        names = {Path(name).parts[0] for name in listed}
        here = {p.name for p in (d / "o/tiny").iterdir()} - {".armanim-run.json"}
        return [] if not names or names == here else [f"o/tiny holds {sorted(here ^ names)} beside its marker's list"]

    out += at_moments(
        k,
        "run with video replacing its own earlier run folder",
        ["run", "s.yaml", "--out", "o", "-q", "--jobs", "1"],
        earlier_run,
        [(t, "SIGINT") for t in (0.8, 1.6, 2.4, 3.2, 4.0, 4.8)],
        timeout=300,
        after=both(whole_or_none("o/tiny"), old_or_new),
    )
    out += at_moments(
        k,
        "a --jobs 2 batch, SIGTERM to armanim alone (its workers must end too)",
        batch,
        two_scenes,
        ((1.0, "SIGTERM"), (2.0, "SIGTERM"), (3.0, "SIGTERM")),
        timeout=300,
        linger=5.0,
        after=whole_or_none("o/a", "o/tiny", "o/index.csv"),
    )
    out += at_moments(
        k,
        "run with video, then SIGHUP 50 ms later",
        ["run", "s.yaml", "--out", "o", "-q", "--jobs", "1"],
        tiny_scene(text=video30),
        ((3.0, "SIGTERMG"),),
        also=((3.05, "SIGHUPG"),),
        codes=(130,),
        timeout=300,
        linger=5.0,
        after=whole_or_none("o/tiny"),
    )
    return out


def loss13_attempts() -> list[Attempt]:
    """Every writer aimed at a file it reads (the scene, an importer's own input, the request),
    at a user's file through a trailing slash, at files of another writer's kind (pages, exports,
    goldens, the lock), at staging and moved-aside names as files; the default outputs of export,
    view and render into a run folder where the user put a file of that name; the user's files
    beside a golden, inside a render folder, a sweep's variant and a batch's folder; the capsule
    cache and TMPDIR inside a run folder, the outputs or the user's folder; one scene twice in a batch."""
    k = "loss13"
    update = ["check", "s.yaml", "--golden", "g", "--update"]
    run = ["run", "s.yaml", "--out", "o", "--no-video", "-q"]
    scene = mine("s.yaml", TINY)
    golden = then(scene, lambda d: armanim_in(d, *update))
    exported = then(finished_run, lambda d: armanim_in(d, "export", "o/tiny", "--out", "e.json"))
    paged = then(finished_run, lambda d: armanim_in(d, "view", "o/tiny", "--out", "v.html"))
    moveit = mine("w.scene", "w\n* b\n1\nbox\n0.1 0.1 0.1\n1 1 1\n0 0 0 1\n0 0 0 0\n.\n")
    importing = ["import", "moveit", "w.scene", "--robot", "panda"]
    sweep = ["sweep", "s.yaml", "--set", "solver.step=0.1,0.2", "--out", "o", "-q", "--jobs", "1"]
    swept = then(scene, lambda d: armanim_in(d, *sweep))
    batch = ["run", "a.yaml", "s.yaml", "--out", "o", "--no-video", "-q", "--jobs", "1"]
    batched = then(scene, mine("a.yaml", TINY.replace("name: tiny", "name: a")), lambda d: armanim_in(d, *batch))

    def in_variant(d: Path) -> None:
        if not (d / "o/tiny_step-0.1").is_dir():
            raise RuntimeError(f"no variant folder tiny_step-0.1: {_listing(d / 'o')}")

    # one attempt a row: label, arguments, setup, exit codes, the user's paths kept
    # fmt: off
    table: list[tuple] = [
        ("run s.yaml --out s.yaml (the scene itself as OUT)", ["run", "s.yaml", "--out", "s.yaml", "--no-video", "-q"], scene, (2, 3), ("s.yaml",)),
        ("render --out s.yaml (the user's scene, a file)", ["render", "o/tiny", "-q", "--size", "64x48", "--out", "s.yaml"], finished_run, (2, 3), ("s.yaml",)),
        ("import moveit w.scene --out w.scene (its own input)", [*importing, "--out", "w.scene"], moveit, (2, 3), ("w.scene",)),
        ("import moveit --request r.yaml --out r.yaml (its own request)", [*importing, "--request", "r.yaml", "--out", "r.yaml"], then(moveit, mine("r.yaml", MOVEIT_REQUEST)), (2, 3), ("r.yaml",)),
        ("import moveit --out the user's URDF", [*importing, "--out", "robot.urdf"], then(moveit, mine("robot.urdf", MINI_URDF)), (2, 3), ("robot.urdf",)),
        ("export --out e.json/ (a slash after the user's file)", ["export", "o/tiny", "--out", "e.json/"], then(finished_run, mine("e.json", "{}\n")), (2, 3), ("e.json",)),
        ("view --out v.html/ (a slash after the user's file)", ["view", "o/tiny", "--out", "v.html/"], then(finished_run, mine("v.html", "<p>mine</p>\n")), (2, 3), ("v.html",)),
        ("schema --out x.json/ (a slash after the user's file)", ["schema", "--out", "x.json/"], mine("x.json", "{}\n"), (2, 3), ("x.json",)),
        ("fk --png p.png/ (a slash after the user's file)", ["fk", "--angles", "0,0,0,0", "--png", "p.png/"], mine("p.png", "mine"), (2, 3), ("p.png",)),
        ("export (into the run folder), the user's joint_trajectory.json put there", ["export", "o/tiny"], then(finished_run, mine("o/tiny/joint_trajectory.json", '{"joint_names": [], "points": []}\n')), (2, 3), ("o/tiny/joint_trajectory.json",)),
        ("view (into the run folder), the user's viewer.html put in a --no-video run", ["view", "o/tiny"], then(finished_run, mine("o/tiny/viewer.html", "<p>mine</p>\n")), (2, 3), ("o/tiny/viewer.html",)),
        ("render (into the run folder), the user's tiny.mp4 put in a --no-video run", ["render", "o/tiny", "-q", "--size", "64x48"], then(finished_run, mine("o/tiny/tiny.mp4", "mine")), (2, 3), ("o/tiny/tiny.mp4",)),
        ("render (into the run folder), the user's notes put there", ["render", "o/tiny", "-q", "--size", "64x48"], then(finished_run, mine("o/tiny/notes.txt")), (2, 3), ("o/tiny/notes.txt",)),
        ("run again, o/.tiny.lock a file of the user's notes", run, then(finished_run, lambda d: os.unlink(d / "o/.tiny.lock"), mine("o/.tiny.lock")), (0, 2, 3), ("o/.tiny.lock",)),
        ("run again, o/.tiny.old-99 a file of the user's", run, then(finished_run, mine("o/.tiny.old-99")), (0, 3), ("o/.tiny.old-99",)),
        ("run again, o/.tiny.abcdefgh.partial a file of the user's", run, then(finished_run, mine("o/.tiny.abcdefgh.partial")), (0, 3), ("o/.tiny.abcdefgh.partial",)),
        ("run, no run yet, o/.tiny.abcdefgh.partial a file of the user's", run, then(scene, mine("o/.tiny.abcdefgh.partial")), (0, 3), ("o/.tiny.abcdefgh.partial",)),
        ("check --update, the user's notes in the golden folder", update, then(golden, mine("g/notes.txt")), (0,), ("g/notes.txt",)),
        ("check --update --golden . (the user's own folder)", ["check", "s.yaml", "--golden", ".", "--update"], then(scene, mine("notes.txt")), (0, 2, 3), ("s.yaml", "notes.txt")),
        ("render --out fig again, the user's notes added to fig since", ["render", "o/tiny", "-q", "--size", "64x48", "--out", "fig"], then(finished_run, lambda d: armanim_in(d, "render", "o/tiny", "-q", "--size", "64x48", "--out", "fig"), mine("fig/notes.txt")), (0, 3), ("fig/notes.txt",)),
        ("render --out fig holding the user's poster.png", ["render", "o/tiny", "-q", "--size", "64x48", "--out", "fig"], then(finished_run, mine("fig/poster.png", "mine")), (3,), ("fig/poster.png",)),
        ("export --out v.html (a page armanim wrote)", ["export", "o/tiny", "--out", "v.html"], paged, (2, 3), ("v.html",)),
        ("view --out e.json (an export armanim wrote)", ["view", "o/tiny", "--out", "e.json"], exported, (2, 3), ("e.json",)),
        ("schema --out v.html (a page armanim wrote)", ["schema", "--out", "v.html"], paged, (2, 3), ("v.html",)),
        ("fk --png v.html (a page armanim wrote)", ["fk", "--angles", "0,0,0,0", "--png", "v.html"], paged, (2, 3), ("v.html",)),
        ("import moveit --out v.html (a page armanim wrote)", [*importing, "--out", "v.html"], then(paged, moveit), (2, 3), ("v.html",)),
        ("import moveit --out e.json (an export armanim wrote)", [*importing, "--out", "e.json"], then(exported, moveit), (2, 3), ("e.json",)),
        ("export --out g/tiny.json (a golden .json armanim wrote)", ["export", "o/tiny", "--out", "g/tiny.json"], then(finished_run, lambda d: armanim_in(d, *update)), (2, 3), ("g",)),
        ("view --out the golden .json armanim wrote", ["view", "o/tiny", "--out", "g/tiny.json"], then(finished_run, lambda d: armanim_in(d, *update)), (2, 3), ("g",)),
        ("view --out o/index.csv (a batch's table)", ["view", "o/tiny", "--out", "o/index.csv"], batched, (2, 3), ("o/index.csv",)),
        ("export --out o/.tiny.lock (the run's lock)", ["export", "o/tiny", "--out", "o/.tiny.lock"], finished_run, (2, 3), ("o/.tiny.lock",)),
        ("view --out o/.tiny.lock (the run's lock)", ["view", "o/tiny", "--out", "o/.tiny.lock"], finished_run, (2, 3), ("o/.tiny.lock",)),
        ("schema --out o/.tiny.lock (the run's lock)", ["schema", "--out", "o/.tiny.lock"], finished_run, (2, 3), ("o/.tiny.lock",)),
        ("check --update --golden o/.tiny.abcdefgh.partial (a staging name)", ["check", "s.yaml", "--golden", "o/.tiny.abcdefgh.partial", "--update"], finished_run, (2,), ()),
        ("fk --png into o/.tiny.old-99 (a moved-aside name)", ["fk", "--angles", "0,0,0,0", "--png", "o/.tiny.old-99/p.png"], then(finished_run, lambda d: (d / "o/.tiny.old-99").mkdir()), (2, 3), ("o/.tiny.old-99",)),
        ("run again, the run folder's scene.yaml hard-linked by the user as mine.yaml", run, then(finished_run, hardlink("o/tiny/scene.yaml", "mine.yaml"), mine("s.yaml", TINY.replace("[0.5, -1, 1]", "[0.5, -1, 1.2]"))), (0, 3), ("mine.yaml",)),
        ("sweep again, the user's notes in a variant's folder", sweep, then(swept, in_variant, mine("o/tiny_step-0.1/notes.txt")), (3,), ("o/tiny_step-0.1/notes.txt",)),
        ("sweep, the user's file at a variant's folder name", sweep, then(scene, mine("o/tiny_step-0.1", "mine")), (3,), ("o/tiny_step-0.1",)),
        ("a batch again, the user's notes in the first scene's folder", batch, then(batched, mine("o/a/notes.txt")), (3,), ("o/a/notes.txt",)),
    ]
    # fmt: on
    out = [
        Attempt(k, label, args, setup, codes, keep=keep, timeout=300, litter_in=("o", "."))
        for label, args, setup, codes, keep in table
    ]
    out.append(
        Attempt(
            k,
            "run s.yaml s.yaml (one scene twice in a batch)",
            ["run", "s.yaml", "s.yaml", "--out", "o", "--no-video", "-q"],
            scene,
            (0, 2),
            keep=("s.yaml",),
            timeout=300,
            after=whole_or_none("o/tiny", "o/index.csv"),
        )
    )

    # the capsule cache and the temporary folder where outputs go
    def fitted_robot(d: Path) -> None:
        urdf_robot(collision=col("a.stl"), files={"a.stl": box_stl()})(d)

    out.append(  # the first run makes the cache in the folder it will swap: refused, naming the cache
        Attempt(
            k,
            "run, ARMANIM_CACHE_DIR inside the run folder",
            run,
            fitted_robot,
            (0, 3),
            timeout=300,
            env={"ARMANIM_CACHE_DIR": "{d}/o/m/cache"},
            message_if_3=r"ARMANIM_CACHE_DIR",
        )
    )
    for label, cache, keep in (
        ("the outputs folder itself", "{d}/o", ()),
        ("the user's own folder (the scene's)", "{d}", ("s.yaml", "robot.urdf", "a.stl")),
    ):
        out.append(
            Attempt(
                k,
                f"run twice, ARMANIM_CACHE_DIR {label}",
                run,
                then(
                    fitted_robot,
                    lambda d, cache=cache: armanim_in(d, *run, env={"ARMANIM_CACHE_DIR": cache.replace("{d}", str(d))}),
                ),
                (0, 3),
                keep=keep,
                timeout=300,
                env={"ARMANIM_CACHE_DIR": cache},
                message_if_3=r"ARMANIM_CACHE_DIR",
            )
        )
    out.append(
        Attempt(
            k,
            "run with video --jobs 2 again, TMPDIR inside the run folder",
            ["run", "s.yaml", "--out", "o", "-q", "--jobs", "2"],
            lambda d: finished_run(d, video=True) and None,
            (0, 2, 3),
            timeout=300,
            env={"TMPDIR": "{d}/o/tiny"},
            message_if_3=r"TMPDIR|temporary",
            after=whole_or_none("o/tiny"),
        )
    )
    return out


def inputs13_attempts() -> list[Attempt]:
    """Scene files in YAML's corners campaigns 10-12 did not write (tabs, merge keys, complex keys,
    YAML 1.1 scalars, look-alike keys, fields of the wrong shape), command-line flags at theirs
    (a value that looks like a flag, repeated flags, ranges, empty values), and the environment
    (an ASCII-only terminal printing a name that is not, COLUMNS of nonsense, an empty cache
    variable, a browser that cannot open). Exit 0, or 2 naming the file and line or the flag."""
    k = "inputs13"
    out: list[Attempt] = []
    t = TINY
    # fmt: off
    scenes: list[tuple[str, str | bytes]] = [
        ("a tab before a key", t.replace("name: tiny", "\tname: tiny")),
        ("a tab inside a flow list", t.replace("[1, 1, 1]}", "[1,\t1,\t1]}")),
        ("a merge key <<", t.replace("arm: {links: [1, 1, 1]}", "base: &b {links: [1, 1, 1]}\narm: {<<: *b}")),
        ("a merge key of a list", t.replace("arm: {links: [1, 1, 1]}", "arm: {<<: [1, 2]}")),
        ("a complex key ? [a]", t + "? [a, b]\n: 1\n"),
        ("only comments", "# nothing\n# here\n"),
        ("only ---", "---\n"),
        ("only ...", "...\n"),
        ("1,000,001 bytes (one past its limit)", t + "#" + "x" * (1_000_001 - len(t) - 2) + "\n"),
        ("1,000,000 bytes (its limit)", t + "#" + "x" * (1_000_000 - len(t) - 2) + "\n"),
        ("a key in capitals (Goals)", t.replace("goals:", "Goals:")),
        ("a key of a Cyrillic o (gоals)", t.replace("goals:", "g\u043eals:")),
        ("a key with a trailing space, quoted", t.replace("goals:", "'goals ':")),
        ("a key with a zero-width space", t.replace("goals:", "goals\u200b:")),
        ("links of 1e0 (YAML 1.1 reads a string)", t.replace("[1, 1, 1]}", "[1e0, 1, 1]}")),
        ("links of 1_000", t.replace("[1, 1, 1]}", "[1_000, 1, 1]}")),
        ("links of 0o7", t.replace("[1, 1, 1]}", "[0o7, 1, 1]}")),
        ("links of .5 and +1", t.replace("[1, 1, 1]}", "[.5, +1, 1]}")),
        ("links of '1' (quoted)", t.replace("[1, 1, 1]}", "['1', 1, 1]}")),
        ("links a string '1,1,1'", t.replace("[1, 1, 1]}", "'1,1,1'}")),
        ("links a mapping", t.replace("[1, 1, 1]}", "{a: 1}}")),
        ("links nested [[1, 1, 1]]", t.replace("[1, 1, 1]}", "[[1, 1, 1]]}")),
        ("goals a single goal, not a list", t.replace("[[1, 1, 1], [0.5, -1, 1]]", "{position: [1, 1, 1]}")),
        ("a goal of four numbers", t.replace("[0.5, -1, 1]", "[0.5, -1, 1, 0]")),
        ("a goal's position of a string", t.replace("[0.5, -1, 1]", "{position: '0.5, -1, 1'}")),
        ("a hold of -1", t.replace("[0.5, -1, 1]", "{position: [0.5, -1, 1], hold: -1}")),
        ("a blend of -0.1", t.replace("[0.5, -1, 1]", "{position: [0.5, -1, 1], blend: -0.1}")),
        ("a hold of 1e-320", t.replace("[0.5, -1, 1]", "{position: [0.5, -1, 1], hold: 1e-320}")),
        ("self_collision on (YAML 1.1 boolean)", t.replace("arm: {links: [1, 1, 1]}", "arm: {links: [1, 1, 1], self_collision: on}")),
        ("self_collision 'off' quoted", t.replace("arm: {links: [1, 1, 1]}", "arm: {links: [1, 1, 1], self_collision: 'off'}")),
        ("render.size a string 160x90", t.replace("size: [160, 90]", "size: 160x90")),
        ("render.fps a string '10'", t.replace("fps: 10", "fps: '10'")),
        ("render.format MP4 in capitals", t.replace("fps: 10}", "fps: 10, format: MP4}")),
        ("solver.method PINV in capitals", t + "solver: {method: PINV}\n"),
        ("solver.weights an unknown key", t + "solver: {weights: {nosuch: 1}}\n"),
        ("an obstacle of an unknown shape key", t + "obstacles: [{cone: {radius: 1}}]\n"),
        ("a box obstacle of size 0 edge", t + "obstacles: [{box: {center: [3, 3, 3], size: [0, 1, 1]}}]\n"),
        ("a capsule of equal ends", t + "obstacles: [{capsule: {a: [3, 3, 3], b: [3, 3, 3], radius: 0.1}}]\n"),
        ("name '' (empty)", t.replace("name: tiny", "name: ''")),
        ("name with a trailing space", t.replace("name: tiny", "name: 'tiny '")),
        ("name of 100 characters", t.replace("name: tiny", "name: " + "n" * 100)),
        ("name of 101 characters", t.replace("name: tiny", "name: " + "n" * 101)),
        ("version 01", t.replace("version: 1", "version: 01")),
        ("version '1'", t.replace("version: 1", "version: '1'")),
        ("no version", t.replace("version: 1\n", "")),
        ("a document end marker then more", t + "...\ngoals: []\n"),
        ("latin-1 bytes in a comment", t.encode() + b"# caf\xe9\n"),
        ("a scene in UTF-8 with a BOM", "\ufeff" + t),
    ]
    # fmt: on
    for label, text in scenes:
        out.append(
            Attempt(
                k,
                f"validate, {label}",
                ["validate", "s.yaml"],
                tiny_scene(text=text),
                (0, 2),
                timeout=120,
                message_if_2=r"s\.yaml(:\d+)?: ",
            )
        )
    # flags
    finished = lambda d: finished_run(d) and None  # noqa: E731
    # fmt: off
    flags: list[tuple[str, list[str], Callable[[Path], None], tuple[int, ...], str]] = [
        ("fk --angles -10,0,0,0 (a value that looks like a flag)", ["fk", "--angles", "-10,0,0,0"], lambda d: None, (0, 2), "--angles"),
        ("ik --goal -1,1,1 (a value that looks like a flag)", ["ik", "--goal", "-1,1,1"], lambda d: None, (0, 1, 2), "--goal"),
        ("ik --goal '1, 1, 1' (spaces)", ["ik", "--goal", "1, 1, 1"], lambda d: None, (0, 1, 2), "--goal"),
        ("ik --goal 1,1,1 --goal 2,2,2 (twice)", ["ik", "--goal", "1,1,1", "--goal", "2,2,2"], lambda d: None, (0, 1, 2), "--goal"),
        ("ik --from 0,0 (two angles for four joints)", ["ik", "--goal", "1,1,1", "--from", "0,0"], lambda d: None, (2,), "--from"),
        ("ik --tolerance 0", ["ik", "--goal", "1,1,1", "--tolerance", "0"], lambda d: None, (0, 1, 2), "--tolerance"),
        ("ik --tolerance nan", ["ik", "--goal", "1,1,1", "--tolerance", "nan"], lambda d: None, (2,), "--tolerance"),
        ("ik --orientation-tolerance -1", ["ik", "--goal", "1,1,1", "--orientation", "tool_axis=0,0,1", "--orientation-tolerance", "-1"], lambda d: None, (2,), "--orientation-tolerance"),
        ("ik --orientation tool_axis=0,0,0", ["ik", "--goal", "1,1,1", "--orientation", "tool_axis=0,0,0"], lambda d: None, (2,), "--orientation"),
        ("ik --orientation axis=0,0,0,90", ["ik", "--goal", "1,1,1", "--orientation", "axis=0,0,0,90"], lambda d: None, (2,), "--orientation"),
        ("ik --orientation 'rpy='", ["ik", "--goal", "1,1,1", "--orientation", "rpy="], lambda d: None, (2,), "--orientation"),
        ("fk --base 1,2", ["fk", "--base", "1,2", "--angles", "0,0,0,0"], lambda d: None, (2,), "--base"),
        ("fk --links 1,nan", ["fk", "--links", "1,nan", "--angles", "0,0"], lambda d: None, (2,), "--links"),
        ("fk --links '' (empty: the default links)", ["fk", "--links", "", "--angles", "0"], lambda d: None, (2,), "--links|--angles"),
        ("fk --angles of five for four joints", ["fk", "--angles", "0,0,0,0,0"], lambda d: None, (2,), "--angles"),
        ("fk --robot PANDA in capitals", ["fk", "--robot", "PANDA", "--angles", "0,0,0,0,0,0,0"], lambda d: None, (0, 2), "--robot"),
        ("fk --scene s.yaml --robot panda (both)", ["fk", "--scene", "s.yaml", "--robot", "panda", "--angles", "0,0,0"], tiny_scene(), (2,), "--scene|--robot"),
        ("robots --package-dir without --fit", ["robots", "--package-dir", "."], lambda d: None, (0, 2), "--package-dir|--fit"),
        ("export --format csv", ["export", "o/tiny", "--format", "csv"], finished, (2,), "--format"),
        ("export --format ''", ["export", "o/tiny", "--format", ""], finished, (2,), "--format"),
        ("check --atol nan", ["check", "s.yaml", "--golden", "g", "--atol", "nan"], tiny_scene(), (2,), "--atol"),
        ("compare --atol-deg inf", ["compare", "o/tiny/trajectory.csv", "o/tiny/trajectory.csv", "--atol-deg", "inf"], finished, (0, 2), "--atol-deg"),
        ("run --jobs 1 --jobs 2 (twice)", ["run", "s.yaml", "--out", "o", "--no-video", "-q", "--jobs", "1", "--jobs", "2"], tiny_scene(), (0, 2), "--jobs"),
        ("run --format GIF in capitals", ["run", "s.yaml", "--out", "o", "-q", "--format", "GIF", "--size", "64x48"], tiny_scene(), (0, 2), "--format"),
        ("run --quality ultra", ["run", "s.yaml", "--out", "o", "-q", "--quality", "ultra"], tiny_scene(), (2,), "--quality"),
        ("run --quality ''", ["run", "s.yaml", "--out", "o", "-q", "--quality", ""], tiny_scene(), (2,), "--quality"),
        ("run --size '' (empty: as not given)", ["run", "s.yaml", "--out", "o", "-q", "--size", ""], tiny_scene(), (0, 2), "--size"),
        ("run --out ''", ["run", "s.yaml", "--out", "", "--no-video", "-q"], tiny_scene(), (0, 2), "--out"),
        ("run --scheduler '' (empty: as not given)", ["run", "s.yaml", "--out", "o", "--no-video", "-q", "--scheduler", ""], tiny_scene(), (0, 2), "--scheduler"),
        ("run '' (an empty scene path)", ["run", "", "--out", "o", "--no-video", "-q"], lambda d: None, (2,), "''|scene|SCENES|path"),
        ("validate - (standard input, closed)", ["validate", "-"], lambda d: None, (2,), "-"),
        ("sweep --set '' (empty)", ["sweep", "s.yaml", "--set", "", "--out", "o", "-q"], tiny_scene(), (2,), "--set"),
        ("sweep --set = (no field)", ["sweep", "s.yaml", "--set", "=1", "--out", "o", "-q"], tiny_scene(), (2,), "--set"),
        ("sweep --set solver.step (no =)", ["sweep", "s.yaml", "--set", "solver.step", "--out", "o", "-q"], tiny_scene(), (2,), "--set"),
    ]
    # fmt: on
    for label, args, setup, codes, flag in flags:
        out.append(Attempt(k, label, args, setup, codes, timeout=200, message_if_2=flag))
    # the environment
    bad = "version: 1\nname: tiny\narm: {links: [1, 1, 'x']}\ngoals: [[1, 1, 1]]\n"
    # fmt: off
    environments: list[tuple[str, list[str], Callable[[Path], None], dict, tuple[int, ...], str]] = [
        ("validate s\u00e9.yaml (a bad field) under PYTHONIOENCODING=ascii", ["validate", "s\u00e9.yaml"], tiny_scene("s\u00e9.yaml", bad), {"PYTHONIOENCODING": "ascii"}, (2,), r"s.*yaml"),
        ("validate s\u00e9.yaml (a bad field) under LC_ALL=C and PYTHONUTF8=0", ["validate", "s\u00e9.yaml"], tiny_scene("s\u00e9.yaml", bad), {"LC_ALL": "C", "LANG": "C", "PYTHONUTF8": "0", "PYTHONIOENCODING": ""}, (2,), r"s.*yaml"),
        ("run a scene named caf\u00e9 under PYTHONIOENCODING=ascii", ["run", "s.yaml", "--out", "o", "--no-video"], tiny_scene(text=TINY.replace("name: tiny", "name: caf\u00e9")), {"PYTHONIOENCODING": "ascii"}, (0, 2), r"name"),
        ("robots under PYTHONIOENCODING=ascii", ["robots"], lambda d: None, {"PYTHONIOENCODING": "ascii"}, (0,), "."),
        ("run under COLUMNS=0", ["run", "s.yaml", "--out", "o", "--no-video"], tiny_scene(), {"COLUMNS": "0"}, (0,), "."),
        ("run under COLUMNS=abc", ["run", "s.yaml", "--out", "o", "--no-video"], tiny_scene(), {"COLUMNS": "abc"}, (0,), "."),
        ("run under COLUMNS=5", ["run", "s.yaml", "--out", "o", "--no-video"], tiny_scene(), {"COLUMNS": "5"}, (0,), "."),
        ("validate a fitted URDF with ARMANIM_CACHE_DIR='' (empty)", ["validate", "s.yaml"], urdf_robot(collision=col("a.stl"), files={"a.stl": box_stl()}), {"ARMANIM_CACHE_DIR": ""}, (0,), "."),
        ("validate a fitted URDF with ARMANIM_CACHE_DIR a relative path", ["validate", "s.yaml"], urdf_robot(collision=col("a.stl"), files={"a.stl": box_stl()}), {"ARMANIM_CACHE_DIR": "rel/cache"}, (0,), "."),
        ("view --open without a display or browser", ["view", "o/tiny", "--open"], finished, {"DISPLAY": "", "BROWSER": "/nonexistent/browser"}, (0, 2, 3), "."),
        ("view --open with BROWSER a program that fails", ["view", "o/tiny", "--open"], finished, {"DISPLAY": "", "BROWSER": "false"}, (0, 2, 3), "."),
    ]
    # fmt: on
    for label, args, setup, env, codes, pattern in environments:
        out.append(Attempt(k, label, args, setup, codes, timeout=120, env=env, message=pattern))
    return out


def summary_agrees(spec: dict) -> Callable[[Path], list[str]]:
    """After a run of ``spec``: summary.json says what trajectory.csv shows. Each position goal's
    last frame holds its final distance and its ``reached``; the totals count the goals reached."""

    def check(d: Path) -> list[str]:
        import csv as _csv
        import json as _json

        folder = d / "o" / spec["name"]
        if not (folder / "summary.json").is_file():
            return ["no summary.json"]
        summary = _json.loads((folder / "summary.json").read_text())
        with open(folder / "trajectory.csv", newline="") as handle:
            rows = list(_csv.DictReader(handle))
        problems = []
        goals = summary["goals"]
        reached = sum(1 for g in goals if g["reached"])
        if summary["totals"]["reached"] != reached or summary["totals"]["missed"] != len(goals) - reached:
            problems.append(
                f"totals {summary['totals']['reached']} reached, {summary['totals']['missed']} missed; the goals say {reached}"
            )
        for (kind, _), g in zip(spec["goals"], goals):
            if kind not in ("point", "hold", "blend"):
                continue
            row = rows[g["last_frame"]]
            if (row["reached"] == "1") != bool(g["reached"]) and kind != "blend":
                problems.append(
                    f"goal {g['index']}: summary reached={g['reached']}, its last frame's reached={row['reached']}"
                )
            if g["final_distance"] is not None and abs(float(row["goal_distance"]) - g["final_distance"]) > 1e-9:
                problems.append(
                    f"goal {g['index']}: final_distance {g['final_distance']:.9g}, its last frame's {row['goal_distance']}"
                )
        return problems

    return check


WRONG13_KINDS = ("point", "joints", "hold", "blend", "line", "arc", "polyline", "text")
"""wrong13's goal kinds: every kind the random scenes know, together (but wrong12's joint goals at
their limits' edge, whose poses may overlap the arm's own links: refused at validate, exit 2)."""


def oracle_runs(k: str, seeds, held: str) -> list[Attempt]:
    """A run of :func:`wrong_scene` of each seed with every kind of goal (:data:`WRONG13_KINDS`),
    held to the rates, the clock and its summary; a scene refused for a joint goal whose pose
    overlaps the arm's own links is exit 2 at its line (nothing to hold then)."""
    out = []
    for seed in seeds:
        text, spec = wrong_scene(seed, WRONG13_KINDS)
        out.append(
            Attempt(
                k,
                f"run a random arm among spheres with every kind of goal (seed {seed}), {held}",
                ["run", "s.yaml", "--out", "o", "--no-video", "-q"],
                tiny_scene(text=text),
                (0, 2),
                timeout=500,
                message_if_2=r"s\.yaml:\d+: goals\[\d+\]: the joint goal's pose has link\d and link\d overlapping",
                after=lambda d, spec=spec: (
                    []
                    if not (d / "o").exists()
                    else both(
                        trajectory_breaks(spec), clock_breaks(f"o/{spec['name']}", spec["fps"]), summary_agrees(spec)
                    )(d)
                ),
            )
        )
    return out


def random_ik_attempts(k: str, rng, count: int, first: int, spread: float) -> list[Attempt]:
    """``count`` ik answers of random arms from random starts within +-``spread`` degrees, held to
    the oracle (numbered from ``first``)."""
    out = []
    for i in range(count):
        links, goal = random_reachable_goal(rng)
        start = [round(float(x), 1) for x in rng.uniform(-spread, spread, len(links))]
        method = str(rng.choice(["pinv", "dls", "newton", "gradient"]))
        out.append(
            Attempt(
                k,
                f"ik of a random {len(links)}-link arm by {method} from a random start ({first + i}), held to the oracle",
                ik_args(links, goal, method, start),
                lambda d: None,
                (0, 1),
                timeout=200,
                after=ik_breaks(links, goal, method, start),
            )
        )
    return out


def wrong13_attempts() -> list[Attempt]:
    """Random arms with every kind of goal together (new seeds), held to the rate limits, the clock
    and to their own summary; fk in degrees and ik from random starts against the campaign's
    kinematics (new draws); compare's verdict with its files in the other order; --strict's exit
    code; a batch's index.csv against each run's summary."""
    import numpy as np

    k = "wrong13"
    out: list[Attempt] = []
    out += oracle_runs(k, range(600, 616), "held to the invariants, the clock and its summary")
    rng = np.random.default_rng(13)
    out += [random_fk_attempt(k, 100 + i, rng, 179, 3) for i in range(4)]
    out += random_ik_attempts(k, rng, 6, 100, 90.0)
    for label, setup, flags, code in (
        ("phi1 moved by 2e-6 deg (twice its tolerance)", moved_cell(2, 3, 2e-6), [], 1),
        ("phi1 moved by 5e-7 deg (half its tolerance)", moved_cell(2, 3, 5e-7), [], 0),
        ("phi3 moved by 3e-3 deg under --atol-deg 1e-3", moved_cell(3, 5, 3e-3), ["--atol-deg", "1e-3"], 1),
        ("z moved by 5e-4 under --atol 1e-3", moved_cell(4, 8, 5e-4), ["--atol", "1e-3"], 0),
        ("z moved by 2e-3 under --atol 1e-3", moved_cell(4, 8, 2e-3), ["--atol", "1e-3"], 1),
        ("reached 0 made 1", moved_cell(2, 11, None), [], 1),
    ):
        out.append(
            Attempt(
                k,
                f"compare in the other order (ACTUAL first), {label}",
                ["compare", "e.csv", "a.csv", *flags],
                setup,
                (code,),
                timeout=120,
            )
        )
    far = TINY.replace("[0.5, -1, 1]", "[0, 0, 10]").replace("render:", "solver: {max_frames_per_goal: 30}\nrender:")
    out.append(
        Attempt(
            k,
            "run --strict, a goal out of reach: exit 1",
            ["run", "s.yaml", "--out", "o", "--no-video", "--strict"],
            tiny_scene(text=far),
            (1,),
            timeout=300,
            message=r"miss|not reached|reach",
        )
    )
    out.append(
        Attempt(
            k,
            "run --strict, every goal reached: exit 0",
            ["run", "s.yaml", "--out", "o", "--no-video", "--strict"],
            tiny_scene(),
            (0,),
            timeout=300,
        )
    )

    def index_agrees(d: Path) -> list[str]:
        import csv as _csv
        import json as _json

        index = d / "o/index.csv"
        if not index.is_file():
            return ["no o/index.csv"]
        with open(index, newline="") as handle:
            rows = list(_csv.DictReader(handle))
        problems = []
        for row in rows:
            name = row.get("name") or row.get("scene")
            if row.get("status") != "ok":  # a scene refused (its row says why): no folder of its own
                if (d / "o" / str(name)).exists():
                    problems.append(f"index.csv says {name} is {row.get('status')}, yet o/{name} exists")
                continue
            summary = d / "o" / str(name) / "summary.json"
            if not summary.is_file():
                problems.append(f"index.csv names {name}, which has no summary")
                continue
            totals = _json.loads(summary.read_text())["totals"]
            for column in ("reached", "missed", "frames"):
                if column in row and row[column] != "" and float(row[column]) != float(totals[column]):
                    problems.append(f"index.csv's {column} of {name} is {row[column]}, its summary's {totals[column]}")
        return problems or ([] if rows else ["index.csv has no rows"])

    for jobs in ("1", "2"):

        def three(d: Path) -> None:
            for seed in (620, 621, 622):
                text, _ = wrong_scene(seed, WRONG13_KINDS)
                write(d / f"w{seed}.yaml", text)
            write(d / "far.yaml", far.replace("name: tiny", "name: far"))

        out.append(
            Attempt(
                k,
                f"a batch --jobs {jobs} of three random arms and a miss: index.csv says what the summaries say",
                [
                    "run",
                    "w620.yaml",
                    "w621.yaml",
                    "w622.yaml",
                    "far.yaml",
                    "--out",
                    "o",
                    "--no-video",
                    "-q",
                    "--jobs",
                    jobs,
                ],
                three,
                (0,),
                timeout=600,
                after=index_agrees,
            )
        )
    return out


# ------------------------------------------------------------------ the fourteenth campaign
#
# A smaller campaign on the code campaign 13 fixed (SIGHUP an interruption, the cache inside a run
# folder named): mesh14, frames14, signals14, loss14, inputs14, wrong14, none a repeat.


def mesh14_attempts() -> list[Attempt]:
    """The box split in ways that keep its triangles' order (two COLLADA primitives, two geometries
    of one node, OBJ groups and objects, two ASCII solids), turned a full turn, scaled by a third,
    or a visual fitted where the link has no collision: each fits as the plain STL."""
    k = "mesh14"
    out: list[Attempt] = []
    pts = box_points()
    half = len(BOX_TRIANGLES) // 2
    tri_p = [" ".join(str(i) for t in part for i in t) for part in (BOX_TRIANGLES[:half], BOX_TRIANGLES[half:])]
    two_prims = box_dae().replace(
        f'<triangles count="12"><input semantic="VERTEX" source="#v" offset="0"/><p>{" ".join(str(i) for t in BOX_TRIANGLES for i in t)}</p></triangles>',
        "".join(
            f'<triangles count="{half}"><input semantic="VERTEX" source="#v" offset="0"/><p>{p}</p></triangles>'
            for p in tri_p
        ),
    )
    obj_lines = box_obj().splitlines()
    faces_at = next(i for i, line in enumerate(obj_lines) if line.startswith("f "))
    grouped = (
        "\n".join(
            [*obj_lines[:faces_at], "g a", *obj_lines[faces_at : faces_at + half], "g b", *obj_lines[faces_at + half :]]
        )
        + "\n"
    )
    objects = grouped.replace("g a", "o a").replace("g b", "o b")

    def solid(part) -> str:
        return (
            "solid p\n"
            + "".join(
                " facet normal 0 0 0\n  outer loop\n"
                + "".join("   vertex {} {} {}\n".format(*pts[i]) for i in t)
                + "  endloop\n endfacet\n"
                for t in part
            )
            + "endsolid p\n"
        )

    # fmt: off
    cases = [
        ("a COLLADA of two triangles elements", "a.dae", {"a.dae": two_prims}, "", ""),
        ("an OBJ of two groups", "a.obj", {"a.obj": grouped}, "", ""),
        ("an OBJ of two objects", "a.obj", {"a.obj": objects}, "", ""),
        ("an ASCII STL of two solids, a half each", "a.stl", {"a.stl": solid(BOX_TRIANGLES[:half]) + solid(BOX_TRIANGLES[half:])}, "", ""),
        ("an STL three times the size at URDF scale 1/3", "a.stl", {"a.stl": box_stl(3.0)}, "0.3333333333333333 0.3333333333333333 0.3333333333333333", ""),
        ("an STL under a collision origin turned a full turn", "a.stl", {"a.stl": box_stl()}, "", "full"),
        ("a COLLADA of a NORMAL input at offset 1, in millimetres", "a.dae", {"a.dae": box_dae("normals", unit="0.001", scale=1000.0)}, "", ""),
        ("an OBJ of quads with CRLF lines", "a.obj", {"a.obj": box_obj("quad", newline="\r\n")}, "", ""),
    ]
    # fmt: on
    for label, name, files, scale, turn in cases:
        origin = "<origin xyz='0 0 0' rpy='0 0 6.283185307179586'/>" if turn else ""
        tag = f"<collision>{origin}{mesh_tag(name, scale)}</collision>"

        def setup(d: Path, tag=tag, files=files) -> None:
            urdf_robot(collision=tag, files={"ref.stl": box_stl(), **files})(d)
            write(d / "ref.urdf", urdf_text(collision=col("ref.stl")))

        out.append(
            Attempt(
                k,
                f"robots --fit, the box as {label}, fits as the plain STL",
                FIT,
                setup,
                (0,),
                timeout=200,
                env={"ARMANIM_CACHE_DIR": "{d}/cache"},
                after=same_fit("robot.urdf", "ref.urdf"),
            )
        )

    def visual_only(d: Path) -> None:
        write(d / "a.stl", box_stl())
        text = urdf_links({2: col("a.stl")})
        write(d / "ref.urdf", text)
        write(d / "robot.urdf", text.replace(col("a.stl"), vis("a.stl")))

    out.append(
        Attempt(
            k,
            "robots --fit, link l2 with a visual box and no collision: fitted as the same box as collision",
            FIT,
            visual_only,
            (0,),
            timeout=200,
            after=same_fit("robot.urdf", "ref.urdf"),
        )
    )
    return out


def frames14_attempts() -> list[Attempt]:
    """The clock at rates campaign 13 did not take (3, 16.6667, 33.333, 60, 90, 100 fps), by the
    scene and by --fps over another scene rate, and a sweep of two NTSC rates."""
    k = "frames14"
    out: list[Attempt] = []
    run = ["run", "s.yaml", "--out", "o", "--no-video", "-q"]
    for fps, hold in (
        ("3", "0.5"),
        ("16.6667", "0.15"),
        ("33.333", "0.1"),
        ("60", "0.0125"),
        ("90", "1.5"),
        ("100", "0.005"),
    ):
        text = HOLDS.replace("HOLD", hold).replace("FPS", fps)
        out.append(
            clock_attempt(k, f"run at render.fps {fps}, holds of {hold} s: the clock adds up", run, text, float(fps))
        )
    for flags, fps in ((["--fps", "24"], 24.0), (["--quality", "medium"], 30.0), (["--fps", "0.25"], 0.25)):
        text = HOLDS.replace("HOLD", "0.75").replace("FPS", "7")
        label = f"run {' '.join(flags)} over a scene at 7 fps: the clock adds up at {fps:g} fps"
        out.append(clock_attempt(k, label, [*run, *flags], text, fps))

    out.append(
        Attempt(
            k,
            "sweep --set render.fps=29.97,59.94: each variant's clock adds up",
            ["sweep", "s.yaml", "--set", "render.fps=29.97,59.94", "--out", "o", "-q", "--jobs", "1"],
            tiny_scene(text=HOLDS.replace("HOLD", "0.2").replace("FPS", "10")),
            (0,),
            timeout=400,
            after=variants_clock((29.97, 59.94)),
        )
    )
    return out


def signals14_attempts() -> list[Attempt]:
    """SIGHUP, now an interruption, in the commands and moments campaign 13 did not send it: view
    into the run folder, render into it, a read-only check, validate of many scenes, fk's picture,
    a sweep with video, ik; and SIGHUP then Ctrl-C, Ctrl-C then SIGHUP."""
    k = "signals14"
    out: list[Attempt] = []
    video30 = TINY.replace("fps: 10", "fps: 30")
    short = LONG.replace("hold: 3600", "hold: 30").replace("hold: 400", "hold: 30")
    update = ["check", "s.yaml", "--golden", "g", "--update"]
    # fmt: off
    cases: list[tuple] = [
        ("view of a 40,000-frame run into its folder", ["view", "o/tiny"], lambda d: finished_run(d, LONG) and None, 1.5, ("o/tiny",), ("o",)),
        ("render into the run folder", ["render", "o/tiny", "-q", "--size", "320x180", "--jobs", "1"], lambda d: finished_run(d, short) and None, 3.0, ("o/tiny",), ("o",)),
        ("check (no update) of a 40,000-frame scene", ["check", "s.yaml", "--golden", "g"], then(tiny_scene(text=LONG), lambda d: armanim_in(d, *update)), 2.0, ("g/tiny.csv",), ("g",)),
        ("validate of 200 scenes", ["validate", *[f"s{i}.yaml" for i in range(200)]], lambda d: [write(d / f"s{i}.yaml", TINY) for i in range(200)] and None, 1.5, (), (".",)),
        ("fk --robot panda --png", ["fk", "--robot", "panda", "--angles", "0,-20,0,-120,0,100,45", "--png", "p.png"], lambda d: None, 1.5, ("p.png",), (".",)),
        ("sweep --video --jobs 2 of 2 variants", ["sweep", "s.yaml", "--set", "solver.step=0.1,0.2", "--out", "o", "-q", "--video", "--jobs", "2"], tiny_scene(), 2.5, (), ("o",)),
        ("run --jobs 2 with video at 30 fps", ["run", "s.yaml", "--out", "o", "-q", "--jobs", "2"], tiny_scene(text=video30), 4.0, ("o/tiny",), ("o",)),
        ("render --format gif --out fig", ["render", "o/tiny", "--format", "gif", "--out", "fig", "-q", "--size", "320x180"], lambda d: finished_run(d, short) and None, 2.5, ("fig",), ("o", "fig", ".")),
    ]
    # fmt: on
    for label, args, setup, delay, whole, where in cases:
        out.append(
            Attempt(
                k,
                f"{label}, SIGHUP to the group at {delay:g} s",
                args,
                setup,
                (0, 130),
                timeout=300,
                interrupt=(delay, "SIGHUPG"),
                litter_in=where,
                linger=5.0,
                after=both(whole_or_none(*whole), again_tidy(*args, codes=(0, 1), where=where)),
            )
        )
    out.append(
        Attempt(
            k,
            "ik --robot panda of an unreachable pose, SIGHUP to armanim alone at 1.5 s",
            ["ik", "--robot", "panda", "--goal", "5,5,5", "--max-iterations", "100000000", "--tolerance", "1e-300"],
            lambda d: None,
            (0, 1, 130),
            timeout=200,
            interrupt=(1.5, "SIGHUP"),
        )
    )
    for first, second in (("SIGHUPG", "SIGINT"), ("SIGINT", "SIGHUPG"), ("SIGHUP", "SIGTERM")):
        out.append(
            Attempt(
                k,
                f"run with video, {first} at 3 s then {second} 30 ms later",
                ["run", "s.yaml", "--out", "o", "-q", "--jobs", "1"],
                tiny_scene(text=video30),
                (0, 130),
                timeout=300,
                interrupt=(3.0, first),
                also=((3.03, second),),
                linger=5.0,
                after=whole_or_none("o/tiny"),
            )
        )
    return out


def loss14_attempts() -> list[Attempt]:
    """Every single-file writer aimed, through a symbolic link at its --out, at a file inside a run
    folder ("no command writes into another run's folder ... through a link"), and at a hard link
    the user made to a run's file."""
    k = "loss14"
    out: list[Attempt] = []
    moveit = mine("w.scene", "w\n* b\n1\nbox\n0.1 0.1 0.1\n1 1 1\n0 0 0 1\n0 0 0 0\n.\n")
    # fmt: off
    cases: list[tuple] = [
        ("check --update, g/tiny.csv a link to the run's trajectory.csv", ["check", "s.yaml", "--golden", "g", "--update"], symlink("../o/tiny/trajectory.csv", "g/tiny.csv")),
        ("check --update, g/tiny.json a link to the run's summary.json", ["check", "s.yaml", "--golden", "g", "--update"], symlink("../o/tiny/summary.json", "g/tiny.json")),
        ("export --out e.json, a link to the run's summary.json", ["export", "o/tiny", "--out", "e.json"], symlink("o/tiny/summary.json", "e.json")),
        ("view --out v.html, a link to the run's scene.yaml", ["view", "o/tiny", "--out", "v.html"], symlink("o/tiny/scene.yaml", "v.html")),
        ("schema --out x.json, a link to the run's timing.json", ["schema", "--out", "x.json"], symlink("o/tiny/timing.json", "x.json")),
        ("fk --png p.png, a link to the run's trajectory.csv", ["fk", "--angles", "0,0,0,0", "--png", "p.png"], symlink("o/tiny/trajectory.csv", "p.png")),
        ("import moveit --out m.yaml, a link to the run's scene.yaml", ["import", "moveit", "w.scene", "--robot", "panda", "--out", "m.yaml"], then(moveit, symlink("o/tiny/scene.yaml", "m.yaml"))),
        ("export --out a new name through a link to the run folder", ["export", "o/tiny", "--out", "r/e.json"], symlink("o/tiny", "r")),
        ("view --out a new name through a link to the run folder", ["view", "o/tiny", "--out", "r/v.html"], symlink("o/tiny", "r")),
        ("export --out e.json, a hard link the user made to the run's trajectory.csv", ["export", "o/tiny", "--out", "e.json"], hardlink("o/tiny/trajectory.csv", "e.json")),
    ]
    # fmt: on
    for label, args, setup in cases:
        out.append(
            Attempt(
                k,
                label,
                args,
                then(finished_run, setup),
                (2, 3),
                keep=("o/tiny",),
                timeout=300,
                after=again_tidy("run", "s.yaml", "--out", "o", "--no-video", "-q", where=("o",)),
            )
        )
    return out


def inputs14_attempts() -> list[Attempt]:
    """A scene at the limits table's edges campaigns 10-13 did not write (nesting 64 and 65 deep,
    integers of 309 and 310 digits, 40 problems in one file), YAML tags of sets and ordered maps,
    and sweep --set keys in unicode."""
    k = "inputs14"
    t = TINY
    deep = lambda n: "[" * n + "1" + "]" * n  # noqa: E731
    # fmt: off
    scenes: list[tuple[str, str]] = [
        ("a value nested 60 deep (under the 64 levels)", t + f"x: {deep(60)}\n"),
        ("a value nested 65 deep", t + f"x: {deep(65)}\n"),
        ("an integer of 309 digits", t.replace("[0.5, -1, 1]", "[0.5, -1, " + "1" * 309 + "]")),
        ("an integer of 310 digits", t.replace("[0.5, -1, 1]", "[0.5, -1, " + "1" * 310 + "]")),
        ("40 goals each of a bad type", t.replace("[[1, 1, 1], [0.5, -1, 1]]", "[" + ", ".join(["x"] * 40) + "]")),
        ("goals a !!set", t.replace("[[1, 1, 1], [0.5, -1, 1]]", "!!set {a: null}")),
        ("arm an !!omap", t.replace("arm: {links: [1, 1, 1]}", "arm: !!omap [{links: [1, 1, 1]}]")),
        ("a !!float tag on a string", t.replace("[0.5, -1, 1]", "[!!float 'x', -1, 1]")),
        ("a !!str tag on a goal's number", t.replace("[0.5, -1, 1]", "[!!str 0.5, -1, 1]")),
        ("an anchor defined twice", t.replace("[[1, 1, 1], [0.5, -1, 1]]", "[&a [1, 1, 1], &a [0.5, -1, 1], *a]")),
    ]
    # fmt: on
    out = [
        Attempt(
            k,
            f"validate, {label}",
            ["validate", "s.yaml"],
            tiny_scene(text=text),
            (0, 2),
            timeout=120,
            message_if_2=r"s\.yaml(:\d+)?: ",
        )
        for label, text in scenes
    ]
    for value in ("sölver.step=0.1", "solver.stép=0.1", "solver.step=0.1,\u00a00.2", "goals[０].hold=1"):
        out.append(
            Attempt(
                k,
                f"sweep --set {value}",
                ["sweep", "s.yaml", "--set", value, "--out", "o", "-q", "--jobs", "1"],
                tiny_scene(),
                (0, 2),
                timeout=300,
                message_if_2="--set",
            )
        )
    return out


def wrong14_attempts() -> list[Attempt]:
    """New draws of campaign 13's oracles: random arms with every kind of goal (rates, velocities,
    export, the clock, the summary), fk and ik against the campaign's kinematics."""
    import numpy as np

    k = "wrong14"
    out: list[Attempt] = []
    out += oracle_runs(k, range(700, 706), "held to every oracle")
    rng = np.random.default_rng(14)
    out += [random_fk_attempt(k, 200 + i, rng, 90, 4) for i in range(3)]
    out += random_ik_attempts(k, rng, 3, 200, 60.0)
    return out


# ------------------------------------------------------------------ the fifteenth campaign


def index_agrees(out: str = "o") -> Callable[[Path], list[str]]:
    """After a batch or a sweep into ``out``: OUT/index.csv says what each run folder's summary.json
    says (status ok, goals, reached, missed, frames, min_clearance, the folder), a row for every run
    folder and no other; a sweep's OUT/<scene>-sweep.csv too (reached, missed, frames, each goal's
    frames, min_clearance, max_joint_step_deg)."""

    def near(cell: str, value: float | None) -> bool:
        if value is None:
            return cell == ""
        return cell != "" and abs(float(cell) - value) <= 1e-5 * max(1.0, abs(value))

    def check(d: Path) -> list[str]:
        import csv as _csv
        import json as _json

        base = d / out
        if not (base / "index.csv").is_file():
            return [f"no {out}/index.csv"]
        runs = {n for n in _listing(base) if (base / n / "summary.json").is_file()}
        summaries = {n: _json.loads((base / n / "summary.json").read_text()) for n in runs}
        with open(base / "index.csv", newline="") as handle:
            rows = list(_csv.DictReader(handle))
        problems = []
        if {r["name"] for r in rows} != runs:
            problems.append(f"index.csv names {sorted(r['name'] for r in rows)}, the run folders are {sorted(runs)}")
        for r in rows:
            s = summaries.get(r["name"])
            if s is None:
                continue
            t = s["totals"]
            for key in ("goals", "reached", "missed", "frames"):
                if not near(r[key], t[key]):
                    problems.append(f"index.csv {r['name']}: {key} {r[key]}, its summary {t[key]}")
            if not near(r["min_clearance"], s["min_clearance"]):
                problems.append(
                    f"index.csv {r['name']}: min_clearance {r['min_clearance']!r}, its summary {s['min_clearance']}"
                )
            if r["status"] != "ok" or Path(r["folder"]).name != r["name"]:
                problems.append(f"index.csv {r['name']}: status {r['status']}, folder {r['folder']}")
        for table in base.glob("*-sweep.csv"):
            with open(table, newline="") as handle:
                for r in _csv.DictReader(handle):
                    s = summaries.get(r["name"])
                    if s is None:
                        problems.append(f"{table.name}: a row {r['name']} without its folder")
                        continue
                    want = {k: s["totals"][k] for k in ("reached", "missed", "frames")}
                    want |= {f"goal{g['index']}_frames": g["frames"] for g in s["goals"]}
                    want |= {"min_clearance": s["min_clearance"], "max_joint_step_deg": s["max_joint_step_deg"]}
                    for key, value in want.items():
                        if key in r and not near(r[key], value):
                            problems.append(f"{table.name} {r['name']}: {key} {r[key]!r}, its summary {value}")
        return problems

    return check


HEADLINE = re.compile(r"^(\S+): (\d+) of (\d+) goals reached, (\d+) frames", re.M)


def messages_agree(out: str = "o") -> Callable[[Path], list[str]]:
    """After ``run`` (not quiet) with its output in d/said.txt: each scene's headline ("NAME: R of
    G goals reached, N frames") and its table's rows (result, frames) say what its summary.json
    says; the table's frames add up to the total."""

    def check(d: Path) -> list[str]:
        import json as _json

        text = (d / "said.txt").read_text() if (d / "said.txt").is_file() else ""
        if "Traceback" in text or "Exception ignored" in text:
            return ["the run (kept in said.txt) ended in a traceback"]
        heads = HEADLINE.findall(text)
        if not heads:
            return ["no headline 'NAME: R of G goals reached, N frames'"]
        problems = []
        for name, reached, goals, frames in heads:
            s = _json.loads((d / out / name / "summary.json").read_text())
            t = s["totals"]
            if (int(reached), int(goals), int(frames)) != (t["reached"], t["goals"], t["frames"]):
                problems.append(f"{name}: said {reached} of {goals}, {frames} frames; summary {t}")
            rows = [
                [c.strip() for c in line.split("│")[1:-1]]
                for line in text.splitlines()
                if line.startswith("│") and line.split("│")[1].strip().isdigit()
            ]
            if len(heads) == 1 and rows:
                table = [(int(r[0]), r[2], int(r[3])) for r in rows]
                if sum(f for _, _, f in table) != t["frames"]:
                    problems.append(
                        f"{name}: the table's frames add up to {sum(f for _, _, f in table)}, not {t['frames']}"
                    )
                for index, result, count in table:
                    g = s["goals"][index]
                    if (result == "reached") != bool(g["reached"]) or count != g["last_frame"] - g["first_frame"] + 1:
                        problems.append(
                            f"{name} goal {index}: the table says {result}, {count} frames; summary {g['reached']}, {g['first_frame']}..{g['last_frame']}"
                        )
        return problems

    return check


def said_to_file(*args: str, env: dict | None = None) -> Callable[[Path], None]:
    """Setup step: armanim ``args`` with its stdout and stderr kept in d/said.txt."""

    def step(d: Path) -> None:
        done = subprocess.run(
            [sys.executable, "-m", "armanim", *args],
            cwd=d,
            env={**os.environ, "PYTHONPATH": str(SRC), "COLUMNS": "120", **(env or {})},
            capture_output=True,
            text=True,
            timeout=600,
        )
        write(d / "said.txt", done.stdout + done.stderr)

    return step


def same_bytes(*pairs: tuple[str, str], folder: tuple[str, str] = ("", "")) -> Callable[[Path], list[str]]:
    """After: each pair of files byte for byte alike (a run is deterministic), but for the runs'
    folder named in them (``folder``: the first's and the second's, as index.csv's column says)."""

    def check(d: Path) -> list[str]:
        problems = []
        for a, b in pairs:
            if not (d / a).is_file() or not (d / b).is_file():
                problems.append(f"{a} or {b} missing")
            elif (d / a).read_bytes().replace(folder[0].encode(), folder[1].encode()) != (d / b).read_bytes():
                problems.append(f"{a} and {b} differ")
        return problems

    return check


def mesh15_attempts() -> list[Attempt]:
    """Mesh files named in ways campaigns 9-14 did not write (spaces and accents in the name, a
    subfolder reached by ``..``, ``file://`` of an absolute path, a name shared by two links at two
    scales, a mesh changed in place with its size and time kept) and non-uniform and doubled scales,
    each fitted as the plain box written that way."""
    k = "mesh15"
    out: list[Attempt] = []

    def fit_case(label: str, tag: Callable[[Path], str], files: dict[str, bytes], ref: bytes, more=None) -> Attempt:
        def setup(d: Path) -> None:
            for name, content in files.items():
                write(d / name, content)
            write(d / "ref.stl", ref)
            write(d / "robot.urdf", urdf_links({2: f"<collision>{tag(d)}</collision>"}))
            write(d / "ref.urdf", urdf_links({2: col("ref.stl")}))
            if more is not None:
                more(d)

        return Attempt(
            k,
            f"robots --fit, {label}, fits as the reference",
            FIT,
            setup,
            (0,),
            timeout=200,
            after=same_fit("robot.urdf", "ref.urdf"),
        )

    box, box2 = box_stl(), box_stl(2.0)
    out.append(
        fit_case(
            "a mesh named 'my box é.stl' (a space, an accent)",
            lambda d: mesh_tag("my box é.stl"),
            {"my box é.stl": box},
            box,
        )
    )
    out.append(fit_case("a mesh named '𝄞.stl' (outside the BMP)", lambda d: mesh_tag("𝄞.stl"), {"𝄞.stl": box}, box))
    out.append(
        fit_case("a mesh named '-rf.stl' (a leading dash)", lambda d: mesh_tag("-rf.stl"), {"-rf.stl": box}, box)
    )
    out.append(
        fit_case(
            "a mesh in a sibling folder by ../",
            lambda d: mesh_tag("sub/../m/a.stl"),
            {"m/a.stl": box, "sub/x": b""},
            box,
        )
    )
    out.append(
        fit_case(
            "a mesh by file:// and its absolute path", lambda d: mesh_tag(f"file://{d}/a.stl"), {"a.stl": box}, box
        )
    )
    out.append(fit_case("a box at URDF scale 2 2 2", lambda d: mesh_tag("a.stl", "2 2 2"), {"a.stl": box}, box2))
    out.append(
        fit_case(
            "a box at a non-uniform scale 2 1 1",
            lambda d: mesh_tag("a.stl", "2 1 1"),
            {"a.stl": box},
            stl_corners_box((2.0, 1.0, 1.0)),
        )
    )
    out.append(
        fit_case(
            "a mesh name of 200 characters", lambda d: mesh_tag("b" * 196 + ".stl"), {"b" * 196 + ".stl": box}, box
        )
    )

    def changed_in_place(d: Path) -> None:
        # the fit is cached (ARMANIM_CACHE_DIR): fit the small box, then write the double box in its
        # place with the same size and times: the next fit must follow the bytes
        env = {"ARMANIM_CACHE_DIR": str(d / "cache")}
        fit_of(d, "robot.urdf", env)
        before = os.stat(d / "a.stl")
        write(d / "a.stl", box2)
        os.utime(d / "a.stl", ns=(before.st_atime_ns, before.st_mtime_ns))

    out.append(
        Attempt(
            k,
            "robots --fit after the mesh changed in place (same size and time): fits the new bytes",
            FIT,
            then(
                lambda d: write(d / "a.stl", box) and None,
                lambda d: write(d / "ref.stl", box2) and None,
                lambda d: write(d / "robot.urdf", urdf_links({2: col("a.stl")})) and None,
                lambda d: write(d / "ref.urdf", urdf_links({2: col("ref.stl")})) and None,
                changed_in_place,
            ),
            (0,),
            timeout=300,
            env={"ARMANIM_CACHE_DIR": "{d}/cache"},
            after=same_fit("robot.urdf", "ref.urdf", env={"ARMANIM_CACHE_DIR": "cache"}),
        )
    )

    def two_scales(d: Path) -> None:
        write(d / "a.stl", box)
        write(d / "ref.stl", box2)
        tag2 = f"<collision>{mesh_tag('a.stl', '2 2 2')}</collision>"
        write(d / "robot.urdf", urdf_links({1: col("a.stl"), 2: tag2}))
        write(d / "ref.urdf", urdf_links({1: col("a.stl"), 2: col("ref.stl")}))

    out.append(
        Attempt(
            k,
            "robots --fit, one file named by two links at scales 1 and 2 (read once): each link its own fit",
            FIT,
            two_scales,
            (0,),
            timeout=200,
            after=same_fit("robot.urdf", "ref.urdf"),
        )
    )
    out.append(
        Attempt(
            k,
            "run --viewer of a URDF whose visual mesh is named with a space and an accent",
            ["run", "s.yaml", "--out", "o", "--no-video", "--viewer", "-q"],
            urdf_robot(visual=vis("my é.stl"), files={"my é.stl": box}),
            (0,),
            timeout=300,
            not_message=r"(?i)not found|missing|capsules instead",
            after=exists("o/m/viewer.html"),
        )
    )
    return out


def stl_corners_box(scale: tuple[float, float, float]) -> bytes:
    """The box scaled by (sx, sy, sz) as a binary STL."""
    import numpy as np

    pts = [[c * s for c, s in zip(p, scale)] for p in box_points()]
    records = np.zeros(len(BOX_TRIANGLES), dtype=[("normal", "<f4", 3), ("v", "<f4", (3, 3)), ("attr", "<u2")])
    records["v"] = [[pts[i] for i in t] for t in BOX_TRIANGLES]
    return b"\0" * 80 + np.uint32(len(BOX_TRIANGLES)).tobytes() + records.tobytes()


BLENDS = (
    "version: 1\nname: tiny\narm: {links: [1, 1, 1]}\n"
    "goals: [{position: [1, 1, 1], blend: 0.2}, {position: [0.5, -1, 1], hold: HOLD}, {joints: [10, 20, 30], blend: 0.1},"
    " {position: [1.2, 0.3, 0.8], hold: HOLD}]\n"
    "render: {size: [160, 90], fps: FPS}\n"
)


def frames15_attempts() -> list[Attempt]:
    """The clock at rates campaigns 13-14 did not take (1, 2.5, 50, 120, 144, 47.952 fps), with
    blended goals between held ones; --fps with --quality together; a sweep of three rates at
    --jobs 2; render --fps of a finished run leaves its clock alone."""
    k = "frames15"
    out: list[Attempt] = []
    run = ["run", "s.yaml", "--out", "o", "--no-video", "-q"]
    for fps, hold in (("1", "2"), ("2.5", "0.4"), ("50", "0.03"), ("120", "0.125"), ("144", "0.01"), ("47.952", "0.5")):
        text = BLENDS.replace("HOLD", hold).replace("FPS", fps)
        out.append(
            clock_attempt(
                k, f"run with blends at render.fps {fps}, holds of {hold} s: the clock adds up", run, text, float(fps)
            )
        )
    text = HOLDS.replace("HOLD", "0.3").replace("FPS", "12")
    out.append(
        clock_attempt(
            k,
            "run --quality low --fps 25 (both): the clock adds up at 25",
            [*run, "--quality", "low", "--fps", "25"],
            text,
            25.0,
        )
    )
    out.append(
        Attempt(
            k,
            "sweep --jobs 2 --set render.fps=5,15,45: each variant's clock adds up",
            ["sweep", "s.yaml", "--set", "render.fps=5,15,45", "--out", "o", "-q", "--jobs", "2"],
            tiny_scene(text=HOLDS.replace("HOLD", "0.3").replace("FPS", "10")),
            (0,),
            timeout=500,
            after=both(variants_clock((5.0, 15.0, 45.0)), index_agrees()),
        )
    )

    def rendered(d: Path) -> None:
        finished_run(d, HOLDS.replace("HOLD", "0.2").replace("FPS", "10"))

    out.append(
        Attempt(
            k,
            "render --fps 24 --out fig of a 10 fps run: the run's clock unchanged",
            ["render", "o/tiny", "--fps", "24", "--out", "fig", "-q", "--size", "160x90", "--jobs", "1"],
            rendered,
            (0,),
            timeout=400,
            after=clock_breaks("o/tiny", 10.0),
        )
    )
    out.append(
        Attempt(
            k,
            "run a joint goal of a 0.001-degree move at 144 fps: the clock adds up",
            run,
            tiny_scene(
                text=TINY.replace(
                    "[[1, 1, 1], [0.5, -1, 1]]", "[{joints: [0, 0, 0]}, {joints: [0.001, 0, 0], hold: 0.1}]"
                ).replace("fps: 10", "fps: 144")
            ),
            (0,),
            timeout=300,
            after=clock_breaks("o/tiny", 144.0),
        )
    )
    return out


def signals15_attempts() -> list[Attempt]:
    """Signals at moments and in commands campaigns 10-14 did not: export --out and view --out
    replacing a file of their own, import moveit --out replacing its own, check --update replacing
    a golden, sweeps and renders of two workers with the signal to armanim alone (its workers end
    with it), SIGHUP during start-up, and a second signal during the tidying."""
    k = "signals15"
    out: list[Attempt] = []
    long_run = lambda d: finished_run(d, LONG) and None  # noqa: E731
    short = LONG.replace("hold: 3600", "hold: 40").replace("hold: 400", "hold: 40")
    video30 = TINY.replace("fps: 10", "fps: 30")

    def boxes(d: Path) -> None:
        box = "* b{i}\n1\nbox\n0.05 0.05 0.05\n{x} {y} 1\n0 0 0 1\n0 0 0 0\n"
        write(
            d / "w.scene",
            "w\n" + "".join(box.format(i=i, x=2 + i % 10, y=i // 10 * 0.1) for i in range(15_000)) + ".\n",
        )

    imp = ["import", "moveit", "w.scene", "--robot", "panda", "--out", "m.yaml"]
    update = ["check", "s.yaml", "--golden", "g", "--update"]
    # (label, args, setup, (delay, signal), whole, where)
    # fmt: off
    cases: list[tuple] = [
        ("export --out e.json replacing its own export of a 40,000-frame run", ["export", "o/tiny", "--out", "e.json"], then(long_run, lambda d: export_of(d, "e.json")), (0.8, "SIGINT"), ("e.json",), (".", "o")),
        ("export --out e.json replacing its own export, SIGHUP to armanim alone", ["export", "o/tiny", "--out", "e.json"], then(long_run, lambda d: export_of(d, "e.json")), (1.2, "SIGHUP"), ("e.json",), (".", "o")),
        ("view --out v.html replacing its own page of a 40,000-frame run", ["view", "o/tiny", "--out", "v.html"], then(long_run, lambda d: armanim_in(d, "view", "o/tiny", "--out", "v.html")), (1.0, "SIGTERM"), ("v.html",), (".", "o")),
        ("import moveit --out m.yaml (15,000 boxes) replacing its own", imp, then(boxes, lambda d: armanim_in(d, *imp)), (1.0, "SIGINT"), ("m.yaml",), (".",)),
        ("import moveit --out m.yaml (15,000 boxes) replacing its own", imp, then(boxes, lambda d: armanim_in(d, *imp)), (2.0, "SIGHUPG"), ("m.yaml",), (".",)),
        ("check --update replacing a 40,000-frame golden", update, then(tiny_scene(text=LONG), lambda d: armanim_in(d, *update)), (2.5, "SIGTERM"), ("g/tiny.csv", "g/tiny.json"), ("g",)),
        ("check --update replacing a 40,000-frame golden", update, then(tiny_scene(text=LONG), lambda d: armanim_in(d, *update)), (4.0, "SIGHUP"), ("g/tiny.csv", "g/tiny.json"), ("g",)),
        ("sweep --jobs 2 of 4 variants, to armanim alone", ["sweep", "s.yaml", "--set", "solver.step=0.1,0.15,0.2,0.25", "--out", "o", "-q", "--jobs", "2"], tiny_scene(text=short), (2.0, "SIGTERM"), (), ("o",)),
        ("sweep --jobs 2 of 4 variants, to armanim alone", ["sweep", "s.yaml", "--set", "solver.step=0.1,0.15,0.2,0.25", "--out", "o", "-q", "--jobs", "2"], tiny_scene(text=short), (3.0, "SIGHUP"), (), ("o",)),
        ("render --jobs 2 --out fig, to armanim alone", ["render", "o/tiny", "--out", "fig", "-q", "--size", "320x180", "--jobs", "2"], lambda d: finished_run(d, short) and None, (3.0, "SIGTERM"), ("fig",), ("o", "fig", ".")),
        ("render --jobs 2 into the run folder", ["render", "o/tiny", "-q", "--size", "320x180", "--jobs", "2"], lambda d: finished_run(d, short) and None, (2.0, "SIGINT"), ("o/tiny",), ("o",)),
        ("run with video during start-up", ["run", "s.yaml", "--out", "o", "-q", "--jobs", "1"], tiny_scene(text=video30), (0.4, "SIGHUPG"), ("o/tiny",), ("o",)),
        ("warm", ["warm"], lambda d: None, (2.0, "SIGHUPG"), (), (".",)),
    ]
    # fmt: on
    for label, args, setup, (delay, signame), whole, where in cases:
        out.append(
            Attempt(
                k,
                f"{label}, {signame} at {delay:g} s",
                args,
                setup,
                (0, 130),
                timeout=400,
                interrupt=(delay, signame),
                litter_in=where,
                linger=5.0,
                after=both(whole_or_none(*whole), again_tidy(*args, codes=(0,), where=where)),
            )
        )
    for first, second, gap in (("SIGINT", "SIGTERM", 0.3), ("SIGTERMG", "SIGINT", 0.15)):
        out.append(
            Attempt(
                k,
                f"a --jobs 2 batch with video, {first} at 2.5 s then {second} {gap:g} s later (during the tidying)",
                ["run", "a.yaml", "s.yaml", "--out", "o", "-q", "--jobs", "2"],
                then(tiny_scene(text=video30), tiny_scene("a.yaml", video30.replace("name: tiny", "name: a"))),
                (0, 130),
                timeout=400,
                interrupt=(2.5, first),
                also=((2.5 + gap, second),),
                linger=5.0,
                after=both(
                    whole_or_none("o/tiny", "o/a", "o/index.csv"),
                    again_tidy("run", "a.yaml", "s.yaml", "--out", "o", "-q", "--no-video", where=("o",)),
                ),
            )
        )
    return out


def loss15_attempts() -> list[Attempt]:
    """Links at output names campaigns 10-14 did not aim: render --out's files, a sweep's table, a
    batch's index.csv, import moveit's --out a hard link to the user's scene or a link to its own
    input, a golden a link to the user's file; and outputs onto inputs (a run folder, a sweep's
    variant folder, render --out holding the scene)."""
    k = "loss15"
    out: list[Attempt] = []
    moveit = mine("w.scene", "w\n* b\n1\nbox\n0.1 0.1 0.1\n1 1 1\n0 0 0 1\n0 0 0 0\n.\n")
    imp = ["import", "moveit", "w.scene", "--robot", "panda", "--out"]
    sweep = ["sweep", "s.yaml", "--set", "solver.step=0.1,0.2", "--out", "o", "-q", "--jobs", "1"]
    batch = ["run", "s.yaml", "a.yaml", "--out", "o", "--no-video", "-q", "--jobs", "1"]
    two = then(tiny_scene(), tiny_scene("a.yaml", TINY.replace("name: tiny", "name: a")))
    render = ["render", "o/tiny", "--out", "fig", "-q", "--size", "160x90", "--jobs", "1"]
    # (label, args, setup, keep, codes)
    # fmt: off
    cases: list[tuple] = [
        ("render --out fig, fig/tiny.mp4 a link to the user's file", render, then(finished_run, mine(), symlink("../mine.txt", "fig/tiny.mp4")), ("mine.txt",), (0, 2, 3)),
        ("render --out fig, fig/plot.png a hard link to the user's file", render, then(finished_run, mine(), lambda d: (d / "fig").mkdir() or None, hardlink("mine.txt", "fig/plot.png")), ("mine.txt",), (0, 2, 3)),
        ("render --out fig again, fig/poster.png since a hard link of the user's", render, then(finished_run, lambda d: armanim_in(d, *render), hardlink("fig/poster.png", "keep.png")), ("keep.png",), (0, 2, 3)),
        ("sweep, o/s-sweep.csv a link to the user's file", sweep, then(tiny_scene(), mine(), symlink("../mine.txt", "o/s-sweep.csv")), ("mine.txt",), (0, 2, 3)),
        ("sweep again, o/s-sweep.csv hard-linked by the user as keep.csv", sweep, then(tiny_scene(), lambda d: armanim_in(d, *sweep), hardlink("o/s-sweep.csv", "keep.csv")), ("keep.csv",), (0, 2, 3)),
        ("a batch, o/index.csv a link to the user's file", batch, then(two, mine(), symlink("../mine.txt", "o/index.csv")), ("mine.txt",), (0, 2, 3)),
        ("a batch again, o/index.csv hard-linked by the user as keep.csv", batch, then(two, lambda d: armanim_in(d, *batch), hardlink("o/index.csv", "keep.csv")), ("keep.csv",), (0, 2, 3)),
        ("import moveit --out m.yaml, a hard link to the user's scene s.yaml", [*imp, "m.yaml"], then(moveit, tiny_scene(), hardlink("s.yaml", "m.yaml")), ("s.yaml", "w.scene"), (0, 2, 3)),
        ("import moveit --out l.scene, a link to its own input w.scene", [*imp, "l.scene"], then(moveit, symlink("w.scene", "l.scene")), ("w.scene",), (2, 3)),
        ("import moveit again, m.yaml (its own) hard-linked by the user as keep.yaml", [*imp, "m.yaml"], then(moveit, lambda d: armanim_in(d, *imp, "m.yaml"), hardlink("m.yaml", "keep.yaml")), ("keep.yaml",), (0, 2, 3)),
        ("check --update, g/tiny.json a link to the user's notes", ["check", "s.yaml", "--golden", "g", "--update"], then(tiny_scene(), mine("mine.json", '{"notes": 1}\n'), symlink("../mine.json", "g/tiny.json")), ("mine.json",), (0, 2, 3)),
        ("export --out e.json, a dangling link into the user's folder", ["export", "o/tiny", "--out", "e.json"], then(finished_run, lambda d: (d / "notes").mkdir() or None, mine("notes/n.txt"), symlink("notes/new.json", "e.json")), ("notes/n.txt",), (0, 2, 3)),
        ("run o/tiny/s.yaml --out o (the scene inside the run folder it replaces)", ["run", "o/tiny/s.yaml", "--out", "o", "--no-video", "-q"], then(finished_run, lambda d: shutil.copy(d / "s.yaml", d / "o/tiny/s.yaml")), ("o/tiny/s.yaml",), (2, 3)),
        ("sweep of o/tiny_step-0.1/s.yaml --out o (the scene inside a variant's folder)", ["sweep", "o/tiny_step-0.1/s.yaml", "--set", "solver.step=0.1,0.2", "--out", "o", "-q", "--jobs", "1"], tiny_scene("o/tiny_step-0.1/s.yaml"), ("o/tiny_step-0.1/s.yaml",), (2, 3)),
        ("view --out l.html, a link to the user's scene s.yaml", ["view", "o/tiny", "--out", "l.html"], then(finished_run, symlink("s.yaml", "l.html")), ("s.yaml",), (0, 2, 3)),
        ("run --out o, o a link to the folder holding the scene", ["run", "s.yaml", "--out", "o", "--no-video", "-q"], then(tiny_scene(), mine(), lambda d: os.symlink(".", d / "o")), ("mine.txt", "s.yaml"), (0, 2, 3)),
    ]
    # fmt: on
    for label, args, setup, keep, codes in cases:
        out.append(Attempt(k, label, args, setup, codes, keep=keep, timeout=400, litter_in=("o", ".", "fig", "g")))
    return out


def inputs15_attempts() -> list[Attempt]:
    """The environment (NUMBA_*, HOME unset, TERM=dumb, NO_COLOR, LANG/LC_ALL=C, COLUMNS huge or
    negative, ARMANIM_SCHEDULER bogus) and odd paths (a scene whose path has spaces and astral
    characters, a leading dash, a path of 3,000 characters, a sweep's variant names past 255 bytes)."""
    k = "inputs15"
    out: list[Attempt] = []
    run = ["run", "s.yaml", "--out", "o", "--no-video", "-q"]
    # fmt: off
    envs: list[tuple[str, dict, list[str], tuple]] = [
        ("NUMBA_DISABLE_JIT=1", {"NUMBA_DISABLE_JIT": "1"}, run, (0,)),
        ("NUMBA_CACHE_DIR=/dev/null", {"NUMBA_CACHE_DIR": "/dev/null"}, run, (0,)),
        ("NUMBA_NUM_THREADS=abc", {"NUMBA_NUM_THREADS": "abc"}, run, (0, 2)),
        ("NUMBA_THREADING_LAYER=tbb (not installed)", {"NUMBA_THREADING_LAYER": "tbb"}, run, (0, 2)),
        ("HOME unset", {"HOME": UNSET}, [*run[:3], "o", "-q", "--jobs", "1"], (0,)),
        ("HOME a file", {"HOME": "/etc/hostname"}, [*run[:3], "o", "-q", "--jobs", "1"], (0,)),
        ("MPLCONFIGDIR=/dev/null", {"MPLCONFIGDIR": "/dev/null"}, [*run[:3], "o", "-q", "--jobs", "1"], (0,)),
        ("TERM=dumb NO_COLOR=1, not quiet", {"TERM": "dumb", "NO_COLOR": "1"}, ["run", "s.yaml", "--out", "o", "--no-video"], (0,)),
        ("LANG=C LC_ALL=C, a scene path 'é 𝄞/s.yaml'", {"LANG": "C", "LC_ALL": "C"}, ["run", "é 𝄞/s.yaml", "--out", "o", "--no-video"], (0,)),
        ("COLUMNS=100000", {"COLUMNS": "100000"}, ["run", "s.yaml", "--out", "o", "--no-video"], (0,)),
        ("COLUMNS=-5", {"COLUMNS": "-5"}, ["run", "s.yaml", "--out", "o", "--no-video"], (0,)),
        ("ARMANIM_SCHEDULER=bogus", {"ARMANIM_SCHEDULER": "bogus"}, run, (0, 2)),
    ]
    # fmt: on
    for label, env, args, codes in envs:

        def setup(d: Path, args=args) -> None:
            write(d / "s.yaml", TINY)
            if "é 𝄞/s.yaml" in args:
                write(d / "é 𝄞" / "s.yaml", TINY)

        out.append(
            Attempt(
                k,
                f"run under {label}",
                args,
                setup,
                codes,
                timeout=600 if "JIT" in label else 400,
                env=env,
                message=r"tiny: 2 of 2 goals reached" if "--no-video" in args and "-q" not in args else None,
                after=(lambda d: [] if (d / "o" / "tiny" / "summary.json").is_file() else ["no o/tiny/summary.json"])
                if codes == (0,)
                else None,
            )
        )
    out.append(
        Attempt(
            k,
            "validate ./-s.yaml and -- -s.yaml (a leading dash)",
            ["validate", "--", "-s.yaml"],
            tiny_scene("-s.yaml"),
            (0,),
            message=r"ok",
        )
    )
    deep = "/".join(["d" * 200] * 15)

    def deep_scene(d: Path) -> None:
        write(d / deep / "s.yaml", TINY)

    out.append(
        Attempt(
            k,
            "run a scene under a path of 3,000 characters, --out beside it",
            ["run", f"{deep}/s.yaml", "--out", f"{deep}/o", "--no-video", "-q"],
            deep_scene,
            (0, 2, 3),
            timeout=300,
            litter_in=(deep,),
        )
    )
    name = "n" * 100
    out.append(
        Attempt(
            k,
            "sweep of a 100-character scene name over four keys (variant names past 255 bytes unless cut)",
            [
                "sweep",
                "s.yaml",
                "--set",
                "solver.step=0.123456789,0.2",
                "--set",
                "solver.damping=0.0123456789",
                "--set",
                "solver.tolerance=0.00123456789",
                "--set",
                "render.fps=12.3456789",
                "--out",
                "o",
                "-q",
                "--jobs",
                "1",
            ],
            tiny_scene(text=TINY.replace("name: tiny", f"name: {name}")),
            (0, 2, 3),
            timeout=400,
            message_if_2="--set|name",
            message_if_3="name|long",
        )
    )
    out.append(
        Attempt(
            k,
            "export --out a name of 255 bytes in accents (its mark's name past 255)",
            ["export", "o/tiny", "--out", "é" * 122 + ".json"],
            lambda d: finished_run(d) and None,
            (0, 2, 3),
            litter_in=(".",),
        )
    )
    return out


def wrong15_attempts() -> list[Attempt]:
    """New draws of the random-arm oracle; a batch's index.csv and a sweep's table against each
    run's summary; the run's headline and table against its summary; a batch at --jobs 2 under
    another PYTHONHASHSEED byte for byte the batch at --jobs 1."""
    k = "wrong15"
    out: list[Attempt] = []
    out += oracle_runs(k, range(800, 804), "held to every oracle")
    scenes = [wrong_scene(seed, WRONG13_KINDS) for seed in (810, 811, 812)]

    def batch_setup(d: Path) -> None:
        for i, (text, _) in enumerate(scenes):
            write(d / f"s{i}.yaml", text)

    names = [f"s{i}.yaml" for i in range(len(scenes))]
    out.append(
        Attempt(
            k,
            "a --jobs 2 batch of three random arms: index.csv agrees with each summary",
            ["run", *names, "--out", "o", "--no-video", "-q", "--jobs", "2"],
            batch_setup,
            (0, 2),
            timeout=600,
            after=index_agrees(),
        )
    )
    out.append(
        Attempt(
            k,
            "a --jobs 2 batch under PYTHONHASHSEED=7, byte for byte the --jobs 1 batch under PYTHONHASHSEED=0",
            ["run", *names, "--out", "o", "--no-video", "-q", "--jobs", "2"],
            then(
                batch_setup,
                lambda d: armanim_in(
                    d, "run", *names, "--out", "p", "--no-video", "-q", "--jobs", "1", env={"PYTHONHASHSEED": "0"}
                ),
            ),
            (0, 2),
            timeout=900,
            env={"PYTHONHASHSEED": "7"},
            after=lambda d: (
                same_bytes(
                    *[
                        (f"o/{n}/trajectory.csv", f"p/{n}/trajectory.csv")
                        for n in _listing(d / "p")
                        if (d / "p" / n).is_dir()
                    ],
                    ("o/index.csv", "p/index.csv"),
                    folder=(",o/", ",p/"),
                )(d)
                if (d / "p").is_dir()
                else ["no p"]
            ),
        )
    )
    out.append(
        Attempt(
            k,
            "sweep of a random arm over solver.method and planner: its table and index.csv agree with each summary",
            [
                "sweep",
                "s.yaml",
                "--set",
                "solver.method=pinv,dls",
                "--set",
                "solver.step=0.1,0.3",
                "--out",
                "o",
                "-q",
                "--jobs",
                "2",
            ],
            tiny_scene(text=scenes[0][0]),
            (0, 2),
            timeout=900,
            after=index_agrees(),
        )
    )
    for seed in (813, 814):
        text, spec = wrong_scene(seed, WRONG13_KINDS)
        out.append(
            Attempt(
                k,
                f"run a random arm (seed {seed}), not quiet: its headline and table agree with its summary",
                ["validate", "s.yaml"],
                then(tiny_scene(text=text), said_to_file("run", "s.yaml", "--out", "o", "--no-video")),
                (0, 2),
                timeout=600,
                after=lambda d, spec=spec: messages_agree()(d) if (d / "o" / spec["name"]).is_dir() else [],
            )
        )
    return out


# ------------------------------------------------------------------ the sixteenth campaign


def locked_up(*paths: str, mode: int = 0o555) -> Callable[[Path], None]:
    """Setup: ``paths`` (relative to the folder; folders made if missing) given ``mode``."""

    def setup(d: Path) -> None:
        for path in paths:
            target = d / path
            if not target.exists():
                target.mkdir(parents=True)
            target.chmod(mode)

    return setup


def listing_of(where: str, *allowed: str) -> Callable[[Path], list[str]]:
    """Check: ``where`` holds only ``allowed`` (nothing half-made there, no file left beside)."""

    def check(d: Path) -> list[str]:
        folder = d / where
        found = sorted(p.name for p in folder.iterdir()) if folder.is_dir() else []
        extra = [name for name in found if name not in allowed]
        return [f"{where} now holds {extra}"] if extra else []

    return check


ROBOT_ONE_MESH = (
    '<?xml version="1.0"?>\n<robot name="r"><link name="l0"/><link name="l1">'
    '<collision><geometry><mesh filename="MESH"/></geometry></collision></link><link name="l2"/>'
    '<joint name="j0" type="revolute"><parent link="l0"/><child link="l1"/><origin xyz="0 0 0.1"/>'
    '<axis xyz="0 0 1"/><limit lower="-2" upper="2" effort="1" velocity="1"/></joint>'
    '<joint name="j1" type="revolute"><parent link="l1"/><child link="l2"/><origin xyz="0 0 0.3"/>'
    '<axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="1" velocity="1"/></joint></robot>\n'
)
MESH_SCENE = (
    "version: 1\nname: m\narm: {urdf: robot.urdf}\ngoals: [[0.1, 0.1, 0.3]]\nrender: {size: [160, 90], fps: 10}\n"
)


def one_mesh_robot(mesh: str = "m.stl", visual: bool = False) -> Callable[[Path], None]:
    """Setup: robot.urdf whose link l1's collision (or visual) is the box ``mesh``, and s.yaml naming it."""

    def setup(d: Path) -> None:
        text = ROBOT_ONE_MESH.replace("MESH", mesh)
        if visual:
            text = text.replace("<collision>", "<visual>").replace("</collision>", "</visual>")
        write(d / "robot.urdf", text)
        write(d / "s.yaml", MESH_SCENE)
        write(d / mesh.replace("package://pk/", "pk/"), box_stl())

    return setup


def compiled_again(d: Path) -> list[str]:
    """Check of a run with nowhere to keep numba's code: run it again as the user; if that run
    compiles again, the first must not have said it compiles "once after installing"."""
    assert AS_USER is not None
    env = {**os.environ, "PYTHONPATH": str(SRC), "COLUMNS": "120", "HOME": "/nonexistent"}
    done = subprocess.run(
        [USER_PYTHON, "-m", "armanim", "run", "s.yaml", "--out", "p", "--no-video"],
        cwd=d,
        env=env,
        capture_output=True,
        text=True,
        timeout=900,
        preexec_fn=_limits(4_000_000_000, AS_USER),
    )
    first = (d / "first.txt").read_text() if (d / "first.txt").exists() else ""
    problems = []
    if "numba compiled its code for" in done.stdout + done.stderr and "once after installing" in first:
        problems.append("the first run said numba compiles 'once after installing', and the second compiled again")
    return problems


def perms16_attempts() -> list[Attempt]:
    """Read-only and unreadable files and folders, as a user who is not root (root writes through
    every mode, so campaigns 1-15 never met them): outputs into read-only folders, write-protected
    run folders, unreadable inputs, caches and homes that cannot be written, another user's lock."""
    k = "perms16"
    out: list[Attempt] = []
    run = ["run", "s.yaml", "--out", "o", "--no-video", "-q"]
    denied = r"permission denied|read-only|write-protected"
    protected = "o/tiny"

    def protected_run(d: Path) -> None:
        finished_run(d)
        (d / protected).chmod(0o555)

    # fmt: off
    outputs: list[tuple[str, list[str], Callable[[Path], None], tuple[str, ...], str | None]] = [
        ("run --out a read-only folder", ["run", "s.yaml", "--out", "ro", "--no-video", "-q"], then(tiny_scene(), locked_up("ro")), ("ro",), None),
        ("run --out a folder under a read-only folder", ["run", "s.yaml", "--out", "ro/sub", "--no-video", "-q"], then(tiny_scene(), locked_up("ro")), ("ro",), None),
        ("run into a write-protected run folder (chmod 555 o/tiny)", run, protected_run, ("o/tiny",), None),
        ("run --viewer into a write-protected run folder", [*run[:-1], "--viewer", "-q"], protected_run, ("o/tiny",), None),
        ("render into a write-protected run folder", ["render", "o/tiny", "--size", "64x36"], protected_run, ("o/tiny",), None),
        ("export into a write-protected run folder (its default --out)", ["export", "o/tiny"], protected_run, ("o/tiny",), None),
        ("view into a write-protected run folder (its default --out)", ["view", "o/tiny"], protected_run, ("o/tiny",), None),
        ("run again, o read-only and o/tiny writable", run, then(finished_run, locked_up("o")), ("o",), None),
        ("export --out a read-only folder", ["export", "o/tiny", "--out", "ro/e.json"], then(finished_run, locked_up("ro")), ("ro", "o/tiny"), None),
        ("view --out a read-only folder", ["view", "o/tiny", "--out", "ro/v.html"], then(finished_run, locked_up("ro")), ("ro", "o/tiny"), None),
        ("render --out a read-only folder", ["render", "o/tiny", "--out", "ro/r", "--size", "64x36"], then(finished_run, locked_up("ro")), ("ro", "o/tiny"), None),
        ("schema --out a read-only folder", ["schema", "--out", "ro/s.json"], locked_up("ro"), ("ro",), None),
        ("fk --png into a read-only folder (the advice names --png, not --out)", ["fk", "--links", "1,1,1", "--angles", "0,10,20", "--png", "ro/p.png"], locked_up("ro"), ("ro",), r"--out"),
        ("check --update, the golden folder read-only (the advice names --golden, not --out)", ["check", "s.yaml", "a.yaml", "--golden", "g", "--update", "-q"], then(tiny_scene(), tiny_scene("a.yaml", OTHER), lambda d: armanim_in(d, "check", "s.yaml", "a.yaml", "--golden", "g", "--update", "-q"), edit("a.yaml", b"solver: {step: 0.2}\n"), locked_up("g")), ("g",), r"--out"),
        ("check --update, a new golden folder under a read-only folder", ["check", "s.yaml", "--golden", "ro/g", "--update", "-q"], then(tiny_scene(), locked_up("ro")), ("ro",), r"--out"),
        ("sweep --out a read-only folder", ["sweep", "s.yaml", "--set", "solver.step=0.1,0.2", "--out", "ro", "-q", "--jobs", "1"], then(tiny_scene(), locked_up("ro")), ("ro",), None),
        ("a batch of two --out a read-only folder", ["run", "s.yaml", "a.yaml", "--out", "ro", "--no-video", "-q", "--jobs", "1"], then(tiny_scene(), tiny_scene("a.yaml", OTHER), locked_up("ro")), ("ro",), None),
        ("a --jobs 2 batch whose root is read-only, one run folder in it written before", ["run", "s.yaml", "a.yaml", "--out", "o", "--no-video", "-q", "--jobs", "2"], then(tiny_scene("a.yaml", OTHER), finished_run, locked_up("o")), ("o",), None),
        ("import moveit --out a read-only folder", ["import", "moveit", "w.scene", "--robot", "panda", "--out", "ro/m.yaml"], then(mine("w.scene", "w\n* b\n1\nbox\n0.1 0.1 0.1\n1 1 1\n0 0 0 1\n0 0 0 0\n.\n"), locked_up("ro")), ("ro", "w.scene"), None),
    ]
    # fmt: on
    for label, args, setup, keep, not_message in outputs:
        out.append(
            Attempt(
                k,
                label,
                args,
                setup,
                (3,),
                message=denied,
                keep=keep,
                timeout=400,
                user=True,
                not_message=not_message,
                litter_in=("o", "ro", "g"),
            )
        )
    # unreadable inputs: exit 2 naming the file
    unreadable: list[tuple[str, list[str], Callable[[Path], None], str, tuple[int, ...]]] = [
        (
            "validate an unreadable scene (chmod 000)",
            ["validate", "s.yaml"],
            then(tiny_scene(), locked_up("s.yaml", mode=0)),
            r"s\.yaml",
            (2,),
        ),
        ("run an unreadable URDF", run, then(one_mesh_robot(), locked_up("robot.urdf", mode=0)), r"robot\.urdf", (2,)),
        (
            "validate an unreadable collision mesh",
            ["validate", "s.yaml"],
            then(one_mesh_robot(), locked_up("m.stl", mode=0)),
            r"m\.stl",
            (2,),
        ),
        (
            "robots --fit of an unreadable collision mesh",
            ["robots", "--fit", "robot.urdf"],
            then(one_mesh_robot(), locked_up("m.stl", mode=0)),
            r"m\.stl",
            (2,),
        ),
        (
            "robots --fit of a mesh in a folder that cannot be entered (chmod 600)",
            ["robots", "--fit", "robot.urdf"],
            then(one_mesh_robot("sub/m.stl"), locked_up("sub", mode=0o600)),
            r"m\.stl",
            (2,),
        ),
        (
            "validate, package:// mesh in a package folder that cannot be listed (chmod 311)",
            ["validate", "s.yaml"],
            then(
                one_mesh_robot("package://pk/m.stl"),
                lambda d: write(
                    d / "s.yaml", MESH_SCENE.replace("urdf: robot.urdf", "urdf: robot.urdf, package_dirs: [.]")
                ),
                locked_up("pk", mode=0o311),
            ),
            r"ok",
            (0,),
        ),
        (
            "run --viewer of an unreadable visual mesh (a note, drawn as capsules)",
            [*run[:-1], "--viewer", "-q"],
            then(one_mesh_robot(visual=True), locked_up("m.stl", mode=0)),
            r"m\.stl.*(permission|read)",
            (0,),
        ),
        (
            "render of a run whose trajectory.csv is unreadable",
            ["render", "o/tiny", "--out", "r", "--size", "64x36"],
            then(finished_run, locked_up("o/tiny/trajectory.csv", mode=0)),
            r"trajectory\.csv",
            (2,),
        ),
        (
            "export of a run whose summary.json is unreadable",
            ["export", "o/tiny", "--out", "e.json"],
            then(finished_run, locked_up("o/tiny/summary.json", mode=0)),
            r"summary\.json",
            (2,),
        ),
        (
            "view of a run whose marker is unreadable",
            ["view", "o/tiny", "--out", "v.html"],
            then(finished_run, locked_up("o/tiny/.armanim-run.json", mode=0)),
            r".",
            (0, 2),
        ),
        (
            "run again into a run folder whose marker is unreadable",
            run,
            then(finished_run, locked_up("o/tiny/.armanim-run.json", mode=0)),
            r"armanim-run\.json",
            (3,),
        ),
        (
            "compare of an unreadable CSV",
            ["compare", "o/tiny/trajectory.csv", "c.csv"],
            then(
                finished_run,
                lambda d: shutil.copy(d / "o/tiny/trajectory.csv", d / "c.csv"),
                locked_up("c.csv", mode=0),
            ),
            r"c\.csv",
            (2,),
        ),
        (
            "check against an unreadable golden",
            ["check", "s.yaml", "--golden", "g", "-q"],
            then(
                tiny_scene(),
                lambda d: armanim_in(d, "check", "s.yaml", "--golden", "g", "--update", "-q"),
                locked_up("g/tiny.csv", mode=0),
            ),
            r"tiny\.csv",
            (1, 2),
        ),
        (
            "run a scene in a folder that cannot be listed (chmod 311)",
            ["run", "sc/s.yaml", "--out", "o", "--no-video", "-q"],
            then(tiny_scene("sc/s.yaml"), locked_up("sc", mode=0o311)),
            r"",
            (0,),
        ),
    ]
    for label, args, setup, message, codes in unreadable:
        out.append(
            Attempt(
                k,
                label,
                args,
                setup,
                codes,
                message=message,
                timeout=400,
                user=True,
                keep=("s.yaml",) if "s.yaml" in args else (),
            )
        )
    # caches, homes and locks
    fit = ["robots", "--fit", "robot.urdf"]
    out += [
        Attempt(
            k,
            "robots --fit, ARMANIM_CACHE_DIR read-only (the fit not kept, the answer given)",
            fit,
            then(one_mesh_robot(), locked_up("cache")),
            (0,),
            message=r"link: \"l1\"",
            env={"ARMANIM_CACHE_DIR": "{d}/cache"},
            keep=("cache",),
            user=True,
        ),
        Attempt(
            k,
            "run, ARMANIM_CACHE_DIR under a read-only folder",
            run,
            then(one_mesh_robot(), locked_up("ro")),
            (0,),
            env={"ARMANIM_CACHE_DIR": "{d}/ro/cache"},
            keep=("ro",),
            user=True,
        ),
        Attempt(
            k,
            "run, the capsule cache's entries unreadable (chmod 000)",
            run,
            then(
                one_mesh_robot(),
                lambda d: armanim_in(d, *fit, env={"ARMANIM_CACHE_DIR": str(d / "cache")}),
                lambda d: [p.chmod(0) for p in (d / "cache").rglob("*") if p.is_file()] and None,
            ),
            (0,),
            env={"ARMANIM_CACHE_DIR": "{d}/cache"},
            user=True,
        ),
        Attempt(
            k,
            "run with video, HOME read-only (matplotlib's and numba's user caches)",
            ["run", "s.yaml", "--out", "o", "-q"],
            then(tiny_scene(), locked_up("home")),
            (0,),
            env={"HOME": "{d}/home", "XDG_CACHE_HOME": UNSET, "MPLCONFIGDIR": UNSET},
            timeout=900,
            user=True,
        ),
        Attempt(
            k,
            "run with video, TMPDIR read-only",
            ["run", "s.yaml", "--out", "o", "-q"],
            then(tiny_scene(), locked_up("tmp")),
            (0,),
            env={"TMPDIR": "{d}/tmp"},
            timeout=600,
            user=True,
            keep=("tmp",),
        ),
        Attempt(
            k,
            "run twice with nowhere to keep numba's code (HOME missing, the install read-only): no false 'once after installing'",
            ["validate", "s.yaml"],
            then(tiny_scene(), said_as_user_to_file("first.txt", "run", "s.yaml", "--out", "o", "--no-video")),
            (0,),
            env={"HOME": "/nonexistent", "XDG_CACHE_HOME": UNSET, "NUMBA_CACHE_DIR": UNSET},
            timeout=900,
            user=True,
            after=compiled_again,
        ),
        Attempt(
            k,
            "run, o/.tiny.lock another user's (root's, 0644): the lock read-only",
            run,
            then(finished_run, mine("o/.tiny.lock", "")),
            (0, 3),
            message_if_3=r"\.tiny\.lock",
            root_owned=("o/.tiny.lock",),
            keep=("o/.tiny.lock",),
            user=True,
        ),
        Attempt(
            k,
            "run, o/.tiny.lock the user's own at chmod 000",
            run,
            then(finished_run, locked_up("o/.tiny.lock", mode=0)),
            (0, 3),
            message_if_3=r"\.tiny\.lock",
            user=True,
        ),
        Attempt(
            k,
            "run into a shared sticky folder where o/tiny is another user's run",
            ["run", "s.yaml", "--out", "sh", "--no-video", "-q"],
            then(
                tiny_scene(),
                lambda d: armanim_in(d, "run", "s.yaml", "--out", "sh", "--no-video", "-q"),
                lambda d: (d / "sh").chmod(0o1777),
            ),
            (3,),
            message=r"sh/tiny",
            root_owned=(
                "sh",
                "sh/tiny",
                "sh/tiny/trajectory.csv",
                "sh/tiny/summary.json",
                "sh/tiny/scene.yaml",
                "sh/tiny/timing.json",
                "sh/tiny/self-collision.yaml",
                "sh/tiny/.armanim-run.json",
                "sh/.tiny.lock",
            ),
            keep=("sh",),
            litter_in=("sh",),
            user=True,
        ),
    ]
    return out


def said_as_user_to_file(name: str, *args: str) -> Callable[[Path], None]:
    """Setup: run armanim as the campaign's user with nowhere to keep numba's code (HOME missing),
    its stdout and stderr into ``name``."""

    def setup(d: Path) -> None:
        assert AS_USER is not None
        os.chown(d, AS_USER[0], AS_USER[1])
        env = {**os.environ, "PYTHONPATH": str(SRC), "COLUMNS": "120", "HOME": "/nonexistent"}
        env.pop("XDG_CACHE_HOME", None)
        env.pop("NUMBA_CACHE_DIR", None)
        for child in d.iterdir():
            os.chown(child, AS_USER[0], AS_USER[1])
        done = subprocess.run(
            [USER_PYTHON, "-m", "armanim", *args],
            cwd=d,
            env=env,
            capture_output=True,
            text=True,
            timeout=900,
            preexec_fn=_limits(4_000_000_000, AS_USER),
        )
        write(d / name, done.stdout + done.stderr)

    return setup


def small_disk(at: str, kilobytes: int, filler: int = 0) -> Callable[[Path], None]:
    """Setup: a tmpfs of ``kilobytes`` mounted at ``at`` (a full disk), ``filler`` bytes of it taken
    by the user's file ``at/filler`` (unmounted by the campaign after the attempt)."""

    def setup(d: Path) -> None:
        (d / at).mkdir(parents=True, exist_ok=True)
        subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={kilobytes}k", "tmpfs", str(d / at)], check=True)
        if filler:
            write(d / at / "filler", b"\0" * filler)

    return setup


def pair_whole(folder: str, name: str = "tiny") -> Callable[[Path], list[str]]:
    """Check: a golden CSV is never left without its JSON, nor a JSON without its CSV."""

    def check(d: Path) -> list[str]:
        csv_there, json_there = (d / folder / f"{name}.csv").exists(), (d / folder / f"{name}.json").exists()
        return (
            []
            if csv_there == json_there
            else [f"{folder}: the golden pair is half there ({csv_there=}, {json_there=})"]
        )

    return check


def index_folder_is(out: str, *folders: str) -> Callable[[Path], list[str]]:
    """Check: index.csv's rows name ``folders`` exactly (read with the csv module)."""

    def check(d: Path) -> list[str]:
        import csv

        path = d / out / "index.csv"
        if not path.exists():
            return [f"no {out}/index.csv"]
        rows = list(csv.DictReader(path.open(newline="")))
        found = sorted(row.get("folder") or "" for row in rows)
        return [] if found == sorted(folders) else [f"index.csv's folders {found!r}, expected {sorted(folders)!r}"]

    return check


def env16_attempts() -> list[Attempt]:
    """A full disk under every writer (a small tmpfs: runs, a run replacing its own folder, render,
    view, export, import, schema, check --update, a sweep and a batch, numba's and the capsules'
    caches, TMPDIR), a file-size limit (RLIMIT_FSIZE), paths past PATH_MAX, newlines in an
    outputs folder's name."""
    k = "env16"
    out: list[Attempt] = []
    full = r"(?i)disk is full|no space|too large"
    moveit = mine("w.scene", "w\n* b\n1\nbox\n0.1 0.1 0.1\n1 1 1\n0 0 0 1\n0 0 0 0\n.\n")
    # fmt: off
    disks: list[tuple[str, list[str], Callable[[Path], None], tuple[str, ...], tuple[int, ...], Callable[[Path], list[str]] | None]] = [
        ("run with video and page into a 200 KB disk", ["run", "s.yaml", "--out", "disk", "-q"], then(tiny_scene(), small_disk("disk", 200)), (), (3,), listing_of("disk", ".tiny.lock")),
        ("run --no-video into a 16 KB disk", ["run", "s.yaml", "--out", "disk", "--no-video", "-q"], then(tiny_scene(), small_disk("disk", 16)), (), (3,), listing_of("disk", ".tiny.lock")),
        ("run again, the disk with room for the old run folder only", ["run", "s.yaml", "--out", "disk", "--no-video", "-q"], then(tiny_scene(), small_disk("disk", 40), lambda d: armanim_in(d, "run", "s.yaml", "--out", "disk", "--no-video", "-q"), edit("s.yaml", b"solver: {step: 0.2}\n")), ("disk/tiny",), (3,), listing_of("disk", ".tiny.lock", "tiny")),
        ("render --out into a full disk", ["render", "o/tiny", "--out", "disk/r", "--size", "64x36"], then(finished_run, small_disk("disk", 8, 4096)), ("o/tiny", "disk/filler"), (3,), listing_of("disk", "filler", ".r.lock")),
        ("view --out into a full disk", ["view", "o/tiny", "--out", "disk/v.html"], then(finished_run, small_disk("disk", 8, 4096)), ("o/tiny", "disk/filler"), (3,), listing_of("disk", "filler")),
        ("export --out into a full disk", ["export", "o/tiny", "--out", "disk/e.json"], then(finished_run, small_disk("disk", 4, 4096)), ("o/tiny", "disk/filler"), (3,), listing_of("disk", "filler")),
        ("import moveit --out into a full disk", ["import", "moveit", "w.scene", "--robot", "panda", "--out", "disk/m.yaml"], then(moveit, small_disk("disk", 4, 4096)), ("w.scene", "disk/filler"), (3,), listing_of("disk", "filler")),
        ("schema --out into a full disk", ["schema", "--out", "disk/s.json"], small_disk("disk", 8, 4096), ("disk/filler",), (3,), listing_of("disk", "filler")),
        ("check --update, a new golden folder on a disk with room for its CSV only", ["check", "s.yaml", "--golden", "disk/g", "--update", "-q"], then(tiny_scene(), small_disk("disk", 16)), (), (3,), pair_whole("disk/g")),
        ("check --update of two scenes, the second pair past the disk", ["check", "s.yaml", "a.yaml", "--golden", "disk", "--update", "-q"], then(tiny_scene(), tiny_scene("a.yaml", OTHER), small_disk("disk", 28)), (), (3,), lambda d: pair_whole("disk")(d) + pair_whole("disk", "other")(d)),
        ("sweep --out a 32 KB disk", ["sweep", "s.yaml", "--set", "solver.step=0.1,0.2", "--out", "disk", "-q", "--jobs", "1"], then(tiny_scene(), small_disk("disk", 32)), (), (0, 3), None),
        ("a --jobs 2 batch into a 32 KB disk", ["run", "s.yaml", "a.yaml", "--out", "disk", "--no-video", "-q", "--jobs", "2"], then(tiny_scene(), tiny_scene("a.yaml", OTHER), small_disk("disk", 32)), (), (3,), None),
    ]
    # fmt: on
    for label, args, setup, keep, codes, after in disks:
        out.append(
            Attempt(
                k, label, args, setup, codes, message=full, keep=keep, after=after, timeout=400, litter_in=("disk", "o")
            )
        )
    # caches and temporary files on a full disk: the command goes on without keeping them
    out += [
        Attempt(
            k,
            "validate, NUMBA_CACHE_DIR on a full disk (numba cannot keep its code)",
            ["validate", "s.yaml"],
            then(tiny_scene(), small_disk("disk", 8, 4096)),
            (0,),
            message=r"^ok",
            env={"NUMBA_CACHE_DIR": "{d}/disk/numba"},
            timeout=600,
        ),
        Attempt(
            k,
            "run --no-video, NUMBA_CACHE_DIR on a full disk",
            ["run", "s.yaml", "--out", "o", "--no-video", "-q"],
            then(tiny_scene(), small_disk("disk", 8, 4096)),
            (0,),
            env={"NUMBA_CACHE_DIR": "{d}/disk/numba"},
            timeout=900,
            after=lambda d: [] if (d / "o/tiny/summary.json").is_file() else ["no o/tiny/summary.json"],
        ),
        Attempt(
            k,
            "robots --fit, ARMANIM_CACHE_DIR on a full disk",
            ["robots", "--fit", "robot.urdf"],
            then(one_mesh_robot(), small_disk("disk", 8, 4096)),
            (0,),
            message=r"link: \"l1\"",
            env={"ARMANIM_CACHE_DIR": "{d}/disk/cache"},
        ),
        Attempt(
            k,
            "run with video, TMPDIR on a full disk",
            ["run", "s.yaml", "--out", "o", "-q"],
            then(tiny_scene(), small_disk("disk", 8, 4096)),
            (0, 3),
            message_if_3=full,
            env={"TMPDIR": "{d}/disk"},
            timeout=600,
            litter_in=("o", "disk"),
        ),
        Attempt(
            k,
            "run with video under a 20 KB file-size limit (RLIMIT_FSIZE)",
            ["run", "s.yaml", "--out", "o", "-q"],
            tiny_scene(),
            (3,),
            message=r"too large|ffmpeg",
            fsize=20_000,
            timeout=600,
            after=listing_of("o", ".tiny.lock"),
        ),
        Attempt(
            k,
            "export --out under a 2 KB file-size limit",
            ["export", "o/tiny", "--out", "e.json"],
            finished_run,
            (3,),
            message=r"e\.json",
            fsize=2_000,
            keep=("o/tiny",),
            litter_in=(".",),
            after=lambda d: [] if not (d / "e.json").exists() else ["e.json written"],
        ),
    ]
    # paths past PATH_MAX (4,096 bytes), newlines in an outputs folder's name
    long = "/".join(["p" * 250] * 17)
    out += [
        Attempt(
            k,
            "run --out a path of 4,266 characters (past PATH_MAX)",
            ["run", "s.yaml", "--out", long, "--no-video", "-q"],
            tiny_scene(),
            (2, 3),
            message=r"long|too|cannot",
            litter_in=(".",),
        ),
        Attempt(
            k,
            "export --out a path past PATH_MAX",
            ["export", "o/tiny", "--out", f"{long}/e.json"],
            finished_run,
            (2, 3),
            message=r"long|too|cannot",
            keep=("o/tiny",),
        ),
        Attempt(
            k,
            "check --update --golden a path past PATH_MAX",
            ["check", "s.yaml", "--golden", long, "--update", "-q"],
            tiny_scene(),
            (2, 3),
            message=r"long|too|cannot",
        ),
        Attempt(
            k,
            "validate a scene whose arm.urdf is a path past PATH_MAX",
            ["validate", "s.yaml"],
            tiny_scene(text=MESH_SCENE.replace("robot.urdf", f"{long}/r.urdf")),
            (2,),
            message=AT_LINE,
        ),
        Attempt(
            k,
            "a batch of two into an outputs folder named 'o<newline>x': index.csv's folders read back",
            ["run", "s.yaml", "a.yaml", "--out", "o\nx", "--no-video", "-q"],
            then(tiny_scene(), tiny_scene("a.yaml", OTHER)),
            (0,),
            after=index_folder_is("o\nx", "o\nx/tiny", "o\nx/other"),
            litter_in=("o\nx",),
        ),
    ]
    return out


PRELUDE = '''
import os, sys
import numpy as np
SCENES = sys.argv[1]


def expect_error(label, call, words=()):
    """The call must raise a clear error (ValueError, TypeError or armanim's own) saying ``words``."""
    from armanim.errors import ArmanimError
    try:
        value = call()
    except (ValueError, TypeError, ArmanimError) as exc:
        text = str(exc)
        missing = [w for w in words if w.lower() not in text.lower()]
        if missing:
            print(f"WRONG {label}: {type(exc).__name__}({text[:300]!r}) does not say {missing}")
            sys.exit(1)
        print(f"ok {label}: {type(exc).__name__}: {text[:200]}")
        return
    print(f"WRONG {label}: no error; it returned {value!r:.300}")
    sys.exit(1)


def wrong(text):
    print("WRONG " + text)
    sys.exit(1)


def expect_exit(label, call, code):
    """The call must raise armanim's own error with the exit code the command would use."""
    from armanim.errors import ArmanimError
    try:
        call()
    except ArmanimError as exc:
        if exc.exit_code != code:
            wrong(f"{label}: exit_code {exc.exit_code}: {exc}")
        print(f"ok {label}: {exc}")
        return
    wrong(f"{label}: no error")


def problem_of(name):
    from armanim import load_scene, scene_to_problem
    return scene_to_problem(load_scene(f"{SCENES}/{name}.yaml").model)
'''
"""What every api16 snippet starts with: its argv[1] is the bundled scenes' folder."""


def api16_attempts() -> list[Attempt]:
    """The Python API of docs/python-api.md called with hostile arguments (poses of the wrong length,
    a scalar, NaN, goals and starts of the wrong shape, bad files and folders, NUMBA_DISABLE_JIT=1),
    each held to what a caller expects: a clear ValueError, TypeError or ArmanimError (with the exit
    code the command would use), never a wrong answer or an error from deep inside; and the compiled
    kinematics against the numpy reference and the Jacobian against finite differences."""
    k = "api16"
    panda = 'from armanim import forward\np = problem_of("panda-place")\n'
    # fmt: off
    snippets: list[tuple[str, str, dict]] = [
        ("forward: 2 angles for a 7-joint Panda", panda + 'expect_error("short", lambda: forward(p.arm, np.zeros(2)).points, ["7"])', {}),
        ("forward: 8 angles for a 7-joint Panda", panda + 'expect_error("long", lambda: forward(p.arm, np.zeros(8)).points, ["7"])', {}),
        ("forward: one number (a 0-d array) for a Panda", panda + 'expect_error("scalar", lambda: forward(p.arm, np.float64(0.3)).points, ["7"])', {}),
        ("forward: a batch (3, 2) for a Panda", panda + 'expect_error("batch", lambda: forward(p.arm, np.zeros((3, 2))).points, ["7"])', {}),
        ("forward: the same short pose twice gives the same answer or an error (no memory it does not own)", panda + '''
big = np.full(64, 7.0)
try:
    a, b = forward(p.arm, big[:2]).points, forward(p.arm, big[:2].copy()).points
except (ValueError, TypeError) as exc:
    print("ok: refused:", exc); sys.exit(0)
if not np.array_equal(a, b):
    wrong(f"one short pose, two answers: tips {a[-1]} and {b[-1]}")
''', {}),
        ("forward: a NaN angle gives NaN, never finite numbers", panda + '''
pose = forward(p.arm, np.array([0.1, np.nan, 0, -1, 0, 1, 0])).points
if np.isfinite(pose[2:]).all():
    wrong(f"a NaN joint, finite points after it: {pose[-1]}")
print("ok")
''', {}),
        ("forward: compiled against the numpy reference, 300 random Panda poses and a (2, 3, 7) batch", panda + '''
from armanim.arm import kinematics
rng = np.random.default_rng(16)
poses = rng.uniform(-3, 3, (300, 7))
for phi in poses:
    a, b = forward(p.arm, phi).points, kinematics.forward(p.arm, phi).points
    if np.abs(a - b).max() > 1e-9:
        wrong(f"compiled and numpy differ by {np.abs(a - b).max()} at {phi}")
batch = poses[:6].reshape(2, 3, 7)
c = forward(p.arm, batch).points
for i in range(2):
    for j in range(3):
        if np.abs(c[i, j] - kinematics.forward(p.arm, batch[i, j]).points).max() > 1e-9:
            wrong(f"the batch's pose {i},{j} differs from the pose alone")
print("ok")
''', {}),
        ("geometric_jacobian: the tip's rows against finite differences, 50 random Panda poses", panda + '''
from armanim.arm.kernel import geometric_jacobian
rng = np.random.default_rng(17)
for phi in rng.uniform(-2.5, 2.5, (50, 7)):
    jac = geometric_jacobian(forward(p.arm, phi), p.arm)
    h = 1e-6
    numeric = np.stack([(forward(p.arm, phi + h * e).tip - forward(p.arm, phi - h * e).tip) / (2 * h) for e in np.eye(7)], axis=1)
    if np.abs(jac[:3] - numeric).max() > 1e-6:
        wrong(f"the Jacobian's tip rows differ from finite differences by {np.abs(jac[:3] - numeric).max()}")
print("ok")
''', {}),
        ("solve_pose: a goal of 2 numbers", 'from armanim import solve_pose\np = problem_of("notes-arm")\nexpect_error("goal", lambda: solve_pose(p, np.array([6.0, 0.0]), p.home), ["goal"])', {}),
        ("solve_pose: a goal of 4 numbers", 'from armanim import solve_pose\np = problem_of("notes-arm")\nexpect_error("goal", lambda: solve_pose(p, np.array([6.0, 0.0, 10, 1]), p.home), ["goal"])', {}),
        ("solve_pose: a start of 6 angles for a Panda", 'from armanim import solve_pose\np = problem_of("panda-place")\nexpect_error("start", lambda: solve_pose(p, np.array([0.5, 0.1, 0.3]), np.zeros(6)), ["7"])', {}),
        ("solve_pose: a start of 3 angles for notes-arm (pinv)", 'from armanim import solve_pose\np = problem_of("notes-arm")\nexpect_error("start", lambda: solve_pose(p, np.array([6.0, 0.0, 10]), np.zeros(3)), [str(len(p.home))])', {}),
        ("solve_pose: a NaN goal is refused or not converged, never 'converged'", '''
from armanim import solve_pose
p = problem_of("notes-arm")
from armanim.errors import ArmanimError
try:
    answer = solve_pose(p, np.array([np.nan, 0.0, 10]), p.home)
except (ValueError, ArmanimError) as exc:
    print("ok: refused:", exc); sys.exit(0)
if answer.status == "converged":
    wrong(f"a NaN goal converged: {answer.phi}")
print("ok:", answer.status)
''', {}),
        ("solve_pose: a converged answer's tip is within the tolerance of its goal (20 random reachable goals)", '''
from armanim import forward, solve_pose
p = problem_of("notes-arm")
rng = np.random.default_rng(18)
for _ in range(20):
    goal = forward(p.arm, p.home + rng.uniform(-0.8, 0.8, len(p.home))).tip
    answer = solve_pose(p, goal, p.home)
    if answer.status == "converged":
        miss = np.linalg.norm(forward(p.arm, answer.phi).tip - goal)
        if miss > max(p.solver.tolerance, 1e-9) * 1.01 or abs(miss - answer.distance) > 1e-9:
            wrong(f"converged {miss} from its goal (tolerance {p.solver.tolerance}, said {answer.distance})")
print("ok")
''', {}),
        ("run_scene under NUMBA_DISABLE_JIT=1", '''
from armanim import RunOptions, run_scene
open("t.yaml", "w").write("version: 1\\nname: tiny\\narm: {links: [1, 1, 1]}\\ngoals: [[1, 1, 1], [0.5, -1, 1]]\\n")
result = run_scene("t.yaml", "o", RunOptions(video=False))
if [g.reached for g in result.solution.goals] != [True, True]:
    wrong(f"goals {[g.reason for g in result.solution.goals]}")
print("ok")
''', {"NUMBA_DISABLE_JIT": "1"}),
        ("solve_trajectory under NUMBA_DISABLE_JIT=1, numba imported by the caller first", '''
import numba
from armanim import load_scene, scene_to_problem, solve_trajectory
solution = solve_trajectory(problem_of("notes-arm"))
print("ok", solution.reached)
''', {"NUMBA_DISABLE_JIT": "1"}),
        ("forward under NUMBA_DISABLE_JIT=1 agrees with the numpy reference", panda + '''
from armanim.arm import kinematics
phi = np.linspace(-1, 1, 7)
if np.abs(forward(p.arm, phi).points - kinematics.forward(p.arm, phi).points).max() > 1e-9:
    wrong("compiled and numpy differ")
print("ok")
''', {"NUMBA_DISABLE_JIT": "1"}),
        ("run_scene of a missing scene: an ArmanimError with exit code 2", '''
from armanim import RunOptions, run_scene
from armanim.errors import ArmanimError
expect_exit("the call", lambda: run_scene("nosuch.yaml", "o", RunOptions(video=False)), 2)
''', {}),
        ("run_scene with out_root a file: an OutputError with exit code 3", '''
from armanim import RunOptions, run_scene
from armanim.errors import ArmanimError
open("t.yaml", "w").write("version: 1\\nname: tiny\\narm: {links: [1, 1, 1]}\\ngoals: [[1, 1, 1]]\\n")
open("afile", "w").write("mine\\n")
try:
    run_scene("t.yaml", "afile", RunOptions(video=False))
except ArmanimError as exc:
    if exc.exit_code != 3:
        wrong(f"exit_code {exc.exit_code}")
    if open("afile").read() != "mine\\n":
        wrong("afile changed")
    print("ok", exc); sys.exit(0)
wrong("no error")
''', {}),
        ("scene_model of a mapping with a NaN goal: a SceneError", '''
from armanim.scene import scene_model
expect_error("nan", lambda: scene_model({"version": 1, "arm": {"links": [1, 1]}, "goals": [[float("nan"), 1, 0]]}), ["goals"])
''', {}),
        ("run_scene with RenderOverrides(size=(0, 0))", '''
from armanim import RenderOverrides, RunOptions, run_scene
open("t.yaml", "w").write("version: 1\\nname: tiny\\narm: {links: [1, 1, 1]}\\ngoals: [[1, 1, 1]]\\n")
expect_error("size", lambda: run_scene("t.yaml", "o", RunOptions(render=RenderOverrides(size=(0, 0)))), ["size"])
''', {}),
        ("run_scene with RenderOverrides(fps=nan)", '''
from armanim import RenderOverrides, RunOptions, run_scene
open("t.yaml", "w").write("version: 1\\nname: tiny\\narm: {links: [1, 1, 1]}\\ngoals: [[1, 1, 1]]\\n")
expect_error("fps", lambda: run_scene("t.yaml", "o", RunOptions(video=False, render=RenderOverrides(fps=float("nan")))), ["fps"])
''', {}),
        ("RunOptions(jobs=0) and jobs=-3", '''
from armanim import RunOptions, run_scene
open("t.yaml", "w").write("version: 1\\nname: tiny\\narm: {links: [1, 1, 1]}\\ngoals: [[1, 1, 1]]\\n")
expect_error("jobs 0", lambda: run_scene("t.yaml", "o", RunOptions(video=False, jobs=0)), ["jobs"])
expect_error("jobs -3", lambda: run_scene("t.yaml", "o", RunOptions(video=False, jobs=-3)), ["jobs"])
''', {}),
        ("parse_setting without '=' and with an empty value list", '''
from armanim import parse_setting
expect_error("no =", lambda: parse_setting("solver.step"), ["--set"])
expect_error("empty", lambda: parse_setting("solver.step="), [])
''', {}),
        ("rerender_run and write_run_viewer of a folder that is not a run: exit code 2", '''
from armanim import rerender_run, write_run_viewer
from armanim.errors import ArmanimError
os.mkdir("notarun")
for call in (lambda: rerender_run("notarun"), lambda: write_run_viewer("notarun")):
    try:
        call()
    except ArmanimError as exc:
        if exc.exit_code != 2:
            wrong(f"exit_code {exc.exit_code}: {exc}")
        continue
    wrong("no error")
print("ok")
''', {}),
        ("retime at fps 0, -1 and NaN", '''
from armanim import solve_trajectory
from armanim.motion.timing.retime import retime
p = problem_of("notes-arm")
s = solve_trajectory(p)
for fps in (0.0, -1.0, float("nan")):
    expect_error(f"fps {fps}", lambda: retime(p, s, fps), ["fps"])
''', {}),
        ("export_run of an unknown format: an ArmanimError with exit code 2", '''
from armanim import RunOptions, export_run, run_scene
from armanim.errors import ArmanimError
open("t.yaml", "w").write("version: 1\\nname: tiny\\narm: {links: [1, 1, 1]}\\ngoals: [[1, 1, 1]]\\n")
run_scene("t.yaml", "o", RunOptions(video=False))
expect_exit("the call", lambda: export_run("o/tiny", "csv"), 2)
''', {}),
    ]
    # fmt: on
    return [
        Attempt(k, label, [str(SCENES)], codes=(0,), python=code, env=env, timeout=600, litter_in=(".",))
        for label, code, env in snippets
    ]


def warm_says_kept(d: Path) -> list[str]:
    """Check of ``warm`` with nowhere to keep numba's code: it must not say the cache keeps it."""
    said = " ".join((d / "said.txt").read_text().split()) if (d / "said.txt").exists() else ""  # wrapped at 80
    return ["warm said numba's cache keeps the code it could not keep"] if "cache keeps it" in said else []


def odd16_attempts() -> list[Attempt]:
    """A second wave on the same new angles, on the fixed code: reading what cannot be written (a
    write-protected run folder rendered, exported and viewed elsewhere, a read-only golden folder
    checked), a batch and a sweep meeting a write-protected run folder, ``warm`` with nowhere to
    keep its code, and more of the Python API (a sweep's jobs, solve_pose's iterations, an
    orientation of NaN, an import of an unknown robot)."""
    k = "odd16"
    out: list[Attempt] = []

    def protected_run(d: Path) -> None:
        finished_run(d)
        (d / "o/tiny").chmod(0o555)

    # fmt: off
    reads: list[tuple[str, list[str], Callable[[Path], None], tuple[str, ...], tuple[int, ...], str | None]] = [
        ("render --out r of a write-protected run folder (only read)", ["render", "o/tiny", "--out", "r", "--size", "64x36"], protected_run, ("o/tiny",), (0,), None),
        ("export --out e.json of a write-protected run folder", ["export", "o/tiny", "--out", "e.json"], protected_run, ("o/tiny",), (0,), None),
        ("view --out v.html of a write-protected run folder", ["view", "o/tiny", "--out", "v.html"], protected_run, ("o/tiny",), (0,), None),
        ("check against a read-only golden folder (only read)", ["check", "s.yaml", "--golden", "g", "-q"], then(tiny_scene(), lambda d: armanim_in(d, "check", "s.yaml", "--golden", "g", "--update", "-q"), locked_up("g")), ("g",), (0,), None),
        ("compare of two read-only CSVs", ["compare", "o/tiny/trajectory.csv", "o/tiny/trajectory.csv"], protected_run, ("o/tiny",), (0,), None),
        ("a batch of two, one run folder write-protected: the other written, the protected one kept", ["run", "s.yaml", "a.yaml", "--out", "o", "--no-video", "-q", "--jobs", "1"], then(tiny_scene("a.yaml", OTHER), protected_run), ("o/tiny",), (3,), r"write-protected"),
        ("a sweep whose variant folder is write-protected", ["sweep", "s.yaml", "--set", "solver.step=0.1,0.2", "--out", "o", "-q", "--jobs", "1"], then(tiny_scene(), lambda d: armanim_in(d, "sweep", "s.yaml", "--set", "solver.step=0.1,0.2", "--out", "o", "-q", "--jobs", "1"), locked_up("o/tiny_step-0.1")), ("o/tiny_step-0.1",), (3,), r"write-protected"),
        ("import moveit --urdf with an unreadable SRDF", ["import", "moveit", "w.scene", "--urdf", "robot.urdf", "--srdf", "r.srdf", "--out", "m.yaml"], then(one_mesh_robot(), mine("w.scene", "w\n* b\n1\nbox\n0.1 0.1 0.1\n1 1 1\n0 0 0 1\n0 0 0 0\n.\n"), mine("r.srdf", "<robot name='r'/>\n"), locked_up("r.srdf", mode=0)), ("w.scene",), (2,), r"r\.srdf"),
    ]
    # fmt: on
    for label, args, setup, keep, codes, message in reads:
        out.append(
            Attempt(
                k,
                label,
                args,
                setup,
                codes,
                message=message,
                keep=keep,
                timeout=400,
                user=True,
                litter_in=("o", "r", "."),
            )
        )
    out.append(
        Attempt(
            k,
            "warm with numba's cache on a full disk: no claim that the cache keeps it",
            ["validate", "s.yaml"],
            then(
                tiny_scene(),
                small_disk("disk", 8, 4096),
                lambda d: write(
                    d / "said.txt",
                    subprocess.run(
                        [sys.executable, "-m", "armanim", "warm"],
                        cwd=d,
                        env={**os.environ, "PYTHONPATH": str(SRC), "NUMBA_CACHE_DIR": str(d / "disk/numba")},
                        capture_output=True,
                        text=True,
                        timeout=1500,
                    ).stdout,
                ),
            ),
            (0,),
            timeout=600,
            after=warm_says_kept,
        )
    )
    # fmt: off
    snippets: list[tuple[str, str]] = [
        ("run_sweep(jobs=0)", '''
from armanim import parse_setting, run_sweep
open("t.yaml", "w").write("version: 1\\nname: tiny\\narm: {links: [1, 1, 1]}\\ngoals: [[1, 1, 1]]\\n")
expect_error("jobs", lambda: run_sweep("t.yaml", [parse_setting("solver.step=0.1,0.2")], "o", jobs=0), ["jobs"])
'''),
        ("solve_pose with max_iterations 0 and -5: an answer or a clear error", '''
from armanim import solve_pose
from armanim.errors import ArmanimError
p = problem_of("notes-arm")
for n in (0, -5):
    try:
        answer = solve_pose(p, np.array([6.0, 0.0, 10.0]), p.home, max_iterations=n)
    except (ValueError, ArmanimError) as exc:
        print("ok refused", n, exc); continue
    if answer.status == "converged" and np.linalg.norm(forward_tip(p, answer.phi) - [6.0, 0.0, 10.0]) > p.solver.tolerance * 1.01:
        wrong(f"converged far from the goal at max_iterations={n}")
    print("ok", n, answer.status)
'''),
        ("solve_pose with an orientation whose rotation is NaN: refused or not converged", '''
from armanim import solve_pose
from armanim.errors import ArmanimError
from armanim.motion.orientation import Orientation
p = problem_of("panda-place")
try:
    answer = solve_pose(p, np.array([0.5, 0.1, 0.3]), p.home, orientation=Orientation(rotation=np.full((3, 3), np.nan)))
except (ValueError, ArmanimError) as exc:
    print("ok refused", exc); sys.exit(0)
if answer.status == "converged":
    wrong("a NaN orientation converged")
print("ok", answer.status)
'''),
        ("Orientation with a zero axis", '''
from armanim.motion.orientation import Orientation
expect_error("zero axis", lambda: Orientation(axis=np.zeros(3)), [])
'''),
        ("import_moveit with RobotSource(robot='nosuch'): exit code 2", '''
from armanim import RobotSource, import_moveit
from armanim.errors import ArmanimError
open("w.scene", "w").write("w\\n* b\\n1\\nbox\\n0.1 0.1 0.1\\n1 1 1\\n0 0 0 1\\n0 0 0 0\\n.\\n")
expect_exit("the call", lambda: import_moveit("w.scene", None, RobotSource(robot="nosuch"), "m.yaml"), 2)
'''),
        ("write_run_viewer of a write-protected run with out= elsewhere", '''
from armanim import RunOptions, run_scene, write_run_viewer
open("t.yaml", "w").write("version: 1\\nname: tiny\\narm: {links: [1, 1, 1]}\\ngoals: [[1, 1, 1]]\\n")
run_scene("t.yaml", "o", RunOptions(video=False))
os.chmod("o/tiny", 0o555)
print("ok", write_run_viewer("o/tiny", out="v.html"))
os.chmod("o/tiny", 0o755)
'''),
    ]
    # fmt: on
    for label, code in snippets:
        code = code.replace("forward_tip(p, answer.phi)", "__import__('armanim').forward(p.arm, answer.phi).tip")
        out.append(Attempt(k, label, [str(SCENES)], codes=(0,), python=code, timeout=600, litter_in=(".",)))
    return out


# ------------------------------------------------------------------ campaign 17: new angles

BACKGROUND: list[subprocess.Popen] = []
"""Processes an attempt's setup started beside armanim (a flapper, a lock holder, a Dask scheduler):
each in a session of its own, all killed after the attempt (:func:`stop_background`)."""


def background(*command: str, env: dict | None = None, cwd: str = "/") -> subprocess.Popen:
    """Start ``command`` in a session of its own, beside the attempt (stopped after it)."""
    proc = subprocess.Popen(
        list(command),
        cwd=cwd,
        env={**os.environ, "PYTHONPATH": str(SRC), **(env or {})},
        stdin=subprocess.DEVNULL,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        start_new_session=True,
    )
    BACKGROUND.append(proc)
    return proc


def stop_background() -> None:
    """Kill every process :func:`background` started (their sessions), and wait for them."""
    while BACKGROUND:
        proc = BACKGROUND.pop()
        with contextlib.suppress(OSError):
            os.killpg(proc.pid, signal.SIGKILL)
        with contextlib.suppress(subprocess.TimeoutExpired):
            proc.wait(10)


FLAPPER = """
import os, sys, time
path, seconds, *variants = sys.argv[1:]
end = time.monotonic() + float(seconds)
tmp, i = path + ".flapping", 0
while time.monotonic() < end:
    v = variants[i % len(variants)]
    i += 1
    try:
        if os.path.lexists(tmp):
            os.unlink(tmp)
        if v.startswith("->"):
            os.symlink(v[2:], tmp)
        else:
            os.link(v, tmp)
        os.replace(tmp, path)
    except OSError:
        pass
    time.sleep(0.002)
"""


def flapping(at: str, *variants: str, seconds: float = 200.0) -> Callable[[Path], None]:
    """Setup step: ``at`` (relative to the folder) swapped, every 2 ms and atomically (a rename),
    between ``variants`` (files relative to the folder, hard-linked in turn, so a FIFO stays one;
    ``->TARGET`` a symbolic link) while armanim runs: a file changing between its check and its
    use, or between two reads (time of check to time of use)."""

    def step(d: Path) -> None:
        paths = [v if v.startswith("->") else str(d / v) for v in variants]
        background(sys.executable, "-c", FLAPPER, str(d / at), str(seconds), *paths)
        time.sleep(0.3)

    return step


def clean_run_agrees(
    args: list[str],
    versions: list[Callable[[Path], None]],
    files: tuple[str, ...] = ("trajectory.csv",),
    run: str = "o/tiny",
) -> Callable[[Path], list[str]]:
    """After: when armanim's run folder ``run`` exists, its ``files`` are byte for byte those of a
    clean run (the same ``args``, no fault) of one of the inputs' ``versions`` (each a setup made
    afresh): a run never mixes two versions of a file that changed under it."""

    def check(d: Path) -> list[str]:
        if not (d / run).is_dir():
            return []
        got = [(d / run / f).read_bytes() if (d / run / f).is_file() else None for f in files]
        for number, version in enumerate(versions):
            clean = d.parent / f"{d.name}.clean{number}"
            shutil.rmtree(clean, ignore_errors=True)
            clean.mkdir()
            version(clean)
            done = subprocess.run(
                [sys.executable, "-m", "armanim", *args],
                cwd=clean,
                env={**os.environ, "PYTHONPATH": str(SRC)},
                capture_output=True,
                timeout=900,
            )
            same = done.returncode == 0 and got == [
                (clean / run / f).read_bytes() if (clean / run / f).is_file() else None for f in files
            ]
            shutil.rmtree(clean, ignore_errors=True)
            if same:
                return []
        return [f"{run}'s {', '.join(files)} match no clean run of the {len(versions)} versions of its inputs"]

    return check


def read_only_disk(at: str, *fill: Callable[[Path], object], kilobytes: int = 65536) -> Callable[[Path], None]:
    """Setup: a tmpfs at ``at``, filled by ``fill`` (steps on the folder), then remounted read-only
    (EROFS: root cannot write through it as it writes through modes)."""

    def setup(d: Path) -> None:
        small_disk(at, kilobytes)(d)
        for step in fill:
            step(d)
        subprocess.run(["mount", "-o", "remount,ro", str(d / at)], check=True)

    return setup


def bind_read_only(at: str) -> Callable[[Path], None]:
    """Setup step: the folder ``at`` bind-mounted on itself read-only."""

    def step(d: Path) -> None:
        subprocess.run(["mount", "--bind", str(d / at), str(d / at)], check=True)
        subprocess.run(["mount", "-o", "remount,bind,ro", str(d / at)], check=True)

    return step


def copy_tree(src: str, dst: str) -> Callable[[Path], None]:
    """Setup step: ``src`` (relative to the folder) copied to ``dst``, modes and times kept."""
    return lambda d: shutil.copytree(d / src, d / dst, symlinks=True) and None


WARM_CACHE: Path | None = None  # --warm-cache: numba's cache of the attacked src, warmed (NUMBA_CACHE_DIR)


def warm_cache_copy(at: str = "nc") -> Callable[[Path], None]:
    """Setup step: a copy of the campaign's warmed numba cache at ``at`` (the attempt's
    ``NUMBA_CACHE_DIR``: its lock files beside each kernel's index)."""

    def step(d: Path) -> None:
        if WARM_CACHE is None:
            raise RuntimeError("this attempt needs --warm-cache (numba's cache of --src, warmed)")
        shutil.copytree(WARM_CACHE, d / at)

    return step


def each_lock(at: str, make: Callable[[Path], None]) -> Callable[[Path], None]:
    """Setup step: every compile lock file under ``at`` removed and made again by ``make(path)``."""

    def step(d: Path) -> None:
        locks = sorted((d / at).rglob("*.lock"))
        if not locks:
            raise RuntimeError(f"no lock file under {at}")
        for lock in locks:
            lock.unlink()
            make(lock)

    return step


LOCK_HOLDER = """
import fcntl, glob, os, sys, time
held = []
for path in sorted(glob.glob(sys.argv[1] + "/**/*.lock", recursive=True)):
    fd = os.open(path, os.O_RDWR)
    fcntl.flock(fd, fcntl.LOCK_EX)
    held.append(fd)
open(sys.argv[2], "w").write(str(len(held)))
time.sleep(float(sys.argv[3]))
"""


def locks_held(at: str, seconds: float = 900.0) -> Callable[[Path], None]:
    """Setup step: another process holds every compile lock under ``at`` for ``seconds`` (a holder
    stopped with Ctrl-Z, or stuck), started and waited for until it holds them."""

    def step(d: Path) -> None:
        background(sys.executable, "-c", LOCK_HOLDER, str(d / at), str(d / "held.txt"), str(seconds))
        deadline = time.monotonic() + 60
        while not (d / "held.txt").exists() and time.monotonic() < deadline:
            time.sleep(0.1)
        if not (d / "held.txt").exists():
            raise RuntimeError("the lock holder did not start")

    return step


def armanim_killed_at(seconds: float, *args: str, env: dict | None = None) -> Callable[[Path], None]:
    """Setup step: armanim ``args`` started and its session killed with SIGKILL after ``seconds``
    (a holder of the compile lock, or a warm, gone mid-compile)."""

    def step(d: Path) -> None:
        proc = subprocess.Popen(
            [sys.executable, "-m", "armanim", *args],
            cwd=d,
            env={**os.environ, "PYTHONPATH": str(SRC), **{k: v.replace("{d}", str(d)) for k, v in (env or {}).items()}},
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
            start_new_session=True,
        )
        try:
            proc.wait(seconds)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()

    return step


def dask_bin() -> str:
    return str(Path(sys.executable).parent / "dask")


def free_port() -> int:
    import socket

    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def wait_listening(port: int, seconds: float = 60.0) -> None:
    import socket

    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        with contextlib.suppress(OSError), socket.create_connection(("127.0.0.1", port), timeout=1):
            return
        time.sleep(0.2)
    raise RuntimeError(f"nothing listens on port {port} after {seconds:g} s")


SILENT_SERVER = """
import socket, sys, time
s = socket.socket(); s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
s.bind(("127.0.0.1", int(sys.argv[1]))); s.listen(16)
kept = []
while True:
    c, _ = s.accept()
    if sys.argv[2] != "silent":
        c.sendall(sys.argv[2].encode().decode("unicode_escape").encode("latin-1")); c.close()
    else:
        kept.append(c)
"""

PORTS: dict[str, int] = {}  # an attempt's name -> its port (chosen as the attempt is made)


def port_of(name: str) -> int:
    if name not in PORTS:
        PORTS[name] = free_port()
    return PORTS[name]


def fake_server(port: int, answer: str = "silent") -> Callable[[Path], None]:
    """Setup step: a TCP server on ``port`` that accepts and never answers, or sends ``answer`` and closes."""

    def step(d: Path) -> None:
        background(sys.executable, "-c", SILENT_SERVER, str(port), answer)
        wait_listening(port)

    return step


def dask_cluster(
    port: int, workers: int = 1, kill_scheduler_at: float | None = None, kill_worker_at: float | None = None
) -> Callable[[Path], None]:
    """Setup step: a Dask scheduler on ``port`` and ``workers`` worker processes (none: a scheduler
    alone), each in a session of its own; the scheduler, or the workers, killed with SIGKILL
    ``kill_*_at`` seconds after the setup ends (armanim then runs)."""

    def step(d: Path) -> None:
        scheduler = background(dask_bin(), "scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard")
        wait_listening(port)
        pids = []
        if workers:
            worker = background(
                dask_bin(),
                "worker",
                f"tcp://127.0.0.1:{port}",
                "--nworkers",
                str(workers),
                "--nthreads",
                "1",
                "--no-dashboard",
                "--no-nanny",
            )
            pids.append(worker.pid)
            time.sleep(6)  # the workers import Dask and register
        for at, pid in ((kill_scheduler_at, scheduler.pid), (kill_worker_at, pids[0] if pids else None)):
            if at is not None and pid is not None:
                background("sh", "-c", f"sleep {at}; kill -KILL -{pid}")

    return step


def nothing_made(*where: str) -> Callable[[Path], list[str]]:
    """Check: no run folder, index or staging left in ``where`` (an outputs folder that may exist,
    empty, or not at all)."""

    def check(d: Path) -> list[str]:
        problems = []
        for place in where:
            base = d / place
            if base.is_dir():
                found = sorted(p.name for p in base.iterdir() if not re.fullmatch(r"\.[^/]+\.lock", p.name))
                if found:  # a run folder's lock OUT/.NAME.lock is kept on purpose (docs/reliability.md, 10)
                    problems.append(f"{place} holds {found[:6]}")
        return problems

    return check


def help_words_kept(*command: str) -> Callable[[Path], list[str]]:
    """Check of ``command --help`` run at a narrow terminal (its output in the attempt's said.txt):
    every word of the same help at 200 columns (option names and their help) is there whole."""

    def check(d: Path) -> list[str]:
        def words(text: str) -> set[str]:
            return set(re.findall(r"[-\w]{3,}", re.sub(r"[│╭╮╰╯─]", " ", text)))

        wide = subprocess.run(
            [sys.executable, "-m", "armanim", *command, "--help"],
            env={**os.environ, "PYTHONPATH": str(SRC), "COLUMNS": "200"},
            capture_output=True,
            text=True,
            timeout=120,
        ).stdout
        narrow = (d / "said.txt").read_text() if (d / "said.txt").exists() else ""
        lost = sorted(words(wide) - words(narrow))
        return [f"{len(lost)} words of the help are missing or cut at 20 columns: {lost[:8]}"] if lost else []

    return check


def same_as_clean(run: str = "o/tiny", text: str = TINY, files: tuple[str, ...] = ("trajectory.csv", "summary.json")):
    """Check: the run folder's ``files`` are those of a clean run of ``text`` (no fault, the campaign's cache)."""
    out = run.split("/")[0]
    return clean_run_agrees(["run", "s.yaml", "--out", out, "--no-video", "-q"], [tiny_scene(text=text)], files, run)


def mesh17_attempts() -> list[Attempt]:
    """Files a mesh names, in shapes campaigns 1-16 did not try: the robot's triangle and byte
    budgets reached by several files (each under its own limit), an instance count weighted by a
    big geometry, a header claiming four billion triangles, a texture named by an MTL or a COLLADA
    image that is a FIFO, an MTL that is a link to a 2 GB sparse file; and meshes swapped while a
    run reads them (a FIFO, a 2 GB sparse file, another mesh: time of check to time of use)."""
    k = "mesh17"
    out: list[Attempt] = []
    tri_obj = "v 0 0 0\nv .05 0 0\nv 0 .05 0\nf 1 2 3\n"

    def many_links(count: int, make: Callable[[Path, int], str]) -> Callable[[Path], None]:
        """Setup: a URDF of ``count`` moving links, link i's collision the mesh ``make(d, i)`` names."""

        def setup(d: Path) -> None:
            lines = ['<?xml version="1.0"?>', '<robot name="r">', '<link name="l0"/>']
            for i in range(1, count + 1):
                lines.append(f'<link name="l{i}"><collision>{mesh_tag(make(d, i))}</collision></link>')
                lines.append(
                    f'<joint name="j{i}" type="revolute"><parent link="l{i - 1}"/><child link="l{i}"/>'
                    f'<origin xyz="0 0 0.1"/><axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="1" velocity="1"/></joint>'
                )
            write(d / "robot.urdf", "\n".join([*lines, "</robot>"]) + "\n")
            write(d / "s.yaml", URDF_SCENE)

        return setup

    def stl_file(triangles: int) -> Callable[[Path, int], str]:
        def make(d: Path, i: int) -> str:
            write(d / f"m{i}.stl", stl(triangles))
            return f"m{i}.stl"

        return make

    def padded_obj(megabytes: int) -> Callable[[Path, int], str]:
        def make(d: Path, i: int) -> str:
            with open(d / f"m{i}.obj", "w") as handle:
                handle.write(tri_obj)
                line = "#" + "x" * 1023 + "\n"
                for _ in range(megabytes * 1024):
                    handle.write(line)
            return f"m{i}.obj"

        return make

    budget = r"2,000,000|triangles|256 MB|bytes|too (big|large|many)"
    # fmt: off
    out += [
        Attempt(k, "robots --fit, two links of 1,050,000 triangles each (2.1 M: over the robot's 2,000,000)", ["robots", "--fit", "robot.urdf"], many_links(2, stl_file(1_050_000)), (2,), message=budget, timeout=300),
        Attempt(k, "robots --fit, five links of a 60 MB OBJ each (300 MB: over the robot's 256 MB, each under 64 MB)", ["robots", "--fit", "robot.urdf"], many_links(5, padded_obj(60)), (2,), message=budget, timeout=300),
        Attempt(k, "validate, five links of a 60 MB OBJ each (over the robot's 256 MB)", ["validate", "s.yaml"], many_links(5, padded_obj(60)), (2,), message=budget, timeout=300),
    ]
    # fmt: on
    big_geometry = dae(1)
    # a geometry of 50,000 triangles, instanced 100 times by one node: 5,000,000 triangles from 3 MB
    corners = " ".join(f"{i * 1e-4:g} 0 0 0 {0.05 + i * 1e-4:g} 0 0 0 0.05" for i in range(50_000))
    heavy = (
        big_geometry.replace('count="9">0 0 0 0.05 0 0 0 0.05 0', f'count="{450_000}">{corners}')
        .replace('accessor source="#a0" count="3"', 'accessor source="#a0" count="150000"')
        .replace(
            '<triangles count="1"><input semantic="VERTEX" source="#v0" offset="0"/><p>0 1 2</p>',
            '<triangles count="50000"><input semantic="VERTEX" source="#v0" offset="0"/><p>'
            + " ".join(str(i) for i in range(150_000))
            + "</p>",
        )
        .replace(
            '<node id="n0"><instance_geometry url="#g0"/></node>',
            '<node id="n0">' + '<instance_geometry url="#g0"/>' * 100 + "</node>",
        )
    )
    claims = b"\0" * 80 + (4_294_967_295).to_bytes(4, "little") + stl(1)[84:]
    mtl_texture = {
        "a.obj": "mtllib m.mtl\nusemtl skin\n" + tri_obj,
        "m.mtl": "newmtl skin\nmap_Kd tex.png\n",
        "tex.png": None,
    }
    dae_image = dae(
        1,
        extra='<library_images><image id="i"><init_from>tex.png</init_from></image></library_images>'
        '<library_effects><effect id="e"><profile_COMMON><newparam sid="s"><surface type="2D"><init_from>i</init_from>'
        '</surface></newparam><newparam sid="p"><sampler2D><source>s</source></sampler2D></newparam><technique sid="t">'
        '<phong><diffuse><texture texture="p" texcoord="UV"/></diffuse></phong></technique></profile_COMMON></effect>'
        '</library_effects><library_materials><material id="mat"><instance_effect url="#e"/></material></library_materials>',
    )
    for label, name, files in [
        ("a COLLADA geometry of 50,000 triangles instanced 100 times by one node", "h.dae", {"h.dae": heavy}),
        ("a binary STL whose header claims 4,294,967,295 triangles (134 bytes)", "c.stl", {"c.stl": claims}),
        ("an OBJ whose MTL's map_Kd texture is a FIFO", "a.obj", mtl_texture),
        ("a COLLADA whose image (init_from) is a FIFO", "i.dae", {"i.dae": dae_image, "tex.png": None}),
        (
            "an OBJ whose mtllib is a link to a 2 GB sparse file",
            "a.obj",
            {"a.obj": "mtllib m.mtl\n" + tri_obj, "m.mtl": ("->", "big.bin")},
        ),
    ]:

        def setup(d: Path, name=name, files=files, where="collision") -> None:
            urdf_robot(collision=col(name), files=files)(d)
            if "big.bin" in str(files):
                sparse(d / "big.bin", 2 << 30)

        def vsetup(d: Path, name=name, files=files) -> None:
            urdf_robot(vis(name), files=files)(d)
            if "big.bin" in str(files):
                sparse(d / "big.bin", 2 << 30)

        heavy_one = name == "h.dae"
        out.append(
            Attempt(
                k,
                f"robots --fit, collision {label}",
                ["robots", "--fit", "robot.urdf"],
                setup,
                (2,) if heavy_one or name == "c.stl" else (0, 2),
                timeout=120,
                message=budget if heavy_one else None,
            )
        )
        out.append(
            Attempt(
                k,
                f"run --viewer, visual {label}",
                ["run", "s.yaml", "--out", "o", "--no-video", "--viewer", "-q"],
                vsetup,
                (0,),
                timeout=200,
            )
        )
    # time of check to time of use: the collision mesh swapped while the run reads it
    box = box_stl()
    for label, other in [
        ("a FIFO", lambda d: fifo(d / ".v/b")),
        ("a 2 GB sparse file", lambda d: sparse(d / ".v/b", 2 << 30)),
        ("a mesh twice the size", lambda d: write(d / ".v/b", box_stl(2.0))),
    ]:

        def setup(d: Path, other=other) -> None:
            one_mesh_robot()(d)
            write(d / ".v/a", box)
            other(d)
            flapping("m.stl", ".v/a", ".v/b")(d)

        versions = [one_mesh_robot()]
        if label == "a mesh twice the size":
            versions.append(then(one_mesh_robot(), lambda d: write(d / "m.stl", box_stl(2.0))))
        out.append(
            Attempt(
                k,
                f"run, the collision mesh swapped every 2 ms with {label} (time of check to time of use)",
                ["run", "s.yaml", "--out", "o", "--no-video", "-q"],
                setup,
                (0, 2),
                timeout=200,
                after=clean_run_agrees(
                    ["run", "s.yaml", "--out", "o", "--no-video", "-q"],
                    versions,
                    ("trajectory.csv", "capsules.yaml"),
                    "o/m",
                ),
            )
        )
    # the URDF swapped between two robots (a link of 0.3 and of 0.5) while the run reads it
    longer = ROBOT_ONE_MESH.replace('xyz="0 0 0.3"', 'xyz="0 0 0.5"').replace("MESH", "m.stl")

    def urdf_swapped(d: Path) -> None:
        one_mesh_robot()(d)
        shutil.copy(d / "robot.urdf", d / ".v_a.urdf")
        write(d / ".v_b.urdf", longer)
        flapping("robot.urdf", ".v_a.urdf", ".v_b.urdf")(d)

    out.append(
        Attempt(
            k,
            "run, the URDF swapped every 2 ms between two robots: the run is one of them",
            ["run", "s.yaml", "--out", "o", "--no-video", "-q"],
            urdf_swapped,
            (0, 1, 2),
            timeout=200,
            after=clean_run_agrees(
                ["run", "s.yaml", "--out", "o", "--no-video", "-q"],
                [one_mesh_robot(), then(one_mesh_robot(), lambda d: write(d / "robot.urdf", longer))],
                ("trajectory.csv", "summary.json", "capsules.yaml"),
                "o/m",
            ),
        )
    )
    return out


def frames17_attempts() -> list[Attempt]:
    """Budgets decided before solving held to what the run then does: for paths of every kind near
    the frame budget (an arc, a polyline, text, a line at a tiny speed), ``validate``'s verdict (kept
    in said.txt) and ``run``'s agree: validate ok -> the run is not refused for its frames and has at
    most 1,000,000; validate refused -> the run is refused the same way, before solving."""
    k = "frames17"
    out: list[Attempt] = []
    head = "version: 1\nname: p\narm: {links: [1, 1, 1], axes: [z, y, y]}\nrender: {size: [160, 90], fps: FPS}\nsolver: {path_tolerance: TOL}\ngoals:\n"
    paths = {
        "an arc": "  - path: {arc: {center: [1, 0, 1], radius: 0.3, normal: [1, 0, 0], from: [1, 0.3, 1], angle: 300}}\n    speed: SPEED\n",
        "a polyline of 50 corners": "  - path: {polyline: ["
        + ", ".join(f"[1, {0.5 - i / 50:.3f}, {1 + 0.1 * (i % 2)}]" for i in range(50))
        + "]}\n    speed: SPEED\n",
        "a text of 8 letters": '  - path: {text: {string: "armanim!", origin: [1, -0.5, 1], height: 0.1, right: [0, 1, 0], up: [0, 0, 1]}}\n    speed: SPEED\n',
        "a line": "  - path: {line: [[1, 0.5, 1], [1, -0.5, 1]]}\n    speed: SPEED\n",
    }
    cases = [
        ("1e-6", "0.5", "30"),
        ("2e-6", "0.5", "30"),
        ("1e-4", "1e-4", "30"),
        ("1e-3", "3e-5", "10"),
        ("5e-6", "0.05", "90"),
    ]
    for label, goal in paths.items():
        for tol, speed, fps in cases:
            text = (head + goal).replace("TOL", tol).replace("SPEED", speed).replace("FPS", fps)
            out.append(
                Attempt(
                    k,
                    f"validate and run agree: {label}, path_tolerance {tol}, speed {speed}, {fps} fps",
                    ["run", "s.yaml", "--out", "o", "--no-video", "-q"],
                    then(tiny_scene(text=text), said_to_file("validate", "s.yaml")),
                    (0, 1, 2),
                    timeout=400,
                    after=validate_and_run_agree,
                )
            )
    return out


def validate_and_run_agree(d: Path) -> list[str]:
    """Check: validate's verdict (said.txt) and the run's (the attempt's own exit and outputs) agree."""
    import json as _json

    said = (d / "said.txt").read_text() if (d / "said.txt").exists() else ""
    validate_ok = (
        said.strip().endswith("ok") or re.search(r"\bok\b", said.splitlines()[-1] if said.strip() else "") is not None
    )
    ran = (d / "o/p/summary.json").is_file()
    problems = []
    if validate_ok and not ran:
        problems.append(f"validate said ok, and the run made no run folder (validate: {said.strip()[-160:]!r})")
    if not validate_ok and ran:
        problems.append(f"validate refused ({said.strip()[-200:]!r}) and the run ran")
    if ran:
        frames = _json.loads((d / "o/p/summary.json").read_text())["totals"]["frames"]
        if frames > 1_000_000:
            problems.append(f"the run has {frames:,} frames, past the 1,000,000 budget")
    return problems


def ro17_attempts() -> list[Attempt]:
    """Read-only file systems (a tmpfs remounted ``ro``, a bind mount ``ro``: EROFS, which root meets
    too, where campaign 16's modes needed a user who is not root) under --out, run folders, numba's
    cache, the capsules' cache, TMPDIR and HOME."""
    k = "ro17"
    out: list[Attempt] = []
    erofs = r"(?i)read-only"
    moveit = mine("w.scene", "w\n* b\n1\nbox\n0.1 0.1 0.1\n1 1 1\n0 0 0 1\n0 0 0 0\n.\n")
    with_run = lambda d: finished_run(d)  # noqa: E731
    # fmt: off
    writers: list[tuple[str, list[str], Callable[[Path], None], str, tuple[str, ...]]] = [
        ("run --out an empty read-only file system", ["run", "s.yaml", "--out", "ro", "--no-video", "-q"], then(tiny_scene(), read_only_disk("ro")), "ro", ()),
        ("run with video --out a read-only file system holding the previous run", ["run", "s.yaml", "--out", "ro", "-q"], then(tiny_scene(), read_only_disk("ro", with_run, lambda d: shutil.copytree(d / "o/tiny", d / "ro/tiny"))), "ro", ("ro",)),
        ("a batch of two --jobs 2 --out a read-only file system", ["run", "s.yaml", "a.yaml", "--out", "ro", "--no-video", "-q", "--jobs", "2"], then(tiny_scene(), tiny_scene("a.yaml", OTHER), read_only_disk("ro")), "ro", ()),
        ("sweep --out a read-only file system", ["sweep", "s.yaml", "--set", "solver.step=0.1,0.2", "--out", "ro", "-q", "--jobs", "1"], then(tiny_scene(), read_only_disk("ro")), "ro", ()),
        ("render of a run on a read-only file system (into its folder)", ["render", "ro/tiny", "--size", "64x36"], then(read_only_disk("ro", with_run, lambda d: shutil.copytree(d / "o/tiny", d / "ro/tiny"))), "ro", ("ro",)),
        ("view of a run on a read-only file system (into its folder)", ["view", "ro/tiny"], then(read_only_disk("ro", with_run, lambda d: shutil.copytree(d / "o/tiny", d / "ro/tiny"))), "ro", ("ro",)),
        ("export of a run on a read-only file system (into its folder)", ["export", "ro/tiny"], then(read_only_disk("ro", with_run, lambda d: shutil.copytree(d / "o/tiny", d / "ro/tiny"))), "ro", ("ro",)),
        ("export --out onto a read-only file system", ["export", "o/tiny", "--out", "ro/e.json"], then(with_run, read_only_disk("ro")), "ro", ()),
        ("render --out onto a read-only file system", ["render", "o/tiny", "--out", "ro", "--size", "64x36"], then(with_run, read_only_disk("ro")), "ro", ()),
        ("check --update --golden on a read-only file system holding a pair", ["check", "s.yaml", "--golden", "ro", "--update", "-q"], then(tiny_scene(), read_only_disk("ro", lambda d: armanim_in(d, "check", "s.yaml", "--golden", "ro", "--update", "-q"))), "ro", ("ro",)),
        ("import moveit --out onto a read-only file system", ["import", "moveit", "w.scene", "--robot", "panda", "--out", "ro/m.yaml"], then(moveit, read_only_disk("ro")), "ro", ()),
        ("schema --out onto a read-only file system", ["schema", "--out", "ro/s.json"], read_only_disk("ro"), "ro", ()),
        ("fk --png onto a read-only file system", ["fk", "--links", "1,1", "--angles", "10,20", "--png", "ro/p.png"], read_only_disk("ro"), "ro", ()),
        ("run --out a folder bind-mounted read-only on itself, holding the previous run", ["run", "s.yaml", "--out", "o", "--no-video", "-q"], then(with_run, bind_read_only("o")), "o", ("o",)),
    ]
    # fmt: on
    for label, args, setup, where, keep in writers:
        out.append(
            Attempt(
                k,
                label,
                args,
                setup,
                (3,),
                message=erofs if "render --out" not in label else r"(?i)read-only|mount point",
                keep=keep,
                timeout=300,
                litter_in=(where, "."),
                after=None if keep else nothing_made(where),
            )
        )
    # caches and homes on a read-only file system: the command goes on, with the clean run's answer
    for label, env, setup in [
        ("NUMBA_CACHE_DIR on an empty read-only file system", {"NUMBA_CACHE_DIR": "{d}/ro"}, read_only_disk("ro")),
        (
            "NUMBA_CACHE_DIR a warmed cache on a read-only file system",
            {"NUMBA_CACHE_DIR": "{d}/ro/nc"},
            read_only_disk("ro", warm_cache_copy("ro/nc"), kilobytes=262144),
        ),
        ("TMPDIR on a read-only file system (with video)", {"TMPDIR": "{d}/ro"}, read_only_disk("ro")),
        ("HOME on a read-only file system (matplotlib's and numba's caches)", {"HOME": "{d}/ro"}, read_only_disk("ro")),
    ]:
        video = "video" in label
        args = ["run", "s.yaml", "--out", "o", "-q"] + ([] if video else ["--no-video"])
        out.append(
            Attempt(
                k,
                f"run, {label}: the clean run's answer",
                args,
                then(tiny_scene(), setup),
                (0,),
                env=env,
                timeout=900,
                litter_in=("o", "ro"),
                after=same_as_clean(),
            )
        )
    out.append(
        Attempt(
            k,
            "run of a URDF robot, ARMANIM_CACHE_DIR on a read-only file system: the clean fit",
            ["run", "s.yaml", "--out", "o", "--no-video", "-q"],
            then(one_mesh_robot(), read_only_disk("ro")),
            (0,),
            env={"ARMANIM_CACHE_DIR": "{d}/ro"},
            timeout=300,
            after=clean_run_agrees(
                ["run", "s.yaml", "--out", "o", "--no-video", "-q"],
                [one_mesh_robot()],
                ("trajectory.csv", "capsules.yaml"),
                "o/m",
            ),
        )
    )
    return out


def lock17_attempts() -> list[Attempt]:
    """The cross-process compile lock (``arm/kernel.py`` ``held_alone``, ``lock_beside``) and
    ``warm --jobs N``: lock files made FIFOs, links to the user's file, folders; every lock held by
    another process; a holder killed mid-compile; two ``warm --jobs 2`` at once; ``warm``
    interrupted. Each on its own copy of the warmed cache or a cold one, held to a clean run's bytes."""
    k = "lock17"
    out: list[Attempt] = []
    nc = {"NUMBA_CACHE_DIR": "{d}/nc"}
    run = ["run", "s.yaml", "--out", "o", "--no-video", "-q"]
    for label, make, _keep in [
        ("a FIFO", lambda p: os.mkfifo(p), ()),
        (
            "a link to the user's file",
            lambda p: os.symlink(next(a for a in p.parents if (a / "mine.txt").exists()) / "mine.txt", p),
            (),
        ),
        ("a folder", lambda p: p.mkdir(), ()),
        ("a file at mode 000", lambda p: (p.write_text(""), p.chmod(0)), ()),
    ]:
        out.append(
            Attempt(
                k,
                f"run on a warmed cache, every compile lock {label}: the clean run's answer",
                run,
                then(tiny_scene(), mine(), warm_cache_copy(), each_lock("nc", make)),
                (0,),
                env=dict(nc),
                keep=("mine.txt",),
                timeout=300,
                after=same_as_clean(),
            )
        )

    def user_link(d: Path) -> None:
        for lock in sorted((d / "nc").rglob("*.lock")):
            lock.unlink()
            os.symlink(d / "mine.txt", lock)

    out.append(
        Attempt(
            k,
            "run on a cold cache, every lock path a link to the user's file: the file kept, the clean answer",
            run,
            then(
                tiny_scene(),
                mine(),
                warm_cache_copy(),
                user_link,
                lambda d: [p.unlink() for p in (d / "nc").rglob("*") if p.suffix in (".nbi", ".nbc")],
            ),
            (0,),
            env=dict(nc),
            keep=("mine.txt",),
            timeout=900,
            after=same_as_clean(),
        )
    )
    out.append(
        Attempt(
            k,
            "run on a warmed cache while another process holds every compile lock: no silent wait",
            run,
            then(tiny_scene(), warm_cache_copy(), locks_held("nc")),
            (0,),
            env=dict(nc),
            timeout=120,
            after=same_as_clean(),
        )
    )
    out.append(
        Attempt(
            k,
            "run on a cold cache while another process holds every compile lock: says it waits, or goes on",
            ["run", "s.yaml", "--out", "o", "--no-video"],
            then(
                tiny_scene(),
                warm_cache_copy(),
                lambda d: [p.unlink() for p in (d / "nc").rglob("*") if p.suffix in (".nbi", ".nbc")],
                locks_held("nc"),
            ),
            (0,),
            env=dict(nc),
            timeout=1000,  # the first run's 300 s: the fix waits at most 600 s in all, saying so, then compiles
            message=r"waiting for another armanim process compiling the same code",
            after=same_as_clean(),
        )
    )
    out.append(
        Attempt(
            k,
            "Ctrl-C at 4 s of a run on a cold cache waiting on a held compile lock: exit 130 at once",
            run,
            then(
                tiny_scene(),
                warm_cache_copy(),
                lambda d: [p.unlink() for p in (d / "nc").rglob("*") if p.suffix in (".nbi", ".nbc")],
                locks_held("nc"),
            ),
            (130,),
            env=dict(nc),
            timeout=30,
            interrupt=(4.0, "SIGINT"),
            litter_in=("o", "."),
            after=nothing_made("o"),
        )
    )
    out.append(
        Attempt(
            k,
            "a warm of a cold cache killed (SIGKILL) at 20 s, then a run: the clean run's answer",
            run,
            then(tiny_scene(), armanim_killed_at(20, "warm", "-q", env=nc)),
            (0,),
            env=dict(nc),
            timeout=900,
            after=same_as_clean(),
        )
    )
    out.append(
        warm_interrupted(
            k,
            "warm --jobs 2 of a cold cache, SIGINT at 15 s: exit 130, nothing left running, then a run: the clean answer",
            (15.0, "SIGINT"),
            nc,
        )
    )
    out.append(
        Attempt(
            k,
            "two warm --jobs 2 at once on one cold cache: both end 0, then a run compiles nothing and gives the clean answer",
            ["warm", "--jobs", "2", "-q"],
            then(
                tiny_scene(),
                lambda d: (d / "nc").mkdir(),
                lambda d: background(
                    sys.executable, "-m", "armanim", "warm", "--jobs", "2", "-q", env={"NUMBA_CACHE_DIR": str(d / "nc")}
                ),
            ),
            (0,),
            env=dict(nc),
            timeout=1200,
            after=same_as_clean_after(nc, compiles=False),
        )
    )
    return out


def warm_interrupted(
    k: str, what: str, interrupt: tuple[float, str], env: dict, *, usable_after: bool = True
) -> Attempt:
    """``warm --jobs 2`` on a cold cache (``env``'s ``NUMBA_CACHE_DIR``) stopped by ``interrupt`` (seconds,
    signal): exit 130, nothing it started still running 15 s later and, with ``usable_after``, a run on
    that cache afterwards gives the clean run's bytes."""
    return Attempt(
        k,
        what,
        ["warm", "--jobs", "2"],
        tiny_scene(),
        (130,),
        env=dict(env),
        timeout=120,
        interrupt=interrupt,
        linger=15,
        after=same_as_clean_after(env) if usable_after else None,
    )


def same_as_clean_after(env: dict, compiles: bool = True) -> Callable[[Path], list[str]]:
    """Check: a run with ``env`` after the attempt (its cache as the attempt left it) gives the clean
    run's trajectory and summary; with ``compiles=False`` it must not compile (its time line)."""

    def check(d: Path) -> list[str]:
        done = subprocess.run(
            [sys.executable, "-m", "armanim", "run", "s.yaml", "--out", "after", "--no-video"],
            cwd=d,
            env={**os.environ, "PYTHONPATH": str(SRC), **{k: v.replace("{d}", str(d)) for k, v in env.items()}},
            capture_output=True,
            text=True,
            timeout=900,
        )
        if done.returncode != 0:
            return [f"the run after: exit {done.returncode}: {(done.stdout + done.stderr).strip()[-300:]}"]
        problems = same_as_clean("after/tiny")(d)
        if not compiles and "compiled" in done.stdout + done.stderr:
            problems.append(
                "the run after two finished warms compiled again: "
                + [line for line in (done.stdout + done.stderr).splitlines() if "compiled" in line][0][:200]
            )
        return problems

    return check


def dask17_attempts() -> list[Attempt]:
    """Dask schedulers that are wrong, silent, without workers, or dying mid-run (``--scheduler``,
    ARMANIM_SCHEDULER): a clear message, docs/scale-out.md's exit code, no partial outputs, no hang."""
    k = "dask17"
    out: list[Attempt] = []
    two = ["run", "s.yaml", "a.yaml", "--out", "o", "--no-video", "-q"]
    scenes = then(tiny_scene(), tiny_scene("a.yaml", OTHER))
    for label, answer in [
        ("accepts and never answers", "silent"),
        ("answers HTTP 400 and hangs up", "HTTP/1.1 400 Bad Request\\r\\n\\r\\n"),
        ("sends 100 KB of zeros and hangs up", "\\x00" * 100),
    ]:
        name = f"a batch with a scheduler address whose server {label}"
        port = port_of(name)
        out.append(
            Attempt(
                k,
                name,
                [*two, "--scheduler", f"tcp://127.0.0.1:{port}"],
                then(scenes, fake_server(port, answer)),
                (2,),
                message=r"--scheduler",
                timeout=60,
                litter_in=("o", "."),
                after=nothing_made("o"),
            )
        )
    for label, address in [
        ("tls:// to a plain scheduler's port", "tls://127.0.0.1:PORT"),
        ("ws:// to a plain scheduler", "ws://127.0.0.1:PORT"),
        ("inproc://nowhere", "inproc://nowhere"),
        ("tcp://127.0.0.1:0", "tcp://127.0.0.1:0"),
        ("tcp://256.1.1.1:8786", "tcp://256.1.1.1:8786"),
    ]:
        name = f"a batch, --scheduler {label}"
        port = port_of(name)
        setup = then(scenes, dask_cluster(port, workers=0)) if "PORT" in address else scenes
        out.append(
            Attempt(
                k,
                name,
                [*two, "--scheduler", address.replace("PORT", str(port))],
                setup,
                (2,),
                message=r"--scheduler",
                timeout=60,
                litter_in=("o", "."),
                after=nothing_made("o"),
            )
        )
    name = "a batch on a scheduler with no workers: no silent wait for ever"
    port = port_of(name)
    out.append(
        Attempt(
            k,
            name,
            [*two, "--scheduler", f"tcp://127.0.0.1:{port}"],
            then(scenes, dask_cluster(port, workers=0)),
            (2, 3),
            message=r"(?i)worker",
            timeout=150,
            litter_in=("o", "."),
        )
    )
    name = "sweep with ARMANIM_SCHEDULER a scheduler killed (SIGKILL) 3 s into the sweep"
    port = port_of(name)
    out.append(
        Attempt(
            k,
            name,
            ["sweep", "s.yaml", "--set", "render.fps=10,20,30,40", "--out", "o", "-q"],
            then(tiny_scene(), dask_cluster(port, 1, kill_scheduler_at=3)),
            (2, 3),
            env={"ARMANIM_SCHEDULER": f"tcp://127.0.0.1:{port}"},
            timeout=200,
            message=r"(?i)scheduler|lost|connect",
            litter_in=("o", "."),
        )
    )
    name = "a batch with video on a scheduler killed (SIGKILL) 4 s in"
    port = port_of(name)
    out.append(
        Attempt(
            k,
            name,
            ["run", "s.yaml", "a.yaml", "--out", "o", "-q", "--scheduler", f"tcp://127.0.0.1:{port}"],
            then(scenes, dask_cluster(port, 1, kill_scheduler_at=4)),
            (2, 3),
            timeout=200,
            message=r"(?i)scheduler|lost|connect",
            litter_in=("o", "."),
        )
    )
    name = "a batch whose only worker is killed (SIGKILL) 3 s in, none left: no silent wait for ever"
    port = port_of(name)
    out.append(
        Attempt(
            k,
            name,
            [*two, "--scheduler", f"tcp://127.0.0.1:{port}"],
            then(scenes, dask_cluster(port, 1, kill_worker_at=3)),
            (0, 2, 3),
            timeout=200,
            litter_in=("o", "."),
        )
    )
    name = "Ctrl-C at 5 s of a batch on a scheduler: exit 130, no partial outputs"
    port = port_of(name)
    out.append(
        Attempt(
            k,
            name,
            ["run", "s.yaml", "a.yaml", "--out", "o", "-q", "--scheduler", f"tcp://127.0.0.1:{port}"],
            then(scenes, dask_cluster(port, 1)),
            (130,),
            timeout=60,
            interrupt=(5.0, "SIGINT"),
            litter_in=("o", "."),
        )
    )
    out.append(
        Attempt(
            k,
            "SIGTERM at 6 s of a --scheduler local --jobs 2 batch: exit 130, its cluster gone 15 s later",
            ["run", "s.yaml", "a.yaml", "--out", "o", "-q", "--scheduler", "local", "--jobs", "2"],
            scenes,
            (130,),
            timeout=90,
            interrupt=(6.0, "SIGTERM"),
            linger=15,
            litter_in=("o", "."),
        )
    )
    out.append(
        Attempt(
            k,
            "SIGTERM at 3 s while connecting to a silent scheduler: exit 130 before its 10 s",
            [*two, "--scheduler", "tcp://127.0.0.1:PORTX"],
            scenes,
            (130,),
            timeout=9,
            interrupt=(3.0, "SIGTERM"),
            litter_in=("o", "."),
        )
    )
    last = out[-1]
    port = port_of(last.name)
    last.args = [a.replace("PORTX", str(port)) for a in last.args]
    last.setup = then(scenes, fake_server(port))
    name = "a batch on a live scheduler and worker: the local batch's bytes"
    port = port_of(name)
    out.append(
        Attempt(
            k,
            name,
            [*two, "--scheduler", f"tcp://127.0.0.1:{port}"],
            then(
                scenes, dask_cluster(port, 1), lambda d: armanim_in(d, *two[:4], "p", "--no-video", "-q", "--jobs", "1")
            ),
            (0,),
            timeout=200,
            after=same_bytes(
                ("o/tiny/trajectory.csv", "p/tiny/trajectory.csv"), ("o/other/summary.json", "p/other/summary.json")
            ),
        )
    )
    return out


def env17_attempts() -> list[Attempt]:
    """The environment: a terminal of 20 columns for every command's help and tables; standard
    output closed, a full device, a reader gone after one line, a reader that never reads; file
    names that are not UTF-8 under LANG=C; HOME empty."""
    k = "env17"
    out: list[Attempt] = []
    commands = [
        [],
        ["fk"],
        ["ik"],
        ["validate"],
        ["schema"],
        ["robots"],
        ["run"],
        ["render"],
        ["view"],
        ["export"],
        ["sweep"],
        ["compare"],
        ["check"],
        ["warm"],
        ["import", "moveit"],
    ]
    for command in commands:
        out.append(
            Attempt(
                k,
                f"armanim {' '.join(command)} --help at COLUMNS=20: every word of the wide help",
                ["validate", "s.yaml"],
                then(tiny_scene(), said_to_file(*command, "--help", env={"COLUMNS": "20"})),
                (0,),
                timeout=120,
                after=help_words_kept(*command),
            )
        )
    # the tables at 20 columns: the run's headline and table, a batch's and a sweep's, the robots list
    out.append(
        Attempt(
            k,
            "run at COLUMNS=20: its headline and goal table say what summary.json says",
            ["validate", "s.yaml"],
            then(tiny_scene(), said_to_file("run", "s.yaml", "--out", "o", "--no-video", env={"COLUMNS": "20"})),
            (0,),
            timeout=300,
            after=messages_agree(),
        )
    )
    out.append(
        Attempt(
            k,
            "robots at COLUMNS=20: every robot named whole",
            ["robots"],
            codes=(0,),
            env={"COLUMNS": "20"},
            message=r"panda.*ur5",
            timeout=60,
        )
    )
    run = ["run", "s.yaml", "--out", "o", "--no-video"]
    # standard output closed, full, gone after a line, never read
    for mode, codes, message in [
        ("closed", (0,), None),
        ("full", (3,), r"(?i)no space|disk is full"),
        ("head", (0,), None),
    ]:
        for args, setup in [
            (["--version"], None),
            (["--help"], None),
            (["run", "--help"], None),
            (["schema"], None),
            (["robots"], None),
            (["fk", "--links", "1,1", "--angles", "10,20"], None),
            (["validate", "s.yaml"], tiny_scene()),
            (run, tiny_scene()),
            (["export", "o/tiny"], finished_run),
            (["compare", "o/tiny/trajectory.csv", "o/tiny/trajectory.csv"], finished_run),
            (["sweep", "s.yaml", "--set", "solver.step=0.1,0.2", "--out", "o", "--jobs", "1"], tiny_scene()),
        ]:
            if mode == "head" and args[0] in ("--version", "export"):
                continue
            out.append(
                Attempt(
                    k,
                    f"armanim {' '.join(args[:2])} with standard output {mode}",
                    args,
                    setup or (lambda d: None),
                    codes,
                    message=message,
                    stdout=mode,
                    timeout=300,
                    after=same_as_clean() if args is run and mode != "full" else None,
                )
            )
    out.append(
        Attempt(
            k,
            "validate of 2,000 bad scenes, standard output a pipe nobody reads, SIGINT at 5 s: exit 130",
            ["validate", *[f"b{i}.yaml" for i in range(2000)]],
            lambda d: (
                [
                    write(
                        d / f"b{i}.yaml", "version: 1\nname: b\narm: {links: [1, 1, 1]}\ngoals: [[1, 1, 1]]\nbogus: 1\n"
                    )
                    for i in range(2000)
                ]
                and None
            ),
            (130,),
            stdout="stuck",
            interrupt=(5.0, "SIGINT"),
            timeout=30,
        )
    )
    # file names that are not UTF-8, under LANG=C
    latin = os.fsdecode(b"\xe9t\xe9")
    c = {"LANG": "C", "LC_ALL": "C"}
    for label, args, setup in [
        (
            "a scene file named in latin-1 bytes",
            ["run", f"{latin}.yaml", "--out", "o", "--no-video"],
            tiny_scene(f"{latin}.yaml"),
        ),
        (
            "an outputs folder named in latin-1 bytes",
            ["run", "s.yaml", "--out", f"o{latin}", "--no-video"],
            tiny_scene(),
        ),
        (
            "a batch of two, its outputs folder in latin-1 bytes (index.csv read back)",
            ["run", "s.yaml", f"{latin}.yaml", "--out", f"o{latin}", "--no-video", "-q", "--jobs", "1"],
            then(tiny_scene(), tiny_scene(f"{latin}.yaml", OTHER)),
        ),
        ("export --out a latin-1 name", ["export", "o/tiny", "--out", f"{latin}.json"], finished_run),
        (
            "a scene, its URDF and mesh in a folder named in latin-1 bytes",
            ["run", f"{latin}/s.yaml", "--out", "o", "--no-video"],
            lambda d: one_mesh_robot()(d / latin),
        ),
        ("validate of a missing scene named in latin-1 bytes", ["validate", f"{latin}-missing.yaml"], lambda d: None),
    ]:
        codes = (2,) if "missing" in label else (0, 2)
        out.append(Attempt(k, f"LANG=C, {label}", args, setup, codes, env=c, timeout=300, litter_in=("o", ".")))
    out.append(
        Attempt(
            k,
            "HOME empty (HOME=), a run with video and a URDF robot's fit",
            ["run", "s.yaml", "--out", "o", "-q"],
            one_mesh_robot(),
            (0,),
            env={"HOME": "", "XDG_CACHE_HOME": UNSET, "ARMANIM_CACHE_DIR": UNSET},
            timeout=300,
        )
    )
    return out


def signals17_attempts() -> list[Attempt]:
    """Interrupts at moments campaigns 1-16 did not reach: while ``robots --fit`` waits on nothing
    (a mesh swapped with a FIFO), while a batch waits for a scheduler's worker, during the tidy-up of
    a run replacing its folder on a bind mount, and SIGHUP to a ``warm --jobs 2``."""
    k = "signals17"
    out: list[Attempt] = []
    nc = {"NUMBA_CACHE_DIR": "{d}/nc"}
    out.append(
        warm_interrupted(
            k,
            "SIGHUP to the group at 12 s of warm --jobs 2 on a cold cache: exit 130, nothing left running, the cache usable",
            (12.0, "SIGHUPG"),
            nc,
        )
    )
    out.append(
        warm_interrupted(
            k,
            "SIGTERM to armanim alone at 12 s of warm --jobs 2 on a cold cache: its workers end with it",
            (12.0, "SIGTERM"),
            nc,
            usable_after=False,
        )
    )
    name = "SIGINT at 8 s of a batch waiting on a scheduler with no workers: exit 130"
    port = port_of(name)
    out.append(
        Attempt(
            k,
            name,
            ["run", "s.yaml", "a.yaml", "--out", "o", "-q", "--scheduler", f"tcp://127.0.0.1:{port}"],
            then(tiny_scene(), tiny_scene("a.yaml", OTHER), dask_cluster(port, workers=0)),
            (130,),
            timeout=40,
            interrupt=(8.0, "SIGINT"),
            litter_in=("o", "."),
        )
    )
    out.append(
        Attempt(
            k,
            "SIGTERM at 3 s of robots --fit, its collision mesh swapped with a FIFO every 2 ms",
            ["robots", "--fit", "robot.urdf"],
            then(
                one_mesh_robot(),
                lambda d: write(d / ".v/a", box_stl()),
                lambda d: fifo(d / ".v/b"),
                flapping("m.stl", ".v/a", ".v/b"),
            ),
            (0, 2, 130),
            timeout=30,
            interrupt=(3.0, "SIGTERM"),
        )
    )
    out.append(
        Attempt(
            k,
            "SIGINT at 1.5 s of a run replacing its folder on a read-only bind mount",
            ["run", "s.yaml", "--out", "o", "-q"],
            then(lambda d: finished_run(d), bind_read_only("o")),
            (3, 130),
            timeout=60,
            interrupt=(1.5, "SIGINT"),
            keep=("o",),
            litter_in=("o", "."),
        )
    )
    return out


def wrong17_attempts() -> list[Attempt]:
    """New draws of the random-arm oracle (rates, clock, summary) and a Dask batch's bytes."""
    return oracle_runs("wrong17", (1701, 1702, 1703, 1704), "held to the rates, the clock and the summary")


def api_snippet_check(text: str) -> None:
    """Compile every api16 snippet (a script mistake found before the campaign runs)."""
    compile(PRELUDE + text, "<api16>", "exec")


# ------------------------------------------------------------------ the eighteenth campaign, part B


def links_naming(names: list[str], where: str = "collision") -> Callable[[Path], None]:
    """Setup: robot.urdf of ``len(names)`` moving links, link i's ``where`` the mesh ``names[i]``
    (``{d}`` in a name: the attempt's folder), and s.yaml naming it."""

    def setup(d: Path) -> None:
        lines = ['<?xml version="1.0"?>', '<robot name="r">', '<link name="l0"/>']
        for i, name in enumerate(names, start=1):
            name = name.replace("{d}", str(d))
            lines.append(f'<link name="l{i}"><{where}>{mesh_tag(name)}</{where}></link>')
            lines.append(
                f'<joint name="j{i}" type="revolute"><parent link="l{i - 1}"/><child link="l{i}"/>'
                f'<origin xyz="0 0 0.1"/><axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="1" velocity="1"/></joint>'
            )
        write(d / "robot.urdf", "\n".join([*lines, "</robot>"]) + "\n")
        write(d / "s.yaml", URDF_SCENE)

    return setup


TRI_OBJ = "v 0 0 0\nv .05 0 0\nv 0 .05 0\nf 1 2 3\n"


def padded_obj_file(at: str, megabytes: int) -> Callable[[Path], None]:
    """Setup: an OBJ of one triangle and ``megabytes`` MB of comment lines at ``at``."""

    def step(d: Path) -> None:
        with open(d / at, "w") as handle:
            handle.write(TRI_OBJ)
            line = "#" + "x" * 1023 + "\n"
            for _ in range(megabytes * 1024):
                handle.write(line)

    return step


def big_text(at: str, head: str, line: str, megabytes: float, tail: str = "") -> Callable[[Path], None]:
    """Setup: ``head``, then ``line`` repeated to about ``megabytes`` MB, then ``tail``, at ``at``."""

    def step(d: Path) -> None:
        with open(d / at, "w") as handle:
            handle.write(head)
            block = line * max(1, (1 << 20) // len(line))
            for _ in range(int(megabytes)):
                handle.write(block)
            handle.write(tail)

    return step


def gltf_text(uri: str) -> str:
    """A glTF 2.0 file of one triangle whose buffer is ``uri``."""
    return (
        '{"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}], '
        '"meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}], '
        '"accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", '
        '"max": [1, 1, 0], "min": [0, 0, 0]}], "bufferViews": [{"buffer": 0, "byteLength": 36}], '
        f'"buffers": [{{"byteLength": 36, "uri": "{uri}"}}]}}'
    )


def data_uri_gltf(at: str, megabytes: int) -> Callable[[Path], None]:
    """Setup: a glTF whose buffer is a data: URI of ``megabytes`` MB of base64."""

    def step(d: Path) -> None:
        with open(d / at, "w") as handle:
            text = gltf_text("DATA")
            head, tail = text.split("DATA")
            handle.write(head + "data:application/octet-stream;base64,")
            block = "QUFB" * (1 << 18)  # 1 MB
            for _ in range(megabytes):
                handle.write(block)
            handle.write(tail)

    return step


def mesh18_attempts() -> list[Attempt]:
    """Files a mesh names, in shapes campaigns 1-17 did not try: one mesh named by five hard links or
    five spellings (read once, so under the robot's 256 MB), glTF/GLB (a format armanim does not
    read) whose buffers are a 200 MB data: URI, file://, http:// and '..' URIs, OBJ of one 60 MB
    line and of 16 million one-corner faces, degenerate faces only, the legacy 'fo' keyword, an ASCII
    STL of 'nan', a PLY or gzip under the name .stl, COLLADA cycles of two nodes through
    <library_nodes>, an external instance_geometry url to a FIFO, a scene instancing a missing
    visual_scene, and a package:// whose package folder is a link loop."""
    k = "mesh18"
    out: list[Attempt] = []
    spent = r"left to read|256 MB in all|more than the"
    fit = ["robots", "--fit", "robot.urdf"]
    viewer = ["run", "s.yaml", "--out", "o", "--no-video", "--viewer", "-q"]

    def hard_links(d: Path) -> None:
        padded_obj_file("m.obj", 60)(d)
        for i in range(1, 6):
            os.link(d / "m.obj", d / f"m{i}.obj")

    five_hard = [f"m{i}.obj" for i in range(1, 6)]
    spellings = ["m.obj", "./m.obj", ".//m.obj", "sub/../m.obj", "file://{d}/m.obj"]

    def spelled(d: Path) -> None:
        padded_obj_file("m.obj", 60)(d)
        (d / "sub").mkdir()

    # fmt: off
    out += [
        Attempt(k, "robots --fit, five links naming five hard links of one 60 MB OBJ (one file: read once, under 256 MB)", fit, then(links_naming(five_hard), hard_links), (0,), not_message=spent, timeout=300),
        Attempt(k, "run --viewer, five visuals naming five hard links of one 60 MB OBJ (read once: no link left out)", viewer, then(links_naming(five_hard, "visual"), hard_links), (0,), not_message=spent, timeout=300),
        Attempt(k, "robots --fit, one 60 MB OBJ by five spellings (m.obj, ./, .//, sub/.., file://): read once", fit, then(links_naming(spellings), spelled), (0,), not_message=spent, timeout=300),
        Attempt(k, "run --viewer, one 60 MB OBJ by five spellings as visuals: read once", viewer, then(links_naming(spellings, "visual"), spelled), (0,), not_message=spent, timeout=300),
    ]
    # fmt: on
    not_read = r"not a format armanim reads"
    gltfs = [
        ("a .gltf whose buffer is a data: URI of 200 MB of base64", "a.gltf", data_uri_gltf("a.gltf", 200)),
        (
            "a .gltf whose buffer uri is file:///dev/zero",
            "a.gltf",
            lambda d: write(d / "a.gltf", gltf_text("file:///dev/zero")),
        ),
        (
            "a .gltf whose buffer uri is http://127.0.0.1:9/b.bin",
            "a.gltf",
            lambda d: write(d / "a.gltf", gltf_text("http://127.0.0.1:9/b.bin")),
        ),
        (
            "a .gltf whose buffer uri is ../../../../dev/zero",
            "a.gltf",
            lambda d: write(d / "a.gltf", gltf_text("../../../../dev/zero")),
        ),
        (
            "a .glb whose buffer is a FIFO b.bin",
            "a.glb",
            then(
                lambda d: write(d / "a.glb", b"glTF\x02\0\0\0" + gltf_text("b.bin").encode()),
                lambda d: fifo(d / "b.bin"),
            ),
        ),
        ("a name a%2Estl (percent-encoded dot: not .stl)", "a%2Estl", lambda d: write(d / "a%2Estl", stl())),
    ]
    for label, name, make in gltfs:
        out.append(
            Attempt(
                k,
                f"robots --fit, collision {label}",
                fit,
                then(links_naming([name]), make),
                (2,),
                message=not_read,
                timeout=60,
            )
        )
        out.append(
            Attempt(
                k,
                f"run --viewer, visual {label}",
                viewer,
                then(links_naming([name], "visual"), make),
                (0,),
                message=not_read,
                timeout=120,
            )
        )
    bad = r"triangles|vertex|not an STL|no triangle|could not be read|cycle|instances itself|not finite"
    shapes = [
        ("an OBJ of one 60 MB 'v' line and a triangle", "a.obj", big_text("a.obj", "v", " 0", 60, "\n" + TRI_OBJ)),
        (
            "an OBJ of one 60 MB 'f' line (30 million corners)",
            "a.obj",
            big_text("a.obj", TRI_OBJ + "f", " 1", 60, "\n"),
        ),
        (
            "an OBJ of 60 MB of 'f 1' lines (15 million faces of one corner)",
            "a.obj",
            big_text("a.obj", TRI_OBJ, "f 1\n", 60),
        ),
        ("an OBJ of 60 MB of 'f 1 2' lines (faces of two corners)", "a.obj", big_text("a.obj", TRI_OBJ, "f 1 2\n", 60)),
        (
            "an OBJ of degenerate faces only (f 1 1 1, f 2 2 2)",
            "a.obj",
            lambda d: write(d / "a.obj", "v 0 0 0\nv .05 0 0\nv 0 .05 0\nf 1 1 1\nf 2 2 2\nf 1 2 1\n"),
        ),
        (
            "an OBJ of faces by the legacy 'fo' keyword only",
            "a.obj",
            lambda d: write(d / "a.obj", "v 0 0 0\nv .05 0 0\nv 0 .05 0\nfo 1 2 3\n"),
        ),
        (
            "an OBJ of 'v nan nan nan' and 'v 1e309 0 0' corners beside one good triangle",
            "a.obj",
            lambda d: write(d / "a.obj", TRI_OBJ + "v nan nan nan\nv 1e309 0 0\nf 4 5 1\n"),
        ),
        (
            "an ASCII STL of 'nan' corners only",
            "a.stl",
            lambda d: write(d / "a.stl", ascii_stl([[float("nan")] * 3] * 3)),
        ),
        (
            "a PLY file under the name .stl",
            "a.stl",
            lambda d: write(
                d / "a.stl",
                "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
            ),
        ),
        (
            "a gzip of a binary STL under the name .stl",
            "a.stl",
            lambda d: write(d / "a.stl", __import__("gzip").compress(stl(2))),
        ),
        (
            "a binary STL of 50,000 triangles all degenerate (three equal corners)",
            "a.stl",
            lambda d: write(d / "a.stl", stl_corners([[0.01, 0.02, 0.03]] * 150_000)),
        ),
        (
            "a COLLADA of two library_nodes instancing each other (a cycle of two)",
            "c.dae",
            lambda d: write(
                d / "c.dae",
                dae(1)
                .replace(
                    "<library_visual_scenes>",
                    '<library_nodes><node id="m1"><instance_node url="#m2"/><instance_geometry url="#g0"/></node><node id="m2"><instance_node url="#m1"/></node></library_nodes><library_visual_scenes>',
                )
                .replace(
                    '<node id="n0"><instance_geometry url="#g0"/></node>',
                    '<node id="n0"><instance_node url="#m1"/></node>',
                ),
            ),
        ),
        (
            "a COLLADA node nesting a child node that instances its grandparent",
            "c.dae",
            lambda d: write(
                d / "c.dae",
                dae(1)
                .replace(
                    "<library_visual_scenes>",
                    '<library_nodes><node id="m1"><instance_geometry url="#g0"/><node id="m1c"><node id="m1cc"><instance_node url="#m1"/></node></node></node></library_nodes><library_visual_scenes>',
                )
                .replace(
                    '<node id="n0"><instance_geometry url="#g0"/></node>',
                    '<node id="n0"><instance_node url="#m1"/></node>',
                ),
            ),
        ),
        (
            "a COLLADA whose instance_geometry url is other.dae#g0, a FIFO",
            "c.dae",
            then(
                lambda d: write(
                    d / "c.dae",
                    dae(1).replace(
                        '<node id="n0"><instance_geometry url="#g0"/></node>',
                        '<node id="n0"><instance_geometry url="other.dae#g0"/><instance_geometry url="#g0"/></node>',
                    ),
                ),
                lambda d: fifo(d / "other.dae"),
            ),
        ),
        (
            "a COLLADA whose scene instances a visual_scene that is not there",
            "c.dae",
            lambda d: write(
                d / "c.dae",
                dae(1).replace('<instance_visual_scene url="#s"/>', '<instance_visual_scene url="#nosuch"/>'),
            ),
        ),
        (
            "a COLLADA of unit meter='1e300'",
            "c.dae",
            lambda d: write(d / "c.dae", dae(1).replace('<unit meter="1"/>', '<unit meter="1e300"/>')),
        ),
        (
            "a COLLADA float_array count of 10^12 over nine numbers",
            "c.dae",
            lambda d: write(d / "c.dae", dae(1).replace('count="9"', 'count="1000000000000"')),
        ),
        (
            "a COLLADA accessor stride 2 over triples",
            "c.dae",
            lambda d: write(d / "c.dae", dae(1).replace('stride="3"', 'stride="2"')),
        ),
    ]
    for label, name, make in shapes:
        out.append(
            Attempt(
                k,
                f"robots --fit, collision {label}",
                fit,
                then(links_naming([name]), make),
                (0, 2),
                message_if_2=bad,
                timeout=240,
            )
        )
        out.append(
            Attempt(
                k,
                f"run --viewer, visual {label}",
                viewer,
                then(links_naming([name], "visual"), make),
                (0,),
                timeout=300,
            )
        )

    def loop_package(d: Path) -> None:
        (d / "pk").mkdir()
        os.symlink("r", d / "pk" / "r")  # pk/r -> pk/r: a link loop

    loop_urdf = ["package://r/a.stl"]
    out.append(
        Attempt(
            k,
            "robots --fit --package-dir pk, collision package://r/a.stl, pk/r a link to itself (a loop)",
            [*fit, "--package-dir", "pk"],
            then(links_naming(loop_urdf), loop_package),
            (2,),
            message=r"not found|a\.stl",
            timeout=60,
        )
    )
    out.append(
        Attempt(
            k,
            "run --viewer, arm.package_dirs [pk], visual package://r/a.stl, pk/r a link to itself (a loop)",
            viewer,
            then(
                links_naming(loop_urdf, "visual"),
                loop_package,
                lambda d: write(
                    d / "s.yaml", URDF_SCENE.replace("{urdf: robot.urdf}", "{urdf: robot.urdf, package_dirs: [pk]}")
                ),
            ),
            (0,),
            message=r"not found",
            timeout=120,
        )
    )
    # variants of what the first pass found: corners that are not finite, kept beside good triangles
    nan_obj = TRI_OBJ + "v nan nan nan\nv 1e309 0 0\nf 4 5 1\n"
    far_obj = TRI_OBJ + "v 1e300 0 0\nf 1 2 4\n"
    tool_scene = URDF_SCENE.replace("{urdf: robot.urdf}", "{urdf: robot.urdf, tool: {mesh: t.obj}}")  # a URDF arm's
    out += [
        Attempt(
            k,
            "run --viewer, arm.tool.mesh an OBJ with NaN and 1e309 corners beside a good triangle",
            viewer,
            then(links_naming(["m.stl"], "visual"), tiny_scene(text=tool_scene), lambda d: write(d / "t.obj", nan_obj)),
            (0,),
            timeout=120,
        ),
        Attempt(
            k,
            "fk --png, visual an OBJ with NaN and 1e309 corners beside a good triangle",
            ["fk", "--scene", "s.yaml", "--angles", "0", "--png", "p.png"],
            then(links_naming(["a.obj"], "visual"), lambda d: write(d / "a.obj", nan_obj)),
            (0,),
            timeout=120,
        ),
        Attempt(
            k,
            "run --viewer, visual an OBJ of a 1e300 corner under scale 1e9 (an infinite corner)",
            viewer,
            then(
                links_naming(["a.obj"], "visual"),
                lambda d: write(d / "a.obj", far_obj),
                lambda d: write(
                    d / "robot.urdf",
                    (d / "robot.urdf").read_text().replace('filename="a.obj"', 'filename="a.obj" scale="1e9 1e9 1e9"'),
                ),
            ),
            (0,),
            timeout=120,
        ),
        Attempt(
            k,
            "view of a run, visual an OBJ with NaN corners beside a good triangle",
            ["view", "o/m", "--out", "v.html"],
            then(
                links_naming(["a.obj"], "visual"),
                lambda d: write(d / "a.obj", nan_obj),
                lambda d: armanim_in(d, "run", "s.yaml", "--out", "o", "--no-video", "-q"),
            ),
            (0,),
            timeout=120,
        ),
    ]
    return out


def frames18_attempts() -> list[Attempt]:
    """Frame budgets whose SUM over many goals crosses the 1,000,000 limit while each goal is far
    under it (holds at 240 fps, max_frames_per_goal x goals, several slow paths, approach and
    retreat lines at a fine path tolerance), and fps 1 and 240 (render.fps's most; 1000 is refused
    at its field): validate's verdict and run's agree (:func:`validate_and_run_agree`)."""
    k = "frames18"
    out: list[Attempt] = []
    head = "version: 1\nname: p\narm: {links: [1, 1, 1], axes: [z, y, y]}\nrender: {size: [160, 90], fps: FPS}\nsolver: {SOLVER}\ngoals:\n"
    point = "  - {position: [1, 0.2, 1], hold: HOLD}\n  - {position: [1, -0.2, 1], hold: HOLD}\n"
    cases = [
        (
            "ten goals held 414.6 s at 240 fps (each 100,104 frames: 1,001,041 in all)",
            "240",
            "max_frames_per_goal: 600",
            point * 5,
            "414.6",
        ),
        (
            "nine goals held 414 s at 240 fps (899,641 in all: under the limit)",
            "240",
            "max_frames_per_goal: 600",
            point * 4 + "  - {position: [1, 0.2, 1], hold: HOLD}\n",
            "414",
        ),
        (
            "ten goals of max_frames_per_goal 100,000 (1,000,001 in all)",
            "30",
            "max_frames_per_goal: 100000",
            point * 5,
            "0",
        ),
        (
            "nine goals of max_frames_per_goal 100,000 and holds of 100 s at 30 fps",
            "30",
            "max_frames_per_goal: 100000",
            point * 4 + "  - {position: [1, 0.2, 1], hold: HOLD}\n",
            "100",
        ),
        (
            "1,000 goals (the most) of max_frames_per_goal 1,000 at fps 1 (1,000,001 in all)",
            "1",
            "max_frames_per_goal: 1000",
            point * 500,
            "0",
        ),
        (
            "400 goals held 1,000 s at fps 1 of max_frames_per_goal 1,500",
            "1",
            "max_frames_per_goal: 1500",
            point * 200,
            "1000",
        ),
    ]
    for label, fps, solver, goals, hold in cases:
        text = head.replace("FPS", fps).replace("SOLVER", solver) + goals.replace("HOLD", hold)
        out.append(
            Attempt(
                k,
                f"validate and run agree: {label}",
                ["run", "s.yaml", "--out", "o", "--no-video", "-q"],
                then(tiny_scene(text=text), said_to_file("validate", "s.yaml")),
                (0, 1, 2),
                timeout=600,
                after=validate_and_run_agree,
            )
        )
    line = "  - path: {line: [[1, 0.3, 1], [1, -0.3, 1]]}\n    speed: SPEED\n"
    for label, fps, tol, speed, count in [
        ("five lines each at 0.6/1e-4 x 30 = 180,000 frames (900,000 and the splits)", "30", "1e-3", "1e-4", 5),
        ("two lines at fps 240 and speed 0.0048 (962,373 counted: under the limit)", "240", "1e-3", "0.0048", 2),
        ("four lines at fps 240 and speed 0.0048", "240", "1e-3", "0.0048", 4),
        ("eight lines at fps 1 and speed 1e-5", "1", "1e-3", "1e-5", 8),
        ("six lines at path_tolerance 2e-6, speed 0.5, 30 fps", "30", "2e-6", "0.5", 6),
    ]:
        text = (
            head.replace("FPS", fps).replace("SOLVER", f"path_tolerance: {tol}") + line.replace("SPEED", speed) * count
        )
        out.append(
            Attempt(
                k,
                f"validate and run agree: {label}",
                ["run", "s.yaml", "--out", "o", "--no-video", "-q"],
                then(tiny_scene(text=text), said_to_file("validate", "s.yaml")),
                (0, 1, 2),
                timeout=600,
                after=validate_and_run_agree,
            )
        )
    lines = {
        "an approach of 1 m at path_tolerance 1e-9": "  - position: [1, 0, 1]\n    approach: {distance: 1, axis: [0, 0, -1], speed: 0.5}\n",
        "a retreat of 1 m at path_tolerance 1e-9": "  - position: [1, 0, 1]\n    retreat: {distance: 1, axis: [0, 0, 1], speed: 0.5}\n",
        "an approach of 0.3 m at speed 1e-6 (30 fps: 9,000,000 frames)": "  - position: [1, 0, 1]\n    approach: {distance: 0.3, axis: [0, 0, -1], speed: 1e-6}\n",
        "four approaches of 0.2 m at speed 0.0025 (19,200 frames each) at 240 fps": "  - position: [1, 0, 1]\n    approach: {distance: 0.2, axis: [0, 0, -1], speed: 0.0025}\n"
        * 4,
    }
    for label, goal in lines.items():
        tol = "1e-9" if "1e-9" in label else "1e-3"
        fps = "240" if "240 fps" in label else "30"
        text = head.replace("FPS", fps).replace("SOLVER", f"path_tolerance: {tol}") + goal
        out.append(
            Attempt(
                k,
                f"validate and run agree: {label}",
                ["run", "s.yaml", "--out", "o", "--no-video", "-q"],
                then(tiny_scene(text=text), said_to_file("validate", "s.yaml")),
                (0, 1, 2),
                timeout=600,
                after=validate_and_run_agree,
            )
        )
    return out


def marker_edited(change: Callable[[dict], None]) -> Callable[[Path], None]:
    """Setup step: the run folder o/tiny's marker rewritten after ``change`` (an older armanim's)."""

    def step(d: Path) -> None:
        import json as _json

        path = d / "o/tiny/.armanim-run.json"
        data = _json.loads(path.read_text())
        change(data)
        path.write_text(_json.dumps(data, indent=2) + "\n")

    return step


def export_parses(out: str) -> Callable[[Path], list[str]]:
    """Check: when ``out`` exists it is a JointTrajectory JSON (joint_names and points)."""

    def check(d: Path) -> list[str]:
        import json as _json

        path = d / out
        if not path.exists():
            return []
        try:
            data = _json.loads(path.read_text())
        except ValueError:
            return [f"{out} is not JSON"]
        return [] if isinstance(data, dict) and "points" in str(data)[:100000] else [f"{out} has no points"]

    return check


def export18_attempts() -> list[Attempt]:
    """``export --out`` into targets campaigns 9-17 did not try (a FIFO of the user's, /dev/null, a
    name with a newline, a tab or a leading dash, a socket, a link loop, the run folder's own
    scene.yaml, a folder's name with a trailing dot), ``--format`` spellings, and exports of runs
    whose marker says an older (or odd) armanim_version."""
    k = "export18"
    out: list[Attempt] = []
    run = lambda d: finished_run(d) and None  # noqa: E731
    refused = r"export|--out|not|refus|exists|armanim"

    def unix_socket(at: str) -> Callable[[Path], None]:
        def step(d: Path) -> None:
            import socket

            sock = socket.socket(socket.AF_UNIX)
            sock.bind(str(d / at))  # left bound: a socket file on disk

        return step

    # fmt: off
    out += [
        Attempt(k, "export --out a FIFO of the user's (never opened for writing: no hang)", ["export", "o/tiny", "--out", "f.json"], then(run, lambda d: fifo(d / "f.json")), (3,), keep=("f.json",), timeout=60, message=refused),
        Attempt(k, "export --out a socket file of the user's", ["export", "o/tiny", "--out", "s.sock"], then(run, unix_socket("s.sock")), (3,), keep=("s.sock",), timeout=60),
        Attempt(k, "export --out /dev/null", ["export", "o/tiny", "--out", "/dev/null"], run, (0, 3), timeout=60, after=lambda d: [] if stat.S_ISCHR(os.stat("/dev/null").st_mode) else ["/dev/null is no longer a device"]),
        Attempt(k, "export --out a link to /dev/null", ["export", "o/tiny", "--out", "n.json"], then(run, symlink("/dev/null", "n.json")), (0, 3), keep=("n.json",), timeout=60, after=lambda d: [] if stat.S_ISCHR(os.stat("/dev/null").st_mode) else ["/dev/null is no longer a device"]),
        Attempt(k, "export --out a name with a newline (e\\n.json)", ["export", "o/tiny", "--out", "e\n.json"], run, (0, 2, 3), timeout=60, after=export_parses("e\n.json")),
        Attempt(k, "export --out a name with a tab and a leading dash (./-e\\t.json)", ["export", "o/tiny", "--out", "./-e\t.json"], run, (0, 2, 3), timeout=60, after=export_parses("-e\t.json")),
        Attempt(k, "export --out a link loop (l.json -> l.json)", ["export", "o/tiny", "--out", "l.json"], then(run, symlink("l.json", "l.json")), (2, 3), keep=("l.json",), timeout=60),
        Attempt(k, "export --out o/tiny/scene.yaml (the run's own scene copy)", ["export", "o/tiny", "--out", "o/tiny/scene.yaml"], run, (2, 3), keep=("o/tiny",), timeout=60),
        Attempt(k, "export --out the scene s.yaml (a user's YAML)", ["export", "o/tiny", "--out", "s.yaml"], run, (3,), keep=("s.yaml",), timeout=60),
        Attempt(k, "export --out 'o/tiny.' (the run folder's name and a dot)", ["export", "o/tiny", "--out", "o/tiny."], run, (0, 2, 3), keep=("o/tiny",), timeout=60, after=export_parses("o/tiny.")),
        Attempt(k, "export --out a folder e.json/ of the user's with a file inside", ["export", "o/tiny", "--out", "e.json"], then(run, mine("e.json/inside.txt")), (3,), keep=("e.json",), timeout=60),
        Attempt(k, "export --format JOINT-TRAJECTORY (capitals)", ["export", "o/tiny", "--format", "JOINT-TRAJECTORY", "--out", "e.json"], run, (0, 2), timeout=60, message_if_2=r"format", after=export_parses("e.json")),
        Attempt(k, "export --format joint_trajectory (an underscore)", ["export", "o/tiny", "--format", "joint_trajectory", "--out", "e.json"], run, (0, 2), timeout=60, message_if_2=r"format", after=export_parses("e.json")),
        Attempt(k, "export --format 'joint-trajectory ' (a trailing space)", ["export", "o/tiny", "--format", "joint-trajectory ", "--out", "e.json"], run, (0, 2), timeout=60, message_if_2=r"format", after=export_parses("e.json")),
        Attempt(k, "export --format given twice (joint-trajectory, then bogus)", ["export", "o/tiny", "--format", "joint-trajectory", "--format", "bogus", "--out", "e.json"], run, (0, 2), timeout=60, message_if_2=r"format"),
    ]
    # fmt: on
    versions = [
        ("0.0.1 (an older armanim)", lambda m: m.update(armanim_version="0.0.1")),
        ("99.0 (a newer armanim)", lambda m: m.update(armanim_version="99.0")),
        ("missing", lambda m: m.pop("armanim_version", None)),
        ("a number (1)", lambda m: m.update(armanim_version=1)),
        ("null", lambda m: m.update(armanim_version=None)),
        ("a list", lambda m: m.update(armanim_version=["0.1.0"])),
        ("10,000 characters", lambda m: m.update(armanim_version="9" * 10_000)),
    ]
    for label, change in versions:
        out.append(
            Attempt(
                k,
                f"export of a run whose marker's armanim_version is {label}",
                ["export", "o/tiny", "--out", "e.json"],
                then(run, marker_edited(change)),
                (0, 2, 3),
                keep=("o/tiny",),
                timeout=60,
                message_if_2=r"o/tiny|marker|armanim",
                after=export_parses("e.json"),
            )
        )
    out.append(
        Attempt(
            k,
            "export of a run whose summary.json says armanim_version 0.0.1 (an older armanim)",
            ["export", "o/tiny", "--out", "e.json"],
            then(
                run,
                lambda d: write(
                    d / "o/tiny/summary.json",
                    (d / "o/tiny/summary.json")
                    .read_text()
                    .replace('"armanim_version": "0.1.0"', '"armanim_version": "0.0.1"'),
                ),
            ),
            (0, 2, 3),
            timeout=60,
            after=export_parses("e.json"),
        )
    )
    out.append(
        Attempt(
            k,
            "export of a run whose marker lists no files (an older armanim's marker)",
            ["export", "o/tiny", "--out", "e.json"],
            then(run, marker_edited(lambda m: m.update(files={}))),
            (0, 2, 3),
            keep=("o/tiny",),
            timeout=60,
            after=export_parses("e.json"),
        )
    )
    # a link that loops, everywhere a command takes a path to write
    loop = lambda name: symlink(name, name)  # noqa: E731
    out += [
        Attempt(
            k,
            "run s.yaml --out l (l a link to itself)",
            ["run", "s.yaml", "--out", "l", "--no-video", "-q"],
            then(tiny_scene(), loop("l")),
            (2, 3),
            keep=("l",),
            timeout=60,
        ),
        Attempt(
            k,
            "sweep --out l (l a link to itself)",
            ["sweep", "s.yaml", "--set", "solver.step=0.1,0.2", "--out", "l", "--no-video", "-q"],
            then(tiny_scene(), loop("l")),
            (2, 3),
            keep=("l",),
            timeout=60,
        ),
        Attempt(
            k,
            "check --update --golden g (g a link to itself)",
            ["check", "s.yaml", "--update", "--golden", "g"],
            then(tiny_scene(), loop("g")),
            (2, 3),
            keep=("g",),
            timeout=60,
        ),
        Attempt(
            k,
            "check --golden g (g a link to itself: no golden there, exit 1)",
            ["check", "s.yaml", "--golden", "g"],
            then(tiny_scene(), loop("g")),
            (1, 2, 3),
            keep=("g",),
            timeout=60,
            message=r"g/tiny\.csv|g: ",
        ),
        Attempt(
            k,
            "import moveit --out l.yaml (a link to itself)",
            ["import", "moveit", "w.scene", "--robot", "panda", "--out", "l.yaml"],
            then(lambda d: write(d / "w.scene", "w\n.\n"), loop("l.yaml")),
            (2, 3),
            keep=("l.yaml",),
            timeout=60,
        ),
        Attempt(
            k,
            "fk --png l.png (a link to itself)",
            ["fk", "--angles", "0,10,20,30", "--png", "l.png"],
            loop("l.png"),
            (2, 3),
            keep=("l.png",),
            timeout=60,
        ),
        Attempt(
            k,
            "export --out o/tiny/l.json, a link to itself inside the run folder",
            ["export", "o/tiny", "--out", "o/tiny/l.json"],
            then(run, loop("o/tiny/l.json")),
            (2, 3),
            keep=("o/tiny",),
            timeout=60,
        ),
        Attempt(
            k,
            "export --out a link to a link that loops (e.json -> l -> l)",
            ["export", "o/tiny", "--out", "e.json"],
            then(run, loop("l"), symlink("l", "e.json")),
            (2, 3),
            keep=("e.json", "l"),
            timeout=60,
        ),
        Attempt(
            k,
            "export --out x/e.json, x a link to itself",
            ["export", "o/tiny", "--out", "x/e.json"],
            then(run, loop("x")),
            (2, 3),
            keep=("x",),
            timeout=60,
        ),
        Attempt(
            k,
            "view --out x/v.html, x a link to itself",
            ["view", "o/tiny", "--out", "x/v.html"],
            then(run, loop("x")),
            (2, 3),
            keep=("x",),
            timeout=60,
        ),
        Attempt(
            k,
            "import moveit --urdf robot.urdf --out x/m.yaml, x a link to itself (found after the rerun)",
            ["import", "moveit", "w.scene", "--urdf", "robot.urdf", "--tip-link", "l3", "--out", "x/m.yaml"],
            then(lambda d: write(d / "w.scene", "w\n.\n"), lambda d: write(d / "robot.urdf", urdf_text()), loop("x")),
            (2, 3),
            keep=("x",),
            timeout=60,
        ),
    ]
    return out


def signals18_attempts() -> list[Attempt]:
    """Interrupts at moments campaigns 1-17 did not reach, each held to leave nothing running
    (``linger``: ffmpeg and workers gone within 3 s) and nothing half-written: during ffmpeg's
    encoding (SIGTERM to armanim alone, SIGHUP alone), during the viewer page's write (SIGTERM alone,
    at new moments), during ``check --update`` (SIGHUP alone), during ``import moveit`` (SIGTERM to
    the group in its first 0.3 s), during a sweep's last variant and index write, and two signals
    1 ms and 10 ms apart (SIGTERM then SIGHUP, SIGINT then SIGTERM)."""
    k = "signals18"
    out: list[Attempt] = []
    video = TINY.replace(
        "[[1, 1, 1], [0.5, -1, 1]]", "[{position: [1, 1, 1], hold: 30}, {position: [0.5, -1, 1], hold: 30}]"
    ).replace("fps: 10", "fps: 30")
    tidy_run = again_tidy("run", "s.yaml", "--out", "o", "-q")
    for delay, signame in [(3.0, "SIGTERM"), (5.0, "SIGHUP"), (7.0, "SIGTERM")]:
        out.append(
            Attempt(
                k,
                f"run with video at 30 fps during encoding, {signame} to armanim alone at {delay:g} s: ffmpeg gone",
                ["run", "s.yaml", "--out", "o", "-q"],
                tiny_scene(text=video),
                (0, 130),
                interrupt=(delay, signame),
                linger=3.0,
                timeout=120,
                after=both(whole_or_none("o/tiny"), tidy_run),
                litter_in=("o", "."),
            )
        )
    for delay, signame, more in [
        (4.0, "SIGINT", ((4.001, "SIGTERM"),)),
        (4.0, "SIGTERM", ((4.01, "SIGHUP"),)),
        (6.0, "SIGHUPG", ((6.001, "SIGINT"),)),
    ]:
        out.append(
            Attempt(
                k,
                f"run with video, {signame} at {delay:g} s then {more[0][1]} {1000 * (more[0][0] - delay):.0f} ms later",
                ["run", "s.yaml", "--out", "o", "-q"],
                tiny_scene(text=video),
                (0, 130),
                interrupt=(delay, signame),
                also=more,
                linger=3.0,
                timeout=120,
                after=both(whole_or_none("o/tiny"), tidy_run),
                litter_in=("o", "."),
            )
        )

    def long_run_then(d: Path) -> None:
        finished_run(d, LONG)

    for delay in (0.6, 1.8):
        out.append(
            Attempt(
                k,
                f"view --out v.html of a 40,000-frame run, SIGTERM to armanim alone at {delay:g} s",
                ["view", "o/tiny", "--out", "v.html"],
                long_run_then,
                (0, 130),
                interrupt=(delay, "SIGTERM"),
                linger=3.0,
                timeout=120,
                after=whole_or_none("v.html"),
                litter_in=("o", "."),
            )
        )
    golden = then(
        lambda d: finished_run(d, LONG), lambda d: armanim_in(d, "check", "s.yaml", "--update", "--golden", "g")
    )
    out.append(
        Attempt(
            k,
            "check --update of a 40,000-frame scene, SIGHUP to armanim alone at 2 s",
            ["check", "s.yaml", "--update", "--golden", "g"],
            golden,
            (0, 130),
            interrupt=(2.0, "SIGHUP"),
            linger=3.0,
            timeout=120,
            litter_in=("g", "."),
            after=again_tidy("check", "s.yaml", "--golden", "g", where=("g", ".")),
        )
    )
    box = "* b{i}\n1\nbox\n0.05 0.05 0.05\n{x} {y} 1\n0 0 0 1\n0 0 0 0\n"
    moveit = "w\n" + "".join(box.format(i=i, x=2 + i % 10, y=i // 10 * 0.1) for i in range(5_000)) + ".\n"
    for delay, signame in [(0.3, "SIGTERMG"), (1.2, "SIGHUP")]:
        out.append(
            Attempt(
                k,
                f"import moveit of 5,000 boxes --out m.yaml, {signame} at {delay:g} s",
                ["import", "moveit", "b.scene", "--robot", "panda", "--out", "m.yaml"],
                lambda d: write(d / "b.scene", moveit),
                (0, 2, 130),
                interrupt=(delay, signame),
                linger=3.0,
                timeout=60,
                after=whole_or_none("m.yaml"),
                litter_in=(".",),
            )
        )
    sweep = TINY.replace("name: tiny", "name: sw")
    for delay, signame in [(2.2, "SIGINT"), (3.0, "SIGTERM"), (3.8, "SIGHUP")]:
        out.append(
            Attempt(
                k,
                f"sweep of 3 variants --no-video (index written last), {signame} at {delay:g} s",
                ["sweep", "s.yaml", "--set", "solver.step=0.1,0.2,0.3", "--out", "o", "--no-video", "-q"],
                tiny_scene(text=sweep),
                (0, 130),
                interrupt=(delay, signame),
                linger=3.0,
                timeout=120,
                after=index_or_none("o"),
                litter_in=("o", "."),
            )
        )
    # two signals together (before Python runs a handler) in other commands than run
    long_then = lambda d: finished_run(d, LONG) and None  # noqa: E731
    for label, args, setup, delay, place in [
        ("view --out v.html of a 40,000-frame run", ["view", "o/tiny", "--out", "v.html"], long_then, 1.0, ("v.html",)),
        (
            "export --out e.json of a 40,000-frame run",
            ["export", "o/tiny", "--out", "e.json"],
            long_then,
            1.0,
            ("e.json",),
        ),
        (
            "a --jobs 2 batch of two scenes with video",
            ["run", "s.yaml", "a.yaml", "--out", "o", "-q", "--jobs", "2"],
            then(tiny_scene(text=video), tiny_scene("a.yaml", video.replace("name: tiny", "name: other"))),
            3.0,
            ("o/tiny", "o/other"),
        ),
        (
            "render --out fig of a run",
            ["render", "o/tiny", "--out", "fig"],
            lambda d: finished_run(d, video) and None,
            2.0,
            ("fig",),
        ),
    ]:
        for first, second in [("SIGINT", "SIGTERM"), ("SIGHUPG", "SIGTERM")]:
            out.append(
                Attempt(
                    k,
                    f"{label}, {first} at {delay:g} s then {second} 1 ms later",
                    args,
                    setup,
                    (0, 130),
                    interrupt=(delay, first),
                    also=((delay + 0.001, second),),
                    linger=3.0,
                    timeout=120,
                    after=whole_or_none(*place),
                    litter_in=("o", "."),
                )
            )
    return out


def index_or_none(out: str) -> Callable[[Path], list[str]]:
    """Check: ``out``'s index.csv (a batch's table), when there, is whole (each row as many cells)."""

    def check(d: Path) -> list[str]:
        for path in (d / out).rglob("index.csv") if (d / out).is_dir() else ():
            text = path.read_text()
            import csv as _csv

            rows = list(_csv.reader(text.splitlines()))
            if not text.endswith("\n") or len({len(r) for r in rows}) > 1:
                return [f"{path.relative_to(d)}: half a table"]
        return []

    return check


def inputs18_attempts() -> list[Attempt]:
    """YAML and numbers campaigns 1-17 did not try: alias bombs (in goals, in a merge key, in a
    flow list), 10,000-deep nesting in flow and block style, a duplicate key in a nested mapping,
    !!python/object/apply, /new, /tuple and /module tags, a BOM with CRLF, UTF-16-LE without a BOM,
    UTF-32, a 100 MB scene, NUL at the end; numbers written '1e400', '.nan', '0x10', 'true',
    '-.inf', '1_0' in fields not tried (fps, max_frames_per_goal, hold, speed, links, size). Each
    is exit 2 at FILE:LINE (or ok), never a traceback, in bounded time."""
    k = "inputs18"
    out: list[Attempt] = []
    at_line = r"s\.yaml:\d+: "
    base = "version: 1\nname: tiny\narm: {links: [1, 1, 1]}\nrender: {size: [160, 90], fps: 10}\n"
    laughs = "".join(f"l{i}: &l{i} [" + ", ".join([f"*l{i - 1}"] * 9) + "]\n" for i in range(1, 10))
    bombs = [
        ("a billion laughs under a key of its own", base + "a0: &l0 [1, 1, 1]\n" + laughs + "goals: [[1, 1, 1]]\n"),
        ("a billion laughs as the goals", base + "x: &l0 [1, 1, 1]\n" + laughs + "goals: *l9\n"),
        (
            "a billion laughs in a merge key",
            base
            + "x: &l0 {a: 1}\n"
            + "".join(
                f"m{i}: &m{i} {{<<: [" + ", ".join([f"*{'l' if i == 1 else 'm'}{0 if i == 1 else i - 1}"] * 9) + "]}\n"
                for i in range(1, 10)
            )
            + "goals: [[1, 1, 1]]\nsolver: *m9\n",
        ),
        ("flow lists 10,000 deep as a goal", base + "goals: [" + "[" * 10_000 + "1" + "]" * 10_000 + "]\n"),
        (
            "flow mappings 10,000 deep under solver",
            base + "goals: [[1, 1, 1]]\nsolver: " + "{a: " * 10_000 + "1" + "}" * 10_000 + "\n",
        ),
        (
            "block mappings 1,000 deep (indented, under the 1 MB limit)",
            base
            + "goals: [[1, 1, 1]]\nsolver:\n"
            + "".join(" " * (i + 1) + f"a{i}:\n" for i in range(1000))
            + " " * 1001
            + "1\n",
        ),
        (
            "a duplicate key inside arm (links twice)",
            base.replace("arm: {links: [1, 1, 1]}", "arm:\n  links: [1, 1, 1]\n  links: [2, 2, 2]")
            + "goals: [[1, 1, 1]]\n",
        ),
        ("a duplicate key in a goal mapping", base + "goals:\n  - {position: [1, 1, 1], position: [0, 0, 2]}\n"),
        (
            "!!python/object/apply:os.system",
            base + "goals: [[1, 1, 1]]\nname: !!python/object/apply:os.system ['touch pwned']\n",
        ),
        (
            "!!python/object/new:builtins.dict",
            base + "goals: [[1, 1, 1]]\nsolver: !!python/object/new:builtins.dict {}\n",
        ),
        ("!!python/tuple as a goal", base + "goals: [!!python/tuple [1, 1, 1]]\n"),
        ("!!python/module:os", base + "goals: [[1, 1, 1]]\nx: !!python/module:os\n"),
        (
            "a tag with a %TAG directive",
            "%TAG !p! tag:yaml.org,2002:python/\n---\n" + base + "goals: [!p!tuple [1, 1, 1]]\n",
        ),
        ("a %YAML 1.1 directive and a document", "%YAML 1.1\n---\n" + base + "goals: [[1, 1, 1]]\n"),
        ("a %YAML 9.9 directive", "%YAML 9.9\n---\n" + base + "goals: [[1, 1, 1]]\n"),
        ("render.fps '1e400'", base.replace("fps: 10", "fps: 1e400") + "goals: [[1, 1, 1]]\n"),
        ("render.fps .nan", base.replace("fps: 10", "fps: .nan") + "goals: [[1, 1, 1]]\n"),
        ("render.fps 0x10", base.replace("fps: 10", "fps: 0x10") + "goals: [[1, 1, 1]]\n"),
        ("render.fps true", base.replace("fps: 10", "fps: true") + "goals: [[1, 1, 1]]\n"),
        ("render.size [true, 90]", base.replace("size: [160, 90]", "size: [true, 90]") + "goals: [[1, 1, 1]]\n"),
        ("render.size [1e400, 90]", base.replace("size: [160, 90]", "size: [1e400, 90]") + "goals: [[1, 1, 1]]\n"),
        ("arm.links [1, true, 1]", base.replace("links: [1, 1, 1]", "links: [1, true, 1]") + "goals: [[1, 1, 1]]\n"),
        ("arm.links [1, 0x1, 1]", base.replace("links: [1, 1, 1]", "links: [1, 0x1, 1]") + "goals: [[1, 1, 1]]\n"),
        ("solver.max_frames_per_goal 1e400", base + "goals: [[1, 1, 1]]\nsolver: {max_frames_per_goal: 1e400}\n"),
        ("solver.max_frames_per_goal .inf", base + "goals: [[1, 1, 1]]\nsolver: {max_frames_per_goal: .inf}\n"),
        ("solver.max_frames_per_goal 600.5", base + "goals: [[1, 1, 1]]\nsolver: {max_frames_per_goal: 600.5}\n"),
        ("solver.max_frames_per_goal true", base + "goals: [[1, 1, 1]]\nsolver: {max_frames_per_goal: true}\n"),
        ("a hold of .inf", base + "goals: [{position: [1, 1, 1], hold: .inf}]\n"),
        ("a hold of 1e400", base + "goals: [{position: [1, 1, 1], hold: 1e400}]\n"),
        ("a hold of true", base + "goals: [{position: [1, 1, 1], hold: true}]\n"),
        ("a path speed -.inf", base + "goals: [{path: {line: [[1, 0.3, 1], [1, -0.3, 1]]}, speed: -.inf}]\n"),
        ("a path speed 1_0", base + "goals: [{path: {line: [[1, 0.3, 1], [1, -0.3, 1]]}, speed: 1_0}]\n"),
        ("a goal [1, 1, 0b1]", base + "goals: [[1, 1, 0b1]]\n"),
        ("a goal ['1', 1, 1] (a quoted number)", base + "goals: [['1', 1, 1]]\n"),
    ]
    for label, text in bombs:
        out.append(
            Attempt(
                k,
                f"validate, {label}",
                ["validate", "s.yaml"],
                tiny_scene(text=text),
                (0, 2),
                message_if_2=at_line,
                timeout=60,
                after=exists("pwned", present=False),
            )
        )
    raw = (base + "goals: [[1, 1, 1]]\n").encode()
    encodings = [
        (
            "a UTF-8 BOM and CRLF line ends with a bad field",
            b"\xef\xbb\xbf" + raw.replace(b"fps: 10", b"fps: -1").replace(b"\n", b"\r\n"),
            (2,),
        ),
        ("UTF-16-LE without a BOM", raw.decode().encode("utf-16-le"), (0, 2)),
        ("UTF-32 with a BOM", raw.decode().encode("utf-32"), (0, 2)),
        ("a NUL at the very end", raw + b"\0", (2,)),
        ("CR alone after a comment, then a key", raw.replace(b"version: 1\n", b"# c\rversion: 1\n"), (0, 2)),
        (
            "a bad field on line 5 of CRLF lines (the line number counted right)",
            raw.replace(b"\n", b"\r\n").replace(b"fps: 10", b"fps: -1"),
            (2,),
        ),
    ]
    for label, data, codes in encodings:
        out.append(
            Attempt(
                k,
                f"validate, {label}",
                ["validate", "s.yaml"],
                lambda d, data=data: write(d / "s.yaml", data),
                codes,
                message_if_2=at_line,
                timeout=60,
            )
        )
    out.append(
        Attempt(
            k,
            "validate, a bad field at line 4 of CRLF lines is said at line 4",
            ["validate", "s.yaml"],
            lambda d: write(d / "s.yaml", raw.replace(b"\n", b"\r\n").replace(b"fps: 10", b"fps: -1")),
            (2,),
            message=r"s\.yaml:4: render\.fps",
            timeout=60,
        )
    )
    out.append(
        Attempt(
            k,
            "validate, a bad field at line 4 after a BOM is said at line 4",
            ["validate", "s.yaml"],
            lambda d: write(d / "s.yaml", b"\xef\xbb\xbf" + raw.replace(b"fps: 10", b"fps: -1")),
            (2,),
            message=r"s\.yaml:4: render\.fps",
            timeout=60,
        )
    )
    out.append(
        Attempt(
            k,
            "validate, a scene of 100 MB (comment lines)",
            ["validate", "s.yaml"],
            big_text("s.yaml", base + "goals: [[1, 1, 1]]\n", "# " + "x" * 97 + "\n", 100),
            (2,),
            message=r"s\.yaml|bytes|MB",
            timeout=60,
        )
    )
    out.append(
        Attempt(
            k,
            "run, a scene of 100 MB of one flow list",
            ["run", "s.yaml", "--out", "o", "--no-video", "-q"],
            big_text("s.yaml", base + "goals: [", "[1, 1, 1], ", 100, "[1, 1, 1]]\n"),
            (2,),
            message=r"s\.yaml|bytes|MB",
            timeout=60,
        )
    )
    # a link that loops, everywhere a command reads a path
    loop = lambda name: symlink(name, name)  # noqa: E731
    run = lambda d: finished_run(d) and None  # noqa: E731
    for label, args, setup, codes in [
        ("validate l.yaml (a link to itself)", ["validate", "l.yaml"], loop("l.yaml"), (2,)),
        ("run l.yaml (a link to itself)", ["run", "l.yaml", "--out", "o", "--no-video", "-q"], loop("l.yaml"), (2,)),
        (
            "fk --scene l.yaml (a link to itself)",
            ["fk", "--scene", "l.yaml", "--angles", "0,0,0"],
            loop("l.yaml"),
            (2,),
        ),
        ("render l (a run folder that is a link to itself)", ["render", "l"], loop("l"), (2,)),
        ("view l (a run folder that is a link to itself)", ["view", "l"], loop("l"), (2,)),
        ("export l (a run folder that is a link to itself)", ["export", "l"], loop("l"), (2,)),
        (
            "compare a trajectory and l.csv (a link to itself)",
            ["compare", "o/tiny/trajectory.csv", "l.csv"],
            then(run, loop("l.csv")),
            (2,),
        ),
        ("robots --fit l.urdf (a link to itself)", ["robots", "--fit", "l.urdf"], loop("l.urdf"), (2,)),
        (
            "import moveit l.scene (a link to itself)",
            ["import", "moveit", "l.scene", "--robot", "panda", "--out", "m.yaml"],
            loop("l.scene"),
            (2,),
        ),
        (
            "validate, arm.urdf a link to itself",
            ["validate", "s.yaml"],
            then(tiny_scene(text=URDF_SCENE.replace("robot.urdf", "l.urdf")), loop("l.urdf")),
            (2,),
        ),
        (
            "robots --fit, --package-dir a link to itself",
            ["robots", "--fit", "robot.urdf", "--package-dir", "pk"],
            then(links_naming(["package://r/a.stl"]), loop("pk")),
            (2,),
        ),
        (
            "run, arm.tool.mesh a link to itself",
            ["run", "s.yaml", "--out", "o", "--no-video", "-q"],
            then(
                links_naming(["m.stl"], "visual"),
                tiny_scene(text=URDF_SCENE.replace("{urdf: robot.urdf}", "{urdf: robot.urdf, tool: {mesh: l.stl}}")),
                loop("l.stl"),
            ),
            (0,),
        ),
        (
            "run --viewer, a visual mesh a link to itself",
            ["run", "s.yaml", "--out", "o", "--no-video", "--viewer", "-q"],
            then(links_naming(["l.stl"], "visual"), loop("l.stl")),
            (0,),
        ),
    ]:
        out.append(Attempt(k, label, args, setup, codes, message_if_2=r"l\.|pk|l\b|loop|symbolic", timeout=60))
    for label, env, codes in [
        ("ARMANIM_CACHE_DIR a link to itself, validate of a fitted URDF", {"ARMANIM_CACHE_DIR": "{d}/c"}, (0,)),
        ("TMPDIR a link to itself, a run with video", {"TMPDIR": "{d}/c"}, (0, 3)),
    ]:
        setup = then(one_mesh_robot(), loop("c")) if "URDF" in label else then(tiny_scene(), loop("c"))
        args = ["validate", "s.yaml"] if "URDF" in label else ["run", "s.yaml", "--out", "o", "-q"]
        out.append(Attempt(k, label, args, setup, codes, env=env, keep=("c",), timeout=120))
    return out


def wrong18_attempts() -> list[Attempt]:
    """Four new draws of the random-arm oracle (rates, clock, summary)."""
    return oracle_runs("wrong18", (1801, 1802, 1803, 1804), "held to the rates, the clock and the summary")


# ------------------------------------------------------------------ the eighteenth campaign, part A (new angles)

LIBFAKETIME = "/usr/lib/x86_64-linux-gnu/faketime/libfaketime.so.1"
RUN_NV = ["run", "s.yaml", "--out", "o", "--no-video", "-q"]


def fake_clock(faketime: str) -> dict[str, str]:
    """An attempt's env: armanim's clock as libfaketime's FAKETIME says (``@2100-01-01 00:00:00``:
    starting there and ticking; ``+0 x10``: ten times faster). libfaketime fakes the wall clock and
    the monotonic one alike (its FAKETIME_DONT_FAKE_MONOTONIC makes Python's sleep fail with EINVAL
    in 0.9.10), and never the times the kernel stamps on files."""
    return {"LD_PRELOAD": LIBFAKETIME, "FAKETIME": faketime}


def clock_file(at: str = "clock.txt", value: str = "+0") -> Callable[[Path], None]:
    """Setup step: libfaketime's timestamp file ``at`` (read at every call: FAKETIME_NO_CACHE)."""
    return lambda d: write(d / at, value + "\n") and None


def clock_set_at(seconds: float, value: str, at: str = "clock.txt") -> Callable[[Path], None]:
    """Setup step: ``value`` written into the timestamp file ``seconds`` after the setup ends (the
    clock jumps then, during the attempt)."""
    return lambda d: (
        background(
            "sh", "-c", f"sleep {seconds}; printf '%s\\n' '{value}' > '{d / at}.new' && mv '{d / at}.new' '{d / at}'"
        )
        and None
    )


def jumping_clock(at: str = "clock.txt") -> dict[str, str]:
    return {"LD_PRELOAD": LIBFAKETIME, "FAKETIME_TIMESTAMP_FILE": "{d}/" + at, "FAKETIME_NO_CACHE": "1"}


def under(env: dict[str, str], *args: str) -> Callable[[Path], None]:
    """Setup step: armanim ``args`` run (checked) with ``env`` (a fake clock: {d} is the folder)."""
    return lambda d: armanim_in(d, *args, env={k: v.replace("{d}", str(d)) for k, v in env.items()})


SKIP_COMPARE = ("timing.json", ".armanim-run.json")


def like_clean_run(
    run: str = "o/tiny",
    setups: tuple[tuple[list[str], Callable[[Path], None]], ...] = ((RUN_NV, tiny_scene()),),
    subset: bool = False,
) -> Callable[[Path], list[str]]:
    """After: the run folder ``run`` holds, byte for byte, the files of a clean run (each of
    ``setups``: armanim's args and the inputs' setup, made afresh with the campaign's clock) but
    timing.json: the same names (or, with ``subset``, some of them: a render may or may not have
    come after), and its next run is not refused. A folder ``run`` that is missing is a problem."""

    def check(d: Path) -> list[str]:
        base = d / run
        if not base.is_dir():
            return [f"no {run}"]
        got = {p.name: p.read_bytes() for p in base.iterdir() if p.name not in SKIP_COMPARE and p.is_file()}
        for number, (args, setup) in enumerate(setups):
            clean = d.parent / f"{d.name}.clean{number}"
            shutil.rmtree(clean, ignore_errors=True)
            clean.mkdir()
            setup(clean)
            done = subprocess.run(
                [sys.executable, "-m", "armanim", *args],
                cwd=clean,
                env={**os.environ, "PYTHONPATH": str(SRC)},
                capture_output=True,
                timeout=900,
            )
            cbase = clean / run
            want = (
                {p.name: p.read_bytes() for p in cbase.iterdir() if p.name not in SKIP_COMPARE and p.is_file()}
                if cbase.is_dir()
                else {}
            )
            shutil.rmtree(clean, ignore_errors=True)
            if done.returncode != 0:
                return [f"the clean run {args} failed: exit {done.returncode}"]
            names_ok = set(got) <= set(want) if subset else set(got) == set(want)
            if names_ok and all(got[n] == want[n] for n in got):
                return []
        names = sorted(got)
        return [f"{run} ({', '.join(names)}) is not, file for file, a clean run of its inputs"]

    return check


def next_run_ok(args: list[str] = RUN_NV, env: dict[str, str] | None = None) -> Callable[[Path], list[str]]:
    """After: the same command again (the real clock, or ``env``) is not refused: exit 0."""

    def check(d: Path) -> list[str]:
        done = subprocess.run(
            [sys.executable, "-m", "armanim", *args],
            cwd=d,
            env={**os.environ, "PYTHONPATH": str(SRC), **{k: v.replace("{d}", str(d)) for k, v in (env or {}).items()}},
            capture_output=True,
            text=True,
            timeout=900,
        )
        if done.returncode != 0 or "Traceback" in done.stderr:
            return [
                f"the next {' '.join(args[:2])}: exit {done.returncode}: {(done.stdout + done.stderr).strip()[-300:]}"
            ]
        return []

    return check


def beside(name: str, *args: str, delay: float = 0.0, env: dict[str, str] | None = None) -> Callable[[Path], None]:
    """Setup step: armanim ``args`` started in the background ``delay`` s after the setup ends
    (the attempt's own armanim starts meanwhile: two commands at once), its output in NAME.out and
    its exit code in NAME.rc."""

    def step(d: Path) -> None:
        script = f'sleep {delay}; "$0" -m armanim "$@" > {name}.out 2>&1; echo $? > {name}.rc'
        background("sh", "-c", script, sys.executable, *args, env=env or {}, cwd=str(d))

    return step


def beside_ended(name: str, codes: tuple[int, ...] = (0,), within: float = 300.0) -> Callable[[Path], list[str]]:
    """After: the background armanim ``name`` (:func:`beside`) ended within ``within`` s with one
    of ``codes``, without a traceback; an exit 3 must say why."""

    def check(d: Path) -> list[str]:
        deadline = time.monotonic() + within
        while not (d / f"{name}.rc").exists() and time.monotonic() < deadline:
            time.sleep(0.2)
        if not (d / f"{name}.rc").exists():
            return [f"the other command ({name}) still running after {within:g} s"]
        time.sleep(0.1)
        code = int((d / f"{name}.rc").read_text().strip() or -1)
        said = (d / f"{name}.out").read_text(errors="replace") if (d / f"{name}.out").exists() else ""
        problems = []
        if "Traceback" in said or "Exception ignored" in said:
            problems.append(f"the other command ({name}) ended in a traceback: {said.strip().splitlines()[-1][:200]}")
        if code not in codes:
            problems.append(f"the other command ({name}): exit {code}, expected {codes}: {said.strip()[-200:]}")
        return problems

    return check


def no_litter(*where: str) -> Callable[[Path], list[str]]:
    """After: no staging folder or temporary file (:data:`LITTER`) under ``where``."""

    def check(d: Path) -> list[str]:
        found = [
            str(p.relative_to(d))
            for place in where
            if (d / place).is_dir()
            for p in ((d / place).iterdir() if place == "." else (d / place).rglob("*"))
            if LITTER.search(p.name)
        ]
        return [f"litter: {found[:4]}"] if found else []

    return check


def then_check(*checks: Callable[[Path], list[str]]) -> Callable[[Path], list[str]]:
    """After: the checks in turn, stopping at the first that finds a problem (the later ones
    would run commands on a folder already found wrong)."""

    def check(d: Path) -> list[str]:
        for one in checks:
            problems = one(d)
            if problems:
                return problems
        return []

    return check


def clock18_attempts() -> list[Attempt]:
    """The wall clock changes (libfaketime): armanim under a clock in 1970 (before every file's
    mtime), in 2039 (past a 32-bit time_t) and 2100, ten times fast, or jumping back a day or ten
    years on during the command; then the next command under the real clock (the marker lists
    mtimes: it must not refuse). Held to the clean run's bytes (all but timing.json: the video too)."""
    k = "clock18"
    out: list[Attempt] = []
    clocks = [("1970", "@1970-01-02 00:00:00"), ("2039", "@2039-06-01 00:00:00"), ("2100", "@2100-01-01 00:00:00")]
    video = ["run", "s.yaml", "--out", "o", "-q"]
    for year, fake in clocks:
        out.append(
            Attempt(
                k,
                f"run under a clock in {year}: the clean run's bytes",
                RUN_NV,
                tiny_scene(),
                (0,),
                env=fake_clock(fake),
                timeout=300,
                after=then_check(like_clean_run(), next_run_ok()),
            )
        )
    out.append(
        Attempt(
            k,
            "run with video --jobs 2 under a clock in 1970: the clean run's bytes, video included",
            [*video, "--jobs", "2"],
            tiny_scene(),
            (0,),
            env=fake_clock(clocks[0][1]),
            timeout=300,
            after=like_clean_run(setups=((video, tiny_scene()),)),
        )
    )
    for year, fake in (clocks[0], clocks[2]):
        out.append(
            Attempt(
                k,
                f"run again under the real clock, the run folder written under a clock in {year}: replaced",
                RUN_NV,
                then(tiny_scene(), under(fake_clock(fake), *RUN_NV)),
                (0,),
                timeout=300,
                after=like_clean_run(),
            )
        )
        out.append(
            Attempt(
                k,
                f"run again under a clock in {year}, the run folder written under the real clock: replaced",
                RUN_NV,
                then(tiny_scene(), under({}, *RUN_NV)),
                (0,),
                env=fake_clock(fake),
                timeout=300,
                after=like_clean_run(),
            )
        )
    batch = ["run", "s.yaml", "a.yaml", "--out", "o", "--no-video", "-q", "--jobs", "2"]
    out.append(
        Attempt(
            k,
            "a batch --jobs 2 under a clock in 2100, then one under the real clock: index.csv replaced",
            batch,
            then(tiny_scene(), tiny_scene("a.yaml", OTHER)),
            (0,),
            env=fake_clock(clocks[2][1]),
            timeout=300,
            after=then_check(index_agrees(), next_run_ok(batch), index_agrees()),
        )
    )
    out.append(
        Attempt(
            k,
            "a batch again under a clock in 1970, index.csv written under the real clock: replaced",
            batch,
            then(tiny_scene(), tiny_scene("a.yaml", OTHER), under({}, *batch)),
            (0,),
            env=fake_clock(clocks[0][1]),
            timeout=300,
            after=index_agrees(),
        )
    )
    sweep = ["sweep", "s.yaml", "--set", "solver.step=0.1,0.2", "--out", "o", "-q", "--jobs", "1"]
    out.append(
        Attempt(
            k,
            "sweep under a clock in 1970, then again under the real clock: its table replaced",
            sweep,
            tiny_scene(),
            (0,),
            env=fake_clock(clocks[0][1]),
            timeout=300,
            after=then_check(index_agrees(), next_run_ok(sweep), index_agrees()),
        )
    )
    update = ["check", "s.yaml", "--golden", "g", "--update", "-q"]
    out.append(
        Attempt(
            k,
            "check --update under a clock in 1970, then check under the real clock: passes",
            update,
            tiny_scene(),
            (0,),
            env=fake_clock(clocks[0][1]),
            timeout=300,
            after=golden_holds("s.yaml"),
        )
    )
    out.append(
        Attempt(
            k,
            "check under a clock in 2100 of a golden updated under the real clock: passes",
            ["check", "s.yaml", "--golden", "g", "-q"],
            then(tiny_scene(), under({}, *update)),
            (0,),
            env=fake_clock(clocks[2][1]),
            timeout=300,
        )
    )
    out.append(
        Attempt(
            k,
            "check --update again under a clock in 1970, the pair written under the real clock: replaced",
            update,
            then(tiny_scene(), under({}, *update), lambda d: write(d / "s.yaml", TINY.replace("0.5, -1", "0.4, -1"))),
            (0,),
            env=fake_clock(clocks[0][1]),
            timeout=300,
            after=golden_holds("s.yaml"),
        )
    )
    out.append(
        Attempt(
            k,
            "compare of two runs' trajectories under a clock in 1970: they agree",
            ["compare", "o/tiny/trajectory.csv", "p/tiny/trajectory.csv"],
            then(tiny_scene(), under({}, *RUN_NV), under({}, "run", "s.yaml", "--out", "p", "--no-video", "-q")),
            (0,),
            env=fake_clock(clocks[0][1]),
            message=r"trajectories agree",
        )
    )
    for cmd, args, made in [
        ("render", ["render", "o/tiny"], ("animation.mp4", "plot.png", "poster.png")),
        ("view", ["view", "o/tiny"], ("viewer.html",)),
        ("export", ["export", "o/tiny"], ("joint_trajectory.json",)),
    ]:
        out.append(
            Attempt(
                k,
                f"{cmd} under a clock in 2039 of a run made under the real clock, then a run replaces it",
                args,
                then(tiny_scene(), under({}, *RUN_NV)),
                (0,),
                env=fake_clock(clocks[1][1]),
                timeout=300,
                after=then_check(exists(*(f"o/tiny/{m}" for m in made)), next_run_ok()),
            )
        )
    out.append(
        Attempt(
            k,
            "export --out e.json under a clock in 2100, then again under the real clock: replaced",
            ["export", "o/tiny", "--out", "e.json"],
            then(tiny_scene(), under({}, *RUN_NV)),
            (0,),
            env=fake_clock(clocks[2][1]),
            after=next_run_ok(["export", "o/tiny", "--out", "e.json"]),
        )
    )
    out.append(
        Attempt(
            k,
            "fk --png under a clock in 1970, then again under the real clock: replaced",
            ["fk", "--links", "1,1", "--angles", "10,20", "--png", "p.png"],
            lambda d: None,
            (0,),
            env=fake_clock(clocks[0][1]),
            after=next_run_ok(["fk", "--links", "1,1", "--angles", "10,20", "--png", "p.png"]),
        )
    )
    # not quiet, on a "terminal" (rich takes FORCE_COLOR for one): the bars, their rate and time left drawn
    bars, drawn = ["run", "s.yaml", "--out", "o", "--jobs", "2"], r"solver steps.*render"
    out.append(
        Attempt(
            k,
            "run with video --jobs 2 under a clock ten times fast (progress bars drawn): the clean bytes",
            bars,
            tiny_scene(),
            (0,),
            env={**fake_clock("+0 x10"), "FORCE_COLOR": "1"},
            message=drawn,
            timeout=300,
            after=like_clean_run(setups=((video, tiny_scene()),)),
        )
    )
    jumps = [("back a day", "-1d"), ("on ten years", "+10y"), ("back to 1970", "@1970-01-02 00:00:00")]
    longer = TINY.replace("render: {size: [160, 90], fps: 10}", "render: {size: [320, 180], fps: 30}")
    for label, value in jumps:
        for at in (1.5, 3.0):
            out.append(
                Attempt(
                    k,
                    f"run with video --jobs 2 (bars drawn), the clock jumping {label} at {at:g} s: the clean bytes",
                    bars,
                    then(tiny_scene(text=longer), clock_file(), clock_set_at(at, value)),
                    (0,),
                    env={**jumping_clock(), "FORCE_COLOR": "1"},
                    message=drawn,
                    timeout=300,
                    after=like_clean_run(setups=((video, tiny_scene(text=longer)),)),
                )
            )
    out.append(
        Attempt(
            k,
            "a batch --jobs 2 with video, the clock jumping back a day at 2 s: index.csv and the folders right",
            ["run", "s.yaml", "a.yaml", "--out", "o", "-q", "--jobs", "2"],
            then(tiny_scene(), tiny_scene("a.yaml", OTHER), clock_file(), clock_set_at(2.0, "-1d")),
            (0,),
            env=jumping_clock(),
            timeout=300,
            after=index_agrees(),
        )
    )
    out.append(
        Attempt(
            k,
            "check --update, the clock jumping on ten years at 1 s, then check under the real clock",
            ["check", "s.yaml", "a.yaml", "--golden", "g", "--update", "-q"],
            then(tiny_scene(), tiny_scene("a.yaml", OTHER), clock_file(), clock_set_at(1.0, "+10y")),
            (0,),
            env=jumping_clock(),
            timeout=300,
            after=golden_holds("s.yaml", "a.yaml"),
        )
    )
    return out


def inplace_edit(path: str, keep_time: bool = True) -> Callable[[Path], None]:
    """Setup step: ``path``'s last digit changed in place (its size kept) and, with ``keep_time``,
    its modification time put back (``touch -r``, ``cp -p``, ``rsync -t`` keep one)."""

    def step(d: Path) -> None:
        target = d / path
        before = os.stat(target)
        data = bytearray(target.read_bytes())
        i = max(j for j in range(len(data)) if chr(data[j]).isdigit())
        data[i] = ord("7") if data[i] != ord("7") else ord("3")
        with open(target, "r+b") as handle:
            handle.write(bytes(data))
        if keep_time:
            os.utime(target, ns=(before.st_atime_ns, before.st_mtime_ns))

    return step


def second_disk(at: str, megabytes: int = 48) -> Callable[[Path], None]:
    """Setup step: an ext4 file system of 128-byte inodes (times to the second, as ext3 and
    older disks, FAT's are to 2 s) loop-mounted at ``at``."""

    def step(d: Path) -> None:
        image = d / f".{at}.img"
        with open(image, "wb") as handle:
            handle.truncate(megabytes << 20)
        subprocess.run(["mkfs.ext4", "-q", "-F", "-I", "128", str(image)], check=True, capture_output=True)
        (d / at).mkdir(parents=True, exist_ok=True)
        subprocess.run(["mount", "-o", "loop", str(image), str(d / at)], check=True)

    return step


def edited_in_the_run_s_second(run: str = "o/tiny", path: str = "trajectory.csv") -> Callable[[Path], None]:
    """Setup step (on a disk of 1 s times): run, then at once a user's script changes a digit of
    ``path`` in place; tried again until the edit falls in the second the run wrote the file in (on
    such a disk its time is then the one the marker records)."""

    def step(d: Path) -> None:
        import json as _json

        for _ in range(10):
            shutil.rmtree(d / run, ignore_errors=True)
            armanim_in(d, *RUN_NV)
            recorded = _json.loads((d / run / ".armanim-run.json").read_text())["files"][path]["mtime_ns"]
            inplace_edit(f"{run}/{path}", keep_time=False)(d)
            if os.stat(d / run / path).st_mtime_ns == recorded:
                return
        raise RuntimeError("no edit fell in the run's second in 10 tries")

    return step


def marker_adds(name: str | Callable[[Path], str], stamp_of: str) -> Callable[[Path], None]:
    """Setup step: the run folder o/tiny's marker edited to list ``name`` (a string, or made from
    the folder) with the size and mtime of ``stamp_of`` (relative to the folder: the user's file)."""

    def step(d: Path) -> None:
        import json as _json

        marker = d / "o/tiny/.armanim-run.json"
        data = _json.loads(marker.read_text())
        st = os.stat(d / stamp_of)
        data["files"][name(d) if callable(name) else name] = {"bytes": st.st_size, "mtime_ns": st.st_mtime_ns}
        marker.write_text(_json.dumps(data, indent=2))

    return step


def other_run(out: str) -> Callable[[Path], None]:
    """Setup step: another run of a scene named tiny (other goals, q.yaml) into ``out``: OUT/tiny."""
    return then(
        tiny_scene("q.yaml", TINY.replace("[0.5, -1, 1]", "[-0.5, -1, 1.5]")),
        under({}, "run", "q.yaml", "--out", out, "--no-video", "-q"),
    )


def between18_attempts() -> list[Attempt]:
    """A file changed between two commands: ``validate`` ok, then the scene, URDF or mesh changed,
    then ``run``; a run, then a file of its folder edited (its size and time kept), truncated, or
    replaced by a link, then ``render``, ``view``, ``export``, ``compare`` and the next ``run``
    (promise 1: it must refuse); a golden pair edited between ``check --update`` and ``check``; a
    run folder's marker edited to list files outside it (the next run must delete nothing there)."""
    k = "between18"
    out: list[Attempt] = []
    at_line = AT_LINE

    def validated(inputs: Callable[[Path], None], change: Callable[[Path], object]) -> Callable[[Path], None]:
        """Setup: the inputs, ``validate`` of them (ok), then the change."""
        return then(inputs, under({}, "validate", "s.yaml"), change)

    out.append(
        Attempt(
            k,
            "validate ok, then a goal of the scene made text, then run: exit 2 at its line",
            RUN_NV,
            validated(tiny_scene(), lambda d: write(d / "s.yaml", TINY.replace("[0.5, -1, 1]", "[0.5, x, 1]"))),
            (2,),
            message=r"s\.yaml:4",
            litter_in=("o", "."),
            after=nothing_made("o"),
        )
    )
    out.append(
        Attempt(
            k,
            "validate ok, then the URDF's joint j2 removed, then run: exit 2 naming the URDF",
            ["run", "s.yaml", "--out", "o", "--no-video", "-q"],
            validated(
                urdf_robot(),
                lambda d: write(d / "robot.urdf", re.sub(r'<joint name="j2".*?</joint>', "", urdf_text(), flags=re.S)),
            ),
            (0, 2),
            message_if_2=at_line,
            litter_in=("o", "."),
        )
    )
    out.append(
        Attempt(
            k,
            "validate ok, then the URDF replaced by a link to /dev/zero, then run: exit 2 at once",
            RUN_NV,
            validated(urdf_robot(), lambda d: ((d / "robot.urdf").unlink(), os.symlink("/dev/zero", d / "robot.urdf"))),
            (2,),
            timeout=60,
            litter_in=("o", "."),
            after=nothing_made("o"),
        )
    )
    mesh_urdf = urdf_robot(collision=col("m.stl"), files={"m.stl": stl(12)})
    out.append(
        Attempt(
            k,
            "validate ok, then the URDF's collision mesh replaced by a FIFO, then run: exit 2, no wait",
            RUN_NV,
            validated(mesh_urdf, lambda d: ((d / "m.stl").unlink(), os.mkfifo(d / "m.stl"))),
            (2,),
            timeout=60,
            litter_in=("o", "."),
            after=nothing_made("o"),
        )
    )
    out.append(
        Attempt(
            k,
            "validate ok, then the collision mesh truncated to 84 bytes of 12 triangles, then run",
            RUN_NV,
            validated(mesh_urdf, lambda d: (d / "m.stl").write_bytes(stl(12)[:84])),
            (0, 2),
            message_if_2=r"m\.stl",
            timeout=120,
            litter_in=("o", "."),
        )
    )
    # a run folder's file changed, then the next run: promise 1
    with_run = lambda d: finished_run(d) and None  # noqa: E731
    for label, change in [
        ("trajectory.csv edited in place, its size and time kept (touch -r)", inplace_edit("o/tiny/trajectory.csv")),
        ("summary.json edited in place, its size and time kept (touch -r)", inplace_edit("o/tiny/summary.json")),
        ("scene.yaml edited in place, its size and time kept (touch -r)", inplace_edit("o/tiny/scene.yaml")),
    ]:
        out.append(
            Attempt(
                k,
                f"run, then {label}, then run again: refused (exit 3), the edit kept",
                RUN_NV,
                then(with_run, change),
                (3,),
                message=r"changed since",
                keep=("o/tiny",),
                timeout=300,
            )
        )
    out.append(
        Attempt(
            k,
            "run onto a disk of 1 s times, trajectory.csv edited right after in the same second, then run again: refused, the edit kept",
            RUN_NV,
            then(tiny_scene(), second_disk("o"), edited_in_the_run_s_second()),
            (3,),
            message=r"changed since",
            keep=("o/tiny",),
            timeout=300,
        )
    )
    out.append(
        Attempt(
            k,
            "run, then trajectory.csv truncated mid-row, then run again: refused, the file kept",
            RUN_NV,
            then(with_run, lambda d: os.truncate(d / "o/tiny/trajectory.csv", 5000)),
            (3,),
            message=r"changed since",
            keep=("o/tiny",),
            timeout=300,
        )
    )
    for cmd, args in [
        ("render", ["render", "o/tiny", "--size", "64x36"]),
        ("view", ["view", "o/tiny"]),
        ("export", ["export", "o/tiny"]),
    ]:
        out.append(
            Attempt(
                k,
                f"run, then trajectory.csv truncated mid-row, then {cmd}: exit 2 at the cut, the folder kept",
                args,
                then(with_run, lambda d: os.truncate(d / "o/tiny/trajectory.csv", 5000)),
                (2,),
                message=r"trajectory\.csv",
                keep=("o/tiny",),
                timeout=300,
            )
        )
        out.append(
            Attempt(
                k,
                f"run, then trajectory.csv a link to another run's, then {cmd}: refused, both kept",
                args,
                then(
                    with_run,
                    other_run("p"),
                    lambda d: (
                        (d / "o/tiny/trajectory.csv").unlink(),
                        os.symlink(d / "p/tiny/trajectory.csv", d / "o/tiny/trajectory.csv"),
                    ),
                ),
                (2, 3),
                message_if_3=r"link|changed",
                keep=("o/tiny", "p/tiny"),
                timeout=300,
            )
        )
        out.append(
            Attempt(
                k,
                f"run, then summary.json emptied, then {cmd}: exit 2 naming it, the folder kept",
                args,
                then(with_run, lambda d: os.truncate(d / "o/tiny/summary.json", 0)),
                (2,),
                message=r"summary\.json",
                keep=("o/tiny",),
                timeout=300,
            )
        )
    out.append(
        Attempt(
            k,
            "run, then summary.json a hard link to another run's, then run again: refused, both kept",
            RUN_NV,
            then(
                with_run,
                under({}, "run", "s.yaml", "--out", "p", "--no-video", "-q"),
                lambda d: (
                    (d / "o/tiny/summary.json").unlink(),
                    os.link(d / "p/tiny/summary.json", d / "o/tiny/summary.json"),
                ),
            ),
            (3,),
            keep=("o/tiny", "p/tiny"),
            timeout=300,
        )
    )
    out.append(
        Attempt(
            k,
            "compare of a run's trajectory.csv and that file truncated mid-row: exit 1 or 2, no traceback",
            ["compare", "o/tiny/trajectory.csv", "cut.csv"],
            then(with_run, lambda d: write(d / "cut.csv", (d / "o/tiny/trajectory.csv").read_bytes()[:5000])),
            (1, 2),
            keep=("cut.csv",),
        )
    )
    out.append(
        Attempt(
            k,
            "render with video, then animation.mp4 edited in place (size and time kept), then render again",
            ["render", "o/tiny", "--size", "64x36"],
            then(with_run, under({}, "render", "o/tiny", "--size", "64x36"), inplace_edit("o/tiny/animation.mp4")),
            (0, 3),
            keep=("o/tiny/animation.mp4",),
            timeout=300,
        )
    )
    # a golden pair edited between check --update and check
    update = under({}, "check", "s.yaml", "--golden", "g", "--update", "-q")
    for label, change, codes, said in [
        ("its CSV's last digit changed", inplace_edit("g/tiny.csv", keep_time=False), (1,), r"fail|differ"),
        ("its CSV truncated mid-row", lambda d: os.truncate(d / "g/tiny.csv", 5000), (1, 2), r"g/tiny\.csv:\d+: "),
        (
            "its .json a link to another scene's golden .json",
            then(
                lambda d: write(d / "h/a.yaml", OTHER),
                under({}, "check", "h/a.yaml", "--golden", "h", "--update", "-q"),
                lambda d: ((d / "g/tiny.json").unlink(), os.symlink(d / "h/other.json", d / "g/tiny.json")),
            ),
            (0,),  # the trajectories agree; the .json's scene sha256 only adds a note
            r"changed since the golden file",
        ),
        (
            "its .json's scene_sha256 edited",
            lambda d: write(
                d / "g/tiny.json",
                re.sub(r'("scene_sha256": ")[0-9a-f]', r"\g<1>x", (d / "g/tiny.json").read_text(), count=1),
            ),
            (0,),
            r"changed since the golden file",
        ),
    ]:
        out.append(
            Attempt(
                k,
                f"check --update, then {label}, then check: the pair kept, what changed said",
                ["check", "s.yaml", "--golden", "g"],
                then(tiny_scene(), update, change),
                codes,
                message=said,
                keep=("g",),
                timeout=300,
            )
        )
    # a marker edited to list what is outside the folder
    mine_out = mine("mine.txt")
    for label, name in [
        ("../../mine.txt (the user's file, its size and time)", "../../mine.txt"),
        ("the user's file by its absolute path, with its size and time", lambda d: str(d / "mine.txt")),
        ("o/tiny/../../mine.txt spelled through the folder", "../tiny/../../mine.txt"),
    ]:
        out.append(
            Attempt(
                k,
                f"a run's marker edited to list {label}, then run: the user's file kept",
                RUN_NV,
                then(with_run, mine_out, marker_adds(name, "mine.txt")),
                (0, 3),
                keep=("mine.txt",),
                timeout=300,
            )
        )
    out.append(
        Attempt(
            k,
            "a run's marker edited to list notes, o/tiny/notes a link to the user's folder, then run: refused, the folder kept",
            RUN_NV,
            then(
                with_run,
                lambda d: write(d / "notes/n.txt", "mine"),
                lambda d: os.symlink(d / "notes", d / "o/tiny/notes"),
                marker_adds("notes", "notes"),
            ),
            (3,),
            keep=("notes", "o/tiny"),
            timeout=300,
        )
    )
    out.append(
        Attempt(
            k,
            "a run's marker edited to list mine.txt, o/tiny/mine.txt a hard link to the user's file, then run: its bytes kept",
            RUN_NV,
            then(
                with_run,
                mine_out,
                lambda d: os.link(d / "mine.txt", d / "o/tiny/mine.txt"),
                marker_adds("mine.txt", "mine.txt"),
            ),
            (0, 3),
            keep=("mine.txt",),
            timeout=300,
        )
    )
    out.append(
        Attempt(
            k,
            "a run's marker edited to list the user's file outside, then render: the user's file kept",
            ["render", "o/tiny", "--size", "64x36"],
            then(with_run, mine_out, marker_adds("../../mine.txt", "mine.txt")),
            (0, 3),
            keep=("mine.txt",),
            timeout=300,
        )
    )
    return out


def concur18_attempts() -> list[Attempt]:
    """Two commands at once on the same things (the other started in the background as the
    attempt's starts): two runs into one folder, a run while render, view or export reads it, two
    ``check --update`` of one golden, a sweep and a run into one OUT, two batches into one OUT, two
    exports to one file. Held to: no data lost, no folder mixing two commands (each file byte for
    byte one clean run's), the loser says why (exit 3) or waits, never a traceback, and the next
    command not refused."""
    k = "concur18"
    out: list[Attempt] = []

    def ended(name: str, codes: tuple[int, ...] = (0,)) -> Callable[[Path], list[str]]:
        """The other command ended (:func:`beside_ended`), then no litter left by either: looked at
        only now (while the other runs, its staging folder is its own)."""
        return then_check(beside_ended(name, codes), no_litter("o", "p", "g", "fig", "."))

    video = ["run", "s.yaml", "--out", "o", "-q"]
    out.append(
        Attempt(
            k,
            "two runs of one scene into one folder at once: both 0, the folder a clean run's",
            RUN_NV,
            then(tiny_scene(), beside("other", *RUN_NV)),
            (0,),
            timeout=300,
            after=then_check(ended("other"), like_clean_run(), next_run_ok()),
        )
    )
    out.append(
        Attempt(
            k,
            "two runs with video --jobs 2 of one scene into one folder at once: both 0, the folder a clean run's",
            [*video, "--jobs", "2"],
            then(tiny_scene(), beside("other", *video, "--jobs", "2")),
            (0,),
            timeout=300,
            after=then_check(ended("other"), like_clean_run(setups=((video, tiny_scene()),)), next_run_ok()),
        )
    )
    far = TINY.replace("[0.5, -1, 1]", "[-0.5, -1, 1.5]")
    two = (
        (["run", "a.yaml", "--out", "o", "--no-video", "-q"], tiny_scene("a.yaml")),
        (["run", "b.yaml", "--out", "o", "--no-video", "-q"], tiny_scene("b.yaml", far)),
    )
    out.append(
        Attempt(
            k,
            "two runs of two scenes of one name into one folder at once: the folder one of them, whole",
            ["run", "a.yaml", "--out", "o", "--no-video", "-q"],
            then(
                tiny_scene("a.yaml"),
                tiny_scene("b.yaml", far),
                beside("other", "run", "b.yaml", "--out", "o", "--no-video", "-q"),
            ),
            (0,),
            timeout=300,
            after=then_check(ended("other"), like_clean_run(setups=two)),
        )
    )
    with_run = lambda d: finished_run(d) and None  # noqa: E731
    for cmd, args, delay in [
        ("render", ["render", "o/tiny"], 0.0),
        ("render", ["render", "o/tiny"], 1.0),
        ("view", ["view", "o/tiny"], 0.0),
        ("export", ["export", "o/tiny"], 0.0),
        ("export --out e.json", ["export", "o/tiny", "--out", "e.json"], 0.0),
    ]:
        clean_sets: tuple[tuple[list[str], Callable[[Path], None]], ...] = ((video, tiny_scene()),)
        if cmd in ("export", "view"):  # it came last: the run's files and its joint_trajectory.json, or the
            # page view writes (its view box from the CSV read back, 1 ulp off the run's own page)
            clean_sets += ((args, then(tiny_scene(), under({}, *video))),)
        out.append(
            Attempt(
                k,
                f"run with video again while {cmd} reads the run folder (started {delay:g} s apart): no mix",
                video,
                then(with_run, beside("other", *args, delay=delay)),
                (0,),
                timeout=300,
                after=then_check(
                    ended("other"), like_clean_run(setups=clean_sets, subset=cmd != "export"), next_run_ok()
                ),
            )
        )
    out.append(
        Attempt(
            k,
            "render of a run while that run is run again without video: both 0, no mix",
            ["render", "o/tiny"],
            then(with_run, beside("other", *RUN_NV)),
            (0,),
            timeout=300,
            after=then_check(
                ended("other"), like_clean_run(setups=((video, tiny_scene()),), subset=True), next_run_ok()
            ),
        )
    )
    update = ["check", "s.yaml", "--golden", "g", "--update", "-q"]
    out.append(
        Attempt(
            k,
            "two check --update of one golden folder at once: both 0, then check passes",
            update,
            then(tiny_scene(), beside("other", *update)),
            (0,),
            timeout=300,
            after=then_check(ended("other"), golden_holds("s.yaml")),
        )
    )
    out.append(
        Attempt(
            k,
            "check --update of two scenes while check reads the golden: check 0 or 1, no traceback",
            ["check", "s.yaml", "a.yaml", "--golden", "g", "--update", "-q"],
            then(
                tiny_scene(),
                tiny_scene("a.yaml", OTHER),
                under({}, "check", "s.yaml", "a.yaml", "--golden", "g", "--update", "-q"),
                lambda d: write(d / "s.yaml", TINY.replace("0.5, -1", "0.4, -1")),
                beside("other", "check", "s.yaml", "a.yaml", "--golden", "g", "-q", delay=0.5),
            ),
            (0,),
            timeout=300,
            after=then_check(ended("other", (0, 1)), golden_holds("s.yaml", "a.yaml")),
        )
    )
    sweep = ["sweep", "s.yaml", "--set", "solver.step=0.1,0.2", "--out", "o", "-q", "--jobs", "1"]
    out.append(
        Attempt(
            k,
            "a sweep and a run of the same scene into one OUT at once: both 0, each folder whole",
            sweep,
            then(tiny_scene(), beside("other", *RUN_NV)),
            (0,),
            timeout=300,
            after=then_check(ended("other"), like_clean_run(), next_run_ok(sweep)),
        )
    )
    out.append(
        Attempt(
            k,
            "two sweeps of one scene into one OUT at once: both 0, the table and folders agree, a third not refused",
            sweep,
            then(tiny_scene(), beside("other", *sweep)),
            (0,),
            timeout=300,
            after=then_check(ended("other"), index_agrees(), next_run_ok(sweep)),
        )
    )
    batch_ab = ["run", "s.yaml", "a.yaml", "--out", "o", "--no-video", "-q"]
    batch_ba = ["run", "a.yaml", "s.yaml", "--out", "o", "--no-video", "-q"]
    for n in range(4):
        out.append(
            Attempt(
                k,
                f"two batches of two scenes into one OUT at once (try {n + 1}): index.csv and its mark agree, a third not refused",
                batch_ab,
                then(tiny_scene(), tiny_scene("a.yaml", OTHER), beside("other", *batch_ba, delay=0.05 * n)),
                (0,),
                timeout=300,
                after=then_check(ended("other"), index_agrees(), next_run_ok(batch_ab)),
            )
        )
    for n in range(3):
        out.append(
            Attempt(
                k,
                f"two exports of two runs to one --out file at once (try {n + 1}): it and its mark agree, a third export not refused",
                ["export", "o/tiny", "--out", "e.json"],
                then(
                    with_run,
                    other_run("p"),
                    beside("other", "export", "p/tiny", "--out", "e.json", delay=0.02 * n),
                ),
                (0, 3),
                message_if_3=r"e\.json",
                timeout=300,
                after=then_check(ended("other", (0, 3)), next_run_ok(["export", "o/tiny", "--out", "e.json"])),
            )
        )
    out.append(
        Attempt(
            k,
            "two render --out fig of two runs at once: fig one render's whole, a third render --out fig not refused",
            ["render", "o/tiny", "--out", "fig", "--size", "64x36"],
            then(
                with_run,
                under({}, "run", "s.yaml", "--out", "p", "--no-video", "-q"),
                beside("other", "render", "p/tiny", "--out", "fig", "--size", "64x36"),
            ),
            (0,),
            timeout=300,
            after=then_check(ended("other"), next_run_ok(["render", "o/tiny", "--out", "fig", "--size", "64x36"])),
        )
    )
    out.append(
        Attempt(
            k,
            "two schema --out s.json at once, then a third: not refused",
            ["schema", "--out", "s.json"],
            beside("other", "schema", "--out", "s.json"),
            (0,),
            after=then_check(ended("other"), next_run_ok(["schema", "--out", "s.json"])),
        )
    )
    # two batches of other scenes (no run folder in common: no lock makes them take turns) ending at
    # the same moment into one OUT: index.csv and its mark written by both, unlocked
    names = {n: TINY.replace("name: tiny", f"name: {n}") for n in ("x1", "x2", "y1", "y2")}
    xs = ["run", "x1.yaml", "x2.yaml", "--out", "o", "--no-video", "-q"]
    ys = ["run", "y1.yaml", "y2.yaml", "--out", "o", "--no-video", "-q"]
    for n in range(6):
        out.append(
            Attempt(
                k,
                f"two batches of other scenes into one OUT at once (try {n + 1}): both 0, index.csv and its mark agree",
                xs,
                then(*(tiny_scene(f"{m}.yaml", t) for m, t in names.items()), beside("other", *ys, delay=0.02 * n)),
                (0,),
                timeout=300,
                after=then_check(ended("other"), next_run_ok(xs)),
            )
        )
    sweep_y = ["sweep", "y1.yaml", "--set", "solver.step=0.1,0.2", "--out", "o", "-q", "--jobs", "1"]
    for n in range(3):
        out.append(
            Attempt(
                k,
                f"a sweep and a batch of other scenes into one OUT at once (try {n + 1}): both 0, index.csv and its mark agree",
                xs,
                then(
                    *(tiny_scene(f"{m}.yaml", t) for m, t in names.items()), beside("other", *sweep_y, delay=0.03 * n)
                ),
                (0,),
                timeout=300,
                after=then_check(ended("other"), next_run_ok(xs)),
            )
        )
    for attempt in out:
        attempt.litter_in = ()  # the attempt's own check would see the other command's live staging folder
    return out


# ------------------------------------------------------------------ the nineteenth campaign: var19

NFS_FLOCK_C = r"""
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <sys/file.h>
/* flock as NFS emulates it (a byte-range lock): LOCK_EX needs a file open for writing, else EBADF */
int flock(int fd, int op) {
    static int (*real)(int, int) = 0;
    if (!real) real = (int (*)(int, int))dlsym(RTLD_NEXT, "flock");
    int fl = fcntl(fd, F_GETFL);
    if ((op & LOCK_EX) && fl >= 0 && (fl & O_ACCMODE) == O_RDONLY) { errno = EBADF; return -1; }
    return real(fd, op);
}
"""


def nfs_flock_shim(d: Path) -> None:
    """Setup step: d/nfsflock.so, a preload making ``flock`` behave as NFS's (EBADF on a folder)."""
    write(d / "nfsflock.c", NFS_FLOCK_C)
    subprocess.run(["gcc", "-shared", "-fPIC", "-o", str(d / "nfsflock.so"), str(d / "nfsflock.c"), "-ldl"], check=True)


def restamped(name: str, digest: bool) -> Callable[[Path], None]:
    """Setup step: o/tiny's marker made to record ``name``'s size and time as they are now, and with
    ``digest`` its sha256 too (else the old sha256 is kept: size and time agree, the bytes do not)."""

    def step(d: Path) -> None:
        path = d / "o/tiny" / name
        info = os.stat(path)

        def edit(data: dict) -> None:
            entry = data["files"][name]
            entry["bytes"], entry["mtime_ns"] = info.st_size, info.st_mtime_ns
            if digest:
                h = hashlib.sha256()
                with open(path, "rb") as handle:
                    for block in iter(lambda: handle.read(1 << 22), b""):
                        h.update(block)
                entry["sha256"] = h.hexdigest()

        marker_edited(edit)(d)

    return step


def mark_agrees(path: str) -> Callable[[Path], list[str]]:
    """After: ``path`` and its mark ``.NAME.armanim.json`` agree (size and sha256)."""

    def check(d: Path) -> list[str]:
        import json as _json

        target = d / path
        mark = target.with_name(f".{target.name}.armanim.json")
        if not target.exists() or not mark.exists():
            return [f"{path} or its mark missing"]
        data = target.read_bytes()
        recorded = _json.loads(mark.read_text())
        if recorded.get("bytes") != len(data) or recorded.get("sha256") != hashlib.sha256(data).hexdigest():
            return [f"{path} and its mark disagree (one command's file beside the other's mark)"]
        return []

    return check


def chain_of_links(name: str, target: str, length: int = 100) -> Callable[[Path], None]:
    """Setup step: ``name`` -> name.1 -> ... -> name.{length-1} -> ``target`` (a chain of ``length`` links)."""

    def step(d: Path) -> None:
        names = [name] + [f"{name}.{i}" for i in range(1, length)]
        for here, there in zip(names, [*names[1:], target]):
            os.symlink(there, d / here)

    return step


def chattr_off(*paths: str) -> Callable[[Path], list[str]]:
    """After: ``chattr -i`` on ``paths`` (so the kept folder can be removed later); no problem."""

    def check(d: Path) -> list[str]:
        for p in paths:
            subprocess.run(["chattr", "-i", str(d / p)], capture_output=True)
        return []

    return check


def mode_is(path: str, mode: int) -> Callable[[Path], list[str]]:
    """After: ``path``'s permission bits are still ``mode`` (the user's protection kept)."""

    def check(d: Path) -> list[str]:
        now = os.stat(d / path).st_mode & 0o777
        return [] if now == mode else [f"{path} is now {now:o}, was made {mode:o}"]

    return check


def var19_attempts() -> list[Attempt]:
    """Campaign 19: new variants on what campaign 18's fixes touched: the run folder marker's
    sha256 (a 2 GB sparse file, a FIFO swapped in, a marker of the older format), the lock of a
    folder of marked files (commands at once, a file system whose flock fails on folders as NFS's),
    ``resolved()`` (links into /proc and /dev/fd, a chain of 100 links), the OBJ reader's regular
    expressions (CRLF, tabs, CR alone, UTF-16, a 60 MB ``v`` line, 64 MB of ``v`` lines, ``v`` lines
    of two numbers) and write protection as root (``chmod 444`` marked files, ``chattr +i``)."""
    k = "var19"
    out: list[Attempt] = []
    with_run = lambda d: finished_run(d) and None  # noqa: E731
    with_video_run = lambda d: finished_run(d, video=True) and None  # noqa: E731
    run_v = ["run", "s.yaml", "--out", "o", "-q"]
    two_gb = 2 << 30

    # -------- the marker's sha256
    out.append(
        Attempt(
            k,
            "run with video, animation.mp4 grown to a 2 GB sparse file, the marker restamped with its sha256: the next run replaces it",
            run_v,
            then(
                with_video_run,
                lambda d: os.truncate(d / "o/tiny/animation.mp4", two_gb),
                restamped("animation.mp4", True),
            ),
            (0,),
            timeout=600,
            after=exists("o/tiny/animation.mp4"),
        )
    )
    out.append(
        Attempt(
            k,
            "run with video, animation.mp4 grown to a 2 GB sparse file, the marker's size and time restamped (old sha256): refused",
            run_v,
            then(
                with_video_run,
                lambda d: os.truncate(d / "o/tiny/animation.mp4", two_gb),
                restamped("animation.mp4", False),
            ),
            (3,),
            message=r"changed since",
            keep=("o/tiny",),
            timeout=600,
        )
    )
    out.append(
        Attempt(
            k,
            "run, trajectory.csv made a 2 GB sparse file (marker restamped with its sha256), then render: exit 2 at its size, no wait",
            ["render", "o/tiny", "--size", "64x36"],
            then(
                with_run, lambda d: os.truncate(d / "o/tiny/trajectory.csv", two_gb), restamped("trajectory.csv", True)
            ),
            (2, 3),
            message=r"trajectory\.csv",
            keep=("o/tiny/trajectory.csv",),
            timeout=300,
        )
    )
    swap_fifo = lambda d: ((d / "o/tiny/trajectory.csv").unlink(), os.mkfifo(d / "o/tiny/trajectory.csv"))  # noqa: E731
    out.append(
        Attempt(
            k,
            "run, then trajectory.csv swapped for a FIFO, then run again: refused, no wait, the FIFO kept",
            RUN_NV,
            then(with_run, swap_fifo),
            (3,),
            message=r"changed since",
            keep=("o/tiny",),
            timeout=60,
        )
    )
    out.append(
        Attempt(
            k,
            "run, then trajectory.csv swapped for a FIFO and the marker restamped to its size 0 and time, then run: refused, no wait",
            RUN_NV,
            then(
                with_run,
                swap_fifo,
                lambda d: marker_edited(
                    lambda data: data["files"]["trajectory.csv"].update(
                        bytes=0, mtime_ns=os.lstat(d / "o/tiny/trajectory.csv").st_mtime_ns
                    )
                )(d),
            ),
            (3,),
            message=r"changed since",
            keep=("o/tiny",),
            timeout=60,
        )
    )
    for what in ("render", "export"):
        args = ["render", "o/tiny", "--size", "64x36"] if what == "render" else ["export", "o/tiny"]
        out.append(
            Attempt(
                k,
                f"run, then trajectory.csv swapped for a FIFO, then {what}: exit 2 or 3, no wait, the FIFO kept",
                args,
                then(with_run, swap_fifo),
                (2, 3),
                message=r"trajectory\.csv",
                keep=("o/tiny",),
                timeout=60,
            )
        )
    out.append(
        Attempt(
            k,
            "a marker of the older format (no sha256), summary.json edited in place with its size and time kept: replaced, as documented",
            RUN_NV,
            then(
                with_run,
                marker_edited(lambda data: [s.pop("sha256", None) for s in data["files"].values() if s]),
                inplace_edit("o/tiny/summary.json"),
            ),
            (0,),
            timeout=300,
            after=like_clean_run(),
        )
    )
    for label, value in [
        ("in capitals (the right digest)", "upper"),
        ("null", None),
        ("a list", ["x"]),
    ]:

        def change(data: dict, value: object = value) -> None:
            entry = data["files"]["trajectory.csv"]
            entry["sha256"] = entry["sha256"].upper() if value == "upper" else value

        out.append(
            Attempt(
                k,
                f"a marker whose trajectory.csv sha256 is {label}, then run: replaced or refused, never a traceback",
                RUN_NV,
                then(with_run, marker_edited(change)),
                (0, 3),
                message_if_3=r"changed since|cannot be read",
                timeout=300,
            )
        )

    # -------- the lock of a folder of marked files
    ended = lambda name, codes=(0,): then_check(beside_ended(name, codes), no_litter("o", "g", "."))  # noqa: E731
    fk_png = ["fk", "--angles", "0,30,45", "--links", "1,1,1", "--png", "o/p.png"]
    out.append(
        Attempt(
            k,
            "fk --png o/p.png and schema --out o/s.json at once into one folder: both 0, each file and its mark agree",
            fk_png,
            beside("other", "schema", "--out", "o/s.json"),
            (0,),
            timeout=120,
            after=then_check(ended("other"), mark_agrees("o/p.png"), mark_agrees("o/s.json")),
        )
    )
    out.append(
        Attempt(
            k,
            "two fk --png o/p.png of two poses at once: both 0, the picture and its mark agree, a third not refused",
            fk_png,
            beside("other", "fk", "--angles", "10,-20,5", "--links", "1,1,1", "--png", "o/p.png"),
            (0, 3),
            message_if_3=r"p\.png",
            timeout=120,
            after=then_check(ended("other", (0, 3)), mark_agrees("o/p.png"), next_run_ok(fk_png)),
        )
    )
    batch = ["run", "s.yaml", "a.yaml", "--out", "o", "--no-video", "-q"]
    out.append(
        Attempt(
            k,
            "check --update --golden o while a batch writes o/index.csv: no deadlock, both 0, the index and its mark agree",
            batch,
            then(
                tiny_scene(),
                tiny_scene("a.yaml", OTHER),
                beside("other", "check", "s.yaml", "a.yaml", "--golden", "o", "--update"),
            ),
            (0,),
            timeout=300,
            after=then_check(ended("other"), mark_agrees("o/index.csv"), exists("o/tiny.csv", "o/other.csv")),
        )
    )
    sweep = ["sweep", "s.yaml", "--set", "solver.step=0.1,0.2", "--out", "o", "-q", "--jobs", "1"]
    out.append(
        Attempt(
            k,
            "a sweep into o while check --update --golden o: no deadlock, both 0, the index and its mark agree",
            sweep,
            then(tiny_scene(), beside("other", "check", "s.yaml", "--golden", "o", "--update")),
            (0,),
            timeout=300,
            after=then_check(ended("other"), mark_agrees("o/index.csv"), exists("o/tiny.csv")),
        )
    )
    nfs = {"LD_PRELOAD": "{d}/nfsflock.so"}
    for label, args, made in [
        ("check --update --golden g", ["check", "s.yaml", "--golden", "g", "--update"], ("g/tiny.csv", "g/tiny.json")),
        ("a batch of two scenes into o", batch, ("o/index.csv",)),
        ("schema --out o/s.json", ["schema", "--out", "o/s.json"], ("o/s.json",)),
        ("fk --png o/p.png", fk_png, ("o/p.png",)),
        ("run (its lock file opened for writing)", RUN_NV, ("o/tiny/trajectory.csv",)),
    ]:
        out.append(
            Attempt(
                k,
                f"{label} where flock fails on a folder as on NFS (EBADF): written unlocked, exit 0",
                args,
                then(nfs_flock_shim, tiny_scene(), tiny_scene("a.yaml", OTHER)),
                (0,),
                env=dict(nfs),
                timeout=300,
                after=exists(*made),
            )
        )
    out.append(
        Attempt(
            k,
            "check --update twice at once where flock fails as on NFS: both 0 (a pair one update's)",
            ["check", "s.yaml", "--golden", "g", "--update"],
            then(
                nfs_flock_shim,
                tiny_scene(),
                beside("other", "check", "s.yaml", "--golden", "g", "--update", env=dict(LD_PRELOAD="{d}/nfsflock.so")),
            ),
            (0,),
            env=dict(nfs),
            timeout=300,
            after=then_check(ended("other"), exists("g/tiny.csv", "g/tiny.json")),
        )
    )

    # -------- links into /proc and /dev/fd, a chain of 100
    for label, args in [
        ("schema --out /dev/stdout (a pipe)", ["schema", "--out", "/dev/stdout"]),
        ("fk --png /dev/fd/1 (a pipe)", ["fk", "--angles", "0,0,0", "--links", "1,1,1", "--png", "/dev/fd/1"]),
        ("schema --out /proc/self/s.json", ["schema", "--out", "/proc/self/s.json"]),
    ]:
        out.append(Attempt(k, f"{label}: exit 0 or 3, no traceback", args, codes=(0, 3), timeout=60))
    out.append(
        Attempt(
            k,
            "export --out /dev/fd/1 (a pipe): exit 3, no traceback",
            ["export", "o/tiny", "--out", "/dev/fd/1"],
            with_run,
            (0, 3),
            timeout=120,
        )
    )
    via_proc = "/proc/self/cwd"
    out.append(
        Attempt(
            k,
            "export /proc/self/cwd/o/tiny --out /proc/self/cwd/e.json: exit 0, a JointTrajectory",
            ["export", f"{via_proc}/o/tiny", "--out", f"{via_proc}/e.json"],
            with_run,
            (0,),
            timeout=120,
            after=export_parses("e.json"),
        )
    )
    out.append(
        Attempt(
            k,
            "render /proc/self/cwd/o/tiny: exit 0, the run folder still the next run's to replace",
            ["render", f"{via_proc}/o/tiny", "--size", "64x36"],
            with_run,
            (0,),
            timeout=300,
            after=next_run_ok(),
        )
    )
    out.append(
        Attempt(
            k,
            "view --out a link into /proc/self/fd/0 (stdin /dev/null): exit 3, the link kept",
            ["view", "o/tiny", "--out", "v.html"],
            then(with_run, lambda d: os.symlink("/proc/self/fd/0", d / "v.html")),
            (3,),
            keep=("v.html",),
            timeout=120,
        )
    )
    for label, args, name in [
        ("export --out", ["export", "o/tiny", "--out", "l"], "e.json"),
        ("render --out", ["render", "o/tiny", "--out", "l", "--format", "gif", "--size", "64x36"], "fig"),
        ("fk --png", ["fk", "--angles", "0,0,0", "--links", "1,1,1", "--png", "l"], "p.png"),
    ]:
        out.append(
            Attempt(
                k,
                f"{label} a chain of 100 links to a missing {name}: exit 0 or 3, every link kept, no traceback",
                args,
                then(with_run, chain_of_links("l", name)),
                (0, 3),
                keep=("l", "l.50", "l.99"),
                timeout=120,
            )
        )
    out.append(
        Attempt(
            k,
            "run of a scene named through a chain of 100 links: exit 2 naming it, or 0",
            ["run", "l", "--out", "o", "--no-video", "-q"],
            then(tiny_scene(), chain_of_links("l", "s.yaml")),
            (0, 2),
            message_if_2=r"\bl\b",
            timeout=300,
        )
    )

    # -------- OBJ read by regular expressions
    tri = b"v 0 0 0\nv .05 0 0\nv 0 .05 0\nf 1 2 3\n"
    for label, data, codes in [
        ("CRLF line ends", tri.replace(b"\n", b"\r\n"), (0,)),
        ("v and f lines of tabs", b"v\t0\t0\t0\nv\t.05\t0\t0\nv\t0\t.05\t0\nf\t1\t2\t3\n", (0,)),
        ("f lines ending in a lone \\r before LF and a comment", tri.replace(b"f 1 2 3\n", b"f 1 2 3 \r# c\r\n"), (0,)),
        ("CR alone as line end (classic Mac)", tri.replace(b"\n", b"\r"), (0, 2)),
        ("UTF-16 with a BOM", tri.decode().encode("utf-16"), (0, 2)),
        ("six v lines of two numbers each", b"v 0 0\nv .05 0\nv 0 .05\nv 1 1\nv 2 2\nv 3 3\nf 1 2 3\n", (2,)),
        ("one 60 MB v line", b"v " + b"0.125 " * 10_000_000 + b"\n" + tri, (0, 2)),
        ("64 MB of v lines", b"v 1 2 3\n" * 8_300_000 + tri.replace(b"f 1 2 3", b"f -1 -2 -3"), (0, 2)),
    ]:
        out.append(
            Attempt(
                k,
                f"robots --fit, collision OBJ of {label}",
                ["robots", "--fit", "robot.urdf"],
                urdf_robot(collision=col("m.obj"), files={"m.obj": data}),
                codes,
                message_if_2=r"m\.obj",
                message=r"three numbers" if codes == (2,) else None,
                keep=("m.obj",),
                timeout=300,
            )
        )
    out.append(
        Attempt(
            k,
            "run --viewer, visual OBJ of six v lines of two numbers each: a note, the mesh not drawn from other corners",
            ["run", "s.yaml", "--out", "o", "--no-video", "--viewer"],
            urdf_robot(
                visual=vis("m.obj"), files={"m.obj": b"v 0 0\nv .05 0\nv 0 .05\nv 1 1\nv 2 2\nv 3 3\nf 1 2 3\n"}
            ),
            (0,),
            message=r"three numbers",
            timeout=300,
        )
    )

    # -------- write protection as root
    for label, args, setup, target in [
        (
            "export --out e.json",
            ["export", "o/tiny", "--out", "e.json"],
            then(with_run, lambda d: export_of(d, "e.json")),
            "e.json",
        ),
        ("schema --out s.json", ["schema", "--out", "s.json"], under({}, "schema", "--out", "s.json"), "s.json"),
        ("fk --png p.png", fk_png[:-1] + ["p.png"], under({}, *fk_png[:-1], "p.png"), "p.png"),
        (
            "a batch's o/index.csv",
            batch,
            then(tiny_scene(), tiny_scene("a.yaml", OTHER), under({}, *batch)),
            "o/index.csv",
        ),
    ]:
        out.append(
            Attempt(
                k,
                f"as root, {label} made read-only (chmod 444), then the same command: refused, the file and its mode kept",
                args,
                then(setup, lambda d, t=target: os.chmod(d / t, 0o444)),
                (3,),
                message=r"write-protected|read-only",
                keep=(target,),
                timeout=300,
                after=mode_is(target, 0o444),
            )
        )
    out.append(
        Attempt(
            k,
            "as root, run folder chmod 555, then render into it: refused, the folder kept",
            ["render", "o/tiny", "--size", "64x36"],
            then(with_video_run, lambda d: os.chmod(d / "o/tiny", 0o555)),
            (3,),
            message=r"write-protected|read-only",
            keep=("o/tiny",),
            timeout=300,
            after=lambda d: (os.chmod(d / "o/tiny", 0o755), [])[1],
        )
    )
    out.append(
        Attempt(
            k,
            "as root, the run's animation.mp4 chmod 444, then render: refused, the folder kept",
            ["render", "o/tiny", "--size", "64x36"],
            then(with_video_run, lambda d: os.chmod(d / "o/tiny/animation.mp4", 0o444)),
            (3,),
            message=r"write-protected|read-only",
            keep=("o/tiny",),
            timeout=300,
        )
    )
    for label, args, setup, target in [
        ("o/tiny/summary.json, then run", RUN_NV, with_run, "o/tiny/summary.json"),
        (
            "o/index.csv, then the batch",
            batch,
            then(tiny_scene(), tiny_scene("a.yaml", OTHER), under({}, *batch)),
            "o/index.csv",
        ),
        (
            "s.json, then schema --out s.json",
            ["schema", "--out", "s.json"],
            under({}, "schema", "--out", "s.json"),
            "s.json",
        ),
    ]:
        out.append(
            Attempt(
                k,
                f"as root, chattr +i {label}: refused (exit 3), the file kept",
                args,
                then(setup, lambda d, t=target: subprocess.run(["chattr", "+i", str(d / t)], check=True)),
                (3,),
                keep=(target,),
                timeout=300,
                after=chattr_off(target),
            )
        )
    return out


CLASSES = {
    "mesh": mesh_attempts,
    "frames": frames_attempts,
    "export": export_attempts,
    "nested": nested_attempts,
    "sizes": sizes_attempts,
    "signals": signal_attempts,
    "folders": folders_attempts,
    "inputs": inputs_attempts,
    "mesh10": mesh10_attempts,
    "frames10": frames10_attempts,
    "signals10": signals10_attempts,
    "loss10": loss10_attempts,
    "inputs10": inputs10_attempts,
    "wrong10": wrong10_attempts,
    "mesh11": mesh11_attempts,
    "frames11": frames11_attempts,
    "signals11": signals11_attempts,
    "loss11": loss11_attempts,
    "inputs11": inputs11_attempts,
    "wrong11": wrong11_attempts,
    "mesh12": mesh12_attempts,
    "frames12": frames12_attempts,
    "signals12": signals12_attempts,
    "loss12": loss12_attempts,
    "inputs12": inputs12_attempts,
    "wrong12": wrong12_attempts,
    "mesh13": mesh13_attempts,
    "frames13": frames13_attempts,
    "signals13": signals13_attempts,
    "loss13": loss13_attempts,
    "inputs13": inputs13_attempts,
    "wrong13": wrong13_attempts,
    "mesh14": mesh14_attempts,
    "frames14": frames14_attempts,
    "signals14": signals14_attempts,
    "loss14": loss14_attempts,
    "inputs14": inputs14_attempts,
    "wrong14": wrong14_attempts,
    "mesh15": mesh15_attempts,
    "frames15": frames15_attempts,
    "signals15": signals15_attempts,
    "loss15": loss15_attempts,
    "inputs15": inputs15_attempts,
    "wrong15": wrong15_attempts,
    "perms16": perms16_attempts,
    "env16": env16_attempts,
    "api16": api16_attempts,
    "odd16": odd16_attempts,
    "mesh17": mesh17_attempts,
    "frames17": frames17_attempts,
    "ro17": ro17_attempts,
    "lock17": lock17_attempts,
    "dask17": dask17_attempts,
    "env17": env17_attempts,
    "signals17": signals17_attempts,
    "wrong17": wrong17_attempts,
    "mesh18": mesh18_attempts,
    "frames18": frames18_attempts,
    "export18": export18_attempts,
    "signals18": signals18_attempts,
    "inputs18": inputs18_attempts,
    "wrong18": wrong18_attempts,
    "clock18": clock18_attempts,
    "between18": between18_attempts,
    "concur18": concur18_attempts,
    "var19": var19_attempts,
}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", choices=list(CLASSES), nargs="*", help="run these classes only")
    parser.add_argument("--match", nargs="*", default=None, help="run the attempts whose name holds one of these texts")
    parser.add_argument("--list", action="store_true", help="list the attempts and stop")
    parser.add_argument("--keep", type=Path, default=None, help="keep every attempt's folder here")
    parser.add_argument("--memory", type=float, default=4.0, help="address-space limit of each attempt, GB (default 4)")
    parser.add_argument(
        "--src", type=Path, default=SRC, help="the armanim source to attack (default: this checkout's src)"
    )
    parser.add_argument(
        "--as-user",
        default=None,
        help="run the non-root attempts (perms16) as this user, when the campaign runs as root",
    )
    parser.add_argument(
        "--user-python", default=sys.executable, help="the interpreter those attempts run (the user must reach it)"
    )
    parser.add_argument(
        "--warm-cache",
        type=Path,
        default=None,
        help="numba's cache (NUMBA_CACHE_DIR) of --src, warmed: lock17 and ro17 copy it into their attempts",
    )
    args = parser.parse_args()
    globals()["SRC"] = args.src.resolve()
    globals()["WARM_CACHE"] = args.warm_cache.resolve() if args.warm_cache else None
    if args.as_user:
        import pwd

        entry = pwd.getpwnam(args.as_user)
        globals().update(
            AS_USER=(entry.pw_uid, entry.pw_gid, entry.pw_dir), AS_USER_NAME=args.as_user, USER_PYTHON=args.user_python
        )
    attempts = [a for name, make in CLASSES.items() if not args.only or name in args.only for a in make()]
    if args.match:
        attempts = [a for a in attempts if any(text in a.name for text in args.match)]
    if args.list:
        for a in attempts:
            print(f"{a.kind:<8} {a.name}")
        print(f"{len(attempts)} attempts")
        return 0
    root = Path(args.keep or tempfile.mkdtemp(prefix="armanim-campaign-"))
    root.mkdir(parents=True, exist_ok=True)
    root.chmod(0o755)  # the attempts run as --as-user reach their folders
    tally: dict[str, dict[str, int]] = {}
    for number, attempt in enumerate(attempts):
        folder = root / f"{number:03d}-{re.sub(r'[^a-z0-9]+', '-', attempt.name.lower())[:60]}"
        for name in attempt.env:
            attempt.env[name] = attempt.env[name].replace("{d}", str(folder))
        try:
            verdict, problems, seconds, code = run_attempt(attempt, folder, int(args.memory * 1e9))
        except Exception as exc:  # the attempt's own setup failed: reported, never counted right
            verdict, problems, seconds, code = "setup", [f"{type(exc).__name__}: {exc}"[:300]], 0.0, None
        finally:
            stop_background()
            unmount_under(folder)
        counts = tally.setdefault(attempt.kind, {})
        counts[verdict] = counts.get(verdict, 0) + 1
        print(f"{attempt.kind:<8} {verdict:<9} exit {code!s:>4} {seconds:6.1f} s  {attempt.name}", flush=True)
        for problem in problems:
            print(f"    {problem}", flush=True)
    if not args.keep:
        shutil.rmtree(root, ignore_errors=True)
    verdicts = ("right", "traceback", "hang", "data loss", "wrong", "setup")
    print(f"\n{'class':<8} {'attempts':>8} " + " ".join(f"{v:>9}" for v in verdicts))
    for kind, counts in tally.items():
        print(f"{kind:<8} {sum(counts.values()):>8} " + " ".join(f"{counts.get(v, 0):>9}" for v in verdicts))
    total = {v: sum(c.get(v, 0) for c in tally.values()) for v in verdicts}
    print(f"{'total':<8} {sum(total.values()):>8} " + " ".join(f"{total[v]:>9}" for v in verdicts))
    return 0 if total["right"] == sum(total.values()) else 1


if __name__ == "__main__":
    sys.exit(main())
