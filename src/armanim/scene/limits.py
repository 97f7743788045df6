"""Joint limits and joint rate limits: the scene's, the robot's own, their defaults and checks.

One module for the angles and rates a joint may not exceed: ``arm.limits`` and
``arm.limit_margin`` (or the URDF's ``<limit>``) become the barrier's :class:`Limits`, and
``arm.max_joint_speed``, ``max_joint_acceleration`` and ``max_joint_jerk`` (or the robot's own,
from its URDF and robot.yaml) the clock's :class:`RateLimits`, in radians; the problems of a
scene's limits and rates (reported at their field, exit 2) and the notes for rates above the
robot's own are here too. Part of Scene -> Problem: :func:`armanim.scene.convert.scene_to_problem`
calls :func:`joint_limits` and :func:`rate_limits`, and degrees become radians nowhere else
than in these two modules.
"""

from __future__ import annotations

import math

import numpy as np

from armanim.arm.kinematics import joints_in_si
from armanim.errors import shown
from armanim.motion.problem import LINK_ACCELERATION_PER_SPEED, Limits, RateLimits, link_arm_rates
from armanim.motion.tunables import DEFAULTS
from armanim.output.numbers import apart
from armanim.scene.armmodel import ArmModel
from armanim.scene.models import SceneModel
from armanim.scene.robots import published_joint_names

URDF_SPEED = 180.0
"""deg/s: ``arm.max_joint_speed`` of a URDF joint whose ``<limit>`` gives no velocity (and whose
robot publishes none): half a turn a second, a typical cobot's joint speed (a UR5's 180, a
Panda's 125 to 150)."""

URDF_SLIDE_SPEED = 0.5
"""m/s: the speed of a prismatic joint whose ``<limit>`` gives no velocity (a linear axis's
typical half a metre a second)."""

SLIDE_JERK_PER_ACCELERATION = 10.0
"""1/s: a prismatic joint's jerk limit per its acceleration limit where ``max_joint_jerk`` is one
number (which sets the revolute joints')."""

RATE_FIELDS = ("max_joint_speed", "max_joint_acceleration", "max_joint_jerk")
"""The arm's joint rate fields (deg/s, deg/s^2, deg/s^3), in this order."""


def joint_limits(arm: ArmModel) -> Limits:
    """The arm's joint limits, radians (metres for a prismatic joint): ``arm.limits`` (degrees;
    metres), else the URDF's own, else none; the barrier's margin ``arm.limit_margin`` (its
    radians, taken as metres by a prismatic joint: 10 degrees keep 0.175 m)."""
    n = arm.joint_count
    slides = arm.sliding
    pairs: list
    if arm.limits is None and arm.is_urdf:  # the URDF's own, in radians (metres) already
        pairs = [
            (p if slide else np.degrees(p)) if p is not None else None for p, slide in zip(arm.urdf_arm.limits, slides)
        ]
    else:
        pairs = arm.limits if arm.limits is not None else [None] * n
    lower = np.array(
        [(float(p[0]) if slide else np.radians(p[0])) if p is not None else -np.inf for p, slide in zip(pairs, slides)]
    )
    upper = np.array(
        [(float(p[1]) if slide else np.radians(p[1])) if p is not None else np.inf for p, slide in zip(pairs, slides)]
    )
    return Limits(lower=lower, upper=upper, margin=float(np.radians(arm.limit_margin)))


def unlimited_limits(n: int) -> Limits:
    """Limits of ``n`` freely turning joints, with the scene's default ``arm.limit_margin``."""
    return Limits.unlimited(n, margin=float(np.radians(ArmModel.model_fields["limit_margin"].default)))


def robot_rates(arm: ArmModel) -> dict[str, tuple[np.ndarray, str]]:
    """A URDF arm's own joint rate limits, radians: scene field name -> ((n,) values, NaN where
    the robot gives none; where they come from). The speed is the robot.yaml's published one,
    else the URDF's ``<limit velocity>``; acceleration and jerk are robot.yaml's, where its
    maker publishes them. An arm of links has none.

    >>> from armanim.scene.loader import scene_model
    >>> arm = scene_model({"version": 1, "arm": {"robot": "panda"}, "goals": [[0.5, 0, 0.5]]}).arm
    >>> own = robot_rates(arm)
    >>> sorted(own), own["max_joint_speed"][0][:2].tolist(), own["max_joint_acceleration"][1]
    (['max_joint_acceleration', 'max_joint_jerk', 'max_joint_speed'], [2.175, 2.175], "the maker's, in robot panda's robot.yaml")
    """
    if not arm.is_urdf:
        return {}
    robot = arm.urdf_arm
    own = {
        "max_joint_speed": (
            np.array([np.nan if v is None else v for v in robot.velocities], dtype=float),
            "the URDF's <limit velocity>",
        )
    }
    bundled = robot.bundled
    for name in RATE_FIELDS if bundled is not None else ():
        assert bundled is not None
        published = bundled.rate(name)
        if published is None:
            continue
        by_joint = dict(zip(published_joint_names(bundled.name), published.values))  # the scene may choose other links
        values = np.array([by_joint.get(joint, np.nan) for joint in robot.joint_names], dtype=float)
        values = np.radians(values) if published.unit.startswith("deg") else values
        if name in own:  # a joint the maker's list does not name keeps the URDF's
            values = np.where(np.isnan(values), own[name][0], values)
        own[name] = (values, f"the maker's, in robot {bundled.name}'s robot.yaml")
    return own


def _given_rates(value, n: int, slides: np.ndarray | None = None, own: np.ndarray | None = None) -> np.ndarray | None:
    """A rate field as the scene gives it (one number for all, or one per joint), radians (metres
    for a prismatic joint); None if left out. One number sets the revolute joints: a prismatic
    joint keeps ``own`` (its rate in m/s..., NaN: none) unless a list gives it."""
    if value is None:
        return None
    if slides is None or not slides.any():
        return np.radians(np.broadcast_to(np.asarray(value, dtype=float), (n,))).copy()
    values = joints_in_si(np.broadcast_to(np.asarray(value, dtype=float), (n,)), slides)
    if not isinstance(value, list) and own is not None:
        values = np.where(slides, own, values)
    return values


def rate_limits(scene: SceneModel) -> RateLimits:
    """The joint rate limits the clock keeps (radians): the scene's ``arm.max_joint_speed``,
    ``max_joint_acceleration`` and ``max_joint_jerk``, or their defaults.

    Speed: a URDF arm's own (:func:`robot_rates`; :data:`URDF_SPEED` for a joint without one),
    an arm of links ``solver.max_joint_step`` x ``render.fps`` (the scene's own fps, whatever
    rate the frames are later sampled at). Acceleration: the robot's published one, else
    :data:`LINK_ACCELERATION_PER_SPEED` x the speed per second. Jerk: only when the scene sets
    ``max_joint_jerk`` (``robot``: the bundled robot's published one).

    >>> from armanim.scene.models import SceneModel
    >>> scene = SceneModel.model_validate({"version": 1, "arm": {"links": [1, 1], "max_joint_speed": [90, 45]}, "goals": [[1, 0, 1]]})
    >>> r = rate_limits(scene)
    >>> np.degrees(r.speed).round(9).tolist(), np.degrees(r.acceleration).round(9).tolist(), r.jerk
    ([90.0, 45.0], [360.0, 180.0], None)
    """
    arm = scene.arm
    n = arm.joint_count
    slides = arm.sliding
    own = robot_rates(arm)
    if arm.is_urdf:
        default = (
            np.radians(URDF_SPEED) if not slides.any() else np.where(slides, URDF_SLIDE_SPEED, np.radians(URDF_SPEED))
        )
        speed = np.where(np.isnan(own["max_joint_speed"][0]), default, own["max_joint_speed"][0])
    else:
        speed = link_arm_rates(n, float(np.radians(scene.solver.max_joint_step)), scene.render.fps).speed
    given = _given_rates(arm.max_joint_speed, n, slides, speed)
    speed = given if given is not None else speed
    published = own.get("max_joint_acceleration", (np.full(n, np.nan),))[0]
    own_acceleration = np.where(np.isnan(published), LINK_ACCELERATION_PER_SPEED * speed, published)
    given = _given_rates(arm.max_joint_acceleration, n, slides, own_acceleration)
    acceleration = own_acceleration if given is None else given
    jerk: np.ndarray | None
    if arm.max_joint_jerk == "robot":
        jerk = own["max_joint_jerk"][0]
    else:
        jerk = _given_rates(arm.max_joint_jerk, n, slides, SLIDE_JERK_PER_ACCELERATION * acceleration)
    return RateLimits(speed=speed, acceleration=acceleration, jerk=jerk)


def limit_problems(arm: ArmModel):
    """(field path, message) of every problem of the arm's joint limits: a range not from min to
    max or too narrow for the planner's buffer, the home pose (given or zeros) outside it."""
    n = arm.joint_count
    if arm.limits is not None:
        for i, pair in enumerate(arm.limits):
            if pair is not None and not pair[0] < pair[1]:
                low, high = apart(pair[0], pair[1])
                yield f"arm.limits[{i}]", f"min must be below max (got [{low}, {high}])"
    yield from _narrow_limits(arm)
    limits = arm.limits if arm.limits is not None or not arm.is_urdf else _urdf_limits_degrees(arm)
    if limits is not None and len(limits) == n and (arm.home is None or len(arm.home) == n):
        bundled = arm.urdf_arm.bundled if arm.is_urdf else None
        yield from _home_outside_limits(
            arm.home if arm.home is not None or bundled is None else list(bundled.home), limits, _units(arm)
        )


def _narrow_limits(arm):
    """Joint ranges no wider than the buffer the planner keeps inside each limit, twice
    (the filter's ``limit_buffer`` of arm.limit_margin at each end, the default gains a scene's
    problem holds): nowhere left for a pose to be."""
    buffer = DEFAULTS.filter.limit_buffer
    least = 2 * buffer * arm.limit_margin
    advice = f"expected wider than 2 x {buffer:g} x arm.limit_margin = {least:g} deg"
    if arm.limits is not None:
        slides = (
            arm.sliding if arm.is_urdf and len(arm.limits) == arm.joint_count else np.zeros(len(arm.limits), dtype=bool)
        )
        for i, pair in enumerate(arm.limits):
            if slides[i]:
                if (
                    pair is not None
                    and pair[0] < pair[1]
                    and pair[1] - pair[0] <= 2 * buffer * math.radians(arm.limit_margin)
                ):
                    yield (
                        f"arm.limits[{i}]",
                        (
                            f"a range of {pair[1] - pair[0]:g} m is too narrow for a prismatic joint (expected wider than "
                            f"2 x {buffer:g} x arm.limit_margin in radians, as metres: widen it or lower arm.limit_margin)"
                        ),
                    )
            elif pair is not None and pair[0] < pair[1] and pair[1] - pair[0] <= least:
                yield (
                    f"arm.limits[{i}]",
                    f"a range of {pair[1] - pair[0]:g} deg is too narrow ({advice}: widen it or lower arm.limit_margin)",
                )
    elif arm.is_urdf:
        for name, pair, slide in zip(arm.urdf_arm.joint_names, _urdf_limits_degrees(arm), arm.sliding):
            if slide and pair[1] - pair[0] <= 2 * buffer * math.radians(arm.limit_margin):
                yield (
                    "arm.limit_margin",
                    (
                        f"the URDF's prismatic joint {shown(name)} has a range of {pair[1] - pair[0]:g} m, too narrow "
                        f"(expected wider than 2 x {buffer:g} x arm.limit_margin in radians, as metres: "
                        "lower arm.limit_margin, or give arm.limits)"
                    ),
                )
            elif not slide and pair is not None and pair[1] - pair[0] <= least:
                yield (
                    "arm.limit_margin",
                    (
                        f"the URDF's joint {shown(name)} has a range of {pair[1] - pair[0]:g} deg, too narrow "
                        f"({advice}: lower arm.limit_margin, or give arm.limits)"
                    ),
                )


def _urdf_limits_degrees(arm) -> list:
    """The URDF's joint limits in degrees (None for a continuous joint; metres for a prismatic one)."""
    return [
        ([p[0], p[1]] if slide else [math.degrees(p[0]), math.degrees(p[1])]) if p is not None else None
        for p, slide in zip(arm.urdf_arm.limits, arm.sliding)
    ]


def _units(arm) -> list[str]:
    """Each joint's unit as the scene writes its values: ``deg``, or ``m`` for a prismatic joint."""
    return ["m" if slide else "deg" for slide in arm.sliding]


def _home_outside_limits(home, limits, units=None):
    """arm.home (given, or the default zeros) within every limited joint's range, its ends included
    (MoveIt's bounds are closed: a start may rest on a limit)."""
    given = home is not None
    angles = home if given else [0.0] * len(limits)
    units = units or ["deg"] * len(limits)
    for i, (angle, pair) in enumerate(zip(angles, limits)):
        if pair is None or not pair[0] < pair[1] or pair[0] <= angle <= pair[1]:
            continue
        step = 1 if units[i] == "deg" else 0.01  # an example a degree (a centimetre) inside
        inside = (
            min(max(angle, pair[0] + step), pair[1] - step) if pair[1] - pair[0] > 2 * step else (pair[0] + pair[1]) / 2
        )
        shown_angle, low, high, example = apart(angle, pair[0], pair[1], inside)
        if given:
            yield (
                f"arm.home[{i}]",
                (
                    f"{shown_angle} {units[i]} is outside joint {i + 1}'s limits arm.limits[{i}] = [{low}, {high}] "
                    f"(expected within them, the ends included: e.g. home[{i}]: {example})"
                ),
            )
        else:
            yield (
                "arm.home",
                (
                    f"is not given, so joint {i + 1} starts at 0 {units[i]}, outside its limits arm.limits[{i}] = "
                    f"[{low}, {high}] (expected within them, the ends included: give arm.home with e.g. {example} for joint {i + 1})"
                ),
            )


def joint_goal_limit_problems(scene: SceneModel):
    """(field path, message) of each joint goal value outside its joint's limits (the ends are
    allowed, as for ``arm.home``); goals of the wrong length are reported by the count check."""
    arm = scene.arm
    n = arm.joint_count
    limits = arm.limits if arm.limits is not None or not arm.is_urdf else _urdf_limits_degrees(arm)
    if limits is None or len(limits) != n:
        return
    units = _units(arm)
    for k, goal in enumerate(scene.goals):
        if goal.joints is None or len(goal.joints) != n:
            continue
        for i, (angle, pair) in enumerate(zip(goal.joints, limits)):
            if pair is not None and pair[0] < pair[1] and not pair[0] <= angle <= pair[1]:
                shown_angle, low, high = apart(angle, pair[0], pair[1])
                yield (
                    f"goals[{k}].joints[{i}]",
                    (
                        f"{shown_angle} {units[i]} is outside joint {i + 1}'s limits [{low}, {high}] "
                        "(expected within them, the ends included)"
                    ),
                )


def rate_problems(arm: ArmModel):
    """Joint rate lists with one value per joint; ``max_joint_jerk: robot`` only for a robot that publishes one."""
    n = arm.joint_count
    for field in RATE_FIELDS:
        values = getattr(arm, field)
        if isinstance(values, list) and len(values) != n:
            yield (
                f"arm.{field}",
                (f"has {len(values)} values, the arm has {n} joints (give one per joint, or one number for all)"),
            )
    if arm.max_joint_jerk == "robot":
        bundled = arm.urdf_arm.bundled if arm.is_urdf else None
        if bundled is None:
            yield (
                "arm.max_joint_jerk",
                (
                    "robot means the bundled robot's published jerk limits, and this arm is not a bundled "
                    "robot (give deg/s^3: one number, or one per joint)"
                ),
            )
        elif bundled.rate("max_joint_jerk") is None or np.isnan(robot_rates(arm)["max_joint_jerk"][0]).any():
            yield (
                "arm.max_joint_jerk",
                (
                    f"robot {bundled.name}'s maker publishes no jerk limits for these joints "
                    "(give deg/s^3: one number, or one per joint)"
                ),
            )


SCENE_RATE_UNITS = {"max_joint_speed": "deg/s", "max_joint_acceleration": "deg/s^2", "max_joint_jerk": "deg/s^3"}


def rate_notes(scene: SceneModel) -> list[tuple[str, str]]:
    """Notes (not errors) for joint rates the scene sets above the robot's own: allowed (an
    animation may be faster than the robot), but no real robot of that kind could follow it.
    One note per field, naming the joints.

    >>> from armanim.scene.loader import scene_model
    >>> scene = scene_model({"version": 1, "arm": {"robot": "panda", "max_joint_speed": 130}, "goals": [[0.5, 0, 0.5]]})
    >>> path, message = rate_notes(scene)[0]
    >>> path, message[:57]
    ('arm.max_joint_speed', "130 deg/s is above the robot's own limit for joints 1-4 (")
    """
    arm = scene.arm
    own = robot_rates(arm)
    used = rate_limits(scene)
    notes = []
    for field, values in zip(RATE_FIELDS, (used.speed, used.acceleration, used.jerk)):
        if getattr(arm, field) is None or field not in own or values is None:
            continue
        limit, source = own[field]
        over = np.nonzero(values > limit * (1 + 1e-9))[0]  # NaN (the robot gives none) is never exceeded
        if not len(over):
            continue
        unit = SCENE_RATE_UNITS[field]
        given = getattr(arm, field)
        names = arm.urdf_arm.joint_names
        slides = arm.sliding  # a prismatic joint's rates in m/s..., as the scene gives them
        if isinstance(given, list):
            listed = [f"{names[i]} {given[i]:g} > {_rate_shown(limit[i], unit, slides[i])}" for i in over[:3]]
            start = "is above"
        else:
            listed = [f"{names[i]} {_rate_shown(limit[i], unit, slides[i])}" for i in over[:3]]
            start = f"{given:g} {unit} is above"
        notes.append(
            (
                f"arm.{field}",
                f"{start} the robot's own limit for {_joint_span(over)} ({', '.join(listed)}"
                f"{', ...' if len(over) > 3 else ''}: {source}); allowed, but a real robot "
                "could not follow this motion",
            )
        )
    return notes


def _rate_shown(value: float, unit: str, slide: bool) -> str:
    """A joint's rate (SI) as the scene writes it: deg/s... for a revolute joint, m/s... for a prismatic one.

    >>> _rate_shown(np.pi, "deg/s", False), _rate_shown(0.2, "deg/s^2", True)
    ('180 deg/s', '0.2 m/s^2')
    """
    return f"{value:.4g} {unit.replace('deg', 'm')}" if slide else f"{np.degrees(value):.4g} {unit}"


def rate_note_lines(scene: SceneModel) -> list[str]:
    """:func:`rate_notes` as lines ``field.path: message`` (summary.json's ``rate_notes``; [] when none)."""
    return [f"{path}: {message}" for path, message in rate_notes(scene)]


def _joint_span(indices) -> str:
    """``joint 3``, ``joints 1-4`` or ``joints 1, 3, 6`` (1-based) of 0-based indices.

    >>> _joint_span([2]), _joint_span([0, 1, 2, 3]), _joint_span([0, 2, 5])
    ('joint 3', 'joints 1-4', 'joints 1, 3, 6')
    """
    indices = [int(i) + 1 for i in indices]
    if len(indices) == 1:
        return f"joint {indices[0]}"
    if indices == list(range(indices[0], indices[-1] + 1)):
        return f"joints {indices[0]}-{indices[-1]}"
    return "joints " + ", ".join(map(str, indices))
