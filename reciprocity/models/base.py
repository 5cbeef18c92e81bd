"""Models (inference): what a strategy assumes about how readings arise.

A model maps a hypothetical source to the mean reading it would cause at a place
(:meth:`Model.mean`) and a reading to its likelihood given that mean
(:meth:`Model.loglik`). Beliefs combine the two. A model is built from what a strategy
is told (``World.nominal()``), never from the world itself.
"""

from __future__ import annotations

from abc import ABC, abstractmethod

import numpy as np
from scipy.special import gammaln, log_ndtr

__all__ = ["Model", "NoiseModel", "GaussianNoise", "PoissonNoise", "BernoulliNoise"]


class NoiseModel(ABC):
    """The distribution of a reading given its mean."""

    @abstractmethod
    def loglik(self, value: float, mean: np.ndarray, *, saturated: bool = False) -> np.ndarray:
        """``log p(value | mean)`` for every entry of `mean`."""

    def outcomes(self, means: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Representative outcomes and their log-probabilities for predictive sums:
        ``(values (k,), logp (k, *means.shape))``. Discrete models enumerate counts; a
        Gaussian reading has no finite set of outcomes shared by every mean (see
        :meth:`reciprocity.beliefs.Predictive.expected_entropy`)."""
        raise NotImplementedError


class GaussianNoise(NoiseModel):
    """Additive Gaussian noise ``N(0, sigma^2)``, with an optional ceiling.

    A reading flagged saturated means *at least* its value: its likelihood is the
    censored ``P(mean + noise >= value) = Phi((mean - value) / sigma)``.
    """

    def __init__(self, sigma: float, ceiling: float | None = None):
        if not np.isfinite(sigma) or sigma <= 0:
            raise ValueError(f"sigma must be a positive number; got {sigma!r}")
        self.sigma = float(sigma)
        self.ceiling = None if ceiling is None else float(ceiling)

    def loglik(self, value, mean, *, saturated=False):
        z = (np.asarray(mean, dtype=float) - float(value)) / self.sigma
        if saturated:
            return log_ndtr(z)
        return -0.5 * z * z - np.log(self.sigma * np.sqrt(2 * np.pi))


class PoissonNoise(NoiseModel):
    """Counts: Poisson with the given mean (hits in a time step, particles in a dwell)."""

    def __init__(self, kmax: int = 30):
        self.kmax = int(kmax)

    def loglik(self, value, mean, *, saturated=False):
        k = float(value)
        mu = np.maximum(np.asarray(mean, dtype=float), 1e-300)
        return k * np.log(mu) - mu - gammaln(k + 1)

    def outcomes(self, means):
        k = np.arange(self.kmax + 1, dtype=float)
        mu = np.maximum(np.asarray(means, dtype=float), 1e-300)
        logp = k.reshape((-1,) + (1,) * mu.ndim) * np.log(mu) - mu - gammaln(k + 1).reshape(
            (-1,) + (1,) * mu.ndim)
        return k, logp


class BernoulliNoise(NoiseModel):
    """Detections: 1 with probability `mean` (clipped to [eps, 1 - eps])."""

    def __init__(self, eps: float = 1e-9):
        self.eps = float(eps)

    def loglik(self, value, mean, *, saturated=False):
        p = np.clip(np.asarray(mean, dtype=float), self.eps, 1 - self.eps)
        return np.log(p) if value >= 0.5 else np.log1p(-p)

    def outcomes(self, means):
        p = np.clip(np.asarray(means, dtype=float), self.eps, 1 - self.eps)
        return np.array([0.0, 1.0]), np.stack([np.log1p(-p), np.log(p)])


class Model(ABC):
    """A forward model: the mean reading at places for hypothetical sources, and a noise."""

    noise: NoiseModel

    @abstractmethod
    def mean(self, sources: np.ndarray, at: np.ndarray) -> np.ndarray:
        """Mean readings, shape (len(at), len(sources)), for sources (n, 2) at places (m, 2)."""

    def loglik(self, value: float, mean: np.ndarray, *, saturated: bool = False) -> np.ndarray:
        """``log p(value | mean)``: the noise model's."""
        return self.noise.loglik(value, mean, saturated=saturated)
