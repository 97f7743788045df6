"""The values a scene file may hold: bounds, number and name types, the strict base model.

What a single value of a scene may be (finite, positive, an angle within [-360, 360], a
joint rate below :data:`RATE_BOUNDS`, a name that can name a folder) and the largest sizes
a scene may ask for (:data:`LIMITS`, documented in docs/reliability.md). The models that
put them together are in :mod:`armanim.scene.models`; the URDF reader takes its bounds here.
"""

from __future__ import annotations

import re
from typing import Annotated, Literal, Union

from pydantic import BaseModel, ConfigDict, Discriminator, Field, Tag

LIMITS = {
    "links": 64,
    "goals": 1000,
    "obstacles": 1000,
    "path_points": 1000,  # points of one polyline path goal
    "text_characters": 1000,  # characters of one text path goal
    "max_frames_per_goal": 100_000,
    "total_frames": 1_000_000,  # frame 0 + every goal's max_frames_per_goal and hold frames (checks.py)
    "magnitude": 1e9,  # largest |coordinate| or length, scene units (checks.py): squares stay far from overflow
    "smallest": 1e-9,  # smallest link, width, tolerance, clearance, max_step, box edge, capsule radius, influence (checks.py)
    "weight": 1e12,  # largest cost weight (checks.py)
}
"""Largest sizes a scene may ask for (documented in docs/reliability.md); file-level limits
(bytes, values, nesting) are in :mod:`armanim.scene.yamlread`."""

ROBOTS = ("panda", "ur5", "iiwa", "ur5_rail")
"""The bundled robots a scene may name (``arm.robot``), each a folder of ``armanim/arm/robots/``
(URDF, licence, robot.yaml: :mod:`armanim.scene.robots` reads them)."""

MIN_JOINT_STEP = 0.001
"""Smallest ``solver.max_joint_step``, degrees: a joint's whole turn is then at most 540,000
frames, so a planned path too long for the frames left is a miss, never an allocation."""

MIN_DEGREES = 1e-6
"""Smallest ``arm.limit_margin`` and ``solver.orientation_tolerance``, degrees: in radians they
stay normal floats the solvers divide by (5e-324 degrees is 0 radians)."""

MIN_FPS = 0.01
"""Slowest frame rate (one frame per 100 s): ffmpeg takes the rate as a fraction with a
denominator of at most 1001, so far slower rates would reach it as 0."""

NAME_PATTERN = r"^[A-Za-z0-9][A-Za-z0-9_.-]*$"
NAME_MAX = 100
"""A run's name becomes a folder name: one path component, never ``.``/``..`` or hidden (so it
cannot be, or collide with, the hidden staging names beside it), no separators or control
characters, and short enough for any file system."""


def name_problem(name: str) -> str | None:
    """Why ``name`` cannot name a run's folder (what is expected), or None if it can.

    >>> name_problem("notes-arm") is None, name_problem("..")
    (True, "'..' is not a valid name (expected letters, digits, '.', '_' or '-', starting with a letter or digit)")
    """
    if len(name) > NAME_MAX:
        return f"a name of {len(name)} characters is too long (expected at most {NAME_MAX})"
    if not re.fullmatch(NAME_PATTERN, name):
        return (
            f"{name!r} is not a valid name (expected letters, digits, '.', '_' or '-', starting with a letter or digit)"
        )
    if name.casefold() == "index.csv" or name.casefold().endswith("-sweep.csv"):
        return (
            f"{name!r} is the name of a table armanim writes beside the run folders (index.csv, "
            "SCENE-sweep.csv): choose another name"
        )
    return None


Finite = Annotated[float, Field(allow_inf_nan=False)]  # strict: "1" (a string) and true are not numbers
Positive = Annotated[float, Field(gt=0, allow_inf_nan=False)]
NonNegative = Annotated[float, Field(ge=0, allow_inf_nan=False)]
Angle = Annotated[float, Field(ge=-360, le=360, allow_inf_nan=False)]
Vector3 = Annotated[list[Finite], Field(min_length=3, max_length=3)]
Angles3 = Annotated[list[Angle], Field(min_length=3, max_length=3)]  # roll, pitch, yaw: each within [-360, 360]
AxisName = Literal["x", "y", "z"]


class Strict(BaseModel):
    """Base of every scene model: unknown keys rejected, instances frozen, no string-to-number coercion."""

    model_config = ConfigDict(extra="forbid", frozen=True, strict=True)


UrdfName = Annotated[str, Field(min_length=1, max_length=200)]
LinkPair = Annotated[list[UrdfName], Field(min_length=2, max_length=2)]

RATE_BOUNDS = {"max_joint_speed": 1e5, "max_joint_acceleration": 1e7, "max_joint_jerk": 1e10}
"""Largest ``arm.max_joint_speed`` (deg/s: about 280 turns a second), ``max_joint_acceleration``
(deg/s^2) and ``max_joint_jerk`` (deg/s^3) a scene may give: far above any arm's (a Panda's
are 150, 1,150 and 573,000), low enough that the clock's arithmetic stays far from overflow."""


def _rate_form(value) -> str:
    """Which form of a joint rate was written: a list (one per joint), or one number."""
    return "list[float]" if isinstance(value, list) else "float"


def _rate_or_robot_form(value) -> str:
    """As :func:`_rate_form`, or ``robot`` (any string: the only word allowed)."""
    return "literal[robot]" if isinstance(value, str) else _rate_form(value)


def joint_rate(name: str, robot: bool = False):
    """A joint rate field's type: one number > 0 for every joint, or a list with one per joint,
    each at most :data:`RATE_BOUNDS`; with ``robot``, also the word ``robot`` (the bundled
    robot's published value). The tags name the forms as pydantic names union branches, so
    that messages name the field itself (``arm.max_joint_speed[2]``)."""
    rate = Annotated[float, Field(gt=0, le=RATE_BOUNDS[name], allow_inf_nan=False)]
    forms = [
        Annotated[rate, Tag("float")],
        Annotated[Annotated[list[rate], Field(max_length=int(LIMITS["links"]))], Tag("list[float]")],
    ]
    if robot:
        forms.append(Annotated[Literal["robot"], Tag("literal[robot]")])
    return Annotated[Union[tuple(forms)], Discriminator(_rate_or_robot_form if robot else _rate_form)]  # noqa: UP007


Side = Annotated[int, Field(ge=16, le=7680)]
"""A picture's side in pixels (``render.size``)."""
