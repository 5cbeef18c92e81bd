"""Finite-element Green's functions of an arena, factorized once.

Every adjoint solve ``-Δv = δ(x - z)`` (eq. 3 of Landa et al.) and every forward
signal ``-Δu = c δ(x - S)`` (eq. 1) is one back-substitution with the same sparse LU
factors: reciprocity ``G(x, z) = G(z, x)`` holds to solver precision because the
stiffness matrix is symmetric.
"""

from __future__ import annotations

import hashlib
import time
from collections import OrderedDict
from typing import TYPE_CHECKING, Callable

import numpy as np
import scipy.sparse as sp

from arenas import Arena, as_points

from ..errors import ReciprocityError
from .inverse_map import basis_values, inverse_map
from .locate import TriangleLocator
from .disk_cache import read_cached, write_cached
from .mesh import cached_mesh

if TYPE_CHECKING:
    import skfem
    from matplotlib.tri import Triangulation

# scikit-fem, SuperLU and the k-d tree are imported where a solver is built or used, so
# that listing strategies and scenarios (which import this module for its names) stays
# cheap (issue 24: start-up).

__all__ = ["GreenSolver", "Field", "GREEN_CACHE_SIZE"]

_WALLS = ("dirichlet", "neumann")
#: :meth:`GreenSolver.probe_matrix` remembers point sets at least this large ...
PROBE_CACHE_MIN = 10_000
#: ... and this many of them per solver (a 1 px/mm floor of ``paper`` is 10 chunks).
PROBE_CACHE_SIZE = 24
#: Bumped whenever a solver would give different Green's functions on the same mesh.
GREEN_FORMAT = 2
#: Green's functions kept on disk by :meth:`GreenSolver.green` with ``cached=True``, the
#: least recently used removed first (about 1 MB each for the truth of ``paper``). A
#: campaign walks its sources in the same order every run, which a least-recently-used
#: cache smaller than the campaign misses every time: this holds the true sources of
#: campaigns of up to 256 distinct sources (about 250 MB on disk for `paper`).
GREEN_CACHE_SIZE = 256


class Field:
    """A scalar field on an arena, evaluable at arbitrary points.

    Parameters
    ----------
    solver : GreenSolver
        The solver whose finite-element space holds the field.
    dofs : ndarray, shape (n_dofs,)
        Values at the solver's nodes :attr:`GreenSolver.nodes` (the P1 vertices, or the
        P2 vertices and edge midpoints).
    name : str
        Label used in plots and VTK files.

    Notes
    -----
    ``field(points)`` interpolates with the finite-element basis; points outside the
    free region get NaN (there is no field there).
    """

    def __init__(self, solver: "GreenSolver", dofs: np.ndarray, name: str = "field"):
        self.solver = solver
        self.dofs = np.asarray(dofs, dtype=float)
        self.name = name

    def __call__(self, points) -> np.ndarray:
        """Values at `points`, shape (n, 2) or (2,), in cm; NaN outside the free region."""
        pts = as_points(points)
        m, inside = self.solver.probe_matrix(pts)
        out = m @ self.dofs
        out[~inside] = np.nan
        return out

    @property
    def nodal(self) -> np.ndarray:
        """Values at :attr:`GreenSolver.nodes`."""
        return self.dofs

    def on_grid(self, spacing: float = 1.0):
        """Raster of the field: ``(x, y, values)`` with ``values[j, i]`` at ``(x[i], y[j])``.

        Parameters
        ----------
        spacing : float
            Grid spacing, cm. Cells outside the free region are NaN.
        """
        x, y, m, inside = self.solver.grid_probe(float(spacing))
        v = m @ self.dofs
        v[~inside] = np.nan
        return x, y, v.reshape(len(y), len(x))

    def __mul__(self, c: float) -> "Field":
        return Field(self.solver, self.dofs * float(c), self.name)

    __rmul__ = __mul__

    def __repr__(self) -> str:
        return f"Field({self.name!r}, {self.dofs.size} dofs)"


class GreenSolver:
    """Green's functions of ``-Δ`` on an arena's free region, by finite elements.

    Parameters
    ----------
    arena : Arena
        The arena (cm).
    h : float
        Mesh size away from re-entrant corners, cm. The default 1 cm gives about
        29 000 unknowns on the built-in ``paper`` arena.
    order : {1, 2}
        Polynomial degree of the Lagrange elements. On a disk, order 2 uses an
        isoparametric (curved) boundary so the geometry does not limit the order.
    walls : {"dirichlet", "neumann"}
        Condition on the obstacle walls. The outer boundary is always Dirichlet
        (``u = 0``), which makes the problem well posed.
    grading : float, optional
        Mesh grading exponent toward re-entrant corners (see
        :func:`reciprocity.fem.mesh.mesh_free_region`); default 0.5 for P1, 0.75 for P2.
    mesh : reciprocity.spaces.MeshSpace, optional
        A mesh of the same arena and `h` to solve on (P1), so a search space and its
        solver share one mesh and one triangulation.

    Notes
    -----
    The mesh comes from the disk cache of :func:`~reciprocity.fem.mesh.cached_mesh`. The
    stiffness matrix is assembled and factorized on the first solve (or by
    :meth:`factorize`): a solver whose fields all come from the disk cache
    (``green(z, cached=True)``) never pays for either.

    Examples
    --------
    >>> import arenas, reciprocity
    >>> solver = reciprocity.GreenSolver(arenas.load("empty"), h=4.0)
    >>> v = solver.green((70.0, 70.0))
    >>> float(v([[70.0, 100.0]])[0]) > 0
    True
    """

    def __init__(self, arena: Arena, h: float = 1.0, order: int = 1,
                 walls: str = "dirichlet", grading: float | None = None, mesh=None):
        import skfem
        from scipy.spatial import cKDTree
        if not isinstance(arena, Arena):
            raise ReciprocityError(f"arena must be an arenas.Arena (see arenas.load); got "
                                   f"{type(arena).__name__}")
        if order not in (1, 2):
            raise ReciprocityError(f"order must be 1 or 2; got {order!r}")
        if walls not in _WALLS:
            raise ReciprocityError(f"walls must be one of {_WALLS}; got {walls!r}")
        self.arena, self.h, self.order, self.walls = arena, float(h), int(order), walls
        if grading is None:
            grading = 0.5 if order == 1 else 0.75
        clock = time.perf_counter()
        if mesh is not None and (mesh.arena is not arena or mesh.h != self.h):
            raise ReciprocityError("mesh must be a MeshSpace of the same arena and h")
        mesh1 = mesh.mesh if mesh is not None else cached_mesh(arena, h, grading=grading)
        #: Wall times (s) of the set-up stages: mesh, then assemble and factorize once done.
        self.timings = {"mesh": time.perf_counter() - clock}
        self._mesh1 = mesh1
        self.mesh = self._curved(mesh1) if (order == 2 and arena.circle is not None) else mesh1
        elem = skfem.ElementTriP1() if order == 1 else skfem.ElementTriP2()
        self.basis = skfem.Basis(self.mesh, elem)
        self._facet_classes = None
        self._classify_boundary()
        self._free = np.setdiff1d(np.arange(self.basis.N), self._dirichlet)
        self._stiffness = self._a_id = self._lu = None
        # point location: a trapezoid map on the straight-sided vertex mesh (O(log n))
        #: Point location and triangulation of the straight-sided vertex mesh (shared with
        #: the search space of the same mesh when one is given).
        self.locator = mesh.locator if mesh is not None else TriangleLocator(mesh1.p.T, mesh1.t.T)
        self._centroids = cKDTree(mesh1.p[:, mesh1.t].mean(axis=1).T)
        self._grid_cache: dict = {}
        self._probe_cache: OrderedDict = OrderedDict()

    @property
    def stiffness(self) -> sp.csr_matrix:
        """Stiffness matrix of ``-Δ`` over every dof (assembled on first use)."""
        if self._stiffness is None:
            from skfem.models.poisson import laplace
            clock = time.perf_counter()
            self._stiffness = laplace.assemble(self.basis).tocsr()
            self.timings["assemble"] = time.perf_counter() - clock
        return self._stiffness

    def factorize(self) -> "GreenSolver":
        """Assemble and factorize now, as the first solve otherwise does; returns the solver.

        Notes
        -----
        The stiffness matrix with the Dirichlet dofs removed is symmetric positive
        definite (the outer boundary is always Dirichlet), so SuperLU orders it by
        minimum degree on ``A + A^T`` and keeps the diagonal pivots (``SymmetricMode``,
        ``diag_pivot_thresh=0``): no row exchanges, which would spoil a symmetric
        ordering, and less fill than the default COLAMD column ordering, hence faster
        back-substitutions, which dominate a search (one or more per reading).
        """
        if self._lu is None:
            from scipy.sparse.linalg import splu
            a_free = self.stiffness[self._free]
            clock = time.perf_counter()
            self._a_id = a_free[:, self._dirichlet].tocsr()
            # symmetric ordering with diagonal pivots (Notes); the same ordering with the
            # default partial pivoting exchanges rows and is many times slower
            self._lu = splu(a_free[:, self._free].tocsc(), permc_spec="MMD_AT_PLUS_A",
                            diag_pivot_thresh=0.0, options=dict(SymmetricMode=True))
            self.timings["factorize"] = time.perf_counter() - clock
        return self

    @property
    def triangulation(self) -> Triangulation:
        """The straight-sided vertex mesh as a matplotlib Triangulation (built once)."""
        return self.locator.triangulation

    # ------------------------------------------------------------------ set-up
    def _curved(self, mesh1: skfem.MeshTri) -> skfem.MeshTri2:
        """Quadratic mesh whose boundary edge midpoints lie on the exact circle."""
        import skfem
        cx, cy, r = self.arena.circle
        m2 = skfem.MeshTri2.from_mesh(mesh1)
        facets = mesh1.boundary_facets()
        ends = mesh1.p[:, mesh1.facets[:, facets]]  # (2, 2, nf)
        on_circle = (np.abs(np.hypot(ends[0] - cx, ends[1] - cy) - r) < 1e-9 * r).all(axis=0)
        mid = mesh1.p.shape[1] + facets[on_circle]  # P2 dofs: vertices, then edges
        loc = m2.doflocs.copy()
        d = loc[:, mid] - np.array([[cx], [cy]])
        loc[:, mid] = d * (r / np.hypot(*d)) + np.array([[cx], [cy]])
        from dataclasses import replace
        return replace(m2, doflocs=loc)

    def _classify_boundary(self) -> None:
        """The Dirichlet dofs: every wall's, or the outer boundary's with Neumann walls."""
        if self.order == 1 and self.walls == "dirichlet":
            # P1 dofs are the nodes, and every wall is Dirichlet: the nodes on the boundary,
            # as scikit-fem's facet tables give them (which cost ten times more to build;
            # the facets are classified when first asked for)
            self._dirichlet = boundary_nodes(self._mesh1.t, self._mesh1.p.shape[1])
            return
        self._classify_facets()
        dir_facets = self.outer_facets if self.walls == "neumann" else np.concatenate(
            [self.outer_facets, self.obstacle_facets])
        self._dirichlet = self.basis.get_dofs(np.sort(dir_facets)).all()

    @property
    def outer_facets(self) -> np.ndarray:
        """The mesh's facets (scikit-fem's numbering) on the outer boundary."""
        if self._facet_classes is None:
            self._classify_facets()
        return self._facet_classes[0]

    @property
    def obstacle_facets(self) -> np.ndarray:
        """The mesh's facets (scikit-fem's numbering) on the obstacles."""
        if self._facet_classes is None:
            self._classify_facets()
        return self._facet_classes[1]

    def _classify_facets(self) -> None:
        """The boundary facets, on the outer boundary or on an obstacle."""
        m = self._mesh1
        facets = m.boundary_facets()
        ends = m.p[:, m.facets[:, facets]]  # (2, 2, nf)
        if self.arena.circle is not None:
            cx, cy, r = self.arena.circle
            dist = np.abs(np.hypot(ends[0] - cx, ends[1] - cy) - r)
            on_outer = (dist < 1e-9 * r).all(axis=0)
        else:
            import shapely
            from shapely.geometry import LinearRing
            ring = LinearRing(self.arena.boundary)
            pts = shapely.points(ends.transpose(1, 2, 0).reshape(-1, 2))
            dist = shapely.distance(ring, pts).reshape(2, -1)
            on_outer = (dist < 1e-9 * max(1.0, np.ptp(self.arena.boundary))).all(axis=0)
        self._facet_classes = (facets[on_outer], facets[~on_outer])

    # ------------------------------------------------------------------ geometry
    @property
    def nodes(self) -> np.ndarray:
        """Locations (cm) of the degrees of freedom, shape (n_dofs, 2)."""
        return self.basis.doflocs.T

    @property
    def n_unknowns(self) -> int:
        """Number of free degrees of freedom (size of the factorized system)."""
        return int(self._free.size)

    @property
    def triangles(self) -> np.ndarray:
        """P1 triangles on :attr:`nodes`, shape (n_tri, 3): the mesh itself for P1, each
        triangle split in four through its edge midpoints for P2."""
        if self.order == 1:
            return self._mesh1.t.T
        return self._mesh1.refined().t.T

    def locate(self, points) -> np.ndarray:
        """Index of the mesh triangle holding each point, -1 outside the free region."""
        return self.locator.locate(as_points(points))

    def probe_matrix(self, points) -> tuple[sp.csr_matrix, np.ndarray]:
        """Sparse matrix mapping dof values to values at `points`, and an inside mask.

        Rows of points outside the free region are zero (mask False). Large point sets
        (at least PROBE_CACHE_MIN points: rasters such as a painted floor) are remembered
        by content, PROBE_CACHE_SIZE of them per solver, so a second field on the same
        raster (the floor of the next episode's source) costs a sparse product instead of
        locating every pixel again.
        """
        pts = as_points(points)
        if len(pts) < PROBE_CACHE_MIN:
            return self._probe_matrix(pts)
        key = hashlib.blake2b(np.ascontiguousarray(pts).tobytes(), digest_size=16).digest()
        hit = self._probe_cache.get(key)
        if hit is None:
            hit = self._probe_cache[key] = self._probe_matrix(pts)
            while len(self._probe_cache) > PROBE_CACHE_SIZE:
                self._probe_cache.popitem(last=False)
        else:
            self._probe_cache.move_to_end(key)
        return hit

    def _probe_matrix(self, pts: np.ndarray, cells: np.ndarray | None = None
                      ) -> tuple[sp.csr_matrix, np.ndarray]:
        """:meth:`probe_matrix` of checked points `pts` (n, 2), with their `cells` when
        they were located already."""
        cells, inside = self._probe_cells(pts, cells)
        idx = np.flatnonzero(inside)
        n = len(pts)
        if idx.size == 0:
            return sp.csr_matrix((n, self.basis.N)), inside
        x = pts[idx].T
        c = cells[idx]
        loc = inverse_map(self.basis.mapping, x[:, :, None], c)
        phis = basis_values(self.basis, loc, c)  # (Nbfun, n, 1)
        rows = np.tile(idx, self.basis.Nbfun)
        cols = self.basis.element_dofs[:, c].ravel()
        m = sp.coo_matrix((phis.ravel(), (rows, cols)), shape=(n, self.basis.N)).tocsr()
        return m, inside

    def _probe_cells(self, pts: np.ndarray, cells: np.ndarray | None = None
                     ) -> tuple[np.ndarray, np.ndarray]:
        """The cell of each of the checked points `pts` (n, 2), cm, whose basis values a probe
        takes, and whether it has one: its triangle (`cells` when located already), and on
        a curved boundary, a point between a chord and its arc the nearest cell's."""
        cells = self.locator.locate(pts) if cells is None else cells.copy()
        inside = cells >= 0
        if self.order == 2 and self.arena.circle is not None and not inside.all():
            near = self._centroids.query(pts[~inside])[1]
            within = self.arena.contains(pts[~inside])
            cells[np.flatnonzero(~inside)[within]] = near[within]
            inside = cells >= 0
        return cells, inside

    def grid_probe(self, spacing: float):
        """Cached raster probe: ``(x, y, matrix, inside)`` for a grid of `spacing` cm."""
        if spacing <= 0 or not np.isfinite(spacing):
            raise ReciprocityError(f"grid spacing must be a positive length in cm; got {spacing!r}")
        if spacing not in self._grid_cache:
            (x0, x1), (y0, y1) = self.arena.bounds
            x = np.arange(x0 + spacing / 2, x1, spacing)
            y = np.arange(y0 + spacing / 2, y1, spacing)
            xx, yy = np.meshgrid(x, y)
            m, inside = self.probe_matrix(np.column_stack([xx.ravel(), yy.ravel()]))
            self._grid_cache[spacing] = (x, y, m, inside)
        return self._grid_cache[spacing]

    # ------------------------------------------------------------------ solves
    def _check_in_free(self, pts: np.ndarray, what: str, cells: np.ndarray) -> None:
        """Refuse a point of `pts` whose cell (of `cells`, as located) is outside."""
        bad = cells < 0
        if bad.any():
            p = pts[np.argmax(bad)]
            raise ReciprocityError(
                f"{what} ({p[0]:.4g}, {p[1]:.4g}) cm is outside the meshed free region of "
                f"arena {self.arena.name!r}; choose a point in the free region")

    def point_sources(self, points, weights=None) -> np.ndarray:
        """Load vector(s) of point sources: column j is ``sum_k w_k φ_i(z_k)`` ...

        Parameters
        ----------
        points : array_like, shape (n, 2)
            Source locations, cm.
        weights : array_like, shape (n,), optional
            Strengths (default 1). The result sums all sources into one vector.
        """
        pts = as_points(points, "source points")
        cells = self.locator.locate(pts)      # once, for the check and the load vector
        self._check_in_free(pts, "source point", cells)
        w = np.ones(len(pts)) if weights is None else np.asarray(weights, dtype=float)
        m, _ = self._probe_matrix(pts, cells)
        return m.T @ w

    def solve(self, rhs: np.ndarray, dirichlet: Callable | None = None,
              flux: Callable | None = None) -> np.ndarray:
        """Solve ``-Δw = f`` for one or several load vectors by back-substitution.

        Parameters
        ----------
        rhs : ndarray, shape (n_dofs,) or (n_dofs, k)
            Load vector(s), e.g. from :meth:`point_sources`.
        dirichlet : callable, optional
            ``g(x, y)`` giving the wall values (default 0) on the Dirichlet walls.
        flux : callable, optional
            ``q(x, y) -> (qx, qy)``: with ``walls="neumann"``, the obstacle walls get
            ``∂w/∂n = q · n`` (n the outward normal of the free region); default 0.

        Returns
        -------
        ndarray, same shape as `rhs`
            Dof values.
        """
        b = np.array(rhs, dtype=float)
        if b.shape[0] != self.basis.N:
            raise ReciprocityError(f"rhs must have {self.basis.N} rows; got {b.shape}")
        w = np.zeros_like(b)
        if dirichlet is not None:
            xd = self.basis.doflocs[:, self._dirichlet]
            g = np.asarray(dirichlet(xd[0], xd[1]), dtype=float)
            w[self._dirichlet] = g if b.ndim == 1 else g[:, None]
        if flux is not None and self.walls == "neumann" and self.obstacle_facets.size:
            import skfem
            fb = skfem.FacetBasis(self.mesh, self.basis.elem, facets=self.obstacle_facets)

            @skfem.LinearForm
            def neumann(v, p):
                qx, qy = flux(p.x[0], p.x[1])
                return (qx * p.n[0] + qy * p.n[1]) * v

            nb = neumann.assemble(fb)
            b = b + (nb if b.ndim == 1 else nb[:, None])
        self.factorize()
        rhs_i = b[self._free] - self._a_id @ w[self._dirichlet]
        w[self._free] = self._lu.solve(rhs_i)
        return w

    def green(self, z, *, cached: bool = False) -> Field:
        """Green's function ``G(·, z)``: the adjoint solve ``-Δv = δ(· - z)`` (eq. 3).

        Parameters
        ----------
        z : array_like, shape (2,)
            Observation point in the free region, cm.
        cached : bool
            Keep the result on disk (under :func:`~reciprocity.fem.disk_cache.cache_dir`, by this
            solver's mesh, elements, walls and `z`, at most GREEN_CACHE_SIZE of them) and
            read it from there when present: the very numbers of the solve, without
            assembling or factorizing. For fields solved again in every process, such as
            a world's true signal.
        """
        z = as_points(z, "observation point")[0]
        name = f"G(., ({z[0]:.4g}, {z[1]:.4g}))"
        key = self._green_key(z) if cached else None
        if key is not None:
            data = read_cached("greens", key, ("dofs",), lambda arrays: self._check_green(arrays["dofs"], z))
            if data is not None:
                return Field(self, data["dofs"], name)
        dofs = self.solve(self.point_sources(z))
        if key is not None:
            write_cached("greens", key, keep=GREEN_CACHE_SIZE, dofs=dofs)
        return Field(self, dofs, name)

    def _green_key(self, z: np.ndarray) -> str:
        """Everything ``G(·, z)`` is computed from: the key of its disk-cache entry."""
        import scipy
        import skfem
        # the libraries' versions: an upgrade must not leave results depending on a warm cache
        mesh = hashlib.sha256()
        for a in (self._mesh1.p, self._mesh1.t):
            mesh.update(np.ascontiguousarray(a).tobytes())
        return (f"green|{GREEN_FORMAT}|scipy {scipy.__version__}|skfem {skfem.__version__}|P{self.order}|"
                f"{self.walls}|{self.arena.circle!r}|mesh {mesh.hexdigest()}|z {float(z[0])!r},{float(z[1])!r}")

    def _check_green(self, dofs: np.ndarray, z: np.ndarray) -> None:
        """A cached ``G(·, z)`` must be N finite float64 dof values of this solver, not
        negative beyond round-off (the maximum principle), and largest near `z`."""
        if dofs.dtype != np.float64 or dofs.shape != (self.basis.N,) or not np.isfinite(dofs).all():
            raise ValueError(f"dofs of {dofs.dtype} {dofs.shape}, not {self.basis.N} finite float64 values")
        top = float(dofs.max())
        if top <= 0 or dofs.min() < -1e-8 * top:
            raise ValueError("not a Green's function: not positive")
        peak = self.basis.doflocs[:, int(np.argmax(dofs))]
        if np.hypot(*(peak - z)) > 3.0 * self.h:
            raise ValueError(f"not G(., z): its peak is {np.hypot(*(peak - z)):.3g} cm from z")

    def greens(self, points) -> np.ndarray:
        """Dof values of ``G(·, z_k)`` for many points at once, shape (n_dofs, n)."""
        pts = as_points(points, "observation points")
        cells = self.locator.locate(pts)      # once, for the check and the load vectors
        self._check_in_free(pts, "observation point", cells)
        m, _ = self._probe_matrix(pts, cells)
        return self.solve(m.T.toarray())

    def field(self, source=None, strength: float | None = None, *, cached: bool = False) -> Field:
        """Forward signal ``u = c G(·, S)`` of eq. (1).

        Parameters
        ----------
        source : array_like, shape (2,), optional
            Source position, cm (default: the arena's true source).
        strength : float, optional
            ``c`` (default: the arena's strength).
        cached : bool
            Read ``G(·, S)`` from the disk cache, or keep it there (see :meth:`green`).
        """
        if source is None:
            if self.arena.source is None:
                raise ReciprocityError(f"arena {self.arena.name!r} has no true source; pass "
                                       "source=(x, y)")
            source = self.arena.source
        c = self.arena.strength if strength is None else float(strength)
        if not np.isfinite(c) or c <= 0:
            raise ReciprocityError(f"strength must be a positive number; got {strength!r}")
        g = self.green(source, cached=cached)
        return Field(self, c * g.dofs, "u")

    # ------------------------------------------------------------------ export
    def save_vtk(self, path, **fields: Field) -> None:
        """Write the mesh and `fields` (name=Field) to a VTK file for ParaView (meshio)."""
        import meshio
        pts = np.column_stack([self.nodes, np.zeros(len(self.nodes))])
        data = {}
        for name, f in fields.items():
            vals = f.dofs if isinstance(f, Field) else np.asarray(f, dtype=float)
            if vals.shape != (len(self.nodes),):
                raise ReciprocityError(f"field {name!r} has shape {vals.shape}, expected "
                                       f"({len(self.nodes)},) values at the solver's nodes")
            data[name] = vals
        meshio.write(str(path), meshio.Mesh(pts, [("triangle", self.triangles)], point_data=data))

    def __repr__(self) -> str:
        return (f"GreenSolver(arena={self.arena.name!r}, h={self.h}, order={self.order}, "
                f"walls={self.walls!r}, unknowns={self.n_unknowns})")


def boundary_nodes(t: np.ndarray, n_nodes: int) -> np.ndarray:
    """The nodes on the boundary of the triangle mesh `t` (3, m): those of the edges that
    only one triangle has, sorted, as ``int32`` (as scikit-fem's ``get_dofs`` gives the
    P1 dofs of the boundary facets)."""
    edges = np.sort(np.hstack([t[[0, 1]], t[[1, 2]], t[[0, 2]]]), axis=0).astype(np.int64)
    keys, counts = np.unique(edges[0] * n_nodes + edges[1], return_counts=True)
    once = keys[counts == 1]
    return np.unique(np.concatenate([once // n_nodes, once % n_nodes])).astype(np.int32)
