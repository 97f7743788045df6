"""The safety filter every step goes through (:mod:`armanim.motion.filter.barrier`): the closest
safe step to a method's proposal, and the clearance policy it and the planner share (the
clearance kept, the planner's floor, a pose's clearances and limits).
"""
