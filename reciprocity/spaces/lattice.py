"""A square lattice inside a circle, with links that may be missing, as a search space.

The lattice of Ristic et al. (2014), Sec. 2.1: nodes at integer points, links of unit
length between horizontal and vertical neighbours. The nodes with ``r <= R0`` are the
*transient* states of the tracer's random walk; the ring ``R0 < r < R0 + 1`` holds the
*absorbing* boundary nodes (``θ(r = R0) = 0``). With R0 = 9 this gives 305 nodes and the
paper's L = 572 potential links.
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import coo_matrix

from .base import SearchSpace

__all__ = ["LatticeSpace", "DIRECTIONS", "CONTROLS"]

#: Unit moves east, west, north, south (the order of direction indices 0..3).
DIRECTIONS = np.array([(1, 0), (-1, 0), (0, 1), (0, -1)], dtype=int)
#: The controls of an observer on the lattice (Ristic et al. Sec. 2.3): stay, east, west,
#: north, south (lattice units). Public: what an observer may do is part of the task.
CONTROLS = np.vstack([[0, 0], DIRECTIONS])


class LatticeSpace(SearchSpace):
    """Nodes and links of a circular square lattice; a mask says which links exist.

    Parameters
    ----------
    radius : float
        R0, lattice units: nodes with ``r <= R0`` are transient, nodes with
        ``R0 < r < R0 + 1`` are the absorbing boundary.
    present : array_like of bool, shape (L,), optional
        Which of the L potential links exist (default: all, the complete grid of the
        paper's Fig. 1).

    Attributes
    ----------
    points : ndarray, shape (n, 2)
        Node coordinates (integers, stored as floats).
    links : ndarray, shape (L, 2)
        Node indices of each potential link (lower index first along x, then y).
    present : ndarray of bool, shape (L,)
    transient : ndarray of bool, shape (n,)
        Nodes inside the circle (not on the absorbing ring).
    link_of : ndarray of int, shape (n, 4)
        Potential link from each node in each direction of :data:`DIRECTIONS`, -1 if none.
    step_of : ndarray of int, shape (n, 4)
        Node one step in each direction, -1 off the lattice.

    Examples
    --------
    >>> s = LatticeSpace(9)
    >>> len(s), len(s.links), int(s.transient.sum())
    (305, 572, 253)
    """

    def __init__(self, radius: float, present=None):
        self.radius = float(radius)
        k = int(np.ceil(self.radius)) + 1
        xs = np.arange(-k, k + 1)
        gx, gy = np.meshgrid(xs, xs, indexing="ij")
        r2 = gx ** 2 + gy ** 2
        inside = r2 < (self.radius + 1) ** 2
        self._k = k
        self._index = -np.ones(inside.shape, dtype=np.int64)
        self._index[inside] = np.arange(int(inside.sum()))
        self.points = np.column_stack([gx[inside], gy[inside]]).astype(float)
        self.transient = (r2[inside] <= self.radius ** 2)
        self.cell_areas = np.ones(len(self.points))
        ij = self.points.astype(int) + k
        self.step_of = -np.ones((len(self.points), 4), dtype=np.int64)
        for d, (dx, dy) in enumerate(DIRECTIONS):
            a, b = ij[:, 0] + dx, ij[:, 1] + dy
            ok = (a >= 0) & (a <= 2 * k) & (b >= 0) & (b <= 2 * k)
            self.step_of[ok, d] = self._index[a[ok], b[ok]]
        # potential links: east and north of each node
        links = []
        for d in (0, 2):
            nb = self.step_of[:, d]
            src = np.flatnonzero(nb >= 0)
            links.append(np.column_stack([src, nb[src]]))
        self.links = np.vstack(links)
        self.link_of = -np.ones((len(self.points), 4), dtype=np.int64)
        n_e = len(links[0])
        ids = np.arange(len(self.links))
        east, north = self.links[:n_e], self.links[n_e:]
        self.link_of[east[:, 0], 0] = ids[:n_e]
        self.link_of[east[:, 1], 1] = ids[:n_e]
        self.link_of[north[:, 0], 2] = ids[n_e:]
        self.link_of[north[:, 1], 3] = ids[n_e:]
        self.present = np.ones(len(self.links), dtype=bool)
        if present is not None:
            p = np.asarray(present, dtype=bool).ravel()
            if p.shape != self.present.shape:
                raise ValueError(f"present must have {len(self.links)} entries; got {p.size}")
            self.present = p.copy()
        self._adjacency()

    def _adjacency(self) -> None:
        a, b = self.links[self.present].T
        n = len(self.points)
        self.adjacency = coo_matrix((np.ones(2 * a.size), (np.r_[a, b], np.r_[b, a])), shape=(n, n)).tocsr()

    def with_links(self, present) -> "LatticeSpace":
        """The same lattice with link mask `present`."""
        out = object.__new__(LatticeSpace)
        out.__dict__.update(self.__dict__)
        out.present = np.asarray(present, dtype=bool).copy()
        out._adjacency()
        return out

    @property
    def second_link_of(self) -> np.ndarray:
        """Secondary link in each direction (the link beyond the adjacent node), (n, 4), -1 if none."""
        nb = self.step_of
        out = -np.ones_like(nb)
        ok = nb >= 0
        out[ok] = self.link_of[nb[ok], np.nonzero(ok)[1]]
        return out

    def index_of(self, points) -> np.ndarray:
        """Node index of each point (m, 2); -1 where a point is not a lattice node."""
        p = np.atleast_2d(np.asarray(points, dtype=float))
        r = np.rint(p)
        ij = r.astype(np.int64) + self._k
        ok = (np.all(np.abs(p - r) < 1e-6, axis=1) & np.all(ij >= 0, axis=1)
              & np.all(ij <= 2 * self._k, axis=1))
        out = -np.ones(len(p), dtype=np.int64)
        out[ok] = self._index[ij[ok, 0], ij[ok, 1]]
        return out

    def contains(self, points) -> np.ndarray:
        return self.index_of(points) >= 0

    def nearest(self, point) -> int:
        i = int(self.index_of(point)[0])
        return i if i >= 0 else super().nearest(point)

    def neighbours(self, i: int) -> np.ndarray:
        a = self.adjacency
        return a.indices[a.indptr[int(i)]:a.indptr[int(i) + 1]].copy()
