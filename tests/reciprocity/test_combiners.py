"""The map combiners of the imaging map (reciprocity.beliefs.combiners): the mean of
eq. (8) and the product, with exact references for the correlated and marginal misfits."""

import numpy as np
import pytest
from scipy.integrate import quad

import arenas
from reciprocity.beliefs.combiners import (COMBINATIONS, COMBINERS, correlated_misfit, marginal_misfit)
from reciprocity.beliefs.imaging import ImagingMap
from reciprocity.models.green import cached_solver


@pytest.fixture(scope="module")
def solver():
    return cached_solver(arenas.load("empty").without_scenario(), 4.0)


def _map(solver, combine, **kw):
    u = solver.field((90.0, 60.0), strength=600.0)
    im = ImagingMap(solver, 12.0, strength=600.0, combine=combine, **kw)
    for z in [(30.0, 30.0), (60.0, 100.0), (110.0, 30.0)]:
        im.add(z, float(u([z])[0]) + 3.0)
    return im


def test_every_combination_has_a_combiner():
    assert set(COMBINERS) == set(COMBINATIONS) and all(COMBINERS[k].name == k for k in COMBINATIONS)


def test_mean_is_eq_8(solver):
    im = _map(solver, "mean")
    assert np.array_equal(im.values(), im.p_maps().mean(axis=1))


def test_product_is_the_rescaled_likelihood(solver):
    im = _map(solver, "product")
    s = np.sum(im._residuals() ** 2, axis=1)
    assert np.allclose(im.values(), np.exp(-(s - s.min())), rtol=1e-12, atol=0) and im.values().max() == 1.0
    # where no source may lie the product is 0, the mean too
    im.restrict(solver.nodes[:, 0] > 70.0)
    assert np.all(im.values()[solver.nodes[:, 0] <= 70.0] == 0.0)


def test_correlated_misfit_without_errors_is_the_sum_of_squares():
    r = np.random.default_rng(0).normal(size=(5, 4))
    assert np.allclose(correlated_misfit(r, 3.0, np.ones((5, 4)), 0.0, 0.0), np.sum(r * r, axis=1), rtol=1e-12)


def test_correlated_misfit_is_the_gaussian_with_a_shared_offset():
    """Sherman-Morrison against the dense covariance ``diag(d) + b^2 11^T``."""
    rng = np.random.default_rng(1)
    sigma, model_error, b = 2.0, 0.1, 1.5
    r, v = rng.normal(size=(3, 4)), rng.uniform(5, 50, size=(3, 4))
    got = correlated_misfit(r, sigma, v, model_error, b)
    s2 = sigma ** 2 / 2
    for i in range(3):
        cov = np.diag(s2 + (model_error * v[i]) ** 2) + b ** 2
        e = r[i] * sigma
        _, logdet = np.linalg.slogdet(cov / s2)
        assert got[i] == pytest.approx(0.5 * e @ np.linalg.solve(cov, e) + 0.5 * logdet, rel=1e-10)


def test_marginal_misfit_is_the_integral_over_the_log_uniform_prior():
    """``-log ∫ exp(-Σ (c g_k - I_k)^2 / sigma^2) dc / c`` over the prior, by quadrature."""
    g = np.array([[0.02, 0.01, 0.005], [0.001, 0.03, 0.002], [0.0, 0.0, 0.0]])
    readings, sigma, (lo, hi) = np.array([12.0, 6.0, 2.0]), 3.0, (50.0, 5000.0)
    got = marginal_misfit(g, readings, np.zeros(3, dtype=bool), sigma, (lo, hi))
    for i in range(3):
        f = lambda c: np.exp(-np.sum((c * g[i] - readings) ** 2) / sigma ** 2 + readings @ readings / sigma ** 2) / c
        ref = -np.log(quad(f, lo, hi, points=np.geomspace(lo, hi, 30)[1:-1], limit=200)[0]) + \
            readings @ readings / sigma ** 2
        assert got[i] == pytest.approx(ref, abs=0.02)          # within the 24-cell rule's error


def test_correlated_misfit_adds_the_extra_variances_on_the_diagonal():
    """With ``extra`` (a candidate's position error), against the dense covariance
    ``diag(d + extra) + b^2 11^T``."""
    rng = np.random.default_rng(2)
    sigma, model_error, b = 2.0, 0.05, 0.7
    r, v, extra = rng.normal(size=(3, 4)), rng.uniform(5, 50, size=(3, 4)), rng.uniform(0, 9, size=(3, 4))
    got = correlated_misfit(r, sigma, v, model_error, b, extra)
    s2 = sigma ** 2 / 2
    for i in range(3):
        cov = np.diag(s2 + (model_error * v[i]) ** 2 + extra[i]) + b ** 2
        e = r[i] * sigma
        _, logdet = np.linalg.slogdet(cov / s2)
        assert got[i] == pytest.approx(0.5 * e @ np.linalg.solve(cov, e) + 0.5 * logdet, rel=1e-10)
