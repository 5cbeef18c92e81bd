"""Solve the simple-car Hamilton-Jacobi equation (eqs. (13)-(14), Landa et al.)."""

from __future__ import annotations

import os
import threading
import time
import warnings
from collections import OrderedDict
from dataclasses import dataclass, replace

import numpy as np

from . import _sweep
from ._grid import Grid, domain_geometry, lower_wall_distance, make_grid
from ._motion import arc_samples, arc_step, first_hits, sample_spacing
from ._search import exact_layer
from .errors import PlanningError
from .limits import check_grid, length
from .options import SolverOptions
from .value_function import ValueFunction

__all__ = ["solve", "SolverOptions"]


@dataclass(frozen=True)
class Workspace:
    """Everything about a solve that does not depend on the target (picklable; shared by a bank).

    Attributes
    ----------
    grid : Grid
        The (x, y, θ) grid.
    distance : numpy.ndarray
        Signed wall distance at the nodes (nx, ny), from the domain's geometry.
    free : numpy.ndarray
        Nodes in free space at least ``clearance`` from every wall (nx, ny).
    geometry : dict
        ``name``, ``boundary`` and ``obstacles`` of the domain.
    rho, clearance : float
        Turning radius and wall clearance (length unit).
    reverse : bool
        Reeds-Shepp car.
    options : SolverOptions
        Numerical parameters.
    ctrl : list of (int, int, float)
        The stencils' (direction, steering, arc length).
    stencils : dict
        Arrays of :func:`build_stencils`.
    """

    grid: Grid
    distance: np.ndarray
    free: np.ndarray
    geometry: dict
    rho: float
    clearance: float
    reverse: bool
    options: SolverOptions
    ctrl: list
    stencils: dict


def window(ws: Workspace, i0: int, i1: int, j0: int, j1: int) -> Workspace:
    """``ws`` restricted to the nodes ``[i0, i1) x [j0, j1)`` of its grid.

    A solve in the window finds the shortest paths that stay in it (the feet
    of their stencils do; an arc may bulge out between its ends, clear of the
    walls as in the whole grid): an upper bound of φ, equal to it wherever
    the optimal path keeps inside.  Its cost is that of the window's nodes.
    """
    g = ws.grid
    if not (0 <= i0 < i1 <= g.nx and 0 <= j0 < j1 <= g.ny and i1 - i0 >= 4 and j1 - j0 >= 4):
        raise PlanningError(f"window [{i0}, {i1}) x [{j0}, {j1}) is not within the {g.nx} x {g.ny} grid "
                            "(at least 4 x 4 nodes)")
    grid = Grid(g.x0 + i0 * g.h, g.y0 + j0 * g.h, g.h, i1 - i0, j1 - j0, g.ntheta)
    stencils = dict(ws.stencils, adm=np.ascontiguousarray(ws.stencils["adm"][:, i0:i1, j0:j1]))
    return replace(ws, grid=grid, distance=np.ascontiguousarray(ws.distance[i0:i1, j0:j1]),
                   free=np.ascontiguousarray(ws.free[i0:i1, j0:j1]), stencils=stencils)


def prepare(domain, rho: float, h: float, ntheta: int, *, clearance: float = 0.0, reverse: bool = False,
            options: SolverOptions | None = None, like: Workspace | None = None) -> Workspace:
    """The target-independent part of :func:`solve`: grid, free space and clear stencils (arguments as there).

    ``like``, optional, is a workspace of another domain (another map of the same arena,
    as a car mapping its walls makes them): when its grid, turning radius, clearance
    and stencils are this one's, the clear-arc bits of the nodes that no change
    of the wall distance or the free space can reach are taken from it (the same bits).
    """
    _validate_grid(rho, h, ntheta, clearance)
    options = options or SolverOptions()
    grid, distance, free = make_grid(domain, float(h), int(ntheta), float(clearance))
    ctrl = options.controls(float(rho), grid, reverse)
    base = None
    # the bits depend on the grid, the turning radius, the clearance and the stencils alone
    if like is not None and like.grid == grid and like.rho == float(rho) and like.clearance == float(clearance) \
            and like.ctrl == ctrl:
        base = (like.distance, like.free, like.stencils["adm"])
    stencils = build_stencils(float(rho), grid, ctrl, distance, free, float(clearance), mask_threads(options),
                              base=base)
    return Workspace(grid, distance, free, domain_geometry(domain), float(rho), float(clearance), bool(reverse),
                     options, ctrl, stencils)


def mask_threads(options: SolverOptions) -> int:
    """Threads that compute the clear-arc masks: ``options.threads`` when set, else one per
    core up to :data:`hjplanner._sweep.GROUPS` (each node's bits are its own, so the masks
    are the same bits for any number, and they scale where the coupled sweeps do not)."""
    if options.threads is not None:
        return max(1, int(options.threads))
    return max(1, min(_sweep.GROUPS, os.cpu_count() or 1))


#: Prepared workspaces kept per process by :func:`prepared` (one is a few MB: the clear-arc
#: bitmask is ``4 ntheta nx ny`` bytes).
PREPARED_KEEP = 4
_PREPARED: OrderedDict = OrderedDict()
_PREPARED_LOCK = threading.Lock()


def prepared(domain, rho: float, h: float, ntheta: int, *, clearance: float = 0.0, reverse: bool = False,
             options: SolverOptions | None = None) -> Workspace:
    """:func:`prepare`, memoised per process on the domain's walls and the arguments.

    The episodes of a campaign on one arena each build a planner for the same walls: they
    share one workspace (a workspace is never modified after it is prepared). The last
    :data:`PREPARED_KEEP` are kept, least recently used dropped first. A new one is
    prepared ``like`` the latest kept with the same settings (:func:`prepare`): a car that
    maps its walls prepares a workspace per map, each a little different from the last.
    """
    geometry = domain_geometry(domain)
    walls = (geometry["name"], geometry["boundary"].tobytes(), geometry["boundary"].shape,
             tuple((o.tobytes(), o.shape) for o in geometry["obstacles"]))
    knobs = None if options is None else tuple(sorted((k, repr(v)) for k, v in vars(options).items()))
    key = (walls, float(rho), float(h), int(ntheta), float(clearance), bool(reverse), knobs)
    with _PREPARED_LOCK:
        if key in _PREPARED:
            _PREPARED.move_to_end(key)
            return _PREPARED[key]
    with _PREPARED_LOCK:                             # the latest of the same settings, on other walls
        like = next((w for k, w in reversed(_PREPARED.items()) if k[1:] == key[1:]), None)
    ws = prepare(domain, rho, h, ntheta, clearance=clearance, reverse=reverse, options=options, like=like)
    with _PREPARED_LOCK:
        _PREPARED[key] = ws
        while len(_PREPARED) > PREPARED_KEEP:
            _PREPARED.popitem(last=False)
    return ws


def build_stencils(rho: float, grid: Grid, ctrl: list[tuple[int, int, float]], distance: np.ndarray,
                   free: np.ndarray, clearance: float, threads: int = 1, base: tuple | None = None) -> dict:
    """Per (layer, control): foot offsets, bilinear corner weights, landing layer, cost; clear-arc bitmasks.

    The foot of stencil c from node (i, j, θ_k) lies in the cell whose lower
    corner is ``(i + off_i, j + off_j)`` of layer ``kk``; its corners carry
    the weights ``w[..., 0:4]`` (order (0,0), (0,1), (1,0), (1,1)).  A weight
    on the node itself is moved to the left-hand side: ``inv_self = 1/(1 - w_self)``.
    ``adm`` (ntheta, nx, ny) is the bitmask of
    :func:`hjplanner._sweep.stencil_masks`: the arcs clear of the walls, at
    the samples also used by :func:`hjplanner._motion.arcs_are_clear`, computed
    by ``threads`` threads (the same bits for any number), from the bits of ``base``
    (``(distance, free, adm)`` of the same grid and stencils) where they cannot differ.
    """
    theta = grid.theta
    nt, nc = grid.ntheta, len(ctrl)
    v, u, s = (np.array(column, dtype=float) for column in zip(*ctrl))
    starts = np.column_stack([np.zeros(nt), np.zeros(nt), theta])
    ends = arc_step(starts[:, None, :], u[None, :], v[None, :], s[None, :], rho)  # (nt, nc, 3)
    gx, gy = ends[..., 0] / grid.h, ends[..., 1] / grid.h
    # Snap round-off so that exact grid landings keep a single stencil node.
    gx = np.where(np.abs(gx - np.round(gx)) < 1e-9, np.round(gx), gx)
    gy = np.where(np.abs(gy - np.round(gy)) < 1e-9, np.round(gy), gy)
    off_i, off_j = np.floor(gx).astype(np.int64), np.floor(gy).astype(np.int64)
    fx, fy = gx - off_i, gy - off_j
    w = np.stack([(1 - fx) * (1 - fy), (1 - fx) * fy, fx * (1 - fy), fx * fy], axis=-1)
    turns = np.rint(v * u * s / (rho * grid.dtheta)).astype(np.int64)  # heading change v u s/ρ (eq. (9))
    kk = (np.arange(nt)[:, None] + turns[None, :]) % nt
    cost = np.broadcast_to(s, (nt, nc)).copy()
    inv_self = np.ones((nt, nc))
    for k, c in zip(*np.nonzero(kk == np.arange(nt)[:, None])):
        for corner, (a, b) in enumerate(((0, 0), (0, 1), (1, 0), (1, 1))):
            if off_i[k, c] + a == 0 and off_j[k, c] + b == 0 and w[k, c, corner] > 0:
                if w[k, c, corner] > 1 - 1e-9:
                    raise PlanningError("straight steps must be longer than the grid spacing h")
                inv_self[k, c] = 1.0 / (1.0 - w[k, c, corner])
                w[k, c, corner] = 0.0
    pad = int(max(np.abs(off_i).max(), np.abs(off_j).max())) + 2
    ci, cj, corner_dist, margin = arc_sample_cells(rho, grid, ctrl, clearance)
    adm = _sweep.stencil_masks(distance, free, float(clearance), ci, cj, corner_dist, margin, s, threads, base)
    # Visit each layer against its forward straight motion (see _sweep).
    rev_i = np.cos(theta) >= 0
    rev_j = np.sin(theta) >= 0
    return dict(off_i=off_i, off_j=off_j, w=w, inv_self=inv_self, kk=kk, cost=cost, adm=adm, rev_i=rev_i,
                rev_j=rev_j, pad=pad)


def arc_sample_cells(rho: float, grid: Grid, ctrl: list[tuple[int, int, float]],
                     clearance: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The clearance samples of every stencil's arc, relative to its start node.

    Returns ``ci, cj`` (ntheta, nc, m): the cell of each sample (grid units, from the
    node), ``corner_dist`` (ntheta, nc, m, 4): its distance to the cell's corners (order
    (0,0), (0,1), (1,0), (1,1); length unit), and ``margin`` (nc,): the certified wall
    distance each sample needs, ``clearance`` plus half the spacing of its arc's samples.
    """
    theta = grid.theta
    nt, nc = grid.ntheta, len(ctrl)
    v, u, s = (np.array(column, dtype=float) for column in zip(*ctrl))
    starts = np.column_stack([np.zeros(nt), np.zeros(nt), theta])
    points = arc_samples(np.repeat(starts, nc, axis=0), np.tile(u, nt), np.tile(v, nt), np.tile(s, nt), rho,
                         sample_spacing(grid.h)) / grid.h
    points = points.reshape(nt, nc, -1, 2)
    ci, cj = np.floor(points[..., 0]).astype(np.int64), np.floor(points[..., 1]).astype(np.int64)
    corner_dist = grid.h * np.stack([np.hypot(points[..., 0] - ci - a, points[..., 1] - cj - b)
                                     for a, b in ((0, 0), (0, 1), (1, 0), (1, 1))], axis=-1)
    return ci, cj, corner_dist, clearance + 0.5 * s / (points.shape[2] - 1)


def _validate_grid(rho, h, ntheta, clearance):
    check_grid(rho, h, int(ntheta) if isinstance(ntheta, np.integer) else ntheta, clearance)


def _validate_target(target, tol):
    if tol is not None:
        length(tol, "tol", zero=True)
    try:
        tx, ty = (float(t) for t in target)
    except (TypeError, ValueError):
        raise PlanningError(f"target must be a point (x, y), got {target!r}") from None
    if not np.isfinite([tx, ty]).all():
        raise PlanningError(f"target must be finite, got {target!r}")
    return tx, ty


def _boundary_data(ws: Workspace, target, tol: float) -> tuple[np.ndarray, float]:
    """Initial values ``bc`` (ntheta, nx, ny), +inf except at states that reach the target directly.

    Returns ``bc`` and the radius ``r0`` of the exact layer (0 for disks).

    Point target (``tol == 0``): the exact value of eqs. (13)-(14) at states
    whose optimal path is shorter than ``r0`` -- a few cells -- and so lies in
    the disk of radius ``r0`` around the target, which must be certified
    clear of the walls.  Next to a wall that disk shrinks; if it gets thinner
    than the nominal radius, the disk of radius h/2 is also a target (first
    hits, as below), so that every heading has boundary data.
    Disk target (``tol > 0``): 0 inside the disk, and the arc length to the
    first hit along each clear stencil's primitive for nodes next to it.
    """
    grid, free = ws.grid, ws.free
    tx, ty = target
    gx, gy = np.meshgrid(grid.x, grid.y, indexing="ij")
    dist = np.hypot(gx - tx, gy - ty)
    if tol > 0:
        return _first_hits(ws, gx, gy, dist, target, tol), 0.0
    bc = np.full((grid.ntheta, grid.nx, grid.ny), np.inf)
    s_max = max(s for _, _, s in ws.ctrl)
    r0 = max(s_max + 2 * grid.h, ws.options.local_radius * np.sqrt(ws.rho * grid.h), ws.options.exact_radius)
    clear = float(lower_wall_distance(ws.distance, grid.x0, grid.y0, grid.h, np.array([tx]), np.array([ty]))[0])
    constrained = clear - ws.clearance < r0
    if constrained:
        r0 = max(clear - ws.clearance, grid.h)
    near = np.nonzero(free & (dist <= r0))
    # every heading at once: (ntheta, nodes near the target)
    exact_layer(bc, near[0], near[1], np.ascontiguousarray(gx[near]), np.ascontiguousarray(gy[near]),
                np.ascontiguousarray(grid.theta, dtype=float), float(tx), float(ty), float(ws.rho), float(r0),
                bool(ws.reverse))
    if constrained:
        bc = np.minimum(bc, _first_hits(ws, gx, gy, dist, target, 0.5 * grid.h))
    return bc, float(r0)


def _first_hits(ws: Workspace, gx, gy, dist, target, radius: float) -> np.ndarray:
    """0 in the disk of ``radius`` about ``target``; nearby, the arc length along a clear stencil to the disk.

    Each arc is sampled every ``s/32``; the hit is placed between the last
    sample outside and the first inside by linear interpolation of the
    distance to the disk.
    """
    grid, free = ws.grid, ws.free
    bc = np.full((grid.ntheta, grid.nx, grid.ny), np.inf)
    v, u, s = (np.array(column, dtype=float) for column in zip(*ws.ctrl))
    near = np.nonzero(free & (dist <= radius + s.max() + grid.h))
    bc[:, free & (dist <= radius)] = 0.0
    fractions = np.linspace(0.0, 1.0, 33)
    # An arc's shape depends on the heading only: sample it once per (heading, control) from the origin.
    origins = np.column_stack([np.zeros(grid.ntheta), np.zeros(grid.ntheta), grid.theta])
    shapes = arc_step(origins[:, None, None, :], u[None, :, None], v[None, :, None], s[None, :, None] * fractions,
                      ws.rho)  # (ntheta, nc, 33, 3)
    rx, ry = gx[near] - target[0], gy[near] - target[1]
    adm = np.ascontiguousarray(ws.stencils["adm"][:, near[0], near[1]])
    hits = first_hits(np.ascontiguousarray(rx), np.ascontiguousarray(ry), np.ascontiguousarray(shapes), s,
                      fractions, adm, float(radius))
    bc[:, near[0], near[1]] = np.minimum(bc[:, near[0], near[1]], hits)
    bc[:, ~free] = np.inf
    return bc


def solve(domain, target, rho: float, h: float, ntheta: int, *, clearance: float = 0.0,
          tol: float | None = None, reverse: bool = False, options: SolverOptions | None = None,
          progress=None) -> ValueFunction:
    """Value function φ(x, y, θ) of the simple car for a target point.

    Solves ``-1 = cosθ φ_x + sinθ φ_y - |φ_θ|/ρ`` with ``φ = 0`` at the target
    (eqs. (13)-(14) of Landa et al.), or its Reeds-Shepp variant
    ``-1 = -|cosθ φ_x + sinθ φ_y| - |φ_θ|/ρ`` when ``reverse=True``.  φ is the
    length of the shortest admissible path (the travel time at unit speed).

    Parameters
    ----------
    domain : arenas.Arena or ((float, float), (float, float))
        An arena, whose walls and obstacles are impassable -- its own
        ``contains`` and ``wall_distance`` decide what is free -- or rectangle
        bounds ``((x0, x1), (y0, y1))`` whose edges are walls.  Length unit as
        in the domain (cm for arenas).
    target : (float, float)
        Target position; any final heading.
    rho : float
        Minimum turning radius, > 0.
    h : float
        Grid spacing in x and y, > 0.
    ntheta : int
        Number of headings, >= 8; ``Δθ = 2π/ntheta``.
    clearance : float, optional
        Distance every path keeps from every wall and obstacle (car
        footprint), >= 0, length unit.  Each stencil's arc is checked all
        along its length, not only at its ends: no path cuts a corner.
    tol : float, optional
        Target radius.  ``None`` or 0: a point target, seeded by its exact
        local solution; > 0: the disk of that radius is the target.
    reverse : bool, optional
        Allow reverse driving (Reeds-Shepp car).
    options : SolverOptions, optional
        Numerical parameters.
    progress : callable, optional
        ``progress(sweeps, blocks_recomputed, blocks)`` after every sweep: the last two
        fall to 0 as the sweeps converge (the command line draws a bar with it).

    Returns
    -------
    ValueFunction
        φ on the grid, +inf at blocked or unreachable states.

    Raises
    ------
    PlanningError
        On invalid parameters or a target outside the free space.

    Notes
    -----
    Semi-Lagrangian scheme along exact arcs, monotone and upwind (see
    :mod:`hjplanner._sweep`): straight steps of 3 h and arcs turning by 1-4
    angular steps, which land on grid headings, so only bilinear
    interpolation in (x, y) is needed.  Long and multiple steps cut the
    numerical diffusion that makes the plain upwind scheme miss a point
    target.  A point target is seeded with the exact value (Bui et al.) at
    the states whose optimal path is shorter than ``r0 ≈ 2 sqrt(ρ h)``
    (stored as ``meta["local_radius"]``).  Walls of a rectangle domain are
    impassable like arena walls.  The error cannot drop below about
    ``ρ Δθ``: refine ``h`` and ``Δθ`` together.  Its measured error and time
    on the reference set-up are in ``benchmarks/LIMITS.md``
    (``benchmarks/bench_hjplanner.py``).

    Examples
    --------
    >>> vf = solve(((-1, 1), (-1, 1)), (0, 0), rho=0.3, h=0.05, ntheta=32)
    >>> abs(float(vf(-0.5, 0.0, 0.0)) - 0.5) < 0.05
    True
    """
    return solve_in(prepare(domain, rho, h, ntheta, clearance=clearance, reverse=reverse, options=options), target,
                    tol=tol, progress=progress)


def solve_in(ws: Workspace, target, *, tol: float | None = None, progress=None) -> ValueFunction:
    """:func:`solve` in a prepared :class:`Workspace` (what a bank does for each of its targets)."""
    tx, ty = _validate_target(target, tol)
    tol = float(tol or 0.0)
    grid = ws.grid
    if not (grid.x0 <= tx <= grid.x1 and grid.y0 <= ty <= grid.y1):
        raise PlanningError(
            f"target ({tx:g}, {ty:g}) is outside the domain [{grid.x0:g}, {grid.x1:g}] x [{grid.y0:g}, {grid.y1:g}]")
    if not target_is_free(grid, ws.free, tx, ty):
        raise PlanningError(
            f"target ({tx:g}, {ty:g}) is inside an obstacle, a wall or their clearance of {ws.clearance:g}; "
            "choose a target in free space")
    t0 = time.perf_counter()
    bc, r0 = _boundary_data(ws, (tx, ty), tol)
    if not np.isfinite(bc).any():
        raise PlanningError(f"no grid node reaches the target within tol={tol:g}; increase tol or refine h")
    phi, sweeps = solve_on_grid(ws, bc, progress, consume_bc=True)
    meta = dict(domain=ws.geometry["name"], target=[tx, ty], rho=ws.rho, h=grid.h, ntheta=grid.ntheta,
                clearance=ws.clearance, tol=tol, reverse=ws.reverse, local_radius=r0, sweeps=int(sweeps),
                solve_time_s=time.perf_counter() - t0, options=ws.options.as_dict())
    return ValueFunction(phi, grid, ws.free, ws.distance, meta, ws.geometry)


def solve_on_grid(ws: Workspace, bc: np.ndarray, progress=None, *,
                  consume_bc: bool = False) -> tuple[np.ndarray, int]:
    """Fixed point of the scheme for boundary data ``bc`` (ntheta, nx, ny), +inf off the target set.

    ``progress(sweeps, blocks_recomputed, blocks)`` is called after each sweep, if given.
    With ``consume_bc`` the sweeps use ``bc``'s memory as their scratch (its contents are
    then undefined): :func:`solve_in` builds ``bc`` for this call alone.

    Returns φ (ntheta, nx, ny), +inf where unreachable, and the number of sweeps.
    """
    grid, st = ws.grid, ws.stencils
    pad = st["pad"]
    bc = np.ascontiguousarray(bc, dtype=float)
    # one pass each way over the 3-D arrays, rather than numpy's temporaries (a cold
    # solve pays for every page it touches)
    # (numpy allocates them: it asks the kernel for huge pages, numba's allocator does not)
    phi = np.empty((grid.ntheta, grid.nx + 2 * pad, grid.ny + 2 * pad))
    _sweep.initial_values(bc, ws.free, pad, phi)
    sweeps = _sweep.solve_sweeps(
        phi, bc, st["off_i"], st["off_j"], st["w"], st["inv_self"], st["kk"], st["cost"], st["adm"], st["rev_i"],
        st["rev_j"], pad, ws.options.sweep_tol * grid.h, ws.options.max_sweeps, ws.options.threads or 1, ws.reverse,
        progress, consume_bc=consume_bc)
    # the unpadded result goes into bc's memory when the sweeps consumed it (their scratch)
    out = bc if consume_bc else np.empty(bc.shape)
    _sweep.final_values(phi, pad, out)
    phi = out
    if sweeps >= ws.options.max_sweeps:
        warnings.warn(f"hjplanner.solve stopped after max_sweeps={sweeps} sweeps before convergence",
                      RuntimeWarning, stacklevel=3)
    return phi, int(sweeps)


def target_is_free(grid: Grid, free: np.ndarray, tx: float, ty: float) -> bool:
    """True when all grid nodes of the cell holding the target are free."""
    i = min(int(np.floor((tx - grid.x0) / grid.h)), grid.nx - 2)
    j = min(int(np.floor((ty - grid.y0) / grid.h)), grid.ny - 2)
    return bool(free[i:i + 2, j:j + 2].all())
