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
