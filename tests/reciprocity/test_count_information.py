"""The wind searches' "info" rule (issue 38): the count's information, the forward columns
that feed it, and the rule in an episode."""

import numpy as np
import pytest
from scipy.stats import poisson

from reciprocity.api import run
from reciprocity.errors import SearchError
from reciprocity.scenarios import from_dict
from reciprocity.strategies.count_information import count_information, systematic_sample
from reciprocity.strategies.reciprocity_wind import ArenaCounts, FreeSpaceCounts, WindReciprocity

from test_flow_world import MODEL_H, SCENARIO, SEED  # the duct of the flow-world tests


def _brute_force(mean: np.ndarray, group: np.ndarray) -> float:
    """I(n; group) of equally weighted samples, summed far into the tail."""
    n = np.arange(int(mean.max() * 3 + 60))
    groups = np.unique(group)
    cond = np.array([poisson.pmf(n[:, None], mean[group == g][None, :]).mean(axis=1) for g in groups])
    share = np.array([np.mean(group == g) for g in groups])
    marginal = share @ cond

    def entropy(p):
        p = p[p > 0]
        return -np.sum(p * np.log(p))
    return entropy(marginal) - sum(s * entropy(c) for s, c in zip(share, cond))


def test_count_information_agrees_with_a_brute_force_sum():
    rng = np.random.default_rng(3)
    for _ in range(20):
        m = int(rng.integers(2, 40))
        mean = rng.gamma(0.7, 6.0, (3, m)) + 1e-3
        group = rng.integers(0, max(1, m // 3), m)
        got = count_information(mean, group)
        want = [_brute_force(mean[c], group) for c in range(3)]
        assert np.allclose(got, want, atol=1e-3), (got, want)


def test_count_information_is_zero_where_the_groups_predict_the_same_count():
    mean = np.array([[4.0, 4.0, 4.0, 4.0], [4.0, 4.0, 0.1, 0.1], [4.0, 4.0, 30.0, 30.0]])
    info = count_information(mean, np.array([0, 0, 1, 1]))
    assert info[0] == pytest.approx(0.0, abs=1e-12)
    # a reading that tells two equally likely groups apart carries at most log 2
    assert 0 < info[1] < info[2] <= np.log(2) + 1e-9
    # samples of one group tell nothing about the group, however different their counts
    assert count_information(mean, np.zeros(4, int)) == pytest.approx(np.zeros(3), abs=1e-12)


def test_systematic_sample_follows_the_weights():
    w = np.array([0.0, 0.25, 0.0, 0.75])
    picks = systematic_sample(w, 400, np.random.default_rng(0))
    assert set(picks) <= {1, 3} and np.sum(picks == 1) == 100


@pytest.mark.parametrize("model", [ArenaCounts, FreeSpaceCounts])
def test_forward_columns_are_the_adjoint_readings_transposed(model):
    """Column j of from_sources is, at every reading node z, what rates(z) gives at node j
    (reciprocity: one forward solve per source instead of one adjoint solve per reading)."""
    told = from_dict(SCENARIO, "duct-wind").build_world(SEED).nominal()
    counts = model(told, MODEL_H)
    pts = counts.space.points
    sources = np.array([10, 200, 700])
    cols = counts.from_sources(sources)
    for z in (5, 333, 900):
        assert np.allclose(cols[z], counts.rates(pts[z])[sources], rtol=1e-8, atol=1e-14)


def test_the_info_rule_finds_the_source_and_repeats_itself():
    sc = from_dict(dict(SCENARIO, max_steps=40), "duct-wind")
    a, b = (run(sc, "reciprocity-wind", seed=SEED, params=dict(h=MODEL_H, rule="info")) for _ in range(2))
    assert a.summary["success"] and a.summary["converged"]
    assert a.summary["n_measurements"] == b.summary["n_measurements"]
    assert all(np.array_equal(x["points"], y["points"]) for x, y in zip(a.trace, b.trace))


def test_a_bad_rule_is_refused():
    with pytest.raises(SearchError, match="rule must be one of info, axis; got 'best'"):
        WindReciprocity(rule="best")
