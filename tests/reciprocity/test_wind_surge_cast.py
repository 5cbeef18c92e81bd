"""Surge-cast in wind (``surge-cast-wind``): the stated wind, the surge, the cast, an episode."""

from __future__ import annotations

import numpy as np
import pytest

from reciprocity.api import run
from reciprocity.env import SearchEnv
from reciprocity.errors import SearchError
from reciprocity.observations import Observation
from reciprocity.scenarios import from_dict
from reciprocity.strategies.base import SearchContext
from reciprocity.strategies.reciprocity_wind import told_wind_direction
from reciprocity.strategies.surge_cast_wind import SurgeCastWind

DUCT = {"name": "duct", "boundary": [[0, 0], [60, 0], [60, 40], [0, 40]],
        "obstacles": [[[28, 12], [34, 12], [34, 28], [28, 28]]]}
SCENARIO = {"world": "flow", "arena": DUCT, "source": [18, 22], "start": [50, 20, 90],
            "inflow": [[[0, 0], [0, 40]]], "outflow": [[[60, 0], [60, 40]]], "speed": 1, "D": 5, "tau": 60,
            "strength": 100, "detector": 1, "truth_h": 1, "max_steps": 60}


def _started(**params) -> SurgeCastWind:
    env = SearchEnv(from_dict(SCENARIO, "duct-wind"))
    _, info = env.reset(seed=0)
    task = info["task"]
    strat = SurgeCastWind(**params)
    strat.start(SearchContext(task.world, task.nominal, np.array(task.starts), np.random.default_rng(0)))
    return strat


def _read(strat, count):
    intent = strat.propose()
    strat.observe([Observation(intent.point, float(count), 0.0, 1.0, "hits")], intent)
    return intent.point


def test_the_stated_wind_blows_from_the_inflow_to_the_outflow():
    assert np.allclose(told_wind_direction({"inflow": [[[0, 0], [0, 40]]], "outflow": [[[60, 0], [60, 40]]]}), [1, 0])
    with pytest.raises(SearchError, match="no direction"):
        told_wind_direction({"inflow": [[[0, 0], [0, 40]]], "outflow": [[[0, 0], [0, 40]]]})


def test_a_detection_surges_upwind_by_a_step():
    strat = _started(step=6.0, h=2.0)
    here = _read(strat, 3)
    nxt = strat.propose().point
    assert nxt[0] == pytest.approx(here[0] - 6.0, abs=1.5) and abs(nxt[1] - here[1]) <= 1.5


def test_before_a_detection_it_zig_zags_upwind():
    strat = _started(step=4.0, cast=4.0, h=2.0)
    start = _read(strat, 0)
    points = []
    for _ in range(3):
        points.append(strat.propose().point)
        _read(strat, 0)
    points = np.array(points)
    assert np.all(np.diff(np.r_[start[0], points[:, 0]]) < 0)            # each leg further upwind
    across = np.sign(points[:, 1] - start[1])
    assert across[0] != across[1] and across[1] != across[2]


def test_after_losing_the_plume_it_casts_across_the_wind_in_growing_legs():
    strat = _started(step=4.0, cast=4.0, h=2.0)
    centre = _read(strat, 2)                         # a detection: the casts centre here
    _read(strat, 0)                                  # the surge point, and the plume lost
    offsets = []
    for _ in range(3):
        p = strat.propose().point
        offsets.append(p[1] - centre[1])
        assert abs(p[0] - centre[0]) <= 2.0          # across the wind from the detection
        _read(strat, 0)
    assert np.sign(offsets[0]) != np.sign(offsets[1]) != np.sign(offsets[2])
    assert abs(offsets[0]) < abs(offsets[1]) < abs(offsets[2])


def test_surge_cast_runs_an_episode_and_stops_at_the_best_rate_read():
    episode = run(from_dict(SCENARIO, "duct-wind"), "surge-cast-wind", seed=0, params={"declare": 5})
    s = episode.summary
    assert s["strategy"] == "surge-cast-wind" and 1 <= s["n_measurements"] <= 60
    assert s["stop_reason"].startswith(("converged", "step cap", "max_steps"))


@pytest.mark.parametrize("key, value", [("step", 0), ("hits", 0), ("declare", 1.5), ("clearance", -1)])
def test_bad_surge_cast_parameters_are_refused(key, value):
    with pytest.raises(SearchError, match=key):
        SurgeCastWind(**{key: value})
