"""Gradients of P1 fields on a triangle mesh: how fast a nodal field changes around each node.

A P1 field is linear on each triangle, so its gradient is one vector per triangle. A node
stands for the points around it (its lumped area, a third of each adjacent triangle); the
mean square gradient over those triangles, area-weighted, says how much the field varies
over the points the node stands for. Near a point load the gradients of the triangles
around the load point opposite ways: averaging the vectors would cancel them, averaging
their squares does not.
"""

from __future__ import annotations

import weakref

import numpy as np
from scipy import sparse

__all__ = ["NodalSlope", "nodal_slope"]

_KEPT: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def nodal_slope(solver) -> "NodalSlope":
    """The :class:`NodalSlope` of a :class:`~reciprocity.fem.GreenSolver`'s P1 mesh, built
    once per solver and kept while the solver lives (every search on it shares it)."""
    out = _KEPT.get(solver)
    if out is None:
        out = _KEPT[solver] = NodalSlope(solver.nodes, solver.triangles)
    return out


class NodalSlope:
    """The root-mean-square gradient of P1 fields around each node of a mesh.

    Parameters
    ----------
    points : ndarray, shape (n, 2)
        Nodes, cm.
    triangles : ndarray of int, shape (m, 3)
        Triangles (node indices).

    Examples
    --------
    >>> import numpy as np
    >>> pts = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]])
    >>> slope = NodalSlope(pts, np.array([[0, 1, 2], [1, 3, 2]]))
    >>> slope(3.0 * pts[:, :1] - 4.0 * pts[:, 1:])      # |(3, -4)| = 5 everywhere
    array([[5.],
           [5.],
           [5.],
           [5.]])
    """

    def __init__(self, points: np.ndarray, triangles: np.ndarray):
        points = np.asarray(points, dtype=float)
        tri = np.asarray(triangles, dtype=np.int64)
        p = points[tri]                                           # (m, 3, 2)
        e1, e2 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
        det = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]          # twice the signed area
        # gradients of the three hat functions: rotate the opposite edge by 90 degrees
        opposite = np.stack([p[:, 2] - p[:, 1], p[:, 0] - p[:, 2], p[:, 1] - p[:, 0]], axis=1)
        gx = -opposite[:, :, 1] / det[:, None]
        gy = opposite[:, :, 0] / det[:, None]
        m, n = len(tri), len(points)
        rows = np.repeat(np.arange(m), 3)
        self._dx = sparse.csr_matrix((gx.ravel(), (rows, tri.ravel())), shape=(m, n))
        self._dy = sparse.csr_matrix((gy.ravel(), (rows, tri.ravel())), shape=(m, n))
        area = 0.5 * np.abs(det)
        w = np.repeat(area / 3.0, 3)
        lumped = np.bincount(tri.ravel(), w, n)
        self._mean = sparse.csr_matrix((w / lumped[tri.ravel()], (tri.ravel(), rows)), shape=(n, m))
        #: Lumped area of each node (a third of each adjacent triangle), cm².
        self.node_areas = lumped

    def __call__(self, values: np.ndarray) -> np.ndarray:
        """The RMS gradient around each node of the fields whose nodal values are the
        columns of `values` (n, k), in their units per cm, shape (n, k)."""
        v = np.asarray(values, dtype=float)
        flat = v.reshape(len(v), -1)
        sq = np.asarray(self._dx @ flat) ** 2 + np.asarray(self._dy @ flat) ** 2
        return np.sqrt(np.asarray(self._mean @ sq)).reshape(v.shape)
