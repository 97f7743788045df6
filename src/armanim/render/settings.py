"""The render settings a command changes for one run (``--size``, ``--fps``, ...).

Plain data: the command line checks each value against the scene's own ``render``
model before it gets here, so an override accepts exactly what a scene file accepts.
No I/O.
"""

from __future__ import annotations

from dataclasses import dataclass, fields, replace

from armanim.motion.problem import RenderSettings
from armanim.names import VideoFormat


@dataclass(frozen=True)
class RenderOverrides:
    """RenderSettings fields given on the command line; None leaves the scene's value.

    Attributes
    ----------
    size : (int, int) or None
        Width and height in pixels.
    fps : float or None
        Frames per second; a run is also solved at this rate (holds are seconds).
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
        """``settings`` with the given fields replaced."""
        return replace(settings, **self.given())
