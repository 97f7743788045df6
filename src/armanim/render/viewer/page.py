"""The viewer page: one HTML file holding the page, the run's data and three.js.

The parts are package data in ``assets/``: ``page.html`` (the markup, with placeholders),
``page.css``, ``page.js`` (the page's own code) and ``three-viewer.min.js`` (three.js,
bundled once by ``tools/viewer-js/build.sh``; its version and sha256 are in
``three-viewer.json``). Nothing is fetched when the page opens: it works from ``file://``.

Every text that comes from a run (the title, joint names, reasons) travels inside the
JSON data block and is put on the page as text, never as markup; the block itself is
escaped so that no ``</script>``, comment or quote in it can end it (:func:`script_json`).
"""

from __future__ import annotations

import hashlib
import html
import json
import os
import stat
from collections.abc import Iterator
from functools import cache
from importlib import resources
from pathlib import Path

from armanim.render.viewer.data import FrameSeries

ASSETS = "assets"
GENERATOR = "armanim viewer"
"""The page's ``<meta name="generator">``: how ``armanim view`` knows a page of armanim's."""
DIGEST = '<meta name="armanim-sha256" content="{}">\n'
"""The page's last line: the sha256 of every byte before it (UTF-8), so ``armanim view --out``
replaces a page only as armanim wrote it, never one a user edited since (their notes in it)."""
DIGEST_TAIL = 128
"""Bytes at the end of a page read to find its digest line (the line is 104)."""
WRITE_BLOCK = 1 << 20
"""Characters of a page gathered before they are handed on to be written (:func:`page_blocks`)."""


def asset_text(name: str) -> str:
    """The text of one file of ``assets/`` (package data)."""
    return resources.files(__package__).joinpath(ASSETS, name).read_text(encoding="utf-8")


@cache
def bundle_info() -> dict:
    """The three.js bundle's record: ``three`` (version), ``esbuild``, ``bytes``, ``sha256``."""
    return json.loads(asset_text("three-viewer.json"))


@cache
def three_bundle() -> str:
    """The minified three.js bundle (window.THREE), as the maintainer script wrote it."""
    return asset_text(bundle_info()["file"])


def script_json(data: object) -> str:
    """``data`` as JSON that is safe inside ``<script type="application/json">``.

    ``<``, ``>`` and ``&`` become ``\\u003c``, ``\\u003e`` and ``\\u0026`` (JSON.parse turns
    them back), so no ``</script>``, ``<!--`` or ``<script`` can appear in the block;
    non-ASCII is escaped too (U+2028 and U+2029 included). NaN and infinity are refused:
    they are not JSON.

    >>> script_json({"title": "</script><b>"})
    '{"title":"\\\\u003c/script\\\\u003e\\\\u003cb\\\\u003e"}'
    """
    return "".join(script_json_pieces(data))


def json_text(value: object) -> str:
    """``value`` as compact JSON, ASCII only, ``<``, ``>`` and ``&`` escaped (:func:`script_json`'s rules)."""
    text = json.dumps(value, separators=(",", ":"), ensure_ascii=True, allow_nan=False)
    return text.replace("<", "\\u003c").replace(">", "\\u003e").replace("&", "\\u0026")


def script_json_pieces(data: object) -> Iterator[str]:
    """:func:`script_json` of ``data`` in pieces that join to it, each
    :class:`~armanim.render.viewer.data.FrameSeries` in it turned into text a chunk of frames at a
    time: a long run's lists are never held whole, as numbers or as text."""
    if isinstance(data, FrameSeries):
        yield "["
        first = True
        for chunk in data.chunks():
            if chunk:
                yield ("" if first else ",") + json_text(chunk)[1:-1]
                first = False
        yield "]"
    elif isinstance(data, dict):
        yield "{"
        for i, (key, value) in enumerate(data.items()):
            yield ("," if i else "") + json_text(str(key)) + ":"
            yield from script_json_pieces(value)
        yield "}"
    elif isinstance(data, (list, tuple)) and any(isinstance(v, (FrameSeries, dict, list, tuple)) for v in data):
        yield "["
        for i, value in enumerate(data):
            if i:
                yield ","
            yield from script_json_pieces(value)
        yield "]"
    else:
        yield json_text(data)


def inline_script(code: str) -> str:
    """JavaScript source made safe to sit in a ``<script>`` element.

    A ``</script`` or ``<!--`` in it (in a string or comment of a library) would end or
    change the element; ``<\\/script`` and ``<\\!--`` mean the same in JavaScript strings.
    """
    return code.replace("</script", "<\\/script").replace("</SCRIPT", "<\\/SCRIPT").replace("<!--", "<\\!--")


def viewer_html(data: dict) -> str:
    """The whole page for ``data`` (from :func:`armanim.render.viewer.data.viewer_data`).

    Examples
    --------
    >>> page = viewer_html({"title": "a <b> & 'c'"})
    >>> page.startswith("<!doctype html>"), "<title>a &lt;b&gt; &amp; &#x27;c&#x27; - armanim</title>" in page
    (True, True)
    """
    return b"".join(page_blocks(data)).decode("utf-8")


def page_pieces(data: dict) -> Iterator[str]:
    """The page for ``data`` (:func:`~armanim.render.viewer.data.viewer_data`'s, or
    :func:`~armanim.render.viewer.data.viewer_parts`') in pieces, without its digest line."""
    parts = {
        "ARMANIM_GENERATOR": lambda: iter([GENERATOR]),
        "ARMANIM_TITLE": lambda: iter([html.escape(str(data.get("title", "")), quote=True)]),
        "/*ARMANIM_CSS*/": lambda: iter([asset_text("page.css")]),
        "/*ARMANIM_DATA*/": lambda: script_json_pieces(data),
        "/*ARMANIM_THREE*/": lambda: iter([inline_script(three_bundle())]),
        "/*ARMANIM_PAGE*/": lambda: iter([inline_script(asset_text("page.js"))]),
    }
    rest = asset_text("page.html")
    for marker, part in parts.items():  # in the template's order, one pass: a part never fills another's marker
        head, found, rest = rest.partition(marker)
        if not found:
            raise ValueError(f"page.html lacks the placeholder {marker} (or has it out of order)")
        yield head
        yield from part()
    yield rest


def page_blocks(data: dict, block: int | None = None) -> Iterator[bytes]:
    """The page for ``data`` as UTF-8 blocks of about ``block`` characters (default
    :data:`WRITE_BLOCK`), its last line :data:`DIGEST` with the sha256 of every byte before it
    (hashed as the blocks go by)."""
    block = block or WRITE_BLOCK
    digest, pending, size = hashlib.sha256(), [], 0
    for piece in page_pieces(data):
        pending.append(piece)
        size += len(piece)
        if size >= block:
            out = "".join(pending).encode("utf-8")
            digest.update(out)
            yield out
            pending, size = [], 0
    out = "".join(pending).encode("utf-8")
    digest.update(out)
    yield out + DIGEST.format(digest.hexdigest()).encode("ascii")


def is_viewer_page(path: str | Path, limit: int = 4096) -> bool:
    """Whether ``path`` is a regular file (or a link to one) that starts like a page armanim wrote.

    Only its first ``limit`` bytes are read; a missing file, a folder or a device is not.
    """
    try:
        if not stat.S_ISREG(os.stat(path).st_mode):
            return False
        with open(path, "rb") as handle:
            head = handle.read(limit)
    except OSError:
        return False
    return f'<meta name="generator" content="{GENERATOR}">'.encode() in head


def is_unchanged_page(path: str | Path) -> bool:
    """Whether the page at ``path`` is, byte for byte, as armanim wrote it: its last line is
    :data:`DIGEST` with the sha256 of every byte before it (hashed in blocks: any size, flat memory)."""
    try:
        with open(path, "rb") as handle:
            size = os.fstat(handle.fileno()).st_size
            handle.seek(max(0, size - DIGEST_TAIL))
            tail = handle.read(DIGEST_TAIL)
            start, _, end = DIGEST.encode().partition(b"{}")
            at = tail.rfind(start)
            if at < 0 or not tail.endswith(end) or len(tail) - at != len(start) + 64 + len(end):
                return False
            recorded = tail[at + len(start) : at + len(start) + 64].decode("ascii", "replace")
            body = size - (len(tail) - at)
            handle.seek(0)
            digest = hashlib.sha256()
            while body > 0:
                block = handle.read(min(body, 1 << 20))
                if not block:
                    return False
                digest.update(block)
                body -= len(block)
    except OSError:
        return False
    return digest.hexdigest() == recorded


def replace_problem(path: str | Path) -> str | None:
    """Why a page must not be written at ``path``, or None if it may (nothing there, or armanim's page).

    >>> replace_problem("/nonexistent/viewer.html") is None
    True
    """
    try:
        mode = os.stat(path).st_mode
    except FileNotFoundError:
        return None if not os.path.islink(path) else "is a link to nothing, which armanim did not make"
    except OSError as exc:
        return f"cannot be inspected ({exc.strerror or exc})"
    if stat.S_ISDIR(mode):
        return "is a folder (expected a file name, e.g. viewer.html)"
    if not stat.S_ISREG(mode):
        return "is not a regular file, so armanim does not write there"
    if not is_viewer_page(path):
        return "is a file armanim did not write (not a viewer page), so it is not replaced"
    if not is_unchanged_page(path):
        return (
            "is a viewer page changed since armanim wrote it (or written by an armanim that did not record its "
            "sha256), so it is not replaced"
        )
    return None
