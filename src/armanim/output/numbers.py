"""THE number formatter of tables, captions and messages.

A value that is zero to the arm's precision prints as ``0`` (kinematics leaves 1e-17 where
the exact answer is 0: ``4.19919e-17`` in a table is noise, not a length), ``-0`` never
prints, and every value has the same number of significant digits. The unit is named by the
caller (a column heading or the words around it).
"""

from __future__ import annotations

import math

PRECISION = 1e-9
"""Of a value's scale (the arm's reach for lengths, a turn for degrees, 1 for a unit
quaternion): smaller values print as 0."""

DIGITS = 6


def number(value: float, scale: float = 1.0, digits: int = DIGITS) -> str:
    """``value`` with ``digits`` significant digits; 0 when it is below PRECISION of ``scale``.

    >>> number(4.19919e-17), number(-1.36821e-17, scale=0.85), number(0.514159265), number(-0.0)
    ('0', '0', '0.514159', '0')
    >>> number(-89.99999999999, scale=360), number(1.5e-6, scale=17), number(float("nan"))
    ('-90', '1.5e-06', 'nan')
    """
    value = float(value)
    if not math.isfinite(value):
        return f"{value}"
    if abs(value) < PRECISION * abs(scale):
        return "0"
    text = f"{value:.{digits}g}"
    return "0" if text in ("-0", "0") else text


def length_unit(arm) -> str:
    """The unit a length of ``arm``'s scene is in, as words around a number name it: ``m`` for a
    URDF arm (its joints have names), ``units`` for an arm of links (scene units).

    >>> import types
    >>> length_unit(types.SimpleNamespace(joint_names=("j1",))), length_unit(types.SimpleNamespace(joint_names=()))
    ('m', 'units')
    """
    return "m" if getattr(arm, "joint_names", ()) else "units"


def apart(*values: float) -> tuple[str, ...]:
    """Values a message compares, each with ``:g``'s six significant digits, or as many more as
    keep different values different, in their order (``[10, 10]`` named two different limits, ``90 deg is outside
    [-90, 90]`` an angle just past 89.99999).

    >>> apart(150.0, -150.0), apart(10.0000001, 10.00000001), apart(89.999995, -90.0, 89.99999)
    (('150', '-150'), ('10.0000001', '10'), ('89.999995', '-90', '89.99999'))
    """
    floats = [float(v) for v in values]
    for digits in range(6, 18):
        texts = tuple(f"{v:.{digits}g}" for v in floats)
        if all((texts[i] == texts[j]) == (floats[i] == floats[j]) for i in range(len(floats)) for j in range(i)):
            return texts
    return tuple(repr(v) for v in floats)
