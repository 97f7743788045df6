"""The caption's glyphs: a frame's stamp, which lays again the last frame's pixels and only the
cells of the characters that changed, draws the bytes a whole stamp draws."""

from __future__ import annotations

import numpy as np
import pytest

from armanim.render.overlay.glyphs import GlyphAtlas
from armanim.render.paint.pixels import make_figure
from armanim.render.paint.style import TEXT_COLOR

CAPTIONS = [
    "t =    0.00 s   goal 0 (of 0-1)   distance    0.412   moving",
    "t =    0.03 s   goal 0 (of 0-1)   distance    0.408   moving",
    "t =    0.07 s   goal 0 (of 0-1)   distance    0.401   moving",
    "t =    0.07 s   goal 0 (of 0-1)   distance    0.401   moving",
    "t =    0.03 s   goal 0 (of 0-1)   distance    0.408   moving",
    "t =    0.10 s   goal 1 (of 0-1)   distance    0.000   reached",
    "t =    0.13 s   goal 1 (of 0-1)   distance    0.000   reached",
    "t =    0.13 s   goal 1 (of 0-1)   distance    0.000   missed: blocked",
    "t =    0.17 s   goal 1 (of 0-1)   distance    0.000   missed: blocked",
]


def _atlas() -> GlyphAtlas:
    return GlyphAtlas(make_figure(64, 64, 100.0)[1], 11.0, TEXT_COLOR)


@pytest.mark.parametrize("x", [12.0, -30.0, 600.0])
def test_stamping_frame_after_frame_draws_what_a_fresh_stamp_draws(x):
    """A run's captions stamped one after the other over a restored background (once over another
    one, once longer, and clipped by the frame's edge), against a fresh atlas stamping each alone."""
    rng = np.random.default_rng(3)
    background = rng.integers(0, 256, (60, 720, 4), dtype=np.uint8)
    other = background.copy()
    other[10:30, 100:140] = 7  # something drawn under the caption in one frame
    atlas = _atlas()
    for k, text in enumerate(CAPTIONS):
        under = other if k == 3 else background
        frame, alone = under.copy(), under.copy()
        atlas.stamp(frame, text, x, 40.0)
        _atlas().stamp(alone, text, x, 40.0)
        assert np.array_equal(frame, alone), text
