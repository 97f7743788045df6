"""A trajectory to a video file: frames drawn by the scene canvas, piped to ffmpeg, in one
process or in contiguous segments drawn by worker processes and joined.

- :mod:`.movie`: ``render_video``, the entry point: the job count, the temporary file
  beside the target, leftovers of killed runs.
- :mod:`.segment`: a contiguous run of frames drawn and encoded into one file.
- :mod:`.parallel`: the worker processes, one segment each, progress on a queue, the
  segments joined.
- :mod:`.encode`: ``FrameWriter`` (frames to imageio-ffmpeg's ffmpeg on a pipe), the GIF
  palette, joining segments without re-encoding.

Stands on :mod:`armanim.render.pictures` (the canvas draws each frame).
"""
