"""Gradient ascent in wind (``gradient-wind``): the fitted slope, the stations, the upwind walk
without a signal, an episode."""

from __future__ import annotations

import numpy as np
import pytest

from reciprocity.api import run
from reciprocity.env import SearchEnv
from reciprocity.errors import SearchError
from reciprocity.observations import Observation
from reciprocity.scenarios import from_dict, load_scenario
from reciprocity.strategies.base import SearchContext
from reciprocity.strategies.gradient_wind import GradientWind, log_rate_slope

DUCT = {"name": "duct", "boundary": [[0, 0], [60, 0], [60, 40], [0, 40]],
        "obstacles": [[[28, 12], [34, 12], [34, 28], [28, 28]]]}
SCENARIO = {"world": "flow", "arena": DUCT, "source": [18, 22], "start": [50, 20, 90],
            "inflow": [[[0, 0], [0, 40]]], "outflow": [[[60, 0], [60, 40]]], "speed": 1, "D": 5, "tau": 60,
            "strength": 100, "detector": 1, "truth_h": 1, "max_steps": 60}


def _started(**params) -> GradientWind:
    env = SearchEnv(from_dict(SCENARIO, "duct-wind"))
    _, info = env.reset(seed=0)
    task = info["task"]
    strat = GradientWind(**params)
    strat.start(SearchContext(task.world, task.nominal, np.array(task.starts), np.random.default_rng(0)))
    return strat


def _station(strat, rate_at) -> list[np.ndarray]:
    """Read one station (three readings) with counts ``rate_at(point)``; the points read."""
    points = []
    for _ in range(3):
        intent = strat.propose()
        points.append(intent.point.copy())
        strat.observe([Observation(intent.point, float(rate_at(intent.point)), 0.0, 1.0, "hits")], intent)
    return points


def test_the_slope_of_a_log_linear_rate_is_recovered():
    """Counts that are exactly ``exp(a + g·x) - 1/2`` give the slope ``g`` back; collinear
    points or fewer than three give none."""
    rng = np.random.default_rng(1)
    g = np.array([0.07, -0.04])
    points = rng.uniform(0, 20, (6, 2))
    counts = np.exp(2.0 + points @ g) - 0.5
    np.testing.assert_allclose(log_rate_slope(points, counts, np.ones(6)), g, rtol=1e-10)
    np.testing.assert_allclose(log_rate_slope(points, counts * 2 + 0.5, np.full(6, 2.0)), g, rtol=1e-10)
    line = np.column_stack([np.arange(4.0), 2 * np.arange(4.0)])
    assert log_rate_slope(line, np.ones(4), np.ones(4)) is None
    assert log_rate_slope(points[:2], counts[:2], np.ones(2)) is None


def test_a_station_is_three_readings_then_a_step_up_the_gradient():
    """Counts rising toward the lower left: after one station the next one lies ``step``
    cm from it toward the lower left (to a mesh node)."""
    strat = _started(step=6.0, probe=4.0, h=2.0)
    source = np.array([10.0, 5.0])
    points = _station(strat, lambda p: 200.0 * np.exp(-np.hypot(*(p - source)) / 8.0))
    station = points[0]
    assert np.hypot(*(points[1] - station)) == pytest.approx(4.0, abs=1.5)
    assert np.hypot(*(points[2] - station)) == pytest.approx(4.0, abs=1.5)
    turn = np.dot(points[1] - station, points[2] - station)
    assert abs(turn) <= 8.0                                          # the second probe goes across
    nxt = strat.propose().point
    move = nxt - station
    assert np.hypot(*move) == pytest.approx(6.0, abs=1.5)
    want = (source - station) / np.hypot(*(source - station))
    assert np.dot(move, want) / np.hypot(*move) > np.cos(np.radians(25))


def test_without_a_hit_it_walks_upwind():
    """No count anywhere: each station moves ``step`` cm against the stated wind (+x here)."""
    strat = _started(step=6.0, probe=4.0, h=2.0)
    stations = []
    for _ in range(3):
        stations.append(_station(strat, lambda p: 0.0)[0])
    steps = np.diff(np.array(stations), axis=0)
    assert np.all(steps[:, 0] < -4.0) and np.all(np.abs(steps[:, 1]) <= 2.0)
    assert not strat.done


def test_it_stops_at_the_best_station_once_the_rate_stops_rising():
    """After a detection, ``declare`` stations without a higher mean rate stop the search
    (CONVERGED) with the estimate at the best station."""
    strat = _started(step=6.0, probe=4.0, declare=2, h=2.0)
    best = _station(strat, lambda p: 50.0)[0]
    for _ in range(2):
        _station(strat, lambda p: 10.0)
    assert strat.done and str(strat.stop_reason).startswith("converged")
    np.testing.assert_allclose(strat.estimate, best)


def test_gradient_wind_runs_an_episode():
    episode = run(from_dict(SCENARIO, "duct-wind"), "gradient-wind", seed=0, params={"declare": 3})
    s = episode.summary
    assert s["strategy"] == "gradient-wind" and 3 <= s["n_measurements"] <= 60
    assert s["stop_reason"].startswith(("converged", "step cap", "max_steps"))


def test_gradient_wind_refuses_poisson_worlds():
    with pytest.raises(SearchError, match="does not apply to scenario .paper. .poisson world"):
        run(load_scenario("paper"), "gradient-wind", seed=0)


@pytest.mark.parametrize("key, value", [("step", 0), ("probe", -1), ("hits", 0), ("declare", 1.5),
                                        ("clearance", -1)])
def test_bad_gradient_parameters_are_refused(key, value):
    with pytest.raises(SearchError, match=key):
        GradientWind(**{key: value})
