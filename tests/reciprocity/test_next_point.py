"""The next-point rule of the reciprocity search (step 13,
reciprocity.strategies.imaging_search.next_point): its scores against brute force, and the
point each rule picks on hand-built beliefs."""

import numpy as np
import pytest

import arenas
from reciprocity.beliefs.imaging import ImagingMap
from reciprocity.errors import SearchError
from reciprocity.models.green import cached_solver
from reciprocity.spaces import mesh_space
from reciprocity.strategies.imaging_search.next_point import (NextPointRule, axis_point, mass_within_reach,
                                                              reach_test_point, survey_point)


@pytest.fixture(scope="module")
def setting():
    geometry = arenas.load("empty").without_scenario()
    solver = cached_solver(geometry, 3.0)
    return solver, mesh_space(geometry, 3.0)


def belief(solver, P):
    im = ImagingMap(solver, 12.0, strength=850.0, combine="product")
    im.add((20.0, 20.0), 0.0)
    im._cache["P"] = np.asarray(P, dtype=float)
    return im


def test_mass_within_reach_against_the_sum():
    rng = np.random.default_rng(0)
    support, w, cand = rng.uniform(0, 100, (300, 2)), rng.uniform(0, 1, 300), rng.uniform(10, 90, (20, 2))
    exact = np.array([np.sum(w * np.exp(-np.sum((support - y) ** 2, 1) / (2 * 12.0 ** 2))) for y in cand])
    got = mass_within_reach(cand, support, w, 12.0)
    assert np.allclose(got, exact, rtol=0.03)          # of order (cell / reach)^2 = 1/36


def test_axis_point_waits_for_a_concentrated_belief(setting):
    solver, space = setting
    allowed = np.ones(len(space.points), dtype=bool)
    wide = np.ones(len(space.points))
    assert axis_point(space, wide, allowed, 12.0, 6.0) is None
    # an elongated belief along x around (70, 70): the point lies on its axis, off its centre
    narrow = np.exp(-((space.points[:, 0] - 70) / 5.0) ** 2 - ((space.points[:, 1] - 70) / 1.5) ** 2)
    p = axis_point(space, narrow, allowed, 12.0, 6.0)
    assert abs(p[1] - 70.0) <= solver.h and 6.0 - solver.h <= abs(p[0] - 70.0) <= 12.0 + solver.h


def test_reach_test_point_reads_beside_the_belief_within_reach(setting):
    solver, space = setting
    near = space.points[:, 0] < 60
    blob = np.hypot(*(space.points - (40.0, 100.0)).T) < 5
    w = np.where(space.points[:, 0] > 110, 1.0, 0.0) + np.where(blob, 3.0, 0.0)
    allowed = np.ones(len(space.points), dtype=bool)
    p = reach_test_point(space, allowed, near, w, 12.0)
    assert np.hypot(*(p - (40.0, 100.0))) < 5.0
    assert reach_test_point(space, allowed, np.zeros_like(near), w, 12.0) is None


def test_survey_point_with_a_travel_discount_prefers_the_near_hidden_part(setting):
    solver, space = setting
    x = space.points[:, 0]
    hidden = np.where((x < 30) | (x > 110), 1.0, 0.0)
    hidden[x > 110] *= 1.2                              # a little more hidden on the right
    allowed = np.ones(len(space.points), dtype=bool)
    assert survey_point(space, allowed, hidden, 12.0, None, np.array([20.0, 70.0]))[0] > 100
    assert survey_point(space, allowed, hidden, 12.0, 20.0, np.array([20.0, 70.0]))[0] < 40
    assert survey_point(space, np.zeros_like(allowed), hidden, 12.0, None, np.zeros(2)) is None


@pytest.mark.parametrize("name", ["reach", "axis"])
def test_a_blob_is_read_beside_or_at_it(setting, name):
    solver, space = setting
    im = belief(solver, np.exp(-np.sum((solver.nodes - (90.0, 60.0)) ** 2, 1) / 50.0))
    rule = NextPointRule(name, 6.0, 12.0)
    rule.start(space, solver, np.random.default_rng(0))
    allowed = rule.separated(im.points)
    p, undecided = rule.choose(im, allowed, 12.0)
    assert not undecided and np.hypot(*(p - (90.0, 60.0))) <= 12.0 + solver.h


def test_nearest_reads_next_to_the_last_point(setting):
    solver, space = setting
    im = belief(solver, np.ones(len(solver.nodes)))
    rule = NextPointRule("nearest", 10.0, 12.0)
    rule.start(space, solver)
    p, _ = rule.choose(im, rule.separated(im.points), 12.0)
    assert 10.0 - 1e-9 <= np.hypot(*(p - 20.0)) <= 10.0 + 2 * solver.h


def test_separated_is_kept_up_to_date(setting):
    solver, space = setting
    rule = NextPointRule("axis", 10.0, 12.0)
    rule.start(space, solver)
    first = rule.separated(np.array([[20.0, 20.0]])).copy()
    both = rule.separated(np.array([[20.0, 20.0], [100.0, 100.0]]))
    assert first.sum() > both.sum() and not both[np.hypot(*(space.points - 100.0).T) < 10.0 - 1e-9].any()


@pytest.mark.parametrize("bad, message", [(dict(rule="spiral"), "rule must be one of"),
                                          (dict(d=0.0), "d must be a positive number"),
                                          (dict(reach=np.inf), "reach must be a positive number")])
def test_bad_settings_name_the_key(bad, message):
    with pytest.raises(SearchError, match=message):
        NextPointRule(**bad)


def test_lookahead_reads_where_two_modes_differ(setting):
    """Two equal modes far apart: the two-step rule reads where their predicted readings
    differ (near one of them), not midway where both predict the same."""
    solver, space = setting
    d1 = np.sum((solver.nodes - (30.0, 70.0)) ** 2, 1)
    d2 = np.sum((solver.nodes - (110.0, 70.0)) ** 2, 1)
    im = belief(solver, np.exp(-d1 / 8.0) + np.exp(-d2 / 8.0))
    rule = NextPointRule("lookahead", 6.0, 12.0)
    rule.start(space, solver, np.random.default_rng(0))
    p, undecided = rule.choose(im, rule.separated(im.points), 12.0)
    assert not undecided
    assert min(np.hypot(*(p - (30.0, 70.0))), np.hypot(*(p - (110.0, 70.0)))) < 30.0
