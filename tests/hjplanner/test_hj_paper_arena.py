"""Planning in the built-in `paper` arena (arenas.load): paths avoid the inflated obstacles."""

import numpy as np
import pytest
from matplotlib.path import Path as MplPath

import arenas
from hjplanner import solve
from hjplanner._grid import distance_to_polygon_edges

RHO, CLEARANCE = 12.0, 3.0


@pytest.fixture(scope="module")
def paper():
    return arenas.load("paper")


@pytest.fixture(scope="module")
def paper_vf(paper):
    return solve(paper, tuple(paper.source), RHO, 2.0, 36, clearance=CLEARANCE)


def test_paper_paths_avoid_obstacles(paper, paper_vf):
    rng = np.random.default_rng(5)
    starts = [tuple(paper.start)]  # (x, y, θ in radians)
    while len(starts) < 8:
        x, y, th = rng.uniform([5, 5, 0], [135, 135, 2 * np.pi])
        if np.isfinite(paper_vf(x, y, th)):
            starts.append((x, y, th))
    for start in starts:
        path = paper_vf.path(start)
        assert path.reached, start
        assert abs(path.length - path.value_start) < 0.1 * path.value_start + 4.0, start
        for obstacle in paper.obstacles:
            assert not MplPath(obstacle).contains_points(path.xy).any()
            assert distance_to_polygon_edges(path.xy, obstacle).min() > CLEARANCE - paper_vf.grid.h
        assert MplPath(paper.boundary).contains_points(path.xy).all()


def test_paper_value_function_is_sane(paper, paper_vf):
    values = paper_vf.values
    assert not np.isnan(values).any()
    assert 0.4 < np.isfinite(values).mean() < 0.95
    assert paper_vf.meta["domain"] == "paper"
    i, j = np.round((np.asarray(paper.source) - [paper_vf.grid.x0, paper_vf.grid.y0]) / paper_vf.grid.h).astype(int)
    assert np.nanmin(values[i - 1:i + 2, j - 1:j + 2]) < 3.0
