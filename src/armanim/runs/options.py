"""What a command asks of a run beyond its scene (:class:`RunOptions`), and the one place it meets
the scene: the rate of the run's frames and how its outputs are written (:func:`output_choice`).

``armanim run`` builds one :class:`RunOptions` from its flags; it travels unchanged through
:func:`armanim.runs.pipeline.run_scene`, :func:`armanim.runs.batch.run_batch` and the batch's
workers to :func:`armanim.runs.pipeline.produce_outputs`, which resolves it against the scene once.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from armanim.errors import UsageError
from armanim.render.settings import OutputOptions, RenderOverrides
from armanim.scene import LoadedScene, render_settings


@dataclass(frozen=True)
class RunOptions:
    """The outputs a command asks of a run, and how they are drawn (plain data, made once).

    Attributes
    ----------
    video : bool
        Render the video, plot.png and poster.png (False: trajectory.csv and summary.json only).
    viewer : bool or None
        Write viewer.html, the interactive page; None: when ``video`` is True.
    jobs : int or None
        Worker processes: scenes in parallel for a batch, the video's segments for one scene
        (None: every core). A batch's worker draws its scene's video in one process.
    render : RenderOverrides
        The scene's render settings a command changes (``--size``, ``--fps``, ``--format``, ...).

    Examples
    --------
    >>> RunOptions(video=False).writes_viewer, RunOptions(video=False, viewer=True).writes_viewer
    (False, True)
    """

    video: bool = True
    viewer: bool | None = None
    jobs: int | None = None
    render: RenderOverrides = field(default_factory=RenderOverrides)

    def __post_init__(self) -> None:
        """Refuse what no run can use, as the command's flags are refused (campaign 16: from Python,
        ``RenderOverrides(size=(0, 0))`` ended in a ZeroDivisionError, ``fps=nan`` in "cannot convert
        float NaN to integer", and ``jobs=0`` or ``-3`` were taken)."""
        if self.jobs is not None and self.jobs < 1:
            raise UsageError(f"jobs: expected at least 1 worker process (got {self.jobs}; None uses every core)")
        checked_render(overrides_data(self.render), "RenderOverrides.")

    @property
    def writes_viewer(self) -> bool:
        """Whether viewer.html is written: ``viewer``, else with the video."""
        return self.video if self.viewer is None else self.viewer


def overrides_data(overrides: RenderOverrides) -> dict:
    """``overrides``' given fields as a scene's ``render`` section holds them (its ``view`` apart)."""
    given = overrides.given()
    data = {k: list(v) if k == "size" else v for k, v in given.items() if k in ("size", "fps", "format")}
    view = {k: given[k] for k in ("elevation", "azimuth") if k in given}
    return data | ({"view": view} if view else {})


def checked_render(data: dict, prefix: str):
    """``data`` (render settings, as a scene's ``render`` section) validated by the scene's own
    model, the one check of a command's flags and of a program's :class:`RenderOverrides`.

    Each override's flag and field share its name (``fps``, ``size``, ``format``, and ``elevation``
    and ``azimuth`` under ``view``): a problem is named ``prefix`` and that name, ``--fps`` for the
    command, ``RenderOverrides.fps`` from Python.

    Raises
    ------
    UsageError
        Its first problem, named as above (exit 2).
    """
    from pydantic import ValidationError

    from armanim.scene.loader import problem_message
    from armanim.scene.models import RenderModel

    try:
        return RenderModel.model_validate(data)
    except ValidationError as exc:
        first = exc.errors()[0]
        fields = [part for part in first["loc"] if isinstance(part, str)]
        name = prefix + (fields[-1] if fields else "render")
        raise UsageError(f"{name}: {problem_message(first, tuple(first['loc']))}") from None


def output_choice(scene: LoadedScene, options: RunOptions) -> tuple[float, OutputOptions]:
    """(fps, output options): the rate of a run's frames and how its outputs are written, for
    ``scene`` under ``options``. The one place both are decided.

    The fps is the command's ``--fps``, else the scene's ``render.fps``:
    :func:`armanim.runs.pipeline.solved_run` puts the run at it, and every writer reads it from the
    run (the motion itself is always solved at the scene's own rate). The render settings are the
    scene's ``render`` section with the command's overrides applied.
    """
    given = options.render
    fps = given.fps if given.fps is not None else scene.model.render.fps
    settings = given.apply(render_settings(scene.model))
    return fps, OutputOptions(settings, video=options.video, viewer=options.writes_viewer, jobs=options.jobs)


__all__ = ["RunOptions", "output_choice"]
