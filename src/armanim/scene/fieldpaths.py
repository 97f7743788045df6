"""Field paths such as ``arm.limits[2]`` and the YAML lines they came from.

The reader (:mod:`armanim.scene.yamlread`) records the line of every path it reads;
the loader names pydantic's errors by the same paths and finds their lines here.
"""

from __future__ import annotations

from dataclasses import dataclass

from armanim.errors import Diagnostic


@dataclass(frozen=True)
class YamlDocument:
    """Plain data of a YAML file and the 1-based line of each field path."""

    data: object
    lines: dict[str, int]
    problems: tuple[Diagnostic, ...] = ()

    def line_of(self, path: str) -> int | None:
        """Line of ``path`` or, failing that, of its nearest parent that has one."""
        while path:
            if path in self.lines:
                return self.lines[path]
            cut = max(path.rfind("."), path.rfind("["))
            path = path[:cut] if cut > 0 else ""
        return self.lines.get("")


def join_path(parent: str, key: str | int) -> str:
    """``arm`` + ``limits`` -> ``arm.limits``; ``arm.limits`` + 2 -> ``arm.limits[2]``."""
    if isinstance(key, int):
        return f"{parent}[{key}]"
    return f"{parent}.{key}" if parent else str(key)


def abbreviate(path: str, keep: int = 40) -> str:
    """A field path cut to about ``keep`` characters (deeply nested paths are unreadable).

    >>> abbreviate("a" + "[0]" * 30)
    'a[0][0][0][0][0][0][0][0][0][0][0][0][0]...(31 levels)'
    """
    if len(path) <= keep:
        return path
    levels = path.count("[") + path.count(".") + 1 - path.startswith("[")
    return f"{path[:keep]}...({levels} levels)"
