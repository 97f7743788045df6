"""The backdrop's legend: an fk picture draws no goal and names none (issue 36).
"""

from __future__ import annotations


def test_fk_png_draws_no_goal_and_names_none_in_the_legend():
    from armanim.render.pictures.backdrop import legend_entries

    labels = [label for label, _ in legend_entries("pose", trail=True, obstacles=False, outcomes=frozenset(), hidden_goal=False, goals=False)]
    assert labels == ["arm"]
