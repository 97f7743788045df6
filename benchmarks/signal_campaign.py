"""The signal sweep of issue 19 at full size: every command, many moments, both signals.

Run: ``python benchmarks/signal_campaign.py`` (some 15-30 minutes on two cores),
``--commands run batch`` for some, ``--delays 0 0.002 0.02 0.3 1`` to change the moments.

tests/system/test_signal_moments.py interrupts each command at a handful of moments; this script
interrupts it at every moment of :data:`MOMENTS` plus each delay, with SIGINT to the group
(a terminal's Ctrl-C) and SIGTERM to armanim (``kill``), and checks each attempt as the
test does (tests/signals.py): exit 0 or 130, no traceback, every folder old or whole new,
no litter, no process left. It prints one line per attempt and a summary, and exits 1 if
any attempt went wrong (the failing attempts' folders are kept under ``--keep``).
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path[:0] = [
    str(ROOT / "tests"),
    str(ROOT / "tests" / "system"),
]  # the harness and the commands are the tests' own (one owner)

MOMENTS = ("start", "workers", "ffmpeg", "poster", "commit")


def main() -> int:
    from signals import Sweep
    from test_signal_moments import _commands

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--commands", nargs="*", default=None, help="run, batch, sweep, 'check --update', render (default: all)"
    )
    parser.add_argument(
        "--delays",
        nargs="*",
        type=float,
        default=[0.0, 0.001, 0.003, 0.02, 0.1, 0.4, 1.0],
        help="seconds after each moment (default: 0 1 ms 3 ms 20 ms 0.1 0.4 1)",
    )
    parser.add_argument(
        "--twice",
        type=float,
        default=None,
        metavar="SECONDS",
        help="send each signal twice, this far apart (a double Ctrl-C)",
    )
    parser.add_argument("--keep", type=Path, default=None, help="keep the attempts' folders here")
    args = parser.parse_args()
    root = Path(args.keep or tempfile.mkdtemp(prefix="armanim-signals-"))
    commands = _commands(root / "scenes-and-commands")
    names = args.commands or list(commands)
    attempts = wrong = skipped = 0
    for name in names:
        sweep = Sweep(commands[name], root / name.replace(" ", "-"))
        for moment in MOMENTS:
            for delay in args.delays:
                for signame in ("SIGINT", "SIGTERM"):
                    outcome = sweep.attempt(moment, delay, signame, args.twice)
                    attempts += 1
                    problems = outcome.problems()
                    wrong += bool(problems)
                    skipped += not outcome.fired
                    verdict = "WRONG " + "; ".join(problems) if problems else "ok"
                    print(
                        f"{name:>15} {moment:>8}+{delay:<6g} {signame:<7} exit {outcome.code:>3}  "
                        f"{' '.join(f'{k}={v}' for k, v in outcome.states.items())}  {'' if outcome.fired else '(ended first) '}{verdict}",
                        flush=True,
                    )
                    if problems:
                        print("    stderr: " + outcome.stderr[-3000:].replace("\n", "\n    "), flush=True)
    print(
        f"\n{attempts} attempts: {attempts - wrong} right, {wrong} wrong ({skipped} ended before their moment); folders in {root}"
    )
    return 1 if wrong else 0


if __name__ == "__main__":
    sys.exit(main())
