"""Closed-form Green's functions used as exact references.

``-Δ G(·, z) = δ(· - z)`` with the sign convention of the paper (eq. 3): ``G > 0``; and
the free-space Green's function of advection-diffusion-decay in a uniform wind.
"""

from __future__ import annotations

import numpy as np

__all__ = ["free_space_green", "disk_green", "free_space_advection_green"]


def free_space_green(x, z) -> np.ndarray:
    """Free-space Green's function ``-ln|x - z| / (2 pi)``.

    Parameters
    ----------
    x : array_like, shape (n, 2)
        Evaluation points, cm.
    z : array_like, shape (2,)
        Source point, cm.

    Returns
    -------
    ndarray, shape (n,)
        ``+inf`` at ``x == z``.
    """
    x = np.atleast_2d(np.asarray(x, dtype=float))
    r = np.hypot(x[:, 0] - z[0], x[:, 1] - z[1])
    with np.errstate(divide="ignore"):
        return -np.log(r) / (2 * np.pi)


def disk_green(x, z, center=(0.0, 0.0), radius: float = 1.0) -> np.ndarray:
    """Dirichlet Green's function of the disk ``|x - center| < radius``.

    ``G(x, z) = -(1/2pi) [ln|x - z| - ln(|z'| |x - z*| / R)]`` with ``z' = z - center``
    and the image point ``z* = center + R^2 z' / |z'|^2`` (method of images).

    Parameters
    ----------
    x : array_like, shape (n, 2)
        Evaluation points, cm.
    z : array_like, shape (2,)
        Source point inside the disk, cm.
    center : array_like, shape (2,)
        Disk centre, cm.
    radius : float
        Disk radius, cm.

    Returns
    -------
    ndarray, shape (n,)
    """
    x = np.atleast_2d(np.asarray(x, dtype=float)) - np.asarray(center, dtype=float)
    zc = np.asarray(z, dtype=float) - np.asarray(center, dtype=float)
    rz = np.hypot(*zc)
    if rz < 1e-14 * radius:
        with np.errstate(divide="ignore"):
            return -np.log(np.hypot(x[:, 0], x[:, 1]) / radius) / (2 * np.pi)
    zstar = zc * radius**2 / rz**2
    d1 = np.hypot(x[:, 0] - zc[0], x[:, 1] - zc[1])
    d2 = np.hypot(x[:, 0] - zstar[0], x[:, 1] - zstar[1])
    with np.errstate(divide="ignore"):
        return -(np.log(d1) - np.log(rz * d2 / radius)) / (2 * np.pi)


def free_space_advection_green(x, z, wind, D: float, tau: float) -> np.ndarray:
    """Free-space Green's function of ``-D Δc + u·∇c + c/τ = δ(· - z)`` in a uniform wind.

    ``c(x) = exp(u·(x - z) / (2D)) K0(|x - z| / λ) / (2 pi D)`` with
    ``1/λ² = |u|²/(4D²) + 1/(D τ)``: the substitution ``c = exp(u·r/(2D)) g`` turns the
    operator into ``-D (Δ - 1/λ²) g``, whose Green's function is ``K0(r/λ) / (2 pi D)``.

    Parameters
    ----------
    x : array_like, shape (n, 2)
        Evaluation points, cm.
    z : array_like, shape (2,)
        Source point, cm.
    wind : array_like, shape (2,)
        Uniform wind velocity ``u``, cm/s.
    D : float
        Diffusivity, cm²/s.
    tau : float
        Lifetime (decay time), s; ``inf`` allowed when the wind is not zero.

    Returns
    -------
    ndarray, shape (n,)
        Concentration per unit source rate, s/cm²; ``+inf`` at ``x == z``.

    Notes
    -----
    Evaluated as ``k0e(s) exp(u·r/(2D) - s)`` (``s = |r|/λ``), which neither overflows
    far downwind nor underflows to 0/0 far upwind.
    """
    from scipy.special import k0e
    x = np.atleast_2d(np.asarray(x, dtype=float))
    r = x - np.asarray(z, dtype=float)
    u = np.asarray(wind, dtype=float)
    inv_lambda = np.sqrt((u @ u) / (4 * D**2) + 1.0 / (D * tau))
    s = np.hypot(r[:, 0], r[:, 1]) * inv_lambda
    with np.errstate(divide="ignore"):
        return k0e(s) * np.exp(r @ u / (2 * D) - s) / (2 * np.pi * D)
