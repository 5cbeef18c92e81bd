"""The mean hit rate of a turbulent plume (Vergassola et al. 2007): the physics the truth
(:mod:`reciprocity.worlds.plume`) simulates and the plume strategies assume.

A source at ``r0`` releases patches at rate ``R``; they live ``τ``, diffuse with ``D`` and
are advected by a mean wind of speed ``V``. A spherical sensor of radius ``a`` at ``r``
meets them at the mean rate

    R(r | r0) = R / ln(λ/a) · A(r, r0) · K0(|r − r0| / λ),   λ = sqrt(D τ / (1 + V² τ / (4 D)))

The advection factor ``A`` differs between the papers reproduced; each form is kept as
its paper writes it (:data:`FORMS`; the world's module doc says which paper uses which).
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np
from scipy.special import k0e


__all__ = ["FORMS", "PlumeParams", "plume_length", "plume_rate"]

#: Advection forms of the mean rate (see the module doc).
FORMS = ("wind", "isotropic")


def plume_length(D: float, tau: float, V: float) -> float:
    """``λ = sqrt(D τ / (1 + V² τ / (4 D)))``, the plume's length scale (length units)."""
    return float(np.sqrt(D * tau / (1.0 + V * V * tau / (4.0 * D))))


@dataclass(frozen=True)
class PlumeParams:
    """Physical parameters of the hit model.

    Attributes
    ----------
    rate : float
        Release rate ``R`` (patches per unit time).
    a : float
        Sensor radius (length unit).
    D : float
        Effective diffusivity (length² per unit time).
    tau : float
        Patch lifetime (time units).
    V : float
        Mean wind speed (length per unit time), ``>= 0``.
    wind_direction : float
        Direction the wind blows toward, degrees from +x counter-clockwise.
    form : str
        Advection form, one of :data:`FORMS`.
    """

    rate: float = 1.0
    a: float = 1.0
    D: float = 1.0
    tau: float = 400.0
    V: float = 0.0
    wind_direction: float = 270.0
    form: str = "wind"

    @property
    def length(self) -> float:
        """λ (length unit)."""
        return plume_length(self.D, self.tau, self.V)

    def scaled(self, m) -> "PlumeParams":
        """These parameters with a mismatch's factors applied (the truth's; `m` is a
        :class:`reciprocity.worlds.plume.PlumeMismatch`)."""
        return PlumeParams(self.rate * m.rate_factor, self.a, self.D * m.diffusivity_factor,
                           self.tau * m.tau_factor, self.V * m.wind_factor,
                           self.wind_direction + m.wind_turn, self.form)

    def as_dict(self) -> dict:
        return {f.name: getattr(self, f.name) for f in fields(self)}


def plume_rate(at, sources, p: PlumeParams) -> np.ndarray:
    """Mean hit rate ``R(r | r0)`` (hits per unit time) at places `at` for `sources`.

    Parameters
    ----------
    at : array_like, shape (m, 2)
        Sensor positions.
    sources : array_like, shape (n, 2)
        Hypothetical source positions.
    p : PlumeParams

    Returns
    -------
    ndarray, shape (m, n)

    Notes
    -----
    Distances below the sensor radius ``a`` are raised to ``a`` (``K0`` diverges at 0;
    a sensor of radius ``a`` cannot be closer to the source than that).
    """
    r = np.atleast_2d(np.asarray(at, dtype=float))
    s = np.atleast_2d(np.asarray(sources, dtype=float))
    dx = r[:, None, 0] - s[None, :, 0]
    dy = r[:, None, 1] - s[None, :, 1]
    d = np.maximum(np.hypot(dx, dy), p.a)
    lam = p.length
    # K0(x) = k0e(x) exp(-x): the advection and decay exponents are summed before exp,
    # so that far from the source neither overflows
    expo = -d / lam
    if p.V > 0:
        c = p.V / (2.0 * p.D)
        if p.form == "wind":
            th = np.radians(p.wind_direction)
            expo = expo + c * (dx * np.cos(th) + dy * np.sin(th))
        else:
            expo = expo + c * d
    return (p.rate / np.log(lam / p.a)) * k0e(d / lam) * np.exp(expo)
