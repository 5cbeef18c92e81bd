"""Beliefs: what a strategy believes about the source, with one protocol for all.

Every belief updates from an :class:`~reciprocity.observations.Observation`, holds
posterior weights over a support of candidate sources, gives an estimate and an
entropy, and predicts the distribution of the next reading at candidate places (what
infotaxis-type rules need). The imaging map of the reciprocity search, a grid
posterior, a particle cloud and a hidden-Markov source map are all beliefs.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass

import numpy as np
from scipy.special import logsumexp

from ..models.base import NoiseModel
from ..observations import Observation

__all__ = ["Belief", "Predictive", "credible_mass", "shannon_entropy", "posterior_entropies", "expected_entropy", "gaussian_expected_entropy", "MIN_PARTICLES"]

#: Gauss-Hermite nodes and weights for E[f(z)], z ~ N(m, s²): z = m + s·sqrt(2)·t.
_GH_T, _GH_W = np.polynomial.hermite.hermgauss(3)
_GH_W = _GH_W / np.sqrt(np.pi)

#: Fewest particles a particle belief is built with (fewer cannot represent a posterior).
MIN_PARTICLES = 10


def shannon_entropy(weights: np.ndarray) -> float:
    """``-Σ w log w`` (nats) of normalised non-negative `weights`."""
    w = np.asarray(weights, dtype=float)
    w = w[w > 0]
    s = w.sum()
    if s <= 0:
        return 0.0
    w = w / s
    return float(-np.sum(w * np.log(w)))


def credible_mass(nodes: np.ndarray, weights: np.ndarray, centre: np.ndarray, radius: float) -> float:
    """The share of `weights` (one per point of `nodes` (n, 2)) within `radius` of `centre`:
    what the credible stopping rules of the reciprocity searches ask of a belief."""
    near = np.sum((nodes - centre) ** 2, axis=1) <= radius ** 2
    return float(weights[near].sum())


def posterior_entropies(joint: np.ndarray, *, log: bool = False):
    """Outcome probabilities and posterior entropies (nats) of a joint table.

    Parameters
    ----------
    joint : ndarray, shape (O, ..., N)
        ``w_i p(o | i)``: the unnormalised posterior over N hypotheses after each of O
        outcomes (axis 0), for any leading shape (candidates, ...) in between; or its
        logarithm when `log`.
    log : bool
        `joint` holds logarithms (for likelihoods that underflow).

    Returns
    -------
    rho : ndarray, shape (O, ...)
        ``P(o)``, renormalised over the outcomes given.
    H : ndarray, shape (O, ...)
        Entropy of the posterior after each outcome (0 where the outcome has no mass).
    P : ndarray, shape (O, ...)
        Unnormalised outcome masses (the posteriors' denominators).
    """
    if log:
        lj = np.asarray(joint, dtype=float)
        lpn = logsumexp(lj, axis=-1)
        finite = np.isfinite(lpn)
        lpost = lj - np.where(finite, lpn, 0.0)[..., None]
        p = np.exp(lpost)
        H = -np.sum(np.where(p > 0, p * lpost, 0.0), axis=-1)
        lrho = lpn - logsumexp(lpn, axis=0, keepdims=True)
        return np.exp(lrho), np.where(finite, H, 0.0), np.exp(lpn)
    P = joint.sum(axis=-1)
    Ps = np.maximum(P, 1e-300)
    jl = joint * np.log(np.where(joint > 0, joint, 1.0))
    H = np.log(Ps) - jl.sum(axis=-1) / Ps
    rho = P / np.maximum(P.sum(axis=0, keepdims=True), 1e-300)
    return rho, np.where(P > 0, H, 0.0), P


def expected_entropy(joint: np.ndarray, weights: np.ndarray | None = None, *, log: bool = False) -> np.ndarray:
    """Expected Shannon entropy (nats) of a posterior after one outcome: ``Σ_o ρ_o H_o``.

    The one expected-entropy computation of every information strategy (infotaxis and its
    family, the reciprocity search's ``rule="info"``, ``arena-infotaxis``,
    ``lattice-reciprocity``, ``detection-infotaxis``); each builds its own joint table from
    its own likelihood.

    Parameters
    ----------
    joint : ndarray, shape (O, ..., N)
        As for :func:`posterior_entropies` (outcomes on axis 0, hypotheses last).
    weights : ndarray, shape (O, ...), optional
        Probability of each outcome. Default: the joint's own outcome masses, normalised
        (the predictive probabilities). Give them when the outcomes are quadrature nodes or
        draws (their weights are not the joint's masses).
    log : bool
        `joint` holds logarithms.

    Returns
    -------
    ndarray, shape (...)
    """
    rho, H, _ = posterior_entropies(joint, log=log)
    if weights is not None:
        rho = np.broadcast_to(np.asarray(weights, dtype=float), H.shape)
    return np.sum(rho * H, axis=0)


def gaussian_expected_entropy(means: np.ndarray, logw: np.ndarray, support: np.ndarray,
                              support_w: np.ndarray, sigma: float) -> np.ndarray:
    """Expected entropy (nats) of a grid posterior after one Gaussian reading at each candidate.

    Parameters
    ----------
    means : ndarray, shape (m, L)
        Predicted reading at each of m candidates for each of L source nodes.
    logw : ndarray, shape (L,)
        Log posterior weights (normalised or not).
    support : ndarray of int, shape (K,)
        Source nodes standing for the predictive mixture (drawn from the posterior).
    support_w : ndarray, shape (K,)
        Their weights (sum 1).
    sigma : float
        Reading noise standard deviation (signal units).

    Returns
    -------
    ndarray, shape (m,)
        ``Σ_k w_k Σ_q ω_q H(posterior | z_kq)`` with ``z_kq = means[:, k] + sigma √2 t_q``.
    """
    z = means[:, support, None] + sigma * np.sqrt(2.0) * _GH_T[None, None, :]       # (m, K, Q)
    r = (z[..., None] - means[:, None, None, :]) / sigma                              # (m, K, Q, L)
    lp = logw[None, None, None, :] - 0.5 * r * r                                      # (m, K, Q, L)
    m, k, q, n = lp.shape
    outcomes = np.moveaxis(lp.reshape(m, k * q, n), 1, 0)                             # (K Q, m, L)
    return expected_entropy(outcomes, np.outer(support_w, _GH_W).reshape(-1, 1), log=True)


@dataclass
class Predictive:
    """The predictive distribution of the next reading at candidate places.

    Attributes
    ----------
    weights : ndarray, shape (n,)
        Posterior weights of the support points (sum 1).
    means : ndarray, shape (m, n)
        Mean reading at each of m candidates if the source were at each support point.
    noise : NoiseModel
        The reading's distribution given its mean.
    """

    weights: np.ndarray
    means: np.ndarray
    noise: NoiseModel

    #: Most support points standing for the predictive mixture of a Gaussian reading.
    GAUSSIAN_SUPPORT = 64

    def expected_entropy(self) -> np.ndarray:
        """Expected Shannon entropy (nats) of the posterior after one reading at each
        candidate, shape (m,): ``Σ_o P(o) H(w · p(o | ·) / P(o))``.

        Discrete readings (counts, detections) sum over their outcomes. A Gaussian reading
        is integrated by Gauss-Hermite quadrature around the mean of each of the
        GAUSSIAN_SUPPORT heaviest support points (the predictive mixture, renormalised),
        each outcome's posterior taken over every support point.
        """
        logw = np.log(np.maximum(self.weights, 1e-300))
        sigma = getattr(self.noise, "sigma", None)
        if sigma is not None:
            top = np.argsort(-self.weights, kind="stable")[:self.GAUSSIAN_SUPPORT]
            return gaussian_expected_entropy(self.means, logw, top, self.weights[top] / self.weights[top].sum(),
                                             float(sigma))
        _, logp = self.noise.outcomes(self.means)          # (k, m, n)
        return expected_entropy(logp + logw, log=True)


class Belief(ABC):
    """The belief protocol."""

    @abstractmethod
    def update(self, obs: Observation) -> None:
        """Condition on one observation."""

    @abstractmethod
    def support(self) -> np.ndarray:
        """Candidate source positions, shape (n, 2)."""

    @abstractmethod
    def weights(self) -> np.ndarray:
        """Posterior weights of :meth:`support`, shape (n,), summing to 1."""

    def estimate(self) -> np.ndarray:
        """Source estimate: the posterior mean (subclasses may refine)."""
        return self.weights() @ self.support()

    def entropy(self) -> float:
        """Shannon entropy of the posterior weights, nats."""
        return shannon_entropy(self.weights())

    def spread(self) -> float:
        """``tr Σ`` of the posterior (squared length units)."""
        w, x = self.weights(), self.support()
        mu = w @ x
        return float(w @ np.sum((x - mu) ** 2, axis=1))

    def predictive(self, candidates: np.ndarray) -> Predictive:
        """Predictive distribution of the next reading at `candidates` (m, 2)."""
        raise NotImplementedError(f"{type(self).__name__} does not predict readings")
