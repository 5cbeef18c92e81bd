"""The PettingZoo face: the parallel API holds, and the VoI team runs the CLI's episodes."""

import pytest

pytest.importorskip("pettingzoo")
from pettingzoo.test import parallel_api_test  # noqa: E402

from reciprocity.api import execute  # noqa: E402
from reciprocity.pettingzoo import TeamPolicy, parallel_env  # noqa: E402


@pytest.mark.parametrize("scenario, agents", [("hajieghrary", None), ("song-100", 2), ("ristic-lattice", 2),
                                              ("paper", 2), ("paper-wind", 2)])
def test_parallel_api(scenario, agents):
    cheap = {"truth_h": 2.0} if scenario == "paper-wind" else {}       # the wind's truth on a coarser mesh
    parallel_api_test(parallel_env(scenario, agents=agents, **cheap), num_cycles=100)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_voi_team_runs_the_cli_episode(seed):
    env = parallel_env("hajieghrary")
    policy = TeamPolicy("voi", env)
    observations, infos = env.reset(seed=seed)
    policy.reset(seed)
    while env.agents:
        actions = policy(observations)
        assert set(actions) == set(env.agents)
        observations, rewards, terminations, truncations, infos = env.step(actions)
    summary = infos["observer_0"]["summary"]
    episode, _, _ = execute("hajieghrary", "voi", seed=seed)
    assert sorted(k for k in set(summary) | set(episode.summary)
                  if k != "wall_time_s" and summary.get(k) != episode.summary.get(k)) == []
    assert summary["messages"] == episode.summary["messages"] and summary["n_agents"] == 3


def test_every_observer_stopping_ends_the_episode():
    env = parallel_env("hajieghrary")
    env.reset(seed=0)
    stop = {a: env.faces[k].stop_action() for k, a in enumerate(env.possible_agents)}
    _, rewards, terminations, truncations, infos = env.step(stop)
    assert all(terminations.values()) and not any(truncations.values()) and env.agents == []
    assert infos["observer_1"]["stop_reason"].startswith("converged")


def test_observations_and_infos_pickle():
    """What a subprocess vector wrapper sends back: observations and infos, reset and final."""
    import pickle
    env = parallel_env("hajieghrary")
    observations, infos = env.reset(seed=0)
    sent = [observations, infos]
    stop = {a: env.faces[k].stop_action() for k, a in enumerate(env.possible_agents)}
    sent += list(env.step(stop))
    back = pickle.loads(pickle.dumps(sent))
    assert back[1]["observer_0"]["task"].n_agents == 3 and back[-1]["observer_0"]["summary"]["n_agents"] == 3


def test_a_team_policy_is_checked_when_made():
    """As on every front door (api.check): the strategy, that it directs a team in this
    world, and its parameters, before the first reset."""
    from reciprocity.errors import SearchError
    env = parallel_env("hajieghrary")
    with pytest.raises(SearchError, match="unknown strategy 'nope'"):
        TeamPolicy("nope", env)
    with pytest.raises(SearchError, match=r"unknown parameter\(s\) nope for strategy 'voi'"):
        TeamPolicy("voi", env, nope=1)
    with pytest.raises(SearchError, match="does not apply to scenario 'hajieghrary'"):
        TeamPolicy("reciprocity", env)
