"""Which possible sources a reading taken where the observer can go would see.

A possible source ``x`` outside the reachable set ``R`` can still be found if a reading at
some point of ``R`` sees it: ``c G(y, x)`` well above the reading noise for some
``y`` in ``R``. For ``x`` outside ``R``, ``G(·, x)`` is harmonic in ``R`` and vanishes on the
walls, so by the maximum principle its largest value over ``R`` lies on the edge of ``R``
facing the rest of the free region: the test needs the adjoint fields of the edge's nodes
only, one back-substitution each (:func:`greatest_green`). A source behind a slit
narrower than the car, or in a room sealed off from ``R``, gives readings indistinguishable
from nothing anywhere the observer can go: it is out of reach, however close it lies.
"""

from __future__ import annotations

import hashlib
import threading
import weakref

import numpy as np

__all__ = ["edge_nodes", "thinned", "greatest_green", "DETECT_PROBES"]

#: Most edge nodes whose adjoint fields :func:`greatest_green` solves for (spread evenly
#: over the edge by thinning on a square lattice).
DETECT_PROBES = 200
#: Results of :func:`greatest_green` kept per solver (the episodes of a campaign on one
#: arena share their reachable part): one float per node each.
KEEP_PER_SOLVER = 8
_kept: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()
_lock = threading.Lock()
#: Columns solved at once (memory: nodes x this many doubles).
CHUNK = 64


def edge_nodes(edges: tuple[np.ndarray, np.ndarray], mask: np.ndarray) -> np.ndarray:
    """Indices of the nodes of `mask` joined by a mesh edge to a node outside it.

    Parameters
    ----------
    edges : tuple of ndarray
        The mesh's edges ``(i, j)``, node indices.
    mask : ndarray of bool, shape (n,)
        A set of nodes.

    Returns
    -------
    ndarray of int
        Sorted node indices.
    """
    i, j = edges
    cut = mask[i] != mask[j]
    ends = np.concatenate([i[cut], j[cut]])
    return np.unique(ends[mask[ends]])


def thinned(points: np.ndarray, idx: np.ndarray, most: int, cell: float) -> np.ndarray:
    """At most `most` of the nodes `idx`, one per cell of a square lattice whose side
    (cm, at least `cell`) grows by half until they fit.

    Parameters
    ----------
    points : ndarray, shape (n, 2)
        Node coordinates, cm.
    idx : ndarray of int
        The nodes to thin.
    most : int
        How many to keep at most (at least 1).
    cell : float
        Smallest lattice side, cm.
    """
    idx = np.asarray(idx, dtype=np.int64)
    side = float(cell)
    while True:
        keys = np.floor(points[idx] / side).astype(np.int64)
        _, first = np.unique(keys, axis=0, return_index=True)
        if len(first) <= max(1, int(most)):
            return idx[np.sort(first)]
        side *= 1.5


def greatest_green(solver, points: np.ndarray, edges, reachable: np.ndarray, reach: float, *,
                   most: int = DETECT_PROBES) -> np.ndarray:
    """``max_y G(y, x)`` over the edge of `reachable`, for every node ``x`` outside it
    within `reach` of it.

    Parameters
    ----------
    solver : reciprocity.fem.GreenSolver
        A P1 solver whose nodes are `points`.
    points : ndarray, shape (n, 2)
        The mesh's nodes, cm.
    edges : tuple of ndarray
        The mesh's edges ``(i, j)``.
    reachable : ndarray of bool, shape (n,)
        Where the observer can go.
    reach : float
        The nodes tested: those outside `reachable` within this distance (cm) of it.
    most : int
        Most edge nodes solved for (thinned evenly, :func:`thinned`).

    Returns
    -------
    ndarray, shape (n,)
        The largest adjoint value at each node tested (a unit source there, read on the
        edge of `reachable`); ``inf`` on `reachable`, 0 elsewhere. Thinning can only lower it.
        Kept per solver for the same arguments (read-only).
    """
    key = hashlib.sha1(np.packbits(reachable).tobytes() + np.float64(reach).tobytes()
                       + np.int64(most).tobytes()).hexdigest()
    with _lock:
        kept = _kept.setdefault(solver, {})
        if key in kept:
            kept[key] = kept.pop(key)                     # the most recently used last
            return kept[key]
    out = _greatest_green(solver, points, edges, reachable, float(reach), int(most))
    out.setflags(write=False)
    with _lock:
        kept[key] = out
        while len(kept) > KEEP_PER_SOLVER:
            kept.pop(next(iter(kept)))
    return out


def _greatest_green(solver, points, edges, reachable, reach, most) -> np.ndarray:
    out = np.zeros(len(points))
    out[reachable] = np.inf
    edge = edge_nodes(edges, reachable)
    if edge.size == 0 or reachable.all():
        return out
    from scipy.spatial import cKDTree
    outside = np.flatnonzero(~reachable)
    d, _ = cKDTree(points[edge]).query(points[outside], distance_upper_bound=reach)
    cand = outside[np.isfinite(d)]
    if cand.size == 0:
        return out
    probes = thinned(points, edge, most, solver.h)
    best = np.zeros(cand.size)
    for s in range(0, probes.size, CHUNK):
        g = solver.greens(points[probes[s:s + CHUNK]])
        np.maximum(best, g[cand].max(axis=1), out=best)
    out[cand] = best
    return out
