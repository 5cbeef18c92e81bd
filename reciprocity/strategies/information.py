"""Expected information of a reading, for choosing where to measure next.

By reciprocity the reading at ``y`` for a source at ``x`` has mean ``c G(y, x) =
c G(x, y)``: one adjoint solve per *candidate source* ``x`` gives the predicted reading
at *every* observation point. The candidate sources and the observation points are the
nodes of one coarse lattice of mesh nodes (:func:`lattice_nodes`); the columns
``G(lattice, x)`` are solved on demand, several in one back-substitution, and kept per
solver (:class:`LatticeGreens`), so a search whose belief has settled on a few lattice
cells solves nothing new. :func:`expected_entropy` scores every observation point by the
entropy of the belief expected after reading there.
"""

from __future__ import annotations


import numpy as np

from arenas.memo import sized_cache

from ..beliefs.base import expected_entropy as _expected_entropy
from ..fem.green import GreenSolver

__all__ = ["lattice_nodes", "LatticeGreens", "lattice_greens", "expected_entropy",
           "two_step_entropy", "mutual_information", "systematic_support"]

#: Gauss-Hermite nodes (in noise standard deviations) and weights of a reading's noise in
#: :func:`two_step_entropy`: exact for polynomials of degree 5 in the noise.
HERMITE_NODES = np.array([-np.sqrt(3.0), 0.0, np.sqrt(3.0)])
HERMITE_WEIGHTS = np.array([1.0, 4.0, 1.0]) / 6.0


def lattice_nodes(points: np.ndarray, spacing: float) -> np.ndarray:
    """Indices of one node per occupied square cell of side `spacing`: the node nearest
    to the cell's centre.

    Parameters
    ----------
    points : ndarray, shape (n, 2)
        Mesh nodes, cm.
    spacing : float
        Cell side, cm.

    Returns
    -------
    ndarray of int, shape (L,)
        Node indices, sorted.
    """
    cell = np.floor(points / spacing).astype(np.int64)
    centre = (cell + 0.5) * spacing
    dist = np.hypot(*(points - centre).T)
    key = (cell[:, 0] - cell[:, 0].min()) * (np.ptp(cell[:, 1]) + 1) + (cell[:, 1] - cell[:, 1].min())
    order = np.lexsort((dist, key))
    first = np.ones(len(order), dtype=bool)
    first[1:] = key[order][1:] != key[order][:-1]
    return np.sort(order[first])


class LatticeGreens:
    """``G(y, x)`` for lattice nodes ``y`` and ``x``, columns solved on demand.

    Parameters
    ----------
    solver : GreenSolver
        A P1 solver (a point source at a node is the unit load vector of its dof).
    spacing : float
        Lattice spacing, cm (see :func:`lattice_nodes`).

    Attributes
    ----------
    nodes : ndarray of int, shape (L,)
        The lattice's mesh-node indices.
    points : ndarray, shape (L, 2)
        Their coordinates, cm.
    anchor : ndarray of int, shape (n_nodes,)
        For every mesh node, the position in :attr:`nodes` of the nearest lattice node.
    n_solved : int
        Columns solved so far (for timing reports).
    """

    def __init__(self, solver: GreenSolver, spacing: float):
        from scipy.spatial import cKDTree
        self.solver = solver
        self.nodes = lattice_nodes(solver.nodes, spacing)
        self.points = solver.nodes[self.nodes]
        self.anchor = cKDTree(self.points).query(solver.nodes)[1]
        self._columns = np.full((len(self.nodes), len(self.nodes)), np.nan, dtype=np.float32)
        self._have = np.zeros(len(self.nodes), dtype=bool)
        self.n_solved = 0

    def columns(self, anchors: np.ndarray) -> np.ndarray:
        """``G(lattice, x_a)`` for lattice positions `anchors`, shape (L, len(anchors)).

        Missing columns are solved together: one multi-column back-substitution."""
        anchors = np.asarray(anchors, dtype=np.int64)
        missing = np.unique(anchors[~self._have[anchors]])
        if missing.size:
            rhs = np.zeros((self.solver.basis.N, missing.size))
            rhs[self.nodes[missing], np.arange(missing.size)] = 1.0
            g = self.solver.solve(rhs)
            self._columns[:, missing] = g[self.nodes]
            self._have[missing] = True
            self.n_solved += int(missing.size)
        return self._columns[:, anchors].astype(float)


#: Bytes of lattice Green's functions kept per process.
LATTICE_CACHE_BYTES = 200 * 2**20


@sized_cache(LATTICE_CACHE_BYTES, maxsize=4)
def lattice_greens(solver: GreenSolver, spacing: float) -> LatticeGreens:
    """The :class:`LatticeGreens` of `solver`, shared by every search on it in a process
    (its columns depend only on the geometry)."""
    return LatticeGreens(solver, float(spacing))


def systematic_support(weights: np.ndarray, k: int, rng: np.random.Generator
                       ) -> tuple[np.ndarray, np.ndarray]:
    """At most `k` distinct indices drawn by systematic resampling, with their weights.

    Parameters
    ----------
    weights : ndarray, shape (L,)
        Non-negative masses.
    k : int
        Draws.
    rng : numpy.random.Generator
        Draws the common offset.

    Returns
    -------
    index : ndarray of int
        Distinct drawn indices.
    weight : ndarray
        Their share of the draws (sums to 1).
    """
    c = np.cumsum(weights / weights.sum())
    u = (rng.random() + np.arange(k)) / k
    drawn = np.minimum(np.searchsorted(c, u), len(weights) - 1)
    index, count = np.unique(drawn, return_counts=True)
    return index, count / k


def expected_entropy(means: np.ndarray, weights: np.ndarray, noise: float) -> np.ndarray:
    """Expected entropy (nats) of the belief over K support points after one reading at
    each candidate.

    For a true source at support point ``j`` the reading at candidate ``y`` is
    ``means[y, j]`` plus Gaussian noise of std `noise`; averaged over that noise, the
    belief weight of point ``i`` is proportional to ``w_i N(means[y, i]; means[y, j],
    2 noise^2)`` (the product of two Gaussians integrated over the reading). The score
    is ``Σ_j w_j H(π_{·|j}(y))``. Support points a candidate cannot tell apart keep
    their share of the entropy; a candidate whose predicted readings differ by several
    noise standard deviations between two modes removes ``log 2`` of it.

    Parameters
    ----------
    means : ndarray, shape (m, K)
        Predicted reading at m candidates for each of K support points (signal units).
    weights : ndarray, shape (K,)
        Belief weights of the support points (sum 1).
    noise : float
        Standard deviation of a reading, signal units.

    Returns
    -------
    ndarray, shape (m,)
        Expected entropy, nats.
    """
    diff = means.T[:, :, None] - means[None, :, :]                    # (j, m, i): outcome j
    log_joint = np.log(np.maximum(weights, 1e-300))[None, None, :] - (diff * diff) / (4.0 * noise * noise)
    return _expected_entropy(log_joint, weights[:, None], log=True)


def two_step_entropy(first: np.ndarray, second: np.ndarray, weights: np.ndarray, noise: float,
                     apart: np.ndarray | None = None) -> np.ndarray:
    """Expected entropy (nats) of the belief after a reading at each first candidate and
    then one more at the best second candidate for what the first one read.

    For a true source at support point ``j`` (probability ``w_j``) the first reading at
    ``y1`` is ``first[y1, j] + noise ξ``, with ξ integrated by 3-point Gauss-Hermite
    quadrature (:data:`HERMITE_NODES`); each outcome gives the exact posterior ``π`` over
    the support, and the second reading is scored by :func:`expected_entropy` under ``π``
    at every second candidate, the best one kept:
    ``E(y1) = Σ_j w_j Σ_q g_q min_{y2} E_π(y1, j, q)(y2)``. A second point may be read
    only where `apart` allows it (e.g. at least the least separation from ``y1``).

    Parameters
    ----------
    first : ndarray, shape (m1, K)
        Predicted reading at the m1 first candidates for each of K support points (signal
        units).
    second : ndarray, shape (m2, K)
        The same at the m2 second candidates.
    weights : ndarray, shape (K,)
        Belief weights of the support points (sum 1).
    noise : float
        Standard deviation of a reading, signal units.
    apart : ndarray of bool, shape (m1, m2), optional
        Whether second candidate ``y2`` may follow first candidate ``y1``; default all.

    Returns
    -------
    ndarray, shape (m1,)
        Expected entropy after both readings, nats (at most :func:`expected_entropy` of the
        first reading alone, up to the quadrature, when the second may be anywhere).
    """
    from scipy.special import logsumexp
    first = np.asarray(first, dtype=float)
    second = np.asarray(second, dtype=float)
    w = np.asarray(weights, dtype=float)
    w = w / w.sum()
    logw = np.log(np.maximum(w, 1e-300))
    two_var = 2.0 * noise * noise
    # the second reading's pair kernel, exp of the log N-overlap of support points i, k at y2
    d2 = second[:, :, None] - second[:, None, :]                      # (m2, k, i)
    log_pair = -(d2 * d2) / (2.0 * two_var)
    pair = np.exp(log_pair)
    m1, k_ = first.shape
    m2 = len(second)
    # outcomes o = (y1, j, q): the first reading for true source j and noise node q
    reads = first[:, :, None] + noise * HERMITE_NODES[None, None, :]  # (m1, j, q)
    lpost = logw[None, None, None, :] - (reads[..., None] - first[:, None, None, :]) ** 2 / two_var
    lpost -= logsumexp(lpost, axis=-1, keepdims=True)                 # (m1, j, q, i)
    lpost = lpost.reshape(-1, k_)
    post = np.exp(lpost)
    # after outcome o, a second reading at y2 whose true source is k leaves weights
    # u_i = post_i pair[y2, k, i] / Z: entropy log Z - Σ_i u_i log u_i / Z, by three
    # matrix products over i
    flat = pair.reshape(m2 * k_, k_).T                                # (i, y2 k)
    z = post @ flat
    b = (post * lpost) @ flat + post @ (pair * log_pair).reshape(m2 * k_, k_).T
    zs = np.maximum(z, 1e-300)
    h = (np.log(zs) - b / zs).reshape(-1, m2, k_)                     # (o, y2, k)
    e2 = np.einsum("ok,omk->om", post, h)                              # (o, y2)
    if apart is not None:
        e2 = np.where(np.repeat(apart, k_ * len(HERMITE_NODES), axis=0), e2, np.inf)
    best = e2.min(axis=1)
    best = np.where(np.isfinite(best), best, -np.sum(post * lpost, axis=1))
    g = (w[:, None] * HERMITE_WEIGHTS[None, :]).reshape(-1)           # (j q)
    return best.reshape(m1, -1) @ g


def mutual_information(means: np.ndarray, weights: np.ndarray, noise: float,
                       bins_per_sd: float = 4.0) -> np.ndarray:
    """Mutual information (nats) between the source and one reading, at each candidate.

    The reading at candidate ``y`` is the mixture ``Σ_j w_j N(means[y, j], noise^2)``;
    ``I = h(reading) - ½ log(2 π e noise^2)``. The mixture's density is deposited on a grid
    of ``noise / bins_per_sd`` (linear weights onto the two nearest bins), convolved with
    the noise's Gaussian and integrated by the midpoint rule: O(m K) work, against the
    O(m K²) of :func:`expected_entropy`, so the belief can keep hundreds of support points.
    The discretisation adds an error of order ``(1 / bins_per_sd)^2 / 12`` nats.

    Parameters
    ----------
    means : ndarray, shape (m, K)
        Predicted reading at m candidates for each of K support points (signal units).
    weights : ndarray, shape (K,)
        Belief weights of the support points (sum 1).
    noise : float
        Standard deviation of a reading, signal units.
    bins_per_sd : float
        Grid cells per noise standard deviation.

    Returns
    -------
    ndarray, shape (m,)
        Mutual information, nats (0 where every support point predicts the same reading).
    """
    from scipy.ndimage import gaussian_filter1d
    means = np.asarray(means, dtype=float)
    w = np.asarray(weights, dtype=float)
    w = w / w.sum()
    m = means.shape[0]
    dy = noise / bins_per_sd
    pad = 5.0 * noise
    lo = means.min(axis=1, keepdims=True) - pad                       # per candidate
    span = means.max(axis=1) - means.min(axis=1) + 2 * pad
    nb = int(np.ceil(span.max() / dy)) + 2
    pos = (means - lo) / dy
    i0 = np.floor(pos).astype(np.int64)
    f = pos - i0
    rows = (np.arange(m) * nb)[:, None]
    hist = np.bincount((rows + i0).ravel(), (w[None, :] * (1.0 - f)).ravel(), minlength=m * nb)
    hist += np.bincount((rows + i0 + 1).ravel(), (w[None, :] * f).ravel(), minlength=m * nb)
    dens = gaussian_filter1d(hist.reshape(m, nb), bins_per_sd, axis=1, mode="constant", truncate=5.0)
    p = dens / np.maximum(dens.sum(axis=1, keepdims=True), 1e-300)
    with np.errstate(divide="ignore", invalid="ignore"):
        h = -np.sum(np.where(p > 0, p * np.log(p), 0.0), axis=1) + np.log(dy)
    return np.maximum(h - 0.5 * np.log(2 * np.pi * np.e * noise ** 2), 0.0)
