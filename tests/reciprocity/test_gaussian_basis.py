"""The Gaussian-basis belief of Hajieghrary, Mox & Hsieh (2017, papers/001), Secs. 3.1-3.2."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.stats import poisson

from reciprocity.beliefs.gaussian_basis import GaussianBasisBelief, basis_width
from reciprocity.models.plume import PlumeParams, plume_rate
from reciprocity.observations import Observation

P = PlumeParams(rate=1.0, a=1.0, D=1.0, tau=100.0, V=0.1, form="isotropic")
BOUNDS = ((0.0, 200.0), (0.0, 200.0))


def belief(means, *, width=4.0, pose_variance=2.0, found_radius=2.0):
    return GaussianBasisBelief(P, means, BOUNDS, width=width, pose_variance=pose_variance,
                               found_radius=found_radius)


def hits(at, z):
    return Observation(np.asarray(at, dtype=float), float(z), 0.0, 1.0, "hits")


def test_entropy_of_one_gaussian_is_exact():
    b = belief([[100.0, 100.0]], width=3.0, pose_variance=2.0)
    assert b.entropy() == pytest.approx(np.log(2 * np.pi * np.e * (9.0 + 2.0)), rel=1e-12)


def test_entropy_of_far_apart_gaussians_is_the_discrete_one_plus_a_gaussian():
    b = belief([[20.0, 20.0], [100.0, 100.0], [180.0, 40.0]], width=1.0, pose_variance=0.0)
    w = np.array([0.5, 0.3, 0.2])
    discrete = -np.sum(w * np.log(w))
    assert b.entropies(w) == pytest.approx(discrete + np.log(2 * np.pi * np.e), rel=1e-9)


def test_entropy_falls_when_overlapping_gaussians_merge():
    apart = belief([[90.0, 100.0], [110.0, 100.0]], width=2.0).entropy()
    close = belief([[99.0, 100.0], [101.0, 100.0]], width=2.0).entropy()
    assert close < apart


def test_update_weights_by_the_likelihood_averaged_over_each_function():
    """Gauss-Hermite average (5 x 5 nodes) against a fine grid over one function (2 %)."""
    mu, s2 = np.array([110.0, 95.0]), 4.0 ** 2 + 2.0
    b = belief([mu], width=4.0, pose_variance=2.0)
    at = np.array([100.0, 100.0])
    g = np.linspace(-6, 6, 241) * np.sqrt(s2)
    gx, gy = np.meshgrid(g, g)
    r0 = np.column_stack([gx.ravel(), gy.ravel()]) + mu
    dens = np.exp(-0.5 * np.sum((r0 - mu) ** 2, axis=1) / s2)
    rate = plume_rate(at[None], r0, P)[0]
    for z in (0, 1, 2):
        brute = np.sum(dens * poisson.pmf(z, rate)) / np.sum(dens)
        assert np.exp(b.log_likelihood(hits(at, z))[0]) == pytest.approx(brute, rel=2e-2)


def test_update_is_bayes_consistent_with_the_outcome_table():
    """The posterior after reading z at a candidate is the outcome table's row for z."""
    rng = np.random.default_rng(3)
    b = belief(rng.uniform(0, 200, (60, 2)), width=basis_width(BOUNDS, 60))
    b.update(hits([60.0, 60.0], 1))
    cands = np.array([[100.0, 100.0], [40.0, 150.0]])
    joint, p_found, _ = b.outcomes(cands, eta=1e-6)
    assert joint.sum(axis=(0, 2)) == pytest.approx(np.ones(2), abs=1e-4)
    assert np.all((p_found >= 0) & (p_found < 1))
    for j, c in enumerate(cands):
        for z in range(joint.shape[0]):
            after = belief(b.support(), width=basis_width(BOUNDS, 60))
            after.logw, after._w = b.logw.copy(), b.weights().copy()
            after.update(hits(c, z))
            assert after.weights() == pytest.approx(joint[z, j] / joint[z, j].sum(), rel=1e-6, abs=1e-12)


def test_updates_commute_and_no_function_is_lost():
    rng = np.random.default_rng(5)
    means = rng.uniform(0, 200, (40, 2))
    a, b = belief(means), belief(means)
    one, two = hits([50.0, 50.0], 0), hits([120.0, 80.0], 2)
    a.update(one), a.update(two)
    b.update(two), b.update(one)
    assert a.weights() == pytest.approx(b.weights(), rel=1e-9)
    assert len(a.support()) == 40 and np.allclose(a.support(), means)
    assert a.weights().sum() == pytest.approx(1.0)


def test_a_hit_moves_mass_toward_the_reading_and_a_miss_away_from_it():
    means = np.array([[100.0, 104.0], [100.0, 180.0]])
    hit, miss = belief(means), belief(means)
    hit.update(hits([100.0, 100.0], 1))
    miss.update(hits([100.0, 100.0], 0))
    assert hit.weights()[0] > 0.5 > miss.weights()[0]


def test_the_search_going_on_rules_out_the_found_disc():
    b = belief([[100.0, 100.0], [150.0, 150.0]], width=0.5, pose_variance=0.0, found_radius=2.0)
    b.update(hits([100.0, 100.0], 0))
    assert b.weights()[0] < 1e-3     # the disc holds all but exp(-8) of it


def test_entropy_stays_finite_when_the_mixture_underflows_at_a_mean():
    """A weight vector on one far corner leaves g(μ) = 0 at the other means: the entropy is
    that of the one Gaussian, not NaN."""
    b = belief([[5.0, 5.0], [195.0, 195.0], [100.0, 20.0]], width=1.0, pose_variance=0.0)
    for w in ([1.0, 0.0, 0.0], [1.0, 1e-320, 0.0]):
        assert b.entropies(np.array(w)) == pytest.approx(np.log(2 * np.pi * np.e), rel=1e-9)
