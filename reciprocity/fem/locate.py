"""Point location on a triangle mesh: which triangle holds each point."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from matplotlib.tri import Triangulation

__all__ = ["BINNED_MIN_POINTS", "MARGIN", "TriangleLocator"]

#: How far inside a triangle (in each barycentric coordinate) a point must be for the
#: compiled pass to answer it; the rest take the exact path (1000 times its tolerance).
MARGIN = 1e-9

#: Fewer points than this go straight to the nearest-centroid path (the same answers): a
#: point run locates a few dozen points, and should not load numba for them.
BINNED_MIN_POINTS = 2048


class TriangleLocator:
    """Finds the triangle of a mesh that holds each query point.

    Parameters
    ----------
    points : ndarray, shape (n, 2)
        Mesh vertices, cm.
    triangles : ndarray, shape (m, 3)
        Triangles as vertex indices.
    """

    def __init__(self, points: np.ndarray, triangles: np.ndarray):
        self.points, self.triangles = points, triangles
        self._triangulation: Triangulation | None = None
        self._finder = None
        self._tree = None
        # the bins, then nearest triangle centroids, then barycentric coordinates
        corners = points[triangles]                                 # (m, 3, 2)
        e1, e2 = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
        det = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
        self._inv = np.stack([np.stack([e2[:, 1], -e2[:, 0]], 1), np.stack([-e1[:, 1], e1[:, 0]], 1)], 1) \
            / det[:, None, None]                                    # rows map p - c0 to (l1, l2)
        self._origin = corners[:, 0]
        # no triangle holds a point farther from every centroid than this
        self._reach = float(np.max(np.linalg.norm(corners - corners.mean(axis=1)[:, None], axis=2)))
        self._corners = corners
        self._bins = None

    @property
    def triangulation(self) -> Triangulation:
        """The mesh as a matplotlib Triangulation (built once; point location, contours)."""
        if self._triangulation is None:
            # matplotlib is imported here, not at the top: locating points never needs it
            from matplotlib.tri import Triangulation
            self._triangulation = Triangulation(self.points[:, 0], self.points[:, 1], self.triangles)
        return self._triangulation

    @property
    def _centroid_tree(self):
        """A k-d tree of the triangle centroids (built on first need)."""
        if self._tree is None:
            from scipy.spatial import cKDTree
            self._tree = cKDTree(self._corners.mean(axis=1))
        return self._tree

    def _binned(self) -> tuple:
        """The triangles binned in square cells about a triangle's size (built once)."""
        if self._bins is None:
            from ._locate_kernels import bin_triangles
            lo, hi = self.points.min(axis=0), self.points.max(axis=0)
            extent = np.maximum(hi - lo, 1e-300)
            m = len(self.triangles)
            # cells of twice a mean triangle's area were the mesh to fill its box (fewer
            # cells than triangles), and never more than 4 per triangle along a side
            size = max(float(np.sqrt(2.0 * extent[0] * extent[1] / m)), float(extent.max()) / (4.0 * m))
            nx, ny = (int(v) for v in np.floor(extent / size) + 1)
            start, items = bin_triangles(np.ascontiguousarray(self._corners, dtype=float),
                                         float(lo[0]), float(lo[1]), size, nx, ny)
            self._bins = (start, items, float(lo[0]), float(lo[1]), size, nx, ny,
                          np.ascontiguousarray(self._inv), np.ascontiguousarray(self._origin))
        return self._bins

    def locate(self, points, k: int = 8) -> np.ndarray:
        """Index of the triangle holding each point (m, 2), -1 outside the mesh.

        From :data:`BINNED_MIN_POINTS` points on, a compiled pass over the triangles binned
        around each point (:mod:`reciprocity.fem._locate_kernels`) answers every point that
        lies inside a triangle by :data:`MARGIN` in its barycentric coordinates: no other
        triangle can hold it, so the answer is the exact one. The rest (near an edge or a
        vertex, or outside the mesh) are tested against the `k` triangles with the nearest
        centroids by barycentric coordinates (a quality mesh holds the point in one of
        them, the first that does is taken), and the rare rest go to matplotlib's
        trapezoid map, built on first need (it costs seconds on a 30 000-triangle mesh,
        which start-up should not pay).
        """
        pts = np.atleast_2d(np.asarray(points, dtype=float))
        if len(pts) < BINNED_MIN_POINTS:
            return self._locate_nearest(pts, k)
        from ._locate_kernels import locate_in_cells
        start, items, x0, y0, size, nx, ny, inv, origin = self._binned()
        out = locate_in_cells(np.ascontiguousarray(pts), inv, origin, start, items, x0, y0, size,
                              nx, ny, MARGIN)
        rest = np.flatnonzero(out < 0)
        if rest.size:
            out[rest] = self._locate_nearest(pts[rest], k)
        return out

    def _locate_nearest(self, pts: np.ndarray, k: int) -> np.ndarray:
        """:meth:`locate` by the `k` nearest centroids, then the trapezoid map."""
        out = -np.ones(len(pts), dtype=np.int64)
        if not len(pts):
            return out
        k = min(k, len(self.triangles))
        dist, cand = self._centroid_tree.query(pts, k=k)
        cand, dist = cand.reshape(len(pts), k), dist.reshape(len(pts), k)
        lam = np.einsum("mkij,mkj->mki", self._inv[cand], pts[:, None, :] - self._origin[cand])
        tol = -1e-12
        inside = (lam[..., 0] >= tol) & (lam[..., 1] >= tol) & (lam.sum(axis=2) <= 1 - tol)
        found = inside.any(axis=1)
        out[found] = cand[found, np.argmax(inside[found], axis=1)]
        rest = np.flatnonzero(~found & (dist[:, 0] <= self._reach))
        if rest.size:
            if self._finder is None:
                self._finder = self.triangulation.get_trifinder()
            out[rest] = self._finder(pts[rest, 0], pts[rest, 1])
        return out
