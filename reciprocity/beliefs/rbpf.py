"""The Rao-Blackwellised particle filter of Ristic, Skvortsov & Walker (2014), Sec. 4.

Each particle carries a source position (continuous) and a searcher node (the sampled
part β of eq. (15)), and, analytically, the probability of existence of every link
(``q``, eqs. (19)–(23)) and the Gamma(η, θ) posterior of the release rate A
(eqs. (24)–(30)). Counts are weighed with the map-independent log model of eq. (25).

All particles see the same counts, so the shape η is one number; θ, q, the source and
the searcher node are per particle. Arrays: ``source`` (N, 2), ``node`` (N,), ``theta``
(N,), ``q`` (N, L) float32.

A reading that carries a position fix (``data["fix"]``: the lattice world's oracle
``localisation: known``) is a perfect position sensor: particles whose node differs lose
their weight (their slips or map were wrong), then every particle stands on the fix.
"""

from __future__ import annotations

import numpy as np
from scipy.special import logsumexp

from ..errors import SearchError
from ..models.lattice import MIN_DISTANCE, log_evidence, log_gain
from ..observations import Observation
from ..spaces.lattice import LatticeSpace
from .base import Belief, shannon_entropy

__all__ = ["RBPFBelief", "systematic_resample", "LOG_FLOOR"]

#: Smallest probability in a log-likelihood (a perfect detector's impossible reading).
LOG_FLOOR = 1e-12


def systematic_resample(w: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """Indices drawn by systematic resampling from normalised weights `w`."""
    n = len(w)
    c = np.cumsum(w)
    c[-1] = 1.0
    return np.searchsorted(c, (rng.random() + np.arange(n)) / n)


class RBPFBelief(Belief):
    """Particles over (source, searcher node) with per-particle map and rate statistics.

    Parameters
    ----------
    space : LatticeSpace
        The *complete* lattice (the searcher's prior knowledge, Sec. 3).
    start : array_like, shape (2,)
        The searcher's known initial node p0.
    rng : numpy.random.Generator
    n_particles : int
        N.
    eta0, theta0 : float
        Gamma prior of A (η0 = 15, θ0 = 1 in the paper).
    q0 : float
        Prior probability that a link exists (0.5).
    persistence : float
        ``p(m_k = m_{k−1})`` of the map dynamics, eq. (21) (0.999).
    slip : float
        p_e of the motion model, eq. (45).
    primary, secondary : (float, float)
        ``(p_d, p_fa)`` of the link detector, eq. (8).
    regularise : bool
        Jitter the source positions after resampling (Sec. 4.4) with the Gaussian
        kernel of optimal width for N particles in 2-D.
    min_distance : float
        Floor of the searcher–source distance in eq. (25).
    links : array_like of bool, shape (L,), optional
        The map when it is known (an oracle rung below the paper): every particle holds
        it with certainty and keeps it (no map dynamics).
    gain : callable, optional
        ``gain(nodes, sources) -> c``: the mean count per unit release rate at searcher
        `nodes` for `sources` (one per particle), in place of eq. (25), e.g. the lattice's
        own field (:class:`reciprocity.models.lattice.LatticeGreen`) on a known map.
    """

    def __init__(self, space: LatticeSpace, start, rng: np.random.Generator, *, n_particles: int = 4000,
                 eta0: float = 15.0, theta0: float = 1.0, q0: float = 0.5, persistence: float = 0.999,
                 slip: float = 0.04, primary=(1.0, 0.0), secondary=(0.8, 0.1), regularise: bool = True,
                 min_distance: float = MIN_DISTANCE, links=None, gain=None):
        self.space, self.rng = space, rng
        self.radius = space.radius
        n = int(n_particles)
        self.n = n
        r = self.radius * np.sqrt(rng.random(n))                          # uniform in the disk
        a = rng.uniform(0, 2 * np.pi, n)
        self.source = np.column_stack([r * np.cos(a), r * np.sin(a)])
        self.node = np.full(n, int(space.index_of(start)[0]), dtype=np.int64)
        self.q = np.full((n, len(space.links)), q0, dtype=np.float32)
        if links is not None:
            self.q[:] = np.asarray(links, dtype=np.float32)[None, :]
            persistence = 1.0
        self.gain = gain
        self.eta = float(eta0)
        self.theta = np.full(n, float(theta0))
        self.w = np.full(n, 1.0 / n)
        self.persistence, self.slip = float(persistence), float(slip)
        self.primary, self.secondary = tuple(primary), tuple(secondary)
        self.regularise, self.min_distance = bool(regularise), float(min_distance)
        self._second = space.second_link_of
        self.ess = float(n)
        self.log_evidence = 0.0

    # -- the Belief protocol ----------------------------------------------------------
    def support(self) -> np.ndarray:
        return self.source

    def weights(self) -> np.ndarray:
        return self.w

    def node_weights(self) -> np.ndarray:
        """Posterior probability of the searcher being at each node, shape (n_nodes,)."""
        return np.bincount(self.node, weights=self.w, minlength=len(self.space.points))

    def position(self) -> np.ndarray:
        """Most probable searcher node (lattice units)."""
        return self.space.points[int(np.argmax(self.node_weights()))]

    def link_probability(self) -> np.ndarray:
        """Posterior probability that each link exists, shape (L,)."""
        return self.w.astype(np.float32) @ self.q

    def rate(self) -> float:
        """Posterior mean of the release rate A (η θ averaged)."""
        return float(self.eta * (self.w @ self.theta))

    def c(self, nodes: np.ndarray | None = None) -> np.ndarray:
        """c of eq. (25) for every particle at `nodes` (default: its own node)."""
        if self.gain is not None:
            return self.gain(self.node if nodes is None else nodes, self.source)
        at = self.space.points[self.node if nodes is None else nodes]
        return log_gain(at, self.source, self.radius, min_distance=self.min_distance)

    # -- prediction: eqs. (21) and (45) -----------------------------------------------
    def predict(self, control: int) -> None:
        """Move every particle's searcher by `control` (0 stay, 1..4 E, W, N, S): carried out
        with probability 1 − p_e, else one of the other four (eq. (45)); a move along a
        link the particle draws as missing (Bernoulli(q)) or off the lattice stays.
        Then the map prediction of eq. (21)."""
        n, rng = self.n, self.rng
        ctrl = np.full(n, int(control))
        fail = rng.random(n) < self.slip
        other = rng.integers(0, 4, fail.sum())
        other = other + (other >= control)                  # uniform over the four others
        ctrl[fail] = other
        moving = ctrl > 0
        d = ctrl[moving] - 1
        nodes = self.node[moving]
        lid = self.space.link_of[nodes, d]
        ok = lid >= 0
        exists = np.zeros(len(nodes), dtype=bool)
        rows = np.flatnonzero(moving)
        exists[ok] = rng.random(ok.sum()) < self.q[rows[ok], lid[ok]]
        self.node[rows[exists]] = self.space.step_of[nodes[exists], d[exists]]
        p = self.persistence
        self.q *= np.float32(2 * p - 1)                      # eq. (21)
        self.q += np.float32(1 - p)

    # -- update: eqs. (22), (29), (30), (34), (38) ------------------------------------
    def _links(self, z1, z2):
        """(rows, link ids or -1, readings, p_d, p_fa) of the link readings per particle."""
        rows, lids, zs, pds, pfas = [], [], [], [], []
        ar = np.arange(self.n)
        for table, z, (pd, pfa) in ((self.space.link_of, z1, self.primary), (self._second, z2, self.secondary)):
            for d in range(4):
                if z[d] < 0:
                    continue
                rows.append(ar)
                lids.append(table[self.node, d])
                zs.append(np.full(self.n, z[d]))
                pds.append(np.full(self.n, pd))
                pfas.append(np.full(self.n, pfa))
        if not rows:
            e = np.zeros(0)
            return e.astype(int), e.astype(int), e, e, e
        return (np.concatenate(rows), np.concatenate(lids), np.concatenate(zs), np.concatenate(pds),
                np.concatenate(pfas))

    def update(self, obs: Observation) -> None:
        """Weigh, update the sufficient statistics, resample (Algorithm 1, lines 7–18)."""
        count = float(obs.value)
        data = obs.data or {}
        fix_logw = 0.0
        if data.get("fix") is not None:       # a perfect position sensor (an oracle)
            fix = int(self.space.index_of(np.asarray(data["fix"], dtype=float))[0])
            if fix < 0:
                raise SearchError(f"a position fix must be a lattice node; got {data['fix']!r}")
            # its likelihood is 1 where a particle's node is the fix, 0 elsewhere: particles whose
            # slips or map put them elsewhere lose their weight, then all stand on the fix
            fix_logw = np.where(self.node == fix, 0.0, np.log(LOG_FLOOR))
            self.node[:] = fix
        z1 = np.asarray(data.get("primary", [-1] * 4), dtype=int)
        z2 = np.asarray(data.get("secondary", [-1] * 4), dtype=int)
        c = self.c()
        logw = log_evidence(count, self.eta, self.theta, c) + fix_logw         # eq. (38)
        rows, lid, z, pd, pfa = self._links(z1, z2)
        if rows.size:
            has = lid >= 0
            qv = np.where(has, self.q[rows, np.maximum(lid, 0)], 0.0).astype(float)
            p1 = np.where(z == 1, pd, 1 - pd) * qv                             # z | m = 1
            p0 = np.where(z == 1, pfa, 1 - pfa) * (1 - qv)                     # z | m = 0
            lik = p1 + p0
            logw += np.bincount(rows, weights=np.log(np.maximum(lik, LOG_FLOOR)), minlength=self.n)
            post = p1 / np.maximum(lik, LOG_FLOOR)                             # eq. (22)
            self.q[rows[has], lid[has]] = post[has]
        self.theta = self.theta / (1.0 + c * self.theta)                       # eq. (30)
        self.eta += count                                                      # eq. (29)
        logw += np.log(self.w)
        total = logsumexp(logw)
        self.log_evidence += float(total)
        w = np.exp(logw - total)
        self.ess = float(1.0 / np.sum(w ** 2))
        self._resample(w)

    def _resample(self, w: np.ndarray) -> None:
        idx = systematic_resample(w, self.rng)
        self.source, self.node = self.source[idx], self.node[idx]
        self.theta, self.q = self.theta[idx], self.q[idx]
        self.w = np.full(self.n, 1.0 / self.n)
        if self.regularise:
            self._jitter()

    def _jitter(self) -> None:
        """Regularisation of the source positions: Gaussian kernel, width
        ``h = (4 / (N (d + 2)))^{1/(d+4)}`` times the particles' covariance (d = 2);
        a jittered position outside the disk keeps its old value."""
        cov = np.cov(self.source.T)
        try:
            chol = np.linalg.cholesky(cov + 1e-9 * np.eye(2))
        except np.linalg.LinAlgError:
            return
        h = (4.0 / (self.n * 4.0)) ** (1.0 / 6.0)
        new = self.source + h * self.rng.standard_normal((self.n, 2)) @ chol.T
        ok = np.sum(new ** 2, axis=1) < self.radius ** 2
        self.source[ok] = new[ok]

    def entropy(self) -> float:
        """Shannon entropy (nats) of the source positions binned on the lattice nodes."""
        idx = self.space.index_of(np.rint(self.source))
        return shannon_entropy(np.bincount(idx[idx >= 0], weights=self.w[idx >= 0]))
