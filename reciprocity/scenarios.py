"""Scenarios: a world and its parameters, by name or from a YAML file."""

from __future__ import annotations

from dataclasses import dataclass, field

import arenas

from .errors import SearchError

__all__ = ["Scenario", "load_scenario", "scenario_names"]


@dataclass
class Scenario:
    """A named world with its parameters (see ``reciprocity scenarios``)."""

    name: str
    world: str
    params: dict = field(default_factory=dict)
    platform: str = "point"
    success_radius: float = 5.0
    arena: arenas.Arena | None = None


def scenario_names() -> list[str]:
    """Names of the built-in scenarios."""
    return list(arenas.builtin_names())


def load_scenario(name_or_path) -> Scenario:
    """The built-in scenario `name_or_path`, or one read from a YAML file."""
    try:
        arena = arenas.load(name_or_path)
    except arenas.ArenaError as exc:
        raise SearchError(str(exc)) from None
    return Scenario(arena.name, "poisson", {}, "point", 5.0, arena)
