"""Pick and place: the world of each goal as the arm grasps, carries and releases named objects.

A goal may grasp a named obstacle (:attr:`~armanim.motion.problem.Goal.grasp`) or release what
the tool holds (:attr:`~armanim.motion.problem.Goal.release`). The arm heads for a grasp goal with
the object still an obstacle; once that goal is reached the object is fixed to the tool frame
(:func:`~armanim.world.carried.grasp_offset`) and, until a release goal is reached, is part of the
arm: its cover (:func:`~armanim.world.carried.cover_capsules`) becomes capsules carried by the last
joint, which keep ``solver.clearance`` from every obstacle and the floor (the same capsules every
clearance, the cost, the filter, the planner and the clock measure) and ``self_clearance`` from
every capsule of a link that is not a touch link. Once the release goal is reached, the object is
an obstacle again where the tool put it (:func:`~armanim.world.carried.placed_body`).

An object may stand on a box (:func:`touching_support`): its cover then touches that box, which
it may do only while the arm heads for the grasp, along the grasp's ``retreat``, along a release's
``approach`` (:func:`approach_support`, which stops the line where the solid comes to touch its
board) and while the arm leaves the release: in those goals' worlds the cover's pairs with that
box are left out (:attr:`World.support`, :attr:`~armanim.arm.capsules.Capsules.allowed`), every
other pair kept; :func:`support_distance` measures the solid itself against it.

Each goal is solved in the :class:`~armanim.motion.problem.Problem` of its world
(:func:`world_problem`); a grasp or release goal that is missed changes nothing. Pure core: no I/O.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import cast

import numpy as np

from armanim.arm.capsules import BASE, Capsules
from armanim.arm.geometry import unit_vector
from armanim.arm.gripper import Gripper, moved_fingers, ramp
from armanim.arm.kinematics import Pose, tool_rotation
from armanim.motion.problem import Goal, Problem
from armanim.world.carried import (
    Body,
    cover_capsules,
    grasp_offset,
    obstacle_body,
    placed_body,
    tool_matrix,
    with_bodies,
    world_cover,
)
from armanim.world.selfcollision import link_names
from armanim.world.selfdistances import SelfPairs

TOUCH = "Touch"
"""The allowed-collision reason of a carried object and a link allowed to touch it (MoveIt's
``touch_links``)."""


@dataclass(frozen=True)
class Held:
    """What the tool carries.

    Attributes
    ----------
    column : int
        The object's clearance column in the scene's own obstacles.
    name : str
        Its name.
    body : Body
        The object where it was grasped.
    offset : (4, 4) array
        Its pose in the tool frame (:func:`~armanim.world.carried.grasp_offset`).
    touch : tuple of str
        The links allowed to touch it.
    support : int or None
        The obstacle it stood on where it was grasped (:func:`touching_support`), which it may
        touch along the grasp's retreat; None: it stood clear of every obstacle.
    """

    column: int
    name: str
    body: Body
    offset: np.ndarray
    touch: tuple[str, ...]
    support: int | None = None


@dataclass(frozen=True)
class World:
    """Where the named objects are, and what the tool holds, while the arm heads for one goal.

    Attributes
    ----------
    moved : dict
        Clearance column (of the scene's obstacles) -> the object's :class:`Body` where it was
        put, or None while it is carried.
    held : Held or None
    """

    moved: dict[int, Body | None] = field(default_factory=dict)
    held: Held | None = None
    near: tuple[int, tuple[str, ...]] | None = None
    """The object the hand is at (its column and touch links) while the arm heads for the goal that
    grasps it, or leaves it after a release: off the obstacles and, where it rests, a part of the
    robot's base (its cover's capsules on :data:`~armanim.arm.capsules.BASE`) that every link but
    the touch links keeps ``self_clearance`` from, so that the fingers may close round it."""
    fingers: float | None = None
    """The gripper's value while the arm moves toward this goal (metres per finger,
    :mod:`armanim.arm.gripper`); None: where ``arm.joint_values`` holds it (or no gripper)."""
    support: int | None = None
    """The obstacle (clearance column of the scene's) the object held, or at the hand, may touch
    in this goal: the one it stands on at a grasp (while the arm heads for it and along its
    retreat), the one it is put on along a release's approach (and while the arm leaves it);
    None: none. Its cover's pairs with that obstacle are left out (:attr:`~armanim.arm.capsules.Capsules.allowed`),
    every other pair kept."""
    stop: float = 1.0
    """Along a release's approach onto a support: the fraction of the line where the solid comes to
    touch it (:func:`approach_support`), where the tool stops (1: the line's end)."""

    def key(self) -> tuple[object, ...]:
        """What tells two worlds apart (for reusing one problem per world)."""
        return (
            tuple(sorted((k, None if b is None else b.matrix().tobytes()) for k, b in self.moved.items())),
            None if self.held is None else (self.held.column, self.held.offset.tobytes(), self.held.touch),
            self.near,
            self.fingers,
            self.support,
            self.stop,
        )


def default_touch_links(problem: Problem) -> tuple[str, ...]:
    """The links allowed to touch a carried object by default: every link the last joint carries
    (the wrist's last link, the hand and the fingers), in the capsules' order.

    >>> from armanim.arm.kinematics import Arm
    >>> from armanim.motion.problem import Goal, Limits
    >>> from armanim.scene.convert import default_solver_settings
    >>> from armanim.world.obstacles import Obstacles
    >>> arm = Arm.from_names([1, 1, 1])
    >>> p = Problem(arm, 0.05, np.zeros(3), Limits.unlimited(3, 0.1), Obstacles.none(), (), default_solver_settings(), 30.0)
    >>> default_touch_links(p)
    ('link3',)
    """
    names = link_names(problem.capsules)
    return tuple(dict.fromkeys(n for n, k in zip(names, problem.capsules.link.tolist()) if k == problem.arm.n - 1))


def tool_transform(problem: Problem, pose: Pose) -> np.ndarray:
    """(..., 4, 4) the world-from-tool transform of ``pose``: the tool frame's rotation and point."""
    return tool_matrix(tool_rotation(problem.arm, pose), pose.tip)


def carried_capsules(problem: Problem, held: Held) -> Capsules:
    """The arm's capsules and, after them, the carried object's cover carried by the last joint
    (named after the object).

    The tool frame is the last joint's frame R_n moved by the chain's last offset o_n and turned
    by its last fixed turn T_n: a point y of the tool frame is o_n + T_n y in the last joint's frame.
    """
    arm, caps = problem.arm, problem.capsules
    start, end, radius = cover_capsules(held.body)
    turn = np.eye(3) if arm.turns is None else arm.turns[-1]
    rotation, origin = turn @ held.offset[:3, :3], arm.offsets[-1] + turn @ held.offset[:3, 3]
    link = np.full(len(radius), arm.n - 1)
    return Capsules(
        link=np.concatenate([caps.link, link]),
        start=np.concatenate([caps.start, start @ rotation.T + origin]),
        end=np.concatenate([caps.end, end @ rotation.T + origin]),
        radius=np.concatenate([caps.radius, radius]),
        names=link_names(caps) + (held.name,) * len(radius),
        joint_segment=np.concatenate([caps.joint_segment, np.zeros(len(radius), dtype=bool)]),
    )


def resting_capsules(problem: Problem, body: Body, name: str) -> Capsules:
    """The arm's capsules and, after them, the cover of an object at rest (``body``) as a part of
    the base (:data:`~armanim.arm.capsules.BASE`: its ends in the world), named ``name``."""
    caps = problem.capsules
    start, end, radius = world_cover(body)
    return Capsules(
        link=np.concatenate([caps.link, np.full(len(radius), BASE)]),
        start=np.concatenate([caps.start, start]),
        end=np.concatenate([caps.end, end]),
        radius=np.concatenate([caps.radius, radius]),
        names=link_names(caps) + (name,) * len(radius),
        joint_segment=np.concatenate([caps.joint_segment, np.zeros(len(radius), dtype=bool)]),
    )


def carried_pairs(pairs: SelfPairs, capsules: Capsules, name: str, touch: tuple[str, ...]) -> SelfPairs:
    """``pairs`` and, after them, every pair of a capsule of the object ``name`` (the last ones of
    ``capsules``) and a capsule of a link that is not a touch link nor rigid with it (carried by
    the same joint); the touch links listed as allowed, reason :data:`TOUCH`."""
    names = link_names(capsules)
    own = [i for i, n in enumerate(names) if n == name]
    first, second, labels = list(pairs.first), list(pairs.second), list(pairs.names)
    for j in range(own[0]):
        if names[j] in touch or capsules.link[j] == capsules.link[own[0]]:
            continue
        for i in own:
            first.append(j)
            second.append(i)
            labels.append((names[j], name))
    touching = tuple((link, name, TOUCH) for link in touch)
    return SelfPairs(
        np.array(first, dtype=int),
        np.array(second, dtype=int),
        pairs.clearance,
        tuple(labels),
        pairs.allowed + touching,
        pairs.mode,
    )


def world_problem(problem: Problem, world: World) -> Problem:
    """``problem`` in ``world``: the objects where they were put, the carried one off the obstacles
    and on the arm (its capsules and pairs)."""
    if not world.moved and world.held is None and world.near is None and world.fingers is None:
        return problem
    if world.fingers is not None and problem.gripper is not None:
        problem = replace(problem, capsules=moved_fingers(problem.capsules, problem.gripper, world.fingers))
    moved = dict(world.moved)
    if world.near is not None:
        moved[world.near[0]] = None
    out = replace(problem, obstacles=with_bodies(problem.obstacles, moved))
    held = world.held
    if held is not None:
        capsules = supported(carried_capsules(problem, held), problem, world)
        return replace(
            out, capsules=capsules, self_pairs=carried_pairs(problem.self_pairs, capsules, held.name, held.touch)
        )
    if world.near is not None:
        column, touch = world.near
        name = object_name(problem, column)
        capsules = supported(
            resting_capsules(problem, world.moved.get(column) or obstacle_body(problem.obstacles, column), name),
            problem,
            world,
        )
        return replace(out, capsules=capsules, self_pairs=carried_pairs(problem.self_pairs, capsules, name, touch))
    return out


def supported(capsules: Capsules, problem: Problem, world: World) -> Capsules:
    """``capsules`` (the arm's, then an object's cover) with the cover allowed to touch ``world``'s
    support (its column among ``world``'s obstacles, :func:`world_columns`); as they are without one."""
    if world.support is None:
        return capsules
    allowed = np.array(capsules.allowed)
    allowed[len(problem.capsules) :] = world_columns(problem, world).index(world.support)
    return replace(capsules, allowed=allowed)


SUPPORT_DEPTH = 1e-9
"""Scene units: how far a solid may lie inside an obstacle and still stand on it (rounding of a
box set exactly on a board, 0.24 - 0.04 = 0.19999999999999998)."""


def touching_support(
    problem: Problem, world: World, body: Body, column: int | None, deeper: bool = False
) -> int | None:
    """The box obstacle the solid ``body`` stands on, in ``world`` (the objects where they were put;
    ``column``, the object itself, left out): of the boxes its cover comes within
    ``solver.clearance`` of, the one its solid is nearest to (:func:`~armanim.world.support.solid_box_distance`),
    if that solid touches it or is apart (at most :data:`SUPPORT_DEPTH` inside, or any depth where
    ``deeper``); None: its cover keeps its clearance from every obstacle, or it stands in one."""
    from armanim.world.carried import cover_clearances
    from armanim.world.obstacles import BOX
    from armanim.world.support import solid_box_distance

    gone = {c: None for c, b in world.moved.items() if b is None} | ({} if column is None else {column: None})
    present = World({**world.moved, **gone})
    obstacles = with_bodies(problem.obstacles, {**world.moved, **gone})
    columns = world_columns(problem, present)
    if not len(obstacles):
        return None
    near = cover_clearances(body, obstacles) < problem.solver.clearance
    best, best_d = None, np.inf
    for j in np.nonzero(near)[0]:
        if obstacles.kinds[j] != BOX:
            continue
        d = solid_box_distance(body, obstacle_body(obstacles, int(j)))
        if d < best_d:
            best, best_d = columns[j], d
    return best if best is not None and (deeper or best_d >= -SUPPORT_DEPTH) else None


def goal_world(problem: Problem, world: World, k: int, pose: Pose | None = None) -> World:
    """The world goal ``k`` is solved in, from the world the goal before left (``pose``: the arm's
    pose as the goal starts): a grasp's object is at the hand (:attr:`World.near`) while the arm
    heads for it, touching what it stands on; along the retreat of a grasp the object held may
    touch what it stood on, and along a release's approach what it is put on
    (:attr:`World.support`, :func:`approach_support`)."""
    goal = problem.goals[k]
    held = world.held
    if goal.grasp is not None and held is None:
        body = world.moved.get(goal.grasp) or obstacle_body(problem.obstacles, goal.grasp)
        return replace(
            world,
            near=(goal.grasp, touch_links(problem, goal.touch_links)),
            support=touching_support(problem, world, body, goal.grasp),
        )
    if held is None or k == 0:
        return world
    if goal.retreat and problem.goals[k - 1].grasp == held.column:
        return replace(world, support=held.support)
    if goal.release and goal.path is not None and problem.goals[k - 1].to_approach and pose is not None:
        support, stop = approach_support(problem, world, goal, pose)
        return replace(world, support=support, stop=stop)
    return world


STOP_STEPS = 60
"""Halvings that find where along a release's approach the solid comes to touch its support
(the line's length / 2^60: far below rounding)."""


def approach_support(problem: Problem, world: World, goal: Goal, pose: Pose) -> tuple[int | None, float]:
    """The obstacle the object ``world`` holds is put on along the approach line of the release
    ``goal`` (the arm at ``pose`` as it starts, the tool's orientation held as there), and the
    fraction of the line where the tool stops: the box the solid touches (:func:`touching_support`)
    where the line ends, or where the solid first comes to touch it along the line, when that lies
    at most ``solver.tolerance`` short of the end (the grasp took the object a little off the
    goal's pose: the goal is still reached); (None, 1.0) for none (the line puts the solid no
    nearer than its cover's clearance, or deeper into the box than that: the cover then keeps its
    clearance and the goal is missed)."""
    from armanim.world.support import solid_box_distance

    assert world.held is not None and goal.path is not None
    held = world.held
    tool = tool_transform(problem, pose)
    start, end = goal.path.start, goal.path.end

    def body_at(t: float) -> Body:
        at = tool.copy()
        at[:3, 3] = start + t * (end - start)
        return placed_body(at, held.offset, held.body)

    support = touching_support(problem, world, body_at(1.0), None, deeper=True)
    if support is None:
        return None, 1.0
    box = world.moved.get(support) or obstacle_body(problem.obstacles, support)
    if solid_box_distance(body_at(1.0), box) >= -SUPPORT_DEPTH:
        return support, 1.0
    low, high = 0.0, 1.0  # the distance along a translation is convex: apart at the line's start, inside at its end
    if solid_box_distance(body_at(low), box) < 0.0:
        return None, 1.0
    for _ in range(STOP_STEPS):
        middle = 0.5 * (low + high)
        low, high = (middle, high) if solid_box_distance(body_at(middle), box) >= 0.0 else (low, middle)
    if (1.0 - low) * float(np.linalg.norm(end - start)) > problem.solver.tolerance:
        return None, 1.0
    return support, low


def stopped_goal(goal: Goal, world: World) -> Goal:
    """``goal`` (a release's approach) with its line ending where ``world`` stops it (:attr:`World.stop`)."""
    if world.stop >= 1.0 or goal.path is None:
        return goal
    from armanim.motion.toolpath import ToolPath

    start, end = goal.path.start, goal.path.end
    return replace(goal, path=ToolPath.polyline(np.array([start, start + world.stop * (end - start)])))


def touch_links(problem: Problem, given: tuple[str, ...] | None) -> tuple[str, ...]:
    """A grasp's touch links: ``given``, or :func:`default_touch_links`."""
    return given if given is not None else default_touch_links(problem)


def object_name(problem: Problem, column: int) -> str:
    """The scene's name of the object in clearance column ``column``."""
    name = problem.obstacles.name(column)
    return name if name is not None else f"obstacles[{column}]"


def after_goal(problem: Problem, world: World, k: int, reached: bool, pose: Pose) -> World:
    """The world once goal ``k`` of ``problem`` ends at ``pose`` (reached or not): a reached grasp
    takes its object into the tool, a reached release puts the held object down where the tool
    is; a missed goal changes nothing.

    A grasp while the tool still holds something (its release was missed) or a release with
    nothing held (its grasp was missed) changes nothing either: validation refuses the scenes
    that would ask either of a run whose goals are all reached.
    """
    goal = problem.goals[k]
    before, world = (
        world,
        replace(world, near=None, support=None, stop=1.0),
    )  # the object at the hand, its support, its line's stop: this goal's alone
    if not reached:
        return world
    if goal.grasp is None and not goal.release:
        return replace(world, fingers=fingers_if_free(problem, before, pose, opened_before_grasp(problem, world, k)))
    tool = tool_transform(problem, pose)
    if goal.grasp is not None:
        if world.held is not None:
            return world
        column = goal.grasp
        body = world.moved.get(column) or obstacle_body(problem.obstacles, column)
        held = Held(
            column,
            object_name(problem, column),
            body,
            grasp_offset(tool, body),
            touch_links(problem, goal.touch_links),
            before.support,
        )
        fingers = (
            None if problem.gripper is None else problem.gripper.grip(body.extent(finger_direction(problem, pose)))
        )
        return World({**world.moved, column: None}, held, fingers=fingers_if_free(problem, before, pose, fingers))
    if world.held is None:
        return world
    placed = placed_body(tool, world.held.offset, world.held.body)
    fingers = None if problem.gripper is None else problem.gripper.upper
    return World(
        {**world.moved, world.held.column: placed},
        None,
        (world.held.column, world.held.touch),
        fingers_if_free(problem, before, pose, fingers),
        before.support,
    )


FINGER_STEPS = 16
"""Values along the fingers' move at which :func:`fingers_free` measures them (more than the
frames the Panda's longest move takes at 60 fps, 12)."""


def fingers_if_free(problem: Problem, world: World, pose: Pose, target: float | None) -> float | None:
    """``target``, the gripper's value after a goal that ends at ``pose`` in ``world``, or where the
    fingers are in ``world`` if moving them there would bring a capsule under its clearance
    (:func:`fingers_free`): the fingers then stay (a grasp's object still attaches)."""
    gripper = problem.gripper
    if gripper is None or target is None:
        return target
    start = gripper.rest if world.fingers is None else world.fingers
    if target == start:
        return world.fingers
    return target if fingers_free(world_problem(problem, world), pose, start, target) else world.fingers


def fingers_free(solved: Problem, pose: Pose, start: float, end: float) -> bool:
    """Whether the gripper of ``solved`` (its capsules with the fingers at ``start``) can move to
    ``end`` at ``pose`` (one pose): at :data:`FINGER_STEPS` + 1 values along the way every capsule
    keeps ``solver.clearance`` from every obstacle and every enabled pair its ``self_clearance``
    (or no less than at ``start``, where it already was under)."""
    from armanim.world.distances import min_link_clearance
    from armanim.world.selfdistances import self_gaps

    assert solved.gripper is not None
    clear, gaps = [], []
    for value in np.linspace(start, end, FINGER_STEPS + 1):
        capsules = moved_fingers(solved.capsules, solved.gripper, float(value), start)
        at = Pose(pose.points, pose.frames)  # a fresh pose: its memo keeps one set of capsules' ends
        clear.append(float(min_link_clearance(at, solved.obstacles, capsules)) if len(solved.obstacles) else np.inf)
        gaps.append(float(self_gaps(at, capsules, solved.self_pairs).d.min()) if len(solved.self_pairs) else np.inf)
    tiny = 1e-12
    return (
        min(clear) >= min(solved.solver.clearance, clear[0]) - tiny
        and min(gaps) >= min(solved.self_pairs.clearance, gaps[0]) - tiny
    )


def opened_before_grasp(problem: Problem, world: World, k: int) -> float | None:
    """The gripper's value after goal ``k`` (reached, neither a grasp nor a release): open (its
    upper limit) where the next goal grasps and the tool holds nothing, else as it was."""
    gripper = problem.gripper
    if gripper is None or world.held is not None or k + 1 >= len(problem.goals) or problem.goals[k + 1].grasp is None:
        return world.fingers
    return gripper.upper


def finger_direction(problem: Problem, pose: Pose) -> np.ndarray:
    """(3,) the unit world direction the gripper's first finger slides along at ``pose`` (one pose)."""
    assert problem.gripper is not None
    rate = problem.gripper.rate
    i = int(np.nonzero(np.any(rate != 0.0, axis=1))[0][0])
    carrier = int(problem.capsules.link[i])
    turn = np.eye(3) if carrier < 0 else pose.frames[carrier]
    return unit_vector(turn @ rate[i])


def finger_holds(goals: tuple[Goal, ...], gripper: Gripper | None) -> tuple[Goal, ...]:
    """``goals`` with the time the fingers take (closed to open at their velocity limit) added to
    the hold of every goal at whose end they may move: a grasp (they close on the object), a
    release (they open), and the goal before the first grasp where ``arm.joint_values`` leaves
    them less than open (they open)."""
    if gripper is None:
        return goals
    first = next((k for k, g in enumerate(goals) if g.grasp is not None), None)
    extra = (gripper.upper - gripper.lower) / gripper.speed
    return tuple(
        replace(g, hold=g.hold + extra)
        if g.grasp is not None or g.release or (first is not None and k == first - 1 and gripper.rest < gripper.upper)
        else g
        for k, g in enumerate(goals)
    )


def frame_fingers(problem: Problem, carry: CarryReport, goal: np.ndarray, fps: float) -> np.ndarray | None:
    """(F,) the gripper's value in each frame (metres per finger; frames' goals ``goal`` (F,) at
    ``fps``): each goal's world's, moving to the next world's over the goal's last frames (its
    hold, where the arm stands still) at the finger joint's velocity limit; None without a gripper."""
    gripper = problem.gripper
    if gripper is None:
        return None
    out = np.full(len(goal), gripper.rest)
    worlds = (*carry.worlds, carry.final)
    for k in range(len(carry.worlds)):
        mine = np.nonzero(goal == k)[0]
        start, end = (gripper.rest if w.fingers is None else w.fingers for w in worlds[k : k + 2])
        out[mine] = ramp(start, end, gripper.ramp_frames(start, end, fps), len(mine))
    return out


@dataclass(frozen=True)
class CarryReport:
    """What each goal grasped and released, and where every moved object ended.

    Attributes
    ----------
    worlds : tuple of World
        The world each goal was solved in, (goals,).
    final : World
        The world after the last goal.
    """

    worlds: tuple[World, ...]
    final: World

    def held_names(self, goal: np.ndarray) -> np.ndarray:
        """(F,) the name of the object the tool holds in each frame (its goal's world), '' for none."""
        names = np.array(["" if w.held is None else w.held.name for w in self.worlds] or [""], dtype=object)
        return cast(np.ndarray, names[goal])

    def grasped(self, k: int) -> str | None:
        """The name of the object goal ``k`` grasped (None: none)."""
        after = self.worlds[k + 1] if k + 1 < len(self.worlds) else self.final
        before = self.worlds[k].held
        return after.held.name if after.held is not None and before is None else None

    def released(self, k: int) -> str | None:
        """The name of the object goal ``k`` put down (None: none)."""
        after = self.worlds[k + 1] if k + 1 < len(self.worlds) else self.final
        before = self.worlds[k].held
        return before.name if before is not None and after.held is None else None


def needs_carrying(problem: Problem) -> bool:
    """Whether any goal grasps or releases (the run then solves each goal in its world)."""
    return any(g.grasp is not None or g.release for g in problem.goals)


def goal_problems(problem: Problem, carry: CarryReport) -> list[Problem]:
    """The problem each goal was solved in (:func:`world_problem` of its world), one object per
    distinct world (so each world's compiled layout is made once)."""
    made: dict[tuple[object, ...], Problem] = {World().key(): problem}
    for w in carry.worlds:
        if w.key() not in made:
            made[w.key()] = world_problem(problem, w)
    return [made[w.key()] for w in carry.worlds]


def carried_clearance(problem: Problem, carry: CarryReport, phi: np.ndarray, goal: np.ndarray) -> np.ndarray:
    """(F,) the least clearance of the carried object's cover to every obstacle and the floor in
    each frame (``phi`` (F, n), its goal ``goal`` (F,)); NaN where the tool holds nothing."""
    from armanim.arm.kinematics import forward
    from armanim.world.distances import min_link_clearance

    out = np.full(len(goal), np.nan)
    problems = goal_problems(problem, carry)
    for k, world in enumerate(carry.worlds):
        rows = np.nonzero(goal == k)[0]
        if world.held is None or not len(rows) or not len(problems[k].obstacles):
            continue
        caps = problems[k].capsules
        own = np.arange(len(problem.capsules), len(caps))
        part = Capsules(
            caps.link[own],
            caps.start[own],
            caps.end[own],
            caps.radius[own],
            joint_segment=caps.joint_segment[own],
            allowed=caps.allowed[own],
        )
        for start in range(0, len(rows), FRAME_CHUNK):  # each link's frame per frame: bounded memory
            some = rows[start : start + FRAME_CHUNK]
            out[some] = min_link_clearance(forward(problem.arm, phi[some]), problems[k].obstacles, part)
    return out


FRAME_CHUNK = 5_000
"""Frames a carrying run's clearances are measured for at once (:func:`carried_clearance`, and
its self pairs: :func:`armanim.motion.trajectory.with_world_self_clearance`): a grasp held an
hour at 240 fps is 864,000 frames, and every link's placement in each of them at once was
gigabytes."""


def support_distance(problem: Problem, carry: CarryReport, phi: np.ndarray, goal: np.ndarray) -> np.ndarray:
    """(F,) the signed distance of the object's solid (not its cover) to the obstacle it may touch
    in each frame (:attr:`World.support`; :func:`~armanim.world.support.solid_box_distance`):
    along a grasp's retreat and a release's approach, and while it stands on it at the hand; NaN
    in the frames of a world without one (``phi`` (F, n), goals ``goal`` (F,))."""
    from armanim.arm.kinematics import forward
    from armanim.world.support import solid_box_distance

    out = np.full(len(goal), np.nan)
    for k, world in enumerate(carry.worlds):
        mine = np.nonzero(goal == k)[0]
        if world.support is None or not len(mine):
            continue
        box = world.moved.get(world.support) or obstacle_body(problem.obstacles, world.support)
        held = world.held
        if held is None:
            assert world.near is not None
            body = world.moved.get(world.near[0]) or obstacle_body(problem.obstacles, world.near[0])
            out[mine] = solid_box_distance(body, box)
            continue
        tools = tool_transform(problem, forward(problem.arm, phi[mine]))
        out[mine] = [solid_box_distance(held.body.moved(t @ held.offset), box) for t in tools]
    return out


def has_support(carry: CarryReport) -> bool:
    """Whether an object touches what it stands on in some goal's world (:attr:`World.support`)."""
    return any(w.support is not None for w in carry.worlds)


def touch_allowed(pairs: SelfPairs, carry: CarryReport) -> SelfPairs:
    """``pairs`` with every grasp's touch links listed as allowed (reason :data:`TOUCH`), once
    each: the run's self-collision.yaml."""
    extra = []
    for world in carry.worlds:
        held = world.held
        if held is not None:
            extra += [(link, held.name, TOUCH) for link in held.touch]
    listed = tuple(dict.fromkeys(pairs.allowed + tuple(extra)))
    return replace(pairs, allowed=listed)


def final_poses(problem: Problem, carry: CarryReport) -> dict[str, Body | None]:
    """Every object a goal grasped, where it is after the last goal (in the tool for one still
    carried: None)."""
    out: dict[str, Body | None] = {}
    for world in (*carry.worlds, carry.final):
        if world.held is not None:
            out[world.held.name] = None
    for column, body in carry.final.moved.items():
        out[object_name(problem, column)] = body
    return out


def replayed_carry(problem: Problem, phi: np.ndarray, goal: np.ndarray, reached: list[bool]) -> CarryReport | None:
    """The :class:`CarryReport` of a finished run (its frames' angles ``phi`` (F, n) and goals
    ``goal`` (F,), and whether each goal was reached), each grasp and release taken again at its
    goal's last frame, where the solve took it; None for a run that grasps nothing."""
    if not needs_carrying(problem):
        return None
    from armanim.arm.kinematics import forward

    world, worlds = World(), []
    for k in range(len(problem.goals)):
        before = np.nonzero(goal < k)[0]
        world = goal_world(problem, world, k, forward(problem.arm, phi[before[-1]]) if len(before) else None)
        worlds.append(world)
        mine = np.nonzero(goal == k)[0]
        if len(mine):
            world = after_goal(problem, world, k, reached[k], forward(problem.arm, phi[mine[-1]]))
        else:
            world = replace(world, near=None)
    return CarryReport(tuple(worlds), world)


def moving_columns(carry: CarryReport) -> list[int]:
    """The clearance columns of the objects some goal takes, in order."""
    columns = {w.held.column for w in (*carry.worlds, carry.final) if w.held is not None}
    return sorted(columns)


def frame_bodies(problem: Problem, carry: CarryReport, phi: np.ndarray, goal: np.ndarray) -> list[list[Body]]:
    """Every frame's (F) moving objects (:func:`moving_columns`, in order) where they are: in the
    tool while held, where they were put, else where the scene puts them."""
    from armanim.arm.kinematics import forward

    columns = moving_columns(carry)
    tools = tool_transform(problem, forward(problem.arm, phi)) if len(phi) else np.zeros((0, 4, 4))
    out = []
    for f in range(len(phi)):
        world = carry.worlds[int(goal[f])]
        bodies = []
        for column in columns:
            held = world.held
            if held is not None and held.column == column:
                bodies.append(held.body.moved(tools[f] @ held.offset))
            else:
                bodies.append(world.moved.get(column) or obstacle_body(problem.obstacles, column))
        out.append(bodies)
    return out


def frame_worlds(
    problem: Problem, carry: CarryReport, goal: np.ndarray, fps: float
) -> list[tuple[Problem, np.ndarray]]:
    """The frames (goals ``goal`` (F,) at ``fps``) grouped by the problem each is measured in:
    its goal's world (:func:`goal_problems`) with the fingers where they are in that frame
    (:func:`frame_fingers`); (problem, (F,) bool) per group, every frame in one."""
    problems = goal_problems(problem, carry)
    fingers = frame_fingers(problem, carry, goal, fps)
    out = []
    for solved in {id(p): p for p in problems}.values():
        ks = [k for k, p in enumerate(problems) if p is solved]
        mine = np.isin(goal, ks)
        if not mine.any():
            continue
        if fingers is None or problem.gripper is None:
            out.append((solved, mine))
            continue
        at = carry.worlds[ks[0]].fingers  # one world, one finger value while the arm moves
        at = problem.gripper.rest if at is None else at
        for value in np.unique(fingers[mine]):
            capsules = moved_fingers(solved.capsules, problem.gripper, float(value), at)
            out.append(
                (
                    solved if capsules is solved.capsules else replace(solved, capsules=capsules),
                    mine & (fingers == value),
                )
            )
    return out


def world_clearance(
    problem: Problem, carry: CarryReport | None, pose: Pose, goal: np.ndarray, fps: float
) -> np.ndarray:
    """(F,) each frame's least capsule clearance, measured in its goal's world with the fingers
    where they are (:func:`frame_worlds`; ``carry`` None: ``problem`` for every frame)."""
    from armanim.world.distances import min_link_clearance

    if carry is None:
        return min_link_clearance(pose, problem.obstacles, problem.capsules)
    out = np.full(len(goal), np.inf)
    for solved, mine in frame_worlds(problem, carry, goal, fps):
        out[mine] = min_link_clearance(Pose(pose.points[mine], pose.frames[mine]), solved.obstacles, solved.capsules)
    return out


def world_columns(problem: Problem, world: World) -> list[int]:
    """The scene's clearance column of each of ``world``'s obstacle columns (:func:`world_problem`
    leaves out the objects carried or at the hand, and keeps the others in order, the floor last).

    >>> from armanim.world.obstacles import Obstacles
    >>> from types import SimpleNamespace
    >>> p = SimpleNamespace(obstacles=Obstacles(np.zeros((3, 3)), np.ones(3), np.ones(3)))
    >>> world_columns(p, World(moved={1: None}))
    [0, 2]
    """
    gone = {c for c, body in world.moved.items() if body is None} | (
        {world.near[0]} if world.near is not None else set()
    )
    return [c for c in range(len(problem.obstacles.kinds)) if c not in gone]
