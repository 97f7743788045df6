"""A signal sweep: interrupt a real armanim process at chosen moments of its life and check
what it leaves (issue 19). Used by tests/system/test_signal_moments.py (a handful of moments per
command) and benchmarks/signal_campaign.py (many more).

A moment is an event in the process's life, not a time, so that a busy machine moves the
moment, never the verdict: ``start`` (its SIGTERM handler is installed, i.e. the entry
module runs), ``workers`` (a worker process runs), ``ffmpeg`` (an ffmpeg encodes),
``poster`` (the staging folder's last file, ``poster.png``, is being drawn: the commit
follows within tens of milliseconds), ``commit`` (a staged marker
``OUT/.<name>.*.partial/.armanim-run.json`` appears: the swap is imminent; it lasts a few
milliseconds, so polling may miss it), each with an optional delay in seconds after it.

After each attempt:

- the exit status is 0 or 130, and stderr has no traceback;
- every output folder (or golden pair) is byte for byte the previous one or the complete
  new one (both made beforehand), and exit 0 means every one is new;
- no staging or temporary file is left in OUT (``.partial``, ``.old-``, ``.tmp``, ``.part``)
  and nothing in the private TMPDIR;
- no process the attempt started (polled while it ran) is alive afterwards.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path

import psutil

MARKER = ".armanim-run.json"
TIMING_FILE = "timing.json"  # a run's wall times: the one file whose bytes differ from run to run
LITTER = (".partial", ".old-", ".tmp", ".part", ".concat")
HANG_GUARD = 300.0  # seconds: far beyond any unloaded attempt (a few seconds)


def _partial_has(where: Path, moment: str) -> bool:
    """Whether a run's staging folder under ``where/out`` holds the file that marks ``moment``:
    the commit's record, or the poster being drawn (the last file before the commit)."""
    patterns = {"commit": [".armanim-run.json"], "poster": [".poster.png.*", "poster.png"]}[moment]
    try:
        return any(any(where.glob(f"out/.*.partial/{name}")) for name in patterns)
    except FileNotFoundError:  # the run renamed its staging folder while the glob read it: not this time
        return False


def snapshot(folder: Path, *roots: Path) -> dict[str, str]:
    """sha256 of every file below ``folder`` (or of the file ``folder``, or of the files its
    last part matches as a glob: ``golden/tiny0.*``, a golden pair) by relative path ({} if
    it is missing); the paths ``roots`` in a file's bytes are read as ``<ROOT>`` (index.csv
    names each run folder by its path)."""

    def digest(path: Path) -> str:
        if path.name == MARKER:  # its list of files (their times differ from run to run)
            return hashlib.sha256(" ".join(sorted(json.loads(path.read_text())["files"])).encode()).hexdigest()
        if path.name == TIMING_FILE:  # its fields and goals (the wall times differ from run to run)
            timing = json.loads(path.read_text())
            return hashlib.sha256(f"{sorted(timing)} {len(timing['goals'])}".encode()).hexdigest()
        data = path.read_bytes()
        for root in roots:
            data = data.replace(str(root).encode(), b"<ROOT>")
        return hashlib.sha256(data).hexdigest()

    if "*" in folder.name:
        return {p.name: digest(p) for p in sorted(folder.parent.glob(folder.name)) if p.is_file()}
    if folder.is_file():
        return {folder.name: digest(folder)}
    if not folder.exists():
        return {}
    return {str(p.relative_to(folder)): digest(p) for p in sorted(folder.rglob("*")) if p.is_file()}


def _catches_sigterm(pid: int) -> bool:
    """Whether process ``pid`` has a handler for SIGTERM (/proc/PID/status SigCgt)."""
    try:
        for line in Path(f"/proc/{pid}/status").read_text().splitlines():
            if line.startswith("SigCgt:"):
                return bool(int(line.split()[1], 16) >> (signal.SIGTERM - 1) & 1)
    except OSError:
        pass
    return False


@dataclass
class Command:
    """One armanim command to interrupt: its arguments (``{out}``, ``{golden}`` are filled in),
    and the folders (relative to the attempt's folder; a glob such as ``golden/tiny0.*`` for a
    golden pair) that must each be old or new afterwards."""

    name: str
    args: list[str]
    folders: list[str]
    prepare_args: list[list[str]] = field(default_factory=list)  # commands that make the "previous" outputs


@dataclass
class Outcome:
    moment: str
    signame: str
    code: int
    stderr: str
    states: dict[str, str]  # folder -> "old", "new" or "mixed"
    litter: list[str]
    strays: list[str]
    fired: bool  # the moment came before the process ended

    def problems(self) -> list[str]:
        """What is wrong with this outcome (empty when it is right)."""
        found = []
        if self.code not in (0, 130):
            found.append(f"exit {self.code}")
        if "Traceback" in self.stderr or "Exception ignored" in self.stderr:
            found.append("a traceback on stderr")
        if any(state == "mixed" for state in self.states.values()):
            found.append(f"a folder neither old nor new: {self.states}")
        if self.code == 0 and any(state != "new" for state in self.states.values()):
            found.append(f"exit 0 but not every folder new: {self.states}")
        if self.litter:
            found.append(f"litter: {self.litter}")
        if self.strays:
            found.append(f"processes left: {self.strays}")
        return found


class Sweep:
    """Prepares, for one command, the previous outputs and the complete new ones, then
    interrupts copies of the previous state at chosen moments."""

    def __init__(self, command: Command, root: Path, python: str = sys.executable):
        self.command, self.root, self.python = command, Path(root), python
        self.template = self.root / "template"
        self.expected_new = self.root / "new"
        self.count = 0
        self.template.mkdir(parents=True)
        for args in command.prepare_args:
            self._run(args, self.template)
        shutil.copytree(self.template, self.expected_new)  # as each attempt starts: from a copy of the previous state
        self._run(command.args, self.expected_new)
        self.old = {f: snapshot(self.template / f, self.template) for f in command.folders}
        self.new = {f: snapshot(self.expected_new / f, self.expected_new, self.template) for f in command.folders}

    def _fill(self, args: list[str], where: Path) -> list[str]:
        return [a.format(out=where / "out", golden=where / "golden") for a in args]

    def _run(self, args: list[str], where: Path) -> None:
        proc = subprocess.run(
            [self.python, "-m", "armanim", *self._fill(args, where)], capture_output=True, text=True, timeout=HANG_GUARD
        )
        assert proc.returncode == 0, proc.stderr

    def attempt(self, moment: str, delay: float, signame: str, again: float | None = None) -> Outcome:
        """Run the command in a copy of the previous state; signal it at ``moment`` + ``delay`` s
        (and, with ``again``, a second time that many seconds later: a double Ctrl-C)."""
        self.count += 1
        where = self.root / f"attempt{self.count}"
        shutil.copytree(self.template, where)
        tmp = Path(tempfile.mkdtemp(prefix="sig", dir="/tmp"))  # short: the forkserver's socket lives there
        env = {**os.environ, "TMPDIR": str(tmp)}
        proc = psutil.Popen(
            [self.python, "-m", "armanim", *self._fill(self.command.args, where)],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.PIPE,
            text=True,
            start_new_session=True,
            env=env,
        )
        seen: dict[int, psutil.Process] = {}
        stop_polling = threading.Event()

        def poll() -> None:  # every process the attempt starts, to check none is left
            while not stop_polling.is_set():
                try:
                    for kid in proc.children(recursive=True):
                        seen.setdefault(kid.pid, kid)
                except psutil.Error:
                    pass
                stop_polling.wait(0.02)

        poller = threading.Thread(target=poll, daemon=True)
        poller.start()
        fired = self._wait_for(moment, proc, where, seen)
        if fired:
            time.sleep(delay)
            sig = getattr(signal, signame)
            for pause in [0.0] if again is None else [0.0, again]:
                time.sleep(pause)
                try:
                    if signame == "SIGINT":
                        os.killpg(proc.pid, sig)  # a terminal's Ctrl-C: the whole group
                    else:
                        proc.send_signal(sig)  # kill: armanim alone
                except (ProcessLookupError, psutil.NoSuchProcess):
                    fired = fired and pause > 0
        try:
            _, stderr = proc.communicate(timeout=HANG_GUARD)
        finally:
            stop_polling.set()
            poller.join()
            if proc.poll() is None:  # pragma: no cover  (the hang guard)
                os.killpg(proc.pid, signal.SIGKILL)
        _, alive = psutil.wait_procs(list(seen.values()), timeout=60)  # a hang guard: they go at once
        strays = [f"{p.pid} {p.name()}" for p in alive if p.is_running() and p.status() != psutil.STATUS_ZOMBIE]
        states = {f: self._state(where, f) for f in self.command.folders}
        litter = [str(p.relative_to(where)) for p in where.rglob("*") if any(mark in p.name for mark in LITTER)]
        litter += [f"$TMPDIR/{p.name}" for p in tmp.iterdir()]
        shutil.rmtree(tmp, ignore_errors=True)
        outcome = Outcome(
            f"{moment}+{delay:g}" + ("" if again is None else f" twice ({again:g} s apart)"),
            signame,
            proc.returncode,
            stderr,
            states,
            litter,
            strays,
            fired,
        )
        if not outcome.problems():
            shutil.rmtree(where, ignore_errors=True)
        return outcome

    def _state(self, where: Path, name: str) -> str:
        now = snapshot(where / name, where, self.template)  # the previous files were made in the template
        return "old" if now == self.old[name] else "new" if now == self.new[name] else "mixed"

    def _wait_for(self, moment: str, proc: psutil.Popen, where: Path, seen: dict) -> bool:
        """Wait until ``moment`` comes (True) or the process ends first (False)."""
        deadline = time.monotonic() + HANG_GUARD
        while proc.poll() is None and time.monotonic() < deadline:
            if self._came(moment, proc, where, seen):
                return True
            time.sleep(0.005)
        return False

    def _came(self, moment: str, proc: psutil.Popen, where: Path, seen: dict) -> bool:
        if moment == "start":
            return _catches_sigterm(proc.pid)
        if moment in ("commit", "poster"):
            return _partial_has(where, moment)
        try:
            kids = list(seen.values())
            if moment == "workers":  # a pool's helpers (forkserver, resource tracker) are not workers
                helper = ("forkserver", "resource_tracker")
                return any(
                    "python" in k.name()
                    and (k.ppid() != proc.pid or not any(h in " ".join(k.cmdline()) for h in helper))
                    for k in kids
                    if k.is_running()
                )
            if moment == "ffmpeg":
                return any("ffmpeg" in k.name() for k in kids if k.is_running())
        except psutil.Error:
            return False
        raise ValueError(f"unknown moment {moment!r}")
