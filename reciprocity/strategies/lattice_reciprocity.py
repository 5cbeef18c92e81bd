"""Reciprocity search on the random lattice: the discrete adjoint (beyond Ristic et al. 2014).

On an undirected lattice the tracer's absorbing random walk is reversible:
``d_x F[x, z] = d_z F[z, x]`` (:class:`reciprocity.models.lattice.LatticeGreen`). The mean
count at the searcher's node z for a source at x is ``A · F[x, z]``, column z of F, so one
sparse solve per visited node gives the likelihood of the count over *every* candidate
source node at once. ``lattice-reciprocity`` keeps a posterior over the source nodes from
the Poisson counts (A known, or A unknown with a Gamma prior integrated out in closed form:
the negative binomial) and moves by an expected-information rule or along shortest paths
toward the posterior mass.

Two ways to know the lattice (``map``):

* ``"known"``: the world's scenario says ``map: known`` and the strategy is told which
  links exist (``nominal["links"]``); its searcher position is an exact HMM over the nodes
  (the motion model of eq. (45) with the strategy's own p_e, and the link detector of
  eq. (8)); counts are not used to localise (an approximation, named below);
* ``"rbpf"``: the map is unknown; the strategy runs the RBPF of Ristic et al.
  (:class:`reciprocity.beliefs.rbpf.RBPFBelief`) for the searcher's position and the link
  probabilities, and uses as its Green's function that of the lattice weighted by the
  RBPF's link probabilities (conductances), refactorised every step and the whole count
  history re-weighed with it.
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import coo_matrix
from scipy.special import gammaln, logsumexp

from ..beliefs.base import expected_entropy
from ..beliefs.rbpf import LOG_FLOOR, RBPFBelief
from ..errors import SearchError
from ..validation import positive
from ..intents import Move, Stay
from ..spaces.lattice import CONTROLS
from ..models.lattice import LatticeGreen
from . import register
from .base import SearchContext, Status, Strategy

__all__ = ["LatticeReciprocityStrategy", "COUNT_FLOOR", "SUPPORT"]

#: Floor of the modelled visits ``F[x, z]`` in a count's likelihood: a count where the
#: model says none can arrive (a slip the position filter missed) must not rule a node out.
COUNT_FLOOR = 1e-6
#: Position probability above which a node is in the searcher's "support" for the
#: paper's self-localisation test: 1/4000, the resolution of the RBPF's 4000 particles.
SUPPORT = 1.0 / 4000


@register
class LatticeReciprocityStrategy(Strategy):
    """Reciprocity imaging on the lattice: a posterior over source nodes from the
    discrete adjoint, one sparse solve per visited node.

    Parameters
    ----------
    map : {"auto", "known", "rbpf"}
        ``"known"``: the scenario must tell the map (``map: known``); ``"rbpf"``: the map
        is estimated by the RBPF (the paper's filter) and its link probabilities weight
        the Green's function; ``"auto"`` (default): ``"known"`` when the scenario tells
        the map, else ``"rbpf"``.
    rule : {"path", "path+mode", "infotaxis"}
        Next move. ``"path"`` (default): the admissible control minimising the
        posterior-expected shortest-path distance to the source (ties: the infotaxis
        score; it reaches the source more often than ``"infotaxis"``, see
        ``benchmarks/lattice_beyond.md``). ``"path+mode"``: the same, but where
        that rule would stay (the searcher is at the graph median of a spread posterior,
        where ``"path"`` can wait until the step cap), a step along the shortest path to
        the posterior's mode. ``"infotaxis"``: among the admissible controls, the one minimising the
        expected entropy of the source posterior after the next count, times the
        probability of *not* stepping on the source (Vergassola et al.'s found term).
    strength : float or None
        The release rate A0 the model assumes (particles per step at unit F); None: unknown,
        Gamma(eta0, theta0) prior integrated out (negative binomial).
    eta0, theta0 : float
        Gamma prior of A0 when `strength` is None (15, 1: the RBPF's prior).
    slip : float or None
        The motion model's p_e (None: the world's nominal value); it may differ from the
        truth's.
    n_particles : int
        N of the RBPF in ``map="rbpf"``.
    green : {"estimated", "complete"}
        With ``map="rbpf"``: the Green's function of the lattice weighted by the RBPF's
        link probabilities, refactorised every step (``"estimated"``), or that of the
        complete lattice (``"complete"``, the ablation: what the map estimate adds), or
        (``"sampled"``) the likelihood averaged over `n_maps` maps drawn link by link from
        the RBPF's link probabilities (the Bayesian average over the map, by Monte Carlo,
        instead of the Green's function of the average map).
    n_maps : int
        K, maps drawn per step for ``green="sampled"`` (common random numbers).
    unseen : {"rbpf", "nominal"}
        Probability of a link the RBPF has not seen, in the Green's function: the RBPF's
        prior 1/2 (``"rbpf"``) or ``1 − p`` of the world's nominal p (``"nominal"``).
    support : float
        Position probability above which a node counts as "in the support" for the
        self-localisation test (``map="known"``; default 1/4000, the RBPF's resolution).

    Notes
    -----
    Assumptions and approximations, named:

    * the searcher's position posterior p_k(s) is filtered from the motion model and the
      link readings only (``map="known"``) or taken from the RBPF; the source likelihood
      of a count uses the position-averaged visits ``F̄_k(x) = Σ_s p_k(s) F[x, s]``
      (mean field in the position; exact when the position is certain, which the
      perfect primary link detector on a known map makes typical);
    * ``F̄`` is floored at :data:`COUNT_FLOOR` (a count where the model expects none must
      not rule a source out: slips or a map the model got wrong);
    * every step the search goes on, the searcher is not on the source: each node x is
      down-weighted by ``1 − p_k(x)`` (the episode stops when the source is reached);
    * the expected-information rule moves the most probable searcher node by the control
      (no slip) to predict the next count.

    Measured success, steps and CPU per step of every variant: ``benchmarks/lattice_beyond.md``.
    """

    name = "lattice-reciprocity"
    worlds = ("lattice",)
    agents = 1

    def __init__(self, *, map: str = "auto", rule: str = "path", strength: float | None = None,
                 eta0: float = 15.0, theta0: float = 1.0, slip: float | None = None,
                 n_particles: int = 4000, support: float = SUPPORT, green: str = "estimated",
                 n_maps: int = 16, unseen: str = "rbpf"):
        super().__init__()
        if map not in ("auto", "known", "rbpf"):
            raise SearchError(f"map must be 'known' (the scenario's map: known), 'rbpf' (estimated by "
                              f"the RBPF) or 'auto'; got {map!r}")
        if rule not in ("infotaxis", "path", "path+mode"):
            raise SearchError(f"rule must be 'path', 'path+mode' or 'infotaxis'; got {rule!r}")
        self.strength = positive(strength, "strength", none=True)
        self.eta0, self.theta0 = positive(eta0, "eta0"), positive(theta0, "theta0")
        if slip is not None and (isinstance(slip, bool) or not isinstance(slip, (int, float))
                                 or not 0 <= slip < 1):
            raise SearchError(f"slip must be a probability in [0, 1) or null; got {slip!r}")
        if isinstance(n_particles, bool) or not isinstance(n_particles, (int, np.integer)) or n_particles < 10:
            raise SearchError(f"n_particles must be a whole number >= 10; got {n_particles!r}")
        if isinstance(support, bool) or not isinstance(support, (int, float)) or not 0 < support < 1:
            raise SearchError(f"support must be a probability in (0, 1); got {support!r}")
        if green not in ("estimated", "complete", "sampled"):
            raise SearchError(f"green must be 'estimated' (the RBPF's map weights the lattice), 'sampled' "
                              f"(maps drawn from it) or 'complete'; got {green!r}")
        if isinstance(n_maps, bool) or not isinstance(n_maps, (int, np.integer)) or n_maps < 1:
            raise SearchError(f"n_maps must be a positive whole number; got {n_maps!r}")
        if unseen not in ("rbpf", "nominal"):
            raise SearchError(f"unseen must be 'rbpf' (the RBPF's prior 1/2) or 'nominal' (1 - p of the "
                              f"world's nominal p); got {unseen!r}")
        self.n_maps, self.unseen_links = int(n_maps), unseen
        self.map, self.rule, self.slip = map, rule, None if slip is None else float(slip)
        self.green_kind = green
        self.n_particles, self.support = int(n_particles), float(support)

    def params(self) -> dict:
        return dict(map=self.map, rule=self.rule, strength=self.strength, eta0=self.eta0, theta0=self.theta0,
                    slip=self.slip, n_particles=self.n_particles, support=self.support, green=self.green_kind,
                    n_maps=self.n_maps, unseen=self.unseen_links)

    # -- start ------------------------------------------------------------------------
    def start(self, ctx: SearchContext) -> None:
        self._reset_state()
        nom = ctx.nominal
        if "space" not in nom:
            raise SearchError("lattice-reciprocity needs a lattice world")
        self.space = nom["space"]
        self.rng = ctx.rng
        self.p_e = float(nom.get("slip", 0.04)) if self.slip is None else self.slip
        self.primary = tuple(nom.get("primary", (1.0, 0.0)))
        self.secondary = tuple(nom.get("secondary", (0.8, 0.1)))
        n = len(self.space.points)
        start = int(self.space.index_of(ctx.start[:2])[0])
        self.mode = self.map if self.map != "auto" else ("known" if nom.get("links") is not None else "rbpf")
        if self.mode == "known":
            if nom.get("links") is None:
                raise SearchError("lattice-reciprocity with map: known needs the scenario's world to say "
                                  "map: known (or use map: rbpf)")
            self.links = np.asarray(nom["links"], dtype=bool)
            self.green = LatticeGreen(self.space, self.links)
            self.pos = np.zeros(n)
            self.pos[start] = 1.0
            self.belief = None
            self._dist = self._distances(self.links)
        else:
            self.belief = RBPFBelief(self.space, ctx.start[:2], ctx.rng, n_particles=self.n_particles,
                                     slip=self.p_e, primary=self.primary, secondary=self.secondary)
            self.green = LatticeGreen(self.space, np.ones(len(self.space.links)))   # the complete lattice
            self.pos = self.belief.node_weights()
            self._dist = None
        self._second = self.space.second_link_of
        self.cand = self.space.transient.copy()            # prior: uniform over the nodes inside R0
        self.history: list[tuple[np.ndarray, np.ndarray, float]] = []   # (nodes, probs, count)
        self.maps = []
        self.unseen = None
        if self.belief is not None and self.unseen_links == "nominal":
            self.unseen = 1.0 - float(nom.get("p") or 0.0)
        if self.belief is not None and self.green_kind == "sampled":
            self._u = self.rng.random((self.n_maps, len(self.space.links)))
            self._sample_maps()
        self.not_here = np.zeros(n)                        # Σ log(1 − p_k(x))
        self.pose = np.asarray(ctx.start[:2], dtype=float).copy()
        self.control = 0
        self._posterior()

    def _distances(self, present) -> np.ndarray:
        sp = self.space
        a, b = sp.links[np.asarray(present, dtype=bool)].T
        n = len(sp.points)
        adj = coo_matrix((np.ones(2 * a.size), (np.r_[a, b], np.r_[b, a])), shape=(n, n)).tocsr()
        from scipy.sparse.csgraph import shortest_path  # here: listing the strategies skips it
        return shortest_path(adj, unweighted=True, directed=False)

    # -- position -----------------------------------------------------------------------
    def _predict_position(self, control: int) -> None:
        sp, p = self.space, self.pos
        out = np.zeros_like(p)
        probs = np.full(len(CONTROLS), self.p_e / (len(CONTROLS) - 1))
        probs[control] = 1.0 - self.p_e
        nodes = np.arange(len(p))
        for c, pc in enumerate(probs):
            if pc <= 0:
                continue
            if c == 0:
                dest = nodes
            else:
                lid = sp.link_of[:, c - 1]
                ok = (lid >= 0) & self.links[np.maximum(lid, 0)]
                dest = np.where(ok, sp.step_of[:, c - 1], nodes)
            out += np.bincount(dest, weights=p * pc, minlength=len(p))
        self.pos = out

    def _update_position(self, z1, z2) -> None:
        sp = self.space
        like = np.ones(len(self.pos))
        for table, z, (pd, pfa) in ((sp.link_of, z1, self.primary), (self._second, z2, self.secondary)):
            for d in range(4):
                if z[d] < 0:
                    continue
                lid = table[:, d]
                m = (lid >= 0) & self.links[np.maximum(lid, 0)]
                like *= np.where(m, pd if z[d] == 1 else 1 - pd, pfa if z[d] == 1 else 1 - pfa)
        post = self.pos * np.maximum(like, LOG_FLOOR)
        post[post < 1e-14 * post.max()] = 0.0
        self.pos = post / post.sum()

    # -- source posterior ---------------------------------------------------------------
    def _fbar(self, nodes, probs, green=None) -> np.ndarray:
        return np.maximum((self.green if green is None else green).visits(nodes) @ probs, COUNT_FLOOR)

    def _loglik(self, green) -> tuple[np.ndarray, np.ndarray]:
        """log-likelihood of the count history for every source node under `green`
        (-inf where `green` admits no source), and ``S(x) = Σ_k F̄_k(x)``."""
        n = len(self.space.points)
        counts = np.array([h[2] for h in self.history])
        if self.history:
            if green is self.green:                        # cache: one F̄ per reading under this model
                if getattr(self, "_fb_green", None) is not green:
                    self._fb_green, self._fb = green, []
                self._fb += [self._fbar(h[0], h[1], green) for h in self.history[len(self._fb):]]
                fb = np.column_stack(self._fb)
            else:
                fb = np.column_stack([self._fbar(h[0], h[1], green) for h in self.history])     # (n, k)
        else:
            fb = np.ones((n, 0))
        s = fb.sum(axis=1)
        ncount = float(counts.sum())
        loglik = np.log(fb) @ counts if counts.size else np.zeros(n)
        if self.strength is not None:
            loglik = loglik - self.strength * s
        else:
            loglik = loglik - (self.eta0 + ncount) * np.log(s + 1.0 / self.theta0)
        self.N = ncount
        return np.where(green.candidates, loglik, -np.inf), s

    def _posterior(self) -> None:
        """log posterior over source nodes from the whole history (recomputed: the map
        estimate may have changed); with sampled maps, the likelihood averaged over them."""
        loglik, self.S = self._loglik(self.green)
        if getattr(self, "maps", None):
            ll = np.array([self._loglik(g)[0] for g in self.maps])
            with np.errstate(invalid="ignore"):
                loglik = logsumexp(ll, axis=0) - np.log(len(self.maps))
        lp = np.where(self.cand & np.isfinite(loglik), loglik + self.not_here, -np.inf)
        if not np.isfinite(lp).any():
            lp = np.where(self.cand, 0.0, -np.inf)
        self.logpost = lp - logsumexp(lp)
        self.post = np.exp(self.logpost)

    def _sample_maps(self) -> None:
        """``green="sampled"``: K maps drawn link by link from the RBPF's link
        probabilities (links it has not seen: ``1 − p`` of the nominal world), with common
        random numbers from step to step."""
        q = self._links_unseen(self._links_believed())
        self.maps = [LatticeGreen(self.space, (u < q).astype(float)) for u in self._u]

    def _links_unseen(self, q: np.ndarray) -> np.ndarray:
        """`q` with the links the RBPF has not seen (still at its prior 1/2) set to
        `self.unseen`."""
        if self.unseen is None:
            return q
        return np.where(np.abs(q - 0.5) < 1e-3, self.unseen, q)

    # -- control ----------------------------------------------------------------------
    def _here(self) -> int:
        return int(np.argmax(self.pos))

    def admissible(self) -> np.ndarray:
        """Mask of the controls: stay, and moves along links believed present at the most
        probable searcher node (the known map; or RBPF probability >= 1/2)."""
        s = self._here()
        lid = self.space.link_of[s]
        ok = np.zeros(len(CONTROLS), dtype=bool)
        ok[0] = True
        if self.belief is None:
            ok[1:] = (lid >= 0) & self.links[np.maximum(lid, 0)]
        else:
            q = self._links_believed()
            ok[1:] = (lid >= 0) & (q[np.maximum(lid, 0)] >= 0.5 - 1e-6)
        return ok

    def _links_believed(self) -> np.ndarray:
        """The RBPF's posterior link probabilities, summed in float64 (float32 sums of
        4000 equal weights land below 1/2); cached until the next observation."""
        if getattr(self, "_qb", None) is None:
            self._qb = self.belief.w @ self.belief.q.astype(float)
        return self._qb

    def _next_node(self, k: int) -> int:
        s = self._here()
        return s if k == 0 else int(self.space.step_of[s, k - 1])

    def expected_entropy(self, node: int) -> float:
        """``(1 − P_found) · E_n[H(source | n)]`` after one count at `node` (nats)."""
        post = self.post.copy()
        p_found = float(post[node])
        post[node] = 0.0
        if post.sum() <= 0:
            return 0.0
        post /= post.sum()
        keep = post > 1e-12
        w, f = post[keep], np.maximum(self.green.visits([node])[keep, 0], COUNT_FLOOR)
        if self.strength is not None:
            mean = self.strength * f
        else:
            a, b = self.eta0 + self.N, 1.0 / self.theta0 + self.S[keep]
            mean = a * f / b
        top = float(mean.max())
        ns = np.arange(int(np.ceil(top + 6 * np.sqrt(top) + 10)))[:, None]
        if self.strength is not None:
            logp = ns * np.log(mean) - mean - gammaln(ns + 1)
        else:
            logp = (gammaln(a + ns) - gammaln(a) - gammaln(ns + 1) + a * np.log(b / (b + f))
                    + ns * np.log(f / (b + f)))
        return (1.0 - p_found) * float(expected_entropy(logp + np.log(w), log=True))   # (counts, x)

    def propose(self):
        if self.done:
            return None
        ok = self.admissible()
        ks = np.flatnonzero(ok)
        info = np.array([self.expected_entropy(self._next_node(k)) for k in ks])
        if self.rule in ("path", "path+mode"):
            dist = self._dist if self.belief is None else self._distances(self._links_believed() >= 0.5 - 1e-6)
            dist = np.where(np.isfinite(dist), dist, 2 * len(dist))
            d = np.array([float(self.post @ dist[self._next_node(k)]) for k in ks])
            score = d + 1e-3 * info
            if self.rule == "path+mode" and ks[int(np.argmin(score))] == 0 and ks.size > 1:
                # at the graph median of a spread posterior: head for its mode instead of waiting
                mode = int(np.argmax(self.post))
                score = np.array([dist[self._next_node(k), mode] + (np.inf if k == 0 else 0.0) for k in ks])
                score = score + 1e-3 * info
        else:
            score = info
        k = int(ks[int(np.argmin(score))])
        self.scores = dict(zip(ks.tolist(), score.tolist()))
        self.control = k
        target = self.pose + CONTROLS[k]
        return Stay(self.pose.copy()) if k == 0 else Move(target)

    # -- update -----------------------------------------------------------------------
    def observe(self, observations, intent, agent: int = 0) -> None:
        for o in observations:
            data = o.data or {}
            z1 = np.asarray(data.get("primary", [-1] * 4), dtype=int)
            z2 = np.asarray(data.get("secondary", [-1] * 4), dtype=int)
            if self.belief is None:
                self._predict_position(self.control)
                self._update_position(z1, z2)
            else:
                self.belief.predict(self.control)
                self.belief.update(o)
                self._qb = None
                self.pos = self.belief.node_weights()
            nodes = np.flatnonzero(self.pos > 0)
            order = np.argsort(self.pos[nodes])[::-1]
            cum = np.cumsum(self.pos[nodes][order])
            nodes = nodes[order[:int(np.searchsorted(cum, 1 - 1e-6)) + 1]]
            probs = self.pos[nodes] / self.pos[nodes].sum()
            self.history.append((nodes, probs, float(o.value)))
            self.not_here += np.log(np.maximum(1.0 - self.pos, LOG_FLOOR))
            self.n_samples += 1
            self.pose = np.asarray(o.position, dtype=float).copy()
        self.n_measurements += len(observations)
        if self.belief is not None and self.green_kind in ("estimated", "sampled"):
            self.green = LatticeGreen(self.space, self._links_unseen(self._links_believed()))
        if self.belief is not None and self.green_kind == "sampled":
            self._sample_maps()
        self._posterior()
        est = self.space.points[int(np.argmax(self.post))]
        order = np.sort(self.post)[::-1]
        area = float(np.searchsorted(np.cumsum(order), 0.95) + 1)        # nodes (unit cells) in the 95 % set
        self.status = Status(est.copy(), area, extra=dict(
            count=float(observations[-1].value), believed_position=self.space.points[self._here()].tolist(),
            p_source_max=float(self.post.max()), control=int(self.control)))

    def position_support(self) -> np.ndarray:
        """Nodes (k, 2) in the support of the position belief, for the environment's
        self-localisation test (as ``rbpf``'s :meth:`~reciprocity.strategies.rbpf.RBPFStrategy.position_support`)."""
        if self.belief is not None:
            return self.space.points[np.unique(self.belief.node)]
        return self.space.points[self.pos >= self.support]

    def figure_record(self) -> dict:
        """The source posterior over the nodes now (``lattice_posterior``), the map it was
        computed on (``lattice_mode``) and the readings it rests on (``lattice_readings``),
        for :func:`reciprocity.viz.lattice.posterior_figure`."""
        return {"lattice_posterior": np.asarray(self.post, dtype=float).copy(), "lattice_mode": self.mode,
                "lattice_readings": len(self.history)}
