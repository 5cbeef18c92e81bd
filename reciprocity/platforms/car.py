"""The car observer: the simulated micro-car driven by Hamilton-Jacobi value functions.

:class:`CarPlatform` is the controller of the paper's testbed (Landa et al., section V)
behind the same :class:`~reciprocity.platforms.base.Platform` interface as the point observer.
For each requested point it

1. gets the value function of the target (on demand, or the nearest of a precomputed
   bank, as the paper does),
2. reads the optimal path off it from the camera's estimate of the pose and drives it,
   steering by the feedback law ``u = -v sign(φ_θ)`` (eq. (15), with ``v`` the gear of
   the path: the car may reverse), re-planning every `replan_every` cm (the paper's blue
   circles) and at every change of gear,
3. stops at the target, dwells and averages the sensor (:meth:`arenas.Testbed.dwell`).

Gradient samples are taken by the paper's manoeuvre (a short reverse, then forward and
to the side) and gradient steps by bang-bang steering among the six actions. The
controller knows only the camera's estimates and the calibrated readings.

The class is assembled from three parts, each in its own module: the walls it plans on and
the value functions it drives with (:mod:`~reciprocity.platforms.car_maps`), the steering
along them with its guards (:mod:`~reciprocity.platforms.car_steering`) and Algorithm 2's
manoeuvres (:mod:`~reciprocity.platforms.car_gradient`).
"""

from __future__ import annotations

from collections import deque
from dataclasses import asdict, dataclass, fields

import numpy as np

from arenas import Arena, ArenaError, CarSpec, Testbed
from arenas.files import check_output
from hjplanner import OnDemandPlanner, PlanningError, ValueFunctionBank
from hjplanner.limits import check_grid

from ..errors import SearchError, UnreachableTarget
from ..intents import Intent, Measure, SampleGradient, StepToward, Survey
from ..observations import Observation
from ..spaces.occupancy import OccupancyGrid
from ..validation import Bound, check_bounds
from .base import Platform
from .car_gradient import GradientManoeuvre
from .car_maps import SCAN_EVERY, SWEEP_MARGIN, WallMaps, _same_walls  # noqa: F401 (SWEEP_MARGIN: by its old path)
from .car_steering import BACK_OFF, CUSP_SLACK, MAX_BACK_OFFS, TRAIL_TICKS, Steering
from .lidar import Lidar

__all__ = ["CAR_KEYS", "CarPlatform", "DrivingOptions", "PLANNERS", "check_car_options", "make_car_platform"]

#: How the car gets the value function of a target.
PLANNERS = ("on-demand", "bank")








@dataclass(frozen=True)
class DrivingOptions:
    """How the car is driven (lengths in cm, times in s).

    Attributes
    ----------
    planner : {"on-demand", "bank"}
        ``"on-demand"`` solves the value function of each requested point (exact
        targets); ``"bank"`` uses the nearest of value functions precomputed on a lattice
        of targets `bank_spacing` apart (the paper's approach: the car then measures at
        the lattice point nearest to the requested one).
    h, ntheta : float, int
        Grid of the value functions (cm, headings).
    clearance : float
        Distance the car's path keeps from every wall, cm. Half the car's width (1.9 cm)
        plus a margin for drift; a turn next to a wall can still bring a corner (3.98 cm
        from the centre) into contact, which is recorded as a collision. 4 cm keeps the
        car off the walls; it closes the narrowest gaps of the ``paper`` arena on the
        1.5 cm grid (3.5 cm opens them, but the car then scrapes and stalls along walls).
    bank_spacing : float
        Lattice spacing of the bank, cm (the paper: 12.7).
    cache_dir : str, optional
        Where the bank keeps its value functions (default ``$HJPLANNER_CACHE``, else
        ``~/.cache/hjplanner``; ``hjplanner cache --info`` shows it).
    replan_every : float
        Distance driven between re-plans, cm.
    stop_tol : float
        The car stops when its centre is this close to the target, cm.
    dwell : float
        Duration of a stationary measurement, s (30 sensor samples at 30 Hz).
    dead_band : float, optional
        Dead band of the steering law on ``|φ_θ|``; default ``0.05 ρ``.
    manoeuvre_reverse, manoeuvre_forward : float
        Arc lengths of the gradient manoeuvre: straight back, then forward at full lock.
    bang_step : float
        Distance between decisions of the bang-bang steering, cm.
    window : float, optional
        On-demand planner: solve each target's value function only in the rectangle of
        the car and the target widened by this much on every side, cm (the paths stay in
        it); the whole map when the car cannot reach the target inside it, or when it
        loses the value function on the way. None solves on the whole map.
    """

    planner: str = "on-demand"
    h: float = 1.5
    ntheta: int = 48
    clearance: float = 4.0
    bank_spacing: float = 12.7
    cache_dir: str | None = None
    replan_every: float = 10.0
    stop_tol: float = 1.5
    dwell: float = 1.0
    dead_band: float | None = None
    manoeuvre_reverse: float = 5.0
    manoeuvre_forward: float = 8.0
    bang_step: float = 2.0
    window: float | None = 30.0

    def __post_init__(self):
        if self.planner not in PLANNERS:
            raise SearchError(f"planner must be one of {PLANNERS}; got {self.planner!r}")
        for key in ("h", "clearance", "bank_spacing", "replan_every", "stop_tol", "dwell",
                    "manoeuvre_reverse", "manoeuvre_forward", "bang_step"):
            val = getattr(self, key)
            if not isinstance(val, (int, float)) or not np.isfinite(val) or val <= 0:
                raise SearchError(f"driving option {key} must be a positive number; got {val!r}")
        if int(self.ntheta) < 8:
            raise SearchError(f"ntheta must be at least 8 headings; got {self.ntheta!r}")
        if self.window is not None and (not isinstance(self.window, (int, float)) or not np.isfinite(self.window)
                                        or self.window <= 0):
            raise SearchError(f"driving option window must be a positive number of cm or None; got {self.window!r}")


class CarPlatform(WallMaps, Steering, GradientManoeuvre, Platform):
    """The micro-car on the simulated testbed, as an observer for any strategy.

    Parameters
    ----------
    testbed : arenas.Testbed
        Floor, sensor, car and camera: the physics, on the true walls.
    options : DrivingOptions
        Planner and controller settings.
    believed : Arena, optional
        The map the car plans on (its value functions, reachability, standable targets and
        manoeuvre checks); default: the testbed's. When the true walls differ from the map,
        the car meets them with its bumper, not with its planner.
    progress : bool
        Show a progress bar while a value-function bank is built.
    lidar : Lidar, optional
        A range sensor on the car: it scans the true walls every SCAN_EVERY cm driven and at
        every re-plan, and its scans are returned after each reading (kind ``"scan"``).
    mapping : bool
        The map is not all known (``map: unknown``): the car keeps its own occupancy grid
        from its scans (:class:`~reciprocity.spaces.occupancy.OccupancyGrid`), plans on the
        believed walls with unknown space free (optimistic: a path through space no beam
        has seen is tried, and abandoned as soon as a beam sees a wall on it; a conservative
        map would shut the car in its first scan's circle), and re-plans whenever the
        believed walls change. The cells its body drove over stay free in the grid
        (:meth:`~reciprocity.spaces.occupancy.OccupancyGrid.sweep`), and a target the
        believed walls shut out (their dilation closes gaps the true walls leave open at
        the car's clearance) is planned once more on the scanned walls
        (:meth:`~reciprocity.spaces.occupancy.OccupancyGrid.scanned_arena`) before it is
        refused. Needs `lidar` and the on-demand planner.

    Attributes
    ----------
    arena : Arena
        The map the car plans on now.
    walls : {"believed", "scanned"}
        Which of its maps that is: the believed walls, or (on an unknown map, while it
        drives to a target they shut out) the scanned ones.
    """

    name = "car"
    intents = (Measure, SampleGradient, StepToward, Survey)
    #: The car reads the world through its own sensor: the noise of its readings is the
    #: calibration's (:meth:`nominal`), not the world's point-reading ``noise``.
    restates = ("noise",)

    def __init__(self, testbed: Testbed, options: DrivingOptions | None = None, *,
                 believed: Arena | None = None, progress: bool = False, lidar: Lidar | None = None,
                 mapping: bool = False):
        super().__init__()
        self.testbed = testbed
        self.lidar = lidar
        if mapping and (lidar is None or (options is not None and options.planner != "on-demand")):
            raise SearchError("a car on an unknown map needs a lidar and the on-demand planner "
                              "(planner=on-demand): a bank is built for walls known in advance")
        #: The map the car plans on (never the true walls unless they are the map).
        self.arena: Arena = (believed if believed is not None else testbed.arena).without_scenario()
        self.options = options or DrivingOptions()
        o, rho = self.options, testbed.spec.rho
        common = dict(rho=rho, h=o.h, ntheta=int(o.ntheta), clearance=o.clearance, reverse=True)
        if o.planner == "bank":
            self.bank = ValueFunctionBank(self.arena.without_scenario(), o.bank_spacing,
                                          cache_dir=o.cache_dir, **common)
            if self.bank.missing():
                self.bank.build(progress=progress)
            self._value_function = self.bank.nearest
        else:
            self.planner = OnDemandPlanner(self.arena.without_scenario(), maxsize=8, **common)
            self._value_function = self.planner.get
        self._planner_options = common
        self.grid = OccupancyGrid(self.arena) if mapping else None
        self.walls = "believed"
        #: per kind of walls: the map and its planner (on an unknown map)
        self._maps = {kind: (self.arena, getattr(self, "planner", None)) for kind in ("believed", "scanned")}
        self._swept: list[np.ndarray] = []
        #: (estimated pose after the tick, steering, gear) of the latest ticks: the way back
        #: (:meth:`~reciprocity.platforms.car_steering.Steering._retrace`)
        self._trail: deque = deque(maxlen=TRAIL_TICKS)
        self._retracing = False
        self._noted = None
        self.scanned_plans = 0
        self._scans: list[Observation] = []
        self._since_scan = 0.0
        self.dead_band = 0.05 * rho if o.dead_band is None else float(o.dead_band)

    # -- Platform interface -------------------------------------------------------------
    def reset(self, start, world, rng: np.random.Generator) -> None:
        s = np.asarray(start, dtype=float).ravel()
        self.world, self.rng = world, rng
        self.pose = self.testbed.reset([s[0], s[1], s[2] if len(s) > 2 else 0.0], rng)
        self.path_length = 0.0
        self.last_route = [self.testbed.car.pose[:2].copy()]
        self._collisions_seen = 0
        self._log = self._new_log()
        self._swept, self._noted, self.scanned_plans = [], None, 0
        self._trail.clear()
        self.testbed.take_log()

    @property
    def time(self) -> float:
        """Simulated time, s."""
        return self.testbed.time

    @property
    def true_position(self) -> np.ndarray:
        return self.testbed.car.pose[:2]

    def _execute(self, intent: Intent) -> list[Observation]:
        if not self._in_free_region(intent.point):
            raise UnreachableTarget(intent.point, f"({intent.point[0]:.4g}, {intent.point[1]:.4g}) "
                                    "is not in the free region")
        self._log = self._new_log()
        if self.grid is not None:
            self._log["maps"] = []
            self._plan_on("believed")
        kind = "gradient" if isinstance(intent, SampleGradient) else "signal"
        try:
            if isinstance(intent, Survey):
                if self.lidar is None:
                    raise SearchError("a Survey needs a range sensor: this car has no lidar")
                self._drive_to(intent.point)
                measured = []
            elif isinstance(intent, SampleGradient):
                measured = self._manoeuvre(2)
            elif isinstance(intent, StepToward):
                self._bang_bang(intent.point)
                measured = [self._measure()]
            else:
                self._drive_to(intent.point)
                measured = [self._measure()]
            if self.lidar is not None:
                self._sense()                       # the scan where the reading was taken
        finally:
            self._close_visit()
        dwell = self.options.dwell
        scans, self._scans = self._scans, []
        return [Observation(m.point, m.intensity, m.time - dwell, dwell, kind, m.saturated, self.agent)
                for m in measured] + scans

    def step_log(self) -> dict:
        return self._log

    def reachable(self, points: np.ndarray) -> np.ndarray | None:
        """Points the car can reach from its pose on its map: by symmetry of the reversible
        car, those from which the value function of the car's own position is finite for
        some heading (one HJ solve). None if the car's position is not a valid target."""
        try:
            vf = self._value_function(self._standable(self.testbed.estimate[:2].copy()))
        except (PlanningError, UnreachableTarget):
            return None
        return _finite_somewhere(vf, points)

    def truly_reachable(self, points: np.ndarray) -> np.ndarray | None:
        """:meth:`reachable` on the true walls from the true position (the evaluator's; one
        extra HJ solve when the map differs from the walls)."""
        true = self.testbed.arena.without_scenario()
        if _same_walls(true, self.arena):
            return self.reachable(points)
        o = self.options
        planner = OnDemandPlanner(true, rho=self.testbed.spec.rho, h=o.h, ntheta=int(o.ntheta),
                                  clearance=o.clearance, reverse=True, maxsize=1)
        here = self.testbed.car.pose[:2].copy()
        if true.wall_distance(here[None])[0] < o.clearance:
            return None
        try:
            vf = planner.get(here)
        except PlanningError:
            return None
        return _finite_somewhere(vf, points)

    def nominal(self) -> dict:
        """``reading_noise``: the calibrated standard deviation of one dwell's reading,
        signal units (:meth:`arenas.sensor.Calibration.signal_noise` over the dwell's
        ``round(dwell x 30 Hz)`` samples, at least one: ``dwell = 1/30`` s is one raw
        sample); ``noise``: the same number, in place of the world's point-reading noise
        (the key strategies read as "the noise of a reading"); ``reading_bias``: the part
        of it that is one offset shared by every reading of the run (the calibration
        fit's error)."""
        tb = self.testbed
        n = max(1, int(round(self.options.dwell * tb.sensor.rate)))
        independent, shared = tb.calibration.signal_noise_parts(tb.floor.mapping, n)
        total = float(np.hypot(independent, shared))
        return dict(reading_noise=total, noise=total, reading_bias=float(shared))

    def summary(self) -> dict:
        """The car's summary keys; on an unknown map also ``scanned_plans``: the drives
        planned on the scanned walls because the believed ones shut the target out."""
        tb = self.testbed
        out = dict(collisions=len(tb.car.collisions),
                   driving=asdict(self.options), rho=tb.spec.rho, speed=tb.spec.speed,
                   calibration_noise=float(tb.calibration.noise))
        if self.grid is not None:
            out["scanned_plans"] = int(self.scanned_plans)
        return out

    def figure_record(self) -> dict:
        """``floor``: the painted floor (:class:`arenas.Floor`); ``calibration``: the
        sensor's calibration (its Fig. 3)."""
        return dict(floor=self.testbed.floor, calibration=self.testbed.calibration)

    # -- bookkeeping -------------------------------------------------------------------
    @staticmethod
    def _new_log() -> dict:
        return dict(replans=[], plans=[], measurements=[], collisions=[], events=[])

    def _close_visit(self) -> None:
        tb = self.testbed
        log = tb.take_log()
        self._log.update(times=log["times"], true_poses=log["true_poses"],
                         estimated_poses=log["estimated_poses"],
                         camera_misses=int((~log["detected"]).sum()), sim_time=tb.time)
        self._log["collisions"] = tb.car.collisions[self._collisions_seen:]
        self._collisions_seen = len(tb.car.collisions)
        self.last_route = [self.last_route[-1]] + list(log["true_poses"][:, :2])
        self.path_length = tb.car.odometer
        self.pose = tb.estimate.copy()

    def _measure(self):
        m = self.testbed.dwell(self.options.dwell)
        if self.grid is not None:                  # it stood there: its body's cells are free
            self._swept.append(self.testbed.estimate.copy())
        self._log["measurements"].append(m.to_dict())
        return m

    def _event(self, text: str) -> None:
        self._log["events"].append(dict(time=self.testbed.time, text=text))

    def _tick(self, steer: float, direction: int) -> np.ndarray:
        est = self.testbed.tick(steer, direction)
        if self.grid is not None:
            self._swept.append(est)
        if not self._retracing:
            self._trail.append((est.copy(), float(steer), int(direction)))
        return est

    def _ticks_for(self, distance: float) -> int:
        per_tick = self.testbed.spec.speed * self.testbed.period
        return max(1, int(np.ceil(distance / per_tick - 1e-9)))

    # -- Algorithm 1: drive to a point with the HJ value function ----------------------
    def _standable(self, target: np.ndarray) -> np.ndarray:
        """The target, or the nearest point within 3 cm that keeps the clearance (plus
        one grid cell); UnreachableTarget if there is none."""
        need = self._clearance() + 0.75 * self.options.h
        if self.arena.wall_distance(target[None])[0] >= need and self.arena.contains(target[None])[0]:
            return target
        for r in np.arange(0.5, 3.01, 0.5):
            ang = np.linspace(0, 2 * np.pi, int(8 + 4 * r), endpoint=False)
            ring = target + r * np.column_stack([np.cos(ang), np.sin(ang)])
            ok = self.arena.contains(ring) & (self.arena.wall_distance(ring) >= need)
            if ok.any():
                return ring[np.flatnonzero(ok)[0]]
        raise UnreachableTarget(target, (
            f"target ({target[0]:.1f}, {target[1]:.1f}) cm is closer than the car's clearance of "
            f"{self.options.clearance:g} cm to a wall: the car cannot stand there"))

    def _drive_to(self, target: np.ndarray) -> None:
        o, tb = self.options, self.testbed
        vf = self._plan(np.asarray(target, dtype=float))
        goal = vf.target
        est = self._virtual(vf, tb.estimate)
        budget = 2.0 * float(vf(*est)) + 60.0
        step = tb.spec.speed * tb.period
        driven, gear_at, plan_s, since_plan, backed_off = 0.0, None, 0.0, 0.0, 0
        dist = np.hypot(*(tb.estimate[:2] - goal))
        while dist > o.stop_tol:
            if driven > budget:
                self._event(f"gave up on target ({goal[0]:.1f}, {goal[1]:.1f}) after {driven:.0f} cm, "
                            f"{dist:.1f} cm short")
                break
            replan = gear_at is None or since_plan >= o.replan_every or plan_s >= gear_at[0][0]
            if self.lidar is not None and (replan or self._since_scan >= SCAN_EVERY) and self._sense():
                # the believed walls changed: the target's value function on the new map
                vf = self._replan_target(np.asarray(target, dtype=float))
                goal, est, replan = vf.target, self._virtual(vf, tb.estimate), True
                budget = max(budget, driven + 2.0 * float(vf(*est)) + 60.0) if np.isfinite(vf(*est)) else budget
            if replan:
                gear_at = self._replan(vf, est)
                if gear_at is None and "window" in vf.meta:
                    vf = self._value_function(vf.target)   # drifted out of the window: the whole map
                    est = self._virtual(vf, tb.estimate)
                    gear_at = self._replan(vf, est)
                if gear_at is None:
                    if not (self._unstick(vf) or self._retrace(vf)):
                        self._event("lost the value function: measuring where the car stands")
                        break
                    est = self._virtual(vf, tb.estimate)
                    continue
                since_plan, plan_s = 0.0, 0.0
            ends, gears = gear_at
            stretch = min(np.searchsorted(ends, plan_s, side="right"), len(gears) - 1)
            v = int(gears[stretch])
            if stretch + 1 < len(gears) and ends[stretch] - plan_s <= CUSP_SLACK and self._boxed_in(v):
                plan_s = float(ends[stretch])              # change gear now: the cusp is here
                v = int(gears[stretch + 1])
            elif self._backs_off(v):                       # the body is about to touch a wall
                if backed_off == MAX_BACK_OFFS:
                    self._event("the plan leads the body into a wall: measuring where the car stands")
                    break
                backed_off += 1
                self._back_off(v)
                driven += BACK_OFF
                gear_at, est = None, self._virtual(vf, tb.estimate)
                dist = np.hypot(*(tb.estimate[:2] - goal))
                continue
            new_est = self._tick(self._steer(vf, est, v), v)
            driven += step
            self._since_scan += step
            since_plan += step
            plan_s += step
            new_dist = np.hypot(*(new_est[:2] - goal))
            est = self._virtual(vf, new_est)
            if new_dist > dist and dist < 3 * o.stop_tol:
                break  # past the closest approach: stop rather than loop around
            dist = new_dist





def _finite_somewhere(vf, points) -> np.ndarray:
    """Mask of `points` (n, 2) where value function `vf` is finite for some of 8 headings."""
    pts = np.asarray(points, dtype=float).reshape(-1, 2)
    x, y = np.ascontiguousarray(pts[:, 0]), np.ascontiguousarray(pts[:, 1])
    certified = vf.certified_clear(x, y)              # the same for every heading: once
    finite = np.zeros(len(pts), dtype=bool)
    for th in np.linspace(0, 2 * np.pi, 8, endpoint=False):
        # the arc readings only lower finite values (never finite <-> inf): left out
        finite |= np.isfinite(vf.at_certified(x, y, np.full(len(pts), th), certified, cubic=False, arcs=False))
    return finite




#: Keys accepted by :func:`make_car_platform`: the driving options, the car's
#: specification and the floor resolution.
CAR_KEYS = tuple(f.name for f in fields(DrivingOptions)) + tuple(f.name for f in fields(CarSpec)) + (
    "px_per_mm",)


#: Bounds of every car option (lengths in cm, times in s, speeds in cm/s): what keeps one
#: episode's value functions within the planner's memory budget and its physics step finite.
CAR_BOUNDS = {
    "h": Bound(0.2, 20, unit="cm"), "ntheta": Bound(8, 360, integer=True), "clearance": Bound(0, 50, unit="cm"),
    "bank_spacing": Bound(0.5, 1000, unit="cm"), "replan_every": Bound(0.1, 1e4, unit="cm"),
    "stop_tol": Bound(0.01, 100, unit="cm"), "dwell": Bound(0.01, 3600, unit="s"),
    "dead_band": Bound(0, 100, none=True), "manoeuvre_reverse": Bound(0.1, 1000, unit="cm"),
    "manoeuvre_forward": Bound(0.1, 1000, unit="cm"), "bang_step": Bound(0.1, 1000, unit="cm"),
    "window": Bound(1, 1000, none=True, unit="cm"), "length": Bound(0.5, 100, unit="cm"), "width": Bound(0.5, 100, unit="cm"), "mass": Bound(0.1, 1e5, unit="g"),
    "speed": Bound(0.1, 1000, unit="cm/s"), "rho": Bound(0.5, 1000, unit="cm"), "lateral_grip": Bound(0.01, 1e4),
    "steer_noise": Bound(0, 10), "speed_noise": Bound(0, 10), "noise_tau": Bound(1e-3, 1e3, unit="s"),
    "servo_tau": Bound(1e-3, 1e3, unit="s"), "dt": Bound(1e-4, 0.1, unit="s"), "px_per_mm": Bound(0.1, 4),
}
#: Most value functions of one bank.
MAX_BANK_TARGETS = 10_000


def check_car_options(car: dict, arena=None) -> tuple[DrivingOptions, CarSpec, float]:
    """Validate car options (cheap): the driving options, the car and the floor resolution.

    With `arena` (the arena the car will drive in), also the planner's grid and bank
    against their budgets, and the bank's cache folder.
    """
    unknown = sorted(set(car) - set(CAR_KEYS))
    if unknown:
        raise SearchError(f"unknown car option(s) {', '.join(unknown)}; choose from {', '.join(CAR_KEYS)}")
    check_bounds(car, CAR_BOUNDS, "car option ")
    drive_keys = {f.name for f in fields(DrivingOptions)}
    spec_keys = {f.name for f in fields(CarSpec)}
    try:
        options = DrivingOptions(**{k: v for k, v in car.items() if k in drive_keys})
        spec = CarSpec(**{k: v for k, v in car.items() if k in spec_keys})
    except (TypeError, ArenaError) as exc:
        raise SearchError(f"bad car option: {exc}") from None
    if options.cache_dir is not None:
        if not isinstance(options.cache_dir, str):
            raise SearchError(f"car option cache_dir must be a folder name; got {options.cache_dir!r}")
        check_output(options.cache_dir, "car option cache_dir", folder=True, error=SearchError)
    if options.planner == "bank":
        from pathlib import Path

        from hjplanner.bank import check_cache_dir, default_cache_dir
        folder = Path(options.cache_dir).expanduser() if options.cache_dir else default_cache_dir()
        try:
            check_cache_dir(folder, "car option cache_dir" if options.cache_dir else "HJPLANNER_CACHE")
        except PlanningError as exc:
            raise SearchError(str(exc)) from None
    if arena is not None:
        _check_planner_budget(options, spec, arena)
    return options, spec, float(car.get("px_per_mm", 1.0))


def _check_planner_budget(options: DrivingOptions, spec: CarSpec, arena) -> None:
    """Refuse a grid or bank beyond the planner's budgets in `arena`, before any solve."""
    b = np.asarray(arena.boundary, dtype=float)
    extent = tuple(b.max(axis=0) - b.min(axis=0))
    try:
        check_grid(spec.rho, options.h, int(options.ntheta), options.clearance, extent)
    except PlanningError as exc:
        raise SearchError(f"car options h={options.h:g}, ntheta={options.ntheta}: {exc}") from None
    if options.planner == "bank":
        n = (int(extent[0] // options.bank_spacing) + 1) * (int(extent[1] // options.bank_spacing) + 1)
        if n > MAX_BANK_TARGETS:
            raise SearchError(f"car option bank_spacing={options.bank_spacing:g} gives about {n} value functions in "
                              f"arena {arena.name!r}; at most {MAX_BANK_TARGETS}: raise it")


def make_car_platform(world, *, progress: bool = False, **car) -> CarPlatform:
    """The car observer in a :class:`~reciprocity.worlds.PoissonWorld`: the floor painted
    from the world's true field, read through the calibrated sensor.

    Parameters
    ----------
    world : PoissonWorld
        The truth (its true walls, strength and paint curve) for the testbed's physics;
        the car plans on the world's nominal arena, or, on an unknown map, on what the
        world tells (its believed arena) and what its own lidar shows.
    progress : bool
        Progress bar while a value-function bank is built.
    **car
        Any of :data:`CAR_KEYS`: :class:`DrivingOptions` fields (``planner``,
        ``replan_every``, ...), :class:`arenas.CarSpec` fields (``rho``, ``speed``, ...),
        and ``px_per_mm``, the floor resolution.
    """
    options, spec, px = check_car_options(car, world.arena)
    believed = getattr(world, "believed", None)          # map: unknown: what the car is told
    lidar = Lidar.from_dict(world.lidar) if getattr(world, "lidar", None) is not None else None
    if believed is not None and options.planner != "on-demand":
        raise SearchError("planner=bank needs the walls in advance; on an unknown map the car plans "
                          "on demand (planner=on-demand)")
    floor = world.floor(px_per_mm=px)
    return CarPlatform(Testbed(world.true_arena, floor, car=spec), options,
                       believed=world.arena if believed is None else believed, progress=progress,
                       lidar=lidar, mapping=believed is not None)
