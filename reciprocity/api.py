"""One call from names to a finished episode: the entry point campaigns, the command line
and benchmarks share.

:func:`check` validates a (scenario, strategy, platform, parameters) combination without
any heavy work (no meshing, no factorization); :func:`run` runs one episode;
:func:`execute` also returns the strategy and platforms (for figures and videos).
"""

from __future__ import annotations

import inspect

from arenas import Arena

from .episode import Episode
from .errors import SearchError
from .scenarios import MAX_AGENTS, Scenario, load_scenario
from .strategies import STRATEGIES, Strategy
from .strategies.parameter_bounds import STRATEGY_BOUNDS
from .validation import check_bounds, whole

__all__ = ["run", "check", "execute", "make_strategy", "strategy_parameters"]


def strategy_parameters(name: str) -> list[str]:
    """The parameter names strategy `name` accepts."""
    sig = inspect.signature(STRATEGIES[name].__init__)
    return [p.name for p in sig.parameters.values() if p.kind is p.KEYWORD_ONLY]


def make_strategy(name: str, **params) -> Strategy:
    """Build the strategy called `name` (see :data:`reciprocity.strategies.STRATEGIES`);
    an unknown or invalid parameter raises SearchError naming the valid ones."""
    if name not in STRATEGIES:
        raise SearchError(f"unknown strategy {name!r}; choose one of {', '.join(STRATEGIES)}")
    valid = strategy_parameters(name)
    unknown = sorted(set(params) - set(valid))
    if unknown:
        raise SearchError(f"unknown parameter(s) {', '.join(unknown)} for strategy {name!r}; "
                          f"valid: {', '.join(valid)}")
    check_bounds(params, STRATEGY_BOUNDS.get(name, {}), where=f"strategy {name!r}: ")
    try:
        return STRATEGIES[name](**params)
    except (TypeError, ValueError) as exc:
        raise SearchError(f"bad parameter for strategy {name!r}: {exc}") from None


def check(scenario: str | Scenario | Arena, strategy: str, *, params: dict | None = None,
          platform: str | None = None, agents: int | None = None, world: dict | None = None,
          platform_options: dict | None = None) -> Scenario:
    """Validate a combination before any heavy work; return the scenario (with the
    world overrides applied).

    Raises
    ------
    SearchError
        Unknown scenario or strategy, a strategy that does not apply to the scenario's
        world, an unknown or invalid parameter, platform, platform option or agent count.
    """
    sc = scenario if isinstance(scenario, Scenario) else load_scenario(scenario)
    sc = sc.with_world(world)
    if strategy not in STRATEGIES:
        raise SearchError(f"unknown strategy {strategy!r}; choose one of {', '.join(STRATEGIES)}")
    cls = STRATEGIES[strategy]
    if sc.world not in cls.worlds:
        fits = [n for n, c in STRATEGIES.items() if sc.world in c.worlds]
        raise SearchError(f"strategy {strategy!r} does not apply to scenario {sc.name!r} ({sc.world} world); "
                          f"strategies for {sc.world} worlds: {', '.join(fits)}")
    plat = platform or sc.platform
    if plat not in sc.kind.platforms:
        raise SearchError(f"platform {plat!r} does not apply to {sc.world} worlds; choose one of "
                          f"{', '.join(sc.kind.platforms)}")
    n = _agents(cls, sc, agents)
    sc.check_observers(n)
    if sc.starts is not None and 1 < len(sc.starts) < n:
        raise SearchError(f"scenario {sc.name!r} gives {len(sc.starts)} start poses for {n} agents; give "
                          "one pose (shared) or one per agent")
    make_strategy(strategy, **(params or {}))
    if plat == "car":
        from .platforms.car import check_car_options
        check_car_options(dict(platform_options or {}), sc.arena)
    return sc


def _agents(cls, sc: Scenario, agents: int | None) -> int:
    if agents is None:
        return cls.agents or sc.agents
    agents = whole(agents, "agents", 1, MAX_AGENTS)
    if cls.agents is not None and agents != cls.agents:
        raise SearchError(f"strategy {cls.name!r} directs {cls.agents} observer(s); got agents={agents}")
    return agents


def execute(scenario: str | Scenario | Arena, strategy: str, *, seed: int = 0, params: dict | None = None,
            platform: str | None = None, agents: int | None = None, world: dict | None = None,
            platform_options: dict | None = None, progress=None, figures: bool = False):
    """Like :func:`run`, but return ``(episode, strategy, platforms)``.

    The episode runs as every episode does: a :class:`~reciprocity.env.SearchEnv` (the
    truth) driven by :func:`~reciprocity.env.rollout` with the strategy as its agent.
    """
    from .env import SearchEnv, rollout
    from .strategies.agent import StrategyAgent
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise SearchError(f"seed must be a non-negative whole number; got {seed!r}")
    sc = check(scenario, strategy, params=params, platform=platform, agents=agents, world=world,
               platform_options=platform_options)
    n = _agents(STRATEGIES[strategy], sc, agents)
    env = SearchEnv(sc, platform=platform, agents=n, platform_options=platform_options)
    agent = StrategyAgent(STRATEGIES[strategy], params, figures=figures)
    episode = rollout(env, agent, seed, progress=progress, figures=figures,
                      options={"progress": True} if progress is not None else None)
    return episode, agent.strategy, env.platforms


def run(scenario: str | Scenario | Arena, strategy: str, *, seed: int = 0, params: dict | None = None,
        platform: str | None = None, agents: int | None = None, world: dict | None = None,
        platform_options: dict | None = None, progress=None, figures: bool = False) -> Episode:
    """Run one episode of `strategy` in `scenario`.

    Parameters
    ----------
    scenario : str, Scenario or arenas.Arena
        A built-in scenario name (``reciprocity scenarios``), a YAML file, a Scenario, or an
        arena (a poisson scenario with the arena's source, strength and start).
    strategy : str
        A strategy name (``reciprocity strategies``).
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
