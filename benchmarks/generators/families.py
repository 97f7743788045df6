"""The motion benchmark's scene families by ``--family``: scene K of a seed, drawn until armanim
accepts it, and its name.
"""

from __future__ import annotations

import numpy as np
from pydantic import ValidationError

from armanim.scene import scene_model
from armanim.scene.checks import scene_problems
from generators.arms import Draft, draw_hard_scene, draw_robot_scene, draw_scene
from generators.shapes import draw_pose_scene, draw_robot_shapes_scene, draw_shapes_scene

FAMILIES = {
    "standard": draw_scene,
    "hard": draw_hard_scene,
    "robots": draw_robot_scene,
    "poses": draw_pose_scene,
    "shapes": draw_shapes_scene,
    "robot-shapes": draw_robot_shapes_scene,
}


SHAPE_FAMILIES = ("shapes", "robot-shapes")


FAMILY_STREAMS = {"hard": 2, "robots": 3, "shapes": 4, "robot-shapes": 5, "poses": 4}
"""The random stream of each family's scenes, fixed so that published figures stay reproducible
(poses and shapes share a number; their generators differ, so their scenes do too)."""
"""Scene generators by ``--family``: the original distribution, the hard one of issue 18
(7-link mixed-axis and planar arms, tight limits everywhere, narrow passages, dense clutter,
goals near spheres and at the edge of reach, 8-12 goals) and the robots of issue 20
(a bundled Panda, UR5 or iiwa among 3-10 spheres, 3-5 goals)."""


def armanim_rejects(scene: dict) -> list:
    """armanim's own objections to a scene mapping: pydantic errors or cross-field problems (empty: valid)."""
    try:
        model = scene_model(scene)
    except ValidationError as exc:
        return [str(exc)]
    return scene_problems(model)


def make_scene(seed: int, index: int, family: str = "standard") -> Draft:
    """Scene ``index`` of the benchmark for ``seed``: drawn until armanim accepts it.

    Parameters
    ----------
    seed : int
        The benchmark's ``--seed``.
    index : int
        0-based scene index; the scene depends only on (seed, index, family).
    family : str
        A key of :data:`FAMILIES`.

    Returns
    -------
    Draft
    """
    rng = np.random.default_rng([seed, index] if family == "standard" else [seed, index, FAMILY_STREAMS[family]])
    while True:
        draft = FAMILIES[family](rng)
        enough = (
            (len(draft.boxes) + len(draft.rods) >= 2 and len(draft.goals) >= 2)
            if family in SHAPE_FAMILIES
            else len(draft.spheres) >= (3 if family in ("robots", "poses") else 2)
        )
        if enough and not armanim_rejects(draft.as_scene_dict(scene_name(seed, index))):
            return draft


def scene_name(seed: int, index: int, method: str | None = None, planner: str | None = None) -> str:
    """The scene's ``name`` (and output folder of ``armanim run``)."""
    return "-".join(str(p) for p in (f"bench-s{seed}-k{index}", method, planner) if p is not None)
