"""The geometry of a function on a P1 mesh: the exact area of a superlevel set, its
bounding polylines, and the maximiser refined below the mesh size. The imaging map's
region of possible sources ``{P_M >= eps}`` and its estimate are computed here."""

from __future__ import annotations

import numpy as np

from ..fem.green import GreenSolver
from ..fem.mesh import triangle_areas

__all__ = ["superlevel_area", "refined_maximum", "contour"]


def superlevel_area(points: np.ndarray, triangles: np.ndarray, values: np.ndarray,
                    level: float, areas: np.ndarray | None = None) -> float:
    """Exact area of ``{f >= level}`` for the P1 interpolant ``f`` of nodal `values`.

    Parameters
    ----------
    points : ndarray, shape (n, 2)
        Node coordinates, cm.
    triangles : ndarray, shape (m, 3)
        Triangles as node indices.
    values : ndarray, shape (n,)
        Nodal values of ``f``.
    level : float
        Threshold.
    areas : ndarray, shape (m,), optional
        Precomputed triangle areas.

    Returns
    -------
    float
        Area, cm^2. Each triangle contributes its area times the exact fraction where
        the linear interpolant is at least `level`.
    """
    area = triangle_areas(points, triangles) if areas is None else areas
    f = values[triangles] - level
    pos = f >= 0
    count = pos.sum(axis=1)
    frac = (count == 3).astype(float)
    mixed = (count == 1) | (count == 2)
    if mixed.any():
        fm, pm, cm = f[mixed], pos[mixed], count[mixed]
        # the lone vertex: the positive one when one is positive, else the negative one
        lone_is_pos = cm == 1
        lone = np.where(lone_is_pos, np.argmax(pm, axis=1), np.argmin(pm, axis=1))
        rows = np.arange(len(fm))
        fa = fm[rows, lone]
        fb = fm[rows, (lone + 1) % 3]
        fc = fm[rows, (lone + 2) % 3]
        corner = (fa / (fa - fb)) * (fa / (fa - fc))
        frac[mixed] = np.where(lone_is_pos, corner, 1.0 - corner)
    return float(np.sum(area * frac))


def refined_maximum(solver: GreenSolver, values: np.ndarray) -> np.ndarray:
    """The maximiser (cm) of nodal `values` on `solver`'s mesh, refined below the mesh size.

    The node of the largest value is refined by the vertex of a least-squares quadratic
    fitted to the nodes within ``2.5 h``, when that quadratic is concave and its vertex
    stays within ``1.5 h`` of the node and inside the free region.

    Parameters
    ----------
    solver : GreenSolver
        The mesh (its nodes, mesh size ``h`` and point location).
    values : ndarray, shape (n_nodes,)
        Nodal values.
    """
    nodes, P = solver.nodes, values
    i = int(np.argmax(P))
    x0 = nodes[i]
    h = solver.h
    near = np.flatnonzero(np.hypot(*(nodes - x0).T) <= 2.5 * h)
    if near.size < 8:
        return x0.copy()
    d = (nodes[near] - x0) / h
    A = np.column_stack([np.ones(len(d)), d[:, 0], d[:, 1], d[:, 0] ** 2,
                         d[:, 0] * d[:, 1], d[:, 1] ** 2])
    coef = np.linalg.lstsq(A, P[near], rcond=None)[0]
    H = np.array([[2 * coef[3], coef[4]], [coef[4], 2 * coef[5]]])
    if np.all(np.linalg.eigvalsh(H) < 0):
        step = np.linalg.solve(H, -coef[1:3])
        if np.hypot(*step) <= 1.5:
            cand = x0 + h * step
            if solver.locate(cand[None])[0] >= 0:
                return cand
    return x0.copy()


def contour(solver: GreenSolver, values: np.ndarray, level: float) -> list[np.ndarray]:
    """Polylines (cm) of ``{f = level}`` for nodal `values` on `solver`'s mesh; none
    when `level` lies outside the values' range."""
    # matplotlib's triangle contouring, on a figure that is never shown
    from matplotlib.figure import Figure
    from matplotlib.tri import Triangulation
    if not (values.min() < level < values.max()):
        return []
    tri = solver.triangulation if solver.order == 1 else Triangulation(
        solver.nodes[:, 0], solver.nodes[:, 1], solver.triangles)
    cs = Figure().add_subplot().tricontour(tri, values, levels=[level])
    return [np.asarray(s) for s in cs.allsegs[0] if len(s) > 1]
