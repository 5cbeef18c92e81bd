"""Platforms: what moves to the observation points and measures the signal there."""

from __future__ import annotations

from abc import ABC, abstractmethod

import numpy as np
import shapely
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra
from scipy.spatial import cKDTree

from arenas import Arena

from .errors import SearchError
from .green import Field, GreenSolver
from .strategies.base import Request

__all__ = ["Platform", "PointPlatform", "check_request"]


def check_request(arena: Arena, request: Request) -> np.ndarray:
    """The request's points as an (n, 2) array; SearchError if one is outside the free region."""
    pts = np.atleast_2d(np.asarray(request.points, dtype=float))
    inside = arena.contains(pts)
    if not inside.all():
        bad = pts[~inside][0]
        raise SearchError(f"requested point ({bad[0]:.4g}, {bad[1]:.4g}) cm is not in the "
                          "free region")
    return pts


class Platform(ABC):
    """Moves to requested points and returns noisy readings there.

    Attributes
    ----------
    pose : ndarray, shape (3,)
        Current pose (x, y cm; heading rad).
    path_length : float
        Distance travelled so far, cm.
    source : ndarray, shape (2,)
        The true source (known to the platform and the episode, never to a strategy).
    """

    pose: np.ndarray
    path_length: float
    source: np.ndarray
    #: The way travelled during the last :meth:`visit`, shape (n, 2), cm.
    last_route: list

    #: Name recorded in the episode summary.
    name: str = "platform"

    def reachable(self, points: np.ndarray) -> np.ndarray | None:
        """Mask of `points` (n, 2) the platform can reach from where it stands, or None
        when it can reach the whole free region (the episode then adds no restriction)."""
        return None

    def step_log(self) -> dict:
        """Platform-specific records of the last :meth:`visit` for the episode trace."""
        return {}

    def summary(self) -> dict:
        """Platform-specific keys for the episode summary (e.g. time driven, collisions)."""
        return {}

    @abstractmethod
    def reset(self, start: np.ndarray, rng: np.random.Generator) -> None:
        """Place the platform at `start` (x, y[, heading])."""

    @abstractmethod
    def visit(self, request: Request) -> tuple[np.ndarray, np.ndarray]:
        """Go to each point of `request` in turn and measure: (points reached, readings)."""


class PointPlatform(Platform):
    """A point observer: moves instantly along the shortest free path, measures exactly
    where it is asked, with additive Gaussian noise ``N(0, noise^2)``.

    Parameters
    ----------
    solver : GreenSolver
        Solver for the true signal. Use a different mesh from the strategy's (the
        default in :func:`reciprocity.runner.make_platform`) to avoid an inverse crime.
    source : array_like, shape (2,)
        True source, cm.
    strength : float
        True strength ``c``.
    noise : float
        Noise standard deviation, signal units.

    Notes
    -----
    The distance moved is the straight segment when it stays in the free region, else
    the shortest path along the edges of the solver's mesh (an upper bound on the true
    geodesic, within a few per cent on a quality mesh).
    """

    name = "point"

    def __init__(self, solver: GreenSolver, source, strength: float, noise: float = 12.0):
        if not np.isfinite(noise) or noise < 0:
            raise SearchError(f"noise must be a non-negative number; got {noise!r}")
        self.arena: Arena = solver.arena
        self.source = np.asarray(source, dtype=float)
        self.field: Field = solver.field(self.source, strength)
        self.noise = float(noise)
        nodes, t = solver.nodes, solver.triangles
        i = np.concatenate([t[:, 0], t[:, 1], t[:, 2]])
        j = np.concatenate([t[:, 1], t[:, 2], t[:, 0]])
        w = np.hypot(*(nodes[i] - nodes[j]).T)
        self._graph = coo_matrix((w, (i, j)), shape=(len(nodes),) * 2).tocsr()
        self._tree = cKDTree(nodes)
        self._nodes = nodes

    def reset(self, start, rng: np.random.Generator) -> None:
        s = np.asarray(start, dtype=float).ravel()
        self.pose = np.array([s[0], s[1], s[2] if len(s) > 2 else 0.0])
        self.path_length = 0.0
        self.last_route = [self.pose[:2].copy()]
        self.rng = rng

    def route(self, a, b) -> np.ndarray:
        """A free path from `a` to `b`: the segment if it is free, else the shortest path
        along mesh edges; shape (n, 2), cm."""
        a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
        if self.arena.free_region.covers(shapely.LineString([a, b])):
            return np.array([a, b])
        ia, ib = self._tree.query([a, b])[1]
        _, pred = dijkstra(self._graph, directed=False, indices=ia, return_predecessors=True)
        chain = [ib]
        while chain[-1] != ia and pred[chain[-1]] >= 0:
            chain.append(pred[chain[-1]])
        return np.vstack([a, self._nodes[chain[::-1]], b])

    def distance(self, a, b) -> float:
        """Free-path distance (cm) between points `a` and `b` (length of :meth:`route`)."""
        return float(np.sum(np.hypot(*np.diff(self.route(a, b), axis=0).T)))

    def visit(self, request: Request) -> tuple[np.ndarray, np.ndarray]:
        pts = check_request(self.arena, request)
        readings = np.empty(len(pts))
        self.last_route = [self.pose[:2].copy()]
        for k, p in enumerate(pts):
            step = p - self.pose[:2]
            leg = self.route(self.pose[:2], p)
            self.last_route.extend(leg[1:])
            self.path_length += float(np.sum(np.hypot(*np.diff(leg, axis=0).T)))
            heading = np.arctan2(step[1], step[0]) if np.hypot(*step) > 0 else self.pose[2]
            self.pose = np.array([p[0], p[1], heading % (2 * np.pi)])
            readings[k] = self.field(p[None])[0] + self.noise * self.rng.standard_normal()
        return pts, readings
