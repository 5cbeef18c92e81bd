"""The hidden Markov plume model of Farrell, Pang & Li (2003): the cell grid, the
state-transition matrix A(t) built from the measured flow (their Appendix II), and the
Viterbi recursions on it.

Cells are numbered ``k = i + j m`` (0-based; ``i`` along x, ``j`` along y), the paper's
``k = i + (j - 1) m`` shifted by one; the paper's exterior cell C0 is index ``N`` in the
full ``(N + 1) × (N + 1)`` matrix. The flow is taken uniform over the region (the one
vehicle measures it only where it is), so every interior row of Ā holds the same four
weights ``(1 - ε_x or ε_x) × (1 - ε_y or ε_y)`` with ``ε = |u| dt / L`` (Appendix II);
odour carried over an edge enters C0. Products with Ā are therefore stencil shifts on
the ``n × m`` grid, which is what makes the maps fast.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import sparse

__all__ = ["CellGrid", "TINY", "Transition", "backtrack", "detection_path", "forward_path", "row_combination",
           "transition", "viterbi", "viterbi_backward"]


@dataclass(frozen=True)
class CellGrid:
    """An ``m × n`` cellular subdivision of a rectangle (the paper's Fig. 2).

    Attributes
    ----------
    region : tuple
        ``(x_min, x_max, y_min, y_max)``, m.
    m, n : int
        Cells along x and along y; ``N = m n``.
    """

    region: tuple
    m: int
    n: int

    @property
    def N(self) -> int:
        return self.m * self.n

    @property
    def L(self) -> tuple[float, float]:
        """Cell sizes ``(L_x, L_y)``, m."""
        x0, x1, y0, y1 = self.region
        return (x1 - x0) / self.m, (y1 - y0) / self.n

    def centres(self) -> np.ndarray:
        """Cell centres (N, 2), in cell order."""
        x0, _, y0, _ = self.region
        lx, ly = self.L
        i, j = np.meshgrid(np.arange(self.m), np.arange(self.n))
        return np.c_[x0 + (i.ravel() + 0.5) * lx, y0 + (j.ravel() + 0.5) * ly]

    def index(self, points) -> np.ndarray:
        """Cell index of each point (eqs. (3)–(4) inverted); points on the far edges
        belong to the last cell."""
        p = np.atleast_2d(np.asarray(points, dtype=float))
        x0, _, y0, _ = self.region
        lx, ly = self.L
        i = np.clip(np.floor((p[:, 0] - x0) / lx).astype(int), 0, self.m - 1)
        j = np.clip(np.floor((p[:, 1] - y0) / ly).astype(int), 0, self.n - 1)
        return i + j * self.m

    def ij(self, k) -> tuple[np.ndarray, np.ndarray]:
        """Column and row ``(i, j)`` of cells `k` (eqs. (3)–(4), 0-based)."""
        k = np.asarray(k)
        return k % self.m, k // self.m

    def from_paper(self, number: int) -> int:
        """Our index of the paper's cell ``C_number``: the paper counts from 1 and its
        rows from the top of the region (its C_64 lies at the top edge, C_488 holds
        the source at (20, 0))."""
        i, row = (int(number) - 1) % self.m, (int(number) - 1) // self.m
        return i + (self.n - 1 - row) * self.m

    def to_paper(self, k: int) -> int:
        """The paper's number of our cell `k` (inverse of :meth:`from_paper`)."""
        i, j = int(k) % self.m, int(k) // self.m
        return i + (self.n - 1 - j) * self.m + 1

    def neighbours(self) -> np.ndarray:
        """The neighbours function of Appendix I: for each cell its inclusive 3 × 3
        neighbourhood, shape (N, 9), ``-1`` where the neighbour is outside (C0)."""
        i, j = self.ij(np.arange(self.N))
        out = np.full((self.N, 9), -1, dtype=np.int64)
        for o, (di, dj) in enumerate((a, b) for b in (-1, 0, 1) for a in (-1, 0, 1)):
            ok = (i + di >= 0) & (i + di < self.m) & (j + dj >= 0) & (j + dj < self.n)
            out[ok, o] = (i + di + (j + dj) * self.m)[ok]
        return out


#: Probabilities below this are set to zero (they would become subnormal numbers).
TINY = 1e-150


def row_combination(weights: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """``Σ_i weights_i rows[i, :]`` (a row vector times a matrix, e.g. α = π Ψ of
    eq. (12)), single-threaded and skipping zero weights (compiled with numba on first
    use)."""
    from ._hmm_kernels import row_combination as compiled
    return compiled(weights, rows)


@dataclass(frozen=True)
class Transition:
    """Ā(t) for a uniform flow (Appendix II), applied `substeps` times.

    Odour in a cell stays along x with probability ``1 - ex`` or moves one cell by `sx`
    (±1) with probability `ex`; independently along y with `ey`, `sy`.

    Attributes
    ----------
    grid : CellGrid
    ex, ey : float
        ``|u_x| dt / L_x`` and ``|u_y| dt / L_y`` per sub-step, in [0, 1).
    sx, sy : int
        Downflow directions, ±1.
    substeps : int
        Ā is the product of this many identical sub-step matrices (so that each moves
        odour less than one cell, the assumption of Appendix II).
    """

    grid: CellGrid
    ex: float
    ey: float
    sx: int = 1
    sy: int = 1
    substeps: int = 1

    @property
    def weights(self) -> tuple:
        """The sub-step's moves ``((di, dj), probability)``; they sum to 1."""
        return tuple(((di, dj), wx * wy)
                     for di, wx in ((0, 1 - self.ex), (self.sx, self.ex))
                     for dj, wy in ((0, 1 - self.ey), (self.sy, self.ey)))

    def _apply(self, x: np.ndarray, sign: int, scale: float = 1.0, out: np.ndarray | None = None
               ) -> np.ndarray:
        from ._hmm_kernels import stencil
        g = self.grid
        y = np.ascontiguousarray(x, dtype=float).reshape(-1, g.n, g.m)
        res = np.empty_like(y) if out is None else out.reshape(y.shape)
        ex, ey = self.ex, self.ey
        w = ((1 - ex) * (1 - ey), ex * (1 - ey), (1 - ex) * ey, ex * ey)
        for k in range(self.substeps):
            if k:
                y = res.copy()
            stencil(y, sign * self.sx, sign * self.sy, *w, scale if k == self.substeps - 1 else 1.0, TINY, res)
        return res.reshape(np.shape(x))

    def superpose(self, psi: np.ndarray, n: int, out: np.ndarray) -> np.ndarray:
        """One step of the superposition recursion, eq. (13):
        ``Ψ(t_n) = (n Ψ(t_{n-1}) Ā(t_{n-1}) + I) / (n + 1)``, written into `out`
        (N × N, distinct from `psi`)."""
        self._apply(psi, 1, n / (n + 1), out)
        out.flat[::out.shape[0] + 1] += 1.0 / (n + 1)
        return out

    def right(self, x: np.ndarray) -> np.ndarray:
        """``x Ā`` for row vectors or matrices `x` (..., N): where the odour of `x` is
        one period later (eqs. (8), (11), (13))."""
        return self._apply(x, 1)

    def left(self, b: np.ndarray) -> np.ndarray:
        """``Ā b`` for a column vector `b` (N,): the probability that odour in each cell
        now reaches where `b` says (eq. (14))."""
        return self._apply(b, -1)

    def matrix(self, pi: np.ndarray | None = None) -> sparse.csr_matrix:
        """The full ``(N + 1) × (N + 1)`` matrix A (eq. (5)), C0 last. Row C0 is `pi`
        (``a_0j = π_j``, odour newly released by the source) when given, else C0 is
        absorbing; every row sums to 1."""
        g = self.grid
        N = g.N
        i, j = g.ij(np.arange(N))
        rows, cols, vals = [np.array([N])], [np.array([N])], [np.array([1.0])]
        for (di, dj), w in self.weights:
            ii, jj = i + di, j + dj
            inside = (ii >= 0) & (ii < g.m) & (jj >= 0) & (jj < g.n)
            rows.append(np.arange(N))
            cols.append(np.where(inside, ii + jj * g.m, N))
            vals.append(np.full(N, w))
        one = sparse.coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                                shape=(N + 1, N + 1)).tocsr()
        one.eliminate_zeros()
        a = one
        for _ in range(self.substeps - 1):
            a = a @ one
        if pi is not None:
            a = a.tolil()
            a[N, :] = 0.0
            a[N, :N] = np.asarray(pi, dtype=float)
            a = a.tocsr()
        return a

    def bar(self) -> sparse.csr_matrix:
        """Ā: A without the exterior row and column, N × N."""
        N = self.grid.N
        return self.matrix()[:N, :N]


def transition(grid: CellGrid, u, dt: float) -> Transition:
    """Ā(t) from the flow `u` = (u_x, u_y) (m/s) averaged over a period `dt` (s)
    (Appendix II, all eight sign cases): odour stays with probability ``1 - ε`` and
    moves one cell downflow with probability ``ε = |u| dt / L`` along each axis,
    independently. A flow that would carry odour a cell or more in `dt` is split into
    sub-steps."""
    lx, ly = grid.L
    ex, ey = abs(u[0]) * dt / lx, abs(u[1]) * dt / ly
    s = max(1, int(np.ceil(max(ex, ey) / 0.95)))
    return Transition(grid, ex / s, ey / s, 1 if u[0] >= 0 else -1, 1 if u[1] >= 0 else -1, s)


# -- Viterbi -----------------------------------------------------------------------------
def _max_product(a: sparse.csr_matrix, log_v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For each row m of `a`: ``max_n log a_mn + log_v_n`` and its first arg max
    (``-1`` where the row has no finite term)."""
    a = a.tocsr()
    N = a.shape[0]
    row = np.repeat(np.arange(N), np.diff(a.indptr))
    with np.errstate(divide="ignore"):
        val = np.log(a.data) + log_v[a.indices]
    best = np.full(N, -np.inf)
    np.maximum.at(best, row, val)
    arg = np.full(N, -1, dtype=np.int64)
    hit = np.isfinite(val) & (val == best[row])
    arg[row[hit][::-1]] = a.indices[hit][::-1]          # the first maximiser wins
    return best, arg


def viterbi(pi: np.ndarray, mats: list) -> tuple[np.ndarray, np.ndarray]:
    """Forward Viterbi recursion of Table III, in logarithms.

    Parameters
    ----------
    pi : ndarray (N,)
        ``δ(t_0)``.
    mats : list of scipy.sparse matrices
        Ā(t_0), ..., Ā(t_{L-1}) (N × N).

    Returns
    -------
    log_delta : ndarray (L + 1, N)
        ``log δ_j(t_k)``: log-probability of the most likely cell sequence to ``C_j(t_k)``.
    psi : ndarray (L, N)
        ``ψ_j(t_k)``, k = 1..L: the most likely cell at ``t_{k-1}`` before ``C_j(t_k)``.
    """
    with np.errstate(divide="ignore"):
        d = np.log(np.asarray(pi, dtype=float))
    out, psi = [d], []
    for a in mats:
        d, arg = _max_product(a.T.tocsr(), d)
        out.append(d)
        psi.append(arg)
    return np.array(out), np.array(psi, dtype=np.int64).reshape(len(mats), -1)


def backtrack(psi: np.ndarray, j: int) -> np.ndarray:
    """The cell sequence ``q*`` from ``t_0`` to ``C_j(t_L)`` (Table III, termination)."""
    q = [int(j)]
    for t in range(len(psi) - 1, -1, -1):
        q.append(int(psi[t][q[-1]]))
    return np.array(q[::-1])


def viterbi_backward(j: int, mats: list) -> tuple[np.ndarray, np.ndarray]:
    """Backward Viterbi of eq. (17): ``μ_m(t_k) = max_n a_mn μ_n(t_{k+1})`` from
    ``μ(t_f) = Δ(j)``, in logarithms.

    Parameters
    ----------
    j : int
        The final cell ``C_j(t_f)``.
    mats : list of scipy.sparse matrices
        Ā(t_s), ..., Ā(t_{f-1}).

    Returns
    -------
    log_mu : ndarray (L + 1, N)
        ``log μ_m(t_k)``, k = 0 (t_s) .. L (t_f): log-probability of the most likely
        cell sequence from ``C_m(t_k)`` to ``C_j(t_f)``.
    nxt : ndarray (L, N)
        ``ψ_m(t_k)``: the most likely next cell after ``C_m(t_k)``.
    """
    N = mats[0].shape[0]
    mu = np.full(N, -np.inf)
    mu[j] = 0.0
    out, nxt = [mu], []
    for a in reversed(mats):
        mu, arg = _max_product(a, mu)
        out.append(mu)
        nxt.append(arg)
    return np.array(out[::-1]), np.array(nxt[::-1], dtype=np.int64).reshape(len(mats), -1)


def forward_path(nxt: np.ndarray, i: int, k: int) -> np.ndarray:
    """The cells from ``C_i(t_k)`` to the end, following ``ψ`` of :func:`viterbi_backward`."""
    q = [int(i)]
    for t in range(k, len(nxt)):
        q.append(int(nxt[t][q[-1]]))
    return np.array(q)


def detection_path(alpha: np.ndarray, neighbours: np.ndarray, j: int, steps: int
                   ) -> tuple[np.ndarray, np.ndarray]:
    """The most likely detection path (Sect. IV-C3) in logarithms: ``μ_m(k+1) =
    α_m max_{n ∈ Ne(m)} μ_n(k)`` from ``μ(0) = Δ(j) α_j``.

    Parameters
    ----------
    alpha : ndarray (N,)
        The plume map α (probability of detectable odour per cell).
    neighbours : ndarray (N, 9)
        :meth:`CellGrid.neighbours` (inclusive, ``-1`` outside).
    j : int
        Start cell.
    steps : int
        Path length s (cells after the start).

    Returns
    -------
    log_mu : ndarray (steps + 1, N)
        ``log μ_m(k)``: the best k-step path from ``C_j`` to ``C_m``.
    prev : ndarray (steps, N)
        ``ψ_m(k)``: the previous cell on that path.
    """
    with np.errstate(divide="ignore"):
        la = np.log(np.maximum(np.asarray(alpha, dtype=float), 0.0))
    mu = np.full(len(la), -np.inf)
    mu[j] = la[j]
    out, prev = [mu], []
    valid = neighbours >= 0
    nb = np.maximum(neighbours, 0)
    for _ in range(steps):
        cand = np.where(valid, mu[nb], -np.inf)
        best = np.argmax(cand, axis=1)
        prev.append(nb[np.arange(len(nb)), best])
        mu = la + cand[np.arange(len(nb)), best]
        out.append(mu)
    return np.array(out), np.array(prev, dtype=np.int64).reshape(steps, -1)
