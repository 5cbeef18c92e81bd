"""How far a solver's Green's functions are from the exact ones, estimated from the solver
alone: the model-error term of a likelihood that knows its errors (issue 33).

The estimate never looks at a truth. It solves the same point sources on the solver's mesh
(size ``h``) and on a mesh twice as coarse (``2 h``), and reads the error of the fine
solution by Richardson's argument: with a pointwise error ``C h^p`` the difference of the
two is ``C h^p (2^p - 1)``, so the fine solution's error is the difference over
``2^p - 1`` (``p = 2`` for P1 away from the source). What a likelihood needs is the
*relative* error of a predicted reading ``c G(x, z)`` at the distances readings are taken:
the returned :class:`DiscretisationError` holds its quantile over sample pairs, and its
profile over distance. The coarse field is compared at the fine nodes, between its own
nodes, where it is further off than at them: the estimate is an upper one (on the disk, where
the exact Green's function is known, 2.6 to 3.6 times the true error at h = 1, 2 and 4 cm;
``tests/reciprocity/test_discretisation.py``).
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass

import numpy as np

from ..errors import ReciprocityError
from .disk_cache import read_cached, write_cached
from .green import GreenSolver
from .mesh import mesh_key

__all__ = ["DiscretisationError", "discretisation_error", "ORDER", "SAMPLE_SOURCES", "QUANTILE", "NEAR_CELLS"]

#: Convergence order assumed by the Richardson estimate (P1 away from the source).
ORDER = 2
#: Point sources solved on both meshes.
SAMPLE_SOURCES = 8
#: Quantile of the relative error over the sample pairs reported as the model error.
QUANTILE = 0.9
#: Pairs closer than this many coarse cells (``2 h``) are left out: there the coarse mesh
#: does not resolve the source and the estimate is meaningless (a reading that close to
#: the source is also rare).
NEAR_CELLS = 3.0
#: Pairs whose fine field is below this share of the sample source's largest are left out
#: (far readings are noise, whatever their relative error).
FLOOR_SHARE = 1e-3
#: Grading of the coarse mesh (that of a P1 solver's by default).
COARSE_GRADING = 0.5
#: Format of the estimates kept on disk (the key of each also holds everything it is made from).
CACHE_FORMAT = 1
#: Estimates kept in the disk cache (the most recently used).
CACHE_KEEP = 64


@dataclass(frozen=True)
class DiscretisationError:
    """Relative error of a solver's Green's functions, estimated by mesh halving.

    Attributes
    ----------
    relative : float
        The QUANTILE of ``|G_h - G_exact| / G_h`` over the sample pairs (a fraction).
    distances : ndarray
        Distance bins' upper edges, cm.
    profile : ndarray
        The same quantile within each distance bin (NaN where a bin is empty).
    h : float
        The solver's mesh size, cm.
    pairs : int
        Sample (source, node) pairs behind the estimate.
    """

    relative: float
    distances: np.ndarray
    profile: np.ndarray
    h: float
    pairs: int


def _sample_sources(pts: np.ndarray, mesh, in_coarse: np.ndarray, coarse_h: float, k: int) -> np.ndarray:
    """`k` of the fine solver's nodes `pts` (on its P1 `mesh`) spread over the free region
    (farthest-point order from the node nearest the centroid), each inside the coarse mesh
    (`in_coarse`) and at least two coarse cells (`coarse_h`, cm) from its walls:
    deterministic, so one geometry always gives one estimate."""
    from scipy.spatial import cKDTree
    boundary = mesh.p.T[np.unique(mesh.facets[:, mesh.boundary_facets()])]
    ok = in_coarse & (cKDTree(boundary).query(pts)[0] >= 2.0 * coarse_h)
    idx = np.flatnonzero(ok)
    if idx.size == 0:
        return np.empty((0, 2))
    cand = pts[idx]
    first = int(np.argmin(np.hypot(*(cand - cand.mean(axis=0)).T)))
    chosen = [first]
    dist = np.hypot(*(cand - cand[first]).T)
    for _ in range(min(k, len(cand)) - 1):
        nxt = int(np.argmax(dist))
        chosen.append(nxt)
        dist = np.minimum(dist, np.hypot(*(cand - cand[nxt]).T))
    return cand[chosen]


def discretisation_error(solver: GreenSolver, *, sources: int = SAMPLE_SOURCES,
                         bins: np.ndarray | None = None) -> DiscretisationError:
    """Estimate the relative error of `solver`'s Green's functions from the solver alone.

    Parameters
    ----------
    solver : GreenSolver
        A P1 solver (the model a strategy images with).
    sources : int
        Sample point sources.
    bins : ndarray, optional
        Distance bin edges (cm) of the profile; default 0, 5, 10, 20, 40, 80, inf.

    Returns
    -------
    DiscretisationError

    Raises
    ------
    ReciprocityError
        When the solver is not P1 or no sample source fits inside the coarse mesh.

    Notes
    -----
    The coarse solver is built on the same arena at ``2 h`` (its mesh from the disk cache of
    meshes); both are solved for the same sources in one multi-column back-substitution
    each. The result is kept on the solver, so a second call costs nothing, and in the disk
    cache (:mod:`reciprocity.fem.disk_cache`) under a key holding everything it is made from:
    the solver's mesh (a digest of its points and triangles), ``h`` and walls, the coarse
    mesh's key, the settings of the estimate, and the versions of scikit-fem, SciPy and
    NumPy. An entry is used only when it passes that cache's checks and these: the bins
    of `bins`, a finite non-negative quantile, a profile of one value per bin, ``h`` and
    a positive pair count; the same numbers, to the bit, as computing it again.
    """
    if solver.order != 1:
        raise ReciprocityError("discretisation_error needs a P1 solver (order=1)")
    edges = np.array([0.0, 5.0, 10.0, 20.0, 40.0, 80.0, np.inf]) if bins is None else np.asarray(bins, float)
    key = (int(sources), tuple(edges.tolist()))
    kept = getattr(solver, "_discretisation", None)
    if kept is not None and kept[0] == key:
        return kept[1]
    disk_key = _disk_key(solver, int(sources), edges)
    stored = read_cached("discretisation", disk_key, _FIELDS, lambda arrays: _check_entry(arrays, solver.h, edges))
    if stored is not None:
        out = DiscretisationError(float(stored["relative"][0]), np.array(stored["distances"], dtype=float),
                                  np.array(stored["profile"], dtype=float), float(stored["h"][0]),
                                  int(stored["pairs"][0]))
        solver._discretisation = (key, out)
        return out
    out = _estimate(solver, int(sources), edges)
    write_cached("discretisation", disk_key, keep=CACHE_KEEP, relative=np.array([out.relative]),
                 distances=out.distances, profile=out.profile, h=np.array([out.h]),
                 pairs=np.array([out.pairs], dtype=np.int64))
    solver._discretisation = (key, out)
    return out


#: The arrays of an estimate kept on disk.
_FIELDS = ("relative", "distances", "profile", "h", "pairs")


def _disk_key(solver: GreenSolver, sources: int, edges: np.ndarray) -> str:
    """Everything an estimate is made from, as its disk-cache key."""
    import scipy
    import skfem
    m = solver._mesh1
    digest = hashlib.sha256()
    for a in (m.p, m.t):
        digest.update(str((a.dtype.str, a.shape)).encode())
        digest.update(np.ascontiguousarray(a).tobytes())
    return (f"discretisation|{CACHE_FORMAT}|order {ORDER}|sources {sources}|edges {edges.tolist()!r}|"
            f"quantile {QUANTILE!r}|near {NEAR_CELLS!r}|floor {FLOOR_SHARE!r}|h {solver.h!r}|"
            f"walls {solver.walls}|mesh {digest.hexdigest()}|"
            f"coarse {mesh_key(solver.arena, 2.0 * solver.h, COARSE_GRADING)}|"
            f"skfem {skfem.__version__}|scipy {scipy.__version__}|numpy {np.__version__}")


def _check_entry(arrays: dict, h: float, edges: np.ndarray) -> None:
    """An estimate read from disk must be one of `h` with a profile over `edges`."""
    rel, dist, prof = arrays["relative"], arrays["distances"], arrays["profile"]
    if rel.shape != (1,) or rel.dtype != np.float64 or not (np.isfinite(rel[0]) and rel[0] >= 0):
        raise ValueError(f"relative error {rel!r} is not one finite fraction >= 0")
    if dist.dtype != np.float64 or not np.array_equal(dist, edges[1:]):
        raise ValueError("distance bins differ from the requested ones")
    if prof.dtype != np.float64 or prof.shape != dist.shape or (prof[~np.isnan(prof)] < 0).any():
        raise ValueError("profile is not one fraction >= 0 (or NaN) per bin")
    if arrays["h"].shape != (1,) or arrays["h"].dtype != np.float64 or float(arrays["h"][0]) != h:
        raise ValueError(f"mesh size {arrays['h']!r}, not {h!r}")
    pairs = arrays["pairs"]
    if pairs.shape != (1,) or pairs.dtype.kind not in "iu" or int(pairs[0]) < 1:
        raise ValueError(f"pair count {pairs!r} is not one positive whole number")


def _estimate(solver: GreenSolver, sources: int, edges: np.ndarray) -> DiscretisationError:
    """The estimate itself (:func:`discretisation_error`, computed)."""
    coarse = GreenSolver(solver.arena, h=2.0 * solver.h, order=1, walls=solver.walls, grading=COARSE_GRADING)
    nodes = solver.nodes
    # the fine nodes located in the coarse mesh once: where sample sources may lie, and
    # where the coarse fields are compared
    probe, inside = coarse.probe_matrix(nodes)
    src = _sample_sources(nodes, solver._mesh1, inside, coarse.h, int(sources))
    if len(src) == 0:
        raise ReciprocityError("no sample source fits inside the coarse mesh: the arena is too small "
                               f"for h = {solver.h:g} cm")
    fine = solver.greens(src)                                       # (n_dofs, k)
    rough = coarse.greens(src)
    rough_at = probe @ rough
    rel, dist = [], []
    for j, s in enumerate(src):
        r = np.hypot(*(nodes - s).T)
        g = fine[:nodes.shape[0], j]
        use = (r >= NEAR_CELLS * coarse.h) & (g > FLOOR_SHARE * g.max()) & inside
        err = np.abs(rough_at[use, j] - g[use]) / (2.0 ** ORDER - 1.0)
        rel.append(err / g[use])
        dist.append(r[use])
    rel, dist = np.concatenate(rel), np.concatenate(dist)
    if rel.size == 0:
        raise ReciprocityError("no sample pair for the discretisation estimate")
    which = np.digitize(dist, edges[1:-1])
    profile = np.array([np.quantile(rel[which == b], QUANTILE) if np.any(which == b) else np.nan
                        for b in range(len(edges) - 1)])
    return DiscretisationError(float(np.quantile(rel, QUANTILE)), edges[1:].copy(), profile,
                               float(solver.h), int(rel.size))
