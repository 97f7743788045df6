"""The clock: when the solved path's poses happen, within each joint's rate limits.

In this order, each module importing only those before it (and the rooms below
:mod:`armanim.motion.timing`): the compiled passes (``passes``: the Hermite pieces and TOPP-RA's
sweeps), the joint-space path (``jointpath``), the time law (``clock``), a goal's motion on it
(``goalmotion``), the corners cut between goals (``smoothing``, ``blend``), a path goal's
timing (``pathtiming``) and the whole solution put on the clock at the output rate (``retime``).
"""
