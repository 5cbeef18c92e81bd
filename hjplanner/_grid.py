"""The (x, y, θ) grid and the rasterisation of free space."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from matplotlib.path import Path as MplPath

from .errors import PlanningError


@dataclass(frozen=True)
class Grid:
    """Uniform grid: ``x_i = x0 + i*h``, ``y_j = y0 + j*h``, ``θ_k = 2πk/ntheta``."""

    x0: float
    y0: float
    h: float
    nx: int
    ny: int
    ntheta: int

    @property
    def dtheta(self) -> float:
        return 2.0 * np.pi / self.ntheta

    @property
    def x(self) -> np.ndarray:
        return self.x0 + self.h * np.arange(self.nx)

    @property
    def y(self) -> np.ndarray:
        return self.y0 + self.h * np.arange(self.ny)

    @property
    def theta(self) -> np.ndarray:
        return self.dtheta * np.arange(self.ntheta)

    @property
    def x1(self) -> float:
        return self.x0 + self.h * (self.nx - 1)

    @property
    def y1(self) -> float:
        return self.y0 + self.h * (self.ny - 1)


def _segments(polygon: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    polygon = np.asarray(polygon, dtype=float)
    return polygon, np.roll(polygon, -1, axis=0)


def distance_to_polygon_edges(points: np.ndarray, polygon: np.ndarray) -> np.ndarray:
    """Euclidean distance from each of ``points`` (n, 2) to the edges of ``polygon`` (m, 2)."""
    a, b = _segments(polygon)
    out = np.full(len(points), np.inf)
    for pa, pb in zip(a, b):
        ab = pb - pa
        denom = float(ab @ ab)
        ap = points - pa
        t = np.clip(ap @ ab / denom, 0.0, 1.0) if denom > 0 else np.zeros(len(points))
        out = np.minimum(out, np.hypot(ap[:, 0] - t * ab[0], ap[:, 1] - t * ab[1]))
    return out


def check_polygon(polygon, what: str) -> np.ndarray:
    polygon = np.asarray(polygon, dtype=float)
    if polygon.ndim != 2 or polygon.shape[1] != 2 or len(polygon) < 3 or not np.all(np.isfinite(polygon)):
        raise PlanningError(f"{what} must be an (n, 2) array of finite vertices with n >= 3, got shape {polygon.shape}")
    return polygon


def free_space(points: np.ndarray, boundary, obstacles, clearance: float) -> np.ndarray:
    """Mask of ``points`` inside ``boundary``, outside ``obstacles``, at least ``clearance`` from every edge."""
    free = MplPath(boundary).contains_points(points)
    for obstacle in obstacles:
        free &= ~MplPath(obstacle).contains_points(points)
    if clearance > 0:
        for polygon in [boundary, *obstacles]:
            free &= distance_to_polygon_edges(points, polygon) >= clearance
    return free


def make_grid(domain, h: float, ntheta: int, clearance: float) -> tuple[Grid, np.ndarray, str, dict]:
    """Grid, free-node mask (nx, ny) and a description of ``domain``.

    ``domain`` is rectangle bounds ``((x0, x1), (y0, y1))`` or an object with
    ``boundary``, ``obstacles`` and ``name`` attributes (an ``arenas.Arena``).
    """
    if hasattr(domain, "boundary"):
        boundary = check_polygon(domain.boundary, "arena boundary")
        obstacles = [check_polygon(o, "arena obstacle") for o in getattr(domain, "obstacles", [])]
        name = str(getattr(domain, "name", "arena"))
        (x0, y0), (x1, y1) = boundary.min(axis=0), boundary.max(axis=0)
    else:
        try:
            (x0, x1), (y0, y1) = np.asarray(domain, dtype=float)
        except (TypeError, ValueError):
            raise PlanningError(
                f"domain must be an Arena or rectangle bounds ((x0, x1), (y0, y1)), got {domain!r}") from None
        if not (np.isfinite([x0, x1, y0, y1]).all() and x1 > x0 and y1 > y0):
            raise PlanningError(f"rectangle bounds need finite x0 < x1 and y0 < y1, got {domain!r}")
        boundary = np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]])
        obstacles = []
        name = f"rect[{x0:g},{x1:g}]x[{y0:g},{y1:g}]"
    nx = int(np.floor((x1 - x0) / h + 1e-9)) + 1
    ny = int(np.floor((y1 - y0) / h + 1e-9)) + 1
    if nx < 4 or ny < 4:
        raise PlanningError(f"grid spacing h={h} is too coarse for a domain of size {x1 - x0:g} x {y1 - y0:g}")
    if nx * ny * ntheta > 200_000_000:
        raise PlanningError(f"grid of {nx} x {ny} x {ntheta} nodes is too large; increase h or reduce ntheta")
    grid = Grid(float(x0), float(y0), float(h), nx, ny, int(ntheta))
    gx, gy = np.meshgrid(grid.x, grid.y, indexing="ij")
    points = np.column_stack([gx.ravel(), gy.ravel()])
    if hasattr(domain, "boundary"):
        free = free_space(points, boundary, obstacles, clearance).reshape(nx, ny)
    else:
        # The rectangle's own edges are walls too; nodes on them are free.
        free = np.ones((nx, ny), dtype=bool)
        if clearance > 0:
            free &= (gx - x0 >= clearance) & (x1 - gx >= clearance) & (gy - y0 >= clearance) & (y1 - gy >= clearance)
    geometry = {"boundary": boundary, "obstacles": obstacles, "name": name}
    return grid, free, name, geometry
