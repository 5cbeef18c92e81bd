"""Point location on a triangle mesh: which triangle holds each point."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from matplotlib.tri import Triangulation

__all__ = ["TriangleLocator"]


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
        from scipy.spatial import cKDTree
        self.points, self.triangles = points, triangles
        self._triangulation: Triangulation | None = None
        self._finder = None
        # nearest triangle centroids, then barycentric coordinates
        corners = points[triangles]                                 # (m, 3, 2)
        self._centroid_tree = cKDTree(corners.mean(axis=1))
        e1, e2 = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
        det = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
        self._inv = np.stack([np.stack([e2[:, 1], -e2[:, 0]], 1), np.stack([-e1[:, 1], e1[:, 0]], 1)], 1) \
            / det[:, None, None]                                    # rows map p - c0 to (l1, l2)
        self._origin = corners[:, 0]
        # no triangle holds a point farther from every centroid than this
        self._reach = float(np.max(np.linalg.norm(corners - corners.mean(axis=1)[:, None], axis=2)))

    @property
    def triangulation(self) -> Triangulation:
        """The mesh as a matplotlib Triangulation (built once; point location, contours)."""
        if self._triangulation is None:
            # matplotlib is imported here, not at the top: locating points never needs it
            from matplotlib.tri import Triangulation
            self._triangulation = Triangulation(self.points[:, 0], self.points[:, 1], self.triangles)
        return self._triangulation

    def locate(self, points, k: int = 8) -> np.ndarray:
        """Index of the triangle holding each point (m, 2), -1 outside the mesh.

        The `k` triangles with the nearest centroids are tested by barycentric
        coordinates (a quality mesh holds the point in one of them); the rare rest go
        to matplotlib's trapezoid map, built on first need (it costs seconds on a
        30 000-triangle mesh, which start-up should not pay).
        """
        pts = np.atleast_2d(np.asarray(points, dtype=float))
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
