"""Search spaces: the mesh of the free region (point location, reachability) and grids."""

import numpy as np
import pytest
from matplotlib.tri import Triangulation

import arenas
from reciprocity.spaces import GridSpace, MeshSpace, mesh_space


@pytest.mark.parametrize("name", ["paper", "disk", "maze"])
def test_point_location_agrees_with_the_trapezoid_map(name):
    """The fast locator (nearest centroids + barycentric test) finds exactly the triangle
    matplotlib's trapezoid map finds, inside, outside and next to walls."""
    arena = arenas.load(name).without_scenario()
    space = MeshSpace(arena, 3.0)
    (x0, x1), (y0, y1) = arena.bounds
    rng = np.random.default_rng(1)
    pts = np.vstack([rng.uniform([x0 - 5, y0 - 5], [x1 + 5, y1 + 5], (20000, 2)),
                     space.points + rng.normal(0, 0.05, space.points.shape)])  # near nodes and walls
    ref = Triangulation(space.points[:, 0], space.points[:, 1], space.triangles).get_trifinder()
    assert np.array_equal(space.locate(pts), ref(pts[:, 0], pts[:, 1]))


def test_reachability_respects_the_clearance_and_gaps():
    arena = arenas.load("paper").without_scenario()
    space = mesh_space(arena, 2.0)
    start = np.array([128.0, 12.0])
    loose, tight = space.reachable_from(start, 0.0), space.reachable_from(start, 4.0)
    assert tight.sum() < loose.sum() and not np.any(tight & ~loose)
    # every reachable node keeps the clearance, measured with the arena's own geometry
    assert np.all(arena.wall_distance(space.points[tight]) >= 4.0 - 1e-9)


def test_path_distance_goes_around_walls():
    """Nodes within a path length (along mesh edges) of a set: never farther than the
    straight line, within a factor 2 of it in the open, and not through a wall (the far
    side of deep_u's wall is close in a straight line only)."""
    space = mesh_space(arenas.load("empty").without_scenario(), 2.0)
    seed = np.zeros(len(space.points), dtype=bool)
    seed[np.argmin(np.hypot(*(space.points - [70.0, 70.0]).T))] = True
    near = space.within_path(seed, 20.0)
    r = np.hypot(*(space.points - space.points[seed][0]).T)
    assert np.all(near[r < 10.0]) and not np.any(near[r > 20.0])
    arena = arenas.load("deep_u").without_scenario()
    space = mesh_space(arena, 2.0)
    inside = np.zeros(len(space.points), dtype=bool)
    inside[np.argmin(np.hypot(*(space.points - arenas.load("deep_u").source).T))] = True
    near = space.within_path(inside, 15.0)
    straight = np.hypot(*(space.points - space.points[inside][0]).T) <= 15.0
    assert near.sum() < straight.sum() and not np.any(near & ~straight)
    assert not space.within_path(np.zeros(len(space.points), dtype=bool), 10.0).any()


def test_grid_neighbours_and_masking():
    g = GridSpace(((0, 4), (0, 3)), 1.0, connectivity=8, mask=lambda p: ~((p[:, 0] > 2) & (p[:, 1] > 2)))
    assert len(g) == 10                       # 12 cells; (2.5, 2.5) and (3.5, 2.5) masked
    centre = g.index_of([[1.5, 1.5]])[0]
    assert len(g.neighbours(centre)) == 7     # 8 around it, (2.5, 2.5) masked
    corner = g.index_of([[3.5, 1.5]])[0]      # its upper neighbours are masked
    assert sorted(g.points[g.neighbours(corner)].tolist()) == [[2.5, 0.5], [2.5, 1.5], [3.5, 0.5]]
    assert g.index_of([[3.5, 2.5], [9.0, 9.0]]).tolist() == [-1, -1]


def test_mesh_cache_returns_the_mesh_it_would_make(tmp_path, monkeypatch):
    from reciprocity.fem.mesh import cached_mesh, mesh_free_region
    arena = arenas.load("maze").without_scenario()
    monkeypatch.setenv("RECIPROCITY_CACHE", str(tmp_path))
    first = cached_mesh(arena, 4.0)
    files = list((tmp_path / "meshes").glob("*.npz"))
    assert len(files) == 1
    again = cached_mesh(arena, 4.0)                    # read back from the file
    fresh = mesh_free_region(arena, 4.0)
    assert np.array_equal(again.p, fresh.p) and np.array_equal(again.t, fresh.t)
    assert np.array_equal(first.t, fresh.t)
    cached_mesh(arena, 3.0)                            # another h, another file
    assert len(list((tmp_path / "meshes").glob("*.npz"))) == 2
    monkeypatch.setenv("RECIPROCITY_CACHE", "off")
    cached_mesh(arena, 5.0)
    assert len(list((tmp_path / "meshes").glob("*.npz"))) == 2
