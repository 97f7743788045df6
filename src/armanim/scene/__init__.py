"""The scene file: YAML with line numbers, validation, the arm's files, Scene -> Problem.

In this order, each module importing only those before it: the values a scene may hold
(``fields``), the pydantic models (``models``, ``armmodel``: validation reads no file), the
URDF and SRDF readers and the bundled robots (``urdf``, ``srdf``, ``robots``: read after
validation), joint limits and rates (``limits``), Scene -> Problem (``convert``, where degrees
become radians, for scene files and ``fk``/``ik`` flags alike), the checks that span fields
(``checks``) and the loader that runs them all (``loader``).
"""

from armanim.scene.convert import (
    default_render_settings,
    default_solver_settings,
    render_settings,
    scene_to_problem,
)
from armanim.scene.limits import unlimited_limits
from armanim.scene.loader import LoadedScene, load_scene, scene_from_bytes, scene_model, validate_scene_text
from armanim.scene.models import SceneModel

__all__ = [
    "LoadedScene",
    "SceneModel",
    "default_render_settings",
    "default_solver_settings",
    "load_scene",
    "render_settings",
    "scene_from_bytes",
    "scene_model",
    "scene_to_problem",
    "unlimited_limits",
    "validate_scene_text",
]
