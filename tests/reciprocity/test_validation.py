"""Parse-time bounds: the helpers of reciprocity.validation and the scenario keys they guard."""

import math

import numpy as np
import pytest

from reciprocity.errors import SearchError
from reciprocity.scenarios import MAX_AGENTS, from_dict
from reciprocity.validation import Bound, check_bounds, number, point, starts_in_box, whole


@pytest.mark.parametrize("value", [True, "3", [3], None, math.nan, math.inf, -1, 11])
def test_number_refuses_anything_but_a_finite_number_in_range(value):
    with pytest.raises(SearchError, match=r"x must be a number in \[0, 10\]; got"):
        number(value, "x", 0, 10)


def test_open_bounds_exclude_their_ends():
    assert number(0.5, "eps", 0, 1, lo_open=True, hi_open=True) == 0.5
    for v in (0, 1):
        with pytest.raises(SearchError, match=r"eps must be a number in \(0, 1\)"):
            Bound(0, 1, lo_open=True, hi_open=True).check(v, "eps")


def test_whole_accepts_integral_floats_only():
    assert whole(4.0, "n", 1, 10) == 4
    for v in (4.5, 0, 11, True, "4"):
        with pytest.raises(SearchError, match="n must be a whole number from 1 to 10"):
            whole(v, "n", 1, 10)


def test_point_and_python_only_values():
    assert point([1, 2], "p").tolist() == [1.0, 2.0]
    for v in ([1], [1, "a"], [[1, 2]], "corner", [1e6, 0]):
        with pytest.raises(SearchError, match="p must be"):
            point(v, "p")
    with pytest.raises(SearchError, match="set it from Python"):
        check_bounds({"solver": "fast"}, {"solver": Bound(python=True)})


def test_starts_in_box_names_the_start_and_the_box():
    starts_in_box(np.array([[1.0, 1.0, 0.0]]), (0, 2, 0, 2), "region")
    with pytest.raises(SearchError, match=r"start \(3, 1\) lies outside the region"):
        starts_in_box(np.array([[3.0, 1.0, 0.0]]), (0, 2, 0, 2), "region")


@pytest.mark.parametrize("common, match", [
    ({"world": ["poisson"]}, "unknown world kind"),
    ({"success_radius": math.inf}, "success_radius must be a number in"),
    ({"max_steps": 10**12}, "max_steps must be a whole number from 1 to 1000000"),
    ({"agents": MAX_AGENTS + 1}, f"agents must be a whole number from 1 to {MAX_AGENTS}"),
    ({"start": [20, 20, "north"]}, "start must be"),
    ({"start": "corner"}, "start must be"),
    ({"start": [500, 500]}, "outside the free region"),
    ({"agents": 3, "start": [[20, 20], [30, 30]]}, "gives 2 poses for 3 agents"),
    ({"strength": 1e308}, r"strength must be a number in \(0, 1e\+06\]"),
    ({"strength": "lots"}, r"strength must be a number"),
    ({"source": [[100, 50]]}, r"source must be \[x, y\]"),
    ({"noise": 1e9}, r"noise must be a number in \[0, 1e\+06\]"),
])
def test_scenario_keys_are_bounded_when_the_file_is_parsed(common, match):
    data = {"world": "poisson", "arena": "empty", **common}
    with pytest.raises(SearchError, match=match) as exc:
        from_dict(data, "s")
    assert "\n" not in str(exc.value)


def test_a_team_may_share_one_start_or_have_one_each():
    assert from_dict({"world": "poisson", "arena": "empty", "agents": 2, "start": [20, 20]}).starts.shape == (1, 3)
    sc = from_dict({"world": "poisson", "arena": "empty", "agents": 2, "start": [[20, 20, 0], [30, 30, 90]]})
    assert sc.starts[1, 2] == pytest.approx(math.pi / 2)


def test_a_wall_shift_that_breaks_the_arena_is_refused_before_any_episode():
    from reciprocity.api import check
    with pytest.raises(SearchError, match="wall_shift of 2 cm makes arena 'paper' invalid") as exc:
        check("paper", "reciprocity", world={"mismatch": {"wall_shift": 2.0}})
    assert "\n" not in str(exc.value)
    check("paper", "reciprocity", world={"mismatch": {"wall_shift": 1.0}})
