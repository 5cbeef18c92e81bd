"""The task's public ``source_clearance``: how far from the walls its sources lie at least.

A world states it (scenario key, or a campaign's ``random_source`` draw), checks that its
true sources keep it, and tells it in the task; the reciprocity strategy takes it as its
prior (``source_clearance="task"``) and never puts belief nearer the walls than that, less
one mesh size."""

import numpy as np
import pytest

from reciprocity.campaign.spec import SOURCE_CLEARANCE
from reciprocity.campaign.worker import world_draw
from reciprocity.env import SearchEnv, rollout
from reciprocity.errors import SearchError
from reciprocity.beliefs.imaging import ImagingMap
from reciprocity.scenarios import from_dict
from reciprocity.strategies import STRATEGIES
from reciprocity.strategies.agent import StrategyAgent
from reciprocity.strategies.multi_source import SourceBook
from reciprocity.strategies.reciprocity import ReciprocityStrategy

PAPER = dict(world="poisson", arena="paper", source=[70.2, 70.2])


def test_the_task_states_the_clearance_only_when_the_world_gives_one():
    _, info = SearchEnv(from_dict({**PAPER, "source_clearance": 8}, name="c8")).reset(seed=0)
    assert info["task"].world_nominal["source_clearance"] == 8.0
    _, info = SearchEnv(from_dict(PAPER, name="c0")).reset(seed=0)
    assert "source_clearance" not in info["task"].world_nominal


@pytest.mark.parametrize("over, message", [
    (dict(source_clearance=-1), "source_clearance must"),
    (dict(source_clearance="far"), "source_clearance must"),
    (dict(source=[3.0, 70.0], source_clearance=8), "source_clearance of 8 cm: source (3, 70) lies 3 cm"),
    (dict(sources=[[70.2, 70.2], [3.0, 70.0]], source_clearance=8),
     "source_clearance of 8 cm: sources[1] (3, 70) lies 3 cm"),
])
def test_a_clearance_the_sources_do_not_keep_is_refused_naming_the_key(over, message):
    with pytest.raises(SearchError) as err:
        from_dict({**PAPER, **over}, name="bad")
    assert message in str(err.value)


def test_a_campaign_draw_states_the_clearance_it_drew_with():
    sc = from_dict(PAPER, name="p")
    for seed in range(5):
        draw = world_draw(sc, seed)
        assert draw["source_clearance"] == SOURCE_CLEARANCE
        world = sc.with_world(draw).build_world(seed)
        assert world.nominal()["source_clearance"] == SOURCE_CLEARANCE
        assert world.arena.wall_distance(world.sources).min() >= SOURCE_CLEARANCE


def _started(params: dict, clearance: float | None):
    over = {} if clearance is None else {"source_clearance": clearance}
    env = SearchEnv(from_dict({**PAPER, **over}, name="p"))
    agent = StrategyAgent(STRATEGIES["reciprocity"], dict(h=2.0, **params))
    return env, agent


def _reset(env, agent):
    """The agent's strategy started on the task of episode 0."""
    _, info = env.reset(seed=0)
    agent.reset(info["task"], np.random.SeedSequence(0))
    return agent.strategy


def test_the_strategy_keeps_its_prior_off_the_walls_by_the_task_s_clearance():
    env, agent = _started({}, 8.0)
    ep = rollout(env, agent, 0)
    s = agent.strategy
    near = s.space.wall_distance < 8.0 - s.solver.h
    assert near.any() and s.params()["source_clearance_used"] == 8.0
    assert np.all(s.imaging.weights()[near] == 0)               # after every reading
    assert ep.summary["success"]
    fresh = s.imaging.first(1)
    assert np.all(fresh.weights()[near] == 0)                   # and on a prefix of them


def test_the_prior_before_any_reading_is_uniform_where_a_source_may_lie():
    s = _reset(*_started({}, 8.0))
    w = s.imaging.weights()
    allowed = s.space.wall_distance >= 8.0 - s.solver.h
    assert np.all(w[~allowed] == 0) and np.all(w[allowed] > 0)
    density = w[allowed] / s.space.cell_areas[allowed]
    assert density.max() == pytest.approx(density.min())


def test_a_number_overrides_the_task_and_zero_lifts_the_prior():
    assert _reset(*_started(dict(source_clearance=0.0), 8.0)).imaging.allowed is None
    s = _reset(*_started(dict(source_clearance=12.0), None))
    assert s.clearance_used == 12.0
    assert not s.imaging.allowed[s.space.wall_distance < 12.0 - s.solver.h].any()


@pytest.mark.parametrize("value", [-1.0, "near", True, float("inf")])
def test_a_bad_strategy_clearance_is_refused(value):
    with pytest.raises(SearchError, match="source_clearance must be 'task' or a distance"):
        ReciprocityStrategy(source_clearance=value)


def test_the_maps_of_one_more_source_keep_the_raw_map_s_prior():
    s = _reset(*_started({}, None))
    raw = ImagingMap(s.solver, 12.0, strength=850.0)
    for z, v in (([30.0, 30.0], 40.0), ([100.0, 40.0], 20.0), ([60.0, 110.0], 30.0)):
        raw.add(np.array(z), v)
    allowed = s.space.wall_distance >= 10.0
    raw.restrict(allowed)
    book = SourceBook(raw, 850.0, 2, s.space.wall_distance)
    more = book.residual_map(exclude_near=[np.array([70.0, 70.0])])
    assert more.allowed is not None and not (more.allowed & ~allowed).any()
    assert np.all(more.values()[~allowed] == 0)


def test_a_generated_arena_states_its_clearance_until_a_scenario_moves_its_source():
    from reciprocity.scenarios import load_scenario
    sc = load_scenario("generate:rooms:3")
    assert sc.build_world(0).nominal()["source_clearance"] == 8.0
    moved = from_dict({"world": "poisson", "arena": {"generate": "rooms", "seed": 3}, "source": [20.0, 20.0]},
                      name="moved")
    assert "source_clearance" not in moved.build_world(0).nominal()
    said = from_dict({"world": "poisson", "arena": {"generate": "rooms", "seed": 3}, "source_clearance": 0},
                     name="said")
    assert "source_clearance" not in said.build_world(0).nominal()
