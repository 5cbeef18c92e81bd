"""Where a car that can reverse can go, without solving for a value function.

A car that drives forwards and backwards with bounded curvature (Reeds and Shepp's car) is
small-time locally controllable: in an open, connected set of free configurations it can
drive from any pose to any other (Laumond et al., "A motion planner for nonholonomic mobile
robots", IEEE T-RA 10(5), 1994). The planner's free configurations are the points at least
the clearance from every wall, at every heading. So the points such a car can reach are the
connected part of that shrunk free region which holds its own position: a flood fill, where
:class:`hjplanner.OnDemandPlanner` would solve a value function over the whole map.

On the planner's grid the flood runs over the free nodes (:func:`hjplanner._grid.make_grid`,
the same nodes the solver treats as free) with 4-neighbours: two free nodes that meet only at
a corner leave the car no room to pass. A point counts as reachable when the four nodes
around it are, as the value function's linear interpolation needs them all finite.

The flood answers for the car of the continuous problem. The solver's car is a
discretisation of it, whose arcs must stay certified at the clearance all along: it cannot
thread a gap whose free nodes form a one-node path, nor use every node at the band's edge.
So the flood's region can be larger than the solver's: ``benchmarks/reach_certify.py``
counts where the two differ, both ways. Where they differ, the value function's answer is
the one the car can drive.

A car that cannot reverse (Dubins') is not locally controllable, and the flood fill would
overstate what it reaches: :class:`ReachableRegion` is for the reversing car only.
:meth:`hjplanner.OnDemandPlanner.reachable_from` labels its own grid's free nodes once.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike
from scipy import ndimage

from ._grid import make_grid
from .errors import PlanningError

__all__ = ["FreeComponents", "ReachableRegion"]

#: Headings of the grid the flood fill asks :func:`make_grid` for (the free nodes do not
#: depend on them; the grid needs some).
_NTHETA = 8


class FreeComponents:
    """The connected parts of a grid's free nodes (4-neighbours), labelled once: every
    start then costs a look-up (:meth:`region`).

    Parameters
    ----------
    grid : Grid
        The planner's grid.
    free : numpy.ndarray, shape (nx, ny)
        Its free nodes (at least the clearance from every wall).
    """

    def __init__(self, grid, free: np.ndarray):
        self.grid = grid
        self.free = np.asarray(free, dtype=bool)
        self.labels, self.count = ndimage.label(self.free)     # scipy's default: 4-neighbours

    @classmethod
    def of(cls, domain, *, h: float, clearance: float) -> "FreeComponents":
        """The free components of `domain` (an ``arenas.Arena`` or rectangle bounds) on the
        grid of spacing `h` (cm) at `clearance` (cm), as the planner builds it."""
        grid, _, free = make_grid(domain, float(h), _NTHETA, float(clearance))
        return cls(grid, free)

    def region(self, start: ArrayLike) -> "ReachableRegion":
        """The :class:`ReachableRegion` of a car at `start` (x, y), cm. When its own node is
        not free (inside the clearance band), the nearest free node within two grid
        spacings stands for it; PlanningError when there is none."""
        p = np.asarray(start, dtype=float).ravel()
        if p.shape != (2,) or not np.all(np.isfinite(p)):
            raise PlanningError(f"start must be two finite numbers (x, y); got {start!r}")
        g = self.grid
        i, j = np.rint((p - (g.x0, g.y0)) / g.h).astype(int)
        near = [(a, b) for a in range(i - 2, i + 3) for b in range(j - 2, j + 3)
                if 0 <= a < g.nx and 0 <= b < g.ny and self.free[a, b]]
        if not near:
            raise PlanningError(f"no free node within {2 * g.h:g} of start ({p[0]:g}, {p[1]:g})")
        a, b = min(near, key=lambda n: (n[0] - i) ** 2 + (n[1] - j) ** 2)
        return ReachableRegion(g, self.labels == self.labels[a, b])


class ReachableRegion:
    """The points a reversing car reaches from its start, keeping its clearance (made by
    :meth:`FreeComponents.region`).

    Parameters
    ----------
    grid : Grid
        The planner's grid.
    nodes : numpy.ndarray, shape (nx, ny)
        The free nodes of the connected part that holds the start.

    Examples
    --------
    >>> import arenas
    >>> paper = arenas.load("paper")
    >>> region = FreeComponents.of(paper, h=1.5, clearance=4.0).region(paper.start[:2])
    >>> region([paper.start[:2], [2.0, 2.0]]).tolist()
    [True, False]
    """

    def __init__(self, grid, nodes: np.ndarray):
        self.grid = grid
        self.nodes = np.asarray(nodes, dtype=bool)

    def __call__(self, points: ArrayLike) -> np.ndarray:
        """Mask of `points` (n, 2), cm, that the car reaches: the four grid nodes around
        each are in the region (points off the grid: False)."""
        pts = np.asarray(points, dtype=float).reshape(-1, 2)
        g = self.grid
        i0 = np.floor((pts[:, 0] - g.x0) / g.h).astype(int)
        j0 = np.floor((pts[:, 1] - g.y0) / g.h).astype(int)
        on = (i0 >= 0) & (j0 >= 0) & (i0 + 1 < g.nx) & (j0 + 1 < g.ny)
        out = np.zeros(len(pts), dtype=bool)
        a, b, n = i0[on], j0[on], self.nodes
        out[on] = n[a, b] & n[a + 1, b] & n[a, b + 1] & n[a + 1, b + 1]
        return out
