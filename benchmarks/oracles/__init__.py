"""Oracles of the benchmarks, independent of armanim's solvers: their own kinematics and
clearances (checked against armanim's at start), pinocchio's, coal's, and a least-squares
search that labels each goal feasible or not.
"""
