"""The map-independent log-concentration model of Ristic et al. (2014), eqs. (5), (6), (25).

The searcher does not know which links are missing, so it cannot use the lattice's
``F``. It uses the steady solution of the Laplace equation in a disk of radius R0 with an
absorbing rim, moved to the source by the Möbius map (Appendix, eqs. (47)–(49)): the mean
count at ``(x, y)`` from a source of rate A at ``(X, Y)`` is ``λ = A · c`` with

    c = −½ (2 log R0 + log [((x−X)² + (y−Y)²) / ((xY − yX)² + (R0² − xX − yY)²)])   (25)

The release rate A gets a Gamma prior, conjugate to the Poisson count (eqs. (26)–(30));
marginalising A gives the negative-binomial evidence ``I`` of eq. (38) and the
Bhattacharyya integral ``J`` of eq. (44), both in closed form here.
"""

from __future__ import annotations

import numpy as np
from scipy.special import gammaln

from .base import Model, PoissonNoise

__all__ = ["LogConcentrationModel", "log_gain", "log_evidence", "log_bhattacharyya", "MIN_DISTANCE"]

#: Searcher–source distance (lattice units) below which c is held at its value there:
#: eq. (25) diverges at the source, and the paper does not say how it treats it.
MIN_DISTANCE = 0.5


def log_gain(at: np.ndarray, sources: np.ndarray, radius: float, *, min_distance: float = MIN_DISTANCE) -> np.ndarray:
    """The constant ``c`` of eq. (25), broadcasting `at` (..., 2) against `sources` (..., 2).

    Parameters
    ----------
    at : ndarray, shape (..., 2)
        Where the count is taken (lattice units).
    sources : ndarray, shape (..., 2)
        Source positions, inside the disk of radius `radius`.
    radius : float
        R0 (lattice units).
    min_distance : float
        The distance is floored at this value (the log diverges at the source).

    Returns
    -------
    ndarray
        ``c >= 0`` (0 on and beyond the rim).
    """
    x, y = at[..., 0], at[..., 1]
    sx, sy = sources[..., 0], sources[..., 1]
    num = np.maximum((x - sx) ** 2 + (y - sy) ** 2, min_distance ** 2)
    den = (x * sy - y * sx) ** 2 + (radius ** 2 - x * sx - y * sy) ** 2
    r2 = radius ** 2 * num / np.maximum(den, 1e-300)                    # eq. (6)
    return np.maximum(-0.5 * np.log(r2), 0.0)                           # eqs. (5), (25)


def log_evidence(n, eta, theta, c) -> np.ndarray:
    """``log I``, eq. (38): the Poisson count `n` of mean ``c·A`` with A ~ Gamma(η, θ)
    integrated out (a negative binomial). Broadcasts."""
    n = np.asarray(n, dtype=float)
    ct = np.asarray(c) * np.asarray(theta)
    return (gammaln(n + eta) - gammaln(eta) - gammaln(n + 1.0)
            + n * np.log(np.maximum(ct, 1e-300)) - (n + eta) * np.log1p(ct))


def log_bhattacharyya(n, eta, theta, c) -> np.ndarray:
    """``log J``, eq. (44): ``∫ sqrt(P(n; c·A)) G(A; η, θ) dA`` in closed form,
    ``c^{n/2} Γ(η + n/2) / (sqrt(n!) Γ(η) θ^η (c/2 + 1/θ)^{η + n/2})``. Broadcasts."""
    n = np.asarray(n, dtype=float)
    c = np.maximum(np.asarray(c, dtype=float), 1e-300)
    theta = np.asarray(theta, dtype=float)
    h = 0.5 * n
    return (h * np.log(c) - 0.5 * gammaln(n + 1.0) + gammaln(eta + h) - gammaln(eta)
            - eta * np.log(theta) - (eta + h) * np.log(0.5 * c + 1.0 / theta))


class LogConcentrationModel(Model):
    """Mean count ``A · c`` of eq. (25) with a known rate A (the :class:`Model` protocol).

    Parameters
    ----------
    radius : float
        R0, lattice units.
    strength : float
        The rate A (effective, ``A0 / f_c``).
    """

    def __init__(self, radius: float, strength: float = 1.0, *, min_distance: float = MIN_DISTANCE):
        self.radius, self.strength, self.min_distance = float(radius), float(strength), float(min_distance)
        self.noise = PoissonNoise()

    def mean(self, sources: np.ndarray, at: np.ndarray) -> np.ndarray:
        s = np.asarray(sources, dtype=float)[None, :, :]
        a = np.asarray(at, dtype=float)[:, None, :]
        return self.strength * log_gain(a, s, self.radius, min_distance=self.min_distance)


class LatticeGreen:
    """The discrete Green's function of a (possibly weighted) lattice, a strategy's model.

    The tracer's random walk of Sec. 2.2 steps from a node along one of its links with
    probability ``w_l / d_i`` (``w_l`` the link's conductance, 1 for an existing link and
    0 for a missing one; ``d_i = Σ w`` over the node's links, those to the absorbing ring
    included). With ``Q = D⁻¹ W`` on the transient nodes, ``I − Q = D⁻¹ L`` where
    ``L = D − W_tt`` is symmetric, so ``F = (I − Q)⁻¹ = L⁻¹ D`` and

        F[x, z] = d_z · G[x, z],   G = L⁻¹ = Gᵀ,   hence   d_x F[x, z] = d_z F[z, x].

    This is reciprocity on the lattice: the mean count at the searcher's node z for a
    source at any x, ``A · F[x, z]``, is column z of F, i.e. ONE sparse solve
    ``L g = e_z`` (the discrete adjoint) gives the likelihood over every candidate source.
    The factorisation of ``L`` is done once (sparse LU), each column is one solve, cached.

    Parameters
    ----------
    space : LatticeSpace
        The lattice geometry (nodes, potential links).
    conductance : array_like, shape (L,), optional
        Weight of each potential link: the model's map (1 present, 0 missing; default
        ``space.present``), or link probabilities (the RBPF's map estimate).

    Notes
    -----
    Transient nodes whose cluster of positive-weight links never reaches the absorbing
    ring (closed clusters, isolated nodes) would make ``L`` singular; they are left out:
    no source there is considered (``candidates`` is False) and a count there is 0 for a
    source elsewhere, as in the truth (:func:`reciprocity.worlds.lattice.green_row`).
    Absorbing nodes get ``F = 0``.
    """

    def __init__(self, space, conductance=None):
        from scipy.sparse import coo_matrix, diags
        from scipy.sparse.csgraph import connected_components
        from scipy.sparse.linalg import splu

        self.space = space
        w = np.asarray(space.present if conductance is None else conductance, dtype=float).ravel()
        if w.shape != (len(space.links),) or not np.all(np.isfinite(w)) or np.any(w < 0):
            raise ValueError(f"conductance must be {len(space.links)} finite non-negative weights")
        n = len(space.points)
        a, b = space.links[w > 0].T
        ww = w[w > 0]
        adj = coo_matrix((np.r_[ww, ww], (np.r_[a, b], np.r_[b, a])), shape=(n, n)).tocsr()
        self.degree = np.asarray(adj.sum(axis=1)).ravel()                 # d_i, boundary links included
        lab = connected_components(adj, directed=False)[1]
        open_ = np.zeros(lab.max() + 1, dtype=bool)
        open_[lab[~space.transient]] = True
        self.candidates = space.transient & open_[lab] & (self.degree > 0)   # where a source may sit
        self._t = np.flatnonzero(self.candidates)
        self._pos = -np.ones(n, dtype=np.int64)
        self._pos[self._t] = np.arange(self._t.size)
        lap = (diags(self.degree) - adj)[self._t][:, self._t]
        self._lu = splu(lap.tocsc()) if self._t.size else None
        self._cache: dict[int, np.ndarray] = {}

    def visits(self, nodes) -> np.ndarray:
        """``F[:, z]`` for each z in `nodes`: shape (n_nodes, m), the expected visits to z
        of a walk started at every node (zero for sources outside ``candidates``)."""
        nodes = np.atleast_1d(np.asarray(nodes, dtype=np.int64))
        n = len(self.space.points)
        todo = [int(z) for z in np.unique(nodes) if int(z) not in self._cache]
        solve = [z for z in todo if self._pos[z] >= 0]
        for z in todo:
            self._cache[z] = np.zeros(n)
        if solve:
            rhs = np.zeros((self._t.size, len(solve)))
            rhs[self._pos[solve], np.arange(len(solve))] = 1.0
            g = self._lu.solve(rhs)
            for j, z in enumerate(solve):
                col = np.zeros(n)
                col[self._t] = g[:, j] * self.degree[z]
                self._cache[z] = col
        return np.column_stack([self._cache[int(z)] for z in nodes])
