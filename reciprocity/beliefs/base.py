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

__all__ = ["Belief", "Predictive", "shannon_entropy", "MIN_PARTICLES"]

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

    def expected_entropy(self) -> np.ndarray:
        """Expected Shannon entropy (nats) of the posterior after one reading at each
        candidate, shape (m,): ``Σ_o P(o) H(w · p(o | ·) / P(o))``."""
        w = self.weights
        _, logp = self.noise.outcomes(self.means)          # (k, m, n)
        logw = np.log(np.maximum(w, 1e-300))
        joint = logp + logw                                # log w_i p(o | i)
        log_po = logsumexp(joint, axis=2)                  # (k, m)
        post = np.exp(joint - log_po[..., None])           # posterior per outcome
        h = -np.sum(np.where(post > 0, post * np.log(np.maximum(post, 1e-300)), 0.0), axis=2)
        po = np.exp(log_po)
        po = po / np.maximum(po.sum(axis=0, keepdims=True), 1e-300)
        return np.sum(po * h, axis=0)


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
