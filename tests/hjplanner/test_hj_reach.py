"""The reversing car's reachable region by flood fill, against the value function."""

import numpy as np
import pytest

import arenas
from hjplanner import OnDemandPlanner, PlanningError
from hjplanner.reach import FreeComponents


def _planner(arena, reverse=True):
    return OnDemandPlanner(arena.without_scenario(), rho=10.0, h=1.5, ntheta=32, clearance=4.0,
                           reverse=reverse, maxsize=1)


def test_a_pocket_behind_a_narrow_slot_is_out_of_reach_and_the_open_floor_in_reach():
    pocket = arenas.Arena.from_polygons(
        [[0, 0], [60, 0], [60, 60], [0, 60]],
        [[[36, 36], [58, 36], [58, 38], [36, 38]], [[36, 38], [38, 38], [38, 58], [36, 58]],
         [[38, 56], [58, 56], [58, 58], [38, 58]], [[56, 38], [58, 38], [58, 53], [56, 53]]],
        name="pocket")
    planner = _planner(pocket)
    region = planner.reachable_from((10.0, 10.0))
    pts = np.array([[47.0, 47.0], [20.0, 45.0], [50.0, 20.0], [2.0, 30.0]])
    assert region(pts).tolist() == [False, True, True, False]     # in the pocket; open; open; in the band
    # the value function of the start agrees at these points
    vf = planner.get((10.0, 10.0))
    hj = np.zeros(len(pts), dtype=bool)
    for th in np.linspace(0, 2 * np.pi, 8, endpoint=False):
        hj |= np.isfinite(vf(pts[:, 0], pts[:, 1], np.full(len(pts), th), cubic=False))
    assert hj.tolist() == region(pts).tolist()
    # one labelling serves every start; a start inside the band stands on its nearest free node
    assert planner.reachable_from((47.0, 47.0))(pts).tolist() == [True, False, False, False]
    assert planner.reachable_from((10.0, 2.5))(pts[1:3]).all()


def test_the_flood_holds_every_point_the_value_function_reaches_on_the_maze():
    maze = arenas.load("maze")
    planner = _planner(maze)
    start = maze.start[:2]
    pts = maze.random_free_points(400, np.random.default_rng(3))
    vf = planner.get(start)
    hj = np.zeros(len(pts), dtype=bool)
    for th in np.linspace(0, 2 * np.pi, 8, endpoint=False):
        hj |= np.isfinite(vf(pts[:, 0], pts[:, 1], np.full(len(pts), th), cubic=False))
    flood = planner.reachable_from(start)(pts)
    assert hj.sum() > 200 and np.all(flood[hj])


def test_refusals():
    maze = arenas.load("maze")
    with pytest.raises(PlanningError, match="reverses"):
        _planner(maze, reverse=False).reachable_from(maze.start[:2])
    planner = _planner(maze)
    with pytest.raises(PlanningError, match="two finite numbers"):
        planner.reachable_from((np.nan, 3.0))
    with pytest.raises(PlanningError, match="no free node"):
        FreeComponents.of(maze, h=1.5, clearance=4.0).region((-50.0, -50.0))
