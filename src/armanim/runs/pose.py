"""One pose of an arm, forward or inverse: what ``armanim fk`` and ``armanim ik`` answer, as values.

Silent (nothing is printed): :func:`forward_pose` and :func:`solve_ik` take a validated scene
model or its problem and numbers (the CLI parses the flags' text), and return frozen answers
whose fields ``armanim fk``/``ik`` print as a table or JSON. Why a pose was missed is a field
of the answer (:class:`PoseMiss`). Angles typed in degrees become radians in
:mod:`armanim.scene.convert`, as a scene file's do; the answers carry the degrees shown.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Literal

import numpy as np
from pydantic import ValidationError

from armanim.arm.kinematics import forward, joints_in_si, joints_shown, tool_rotation
from armanim.arm.rotations import rotation_quaternion, rotation_rpy
from armanim.errors import UsageError
from armanim.motion.ik import PoseSolution, solve_pose
from armanim.motion.orientation import Orientation
from armanim.motion.problem import Problem
from armanim.motion.solvers import METHODS
from armanim.motion.stalls import beyond_reach
from armanim.output.numbers import length_unit
from armanim.scene.convert import radians, scene_to_problem
from armanim.scene.fields import MIN_DEGREES
from armanim.scene.models import SceneModel, SolverModel
from armanim.world.selfdistances import self_gaps


@dataclass(frozen=True)
class FkAnswer:
    """An arm's pose at given joint angles (``armanim fk``).

    Attributes
    ----------
    problem : Problem
        The arm (its limits, reach), as the scene or the flags give it, without the arm's own
        pairs (``self_pairs`` empty: one pose's forward kinematics never asks for them).
    phi : (n,) array
        The joint angles, radians.
    angles_deg : (n,) array
        The joint angles in degrees, as typed when typed in degrees.
    joint_degrees : (n,) array
        ``phi`` in degrees (the table's column).
    joints : (n + 1, 3) array
        Joint positions from the base, then the tip.
    tip : (3,) array
    tip_quaternion_wxyz : (4,) array
    tip_rpy_deg : (3,) array
        The tool frame's orientation, a quaternion and URDF's roll, pitch, yaw in degrees.
    notes : tuple of str
        Joints outside the scene's limits (none for an arm made of flags).
    """

    problem: Problem
    phi: np.ndarray
    angles_deg: np.ndarray
    joint_degrees: np.ndarray
    joints: np.ndarray
    tip: np.ndarray
    tip_quaternion_wxyz: np.ndarray
    tip_rpy_deg: np.ndarray
    notes: tuple[str, ...]


def forward_pose(model: SceneModel, angles: np.ndarray, in_radians: bool = False, with_notes: bool = False) -> FkAnswer:
    """Forward kinematics of ``model``'s arm at ``angles`` ((n,), degrees, or radians with
    ``in_radians``); ``with_notes``: name the joints outside the scene's limits.

    >>> from armanim.scene import scene_model
    >>> answer = forward_pose(scene_model({"version": 1, "arm": {"links": [1, 1]}, "goals": [[1, 0, 1]]}), np.array([0.0, 90.0]))
    >>> answer.tip.round(12).tolist(), answer.angles_deg.tolist()
    ([1.0, 0.0, 1.0], [0.0, 90.0])
    """
    problem = scene_to_problem(model, own_pairs=False)  # one pose's FK asks nothing of them
    slides = problem.arm.prismatic  # a prismatic joint's value is metres either way
    phi = angles if in_radians else (radians(angles) if slides is None else joints_in_si(angles, slides))
    pose = forward(problem.arm, phi)
    rot = tool_rotation(problem.arm, pose)
    return FkAnswer(
        problem=problem,
        phi=phi,
        angles_deg=joints_shown(angles, slides) if in_radians else angles,
        joint_degrees=joints_shown(phi, slides),
        joints=pose.points,
        tip=pose.tip,
        tip_quaternion_wxyz=rotation_quaternion(rot),
        tip_rpy_deg=np.degrees(rotation_rpy(rot)),
        notes=tuple(problem.limits.notes(phi)) if with_notes else (),
    )


@dataclass(frozen=True)
class PoseMiss:
    """Why ``armanim ik`` did not reach a pose: ``kind``, and ``text``, what it says (``reason`` in its JSON)."""

    kind: Literal["out_of_reach", "numerical", "no_pose_found", "orientation_unreachable"]
    text: str


@dataclass(frozen=True)
class IkAnswer:
    """One pose solved to convergence (``armanim ik``).

    Attributes
    ----------
    problem : Problem
        The arm with the method and tolerances solved with.
    target : (3,) array
    solution : armanim.motion.ik.PoseSolution
        The outcome: status, angles (radians), tip, distance, counts, who found it.
    angles_deg : (n,) array
        The solution's angles, degrees.
    orientation_error_deg : float or None
        The tool's angle from the goal's orientation, degrees (None without one).
    orientation_tolerance_deg : float
    self_clearance : float or None
        The least gap of the arm's own enabled pairs, and ``self_pair``, that pair (None without pairs).
    self_pair : str or None
    miss : PoseMiss or None
        Why the pose was not reached (None when it converged).
    """

    problem: Problem
    target: np.ndarray
    solution: PoseSolution
    angles_deg: np.ndarray
    orientation_error_deg: float | None
    orientation_tolerance_deg: float
    self_clearance: float | None
    self_pair: str | None
    miss: PoseMiss | None


def ik_problem(model: SceneModel, method: str | None, tolerance: float | None, from_flags: bool) -> Problem:
    """The scene's problem with ``--method`` and ``--tolerance`` applied (an arm made of
    flags solves to 0.001 unless told otherwise: the scene default suits animation, not one pose)."""
    problem = scene_to_problem(model)
    settings = problem.solver
    if method is not None:
        if method not in METHODS:
            raise UsageError(f"--method: {method!r} is not a method (expected one of {', '.join(METHODS)})")
        settings = replace(settings, method=method)
    if tolerance is not None and not tolerance > 0:
        raise UsageError(f"--tolerance: must be > 0 (got {tolerance})")
    if tolerance is not None or from_flags:
        settings = replace(settings, tolerance=tolerance or 1e-3)
    return replace(problem, solver=settings)


def with_orientation_tolerance(problem: Problem, degrees: float) -> Problem:
    """``problem`` with ``--orientation-tolerance`` (degrees), checked by the scene's own field
    (``solver.orientation_tolerance``) and converted as a scene's is."""
    try:
        SolverModel(orientation_tolerance=degrees)
    except ValidationError:
        raise UsageError(
            f"--orientation-tolerance: expected degrees in [{MIN_DEGREES:g}, 180] (got {degrees:g})"
        ) from None
    return replace(problem, solver=replace(problem.solver, orientation_tolerance=float(radians(degrees))))


def solve_ik(
    problem: Problem,
    target: np.ndarray,
    start_deg: np.ndarray | None,
    max_iterations: int,
    orientation: Orientation | None = None,
) -> IkAnswer:
    """Solve one pose of ``problem``'s arm to ``target`` from ``start_deg`` (degrees; default home)."""
    phi0 = radians(start_deg) if start_deg is not None else problem.home
    solution = solve_pose(problem, target, phi0, max_iterations, orientation=orientation)
    gap, pair = least_self_gap(problem, solution.phi)
    return IkAnswer(
        problem=problem,
        target=target,
        solution=solution,
        angles_deg=joints_shown(solution.phi, problem.arm.prismatic),
        orientation_error_deg=None
        if solution.orientation_error is None
        else float(np.degrees(solution.orientation_error)),
        orientation_tolerance_deg=float(np.degrees(problem.solver.orientation_tolerance)),
        self_clearance=gap,
        self_pair=pair,
        miss=pose_miss(problem, target, solution),
    )


def least_self_gap(problem: Problem, phi: np.ndarray) -> tuple[float | None, str | None]:
    """The least gap of the arm's own enabled pairs at ``phi`` and its pair (None, None without pairs)."""
    if not len(problem.self_pairs):
        return None, None
    gaps = self_gaps(forward(problem.arm, phi), problem.capsules, problem.self_pairs).d
    return float(gaps.min()), problem.self_pairs.labels[int(np.argmin(gaps))]


def pose_miss(problem: Problem, target: np.ndarray, solution: PoseSolution) -> PoseMiss | None:
    """Why the pose was not reached, when it can be told: the goal out of reach, the linear
    algebra failing, the tip at the goal but not the tool's orientation; None when it converged."""
    if solution.status == "converged":
        return None
    away = float(np.linalg.norm(target - problem.arm.base))
    if solution.orientation_error is not None and solution.distance < problem.solver.tolerance:
        return PoseMiss(
            "orientation_unreachable",
            (
                f"orientation_unreachable: the tip is at the goal, the tool {np.degrees(solution.orientation_error):.3g} deg from its "
                "orientation, the closest these attempts found (an arm with fewer than 6 joints cannot hold every orientation)"
            ),
        )
    if beyond_reach(problem, target):
        unit = length_unit(problem.arm)
        return PoseMiss(
            "out_of_reach",
            f"out of reach: the goal is {away:.4g} {unit} from the base, the arm is "
            f"{problem.arm.reach:.4g} {unit} long (the tip is as close as it gets)",
        )
    if solution.status == "numerical":
        return PoseMiss(
            "numerical",
            "numerical: a step failed in linear algebra (a singular matrix or a NaN); "
            "try another --method or --from other angles",
        )
    return PoseMiss(
        "no_pose_found",
        "no pose found within the iterations (a local minimum, a limit or an obstacle in the way: "
        "try --from other angles)",
    )


def ik_report(answer: IkAnswer) -> dict:
    """``armanim ik --json``'s fields: the method, the outcome, the pose, why it was not reached."""
    solution = answer.solution
    data = {
        "method": answer.problem.solver.method,
        "converged": solution.converged,
        "status": solution.status,
        "angles_deg": answer.angles_deg.tolist(),
        "tip": solution.tip.tolist(),
        "error": solution.distance,
        "steps": solution.steps,
        "iterations": solution.iterations,
        "found_by": solution.found_by,
    }
    if answer.orientation_error_deg is not None:
        data["orientation_error_deg"] = answer.orientation_error_deg
    if answer.self_clearance is not None:
        data["self_clearance"] = answer.self_clearance
        data["self_pair"] = answer.self_pair
    if answer.miss is not None:
        data["reason"] = answer.miss.text
    if answer.problem.solver.method == "newton":
        data["gd_iterations"] = data.pop("iterations")
        data["newton_iterations"] = solution.newton_iterations
    return data
