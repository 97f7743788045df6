"""Running armanim on the benchmark's scenes: a timed solve per method and planner, the
invariants of each trajectory, the oracle's labels, and paired timings of shapes against their
spheres-only twins.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
from generators.arms import Draft
from generators.families import SHAPE_FAMILIES, make_scene, scene_name
from oracles.geometry import DEFAULT_CLEARANCE, Geometry
from oracles.reach import is_witness, label_goal
from oracles.robots import min_clearance

from armanim.arm.kinematics import forward
from armanim.motion.trajectory import solve_trajectory
from armanim.scene import scene_model
from armanim.scene.convert import scene_to_problem
from armanim.scene.models import SceneModel, SolverModel
from armanim.world.distances import clearances, min_link_clearance

METHODS = ("pinv", "dls", "newton", "gradient")


NEAR_SURFACE = 1e-3  # a frame "touches" when its smallest clearance is below this


AT_LIMIT = 1e-3  # radians: a frame "rests on a limit" when a joint is this close to it


ROUNDING = 1e-9  # slack of the invariants


def planner_field_exists() -> bool:
    """Whether this armanim has ``solver.planner``."""
    return "planner" in SolverModel.model_fields


def clearance_of(model: SceneModel) -> float | None:
    """The scene's resolved ``solver.clearance`` (scene units), or None when armanim has no such field."""
    if "clearance" not in SolverModel.model_fields:
        return None
    resolved = getattr(scene_to_problem(model).solver, "clearance", None)
    value = resolved if resolved is not None else model.solver.clearance
    return float(value) if value is not None else None


def timed_solve(problem):
    """Solve and time it: (solution, total seconds, per-goal end times in seconds from the start,
    CPU seconds of this process: less hit than the wall clock by other work on the machine)."""
    marks = []
    cpu = time.process_time()
    start = time.perf_counter()

    def progress(done, _bound):
        marks.append((done, time.perf_counter() - start))

    try:
        solution = solve_trajectory(problem, progress=progress)
    except TypeError:  # a solve_trajectory without progress
        solution = solve_trajectory(problem)
    return solution, time.perf_counter() - start, marks, time.process_time() - cpu


def goal_wall_times(reports, marks, total: float) -> list[float]:
    """Wall time of each goal from the progress marks (nan when there are none)."""
    if not marks:
        return [float("nan")] * len(reports)
    counts = np.array([m[0] for m in marks])
    times = np.array([m[1] for m in marks])
    ends, previous = [], 0.0
    for report in reports:
        last = report.last_frame + 1 if report.last_frame >= 0 else None
        if last is not None:
            upto = np.nonzero(counts <= last)[0]
            previous = float(times[upto[-1]]) if len(upto) else previous
        ends.append(previous)
    return list(np.diff([0.0] + ends))


def invariant_breaks(problem, trajectory, clearance: float | None, geo: Geometry) -> list[str]:
    """Every invariant a trajectory breaks, as short messages (empty: all hold).

    NaN anywhere; a limited joint on or past its limit; the smallest capsule clearance
    (armanim's own and the oracle's recomputation) below the setting (or <= 0 without
    one); a joint turning more than ``max_joint_step`` in a frame (wrap-aware).
    """
    breaks = []
    phi = trajectory.phi
    if not (
        np.all(np.isfinite(phi)) and np.all(np.isfinite(trajectory.tip)) and not np.any(np.isnan(trajectory.clearance))
    ):
        return ["NaN or infinity in phi, tip or clearance"]
    lim = problem.limits
    outside = (phi <= lim.lower) | (phi >= lim.upper)
    if np.any(outside):
        frame, joint = np.argwhere(outside)[0]
        breaks.append(
            f"joint {joint + 1} at {np.degrees(phi[frame, joint]):.6g} deg on frame {frame} is not strictly inside its limits"
        )
    floor = clearance - ROUNDING if clearance is not None else 0.0
    for source, values in (("armanim", trajectory.clearance), ("oracle", min_clearance(geo, phi))):
        bad = values < floor if clearance is not None else values <= floor
        if np.any(bad):
            frame = int(np.argmax(bad))
            wanted = f">= {clearance:.3g} (solver.clearance)" if clearance is not None else "> 0"
            breaks.append(f"clearance {values[frame]:.3g} ({source}) on frame {frame}, expected {wanted}")
    if len(phi) > 1:
        turn = np.abs(np.mod(np.diff(phi, axis=0) + np.pi, 2 * np.pi) - np.pi)
        if turn.max() > problem.solver.max_joint_step + ROUNDING:
            frame = int(np.argmax(turn.max(axis=1))) + 1
            breaks.append(
                f"a joint turned {np.degrees(turn.max()):.12g} deg on frame {frame} (max_joint_step "
                f"{np.degrees(problem.solver.max_joint_step):.12g}, excess {turn.max() - problem.solver.max_joint_step:.3g} rad)"
            )
    return breaks


@dataclass
class Run:
    """One scene solved with one method and planner setting."""

    scene: int
    kind: str
    method: str
    planner: str
    reached: list  # per goal
    reasons: list  # per goal: None or the miss reason
    planned: list  # per goal: True / False, or None when GoalReport has no ``planned``
    easy: list  # per goal: for a feasible miss, whether a straight joint-space line to an oracle pose is clear
    goal_seconds: list
    frames: int
    near_surface: int
    at_limit: int
    seconds: float
    breaks: list
    cpu_seconds: float = 0.0


def straight_line_clear(geo: Geometry, start: np.ndarray, end: np.ndarray) -> bool:
    """True when the straight joint-space segment start-end stays inside the limits and never enters a sphere.

    Sampled so that no arm point moves more than 0.02 (or the clearance, if smaller) between
    samples, at most 20000 samples. The start is the arm's own pose, which may touch a surface,
    so the test is clearance > 0, not >= the clearance setting.
    """
    travel = geo.reach * np.abs(end - start).sum()  # bounds how far any arm point moves along the segment
    samples = int(min(max(np.ceil(travel / min(geo.clearance, 0.02)), 2), 20000))
    path = start + np.linspace(0.0, 1.0, samples)[:, None] * (end - start)
    inside = np.all((path > geo.lower) & (path < geo.upper))
    return bool(inside and np.all(min_clearance(geo, path) > 0))


def easy_misses(geo: Geometry, verdicts: list, reports, phi: np.ndarray) -> list:
    """Per goal: for a feasible goal missed, whether the straight joint-space line from the arm's
    last pose on that goal to the oracle's pose is clear (an easy miss); None otherwise."""
    easy, pose = [], phi[0]
    for verdict, report in zip(verdicts, reports):
        pose = phi[report.last_frame] if report.last_frame >= 0 else pose
        easy.append(straight_line_clear(geo, pose, verdict.pose) if verdict.feasible and not report.reached else None)
    return easy


def solve_one(draft: Draft, seed: int, index: int, method: str, planner: str, geo: Geometry, verdicts: list) -> Run:
    """Solve a scene with one method and planner setting, and check its trajectory."""
    field_planner = planner if planner_field_exists() else None
    model = scene_model(draft.as_scene_dict(scene_name(seed, index, method, field_planner), method, field_planner))
    problem = scene_to_problem(model)
    try:
        solution, seconds, marks, cpu_seconds = timed_solve(problem)
    except Exception as exc:  # noqa: BLE001 - a crash is a broken invariant reported with its scene, not the end of the run
        return crashed_run(draft, index, method, planner, exc)
    traj = solution.trajectory
    lim = problem.limits
    gaps = np.minimum(traj.phi - lim.lower, lim.upper - traj.phi)
    return Run(
        scene=index,
        kind=draft.kind,
        method=method,
        planner=planner,
        reached=[bool(g.reached) for g in solution.goals],
        reasons=[g.reason for g in solution.goals],
        planned=[getattr(g, "planned", None) for g in solution.goals],
        easy=easy_misses(geo, verdicts, solution.goals, traj.phi),
        goal_seconds=goal_wall_times(solution.goals, marks, seconds),
        frames=int(traj.frames),
        near_surface=int(np.sum(traj.clearance < NEAR_SURFACE)),
        at_limit=int(np.sum(np.any(gaps < AT_LIMIT, axis=1))),
        seconds=seconds,
        breaks=invariant_breaks(problem, traj, clearance_of(model), geo),
        cpu_seconds=cpu_seconds,
    )


def crashed_run(draft: Draft, index: int, method: str, planner: str, exc: Exception) -> Run:
    """The Run of a solve that raised: every goal missed with reason ``crash``, one broken invariant."""
    goals = len(draft.goals)
    return Run(
        scene=index,
        kind=draft.kind,
        method=method,
        planner=planner,
        reached=[False] * goals,
        reasons=["crash"] * goals,
        planned=[None] * goals,
        easy=[None] * goals,
        goal_seconds=[float("nan")] * goals,
        frames=0,
        near_surface=0,
        at_limit=0,
        seconds=0.0,
        breaks=[f"solve_trajectory raised {type(exc).__name__}: {exc}"],
    )


@dataclass
class SceneResult:
    """Everything measured on one scene: the oracle's labels and one Run per method and planner."""

    index: int
    kind: str
    verdicts: list
    witness_missed: int  # goals whose generator pose is a witness but the oracle found none
    oracle_seconds: float
    runs: list
    twin_runs: list = field(
        default_factory=list
    )  # (method, frames, seconds, CPU seconds) of the spheres-only twin (shape families)
    shape_times: list = field(
        default_factory=list
    )  # (method, frames, seconds, CPU seconds) of the shapes, timed beside the twin
    distance_seconds: tuple = ()  # (shapes single, twin single, shapes batched, twin batched) seconds per pose


def oracle_geometry(draft: Draft, seed: int, index: int) -> Geometry:
    """The oracle's geometry of a scene, with armanim's tolerance and clearance setting."""
    model = scene_model(draft.as_scene_dict(scene_name(seed, index)))
    clearance = clearance_of(model)
    return draft.geometry(DEFAULT_CLEARANCE if clearance is None else clearance, model.solver.tolerance)


def label_scene(draft: Draft, geo: Geometry, seed: int, index: int) -> tuple[list, int]:
    """The oracle's verdict on every goal, and how many generator witnesses it failed to match."""
    verdicts, missed = [], 0
    for k, goal in enumerate(draft.goals):
        witness = draft.witnesses[k]
        orientation = draft.orientations[k] if draft.orientations else None
        verdict = label_goal(geo, goal, np.random.default_rng([seed, index, k, 7]), orientation=orientation)
        if not verdict.feasible and witness is not None and is_witness(geo, goal, witness, orientation):
            missed += 1
        verdicts.append(verdict)
    return verdicts, missed


def bench_scene(task: tuple) -> SceneResult:
    """Worker: generate scene ``index``, label its goals, solve it with every method and planner setting."""
    seed, index, methods, planners, family, rounds = task
    draft = make_scene(seed, index, family)
    geo = oracle_geometry(draft, seed, index)
    start = time.perf_counter()
    verdicts, missed = label_scene(draft, geo, seed, index)
    oracle_seconds = time.perf_counter() - start
    runs = [solve_one(draft, seed, index, m, p, geo, verdicts) for m in methods for p in planners]
    timings = (
        [paired_timing(draft, seed, index, run, rounds) for run in runs if run.planner == planners[0]]
        if family in SHAPE_FAMILIES
        else []
    )
    distances = distance_timing(draft, seed, index) if family in SHAPE_FAMILIES else ()
    return SceneResult(
        index,
        draft.kind,
        verdicts,
        missed,
        oracle_seconds,
        runs,
        twin_runs=[t for _, t in timings],
        shape_times=[s for s, _ in timings],
        distance_seconds=distances,
    )


def distance_timing(draft: Draft, seed: int, index: int, poses: int = 200, batch: int = 2000) -> tuple:
    """Seconds per pose of armanim's clearances (forward kinematics included) with the scene's shapes
    and with its spheres-only twin: every clearance of one pose at a time (what each frame's filter
    computes) and the smallest of ``batch`` poses at once (``min_link_clearance``: what the planner
    checks), the best of three rounds each."""
    problems = [
        scene_to_problem(scene_model(d.as_scene_dict(scene_name(seed, index)))) for d in (draft, draft.spheres_twin())
    ]
    rng = np.random.default_rng([seed, index, 22])
    phi = rng.uniform(-np.pi, np.pi, (batch, problems[0].arm.n))
    out = []
    for single in (True, False):
        for problem in problems:
            best = np.inf
            for _ in range(3):
                start = time.perf_counter()
                if single:
                    for q in phi[:poses]:
                        clearances(forward(problem.arm, q), problem.obstacles, problem.capsules)
                else:
                    min_link_clearance(forward(problem.arm, phi), problem.obstacles, problem.capsules)
                best = min(best, (time.perf_counter() - start) / (poses if single else batch))
            out.append(best)
    return tuple(out)


def scene_problem(draft: Draft, seed: int, index: int, method: str, planner: str):
    """armanim's problem of a draft solved with one method and planner setting."""
    field_planner = planner if planner_field_exists() else None
    return scene_to_problem(
        scene_model(draft.as_scene_dict(scene_name(seed, index, method, field_planner), method, field_planner))
    )


def paired_timing(draft: Draft, seed: int, index: int, run: Run, rounds: int) -> tuple[tuple, tuple]:
    """(method, frames, seconds, CPU seconds) of the scene with its shapes and of its spheres-only
    twin (:meth:`Draft.spheres_twin`) solved alike, each the best of ``rounds`` solves taken in
    turn (shapes, twin, shapes, ...; the first shapes solve is ``run``'s own), so that both meet
    the same moments of a shared machine's load. A solve is deterministic: each round repeats it."""
    shaped = scene_problem(draft, seed, index, run.method, run.planner)
    twin = scene_problem(draft.spheres_twin(), seed, index, run.method, run.planner)
    best = {"shapes": [run.frames, run.seconds, run.cpu_seconds], "twin": [0, np.inf, np.inf]}
    for k in range(rounds):
        for name, problem in (("shapes", shaped), ("twin", twin)):
            if name == "shapes" and k == 0:
                continue  # timed already by solve_one
            solution, seconds, _, cpu_seconds = timed_solve(problem)
            kept = best[name]
            kept[0], kept[1], kept[2] = (
                int(solution.trajectory.frames),
                min(kept[1], seconds),
                min(kept[2], cpu_seconds),
            )
    return tuple([run.method] + best["shapes"]), tuple([run.method] + best["twin"])


def twin_rows(results: list, methods: list, planner: str) -> list[list[str]]:
    """Per method: ms per frame with the shapes, with their spheres-only twins, and the ratio; the
    same in CPU time (the wall clock's ratio moves with whatever else the machine runs)."""
    rows = []
    for method in methods:
        shapes = [t for r in results for t in r.shape_times if t[0] == method]
        twins = [t for r in results for t in r.twin_runs if t[0] == method]
        if not shapes or not twins:
            continue
        frames, twin_frames = max(sum(t[1] for t in shapes), 1), max(sum(t[1] for t in twins), 1)
        shaped = 1000.0 * sum(t[2] for t in shapes) / frames
        spheres = 1000.0 * sum(t[2] for t in twins) / twin_frames
        cpu_shaped = 1000.0 * sum(t[3] for t in shapes) / frames
        cpu_spheres = 1000.0 * sum(t[3] for t in twins) / twin_frames
        rows.append(
            [
                method,
                f"{shaped:.2f}",
                f"{spheres:.2f}",
                f"{shaped / spheres:.2f}x",
                f"{cpu_shaped:.2f}",
                f"{cpu_spheres:.2f}",
                f"{cpu_shaped / cpu_spheres:.2f}x",
            ]
        )
    return rows
