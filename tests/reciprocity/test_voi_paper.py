"""``voi`` with the paper's own set-up (papers/001): preset, belief, Remark 3, plain resampling."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from reciprocity.api import run
from reciprocity.beliefs.gaussian_basis import GaussianBasisBelief
from reciprocity.errors import SearchError
from reciprocity.observations import MessageLog, Observation
from reciprocity.scenarios import load_scenario
from reciprocity.strategies import STRATEGIES
from reciprocity.strategies.base import SearchContext

VOI = STRATEGIES["voi"]


def started(n_agents=3, **params):
    """A `voi` team started on the `hajieghrary` scenario's nominal description (what a
    strategy is told), with a seeded generator."""
    world = load_scenario("hajieghrary").build_world(0)
    s = VOI(**params)
    starts = np.array([[20.0, 20.0, 0.0], [20.0, 180.0, 0.0], [180.0, 20.0, 0.0]])[:n_agents]
    s.start(SearchContext("plume", world.nominal(), starts, np.random.default_rng(1), MessageLog()))
    return s


def test_paper_preset_builds_gaussian_basis_searchers():
    s = started(preset="paper", basis=50)
    assert all(isinstance(t.belief, GaussianBasisBelief) and t.belief.M == 50 for t in s.searchers)
    assert s.setup["own"] == "voi" and s.setup["pose_variance"] == 2.0
    assert s.params()["belief"] == "gaussian-basis" and "belief" not in VOI().params()


def test_explicit_parameters_win_over_the_preset():
    s = VOI(preset="paper", own="all", pose_variance=0.5)
    assert s.setup["own"] == "all" and s.setup["pose_variance"] == 0.5 and s.setup["basis"] == 300


def test_plain_resampling_never_moves_a_particle():
    s = started(particles=200, rejuvenate=False)
    assert all(t.belief.mcmc_steps == 0 for t in s.searchers)
    b = s.searchers[0].belief
    before = {tuple(p) for p in b.support()}
    for k in range(30):
        b.update(Observation(np.array([100.0 + k, 100.0]), 2.0, float(k), 1.0, "hits"))
    assert b.n_resampled > 0 and {tuple(p) for p in b.support()} <= before


def test_remark_3_a_robot_may_drop_its_own_hit():
    """With own='voi' and a threshold no event reaches, a robot's own hit leaves its belief
    as it was; its nulls still enter; with own='all' the hit enters."""
    hit = Observation(np.array([22.0, 22.0]), 1.0, 0.0, 1.0, "hits")
    null = Observation(np.array([22.0, 22.0]), 0.0, 0.0, 1.0, "hits")
    for own, changes in (("voi", False), ("all", True)):
        s = started(preset="paper", basis=40, own=own, share="none", threshold=1e6)
        s.propose()
        w0 = s.searchers[0].belief.weights().copy()
        s.observe([hit], None, 0)
        assert (not np.allclose(s.searchers[0].belief.weights(), w0)) is changes
        assert np.allclose(s.searchers[0].pos, hit.position)
    s.observe([null], None, 0)
    assert not np.allclose(s.searchers[0].belief.weights(), w0)


def test_value_of_information_of_a_basis_belief_is_positive_and_finite():
    s = started(preset="paper", basis=40)
    b = s.searchers[0].belief
    v = s.value_of_information(b, Observation(np.array([100.0, 100.0]), 1.0, 0.0, 1.0, "hits"))
    assert np.isfinite(v) and v > 0


def test_a_short_paper_episode_runs_and_shares():
    sc = replace(load_scenario("hajieghrary"), max_steps=4)
    ep = run(sc, "voi", seed=1, params=dict(preset="paper", basis=40, share="all"))
    assert ep.summary["steps"] == 4 and ep.summary["messages"] == 3 * 4


@pytest.mark.parametrize("key, value, match", [
    ("belief", "grid", "belief must be 'particles' or 'gaussian-basis'"),
    ("own", "some", "own must be 'all' or 'voi'"),
    ("preset", "fast", "preset must be 'paper'"),
    ("basis", 5, "basis must be at least"),
    ("rejuvenate", "yes", "rejuvenate must be true or false"),
])
def test_bad_values_are_refused(key, value, match):
    with pytest.raises(SearchError, match=match):
        VOI(**{key: value})
