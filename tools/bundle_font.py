"""Maintainer script: the single-stroke font of text path goals, as package data.

Reads the Roman simplex Hershey font (``futural``) from the PyPI package ``hershey-fonts``
2.1.0 (MIT, https://github.com/apshu/HersheyFonts; the font data after the Usenet
distribution of the Hershey fonts) and writes ``src/armanim/scene/fonts/futural.json``: for
every printable ASCII character (32..126) its advance width and its strokes, each stroke a
flat list ``[x0, y0, x1, y1, ...]`` of integer font units, x from the glyph's left side,
y up from the baseline; the capital height is ``cap_height`` units. The file carries the
Hershey fonts' usage notice and the package's MIT notice, as does ``fonts/README.md``.
Run time reads that JSON with the standard library alone; users and CI never run this.

Usage::

    pip download hershey-fonts==2.1.0 --no-deps -d /tmp/hf && pip install /tmp/hf/*.whl
    python tools/bundle_font.py
"""

from __future__ import annotations

import json
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
TARGET = ROOT / "src" / "armanim" / "scene" / "fonts" / "futural.json"
FONT = "futural"

NOTICE = [
    "USE RESTRICTION: This distribution of the Hershey Fonts may be used by anyone for any purpose, commercial or otherwise, providing that:",
    "1. The following acknowledgements must be distributed with the font data:",
    "- The Hershey Fonts were originally created by Dr. A. V. Hershey while working at the U. S. National Bureau of Standards.",
    "- The format of the Font data in this distribution was originally created by James Hurt, Cognition, Inc., "
    "900 Technology Park Drive, Billerica, MA 01821 (mit-eddie!ci-dandelion!hurt)",
    "2. The font data in this distribution may be converted into any other format *EXCEPT* the format distributed by the U.S. NTIS "
    "(which organization holds the rights to the distribution and use of the font data in that particular format).",
    "Converted by armanim's tools/bundle_font.py from the Python package hershey-fonts 2.1.0 "
    "(https://github.com/apshu/HersheyFonts; MIT License, Copyright (c) 2020 apshu).",
]


def glyph_table(font) -> dict:
    """Per printable ASCII character: ``{"advance": units, "strokes": [[x0, y0, x1, y1, ...], ...]}``,
    x from the glyph's left side, y up from the baseline (Hershey's y points down)."""
    base = int(font.render_options["base_line"])
    glyphs = {}
    for code in range(32, 127):
        glyph = font.all_glyphs[chr(code)]
        left = glyph.left_offset
        strokes = [[v for x, y in stroke for v in (int(x - left), int(base - y))] for stroke in glyph.strokes]
        glyphs[chr(code)] = {"advance": int(glyph.char_width), "strokes": strokes}
    return glyphs


def main() -> None:
    from HersheyFonts import HersheyFonts

    font = HersheyFonts()
    font.load_default_font(FONT)
    options = font.render_options
    data = {
        "name": "Hershey Roman simplex (futural)",
        "notice": NOTICE,
        "cap_height": int(options["base_line"] - options["cap_line"]),
        "descent": int(options["bottom_line"] - options["base_line"]),
        "glyphs": glyph_table(font),
    }
    TARGET.parent.mkdir(parents=True, exist_ok=True)
    text = json.dumps(data, ensure_ascii=True, separators=(",", ":"))
    TARGET.write_text(text.replace(',"glyphs":{', ',"glyphs":{\n').replace('},"', '},\n"') + "\n", encoding="utf-8")
    print(f"wrote {TARGET.relative_to(ROOT)}: {len(data['glyphs'])} glyphs, {TARGET.stat().st_size:,} bytes")


if __name__ == "__main__":
    main()
