"""The ``armanim`` command: one module per command, each a thin Typer function over the
importable API (which returns results and prints nothing).

Importing this package registers every command on :data:`app`.
"""

from __future__ import annotations

import importlib

from armanim.cli.app import app

COMMAND_MODULES = ("pose", "scenes", "robots", "run", "view", "sweep", "golden")
"""Importing each registers its commands, in this order in ``armanim --help``."""
for _module in COMMAND_MODULES:
    importlib.import_module(f"armanim.cli.{_module}")


def _terminate(signum, frame):
    raise KeyboardInterrupt  # SIGTERM takes the same clean-up path as Ctrl-C


def main() -> None:
    """Entry point of the ``armanim`` console script."""
    import signal

    signal.signal(signal.SIGTERM, _terminate)
    app()


__all__ = ["app", "main"]
