"""Surge-cast in wind among walls (issue 38): the moth's baseline on the ``flow`` worlds.

The reactive search of the plume literature, with no model of the plume: on a detection,
surge upwind; when the plume is lost, cast across the wind in legs that grow until it is
found again. Here the readings are counts over a dwell and the observer reads where it
stops, so one reading is one move:

- **the wind it uses** is the one the task states, blowing from the inflow's midpoint toward
  the outflow's (the observer has no anemometer): among walls that bend the wind it is the
  wall-blind direction the plume papers assume;
- **a detection** is a count of at least ``hits``;
- **surge**: the next point is ``step`` cm upwind of a detection;
- **cast**: after a reading without one, the next point lies across the wind from the last
  detection, ``cast`` cm on one side, then on the other side one ``step`` further, and so
  on; before the first detection, legs of ``cast`` cm zig-zag upwind from the start
  instead, each one ``step`` further upwind than the last (the plume is yet to be found);
- each point is the reachable node of the strategy's mesh nearest to the one asked for; a
  leg the walls block turns to the other side;
- **stop**: CONVERGED once, after a first detection, ``declare`` readings in a row have
  not read more hits per second than the best so far, with the estimate at the best;
  STEP_CAP after ``max_steps`` readings. The estimate is where the most hits per second
  were read.
"""

from __future__ import annotations

import numpy as np

from ..intents import Measure
from ..outcome import StopReason
from ..validation import number
from . import register
from .base import SearchContext, Status
from .reciprocity_wind import ModelFreeWind

__all__ = ["SurgeCastWind"]


@register
class SurgeCastWind(ModelFreeWind):
    """Surge upwind on a detection, cast across the wind when it is lost (see the module doc).

    Parameters
    ----------
    step : float
        Length of a surge, and how much each cast leg grows, cm.
    cast : float
        First cast leg, cm.
    hits : int
        Count that makes a reading a detection.
    declare : int
        Readings in a row without a higher hit rate than the best that stop the search.
    max_steps : int
        Readings before the search stops at its cap.
    h : float
        Mesh size of the nodes it moves between, cm.
    clearance : float
        Points read keep this distance from the walls, cm.
    """

    name = "surge-cast-wind"

    def __init__(self, *, step: float = 6.0, cast: float = 6.0, hits: int = 1, declare: int = 12,
                 max_steps: int = 80, h: float = 2.0, clearance: float = 3.0):
        super().__init__(step=step, hits=hits, declare=declare, max_steps=max_steps, h=h, clearance=clearance)
        self.cast = number(cast, "cast", 0.0, 1e3, lo_open=True, unit="cm")

    def params(self) -> dict:
        return dict(step=self.step, cast=self.cast, hits=self.hits, declare=self.declare,
                    max_steps=self.max_steps, h=self.h, clearance=self.clearance)

    def start(self, ctx: SearchContext) -> None:
        super().start(ctx)
        self._next = np.asarray(ctx.start[:2], dtype=float).copy()
        self._anchor = self._next.copy()         # the last detection (the start before any)
        self._detected = False
        self._leg, self._side = self.cast, 1.0
        self._best, self._best_rate, self._since_best = None, -np.inf, 0
        self._check_reachable()

    def propose(self) -> Measure | None:
        return None if self.done else Measure(self._next.copy())

    def observe(self, observations, intent, agent: int = 0) -> None:
        obs = observations[0]
        here = np.asarray(obs.position, dtype=float)[:2]
        count, rate = float(obs.value), float(obs.value) / max(float(obs.dwell), 1e-12)
        self.n_measurements += 1
        self.n_samples += 1
        if rate > self._best_rate:
            self._best, self._best_rate, self._since_best = here.copy(), rate, 0
        else:
            self._since_best += 1
        self.status = Status(self._best.copy(), None, extra=dict(best_rate=self._best_rate, hits=count))
        if self._detected and self._since_best >= self.declare:
            self.stop(StopReason.CONVERGED, f"{self.declare} readings without more than "
                                            f"{self._best_rate:.3g} hits/s")
        elif self.n_measurements >= self.max_steps:
            self.stop(StopReason.STEP_CAP, f"max_steps = {self.max_steps} readings")
        elif count >= self.hits:
            self._anchor, self._leg, self._detected = here.copy(), self.cast, True
            self._next = self._nearest(here - self.step * self.downwind, here)
        else:
            self._next = self._cast(here)
        if not self.done:
            self.status.extra["next"] = self._next.tolist()

    def reject(self, intent, point: np.ndarray, reason: str, agent: int = 0) -> None:
        """Leave out the neighbourhood of an unreachable point and cast on the other side."""
        if self._count_rejection(reason):
            return
        if not self._refuse_around(point, max(0.5 * self.step, self.h)):
            self.stop(StopReason.NO_TARGET, "no admissible observation point left")
            return
        self._next = self._cast(np.asarray(point, dtype=float))

    # -- moves ---------------------------------------------------------------------------
    def _cast(self, here: np.ndarray) -> np.ndarray:
        """The next cast point: across the wind from the last detection, alternating sides,
        each leg one step longer (before any detection, legs of ``cast`` zig-zagging
        upwind); a leg the walls cut short turns to the other side."""
        across = np.array([-self.downwind[1], self.downwind[0]])
        for _ in range(4):
            self._side = -self._side
            if not self._detected:              # no plume yet: zig-zag upwind
                self._anchor = self._anchor - self.step * self.downwind
            want = self._anchor + self._side * self._leg * across
            self._leg += self.step if self._detected else 0.0
            nxt = self._nearest(want, here)
            if np.hypot(*(nxt - here)) >= 0.5 * self.h:
                return nxt
        return self._nearest(self._anchor, here)
