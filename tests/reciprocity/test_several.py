"""How the reciprocity search drives the book of several sources
(reciprocity.strategies.imaging_search.several)."""

import numpy as np
import pytest

import arenas
from reciprocity.beliefs.imaging import ImagingMap
from reciprocity.errors import SearchError
from reciprocity.models.green import cached_solver
from reciprocity.strategies.imaging_search.several import MORE_TOL, SeveralSources


def test_the_task_sets_the_number_of_sources():
    solver = cached_solver(arenas.load("empty").without_scenario(), 4.0)
    im = ImagingMap(solver, 12.0, strength=850.0, combine="product")
    one, several = SeveralSources(), SeveralSources()
    one.start({}, im, 850.0, np.ones(len(solver.nodes)))
    assert one.bound == 1 and one.book is None and one.estimates is None and one.estimates_sd is None
    several.start(dict(max_sources=3), im, 850.0, np.ones(len(solver.nodes)))
    assert several.bound == 3 and several.book is not None and several.estimates.shape == (0, 2)
    capped = SeveralSources(max_sources=2)
    capped.start(dict(max_sources=3), im, 850.0, np.ones(len(solver.nodes)))
    assert capped.bound == 2
    assert SeveralSources().params(None) == dict(max_sources=None, more_tol=MORE_TOL, survey_travel=None,
                                                 survey_reach="reach")


def test_support_is_within_reach_or_along_the_free_region():
    class Reach:
        def within_path(self, length):
            return np.array([length > 10])
    near = lambda: np.array([True])
    assert SeveralSources().support(near, Reach())[0]
    assert SeveralSources(survey_reach=5.0).support(near, Reach())[0] == False   # noqa: E712


@pytest.mark.parametrize("bad, message", [(dict(max_sources=0), "max_sources must be"),
                                          (dict(more_tol=1.0), "more_tol must be a probability"),
                                          (dict(survey_travel=-1.0), "survey_travel must be"),
                                          (dict(survey_reach="far"), "survey_reach must be")])
def test_bad_settings_name_the_key(bad, message):
    with pytest.raises(SearchError, match=message):
        SeveralSources(**bad)
