"""Issue 40's comparison in one command: ``python benchmarks/ik_bench.py --compare [--quick]``.

Five parts, each timed in this one process with the contenders interleaved (the order drawn
afresh for every IK target, rotated on every FK or start-up round; the garbage collector off
during each call), so machine load and a predecessor's caches hit them alike; only ratios within
one run are verdicts, times are printed for scale.

1. **FK**, the Panda's tool frame: armanim's numpy ``forward`` + ``tool_rotation``, the compiled
   kernel (``armanim.arm.kernel.forward_with_tool``), pinocchio (``forwardKinematics`` +
   ``updateFramePlacement``), robotics-toolbox's ``ETS.eval``; one pose per call and a batch
   (armanim's batched calls against a Python loop over pinocchio).
2. **6-D pose IK, Panda**: random reachable targets (the tool frame of random poses 0.05 rad
   inside the URDF limits), every solver seeded with the home pose, success judged by pinocchio's
   FK (inside the limits, 1 mm and 1 degree). armanim ``solve_pose`` (what ``armanim ik
   --orientation`` does) with ``pinv`` and ``dls``, with the bundled self-collision (its default)
   and without it (as the peers, which know none); rtb ``ik_LM`` (C++); TRAC-IK (pytracik,
   ``Speed``, 5 ms timeout); a pinocchio CLIK loop (log6 error, damped pseudo-inverse, as
   pinocchio's example); pink (a QP a step, DAQP) and ikpy on fewer targets.
2b. **6-D pose IK, Panda, self-free targets**: targets from random poses inside the limits whose
   enabled pairs of the Panda's own capsules are all at least ``self_clearance`` apart, measured
   by coal on capsules placed by pinocchio's frames (:func:`panda_pair_gaps`, not armanim's
   distance code); the same targets for every solver. armanim with its default self-collision
   succeeds when the answer is reached (as in 2) and keeps every pair apart by that judge; the
   peers know no self-collision and are judged by the FK alone (how many of their answers keep
   the pairs apart is printed beside). Part 2's targets stay as they were: 162 of its 300
   source poses hold two capsules within ``self_clearance``, which armanim refuses by design.
3. **Position IK, the notes' arm** (z, y, y, y; from the singular straight pose): armanim
   ``pinv`` and ``dls``, rtb ``ik_LM`` with a position mask, ikpy; success by a numpy FK written
   here (1 mm, inside the limits).
4. **Start-up**: whole processes, rotated rounds: ``python -c pass``, ``python -c 'import numpy'``,
   the imports of the stack a run is built on (numpy, scipy.linalg, pydantic, yaml, typer, rich,
   numba), ``armanim --version``, ``armanim run scenes/notes-arm.yaml --no-video``; and the
   small run's time as a ratio to the stack's imports.

The peers (robotics-toolbox, TRAC-IK, pink, ikpy; pinocchio comes with the test extra) are optional: a missing
one is a row that says so. Set ``OPENBLAS_NUM_THREADS=1`` (done here before numpy loads).
"""

from __future__ import annotations

import gc
import os
import statistics
import subprocess
import sys
import time
import warnings
from pathlib import Path

for _name in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_name, "1")

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
POS_TOL, ANG_TOL = 1e-3, np.radians(1.0)
NOTES_LINKS, NOTES_BASE, NOTES_LIMITS_DEG = (2.0, 5.0, 5.0, 5.0), (5.0, 5.0, 0.0), (None, 100.0, 150.0, 150.0)


def timed(call, *args):
    """(seconds, result) of one call, the garbage collector off."""
    gc.disable()
    try:
        start = time.perf_counter()
        out = call(*args)
        return time.perf_counter() - start, out
    finally:
        gc.enable()


def pct(values, q: float) -> float:
    return float(np.percentile(np.asarray(values), q))


def ms(seconds: float) -> str:
    return f"{seconds * 1e3:.3f} ms" if seconds >= 1e-3 else f"{seconds * 1e6:.1f} us"


def optional(make):
    """``make()``, or None and why when its library is missing or fails to load."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return make(), None
    except ImportError as exc:
        return None, f"not installed ({exc.name}): pip install -e .[bench] (benchmarks/README.md)"
    except Exception as exc:  # noqa: BLE001 (a peer that cannot load is a row saying why)
        return None, f"cannot load: {exc}"


# ----------------------------------------------------------------------------- the Panda in every library


def panda_problem(method: str, self_collision: str = "auto"):
    from armanim.scene import scene_model, scene_to_problem

    return scene_to_problem(
        scene_model(
            {
                "version": 1,
                "arm": {"robot": "panda", "self_collision": self_collision},
                "goals": [[0.3, 0.0, 0.4]],
                "solver": {"method": method, "tolerance": POS_TOL, "orientation_tolerance": 1.0},
            }
        )
    )


def kinematic_urdf(path: Path) -> Path:
    from ik_bench import kinematic_urdf as strip

    return strip(path)


def panda_pinocchio():
    """pinocchio's model of the bundled URDF reduced to the 7 arm joints (the fingers locked)."""
    import pinocchio as pin

    from armanim.scene.robots import bundled_robot

    info = bundled_robot("panda")
    full = pin.buildModelFromUrdf(str(kinematic_urdf(info.urdf)))
    arm_joints = [f"panda_joint{i}" for i in range(1, 8)]
    lock = [full.getJointId(n) for n in full.names[1:] if n not in arm_joints]
    model = pin.buildReducedModel(full, lock, pin.neutral(full)) if lock else full
    return pin, model, model.createData(), model.getFrameId(info.tip_link)


def pinocchio_clik(its: int = 100, restarts: int = 20, damp: float = 1e-6, cap: float = 1.0, seed: int = 0):
    """pinocchio's CLIK example (log6 error in the tool frame, -Jlog6 J, damped pseudo-inverse),
    the step capped at 1 rad, clamped to the limits, random restarts."""
    pin, model, data, tip = panda_pinocchio()
    lo, hi = model.lowerPositionLimit.copy(), model.upperPositionLimit.copy()
    rng = np.random.default_rng(seed)
    eye6 = np.eye(6)

    def solve(p, rot, q0):
        target = pin.SE3(rot, p)
        q = np.array(q0, dtype=float)
        for _ in range(restarts + 1):
            for _ in range(its):
                pin.forwardKinematics(model, data, q)
                placed = pin.updateFramePlacement(model, data, tip)
                dpos = p - placed.translation
                error = placed.actInv(target)
                err = pin.log6(error).vector
                if dpos @ dpos < POS_TOL * POS_TOL and np.sqrt(err[3:] @ err[3:]) < ANG_TOL:
                    return q
                jac = -pin.Jlog6(error.inverse()) @ pin.computeFrameJacobian(
                    model, data, q, tip, pin.ReferenceFrame.LOCAL
                )
                v = -jac.T @ np.linalg.solve(jac @ jac.T + damp * eye6, err)
                n = np.sqrt(v @ v)
                if n > cap:
                    v *= cap / n
                q = np.clip(q + v, lo, hi)
            q = rng.uniform(lo, hi)
        return q

    return solve


def rtb_panda():
    import roboticstoolbox as rtb

    from armanim.scene.robots import bundled_robot

    info = bundled_robot("panda")
    ets = rtb.Robot.URDF(str(kinematic_urdf(info.urdf))).ets(start=info.base_link, end=info.tip_link)
    tol = 0.5 * (0.9e-3) ** 2  # rtb stops on E = 1/2 |[e_p; e_r]|^2

    def solve(p, rot, q0):
        t = np.eye(4)
        t[:3, :3], t[:3, 3] = rot, p
        return np.asarray(ets.ik_LM(t, q0=q0, joint_limits=True, tol=tol, ilimit=30, slimit=100).q)

    return ets, solve


def tracik_panda(timeout: float = 0.005, eps: float = 1e-5):
    """TRAC-IK (pytracik, ``Speed``: KDL's Newton and an SQP raced, random restarts within the
    timeout), given the URDF's own limits: pytracik 0.0.3 reads this URDF's as [0, 0]."""
    import pytracik

    from armanim.scene.robots import bundled_robot

    info = bundled_robot("panda")
    text = kinematic_urdf(info.urdf).read_text()
    solver = pytracik.TRAC_IK(info.base_link, info.tip_link, text, timeout, eps, pytracik.SolveType.Speed)
    limits = panda_problem("pinv").limits
    pytracik.set_joint_limits(solver, [float(v) for v in limits.lower], [float(v) for v in limits.upper])

    def solve(p, rot, q0):
        x, y, z, w = quaternion_xyzw(rot)
        found = pytracik.ik(solver, np.asarray(q0, dtype=float), p[0], p[1], p[2], x, y, z, w)
        return np.asarray(found[1:]) if found[0] >= 0 else None

    return solve


def quaternion_xyzw(rot: np.ndarray) -> tuple[float, float, float, float]:
    """A rotation matrix's unit quaternion (x, y, z, w), by scipy (not armanim)."""
    from scipy.spatial.transform import Rotation

    x, y, z, w = Rotation.from_matrix(rot).as_quat()
    return float(x), float(y), float(z), float(w)


def pink_panda(its: int = 100, restarts: int = 20, seed: int = 0):
    """pink's differential IK iterated to the pose: a FrameTask (position and orientation cost 1),
    its configuration limits, one QP a step (DAQP through qpsolvers), random restarts as rtb's."""
    import pink
    from pink.tasks import FrameTask

    from armanim.scene.robots import bundled_robot

    pin, model, data, _ = panda_pinocchio()
    tip = bundled_robot("panda").tip_link
    lo, hi = model.lowerPositionLimit.copy(), model.upperPositionLimit.copy()
    rng = np.random.default_rng(seed)
    task = FrameTask(tip, position_cost=1.0, orientation_cost=1.0, lm_damping=1e-6)

    def solve(p, rot, q0):
        task.set_target(pin.SE3(rot, p))
        q = np.array(q0, dtype=float)
        for _ in range(restarts + 1):
            conf = pink.Configuration(model, data, q)
            for _ in range(its):
                placed = conf.get_transform_frame_to_world(tip)
                if (
                    np.linalg.norm(p - placed.translation) < POS_TOL
                    and np.linalg.norm(pin.log3(placed.rotation.T @ rot)) < ANG_TOL
                ):
                    return conf.q
                conf.integrate_inplace(
                    pink.solve_ik(conf, [task], 1.0, solver="daqp", damping=1e-12, safety_break=False), 1.0
                )
            q = rng.uniform(lo, hi)
        return conf.q

    return solve


def pose_peers():
    """(name, make) of each optional peer of the 6-D Panda parts: ``make()`` gives its solve(p, rot, q0)."""
    return (
        ("rtb ik_LM (C++)", lambda: rtb_panda()[1]),
        ("TRAC-IK (pytracik, 5 ms)", tracik_panda),
        ("pink (QP, DAQP)", pink_panda),
        ("ikpy", ikpy_panda),
    )


FEWER_TARGETS = ("pink (QP, DAQP)", "ikpy")
"""The slow peers, timed on a fifth of the targets."""


def pose_solvers(problems: dict, warm_up: tuple) -> tuple[dict, list[str]]:
    """The 6-D Panda parts' contenders, each solve(p, rot, q0) -> q or None, run once on
    ``warm_up`` (numba's cache, rtb's first call): armanim ``solve_pose`` on each of ``problems``
    (name -> Problem), pinocchio's CLIK loop and the installed peers; and a line for each skipped one."""
    from armanim.motion.ik import solve_pose
    from armanim.motion.orientation import Orientation

    solvers = {
        f"armanim {m}": (lambda p, r, q0, pr=pr: solve_pose(pr, p, q0, 2000, orientation=Orientation(rotation=r)).phi)
        for m, pr in problems.items()
    }
    solvers["pinocchio CLIK loop"] = pinocchio_clik()
    skipped = []
    for name, make in pose_peers():
        solve, why = optional(make)
        if solve is None:
            skipped.append(f"   {name:34s} skipped: {why}")
        else:
            solvers[name] = solve
    for solve in solvers.values():
        solve(*warm_up)
    return solvers, skipped


def pinocchio_judge(parts):
    """judge(q, case): q reaches the case's (p, rot) by pinocchio's FK (1 mm, 1 degree), inside the limits."""
    pin, model, data, tip = parts
    lo, hi = model.lowerPositionLimit, model.upperPositionLimit

    def judge(q, case):
        if q.shape != (7,) or not np.all(np.isfinite(q)) or np.any(q < lo - 1e-9) or np.any(q > hi + 1e-9):
            return False
        pin.forwardKinematics(model, data, q)
        placed = pin.updateFramePlacement(model, data, tip)
        angle = np.arccos(np.clip((np.trace(placed.rotation.T @ case[1]) - 1) / 2, -1, 1))
        return bool(np.linalg.norm(placed.translation - case[0]) < POS_TOL and angle < ANG_TOL)

    return judge


def ikpy_panda():
    from ik_bench import urdf_path_elements
    from ikpy.chain import Chain

    from armanim.scene.robots import bundled_robot

    info = bundled_robot("panda")
    chain = Chain.from_urdf_file(str(info.urdf), base_elements=urdf_path_elements(info), last_link_vector=None)
    moving = [i for i, link in enumerate(chain.links) if getattr(link, "joint_type", "fixed") != "fixed" and i > 0]
    chain.active_links_mask = np.array([i in moving for i in range(len(chain.links))])

    def solve(p, rot, q0):
        full = np.zeros(len(chain.links))
        full[moving] = q0
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return np.asarray(chain.inverse_kinematics(p, rot, orientation_mode="all", initial_position=full))[moving]

    return solve


# ----------------------------------------------------------------------------- 1. FK


def part_fk(quick: bool) -> None:
    from armanim.arm import kernel
    from armanim.arm.kinematics import forward, tool_rotation

    problem = panda_problem("pinv")
    arm = problem.arm
    (pin_parts, why) = optional(panda_pinocchio)
    if pin_parts is None:
        print(f"1. FK: skipped, pinocchio {why}")
        return
    pin, model, data, tip = pin_parts
    rng = np.random.default_rng(0)
    q = rng.uniform(problem.limits.lower, problem.limits.upper, (10_000 if not quick else 2_000, arm.n))
    for k in range(50):  # the check first: the same tool frame everywhere
        pin.forwardKinematics(model, data, q[k])
        placed = pin.updateFramePlacement(model, data, tip)
        pose, tool = kernel.forward_with_tool(arm, q[k])
        assert np.abs(pose.tip - placed.translation).max() < 1e-12 and np.abs(tool - placed.rotation).max() < 1e-12
        assert np.abs(forward(arm, q[k]).tip - placed.translation).max() < 1e-12

    def numpy_one(p):
        pose = forward(arm, p)
        return pose.tip, tool_rotation(arm, pose)

    def pin_one(p):
        pin.forwardKinematics(model, data, p)
        return pin.updateFramePlacement(model, data, tip)

    ones = {
        "armanim numpy forward": numpy_one,
        "armanim compiled kernel": lambda p: kernel.forward_with_tool(arm, p),
        "pinocchio": pin_one,
    }
    rtb, rtb_why = optional(rtb_panda)
    if rtb is not None:
        ones["rtb ETS.eval"] = rtb[0].eval
    calls = 2000 if not quick else 400
    per = {name: [] for name in ones}
    names = list(ones)
    for r in range(15 if not quick else 5):
        for name in names[r % len(names) :] + names[: r % len(names)]:
            f = ones[name]
            sample = q[:calls]
            spent, _ = timed(lambda f=f, sample=sample: [f(p) for p in sample])
            per[name].append(spent / calls)
    print("1. FK, Panda tool frame, one pose per call (rounds of", calls, "calls):")
    for name in names:
        ratio = statistics.median(a / b for a, b in zip(per[name], per["pinocchio"]))
        print(
            f"   {name:28s} median {ms(statistics.median(per[name])):>10}  / pinocchio, median of rounds {ratio:6.2f}x"
        )
    if rtb is None:
        print(f"   rtb ETS.eval                 skipped: robotics-toolbox {rtb_why}")

    batch = {
        "armanim numpy forward(Q)": numpy_one,
        "armanim compiled kernel(Q)": lambda Q: kernel.forward_with_tool(arm, Q),
        "pinocchio, a Python loop": lambda Q: [pin_one(p) for p in Q],
    }
    per = {name: [] for name in batch}
    names = list(batch)
    for r in range(7 if not quick else 3):
        for name in names[r % len(names) :] + names[: r % len(names)]:
            spent, _ = timed(batch[name], q)
            per[name].append(spent / len(q))
    print(f"   a batch of {len(q):,} poses in one call, time per pose:")
    for name in names:
        ratio = statistics.median(a / b for a, b in zip(per[name], per["pinocchio, a Python loop"]))
        print(f"   {name:28s} median {ms(statistics.median(per[name])):>10}  / pinocchio loop {ratio:6.2f}x")


# ----------------------------------------------------------------------------- 2 and 3. IK


def interleaved(solvers: dict, cases: list, judge, limit: dict) -> dict:
    """Each solver on each case in turn, in an order drawn afresh per case (seeded), so that each
    solver follows each other one as often: a solve runs slower after one that filled the caches
    with its own code and data (TRAC-IK's threads most: a fixed rotation, once pink and ikpy stop
    at their fewer targets, put the same solver after it every time). Returns (times, successes,
    answers) per solver (an answer: the angles returned, None where the solve raised)."""
    out = {name: ([], [], []) for name in solvers}
    names = list(solvers)
    order = np.random.default_rng(0)
    for k, case in enumerate(cases):
        for name in order.permutation(names):
            if k >= limit.get(name, len(cases)):
                continue
            try:
                spent, phi = timed(solvers[name], *case)
            except Exception:  # noqa: BLE001 (a solve that raises is a failure)
                spent, phi = 0.0, None
            out[name][0].append(spent)
            out[name][1].append(phi is not None and judge(np.asarray(phi, dtype=float), case))
            out[name][2].append(None if phi is None else np.asarray(phi, dtype=float))
    return out


def report(title: str, results: dict, peer: str | None) -> None:
    print(title)
    base = statistics.median(results[peer][0]) if peer in results and results[peer][0] else None
    for name, (times, oks, *_) in results.items():
        if not times:
            continue
        ratio = f"{statistics.median(times) / base:7.2f}x {peer}" if base else ""
        print(
            f"   {name:34s} {len(times):4d} targets  success {100 * np.mean(oks):5.1f} %  median {ms(statistics.median(times)):>10}"
            f"  p90 {ms(pct(times, 90)):>10}  {ratio}"
        )


def part_pose(count: int) -> None:
    from armanim.arm.kinematics import forward, tool_rotation

    problems = {m: panda_problem(m) for m in ("pinv", "dls")}
    problems |= {
        f"{m}, self-collision off": panda_problem(m, "off") for m in ("pinv", "dls")
    }  # as the peers: no self-collision
    base = problems["pinv"]
    pin_parts, why = optional(panda_pinocchio)
    if pin_parts is None:
        print(f"2. 6-D Panda IK: skipped, pinocchio (the judge) {why}")
        return
    rng = np.random.default_rng(0)
    source = rng.uniform(base.limits.lower + 0.05, base.limits.upper - 0.05, (count, base.arm.n))
    pose = forward(base.arm, source)
    cases = [(pose.tip[k], tool_rotation(base.arm, pose)[k], base.home) for k in range(count)]

    judge = pinocchio_judge(pin_parts)
    solvers, skipped = pose_solvers(problems, cases[0])
    results = interleaved(solvers, cases, judge, {name: max(10, count // 5) for name in FEWER_TARGETS})
    peer = "rtb ik_LM (C++)" if "rtb ik_LM (C++)" in solvers else "pinocchio CLIK loop"
    report(
        f"2. 6-D pose IK, Panda, {count} random reachable targets from home, 1 mm / 1 deg by pinocchio's FK:",
        results,
        peer,
    )
    from armanim.world.selfdistances import self_gaps

    touching = int((self_gaps(pose, base.capsules, base.self_pairs).least < base.self_pairs.clearance).sum())
    print(
        f"   ({touching} of the {count} targets' source poses bring two of armanim's Panda capsules within self_clearance:"
        " armanim's self-collision keeps them apart, the peers have none)"
    )
    for line in skipped:
        print(line)


def panda_pair_gaps():
    """A judge of the Panda's own pairs written here, apart from armanim's distance code: each
    enabled pair's gap (distance less both radii, metres) at a pose, the capsules placed by
    pinocchio's joint frames and measured by coal (capsule against capsule). Taken from armanim
    are only the robot's data: which joint carries each capsule, its segment in that joint's
    frame, its radius (the bundled URDF's collision capsules) and the enabled pairs with their
    ``self_clearance`` (the robot's default matrix). Returns (gaps(q) -> (P,), clearance)."""
    import coal

    from armanim.arm.capsules import capsule_ends
    from armanim.arm.kinematics import forward

    pin, model, data, _ = panda_pinocchio()
    problem = panda_problem("pinv")
    caps, pairs = problem.capsules, problem.self_pairs
    if caps.joint_segment.any():
        raise RuntimeError("a joint-to-joint capsule: not placed by this judge")
    joints = [
        model.getJointId(f"panda_joint{k + 1}") if k >= 0 else 0 for k in caps.link
    ]  # the base's (carrier -1): the universe
    shapes, axes, centres = [], [], []
    for start, end, radius in zip(caps.start, caps.end, caps.radius):
        axis = end - start
        length = float(np.linalg.norm(axis))
        z = axis / length if length > 0 else np.array([0.0, 0.0, 1.0])
        x = np.cross(z, [1.0, 0, 0] if abs(z[0]) < 0.9 else [0, 1.0, 0])
        x /= np.linalg.norm(x)
        shapes.append(coal.Capsule(float(radius), length))  # coal's capsule: its axis along its local z, centred
        axes.append(np.stack([x, np.cross(z, x), z], axis=1))
        centres.append((start + end) / 2)
    request = coal.DistanceRequest()

    def gaps(q: np.ndarray) -> np.ndarray:
        pin.forwardKinematics(model, data, q)
        placed = [data.oMi[j] for j in joints]
        tfs = [
            coal.Transform3s(m.rotation @ r, m.rotation @ c + m.translation) for m, r, c in zip(placed, axes, centres)
        ]
        out = np.empty(len(pairs.first))
        for k, (a, b) in enumerate(zip(pairs.first, pairs.second)):
            out[k] = coal.distance(shapes[a], tfs[a], shapes[b], tfs[b], request, coal.DistanceResult())
        return out

    # a check of the placement (not of the distances): the capsules' world ends as armanim places them
    rng = np.random.default_rng(7)
    for q in rng.uniform(problem.limits.lower, problem.limits.upper, (20, problem.arm.n)):
        pin.forwardKinematics(model, data, q)
        a, b = capsule_ends(caps, forward(problem.arm, q))
        for k, j in enumerate(joints):
            m = data.oMi[j]
            assert np.abs(m.rotation @ caps.start[k] + m.translation - a[k]).max() < 1e-9
            assert np.abs(m.rotation @ caps.end[k] + m.translation - b[k]).max() < 1e-9
    return gaps, float(pairs.clearance)


def part_pose_self_free(count: int) -> None:
    """6-D Panda IK on targets whose source poses keep every enabled pair of the Panda's own
    capsules at least ``self_clearance`` apart (by :func:`panda_pair_gaps`), so that armanim with
    its self-collision on (the robot's default) is not refused by design; the same targets for
    every solver. armanim's success also asks its answer to keep every pair apart (the same judge);
    the peers, which know no self-collision, are judged by the FK alone, and how many of their
    answers keep the pairs apart is printed beside."""

    parts, why = optional(panda_pinocchio)
    judge_parts, judge_why = optional(panda_pair_gaps)
    if parts is None or judge_parts is None:
        print(f"2b. 6-D Panda IK, self-free targets: skipped, {why or judge_why}")
        return
    pin, model, data, tip = parts
    gaps, clearance = judge_parts
    lo, hi = model.lowerPositionLimit, model.upperPositionLimit
    rng = np.random.default_rng(1)
    cases, drawn = [], 0
    while len(cases) < count:
        q = rng.uniform(lo + 0.05, hi - 0.05)
        drawn += 1
        if gaps(q).min() < clearance:
            continue
        pin.forwardKinematics(model, data, q)
        placed = pin.updateFramePlacement(model, data, tip)
        cases.append((placed.translation.copy(), placed.rotation.copy(), panda_problem("pinv").home))
    home_gap = gaps(cases[0][2]).min()
    assert home_gap >= clearance, "the start (home) keeps the pairs apart"

    reaches = pinocchio_judge(parts)
    solvers, skipped = pose_solvers({m: panda_problem(m) for m in ("pinv", "dls")}, cases[0])
    results = interleaved(solvers, cases, reaches, {name: max(10, count // 5) for name in FEWER_TARGETS})
    peer = "rtb ik_LM (C++)" if "rtb ik_LM (C++)" in solvers else "pinocchio CLIK loop"
    base = statistics.median(results[peer][0])
    print(
        f"2b. 6-D pose IK, Panda, {count} random reachable targets whose source poses keep every enabled pair of its"
        f" capsules >= self_clearance ({clearance * 1e3:g} mm) apart ({count} of {drawn} drawn), from home, armanim"
        " with the robot's default self-collision; reached: 1 mm / 1 deg by pinocchio's FK, inside the limits;"
        " pairs apart: every enabled pair >= self_clearance by coal (pinocchio's frames):"
    )
    for name, (times, oks, answers) in results.items():
        apart = [ok and gaps(q).min() >= clearance for ok, q in zip(oks, answers)]
        success = apart if name.startswith("armanim") else oks
        print(
            f"   {name:34s} {len(times):4d} targets  success {100 * np.mean(success):5.1f} %  median {ms(statistics.median(times)):>10}"
            f"  p90 {ms(pct(times, 90)):>10}  {statistics.median(times) / base:7.2f}x {peer}"
            f"   (reached {100 * np.mean(oks):5.1f} %, reached with the pairs apart {100 * np.mean(apart):5.1f} %)"
        )
    for line in skipped:
        print(line)


def notes_fk(q: np.ndarray) -> np.ndarray:
    """The notes' arm's tip, a numpy chain of its own (z, then y, y, y; links along z)."""
    c, s = np.cos(q[0]), np.sin(q[0])
    rot = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    p = np.array(NOTES_BASE) + rot @ np.array([0, 0, NOTES_LINKS[0]])
    for k in range(1, 4):
        ca, sa = np.cos(q[k]), np.sin(q[k])
        rot = rot @ np.array([[ca, 0.0, sa], [0.0, 1.0, 0.0], [-sa, 0.0, ca]])
        p = p + rot @ np.array([0, 0, NOTES_LINKS[k]])
    return p


def part_position(count: int) -> None:
    from armanim.arm.kinematics import Arm
    from armanim.motion.ik import solve_pose
    from armanim.motion.problem import Goal, Limits, Problem
    from armanim.scene import default_solver_settings
    from armanim.world.obstacles import Obstacles

    lower = np.array([-np.inf if d is None else -np.radians(d) for d in NOTES_LIMITS_DEG])
    hard = np.where(np.isfinite(lower), lower, -np.pi)

    def problem(method):
        return Problem(
            arm=Arm.from_names(list(NOTES_LINKS), base=NOTES_BASE),
            half_width=0.3,
            home=np.zeros(4),
            limits=Limits(lower=lower, upper=-lower, margin=float(np.radians(15.0))),
            obstacles=Obstacles.none(),
            goals=(Goal(np.zeros(3), hold=0.0),),
            solver=default_solver_settings(method=method, tolerance=POS_TOL),
            fps=30.0,
        )

    rng = np.random.default_rng(0)
    inner = np.radians(15.0)
    goals = [notes_fk(rng.uniform(hard + inner, -hard - inner)) for _ in range(count)]
    cases = [(g, np.zeros(4)) for g in goals]

    def judge(q, case):
        inside = q.shape == (4,) and np.all(q >= hard - 1e-9) and np.all(q <= -hard + 1e-9)
        return bool(inside and np.linalg.norm(notes_fk(q) - case[0]) < POS_TOL)

    solvers = {f"armanim {m}": (lambda g, q0, pr=problem(m): solve_pose(pr, g, q0, 2000).phi) for m in ("pinv", "dls")}
    skipped = []

    def rtb_notes():
        from roboticstoolbox import ET

        lo = hard
        ets = (
            ET.tx(NOTES_BASE[0])
            * ET.ty(NOTES_BASE[1])
            * ET.Rz(qlim=[-np.pi, np.pi])
            * ET.tz(NOTES_LINKS[0])
            * ET.Ry(qlim=[lo[1], -lo[1]])
            * ET.tz(NOTES_LINKS[1])
            * ET.Ry(qlim=[lo[2], -lo[2]])
            * ET.tz(NOTES_LINKS[2])
            * ET.Ry(qlim=[lo[3], -lo[3]])
            * ET.tz(NOTES_LINKS[3])
        )
        mask = np.array([1.0, 1, 1, 0, 0, 0])

        def solve(g, q0):
            t = np.eye(4)
            t[:3, 3] = g
            return np.asarray(
                ets.ik_LM(t, q0=q0, mask=mask, joint_limits=True, tol=0.5 * (0.9e-3) ** 2, ilimit=30, slimit=100).q
            )

        return solve

    def ikpy_notes():
        from ikpy.chain import Chain
        from ikpy.link import OriginLink, URDFLink

        links = [
            OriginLink(),
            URDFLink("j1", origin_translation=list(NOTES_BASE), origin_orientation=[0, 0, 0], rotation=[0, 0, 1]),
        ]
        for k in range(1, 4):
            links.append(
                URDFLink(
                    f"j{k + 1}",
                    origin_translation=[0, 0, NOTES_LINKS[k - 1]],
                    origin_orientation=[0, 0, 0],
                    rotation=[0, 1, 0],
                    bounds=(hard[k], -hard[k]),
                )
            )
        links.append(
            URDFLink(
                "tip",
                origin_translation=[0, 0, NOTES_LINKS[3]],
                origin_orientation=[0, 0, 0],
                rotation=None,
                joint_type="fixed",
            )
        )
        chain = Chain(links, active_links_mask=[False, True, True, True, True, False])
        return lambda g, q0: np.asarray(chain.inverse_kinematics(g, initial_position=np.r_[0.0, q0, 0.0]))[1:5]

    for name, make in (("rtb ik_LM (C++)", rtb_notes), ("ikpy", ikpy_notes)):
        solve, why = optional(make)
        if solve is None:
            skipped.append(f"   {name:34s} skipped: {why}")
        else:
            solvers[name] = solve
    for name in solvers:
        solvers[name](*cases[0])
    results = interleaved(solvers, cases, judge, {name: max(10, count // 5) for name in FEWER_TARGETS})
    peer = "rtb ik_LM (C++)" if "rtb ik_LM (C++)" in solvers else None
    report(
        f"3. position IK, the notes' arm, {count} targets from the straight pose, 1 mm by a numpy FK of its own:",
        results,
        peer,
    )
    for line in skipped:
        print(line)


# ----------------------------------------------------------------------------- 4. start-up


def part_startup(rounds: int) -> None:
    armanim = [sys.executable, "-m", "armanim"]
    out = Path(os.environ.get("TMPDIR", "/tmp")) / "ik_compare_runs"
    cases = {
        "python -c pass": [sys.executable, "-c", "pass"],
        "python -c 'import numpy'": [sys.executable, "-c", "import numpy"],
        STACK: [sys.executable, "-c", f"import {STACK_MODULES}"],
        "armanim --version": [*armanim, "--version"],
        "armanim run notes-arm --no-video": [
            *armanim,
            "run",
            "scenes/notes-arm.yaml",
            "--no-video",
            "-q",
            "--out",
            str(out),
        ],
    }
    times = {name: [] for name in cases}
    names = list(cases)
    for r in range(rounds + 1):
        for name in names[r % len(names) :] + names[: r % len(names)]:
            start = time.perf_counter()
            subprocess.run(cases[name], cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
            if r:  # round 0 warms the caches up
                times[name].append(time.perf_counter() - start)
    print(f"4. start-up, whole processes, {rounds} rotated rounds (after a warm-up round):")
    for name in names:
        print(f"   {name:34s} min {min(times[name]):.3f} s  median {statistics.median(times[name]):.3f} s")
    ratio = statistics.median(a / b for a, b in zip(times[names[-1]], times[STACK]))
    print(f"   a small run is {ratio:.1f}x importing the stack it runs on (median of rounds)")


# What every `armanim run` imports by design (the chosen dependencies): the floor of a small run's time.
STACK_MODULES = "numpy, scipy.linalg, pydantic, yaml, typer, rich, numba"
STACK = "python -c 'import the stack'"


PARTS = ("fk", "pose", "self-free", "position", "startup")


def main(quick: bool, parts: tuple[str, ...] = PARTS, count: int | None = None) -> None:
    """The parts named in ``parts`` (all by default); ``count``: the IK parts' targets (else 300
    and 200, 40 with ``quick``)."""
    print(
        f"python {sys.version.split()[0]}, numpy {np.__version__}, {os.cpu_count()} cores, load {os.getloadavg()[0]:.2f}"
    )
    if "fk" in parts:
        part_fk(quick)
    if "pose" in parts:
        part_pose(count or (40 if quick else 300))
    if "self-free" in parts:
        part_pose_self_free(count or (40 if quick else 300))
    if "position" in parts:
        part_position(count or (40 if quick else 200))
    if "startup" in parts:
        part_startup(3 if quick else 7)
    print(f"load at the end {os.getloadavg()[0]:.2f}")
