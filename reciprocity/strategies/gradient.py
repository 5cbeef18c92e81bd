"""Algorithm 2 of Landa et al.: gradient ascent with three-point gradient estimates."""

from __future__ import annotations

import numpy as np

from ..errors import SearchError
from ..intents import Measure, SampleGradient, StepToward
from ..outcome import StopReason
from ..spaces import MeshSpace, mesh_space
from .base import SearchContext, Status, Strategy

__all__ = ["GradientStrategy", "three_point_gradient"]


def three_point_gradient(points: np.ndarray, readings: np.ndarray) -> np.ndarray:
    """Gradient of the plane through three samples (line 14 of Algorithm 2).

    Parameters
    ----------
    points : ndarray, shape (3, 2)
        Sample points, cm, not collinear.
    readings : ndarray, shape (3,)
        Signal at the points.

    Returns
    -------
    ndarray, shape (2,)
        Signal units per cm.
    """
    p = np.asarray(points, dtype=float)
    A = p[1:] - p[0]
    if abs(np.linalg.det(A)) < 1e-9 * max(1.0, np.abs(A).max()) ** 2:
        raise SearchError("the three gradient samples are collinear; spread them out")
    return np.linalg.solve(A, np.asarray(readings[1:], dtype=float) - readings[0])


#: The stall rule stops a search with `i_max` only once a sample reached this fraction of
#: it: without this condition the rule stopped car runs off the source, stuck against walls
#: (``docs/testbed.md``, *Two defaults of the car's searches*); a reading of 0.6 u_max lies
#: within about 5 cm of the source on ``paper``.
STALL_FRACTION = 0.6


class GradientStrategy(Strategy):
    """Gradient ascent (Algorithm 2).

    While the signal is weaker than `i_min` the observer explores: the next point is the
    admissible point nearest to the current one at least `d` from all earlier samples
    (ties, the whole ring of such points, broken toward the centroid of the part of the
    arena not yet explored, so the observer does not trail along the walls). Once the signal is strong enough, two
    extra samples (a short step back, then forward and to the side, `delta` cm) give a
    linear gradient estimate and the observer steps along it. The step does not
    overshoot: for a point source ``|∇u| ≈ c / (2 pi r)``, so the step is at most
    `kappa` times the distance ``r ≈ c / (2 pi |∇u|)`` this implies, and at most
    `step_max`.

    The paper stops when a reading exceeds ``I_max``, the signal at the source, which it
    assumes known; the estimate is then the observer's position. That rule is used when
    `i_max` is given (``stop_radius=0, stall_steps=0`` make it the only rule, as in the
    paper). By
    default (``i_max=None``), which needs no knowledge of the source, and also alongside
    ``I_max`` unless ``stop_radius=0``, the search stops once a gradient estimate puts the
    source within `stop_radius`; the estimate is again the observer's position (moving it
    along the gradient does not help: so close to the source the three samples straddle
    it). **Deviation from the paper**: on the car, ``I_max`` is the sensor's saturation,
    reached only within about 2.5 cm of the source, which a car with a 15 cm turning
    radius rarely hits; with ``I_max`` alone the search circles the saturated disk
    (measured in ``benchmarks/reciprocity_rules.md``).

    A search that stalls also stops (``StopReason.CONVERGED``): when the last
    `stall_steps` gradient steps all start within `stall_radius` of their centroid (and,
    with `i_max`, the strongest sample so far reached STALL_FRACTION of it: the observer
    circles the source rather than a wall), the estimate is the sample with the largest
    reading so far. ``stall_steps=0`` disables it.

    Parameters
    ----------
    i_min : float
        Gradient sampling starts above this reading (signal units).
    i_max : float or None
        Stop above this reading (the paper's rule), or None for the gradient rule.
    stop_radius : float
        Gradient rule: stop when the estimated source distance is below this, cm; 0 for
        none (then `i_max`, where given, the stall rule and `max_steps` end the search; on
        the car the platform supplies `i_max`).
    d : float
        Exploration separation, cm.
    delta : float
        Offset of the two gradient samples, cm.
    step_max : float
        Largest step along the gradient, cm.
    kappa : float
        Fraction of the estimated source distance taken per step.
    max_steps : int
        Give up after this many signal measurements.
    stall_steps : int
        Gradient steps of the stall rule; 0 for none.
    stall_radius : float
        Radius (cm) of the stall rule.
    clearance : float
        Distance kept from walls, cm.
    strength : float or "arena"
        Source strength ``c`` used to size steps.
    h : float
        Mesh size (cm) of the admissible-point set (a mesh only: nothing is solved).
    space : MeshSpace, optional
        A prebuilt mesh of the arena to choose points from.
    """

    name = "gradient"
    start_limits = ("i_max",)     # the car's calibrated range: one per episode's floor

    def __init__(self, *, i_min: float = 18.0, i_max: float | None = None,
                 stop_radius: float = 3.0, d: float = 15.0,
                 delta: float = 5.0, step_max: float = 15.0, kappa: float = 0.5,
                 max_steps: int = 60, clearance: float = 3.0, strength="arena",
                 h: float = 1.0, space: MeshSpace | None = None, stall_steps: int = 3,
                 stall_radius: float = 4.0):
        super().__init__()
        if not 0 <= i_min < (np.inf if i_max is None else i_max):
            raise SearchError(f"need 0 <= i_min < i_max; got i_min={i_min!r}, i_max={i_max!r}")
        for key, val in dict(d=d, delta=delta, step_max=step_max, kappa=kappa, h=h,
                             stall_radius=stall_radius).items():
            if not np.isfinite(val) or val <= 0:
                raise SearchError(f"{key} must be a positive number; got {val!r}")
        if not np.isfinite(stop_radius) or stop_radius < 0:
            raise SearchError(f"stop_radius must be a distance >= 0 cm (0: no radius rule); "
                              f"got {stop_radius!r}")
        if int(stall_steps) != stall_steps or stall_steps < 0 or stall_steps == 1:
            raise SearchError(f"stall_steps must be 0 (off) or a whole number >= 2; got {stall_steps!r}")
        if int(max_steps) < 1:
            raise SearchError(f"max_steps must be at least 1; got {max_steps!r}")
        self.i_min, self.d, self.delta = float(i_min), float(d), float(delta)
        self.i_max, self.stop_radius = (None if i_max is None else float(i_max)), float(stop_radius)
        self.step_max, self.kappa, self.max_steps = float(step_max), float(kappa), int(max_steps)
        self.clearance, self.strength, self.h, self.space = float(clearance), strength, float(h), space
        self.stall_steps, self.stall_radius = int(stall_steps), float(stall_radius)

    def params(self) -> dict:
        return dict(i_min=self.i_min, i_max=self.i_max, stop_radius=self.stop_radius, d=self.d, delta=self.delta,
                    step_max=self.step_max, kappa=self.kappa, max_steps=self.max_steps,
                    clearance=self.clearance, strength=self.strength, stall_steps=self.stall_steps,
                    stall_radius=self.stall_radius)

    def start(self, ctx: SearchContext) -> None:
        self._reset_state()
        if "i_max" in ctx.limits:                       # left unset: the platform's
            i_max = float(ctx.limits["i_max"])
            if not self.i_min < i_max:
                raise SearchError(f"need 0 <= i_min < i_max; got i_min={self.i_min!r}, i_max={i_max!r} "
                                  "(the platform's)")
            self.i_max = i_max
        arena, pose = ctx.arena, ctx.start
        geometry = arena.without_scenario()
        if self.space is None or self.space.arena is not geometry:
            self.space = mesh_space(geometry, max(self.h, 1.0))
        self.arena = arena
        self.c = ctx.nominal.get("strength", arena.strength) if self.strength == "arena" else float(self.strength)
        self._reachable = self.space.reachable_from(pose[:2], self.clearance)
        self.heading = float(pose[2]) if len(pose) > 2 else 0.0
        self.visited = np.empty((0, 2))
        self.samples = np.empty((0, 2))
        self.position = np.asarray(pose[:2], dtype=float)
        self.reading = None
        self.gradients: list[tuple[list, list]] = []
        self._best = (-np.inf, self.position.copy())
        self._pending = Measure(self.position.copy())

    def propose(self):
        return None if self.done else self._pending

    def figure_record(self) -> dict:
        """``gradients``: every gradient estimate as ``(point, gradient)``, in the order made."""
        return dict(gradients=list(self.gradients))

    def observe(self, observations, intent, agent: int = 0) -> None:
        points = np.array([o.position for o in observations]).reshape(-1, 2)
        readings = np.array([o.value for o in observations], dtype=float)
        self.n_samples += len(readings)
        self.samples = np.vstack([self.samples, points])
        k = int(np.argmax(readings))
        if readings[k] > self._best[0]:
            self._best = (float(readings[k]), points[k].copy())
        if isinstance(intent, SampleGradient):
            pts = np.vstack([self.position, points])
            vals = np.concatenate([[self.reading], readings])
            g = three_point_gradient(pts, vals)
            self.gradients.append((self.position.tolist(), g.tolist()))
            norm = np.hypot(*g)
            r_est = self.c / (2 * np.pi * norm) if norm > 0 else np.inf
            if r_est <= self.stop_radius:
                self.stop(StopReason.CONVERGED, "gradient puts the source within stop_radius")
                return
            if self._stalled():
                self.status = Status(self._best[1].copy(), None)
                self.stop(StopReason.CONVERGED, f"stalled: the last {self.stall_steps} gradient steps "
                                                f"started within {self.stall_radius:g} cm; estimate: "
                                                "the strongest sample")
                return
            self._pending = StepToward(self._gradient_step(g))
            return
        new = points[-1]
        if np.hypot(*(new - self.position)) > 1e-9:
            self.heading = float(np.arctan2(*(new - self.position)[::-1]))
        self.position, self.reading = new, float(readings[-1])
        self.visited = np.vstack([self.visited, new])
        self.n_measurements += 1
        self.status = Status(self.position.copy(), None)
        if self.i_max is not None and (self.reading >= self.i_max or observations[-1].saturated):
            self.stop(StopReason.CONVERGED, "signal above i_max")
        elif self.n_measurements >= self.max_steps:
            self.stop(StopReason.STEP_CAP, f"max_steps = {self.max_steps} measurements")
        elif self.reading < self.i_min:
            self._explore_or_stop()
        else:
            self._pending = SampleGradient(self.position.copy(), self.delta)

    def _stalled(self) -> bool:
        """Whether the last `stall_steps` gradient steps started within `stall_radius` of
        their centroid."""
        if not self.stall_steps or len(self.gradients) < self.stall_steps:
            return False
        if self.i_max is not None and self._best[0] < STALL_FRACTION * self.i_max:
            return False            # stuck far from the source (a wall): keep going
        starts = np.array([g[0] for g in self.gradients[-self.stall_steps:]])
        return bool(np.all(np.hypot(*(starts - starts.mean(axis=0)).T) <= self.stall_radius))

    def _explore_or_stop(self) -> None:
        nxt = self._explore()
        if nxt is None:
            self.stop(StopReason.NO_TARGET, "no admissible exploration point left")
        else:
            self._pending = Measure(nxt)

    def restrict(self, mask_of) -> None:
        mask = mask_of(self.space.points)
        if mask is not None and (self._reachable & mask).any():
            self._reachable &= mask

    def reject(self, intent, point: np.ndarray, reason: str, agent: int = 0) -> None:
        """While exploring, exclude the unreachable point's neighbourhood and explore
        elsewhere; an unreachable gradient step or sample ends the search."""
        exploring = isinstance(intent, Measure) and self.reading is not None and self.reading < self.i_min
        if self._count_rejection(reason):
            return
        if not exploring:
            super().reject(intent, point, reason, agent)
            return
        self._reachable &= ~self.space.around(point, max(0.5 * self.d, self.space.h))
        self._explore_or_stop()

    def _explore(self) -> np.ndarray | None:
        """Lines 9-12: nearest admissible point at least d from all samples."""
        cand = self.space
        allowed = self._reachable & cand.separated(self.visited, self.d)
        if not allowed.any():
            return None
        centroid = cand.points[allowed].mean(axis=0)
        toward = -np.hypot(*(cand.points - centroid).T)
        return cand.nearest_ring(self.position, allowed, toward, self.space.h)

    def _gradient_step(self, g: np.ndarray) -> np.ndarray:
        """Lines 16-17: step along the gradient without overshooting the source."""
        norm = np.hypot(*g)
        if norm == 0:
            return self.position.copy()
        r_est = self.c / (2 * np.pi * norm)
        step = min(self.step_max, self.kappa * r_est)
        self.heading = float(np.arctan2(g[1], g[0]))
        u = g / norm
        cand = self.space
        for s in step * 0.5 ** np.arange(6):
            target = self.position + s * u
            if cand.nearest_in(target, self._reachable) is not None and self.arena.contains(target, self.clearance)[0]:
                return target
        near = cand.nearest_in(self.position + step * u, self._reachable)
        return self.position.copy() if near is None else near
