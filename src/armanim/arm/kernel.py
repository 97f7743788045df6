"""The kinematics of one pose, compiled (numba): joint points and frames, the tool frame, the
6 x n geometric Jacobian and the rotation log, for one pose or a batch.

The same chain as :func:`armanim.arm.kinematics.forward` (which stays the reference: the tests
hold these to it within 1e-12), written as scalar loops: one Panda pose costs some 2 us here
against 50 us as numpy array operations, most of which was the fixed cost of each small numpy
call. The arm's constants are packed once into two arrays (:func:`packed_chain`), so a call
passes three arrays to numba. Rodrigues' formula and the cross products are the same
operations in the same order as the numpy code; a 3 x 3 product may differ from numpy's (BLAS)
in the last bit.

numba compiles on first use and caches the machine code beside this file, in
``NUMBA_CACHE_DIR`` or the user's cache folder (or nowhere when none is writable: then each
process compiles again). This module is imported where a solve starts, never by ``fk``,
``validate`` or ``--version``. Pure core: numpy and numba only, radians.
"""

from __future__ import annotations

import contextlib
import hashlib
import math
import os
import threading
import time
import warnings
from collections.abc import Callable, Iterator
from typing import Any, TypeVar, cast

import numba
import numba.core.caching
import numba.core.registry
import numba.core.sigutils
import numpy as np

from armanim.arm.kinematics import Arm, Pose, kind_axes

F = TypeVar("F", bound=Callable[..., Any])


def compiled(**options: Any) -> Callable[[F], F]:
    """``numba.njit(**options)`` with its machine code cached on disk where numba finds a
    writable folder (beside the module, ``NUMBA_CACHE_DIR`` or the user's cache folder), and
    compiled afresh in each process where it finds none (a read-only install run by a user
    without a writable home: numba refuses ``cache=True`` there instead of going without).
    The cached code is kept only while every module of :data:`COMPILED_MODULES` is unchanged
    (:func:`stamp_cache`)."""

    def compile_(function: F) -> F:  # numba's dispatcher is called as the function is (numba ships no types)
        _jit_enabled()
        try:
            dispatcher = numba.njit(cache=True, **options)(function)
        except RuntimeError as error:
            if "no locator available" not in str(error):
                raise
            global CODE_KEPT
            CODE_KEPT = False
            return cast(F, numba.njit(cache=False, **options)(function))
        stamp_cache(dispatcher, sources_stamp(COMPILED_MODULES))
        load_lightly(dispatcher)
        compile_once_among_processes(dispatcher)
        return cast(F, dispatcher)

    return compile_


CODE_KEPT = True
"""False once numba could not keep a compiled function's machine code (no writable folder for its
cache, or a write to it failed: a full disk): this process's compiling is then not "once after
installing", the next one compiles again."""


def _jit_enabled() -> None:
    """numba's ``DISABLE_JIT`` turned off, with a warning, before armanim's kernels are made.

    ``NUMBA_DISABLE_JIT=1`` makes numba return plain Python functions, which armanim's kernels are
    not written for: under numba's numpy error model x / 0 is inf or NaN, plain Python raises
    (campaign 15's command, campaign 16's Python API: ``run_scene`` ended in a ZeroDivisionError).
    numba reads the setting again as each kernel compiles (its own implementations of numpy's
    functions are made then), so it stays off from here on in this process; a program's functions
    decorated before armanim was imported stay uncompiled. The command drops the variable before
    numba is imported (``armanim.__main__``) and never gets here with it on."""
    config: Any = numba.core.config  # numba's settings, read from the environment (untyped)
    if config.DISABLE_JIT:
        config.DISABLE_JIT = False
        warnings.warn(
            "NUMBA_DISABLE_JIT is ignored from here on: armanim's numerical code runs compiled only",
            stacklevel=3,
        )


class _LoadsLightly(numba.core.caching.FunctionCache):
    """numba's cache of one function, loading its machine code without importing numba's compilers.

    Before loading a cached function numba refreshes its whole target (imports and registers the
    implementations of numpy's linear algebra, random generators, polynomials, typed containers,
    ...: some 0.2 s of CPU, the most of a small run's time in numba), which only a compile needs.
    Loading needs numba's runtime (its reference counts), initialised here. A compile (a miss)
    refreshes the target itself, as before."""

    def save_overload(self, sig: Any, data: Any) -> None:
        """numba's, with two changes. The index (every signature's entry, read, added to and written
        again) is written under the kernel's lock: two processes saving two signatures at once would
        otherwise keep one of them. A write that fails (a full disk; a cache folder made read-only
        since) only leaves the machine code unkept: numba raised it, and every command that compiled
        ended in exit 3 (campaign 16: ``validate`` with ``NUMBA_CACHE_DIR`` on a full disk)."""
        save: Any = super().save_overload  # numba's own, untyped
        index = getattr(getattr(self, "_cache_file", None), "_index_path", None)
        try:
            if not isinstance(index, str):
                save(sig, data)
                return
            with held_alone(lock_beside(index)):
                save(sig, data)
        except OSError:
            global CODE_KEPT
            CODE_KEPT = False

    def load_overload(self, sig: Any, target_context: Any) -> Any:
        from numba.core.runtime.nrt import rtsys

        rtsys.initialize(target_context)
        with self._guard_against_spurious_io_errors():
            load: Any = self._load_overload  # numba's own, untyped
            return load(sig, target_context)


def load_lightly(dispatcher: Any) -> None:
    """Load ``dispatcher``'s cached machine code as :class:`_LoadsLightly` does, where numba keeps
    the cache as this version of numba does (else nothing changes)."""
    cache = getattr(dispatcher, "_cache", None)
    if type(cache) is numba.core.caching.FunctionCache and hasattr(cache, "_guard_against_spurious_io_errors"):
        cache.__class__ = _LoadsLightly


COMPILE_WAIT_S = 600.0
"""Seconds a process waits, in all, for other processes' compiles of the kernels it needs before it
compiles them itself (a compile takes some 1-60 s; a holder stopped or stuck must not stop the
others). Once a wait has run out, the process waits on no lock again: campaign 17's holder of every
lock would otherwise have kept a run on a cold cache waiting 600 s for each of its kernels."""

WAIT_LISTENERS: list[Callable[[str, float], None]] = []
"""Called once per wait that passes a second, with the lock file and the seconds the wait may still
take (the command says so on stderr: a wait is never silent)."""

_HELD: set[str] = set()
_HELD_GUARD = threading.Lock()
_WAIT_LEFT = [COMPILE_WAIT_S]  # this process's waits share one budget (a list: changed in place)
_HOLDS_LOCKS = [True]  # False: compile_without_holding_locks


def compile_without_holding_locks() -> None:
    """From now on this process waits for other processes' compiles as before, but holds no compile
    lock while it compiles, so it never makes another process wait: a first run's second process
    (:mod:`armanim.runs.beside`) compiles ahead of the run, and the run must never wait on it (nor say
    that it waits). Where both compile the same kernel at once, each compiles it."""
    _HOLDS_LOCKS[0] = False


@contextlib.contextmanager
def held_alone(lock_path: str, wait_s: float = COMPILE_WAIT_S) -> Iterator[None]:
    """Hold the exclusive lock ``lock_path`` (a file beside numba's cache index of one kernel) while
    the body runs, so that processes sharing a cache compile each kernel once: a second process
    waits (at most ``wait_s`` seconds, and at most what is left of its :data:`COMPILE_WAIT_S`) and
    then finds the first one's machine code in the cache.

    The lock is ``flock``'s, so the kernel releases it when its holder ends, however it ends. A
    thread of a process that already holds ``lock_path`` (a nested compile, or another thread,
    which numba's own lock then orders) goes on without it. Where the lock file cannot be made
    (a cache folder not writable, no ``fcntl``), the body runs as before.
    """
    with _HELD_GUARD:
        held_here = lock_path in _HELD
        _HELD.add(lock_path)
    if held_here:
        yield
        return
    try:
        import fcntl  # noqa: F401  (where there is none, the body runs without a lock)

        # never through a link (a file made where it points), never waiting on a FIFO planted there
        fd = os.open(lock_path, os.O_RDWR | os.O_CREAT | os.O_CLOEXEC | os.O_NOFOLLOW | os.O_NONBLOCK, 0o644)
    except (ImportError, OSError):
        fd = None
    try:
        if fd is not None:
            _locked_within(fd, lock_path, min(wait_s, _WAIT_LEFT[0]))
            if not _HOLDS_LOCKS[0]:  # waited for the others' compile; makes none wait on its own
                os.close(fd)
                fd = None
        yield
    finally:
        if fd is not None:
            os.close(fd)  # releases the lock
        with _HELD_GUARD:
            _HELD.discard(lock_path)


def _locked_within(fd: int, lock_path: str, wait_s: float) -> bool:
    """Take ``flock``'s exclusive lock on ``fd`` within ``wait_s`` seconds (whether it was taken),
    telling :data:`WAIT_LISTENERS` once a wait passes a second; the time waited comes off this
    process's budget (:data:`COMPILE_WAIT_S`)."""
    import fcntl

    started = time.monotonic()
    told = False
    try:
        while True:
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
                return True
            except BlockingIOError:
                waited = time.monotonic() - started
                if waited >= wait_s:
                    return False
                if waited >= 1.0 and not told:
                    told = True
                    for listener in list(WAIT_LISTENERS):
                        listener(lock_path, wait_s - waited)
                time.sleep(0.05)
            except OSError:
                return False
    finally:
        _WAIT_LEFT[0] = max(0.0, _WAIT_LEFT[0] - (time.monotonic() - started))


class _CompilesOnce(numba.core.registry.CPUDispatcher):
    """numba's dispatcher, compiling a kernel for one signature under :func:`held_alone`: two
    processes that share a cache (a batch's workers, the suite's, ``warm``'s) compile it once, not
    each, and compile different signatures side by side."""

    def compile(self, sig: Any) -> Any:
        normalized: Any = numba.core.sigutils.normalize_signature  # numba's own, untyped
        args, _ = normalized(sig)
        lock_path = compile_lock_path(self, tuple(args))
        if lock_path is None or tuple(args) in self.overloads or self._kept(sig):
            return super().compile(sig)  # nothing to compile: no lock to wait on (campaign 17)
        with held_alone(lock_path):
            return super().compile(sig)  # numba looks in its cache first: the other's code

    def _kept(self, sig: Any) -> bool:
        """Whether numba's cache index holds machine code for ``sig`` (read as numba reads it before
        it loads the code). A run on a warmed cache then takes no lock: campaign 17's process
        holding every lock kept such a run waiting 600 s for each kernel it merely loaded."""
        cache: Any = getattr(self, "_cache", None)  # numba's, untyped
        target: Any = self.targetctx
        try:
            key = cache._index_key(sig, target.codegen())
            return key in cache._cache_file._load_index()
        except Exception:  # noqa: BLE001  (a cache laid out otherwise: the lock as before)
            return False


def index_path(dispatcher: Any) -> str | None:
    """numba's cache index of ``dispatcher`` (``.nbi``: every signature's entry), or None where
    numba keeps no cache for it."""
    index = getattr(getattr(getattr(dispatcher, "_cache", None), "_cache_file", None), "_index_path", None)
    return index if isinstance(index, str) else None


def compile_lock_path(dispatcher: Any, args: tuple[Any, ...]) -> str | None:
    """The lock file of ``dispatcher``'s compile for the argument types ``args``
    (:func:`lock_beside` its cache index); None where numba keeps no cache for it."""
    index = index_path(dispatcher)
    return None if index is None else lock_beside(index, args)


def lock_beside(index: str, args: tuple[Any, ...] | None = None) -> str:
    """The lock file beside numba's cache index ``index`` (a path ending ``.nbi``): the index's own
    (its writes), or one signature's compile (``args``, its argument types, named by their hash).

    >>> lock_beside("c/f-1.py311.nbi"), lock_beside("c/f-1.py311.nbi", ("none",))[:-22]
    ('c/f-1.py311.lock', 'c/f-1.py311')
    """
    base = os.path.splitext(index)[0]
    if args is None:
        return f"{base}.lock"
    digest = hashlib.sha1(repr(tuple(str(a) for a in args)).encode()).hexdigest()[:16]
    return f"{base}-{digest}.lock"


def compile_once_among_processes(dispatcher: Any) -> None:
    """Make ``dispatcher`` a :class:`_CompilesOnce` where it is numba's CPU dispatcher with a cache
    (else nothing changes)."""
    if type(dispatcher) is numba.core.registry.CPUDispatcher and index_path(dispatcher) is not None:
        dispatcher.__class__ = _CompilesOnce


COMPILED_MODULES = (
    "arm/kernel.py",
    "world/compiled.py",
    "motion/timing/passes.py",
    "motion/kernels/linalg.py",
    "motion/kernels/tasks.py",
    "motion/kernels/check.py",
    "motion/kernels/qp.py",
    "motion/kernels/attempt.py",
    "motion/kernels/frame.py",
    "motion/planning/check.py",
    "render/solids/rasterloops.py",
)
"""Every module of armanim that defines compiled functions (paths inside the package): one's
machine code holds the compiled functions it calls from the others."""


SourcesStamp = tuple[tuple[str, float | None, int | None], ...]


def sources_stamp(paths: tuple[str, ...], root: str | None = None) -> SourcesStamp:
    """(path, mtime, size) of each source file (``root`` the folder they are in, armanim's by
    default; a file that cannot be read stamps as (path, None, None)): what numba stamps one file with."""
    import os

    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__))) if root is None else root
    stamp: list[tuple[str, float | None, int | None]] = []
    for path in paths:
        try:
            status = os.stat(os.path.join(root, path))
        except OSError:
            stamp.append((path, None, None))
        else:
            stamp.append((path, status.st_mtime, status.st_size))
    return tuple(stamp)


def stamp_cache(dispatcher: Any, stamp: SourcesStamp) -> None:
    """Keep a compiled function's cached machine code only while ``stamp`` holds too.

    numba keeps a function's cache while its own file's (mtime, size) is unchanged, but the
    machine code also holds every compiled function it calls, inlined or linked from other
    modules: after an edit there (a ``git pull`` of an editable install) it would run the old
    callee. The index numba checks is stamped with the sources of all of them as well. Where
    numba keeps no cache, or its cache is laid out otherwise, nothing changes.
    """
    cache_file = getattr(getattr(dispatcher, "_cache", None), "_cache_file", None)
    if cache_file is not None and hasattr(cache_file, "_source_stamp"):
        cache_file._source_stamp = (cache_file._source_stamp, stamp)


JIT = dict(error_model="numpy", nogil=True)
"""The options of every compiled kernel: numpy's error model (x / 0 is inf or NaN, as the closed
forms and the bounds expect), the GIL released (render and batch workers run kernels in threads)."""
INLINE = dict(inline="always", **JIT)
""":data:`JIT` for the small helpers inlined into their callers."""

AXIS, K, K2, OFFSET, TURN, KIND, WIDTH = 0, 3, 12, 21, 24, 33, 34
"""Columns of a joint's row in :func:`packed_chain`: its axis a_i (3), K = [a_i]x (9, row
major), K^2 (9), its offset o_i (3), its turn T_i (9, row major) and its kind (1: prismatic,
0: revolute)."""


def packed_chain(arm: Arm) -> tuple[np.ndarray, np.ndarray]:
    """The arm's constants as the kernels read them: (n, 34) joint rows (see :data:`WIDTH`)
    and the root (12,): the base p_1, then R_0 row major. Computed once per arm (kept on it).

    >>> arm = Arm.from_names([2, 5], base=(5, 5, 0))
    >>> rows, root = packed_chain(arm)
    >>> rows.shape, root[:3].tolist()
    ((2, 34), [5.0, 5.0, 0.0])
    """
    memo = arm.__dict__.get("_packed")
    if memo is not None:
        return cast(tuple[np.ndarray, np.ndarray], memo)
    n = arm.n
    turns = np.broadcast_to(np.eye(3), (n, 3, 3)) if arm.turns is None else arm.turns
    rows = np.concatenate(
        [
            arm.axes,
            arm._k.reshape(n, 9),
            arm._k2.reshape(n, 9),
            arm.offsets,
            turns.reshape(n, 9),
            arm.slides[:, None].astype(float),
        ],
        axis=1,
    )
    start = np.eye(3) if arm.base_rotation is None else arm.base_rotation
    root = np.concatenate([arm.base, start.reshape(9)])
    packed = (np.ascontiguousarray(rows, dtype=float), np.ascontiguousarray(root, dtype=float))
    object.__setattr__(arm, "_packed", packed)  # a cache of constants: the arm stays what it was
    return packed


@compiled(**INLINE)
def _chain(
    rows: np.ndarray,
    root: np.ndarray,
    phi: np.ndarray,
    points: np.ndarray,
    frames: np.ndarray,
    axes: np.ndarray,
    tool: np.ndarray,
) -> None:
    """One pose into ``points`` (n+1, 3), ``frames`` (n, 3, 3), world ``axes`` (n, 3) and the
    tool frame ``tool`` (3, 3). A prismatic joint (its row's :data:`KIND`) turns by nothing
    (Rot(a, 0) = I exactly) and slides its frame's origin by phi_i w_i."""
    n = rows.shape[0]
    rot = np.empty((3, 3))
    local = np.empty((3, 3))
    for a in range(3):
        points[0, a] = root[a]
        for b in range(3):
            rot[a, b] = root[3 + 3 * a + b]
    for i in range(n):
        slides = rows[i, KIND] != 0.0
        angle = 0.0 if slides else phi[i]
        s = math.sin(angle)
        c = 1.0 - math.cos(angle)
        for a in range(3):
            for b in range(3):
                local[a, b] = (1.0 if a == b else 0.0) + s * rows[i, K + 3 * a + b] + c * rows[i, K2 + 3 * a + b]
        for a in range(3):
            for b in range(3):
                frames[i, a, b] = rot[a, 0] * local[0, b] + rot[a, 1] * local[1, b] + rot[a, 2] * local[2, b]
        if slides:
            for a in range(3):
                points[i, a] += phi[i] * (
                    frames[i, a, 0] * rows[i, AXIS]
                    + frames[i, a, 1] * rows[i, AXIS + 1]
                    + frames[i, a, 2] * rows[i, AXIS + 2]
                )
        for a in range(3):
            f0, f1, f2 = frames[i, a, 0], frames[i, a, 1], frames[i, a, 2]
            points[i + 1, a] = points[i, a] + (
                f0 * rows[i, OFFSET] + f1 * rows[i, OFFSET + 1] + f2 * rows[i, OFFSET + 2]
            )
            axes[i, a] = f0 * rows[i, AXIS] + f1 * rows[i, AXIS + 1] + f2 * rows[i, AXIS + 2]
            for b in range(3):
                rot[a, b] = f0 * rows[i, TURN + b] + f1 * rows[i, TURN + 3 + b] + f2 * rows[i, TURN + 6 + b]
    for a in range(3):
        for b in range(3):
            tool[a, b] = rot[a, b]


@compiled(**JIT)
def _forward_one(
    rows: np.ndarray,
    root: np.ndarray,
    phi: np.ndarray,
    points: np.ndarray,
    frames: np.ndarray,
    axes: np.ndarray,
    tool: np.ndarray,
) -> None:
    """One pose into arrays the caller made (four arrays handed back by numba cost a microsecond more)."""
    _chain(rows, root, phi, points, frames, axes, tool)


@compiled(**JIT)
def _forward_many(
    rows: np.ndarray, root: np.ndarray, phi: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    n = rows.shape[0]
    m = phi.shape[0]
    points = np.empty((m, n + 1, 3))
    frames = np.empty((m, n, 3, 3))
    axes = np.empty((m, n, 3))
    tool = np.empty((m, 3, 3))
    for k in range(m):
        _chain(rows, root, phi[k], points[k], frames[k], axes[k], tool[k])
    return points, frames, axes, tool


@compiled(**INLINE)
def joint_slides(axes: np.ndarray, j: int) -> bool:
    """Whether joint j is prismatic, read from world ``axes``: (n, 4) axes carry each joint's kind
    in a fourth column (1: prismatic, its row's :data:`KIND`), (n, 3) axes are all revolute. The
    one reading of that convention: the kernels' Jacobians (:func:`_jacobian`,
    :mod:`armanim.motion.kernels.tasks`) and pair rows (:mod:`armanim.world.compiled`) take a
    prismatic joint's column as w_j (a point it carries slides along its axis) and no turn."""
    return bool(axes.shape[1] > 3 and axes[j, 3] != 0.0)


@compiled(**INLINE)
def _jacobian(points: np.ndarray, axes: np.ndarray, jac: np.ndarray) -> None:
    """The 6 x n geometric Jacobian of the tool into ``jac``: rows 0-2 w_j x (e - p_j) (the
    tip's), rows 3-5 w_j (the tool's angular velocity), as :func:`tip_jacobian` and
    :func:`angular_jacobian` compute them; a prismatic joint's (:func:`joint_slides`) w_j over 0."""
    n = axes.shape[0]
    for j in range(n):
        w0, w1, w2 = axes[j, 0], axes[j, 1], axes[j, 2]
        if joint_slides(axes, j):  # the tip slides along the axis, the tool does not turn
            jac[0, j], jac[1, j], jac[2, j] = w0, w1, w2
            jac[3, j] = jac[4, j] = jac[5, j] = 0.0
            continue
        l0 = points[n, 0] - points[j, 0]
        l1 = points[n, 1] - points[j, 1]
        l2 = points[n, 2] - points[j, 2]
        jac[0, j] = w1 * l2 - w2 * l1
        jac[1, j] = w2 * l0 - w0 * l2
        jac[2, j] = w0 * l1 - w1 * l0
        jac[3, j] = w0
        jac[4, j] = w1
        jac[5, j] = w2


@compiled(**JIT)
def _jacobian_one(points: np.ndarray, axes: np.ndarray) -> np.ndarray:
    jac = np.empty((6, axes.shape[0]))
    _jacobian(points, axes, jac)
    return jac


@compiled(**JIT)
def _jacobian_many(points: np.ndarray, axes: np.ndarray) -> np.ndarray:
    jac = np.empty((axes.shape[0], 6, axes.shape[1]))
    for k in range(axes.shape[0]):
        _jacobian(points[k], axes[k], jac[k])
    return jac


@compiled(**INLINE)
def _log(rot: np.ndarray, out: np.ndarray) -> None:
    """The rotation vector of ``rot`` (3, 3) into ``out`` (3,): :func:`armanim.arm.rotations.rotation_log`'s
    formulas (the series near 0, the symmetric part near pi)."""
    sx = 0.5 * (rot[2, 1] - rot[1, 2])
    sy = 0.5 * (rot[0, 2] - rot[2, 0])
    sz = 0.5 * (rot[1, 0] - rot[0, 1])
    cos = min(1.0, max(-1.0, 0.5 * (rot[0, 0] + rot[1, 1] + rot[2, 2] - 1.0)))
    sin = math.sqrt(sx * sx + sy * sy + sz * sz)
    angle = math.atan2(sin, cos)
    if angle < 1e-4:
        scale = 1.0 + angle * angle / 6.0
    elif cos < -0.9:  # the axis from (R + R^T)/2 = cos I + (1 - cos) a a^T, its sign from the skew part
        best = 0
        top = -np.inf
        for c in range(3):
            d = (0.5 * (rot[c, c] + rot[c, c]) - cos) / (1.0 - cos)
            if d > top:
                top = d
                best = c
        length = 0.0
        for a in range(3):
            v = (0.5 * (rot[a, best] + rot[best, a]) - (cos if a == best else 0.0)) / (1.0 - cos)
            out[a] = v
            length += v * v
        length = math.sqrt(length)
        if length <= 0.0:
            length = 1.0
        for a in range(3):
            out[a] = out[a] / length
        sign = -1.0 if out[0] * sx + out[1] * sy + out[2] * sz < 0.0 else 1.0
        for a in range(3):
            out[a] = sign * angle * out[a]
        return
    else:
        scale = angle / sin
    out[0] = scale * sx
    out[1] = scale * sy
    out[2] = scale * sz


@compiled(**JIT)
def _log_one(rot: np.ndarray) -> np.ndarray:
    out = np.empty(3)
    _log(rot, out)
    return out


@compiled(**JIT)
def _log_many(rot: np.ndarray) -> np.ndarray:
    out = np.empty((rot.shape[0], 3))
    for k in range(rot.shape[0]):
        _log(rot[k], out[k])
    return out


@compiled(**JIT)
def _error_to(goal: np.ndarray, tool: np.ndarray) -> np.ndarray:
    """log(R_g R^T) (3,): the world rotation vector from the tool frame to the goal's."""
    rel = np.empty((3, 3))
    for a in range(3):
        for b in range(3):
            rel[a, b] = goal[a, 0] * tool[b, 0] + goal[a, 1] * tool[b, 1] + goal[a, 2] * tool[b, 2]
    out = np.empty(3)
    _log(rel, out)
    return out


def forward(arm: Arm, phi: np.ndarray) -> Pose:
    """:func:`armanim.arm.kinematics.forward`, compiled: ``points`` (..., n+1, 3), ``frames``
    (..., n, 3, 3) and the world ``axes`` (..., n, 3) of one pose (n,) or a batch (..., n).

    >>> arm = Arm.from_names([2, 5, 5, 5], base=(5, 5, 0))
    >>> forward(arm, np.zeros(4)).tip.tolist()
    [5.0, 5.0, 17.0]
    """
    return forward_with_tool(arm, phi)[0]


def forward_with_tool(arm: Arm, phi: np.ndarray) -> tuple[Pose, np.ndarray]:
    """:func:`forward` and the tool frame's world rotation (..., 3, 3) (:func:`armanim.arm.kinematics.tool_rotation`).

    Raises
    ------
    ValueError
        ``phi``'s last axis is not one angle a joint (campaign 16: a short pose was read past its end).
    """
    rows, root = packed_chain(arm)
    phi = np.ascontiguousarray(phi, dtype=float)
    n = rows.shape[0]
    if phi.ndim == 0 or phi.shape[-1] != n:  # the kernels index n angles unchecked: past a short array's end
        raise ValueError(
            f"expected the angles of the arm's {n} joints, a pose ({n},) or a batch (..., {n}); got shape {phi.shape}"
        )
    if phi.ndim == 1:
        points, frames, axes, tool = np.empty((n + 1, 3)), np.empty((n, 3, 3)), np.empty((n, 3)), np.empty((3, 3))
        _forward_one(rows, root, phi, points, frames, axes, tool)
        return Pose(points, frames, axes), tool
    batch = phi.shape[:-1]
    points, frames, axes, tool = _forward_many(rows, root, phi.reshape(-1, n))
    return Pose(
        points=points.reshape(batch + (n + 1, 3)),
        frames=frames.reshape(batch + (n, 3, 3)),
        axes=axes.reshape(batch + (n, 3)),
    ), tool.reshape(batch + (3, 3))


def geometric_jacobian(pose: Pose, arm: Arm | None = None) -> np.ndarray:
    """The tool's 6 x n geometric Jacobian (..., 6, n) of a pose from :func:`forward` (its
    ``axes`` set): [:func:`tip_jacobian`; :func:`angular_jacobian`]. ``arm``: the pose's arm,
    needed where it has prismatic joints (None: every joint revolute).

    >>> arm = Arm.from_names([1, 1], axes=["z", "y"])
    >>> geometric_jacobian(forward(arm, np.zeros(2))).tolist()
    [[0.0, 1.0], [0.0, 0.0], [0.0, 0.0], [0.0, 0.0], [0.0, 1.0], [1.0, 0.0]]
    """
    assert pose.axes is not None  # set by forward
    axes = pose.axes if arm is None else kind_axes(arm, pose.axes)
    if pose.points.ndim == 2:
        return _jacobian_one(pose.points, axes)
    batch = pose.points.shape[:-2]
    n = pose.axes.shape[-2]
    jac = _jacobian_many(pose.points.reshape(-1, n + 1, 3), axes.reshape(-1, n, axes.shape[-1]))
    return cast(np.ndarray, jac.reshape(batch + (6, n)))


def rotation_log(rot: np.ndarray) -> np.ndarray:
    """:func:`armanim.arm.rotations.rotation_log`, compiled: the rotation vectors (..., 3) of
    rotations (..., 3, 3).

    >>> from armanim.arm.rotations import rotation_exp
    >>> np.round(rotation_log(rotation_exp(np.array([0.3, -0.2, 0.1]))), 12).tolist()
    [0.3, -0.2, 0.1]
    """
    rot = np.ascontiguousarray(rot, dtype=float)
    if rot.ndim == 2:
        return _log_one(rot)
    return _log_many(rot.reshape(-1, 3, 3)).reshape(rot.shape[:-1])


def rotation_error(goal: np.ndarray, tool: np.ndarray) -> np.ndarray:
    """log(R_g R^T) (3,) for one goal rotation and one tool frame (3, 3): the residual of
    :func:`armanim.motion.orientation.orientation_residual`, in one compiled call."""
    return _error_to(np.ascontiguousarray(goal, dtype=float), np.ascontiguousarray(tool, dtype=float))


@compiled(**JIT)
def _capsule_ends_one(
    points: np.ndarray,
    frames: np.ndarray,
    link: np.ndarray,
    start: np.ndarray,
    end: np.ndarray,
    joint_segment: np.ndarray,
    a: np.ndarray,
    b: np.ndarray,
) -> None:
    """Every capsule's world ends of one pose into a, b (c, 3): p_k + R_k x, or the joint points
    themselves for a joint-to-joint capsule, its own ends for one on the base (carrier -1); the sums
    in numpy's einsum order."""
    for c in range(link.shape[0]):
        k = link[c]
        if k < 0:  # on the base: already in the world
            for i in range(3):
                a[c, i] = start[c, i]
                b[c, i] = end[c, i]
        elif joint_segment[c]:
            for i in range(3):
                a[c, i] = points[k, i]
                b[c, i] = points[k + 1, i]
        else:
            for i in range(3):
                a[c, i] = points[k, i] + (
                    frames[k, i, 0] * start[c, 0] + frames[k, i, 1] * start[c, 1] + frames[k, i, 2] * start[c, 2]
                )
                b[c, i] = points[k, i] + (
                    frames[k, i, 0] * end[c, 0] + frames[k, i, 1] * end[c, 1] + frames[k, i, 2] * end[c, 2]
                )


def capsule_ends_one(
    link: np.ndarray,
    start: np.ndarray,
    end: np.ndarray,
    joint_segment: np.ndarray,
    points: np.ndarray,
    frames: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """World ends a, b (c, 3) of capsules (``link`` (c,) int, ``start``/``end`` (c, 3) in their
    joint's frame, ``joint_segment`` (c,) bool) at one pose (``points`` (n+1, 3), ``frames``
    (n, 3, 3)): :func:`armanim.arm.capsules.capsule_ends` of one pose, compiled.

    >>> arm = Arm.from_names([2, 5], base=(1, 0, 0))
    >>> pose = forward(arm, np.zeros(2))
    >>> a, b = capsule_ends_one(np.array([1]), np.zeros((1, 3)), np.array([[0.0, 0, 1]]), np.array([False]), pose.points, pose.frames)
    >>> a.tolist(), b.tolist()
    ([[1.0, 0.0, 2.0]], [[1.0, 0.0, 3.0]])
    """
    count = len(link)
    a, b = np.empty((count, 3)), np.empty((count, 3))
    ends = np.empty(
        (count, 6)
    )  # start and end as column views of one array, as the compiled callers pass them (one compile)
    ends[:, :3], ends[:, 3:] = start, end
    _capsule_ends_one(
        np.ascontiguousarray(points, dtype=float),
        np.ascontiguousarray(frames, dtype=float),
        link,
        ends[:, :3],
        ends[:, 3:],
        np.ascontiguousarray(joint_segment, dtype=np.bool_),
        a,
        b,
    )
    return a, b


def machine_code_cached(*functions: Any) -> bool:
    """Whether numba's on-disk cache holds machine code of each compiled function (a dispatcher of
    :func:`compiled`) for this Python: False means its first call compiles it, some seconds. Where
    numba keeps no cache (a read-only install) or does not say, True: no notice beats a wrong one.

    >>> machine_code_cached()
    True
    """
    from pathlib import Path

    for function in functions:
        try:
            cache_file = function._cache._cache_file  # numba's own index of the function's machine code
            index = Path(cache_file._index_path)
        except (AttributeError, TypeError):
            continue
        if not index.exists():
            return False
        try:
            if not cache_file._load_index():  # stale (a source stamp changed) or empty: it compiles
                return False
        except Exception:  # noqa: BLE001 (an index numba cannot read now is one it compiles again)
            return False
    return True
