"""Steady advection-diffusion-decay on an arena, and its discrete adjoint.

A substance released at ``x_s`` diffuses (``D``, cm²/s), is carried by a wind ``u``
(cm/s, divergence free, tangent to the walls: :class:`~reciprocity.fem.wind.WindField`)
and decays with lifetime ``τ`` (s)::

    L c = -D Δc + u·∇c + c/τ = δ(x - x_s),        L* v = -D Δv - u·∇v + v/τ = δ(x - z).

The Green's function of ``L`` is no longer symmetric, but reciprocity survives as
``c(z; x_s) = v(x_s; z)``: the reading at ``z`` of a source at ``x_s`` is the adjoint
field of ``z`` (wind reversed) evaluated at ``x_s``, so one adjoint solve per reading
scores every candidate source, as the Poisson adjoint does without wind.

Walls are either **impermeable** (no flux through them) or **absorbing** (``c = 0``).
"""

from __future__ import annotations

import time
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp

from arenas import Arena, as_points

from ..errors import ReciprocityError
from .green import Field, GreenSolver
from .wind import WindField, _positive

if TYPE_CHECKING:
    import skfem

# scikit-fem and SuperLU are imported where a solver is built (issue 24: start-up).

__all__ = ["AdvectionSolver", "WALL_KINDS"]

#: Wall conditions: zero total flux, or zero concentration.
WALL_KINDS = ("impermeable", "absorbing")
#: Diffusive term of the SUPG parameter, ``τ_K = 1 / (Σ_i |u·∇φ_i| + SUPG_DIFFUSION D / h_K² + 1/τ)``:
#: 12 matches the optimal one-dimensional parameter ``h/(2|u|) (coth Pe - 1/Pe)`` at small
#: cell Péclet numbers, the advective term matches it at large ones.
SUPG_DIFFUSION = 12.0


class AdvectionSolver:
    """Concentrations of ``-D Δc + u·∇c + c/τ = δ(x - x_s)`` on an arena, and their adjoints.

    Parameters
    ----------
    arena : Arena
        The arena (cm).
    wind : WindField
        The wind, cm/s (a potential flow through `arena`, or a uniform wind).
    D : float
        Diffusivity, cm²/s.
    tau : float
        Lifetime of the substance (decay time), s; ``inf`` for no decay (then absorbing
        walls, or an outflow, are needed for a bounded solution).
    h : float, optional
        Mesh size, cm; default the mesh of the wind's potential (1 cm for a uniform wind).
    walls : {"impermeable", "absorbing"}
        ``"impermeable"``: no flux through walls and obstacles (see Notes for the open
        parts of the boundary where the wind crosses it); ``"absorbing"``: ``c = 0`` on
        the whole boundary.
    supg : bool
        Add the streamline-upwind Petrov-Galerkin stabilisation (default True). Without it
        the Galerkin solution oscillates once the cell Péclet number exceeds about 1.

    Notes
    -----
    **Weak form.** With ``∇·u = 0``, multiplying by a test function ``w`` and integrating by
    parts gives::

        a(c, w) = ∫ D ∇c·∇w + (u·∇c) w + c w / τ  -  ∮_{u·n<0} (u·n) c w
                + Σ_K τ_K ∫_K (u·∇c + c/τ - D Δc)(u·∇w).

    The boundary term makes the natural conditions zero *total* flux
    ``(-D ∇c + u c)·n = 0`` where the wind enters (Danckwerts: clean air comes in) and
    zero *diffusive* flux ``∂c/∂n = 0`` where it leaves or runs along the wall. On walls
    and obstacles ``u·n = 0``, so both are ``∂c/∂n = 0``: impermeable. Integrating by
    parts the other way shows the adjoint carries the mirrored conditions (total flux
    zero where the *reversed* wind enters): the adjoint is the same kind of problem with
    the wind reversed, and ``a(c, c) ≥ D|∇c|² + |c|²/τ + ½∮|u·n| c²`` keeps both
    coercive even for a discrete wind with a small ``u·n`` on the walls.

    **Stabilisation.** The last sum is SUPG (Brooks & Hughes 1982) with
    ``τ_K = 1/(Σ_i |u·∇φ_i| + SUPG_DIFFUSION D/h_K² + 1/τ)``, ``h_K`` the longest edge.
    Only P1 elements are offered (``Δc = 0`` in each triangle; P2 would need the
    elements' second derivatives in the residual). The point source is loaded
    consistently, with the SUPG test function at the source: row ``b(x_s)`` of
    :meth:`source_matrix`, ``φ_i(x_s) + τ_K u·∇φ_i(x_s)``. A reading is the point value
    ``p(z)``, ``p_i(z) = φ_i(z)``.

    **Discrete adjoint.** The stabilised matrix ``A`` is not symmetric. The adjoint solve
    uses ``Aᵀ``, the adjoint of the discretisation, not a discretisation of ``L*``: one
    LU factorization of ``A`` serves both (SuperLU's transposed solve), and the adjoint
    field of a reading at ``z`` is read at a source position ``x`` through the same load
    ``b(x)``, so that::

        forward(x)(z) = p(z)ᵀ A⁻¹ b(x) = b(x)ᵀ A⁻ᵀ p(z) = adjoint(z)(x)

    to round-off. ``Aᵀ`` applies the streamline test on the upwind side of the reversed
    wind, the wrong side for ``L*``: SUPG is adjoint-inconsistent (Collis & Heinkenschloss
    2002): the adjoint's nodal values, as a P1 field, converge to the adjoint Green's
    function at a lower order than the forward field (``benchmarks/advection.md``), but
    read through ``b(x)`` they are the forward field exactly, with its order.

    Examples
    --------
    >>> import arenas
    >>> arena = arenas.load("empty")
    >>> wind = WindField.uniform((1.0, 0.0), 2.0)
    >>> s = AdvectionSolver(arena, wind, D=5.0, tau=20.0, h=6.0)
    >>> c = s.forward((50.0, 70.0))
    >>> bool(c([[80.0, 70.0]])[0] > c([[20.0, 70.0]])[0])   # downwind is stronger
    True
    """

    def __init__(self, arena: Arena, wind: WindField, D: float, tau: float, *, h: float | None = None,
                 walls: str = "impermeable", supg: bool = True):
        if not isinstance(arena, Arena):
            raise ReciprocityError(f"arena must be an arenas.Arena (see arenas.load); got {type(arena).__name__}")
        if not isinstance(wind, WindField):
            raise ReciprocityError(f"wind must be a WindField (WindField.potential or WindField.uniform); "
                                   f"got {type(wind).__name__}")
        if walls not in WALL_KINDS:
            raise ReciprocityError(f"walls must be one of {WALL_KINDS}; got {walls!r}")
        self.D = _positive(D, "diffusivity D (cm²/s)")
        self.tau = np.inf if tau == np.inf else _positive(tau, "lifetime tau (s)")
        if h is None:
            h = wind.solver.h if wind.solver is not None else 1.0
        if wind.solver is not None and not _same_walls(wind.solver.arena, arena):
            raise ReciprocityError("the wind's potential was solved on another arena; build it with "
                                   "WindField.potential(arena, ...) on this arena")
        #: The finite-element space: mesh, P1 basis, point location, probes and point loads.
        self.space = GreenSolver(arena, h=h, order=1, walls="dirichlet")
        self.arena, self.wind, self.walls, self.supg = arena, wind, walls, bool(supg)
        self.h = self.space.h
        self.timings = dict(self.space.timings)
        basis = self.space.basis
        self._dirichlet = (basis.get_dofs(np.concatenate([self.space.outer_facets, self.space.obstacle_facets])).all()
                           if walls == "absorbing" else np.empty(0, dtype=int))
        self._free = np.setdiff1d(np.arange(basis.N), self._dirichlet)
        self._matrix = self._lu = self._h_k = None
        self._as_source = _SourceReading(self)

    # ------------------------------------------------------------------ assembly
    @property
    def matrix(self) -> sp.csr_matrix:
        """The stabilised operator ``A`` over every dof (assembled on first use)."""
        if self._matrix is None:
            clock = time.perf_counter()
            self._matrix = (self._interior_form() + self._inflow_form()).tocsr()
            self.timings["assemble"] = time.perf_counter() - clock
        return self._matrix

    def _interior_form(self) -> sp.spmatrix:
        import skfem
        from skfem.helpers import dot, grad
        basis = self.space.basis
        u = self.wind.at_quadrature(basis)
        D, rate = self.D, 1.0 / self.tau

        @skfem.BilinearForm
        def galerkin(c, w, p):
            return D * dot(grad(c), grad(w)) + (p.ux * c.grad[0] + p.uy * c.grad[1]) * w + rate * c * w

        @skfem.BilinearForm
        def streamline(c, w, p):
            # P1: Δc = 0 in each triangle, so the residual is u·∇c + c/τ
            residual = p.ux * c.grad[0] + p.uy * c.grad[1] + rate * c
            return p.tau_k * residual * (p.ux * w.grad[0] + p.uy * w.grad[1])

        a = galerkin.assemble(basis, ux=u[0], uy=u[1])
        if self.supg:
            a = a + streamline.assemble(basis, ux=u[0], uy=u[1], tau_k=self._supg_parameter(basis, u))
        return a

    def _supg_parameter(self, basis: skfem.CellBasis, u: np.ndarray) -> np.ndarray:
        """``τ_K`` at the quadrature points, shape (n_elements, n_points), s."""
        grads = [basis.basis[i][0].grad for i in range(basis.Nbfun)]
        return self._tau_k(u, grads, np.arange(basis.nelems)[:, None])

    def _tau_k(self, u: np.ndarray, grads: list, cells: np.ndarray) -> np.ndarray:
        """``τ_K = 1/(Σ_i |u·∇φ_i| + SUPG_DIFFUSION D/h_K² + 1/τ)`` for the wind `u` (2, ...) and the
        basis gradients `grads` (each (2, ...)) at points of the triangles `cells`."""
        if self._h_k is None:
            mesh = self.space.mesh
            p = mesh.p[:, mesh.t]                                           # (2, 3, n_el)
            edges = np.stack([p[:, 1] - p[:, 0], p[:, 2] - p[:, 1], p[:, 0] - p[:, 2]])
            self._h_k = np.hypot(edges[:, 0], edges[:, 1]).max(axis=0)      # longest edge
        # Σ_i |u·∇φ_i| = 2|u| / (length of the triangle along u) for the P1 hat functions
        streak = sum(np.abs(u[0] * g[0] + u[1] * g[1]) for g in grads)
        return 1.0 / (streak + SUPG_DIFFUSION * self.D / self._h_k[cells] ** 2 + 1.0 / self.tau)

    def source_matrix(self, points) -> sp.csr_matrix:
        """Loads of unit point sources at `points` (n, 2) cm, one row each, shape (n, n_dofs).

        Row k is ``φ_i(x_k) + τ_K u(x_k)·∇φ_i(x_k)``: the Galerkin load and the SUPG test
        function at the source, so the stabilised scheme stays consistent there (without
        the streamline term the source acts as a spurious dipole of strength ``τ_K u`` and
        the L2 error away from it drops to first order at high Péclet numbers).

        Raises
        ------
        ReciprocityError
            If a point is outside the meshed free region.
        """
        from .inverse_map import inverse_map
        pts = as_points(points, "source point")
        basis = self.space.basis
        cells = self.space.locate(pts)
        if (cells < 0).any():
            p = pts[np.argmax(cells < 0)]
            raise ReciprocityError(f"source point ({p[0]:.4g}, {p[1]:.4g}) cm is outside the meshed free "
                                   f"region of arena {self.arena.name!r}; choose a point in the free region")
        loc = inverse_map(basis.mapping, pts.T[:, :, None], cells)
        fields = [basis.elem.gbasis(basis.mapping, loc, k, tind=cells)[0] for k in range(basis.Nbfun)]
        values = np.array([np.asarray(f)[:, 0] for f in fields])                  # (Nbfun, n)
        if self.supg:
            grads = [f.grad[:, :, 0] for f in fields]
            u = np.nan_to_num(self.wind(pts).T)   # a point off the wind's own mesh: no wind
            tau = self._tau_k(u, grads, cells)
            values = values + tau * np.array([u[0] * g[0] + u[1] * g[1] for g in grads])
        rows = np.tile(np.arange(len(pts)), basis.Nbfun)
        cols = basis.element_dofs[:, cells].ravel()
        return sp.coo_matrix((values.ravel(), (rows, cols)), shape=(len(pts), basis.N)).tocsr()

    def _inflow_form(self) -> sp.spmatrix:
        """``-∮_{u·n<0} (u·n) c w``: total flux zero where the wind enters (impermeable walls only;
        absorbing walls fix every boundary value)."""
        import skfem
        basis = self.space.basis
        n = basis.N
        if self.walls == "absorbing":
            return sp.csr_matrix((n, n))
        facets = np.concatenate([self.space.outer_facets, self.space.obstacle_facets])
        fb = skfem.FacetBasis(basis.mesh, basis.elem, facets=facets)
        u = self._wind_on_facets(fb)

        @skfem.BilinearForm
        def inflow(c, w, p):
            un = p.ux * p.n[0] + p.uy * p.n[1]
            return -np.minimum(un, 0.0) * c * w

        return inflow.assemble(fb, ux=u[0], uy=u[1])

    def _wind_on_facets(self, fb: skfem.FacetBasis) -> np.ndarray:
        """Wind at the facet quadrature points, evaluated in the triangle behind each facet."""
        x = np.asarray(fb.global_coordinates())                        # (2, nf, nq)
        if self.wind.is_uniform:
            return self.wind(x.reshape(2, -1).T).T.reshape(x.shape)
        cells = np.repeat(fb.tind, x.shape[-1])
        pts = x.reshape(2, -1).T
        own = self.wind.solver.mesh
        mesh = self.space.mesh
        if not (own.t.shape == mesh.t.shape and np.array_equal(own.t, mesh.t) and np.array_equal(own.p, mesh.p)):
            # another mesh of the arena: locate a point just inside the triangle behind the facet
            centroid = mesh.p[:, mesh.t[:, cells]].mean(axis=1).T
            pts = pts + 1e-6 * (centroid - pts)
            cells = self.wind.solver.locate(pts)
            lost = cells < 0                  # off the wind's mesh (a curved wall): its triangle's centroid
            pts[lost] = centroid[lost]
            cells[lost] = self.wind.solver.locate(pts[lost])
        return self.wind._gradient_in_cells(pts, cells).T.reshape(x.shape)

    def factorize(self) -> "AdvectionSolver":
        """Assemble and factorize ``A`` (free dofs) now, as the first solve otherwise does."""
        if self._lu is None:
            from scipy.sparse.linalg import splu
            a = self.matrix
            clock = time.perf_counter()
            self._lu = splu(a[self._free][:, self._free].tocsc())
            self.timings["factorize"] = time.perf_counter() - clock
        return self

    # ------------------------------------------------------------------ solves
    @property
    def n_unknowns(self) -> int:
        """Number of free degrees of freedom (size of the factorized system)."""
        return int(self._free.size)

    def _solve(self, rhs: np.ndarray, trans: str) -> np.ndarray:
        self.factorize()
        out = np.zeros_like(rhs)
        out[self._free] = self._lu.solve(np.ascontiguousarray(rhs[self._free]), trans=trans)
        return out

    def forwards(self, points) -> np.ndarray:
        """Dof values of the concentrations of unit sources at `points` (n, 2) cm, shape (n_dofs, n)."""
        return self._solve(self.source_matrix(points).T.toarray(), "N")

    def adjoints(self, points) -> np.ndarray:
        """Dof values of the adjoint fields of readings at `points` (n, 2) cm, shape (n_dofs, n).

        ``source_matrix(x) @ adjoints(z)`` is the matrix of readings at `z` from unit
        sources at `x`: one solve per reading scores every candidate source.
        """
        pts = as_points(points, "observation point")
        m, inside = self.space.probe_matrix(pts)
        if not inside.all():
            p = pts[np.argmin(inside)]
            raise ReciprocityError(f"observation point ({p[0]:.4g}, {p[1]:.4g}) cm is outside the meshed free "
                                   f"region of arena {self.arena.name!r}; choose a point in the free region")
        return self._solve(m.T.toarray(), "T")

    def forward(self, source) -> Field:
        """Concentration ``c(·; x_s)`` of a unit source at `source` (2,), cm, read at any point.

        Returns
        -------
        Field
            Concentration per unit release rate, s/cm² (``field(z)`` is the reading at `z`).
        """
        x = as_points(source, "source point")[0]
        return Field(self.space, self.forwards(x[None])[:, 0], f"c(., ({x[0]:.4g}, {x[1]:.4g}))")

    def adjoint(self, z) -> Field:
        """Adjoint field of a reading at `z` (2,), cm: ``L* v = δ(· - z)``, wind reversed, solved with ``Aᵀ``.

        Returns
        -------
        Field
            Evaluated at `x` it gives the reading at `z` of a unit source at `x`
            (:meth:`source_matrix` applied to the dofs): ``adjoint(z)(x) == forward(x)(z)``
            to round-off (reciprocity; see Notes of the class).
        """
        z = as_points(z, "observation point")[0]
        return Field(self._as_source, self.adjoints(z[None])[:, 0], f"v(., ({z[0]:.4g}, {z[1]:.4g}))")

    def __repr__(self) -> str:
        return (f"AdvectionSolver(arena={self.arena.name!r}, D={self.D}, tau={self.tau}, walls={self.walls!r}, "
                f"h={self.h}, unknowns={self.n_unknowns})")


def _same_walls(a: Arena, b: Arena) -> bool:
    """The two arenas have the same boundary and obstacles."""
    return (np.array_equal(a.boundary, b.boundary) and len(a.obstacles) == len(b.obstacles)
            and all(np.array_equal(p, q) for p, q in zip(a.obstacles, b.obstacles)))


class _SourceReading:
    """An advection solver's space read as a *source position*: the probe of an adjoint
    :class:`Field` is :meth:`AdvectionSolver.source_matrix`, so that evaluating the
    adjoint of a reading at `x` gives the reading from a unit source at `x`."""

    def __init__(self, solver: AdvectionSolver):
        self.solver = solver
        self._grids: dict = {}

    def probe_matrix(self, points) -> tuple[sp.csr_matrix, np.ndarray]:
        """Source rows at `points` (zero rows outside the free region) and the inside mask."""
        pts = as_points(points)
        inside = self.solver.space.locate(pts) >= 0
        n_dofs = self.solver.space.basis.N
        if not inside.any():
            return sp.csr_matrix((len(pts), n_dofs)), inside
        rows = self.solver.source_matrix(pts[inside]).tocoo()
        m = sp.coo_matrix((rows.data, (np.flatnonzero(inside)[rows.row], rows.col)),
                          shape=(len(pts), n_dofs)).tocsr()
        return m, inside

    def grid_probe(self, spacing: float):
        """``(x, y, matrix, inside)`` of a raster of `spacing` cm, as :meth:`GreenSolver.grid_probe`."""
        if spacing not in self._grids:
            x, y, _, inside = self.solver.space.grid_probe(spacing)
            xx, yy = np.meshgrid(x, y)
            m, inside = self.probe_matrix(np.column_stack([xx.ravel(), yy.ravel()]))
            self._grids[spacing] = (x, y, m, inside)
        return self._grids[spacing]
