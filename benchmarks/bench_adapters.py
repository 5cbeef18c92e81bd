"""The Gymnasium and PettingZoo faces against the command line, on the same seeds.

    python benchmarks/bench_adapters.py [--seeds 5]

Prints, as Markdown (results: benchmarks/adapters.md):

1. ``check_env`` for every registered id and ``parallel_api_test`` for four scenarios;
2. per world (Poisson-v0 with ``reciprocity``, Plume-v0 with ``infotaxis`` on ``otto-2d``,
   Lattice-v0 with the paper's ``rbpf``) and seed: readings and estimate through Gymnasium
   (``StrategyPolicy``) and through ``reciprocity run`` (:func:`reciprocity.api.execute`),
   and the summary keys that differ (the wall time aside);
3. the rows of ``reproduce hajieghrary-voi`` (one searcher, three sharing all, three by
   value of information) through PettingZoo (``TeamPolicy``) against the command line.
"""

from __future__ import annotations

import argparse
import time
import warnings

import gymnasium
from gymnasium.utils.env_checker import check_env
from pettingzoo.test import parallel_api_test

import reciprocity.gym as rg
from reciprocity.api import execute
from reciprocity.pettingzoo import TeamPolicy, parallel_env


def differing(a: dict, b: dict) -> list[str]:
    return sorted(k for k in set(a) | set(b) if k != "wall_time_s" and a.get(k) != b.get(k))


def gym_episode(env_id, scenario, strategy, seed):
    env = gymnasium.make(env_id, scenario=scenario)
    policy = rg.StrategyPolicy(strategy, env)
    obs, _ = env.reset(seed=seed)
    policy.reset(seed)
    done, info = False, {}
    while not done:
        obs, _, terminated, truncated, info = env.step(policy(obs))
        done = terminated or truncated
    return info["summary"]


def team_episode(strategy, params, agents, seed):
    env = parallel_env("hajieghrary", agents=agents)
    policy = TeamPolicy(strategy, env, **params)
    obs, _ = env.reset(seed=seed)
    policy.reset(seed)
    infos = {}
    while env.agents:
        obs, _, _, _, infos = env.step(policy(obs))
    return infos["observer_0"]["summary"]


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=5)
    args = ap.parse_args(argv)
    print("| face | id or scenario | check | time (s) |\n|---|---|---|---|")
    for env_id in sorted(rg.IDS):
        clock = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            check_env(gymnasium.make(env_id).unwrapped)
        print(f"| Gymnasium | {env_id} | check_env passed | {time.perf_counter() - clock:.1f} |")
    for scenario, agents in (("hajieghrary", None), ("song-100", 2), ("ristic-lattice", 2), ("paper", 2)):
        clock = time.perf_counter()
        parallel_api_test(parallel_env(scenario, agents=agents), num_cycles=100)
        print(f"| PettingZoo | {scenario} ({agents or 3} observers) | parallel_api_test passed | "
              f"{time.perf_counter() - clock:.1f} |")
    print("\n| world (id, strategy) | seed | readings Gym / CLI | estimate Gym = CLI | summary keys that differ |")
    print("|---|---|---|---|---|")
    for env_id, scenario, strategy in (("reciprocity/Poisson-v0", "paper", "reciprocity"),
                                       ("reciprocity/Plume-v0", "otto-2d", "infotaxis"),
                                       ("reciprocity/Lattice-v0", "ristic-lattice", "rbpf")):
        for seed in range(args.seeds):
            g = gym_episode(env_id, scenario, strategy, seed)
            drawn = None
            if env_id == "reciprocity/Poisson-v0":           # it draws source and start per seed
                from reciprocity.campaign.worker import world_draw
                from reciprocity.scenarios import load_scenario
                drawn = world_draw(load_scenario(scenario), seed)
            c = execute(scenario, strategy, seed=seed, world=drawn)[0].summary
            print(f"| {env_id}, {strategy} | {seed} | {g['n_measurements']} / {c['n_measurements']} | "
                  f"{g['estimate'] == c['estimate']} | {', '.join(differing(g, c)) or 'none'} |")
    print("\n| hajieghrary-voi row | seed | steps PettingZoo / CLI | success | messages | keys that differ |")
    print("|---|---|---|---|---|---|")
    for label, strategy, params, agents in (("1 searcher", "infotaxis", {}, 1),
                                            ("3, share all", "voi", {"share": "all"}, None),
                                            ("3, share by VoI", "voi", {"share": "voi"}, None)):
        for seed in range(args.seeds):
            p = team_episode(strategy, params, agents, seed)
            c = execute("hajieghrary", strategy, seed=seed, params=params, agents=agents)[0].summary
            print(f"| {label} | {seed} | {p['steps']} / {c['steps']} | {p['success']} | {p.get('messages', '–')} | "
                  f"{', '.join(differing(p, c)) or 'none'} |")


if __name__ == "__main__":
    main()
