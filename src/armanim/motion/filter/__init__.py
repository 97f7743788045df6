"""The safety filter every step goes through (:mod:`armanim.motion.filter.barrier`: the closest
safe step to a method's proposal) and the clearance policy it shares with the planner
(:mod:`armanim.motion.filter.clearance`: the clearances and the limit buffer kept, a pose's
clearances and limits judged by them).
"""
