"""Infotaxis in wind among walls (issue 38): the step of least expected entropy, from counts.

The infotaxis rule of the plume papers (Vergassola et al.; Song et al., papers/002) on the
``flow`` worlds, with two likelihoods, so that it meets reciprocity in wind on one footing:

- ``infotaxis-wind``: the arena's own model (:class:`~reciprocity.strategies.reciprocity_wind.ArenaCounts`:
  the advection-diffusion-decay Green's function of the arena's wind, which sees the walls);
- ``free-space-infotaxis-wind``: the plume papers' own model
  (:class:`~reciprocity.strategies.reciprocity_wind.FreeSpaceCounts`: a uniform wind, no walls).

Everything but the next point is :class:`~reciprocity.strategies.reciprocity_wind.WindReciprocity`'s:
the count posterior over (node, release rate) with the task's source clearance, one adjoint
solve per reading, the credible stop and the reading cap. The next point:

- **moves**: the reachable nodes between ``step / 2`` and ``step`` cm from the last point
  read, at least ``d`` from every point read, one per ``moves`` sectors of direction (the
  nearest to ``step`` in each); the point observer walks the free path to it;
- **score**: the expected entropy of the posterior over the source's position after a count
  there, ``Σ_k p(k) H(x | k)``, the counts ``k`` summed from 0 to the 1 − 10⁻⁴ quantile of
  the predictive, over the ``support`` most probable (node, rate) pairs of the posterior
  (renormalised; the rest hold less than 10⁻⁴ of it, or are cut at ``support`` pairs);
- **no move left** (every node near enough is read or out of reach): the reciprocity
  rule's next point (:meth:`WindReciprocity._choose_next`), a jump.
"""

from __future__ import annotations

import numpy as np
from scipy.special import gammaln
from scipy.stats import poisson

from ..validation import number, whole
from . import register
from .reciprocity_wind import BACKGROUND, CREDIBLE_RADIUS, D_READ, MAX_STEPS, FreeSpaceCounts, WindReciprocity

__all__ = ["WindInfotaxis", "FreeSpaceWindInfotaxis", "expected_entropy"]

#: Largest count a score sums to (a reading predicted to hold more is scored up to it).
MAX_COUNT = 2000
#: Posterior mass the pairs left out of a score may hold at most.
LEFT_OUT = 1e-4


def expected_entropy(weights: np.ndarray, node: np.ndarray, mean: np.ndarray, n_nodes: int) -> float:
    """Expected entropy (nats) of the posterior over nodes after one Poisson count.

    Parameters
    ----------
    weights : numpy.ndarray
        (m,) posterior weights of (node, rate) pairs, summing to 1.
    node : numpy.ndarray
        (m,) the node of each pair.
    mean : numpy.ndarray
        (m,) the mean count of each pair at the reading, > 0.
    n_nodes : int
        Number of nodes.

    Returns
    -------
    float
        ``Σ_k p(k) H(x | k)``, ``k`` from 0 to the 1 − :data:`LEFT_OUT` quantile of the
        predictive (at most :data:`MAX_COUNT`).
    """
    top = int(min(MAX_COUNT, poisson.ppf(1 - LEFT_OUT, float(mean.max()))))
    k = np.arange(top + 1, dtype=float)
    # (K, m) joint of count and pair, then marginal over rates per node
    log_p = k[:, None] * np.log(mean)[None, :] - mean[None, :] - gammaln(k + 1)[:, None]
    joint = weights[None, :] * np.exp(log_p)
    per_node = np.zeros((len(k), n_nodes))
    np.add.at(per_node.T, node, joint.T)
    p_k = per_node.sum(axis=1)
    keep = p_k > 0
    post = per_node[keep] / p_k[keep, None]
    with np.errstate(divide="ignore", invalid="ignore"):
        h = -np.where(post > 0, post * np.log(post), 0.0).sum(axis=1)
    return float(np.sum(p_k[keep] * h) / p_k[keep].sum())


@register
class WindInfotaxis(WindReciprocity):
    """Infotaxis in wind with the arena's likelihood: the step of least expected entropy
    (see the module doc).

    Parameters
    ----------
    step : float
        Longest move, cm (moves are between ``step / 2`` and ``step``).
    moves : int
        Sectors of direction, one candidate move each.
    support : int
        Most (node, rate) pairs of the posterior a score sums over.
    h, d, reach, credible_radius, credible_mass, max_steps, clearance, background, source_clearance
        As :class:`~reciprocity.strategies.reciprocity_wind.WindReciprocity` (``reach`` serves
        only the jump when no move is left).
    """

    name = "infotaxis-wind"

    def __init__(self, *, step: float = 8.0, moves: int = 12, support: int = 4096, h: float = 2.0,
                 d: float = D_READ, reach: float = 12.0, credible_radius: float = CREDIBLE_RADIUS,
                 credible_mass: float = 0.95, max_steps: int = MAX_STEPS, clearance: float = 3.0,
                 background: float = BACKGROUND, source_clearance: float | str = "task"):
        # the jump when no move is left stays the reciprocity search's "axis" rule
        super().__init__(rule="axis", h=h, d=d, reach=reach, credible_radius=credible_radius,
                         credible_mass=credible_mass, max_steps=max_steps, clearance=clearance,
                         background=background, source_clearance=source_clearance)
        self.step = number(step, "step", 0.0, 1e3, lo_open=True, unit="cm")
        self.moves = whole(moves, "moves", 1, 360)
        self.support = whole(support, "support", 16, 10 ** 6)

    def params(self) -> dict:
        return dict(super().params(), step=self.step, moves=self.moves, support=self.support)

    def _choose_next(self) -> None:
        cands = self._moves()
        if len(cands) == 0:
            super()._choose_next()
            return
        pairs, node, rate = self._pairs()
        scores = [expected_entropy(pairs, node, self._mean(z, node, rate), len(self.space.points)) for z in cands]
        self._next = cands[int(np.argmin(scores))].copy()
        self.status.extra["next"] = self._next.tolist()
        self.status.extra["expected_entropy"] = float(np.min(scores))

    def _moves(self) -> np.ndarray:
        """Candidate points (n, 2), cm: per sector of direction, the admissible node whose
        distance from the last point read is nearest to :attr:`step`."""
        here = self._here
        r = self.space.points - here
        dist = np.hypot(r[:, 0], r[:, 1])
        ok = self._reachable & self._far & (dist > 0.5 * self.step) & (dist <= self.step)
        idx = np.flatnonzero(ok)
        if idx.size == 0:
            return np.zeros((0, 2))
        sector = np.floor((np.arctan2(r[idx, 1], r[idx, 0]) + np.pi) / (2 * np.pi) * self.moves).astype(int)
        order = np.lexsort((self.step - dist[idx], sector))
        first = np.r_[True, sector[order][1:] != sector[order][:-1]]
        return self.space.points[idx[order][first]]

    def _pairs(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The most probable (node, rate) pairs of the posterior: weights (renormalised),
        node indices and release rates."""
        post = self.belief
        logw = np.where(post.allowed[:, None], post.loglik, -np.inf) + np.log(post.areas)[:, None]
        w = np.exp(logw - logw.max()).ravel()
        w /= w.sum()
        order = np.argsort(w)[::-1]
        keep = int(np.searchsorted(np.cumsum(w[order]), 1 - LEFT_OUT)) + 1
        order = order[:min(keep, self.support)]
        node, cell = np.divmod(order, post.loglik.shape[1])
        pw = w[order]
        return pw / pw.sum(), node, post.rates[cell]

    def _mean(self, z: np.ndarray, node: np.ndarray, rate: np.ndarray) -> np.ndarray:
        """Mean count at `z` of each (node, rate) pair, over one dwell."""
        per_unit = np.maximum(self.counts.rates(z), 0.0)
        return (per_unit[node] * rate + self.background) * self._dwell

    def start(self, ctx) -> None:
        self._here = np.asarray(ctx.start[:2], dtype=float).copy()
        self._dwell = 1.0
        super().start(ctx)

    def observe(self, observations, intent, agent: int = 0) -> None:
        self._dwell = float(observations[0].dwell)
        self._here = np.asarray(observations[0].position, dtype=float)[:2].copy()
        super().observe(observations, intent, agent)


@register
class FreeSpaceWindInfotaxis(WindInfotaxis):
    """:class:`WindInfotaxis` with the free-space likelihood of a uniform wind, blind to the
    walls (the plume papers' own model)."""

    name = "free-space-infotaxis-wind"
    model = FreeSpaceCounts
