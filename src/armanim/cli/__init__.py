"""The ``armanim`` command: one module per command, each a thin Typer function over the
importable API (which returns results and prints nothing).

Importing this package registers every command on :data:`app`.
"""

from __future__ import annotations

import importlib

from armanim.cli.app import app

COMMAND_MODULES = ("pose", "scenes", "robots", "run", "view", "export", "sweep", "golden", "moveit", "warm")
"""Importing each registers its commands, in this order in ``armanim --help``."""
for _module in COMMAND_MODULES:
    importlib.import_module(f"armanim.cli.{_module}")


def main() -> None:
    """Run the command line in this process (see :mod:`armanim.__main__`, which calls it)."""
    from armanim.cli.app import flushed_or_failed, quiet_when_closed
    from armanim.cli.interrupts import ignore_until_exit, own_the_process

    own_the_process()
    quiet_when_closed()
    try:
        failed = None
        try:
            app()
        except OSError as exc:  # written outside a command (its --help, --version): the device refused it
            failed = exc
        finally:
            flushed_or_failed(failed)
    finally:
        # every way out (a usage error, --help, an outcome): at shutdown CPython puts SIG_DFL back
        # in place of a Python handler, so a signal then would end the process by it (-15, -2)
        ignore_until_exit()


__all__ = ["app", "main"]
