"""The FEM mesh of an arena's free region as a search space (meshing without solving).

A strategy that needs candidate points, neighbours, reachability or nodal areas builds a
:class:`MeshSpace`; only one that solves for Green's functions also builds a
:class:`~reciprocity.fem.green.GreenSolver` on the *same* mesh (``GreenSolver(arena, h,
mesh=space)``), so one triangulation serves both.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from scipy.sparse import coo_matrix

from arenas import Arena
from arenas.memo import sized_cache

from ..fem.locate import TriangleLocator
from ..fem.mesh import cached_mesh, node_areas
from .base import SearchSpace

if TYPE_CHECKING:
    from matplotlib.tri import Triangulation

__all__ = ["MeshSpace", "mesh_space"]


class MeshSpace(SearchSpace):
    """Nodes of a triangle mesh of the free region, usable as candidate sources and
    observation points.

    Parameters
    ----------
    arena : Arena
        The arena (its geometry only is used), cm.
    h : float
        Mesh size, cm (see :func:`reciprocity.fem.mesh.mesh_free_region`).
    grading : float
        Grading exponent toward re-entrant corners.

    Attributes
    ----------
    points : ndarray, shape (n, 2)
        Mesh vertices, cm.
    triangles : ndarray, shape (m, 3)
        Triangles as vertex indices.
    cell_areas : ndarray, shape (n,)
        Lumped nodal areas (a third of each adjacent triangle), cm².
    wall_distance : ndarray, shape (n,)
        Distance of each node to the nearest wall, cm.
    edges : tuple of ndarray
        ``(i, j)``: the triangles' directed edges as node index pairs (each interior
        edge appears twice, once per direction).
    mesh : skfem.MeshTri, optional
        An existing mesh of the arena to wrap instead of meshing (keyword only).
    """

    def __init__(self, arena: Arena, h: float = 1.0, grading: float | None = 0.5, *, mesh=None):
        self.arena, self.h = arena, float(h)
        self.mesh = mesh if mesh is not None else cached_mesh(arena, self.h, grading=grading)
        self.points = self.mesh.p.T
        self.triangles = self.mesh.t.T
        self.cell_areas = node_areas(self.points, self.triangles)
        t = self.triangles
        self.edges = (np.concatenate([t[:, 0], t[:, 1], t[:, 2]]),
                       np.concatenate([t[:, 1], t[:, 2], t[:, 0]]))
        self._labels: dict[float, np.ndarray] = {}
        self._wall_distance = None
        self._adjacency = None
        self._edge_graph = None
        #: Point location on the mesh (shared with the FEM solver built on it).
        self.locator = TriangleLocator(self.points, self.triangles)

    @property
    def wall_distance(self) -> np.ndarray:
        """Distance of each node to the nearest wall, cm (computed once, on first use)."""
        if self._wall_distance is None:
            self._wall_distance = self.arena.wall_distance(self.points)
        return self._wall_distance

    @property
    def nodes(self) -> np.ndarray:
        """Alias of :attr:`points` (mesh nodes, cm)."""
        return self.points

    @property
    def triangulation(self) -> Triangulation:
        """The mesh as a matplotlib Triangulation (built once; point location, contours)."""
        return self.locator.triangulation

    # -- SearchSpace --------------------------------------------------------------------
    def contains(self, points) -> np.ndarray:
        return self.arena.contains(np.atleast_2d(np.asarray(points, dtype=float)))

    def neighbours(self, i: int) -> np.ndarray:
        if self._adjacency is None:
            i_, j_ = self.edges
            n = len(self.points)
            a = coo_matrix((np.ones(i_.size), (i_, j_)), shape=(n, n)).tocsr()
            self._adjacency = ((a + a.T) > 0).tocsr()
        return self._adjacency[int(i)].indices.copy()

    def locate(self, points, k: int = 8) -> np.ndarray:
        """Index of the triangle holding each point (m, 2), -1 outside the mesh
        (see :meth:`reciprocity.fem.locate.TriangleLocator.locate`)."""
        return self.locator.locate(points, k)

    # -- candidates ---------------------------------------------------------------------
    def admissible(self, clearance: float = 0.0) -> np.ndarray:
        """Mask of nodes at least `clearance` cm from every wall."""
        return self.wall_distance >= float(clearance)

    def _components(self, clearance: float) -> np.ndarray:
        key = float(clearance)
        if key not in self._labels:
            ok = self.admissible(key)
            i, j = self.edges
            keep = ok[i] & ok[j]
            n = len(self.points)
            graph = coo_matrix((np.ones(keep.sum()), (i[keep], j[keep])), shape=(n, n))
            from scipy.sparse.csgraph import connected_components
            _, label = connected_components(graph, directed=False)
            label[~ok] = -1
            self._labels[key] = label
        return self._labels[key]

    def within_path(self, mask: np.ndarray, distance: float) -> np.ndarray:
        """Mask of nodes at most `distance` (cm) from a node of `mask` along the mesh's
        edges, i.e. through the free region, never through a wall.

        Parameters
        ----------
        mask : ndarray of bool, shape (n,)
            The starting nodes.
        distance : float
            Path length, cm.

        Returns
        -------
        ndarray of bool, shape (n,)
        """
        mask = np.asarray(mask, dtype=bool)
        if not mask.any():
            return np.zeros(len(self.points), dtype=bool)
        if self._edge_graph is None:
            i, j = self.edges
            w = np.hypot(*(self.points[i] - self.points[j]).T)
            n = len(self.points)
            self._edge_graph = coo_matrix((w, (i, j)), shape=(n, n)).tocsr()
        from scipy.sparse.csgraph import dijkstra
        d = dijkstra(self._edge_graph, directed=False, indices=np.flatnonzero(mask),
                     min_only=True, limit=float(distance))
        return np.isfinite(d)

    def reachable_from(self, point, clearance: float = 0.0) -> np.ndarray:
        """Mask of nodes at `clearance` from the walls in the connected part of that
        clearance-shrunk region nearest to `point` (a car cannot squeeze through a gap
        narrower than twice its clearance)."""
        label = self._components(clearance)
        ok = np.flatnonzero(label >= 0)
        if ok.size == 0:
            return np.zeros(len(self.points), dtype=bool)
        p = np.asarray(point, dtype=float)
        nearest = ok[np.argmin(np.sum((self.points[ok] - p) ** 2, axis=1))]
        return label == label[nearest]

    def nearest_in(self, point, mask: np.ndarray) -> np.ndarray | None:
        """The node of `mask` nearest to `point` (cm), or None if the mask is empty."""
        idx = np.flatnonzero(mask)
        if idx.size == 0:
            return None
        d = np.sum((self.points[idx] - np.asarray(point, dtype=float)) ** 2, axis=1)
        return self.points[idx[np.argmin(d)]].copy()

    def around(self, point, radius: float) -> np.ndarray:
        """Mask of nodes within `radius` (cm) of `point`."""
        return np.sum((self.points - np.asarray(point, dtype=float)) ** 2, axis=1) <= radius * radius

    def separated(self, visited, d: float) -> np.ndarray:
        """Mask of nodes at distance at least `d` (cm) from every visited point."""
        v = np.atleast_2d(np.asarray(visited, dtype=float))
        if v.size == 0:
            return np.ones(len(self.points), dtype=bool)
        d2 = (self.points[:, None, 0] - v[None, :, 0]) ** 2 + (self.points[:, None, 1] - v[None, :, 1]) ** 2
        return d2.min(axis=1) >= d * d

    def nearest_ring(self, center, mask: np.ndarray, score: np.ndarray,
                     width: float) -> np.ndarray | None:
        """Among `mask` nodes within `width` cm of the nearest one to `center`, the one
        with the highest `score`; None if the mask is empty."""
        idx = np.flatnonzero(mask)
        if idx.size == 0:
            return None
        d = np.hypot(*(self.points[idx] - np.asarray(center, dtype=float)).T)
        ring = idx[d <= d.min() + width]
        return self.points[ring[np.argmax(score[ring])]].copy()


#: Bytes of search spaces kept per process.
SPACE_CACHE_BYTES = 120 * 2**20


@sized_cache(SPACE_CACHE_BYTES, maxsize=16)
def mesh_space(arena: Arena, h: float) -> MeshSpace:
    """A :class:`MeshSpace` shared by every episode on the same arena geometry and `h`
    (pass ``arena.without_scenario()``, which is cached per arena)."""
    return MeshSpace(arena, float(h))
