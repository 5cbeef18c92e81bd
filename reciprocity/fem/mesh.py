"""Triangular meshes of an arena's free region, graded toward re-entrant corners.

The free region ``D \\ Omega`` is meshed with Shewchuk's Triangle (quality Delaunay,
minimum angle 30 degrees). Near a re-entrant corner of interior angle ``omega > pi``
the Green's function behaves like ``r**(pi/omega)``; a uniform mesh then loses the
optimal order, so the local mesh size is graded as ``h(r) = h * (r/R)**gamma`` within
``R`` of each such corner (Apel, Sändig & Whiteman 1996; Babuška 1970).
"""

from __future__ import annotations

import hashlib
from typing import TYPE_CHECKING

import numpy as np

from arenas import Arena

from ..errors import MeshError
from .disk_cache import read_cached, write_cached

if TYPE_CHECKING:
    import skfem

# scikit-fem and Triangle are imported by the functions that mesh, so that the nodal
# helpers below and the modules importing this one load without them (issue 24).

__all__ = ["mesh_free_region", "cached_mesh", "reentrant_corners", "triangle_areas", "node_areas",
           "triangle_budget", "MAX_TRIANGLES"]

# Triangle's max-area bound giving a mean edge length close to h with 30-degree quality
# (measured: an area bound of sqrt(3)/4 h^2 yields a mean edge of 0.82 h)
_AREA_PER_H2 = 0.65
#: A mesh has at most this many times the triangles of a uniform mesh of size h over the
#: free area (plus MESH_TRIANGLES_SLACK): grading toward corners and small features may
#: add that much, never more. Triangle is told the bound (its ``S`` switch caps the points
#: it adds), so a geometry with hundreds of corners or sliver gaps, such as believed walls
#: traced from an occupancy grid, is meshed less finely near them instead of without end.
MESH_TRIANGLES_FACTOR = 4.0
#: Triangles allowed beyond the factor (small arenas, many input vertices).
MESH_TRIANGLES_SLACK = 20_000
#: Most triangles of any mesh (about 1 GB for the solver of a P1 mesh this size).
MAX_TRIANGLES = 2_000_000


#: Spikes of the free region narrower than this (cm) are removed when Triangle fails on
#: the exact geometry (:func:`_without_spikes`).
SPIKE_CM = 1e-6


def _without_spikes(free):
    """`free` opened by SPIKE_CM (mitred corners, so nothing else moves): a believed wall
    laid along the boundary can leave a spike of free space 1e-15 cm wide, on which
    Triangle runs out of precision (``Triangulation failed``)."""
    out = free.buffer(-SPIKE_CM, join_style="mitre").buffer(SPIKE_CM, join_style="mitre")
    return max(getattr(out, "geoms", [out]), key=lambda g: g.area)


def _rings(arena: Arena, h: float, free=None) -> list[np.ndarray]:
    """Boundary rings of the free region (or of `free`): [exterior, *holes], each (n, 2),
    not closed."""
    free = arena.free_region if free is None else free
    rings = [np.asarray(free.exterior.coords)[:-1]]
    rings += [np.asarray(r.coords)[:-1] for r in free.interiors]
    if arena.circle is not None and not arena.obstacles:
        cx, cy, r = arena.circle
        n = max(16, int(np.ceil(2 * np.pi * r / h)))
        a = np.linspace(0, 2 * np.pi, n, endpoint=False)
        rings[0] = np.column_stack([cx + r * np.cos(a), cy + r * np.sin(a)])
    return rings


def triangle_areas(points: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """Areas of `triangles` (m, 3) over `points` (n, 2), shape (m,)."""
    p = points[triangles]
    e1, e2 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    return 0.5 * np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])


def node_areas(points: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """Lumped area of each node (a third of each adjacent triangle), shape (n,)."""
    a = np.repeat(triangle_areas(points, triangles) / 3, 3)
    return np.bincount(triangles.ravel(), a, len(points))


def reentrant_corners(arena: Arena) -> np.ndarray:
    """Vertices (cm) of the free region whose interior angle exceeds pi, shape (n, 2)."""
    free = arena.free_region
    out = []
    # the exterior is counter-clockwise and holes clockwise after shapely's orient()
    from shapely.geometry.polygon import orient
    free = orient(free, sign=1.0)
    for ring in [free.exterior, *free.interiors]:
        v = np.asarray(ring.coords)[:-1]
        if arena.circle is not None and ring is free.exterior:
            continue
        e_in = v - np.roll(v, 1, axis=0)
        e_out = np.roll(v, -1, axis=0) - v
        cross = e_in[:, 0] * e_out[:, 1] - e_in[:, 1] * e_out[:, 0]
        # with the free region on the left of each ring, a right turn is re-entrant
        out.append(v[cross < -1e-12])
    return np.vstack(out) if out else np.empty((0, 2))


def _segments(rings: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    verts, segs, offset = [], [], 0
    for r in rings:
        n = len(r)
        verts.append(r)
        idx = offset + np.arange(n)
        segs.append(np.column_stack([idx, np.roll(idx, -1)]))
        offset += n
    return np.vstack(verts), np.vstack(segs)


def triangle_budget(arena: Arena, h: float) -> int:
    """Most triangles a mesh of `arena` at size `h` (cm) may have: MESH_TRIANGLES_FACTOR
    times a uniform mesh's over the free area, plus MESH_TRIANGLES_SLACK and twice the
    input vertices, at most MAX_TRIANGLES."""
    n_vertices = len(arena.boundary) + sum(len(o) for o in arena.obstacles)
    uniform = arena.area / (_AREA_PER_H2 * h * h)
    return int(min(MESH_TRIANGLES_FACTOR * uniform + MESH_TRIANGLES_SLACK + 2 * n_vertices, MAX_TRIANGLES))


def _area_switch(area: float) -> str:
    """`area` as Triangle's ``a`` switch reads it: ten significant digits, never in exponent
    form (Triangle reads ``a2.54e-05`` as ``a2.54`` and meshes far coarser, silently)."""
    text = f"{area:.10g}"
    if "e" in text:
        text = np.format_float_positional(area, precision=10, unique=False, fractional=False, trim="-")
    return text


def _triangulate(pslg: dict, switches: str, budget: int) -> dict:
    """Triangle with at most `budget` triangles (its ``S`` switch bounds the added points;
    a triangulation has fewer than twice its points), its failures as MeshError."""
    import triangle
    n_in = len(pslg["vertices"])
    steiner = max(budget // 2 - n_in, 0)
    try:
        out = triangle.triangulate(pslg, f"{switches}S{steiner}")
    except (RuntimeError, ValueError, MemoryError) as exc:
        raise MeshError(f"Triangle could not mesh the free region ({exc}); the geometry has "
                        f"{n_in} vertices") from None
    if "triangles" not in out or len(out["triangles"]) == 0:
        raise MeshError("Triangle produced no elements; check the arena geometry")
    return out


def _pslg(arena: Arena, h: float, free) -> dict:
    """Triangle's input for the free region `free`: vertices, segments and hole points."""
    rings = _rings(arena, h, free)
    verts, segs = _segments(rings)
    pslg = {"vertices": verts, "segments": segs}
    if len(rings) > 1:
        from shapely.geometry import Polygon
        pslg["holes"] = np.array([Polygon(r).representative_point().coords[0] for r in free.interiors])
    return pslg


def mesh_free_region(arena: Arena, h: float, *, grading: float | None = 0.5,
                     grading_radius: float | None = None, h_min: float | None = None,
                     max_passes: int = 6) -> skfem.MeshTri:
    """Mesh the free region of `arena` with triangles of size about `h` (cm).

    Parameters
    ----------
    arena : Arena
        The arena; its obstacles become holes.
    h : float
        Target edge length away from corners, cm.
    grading : float or None
        Exponent ``gamma`` in ``h(r) = h (r/R)**gamma`` near re-entrant corners
        (``None`` or 0 for a quasi-uniform mesh). For a 270-degree corner, P1 keeps its
        optimal order for ``gamma > 1/3``; P2 needs ``gamma > 2/3``.
    grading_radius : float, optional
        ``R``, cm; default ``8 h``.
    h_min : float, optional
        Smallest edge length, cm; default ``h / 25``.
    max_passes : int
        Refinement passes of Triangle toward the graded size field.

    Returns
    -------
    skfem.MeshTri
        Nodes in cm; at most :func:`triangle_budget` triangles (grading stops, and
        Triangle adds no more points, at the budget).

    Raises
    ------
    MeshError
        A mesh size out of range, a uniform mesh over the budget, or a geometry Triangle
        cannot mesh.
    """
    import skfem
    from scipy.spatial import cKDTree
    if not np.isfinite(h) or h <= 0:
        raise MeshError(f"mesh size h must be a positive length in cm; got {h!r}")
    (x0, x1), (y0, y1) = arena.bounds
    size = min(x1 - x0, y1 - y0)
    if h > size / 4:
        raise MeshError(f"mesh size h={h} cm is too coarse for an arena {size:.3g} cm across; "
                        f"use h <= {size / 4:.3g}")
    n_est = arena.area / (_AREA_PER_H2 * h * h)
    if n_est > MAX_TRIANGLES / MESH_TRIANGLES_FACTOR:
        least = (arena.area * MESH_TRIANGLES_FACTOR / (_AREA_PER_H2 * MAX_TRIANGLES)) ** 0.5
        raise MeshError(f"h={h} cm would need about {n_est:.2g} triangles; use h >= {least:.3g} cm")
    budget = triangle_budget(arena, h)
    switches = f"pq30a{_area_switch(_AREA_PER_H2 * h * h)}"
    try:
        mesh = _triangulate(_pslg(arena, h, arena.free_region), switches, budget)
        _refuse_degenerate(mesh, h)
    except MeshError:
        mesh = _triangulate(_pslg(arena, h, _without_spikes(arena.free_region)), switches, budget)
        _refuse_degenerate(mesh, h)
    corners = reentrant_corners(arena)
    if grading and len(corners):
        radius = grading_radius or 8.0 * h
        hmin = h_min or h / 25.0
        tree = cKDTree(corners)
        for _ in range(max_passes):
            p, t = mesh["vertices"], mesh["triangles"]
            r = tree.query(p[t].mean(axis=1))[0]
            target = h * np.clip((r / radius) ** grading, hmin / h, 1.0)
            area = _AREA_PER_H2 * target**2
            now = triangle_areas(p, t)
            if np.all(now <= 1.5 * area):
                break
            # the pass would make about sum(now / area) triangles: stop grading at the budget
            if np.sum(np.maximum(now / area, 1.0)) > budget:
                break
            mesh["triangle_max_area"] = area
            try:
                graded = _triangulate(mesh, "rpq30a", budget)
                _refuse_degenerate(graded, h)
            except MeshError:
                break                   # the mesh of the last pass, less graded
            mesh = graded
    p, t = mesh["vertices"], mesh["triangles"]
    return skfem.MeshTri(np.ascontiguousarray(p.T), np.ascontiguousarray(t.T))


#: Smallest triangle area kept, as a share of ``h^2``: below it a triangle is degenerate
#: (a sliver of a spike in a believed map: its Jacobian divides by zero).
MIN_TRIANGLE_SHARE = 1e-9


def _refuse_degenerate(mesh: dict, h: float) -> None:
    """Raise MeshError when `mesh` (Triangle's output) holds a triangle of (nearly) zero area."""
    area = triangle_areas(mesh["vertices"], mesh["triangles"])
    if area.size and float(area.min()) <= MIN_TRIANGLE_SHARE * h * h:
        raise MeshError(f"the mesh has {int(np.sum(area <= MIN_TRIANGLE_SHARE * h * h))} degenerate "
                        "triangle(s) (zero area): the free region has a sliver Triangle cannot resolve")


#: Bumped whenever :func:`mesh_free_region` would produce a different mesh.
MESH_FORMAT = 1


def cached_mesh(arena: Arena, h: float, *, grading: float | None = 0.5) -> skfem.MeshTri:
    """:func:`mesh_free_region`, kept on disk by the arena's geometry, `h` and `grading`.

    Triangle is deterministic, so a cached mesh is the mesh that would be made; it saves
    the meshing at start-up. A cache that cannot be read or written
    is passed over silently (the mesh is then made as usual).
    """
    import skfem
    key = mesh_key(arena, h, grading)
    data = read_cached("meshes", key, ("p", "t"), lambda arrays: _check_mesh_arrays(arena, arrays))
    if data is not None:
        return skfem.MeshTri(np.ascontiguousarray(data["p"]), np.ascontiguousarray(data["t"]))
    mesh = mesh_free_region(arena, h, grading=grading)
    write_cached("meshes", key, p=mesh.p, t=mesh.t)
    return mesh


def mesh_key(arena: Arena, h: float, grading: float | None) -> str:
    """The disk-cache key of :func:`cached_mesh`'s mesh: everything it is made from (the
    arena's rings and circle, `h`, `grading`, the mesher's version and this format)."""
    import triangle
    rings = hashlib.sha256()
    for ring in (arena.boundary, *arena.obstacles):
        rings.update(np.ascontiguousarray(ring, dtype=float).tobytes())
        rings.update(b"|")
    version = getattr(triangle, "__version__", "")
    return (f"mesh|{MESH_FORMAT}|triangle {version}|h {float(h)!r}|grading {grading!r}|{arena.circle!r}|"
            f"rings {rings.hexdigest()}")


def _check_mesh_arrays(arena: Arena, arrays: dict) -> None:
    """A cached mesh must be finite float64 points inside the arena's bounding box and
    int triangles of positive area indexing them."""
    p, t = arrays["p"], arrays["t"]
    if p.dtype != np.float64 or p.ndim != 2 or p.shape[0] != 2 or p.shape[1] < 3 or not np.isfinite(p).all():
        raise ValueError(f"points of {p.dtype} {p.shape}, not (2, n) finite float64")
    if t.dtype.kind not in "iu" or t.ndim != 2 or t.shape[0] != 3 or t.shape[1] < 1:
        raise ValueError(f"triangles of {t.dtype} {t.shape}, not (3, m) integers")
    if t.min() < 0 or t.max() >= p.shape[1]:
        raise ValueError("triangles index points that do not exist")
    lo, hi = arena.boundary.min(axis=0), arena.boundary.max(axis=0)
    tol = 1e-6 * float(np.max(hi - lo))
    if (p.min(axis=1) < lo - tol).any() or (p.max(axis=1) > hi + tol).any():
        raise ValueError("points outside the arena")
    if (triangle_areas(p.T, t.T) <= 0).any():
        raise ValueError("triangles of zero area")
