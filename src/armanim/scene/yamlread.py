"""Safe YAML reading that remembers where every value came from.

The text is read as a stream of YAML *events* (libyaml's C parser when PyYAML has
it, else PyYAML's pure-Python one) and turned into plain Python data by hand, with
an explicit stack instead of recursion. That gives, in one pass and before any
large structure is built:

- the line of every field path, and duplicate keys reported with both lines;
- nothing ever constructed from a ``!!python/...`` (or any non-standard) tag: such
  tags are reported, their value becomes null;
- bounded work and memory for hostile files: at most :data:`MAX_NODES` values
  (counted after alias expansion, so a "billion laughs" alias bomb stops after a few
  thousand events), at most :data:`MAX_DEPTH` levels of nesting (``[[[[...]]]]``
  10,000 deep stops at level 65, never reaching a RecursionError), no alias that
  refers to its own value, integers too large for a float reported as such.

The file size limit (:data:`MAX_FILE_BYTES`) is checked by the loader before the text
is read. Limits on the scene's contents (links, goals, obstacles, frames) live in
:data:`armanim.scene.models.LIMITS`.
"""

from __future__ import annotations

import copy
import re
from dataclasses import dataclass

import yaml

from armanim.errors import Diagnostic, SceneError

MAX_FILE_BYTES = 1_000_000
MAX_NODES = 25_000  # keys and values after alias expansion (the largest valid scene has about 19,000)
MAX_DEPTH = 64  # nested lists / mappings (a valid scene nests 4 deep)
MAX_FLOAT_DIGITS = 309  # an integer with more digits is beyond a float (1.8e308)


class SceneLoader(yaml.SafeLoader):
    """PyYAML's safe loader, reading ``1e-3`` as a number as YAML 1.2 does
    (YAML 1.1 wants a dot: ``1.0e-3``), since scenes and the docs write ``1e3``."""


SceneLoader.add_implicit_resolver(
    "tag:yaml.org,2002:float",
    re.compile(r"^[-+]?(?:[0-9][0-9_]*)(?:\.[0-9_]*)?[eE][-+]?[0-9]+$"),
    list("-+0123456789"),
)

_EventParser = getattr(yaml, "CSafeLoader", None) if getattr(yaml, "__with_libyaml__", False) else None

_STANDARD_TAGS = {
    "tag:yaml.org,2002:" + t for t in ("map", "seq", "str", "int", "float", "bool", "null")
}
_MERGE_TAG = "tag:yaml.org,2002:merge"
_DECIMAL = re.compile(r"[-+]?(?:0|[1-9][0-9]*)")  # the common ints and floats, read without
_DECIMAL_FLOAT = re.compile(r"[-+]?[0-9]+\.[0-9]*(?:[eE][-+]?[0-9]+)?|[-+]?[0-9]+[eE][-+]?[0-9]+")  # PyYAML's detour


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


def _line(event_or_mark) -> int | None:
    mark = getattr(event_or_mark, "start_mark", event_or_mark)
    return mark.line + 1 if mark is not None else None


def _short_tag(tag: str) -> str:
    return tag.replace("tag:yaml.org,2002:", "!!")


class _Container:
    """An open list or mapping on the builder's stack."""

    __slots__ = ("kind", "path", "value", "line", "anchor", "size", "depth", "key", "key_line", "skip_key",
                 "first_line", "discard", "is_key")

    def __init__(self, kind: str, path: str, line: int | None, anchor: str | None, discard: bool):
        self.kind = kind  # "seq" or "map"
        self.path = path
        self.value: list | dict = [] if kind == "seq" else {}
        self.line = line
        self.anchor = anchor
        self.size = 1  # values inside, itself included (for aliases to it)
        self.depth = 1  # levels of nesting inside, itself included
        self.key = None  # mapping: the key whose value comes next
        self.key_line = None
        self.skip_key = False  # mapping: the pending key was rejected, drop its value
        self.first_line: dict[str, int] = {}
        self.discard = discard  # a collection with an unsupported tag: content read, then dropped
        self.is_key = False  # a list or mapping used as a mapping key (rejected)


class _Builder:
    """Plain data from YAML events, bounded in size and depth (see the module docstring)."""

    def __init__(self, file: str):
        self.file = file
        self.lines: dict[str, int] = {}
        self.problems: list[Diagnostic] = []
        self.nodes = 0
        self.stack: list[_Container] = []
        self.anchors: dict[str, tuple[object, int, int]] = {}  # anchor -> (value, size, depth)
        self.open_anchors: set[str] = set()
        self.root: object = None
        self.have_root = False
        self._loader = SceneLoader("")  # resolver and constructor of plain scalars
        self._tags: dict[tuple[str, bool], str] = {}  # resolved tags of short plain values

    # ---------------------------------------------------------------- limits

    def _fail(self, path: str, message: str, line: int | None):
        raise SceneError(self.file, [Diagnostic(path, message, line)])

    def _count(self, size: int, depth: int, path: str, line: int | None) -> None:
        self.nodes += size
        if self.nodes > MAX_NODES:
            self._fail(path, f"the document expands to more than {MAX_NODES:,} values (an alias bomb, or far more "
                             "data than a scene needs; see the limits in docs/reliability.md)", line)
        if len(self.stack) + depth > MAX_DEPTH + 1:
            self._fail(abbreviate(path), f"nesting deeper than {MAX_DEPTH} levels (expected a flat scene as in docs/scene-format.md)", line)

    # ---------------------------------------------------------------- where values go

    def _child_path(self, line: int | None) -> str | None:
        """Path of the next value in the innermost container (None: the value is dropped)."""
        if not self.stack:
            return ""
        top = self.stack[-1]
        if top.discard:
            return None
        if top.kind == "seq":
            return join_path(top.path, len(top.value))
        if top.skip_key:
            return None
        return join_path(top.path, top.key)

    def _is_key_position(self) -> bool:
        return bool(self.stack) and self.stack[-1].kind == "map" and self.stack[-1].key is None and not self.stack[-1].skip_key

    def _place(self, value, size: int, depth: int) -> None:
        """Put a finished value into its container (or make it the root)."""
        if not self.stack:
            self.root, self.have_root = value, True
            return
        top = self.stack[-1]
        top.size += size
        top.depth = max(top.depth, depth + 1)
        if top.kind == "seq":
            if not top.discard:
                top.value.append(value)
            return
        if not top.discard and not top.skip_key:
            top.value[top.key] = value
        top.key, top.skip_key = None, False

    def _key(self, event, value, size: int = 1) -> None:
        """A mapping key has been read: check it, remember where it is."""
        top = self.stack[-1]
        top.size += size
        line = _line(event)
        if top.discard:
            top.skip_key = True
            return
        if value is _REJECTED_KEY:
            top.skip_key = True
            return
        key = value if isinstance(value, str) else str(value)
        child = join_path(top.path, key)
        if key in top.first_line:
            self.problems.append(Diagnostic(child, f"duplicate key {key!r}: first on line {top.first_line[key]}, again on line {line} (keep one)", line))
            top.skip_key = True
            return
        top.first_line[key] = line
        self.lines[child] = line
        top.key, top.key_line = key, line

    # ---------------------------------------------------------------- events

    def feed(self, event) -> None:
        if isinstance(event, yaml.ScalarEvent):
            self._scalar(event)
        elif isinstance(event, (yaml.SequenceStartEvent, yaml.MappingStartEvent)):
            self._start(event)
        elif isinstance(event, (yaml.SequenceEndEvent, yaml.MappingEndEvent)):
            self._end()
        elif isinstance(event, yaml.AliasEvent):
            self._alias(event)

    def _scalar(self, event) -> None:
        line = _line(event)
        key_position = self._is_key_position()
        path = self.stack[-1].path if key_position else self._child_path(line)
        self._count(1, 0, path or "", line)
        if key_position:
            tag = self._scalar_tag(event)
            if tag == _MERGE_TAG:
                self.problems.append(Diagnostic(path, "merge keys (<<) are not supported (write the keys out in full)", line))
                value = _REJECTED_KEY
            elif tag not in _STANDARD_TAGS:
                self.problems.append(Diagnostic(path, f"a mapping key must be a plain name (got a {_short_tag(tag)!r} value)", line))
                value = _REJECTED_KEY
            else:
                value = self._construct(event, tag, path, line)
            self._key(event, value)
            if event.anchor:
                self.anchors[event.anchor] = (value if value is not _REJECTED_KEY else None, 1, 0)
            return
        value = None
        if path is not None:
            self.lines.setdefault(path, line)
            tag = self._scalar_tag(event)
            if tag not in _STANDARD_TAGS:
                self.problems.append(Diagnostic(path, f"unsupported YAML tag {_short_tag(tag)!r}, not executed (expected plain values: numbers, strings, lists, mappings)", line))
            else:
                value = self._construct(event, tag, path, line)
        if event.anchor:
            self.anchors[event.anchor] = (value, 1, 0)
        self._place(value, 1, 0)

    def _scalar_tag(self, event) -> str:
        if event.tag is not None and event.tag != "!":
            return event.tag
        key = (event.value, event.implicit[0])
        tag = self._tags.get(key)
        if tag is None:
            tag = self._loader.resolve(yaml.ScalarNode, event.value, event.implicit)
            if len(self._tags) < 4096 and len(event.value) < 64:
                self._tags[key] = tag
        return tag

    def _construct(self, event, tag: str, path: str, line: int | None):
        value = event.value
        if tag == "tag:yaml.org,2002:str":
            return value
        if tag == "tag:yaml.org,2002:int":
            digits = sum(c.isdigit() for c in value) if len(value) > MAX_FLOAT_DIGITS else 0
            if digits > MAX_FLOAT_DIGITS:
                self.problems.append(Diagnostic(path, f"a {digits}-digit integer is too large (numbers must be finite: at most about 1.8e308)", line))
                return _TOO_LARGE
            if _DECIMAL.fullmatch(value):
                return int(value)
        elif tag == "tag:yaml.org,2002:float" and _DECIMAL_FLOAT.fullmatch(value):
            return float(value)
        node = yaml.ScalarNode(tag, event.value, event.start_mark, event.end_mark, event.style)
        try:
            return self._loader.construct_object(node, deep=True)
        except (ValueError, OverflowError, yaml.YAMLError) as exc:
            self.problems.append(Diagnostic(path, f"cannot read {_short_tag(tag)} value: {exc}", line))
            return None

    def _start(self, event) -> None:
        line = _line(event)
        key_position = self._is_key_position()
        path = self.stack[-1].path if key_position else self._child_path(line)
        self._count(1, 1, path or "", line)
        kind = "seq" if isinstance(event, yaml.SequenceStartEvent) else "map"
        discard = path is None or key_position
        if key_position:
            self.problems.append(Diagnostic(path, f"a mapping key must be a plain name (got a {'list' if kind == 'seq' else 'mapping'})", line))
        elif path is not None:
            self.lines.setdefault(path, line)
            standard = "tag:yaml.org,2002:" + kind
            if event.tag not in (None, "!", standard):
                self.problems.append(Diagnostic(path, f"unsupported YAML tag {_short_tag(event.tag)!r}, not executed (expected plain values: numbers, strings, lists, mappings)", line))
                discard = True
        container = _Container(kind, path or "", line, event.anchor, discard)
        container.is_key = key_position
        if event.anchor:
            self.open_anchors.add(event.anchor)
        self.stack.append(container)

    def _end(self) -> None:
        done = self.stack.pop()
        if done.anchor:
            self.open_anchors.discard(done.anchor)
        value = None if done.discard else done.value
        if done.anchor:
            self.anchors[done.anchor] = (value, done.size, done.depth)
        if done.is_key:
            self._key_done(done)
        else:
            self._place(value, done.size, done.depth)

    def _key_done(self, done: _Container) -> None:
        top = self.stack[-1]
        top.size += done.size
        top.depth = max(top.depth, done.depth + 1)
        top.skip_key = True

    def _alias(self, event) -> None:
        line = _line(event)
        key_position = self._is_key_position()
        path = self.stack[-1].path if key_position else self._child_path(line)
        if event.anchor in self.open_anchors:
            self._fail(path or "", f"the alias *{event.anchor} refers to a value that contains it (a recursive structure cannot be a scene)", line)
        if event.anchor not in self.anchors:
            self._fail(path or "", f"found undefined alias *{event.anchor} (define it with &{event.anchor} first)", line)
        value, size, depth = self.anchors[event.anchor]
        self._count(size, depth, path or "", line)
        if key_position:
            if isinstance(value, (list, dict)) or value is None:
                self.problems.append(Diagnostic(path, "a mapping key must be a plain name", line))
                self._key(event, _REJECTED_KEY, size)
            else:
                self._key(event, value, size)
            return
        if path is not None:
            self.lines.setdefault(path, line)
        self._place(copy.deepcopy(value) if isinstance(value, (list, dict)) else value, size, depth)


class TooLarge(float):
    """Stand-in (infinity) for an integer too large for a float; already reported by the reader,
    so the loader drops the model's second message about it."""


class _Rejected:
    def __repr__(self) -> str:
        return "<rejected key>"


_REJECTED_KEY = _Rejected()
_TOO_LARGE = TooLarge("inf")


def _yaml_error(file: str, text: str, exc: yaml.YAMLError) -> SceneError:
    """A SceneError for PyYAML's or libyaml's parse error, with its line and no internals."""
    mark = getattr(exc, "problem_mark", None) or getattr(exc, "context_mark", None)
    line = mark.line + 1 if mark is not None else None
    if isinstance(exc, yaml.reader.ReaderError):
        line = text[: exc.position].count("\n") + 1
        char = chr(exc.character) if isinstance(exc.character, int) else exc.character
        return SceneError(file, [Diagnostic("", f"character {char!r} is not allowed in YAML (control characters must be removed)", line)])
    problem = getattr(exc, "problem", None) or str(exc).splitlines()[0]
    context = getattr(exc, "context", None)
    if context and context not in problem:
        problem = f"{problem} {context}"
    lines = text.splitlines()
    if line is not None and 0 < line <= len(lines) and "\t" in lines[line - 1]:
        problem += f" (line {line} has a tab character: YAML indentation must use spaces, never tabs)"
    return SceneError(file, [Diagnostic("", f"not valid YAML: {problem}", line)])


def read_yaml(text: str, file: str) -> YamlDocument:
    """Parse YAML text into plain data with line numbers.

    Duplicate keys and unsupported tags are returned in ``problems`` (the first
    value is kept, a tagged value becomes null) so that validation can go on and
    report everything at once.

    Raises
    ------
    SceneError
        Broken YAML, an empty document, several documents, alias bombs, too many
        values or too deep nesting (found while reading: no large structure is built).
    """
    builder = _Builder(file)
    documents = 0
    parser = (_EventParser or SceneLoader)(text)
    try:
        while parser.check_event():
            event = parser.get_event()
            if isinstance(event, yaml.DocumentStartEvent):
                documents += 1
                if documents > 1:
                    raise SceneError(file, [Diagnostic("", "but found another document (a scene is one YAML document)", _line(event))])
            else:
                builder.feed(event)
    except yaml.YAMLError as exc:
        raise _yaml_error(file, text, exc) from None
    except RecursionError:  # pragma: no cover  (the builder has no recursion; kept as a last guard)
        raise SceneError(file, [Diagnostic("", f"nesting deeper than {MAX_DEPTH} levels")]) from None
    finally:
        dispose = getattr(parser, "dispose", None)
        if dispose is not None:
            dispose()
    if not builder.have_root:
        raise SceneError(file, [Diagnostic("", "the file is empty (expected a scene: see docs/scene-format.md)", 1)])
    return YamlDocument(data=builder.root, lines=builder.lines, problems=tuple(builder.problems))

