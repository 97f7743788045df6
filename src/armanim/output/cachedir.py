"""Where armanim keeps its capsule-fit cache: one owner for the folder's path, so that the fit
(:mod:`armanim.scene.meshcapsules`) and the run folders' guard (:mod:`armanim.output.rundir`,
which names the cache when it stands inside a run folder) agree on it."""

from __future__ import annotations

import os
from pathlib import Path

CACHE_ENV = "ARMANIM_CACHE_DIR"


def capsule_cache_path() -> Path:
    """The capsule cache's folder as configured (``ARMANIM_CACHE_DIR``, else the user's cache
    folder's ``armanim/capsules``: ``XDG_CACHE_HOME`` or ``~/.cache``), whether or not it exists.
    (No doctest: it would have to set the variable the suite's own cache folder is given by.)
    """
    given = os.environ.get(CACHE_ENV)
    if given:
        return Path(given)
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "armanim" / "capsules"


def cache_inside(folder: Path) -> Path | None:
    """The capsule cache's folder when it is ``folder`` or lies inside it (a run folder, which a run
    replaces whole), else None."""
    try:
        cache, outer = capsule_cache_path().resolve(), Path(folder).resolve()
    except (OSError, RuntimeError):
        return None
    return cache if cache.is_relative_to(outer) else None
