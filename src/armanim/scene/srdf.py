"""Read an SRDF's allowed-collision pairs, and check the link names of ``arm.self_collision``.

Only ``<disable_collisions link1="a" link2="b" reason="..."/>`` (children of ``<robot>``) is read:
MoveIt's form of the allowed-collision matrix, the one pinocchio's ``removeCollisionPairs``
reads too; everything else in the file (groups, end effectors, virtual joints) is ignored. The
file is parsed with the URDF reader's guards (:func:`armanim.scene.urdf._parse_xml`: no DTD, bounded
size, depth and element count). Every problem is a ``FILE:LINE: message`` (exit 2).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from armanim.errors import Diagnostic, SceneError
from armanim.output.files import read_named_file
from armanim.scene.urdf import MAX_URDF_BYTES, _parse_xml


@dataclass(frozen=True)
class Srdf:
    """The allowed pairs a scene's ``self_collision`` gives.

    Attributes
    ----------
    pairs : tuple of (str, str, str)
        (link1, link2, reason) of every ``<disable_collisions>`` (reason ``SRDF`` when it has none).
    source : bytes or None
        The SRDF's bytes, which a run folder keeps (None without an SRDF).
    """

    pairs: tuple[tuple[str, str, str], ...] = ()
    source: bytes | None = None


def parse_srdf(raw: bytes, file: str, links: tuple[str, ...]) -> tuple[tuple[str, str, str], ...]:
    """The ``<disable_collisions>`` pairs of SRDF bytes whose links are all in ``links``.

    >>> parse_srdf(b'<robot name="r"><disable_collisions link1="a" link2="b" reason="Adjacent"/></robot>', "r.srdf", ("a", "b"))
    (('a', 'b', 'Adjacent'),)
    """
    root = _parse_xml(raw, file)
    if root.tag != "robot":
        raise SceneError(
            file, [Diagnostic("", f"the top element is <{root.tag}> (expected <robot>: an SRDF file)", root.line)]
        )
    problems, pairs = [], []
    for el in root.findall("disable_collisions"):
        first, second = el.attrib.get("link1"), el.attrib.get("link2")
        if first is None or second is None:
            problems.append(Diagnostic("", "a <disable_collisions> needs link1 and link2 attributes", el.line))
            continue
        unknown = [n for n in (first, second) if n not in links]
        if unknown:
            shown = ", ".join(links[:12]) + (", ..." if len(links) > 12 else "")
            problems.append(
                Diagnostic(
                    "", f"link {unknown[0]!r} is not a link of the arm's robot (expected one of: {shown})", el.line
                )
            )
            continue
        pairs.append((first, second, el.attrib.get("reason") or "SRDF"))
    if problems:
        raise SceneError(file, problems)
    return tuple(pairs)


def resolve_self_collision(
    spec, links: tuple[str, ...], scene_dir: str | Path = ".", srdf_file: str | Path | None = None
) -> Srdf:
    """Check the link names of ``arm.self_collision``'s ``allow`` and ``check`` lists (``spec``, a
    ``SelfCollisionModel``; a ValueError, reported at ``arm``) against ``links``, the names it may use
    (the URDF's links, or ``link1``... for an arm of links), and read its SRDF, if any (relative to
    ``scene_dir``, or the file ``srdf_file``: a run folder's copy)."""
    for field in ("allow", "check"):
        for k, pair in enumerate(getattr(spec, field)):
            for name in pair:
                if name not in links:
                    shown = ", ".join(links[:12]) + (", ..." if len(links) > 12 else "")
                    raise ValueError(
                        f"self_collision.{field}[{k}] names {name!r}, not a link of the arm (expected one of: {shown})"
                    )
            if pair[0] == pair[1]:
                raise ValueError(
                    f"self_collision.{field}[{k}] pairs {pair[0]!r} with itself (expected two different links)"
                )
    if spec.srdf is None:
        return Srdf()
    path = Path(srdf_file) if srdf_file else Path(scene_dir or ".") / spec.srdf
    raw = read_named_file("self_collision.srdf", path, MAX_URDF_BYTES, "an SRDF file")
    return Srdf(parse_srdf(raw, str(path), links), raw)
