"""What every picture is painted with: the palette, the frame's layout and floor geometry,
and figures and pixel buffers of an exact size.

- :mod:`.style`: colours, sizes and fonts.
- :mod:`.scenery`: the frame's layout, the floor and its grid, shadows, label placement
  (pure numpy).
- :mod:`.pixels`: matplotlib figures of an exact pixel size, sprites and their
  compositing, ``write_png``.

The lowest floor of :mod:`armanim.render`: it imports no other sub-room.
"""
