"""The (x, y, θ) grid, the wall-distance raster of the domain and certified clearances.

The planner knows the domain through one raster: the signed distance ``D``
from each grid node to the nearest wall (positive in free space), taken from
the arena's own geometry (``Arena.wall_distance`` and ``Arena.contains``) or,
for rectangle bounds, from the distance to the four edges.  Since a distance
function is 1-Lipschitz, any point ``p`` of a cell satisfies

    d(p) >= L(p) = max over the cell's corners c of ( D(c) - |p - c| ),

a lower bound on its true wall distance that is never optimistic.  A point is
*certified* at clearance ``r`` when ``L(p) >= r``: it is then in free space at
least ``r`` from every wall, whatever the shape of the walls between nodes.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

from .errors import PlanningError
from .limits import check_grid, grid_shape


@dataclass(frozen=True)
class Grid:
    """Uniform grid: ``x_i = x0 + i*h``, ``y_j = y0 + j*h``, ``θ_k = 2πk/ntheta`` (length unit of the domain)."""

    x0: float
    y0: float
    h: float
    nx: int
    ny: int
    ntheta: int

    @property
    def dtheta(self) -> float:
        """Angular step ``2π/ntheta`` (radians)."""
        return 2.0 * np.pi / self.ntheta

    @property
    def x(self) -> np.ndarray:
        """Node abscissae (nx,)."""
        return self.x0 + self.h * np.arange(self.nx)

    @property
    def y(self) -> np.ndarray:
        """Node ordinates (ny,)."""
        return self.y0 + self.h * np.arange(self.ny)

    @property
    def theta(self) -> np.ndarray:
        """Grid headings (ntheta,), radians."""
        return self.dtheta * np.arange(self.ntheta)

    @property
    def x1(self) -> float:
        """Largest abscissa."""
        return self.x0 + self.h * (self.nx - 1)

    @property
    def y1(self) -> float:
        """Largest ordinate."""
        return self.y0 + self.h * (self.ny - 1)

    def nodes(self) -> np.ndarray:
        """Node positions (nx * ny, 2), x index first."""
        gx, gy = np.meshgrid(self.x, self.y, indexing="ij")
        return np.column_stack([gx.ravel(), gy.ravel()])


def is_arena(domain) -> bool:
    """Whether ``domain`` offers the arena geometry the planner uses (an ``arenas.Arena``)."""
    return all(hasattr(domain, name) for name in ("boundary", "obstacles", "contains", "wall_distance"))


def _rectangle(domain) -> tuple[float, float, float, float]:
    if hasattr(domain, "boundary"):
        raise PlanningError(
            f"domain {getattr(domain, 'name', domain)!r} has polygons but no contains/wall_distance methods; "
            "build it with arenas.Arena.from_polygons(boundary, obstacles)")
    try:
        (x0, x1), (y0, y1) = np.asarray(domain, dtype=float)
    except (TypeError, ValueError):
        raise PlanningError(
            f"domain must be an arenas.Arena or rectangle bounds ((x0, x1), (y0, y1)), got {domain!r}") from None
    if not (np.isfinite([x0, x1, y0, y1]).all() and x1 > x0 and y1 > y0):
        raise PlanningError(f"rectangle bounds need finite x0 < x1 and y0 < y1, got {domain!r}")
    return float(x0), float(x1), float(y0), float(y1)


def domain_geometry(domain) -> dict:
    """``name``, ``boundary`` and ``obstacles`` polygons of ``domain`` (for metadata, cache keys and plots).

    Raises
    ------
    PlanningError
        If ``domain`` is neither an arena nor valid rectangle bounds.
    """
    if is_arena(domain):
        return {"name": str(getattr(domain, "name", "arena")),
                "boundary": np.asarray(domain.boundary, dtype=float),
                "obstacles": [np.asarray(o, dtype=float) for o in domain.obstacles]}
    x0, x1, y0, y1 = _rectangle(domain)
    return {"name": f"rect[{x0:g},{x1:g}]x[{y0:g},{y1:g}]",
            "boundary": np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]]), "obstacles": []}


def make_grid(domain, h: float, ntheta: int, clearance: float) -> tuple[Grid, np.ndarray, np.ndarray]:
    """Grid, signed wall-distance raster ``D`` (nx, ny) and free-node mask (nx, ny) of ``domain``.

    ``domain`` is an ``arenas.Arena`` -- its ``contains`` and ``wall_distance``
    decide which nodes are free -- or rectangle bounds ``((x0, x1), (y0, y1))``
    whose edges are walls (nodes on them are free when ``clearance`` is 0).
    A node is free when it is in free space at least ``clearance`` from every
    wall.  ``D`` is negative at nodes outside the free space.

    Raises
    ------
    PlanningError
        On an invalid domain, or a grid too coarse or too large for it.
    """
    if is_arena(domain):
        (x0, y0), (x1, y1) = np.min(domain.boundary, axis=0), np.max(domain.boundary, axis=0)
    else:
        x0, x1, y0, y1 = _rectangle(domain)
    check_grid(1.0, h, int(ntheta), 0.0, (x1 - x0, y1 - y0))
    nx, ny = grid_shape((x1 - x0, y1 - y0), h)
    if nx < 4 or ny < 4:
        raise PlanningError(f"grid spacing h={h} is too coarse for a domain of size {x1 - x0:g} x {y1 - y0:g}")
    grid = Grid(float(x0), float(y0), float(h), nx, ny, int(ntheta))
    points = grid.nodes()
    if is_arena(domain):
        inside = np.asarray(domain.contains(points), dtype=bool)
        distance = np.where(inside, 1.0, -1.0) * np.asarray(domain.wall_distance(points), dtype=float)
        # free: inside, and at least `clearance` from every wall (the distance just measured)
        free = inside & (distance >= clearance) if clearance > 0 else inside
    else:
        distance = np.min([points[:, 0] - x0, x1 - points[:, 0], points[:, 1] - y0, y1 - points[:, 1]], axis=0)
        free = distance >= clearance
    return grid, distance.reshape(nx, ny), free.reshape(nx, ny)


@njit(cache=True, nogil=True, inline="always")
def lower_wall_bound(distance, x0, y0, h, x, y):
    """:func:`lower_wall_distance` of one point (x, y)."""
    nx, ny = distance.shape
    gx = (x - x0) / h
    gy = (y - y0) / h
    if not (gx >= -1e-9 and gx <= nx - 1 + 1e-9 and gy >= -1e-9 and gy <= ny - 1 + 1e-9):
        return -np.inf
    i = min(max(int(np.floor(gx)), 0), nx - 2)
    j = min(max(int(np.floor(gy)), 0), ny - 2)
    best = -np.inf
    for a in range(2):
        for b in range(2):
            bound = distance[i + a, j + b] - h * np.hypot(gx - i - a, gy - j - b)
            if bound > best:
                best = bound
    return best


@njit(cache=True, nogil=True)
def lower_wall_distance(distance, x0, y0, h, xs, ys):
    """Certified lower bound ``L(p)`` of the wall distance at each point (see the module notes).

    ``-inf`` outside the grid.
    """
    out = np.empty(xs.shape[0])
    for m in range(xs.shape[0]):
        out[m] = lower_wall_bound(distance, x0, y0, h, xs[m], ys[m])
    return out
