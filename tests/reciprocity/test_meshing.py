"""The belief's mesh: candidate points, the source clearance, re-meshing on an unknown map
(reciprocity.strategies.imaging_search.meshing)."""

import numpy as np
import pytest

import arenas
from reciprocity.beliefs.imaging import ImagingMap
from reciprocity.errors import MeshError, SearchError
from reciprocity.fem.green import GreenSolver
from reciprocity.models.green import cached_solver
from reciprocity.spaces import mesh_space
from reciprocity.strategies.imaging_search import meshing
from reciprocity.strategies.imaging_search.meshing import BeliefMesh, candidate_space, keep_off_walls


@pytest.fixture(scope="module")
def geometry():
    return arenas.load("empty").without_scenario()


def test_the_candidates_are_the_solvers_nodes(geometry):
    solver = cached_solver(geometry, 4.0)
    assert np.allclose(candidate_space(geometry, solver).points, solver.nodes, rtol=0, atol=1e-9)
    with pytest.raises(SearchError, match="needs a P1 solver"):
        candidate_space(geometry, GreenSolver(geometry, h=8.0, order=2))


def test_keep_off_walls(geometry):
    solver = cached_solver(geometry, 4.0)
    space = mesh_space(geometry, 4.0)
    im = ImagingMap(solver, 12.0, strength=850.0)
    keep_off_walls(im, space, 0.0, 4.0)
    assert im.allowed is None                                   # no clearance: anywhere
    keep_off_walls(im, space, 12.0, 4.0)
    assert not im.allowed[space.wall_distance < 8.0].any() and im.allowed[space.wall_distance >= 8.0].all()
    keep_off_walls(im, space, 1e4, 4.0)                        # leaves no node: as it was
    assert im.allowed[space.wall_distance >= 8.0].all()


def test_a_failed_remesh_is_noted(monkeypatch):
    def fail(*args, **kwargs):
        raise MeshError("Triangulation failed (simulated)")
    monkeypatch.setattr(meshing, "MeshSpace", fail)

    class Map:                                                  # what remesh reads of a MapKeeper
        arena, revision = None, 3
    notes = {"remesh_failures": 0}
    assert meshing.remesh(Map(), 2.0, notes) is None
    assert notes["remesh_failures"] == 1 and notes["remesh_note"].startswith("re-mesh of believed map 3 failed")


@pytest.mark.parametrize("bad, message", [(dict(h=0.0), "h must be a positive number"),
                                          (dict(survey="yes"), "survey must be true or false"),
                                          (dict(source_clearance=-1.0), "source_clearance must be")])
def test_bad_settings_name_the_key(bad, message):
    with pytest.raises(SearchError, match=message):
        BeliefMesh(**bad)
