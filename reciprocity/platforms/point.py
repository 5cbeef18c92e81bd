"""The point observer: moves instantly along the shortest free path and reads exactly
where it is asked."""

from __future__ import annotations

import numpy as np
import shapely
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra
from scipy.spatial import cKDTree

from ..errors import SearchError, UnreachableTarget
from ..intents import Intent, Measure, Move, SampleGradient, Stay, StepToward, Survey
from ..observations import Observation
from ..worlds.base import World
from .base import Platform
from .lidar import Lidar

__all__ = ["PointPlatform", "gradient_sample_points"]


def gradient_sample_points(position, heading: float, offset: float, contains) -> np.ndarray:
    """The two extra samples of a three-point gradient (line 13 of Algorithm 2): a short
    step back, then forward and to the side, `offset` away; rotated by quarter turns
    until both are free (``contains(points) -> mask``), else shrunk. Shape (2, 2)."""
    e = np.array([np.cos(heading), np.sin(heading)])
    n = np.array([-e[1], e[0]])
    p = np.asarray(position, dtype=float)
    for turn in (0.0, np.pi / 2, np.pi, 3 * np.pi / 2):
        rot = np.array([[np.cos(turn), -np.sin(turn)], [np.sin(turn), np.cos(turn)]])
        pts = p + offset * np.array([rot @ -e, rot @ (e + n) / np.sqrt(2)])
        if contains(pts).all():
            return pts
    return p + offset * np.array([-e, (e + n) / np.sqrt(2)]) * 0.3


class PointPlatform(Platform):
    """A point observer: moves instantly along the shortest free path and reads the
    world's sensor exactly where it is asked.

    Parameters
    ----------
    space : reciprocity.spaces.MeshSpace
        A mesh of the *true* free region, for routes (its edges carry the shortest paths).
    dwell : float
        Duration of one reading, s (the clock advances by it per reading).
    lidar : Lidar, optional
        A range sensor read at every stop on the world's true walls: each intent's
        observations then end with one ``"scan"`` observation per stop, after the signal
        readings (instantaneous: the clock does not advance). None: no scans, nothing
        else changes.

    Notes
    -----
    The distance moved is the straight segment when it stays in the free region, else
    the shortest path along the edges of the mesh (an upper bound on the geodesic,
    within a few per cent on a quality mesh).
    """

    name = "point"
    intents = (Measure, SampleGradient, StepToward, Move, Stay, Survey)

    def __init__(self, space, dwell: float = 1.0, lidar: Lidar | None = None):
        super().__init__()
        self.lidar = lidar
        if not np.isfinite(dwell) or dwell < 0:
            raise SearchError(f"dwell must be a non-negative number of seconds; got {dwell!r}")
        self.space, self.dwell = space, float(dwell)
        self.arena = space.arena
        i, j = space.edges
        w = np.hypot(*(space.points[i] - space.points[j]).T)
        self._graph = coo_matrix((w, (i, j)), shape=(len(space.points),) * 2).tocsr()
        self._tree = cKDTree(space.points)

    def reset(self, start, world: World, rng: np.random.Generator) -> None:
        s = np.asarray(start, dtype=float).ravel()
        self.world, self.rng = world, rng
        self.pose = np.array([s[0], s[1], s[2] if len(s) > 2 else 0.0])
        self.path_length, self.time = 0.0, 0.0
        self.last_route = [self.pose[:2].copy()]

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
        if chain[-1] != ia:
            raise UnreachableTarget(b, f"({b[0]:.1f}, {b[1]:.1f}) is not connected to the observer")
        return np.vstack([a, self.space.points[chain[::-1]], b])

    def distance(self, a, b) -> float:
        """Free-path distance (cm) between points `a` and `b` (length of :meth:`route`)."""
        return float(np.sum(np.hypot(*np.diff(self.route(a, b), axis=0).T)))

    def _go(self, p: np.ndarray) -> None:
        if not self.world.contains(p[None])[0]:
            raise UnreachableTarget(p, f"({p[0]:.4g}, {p[1]:.4g}) is not in the free region")
        step = p - self.pose[:2]
        leg = self.route(self.pose[:2], p)
        self.last_route.extend(leg[1:])
        self.path_length += float(np.sum(np.hypot(*np.diff(leg, axis=0).T)))
        heading = np.arctan2(step[1], step[0]) if np.hypot(*step) > 0 else self.pose[2]
        self.pose = np.array([p[0], p[1], heading % (2 * np.pi)])

    def _read(self, kind: str) -> Observation:
        r = self.world.read(self.pose[:2], time=self.time, dwell=self.dwell, rng=self.rng, observer=self.agent)
        obs = Observation(self.pose[:2].copy(), r.value, self.time, self.dwell, r.kind if kind == "signal"
                          else kind, r.saturated, self.agent, r.data)
        self.time += self.dwell
        return obs

    def _scan(self) -> Observation:
        """A range scan of the true walls from the true pose (kind ``"scan"``)."""
        scan = self.lidar.scan(self.world.true_arena, self.pose, self.rng)
        return Observation(self.pose[:2].copy(), float(scan.ranges.min()), self.time, 0.0, "scan",
                           agent=self.agent, data=scan.as_data())

    def _execute(self, intent: Intent) -> list[Observation]:
        self.last_route = [self.pose[:2].copy()]
        out, scans = [], []
        if isinstance(intent, SampleGradient):
            here = self.pose.copy()
            pts = gradient_sample_points(here[:2], here[2], intent.offset, self.world.contains)
            for p in pts:
                self._go(p)
                out.append(self._read("gradient"))
                scans += [self._scan()] if self.lidar is not None else []
            return out + scans
        if isinstance(intent, Survey):
            if self.lidar is None:
                raise SearchError("a Survey needs a range sensor: this point observer has no lidar")
            self._go(intent.point)
            return [self._scan()]
        if not isinstance(intent, Stay):
            self._go(intent.point)
        out.append(self._read("signal"))
        return out + ([self._scan()] if self.lidar is not None else [])
