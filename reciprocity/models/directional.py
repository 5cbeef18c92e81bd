"""The directional hit rate of Hajieghrary, Mox & Hsieh (2017, papers/001), eq. (14).

A sensor behind a funnel meets patches at a rate that depends on the distance to the
source and on the robot's course ``v`` (a unit vector) just before the reading:

    R(r | r0, v) = R / ln(λ/a) · exp(V / (2D) · (r − r0) · v) · K0(|r − r0| / λ)

with ``λ`` as in eq. (1) (:func:`reciprocity.models.plume.plume_length`).

The sign of the exponent as printed and the paper's words disagree: the text (and the
caption of its Fig. 3) says "a robot with sensor facing towards the source ... has a
greater chance of making a detection than one facing away", but with ``v`` pointing at
the source ``(r − r0) · v = −|r − r0|``, so eq. (14) as printed gives the *smaller*
rate. :data:`SENSES` keeps both: ``"toward"`` (the words: ``exp(V/(2D) (r0 − r) · v)``)
and ``"printed"`` (the equation as typeset).
"""

from __future__ import annotations

import numpy as np
from scipy.special import k0e

from .plume import PlumeParams

__all__ = ["SENSES", "directional_rate"]

#: Readings of eq. (14)'s sign (see the module doc).
SENSES = ("toward", "printed")


def directional_rate(at, course, sources, p: PlumeParams, sense: str = "toward") -> np.ndarray:
    """Mean hit rate of eq. (14) (hits per unit time) at places `at` moving along `course`.

    Parameters
    ----------
    at : array_like, shape (m, 2)
        Sensor positions (length unit).
    course : array_like, shape (m,)
        Heading of the robot just before each reading, rad (0 along +x, counter-clockwise).
    sources : array_like, shape (n, 2)
        Hypothetical source positions (length unit).
    p : PlumeParams
        ``rate``, ``a``, ``D``, ``tau`` and ``V`` of eq. (14) (``form`` and
        ``wind_direction`` are not used: the course takes the wind's place).
    sense : {"toward", "printed"}
        ``"toward"``: more hits when facing the source (the paper's words);
        ``"printed"``: the exponent as typeset.

    Returns
    -------
    ndarray, shape (m, n)

    Notes
    -----
    Distances below the sensor radius ``a`` are raised to ``a``, as in
    :func:`reciprocity.models.plume.plume_rate`; with ``V = 0`` both senses give that
    isotropic rate.
    """
    if sense not in SENSES:
        raise ValueError(f"sense must be one of {', '.join(SENSES)}; got {sense!r}")
    r = np.atleast_2d(np.asarray(at, dtype=float))
    s = np.atleast_2d(np.asarray(sources, dtype=float))
    th = np.atleast_1d(np.asarray(course, dtype=float))
    dx = r[:, None, 0] - s[None, :, 0]
    dy = r[:, None, 1] - s[None, :, 1]
    d = np.maximum(np.hypot(dx, dy), p.a)
    lam = p.length
    along = dx * np.cos(th)[:, None] + dy * np.sin(th)[:, None]          # (r − r0) · v
    sign = 1.0 if sense == "printed" else -1.0
    expo = -d / lam + sign * p.V / (2.0 * p.D) * along                   # K0 = k0e · exp(−x)
    return (p.rate / np.log(lam / p.a)) * k0e(d / lam) * np.exp(expo)
