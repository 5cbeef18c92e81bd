"""One call from names to a finished episode: what the command line and benchmarks use."""

from __future__ import annotations

from functools import lru_cache


from arenas import Arena

from .episode import Episode, run_episode
from .errors import SearchError
from .green import GreenSolver
from .platforms import PointPlatform
from .strategies import STRATEGIES, Strategy

__all__ = ["PLATFORMS", "make_strategy", "search", "cached_solver", "TRUTH_MESH_RATIO"]

PLATFORMS = ("point", "car")

#: The true signal is computed on a mesh this much finer than the strategy's, so the
#: data do not come from the very model that inverts them (no "inverse crime").
TRUTH_MESH_RATIO = 0.7


@lru_cache(maxsize=8)
def cached_solver(arena: Arena, h: float, order: int = 1) -> GreenSolver:
    """A :class:`GreenSolver` shared across episodes on the same arena object."""
    return GreenSolver(arena, h=h, order=order)


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
           progress=None) -> tuple[Episode, Strategy, PointPlatform]:
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
        Strategy parameters.
    progress : callable, optional
        Per-step callback.

    Returns
    -------
    (Episode, Strategy, Platform)
    """
    if platform not in PLATFORMS:
        raise SearchError(f"unknown platform {platform!r}; choose one of {PLATFORMS}")
    if platform == "car":
        raise SearchError("the car platform needs the simulated testbed, which is not built "
                          "yet; use --platform point")
    arena = arena.with_scenario(source=source, strength=strength, start=start)
    if arena.source is None:
        raise SearchError(f"arena {arena.name!r} has no true source: pass source=(x, y)")
    solver = cached_solver(arena.without_scenario(), float(h))
    truth = cached_solver(arena.without_scenario(), float(h) * TRUTH_MESH_RATIO)
    strat = make_strategy(strategy, solver, **(params or {}))
    plat = PointPlatform(truth, arena.source, arena.strength, noise)
    episode = run_episode(arena, strat, plat, start=arena.start, seed=seed, progress=progress)
    return episode, strat, plat
