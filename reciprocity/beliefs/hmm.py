"""The hidden-Markov source likelihood map of Farrell, Pang & Li (2003), as a Belief.

The map is updated once per mapping period from the M sensor readings taken in it: the
mean measured flow (eqs. (1)–(2)) gives Ā(t) (:mod:`reciprocity.models.hmm`), which
advances the superposition matrix Ψ (eq. (13)); the peak detection over the period
(detected or not) in the vehicle's cell C_k updates the source likelihood map π̂ with
the column β̄_k = Ψ e_k (eq. (16) and the SLIM update of Sect. IV-B1). The plume map is
α = π̂ Ψ (eq. (12)). The most likely odour path (MLOP, Viterbi over the stored flow,
Table III / eq. (17)) and the most likely detection path (MLDP, Sect. IV-C3) are
available at any time, and so is the intersection estimate of the paper's conclusion.
"""

from __future__ import annotations

import numpy as np

from ..errors import SearchError
from ..models.hmm import (TINY, CellGrid, Transition, detection_path, forward_path, row_combination,
                          transition, viterbi_backward)
from ..observations import Observation
from .base import Belief

__all__ = ["HMMSourceMap", "plume_map"]


def plume_map(pi: np.ndarray, transitions: list[Transition]) -> np.ndarray:
    """The plume likelihood map α(t_n, t_0) for a fixed source vector `pi` by the
    forward recursion of Table I / eq. (11):
    ``α(t_n) = (π + n α(t_{n-1}) Ā(t_{n-1})) / (n + 1)``."""
    a = np.asarray(pi, dtype=float).copy()
    for n, t in enumerate(transitions, start=1):
        a = (pi + n * t.right(a)) / (n + 1)
    return a


class HMMSourceMap(Belief):
    """Source likelihood map π̂ over the cells of a rectangle, with Ψ, α, β̄, MLOP, MLDP.

    Parameters
    ----------
    grid : CellGrid
        The cells (the paper's 40 × 25 over 100 m × 100 m).
    period : float
        Mapping period, s (the paper's 1 s).
    readings : int
        Sensor readings per period, M.
    eps_d, eps_c : float
        Gains of the SLIM update on a detection and on a non-detection, in (0, 1).
    mu : float
        Detection probability when the cell holds detectable odour (the vector b).
    radius : float
        Radius of the estimate's neighbourhood around the map's peak, m.
    """

    def __init__(self, grid: CellGrid, *, period: float = 1.0, readings: int = 10, eps_d: float = 0.1,
                 eps_c: float = 0.01, mu: float = 0.5, radius: float = 5.0):
        for name, v in (("eps_d", eps_d), ("eps_c", eps_c), ("mu", mu)):
            if not 0 < v < 1:
                raise SearchError(f"{name} must lie in (0, 1); got {v!r}")
        if not period > 0 or int(readings) < 1:
            raise SearchError(f"the mapping period must be positive and hold at least one reading; "
                              f"got period={period!r}, readings={readings!r}")
        self.grid, self.period, self.M = grid, float(period), int(readings)
        self.eps_d, self.eps_c, self.mu, self.radius = float(eps_d), float(eps_c), float(mu), float(radius)
        N = grid.N
        self.centres = grid.centres()
        self._neighbours = grid.neighbours()
        self.pi = np.full(N, 1.0 / N)                      # uniform prior (Sect. III-B)
        self.psi = np.eye(N)                               # Ψ(t_0, t_0) = I
        self._buf = np.empty_like(self.psi)
        self.n = 0                                         # map updates so far
        self.transitions: list[Transition] = []            # Ā(t_0) ... Ā(t_{n-1})
        self.events: list[tuple[int, int, bool]] = []      # (n, cell, detected)
        self._winds: list = []
        self._detected = False
        self._alpha = None
        self.flow = np.zeros(2)                            # the last period's mean flow, m/s

    # -- updates -------------------------------------------------------------------------
    def update(self, obs: Observation) -> None:
        """Take one detector reading (value 0/1, ``data["wind"]``); every M readings the
        map advances one period."""
        if obs.data is None or "wind" not in obs.data:
            raise SearchError("the hidden-Markov map needs the local wind with every reading (data['wind'])")
        self._winds.append(obs.data["wind"])
        self._detected |= bool(obs.value > 0)
        self._position = obs.position
        if len(self._winds) >= self.M:
            u = np.mean(np.asarray(self._winds, dtype=float), axis=0)    # eqs. (1)-(2)
            self.advance(u, self._detected, self._position)
            self._winds, self._detected = [], False

    def advance(self, u, detected: bool, position) -> None:
        """One mapping period: Ψ by eq. (13) with Ā from the mean flow `u` (m/s), then the
        SLIM update from a detection or non-detection at `position`."""
        self.flow = np.asarray(u, dtype=float)
        t = transition(self.grid, self.flow, self.period)
        self.n += 1
        t.superpose(self.psi, self.n, self._buf)
        self.psi, self._buf = self._buf, self.psi
        self.transitions.append(t)
        k = int(self.grid.index(position)[0])
        b = self.beta(k)
        if detected:
            self.pi = (1 - self.eps_d) * self.pi + self.eps_d * b
        else:
            self.pi = (1 + self.eps_c) * self.pi - self.eps_c * b
            self.pi[self.pi < TINY] = 0.0
            s = self.pi.sum()
            self.pi = self.pi / s if s > 0 else np.full_like(self.pi, 1.0 / len(self.pi))
        self.events.append((self.n, k, bool(detected)))
        self._alpha = None

    # -- maps ------------------------------------------------------------------------------
    def beta(self, k: int) -> np.ndarray:
        """β̄_k(t_n, t_0) = Ψ e_k (eq. (16)), normalised to sum 1: which cells are likely
        to have released odour detectable now in C_k."""
        b = self.psi[:, k].copy()
        s = b.sum()
        return b / s if s > 0 else b

    def alpha(self) -> np.ndarray:
        """The plume map α(t_n, t_0) = π̂ Ψ (eq. (12)): probability that each cell holds
        detectable odour now, for the current source map."""
        if self._alpha is None:
            self._alpha = row_combination(self.pi, self.psi)
        return self._alpha

    def detection_probability(self) -> np.ndarray:
        """``b_k α_k = μ α_k`` (eq. (6)): probability of a detection in each cell now."""
        return self.mu * self.alpha()

    def support(self) -> np.ndarray:
        return self.centres

    def weights(self) -> np.ndarray:
        return self.pi / self.pi.sum()

    def estimate(self) -> np.ndarray:
        """The π̂-weighted mean of the cells within `radius` of the map's peak."""
        near = self.near(self.centres[int(np.argmax(self.pi))])
        w = self.pi * near
        return w @ self.centres / w.sum()

    def near(self, point) -> np.ndarray:
        """Mask of cells whose centre is within `radius` of `point`."""
        return np.hypot(*(self.centres - np.asarray(point, dtype=float)).T) <= self.radius

    def mass_near_peak(self) -> float:
        """Map mass within `radius` of the map's peak."""
        return float(self.weights()[self.near(self.centres[int(np.argmax(self.pi))])].sum())

    # -- paths -----------------------------------------------------------------------------
    def mlop(self, j: int, horizon: int | None = None) -> tuple[np.ndarray, int]:
        """The most likely odour path to ``C_j`` now (eq. (17), backward Viterbi over the
        last `horizon` periods), from the start cell and time maximising
        ``π̂_m μ_m(t_k)``. Returns the cells (time order) and the index of the start
        period."""
        ts = self.transitions[-horizon:] if horizon else self.transitions
        if not ts:
            return np.array([j]), self.n
        log_mu, nxt = viterbi_backward(j, [t.bar() for t in ts])
        with np.errstate(divide="ignore"):
            score = np.log(self.pi)[None, :] + log_mu
        k, m = np.unravel_index(int(np.argmax(score)), score.shape)
        return forward_path(nxt, int(m), int(k)), self.n - len(ts) + int(k)

    def mldp(self, j: int, steps: int, end: int | None = None) -> np.ndarray:
        """The `steps`-step most likely detection path from ``C_j`` (Sect. IV-C3) on the
        current α, to `end` (default: the best end cell). Cells in path order."""
        log_mu, prev = detection_path(self.alpha(), self._neighbours, j, steps)
        q = [int(np.argmax(log_mu[-1])) if end is None else int(end)]
        for s in range(steps - 1, -1, -1):
            q.append(int(prev[s][q[-1]]))
        return np.array(q[::-1])

    def intersection(self, j: int, *, tau: float = 0.5, steps: int = 25) -> dict:
        """The conclusion's two source estimates from a detection in ``C_j``:
        the cells where ``c_k = α_k β̄_jk`` exceeds `tau` × its maximum (idea 2), and
        the cells shared by the MLOP to ``C_j`` and the MLDP from ``C_j`` (idea 1).

        Returns
        -------
        dict
            ``cells`` (idea 2), ``estimate`` (their c-weighted centre, m),
            ``crossing`` (idea 1 cells, possibly empty).
        """
        c = self.alpha() * self.beta(j)
        cells = np.flatnonzero(c >= tau * c.max()) if c.max() > 0 else np.array([j])
        w = c[cells] if c.max() > 0 else np.ones(1)
        odour, _ = self.mlop(j)
        crossing = np.intersect1d(odour, self.mldp(j, steps))
        return dict(cells=cells, estimate=w @ self.centres[cells] / w.sum(), crossing=crossing)
