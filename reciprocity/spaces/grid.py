"""A regular grid of square cells as a search space (plume worlds, grid walkers)."""

from __future__ import annotations

import numpy as np

from .base import SearchSpace

__all__ = ["GridSpace"]


class GridSpace(SearchSpace):
    """Cell centres of a regular grid over a rectangle, optionally masked.

    Parameters
    ----------
    bounds : ((x0, x1), (y0, y1))
        The rectangle (the world's length unit).
    spacing : float
        Cell size.
    connectivity : {4, 8}
        Moves to the 4 edge neighbours, or also the 4 diagonal ones.
    mask : callable, optional
        ``mask(points) -> bool array``: cells whose centre is False are left out.

    Examples
    --------
    >>> g = GridSpace(((0, 3), (0, 2)), 1.0)
    >>> len(g), g.points[0].tolist()
    (6, [0.5, 0.5])
    >>> sorted(g.neighbours(0).tolist())
    [1, 3]
    """

    def __init__(self, bounds, spacing: float, connectivity: int = 4, mask=None):
        (x0, x1), (y0, y1) = bounds
        if not (np.isfinite(spacing) and spacing > 0):
            raise ValueError(f"grid spacing must be a positive number; got {spacing!r}")
        if connectivity not in (4, 8):
            raise ValueError(f"connectivity must be 4 or 8; got {connectivity!r}")
        self.bounds = ((float(x0), float(x1)), (float(y0), float(y1)))
        self.spacing = float(spacing)
        self.nx = max(1, int(round((x1 - x0) / spacing)))
        self.ny = max(1, int(round((y1 - y0) / spacing)))
        ix, iy = np.meshgrid(np.arange(self.nx), np.arange(self.ny))
        ix, iy = ix.ravel(), iy.ravel()
        pts = np.column_stack([x0 + (ix + 0.5) * spacing, y0 + (iy + 0.5) * spacing])
        keep = np.ones(len(pts), dtype=bool) if mask is None else np.asarray(mask(pts), dtype=bool)
        self.points = pts[keep]
        self._ij = np.column_stack([ix[keep], iy[keep]])
        self._index = -np.ones((self.ny, self.nx), dtype=int)
        self._index[self._ij[:, 1], self._ij[:, 0]] = np.arange(keep.sum())
        self.cell_areas = np.full(len(self.points), self.spacing ** 2)
        steps = [(1, 0), (-1, 0), (0, 1), (0, -1)]
        if connectivity == 8:
            steps += [(1, 1), (1, -1), (-1, 1), (-1, -1)]
        self._steps = np.array(steps)

    def index_of(self, points) -> np.ndarray:
        """Cell index of each point (m, 2); -1 outside the grid or masked."""
        p = np.atleast_2d(np.asarray(points, dtype=float))
        (x0, _), (y0, _) = self.bounds
        ix = np.floor((p[:, 0] - x0) / self.spacing).astype(int)
        iy = np.floor((p[:, 1] - y0) / self.spacing).astype(int)
        ok = (ix >= 0) & (ix < self.nx) & (iy >= 0) & (iy < self.ny)
        out = -np.ones(len(p), dtype=int)
        out[ok] = self._index[iy[ok], ix[ok]]
        return out

    def contains(self, points) -> np.ndarray:
        return self.index_of(points) >= 0

    def neighbours(self, i: int) -> np.ndarray:
        ij = self._ij[int(i)] + self._steps
        ok = (ij[:, 0] >= 0) & (ij[:, 0] < self.nx) & (ij[:, 1] >= 0) & (ij[:, 1] < self.ny)
        idx = self._index[ij[ok, 1], ij[ok, 0]]
        return idx[idx >= 0]

    def nearest(self, point) -> int:
        i = int(self.index_of(point)[0])
        return i if i >= 0 else super().nearest(point)
