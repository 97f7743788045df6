"""Processes and signals: how armanim starts workers, stops them and is interrupted.

The rooms that start processes (runs/ for batches, render/ for a video's segments) or must not
be cut short by a signal (output/'s atomic writes and folder swaps) import this room; it
imports none of them (only :mod:`armanim.errors`), so it sits below output/ and above the
pure core, which never starts a process.

- :mod:`.executors`: where a batch's scenes run: in this process, a pool of local workers, or
  Dask.
- :mod:`.deferred`: Ctrl-C and SIGTERM held back while a clean-up or a swap runs.
- :mod:`.interrupted`: whether Ctrl-C or SIGTERM came while the current command ran.
- :mod:`.forkserver_signals`: the batch pool's forkserver starts with SIGINT and SIGTERM blocked.
- :mod:`.workers`: worker processes that never outlive armanim and stop quietly (their
  clean-ups, signals blocked while they start, the parent watched).
"""
