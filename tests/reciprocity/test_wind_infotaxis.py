"""Infotaxis in wind (``infotaxis-wind``, ``free-space-infotaxis-wind``): the expected entropy
of a count, the moves, and an episode on a small duct."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.stats import poisson

from reciprocity.api import run
from reciprocity.env import SearchEnv
from reciprocity.errors import SearchError
from reciprocity.scenarios import from_dict
from reciprocity.strategies.base import SearchContext
from reciprocity.strategies.infotaxis_wind import WindInfotaxis, expected_entropy

DUCT = {"name": "duct", "boundary": [[0, 0], [60, 0], [60, 40], [0, 40]],
        "obstacles": [[[28, 12], [34, 12], [34, 28], [28, 28]]]}
SCENARIO = {"world": "flow", "arena": DUCT, "source": [18, 22], "start": [52, 8, 90],
            "inflow": [[[0, 0], [0, 40]]], "outflow": [[[60, 0], [60, 40]]], "speed": 1, "D": 5, "tau": 60,
            "strength": 100, "detector": 1, "truth_h": 1, "max_steps": 60}


def _entropy(p):
    p = p[p > 0]
    return float(-(p * np.log(p)).sum())


def test_the_expected_entropy_of_two_nodes_is_the_sum_over_counts():
    """Two nodes, one rate each: Σ_k p(k) H(x | k) summed by hand over k = 0..200. The score
    stops at the 1 - 1e-4 quantile of the largest mean's counts, so it may differ by about
    that share."""
    w, mean = np.array([0.3, 0.7]), np.array([2.0, 9.0])
    k = np.arange(201)
    joint = w[None, :] * poisson.pmf(k[:, None], mean[None, :])
    p_k = joint.sum(axis=1)
    by_hand = sum(p_k[i] * _entropy(joint[i] / p_k[i]) for i in range(len(k)) if p_k[i] > 0)
    assert expected_entropy(w, np.array([0, 1]), mean, 2) == pytest.approx(by_hand, rel=1e-3)


def test_a_count_is_expected_to_leave_no_more_entropy_than_the_prior():
    """Information never hurts in expectation: E[H(x | k)] ≤ H(x), on random posteriors over
    (node, rate) pairs; a reading that cannot tell the nodes apart leaves H(x)."""
    rng = np.random.default_rng(0)
    for _ in range(20):
        n, m = 6, 30
        node = rng.integers(0, n, m)
        w = rng.dirichlet(np.ones(m))
        mean = rng.uniform(0.1, 30.0, m)
        prior = _entropy(np.bincount(node, weights=w, minlength=n))
        assert expected_entropy(w, node, mean, n) <= prior + 1e-9
    node = np.array([0, 1, 2])
    w = np.array([0.2, 0.3, 0.5])
    assert expected_entropy(w, node, np.full(3, 4.0), 3) == pytest.approx(_entropy(w), rel=1e-9)


def test_the_moves_are_one_per_sector_within_a_step():
    sc = from_dict(SCENARIO, "duct-wind")
    strat = WindInfotaxis(step=8.0, moves=8)
    env = SearchEnv(sc)
    _, info = env.reset(seed=0)
    task = info["task"]
    strat.start(SearchContext(task.world, task.nominal, np.array(task.starts), np.random.default_rng(0)))
    cands = strat._moves()
    here = np.array(task.starts)[0][:2]
    # by brute force: per sector of 45°, the admissible node between 4 and 8 cm whose
    # distance is nearest to the step
    pts = strat.space.points
    r = pts - here
    dist = np.hypot(r[:, 0], r[:, 1])
    ok = strat._reachable & strat._far & (dist > 4.0) & (dist <= 8.0)
    sector = np.floor((np.arctan2(r[:, 1], r[:, 0]) + np.pi) / (2 * np.pi) * 8).astype(int)
    want = {}
    for i in np.flatnonzero(ok):
        if sector[i] not in want or dist[i] > dist[want[sector[i]]]:
            want[sector[i]] = i
    assert len(want) >= 3                                 # the duct leaves several directions open
    assert len(cands) == len(want)
    got = {tuple(np.round(c, 9)) for c in cands}
    assert got == {tuple(np.round(pts[i], 9)) for i in want.values()}


@pytest.mark.parametrize("name", ["infotaxis-wind", "free-space-infotaxis-wind"])
def test_infotaxis_in_wind_runs_an_episode_and_reports_its_parameters(name):
    episode = run(from_dict(SCENARIO, "duct-wind"), name, seed=0, params={"h": 2.0, "max_steps": 25})
    s = episode.summary
    assert s["strategy"] == name and 1 <= s["n_measurements"] <= 25
    assert s["params"]["step"] == 8.0 and s["params"]["source_clearance"] == "task"


def test_bad_moves_are_refused():
    with pytest.raises(SearchError, match="moves"):
        WindInfotaxis(moves=0)
