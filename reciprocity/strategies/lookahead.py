"""A plume searcher beyond the papers: a one- or two-step look-ahead of a cost-to-go.

The infotaxis family (:mod:`reciprocity.strategies.infotaxis`) scores each move by one
quantity of the belief expected after the next reading. :class:`Lookahead` generalises
this in two directions:

*What is scored* (``cost``), for a belief ``p`` (weights ``w_i`` on sources ``x_i``) with
the searcher at ``r``, the found case scoring 0:

``"entropy"``
    ``H(p)`` (nats): with ``depth=1`` this is infotaxis exactly (eq. (3) of papers/002
    up to the constant ``S``).
``"space-aware"``
    otto's ``log2(D + 2^(H/ln 2 − 1) − 1/2)``, ``D`` the mean Manhattan distance in steps;
    with ``depth=1`` this is otto's space-aware infotaxis exactly.
``"distance"``
    ``(Σ w_i |r − x_i|^q)^(1/q) + κ sqrt(tr Σ(p))`` (length units, ``q`` = `power`):
    a power mean of the remaining path if the source were shown now, plus ``κ`` times
    the belief's spread in length units, a stand-in for the detour still needed to
    learn where it is (the reciprocity search also mixes distance to the belief with
    an information term). With ``q = 3`` the first term is the cube root of free
    energy's potential (eq. (4) of papers/002, γ = 3), so it is in length units and
    comparable with the spread; papers/002 instead adds ``α tr(Σ)^β`` times the
    entropy, which with its printed α, β is orders of magnitude smaller than the potential
    (``docs/papers/song2019.md``). Unlike the particle entropy, the
    spread does not reset when the cloud is resampled. Defaults ``q = 3``, ``κ = 2``:
    the best of the settings measured on ``song-100``.

*How far ahead* (``depth``): ``1`` scores ``(1 − P_f(v)) Σ_z ρ_z(v) C(r_v, p_z)``;
``2`` replaces ``C(r_v, p_z)`` by the best score of the second move from ``r_v`` after
outcome ``z`` (an expectimin tree over two readings, one vectorised pass over
moves × outcomes × moves × outcomes × particles). Outcomes at the second level are
Poisson counts summed up to ``second_kmax`` with the tail lumped into the last (otto's
hit cap is used where the world has one).

Measured against free energy, infotaxis and a walker that knows the source, on ``song-100``
and ``otto-2d``: ``benchmarks/plume_beyond.md``, section 1.
"""

from __future__ import annotations

import numpy as np

from ..errors import SearchError
from ..validation import positive
from ..models.plume import plume_rate
from ..beliefs.base import posterior_entropies
from ..beliefs.particles import outcome_table, _poisson_ppf
from . import register
from .infotaxis import PlumeSearch

__all__ = ["Lookahead", "COSTS", "move_set"]

#: Costs a :class:`Lookahead` can score (see the module doc).
COSTS = ("entropy", "space-aware", "distance")


def move_set(nominal: dict, positions: np.ndarray, headings: np.ndarray):
    """Every next place and heading from each of `positions` (n, 2), with a mask of those
    inside the area.

    Returns
    -------
    points : ndarray, shape (n, k, 2)
    headings : ndarray, shape (n, k)
    inside : ndarray of bool, shape (n, k)

    Notes
    -----
    The same moves, in the same order, as
    :func:`reciprocity.strategies.infotaxis.candidate_moves`, but without dropping the
    places outside the area (so that every position has the same number of moves).
    """
    p = np.asarray(positions, dtype=float).reshape(-1, 2)
    h = np.asarray(headings, dtype=float).reshape(-1)
    step, motion = float(nominal["step"]), nominal["motion"]
    if motion == "turn":
        hd = h[:, None] + np.asarray(nominal["turns"])[None, :]
        pts = p[:, None, :] + step * np.stack([np.cos(hd), np.sin(hd)], axis=-1)
    else:
        dirs = [(-1, 0), (1, 0), (0, -1), (0, 1)]
        if motion == "reach" or nominal.get("moves", 4) == 8:
            dirs += [(-1, -1), (1, -1), (-1, 1), (1, 1)]
        d = np.array(dirs, dtype=float)
        pts = p[:, None, :] + step * d[None]
        hd = np.broadcast_to(np.arctan2(d[:, 1], d[:, 0]), pts.shape[:2]).copy()
    (x0, x1), (y0, y1) = nominal["bounds"]
    inside = (pts[..., 0] >= x0) & (pts[..., 0] <= x1) & (pts[..., 1] >= y0) & (pts[..., 1] <= y1)
    return pts, hd, inside


@register
class Lookahead(PlumeSearch):
    """Expected cost-to-go after one or two readings (beyond the papers; see the module doc).

    Parameters
    ----------
    cost : {"distance", "entropy", "space-aware"}
        What is scored on each expected belief.
    depth : {1, 2}
        Readings looked ahead.
    kappa : float
        Weight of the spread in the ``"distance"`` cost (dimensionless).
    power : float
        The ``"distance"`` cost's distance term is the power mean
        ``(Σ w_i |r − x_i|^power)^(1/power)`` (length units; 1: the mean distance).
    second_kmax : int
        Largest count told apart at the second level (the rest lumped), >= 1.
    particles, resample_below, mcmc_steps, eta
        As for :class:`reciprocity.strategies.infotaxis.PlumeSearch`.
    """

    name = "lookahead"

    def __init__(self, *, cost: str = "distance", depth: int = 1, kappa: float = 2.0, power: float = 3.0,
                 second_kmax: int = 6,
                 particles: int = 600, resample_below: float = 1 / 3, mcmc_steps: int = 1, eta: float = 1e-3):
        if cost not in COSTS:
            raise SearchError(f"cost must be one of {', '.join(COSTS)}; got {cost!r}")
        if depth not in (1, 2) or isinstance(depth, bool):
            raise SearchError(f"depth must be 1 or 2; got {depth!r}")
        self.cost = cost
        self.depth = depth
        self.kappa = positive(kappa, "kappa")
        self.power = positive(power, "power")
        self.second_kmax = positive(second_kmax, "second_kmax", integer=True)
        super().__init__(particles=particles, resample_below=resample_below, mcmc_steps=mcmc_steps, eta=eta)

    def params(self) -> dict:
        return dict(super().params(), cost=self.cost, depth=self.depth, kappa=self.kappa, power=self.power,
                    second_kmax=self.second_kmax)

    # -- the cost of a batch of beliefs -----------------------------------------------------
    def _cost(self, joint: np.ndarray, at: np.ndarray) -> np.ndarray:
        """Cost of each belief ``joint[..., i] / Σ_i joint[..., i]`` with the searcher at
        `at` (broadcast over the leading axes but the first, the outcome), shape ``joint.shape[:-1]``.

        Parameters
        ----------
        joint : ndarray, shape (K, ..., M)
            Unnormalised posterior weights, one belief per leading index.
        at : ndarray, shape (..., 2)
            Searcher position for each belief (without the outcome axis).
        """
        x = self.belief.support()
        P = joint.sum(axis=-1)
        Ps = np.maximum(P, 1e-300)
        if self.cost in ("entropy", "space-aware"):
            H = posterior_entropies(joint)[1]         # 0 where P = 0, as _expected has it
            if self.cost == "entropy":
                return H
            cell = float(self.nominal["step"])
            man = (np.abs(at[..., None, 0] - x[:, 0]) + np.abs(at[..., None, 1] - x[:, 1])) / cell
            D = (joint * man[None]).sum(axis=-1) / Ps
            v = D + 2.0 ** (H / np.log(2.0) - 1.0) - 0.5
            return np.where(v > 0, np.log2(np.where(v > 0, v, 1.0)), v)
        dist = np.hypot(at[..., None, 0] - x[:, 0], at[..., None, 1] - x[:, 1])
        if self.power == 1.0:
            D = (joint * dist[None]).sum(axis=-1) / Ps
        else:
            D = ((joint * dist[None] ** self.power).sum(axis=-1) / Ps) ** (1.0 / self.power)
        m = np.einsum("...i,ic->...c", joint, x) / Ps[..., None]
        second = (joint * np.sum(x * x, axis=1)).sum(axis=-1) / Ps
        tr = np.maximum(second - np.sum(m * m, axis=-1), 0.0)
        return D + self.kappa * np.sqrt(tr)

    def _expected(self, joint, P, at):
        """``Σ_z ρ_z C(at, p_z)`` over the outcome axis 0 of `joint`, given not found."""
        rho = P / np.maximum(P.sum(axis=0, keepdims=True), 1e-300)
        return np.sum(rho * np.where(P > 0, self._cost(joint, at), 0.0), axis=0)

    # -- scoring -----------------------------------------------------------------------------
    def scores(self, cands):
        joint, p_found, _ = self.belief.outcomes(cands, eta=self.eta)     # (K+1, m, M)
        P = joint.sum(axis=2)
        if self.depth == 1:
            return (1.0 - p_found) * self._expected(joint, P, cands)
        return (1.0 - p_found) * self._second(cands, joint, P)

    def _second(self, cands, joint, P):
        """Depth two: ``Σ_z ρ_z min_u (1 − P_f(u | z)) Σ_z' ρ_z' C(r_u, p_zz')`` per first move."""
        b = self.belief
        x = b.support()
        # headings after each first move (the same order as candidate_moves)
        _, hds_all, inside_all = move_set(self.nominal, self.pos[None], np.array([self.heading]))
        hds = hds_all[0][inside_all[0]]
        pts2, _, inside2 = move_set(self.nominal, cands, hds)          # (m, k, 2), (m, k)
        m, k = inside2.shape
        post = joint / np.maximum(P[..., None], 1e-300)                 # (Z, m, M) posteriors after z
        d2 = np.hypot(pts2[..., None, 0] - x[:, 0], pts2[..., None, 1] - x[:, 1])    # (m, k, M)
        near = d2 <= b.found_radius
        w2 = post[:, :, None, :] * ~near[None]                          # (Z, m, k, M)
        mass = w2.sum(axis=-1)
        pf2 = 1.0 - mass                                                # (Z, m, k)
        w2 = w2 / np.maximum(mass[..., None], 1e-300)
        mu2 = plume_rate(pts2.reshape(-1, 2), x, b.params).reshape(m, k, -1) * b.dt
        if b.max_hits is not None:
            cap = b.max_hits
            table = outcome_table(mu2, cap, cap)
        else:
            mbar = float(np.max(np.einsum("zmki,mki->zmk", w2, mu2)))
            top = min(int(_poisson_ppf(1.0 - self.eta, mbar)), self.second_kmax)
            table = outcome_table(mu2, top, top)                        # tail lumped at top
        joint2 = table[:, None] * w2[None]                              # (Z', Z, m, k, M)
        P2 = joint2.sum(axis=-1)
        inner = (1.0 - np.clip(pf2, 0.0, 1.0)) * self._expected(joint2, P2, pts2[None])   # (Z, m, k)
        inner = np.where(inside2[None], inner, np.inf)
        best = np.min(inner, axis=2)                                    # (Z, m)
        best = np.where(np.isfinite(best), best, self._expected(joint, P, cands)[None])
        rho = P / np.maximum(P.sum(axis=0, keepdims=True), 1e-300)
        return np.sum(np.where(P > 0, rho * best, 0.0), axis=0)
