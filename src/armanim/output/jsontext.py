"""JSON as armanim writes and reads it: strict out, guarded in.

Every JSON armanim writes (summary.json, the marker, a golden ``.json``, ``--json`` prints,
the schema) goes through :func:`json_text`, which refuses NaN and the infinities (they are
not JSON: ``JSON.parse`` and ``jq`` reject them), so a non-finite value is a bug the tests
catch, never a file other tools cannot read. Every JSON armanim reads back goes through
:func:`parse_json`, for which nesting too deep for the decoder is a ValueError like any
other text that is not what it should be, never a RecursionError.
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


def parse_json(text: str | bytes):
    """``json.loads(text)``; nesting deeper than the decoder takes is a ValueError.

    >>> parse_json("[" * 100_000 + "]" * 100_000)
    Traceback (most recent call last):
    ...
    ValueError: nested too deep
    """
    try:
        return json.loads(text)
    except RecursionError:
        raise ValueError("nested too deep") from None
