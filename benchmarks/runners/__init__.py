"""What runs armanim for the benchmarks and reports on it: timed solves, the invariants of each
trajectory, self-tests of the oracles, the report's tables. The command lines are the
``benchmarks/*_bench.py`` scripts.
"""
