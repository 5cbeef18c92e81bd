"""The planner's input bounds: lengths, headings and the node budget."""

import math

import pytest

from hjplanner.errors import PlanningError
from hjplanner.limits import MAX_LENGTH, MAX_NODES, check_grid, grid_shape, length


@pytest.mark.parametrize("value", [0, -1, math.nan, math.inf, 2 * MAX_LENGTH, True, "1"])
def test_a_length_out_of_bounds_is_refused(value):
    with pytest.raises(PlanningError, match=r"rho must be a number in \(0, 100000\]"):
        length(value, "rho")


def test_zero_is_a_length_only_where_allowed():
    assert length(0, "clearance", zero=True) == 0.0
    with pytest.raises(PlanningError):
        length(0, "h")


@pytest.mark.parametrize("ntheta", [7, 721, 8.0, True])
def test_headings_are_a_whole_number_from_8_to_720(ntheta):
    with pytest.raises(PlanningError, match="ntheta must be a whole number from 8 to 720"):
        check_grid(1.0, 1.0, ntheta, 0.0)


def test_the_node_budget_counts_every_node():
    nx, ny = grid_shape((100.0, 50.0), 1.0)
    assert (nx, ny) == (101, 51)
    ntheta = MAX_NODES // (nx * ny)            # just within the budget
    check_grid(1.0, 1.0, min(ntheta, 720), 0.0, (100.0, 50.0))
    with pytest.raises(PlanningError, match="increase h or reduce ntheta"):
        check_grid(1.0, 0.01, 72, 0.0, (100.0, 50.0))
