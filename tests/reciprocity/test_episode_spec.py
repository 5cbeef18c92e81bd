"""EpisodeSpec: an episode is checked once, its strategy built once, and a Gym step
delivers each percept once (issue 37)."""

import functools
from dataclasses import FrozenInstanceError

import pytest

from reciprocity import api
from reciprocity.env import SearchEnv
from reciprocity.errors import SearchError
from reciprocity.scenarios import Scenario
from reciprocity.strategies import STRATEGIES
from reciprocity.strategies.agent import StrategyAgent

#: A cheap episode: a few random steps on the lattice.
SCENARIO, STRATEGY, PARAMS = "ristic-lattice", "random-walk", {"n_steps": 3}


def _count(monkeypatch, owner, name: str) -> list:
    """Count the calls of ``owner.name`` (the calls still go through)."""
    calls = []
    original = getattr(owner, name)

    @functools.wraps(original)
    def counted(*args, **kwargs):
        calls.append(1)
        return original(*args, **kwargs)
    monkeypatch.setattr(owner, name, counted)
    return calls


def test_check_returns_one_immutable_spec():
    spec = api.check(SCENARIO, STRATEGY, params=PARAMS, seeds=[0, 1])
    assert isinstance(spec, api.EpisodeSpec)
    assert (spec.strategy, spec.strategy_class, spec.platform, spec.agents, spec.seeds) == \
        (STRATEGY, STRATEGIES[STRATEGY], "lattice", 1, (0, 1))
    with pytest.raises(FrozenInstanceError):
        spec.agents = 2
    with pytest.raises(TypeError):
        spec.params["n_steps"] = 4                        # a read-only mapping


def test_a_run_checks_its_scenario_once_and_builds_its_strategy_once(monkeypatch):
    built = _count(monkeypatch, STRATEGIES[STRATEGY], "__init__")
    observers = _count(monkeypatch, Scenario, "check_observers")
    spec = api.check(SCENARIO, STRATEGY, params=PARAMS, seeds=0)
    episode = api.run(spec, seed=0)
    assert len(built) == 1 and len(observers) == 1
    again = api.run(SCENARIO, STRATEGY, params=PARAMS, seed=0)       # the one-call form: the same
    assert len(built) == 2 and len(observers) == 2
    assert again.summary["estimate"] == episode.summary["estimate"]


@pytest.mark.parametrize("strategy, given", [
    ("reciprocity", {}), ("reciprocity", {"clearance": 2.0}),
    ("gradient", {}), ("gradient", {"clearance": 2.0, "i_max": 500.0}),
])
def test_on_the_car_the_strategy_is_built_once_with_the_platforms_limits(monkeypatch, strategy, given):
    """The car's clearance is known at the check and fills the strategy's parameter there;
    the sensor's i_max, known once the episode's floor is calibrated, reaches the gradient
    when it starts. Either way the agent takes the one strategy the check built, and a
    parameter the user gave is never overridden."""
    built = _count(monkeypatch, STRATEGIES[strategy], "__init__")
    if strategy == "reciprocity":         # its start (meshes, solves) has nothing to do with the limits
        monkeypatch.setattr(STRATEGIES[strategy], "start", lambda self, ctx: None)
        monkeypatch.setattr(STRATEGIES[strategy], "restrict", lambda self, reachable: None)
    spec = api.check("paper", strategy, params=given, platform="car", platform_options={"clearance": 5.0},
                     seeds=0)
    _, info = SearchEnv(spec).reset(seed=0)
    agent = StrategyAgent(spec)
    agent.reset(info["task"], info["agent_seed"])
    limits = info["task"].limits
    assert limits["clearance"] == 5.0 and limits["i_max"] > 0
    assert len(built) == 1
    assert agent.strategy.clearance == given.get("clearance", 5.0)
    if strategy == "gradient":
        assert agent.strategy.i_max == given.get("i_max", limits["i_max"])
        assert agent.strategy.params()["i_max"] == agent.strategy.i_max


def test_a_strategy_built_by_hand_keeps_its_parameters_as_given():
    """A strategy handed over already built is not told the platform's limits."""
    strategy = STRATEGIES["gradient"](h=2.0)
    spec = api.check("paper", "gradient", platform="car", seeds=0)
    _, info = SearchEnv(spec).reset(seed=0)
    agent = StrategyAgent(strategy)
    agent.reset(info["task"], info["agent_seed"])
    assert agent.strategy is strategy and strategy.i_max is None and strategy.clearance == 3.0


def test_the_old_forms_give_the_same_messages():
    with pytest.raises(SearchError, match="platform 'walker' does not apply to poisson worlds"):
        SearchEnv("paper", platform="walker")
    with pytest.raises(SearchError, match="platform 'walker' does not apply to poisson worlds"):
        api.check("paper", "gradient", platform="walker")
    with pytest.raises(SearchError, match="seed must be a non-negative whole number; got -1"):
        api.run(SCENARIO, STRATEGY, params=PARAMS, seed=-1)
    with pytest.raises(SearchError, match="an EpisodeSpec is checked already"):
        SearchEnv(api.check(SCENARIO, STRATEGY), agents=2)


def test_a_seed_outside_the_spec_is_checked_when_the_episode_starts():
    env = SearchEnv(api.check(SCENARIO, STRATEGY, params=PARAMS, seeds=0))
    env.reset(seed=0)
    with pytest.raises(SearchError, match="seed must be a non-negative whole number; got 1.5"):
        env.reset(seed=1.5)


def test_a_gym_step_delivers_each_percept_once_and_reads_its_action_once(monkeypatch):
    gymnasium = pytest.importorskip("gymnasium")
    import sys
    rollout_module = sys.modules["reciprocity.env.rollout"]       # (the package's `rollout` is the function)
    env_module = sys.modules["reciprocity.env.search_env"]
    from reciprocity.gym import StrategyPolicy
    from reciprocity.gym.env import DeclaringAgent
    from reciprocity.gym.faces import Face
    read = _count(monkeypatch, rollout_module, "intents_of")
    read_env = _count(monkeypatch, env_module, "intents_of")
    face = _count(monkeypatch, Face, "observe")
    declared = _count(monkeypatch, DeclaringAgent, "observe")
    env = gymnasium.make("reciprocity/Lattice-v0")
    env.reset(seed=0)
    for k, action in enumerate((1, 2, 3), start=1):
        env.step(action)
        assert (len(read), len(read_env), len(face), len(declared)) == (k, 0, k, k)
    policy = StrategyPolicy("rbpf", env)                 # a policy's agent: the same, once each
    observed = _count(monkeypatch, type(policy.agent), "observe")
    env.reset(seed=1)
    policy.reset(1)
    env.step(policy(None))
    assert (len(read), len(face), len(observed), len(declared)) == (4, 4, 1, 3)
