"""The planner's collision checks, compiled (numba): poses' margins and a motion's certificate.

RRT-Connect asks thousands of poses and motions whether they are free. In numpy each pose costs
some 400 microseconds of calls (:func:`~armanim.motion.solvers.barrier.split_clearances`); here
one pose is its kinematics (:mod:`armanim.arm.kernel`), its capsules' clearances to every obstacle
and the floor (:func:`armanim.motion.solvers.compiled_frame._clearances`, in the scene's order)
and its enabled pairs' gaps (:func:`armanim.world.compiled.capsule_pair_gaps`) in one call, and a
whole motion check (:func:`armanim.motion.planning.path.motion_is_free`: the coarse samples, then
the halving, level by level, by the same lever-arm bounds) is one call too.

The numbers are the numpy path's to rounding (other summation orders); the numpy functions stay
the reference, and the tests hold the two to each other. Pure core: numpy and numba only.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from armanim.arm.kernel import _capsule_ends_one, _forward_one, compiled, packed_chain
from armanim.motion.planning.path import coarse_spacing
from armanim.motion.problem import Problem
from armanim.motion.solvers.barrier import limit_buffer, self_shift
from armanim.motion.solvers.compiled_frame import _clearances, _world
from armanim.world.compiled import capsule_pair_gaps

_JIT = {"nogil": True}


@compiled(**_JIT)
def _margins(rows: np.ndarray, root: np.ndarray, caps: np.ndarray, link: np.ndarray, part_radius: np.ndarray,
             world: tuple[np.ndarray, ...], m: int, pairs: tuple[np.ndarray, np.ndarray, np.ndarray], shift: float,
             phi: np.ndarray, clear: np.ndarray, own: np.ndarray) -> None:
    """For poses ``phi`` (k, n): the least clearance of any capsule to any of the ``m`` obstacle
    columns (the floor's among them) into ``clear`` (k,) (+inf without any), and every enabled
    pair's gap plus ``shift`` into ``own`` (k, P)."""
    k, n = phi.shape
    c = link.shape[0]
    first, second, pair_radii = pairs
    count = first.shape[0]
    points = np.empty((n + 1, 3))
    frames = np.empty((n, 3, 3))
    axes = np.empty((n, 3))
    tool = np.empty((3, 3))
    a = np.empty((c, 3))
    b = np.empty((c, 3))
    d = np.empty((c + 1, m))
    t = np.empty((c + 1, m))
    normal = np.empty((c + 1, m, 3))
    gap_t = np.empty(count)
    gap_s = np.empty(count)
    gap = np.empty(count)
    gap_normal = np.empty((count, 3))
    joint_segment = caps[:, 7] > 0.5
    for i in range(k):
        _forward_one(rows, root, phi[i], points, frames, axes, tool)
        _capsule_ends_one(points, frames, link, caps[:, 0:3], caps[:, 3:6], joint_segment, a, b)
        least = np.inf
        if m:
            _clearances(points, a, b, part_radius, world, d, t, normal)
            for part in range(c):
                for j in range(m):
                    if d[part, j] < least or d[part, j] != d[part, j]:
                        least = d[part, j]
        clear[i] = least
        if count:
            capsule_pair_gaps(a, b, first, second, pair_radii, gap_t, gap_s, gap, gap_normal)
            for p in range(count):
                own[i, p] = gap[p] + shift


@compiled(**_JIT)
def _least(clear: np.ndarray, own: np.ndarray) -> np.ndarray:
    """(k,) the least of each pose's obstacle clearance and shifted pair gaps."""
    out = clear.copy()
    for i in range(own.shape[0]):
        for p in range(own.shape[1]):
            if own[i, p] < out[i] or own[i, p] != own[i, p]:
                out[i] = own[i, p]
    return out


@compiled(**_JIT)
def _inside(phi: np.ndarray, lower: np.ndarray, upper: np.ndarray, buffer: float) -> bool:
    """Whether every joint of the pose is within [lower + buffer, upper - buffer] (unlimited: +-inf)."""
    for j in range(phi.shape[0]):
        if not (phi[j] >= lower[j] + buffer and phi[j] <= upper[j] - buffer):
            return False
    return True


@compiled(**_JIT)
def _motion_free(rows: np.ndarray, root: np.ndarray, caps: np.ndarray, link: np.ndarray, part_radius: np.ndarray,
                 world: tuple[np.ndarray, ...], m: int, pairs: tuple[np.ndarray, np.ndarray, np.ndarray], shift: float,
                 limits: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray], settings: np.ndarray,
                 a: np.ndarray, b: np.ndarray, floor: float) -> tuple[bool, int]:
    """:func:`armanim.motion.planning.path.motion_is_free` of the segment a-b, compiled.

    ``limits``: (lower, upper, levers (n,), pair levers (n, P)); ``settings``: (d_safe, the coarse
    samples' spacing, certify_to, max_halvings, max_samples, buffer). Returns (free, poses checked)."""
    lower, upper, levers, pair_levers = limits
    d_safe, spacing, certify_to = settings[0], settings[1], settings[2]
    max_halvings, max_samples, buffer = int(settings[3]), settings[4], settings[5]
    n = a.shape[0]
    count_pairs = pairs[0].shape[0]
    travel = 0.0
    for j in range(n):
        travel += abs(b[j] - a[j]) * levers[j]
    count = travel / spacing
    if not count <= max_samples:
        return False, 0
    samples = max(int(math.ceil(count)) + 1, 2)
    u = np.linspace(0.0, 1.0, samples)
    poses = np.empty((samples, n))
    for i in range(samples):
        for j in range(n):
            poses[i, j] = a[j] + u[i] * (b[j] - a[j])
    clear = np.empty(samples)
    own = np.empty((samples, count_pairs))
    _margins(rows, root, caps, link, part_radius, world, m, pairs, shift, poses, clear, own)
    checks = samples
    least = _least(clear, own)
    for i in range(samples):
        if not least[i] >= floor:
            return False, checks
    if not (_inside(poses[0], lower, upper, buffer) and _inside(poses[samples - 1], lower, upper, buffer)):
        return False, checks
    lo, hi = poses[:-1].copy(), poses[1:].copy()
    c_lo, c_hi = clear[:-1].copy(), clear[1:].copy()
    o_lo, o_hi = own[:-1].copy(), own[1:].copy()
    for _ in range(max_halvings):
        pieces = lo.shape[0]
        if pieces == 0:
            return True, checks
        doubtful = np.zeros(pieces, dtype=np.bool_)
        for i in range(pieces):
            travel = 0.0
            for j in range(n):
                travel += abs(hi[i, j] - lo[i, j]) * levers[j]
            if not travel > certify_to * d_safe:
                continue
            doubt = c_lo[i] + c_hi[i] < travel + 2 * floor
            for p in range(count_pairs):
                reach = 0.0
                for j in range(n):
                    reach += abs(hi[i, j] - lo[i, j]) * pair_levers[j, p]
                if o_lo[i, p] + o_hi[i, p] < reach + 2 * floor:
                    doubt = True
            doubtful[i] = doubt
        kept = np.nonzero(doubtful)[0]
        left = kept.shape[0]
        if left == 0:
            return True, checks
        mid = np.empty((left, n))
        for r in range(left):
            for j in range(n):
                mid[r, j] = 0.5 * (lo[kept[r], j] + hi[kept[r], j])
        c_mid = np.empty(left)
        o_mid = np.empty((left, count_pairs))
        _margins(rows, root, caps, link, part_radius, world, m, pairs, shift, mid, c_mid, o_mid)
        checks += left
        least = _least(c_mid, o_mid)
        for r in range(left):
            if not least[r] >= floor:
                return False, checks
        new_lo = np.empty((2 * left, n))
        new_hi = np.empty((2 * left, n))
        new_c_lo = np.empty(2 * left)
        new_c_hi = np.empty(2 * left)
        new_o_lo = np.empty((2 * left, count_pairs))
        new_o_hi = np.empty((2 * left, count_pairs))
        for r in range(left):
            i = kept[r]
            new_lo[r], new_hi[r], new_lo[left + r], new_hi[left + r] = lo[i], mid[r], mid[r], hi[i]
            new_c_lo[r], new_c_hi[r], new_c_lo[left + r], new_c_hi[left + r] = c_lo[i], c_mid[r], c_mid[r], c_hi[i]
            new_o_lo[r], new_o_hi[r], new_o_lo[left + r], new_o_hi[left + r] = o_lo[i], o_mid[r], o_mid[r], o_hi[i]
        lo, hi, c_lo, c_hi, o_lo, o_hi = new_lo, new_hi, new_c_lo, new_c_hi, new_o_lo, new_o_hi
        if 2 * left > max_samples:
            return False, checks
    return lo.shape[0] == 0, checks


@dataclass(frozen=True)
class CompiledCheck:
    """One problem's arrays as the compiled checks read them, packed once per plan.

    ``closed``: a motion's ends may rest on the limits (a joint goal's path), else they keep the
    filter's buffer inside them, as :func:`~armanim.motion.solvers.barrier.within_limits`.
    """

    chain: tuple[np.ndarray, np.ndarray]
    body: tuple[np.ndarray, np.ndarray, np.ndarray]
    world: tuple[np.ndarray, ...]
    columns: int
    pairs: tuple[np.ndarray, np.ndarray, np.ndarray]
    shift: float
    limits: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]
    settings: np.ndarray

    @classmethod
    def of(cls, problem: Problem, closed: bool = False) -> CompiledCheck:
        caps, pairs, opts = problem.capsules, problem.self_pairs, problem.tunables.planner
        packed = np.concatenate([caps.start, caps.end, caps.radius[:, None], caps.joint_segment[:, None].astype(float)], axis=1)
        n = problem.arm.n
        return cls(
            chain=packed_chain(problem.arm),
            body=(np.ascontiguousarray(packed), np.ascontiguousarray(caps.link, dtype=np.int64),
                  np.ascontiguousarray(caps.part_radius, dtype=float)),
            world=_world(problem),
            columns=len(problem.obstacles.kinds),
            pairs=(np.ascontiguousarray(pairs.first, dtype=np.int64), np.ascontiguousarray(pairs.second, dtype=np.int64),
                   np.ascontiguousarray(pairs.radii(caps), dtype=float)),
            shift=self_shift(problem) if len(pairs) else 0.0,
            limits=(np.ascontiguousarray(problem.limits.lower, dtype=float), np.ascontiguousarray(problem.limits.upper, dtype=float),
                    np.ascontiguousarray(problem.lever_arms, dtype=float),
                    np.ascontiguousarray(problem.pair_lever_rows.reshape(len(pairs), n).T, dtype=float)),
            settings=np.array([problem.solver.clearance, coarse_spacing(problem), opts.certify_to, opts.max_halvings, opts.max_samples,
                               0.0 if closed else limit_buffer(problem)]),
        )

    def margins(self, phi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(k,) the least obstacle clearance and (k, P) the shifted pair gaps of poses ``phi`` (k, n):
        :func:`~armanim.motion.solvers.barrier.split_clearances`, compiled."""
        phi = np.ascontiguousarray(np.atleast_2d(phi), dtype=float)
        clear = np.empty(len(phi))
        own = np.empty((len(phi), len(self.pairs[0])))
        _margins(*self.chain, *self.body, self.world, self.columns, self.pairs, self.shift, phi, clear, own)
        return clear, own

    def pose_clearance(self, phi: np.ndarray) -> float:
        """One pose's :func:`~armanim.motion.solvers.barrier.pose_clearance` (n,), compiled."""
        clear, own = self.margins(phi)
        return float(min(clear[0], own.min())) if own.size else float(clear[0])

    def pose_free(self, phi: np.ndarray, floor: float) -> bool:
        """Whether the pose (n,) is within the limits (by the buffer, unless closed) and keeps ``floor``."""
        lower, upper = self.limits[0], self.limits[1]
        return bool(_inside(phi, lower, upper, float(self.settings[5])) and self.pose_clearance(phi) >= floor)

    def motion_free(self, a: np.ndarray, b: np.ndarray, floor: float) -> tuple[bool, int]:
        """:func:`~armanim.motion.planning.path.motion_is_free` of the segment a-b, compiled."""
        free, checks = _motion_free(*self.chain, *self.body, self.world, self.columns, self.pairs, self.shift, self.limits, self.settings,
                                    np.ascontiguousarray(a, dtype=float), np.ascontiguousarray(b, dtype=float), float(floor))
        return bool(free), int(checks)


__all__ = ["CompiledCheck"]
