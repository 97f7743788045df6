"""The viewer page: a run as one interactive, offline HTML file (``viewer.html``).

- :func:`armanim.render.viewer.data.viewer_data`: a solved run as the page's data
  (joint positions from armanim's forward kinematics, rounded).
- :func:`armanim.render.viewer.page.viewer_html`: the page, with the data and three.js inline.
- :func:`write_viewer`: both, written atomically to a file.

docs/viewer.md describes the page, its controls, its API (``window.armanim``) and the data format.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

VIEWER_FILE = "viewer.html"
"""The page's name in a run folder."""


def write_viewer(problem, trajectory, reports: Sequence, settings, path: str | Path, *, title: str) -> Path:
    """Write the viewer page of a solved run to ``path`` (atomically) and return the path.

    Parameters
    ----------
    problem : Problem
    trajectory : Trajectory
    reports : sequence of GoalReport
    settings : RenderSettings
        The video's camera angles, bounds and trail.
    path : file to write (a temporary file beside it is moved into place)
    title : shown on the page (any text: it is escaped)

    Raises
    ------
    OutputError
        The file could not be written (nothing half-written is left).
    """
    from armanim.output.atomic import write_text_atomic
    from armanim.render.viewer.data import viewer_data
    from armanim.render.viewer.page import viewer_html

    path = Path(path)
    write_text_atomic(path, viewer_html(viewer_data(problem, trajectory, reports, settings, title=title)))
    return path


__all__ = ["VIEWER_FILE", "write_viewer"]
