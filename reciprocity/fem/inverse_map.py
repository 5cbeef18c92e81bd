"""Points of a triangle mesh in their cells' reference coordinates, and the basis values there.

:func:`inverse_map` is scikit-fem's inverse element map (``mapping.invF``) with a fallback
for points just outside their cell on a curved boundary; :func:`basis_values` gives the
values of a Lagrange basis at the reference points it returns. Both answer large sets
(from :data:`COMPILED_MIN_POINTS` points on: a painted floor's pixels) with compiled kernels
(:mod:`reciprocity.fem._inverse_kernels`) that repeat scikit-fem's arithmetic operation for
operation, so the answers are the same to the bit; smaller sets, and meshes or elements the
kernels do not know, take scikit-fem's NumPy code, so that a point run loads no numba.
"""

from __future__ import annotations

import numpy as np

__all__ = ["COMPILED_MIN_POINTS", "INVERSE_ITERATIONS", "basis_values", "inverse_map"]

#: Newton steps of the fallback inverse map (:func:`inverse_map`).
INVERSE_ITERATIONS = 50

#: From this many points on, the compiled kernels answer.
COMPILED_MIN_POINTS = 2048

#: scikit-fem's default steps and tolerance of ``MappingIsoparametric.invF``.
NEWTON_ITERATIONS, NEWTON_TOL = 50, 1e-12


def _kind(mapping) -> str | None:
    """``"affine"`` for a triangle mesh's affine map, ``"p2"`` for a quadratic triangle
    mesh's isoparametric one, else None (the NumPy path: another mesh, or a scikit-fem
    whose mappings keep their arrays elsewhere)."""
    from skfem.element import ElementTriP2
    from skfem.mapping import MappingAffine, MappingIsoparametric
    try:
        if type(mapping) is MappingAffine and mapping.dim == 2 and mapping.tind is None \
                and mapping.mesh.t.shape[0] == 3 and mapping.invA.shape[:2] == (2, 2):
            return "affine"
        if type(mapping) is MappingIsoparametric and type(mapping.elem) is ElementTriP2 \
                and mapping.mesh.dofs.element_dofs.shape[0] == 6 and mapping.mesh.doflocs.shape[0] == 2:
            return "p2"
    except AttributeError:
        pass
    return None


def inverse_map(mapping, x: np.ndarray, tind: np.ndarray) -> np.ndarray:
    """Reference coordinates of the points `x` (2, n, 1), cm, in the cells `tind`.

    scikit-fem's Newton iteration (``mapping.invF``), and where it does not converge (a point
    just outside its cell on a curved boundary, where the iterate bounces on the clipped
    reference square), the same iteration with the iterate kept in the reference triangle,
    :data:`INVERSE_ITERATIONS` steps from its centre: the nearest point of the cell, whose
    basis values are those of the boundary next to the point. As scikit-fem's, the
    iteration is one for all the points of a call: they all step until every one has
    converged, and one that does not sends them all to the fallback.

    Returns
    -------
    ndarray, shape (2, n, 1)
    """
    tind = np.asarray(tind)
    kind = _kind(mapping) if x.shape[1] >= COMPILED_MIN_POINTS and x.shape[2] == 1 else None
    if kind == "affine":
        from ._inverse_kernels import affine_inverse
        pts = np.ascontiguousarray(x[:, :, 0], dtype=float)
        return affine_inverse(pts, tind.astype(np.int64), mapping.invA, mapping.b)[:, :, None]
    if kind == "p2":
        from ._inverse_kernels import p2_newton, p2_projected
        pts = np.ascontiguousarray(x[:, :, 0], dtype=float)
        cells = tind.astype(np.int64)
        doflocs = np.ascontiguousarray(mapping.mesh.doflocs, dtype=float)
        dofs = np.ascontiguousarray(mapping.mesh.dofs.element_dofs, dtype=np.int64)
        X, done = p2_newton(pts, cells, doflocs, dofs, NEWTON_ITERATIONS, NEWTON_TOL)
        if not done:
            X, done = p2_projected(pts, cells, doflocs, dofs, INVERSE_ITERATIONS)
        if done:
            return X[:, :, None]
        # a zero Jacobian in the fallback: the NumPy path says so as scikit-fem does
        return _projected(mapping, x, tind)
    try:
        return mapping.invF(x, tind=tind)
    except Exception:                            # noqa: BLE001 -- scikit-fem raises a bare Exception
        pass
    return _projected(mapping, x, tind)


def _projected(mapping, x: np.ndarray, tind: np.ndarray) -> np.ndarray:
    """The fallback of :func:`inverse_map` in NumPy."""
    X = np.full(x.shape, 1.0 / 3.0)
    for _ in range(INVERSE_ITERATIONS):
        dX = np.einsum("ijkl,jkl->ikl", mapping.invDF(X, tind), x - mapping.F(X, tind))
        X = _in_reference_triangle(X + dX)
    return X


def _in_reference_triangle(X: np.ndarray) -> np.ndarray:
    """`X` (2, n, 1) moved into the reference triangle ``{X0, X1 >= 0, X0 + X1 <= 1}``."""
    X = np.clip(X, 0.0, 1.0)
    excess = np.maximum(X[0] + X[1] - 1.0, 0.0) / 2.0
    return np.clip(X - excess[None], 0.0, 1.0)


def basis_values(basis, X: np.ndarray, tind: np.ndarray) -> np.ndarray:
    """The values of each of `basis`'s functions at reference points `X` (2, n, 1) of the
    cells `tind`: shape (Nbfun, n, 1), as ``basis.elem.gbasis(...)[0]`` gives them."""
    from skfem.element import ElementTriP1, ElementTriP2
    elem = type(basis.elem)
    if X.shape[1] >= COMPILED_MIN_POINTS and X.shape[2] == 1 and elem in (ElementTriP1, ElementTriP2):
        from ._inverse_kernels import p1_values, p2_values
        pts = np.ascontiguousarray(X[:, :, 0], dtype=float)
        return (p1_values if elem is ElementTriP1 else p2_values)(pts)[:, :, None]
    return np.array([basis.elem.gbasis(basis.mapping, X, k, tind=tind)[0]
                     for k in range(basis.Nbfun)])
