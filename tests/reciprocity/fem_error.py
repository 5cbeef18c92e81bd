"""L2 errors of finite-element fields against exact solutions, by quadrature."""

import numpy as np


def l2_error_away(solver, dofs, exact, z, rmin):
    """(absolute, relative) L2 error of `dofs` against `exact(x, y)` over the elements whose
    centroid lies at least `rmin` from `z`, computed with the basis' quadrature."""
    basis = solver.basis
    uh = np.asarray(basis.interpolate(dofs))
    x = np.asarray(basis.global_coordinates())
    ex = exact(x[0], x[1])
    centroid = solver.mesh.p[:, solver.mesh.t].mean(axis=1)
    keep = np.hypot(centroid[0] - z[0], centroid[1] - z[1]) >= rmin
    w = basis.dx[keep]
    err = np.sqrt(np.sum(w * (uh[keep] - ex[keep]) ** 2))
    return err, err / np.sqrt(np.sum(w * ex[keep] ** 2))


def observed_order(hs, errs):
    """Slope of log(err) against log(h)."""
    return np.polyfit(np.log(hs), np.log(errs), 1)[0]
