"""The one expected-entropy function of the information strategies (beliefs.base)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from reciprocity.beliefs.base import expected_entropy, posterior_entropies
from reciprocity.strategies.information import expected_entropy as gaussian_expected


def test_known_values():
    w = np.array([0.5, 0.5])
    telling = np.array([[[1.0, 0.0]], [[0.0, 1.0]]]) * w          # outcome o says hypothesis o
    silent = np.array([[[0.5, 0.5]], [[0.5, 0.5]]]) * w
    assert expected_entropy(telling) == pytest.approx([0.0])
    assert expected_entropy(silent) == pytest.approx([np.log(2)])


@settings(max_examples=50, deadline=None)
@given(st.integers(1, 4), st.integers(1, 5), st.integers(2, 6), st.integers(0, 2**32 - 1))
def test_log_and_linear_tables_agree_and_never_exceed_the_prior(outcomes, candidates, n, seed):
    rng = np.random.default_rng(seed)
    w = rng.dirichlet(np.ones(n))
    lik = rng.dirichlet(np.ones(outcomes), size=(candidates, n)).transpose(2, 0, 1)   # p(o | i), sums to 1 over o
    joint = lik * w
    lin = expected_entropy(joint)
    log = expected_entropy(np.log(joint), log=True)
    assert np.allclose(lin, log, atol=1e-10)
    prior = -np.sum(w * np.log(w))
    assert np.all(lin <= prior + 1e-9)                                # information never hurts on average
    rho, H, P = posterior_entropies(joint)
    assert np.allclose(rho.sum(axis=0), 1) and np.allclose(P.sum(axis=0), 1)


def test_the_gaussian_closed_form_is_the_same_expectation_as_a_direct_sum():
    """information.expected_entropy (the reciprocity search's rule="info") against the
    formula written out: Σ_j w_j H(π_{.|j}), π_{i|j} ∝ w_i N(m_i; m_j, 2σ²)."""
    rng = np.random.default_rng(0)
    means = rng.uniform(0, 50, size=(4, 7))
    w = rng.dirichlet(np.ones(7))
    sigma = 6.0
    direct = np.zeros(4)
    for y in range(4):
        for j in range(7):
            k = w * np.exp(-(means[y] - means[y, j]) ** 2 / (4 * sigma**2))
            p = k / k.sum()
            direct[y] += w[j] * -np.sum(p * np.log(p))
    assert np.allclose(gaussian_expected(means, w, sigma), direct, rtol=1e-12)


def test_two_step_entropy_is_the_sum_written_out():
    """information.two_step_entropy (rule="lookahead") against a direct sum over the first
    reading's outcomes (true source j, Gauss-Hermite node q), each posterior written out and
    the best second candidate taken by information.expected_entropy."""
    from reciprocity.strategies.information import HERMITE_NODES, HERMITE_WEIGHTS, two_step_entropy
    rng = np.random.default_rng(1)
    first, second = rng.uniform(0, 40, size=(3, 6)), rng.uniform(0, 40, size=(5, 6))
    w = rng.dirichlet(np.ones(6))
    sigma = 5.0
    apart = rng.random((3, 5)) < 0.7
    apart[:, 0] = True
    direct = np.zeros(3)
    for a in range(3):
        for j in range(6):
            for xi, g in zip(HERMITE_NODES, HERMITE_WEIGHTS):
                post = w * np.exp(-(first[a, j] + sigma * xi - first[a]) ** 2 / (2 * sigma**2))
                post /= post.sum()
                direct[a] += w[j] * g * gaussian_expected(second, post, sigma)[apart[a]].min()
    assert np.allclose(two_step_entropy(first, second, w, sigma, apart=apart), direct, rtol=1e-10)


def test_two_step_entropy_is_near_a_fine_quadrature_and_below_one_step():
    """The 3-node quadrature of the first reading's noise against a 2001-point one; and two
    readings never expect more entropy than the better first one alone."""
    from reciprocity.strategies.information import two_step_entropy
    rng = np.random.default_rng(2)
    first, second = rng.normal(0, 3, size=(3, 5)), rng.normal(0, 3, size=(4, 5))
    w = rng.dirichlet(np.ones(5))
    sigma = 1.3
    fine = np.zeros(3)
    for a in range(3):
        r = np.linspace(first[a].min() - 8 * sigma, first[a].max() + 8 * sigma, 2001)
        joint = w * np.exp(-(r[:, None] - first[a]) ** 2 / (2 * sigma**2)) / np.sqrt(2 * np.pi * sigma**2)
        pr = joint.sum(axis=1)
        best = [gaussian_expected(second, p / p.sum(), sigma).min() for p in joint]
        fine[a] = np.sum(pr * np.array(best)) * (r[1] - r[0])
    got = two_step_entropy(first, second, w, sigma)
    assert np.allclose(got, fine, atol=0.02)
    assert np.all(got <= gaussian_expected(first, w, sigma) + 0.02)
