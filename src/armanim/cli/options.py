"""Options shared by several commands and the parsing of their values.

Every value a flag takes is checked by the same rule as the scene file's field it
stands for, so a flag accepts exactly what a scene accepts; a bad one is a UsageError
(exit 2) naming the flag.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from armanim.cli.app import err, say
from armanim.errors import UsageError

if TYPE_CHECKING:  # numpy and the render room are imported where used: --version, validate and fk start fast
    import numpy as np

    from armanim.render.settings import RenderOverrides

QuietOpt = Annotated[
    bool,
    typer.Option(
        "--quiet",
        "-q",
        help="No progress bars and no tables (notes, the warnings that a picture or a model is not what was asked, are still printed).",
    ),
]
JobsOpt = Annotated[int | None, typer.Option("--jobs", "-j", help="Worker processes (default: all cores).")]
SchedulerOpt = Annotated[
    str | None,
    typer.Option(
        "--scheduler",
        envvar="ARMANIM_SCHEDULER",
        help="Run on Dask: tcp://HOST:8786, or 'local' for a LocalCluster (needs pip install -e '.\\[dask]').",
        show_envvar=True,
    ),
]
QUALITY = {
    "low": ("854x480", 15.0),
    "medium": ("1280x720", 30.0),
    "high": ("1920x1080", 60.0),
    "4k": ("3840x2160", 60.0),
}  # --quality: size and fps, as manim's presets
QualityOpt = Annotated[
    str | None,
    typer.Option(
        "--quality",
        help="low (854x480@15), medium (1280x720@30), high (1920x1080@60) or 4k (3840x2160@60): "
        "overrides the scene's render size and fps (--size and --fps override it in turn).",
    ),
]


def file_path(text: str | Path) -> Path:
    """A file to write, named on the command line (``export --out``, ``schema --out``, ``fk --png``,
    ``view --out``, ``import moveit --out``), as a Path. A name that ends with ``/`` means a folder,
    and Path() would drop the slash: ``export --out exports/`` wrote a file named ``exports``
    (campaign 9), so it is a usage error (exit 2).

    >>> file_path("a/b.json").as_posix()
    'a/b.json'
    """
    if isinstance(text, str) and text.endswith(("/", os.sep)):
        raise typer.BadParameter(f"{text!r} ends with '/', so it names a folder: give a file's name")
    return Path(text)


def parse_numbers(text: str, flag: str, count: int | None = None) -> np.ndarray:
    """``"0,30,45"`` -> array; a clear UsageError for anything else.

    >>> parse_numbers("0, 30,45", "--angles").tolist()
    [0.0, 30.0, 45.0]
    """
    import numpy as np

    parts = [p.strip() for p in text.replace(" ", ",").split(",") if p.strip()]
    values = np.array([_number(p, flag) for p in parts])
    if not len(values) or not np.all(np.isfinite(values)):
        raise UsageError(f"{flag}: expected finite comma-separated numbers (got {shown(text)})")
    if count is not None and len(values) != count:
        raise UsageError(f"{flag}: expected {count} numbers (got {len(values):,}: {shown(text)})")
    return values


def shown(text: str, limit: int = 60) -> str:
    """``text`` quoted for a message, cut to ``limit`` characters (a flag may hold 100 kB).

    >>> shown("0,1"), shown("1," * 40, limit=10)
    ("'0,1'", "'1,1,1,1,1,...' (80 characters)")
    """
    if len(text) <= limit:
        return repr(text)
    return f"{text[:limit]!r}"[:-1] + f"...' ({len(text):,} characters)"


def _number(text: str, flag: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise UsageError(
            f"{flag}: {shown(text)} is not a number (expected comma-separated numbers, e.g. {flag} 0,30,45)"
        ) from None


def parse_lengths(text: str, flag: str, count: int | None = None) -> np.ndarray:
    """:func:`parse_numbers` for positions and lengths, held to the scene's size limit
    (beyond it, squares of distances overflow)."""
    import numpy as np

    from armanim.scene.models import LIMITS

    values = parse_numbers(text, flag, count)
    limit = LIMITS["magnitude"]
    if np.any(np.abs(values) > limit):
        big = values[np.argmax(np.abs(values))]
        raise UsageError(f"{flag}: {big:g} is too large (expected at most {limit:g} in size: choose a smaller unit)")
    return values


def parse_size(text: str) -> list[int]:
    """``"640x360"`` -> [640, 360] (its range is the scene's ``render.size``, checked later)."""
    try:
        return [int(v) for v in text.lower().split("x", 1)]
    except ValueError:
        raise UsageError(f"--size: expected WIDTHxHEIGHT, e.g. 640x360 (got {text!r})") from None


def usable_cores() -> int:
    """The cores this process may use (its CPU affinity where the system has one)."""
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)


def usable_jobs(jobs: int | None) -> int | None:
    """``--jobs``, at most the cores this process may use (more only add processes and
    memory); a note on stderr says so when it is lowered."""
    if jobs is not None and jobs < 1:  # checked here, not by click: one line, as every usage error
        raise UsageError(f"--jobs: expected at least 1 worker process (got {jobs}; leave it out to use every core)")
    cores = usable_cores()
    if jobs is not None and jobs > cores:
        say(f"note: --jobs {jobs} is more than the {cores} cores here; using {cores}", err)
        return cores
    return jobs


def render_overrides(
    size: str | None,
    fps: float | None,
    fmt: str | None,
    elevation: float | None = None,
    azimuth: float | None = None,
    quality: str | None = None,
) -> RenderOverrides:
    """The render settings given on the command line, checked by the scene's own
    ``render`` model. ``quality`` names a preset of :data:`QUALITY`; ``size`` and ``fps`` win over it."""
    if quality is not None:
        if quality.lower() not in QUALITY:
            raise UsageError(f"--quality: expected one of {', '.join(QUALITY)} (got {quality!r})")
        preset_size, preset_fps = QUALITY[quality.lower()]
        size, fps = size or preset_size, fps or preset_fps
    given = {"fps": fps, "size": parse_size(size) if size else None, "format": fmt}
    view = {k: v for k, v in (("elevation", elevation), ("azimuth", azimuth)) if v is not None}
    data = {k: v for k, v in given.items() if v is not None} | ({"view": view} if view else {})
    model = _checked_render_model(data)
    from armanim.render.settings import RenderOverrides

    return RenderOverrides(
        size=tuple(model.size) if "size" in data else None,
        fps=model.fps if "fps" in data else None,
        format=model.format if "format" in data else None,
        **{k: getattr(model.view, k) for k in view},
    )


def _checked_render_model(data: dict):
    """``data`` validated by the scene's RenderModel; its first problem names the flag."""
    from armanim.runs.options import checked_render

    return checked_render(data, "--")
