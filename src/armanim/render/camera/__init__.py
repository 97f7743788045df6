"""Where things appear in a frame: the camera and its projection, the fixed world box of a run,
and the view fitted into the frame.

- :mod:`.view`: the world-to-screen map of a fixed orthographic camera (one affine matrix) and
  flat shading.
- :mod:`.projection`: the camera's rotation from elevation and azimuth, the view fitted to
  points, a planar arm's face-on angles.
- :mod:`.bounds`: the fixed world box of a video and the extent of the world's boxes and
  capsules.
- :mod:`.framing`: the floor's height and rectangle and the view that fits a run's content.

Pure numpy: nothing is drawn here. Below the solids, overlays and pictures, which project
through a :class:`~armanim.render.camera.view.View`.
"""
