"""Drawing and encoding: trajectories to videos, poses to PNGs, runs to plots.

Importing this package loads nothing heavy; matplotlib is imported only by the
modules that draw. Import the function you need from its module:

- :func:`armanim.render.video.movie.render_video`: a trajectory to MP4 or GIF.
- :func:`armanim.render.pictures.pose.render_pose_png`: one pose to a PNG.
- :func:`armanim.render.pictures.plot.plot_run`: distance, clearance and joint angles over time.
- :func:`armanim.render.camera.bounds.auto_bounds`: the fixed world box of a video.

The same names are also reachable as attributes of this package, loaded on first use.
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
