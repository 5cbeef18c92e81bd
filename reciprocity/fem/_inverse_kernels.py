"""The numba kernels of the inverse reference map (:mod:`reciprocity.fem.inverse_map`).

They live apart so that importing the FEM layer loads no numba; the inverse map imports
this module where a kernel first runs, and ``cache=True`` keeps the compiled code on disk
between processes.

Each kernel repeats scikit-fem 12's NumPy arithmetic operation for operation, in the same
order, so that its answers are the same to the bit:

* :func:`affine_inverse`: ``MappingAffine.invF``, ``invA (x - b)``;
* :func:`p2_newton`: ``MappingIsoparametric.invF`` on a quadratic triangle mesh, a Newton
  iteration from the reference point (0.5, 0.5), clipped to the unit square, that every
  point of the call takes in step until *all* of them have moved by less than the
  tolerance (an iteration that never gets there, or a zero Jacobian, fails the call). The
  kernel walks each point alone and finds that step from the walks;
* :func:`p2_projected`: the fallback of :func:`reciprocity.fem.inverse_map.inverse_map`
  when that fails, the same Newton step from (1/3, 1/3) kept in the reference triangle,
  a fixed number of times;
* :func:`p1_values`, :func:`p2_values`: the values of the basis functions at reference
  points, as ``ElementTriP1.lbasis`` and ``ElementTriP2.lbasis`` write them.

No expression is contracted into fused multiply-adds (numba does not, without
``fastmath``), and ``x ** 2`` is ``x * x``, as NumPy computes a square.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["affine_inverse", "p1_values", "p2_newton", "p2_projected", "p2_values"]

#: No step: beyond any walk (walks take at most 63 steps, the bits of an int64).
NO_STEP = 64


@njit(cache=True)
def affine_inverse(x, cells, inv_a, b):  # pragma: no cover (compiled)
    """Reference coordinates of points in affine triangles.

    Parameters
    ----------
    x : ndarray, shape (2, n)
        Points, cm.
    cells : ndarray of int, shape (n,)
        The triangle of each point.
    inv_a : ndarray, shape (2, 2, m)
        The inverse of each triangle's affine map's matrix, 1/cm.
    b : ndarray, shape (2, m)
        Each triangle's first corner, cm.

    Returns
    -------
    ndarray, shape (2, n)
    """
    n = x.shape[1]
    out = np.empty((2, n))
    for p in range(n):
        c = cells[p]
        y0 = x[0, p] - b[0, c]
        y1 = x[1, p] - b[1, c]
        out[0, p] = inv_a[0, 0, c] * y0 + inv_a[0, 1, c] * y1
        out[1, p] = inv_a[1, 0, c] * y0 + inv_a[1, 1, c] * y1
    return out


@njit(cache=True, inline="always")
def _p2_phi(x, y):  # pragma: no cover (compiled)
    """The six quadratic basis functions at the reference point (`x`, `y`), as
    ``ElementTriP2.lbasis`` writes them."""
    return (1. - 3. * x - 3. * y + 2. * (x * x) + 4. * x * y + 2. * (y * y),
            2. * (x * x) - x,
            2. * (y * y) - y,
            4. * x - 4. * (x * x) - 4. * x * y,
            4. * x * y,
            4. * y - 4. * x * y - 4. * (y * y))


@njit(cache=True)
def _p2_step(px, py, tx, ty, X0, X1):  # pragma: no cover (compiled)
    """One Newton step of the quadratic map with nodes `px`, `py` towards (`tx`, `ty`).

    Returns ``(dX0, dX1, ok)``; ``ok`` is False where the Jacobian's determinant is zero.
    The sums run over the six nodes in scikit-fem's order, from zero.
    """
    x, y = X0, X1
    phi = _p2_phi(x, y)
    # derivatives (d/dx, d/dy) of each basis function, as ElementTriP2.lbasis writes them
    a0 = -3 + 4. * x + 4. * y
    b0 = -3 + 4. * x + 4. * y
    a1 = 4. * x - 1
    b1 = 0. * x
    a2 = 0. * x
    b2 = 4. * y - 1
    a3 = 4 - 8. * x - 4. * y
    b3 = -4. * x
    a4 = 4. * y
    b4 = 4. * x
    a5 = -4. * y
    b5 = 4 - 4. * x - 8. * y
    a = (a0, a1, a2, a3, a4, a5)
    b = (b0, b1, b2, b3, b4, b5)
    F0 = F1 = J00 = J01 = J10 = J11 = 0.0
    for k in range(6):                              # each sum over the nodes in order, from zero
        F0 += px[k] * phi[k]
        F1 += py[k] * phi[k]
        J00 += px[k] * a[k]
        J01 += px[k] * b[k]
        J10 += py[k] * a[k]
        J11 += py[k] * b[k]
    det = J00 * J11 - J01 * J10
    if det == 0.0:
        return 0.0, 0.0, False
    i00 = J11 / det
    i01 = -J01 / det
    i10 = -J10 / det
    i11 = J00 / det
    r0 = tx - F0
    r1 = ty - F1
    return i00 * r0 + i01 * r1, i10 * r0 + i11 * r1, True


@njit(cache=True)
def _nodes(doflocs, dofs, c, px, py):  # pragma: no cover (compiled)
    """The six nodes of cell `c` into `px`, `py`."""
    for k in range(6):
        px[k] = doflocs[0, dofs[k, c]]
        py[k] = doflocs[1, dofs[k, c]]


@njit(cache=True)
def _p2_walk(x, cells, doflocs, dofs, steps, tol, until_settled, p, px, py, X):  # pragma: no cover (compiled)
    """Point `p`'s Newton iterates from its entry of `X`, at most `steps` steps, in place;
    with `until_settled`, only until the first step that moves it by less than `tol`.

    Returns ``(unsettled, zero)``: bit ``k`` of `unsettled` is set when step ``k`` moved the
    point by `tol` or more, and `zero` is the step whose Jacobian's determinant was zero
    (where the walk stopped), or :data:`NO_STEP`.
    """
    _nodes(doflocs, dofs, cells[p], px, py)
    unsettled = np.int64(0)
    for k in range(steps):
        u, v = X[0, p], X[1, p]
        d0, d1, ok = _p2_step(px, py, x[0, p], x[1, p], u, v)
        if not ok:
            return unsettled, k
        X[0, p] = min(max(u + d0, 0.), 1.)
        X[1, p] = min(max(v + d1, 0.), 1.)
        if abs(d0) + abs(d1) < tol:
            if until_settled:
                break
        else:
            unsettled |= np.int64(1) << k
    return unsettled, NO_STEP


@njit(cache=True)
def p2_newton(x, cells, doflocs, dofs, iterations, tol):  # pragma: no cover (compiled)
    """``MappingIsoparametric.invF`` of scikit-fem 12 on a quadratic triangle mesh.

    scikit-fem steps every point from (0.5, 0.5) together and returns at the first step
    at which all of them moved by less than `tol`; it raises when no step gets there, or
    when a Jacobian's determinant is zero at a step before it. Here each point walks
    alone (:func:`_p2_walk`), which keeps its six nodes at hand:

    1. every point walks until it first settles: the steps before are steps at which not
       all had settled, so the first step not among them is the earliest candidate;
    2. every point walks to the candidate step; if all have settled there, it is
       scikit-fem's step (each earlier one was ruled out) and the walk its answer; if not,
       the steps seen unsettled are ruled out too, and so is every step at which a point
       seen unsettled there (one that had settled and moved again) is unsettled: such a
       point walks all the steps alone. The walks go on to the next candidate.

    Parameters
    ----------
    x : ndarray, shape (2, n)
        Points, cm.
    cells : ndarray of int, shape (n,)
        The cell of each point.
    doflocs : ndarray, shape (2, ndofs)
        The mesh's node positions (vertices, then edge nodes), cm.
    dofs : ndarray of int, shape (6, ncells)
        Each cell's six nodes.
    iterations : int
        At most this many steps (at most 63).
    tol : float
        A point has settled at a step that moved it by less than `tol` (the sum of both
        coordinates' moves).

    Returns
    -------
    X : ndarray, shape (2, n)
        The reference coordinates at that step.
    converged : bool
        False where scikit-fem raises; `X` is then of no use.
    """
    n = x.shape[1]
    X = np.full((2, n), 0.5)
    px = np.empty(6)
    py = np.empty(6)
    ruled_out = np.int64(0)                         # steps at which some point had not settled
    zero = NO_STEP                                  # the first step with a zero Jacobian
    walked = -1                                     # steps the second walks have taken
    whole = np.zeros(n, dtype=np.bool_)             # points whose every step is known
    witness = np.empty(n, dtype=np.int64)
    scratch = np.empty((2, n))
    for p in range(n):
        unsettled, z = _p2_walk(x, cells, doflocs, dofs, iterations, tol, True, p, px, py, X)
        ruled_out |= unsettled
        zero = min(zero, z)
        whole[p] = z < NO_STEP or (unsettled >> (iterations - 1)) & 1 == 1   # never settled
    while True:
        step = 0
        while step < iterations and (ruled_out >> step) & 1:
            step += 1
        if step == iterations or zero <= step:
            return X, False
        if walked < 0:                              # the first candidate: walk from the start
            X[:] = 0.5
            walked = 0
        seen = np.int64(0)                          # (the walks go on from the last candidate)
        witnesses = 0
        for p in range(n):
            unsettled, z = _p2_walk(x, cells, doflocs, dofs, step + 1 - walked, tol, False, p, px, py, X)
            unsettled <<= walked
            seen |= unsettled
            zero = min(zero, z + walked)
            if (unsettled >> step) & 1 and not whole[p]:
                witness[witnesses] = p
                witnesses += 1
        walked = step + 1
        if zero <= step:
            return X, False
        if not (seen >> step) & 1:
            return X, True
        ruled_out |= seen
        for i in range(witnesses):                  # a point seen moving again: all its steps
            p = witness[i]
            whole[p] = True
            scratch[0, p] = scratch[1, p] = 0.5
            unsettled, z = _p2_walk(x, cells, doflocs, dofs, iterations, tol, False, p, px, py, scratch)
            ruled_out |= unsettled
            zero = min(zero, z)


@njit(cache=True)
def p2_projected(x, cells, doflocs, dofs, iterations):  # pragma: no cover (compiled)
    """The fallback Newton iteration: from (1/3, 1/3), `iterations` steps, each iterate
    moved into the reference triangle as
    :func:`reciprocity.fem.inverse_map._in_reference_triangle` moves it. A point whose step
    leaves it where it was, to the bit, stays there.

    Returns ``(X, ok)``; ``ok`` is False where a Jacobian's determinant was zero.
    """
    n = x.shape[1]
    X = np.full((2, n), 1.0 / 3.0)
    px = np.empty(6)
    py = np.empty(6)
    for p in range(n):
        _nodes(doflocs, dofs, cells[p], px, py)
        for _ in range(iterations):
            a, b = X[0, p], X[1, p]
            d0, d1, ok = _p2_step(px, py, x[0, p], x[1, p], a, b)
            if not ok:
                return X, False
            u = min(max(a + d0, 0.0), 1.0)
            v = min(max(b + d1, 0.0), 1.0)
            excess = max(u + v - 1.0, 0.0) / 2.0
            X[0, p] = min(max(u - excess, 0.0), 1.0)
            X[1, p] = min(max(v - excess, 0.0), 1.0)
            if X[0, p] == a and X[1, p] == b:
                break
    return X, True


@njit(cache=True)
def p1_values(X):  # pragma: no cover (compiled)
    """The three linear basis functions at reference points `X` (2, n): (3, n)."""
    n = X.shape[1]
    out = np.empty((3, n))
    for p in range(n):
        x, y = X[0, p], X[1, p]
        out[0, p] = 1. - x - y
        out[1, p] = x
        out[2, p] = y
    return out


@njit(cache=True)
def p2_values(X):  # pragma: no cover (compiled)
    """The six quadratic basis functions at reference points `X` (2, n): (6, n)."""
    n = X.shape[1]
    out = np.empty((6, n))
    for p in range(n):
        phi = _p2_phi(X[0, p], X[1, p])
        for k in range(6):
            out[k, p] = phi[k]
    return out
