"""Plain YAML scalars as a scene reads them: tags resolved, values constructed safely.

Numbers are read as YAML 1.2 reads them (``1e-3`` is a float), only the standard tags
are constructed, and an integer too large for a float is reported instead of built.
"""

from __future__ import annotations

import re

import yaml

MAX_FLOAT_DIGITS = 309  # an integer with more digits is beyond a float (1.8e308)

STANDARD_TAGS = {"tag:yaml.org,2002:" + t for t in ("map", "seq", "str", "int", "float", "bool", "null")}
MERGE_TAG = "tag:yaml.org,2002:merge"
_DECIMAL = re.compile(r"[-+]?(?:0|[1-9][0-9]*)")  # the common ints and floats, read without
_DECIMAL_FLOAT = re.compile(r"[-+]?[0-9]+\.[0-9]*(?:[eE][-+]?[0-9]+)?|[-+]?[0-9]+[eE][-+]?[0-9]+")  # PyYAML's detour


class SceneLoader(yaml.SafeLoader):
    """PyYAML's safe loader, reading ``1e-3`` as a number as YAML 1.2 does
    (YAML 1.1 wants a dot: ``1.0e-3``), since scenes and the docs write ``1e3``."""


SceneLoader.add_implicit_resolver(
    "tag:yaml.org,2002:float",
    re.compile(r"^[-+]?(?:[0-9][0-9_]*)(?:\.[0-9_]*)?[eE][-+]?[0-9]+$"),
    list("-+0123456789"),
)


class TooLarge(float):
    """Stand-in (infinity) for an integer too large for a float; already reported by the reader,
    so the loader drops the model's second message about it."""


_TOO_LARGE = TooLarge("inf")


def short_tag(tag: str) -> str:
    """A YAML tag as it is written in a file: ``tag:yaml.org,2002:str`` -> ``!!str``."""
    return tag.replace("tag:yaml.org,2002:", "!!")


class ScalarReader:
    """Tags and values of scalar events (the tags of short plain values are cached)."""

    def __init__(self) -> None:
        self._loader = SceneLoader("")  # resolver and constructor of plain scalars
        self._tags: dict[tuple[str, bool], str] = {}  # resolved tags of short plain values

    def tag(self, event: yaml.ScalarEvent) -> str:
        """The scalar's explicit tag, else the one its plain text resolves to."""
        if event.tag is not None and event.tag != "!":
            return event.tag
        key = (event.value, event.implicit[0])
        tag = self._tags.get(key)
        if tag is None:
            tag = self._loader.resolve(yaml.ScalarNode, event.value, event.implicit)
            if len(self._tags) < 4096 and len(event.value) < 64:
                self._tags[key] = tag
        return tag

    def value(self, event: yaml.ScalarEvent, tag: str) -> tuple[object, str | None]:
        """``(value, problem)`` of a scalar with a standard ``tag``.

        ``problem`` is None, or says why the value cannot be read; the value is then
        None, or :class:`TooLarge` for an integer beyond a float.
        """
        value = event.value
        if tag == "tag:yaml.org,2002:str":
            return value, None
        if tag == "tag:yaml.org,2002:int":
            digits = sum(c.isdigit() for c in value) if len(value) > MAX_FLOAT_DIGITS else 0
            if digits > MAX_FLOAT_DIGITS:
                return (
                    _TOO_LARGE,
                    f"a {digits}-digit integer is too large (numbers must be finite: at most about 1.8e308)",
                )
            if _DECIMAL.fullmatch(value):
                return int(value), None
        elif tag == "tag:yaml.org,2002:float" and _DECIMAL_FLOAT.fullmatch(value):
            return float(value), None
        node = yaml.ScalarNode(tag, event.value, event.start_mark, event.end_mark, event.style)
        try:
            return self._loader.construct_object(node, deep=True), None
        except (ValueError, OverflowError, yaml.YAMLError) as exc:
            return None, f"cannot read {short_tag(tag)} value: {exc}"
