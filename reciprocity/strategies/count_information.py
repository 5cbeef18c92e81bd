"""What a Poisson count would tell about where the source is: the ``"info"`` next-point rule
of the wind searches.

A reading at ``z`` over a dwell ``Δt`` counts ``n ~ Poisson(μ)``, ``μ = (q g(z; x) + b) Δt``
for a source at ``x`` of release rate ``q``. Over a posterior sample of (node, rate) pairs
the count's mutual information with the source's node,

    I(n; x) = H(n) − Σ_x p(x) H(n | x),

``p(n | x)`` the mixture over the pairs of that node, is what the reading is expected to
take off the entropy of the belief over positions (Vergassola et al.'s infotaxis score, for
a jump to any point rather than a step). By reciprocity one *forward* solve per sampled
node gives ``g(z; x)`` at every candidate ``z`` at once
(:meth:`~reciprocity.strategies.reciprocity_wind.ArenaCounts.from_sources`).
"""

from __future__ import annotations

import numpy as np
from scipy.special import gammaln
from scipy.stats import poisson

__all__ = ["count_information", "systematic_sample", "LEFT_OUT", "MAX_COUNT"]

#: Largest count a score sums to.
MAX_COUNT = 2000
#: Predictive mass beyond the largest count summed.
LEFT_OUT = 1e-4
#: Elements (candidates x counts x samples) of one vectorised block.
CHUNK = 2_000_000


def systematic_sample(weights: np.ndarray, m: int, rng: np.random.Generator) -> np.ndarray:
    """`m` indices drawn by systematic resampling from `weights` (n,) summing to 1."""
    cdf = np.cumsum(weights)
    u = (rng.random() + np.arange(m)) / m
    return np.minimum(np.searchsorted(cdf, u * cdf[-1], side="right"), len(weights) - 1)


def count_information(mean: np.ndarray, group: np.ndarray) -> np.ndarray:
    """Mutual information (nats) between a Poisson count and the group (the node) of equally
    weighted samples, for each candidate reading.

    Parameters
    ----------
    mean : numpy.ndarray
        (k, m) mean count of each of `m` samples at each of `k` candidate readings, > 0.
    group : numpy.ndarray
        (m,) the group (e.g. the node) of each sample, integers.

    Returns
    -------
    numpy.ndarray
        (k,) ``I(n; group)``, the count summed from 0 to the 1 − :data:`LEFT_OUT` quantile of
        the largest mean (at most :data:`MAX_COUNT`).

    Examples
    --------
    >>> mean = np.array([[1.0, 1.0], [0.1, 20.0]])
    >>> info = count_information(mean, np.array([0, 1]))
    >>> bool(info[0] < 1e-12), bool(info[1] > 0.6)
    (True, True)
    """
    mean = np.asarray(mean, dtype=float)
    k, m = mean.shape
    top = int(min(MAX_COUNT, poisson.ppf(1 - LEFT_OUT, float(mean.max()))))
    n = np.arange(top + 1, dtype=float)
    groups, member = np.unique(np.asarray(group, dtype=int), return_inverse=True)
    share = np.bincount(member).astype(float) / m                              # p(group)
    # (m, g): the mean over a group's samples
    average = np.zeros((m, len(groups)))
    average[np.arange(m), member] = 1.0 / np.bincount(member)[member]
    out = np.empty(k)
    chunk = max(1, CHUNK // (len(n) * m))
    for c0 in range(0, k, chunk):
        mu = mean[c0:c0 + chunk]                                               # (c, m)
        log_p = n[None, :, None] * np.log(mu)[:, None, :] - mu[:, None, :] - gammaln(n + 1)[None, :, None]
        cond = np.exp(log_p) @ average                                         # p(n | group), (c, N, g)
        marginal = cond @ share                                                # p(n), (c, N)
        out[c0:c0 + chunk] = _entropy(marginal.T) - share @ _entropy(cond.transpose(1, 0, 2).reshape(len(n), -1)) \
            .reshape(len(mu), len(groups)).T
    return np.maximum(out, 0.0)


def _entropy(p: np.ndarray) -> np.ndarray:
    """Entropy (nats) of the distributions in the columns of `p` (or of `p`), with 0 log 0 = 0;
    each column renormalised over the counts summed."""
    p = p / p.sum(axis=0)
    with np.errstate(divide="ignore", invalid="ignore"):
        return -np.where(p > 0, p * np.log(p), 0.0).sum(axis=0)
