"""One call from names to a finished episode: the entry point campaigns, the command line
and benchmarks share.

:func:`check` validates a (scenario, strategy, platform, parameters) combination without
any heavy work (no meshing, no factorization); :func:`run` runs one episode;
:func:`execute` also returns the strategy and platforms (for figures and videos).
"""

from __future__ import annotations

import inspect
from dataclasses import replace

import numpy as np

from arenas import Arena

from .env.spec import (EpisodeSpec, check_team, checked_agents, checked_options_and_limits, checked_platform,
                       checked_seed)
from .episode import Episode
from .errors import SearchError
from .scenarios import Scenario, load_scenario
from .strategies import STRATEGIES, Strategy
from .strategies.agent import with_limits
from .strategies.parameter_bounds import STRATEGY_BOUNDS
from .validation import check_bounds

__all__ = ["run", "check", "execute", "make_strategy", "strategy_parameters", "EpisodeSpec"]


def strategy_parameters(name: str) -> list[str]:
    """The parameter names strategy `name` accepts."""
    return _parameters(STRATEGIES[name])


def _parameters(cls: type) -> list[str]:
    """The parameter names strategy class `cls` accepts (its keyword-only ones)."""
    sig = inspect.signature(cls.__init__)
    return [p.name for p in sig.parameters.values() if p.kind is p.KEYWORD_ONLY]


def _checked_params(cls: type, name: str, params: dict) -> None:
    """Refuse parameters strategy `name` (class `cls`) does not take, or out of their bounds."""
    valid = _parameters(cls)
    unknown = sorted(set(params) - set(valid))
    if unknown:
        raise SearchError(f"unknown parameter(s) {', '.join(unknown)} for strategy {name!r}; "
                          f"valid: {', '.join(valid)}")
    check_bounds(params, STRATEGY_BOUNDS.get(name, {}), where=f"strategy {name!r}: ")


def _strategy_class(name: str) -> type:
    cls = STRATEGIES.get(name)              # one look-up (the registry imports on first use)
    if cls is None:
        raise SearchError(f"unknown strategy {name!r}; choose one of {', '.join(STRATEGIES)}")
    return cls


def make_strategy(name: str, **params) -> Strategy:
    """Build the strategy called `name` (see :data:`reciprocity.strategies.STRATEGIES`);
    an unknown or invalid parameter raises SearchError naming the valid ones."""
    cls = _strategy_class(name)
    _checked_params(cls, name, params)
    return _built(cls, name, params)


def _built(cls: type, name: str, params: dict) -> Strategy:
    try:
        return cls(**params)
    except (TypeError, ValueError) as exc:
        raise SearchError(f"bad parameter for strategy {name!r}: {exc}") from None


def check(scenario: str | Scenario | Arena | EpisodeSpec, strategy: str, *, params: dict | None = None,
          platform: str | None = None, agents: int | None = None, world: dict | None = None,
          platform_options: dict | None = None, seeds=()) -> EpisodeSpec:
    """Validate an episode before any heavy work, once: the one :class:`EpisodeSpec`
    every front door builds and :class:`~reciprocity.env.SearchEnv` and the strategy's
    agent take without checking again.

    Parameters
    ----------
    scenario : str, Scenario, arenas.Arena or EpisodeSpec
        A built-in scenario name, a YAML file, a Scenario, or an arena; an EpisodeSpec
        already checked for `strategy` is returned as it is (with `seeds` added); another
        spec (e.g. an environment's alone) is checked for `strategy` with its scenario,
        platform and options (and its number of observers when it names no strategy).
    strategy : str
        A strategy name (``reciprocity strategies``).
    params, platform, agents, world, platform_options
        As :func:`run`.
    seeds : int or iterable of int
        Episode seeds to check with the spec (whole numbers >= 0).

    Returns
    -------
    EpisodeSpec
        Its ``scenario`` has the world overrides applied. The strategy it was checked by
        building is handed to the first episode's agent (a run builds it once).

    Raises
    ------
    SearchError
        Unknown scenario or strategy, a strategy that does not apply to the scenario's
        world, an unknown or invalid parameter, platform, platform option, agent count
        or seed.
    """
    seeds = tuple(checked_seed(s) for s in ((seeds,) if isinstance(seeds, (int, np.integer)) else seeds))
    if isinstance(scenario, EpisodeSpec) and scenario.strategy == strategy and \
            not (params or platform or agents is not None or world or platform_options):
        return replace(scenario, seeds=tuple(dict.fromkeys(scenario.seeds + seeds)))
    if isinstance(scenario, EpisodeSpec):              # another strategy, or overrides: its own choices kept
        platform = platform or scenario.platform
        agents = scenario.agents if agents is None and scenario.strategy is None else agents
        platform_options = platform_options or dict(scenario.platform_options)
        scenario = scenario.scenario
    sc = scenario if isinstance(scenario, Scenario) else load_scenario(scenario)
    sc = sc.with_world(world)
    cls = _strategy_class(strategy)
    if sc.world not in cls.worlds:
        fits = [n for n, c in STRATEGIES.items() if sc.world in c.worlds]
        raise SearchError(f"strategy {strategy!r} does not apply to scenario {sc.name!r} ({sc.world} world); "
                          f"strategies for {sc.world} worlds: {', '.join(fits)}")
    plat = checked_platform(sc, platform)
    n = _agents(cls, sc, agents)
    check_team(sc, n)
    params = dict(params or {})
    _checked_params(cls, strategy, params)
    options, limits = checked_options_and_limits(sc, plat, platform_options)
    build = with_limits(cls, params, limits) if limits else params    # as the agent will: built once
    built = _built(cls, strategy, build)
    spec = EpisodeSpec(sc, plat, n, options, strategy, cls, params, seeds)
    spec._built.append((built, build))
    return spec


def _agents(cls, sc: Scenario, agents: int | None) -> int:
    if agents is None:
        return cls.agents or sc.agents
    agents = checked_agents(agents)
    if cls.agents is not None and agents != cls.agents:
        raise SearchError(f"strategy {cls.name!r} directs {cls.agents} observer(s); got agents={agents}")
    return agents


def execute(scenario: str | Scenario | Arena | EpisodeSpec, strategy: str | None = None, *, seed: int = 0,
            params: dict | None = None, platform: str | None = None, agents: int | None = None,
            world: dict | None = None, platform_options: dict | None = None, progress=None,
            figures: bool = False):
    """Like :func:`run`, but return ``(episode, strategy, platforms)``.

    The episode runs as every episode does: a :class:`~reciprocity.env.SearchEnv` (the
    truth) driven by :func:`~reciprocity.env.rollout` with the strategy as its agent,
    both built from the one :class:`EpisodeSpec` of :func:`check`.
    """
    from .env import SearchEnv, rollout
    from .strategies.agent import StrategyAgent
    if isinstance(scenario, EpisodeSpec) and strategy in (None, scenario.strategy) and type(seed) is int \
            and seed in scenario.seeds and not (params or platform or agents is not None or world or platform_options):
        spec = scenario                                 # checked already, with this seed
    else:
        spec = check(scenario, strategy or getattr(scenario, "strategy", None), params=params, platform=platform,
                     agents=agents, world=world, platform_options=platform_options, seeds=seed)
    env = SearchEnv(spec)
    agent = StrategyAgent(spec, figures=figures)
    episode = rollout(env, agent, seed, progress=progress, figures=figures,
                      options={"progress": True} if progress is not None else None)
    return episode, agent.strategy, env.platforms


def run(scenario: str | Scenario | Arena | EpisodeSpec, strategy: str | None = None, *, seed: int = 0, params: dict | None = None,
        platform: str | None = None, agents: int | None = None, world: dict | None = None,
        platform_options: dict | None = None, progress=None, figures: bool = False) -> Episode:
    """Run one episode of `strategy` in `scenario`.

    Parameters
    ----------
    scenario : str, Scenario, arenas.Arena or EpisodeSpec
        A built-in scenario name (``reciprocity scenarios``), a YAML file, a Scenario, an
        arena (a poisson scenario with the arena's source, strength and start), or the
        spec :func:`check` returned (then nothing is checked again).
    strategy : str, optional
        A strategy name (``reciprocity strategies``); with a spec, its own.
    seed : int
        Episode seed (the world's random parts, noise, motion, the strategy's draws).
    params : dict, optional
        Strategy parameters.
    platform : str, optional
        ``"point"``, ``"car"``, ``"walker"``, ...; default: the scenario's.
    agents : int, optional
        Number of observers; default: the strategy's (or the scenario's).
    world : dict, optional
        Overrides of the scenario's world parameters (e.g. ``source``, ``strength``,
        ``noise``, ``mismatch``) and ``start``.
    platform_options : dict, optional
        Options of the platform (car: :data:`reciprocity.platforms.car.CAR_KEYS`).
    progress : callable, optional
        Called with each step record.
    figures : bool
        Keep what the figures draw in the episode (:attr:`Episode.belief`,
        :attr:`Episode.truth`; :func:`reciprocity.viz.episode.episode_figures` draws them).

    Returns
    -------
    Episode
        ``episode.summary`` holds the contract keys (:data:`reciprocity.episode.SUMMARY_KEYS`).

    Examples
    --------
    >>> from reciprocity.api import run
    >>> s = run("empty", "reciprocity", seed=1, params={"h": 4.0}).summary
    >>> s["world"], s["converged"] in (True, False)
    ('poisson', True)
    """
    return execute(scenario, strategy, seed=seed, params=params, platform=platform, agents=agents,
                   world=world, platform_options=platform_options, progress=progress, figures=figures)[0]
