"""Infotaxis on binary detections of a filament plume (``detection-infotaxis``).

The plume worlds' infotaxis (:mod:`.infotaxis`) expects Poisson hit counts from the K0
model; the ``filament`` world gives 0/1 detections at 10 Hz and the local wind. Here:

* the belief is a grid of source hypotheses (cells of `resolution` m over the region,
  uniform prior), in log form;
* its likelihood is :class:`~reciprocity.models.detection.DetectionModel`, a
  time-averaged meandering-plume envelope oriented along the wind the vehicle has
  measured (:class:`~reciprocity.models.detection.WindEstimate`, its running mean and
  direction spread), never the world's filaments;
* it is updated once per decision `period` (1 s) with one Bernoulli outcome, "at least
  one detection in the period", read at the period's mean position. Why not every
  10-Hz reading: at fixed points of the calibration plume the per-reading detection
  frequency is nearly the per-period frequency
  (``benchmarks/filament_detection_calibration.md``), so the ten
  readings of a second carry about one reading's worth of independent information;
  counting them as ten would make the posterior ten times over-confident. Periods are
  still correlated through the meander (its 20 s time constant); `temper` (≤ 1) raises
  each period's likelihood to that power to allow for it, and the log-posterior relaxes
  toward the uniform prior with time constant `memory` (s; ``None``, the default:
  never), so that a long run of misses while the meander (or the slowly varying wind
  field) had carried the plume elsewhere does not rule out its true source for good
  (measured in ``benchmarks/filament_search.md``);
* each period the vehicle chooses among `n_headings` waypoints `lookahead` m away the
  one with the least expected entropy after its reading (Vergassola et al. 2007):
  ``(1 − P_f(v)) Σ_z ρ_z(v) S_z(v)``, ``P_f(v)`` the posterior mass within `found` m of
  ``v`` (entropy 0 once there), ``ρ_z`` the predicted probability of outcome ``z``;
* it stops when the posterior mass within `radius` m of its most likely cell reaches
  `stop_mass`, after `min_time` s, at least `min_hits` periods with a detection and with
  the vehicle within `2 radius` of the estimate; the estimate is the posterior mean over
  that disc, and (optionally) only once `overshoot` periods without detection were read
  upwind of the estimate (1 to `2 radius` m upwind along the measured wind, within
  `radius` crosswind): the vehicle has passed the source and lost the odour. Off by
  default: the vehicle then circles a correct estimate until the time runs out
  (``benchmarks/filament_search.md``). (Without the hit count and the
  distance condition, trial runs stopped on a few detections of the plume's far end at
  the region's downwind edge. Runs still stop in the middle of a run of detections
  while the vehicle surges upwind 5–10 m short of the source: consecutive periods in
  the plume are correlated, and the model's near-source peak explains a run of them
  best.)

Measured (success, wrong stops and the main failure, the curved plume):
``benchmarks/filament_search.md``.

Deviation from Vergassola et al.: their searcher only ends by reaching the source; ours
declares an estimate (the ``filament`` world scores the estimate, 5 m), and moves to
waypoints `lookahead` m away at 1 m/s rather than to neighbouring lattice cells.
"""

from __future__ import annotations

import numpy as np

from ..beliefs.base import expected_entropy
from ..errors import SearchError
from ..validation import positive
from ..models.detection import DetectionModel, WindEstimate
from ..outcome import StopReason
from . import register
from .base import SearchContext, Status
from .hmm import _PlaneWalk

__all__ = ["DetectionInfotaxis", "entropy"]


def entropy(w: np.ndarray, axis: int = -1) -> np.ndarray:
    """Shannon entropy (nats) of normalised weights along `axis`."""
    w = np.asarray(w, dtype=float)
    return -np.sum(np.where(w > 0, w * np.log(np.where(w > 0, w, 1.0)), 0.0), axis=axis)


@register
class DetectionInfotaxis(_PlaneWalk):
    """Infotaxis over a grid of source hypotheses, on per-period binary detections
    (module doc).

    Parameters
    ----------
    resolution : float
        Side of the hypothesis cells, m.
    period : float
        Decision and update period, s.
    lookahead : float
        Distance of the candidate waypoints, m.
    n_headings : int
        Number of candidate headings (evenly spaced).
    found : float
        Radius within which the source counts as found in the expected entropy, m.
    radius : float
        Radius of the stopping disc around the most likely cell, m.
    stop_mass : float
        Stop when the posterior mass in that disc reaches this, in (0, 1).
    min_time : float
        Never stop before this many seconds.
    temper : float
        Exponent (0, 1] on each period's likelihood (correlated periods).
    wind_window : float
        Time constant of the measured wind's running mean, s (the default compared with
        60 s: ``benchmarks/filament_search.md``).
    memory : float or None
        Time constant of the relaxation of the log-posterior toward uniform, s.
    min_hits : int
        Never stop before this many periods with a detection.
    overshoot : int
        Stop only after this many non-detections upwind of the estimate (module doc;
        0: no such condition).
    min_gain : float
        When no waypoint's expected entropy drop reaches this (nats), the vehicle heads
        for the most likely cell instead (one-step infotaxis has no gradient far from
        the posterior's mass: in trial runs it parked at the region's edge).
    """

    name = "detection-infotaxis"

    def __init__(self, *, resolution: float = 1.0, period: float = 1.0, lookahead: float = 2.0,
                 n_headings: int = 8, found: float = 2.0, radius: float = 4.0, stop_mass: float = 0.85,
                 min_time: float = 60.0, temper: float = 0.5, wind_window: float = 20.0,
                 min_gain: float = 1e-3, min_hits: int = 5,
                 memory: float | None = None, overshoot: int = 0):
        super().__init__()
        self.resolution = positive(resolution, "resolution")
        self.period = positive(period, "period")
        self.lookahead = positive(lookahead, "lookahead")
        self.found = positive(found, "found")
        self.radius = positive(radius, "radius")
        self.stop_mass = positive(stop_mass, "stop_mass", below_one=True)
        self.min_time = positive(min_time, "min_time")
        self.wind_window = positive(wind_window, "wind_window")
        self.temper = positive(temper, "temper")
        self.min_gain = positive(min_gain, "min_gain")
        if self.temper > 1:
            raise SearchError(f"temper must lie in (0, 1]; got {temper!r}")
        if isinstance(n_headings, bool) or not isinstance(n_headings, int) or n_headings < 2:
            raise SearchError(f"n_headings must be a whole number of at least 2; got {n_headings!r}")
        self.n_headings = n_headings
        if isinstance(min_hits, bool) or not isinstance(min_hits, int) or min_hits < 0:
            raise SearchError(f"min_hits must be a non-negative whole number; got {min_hits!r}")
        self.min_hits = min_hits
        self.memory = None if memory is None else positive(memory, "memory")
        if isinstance(overshoot, bool) or not isinstance(overshoot, int) or overshoot < 0:
            raise SearchError(f"overshoot must be a non-negative whole number; got {overshoot!r}")
        self.overshoot = overshoot
        self.model = DetectionModel()

    def params(self) -> dict:
        return dict(resolution=self.resolution, period=self.period, lookahead=self.lookahead,
                    n_headings=self.n_headings, found=self.found, radius=self.radius,
                    stop_mass=self.stop_mass, min_time=self.min_time, temper=self.temper,
                    wind_window=self.wind_window, min_gain=self.min_gain, min_hits=self.min_hits, memory=self.memory, overshoot=self.overshoot)

    def start(self, ctx: SearchContext) -> None:
        self._start_plane(ctx)
        x0, x1, y0, y1 = self.region
        nx = max(1, int(round((x1 - x0) / self.resolution)))
        ny = max(1, int(round((y1 - y0) / self.resolution)))
        xs = x0 + (np.arange(nx) + 0.5) * (x1 - x0) / nx
        ys = y0 + (np.arange(ny) + 0.5) * (y1 - y0) / ny
        gx, gy = np.meshgrid(xs, ys, indexing="ij")
        self.cells = np.c_[gx.ravel(), gy.ravel()]
        self.logw = np.full(len(self.cells), -np.log(len(self.cells)))
        self.wind = WindEstimate(window=self.wind_window)
        self.readings = max(1, int(round(self.period / self.dt)))
        self._buf_pos: list = []
        self._buf_hit = False
        self.n_updates = 0
        self.n_periods_hit = 0
        self.n_fallback = 0
        self._misses: list = []
        self.target = self.pos.copy()
        self.headings = 2 * np.pi * np.arange(self.n_headings) / self.n_headings

    # -- belief ----------------------------------------------------------------------------
    def weights(self) -> np.ndarray:
        """Normalised posterior weights of the hypothesis cells."""
        w = np.exp(self.logw - self.logw.max())
        return w / w.sum()

    def update_period(self, position, detected: bool) -> None:
        """Bayes' rule for one period's outcome read at `position` (m)."""
        p = self.model.probability(self.cells, np.asarray(position, dtype=float), self.wind.mean,
                                   self.wind.spread)
        if self.memory is not None:
            self.logw *= np.exp(-self.period / self.memory)
        self.logw += self.temper * np.log(p if detected else 1.0 - p)
        self.logw -= self.logw.max()
        self.n_updates += 1
        self.n_periods_hit += int(detected)
        if not detected:
            self._misses.append(np.asarray(position, dtype=float))

    def stop_disc(self) -> tuple[float, np.ndarray]:
        """Posterior mass within `radius` of the most likely cell, and the posterior mean
        over that disc (m)."""
        w = self.weights()
        peak = self.cells[int(np.argmax(w))]
        inside = np.hypot(*(self.cells - peak).T) <= self.radius
        m = float(w[inside].sum())
        return m, (w[inside] @ self.cells[inside]) / max(m, 1e-300)

    def overshot(self, estimate) -> bool:
        """Whether `overshoot` periods without detection were read upwind of `estimate`
        (1 to ``2 radius`` m along the measured wind, within `radius` crosswind)."""
        if self.overshoot == 0:
            return True
        if not self._misses:
            return False
        u = self.wind.mean / max(float(np.hypot(*self.wind.mean)), 1e-9)
        rel = np.asarray(self._misses[-600:]) - np.asarray(estimate)
        d, c = rel @ u, rel @ np.array([-u[1], u[0]])
        return int(np.sum((d <= -1.0) & (d >= -2 * self.radius) & (np.abs(c) <= self.radius))) >= self.overshoot

    def scores(self, points: np.ndarray) -> np.ndarray:
        """Expected entropy after a period's reading at each of `points` (K, 2)."""
        w = self.weights()
        p = self.model.probability(self.cells, points, self.wind.mean, self.wind.spread) ** self.temper
        q = (1 - p) if self.temper == 1 else (1 - p ** (1 / self.temper)) ** self.temper
        joint = np.stack([p, q]) * w                                 # (2 outcomes, K, cells)
        # the tempered masses weigh the outcomes as they are (they sum to more than 1 when
        # temper < 1); see benchmarks/filament_search.md
        s = expected_entropy(joint, joint.sum(axis=-1))
        near = np.hypot(*(self.cells[None, :, :] - points[:, None, :]).transpose(2, 0, 1)) <= self.found
        return (1 - (near * w).sum(axis=1)) * s

    def _decide(self) -> None:
        cand = self.pos + self.lookahead * np.c_[np.cos(self.headings), np.sin(self.headings)]
        cand = np.array([self._clip(c) for c in cand])
        moved = np.hypot(*(cand - self.pos).T) > 0.25 * self.lookahead
        sc = self.scores(cand)
        sc[~moved] = np.inf
        w = self.weights()
        if entropy(w) - sc.min() < self.min_gain:
            # no waypoint within reach is informative: head for the most likely cell
            peak = self.cells[int(np.argmax(w))]
            d = peak - self.pos
            n = float(np.hypot(*d))
            self.target = self._clip(self.pos + d * min(1.0, self.lookahead / n)) if n > 0 else self.pos.copy()
            self.n_fallback += 1
            return
        self.target = cand[int(np.argmin(sc))]

    # -- protocol ------------------------------------------------------------------------
    def propose(self):
        if self.done:
            return None
        if self.n_updates == 0 and not self._buf_pos:
            self._decide()
        return self._toward(self.target)

    def observe(self, observations, intent, agent: int = 0) -> None:
        for o in observations:
            if o.data is None or "wind" not in o.data:
                raise SearchError("detection-infotaxis needs the local wind with every reading (data['wind'])")
            self.n_samples += 1
            self.n_measurements += 1
            self.pos = o.position.copy()
            self.time = o.time + o.dwell
            self.wind.add(o.data["wind"], self.dt)
            self._buf_pos.append(self.pos.copy())
            self._buf_hit = self._buf_hit or o.value > 0
            if len(self._buf_pos) >= self.readings:
                self.update_period(np.mean(self._buf_pos, axis=0), self._buf_hit)
                self._buf_pos, self._buf_hit = [], False
                mass, est = self.stop_disc()
                self.status = Status(est, float(np.pi * self.radius ** 2),
                                     extra=dict(map_mass=mass, detections=self.n_periods_hit))
                if (mass >= self.stop_mass and self.time >= self.min_time and self.n_periods_hit >= self.min_hits
                        and np.hypot(*(est - self.pos)) <= 2 * self.radius
                        and self.overshot(est)):
                    self.stop(StopReason.CONVERGED, f"posterior mass {mass:.2f} within {self.radius:g} m")
                    return
                self._decide()
