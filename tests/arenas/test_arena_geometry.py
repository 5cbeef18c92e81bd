"""Arena geometry: construction, queries and validation messages."""

import numpy as np
import pytest

import arenas
from arenas import Arena, ArenaError

SQUARE = [[0, 0], [10, 0], [10, 10], [0, 10]]


def test_builtins_load_and_are_valid():
    names = arenas.builtin_names()
    assert {"paper", "empty", "disk", "maze", "deep_u"} <= set(names)
    for name in names:
        a = arenas.load(name)
        assert a.source is not None and a.contains(a.source)[0]
        assert a.start is not None and a.contains(a.start[:2])[0]


def test_paper_arena_matches_the_paper_setup():
    a = arenas.load("paper")
    assert a.bounds == ((0.0, 140.0), (0.0, 140.0))
    assert np.allclose(a.source, [70.21, 70.21])
    assert len(a.obstacles) >= 4
    # at least one obstacle is non-convex
    from shapely.geometry import Polygon
    assert any(Polygon(o).convex_hull.area > Polygon(o).area + 1 for o in a.obstacles)


def test_deep_u_blocks_the_straight_line_to_the_source():
    from shapely.geometry import LineString
    a = arenas.load("deep_u")
    assert not a.free_region.covers(LineString([a.start[:2], a.source]))


def test_contains_clearance_and_wall_distance():
    a = Arena.from_polygons(SQUARE, [[[4, 4], [6, 4], [6, 6], [4, 6]]])
    pts = np.array([[1, 1], [5, 5], [3, 5], [11, 5]])
    assert a.contains(pts).tolist() == [True, False, True, False]
    assert np.allclose(a.wall_distance([[1, 1], [3, 5]]), [1, 1])
    assert a.contains([[3, 5]], clearance=1.5).tolist() == [False]
    assert a.area == pytest.approx(96)


def test_disk_is_a_circle():
    d = Arena.disk((1, 2), 3.0)
    assert d.circle == (1.0, 2.0, 3.0)
    assert np.allclose(np.hypot(*(d.boundary - [1, 2]).T), 3.0)


def test_orientation_is_normalised_and_closing_vertex_dropped():
    a = Arena.from_polygons(SQUARE[::-1] + [SQUARE[-1]])
    assert len(a.boundary) == 4


def test_random_free_points_are_free_and_seeded():
    a = arenas.load("paper")
    p1 = a.random_free_points(50, np.random.default_rng(3), clearance=2.0)
    p2 = a.random_free_points(50, np.random.default_rng(3), clearance=2.0)
    assert np.array_equal(p1, p2)
    assert a.contains(p1, clearance=2.0).all()


def test_with_scenario_validates_and_copies():
    a = arenas.load("empty")
    b = a.with_scenario(source=(10, 10), start=(20, 20, 7.0))
    assert np.allclose(b.source, [10, 10]) and b.start[2] == pytest.approx(7.0 - 2 * np.pi)
    assert np.allclose(a.source, [90, 60])
    assert a.without_scenario() is b.without_scenario()


@pytest.mark.parametrize("boundary, obstacles, match", [
    ([[0, 0], [10, 10], [10, 0], [0, 10]], [], "intersects itself"),
    ([[0, 0], [10, 0]], [], "at least 3 vertices"),
    ([[0, 0], [1e-6, 0], [0, 1e-6]], [], "degenerate"),
    ([[0, 0], [10, 0], [float("nan"), 10]], [], "NaN"),
    (SQUARE, [[[8, 8], [12, 8], [12, 9], [8, 9]]], "not inside the arena boundary"),
    (SQUARE, [[[2, 2], [5, 2], [5, 5], [2, 5]], [[4, 4], [7, 4], [7, 7], [4, 7]]], "overlap"),
    (SQUARE, [[[0, 4], [10, 4], [10, 5], [0, 5]]], "split into 2 disconnected parts"),
    (SQUARE, [[[2, 2], [5, 2], [5, 5], [2, 5]], [[5, 5], [7, 5], [7, 7], [5, 7]]], "touch at a single point"),
    (SQUARE, [[[0, 5], [3, 4], [3, 6]]], "touches the boundary at a single point"),
    (SQUARE, [[[0, 0], [10, 0], [10, 10], [0, 10]]], "no free region"),
])
def test_invalid_geometry_is_explained(boundary, obstacles, match):
    with pytest.raises(ArenaError, match=match):
        Arena.from_polygons(boundary, obstacles)


def test_source_and_start_must_be_free():
    with pytest.raises(ArenaError, match="inside an obstacle"):
        Arena.from_polygons(SQUARE, [[[4, 4], [6, 4], [6, 6], [4, 6]]], source=(5, 5))
    with pytest.raises(ArenaError, match="outside the arena"):
        Arena.from_polygons(SQUARE, start=(20, 5, 0))
    with pytest.raises(ArenaError, match="strength"):
        Arena.from_polygons(SQUARE, strength=-1)


def test_obstacle_may_lean_on_the_boundary():
    a = Arena.from_polygons(SQUARE, [[[0, 4], [6, 4], [6, 5], [0, 5]]])
    assert a.area == pytest.approx(94)
