"""The walker: one move per time step, on a lattice, a grid or the plane, and may slip."""

from __future__ import annotations

import numpy as np

from ..errors import SearchError
from ..intents import Intent, Move, Stay
from ..observations import Observation
from ..worlds.base import World
from .base import Platform

__all__ = ["WalkerPlatform"]


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
        # a directional sensor reads by the course just taken (papers/001, eq. (14))
        course = dict(course=float(self.pose[2])) if getattr(self.world, "sense", None) else {}
        r = self.world.read(self._true, time=self.time, dwell=self.dt, rng=self.rng, observer=self.agent, **course)
        obs = Observation(self.pose[:2].copy(), r.value, self.time, self.dt, r.kind, r.saturated,
                          self.agent, r.data)
        self.time += self.dt
        return [obs]

    def summary(self) -> dict:
        return dict(slips=int(self.slips))
