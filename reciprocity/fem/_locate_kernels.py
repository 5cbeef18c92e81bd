"""The numba kernels of point location (:mod:`reciprocity.fem.locate`).

They live apart so that importing the FEM layer loads no numba; the locator imports this
module where a kernel first runs, and ``cache=True`` keeps the compiled code on disk
between processes.

The triangles are binned into a uniform grid of square cells by their bounding boxes
(:func:`bin_triangles`); a point is then tested against the triangles of its own cell only
(:func:`locate_in_cells`). A point is answered only when it lies inside one triangle by a
`margin` in every barycentric coordinate: no other triangle of a conforming mesh can then
hold it, so the answer is the one any exact test gives. Every other point (near an edge
or a vertex, outside the bins, or in no binned triangle) is left for the caller's exact
path.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["bin_triangles", "locate_in_cells"]


@njit(cache=True)
def bin_triangles(corners, x0, y0, size, nx, ny):  # pragma: no cover (compiled)
    """CSR lists of the triangles whose bounding box meets each cell.

    Parameters
    ----------
    corners : ndarray, shape (m, 3, 2)
        Triangle corners, cm.
    x0, y0, size : float
        Lower-left corner and side of the cells, cm.
    nx, ny : int
        Cells along x and y.

    Returns
    -------
    start : ndarray of int64, shape (nx * ny + 1,)
        Cell ``c = i * ny + j`` holds ``items[start[c]:start[c + 1]]``.
    items : ndarray of int64
        Triangle indices, in increasing order within each cell.
    """
    m = corners.shape[0]
    lo = np.empty((m, 2), np.int64)
    hi = np.empty((m, 2), np.int64)
    count = np.zeros(nx * ny + 1, np.int64)
    for t in range(m):
        xa = min(corners[t, 0, 0], corners[t, 1, 0], corners[t, 2, 0])
        xb = max(corners[t, 0, 0], corners[t, 1, 0], corners[t, 2, 0])
        ya = min(corners[t, 0, 1], corners[t, 1, 1], corners[t, 2, 1])
        yb = max(corners[t, 0, 1], corners[t, 1, 1], corners[t, 2, 1])
        lo[t, 0] = min(max(int(np.floor((xa - x0) / size)), 0), nx - 1)
        hi[t, 0] = min(max(int(np.floor((xb - x0) / size)), 0), nx - 1)
        lo[t, 1] = min(max(int(np.floor((ya - y0) / size)), 0), ny - 1)
        hi[t, 1] = min(max(int(np.floor((yb - y0) / size)), 0), ny - 1)
        for i in range(lo[t, 0], hi[t, 0] + 1):
            for j in range(lo[t, 1], hi[t, 1] + 1):
                count[i * ny + j + 1] += 1
    for c in range(nx * ny):
        count[c + 1] += count[c]
    items = np.empty(count[nx * ny], np.int64)
    fill = count[:-1].copy()
    for t in range(m):
        for i in range(lo[t, 0], hi[t, 0] + 1):
            for j in range(lo[t, 1], hi[t, 1] + 1):
                c = i * ny + j
                items[fill[c]] = t
                fill[c] += 1
    return count, items


@njit(cache=True)
def locate_in_cells(pts, inv, origin, start, items, x0, y0, size, nx, ny,
                    margin):  # pragma: no cover (compiled)
    """The triangle holding each point by `margin` in its barycentric coordinates, -1
    where no binned triangle does (the caller decides those).

    ``inv[t]`` maps ``p - origin[t]`` to the coordinates ``(l1, l2)`` of corners 1 and 2
    (:class:`reciprocity.fem.locate.TriangleLocator`); the point is taken when ``l1``,
    ``l2`` and ``1 - l1 - l2`` are all at least `margin`.
    """
    n = pts.shape[0]
    out = np.full(n, -1, np.int64)
    for k in range(n):
        px, py = pts[k, 0], pts[k, 1]
        fi = (px - x0) / size
        fj = (py - y0) / size
        if not (fi >= 0.0 and fi < nx and fj >= 0.0 and fj < ny):     # NaN fails too
            continue
        c = int(fi) * ny + int(fj)
        for q in range(start[c], start[c + 1]):
            t = items[q]
            dx, dy = px - origin[t, 0], py - origin[t, 1]
            l1 = inv[t, 0, 0] * dx + inv[t, 0, 1] * dy
            l2 = inv[t, 1, 0] * dx + inv[t, 1, 1] * dy
            if l1 >= margin and l2 >= margin and l1 + l2 <= 1.0 - margin:
                out[k] = t
                break
    return out
