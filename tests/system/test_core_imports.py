"""The pure core imports no edge library, and the rooms import one way (design.md).

The pure core is every module under ``armanim.arm``, ``armanim.world`` and
``armanim.motion``: numpy, scipy.linalg (the pseudo-inverse's SVD, imported at the first
solve), DAQP, OMPL and numba (the compiled closed form) only. Rooms are ordered
cli > runs > scene > render > output > procs > motion > world > arm, and a module imports only
from its own room or the rooms below it (``errors`` and ``names`` serve all). Inside
``render`` and ``motion``, the sub-rooms are ordered the same way (:data:`RENDER_ROOMS`,
:data:`MOTION_ROOMS`; a module directly in the room is a sub-room of its own).
"""

from __future__ import annotations

import ast
import json
import subprocess
import sys
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[2] / "src" / "armanim"
CORE_ROOMS = ["arm", "world", "motion"]
ROOMS = ["cli", "runs", "scene", "render", "output", "procs", "motion", "world", "arm"]  # top to bottom
RENDER_ROOMS = [
    "viewer",
    "video",
    "pictures",
    "overlay",
    "solids",
    "camera",
    "paint",
    "settings",
]  # render's, top to bottom
MOTION_ROOMS = [
    "timing",
    "trajectory",
    "paths",
    "stalls",
    "framestep",
    "ik",
    "planning",
    "kernels",
    "filter",
    "solvers",
    "cost",
    "solution",
    "carry",
    "problem",
    "toolpath",
    "orientation",
    "tunables",
]  # motion's, top to bottom
MOTION_UPWARD = {
    (
        "problem",
        "kernels",
    ): "Problem.kernel and Problem.compiled_plans build the kernels' layout on first use (a lazy import)",
}
"""The imports back up inside ``motion`` that are known, each with why: none may be added."""
SHARED = {"errors", "names", "__init__", "__main__"}
FORBIDDEN = ["matplotlib", "yaml", "pydantic", "typer", "rich", "click", "imageio"]


def _modules(room: str) -> list[str]:
    return sorted(
        "armanim." + ".".join(p.relative_to(SRC).with_suffix("").parts).removesuffix(".__init__")
        for p in (SRC / room).rglob("*.py")
    )


COMPILED = (
    "armanim.arm.kernel",
    "armanim.world.compiled",
    "armanim.motion.timing.passes",
    "armanim.motion.kernels.linalg",
    "armanim.motion.kernels.tasks",
    "armanim.motion.kernels.check",
    "armanim.motion.kernels.qp",
    "armanim.motion.kernels.attempt",
    "armanim.motion.kernels.frame",
    "armanim.motion.planning.check",
    "armanim.render.solids.rasterloops",
)
"""The modules that import numba, which loads pyyaml for its own settings and scipy when
installed: left out of the walks below (:func:`test_numba_loads_only_for_boxes_and_capsules`
holds it to the runs that need it)."""


def test_core_loads_no_edge_library():
    core = [m for room in CORE_ROOMS for m in _modules(room) if m not in COMPILED]
    assert len(core) > 20  # the walk found the rooms
    code = (
        "import importlib, json, sys\n"
        f"for m in {core!r}: importlib.import_module(m)\n"
        f"print(json.dumps(sorted(m for m in {FORBIDDEN!r} if m in sys.modules)))\n"
        "print(json.dumps(sorted(sys.modules)))\n"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    loaded, modules = (json.loads(line) for line in proc.stdout.splitlines())
    assert loaded == [], loaded
    assert "armanim.arm.kinematics" in modules and "numpy" in modules  # the imports did happen
    edges = ("armanim.scene", "armanim.render", "armanim.cli", "armanim.runs", "armanim.output", "armanim.procs")
    assert not [m for m in modules if m.startswith(edges)]


def test_no_module_of_armanim_imports_a_library_it_does_not_declare():
    """No module of armanim loads scipy when imported (scipy.linalg is the pseudo-inverse's
    SVD, imported at the first solve: :func:`test_commands_that_never_solve_never_import_scipy`),
    nor a test extra's library (oracles): a fresh install without the test extra runs every command."""
    modules = [m for room in ROOMS for m in _modules(room) if m not in COMPILED] + ["armanim", "armanim.testing"]
    code = (
        "import importlib, sys\n"
        f"for m in {modules!r}: importlib.import_module(m)\n"
        "print(sorted(m for m in ('scipy', 'pinocchio', 'coal', 'hypothesis', 'playwright', 'psutil') if m in sys.modules))\n"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "[]"


@pytest.mark.parametrize(
    "args",
    [
        ["--version"],
        ["schema"],
        ["validate", "scenes/notes-arm.yaml"],
        ["validate", "scenes/panda-place.yaml"],
        ["fk", "--angles", "0,30,45,10", "--links", "2,5,5,5"],
        ["fk", "--robot", "panda", "--angles=0,-45,0,-135,0,90,45"],
    ],
    ids=lambda a: "-".join(a[:2]),
)
def test_commands_that_never_solve_never_import_scipy(args):
    """scipy.linalg costs about 0.3 s to import (benchmarks/README.md): only a solve pays it.
    The command runs with scipy unimportable (numba, which some of them load for the arm's own
    distances, imports scipy only when it can: with scipy installed it pays for it anyway)."""
    out = _command_in_a_fresh_python(
        args,
        "print(result.exit_code, repr(result.exception))",
        before="sys.modules['scipy'] = None  # any import of scipy fails",
    )
    assert out.strip() == "0 None"


def _command_in_a_fresh_python(args: list[str], report: str, before: str = "") -> str:
    """What ``report`` prints (Python, after ``result`` holds the command's CliRunner result, with
    ``sys`` imported) after ``armanim args`` ran in a fresh interpreter, ``before`` run first."""
    code = "\n".join(
        [
            "import sys",
            before,
            "from typer.testing import CliRunner",
            "from armanim.cli import app",
            f"result = CliRunner().invoke(app, {args!r})",
            report,
            "",
        ]
    )
    proc = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=120, cwd=SRC.parent.parent
    )
    assert proc.returncode == 0, proc.stderr
    return proc.stdout


@pytest.mark.parametrize(
    "args",
    [
        ["fk", "--angles", "0,30,45,10", "--links", "2,5,5,5"],
        ["fk", "--robot", "panda", "--angles=0,-45,0,-135,0,90,45"],
    ],
    ids=lambda a: "-".join(a[:3]),
)
def test_fk_never_loads_numba(args):
    """One pose's FK needs neither the compiled kernels nor the arm's own pairs: an arm of links
    would sample its self-collision matrix with the compiled closed form (numba's import and its
    first cache load, some 0.4 s of a 0.3 s command, benchmarks/README.md)."""
    out = _command_in_a_fresh_python(
        args, "print(result.exit_code, 'numba' in sys.modules, 'armanim.world.selfcollision' in sys.modules)"
    )
    assert out.split() == ["0", "False", "True"]  # the module is imported, its sampling never runs


def test_a_solve_loads_scipy_linalg():
    code = (
        "import sys\n"
        "import numpy as np\n"
        "from armanim.arm.linalg import pseudo_inverse\n"
        "print('scipy.linalg' in sys.modules)\n"
        "pseudo_inverse(np.eye(3))\n"
        "print('scipy.linalg' in sys.modules)\n"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.split() == ["False", "True"]


def _imported_rooms(path: Path) -> set[str]:
    tree = ast.parse(path.read_text())
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names.add(node.module)
        elif isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
    return {n.split(".")[1] for n in names if n.startswith("armanim.") and n.count(".") >= 1}


@pytest.mark.parametrize("room", ROOMS)
def test_imports_run_down_the_rooms(room):
    above = set(ROOMS[: ROOMS.index(room)])
    wrong = {str(p.relative_to(SRC)): sorted(_imported_rooms(p) & above) for p in (SRC / room).rglob("*.py")}
    assert {k: v for k, v in wrong.items() if v} == {}


def _imported_sub_rooms(path: Path, room: str) -> set[str]:
    """The sub-rooms of ``armanim.<room>`` a module imports (``from armanim.<room> import x``
    names sub-room ``x``)."""
    rooms = set()
    top = f"armanim.{room}"
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and node.module == top and node.level == 0:
            rooms.update(alias.name for alias in node.names)
        names = [node.module] if isinstance(node, ast.ImportFrom) and node.module and node.level == 0 else []
        names += [alias.name for alias in node.names] if isinstance(node, ast.Import) else []
        rooms.update(n.split(".")[2] for n in names if n.startswith(top + "."))
    return rooms


def _sub_room(path: Path, room: str) -> str:
    return path.relative_to(SRC / room).with_suffix("").parts[0]


@pytest.mark.parametrize("room, order", [("render", RENDER_ROOMS), ("motion", MOTION_ROOMS)])
def test_every_module_is_in_an_ordered_sub_room(room, order):
    rooms = {_sub_room(p, room) for p in (SRC / room).rglob("*.py")} - {"__init__"}
    assert rooms == set(order)


@pytest.mark.parametrize(
    "room, sub, order, allowed",
    [("render", sub, RENDER_ROOMS, {}) for sub in RENDER_ROOMS]
    + [("motion", sub, MOTION_ROOMS, MOTION_UPWARD) for sub in MOTION_ROOMS],
)
def test_imports_run_down_the_sub_rooms(room, sub, order, allowed):
    above = set(order[: order.index(sub)])
    paths = [p for p in (SRC / room).rglob("*.py") if _sub_room(p, room) == sub]
    assert paths
    wrong = {
        str(p.relative_to(SRC)): sorted(r for r in _imported_sub_rooms(p, room) & above if (sub, r) not in allowed)
        for p in paths
    }
    assert {k: v for k, v in wrong.items() if v} == {}


def test_the_known_imports_back_up_in_motion_are_still_there():
    """An allowed import back up that is gone leaves :data:`MOTION_UPWARD` (it may not come back unseen)."""
    for sub, up in MOTION_UPWARD:
        paths = [p for p in (SRC / "motion").rglob("*.py") if _sub_room(p, "motion") == sub]
        assert any(up in _imported_sub_rooms(p, "motion") for p in paths), (sub, up)


def test_the_cli_asks_the_rooms_below_and_never_the_core_directly():
    """``armanim`` commands are thin: they parse flags and print answers of the silent API
    (``runs``, ``scene``, ``render``, ``output``), never calling the pure core themselves."""
    core = ("armanim.motion", "armanim.arm", "armanim.world")
    found = {}
    for path in (SRC / "cli").rglob("*.py"):
        tree = ast.parse(path.read_text())
        names = [n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom) and n.module]
        names += [a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names]
        wrong = sorted(n for n in names if n.startswith(core))
        if wrong:
            found[path.name] = wrong
    assert len(list((SRC / "cli").rglob("*.py"))) > 10  # the walk found the commands
    assert found == {}


def test_the_top_holds_only_the_shared_modules():
    top = {p.stem for p in SRC.glob("*.py")}
    assert top == SHARED | {"testing"}, top


def test_numba_loads_only_for_boxes_and_capsules():
    """numba is imported by the compiled closed form (on the first box) and the clock's passes
    (when a run is retimed) only: every other module, and distances among spheres only, start
    without its 0.2 s import (fk, validate, the planner's checks)."""
    modules = [m for room in ROOMS for m in _modules(room) if m not in COMPILED] + ["armanim", "armanim.testing"]
    code = (
        "import importlib, sys\n"
        "import numpy as np\n"
        f"for m in {modules!r}: importlib.import_module(m)\n"
        "from armanim.arm.capsules import joint_capsules\n"
        "from armanim.arm.kinematics import Arm, forward\n"
        "from armanim.world.distances import clearances\n"
        "from armanim.world.obstacles import Obstacles\n"
        "arm = Arm.from_names([2, 5])\n"
        "pose = forward(arm, np.zeros(2))\n"
        "clearances(pose, Obstacles(np.array([[3.0, 3, 3]]), np.ones(1), np.ones(1)), joint_capsules(arm, 0.1))\n"
        "print('numba' in sys.modules)\n"
        "clearances(pose, Obstacles(np.zeros((0, 3)), np.zeros(0), np.zeros(1), floor=-1.0), joint_capsules(arm, 0.1))\n"
        "print('numba' in sys.modules)\n"
        "from armanim.world.obstacles import Boxes\n"
        "box = Boxes(np.array([[3.0, 3, 3]]), np.ones((1, 3)), np.eye(3)[None])\n"
        "clearances(pose, Obstacles(np.zeros((0, 3)), np.zeros(0), np.ones(1), boxes=box), joint_capsules(arm, 0.1))\n"
        "print('numba' in sys.modules)\n"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.split() == ["False", "False", "True"]


def test_version_imports_neither_numpy_nor_the_command_line_libraries():
    """``armanim --version`` answers before numpy, typer and rich are imported (0.1 s of
    start-up, benchmarks/README.md), with the very line the app's own ``--version`` prints."""
    code = (
        "import sys\n"
        "sys.argv = ['armanim', '--version']\n"
        "from armanim.__main__ import main\n"
        "main()\n"
        "print(sorted(m for m in ('numpy', 'typer', 'rich', 'pydantic', 'yaml') if m in sys.modules))\n"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    line, loaded = proc.stdout.splitlines()
    assert loaded == "[]"
    from typer.testing import CliRunner

    from armanim.cli import app

    assert CliRunner().invoke(app, ["--version"]).stdout == line + "\n"


@pytest.mark.parametrize("args", [["--version"], ["validate", "scenes/notes-arm.yaml"]], ids=lambda a: a[0])
def test_commands_that_draw_nothing_never_import_rich_tables_or_progress_bars(args):
    """The command line imports numpy, rich's tables and progress bars where a command uses them."""
    code = (
        "import sys\n"
        "from typer.testing import CliRunner\n"
        "from armanim.cli import app\n"
        f"result = CliRunner().invoke(app, {args!r})\n"
        "print(result.exit_code, sorted(m for m in ('rich.table', 'rich.progress') if m in sys.modules))\n"
    )
    proc = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=120, cwd=SRC.parent.parent
    )
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "0 []"
