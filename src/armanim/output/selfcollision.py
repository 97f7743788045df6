"""self-collision.yaml: the run's allowed-collision matrix, so a reader sees what was not checked.

Every allowed pair of links with its reason (MoveIt's words), and every enabled pair, as
``armanim`` used them; written atomically like the other outputs.
"""

from __future__ import annotations

import json
from pathlib import Path

from armanim.output.atomic import write_text_atomic
from armanim.world.selfdistances import SelfPairs

SELF_COLLISION_FILE = "self-collision.yaml"


def self_collision_text(pairs: SelfPairs) -> str:
    """The file's text: the mode, the clearance, the enabled and the allowed pairs (YAML; names
    are written as JSON strings, which YAML reads as they are).

    >>> import numpy as np
    >>> print(self_collision_text(SelfPairs(np.array([0]), np.array([2]), 0.01, (("l1", "l3"),), (("l1", "l2", "Adjacent"),), "auto")), end="")
    # The arm's allowed-collision matrix for this run (armanim): every enabled pair keeps
    # self_clearance apart in every frame; the allowed pairs were never checked.
    mode: auto
    self_clearance: 0.01
    enabled:
      - ["l1", "l3"]
    allowed:
      - ["l1", "l2", "Adjacent"]
    """
    enabled = list(dict.fromkeys(pairs.names))
    lines = [
        "# The arm's allowed-collision matrix for this run (armanim): every enabled pair keeps",
        "# self_clearance apart in every frame; the allowed pairs were never checked.",
        f"mode: {pairs.mode}",
        f"self_clearance: {pairs.clearance!r}" if pairs.mode != "off" else "self_clearance: null",
        "enabled:" + ("" if enabled else " []"),
        *(f"  - [{json.dumps(a)}, {json.dumps(b)}]" for a, b in enabled),
        "allowed:" + ("" if pairs.allowed else " []"),
        *(f"  - [{json.dumps(a)}, {json.dumps(b)}, {json.dumps(reason)}]" for a, b, reason in pairs.allowed),
    ]
    return "\n".join(lines) + "\n"


def write_self_collision(pairs: SelfPairs, path: Path) -> None:
    """Write self-collision.yaml atomically."""
    write_text_atomic(path, self_collision_text(pairs))
