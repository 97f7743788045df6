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

The events are turned into data by :mod:`armanim.scene.yamlevents`, their scalars by
:mod:`armanim.scene.yamlscalars`; field paths and their lines are kept as in
:mod:`armanim.scene.fieldpaths`.
"""

from __future__ import annotations

import yaml

from armanim.errors import Diagnostic, SceneError
from armanim.scene.fieldpaths import YamlDocument
from armanim.scene.yamlevents import EventBuilder, event_line, too_deep
from armanim.scene.yamlscalars import SceneLoader

MAX_FILE_BYTES = 1_000_000
MAX_NODES = 25_000  # keys and values after alias expansion (the largest valid scene has about 19,000)
MAX_DEPTH = 64  # nested lists / mappings (a valid scene nests 4 deep)

_EventParser = getattr(yaml, "CSafeLoader", None) if getattr(yaml, "__with_libyaml__", False) else None


def _yaml_error(file: str, text: str, exc: yaml.YAMLError) -> SceneError:
    """A SceneError for PyYAML's or libyaml's parse error, with its line and no internals."""
    mark = getattr(exc, "problem_mark", None) or getattr(exc, "context_mark", None)
    line = mark.line + 1 if mark is not None else None
    if isinstance(exc, yaml.reader.ReaderError):
        line = text[: exc.position].count("\n") + 1
        char = chr(exc.character) if isinstance(exc.character, int) else exc.character
        return SceneError(
            file,
            [Diagnostic("", f"character {char!r} is not allowed in YAML (control characters must be removed)", line)],
        )
    problem = getattr(exc, "problem", None) or str(exc).splitlines()[0]
    if "maximum nesting depth" in problem:  # PyYAML >= 6.0.3 stops deep flow nesting in its scanner, before our count
        return SceneError(file, [Diagnostic("", too_deep(MAX_DEPTH), line)])
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
    builder = EventBuilder(file, MAX_NODES, MAX_DEPTH)
    documents = 0
    parser = (_EventParser or SceneLoader)(text)
    try:
        while parser.check_event():
            event = parser.get_event()
            if isinstance(event, yaml.DocumentStartEvent):
                documents += 1
                if documents > 1:
                    raise SceneError(
                        file,
                        [
                            Diagnostic(
                                "", "but found another document (a scene is one YAML document)", event_line(event)
                            )
                        ],
                    )
            else:
                builder.feed(event)
    except yaml.YAMLError as exc:
        raise _yaml_error(file, text, exc) from None
    except RecursionError:  # pragma: no cover  (the builder has no recursion; kept as a last guard)
        raise SceneError(file, [Diagnostic("", too_deep(MAX_DEPTH))]) from None
    finally:
        dispose = getattr(parser, "dispose", None)
        if dispose is not None:
            dispose()
    if not builder.have_root:
        raise SceneError(file, [Diagnostic("", "the file is empty (expected a scene: see docs/scene-format.md)", 1)])
    return YamlDocument(data=builder.root, lines=builder.lines, problems=tuple(builder.problems))
