"""A solved run: the one value every writer of a run reads.

Made once per run by :func:`armanim.runs.pipeline.solved_run` (a fresh solve, or a finished
run read back for another fps); trajectory.csv, summary.json, the viewer page, the video, the
plot and the poster are each written from it, as ``writer(run, ..., path)``.

It lives here, in the lowest room that writes it (output/ writes the CSV and the summary, and
render/ above it draws the pictures), and not in motion/: besides the problem and its solution
it carries the scene's name and the identity of its file, which the pure core never sees.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from armanim.arm.visuals import ArmMeshes, LinkPlaces
from armanim.motion.problem import Problem
from armanim.motion.solution import GoalReport, Solution, Trajectory


@dataclass(frozen=True)
class RunTiming:
    """Wall times of one solve, seconds: never in summary.json or trajectory.csv, which reruns
    reproduce byte for byte.

    Attributes
    ----------
    convert_s : float
        The validated scene to the motion problem (the robot's kinematics, capsules, pairs).
    solve_s : float
        The frame loop over every goal: IK, planning and frames.
    clock_s : float
        The solved path put on the clock (TOPP-RA, its probes and detours) at the output rate.
    goals : tuple of float
        Each goal's share of ``solve_s``, in the order of the scene's goals.
    """

    convert_s: float
    solve_s: float
    clock_s: float
    goals: tuple[float, ...]

    @property
    def scene_to_trajectory_s(self) -> float:
        """From the validated scene to the timed trajectory: ``convert_s + solve_s + clock_s``."""
        return self.convert_s + self.solve_s + self.clock_s


@dataclass(frozen=True)
class SolvedRun:
    """A scene solved and put on the clock at its output rate.

    Attributes
    ----------
    name : str
        The scene's name: its run folder and the pictures' title.
    problem : Problem
        The problem at the output rate: ``problem.fps`` is the rate of the trajectory's frames.
    solution : Solution
        The trajectory (F frames at ``problem.fps``) and one report per goal.
    scene_file : str
        The scene file's name, as summary.json records it.
    sha256 : str
        Of the scene file's bytes.
    rate_notes : tuple of str
        The scene's joint rate limits above the robot's own
        (:func:`armanim.scene.checks.rate_note_lines`), for summary.json.
    meshes : ArmMeshes or None
        How the robot looks (its URDF's visual meshes, placed on the arm's frames), for the
        pictures; None: it is drawn as its capsules.
    places : dict or None
        Where each link of a URDF robot sits on ``problem.arm``'s joints
        (:data:`armanim.arm.visuals.LinkPlaces`), made with the problem: ``meshes`` are placed by
        it. None for an arm of links.
    timing : RunTiming or None
        How long the solve took (a fresh solve; None for a run read back), for timing.json.
    """

    name: str
    problem: Problem
    solution: Solution
    scene_file: str = ""
    sha256: str = ""
    rate_notes: tuple[str, ...] = ()
    meshes: ArmMeshes | None = None
    places: LinkPlaces | None = field(default=None, compare=False, repr=False)
    timing: RunTiming | None = field(default=None, compare=False)

    @property
    def trajectory(self) -> Trajectory:
        """The frames of the run."""
        return self.solution.trajectory

    @property
    def reports(self) -> tuple[GoalReport, ...]:
        """One report per goal: reached or missed, its frames."""
        return self.solution.goals

    @property
    def fps(self) -> float:
        """Frames per second of the trajectory: the one rate of everything written from the run."""
        return self.solution.trajectory.fps
