"""What is drawn over the solids and says what happens: goal markers, captions, the caption's
glyphs and orientation triads.

- :mod:`.caption`: each goal's state per frame and the caption line (pure).
- :mod:`.markers`: the numbered goal markers, one sprite per goal and state.
- :mod:`.glyphs`: the caption's monospaced characters drawn once and stamped.
- :mod:`.triads`: the tool's and the oriented goals' RGB axes.
- :mod:`.paths`: path goals' ink behind the tool and the path ahead of it, per frame (pure).

Draws on :mod:`armanim.render.paint`; knows nothing of the camera or the solids.
"""
