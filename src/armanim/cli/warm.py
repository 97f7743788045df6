"""``armanim warm``: compile armanim's numerical code now, not at the first run."""

from __future__ import annotations

from armanim.cli.app import app, err, handle_errors, out, say
from armanim.cli.options import JobsOpt, QuietOpt, usable_cores, usable_jobs


@app.command()
@handle_errors
def warm(jobs: JobsOpt = None, quiet: QuietOpt = False) -> None:
    """Compile armanim's numerical code for this machine now (numba; once after installing or upgrading), so that the first [bold]armanim run[/bold] or [bold]ik[/bold] starts at once. It solves small scenes that call every compiled kernel (an arm of links among every shape and in an empty world, a Panda with its self pairs, a UR5 on a rail, joint goals, planning, IK) and draws a tiny frame (the video's rasteriser), in memory: nothing is written but numba's cache. Its pieces run in worker processes on every core (--jobs), which share numba's cache: each kernel is compiled by one of them. A second warm takes a few seconds.

    Example: [bold]armanim warm[/bold] after [bold]pip install[/bold] (in a container image: the layer after the install)
    """
    from armanim.cli.progress import bars
    from armanim.runs.stopwatch import stopwatch
    from armanim.runs.warm import warm as warm_kernels
    from armanim.runs.warmth import NOT_KEPT

    workers = usable_jobs(jobs) or usable_cores()
    with stopwatch() as watch, bars(quiet) as progress:
        warmed = warm_kernels(lambda label, done, total: progress("warm", done, total, (label,)), jobs=workers)
    if not warmed.kept:  # said even with --quiet: the warm did not do what it is for
        say(f"armanim warm: {NOT_KEPT}", err)
    elif not quiet:
        where = f" in {workers} processes" if workers > 1 else ""
        what = (
            f"numba compiled for {warmed.compiling:.1f} s{where}"
            if warmed.compiling
            else "all of it was compiled already"
        )
        out.print(
            f"armanim warm: {warmed.solves} solves in {watch.seconds:.1f} s ({what}; numba's cache keeps it until armanim changes)"
        )
