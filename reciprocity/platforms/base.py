"""Platforms: what turns a strategy's intents into motion and readings.

A platform holds the world (the truth) and the observer's true pose; it moves as an
intent asks, in its own way, and returns :class:`~reciprocity.observations.Observation`
records made from what the world's sensor read. Three platforms exist: the point
observer (moves instantly along free paths), the walker (one move per time step, on a
lattice, a grid or the plane, and may slip) and the car (:mod:`reciprocity.car_platform`).
"""

from __future__ import annotations

from abc import ABC, abstractmethod

import numpy as np
import shapely
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra
from scipy.spatial import cKDTree

from .errors import SearchError, UnreachableTarget
from .intents import Intent, Measure, Move, SampleGradient, Stay, StepToward
from .observations import Observation
from .worlds.base import World

__all__ = ["Platform", "PointPlatform", "WalkerPlatform", "gradient_sample_points"]


class Platform(ABC):
    """Moves as intents ask and returns observations.

    Attributes
    ----------
    pose : ndarray, shape (3,)
        Current pose as the platform reports it (x, y; heading rad).
    path_length : float
        Distance travelled so far.
    time : float
        The platform's clock (s, or steps in time-stepped worlds).
    last_route : list
        The way travelled during the last intent, points (2,).
    """

    #: Name recorded in the episode summary.
    name: str = "platform"
    #: Intent types the platform can carry out.
    intents: tuple = ()

    def __init__(self) -> None:
        self.agent = 0

    def reachable(self, points: np.ndarray) -> np.ndarray | None:
        """Mask of `points` (n, 2) the platform can reach from where it stands, or None
        when it can reach the whole free region (the episode then adds no restriction)."""
        return None

    def nominal(self) -> dict:
        """What the platform knows of its own readings, added to the world's nominal
        description a strategy sees (e.g. ``reading_noise``: the standard deviation of one
        reading, signal units, from the platform's own calibration). Called after
        :meth:`reset`."""
        return {}

    def step_log(self) -> dict:
        """Platform-specific records of the last intent for the episode trace."""
        return {}

    def summary(self) -> dict:
        """Platform-specific keys for the episode summary."""
        return {}

    @property
    def true_position(self) -> np.ndarray:
        """Where the observer really is (the episode's business, never a strategy's)."""
        return self.pose[:2]

    @abstractmethod
    def reset(self, start, world: World, rng: np.random.Generator) -> None:
        """Place the platform at `start` (x, y[, heading]) in `world`."""

    def execute(self, intent: Intent) -> list[Observation]:
        """Carry out `intent`; the observations it produced."""
        if not isinstance(intent, self.intents):
            names = ", ".join(t.__name__ for t in self.intents)
            raise SearchError(f"the {self.name} platform cannot carry out {type(intent).__name__}; "
                              f"it takes {names}")
        return self._execute(intent)

    @abstractmethod
    def _execute(self, intent: Intent) -> list[Observation]:
        """Carry out a supported intent."""


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

    Notes
    -----
    The distance moved is the straight segment when it stays in the free region, else
    the shortest path along the edges of the mesh (an upper bound on the geodesic,
    within a few per cent on a quality mesh).
    """

    name = "point"
    intents = (Measure, SampleGradient, StepToward, Move, Stay)

    def __init__(self, space, dwell: float = 1.0):
        super().__init__()
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
        r = self.world.read(self.pose[:2], time=self.time, dwell=self.dwell, rng=self.rng)
        obs = Observation(self.pose[:2].copy(), r.value, self.time, self.dwell, r.kind if kind == "signal"
                          else kind, r.saturated, self.agent, r.data)
        self.time += self.dwell
        return obs

    def _execute(self, intent: Intent) -> list[Observation]:
        self.last_route = [self.pose[:2].copy()]
        if isinstance(intent, SampleGradient):
            here = self.pose.copy()
            pts = gradient_sample_points(here[:2], here[2], intent.offset, self.world.contains)
            out = []
            for p in pts:
                self._go(p)
                out.append(self._read("gradient"))
            return out
        if not isinstance(intent, Stay):
            self._go(intent.point)
        return [self._read("signal")]


class WalkerPlatform(Platform):
    """A time-stepped observer: each :class:`Move` goes to one of the places one step
    away, each :class:`Stay` stays; then it reads the world for one time step.

    Parameters
    ----------
    space : reciprocity.spaces.SearchSpace
        The *true* places and their neighbours (a lattice with its missing links, a
        grid). Moves go to a neighbour of the current place; with ``space=None`` the
        walker moves in the plane, at most `max_step` per step.
    slip : float
        Probability that a move ends at another neighbour, chosen at random, without
        the walker knowing (it still reports the place it was sent to).
    max_step : float, optional
        Largest move in the plane (``space=None``), the world's length unit.
    dt : float
        Duration of one step (s, or 1 in step-counted worlds).
    """

    name = "walker"
    intents = (Move, Stay)

    def __init__(self, space=None, *, slip: float = 0.0, max_step: float | None = None, dt: float = 1.0):
        super().__init__()
        if not 0.0 <= slip < 1.0:
            raise SearchError(f"slip probability must lie in [0, 1); got {slip!r}")
        if space is None and (max_step is None or not max_step > 0):
            raise SearchError("a walker in the plane needs a positive max_step")
        self.space, self.slip, self.max_step, self.dt = space, float(slip), max_step, float(dt)

    def reset(self, start, world: World, rng: np.random.Generator) -> None:
        s = np.asarray(start, dtype=float).ravel()
        self.world, self.rng = world, rng
        self.pose = np.array([s[0], s[1], s[2] if len(s) > 2 else 0.0])
        self._true = self.pose[:2].copy()
        self.path_length, self.time, self.slips = 0.0, 0.0, 0
        self.last_route = [self.pose[:2].copy()]

    @property
    def true_position(self) -> np.ndarray:
        return self._true

    def _execute(self, intent: Intent) -> list[Observation]:
        self.last_route = [self._true.copy()]
        if isinstance(intent, Move):
            target = intent.point
            if self.space is not None:
                here = self.space.nearest(self._true)
                nbrs = self.space.neighbours(here)
                want = self.space.nearest(target)
                # the walker goes where it was sent if that is a neighbour it can reach; a
                # move along a link that does not exist leaves it where it is
                dest = want if want in nbrs else here
                if len(nbrs) > 1 and self.rng.random() < self.slip:
                    others = nbrs[nbrs != dest]
                    dest = int(others[self.rng.integers(len(others))])
                    self.slips += 1
                new = self.space.points[dest]
            else:
                step = target - self._true
                dist = float(np.hypot(*step))
                if dist > self.max_step * (1 + 1e-9):
                    raise SearchError(f"a move of {dist:.3g} exceeds the walker's max_step {self.max_step:g}")
                new = target if self.world.contains(target[None])[0] else self._true
            self.path_length += float(np.hypot(*(new - self._true)))
            d = target - self.pose[:2]
            heading = np.arctan2(d[1], d[0]) if np.hypot(*d) > 0 else self.pose[2]
            self._true = np.asarray(new, dtype=float).copy()
            # the walker reports where it was sent (it does not know it slipped)
            self.pose = np.array([target[0], target[1], heading % (2 * np.pi)])
            self.last_route.append(self._true.copy())
        r = self.world.read(self._true, time=self.time, dwell=self.dt, rng=self.rng)
        obs = Observation(self.pose[:2].copy(), r.value, self.time, self.dt, r.kind, r.saturated,
                          self.agent, r.data)
        self.time += self.dt
        return [obs]

    def summary(self) -> dict:
        return dict(slips=int(self.slips))
