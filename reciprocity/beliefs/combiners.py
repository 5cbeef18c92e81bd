"""How the maps of single readings combine into the imaging function ``P_M``.

A combiner is a small part of an :class:`~reciprocity.beliefs.imaging.ImagingMap`:
given the map's readings and adjoint fields, it returns ``P_M`` at every node.

- :class:`MeanCombiner` is eq. (8) of Landa et al.: the mean of the maps
  ``p_k = exp(-(v_k - I_k)^2 / sigma^2)`` of eq. (7).
- :class:`ProductCombiner` is the Bayesian alternative: the likelihood of all readings,
  rescaled to a maximum of 1; with the model's relative error and a shared offset
  (:func:`correlated_misfit`), or with the strength integrated out over a log-uniform prior
  (:func:`marginal_misfit`).
"""

from __future__ import annotations

import numpy as np

__all__ = ["COMBINATIONS", "COMBINERS", "MeanCombiner", "ProductCombiner", "combiner",
           "correlated_misfit", "marginal_misfit", "STRENGTH_CELLS"]

COMBINATIONS = ("mean", "product")
#: Log-spaced cells over which the prior ``1/c`` of an unknown strength is averaged
#: (:func:`marginal_misfit`): over a factor 100, neighbouring edges 21 % apart; ``1/c`` is
#: taken at the mean of ``c`` within each cell, so the marginal agrees with quadrature to
#: within 2 % (``tests/reciprocity/test_imaging.py``).
STRENGTH_CELLS = 24


class MeanCombiner:
    """Eq. (8): ``P_M`` is the mean of the maps ``p_k``; zero where no source may lie."""

    name = "mean"

    def values(self, im) -> np.ndarray:
        """``P_M`` at every node of the map `im`, in [0, 1]."""
        P = im.p_maps().mean(axis=1)
        if im.allowed is not None:
            P = np.where(im.allowed, P, 0.0)
        return P


class ProductCombiner:
    """The likelihood of all readings, ``exp(-(s - min s))`` for the per-node misfit ``s``:
    the sum of squared residuals over ``sigma``, or with the map's ``model_error`` and
    ``offset_sd`` its ``_correlated_misfit`` (:func:`correlated_misfit`, which a map
    subclass may replace), or with its ``strength_range``
    :func:`marginal_misfit`."""

    name = "product"

    def values(self, im) -> np.ndarray:
        """``P_M`` at every node of the map `im`, in [0, 1] (its maximum is 1)."""
        if im.strength_range is not None:
            s = im._marginal_misfit()
        else:
            r = im._residuals()
            if im.model_error > 0 or im.offset_sd > 0 or getattr(im, "position_error", False):
                s = im._correlated_misfit(r)
            else:
                s = np.sum(r * r, axis=1)
        if im.allowed is not None:
            s = np.where(im.allowed, s, np.inf)
        return np.exp(-(s - s.min()))


#: Combination name -> combiner.
COMBINERS = {"mean": MeanCombiner(), "product": ProductCombiner()}


def combiner(name: str) -> MeanCombiner | ProductCombiner:
    """The combiner called `name` (one of :data:`COMBINATIONS`)."""
    return COMBINERS[name]


def correlated_misfit(r: np.ndarray, sigma: float, model: np.ndarray, model_error: float,
                      offset_sd: float, extra: np.ndarray | None = None) -> np.ndarray:
    """``-log`` likelihood per node (up to a constant) of readings with independent
    variances ``d_k = s^2 + (model_error v_k)^2 + extra_k`` (``s = sigma/sqrt 2``) and one shared
    offset of variance ``offset_sd^2`` integrated out (Sherman-Morrison; the
    log-determinant counts, as the variances differ from node to node).

    Parameters
    ----------
    r : ndarray, shape (n_nodes, M)
        Residuals over ``sigma`` (censoring applied).
    sigma : float
        ``sigma`` of eq. (7), signal units.
    model : ndarray, shape (n_nodes, M)
        Predicted readings ``v_k(x)``, signal units.
    model_error : float
        Relative error of a predicted reading (a fraction).
    offset_sd : float
        Standard deviation of the shared offset, signal units.
    extra : ndarray, shape (n_nodes, M), optional
        Further independent variances, signal units² (a candidate's position error).
    """
    s2 = sigma ** 2 / 2.0
    d = s2 + (model_error * model) ** 2                          # (n_nodes, M)
    if extra is not None:
        d = d + extra
    e = r * sigma                                                # residuals, signal units
    q = np.sum(e * e / d, axis=1)
    logdet = np.sum(np.log(d / s2), axis=1)
    if offset_sd > 0:
        b2 = offset_sd ** 2
        inv_sum = np.sum(1.0 / d, axis=1)
        q = q - b2 * np.sum(e / d, axis=1) ** 2 / (1.0 + b2 * inv_sum)
        logdet = logdet + np.log1p(b2 * inv_sum)
    return 0.5 * q + 0.5 * logdet


def marginal_misfit(g_all: np.ndarray, readings: np.ndarray, saturated: np.ndarray, sigma: float,
                    strength_range: tuple[float, float]) -> np.ndarray:
    """``-log`` of the likelihood integrated over the log-uniform strength prior, per
    node (up to a constant).

    ``Σ (c g_k - I_k)^2 / sigma^2`` is quadratic in ``c``, ``(A c^2 - 2 B c + C) /
    sigma^2``; its integral over ``[lo, hi]`` is a difference of normal CDFs, and the
    prior's ``1/c`` is averaged over :data:`STRENGTH_CELLS` cells of a log grid. A uniform
    prior instead would favour points weakly coupled to every observation point (the
    integral's width grows as ``1/|g|``). Saturated (censored) readings are scored at each
    node's most probable ``c``.

    Parameters
    ----------
    g_all : ndarray, shape (n_nodes, M)
        Nodal values of ``G(·, z_k)``, one column per reading.
    readings : ndarray, shape (M,)
        The readings ``I_k``, signal units.
    saturated : ndarray of bool, shape (M,)
        Which readings were at the sensor's ceiling.
    sigma : float
        ``sigma`` of eq. (7), signal units.
    strength_range : (float, float)
        The prior's ``(lo, hi)``, units of the strength.
    """
    from scipy.special import log_ndtr
    lo, hi = strength_range
    free = ~saturated
    g, I = g_all[:, free], readings[free]
    A = np.einsum("ij,ij->i", g, g)
    B = g @ I
    C = float(I @ I)
    tiny = A <= 1e-300
    Asafe = np.where(tiny, 1.0, A)
    chat = B / Asafe
    s = sigma / np.sqrt(2.0 * Asafe)                         # posterior std of c
    la, lb = log_ndtr((lo - chat) / s), log_ndtr((hi - chat) / s)
    with np.errstate(divide="ignore", invalid="ignore"):
        log_mass = lb + np.log1p(-np.exp(np.minimum(la - lb, 0.0)))
    log_int = np.log(s * np.sqrt(2.0 * np.pi)) + log_mass  # log ∫ exp(-A (c - chat)^2 / sigma^2)
    # E[1/c] under that truncated Gaussian, cell by cell of a log grid
    lo_g = max(lo, hi * 1e-6)
    edges = np.geomspace(lo_g, hi, STRENGTH_CELLS + 1)
    t = (edges[None, :] - chat[:, None]) / s[:, None]
    log_below, log_above = log_ndtr(t), log_ndtr(-t)
    mass = np.diff(np.exp(log_below), axis=1)
    pdf = np.exp(-0.5 * t * t) / np.sqrt(2.0 * np.pi)
    mid = np.sqrt(edges[:-1] * edges[1:])
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        # 1/c at the mean of c within each cell (exact as the Gaussian narrows)
        within = chat[:, None] + s[:, None] * (pdf[:, :-1] - pdf[:, 1:]) / mass
        within = np.where(mass > 1e-12, within, mid)
        # a cell narrow against the Gaussian: its density is linear across it, and the
        # difference of densities above would cancel to round-off
        width, centre = np.diff(edges), 0.5 * (edges[:-1] + edges[1:])
        linear = centre - width ** 2 / 12.0 * (centre - chat[:, None]) / s[:, None] ** 2
        within = np.clip(np.where(np.diff(t, axis=1) < 1e-2, linear, within), edges[:-1], edges[1:])
        # the cells' shares of the mass from their logarithms: far in a tail (a node
        # whose fitted strength lies far outside the prior) the masses themselves
        # underflow, and their ratios are what counts
        la, lb = log_below[:, :-1], log_below[:, 1:]
        ua, ub = log_above[:, :-1], log_above[:, 1:]
        low = lb + np.log1p(-np.exp(np.minimum(la - lb, 0.0)))
        high = ua + np.log1p(-np.exp(np.minimum(ub - ua, 0.0)))
        log_cell = np.where(t[:, :-1] + t[:, 1:] < 0, low, high)
        top = log_cell.max(axis=1, keepdims=True)
        share = np.exp(log_cell - top)
        mean_inv = np.sum(share / within, axis=1) / share.sum(axis=1)
        # a Gaussian so wide that no cell differs from the next: the prior alone
        flat = np.log(hi / lo_g) / (hi - lo_g)
        mean_inv = np.where(np.isfinite(mean_inv) & np.isfinite(top[:, 0]), mean_inv, flat)
    misfit = (C - B * chat) / sigma ** 2 - log_int - np.log(mean_inv)
    del log_below, log_above
    # a node no reading sees: the likelihood does not depend on c, the prior integrates to 1
    misfit = np.where(tiny, C / sigma ** 2 - np.log(np.log(hi / lo_g)), misfit)
    if saturated.any():
        c = np.clip(chat, lo, hi)
        r = np.minimum(c[:, None] * g_all[:, saturated] - readings[saturated], 0.0)
        misfit = misfit + np.sum(r * r, axis=1) / sigma ** 2
    return np.where(np.isfinite(misfit), misfit, np.inf)
