"""Point location (reciprocity.fem.locate): the compiled pass over binned triangles answers
exactly as the nearest-centroid test and the trapezoid map do, on every kind of point."""

import numpy as np
import pytest
import skfem
from matplotlib.tri import Triangulation

import arenas
from arenas.floor import free_pixels
from reciprocity.fem.locate import MARGIN, TriangleLocator
from reciprocity.fem.mesh import mesh_free_region


def _hard_points(mesh, arena, rng):
    """Pixel centres, random points over the bounds (walls and outside included), the
    nodes, edge midpoints and points along edges: the points every locator must agree on."""
    p = mesh.p.T
    a, b = p[mesh.facets[0]], p[mesh.facets[1]]
    (x0, x1), (y0, y1) = arena.bounds
    return {
        "pixel centres": free_pixels(arena, 4.0)[1],
        "random": rng.uniform([x0 - 3, y0 - 3], [x1 + 3, y1 + 3], (20000, 2)),
        "nodes": p,
        "edge midpoints": (a + b) / 2,
        "along edges": a + rng.uniform(0, 1, (len(a), 1)) * (b - a),
        "near nodes": p + rng.normal(0, 1e-10, p.shape),
    }


@pytest.mark.parametrize("which", ["paper", "maze", "pillars"])
def test_the_compiled_pass_gives_the_exact_answer(which, monkeypatch):
    monkeypatch.setattr("reciprocity.fem.locate.BINNED_MIN_POINTS", 0)    # every set binned
    arena = arenas.generate("pillars", 1) if which == "pillars" else arenas.load(which)
    mesh = mesh_free_region(arena.without_scenario(), 3.0)
    loc = TriangleLocator(mesh.p.T, mesh.t.T)
    for kind, pts in _hard_points(mesh, arena, np.random.default_rng(3)).items():
        assert np.array_equal(loc.locate(pts), loc._locate_nearest(pts, 8)), kind


def test_the_compiled_pass_answers_only_points_well_inside():
    """What the bins answer lies inside its triangle by the margin; the rest (nodes, edges)
    are left to the exact path, and the bins answer nearly all pixel centres."""
    from reciprocity.fem._locate_kernels import locate_in_cells
    arena = arenas.load("paper")
    mesh = mesh_free_region(arena.without_scenario(), 3.0)
    loc = TriangleLocator(mesh.p.T, mesh.t.T)
    start, items, x0, y0, size, nx, ny, inv, origin = loc._binned()
    assert len(start) == nx * ny + 1 and nx * ny <= 9 * len(mesh.t.T) + 1
    pts = free_pixels(arena, 4.0)[1]
    got = locate_in_cells(pts, inv, origin, start, items, x0, y0, size, nx, ny, MARGIN)
    ok = got >= 0
    assert ok.mean() > 0.99
    lam = np.einsum("mij,mj->mi", inv[got[ok]], pts[ok] - origin[got[ok]])
    assert (lam.min(axis=1) >= MARGIN).all() and (lam.sum(axis=1) <= 1 - MARGIN).all()
    nodes = locate_in_cells(mesh.p.T.copy(), inv, origin, start, items, x0, y0, size, nx, ny, MARGIN)
    assert (nodes == -1).all()


def test_a_thin_mesh_keeps_its_bins_few_and_its_answers_exact(monkeypatch):
    monkeypatch.setattr("reciprocity.fem.locate.BINNED_MIN_POINTS", 0)
    mesh = skfem.MeshTri.init_tensor(np.linspace(0, 1000, 200), np.linspace(0, 1e-3, 3))
    loc = TriangleLocator(mesh.p.T, mesh.t.T)
    start = loc._binned()[0]
    assert len(start) - 1 <= 9 * len(mesh.t.T) + 1
    rng = np.random.default_rng(4)
    pts = np.column_stack([rng.uniform(-1, 1001, 5000), rng.uniform(-1e-4, 1.1e-3, 5000)])
    ref = Triangulation(mesh.p[0], mesh.p[1], mesh.t.T).get_trifinder()
    assert np.array_equal(loc.locate(pts), ref(pts[:, 0], pts[:, 1]))


def test_no_points_and_one_point():
    mesh = skfem.MeshTri.init_symmetric()
    loc = TriangleLocator(mesh.p.T, mesh.t.T)
    assert loc.locate(np.zeros((0, 2))).shape == (0,)
    ref = Triangulation(mesh.p[0], mesh.p[1], mesh.t.T).get_trifinder()
    assert loc.locate([0.25, 0.5]).tolist() == ref([0.25], [0.5]).tolist()


def test_a_few_points_load_no_numba():
    """A point run locates a few dozen points: the nearest-centroid path serves them, and
    numba (0.3-0.9 s to load) stays out of the process."""
    import subprocess
    import sys
    code = ("import sys, numpy as np, skfem; from reciprocity.fem.locate import TriangleLocator, "
            "BINNED_MIN_POINTS as n; m = skfem.MeshTri.init_symmetric().refined(3); "
            "loc = TriangleLocator(m.p.T, m.t.T); loc.locate(np.random.default_rng(0).uniform(0, 1, (n - 1, 2))); "
            "print('numba' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "False"
