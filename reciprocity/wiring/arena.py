"""The ``arena`` key of the arena scenarios (``poisson``, ``flow``)."""

from __future__ import annotations

import numpy as np

import arenas
from arenas import Arena

from ..errors import SearchError

__all__ = ["scenario_arena", "check_start", "default_start"]


def scenario_arena(value, world: str) -> Arena:
    """The arena a scenario's ``arena`` key names: an :class:`~arenas.Arena`, a mapping (the
    arena file's keys), or a built-in name or file path. Raises ``arenas.ArenaError`` on a
    bad arena and :class:`SearchError` when there is none; `world` names the kind in the
    message."""
    if isinstance(value, Arena):
        return value
    if isinstance(value, dict):
        return arenas.from_dict(value, where="scenario arena")
    if value is None:
        raise SearchError(f"a {world} scenario needs an arena: a built-in name, a file or a mapping")
    return arenas.load(value)


def check_start(params: dict, starts: np.ndarray) -> None:
    """Refuse a start (rows x, y[, heading], cm) outside the free region of ``params["arena"]``."""
    arena = params["arena"]
    inside = arena.contains(starts[:, :2])
    if not np.all(inside):
        s = starts[int(np.argmin(inside))]
        raise SearchError(f"start ({s[0]:g}, {s[1]:g}) cm is outside the free region of arena {arena.name!r} "
                          "(outside the boundary or inside an obstacle)")


def default_start(world, rng: np.random.Generator) -> np.ndarray:
    """The start of an arena world (x, y cm, heading rad): the arena's own, else a free
    point at least 5 cm from every wall with a random heading."""
    if world.arena.start is not None:
        return world.arena.start.copy()
    p = world.arena.random_free_points(1, rng, clearance=5.0)[0]
    return np.array([p[0], p[1], rng.uniform(0, 2 * np.pi)])
