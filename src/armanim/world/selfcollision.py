"""The allowed-collision matrix: which pairs of the arm's own links are never checked, and why.

The rules are the MoveIt Setup Assistant's (``computeDefaultCollisions``), on armanim's capsules:

``Adjacent``
    links carried by the same joint (they never move relative to one another) or by
    consecutive joints (a joint between them: they touch at their joint);
``Default``
    links closer than the clearance at the arm's default poses (its home and, for a URDF arm
    other than a bundled robot, MoveIt's default values: every joint at 0, or at the middle of
    limits that exclude 0; a bundled robot's default is its home, as MoveIt's ``ready`` state):
    they start that near, the matrix cannot ask them apart;
``Always``
    links closer than the clearance in every one of :data:`NEVER_SAMPLES` random poses inside
    the limits (unlimited joints in [-pi, pi)), drawn from :data:`NEVER_SEED`: deterministic
    (with the default poses' rule, such a pair is ``Default`` first, as in MoveIt);
``Never``
    links never closer than the clearance in those poses.

The base link (capsules carried by :data:`~armanim.arm.capsules.BASE`) is a link like the
others: adjacent to the links the first joint carries.

Every other pair of links is checked: each of its capsule pairs keeps ``solver.self_clearance``.
A user's ``allow`` pairs are added (``User``), ``check`` pairs removed from the matrix. Pure core:
numpy only; files (bundled matrices, SRDF) are read in :mod:`armanim.scene`.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from armanim.arm.capsules import Capsules
from armanim.arm.kinematics import Arm, forward
from armanim.world.selfdistances import SelfPairs, self_gaps

NEVER_SAMPLES = 10_000
"""Random in-limit poses the ``Never`` rule tries (MoveIt's Setup Assistant default density)."""
NEVER_SEED = 20261204
"""The seed of those poses: the same arm always gets the same matrix."""
CHUNK = 1_000
"""Poses measured at once (bounds the memory of an arm of many links)."""

ADJACENT, DEFAULT, ALWAYS, NEVER, USER, SRDF = "Adjacent", "Default", "Always", "Never", "User", "SRDF"
RULES = (ADJACENT, DEFAULT, ALWAYS, NEVER)
"""MoveIt's rules, in the order they are applied."""


def link_names(capsules: Capsules) -> tuple[str, ...]:
    """The link each capsule belongs to: its URDF link, or ``linkK`` (1-based joint) for a
    link-by-link arm's joint-to-joint capsules.

    >>> from armanim.arm.capsules import joint_capsules
    >>> link_names(joint_capsules(Arm.from_names([1, 1]), 0.1))
    ('link1', 'link2')
    """
    if capsules.names:
        return tuple(capsules.names)
    return tuple(f"link{k + 1}" for k in capsules.link)


def link_pairs(capsules: Capsules) -> list[tuple[str, str]]:
    """Every pair of distinct links that carry capsules, in the capsules' order.

    >>> from armanim.arm.capsules import joint_capsules
    >>> link_pairs(joint_capsules(Arm.from_names([1, 1, 1]), 0.1))
    [('link1', 'link2'), ('link1', 'link3'), ('link2', 'link3')]
    """
    names = list(dict.fromkeys(link_names(capsules)))
    return [(a, b) for i, a in enumerate(names) for b in names[i + 1 :]]


def adjacent_pairs(capsules: Capsules) -> set[tuple[str, str]]:
    """The link pairs carried by the same joint or by consecutive joints."""
    names = link_names(capsules)
    carrier: dict[str, set[int]] = {}
    for name, link in zip(names, capsules.link.tolist()):
        carrier.setdefault(name, set()).add(link)
    return {(a, b) for a, b in link_pairs(capsules) if min(abs(i - j) for i in carrier[a] for j in carrier[b]) <= 1}


def capsule_pairs(capsules: Capsules, links: list[tuple[str, str]]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The capsule pairs (first, second, (P,) each) of the link pairs ``links`` and, for each,
    the index of its link pair in ``links``."""
    names = link_names(capsules)
    first, second, owner = [], [], []
    index = {pair: k for k, pair in enumerate(links)}
    for i in range(len(names)):
        for j in range(i + 1, len(names)):
            k = index.get((names[i], names[j]), index.get((names[j], names[i])))
            if k is not None:
                first.append(i)
                second.append(j)
                owner.append(k)
    return np.array(first, dtype=int), np.array(second, dtype=int), np.array(owner, dtype=int)


def least_link_gaps(arm: Arm, capsules: Capsules, links: list[tuple[str, str]], phis: np.ndarray) -> np.ndarray:
    """(k, L) the least gap of each link pair (over its capsule pairs) at each of the (k, n) poses."""
    first, second, owner = capsule_pairs(capsules, links)
    phis = np.atleast_2d(phis)
    out = np.full((len(phis), len(links)), np.inf)
    if not len(first):
        return out
    pairs = SelfPairs(first, second, 0.0)
    for start in range(0, len(phis), CHUNK):
        d = self_gaps(forward(arm, phis[start : start + CHUNK]), capsules, pairs).d
        block = out[start : start + CHUNK]
        for k in range(len(links)):
            mine = owner == k
            if mine.any():
                block[:, k] = d[:, mine].min(axis=1)
    return out


def default_pose(lower: np.ndarray, upper: np.ndarray) -> np.ndarray:
    """MoveIt's default joint values: 0 where the limits allow it, else the middle of the limits.

    >>> default_pose(np.radians([-90.0, -170.0]), np.radians([90.0, -10.0])).round(4).tolist()
    [0.0, -1.5708]
    """
    inside = (lower <= 0.0) & (upper >= 0.0)
    limited = np.isfinite(lower) & np.isfinite(upper)
    middle = 0.5 * (np.where(limited, lower, 0.0) + np.where(limited, upper, 0.0))  # no inf - inf for a free joint
    return np.where(inside | ~limited, 0.0, middle)


def random_poses(
    lower: np.ndarray, upper: np.ndarray, count: int = NEVER_SAMPLES, seed: int = NEVER_SEED
) -> np.ndarray:
    """(count, n) poses drawn uniformly inside the limits ([-pi, pi) for an unlimited joint).

    >>> random_poses(np.array([0.0, -np.inf]), np.array([1.0, np.inf]), 3).shape
    (3, 2)
    """
    lo = np.where(np.isfinite(lower), lower, -np.pi)
    hi = np.where(np.isfinite(upper), upper, np.pi)
    return lo + (hi - lo) * np.random.default_rng(seed).random((count, len(lo)))


def automatic_matrix(
    arm: Arm,
    capsules: Capsules,
    lower: np.ndarray,
    upper: np.ndarray,
    defaults: list[np.ndarray],
    clearance: float,
    samples: int = NEVER_SAMPLES,
    seed: int = NEVER_SEED,
    rules: tuple[str, ...] = RULES,
    decided: Sequence[tuple[str, str]] = (),
) -> dict[tuple[str, str], str]:
    """The allowed link pairs and their reasons by MoveIt's rules (see the module docstring).

    ``defaults``: the default poses (radians); ``clearance``: how near counts as touching;
    ``rules``: the rules applied (an SRDF's scene applies ``Adjacent`` and ``Always`` alone);
    ``decided``: link pairs left out of the sampling (an SRDF's, whose reasons it gives).

    >>> from armanim.arm.capsules import joint_capsules
    >>> arm = Arm.from_names([1, 1, 1, 1], axes=["z", "z", "z", "z"], direction="x")
    >>> lim = np.radians([-170.0] * 4), np.radians([170.0] * 4)
    >>> automatic_matrix(arm, joint_capsules(arm, 0.05), *lim, [np.zeros(4)], 0.01, samples=500)
    {('link1', 'link2'): 'Adjacent', ('link2', 'link3'): 'Adjacent', ('link3', 'link4'): 'Adjacent'}
    """
    links = link_pairs(capsules)
    adjacent = adjacent_pairs(capsules) if ADJACENT in rules else set()
    allowed = {pair: ADJACENT for pair in links if pair in adjacent}
    skip = {_key(*pair) for pair in decided}
    rest = [pair for pair in links if pair not in adjacent and _key(*pair) not in skip]
    if not rest or not {DEFAULT, ALWAYS, NEVER} & set(rules):
        return allowed
    if set(rules) & {DEFAULT, NEVER} == set():  # Always alone: a pair apart in one pose is out
        allowed.update(
            {
                pair: ALWAYS
                for pair in always_near(arm, capsules, rest, random_poses(lower, upper, samples, seed), clearance)
            }
        )
        return allowed
    at_default = (
        least_link_gaps(arm, capsules, rest, np.array(defaults)).min(axis=0)
        if DEFAULT in rules
        else np.full(len(rest), np.inf)
    )
    gaps = least_link_gaps(arm, capsules, rest, random_poses(lower, upper, samples, seed))
    nearest, farthest = gaps.min(axis=0), gaps.max(axis=0)
    for k, pair in enumerate(rest):
        if at_default[k] < clearance:
            allowed[pair] = DEFAULT
        elif ALWAYS in rules and farthest[k] < clearance:
            allowed[pair] = ALWAYS
        elif NEVER in rules and nearest[k] >= clearance:
            allowed[pair] = NEVER
    return allowed


def always_near(
    arm: Arm, capsules: Capsules, links: list[tuple[str, str]], poses: np.ndarray, clearance: float
) -> list[tuple[str, str]]:
    """The link pairs of ``links`` closer than ``clearance`` at every one of the (k, n) ``poses``
    (MoveIt's ``Always``), measured a few poses at a time (16, then 4 times as many, up to
    :data:`CHUNK`), each pair dropped at the first batch that has it apart: the same pairs as ``least_link_gaps(...).max(axis=0) < clearance``,
    most of the work left out (few pairs are near in every pose).

    >>> from armanim.arm.capsules import joint_capsules
    >>> arm = Arm.from_names([0.1, 0.1, 0.1])
    >>> always_near(arm, joint_capsules(arm, 0.5), [("link1", "link3")], np.zeros((3, 3)), 0.01)
    [('link1', 'link3')]
    """
    left, start, size = list(links), 0, 16
    while left and start < len(poses):
        near = least_link_gaps(arm, capsules, left, poses[start : start + size]).max(axis=0) < clearance
        left = [pair for pair, kept in zip(left, near) if kept]
        start, size = start + size, min(4 * size, CHUNK)
    return left


def enabled_pairs(
    capsules: Capsules,
    allowed: dict[tuple[str, str], str],
    clearance: float,
    mode: str,
    check: Sequence[tuple[str, str]] = (),
) -> SelfPairs:
    """The :class:`SelfPairs` of every capsule pair of distinct, moving-apart links whose link
    pair is not ``allowed`` (or is listed in ``check``), with the allowed pairs' reasons.

    Links carried by the same joint are rigid together: never checked, whatever the lists say.

    >>> from armanim.arm.capsules import joint_capsules
    >>> caps = joint_capsules(Arm.from_names([1, 1, 1]), 0.1)
    >>> pairs = enabled_pairs(caps, {("link1", "link2"): "Adjacent", ("link2", "link3"): "Adjacent"}, 0.01, "auto")
    >>> pairs.names, len(pairs.allowed)
    ((('link1', 'link3'),), 2)
    """
    forced = {_key(a, b) for a, b in check}
    kept = {_key(*pair): (pair, reason) for pair, reason in allowed.items() if _key(*pair) not in forced}
    names = link_names(capsules)
    first, second, labels = [], [], []
    for i in range(len(names)):
        for j in range(i + 1, len(names)):
            if names[i] == names[j] or capsules.link[i] == capsules.link[j] or _key(names[i], names[j]) in kept:
                continue
            first.append(i)
            second.append(j)
            labels.append((names[i], names[j]))
    listed = tuple((a, b, reason) for (a, b), reason in kept.values())
    return SelfPairs(
        np.array(first, dtype=int), np.array(second, dtype=int), float(clearance), tuple(labels), listed, mode
    )


def _key(a: str, b: str) -> tuple[str, str]:
    """An unordered pair as a key."""
    return (a, b) if a <= b else (b, a)
