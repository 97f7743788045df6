"""Whether a command's first solve on this machine compiles armanim's numerical code first.

numba compiles the compiled kernels at their first call after installing or upgrading and keeps
the machine code in its cache; that first time takes some 20-30 s of CPU for a small scene (a robot's or
other obstacles' kernels more), during which a progress bar would stand still. The commands tell a user at a
terminal so (:func:`compiles_first`), and count the kernels as numba starts each (:func:`armanim.cli.app.count_compiles`).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Literal


def compiles_first(command: Literal["run", "ik"], problem: object = None) -> bool:
    """Whether ``command``'s solve would compile kernels first: the kinematics kernel every solve
    calls, for ``run`` the compiled frame (:mod:`armanim.motion.kernels.frame`), and for ``ik`` of ``problem`` (a :class:`~armanim.motion.problem.Problem`) the compiled attempt where it runs, are not in numba's
    cache yet. (A kernel only some scenes call, a box's or a cylinder's distances, compiles at its first use in a
    few seconds, unannounced.)"""
    from armanim.arm import kernel
    from armanim.motion.problem import Problem

    functions: list[Any] = [kernel._forward_one]
    if command == "run":  # the frames of pinv and dls (the default methods' frames are compiled)
        from armanim.motion.kernels.frame import frame_loop

        functions.append(frame_loop)
    if command == "ik" and isinstance(problem, Problem):
        from armanim.motion.kernels.plan import compiled_plan
        from armanim.motion.solvers import METHODS

        if compiled_plan(problem, METHODS[problem.solver.method], None, "attempt") is not None:
            from armanim.motion.kernels.attempt import attempt_loop

            functions.append(attempt_loop)
    return not kernel.CODE_KEPT or not kernel.machine_code_cached(*functions)


def tell_lock_waits(say: Callable[[str], None]) -> None:
    """From now on in this process, ``say`` a line when a compile waits on another process's lock
    (:data:`armanim.arm.kernel.WAIT_LISTENERS`; once, however often it is asked): campaign 17's run
    waited on them without a word."""
    from armanim.arm import kernel

    def tell(lock_path: str, seconds: float) -> None:
        say(
            f"armanim: waiting for another armanim process compiling the same code (lock {lock_path}); "
            f"at most {seconds:.0f} s more, then this one compiles it"
        )

    if not any(getattr(listener, "armanim_says", False) for listener in kernel.WAIT_LISTENERS):
        tell.armanim_says = True  # type: ignore[attr-defined]
        kernel.WAIT_LISTENERS.append(tell)


def machine_code_kept() -> bool:
    """Whether numba keeps what this process compiles (False: no writable folder for its cache, or
    a write to it failed, and the next command compiles again): :data:`armanim.arm.kernel.CODE_KEPT`."""
    from armanim.arm import kernel

    return kernel.CODE_KEPT


FIRST_COMPILE = (
    "armanim: compiling its numerical code for this machine, once after installing (a kernel at a time, "
    "counted below; armanim warm does it ahead)"
)
"""What a command says at a terminal before a solve that compiles first."""
NOT_KEPT = (
    "numba finds no folder it can keep its compiled code in, so every command compiles it again: "
    "set NUMBA_CACHE_DIR to a writable folder with room"
)
"""Why a command compiles again each time (campaign 16: a read-only install, no writable home, a full disk)."""


def first_compile_notice() -> str:
    """What a command says at a terminal before a solve that compiles first: once after installing,
    or every time where numba keeps nothing (:data:`NOT_KEPT`)."""
    if machine_code_kept():
        return FIRST_COMPILE
    return f"armanim: compiling its numerical code for this machine (a kernel at a time, counted below): {NOT_KEPT}"
