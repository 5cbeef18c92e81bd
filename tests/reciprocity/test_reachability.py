"""Where the reciprocity search can read, and what it can see from there
(reciprocity.strategies.imaging_search.reachability)."""

import numpy as np
import pytest

import arenas
from reciprocity.beliefs.imaging import ImagingMap
from reciprocity.errors import SearchError
from reciprocity.models.green import cached_solver
from reciprocity.spaces import mesh_space
from reciprocity.strategies.imaging_search.reachability import PATH_SLACK, Reachability


@pytest.fixture(scope="module")
def setting():
    geometry = arenas.load("empty").without_scenario()
    return cached_solver(geometry, 3.0), mesh_space(geometry, 3.0)


def test_before_a_reading_within_reach_is_distance_and_path(setting):
    solver, space = setting
    reach = Reachability(12.0, 3.0)
    reach.start(space, solver, (20.0, 20.0))
    reach.restrict(space.points[:, 0] < 40)
    near = reach.near(ImagingMap(solver, 12.0, strength=850.0), 12.0)
    x = space.points[:, 0]
    assert near[x < 40].all() and near[(x > 45) & (x < 50)].all() and not near[x > 55].any()


def test_seen_sources_after_a_reading(setting):
    """Possible sources in the band the clearance keeps the observer out of (beside the
    wall) are within reach once a reading would see them: with a small noise, not with
    a huge one; the reachable part always is."""
    solver, space = setting
    reach = Reachability(12.0, 3.0)
    reach.start(space, solver, (20.0, 20.0))
    im = ImagingMap(solver, 12.0, strength=850.0)
    im.add((20.0, 20.0), 0.0)
    x, y = space.points.T
    band = (x > 0.5) & (x < 2.5) & (y > 40) & (y < 100)
    assert band.any() and not reach.reachable[band].any()
    assert reach.near(im, 1e-9)[band].all()
    assert not reach.near(im, 1e6)[band].any() and reach.near(im, 1e6)[reach.reachable].all()


def test_exclude_rebuild_and_within_path(setting):
    solver, space = setting
    reach = Reachability(12.0, 3.0)
    reach.start(space, solver, (20.0, 20.0))
    full = reach.reachable.copy()
    reach.exclude((70.0, 70.0), 10.0)
    gone = np.hypot(*(space.points - 70.0).T) < 10.0 - 1e-9
    assert not reach.reachable[gone].any() and reach.sensing[gone & full].all()
    reach.rebuild(space, solver, [((70.0, 70.0), 10.0)])
    assert not reach.reachable[gone].any() and reach.sensing.sum() == space.admissible(3.0).sum()
    reach.restrict(space.points[:, 0] < 30)
    wide = reach.within_path(PATH_SLACK * 12.0)
    assert wide[space.points[:, 0] < 30].all() and not wide[space.points[:, 0] > 60].any()


def test_a_negative_clearance_is_refused():
    with pytest.raises(SearchError, match="clearance must be >= 0 cm"):
        Reachability(12.0, -1.0)
