"""One call from an arena to a finished episode (the arena-centred convenience of
:mod:`reciprocity.api`, kept for scripts and examples)."""

from __future__ import annotations

from arenas import Arena

from .api import execute, make_strategy
from .episode import Episode
from .errors import SearchError
from .platforms.base import Platform
from .platforms.car import CAR_KEYS
from .scenarios import Scenario
from .strategies import Strategy
from .models.green import cached_solver
from .worlds.poisson import TRUTH_MESH_RATIO

__all__ = ["PLATFORMS", "CAR_KEYS", "TRUTH_MESH_RATIO", "cached_solver", "make_strategy", "search"]

#: Platforms of arena (poisson) worlds.
PLATFORMS = ("point", "car")


def search(arena: Arena, strategy: str = "reciprocity", *, source=None,
           strength: float | None = None, start=None, platform: str = "point",
           seed: int = 0, noise: float = 12.0, h: float = 1.0, params: dict | None = None,
           car: dict | None = None, mismatch: dict | None = None,
           progress=None) -> tuple[Episode, Strategy, Platform]:
    """Run one episode on `arena` by names.

    Parameters
    ----------
    arena : Arena
        The arena; its true source, strength and start are the defaults.
    strategy : str
        A strategy for poisson worlds (``"reciprocity"``, ``"gradient"``, ...).
    source : array_like, shape (2,), optional
        True source, cm.
    strength : float, optional
        True source strength ``c`` (also what the strategy is told, unless a
        ``mismatch`` says otherwise).
    start : array_like, shape (2,) or (3,), optional
        Start pose (x, y cm[, heading rad]).
    platform : {"point", "car"}
        The observer.
    seed : int
        Episode seed.
    noise : float
        Measurement noise standard deviation, signal units (point observer).
    h : float
        Mesh size of the strategy, cm (the truth's is :data:`TRUTH_MESH_RATIO` × `h`).
    params : dict, optional
        Strategy parameters. On the car the strategy's ``clearance`` defaults to the
        car's and the gradient strategy's ``i_max`` to the top of the sensor's range.
    car : dict, optional
        Car options (:data:`CAR_KEYS`); only with ``platform="car"``.
    mismatch : dict, optional
        How the truth departs from the arena the strategy is told
        (:class:`reciprocity.worlds.Mismatch`).
    progress : callable, optional
        Per-step callback.

    Returns
    -------
    (Episode, Strategy, Platform)
    """
    if platform not in PLATFORMS:
        raise SearchError(f"unknown platform {platform!r}; choose one of {', '.join(PLATFORMS)}")
    if car and platform != "car":
        raise SearchError("car options need platform='car'")
    world = dict(arena=arena, noise=noise, truth_h=float(h) * TRUTH_MESH_RATIO, mismatch=mismatch or {})
    if source is not None:
        world["source"] = source
    if strength is not None:
        world["strength"] = strength
    sc = Scenario(arena.name, "poisson", {}, platform)
    sc = sc.with_world(world)
    if start is not None:
        sc = sc.with_world({"start": start})
    elif arena.start is not None:
        sc = sc.with_world({"start": arena.start})
    params = dict(params or {})
    if "h" in _accepted(strategy):
        params.setdefault("h", float(h))
    episode, strat, plats = execute(sc, strategy, seed=seed, params=params, platform=platform,
                                    platform_options=car, progress=progress)
    return episode, strat, plats[0]


def _accepted(strategy: str) -> list[str]:
    from .api import strategy_parameters
    from .strategies import STRATEGIES
    return strategy_parameters(strategy) if strategy in STRATEGIES else []
