"""How long a run took from its scene file (and its URDF) to its outputs, with numba's compiling
apart: the first run after installing compiles armanim's numerical code once (some 20-30 s of CPU for a small scene),
which says nothing of how long a robot takes to bring up (issue 52, item 5).

The time is printed, never written: ``summary.json`` stays byte-identical between reruns.
"""

from __future__ import annotations

import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass


@dataclass
class Stopwatch:
    """Wall seconds of a timed block (``seconds``) and of numba's compiling inside it
    (``compiling``), both set when the block ends."""

    seconds: float = 0.0
    compiling: float = 0.0

    @property
    def without_compiling(self) -> float:
        """The block's seconds less numba's compiling."""
        return max(0.0, self.seconds - self.compiling)


@contextmanager
def stopwatch() -> Iterator[Stopwatch]:
    """Time a block, and numba's compiling in it (numba's own ``numba:compile`` events, each
    outermost compile once however many functions it compiles inside; loading machine code from
    numba's cache is not compiling).

    >>> with stopwatch() as watch:
    ...     pass
    >>> watch.seconds >= watch.compiling == 0.0
    True
    """
    from numba.core import event  # numba's event API (public since 0.53)

    watch = Stopwatch()

    def compiled(seconds: float) -> None:
        watch.compiling = seconds

    start = time.perf_counter()
    try:
        with event.install_timer("numba:compile", compiled):
            yield watch
    finally:
        watch.seconds = time.perf_counter() - start
