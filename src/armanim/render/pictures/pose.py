"""One pose of the arm to a PNG (``armanim fk --png``), drawn by the scene canvas."""

from __future__ import annotations

import numpy as np

from armanim.arm.kinematics import forward, joints_shown
from armanim.arm.visuals import ArmMeshes
from armanim.motion.problem import Problem
from armanim.output.numbers import number
from armanim.render.overlay.caption import PENDING
from armanim.render.paint.pixels import write_png
from armanim.render.pictures.canvas import FrameState, SceneCanvas
from armanim.render.settings import RenderSettings
from armanim.render.solids.arm import near_capsules


def pose_caption(problem: Problem, phi: np.ndarray) -> str:
    """Caption of a single pose: its joint angles in degrees and its tip."""
    tip = forward(problem.arm, phi).tip
    angles = ", ".join(
        number(a, 360, 4) for a in joints_shown(phi, problem.arm.prismatic)
    )  # metres for a prismatic joint
    return f"phi = [{angles}] deg   tip = ({', '.join(number(v, problem.arm.reach, 4) for v in tip)})"


def render_pose_png(
    problem: Problem, phi: np.ndarray, settings: RenderSettings, path, *, title: str, meshes: ArmMeshes | None = None
) -> None:
    """Draw one pose of the arm (:func:`draw_pose`) to the PNG file ``path`` (str or Path),
    written to a temporary file beside it, then moved in place."""
    write_png(draw_pose(problem, phi, settings, title=title, meshes=meshes), path)


def draw_pose(
    problem: Problem, phi: np.ndarray, settings: RenderSettings, *, title: str, meshes: ArmMeshes | None = None
) -> np.ndarray:
    """(H, W, 4) uint8: one pose of the arm drawn at ``settings.size`` pixels.

    Parameters
    ----------
    problem : Problem
        The arm, its obstacles and goals (all goals drawn as pending).
    phi : (n,) array
        Joint angles, radians.
    settings : RenderSettings
        Size, view and bounds (``trail`` and ``format`` are not used).
    title : str
        Shown top left.
    meshes : ArmMeshes, optional
        The robot's look and the scene's furniture, as a run's pictures draw them (None: the
        arm's capsules).
    """
    phi = np.asarray(phi, dtype=float)
    pose = forward(problem.arm, phi)
    caption = pose_caption(problem, phi)
    near = near_capsules(problem, pose)
    scene = SceneCanvas(
        problem,
        settings,
        title=title,
        extent=pose.points,
        picture="pose",
        caption_template=caption,
        meshes=meshes,
        near_self=near is not None and bool(near.any()),
    )
    state = FrameState(pose=pose, trail_end=0, goal_status=np.full(len(problem.goals), PENDING), caption=caption)
    return scene.draw(state)
