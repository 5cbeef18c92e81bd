"""Free-energy infotaxis in wind among walls (issue 38): Song, He & Lei's criterion on counts.

The free-energy rule of papers/002 (eqs. (8)-(10); :class:`~reciprocity.strategies.infotaxis.FreeEnergyInfotaxis`
on the plume worlds) on the ``flow`` worlds, with two likelihoods, as infotaxis in wind has:

- ``free-energy-wind``: the arena's own model (it sees the walls);
- ``free-space-free-energy-wind``: the plume papers' wall-blind model.

Everything but the score is :class:`~reciprocity.strategies.infotaxis_wind.WindInfotaxis`'s:
the count posterior, the candidate moves (one per sector, at most ``step`` cm), the
(node, rate) pairs summed over, the jump when no move is left, the credible stop. The score
of a move to ``z`` is the expected free energy after a count ``k`` there,

    F(z) = Σ_k p(k) [ W_k + α tr(Σ_k)^β S_k ],

``W_k = Σ_x p(x | k) |z − x|^γ`` the potential energy (eq. (4)), ``Σ_k`` the covariance and
``S_k`` the entropy of the posterior over nodes after ``k`` (eqs. (9)-(10)); the move of
least ``F`` is taken. The paper's lattice has unit cells and unit moves; here lengths are
measured in moves (``step``), so that its ``α = 0.01, β = 1.4, γ = 3`` weigh the terms as on
its lattice.
"""

from __future__ import annotations

import numpy as np
from scipy.special import gammaln
from scipy.stats import poisson

from ..validation import positive
from . import register
from .infotaxis_wind import LEFT_OUT, MAX_COUNT, WindInfotaxis
from .reciprocity_wind import BACKGROUND, CREDIBLE_RADIUS, D_READ, MAX_STEPS, FreeSpaceCounts

__all__ = ["WindFreeEnergy", "FreeSpaceWindFreeEnergy", "expected_free_energy"]


def expected_free_energy(weights: np.ndarray, node: np.ndarray, mean: np.ndarray, nodes: np.ndarray,
                         z: np.ndarray, alpha: float, beta: float, gamma: float) -> float:
    """Expected free energy of a reading at `z` after one Poisson count (see the module doc).

    Parameters
    ----------
    weights : numpy.ndarray
        (m,) posterior weights of (node, rate) pairs, summing to 1.
    node : numpy.ndarray
        (m,) the node index of each pair.
    mean : numpy.ndarray
        (m,) the mean count of each pair at the reading, > 0.
    nodes : numpy.ndarray
        (n, 2) the nodes' positions, in the unit of the energy (moves).
    z : numpy.ndarray
        (2,) the reading point, same unit.
    alpha, beta, gamma : float
        The temperature's factor and exponent, and the distance's exponent.

    Returns
    -------
    float
        ``Σ_k p(k) [W_k + α tr(Σ_k)^β S_k]``, ``k`` from 0 to the 1 − LEFT_OUT quantile of
        the predictive (at most MAX_COUNT).
    """
    top = int(min(MAX_COUNT, poisson.ppf(1 - LEFT_OUT, float(mean.max()))))
    k = np.arange(top + 1, dtype=float)
    log_p = k[:, None] * np.log(mean)[None, :] - mean[None, :] - gammaln(k + 1)[:, None]
    joint = weights[None, :] * np.exp(log_p)                                  # (K, m)
    used, slot = np.unique(node, return_inverse=True)                        # the nodes the pairs hold
    per_node = np.zeros((len(k), len(used)))
    np.add.at(per_node.T, slot, joint.T)
    p_k = per_node.sum(axis=1)
    keep = p_k > 0
    post = per_node[keep] / p_k[keep, None]                                  # p(x | k)
    x = nodes[used]
    potential = post @ (np.hypot(*(x - z).T) ** gamma)                        # W_k
    mean_x = post @ x
    spread = np.maximum(post @ np.sum(x * x, axis=1) - np.sum(mean_x ** 2, axis=1), 0.0)   # tr(Σ_k)
    with np.errstate(divide="ignore", invalid="ignore"):
        entropy = -np.where(post > 0, post * np.log(post), 0.0).sum(axis=1)   # S_k
    pk = p_k[keep] / p_k[keep].sum()
    return float(pk @ (potential + alpha * spread ** beta * entropy))


@register
class WindFreeEnergy(WindInfotaxis):
    """Free-energy infotaxis in wind with the arena's likelihood (see the module doc).

    Parameters
    ----------
    alpha, beta : float
        Temperature ``T = α tr(Σ)^β``, lengths in moves (the paper's 0.01, 1.4).
    gamma : float
        Exponent of the distance in the potential energy (the paper's 3).
    step, moves, support, h, d, reach
        As :class:`~reciprocity.strategies.infotaxis_wind.WindInfotaxis`.
    credible_radius, credible_mass, max_steps, clearance, background, source_clearance
        As :class:`~reciprocity.strategies.infotaxis_wind.WindInfotaxis`.
    """

    name = "free-energy-wind"

    def __init__(self, *, alpha: float = 0.01, beta: float = 1.4, gamma: float = 3.0, step: float = 8.0,
                 moves: int = 12, support: int = 4096, h: float = 2.0, d: float = D_READ, reach: float = 12.0,
                 credible_radius: float = CREDIBLE_RADIUS, credible_mass: float = 0.95, max_steps: int = MAX_STEPS,
                 clearance: float = 3.0, background: float = BACKGROUND, source_clearance: float | str = "task"):
        super().__init__(step=step, moves=moves, support=support, h=h, d=d, reach=reach,
                         credible_radius=credible_radius, credible_mass=credible_mass, max_steps=max_steps,
                         clearance=clearance, background=background, source_clearance=source_clearance)
        self.alpha = positive(alpha, "alpha")
        self.beta = positive(beta, "beta")
        self.gamma = positive(gamma, "gamma")

    def params(self) -> dict:
        return dict(super().params(), alpha=self.alpha, beta=self.beta, gamma=self.gamma)

    def _choose_next(self) -> None:
        cands = self._moves()
        if len(cands) == 0:
            super(WindInfotaxis, self)._choose_next()
            return
        pairs, node, rate = self._pairs()
        unit = self.space.points / self.step
        scores = [expected_free_energy(pairs, node, self._mean(z, node, rate), unit, z / self.step, self.alpha,
                                       self.beta, self.gamma) for z in cands]
        self._next = cands[int(np.argmin(scores))].copy()
        self.status.extra["next"] = self._next.tolist()
        self.status.extra["free_energy"] = float(np.min(scores))


@register
class FreeSpaceWindFreeEnergy(WindFreeEnergy):
    """:class:`WindFreeEnergy` with the free-space likelihood of a uniform wind, blind to the
    walls (the plume papers' own model)."""

    name = "free-space-free-energy-wind"
    model = FreeSpaceCounts
