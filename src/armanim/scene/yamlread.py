"""Safe YAML reading that remembers where every value came from.

The document is composed into nodes by PyYAML's safe loader (nothing is ever
constructed from a ``!!python/...`` tag: such tags are reported), then turned into
plain Python data by hand so that each field path gets its line, duplicate keys
are reported with both lines, and alias expansion is bounded.
"""

from __future__ import annotations

from dataclasses import dataclass

import re

import yaml

from armanim.errors import Diagnostic, SceneError

MAX_FILE_BYTES = 1_000_000
MAX_NODES = 200_000  # values after alias expansion: stops "billion laughs" early
MAX_DEPTH = 64

class SceneLoader(yaml.SafeLoader):
    """PyYAML's safe loader, reading ``1e-3`` as a number as YAML 1.2 does
    (YAML 1.1 wants a dot: ``1.0e-3``), since scenes and the docs write ``1e3``."""


SceneLoader.add_implicit_resolver(
    "tag:yaml.org,2002:float",
    re.compile(r"^[-+]?(?:[0-9][0-9_]*)(?:\.[0-9_]*)?[eE][-+]?[0-9]+$"),
    list("-+0123456789"),
)

_STANDARD_TAGS = {
    "tag:yaml.org,2002:" + t for t in ("map", "seq", "str", "int", "float", "bool", "null")
}


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


class _Builder:
    def __init__(self, file: str):
        self.file = file
        self.lines: dict[str, int] = {}
        self.problems: list[Diagnostic] = []
        self.nodes = 0
        self._scalar = SceneLoader("")

    def build(self, node: yaml.Node, path: str, depth: int = 0):
        self.nodes += 1
        if self.nodes > MAX_NODES:
            raise SceneError(self.file, [Diagnostic(path, f"the document expands to more than {MAX_NODES} values (alias bomb?); keep scenes small and without deep aliases", node.start_mark.line + 1)])
        if depth > MAX_DEPTH:
            raise SceneError(self.file, [Diagnostic(path, f"nesting deeper than {MAX_DEPTH} levels (expected a flat scene as in docs/scene-format.md)", node.start_mark.line + 1)])
        self.lines.setdefault(path, node.start_mark.line + 1)
        if node.tag not in _STANDARD_TAGS:
            tag = node.tag.replace("tag:yaml.org,2002:", "!!")
            self.problems.append(Diagnostic(path, f"unsupported YAML tag {tag!r}, not executed (expected plain values: numbers, strings, lists, mappings)", node.start_mark.line + 1))
            return None
        if isinstance(node, yaml.MappingNode):
            return self._mapping(node, path, depth)
        if isinstance(node, yaml.SequenceNode):
            return [self.build(item, join_path(path, i), depth + 1) for i, item in enumerate(node.value)]
        return self._scalar.construct_object(node, deep=True)

    def _mapping(self, node: yaml.MappingNode, path: str, depth: int) -> dict:
        result: dict = {}
        first_line: dict = {}
        for key_node, value_node in node.value:
            line = key_node.start_mark.line + 1
            if not isinstance(key_node, yaml.ScalarNode) or key_node.tag not in _STANDARD_TAGS:
                self.problems.append(Diagnostic(path, "a mapping key must be a plain name", line))
                continue
            key = self._scalar.construct_object(key_node)
            if not isinstance(key, str):
                key = str(key)
            child = join_path(path, key)
            if key in first_line:
                self.problems.append(Diagnostic(child, f"duplicate key {key!r}: first on line {first_line[key]}, again on line {line} (keep one)", line))
                continue
            first_line[key] = line
            self.lines[child] = line
            result[key] = self.build(value_node, child, depth + 1)
        return result


def read_yaml(text: str, file: str) -> YamlDocument:
    """Parse YAML text into plain data with line numbers.

    Duplicate keys and unsupported tags are returned in ``problems`` (the first
    value is kept, a tagged value becomes null) so that validation can go on and
    report everything at once.

    Raises
    ------
    SceneError
        Broken YAML, an empty document, several documents, alias bombs or too deep
        nesting.
    """
    try:
        root = yaml.compose(text, Loader=SceneLoader)
    except yaml.composer.ComposerError as exc:
        line = exc.problem_mark.line + 1 if exc.problem_mark else None
        raise SceneError(file, [Diagnostic("", f"{exc.problem} (a scene is one YAML document)", line)]) from None
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        problem = getattr(exc, "problem", None) or str(exc)
        raise SceneError(file, [Diagnostic("", f"not valid YAML: {problem}", mark.line + 1 if mark else None)]) from None
    except RecursionError:
        raise SceneError(file, [Diagnostic("", f"nesting deeper than {MAX_DEPTH} levels")]) from None
    if root is None:
        raise SceneError(file, [Diagnostic("", "the file is empty (expected a scene: see docs/scene-format.md)", 1)])
    builder = _Builder(file)
    data = builder.build(root, "")
    return YamlDocument(data=data, lines=builder.lines, problems=tuple(builder.problems))
