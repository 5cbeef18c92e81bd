"""The inverse of the quadratic (isoparametric) element map: scikit-fem's Newton iteration,
and a fallback for points just outside their cell on a curved boundary (issue 35: the car's
floor on a generated ring arena raised "Newton iteration didn't converge")."""

import numpy as np
import pytest

import arenas
from reciprocity.fem import inverse_map as im
from reciprocity.fem.green import GreenSolver


def test_inside_points_map_as_scikit_fem_does_and_outside_ones_stay_in_their_cell():
    solver = GreenSolver(arenas.load("disk"), h=6.0, order=2)
    mapping = solver.basis.mapping
    cells = np.arange(0, solver.basis.mesh.t.shape[1], 7)
    # points inside their cells: the image of interior reference points
    ref = np.array([[0.2], [0.3]])[:, :, None] * np.ones((1, len(cells), 1))
    x = mapping.F(ref, cells)
    np.testing.assert_allclose(im.inverse_map(mapping, x, cells), mapping.invF(x, tind=cells))
    np.testing.assert_allclose(im.inverse_map(mapping, x, cells), ref, atol=1e-10)
    # far outside every cell: scikit-fem gives up, the fallback returns a point of the cell
    far = np.full((2, len(cells), 1), 1e3)
    with pytest.raises(Exception, match="Newton"):
        mapping.invF(far, tind=cells)
    X = im.inverse_map(mapping, far, cells)
    assert np.isfinite(X).all()
    assert (X >= 0).all() and (X[0] + X[1] <= 1 + 1e-12).all()


# --------------------------------------------------------------- the compiled kernels
# From COMPILED_MIN_POINTS points on, compiled kernels answer; they repeat scikit-fem's
# arithmetic, so their answers are scikit-fem's (and the NumPy fallback's) to the bit.



def _floor_like(solver, n, seed, rim=True):
    """`n` random points of the arena's box, in their cells as a probe matrix puts them
    (points between a chord and its arc in the nearest cell); those in no cell dropped."""
    (x0, x1), (y0, y1) = solver.arena.bounds
    rng = np.random.default_rng(seed)
    pts = np.column_stack([rng.uniform(x0, x1, n), rng.uniform(y0, y1, n)])
    if rim and solver.arena.circle is not None:    # and a tenth along the circle, inside it
        cx, cy, r = solver.arena.circle
        a, d = rng.uniform(0, 2 * np.pi, n // 10), r - solver.h * rng.uniform(0, 0.05, n // 10)
        pts = np.vstack([pts, np.column_stack([cx + d * np.cos(a), cy + d * np.sin(a)])])
    cells, keep = solver._probe_cells(pts)
    return pts[keep].T[:, :, None], cells[keep]


def _numpy_path(solver, x, cells):
    """scikit-fem's inverse map, or the NumPy fallback where it raises; and the basis values."""
    mapping = solver.basis.mapping
    try:
        X, fell_back = mapping.invF(x, tind=cells), False
    except Exception:                                    # noqa: BLE001 - scikit-fem's bare Exception
        X, fell_back = im._projected(mapping, x, cells), True
    phis = np.array([solver.basis.elem.gbasis(mapping, X, k, tind=cells)[0]
                     for k in range(solver.basis.Nbfun)])
    return X, phis, fell_back


@pytest.mark.parametrize("arena, order, h", [("disk", 2, 4.0), ("paper", 1, 6.0), ("paper", 2, 8.0)])
def test_the_compiled_kernels_give_scikit_fems_answers_to_the_bit(arena, order, h):
    solver = GreenSolver(arenas.load(arena), h=h, order=order)
    fell_back_on = []                              # the seeds whose set sent scikit-fem to the fallback
    for seed in range(2 if arena == "disk" else 1):
        x, cells = _floor_like(solver, 6000, seed)
        assert x.shape[1] >= im.COMPILED_MIN_POINTS
        X, phis, fell_back = _numpy_path(solver, x, cells)
        if fell_back:
            fell_back_on.append(seed)
        got = im.inverse_map(solver.basis.mapping, x, cells)
        assert got.shape == X.shape and np.array_equal(got, X)
        values = im.basis_values(solver.basis, got, cells)
        assert values.shape == phis.shape and np.array_equal(values, phis)
    if arena == "disk":      # points beyond a curved cell's chord: scikit-fem's Newton gives up
        assert fell_back_on, "no set sent scikit-fem's Newton to the fallback"


@pytest.mark.parametrize("tol, n, steps, again", [(3e-14, 100, 4, True), (5e-14, 2500, 6, False),
                                                 (3e-14, 1000, None, True)])
def test_a_newton_whose_points_settle_and_move_again_stops_where_scikit_fems_does(tol, n, steps, again):
    """Below scikit-fem's tolerance, rounding moves settled points again: scikit-fem stops
    at the first step at which all points have settled (`steps`), or raises (None), and
    the compiled Newton, which walks each point alone, finds the same step."""
    from reciprocity.fem._inverse_kernels import p2_newton
    solver = GreenSolver(arenas.load("disk"), h=4.0, order=2)
    mapping = solver.basis.mapping
    x, cells = _floor_like(solver, 5000, 0, rim=False)
    x, cells = x[:, :n], cells[:n]
    X = np.full(x.shape, 0.5)                      # scikit-fem's steps, counted
    unsettled = []
    while len(unsettled) < 50 and (not unsettled or unsettled[-1]):
        dX = np.einsum("ijkl,jkl->ikl", mapping.invDF(X, cells), x - mapping.F(X, cells))
        X = np.clip(X + dX, 0.0, 1.0)
        unsettled.append(int((np.abs(dX).sum(axis=(0, 2)) >= tol).sum()))
    assert again == any(b > a for a, b in zip(unsettled, unsettled[1:]))  # more moving again
    got, converged = p2_newton(np.ascontiguousarray(x[:, :, 0]), cells.astype(np.int64),
                               np.ascontiguousarray(mapping.mesh.doflocs),
                               mapping.mesh.dofs.element_dofs.astype(np.int64), 50, tol)
    if steps is None:
        assert not converged
        with pytest.raises(Exception, match="Newton"):
            mapping.invF(x, tind=cells, newton_tol=tol)
    else:
        assert converged and len(unsettled) == steps
        assert np.array_equal(got, mapping.invF(x, tind=cells, newton_tol=tol)[:, :, 0])


def test_fewer_points_take_scikit_fems_own_code():
    solver = GreenSolver(arenas.load("disk"), h=4.0, order=2)
    x, cells = _floor_like(solver, 3000, 1)
    x, cells = x[:, :100], cells[:100]
    X, _, _ = _numpy_path(solver, x, cells)
    assert np.array_equal(im.inverse_map(solver.basis.mapping, x, cells), X)


def test_a_zero_jacobian_fails_the_compiled_newton_as_scikit_fem_raises():
    from reciprocity.fem._inverse_kernels import p2_newton, p2_projected
    doflocs = np.zeros((2, 6))                     # all six nodes at one point
    dofs = np.arange(6, dtype=np.int64)[:, None]
    x = np.zeros((2, 3))
    cells = np.zeros(3, dtype=np.int64)
    assert not p2_newton(x, cells, doflocs, dofs, 50, 1e-12)[1]
    assert not p2_projected(x, cells, doflocs, dofs, 50)[1]
