"""The compiled motion code (numba), in one room: where a step of ``pinv`` or ``dls`` is computed
compiled, beside the numpy line it follows (:mod:`armanim.motion.solvers`, the oracle).

- :mod:`~armanim.motion.kernels.plan`: whether a step runs compiled (:func:`~armanim.motion.kernels.plan.compiled_plan`);
- :mod:`~armanim.motion.kernels.layout`: the problem as the kernels read it (one
  :class:`~armanim.motion.kernels.layout.KernelProblem` a problem, one enumeration of the settings' slots);
- :mod:`~armanim.motion.kernels.linalg`: the inverses;
- :mod:`~armanim.motion.kernels.tasks`: the tasks, the pushes and the proposals;
- :mod:`~armanim.motion.kernels.qp`: the safety filter's QP;
- :mod:`~armanim.motion.kernels.check`: the exact checks (clearances, the arm's own pairs' gaps);
- :mod:`~armanim.motion.kernels.attempt`: an IK attempt's loop of steps, in one call;
- :mod:`~armanim.motion.kernels.frame`: one frame of the frame loop.

Importing this package or ``plan`` and ``layout`` loads no numba; the other modules compile
(:func:`armanim.arm.kernel.compiled`) and are imported where a solve starts.
"""
