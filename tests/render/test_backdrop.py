"""The backdrop's legend: an fk picture draws no goal and names none (issue 36)."""

from __future__ import annotations


def test_fk_png_draws_no_goal_and_names_none_in_the_legend():
    from armanim.render.pictures.backdrop import legend_entries

    labels = [
        label
        for label, _ in legend_entries(
            "pose", trail=True, obstacles=False, outcomes=frozenset(), hidden_goal=False, goals=False
        )
    ]
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
    entries = dict(
        legend_entries(
            "video",
            trail=True,
            obstacles=True,
            outcomes=frozenset({"reached"}),
            hidden_goal=False,
            robot=True,
            near_self=True,
        )
    )
    tint = np.asarray(ROBOT_LEGEND_COLOR) * (1 - NEAR_TINT) + np.asarray(SELF_NEAR_COLOR) * NEAR_TINT
    assert np.allclose(entries["near itself"].get_color(), tint)
    assert "near itself" not in dict(
        legend_entries("video", trail=True, obstacles=True, outcomes=frozenset(), hidden_goal=False, robot=True)
    )


def test_the_pen_is_no_colour_drawn_along_it():
    """Issue 50: ur5-pen's blue pen lay on the tool triad's blue z axis and read as one line. The pen's
    body is far from every colour drawn at the tool (the triad's axes) or near it (ink, tip path, near tint)."""
    import numpy as np
    from matplotlib.colors import to_rgb

    from armanim.render.paint.style import AXIS_COLORS, INK_COLOR, SELF_NEAR_COLOR, TRAIL_COLOR
    from armanim.scene.looks import PEN_BODY_RGB

    for color in (*AXIS_COLORS, INK_COLOR, TRAIL_COLOR, SELF_NEAR_COLOR):
        assert np.linalg.norm(np.subtract(PEN_BODY_RGB, to_rgb(color))) > 0.35, color


def test_a_path_goal_s_marker_is_open_so_its_ink_shows_through():
    """Issue 50: goal markers covered the first letter of the ink ("rmanim"). A path goal's marker
    (at its path's start) is a ring: the pixel under its centre is left as it was; a point goal's is filled."""
    import numpy as np

    from armanim.render.overlay.caption import CURRENT, REACHED
    from armanim.render.overlay.markers import GoalMarkers
    from armanim.render.paint.pixels import composite, make_figure

    fig, _ = make_figure(200, 100, 100)
    scratch = make_figure(60, 60, 100)[1]
    markers = GoalMarkers(
        fig,
        np.array([[50.0, 50.0, 0.0], [150.0, 50.0, 0.0]]),
        np.zeros(2, dtype=bool),
        (200, 100),
        open_goals=np.array([True, False]),
    )
    for code in (REACHED, CURRENT):
        frame = np.zeros((100, 200, 4), dtype=np.uint8)
        frame[..., :3] = (20, 30, 90)  # ink everywhere
        frame[..., 3] = 255
        for goal in (0, 1):
            composite(frame, markers._stamp(scratch, goal, code))
        assert tuple(frame[50, 50, :3]) == (20, 30, 90), code  # the path goal's centre: the ink
        assert tuple(frame[50, 150, :3]) != (20, 30, 90), code  # the point goal's: its marker
