"""Short episodes of ``hmm`` and ``surge-cast`` in the farrell scenario: the contract's
summary keys, reproducibility, parameters and bad input."""

import numpy as np
import pytest

from reciprocity.api import check, run
from reciprocity.episode import SUMMARY_KEYS
from reciprocity.errors import SearchError


@pytest.mark.parametrize("strategy", ["hmm", "surge-cast"])
def test_short_episode_has_the_contract_keys(strategy):
    sc = check("farrell", strategy).scenario
    sc.max_steps = 300                                    # 30 s at 10 Hz
    ep = run(sc, strategy, seed=3, world={"start": [60.0, 5.0], "spinup": 60.0})
    s = ep.summary
    assert set(SUMMARY_KEYS) <= set(s)
    assert s["world"] == "filament" and s["strategy"] == strategy and s["steps"] <= 300
    assert s["path_length"] <= 0.1 * s["steps"] + 1e-9     # 1 m/s at 10 Hz
    assert s["sim_time_s"] == pytest.approx(0.1 * s["steps"])
    pts = np.array([r["pose"][:2] for r in ep.trace])
    assert (pts[:, 0] >= 0).all() and (pts[:, 0] <= 100).all() and (np.abs(pts[:, 1]) <= 50).all()
    again = run(sc, strategy, seed=3, world={"start": [60.0, 5.0], "spinup": 60.0}).summary
    assert again["estimate"] == s["estimate"] and again["steps"] == s["steps"]


def test_hmm_status_reports_the_map():
    sc = check("farrell", "hmm").scenario
    sc.max_steps = 200
    ep = run(sc, "hmm", seed=1, world={"start": [50.0, 0.0], "spinup": 60.0})
    rec = [r for r in ep.trace if "map_mass" in r]
    assert len(rec) >= 19                                 # one map update per second
    assert 0 < rec[-1]["map_mass"] <= 1


@pytest.mark.parametrize("strategy, params, words", [
    ("hmm", {"eps_d": 1.5}, "eps_d"), ("hmm", {"horizon": 0}, "horizon"),
    ("hmm", {"stop_mass": 0}, "stop_mass"), ("hmm", {"target": "moon"}, "target"),
    ("surge-cast", {"surge_time": -1}, "surge_time"), ("hmm", {"bogus": 1}, "bogus"),
    ("hmm", {"target": "verify", "approach": 1.0}, "approach"),
    ("hmm", {"discount_visits": 1}, "discount_visits"),
])
def test_bad_parameters_are_one_line(strategy, params, words):
    with pytest.raises(SearchError) as e:
        check("farrell", strategy, params=params)
    assert words in str(e.value) and "\n" not in str(e.value)


def test_hmm_applies_to_filament_worlds_only():
    with pytest.raises(SearchError, match="does not apply"):
        check("paper", "hmm")


@pytest.mark.benchmark
def test_a_300_s_search_takes_under_10_s():
    import time
    t0 = time.perf_counter()
    s = run("farrell", "hmm", seed=0, world={"start": [95.0, -45.0]}, params={"stop_mass": 0.99}).summary
    assert s["steps"] == 3000 and time.perf_counter() - t0 < 10.0


def test_verify_heads_for_the_peak_and_stops_only_there():
    from reciprocity.strategies.hmm import HMMSearch
    from reciprocity.strategies.base import SearchContext
    from reciprocity.observations import Observation
    s = HMMSearch(target="verify", min_time=1.0, stop_mass=0.3)
    nominal = dict(region=(0.0, 100.0, -50.0, 50.0), cells=(40, 25), sampling_rate=10.0, speed=1.0)
    s.start(SearchContext("filament", nominal, np.array([[80.0, 20.0, 0.0]]), np.random.default_rng(0)))
    # a map concentrated at one cell far from the vehicle: the plan goes there, no stop
    k = int(s.grid.index(np.array([30.0, 0.0]))[0])
    s.belief.pi[:] = 1e-6
    s.belief.pi[k] = 1.0
    for i in range(10):
        s.observe([Observation(np.array([80.0, 20.0]), 0.0, time=0.1 * i, dwell=0.1, kind="detection",
                               data={"wind": [1.0, 0.0]})], None)
    assert not s.done and s.goal == int(np.argmax(s.belief.pi))
    assert np.hypot(*(s.target - [80.0, 20.0])) < 5          # one cell along the path
    # the same map with the vehicle at its peak: it stops
    s.belief.pi[:] = 1e-6
    s.belief.pi[k] = 1.0
    c = s.belief.centres[k]
    for i in range(10):
        s.observe([Observation(c.copy(), 0.0, time=1.0 + 0.1 * i, dwell=0.1, kind="detection",
                               data={"wind": [1.0, 0.0]})], None)
    assert s.done and "map mass" in s.stop_reason


def test_farrell_table_compares_the_planners_on_the_same_starts():
    from reciprocity.campaign.tables.farrell2003 import FARRELL_HMM, FARRELL_VARIANTS
    spec = FARRELL_HMM.spec(3)
    assert tuple(v.label for v in spec.variants) == FARRELL_VARIANTS
    assert {v.strategy for v in spec.variants} == {"hmm", "surge-cast", "detection-infotaxis"}
    tasks = list(spec.tasks())
    assert len(tasks) == 3 * len(FARRELL_VARIANTS)
    # one episode seed per seed index, shared by every variant (the same start)
    by_index = {}
    for t in tasks:
        by_index.setdefault(t.seed_index, set()).add(t.seed)
    assert all(len(s) == 1 for s in by_index.values()) and len(by_index) == 3
    assert {pv.variant for pv in FARRELL_HMM.paper} == set(FARRELL_VARIANTS)



@pytest.mark.parametrize("discount", [False, True])
def test_discount_visits_moves_the_goal_off_a_visited_cell(discount):
    from reciprocity.strategies.hmm import HMMSearch
    from reciprocity.strategies.base import SearchContext
    from reciprocity.observations import Observation
    s = HMMSearch(target="verify", discount_visits=discount)
    nominal = dict(region=(0.0, 100.0, -50.0, 50.0), cells=(40, 25), sampling_rate=10.0, speed=1.0)
    s.start(SearchContext("filament", nominal, np.array([[40.0, -12.0, 0.0]]), np.random.default_rng(0)))
    for i in range(10):
        s.observe([Observation(np.array([40.0, -12.0]), 0.0, time=0.1 * i, dwell=0.1, kind="detection",
                               data={"wind": [1.0, 0.0]})], None)
    s._plan(upwind=False)
    first = s.goal
    s.visits[first] += 50                        # the vehicle has spent 50 s there
    s._plan(upwind=False)
    assert (s.goal != first) == discount

