"""One picture of the scene and the still pictures built on it.

- :mod:`.canvas`: :class:`~armanim.render.pictures.canvas.SceneCanvas`, the scene drawn once
  (the background), then any number of frames (shadow, trail, solids in painter's order,
  goal markers, caption); video frames are drawn by it too.
- :mod:`.backdrop`: what is drawn once into that background: floor, shells, world axes,
  title, legend, the caption's box.
- :mod:`.pose`: one pose to a PNG (``armanim fk --png``).
- :mod:`.poster`: ``poster.png``, the arm faintly on each goal, the tip's path and the path goals' ink.
- :mod:`.plot`: ``plot.png``, distance, clearance, speeds and joint angles over time.

Stands on the overlays, the solids, the camera and the paint; :mod:`armanim.render.video`
draws its frames with the canvas.
"""
