"""A random walk: the null strategy, defined on every world (contract tests, baselines)."""

from __future__ import annotations

import numpy as np

from ..errors import SearchError
from ..intents import Measure, Move
from ..outcome import StopReason
from ..spaces import mesh_space
from .base import SearchContext, Status, Strategy

__all__ = ["RandomWalkStrategy"]


class RandomWalkStrategy(Strategy):
    """Go to a random place one step away, `n_steps` times; estimate the source at the
    place of the largest reading. It never converges (it stops on its step cap): it is
    the floor any strategy must beat, and the probe of the framework's contract.

    On worlds with a space of places (``nominal["space"]``: a lattice, a grid) each step
    is a :class:`~reciprocity.intents.Move` to a random neighbour; on arena worlds a
    :class:`~reciprocity.intents.Measure` at a random mesh node within `step` cm that
    keeps `clearance` from the walls; on open plane worlds (``nominal["bounds"]`` and
    ``nominal["max_step"]``) a :class:`~reciprocity.intents.Move` of one step in a random
    direction that stays within the bounds.

    Parameters
    ----------
    n_steps : int
        Number of steps.
    step : float
        Step length on arena worlds, cm.
    clearance : float
        Distance kept from walls on arena worlds, cm.
    """

    name = "random-walk"
    worlds = ("poisson", "lattice", "plume", "filament", "flow")
    agents = None

    def __init__(self, *, n_steps: int = 10, step: float = 10.0, clearance: float = 3.0):
        super().__init__()
        if int(n_steps) < 1:
            raise SearchError(f"n_steps must be at least 1; got {n_steps!r}")
        if not np.isfinite(step) or step <= 0:
            raise SearchError(f"step must be a positive length; got {step!r}")
        self.n_steps, self.step, self.clearance = int(n_steps), float(step), float(clearance)

    def params(self) -> dict:
        return dict(n_steps=self.n_steps, step=self.step, clearance=self.clearance)

    def start(self, ctx: SearchContext) -> None:
        self._reset_state()
        self.rng = ctx.rng
        self.space = ctx.nominal.get("space")
        self.bounds = ctx.nominal.get("bounds") if ctx.arena is None else None
        if self.space is None and self.bounds is not None:
            self.plane_step = float(ctx.nominal.get("max_step", self.step))
        elif self.space is None:
            geometry = ctx.arena.without_scenario()
            self.mesh = mesh_space(geometry, max(1.0, self.step / 4))
            self._ok = self.mesh.reachable_from(ctx.start[:2], self.clearance)
        self.positions = ctx.starts[:, :2].copy()
        self.best = (-np.inf, ctx.start[:2].copy())
        self.rounds = 0

    def _next(self, position: np.ndarray):
        if self.space is not None:
            options = self.space.step_candidates(position)
            return Move(options[self.rng.integers(len(options))]) if len(options) else None
        if self.bounds is not None:
            (x0, x1), (y0, y1) = self.bounds
            for _ in range(32):
                a = self.rng.uniform(0, 2 * np.pi)
                p = position + self.plane_step * np.array([np.cos(a), np.sin(a)])
                if x0 <= p[0] <= x1 and y0 <= p[1] <= y1:
                    return Move(p)
            return None
        near = self._ok & self.mesh.around(position, self.step)
        idx = np.flatnonzero(near if near.any() else self._ok)
        return Measure(self.mesh.points[idx[self.rng.integers(idx.size)]]) if idx.size else None

    def propose(self):
        if self.done:
            return None
        if self.rounds >= self.n_steps:
            self.stop(StopReason.STEP_CAP, f"{self.n_steps} random steps")
            return None
        intents = {a: self._next(p) for a, p in enumerate(self.positions)}
        if any(v is None for v in intents.values()):
            self.stop(StopReason.NO_TARGET, "no place to step to")
            return None
        self.rounds += 1
        return intents

    def observe(self, observations, intent, agent: int = 0) -> None:
        for o in observations:
            self.n_samples += 1
            if o.value > self.best[0]:
                self.best = (float(o.value), o.position.copy())
        self.n_measurements += len(observations)
        self.positions[agent] = observations[-1].position
        self.status = Status(self.best[1].copy())
