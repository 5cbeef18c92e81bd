"""Wind fields that respect the walls: potential flow through an arena.

A source in wind needs a velocity field ``u`` (cm/s) that does not blow through walls or
obstacles. The least that does is **potential flow**: ``u = ∇φ`` with ``Δφ = 0`` in the
free region, ``∂φ/∂n = 0`` on every wall and obstacle (no penetration) and the normal
velocity prescribed on inflow and outflow segments of the outer boundary. It is
divergence free, needs one Laplace solve with the arena's finite elements, and has no
parameter beyond the inflow. It is irrotational and inviscid, so it has no wakes, no
recirculation behind obstacles and no boundary layers (it slips along the walls); the
next step toward a real indoor flow is Stokes flow (``-ν Δu + ∇p = 0``, ``∇·u = 0``,
``u = 0`` on the walls), a mixed (Taylor-Hood) solve on the same mesh.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from arenas import Arena, as_points

from ..errors import ReciprocityError
from .green import Field, GreenSolver
from .inverse_map import inverse_map

if TYPE_CHECKING:
    import skfem

# scikit-fem and SuperLU are imported where a potential is solved (issue 24: start-up).

__all__ = ["WindField", "boundary_segments"]

#: Degree of the potential's Lagrange elements: quadratic, so the velocity ``∇φ`` is
#: piecewise linear and ``u·n`` on the walls converges at second order.
WIND_ORDER = 2
#: Mesh grading toward re-entrant corners (that of the P1 solvers, whose mesh the potential
#: then shares: its gradient is interpolated, not located, at their quadrature points).
MESH_GRADING = 0.5
#: A segment end farther than this from the boundary polygon (relative to the arena's
#: size) is not on the boundary.
ON_BOUNDARY_REL = 1e-9
#: Gauss-Legendre points per boundary facet for the inflow/outflow loads (exact for the
#: quadratic shape functions on any part of a facet).
_EDGE_GAUSS = 3


class WindField:
    """A steady wind ``u(x)`` over an arena, cm/s, evaluable at arbitrary points.

    Build one with :meth:`potential` (a flow through the arena that respects its walls)
    or :meth:`uniform` (the same vector everywhere: free-space references and tests).

    Parameters
    ----------
    velocity : ndarray, shape (2,), optional
        The constant wind of a uniform field, cm/s.
    potential : Field, optional
        The velocity potential ``φ`` (cm²/s) of a potential flow, on its solver's mesh.
    speed : float
        The speed that defines the field: the uniform speed, or the inflow speed.

    Notes
    -----
    Exactly one of `velocity` and `potential` is given; prefer the constructors.
    """

    def __init__(self, velocity=None, potential: Field | None = None, speed: float = 0.0):
        if (velocity is None) == (potential is None):
            raise ReciprocityError("give a WindField either a constant velocity or a potential "
                                   "(use WindField.uniform or WindField.potential)")
        self._velocity = None if velocity is None else np.asarray(velocity, dtype=float).reshape(2)
        self.potential_field = potential
        self.speed = float(speed)
        self._max_speed: float | None = None

    # ------------------------------------------------------------------ constructors
    @classmethod
    def uniform(cls, direction, speed: float) -> "WindField":
        """The same wind everywhere (it ignores walls): references and tests.

        Parameters
        ----------
        direction : array_like, shape (2,) or float
            Direction of the wind: a vector (any length but zero) or a heading in radians
            (0 along +x, counter-clockwise).
        speed : float
            Wind speed, cm/s (zero allowed: no wind).

        Returns
        -------
        WindField

        Examples
        --------
        >>> w = WindField.uniform((1.0, 0.0), 5.0)
        >>> w([[10.0, 20.0]]).tolist()
        [[5.0, 0.0]]
        """
        speed = _positive(speed, "wind speed", allow_zero=True)
        d = np.asarray(direction, dtype=float)
        if d.ndim == 0:
            d = np.array([np.cos(d), np.sin(d)])
        norm = float(np.hypot(*d)) if d.shape == (2,) else np.nan
        if not np.isfinite(norm) or norm == 0:
            raise ReciprocityError(f"wind direction must be a non-zero vector (dx, dy) or a heading in "
                                   f"radians; got {direction!r}")
        return cls(velocity=speed * d / norm, speed=speed)

    @classmethod
    def potential(cls, arena: Arena, inflow, outflow, speed: float, h: float = 1.0,
                  order: int = WIND_ORDER) -> "WindField":
        """Potential flow through `arena` from inflow to outflow segments of its boundary.

        Solves ``Δφ = 0`` with ``∂φ/∂n = -U`` on the inflow segments, ``∂φ/∂n = U L_in /
        L_out`` on the outflow segments (the same flux leaves as enters) and ``∂φ/∂n = 0``
        on every other wall and obstacle, and returns ``u = ∇φ``.

        Parameters
        ----------
        arena : Arena
            The arena (cm).
        inflow, outflow : sequence of ((x0, y0), (x1, y1))
            Segments of the outer boundary, cm, where the wind enters and leaves. Each must
            lie along the boundary polygon and not along an obstacle attached to it.
        speed : float
            Inflow speed ``U`` normal to the inflow segments, cm/s.
        h : float
            Mesh size, cm (the mesh of :class:`GreenSolver` for the same arena and `h`).
        order : {1, 2}
            Degree of the potential's elements (default :data:`WIND_ORDER`).

        Returns
        -------
        WindField

        Raises
        ------
        ReciprocityError
            If a segment is not on the outer boundary, or the speed is not positive.

        Notes
        -----
        The Neumann problem fixes ``φ`` up to a constant; the flux data balance exactly
        (the segment loads are integrated exactly over the parts of facets they cover), so
        pinning one value gives the solution. Total inflow is ``U`` times the inflow length.

        Examples
        --------
        >>> import arenas
        >>> w = WindField.potential(arenas.load("empty"), inflow=[((0, 40), (0, 100))],
        ...                         outflow=[((140, 40), (140, 100))], speed=10.0, h=8.0)
        >>> bool(w([[70.0, 70.0]])[0, 0] > 0)
        True
        """
        speed = _positive(speed, "inflow speed")
        # the mesh grading of the P1 solvers, so the advection solver shares this mesh
        solver = GreenSolver(arena, h=h, order=order, walls="neumann", grading=MESH_GRADING)
        seg_in = _segments(arena, inflow, "inflow")
        seg_out = _segments(arena, outflow, "outflow")
        covered_in = _check_on_outer_facets(solver, seg_in, "inflow")
        covered_out = _check_on_outer_facets(solver, seg_out, "outflow")
        _check_disjoint(seg_in, seg_out)
        length_in, length_out = covered_in.sum(), covered_out.sum()
        # weak form: ∫ ∇φ·∇v = ∮ (∂φ/∂n) v, ∂φ/∂n = u·n (n outward)
        rhs = (-speed * _segment_load(solver, seg_in)
               + speed * length_in / length_out * _segment_load(solver, seg_out))
        phi = _neumann_solve(solver.stiffness, rhs)
        return cls(potential=Field(solver, phi, "potential"), speed=speed)

    # ------------------------------------------------------------------ evaluation
    @property
    def is_uniform(self) -> bool:
        """True for a constant wind (:meth:`uniform`)."""
        return self._velocity is not None

    @property
    def solver(self) -> GreenSolver | None:
        """The finite-element space of the potential (None for a uniform wind)."""
        return None if self.potential_field is None else self.potential_field.solver

    def __call__(self, points) -> np.ndarray:
        """Wind at `points` (n, 2) in cm, shape (n, 2), cm/s; NaN outside the free region."""
        pts = as_points(points)
        if self.is_uniform:
            return np.broadcast_to(self._velocity, pts.shape).copy()
        solver = self.solver
        cells = solver.locate(pts)
        out = np.full(pts.shape, np.nan)
        inside = cells >= 0
        if inside.any():
            out[inside] = self._gradient_in_cells(pts[inside], cells[inside])
        return out

    def _gradient_in_cells(self, pts: np.ndarray, cells: np.ndarray) -> np.ndarray:
        """``∇φ`` at `pts` (n, 2) lying in mesh triangles `cells`, shape (n, 2)."""
        basis = self.solver.basis
        loc = inverse_map(basis.mapping, pts.T[:, :, None], cells)
        phi = self.potential_field.dofs
        grad = np.zeros((2, len(pts)))
        for k in range(basis.Nbfun):
            g = basis.elem.gbasis(basis.mapping, loc, k, tind=cells)[0].grad[:, :, 0]
            grad += g * phi[basis.element_dofs[k, cells]]
        return grad.T

    def at_quadrature(self, basis: skfem.CellBasis) -> np.ndarray:
        """Wind at the quadrature points of a scikit-fem basis, shape (2, n_elements, n_points).

        On the potential's own mesh the gradient is interpolated directly; on any other
        mesh of the same arena the quadrature points are located first.
        """
        n_el, n_qp = basis.nelems, basis.X.shape[-1]
        if self.is_uniform:
            return np.broadcast_to(self._velocity[:, None, None], (2, n_el, n_qp)).copy()
        own = self.solver.mesh
        if basis.mesh.t.shape == own.t.shape and np.array_equal(basis.mesh.t, own.t) \
                and np.array_equal(basis.mesh.p, own.p):
            import skfem
            same = skfem.Basis(own, self.solver.basis.elem, quadrature=basis.quadrature)
            return np.asarray(same.interpolate(self.potential_field.dofs).grad)
        x = np.asarray(basis.global_coordinates()).reshape(2, -1)
        return self(x.T).T.reshape(2, n_el, n_qp)

    def element_velocity(self, mesh: skfem.MeshTri) -> np.ndarray:
        """Wind at the centroid of each triangle of `mesh`, shape (n_triangles, 2), cm/s."""
        return self(mesh.p[:, mesh.t].mean(axis=1).T)

    def node_velocity(self, mesh: skfem.MeshTri) -> np.ndarray:
        """Wind at each vertex of `mesh`, shape (n_vertices, 2), cm/s: the area-weighted
        mean over the triangles around the vertex (``∇φ`` jumps between triangles)."""
        import skfem
        corners = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])      # reference vertices, mesh.t order
        basis = skfem.Basis(mesh, skfem.ElementTriP1(), quadrature=(corners, np.full(3, 1.0 / 6.0)))
        u = self.at_quadrature(basis)                                 # (2, n_tri, 3)
        area = np.asarray(basis.dx).sum(axis=1)
        out = np.zeros((mesh.p.shape[1], 2))
        weight = np.zeros(mesh.p.shape[1])
        for k in range(3):
            np.add.at(out, mesh.t[k], (u[:, :, k] * area).T)
            np.add.at(weight, mesh.t[k], area)
        return out / weight[:, None]

    @property
    def max_speed(self) -> float:
        """Largest wind speed over the free region, cm/s (at the quadrature points of the
        potential's mesh for a potential flow)."""
        if self._max_speed is None:
            if self.is_uniform:
                self._max_speed = float(np.hypot(*self._velocity))
            else:
                u = self.at_quadrature(self.solver.basis)
                self._max_speed = float(np.hypot(u[0], u[1]).max())
        return self._max_speed

    def peclet(self, h: float, D: float) -> float:
        """Largest cell Péclet number ``max|u| h / (2 D)`` on a mesh of size `h`.

        Parameters
        ----------
        h : float
            Mesh size, cm.
        D : float
            Diffusivity, cm²/s.

        Returns
        -------
        float
            Above 1 the plain Galerkin method oscillates; the advection solver adds
            streamline-upwind stabilisation (SUPG).
        """
        return self.max_speed * _positive(h, "mesh size") / (2.0 * _positive(D, "diffusivity"))

    def __repr__(self) -> str:
        if self.is_uniform:
            return f"WindField.uniform({self._velocity.tolist()})"
        return f"WindField.potential(arena={self.solver.arena.name!r}, speed={self.speed}, h={self.solver.h})"


# ---------------------------------------------------------------------- helpers
def boundary_segments(arena: Arena, inflow, outflow) -> tuple[np.ndarray, np.ndarray]:
    """The inflow and outflow segments checked against `arena`'s outer boundary without
    meshing: each along one straight edge of the boundary polygon, of positive length,
    and no inflow overlapping an outflow. (Whether an obstacle attached to the boundary
    covers part of one is known only on the mesh: :meth:`WindField.potential`.)

    Returns
    -------
    (ndarray (n, 2, 2), ndarray (m, 2, 2))
        The inflow and outflow segments, cm.

    Raises
    ------
    ReciprocityError
        As :meth:`WindField.potential` for the same segments.
    """
    seg_in = _segments(arena, inflow, "inflow")
    seg_out = _segments(arena, outflow, "outflow")
    _check_disjoint(seg_in, seg_out)
    return seg_in, seg_out


def _positive(value, what: str, allow_zero: bool = False) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        v = np.nan
    if not np.isfinite(v) or v < 0 or (v == 0 and not allow_zero):
        bound = "a non-negative" if allow_zero else "a positive"
        raise ReciprocityError(f"{what} must be {bound} number; got {value!r}")
    return v


def _segments(arena: Arena, segments, what: str) -> np.ndarray:
    """`segments` as an (n, 2, 2) array, each lying along an edge of the boundary polygon."""
    try:
        seg = np.asarray(segments, dtype=float)
    except (TypeError, ValueError):
        seg = np.empty(0)
    if seg.ndim != 3 or seg.shape[1:] != (2, 2) or len(seg) == 0 or not np.isfinite(seg).all():
        raise ReciprocityError(f"{what} must be a list of segments ((x0, y0), (x1, y1)) in cm; got {segments!r}")
    b = arena.boundary
    edges = np.stack([b, np.roll(b, -1, axis=0)], axis=1)               # (m, 2, 2)
    tol = ON_BOUNDARY_REL * max(1.0, float(np.ptp(b)))
    for p0, p1 in seg:
        if np.hypot(*(p1 - p0)) <= tol:
            raise ReciprocityError(f"{what} segment {_fmt(p0)}-{_fmt(p1)} has zero length")
        if not _on_one_edge(p0, p1, edges, tol):
            raise ReciprocityError(
                f"{what} segment {_fmt(p0)}-{_fmt(p1)} cm does not lie along one edge of the boundary of "
                f"arena {arena.name!r}; give both ends on the same straight wall of the outer boundary")
    return seg


def _on_one_edge(p0, p1, edges: np.ndarray, tol: float) -> bool:
    """Both ends within `tol` of one boundary edge (so the whole segment is)."""
    return bool(((_distance_to_segments(p0, edges) <= tol) & (_distance_to_segments(p1, edges) <= tol)).any())


def _distance_to_segments(p: np.ndarray, edges: np.ndarray) -> np.ndarray:
    a, b = edges[:, 0], edges[:, 1]
    d = b - a
    t = np.clip(np.einsum("ij,ij->i", p - a, d) / np.maximum(np.einsum("ij,ij->i", d, d), 1e-300), 0, 1)
    return np.hypot(*(a + t[:, None] * d - p).T)


def _fmt(p) -> str:
    return f"({p[0]:.4g}, {p[1]:.4g})"


def _facet_overlaps(solver: GreenSolver, seg: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Outer facets along segment `seg` (2, 2): facet indices and the covered parameter
    interval ``[t0, t1]`` of each (t from the facet's first vertex to its second)."""
    mesh = solver.mesh
    f = solver.outer_facets
    a, b = mesh.p[:, mesh.facets[0, f]].T, mesh.p[:, mesh.facets[1, f]].T    # (nf, 2)
    p0, p1 = seg
    length = np.hypot(*(p1 - p0))
    d = (p1 - p0) / length
    normal = np.array([-d[1], d[0]])
    tol = ON_BOUNDARY_REL * max(1.0, float(np.ptp(solver.arena.boundary)))
    collinear = (np.abs((a - p0) @ normal) <= tol) & (np.abs((b - p0) @ normal) <= tol)
    sa, sb = (a - p0) @ d, (b - p0) @ d
    lo = np.maximum(np.minimum(sa, sb), 0.0)
    hi = np.minimum(np.maximum(sa, sb), length)
    keep = collinear & (hi > lo + tol)
    sa, sb, lo, hi = sa[keep], sb[keep], lo[keep], hi[keep]
    t0, t1 = (lo - sa) / (sb - sa), (hi - sa) / (sb - sa)
    return f[keep], np.minimum(t0, t1), np.maximum(t0, t1)


def _check_on_outer_facets(solver: GreenSolver, segs: np.ndarray, what: str) -> np.ndarray:
    """Length (cm) of each segment covered by outer facets of the mesh; raises when a part
    of a segment runs along an obstacle attached to the boundary instead."""
    mesh = solver.mesh
    covered = np.empty(len(segs))
    for i, seg in enumerate(segs):
        f, t0, t1 = _facet_overlaps(solver, seg)
        flen = np.hypot(*(mesh.p[:, mesh.facets[1, f]] - mesh.p[:, mesh.facets[0, f]]))
        covered[i] = float(np.sum((t1 - t0) * flen))
        length = float(np.hypot(*(seg[1] - seg[0])))
        if covered[i] < length * (1 - 1e-9):
            raise ReciprocityError(
                f"{what} segment {_fmt(seg[0])}-{_fmt(seg[1])} cm runs along an obstacle attached to the "
                f"boundary of arena {solver.arena.name!r} ({length - covered[i]:.3g} cm of it are not free "
                f"boundary); shorten it to the open part of the wall")
    return covered


def _check_disjoint(seg_in: np.ndarray, seg_out: np.ndarray) -> None:
    for a in seg_in:
        for b in seg_out:
            d = b[1] - b[0]
            n = np.array([-d[1], d[0]]) / np.hypot(*d)
            if abs((a[0] - b[0]) @ n) > 1e-9 * (1 + np.abs(a).max()) or abs((a[1] - b[0]) @ n) > 1e-9 * (1 + np.abs(a).max()):
                continue
            u = d / np.hypot(*d)
            sa = sorted(((a[0] - b[0]) @ u, (a[1] - b[0]) @ u))
            if min(sa[1], np.hypot(*d)) > max(sa[0], 0.0):
                raise ReciprocityError(f"inflow segment {_fmt(a[0])}-{_fmt(a[1])} overlaps outflow segment "
                                       f"{_fmt(b[0])}-{_fmt(b[1])} cm; make them disjoint")


def _segment_load(solver: GreenSolver, segs: np.ndarray) -> np.ndarray:
    """``∫_segments v_i ds`` for every basis function ``v_i`` of `solver`: exact on facets
    the segments cover in part (Gauss-Legendre on the covered part)."""
    basis = solver.basis
    mesh = solver.mesh
    out = np.zeros(basis.N)
    xg, wg = np.polynomial.legendre.leggauss(_EDGE_GAUSS)
    for seg in segs:
        f, t0, t1 = _facet_overlaps(solver, seg)
        flen = np.hypot(*(mesh.p[:, mesh.facets[1, f]] - mesh.p[:, mesh.facets[0, f]]))
        t = t0[:, None] + (t1 - t0)[:, None] * (xg[None] + 1) / 2           # (nf, ng)
        w = (t1 - t0)[:, None] * wg[None] / 2 * flen[:, None]
        ends = [basis.nodal_dofs[0, mesh.facets[0, f]], basis.nodal_dofs[0, mesh.facets[1, f]]]
        if solver.order == 1:
            shapes = [(1 - t, ends[0]), (t, ends[1])]
        else:
            shapes = [((1 - t) * (1 - 2 * t), ends[0]), (t * (2 * t - 1), ends[1]),
                      (4 * t * (1 - t), basis.facet_dofs[0, f])]
        for phi, dofs in shapes:
            np.add.at(out, dofs, np.sum(w * phi, axis=1))
    return out


def _neumann_solve(stiffness, rhs: np.ndarray) -> np.ndarray:
    """Solution of the pure Neumann problem ``K φ = rhs`` (compatible data) with ``φ_0 = 0``."""
    from scipy.sparse.linalg import splu
    free = np.arange(1, stiffness.shape[0])
    k = stiffness[free][:, free].tocsc()
    lu = splu(k, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0, options=dict(SymmetricMode=True))
    phi = np.zeros(stiffness.shape[0])
    phi[free] = lu.solve(rhs[free])
    return phi
