"""Property tests decided by the commit, never by chance (issue 50, item 13): CI loads the
Hypothesis profile ``ci`` (derandomize: the same examples on every run), ``.ci/run`` does too, and
``explore`` runs ten times each test's own examples for a search by hand (tests/conftest.py)."""

from __future__ import annotations

from types import SimpleNamespace

import conftest
from conftest import ROOT
from hypothesis import given, settings
from hypothesis import strategies as st


def _draws(profile: str, count: int = 25) -> list:
    drawn: list = []

    @settings(settings.get_profile(profile), max_examples=count)
    @given(st.floats(allow_nan=False), st.lists(st.integers(), max_size=5))
    def probe(x, xs):
        drawn.append((x, tuple(xs)))

    probe()
    return drawn


def test_the_ci_profile_draws_the_same_examples_every_run():
    assert settings.get_profile("ci").derandomize and settings.get_profile("ci").database is None
    first = _draws("ci")
    assert len(first) == 25 and _draws("ci") == first


def test_ci_loads_the_ci_profile_and_so_does_the_ci_script():
    assert conftest.hypothesis_profile({"CI": "true"}) == "ci"
    assert conftest.hypothesis_profile({}) == "armanim"
    assert conftest.hypothesis_profile({"CI": "true", "ARMANIM_HYPOTHESIS_PROFILE": "explore"}) == "explore"
    script = (ROOT / ".ci" / "run").read_text()
    assert "export ARMANIM_HYPOTHESIS_PROFILE=ci" in script
    assert script.index("export ARMANIM_HYPOTHESIS_PROFILE=ci") < script.index('bash -euo pipefail -c "$command"')


def test_explore_runs_ten_times_each_tests_own_examples():
    @settings(max_examples=7)
    @given(st.integers())
    def own(x):
        pass

    previous = settings.get_current_profile_name()
    settings.load_profile("explore")
    try:
        conftest.pytest_collection_modifyitems(None, [SimpleNamespace(obj=own), SimpleNamespace(obj=own)])
    finally:
        settings.load_profile(previous)
    assert own._hypothesis_internal_use_settings.max_examples == 7 * conftest.EXPLORE_FACTOR  # scaled once
    assert settings.get_profile("explore").max_examples == 30 * conftest.EXPLORE_FACTOR
