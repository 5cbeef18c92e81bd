"""One episode, validated once: :class:`EpisodeSpec`.

A front door (the command line, a campaign worker, the Gymnasium and PettingZoo faces,
:func:`reciprocity.api.run`) parses what it is given into one ``EpisodeSpec`` with
:func:`reciprocity.api.check`; :class:`~reciprocity.env.SearchEnv` and the strategy's
agent take it and check nothing again. Each message about a bad combination is written
here, or in :mod:`reciprocity.api` for the strategy's part, and nowhere else.

The environment's part (:func:`environment_spec`: the scenario with its world overrides,
the platform, the number of observers, the platform's options) is checked here, below
the strategies, so that a :class:`~reciprocity.env.SearchEnv` built from a bare scenario
checks it in the same words.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any, Mapping

import numpy as np

from ..errors import SearchError
from ..scenarios import Scenario, load_scenario
from ..validation import MAX_AGENTS, whole

__all__ = ["EpisodeSpec", "environment_spec", "checked_seed", "checked_agents", "checked_platform", "check_team",
           "checked_options"]



def checked_seed(seed) -> int:
    """`seed` as an episode seed (a whole number >= 0); SearchError otherwise."""
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise SearchError(f"seed must be a non-negative whole number; got {seed!r}")
    return int(seed)


def checked_agents(agents) -> int:
    """`agents` as a number of observers, from 1 to :data:`~reciprocity.validation.MAX_AGENTS`."""
    return whole(agents, "agents", 1, MAX_AGENTS)


@dataclass(frozen=True)
class EpisodeSpec:
    """The validated, immutable description of an episode (or of a campaign's episodes
    of one variant): what :class:`~reciprocity.env.SearchEnv` and
    :class:`~reciprocity.strategies.agent.StrategyAgent` take without checking again.

    Build it with :func:`reciprocity.api.check` (a strategy's episode) or
    :func:`environment_spec` (the environment alone, e.g. for an outside policy).

    Attributes
    ----------
    scenario : Scenario
        The scenario with the world overrides applied (checked).
    platform : str
        The platform's name (one of the world kind's).
    agents : int
        Number of observers.
    platform_options : Mapping
        The platform's options (the car's: checked against
        :data:`reciprocity.platforms.car.CAR_KEYS`).
    strategy : str or None
        The strategy's registered name (None: an environment alone).
    strategy_class : type or None
        Its class (:data:`reciprocity.strategies.STRATEGIES`).
    params : Mapping
        The strategy's parameters (names and bounds checked).
    seeds : tuple of int
        Episode seeds checked with the spec (whole numbers >= 0); a seed among them is not
        checked again when an episode starts.
    """

    scenario: Scenario
    platform: str
    agents: int
    platform_options: Mapping[str, Any] = field(default_factory=dict)
    strategy: str | None = None
    strategy_class: type | None = None
    params: Mapping[str, Any] = field(default_factory=dict)
    seeds: tuple[int, ...] = ()
    # the strategy that checking its parameters built, with the parameters it was built
    # with (the spec's and the platform limits known at the check): handed to the first
    # agent that asks for it with equal parameters, so that a run builds its strategy once
    _built: list = field(default_factory=list, compare=False, repr=False)

    def __post_init__(self):
        object.__setattr__(self, "platform_options", MappingProxyType(dict(self.platform_options)))
        object.__setattr__(self, "params", MappingProxyType(dict(self.params)))
        object.__setattr__(self, "seeds", tuple(self.seeds))

    @property
    def name(self) -> str:
        """The scenario's name."""
        return self.scenario.name

    def take_strategy(self, params: Mapping[str, Any]):
        """The strategy built while checking, once, when `params` (the spec's, with the
        limits the task adds) equal those it was built with, key for key and value for
        value; else None (the caller builds its own)."""
        if self._built and _same_params(params, self._built[-1][1]):
            return self._built.pop()[0]
        return None

    def with_scenario(self, scenario: Scenario) -> "EpisodeSpec":
        """The same spec for another draw of its scenario's world (the Gymnasium face's
        ``random_source``: a source and start drawn per episode, checked by
        :meth:`Scenario.with_world`)."""
        return EpisodeSpec(scenario, self.platform, self.agents, self.platform_options, self.strategy,
                           self.strategy_class, self.params, self.seeds)


def _same_params(a: Mapping[str, Any], b: Mapping[str, Any]) -> bool:
    """Whether two parameter sets have the same keys and each the same value (the same
    object, or equal numbers and strings; anything that compares otherwise is not)."""
    if set(a) != set(b):
        return False
    for key, value in a.items():
        other = b[key]
        if value is other:
            continue
        try:
            if not (type(value) is type(other) and bool(value == other)):
                return False
        except (TypeError, ValueError):                 # arrays and the like
            return False
    return True


def checked_platform(sc: Scenario, platform: str | None) -> str:
    """`platform` (None: the scenario's), one of the scenario's world kind's platforms."""
    plat = platform or sc.platform
    if plat not in sc.kind.platforms:
        raise SearchError(f"platform {plat!r} does not apply to {sc.world} worlds; choose one of "
                          f"{', '.join(sc.kind.platforms)}")
    return plat


def check_team(sc: Scenario, n: int) -> None:
    """Refuse `n` observers the scenario cannot start: its world's own conditions, and
    start poses that are neither one (shared) nor one per observer."""
    sc.check_observers(n)
    if sc.starts is not None and 1 < len(sc.starts) < n:
        raise SearchError(f"scenario {sc.name!r} gives {len(sc.starts)} start poses for {n} agents; give "
                          "one pose (shared) or one per agent")


def checked_options(sc: Scenario, platform: str, options: dict | None) -> dict:
    """The platform's options, checked (the car's against its keys and the arena)."""
    return checked_options_and_limits(sc, platform, options)[0]


def checked_options_and_limits(sc: Scenario, platform: str, options: dict | None) -> tuple[dict, dict]:
    """:func:`checked_options`, and the task limits they fix before any episode: on the
    car its ``clearance`` (cm), the value :class:`~reciprocity.env.SearchEnv` puts in
    every episode's ``Task.limits``. (The sensor's ``i_max`` comes from the episode's
    calibrated floor, so only an episode knows it.)"""
    options = dict(options or {})
    if platform == "car":
        from ..platforms.car import check_car_options
        driving = check_car_options(dict(options), sc.arena)[0]
        return options, {"clearance": float(driving.clearance)}
    return options, {}


def environment_spec(scenario, *, platform: str | None = None, agents: int | None = None,
                     world: dict | None = None, platform_options: dict | None = None) -> EpisodeSpec:
    """The environment's part of an episode, checked: the scenario (a name, a file, a
    :class:`Scenario` or an :class:`arenas.Arena`) with the `world` overrides, the platform,
    `agents` observers (None: the scenario's) and the platform's options.

    Raises
    ------
    SearchError
        A platform that does not apply to the world, a bad number of observers, start
        poses that are neither one (shared) nor one per observer, bad car options.
    """
    sc = scenario if isinstance(scenario, Scenario) else load_scenario(scenario)
    sc = sc.with_world(world)
    plat = checked_platform(sc, platform)
    n = checked_agents(sc.agents if agents is None else agents)
    check_team(sc, n)
    return EpisodeSpec(sc, plat, n, checked_options(sc, plat, platform_options))
