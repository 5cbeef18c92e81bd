"""A belief over the source position spanned by fixed Gaussian basis functions.

Hajieghrary, Mox & Hsieh (2017, papers/001), Sections 3.1-3.2: the source density is a
mixture of ``M`` Gaussians (eq. (9))

    P_t(r) = Σ_i w_i N(r; μ_i, C),   C = s² I,

whose means ``μ_i`` are scattered at random over the area once and never move ("no
particle is lost in the estimation process, and the incoming information stream is used
to adjust the weights of the Gaussian functions", its Fig. 8); there is no resampling.
Each reading multiplies every weight by the likelihood of that reading (eq. (7), the
Poisson law of eq. (2)) averaged over the component (the pose-uncertainty mixture of
Section 3.1: each hypothesis stands for a Gaussian around its mean):

    w_i ← w_i ∫ N(r0; μ_i, C) p(z | R(r | r0) Δt) dr0,

by a product Gauss-Hermite rule. The covariance is ``C = (width² + pose_variance) I``:
the basis function's own width (Section 3.2 leaves it to "well-tuned parameters") plus
the robot's pose uncertainty (``Σ = 2 I`` in its Section 4).

The entropy is the three-term Taylor approximation of eq. (12) (Huber et al. 2008): the
logarithm of the mixture expanded to second order around each mean, integrated against
that component (the first-order term vanishes):

    H ≈ −Σ_i w_i [log g(μ_i) + ½ tr(∇² log g(μ_i) C)],   g the mixture density.

It is exact for one component and, for components far apart, tends to the discrete
entropy of the weights plus the entropy of one Gaussian, ``log(2π e s²)``.

With a directional sensor (``sense`` given: eq. (14) of papers/001,
:func:`reciprocity.models.directional.directional_rate`) every rate also takes the
robot's course just before the reading.

A search that goes on tells that the source is not within ``found_radius`` of a place
read from: each weight is multiplied by the component's mass outside that disc (the
shape of the component is kept, a projection).
"""

from __future__ import annotations

import numpy as np
from scipy.special import gammaln
from scipy.stats import ncx2

from ..models.directional import directional_rate
from ..models.plume import PlumeParams, plume_rate
from ..observations import Observation
from .base import Belief
from .particles import outcome_table

__all__ = ["GaussianBasisBelief", "basis_width", "QUADRATURE_NODES"]

#: Gauss-Hermite nodes per axis of the likelihood average over one component.
QUADRATURE_NODES = 5


def basis_width(bounds, n: int) -> float:
    """Our choice of basis width: half the mean spacing ``sqrt(area / n) / 2`` (length
    unit), so that neighbouring functions overlap and the mixture has no holes."""
    (x0, x1), (y0, y1) = bounds
    return 0.5 * float(np.sqrt((x1 - x0) * (y1 - y0) / n))


def _gauss_hermite_2d(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Nodes (n², 2) and weights (n²,) of E[f(x)], x ~ N(0, I₂): product rule."""
    t, w = np.polynomial.hermite.hermgauss(n)
    t, w = t * np.sqrt(2.0), w / np.sqrt(np.pi)
    tx, ty = np.meshgrid(t, t)
    wx, wy = np.meshgrid(w, w)
    return np.column_stack([tx.ravel(), ty.ravel()]), (wx * wy).ravel()


class GaussianBasisBelief(Belief):
    """Weights on fixed Gaussian basis functions over the source position.

    Parameters
    ----------
    params : PlumeParams
        The nominal hit model (what the strategy is told).
    means : ndarray, shape (M, 2)
        Centres of the basis functions (length unit); they never move.
    bounds : ((x0, x1), (y0, y1))
        The search area (length unit).
    width : float
        Standard deviation of each basis function (length unit).
    pose_variance : float
        Variance of the robot's position estimate per axis (length²), added to the
        components' covariance (papers/001, Section 3.1; its ``Σ = 2 I``).
    dt : float
        Duration of one reading; the expected count is ``R(r | r0) dt``.
    found_radius : float
        A reading at ``r`` tells the source is not within this distance of ``r``.
    max_hits : int or None
        Counts ``>= max_hits`` are one outcome, else plain Poisson.
    sense : {None, "toward", "printed"}
        None: the sensor has no direction; else the directional sensor of eq. (14), read
        in that sense; readings then need the robot's course.

    Attributes
    ----------
    variance : float
        ``s² = width² + pose_variance``, the components' variance per axis (length²).
    """

    def __init__(self, params: PlumeParams, means, bounds, *, width: float, pose_variance: float = 0.0,
                 dt: float = 1.0, found_radius: float = 0.0, max_hits: int | None = None,
                 sense: str | None = None):
        self.params, self.bounds, self.sense = params, bounds, sense
        self.mu = np.asarray(means, dtype=float).copy()
        self.M = len(self.mu)
        self.variance = float(width) ** 2 + float(pose_variance)
        self.dt, self.found_radius, self.max_hits = float(dt), float(found_radius), max_hits
        nodes, self._qw = _gauss_hermite_2d(QUADRATURE_NODES)
        self._qx = nodes * np.sqrt(self.variance)                       # offsets of r0 from μ_i
        self.logw = np.zeros(self.M)
        self._w = np.full(self.M, 1.0 / self.M)
        d = self.mu[:, None, :] - self.mu[None, :, :]                     # μ_i − μ_j, (M, M, 2)
        s2 = self.variance
        self._N = np.exp(-0.5 * np.sum(d * d, axis=2) / s2) / (2 * np.pi * s2)   # N(μ_i; μ_j, C)
        self._Ndx, self._Ndy = self._N * d[..., 0], self._N * d[..., 1]
        self._Nd2 = self._N * np.sum(d * d, axis=2)

    # -- the protocol -----------------------------------------------------------------
    def support(self) -> np.ndarray:
        return self.mu

    def weights(self) -> np.ndarray:
        return self._w

    def n_eff(self) -> float:
        """Effective number of basis functions ``1 / Σ w²``."""
        return float(1.0 / np.sum(self._w ** 2))

    def spread(self) -> float:
        """``tr Σ`` of the mixture (length²): the weights' spread plus ``2 s²``."""
        m = self._w @ self.mu
        return float(self._w @ np.sum((self.mu - m) ** 2, axis=1)) + 2.0 * self.variance

    # -- likelihoods -------------------------------------------------------------------
    def rates(self, at, courses=None) -> np.ndarray:
        """Expected hits per reading at places `at` (m, 2), reached along `courses` (m,)
        rad (directional sensor only), for a source at each quadrature node of each
        component, shape (m, M, Q)."""
        src = (self.mu[:, None, :] + self._qx[None]).reshape(-1, 2)
        c = np.atleast_2d(np.asarray(at, dtype=float))
        if self.sense is None:
            r = plume_rate(c, src, self.params)
        else:
            r = directional_rate(c, np.broadcast_to(np.asarray(courses, dtype=float), (len(c),)), src,
                                 self.params, self.sense)
        return (r * self.dt).reshape(len(c), self.M, len(self._qw))

    def _node_loglik(self, z: float, mu: np.ndarray) -> np.ndarray:
        if self.max_hits is not None and z >= self.max_hits:
            return np.log(np.maximum(outcome_table(mu, self.max_hits, self.max_hits)[-1], 1e-300))
        mu = np.maximum(mu, 1e-300)
        return z * np.log(mu) - mu - gammaln(z + 1)

    def log_likelihood(self, obs: Observation, course: float | None = None) -> np.ndarray:
        """``log ∫ N(r0; μ_i, C) p(z | r0) dr0`` of reading `obs` (taken along `course`,
        rad, for a directional sensor) for each component, (M,)."""
        ll = self._node_loglik(float(obs.value),
                               self.rates(np.asarray(obs.position, dtype=float)[None], course)[0])
        top = np.max(ll, axis=1, keepdims=True)
        return top[:, 0] + np.log(np.exp(ll - top) @ self._qw)

    def inside(self, at) -> np.ndarray:
        """Mass of each component within ``found_radius`` of each place of `at` (m, 2),
        shape (m, M): a non-central chi-square law of ``|r0 − r|² / s²``."""
        c = np.atleast_2d(np.asarray(at, dtype=float))
        if self.found_radius <= 0:
            return np.zeros((len(c), self.M))
        d2 = np.sum((c[:, None, :] - self.mu[None]) ** 2, axis=2) / self.variance
        return ncx2.cdf(self.found_radius ** 2 / self.variance, 2, d2)

    def update(self, obs: Observation, course: float | None = None) -> None:
        """Condition on `obs` (kind ``"hits"``, value = count) taken at ``obs.position``
        (along `course`, rad, for a directional sensor)."""
        ll = self.log_likelihood(obs, course)
        if self.found_radius > 0:
            ll = ll + np.log(np.maximum(1.0 - self.inside(obs.position)[0], 1e-300))
        self.logw += ll
        self.logw -= np.max(self.logw)
        w = np.exp(self.logw)
        self._w = w / w.sum()

    # -- entropy, eq. (12) ---------------------------------------------------------------
    def entropies(self, weights: np.ndarray) -> np.ndarray:
        """Mixture entropy (nats) by eq. (12), for each row of `weights` (..., M), each a
        weight vector over the components (normalised here; all-zero rows give 0)."""
        W = np.asarray(weights, dtype=float)
        shape = W.shape[:-1]
        W = W.reshape(-1, self.M)
        tot = W.sum(axis=1, keepdims=True)
        W = W / np.where(tot > 0, tot, 1.0)
        s2 = self.variance
        # ratios to g, so that a mean where the mixture underflows (a component of weight
        # 0 far from the others) gives finite terms, which its zero weight then drops
        g = np.maximum(W @ self._N.T, 1e-300)                        # g(μ_i)
        rx, ry = -(W @ self._Ndx.T) / (s2 * g), -(W @ self._Ndy.T) / (s2 * g)   # ∇g / g
        lap = (W @ self._Nd2.T) / (s2 ** 2 * g) - 2.0 / s2             # tr ∇²g / g
        tr = s2 * (lap - (rx * rx + ry * ry))                          # tr(∇² log g · C)
        H = -np.sum(np.where(W > 0, W * (np.log(g) + 0.5 * tr), 0.0), axis=1)
        return np.where(tot[:, 0] > 0, H, 0.0).reshape(shape)

    def entropy(self) -> float:
        """Entropy of the current mixture, eq. (12) (nats)."""
        return float(self.entropies(self._w))

    # -- what infotaxis needs ----------------------------------------------------------
    def outcomes(self, candidates, *, eta: float = 1e-3, courses=None):
        """Joint table of the next reading at each candidate (reached along `courses`,
        rad, for a directional sensor), given the source is not found there.

        Returns
        -------
        joint : ndarray, shape (K+1, m, M)
            ``w'_i P(z | i)``, ``P(z | i)`` the Poisson law averaged over component ``i``,
            ``w'`` the weights times each component's mass outside the found disc,
            renormalised.
        p_found : ndarray, shape (m,)
            Mixture mass within ``found_radius`` of each candidate.
        dist : ndarray, shape (m, M)
            Distances from candidates to the means.
        """
        c = np.atleast_2d(np.asarray(candidates, dtype=float))
        mu = self.rates(c, courses)                                    # (m, M, Q)
        inside = self.inside(c)                                        # (m, M)
        w = self._w[None, :] * (1.0 - inside)
        p_found = 1.0 - w.sum(axis=1)
        w = w / np.maximum(w.sum(axis=1, keepdims=True), 1e-300)
        if self.max_hits is None:
            mbar = float(np.max(np.einsum("mi,miq,q->m", w, mu, self._qw)))
            from scipy.stats import poisson
            kmax = max(1, int(poisson.ppf(1.0 - eta, max(mbar, 1e-12))))
        else:
            kmax = self.max_hits
        lik = outcome_table(mu, self.max_hits, kmax) @ self._qw        # (K+1, m, M)
        dist = np.hypot(c[:, None, 0] - self.mu[None, :, 0], c[:, None, 1] - self.mu[None, :, 1])
        return lik * w[None], np.clip(p_found, 0.0, 1.0), dist
