"""Admissible observation points: mesh nodes a platform can reach and stand on.

Both search strategies choose their next point among the mesh nodes that are in the
free region at a given clearance from every wall and in the same connected part of
that clearance-shrunk region as the observer (a car cannot squeeze through a gap
narrower than twice its clearance).
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from .green import GreenSolver

__all__ = ["CandidateSet"]


class CandidateSet:
    """Mesh nodes usable as observation points at `clearance` cm from the walls.

    Parameters
    ----------
    solver : GreenSolver
        Supplies the nodes and triangles.
    clearance : float
        Minimum distance (cm) from any wall.
    """

    def __init__(self, solver: GreenSolver, clearance: float = 0.0):
        self.nodes = solver.nodes
        self.clearance = float(clearance)
        self.wall_distance = solver.arena.wall_distance(self.nodes)
        ok = self.wall_distance >= self.clearance
        t = solver.triangles
        i = np.concatenate([t[:, 0], t[:, 1], t[:, 2]])
        j = np.concatenate([t[:, 1], t[:, 2], t[:, 0]])
        keep = ok[i] & ok[j]
        n = len(self.nodes)
        graph = coo_matrix((np.ones(keep.sum()), (i[keep], j[keep])), shape=(n, n))
        _, self._label = connected_components(graph, directed=False)
        self._label[~ok] = -1
        self._ok = ok

    def reachable_from(self, point) -> np.ndarray:
        """Boolean mask of admissible nodes in the connected part nearest to `point`."""
        p = np.asarray(point, dtype=float)
        d = np.hypot(*(self.nodes[self._ok] - p).T)
        if d.size == 0:
            return np.zeros(len(self.nodes), dtype=bool)
        label = self._label[np.flatnonzero(self._ok)[np.argmin(d)]]
        return self._label == label

    def nearest(self, point, mask: np.ndarray) -> np.ndarray | None:
        """The node of `mask` nearest to `point`, or None if the mask is empty."""
        idx = np.flatnonzero(mask)
        if idx.size == 0:
            return None
        d = np.hypot(*(self.nodes[idx] - np.asarray(point, dtype=float)).T)
        return self.nodes[idx[np.argmin(d)]].copy()

    def around(self, point, radius: float) -> np.ndarray:
        """Mask of nodes within `radius` (cm) of `point`."""
        return np.hypot(*(self.nodes - np.asarray(point, dtype=float)).T) <= radius

    def separated(self, visited: np.ndarray, d: float) -> np.ndarray:
        """Mask of nodes at distance at least `d` (cm) from every visited point."""
        v = np.atleast_2d(np.asarray(visited, dtype=float))
        if v.size == 0:
            return np.ones(len(self.nodes), dtype=bool)
        d2 = (self.nodes[:, None, 0] - v[None, :, 0]) ** 2 + (self.nodes[:, None, 1] - v[None, :, 1]) ** 2
        return d2.min(axis=1) >= d * d

    def nearest_ring(self, center, mask: np.ndarray, score: np.ndarray,
                     width: float) -> np.ndarray | None:
        """Among `mask` nodes within `width` cm of the nearest one to `center`, the one
        with the highest `score`; None if the mask is empty."""
        idx = np.flatnonzero(mask)
        if idx.size == 0:
            return None
        d = np.hypot(*(self.nodes[idx] - np.asarray(center, dtype=float)).T)
        ring = idx[d <= d.min() + width]
        return self.nodes[ring[np.argmax(score[ring])]].copy()
