"""What the pictures of a run are asked to be: the scene's ``render`` section resolved
(:class:`RenderSettings`, built by :func:`armanim.scene.render_settings`), what a command
changes in it for one run (:class:`RenderOverrides`: ``--size``, ``--fps``, ...), and which of a
run's outputs are written and how (:class:`OutputOptions`).

Plain data, read only by the render room (the solver never sees it): the command line checks
each override against the scene's own ``render`` model before it gets here, so an override
accepts exactly what a scene file accepts. No I/O. The lowest floor of :mod:`armanim.render`.
"""

from __future__ import annotations

from dataclasses import dataclass, fields, replace

import numpy as np

from armanim.names import RobotLook, VideoFormat


@dataclass(frozen=True)
class RenderSettings:
    """The scene's ``render`` section, resolved (plain data, read by the render room only).

    Its ``fps`` is not here: the rate of a run's frames is the run's own
    (:attr:`armanim.output.solved.SolvedRun.fps`), chosen once by :func:`armanim.runs.options.output_choice`.

    Attributes
    ----------
    size : (int, int)
        Width and height in pixels.
    elevation, azimuth : float or None
        Camera angles in degrees (as matplotlib's ``view_init`` takes them); None:
        face-on for a planar arm, else 25 and -60 (see :mod:`armanim.render.camera.projection`).
    bounds : (3, 2) array or None
        [[xmin, xmax], [ymin, ymax], [zmin, zmax]]; None means auto.
    trail : bool
        Draw the tip's path.
    format : str
        ``"mp4"`` or ``"gif"``.
    robot : str
        How a robot with visual meshes is drawn: ``"mesh"`` (as it looks), ``"capsules"`` (the
        shapes every clearance is measured on) or ``"both"`` (the capsules translucent over it).
    """

    size: tuple[int, int]
    elevation: float | None
    azimuth: float | None
    bounds: np.ndarray | None
    trail: bool
    format: VideoFormat
    robot: RobotLook = "mesh"


@dataclass(frozen=True)
class RenderOverrides:
    """Render settings given on the command line; None leaves the scene's value.

    Attributes
    ----------
    size : (int, int) or None
        Width and height in pixels.
    fps : float or None
        Frames per second of the run's frames (the video, trajectory.csv, the viewer). The
        motion is still solved at the scene's own ``render.fps`` and then put on the clock, or
        a finished run resampled, at this rate: the same seconds either way.
    format : str or None
        ``"mp4"`` or ``"gif"``.
    elevation, azimuth : float or None
        Camera angles in degrees.

    Examples
    --------
    >>> RenderOverrides(size=(640, 360), fps=12.0).given()
    {'size': (640, 360), 'fps': 12.0}
    """

    size: tuple[int, int] | None = None
    fps: float | None = None
    format: VideoFormat | None = None
    elevation: float | None = None
    azimuth: float | None = None

    def given(self) -> dict:
        """The overridden fields and their values (the fields left None are not given)."""
        return {f.name: getattr(self, f.name) for f in fields(self) if getattr(self, f.name) is not None}

    def apply(self, settings: RenderSettings) -> RenderSettings:
        """``settings`` with the given fields replaced (``fps`` is the run's, not the settings')."""
        return replace(settings, **{k: v for k, v in self.given().items() if k != "fps"})


@dataclass(frozen=True)
class OutputOptions:
    """How a solved run is written: the pictures' settings and which outputs.

    trajectory.csv and summary.json are always written; these choose the rest. Every writer of
    a run takes ``(run, options, path)`` (:class:`armanim.output.solved.SolvedRun`).

    Attributes
    ----------
    render : RenderSettings
        Size, format, view, bounds and trail of the pictures.
    video : bool
        Write the video, plot.png and poster.png.
    viewer : bool
        Write viewer.html.
    jobs : int or None
        Worker processes drawing the video (None: every core).
    """

    render: RenderSettings
    video: bool = True
    viewer: bool = True
    jobs: int | None = None
