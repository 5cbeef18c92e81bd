"""The simulated testbed: painted floor, reflectance sensor, pymunk car, overhead camera.

:class:`Testbed` is the world as a controller sees it through its two instruments. A
controller commands ``(steer, direction)`` once per camera frame (:meth:`Testbed.tick`)
and gets back the camera's estimate of the car's pose, never the true pose; it asks for
a stationary measurement (:meth:`Testbed.dwell`) and gets back raw ADC counts, which the
sensor's calibration turns into signal. The true poses and every raw reading are logged
for the trace, which the controller cannot read.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .camera import OverheadCamera
from .car import Car, CarSpec
from .errors import ArenaError
from .floor import Floor
from .geometry import Arena
from .sensor import Calibration, ReflectanceSensor

__all__ = ["Testbed", "Measurement", "dead_reckon"]


def dead_reckon(pose: np.ndarray, steer: float, direction: int, distance: float, rho: float) -> np.ndarray:
    """Pose after driving `distance` cm on the commanded arc (curvature ``steer / rho``,
    ``direction`` +1 forward / -1 reverse): the prediction used when the camera misses."""
    x, y, th = pose
    dth = direction * steer * distance / rho
    if abs(dth) < 1e-12:
        chord, mid = distance, th
    else:
        chord, mid = 2.0 * rho * np.sin(0.5 * abs(dth)) / abs(steer), th + 0.5 * dth
    return np.array([x + direction * chord * np.cos(mid), y + direction * chord * np.sin(mid),
                     (th + dth) % (2 * np.pi)])


@dataclass
class Measurement:
    """A stationary measurement: the readings taken while the car dwelt at one spot.

    Attributes
    ----------
    point : ndarray, shape (2,)
        Where the sensor spot was, by the camera's estimate, cm.
    true_point : ndarray, shape (2,)
        Where it really was, cm (for the trace only).
    counts : ndarray of int
        Raw ADC counts, one per sensor sample.
    intensity : float
        Calibrated signal of the mean count (a lower bound if saturated).
    saturated : bool
        The mean count is in the sensor's flat range above grey 185.
    time : float
        Simulated time at the end of the dwell, s.
    """

    point: np.ndarray
    true_point: np.ndarray
    counts: np.ndarray
    intensity: float
    saturated: bool
    time: float

    def to_dict(self) -> dict:
        return dict(point=self.point.tolist(), true_point=self.true_point.tolist(),
                    counts=self.counts.tolist(), intensity=self.intensity,
                    saturated=self.saturated, time=self.time)


@dataclass
class _Log:
    """What happened since the last :meth:`Testbed.take_log` (true and estimated poses)."""

    times: list = field(default_factory=list)
    true: list = field(default_factory=list)
    estimated: list = field(default_factory=list)
    detected: list = field(default_factory=list)


class Testbed:
    """The testbed of Landa et al., section V, in simulation.

    Parameters
    ----------
    arena : Arena
        Walls and obstacles (the car collides with them).
    floor : Floor
        The painted floor the sensor reads; the simulation never sees the field itself.
    car : CarSpec
        The micro-car.
    sensor : ReflectanceSensor
        The downward reflectance sensor.
    camera : OverheadCamera, optional
        Default: an :class:`~arenas.camera.OverheadCamera` over the floor image.
    calibration : Calibration, optional
        Default: calibrated on a grey strip at every :meth:`reset` (the paper's Fig. 3).
    """

    def __init__(self, arena: Arena, floor: Floor, *, car: CarSpec | None = None,
                 sensor: ReflectanceSensor | None = None, camera: OverheadCamera | None = None,
                 calibration: Calibration | None = None):
        if not isinstance(floor, Floor):
            raise ArenaError(f"floor must be an arenas.Floor (see arenas.render_floor); got {type(floor).__name__}")
        self.arena, self.floor = arena, floor
        self.spec = car or CarSpec()
        self.car = Car(arena, self.spec)
        self.sensor = sensor or ReflectanceSensor()
        self.camera = camera or OverheadCamera(arena, floor.image, car_length=self.spec.length,
                                               car_width=self.spec.width)
        self.period = 1.0 / self.camera.rate
        self._fixed_calibration = calibration
        self.calibration = calibration

    def reset(self, pose, rng: np.random.Generator) -> np.ndarray:
        """Place the car at `pose` (x, y cm, heading rad), calibrate the sensor unless a
        calibration was given, take the first camera fix; returns the estimated pose."""
        self.rng = rng
        self.car.reset(np.asarray(pose, dtype=float), rng)
        if self._fixed_calibration is None:
            self.calibration = self.sensor.calibrate(rng)
        self.log = _Log()
        obs = self.camera.observe(self.car.pose, rng)
        if obs is None:
            raise ArenaError("the overhead camera cannot see the car at its start pose; check that "
                             "the start is inside the arena and the camera covers it")
        self.estimate = obs.pose.copy()
        self._record(True)
        return self.estimate.copy()

    @property
    def time(self) -> float:
        """Simulated time since :meth:`reset`, s."""
        return self.car.time

    def tick(self, steer: float, direction: int) -> np.ndarray:
        """Drive one camera period with the given command; returns the new pose estimate.

        When the camera misses the tag the estimate is dead-reckoned from the command.
        """
        before = self.car.odometer
        self.car.drive(steer, direction, self.period)
        obs = self.camera.observe(self.car.pose, self.rng, near=self.estimate[:2])
        if obs is None:
            self.estimate = dead_reckon(self.estimate, steer, direction, self.car.odometer - before, self.spec.rho)
        else:
            self.estimate = obs.pose.copy()
        self._record(obs is not None)
        return self.estimate.copy()

    def dwell(self, duration: float) -> Measurement:
        """Stop, and average the sensor over `duration` s (``rate x duration`` samples)."""
        if not np.isfinite(duration) or duration <= 0:
            raise ArenaError(f"dwell duration must be a positive number of seconds; got {duration!r}")
        n = max(1, int(round(duration * self.sensor.rate)))
        self.car.drive(0.0, 0, 0.25)  # brake to rest before reading
        counts = []
        for _ in range(n):
            self.car.drive(0.0, 0, 1.0 / self.sensor.rate)
            counts.append(self.sensor.read(self.floor, self.car.pose, self.rng)[0])
        obs = self.camera.observe(self.car.pose, self.rng, near=self.estimate[:2])
        if obs is not None:
            self.estimate = obs.pose.copy()
        self._record(obs is not None)
        counts = np.asarray(counts, dtype=int)
        value, flag = self.calibration.intensity(counts.mean(), self.floor.mapping, n=len(counts))
        return Measurement(point=self.sensor.position(self.estimate)[0],
                           true_point=self.sensor.position(self.car.pose)[0], counts=counts,
                           intensity=float(np.ravel(value)[0]), saturated=bool(np.ravel(flag)[0]),
                           time=self.time)

    def _record(self, detected: bool) -> None:
        self.log.times.append(self.time)
        self.log.true.append(self.car.pose.copy())
        self.log.estimated.append(self.estimate.copy())
        self.log.detected.append(detected)

    def take_log(self) -> dict:
        """True and estimated poses (and camera detections) since the last call, as arrays."""
        log, self.log = self.log, _Log()
        return dict(times=np.asarray(log.times), true_poses=np.asarray(log.true).reshape(-1, 3),
                    estimated_poses=np.asarray(log.estimated).reshape(-1, 3),
                    detected=np.asarray(log.detected, dtype=bool))
