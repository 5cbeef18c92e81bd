"""Green's functions against exact solutions: observed orders, symmetry, obstacles."""

import numpy as np
import pytest
from fem_error import l2_error_away, observed_order

import arenas
import reciprocity as r

Z = np.array([0.3, 0.2])


def disk_exact(x, y):
    return r.disk_green(np.column_stack([x.ravel(), y.ravel()]), Z).reshape(x.shape)


@pytest.mark.parametrize("order, hs, rate", [(1, [0.1, 0.05, 0.025, 0.0125], 1.9),
                                             (2, [0.1, 0.05, 0.025], 2.8)])
def test_disk_observed_l2_order(order, hs, rate):
    disk = arenas.Arena.disk((0, 0), 1.0)
    errs = []
    for h in hs:
        s = r.GreenSolver(disk, h=h, order=order)
        errs.append(l2_error_away(s, s.green(Z).dofs, disk_exact, Z, 0.25)[0])
    assert observed_order(hs, errs) >= rate


def test_disk_default_resolution_relative_error():
    arena = arenas.load("disk")
    z = np.array([85.0, 60.0])
    s = r.GreenSolver(arena)  # default h = 1 cm

    def exact(x, y):
        return r.disk_green(np.column_stack([x.ravel(), y.ravel()]), z, (70, 70), 70).reshape(x.shape)

    _, rel = l2_error_away(s, s.green(z).dofs, exact, z, 3 * s.h)
    assert rel < 5e-3
    # pointwise too, at points three mesh sizes or more from the source, away from the wall
    rng = np.random.default_rng(0)
    pts = arena.random_free_points(400, rng, clearance=2.0)
    pts = pts[np.hypot(*(pts - z).T) >= 3 * s.h]
    ex = r.disk_green(pts, z, (70, 70), 70)
    assert np.max(np.abs(s.green(z)(pts) - ex)) / np.max(ex) < 5e-3


def _holed_square():
    # a unit square with a non-convex (L-shaped) hole and a triangle: re-entrant corners
    return arenas.Arena.from_polygons(
        [[0, 0], [1, 0], [1, 1], [0, 1]],
        [[[0.55, 0.55], [0.85, 0.55], [0.85, 0.65], [0.65, 0.65], [0.65, 0.85], [0.55, 0.85]],
         [[0.15, 0.6], [0.35, 0.7], [0.2, 0.85]]])


def _free_space(x, y):
    return -np.log(np.hypot(x - Z[0], y - Z[1])) / (2 * np.pi)


def _free_space_flux(x, y):
    d2 = (x - Z[0]) ** 2 + (y - Z[1]) ** 2
    return -(x - Z[0]) / (2 * np.pi * d2), -(y - Z[1]) / (2 * np.pi * d2)


@pytest.mark.parametrize("walls", ["dirichlet", "neumann"])
def test_free_space_solution_with_obstacles(walls):
    """-ln|x - z| / 2pi with its own wall data solves the problem on any holed domain."""
    arena = _holed_square()
    hs, errs = [0.08, 0.04, 0.02], []
    for h in hs:
        s = r.GreenSolver(arena, h=h, walls=walls)
        w = s.solve(s.point_sources(Z), dirichlet=_free_space,
                    flux=_free_space_flux if walls == "neumann" else None)
        errs.append(l2_error_away(s, w, _free_space, Z, 0.15)[0])
    assert observed_order(hs, errs) >= 1.9
    assert errs[-1] < 1e-3


def test_the_truths_discretisation_keeps_third_order_at_reentrant_corners():
    """The Poisson world's own solver (P2 on a mesh graded toward re-entrant corners) reaches
    its elements' L2 order 3 away from the source on a holed domain."""
    from reciprocity.worlds.poisson import TRUTH_ORDER, truth_solver
    arena = _holed_square()
    hs, errs = [0.04, 0.02, 0.01], []
    for h in hs:
        s = truth_solver(arena, h)
        assert s.order == TRUTH_ORDER == 2
        w = s.solve(s.point_sources(Z), dirichlet=_free_space)
        errs.append(l2_error_away(s, w, _free_space, Z, 0.15)[0])
    assert observed_order(hs, errs) >= 2.8
    assert errs[-1] < 5e-7


def test_reciprocity_symmetry():
    arena = arenas.load("paper")
    s = r.GreenSolver(arena, h=3.0)
    pts = arena.random_free_points(6, np.random.default_rng(1), clearance=1.0)
    G = np.array([s.green(p)(pts) for p in pts])  # G[i, j] = G(x_j, z_i)
    assert np.allclose(G, G.T, rtol=1e-10, atol=1e-12 * np.abs(G).max())


def test_neumann_walls_raise_the_signal_behind_obstacles():
    arena = arenas.load("paper")
    z = np.array([70.0, 70.0])
    d = r.GreenSolver(arena, h=3.0).green(z)
    n = r.GreenSolver(arena, h=3.0, walls="neumann").green(z)
    probe = np.array([[70.0, 110.0], [20.0, 100.0], [120.0, 80.0]])
    assert np.all(n(probe) > d(probe))


def test_forward_field_is_strength_times_green():
    arena = arenas.load("empty")
    s = r.GreenSolver(arena, h=4.0)
    u = s.field((60.0, 50.0), strength=850.0)
    g = s.green((60.0, 50.0))
    assert np.allclose(u.dofs, 850.0 * g.dofs)
    assert np.allclose(s.field().dofs, arena.strength * s.green(arena.source).dofs)


def test_batch_greens_match_single_solves():
    arena = arenas.load("maze")
    s = r.GreenSolver(arena, h=4.0)
    pts = np.array([[20.0, 20.0], [120.0, 50.0], [60.0, 120.0]])
    batch = s.greens(pts)
    for k, p in enumerate(pts):
        assert np.allclose(batch[:, k], s.green(p).dofs)


def test_mesh_is_graded_toward_reentrant_corners():
    arena = arenas.load("deep_u")
    m = r.mesh_free_region(arena, 4.0)
    corners = r.reentrant_corners(arena)
    # the U's two outer corners and four arm-tip corners are 270 degrees seen from the free region
    assert len(corners) == 6
    centroid = m.p[:, m.t].mean(axis=1).T
    p = m.p[:, m.t]
    size = np.sqrt(0.5 * np.abs((p[0, 1] - p[0, 0]) * (p[1, 2] - p[1, 0])
                                - (p[0, 2] - p[0, 0]) * (p[1, 1] - p[1, 0])))
    near = np.min(np.hypot(*(centroid[:, None, :] - corners[None]).transpose(2, 0, 1)), axis=1) < 2
    assert size[near].mean() < 0.5 * size[~near].mean()


def test_point_location_is_fast_and_correct_for_many_points():
    arena = arenas.load("paper")
    s = r.GreenSolver(arena, h=2.0)
    rng = np.random.default_rng(2)
    pts = np.column_stack([rng.uniform(0, 140, 100_000), rng.uniform(0, 140, 100_000)])
    cells = s.locate(pts)
    assert np.array_equal(cells >= 0, arena.contains(pts))
    v = s.green((70.0, 70.0))(pts)
    assert np.isnan(v[cells < 0]).all() and np.isfinite(v[cells >= 0]).all()


def test_vtk_export(tmp_path):
    import meshio
    s = r.GreenSolver(arenas.load("empty"), h=8.0)
    s.save_vtk(tmp_path / "g.vtu", G=s.green((50.0, 50.0)))
    mesh = meshio.read(tmp_path / "g.vtu")
    assert mesh.point_data["G"].shape == (len(s.nodes),)


def test_bad_input_messages():
    arena = arenas.load("paper")
    with pytest.raises(r.ReciprocityError, match="order must be 1 or 2"):
        r.GreenSolver(arena, order=3)
    with pytest.raises(r.ReciprocityError, match="walls must be"):
        r.GreenSolver(arena, walls="robin")
    with pytest.raises(r.MeshError, match="positive length"):
        r.GreenSolver(arena, h=-1)
    with pytest.raises(r.MeshError, match="too coarse"):
        r.GreenSolver(arena, h=100)
    s = r.GreenSolver(arena, h=5.0)
    with pytest.raises(r.ReciprocityError, match="outside the meshed free region"):
        s.green((70.0, 99.0))  # inside the hook-shaped obstacle


def test_a_cached_green_function_is_the_solve_itself(tmp_path, monkeypatch):
    """``green(z, cached=True)`` keeps the very numbers of the solve on disk; a new solver
    of the same mesh reads them back without assembling or factorizing."""
    monkeypatch.setenv("RECIPROCITY_CACHE", str(tmp_path))
    arena = arenas.load("paper")
    first = r.GreenSolver(arena, h=4.0, order=2).field((70.0, 70.0), 850.0, cached=True)
    again = r.GreenSolver(arena, h=4.0, order=2)
    u = again.field((70.0, 70.0), 850.0, cached=True)
    assert np.array_equal(u.dofs, first.dofs) and again._lu is None
    assert not np.array_equal(again.green((70.0, 71.0), cached=True).dofs, u.dofs / 850.0)
