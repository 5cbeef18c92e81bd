"""The inverse of the quadratic (isoparametric) element map: scikit-fem's Newton iteration,
and a fallback for points just outside their cell on a curved boundary (issue 35: the car's
floor on a generated ring arena raised "Newton iteration didn't converge")."""

import numpy as np
import pytest

import arenas
from reciprocity.fem.green import GreenSolver, _inverse_map


def test_inside_points_map_as_scikit_fem_does_and_outside_ones_stay_in_their_cell():
    solver = GreenSolver(arenas.load("disk"), h=6.0, order=2)
    mapping = solver.basis.mapping
    cells = np.arange(0, solver.basis.mesh.t.shape[1], 7)
    # points inside their cells: the image of interior reference points
    ref = np.array([[0.2], [0.3]])[:, :, None] * np.ones((1, len(cells), 1))
    x = mapping.F(ref, cells)
    np.testing.assert_allclose(_inverse_map(mapping, x, cells), mapping.invF(x, tind=cells))
    np.testing.assert_allclose(_inverse_map(mapping, x, cells), ref, atol=1e-10)
    # far outside every cell: scikit-fem gives up, the fallback returns a point of the cell
    far = np.full((2, len(cells), 1), 1e3)
    with pytest.raises(Exception, match="Newton"):
        mapping.invF(far, tind=cells)
    X = _inverse_map(mapping, far, cells)
    assert np.isfinite(X).all()
    assert (X >= 0).all() and (X[0] + X[1] <= 1 + 1e-12).all()
