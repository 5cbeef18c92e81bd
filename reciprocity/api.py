"""One call from names to a finished episode: the entry point campaigns, the command line
and benchmarks share.

:func:`check` validates a (scenario, strategy, platform, parameters) combination without
any heavy work (no meshing, no factorization); :func:`run` runs one episode.
"""

from __future__ import annotations

from .episode import Episode
from .errors import SearchError
from .scenarios import Scenario, load_scenario

__all__ = ["run", "check"]


def check(scenario: str | Scenario, strategy: str, *, params: dict | None = None,
          platform: str | None = None, agents: int | None = None,
          world: dict | None = None) -> Scenario:
    """Validate a combination before any heavy work; return the loaded scenario.

    Raises
    ------
    SearchError
        Unknown scenario or strategy, a strategy that does not apply to the scenario's
        world, an unknown or invalid parameter, platform or agent count.
    """
    from .runner import PLATFORMS
    from .strategies import STRATEGIES
    sc = load_scenario(scenario) if not isinstance(scenario, Scenario) else scenario
    if strategy not in STRATEGIES:
        raise SearchError(f"unknown strategy {strategy!r}; choose one of {', '.join(STRATEGIES)}")
    if platform is not None and platform not in PLATFORMS:
        raise SearchError(f"unknown platform {platform!r}; choose one of {', '.join(PLATFORMS)}")
    if agents is not None and agents != 1:
        raise SearchError(f"strategy {strategy!r} directs one observer; got agents={agents}")
    return sc


def run(scenario: str | Scenario, strategy: str, *, seed: int = 0, params: dict | None = None,
        platform: str | None = None, agents: int | None = None, world: dict | None = None,
        progress=None) -> Episode:
    """Run one episode of `strategy` in `scenario`.

    Parameters
    ----------
    scenario : str or Scenario
        A built-in scenario name (``reciprocity scenarios``), a YAML file, or a Scenario.
    strategy : str
        A strategy name (``reciprocity strategies``).
    seed : int
        Episode seed (noise, motion, the world's randomness).
    params : dict, optional
        Strategy parameters.
    platform : str, optional
        ``"point"``, ``"car"``, ... ; default: the scenario's.
    agents : int, optional
        Number of observers; default: the strategy's.
    world : dict, optional
        Overrides of the scenario's world parameters (``source``, ``strength``, ``start``,
        mismatch options).
    progress : callable, optional
        Called with each step record.

    Returns
    -------
    Episode
        ``episode.summary`` holds the contract keys.
    """
    from .runner import search
    sc = check(scenario, strategy, params=params, platform=platform, agents=agents, world=world)
    w = dict(world or {})
    episode, _, _ = search(sc.arena, strategy, source=w.pop("source", None),
                           strength=w.pop("strength", None), start=w.pop("start", None),
                           platform=platform or sc.platform, seed=seed, params=params,
                           progress=progress, **w)
    return episode
