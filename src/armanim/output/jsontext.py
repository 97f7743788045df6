"""JSON as armanim writes and reads it: strict out, guarded in.

Every JSON armanim writes (summary.json, the marker, a golden ``.json``, ``--json`` prints,
the schema) goes through :func:`json_text`, which refuses NaN and the infinities (they are
not JSON: ``JSON.parse`` and ``jq`` reject them), so a non-finite value is a bug the tests
catch, never a file other tools cannot read. Every JSON armanim reads back goes through
:func:`parse_json`, for which nesting deeper than :data:`MAX_JSON_DEPTH` is a ValueError like any
other text that is not what it should be, never a RecursionError, on every Python.
"""

from __future__ import annotations

import json


def json_text(data, **options) -> str:
    """``json.dumps(data, **options)`` with ``allow_nan=False``.

    >>> json_text({"a": [1.5, None]})
    '{"a": [1.5, null]}'
    >>> json_text(float("nan"))  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: Out of range float values are not JSON compliant...
    """
    return json.dumps(data, allow_nan=False, **options)


MAX_JSON_DEPTH = 100
"""The deepest nesting of arrays and objects :func:`parse_json` takes (armanim's own files nest
fewer than ten deep). Python's decoder stops at its recursion limit, which differs between
versions (about 1,000 on 3.11; 1,500 arrays parsed on 3.13): the bound is armanim's own, so every
Python gives one answer."""


def parse_json(text: str | bytes):
    """``json.loads(text)``; nesting deeper than :data:`MAX_JSON_DEPTH` is a ValueError.

    >>> parse_json("[" * 100_000 + "]" * 100_000)
    Traceback (most recent call last):
    ...
    ValueError: nested too deep
    >>> parse_json('{"a": [[1]]}'), json_depth(parse_json("[" * 100 + "]" * 100))
    ({'a': [[1]]}, 100)
    """
    try:
        data = json.loads(text)
    except RecursionError:
        raise ValueError("nested too deep") from None
    if json_depth(data) > MAX_JSON_DEPTH:
        raise ValueError("nested too deep")
    return data


def json_depth(data) -> int:
    """How deeply ``data`` (parsed JSON) nests arrays and objects: 0 for a number, a string or null,
    1 for ``[]``. Counted without recursion, so any depth the decoder took is counted.

    >>> json_depth(1), json_depth([]), json_depth({"a": [1, {"b": []}]})
    (0, 1, 4)
    """
    deepest = 0
    stack = [(data, 1)]
    while stack:
        item, depth = stack.pop()
        children = item.values() if isinstance(item, dict) else item if isinstance(item, list) else None
        if children is None:
            continue
        deepest = max(deepest, depth)
        stack.extend((child, depth + 1) for child in children if isinstance(child, (dict, list)))
    return deepest
