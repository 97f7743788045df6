"""Plain data from a stream of YAML events, bounded in size and depth.

The builder behind :func:`armanim.scene.yamlread.read_yaml` (that module says what
it guarantees): an explicit stack instead of recursion, the line of every field path,
duplicate keys and non-standard tags reported instead of constructed.
"""

from __future__ import annotations

import copy

import yaml

from armanim.errors import Diagnostic, SceneError
from armanim.scene.fieldpaths import abbreviate, join_path
from armanim.scene.yamlscalars import MERGE_TAG, STANDARD_TAGS, ScalarReader, short_tag


def event_line(event_or_mark) -> int | None:
    """1-based line where a YAML event (or mark) starts; None where it has no mark."""
    mark = getattr(event_or_mark, "start_mark", event_or_mark)
    return mark.line + 1 if mark is not None else None


def _parsed_line(event) -> int:
    """:func:`event_line` of an event the parser made (it always has its mark)."""
    line = event_line(event)
    assert line is not None, "a parsed event has its mark"
    return line


class _Container:
    """An open list or mapping on the builder's stack."""

    __slots__ = (
        "kind",
        "path",
        "value",
        "line",
        "anchor",
        "size",
        "depth",
        "key",
        "key_line",
        "skip_key",
        "first_line",
        "discard",
        "is_key",
    )

    def __init__(self, kind: str, path: str, line: int | None, anchor: str | None, discard: bool):
        self.kind = kind  # "seq" or "map"
        self.path = path
        self.value: list[object] | dict[str, object] = [] if kind == "seq" else {}
        self.line = line
        self.anchor = anchor
        self.size = 1  # values inside, itself included (for aliases to it)
        self.depth = 1  # levels of nesting inside, itself included
        self.key: str | None = None  # mapping: the key whose value comes next
        self.key_line: int | None = None
        self.skip_key = False  # mapping: the pending key was rejected, drop its value
        self.first_line: dict[str, int | None] = {}
        self.discard = discard  # a collection with an unsupported tag: content read, then dropped
        self.is_key = False  # a list or mapping used as a mapping key (rejected)


def too_deep(max_depth: int) -> str:
    """The message for a document nested deeper than ``max_depth`` levels.

    >>> too_deep(64)
    'nesting deeper than 64 levels (expected a flat scene as in docs/scene-format.md)'
    """
    return f"nesting deeper than {max_depth} levels (expected a flat scene as in docs/scene-format.md)"


class EventBuilder:
    """Plain data from YAML events, at most ``max_nodes`` values and ``max_depth`` levels deep."""

    def __init__(self, file: str, max_nodes: int, max_depth: int):
        self.file = file
        self.max_nodes, self.max_depth = max_nodes, max_depth
        self.lines: dict[str, int] = {}
        self.problems: list[Diagnostic] = []
        self.nodes = 0
        self.stack: list[_Container] = []
        self.anchors: dict[str, tuple[object, int, int]] = {}  # anchor -> (value, size, depth)
        self.open_anchors: set[str] = set()
        self.root: object = None
        self.have_root = False
        self._scalars = ScalarReader()

    # ---------------------------------------------------------------- limits

    def _fail(self, path: str, message: str, line: int | None):
        raise SceneError(self.file, [Diagnostic(path, message, line)])

    def _count(self, size: int, depth: int, path: str, line: int | None) -> None:
        self.nodes += size
        if self.nodes > self.max_nodes:
            self._fail(
                path,
                f"the document expands to more than {self.max_nodes:,} values (an alias bomb, or far more "
                "data than a scene needs; see the limits in docs/reliability.md)",
                line,
            )
        if len(self.stack) + depth > self.max_depth + 1:
            self._fail(abbreviate(path), too_deep(self.max_depth), line)

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
        if top.skip_key or top.key is None:  # a mapping's value comes after its key
            return None
        return join_path(top.path, top.key)

    def _is_key_position(self) -> bool:
        return (
            bool(self.stack)
            and self.stack[-1].kind == "map"
            and self.stack[-1].key is None
            and not self.stack[-1].skip_key
        )

    def _place(self, value, size: int, depth: int) -> None:
        """Put a finished value into its container (or make it the root)."""
        if not self.stack:
            self.root, self.have_root = value, True
            return
        top = self.stack[-1]
        top.size += size
        top.depth = max(top.depth, depth + 1)
        if isinstance(top.value, list):
            if not top.discard:
                top.value.append(value)
            return
        if not top.discard and not top.skip_key and top.key is not None:
            top.value[top.key] = value
        top.key, top.skip_key = None, False

    def _key(self, event, value, size: int = 1) -> None:
        """A mapping key has been read: check it, remember where it is."""
        top = self.stack[-1]
        top.size += size
        line = _parsed_line(event)
        if top.discard:
            top.skip_key = True
            return
        if value is _REJECTED_KEY:
            top.skip_key = True
            return
        key = value if isinstance(value, str) else str(value)
        child = join_path(top.path, key)
        if key in top.first_line:
            self.problems.append(
                Diagnostic(
                    child,
                    f"duplicate key {key!r}: first on line {top.first_line[key]}, again on line {line} (keep one)",
                    line,
                )
            )
            top.skip_key = True
            return
        top.first_line[key] = line
        self.lines[child] = line
        top.key, top.key_line = key, line

    # ---------------------------------------------------------------- events

    def feed(self, event) -> None:
        """Take the next scalar, collection start or end, or alias of the document."""
        if isinstance(event, yaml.ScalarEvent):
            self._scalar(event)
        elif isinstance(event, (yaml.SequenceStartEvent, yaml.MappingStartEvent)):
            self._start(event)
        elif isinstance(event, (yaml.SequenceEndEvent, yaml.MappingEndEvent)):
            self._end()
        elif isinstance(event, yaml.AliasEvent):
            self._alias(event)

    def _scalar(self, event) -> None:
        line = _parsed_line(event)
        key_position = self._is_key_position()
        path = self.stack[-1].path if key_position else self._child_path(line)
        self._count(1, 0, path or "", line)
        if key_position:
            where = self.stack[-1].path
            tag = self._scalars.tag(event)
            key: object = _REJECTED_KEY
            if tag == MERGE_TAG:
                self.problems.append(
                    Diagnostic(where, "merge keys (<<) are not supported (write the keys out in full)", line)
                )
            elif tag not in STANDARD_TAGS:
                self.problems.append(
                    Diagnostic(where, f"a mapping key must be a plain name (got a {short_tag(tag)!r} value)", line)
                )
            else:
                key = self._construct(event, tag, where, line)
            self._key(event, key)
            if event.anchor:
                self.anchors[event.anchor] = (key if key is not _REJECTED_KEY else None, 1, 0)
            return
        value = None
        if path is not None:
            self.lines.setdefault(path, line)
            tag = self._scalars.tag(event)
            if tag not in STANDARD_TAGS:
                self.problems.append(
                    Diagnostic(
                        path,
                        f"unsupported YAML tag {short_tag(tag)!r}, not executed (expected plain values: numbers, strings, lists, mappings)",
                        line,
                    )
                )
            else:
                value = self._construct(event, tag, path, line)
        if event.anchor:
            self.anchors[event.anchor] = (value, 1, 0)
        self._place(value, 1, 0)

    def _construct(self, event, tag: str, path: str, line: int | None):
        value, problem = self._scalars.value(event, tag)
        if problem is not None:
            self.problems.append(Diagnostic(path, problem, line))
        return value

    def _start(self, event) -> None:
        line = _parsed_line(event)
        key_position = self._is_key_position()
        path = self.stack[-1].path if key_position else self._child_path(line)
        self._count(1, 1, path or "", line)
        kind = "seq" if isinstance(event, yaml.SequenceStartEvent) else "map"
        discard = path is None or key_position
        if key_position:
            self.problems.append(
                Diagnostic(
                    self.stack[-1].path,
                    f"a mapping key must be a plain name (got a {'list' if kind == 'seq' else 'mapping'})",
                    line,
                )
            )
        elif path is not None:
            self.lines.setdefault(path, line)
            standard = "tag:yaml.org,2002:" + kind
            if event.tag not in (None, "!", standard):
                self.problems.append(
                    Diagnostic(
                        path,
                        f"unsupported YAML tag {short_tag(event.tag)!r}, not executed (expected plain values: numbers, strings, lists, mappings)",
                        line,
                    )
                )
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
        line = _parsed_line(event)
        key_position = self._is_key_position()
        path = self.stack[-1].path if key_position else self._child_path(line)
        if event.anchor in self.open_anchors:
            self._fail(
                path or "",
                f"the alias *{event.anchor} refers to a value that contains it (a recursive structure cannot be a scene)",
                line,
            )
        if event.anchor not in self.anchors:
            self._fail(
                path or "", f"found undefined alias *{event.anchor} (define it with &{event.anchor} first)", line
            )
        value, size, depth = self.anchors[event.anchor]
        self._count(size, depth, path or "", line)
        if key_position:
            if isinstance(value, (list, dict)) or value is None:
                self.problems.append(Diagnostic(self.stack[-1].path, "a mapping key must be a plain name", line))
                self._key(event, _REJECTED_KEY, size)
            else:
                self._key(event, value, size)
            return
        if path is not None:
            self.lines.setdefault(path, line)
        self._place(copy.deepcopy(value) if isinstance(value, (list, dict)) else value, size, depth)


class _Rejected:
    def __repr__(self) -> str:
        return "<rejected key>"


_REJECTED_KEY = _Rejected()
