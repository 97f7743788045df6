"""The viewer page: a run as one interactive, offline HTML file (``viewer.html``).

- :func:`armanim.render.viewer.data.viewer_data`: a solved run as the page's data
  (joint positions from armanim's forward kinematics, rounded).
- :func:`armanim.render.viewer.page.viewer_html`: the page, with the data and three.js inline.
- :func:`write_viewer`: both, written atomically to a file a block at a time (a long run's
  frames are never held whole as text; past :data:`~armanim.render.viewer.data.MAX_PAGE_FRAMES`
  the page shows one frame in ``step``).

docs/viewer.md describes the page, its controls, its API (``window.armanim``) and the data format.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from armanim.output.solved import SolvedRun
    from armanim.render.settings import OutputOptions

VIEWER_FILE = "viewer.html"
"""The page's name in a run folder."""


def write_viewer(run: SolvedRun, options: OutputOptions, path: str | Path) -> Path:
    """Write the viewer page of a solved run to ``path`` (atomically) and return the path.

    Parameters
    ----------
    run : SolvedRun
        The run; its name is shown on the page (any text: it is escaped).
    options : OutputOptions
        ``render``: the video's camera angles, bounds and trail.
    path : file to write (a temporary file beside it is moved into place)

    Raises
    ------
    OutputError
        The file could not be written (nothing half-written is left).
    """
    from armanim.output.atomic import write_chunks_atomic
    from armanim.render.viewer.data import viewer_parts
    from armanim.render.viewer.page import page_blocks

    path = Path(path)
    parts = viewer_parts(
        run.problem,
        run.trajectory,
        run.reports,
        options.render,
        title=run.name,
        meshes=run.meshes,
        carry=run.solution.carry,
    )
    write_chunks_atomic(path, page_blocks(parts))  # its lists turned into text a few frames at a time
    return path


__all__ = ["VIEWER_FILE", "write_viewer"]
