"""One call from names to a finished episode: what the command line and benchmarks use."""

from __future__ import annotations

from dataclasses import fields
from functools import lru_cache

import numpy as np

from arenas import Arena, CarSpec, Floor, Testbed, render_floor

from .episode import Episode, run_episode
from .errors import SearchError
from .green import GreenSolver
from .car_platform import CarPlatform, DrivingOptions
from .platforms import Platform, PointPlatform
from .strategies import STRATEGIES, Strategy

__all__ = ["PLATFORMS", "make_strategy", "make_car_platform", "search", "cached_solver",
           "cached_floor", "TRUTH_MESH_RATIO", "CAR_KEYS"]

PLATFORMS = ("point", "car")

#: The true signal is computed on a mesh this much finer than the strategy's, so the
#: data do not come from the very model that inverts them (no "inverse crime").
TRUTH_MESH_RATIO = 0.7


@lru_cache(maxsize=8)
def cached_solver(arena: Arena, h: float, order: int = 1) -> GreenSolver:
    """A :class:`GreenSolver` shared across episodes on the same arena object."""
    return GreenSolver(arena, h=h, order=order)


@lru_cache(maxsize=4)
def _floor(arena: Arena, source: tuple, strength: float, h: float, px_per_mm: float) -> Floor:
    field = cached_solver(arena, h).field(np.array(source), strength)
    return render_floor(arena, field, px_per_mm=px_per_mm)


def cached_floor(arena: Arena, source, strength: float, *, h: float = 1.0 * TRUTH_MESH_RATIO,
                 px_per_mm: float = 1.0) -> Floor:
    """The testbed floor painted from the true field (FEM mesh size `h` cm), cached."""
    return _floor(arena.without_scenario(), tuple(float(v) for v in source), float(strength),
                  float(h), float(px_per_mm))


#: Keys accepted by :func:`make_car_platform` (and ``search(car=...)``): the driving
#: options, the car's specification and the floor resolution.
CAR_KEYS = tuple(f.name for f in fields(DrivingOptions)) + tuple(f.name for f in fields(CarSpec)) + (
    "px_per_mm",)


def make_car_platform(arena: Arena, *, h: float = 1.0, progress: bool = False, **car) -> CarPlatform:
    """The car observer on `arena` (with its true source and strength set).

    Parameters
    ----------
    arena : Arena
        With its true source and strength.
    h : float
        Mesh size of the strategy; the floor is painted from a field on a mesh
        :data:`TRUTH_MESH_RATIO` times finer.
    progress : bool
        Progress bar while a value-function bank is built.
    **car
        Any of :data:`CAR_KEYS`: :class:`DrivingOptions` fields (``planner``,
        ``replan_every``, ...), :class:`arenas.CarSpec` fields (``rho``, ``speed``, ...),
        and ``px_per_mm``, the floor resolution.
    """
    unknown = sorted(set(car) - set(CAR_KEYS))
    if unknown:
        raise SearchError(f"unknown car option(s) {', '.join(unknown)}; choose from {', '.join(CAR_KEYS)}")
    drive_keys = {f.name for f in fields(DrivingOptions)}
    spec_keys = {f.name for f in fields(CarSpec)}
    try:
        options = DrivingOptions(**{k: v for k, v in car.items() if k in drive_keys})
        spec = CarSpec(**{k: v for k, v in car.items() if k in spec_keys})
    except TypeError as exc:
        raise SearchError(f"bad car option: {exc}") from None
    floor = cached_floor(arena, arena.source, arena.strength, h=h * TRUTH_MESH_RATIO,
                         px_per_mm=float(car.get("px_per_mm", 1.0)))
    return CarPlatform(Testbed(arena, floor, car=spec), arena.source, options, progress=progress)


def make_strategy(name: str, solver: GreenSolver | None = None, **params) -> Strategy:
    """Build the strategy called `name` (see :data:`reciprocity.STRATEGIES`)."""
    if name not in STRATEGIES:
        raise SearchError(f"unknown strategy {name!r}; choose one of {', '.join(STRATEGIES)}")
    try:
        return STRATEGIES[name](solver=solver, **params)
    except TypeError as exc:
        raise SearchError(f"bad parameter for strategy {name!r}: {exc}") from None


def search(arena: Arena, strategy: str = "reciprocity", *, source=None,
           strength: float | None = None, start=None, platform: str = "point",
           seed: int = 0, noise: float = 12.0, h: float = 1.0, params: dict | None = None,
           car: dict | None = None, progress=None) -> tuple[Episode, Strategy, Platform]:
    """Run one episode by names.

    Parameters
    ----------
    arena : Arena
        The arena; its true source, strength and start are the defaults.
    strategy : str
        ``"reciprocity"`` or ``"gradient"``.
    source : array_like, shape (2,), optional
        True source, cm.
    strength : float, optional
        True source strength ``c``.
    start : array_like, shape (2,) or (3,), optional
        Start pose (x, y cm[, heading rad]).
    platform : {"point", "car"}
        The observer.
    seed : int
        Episode seed.
    noise : float
        Measurement noise standard deviation, signal units.
    h : float
        Mesh size of the strategy's solver, cm.
    params : dict, optional
        Strategy parameters. On the car the strategy's ``clearance`` defaults to the
        car's, so that it only proposes points where the car can stand, and the gradient
        strategy's ``i_max`` to the top of the sensor's working range (it stops once the
        sensor saturates, the paper's rule).
    car : dict, optional
        Car options (see :func:`make_car_platform`); only with ``platform="car"``.
    progress : callable, optional
        Per-step callback.

    Returns
    -------
    (Episode, Strategy, Platform)
    """
    if platform not in PLATFORMS:
        raise SearchError(f"unknown platform {platform!r}; choose one of {PLATFORMS}")
    if car and platform != "car":
        raise SearchError("car options need platform='car'")
    arena = arena.with_scenario(source=source, strength=strength, start=start)
    if arena.source is None:
        raise SearchError(f"arena {arena.name!r} has no true source: pass source=(x, y)")
    solver = cached_solver(arena.without_scenario(), float(h))
    truth = cached_solver(arena.without_scenario(), float(h) * TRUTH_MESH_RATIO)
    params = dict(params or {})
    if platform == "car":
        plat = make_car_platform(arena, h=float(h), progress=progress is not None, **(car or {}))
        params.setdefault("clearance", plat.options.clearance)
        if strategy == "gradient":
            # the paper's stop rule, I_max: the top of the sensor's working range (the signal
            # painted at grey 185). Above it the sensor saturates: the car is within a few
            # cm of the source and no reading can tell it more.
            params.setdefault("i_max", plat.testbed.floor.mapping.u_max)
    else:
        plat = PointPlatform(truth, arena.source, arena.strength, noise)
    strat = make_strategy(strategy, solver, **params)
    episode = run_episode(arena, strat, plat, start=arena.start, seed=seed, progress=progress)
    return episode, strat, plat
