"""Checks of a scene that span several fields, each reported with its field path.

Run after the models validated, so every value has its type; every problem is
collected, none stops the others.
"""

from __future__ import annotations

import math
import re
from dataclasses import replace

import numpy as np

from armanim.arm.capsules import tip_radius
from armanim.arm.kinematics import forward
from armanim.errors import Diagnostic
from armanim.motion.carry import World, touching_support
from armanim.motion.paths.following import most_following_frames, path_spacing
from armanim.motion.problem import frames_in
from armanim.motion.tunables import DEFAULTS
from armanim.output.numbers import apart
from armanim.scene.convert import (
    orientation_rotation,
    retreat_direction,
    scene_goal,
    scene_obstacles,
    scene_to_problem,
    tool_path,
)
from armanim.scene.limits import RATE_FIELDS, joint_goal_limit_problems, limit_problems, rate_problems
from armanim.scene.models import LIMITS, SceneModel
from armanim.world.carried import cover_margin, obstacle_body, resting_clearances, with_bodies
from armanim.world.distances import clearances, point_clearances
from armanim.world.obstacles import FLOOR
from armanim.world.selfdistances import self_gaps


def scene_problems(scene: SceneModel, unknown: frozenset[str] | set[str] = frozenset()) -> list[tuple[str, str]]:
    """Every cross-field problem of a validated scene, as (field path, message) pairs, in one pass.

    Parameters
    ----------
    scene : SceneModel
    unknown : set of str
        Field paths whose values are not the file's: left out after a field error (``solver.clearance``,
        ``arm.home``, ``goals[2].speed``), or stand-ins (``arm``: an arm that could not be read). A
        check that reads one is skipped, so that a default never makes a problem up; the others run.

    A problem that makes a value unusable (a joint count, a coordinate beyond the limits) keeps
    that value out of the collision checks: a goal or obstacle is then left out of them, an arm
    field leaves only the goals' own points to check, and the rest is still checked.
    """

    def known(*fields: str) -> bool:
        return not any(_overlaps(u, f) for u in unknown for f in fields)

    arm_known = "arm" not in unknown  # (a stand-in arm; a field of it left out is a default)
    counts = list(_count_problems(scene)) if arm_known else []
    rates = list(rate_problems(scene.arm)) if arm_known else []
    magnitudes = list(_magnitude_problems(scene))
    budget = (
        list(_budget_problems(scene))
        if known("goals", "render.fps", "solver.max_frames_per_goal", "solver.tolerance", "solver.path_tolerance")
        else []
    )
    slow = (
        list(_slow_rate_problems(scene))
        if arm_known
        and not rates
        and all(path != "arm.axes" for path, _ in counts)
        and known("render.fps", "solver.max_joint_step", *(f"arm.{f}" for f in RATE_FIELDS))
        else []
    )
    arm = list(limit_problems(scene.arm)) if known("arm.home", "arm.limits", "arm.limit_margin") else []
    arm += list(joint_goal_limit_problems(scene)) if known("arm.limits") else []
    arm += list(_bounds_problems(scene)) if known("render.bounds") else []
    carrying = list(_carry_problems(scene)) if arm_known and known("goals", "obstacles") else []
    problems = (
        counts
        + rates
        + arm
        + magnitudes
        + budget
        + slow
        + list(_pen_problems(scene))
        + list(_name_problems(scene))
        + carrying
    )
    problems += _collision_checks(scene, set(unknown) | {path for path, _ in counts + rates + magnitudes + carrying})
    return [(path, message) for path, message in problems if known(path)]


def _overlaps(a: str, b: str) -> bool:
    """One field path holds the other (or they are one).

    >>> _overlaps("arm", "arm.home[2]"), _overlaps("goals[1].speed", "goals"), _overlaps("goals[1]", "goals[10]")
    (True, True, False)
    """
    short, long = sorted((a, b), key=len)
    return long == short or long.startswith((short + ".", short + "["))


INDEXED = re.compile(r"\b(goals|obstacles)\[(\d+)\]")


def _collision_checks(scene: SceneModel, unusable: set[str]) -> list[tuple[str, str]]:
    """The clearance problems of the home pose, the goals and the joint goals' poses, with every
    value in ``unusable`` left out: goals and obstacles dropped (the rest keep their indices in
    the messages), the floor dropped, the default home taken and its checks skipped; an unusable
    arm or clearance leaves only the goal points inside an obstacle or below the floor."""
    n = scene.arm.joint_count if "arm" not in unusable else -1
    goals = [
        k
        for k, goal in enumerate(scene.goals)
        if not any(_overlaps(u, f"goals[{k}]") for u in unusable) and (goal.joints is None or len(goal.joints) == n)
    ]
    obstacles = [k for k in range(len(scene.obstacles)) if not any(_overlaps(u, f"obstacles[{k}]") for u in unusable)]
    arm_usable = not any(_overlaps(u, "arm") and not _overlaps(u, "arm.home") for u in unusable)
    home_usable = not any(_overlaps(u, "arm.home") for u in unusable) and (
        scene.arm.home is None or len(scene.arm.home) == n
    )
    clearance_known = not any(_overlaps(u, f) for u in unusable for f in ("solver.clearance", "solver.self_clearance"))
    floor = scene.floor if not any(_overlaps(u, "floor") for u in unusable) else None
    arm = scene.arm if home_usable else scene.arm.model_copy(update={"home": None})
    reduced = scene.model_copy(
        update={
            "goals": [scene.goals[k] for k in goals],
            "obstacles": [scene.obstacles[k] for k in obstacles],
            "floor": floor,
            "arm": arm,
        }
    )
    problems: list[tuple[str, str]] = []
    if arm_usable and clearance_known:
        problem = scene_to_problem(reduced, retreats=False)  # one goal per scene goal: the messages name the scene's
        tip_size = "the last link's radius" if scene.arm.is_urdf else "arm.width / 2"
        problems += list(_grasp_problems(reduced, problem))
        if home_usable:
            problems += list(_home_collision_problems(problem))
            problems += list(_self_collision_problems(problem, "arm.home" if scene.arm.home is not None else "arm"))
        problems += list(
            _goal_point_problems(
                problem.obstacles,
                problem.goals,
                tip_radius(problem.arm, problem.capsules) + problem.solver.clearance,
                tip_size,
            )
        )
        for k, goal in enumerate(problem.goals):
            if goal.joints is not None:
                problems += list(
                    _pose_collision_problems(problem, goal.joints, f"goals[{k}]", "the joint goal's pose", "the goal")
                )
                problems += list(
                    _self_collision_problems(problem, f"goals[{k}]", goal.joints, "the joint goal's pose", "the goal")
                )
    else:  # the goals' own points need no arm
        points = [
            scene_goal(g) if g.joints is None and g.grasp is None else None for g in reduced.goals
        ]  # each at its index
        problems += list(_goal_point_problems(scene_obstacles(reduced), tuple(points), None, ""))
    indices = {"goals": goals, "obstacles": obstacles}

    def original(match: re.Match) -> str:
        kept = indices[match.group(1)]
        k = int(match.group(2))
        return f"{match.group(1)}[{kept[k]}]" if k < len(kept) else match.group(0)

    return [(INDEXED.sub(original, path), INDEXED.sub(original, message)) for path, message in problems]


def _carry_problems(scene: SceneModel):
    """Grasps and releases that cannot be carried out, in the goals' order: a grasp of a name no
    obstacle has, of an object while the tool holds one, a release with nothing held, both on one
    goal, on a path goal, touch links without a grasp or naming no link, and blending in a scene
    that carries (each goal's world is its own: it starts and ends at rest)."""
    names = [o.name for o in scene.obstacles]
    links = _link_names(scene)
    held: tuple[str, int] | None = None
    for k, goal in enumerate(scene.goals):
        if goal.grasp is not None and goal.release:
            yield (
                f"goals[{k}].release",
                "is on a goal that grasps (expected grasp or release: true on a goal, not both)",
            )
            continue
        if (goal.grasp is not None or goal.release) and goal.path is not None:
            field = "grasp" if goal.grasp is not None else "release"
            yield (
                f"goals[{k}].{field}",
                "is on a path goal (expected a point, pose or joint goal: give the path its own goal after this one)",
            )
        if (goal.grasp is not None or goal.release) and goal.blend is not None:
            yield f"goals[{k}].blend", "is on a goal that grasps or releases (the tool stops there: leave blend out)"
        for name, line, end, axis, instead in (
            ("approach", goal.approach, "ends at", "[0, 0, -1]", ""),
            (
                "retreat",
                goal.retreat,
                "starts at",
                "[0, 0, 1]",
                "; give the path a straight piece of its own at its end instead",
            ),
        ):
            if line is None:
                continue
            if goal.path is not None:
                yield (
                    f"goals[{k}].{name}",
                    f"is on a path goal (expected a point or pose goal: the line {end} its position{instead})",
                )
            elif goal.joints is not None:
                yield (
                    f"goals[{k}].{name}",
                    f"is on a joint goal (expected a point or pose goal: the line {end} its position)",
                )
            elif line.axis == "tool" and goal.orientation is None and goal.tool_axis is None:
                yield (
                    f"goals[{k}].{name}.axis",
                    (
                        "is tool on a goal without orientation or tool_axis (the tool's z is unknown there: "
                        f"give the goal an orientation, or a world direction such as axis: {axis})"
                    ),
                )
        if goal.touch_links is not None:
            if goal.grasp is None:
                yield f"goals[{k}].touch_links", "is on a goal that grasps nothing (expected it beside grasp: NAME)"
            for j, link in enumerate(goal.touch_links):
                if links is not None and link not in links:
                    yield (
                        f"goals[{k}].touch_links[{j}]",
                        (f"{link!r} names no link of the arm (expected one of: {', '.join(repr(n) for n in links)})"),
                    )
        if goal.grasp is not None:
            if goal.grasp not in names:
                known = [repr(n) for n in names if n is not None]
                yield (
                    f"goals[{k}].grasp",
                    (
                        f"{goal.grasp!r} names no obstacle (expected the name of one: "
                        f"{', '.join(known) if known else 'no obstacle has a name; add name: to the one to take'})"
                    ),
                )
            elif held is not None:
                yield (
                    f"goals[{k}].grasp",
                    (
                        f"takes {goal.grasp!r} while the tool still holds {held[0]!r} (grasped at goals[{held[1]}]: "
                        "put it down first with release: true on a goal between)"
                    ),
                )
            else:
                held = (goal.grasp, k)
        elif goal.release:
            if held is None:
                yield (
                    f"goals[{k}].release",
                    (
                        "puts down nothing: the tool holds nothing here (expected grasp: NAME on an earlier "
                        "goal, or leave release out)"
                    ),
                )
            held = None
    carries = any(g.grasp is not None or g.release for g in scene.goals)
    if carries and scene.solver.blend is not None:
        yield (
            "solver.blend",
            "is set in a scene that grasps or releases (each goal of such a scene starts and ends at rest: leave it out)",
        )


def _link_names(scene: SceneModel) -> list[str] | None:
    """The names a scene's ``touch_links`` may use: the URDF arm's links with capsules, or
    ``link1`` ... for an arm of links."""
    if not scene.arm.is_urdf:
        return [f"link{k + 1}" for k in range(len(scene.arm.links or []))]
    try:
        from armanim.scene.convert import scene_arm

        _, capsules = scene_arm(scene.arm, [])
    except Exception:  # noqa: BLE001 (an arm the other checks report)
        return None
    return list(dict.fromkeys(capsules.names)) if capsules is not None else None


def gripper_opening(scene: SceneModel) -> float | None:
    """The widest a URDF arm's gripper opens: the sum of the upper limits of its prismatic joints
    held off the chain (the Panda's two fingers: 0.08 m); None without such joints."""
    if not scene.arm.is_urdf:
        return None
    uppers = [j.limits[1] for j in scene.arm.urdf_arm.held if j.kind == "prismatic" and j.limits is not None]
    return float(sum(uppers)) if uppers else None


def finger_axis(problem, tool: np.ndarray) -> np.ndarray | None:
    """(3,) the unit world direction the gripper's fingers close along when the tool frame's world
    rotation is ``tool`` (3, 3); None without a gripper, or with fingers not on the last joint."""
    gripper = problem.gripper
    if gripper is None:
        return None
    i = int(np.nonzero(np.any(gripper.rate != 0.0, axis=1))[0][0])
    if int(problem.capsules.link[i]) != problem.arm.n - 1:
        return None
    turn = np.eye(3) if problem.arm.turns is None else problem.arm.turns[-1]
    along = tool @ turn.T @ gripper.rate[i]  # the last joint's frame is the tool's turned by T_n
    return along / np.linalg.norm(along)


def _grasp_problems(scene: SceneModel, problem):
    """Each grasp's object as the tool will take it: wider than the gripper opens, out of the
    tool's reach at the grasp goal (its tool point must lie in the object or within
    ``solver.tolerance`` of it), or resting closer than ``solver.clearance`` to another obstacle or
    the floor as the arm will carry it (its cover: :func:`~armanim.world.carried.cover_capsules`)."""
    opening = gripper_opening(scene)
    d_safe = problem.solver.clearance
    for k, goal in enumerate(problem.goals):
        if goal.grasp is None:
            continue
        body = obstacle_body(problem.obstacles, goal.grasp)
        name = problem.obstacles.name(goal.grasp)
        if opening is not None and body.width() > opening:
            yield (
                f"goals[{k}].grasp",
                (
                    f"{name!r} is {body.width():.3g} across at its narrowest, wider than the gripper opens "
                    f"({opening:.3g}: its finger joints' limits; expected a smaller object)"
                ),
            )
        elif opening is not None and goal.orientation is not None and goal.orientation.rotation is not None:
            across = finger_axis(problem, goal.orientation.rotation)
            if across is not None and body.extent(across) > opening + 1e-9:
                yield (
                    f"goals[{k}].grasp",
                    (
                        f"{name!r} is {body.extent(across):.3g} across the fingers at this goal's orientation, wider "
                        f"than the gripper opens ({opening:.3g}: its finger joints' limits; expected the goal turned "
                        f"about the tool's z so that the fingers close on its {body.width():.3g} side)"
                    ),
                )
        at = goal.path.end if goal.path is not None else goal.position  # an approach's line ends at the goal
        gap = point_clearances(
            at[None],
            with_bodies(
                problem.obstacles,
                {
                    c: None
                    for c in range(len(problem.obstacles.kinds))
                    if c != goal.grasp and problem.obstacles.kinds[c] != FLOOR
                },
            ),
        )
        reach = float(gap[0, 0])
        if reach > problem.solver.tolerance:
            yield (
                f"goals[{k}].grasp",
                (
                    f"{name!r} is {reach:.3g} from the goal's tool point (expected the tool point in the object or "
                    f"within solver.tolerance = {problem.solver.tolerance:g} of it: move the goal onto the object)"
                ),
            )
        rest = resting_clearances(problem.obstacles, goal.grasp)
        support = touching_support(problem, World(), body, goal.grasp)
        if support is not None and scene.goals[k].retreat is not None:
            yield from _support_problems(scene, problem, k, body, support)
            rest[support] = np.inf  # it may touch what it stands on along its retreat
        for column in (int(c) for c in np.nonzero(rest < d_safe)[0]):
            where = (
                "the floor" if problem.obstacles.kinds[column] == FLOOR else _obstacle_words(problem.obstacles, column)
            )
            standing = (
                (
                    f"; or, as it stands on it, give goals[{k}] a retreat: the straight line along which it may leave it "
                    "touching"
                )
                if column == support
                else ""
            )
            yield (
                f"obstacles[{goal.grasp}]",
                (
                    f"{name!r} rests {rest[column]:.3g} from {where} as the arm will carry it (its cover of capsules, which lies up to "
                    f"{cover_margin(body):.3g} beyond it; expected at least solver.clearance = {d_safe:g}, so that it keeps its clearance "
                    f"from the grasp on: move it {d_safe - rest[column]:.3g} farther, or lower solver.clearance{standing})"
                ),
            )


def _support_problems(scene: SceneModel, problem, k: int, body, support: int):
    """A grasp with a ``retreat`` of an object that stands on the box ``support`` (its cover within
    ``solver.clearance`` of it: :func:`~armanim.motion.carry.touching_support`), which it may
    touch along that line only: the line must take its cover ``solver.clearance`` (and
    ``solver.tolerance``, how far the grasp may take it off the goal) away from it."""
    from armanim.world.carried import cover_clearances

    model = scene.goals[k]
    assert model.retreat is not None
    name = problem.obstacles.name(goal_column := problem.goals[k].grasp)
    where = _obstacle_words(problem.obstacles, support)
    d_safe = problem.solver.clearance
    direction = retreat_direction(model)
    if direction is None or goal_column is None:
        return  # the retreat's own check says why
    lifted = replace(body, center=body.center + model.retreat.distance * direction)  # the line holds the orientation
    apart = float(
        cover_clearances(lifted, with_bodies(problem.obstacles, {goal_column: None}))[
            _kept_column(problem, goal_column, support)
        ]
    )
    if apart < d_safe + problem.solver.tolerance:
        yield (
            f"goals[{k}].retreat.distance",
            (
                f"the retreat leaves {name!r} {apart:.3g} from {where}, which it stands on (its cover of "
                f"capsules); expected at least solver.clearance + solver.tolerance = "
                f"{d_safe + problem.solver.tolerance:g}, so that it keeps its clearance after the line: "
                f"a longer retreat, about {model.retreat.distance + d_safe + problem.solver.tolerance - apart:.3g}"
            ),
        )


def _kept_column(problem, gone: int, column: int) -> int:
    """The column ``column`` of the scene's obstacles among them without the column ``gone``."""
    return column - (1 if gone < column else 0)


def _name_problems(scene: SceneModel):
    """Obstacles that share a ``name`` (each after the first)."""
    first: dict[str, int] = {}
    for k, obstacle in enumerate(scene.obstacles):
        if obstacle.name is None:
            continue
        if obstacle.name in first:
            yield (
                f"obstacles[{k}].name",
                (
                    f"{obstacle.name!r} already names obstacles[{first[obstacle.name]}] "
                    "(expected each obstacle's name once: rename one)"
                ),
            )
        else:
            first[obstacle.name] = k


def _pen_problems(scene: SceneModel):
    """A text goal whose tool axis points out of the board's front (the pen would come at the
    board from behind, and lift into it)."""
    for k, goal in enumerate(scene.goals):
        text = goal.path.text if goal.path is not None else None
        if text is None or (goal.tool_axis is None and goal.orientation is None):
            continue
        front = [float(v) + 0.0 for v in np.cross(text.right, text.up)]
        if goal.tool_axis is not None:
            axis = goal.tool_axis
        else:
            assert goal.orientation is not None  # one of the two, as tested above
            axis = orientation_rotation(goal.orientation)[:, 2].tolist()
        if sum(a * f for a, f in zip(axis, front)) > 0:
            field = "tool_axis" if goal.tool_axis is not None else "orientation"
            yield (
                f"goals[{k}].{field}",
                (
                    f"points the tool out of the board's front (right x up = {_vector(front)}, the side the text reads from and the "
                    f"pen lifts to; expected the tool pointing into the board, e.g. tool_axis: {_vector([-f + 0.0 for f in front])}, "
                    "or negate right to write on the other face)"
                ),
            )


def _vector(values) -> str:
    return "[" + ", ".join(f"{v:.6g}" for v in values) + "]"


def _self_collision_problems(problem, path: str, phi=None, pose: str = "the home pose", change: str = "arm.home"):
    """Enabled pairs of the arm's own capsules closer than ``solver.self_clearance`` at home (or at
    the pose ``phi``), each named."""
    pairs = problem.self_pairs
    if not len(pairs):
        return
    gaps = self_gaps(forward(problem.arm, problem.home if phi is None else phi), problem.capsules, pairs).d
    seen = set()
    for k in np.argsort(gaps, kind="stable"):
        if not gaps[k] < pairs.clearance or pairs.names[k] in seen:
            continue
        seen.add(pairs.names[k])
        a, b = pairs.names[k]
        yield (
            path,
            (
                f"{pose} has {a} and {b} {'overlapping' if gaps[k] <= 0 else 'closer than solver.self_clearance'} "
                f"(gap {gaps[k]:.3g}, expected at least solver.self_clearance = {pairs.clearance:g}: change {change}, "
                f"allow the pair (arm.self_collision: {{auto: true, allow: [[{a}, {b}]]}}) or lower solver.self_clearance)"
            ),
        )


def _count_problems(scene: SceneModel):
    """arm.axes, home and limits of another length than the arm's joints (the arm is then unknown)."""
    arm = scene.arm
    n = arm.joint_count
    for field in ("axes", "home", "limits"):
        values = getattr(arm, field)
        if values is not None and len(values) != n:
            yield (
                f"arm.{field}",
                f"has {len(values)} entries, the arm has {n} {'joints' if arm.is_urdf else 'links'} (expected one per joint)",
            )
    for k, goal in enumerate(scene.goals):
        if goal.joints is not None and len(goal.joints) != n:
            yield (
                f"goals[{k}].joints",
                (
                    f"has {len(goal.joints)} values, the arm has {n} moving joints "
                    "(expected one per joint, in order, as arm.home)"
                ),
            )


def _bounds_problems(scene: SceneModel):
    """``render.bounds`` ranges that are not from min to max."""
    if scene.render.bounds != "auto":
        for axis, pair in zip("xyz", scene.render.bounds):
            if not pair[0] < pair[1]:
                low, high = apart(pair[0], pair[1])
                yield "render.bounds", f"{axis} range must have min < max (got [{low}, {high}])"


def frame_budget(scene: SceneModel) -> int:
    """Most frames the scene can produce: frame 0, then every goal's frame cap and hold frames,
    and a path goal's frames along its path (:func:`path_frames`)."""
    fps = scene.render.fps
    per_goal = scene.solver.max_frames_per_goal
    lines = sum(
        per_goal + line_frames(line, fps) for _, line in _lines(scene)
    )  # an approach's or retreat's goal of its own
    return 1 + lines + sum(per_goal + frames_in(g.hold, fps) + path_frames(g, fps) for g in scene.goals)


MOST_PATH_FRAMES = 10**15
"""Cap of :func:`path_frames` (a path far too long for its speed counts as this many)."""


def path_frames(goal, fps: float) -> int:
    """Frames the tool takes along a path goal's path at its ``speed`` and ``fps``, rounded up
    (0 for a point goal; at most :data:`MOST_PATH_FRAMES`).

    >>> from armanim.scene.models import GoalModel
    >>> path_frames(GoalModel(path={"line": [[0, 0, 0], [0.3, 0, 0]]}, speed=0.1), 30.0)
    90
    """
    if goal.path is None:
        return 0
    # a length past float's range (a point at 1e308) is inf: _magnitude_problems reports the point
    with np.errstate(all="ignore"):
        length = tool_path(goal.path).length
    return _frames_along(length, goal.speed, fps)


def _frames_along(length: float, speed: float, fps: float) -> int:
    """Frames a tool takes over ``length`` at ``speed`` and ``fps``, rounded up, at most :data:`MOST_PATH_FRAMES`."""
    with np.errstate(all="ignore"):  # a scene's extreme numbers are reported by _magnitude_problems
        frames = length / speed * fps
    return math.ceil(frames - 1e-9) if frames < MOST_PATH_FRAMES else MOST_PATH_FRAMES


def _lines(scene: SceneModel):
    """(field path, ApproachModel) of every goal's ``approach`` and ``retreat``."""
    for k, goal in enumerate(scene.goals):
        for name in ("approach", "retreat"):
            line = getattr(goal, name)
            if line is not None:
                yield f"goals[{k}].{name}", line


def line_frames(line, fps: float) -> int:
    """Frames the tool takes along an ``approach`` or ``retreat`` line at its speed (default: its
    distance a second) and ``fps``, rounded up (at most :data:`MOST_PATH_FRAMES`).

    >>> from armanim.scene.models import ApproachModel
    >>> line_frames(ApproachModel(distance=0.1), 30.0), line_frames(ApproachModel(distance=0.1, speed=0.01), 30.0)
    (30, 300)
    """
    return _frames_along(line.distance, line.speed if line.speed is not None else line.distance, fps)


def _magnitudes(scene: SceneModel):
    """(field path, value) of every coordinate and length of the scene."""
    arm = scene.arm
    yield from ((f"arm.base[{i}]", v) for i, v in enumerate(arm.base or ()))
    yield from ((f"arm.links[{i}]", v) for i, v in enumerate(arm.links or ()))
    yield "arm.width", arm.resolved_width
    if arm.tool is not None:
        yield from ((f"arm.tool.xyz[{i}]", v) for i, v in enumerate(arm.tool.xyz))
    for k, capsule in enumerate(arm.collision if isinstance(arm.collision, list) else ()):
        for label, value in (("from", capsule.from_), ("to", capsule.to), ("radius", [capsule.radius])):
            yield from (
                (f"arm.collision[{k}].{label}[{i}]" if label != "radius" else f"arm.collision[{k}].radius", v)
                for i, v in enumerate(value)
            )
    for k, obstacle in enumerate(scene.obstacles):
        yield from _obstacle_magnitudes(f"obstacles[{k}]", obstacle)
    if scene.floor is not None:
        yield "floor", scene.floor
    for where, line in _lines(scene):
        yield f"{where}.distance", line.distance
        if line.speed is not None:
            yield f"{where}.speed", line.speed
    for k, goal in enumerate(scene.goals):
        if goal.joints is not None:
            continue  # angles: the limits bound them
        if goal.path is None:
            yield from ((f"goals[{k}].position[{i}]", v) for i, v in enumerate(goal.position or ()))
        else:
            yield from _path_magnitudes(f"goals[{k}].path", goal.path)
    solver = scene.solver
    yield "solver.tolerance", solver.tolerance
    if solver.path_tolerance is not None:
        yield "solver.path_tolerance", solver.path_tolerance
    yield "solver.damping", solver.damping
    if solver.max_step is not None:
        yield "solver.max_step", solver.max_step
    if solver.clearance is not None:
        yield "solver.clearance", solver.clearance
    if solver.self_clearance is not None:
        yield "solver.self_clearance", solver.self_clearance
    if solver.orientation_weight is not None:  # a length per radian
        yield "solver.orientation_weight", solver.orientation_weight
    if scene.render.bounds != "auto":
        for axis, pair in zip("xyz", scene.render.bounds):
            yield from ((f"render.bounds.{axis}", v) for v in pair)


def _path_magnitudes(path: str, model):
    """(field path, value) of every coordinate and length of a path goal's path."""
    form = model.form
    value = getattr(model, form)
    if form in ("line", "polyline"):
        for j, point in enumerate(value):
            yield from ((f"{path}.{form}[{j}][{i}]", v) for i, v in enumerate(point))
        return
    names = ("center", "start") if form == "arc" else ("origin",)
    for name in names:
        yield from ((f"{path}.{form}.{name}[{i}]", v) for i, v in enumerate(getattr(value, name)))
    if form == "text":
        yield f"{path}.text.height", value.height
        if value.lift is not None:
            yield f"{path}.text.lift", value.lift


def _obstacle_magnitudes(path: str, obstacle):
    """(field path, value) of every coordinate and length of one obstacle."""
    shape = obstacle.box or obstacle.capsule or obstacle.cylinder
    own = f"{path}.{obstacle.kind}" if shape is not None else path
    fields = {"center": 3, "size": 3, "from_": 3, "to": 3, "length": 1, "radius": 1}
    for name in fields:
        value = getattr(shape if shape is not None else obstacle, name, None)
        if value is None:
            continue
        label = "from" if name == "from_" else name
        if isinstance(value, list):
            yield from ((f"{own}.{label}[{i}]", v) for i, v in enumerate(value))
        else:
            yield f"{own}.{label}", value
    if obstacle.influence is not None:
        yield f"{path}.influence", obstacle.influence


POSITIVE_LENGTHS = re.compile(
    r"arm\.links\[\d+\]|arm\.width|solver\.(tolerance|path_tolerance|max_step|clearance|self_clearance|orientation_weight)"
    r"|obstacles\[\d+\]\.(box\.size\[\d\]|capsule\.radius|cylinder\.(length|radius)|influence)|goals\[\d+\]\.path\.text\.(height|lift)"
    r"|goals\[\d+\]\.(approach|retreat)\.(distance|speed)"
)
"""The lengths that must be > 0: each is also at least LIMITS["smallest"] (its ratio to the
largest, 1e18 at most, keeps every square and quotient of the solvers within a float)."""


def _magnitude_problems(scene: SceneModel):
    """Coordinates and lengths beyond :data:`LIMITS`' magnitude, lengths below its smallest, cost weights too large."""
    big, small = LIMITS["magnitude"], LIMITS["smallest"]
    for path, value in _magnitudes(scene):
        if abs(value) > big:
            yield path, f"{value:g} is too large (expected at most {big:g} in size: choose a smaller unit)"
        elif 0 < value < small and POSITIVE_LENGTHS.fullmatch(path):
            yield path, f"{value:g} is too small (expected at least {small:g}: choose a larger unit)"
    if sum(scene.arm.links or ()) > big:
        yield (
            "arm.links",
            f"the arm is {sum(scene.arm.links or ()):g} long (expected at most {big:g}: choose a smaller unit)",
        )
    weights = scene.solver.weights
    for name in type(weights).model_fields:
        value = getattr(weights, name)
        if value > LIMITS["weight"]:
            yield f"solver.weights.{name}", f"{value:g} is too large (expected at most {LIMITS['weight']:g})"


def _budget_problems(scene: SceneModel):
    """The frames the scene may run, and those following its path goals, against the frame limit."""
    budget = frame_budget(scene)
    limit = int(LIMITS["total_frames"])
    along = [
        (f"goals[{k}].speed", path_frames(g, scene.render.fps), "this goal's path", "the path")
        for k, g in enumerate(scene.goals)
    ]
    along += [
        (f"{where}.speed", line_frames(line, scene.render.fps), f"this {where.rsplit('.', 1)[1]}", "its distance")
        for where, line in _lines(scene)
    ]
    field, most, what, shorter = max(along, key=lambda a: a[1])
    if budget > limit and most > budget // 2:
        yield (
            field,
            (
                f"the scene may run {budget:,} frames, {most:,} of them along {what} at {scene.render.fps:g} fps "
                f"(expected at most {limit:,} in all: raise the speed or shorten {shorter})"
            ),
        )
    elif budget > limit:
        holds = budget - 1 - len(scene.goals) * scene.solver.max_frames_per_goal
        yield (
            ("goals" if holds > budget // 2 else "solver.max_frames_per_goal"),
            (
                f"the scene may run {budget:,} frames (max_frames_per_goal {scene.solver.max_frames_per_goal:,} and the holds "
                f"at {scene.render.fps:g} fps over {len(scene.goals)} goals; expected at most {limit:,}: "
                "lower max_frames_per_goal, the holds or the number of goals)"
            ),
        )
    else:
        yield from _following_problems(scene, limit)


SMALLEST_MOVE_DEG = 1.0
"""A joint rate so low that moving a joint this far (degrees) would take more frames than the
limit is refused at validate: the run would be refused by its clock for any motion at all."""


def _slow_rate_problems(scene: SceneModel):
    """Joint speed, acceleration or jerk limits under which moving one joint
    :data:`SMALLEST_MOVE_DEG` from rest to rest takes more than the frame limit at the scene's fps
    (at the speed alone, then the acceleration alone from rest to rest, the jerk alone; each
    alone fitting, the three together as the clock times them, :func:`smallest_move_seconds`):
    the field, the frames that move would take, and the least value that fits."""
    from armanim.scene.limits import rate_limits

    fps, limit = scene.render.fps, LIMITS["total_frames"]
    seconds = limit / fps
    theta = math.radians(SMALLEST_MOVE_DEG)
    rates = rate_limits(scene)
    # time of the smallest move under each limit alone, and the least limit that makes it in ``seconds``
    kinds = (
        ("max_joint_speed", rates.speed, lambda v: theta / v, theta / seconds),
        ("max_joint_acceleration", rates.acceleration, lambda a: 2.0 * math.sqrt(theta / a), 4.0 * theta / seconds**2),
        ("max_joint_jerk", rates.jerk, lambda j: (32.0 * theta / j) ** (1.0 / 3.0), 32.0 * theta / seconds**3),
    )
    said = False
    if all(values is None or not len(values) or float(np.min(values)) >= floor for _, values, _, floor in kinds):
        together = _together_problem(scene, theta, rates, seconds)
        if together is not None:
            field, k, value, took, least = together
            yield _slow_rate_message(scene, field, k, value, theta, took * fps, least, together=True)
        return
    for field, values, duration, floor in kinds:
        if values is None or not len(values) or float(np.min(values)) >= floor:
            continue
        if said and getattr(scene.arm, field) is None:  # a default made from the speed already named
            continue
        said = True
        k = int(np.argmin(values))
        with np.errstate(all="ignore"):
            frames = duration(float(values[k])) * fps if values[k] > 0 else math.inf
        yield _slow_rate_message(scene, field, k, float(values[k]), theta, frames, floor)


def _slow_rate_message(
    scene: SceneModel, field: str, k: int, value: float, theta: float, frames: float, least: float, together=False
) -> tuple[str, str]:
    """The problem of ``field`` (its joint ``k``'s ``value``, SI) under which moving that joint
    ``theta`` takes ``frames`` frames: its unit (degrees, or metres for a prismatic joint), what it
    is set by, and the least value that fits (``least``; inf: none with the other rates as they
    are). ``together``: too slow only with the other rates, each of which alone would fit."""
    from armanim.scene.limits import SCENE_RATE_UNITS

    fps, limit = scene.render.fps, LIMITS["total_frames"]
    slides = scene.arm.sliding
    slide = len(slides) > k and bool(slides[k])  # a prismatic joint's rates are m/s..., its move theta metres
    unit = SCENE_RATE_UNITS[field].replace("deg", "m") if slide else SCENE_RATE_UNITS[field]
    shown = (lambda v: v) if slide else math.degrees
    move = f"{theta:.3g} m" if slide else f"{SMALLEST_MOVE_DEG:g} degree"
    took = f"{math.ceil(frames):,}" if frames < 1e18 else "more than 10^18"
    source = "" if getattr(scene.arm, field) is not None else " (not set: the arm's default; set it to override)"
    which = f"joint {k + 1}'s " if isinstance(getattr(scene.arm, field), list) else ""
    others = [f for f in RATE_FIELDS if f != field and (f != "max_joint_jerk" or scene.arm.max_joint_jerk is not None)]
    with_others = f" with {' and '.join(f'arm.{f}' for f in others)} as they are" if together else ""
    remedy = (
        f"raise it to at least {_rounded_up(shown(least)):.2g} {unit}"
        if least < math.inf
        else "no value of it fits with the others as they are: raise " + " or ".join(f"arm.{f}" for f in others)
    )
    return (
        f"arm.{field}",
        (
            f"{which}{shown(value):g} {unit}{source} is too slow for the frame limit{with_others}: moving "
            f"{'it' if which else 'a joint'} {move} from rest to rest would take {took} frames at {fps:g} fps "
            f"(expected at most {limit:,} in all: {remedy})"
        ),
    )


def smallest_move_seconds(theta: float, speed: np.ndarray, acceleration: np.ndarray, jerk: np.ndarray | None):
    """Seconds the clock takes to move each joint ``theta`` from rest to rest under its limits
    together, as :mod:`armanim.motion.timing.clock` times one joint's motion: the time-optimal
    trapezoid (or triangle) of its speed and acceleration, plus, with a jerk limit, the window
    the clock smooths every joint's law with (``max(2 a / j)`` over the joints).

    Parameters
    ----------
    theta : float
        The move, radians (metres for a prismatic joint).
    speed, acceleration : (n,) float arrays
        Rad/s and rad/s^2 (m/s, m/s^2).
    jerk : (n,) float array or None
        Rad/s^3; None without a jerk limit.

    Returns
    -------
    (n,) float array
        Seconds.

    >>> smallest_move_seconds(1.0, np.array([0.5]), np.array([1.0]), None).tolist()  # 2 s cruise, 0.5 s ramps
    [2.5]
    >>> smallest_move_seconds(1.0, np.array([10.0]), np.array([1.0]), np.array([2.0])).tolist()  # a triangle, and 1 s
    [3.0]
    """
    from armanim.motion.timing.clock import jerk_window  # the clock owns the window it smooths with

    with np.errstate(all="ignore"):
        cruise = speed**2 < theta * acceleration
        trapezoid = np.where(cruise, theta / speed + speed / acceleration, 2.0 * np.sqrt(theta / acceleration))
        window = jerk_window(acceleration, jerk) if jerk is not None and len(jerk) else 0.0
    return trapezoid + window


def _together_problem(scene: SceneModel, theta: float, rates, seconds: float):
    """The field to raise when each rate alone lets the smallest move fit the frame limit but
    the three together do not (a jerk window of ``2 a / j`` on top of the trapezoid; a speed at
    its floor and the ramps its acceleration adds): (field, joint, its value, seconds the move
    takes, the least value that fits, inf for none), or None.

    Campaign 10 (issue 50): ``max_joint_jerk: 1e-6`` (a million times its floor alone) passed
    validate, and run refused its clock of 7.2e10 frames."""
    speed, acceleration, jerk = rates.speed, rates.acceleration, rates.jerk
    seconds *= 1 - 1e-9  # the clock refuses a hair over the limit: the least values keep clear of it
    took = smallest_move_seconds(theta, speed, acceleration, jerk)
    k = int(np.argmax(took))
    if not took[k] > seconds:
        return None
    trapezoid = smallest_move_seconds(theta, speed, acceleration, None)
    window = took[k] - trapezoid[k]
    if window >= trapezoid[k] and jerk is not None:
        room = seconds - float(np.max(trapezoid))
        least = float(np.max(2.0 * acceleration / room)) if room > 0 else math.inf
        widest = int(np.argmax(2.0 * acceleration / jerk))  # the joint whose window the clock takes
        return "max_joint_jerk", widest, float(jerk[widest]), took[k], least
    room = seconds - window  # for the trapezoid: theta / v + v / a, or 2 sqrt(theta / a) once v^2 >= theta a
    v, a = float(speed[k]), float(acceleration[k])
    if room > 0 and room**2 > 4.0 * theta / a:  # theta / v + v / a = room has a root: the least speed
        return "max_joint_speed", k, v, took[k], a * (room - math.sqrt(room**2 - 4.0 * theta / a)) / 2.0
    triangle = 4.0 * theta / room**2 if room > 0 else math.inf
    least = triangle if v**2 >= theta * triangle else (v / (room - theta / v) if room > theta / v else math.inf)
    return "max_joint_acceleration", k, a, took[k], least


def _rounded_up(value: float) -> float:
    """``value`` rounded up to two significant digits (a bound to advise that is never short of it).

    >>> _rounded_up(4.7912e-07), _rounded_up(0.00049)
    (4.8e-07, 0.00049)
    """
    if not 0 < value < math.inf:
        return value
    unit = 10.0 ** (math.floor(math.log10(value)) - 1)
    return float(f"{math.ceil(value / unit * (1 - 1e-12)) * unit:.2g}")


def _followed(scene: SceneModel):
    """(goal index, what it is, the field of its speed, its path, its speed) of every path the run
    follows: each path goal's path, and each ``approach`` and ``retreat`` line, which the run follows
    as a path goal of its own (:func:`armanim.scene.convert.handling`, :func:`with_retreats`)."""
    from armanim.motion.toolpath import ToolPath

    for k, goal in enumerate(scene.goals):
        if goal.path is not None and goal.speed is not None:  # a path goal has its speed (GoalModel)
            yield k, f"goals[{k}]'s path", f"goals[{k}].speed", tool_path(goal.path), goal.speed
        for name in ("approach", "retreat"):
            line = getattr(goal, name)
            if line is not None:
                straight = ToolPath.polyline(np.array([[0.0, 0.0, 0.0], [line.distance, 0.0, 0.0]]))
                speed = line.speed if line.speed is not None else line.distance
                yield k, f"goals[{k}]'s {name}", f"goals[{k}].{name}.speed", straight, speed


def _following_problems(scene: SceneModel, limit: int):
    """The frames following the path goals and the approach and retreat lines may take, as the run
    counts them before it solves (:func:`armanim.motion.paths.following.most_following_frames`: the
    path's samples, every ``tunables.path.spacing_per_tolerance`` path tolerances or a frame's
    travel, each step halved up to ``tunables.path.max_splits`` times: the defaults, which no scene
    field sets), counted without making the samples, against the frame limit: the field that sets
    the spacing, and what to change it to. (Campaign 18: an approach or a retreat at a fine path
    tolerance was not counted here, and the run refused what validate called ok.)"""
    per_tolerance, max_splits = DEFAULTS.path.spacing_per_tolerance, DEFAULTS.path.max_splits
    fps, per_goal = scene.render.fps, scene.solver.max_frames_per_goal
    tolerance = scene.solver.path_tolerance if scene.solver.path_tolerance is not None else scene.solver.tolerance
    followed = list(_followed(scene))
    following = []
    for _, _, _, path, speed in followed:
        with np.errstate(all="ignore"):  # extreme numbers are reported by _magnitude_problems
            spacing = path_spacing(speed, fps, tolerance, per_tolerance)
            samples = (
                path.length / spacing if spacing > 0 else math.inf
            )  # a subnormal tolerance: too many to count in an int
            following.append(most_following_frames(path, spacing, per_goal, max_splits) if samples < 1e15 else 10**18)
    lines = sum(per_goal for _, line in _lines(scene))  # each line a goal of its own (frame_budget)
    budget = 1 + lines + sum(per_goal + frames_in(g.hold, fps) for g in scene.goals) + sum(following)
    if budget <= limit or not followed:
        return
    i = following.index(max(following))
    _, what, speed_field, path, speed = followed[i]
    room = (limit - (budget - following[i]) - per_goal - 1) // 2**max_splits - len(path.pieces)
    spacing = path.length / room if room > 0 else math.inf
    counted = f"up to {following[i]:,} frames, {budget:,} in all" if following[i] < 10**18 else "more than 10^15 frames"
    said = f"following {what} ({path.length:g} long) may take {counted} (expected at most {limit:,}): its samples are"
    if per_tolerance * tolerance < speed / fps:
        field = "solver.path_tolerance" if scene.solver.path_tolerance is not None else "solver.tolerance"
        need = _rounded_up(spacing / per_tolerance)
        yield (
            field,
            (
                f"{tolerance:g} is too fine for the frame limit: {said} {per_tolerance:g} path tolerances "
                f"apart, each step halved up to {max_splits} times"
                + (
                    f" (raise {field} to at least about {need:.2g}, or shorten the path)"
                    if room > 0
                    else " (lower max_frames_per_goal, the holds or the number of goals)"
                )
            ),
        )
    else:
        yield (
            speed_field,
            (
                f"{speed:g} is too slow for the frame limit: {said} a frame's travel apart "
                f"at {fps:g} fps, each step halved up to {max_splits} times "
                "(raise the speed or shorten the path)"
            ),
        )


def _home_collision_problems(problem):
    """Links of the home pose closer than ``solver.clearance`` to an obstacle or the floor, and a floor above the base."""
    obstacles = problem.obstacles
    if not len(obstacles):
        return
    d_safe = problem.solver.clearance
    yield from _floor_problems(problem)
    cl = clearances(forward(problem.arm, problem.home), obstacles, problem.capsules)
    for link, obs in zip(*np.nonzero(cl.links < d_safe)):
        inside = cl.links[link, obs] <= 0
        if problem.capsules.link[link] < 0:  # the base: no pose can move it
            name = problem.capsules.names[link] if problem.capsules.names else "the base"
            yield (
                _obstacle_path(obstacles, obs),
                (
                    f"the robot's base (link {name!r}, which never moves) is "
                    f"{'inside this obstacle' if inside else 'closer to it than solver.clearance'} "
                    f"(clearance {cl.links[link, obs]:.3g}, expected at least solver.clearance = {d_safe:g}: "
                    "move the obstacle or arm.base, or lower solver.clearance)"
                ),
            )
            continue
        shown = (
            f"link {problem.capsules.names[link]!r}" if problem.capsules.names else f"link {link + 1}"
        )  # a URDF's: by name
        yield (
            _obstacle_path(obstacles, obs),
            (
                f"{shown} of the arm's home pose is {'inside ' + _floor_or(obstacles, obs, _named(obstacles, obs, 'this obstacle')) if inside else 'closer to ' + _floor_or(obstacles, obs, _named(obstacles, obs, 'it')) + ' than solver.clearance'} "
                f"(clearance {cl.links[link, obs]:.3g}, expected at least solver.clearance = {d_safe:g}: "
                f"move {_floor_or(obstacles, obs, 'the obstacle')}, change arm.home or lower solver.clearance)"
            ),
        )


def _goal_point_problems(obstacles, goals, keep: float | None, tip_size: str):
    """Point and path goals (their start) inside an obstacle or below the floor, or (``keep``: the
    last link's radius + ``solver.clearance``, None when the arm is not known) closer than ``keep``;
    ``goals`` in the scene's order, None for one not checked here (a joint goal, or a grasp when
    the arm is not known: its point lies in the object it takes)."""
    if not len(obstacles):
        return
    moving = {
        g.grasp for g in goals if getattr(g, "grasp", None) is not None
    }  # the objects a tool takes: _grasp_problems
    for k, goal in enumerate(goals):
        if goal is None or goal.joints is not None:
            continue  # its tool point is no part of the arm: the pose's links are checked (scene_problems)
        gap = point_clearances(goal.position[None], obstacles)[0]
        near = gap < keep if keep is not None else gap <= 0
        for obs in (int(o) for o in np.nonzero(near)[0]):
            if obs in moving:
                continue
            where = _obstacle_path(obstacles, obs) if obstacles.kinds[obs] == FLOOR else _obstacle_words(obstacles, obs)
            if gap[obs] <= 0:
                yield (
                    f"goals[{k}]",
                    f"lies {'below the floor' if where == 'floor' else 'inside ' + where} (the tip can never reach it; move the goal or {_floor_or(obstacles, obs, 'the obstacle')})",
                )
            else:
                yield (
                    f"goals[{k}]",
                    (
                        f"is {gap[obs]:.3g} from {'the floor' if where == 'floor' else 'the surface of ' + where} (expected at least {tip_size} + "
                        f"solver.clearance = {keep:g}, so that the last link can keep its clearance "
                        f"there: move the goal or {_floor_or(obstacles, obs, 'the obstacle')}, or lower solver.clearance)"
                    ),
                )


def _pose_collision_problems(problem, phi, path: str, pose: str, change: str):
    """Links of the pose ``phi`` (radians) closer than ``solver.clearance`` to an obstacle or the floor."""
    obstacles = problem.obstacles
    if not len(obstacles):
        return
    d_safe = problem.solver.clearance
    cl = clearances(forward(problem.arm, phi), obstacles, problem.capsules)
    for link, obs in zip(*np.nonzero(cl.links < d_safe)):
        if problem.capsules.link[link] < 0:
            continue  # the base, which no pose moves: checked with the home pose
        where = _floor_or(obstacles, obs, _obstacle_words(obstacles, obs))
        inside = cl.links[link, obs] <= 0
        part = f"link {problem.capsules.names[link]!r}" if problem.capsules.names else f"link {link + 1}"
        yield (
            path,
            (
                f"{part} of {pose} is {'inside ' + where if inside else 'closer to ' + where + ' than solver.clearance'} "
                f"(clearance {cl.links[link, obs]:.3g}, expected at least solver.clearance = {d_safe:g}: "
                f"change {change}, move {where} or lower solver.clearance)"
            ),
        )


def _floor_problems(problem):
    """The floor below the arm's base (the base stands on it or above it)."""
    floor = problem.obstacles.floor
    base = float(problem.arm.base[2])
    if floor is not None and floor > base:
        yield "floor", f"{floor:g} is above the arm's base (base z = {base:g}; expected the floor at or below the base)"


def _obstacle_path(obstacles, column: int) -> str:
    """The field path of a clearance column: ``obstacles[k]``, or ``floor`` (the last column)."""
    return "floor" if obstacles.kinds[column] == FLOOR else f"obstacles[{column}]"


def _obstacle_words(obstacles, column: int) -> str:
    """How a message names an obstacle: ``obstacles[k]``, with its name where it has one (``obstacles[0] ('can1')``)."""
    name = obstacles.name(column)
    return _obstacle_path(obstacles, column) + (f" ({name!r})" if name is not None else "")


def _named(obstacles, column: int, words: str) -> str:
    """``words``, or the obstacle's name where it has one (``'can1'``)."""
    name = obstacles.name(column)
    return words if name is None else repr(name)


def _floor_or(obstacles, column: int, words: str) -> str:
    """How a message names a clearance column: ``the floor``, or ``words`` for an obstacle."""
    return "the floor" if obstacles.kinds[column] == FLOOR else words


RADIAN_LIKE = 6.3  # just above 2 pi: angles all smaller than this, and not whole, look like radians


def radian_notes(scene: SceneModel) -> list[tuple[str, str]]:
    """Notes (not errors) for angle fields whose values look like radians: every value
    smaller than 6.3 in size and some not whole numbers. armanim reads degrees.

    >>> from armanim.scene.models import SceneModel
    >>> scene = SceneModel.model_validate({"version": 1, "arm": {"links": [1, 1], "home": [0.5, 1.2]}, "goals": [[1, 0, 1]]})
    >>> radian_notes(scene)[0][0]
    'arm.home'
    """
    arm = scene.arm
    fields = {"arm.home": arm.home or [], "arm.limits": [v for pair in arm.limits or [] if pair for v in pair]}
    notes = []
    for path, values in fields.items():
        if values and all(abs(v) < RADIAN_LIKE for v in values) and any(v != int(v) for v in values):
            example = next(v for v in values if v != int(v))
            notes.append(
                (
                    path,
                    f"these angles look like radians (all below {RADIAN_LIKE} in size, not all whole); "
                    f"armanim reads degrees: {example:g} rad would be {math.degrees(example):.4g}",
                )
            )
    return notes


def as_diagnostics(pairs, line_of) -> list[Diagnostic]:
    """Attach line numbers to (path, message) pairs."""
    return [Diagnostic(path, message, line_of(path)) for path, message in pairs]


def fallback_notes(scene: SceneModel) -> list[tuple[str, str]]:
    """Notes on the URDF arm's capsules that are not its collision geometry: links fitted to their
    visual meshes (no ``<collision>``), visual meshes that could not be read for it, and moving
    links with no geometry at all, which get a joint-to-joint capsule of radius ``arm.width / 2``."""
    arm = scene.arm
    if not arm.is_urdf:
        return []
    robot, notes = arm.urdf_arm, []
    if robot.from_visuals:
        notes.append(
            (
                "arm.collision",
                f"links {', '.join(robot.from_visuals)} have no <collision>: their capsules are fitted "
                "to their visual meshes (the run folder's capsules.yaml lists them)",
            )
        )
    notes += [("arm.collision", f"{problem}: not fitted") for problem in robot.unread_meshes]
    if robot.fallback_links:
        links = ", ".join(robot.fallback_links)
        notes.append(
            (
                "arm.collision",
                f"links {links} have no collision geometry armanim can use (no primitive, no mesh): "
                f"each gets a capsule from its joint to the next of radius arm.width / 2 = "
                f"{arm.resolved_width / 2:g} (give arm.collision to set them)",
            )
        )
    return notes
