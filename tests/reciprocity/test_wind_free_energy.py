"""Free-energy infotaxis in wind (``free-energy-wind``, ``free-space-free-energy-wind``): the
expected free energy of a count, and an episode on a small duct."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.stats import poisson

from reciprocity.api import run
from reciprocity.errors import SearchError
from reciprocity.scenarios import from_dict
from reciprocity.strategies.free_energy_wind import WindFreeEnergy, expected_free_energy
from test_wind_infotaxis import SCENARIO  # the duct of the infotaxis-in-wind tests


def test_the_expected_free_energy_of_two_nodes_is_the_sum_over_counts():
    """Two nodes, one rate each: Σ_k p(k) [W_k + α tr(Σ_k)^β S_k] summed by hand over
    k = 0..200 (the score stops at the 1 - 1e-4 quantile of the largest mean's counts)."""
    w, mean = np.array([0.3, 0.7]), np.array([2.0, 9.0])
    nodes = np.array([[0.0, 0.0], [3.0, 4.0]])
    z = np.array([0.0, 4.0])
    alpha, beta, gamma = 0.5, 1.4, 3.0
    k = np.arange(201)
    joint = w[None, :] * poisson.pmf(k[:, None], mean[None, :])
    p_k = joint.sum(axis=1)
    total = 0.0
    for i in range(len(k)):
        if p_k[i] == 0:
            continue
        post = joint[i] / p_k[i]
        energy = post @ np.hypot(*(nodes - z).T) ** gamma
        centre = post @ nodes
        spread = post @ np.sum((nodes - centre) ** 2, axis=1)
        entropy = -sum(p * np.log(p) for p in post if p > 0)
        total += p_k[i] * (energy + alpha * spread ** beta * entropy)
    got = expected_free_energy(w, np.array([0, 1]), mean, nodes, z, alpha, beta, gamma)
    assert got == pytest.approx(total, rel=1e-3)


def test_one_node_leaves_only_the_potential_energy():
    """A posterior on one node: no spread, no entropy; the score is its distance to the
    power γ, however many rates the pairs hold."""
    nodes = np.array([[1.0, 1.0], [5.0, 5.0]])
    got = expected_free_energy(np.array([0.5, 0.5]), np.array([1, 1]), np.array([3.0, 8.0]), nodes,
                               np.array([2.0, 5.0]), 0.01, 1.4, 3.0)
    assert got == pytest.approx(27.0)


@pytest.mark.parametrize("name", ["free-energy-wind", "free-space-free-energy-wind"])
def test_free_energy_in_wind_runs_an_episode_and_reports_its_parameters(name):
    sc = from_dict(dict(SCENARIO, max_steps=30), "duct-wind")
    a, b = (run(sc, name, seed=0, params=dict(h=2.0, step=6.0)) for _ in range(2))
    s = a.summary
    assert s["strategy"] == name and 1 <= s["n_measurements"] <= 30
    assert s["n_measurements"] == b.summary["n_measurements"]
    assert all(np.array_equal(x["points"], y["points"]) for x, y in zip(a.trace, b.trace))
    assert s["params"]["alpha"] == 0.01 and s["params"]["gamma"] == 3.0 and s["params"]["step"] == 6.0


def test_bad_free_energy_parameters_are_refused():
    with pytest.raises(SearchError, match="alpha"):
        WindFreeEnergy(alpha=-1.0)
    with pytest.raises(SearchError, match="gamma"):
        WindFreeEnergy(gamma=0.0)
