"""The simulated micro-car: a pymunk rigid body driven like the testbed's vehicle.

Section V of Landa et al. describes the micro-vehicle: a 7 x 3.8 cm, 65 g car with
car-like steering, driven at constant speed and tracked by an overhead camera. Here it
is a dynamic box in a :class:`pymunk.Space` whose static walls are the arena boundary
and obstacles. Each fixed physics step applies

* a velocity servo along the car axis toward ``direction * speed * (1 + n_v)``,
* the yaw rate ``v * (steer + n_s) / rho`` of car-like (Dubins) steering, and
* lateral tyre friction that decays the sideways velocity at ``lateral_grip`` 1/s
  (not instantly: the tyres slip a little in turns),

where ``n_v`` and ``n_s`` are Ornstein-Uhlenbeck actuation noises: slowly wandering
speed and steering errors, so that open-loop driving drifts and the closed loop
(camera + planner) has something to correct. Contacts with the walls are resolved by
pymunk and logged in :attr:`Car.collisions`.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass

import numpy as np
import pymunk
from shapely.geometry import Polygon

from .errors import ArenaError
from .geometry import Arena

__all__ = ["Car", "CarSpec", "car_footprint"]

#: Radius (cm) of the static wall segments: walls are this much thicker than drawn.
WALL_RADIUS = 0.1

_CAR, _WALL, _OBSTACLE = 1, 2, 3
_TWO_PI = 2.0 * math.pi


@dataclass(frozen=True)
class CarSpec:
    """Physical and actuation parameters of the micro-car.

    Parameters
    ----------
    length, width : float
        Body size, cm (the testbed car is 7 x 3.8 cm).
    mass : float
        Mass, g.
    speed : float
        Constant driving speed, cm/s.
    rho : float
        Minimum turning radius, cm: ``|steer| = 1`` gives curvature ``1 / rho``.
    lateral_grip : float
        Rate (1/s) at which tyre friction kills the sideways velocity. Finite, so the
        car slips a little in turns (at full lock the slip angle is about
        ``speed / (rho * lateral_grip)`` rad).
    steer_noise : float
        Standard deviation of the steering error, relative to the full-lock curvature
        ``1 / rho``: the curvature driven is ``(steer + n_s) / rho`` with ``n_s`` an
        Ornstein-Uhlenbeck process of this stationary std (dimensionless). It is added
        rather than multiplied so that straight driving (``steer = 0``) wanders too.
    speed_noise : float
        Relative standard deviation of the speed error ``n_v`` (speed driven
        ``speed * (1 + n_v)``), an Ornstein-Uhlenbeck process.
    noise_tau : float
        Correlation time of both actuation noises, s.
    servo_tau : float
        Time constant of the speed servo (acceleration and braking), s.
    dt : float
        Fixed physics step, s.

    Notes
    -----
    The noise defaults make an open-loop straight drift laterally and turn its heading
    (by how much: ``docs/testbed.md``): a closed loop has something to correct, as on
    the real testbed.
    """

    length: float = 7.0
    width: float = 3.8
    mass: float = 65.0
    speed: float = 10.0
    rho: float = 15.0
    lateral_grip: float = 20.0
    steer_noise: float = 0.05
    speed_noise: float = 0.05
    noise_tau: float = 0.5
    servo_tau: float = 0.05
    dt: float = 1 / 120

    def __post_init__(self) -> None:
        for name in ("length", "width", "mass", "speed", "rho", "lateral_grip", "noise_tau",
                     "servo_tau", "dt"):
            value = getattr(self, name)
            if not (_is_number(value) and math.isfinite(value) and value > 0):
                raise ArenaError(f"CarSpec.{name} must be a positive finite number; got {value!r}")
        for name in ("steer_noise", "speed_noise"):
            value = getattr(self, name)
            if not (_is_number(value) and math.isfinite(value) and value >= 0):
                raise ArenaError(
                    f"CarSpec.{name} must be a finite number >= 0 (0 turns the noise off); "
                    f"got {value!r}")


def _is_number(value) -> bool:
    return isinstance(value, numbers.Real) and not isinstance(value, bool)


def car_footprint(pose, length: float, width: float) -> np.ndarray:
    """Corners of a car body at `pose`, shape (4, 2), cm, counter-clockwise.

    Parameters
    ----------
    pose : array_like, shape (3,)
        ``(x, y, theta)``: centre in cm, heading in radians.
    length, width : float
        Body size, cm.

    Returns
    -------
    ndarray, shape (4, 2)
        Front-right, front-left, rear-left, rear-right corners, cm.
    """
    x, y, th = (float(v) for v in np.asarray(pose, dtype=float).ravel()[:3])
    c, s = math.cos(th), math.sin(th)
    local = np.array([[1, -1], [1, 1], [-1, 1], [-1, -1]]) * [length / 2, width / 2]
    return np.column_stack([x + c * local[:, 0] - s * local[:, 1],
                            y + s * local[:, 0] + c * local[:, 1]])


class Car:
    """The micro-car in an arena, simulated with pymunk.

    Parameters
    ----------
    arena : Arena
        The arena; its boundary and obstacles become static wall segments of radius
        :data:`WALL_RADIUS` cm.
    spec : CarSpec
        Car parameters.

    Attributes
    ----------
    space : pymunk.Space
        The physics space (no gravity). Rebuilt by :meth:`reset`, so that every episode
        starts from the same solver state and a seed reproduces it bit for bit.
    time : float
        Simulated time since :meth:`reset`, s.
    odometer : float
        Distance actually driven since :meth:`reset` (integral of ``|v| dt``), cm.
    collisions : list of dict
        One entry per contact that begins: the car starts touching the outer wall
        (``"shape": "wall", "index": -1``) or obstacle ``index`` (``"shape":
        "obstacle"``) it was not touching. Keys ``time`` (s, end of the physics step in
        which it began), ``x``, ``y`` (cm, the contact point). Sliding along a wall
        across polygon vertices is one contact.

    Examples
    --------
    >>> import numpy as np, arenas
    >>> car = arenas.Car(arenas.load("empty"))
    >>> car.reset((20.0, 20.0, 0.0), np.random.default_rng(1))
    >>> car.drive(0.0, +1, 1.0)
    >>> bool(9.0 < car.odometer < 10.5)
    True
    """

    def __init__(self, arena: Arena, spec: CarSpec = CarSpec()) -> None:
        if not isinstance(arena, Arena):
            raise ArenaError(f"Car needs an arenas.Arena; got {type(arena).__name__} "
                             "(build one with arenas.load or Arena.from_polygons)")
        if not isinstance(spec, CarSpec):
            raise ArenaError(f"spec must be a CarSpec; got {type(spec).__name__}")
        self.arena = arena
        self.spec = spec
        dt = spec.dt
        self._servo_gain = 1.0 - math.exp(-dt / spec.servo_tau)
        self._grip_decay = math.exp(-spec.lateral_grip * dt)
        self._ou_decay = math.exp(-dt / spec.noise_tau)
        self._ou_kick = math.sqrt(1.0 - self._ou_decay ** 2)
        self._free = arena.free_region
        self.space: pymunk.Space | None = None
        self._body: pymunk.Body | None = None
        self._shape: pymunk.Poly | None = None
        self._rng: np.random.Generator | None = None
        self.time = 0.0
        self.odometer = 0.0
        self.collisions: list[dict] = []
        self._step_end = 0.0  # time stamp for the collision callback
        self._n_steer = 0.0
        self._n_speed = 0.0

    # ------------------------------------------------------------------ set-up
    def _build_space(self, x: float, y: float, theta: float) -> None:
        spec = self.spec
        space = pymunk.Space()
        space.gravity = (0.0, 0.0)
        kinds: dict = {}
        for ring, ctype, index in ([(self.arena.boundary, _WALL, -1)]
                                   + [(o, _OBSTACLE, i) for i, o in enumerate(self.arena.obstacles)]):
            segments = _wall_segments(space.static_body, ring, ctype)
            space.add(*segments)
            for seg in segments:
                kinds[seg] = ("wall" if ctype == _WALL else "obstacle", index)
        body = pymunk.Body(spec.mass, pymunk.moment_for_box(spec.mass, (spec.length, spec.width)))
        body.position = (x, y)
        body.angle = theta
        shape = pymunk.Poly.create_box(body, (spec.length, spec.width))
        shape.collision_type = _CAR
        shape.friction = 0.3
        shape.elasticity = 0.0
        space.add(body, shape)
        if self.space is not None:
            # detach the car now, so that the old space's clean-up has no contacts left
            # to report through callbacks while it is garbage-collected
            self.space.remove(self._body, self._shape)
        self.space, self._body, self._shape = space, body, shape

        touching: dict = {}  # per space, so the old space's clean-up cannot touch the new log

        def wall_of(arbiter: pymunk.Arbiter) -> tuple:
            a, b = arbiter.shapes  # (car, wall) as registered, but not promised on clean-up
            return kinds[b] if b in kinds else kinds[a]

        def begin(arbiter: pymunk.Arbiter, _space, _data) -> None:
            key = wall_of(arbiter)
            touching[key] = touching.get(key, 0) + 1
            if touching[key] == 1:
                pts = arbiter.contact_point_set.points
                px = sum(p.point_b.x for p in pts) / len(pts)
                py = sum(p.point_b.y for p in pts) / len(pts)
                self.collisions.append({"time": self._step_end, "x": float(px), "y": float(py),
                                        "shape": key[0], "index": key[1]})

        def separate(arbiter: pymunk.Arbiter, _space, _data) -> None:
            key = wall_of(arbiter)
            touching[key] = touching.get(key, 1) - 1

        for ctype in (_WALL, _OBSTACLE):
            space.on_collision(_CAR, ctype, begin=begin, separate=separate)

    def reset(self, pose, rng: np.random.Generator) -> None:
        """Place the car at `pose` at rest and restart the clock, odometer and noise.

        Parameters
        ----------
        pose : array_like, shape (3,)
            ``(x, y, theta)``: centre in cm, heading in radians.
        rng : numpy.random.Generator
            Source of the actuation noise for the episode; the car keeps it. The noise
            processes start from their stationary distribution.

        Raises
        ------
        ArenaError
            If the pose is malformed or the car body would overlap a wall.
        """
        p = np.asarray(pose, dtype=float).ravel()
        if p.shape != (3,) or not np.all(np.isfinite(p)):
            raise ArenaError(f"pose must be three finite numbers (x cm, y cm, theta rad); got {pose!r}")
        if not isinstance(rng, np.random.Generator):
            raise ArenaError(f"rng must be a numpy.random.Generator (np.random.default_rng(seed)); "
                             f"got {type(rng).__name__}")
        x, y, theta = float(p[0]), float(p[1]), float(p[2]) % _TWO_PI
        body = Polygon(car_footprint((x, y, theta), self.spec.length, self.spec.width))
        if body.difference(self._free).area > 1e-6:
            gap = "outside the arena" if not self.arena.contains((x, y))[0] else "overlapping a wall"
            raise ArenaError(
                f"a car at ({x:.4g}, {y:.4g}, {theta:.3g} rad) would be {gap}; place its centre "
                f"at least {math.hypot(self.spec.length, self.spec.width) / 2:.2f} cm from walls")
        self._rng = rng
        self.time = 0.0
        self.odometer = 0.0
        self.collisions = []
        self._step_end = 0.0
        self._n_steer = self.spec.steer_noise * float(rng.standard_normal())
        self._n_speed = self.spec.speed_noise * float(rng.standard_normal())
        self._build_space(x, y, theta)

    # ------------------------------------------------------------------ state
    def _require_reset(self) -> pymunk.Body:
        if self._body is None:
            raise ArenaError("the car has not been placed yet; call car.reset(pose, rng) first")
        return self._body

    @property
    def pose(self) -> np.ndarray:
        """True pose ``(x, y, theta)``: cm, cm, radians in [0, 2 pi)."""
        body = self._require_reset()
        x, y = body.position
        return np.array([x, y, body.angle % _TWO_PI])

    @property
    def velocity(self) -> np.ndarray:
        """``(forward, sideways)`` velocity in the car frame, cm/s (sideways positive left)."""
        body = self._require_reset()
        vx, vy = body.velocity
        c, s = math.cos(body.angle), math.sin(body.angle)
        return np.array([vx * c + vy * s, -vx * s + vy * c])

    def footprint(self) -> np.ndarray:
        """Corners of the car body at its true pose, shape (4, 2), cm."""
        return car_footprint(self.pose, self.spec.length, self.spec.width)

    # ------------------------------------------------------------------ driving
    def drive(self, steer: float, direction: int, duration: float) -> None:
        """Drive with a fixed command for `duration` seconds.

        Advances ``ceil(duration / dt - 1e-9)`` physics steps of ``spec.dt``.

        Parameters
        ----------
        steer : float
            Steering in [-1, 1]; +1 is full left (curvature ``1 / rho``), -1 full right.
        direction : int
            +1 forward, -1 reverse, 0 brake to rest.
        duration : float
            Seconds to drive, >= 0.

        Raises
        ------
        ArenaError
            If a command is out of range or :meth:`reset` was not called.
        """
        body = self._require_reset()
        try:
            steer = float(steer)
        except (TypeError, ValueError) as exc:
            raise ArenaError(f"steer must be a number in [-1, 1]; got {steer!r}") from exc
        if not (math.isfinite(steer) and -1.0 <= steer <= 1.0):
            raise ArenaError(f"steer must be a finite number in [-1, 1] (+1 = full left); got {steer!r}")
        if not _is_number(direction) or direction not in (-1, 0, 1):
            raise ArenaError(f"direction must be +1 (forward), -1 (reverse) or 0 (stop); got {direction!r}")
        try:
            duration = float(duration)
        except (TypeError, ValueError) as exc:
            raise ArenaError(f"duration must be a number of seconds >= 0; got {duration!r}") from exc
        if not (math.isfinite(duration) and duration >= 0):
            raise ArenaError(f"duration must be a finite number of seconds >= 0; got {duration!r}")
        spec = self.spec
        dt = spec.dt
        n = math.ceil(duration / dt - 1e-9)
        if n <= 0:
            return
        kicks = self._rng.standard_normal((n, 2)).tolist()
        # The commands act as a force and a torque, not as velocities set directly:
        # pymunk integrates positions before it solves contacts, so a velocity set
        # into a wall would push the car a little further into it every step.
        step, cos, sin, hypot = self.space.step, math.cos, math.sin, math.hypot
        decay, kick = self._ou_decay, self._ou_kick
        kick_s, kick_v = kick * spec.steer_noise, kick * spec.speed_noise
        gain, slip, inv_rho = self._servo_gain, self._grip_decay - 1.0, 1.0 / spec.rho
        m_dt, i_dt = body.mass / dt, body.moment / dt
        target0 = direction * spec.speed
        n_s, n_v = self._n_steer, self._n_speed
        t, odo = self.time, self.odometer
        for k_s, k_v in kicks:  # ~10^4 steps per episode: keep this loop lean
            n_s = decay * n_s + kick_s * k_s
            n_v = decay * n_v + kick_v * k_v
            vx, vy = body.velocity
            odo += hypot(vx, vy) * dt  # pymunk moves the body with this velocity first
            a = body.angle
            c, s = cos(a), sin(a)
            v = vx * c + vy * s
            dv = (target0 * (1.0 + n_v) - v) * gain  # speed servo along the axis
            dw = (vy * c - vx * s) * slip  # tyres remove part of the sideways velocity
            body.force = (m_dt * (dv * c - dw * s), m_dt * (dv * s + dw * c))
            body.torque = i_dt * ((v + dv) * (steer + n_s) * inv_rho - body.angular_velocity)
            t += dt
            self._step_end = t
            step(dt)
        self._n_steer, self._n_speed = n_s, n_v
        self.time, self.odometer = t, odo


def _wall_segments(static_body: pymunk.Body, ring: np.ndarray, ctype: int) -> list:
    """Closed polyline of static segments along `ring`, with neighbours set so the car
    slides over the joints instead of catching on them."""
    pts = [tuple(map(float, p)) for p in ring]
    n = len(pts)
    segs = []
    for i in range(n):
        seg = pymunk.Segment(static_body, pts[i], pts[(i + 1) % n], WALL_RADIUS)
        seg.set_neighbors(pts[i - 1], pts[(i + 2) % n])
        seg.collision_type = ctype
        seg.friction = 0.3
        seg.elasticity = 0.0
        segs.append(seg)
    return segs
