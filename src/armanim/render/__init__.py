"""Drawing and encoding: trajectories to videos, poses to PNGs, runs to plots.

Importing this package loads nothing heavy; matplotlib is imported only by the
modules that draw. Import the function you need from its module:

- :func:`armanim.render.video.movie.render_video`: a trajectory to MP4 or GIF.
- :func:`armanim.render.pictures.pose.render_pose_png`: one pose to a PNG.
- :func:`armanim.render.pictures.plot.plot_run`: distance, clearance and joint angles over time.
- :func:`armanim.render.camera.bounds.auto_bounds`: the fixed world box of a video.

The same names are also reachable as attributes of this package, loaded on first use.

The room is split into sub-rooms by role, each importing only from those below it (top to
bottom): ``viewer/`` (the interactive page), ``video/`` (frames to a video file, in worker
processes), ``pictures/`` (the scene canvas and the still pictures), ``overlay/`` (markers,
captions, triads), ``solids/`` (the arm's and the obstacles' solids, the painter's order),
``camera/`` (projection, bounds, framing), ``paint/`` (palette, layout, pixels) and
:mod:`armanim.render.settings` (what a run's pictures are asked to be). Writers take
``(run, options, path)``: a :class:`~armanim.output.solved.SolvedRun` and
:class:`~armanim.render.settings.OutputOptions`.
"""

from __future__ import annotations

_LAZY = {
    "render_video": "armanim.render.video.movie",
    "render_pose_png": "armanim.render.pictures.pose",
    "plot_run": "armanim.render.pictures.plot",
    "auto_bounds": "armanim.render.camera.bounds",
}

__all__ = list(_LAZY)


def __getattr__(name: str):
    if name in _LAZY:
        import importlib

        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'armanim.render' has no attribute {name!r}")
