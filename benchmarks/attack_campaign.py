"""The ninth attack campaign (issue 50): hostile inputs, interrupts and outputs, as a script.

Run: ``python benchmarks/attack_campaign.py`` (some 20-40 minutes on two shared cores),
``--only CLASS`` for one class (mesh, frames, export, nested, sizes, signals, folders, inputs),
``--match TEXT`` for the attempts whose name holds TEXT, ``--list`` to list them, ``--keep DIR``
to keep every attempt's folder.

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
    interrupt: tuple[float, str] | None = None  # (seconds, "SIGINT" to the group | "SIGTERM" to armanim)
    env: dict[str, str] = field(default_factory=dict)
    after: Callable[[Path], list[str]] | None = None  # more checks: a list of problems
    litter_in: tuple[str, ...] = ("o",)  # folders where outputs go: no staging or temporary file left


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


def _limits(memory: int) -> Callable[[], None]:
    def apply() -> None:
        os.setsid()
        os.nice(10)
        resource.setrlimit(resource.RLIMIT_AS, (memory, memory))

    return apply


def run_attempt(attempt: Attempt, folder: Path, memory: int) -> tuple[str, list[str], float, int | None]:
    """Run one attempt in ``folder``: (verdict class, problems, seconds, exit code)."""
    folder.mkdir(parents=True)
    attempt.setup(folder)
    kept = {p: fingerprint(folder / p) for p in attempt.keep}
    args = [a.replace("{d}", str(folder)) for a in attempt.args]
    env = dict(os.environ, PYTHONPATH=str(SRC), COLUMNS="120", **attempt.env)
    started = time.perf_counter()
    proc = subprocess.Popen(
        [sys.executable, "-m", "armanim", *args],
        cwd=folder,
        env=env,
        stdin=subprocess.DEVNULL,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        errors="replace",
        preexec_fn=_limits(memory),
    )
    if attempt.interrupt is not None:
        delay, signame = attempt.interrupt
        try:
            proc.wait(delay)
        except subprocess.TimeoutExpired:
            if signame == "SIGINT":
                os.killpg(proc.pid, signal.SIGINT)
            else:
                proc.send_signal(signal.SIGTERM)
    hung = False
    try:
        out, err = proc.communicate(timeout=attempt.timeout)
    except subprocess.TimeoutExpired:
        hung = True
        os.killpg(proc.pid, signal.SIGKILL)
        out, err = proc.communicate()
    seconds = time.perf_counter() - started
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
    for path, before in kept.items():
        if fingerprint(folder / path) != before:
            problems.append(f"{path} changed")
            verdict = "data loss"
    for where in attempt.litter_in:
        base = folder / where
        if base.is_dir():
            litter = [str(p.relative_to(folder)) for p in base.rglob("*") if LITTER.search(p.name)]
            if litter:
                problems.append(f"litter: {litter[:4]}")
    if attempt.after is not None:
        problems += attempt.after(folder)
    if problems and verdict == "right":
        verdict = "wrong"
    if problems and not text.strip() == "":
        problems.append("said: " + " | ".join(text.strip().splitlines()[-3:])[:400])
    return verdict, problems, seconds, proc.returncode


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


def urdf_robot(visual: str = "", collision: str | None = None, files: dict[str, bytes | str | None] | None = None):
    """Setup: robot.urdf and s.yaml, and ``files`` (None: a FIFO)."""

    def setup(d: Path) -> None:
        write(d / "robot.urdf", urdf_text(visual, collision))
        write(d / "s.yaml", URDF_SCENE)
        for name, content in (files or {}).items():
            if content is None:
                fifo(d / name)
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


CLASSES = {
    "mesh": mesh_attempts,
    "frames": frames_attempts,
    "export": export_attempts,
    "nested": nested_attempts,
    "sizes": sizes_attempts,
    "signals": signal_attempts,
    "folders": folders_attempts,
    "inputs": inputs_attempts,
}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", choices=list(CLASSES), nargs="*", help="run these classes only")
    parser.add_argument("--match", default=None, help="run the attempts whose name holds this text")
    parser.add_argument("--list", action="store_true", help="list the attempts and stop")
    parser.add_argument("--keep", type=Path, default=None, help="keep every attempt's folder here")
    parser.add_argument("--memory", type=float, default=4.0, help="address-space limit of each attempt, GB (default 4)")
    parser.add_argument(
        "--src", type=Path, default=SRC, help="the armanim source to attack (default: this checkout's src)"
    )
    args = parser.parse_args()
    globals()["SRC"] = args.src.resolve()
    attempts = [a for name, make in CLASSES.items() if not args.only or name in args.only for a in make()]
    if args.match:
        attempts = [a for a in attempts if args.match in a.name]
    if args.list:
        for a in attempts:
            print(f"{a.kind:<8} {a.name}")
        print(f"{len(attempts)} attempts")
        return 0
    root = Path(args.keep or tempfile.mkdtemp(prefix="armanim-campaign-"))
    tally: dict[str, dict[str, int]] = {}
    for number, attempt in enumerate(attempts):
        folder = root / f"{number:03d}-{re.sub(r'[^a-z0-9]+', '-', attempt.name.lower())[:60]}"
        for name in attempt.env:
            attempt.env[name] = attempt.env[name].replace("{d}", str(folder))
        try:
            verdict, problems, seconds, code = run_attempt(attempt, folder, int(args.memory * 1e9))
        except Exception as exc:  # the attempt's own setup failed: reported, never counted right
            verdict, problems, seconds, code = "setup", [f"{type(exc).__name__}: {exc}"[:300]], 0.0, None
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
