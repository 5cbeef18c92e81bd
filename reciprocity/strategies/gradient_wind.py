"""Gradient ascent on the hit rate in wind among walls (issue 38): the chemotaxis baseline on
the ``flow`` worlds.

The gradient baseline of the Poisson search reads the field's gradient with its sensor; a
count world offers no gradient, so this one estimates it from counts, as a chemotactic
walker does, with no model of the plume:

- **a station** is three readings: at the station, and ``probe`` cm from it along the last
  move and across it (the side alternating from station to station);
- **the gradient** is the slope of the plane fitted by weighted least squares to
  ``log((count + 1/2) / dwell)`` over the station's readings and every earlier one within
  ``probe`` cm of it (weights ``count + 1/2``, the inverse variance of a log-count); the
  half count keeps a zero count finite;
- **the move**: ``step`` cm along the fitted gradient to the next station; while the
  readings the fit uses hold fewer than ``hits`` hits in all, there is no gradient to follow
  and the move is ``step`` cm upwind, along the wind the task states (the observer has no
  anemometer), as the moth's search does before its first contact;
- each point is the reachable node of the strategy's mesh nearest to the one asked for;
- **stop**: CONVERGED once, after a first detection (a reading of at least ``hits``),
  ``declare`` stations in a row have not read more hits per second on average than the best
  station so far, with the estimate at that station; STEP_CAP after ``max_steps`` readings.
"""

from __future__ import annotations

import numpy as np

from ..intents import Measure
from ..outcome import StopReason
from ..validation import number
from . import register
from .base import SearchContext, Status
from .reciprocity_wind import ModelFreeWind

__all__ = ["GradientWind", "log_rate_slope"]


def log_rate_slope(points: np.ndarray, counts: np.ndarray, dwells: np.ndarray) -> np.ndarray | None:
    """Slope (per cm) of the plane fitted by weighted least squares to the log hit rates.

    Parameters
    ----------
    points : numpy.ndarray
        (n, 2) reading positions, cm.
    counts : numpy.ndarray
        (n,) hits counted.
    dwells : numpy.ndarray
        (n,) dwell of each reading, s.

    Returns
    -------
    numpy.ndarray or None
        The gradient of ``log((count + 1/2) / dwell)`` (2,), 1/cm; None when the points do
        not span a plane (fewer than three, or all on one line).
    """
    points = np.asarray(points, dtype=float)
    if len(points) < 3:
        return None
    y = np.log((np.asarray(counts, dtype=float) + 0.5) / np.asarray(dwells, dtype=float))
    design = np.column_stack([np.ones(len(points)), points - points.mean(axis=0)])
    if np.linalg.matrix_rank(design, tol=1e-6 * max(1.0, float(np.abs(design).max()))) < 3:
        return None
    root_w = np.sqrt(np.asarray(counts, dtype=float) + 0.5)
    coef = np.linalg.lstsq(design * root_w[:, None], y * root_w, rcond=None)[0]
    return coef[1:]


@register
class GradientWind(ModelFreeWind):
    """Gradient ascent on the log hit rate, estimated from counts at stations of three
    readings; upwind while there is no signal (see the module doc).

    Parameters
    ----------
    step : float
        Move from one station to the next, cm.
    probe : float
        Distance of a station's two probe readings from it, cm.
    hits : int
        Count that makes a reading a detection, and the hits a fit needs to be followed.
    declare : int
        Stations in a row without a higher mean hit rate than the best that stop the search.
    max_steps : int
        Readings before the search stops at its cap.
    h : float
        Mesh size of the nodes it moves between, cm.
    clearance : float
        Points read keep this distance from the walls, cm.
    """

    name = "gradient-wind"

    def __init__(self, *, step: float = 6.0, probe: float = 4.0, hits: int = 1, declare: int = 4,
                 max_steps: int = 80, h: float = 2.0, clearance: float = 3.0):
        super().__init__(step=step, hits=hits, declare=declare, max_steps=max_steps, h=h, clearance=clearance)
        self.probe = number(probe, "probe", 0.0, 1e3, lo_open=True, unit="cm")

    def params(self) -> dict:
        return dict(step=self.step, probe=self.probe, hits=self.hits, declare=self.declare,
                    max_steps=self.max_steps, h=self.h, clearance=self.clearance)

    def start(self, ctx: SearchContext) -> None:
        super().start(ctx)
        self._heading = -self.downwind.copy()    # the direction of the last move: upwind at first
        self._side = 1.0
        self._readings: list[tuple[float, float, float, float]] = []   # x, y, count, dwell
        self._detected = False
        self._best, self._best_rate, self._since_best = None, -np.inf, 0
        self._begin_station(np.asarray(ctx.start[:2], dtype=float))
        self._check_reachable()

    def propose(self) -> Measure | None:
        return None if self.done else Measure(self._queue[0].copy())

    def observe(self, observations, intent, agent: int = 0) -> None:
        obs = observations[0]
        here = np.asarray(obs.position, dtype=float)[:2]
        count, dwell = float(obs.value), max(float(obs.dwell), 1e-12)
        self.n_measurements += 1
        self.n_samples += 1
        self._readings.append((here[0], here[1], count, dwell))
        self._station_rates.append(count / dwell)
        self._detected |= count >= self.hits
        self._queue.pop(0)
        if self._station_point is None:
            self._station_point = here.copy()
            self._queue = [self._nearest(here + self.probe * d, here) for d in self._probe_directions()]
        if not self._queue:
            self._end_station()
        if self.done:
            return
        if self.n_measurements >= self.max_steps:
            self.stop(StopReason.STEP_CAP, f"max_steps = {self.max_steps} readings")
        if self._best is not None:
            self.status = Status(self._best.copy(), None, extra=dict(best_rate=self._best_rate, hits=count))
            if not self.done:
                self.status.extra["next"] = self._queue[0].tolist()

    def reject(self, intent, point: np.ndarray, reason: str, agent: int = 0) -> None:
        """Leave out the neighbourhood of an unreachable point; a probe is skipped, a
        station is taken at the nearest node left."""
        if self._count_rejection(reason):
            return
        if not self._refuse_around(point, max(0.5 * self.probe, self.h)):
            self.stop(StopReason.NO_TARGET, "no admissible observation point left")
            return
        point = np.asarray(point, dtype=float)
        if self._station_point is None:
            self._queue = [self._nearest(point, point)]
        else:
            self._queue.pop(0)
            if not self._queue:
                self._end_station()

    # -- stations --------------------------------------------------------------------------
    def _begin_station(self, point: np.ndarray) -> None:
        """Queue a station's first reading at `point` (its probes follow once it is read)."""
        self._station_point, self._station_rates = None, []
        self._queue = [point.copy()]

    def _probe_directions(self) -> list[np.ndarray]:
        """Along the last move and across it, on alternating sides."""
        self._side = -self._side
        across = self._side * np.array([-self._heading[1], self._heading[0]])
        return [self._heading.copy(), across]

    def _end_station(self) -> None:
        """Score the station, then move to the next along the fitted gradient (upwind
        without a signal)."""
        station = self._station_point
        rate = float(np.mean(self._station_rates))
        if rate > self._best_rate:
            self._best, self._best_rate, self._since_best = station.copy(), rate, 0
        else:
            self._since_best += 1
        if self._detected and self._since_best >= self.declare:
            self.stop(StopReason.CONVERGED, f"{self.declare} stations without more than "
                                            f"{self._best_rate:.3g} hits/s on average")
            return
        move = self._uphill(station)
        self._heading = move
        self._begin_station(self._nearest(station + self.step * move, station))

    def _uphill(self, station: np.ndarray) -> np.ndarray:
        """Unit direction of the fitted log-rate gradient at `station`, or upwind when the
        readings near it hold fewer than ``hits`` hits or span no plane."""
        r = np.array(self._readings)
        near = np.hypot(r[:, 0] - station[0], r[:, 1] - station[1]) <= self.probe + 0.5 * self.h
        if r[near, 2].sum() >= self.hits:
            slope = log_rate_slope(r[near, :2], r[near, 2], r[near, 3])
            size = 0.0 if slope is None else float(np.hypot(*slope))
            if size > 0:
                return slope / size
        return -self.downwind.copy()
