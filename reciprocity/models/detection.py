"""A time-averaged detection model of a meandering plume, for strategies that read a
binary detector (the ``filament`` world) and the local wind.

What a searcher can believe about a filament plume without simulating filaments: seen
from a point ``y`` and a source ``x``, with the measured mean wind direction ``û`` and
``d = (y − x)·û`` (downwind, m), ``c = (y − x)·n̂`` (crosswind, m), the probability of at
least one detection in one decision period is

``P = ε + (1 − ε) p(d) exp(−c² / (2 σ(d)²))``,
``σ(d) = sqrt(σ0² + (γ σ_θ max(d, 0))²)``,
``p(d) = min(p_max, A σ(d)^−b)`` downwind and ``p(0) exp(d / ℓ)`` upwind (d < 0),

a Gaussian envelope of the meandering plume whose width grows in proportion to the
spread of the measured wind direction ``σ_θ`` (rad), whose peak falls as the plume
spreads, and a small floor ``ε`` for detections the envelope does not explain (the
tails of the meander, model error). This is a model, not the world's filaments.

Calibration: the defaults are fitted to the ``farrell`` scenario's plume, from the
fraction of 1-s periods with at least one detection at fixed points around the source and
the spread of the wind direction there; ``benchmarks/filament_detection_calibration.py``
repeats the measurement and ``benchmarks/filament_detection_calibration.md`` records it.
Successive readings within one second are almost fully correlated, which is why the model
(and :mod:`reciprocity.strategies.detection_infotaxis`) counts one Bernoulli outcome per
period ("any detection in it"), not ten.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import SearchError

__all__ = ["DetectionModel", "WindEstimate"]


@dataclass(frozen=True)
class DetectionModel:
    """Per-period detection probability of a meandering plume (module doc).

    Attributes
    ----------
    sigma0 : float
        Envelope width at the source, m.
    gamma : float
        Envelope growth per metre downwind per radian of wind-direction spread.
    amplitude, decay : float
        ``A`` and ``b`` of the peak ``p(d) = min(p_max, A σ(d)^−b)`` (σ in m).
    p_max : float
        Largest per-period detection probability.
    upwind : float
        Length ``ℓ`` over which the probability falls upwind of the source, m.
    floor : float
        ``ε``: per-period probability of a detection the envelope does not explain.
    """

    sigma0: float = 1.1
    gamma: float = 0.7
    amplitude: float = 0.97
    decay: float = 0.41
    p_max: float = 0.91
    upwind: float = 0.47
    floor: float = 0.01

    def __post_init__(self):
        for name in ("sigma0", "gamma", "amplitude", "upwind"):
            v = getattr(self, name)
            if not (np.isfinite(v) and v > 0):
                raise SearchError(f"{name} must be a positive number; got {v!r}")
        if not (np.isfinite(self.decay) and self.decay >= 0):
            raise SearchError(f"decay must be a non-negative number; got {self.decay!r}")
        for name in ("p_max", "floor"):
            v = getattr(self, name)
            if not 0 < v < 1:
                raise SearchError(f"{name} must lie in (0, 1); got {v!r}")

    def probability(self, sources: np.ndarray, points: np.ndarray, wind_dir: np.ndarray,
                    sigma_theta: float) -> np.ndarray:
        """P(at least one detection in a period at each of `points` | source at each of
        `sources`).

        Parameters
        ----------
        sources : ndarray, shape (N, 2)
            Source hypotheses, m.
        points : ndarray, shape (K, 2) or (2,)
            Where the vehicle reads, m.
        wind_dir : ndarray, shape (2,)
            Mean wind (any length; only its direction is used), m/s.
        sigma_theta : float
            Standard deviation of the measured wind direction, rad.

        Returns
        -------
        ndarray, shape (K, N) (or (N,) for a single point)
        """
        pts = np.asarray(points, dtype=float)
        single = pts.ndim == 1
        pts = np.atleast_2d(pts)
        w = np.asarray(wind_dir, dtype=float)
        n = float(np.hypot(*w))
        u = w / n if n > 0 else np.array([1.0, 0.0])
        rel_x = pts[:, None, 0] - sources[None, :, 0]
        rel_y = pts[:, None, 1] - sources[None, :, 1]
        d = rel_x * u[0] + rel_y * u[1]
        c = -rel_x * u[1] + rel_y * u[0]
        sig2 = self.sigma0 ** 2 + (self.gamma * sigma_theta * np.maximum(d, 0.0)) ** 2
        peak = np.minimum(self.p_max, self.amplitude * sig2 ** (-0.5 * self.decay))
        peak = np.where(d < 0, peak * np.exp(np.minimum(d, 0.0) / self.upwind), peak)
        p = self.floor + (1 - self.floor) * peak * np.exp(-0.5 * c * c / sig2)
        return p[0] if single else p


class WindEstimate:
    """What the vehicle knows of the wind: an exponentially weighted mean of the winds it
    measured (time constant `window`, s) and the spread of their directions about it.

    Parameters
    ----------
    window : float
        Time constant of the running mean, s.
    prior_spread : float
        Direction spread (rad) assumed before `prior_weight` seconds of readings.
    prior_weight : float
        Weight of `prior_spread`, s of readings.
    """

    def __init__(self, window: float = 60.0, prior_spread: float = 0.5, prior_weight: float = 10.0):
        self.window, self.prior_spread, self.prior_weight = float(window), float(prior_spread), float(prior_weight)
        self.mean = np.zeros(2)
        self._sum_w = 0.0
        self._sq = 0.0          # weighted sum of squared direction deviations

    def add(self, wind, dt: float) -> None:
        """One reading `wind` (u_x, u_y), m/s, lasting `dt` s."""
        w = np.asarray(wind, dtype=float)
        a = dt / self.window if self._sum_w > 0 else 1.0
        self.mean = (1 - a) * self.mean + a * w
        m = float(np.hypot(*self.mean))
        if m > 0 and np.hypot(*w) > 0:
            dev = np.arctan2(self.mean[0] * w[1] - self.mean[1] * w[0], self.mean @ w)
            self._sq += dt * dev * dev
        self._sum_w += dt

    @property
    def spread(self) -> float:
        """Standard deviation of the measured wind direction about the mean, rad."""
        return float(np.sqrt((self._sq + self.prior_weight * self.prior_spread ** 2)
                             / (self._sum_w + self.prior_weight)))
