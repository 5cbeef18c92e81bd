"""The random-lattice world (truth) of Ristic, Skvortsov & Walker (2014).

A tracer source sits at a node of a circular square lattice from which a fraction `p`
of the links was removed at random. The mean concentration is that of the tracer's
random walk on the incomplete lattice as an absorbing Markov chain (Sec. 2.2):
``λ_j = A0 · F_ij`` with ``F = (I − Q)^−1`` (eq. (3)), computed here from one sparse LU
solve for the source's row, never a dense inverse. Sensor 1 counts Poisson particles of
mean λ at the searcher's node (eq. (4)); sensor 2 reports the primary and secondary links
around it through the detection matrices of eq. (8).

Several sources (``sources``) release independently, so the mean counts add up:
``λ_j = Σ_k A0_k · F_(i_k) j``, one sparse LU solve per source.
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import csc_matrix, diags
from scipy.sparse.csgraph import connected_components
from scipy.sparse.linalg import splu

from ..errors import SearchError
from ..spaces.lattice import LatticeSpace
from .base import Reading, World, source_set

__all__ = ["LatticeWorld", "draw_links", "green_row", "PERCOLATION_THRESHOLD", "MAX_REDRAWS"]

#: Bond-percolation threshold of the square lattice (p_c = 1/2).
PERCOLATION_THRESHOLD = 0.5
#: Draws of the missing links tried before giving up on a connected lattice.
MAX_REDRAWS = 20000
#: Links drawn in all the draws together before giving up (about a second of work): a
#: large lattice whose every node must stay connected is rarely so, and is answered with
#: an error instead of minutes of redraws.
MAX_REDRAW_LINKS = 10_000_000


def clusters(space: LatticeSpace) -> np.ndarray:
    return connected_components(space.adjacency, directed=False)[1]


def draw_links(space: LatticeSpace, p: float, rng: np.random.Generator, *, connectivity: str = "all",
               keep: tuple = ()) -> tuple[np.ndarray, int]:
    """Remove ``round(p·L)`` links at random until the free region is connected.

    Parameters
    ----------
    space : LatticeSpace
        The complete lattice.
    p : float
        Fraction of links removed (below the percolation threshold 1/2).
    rng : numpy.random.Generator
    connectivity : {"all", "nodes"}
        ``"all"``: every transient node lies in one cluster (the paper's Fig. 2: "all
        nodes in the incomplete lattice are connected"), redrawn until so. ``"nodes"``:
        only the nodes in `keep` must share a cluster (large lattices, where isolated
        nodes are certain).
    keep : tuple of int
        Node indices that must lie in one cluster (source and start).

    Returns
    -------
    present : ndarray of bool, shape (L,)
    draws : int
        Number of draws it took.
    """
    n_links = len(space.links)
    n_cut = int(round(p * n_links))
    keep = np.asarray(keep, dtype=np.int64)
    tries = max(10, min(MAX_REDRAWS, MAX_REDRAW_LINKS // max(n_links, 1)))
    for draw in range(1, tries + 1):
        present = np.ones(n_links, dtype=bool)
        present[rng.choice(n_links, n_cut, replace=False)] = False
        lab = clusters(space.with_links(present))
        ok = keep.size == 0 or np.all(lab[keep] == lab[keep[0]])
        if connectivity == "all":
            t = lab[space.transient]
            ok = ok and np.all(t == t[0]) and (keep.size == 0 or lab[keep[0]] == t[0])
        if ok:
            return present, draw
    raise SearchError(f"no connected lattice in {tries} draws with p = {p:g} and {n_links} links; lower p, "
                      "shrink radius or use connectivity: nodes")


def green_row(space: LatticeSpace, source: int) -> np.ndarray:
    """Row `source` of the fundamental matrix ``F = (I − Q)^−1`` (eq. (3)) on all nodes.

    ``F_ij`` is the expected number of visits to node j of a walker started at node i
    before absorption on the boundary ring; transitions go along existing links with
    probability ``1/m`` (m links at the node). One sparse LU solve of
    ``(I − Q)^T x = e_i`` on the transient nodes of the source's cluster (a cluster
    that never reaches the boundary would make ``I − Q`` singular); absorbing and
    unreachable nodes get 0.

    Parameters
    ----------
    space : LatticeSpace
        The lattice with its missing links.
    source : int
        Node index of the source (a transient node).

    Returns
    -------
    ndarray, shape (n,)
    """
    lab = clusters(space)
    if not np.any(~space.transient & (lab == lab[source])):
        raise SearchError("the source's cluster of links never reaches the boundary ring; redraw the lattice")
    t = np.flatnonzero(space.transient & (lab == lab[source]))   # closed clusters elsewhere: F = 0
    adj = space.adjacency
    deg = np.asarray(adj.sum(axis=1)).ravel()
    inv = np.divide(1.0, deg, out=np.zeros_like(deg), where=deg > 0)
    q = (diags(inv) @ adj)[t][:, t]                        # Q: transient -> transient
    a = csc_matrix(diags(np.ones(len(t))) - q).T.tocsc()   # (I − Q)^T
    pos = -np.ones(len(space.points), dtype=np.int64)
    pos[t] = np.arange(len(t))
    if pos[source] < 0:
        raise SearchError("the source must be a transient node (r <= R0)")
    e = np.zeros(len(t))
    e[pos[source]] = 1.0
    out = np.zeros(len(space.points))
    out[t] = splu(a).solve(e)
    return out


class LatticeWorld(World):
    """Truth of the lattice search: a source on a lattice with missing links.

    Parameters
    ----------
    space : LatticeSpace
        The *true* lattice (its missing links).
    source : array_like, shape (2,), or None
        Source node (lattice units); None when `sources` gives them.
    strength : float
        Release rate A0 (particles per step at unit F): the nominal one, and the true
        one of every source unless `strengths` says otherwise.
    primary, secondary : (float, float)
        ``(p_d, p_fa)`` of the link detector for the adjacent and the next links (eq. (8)).
    p : float, optional
        Fraction of links removed (nominal; for the record).
    slip : float
        p_e of the searcher's motion (eq. (45)); the platform's and the strategy's.
    draws : int
        Draws it took to get a connected lattice (reported by :meth:`describe`).
    map_known : bool
        Tell strategies which links exist (``nominal()["links"]``, the scenario's
        ``map: known``); False (the paper): they are told only the complete lattice.
    localisation_known : bool
        Every reading carries the node it was taken at (``data["fix"]``, the scenario's
        ``localisation: known``): an oracle position sensor for the ladder of
        ``docs/papers/ristic2014.md``. False (the paper): the searcher
        knows only its start and the controls it commanded.
    sources : array_like, shape (K, 2), optional
        Several source nodes (lattice units, distinct transient nodes), replacing
        `source` (which, if given, must be the first); the mean counts add up.
    strengths : array_like, shape (K,), optional
        Their release rates A0 (particles per step at unit F; default: each `strength`).
    max_sources : int, optional
        The task's public bound on the number of sources (default 1 with `source`,
        MAX_SOURCES with `sources`): part of what a strategy is told, never the number of
        sources itself.
    """

    kind = "lattice"
    found_radius = 0.5

    def __init__(self, space: LatticeSpace, source, strength: float, *, primary=(1.0, 0.0),
                 secondary=(0.8, 0.1), p: float | None = None, slip: float = 0.04, draws: int = 1,
                 map_known: bool = False, localisation_known: bool = False, sources=None, strengths=None,
                 max_sources: int | None = None):
        self.space = space
        self.sources, given, self.max_sources = source_set("lattice", source, sources, strengths, strength,
                                                           max_sources, each="release rate A0")
        self.source = self.sources[0]
        self.strength = float(strength)
        #: true release rates A0 of the sources (the nominal one is `strength`)
        self.strengths = given
        self.primary, self.secondary = tuple(map(float, primary)), tuple(map(float, secondary))
        self.p, self.slip, self.draws = p, float(slip), int(draws)
        self.map_known = bool(map_known)
        self.localisation_known = bool(localisation_known)
        self.source_nodes = space.index_of(self.sources).astype(int)
        if np.any(self.source_nodes < 0) or len(set(self.source_nodes.tolist())) < len(self.source_nodes):
            raise SearchError(f"sources {self.sources.tolist()} must be distinct nodes of the lattice (integers "
                              f"within R0 = {space.radius:g})")
        self.source_node = int(self.source_nodes[0])
        # eq. (3)-(4) per source; independent releases add their mean counts
        self.lam = np.sum([c * green_row(space, i) for c, i in zip(self.strengths, self.source_nodes.tolist())],
                          axis=0)
        self._second = space.second_link_of

    def contains(self, points) -> np.ndarray:
        return self.space.contains(points)

    def figure_record(self) -> dict:
        """The true lattice (``lattice``: its nodes, links, which are present, its radius),
        the source, the mean count λ per node and the release strength, for the figures
        (:mod:`reciprocity.viz.lattice`)."""
        sp = self.space
        return {"lattice": {"points": sp.points.copy(), "links": sp.links.copy(), "present": sp.present.copy(),
                            "radius": float(sp.radius)},
                "source": np.asarray(self.source, dtype=float).copy(), "lam": self.lam.copy(),
                "strength": self.strength}

    def mean(self, position) -> float:
        """Mean count λ at `position` (eq. (4)): ``A0 · F_ij``."""
        return float(self.lam[self.space.index_of(position)[0]])

    def links_seen(self, node: int, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
        """What sensor 2 reports at `node`: primary and secondary link readings per
        direction (E, W, N, S), 1 present, 0 absent, -1 not observable (the secondary
        link behind a missing primary link)."""
        sp = self.space
        lid = sp.link_of[node]
        m1 = (lid >= 0) & sp.present[np.maximum(lid, 0)]
        sid = self._second[node]
        m2 = (sid >= 0) & sp.present[np.maximum(sid, 0)]
        u = rng.random(8)
        pd1, pf1 = self.primary
        pd2, pf2 = self.secondary
        z1 = np.where(m1, u[:4] < pd1, u[:4] < pf1).astype(int)
        z2 = np.where(m2, u[4:] < pd2, u[4:] < pf2).astype(int)
        z2[~m1] = -1
        return z1, z2

    def read(self, position, *, time: float, dwell: float, rng: np.random.Generator,
             observer: int = 0) -> Reading:
        node = int(self.space.index_of(position)[0])
        if node < 0:
            raise SearchError(f"({position[0]:g}, {position[1]:g}) is not a lattice node")
        n = int(rng.poisson(self.lam[node] * max(dwell, 0.0)))
        z1, z2 = self.links_seen(node, rng)
        data = {"primary": z1.tolist(), "secondary": z2.tolist()}
        if self.localisation_known:
            data["fix"] = self.space.points[node].tolist()
        return Reading(float(n), False, "hits", data)

    def nominal(self) -> dict:
        full = LatticeSpace(self.space.radius)
        out = dict(space=full, radius=self.space.radius, primary=self.primary,
                   secondary=self.secondary, p=self.p, slip=self.slip,
                   localisation="known" if self.localisation_known else "unknown")
        if self.map_known:
            out["links"] = self.space.present.copy()      # the map, never the source
        return self._nominal_sources(out)

    def describe_start(self, start) -> dict:
        """``shortest_path``: links from the node of `start` to the nearest source over the
        links present (None when they are not connected)."""
        from scipy.sparse.csgraph import shortest_path
        node = int(self.space.index_of(np.asarray(start, dtype=float)[:2])[0])
        if node < 0:
            return {"shortest_path": None}
        d = shortest_path(self.space.adjacency, unweighted=True, directed=False, indices=node)[self.source_nodes].min()
        return {"shortest_path": int(d) if np.isfinite(d) else None}

    def describe(self) -> dict:
        out = dict(strength=self.strength, missing_links=int((~self.space.present).sum()),
                   lattice_draws=self.draws, map_known=self.map_known,
                   localisation_known=self.localisation_known)
        return self._described_sources(out)
