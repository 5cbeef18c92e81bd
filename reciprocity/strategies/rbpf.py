"""Search in an unknown lattice with a Rao-Blackwellised particle filter (Ristic et al. 2014).

``rbpf`` is the paper's searcher: the filter of :class:`reciprocity.beliefs.rbpf.RBPFBelief`
and a one-step motion control that maximises the expected Bhattacharyya information
gain of eq. (13), estimated with M ideal measurements (Sec. 4.3, Algorithm 2).
``rbpf-infotaxis`` is the same filter with the expected drop of the Shannon entropy of
the particle weights instead.
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import coo_matrix
from scipy.special import logsumexp

from ..beliefs.base import MIN_PARTICLES
from ..beliefs.rbpf import RBPFBelief
from ..errors import SearchError
from ..intents import Move, Stay
from ..spaces.lattice import CONTROLS
from ..models.lattice import MIN_DISTANCE, log_bhattacharyya, log_evidence
from . import register
from .base import SearchContext, Status, Strategy

__all__ = ["RBPFStrategy", "RBPFInfotaxisStrategy", "MIN_PARTICLES"]



def _lattice_gain(space, links):
    """The lattice's own field on the map `links` as the RBPF's gain: ``c = F[x, z]`` for a
    source particle at (the node nearest) x and the searcher at node z (one sparse solve per
    searcher node, cached); a particle off every candidate node gets a tiny gain."""
    from ..models.lattice import LatticeGreen
    green = LatticeGreen(space.with_links(links))

    def gain(nodes, sources):
        nodes = np.asarray(nodes, dtype=np.int64)
        src = space.index_of(np.rint(sources))
        uniq, inv = np.unique(nodes, return_inverse=True)
        cols = green.visits(uniq)                                # (n_nodes, k)
        if nodes.ndim == 0:
            return np.where(src >= 0, cols[np.maximum(src, 0), 0], 0.0) + 1e-9
        if nodes.shape == src.shape:
            c = cols[np.maximum(src, 0), inv.reshape(nodes.shape)]
        else:                                                    # one node for every particle
            c = cols[np.maximum(src, 0), inv[0]]
        return np.where(src >= 0, c, 0.0) + 1e-9
    return gain


@register
class RBPFStrategy(Strategy):
    """The searcher of Ristic, Skvortsov & Walker (2014): RBPF + Bhattacharyya gain.

    Each step: choose the control of largest expected gain among "stay" and the moves
    along links not believed missing (posterior probability >= 1/2 from the particles'
    searcher nodes); if the believed node was visited more than `loop_visits` times in the last
    `loop_window` steps, a random admissible control instead (Sec. 4.4); then predict,
    weigh and resample (Algorithm 1). The search ends when the searcher reaches the source
    (the world says so) or at the scenario's step cap.

    Parameters
    ----------
    n_particles : int
        N (4000 in the paper).
    n_gain : int
        M, ideal measurements per control (400).
    eta0, theta0 : float
        Gamma prior of the release rate (15, 1).
    q0 : float
        Prior probability of a link (0.5).
    persistence : float
        Map dynamics of eq. (21) (0.999).
    ideal : {"mean", "sample"}
        Rate of an ideal measurement: the Gamma mean ``η θ`` (Algorithm 2, line 8), or a
        draw from ``G(η, θ)`` (the text of Sec. 4.3).
    regularise : bool
        Jitter source particles after resampling (Sec. 4.4).
    min_distance : float
        Floor of the distance in eq. (25) (the paper does not say how the singularity at
        the source is treated).
    loop_window, loop_visits : int
        The anti-oscillation rule of Sec. 4.4 (10 steps, more than 3 visits).
    stay : bool
        "Stay" is one of the controls (the paper's U_k); False: only when no move is admissible.
    planner : {"gain", "path"}
        ``"gain"`` (default, the paper): the control of largest expected gain.
        ``"path"`` (beyond the paper, a longer horizon): the admissible control that
        minimises the expected shortest-path distance over the believed map to the source
        particles (ties: the larger gain). No better than ``"gain"``
        (``benchmarks/lattice_beyond.md``).
    controls : {"believed", "all"}
        The controls scored each step: ``"believed"`` (default) stay and the moves along
        links not believed missing (posterior >= 1/2); ``"all"``: the five controls of
        Algorithm 2, line 2, every step (the paper's text).
    map : {"unknown", "known"}
        ``"unknown"`` (the paper): the map is estimated. ``"known"`` (an oracle for the
        ladder of ``docs/papers/ristic2014.md``): the scenario's map
        (``map: known``), held with certainty.
    field : {"conformal", "lattice"}
        The count model: eq. (25) (the paper), or the lattice's own field on the known map
        (an oracle; needs ``map="known"``).

    Notes
    -----
    Deviations from the paper (what each changes is measured in
    ``benchmarks/lattice_beyond.md``):

    * eq. (44) is integrated in closed form (the paper integrates numerically);
    * c of eq. (25) is held at its value at distance `min_distance` (0.5) closer to a
      source (the paper does not say how it treats the singularity);
    * a particle's failed or commanded move along a link it draws as missing
      (Bernoulli(q)) leaves it in place, as the true searcher does (eq. (45) is silent);
    * moves along links of probability exactly 1/2 are admissible, so the first move
      (before any link was seen) is allowed; "stay" remains a control;
    * by default only stay and the moves along links not believed missing are scored
      (``controls="believed"``); Algorithm 2's text scores all five every step
      (``controls="all"``), which on the paper's lattice loses most runs.
    """

    name = "rbpf"
    worlds = ("lattice",)
    agents = 1
    gain_kind = "bhattacharyya"

    def __init__(self, *, n_particles: int = 4000, n_gain: int = 400, eta0: float = 15.0, theta0: float = 1.0,
                 q0: float = 0.5, persistence: float = 0.999, ideal: str = "mean", regularise: bool = True,
                 min_distance: float = MIN_DISTANCE, loop_window: int = 10, loop_visits: int = 3,
                 stay: bool = True, planner: str = "gain", map: str = "unknown", field: str = "conformal",
                 controls: str = "believed"):
        super().__init__()
        if controls not in ("believed", "all"):
            raise SearchError(f"controls must be 'believed' (moves along links not believed missing) or 'all' "
                              f"(the five controls of Algorithm 2, line 2); got {controls!r}")
        self.controls = controls
        if map not in ("unknown", "known"):
            raise SearchError(f"map must be 'unknown' (the paper) or 'known' (an oracle: the scenario must say "
                              f"map: known); got {map!r}")
        if field not in ("conformal", "lattice"):
            raise SearchError(f"field must be 'conformal' (the paper's eq. (25)) or 'lattice' (the lattice's own "
                              f"field on the known map, an oracle); got {field!r}")
        if field == "lattice" and map != "known":
            raise SearchError("field='lattice' needs map='known' (the lattice's field is that of its map)")
        self.map, self.field = map, field
        if planner not in ("gain", "path"):
            raise SearchError(f"planner must be 'gain' (the paper's one-step gain) or 'path' (shortest paths "
                              f"over the believed map toward the source particles); got {planner!r}")
        self.planner = planner
        if isinstance(n_particles, bool) or not isinstance(n_particles, (int, np.integer)) or n_particles < MIN_PARTICLES:
            raise SearchError(f"n_particles must be a whole number >= {MIN_PARTICLES}; got {n_particles!r}")
        if isinstance(n_gain, bool) or not isinstance(n_gain, (int, np.integer)) or n_gain < 1:
            raise SearchError(f"n_gain must be a positive whole number; got {n_gain!r}")
        for key, v in (("eta0", eta0), ("theta0", theta0), ("min_distance", min_distance)):
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not np.isfinite(v) or v <= 0:
                raise SearchError(f"{key} must be a positive number; got {v!r}")
        if not 0 < q0 < 1 or not 0.5 <= persistence <= 1:
            raise SearchError(f"q0 must lie in (0, 1) and persistence in [0.5, 1]; got {q0!r}, {persistence!r}")
        if ideal not in ("mean", "sample"):
            raise SearchError(f"ideal must be 'mean' (Algorithm 2) or 'sample' (Sec. 4.3); got {ideal!r}")
        if int(loop_window) < 1 or int(loop_visits) < 1:
            raise SearchError("loop_window and loop_visits must be positive whole numbers")
        self.n_particles, self.n_gain = int(n_particles), int(n_gain)
        self.eta0, self.theta0, self.q0, self.persistence = float(eta0), float(theta0), float(q0), float(persistence)
        self.ideal, self.regularise, self.min_distance = ideal, bool(regularise), float(min_distance)
        self.loop_window, self.loop_visits = int(loop_window), int(loop_visits)
        self.stay = bool(stay)

    def params(self) -> dict:
        return dict(n_particles=self.n_particles, n_gain=self.n_gain, eta0=self.eta0, theta0=self.theta0,
                    q0=self.q0, persistence=self.persistence, ideal=self.ideal, regularise=self.regularise,
                    min_distance=self.min_distance, loop_window=self.loop_window, loop_visits=self.loop_visits,
                    stay=self.stay, planner=self.planner, map=self.map, field=self.field, controls=self.controls)

    def start(self, ctx: SearchContext) -> None:
        self._reset_state()
        nom = ctx.nominal
        self.space = nom["space"]
        self.rng = ctx.rng
        links = gain = None
        if self.map == "known":
            if "links" not in nom:
                raise SearchError("map='known' needs a scenario that tells the map (map: known)")
            links = np.asarray(nom["links"], dtype=bool)
            if self.field == "lattice":
                gain = _lattice_gain(self.space, links)
        self.belief = RBPFBelief(self.space, ctx.start[:2], ctx.rng, n_particles=self.n_particles, eta0=self.eta0,
                                 theta0=self.theta0, q0=self.q0, persistence=self.persistence,
                                 slip=float(nom.get("slip", 0.04)), primary=nom.get("primary", (1.0, 0.0)),
                                 secondary=nom.get("secondary", (0.8, 0.1)), regularise=self.regularise,
                                 min_distance=self.min_distance, links=links, gain=gain)
        self.pose = np.asarray(ctx.start[:2], dtype=float).copy()
        self.visits: list[int] = []
        self.gains = np.zeros(len(CONTROLS))
        self.n_random = 0

    # -- control ----------------------------------------------------------------------
    def admissible(self) -> np.ndarray:
        """Mask of the five controls: stay, and moves along links whose posterior
        probability of existence from the particles' searcher nodes is at least 1/2
        (so the first move, before any link was seen, may try any direction)."""
        b = self.belief
        ok = np.zeros(len(CONTROLS), dtype=bool)
        lid = self.space.link_of[b.node]                            # (N, 4)
        has = lid >= 0
        q = np.where(has, b.q[np.arange(b.n)[:, None], np.maximum(lid, 0)], 0.0)
        ok[1:] = b.w @ q >= 0.5 - 1e-6          # not believed missing (the prior q0 = 0.5 is admissible)
        ok[0] = self.stay or not ok[1:].any()
        return ok

    def _scores(self, logI: np.ndarray, logJ: np.ndarray, logw: np.ndarray) -> np.ndarray:
        """D^{(j)} of eq. (43) for each hypothetical count (rows of logI, logJ)."""
        return -2.0 * (logsumexp(logJ + logw, axis=1) - 0.5 * logsumexp(logI + logw, axis=1))

    def gains_of(self, ok: np.ndarray) -> np.ndarray:
        """Expected gain of each admissible control (Algorithm 2); -inf elsewhere."""
        b, rng = self.belief, self.rng
        out = np.full(len(CONTROLS), -np.inf)
        logw = np.log(b.w)
        for k in np.flatnonzero(ok):
            nodes = b.node if k == 0 else self.space.step_of[b.node, k - 1]
            nodes = np.where(nodes >= 0, nodes, b.node)             # ideal move: p + u on the lattice
            c = b.c(nodes)
            j = rng.integers(0, b.n, self.n_gain)
            rate = b.eta * b.theta[j] if self.ideal == "mean" else rng.gamma(b.eta, b.theta[j])
            counts, mult = np.unique(np.rint(rate * c[j]), return_counts=True)
            logI = log_evidence(counts[:, None], b.eta, b.theta[None, :], c[None, :])
            logJ = log_bhattacharyya(counts[:, None], b.eta, b.theta[None, :], c[None, :])
            out[k] = float(mult @ self._scores(logI, logJ, logw)) / self.n_gain
        return out

    def propose(self):
        if self.done:
            return None
        ok = self.admissible() if self.controls == "believed" else np.ones(len(CONTROLS), dtype=bool)
        here = int(np.argmax(self.belief.node_weights()))
        recent = self.visits[-self.loop_window:]
        if recent.count(here) > self.loop_visits:
            k = int(self.rng.choice(np.flatnonzero(ok)))
            self.n_random += 1
            self.gains = np.full(len(CONTROLS), np.nan)
        else:
            self.gains = self.gains_of(ok)
            k = int(np.argmax(self.gains)) if self.planner == "gain" else self._path_control(ok, here)
        self.control = k
        target = self.pose + CONTROLS[k]
        return Stay(self.pose.copy()) if k == 0 else Move(target)

    def _path_control(self, ok: np.ndarray, here: int) -> int:
        """The ``planner="path"`` control: the admissible control whose next node minimises
        the expected shortest-path distance, over the links believed present
        (probability >= 1/2), to the source particles binned on the nodes; ties go to
        the larger gain. A longer horizon than the one-step gain: it routes around
        walls the searcher has seen instead of being trapped in dead ends."""
        b, sp = self.belief, self.space
        n = len(sp.points)
        src = sp.index_of(np.rint(b.source))
        post = np.bincount(src[src >= 0], weights=b.w[src >= 0], minlength=n)
        q = b.w @ b.q.astype(float)
        a, c = sp.links[q >= 0.5 - 1e-6].T
        adj = coo_matrix((np.ones(2 * a.size), (np.r_[a, c], np.r_[c, a])), shape=(n, n)).tocsr()
        from scipy.sparse.csgraph import shortest_path  # here: listing the strategies skips it
        ks = np.flatnonzero(ok)
        nxt = [here if k == 0 else int(sp.step_of[here, k - 1]) for k in ks]
        nxt = [here if j < 0 else j for j in nxt]
        dist = shortest_path(adj, unweighted=True, directed=False, indices=nxt)
        dist = np.where(np.isfinite(dist), dist, 2.0 * n)
        score = dist @ post - 1e-3 * np.nan_to_num(self.gains[ks], neginf=0.0)
        return int(ks[int(np.argmin(score))])

    # -- update -----------------------------------------------------------------------
    def _control_of(self, intent) -> int:
        """The control `intent` stands for (what :meth:`propose` chose, or what another
        driver commanded): its offset from the reported pose among :data:`CONTROLS`."""
        u = np.rint(np.asarray(intent.point, dtype=float) - self.pose).astype(int)
        k = np.flatnonzero(np.all(CONTROLS == u, axis=1))
        return int(k[0]) if k.size and not isinstance(intent, Stay) else 0

    def observe(self, observations, intent, agent: int = 0) -> None:
        b = self.belief
        self.control = self._control_of(intent)
        for o in observations:
            b.predict(self.control)
            b.update(o)
            self.n_samples += 1
            self.pose = np.asarray(o.position, dtype=float).copy()
        self.n_measurements += len(observations)
        self.visits.append(int(np.argmax(b.node_weights())))          # the believed node
        est = b.estimate()
        cov = np.cov(b.source.T, aweights=b.w)
        area = float(np.pi * 5.991 * np.sqrt(max(np.linalg.det(cov), 0.0)))   # 95 % ellipse
        self.status = Status(est, area, extra=dict(
            count=float(observations[-1].value), rate=b.rate(), ess=b.ess,
            believed_position=b.position().tolist(), gains=np.where(np.isfinite(self.gains), self.gains, None).tolist(),
            control=int(self.control)))

    def position_support(self) -> np.ndarray:
        """Nodes (k, 2) in the support of the searcher-position particles: the strategy's
        declaration for the paper's self-localisation test (Sec. 5.1), which the environment
        makes against the true node once the search is over."""
        return self.space.points[np.unique(self.belief.node)]

    def figure_record(self) -> dict:
        """The particle clouds now (``lattice_particles``: source particles, the searcher's
        node particles as points, each link's probability), for
        :func:`reciprocity.viz.lattice.search_figure`."""
        b = self.belief
        return {"lattice_particles": {"source": b.source.copy(), "nodes": b.space.points[b.node].copy(),
                                      "links": b.link_probability().copy()}}


@register
class RBPFInfotaxisStrategy(RBPFStrategy):
    """The RBPF searcher with an infotaxis reward: the expected drop of the Shannon
    entropy of the particle weights over the M ideal measurements (instead of the
    Bhattacharyya distance of eq. (13)). Same filter, parameters and heuristics."""

    name = "rbpf-infotaxis"
    gain_kind = "shannon"

    def _scores(self, logI: np.ndarray, logJ: np.ndarray, logw: np.ndarray) -> np.ndarray:
        lp = logI + logw
        lp = lp - logsumexp(lp, axis=1, keepdims=True)
        h_post = -np.sum(np.exp(lp) * lp, axis=1)
        h_prior = -float(np.sum(np.exp(logw) * logw))
        return h_prior - h_post

