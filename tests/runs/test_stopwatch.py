"""The run's time (issue 52, item 5): numba's compiling inside a timed block is measured apart
(numba's own compile events), and the run's line says both."""

from __future__ import annotations

import time

from armanim.cli.reports import run_time_line
from armanim.runs.stopwatch import stopwatch


def test_a_fresh_compile_is_counted_apart_and_a_compiled_call_is_not():
    import numba

    @numba.njit(cache=False)
    def fresh(x):  # a new function: its first call compiles
        return x * 2.0 + 1.0

    with stopwatch() as cold:
        fresh(1.0)
        time.sleep(0.05)
    assert 0.0 < cold.compiling < cold.seconds and cold.without_compiling >= 0.05
    with stopwatch() as warm:
        fresh(2.0)
    assert warm.compiling == 0.0 and warm.without_compiling == warm.seconds


def test_the_run_time_line_names_the_urdf_and_numbas_compiling_apart():
    from armanim.runs.stopwatch import Stopwatch

    assert run_time_line(Stopwatch(5.0, 0.0), False, False) == "time: 5.0 s from the scene to the outputs"
    assert run_time_line(Stopwatch(40.0, 31.0), True, True).startswith(
        "time: 9.0 s from the scene and its URDF to the video (numba"
    )
