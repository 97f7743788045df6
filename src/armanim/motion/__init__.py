"""Motion: the problem, the cost, the methods, the safety filter, stalls, the planner, the frame loop and single-pose IK (pure core)."""
