"""``armanim warm``: compile armanim's numerical code now, not at the first run."""

from __future__ import annotations

from armanim.cli.app import app, err, handle_errors, out, say
from armanim.cli.options import QuietOpt


@app.command()
@handle_errors
def warm(quiet: QuietOpt = False) -> None:
    """Compile armanim's numerical code for this machine now (numba; once after installing or upgrading), so that the first [bold]armanim run[/bold] or [bold]ik[/bold] starts at once. It solves small scenes that call every compiled kernel (an arm of links among every shape and in an empty world, a Panda with its self pairs, a UR5 on a rail, joint goals, planning, IK) and draws a tiny frame (the video's rasteriser), in memory: nothing is written but numba's cache. A second warm takes about a second.

    Example: [bold]armanim warm[/bold] after [bold]pip install[/bold] (in a container image: the layer after the install)
    """
    from armanim.cli.progress import bars
    from armanim.runs.stopwatch import stopwatch
    from armanim.runs.warm import warm as warm_kernels
    from armanim.runs.warmth import NOT_KEPT, machine_code_kept

    with stopwatch() as watch, bars(quiet) as progress:
        solves = warm_kernels(lambda label, done, total: progress("warm", done, total, (label,)))
    if not machine_code_kept():  # said even with --quiet: the warm did not do what it is for
        say(f"armanim warm: {NOT_KEPT}", err)
    elif not quiet:
        what = f"numba compiled for {watch.compiling:.1f} s" if watch.compiling else "all of it was compiled already"
        out.print(
            f"armanim warm: {solves} solves in {watch.seconds:.1f} s ({what}; numba's cache keeps it until armanim changes)"
        )
