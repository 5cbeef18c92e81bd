"""Infotaxis with other reward functions: the Infotaxis II and III rows of Song et al.'s Table 1.

Song, He & Lei (2019, papers/002) compare, in their Table 1, two rows taken from Ristic,
Skvortsov & Gunatilaka (2016), "A study of cognitive strategies for an autonomous search"
(Information Fusion 28, 1-9), which papers/002 describes only as "an infotaxis scheme
based on three different reward functions, developing an improved infotaxis scheme based
on Rényi divergence". We did not reach that paper's text; what we use of it, and what we
had to choose, is in ``docs/papers/song2019.md``. Both strategies here keep everything of
:class:`~reciprocity.strategies.infotaxis.PlumeSearch` (the particle belief, the moves, the
sum over counts up to ``z_max``) and change only the reward of a move ``v``:

``infotaxis-ii``
    the expected Rényi divergence of order ``alpha`` of the belief after the next outcome
    from the belief now (maximised), :func:`expected_renyi_divergence`;
``infotaxis-iii``
    the expected Bayesian estimation error after the next outcome, the trace of the
    posterior covariance of the source position (minimised),
    :func:`expected_posterior_spread`.

The outcomes of a move are those of infotaxis' eq. (3) in papers/002: the source is
found at ``r_v`` (the mass within the found radius), or it is not and the sensor counts
``z`` hits.
"""

from __future__ import annotations

import numpy as np

from ..beliefs.base import posterior_entropies
from ..validation import positive
from ..errors import SearchError
from . import register
from .infotaxis import PlumeSearch

__all__ = ["InfotaxisII", "InfotaxisIII", "expected_renyi_divergence", "expected_posterior_spread"]


def expected_renyi_divergence(joint: np.ndarray, weights: np.ndarray, near: np.ndarray,
                              alpha: float = 0.5) -> np.ndarray:
    """Expected Rényi divergence of order `alpha` (nats) of the belief after the next
    outcome at each candidate from the belief now.

    ``D_α(q ‖ w) = ln(Σ_i q_i^α w_i^(1-α)) / (α - 1)``. The found outcome (probability
    ``P_f``, the mass within the found radius) leaves ``w`` restricted to that zone, whose
    divergence is ``-ln P_f`` for every α; a count ``z`` leaves ``q ∝ w'_i p(z | i)`` with
    ``w'`` the belief off the zone.

    Parameters
    ----------
    joint : ndarray, shape (K+1, m, M)
        ``w'_i p(z | i, v)`` over counts, candidates and particles
        (:meth:`~reciprocity.beliefs.particles.ParticleBelief.outcomes`).
    weights : ndarray, shape (M,)
        The belief now, normalised.
    near : ndarray of bool, shape (m, M)
        Particles within the found radius of each candidate.
    alpha : float
        Order of the divergence, positive and not 1 (0.5: twice the Bhattacharyya
        distance).

    Returns
    -------
    ndarray, shape (m,)
        ``P_f (-ln P_f) + (1 - P_f) Σ_z ρ_z D_α(q_z ‖ w)``, nats.
    """
    w = np.asarray(weights, dtype=float)
    p_found = np.clip(np.where(near, w[None, :], 0.0).sum(axis=1), 0.0, 1.0)          # (m,)
    rho, _, P = posterior_entropies(joint)                                            # (K+1, m)
    # q_i / w_i = w'_i p(z|i) / (w_i P_z): joint / (w P_z), 0 on the zone
    ratio = joint / np.maximum(w, 1e-300)[None, None, :] / np.maximum(P, 1e-300)[..., None]
    inner = np.einsum("i,zmi->zm", w, ratio ** alpha)
    d_count = np.log(np.maximum(inner, 1e-300)) / (alpha - 1.0)
    d_found = -np.log(np.maximum(p_found, 1e-300))
    return p_found * d_found + (1.0 - p_found) * np.sum(rho * d_count, axis=0)


def expected_posterior_spread(joint: np.ndarray, weights: np.ndarray, near: np.ndarray,
                              support: np.ndarray) -> np.ndarray:
    """Expected trace of the posterior covariance of the source position after the next
    outcome at each candidate (length²): the Bayes risk of the posterior-mean estimate
    under squared error.

    Parameters
    ----------
    joint : ndarray, shape (K+1, m, M)
        ``w'_i p(z | i, v)`` as for :func:`expected_renyi_divergence`.
    weights : ndarray, shape (M,)
        The belief now, normalised.
    near : ndarray of bool, shape (m, M)
        Particles within the found radius of each candidate.
    support : ndarray, shape (M, 2)
        Particle positions.

    Returns
    -------
    ndarray, shape (m,)
        ``P_f tr Σ_found + (1 - P_f) Σ_z ρ_z tr Σ_z``.
    """
    x = np.asarray(support, dtype=float)
    sq = np.sum(x * x, axis=1)
    rho, _, P = posterior_entropies(joint)
    Ps = np.maximum(P, 1e-300)
    mean = np.einsum("zmi,ic->zmc", joint, x) / Ps[..., None]
    tr_count = np.maximum(np.einsum("zmi,i->zm", joint, sq) / Ps - np.sum(mean ** 2, axis=2), 0.0)
    wf = np.where(near, np.asarray(weights, dtype=float)[None, :], 0.0)             # (m, M)
    p_found = np.clip(wf.sum(axis=1), 0.0, 1.0)
    pf = np.maximum(p_found, 1e-300)
    mf = wf @ x / pf[:, None]
    tr_found = np.maximum(wf @ sq / pf - np.sum(mf ** 2, axis=1), 0.0)
    return p_found * tr_found + (1.0 - p_found) * np.sum(rho * tr_count, axis=0)


class _RewardInfotaxis(PlumeSearch):
    """A :class:`PlumeSearch` scored by a reward of the outcomes of each move."""

    def _outcomes(self, cands):
        joint, _, dist = self.belief.outcomes(cands, eta=self.eta)
        return joint, self.belief.weights(), dist <= self.belief.found_radius


@register
class InfotaxisII(_RewardInfotaxis):
    """Infotaxis with the expected Rényi divergence as reward (the Infotaxis II row of
    papers/002's Table 1, after Ristic, Skvortsov & Gunatilaka 2016; our reading).

    Parameters
    ----------
    alpha : float
        Order of the Rényi divergence (0.5, the Bhattacharyya case Ristic et al. use in
        papers/000; 1 would be the Kullback-Leibler divergence, whose expectation is
        infotaxis' expected entropy drop).
    particles, resample_below, mcmc_steps, eta
        As for :class:`~reciprocity.strategies.infotaxis.PlumeSearch`.
    """

    name = "infotaxis-ii"

    def __init__(self, *, alpha: float = 0.5, particles: int = 600, resample_below: float = 1 / 3,
                 mcmc_steps: int = 1, eta: float = 1e-3):
        self.alpha = positive(alpha, "alpha")
        if self.alpha == 1.0:
            raise SearchError("alpha must differ from 1 (the Rényi divergence of order 1 is the "
                              "Kullback-Leibler divergence: use infotaxis); got 1")
        super().__init__(particles=particles, resample_below=resample_below, mcmc_steps=mcmc_steps, eta=eta)

    def params(self) -> dict:
        return dict(super().params(), alpha=self.alpha)

    def scores(self, cands):
        joint, w, near = self._outcomes(cands)
        return -expected_renyi_divergence(joint, w, near, self.alpha)


@register
class InfotaxisIII(_RewardInfotaxis):
    """Infotaxis with the expected Bayesian estimation error as reward: the move after
    which the posterior covariance of the source position is expected smallest (the
    Infotaxis III row of papers/002's Table 1, after Ristic, Skvortsov & Gunatilaka 2016;
    our reading)."""

    name = "infotaxis-iii"

    def scores(self, cands):
        joint, w, near = self._outcomes(cands)
        return expected_posterior_spread(joint, w, near, self.belief.support())
