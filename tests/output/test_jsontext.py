"""JSON written strictly (no NaN, no infinity) and read back with a depth guard (issue 36).

Each test is named in docs/reliability.md, which it keeps true.
"""

from __future__ import annotations

import math

import pytest

from armanim.output.jsontext import json_text, parse_json


def test_json_is_written_strictly_and_read_with_a_depth_guard():
    with pytest.raises(ValueError):
        json_text({"final_distance": math.inf})
    for deep in ("[" * 1500 + "]" * 1500, '{"a":' * 100_000 + "1" + "}" * 100_000):
        with pytest.raises(ValueError, match="nested too deep"):
            parse_json(deep)
