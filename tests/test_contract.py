"""The framework's contract: every strategy runs on a small instance of every world it
claims, the null strategy runs on every world and platform, and every episode's summary
has the public keys (../shared/DESIGN.md) with consistent outcome semantics."""

import json
from dataclasses import replace

import numpy as np
import pytest

from reciprocity import SUMMARY_KEYS
from reciprocity.api import run, strategy_parameters
from reciprocity.scenarios import WORLD_KINDS, load_scenario, scenario_names
from reciprocity.strategies import STRATEGIES

#: Rounds per contract episode: enough to exercise every step of the loop, cheap.
ROUNDS = 6


def _scenarios_by_world() -> dict:
    """One built-in scenario per world kind (the small empty arena for poisson)."""
    out = {"poisson": "empty"}
    for name in scenario_names():
        out.setdefault(load_scenario(name).world, name)
    return out


BY_WORLD = _scenarios_by_world()
STRATEGY_CASES = [(s, n) for w, s in BY_WORLD.items() for n, cls in STRATEGIES.items() if w in cls.worlds]
PLATFORM_CASES = [(s, p) for w, s in BY_WORLD.items() for p in WORLD_KINDS[w].platforms]


def _quick(strategy: str) -> dict:
    params = dict(getattr(STRATEGIES[strategy], "quick_params", {}))
    if "h" in strategy_parameters(strategy):
        params.setdefault("h", 4.0)
    return params


def _check_summary(s: dict, rounds: int) -> None:
    assert set(SUMMARY_KEYS) <= set(s), set(SUMMARY_KEYS) - set(s)
    assert s["steps"] <= rounds
    assert s["n_samples"] >= s["n_measurements"] >= 0
    assert s["sim_time_s"] >= 0 and s["wall_time_s"] > 0 and s["path_length"] >= 0
    assert len(s["source"]) == 2 and isinstance(s["source_reachable"], bool)
    if s["estimate"] is not None:
        assert s["error"] == pytest.approx(float(np.hypot(*np.subtract(s["estimate"], s["source"]))))
    if s["success"]:
        assert s["converged"]
    if s["stop"] in ("step cap", "no target", "unreachable", "gave up"):
        assert not s["converged"] and not s["success"]
    json.dumps(s, default=float)


@pytest.mark.parametrize("scenario, strategy", STRATEGY_CASES)
def test_every_strategy_runs_on_every_world_it_claims(scenario, strategy):
    sc = replace(load_scenario(scenario), max_steps=ROUNDS)
    episode = run(sc, strategy, seed=1, params=_quick(strategy))
    _check_summary(episode.summary, ROUNDS)
    assert episode.summary["strategy"] == strategy and episode.summary["world"] == sc.world
    again = run(sc, strategy, seed=1, params=_quick(strategy)).summary
    for key in ("estimate", "n_measurements", "n_samples", "steps", "path_length", "stop_reason"):
        assert again[key] == episode.summary[key], key  # same seed, same result


@pytest.mark.parametrize("scenario, platform", PLATFORM_CASES)
def test_the_null_strategy_runs_on_every_world_and_platform(scenario, platform):
    sc = replace(load_scenario(scenario), max_steps=ROUNDS)
    episode = run(sc, "random-walk", seed=2, platform=platform, params={"n_steps": 3})
    s = episode.summary
    _check_summary(s, 3)
    assert s["platform"] == platform and s["stop"] == "step cap" and not s["success"]
    # the trace is typed per observation: one reading (or more) per record, time-stamped
    for rec in episode.records:
        assert rec.observations and all(o.time >= 0 for o in rec.observations)


def test_every_world_kind_has_a_builtin_scenario():
    assert set(BY_WORLD) == set(WORLD_KINDS)


def test_unsupported_pairs_are_refused_with_the_strategies_that_fit():
    from reciprocity.errors import SearchError
    for world, scenario in BY_WORLD.items():
        for name, cls in STRATEGIES.items():
            if world in cls.worlds:
                continue
            with pytest.raises(SearchError, match=f"does not apply to scenario .*strategies for {world} worlds"):
                run(scenario, name, seed=0)
