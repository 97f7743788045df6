"""The backdrop's legend: an fk picture draws no goal and names none (issue 36).
"""

from __future__ import annotations


def test_fk_png_draws_no_goal_and_names_none_in_the_legend():
    from armanim.render.pictures.backdrop import legend_entries

    labels = [label for label, _ in legend_entries("pose", trail=True, obstacles=False, outcomes=frozenset(), hidden_goal=False, goals=False)]
    assert labels == ["arm"]


def test_the_amber_tint_is_named_in_the_legend_when_a_frame_shows_it(tmp_path):
    """Issue 50: panda-shelf's Panda turned tan in 73 frames and the legend did not say why. The
    video's legend names it from the run's self-clearance; the swatch is the tinted robot's colour."""
    import numpy as np
    from conftest import SCENES

    from armanim.render.paint.style import SELF_NEAR_COLOR
    from armanim.render.pictures.backdrop import ROBOT_LEGEND_COLOR, legend_entries
    from armanim.render.pictures.canvas import near_in_frames
    from armanim.render.solids.robot import NEAR_TINT
    from armanim.scene import load_scene, scene_to_problem

    problem = scene_to_problem(load_scene(SCENES / "panda-shelf.yaml").model)
    clearance = problem.self_pairs.clearance
    assert near_in_frames(problem, np.array([5 * clearance, 1.5 * clearance]))
    assert not near_in_frames(problem, np.array([5 * clearance, np.nan])) and not near_in_frames(problem, None)
    entries = dict(legend_entries("video", trail=True, obstacles=True, outcomes=frozenset({"reached"}), hidden_goal=False,
                                  robot=True, near_self=True))
    tint = np.asarray(ROBOT_LEGEND_COLOR) * (1 - NEAR_TINT) + np.asarray(SELF_NEAR_COLOR) * NEAR_TINT
    assert np.allclose(entries["near itself"].get_color(), tint)
    assert "near itself" not in dict(legend_entries("video", trail=True, obstacles=True, outcomes=frozenset(),
                                                    hidden_goal=False, robot=True))


def test_the_pen_is_no_colour_drawn_along_it():
    """Issue 50: ur5-pen's blue pen lay on the tool triad's blue z axis and read as one line. The pen's
    body is far from every colour drawn at the tool (the triad's axes) or near it (ink, tip path, near tint)."""
    import numpy as np
    from matplotlib.colors import to_rgb

    from armanim.render.paint.style import AXIS_COLORS, INK_COLOR, SELF_NEAR_COLOR, TRAIL_COLOR
    from armanim.scene.looks import PEN_BODY_RGB

    for color in (*AXIS_COLORS, INK_COLOR, TRAIL_COLOR, SELF_NEAR_COLOR):
        assert np.linalg.norm(np.subtract(PEN_BODY_RGB, to_rgb(color))) > 0.35, color
