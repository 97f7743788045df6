"""Runs: one scene end to end, batches, executors, sweeps, golden checks (the silent API the commands call)."""
