"""Bounded re-meshing (issue 33): believed walls, meshes and failed re-meshes.

Every geometry the toolkit makes for itself is bounded like user input: the believed walls
of an unknown map are simplified to a vertex budget, free slivers are closed, a mesh has
at most :func:`~reciprocity.fem.mesh.triangle_budget` triangles, Triangle's failures are
MeshErrors, and a re-mesh that fails keeps the last good mesh and says so in the summary.
"""

import numpy as np
import pytest

import arenas
from reciprocity.env import SearchEnv, rollout
from reciprocity.errors import MeshError
from reciprocity.fem import mesh as fem_mesh
from reciprocity.fem.mesh import mesh_free_region, triangle_budget
from reciprocity.spaces import occupancy
from reciprocity.spaces.occupancy import MAX_BELIEVED_VERTICES, OccupancyGrid
from reciprocity.strategies import STRATEGIES
from reciprocity.strategies.agent import StrategyAgent

BOX = arenas.Arena.from_polygons([[0, 0], [140, 0], [140, 140], [0, 140]])


def _noisy_grid(share: float, seed: int = 0) -> OccupancyGrid:
    """A grid seen everywhere with `share` of its cells occupied at random: salt and pepper
    walls, hundreds of tiny obstacles and corners."""
    grid = OccupancyGrid(BOX, 1.0)
    rng = np.random.default_rng(seed)
    grid.logodds[:] = np.where(rng.random(grid.logodds.shape) < share, 4.0, -4.0)
    grid.seen[:] = True
    return grid


@pytest.mark.parametrize("share", [0.01, 0.02, 0.1])
def test_a_pathological_grid_gives_a_bounded_believed_arena_and_never_raises(share):
    grid = _noisy_grid(share)
    arena = grid.believed_arena()
    assert sum(len(o) for o in arena.obstacles) <= MAX_BELIEVED_VERTICES
    assert arena.free_region.geom_type == "Polygon"


def test_the_walls_are_simplified_to_the_budget_or_refused(monkeypatch):
    grid = _noisy_grid(0.02)
    unbounded = len(grid.believed_arena().obstacles)
    assert unbounded > 20
    monkeypatch.setattr(occupancy, "MAX_BELIEVED_VERTICES", 300)
    simplified = _noisy_grid(0.02).believed_geometry()   # simplified, then the smallest parts left out
    assert simplified is not None and 200 < occupancy._vertices(simplified) <= 300
    monkeypatch.setattr(occupancy, "MAX_BELIEVED_VERTICES", 10)
    refused = _noisy_grid(0.02)
    assert refused.believed_geometry() is None
    assert refused.believed_arena().obstacles == [] and refused.revision == 0   # the last good one


def test_a_mesh_never_exceeds_its_triangle_budget(monkeypatch):
    arena = _noisy_grid(0.02).believed_arena()
    free = mesh_free_region(arena, 1.5).t.shape[1]
    monkeypatch.setattr(fem_mesh, "MESH_TRIANGLES_FACTOR", 1.0)
    monkeypatch.setattr(fem_mesh, "MESH_TRIANGLES_SLACK", 0)
    budget = triangle_budget(arena, 1.5)
    assert budget < free                          # the bound bites on this geometry
    assert mesh_free_region(arena, 1.5).t.shape[1] <= budget


def test_a_triangle_failure_is_a_mesh_error(monkeypatch):
    import triangle

    def fail(*args, **kwargs):
        raise RuntimeError("Triangulation failed")
    monkeypatch.setattr(triangle, "triangulate", fail)
    with pytest.raises(MeshError, match="Triangulation failed"):
        mesh_free_region(arenas.load("maze"), 3.0)


def test_a_failed_remesh_keeps_the_last_good_mesh_and_is_recorded(monkeypatch):
    from reciprocity.strategies.imaging_search import meshing

    def fail(arena, h, *args, **kwargs):
        raise MeshError("Triangulation failed (simulated)")
    monkeypatch.setattr(meshing, "MeshSpace", fail)          # every re-mesh; start() meshes as usual
    env = SearchEnv("deep_u", world={"map": "unknown"})
    agent = StrategyAgent(STRATEGIES["reciprocity"], {"h": 3.0, "max_steps": 4})
    ep = rollout(env, agent, seed=0)
    strat = agent.strategy
    assert ep.summary["remesh_failures"] >= 1
    assert "kept the last good mesh" in ep.summary["remesh_note"]
    assert strat.solver.arena.obstacles == []               # the first (boundary-only) mesh
    assert strat.mapping.arena.obstacles                    # while the map did change
    assert ep.summary["n_measurements"] >= 1


def test_believed_maps_do_not_fill_the_process_wide_solver_cache():
    """The memory blow-up: every believed map's solver stayed in cached_solver's cache
    (eight of them, ~70 MB each on a 140 cm arena, GBs on larger ones)."""
    from reciprocity.models.green import cached_solver
    cached_solver.cache_clear()
    env = SearchEnv("deep_u", world={"map": "unknown"})
    agent = StrategyAgent(STRATEGIES["reciprocity"], {"h": 3.0, "max_steps": 5})
    ep = rollout(env, agent, seed=0)
    assert agent.strategy.mapping.revision >= 2 and ep.summary["remesh_failures"] == 0
    assert cached_solver.cache_info().currsize == 1              # the boundary-only start


def test_a_known_map_episode_has_no_remesh_record():
    env = SearchEnv("empty")
    ep = rollout(env, StrategyAgent(STRATEGIES["reciprocity"], {"h": 4.0, "max_steps": 2}), seed=0)
    assert "remesh_failures" not in ep.summary


def test_a_spike_of_no_width_is_removed_and_nothing_else():
    from shapely.geometry import Polygon
    spiky = Polygon([(0, 0), (10, 0), (10, 5), (15, 5), (10, 5 + 1e-15), (10, 10), (0, 10)])
    clean = fem_mesh._without_spikes(spiky)
    assert np.asarray(clean.exterior.coords)[:, 0].max() == pytest.approx(10.0)
    assert clean.area == pytest.approx(100.0) and clean.symmetric_difference(spiky).area < 1e-9


def test_meshing_retries_without_spikes_when_triangle_fails(monkeypatch):
    """On a believed ring arena, Triangle ran out of precision on a spike 4e-15 cm wide
    (a wall laid along the boundary); the exact geometry is tried first."""
    import triangle
    real, calls = triangle.triangulate, []

    def first_fails(pslg, switches):
        calls.append(switches)
        if len(calls) == 1:
            raise RuntimeError("Triangulation failed")
        return real(pslg, switches)
    monkeypatch.setattr(triangle, "triangulate", first_fails)
    mesh = mesh_free_region(arenas.load("maze"), 3.0, grading=None)
    assert len(calls) == 2 and mesh.t.shape[1] > 100


def test_a_fine_mesh_is_as_fine_as_asked():
    """Triangle's area switch never goes out in exponent form (``a2.54e-05`` read as
    ``a2.54``: a mesh 100 times coarser than asked, silently)."""
    from reciprocity.fem.mesh import _AREA_PER_H2, _area_switch
    assert _area_switch(2.54e-05) == "0.0000254" and _area_switch(0.8660254037844386) == "0.8660254038"
    arena = arenas.Arena.disk((0.0, 0.0), 0.1, n_boundary=64)
    h = 0.004
    triangles = mesh_free_region(arena, h).t.T
    assert len(triangles) > 0.5 * arena.area / (_AREA_PER_H2 * h * h)
