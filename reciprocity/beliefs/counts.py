"""A posterior over (source position, release rate) from Poisson counts.

Each reading ``n_k`` over a dwell ``Δt_k`` has, for a source at candidate ``x`` with
release rate ``q``, the mean ``μ_k(x, q) = q g_k(x) Δt_k + b Δt_k``: ``g_k(x)`` the mean
hits per second per unit release rate (by reciprocity, one adjoint solve per reading
gives it at every candidate) and ``b`` a small background rate that keeps a count the
model cannot explain (an upwind tail the model underestimates) from ruling a candidate
out for good. The likelihood is Poisson, ``Π_k μ_k^{n_k} e^{-μ_k} / n_k!``. The release
rate is integrated out over a log-uniform prior on ``[lo, hi]`` (as the Poisson imaging
map integrates out an unknown strength), numerically on ``cells`` log-spaced values,
and the prior over positions is uniform in area (each node weighted by its area).
"""

from __future__ import annotations

import numpy as np
from scipy.special import logsumexp

from .base import Belief, shannon_entropy

__all__ = ["CountPosterior"]


class CountPosterior(Belief):
    """Posterior over candidate sources (mesh nodes) and release rates from Poisson counts.

    Parameters
    ----------
    nodes : ndarray, shape (n, 2)
        Candidate sources, cm.
    areas : ndarray, shape (n,)
        Area each candidate stands for, cm² (the uniform prior in area).
    rate_range : (float, float)
        ``(lo, hi)`` of the log-uniform prior of the release rate, particles/s.
    background : float
        Background count rate ``b``, hits/s, added to every candidate's mean.
    cells : int
        Log-spaced release rates the prior is integrated over.

    Examples
    --------
    >>> nodes = np.array([[0.0, 0.0], [10.0, 0.0]])
    >>> post = CountPosterior(nodes, np.ones(2), (1.0, 100.0), background=0.0)
    >>> post.add(np.array([0.2, 0.001]), count=5, dwell=1.0)
    >>> bool(post.weights()[0] > 0.9)
    True
    """

    def __init__(self, nodes: np.ndarray, areas: np.ndarray, rate_range: tuple[float, float], *,
                 background: float = 0.01, cells: int = 24):
        self.nodes = np.asarray(nodes, dtype=float)
        self.areas = np.asarray(areas, dtype=float)
        lo, hi = rate_range
        self.rates = np.geomspace(lo, hi, int(cells))
        self.background = float(background)
        self.loglik = np.zeros((len(self.nodes), len(self.rates)))
        self.n = 0
        #: every reading conditioned on, in order: (rate, count, dwell); :meth:`first` replays them
        self.readings: list[tuple[np.ndarray, float, float]] = []
        #: candidates the prior allows (:meth:`restrict`); all by default
        self.allowed = np.ones(len(self.nodes), dtype=bool)
        self._cache: dict = {}

    def restrict(self, allowed: np.ndarray) -> None:
        """Give the candidates outside `allowed` (n,) bool no prior mass (e.g. nearer the walls
        than the task says a source can be). A mask that allows none is refused."""
        allowed = np.asarray(allowed, dtype=bool)
        if allowed.shape != self.allowed.shape or not (allowed & self.allowed).any():
            raise ValueError(f"restrict needs a mask of {len(self.nodes)} candidates that keeps at least one")
        self.allowed = self.allowed & allowed
        self._cache.clear()

    def add(self, rate: np.ndarray, count: float, dwell: float) -> None:
        """Condition on `count` hits over `dwell` s, with `rate` (n,) the mean hits per
        second per unit release rate at the reading from a source at each candidate."""
        rate = np.maximum(rate, 0.0)
        mu = (rate[:, None] * self.rates[None, :] + self.background) * float(dwell)
        self.loglik += float(count) * np.log(mu) - mu
        self.loglik -= self.loglik.max()
        self.n += 1
        self.readings.append((rate, float(count), float(dwell)))
        self._cache.clear()

    def first(self, k: int) -> "CountPosterior":
        """The posterior after the first `k` readings alone (for figures of each step)."""
        out = CountPosterior(self.nodes, self.areas, (self.rates[0], self.rates[-1]),
                             background=self.background, cells=len(self.rates))
        out.allowed = self.allowed.copy()
        for rate, count, dwell in self.readings[:k]:
            out.add(rate, count, dwell)
        return out

    def update(self, obs) -> None:
        raise NotImplementedError("a CountPosterior needs each reading's rates: use add(rate, count, dwell)")

    # ------------------------------------------------------------------ belief protocol
    def support(self) -> np.ndarray:
        return self.nodes

    def log_marginal(self) -> np.ndarray:
        """``log p(readings | x)`` up to a constant, the release rate integrated out, per node."""
        if "marginal" not in self._cache:
            self._cache["marginal"] = logsumexp(self.loglik, axis=1)
        return self._cache["marginal"]

    def weights(self) -> np.ndarray:
        if "w" not in self._cache:
            lm = np.where(self.allowed, self.log_marginal(), -np.inf)
            w = self.areas * np.exp(lm - lm.max())
            self._cache["w"] = w / w.sum()
        return self._cache["w"]

    def rate_posterior(self) -> np.ndarray:
        """Posterior of the release rate over :attr:`rates`, shape (cells,)."""
        w = self.weights()
        p = np.exp(self.loglik - self.log_marginal()[:, None])
        out = w @ p
        return out / out.sum()

    def estimate(self, radius: float = 3.0) -> np.ndarray:
        """The posterior mean within `radius` cm of the most probable node, cm."""
        w = self.weights()
        top = self.nodes[int(np.argmax(w / self.areas))]
        near = np.sum((self.nodes - top) ** 2, axis=1) <= radius ** 2
        return (w[near] @ self.nodes[near]) / w[near].sum()

    def entropy(self) -> float:
        return shannon_entropy(self.weights())
