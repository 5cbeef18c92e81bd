"""A particle belief over the source position for hit-count (plume) observations.

The posterior is a weighted cloud ``{(r0_m, w_m)}`` (eq. (6), Song et al. 2019,
papers/002). Each reading of ``z`` hits at ``r`` multiplies the weights by the Poisson
likelihood ``p(z | R(r | r0_m) Δt)`` (eqs. (1), (7)); when the effective sample size
``1 / Σ w²`` falls below a threshold (``M/3`` in the paper) the cloud is resampled
(systematic) and each particle takes Metropolis-Hastings moves whose target is the
posterior of the whole history (the "MCMC move" of Section 3.2, as in Ristic's filter):
a Gaussian random walk scaled by the cloud's covariance, accepted with the ratio of the
history likelihoods. A grid posterior (otto) is the same object with particles on the
cell centres and no resampling.

A search that goes on tells that the source is not within ``found_radius`` of any place
visited: those particles get weight 0 (the first term of eq. (3) of papers/002 and
otto's ``p_end``).

Neither papers/001 nor papers/002 estimates the release rate (it is known to the
searcher); the cloud is over position only.
"""

from __future__ import annotations

import numpy as np
from scipy.special import gammaln

from ..models.base import PoissonNoise
from ..observations import Observation
from ..models.plume import PlumeParams, plume_rate
from .base import Belief, Predictive

__all__ = ["ParticleBelief", "grid_particles", "outcome_table"]


def grid_particles(bounds, n: int) -> np.ndarray:
    """About `n` particles on a regular grid over `bounds` ((x0, x1), (y0, y1)), exactly
    `n` of them (a near-square lattice thinned evenly), shape (n, 2)."""
    (x0, x1), (y0, y1) = bounds
    nx = max(1, int(np.ceil(np.sqrt(n * (x1 - x0) / (y1 - y0)))))
    ny = max(1, int(np.ceil(n / nx)))
    gx = x0 + (np.arange(nx) + 0.5) * (x1 - x0) / nx
    gy = y0 + (np.arange(ny) + 0.5) * (y1 - y0) / ny
    pts = np.column_stack([a.ravel() for a in np.meshgrid(gx, gy)])
    keep = np.unique(np.linspace(0, len(pts) - 1, n).round().astype(int))
    return pts[keep]


def outcome_table(means: np.ndarray, max_hits: int | None, kmax: int) -> np.ndarray:
    """``P(z | mean)`` for ``z = 0..K``, shape (K+1, *means.shape): Poisson, with counts
    ``>= max_hits`` lumped into the last outcome when `max_hits` is given, else cut at
    `kmax` (``K = kmax``)."""
    mu = np.maximum(np.asarray(means, dtype=float), 1e-300)
    top = kmax if max_hits is None else max_hits
    k = np.arange(top + 1, dtype=float).reshape((-1,) + (1,) * mu.ndim)
    p = np.exp(k * np.log(mu)[None] - mu[None] - gammaln(k + 1))
    if max_hits is not None:
        p[-1] = np.maximum(0.0, 1.0 - p[:-1].sum(axis=0))
    return p


class ParticleBelief(Belief):
    """Weighted particles over the source position, conditioned on hit counts.

    Parameters
    ----------
    params : PlumeParams
        The nominal hit model (what the strategy is told).
    particles : ndarray, shape (M, 2)
        Initial particles (uniform prior weights).
    bounds : ((x0, x1), (y0, y1))
        The search area (the prior's support; MCMC moves stay inside).
    rng : numpy.random.Generator
    dt : float
        Duration of one reading; the expected count is ``R(r | r0) dt``.
    resample_below : float or None
        Resample when ``M_eff < resample_below · M`` (papers/002: 1/3); None: never (grid).
    mcmc_steps : int
        Metropolis-Hastings moves per particle after a resampling.
    found_radius : float
        Particles this close to a place read from get weight 0 (the search would have
        ended there).
    max_hits : int or None
        Counts ``>= max_hits`` are one outcome (otto's hit cap), else plain Poisson.
    """

    def __init__(self, params: PlumeParams, particles, bounds, rng: np.random.Generator, *, dt: float = 1.0,
                 resample_below: float | None = 1 / 3, mcmc_steps: int = 1, found_radius: float = 0.0,
                 max_hits: int | None = None):
        self.params, self.bounds, self.rng = params, bounds, rng
        self.x = np.asarray(particles, dtype=float).copy()
        self.M = len(self.x)
        self.logw = np.zeros(self.M)
        self.loglik = np.zeros(self.M)      # log-likelihood of the whole history per particle
        self.dt, self.resample_below, self.mcmc_steps = float(dt), resample_below, int(mcmc_steps)
        self.found_radius, self.max_hits = float(found_radius), max_hits
        self.hist_pos: list[np.ndarray] = []
        self.hist_z: list[float] = []
        self.n_resampled = 0
        self._w = np.full(self.M, 1.0 / self.M)

    # -- the protocol -----------------------------------------------------------------
    def support(self) -> np.ndarray:
        return self.x

    def weights(self) -> np.ndarray:
        return self._w

    def mean_counts(self, at) -> np.ndarray:
        """Expected hits per reading at places `at` (m, 2) for each particle, (m, M)."""
        return plume_rate(at, self.x, self.params) * self.dt

    def _loglik(self, z: float, mu: np.ndarray) -> np.ndarray:
        if self.max_hits is not None and z >= self.max_hits:
            return np.log(np.maximum(outcome_table(mu, self.max_hits, self.max_hits)[-1], 1e-300))
        mu = np.maximum(mu, 1e-300)
        return z * np.log(mu) - mu - gammaln(z + 1)

    def _history_loglik(self, pts: np.ndarray) -> np.ndarray:
        """Log-likelihood of the whole history for source positions `pts` (n, 2)."""
        if not self.hist_pos:
            return np.zeros(len(pts))
        at = np.array(self.hist_pos)
        z = np.array(self.hist_z)
        mu = plume_rate(at, pts, self.params) * self.dt          # (k, n)
        if self.max_hits is None:
            ll = (z[:, None] * np.log(np.maximum(mu, 1e-300)) - mu - gammaln(z + 1)[:, None]).sum(axis=0)
        else:
            ll = sum(self._loglik(zk, mk) for zk, mk in zip(z, mu))
        if self.found_radius > 0:
            d = np.hypot(at[:, None, 0] - pts[None, :, 0], at[:, None, 1] - pts[None, :, 1])
            ll = np.where((d <= self.found_radius).any(axis=0), -np.inf, ll)
        return ll

    def update(self, obs: Observation) -> None:
        """Condition on `obs` (kind ``"hits"``, value = count) taken at ``obs.position``."""
        r = np.asarray(obs.position, dtype=float)
        z = float(obs.value)
        ll = self._loglik(z, self.mean_counts(r[None])[0])
        if self.found_radius > 0:
            ll = np.where(np.hypot(*(self.x - r).T) <= self.found_radius, -np.inf, ll)
        self.hist_pos.append(r)
        self.hist_z.append(z)
        self.loglik += ll
        self.logw += ll
        self._normalise()
        if self.resample_below is not None and self.n_eff() < self.resample_below * self.M:
            self.resample()

    def _normalise(self) -> None:
        top = np.max(self.logw)
        if not np.isfinite(top):
            # every particle ruled out (a narrow posterior pushed out by a reading): draw a
            # fresh cloud from the prior, weighted by the whole history
            (x0, x1), (y0, y1) = self.bounds
            self.x = np.column_stack([self.rng.uniform(x0, x1, self.M), self.rng.uniform(y0, y1, self.M)])
            self.loglik = self._history_loglik(self.x)
            self.logw = self.loglik.copy()
            top = np.max(self.logw)
            if not np.isfinite(top):
                self.logw = np.zeros(self.M)
                top = 0.0
        self.logw -= top
        w = np.exp(self.logw)
        self._w = w / w.sum()

    def n_eff(self) -> float:
        """Effective sample size ``1 / Σ w²``."""
        return float(1.0 / np.sum(self._w ** 2))

    def resample(self) -> None:
        """Systematic resampling, then Metropolis-Hastings moves on the history posterior."""
        u = (self.rng.random() + np.arange(self.M)) / self.M
        idx = np.minimum(np.searchsorted(np.cumsum(self._w), u), self.M - 1)
        dev = self.x - self._w @ self.x
        cov = (self._w[:, None] * dev).T @ dev + 1e-6 * np.eye(2)      # weighted, biased
        self.x, self.loglik = self.x[idx].copy(), self.loglik[idx].copy()
        h = (4.0 / (self.M * 4.0)) ** (1.0 / 6.0)     # Silverman's factor for d = 2
        chol = np.linalg.cholesky(h * h * cov + 1e-9 * np.eye(2))
        (x0, x1), (y0, y1) = self.bounds
        for _ in range(self.mcmc_steps):
            prop = self.x + self.rng.standard_normal((self.M, 2)) @ chol.T
            inside = (prop[:, 0] >= x0) & (prop[:, 0] <= x1) & (prop[:, 1] >= y0) & (prop[:, 1] <= y1)
            ll = np.full(self.M, -np.inf)
            ll[inside] = self._history_loglik(prop[inside])
            accept = np.log(self.rng.random(self.M)) < ll - self.loglik
            self.x[accept], self.loglik[accept] = prop[accept], ll[accept]
        self.logw = np.zeros(self.M)
        self._w = np.full(self.M, 1.0 / self.M)
        self.n_resampled += 1

    def spread(self) -> float:
        """``tr Σ`` of the weighted cloud (length²)."""
        mu = self._w @ self.x
        return float(self._w @ np.sum((self.x - mu) ** 2, axis=1))

    def predictive(self, candidates) -> Predictive:
        """Predictive distribution of the next count at `candidates` (m, 2)."""
        return Predictive(self._w, self.mean_counts(candidates), PoissonNoise(kmax=30))

    # -- what infotaxis-type rules need, vectorised over candidates and outcomes ---------
    def found_mass(self, candidates) -> np.ndarray:
        """Posterior mass within ``found_radius`` of each candidate, (m,)."""
        c = np.atleast_2d(candidates)
        near = np.hypot(c[:, None, 0] - self.x[None, :, 0], c[:, None, 1] - self.x[None, :, 1]) <= self.found_radius
        return near.astype(float) @ self._w

    def outcomes(self, candidates, *, eta: float = 1e-3, radius: float | None = None):
        """Joint table of the next reading at each candidate, given the source is not
        found there (not within `radius`, default ``found_radius``).

        Returns
        -------
        joint : ndarray, shape (K+1, m, M)
            ``w'_i p(z | i)`` with ``w'`` the weights renormalised off the found zone.
        p_found : ndarray, shape (m,)
            Posterior mass within `radius` of each candidate (the not-found weights
            exclude it).
        dist : ndarray, shape (m, M)
            Distances from candidates to particles.

        Notes
        -----
        Counts are summed up to ``z_max``, the smallest count whose Poisson CDF at the
        largest mixture mean ``μ(v) = Σ w R(v, r0) Δt`` exceeds ``1 - eta`` (papers/002,
        Section 3.3), or lumped at ``max_hits`` (otto).
        """
        c = np.atleast_2d(np.asarray(candidates, dtype=float))
        mu = self.mean_counts(c)                                     # (m, M)
        dist = np.hypot(c[:, None, 0] - self.x[None, :, 0], c[:, None, 1] - self.x[None, :, 1])
        rad = self.found_radius if radius is None else radius
        w = np.where(dist <= rad, 0.0, self._w[None, :])            # (m, M)
        mass = w.sum(axis=1, keepdims=True)
        p_found = 1.0 - mass[:, 0]
        w = w / np.maximum(mass, 1e-300)
        if self.max_hits is None:
            mbar = float(np.max(np.sum(w * mu, axis=1)))
            kmax = int(_poisson_ppf(1.0 - eta, mbar))
        else:
            kmax = self.max_hits
        joint = outcome_table(mu, self.max_hits, kmax) * w[None]
        return joint, np.clip(p_found, 0.0, 1.0), dist


def _poisson_ppf(q: float, mu: float) -> int:
    """Smallest ``k`` with ``P(Z <= k) >= q`` for ``Z ~ Poisson(mu)`` (at least 1)."""
    k = np.arange(int(mu + 12 * np.sqrt(mu + 1) + 12))
    cdf = np.cumsum(np.exp(k * np.log(max(mu, 1e-300)) - mu - gammaln(k + 1)))
    return max(1, int(np.searchsorted(cdf, q)))
