"""The scene file: pydantic models, YAML loading with line numbers, Scene -> Problem."""

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
    "LoadedScene", "SceneModel", "default_render_settings", "default_solver_settings", "load_scene", "render_settings",
    "scene_from_bytes", "scene_model", "scene_to_problem", "unlimited_limits", "validate_scene_text",
]
