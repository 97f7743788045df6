"""Solver benchmark for armanim: ratios measured in one run, never absolute times.

    python benchmarks/solver_bench.py [--targets 500] [--quick] [--seed 0]

(a) One full frame of armanim's ``pinv`` method on the course notes' arm with three
    obstacles (``pinv_step`` + the barrier's ``shorten_step``) against a plain numpy
    pseudo-inverse step of the same chain with no obstacles (FK + analytic Jacobian +
    ``np.linalg.pinv`` + update, written below). Target: armanim / plain <= 2.5.

(b) Solving to convergence (tolerance 1e-3, no obstacles) from the straight pose, a
    singular pose of this arm, to N random reachable targets: every armanim method via
    ``armanim.motion.ik.solve_pose`` against ikpy's ``Chain.inverse_kinematics``. Target:
    armanim at least 20x faster than ikpy with at least its success rate.

Only ratios of times measured in this run are printed as verdicts, so the numbers mean
the same on a fast or a slow machine. See benchmarks/README.md.
"""

from __future__ import annotations

import argparse
import gc
import time
import warnings
from dataclasses import replace

import numpy as np

from armanim.arm.kinematics import Arm, forward
from armanim.motion.filter.barrier import safe_step
from armanim.motion.ik import solve_pose
from armanim.motion.problem import Goal, Limits, Problem, SolverSettings
from armanim.motion.solvers import METHODS, arm_state
from armanim.motion.solvers.linear import pinv_step
from armanim.scene import default_solver_settings
from armanim.world.distances import clearances, min_link_clearance
from armanim.world.obstacles import Obstacles

# ---------------------------------------------------------------------------------------
# The course notes' arm, its limits and the obstacles of part (a)
# ---------------------------------------------------------------------------------------

LINKS = [2.0, 5.0, 5.0, 5.0]
BASE = (5.0, 5.0, 0.0)
LIMITS_DEG = [None, 100.0, 150.0, 150.0]  # symmetric +-, None = unlimited
MARGIN_DEG = 15.0
WIDTH = 0.6
OBSTACLES = [  # center, radius, influence R
    ((12.0, 9.0, 8.0), 2.0, 2.0),
    ((4.0, 12.0, 11.0), 1.5, 2.0),
    ((9.0, 2.0, 13.0), 1.2, 1.5),
]
TOLERANCE = 1e-3  # part (b)
MAX_ITERATIONS = 2000  # part (b): the default of `armanim ik --max-iterations`

TARGET_FRAME_RATIO = 2.5  # (a): armanim frame / plain frame at most this
TARGET_SPEEDUP = 20.0  # (b): ikpy / armanim at least this


def notes_limits() -> Limits:
    lower = np.array([-np.inf if d is None else -np.radians(d) for d in LIMITS_DEG])
    return Limits(lower=lower, upper=-lower, margin=float(np.radians(MARGIN_DEG)))


def notes_obstacles() -> Obstacles:
    return Obstacles(
        centers=np.array([c for c, _, _ in OBSTACLES], dtype=float),
        radii=np.array([r for _, r, _ in OBSTACLES], dtype=float),
        influence=np.array([big for _, _, big in OBSTACLES], dtype=float),
    )


def make_problem(obstacles: Obstacles, settings: SolverSettings) -> Problem:
    arm = Arm.from_names(LINKS, base=BASE)
    return Problem(
        arm=arm,
        half_width=WIDTH / 2,
        home=np.zeros(arm.n),
        limits=notes_limits(),
        obstacles=obstacles,
        goals=(Goal(np.zeros(3), hold=0.0),),
        solver=settings,
        fps=30.0,
    )


def random_poses(rng: np.random.Generator, count: int, limits: Limits) -> np.ndarray:
    """(count, n) angles uniformly inside the limits, kept off them by the margin."""
    lo = np.where(limits.limited, limits.lower + limits.margin, -np.pi)
    hi = np.where(limits.limited, limits.upper - limits.margin, np.pi)
    return rng.uniform(lo, hi, size=(count, len(lo)))


# ---------------------------------------------------------------------------------------
# The plain reference: self-contained numpy FK, analytic Jacobian, pinv, update
# ---------------------------------------------------------------------------------------

_LINKS = np.array(LINKS)
_BASE = np.array(BASE)


def _rot_z(a: float) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _rot_y(a: float) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def plain_fk(phi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Joint points (5, 3) and world joint axes (4, 3) of the notes' arm, chain z, y, y, y."""
    points = np.empty((5, 3))
    axes = np.empty((4, 3))
    rot = _rot_z(phi[0])
    points[0] = _BASE
    axes[0] = rot[:, 2]
    points[1] = _BASE + _LINKS[0] * rot[:, 2]
    for i in range(1, 4):
        rot = rot @ _rot_y(phi[i])
        axes[i] = rot[:, 1]
        points[i + 1] = points[i] + _LINKS[i] * rot[:, 2]
    return points, axes


def plain_step(phi: np.ndarray, goal: np.ndarray, beta: float = 0.1) -> np.ndarray:
    """One pseudo-inverse frame with no obstacles and no limits: phi + J^+ beta (g - e)."""
    points, axes = plain_fk(phi)
    tip = points[-1]
    jac = np.cross(axes, tip - points[:-1]).T  # (3, 4): column j = w_j x (e - p_j)
    return phi + np.linalg.pinv(jac) @ (beta * (goal - tip))


# ---------------------------------------------------------------------------------------
# Timing: interleaved, min over repeats (timeit's advice: the min is the least noisy)
# ---------------------------------------------------------------------------------------


def interleaved_min(candidates: dict, repeats: int) -> dict:
    """Seconds per call of each zero-argument batch function: min over ``repeats`` rounds,
    the candidates alternated (order reversed every round) so drift hits them alike.

    Each candidate returns how many calls its batch made.
    """
    names = list(candidates)
    best = {name: np.inf for name in names}
    gc_was = gc.isenabled()
    gc.disable()
    try:
        for r in range(repeats):
            for name in names if r % 2 == 0 else reversed(names):
                t0 = time.perf_counter()
                calls = candidates[name]()
                best[name] = min(best[name], (time.perf_counter() - t0) / calls)
    finally:
        if gc_was:
            gc.enable()
    return best


# ---------------------------------------------------------------------------------------
# (a) one frame
# ---------------------------------------------------------------------------------------


def frame_cases(rng: np.random.Generator, problem: Problem, count: int):
    """Collision-free start poses, half of them with some arm part inside an obstacle's
    influence shell (the repulsion is computed), half free; goals are FK of random poses."""
    near, far = [], []
    want = count // 2
    while len(near) < want or len(far) < count - want:
        batch = random_poses(rng, 256, problem.limits)
        pose = forward(problem.arm, batch)
        ok = min_link_clearance(pose, problem.obstacles, problem.capsules) > 0.05
        cl = clearances(pose, problem.obstacles, problem.capsules)
        inside = np.any(cl.d < problem.obstacles.influence, axis=(-1, -2))
        for phi, good, close in zip(batch, ok, inside):
            if not good:
                continue
            bucket = near if close else far
            if len(bucket) < (want if close else count - want):
                bucket.append(phi)
    goals = forward(problem.arm, random_poses(rng, count, problem.limits)).tip
    return np.array(near), np.array(far), goals


def bench_frame(rng: np.random.Generator, poses: int, repeats: int) -> None:
    print("(a) one frame of pinv on the notes' arm, 3 obstacles vs plain numpy pinv step, no obstacles")
    settings = default_solver_settings(method="pinv")
    problem = make_problem(notes_obstacles(), settings)
    bare = make_problem(Obstacles.none(), settings)
    near, far, goals = frame_cases(rng, problem, poses)
    # The frame loop carries each pose's kinematics and clearances from the barrier check
    # of the previous frame (ArmState), so a frame starts from a state, as here.
    phis = np.concatenate([near, far])
    cases = [(arm_state(problem, phi), goal) for phi, goal in zip(phis, goals)]
    bare_cases = [(arm_state(bare, phi), goal) for phi, goal in zip(phis, goals)]
    cases_near = cases[: len(near)]
    cases_far = cases[len(near) :]

    # the two agree on the step itself where nothing is near (sanity, not timing)
    for state, goal in bare_cases[len(near) :][:20]:
        ours = safe_step(bare, state, pinv_step(bare, state, goal).dphi)
        if ours.scale == 1.0:
            ref = plain_step(state.phi, goal, settings.beta)
            assert np.allclose(ours.state.tip, forward(bare.arm, ref).tip, atol=1e-9), (
                "armanim's pinv frame and the plain step disagree"
            )

    def run(step, subset):
        def batch():
            for state, goal in subset:
                step(state, goal)
            return len(subset)

        return batch

    def armanim_frame(prob):
        return lambda state, goal: safe_step(prob, state, pinv_step(prob, state, goal).dphi)

    frame = armanim_frame(problem)
    only_step = lambda state, goal: pinv_step(problem, state, goal)  # noqa: E731
    dphis = {id(state): pinv_step(problem, state, goal).dphi for state, goal in cases}
    only_shorten = lambda state, goal: safe_step(problem, state, dphis[id(state)])  # noqa: E731
    plain = lambda state, goal: plain_step(state.phi, goal, settings.beta)  # noqa: E731

    t = interleaved_min(
        {
            "armanim": run(frame, cases),
            "plain": run(plain, cases),
            "armanim_near": run(frame, cases_near),
            "armanim_far": run(frame, cases_far),
            "armanim_bare": run(armanim_frame(bare), bare_cases),
            "pinv_step": run(only_step, cases),
            "shorten_step": run(only_shorten, cases),
        },
        repeats,
    )
    blocked = sum(
        safe_step(problem, state, dphis[id(state)]).scale
        < min(1.0, settings.max_joint_step / max(np.max(np.abs(dphis[id(state)])), 1e-300))
        for state, _ in cases
    )
    print(
        f"    poses: {len(cases)} ({len(near)} with an obstacle within influence, {len(far)} free); "
        f"{blocked} steps shortened by a barrier; min of {repeats} interleaved repeats"
    )
    ratio = t["armanim"] / t["plain"]
    print(
        f"    armanim frame / plain step            {ratio:6.2f}x   (target <= {TARGET_FRAME_RATIO}x)  "
        f"{'PASS' if ratio <= TARGET_FRAME_RATIO else 'FAIL'}"
    )
    print(f"      poses near an obstacle / plain      {t['armanim_near'] / t['plain']:6.2f}x")
    print(f"      poses free of obstacles / plain     {t['armanim_far'] / t['plain']:6.2f}x")
    print(f"      same frame, no obstacles / plain    {t['armanim_bare'] / t['plain']:6.2f}x")
    print(f"      pinv_step alone / plain             {t['pinv_step'] / t['plain']:6.2f}x")
    print(f"      shorten_step alone / plain          {t['shorten_step'] / t['plain']:6.2f}x")
    print(f"    (plain step: {t['plain'] * 1e6:.0f} us on this machine, for scale only)")


# ---------------------------------------------------------------------------------------
# (b) solve to convergence: armanim methods vs ikpy
# ---------------------------------------------------------------------------------------


def ikpy_chain(limits: Limits):
    """The notes' arm as an ikpy chain: origin, base translation + Rz, then Ry joints with
    their link offsets along z, and a fixed tip link."""
    from ikpy.chain import Chain
    from ikpy.link import OriginLink, URDFLink

    offsets = [BASE] + [(0.0, 0.0, length) for length in LINKS[:-1]]
    axes = [(0, 0, 1)] + [(0, 1, 0)] * (len(LINKS) - 1)
    links = [OriginLink()]
    for i, (offset, axis) in enumerate(zip(offsets, axes)):
        bounds = (float(limits.lower[i]), float(limits.upper[i])) if limits.limited[i] else None
        links.append(
            URDFLink(
                f"joint{i + 1}", origin_translation=offset, origin_orientation=(0, 0, 0), rotation=axis, bounds=bounds
            )
        )
    links.append(
        URDFLink("tip", origin_translation=(0.0, 0.0, LINKS[-1]), origin_orientation=(0, 0, 0), joint_type="fixed")
    )
    mask = [False] + [True] * len(LINKS) + [False]
    return Chain(links, active_links_mask=mask, name="notes_arm")


def check_ikpy_fk(chain, arm: Arm, rng: np.random.Generator) -> float:
    """Largest tip difference between ikpy's and armanim's FK over random poses."""
    worst = 0.0
    for phi in rng.uniform(-np.pi, np.pi, size=(50, arm.n)):
        theirs = chain.forward_kinematics(np.concatenate([[0.0], phi, [0.0]]))[:3, 3]
        worst = max(worst, float(np.linalg.norm(theirs - forward(arm, phi).tip)))
    return worst


def bench_solve(rng: np.random.Generator, count: int) -> None:
    print(
        f"(b) solve to |e - g| < {TOLERANCE:g} from the straight (singular) pose, {count} random "
        f"reachable targets, no obstacles, notes' limits"
    )
    base_settings = default_solver_settings(tolerance=TOLERANCE)
    problems = {m: make_problem(Obstacles.none(), replace(base_settings, method=m)) for m in METHODS}
    arm = problems["pinv"].arm
    limits = problems["pinv"].limits
    targets = forward(arm, random_poses(rng, count, limits)).tip
    start = np.zeros(arm.n)

    try:
        import ikpy

        chain = ikpy_chain(limits)
        mismatch = check_ikpy_fk(chain, arm, rng)
        assert mismatch < 1e-9, f"ikpy's chain is not the notes' arm: FK differs by {mismatch:g}"
        print(
            f"    ikpy {ikpy.__version__}: FK matches armanim.arm.kinematics.forward on 50 random poses "
            f"(max |diff| {mismatch:.1e})"
        )
    except ImportError:
        chain = None
        print(
            "    ikpy is not installed: SKIPPING the ikpy comparison "
            "(install the optional extra: pip install -e .[bench])"
        )

    solvers = {m: (lambda goal, p=problems[m]: solve_pose(p, goal, start, MAX_ITERATIONS)) for m in METHODS}
    # what-if rows, not judged: the linear methods with scene settings suited to solving rather
    # than animating (a full step beta = 1, joints may turn 30 degrees per iteration)
    for m in ("pinv", "dls"):
        fast = replace(problems[m].solver, beta=1.0, max_joint_step=float(np.radians(30.0)))
        solvers[f"{m}*"] = lambda goal, p=replace(problems[m], solver=fast): solve_pose(p, goal, start, MAX_ITERATIONS)
    if chain is not None:
        full_start = np.zeros(len(chain.links))

        def ikpy_solve(goal):
            return chain.inverse_kinematics(goal, initial_position=full_start)[1:-1]

        solvers["ikpy"] = ikpy_solve

    elapsed = {name: 0.0 for name in solvers}
    reached = {name: 0 for name in solvers}
    iterations = {name: 0 for name in solvers}
    names = list(solvers)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for k, goal in enumerate(targets):  # interleaved target by target
            order = names if k % 2 == 0 else names[::-1]
            for name in order:
                t0 = time.perf_counter()
                out = solvers[name](goal)
                elapsed[name] += time.perf_counter() - t0
                phi = out.phi if name != "ikpy" else np.asarray(out)
                if name != "ikpy":
                    iterations[name] += out.iterations
                inside = np.all((phi >= limits.lower) & (phi <= limits.upper))
                if inside and np.linalg.norm(forward(arm, phi).tip - goal) < TOLERANCE:
                    reached[name] += 1

    print(f"    {'solver':<10}{'per solve':>12}{'success':>10}{'mean its':>10}{'ikpy / this':>14}")
    ikpy_time = elapsed.get("ikpy")
    for name in names:
        per = elapsed[name] / count
        speed = f"{ikpy_time / elapsed[name]:13.1f}x" if ikpy_time is not None else f"{'-':>14}"
        its = f"{iterations[name] / count:10.1f}" if name != "ikpy" else f"{'-':>10}"
        print(f"    {name:<10}{per * 1e3:9.2f} ms{100 * reached[name] / count:9.1f}%{its}{speed}")
    print("    * not the defaults: scene settings step: 1, max_joint_step: 30 (what-if, not judged)")
    if ikpy_time is None:
        print("    (no ikpy: speed ratios and the 20x target skipped)")
        return
    print(
        f"    targets: ikpy / armanim >= {TARGET_SPEEDUP:g}x with success >= ikpy's "
        f"({100 * reached['ikpy'] / count:.1f}%)"
    )
    for m in METHODS:
        speed = ikpy_time / elapsed[m]
        ok = speed >= TARGET_SPEEDUP and reached[m] >= reached["ikpy"]
        print(
            f"      {m:<10}{speed:7.1f}x  {'PASS' if ok else 'FAIL'}"
            f"{'' if reached[m] >= reached['ikpy'] else '  (lower success rate)'}"
        )


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--targets", type=int, default=500, help="random reachable targets of part (b)")
    parser.add_argument("--quick", action="store_true", help="fewer poses, repeats and targets (smoke run)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--only", choices=["a", "b"], help="run one part only")
    args = parser.parse_args(argv)
    poses, repeats = (60, 3) if args.quick else (400, 9)
    targets = min(args.targets, 40) if args.quick else args.targets
    print(f"armanim solver benchmark (seed {args.seed}{', quick' if args.quick else ''}); numpy {np.__version__}")
    if args.only in (None, "a"):
        bench_frame(np.random.default_rng(args.seed), poses, repeats)
    if args.only in (None, "b"):
        bench_solve(np.random.default_rng(args.seed + 1), targets)


if __name__ == "__main__":
    main()
