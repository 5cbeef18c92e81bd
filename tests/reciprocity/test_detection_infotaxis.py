"""The detection model of a meandering plume, and ``detection-infotaxis`` in the farrell
scenario: the model's shape, the belief's Bayes update, the decision, short episodes,
bad input."""

import numpy as np
import pytest

from reciprocity.api import check, run
from reciprocity.episode import SUMMARY_KEYS
from reciprocity.errors import SearchError
from reciprocity.models.detection import DetectionModel, WindEstimate
from reciprocity.strategies.base import SearchContext
from reciprocity.strategies.detection_infotaxis import DetectionInfotaxis, entropy

SOURCE = np.array([[20.0, 0.0]])


def _p(point, wind=(1.0, 0.0), spread=0.67, model=None):
    return float((model or DetectionModel()).probability(SOURCE, np.array(point, float), np.array(wind), spread)[0])


def test_model_is_highest_just_downwind_and_falls_crosswind_and_upwind():
    m = DetectionModel()
    assert _p([21, 0]) > _p([30, 0]) > _p([60, 0]) > m.floor           # peak falls downwind
    assert _p([30, 0]) > _p([30, 5]) > _p([30, 15])                    # Gaussian crosswind
    assert _p([30, 5]) == pytest.approx(_p([30, -5]))
    assert _p([17, 0]) < 0.02 and _p([10, 0]) == pytest.approx(m.floor, abs=1e-6)
    assert _p([21, 0]) <= m.p_max
    # the envelope turns with the measured wind: downwind along +y now
    assert _p([20, 10], wind=(0.0, 2.0)) > 10 * _p([30, 0], wind=(0.0, 2.0))


def test_model_widens_with_the_measured_direction_spread():
    narrow, wide = _p([40, 8], spread=0.1), _p([40, 8], spread=0.8)
    assert wide > 5 * narrow
    assert _p([40, 0], spread=0.1) > _p([40, 0], spread=0.8)


def test_model_matches_its_calibration_points():
    # per-period detection fractions measured in the farrell plume (models/detection.py)
    for (d, c), measured in {(10, 0): 0.44, (20, 0): 0.36, (20, 10): 0.17, (2, 0): 0.81, (50, 0): 0.23}.items():
        assert _p([20 + d, c]) == pytest.approx(measured, abs=0.12)


def test_model_shapes_broadcast():
    m = DetectionModel()
    src = np.random.default_rng(0).uniform(0, 50, (7, 2))
    assert m.probability(src, np.zeros((3, 2)), np.array([1.0, 0]), 0.5).shape == (3, 7)
    assert m.probability(src, np.zeros(2), np.array([1.0, 0]), 0.5).shape == (7,)


def test_wind_estimate_mean_and_spread():
    w = WindEstimate(window=10.0, prior_weight=1e-9)
    rng = np.random.default_rng(1)
    ang = 0.3 * rng.standard_normal(20000)
    for a in ang:
        w.add([np.cos(a), np.sin(a)], 0.1)
    assert np.arctan2(w.mean[1], w.mean[0]) == pytest.approx(0.0, abs=0.1)
    assert w.spread == pytest.approx(0.3, rel=0.1)


@pytest.mark.parametrize("kw", [dict(sigma0=0), dict(p_max=1.0), dict(floor=0), dict(decay=-1)])
def test_model_rejects_bad_parameters(kw):
    with pytest.raises(SearchError):
        DetectionModel(**kw)


def _started(**params):
    sc = check("farrell", "detection-infotaxis")
    s = DetectionInfotaxis(**params)
    nominal = dict(region=(0.0, 100.0, -50.0, 50.0), cells=(40, 25), sampling_rate=10.0, speed=1.0)
    s.start(SearchContext("filament", nominal, np.array([[60.0, 0.0, 0.0]]), np.random.default_rng(0)))
    assert sc is not None
    return s


def test_update_is_bayes_rule_on_the_grid():
    s = _started(temper=1.0, resolution=5.0)
    for _ in range(30):
        s.wind.add([1.0, 0.0], 0.1)
    w0 = s.weights()
    p = s.model.probability(s.cells, np.array([60.0, 0.0]), s.wind.mean, s.wind.spread)
    s.update_period([60.0, 0.0], True)
    expect = w0 * p / (w0 @ p)
    assert np.allclose(s.weights(), expect)
    s.update_period([60.0, 0.0], False)
    expect = expect * (1 - p) / (expect @ (1 - p))
    assert np.allclose(s.weights(), expect)
    # a detection moves mass upwind of the vehicle, not downwind
    up = s.cells[:, 0] < 60
    assert s.weights()[up].sum() > 0.9


def test_expected_entropy_prefers_the_informative_waypoint():
    s = _started(temper=1.0, resolution=2.0)
    for _ in range(30):
        s.wind.add([1.0, 0.0], 0.1)
    # belief: the source is one of two spots, 10 m upwind of two waypoints 20 m apart
    s.logw[:] = -np.inf
    for spot in ([50.0, 10.0], [50.0, -10.0]):
        s.logw[int(np.argmin(np.hypot(*(s.cells - spot).T)))] = 0.0
    sc = s.scores(np.array([[60.0, 10.0], [60.0, 40.0]]))
    assert entropy(s.weights()) == pytest.approx(np.log(2))
    assert sc[0] < sc[1] and sc[1] == pytest.approx(np.log(2), abs=0.01)


def test_memory_relaxes_the_belief_toward_uniform():
    s = _started(temper=1.0, resolution=5.0, memory=10.0)
    for _ in range(30):
        s.wind.add([1.0, 0.0], 0.1)
    s.update_period([60.0, 0.0], True)
    h1 = entropy(s.weights())
    for _ in range(100):                      # far upwind of every cell: no information
        s.update_period([-500.0, 0.0], False)
    assert entropy(s.weights()) > h1 and entropy(s.weights()) == pytest.approx(np.log(len(s.cells)), rel=1e-3)


def test_overshoot_needs_a_miss_upwind_of_the_estimate():
    s = _started(radius=4.0, overshoot=2)
    for _ in range(30):
        s.wind.add([1.0, 0.0], 0.1)
    est = np.array([30.0, 0.0])
    s.update_period([35.0, 0.0], False)       # downwind of the estimate
    s.update_period([27.0, 9.0], False)       # upwind but too far crosswind
    s.update_period([29.5, 0.0], False)       # upwind by less than 1 m
    s.update_period([27.0, 2.0], False)       # 3 m upwind, 2 m crosswind: the first
    assert not s.overshot(est)
    s.update_period([26.0, -1.0], True)       # a detection does not count
    assert not s.overshot(est)
    s.update_period([25.0, -1.0], False)      # the second
    assert s.overshot(est)


def test_short_episode_has_the_contract_keys_and_is_reproducible():
    sc = check("farrell", "detection-infotaxis").scenario
    sc.max_steps = 300
    ep = run(sc, "detection-infotaxis", seed=3, world={"start": [60.0, 5.0], "spinup": 60.0})
    s = ep.summary
    assert set(SUMMARY_KEYS) <= set(s)
    assert s["path_length"] <= 0.1 * s["steps"] + 1e-9
    rec = [r for r in ep.trace if "map_mass" in r]
    assert len(rec) >= 29 and 0 < rec[-1]["map_mass"] <= 1
    again = run(sc, "detection-infotaxis", seed=3, world={"start": [60.0, 5.0], "spinup": 60.0}).summary
    assert again["estimate"] == s["estimate"] and again["steps"] == s["steps"]


def test_a_start_in_the_plume_moves_upwind():
    # started 20 m downwind of the source on the plume's axis: after 30 s the vehicle
    # is closer to the source (a drift downwind or a random walk would not be)
    sc = check("farrell", "detection-infotaxis").scenario
    sc.max_steps = 300
    closer = 0
    for seed in range(3):
        ep = run(sc, "detection-infotaxis", seed=seed, world={"start": [40.0, 0.0]})
        end = np.array(ep.trace[-1]["pose"][:2])
        closer += np.hypot(*(end - [20.0, 0.0])) < 15.0
    assert closer >= 2


@pytest.mark.parametrize("params, words", [
    ({"temper": 1.5}, "temper"), ({"stop_mass": 1.0}, "stop_mass"), ({"n_headings": 1}, "n_headings"),
    ({"lookahead": 0}, "lookahead"), ({"bogus": 1}, "bogus"), ({"memory": 0}, "memory"),
    ({"min_hits": -1}, "min_hits"), ({"overshoot": -1}, "overshoot"),
])
def test_bad_parameters_are_one_line(params, words):
    with pytest.raises(SearchError) as e:
        check("farrell", "detection-infotaxis", params=params)
    assert words in str(e.value) and "\n" not in str(e.value)


def test_applies_to_filament_worlds_only():
    with pytest.raises(SearchError, match="does not apply"):
        check("paper", "detection-infotaxis")
