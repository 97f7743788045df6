"""The scene file: pydantic models, YAML loading with line numbers, Scene -> Problem."""

from armanim.scene.convert import render_settings, scene_to_problem
from armanim.scene.loader import LoadedScene, load_scene, scene_from_bytes, validate_scene_text
from armanim.scene.models import SceneModel

__all__ = ["LoadedScene", "SceneModel", "load_scene", "scene_from_bytes", "render_settings", "scene_to_problem", "validate_scene_text"]
